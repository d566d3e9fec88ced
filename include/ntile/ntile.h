/* ntile — a small, fast, deterministic 2D collision engine in the style of N.
 *
 * Include this header to get the whole public API:
 *   base.h   scalar type, vectors, status codes, allocator and assert hooks
 *   tiles.h  the 34 N tiles, exact minimum-translation routines, tile ray casts
 *   map.h    the tile map: edge states, resolution, ray casts
 */
#ifndef NTILE_H
#define NTILE_H

#include "base.h"
#include "tiles.h"
#include "map.h"
#include "world.h"

#endif
