/* Transitional: what src/core.h held before it was split into core_internal.h (helpers
 * for every engine source) and simulation.h (the world simulation), plus the
 * old one-letter cast macro R(x). Only the engine files not yet converted include it
 * (world.c, response.c, grid.c, map.c, narrow.c, sleep.c, tests/test_world_skip.c); new
 * code includes core_internal.h or simulation.h and writes (nt_real)x. Delete this file
 * once none includes it. */
#ifndef NT_CORE_H
#define NT_CORE_H

#include "core_internal.h"
#include "simulation.h"

#define R(x) ((nt_real)(x))

#endif
