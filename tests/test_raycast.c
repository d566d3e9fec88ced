/* Ray casts: nt_tile_raycast and nt_map_raycast against independent references.
 *
 * The reference geometry below is written from the notes' shape table (canonical `pn`
 * shapes, mirrored x -> 1-x when signx < 0 and y -> 1-y when signy > 0), in double,
 * without using the library's tables or nt_tile_contains_point. First entries are
 * found by sampling the segment finely and bisecting the first outside->inside step;
 * expected normals come from the boundary piece the hit point lies on. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ntile/ntile.h"
#include "ref.h"

/* ------------------------------------------------------------------------------ */
/* Reference tile geometry (double).                                                */

enum { F_EMPTY, F_FULL, F_45, F_CONCAVE, F_CONVEX, F_22S, F_22B, F_67S, F_67B, F_HALF };

typedef struct shape_ref {
    int fam;
    int sx, sy;       /* normal signs of the orientation (pn = +1, -1) */
    double x0, y0, x1, y1; /* HALF / FULL: the solid rectangle */
} shape_ref;

static shape_ref shape_of(int id)
{
    shape_ref s;
    memset(&s, 0, sizeof s);
    s.sx = 1;
    s.sy = -1;
    if (id == 0) {
        s.fam = F_EMPTY;
        return s;
    }
    if (id == 1 || id >= 30) {
        s.fam = id == 1 ? F_FULL : F_HALF;
        s.x0 = 0, s.y0 = 0, s.x1 = 1, s.y1 = 1;
        if (id == 30) s.y0 = 0.5; /* HALFd: bottom half */
        if (id == 31) s.x0 = 0.5; /* HALFr: right half */
        if (id == 32) s.y1 = 0.5; /* HALFu: top half */
        if (id == 33) s.x1 = 0.5; /* HALFl: left half */
        return s;
    }
    static const int fams[7] = {F_45, F_CONCAVE, F_CONVEX, F_22S, F_22B, F_67S, F_67B};
    int k = (id - 2) / 4, o = (id - 2) % 4; /* o: pn, nn, np, pp */
    s.fam = fams[k];
    s.sx = (o == 0 || o == 3) ? 1 : -1;
    s.sy = (o == 0 || o == 1) ? -1 : 1;
    return s;
}

/* Into / out of the canonical pn frame (an involution). */
static void canon(const shape_ref *s, double x, double y, double *X, double *Y)
{
    *X = s->sx < 0 ? 1 - x : x;
    *Y = s->sy > 0 ? 1 - y : y;
}

/* Strictly inside the solid. */
static int ref_inside(int id, double x, double y)
{
    shape_ref s = shape_of(id);
    if (s.fam == F_EMPTY) return 0;
    if (s.fam == F_FULL || s.fam == F_HALF) return x > s.x0 && x < s.x1 && y > s.y0 && y < s.y1;
    double X, Y;
    canon(&s, x, y, &X, &Y);
    switch (s.fam) {
    case F_45: return X > 0 && Y < 1 && Y > X;
    case F_CONCAVE: return X > 0 && X < 1 && Y > 0 && Y < 1 && (X - 1) * (X - 1) + Y * Y > 1;
    case F_CONVEX: return X > 0 && Y < 1 && X * X + (Y - 1) * (Y - 1) < 1;
    case F_22S: return X > 0 && Y < 1 && Y > 0.5 + X / 2;
    case F_22B: return X > 0 && X < 1 && Y < 1 && Y > X / 2;
    case F_67S: return X > 0 && Y < 1 && Y > 2 * X;
    case F_67B: return X > 0 && Y > 0 && Y < 1 && Y > 2 * X - 1;
    }
    return 0;
}

/* Boundary pieces in the canonical frame: segments with outward normals, or an arc. */
typedef struct piece {
    int arc;         /* 0 segment, 1 convex arc, 2 concave arc */
    double ax, ay, bx, by;
    double nx, ny;
} piece;

static int canon_pieces(const shape_ref *s, piece *p)
{
    const double r5 = sqrt(5.0), r2 = sqrt(2.0);
    int n = 0;
#define SEG(a, b, c, d, e, f) (p[n].arc = 0, p[n].ax = a, p[n].ay = b, p[n].bx = c, p[n].by = d, p[n].nx = e, p[n].ny = f, n++)
    switch (s->fam) {
    case F_FULL:
    case F_HALF:
        SEG(s->x0, s->y0, s->x0, s->y1, -1, 0);
        SEG(s->x1, s->y0, s->x1, s->y1, 1, 0);
        SEG(s->x0, s->y0, s->x1, s->y0, 0, -1);
        SEG(s->x0, s->y1, s->x1, s->y1, 0, 1);
        break;
    case F_45:
        SEG(0, 0, 0, 1, -1, 0);
        SEG(0, 1, 1, 1, 0, 1);
        SEG(0, 0, 1, 1, 1 / r2, -1 / r2);
        break;
    case F_CONCAVE:
    case F_CONVEX:
        SEG(0, 0, 0, 1, -1, 0);
        SEG(0, 1, 1, 1, 0, 1);
        p[n].arc = s->fam == F_CONVEX ? 1 : 2;
        p[n].ax = s->fam == F_CONVEX ? 0 : 1; /* centre */
        p[n].ay = s->fam == F_CONVEX ? 1 : 0;
        n++;
        break;
    case F_22S:
        SEG(0, 0.5, 0, 1, -1, 0);
        SEG(0, 1, 1, 1, 0, 1);
        SEG(0, 0.5, 1, 1, 1 / r5, -2 / r5);
        break;
    case F_22B:
        SEG(0, 0, 0, 1, -1, 0);
        SEG(0, 1, 1, 1, 0, 1);
        SEG(1, 0.5, 1, 1, 1, 0);
        SEG(0, 0, 1, 0.5, 1 / r5, -2 / r5);
        break;
    case F_67S:
        SEG(0, 0, 0, 1, -1, 0);
        SEG(0, 1, 0.5, 1, 0, 1);
        SEG(0, 0, 0.5, 1, 2 / r5, -1 / r5);
        break;
    case F_67B:
        SEG(0, 0, 0, 1, -1, 0);
        SEG(0, 1, 1, 1, 0, 1);
        SEG(0, 0, 0.5, 0, 0, -1);
        SEG(0.5, 0, 1, 1, 2 / r5, -1 / r5);
        break;
    }
#undef SEG
    return n;
}

static double seg_dist(double px, double py, double ax, double ay, double bx, double by)
{
    double dx = bx - ax, dy = by - ay;
    double u = ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy);
    if (u < 0) u = 0;
    if (u > 1) u = 1;
    double qx = ax + u * dx - px, qy = ay + u * dy - py;
    return sqrt(qx * qx + qy * qy);
}

/* Distance from (x, y) to the boundary, the normal of the nearest piece, and the
 * distance to the second-nearest piece (small = near a vertex: normal ambiguous). */
static double ref_boundary(int id, double x, double y, double *nx, double *ny, double *second, double *n2x,
                           double *n2y)
{
    shape_ref s = shape_of(id);
    piece p[4];
    int np = canon_pieces(&s, p);
    int mirror = s.fam != F_FULL && s.fam != F_HALF;
    double X = x, Y = y;
    if (mirror) canon(&s, x, y, &X, &Y);
    double best = 1e300, sec = 1e300, bnx = 0, bny = 0, snx = 0, sny = 0;
    for (int i = 0; i < np; i++) {
        double d, qx, qy;
        if (p[i].arc) {
            /* the quarter of the circle inside the cell; its ends are (0,0) and (1,1) */
            double vx = X - p[i].ax, vy = Y - p[i].ay, l = sqrt(vx * vx + vy * vy);
            int in_quarter = p[i].arc == 1 ? (vx >= 0 && vy <= 0) : (vx <= 0 && vy >= 0);
            if (in_quarter && l > 0) {
                d = fabs(l - 1);
                qx = vx / l, qy = vy / l;
            } else {
                double d0 = hypot(X, Y), d1 = hypot(X - 1, Y - 1);
                double ex = d0 < d1 ? 0 : 1, ey = ex;
                d = d0 < d1 ? d0 : d1;
                qx = ex - p[i].ax, qy = ey - p[i].ay; /* the normal at that end */
            }
            if (p[i].arc == 2) qx = -qx, qy = -qy;
        } else {
            d = seg_dist(X, Y, p[i].ax, p[i].ay, p[i].bx, p[i].by);
            qx = p[i].nx, qy = p[i].ny;
        }
        if (mirror) {
            if (s.sx < 0) qx = -qx;
            if (s.sy > 0) qy = -qy;
        }
        if (d < best) {
            sec = best, snx = bnx, sny = bny;
            best = d, bnx = qx, bny = qy;
        } else if (d < sec) {
            sec = d, snx = qx, sny = qy;
        }
    }
    if (nx) *nx = bnx, *ny = bny;
    if (second) *second = sec;
    if (n2x) *n2x = snx, *n2y = sny;
    return best;
}

/* ------------------------------------------------------------------------------ */
/* Helpers.                                                                         */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double rnd(void) /* [0, 1) */
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}
static double rnd_in(double a, double b) { return a + (b - a) * rnd(); }

#define TOL_T 1e-4
#define ANY 99999

static const char *tname(int id) { return nt_tile_get_info(id)->name; }

static int cast_tile(int id, double px, double py, double dx, double dy, double tmax, double *t, double *nx,
                     double *ny)
{
    nt_real tt = -1;
    nt_vec2 n = nt_v2(7, 7);
    bool hit = nt_tile_raycast(id, nt_v2((nt_real)px, (nt_real)py), nt_v2((nt_real)dx, (nt_real)dy), (nt_real)tmax,
                               &tt, &n);
    *t = tt;
    *nx = n.x;
    *ny = n.y;
    return hit;
}

/* Reference first entry of the segment into the tile: sampling + bisection.
 * Returns 1 with *t; *tex = a point of the interior run's end (for chord length). */
static int ref_first_entry(int id, double px, double py, double dx, double dy, double tmax, double *t,
                           double *tex)
{
    const int N = 4000;
    if (ref_inside(id, px, py)) {
        *t = 0;
        *tex = 0;
        return 1;
    }
    for (int i = 1; i <= N; i++) {
        double ti = tmax * i / N;
        if (ref_inside(id, px + ti * dx, py + ti * dy)) {
            double lo = tmax * (i - 1) / N, hi = ti;
            for (int k = 0; k < 80; k++) {
                double mid = 0.5 * (lo + hi);
                if (ref_inside(id, px + mid * dx, py + mid * dy)) hi = mid;
                else lo = mid;
            }
            *t = hi;
            /* end of the run */
            double a = ti, b = ti;
            int j = i;
            while (j < N && ref_inside(id, px + tmax * (j + 1) / N * dx, py + tmax * (j + 1) / N * dy)) j++;
            b = tmax * (j + 1) / N;
            if (j >= N) b = tmax;
            a = tmax * j / N;
            for (int k = 0; k < 80 && j < N; k++) {
                double mid = 0.5 * (a + b);
                if (ref_inside(id, px + mid * dx, py + mid * dy)) a = mid;
                else b = mid;
            }
            *tex = a;
            return 1;
        }
    }
    return 0;
}

/* Some point of [t0, t1] strictly inside (fine sampling). */
static int inside_somewhere(int id, double px, double py, double dx, double dy, double t0, double t1)
{
    const int N = 20000;
    for (int i = 0; i <= N; i++) {
        double t = t0 + (t1 - t0) * i / N;
        if (ref_inside(id, px + t * dx, py + t * dy)) return 1;
    }
    return 0;
}

/* ------------------------------------------------------------------------------ */
/* The reference itself (sanity: the shapes match the notes' vertices and normals). */

static void test_reference_geometry(void **state)
{
    (void)state;
    /* A few hand facts straight from the table in the notes. */
    assert_true(ref_inside(2, 0.1, 0.9));  /* 45DEGpn: solid toward (0,1) */
    assert_false(ref_inside(2, 0.9, 0.1));
    assert_true(ref_inside(5, 0.1, 0.1));  /* 45DEGpp: solid toward (0,0) */
    assert_true(ref_inside(3, 0.9, 0.9));  /* 45DEGnn: solid toward (1,1) */
    assert_true(ref_inside(4, 0.9, 0.1));  /* 45DEGnp: solid toward (1,0) */
    assert_true(ref_inside(6, 0.05, 0.95)); /* CONCAVEpn: corner (0,1) solid */
    assert_false(ref_inside(6, 0.5, 0.3));  /* inside the disc around (1,0) */
    assert_true(ref_inside(10, 0.3, 0.7));  /* CONVEXpn: quarter disc around (0,1) */
    assert_false(ref_inside(10, 0.9, 0.1));
    assert_true(ref_inside(14, 0.1, 0.9));  /* 22DEGpnS */
    assert_false(ref_inside(14, 0.1, 0.5));
    assert_true(ref_inside(18, 0.9, 0.6));  /* 22DEGpnB */
    assert_false(ref_inside(18, 0.9, 0.4));
    assert_true(ref_inside(22, 0.2, 0.9));  /* 67DEGpnS */
    assert_false(ref_inside(22, 0.3, 0.5));
    assert_true(ref_inside(26, 0.3, 0.1));  /* 67DEGpnB */
    assert_false(ref_inside(26, 0.7, 0.1));
    assert_true(ref_inside(30, 0.5, 0.7));  /* HALFd */
    assert_true(ref_inside(31, 0.7, 0.5));  /* HALFr */
    assert_true(ref_inside(32, 0.5, 0.3));  /* HALFu */
    assert_true(ref_inside(33, 0.3, 0.5));  /* HALFl */
    /* The sloped normals point from the solid to the free side, with the table's signs. */
    for (int id = 2; id < 30; id++) {
        shape_ref s = shape_of(id);
        const nt_tile_info *ti = nt_tile_get_info(id);
        assert_int_equal(ti->signx, s.sx);
        assert_int_equal(ti->signy, s.sy);
    }
    /* Cross-check with the library's point test on random points (not the only reference). */
    int mism = 0;
    for (int id = 0; id < NT_TILE_COUNT; id++)
        for (int i = 0; i < 4000; i++) {
            double x = rnd_in(-0.2, 1.2), y = rnd_in(-0.2, 1.2);
            nt_real fx = (nt_real)x, fy = (nt_real)y;
            int a = ref_inside(id, fx, fy);
            int b = nt_tile_contains_point(id, nt_v2(fx, fy));
            if (a != b && ref_boundary(id, fx, fy, NULL, NULL, NULL, NULL, NULL) > 1e-5) {
                if (mism++ < 5) print_message("contains_point mismatch %s (%g, %g): ref %d lib %d\n", tname(id), x, y, a, b);
            }
        }
    assert_int_equal(mism, 0);
}

/* ------------------------------------------------------------------------------ */
/* Random segments against every tile.                                              */

static void check_tile_ray(int id, double px, double py, double dx, double dy, double tmax, int *hits,
                           int *unverified)
{
    double t, nx, ny;
    int hit = cast_tile(id, px, py, dx, dy, tmax, &t, &nx, &ny);
    /* reference on the values the library actually received */
    px = (nt_real)px, py = (nt_real)py, dx = (nt_real)dx, dy = (nt_real)dy, tmax = (nt_real)tmax;
    double tr, tex;
    int rh = ref_first_entry(id, px, py, dx, dy, tmax, &tr, &tex);
    double len = sqrt(dx * dx + dy * dy);
    if (rh) {
        if (!hit) {
            /* only a sliver thinner than rounding may be missed */
            double depth = 0;
            for (int k = 0; k <= 64; k++) {
                double tt = tr + (tex - tr) * k / 64;
                double d = ref_boundary(id, px + tt * dx, py + tt * dy, NULL, NULL, NULL, NULL, NULL);
                if (d > depth) depth = d;
            }
            if (depth > 1e-5)
                fail_msg("%s: missed p=(%.9g,%.9g) d=(%.9g,%.9g) tmax=%.9g, ref t=%.9g depth %g", tname(id), px, py,
                         dx, dy, tmax, tr, depth);
            (*unverified)++;
            return;
        }
        double tol = TOL_T;
        if (!NT_REAL_IS_DOUBLE && (tex - tr) * len < 1e-2) tol = 1e-3; /* near-tangent chord in float */
        if (fabs(t - tr) * (len > 1 ? len : 1) > tol) {
            /* an earlier sliver that sampling stepped over? */
            if (!(t < tr && inside_somewhere(id, px, py, dx, dy, t, t + 1e-3)))
                fail_msg("%s: t=%.9g ref %.9g p=(%.9g,%.9g) d=(%.9g,%.9g) tmax=%.9g", tname(id), t, tr, px, py, dx, dy,
                         tmax);
            (*unverified)++;
            return;
        }
        (*hits)++;
    } else {
        if (hit) {
            double hi = t + 1e-3 < tmax ? t + 1e-3 : tmax;
            if (!inside_somewhere(id, px, py, dx, dy, t, hi)) {
                double bd = ref_boundary(id, px + t * dx, py + t * dy, NULL, NULL, NULL, NULL, NULL);
                if (bd > 1e-5)
                    fail_msg("%s: false hit t=%.9g p=(%.9g,%.9g) d=(%.9g,%.9g) tmax=%.9g", tname(id), t, px, py, dx,
                             dy, tmax);
            }
            (*unverified)++;
        }
        return;
    }
    /* Normals. */
    if (tr == 0) {
        assert_true(t == 0);
        if (!(nx == 0 && ny == 0)) fail_msg("%s: start inside but normal (%g,%g)", tname(id), nx, ny);
        return;
    }
    double hx = px + t * dx, hy = py + t * dy;
    double enx, eny, sec, e2x, e2y;
    ref_boundary(id, hx, hy, &enx, &eny, &sec, &e2x, &e2y);
    double err1 = hypot(nx - enx, ny - eny), err2 = hypot(nx - e2x, ny - e2y);
    int ok = err1 < 2e-3 || (sec < 1e-3 && err2 < 2e-3);
    if (!ok)
        fail_msg("%s: normal (%.6g,%.6g), expected (%.6g,%.6g) at (%.6g,%.6g); p=(%.9g,%.9g) d=(%.9g,%.9g) t=%.9g",
                 tname(id), nx, ny, enx, eny, hx, hy, px, py, dx, dy, t);
    assert_true(nx * dx + ny * dy <= 1e-6);
}

static void test_tile_random(void **state)
{
    (void)state;
    rng_state = 12345;
    for (int id = 1; id < NT_TILE_COUNT; id++) {
        int hits = 0, unverified = 0;
        for (int i = 0; i < 1500; i++) {
            double px = rnd_in(-0.6, 1.6), py = rnd_in(-0.6, 1.6);
            double qx = rnd_in(-0.6, 1.6), qy = rnd_in(-0.6, 1.6);
            double tmax = (i & 1) ? 1.0 : rnd_in(0.1, 1.5);
            check_tile_ray(id, px, py, qx - px, qy - py, tmax, &hits, &unverified);
        }
        /* short segments from near the surface */
        for (int i = 0; i < 500; i++) {
            double px = rnd_in(0, 1), py = rnd_in(0, 1);
            double a = rnd_in(0, 6.283185307179586), l = rnd_in(0.001, 0.3);
            check_tile_ray(id, px, py, l * cos(a), l * sin(a), 1.0, &hits, &unverified);
        }
        if (hits < 300 || unverified > 10)
            fail_msg("%s: %d verified hits, %d unverified", tname(id), hits, unverified);
    }
}

/* ------------------------------------------------------------------------------ */
/* Hand-computed tile cases.                                                        */

#define ASSERT_NEAR(a, b, tol) \
    do { \
        double a_ = (a), b_ = (b); \
        if (!(fabs(a_ - b_) <= (tol))) fail_msg("%s = %.9g, expected %.9g", #a, a_, b_); \
    } while (0)

static void expect_hit(int id, double px, double py, double dx, double dy, double tmax, double et, double enx,
                       double eny)
{
    double t, nx, ny;
    if (!cast_tile(id, px, py, dx, dy, tmax, &t, &nx, &ny))
        fail_msg("%s: no hit for p=(%g,%g) d=(%g,%g), expected t=%g", tname(id), px, py, dx, dy, et);
    ASSERT_NEAR(t, et, 1e-6);
    ASSERT_NEAR(nx, enx, 1e-6);
    ASSERT_NEAR(ny, eny, 1e-6);
}

static void expect_miss(int id, double px, double py, double dx, double dy, double tmax)
{
    double t, nx, ny;
    if (cast_tile(id, px, py, dx, dy, tmax, &t, &nx, &ny))
        fail_msg("%s: unexpected hit t=%g n=(%g,%g) for p=(%g,%g) d=(%g,%g)", tname(id), t, nx, ny, px, py, dx, dy);
}

/* Mirror a canonical (pn) point / direction / normal into tile id's orientation. */
static void mir(int id, double *x, double *y, int is_vec)
{
    shape_ref s = shape_of(id);
    if (s.sx < 0) *x = is_vec ? -*x : 1 - *x;
    if (s.sy > 0) *y = is_vec ? -*y : 1 - *y;
}

static void test_tile_grazing(void **state)
{
    (void)state;
    /* Along every edge of FULL, inside the edge and beyond it: no hit. */
    expect_miss(1, -0.5, 0, 2, 0, 1);
    expect_miss(1, 0.2, 0, 0.5, 0, 1);
    expect_miss(1, 0, -0.5, 0, 2, 1);
    expect_miss(1, 1, 1.5, 0, -2, 1);
    expect_miss(1, 1.5, 1, -2, 0, 1);
    /* Along the HALF tiles' inner faces. */
    expect_miss(30, -1, 0.5, 3, 0, 1);
    expect_miss(31, 0.5, -1, 0, 3, 1);
    expect_miss(32, 2, 0.5, -3, 0, 1);
    expect_miss(33, 0.5, 2, 0, -3, 1);
    /* Along each hypotenuse, extended past both ends, every orientation. */
    struct { int base; double ax, ay, bx, by; } hyp[] = {
        {2, 0, 0, 1, 1}, {14, 0, 0.5, 1, 1}, {18, 0, 0, 1, 0.5}, {22, 0, 0, 0.5, 1}, {26, 0.5, 0, 1, 1},
    };
    for (int h = 0; h < 5; h++)
        for (int o = 0; o < 4; o++) {
            int id = hyp[h].base + o;
            double ax = hyp[h].ax, ay = hyp[h].ay, bx = hyp[h].bx, by = hyp[h].by;
            mir(id, &ax, &ay, 0);
            mir(id, &bx, &by, 0);
            double dx = bx - ax, dy = by - ay;
            expect_miss(id, ax - dx, ay - dy, 3 * dx, 3 * dy, 1);
            expect_miss(id, ax + 0.25 * dx, ay + 0.25 * dy, 0.5 * dx, 0.5 * dy, 1);
        }
    /* Touching a vertex only. */
    expect_miss(1, -1, 1, 2, -2, 1);       /* x + y = 0 touches (0,0) */
    expect_miss(1, 2, 0, -2, 2, 1.0);      /* x + y = 2 touches (1,1) */
    expect_miss(2, -0.5, 0.5, 1, -1, 1);   /* 45DEGpn: y = -x touches (0,0) */
    expect_miss(2, 0.5, 1.5, 1, -1, 1);    /* 45DEGpn: x + y = 2 touches (1,1) */
    expect_miss(10, -1, 0, 2, 0, 1);       /* CONVEXpn: y = 0 touches the arc at (0,0) */
    expect_miss(10, 1, -1, 0, 3, 1);       /* CONVEXpn: x = 1 touches the arc at (1,1) */
    expect_miss(10, 0.5, 1 - sqrt(2.0) + 0.5, 1, 1, 1.0); /* tangent to the arc at 45 degrees */
    /* Ending exactly on the surface is not entering it. */
    expect_miss(1, 0.5, -1, 0, 1, 1);
    expect_miss(2, 1, 0, -1, 1, 0.5);      /* reaches the hypotenuse at (0.5,0.5) with t = tmax */
    /* Leaving, or moving along the boundary from a surface point. */
    expect_miss(1, 0.5, 0, 0, -1, 1);
    expect_miss(6, 0.5, 1, 0, 1, 1);
}

static void test_tile_known_hits(void **state)
{
    (void)state;
    const double s2 = 1 / sqrt(2.0), s5 = 1 / sqrt(5.0);
    /* Each sloped tile: from outside along -normal through the middle of the slope. */
    struct { int base; double mx, my, nx, ny; } slope[] = {
        {2, 0.5, 0.5, s2, -s2},  {14, 0.5, 0.75, s5, -2 * s5}, {18, 0.5, 0.25, s5, -2 * s5},
        {22, 0.25, 0.5, 2 * s5, -s5}, {26, 0.75, 0.5, 2 * s5, -s5},
    };
    for (int h = 0; h < 5; h++)
        for (int o = 0; o < 4; o++) {
            int id = slope[h].base + o;
            double mx = slope[h].mx, my = slope[h].my, nx = slope[h].nx, ny = slope[h].ny;
            mir(id, &mx, &my, 0);
            mir(id, &nx, &ny, 1);
            /* the table agrees with the analytic normal */
            const nt_tile_info *ti = nt_tile_get_info(id);
            ASSERT_NEAR(ti->normal.x, nx, 1e-6);
            ASSERT_NEAR(ti->normal.y, ny, 1e-6);
            expect_hit(id, mx + 0.2 * nx, my + 0.2 * ny, -0.4 * nx, -0.4 * ny, 1, 0.5, nx, ny);
            /* oblique: 30 degrees off the normal, hitting the same point at t = 0.25 */
            double c = cos(0.5), sn = sin(0.5);
            double vx = -(nx * c - ny * sn), vy = -(nx * sn + ny * c);
            expect_hit(id, mx - 0.1 * vx, my - 0.1 * vy, 0.4 * vx, 0.4 * vy, 1, 0.25, nx, ny);
        }
    /* CONCAVE: from the arc's centre into the hollow, hitting the arc at distance 1,
     * normal toward the centre; CONVEX: from the far corner toward the centre. */
    for (int o = 0; o < 4; o++) {
        int cv = 6 + o, cx = 10 + o;
        double ax = 1, ay = 0, bx = 0, by = 1; /* pn: centre (1,0) -> opposite corner */
        mir(cv, &ax, &ay, 0);
        mir(cv, &bx, &by, 0);
        double dx = bx - ax, dy = by - ay;
        expect_hit(cv, ax, ay, dx, dy, 1, s2, -dx * s2, -dy * s2); /* toward the centre = -d/|d| */
        /* CONVEXpn centre (0,1): from (1,0) toward it, hits at t = 1 - 1/sqrt2 */
        double qx = 1, qy = 0, ex = 0, ey = 1;
        mir(cx, &qx, &qy, 0);
        mir(cx, &ex, &ey, 0);
        double ux = ex - qx, uy = ey - qy;
        expect_hit(cx, qx, qy, ux, uy, 1, 1 - s2, -ux * s2, -uy * s2);
        /* CONCAVE: a ray across the hollow parallel to a straight side hits the far side. */
        double p0x = 0.9, p0y = 0.95, d0x = -1.8, d0y = 0; /* pn: along y = 0.95 going left */
        mir(cv, &p0x, &p0y, 0);
        mir(cv, &d0x, &d0y, 1);
        /* pn: leaves the disc around (1,0) at x = 1 - sqrt(1 - 0.95^2) */
        double xe = 1 - sqrt(1 - 0.95 * 0.95);
        double te = (0.9 - xe) / 1.8;
        double ncx = 1 - xe, ncy = -0.95; /* toward the centre (1,0) */
        double l = hypot(ncx, ncy);
        ncx /= l, ncy /= l;
        mir(cv, &ncx, &ncy, 1);
        expect_hit(cv, p0x, p0y, d0x, d0y, 1, te, ncx, ncy);
    }
    /* Straight faces. */
    expect_hit(1, 0.5, -1, 0, 4, 1, 0.25, 0, -1);
    expect_hit(1, -1, 0.5, 4, 0, 1, 0.25, -1, 0);
    expect_hit(1, 2, 0.5, -4, 0, 1, 0.25, 1, 0);
    expect_hit(1, 0.5, 2, 0, -4, 1, 0.25, 0, 1);
    expect_hit(30, 0.3, 0, 0, 1, 1, 0.5, 0, -1);    /* HALFd top face at y = 0.5 */
    expect_hit(31, 0, 0.3, 1, 0, 1, 0.5, -1, 0);    /* HALFr */
    expect_hit(32, 0.3, 1, 0, -1, 1, 0.5, 0, 1);    /* HALFu */
    expect_hit(33, 1, 0.3, -1, 0, 1, 0.5, 1, 0);    /* HALFl */
    expect_hit(26, 0.25, -1, 0, 2, 1, 0.5, 0, -1);  /* 67DEGpnB's short top face */
    expect_hit(18, 1.5, 0.75, -1, 0, 1, 0.5, 1, 0); /* 22DEGpnB's short right face */
    /* Starting inside: t = 0, normal (0,0); zero-length inside / outside. */
    for (int id = 1; id < NT_TILE_COUNT; id++) {
        double x = 0.5, y = 0.5;
        for (int k = 0; k < 1000 && !ref_inside(id, x, y); k++) x = rnd(), y = rnd();
        expect_hit(id, x, y, 0.3, -0.2, 1, 0, 0, 0);
        expect_hit(id, x, y, 0, 0, 1, 0, 0, 0);
        expect_hit(id, x, y, 0.3, -0.2, 0, 0, 0, 0);
    }
    expect_miss(2, 0.9, 0.1, 0, 0, 1);
    expect_miss(6, 0.5, 0.3, 0, 0, 1);
    expect_miss(1, 0, 0.5, 0, 0, 1); /* a point on the boundary is not inside */
    /* Starting on the boundary and going in: t = 0 with that face's normal. */
    expect_hit(1, 0.5, 0, 0, 1, 1, 0, 0, -1);
    expect_hit(2, 0.5, 0.5, -1, 1, 1, 0, s2, -s2);
    /* Through a vertex into the interior: one of the two faces there. */
    {
        double t, nx, ny;
        assert_true(cast_tile(1, -1, -1, 3, 3, 1, &t, &nx, &ny));
        ASSERT_NEAR(t, 1.0 / 3, 1e-6);
        assert_true((nx == -1 && ny == 0) || (nx == 0 && ny == -1));
        assert_true(cast_tile(2, -1, 1.5, 2, -1, 1, &t, &nx, &ny)); /* through (0,1) */
        ASSERT_NEAR(t, 0.5, 1e-6);
        assert_true((nx == -1 && ny == 0) || (nx == 0 && ny == 1));
    }
    /* tmax short of the surface. */
    expect_miss(1, 0.5, -1, 0, 4, 0.2);
    /* Invalid input. */
    double t, nx, ny;
    assert_false(cast_tile(0, 0.5, 0.5, 1, 0, 1, &t, &nx, &ny));
    assert_false(cast_tile(34, 0.5, 0.5, 1, 0, 1, &t, &nx, &ny));
    assert_false(cast_tile(-1, 0.5, 0.5, 1, 0, 1, &t, &nx, &ny));
    assert_false(cast_tile(1, 0.5, 0.5, 1, 0, -1, &t, &nx, &ny));
    assert_false(cast_tile(1, NAN, 0.5, 1, 0, 1, &t, &nx, &ny));
    assert_false(cast_tile(1, 0.5, 0.5, INFINITY, 0, 1, &t, &nx, &ny));
    assert_false(cast_tile(1, 0.5, 0.5, 1, 0, NAN, &t, &nx, &ny));
    assert_true(nt_tile_raycast(1, nt_v2(0.5, -1), nt_v2(0, 2), 1, NULL, NULL));
}

/* ------------------------------------------------------------------------------ */
/* Map ray casts.                                                                   */

typedef struct tmap {
    nt_map *m;
    int w, h;
    double cell;
    uint8_t tiles[64 * 64];
} tmap;

static void tmap_init(tmap *t, int w, int h, double cell)
{
    nt_map_def def = nt_default_map_def();
    def.width = w;
    def.height = h;
    def.cell_size = (nt_real)cell;
    t->w = w;
    t->h = h;
    t->cell = cell;
    memset(t->tiles, 0, sizeof t->tiles);
    assert_int_equal(nt_map_create(&def, &t->m), NT_OK);
}

static void tmap_set(tmap *t, int x, int y, int id)
{
    t->tiles[y * t->w + x] = (uint8_t)id;
    assert_int_equal(nt_map_set_tile(t->m, x, y, id), NT_OK);
}

static int tmap_tile(const tmap *t, int x, int y)
{
    if (x < 0 || y < 0 || x >= t->w || y >= t->h) return 1;
    return t->tiles[y * t->w + x];
}

/* Point in the interior of the union (grid units). Off grid lines: the cell's tile.
 * On a line: every point of a tiny neighbourhood must be solid. */
static int ref_map_at(const tmap *t, double gx, double gy)
{
    double fx = floor(gx), fy = floor(gy);
    return ref_inside(tmap_tile(t, (int)fx, (int)fy), gx - fx, gy - fy);
}

static int ref_map_interior(const tmap *t, double gx, double gy)
{
    if (gx != floor(gx) && gy != floor(gy)) return ref_map_at(t, gx, gy);
    const double e = 1e-9;
    for (int k = 0; k < 16; k++) {
        double a = k * (6.283185307179586 / 16) + 0.01;
        if (!ref_map_at(t, gx + e * cos(a), gy + e * sin(a))) return 0;
    }
    return 1;
}

/* Reference: the first t in [0,1] at which p0 + t (p1 - p0) (grid units) is inside. */
static int ref_map_entry(const tmap *t, double x0, double y0, double x1, double y1, double *tr)
{
    double dx = x1 - x0, dy = y1 - y0;
    if (ref_map_interior(t, x0, y0)) {
        *tr = 0;
        return 1;
    }
    double len = sqrt(dx * dx + dy * dy);
    /* A power of two: with dyadic endpoints the samples are exact points of the line. */
    int N = 2048;
    while (N < len * 1000 + 2000) N *= 2;
    for (int i = 1; i <= N; i++) {
        double ti = (double)i / N;
        if (ref_map_interior(t, x0 + ti * dx, y0 + ti * dy)) {
            double lo = (double)(i - 1) / N, hi = ti;
            for (int k = 0; k < 80; k++) {
                double mid = 0.5 * (lo + hi);
                if (ref_map_interior(t, x0 + mid * dx, y0 + mid * dy)) hi = mid;
                else lo = mid;
            }
            *tr = hi;
            return 1;
        }
    }
    return 0;
}

static void dump_map(const tmap *t)
{
    for (int y = 0; y < t->h; y++) {
        char line[64 * 4 + 2];
        int k = 0;
        for (int x = 0; x < t->w; x++) k += snprintf(line + k, sizeof line - (size_t)k, "%3d", tmap_tile(t, x, y));
        print_message("%s\n", line);
    }
}

static int map_cast(const tmap *t, double x0, double y0, double x1, double y1, nt_ray_hit *h)
{
    memset(h, 0x55, sizeof *h);
    return nt_map_raycast(t->m, nt_v2((nt_real)x0, (nt_real)y0), nt_v2((nt_real)x1, (nt_real)y1), h);
}

/* Every point of a disc of radius r around (gx, gy) is inside: the union is entered
 * by more than rounding there. */
static int deep_at(const tmap *t, double gx, double gy, double r)
{
    if (!ref_map_interior(t, gx, gy)) return 0;
    for (int k = 0; k < 16; k++) {
        double a = k * (6.283185307179586 / 16) + 0.01;
        if (!ref_map_interior(t, gx + r * cos(a), gy + r * sin(a))) return 0;
    }
    return 1;
}

static int deep_between(const tmap *t, double gx0, double gy0, double gdx, double gdy, double ta, double tb)
{
    const int N = 4000;
    for (int i = 0; i <= N; i++) {
        double tt = ta + (tb - ta) * i / N;
        if (deep_at(t, gx0 + tt * gdx, gy0 + tt * gdy, 1e-5)) return 1;
    }
    return 0;
}

/* Distance to the boundary of the tiles whose cells touch the point. */
static double near_tile_boundary(const tmap *t, double gx, double gy)
{
    double best = 1e300;
    for (int dy = -1; dy <= 1; dy += 2)
        for (int dx = -1; dx <= 1; dx += 2) {
            int cx = (int)floor(gx + dx * 1e-6), cy = (int)floor(gy + dy * 1e-6);
            double d = ref_boundary(tmap_tile(t, cx, cy), gx - cx, gy - cy, NULL, NULL, NULL, NULL, NULL);
            if (d < best) best = d;
        }
    return best;
}

static int map_unverified = 0;
static int map_strict = 1; /* early hits must be confirmed by fine sampling */

/* Interior points right after the code's hit: fine sampling over 2e-3 cells. */
static int inside_after(const tmap *t, double gx0, double gy0, double gdx, double gdy, double glen, double f)
{
    for (int i = 0; i <= 40000; i++) {
        double tt = f + (2e-3 / (glen > 1 ? glen : 1)) * i / 40000;
        if (tt <= 1 && ref_map_interior(t, gx0 + tt * gdx, gy0 + tt * gdy)) return 1;
    }
    return 0;
}

/* Compare a world-units segment with the reference. `check_normal`: check the normal
 * against the surface piece at the hit point. Returns 1 on a checked hit. Answers
 * that differ from the sampled reference only by an entry thinner than rounding
 * (a touch at a vertex or cusp, a sliver) are counted in map_unverified. */
static int check_map_ray(const tmap *t, double x0, double y0, double x1, double y1, int check_normal)
{
    nt_ray_hit h;
    int hit = map_cast(t, x0, y0, x1, y1, &h);
    x0 = (nt_real)x0, y0 = (nt_real)y0, x1 = (nt_real)x1, y1 = (nt_real)y1;
    const double c = t->cell;
    double gx0 = x0 / c, gy0 = y0 / c, gx1 = x1 / c, gy1 = y1 / c;
    double gdx = gx1 - gx0, gdy = gy1 - gy0, glen = sqrt(gdx * gdx + gdy * gdy);
    double tr;
    int rh = ref_map_entry(t, gx0, gy0, gx1, gy1, &tr);
    double f = hit ? h.fraction : 2;
    double hx = gx0 + f * gdx, hy = gy0 + f * gdy;
    if (!rh) {
        if (hit) {
            if (map_strict ? !inside_after(t, gx0, gy0, gdx, gdy, glen, f) : near_tile_boundary(t, hx, hy) > 1e-5) {
                dump_map(t);
                fail_msg("map: false hit f=%.9g cell (%d,%d) for (%.9g,%.9g)->(%.9g,%.9g) cell %g", f, h.cell_x,
                         h.cell_y, x0, y0, x1, y1, c);
            }
            map_unverified++;
        }
        return 0;
    }
    double err = fabs(f - tr) * (glen > 1 ? glen : 1);
    if (!hit || err > TOL_T) {
        if (!hit || f > tr) {
            /* later than the reference (or not at all): only a thin entry may be skipped */
            if (deep_between(t, gx0, gy0, gdx, gdy, tr, hit ? f : 1)) {
                dump_map(t);
                fail_msg("map: %s f=%.9g, ref %.9g for (%.9g,%.9g)->(%.9g,%.9g) cell %g (hit cell %d,%d n=(%g,%g))",
                         hit ? "late hit" : "missed", hit ? f : -1.0, tr, x0, y0, x1, y1, c, hit ? h.cell_x : 0,
                         hit ? h.cell_y : 0, hit ? (double)h.normal.x : 0.0, hit ? (double)h.normal.y : 0.0);
            }
        } else if (map_strict ? !inside_after(t, gx0, gy0, gdx, gdy, glen, f)
                              : near_tile_boundary(t, hx, hy) > 1e-5) {
            /* earlier: an entry the sampling stepped over, on a surface */
            dump_map(t);
            fail_msg("map: early hit f=%.9g, ref %.9g for (%.9g,%.9g)->(%.9g,%.9g) cell %g (hit cell %d,%d)", f, tr, x0,
                     y0, x1, y1, c, h.cell_x, h.cell_y);
        }
        if (getenv("RAY_VERBOSE"))
            print_message("thin: hit %d f=%.9g ref %.9g (%.9g,%.9g)->(%.9g,%.9g) cell %g hitcell %d,%d\n", hit, f, tr, x0,
                          y0, x1, y1, c, hit ? h.cell_x : 0, hit ? h.cell_y : 0);
        if (getenv("RAY_VERBOSE") && atoi(getenv("RAY_VERBOSE")) > 1) dump_map(t);
        map_unverified++;
        return 0;
    }
    /* point = p0 + f (p1 - p0) */
    ASSERT_NEAR(h.point.x, x0 + h.fraction * (x1 - x0), 1e-4 * c + 1e-5 * fabs(x0));
    ASSERT_NEAR(h.point.y, y0 + h.fraction * (y1 - y0), 1e-4 * c + 1e-5 * fabs(y0));
    if (tr == 0 && ref_map_interior(t, gx0, gy0)) {
        if (!(h.normal.x == 0 && h.normal.y == 0))
            fail_msg("map: start inside, normal (%g,%g) for (%.9g,%.9g)", (double)h.normal.x, (double)h.normal.y, x0, y0);
        return 1;
    }
    double nl = hypot(h.normal.x, h.normal.y);
    if (fabs(nl - 1) > 1e-5) {
        if (nl == 0 && f == 0 && near_tile_boundary(t, gx0, gy0) < 1e-5) {
            map_unverified++; /* starts within rounding of a surface: inside or not */
            return 0;
        }
        dump_map(t);
        fail_msg("map: normal (%g,%g) at f=%.9g ref %.9g for (%.9g,%.9g)->(%.9g,%.9g) cell %g hit cell %d,%d",
                 (double)h.normal.x, (double)h.normal.y, f, tr, x0, y0, x1, y1, c, h.cell_x, h.cell_y);
    }
    if (!check_normal) return 1;
    assert_true(h.normal.x * gdx + h.normal.y * gdy < 1e-6);
    /* The entered tile: the cell just past the hit point. */
    hx = gx0 + tr * gdx, hy = gy0 + tr * gdy;
    double vx = fabs(hx - floor(hx + 0.5)), vy = fabs(hy - floor(hy + 0.5));
    if (vx < 1e-4 && vy < 1e-4) return 1; /* at a grid vertex: several normals and cells are right */
    double ex = hx + gdx * 1e-7 / glen, ey = hy + gdy * 1e-7 / glen;
    int cx = (int)floor(ex), cy = (int)floor(ey);
    int id = tmap_tile(t, cx, cy);
    double enx, eny, sec, e2x, e2y;
    ref_boundary(id, hx - cx, hy - cy, &enx, &eny, &sec, &e2x, &e2y);
    if (sec < 1e-3) return 1; /* at a vertex: several normals are right */
    if (hypot(h.normal.x - enx, h.normal.y - eny) > 2e-3)
        fail_msg("map: normal (%.6g,%.6g), expected (%.6g,%.6g) (%s at cell %d,%d) at f=%.9g for (%.9g,%.9g)->(%.9g,%.9g)",
                 (double)h.normal.x, (double)h.normal.y, enx, eny, tname(id), cx, cy, f, x0, y0, x1, y1);
    if ((vx > 1e-5 && vy > 1e-5) && (h.cell_x != cx || h.cell_y != cy))
        fail_msg("map: hit cell (%d,%d), expected (%d,%d) for (%.9g,%.9g)->(%.9g,%.9g)", h.cell_x, h.cell_y, cx, cy, x0,
                 y0, x1, y1);
    return 1;
}

static void expect_map_hit(const tmap *t, double x0, double y0, double x1, double y1, double ef, double enx,
                           double eny, int ecx, int ecy)
{
    nt_ray_hit h;
    if (!map_cast(t, x0, y0, x1, y1, &h))
        fail_msg("map: no hit for (%g,%g)->(%g,%g), expected f=%g", x0, y0, x1, y1, ef);
    ASSERT_NEAR(h.fraction, ef, 1e-5);
    if (enx != ANY) {
        ASSERT_NEAR(h.normal.x, enx, 1e-6);
        ASSERT_NEAR(h.normal.y, eny, 1e-6);
    } else {
        ASSERT_NEAR(hypot(h.normal.x, h.normal.y), 1, 1e-6);
    }
    x0 = (nt_real)x0, y0 = (nt_real)y0, x1 = (nt_real)x1, y1 = (nt_real)y1;
    ASSERT_NEAR(h.point.x, x0 + ef * (x1 - x0), 1e-4 * t->cell + 1e-6 * fabs(x0));
    ASSERT_NEAR(h.point.y, y0 + ef * (y1 - y0), 1e-4 * t->cell + 1e-6 * fabs(y0));
    if (ecx != ANY) assert_int_equal(h.cell_x, ecx);
    if (ecy != ANY) assert_int_equal(h.cell_y, ecy);
}

static void expect_map_miss(const tmap *t, double x0, double y0, double x1, double y1)
{
    nt_ray_hit h;
    if (map_cast(t, x0, y0, x1, y1, &h))
        fail_msg("map: unexpected hit f=%g n=(%g,%g) cell (%d,%d) for (%g,%g)->(%g,%g)", (double)h.fraction,
                 (double)h.normal.x, (double)h.normal.y, h.cell_x, h.cell_y, x0, y0, x1, y1);
}

/* Rays across the sliver at a CONCAVE tile's cusp (issue 20). At a distance s from a
 * cusp the solid between the straight side and the arc is 1 - sqrt(1 - s^2), about
 * s^2 / 2, thick: float once counted a run that short (up to a few 1e-6) as a touch
 * and missed it, where double hits. Each ray runs along the side's normal, once from
 * outside the cell (entering at the side) and once from the hollow (entering where it
 * leaves the disc), on the tile alone and in a map; the sliver is checked against the
 * independent reference (tests/ref.c) on the values the library receives. */
static void cusp_ray(int id, double px, double py, double dx, double dy, double et, double enx, double eny,
                     double thick)
{
    /* The reference on the rounded inputs: outside just before the entry, inside at
     * the middle of the sliver. */
    px = (nt_real)px, py = (nt_real)py;
    if (ref_point_in_tile(id, px + (et - 0.25 * thick) * dx, py + (et - 0.25 * thick) * dy) ||
        !ref_point_in_tile(id, px + (et + 0.5 * thick) * dx, py + (et + 0.5 * thick) * dy))
        fail_msg("%s: no sliver at p=(%.9g,%.9g) d=(%g,%g) t=%.9g thick %g", tname(id), px, py, dx, dy, et, thick);
    double t, nx, ny;
    if (!cast_tile(id, px, py, dx, dy, 2, &t, &nx, &ny))
        fail_msg("%s: missed a sliver %.3g thick: p=(%.9g,%.9g) d=(%g,%g), ref t=%.9g", tname(id), thick, px, py, dx,
                 dy, et);
    ASSERT_NEAR(t, et, 1e-6);
    ASSERT_NEAR(nx, enx, 1e-3);
    ASSERT_NEAR(ny, eny, 1e-3);
    /* The same ray in a 3 x 3 map with the tile in the middle, EMPTY around it. */
    tmap m;
    tmap_init(&m, 3, 3, 1);
    tmap_set(&m, 1, 1, id);
    nt_ray_hit h;
    double x0 = px + 1, y0 = py + 1, x1 = x0 + 2 * dx, y1 = y0 + 2 * dy;
    if (!map_cast(&m, x0, y0, x1, y1, &h))
        fail_msg("%s: map missed a sliver %.3g thick: (%.9g,%.9g)->(%.9g,%.9g)", tname(id), thick, x0, y0, x1, y1);
    ASSERT_NEAR(h.fraction, et / 2, 1e-6);
    ASSERT_NEAR(h.normal.x, enx, 1e-3);
    ASSERT_NEAR(h.normal.y, eny, 1e-3);
    assert_int_equal(h.cell_x, 1);
    assert_int_equal(h.cell_y, 1);
    nt_map_destroy(m.m);
}

static void test_tile_concave_cusp(void **state)
{
    (void)state;
    for (int id = 0; id < NT_TILE_COUNT; id++) {
        double ox, oy;
        if (ref_tile_kind(id) != REF_KIND_CONCAVE) continue;
        assert_true(ref_tile_arc_center(id, &ox, &oy));
        for (int cusp = 0; cusp < 2; cusp++) {
            /* The cusp Q (an end of the arc, a corner of the cell) and the axis of the
             * side through it: the side is x = Q.x (cusp 0) or y = Q.y (cusp 1). */
            double qx = cusp ? ox : 1 - ox, qy = cusp ? 1 - oy : oy;
            for (int k = 0; k < 40; k++) {
                double thick = 1e-4 * pow(1e-3, k / 39.0); /* 1e-4 .. 1e-7 cell */
                double s = sqrt(thick * (2 - thick));  /* 1 - sqrt(1 - s^2) = thick */
                double a = 0.05 + 0.4 * k / 39.0;       /* the start's distance from the sliver */
                /* u: the side's inward direction (towards the arc's centre); w: along the
                 * side, from the cusp into the cell. */
                double ux = cusp ? 0 : (ox > qx ? 1 : -1), uy = cusp ? (oy > qy ? 1 : -1) : 0;
                double wx = cusp ? (qx > 0.5 ? -1 : 1) : 0, wy = cusp ? 0 : (qy > 0.5 ? -1 : 1);
                double bx = qx + s * wx, by = qy + s * wy; /* where the ray crosses the side */
                /* From outside the cell, along u: enters at the side, normal -u. */
                cusp_ray(id, bx - a * ux, by - a * uy, ux, uy, a, -ux, -uy, thick);
                /* From the hollow, along -u: enters where it leaves the disc; the normal
                 * points to the arc's centre. */
                double ex = bx + thick * ux, ey = by + thick * uy, nl = hypot(ox - ex, oy - ey);
                cusp_ray(id, ex + a * ux, ey + a * uy, -ux, -uy, a, (ox - ex) / nl, (oy - ey) / nl, thick);
            }
        }
    }
}

/* A floor of FULL tiles on row 6 of a 10 x 8 map, for cell sizes 1 and 24. */
static void floor_cases(double c)
{
    tmap t;
    tmap_init(&t, 10, 8, c);
    for (int x = 0; x < 10; x++) tmap_set(&t, x, 6, NT_TILE_FULL);
    /* Straight down, inside a column and exactly on the seam x = 3 (a grid line). */
    expect_map_hit(&t, 2.5 * c, 1 * c, 2.5 * c, 7 * c, 5.0 / 6, 0, -1, 2, 6);
    expect_map_hit(&t, 3 * c, 1 * c, 3 * c, 7 * c, 5.0 / 6, 0, -1, ANY, ANY);
    /* Slanted, hitting the floor exactly at the seam vertex (3, 6): 45 degrees and 2:1. */
    expect_map_hit(&t, 1 * c, 4 * c, 4 * c, 7 * c, 2.0 / 3, 0, -1, ANY, ANY);
    expect_map_hit(&t, 2 * c, 4 * c, 4 * c, 8 * c, 0.5, 0, -1, ANY, ANY);
    expect_map_hit(&t, 5 * c, 4 * c, 2 * c, 7 * c, 2.0 / 3, 0, -1, ANY, ANY);
    /* Grazing along the floor's top surface (y = 6): no hit, in both directions. */
    expect_map_miss(&t, 0.5 * c, 6 * c, 9.5 * c, 6 * c);
    expect_map_miss(&t, 9.5 * c, 6 * c, 0.25 * c, 6 * c);
    expect_map_miss(&t, 0 * c, 6 * c, 10 * c, 6 * c); /* from border to border, still on the surface */
    /* ... but running on into the border's wall hits it. */
    expect_map_hit(&t, 5 * c, 6 * c, 15 * c, 6 * c, 0.5, -1, 0, 10, ANY);
    /* Along the seam line y = 7 between the floor and the bottom row: the seam between
     * two solids is not a surface, so starting there is inside. */
    tmap_set(&t, 4, 7, NT_TILE_FULL);
    tmap_set(&t, 5, 7, NT_TILE_FULL);
    expect_map_hit(&t, 4.5 * c, 7 * c, 4.5 * c, 3 * c, 0, 0, 0, ANY, ANY);
    expect_map_hit(&t, 1.5 * c, 7 * c, 8.5 * c, 7 * c, 2.5 / 7, -1, 0, ANY, ANY); /* enters under (4,6) at x = 4 */
    expect_map_hit(&t, 3.5 * c, 6.5 * c, 3.5 * c, 1 * c, 0, 0, 0, 3, 6);
    /* Starting on the floor surface, leaving: no hit; going in: t = 0 with (0,-1). */
    expect_map_miss(&t, 2.5 * c, 6 * c, 2.5 * c, 2 * c);
    expect_map_hit(&t, 2.5 * c, 6 * c, 2.5 * c, 6.5 * c, 0, 0, -1, 2, 6);
    expect_map_hit(&t, 3 * c, 6 * c, 3.5 * c, 6.5 * c, 0, 0, -1, 3, 6); /* from the seam vertex */
    /* Points. */
    expect_map_hit(&t, 2.5 * c, 6.5 * c, 2.5 * c, 6.5 * c, 0, 0, 0, 2, 6);
    expect_map_hit(&t, 3 * c, 6.5 * c, 3 * c, 6.5 * c, 0, 0, 0, ANY, ANY); /* on the seam */
    expect_map_miss(&t, 2.5 * c, 5.5 * c, 2.5 * c, 5.5 * c);
    expect_map_miss(&t, 2.5 * c, 6 * c, 2.5 * c, 6 * c); /* on the surface */
    /* Leaving the map: the border behaves as FULL tiles. */
    expect_map_hit(&t, 5.5 * c, 3.5 * c, 15 * c, 3.5 * c, 4.5 / 9.5, -1, 0, 10, 3);
    expect_map_hit(&t, 5.5 * c, 3.5 * c, -4.5 * c, 3.5 * c, 0.55, 1, 0, -1, 3);
    expect_map_hit(&t, 5.5 * c, 3.5 * c, 5.5 * c, -3.5 * c, 0.5, 0, 1, 5, -1);
    expect_map_hit(&t, 5.5 * c, 3.5 * c, 5.5 * c + 1e30, 3.5 * c, 4.5 * c / 1e30, -1, 0, 10, 3);
    expect_map_hit(&t, 2 * c, 2 * c, -2 * c, -2 * c, 0.5, ANY, ANY, -1, -1);
    nt_map_destroy(t.m);
}

static void test_map_floor(void **state)
{
    (void)state;
    floor_cases(1);
    floor_cases(24);
}

static void test_map_corner_cases(void **state)
{
    (void)state;
    tmap t;
    tmap_init(&t, 10, 10, 1);
    /* Diagonal through the grid vertex (5,5) into a FULL diagonal cell whose left
     * neighbour is also solid (so the left face is a seam): the surface is the top. */
    tmap_set(&t, 5, 5, NT_TILE_FULL);
    tmap_set(&t, 4, 5, NT_TILE_FULL);
    expect_map_hit(&t, 3.5, 3.5, 6.5, 6.5, 0.5, 0, -1, ANY, ANY);
    expect_map_hit(&t, 2.5, 3.5, 5.5, 6.5, 0.5, ANY, ANY, 4, 5); /* into (4,5): a convex corner */
    /* Same with the seam above instead: the surface is the left face. */
    tmap_set(&t, 4, 5, NT_TILE_EMPTY);
    tmap_set(&t, 5, 4, NT_TILE_FULL);
    expect_map_hit(&t, 3.5, 3.5, 6.5, 6.5, 0.5, -1, 0, ANY, ANY);
    /* Pinch: two solids touching at the vertex, the diagonal cell empty: passes. */
    tmap_set(&t, 5, 5, NT_TILE_EMPTY);
    tmap_set(&t, 4, 5, NT_TILE_FULL);
    expect_map_miss(&t, 3.5, 3.5, 6.5, 6.5);
    expect_map_miss(&t, 6.5, 6.5, 3.5, 3.5);
    expect_map_miss(&t, 5, 5, 6.5, 6.5);     /* starting at the pinch */
    expect_map_hit(&t, 5, 5, 4.5, 5.5, 0, ANY, ANY, 4, 5); /* from the pinch into (4,5): its corner */
    /* Point at the pinch vertex: boundary, not inside. */
    expect_map_miss(&t, 5, 5, 5, 5);
    /* A vertex where four FULL cells meet is inside. */
    tmap_set(&t, 5, 5, NT_TILE_FULL);
    tmap_set(&t, 4, 4, NT_TILE_FULL);
    expect_map_hit(&t, 5, 5, 5, 5, 0, 0, 0, ANY, ANY);
    expect_map_hit(&t, 5, 5, 9, 2, 0, 0, 0, ANY, ANY);
    nt_map_destroy(t.m);
    /* Along a grid line with partial covers: HALFr over FULL. The line y = 5 is inside
     * the union only under the HALFr's solid half, x in (3.5, 4). */
    tmap_init(&t, 10, 10, 1);
    tmap_set(&t, 3, 4, NT_TILE_HALFr);
    tmap_set(&t, 3, 5, NT_TILE_FULL);
    expect_map_hit(&t, 0.5, 5, 8, 5, 3.0 / 7.5, -1, 0, 3, 4); /* the HALFr's inner face */
    expect_map_hit(&t, 8, 5, 0.5, 5, 4.0 / 7.5, 1, 0, ANY, ANY); /* the right walls */
    expect_map_hit(&t, 3.75, 5, 3.75, 5, 0, 0, 0, ANY, ANY);    /* a point on that seam */
    expect_map_miss(&t, 3.25, 5, 3.25, 5);                      /* on the FULL's top, beside the half */
    expect_map_miss(&t, 3, 0.5, 3, 9);                          /* along x = 3: left faces, grazed */
    expect_map_miss(&t, 4, 9, 4, 0.5);                          /* along x = 4: right faces, grazed */
    /* down the HALFr's face x = 3.5 (a graze), then into the FULL's top at its corner */
    expect_map_hit(&t, 3.5, 0.5, 3.5, 9, 4.5 / 8.5, 0, -1, 3, 5);
    nt_map_destroy(t.m);
}

static void test_map_diagonal_into_slope(void **state)
{
    (void)state;
    tmap t;
    tmap_init(&t, 10, 10, 1);
    tmap_set(&t, 5, 5, NT_TILE_45DEGnn); /* solid toward (1,1) of the cell */
    /* Along the hypotenuse's line x + y = 11 (from (6,5) to (5,6)): grazing, no hit. */
    expect_map_miss(&t, 8, 3, 3, 8);
    /* Diagonal (1,1) through the vertex (5,5): enters the cell at its corner (5,5), which
     * is outside the solid, and meets the hypotenuse at (5.5, 5.5). */
    expect_map_hit(&t, 3.5, 3.5, 6.5, 6.5, 2.0 / 3, -sqrt(0.5), -sqrt(0.5), 5, 5);
    /* A 45DEGpp in the diagonal cell: solid toward (0,0), entered exactly at its corner. */
    tmap_set(&t, 5, 5, NT_TILE_45DEGpp);
    expect_map_hit(&t, 3.5, 3.5, 6.5, 6.5, 0.5, ANY, ANY, 5, 5);
    nt_map_destroy(t.m);
}

/* Random maps against the brute-force reference. */
static void random_map(tmap *t, int w, int h, double c, double p_empty)
{
    tmap_init(t, w, h, c);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int id = rnd() < p_empty ? 0 : 1 + (int)(rnd() * 33);
            if (id > 33) id = 33;
            tmap_set(t, x, y, id);
        }
}

static void map_random_runs(double c, uint64_t seed)
{
    rng_state = seed;
    int checked = 0, total = 0, thin_general = 0, n_general = 0, n_special = 0;
    map_unverified = 0;
    for (int round = 0; round < 6; round++) {
        tmap t;
        random_map(&t, 14, 10, c, round < 3 ? 0.7 : 0.45);
        int before = map_unverified;
        for (int i = 0; i < 250; i++) {
            double x0 = rnd_in(-0.3, 14.3), y0 = rnd_in(-0.3, 10.3);
            double x1 = rnd_in(-0.3, 14.3), y1 = rnd_in(-0.3, 10.3);
            checked += check_map_ray(&t, x0 * c, y0 * c, x1 * c, y1 * c, 1);
            total++;
            n_general++;
        }
        thin_general += map_unverified - before;
        before = map_unverified;
        /* Rays through grid vertices: 45 degrees and 2:1 lines through integer points. */
        for (int i = 0; i < 120; i++) {
            int ax = 1 + (int)(rnd() * 12), ay = 1 + (int)(rnd() * 8);
            int kx = (int)(rnd() * 4) - 2, ky = (int)(rnd() * 4) - 2;
            if (kx == 0) kx = 1;
            if (ky == 0) ky = -1;
            if (i & 1) kx *= 2;
            /* dyadic: every coordinate is exact in float and double, so these lines pass
             * exactly through the vertices (and often run exactly along slopes) */
            double s0 = (26 + (int)(rnd() * 205)) / 256.0, s1 = (384 + (int)(rnd() * 897)) / 256.0;
            checked += check_map_ray(&t, (ax - s0 * kx) * c, (ay - s0 * ky) * c, (ax + s1 * kx) * c,
                                     (ay + s1 * ky) * c, 1);
            total++;
            n_special++;
        }
        /* Rays along grid lines (horizontal and vertical), from and to random points. The
         * reference's neighbourhood test sees a sliver of interior near a cusp that
         * touches the line, so these are compared leniently. */
        map_strict = 0;
        for (int i = 0; i < 160; i++) {
            int line = (int)(rnd() * 11);
            double a = rnd_in(-0.2, 14.2), b = rnd_in(-0.2, 14.2);
            if (i & 1) checked += check_map_ray(&t, a * c, line * c, b * c, line * c, 0);
            else checked += check_map_ray(&t, line * c, a * 10 / 14 * c, line * c, b * 10 / 14 * c, 0);
            total++;
            n_special++;
        }
        map_strict = 1;
        int thin_special = map_unverified - before;
        (void)thin_special;
        before = map_unverified;
        /* Short segments and points. */
        for (int i = 0; i < 200; i++) {
            double x0 = rnd_in(0, 14), y0 = rnd_in(0, 10);
            double l = (i % 4 == 0) ? 0 : rnd_in(0, 0.5), a = rnd_in(0, 6.283185307179586);
            checked += check_map_ray(&t, x0 * c, y0 * c, (x0 + l * cos(a)) * c, (y0 + l * sin(a)) * c, 1);
            total++;
            n_general++;
        }
        thin_general += map_unverified - before;
        nt_map_destroy(t.m);
    }
    int thin_special = map_unverified - thin_general;
    print_message("cell %g: %d of %d rays gave checked hits; thin-entry differences: %d of %d general rays, "
                  "%d of %d rays through vertices or along grid lines\n",
                  c, checked, total, thin_general, n_general, thin_special, n_special);
    if (checked < total / 3) fail_msg("only %d of %d rays gave a checked hit", checked, total);
    /* Random rays almost never pass within rounding of a surface; rays built through
     * vertices often run exactly along a slope, where float inputs decide the side. */
    if (thin_general > n_general / 500 + 1) fail_msg("%d thin-entry differences", thin_general);
    if (thin_special > n_special / 200) fail_msg("%d thin-entry differences", thin_special);
}

static void test_map_random(void **state)
{
    (void)state;
    map_random_runs(1, 777);
}

static void test_map_random_cell24(void **state)
{
    (void)state;
    map_random_runs(24, 4242);
    map_random_runs(0.375, 99);
}

/* Thousands of cells: the walk must not drift off the segment (a near miss stays a
 * miss, a shallow hit is found at the right place). */
static void test_map_long_rays(void **state)
{
    (void)state;
    tmap t;
    nt_map_def def = nt_default_map_def();
    def.width = 3000;
    def.height = 2048;
    def.cell_size = 1;
    assert_int_equal(nt_map_create(&def, &t.m), NT_OK);
    assert_int_equal(nt_map_set_tile(t.m, 2900, 2000, NT_TILE_FULL), NT_OK);
    t.cell = 1;
    const double x0 = 10.5, y0 = 7.25;
    /* Passing 0.01 above the cell's top-right corner (2901, 2000): no hit. */
    {
        double ax = 2901.01, ay = 1999.99;
        double x1 = x0 + (ax - x0) * 1.02, y1 = y0 + (ay - y0) * 1.02;
        expect_map_miss(&t, x0, y0, x1, y1);
        expect_map_miss(&t, x1, y1, x0, y0);
    }
    /* Through the corner region 0.01 deep: enters the top face where y = 2000. */
    {
        double ax = 2900.99, ay = 2000.01;
        double x1 = x0 + (ax - x0) * 1.02, y1 = y0 + (ay - y0) * 1.02;
        double ty = (2000 - y0) / (y1 - y0); /* the line reaches y = 2000 */
        nt_ray_hit h;
        assert_true(map_cast(&t, x0, y0, x1, y1, &h));
        ASSERT_NEAR(h.fraction, ty, 2e-6);
        ASSERT_NEAR(h.normal.x, 0, 0);
        ASSERT_NEAR(h.normal.y, -1, 0);
        assert_int_equal(h.cell_x, 2900);
        assert_int_equal(h.cell_y, 2000);
    }
    /* A near-horizontal ray 0.01 below the row's bottom, over 2900 cells: no hit;
     * 0.01 above it: hits the left face. */
    expect_map_miss(&t, 0.5, 2001.01, 2999.5, 2001.02);
    {
        nt_ray_hit h;
        assert_true(map_cast(&t, 0.5, 2000.98, 2999.5, 2000.99, &h));
        ASSERT_NEAR(h.fraction, (2900 - 0.5) / 2999.0, 2e-6);
        ASSERT_NEAR(h.normal.x, -1, 0);
    }
    nt_map_destroy(t.m);
}

static void test_map_invalid(void **state)
{
    (void)state;
    tmap t;
    tmap_init(&t, 4, 4, 24);
    nt_ray_hit h;
    assert_false(nt_map_raycast(NULL, nt_v2(1, 1), nt_v2(2, 2), &h));
    assert_false(nt_map_raycast(t.m, nt_v2(NAN, 1), nt_v2(2, 2), &h));
    assert_false(nt_map_raycast(t.m, nt_v2(1, 1), nt_v2(INFINITY, 2), &h));
    assert_false(nt_map_raycast(t.m, nt_v2(30, 30), nt_v2(40, 50), &h));
    assert_false(nt_map_raycast(t.m, nt_v2(30, 30), nt_v2(40, 50), NULL));
    assert_true(nt_map_raycast(t.m, nt_v2(30, 30), nt_v2(400, 50), NULL));
    /* huge coordinates: outside the map is inside the border */
    expect_map_hit(&t, -1e30, 5, 40, 40, 0, 0, 0, ANY, ANY);
    expect_map_hit(&t, 3e38, 3e38, -3e38, -3e38, 0, 0, 0, ANY, ANY);
    expect_map_hit(&t, 48, 48, 3e38, 48, 48 / 3e38, -1, 0, 4, 1);
    nt_map_destroy(t.m);
    /* A segment whose direction in cells overflows (float, small cells) still finds the border. */
    tmap_init(&t, 4, 4, 0.25);
    nt_ray_hit hh;
    assert_true(nt_map_raycast(t.m, nt_v2(0.5, 0.5), nt_v2((nt_real)3e38, 0.5), &hh));
    ASSERT_NEAR(hh.point.x, 1, 1e-6);
    ASSERT_NEAR(hh.point.y, 0.5, 1e-6);
    ASSERT_NEAR(hh.normal.x, -1, 0);
    assert_int_equal(hh.cell_x, 4);
    assert_true(hh.fraction > 0 && hh.fraction < 1e-30);
    assert_true(nt_map_raycast(t.m, nt_v2(0.5, 0.5), nt_v2((nt_real)-3e38, (nt_real)1e38), &hh));
    ASSERT_NEAR(hh.point.x, 0, 1e-6);
    ASSERT_NEAR(hh.normal.x, 1, 0);
    nt_map_destroy(t.m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference_geometry),
        cmocka_unit_test(test_tile_grazing),
        cmocka_unit_test(test_tile_known_hits),
        cmocka_unit_test(test_tile_random),
        cmocka_unit_test(test_tile_concave_cusp),
        cmocka_unit_test(test_map_floor),
        cmocka_unit_test(test_map_corner_cases),
        cmocka_unit_test(test_map_diagonal_into_slope),
        cmocka_unit_test(test_map_random),
        cmocka_unit_test(test_map_random_cell24),
        cmocka_unit_test(test_map_long_rays),
        cmocka_unit_test(test_map_invalid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
