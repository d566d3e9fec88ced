/* Tiled import internals: a format-neutral model of a map that the JSON (json.c)
 * and XML (xml.c) readers fill and the builder (tiled.c) turns into an nt_level;
 * the arena everything of one import lives in; messages with positions. */
#ifndef NTILE_TOOLS_TILED_INTERNAL_H
#define NTILE_TOOLS_TILED_INTERNAL_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include "tiled.h"

/* Deepest nesting of group layers (and of XML elements) accepted. */
#define TL_MAX_DEPTH 64

/* ---------------------------------------------------------------- arena */

typedef struct tl_block tl_block;
typedef struct tl_arena {
    tl_block *head;
} tl_arena;

void *tl_alloc(tl_arena *a, size_t size); /* zeroed; NULL when out of memory */
char *tl_strndup(tl_arena *a, const char *s, size_t n);
void tl_arena_free(tl_arena *a);

/* ---------------------------------------------------------------- the model */

/* Where an element was written: the file, and its line and column (0 when the
 * parser does not know them: JSON values). */
typedef struct tl_loc {
    const char *file;
    int line, col;
} tl_loc;

/* A custom property. value is its text (booleans "true"/"false", numbers as
 * written or printed with %.17g); NULL for class properties. type is Tiled's
 * ("string" when not given). */
typedef struct tl_prop {
    const char *name, *type, *value;
    tl_loc loc;
} tl_prop;

typedef struct tl_props {
    tl_prop *v;
    int n;
} tl_props;

typedef struct tl_tile {
    long long id;
    tl_props props;
    tl_loc loc;
} tl_tile;

typedef struct tl_tileset {
    const char *name;       /* NULL until known */
    long long firstgid;
    long long tilecount;    /* -1 when not given */
    const char *source;     /* external tileset: the path as written in the map; NULL when embedded */
    tl_loc loc;             /* the tileset element in the map */
    tl_loc def;             /* where the tiles are defined (the map, or the external file) */
    tl_tile *tiles;
    int ntiles;
} tl_tileset;

enum { TL_RECT, TL_ELLIPSE, TL_POINT, TL_POLYLINE, TL_POLYGON, TL_TEXT, TL_TILE_OBJECT, TL_TEMPLATE };

typedef struct tl_object {
    long long id;
    const char *name; /* "" when unnamed */
    const char *type; /* Tiled's class/type field, "" when empty */
    int shape;        /* TL_* */
    double x, y, w, h, rotation;
    double *points;   /* polyline, polygon: x0 y0 x1 y1 ..., relative to x, y */
    int npoints;
    tl_props props;
    tl_loc loc;
} tl_object;

enum { TL_LAYER_TILES, TL_LAYER_OBJECTS, TL_LAYER_OTHER };

typedef struct tl_layer {
    int kind;
    const char *name;
    tl_loc loc;
    long long width, height;
    double offx, offy;       /* the layer's offset plus its groups' offsets */
    tl_props props;
    /* Tile layers: either gids (JSON arrays, XML <tile> elements) or encoded text. */
    uint32_t *gids;
    size_t ngids;
    int has_gids;
    const char *encoding;    /* "csv" or "base64" when text is used */
    const char *compression; /* "" when none */
    const char *text;
    size_t text_len;
    tl_loc text_loc;         /* where the text starts */
    tl_loc data_loc;         /* the data element */
    /* Object layers. */
    tl_object *objects;
    int nobjects;
} tl_layer;

typedef struct tl_map {
    tl_loc loc;
    const char *orientation;
    int infinite;
    long long width, height, tilewidth, tileheight;
    tl_props props;
    tl_tileset *tilesets;
    int ntilesets;
    tl_layer *layers; /* tile and object layers, groups flattened, bottom first */
    int nlayers;
} tl_map;

/* Layers as a reader collects them (groups flattened): an arena array that doubles. */
typedef struct tl_layer_list {
    tl_layer *v;
    int n, cap;
} tl_layer_list;

/* A new zeroed layer at the end of L; NULL when out of memory. */
tl_layer *tl_new_layer(tl_arena *a, tl_layer_list *L);

/* ---------------------------------------------------------------- one import */

typedef struct tl_ctx {
    tl_arena arena;
    nt_text_error *err;
    nt_warning_fn *warn;
    void *wctx;
    int warnings;
} tl_ctx;

/* Set the error "FILE[:LINE:COL]: text"; returns NT_ERR_PARSE. */
nt_status tl_fail(tl_ctx *c, tl_loc at, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
nt_status tl_vfail(tl_ctx *c, tl_loc at, const char *fmt, va_list ap);
/* "FILE: out of memory"; returns NT_ERR_OUT_OF_MEMORY. */
nt_status tl_oom(tl_ctx *c, const char *file);
/* A warning "FILE[:LINE:COL]: warning: text". */
void tl_warn(tl_ctx *c, tl_loc at, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* The readers. A map reader fills *m (tilesets with a source are left for the
 * builder to read); a tileset reader fills the name, tile count and tiles of *ts
 * from an external tileset file. */
nt_status tl_json_map(tl_ctx *c, const char *file, const char *text, size_t len, tl_map *m);
nt_status tl_json_tileset(tl_ctx *c, const char *file, const char *text, size_t len, tl_tileset *ts);
nt_status tl_xml_map(tl_ctx *c, const char *file, const char *text, size_t len, tl_map *m);
nt_status tl_xml_tileset(tl_ctx *c, const char *file, const char *text, size_t len, tl_tileset *ts);

/* A quoted, printable copy of s for messages (at most ~40 bytes). buf: 64 bytes. */
const char *tl_quote(char buf[64], const char *s);

#endif
