/* bench-peers — the same scenes in ntile, Chipmunk2D 7 and Box2D 2.4, in one run.
 *
 *   build/bench-peers [SCENE...] [--runs N] [--bodies N] [--tune]
 *
 * Every scene (tools/ntile/scene.c) is built from the same data by each engine's
 * builder (engine_ntile.c, chipmunk.c, box2d.c + box2d_shim.cpp) with the same map,
 * bodies (no rotation), dt, gravity, bounce and friction. Each peer runs at its
 * default solver settings and at a setting tuned to match ntile's error (found with
 * --tune, below). Per scene and engine it prints ns per body-step (median of N runs,
 * default 5), the error metrics of metrics.h, and the time ratio ntile/peer.
 * rain and particles run at --bodies bodies (default 2,000, map 116 x 116): at
 * 10,000 the peers alone take several minutes per scene (Box2D's continuous
 * collision costs grow faster than the body count), past this benchmark's budget of
 * two minutes a run.
 *
 * --tune: on rain and particles, try each peer's settings from cheap to expensive and
 * mark any whose tile penetration is at most ntile's with no more tunnelled bodies.
 * On this machine none did (ntile keeps bodies within 5e-4 cell of the surface; Box2D's
 * own slop is 5e-3 cell): the `tuned` settings below are the most accurate ones tried
 * that keep a run within two minutes (zero tunnelled bodies, the least penetration).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"
#include "engine.h"
#include "peers.h"

typedef struct peer {
    const engine *e;
    engine_setting def, tuned;
} peer;

/* Chipmunk: 10 iterations, collision slop 0.1 unit (1/240 cell) by default.
 * Box2D: 8 velocity and 3 position iterations (its manual's recommendation). */
static const peer peers[] = {
    {&engine_chipmunk, {"default", 0, 0, 1, -1, 0}, {"tuned", 10, 0, 16, 0.0001, 0}},
    {&engine_box2d, {"default", 8, 3, 1, -1, 0}, {"tuned", 8, 3, 4, -1, 0}},
};
#define NPEERS (int)(sizeof peers / sizeof peers[0])

static const char *const default_scenes[] = {"rain", "particles", "slide", "bounce", "gas",
                                             "incline", "flight", "rest", "tunnel"};

static void usage(FILE *f)
{
    fprintf(f, "usage: bench-peers [SCENE...] [--runs N] [--bodies N] [--tune]\n  scenes:");
    for (int i = 0; scene_names[i]; i++) fprintf(f, " %s", scene_names[i]);
    fprintf(f, "\n");
}

static int known_scene(const char *name)
{
    for (int i = 0; scene_names[i]; i++)
        if (strcmp(scene_names[i], name) == 0) return 1;
    return 0;
}

static void print_setting(const engine *e, const engine_setting *set, char *buf, size_t n)
{
    if (e == &engine_chipmunk)
        snprintf(buf, n, "%s: %d iterations, slop %s, %d substep%s", set->label,
                 set->velocity_iterations > 0 ? set->velocity_iterations : 10,
                 set->slop >= 0 ? "" : "0.1 unit", set->substeps, set->substeps > 1 ? "s" : "");
    else
        snprintf(buf, n, "%s: %d velocity + %d position iterations, %d substep%s, continuous collision %s",
                 set->label, set->velocity_iterations, set->position_iterations, set->substeps,
                 set->substeps > 1 ? "s" : "", set->no_ccd ? "off" : "on");
    if (e == &engine_chipmunk && set->slop >= 0) {
        char tail[160];
        snprintf(tail, sizeof tail, "%s: %d iterations, slop %g cell, %d substep%s", set->label,
                 set->velocity_iterations > 0 ? set->velocity_iterations : 10, set->slop, set->substeps,
                 set->substeps > 1 ? "s" : "");
        snprintf(buf, n, "%s", tail);
    }
}

static int tune(int runs, int bodies)
{
    static const engine_setting cp_try[] = {
        {"c1", 10, 0, 1, -1, 0},     {"c2", 10, 0, 1, 0.001, 0},  {"c3", 20, 0, 1, 0.001, 0},
        {"c4", 10, 0, 2, 0.001, 0},  {"c5", 10, 0, 2, 0.0002, 0}, {"c6", 20, 0, 2, 0.0002, 0},
        {"c7", 10, 0, 4, 0.0002, 0}, {"c8", 20, 0, 4, 0.0002, 0}, {"c9", 10, 0, 8, 0.0002, 0},
        {"c10", 10, 0, 16, 0.0001, 0}};
    static const engine_setting b2_try[] = {
        {"b1", 8, 3, 1, -1, 1}, {"b2", 8, 3, 1, -1, 0}, {"b3", 16, 6, 1, -1, 1}, {"b4", 8, 3, 2, -1, 1},
        {"b5", 8, 3, 2, -1, 0}, {"b6", 8, 3, 4, -1, 1}, {"b7", 8, 3, 4, -1, 0}, {"b8", 8, 3, 8, -1, 1}};
    const char *names[] = {"rain", "particles"};
    engine_setting none = {"ntile", 0, 0, 1, -1, 0};
    printf("# Chipmunk %s: %s\n", chipmunk_version(), chipmunk_build);
    for (int k = 0; k < 2; k++) {
        scene s;
        if (!scene_make(names[k], bodies, &s)) return 2;
        run_result nt = bench_run(&engine_ntile, &none, &s, runs, 1);
        printf("# tune %s: ntile %.1f ns, penetration %.2g, tunnelled %d\n", names[k], nt.ns, nt.m.penetration,
               nt.m.tunnelled);
        bench_print_header("setting");
        for (int p = 0; p < NPEERS; p++) {
            const engine_setting *list = p == 0 ? cp_try : b2_try;
            int count = p == 0 ? (int)(sizeof cp_try / sizeof cp_try[0]) : (int)(sizeof b2_try / sizeof b2_try[0]);
            for (int i = 0; i < count; i++) {
                run_result r = bench_run(peers[p].e, &list[i], &s, runs, 1);
                char label[128], desc[200];
                snprintf(label, sizeof label, "%s %s", peers[p].e->name, list[i].label);
                print_setting(peers[p].e, &list[i], desc, sizeof desc);
                int match = r.m.penetration <= nt.m.penetration && r.m.tunnelled <= nt.m.tunnelled;
                char extra[260];
                snprintf(extra, sizeof extra, "  %s%s", desc, match ? "  <- matches ntile" : "");
                bench_print_row(label, &r, extra);
                fflush(stdout);
            }
        }
        scene_free(&s);
    }
    return 0;
}

int main(int argc, char **argv)
{
    int runs = 5, do_tune = 0, nnames = 0, bodies = 2000;
    /* room for the arguments or the default list, whichever is longer */
    size_t room = (size_t)argc + sizeof default_scenes / sizeof default_scenes[0] + 1;
    const char **names = calloc(room, sizeof *names);
    if (!names) return 2;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc) {
            runs = atoi(argv[++i]);
            if (runs < 5) {
                fprintf(stderr, "bench-peers: --runs must be at least 5 (the figure is a median)\n");
                return 2;
            }
        } else if (strcmp(argv[i], "--bodies") == 0 && i + 1 < argc) {
            bodies = atoi(argv[++i]);
            if (bodies < 1 || bodies > 1000000) {
                fprintf(stderr, "bench-peers: --bodies needs a count in 1..1000000\n");
                return 2;
            }
        } else if (strcmp(argv[i], "--tune") == 0) {
            do_tune = 1;
        } else if (argv[i][0] == '-' || !known_scene(argv[i])) {
            fprintf(stderr, "bench-peers: unknown argument '%s'\n", argv[i]);
            usage(stderr);
            return 2;
        } else {
            names[nnames++] = argv[i];
        }
    }
    if (nt_real_size() != (int)sizeof(nt_real)) {
        fprintf(stderr, "bench-peers: built against a library with a different scalar type\n");
        return 2;
    }
    if (do_tune) {
        int rc = tune(runs, bodies);
        free(names);
        return rc;
    }
    if (nnames == 0)
        for (size_t i = 0; i < sizeof default_scenes / sizeof default_scenes[0]; i++) names[nnames++] = default_scenes[i];
    double start = bench_now_ns();
    printf("# bench-peers: ntile (%s) against Chipmunk2D 7.0.3 and Box2D 2.4.1, no rotation, same scenes; median of "
           "%d runs; rain and particles with %d bodies\n",
           SCALAR_NAME, runs, bodies);
    printf("# Chipmunk %s: %s\n", chipmunk_version(), chipmunk_build);
    for (int p = 0; p < NPEERS; p++) {
        char a[200], b[200];
        print_setting(peers[p].e, &peers[p].def, a, sizeof a);
        print_setting(peers[p].e, &peers[p].tuned, b, sizeof b);
        printf("# %s settings: %s; %s\n", peers[p].e->name, a, b);
    }
    bench_print_legend();
    printf("# ntile/peer: ntile's ns per body-step over the peer's (below 1: ntile is faster; 0.1: 10x faster)\n");
    bench_print_header("scene / engine");
    engine_setting none = {"ntile", 0, 0, 1, -1, 0};
    for (int k = 0; k < nnames; k++) {
        scene s;
        int sized = strcmp(names[k], "rain") == 0 || strcmp(names[k], "particles") == 0;
        if (!scene_make(names[k], sized ? bodies : 0, &s)) {
            fprintf(stderr, "bench-peers: could not build scene '%s'\n", names[k]);
            return 2;
        }
        run_result nt = bench_run(&engine_ntile, &none, &s, runs, 1);
        if (!nt.ok) return 2;
        char label[128];
        snprintf(label, sizeof label, "%s ntile", names[k]);
        bench_print_row(label, &nt, NULL);
        for (int p = 0; p < NPEERS; p++)
            for (int t = 0; t < 2; t++) {
                const engine_setting *set = t ? &peers[p].tuned : &peers[p].def;
                run_result r = bench_run(peers[p].e, set, &s, runs, 1);
                if (!r.ok) {
                    fprintf(stderr, "bench-peers: %s failed on %s\n", peers[p].e->name, names[k]);
                    return 2;
                }
                char extra[64];
                snprintf(extra, sizeof extra, "  ntile/peer %.3f (%.1fx)", nt.ns / r.ns, r.ns / nt.ns);
                snprintf(label, sizeof label, "%s %s %s", names[k], peers[p].e->name, set->label);
                bench_print_row(label, &r, extra);
                fflush(stdout);
            }
        scene_free(&s);
    }
    printf("# total %.1f s\n", (bench_now_ns() - start) * 1e-9);
    free(names);
    return 0;
}
