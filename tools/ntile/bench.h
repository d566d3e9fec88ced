/* ntile bench — what the benchmark files share (bench.c, bench_world.c, ...). */
#ifndef NTILE_BENCH_H
#define NTILE_BENCH_H

#include <stdint.h>
#include <stdio.h>
#include "ntile/ntile.h"

#define SCALAR_NAME (NT_REAL_IS_DOUBLE ? "double" : "float")

typedef struct bench_opts {
    int runs;      /* timed runs; the median is reported */
    double min_ms; /* shortest duration of one run (micro-benchmarks) */
    const char *out; /* --out: output file (sweep: CSV; plot: prefix of .csv and .svg) */
    int wide;        /* --wide (world): every error column in one wide row per scene */
    int profile;     /* --profile (world, scaling): the step split by phase under each scene or body count */
} bench_opts;

/* A run's spread above this (percent) means the host was busy: a warning on stderr. */
#define BENCH_SPREAD_WARN 25.0
/* The warning on f (stderr in the benchmarks), when a spread (percent) is above
 * BENCH_SPREAD_WARN; returns 1 when it warned. */
int bench_warn_spread(FILE *f, const char *bench, const char *what, double spread);

/* CLOCK_MONOTONIC in nanoseconds. */
double bench_now_ns(void);
/* qsort comparison of doubles. */
int bench_cmp_double(const void *a, const void *b);
/* Options of a benchmark that takes no words and reports medians: 1 when there are no
 * words and --runs is at least 5, else 0 with a message on stderr. */
int bench_plain_args(const char *name, const bench_opts *opts, int nargs, char **args);
/* The median of v[0..n-1] (n >= 1), which it sorts; *lo and *hi (may be NULL) get the
 * smallest and largest. */
double bench_median(double *v, int n, double *lo, double *hi);
/* splitmix64 step, and a uniform double in [lo, hi) from it. */
uint64_t bench_rng_next(uint64_t *s);
double bench_rng_range(uint64_t *s, double lo, double hi);

/* `ntile bench world [SCENE...]` (bench_world.c), `scaling` (bench_scaling.c),
 * `sweep` and `plot` (bench_sweep.c), `character` (bench_character.c). */
int bench_world(const bench_opts *opts, int nargs, char **args);
int bench_scaling(const bench_opts *opts, int nargs, char **args);
int bench_sweep(const bench_opts *opts, int nargs, char **args);
int bench_plot(const bench_opts *opts, int nargs, char **args);
int bench_character(const bench_opts *opts, int nargs, char **args);

#endif
