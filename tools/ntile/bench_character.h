/* ntile bench character — the character scene (bench_character.c), shared with
 * tests/test_bench.c: characters on the particles map, each running at its own speed,
 * reversing at walls, jumping at random. */
#ifndef NTILE_BENCH_CHARACTER_H
#define NTILE_BENCH_CHARACTER_H

#include "ntile/ntile.h"
#include "scene.h"

/* The character scene of bench character (bench_character.c): characters on the
 * particles map, each running at its own speed, reversing at walls, jumping at random. */
typedef struct char_counts {
    long moves, on_floor, jumps, landings, snaps, step_ups;
    long reversals, blocked; /* turned back at a wall facing the run; where the run went nowhere */
} char_counts;

typedef struct char_state {
    double x;             /* where the last move ended */
    double vy, speed;     /* vertical velocity kept from the last move; run speed (units/s) */
    int dir;              /* -1 left, 1 right */
    int countdown;        /* steps on a floor before the next jump */
    int on_floor;
} char_state;

typedef struct char_scene {
    scene s;
    nt_world *world;
    nt_body_id *ids;
    char_state *chars;
    nt_vec2 *in;               /* this step's velocities */
    nt_character_result *res;  /* this step's results */
    uint64_t rng;
    char_counts count;
} char_scene;

/* Every body of s a box of the characters' shape. */
void char_scene_shape(scene *s);
/* n characters on rain's map for n bodies (n <= 0: particles' count); 0 on failure. */
int char_scene_make(int n, char_scene *cs);
/* One step: inputs, every character's move (with move_ns: their time added, ns), the
 * results into the counts, the world step. 0 on failure (a message on stderr). */
int char_scene_step(char_scene *cs, double *move_ns);
/* Deepest overlap with tiles (cells, nt_map_overlap_depth) into *depth when larger;
 * characters deeper than NT_CAST_START_TOLERANCE added to *deep, those whose centre is
 * outside the map to *outside. */
void char_scene_check(const char_scene *cs, double *depth, int *deep, int *outside);
void char_scene_free(char_scene *cs);

#endif
