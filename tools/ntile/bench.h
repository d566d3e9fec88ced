/* ntile bench — what the benchmark files share (bench.c, bench_world.c). */
#ifndef NTILE_BENCH_H
#define NTILE_BENCH_H

#include <stdint.h>
#include "ntile/ntile.h"

#define SCALAR_NAME (NT_REAL_IS_DOUBLE ? "double" : "float")

typedef struct bench_opts {
    int runs;      /* timed runs; the median is reported */
    double min_ms; /* shortest duration of one run (micro-benchmarks) */
} bench_opts;

/* CLOCK_MONOTONIC in nanoseconds. */
double bench_now_ns(void);
/* qsort comparison of doubles. */
int bench_cmp_double(const void *a, const void *b);
/* splitmix64 step, and a uniform double in [lo, hi) from it. */
uint64_t bench_rng_next(uint64_t *s);
double bench_rng_range(uint64_t *s, double lo, double hi);

/* The rain scene of `bench world` with n bodies (the map grows with sqrt(n): 256 x 256
 * cells at 10,000), for the soak test; ids receives the handles. NULL on failure
 * (message on stderr). */
nt_world *bench_rain_world(int bodies, nt_body_id *ids);

/* `ntile bench world [SCENE...]` (bench_world.c). */
int bench_world(const bench_opts *opts, int nargs, char **args);

#endif
