/* ntile soak — a long run of the rain scene that checks, after every step:
 *   - every position and velocity is finite;
 *   - every body's centre is inside the map;
 *   - no dynamic body is inside solid by more than 1e-3 cell (nt_map_overlap_depth);
 *   - a body asleep before and after a step has not moved (not one bit);
 * and reports the total energy (kinetic + gravitational) step to step: its largest
 * rise, which position correction of overlapping bodies can cause, is printed, and
 * fails the run above `--max-energy-rise` (relative to the energy scale m g H).
 *
 * `ntile soak [--steps N] [--bodies N] [--max-energy-rise F]`; exit 0 when every check
 * held, 1 when one failed (the first failure is printed), 2 for usage errors.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"
#include "engine.h"
#include "scene.h"
#include "ntile/ntile.h"

typedef struct soak_state {
    nt_vec2 p;
    int asleep;
} soak_state;

void cli_soak_usage(FILE *f)
{
    fputs("  ntile soak [--steps N] [--bodies N] [--max-energy-rise F]\n"
          "      Run the rain scene (default 1,000,000 steps, 10,000 bodies) checking after\n"
          "      every step: finite numbers, bodies inside the map, no body inside solid by\n"
          "      more than 1e-3 cell, sleeping bodies not moving; prints the figures. Exit 1\n"
          "      when a check fails.\n",
          f);
}

static int arg_long(int argc, char **argv, int *i, long lo, long hi, long *out)
{
    char *end;
    long v = *i + 1 < argc ? strtol(argv[*i + 1], &end, 10) : 0;
    if (*i + 1 >= argc || end == argv[*i + 1] || *end || v < lo || v > hi) {
        fprintf(stderr, "ntile soak: %s needs a whole number in %ld..%ld\n", argv[*i], lo, hi);
        return 0;
    }
    *out = v;
    (*i)++;
    return 1;
}

int cli_soak(int argc, char **argv)
{
    long steps = 1000000, bodies = 10000;
    double max_rise = 1e-4;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            printf("usage:\n");
            cli_soak_usage(stdout);
            return CLI_OK;
        } else if (strcmp(argv[i], "--steps") == 0) {
            if (!arg_long(argc, argv, &i, 1, 1000000000L, &steps)) return CLI_USAGE;
        } else if (strcmp(argv[i], "--bodies") == 0) {
            if (!arg_long(argc, argv, &i, 1, 200000, &bodies)) return CLI_USAGE;
        } else if (strcmp(argv[i], "--max-energy-rise") == 0 && i + 1 < argc) {
            char *end;
            max_rise = strtod(argv[++i], &end);
            if (*end || !(max_rise >= 0)) {
                fprintf(stderr, "ntile soak: --max-energy-rise needs a number >= 0\n");
                return CLI_USAGE;
            }
        } else {
            fprintf(stderr, "ntile soak: unknown argument '%s'\nusage:\n", argv[i]);
            cli_soak_usage(stderr);
            return CLI_USAGE;
        }
    }
    nt_body_id *ids = malloc(sizeof *ids * (size_t)bodies);
    soak_state *st = malloc(sizeof *st * (size_t)bodies);
    scene sc;
    int made = ids && st && scene_make("rain", (int)bodies, &sc);
    nt_world *w = made ? ntile_scene_world(&sc, ids) : NULL;
    nt_real dt = made ? (nt_real)sc.dt : 0;
    if (made) {
        bodies = sc.nbodies;
        scene_free(&sc);
    }
    if (!w) {
        fprintf(stderr, "ntile soak: cannot build the scene\n");
        free(ids);
        free(st);
        return CLI_USAGE;
    }
    const nt_map *map = nt_world_get_map(w);
    double cell = (double)nt_map_get_cell_size(map), mw = nt_map_get_width(map) * cell, mh = nt_map_get_height(map) * cell;
    double g = (double)nt_world_get_gravity(w).y;
    /* Energy scale: every body lifted across the whole map. */
    double mass = 0;
    for (long i = 0; i < bodies; i++) mass += (double)nt_body_get_mass(w, ids[i]);
    double escale = mass * fabs(g) * mh;
    double worst_pen = 0, worst_rise = 0, e_prev = 0;
    long wakes = 0, sleeps = 0, failed_step = -1;
    char why[256] = "";
    for (long i = 0; i < bodies; i++) {
        st[i].p = nt_body_get_position(w, ids[i]);
        st[i].asleep = !nt_body_is_awake(w, ids[i]);
    }
    for (long s = 1; s <= steps && failed_step < 0; s++) {
        if (nt_world_step(w, dt) != NT_OK) {
            snprintf(why, sizeof why, "nt_world_step failed");
            failed_step = s;
            break;
        }
        double e = 0;
        for (long i = 0; i < bodies && failed_step < 0; i++) {
            nt_vec2 p = nt_body_get_position(w, ids[i]), v = nt_body_get_velocity(w, ids[i]);
            if (!isfinite((double)p.x) || !isfinite((double)p.y) || !isfinite((double)v.x) || !isfinite((double)v.y)) {
                snprintf(why, sizeof why, "body %ld is not finite", i);
                failed_step = s;
                break;
            }
            if (p.x < 0 || p.y < 0 || p.x > mw || p.y > mh) {
                snprintf(why, sizeof why, "body %ld outside the map at (%g, %g)", i, (double)p.x, (double)p.y);
                failed_step = s;
                break;
            }
            double pen = (double)nt_map_overlap_depth(map, p, nt_body_get_shape(w, ids[i])) / cell;
            if (pen > worst_pen) worst_pen = pen;
            if (pen > 1e-3) {
                snprintf(why, sizeof why, "body %ld inside solid by %g cell", i, pen);
                failed_step = s;
                break;
            }
            int asleep = !nt_body_is_awake(w, ids[i]);
            if (asleep && st[i].asleep && memcmp(&p, &st[i].p, sizeof p) != 0) {
                snprintf(why, sizeof why, "body %ld moved while asleep", i);
                failed_step = s;
                break;
            }
            wakes += st[i].asleep && !asleep;
            sleeps += !st[i].asleep && asleep;
            st[i].p = p;
            st[i].asleep = asleep;
            double m = (double)nt_body_get_mass(w, ids[i]);
            e += 0.5 * m * ((double)v.x * v.x + (double)v.y * v.y) - m * g * (double)p.y;
        }
        if (failed_step >= 0) break;
        if (s > 1 && (e - e_prev) / escale > worst_rise) worst_rise = (e - e_prev) / escale;
        e_prev = e;
        if (worst_rise > max_rise) {
            snprintf(why, sizeof why, "total energy rose by %.3g of m g H in one step", worst_rise);
            failed_step = s;
        }
    }
    printf("soak: %ld steps of rain with %ld bodies: worst penetration %.3g cell, worst energy rise %.3g of m g H "
           "per step, %ld sleeps, %ld wakes, %d awake at the end\n",
           failed_step < 0 ? steps : failed_step, bodies, worst_pen, worst_rise, sleeps, wakes, nt_world_get_awake_count(w));
    if (failed_step >= 0) printf("soak: FAILED at step %ld: %s\n", failed_step, why);
    nt_world_destroy(w);
    free(ids);
    free(st);
    return failed_step < 0 ? CLI_OK : CLI_INPUT_ERRORS;
}
