/* ntile bench world — ns per body-step and error metrics of whole-world scenes.
 *
 * `ntile bench world [SCENE...]` (all scenes when none is named; the scenes are
 * described in scene.c). Every run builds its scene anew from a fixed seed (not
 * timed), steps it through its warm-up (not timed), then times `steps` calls of
 * nt_world_step; the figure is the median over the runs of elapsed time / (bodies x
 * steps), with the spread (half the range over the runs, relative to the median).
 * One more run, untimed, reads every body after every step for the error metrics
 * (metrics.h): the same figures bench-peers computes for Chipmunk2D and Box2D.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "cli.h"
#include "engine.h"

/* ---------- the targets ----------
 *
 * The stated targets of the world scenes (README "Benchmarks"; the
 * newest where they differ): wall time per body-step, the body-overlap, energy and
 * analytic errors, and the tiles (penetration, tunnels, ghost bumps) everywhere. */

typedef struct check {
    char what[40], value[40], target[24];
    int pass;
} check;

typedef struct checks {
    check c[8];
    int n;
} checks;

/* Compare v with a target: op "<=" or "==". A figure that does not apply (< 0) adds nothing. */
static void add_check(checks *cs, const char *what, double v, const char *op, double target)
{
    if (v < 0 || cs->n == 8) return;
    check *c = &cs->c[cs->n++];
    snprintf(c->what, sizeof c->what, "%s", what);
    /* Times with one decimal, errors as in the --wide table (two digits). */
    if (strncmp(what, "time (", 6) == 0 && v >= 1) snprintf(c->value, sizeof c->value, "%.1f", v);
    else snprintf(c->value, sizeof c->value, "%.2g", v);
    snprintf(c->target, sizeof c->target, "%s %.3g", op, target);
    c->pass = op[0] == '=' ? v == target : v <= target;
}

/* The checks of one scene. rain_ns: rain's time in this run, or -1. */
static void scene_checks(const char *name, const run_result *r, double rain_ns, checks *cs)
{
    const metrics *m = &r->m;
    cs->n = 0;
    static const struct {
        const char *scene;
        double ns;
    } times[] = {{"rain", 170}, {"particles", 35}, {"asleep", 3}};
    for (size_t i = 0; i < sizeof times / sizeof times[0]; i++)
        if (strcmp(name, times[i].scene) == 0) add_check(cs, "time (ns/body-step)", r->ns, "<=", times[i].ns);
    if (strcmp(name, "sparse") == 0 && rain_ns > 0) add_check(cs, "time / rain's", r->ns / rain_ns, "<=", 1.0 / 3);
    if (strcmp(name, "rain") == 0) {
        add_check(cs, "worst overlap (cell)", m->overlap, "<=", 0.15);
        add_check(cs, "deep pairs", (double)m->deep_pairs, "==", 0);
    }
    if (strcmp(name, "pile") == 0) {
        add_check(cs, "settled overlap (cell)", m->settled, "<=", 0.10);
        add_check(cs, "deep pairs", (double)m->deep_pairs, "==", 0);
    }
    if (strcmp(name, "bounce") == 0) {
        add_check(cs, "energy drift", m->energy_drift, "<=", 0.005);
        add_check(cs, "apex error", m->bounce_error, "<=", 0.05);
    }
    if (strcmp(name, "gas") == 0) add_check(cs, "energy drift", m->energy_drift, "<=", 0.005);
    if (strcmp(name, "flight") == 0) add_check(cs, "path error", m->flight_error, "<=", 1e-4);
    if (strcmp(name, "rest") == 0) add_check(cs, "jitter (cell)", m->jitter, "<=", 2.5e-6);
    if (strcmp(name, "incline") == 0) add_check(cs, "jitter (cell)", m->jitter, "<=", 5.4e-6);
    /* The tiles, in every scene: penetration, tunnels, ghost bumps. */
    add_check(cs, "tile penetration (cell)", m->penetration, "<=", 3.7e-4);
    add_check(cs, "tunnels", (double)m->tunnelled, "==", 0);
    if (m->ghost_bumps >= 0) add_check(cs, "ghost bumps", (double)m->ghost_bumps, "==", 0);
}

#define NARROW_HEAD "%-11s %7s %12s %7s  %-24s %9s %-10s %s\n"

static void print_narrow_header(void)
{
    printf(NARROW_HEAD, "scene", "bodies", "ns/body-step", "spread", "check", "value", "target", "result");
}

/* One row per check; the scene's figures on the first. */
static void print_narrow(const char *name, const run_result *r, const checks *cs, int *failed)
{
    char ns[32], spread[32], bodies[32];
    if (r->ns >= 1) snprintf(ns, sizeof ns, "%.2f", r->ns);
    else snprintf(ns, sizeof ns, "%.2g", r->ns);
    snprintf(spread, sizeof spread, "%.1f%%", run_spread(r));
    snprintf(bodies, sizeof bodies, "%d", r->bodies);
    if (cs->n == 0) printf("%-11s %7s %12s %7s  (no target)\n", name, bodies, ns, spread);
    for (int i = 0; i < cs->n; i++) {
        const check *c = &cs->c[i];
        printf(NARROW_HEAD, i ? "" : name, i ? "" : bodies, i ? "" : ns, i ? "" : spread, c->what, c->value, c->target,
               c->pass ? "PASS" : "FAIL");
        *failed += !c->pass;
    }
}

int bench_world(const bench_opts *opts, int nargs, char **args)
{
    static const char *const all[] = {"rain",  "particles", "giants", "sparse", "pile",   "asleep", "scale", "slide",
                                      "bounce", "gas",      "incline", "flight", "rest",  "tunnel", "free",  "touching"};
    const int nall = (int)(sizeof all / sizeof all[0]);
    if (opts->runs < 1) {
        fprintf(stderr, "ntile bench world: --runs must be at least 1\n");
        return CLI_USAGE;
    }
    for (int i = 0; i < nargs; i++) {
        int known = 0;
        for (int k = 0; k < nall; k++) known |= strcmp(args[i], all[k]) == 0;
        if (!known) {
            fprintf(stderr, "ntile bench world: unknown scene '%s' (scenes:", args[i]);
            for (int k = 0; k < nall; k++) fprintf(stderr, " %s", all[k]);
            fprintf(stderr, ")\n");
            return CLI_USAGE;
        }
    }
    int total = 0;
    for (int k = 0; k < nall; k++) {
        int wanted = nargs == 0;
        for (int i = 0; i < nargs; i++) wanted |= strcmp(args[i], all[k]) == 0;
        total += wanted;
    }
    printf("# ntile bench world: dt 1/40 s, %s, median of %d runs (the scenes: tools/ntile/scene.c)\n",
           SCALAR_NAME, opts->runs);
    if (opts->wide) {
        bench_print_legend();
        bench_print_header("scene");
    } else {
        printf("# ns/body-step: median of the timed runs; spread: (max - min) / 2 / median. Each check against its\n"
               "# targets: README \"Benchmarks\"; every error column: --wide; phases: --profile.\n");
        print_narrow_header();
    }
    fflush(stdout);
    engine_setting none = {"ntile", 0, 0, 1, -1, 0};
    double rain_ns = -1;
    int done = 0, failed = 0, checked = 0;
    for (int k = 0; k < nall; k++) {
        int wanted = nargs == 0;
        for (int i = 0; i < nargs; i++) wanted |= strcmp(args[i], all[k]) == 0;
        if (!wanted) continue;
        const char *name = all[k];
        fprintf(stderr, "ntile bench world: [%d/%d] %s ...\n", ++done, total, name);
        fflush(stderr);
        if (strcmp(name, "scale") == 0) {
            static const int counts[] = {1000, 10000, 100000};
            static const char *const labels[] = {"scale-1k", "scale-10k", "scale-100k"};
            double lo = 1e300, hi = 0;
            for (int j = 0; j < 3; j++) {
                scene s;
                if (!scene_make("rain", counts[j], &s)) return CLI_USAGE;
                /* the metrics of rain are in the rain row; here only the time */
                run_result r = bench_run(&engine_ntile, &none, &s, opts->runs, 0);
                scene_free(&s);
                if (!r.ok) return CLI_USAGE;
                r.m = (metrics){-1, -1, 0, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};
                if (opts->wide) {
                    bench_print_row(labels[j], &r, NULL);
                } else {
                    checks none_checks = {.n = 0};
                    print_narrow(labels[j], &r, &none_checks, &failed);
                }
                bench_warn_spread(stderr, "world", labels[j], run_spread(&r));
                lo = r.ns < lo ? r.ns : lo;
                hi = r.ns > hi ? r.ns : hi;
            }
            double sp = (hi / lo - 1) * 100;
            int pass = sp <= 35;
            printf("%-18s spread %.1f %% (largest / smallest ns per body-step, 1k to 100k bodies; target <= 35 %%) %s\n",
                   "scale", sp, pass ? "PASS" : "FAIL");
            failed += !pass;
            checked++;
            fflush(stdout);
            continue;
        }
        scene s;
        if (!scene_make(name, 0, &s)) {
            fprintf(stderr, "ntile bench world: could not build scene '%s'\n", name);
            return CLI_USAGE;
        }
        long long steps0 = ntile_body_steps;
        run_result r = bench_run(&engine_ntile, &none, &s, opts->runs, 1);
        nt_world_profile prof;
        int profiled = r.ok && opts->profile && ntile_scene_profile(&s, &prof);
        if (r.ok && opts->profile && !profiled)
            fprintf(stderr, "ntile bench world: could not profile '%s' (its phases are left out)\n", name);
        double per = 1e6 / ((double)s.nbodies * s.steps); /* ms in all -> ns per body-step */
        scene_free(&s);
        if (!r.ok) return CLI_USAGE;
        if (strcmp(name, "rain") == 0) rain_ns = r.ns;
        checks cs;
        scene_checks(name, &r, rain_ns, &cs);
        checked += cs.n;
        if (opts->wide) {
            bench_print_row(name, &r, NULL);
            for (int i = 0; i < cs.n; i++) {
                printf("#  %-16s %-24s %9s %-10s %s\n", name, cs.c[i].what, cs.c[i].value, cs.c[i].target,
                       cs.c[i].pass ? "PASS" : "FAIL");
                failed += !cs.c[i].pass;
            }
        } else {
            print_narrow(name, &r, &cs, &failed);
        }
        bench_warn_spread(stderr, "world", name, run_spread(&r));
        if (profiled)
            printf("#  %-16s phases, ns/body-step: pairs %.1f  contacts %.1f  correct %.1f  solve %.1f  move %.1f  "
                   "sleep %.1f  (one more run, nt_world_get_profile)\n",
                   name, prof.pairs * per, prof.contacts * per, prof.correct * per, prof.solve * per, prof.move * per,
                   prof.sleep * per);
        printf("#  %-16s body-steps inside nt_world_step: %lld (every run: timed, warm-up, metrics%s)\n", name,
               ntile_body_steps - steps0, profiled ? " and profile" : "");
        fflush(stdout);
    }
    printf("# checks: %d passed, %d failed\n", checked - failed, failed);
    return CLI_OK;
}
