/* tilegen: the tile tables of src/tile_tables.c, computed from the canonical `pn`
 * shapes of N's tile set (make tiles writes them; tests/test_tilegen.c checks the
 * committed file against them byte for byte). */
#ifndef NT_TILEGEN_H
#define NT_TILEGEN_H

#include <stdio.h>

/* Write the whole of src/tile_tables.c to out; 0 on success, -1 on a write error. */
int tilegen_write(FILE *out);

#endif
