#define _POSIX_C_SOURCE 200809L
/* ntile bench sweep / plot — run time against error.
 *
 * `ntile bench sweep [--runs N] [--out FILE.csv]` runs the world with one setting
 * changed at a time from the defaults and writes one CSV row per setting:
 *   step length   frames of 1/20 s, or 1/40 s frames in 1, 2 or 4 steps (dt/substeps)
 *   velocity iterations 1, 2, 4, 8, 16; position iterations 0, 1, 2, 4, 8
 *   friction      every scene in N's model, or every scene in Coulomb's (the default
 *                 is each scene's own: rain and slide N, pile, rest and incline Coulomb)
 * and the scalar type of the binary (build it with NT_DOUBLE=1 for double). The time
 * is ns per body per 1/40 s simulated on rain at 4,000 bodies (median of N runs, so
 * a setting that takes two steps per frame pays for both); the errors are those of
 * metrics.h on rain (4,000), pile, rest, bounce, slide and incline, each scene run
 * for the same simulated time whatever the step.
 *
 * `ntile bench plot FILE.csv... [--out PREFIX]` reads sweep CSVs (float and double),
 * finds the Pareto front of time against each of two errors (the deepest overlap of
 * two bodies, and the bounce apex height error), prints it and writes PREFIX.csv (all
 * rows, with front flags) and PREFIX.svg (both plots).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "../common/stream.h"
#include "cli.h"
#include "engine.h"
#include "plot.h"

typedef struct sweep_cfg {
    const char *label;
    int frame_div;   /* frame dt = 1 / frame_div */
    int substeps;
    int vel, pos;
    int model;       /* -1: each scene's own, 0: N, 1: Coulomb */
} sweep_cfg;

static const sweep_cfg configs[] = {
    {"default", 40, 1, 8, 4, -1},    {"dt 1/20", 20, 1, 8, 4, -1},   {"dt 1/80 (2 sub)", 40, 2, 8, 4, -1},
    {"dt 1/160 (4 sub)", 40, 4, 8, 4, -1}, {"vel 1", 40, 1, 1, 4, -1}, {"vel 2", 40, 1, 2, 4, -1},
    {"vel 4", 40, 1, 4, 4, -1},      {"vel 16", 40, 1, 16, 4, -1},   {"pos 0", 40, 1, 8, 0, -1},
    {"pos 1", 40, 1, 8, 1, -1},      {"pos 2", 40, 1, 8, 2, -1},     {"pos 8", 40, 1, 8, 8, -1},
    {"friction N", 40, 1, 8, 4, 0},  {"friction Coulomb", 40, 1, 8, 4, 1},
};
#define NCONFIGS (int)(sizeof configs / sizeof configs[0])

#define CSV_HEADER                                                                                                  \
    "scalar,setting,frame_dt,substeps,velocity_iterations,position_iterations,friction,ns_per_body_per_40th_s,"   \
    "spread_pct,penetration,overlap,tunnelled,ghost_bumps,jitter,energy_drift,apex_error,incline_error"

/* Apply a setting to a scene: solver settings, model, and the step counts for the
 * same simulated time. */
static void apply(scene *s, const sweep_cfg *c)
{
    double f = 40.0 / c->frame_div; /* frames of 1/40 s per frame */
    s->dt = 1.0 / c->frame_div;
    s->substeps = c->substeps;
    s->velocity_iterations = c->vel;
    s->position_iterations = c->pos;
    if (c->model >= 0) s->coulomb = c->model;
    s->warm_steps = (int)lround(s->warm_steps / f);
    s->steps = (int)lround(s->steps / f);
    s->rest_from = (int)lround(s->rest_from / f);
    s->until_asleep = (int)lround(s->until_asleep / f);
}

static double maxd(double a, double b) { return a > b ? a : b; }

/* Errors of one scene under a setting (one run, no timing figure needed). */
static int scene_errors(const char *name, int n, const sweep_cfg *c, metrics *out)
{
    scene s;
    if (!scene_make(name, n, &s)) return 0;
    apply(&s, c);
    engine_setting none = {"ntile", 0, 0, 1, -1, 0};
    run_result r = bench_run(&engine_ntile, &none, &s, 1, 1);
    scene_free(&s);
    *out = r.m;
    return r.ok;
}

int bench_sweep(const bench_opts *opts, int nargs, char **args)
{
    if (!bench_plain_args("sweep", opts, nargs, args)) return CLI_USAGE;
    FILE *csv = NULL;
    if (opts->out) {
        csv = fopen(opts->out, "w");
        if (!csv) {
            fprintf(stderr, "ntile bench sweep: cannot write '%s'\n", opts->out);
            return CLI_USAGE;
        }
        fprintf(csv, "%s\n", CSV_HEADER);
    }
    printf("# ntile bench sweep (%s): time = ns per body per 1/40 s simulated on rain (4,000 bodies), median of %d "
           "runs;\n# errors as in bench world, over rain, pile, rest, bounce, slide and incline\n",
           SCALAR_NAME, opts->runs);
    printf("%-18s %10s %7s %9s %9s %6s %6s %9s %8s %8s %8s\n", "setting", "ns/40th s", "spread", "pen", "overlap",
           "tunnel", "ghost", "jitter", "energy", "apex", "incline");
    for (int k = 0; k < NCONFIGS; k++) {
        const sweep_cfg *c = &configs[k];
        scene s;
        if (!scene_make("rain", 4000, &s)) return CLI_USAGE;
        apply(&s, c);
        engine_setting none = {"ntile", 0, 0, 1, -1, 0};
        run_result rain = bench_run(&engine_ntile, &none, &s, opts->runs, 1);
        scene_free(&s);
        metrics pile, rest, bounce, slide, incline = {0}; /* incline: Coulomb only (mu above 1) */
        if (!rain.ok || !scene_errors("pile", 0, c, &pile) || !scene_errors("rest", 0, c, &rest) ||
            !scene_errors("bounce", 0, c, &bounce) || !scene_errors("slide", 0, c, &slide) ||
            (c->model != 0 && !scene_errors("incline", 0, c, &incline))) {
            fprintf(stderr, "ntile bench sweep: setting '%s' failed\n", c->label);
            if (csv) fclose(csv);
            return CLI_USAGE;
        }
        double ns = rain.ns * c->frame_div / 40.0;
        double pen = maxd(maxd(rain.m.penetration, pile.penetration), maxd(rest.penetration, slide.penetration));
        double overlap = maxd(maxd(rain.m.overlap, pile.overlap), rest.overlap);
        int tunnel = rain.m.tunnelled + pile.tunnelled + rest.tunnelled + bounce.tunnelled + slide.tunnelled;
        /* the incline's answer is Coulomb's law: not asked of N's model */
        double incl = c->model == 0 ? -1 : incline.incline_error;
        double jitter = maxd(rest.jitter, c->model == 0 ? -1 : incline.jitter);
        printf("%-18s %10.2f %6.1f%% %9.2g %9.2g %6d %6d %9.2g %8.2g %8.2g %8.2g\n", c->label, ns, run_spread(&rain), pen,
               overlap, tunnel, slide.ghost_bumps, jitter, bounce.energy_drift, bounce.bounce_error, incl);
        fflush(stdout);
        if (csv)
            fprintf(csv, "%s,%s,%.6g,%d,%d,%d,%s,%.4f,%.2f,%.6g,%.6g,%d,%d,%.6g,%.6g,%.6g,%.6g\n", SCALAR_NAME,
                    c->label, 1.0 / c->frame_div, c->substeps, c->vel, c->pos,
                    c->model < 0 ? "scene" : c->model ? "coulomb" : "n", ns, run_spread(&rain), pen, overlap, tunnel,
                    slide.ghost_bumps, jitter, bounce.energy_drift, bounce.bounce_error, incl);
    }
    if (csv && fclose(csv) != 0) {
        fprintf(stderr, "ntile bench sweep: error writing '%s'\n", opts->out);
        return CLI_USAGE;
    }
    return CLI_OK;
}

/* ---------- plot ---------- */

#define MAX_ROWS 256
#define NCOLS 17

typedef struct sweep_row {
    char scalar[16], setting[40];
    double ns, overlap, apex;
    char line[512]; /* the CSV row as read */
} sweep_row;

int bench_plot(const bench_opts *opts, int nargs, char **args)
{
    if (nargs < 1) {
        fprintf(stderr, "ntile bench plot: give the sweep CSV files\n");
        return CLI_USAGE;
    }
    sweep_row *rows = calloc(MAX_ROWS, sizeof *rows);
    plot_point *pa = calloc(MAX_ROWS, sizeof *pa), *pb = calloc(MAX_ROWS, sizeof *pb);
    int n = 0, rc = CLI_USAGE;
    if (!rows || !pa || !pb) goto done;
    for (int f = 0; f < nargs; f++) {
        char why[600];
        FILE *in = stream_open_regular(args[f], STREAM_MAX_FILE, why, sizeof why);
        if (!in) {
            fprintf(stderr, "ntile bench plot: %s\n", why);
            goto done;
        }
        char line[512];
        int first = 1;
        while (fgets(line, sizeof line, in)) {
            if (first) { /* the header */
                first = 0;
                if (strncmp(line, "scalar,setting,", 15) != 0) {
                    fprintf(stderr, "ntile bench plot: '%s' is not a sweep CSV\n", args[f]);
                    fclose(in);
                    goto done;
                }
                continue;
            }
            if (n == MAX_ROWS) break;
            sweep_row *r = &rows[n];
            snprintf(r->line, sizeof r->line, "%s", line);
            r->line[strcspn(r->line, "\r\n")] = 0;
            char *fld[NCOLS];
            if (csv_split(line, fld, NCOLS) != NCOLS) {
                fprintf(stderr, "ntile bench plot: '%s': a row without %d fields\n", args[f], NCOLS);
                fclose(in);
                goto done;
            }
            snprintf(r->scalar, sizeof r->scalar, "%s", fld[0]);
            snprintf(r->setting, sizeof r->setting, "%s", fld[1]);
            r->ns = strtod(fld[7], NULL);
            r->overlap = strtod(fld[10], NULL);
            r->apex = strtod(fld[15], NULL);
            n++;
        }
        fclose(in);
    }
    static const char *const series[] = {"float", "double"};
    for (int i = 0; i < n; i++) {
        int s = strcmp(rows[i].scalar, "double") == 0;
        /* log axes: errors of 0 (or none) sit at the floor of 1e-6 */
        pa[i] = (plot_point){rows[i].ns, fmax(rows[i].overlap, 1e-6), s, 0, ""};
        pb[i] = (plot_point){rows[i].ns, fmax(rows[i].apex, 1e-6), s, 0, ""};
        snprintf(pa[i].label, sizeof pa[i].label, "%s %s", rows[i].scalar, rows[i].setting);
        snprintf(pb[i].label, sizeof pb[i].label, "%s %s", rows[i].scalar, rows[i].setting);
    }
    int fa = plot_pareto(pa, n), fb = plot_pareto(pb, n);
    printf("# ntile bench plot: %d settings; Pareto front (no setting both faster and more accurate):\n"
           "# %d against body overlap, %d against bounce apex error ('*' marks the front)\n",
           n, fa, fb);
    printf("%-8s %-18s %10s %10s %2s %10s %2s\n", "scalar", "setting", "ns/40th s", "overlap", "", "apex", "");
    for (int i = 0; i < n; i++)
        printf("%-8s %-18s %10.2f %10.3g %2s %10.3g %2s\n", rows[i].scalar, rows[i].setting, rows[i].ns,
               rows[i].overlap, pa[i].front ? "*" : "", rows[i].apex, pb[i].front ? "*" : "");
    if (opts->out) {
        char path[1024];
        snprintf(path, sizeof path, "%s.csv", opts->out);
        FILE *csv = fopen(path, "w");
        if (!csv) {
            fprintf(stderr, "ntile bench plot: cannot write '%s'\n", path);
            goto done;
        }
        fprintf(csv, "%s,front_overlap,front_apex\n", CSV_HEADER);
        for (int i = 0; i < n; i++) fprintf(csv, "%s,%d,%d\n", rows[i].line, pa[i].front, pb[i].front);
        int bad = fclose(csv) != 0;
        snprintf(path, sizeof path, "%s.svg", opts->out);
        FILE *svg = bad ? NULL : fopen(path, "w");
        plot_panel panels[2] = {
            {"time against body overlap", "ns per body per 1/40 s (rain, 4,000 bodies)",
             "deepest body-body overlap, cells", pa, n},
            {"time against bounce apex error", "ns per body per 1/40 s (rain, 4,000 bodies)",
             "bounce apex height, relative error", pb, n}};
        int written = svg && plot_svg(svg, panels, 2, series, 2);
        if (svg && fclose(svg) != 0) written = 0;
        if (!written) {
            fprintf(stderr, "ntile bench plot: cannot write '%s'\n", path);
            goto done;
        }
        printf("# wrote %s.csv and %s.svg\n", opts->out, opts->out);
    }
    rc = CLI_OK;
done:
    free(rows);
    free(pa);
    free(pb);
    return rc;
}
