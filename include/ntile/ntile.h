/* ntile — a small, fast, deterministic 2D collision engine in the style of N.
 *
 * Include this header to get the whole public API:
 *   base.h   scalar type, vectors, status codes, allocator and assert hooks
 *   tiles.h  the 34 N tiles, exact minimum-translation routines, tile ray casts
 *   map.h    the tile map: edge states, resolution, ray casts
 *   world.h  the world: bodies, the step, events, queries, debug draw
 *   character.h shape casts (box or circle swept against tiles and bodies)
 *   level.h  levels: the .ntl format, N v1.4 import, level -> world
 *   replay.h replays: the .ntr format
 *
 * The game layer (player controller, level objects, replay runner) is a separate
 * library, libntile-game, with its own header ntile/game.h; this header does not
 * include it.
 */
#ifndef NTILE_H
#define NTILE_H

#include "base.h"
#include "tiles.h"
#include "map.h"
#include "world.h"
#include "character.h"
#include "level.h"
#include "replay.h"

#endif
