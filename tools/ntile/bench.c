/* ntile bench — timing scenes.
 *
 * `ntile bench SCENE [--runs N] [--min-ms MS]`. Each scene is one entry of the
 * `scenes` table below: a name, a one-line summary and a function receiving the
 * parsed common options. Every figure is the median of N timed runs (default 7);
 * a run repeats the work until it lasts at least MS milliseconds (default 20).
 * Times come from clock_gettime(CLOCK_MONOTONIC).
 */
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "bench.h"
#include "cli.h"
#include "ntile/ntile.h"

/* Results of the timed work reach this sink, so the calls cannot be optimised away. */
static volatile double bench_sink;

/* One unit of work: repeat it `reps` times, return a value that depends on every result. */
typedef double bench_work(const void *ctx, long reps);

/* Median over opts->runs runs of the time per item (ns), where one repetition of
 * `work` handles `items` items. The repetition count is calibrated first so that a
 * run lasts at least opts->min_ms. */
static double bench_median_ns(const bench_opts *opts, bench_work *work, const void *ctx, double items)
{
    long reps = 1;
    for (;;) {
        double t0 = bench_now_ns();
        bench_sink += work(ctx, reps);
        double dt = bench_now_ns() - t0;
        if (dt >= opts->min_ms * 1e6 || reps >= (1L << 30)) break;
        reps *= 2;
    }
    double *per = malloc((size_t)opts->runs * sizeof *per);
    if (!per) return -1;
    for (int r = 0; r < opts->runs; r++) {
        double t0 = bench_now_ns();
        bench_sink += work(ctx, reps);
        per[r] = (bench_now_ns() - t0) / ((double)reps * items);
    }
    double m = bench_median(per, opts->runs, NULL, NULL);
    free(per);
    return m;
}

static nt_real rng_range(uint64_t *s, double lo, double hi)
{
    return (nt_real)bench_rng_range(s, lo, hi);
}

/* ---------- scene: narrow ---------- */

#define NARROW_PLACEMENTS 4096
#define NARROW_TILES (NT_TILE_COUNT - 1) /* every tile but EMPTY */

typedef struct placement {
    nt_vec2 c;
    nt_vec2 h; /* circles: radius in h.x */
} placement;

typedef struct narrow_set {
    int circle;
    int ntiles;
    int tiles[NARROW_TILES];
    const placement *const *by_tile; /* NARROW_PLACEMENTS overlapping placements per tile id */
} narrow_set;

static double narrow_work(const void *ctx, long reps)
{
    const narrow_set *set = ctx;
    double acc = 0;
    nt_mtv m;
    for (long r = 0; r < reps; r++) {
        for (int k = 0; k < set->ntiles; k++) {
            int tile = set->tiles[k];
            const placement *p = set->by_tile[tile];
            nt_real sum = 0;
            if (set->circle) {
                for (int i = 0; i < NARROW_PLACEMENTS; i++)
                    if (nt_tile_collide_circle(tile, p[i].c, p[i].h.x, &m)) sum += m.depth;
            } else {
                for (int i = 0; i < NARROW_PLACEMENTS; i++)
                    if (nt_tile_collide_aabb(tile, p[i].c, p[i].h, &m)) sum += m.depth;
            }
            acc += (double)sum;
        }
    }
    return acc;
}

/* Random placements that overlap the tile: sizes in [0.02, 0.5], centres uniform over
 * the cell grown by the size, kept when the routine reports an overlap. */
static int narrow_generate(int tile, int circle, uint64_t *rng, placement *out)
{
    long attempts = 0;
    for (int i = 0; i < NARROW_PLACEMENTS;) {
        if (++attempts > 1000L * NARROW_PLACEMENTS) return 0;
        placement p;
        p.h.x = rng_range(rng, 0.02, 0.5);
        p.h.y = circle ? p.h.x : rng_range(rng, 0.02, 0.5);
        p.c.x = rng_range(rng, -p.h.x, 1 + p.h.x);
        p.c.y = rng_range(rng, -p.h.y, 1 + p.h.y);
        nt_mtv m;
        bool hit = circle ? nt_tile_collide_circle(tile, p.c, p.h.x, &m) : nt_tile_collide_aabb(tile, p.c, p.h, &m);
        if (hit) out[i++] = p;
    }
    return 1;
}

static int bench_narrow(const bench_opts *opts, int nargs, char **args)
{
    if (nargs > 0) {
        fprintf(stderr, "ntile bench narrow: unexpected argument '%s'\n", args[0]);
        return CLI_USAGE;
    }
    static const struct {
        nt_tile_class cls;
        const char *name;
    } classes[] = {{NT_CLASS_POLYGON, "polygon"}, {NT_CLASS_CONVEX, "convex"}, {NT_CLASS_CONCAVE, "concave"}};
    static const char *const shape_names[2] = {"aabb", "circle"};
    placement *pool = malloc(sizeof(placement) * NARROW_PLACEMENTS * NARROW_TILES * 2);
    if (!pool) {
        fprintf(stderr, "ntile bench narrow: out of memory\n");
        return CLI_USAGE;
    }
    const placement *by_tile[2][NT_TILE_COUNT] = {{NULL}};
    uint64_t rng = 0x6E74696C65ull; /* "ntile" */
    for (int circle = 0; circle < 2; circle++) {
        for (int tile = 1; tile < NT_TILE_COUNT; tile++) {
            placement *p = pool + ((size_t)circle * NARROW_TILES + (size_t)(tile - 1)) * NARROW_PLACEMENTS;
            if (!narrow_generate(tile, circle, &rng, p)) {
                fprintf(stderr, "ntile bench narrow: could not place overlapping %s on tile %s\n",
                        circle ? "circles" : "boxes", nt_tile_get_info(tile)->name);
                free(pool);
                return CLI_USAGE;
            }
            by_tile[circle][tile] = p;
        }
    }
    printf("# ntile bench narrow: %d overlapping placements on each of %d solid tiles, %s, median of %d runs\n",
           NARROW_PLACEMENTS, NARROW_TILES, SCALAR_NAME, opts->runs);
    for (int circle = 0; circle < 2; circle++) {
        narrow_set all = {circle, 0, {0}, by_tile[circle]};
        for (int tile = 1; tile < NT_TILE_COUNT; tile++) all.tiles[all.ntiles++] = tile;
        double ns = bench_median_ns(opts, narrow_work, &all, (double)all.ntiles * NARROW_PLACEMENTS);
        printf("narrow %-17s %7.2f ns/test (median of %d runs, %s)\n", circle ? "circle-vs-tile" : "aabb-vs-tile", ns,
               opts->runs, SCALAR_NAME);
        for (size_t c = 0; c < sizeof classes / sizeof classes[0]; c++) {
            narrow_set set = {circle, 0, {0}, by_tile[circle]};
            for (int tile = 1; tile < NT_TILE_COUNT; tile++)
                if (nt_tile_get_info(tile)->cls == classes[c].cls) set.tiles[set.ntiles++] = tile;
            ns = bench_median_ns(opts, narrow_work, &set, (double)set.ntiles * NARROW_PLACEMENTS);
            char label[32];
            snprintf(label, sizeof label, "%s-vs-%s", shape_names[circle], classes[c].name);
            printf("narrow %-17s %7.2f ns/test   (%d %s tiles)\n", label, ns, set.ntiles, classes[c].name);
        }
    }
    free(pool);
    return CLI_OK;
}

/* ---------- scene table and the subcommand ---------- */

/* The options a benchmark reads besides --runs and --min-ms: any other is refused
 * rather than ignored. */
enum { OPT_WIDE = 1, OPT_PROFILE = 2, OPT_OUT = 4 };

typedef struct bench_scene {
    const char *name;
    const char *summary;
    int (*run)(const bench_opts *opts, int nargs, char **args); /* args: the words after the name */
    unsigned options;                                           /* OPT_* */
} bench_scene;

static const bench_scene scenes[] = {
    {"narrow", "ns per AABB-vs-tile and circle-vs-tile test over the 33 solid tiles", bench_narrow, 0},
    {"world", "ns per body-step and error metrics of world scenes (tools/ntile/scene.c): bench world [SCENE...]",
     bench_world, OPT_WIDE | OPT_PROFILE},
    {"scaling", "ns per body-step at 1k/10k/100k bodies, memory per body and cell, skipping ratios",
     bench_scaling, OPT_PROFILE},
    {"character", "ns per character move (1,000 running and jumping over rain's map) against a particles body-step",
     bench_character, 0},
    {"sweep", "run time against error over dt, substeps, iterations, friction model: --out FILE.csv", bench_sweep,
     OPT_OUT},
    {"plot", "Pareto front and SVG of sweep CSVs: bench plot FILE.csv... --out PREFIX", bench_plot, OPT_OUT},
};
#define SCENE_COUNT (sizeof scenes / sizeof scenes[0])

void cli_bench_usage(FILE *f)
{
    fputs("  ntile bench SCENE [NAME...] [--runs N] [--min-ms MS] [--out PATH] [--wide] [--profile]\n"
          "      Time a part of the engine: median of N runs (default 7), each lasting at\n"
          "      least MS milliseconds (default 20). A progress line per scene goes to\n"
          "      stderr, and a warning when a spread is above 25 % (a busy host). world:\n"
          "      one narrow row per check with PASS/FAIL against its target; --wide: every\n"
          "      error column instead; --profile (world, scaling): the step split by phase\n"
          "      under each scene or body count.\n"
          "      Scenes:\n",
          f);
    for (size_t i = 0; i < SCENE_COUNT; i++) fprintf(f, "        %-10s %s\n", scenes[i].name, scenes[i].summary);
}

static int bench_usage_error(void)
{
    fprintf(stderr, "usage:\n");
    cli_bench_usage(stderr);
    return CLI_USAGE;
}

/* A number in [lo, hi] from an option's argument. */
static int option_number(int argc, char **argv, int *i, double lo, double hi, double *out)
{
    const char *name = argv[*i];
    char *end;
    double v = *i + 1 < argc ? strtod(argv[*i + 1], &end) : 0;
    if (*i + 1 >= argc || end == argv[*i + 1] || *end || !(v >= lo && v <= hi)) {
        fprintf(stderr, "ntile bench: %s needs a number in %g..%g\n", name, lo, hi);
        return 0;
    }
    *out = v;
    (*i)++;
    return 1;
}

int cli_bench(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            printf("usage:\n");
            cli_bench_usage(stdout);
            return CLI_OK;
        }
    if (argc < 2) {
        fprintf(stderr, "ntile bench: missing benchmark name\n");
        return bench_usage_error();
    }
    const bench_scene *scene = NULL;
    for (size_t i = 0; i < SCENE_COUNT; i++)
        if (strcmp(argv[1], scenes[i].name) == 0) scene = &scenes[i];
    if (!scene) {
        fprintf(stderr, "ntile bench: unknown benchmark '%s'\n", argv[1]);
        return bench_usage_error();
    }
    bench_opts opts = {7, 20, NULL, 0, 0};
    char **words = malloc(sizeof(char *) * (size_t)argc);
    int nwords = 0;
    if (!words) return CLI_USAGE;
    for (int i = 2; i < argc; i++) {
        double v = 0;
        if (strcmp(argv[i], "--runs") == 0) {
            if (!option_number(argc, argv, &i, 1, 1001, &v) || v != (int)v) {
                if (v != (int)v) fprintf(stderr, "ntile bench: --runs needs a whole number\n");
                free(words);
                return bench_usage_error();
            }
            opts.runs = (int)v;
        } else if (strcmp(argv[i], "--min-ms") == 0) {
            if (!option_number(argc, argv, &i, 0, 60000, &v)) {
                free(words);
                return bench_usage_error();
            }
            opts.min_ms = v;
        } else if (strcmp(argv[i], "--wide") == 0) {
            opts.wide = 1;
        } else if (strcmp(argv[i], "--profile") == 0) {
            opts.profile = 1;
        } else if (strcmp(argv[i], "--out") == 0) {
            if (i + 1 >= argc) {
                fprintf(stderr, "ntile bench: --out needs a path\n");
                free(words);
                return bench_usage_error();
            }
            opts.out = argv[++i];
        } else if (argv[i][0] == '-') {
            fprintf(stderr, "ntile bench %s: unknown option '%s'\n", scene->name, argv[i]);
            free(words);
            return bench_usage_error();
        } else {
            words[nwords++] = argv[i];
        }
    }
    static const struct {
        unsigned bit;
        const char *name;
    } used[] = {{OPT_WIDE, "--wide"}, {OPT_PROFILE, "--profile"}, {OPT_OUT, "--out"}};
    const unsigned given = (opts.wide ? OPT_WIDE : 0u) | (opts.profile ? OPT_PROFILE : 0u) | (opts.out ? OPT_OUT : 0u);
    for (size_t k = 0; k < sizeof used / sizeof used[0]; k++)
        if ((given & used[k].bit) && !(scene->options & used[k].bit)) {
            fprintf(stderr, "ntile bench %s: %s does not apply to this benchmark\n", scene->name, used[k].name);
            free(words);
            return bench_usage_error();
        }
    int rc = scene->run(&opts, nwords, words);
    free(words);
    return rc;
}
