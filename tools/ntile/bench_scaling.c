/* ntile bench scaling — how the cost grows and what the world skips.
 *
 * `ntile bench scaling [--runs N]` prints:
 *   - ns per body-step of rain at 1k, 10k and 100k bodies (the map grows with the count);
 *   - memory per map cell and per body, counted through the allocator hook
 *     (nt_set_allocator): live bytes of empty worlds of two sizes, and of the rain world
 *     with 10k bodies after creation and at its peak over 120 steps;
 *   - the skipping ratios, each measured in this run: asleep against awake bodies (the
 *     pile with and without sleep), particles (tiles only) against rain, and bodies with
 *     an empty neighbourhood (free) against bodies resting on tiles (touching);
 *   - what waking one small group costs in worlds of 1,980 and 19,800 sleeping bodies.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "cli.h"
#include "engine.h"

/* ---------- counting allocator: a size header in front of every block ---------- */

typedef struct mem_count {
    long long live, peak, blocks;
} mem_count;

static mem_count mem;

#define HEADER 16 /* keeps the block 16-byte aligned */

static void *count_alloc(size_t size, void *user)
{
    (void)user;
    unsigned char *p = malloc(size + HEADER);
    if (!p) return NULL;
    memcpy(p, &size, sizeof size);
    mem.live += (long long)size;
    mem.blocks++;
    if (mem.live > mem.peak) mem.peak = mem.live;
    return p + HEADER;
}

static void count_free(void *ptr, void *user)
{
    (void)user;
    unsigned char *p = (unsigned char *)ptr - HEADER;
    size_t size;
    memcpy(&size, p, sizeof size);
    mem.live -= (long long)size;
    mem.blocks--;
    free(p);
}

/* Live bytes of an empty world of side x side cells. */
static long long empty_world_bytes(int side)
{
    nt_world_def d = nt_default_world_def();
    d.map.width = d.map.height = side;
    long long before = mem.live;
    nt_world *w = NULL;
    if (nt_world_create(&d, &w) != NT_OK) return -1;
    long long bytes = mem.live - before;
    nt_world_destroy(w);
    return bytes;
}

static run_result timed(const bench_opts *opts, const char *name, int n)
{
    scene s;
    run_result r = {0};
    if (!scene_make(name, n, &s)) return r;
    engine_setting none = {"ntile", 0, 0, 1, -1, 0};
    r = bench_run(&engine_ntile, &none, &s, opts->runs, 0);
    scene_free(&s);
    return r;
}

/* Step until nothing is awake (at most 5000 steps), then once more: the step that sets
 * the sleepers' contacts aside, a one-off that belongs to falling asleep. */
static void settle(nt_world *w, nt_real dt)
{
    for (int k = 0; k < 5000 && nt_world_get_awake_count(w) > 0; k++) nt_world_step(w, dt);
    nt_world_step(w, dt);
}

/* Median time (microseconds) of waking one two-box stack and stepping once, in a world
 * of `shelves` x 99 such stacks all asleep (Coulomb 0.5, 1/60 s): what a wake costs
 * next to the sleeping bodies it does not touch. NAN when the world cannot be built. */
static double wake_cost(int shelves, int *bodies)
{
    enum { WAKES = 21 };
    nt_world_def d = nt_default_world_def();
    d.map.width = 200;
    d.map.height = shelves * 3 + 2;
    d.map.cell_size = 1;
    d.gravity = nt_v2(0, 10);
    d.friction_model = NT_FRICTION_COULOMB;
    d.tile_material.friction = (nt_real)0.5;
    d.tile_material.bounce = 0;
    nt_world *w = NULL;
    nt_body_id *ids = malloc(sizeof *ids * 198 * (size_t)shelves);
    if (!ids || nt_world_create(&d, &w) != NT_OK) {
        free(ids);
        return NAN;
    }
    int n = 0;
    for (int k = 0; k < shelves; k++) {
        int fy = 3 * k + 3;
        for (int x = 0; x < 200; x++) nt_world_set_tile(w, x, fy, NT_TILE_FULL);
        for (int x = 1; x < 199; x += 2)
            for (int j = 0; j < 2; j++) {
                nt_body_def b = nt_default_body_def();
                b.shape = nt_shape_aabb((nt_real)0.3, (nt_real)0.3);
                b.position = nt_v2((nt_real)(x + 0.5), (nt_real)(fy - 0.31 - 0.6 * j));
                b.material.friction = (nt_real)0.5;
                b.material.bounce = 0;
                if (nt_body_create(w, &b, &ids[n]) == NT_OK) n++;
            }
    }
    const nt_real dt = (nt_real)(1.0 / 60);
    nt_world_step(w, dt);
    settle(w, dt);
    double us[WAKES];
    for (int q = 0; q < WAKES; q++) {
        double t0 = bench_now_ns();
        nt_body_set_awake(w, ids[(q * 7919) % n], true);
        nt_world_step(w, dt);
        us[q] = (bench_now_ns() - t0) * 1e-3;
        settle(w, dt);
    }
    nt_world_destroy(w);
    free(ids);
    *bodies = n;
    qsort(us, WAKES, sizeof *us, bench_cmp_double);
    return us[WAKES / 2];
}

/* --profile: rain's step at n bodies split by phase (one more run). */
static void print_phases(int n)
{
    scene s;
    nt_world_profile prof;
    if (!scene_make("rain", n, &s)) {
        fprintf(stderr, "ntile bench scaling: could not build rain with %d bodies for its phases\n", n);
        return;
    }
    if (!ntile_scene_profile(&s, &prof)) {
        fprintf(stderr, "ntile bench scaling: could not profile rain with %d bodies\n", n);
    } else {
        double per = 1e6 / ((double)s.nbodies * s.steps); /* ms in all -> ns per body-step */
        printf("#  rain %6d phases, ns/body-step: pairs %.1f  contacts %.1f  correct %.1f  solve %.1f  move %.1f  "
               "sleep %.1f  (one more run, nt_world_get_profile)\n",
               n, prof.pairs * per, prof.contacts * per, prof.correct * per, prof.solve * per, prof.move * per,
               prof.sleep * per);
        fflush(stdout);
    }
    scene_free(&s);
}

int bench_scaling(const bench_opts *opts, int nargs, char **args)
{
    if (!bench_plain_args("scaling", opts, nargs, args)) return CLI_USAGE;
    printf("# ntile bench scaling: %s, median of %d runs, dt 1/40 s\n", SCALAR_NAME, opts->runs);
    static const int counts[] = {1000, 10000, 100000};
    double lo = 1e300, hi = 0;
    for (int j = 0; j < 3; j++) {
        fprintf(stderr, "ntile bench scaling: [%d/5] rain with %d bodies ...\n", j + 1, counts[j]);
        run_result r = timed(opts, "rain", counts[j]);
        if (!r.ok) return CLI_USAGE;
        printf("scale rain %6d bodies  %8.2f ns/body-step  spread %.1f %%\n", counts[j], r.ns, run_spread(&r));
        fflush(stdout);
        char what[32];
        snprintf(what, sizeof what, "rain with %d bodies", counts[j]);
        bench_warn_spread(stderr, "scaling", what, run_spread(&r));
        lo = r.ns < lo ? r.ns : lo;
        hi = r.ns > hi ? r.ns : hi;
        if (opts->profile) print_phases(counts[j]);
    }
    printf("scale spread %.1f %% (largest / smallest ns per body-step, 1k to 100k bodies; target <= 35 %%) %s\n",
           (hi / lo - 1) * 100, (hi / lo - 1) * 100 <= 35 ? "PASS" : "FAIL");
    fprintf(stderr, "ntile bench scaling: [4/5] memory ...\n");

    /* memory, through the allocator hook */
    nt_set_allocator(count_alloc, count_free, NULL);
    long long a = empty_world_bytes(256), b = empty_world_bytes(512);
    scene s;
    if (!scene_make("rain", 10000, &s)) {
        nt_set_allocator(NULL, NULL, NULL);
        return CLI_USAGE;
    }
    long long base = empty_world_bytes(s.width);
    engine_setting none = {"ntile", 0, 0, 1, -1, 0};
    mem.peak = mem.live;
    long long start = mem.live;
    void *w = engine_ntile.create(&s, &none);
    long long created = mem.live - start;
    for (int k = 0; k < s.steps && w; k++) engine_ntile.step(w);
    long long peak = mem.peak - start, after = mem.live - start;
    /* the runner's own arrays (the id list) are not from the hook: only the world counts */
    if (w) engine_ntile.destroy(w);
    long long leaked = mem.live - start;
    nt_set_allocator(NULL, NULL, NULL);
    int n = s.nbodies;
    scene_free(&s);
    if (a < 0 || b < 0 || base < 0 || !w) return CLI_USAGE;
    double per_cell = (double)(b - a) / (512.0 * 512 - 256.0 * 256);
    printf("memory per cell   %.2f bytes (empty worlds of 256^2 and 512^2 cells: %lld and %lld bytes)\n", per_cell, a,
           b);
    printf("memory per body   %.1f bytes after creation, %.1f after 120 steps, %.1f at the peak (rain, %d bodies, "
           "world without bodies %lld bytes)%s\n",
           (double)(created - base) / n, (double)(after - base) / n, (double)(peak - base) / n, n, base,
           leaked ? "  (memory left after destroy!)" : "");

    /* skipping ratios */
    fprintf(stderr, "ntile bench scaling: [5/5] skipping ratios (pile, asleep, rain, particles, free, touching) ...\n");
    run_result awake = timed(opts, "pile", 0), asleep = timed(opts, "asleep", 0);
    run_result rain = timed(opts, "rain", 10000), parts = timed(opts, "particles", 10000);
    run_result fr = timed(opts, "free", 10000), touch = timed(opts, "touching", 10000);
    if (!awake.ok || !asleep.ok || !rain.ok || !parts.ok || !fr.ok || !touch.ok) return CLI_USAGE;
    printf("skip asleep/awake      %8.2g  (pile of 3000: %.2g ns asleep, %.2f ns awake with sleep off)\n",
           asleep.ns / awake.ns, asleep.ns, awake.ns);
    printf("skip particles/rain    %8.4f  (10000 bodies: %.2f ns tiles only, %.2f ns with body contacts)\n",
           parts.ns / rain.ns, parts.ns, rain.ns);
    printf("skip free/touching     %8.4f  (10000 bodies, tiles only: %.2f ns with nothing near, %.2f ns resting on "
           "a floor)\n",
           fr.ns / touch.ns, fr.ns, touch.ns);
    int n1 = 0, n2 = 0;
    double w1 = wake_cost(10, &n1), w2 = wake_cost(100, &n2);
    printf("wake one group         %8.2f us with %d bodies asleep, %.2f us with %d (set_awake on a two-box stack "
           "and one step, median of 21)\n",
           w1, n1, w2, n2);
    return CLI_OK;
}
