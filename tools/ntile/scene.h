/* ntile bench — scenes as plain data, shared by every engine.
 *
 * A scene is a tile map (ids of N's tile set), a list of bodies and the world
 * settings, all in ntile's units (cell_size world units per cell, seconds, y down).
 * Each engine has a builder that turns this data into its own world (ntile here in
 * engine_ntile.c, Chipmunk2D and Box2D in tools/bench-peers/), so every engine runs
 * exactly the same scene. Scenes are generated from fixed seeds: deterministic.
 *
 * Bodies carry a role that tells the error metrics (metrics.h) what the right
 * answer is for them: at rest, sliding on a flat floor, in free flight, ...
 */
#ifndef NTILE_BENCH_SCENE_H
#define NTILE_BENCH_SCENE_H

#include <stdint.h>
#include "ntile/ntile.h"

/* What the metrics check for one body (besides penetration and tunnelling, which
 * are checked for every body). role_a / role_b are the role's data. */
typedef enum body_role {
    ROLE_NONE = 0,
    ROLE_REST,    /* should not move from step scene.rest_from on (jitter) */
    ROLE_SLIDE,   /* slides on a flat floor once centre x >= role_a (ghost bumps); role_b = 1: friction 0
                     and flat from the start, so its speed must not change (speed loss) */
    ROLE_FLIGHT,  /* free flight for the whole run: p0 + v0 t + g t^2 / 2 */
    ROLE_BOUNCE,  /* dropped from rest onto a flat floor: apex heights e^(2n) h0; role_a = the
                     centre's y when resting on the floor */
    ROLE_ENERGY,  /* counts in the scene's energy (bounce 1 scenes); role_a = the reference y for
                     potential energy (the centre's y resting on the floor) */
    ROLE_INCLINE  /* slides down a slope: acceleration g (sin - mu cos) along (role_a, role_b),
                     the unit down-slope direction; expected acceleration in scene units in accel */
} body_role;

typedef struct scene_body {
    int circle;           /* 0 box, 1 circle */
    double hx, hy;        /* half-size (circle: radius in both) */
    double x, y, vx, vy;  /* centre and velocity */
    double mass;
    double friction, bounce;
    int collide_bodies;   /* 0: tiles only (ntile mask 0) */
    body_role role;
    double role_a, role_b, accel;
} scene_body;

typedef struct scene {
    const char *name;
    const char *summary;
    int width, height;   /* cells */
    double cell;         /* world units per cell */
    uint8_t *tiles;      /* width * height tile ids, row-major */
    double gx, gy;       /* gravity */
    double dt;           /* seconds per step */
    int coulomb;         /* friction model: 0 N, 1 Coulomb */
    double tile_friction, tile_bounce;
    double restitution_threshold; /* units / s */
    int sleep;           /* sleeping on */
    int velocity_iterations, position_iterations; /* ntile's settings */
    int substeps;        /* each step is done as this many world steps of dt / substeps */
    int warm_steps;      /* untimed steps before timing */
    int until_asleep;    /* keep warming up to this many more steps until nothing is awake */
    int steps;           /* timed steps */
    double min_timed_ms; /* > 0: keep stepping past `steps` until this much is timed (scenes
                          * whose state no longer changes: a short window is at the mercy
                          * of the host's scheduling); metrics cover `steps` only */
    int rest_from;       /* ROLE_REST bodies should be still from this step on (counted from 0) */
    int nbodies;
    scene_body *bodies;
} scene;

/* Names of every scene scene_make knows, NULL-terminated. */
extern const char *const scene_names[];

/* Build the named scene with n bodies (n <= 0: the scene's own count). Returns 0 for
 * an unknown name or when memory runs out. Free with scene_free. */
int scene_make(const char *name, int n, scene *out);
void scene_free(scene *s);

/* The body count scene_make uses by default. */
int scene_default_bodies(const char *name);

/* Total steps of a run: warm-up + timed (without the until-asleep part). */
static inline int scene_total_steps(const scene *s) { return s->warm_steps + s->steps; }

#endif
