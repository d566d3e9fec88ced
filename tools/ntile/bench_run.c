/* ntile bench — run a scene on an engine: timing and error metrics (see engine.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "engine.h"

/* One untimed step, counted in *warm and tracked by t (when given). */
static int warm_step(const engine *e, void *w, int *warm, metrics_tracker *t, body_state *st)
{
    if (!e->step(w)) return 0;
    (*warm)++;
    if (t) {
        e->read(w, st);
        metrics_step(t, st);
    }
    return 1;
}

void *bench_warmed(const engine *e, const engine_setting *set, const scene *s, int *warm, metrics_tracker *t,
                   body_state *st)
{
    void *w = e->create(s, set);
    if (!w) return NULL;
    *warm = 0;
    for (int k = 0; k < s->warm_steps; k++)
        if (!warm_step(e, w, warm, t, st)) goto fail;
    for (int k = 0; k < s->until_asleep && e->awake(w) > 0; k++)
        if (!warm_step(e, w, warm, t, st)) goto fail;
    /* And one step more: the step after the last body falls asleep puts its contacts
     * aside (ntile parks them then), a one-off that belongs to falling asleep. */
    if (s->until_asleep > 0 && e->awake(w) == 0 && !warm_step(e, w, warm, t, st)) goto fail;
    return w;
fail:
    e->destroy(w);
    return NULL;
}

double run_spread(const run_result *r) { return r->ns > 0 ? (r->ns_max - r->ns_min) / 2 / r->ns * 100 : 0; }

run_result bench_run(const engine *e, const engine_setting *set, const scene *s, int runs, int with_metrics)
{
    run_result res = {0};
    double start = bench_now_ns();
    res.bodies = s->nbodies;
    res.steps = s->steps;
    if (runs < 1) runs = 1;
    double *per = malloc(sizeof(double) * (size_t)runs);
    body_state *st = malloc(sizeof *st * (size_t)(s->nbodies > 0 ? s->nbodies : 1));
    metrics_tracker *t = with_metrics ? metrics_begin(s) : NULL;
    int ok = per && st && (!with_metrics || t);
    for (int r = 0; r < runs && ok; r++) {
        /* the first run also feeds the metrics: only the steps are timed */
        metrics_tracker *tr = r == 0 ? t : NULL;
        int warm = 0;
        void *w = bench_warmed(e, set, s, &warm, tr, st);
        if (!w) {
            ok = 0;
            break;
        }
        double elapsed = 0, min_ns = s->min_timed_ms * 1e6;
        int k = 0;
        /* (The step cap guards against a clock too coarse to see a step.) */
        for (; ok && (k < s->steps || (elapsed < min_ns && k < 100000000)); k++) {
            double t0 = bench_now_ns();
            ok = e->step(w);
            elapsed += bench_now_ns() - t0;
            if (tr && k < s->steps) {
                e->read(w, st);
                metrics_step(tr, st);
            }
        }
        res.awake = e->awake(w);
        res.warm = warm;
        e->destroy(w);
        per[r] = elapsed / ((double)(s->nbodies > 0 ? s->nbodies : 1) * (double)(k > 0 ? k : 1));
    }
    if (ok) {
        res.ns = bench_median(per, runs, &res.ns_min, &res.ns_max);
        if (t) res.m = metrics_get(t);
        res.ok = 1;
    }
    metrics_end(t);
    free(per);
    free(st);
    res.wall_s = (bench_now_ns() - start) * 1e-9;
    return res;
}

/* A figure, or "-" when it does not apply (negative). */
static const char *fig(char *buf, size_t n, const char *fmt, double v)
{
    if (v < 0) snprintf(buf, n, "-");
    else snprintf(buf, n, fmt, v);
    return buf;
}

/* The analytic error that applies to a scene, as "kind value". */
static const char *analytic(char *buf, size_t n, const metrics *m)
{
    if (m->bounce_error >= 0) snprintf(buf, n, "apex %.2g", m->bounce_error);
    else if (m->incline_error >= 0) snprintf(buf, n, "accel %.2g", m->incline_error);
    else if (m->flight_error >= 0) snprintf(buf, n, "path %.2g", m->flight_error);
    else snprintf(buf, n, "-");
    return buf;
}

void bench_print_header(const char *first)
{
    printf("%-26s %7s %7s %10s %7s %9s %9s %9s %9s %6s %6s %9s %8s %9s %12s\n", first, "bodies", "awake",
           "ns/body-step", "spread", "pen", "overlap", "p99", "settled", "deep", "tunnel", "ghost", "energy", "jitter", "analytic");
}

void bench_print_row(const char *label, const run_result *r, const char *extra)
{
    char a[32], b[32], c[32], d[32], e[32], p[32], q[32];
    const metrics *m = &r->m;
    char ghost[32];
    if (m->ghost_bumps < 0) snprintf(ghost, sizeof ghost, "-");
    else snprintf(ghost, sizeof ghost, "%d", m->ghost_bumps);
    char deep[32];
    if (m->deep_pairs < 0) snprintf(deep, sizeof deep, "-");
    else snprintf(deep, sizeof deep, "%ld", m->deep_pairs);
    char ns[32];
    /* Two decimals, or two significant digits below 1 (an asleep body is a few
     * thousandths of a nanosecond). */
    if (r->ns >= 1) snprintf(ns, sizeof ns, "%.2f", r->ns);
    else snprintf(ns, sizeof ns, "%.2g", r->ns);
    printf("%-26s %7d %7d %10s %6.1f%% %9s %9s %9s %9s %6s %6d %9s %8s %9s %12s%s\n", label, r->bodies, r->awake, ns,
           run_spread(r), fig(a, sizeof a, "%.2g", m->penetration), fig(b, sizeof b, "%.2g", m->overlap),
           fig(p, sizeof p, "%.2g", m->overlap_p99), fig(q, sizeof q, "%.2g", m->settled), deep, m->tunnelled, ghost, fig(c, sizeof c, "%.2g", m->energy_drift), fig(d, sizeof d, "%.2g", m->jitter),
           analytic(e, sizeof e, m), extra ? extra : "");
}

void bench_print_legend(void)
{
    printf("# ns/body-step: median of the timed runs; spread: (max - min) / 2 / median over the runs.\n"
           "# pen: deepest penetration into a tile (cells, ntile's exact nt_map_overlap_depth);\n"
           "# overlap: deepest overlap of two colliding bodies (cells); p99: 99th percentile over the steps of\n"
           "# each step's deepest overlap (cells); settled: deepest overlap after the first %.2g s; deep: pair-steps overlapping by %.2g cell or more (a pair\n"
           "# counts once per step it ends that deep); tunnel: bodies whose centre ended in\n"
           "# solid or outside the map, or passed through solid; ghost: bodies that moved up faster than\n"
           "# %.2g cell/s sliding on a flat floor; energy: max |E - E0| / E0 (bounce 1 bodies); jitter: largest\n"
           "# move of a body that should rest (cells); analytic: relative error of bounce apex heights,\n"
           "# incline acceleration or free-flight path. '-': nothing in the scene it applies to.\n",
           SETTLE_TIME, DEEP_OVERLAP, GHOST_SPEED);
}

