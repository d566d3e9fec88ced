/* Ray casts: a segment against one tile (exact), and against the map (grid walk).
 *
 * Tile routine. The interior of every tile is the intersection of open half-planes,
 * optionally intersected with an open disc (CONVEX) or with the outside of a closed
 * disc (CONCAVE). Along the line p + t d each half-plane keeps an open t interval
 * (Cyrus-Beck); the segment enters the interior at the first t of the result that lies
 * in [0, tmax], provided the interval is not empty (a graze or a vertex touch gives an
 * empty interval and no hit). Polygon edges are rebuilt from the table's vertices
 * (coordinates 0, 0.5, 1), so their unnormalised normals and offsets are exact: a
 * segment lying on an edge, slopes included, gives exactly zero and never hits. The
 * straight sides of round tiles are the cell sides their table cover spans whole.
 * An interior run shorter than the rounding of t (a segment through a vertex or a
 * cusp, a tangent to an arc) counts as a touch; a start strictly inside always hits.
 *
 * Map walk. The segment is walked cell by cell (Amanatides & Woo: per step one compare
 * and one add). The start cell is tested first; at each crossed edge the leaving
 * cell's `walls` bit says whether the entered cell's solid covers the whole edge (a hit
 * on that edge, axis normal, no shape test); EMPTY cells are skipped; other cells get
 * the exact tile routine in their local coordinates. Exact vertex crossings step
 * diagonally (the two side cells are only touched at a point). A tie that the
 * accumulated tMax values missed by rounding shows up as a wall crossing at an end
 * of the edge: the exact tile test decides those instead of the shortcut. Special cases:
 *   - a start point on a grid line or vertex is classified first (inside the union of
 *     the tiles when both sides cover it: the seam between two solids is not a surface);
 *   - a segment lying along a grid line can only be inside the union where the tiles on
 *     both sides of the line cover it, so it walks the line's per-cell cover intervals;
 *   - when the entry is a tie between faces (a vertex), a face that is a seam (the
 *     cell's `seams` bit) is not chosen as the surface normal when another one is.
 */
#include <float.h>
#include "core_internal.h"

/* ------------------------------------------------------------------------------ */
/* Entry selection: the latest entering constraint, with ties resolved toward faces  */
/* that are not seams, then toward the face most opposed to the direction.           */

typedef struct entry {
    nt_real t;      /* latest entering t among all constraints */
    nt_vec2 n;      /* its normal */
    nt_real dot;    /* n . d */
    int masked;     /* it is a seam face */
    nt_real tu;     /* latest entering t among the faces that are not seams */
    nt_vec2 nu;
    nt_real dotu;
} entry;

static inline void entry_init(entry *e)
{
    e->t = -NT_REAL_MAX;
    e->n = nt_v2(0, 0);
    e->dot = 0;
    e->masked = 0;
    e->tu = -NT_REAL_MAX;
    e->nu = nt_v2(0, 0);
    e->dotu = 0;
}

static inline void entry_add(entry *e, nt_real t, nt_vec2 n, nt_real dot, int masked)
{
    if (t > e->t || (t == e->t && ((e->masked && !masked) || (e->masked == masked && dot < e->dot)))) {
        e->t = t;
        e->n = n;
        e->dot = dot;
        e->masked = masked;
    }
    if (!masked && (t > e->tu || (t == e->tu && dot < e->dotu))) {
        e->tu = t;
        e->nu = n;
        e->dotu = dot;
    }
}

/* The normal of the entry: a seam face only when no real face enters at (nearly) the
 * same time. `tol` absorbs the rounding of two entering times computed from different
 * faces through the same vertex. */
static inline nt_vec2 entry_normal(const entry *e, nt_real tol)
{
    if (e->masked && e->tu > -NT_REAL_MAX && e->tu >= e->t - tol) return e->nu;
    return e->n;
}

/* The rounding scale of t for this segment: two entering times closer than this are
 * a tie, and an interior run shorter than this is a touch (a segment through a vertex
 * or a cusp computes a run of a few ulps instead of an empty one). */
static inline nt_real t_tol(nt_vec2 p, nt_vec2 d)
{
    nt_real s = nt__fabs(d.x) + nt__fabs(d.y);
    if (!(s > 0)) return 0;
    return (nt_real)32 * NT_REAL_EPS * (1 + nt__fabs(p.x) + nt__fabs(p.y)) / s;
}

/* The interior run (lo, hi) is a hit for the segment t in [0, tmax]: it contains the
 * start (strictly inside: always a hit), or it begins within the segment and is
 * longer than rounding. */
static inline int run_hits(nt_real lo, nt_real hi, nt_real tmax, nt_real tol)
{
    if (!(lo < hi)) return 0;
    if (lo < 0) return hi > 0;
    return lo < tmax && nt__min(hi, tmax) - lo > tol;
}

/* Which cell side the segment a-b lies on, or -1. */
static inline int edge_side(nt_vec2 a, nt_vec2 b)
{
    if (a.x == b.x) {
        if (a.x == 0) return NT_SIDE_LEFT;
        if (a.x == 1) return NT_SIDE_RIGHT;
    }
    if (a.y == b.y) {
        if (a.y == 0) return NT_SIDE_TOP;
        if (a.y == 1) return NT_SIDE_BOTTOM;
    }
    return -1;
}

/* Unit outward normal of the polygon edge a->b (exact normal (a.y - b.y, b.x - a.x)). */
static inline nt_vec2 edge_unit_normal(const nt_tile_info *ti, nt_real nx, nt_real ny)
{
    if (nx == 0) return nt_v2(0, ny > 0 ? (nt_real)1 : (nt_real)-1);
    if (ny == 0) return nt_v2(nx > 0 ? (nt_real)1 : (nt_real)-1, 0);
    return ti->normal; /* the one sloped edge */
}

/* ------------------------------------------------------------------------------ */
/* The three shape classes.                                                          */

static bool ray_polygon(int tile, nt_vec2 p, nt_vec2 d, nt_real tmax, unsigned mask, nt_real *t_out,
                        nt_vec2 *n_out)
{
    const nt_tile_info *ti = &nt__tiles[tile];
    const int nv = ti->vertex_count;
    entry e;
    entry_init(&e);
    nt_real tout = NT_REAL_MAX;
    for (int i = 0; i < nv; i++) {
        nt_vec2 a = ti->vertices[i], b = ti->vertices[i + 1 < nv ? i + 1 : 0];
        nt_real nx = a.y - b.y, ny = b.x - a.x; /* outward, exact */
        nt_real s0 = nx * (p.x - a.x) + ny * (p.y - a.y);
        nt_real dn = nx * d.x + ny * d.y;
        if (dn == 0) {
            if (s0 >= 0) return false; /* parallel, outside or on the edge's line */
            continue;
        }
        nt_real t = -s0 / dn;
        if (dn < 0) {
            int side = edge_side(a, b);
            nt_vec2 un = edge_unit_normal(ti, nx, ny);
            entry_add(&e, t, un, nt__dot(un, d), side >= 0 && ((mask >> side) & 1u));
        } else if (t < tout) {
            tout = t;
        }
    }
    const nt_real tol = t_tol(p, d);
    if (!run_hits(e.t, tout, tmax, tol)) return false;
    if (e.t < 0) {
        *t_out = 0;
        *n_out = nt_v2(0, 0);
    } else {
        *t_out = e.t;
        *n_out = entry_normal(&e, tol);
    }
    return true;
}

/* The cell's sides as half-planes: inside iff nx*x + ny*y < off (indexed by nt_side). */
static const nt_real side_nx[4] = {(nt_real)-1, (nt_real)1, (nt_real)0, (nt_real)0};
static const nt_real side_ny[4] = {(nt_real)0, (nt_real)0, (nt_real)-1, (nt_real)1};
static const nt_real side_off[4] = {(nt_real)0, (nt_real)1, (nt_real)0, (nt_real)1};

/* The sides of a round tile that are straight faces: the ones its solid covers whole. */
static inline unsigned straight_sides(const nt_tile_info *ti)
{
    unsigned m = 0;
    for (int s = 0; s < 4; s++)
        if (ti->cover_lo[s] <= 0 && ti->cover_hi[s] >= 1) m |= 1u << s;
    return m;
}

/* Clip the line against the cell sides in `sides` (bit per side). */
static bool clip_sides(unsigned sides, nt_vec2 p, nt_vec2 d, unsigned mask, entry *e, nt_real *tout)
{
    for (int s = 0; s < 4; s++) {
        if (!((sides >> s) & 1u)) continue;
        nt_real s0 = side_nx[s] * p.x + side_ny[s] * p.y - side_off[s];
        nt_real dn = side_nx[s] * d.x + side_ny[s] * d.y;
        if (dn == 0) {
            if (s0 >= 0) return false;
            continue;
        }
        nt_real t = -s0 / dn;
        if (dn < 0) {
            nt_vec2 un = nt_v2(side_nx[s], side_ny[s]);
            entry_add(e, t, un, nt__dot(un, d), (mask >> s) & 1u);
        } else if (t < *tout) {
            *tout = t;
        }
    }
    return true;
}

/* The line p + t d against the circle |x - c| = 1: the chord's t interval.
 * Returns 0 when the line misses the open disc (tangent included). */
static int disc_interval(nt_vec2 p, nt_vec2 d, nt_vec2 c, nt_real *t1, nt_real *t2)
{
    /* Work with a direction of size ~1 so that nothing overflows or underflows. */
    nt_real s = nt__fabs(d.x) + nt__fabs(d.y);
    nt_vec2 u = nt_v2(d.x / s, d.y / s);
    nt_vec2 f = nt__sub(p, c);
    nt_real a = nt__dot(u, u), b = nt__dot(f, u), cc = nt__dot(f, f) - 1;
    nt_real disc = b * b - a * cc;
    /* A tangent line only touches the disc: a discriminant within the rounding of its
     * two terms is treated as zero (a graze, not an entry). */
    if (!(disc > (nt_real)8 * NT_REAL_EPS * (b * b + nt__fabs(a * cc)))) return 0;
    nt_real sq = nt__sqrt(disc);
    nt_real q = b >= 0 ? -(b + sq) : -(b - sq);
    nt_real r1 = q / a, r2 = cc / q;
    if (r1 > r2) {
        nt_real tmp = r1;
        r1 = r2;
        r2 = tmp;
    }
    *t1 = r1 / s;
    *t2 = r2 / s;
    return 1;
}

static inline nt_vec2 unit(nt_vec2 v)
{
    nt_real l = nt__len(v);
    return l > 0 ? nt_v2(v.x / l, v.y / l) : nt_v2(0, 0);
}

static bool ray_convex(int tile, nt_vec2 p, nt_vec2 d, nt_real tmax, unsigned mask, nt_real *t_out,
                       nt_vec2 *n_out)
{
    const nt_tile_info *ti = &nt__tiles[tile];
    entry e;
    entry_init(&e);
    nt_real tout = NT_REAL_MAX;
    /* quarter disc = disc and the half-planes of its two straight sides */
    if (!clip_sides(straight_sides(ti), p, d, mask, &e, &tout)) return false;
    nt_vec2 f = nt__sub(p, ti->arc_center);
    if (d.x == 0 && d.y == 0) {
        if (!(nt__dot(f, f) < 1)) return false;
    } else {
        nt_real t1, t2;
        if (!disc_interval(p, d, ti->arc_center, &t1, &t2)) return false;
        nt_vec2 n = unit(nt__add(f, nt__scale(d, t1))); /* outward: away from the centre */
        entry_add(&e, t1, n, nt__dot(n, d), 0);
        if (t2 < tout) tout = t2;
    }
    const nt_real tol = t_tol(p, d);
    if (!run_hits(e.t, tout, tmax, tol)) return false;
    if (e.t < 0) {
        *t_out = 0;
        *n_out = nt_v2(0, 0);
    } else {
        *t_out = e.t;
        *n_out = entry_normal(&e, tol);
    }
    return true;
}

#if !NT_REAL_IS_DOUBLE
/* ray_concave's verdict redone in double on the same (float) inputs. Near a cusp the
 * solid between the arc and a side is about y^2 / 2 thick at a distance y from it, so
 * float's rounding of t (t_tol: a few 1e-6) would pass a ray through a real sliver up
 * to 3e-3 cell from the cusp as a touch, where double hits. Only float misses come
 * here, so every float hit keeps its bits. Returns 1 on a hit with its t (< 0: the
 * start is inside) and whether the entry is the arc (leaving the disc) rather than a
 * side (masked: the float entry's side is a seam). The arithmetic is that of
 * clip_sides, disc_interval, t_tol and run_hits, so the verdict is the double build's. */
static int concave_wide(nt_vec2 c, nt_vec2 p0, nt_vec2 d0, nt_real tmax0, int masked, double *t_out, int *on_arc)
{
    const double px = p0.x, py = p0.y, dx = d0.x, dy = d0.y, tmax = tmax0;
    double A = -DBL_MAX, B = DBL_MAX;
    for (int s = 0; s < 4; s++) {
        double s0 = (double)side_nx[s] * px + (double)side_ny[s] * py - (double)side_off[s];
        double dn = (double)side_nx[s] * dx + (double)side_ny[s] * dy;
        if (dn == 0) {
            if (s0 >= 0) return 0;
            continue;
        }
        double t = -s0 / dn;
        if (dn < 0) {
            if (t > A) A = t;
        } else if (t < B) {
            B = t;
        }
    }
    if (!(A < B)) return 0;
    const double fx = px - (double)c.x, fy = py - (double)c.y;
    double d1 = DBL_MAX, d2 = DBL_MAX;
    const double sd = fabs(dx) + fabs(dy);
    if (!(sd > 0)) {
        if (!(fx * fx + fy * fy > 1)) return 0;
    } else {
        const double ux = dx / sd, uy = dy / sd;
        const double a = ux * ux + uy * uy, b = fx * ux + fy * uy, cc = fx * fx + fy * fy - 1;
        const double disc = b * b - a * cc;
        if (disc > 8 * DBL_EPSILON * (b * b + fabs(a * cc))) {
            const double sq = sqrt(disc), q = b >= 0 ? -(b + sq) : -(b - sq);
            double r1 = q / a, r2 = cc / q;
            if (r1 > r2) {
                const double tmp = r1;
                r1 = r2;
                r2 = tmp;
            }
            d1 = r1 / sd;
            d2 = r2 / sd;
        }
    }
    const double tol = sd > 0 ? 32 * DBL_EPSILON * (1 + fabs(px) + fabs(py)) / sd : 0;
    for (int run = 1; run <= 2; run++) {
        if (run == 2 && d2 == DBL_MAX) break;
        double lo = run == 1 ? A : (A > d2 ? A : d2), hi = run == 1 ? (B < d1 ? B : d1) : B;
        if (!(lo < hi)) continue;
        if (lo < 0 ? hi > 0 : lo < tmax && (hi < tmax ? hi : tmax) - lo > tol) {
            *t_out = lo;
            *on_arc = run == 2 && (d2 > A || (d2 == A && masked));
            return 1;
        }
    }
    return 0;
}
#endif

/* A miss of ray_concave's float arithmetic: in float builds, the double verdict. */
static bool concave_miss(const nt_tile_info *ti, nt_vec2 p, nt_vec2 d, nt_real tmax, const entry *e, nt_real *t_out,
                         nt_vec2 *n_out)
{
#if NT_REAL_IS_DOUBLE
    (void)ti, (void)p, (void)d, (void)tmax, (void)e, (void)t_out, (void)n_out;
    return false;
#else
    double t;
    int on_arc;
    if (!concave_wide(ti->arc_center, p, d, tmax, e->masked, &t, &on_arc)) return false;
    if (t < 0) {
        *t_out = 0;
        *n_out = nt_v2(0, 0);
        return true;
    }
    *t_out = (nt_real)t;
    if (on_arc) *n_out = unit(nt__scale(nt__add(nt__sub(p, ti->arc_center), nt__scale(d, *t_out)), (nt_real)-1));
    else *n_out = entry_normal(e, t_tol(p, d));
    return true;
#endif
}

static bool ray_concave(int tile, nt_vec2 p, nt_vec2 d, nt_real tmax, unsigned mask, nt_real *t_out,
                        nt_vec2 *n_out)
{
    const nt_tile_info *ti = &nt__tiles[tile];
    entry e;
    entry_init(&e);
    nt_real tout = NT_REAL_MAX;
    if (!clip_sides(0xFu, p, d, mask, &e, &tout)) return false; /* clipped to the cell */
    const nt_real A = e.t, B = tout;
    if (!(A < B)) return concave_miss(ti, p, d, tmax, &e, t_out, n_out);
    nt_vec2 f = nt__sub(p, ti->arc_center);
    nt_real d1 = NT_REAL_MAX, d2 = NT_REAL_MAX; /* the closed disc's t interval */
    if (d.x == 0 && d.y == 0) {
        if (!(nt__dot(f, f) > 1)) return concave_miss(ti, p, d, tmax, &e, t_out, n_out);
    } else if (!disc_interval(p, d, ti->arc_center, &d1, &d2)) {
        d1 = d2 = NT_REAL_MAX; /* misses the disc: nothing removed */
    }
    const nt_real tol = t_tol(p, d);
    /* Before the disc: (A, min(B, d1)). */
    if (run_hits(A, nt__min(B, d1), tmax, tol)) {
        if (A < 0) {
            *t_out = 0;
            *n_out = nt_v2(0, 0);
        } else {
            *t_out = A;
            *n_out = entry_normal(&e, tol);
        }
        return true;
    }
    /* After the disc: (max(A, d2), B). */
    if (d2 == NT_REAL_MAX) return concave_miss(ti, p, d, tmax, &e, t_out, n_out);
    nt_real lo = nt__max(A, d2);
    if (!run_hits(lo, B, tmax, tol)) return concave_miss(ti, p, d, tmax, &e, t_out, n_out);
    if (lo < 0) {
        *t_out = 0;
        *n_out = nt_v2(0, 0);
        return true;
    }
    if (d2 > A || (d2 == A && e.masked)) {
        /* Leaving the disc: the surface normal points toward the arc's centre. */
        *t_out = d2;
        *n_out = unit(nt__scale(nt__add(f, nt__scale(d, d2)), (nt_real)-1));
    } else {
        *t_out = A;
        *n_out = entry_normal(&e, tol);
    }
    return true;
}

/* Tile routine with a seam mask (bit per side); inputs already validated. */
static bool ray_tile_m(int tile, nt_vec2 p, nt_vec2 d, nt_real tmax, unsigned mask, nt_real *t_out,
                       nt_vec2 *n_out)
{
    switch (nt__tiles[tile].cls) {
    case NT_CLASS_POLYGON: return ray_polygon(tile, p, d, tmax, mask, t_out, n_out);
    case NT_CLASS_CONVEX: return ray_convex(tile, p, d, tmax, mask, t_out, n_out);
    case NT_CLASS_CONCAVE: return ray_concave(tile, p, d, tmax, mask, t_out, n_out);
    case NT_CLASS_EMPTY: break;
    }
    return false;
}

bool nt_tile_raycast(int tile, nt_vec2 p0, nt_vec2 d, nt_real tmax, nt_real *t_out, nt_vec2 *normal_out)
{
    if (tile <= NT_TILE_EMPTY || tile >= NT_TILE_COUNT) return false;
    if (!nt__finite(p0.x) || !nt__finite(p0.y) || !nt__finite(d.x) || !nt__finite(d.y) || !nt__finite(tmax))
        return false;
    if (tmax < 0) return false;
    nt_real t;
    nt_vec2 n;
    if (!ray_tile_m(tile, p0, d, tmax, 0, &t, &n)) return false;
    if (t_out) *t_out = t;
    if (normal_out) *normal_out = n;
    return true;
}

/* ------------------------------------------------------------------------------ */
/* Map ray casts.                                                                    */

static inline nt__cell cell_at(const nt_map *m, int x, int y)
{
    if (x >= 0 && y >= 0 && x < m->w && y < m->h) return m->cells[(size_t)y * (size_t)m->w + (size_t)x];
    return nt__map_cell(m, x, y);
}

static inline int cover_has(int tile, int side, nt_real u)
{
    const nt_tile_info *ti = &nt__tiles[tile];
    return ti->cover_lo[side] < u && u < ti->cover_hi[side];
}

/* The tile's solid fills a neighbourhood of its cell corner (cx, cy) in {0,1}^2:
 * both sides meeting there are covered (not just touched) up to the corner. */
static inline int corner_full(int tile, int cx, int cy)
{
    const nt_tile_info *ti = &nt__tiles[tile];
    int sh = cy ? NT_SIDE_BOTTOM : NT_SIDE_TOP, sv = cx ? NT_SIDE_RIGHT : NT_SIDE_LEFT;
    nt_real uh = (nt_real)cx, uv = (nt_real)cy;
    return ti->cover_lo[sh] < ti->cover_hi[sh] && ti->cover_lo[sh] <= uh && uh <= ti->cover_hi[sh] &&
           ti->cover_lo[sv] < ti->cover_hi[sv] && ti->cover_lo[sv] <= uv && uv <= ti->cover_hi[sv];
}

/* Is the grid point g (cell (ix, iy) = floor(g)) inside the interior of the union of
 * the tiles? On a grid line both cells must cover the point; at a vertex all four
 * cells must fill their corner. */
static bool point_interior(const nt_map *m, nt_vec2 g, int ix, int iy, int onx, int ony, int ox, int oy)
{
    /* g, ix, iy relative to the cell (ox, oy) */
    const int X = ix + ox, Y = iy + oy;
    if (!onx && !ony) return nt_tile_contains_point(nt__map_tile(m, X, Y), nt_v2(g.x - (nt_real)ix, g.y - (nt_real)iy));
    if (onx && !ony) {
        nt_real u = g.y - (nt_real)iy;
        return cover_has(nt__map_tile(m, X - 1, Y), NT_SIDE_RIGHT, u) && cover_has(nt__map_tile(m, X, Y), NT_SIDE_LEFT, u);
    }
    if (ony && !onx) {
        nt_real u = g.x - (nt_real)ix;
        return cover_has(nt__map_tile(m, X, Y - 1), NT_SIDE_BOTTOM, u) && cover_has(nt__map_tile(m, X, Y), NT_SIDE_TOP, u);
    }
    return corner_full(nt__map_tile(m, X - 1, Y - 1), 1, 1) && corner_full(nt__map_tile(m, X, Y - 1), 0, 1) &&
           corner_full(nt__map_tile(m, X - 1, Y), 1, 0) && corner_full(nt__map_tile(m, X, Y), 0, 0);
}

/* The outward normal of the face that leaves side `side` of the tile at parameter u
 * (an end of the side's cover interval) and runs into the cell. Returns 0 if none. */
static int face_normal_at(int tile, int side, nt_real u, nt_vec2 *n)
{
    const nt_tile_info *ti = &nt__tiles[tile];
    nt_vec2 P;
    switch (side) {
    case NT_SIDE_LEFT: P = nt_v2(0, u); break;
    case NT_SIDE_RIGHT: P = nt_v2(1, u); break;
    case NT_SIDE_TOP: P = nt_v2(u, 0); break;
    default: P = nt_v2(u, 1); break;
    }
    if (ti->cls == NT_CLASS_POLYGON) {
        const int nv = ti->vertex_count;
        for (int i = 0; i < nv; i++) {
            nt_vec2 a = ti->vertices[i], b = ti->vertices[i + 1 < nv ? i + 1 : 0];
            int at = (a.x == P.x && a.y == P.y) || (b.x == P.x && b.y == P.y);
            if (!at || edge_side(a, b) == side) continue;
            *n = edge_unit_normal(ti, a.y - b.y, b.x - a.x);
            return 1;
        }
        return 0;
    }
    if (ti->cls == NT_CLASS_EMPTY) return 0;
    nt_real dx = P.x - ti->arc_center.x, dy = P.y - ti->arc_center.y;
    if (dx * dx + dy * dy == 1) { /* an end of the arc (P and the centre are cell corners) */
        *n = ti->cls == NT_CLASS_CONVEX ? nt_v2(dx, dy) : nt_v2(-dx, -dy);
        return 1;
    }
    /* Otherwise the other straight side through P. */
    unsigned sides = straight_sides(ti);
    for (int s = 0; s < 4; s++) {
        if (s == side || !((sides >> s) & 1u)) continue;
        int on = (s == NT_SIDE_LEFT && P.x == 0) || (s == NT_SIDE_RIGHT && P.x == 1) ||
                 (s == NT_SIDE_TOP && P.y == 0) || (s == NT_SIDE_BOTTOM && P.y == 1);
        if (on) {
            *n = nt_v2(side_nx[s], side_ny[s]);
            return 1;
        }
    }
    return 0;
}

typedef struct ray_ctx {
    const nt_map *map;
    nt_vec2 p0, d;   /* world start and (possibly scaled) world direction */
    nt_vec2 g0, gd;  /* the same in grid units (cells); g0 from the corner of the cell (ox, oy) */
    int ox, oy;
    nt_real tend;    /* the segment is t in [0, tend] (1 unless d had to be scaled) */
} ray_ctx;

static bool report(const ray_ctx *r, nt_real t, nt_vec2 n, int cx, int cy, nt_ray_hit *out)
{
    if (t < 0) t = 0;
    if (out) {
        nt_real f = t / r->tend;
        out->fraction = f > 1 ? (nt_real)1 : f;
        out->point = t > 0 ? nt_v2(r->p0.x + t * r->d.x, r->p0.y + t * r->d.y) : r->p0;
        out->normal = n;
        out->cell_x = cx;
        out->cell_y = cy;
    }
    return true;
}

/* A segment lying on a grid line: axis 0 = moving along x on the line y = line,
 * axis 1 = moving along y on the line x = line. Inside the union only where the cells
 * on both sides cover the line: walk their cover intervals. */
static bool gridline_walk(const ray_ctx *r, int axis, int line, nt_ray_hit *out)
{
    const nt_map *m = r->map;
    nt_real s0 = axis == 0 ? r->g0.x : r->g0.y;
    nt_real ds = axis == 0 ? r->gd.x : r->gd.y;
    int step = ds > 0 ? 1 : -1;
    int i = nt__floor_int(s0);
    if ((nt_real)i == s0 && ds < 0) i--;
    const int sa = axis == 0 ? NT_SIDE_BOTTOM : NT_SIDE_RIGHT; /* side of the cell before the line */
    const int sb = axis == 0 ? NT_SIDE_TOP : NT_SIDE_LEFT;     /* side of the cell after it */
    nt_vec2 dir = axis == 0 ? nt_v2((nt_real)step, 0) : nt_v2(0, (nt_real)step);
    for (int guard = 0; guard < 2 * NT_MAP_MAX_SIDE + 8; guard++, i += step) {
        nt_real near = (nt_real)(step > 0 ? i : i + 1);
        if ((near - s0) / ds >= r->tend) break;
        int ax = axis == 0 ? i : line - 1, ay = axis == 0 ? line - 1 : i;
        int bx = axis == 0 ? i : line, by = axis == 0 ? line : i;
        int ta = nt__map_tile(m, ax + r->ox, ay + r->oy), tb = nt__map_tile(m, bx + r->ox, by + r->oy);
        const nt_tile_info *ia = &nt__tiles[ta], *ib = &nt__tiles[tb];
        nt_real lo = nt__max(ia->cover_lo[sa], ib->cover_lo[sb]);
        nt_real hi = nt__min(ia->cover_hi[sa], ib->cover_hi[sb]);
        if (!(lo < hi)) continue;
        nt_real u = step > 0 ? lo : hi;
        nt_real t_in = ((nt_real)i + u - s0) / ds;
        nt_real t_out = ((nt_real)i + (step > 0 ? hi : lo) - s0) / ds;
        if (!(t_out > 0)) continue; /* behind the start */
        if (t_in >= r->tend) break;
        if (t_in < 0) return report(r, 0, nt_v2(0, 0), bx + r->ox, by + r->oy, out);
        /* The surface met: the face leaving the line at u, of whichever side ends the gap. */
        nt_vec2 n = nt_v2(-dir.x, -dir.y), cand;
        int cx = bx, cy = by, found = 0;
        if ((step > 0 ? ia->cover_lo[sa] : ia->cover_hi[sa]) == u && face_normal_at(ta, sa, u, &cand)) {
            n = cand;
            cx = ax;
            cy = ay;
            found = 1;
        }
        if ((step > 0 ? ib->cover_lo[sb] : ib->cover_hi[sb]) == u && face_normal_at(tb, sb, u, &cand) &&
            (!found || nt__dot(cand, dir) < nt__dot(n, dir))) {
            n = cand;
            cx = bx;
            cy = by;
        }
        return report(r, t_in, n, cx + r->ox, cy + r->oy, out);
    }
    return false;
}

bool nt_map_raycast(const nt_map *map, nt_vec2 p0, nt_vec2 p1, nt_ray_hit *out)
{
    if (!map) return false;
    if (!nt__finite(p0.x) || !nt__finite(p0.y) || !nt__finite(p1.x) || !nt__finite(p1.y)) return false;
    const nt_real cs = map->cell;
    ray_ctx r;
    r.map = map;
    r.p0 = p0;
    nt_vec2 ga = nt_v2(p0.x / cs, p0.y / cs);
    r.tend = 1;
    r.d = nt__sub(p1, p0);

    /* Outside the map: inside the border's solid. */
    if (!(ga.x >= 0 && ga.y >= 0 && ga.x <= (nt_real)map->w && ga.y <= (nt_real)map->h))
        return report(&r, 0, nt_v2(0, 0), nt__floor_int(ga.x), nt__floor_int(ga.y), out);

    /* The walk works from the corner of the start's cell (ox, oy): the start is taken
     * from there in double, where p0 - ox * cell is exact for float (a cell index of
     * at most 13 bits times a float cell size), and rounded once, so that it keeps
     * every bit of p0 however far from the map's origin; cells are numbered from
     * there too, and the crossings computed in them keep the precision they have near
     * the origin. */
    r.ox = nt__floor_int(ga.x);
    r.oy = nt__floor_int(ga.y);
    r.g0 = nt_v2((nt_real)(((double)p0.x - (double)r.ox * (double)cs) / (double)cs),
                 (nt_real)(((double)p0.y - (double)r.oy * (double)cs) / (double)cs));

    const int ix = nt__floor_int(r.g0.x), iy = nt__floor_int(r.g0.y);
    const int onx = (nt_real)ix == r.g0.x, ony = (nt_real)iy == r.g0.y;

    /* Direction in cells. A huge segment (p1 - p0 overflowing) is scaled down by powers
     * of two: t then runs over [0, tend] with tend = 2^k. */
    r.gd = nt_v2(r.d.x / cs, r.d.y / cs);
    if (!nt__finite(r.gd.x) || !nt__finite(r.gd.y)) {
        nt_real k = 1;
        do {
            k *= (nt_real)0.5;
            r.d = nt__sub(nt__scale(p1, k), nt__scale(p0, k));
            r.gd = nt_v2(r.d.x / cs, r.d.y / cs);
        } while (!nt__finite(r.gd.x) || !nt__finite(r.gd.y));
        r.tend = 1 / k;
    }
    const int zero = r.gd.x == 0 && r.gd.y == 0;

    /* A start on a grid line or vertex, or a point: classify it against the union. */
    if (onx || ony || zero) {
        if (point_interior(map, r.g0, ix, iy, onx, ony, r.ox, r.oy))
            return report(&r, 0, nt_v2(0, 0), ix + r.ox, iy + r.oy, out);
        if (zero) return false;
        if (onx && r.gd.x == 0) return gridline_walk(&r, 1, ix, out);
        if (ony && r.gd.y == 0) return gridline_walk(&r, 0, iy, out);
    }

    /* Amanatides & Woo. The start cell is the one the segment moves into. */
    int cx = ix - (onx && r.gd.x < 0), cy = iy - (ony && r.gd.y < 0);
    const int stepx = r.gd.x > 0 ? 1 : (r.gd.x < 0 ? -1 : 0);
    const int stepy = r.gd.y > 0 ? 1 : (r.gd.y < 0 ? -1 : 0);
    /* tMax / tDelta accumulate one rounding per step: they are kept in double even when
     * nt_real is float, so that the drift stays far below a cell on the longest walks
     * (in float it would grow like steps^2 * 2^-25 cells). */
    double tmx = DBL_MAX, tmy = DBL_MAX, tdx = 0, tdy = 0;
    const double tend = (double)r.tend;
    if (stepx) {
        tmx = ((double)(stepx > 0 ? cx + 1 : cx) - (double)r.g0.x) / (double)r.gd.x;
        tdx = (double)stepx / (double)r.gd.x;
    }
    if (stepy) {
        tmy = ((double)(stepy > 0 ? cy + 1 : cy) - (double)r.g0.y) / (double)r.gd.y;
        tdy = (double)stepy / (double)r.gd.y;
    }

    nt_real t;
    nt_vec2 n;
    nt__cell cur = cell_at(map, cx + r.ox, cy + r.oy);
    if (cur.tile != NT_TILE_EMPTY &&
        ray_tile_m(cur.tile, nt_v2(r.g0.x - (nt_real)cx, r.g0.y - (nt_real)cy), r.gd, r.tend, cur.seams, &t, &n))
        return report(&r, t, n, cx + r.ox, cy + r.oy, out);

    /* Rounding of the crossing point along an edge, in cells. */
    const nt_real vtol = (nt_real)64 * NT_REAL_EPS *
                         (1 + nt__fabs(r.g0.x) + nt__fabs(r.g0.y) + nt__fabs(r.gd.x) + nt__fabs(r.gd.y));
    /* Inside the map the walk meets the border within w + h + 2 steps. */
    const int max_steps = 2 * (map->w + map->h) + 16;
    for (int k = 0; k < max_steps; k++) {
        int side;
        if (tmx < tmy) {
            if (tmx >= tend) break;
            cx += stepx;
            tmx += tdx;
            side = stepx > 0 ? NT_SIDE_RIGHT : NT_SIDE_LEFT;
        } else if (tmy < tmx) {
            if (tmy >= tend) break;
            cy += stepy;
            tmy += tdy;
            side = stepy > 0 ? NT_SIDE_BOTTOM : NT_SIDE_TOP;
        } else {
            /* Through a vertex: the side cells are only touched at a point. */
            if (tmx >= tend) break;
            cx += stepx;
            cy += stepy;
            tmx += tdx;
            tmy += tdy;
            side = -1;
        }
        if (side >= 0 && ((cur.walls >> side) & 1u)) {
            /* The entered cell's solid covers the whole edge: a flat wall, provided the
             * segment crosses the edge inside its span. Near an end of the edge (a
             * vertex crossing that the accumulated tMax did not see as a tie) the exact
             * tile test below decides instead. */
            nt_real v;
            if (side <= NT_SIDE_RIGHT) {
                t = ((nt_real)(stepx > 0 ? cx : cx + 1) - r.g0.x) / r.gd.x;
                v = r.g0.y + t * r.gd.y - (nt_real)cy;
                n = nt_v2((nt_real)-stepx, 0);
            } else {
                t = ((nt_real)(stepy > 0 ? cy : cy + 1) - r.g0.y) / r.gd.y;
                v = r.g0.x + t * r.gd.x - (nt_real)cx;
                n = nt_v2(0, (nt_real)-stepy);
            }
            if (t >= r.tend) return false;
            if (v > vtol && v < 1 - vtol) {
                report(&r, t, n, cx + r.ox, cy + r.oy, out);
                if (out) { /* put the point exactly on the wall */
                    if (side <= NT_SIDE_RIGHT) out->point.x = (nt_real)(r.ox + (stepx > 0 ? cx : cx + 1)) * cs;
                    else out->point.y = (nt_real)(r.oy + (stepy > 0 ? cy : cy + 1)) * cs;
                }
                return true;
            }
        }
        cur = cell_at(map, cx + r.ox, cy + r.oy);
        if (cur.tile == NT_TILE_EMPTY) continue;
        if (ray_tile_m(cur.tile, nt_v2(r.g0.x - (nt_real)cx, r.g0.y - (nt_real)cy), r.gd, r.tend, cur.seams, &t, &n))
            return report(&r, t, n, cx + r.ox, cy + r.oy, out);
    }
    return false;
}
