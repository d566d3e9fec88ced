/* ntile bench — one interface over the engines that run a scene (ntile here,
 * Chipmunk2D and Box2D in tools/bench-peers/), so that timing and error metrics are
 * measured by the same code for every engine. */
#ifndef NTILE_BENCH_ENGINE_H
#define NTILE_BENCH_ENGINE_H

#include "metrics.h"
#include "scene.h"

/* Solver settings of a peer engine; ntile takes its settings from the scene. */
typedef struct engine_setting {
    const char *label;        /* "default", "tuned" */
    int velocity_iterations;  /* Box2D velocity iterations, Chipmunk iterations; 0: the engine's default */
    int position_iterations;  /* Box2D only; 0: the default */
    int substeps;             /* world steps per scene step (of dt / substeps); 0 or 1: one */
    double slop;              /* allowed overlap in cells (Chipmunk collision slop); < 0: the default */
    int no_ccd;               /* Box2D: continuous collision off (on by default) */
} engine_setting;

typedef struct engine {
    const char *name;
    /* Build the scene; NULL on failure. */
    void *(*create)(const scene *s, const engine_setting *set);
    /* Advance by one scene step (s->dt). Returns 0 on failure. */
    int (*step)(void *world);
    /* Every body's centre and velocity, in scene units and creation order. */
    void (*read)(void *world, body_state *out);
    /* Bodies awake (simulated). */
    int (*awake)(void *world);
    void (*destroy)(void *world);
} engine;

/* The ntile engine (engine_ntile.c). */
extern const engine engine_ntile;

/* The scene as an ntile world (ids receives the s->nbodies handles); NULL on failure,
 * with a message on stderr. */
nt_world *ntile_scene_world(const scene *s, nt_body_id *ids);

/* Build scene s on engine e and warm it up (s->warm_steps steps, then until nothing
 * is awake when the scene asks); *warm gets the steps taken. With t, every state
 * goes through the metrics (st: room for s->nbodies). NULL on failure. */
void *bench_warmed(const engine *e, const engine_setting *set, const scene *s, int *warm, metrics_tracker *t,
                   body_state *st);

/* One more run of the scene (warmed up by bench_warmed) with nt_world_enable_profile:
 * *out receives the phase times summed over its s->steps steps, in milliseconds.
 * Returns 0 on failure. */
int ntile_scene_profile(const scene *s, nt_world_profile *out);
/* Body-steps taken inside nt_world_step by this engine so far (every call adds the
 * world's body count): with callgrind's count of instructions inside nt_world_step,
 * instructions per body-step exactly. */
extern long long ntile_body_steps;

/* One scene run on one engine: the timing of `runs` runs; the first also reads every
 * body after every step for the error metrics (outside the timed calls). */
typedef struct run_result {
    int ok;
    double ns, ns_min, ns_max; /* ns per body-step: median, smallest, largest over the runs */
    int bodies, awake, warm, steps;
    double wall_s;            /* wall time of everything, seconds */
    metrics m;
} run_result;

/* Run scene s on engine e: `runs` runs, each building the scene anew, warming up and
 * timing the s->steps calls of step (each call timed alone); with_metrics: the first
 * run's states go through the metrics. */
run_result bench_run(const engine *e, const engine_setting *set, const scene *s, int runs, int with_metrics);

/* Spread of a result in percent: (largest - smallest) / 2 / median. */
double run_spread(const run_result *r);

/* The results table: legend, header (first column titled `first`), one row. */
void bench_print_legend(void);
void bench_print_header(const char *first);
void bench_print_row(const char *label, const run_result *r, const char *extra); /* extra: appended, or NULL */

#endif
