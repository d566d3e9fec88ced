/* ntile bench — error metrics, computed the same way for every engine.
 *
 * After every step the engine's body positions and velocities (in the scene's units)
 * go through metrics_step. The measures use ntile's exact routines on those
 * positions, whichever engine produced them:
 *   penetration  deepest overlap of a body with one tile (nt_map_overlap_depth), cells
 *   overlap      deepest overlap between two bodies that collide (nt_collide_shapes), cells
 *   overlap_p99  99th percentile over the steps of each step's deepest overlap, cells (a
 *                single deepest event is a noisy measure)
 *   settled      deepest overlap between two bodies after the first second of the run
 *                (SETTLE_TIME), cells: a stack dropped in place settles first
 *   deep_pairs   pair-steps overlapping by DEEP_OVERLAP cell or more: a pair counts once
 *                for every step it ends that deep
 *   tunnelled    bodies that, at the end of some step, had their centre inside a solid
 *                tile or outside the map, or whose centre's straight path during the step
 *                crossed solid over more than the body's smaller half-size (it went through
 *                a wall; a path that only cuts a corner by less is not counted)
 *   ghost bumps  ROLE_SLIDE bodies that, over a flat floor, moved upwards faster than
 *                GHOST_SPEED (cells/s); max_up is the largest upward speed seen there
 *   speed loss   ROLE_SLIDE bodies on a frictionless flat floor: 1 - |vx_end| / |vx_0|
 *   energy drift ROLE_ENERGY bodies: max over steps of |E - E0| / E0, E kinetic plus
 *                potential energy above each body's resting height
 *   jitter       ROLE_REST bodies: largest distance from their place at step rest_from
 *                (cells), and largest speed after it (cells/s)
 *   analytic     relative errors: bounce apex heights against e^(2n) h0 (first 3 apexes),
 *                incline acceleration (velocity change from rest_from to the end) against
 *                g (sin - mu cos), free flight: the displacement at the end against v0 t + g t^2 / 2
 *                (relative to g t^2 / 2)
 * A value is -1 where the scene has no body it applies to.
 */
#ifndef NTILE_BENCH_METRICS_H
#define NTILE_BENCH_METRICS_H

#include "scene.h"

/* Upward speed (cells/s) above which sliding on a flat floor counts as a ghost bump. */
#define GHOST_SPEED 0.05
/* Body-body overlap (cells) from which a pair counts in deep_pairs. */
#define DEEP_OVERLAP 0.25
/* Seconds after which a scene's body overlap counts in `settled`. */
#define SETTLE_TIME 1.0

/* A body's state in scene units. */
typedef struct body_state {
    double x, y, vx, vy;
} body_state;

typedef struct metrics {
    double penetration;   /* cells */
    double overlap;       /* cells, -1 when no two bodies collide */
    int tunnelled;        /* bodies */
    int ghost_bumps;      /* bodies, -1 without ROLE_SLIDE bodies */
    double max_up;        /* cells/s */
    double speed_loss;    /* relative */
    double energy_drift;  /* relative */
    double jitter;        /* cells */
    double rest_speed;    /* cells/s */
    double bounce_error;  /* relative */
    double incline_error; /* relative */
    double flight_error;  /* relative */
    double overlap_p99;   /* cells, -1 when no two bodies collide */
    double settled;       /* cells, -1 when no two bodies collide or the run is not longer than SETTLE_TIME */
    long deep_pairs;      /* pair-steps, -1 when no two bodies collide */
} metrics;

typedef struct metrics_tracker metrics_tracker;

/* Start tracking a run of scene s from the bodies' initial state (s->bodies). NULL when
 * memory runs out. */
metrics_tracker *metrics_begin(const scene *s);
/* Account for the state after one more step. */
void metrics_step(metrics_tracker *t, const body_state *state);
/* The figures so far. */
metrics metrics_get(const metrics_tracker *t);
void metrics_end(metrics_tracker *t);

/* The pieces, for tests: penetration of a body (cells); whether a centre is inside
 * solid or outside the map; whether the centre path p0 -> p1 went through solid
 * longer than min_half; the energy of one body. */
double metrics_penetration(const nt_map *map, const scene_body *b, double x, double y);
int metrics_centre_in_solid(const nt_map *map, double x, double y);
int metrics_path_tunnels(const nt_map *map, double x0, double y0, double x1, double y1, double min_half);
double metrics_energy(const scene *s, const scene_body *b, const body_state *st);

/* A map holding the scene's tiles (for metrics and peer geometry); NULL on failure. */
nt_map *metrics_scene_map(const scene *s);

#endif
