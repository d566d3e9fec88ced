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
    printf("# ntile bench world: dt 1/40 s, %s, median of %d runs; scenes are described in tools/ntile/scene.c\n",
           SCALAR_NAME, opts->runs);
    bench_print_legend();
    bench_print_header("scene");
    engine_setting none = {"ntile", 0, 0, 1, -1, 0};
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
                scene s;
                if (!scene_make("rain", counts[j], &s)) return CLI_USAGE;
                /* the metrics of rain are in the rain row; here only the time */
                run_result r = bench_run(&engine_ntile, &none, &s, opts->runs, 0);
                scene_free(&s);
                if (!r.ok) return CLI_USAGE;
                r.m = (metrics){-1, -1, 0, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};
                bench_print_row(labels[j], &r, NULL);
                lo = r.ns < lo ? r.ns : lo;
                hi = r.ns > hi ? r.ns : hi;
            }
            printf("%-18s spread %.1f %% (largest / smallest ns per body-step, 1k to 100k bodies)\n", "scale",
                   (hi / lo - 1) * 100);
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
        int profiled = r.ok && ntile_scene_profile(&s, &prof);
        double per = 1e6 / ((double)s.nbodies * s.steps); /* ms in all -> ns per body-step */
        scene_free(&s);
        if (!r.ok) return CLI_USAGE;
        bench_print_row(name, &r, NULL);
        if (profiled)
            printf("#  %-16s phases, ns/body-step: pairs %.1f  contacts %.1f  correct %.1f  solve %.1f  move %.1f  "
                   "sleep %.1f  (one more run, nt_world_get_profile)\n",
                   name, prof.pairs * per, prof.contacts * per, prof.correct * per, prof.solve * per, prof.move * per,
                   prof.sleep * per);
        printf("#  %-16s body-steps inside nt_world_step: %lld (every run: timed, warm-up, metrics and profile)\n", name,
               ntile_body_steps - steps0);
        fflush(stdout);
    }
    return CLI_OK;
}
