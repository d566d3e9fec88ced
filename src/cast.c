/* Shape casts: a box or circle swept against the tiles and the bodies, exactly.
 *
 * Everything is in cell units. Against one tile or body the shape's centre is inside
 * the interior of the Minkowski region M = solid (+) shape exactly when they overlap.
 * Box against a polygon tile or a box body: M is a convex polygon (the expanded bounds
 * cut by the slope's support line, narrow.c), so the entry is the largest entry time
 * over its half-planes (Cyrus-Beck). Every other pair: M's boundary lies on a known
 * finite set of lines and circles (a superset is enough), so between two consecutive
 * crossings of the segment with them the segment is wholly inside M or wholly outside;
 * the exact overlap test at the middle of each piece says which. The first inside
 * piece starts at the entry time.
 */
#include "simulation.h"

/* A crossing of the segment with a boundary curve, and the curve's normal there:
 * a line's unit normal, or a circle's radius vector (made unit when asked for),
 * oriented against the motion when asked for (xing_normal): a piece entered there is
 * entered through it. Only the normal of the crossing nearest an entry is ever used. */
typedef struct xing {
    nt_real t;
    nt_real nx, ny;
    int circle;
} xing;

enum { MAX_X = 64 };

typedef struct xings {
    xing x[MAX_X + 1]; /* the last: scratch, written when the list is full */
    int n;
} xings;

/* The segment a + t d, t in [0, 1], the depth that counts as inside, and the time
 * after which an entry is of no use (the best so far). A stretch inside is followed
 * past tmax to judge its depth: cutting it there could leave it too shallow to count. */
typedef struct seg {
    nt_vec2 a, d;
    nt_real tmax, tiny;
    nt_real tiny_per_t; /* rounding grows with the distance travelled: tiny + t * this */
} seg;

/* The first entry found so far. */
typedef struct hitrec {
    nt_real t;
    nt_vec2 n;
    int kind; /* 0: none, 1: tile, 2: body, 3: start inside */
    int cx, cy;
    int32_t body;
    nt_vec2 lo, hi; /* bounds of what was hit (for the contact point) */
} hitrec;

/* Kept when t is in [-1, 1] and the list has room; written either way, counted only
 * then (no branch: whether a crossing is kept is a coin toss). */
static inline void add_x(xings *X, nt_real t, nt_real nx, nt_real ny, int circle)
{
    xing *e = &X->x[X->n];
    e->t = t;
    e->nx = nx;
    e->ny = ny;
    e->circle = circle;
    X->n += (X->n < MAX_X) & (t <= 1) & (t >= -1);
}

/* The unit normal of crossing i, against the motion. */
static nt_vec2 xing_normal(const xings *X, const seg *s, int i)
{
    nt_real nx = X->x[i].nx, ny = X->x[i].ny;
    if (X->x[i].circle) {
        nt_real l = nt__sqrt(nx * nx + ny * ny);
        nx = nx / l, ny = ny / l;
    }
    if (nx * s->d.x + ny * s->d.y > 0) nx = -nx, ny = -ny;
    return nt_v2(nx, ny);
}

/* The line n . p = e (n unit), with den = n . d and na = n . a computed by the caller
 * (one line direction serves several offsets e). */
static inline void line_x_pre(xings *X, nt_real nx, nt_real ny, nt_real den, nt_real na, nt_real e)
{
    if (den == 0) return;
    nt_real num = e - na;
    /* |num| > 2 |den|: the quotient, correctly rounded, is at least 2 in size and
     * add_x would drop it (most lines of a short segment are far): no division. */
    if (!(nt__fabs(num) <= 2 * nt__fabs(den))) return;
    add_x(X, num / den, nx, ny, 0);
}

/* The line n . p = e (n unit). */
static inline void line_x(xings *X, const seg *s, nt_real nx, nt_real ny, nt_real e)
{
    line_x_pre(X, nx, ny, nx * s->d.x + ny * s->d.y, nx * s->a.x + ny * s->a.y, e);
}

/* The circle |p - q| = rad; A = d . d. */
/* How far from the start a crossing with t in [-1, 1] can lie: |d|, here 1.25 |d|. */
static inline nt_real circle_reach(nt_real A) { return (nt_real)1.25 * nt__sqrt(A); }

/* The circle |p - q| = rad; A = d . d, reach = circle_reach(A). When the start is
 * farther than reach from the circle, by more than the rounding of the roots, every
 * root lies beyond t = +-1 and add_x would drop it: they are not computed. The
 * rounding: near tangency a root's place can be off by about sqrt(3 eps) (|q - a| +
 * rad), 6e-4 (|q - a| + rad) in float, which the distance itself outgrows beyond
 * 2 rad; the spare 4e-3 (1 + rad) covers it with room. */
static void circle_roots(xings *X, const seg *s, nt_real A, nt_real mx, nt_real my, nt_real rad);

/* The test above inline (most circles are far: no call), the roots in a function of
 * their own. */
static inline void circle_x_a(xings *X, const seg *s, nt_real A, nt_real reach, nt_real qx, nt_real qy, nt_real rad)
{
    if (!(rad > 0)) return;
    nt_real mx = s->a.x - qx, my = s->a.y - qy;
    nt_real m2 = mx * mx + my * my, w = reach + (nt_real)4e-3 * (1 + rad);
    if (m2 > (rad + w) * (rad + w) || (rad > w && m2 < (rad - w) * (rad - w))) return;
    circle_roots(X, s, A, mx, my, rad);
}

static void circle_roots(xings *X, const seg *s, nt_real A, nt_real mx, nt_real my, nt_real rad)
{
    nt_real B = mx * s->d.x + my * s->d.y;
    nt_real C = mx * mx + my * my - rad * rad;
    /* B^2 - A C written as A rad^2 - (m x d)^2: no cancellation between two large
     * terms when the circle is small and far. */
    nt_real cr = mx * s->d.y - my * s->d.x;
    nt_real disc = A * rad * rad - cr * cr;
    if (!(A > 0) || disc < 0) return;
    /* Roots of A t^2 + 2 B t + C without cancellation. */
    nt_real k = -(B + (B >= 0 ? nt__sqrt(disc) : -nt__sqrt(disc)));
    nt_real roots[2];
    int nr = 0;
    if (k != 0) {
        roots[nr++] = k / A;
        roots[nr++] = C / k;
    } else {
        roots[nr++] = 0;
    }
    for (int i = 0; i < nr; i++) {
        nt_real t = roots[i];
        nt_real px = mx + s->d.x * t, py = my + s->d.y * t;
        if (px * px + py * py > 0) add_x(X, t, px, py, 1); /* a unit normal exists */
    }
}

static void circle_x(xings *X, const seg *s, nt_real qx, nt_real qy, nt_real rad)
{
    nt_real A = s->d.x * s->d.x + s->d.y * s->d.y;
    circle_x_a(X, s, A, circle_reach(A), qx, qy, rad);
}

/* The same bits (not only the same value: -0 and +0 differ). */
static inline int same_bits(nt_real a, nt_real b) { return memcmp(&a, &b, sizeof a) == 0; }

/* What a piece of the segment is inside of. */
typedef struct region {
    int tile;      /* >= 0: this tile, local coordinates; -1: a body */
    nt_shape obj;  /* the cast shape (cell units) */
    nt_vec2 bp;    /* body centre */
    nt_shape bs;   /* body shape */
} region;

static nt_real region_depth(const region *g, nt_vec2 p, nt_vec2 *n)
{
    nt_mtv m;
    int hit;
    if (g->tile >= 0 && g->obj.type == NT_SHAPE_AABB) /* nt_tile_collide_shape's own call for a box */
        hit = nt__collide_tile_aabb_m(g->tile, p, g->obj.half, 0, &m) == NT__PUSH;
    else
        hit = g->tile >= 0 ? nt_tile_collide_shape(g->tile, p, g->obj, &m) : nt_collide_shapes(p, g->obj, g->bp, g->bs, &m);
    if (!hit) return 0;
    *n = m.normal;
    return m.depth;
}

/* First entry from the crossings: see the top of the file. A run of pieces inside
 * (depth > 0) is an entry when it gets deeper than rounding somewhere (at a piece's
 * middle): a short first piece, cut off by a curve that bounds nothing there, must
 * not delay the entry. one_way: only entries through a surface facing up count.
 *
 * The crossings are walked in time order without sorting them (the walk seldom
 * passes more than two or three): each step takes the earliest crossing after the
 * last one, equal times being one boundary. The normal is that of the crossing
 * nearest to the run's start, the first in time order (then in the order listed) on
 * ties, as a stable sort would put it. */
static int pieces_entry(const xings *X, const seg *s, const region *g, int one_way, nt_real *t_out, nt_vec2 *n_out)
{
    nt_real prev = 0, run_start = 0, run_depth = 0;
    nt_vec2 run_n = nt_v2(0, 0);
    int in_run = 0;
    for (;;) {
        if (!in_run && prev >= s->tmax) break;
        nt_real b = 1;
        int last = 1;
        for (int i = 0; i < X->n; i++) {
            nt_real t = X->x[i].t;
            if (t > prev && (last || t < b)) b = t, last = 0;
        }
        nt_vec2 mn = nt_v2(0, 0);
        nt_real depth = 0;
        if (b > prev) {
            nt_real mid = (nt_real)0.5 * (prev + b);
            depth = region_depth(g, nt_v2(s->a.x + s->d.x * mid, s->a.y + s->d.y * mid), &mn);
        }
        if (depth > 0) {
            if (!in_run) in_run = 1, run_start = prev, run_depth = 0, run_n = mn;
            run_depth = nt__max(run_depth, depth);
        }
        if (in_run && (depth <= 0 || last)) {
            in_run = 0;
            if (run_depth > s->tiny + run_start * s->tiny_per_t) {
                /* The curve crossed nearest to the run's start bounds it there. */
                nt_real best = NT_REAL_MAX, best_t = 0;
                int bi = -1;
                for (int i = 0; i < X->n; i++) {
                    nt_real t = X->x[i].t, e = nt__fabs(t - run_start);
                    if (e < best || (e == best && t < best_t)) best = e, best_t = t, bi = i;
                }
                nt_vec2 n = bi >= 0 ? xing_normal(X, s, bi) : run_n;
                if (!one_way || n.y < 0) {
                    *t_out = run_start;
                    *n_out = n;
                    return 1;
                }
            }
        }
        prev = nt__max(prev, b);
        if (last) break;
    }
    return 0;
}

/* Convex M = { p : n_i . p < e_i for every i }: Cyrus-Beck, and the middle of the
 * inside stretch must be deeper than rounding. */
static int halfplanes_entry(const nt_real (*L)[3], int nl, const seg *s, int one_way, nt_real *t_out, nt_vec2 *n_out)
{
    nt_real tin = -NT_REAL_MAX, tout = NT_REAL_MAX, nearest = NT_REAL_MAX;
    int in_i = -1, near_i = 0;
    for (int i = 0; i < nl; i++) {
        nt_real gap = L[i][2] - (L[i][0] * s->a.x + L[i][1] * s->a.y); /* > 0: inside at a */
        nt_real den = L[i][0] * s->d.x + L[i][1] * s->d.y;
        if (gap < nearest) nearest = gap, near_i = i;
        if (den == 0) {
            if (gap <= 0) return 0;
            continue;
        }
        nt_real t = gap / den;
        if (den < 0) {
            if (t > tin) tin = t, in_i = i;
        } else if (t < tout) {
            tout = t;
        }
    }
    nt_real lo = nt__max(tin, 0), hi = nt__min(tout, 1);
    if (!(lo < hi) || !(lo < s->tmax)) return 0;
    nt_real mid = (nt_real)0.5 * (lo + hi), depth = NT_REAL_MAX;
    for (int i = 0; i < nl; i++)
        depth = nt__min(depth, L[i][2] - (L[i][0] * (s->a.x + s->d.x * mid) + L[i][1] * (s->a.y + s->d.y * mid)));
    if (!(depth > s->tiny + lo * s->tiny_per_t)) return 0;
    int i = in_i >= 0 ? in_i : near_i;
    nt_vec2 n = nt_v2(L[i][0], L[i][1]);
    if (one_way && !(n.y < 0)) return 0; /* a convex region is entered once */
    *t_out = lo;
    *n_out = n;
    return 1;
}

/* Room for rounding (of the segment's points, of the narrow phase's sums) in the
 * tests below that prove a box clear of a round tile: far more than either. */
#define CLEAR_MARGIN (nt_real)1e-4

/* The box's bounds over the whole segment, in the tile's canonical frame (narrow.c's
 * to_canon: CONVEX's solid the quarter disc around (0,1), CONCAVE's the cell outside
 * the disc around (1,0)), cut to the cell: when that rectangle stays CLEAR_MARGIN
 * clear of the solid (CONVEX: its nearest point to the arc's centre beyond 1 + margin;
 * CONCAVE: its farthest point within 1 - margin, so the box's part in the cell lies
 * in the hollow), the box at every piece's middle is clear of it too: no entry,
 * without the curves. */
static int round_box_clear(const nt_tile_info *ti, const seg *s, nt_vec2 h)
{
    nt_real x0 = s->a.x, x1 = s->a.x + s->d.x, y0 = s->a.y, y1 = s->a.y + s->d.y;
    if (ti->signx < 0) x0 = 1 - x0, x1 = 1 - x1;
    if (ti->signy > 0) y0 = 1 - y0, y1 = 1 - y1;
    nt_real xl = nt__max(nt__min(x0, x1) - h.x, 0), yh = nt__min(nt__max(y0, y1) + h.y, 1);
    if (ti->cls == NT_CLASS_CONVEX) return xl * xl + (1 - yh) * (1 - yh) > (1 + CLEAR_MARGIN) * (1 + CLEAR_MARGIN);
    return (1 - xl) * (1 - xl) + yh * yh < (1 - CLEAR_MARGIN) * (1 - CLEAR_MARGIN);
}

/* One of poly_entry's half-planes (index i, gap > 0 inside at the start, den = n . d),
 * its loop step written out: 0 when the segment misses the region. */
static inline int poly_plane(int i, nt_real gap, nt_real den, nt_real *tin, int *in_i, nt_real *tout)
{
    if (den == 0) return !(gap <= 0);
    nt_real t = gap / den;
    if (den < 0) {
        if (t > *tin) *tin = t, *in_i = i;
    } else if (t < *tout) {
        *tout = t;
    }
    return 1;
}

/* halfplanes_entry for a box against a POLYGON tile: the half-planes of tile_entry's
 * table (the bounds grown by the box, then the slope's), with the products by the
 * table's 0 and +-1 left out: n . a for n = (-1, 0) is (-1) a.x + 0 a.y, which is -a.x
 * (adding a zero to a non-zero sum changes nothing, and when a.x is zero the zero's
 * sign does not reach the result: e + a.x and e - (-a.x + 0) are both +0 for e = +0,
 * and e otherwise). Same values, same order, same answer. */
static int poly_entry(const nt_tile_info *ti, const nt__tile_geom *g, const seg *s, nt_vec2 h, int one_way,
                      nt_real *t_out, nt_vec2 *n_out)
{
    const nt_real ax = s->a.x, ay = s->a.y, dx = s->d.x, dy = s->d.y;
    /* The planes one by one, in their order, not over arrays: the values stay in
     * registers. */
    const nt_real e0 = h.x - ti->bounds_min.x, gap0 = e0 + ax;
    const nt_real e1 = ti->bounds_max.x + h.x, gap1 = e1 - ax;
    const nt_real e2 = h.y - ti->bounds_min.y, gap2 = e2 + ay;
    const nt_real e3 = ti->bounds_max.y + h.y, gap3 = e3 - ay;
    const int slope = g->has_slope;
    nt_real e4 = 0, gap4 = 0, den4 = 0, snx = 0, sny = 0;
    if (slope) {
        nt_real ux = g->slope[0], uy = g->slope[1];
        snx = g->slope[4], sny = g->slope[5];
        e4 = (g->slope[2] + h.x * nt__fabs(ux) + h.y * nt__fabs(uy)) * g->slope[3];
        gap4 = e4 - (snx * ax + sny * ay);
        den4 = snx * dx + sny * dy;
    }
    nt_real tin = -NT_REAL_MAX, tout = NT_REAL_MAX;
    int in_i = -1;
    if (!poly_plane(0, gap0, -dx, &tin, &in_i, &tout) || !poly_plane(1, gap1, dx, &tin, &in_i, &tout) ||
        !poly_plane(2, gap2, -dy, &tin, &in_i, &tout) || !poly_plane(3, gap3, dy, &tin, &in_i, &tout) ||
        (slope && !poly_plane(4, gap4, den4, &tin, &in_i, &tout)))
        return 0;
    nt_real lo = nt__max(tin, 0), hi = nt__min(tout, 1);
    if (!(lo < hi) || !(lo < s->tmax)) return 0;
    nt_real mid = (nt_real)0.5 * (lo + hi);
    nt_real px = ax + dx * mid, py = ay + dy * mid;
    nt_real depth = nt__min(NT_REAL_MAX, e0 + px);
    depth = nt__min(depth, e1 - px);
    depth = nt__min(depth, e2 + py);
    depth = nt__min(depth, e3 - py);
    if (slope) depth = nt__min(depth, e4 - (snx * px + sny * py));
    if (!(depth > s->tiny + lo * s->tiny_per_t)) return 0;
    int i = in_i;
    if (i < 0) {
        /* No plane entered (no motion across any): the nearest, the first of the
         * smallest gaps, found only now (halfplanes_entry tracks it in its loop). */
        nt_real nearest = NT_REAL_MAX;
        i = 0;
        if (gap0 < nearest) nearest = gap0, i = 0;
        if (gap1 < nearest) nearest = gap1, i = 1;
        if (gap2 < nearest) nearest = gap2, i = 2;
        if (gap3 < nearest) nearest = gap3, i = 3;
        if (slope && gap4 < nearest) i = 4;
    }
    static const nt_real axis_n[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
    nt_vec2 n = i < 4 ? nt_v2(axis_n[i][0], axis_n[i][1]) : nt_v2(snx, sny);
    if (one_way && !(n.y < 0)) return 0; /* a convex region is entered once */
    *t_out = lo;
    *n_out = n;
    return 1;
}

/* tile_entry for every pair but a box against a POLYGON tile: the crossings with
 * the curves. Out of line: the common polygon case does not pay for its frame. */
NT__NOINLINE static int curves_entry(int tile, const seg *s, const nt_shape *obj_p, int one_way, nt_real *t, nt_vec2 *n)
{
    const nt_shape obj = *obj_p;
    const nt_tile_info *ti = &nt__tiles[tile];
    nt_vec2 h = obj.half;
    if (obj.type == NT_SHAPE_AABB && (ti->cls == NT_CLASS_CONVEX || ti->cls == NT_CLASS_CONCAVE)) {
        /* Clear of the cell along an axis at the start and not moving back along it:
         * the box routine's test along that axis (canonical frame: the same sums as
         * aabb_convex and aabb_concave, per class for x) fails at every piece's middle
         * too, rounding being monotonic (a middle's coordinate lies on the start's
         * side), so every region depth is 0 and pieces_entry would answer no entry. */
        nt_real ky = ti->signy > 0 ? 1 - s->a.y : s->a.y, vy = ti->signy > 0 ? -s->d.y : s->d.y;
        if ((ky + h.y <= 0 && vy <= 0) || (1 + h.y - ky <= 0 && vy >= 0)) return 0;
        nt_real kx = ti->signx < 0 ? 1 - s->a.x : s->a.x, vx = ti->signx < 0 ? -s->d.x : s->d.x;
        nt_real dr = ti->cls == NT_CLASS_CONVEX ? 1 + h.x - kx : 1 - (kx - h.x);
        if ((kx + h.x <= 0 && vx <= 0) || (dr <= 0 && vx >= 0)) return 0;
    }
    if (obj.type == NT_SHAPE_AABB && round_box_clear(ti, s, h)) return 0;
    xings X;
    X.n = 0;
    int nv = ti->vertex_count;
    int round = ti->cls == NT_CLASS_CONVEX || ti->cls == NT_CLASS_CONCAVE;
    nt_vec2 o = ti->arc_center;
    if (obj.type == NT_SHAPE_CIRCLE) {
        /* M = points within r of the tile: its edges moved out by r, circles of radius
         * r around its corners, and the arc's circle grown or shrunk by r. */
        nt_real r = h.x;
        for (int i = 0; i < nv; i++) {
            nt_vec2 v = ti->vertices[i], w = ti->vertices[(i + 1) % nv];
            circle_x(&X, s, v.x, v.y, r);
            nt_real ex = -(w.y - v.y), ey = w.x - v.x, len = nt__sqrt(ex * ex + ey * ey);
            if (len > 0) line_x(&X, s, ex / len, ey / len, (ex * v.x + ey * v.y) / len + r);
        }
        if (round) {
            circle_x(&X, s, o.x, o.y, 1 + r);
            circle_x(&X, s, o.x, o.y, nt__fabs(1 - r));
        }
    } else {
        /* M = tile (+) box: each box corner running along each tile edge and the arc,
         * and each box side running past each tile corner. A crossing equal bit for
         * bit to one listed before it (an axis-aligned edge met by two corners at the
         * same offset, two tile corners on one line) is left out: it bounds no piece
         * of its own and is never the only nearest (leaving one in changes nothing). Each edge's normal, n . d and
         * n . a are computed once, as line_x would compute them for every corner.
         * An edge whose four lines line_x_pre would all drop is skipped (live 0): they
         * lie within |n.x| h.x + |n.y| h.y of the edge's own line, so a start farther
         * from that line than 2 |n . d|, with CLEAR_MARGIN of room for the rounding of
         * the sums (relative to their size), has every |e - n . a| above 2 |n . d|. */
        nt_real enx[4], eny[4], eex[4], eey[4], elen[4], eden[4], ena[4], eoff[4][4];
        int live[4];
        for (int i = 0; i < nv; i++) {
            nt_vec2 v = ti->vertices[i], w = ti->vertices[(i + 1) % nv];
            eex[i] = -(w.y - v.y), eey[i] = w.x - v.x, elen[i] = nt__sqrt(eex[i] * eex[i] + eey[i] * eey[i]);
            live[i] = 0;
            if (elen[i] > 0) {
                enx[i] = eex[i], eny[i] = eey[i];
                if (elen[i] != 1) enx[i] = enx[i] / elen[i], eny[i] = eny[i] / elen[i];
                eden[i] = enx[i] * s->d.x + eny[i] * s->d.y;
                ena[i] = enx[i] * s->a.x + eny[i] * s->a.y;
                nt_real den2 = 2 * nt__fabs(eden[i]);
                nt_real gap = nt__fabs((enx[i] * v.x + eny[i] * v.y) - ena[i]) - (nt__fabs(enx[i]) * h.x + nt__fabs(eny[i]) * h.y);
                live[i] = eden[i] != 0 && gap <= den2 + CLEAR_MARGIN * (1 + nt__fabs(ena[i]) + den2);
            }
        }
        nt_real A = s->d.x * s->d.x + s->d.y * s->d.y, reach = circle_reach(A);
        /* Each corner's offset along each edge, edge by edge (one test of the length
         * per edge); the crossings below are listed corner by corner as before. */
        for (int i = 0; i < nv; i++) {
            if (!live[i]) continue;
            nt_vec2 v = ti->vertices[i];
            for (int k = 0; k < 4; k++) {
                nt_real sx = (k & 1) ? h.x : -h.x, sy = (k & 2) ? h.y : -h.y;
                eoff[i][k] = eex[i] * (v.x - sx) + eey[i] * (v.y - sy);
            }
            if (elen[i] != 1) /* x / 1 is x, bit for bit */
                for (int k = 0; k < 4; k++) eoff[i][k] = eoff[i][k] / elen[i];
        }
        for (int k = 0; k < 4; k++) {
            nt_real sx = (k & 1) ? h.x : -h.x, sy = (k & 2) ? h.y : -h.y;
            for (int i = 0; i < nv; i++) {
                if (!live[i]) continue;
                nt_real e = eoff[i][k];
                /* The corners that share this one's x (k ^ 2) or y (k ^ 1) offset give
                 * the same line for an axis-aligned edge: compared with those listed
                 * before it. (A repeat left in would change nothing either.) */
                int dup = ((k & 2) && same_bits(eoff[i][k & 1], e)) || ((k & 1) && same_bits(eoff[i][k & 2], e));
                if (!dup) line_x_pre(&X, enx[i], eny[i], eden[i], ena[i], e);
            }
            if (round) circle_x_a(&X, s, A, reach, o.x - sx, o.y - sy, 1);
        }
        nt_real denx = (nt_real)1 * s->d.x + (nt_real)0 * s->d.y, nax = (nt_real)1 * s->a.x + (nt_real)0 * s->a.y;
        nt_real deny = (nt_real)0 * s->d.x + (nt_real)1 * s->d.y, nay = (nt_real)0 * s->a.x + (nt_real)1 * s->a.y;
        for (int i = 0; i < nv; i++) {
            nt_vec2 v = ti->vertices[i];
            int dupx = 0, dupy = 0;
            for (int j = 0; j < i; j++) {
                dupx |= same_bits(ti->vertices[j].x, v.x);
                dupy |= same_bits(ti->vertices[j].y, v.y);
            }
            if (!dupx) {
                line_x_pre(&X, 1, 0, denx, nax, v.x - h.x);
                line_x_pre(&X, 1, 0, denx, nax, v.x + h.x);
            }
            if (!dupy) {
                line_x_pre(&X, 0, 1, deny, nay, v.y - h.y);
                line_x_pre(&X, 0, 1, deny, nay, v.y + h.y);
            }
        }
    }
    region g;
    g.tile = tile;
    g.obj = obj;
    g.bp = nt_v2(0, 0);
    g.bs = obj;
    return pieces_entry(&X, s, &g, one_way, t, n);
}

/* The segment (local to the tile's cell) against one tile. */
static int tile_entry(int tile, const seg *s, const nt_shape *obj_p, int one_way, nt_real *t, nt_vec2 *n)
{
    const nt_tile_info *ti = &nt__tiles[tile];
    if (obj_p->type == NT_SHAPE_AABB && ti->cls == NT_CLASS_POLYGON)
        return poly_entry(ti, &nt__geom[tile], s, obj_p->half, one_way, t, n);
    return curves_entry(tile, s, obj_p, one_way, t, n);
}

/* The segment (cell units) against one body (centre bp, shape bs, cell units). */
static int body_entry(nt_vec2 bp, nt_shape bs, const seg *s, nt_shape obj, int one_way, nt_real *t, nt_vec2 *n)
{
    if (obj.type == NT_SHAPE_AABB && bs.type == NT_SHAPE_AABB) {
        nt_real hx = obj.half.x + bs.half.x, hy = obj.half.y + bs.half.y;
        nt_real L[4][3] = {{-1, 0, hx - bp.x}, {1, 0, bp.x + hx}, {0, -1, hy - bp.y}, {0, 1, bp.y + hy}};
        return halfplanes_entry((const nt_real(*)[3])L, 4, s, one_way, t, n);
    }
    xings X;
    X.n = 0;
    if (obj.type == NT_SHAPE_CIRCLE && bs.type == NT_SHAPE_CIRCLE) {
        circle_x(&X, s, bp.x, bp.y, obj.half.x + bs.half.x);
    } else {
        /* A box and a circle: the box grown by r, corners rounded. */
        nt_vec2 hb = obj.type == NT_SHAPE_AABB ? obj.half : bs.half;
        nt_real r = obj.type == NT_SHAPE_CIRCLE ? obj.half.x : bs.half.x;
        line_x(&X, s, 1, 0, bp.x - hb.x - r);
        line_x(&X, s, 1, 0, bp.x + hb.x + r);
        line_x(&X, s, 0, 1, bp.y - hb.y - r);
        line_x(&X, s, 0, 1, bp.y + hb.y + r);
        for (int k = 0; k < 4; k++)
            circle_x(&X, s, bp.x + ((k & 1) ? hb.x : -hb.x), bp.y + ((k & 2) ? hb.y : -hb.y), r);
    }
    region g;
    g.tile = -1;
    g.obj = obj;
    g.bp = bp;
    g.bs = bs;
    return pieces_entry(&X, s, &g, one_way, t, n);
}

/* ------------------------------------------------------------------ the cast */

typedef struct caster {
    const nt_map *map;
    const nt_world *world;     /* one-way cells and bodies; NULL for a map cast */
    const nt_query_filter *filter;
    nt_vec2 p0, d;             /* cell units */
    nt_shape obj;              /* cell units, as given */
    nt_vec2 pos;               /* the start and the shape in world units, as given */
    nt_shape shape;
    nt_shape sweep;            /* the shape swept: obj shrunk by the resting depth */
    nt_real tiny0, tol;        /* rounding at the start, and the resting limit */
    nt_real tiny_per_t;        /* the sweep: rounding grows by this over the way (t = 1) */
    int tiles;
    int one_way_cells;         /* the world has one-way cells */
    int rx0, ry0, rx1, ry1;    /* the cells of the start box and the box swept (run_cast) */
    nt__cast_start *start;     /* the tiles' start overlaps, kept across casts; NULL: none */
    hitrec best;
} caster;

/* A one-way cell the shape overlaps at the start, other than resting on it from
 * above, is ignored by the whole cast. depth/normal: its start overlap. */
static int one_way_ignored(nt_real depth, nt_vec2 n, const caster *c)
{
    return depth > c->tiny0 && !(depth <= c->tol && n.y < 0);
}

/* The flags' lookup out of line: the test of one_way_cells, inline, spares most
 * casts the call (a world without one-way cells). */
NT__NOINLINE static int cell_flag_one_way(const caster *c, int x, int y)
{
    return (nt__cell_flags(c->world, x, y) & NT_CELL_ONE_WAY) != 0;
}

static inline int cell_one_way(const caster *c, int x, int y)
{
    return c->one_way_cells && cell_flag_one_way(c, x, y);
}

/* A one-way cell the cast passes through (filter.one_way_off). */
static inline int cell_skipped(const caster *c, int x, int y)
{
    return c->one_way_cells && c->filter && c->filter->one_way_off && cell_flag_one_way(c, x, y);
}

/* A tile's start depth when its masked test pushes (m; u: the plain test, read only
 * when m is deeper than the tolerance). */
static nt_real start_push_depth(const caster *c, const nt_mtv *m, const nt_mtv *u, nt_vec2 *n)
{
    /* Resting on a corner where a seam meets an exposed edge (a slope's crest beside a
     * FULL tile): the way out past the seam is deep, but the shape only touches the
     * tile (plain depth within the tolerance) and the map as a whole agrees. */
    if (m->depth > c->tol && u->depth <= c->tol) {
        nt_resolution res;
        nt_real tw = c->tol * c->map->cell;
        if (!nt_map_resolve(c->map, c->pos, c->shape, &res) || nt__dot(res.push, res.push) <= tw * tw) {
            *n = u->normal;
            return u->depth;
        }
    }
    *n = m->normal;
    return m->depth;
}

/* A box's start overlap with a tile (cell, seams mask) provably no deeper than tiny0,
 * so that the scan finds no contact there, from the first sums of the box routine
 * (aabb_polygon, aabb_convex, aabb_concave: the same expressions, the same bits): one
 * at or below 0 separates; one on no seam (never masked) is a candidate, and the depth
 * is the smallest candidate. Most start cells only touch the box (the floor under it,
 * a wall beside it): no call. */
static NT__INLINE int box_start_shallow(const caster *c, int tile, unsigned mask, nt_vec2 l)
{
    const nt_tile_info *ti = &nt__tiles[tile];
    const nt_vec2 h = c->obj.half;
    const nt_real t = c->tiny0;
    /* Candidate v, masked when mask & bit: no deeper than t. */
#define SHALLOW(v, bit) ((v) <= t && ((v) <= 0 || !(mask & (bit))))
    if (ti->cls == NT_CLASS_POLYGON) {
        nt_real du = l.y + h.y - ti->bounds_min.y;
        if (SHALLOW(du, 1u << NT_SIDE_TOP)) return 1;
        nt_real dl = l.x + h.x - ti->bounds_min.x;
        if (SHALLOW(dl, 1u << NT_SIDE_LEFT)) return 1;
        nt_real dr = ti->bounds_max.x - (l.x - h.x);
        if (SHALLOW(dr, 1u << NT_SIDE_RIGHT)) return 1;
        nt_real dd = ti->bounds_max.y - (l.y - h.y);
        if (SHALLOW(dd, 1u << NT_SIDE_BOTTOM)) return 1;
        const nt__tile_geom *g = &nt__geom[tile];
        if (!g->has_slope) return 0;
        nt_real ux = g->slope[0], uy = g->slope[1];
        nt_real ds = g->slope[2] - (ux * l.x + uy * l.y) + h.x * nt__fabs(ux) + h.y * nt__fabs(uy);
        return ds <= 0 || ds * g->slope[3] <= t;
    }
    if (ti->cls != NT_CLASS_CONVEX && ti->cls != NT_CLASS_CONCAVE) return 0;
    /* narrow.c's to_canon; its right and up candidates are never masked. */
    int fx = ti->signx < 0, fy = ti->signy > 0;
    nt_real kx = fx ? 1 - l.x : l.x, ky = fy ? 1 - l.y : l.y;
    nt_real du = ky + h.y;
    if (du <= t) return 1;
    nt_real dr = ti->cls == NT_CLASS_CONVEX ? 1 + h.x - kx : 1 - (kx - h.x);
    if (dr <= t) return 1;
    if (ti->cls == NT_CLASS_CONVEX) {
        /* The arc (resting on a hill): separate beyond it, else a candidate. */
        nt_real vx = kx - h.x, vy = ky - (1 - h.y);
        if (vx > 0 && vy < 0) {
            nt_real d2 = vx * vx + vy * vy;
            if (d2 >= 1 || 1 - nt__sqrt(d2) <= t) return 1;
        }
    } else {
        /* The hollow (resting in a quarter pipe): separate within it, else a candidate. */
        nt_real ox = 1 - (kx - h.x), oy = 0 - (ky + h.y);
        nt_real d2 = ox * ox + oy * oy;
        if (d2 <= 1 || nt__sqrt(d2) - 1 <= t) return 1;
    }
    nt_real dl = kx + h.x;
    if (SHALLOW(dl, 1u << (fx ? NT_SIDE_RIGHT : NT_SIDE_LEFT))) return 1;
    nt_real dd = 1 + h.y - ky;
    return SHALLOW(dd, 1u << (fy ? NT_SIDE_TOP : NT_SIDE_BOTTOM));
#undef SHALLOW
}

/* Start overlap of the given shape with one tile (its cell), seams ignored as
 * nt_map_resolve ignores them. Returns the depth (NT_REAL_MAX when every way out is a
 * seam). */
static NT__INLINE nt_real cell_start_depth(const caster *c, int x, int y, nt__cell cell, nt_vec2 *n)
{
    *n = nt_v2(0, 0);
    if (cell.tile == NT_TILE_EMPTY) return 0;
    nt_vec2 l = nt_v2(c->p0.x - (nt_real)x, c->p0.y - (nt_real)y);
    nt_mtv m, u;
    if (c->obj.type == NT_SHAPE_AABB) {
        if (box_start_shallow(c, cell.tile, cell.seams, l)) return 0;
        /* A box's overlap does not depend on the mask (the masked routine is the
         * plain one with mask 0, and separates exactly when it does): the plain test
         * is needed only for a masked tile's depth. */
        int r = nt__collide_tile_aabb_m(cell.tile, l, c->obj.half, cell.seams, &m);
        if (r == NT__SEPARATE) return 0;
        /* The plain depth: for a masked tile, and for the corner case below. */
        if (r == NT__MASKED || m.depth > c->tol) nt__collide_tile_aabb_m(cell.tile, l, c->obj.half, 0, &u);
        if (r == NT__MASKED) return u.depth <= c->tol ? 0 : NT_REAL_MAX;
        return start_push_depth(c, &m, &u, n);
    }
    /* The overlap itself from the plain test: the masked one measures the way out. */
    if (!nt_tile_collide_shape(cell.tile, l, c->obj, &u)) return 0;
    int r = c->obj.type == NT_SHAPE_CIRCLE ? nt__collide_tile_circle_m(cell.tile, l, c->obj.half.x, cell.seams, &m)
                                           : nt__collide_tile_aabb_m(cell.tile, l, c->obj.half, cell.seams, &m);
    if (r == NT__SEPARATE) return 0;
    if (r == NT__MASKED) {
        /* Every way out of this tile alone is a seam: its neighbours, which cover
         * those sides, give the contacts; only a deep overlap counts here. */
        return u.depth <= c->tol ? 0 : NT_REAL_MAX;
    }
    return start_push_depth(c, &m, &u, n);
}

static NT__INLINE nt_real tile_start_depth(const caster *c, int x, int y, nt_vec2 *n)
{
    const nt_map *map = c->map;
    nt__cell cell = nt__map_in(map, x, y) ? map->cells[(size_t)y * (size_t)map->w + (size_t)x] : nt__map_cell(map, x, y);
    return cell_start_depth(c, x, y, cell, n);
}

/* One start overlap: deep ends the cast, approaching stops it at 0, else it counts
 * towards the resting depth. Returns 1 when the cast is decided. */
static int start_contact(caster *c, nt_real depth, nt_vec2 n, int kind, int cx, int cy, int32_t body, nt_real *rest)
{
    if (depth <= c->tiny0) return 0;
    if (depth > c->tol) {
        c->best.t = 0;
        c->best.n = nt_v2(0, 0);
        c->best.kind = 3;
        c->best.cx = cx;
        c->best.cy = cy;
        c->best.body = body;
        return 1;
    }
    if (nt__dot(n, c->d) < 0 && c->best.kind == 0) {
        c->best.t = 0;
        c->best.n = n;
        c->best.kind = kind;
        c->best.cx = cx;
        c->best.cy = cy;
        c->best.body = body;
    }
    if (depth > *rest) *rest = depth;
    return 0;
}

static void set_tile_bounds(hitrec *h, int tile, int x, int y)
{
    const nt_tile_info *ti = &nt__tiles[tile];
    h->lo = nt_v2((nt_real)x + ti->bounds_min.x, (nt_real)y + ti->bounds_min.y);
    h->hi = nt_v2((nt_real)x + ti->bounds_max.x, (nt_real)y + ti->bounds_max.y);
}

/* Start overlaps with the tiles. Returns 1 when the cast is decided (deep). */
/* One tile's start overlap, in scan order. Returns 1 when the cast is decided. */
static int start_tile(caster *c, nt_real depth, nt_vec2 n, int x, int y, int tile, nt_real *rest)
{
    int had = c->best.kind;
    if (start_contact(c, depth, n, 1, x, y, -1, rest)) return 1;
    if (!had && c->best.kind) set_tile_bounds(&c->best, tile, x, y);
    return 0;
}

/* Start overlaps with the tiles. Returns 1 when the cast is decided (deep).
 *
 * What the scan finds depends on the start (p0, the shape), the map and its one-way
 * cells, and the filter's one_way_off, not on the motion: a cast from the same place
 * in the same world (the mover's next slide after meeting a surface at t = 0) replays
 * the overlaps that count (deeper than tiny0, not ignored one-way cells) in the same
 * order instead of measuring them again. The caller keeps c->start valid only for one
 * world state and one filter (one move). */
static int start_tiles(caster *c, nt_real *rest)
{
    nt__cast_start *sc = c->start;
    nt_vec2 h = c->obj.half, p0 = c->p0;
    if (sc && sc->valid && same_bits(sc->p0.x, p0.x) && same_bits(sc->p0.y, p0.y) && same_bits(sc->half.x, h.x) &&
        same_bits(sc->half.y, h.y) && same_bits(sc->pos.x, c->pos.x) && same_bits(sc->pos.y, c->pos.y)) {
        for (int i = 0; i < sc->n; i++)
            if (start_tile(c, sc->e[i].depth, sc->e[i].n, sc->e[i].x, sc->e[i].y, sc->e[i].tile, rest)) return 1;
        return 0;
    }
    if (sc) sc->valid = 0, sc->n = 0;
    int keep = sc != NULL;
    /* The start box's cells; the swept box's range starts (ends) with them on the
     * side the motion leaves from: the same sums, the same floors. */
    nt_vec2 p1 = nt__add(c->p0, c->d);
    int x0 = p0.x <= p1.x ? c->rx0 : nt__floor_int(p0.x - h.x), x1 = p0.x >= p1.x ? c->rx1 : nt__floor_int(p0.x + h.x);
    int y0 = p0.y <= p1.y ? c->ry0 : nt__floor_int(p0.y - h.y), y1 = p0.y >= p1.y ? c->ry1 : nt__floor_int(p0.y + h.y);
    int decided = 0;
    for (int y = y0; y <= y1 && !decided; y++)
        for (int x = x0; x <= x1; x++) {
            nt_vec2 n;
            /* An EMPTY cell overlaps nothing: no depth, no contact. (The cell read
             * once; outside the map nt__map_tile's FULL, nt__map_cell's.) */
            const nt_map *map = c->map;
            int in = nt__map_in(map, x, y);
            nt__cell cell;
            cell.tile = NT_TILE_FULL;
            if (in) cell = map->cells[(size_t)y * (size_t)map->w + (size_t)x];
            int tile = cell.tile;
            if (tile == NT_TILE_EMPTY || cell_skipped(c, x, y)) continue;
            if (!in) cell = nt__map_cell(map, x, y);
            nt_real depth = cell_start_depth(c, x, y, cell, &n);
            if (cell_one_way(c, x, y) && one_way_ignored(depth, n, c)) continue;
            if (depth <= c->tiny0) continue; /* start_contact: no contact */
            if (keep) {
                if (sc->n < NT__CAST_START_MAX) {
                    sc->e[sc->n].depth = depth;
                    sc->e[sc->n].n = n;
                    sc->e[sc->n].x = x;
                    sc->e[sc->n].y = y;
                    sc->e[sc->n].tile = tile;
                    sc->n++;
                } else {
                    keep = 0;
                }
            }
            if (start_tile(c, depth, n, x, y, tile, rest)) {
                decided = 1;
                break;
            }
        }
    if (keep) {
        sc->valid = 1;
        sc->p0 = p0;
        sc->half = h;
        sc->pos = c->pos;
    }
    return decided;
}

/* The sweep against one tile cell (not EMPTY). */
static void sweep_cell(caster *c, int x, int y, int tile, nt_real tmax)
{
    if (cell_skipped(c, x, y)) return;
    int one_way = cell_one_way(c, x, y);
    if (one_way) {
        nt_vec2 n;
        if (one_way_ignored(tile_start_depth(c, x, y, &n), n, c)) return;
    }
    seg s;
    s.a = nt_v2(c->p0.x - (nt_real)x, c->p0.y - (nt_real)y);
    s.d = c->d;
    s.tmax = tmax;
    s.tiny = c->tiny0;
    s.tiny_per_t = c->tiny_per_t;
    nt_real t;
    nt_vec2 n;
    if (tile_entry(tile, &s, &c->sweep, one_way, &t, &n) && t < c->best.t) {
        c->best.t = t;
        c->best.n = n;
        c->best.kind = 1;
        c->best.cx = x;
        c->best.cy = y;
        c->best.body = -1;
        set_tile_bounds(&c->best, tile, x, y);
    }
}

/* t range in which the centre's coordinate p + t d lies within [lo, hi]. */
static int slab(nt_real p, nt_real d, nt_real lo, nt_real hi, nt_real *t0, nt_real *t1)
{
    if (d == 0) {
        *t0 = 0;
        *t1 = 1;
        return p >= lo && p <= hi;
    }
    nt_real a = (lo - p) / d, b = (hi - p) / d;
    *t0 = nt__min(a, b);
    *t1 = nt__max(a, b);
    return 1;
}

/* The cells the swept shape covers, column by column and row by row in the direction
 * of motion, so that the walk stops once every cell left starts after the best hit. */
static void sweep_tiles(caster *c)
{
    nt_vec2 h = c->sweep.half, p0 = c->p0, d = c->d;
    nt_real xa = nt__min(p0.x, p0.x + d.x), xb = nt__max(p0.x, p0.x + d.x);
    int same = same_bits(h.x, c->obj.half.x), samey = same_bits(h.y, c->obj.half.y); /* not shrunk: run_cast's range */
    int cx0 = same ? c->rx0 : nt__floor_int(xa - h.x), cx1 = same ? c->rx1 : nt__floor_int(xb + h.x);
    int sx = d.x < 0 ? -1 : 1, sy = d.y < 0 ? -1 : 1;
    int polys = c->sweep.type == NT_SHAPE_AABB && (d.x == 0 || d.y == 0); /* see below */
    /* Each walk counts its cells down (one test a step, whichever the direction). */
    for (int x = sx > 0 ? cx0 : cx1, nx = cx1 - cx0 + 1; nx > 0; nx--, x += sx) {
        nt_real t0, t1;
        if (!slab(p0.x, d.x, (nt_real)x - h.x, (nt_real)x + 1 + h.x, &t0, &t1)) continue;
        if (t0 > c->best.t) break;
        t0 = nt__max(t0, 0);
        t1 = nt__min(t1, 1);
        if (t0 > t1) continue;
        int cy0, cy1;
        if (samey && t0 == 0 && t1 == 1) {
            /* The column across the whole way: run_cast's rows (the same sums; a
             * zero's sign, d.y * 0, changes no floor). */
            cy0 = c->ry0, cy1 = c->ry1;
        } else {
            nt_real ya = nt__min(p0.y + d.y * t0, p0.y + d.y * t1), yb = nt__max(p0.y + d.y * t0, p0.y + d.y * t1);
            cy0 = nt__floor_int(ya - h.y), cy1 = nt__floor_int(yb + h.y);
        }
        for (int y = sy > 0 ? cy0 : cy1, ny = cy1 - cy0 + 1; ny > 0; ny--, y += sy) {
            /* EMPTY cells first: the rows are met in order of time, so a row
             * starting after the best hit is followed only by such rows, and the
             * walk stops at the first one that is not EMPTY as it would have at
             * the first. */
            int tile = nt__map_tile(c->map, x, y);
            if (tile == NT_TILE_EMPTY) continue;
            /* The row's slab entry time (slab's t0: the side met first), when moving
             * across rows. */
            if (d.y != 0 && ((sy > 0 ? (nt_real)y - h.y : (nt_real)y + 1 + h.y) - p0.y) / d.y > c->best.t) break;
            /* A box moving along a row or a column of POLYGON tiles it only touches or
             * clears (a floor under a box sliding on it, a wall beside a box falling):
             * poly_entry would stop at that axis's half-plane (n . d = 0, not inside)
             * and answer no entry; the same sums say so here. */
            if (polys && nt__tiles[tile].cls == NT_CLASS_POLYGON) {
                const nt_tile_info *ti = &nt__tiles[tile];
                if (d.y == 0) {
                    nt_real ay = p0.y - (nt_real)y;
                    if ((h.y - ti->bounds_min.y) + ay <= 0 || (ti->bounds_max.y + h.y) - ay <= 0) continue;
                } else if (d.x == 0) {
                    nt_real ax = p0.x - (nt_real)x;
                    if ((h.x - ti->bounds_min.x) + ax <= 0 || (ti->bounds_max.x + h.x) - ax <= 0) continue;
                }
            }
            sweep_cell(c, x, y, tile, nt__min(c->best.t, (nt_real)1));
            /* An entry is never before 0 and replaces the best only when earlier: a
             * hit at 0 (a floor met at once) is the answer. */
            if (c->best.t <= 0) return;
        }
    }
}

/* ---- bodies ---- */

typedef struct body_pass {
    caster *c;
    int start;     /* 1: start overlaps, 0: the sweep */
    nt_real *rest;
    int decided;
} body_pass;

static bool body_visit(const nt_world *w, int32_t i, void *vctx)
{
    body_pass *bp = (body_pass *)vctx;
    caster *c = bp->c;
    if (!nt__query_sees(w, i, c->filter)) return true;
    const nt__body *b = &w->bodies[i];
    nt_real ic = w->map->inv_cell;
    nt_vec2 p = nt_v2(b->p.x * ic, b->p.y * ic);
    nt_shape bs = nt__body_shape(b);
    bs.half = nt_v2(bs.half.x * ic, bs.half.y * ic);
    if (b->one_way) {
        /* A one-way platform the shape overlaps at the start, other than resting on
         * it from above, is ignored by the whole cast (as one-way cells are), and so
         * is every one with one_way_off. */
        if (c->filter->one_way_off) return true;
        nt_mtv m;
        if (nt_collide_shapes(c->p0, c->obj, p, bs, &m) && one_way_ignored(m.depth, m.normal, c)) return true;
    }
    if (bp->start) {
        nt_mtv m;
        if (!nt_collide_shapes(c->p0, c->obj, p, bs, &m)) return true;
        int had = c->best.kind;
        if (start_contact(c, m.depth, m.normal, 2, 0, 0, i, bp->rest)) {
            bp->decided = 1;
            return false;
        }
        if (!had && c->best.kind) {
            c->best.lo = nt__sub(p, bs.half);
            c->best.hi = nt__add(p, bs.half);
        }
        return true;
    }
    seg s;
    s.a = c->p0;
    s.d = c->d;
    s.tmax = nt__min(c->best.t, (nt_real)1);
    s.tiny = c->tiny0;
    s.tiny_per_t = c->tiny_per_t;
    nt_real t;
    nt_vec2 n;
    if (body_entry(p, bs, &s, c->sweep, b->one_way, &t, &n) && t < c->best.t) {
        c->best.t = t;
        c->best.n = n;
        c->best.kind = 2;
        c->best.body = i;
        c->best.cx = c->best.cy = 0;
        c->best.lo = nt__sub(p, bs.half);
        c->best.hi = nt__add(p, bs.half);
    }
    return true;
}

/* Can the cast meet a body at all? */
static inline int cast_sees_bodies(const caster *c)
{
    const nt_world *w = c->world;
    return w && w->heads && w->grid_bodies != 0 && c->filter->mask != 0;
}

static void visit_bodies(caster *c, body_pass *bp, nt_vec2 lo, nt_vec2 hi)
{
    const nt_world *w = c->world;
    if (!cast_sees_bodies(c)) return;
    nt_real cell = w->map->cell;
    nt__grid_visit(w, nt__scale(lo, cell), nt__scale(hi, cell), body_visit, bp);
}

/* ---- input, output ---- */

/* Where the shape (at its centre q, cell units) touches what it hit: its support point
 * against the normal, the middle of the shared stretch when a whole side faces it.
 * (NT__INLINE, as the start scan's cell tests: measured cheaper inline; pieces_entry and
 * start_push_depth were not.) */
static NT__INLINE nt_vec2 contact_point(const caster *c, nt_vec2 q)
{
    const hitrec *b = &c->best;
    nt_vec2 h = c->obj.half, n = b->n;
    if (b->kind == 3 || (n.x == 0 && n.y == 0)) return q;
    if (c->obj.type == NT_SHAPE_CIRCLE) return nt_v2(q.x - n.x * h.x, q.y - n.y * h.x);
    nt_vec2 p;
    if (n.x == 0) {
        nt_real lo = nt__max(q.x - h.x, b->lo.x), hi = nt__min(q.x + h.x, b->hi.x);
        p = nt_v2(lo <= hi ? (nt_real)0.5 * (lo + hi) : q.x, n.y < 0 ? q.y + h.y : q.y - h.y);
    } else if (n.y == 0) {
        nt_real lo = nt__max(q.y - h.y, b->lo.y), hi = nt__min(q.y + h.y, b->hi.y);
        p = nt_v2(n.x < 0 ? q.x + h.x : q.x - h.x, lo <= hi ? (nt_real)0.5 * (lo + hi) : q.y);
    } else {
        p = nt_v2(n.x < 0 ? q.x + h.x : q.x - h.x, n.y < 0 ? q.y + h.y : q.y - h.y);
    }
    return p;
}

/* Are the cells [x0, x1] x [y0, y1] all EMPTY cells of the map? One open3 bit per
 * 3 x 3 block; no (the long way) near the map's edge or for a large range. */
static int cells_empty(const nt_map *map, int x0, int y0, int x1, int y1)
{
    if (x1 - x0 > 8 || y1 - y0 > 8) return 0;
    for (int y = y0 + 1; y - 1 <= y1; y += 3)
        for (int x = x0 + 1; x - 1 <= x1; x += 3)
            if (!nt__map_open3(map, x, y)) return 0;
    return 1;
}

/* The whole cast. Returns 1 on a hit (c->best). */
static int run_cast(caster *c)
{
    /* Every cell the start and the sweep can look at (the start box and the swept
     * box, obj being at least the swept shape) EMPTY: neither finds anything there. */
    int tiles = c->tiles;
    if (tiles) {
        nt_vec2 h = c->obj.half, p1 = nt__add(c->p0, c->d);
        c->rx0 = nt__floor_int(nt__min(c->p0.x, p1.x) - h.x), c->ry0 = nt__floor_int(nt__min(c->p0.y, p1.y) - h.y);
        c->rx1 = nt__floor_int(nt__max(c->p0.x, p1.x) + h.x), c->ry1 = nt__floor_int(nt__max(c->p0.y, p1.y) + h.y);
        tiles = !cells_empty(c->map, c->rx0, c->ry0, c->rx1, c->ry1);
    }
    /* Nothing to meet (no tile there, no body to see): the end, as the passes below
     * would find. */
    int bodies = cast_sees_bodies(c);
    if (!tiles && !bodies) return 0;
    /* Rounding: of the start's coordinates, and of the way travelled (a long cast
     * must not make what is near the start look shallow). The start's allowance
     * covers where earlier moves left the shape against the surfaces they stopped it
     * at: 16 units in the last place of its coordinates (cells) up to 256 cells from
     * the origin, at least that much (4.9e-4 cell) beyond, and 4 units where that is
     * more (from 1,024 cells: 2e-3 cell at 4,096). Growing with 16 units, it was
     * 7.8e-3 cell there (the resting limit tol twice that): casts missed shallow hits
     * at the end of their way and a character stopped on slopes (tests/test_far.c). */
    nt_real mag0 = nt__max(nt__fabs(c->p0.x), nt__fabs(c->p0.y));
    c->tiny0 = nt__max((nt_real)16 * NT_REAL_EPS * nt__clamp(mag0, (nt_real)1, (nt_real)256), (nt_real)4 * NT_REAL_EPS * mag0);
    c->tiny_per_t = (nt_real)16 * NT_REAL_EPS * (nt__fabs(c->d.x) + nt__fabs(c->d.y));
    c->tol = nt__max((nt_real)NT_CAST_START_TOLERANCE, 2 * c->tiny0);
    c->best.t = 2;
    c->best.kind = 0;
    c->best.n = nt_v2(0, 0);
    c->best.cx = c->best.cy = 0;
    c->best.body = -1;
    c->best.lo = c->best.hi = nt_v2(0, 0);
    nt_real rest = 0;
    if (tiles && start_tiles(c, &rest)) return 1;
    body_pass bp;
    bp.c = c;
    bp.rest = &rest;
    bp.decided = 0;
    bp.start = 1;
    if (bodies) visit_bodies(c, &bp, nt__sub(c->p0, c->obj.half), nt__add(c->p0, c->obj.half));
    if (bp.decided) return 1;
    if (c->best.kind) return 1; /* approaching a surface it rests on */
    /* Resting: sweep a shape smaller by the resting depth (and rounding). */
    c->sweep = c->obj;
    if (rest > 0) {
        nt_real k = rest + c->tiny0;
        c->sweep.half = nt_v2(nt__max(c->obj.half.x - k, 0), nt__max(c->obj.half.y - k, 0));
    }
    if (tiles) sweep_tiles(c);
    bp.start = 0;
    if (bodies) {
        nt_vec2 p1 = nt__add(c->p0, c->d);
        nt_vec2 lo = nt_v2(nt__min(c->p0.x, p1.x) - c->obj.half.x, nt__min(c->p0.y, p1.y) - c->obj.half.y);
        nt_vec2 hi = nt_v2(nt__max(c->p0.x, p1.x) + c->obj.half.x, nt__max(c->p0.y, p1.y) + c->obj.half.y);
        visit_bodies(c, &bp, lo, hi);
    }
    return c->best.kind != 0 && c->best.t <= 1;
}

/* Every field run_cast reads is set here or by the caller (world, filter, tiles,
 * one_way_cells); run_cast sets sweep and best. shape_known: the caller checked the
 * shape with nt__cast_shape_ok. */
static inline int setup(caster *c, const nt_map *map, nt_vec2 pos, const nt_shape *shape_p, nt_vec2 translation,
                        int shape_known)
{
    nt_shape shape = *shape_p;
    if (!map || (!shape_known && !nt__cast_shape_ok(shape, map->cell))) return 0;
    nt_real ic = map->inv_cell;
    c->map = map;
    c->world = NULL;
    c->filter = NULL;
    c->start = NULL;
    c->tiles = 1;
    c->one_way_cells = 0;
    c->p0 = nt_v2(pos.x * ic, pos.y * ic);
    c->d = nt_v2(translation.x * ic, translation.y * ic);
    c->obj = shape;
    c->obj.half = nt_v2(shape.half.x * ic, shape.half.y * ic);
    c->pos = pos;
    c->shape = shape;
    /* Finite sums: then pos and translation are finite too (a NaN or an infinity among
     * them makes its sum NaN or infinite, ic being finite and positive). */
    return nt__finite(c->p0.x + c->d.x) && nt__finite(c->p0.y + c->d.y);
}

bool nt_map_cast_shape(const nt_map *map, nt_vec2 pos, nt_shape shape, nt_vec2 translation, nt_shape_cast_hit *out)
{
    nt_shape_cast_hit r;
    memset(&r, 0, sizeof r);
    if (out) *out = r;
    caster c;
    if (!setup(&c, map, pos, &shape, translation, 0)) return false;
    if (!run_cast(&c)) return false;
    nt_vec2 q = nt__add(c.p0, nt__scale(c.d, c.best.t));
    r.fraction = c.best.t;
    r.normal = c.best.n;
    r.point = nt__scale(contact_point(&c, q), map->cell);
    r.cell_x = c.best.cx;
    r.cell_y = c.best.cy;
    if (out) *out = r;
    return true;
}

bool nt_world_cast_shape(const nt_world *world, nt_vec2 pos, nt_shape shape, nt_vec2 translation,
                         nt_query_filter filter, nt_world_shape_hit *out)
{
    nt_world_shape_hit scratch;
    if (!world) return nt__world_cast_shape(world, pos, &shape, translation, &filter, 0, NULL, out ? out : &scratch);
    NT__LOCK(world); /* the filter's accept callback */
    bool hit = nt__world_cast_shape(world, pos, &shape, translation, &filter, 0, NULL, out ? out : &scratch);
    NT__UNLOCK(world);
    return hit;
}

/* The result is written in place, zero until a hit is known (a copy of a struct just
 * written field by field stalls on store forwarding). */
bool nt__world_cast_shape(const nt_world *world, nt_vec2 pos, const nt_shape *shape, nt_vec2 translation,
                          const nt_query_filter *filter, int shape_known, nt__cast_start *start, nt_world_shape_hit *out)
{
    nt_world_shape_hit *r = out;
    memset(r, 0, sizeof *r);
    if (!world) return false;
    caster c;
    if (!setup(&c, world->map, pos, shape, translation, shape_known)) return false;
    c.world = world;
    c.filter = filter;
    c.start = start;
    c.tiles = filter->tiles;
    c.one_way_cells = world->oneway_count > 0;
    if (!run_cast(&c)) return false;
    nt_vec2 q = nt__add(c.p0, nt__scale(c.d, c.best.t));
    r->fraction = c.best.t;
    r->normal = c.best.n;
    r->point = nt__scale(contact_point(&c, q), world->map->cell);
    if (c.best.body >= 0) {
        r->body.index1 = c.best.body + 1;
        r->body.world0 = world->tag;
        r->body.generation = world->bodies[c.best.body].generation;
    } else {
        r->cell_x = c.best.cx;
        r->cell_y = c.best.cy;
    }
    return true;
}
