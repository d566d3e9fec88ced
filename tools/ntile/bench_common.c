/* ntile bench — helpers shared by the ntile CLI's benchmarks and bench-peers. */
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "bench.h"

double bench_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

int bench_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int bench_plain_args(const char *name, const bench_opts *opts, int nargs, char **args)
{
    if (nargs > 0) {
        fprintf(stderr, "ntile bench %s: unexpected argument '%s'\n", name, args[0]);
        return 0;
    }
    if (opts->runs < 5) {
        fprintf(stderr, "ntile bench %s: --runs must be at least 5 (the figure is a median)\n", name);
        return 0;
    }
    return 1;
}

double bench_median(double *v, int n, double *lo, double *hi)
{
    qsort(v, (size_t)n, sizeof *v, bench_cmp_double);
    if (lo) *lo = v[0];
    if (hi) *hi = v[n - 1];
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

/* splitmix64: a fixed seed makes every run time the same placements. */
uint64_t bench_rng_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [lo, hi). */
double bench_rng_range(uint64_t *s, double lo, double hi)
{
    return lo + (hi - lo) * ((double)(bench_rng_next(s) >> 11) * 0x1.0p-53);
}

int bench_warn_spread(FILE *f, const char *bench, const char *what, double spread)
{
    if (!(spread > BENCH_SPREAD_WARN)) return 0;
    fprintf(f, "ntile bench %s: warning: %s: spread %.1f %% over the runs (above %.0f %%): the host was busy, "
                        "the time is not reliable; run again on a quiet machine\n",
            bench, what, spread, BENCH_SPREAD_WARN);
    return 1;
}
