/* ntile — Tiled map import (the CLI side: reads files, needs jansson, expat, zlib).
 *
 * Not part of libntile: the engine never touches the file system and depends on
 * libc and libm only. This module reads a Tiled map (.tmj JSON or .tmx XML), the
 * external tilesets it names (.tsx / .tsj, relative to the map's directory), and
 * builds an nt_level. README.md ("Importing Tiled maps") describes the mapping.
 */
#ifndef NTILE_TOOLS_TILED_H
#define NTILE_TOOLS_TILED_H

#include <stddef.h>
#include <stdint.h>
#include "ntile/level.h"

/* Tiled's flip flags in a global tile id (Tiled 1.x). */
#define TILED_FLIP_H 0x80000000u   /* horizontal: x -> 1 - x */
#define TILED_FLIP_V 0x40000000u   /* vertical: y -> 1 - y */
#define TILED_FLIP_D 0x20000000u   /* diagonal (applied first): x <-> y */
#define TILED_FLIP_HEX 0x10000000u /* hexagonal maps' 120-degree rotation: ignored */
#define TILED_GID_MASK 0x0fffffffu

/* Import the map `path` whose text is text[0..length) (the caller read it; `path`
 * names it in messages and locates external tilesets). The format follows the
 * extension (.tmj/.json JSON, .tmx/.xml XML); other names: JSON when the text starts
 * with '{' (after blanks), XML otherwise. On success *out holds the
 * level; warnings (skipped objects, flips that have no N tile, ...) go to `warn`
 * (may be NULL) as "FILE[:LINE:COL]: warning: ELEMENT: text". On failure *out is
 * NULL, nothing is left allocated, and `error` holds "FILE[:LINE:COL]: ELEMENT:
 * text" (line and column where the parser knows them). Returns NT_OK, NT_ERR_PARSE
 * (bad input, unreadable tileset) or NT_ERR_OUT_OF_MEMORY. */
nt_status tiled_import(const char *path, const char *text, size_t length, nt_level **out, nt_text_error *error,
                       nt_warning_fn *warn, void *context);

/* The N tile a tile shows after Tiled's flips (flags: TILED_FLIP_* bits of the gid),
 * or -1 when the flipped shape is not an N tile. EMPTY and FULL map to themselves. */
int tiled_flip_tile(int tile, uint32_t flags);

#endif
