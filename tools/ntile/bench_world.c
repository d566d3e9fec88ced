/* ntile bench world — ns per body-step of whole-world scenes.
 *
 * `ntile bench world [SCENE...]` (all scenes when none is named). Every run builds
 * its scene anew from a fixed seed (not timed), steps it through a warm-up (not
 * timed), then times `steps` calls of nt_world_step; the figure is the median over
 * the runs of elapsed time / (bodies x steps). World defaults throughout: N's scale
 * (cell 24 units, gravity 320 units/s^2), dt = 1/40 s, N's friction model, except where
 * said.
 *
 *   rain       bodies (half circles, half boxes, half-sizes 0.2..0.4 cell) start in
 *              the empty cells of a 256 x 256 map whose ledges use every tile shape,
 *              fall and settle on them
 *   particles  the same scene with every body's mask 0: tiles only, no broad phase
 *   sparse     bodies flying in straight lines (no gravity) through a 256 x 256 map
 *              that is almost empty
 *   pile       a 64-cell-wide container filled with 3000 bodies (Coulomb friction 0.5,
 *              no bounce), sleep off: dense contact
 *   asleep     that pile with sleep on, stepped until every body sleeps, then timed
 *   scale      rain at 1k, 10k and 100k bodies, the map grown to keep the density
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "cli.h"
#include "ntile/ntile.h"

static nt_real R(double v) { return (nt_real)v; }

#define DT (R(1) / 40)

typedef enum scene_kind { KIND_RAIN, KIND_SPARSE, KIND_PILE } scene_kind;

typedef struct scene_cfg {
    const char *label;
    scene_kind kind;
    int side;        /* map width = height in cells (pile: container width) */
    int bodies;
    uint32_t mask;   /* every body's mask */
    int sleep;       /* world sleeping on */
    int warm_steps;  /* untimed steps before timing */
    int until_asleep;/* keep warming (up to this many more steps) until nothing is awake */
    int steps;       /* timed steps */
} scene_cfg;

typedef struct scene_result {
    double ns;       /* median ns per body-step */
    int bodies, awake, warm;
    int ok;
} scene_result;

static int world_or_die(nt_status st, const char *what)
{
    if (st != NT_OK) {
        fprintf(stderr, "ntile bench world: %s failed: %s\n", what, nt_status_string(st));
        return 0;
    }
    return 1;
}

/* Tiles of the rain map: a full floor row, then ledges of 2..6 cells whose tiles
 * cycle through all 33 solid shapes, about one cell in six solid. */
static void rain_tiles(uint8_t *t, int side, uint64_t *rng)
{
    memset(t, NT_TILE_EMPTY, (size_t)side * (size_t)side);
    for (int x = 0; x < side; x++) t[(size_t)(side - 1) * (size_t)side + (size_t)x] = NT_TILE_FULL;
    int ledges = side * side / 24, next = 1;
    for (int k = 0; k < ledges; k++) {
        int len = 2 + (int)(bench_rng_next(rng) % 5);
        int x0 = (int)(bench_rng_next(rng) % (uint64_t)side);
        int y = 3 + (int)(bench_rng_next(rng) % (uint64_t)(side - 4));
        for (int x = x0; x < x0 + len && x < side; x++) {
            t[(size_t)y * (size_t)side + (size_t)x] = (uint8_t)next;
            next = next % (NT_TILE_COUNT - 1) + 1;
        }
    }
}

/* A few scattered tiles (one cell in 500). */
static void sparse_tiles(uint8_t *t, int side, uint64_t *rng)
{
    memset(t, NT_TILE_EMPTY, (size_t)side * (size_t)side);
    for (int k = 0; k < side * side / 500; k++)
        t[bench_rng_next(rng) % ((uint64_t)side * (uint64_t)side)] = (uint8_t)(1 + bench_rng_next(rng) % 33);
}

/* Build a scene; ids (may be NULL) receives the c->bodies handles in creation order. */
static nt_world *build(const scene_cfg *c, nt_body_id *ids)
{
    uint64_t rng = 0x7261696Eull + (uint64_t)c->bodies; /* "rain" */
    nt_world_def d = nt_default_world_def();
    int w = c->side, h = c->side;
    if (c->kind == KIND_PILE) h = c->bodies / c->side + 8;
    d.map.width = w;
    d.map.height = h;
    d.enable_sleep = c->sleep != 0;
    d.body_capacity = c->bodies;
    if (c->kind == KIND_SPARSE) d.gravity = nt_v2(0, 0);
    if (c->kind == KIND_PILE) {
        /* A pile that comes to rest: Coulomb friction 0.5, no bounce. (With N's
         * slippery defaults, 0.05 and no static friction, a pile keeps flowing.) */
        d.friction_model = NT_FRICTION_COULOMB;
        d.tile_material.friction = R(0.5);
        d.tile_material.bounce = 0;
    }
    nt_world *world = NULL;
    if (!world_or_die(nt_world_create(&d, &world), "nt_world_create")) return NULL;
    nt_real cell = d.map.cell_size;
    size_t ncells = (size_t)w * (size_t)h;
    uint8_t *tiles = calloc(ncells, 1), *used = calloc(ncells, 1);
    if (!tiles || !used) {
        fprintf(stderr, "ntile bench world: out of memory\n");
        free(tiles);
        free(used);
        nt_world_destroy(world);
        return NULL;
    }
    if (c->kind == KIND_RAIN) rain_tiles(tiles, w, &rng);
    else if (c->kind == KIND_SPARSE) sparse_tiles(tiles, w, &rng);
    if (!world_or_die(nt_world_set_tiles(world, tiles, ncells), "nt_world_set_tiles")) goto fail;
    if (c->kind != KIND_PILE) {
        /* Spawn cells: random empty cells with empty cells above and below, one body
         * each. Bodies are then created in reading order of their cells, as a level
         * lists them. */
        for (int i = 0; i < c->bodies; i++) {
            int tries = 0;
            for (;;) {
                size_t k = (size_t)(bench_rng_next(&rng) % ncells);
                int y = (int)(k / (size_t)w);
                if (!used[k] && tiles[k] == NT_TILE_EMPTY && y >= 1 && y <= h - 2 &&
                    tiles[k - (size_t)w] == NT_TILE_EMPTY && tiles[k + (size_t)w] == NT_TILE_EMPTY) {
                    used[k] = 1;
                    break;
                }
                if (++tries > 1000) {
                    fprintf(stderr, "ntile bench world: no room for %d bodies\n", c->bodies);
                    goto fail;
                }
            }
        }
    }
    size_t next_cell = 0;
    for (int i = 0; i < c->bodies; i++) {
        nt_body_def b = nt_default_body_def();
        double half = bench_rng_range(&rng, 0.2, 0.4) * (double)cell;
        b.shape = (i & 1) ? nt_shape_circle(R(half)) : nt_shape_aabb(R(half), R(half));
        b.mask = c->mask;
        int x, y;
        if (c->kind == KIND_PILE) {
            /* Rows from the bottom, one body per cell, 0.1 cell apart. */
            x = i % w;
            y = h - 1 - i / w;
            b.shape = (i & 1) ? nt_shape_circle(R(0.45 * cell)) : nt_shape_aabb(R(0.45 * cell), R(0.45 * cell));
            b.material.friction = R(0.5);
            b.material.bounce = 0;
        } else {
            while (!used[next_cell]) next_cell++;
            x = (int)(next_cell % (size_t)w);
            y = (int)(next_cell / (size_t)w);
            next_cell++;
        }
        b.position = nt_v2(R(((double)x + 0.5 + bench_rng_range(&rng, -0.05, 0.05)) * (double)cell),
                           R(((double)y + 0.5 + bench_rng_range(&rng, -0.05, 0.05)) * (double)cell));
        if (c->kind == KIND_SPARSE) {
            double a = bench_rng_range(&rng, 0, 6.283185307179586), s = bench_rng_range(&rng, 2.5, 8) * (double)cell;
            b.velocity = nt_v2(R(s * cos(a)), R(s * sin(a)));
        } else if (c->kind == KIND_RAIN) {
            b.velocity = nt_v2(R(bench_rng_range(&rng, -2, 2) * (double)cell), R(bench_rng_range(&rng, 0, 2) * (double)cell));
        }
        nt_body_id id;
        if (!world_or_die(nt_body_create(world, &b, &id), "nt_body_create")) goto fail;
        if (ids) ids[i] = id;
    }
    free(tiles);
    free(used);
    return world;
fail:
    free(tiles);
    free(used);
    nt_world_destroy(world);
    return NULL;
}

static int step_n(nt_world *w, int n)
{
    for (int s = 0; s < n; s++)
        if (!world_or_die(nt_world_step(w, DT), "nt_world_step")) return 0;
    return 1;
}

static scene_result run_scene(const bench_opts *opts, const scene_cfg *c)
{
    scene_result res = {0, c->bodies, 0, 0, 0};
    double *per = malloc(sizeof(double) * (size_t)opts->runs);
    if (!per) return res;
    for (int r = 0; r < opts->runs; r++) {
        nt_world *w = build(c, NULL);
        if (!w || !step_n(w, c->warm_steps)) {
            nt_world_destroy(w);
            free(per);
            return res;
        }
        int warm = c->warm_steps;
        for (int s = 0; s < c->until_asleep && nt_world_get_awake_count(w) > 0; s++, warm++)
            if (!step_n(w, 1)) {
                nt_world_destroy(w);
                free(per);
                return res;
            }
        double t0 = bench_now_ns();
        int ok = step_n(w, c->steps);
        double t1 = bench_now_ns();
        res.awake = nt_world_get_awake_count(w);
        res.warm = warm;
        nt_world_destroy(w);
        if (!ok) {
            free(per);
            return res;
        }
        per[r] = (t1 - t0) / ((double)c->bodies * (double)c->steps);
    }
    qsort(per, (size_t)opts->runs, sizeof *per, bench_cmp_double);
    res.ns = opts->runs % 2 ? per[opts->runs / 2] : (per[opts->runs / 2 - 1] + per[opts->runs / 2]) / 2;
    res.ok = 1;
    free(per);
    return res;
}

static void print_result(const char *label, const scene_result *r, const scene_cfg *c, const bench_opts *opts)
{
    printf("%-11s %8.2f ns/body-step  bodies %d, awake %d after the timed steps (%d timed after %d warm-up), "
           "median of %d runs, %s\n",
           label, r->ns, r->bodies, r->awake, c->steps, r->warm, opts->runs, SCALAR_NAME);
}

/* The rain scene at n bodies: the map side grows with sqrt(n) (256 at 10k). */
static scene_cfg rain_cfg(const char *label, int n, uint32_t mask)
{
    int side = (int)ceil(256.0 * sqrt((double)n / 10000.0));
    scene_cfg c = {label, KIND_RAIN, side, n, mask, 1, 0, 0, 120};
    return c;
}

int bench_world(const bench_opts *opts, int nargs, char **args)
{
    static const char *const all[] = {"rain", "particles", "sparse", "pile", "asleep", "scale"};
    const int nall = (int)(sizeof all / sizeof all[0]);
    if (opts->runs < 5) {
        fprintf(stderr, "ntile bench world: --runs must be at least 5 (the figure is a median)\n");
        return CLI_USAGE;
    }
    for (int i = 0; i < nargs; i++) {
        int known = 0;
        for (int k = 0; k < nall; k++) known |= strcmp(args[i], all[k]) == 0;
        if (!known) {
            fprintf(stderr, "ntile bench world: unknown scene '%s' (scenes: rain particles sparse pile asleep scale)\n",
                    args[i]);
            return CLI_USAGE;
        }
    }
    printf("# ntile bench world: ns per body-step (timed nt_world_step / bodies / steps), dt 1/40 s, %s\n",
           SCALAR_NAME);
    for (int k = 0; k < nall; k++) {
        int wanted = nargs == 0;
        for (int i = 0; i < nargs; i++) wanted |= strcmp(args[i], all[k]) == 0;
        if (!wanted) continue;
        const char *name = all[k];
        if (strcmp(name, "scale") == 0) {
            static const int counts[] = {1000, 10000, 100000};
            static const char *const labels[] = {"scale-1k", "scale-10k", "scale-100k"};
            double lo = 1e300, hi = 0;
            for (int j = 0; j < 3; j++) {
                scene_cfg c = rain_cfg(labels[j], counts[j], 0xFFFFFFFFu);
                scene_result r = run_scene(opts, &c);
                if (!r.ok) return CLI_USAGE;
                print_result(labels[j], &r, &c, opts);
                lo = r.ns < lo ? r.ns : lo;
                hi = r.ns > hi ? r.ns : hi;
            }
            printf("scale       spread %.1f %% (largest / smallest ns per body-step, 1k to 100k bodies)\n",
                   (hi / lo - 1) * 100);
            continue;
        }
        scene_cfg c;
        if (strcmp(name, "rain") == 0) c = rain_cfg(name, 10000, 0xFFFFFFFFu);
        else if (strcmp(name, "particles") == 0) c = rain_cfg(name, 10000, 0);
        else if (strcmp(name, "sparse") == 0) c = (scene_cfg){name, KIND_SPARSE, 256, 10000, 0xFFFFFFFFu, 1, 0, 0, 120};
        else if (strcmp(name, "pile") == 0) c = (scene_cfg){name, KIND_PILE, 64, 3000, 0xFFFFFFFFu, 0, 40, 0, 60};
        else c = (scene_cfg){name, KIND_PILE, 64, 3000, 0xFFFFFFFFu, 1, 40, 4000, 200};
        scene_result r = run_scene(opts, &c);
        if (!r.ok) return CLI_USAGE;
        print_result(name, &r, &c, opts);
    }
    return CLI_OK;
}

nt_world *bench_rain_world(int bodies, nt_body_id *ids)
{
    scene_cfg c = rain_cfg("rain", bodies, 0xFFFFFFFFu);
    return build(&c, ids);
}
