/* ntile bench — Pareto fronts, CSV and SVG plots (no plotting dependency). */
#ifndef NTILE_BENCH_PLOT_H
#define NTILE_BENCH_PLOT_H

#include <stdio.h>

typedef struct plot_point {
    double x, y;   /* both > 0 for log axes; smaller is better on both */
    int series;    /* colour / legend index */
    int front;     /* set by plot_pareto */
    char label[64];
} plot_point;

/* Mark the points no other point beats on both x and y (<= on both, < on one).
 * Returns how many are on the front. */
int plot_pareto(plot_point *p, int n);

/* One SVG document holding `panels` plots side by side. */
typedef struct plot_panel {
    const char *title, *xlabel, *ylabel;
    const plot_point *points;
    int count;
} plot_panel;

/* Write the SVG: log-log axes with decade ticks, one circle per point (filled when
 * on the front), the front joined by a line, a legend of series names. Returns 0 on
 * a write error. */
int plot_svg(FILE *f, const plot_panel *panels, int npanels, const char *const *series, int nseries);

/* CSV: one header line, then rows of comma-separated fields (no quoting: fields never
 * hold commas). csv_split splits a line in place; returns the field count. */
int csv_split(char *line, char **fields, int max);

#endif
