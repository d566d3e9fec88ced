/* bench-peers — the peer engines (chipmunk.c, box2d.c). */
#ifndef NTILE_BENCH_PEERS_H
#define NTILE_BENCH_PEERS_H

#include "engine.h"

extern const engine engine_chipmunk;
extern const engine engine_box2d;
/* Which Chipmunk library this program is linked with (the Makefile's CHIPMUNK). */
extern const char chipmunk_build[];
const char *chipmunk_version(void); /* the library's own cpVersionString */

#endif
