/* Independent geometric reference for the ntile tests.
 *
 * Everything here is written in double precision from the tile descriptions in
 * shared/reference/n-collision-notes.md, whatever nt_real is, and never calls the
 * engine (no nt_collide_*, no nt_tile_contains_point, no engine tables). Tests
 * compare the engine against these functions, never against the engine itself.
 *
 * Conventions are the engine's: unit cell [0,1]^2 per tile, y down, tile ids 0..33
 * with N's names. "Overlap" means the interiors intersect (touching is free). An
 * object is a box (half-sizes hw, hh) or a circle (radius r) that never rotates; a
 * box or circle of size 0 is a point (overlaps when strictly inside). Sizes are either
 * all zero or all positive.
 *
 * Minimum translation (MTV) = distance from the object's centre to the set F of
 * centres where the object is free. Two independent computations are provided:
 *  - ref_mtv_tile / ref_mtv_map: exhaustive candidates. Every boundary point of F is
 *    a contact position (a box corner on a tile edge or arc, a tile vertex on a box
 *    side, a circle tangent to an edge, vertex or arc), so it lies on one of a finite
 *    set of lines and circles built from every feature pair. The nearest free point is
 *    then the foot of the perpendicular from the centre onto one of those curves, or an
 *    intersection of two of them. All such points are generated, sorted by distance
 *    and checked with the independent overlap test; the first free one wins. Exact up
 *    to rounding (~1e-9: the free test shrinks the object by 1e-9 so that exact
 *    contact positions count as free despite rounding).
 *  - ref_mtv_*_sampled: no geometry knowledge at all: uniformly sampled directions
 *    (with an offset, so no axis or known normal is ever sampled exactly), for each the
 *    first free distance by scanning + bisection, then golden-section refinement of
 *    the angle around the best few directions, then a 2D pattern search from the best
 *    free point (reaches the tip of thin free wedges that rays cross in short chords).
 *    Slow; tests/test_narrow.c uses it to cross-check the former.
 * Both are cheap enough for thousands of calls per test (ref_mtv_tile: ~10 us).
 */
#ifndef NT_TEST_REF_H
#define NT_TEST_REF_H

#include <stdbool.h>

/* Tile kinds of the reference description. */
enum { REF_KIND_EMPTY = 0, REF_KIND_POLYGON = 1, REF_KIND_CONVEX = 2, REF_KIND_CONCAVE = 3 };

/// An object shape: a box (hw, hh) or a circle (r = hw = hh).
typedef struct ref_shape {
    int is_circle;
    double hw, hh;
} ref_shape;

static inline ref_shape ref_aabb(double hw, double hh)
{
    ref_shape s;
    s.is_circle = 0;
    s.hw = hw;
    s.hh = hh;
    return s;
}

static inline ref_shape ref_circle(double r)
{
    ref_shape s;
    s.is_circle = 1;
    s.hw = r;
    s.hh = r;
    return s;
}

/// The same shape grown (delta > 0) or shrunk (delta < 0) by delta on every side.
ref_shape ref_shape_grow(ref_shape s, double delta);

/* ---- the tile set, from the notes ---- */

/// N's name of a tile id ("45DEGpn"), NULL outside 0..33.
const char *ref_tile_name(int id);
/// REF_KIND_* of a tile.
int ref_tile_kind(int id);
/// Signs of the sloped surface's outward normal as encoded by the name suffix
/// (pn = (+1,-1), nn = (-1,-1), np = (-1,+1), pp = (+1,+1)); 0, 0 for EMPTY, FULL, HALF.
void ref_tile_signs(int id, int *sx, int *sy);
/// Corners of the tile: the polygon's vertices (POLYGON), or the straight corners of
/// a round tile (its two arc end points and the corner where its two straight sides
/// meet). Returns the count (0..4); xs, ys must hold 4.
int ref_tile_corners(int id, double *xs, double *ys);
/// Round tiles: the arc's centre (radius 1). False for other tiles.
bool ref_tile_arc_center(int id, double *ox, double *oy);

/// True when (x, y) is strictly inside the tile (unit cell coordinates).
bool ref_point_in_tile(int id, double x, double y);
/// Signed distance from (x, y) to the tile: < 0 inside (minus the distance to the
/// boundary), 0 on the boundary, > 0 outside. EMPTY: +infinity.
double ref_tile_signed_distance(int id, double x, double y);

/// Do the interiors of the object (centre cx, cy) and the tile intersect?
bool ref_object_overlaps_tile(int id, ref_shape s, double cx, double cy);

/// Minimum translation of the object out of the tile alone: *dx, *dy = the displacement
/// that frees it (one of the minimisers; 0, 0 when already free); returns its length, the
/// depth. dx / dy may be NULL.
double ref_mtv_tile(int id, ref_shape s, double cx, double cy, double *dx, double *dy);

/// The same by pure direction sampling (ndir directions, e.g. 720). Slow.
double ref_mtv_tile_sampled(int id, ref_shape s, double cx, double cy, int ndir, double *dx, double *dy);

/* ---- small maps: tiles[y * w + x], cell size 1, cells outside the map are FULL ---- */

/// The tile at a cell of the map (FULL outside).
int ref_map_tile(const int *tiles, int w, int h, int x, int y);

/// Does the object overlap the union of the map's tiles?
bool ref_object_overlaps_map(const int *tiles, int w, int h, ref_shape s, double cx, double cy);

/// Minimum translation out of the union of all tiles (seams between tiles are not
/// surfaces): *dx, *dy = the displacement that frees the object (0, 0 when free); returns
/// its length (0 when free; -1, with 0, 0, if no free position exists at all, i.e. the map
/// has no room for the object). Points on an internal seam count as free (the union's
/// interior contains the seam; this only matters for 0-size objects).
/// Exact up to ~1e-9, except in the pathological case of a gap narrower than 2e-9
/// wider than the object (it counts as room).
double ref_mtv_map(const int *tiles, int w, int h, ref_shape s, double cx, double cy, double *dx, double *dy);

/// The same by direction sampling (ndir directions; max_dist bounds the search, e.g. 3).
/// Returns -1 if nothing free was found within max_dist. Slow, and it can miss pockets of
/// room narrower than its 1/128 scan step (then it answers farther or -1).
double ref_mtv_map_sampled(const int *tiles, int w, int h, ref_shape s, double cx, double cy, int ndir,
                           double max_dist, double *dx, double *dy);

/* ---- shape casts by brute force ---- */

/// Does the object (shrunk by eps on every side) overlap the map? eps >= 0.
bool ref_object_overlaps_map_eps(const int *tiles, int w, int h, ref_shape s, double cx, double cy, double eps);

/// First t in [0, 1] at which the object moving from (cx, cy) by (dx, dy) overlaps the
/// map's tiles (the object shrunk by eps >= 0 on every side, so that grazes shallower than
/// eps are not overlaps): a scan in steps of at most `step` cells of travel (thin features
/// are not skipped as long as their chord is longer), then bisection to 1e-13. True and *t
/// when it overlaps somewhere on the way (t = 0 when it starts overlapping).
bool ref_cast_map(const int *tiles, int w, int h, ref_shape s, double cx, double cy, double dx, double dy, double eps,
                  double step, double *t);

/// Do two objects' interiors overlap (a shrunk by eps)?
bool ref_objects_overlap(ref_shape a, double ax, double ay, ref_shape b, double bx, double by, double eps);

/// The same brute-force cast against one body (shape b at bx, by).
bool ref_cast_object(ref_shape a, double ax, double ay, double dx, double dy, ref_shape b, double bx, double by,
                     double eps, double step, double *t);

/* ---- deterministic PRNG for the tests (splitmix64) ---- */

typedef struct ref_rng {
    unsigned long long state;
} ref_rng;

static inline ref_rng ref_rng_seed(unsigned long long seed)
{
    ref_rng r;
    r.state = seed;
    return r;
}

/// Next 64 random bits.
unsigned long long ref_rng_next(ref_rng *r);
/// Uniform double in [lo, hi).
double ref_rng_uniform(ref_rng *r, double lo, double hi);
/// Uniform integer in [0, n).
int ref_rng_int(ref_rng *r, int n);

#endif
