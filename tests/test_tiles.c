/* The tile table against the independent reference (tests/ref.c) and hand data:
 * names and ids, classes and signs, point containment, normals, corners, bounds,
 * side coverage. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "ntile/ntile.h"
#include "ref.h"
/* The engine's internal tables, for the check that they agree with each other. */
#include "../src/core_internal.h"

#define NTILES 34

/* Round a double to the library's scalar type and back: engine and reference must see
 * exactly the same input. */
static double rr(double x) { return (double)(nt_real)x; }

/* Within a tolerance appropriate to how the table stores values (nt_real). */
static const double TAB_TOL = NT_REAL_IS_DOUBLE ? 1e-12 : 1e-6;

/* ------------------------------------------------------------ names / ids */

static void test_names_roundtrip(void **state)
{
    (void)state;
    assert_int_equal(NT_TILE_COUNT, NTILES);
    for (int id = 0; id < NTILES; id++) {
        const nt_tile_info *info = nt_tile_get_info(id);
        assert_non_null(info);
        assert_non_null(info->name);
        assert_string_equal(info->name, ref_tile_name(id));
        assert_int_equal(nt_tile_from_name(ref_tile_name(id)), id);
        /* The level-string character is '0' + id (notes), so ids are dense 0..33. */
    }
    /* Enum constants carry N's ids. */
    assert_int_equal(nt_tile_from_name("EMPTY"), NT_TILE_EMPTY);
    assert_int_equal(nt_tile_from_name("FULL"), NT_TILE_FULL);
    assert_int_equal(nt_tile_from_name("45DEGpn"), NT_TILE_45DEGpn);
    assert_int_equal(nt_tile_from_name("45DEGpp"), NT_TILE_45DEGpp);
    assert_int_equal(nt_tile_from_name("CONCAVEnn"), NT_TILE_CONCAVEnn);
    assert_int_equal(nt_tile_from_name("CONVEXnp"), NT_TILE_CONVEXnp);
    assert_int_equal(nt_tile_from_name("22DEGppS"), NT_TILE_22DEGppS);
    assert_int_equal(nt_tile_from_name("22DEGnpB"), NT_TILE_22DEGnpB);
    assert_int_equal(nt_tile_from_name("67DEGnnS"), NT_TILE_67DEGnnS);
    assert_int_equal(nt_tile_from_name("67DEGpnB"), NT_TILE_67DEGpnB);
    assert_int_equal(nt_tile_from_name("HALFd"), NT_TILE_HALFd);
    assert_int_equal(nt_tile_from_name("HALFr"), NT_TILE_HALFr);
    assert_int_equal(nt_tile_from_name("HALFu"), NT_TILE_HALFu);
    assert_int_equal(nt_tile_from_name("HALFl"), NT_TILE_HALFl);
    assert_int_equal(NT_TILE_HALFl, 33);
}

static void test_unknown_names_and_ids(void **state)
{
    (void)state;
    const char *bad[] = {"", "full", "Full", "FULL ", " FULL", "45DEG", "45DEGpnx", "45DEGPN", "HALF",
                         "HALFD", "CONVEX", "22DEGpn", "67DEGpnb", "0", "1", "EMPTY\n"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) assert_int_equal(nt_tile_from_name(bad[i]), -1);
    assert_int_equal(nt_tile_from_name(NULL), -1);
    const int ids[] = {-1, 34, 35, 100, INT_MIN, INT_MAX};
    for (size_t i = 0; i < sizeof ids / sizeof ids[0]; i++) assert_null(nt_tile_get_info(ids[i]));
}

/* ----------------------------------------------------------- class, signs */

static void test_classes_and_signs(void **state)
{
    (void)state;
    for (int id = 0; id < NTILES; id++) {
        const nt_tile_info *info = nt_tile_get_info(id);
        int kind = ref_tile_kind(id);
        int cls = kind == REF_KIND_EMPTY     ? NT_CLASS_EMPTY
                  : kind == REF_KIND_POLYGON ? NT_CLASS_POLYGON
                  : kind == REF_KIND_CONVEX  ? NT_CLASS_CONVEX
                                             : NT_CLASS_CONCAVE;
        if ((int)info->cls != cls) fail_msg("%s: class %d, expected %d", ref_tile_name(id), (int)info->cls, cls);
        int sx, sy;
        ref_tile_signs(id, &sx, &sy);
        if (info->signx != sx || info->signy != sy)
            fail_msg("%s: signs (%d,%d), expected (%d,%d)", ref_tile_name(id), info->signx, info->signy, sx, sy);
    }
}

/* ------------------------------------------------------ point containment */

static bool engine_contains(int id, double x, double y)
{
    return nt_tile_contains_point(id, nt_v2((nt_real)x, (nt_real)y));
}

static void test_contains_point_random(void **state)
{
    (void)state;
    ref_rng rng = ref_rng_seed(0x7117e5ULL);
    for (int id = 0; id < NTILES; id++) {
        int checked = 0, inside = 0, bad = 0;
        for (int i = 0; i < 20000; i++) {
            double x = rr(ref_rng_uniform(&rng, -0.25, 1.25));
            double y = rr(ref_rng_uniform(&rng, -0.25, 1.25));
            double sd = ref_tile_signed_distance(id, x, y);
            if (fabs(sd) < 1e-6) continue; /* too close to the boundary for float input */
            bool want = ref_point_in_tile(id, x, y), got = engine_contains(id, x, y);
            checked++;
            inside += want;
            if (want != got && bad++ < 5)
                print_message("%s: contains(%.9g, %.9g) = %d, reference %d\n", ref_tile_name(id), x, y, got, want);
        }
        if (bad) fail_msg("%s: %d of %d random points disagree", ref_tile_name(id), bad, checked);
        assert_true(checked > 19000);
        if (id != NT_TILE_EMPTY) assert_true(inside > 1000); /* the test is not vacuous */
    }
}

/* Hand-picked points for the `pn` shapes, expected values worked out by hand from the
 * notes; every orientation is checked through the notes' mirror rule. */
typedef struct hp {
    int id; /* a pn tile (or FULL / HALF / EMPTY: no mirroring) */
    double x, y;
    int inside;
} hp;

static const hp HAND_POINTS[] = {
    {NT_TILE_EMPTY, 0.5, 0.5, 0},
    {NT_TILE_FULL, 0.5, 0.5, 1}, {NT_TILE_FULL, 0.999, 0.001, 1}, {NT_TILE_FULL, 0, 0.5, 0},
    {NT_TILE_FULL, 1, 1, 0}, {NT_TILE_FULL, 0.5, 1, 0}, {NT_TILE_FULL, 1.001, 0.5, 0},
    /* 45: triangle (0,0) (0,1) (1,1), solid where y > x */
    {NT_TILE_45DEGpn, 0.25, 0.75, 1}, {NT_TILE_45DEGpn, 0.0625, 0.125, 1}, {NT_TILE_45DEGpn, 0.5, 0.5, 0},
    {NT_TILE_45DEGpn, 0.75, 0.25, 0}, {NT_TILE_45DEGpn, 0, 0, 0}, {NT_TILE_45DEGpn, 0, 0.5, 0},
    {NT_TILE_45DEGpn, 0.5, 1, 0}, {NT_TILE_45DEGpn, 0.001, 0.999, 1},
    /* CONCAVE: cell minus disc radius 1 around (1,0) */
    {NT_TILE_CONCAVEpn, 0.5, 0.5, 0}, {NT_TILE_CONCAVEpn, 0.125, 0.875, 1}, {NT_TILE_CONCAVEpn, 0.25, 0.75, 1},
    {NT_TILE_CONCAVEpn, 0, 1, 0}, {NT_TILE_CONCAVEpn, 0.5, 1, 0}, {NT_TILE_CONCAVEpn, 0, 0, 0},
    {NT_TILE_CONCAVEpn, 1, 1, 0}, {NT_TILE_CONCAVEpn, 0.9, 0.1, 0}, {NT_TILE_CONCAVEpn, 0.01, 0.5, 1},
    /* CONVEX: quarter disc radius 1 around (0,1) */
    {NT_TILE_CONVEXpn, 0.5, 0.5, 1}, {NT_TILE_CONVEXpn, 0.875, 0.125, 0}, {NT_TILE_CONVEXpn, 0, 0, 0},
    {NT_TILE_CONVEXpn, 1, 1, 0}, {NT_TILE_CONVEXpn, 0, 1, 0}, {NT_TILE_CONVEXpn, 0.1, 0.9, 1},
    {NT_TILE_CONVEXpn, 0.6, 0.3, 1}, /* |(0.6,-0.7)| = 0.922 < 1 */
    {NT_TILE_CONVEXpn, 0.7, 0.2, 0}, /* |(0.7,-0.8)| = 1.063 > 1 */
    /* 22 S: (0,0.5) (0,1) (1,1), solid where y > 0.5 + x/2 */
    {NT_TILE_22DEGpnS, 0.5, 0.875, 1}, {NT_TILE_22DEGpnS, 0.5, 0.75, 0}, {NT_TILE_22DEGpnS, 0.5, 0.625, 0},
    {NT_TILE_22DEGpnS, 0, 0.5, 0}, {NT_TILE_22DEGpnS, 0.25, 0.5, 0}, {NT_TILE_22DEGpnS, 0.125, 0.75, 1},
    /* 22 B: (0,0) (1,0.5) (1,1) (0,1), solid where y > x/2 */
    {NT_TILE_22DEGpnB, 0.5, 0.25, 0}, {NT_TILE_22DEGpnB, 0.5, 0.375, 1}, {NT_TILE_22DEGpnB, 0.5, 0.125, 0},
    {NT_TILE_22DEGpnB, 1, 0.5, 0}, {NT_TILE_22DEGpnB, 0.875, 0.5, 1}, {NT_TILE_22DEGpnB, 0.125, 0.0625, 0},
    /* 67 S: (0,0) (0,1) (0.5,1), solid where y > 2x */
    {NT_TILE_67DEGpnS, 0.25, 0.5, 0}, {NT_TILE_67DEGpnS, 0.125, 0.5, 1}, {NT_TILE_67DEGpnS, 0.375, 0.5, 0},
    {NT_TILE_67DEGpnS, 0.5, 1, 0}, {NT_TILE_67DEGpnS, 0.4375, 0.9375, 1}, {NT_TILE_67DEGpnS, 0.75, 0.9, 0},
    /* 67 B: (0,0) (0.5,0) (1,1) (0,1), solid where y > 2x - 1 */
    {NT_TILE_67DEGpnB, 0.75, 0.5, 0}, {NT_TILE_67DEGpnB, 0.5, 0.5, 1}, {NT_TILE_67DEGpnB, 0.875, 0.5, 0},
    {NT_TILE_67DEGpnB, 0.5, 0, 0}, {NT_TILE_67DEGpnB, 0.25, 0.0625, 1}, {NT_TILE_67DEGpnB, 0.9375, 0.9375, 1},
    /* HALF tiles */
    {NT_TILE_HALFd, 0.5, 0.75, 1}, {NT_TILE_HALFd, 0.5, 0.5, 0}, {NT_TILE_HALFd, 0.5, 0.25, 0},
    {NT_TILE_HALFr, 0.75, 0.5, 1}, {NT_TILE_HALFr, 0.5, 0.5, 0}, {NT_TILE_HALFr, 0.25, 0.5, 0},
    {NT_TILE_HALFu, 0.5, 0.25, 1}, {NT_TILE_HALFu, 0.5, 0.5, 0}, {NT_TILE_HALFu, 0.5, 0.75, 0},
    {NT_TILE_HALFl, 0.25, 0.5, 1}, {NT_TILE_HALFl, 0.5, 0.5, 0}, {NT_TILE_HALFl, 0.75, 0.5, 0},
};

static void test_contains_point_hand(void **state)
{
    (void)state;
    int bad = 0;
    for (size_t i = 0; i < sizeof HAND_POINTS / sizeof HAND_POINTS[0]; i++) {
        const hp *h = &HAND_POINTS[i];
        int family = h->id >= 2 && h->id < 30;
        for (int k = 0; k < (family ? 4 : 1); k++) {
            /* pn, nn, np, pp: mirror x for nn and np, y for np and pp. */
            int id = h->id + k;
            double x = (k == 1 || k == 2) ? 1 - h->x : h->x;
            double y = (k >= 2) ? 1 - h->y : h->y;
            x = rr(x);
            y = rr(y);
            if (engine_contains(id, x, y) != (bool)h->inside) {
                print_message("%s: contains(%g, %g) should be %d\n", ref_tile_name(id), x, y, h->inside);
                bad++;
            }
            /* The reference agrees with the hand value too. */
            if (ref_point_in_tile(id, x, y) != (bool)h->inside)
                fail_msg("reference %s: contains(%g, %g) should be %d", ref_tile_name(id), x, y, h->inside);
        }
    }
    assert_int_equal(bad, 0);
}

/* Corners, edge midpoints and arc end points are on the boundary: never inside. A
 * point just inside each straight edge's midpoint and each corner's bisector is. */
static void test_contains_point_boundary(void **state)
{
    (void)state;
    int bad = 0;
    for (int id = 0; id < NTILES; id++) {
        double xs[4], ys[4];
        int n = ref_tile_corners(id, xs, ys);
        for (int i = 0; i < n; i++) {
            if (engine_contains(id, xs[i], ys[i])) {
                print_message("%s: corner (%g,%g) inside\n", ref_tile_name(id), xs[i], ys[i]);
                bad++;
            }
            int j = (i + 1) % n;
            double mx = 0.5 * (xs[i] + xs[j]), my = 0.5 * (ys[i] + ys[j]);
            /* Round tiles: only corners 0-1 and 1-2 are joined by straight sides. */
            if (ref_tile_kind(id) != REF_KIND_POLYGON && i == n - 1) continue;
            if (engine_contains(id, mx, my)) {
                print_message("%s: edge midpoint (%g,%g) inside\n", ref_tile_name(id), mx, my);
                bad++;
            }
        }
        /* Points strictly inside, one per edge: move from the midpoint toward the
         * tile's interior (towards the centroid of its corners) by 1e-3. */
        if (n >= 3) {
            double gx = 0, gy = 0;
            for (int i = 0; i < n; i++) {
                gx += xs[i] / n;
                gy += ys[i] / n;
            }
            for (int i = 0; i < n; i++) {
                if (ref_tile_kind(id) != REF_KIND_POLYGON && i == n - 1) continue;
                int j = (i + 1) % n;
                double mx = 0.5 * (xs[i] + xs[j]), my = 0.5 * (ys[i] + ys[j]);
                double dx = gx - mx, dy = gy - my, l = hypot(dx, dy);
                double px = rr(mx + 1e-3 * dx / l), py = rr(my + 1e-3 * dy / l);
                assert_true(ref_point_in_tile(id, px, py));
                if (!engine_contains(id, px, py)) fail_msg("%s: (%g,%g) just inside is not", ref_tile_name(id), px, py);
            }
        }
        /* Round tiles: just either side of the arc's midpoint. */
        double ox, oy;
        if (ref_tile_arc_center(id, &ox, &oy)) {
            double ux = (0.5 - ox) / fabs(0.5 - ox) * sqrt(0.5), uy = (0.5 - oy) / fabs(0.5 - oy) * sqrt(0.5);
            int convex = ref_tile_kind(id) == REF_KIND_CONVEX;
            double inx = rr(ox + ux * 0.999), iny = rr(oy + uy * 0.999);
            double outx = rr(ox + ux * 1.001), outy = rr(oy + uy * 1.001);
            if (engine_contains(id, inx, iny) != convex) fail_msg("%s: just inside the arc", ref_tile_name(id));
            if (engine_contains(id, outx, outy) == convex) fail_msg("%s: just outside the arc", ref_tile_name(id));
        }
    }
    /* Out-of-range ids contain nothing. */
    assert_false(nt_tile_contains_point(-1, nt_v2(0.5f, 0.5f)));
    assert_false(nt_tile_contains_point(34, nt_v2(0.5f, 0.5f)));
    assert_int_equal(bad, 0);
}

/* ----------------------------------------------------------------- normals */

/* The notes' unit normals: 45: (sx, sy)/sqrt2; 22: (sx, 2 sy)/sqrt5; 67: (2 sx, sy)/sqrt5;
 * HALFd (0,-1), HALFu (0,1), HALFl (1,0), HALFr (-1,0); the header: (0,0) for EMPTY,
 * FULL and round tiles. */
static void notes_normal(int id, double *nx, double *ny)
{
    int sx, sy;
    ref_tile_signs(id, &sx, &sy);
    *nx = 0;
    *ny = 0;
    const double s2 = sqrt(2.0), s5 = sqrt(5.0);
    if (id >= 2 && id <= 5) {
        *nx = sx / s2;
        *ny = sy / s2;
    } else if (id >= 14 && id <= 21) {
        *nx = sx / s5;
        *ny = 2 * sy / s5;
    } else if (id >= 22 && id <= 29) {
        *nx = 2 * sx / s5;
        *ny = sy / s5;
    } else if (id == NT_TILE_HALFd) {
        *ny = -1;
    } else if (id == NT_TILE_HALFu) {
        *ny = 1;
    } else if (id == NT_TILE_HALFl) {
        *nx = 1;
    } else if (id == NT_TILE_HALFr) {
        *nx = -1;
    }
}

static void test_normals_polygon(void **state)
{
    (void)state;
    for (int id = 1; id < NTILES; id++) {
        if (ref_tile_kind(id) != REF_KIND_POLYGON) continue;
        const nt_tile_info *info = nt_tile_get_info(id);
        double nx, ny;
        notes_normal(id, &nx, &ny);
        if (fabs(info->normal.x - nx) > TAB_TOL || fabs(info->normal.y - ny) > TAB_TOL)
            fail_msg("%s: normal (%g,%g), expected (%g,%g)", ref_tile_name(id), (double)info->normal.x,
                     (double)info->normal.y, nx, ny);
        if (id == NT_TILE_FULL) continue;
        double len = hypot(info->normal.x, info->normal.y);
        assert_true(fabs(len - 1) < TAB_TOL);
        /* The surface with that normal: the polygon edge that is not on a cell side. */
        double xs[4], ys[4];
        int n = ref_tile_corners(id, xs, ys), found = 0;
        for (int i = 0; i < n; i++) {
            int j = (i + 1) % n;
            int on_side = (xs[i] == xs[j] && (xs[i] == 0 || xs[i] == 1)) || (ys[i] == ys[j] && (ys[i] == 0 || ys[i] == 1));
            if (on_side) continue;
            found++;
            double ex = xs[j] - xs[i], ey = ys[j] - ys[i];
            /* Perpendicular to the surface... */
            assert_true(fabs(ex * info->normal.x + ey * info->normal.y) < 1e-6);
            /* ...and pointing out of the solid. */
            double mx = 0.5 * (xs[i] + xs[j]), my = 0.5 * (ys[i] + ys[j]);
            double e = 1e-4;
            if (ref_point_in_tile(id, mx + e * info->normal.x, my + e * info->normal.y))
                fail_msg("%s: +normal from the surface is inside", ref_tile_name(id));
            if (!ref_point_in_tile(id, mx - e * info->normal.x, my - e * info->normal.y))
                fail_msg("%s: -normal from the surface is outside", ref_tile_name(id));
        }
        assert_int_equal(found, 1);
    }
}

/* include/ntile/tiles.h: the normal is (0,0) for EMPTY and FULL; for round tiles it is
 * the unit outward normal at the middle of the arc. */
static void test_normals_empty_and_round(void **state)
{
    (void)state;
    for (int id = 0; id < NTILES; id++) {
        int kind = ref_tile_kind(id);
        const nt_tile_info *info = nt_tile_get_info(id);
        double nx = info->normal.x, ny = info->normal.y;
        if (id == NT_TILE_EMPTY || id == NT_TILE_FULL) {
            if (nx != 0 || ny != 0) fail_msg("%s: normal (%g,%g), expected (0,0)", ref_tile_name(id), nx, ny);
            continue;
        }
        if (kind == REF_KIND_POLYGON) continue; /* checked with the sloped faces above */
        double ox, oy;
        assert_true(ref_tile_arc_center(id, &ox, &oy));
        assert_true(fabs(sqrt(nx * nx + ny * ny) - 1) < 1e-6);
        /* The arc's middle lies on the diagonal through the arc centre, toward the cell. */
        double dx = 0.5 - ox, dy = 0.5 - oy, dl = sqrt(dx * dx + dy * dy);
        double mx = ox + dx / dl, my = oy + dy / dl, e = 1e-4;
        if (ref_point_in_tile(id, mx + e * nx, my + e * ny))
            fail_msg("%s: +normal from the arc's middle is inside", ref_tile_name(id));
        if (!ref_point_in_tile(id, mx - e * nx, my - e * ny))
            fail_msg("%s: -normal from the arc's middle is outside", ref_tile_name(id));
    }
}

/* --------------------------------------------------- corners, arcs, bounds */

static int has_point(const nt_vec2 *v, int n, double x, double y)
{
    for (int i = 0; i < n; i++)
        if (fabs(v[i].x - x) < TAB_TOL && fabs(v[i].y - y) < TAB_TOL) return 1;
    return 0;
}

static void test_vertices_and_arcs(void **state)
{
    (void)state;
    for (int id = 0; id < NTILES; id++) {
        const nt_tile_info *info = nt_tile_get_info(id);
        double xs[4], ys[4];
        int n = ref_tile_corners(id, xs, ys);
        if (info->vertex_count != n) fail_msg("%s: %d vertices, expected %d", ref_tile_name(id), info->vertex_count, n);
        for (int i = 0; i < n; i++)
            if (!has_point(info->vertices, info->vertex_count, xs[i], ys[i]))
                fail_msg("%s: corner (%g,%g) missing", ref_tile_name(id), xs[i], ys[i]);
        if (ref_tile_kind(id) == REF_KIND_POLYGON) {
            /* Counter-clockwise on screen: edge a->b has outward normal (-(b.y-a.y), b.x-a.x). */
            for (int i = 0; i < n; i++) {
                nt_vec2 a = info->vertices[i], b = info->vertices[(i + 1) % n];
                double nx = -(b.y - a.y), ny = b.x - a.x, l = hypot(nx, ny);
                double mx = 0.5 * (a.x + b.x), my = 0.5 * (a.y + b.y), e = 1e-4 / l;
                if (ref_point_in_tile(id, mx + e * nx, my + e * ny) || !ref_point_in_tile(id, mx - e * nx, my - e * ny))
                    fail_msg("%s: edge %d is not counter-clockwise (outward normal rule)", ref_tile_name(id), i);
            }
        }
        double ox, oy;
        if (ref_tile_arc_center(id, &ox, &oy)) {
            if (fabs(info->arc_center.x - ox) > TAB_TOL || fabs(info->arc_center.y - oy) > TAB_TOL)
                fail_msg("%s: arc centre (%g,%g), expected (%g,%g)", ref_tile_name(id), (double)info->arc_center.x,
                         (double)info->arc_center.y, ox, oy);
        }
    }
}

static void test_bounds(void **state)
{
    (void)state;
    const nt_tile_info *e = nt_tile_get_info(NT_TILE_EMPTY);
    assert_true(e->bounds_min.x > e->bounds_max.x && e->bounds_min.y > e->bounds_max.y);
    for (int id = 1; id < NTILES; id++) {
        const nt_tile_info *info = nt_tile_get_info(id);
        /* Bounds of the solid: sample the closed tile on a fine grid (the extremes are at
         * 0, 0.5 or 1, which the grid contains). */
        double lox = 2, loy = 2, hix = -1, hiy = -1;
        for (int i = 0; i <= 256; i++)
            for (int j = 0; j <= 256; j++) {
                double x = i / 256.0, y = j / 256.0;
                if (ref_tile_signed_distance(id, x, y) > 1e-12) continue;
                lox = fmin(lox, x);
                hix = fmax(hix, x);
                loy = fmin(loy, y);
                hiy = fmax(hiy, y);
            }
        if (fabs(info->bounds_min.x - lox) > TAB_TOL || fabs(info->bounds_min.y - loy) > TAB_TOL ||
            fabs(info->bounds_max.x - hix) > TAB_TOL || fabs(info->bounds_max.y - hiy) > TAB_TOL)
            fail_msg("%s: bounds (%g,%g)-(%g,%g), expected (%g,%g)-(%g,%g)", ref_tile_name(id),
                     (double)info->bounds_min.x, (double)info->bounds_min.y, (double)info->bounds_max.x,
                     (double)info->bounds_max.y, lox, loy, hix, hiy);
    }
}

/* ----------------------------------------------------------------- coverage */

static void test_side_coverage(void **state)
{
    (void)state;
    const int N = 1024; /* samples k/N: contains every interval end (0, 0.5, 1) */
    for (int id = 0; id < NTILES; id++) {
        const nt_tile_info *info = nt_tile_get_info(id);
        for (int side = 0; side < 4; side++) {
            int first = -1, last = -1, count = 0;
            for (int k = 0; k <= N; k++) {
                double u = (double)k / N, x, y;
                switch (side) {
                case NT_SIDE_LEFT: x = 0; y = u; break;
                case NT_SIDE_RIGHT: x = 1; y = u; break;
                case NT_SIDE_TOP: x = u; y = 0; break;
                default: x = u; y = 1; break;
                }
                if (ref_tile_signed_distance(id, x, y) <= 1e-12) { /* in the closed solid */
                    if (first < 0) first = k;
                    last = k;
                    count++;
                }
            }
            /* The covered part of a side is one interval (or a point, or nothing). */
            if (count) assert_int_equal(count, last - first + 1);
            double lo = info->cover_lo[side], hi = info->cover_hi[side];
            if (!count) {
                if (!(lo > hi)) fail_msg("%s side %d: covered [%g,%g], expected nothing", ref_tile_name(id), side, lo, hi);
            } else if (fabs(lo - (double)first / N) > TAB_TOL || fabs(hi - (double)last / N) > TAB_TOL) {
                fail_msg("%s side %d: covered [%g,%g], expected [%g,%g]", ref_tile_name(id), side, lo, hi,
                         (double)first / N, (double)last / N);
            }
        }
    }
}


/* ------------------------------------------------------------ internal tables agree */

/* The narrow phase's face table (nt__polys) is hand-kept data beside the edge table
 * (nt__geom) and the public table (vertices): the three must describe the same
 * polygons. Every edge is one used face with the same integer half-plane and unit
 * normal, ends at two of the tile's vertices, and faces come in the documented
 * order (the slope, then outward normals -y, +y, -x, +x); other tiles have no face. */
static void test_face_table_matches_edges(void **state)
{
    (void)state;
    for (int t = 0; t < NTILES; t++) {
        const nt__poly *pf = &nt__polys[t];
        const nt__tile_geom *g = &nt__geom[t];
        const nt_tile_info *info = &nt__tiles[t];
        int used = 0;
        for (int f = 0; f < 4; f++) used += pf->ud[f] != NT_REAL_MAX;
        if (info->cls != NT_CLASS_POLYGON) {
            assert_int_equal(used, 0);
            continue;
        }
        assert_int_equal(used, g->edge_count);
        /* Used faces first, in the documented order of normals. */
        int rank_prev = -1;
        for (int f = 0; f < used; f++) {
            const nt__face *fc = &pf->face[f];
            int rank = (fc->nx != 0 && fc->ny != 0) ? 0
                       : fc->ny < 0                 ? 1
                       : fc->ny > 0                 ? 2
                       : fc->nx < 0                 ? 3
                                                    : 4;
            assert_true(rank > rank_prev);
            rank_prev = rank;
        }
        for (int e = 0; e < g->edge_count; e++) {
            const nt__edge *ed = &g->edges[e];
            int match = -1;
            for (int f = 0; f < used; f++)
                if (pf->ux[f] == ed->ux && pf->uy[f] == ed->uy && pf->ud[f] == ed->ud) match = f;
            if (match < 0) fail_msg("tile %d: edge %d has no face", t, e);
            const nt__face *fc = &pf->face[match];
            assert_true(pf->inv[match] == ed->inv);
            assert_true(fc->nx == ed->nx && fc->ny == ed->ny);
            assert_true(fabs((double)fc->tx - (double)ed->tx) < TAB_TOL && fabs((double)fc->ty - (double)ed->ty) < TAB_TOL);
            /* Its ends: the edge's start and end, each a vertex of the tile, and on the
             * face's line. */
            double ends[2][2] = {{(double)ed->ax, (double)ed->ay},
                                 {(double)ed->ax + (double)ed->tx * (double)ed->len,
                                  (double)ed->ay + (double)ed->ty * (double)ed->len}};
            for (int q = 0; q < 2; q++) {
                assert_true(fabs((double)fc->vx[q] - ends[q][0]) < TAB_TOL);
                assert_true(fabs((double)fc->vy[q] - ends[q][1]) < TAB_TOL);
                int vertex = 0;
                for (int v = 0; v < info->vertex_count; v++)
                    vertex |= fabs((double)info->vertices[v].x - (double)fc->vx[q]) < TAB_TOL &&
                              fabs((double)info->vertices[v].y - (double)fc->vy[q]) < TAB_TOL;
                assert_true(vertex);
                double on = (double)pf->ux[match] * (double)fc->vx[q] + (double)pf->uy[match] * (double)fc->vy[q] -
                            (double)pf->ud[match];
                assert_true(fabs(on) < TAB_TOL);
            }
        }
        /* Outward: the vertices' centroid is inside every face. */
        double cx = 0, cy = 0;
        for (int v = 0; v < info->vertex_count; v++) {
            cx += (double)info->vertices[v].x / info->vertex_count;
            cy += (double)info->vertices[v].y / info->vertex_count;
        }
        for (int f = 0; f < used; f++)
            assert_true((double)pf->ux[f] * cx + (double)pf->uy[f] * cy - (double)pf->ud[f] < 0);
    }
}

/* Masking a tile's seam sides only takes ways out away: a shape clear of the tile
 * (by the reference) is clear with any mask too, for every tile, boxes of any size
 * and circles above half a cell up to NT_MAX_HALF_CELLS. (A large circle beside a
 * masked polygon corner used to get a push. A small one still does where its
 * neighbour's push is the same, kept so that recorded replays keep their bits.) */
static void test_masks_never_invent_overlap(void **state)
{
    (void)state;
    ref_rng rng = ref_rng_seed(5150);
    long checked = 0;
    for (int tile = 1; tile < NT_TILE_COUNT; tile++)
        for (int k = 0; k < 3000; k++) {
            double r = ref_rng_uniform(&rng, 0.05, NT_MAX_HALF_CELLS), hy = ref_rng_uniform(&rng, 0.05, NT_MAX_HALF_CELLS);
            int circle = k & 1;
            if (circle) r = ref_rng_uniform(&rng, 0.5001, NT_MAX_HALF_CELLS);
            ref_shape rs = circle ? ref_circle(r) : ref_aabb(r, hy);
            double x = ref_rng_uniform(&rng, -r - 1, r + 2), y = ref_rng_uniform(&rng, -rs.hh - 1, rs.hh + 2);
            if (ref_object_overlaps_tile(tile, ref_shape_grow(rs, 1e-6), x, y)) continue;
            unsigned mask = (unsigned)ref_rng_int(&rng, 16);
            nt_mtv m;
            nt_vec2 c = nt_v2((nt_real)x, (nt_real)y);
            int got = circle ? nt__collide_tile_circle_m(tile, c, (nt_real)r, mask, &m)
                             : nt__collide_tile_aabb_m(tile, c, nt_v2((nt_real)r, (nt_real)hy), mask, &m);
            if (got != NT__SEPARATE)
                fail_msg("tile %d mask %u %s %g x %g at (%g, %g): %d, but clear of the tile", tile, mask,
                         circle ? "circle" : "box", r, hy, x, y, got);
            checked++;
        }
    nt_mtv m;
    assert_int_equal(nt__collide_tile_circle_m(NT_TILE_45DEGpp, nt_v2((nt_real)1.3966, (nt_real)-1.2761), (nt_real)1.2773,
                                               1u << NT_SIDE_TOP, &m),
                     NT__SEPARATE);
    print_message("  %ld clear placements, every mask\n", checked);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names_roundtrip),
        cmocka_unit_test(test_unknown_names_and_ids),
        cmocka_unit_test(test_classes_and_signs),
        cmocka_unit_test(test_contains_point_random),
        cmocka_unit_test(test_contains_point_hand),
        cmocka_unit_test(test_contains_point_boundary),
        cmocka_unit_test(test_normals_polygon),
        cmocka_unit_test(test_normals_empty_and_round),
        cmocka_unit_test(test_vertices_and_arcs),
        cmocka_unit_test(test_bounds),
        cmocka_unit_test(test_side_coverage),
        cmocka_unit_test(test_face_table_matches_edges),
        cmocka_unit_test(test_masks_never_invent_overlap),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
