/* bench-peers — the tile map as closed outlines, for engines without tiles.
 *
 * The solid of the map (N's tiles, plus a ring of FULL cells around the map for its
 * border) becomes closed loops of vertices in scene units: the boundary of the union
 * of the tiles, seams between solid tiles removed, collinear runs merged. Walking a
 * loop, the solid is on the left on screen (y down) and the free side on the right:
 * edge a->b has its outward normal (-(b.y - a.y), b.x - a.x) / |b - a|.
 *
 * Round tiles become ARC_SEGMENTS straight pieces per quarter circle, chosen so the
 * outline contains the exact solid: a convex arc gets tangent segments (outside the
 * disc), a concave arc chords (outside the free disc). A body that never overlaps the
 * outlines never overlaps the exact tiles, so ntile's exact penetration measures the
 * peer engine's solver, not this approximation (which may leave gaps of at most
 * 1/cos(pi/(4 ARC_SEGMENTS)) - 1 = 0.5 % of a cell).
 */
#ifndef NTILE_BENCH_GEOMETRY_H
#define NTILE_BENCH_GEOMETRY_H

#include "scene.h"

#define ARC_SEGMENTS 8

typedef struct geo_point {
    double x, y;
} geo_point;

typedef struct geo_loops {
    int count;         /* loops */
    int *start;        /* count + 1 offsets into points: loop k is points[start[k]] .. points[start[k+1] - 1] */
    geo_point *points; /* closed loops: the last point joins the first */
    int edges;         /* total edges */
} geo_loops;

/* Outlines of scene s; 0 when memory runs out. */
int geo_build(const scene *s, geo_loops *out);
void geo_free(geo_loops *g);

#endif
