/* ntile bench character — what a character move costs against a plain body-step.
 *
 * `ntile bench character [--runs N]`: 1,000 characters run and jump over the rain map
 * as rain sizes it for 1,000 bodies (81 x 81 cells, ledges of every tile shape, the
 * density of rain's 10,000-body 256 x 256 map); N's scale: cell 24 units, gravity 320
 * units/s^2, dt 1/40 s. Each character is a box of half-size 0.3 x 0.4 cell placed where
 * rain places its bodies (one empty cell with empty cells above and below, centre
 * within 0.05 cell of the cell's: the box fits the cell whatever its neighbours, and 0.4
 * is the largest of rain's half-sizes), made a character with the default settings
 * (50-degree floors, snap and step-up of half a cell) and, like particles' bodies,
 * colliding with tiles only. Each step every character runs left or right at its own
 * constant speed (2..5 cells/s), falls under gravity, keeps the vertical velocity its
 * move returns, turns back when it meets a wall facing its run (result.on_wall) or when
 * its run went nowhere (wedged where a floor meets a sloped ceiling), and jumps (1..3
 * cells high) once it has spent its countdown of 10..60 steps on floors. Splitmix64
 * from a fixed seed: every run is the same (checked: the counts of every run must match).
 * Then the world steps.
 *
 * Timed: the calls of nt_character_move alone (one clock read around the 1,000 moves
 * of a step; the inputs are computed before and the results read after), over
 * CHAR_STEPS steps after CHAR_WARM untimed ones (they fall from where they were placed
 * and land); the figure is the median over the runs of time / moves. The reference is
 * particles with bodies of the same shape (every body a 0.3 x 0.4 box; the same map,
 * count and placements), run and timed as bench world does (bench_run: 120 steps from
 * the start, sleep on): ns per body-step. The target: a move costs at most CHAR_TARGET
 * times that (PASS/FAIL; the exit status stays 0 either way, 1 when two runs of the
 * characters differ). For the reader, not the target: the same bodies with sleep off
 * over the characters' window. The runs of the three are interleaved, each figure the
 * median of its own runs.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "bench_character.h"
#include "cli.h"
#include "engine.h"

#define CHAR_BODIES 1000
#define CHAR_WARM 40   /* untimed: they fall from where they were placed and land */
#define CHAR_STEPS 160 /* timed */
#define CHAR_TARGET 3.0
#define CHAR_HX 0.3 /* half-size, cells */
#define CHAR_HY 0.4

void char_scene_shape(scene *s)
{
    for (int i = 0; i < s->nbodies; i++) {
        s->bodies[i].circle = 0;
        s->bodies[i].hx = CHAR_HX * s->cell;
        s->bodies[i].hy = CHAR_HY * s->cell;
    }
}

/* Steps until the next jump, and a jump speed for 1..3 cells of height. */
static int next_jump(uint64_t *rng) { return 10 + (int)(bench_rng_next(rng) % 51); }
static double jump_speed(const scene *s, uint64_t *rng)
{
    return sqrt(2 * s->gy * bench_rng_range(rng, 1, 3) * s->cell);
}

void char_scene_free(char_scene *cs)
{
    nt_world_destroy(cs->world);
    free(cs->ids);
    free(cs->chars);
    free(cs->in);
    free(cs->res);
    scene_free(&cs->s);
    memset(cs, 0, sizeof *cs);
}

int char_scene_make(int n, char_scene *cs)
{
    memset(cs, 0, sizeof *cs);
    if (!scene_make("particles", n, &cs->s)) return 0;
    char_scene_shape(&cs->s);
    size_t nb = (size_t)cs->s.nbodies;
    cs->ids = malloc(nb * sizeof *cs->ids);
    cs->chars = calloc(nb, sizeof *cs->chars);
    cs->in = malloc(nb * sizeof *cs->in);
    cs->res = calloc(nb, sizeof *cs->res);
    if (!cs->ids || !cs->chars || !cs->in || !cs->res || !(cs->world = ntile_scene_world(&cs->s, cs->ids))) {
        char_scene_free(cs);
        return 0;
    }
    cs->rng = 0x63686172ull + (uint64_t)n; /* "char" */
    nt_character_def def = nt_default_character_def();
    for (int i = 0; i < cs->s.nbodies; i++) {
        char_state *c = &cs->chars[i];
        if (nt_character_create(cs->world, cs->ids[i], &def) != NT_OK) {
            char_scene_free(cs);
            return 0;
        }
        c->dir = bench_rng_next(&cs->rng) & 1 ? 1 : -1;
        c->speed = bench_rng_range(&cs->rng, 2, 5) * cs->s.cell;
        c->countdown = next_jump(&cs->rng);
        c->x = cs->s.bodies[i].x;
    }
    return 1;
}

int char_scene_step(char_scene *cs, double *move_ns)
{
    const scene *s = &cs->s;
    const int n = s->nbodies;
    const nt_real dt = (nt_real)s->dt;
    /* The controller's input: run, fall, jump. */
    for (int i = 0; i < n; i++) {
        char_state *c = &cs->chars[i];
        c->vy += s->gy * s->dt;
        if (c->on_floor && --c->countdown <= 0) {
            c->vy = -jump_speed(s, &cs->rng);
            c->countdown = next_jump(&cs->rng);
            cs->count.jumps++;
        }
        cs->in[i] = nt_v2((nt_real)(c->dir * c->speed), (nt_real)c->vy);
    }
    /* The moves: the timed part. */
    int bad = 0;
    double t0 = move_ns ? bench_now_ns() : 0;
    for (int i = 0; i < n; i++) bad |= nt_character_move(cs->world, cs->ids[i], cs->in[i], dt, &cs->res[i]) != NT_OK;
    if (move_ns) *move_ns += bench_now_ns() - t0;
    if (bad) {
        fprintf(stderr, "bench character: nt_character_move failed\n");
        return 0;
    }
    /* What they met: keep the slid velocity; reverse at a wall that faces the run, or
     * when the run went nowhere (wedged where a floor meets a sloped ceiling). */
    for (int i = 0; i < n; i++) {
        char_state *c = &cs->chars[i];
        const nt_character_result *r = &cs->res[i];
        double x = (double)r->position.x;
        c->vy = (double)r->velocity.y;
        c->on_floor = r->on_floor;
        if (r->on_wall && (double)r->wall_normal.x * c->dir < 0) {
            c->dir = -c->dir;
            cs->count.reversals++;
        } else if (fabs(x - c->x) < 0.01 * c->speed * s->dt) {
            c->dir = -c->dir;
            cs->count.blocked++;
        }
        c->x = x;
        cs->count.moves++;
        cs->count.on_floor += r->on_floor;
        cs->count.landings += r->landed;
        cs->count.snaps += r->snapped;
        cs->count.step_ups += r->stepped_up;
    }
    if (nt_world_step(cs->world, dt) != NT_OK) {
        fprintf(stderr, "bench character: nt_world_step failed\n");
        return 0;
    }
    return 1;
}

void char_scene_check(const char_scene *cs, double *depth, int *deep, int *outside)
{
    const nt_map *map = nt_world_get_map(cs->world);
    double cell = cs->s.cell, w = cs->s.width * cell, h = cs->s.height * cell;
    for (int i = 0; i < cs->s.nbodies; i++) {
        nt_vec2 p = nt_body_get_position(cs->world, cs->ids[i]);
        double d = (double)nt_map_overlap_depth(map, p, nt_body_get_shape(cs->world, cs->ids[i])) / cell;
        if (d > *depth) *depth = d;
        *deep += d > NT_CAST_START_TOLERANCE;
        *outside += !((double)p.x > 0 && (double)p.x < w && (double)p.y > 0 && (double)p.y < h);
    }
}

/* One run: a new scene, CHAR_WARM steps, then CHAR_STEPS timed ones: ns per move;
 * the counts of the timed steps and the end state. */
static double char_run(int n, char_counts *count, double *depth, int *deep, int *outside)
{
    char_scene cs;
    if (!char_scene_make(n, &cs)) {
        fprintf(stderr, "ntile bench character: could not build the scene\n");
        return -1;
    }
    double ns = 0;
    for (int k = 0; k < CHAR_WARM + CHAR_STEPS; k++) {
        if (k == CHAR_WARM) {
            ns = 0;
            memset(&cs.count, 0, sizeof cs.count);
        }
        if (!char_scene_step(&cs, &ns)) {
            char_scene_free(&cs);
            return -1;
        }
    }
    *count = cs.count;
    char_scene_check(&cs, depth, deep, outside);
    double per = ns / (double)cs.count.moves;
    char_scene_free(&cs);
    return per;
}

int bench_character(const bench_opts *opts, int nargs, char **args)
{
    if (!bench_plain_args("character", opts, nargs, args)) return CLI_USAGE;
    /* The reference, and (not the target's reference, for the reader) the same bodies
     * with sleep off over the characters' window: CHAR_WARM untimed steps, CHAR_STEPS
     * timed. */
    scene ref, awake;
    if (!scene_make("particles", CHAR_BODIES, &ref)) return CLI_USAGE;
    if (!scene_make("particles", CHAR_BODIES, &awake)) {
        scene_free(&ref);
        return CLI_USAGE;
    }
    char_scene_shape(&ref);
    char_scene_shape(&awake);
    awake.sleep = 0;
    awake.warm_steps = CHAR_WARM;
    awake.steps = CHAR_STEPS;
    printf("# ntile bench character: %d characters (boxes %.1f x %.1f cell, tiles only) running 2..5 cells/s and "
           "jumping 1..3 cells\n# on rain's %d x %d map for %d bodies; %d steps of 1/40 s after %d untimed; %s; "
           "median of %d runs, interleaved with the references' (a noisy host: medians)\n",
           CHAR_BODIES, 2 * CHAR_HX, 2 * CHAR_HY, ref.width, ref.height, CHAR_BODIES, CHAR_STEPS, CHAR_WARM,
           SCALAR_NAME, opts->runs);
    /* Runs interleaved (a character run, a reference run, a sleep-off run, and again),
     * so that the host's slower spells fall on all three alike. */
    double *per = malloc(sizeof(double) * 3 * (size_t)opts->runs);
    double *per_ref = per + opts->runs, *per_awake = per_ref + opts->runs;
    char_counts first = {0}, count;
    double depth = 0;
    int deep = 0, outside = 0, same = 1, ok = per != NULL, ref_awake = 0;
    engine_setting none = {"ntile", 0, 0, 1, -1, 0};
    fprintf(stderr, "ntile bench character: %d runs of the characters and of the reference ...\n", opts->runs);
    for (int r = 0; r < opts->runs && ok; r++) {
        per[r] = char_run(CHAR_BODIES, &count, &depth, &deep, &outside);
        run_result a = bench_run(&engine_ntile, &none, &ref, 1, 0), b = bench_run(&engine_ntile, &none, &awake, 1, 0);
        ok = per[r] >= 0 && a.ok && b.ok;
        per_ref[r] = a.ns;
        per_awake[r] = b.ns;
        ref_awake = a.awake;
        if (r == 0) first = count;
        same &= memcmp(&first, &count, sizeof count) == 0;
    }
    int ref_steps = ref.steps;
    scene_free(&ref);
    scene_free(&awake);
    if (!ok) {
        free(per);
        return CLI_USAGE;
    }
    double lo, hi, ns = bench_median(per, opts->runs, &lo, &hi);
    run_result rr = {0}, aw = {0};
    rr.ns = bench_median(per_ref, opts->runs, &rr.ns_min, &rr.ns_max);
    aw.ns = bench_median(per_awake, opts->runs, &aw.ns_min, &aw.ns_max);
    free(per);
    double ratio = ns / rr.ns;
    bench_warn_spread(stderr, "character", "character move", ns > 0 ? (hi - lo) / 2 / ns * 100 : 0);
    bench_warn_spread(stderr, "character", "reference particles step", run_spread(&rr));
    printf("%-30s %8.1f ns/move       (%d x %d moves a run; runs %.1f..%.1f)\n", "character move", ns,
           CHAR_BODIES, CHAR_STEPS, lo, hi);
    printf("%-30s %8.1f ns/body-step  (particles, every body a %.1f x %.1f box, %d x %d steps; runs %.1f..%.1f; "
           "awake at the end %d)\n",
           "reference: particles step", rr.ns, 2 * CHAR_HX, 2 * CHAR_HY, CHAR_BODIES, ref_steps, rr.ns_min,
           rr.ns_max, ref_awake);
    printf("%-30s %8.2f x          (target: at most %.0f x)\n", "ratio move / body-step", ratio, CHAR_TARGET);
    printf("# not the reference: particles with sleep off over the characters' %d + %d steps: %.1f ns/body-step "
           "(runs %.1f..%.1f), a move %.2f x that\n",
           CHAR_WARM, CHAR_STEPS, aw.ns, aw.ns_min, aw.ns_max, ns / aw.ns);
    printf("%s: a character move costs %.2f x a particles body-step (target at most %.0f x)\n",
           ratio <= CHAR_TARGET ? "PASS" : "FAIL", ratio, CHAR_TARGET);
    long m = first.moves > 0 ? first.moves : 1;
    printf("# each run (timed steps): %ld moves, %.1f %% on a floor, %ld jumps, %ld landings, %ld wall reversals, "
           "%ld turns where the run went nowhere, %ld snaps, %ld step-ups%s\n",
           first.moves, 100.0 * (double)first.on_floor / (double)m, first.jumps, first.landings, first.reversals,
           first.blocked, first.snaps, first.step_ups,
           same ? " (every run the same)" : " (RUNS DIFFER: not deterministic)");
    printf("# at the end of the runs: deepest overlap with tiles %.2g cell, characters deeper than %g cell %d (of "
           "%d), outside the map %d\n",
           depth, NT_CAST_START_TOLERANCE, deep, CHAR_BODIES * opts->runs, outside);
    return same ? CLI_OK : CLI_INPUT_ERRORS;
}
