/* Narrow phase: exact minimum translation vectors.
 *
 * For an object A (centre c) and a solid region T, the object is free exactly when
 * c lies outside the interior of M = T (+) A (Minkowski sum). The minimum translation
 * is the distance from c to the free set F = complement of int(M). Every routine
 * below writes F as a union of simple pieces (half-planes, discs, outsides of
 * discs restricted to a sector), so the distance to F is the smallest distance to a
 * piece: exact, not an approximation. The derivations are in the comments.
 *
 * Round tiles are solved in their canonical `pn` orientation: the object's centre
 * is mirrored into it (boxes and circles are symmetric) and the normal mirrored back.
 */
#include "core_internal.h"
#include "pair_internal.h"

#define SIDE_BIT(s) (1u << (s))

/* GCC's straight-line vectoriser builds a double-precision nt_vec2 argument as one
 * vector from its two stored halves: a store-forwarding stall that doubles the cost
 * of the fast routines. The arithmetic is the same either way, so are the bits. */
#if NT_REAL_IS_DOUBLE && defined(__GNUC__) && !defined(__clang__)
#define NT__SCALAR __attribute__((optimize("no-tree-slp-vectorize")))
#else
#define NT__SCALAR
#endif

/* Candidate pushes, chosen without branches: on random placements every "is this
 * one shorter" comparison is unpredictable, so the minimum is taken with
 * conditional moves over a small list. A masked candidate has depth NT_REAL_MAX and
 * is never chosen; ties keep the first candidate listed. */
typedef struct cands {
    nt_real d[8], nx[8], ny[8];
    int n;
} cands;

static inline void cand(cands *k, nt_real depth, nt_real nx, nt_real ny)
{
    k->d[k->n] = depth;
    k->nx[k->n] = nx;
    k->ny[k->n] = ny;
    k->n++;
}

/* Masked unless `open`. */
static inline void cand_if(cands *k, int open, nt_real depth, nt_real nx, nt_real ny)
{
    cand(k, open ? depth : NT_REAL_MAX, nx, ny);
}

static inline int pick(const cands *k, int sx_flip, int sy_flip, nt_mtv *out)
{
    nt_real bd = k->d[0];
    int bi = 0;
    for (int i = 1; i < k->n; i++) {
        int better = k->d[i] < bd;
        bd = better ? k->d[i] : bd;
        bi = better ? i : bi;
    }
    if (bd == NT_REAL_MAX) return NT__MASKED;
    out->normal.x = sx_flip ? -k->nx[bi] : k->nx[bi];
    out->normal.y = sy_flip ? -k->ny[bi] : k->ny[bi];
    out->depth = bd;
    return NT__PUSH;
}

/* Index of the smallest of two or three depths, the first on ties. Written with
 * integer selects, which compilers keep free of branches (random placements make
 * every comparison a coin toss). */
static inline int first_min2(const nt_real *d)
{
    return d[1] < d[0];
}

static inline int first_min3(const nt_real *d)
{
    int i = d[1] < d[0];
    nt_real m = nt__min(d[1], d[0]);
    int j = d[2] < m;
    return (j << 1) | (i & (j - 1));
}

/* A single push, mirrored back from the canonical frame. */
static inline int push_out(nt_real depth, nt_real nx, nt_real ny, int sx_flip, int sy_flip, nt_mtv *out)
{
    out->normal.x = sx_flip ? -nx : nx;
    out->normal.y = sy_flip ? -ny : ny;
    out->depth = depth;
    return NT__PUSH;
}

/* A box's four axis pushes out of a polygon tile's bounds, masked by seams. */
static inline void axis_cands(cands *q, unsigned mask, nt_real du, nt_real dd, nt_real dl, nt_real dr)
{
    cand_if(q, !(mask & SIDE_BIT(NT_SIDE_TOP)), du, 0, -1);
    cand_if(q, !(mask & SIDE_BIT(NT_SIDE_BOTTOM)), dd, 0, 1);
    cand_if(q, !(mask & SIDE_BIT(NT_SIDE_LEFT)), dl, -1, 0);
    cand_if(q, !(mask & SIDE_BIT(NT_SIDE_RIGHT)), dr, 1, 0);
}

/* ---------- box vs convex polygon: separating axes ----------
 * M's face normals are the box's (x, y) and the polygon's; the polygon's axis-aligned
 * faces are covered by its bounds, so the candidates are four axis pushes and the
 * slope's normal. */
static int aabb_polygon(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out)
{
    const nt_tile_info *t = &nt__tiles[tile];
    const nt__tile_geom *g = &nt__geom[tile];
    nt_real dl = c.x + h.x - t->bounds_min.x; /* move -x */
    nt_real dr = t->bounds_max.x - (c.x - h.x); /* move +x */
    nt_real du = c.y + h.y - t->bounds_min.y; /* move -y */
    nt_real dd = t->bounds_max.y - (c.y - h.y); /* move +y */
    if (dl <= 0 || dr <= 0 || du <= 0 || dd <= 0) return NT__SEPARATE;
    cands q;
    q.n = 0;
    /* The axis pushes listed in each branch: a fixed count lets the compiler keep the
     * list in registers. */
    if (g->has_slope) {
        /* Decide with the integer normal (exact at touching), measure with the unit one. */
        nt_real ux = g->slope[0], uy = g->slope[1];
        nt_real ds = g->slope[2] - (ux * c.x + uy * c.y) + h.x * nt__fabs(ux) + h.y * nt__fabs(uy);
        if (ds <= 0) return NT__SEPARATE;
        cand(&q, ds * g->slope[3], g->slope[4], g->slope[5]);
        axis_cands(&q, mask, du, dd, dl, dr);
        return pick(&q, 0, 0, out);
    }
    axis_cands(&q, mask, du, dd, dl, dr);
    return pick(&q, 0, 0, out);
}

/* ---------- circle vs convex polygon ----------
 * Every polygon tile is its bounds box B, cut by the slope's half-plane H when it has
 * one. Centre inside: leave through the nearest
 * face (distance + r); B's faces that are only a vertex of the tile never win, the
 * slope being nearer along that direction. Centre outside: the nearest point p of
 * B n H is clamp(c, B) when that lies in H, and otherwise the nearest point of the
 * slope segment (the constraint H is then active). Push along c - p by r - |c - p|,
 * with the face's exact normal and distance when p is inside a face (a masked face
 * then gives no push). This general form serves masked tiles (seams); the unmasked
 * case is circle_polygon below, which reaches the same nearest point by another
 * route with almost no branches on the placement (random placements make every
 * region test a coin toss, and a mispredicted branch costs more than computing
 * both sides). The two agree to rounding. */
static int circle_polygon_general(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    const nt_tile_info *t = &nt__tiles[tile];
    const nt__tile_geom *g = &nt__geom[tile];
    nt_real x0 = t->bounds_min.x, y0 = t->bounds_min.y, x1 = t->bounds_max.x, y1 = t->bounds_max.y;
    /* Signed distances outside B's faces (exact: the bounds are dyadic) and H. */
    nt_real sl = x0 - c.x, sr = c.x - x1, st = y0 - c.y, sb = c.y - y1;
    nt_real smax = nt__max(nt__max(sl, sr), nt__max(st, sb));
    nt_real ss = -NT_REAL_MAX;
    if (g->has_slope) {
        ss = (g->slope[0] * c.x + g->slope[1] * c.y - g->slope[2]) * g->slope[3];
        smax = nt__max(smax, ss);
    }
    if (smax >= r) return NT__SEPARATE; /* also a point (r = 0) on the boundary */
    /* A face of B is maskable only where it lies on the cell's side (tested where a
     * branch needs it). */
#define OPEN_L (!(x0 == 0 && (mask & SIDE_BIT(NT_SIDE_LEFT))))
#define OPEN_R (!(x1 == 1 && (mask & SIDE_BIT(NT_SIDE_RIGHT))))
#define OPEN_T (!(y0 == 0 && (mask & SIDE_BIT(NT_SIDE_TOP))))
#define OPEN_B (!(y1 == 1 && (mask & SIDE_BIT(NT_SIDE_BOTTOM))))
    if (smax <= 0) {
        cands q;
        q.n = 0;
        if (g->has_slope) cand(&q, r - ss, g->slope[4], g->slope[5]);
        cand_if(&q, OPEN_T, r - st, 0, -1);
        cand_if(&q, OPEN_B, r - sb, 0, 1);
        cand_if(&q, OPEN_L, r - sl, -1, 0);
        cand_if(&q, OPEN_R, r - sr, 1, 0);
        return pick(&q, 0, 0, out);
    }
    nt_real px = nt__clamp(c.x, x0, x1), py = nt__clamp(c.y, y0, y1);
    if (g->has_slope && g->slope[0] * px + g->slope[1] * py > g->slope[2]) {
        const nt__face *e = &nt__polys[tile].face[0]; /* the slope comes first */
        int before = (c.x - e->vx[0]) * e->tx + (c.y - e->vy[0]) * e->ty <= 0;
        int after = (c.x - e->vx[1]) * e->tx + (c.y - e->vy[1]) * e->ty >= 0;
        if (!before && !after) return push_out(r - ss, e->nx, e->ny, 0, 0, out);
        px = e->vx[after];
        py = e->vy[after];
    } else if ((px == c.x) != (py == c.y)) {
        /* Inside one face's slab: the nearest point is on that face. */
        int horiz = px == c.x; /* the nearest face is horizontal (top or bottom) */
        if (horiz) {
            if (!(st > 0 ? OPEN_T : OPEN_B)) return NT__MASKED;
            return push_out(r - nt__max(st, sb), 0, st > 0 ? (nt_real)(-1) : (nt_real)1, 0, 0, out);
        }
        if (!(sl > 0 ? OPEN_L : OPEN_R)) return NT__MASKED;
        return push_out(r - nt__max(sl, sr), sl > 0 ? (nt_real)(-1) : (nt_real)1, 0, 0, 0, out);
    } else if (px != c.x && py != c.y) {
        /* A corner of B (a tile vertex). Where one of its two faces is a seam, the
         * neighbour's solid continues the other face past the corner: the corner is
         * no corner of the union, and its push would be a sideways bump. Push off the
         * other face's line instead (as far as the corner's push, or further). */
        int v_open = sl > 0 ? OPEN_L : OPEN_R, h_open = st > 0 ? OPEN_T : OPEN_B;
        /* Only when the circle reaches the corner at all. (Up to half a cell the push
         * of a circle clear of the corner is one its neighbour gives anyway, and
         * recorded replays keep it.) */
        nt_real cx = c.x - px, cy = c.y - py;
        if (r > (nt_real)0.5 && cx * cx + cy * cy >= r * r) return NT__SEPARATE;
        if (!v_open && !h_open) return NT__MASKED;
        if (!v_open) return push_out(r - nt__max(st, sb), 0, st > 0 ? (nt_real)(-1) : (nt_real)1, 0, 0, out);
        if (!h_open) return push_out(r - nt__max(sl, sr), sl > 0 ? (nt_real)(-1) : (nt_real)1, 0, 0, 0, out);
    }
#undef OPEN_L
#undef OPEN_R
#undef OPEN_T
#undef OPEN_B
    nt_real vx = c.x - px, vy = c.y - py;
    nt_real dist = nt__sqrt(vx * vx + vy * vy);
    if (dist >= r) return NT__SEPARATE;
    return push_out(r - dist, vx / dist, vy / dist, 0, 0, out);
}

/* Below this squared distance a centre just outside the tile could lose its
 * direction to underflow; the general routine measures those. */
#if NT_REAL_IS_DOUBLE
#define TINY_D2 1e-290
#else
#define TINY_D2 1e-30f
#endif

NT__SCALAR static int circle_polygon(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    if (mask) return circle_polygon_general(tile, c, r, mask, out);
    /* The face of largest separation s; ties keep the first listed (a tournament
     * of pairs, which compilers keep free of branches). Inside, that face is the
     * way out. Outside, the nearest point of a convex polygon lies on that face or
     * is one of its two ends. */
    const nt__poly *f = &nt__polys[tile];
    nt_real sv[4], cx = c.x, cy = c.y;
    for (int q = 0; q < 4; q++) sv[q] = (f->ux[q] * cx + f->uy[q] * cy - f->ud[q]) * f->inv[q];
    nt_real s0 = sv[0], s1 = sv[1], s2 = sv[2], s3 = sv[3];
    int i01 = s1 > s0, i23 = s3 > s2;
    nt_real m01 = nt__max(s1, s0), m23 = nt__max(s3, s2);
    int hi = m23 > m01;
    nt_real bs = nt__max(m23, m01);
    if (bs >= r) return NT__SEPARATE; /* also a point (r = 0) on the boundary */
    const nt__face *e = &f->face[(hi << 1) | ((i23 & -hi) | (i01 & (hi - 1)))];
    /* Beyond an end: measured from that end, so that a centre a rounding error away
     * from a vertex still finds the right side of it. */
    nt_real u[2];
    for (int q = 0; q < 2; q++) u[q] = (cx - e->vx[q]) * e->tx + (cy - e->vy[q]) * e->ty;
    int end = u[1] >= 0; /* beyond end 1 */
    if ((bs > 0) & (end | (u[0] <= 0))) {
        /* Outside, beyond an end of the face: the nearest point is that end. */
        nt_real vx = cx - e->vx[end], vy = cy - e->vy[end];
        nt_real d2 = vx * vx + vy * vy;
        if (d2 < TINY_D2) return circle_polygon_general(tile, c, r, mask, out);
        nt_real dist = nt__sqrt(d2);
        if (dist >= r) return NT__SEPARATE;
        return push_out(r - dist, vx / dist, vy / dist, 0, 0, out);
    }
    return push_out(r - bs, e->nx, e->ny, 0, 0, out);
}

/* Canonical frame of a round tile: its `pn` orientation. */
typedef struct canon {
    nt_real x, y;
    int fx, fy;           /* mirrored in x / y */
    unsigned mleft, mbottom; /* the canonical left / bottom face is masked */
} canon;

static inline canon to_canon(int tile, nt_vec2 c, unsigned mask)
{
    const nt_tile_info *t = &nt__tiles[tile];
    canon k;
    k.fx = t->signx < 0;
    k.fy = t->signy > 0;
    k.x = k.fx ? 1 - c.x : c.x;
    k.y = k.fy ? 1 - c.y : c.y;
    k.mleft = mask & SIDE_BIT(k.fx ? NT_SIDE_RIGHT : NT_SIDE_LEFT);
    k.mbottom = mask & SIDE_BIT(k.fy ? NT_SIDE_TOP : NT_SIDE_BOTTOM);
    return k;
}

/* ---------- box vs CONVEX (quarter disc, centre o = (0,1), radius 1) ----------
 * M is convex: the box's four faces swept over the tile's extremes, and the arc
 * of radius 1 around o' = o + (hw, -hh), whose normals span the (+x, -y) quadrant.
 * The arc constrains only when c - o' points into that quadrant. */
static int aabb_convex(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out)
{
    canon k = to_canon(tile, c, mask);
    nt_real dl = k.x + h.x, dr = 1 + h.x - k.x;
    nt_real du = k.y + h.y, dd = 1 + h.y - k.y;
    if (dl <= 0 || dr <= 0 || du <= 0 || dd <= 0) return NT__SEPARATE;
    nt_real vx = k.x - h.x, vy = k.y - (1 - h.y);
    int arc = vx > 0 && vy < 0;
    nt_real d2 = vx * vx + vy * vy;
    if (arc && d2 >= 1) return NT__SEPARATE;
    nt_real dist = arc ? nt__sqrt(d2) : 1;
    cands q;
    q.n = 0;
    cand_if(&q, arc, 1 - dist, vx / dist, vy / dist);
    cand(&q, du, 0, -1);
    cand_if(&q, !k.mbottom, dd, 0, 1);
    cand_if(&q, !k.mleft, dl, -1, 0);
    cand(&q, dr, 1, 0);
    return pick(&q, k.fx, k.fy, out);
}

/* ---------- circle vs CONVEX ----------
 * Convex tile: nearest-point logic, with the arc's Voronoi region being the quadrant
 * x >= 0, y <= 1 seen from o. */
static int circle_convex_general(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    canon k = to_canon(tile, c, mask);
    nt_real x = k.x, y = k.y;
    if (x >= 0 && y <= 1) {
        nt_real vx = x, vy = y - 1;
        nt_real d2 = vx * vx + vy * vy;
        nt_real dist = nt__sqrt(d2);
        if (d2 <= 1) {
            /* Centre in the closed quarter disc. */
            int interior = x > 0 && y < 1 && d2 < 1;
            if (!interior && r == 0) return NT__SEPARATE;
            nt_real dd = dist > 0 ? dist : 1;
            cands q;
            q.n = 0;
            cand_if(&q, dist > 0, 1 - dist + r, vx / dd, vy / dd);
            cand_if(&q, !k.mbottom, 1 - y + r, 0, 1);
            cand_if(&q, !k.mleft, x + r, -1, 0);
            return pick(&q, k.fx, k.fy, out);
        }
        nt_real gap = dist - 1;
        if (gap >= r) return NT__SEPARATE;
        return push_out(r - gap, vx / dist, vy / dist, k.fx, k.fy, out);
    }
    nt_real px, py; /* nearest point when it is a corner */
    if (x < 0 && y <= 1) {
        if (y >= 0) {
            if (-x >= r) return NT__SEPARATE;
            if (k.mleft) return NT__MASKED;
            return push_out(r + x, -1, 0, k.fx, k.fy, out);
        }
        px = 0;
        py = 0;
    } else if (x >= 0 && y > 1) {
        if (x <= 1) {
            if (y - 1 >= r) return NT__SEPARATE;
            if (k.mbottom) return NT__MASKED;
            return push_out(r - (y - 1), 0, 1, k.fx, k.fy, out);
        }
        px = 1;
        py = 1;
    } else {
        px = 0;
        py = 1;
    }
    nt_real vx = x - px, vy = y - py;
    nt_real dist = nt__sqrt(vx * vx + vy * vy);
    if (dist >= r) return NT__SEPARATE;
    /* A corner next to a seam face is no corner of the union (the neighbour continues
     * the surface): push off the line of the surface that goes on instead. The arc's
     * tangent is horizontal at (0,0) and vertical at (1,1). */
    if (px == 0 && py == 0 && k.mleft) return push_out(r + y, 0, -1, k.fx, k.fy, out);
    if (px == 1 && py == 1 && k.mbottom) return push_out(r - (x - 1), 1, 0, k.fx, k.fy, out);
    if (px == 0 && py == 1 && (k.mleft || k.mbottom)) {
        if (k.mleft && k.mbottom) return NT__MASKED;
        if (k.mleft) return push_out(r - (y - 1), 0, 1, k.fx, k.fy, out);
        return push_out(r + x, -1, 0, k.fx, k.fy, out);
    }
    return push_out(r - dist, vx / dist, vy / dist, k.fx, k.fy, out);
}

/* The unmasked case in one pass. Every candidate is the distance to a piece of
 * the free set: the half-planes x <= -r and y >= 1 + r, and the outside of a disc
 * around the nearest point p of the tile's support: the arc's centre o with radius
 * 1 + r in the arc's quadrant (x >= 0, y <= 1), elsewhere the nearest point of
 * the cell with radius r (the tile's faces and corners there). The smallest is
 * the way out; none positive means the circle is free. */
NT__SCALAR static int circle_convex(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    if (mask) return circle_convex_general(tile, c, r, mask, out);
    canon k = to_canon(tile, c, 0);
    nt_real x = k.x, y = k.y;
    int quad = (x >= 0) & (y <= 1);
    /* Selections by index: compilers keep them free of branches. */
    const nt_real px[2] = {nt__clamp(x, 0, 1), 0}, py[2] = {nt__clamp(y, 0, 1), 1};
    nt_real vx = x - px[quad], vy = y - py[quad];
    nt_real d2 = vx * vx + vy * vy;
    if (d2 < TINY_D2) return circle_convex_general(tile, c, r, mask, out);
    nt_real dist = nt__sqrt(d2);
    const nt_real d[3] = {((nt_real)quad - dist) + r, 1 - y + r, x + r};
    const nt_real nx[3] = {vx / dist, 0, -1}, ny[3] = {vy / dist, 1, 0};
    int i = first_min3(d);
    if (d[i] <= 0) return NT__SEPARATE;
    return push_out(d[i], nx[i], ny[i], k.fx, k.fy, out);
}

/* ---------- box vs CONCAVE (cell minus the disc of radius 1 around o = (1,0)) ----------
 * A box is free iff it leaves the cell's span on some side, or its corner nearest
 * the solid, p = (left, bottom), lies in the disc: the part of the box inside the
 * cell is then inside the disc, because p is that part's farthest point from o.
 * So F = {p.x >= 1} u {right <= 0} u {top >= 1} u {p.y <= 0} u {|p - o| <= 1}. */
static int aabb_concave(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out)
{
    canon k = to_canon(tile, c, mask);
    nt_real px = k.x - h.x, py = k.y + h.y;
    nt_real dr = 1 - px;         /* move +x until the left side clears x = 1 */
    nt_real dl = k.x + h.x;      /* move -x until the right side clears x = 0 */
    nt_real dd = 1 + h.y - k.y;  /* move +y until the top clears y = 1 */
    nt_real du = py;             /* move -y until the bottom clears y = 0 */
    if (dr <= 0 || dl <= 0 || dd <= 0 || du <= 0) return NT__SEPARATE;
    nt_real ox = 1 - px, oy = 0 - py;
    nt_real d2 = ox * ox + oy * oy;
    if (d2 <= 1) return NT__SEPARATE;
    nt_real dist = nt__sqrt(d2);
    cands q;
    q.n = 0;
    cand(&q, dist - 1, ox / dist, oy / dist);
    cand(&q, du, 0, -1);
    cand_if(&q, !k.mbottom, dd, 0, 1);
    cand_if(&q, !k.mleft, dl, -1, 0);
    cand(&q, dr, 1, 0);
    return pick(&q, k.fx, k.fy, out);
}

/* Push toward the point v + r * unit(c - v) on the circle of radius r around v. */
static inline void cand_vertex(cands *q, nt_real x, nt_real y, nt_real vx, nt_real vy, nt_real r)
{
    nt_real dx = x - vx, dy = y - vy;
    nt_real d = nt__sqrt(dx * dx + dy * dy);
    if (d <= 0) return; /* the neighbouring pieces give the same depth */
    if (d < r) cand(q, r - d, dx / d, dy / d);
    else cand(q, d - r, -dx / d, -dy / d);
}

/* ---------- circle vs CONCAVE ----------
 * The boundary of M is made of the offsets of T's features: the left and bottom
 * faces (lines x = -r, y = 1 + r), the concave arc (circle of radius 1 - r around
 * o, free inside), and circles of radius r around the corner (0,1) and the two
 * cusps (0,0) and (1,1). The free set is the union of the half-planes x <= -r,
 * y >= 1 + r, y <= -r, x >= 1 + r, the disc |c - o| <= 1 - r, and the parts of the
 * vertex circles' outsides inside each vertex's normal cone (cusp (0,0): y <= 0;
 * cusp (1,1): x >= 1; corner (0,1): x <= 0 and y >= 1). A vertex candidate whose
 * nearest circle point falls outside its cone is dominated by a neighbouring piece,
 * whose end point it would be. These pieces hold for r <= 1/2 only (the callers send
 * larger circles to circle_concave_large below). */
static int circle_concave_general(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    canon k = to_canon(tile, c, mask);
    nt_real x = k.x, y = k.y;
    nt_real ox = x - 1, oy = y;
    nt_real d2o = ox * ox + oy * oy;
    nt_real dist_o = nt__sqrt(d2o);
    /* Exact overlap test: the distance from c to T. */
    int in_cell = x >= 0 && x <= 1 && y >= 0 && y <= 1;
    if (in_cell && d2o >= 1) {
        int interior = x > 0 && x < 1 && y > 0 && y < 1 && d2o > 1;
        if (!interior && r == 0) return NT__SEPARATE;
    } else {
        nt_real ly = nt__clamp(y, 0, 1), bx = nt__clamp(x, 0, 1);
        nt_real g2 = x * x + (y - ly) * (y - ly);                   /* left face */
        nt_real gb = (x - bx) * (x - bx) + (y - 1) * (y - 1);      /* bottom face */
        if (gb < g2) g2 = gb;
        nt_real gap = nt__sqrt(g2);
        if (x <= 1 && y >= 0) gap = nt__min(gap, nt__fabs(dist_o - 1)); /* the arc */
        if (gap >= r) return NT__SEPARATE;
    }
    nt_real so = dist_o > 0 ? dist_o : 1;
    cands q;
    q.n = 0;
    cand_if(&q, dist_o > 0, dist_o - (1 - r), -ox / so, -oy / so);
    cand(&q, y + r, 0, -1);
    cand_if(&q, !k.mbottom, 1 + r - y, 0, 1);
    cand_if(&q, !k.mleft, x + r, -1, 0);
    cand(&q, 1 + r - x, 1, 0);
    /* A vertex next to a seam face is no vertex of the union: the lines of the
     * surfaces that go on past it (listed above) stand for it. */
    if (y <= 0 && !k.mleft) cand_vertex(&q, x, y, 0, 0, r);
    if (x >= 1 && !k.mbottom) cand_vertex(&q, x, y, 1, 1, r);
    if (x <= 0 && y >= 1 && !k.mleft && !k.mbottom) cand_vertex(&q, x, y, 0, 1, r);
    return pick(&q, k.fx, k.fy, out);
}

/* ---------- circle vs CONCAVE, radius above half a cell ----------
 * The pieces above assume a small circle: the hollow's disc of radius 1 - r is
 * empty once r >= 1, and a vertex's cone is no longer free of the other features
 * (a circle of radius 2 at (2.5, 0) is in the cusp (0,0)'s cone, 2.5 from it, yet
 * overlaps the corner (1,1)). So the free set F = {dist(c, T) >= r} is searched
 * directly: its nearest point lies on one of the offset curves of T's features
 * (the faces' lines x = -r, y = 1 + r; circles of radius r around the vertices
 * (0,0), (1,1), (0,1); the hollow's circle of radius 1 - r while r < 1; and the
 * cell's far sides x = 1 + r, y = -r, which bound F too), at the foot of c on one
 * or where two cross. Every such point is checked against the exact distance to T;
 * the nearest free one is the way out. A masked face drops its line and the
 * vertices next to it, as in the general routine. */
static nt_real concave_dist(nt_real x, nt_real y)
{
    if (x >= 0 && x <= 1 && y >= 0 && y <= 1 && (x - 1) * (x - 1) + y * y >= 1) return 0;
    nt_real ly = nt__clamp(y, 0, 1), bx = nt__clamp(x, 0, 1);
    nt_real g2 = nt__min(x * x + (y - ly) * (y - ly), (x - bx) * (x - bx) + (y - 1) * (y - 1));
    nt_real g = nt__sqrt(g2);
    if (x <= 1 && y >= 0) g = nt__min(g, nt__fabs(nt__sqrt((x - 1) * (x - 1) + y * y) - 1));
    return g;
}

nt_real nt__concave_gap(int tile, nt_vec2 c)
{
    canon k = to_canon(tile, c, 0);
    return concave_dist(k.x, k.y);
}

typedef struct curve {
    int circle;
    nt_real a, b, c; /* line: a*x + b*y = c (unit normal); circle: centre (a, b), radius c */
} curve;

/* Feet and crossings of the offset curves: the nearest point of F. */
typedef struct near_free {
    nt_real x, y, r, tol; /* the centre, the radius, the freeness tolerance */
    nt_real best, px, py; /* the shortest freeing move so far */
} near_free;

/* A candidate given by its displacement from the centre (feet keep their exact
 * direction that way; a point far from the origin would lose it). */
static void try_move(near_free *nf, nt_real dx, nt_real dy)
{
    nt_real d2 = dx * dx + dy * dy;
    if (!(d2 < nf->best * nf->best) || d2 <= 0) return;
    if (concave_dist(nf->x + dx, nf->y + dy) < nf->r - nf->tol) return;
    nt_real d = nt__sqrt(d2);
    if (d >= nf->best) return;
    nf->best = d;
    nf->px = dx;
    nf->py = dy;
}

static void try_point(near_free *nf, nt_real qx, nt_real qy) { try_move(nf, qx - nf->x, qy - nf->y); }

static void curve_foot(near_free *nf, const curve *u)
{
    if (!u->circle) {
        nt_real s = u->a * nf->x + u->b * nf->y - u->c;
        try_move(nf, -s * u->a, -s * u->b);
        return;
    }
    nt_real dx = nf->x - u->a, dy = nf->y - u->b;
    nt_real d = nt__sqrt(dx * dx + dy * dy);
    if (d > 0) try_move(nf, dx / d * (u->c - d), dy / d * (u->c - d));
}

static void curve_cross(near_free *nf, const curve *u, const curve *v)
{
    if (u->circle && !v->circle) {
        const curve *t = u;
        u = v;
        v = t;
    }
    if (!u->circle && !v->circle) {
        nt_real det = u->a * v->b - u->b * v->a;
        if (det == 0) return;
        try_point(nf, (u->c * v->b - v->c * u->b) / det, (u->a * v->c - v->a * u->c) / det);
        return;
    }
    if (!u->circle) { /* line u, circle v */
        nt_real s = u->a * v->a + u->b * v->b - u->c;
        if (nt__fabs(s) > v->c) return;
        nt_real fx = v->a - s * u->a, fy = v->b - s * u->b;
        nt_real hc = nt__sqrt(nt__max(0, v->c * v->c - s * s));
        try_point(nf, fx - u->b * hc, fy + u->a * hc);
        try_point(nf, fx + u->b * hc, fy - u->a * hc);
        return;
    }
    nt_real dx = v->a - u->a, dy = v->b - u->b;
    nt_real d2 = dx * dx + dy * dy, d = nt__sqrt(d2);
    if (d <= 0 || d > u->c + v->c || d < nt__fabs(u->c - v->c)) return;
    nt_real k = (u->c * u->c - v->c * v->c + d2) / (2 * d);
    nt_real hh = nt__sqrt(nt__max(0, u->c * u->c - k * k));
    nt_real bx = u->a + dx * k / d, by = u->b + dy * k / d;
    try_point(nf, bx - dy * hh / d, by + dx * hh / d);
    try_point(nf, bx + dy * hh / d, by - dx * hh / d);
}

NT__NOINLINE static int circle_concave_large(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    canon k = to_canon(tile, c, mask);
    /* Free within the tolerance that the candidates below are held to: a touching
     * centre a rounding error inside is its own foot, a move of length 0. */
    nt_real tol = (nt_real)4 * NT_REAL_EPS * (2 + r);
    if (concave_dist(k.x, k.y) >= r - tol) return NT__SEPARATE;
    curve cv[8];
    int n = 0;
    cv[n++] = (curve){0, 0, -1, r};     /* y = -r */
    cv[n++] = (curve){0, 1, 0, 1 + r};  /* x = 1 + r */
    if (!k.mleft) {
        cv[n++] = (curve){0, 1, 0, -r};  /* x = -r */
        cv[n++] = (curve){1, 0, 0, r};   /* cusp (0,0) */
    }
    if (!k.mbottom) {
        cv[n++] = (curve){0, 0, 1, 1 + r}; /* y = 1 + r */
        cv[n++] = (curve){1, 1, 1, r};     /* cusp (1,1) */
    }
    if (!k.mleft && !k.mbottom) cv[n++] = (curve){1, 0, 1, r}; /* corner (0,1) */
    if (r < 1) cv[n++] = (curve){1, 1, 0, 1 - r};                 /* the hollow */
    near_free nf = {k.x, k.y, r, tol, NT_REAL_MAX, 0, 0};
    for (int i = 0; i < n; i++) curve_foot(&nf, &cv[i]);
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++) curve_cross(&nf, &cv[i], &cv[j]);
    if (nf.best == NT_REAL_MAX) return NT__MASKED;
    return push_out(nf.best, nf.px / nf.best, nf.py / nf.best, k.fx, k.fy, out);
}

/* The unmasked case away from the vertices' cones (y <= 0, x >= 1, and x <= 0
 * with y >= 1) in one pass: there the free set is the four half-planes and the
 * disc, so the smallest candidate is the way out and none positive means free. */
NT__SCALAR static int circle_concave(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    if (r > (nt_real)0.5) return circle_concave_large(tile, c, r, mask, out);
    canon k = to_canon(tile, c, 0);
    nt_real x = k.x, y = k.y;
    if (mask | (y <= 0) | (x >= 1) | ((x <= 0) & (y >= 1))) return circle_concave_general(tile, c, r, mask, out);
    nt_real ox = x - 1, oy = y;
    nt_real dist_o = nt__sqrt(ox * ox + oy * oy); /* > 0: x < 1 */
    const nt_real d[5] = {dist_o - (1 - r), y + r, 1 + r - y, x + r, 1 + r - x};
    const nt_real nx[5] = {-ox / dist_o, 0, 0, -1, 1}, ny[5] = {-oy / dist_o, -1, 1, 0, 0};
    int i = first_min3(d), j = first_min2(d + 3) + 3;
    i = d[j] < d[i] ? j : i;
    if (d[i] <= 0) return NT__SEPARATE;
    return push_out(d[i], nx[i], ny[i], k.fx, k.fy, out);
}

/* Dispatch through a table by shape class: one indexed call, not a chain of
 * comparisons. */
typedef int (*aabb_fn)(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out);
typedef int (*circle_fn)(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out);

static int aabb_none(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out)
{
    (void)tile, (void)c, (void)h, (void)mask, (void)out;
    return NT__SEPARATE;
}

static int circle_none(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    (void)tile, (void)c, (void)r, (void)mask, (void)out;
    return NT__SEPARATE;
}

/* Indexed by nt_tile_class. */
static const aabb_fn aabb_by_class[] = {aabb_none, aabb_polygon, aabb_convex, aabb_concave};
static const circle_fn circle_by_class[] = {circle_none, circle_polygon, circle_convex, circle_concave};

int nt__collide_tile_aabb_m(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out)
{
    if ((unsigned)tile >= NT_TILE_COUNT) return NT__SEPARATE;
    return aabb_by_class[nt__tiles[tile].cls](tile, c, h, mask, out);
}

int nt__collide_map_tile_aabb_m(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out)
{
    return aabb_by_class[nt__tiles[tile].cls](tile, c, h, mask, out);
}

int nt__collide_tile_circle_m(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    if ((unsigned)tile >= NT_TILE_COUNT) return NT__SEPARATE;
    return circle_by_class[nt__tiles[tile].cls](tile, c, r, mask, out);
}

int nt__collide_map_tile_circle_m(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    return circle_by_class[nt__tiles[tile].cls](tile, c, r, mask, out);
}

/* The masked routines write *out only when they push, so a caller's NULL can be
 * swapped for a scratch result without a copy. */
bool nt_tile_collide_aabb(int tile, nt_vec2 center, nt_vec2 half, nt_mtv *out)
{
    nt_mtv scratch;
    return nt__collide_tile_aabb_m(tile, center, half, 0, out ? out : &scratch) == NT__PUSH;
}

bool nt_tile_collide_circle(int tile, nt_vec2 center, nt_real radius, nt_mtv *out)
{
    nt_mtv scratch;
    return nt__collide_tile_circle_m(tile, center, radius, 0, out ? out : &scratch) == NT__PUSH;
}

bool nt_tile_collide_shape(int tile, nt_vec2 center, nt_shape shape, nt_mtv *out)
{
    return shape.type == NT_SHAPE_CIRCLE ? nt_tile_collide_circle(tile, center, shape.half.x, out)
                                         : nt_tile_collide_aabb(tile, center, shape.half, out);
}

/* ---------- object pairs ----------
 * The arithmetic is in pair_internal.h, shared with the pair search and the position
 * correction. */

bool nt_collide_aabbs(nt_vec2 ca, nt_vec2 ha, nt_vec2 cb, nt_vec2 hb, nt_mtv *out)
{
    nt_mtv m;
    if (!nt__aabbs_depth(ca, ha, cb, hb, 0, &m)) return false;
    if (out) *out = m;
    return true;
}

bool nt_collide_circles(nt_vec2 ca, nt_real ra, nt_vec2 cb, nt_real rb, nt_mtv *out)
{
    nt_mtv m;
    if (!nt__circles_depth(ca, ra, cb, rb, 0, &m)) return false;
    if (out) *out = m;
    return true;
}

bool nt_collide_aabb_circle(nt_vec2 ca, nt_vec2 ha, nt_vec2 cb, nt_real rb, nt_mtv *out)
{
    nt_mtv m;
    if (!nt__aabb_circle_depth(ca, ha, cb, rb, &m)) return false;
    if (out) *out = m;
    return true;
}

bool nt_collide_shapes(nt_vec2 pa, nt_shape a, nt_vec2 pb, nt_shape b, nt_mtv *out)
{
    nt_mtv m;
    if (!nt__shapes_depth(pa, a.type, a.half, pb, b.type, b.half, &m)) return false;
    if (out) *out = m;
    return true;
}
