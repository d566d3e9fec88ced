/* Narrow phase against the independent reference (tests/ref.c), hand-computed cases,
 * and object pairs against a brute force written here.
 *
 * Every input is rounded to nt_real first, so the engine and the reference see the
 * same numbers; the reference then works in double. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "ntile/ntile.h"
#include "ref.h"

/* Depth agreement: float carries ~1e-7 error through a few operations (the largest
 * seen is 1.5e-7, so 1e-5 leaves room); the reference is exact to ~1e-9. */
static const double DEPTH_TOL = NT_REAL_IS_DOUBLE ? 1e-8 : 1e-5;
static const double UNIT_TOL = NT_REAL_IS_DOUBLE ? 1e-9 : 1e-5;
static const double NORMAL_TOL = NT_REAL_IS_DOUBLE ? 1e-9 : 1e-5;
/* Freeing checks: the object is free after moving by normal * (depth + FREE_MARGIN) and
 * still overlapping after normal * (depth - BACK_OFF). */
static const double FREE_MARGIN = NT_REAL_IS_DOUBLE ? 1e-7 : 1e-4;
static const double BACK_OFF = NT_REAL_IS_DOUBLE ? 1e-6 : 1e-3;
/* Cases this close to touching are ambiguous in float: skipped in random runs. */
static const double TOUCH_SKIP = 1e-5;

static double rr(double x) { return (double)(nt_real)x; }

static const char *shape_str(ref_shape s, char *buf, size_t n)
{
    if (s.is_circle) snprintf(buf, n, "circle r=%.9g", s.hw);
    else snprintf(buf, n, "box %.9gx%.9g", s.hw, s.hh);
    return buf;
}

/* ------------------------------------------------------- engine wrappers */

static int g_api_mismatch;
static double g_max_err;

/* The tile routine for the shape; also checks that nt_tile_collide_shape and a NULL
 * output give the same answer. */
static bool eng_tile(int tile, ref_shape s, double cx, double cy, nt_mtv *m)
{
    nt_vec2 c = nt_v2((nt_real)cx, (nt_real)cy);
    nt_shape sh = s.is_circle ? nt_shape_circle((nt_real)s.hw) : nt_shape_aabb((nt_real)s.hw, (nt_real)s.hh);
    bool r = s.is_circle ? nt_tile_collide_circle(tile, c, (nt_real)s.hw, m)
                         : nt_tile_collide_aabb(tile, c, sh.half, m);
    nt_mtv m2;
    bool r2 = nt_tile_collide_shape(tile, c, sh, &m2);
    bool r3 = s.is_circle ? nt_tile_collide_circle(tile, c, (nt_real)s.hw, NULL)
                          : nt_tile_collide_aabb(tile, c, sh.half, NULL);
    if (r2 != r || r3 != r ||
        (r && (m2.depth != m->depth || m2.normal.x != m->normal.x || m2.normal.y != m->normal.y)))
        g_api_mismatch++;
    return r;
}

/* Checks every verdict-independent property of an MTV against the reference: unit
 * normal; moving by depth (+FREE_MARGIN) frees the object; moving by depth - BACK_OFF
 * does not. Returns a description of the first problem, or NULL. */
static const char *check_mtv_frees(int tile, ref_shape s, double cx, double cy, const nt_mtv *m)
{
    double nx = m->normal.x, ny = m->normal.y, d = m->depth;
    if (!(fabs(hypot(nx, ny) - 1) <= UNIT_TOL)) return "normal is not unit length";
    if (!(d > 0)) return "depth is not positive";
    double f = d + FREE_MARGIN, b = d - BACK_OFF;
    if (ref_object_overlaps_tile(tile, s, cx + nx * f, cy + ny * f))
        return "moving by normal*(depth+margin) does not free the object";
    if (b > 0 && !ref_object_overlaps_tile(tile, s, cx + nx * b, cy + ny * b))
        return "moving by normal*(depth-back_off) already frees the object (depth too large)";
    return NULL;
}

/* One placement against the reference. Returns -1 when the object is within
 * TOUCH_SKIP of touching (not checked), else whether it overlaps; a wrong verdict, a
 * depth off the reference minimum or an MTV that does not free the object counts in
 * *failures (the first 12 printed, prefixed with label). Tracks the largest depth
 * error in g_max_err. */
static int check_placement(const char *label, int tile, ref_shape s, double cx, double cy, int *failures)
{
    char buf[96];
    bool lo = ref_object_overlaps_tile(tile, ref_shape_grow(s, -TOUCH_SKIP), cx, cy);
    bool hi = ref_object_overlaps_tile(tile, ref_shape_grow(s, TOUCH_SKIP), cx, cy);
    if (lo != hi) return -1;
    nt_mtv m = {{0, 0}, 0};
    bool got = eng_tile(tile, s, cx, cy, &m);
    const char *why = NULL;
    double want_d = 0;
    if (got != lo) {
        why = lo ? "engine misses an overlap" : "engine reports an overlap that is not there";
    } else if (lo) {
        want_d = ref_mtv_tile(tile, s, cx, cy, NULL, NULL);
        double err = fabs(m.depth - want_d);
        if (err > g_max_err) g_max_err = err;
        if (!(err <= DEPTH_TOL)) why = "depth differs from the reference minimum";
        else why = check_mtv_frees(tile, s, cx, cy, &m);
    }
    if (why && (*failures)++ < 12)
        print_message("%s%s, %s at (%.9g, %.9g): %s (engine %d depth %.9g normal (%.6g,%.6g); "
                      "reference %d depth %.9g)\n",
                      label, ref_tile_name(tile), shape_str(s, buf, sizeof buf), cx, cy, why, got, (double)m.depth,
                      (double)m.normal.x, (double)m.normal.y, lo, want_d);
    return lo;
}

/* --------------------------------------------------- (a) random placements */

/* Bodies up to NT_MAX_HALF_CELLS (issue 18): half-sizes 0.5..4 cells, boxes also thin
 * one way (0.02..0.3 against up to 4, e.g. a 0.1 x 4 plank), centres anywhere the object
 * can reach the tile. */
static ref_shape large_shape(ref_rng *rng, int circle)
{
    double a = rr(ref_rng_uniform(rng, 0.5, NT_MAX_HALF_CELLS)), b = rr(ref_rng_uniform(rng, 0.5, NT_MAX_HALF_CELLS));
    if (circle) return ref_circle(a);
    int thin = ref_rng_int(rng, 3);
    if (thin == 1) b = rr(ref_rng_uniform(rng, 0.02, 0.3));
    if (thin == 2) return ref_aabb(rr(ref_rng_uniform(rng, 0.02, 0.3)), b);
    return ref_aabb(a, b);
}

static void run_random(int circle, int large, int per_tile, unsigned long long seed)
{
    int failures = 0, overlaps = 0, checked = 0;
    g_api_mismatch = 0;
    g_max_err = 0;
    for (int tile = 1; tile < NT_TILE_COUNT; tile++) {
        ref_rng rng = ref_rng_seed(seed * 1000 + (unsigned long long)tile);
        int tile_overlaps = 0;
        for (int i = 0; i < per_tile; i++) {
            ref_shape s;
            double cx, cy;
            if (large) {
                s = large_shape(&rng, circle);
                cx = rr(ref_rng_uniform(&rng, -0.3 - s.hw, 1.3 + s.hw));
                cy = rr(ref_rng_uniform(&rng, -0.3 - s.hh, 1.3 + s.hh));
            } else {
                s = circle ? ref_circle(rr(ref_rng_uniform(&rng, 0.02, 0.5)))
                           : ref_aabb(rr(ref_rng_uniform(&rng, 0.02, 0.5)), rr(ref_rng_uniform(&rng, 0.02, 0.5)));
                if (i % 20 == 0) s = circle ? ref_circle(0) : ref_aabb(0, 0); /* a point */
                cx = rr(ref_rng_uniform(&rng, -0.6, 1.6));
                cy = rr(ref_rng_uniform(&rng, -0.6, 1.6));
            }
            int r = check_placement(large ? "large: " : "", tile, s, cx, cy, &failures);
            checked += r >= 0;
            overlaps += r > 0;
            tile_overlaps += r > 0;
        }
        /* Enough overlapping placements per tile for the depth checks to mean something. */
        if (tile_overlaps < per_tile / 8) fail_msg("%s: only %d overlaps", ref_tile_name(tile), tile_overlaps);
    }
    print_message("%s%s: %d placements checked, %d overlapping, %d failures, largest depth error %.3g\n",
                  large ? "large " : "", circle ? "circle" : "box", checked, overlaps, failures, g_max_err);
    assert_int_equal(g_api_mismatch, 0);
    assert_int_equal(failures, 0);
}

static void test_random_box(void **state)
{
    (void)state;
    run_random(0, 0, 2000, 11);
}

static void test_random_circle(void **state)
{
    (void)state;
    run_random(1, 0, 2000, 12);
}

static void test_random_large_box(void **state)
{
    (void)state;
    run_random(0, 1, 1500, 31);
}

static void test_random_large_circle(void **state)
{
    (void)state;
    run_random(1, 1, 1500, 32);
}

/* Large objects with their surface near the tile's: the box's corner (or the circle's
 * rim) within 1e-2 of a tile vertex, where the routines decide between pieces. */
static void test_large_near_vertices(void **state)
{
    (void)state;
    int failures = 0, overlaps = 0;
    ref_rng rng = ref_rng_seed(4343);
    for (int tile = 1; tile < NT_TILE_COUNT; tile++) {
        for (int i = 0; i < 600; i++) {
            int circle = i & 1;
            ref_shape s = large_shape(&rng, circle);
            double vx = ref_rng_int(&rng, 3) / 2.0, vy = ref_rng_int(&rng, 3) / 2.0;
            double scale = pow(10, -ref_rng_uniform(&rng, 2, 6));
            double ex = scale * ref_rng_uniform(&rng, -1, 1), ey = scale * ref_rng_uniform(&rng, -1, 1);
            double cx, cy;
            if (circle) { /* the rim through the vertex, from any direction */
                double a = ref_rng_uniform(&rng, 0, 2 * 3.14159265358979323846);
                cx = rr(vx + s.hw * cos(a) + ex);
                cy = rr(vy + s.hw * sin(a) + ey);
            } else {
                cx = rr(vx + ex + (ref_rng_int(&rng, 2) ? s.hw : -s.hw));
                cy = rr(vy + ey + (ref_rng_int(&rng, 2) ? s.hh : -s.hh));
            }
            overlaps += check_placement("large near vertex: ", tile, s, cx, cy, &failures) > 0;
        }
    }
    print_message("large near vertices: %d overlaps, %d failures\n", overlaps, failures);
    assert_true(overlaps > 4000);
    assert_int_equal(failures, 0);
}

/* Small objects near the boundary: sizes 0.001..0.05 and centres on a thin band around
 * the tile's surface, where most of the case analysis happens. */
static void test_random_small_near_surface(void **state)
{
    (void)state;
    int failures = 0;
    ref_rng rng = ref_rng_seed(77);
    for (int tile = 1; tile < NT_TILE_COUNT; tile++) {
        for (int i = 0; i < 600; i++) {
            int circle = i & 1;
            ref_shape s = circle ? ref_circle(rr(ref_rng_uniform(&rng, 0.001, 0.05)))
                                 : ref_aabb(rr(ref_rng_uniform(&rng, 0.001, 0.05)), rr(ref_rng_uniform(&rng, 0.001, 0.05)));
            double cx = rr(ref_rng_uniform(&rng, -0.1, 1.1)), cy = rr(ref_rng_uniform(&rng, -0.1, 1.1));
            if (fabs(ref_tile_signed_distance(tile, cx, cy)) > 0.08) continue;
            check_placement("", tile, s, cx, cy, &failures);
        }
    }
    assert_int_equal(failures, 0);
}

/* Centres within 1e-6 to 1e-2 of a tile vertex or cusp (every vertex lies on the
 * 1/2 grid), inside and outside: where the routines decide between a face and a
 * vertex, and where rounding picks the side. */
static void test_near_vertices(void **state)
{
    (void)state;
    int failures = 0, overlaps = 0;
    ref_rng rng = ref_rng_seed(4242);
    for (int tile = 1; tile < NT_TILE_COUNT; tile++) {
        for (int i = 0; i < 3000; i++) {
            int circle = i & 1;
            ref_shape s = circle ? ref_circle(rr(ref_rng_uniform(&rng, 0.02, 0.5)))
                                 : ref_aabb(rr(ref_rng_uniform(&rng, 0.02, 0.5)), rr(ref_rng_uniform(&rng, 0.02, 0.5)));
            double vx = ref_rng_int(&rng, 3) / 2.0, vy = ref_rng_int(&rng, 3) / 2.0;
            double scale = pow(10, -ref_rng_uniform(&rng, 2, 6));
            double cx = rr(vx + scale * ref_rng_uniform(&rng, -1, 1)), cy = rr(vy + scale * ref_rng_uniform(&rng, -1, 1));
            if (!circle) { /* a box's corner near the vertex, not its centre */
                cx = rr(cx + (ref_rng_int(&rng, 2) ? s.hw : -s.hw));
                cy = rr(cy + (ref_rng_int(&rng, 2) ? s.hh : -s.hh));
            }
            overlaps += check_placement("near vertex: ", tile, s, cx, cy, &failures) > 0;
        }
    }
    print_message("near vertices: %d overlaps, %d failures\n", overlaps, failures);
    assert_true(overlaps > 20000);
    assert_int_equal(failures, 0);
}

/* Placements on a 1/16 grid (exact in binary): centres on vertices, edges and cusps,
 * sizes that make exact contacts. The reference is exact on these inputs (its box test
 * uses only products of grid values by 0.5 or 1; circles meet slopes only at vertices).
 * Exact contacts must not count as overlaps; everything else as in the random runs. */
static void run_grid(int large)
{
    int failures = 0, contacts = 0, contact_failures = 0, overlaps = 0, per_tile[NT_TILE_COUNT] = {0};
    char buf[96];
    ref_rng rng = ref_rng_seed(large ? 2025 : 2024);
    for (int tile = 1; tile < NT_TILE_COUNT; tile++) {
        for (int i = 0; i < 1500; i++) {
            int circle = i & 1;
            /* Sizes in sixteenths: 1..8 (up to half a cell), or 8..64 (up to NT_MAX_HALF_CELLS)
             * with one side of a box sometimes thin; centres over the reach of the object. */
            int a16 = 1 + ref_rng_int(&rng, 8), b16 = 1 + ref_rng_int(&rng, 8);
            if (large) {
                a16 = 8 + ref_rng_int(&rng, 16 * NT_MAX_HALF_CELLS - 7);
                b16 = ref_rng_int(&rng, 3) ? 8 + ref_rng_int(&rng, 16 * NT_MAX_HALF_CELLS - 7) : 1 + ref_rng_int(&rng, 4);
            }
            double a = a16 / 16.0, b = b16 / 16.0;
            ref_shape s = circle ? ref_circle(a) : ref_aabb(a, b);
            int ex = 8 + (large ? a16 : 0), ey = 8 + (large ? (circle ? a16 : b16) : 0);
            double cx = (ref_rng_int(&rng, 17 + 2 * ex) - ex) / 16.0, cy = (ref_rng_int(&rng, 17 + 2 * ey) - ey) / 16.0;
            bool exact = ref_object_overlaps_tile(tile, s, cx, cy);
            bool lo = ref_object_overlaps_tile(tile, ref_shape_grow(s, -TOUCH_SKIP), cx, cy);
            bool hi = ref_object_overlaps_tile(tile, ref_shape_grow(s, TOUCH_SKIP), cx, cy);
            nt_mtv m = {{0, 0}, 0};
            bool got = eng_tile(tile, s, cx, cy, &m);
            const char *why = NULL;
            double want_d = 0;
            if (lo != hi) {
                if (exact) continue; /* overlap shallower than 1e-5: not on this grid */
                contacts++;
                if (got) {
                    why = "exact contact reported as an overlap";
                    contact_failures++;
                    per_tile[tile]++;
                }
            } else if (got != lo) {
                why = lo ? "engine misses an overlap" : "engine reports an overlap that is not there";
            } else if (lo) {
                overlaps++;
                want_d = ref_mtv_tile(tile, s, cx, cy, NULL, NULL);
                if (!(fabs(m.depth - want_d) <= DEPTH_TOL)) why = "depth differs from the reference minimum";
                else why = check_mtv_frees(tile, s, cx, cy, &m);
            }
            if (why && failures++ < 16)
                print_message("grid: %s, %s at (%g, %g): %s (engine %d depth %.9g normal (%.6g,%.6g); "
                              "reference %d depth %.9g)\n",
                              ref_tile_name(tile), shape_str(s, buf, sizeof buf), cx, cy, why, got, (double)m.depth,
                              (double)m.normal.x, (double)m.normal.y, exact, want_d);
        }
    }
    print_message("grid%s: %d overlaps, %d exact contacts (%d reported as overlaps), %d failures\n", large ? " (large)" : "",
                  overlaps, contacts, contact_failures, failures);
    for (int t = 0; t < NT_TILE_COUNT; t++)
        if (per_tile[t]) print_message("grid: %s: %d exact contacts reported as overlaps\n", ref_tile_name(t), per_tile[t]);
    assert_true(contacts > 1000 && overlaps > 10000);
    assert_int_equal(failures, 0);
}

static void test_grid_placements(void **state)
{
    (void)state;
    run_grid(0);
}

static void test_grid_placements_large(void **state)
{
    (void)state;
    run_grid(1);
}

static void test_empty_and_invalid_tiles(void **state)
{
    (void)state;
    nt_mtv m;
    const int tiles[] = {NT_TILE_EMPTY, -1, 34, 1000};
    for (size_t i = 0; i < sizeof tiles / sizeof tiles[0]; i++) {
        assert_false(nt_tile_collide_aabb(tiles[i], nt_v2(0.5f, 0.5f), nt_v2(0.5f, 0.5f), &m));
        assert_false(nt_tile_collide_circle(tiles[i], nt_v2(0.5f, 0.5f), 0.5f, &m));
        assert_false(nt_tile_collide_shape(tiles[i], nt_v2(0.5f, 0.5f), nt_shape_circle(0.25f), &m));
        assert_false(nt_tile_collide_aabb(tiles[i], nt_v2(0.5f, 0.5f), nt_v2(0, 0), &m));
    }
}

/* ------------------------------------------------ (b) hand-computed cases */

#define S2 0.70710678118654752 /* 1/sqrt2 */
#define S5A 0.44721359549995794 /* 1/sqrt5 */
#define S5B 0.89442719099991588 /* 2/sqrt5 */

enum { BOX = 0, CIRCLE = 1, POINT = 2 };

typedef struct hc {
    int tile;      /* pn tiles are also run mirrored into nn, np, pp */
    int shape;     /* BOX, CIRCLE, POINT (run as both a 0x0 box and a radius-0 circle) */
    double hw, hh; /* circle: hw = r */
    double cx, cy;
    int overlap;
    double depth;
    int nn;        /* allowed normals (ties); 0 = any direction that frees the object */
    double n[4][2];
} hc;

/* Expected values worked out by hand from the geometry in the notes. */
static const hc HAND[] = {
    /* FULL: box / circle / point centred, max-size box, corner and side contacts. */
    {NT_TILE_FULL, BOX, 0.25, 0.25, 0.5, 0.5, 1, 0.75, 4, {{1, 0}, {-1, 0}, {0, 1}, {0, -1}}},
    {NT_TILE_FULL, BOX, 0.5, 0.25, 0.5, 0.5, 1, 0.75, 2, {{0, 1}, {0, -1}}},
    {NT_TILE_FULL, BOX, 0.5, 0.5, 0.5, 0.5, 1, 1.0, 4, {{1, 0}, {-1, 0}, {0, 1}, {0, -1}}},
    {NT_TILE_FULL, CIRCLE, 0.25, 0.25, 0.5, 0.5, 1, 0.75, 4, {{1, 0}, {-1, 0}, {0, 1}, {0, -1}}},
    {NT_TILE_FULL, POINT, 0, 0, 0.5, 0.5, 1, 0.5, 4, {{1, 0}, {-1, 0}, {0, 1}, {0, -1}}},
    {NT_TILE_FULL, POINT, 0, 0, 0.25, 0.5, 1, 0.25, 1, {{-1, 0}}},
    {NT_TILE_FULL, POINT, 0, 0, 0, 0.5, 0, 0, 0, {{0}}},
    {NT_TILE_FULL, POINT, 0, 0, 0.5, 0, 0, 0, 0, {{0}}},
    {NT_TILE_FULL, POINT, 0, 0, 0, 0, 0, 0, 0, {{0}}},
    {NT_TILE_FULL, POINT, 0, 0, 1, 1, 0, 0, 0, {{0}}},
    {NT_TILE_FULL, BOX, 0.25, 0.25, -0.25, 0.5, 0, 0, 0, {{0}}},         /* side contact */
    {NT_TILE_FULL, CIRCLE, 0.25, 0.25, -0.25, 0.5, 0, 0, 0, {{0}}},      /* side contact */
    {NT_TILE_FULL, CIRCLE, 0.3125, 0.3125, -0.1875, -0.25, 0, 0, 0, {{0}}}, /* corner contact (3-4-5) */
    {NT_TILE_FULL, BOX, 0.25, 0.25, -0.25, -0.25, 0, 0, 0, {{0}}},       /* corner to corner */
    {NT_TILE_FULL, BOX, 0.25, 0.25, -0.1875, -0.125, 1, 0.0625, 1, {{-1, 0}}},
    {NT_TILE_FULL, CIRCLE, 0.5, 0.5, -0.1875, -0.25, 1, 0.1875, 1, {{-0.6, -0.8}}},
    {NT_TILE_FULL, BOX, 0.25, 0.25, 1.0, 0.5, 1, 0.25, 1, {{1, 0}}},
    /* 45DEGpn: triangle (0,0) (0,1) (1,1); surface normal (1,-1)/sqrt2. */
    {NT_TILE_45DEGpn, CIRCLE, 0.25, 0.25, 0.5, 0.5, 1, 0.25, 1, {{S2, -S2}}},      /* centre on hypotenuse */
    {NT_TILE_45DEGpn, BOX, 0.25, 0.25, 0.5, 0.5, 1, 0.5 * S2, 1, {{S2, -S2}}},     /* corner 0.5/sqrt2 deep */
    {NT_TILE_45DEGpn, BOX, 0.25, 0.25, 1, 1, 1, 0.25, 2, {{1, 0}, {0, 1}}},        /* centre on a vertex */
    {NT_TILE_45DEGpn, CIRCLE, 0.25, 0.25, 0, 0, 1, 0.25, 0, {{0}}},                /* on the apex: r in its cone */
    {NT_TILE_45DEGpn, POINT, 0, 0, 0.25, 0.75, 1, 0.25, 2, {{-1, 0}, {0, 1}}},
    {NT_TILE_45DEGpn, POINT, 0, 0, 0.0625, 0.125, 1, 0.0625 * S2, 1, {{S2, -S2}}},
    {NT_TILE_45DEGpn, POINT, 0, 0, 0.5, 0.5, 0, 0, 0, {{0}}},
    {NT_TILE_45DEGpn, POINT, 0, 0, 1, 1, 0, 0, 0, {{0}}},
    {NT_TILE_45DEGpn, BOX, 0.25, 0.25, 0.75, 0.25, 0, 0, 0, {{0}}},                /* corner on hypotenuse */
    {NT_TILE_45DEGpn, CIRCLE, 0.125, 0.125, 0.25, 1, 1, 0.125, 1, {{0, 1}}},       /* centre on bottom side */
    /* CONVEXpn: quarter disc radius 1 around (0,1). */
    {NT_TILE_CONVEXpn, CIRCLE, 0.25, 0.25, 0, 1, 1, 0.25, 0, {{0}}},               /* on the arc centre */
    {NT_TILE_CONVEXpn, BOX, 0.25, 0.25, 0, 1, 1, 0.25, 2, {{-1, 0}, {0, 1}}},
    {NT_TILE_CONVEXpn, CIRCLE, 0.25, 0.25, 0.5, 0.5, 1, 1.25 - S2, 1, {{S2, -S2}}},
    {NT_TILE_CONVEXpn, BOX, 0.25, 0.25, 0.5, 0.5, 1, 1 - 0.5 * S2, 1, {{S2, -S2}}},
    {NT_TILE_CONVEXpn, POINT, 0, 0, 0.5, 0.5, 1, 1 - S2, 1, {{S2, -S2}}},
    {NT_TILE_CONVEXpn, CIRCLE, 0.25, 0.25, 1, 0, 0, 0, 0, {{0}}},                  /* gap sqrt2-1 > r */
    {NT_TILE_CONVEXpn, CIRCLE, 0.5, 0.5, 1, 0, 1, 1.5 - 2 * S2, 1, {{S2, -S2}}},   /* gap sqrt2-1 < r */
    {NT_TILE_CONVEXpn, BOX, 0.25, 0.25, 1.25, 0.75, 0, 0, 0, {{0}}},               /* touches (1,1) */
    {NT_TILE_CONVEXpn, POINT, 0, 0, 1, 1, 0, 0, 0, {{0}}},
    {NT_TILE_CONVEXpn, POINT, 0, 0, 0, 0, 0, 0, 0, {{0}}},
    /* CONCAVEpn: cell minus disc radius 1 around (1,0). */
    {NT_TILE_CONCAVEpn, CIRCLE, 0.25, 0.25, 1, 0, 0, 0, 0, {{0}}},                 /* on the arc centre */
    {NT_TILE_CONCAVEpn, CIRCLE, 0.5, 0.5, 1, 0, 0, 0, 0, {{0}}},
    {NT_TILE_CONCAVEpn, BOX, 0.5, 0.5, 1, 0, 0, 0, 0, {{0}}},                      /* corner (0.5,0.5) in disc */
    {NT_TILE_CONCAVEpn, CIRCLE, 0.25, 0.25, 0, 0, 1, 0.25, 0, {{0}}},              /* on the cusp */
    {NT_TILE_CONCAVEpn, BOX, 0.25, 0.25, 0, 0, 1, 0.25, 2, {{-1, 0}, {0, -1}}},
    {NT_TILE_CONCAVEpn, CIRCLE, 0.125, 0.125, 0.25, 0.75, 1, 0.75 * 2 * S2 - 0.875, 1, {{S2, -S2}}},
    {NT_TILE_CONCAVEpn, BOX, 0.125, 0.125, 0.125, 0.875, 1, 0.25, 2, {{-1, 0}, {0, 1}}},
    {NT_TILE_CONCAVEpn, POINT, 0, 0, 0.125, 0.875, 1, 0.125, 2, {{-1, 0}, {0, 1}}},
    {NT_TILE_CONCAVEpn, POINT, 0, 0, 0.5, 0.5, 0, 0, 0, {{0}}},
    {NT_TILE_CONCAVEpn, POINT, 0, 0, 0, 1, 0, 0, 0, {{0}}},
    {NT_TILE_CONCAVEpn, BOX, 0.25, 0.25, 1.25, 0.75, 0, 0, 0, {{0}}},              /* touches the cusp (1,1) */
    /* 22DEGpnS: (0,0.5) (0,1) (1,1); surface y = 0.5 + x/2, normal (1,-2)/sqrt5. */
    {NT_TILE_22DEGpnS, POINT, 0, 0, 0.25, 0.875, 1, 0.125, 1, {{0, 1}}},
    {NT_TILE_22DEGpnS, BOX, 0.25, 0.125, 0.5, 0.75, 1, 0.5 * S5A, 1, {{S5A, -S5B}}}, /* centre on surface */
    {NT_TILE_22DEGpnS, POINT, 0, 0, 0.5, 0.75, 0, 0, 0, {{0}}},
    {NT_TILE_22DEGpnS, BOX, 0.125, 0.125, 0.375, 0.5, 0, 0, 0, {{0}}},             /* corner on surface */
    {NT_TILE_22DEGpnS, CIRCLE, 0.25, 0.25, 0, 0.25, 0, 0, 0, {{0}}},               /* touches the tip */
    /* 22DEGpnB: (0,0) (1,0.5) (1,1) (0,1); surface y = x/2. */
    {NT_TILE_22DEGpnB, BOX, 0.125, 0.125, 0.625, 0.125, 0, 0, 0, {{0}}},           /* corner on surface */
    {NT_TILE_22DEGpnB, POINT, 0, 0, 0.5, 0.25, 0, 0, 0, {{0}}},
    {NT_TILE_22DEGpnB, POINT, 0, 0, 0.5, 0.375, 1, 0.25 * S5A, 1, {{S5A, -S5B}}},
    /* 67DEGpnS: (0,0) (0,1) (0.5,1); surface y = 2x, normal (2,-1)/sqrt5. */
    {NT_TILE_67DEGpnS, CIRCLE, 0.125, 0.125, 0.25, 0.5, 1, 0.125, 1, {{S5B, -S5A}}}, /* centre on surface */
    {NT_TILE_67DEGpnS, POINT, 0, 0, 0.125, 0.5, 1, 0.25 * S5A, 1, {{S5B, -S5A}}},
    /* 67DEGpnB: (0,0) (0.5,0) (1,1) (0,1); surface y = 2x - 1. */
    {NT_TILE_67DEGpnB, POINT, 0, 0, 0.75, 0.5, 0, 0, 0, {{0}}},
    {NT_TILE_67DEGpnB, POINT, 0, 0, 0.5, 0.5, 1, 0.5 * S5A, 1, {{S5B, -S5A}}},
    {NT_TILE_67DEGpnB, BOX, 0.25, 0.25, 0.5, 0.5, 1, 1.25 * S5A, 1, {{S5B, -S5A}}},
    /* HALF tiles. */
    {NT_TILE_HALFd, BOX, 0.25, 0.25, 0.5, 0.5, 1, 0.25, 1, {{0, -1}}},
    {NT_TILE_HALFd, CIRCLE, 0.25, 0.25, 0.5, 0.25, 0, 0, 0, {{0}}},                /* touches the top face */
    {NT_TILE_HALFd, CIRCLE, 0.25, 0.25, -0.25, 0.5, 0, 0, 0, {{0}}},               /* touches corner (0,0.5) */
    {NT_TILE_HALFd, CIRCLE, 0.25, 0.25, -0.125, 0.375, 1, 0.25 - 0.25 * S2, 1, {{-S2, -S2}}},
    {NT_TILE_HALFd, POINT, 0, 0, 0.5, 0.5, 0, 0, 0, {{0}}},
    {NT_TILE_HALFd, POINT, 0, 0, 0.5, 0.75, 1, 0.25, 2, {{0, -1}, {0, 1}}},
    {NT_TILE_HALFr, BOX, 0.25, 0.25, 0.5, 0.5, 1, 0.25, 1, {{-1, 0}}},
    {NT_TILE_HALFr, POINT, 0, 0, 0.5, 0.5, 0, 0, 0, {{0}}},
    {NT_TILE_HALFu, BOX, 0.25, 0.25, 0.5, 0.5, 1, 0.25, 1, {{0, 1}}},
    {NT_TILE_HALFu, CIRCLE, 0.25, 0.25, 0.5, 0.75, 0, 0, 0, {{0}}},
    {NT_TILE_HALFl, BOX, 0.25, 0.25, 0.5, 0.5, 1, 0.25, 1, {{1, 0}}},
    {NT_TILE_HALFl, CIRCLE, 0.125, 0.125, 0.5, 0.5, 1, 0.125, 1, {{1, 0}}},        /* centre on the face */
    /* EMPTY never collides. */
    {NT_TILE_EMPTY, BOX, 0.5, 0.5, 0.5, 0.5, 0, 0, 0, {{0}}},
    {NT_TILE_EMPTY, CIRCLE, 0.5, 0.5, 0.5, 0.5, 0, 0, 0, {{0}}},
    {NT_TILE_EMPTY, POINT, 0, 0, 0.5, 0.5, 0, 0, 0, {{0}}},
};

static void test_hand_cases(void **state)
{
    (void)state;
    int failures = 0;
    char buf[96];
    for (size_t i = 0; i < sizeof HAND / sizeof HAND[0]; i++) {
        const hc *h = &HAND[i];
        int family = h->tile >= 2 && h->tile < 30;
        for (int k = 0; k < (family ? 4 : 1); k++) {
            /* pn -> nn, np, pp: mirror x for nn and np, y for np and pp (notes). */
            int mx = k == 1 || k == 2, my = k >= 2, tile = h->tile + k;
            double cx = mx ? 1 - h->cx : h->cx, cy = my ? 1 - h->cy : h->cy;
            for (int variant = 0; variant < (h->shape == POINT ? 2 : 1); variant++) {
                ref_shape s = h->shape == BOX      ? ref_aabb(h->hw, h->hh)
                              : h->shape == CIRCLE ? ref_circle(h->hw)
                              : variant == 0       ? ref_aabb(0, 0)
                                                   : ref_circle(0);
                nt_mtv m = {{0, 0}, 0};
                bool got = eng_tile(tile, s, cx, cy, &m);
                const char *why = NULL;
                /* The reference must reproduce the hand value too. */
                double rd = ref_mtv_tile(tile, s, cx, cy, NULL, NULL);
                if (ref_object_overlaps_tile(tile, s, cx, cy) != (bool)h->overlap || fabs(rd - h->depth) > 1e-9)
                    fail_msg("reference disagrees with hand case %zu (%s): depth %.12g vs %.12g", i, ref_tile_name(tile),
                             rd, h->depth);
                if (got != (bool)h->overlap) {
                    why = h->overlap ? "no overlap reported" : "overlap reported for a contact or a miss";
                } else if (got) {
                    if (!(fabs(m.depth - h->depth) <= DEPTH_TOL)) why = "wrong depth";
                    else if (h->nn > 0) {
                        int ok = 0;
                        for (int j = 0; j < h->nn; j++) {
                            double ex = mx ? -h->n[j][0] : h->n[j][0], ey = my ? -h->n[j][1] : h->n[j][1];
                            if (fabs(m.normal.x - ex) <= NORMAL_TOL && fabs(m.normal.y - ey) <= NORMAL_TOL) ok = 1;
                        }
                        if (!ok) why = "normal is not one of the minimising directions";
                    }
                    if (!why) why = check_mtv_frees(tile, s, cx, cy, &m);
                }
                if (why && failures++ < 20)
                    print_message("hand case %zu: %s, %s at (%g, %g): %s (engine %d depth %.9g normal (%.6g,%.6g); "
                                  "expected %d depth %.9g)\n",
                                  i, ref_tile_name(tile), shape_str(s, buf, sizeof buf), cx, cy, why, got,
                                  (double)m.depth, (double)m.normal.x, (double)m.normal.y, h->overlap, h->depth);
            }
        }
    }
    assert_int_equal(g_api_mismatch, 0);
    assert_int_equal(failures, 0);
}

/* --------------------------------------------------------------- (c) pairs */

/* Brute force for pairs: the exact overlap predicate, and the MTV by sampled
 * directions (the overlapping set of centres is convex, so along each ray there is one
 * exit point: bisection), refined by golden section around the best local minima. */
static bool pair_overlap(ref_shape a, double ax, double ay, ref_shape b, double bx, double by)
{
    if (!a.is_circle && !b.is_circle) return fabs(ax - bx) < a.hw + b.hw && fabs(ay - by) < a.hh + b.hh;
    if (a.is_circle && b.is_circle) {
        double dx = ax - bx, dy = ay - by, r = a.hw + b.hw;
        return dx * dx + dy * dy < r * r;
    }
    const ref_shape *box = a.is_circle ? &b : &a, *cir = a.is_circle ? &a : &b;
    double px = a.is_circle ? bx : ax, py = a.is_circle ? by : ay; /* box centre */
    double qx = a.is_circle ? ax : bx, qy = a.is_circle ? ay : by; /* circle centre */
    double nx = fmin(fmax(qx, px - box->hw), px + box->hw), ny = fmin(fmax(qy, py - box->hh), py + box->hh);
    return (qx - nx) * (qx - nx) + (qy - ny) * (qy - ny) < cir->hw * cir->hw;
}

static double pair_exit(ref_shape a, double ax, double ay, ref_shape b, double bx, double by, double th)
{
    double ux = cos(th), uy = sin(th), lo = 0, hi = 3;
    for (int i = 0; i < 56; i++) {
        double mid = 0.5 * (lo + hi);
        if (pair_overlap(a, ax + mid * ux, ay + mid * uy, b, bx, by)) lo = mid;
        else hi = mid;
    }
    return hi;
}

static double pair_mtv_ref(ref_shape a, double ax, double ay, ref_shape b, double bx, double by)
{
    enum { N = 256 };
    double t[N], best = INFINITY;
    const double th0 = 0.0731, dth = 2 * 3.14159265358979323846 / N;
    for (int k = 0; k < N; k++) t[k] = pair_exit(a, ax, ay, b, bx, by, th0 + k * dth);
    for (int pick = 0; pick < 4; pick++) {
        int kb = -1;
        for (int k = 0; k < N; k++)
            if (t[k] <= t[(k + 1) % N] && t[k] <= t[(k + N - 1) % N] && (kb < 0 || t[k] < t[kb])) kb = k;
        if (kb < 0) break;
        double lo = th0 + (kb - 1) * dth, hi = th0 + (kb + 1) * dth, g = 0.6180339887498949;
        double a1 = hi - g * (hi - lo), a2 = lo + g * (hi - lo);
        double f1 = pair_exit(a, ax, ay, b, bx, by, a1), f2 = pair_exit(a, ax, ay, b, bx, by, a2);
        for (int it = 0; it < 50; it++) {
            if (f1 <= f2) {
                hi = a2;
                a2 = a1;
                f2 = f1;
                a1 = hi - g * (hi - lo);
                f1 = pair_exit(a, ax, ay, b, bx, by, a1);
            } else {
                lo = a1;
                a1 = a2;
                f1 = f2;
                a2 = lo + g * (hi - lo);
                f2 = pair_exit(a, ax, ay, b, bx, by, a2);
            }
        }
        best = fmin(best, fmin(f1, f2));
        t[kb] = INFINITY;
    }
    return best;
}

static nt_shape to_nt(ref_shape s)
{
    return s.is_circle ? nt_shape_circle((nt_real)s.hw) : nt_shape_aabb((nt_real)s.hw, (nt_real)s.hh);
}

/* Engine answer for a pair via nt_collide_shapes; the dedicated routine for the combo
 * (when there is one) must give the same result. */
static bool eng_pair(ref_shape a, double ax, double ay, ref_shape b, double bx, double by, nt_mtv *m, int *mismatch)
{
    nt_vec2 pa = nt_v2((nt_real)ax, (nt_real)ay), pb = nt_v2((nt_real)bx, (nt_real)by);
    bool r = nt_collide_shapes(pa, to_nt(a), pb, to_nt(b), m);
    nt_mtv m2 = {{0, 0}, 0};
    bool r2 = r;
    int have = 1;
    if (!a.is_circle && !b.is_circle) r2 = nt_collide_aabbs(pa, to_nt(a).half, pb, to_nt(b).half, &m2);
    else if (a.is_circle && b.is_circle) r2 = nt_collide_circles(pa, (nt_real)a.hw, pb, (nt_real)b.hw, &m2);
    else if (!a.is_circle) r2 = nt_collide_aabb_circle(pa, to_nt(a).half, pb, (nt_real)b.hw, &m2);
    else have = 0;
    if (have && (r2 != r || (r && (m2.depth != m->depth || m2.normal.x != m->normal.x || m2.normal.y != m->normal.y))))
        (*mismatch)++;
    if (nt_collide_shapes(pa, to_nt(a), pb, to_nt(b), NULL) != r) (*mismatch)++;
    return r;
}

static const char *check_pair_mtv(ref_shape a, double ax, double ay, ref_shape b, double bx, double by, const nt_mtv *m)
{
    double nx = m->normal.x, ny = m->normal.y, d = m->depth;
    if (!(fabs(hypot(nx, ny) - 1) <= UNIT_TOL)) return "normal is not unit length";
    if (!(d > 0)) return "depth is not positive";
    double f = d + FREE_MARGIN, k = d - BACK_OFF;
    if (pair_overlap(a, ax + nx * f, ay + ny * f, b, bx, by)) return "moving A by normal*(depth+margin) does not free it";
    if (k > 0 && !pair_overlap(a, ax + nx * k, ay + ny * k, b, bx, by))
        return "moving A by normal*(depth-back_off) already frees it";
    return NULL;
}

static void test_pairs_random(void **state)
{
    (void)state;
    int failures = 0, mismatch = 0;
    char b1[96], b2[96];
    for (int combo = 0; combo < 4; combo++) {
        ref_rng rng = ref_rng_seed(500 + (unsigned long long)combo);
        int overlaps = 0;
        for (int i = 0; i < 1500; i++) {
            double s1 = rr(ref_rng_uniform(&rng, 0.02, 0.5)), s2 = rr(ref_rng_uniform(&rng, 0.02, 0.5));
            double s3 = rr(ref_rng_uniform(&rng, 0.02, 0.5)), s4 = rr(ref_rng_uniform(&rng, 0.02, 0.5));
            ref_shape a = (combo & 1) ? ref_circle(s1) : ref_aabb(s1, s2);
            ref_shape b = (combo & 2) ? ref_circle(s3) : ref_aabb(s3, s4);
            double ax = rr(ref_rng_uniform(&rng, 0, 1)), ay = rr(ref_rng_uniform(&rng, 0, 1));
            double bx = rr(ax + ref_rng_uniform(&rng, -1, 1)), by = rr(ay + ref_rng_uniform(&rng, -1, 1));
            bool lo = pair_overlap(ref_shape_grow(a, -TOUCH_SKIP / 2), ax, ay, ref_shape_grow(b, -TOUCH_SKIP / 2), bx, by);
            bool hi = pair_overlap(ref_shape_grow(a, TOUCH_SKIP / 2), ax, ay, ref_shape_grow(b, TOUCH_SKIP / 2), bx, by);
            if (lo != hi) continue;
            nt_mtv m = {{0, 0}, 0};
            bool got = eng_pair(a, ax, ay, b, bx, by, &m, &mismatch);
            const char *why = NULL;
            double want = 0;
            if (got != lo) {
                why = lo ? "engine misses an overlap" : "engine reports an overlap that is not there";
            } else if (lo) {
                overlaps++;
                want = pair_mtv_ref(a, ax, ay, b, bx, by);
                if (!(fabs(m.depth - want) <= DEPTH_TOL)) why = "depth differs from the brute force";
                else why = check_pair_mtv(a, ax, ay, b, bx, by, &m);
            }
            if (why && failures++ < 12)
                print_message("A %s at (%.9g,%.9g), B %s at (%.9g,%.9g): %s (engine %d depth %.9g normal "
                              "(%.6g,%.6g); brute force %d depth %.9g)\n",
                              shape_str(a, b1, sizeof b1), ax, ay, shape_str(b, b2, sizeof b2), bx, by, why, got,
                              (double)m.depth, (double)m.normal.x, (double)m.normal.y, lo, want);
        }
        assert_true(overlaps > 300);
    }
    assert_int_equal(mismatch, 0);
    assert_int_equal(failures, 0);
}

static void test_pairs_touching(void **state)
{
    (void)state;
    nt_mtv m;
    /* Boxes side by side and corner to corner. */
    assert_false(nt_collide_aabbs(nt_v2(0, 0), nt_v2(0.25f, 0.25f), nt_v2(0.5f, 0), nt_v2(0.25f, 0.25f), &m));
    assert_false(nt_collide_aabbs(nt_v2(0, 0), nt_v2(0.25f, 0.25f), nt_v2(0.5f, 0.5f), nt_v2(0.25f, 0.25f), &m));
    assert_false(nt_collide_aabbs(nt_v2(0, 0), nt_v2(0.25f, 0.125f), nt_v2(0.125f, -0.375f), nt_v2(0.5f, 0.25f), &m));
    /* Circles: along an axis, and along a 3-4-5 diagonal (exact in binary). */
    assert_false(nt_collide_circles(nt_v2(0, 0), 0.25f, nt_v2(0.5f, 0), 0.25f, &m));
    assert_false(nt_collide_circles(nt_v2(0, 0), 0.1875f, nt_v2(0.1875f, 0.25f), 0.125f, &m));
    /* Box and circle: on a face, and at a corner (3-4-5). */
    assert_false(nt_collide_aabb_circle(nt_v2(0, 0), nt_v2(0.25f, 0.25f), nt_v2(0.5f, 0), 0.25f, &m));
    assert_false(nt_collide_aabb_circle(nt_v2(0, 0), nt_v2(0.25f, 0.25f), nt_v2(0.4375f, 0.5f), 0.3125f, &m));
    /* The same through nt_collide_shapes, both ways round. */
    nt_shape bx = nt_shape_aabb(0.25f, 0.25f), c = nt_shape_circle(0.3125f);
    assert_false(nt_collide_shapes(nt_v2(0, 0), bx, nt_v2(0.4375f, 0.5f), c, &m));
    assert_false(nt_collide_shapes(nt_v2(0.4375f, 0.5f), c, nt_v2(0, 0), bx, &m));
    assert_false(nt_collide_shapes(nt_v2(0, 0), bx, nt_v2(0, -0.5f), bx, &m));
    assert_false(nt_collide_shapes(nt_v2(0, 0), nt_shape_circle(0.25f), nt_v2(0, 0.5f), nt_shape_circle(0.25f), &m));
    /* Just inside those contacts they do overlap, by the amount of the overlap. */
    assert_true(nt_collide_circles(nt_v2(0, 0), 0.1875f, nt_v2(0.1875f, 0.25f), 0.1875f, &m));
    assert_true(fabs(m.depth - 0.0625) < DEPTH_TOL);
    assert_true(fabs(m.normal.x + 0.6) < NORMAL_TOL && fabs(m.normal.y + 0.8) < NORMAL_TOL);
    assert_true(nt_collide_aabb_circle(nt_v2(0, 0), nt_v2(0.25f, 0.25f), nt_v2(0.4375f, 0.5f), 0.375f, &m));
    assert_true(fabs(m.depth - 0.0625) < DEPTH_TOL);
    assert_true(fabs(m.normal.x + 0.6) < NORMAL_TOL && fabs(m.normal.y + 0.8) < NORMAL_TOL);
}

/* Coincident centres: documented (tiles.h) to push A along -y; A then has to travel
 * the sum of the half-heights (radii) to come free. Checked for every combination,
 * including a box wider than tall, where -y is not the shortest way out. */
static void test_pairs_coincident(void **state)
{
    (void)state;
    const ref_shape shapes[4][2] = {
        {{0, 0.25, 0.125}, {0, 0.125, 0.25}},
        {{1, 0.25, 0.25}, {1, 0.125, 0.125}},
        {{0, 0.1, 0.3}, {1, 0.2, 0.2}},
        {{1, 0.2, 0.2}, {0, 0.1, 0.3}},
    };
    int bad = 0;
    for (int i = 0; i < 4; i++) {
        for (int j = 0; j < 2; j++) {
            ref_shape a = shapes[i][j], b = shapes[i][1 - j];
            a.hw = rr(a.hw);
            a.hh = rr(a.hh);
            b.hw = rr(b.hw);
            b.hh = rr(b.hh);
            nt_vec2 p = nt_v2(0.375f, 0.625f);
            nt_mtv m = {{0, 0}, 0};
            int mism = 0;
            bool got = eng_pair(a, p.x, p.y, b, p.x, p.y, &m, &mism);
            double want = a.hh + b.hh;
            char b1[96], b2[96];
            if (!got || mism || m.normal.x != 0 || m.normal.y != -1 || fabs(m.depth - want) > DEPTH_TOL) {
                print_message("coincident A %s, B %s: engine %d normal (%g,%g) depth %.9g; expected (0,-1) depth %.9g\n",
                              shape_str(a, b1, sizeof b1), shape_str(b, b2, sizeof b2), got, (double)m.normal.x,
                              (double)m.normal.y, (double)m.depth, want);
                bad++;
            }
        }
    }
    assert_int_equal(bad, 0);
}

/* ------------------------------------------- the reference checks itself */

/* A position within `rad` of (qx, qy) where the object is free in the map (exact test):
 * proves that the reference's minimiser is a real way out, not a rounding artefact. */
static bool free_near(const int *tiles, int w, int h, ref_shape s, double qx, double qy, double rad)
{
    if (!ref_object_overlaps_map(tiles, w, h, s, qx, qy)) return true;
    for (double r = rad * 1e-3; r <= rad * 1.0001; r *= 10)
        for (int j = 0; j < 64; j++) {
            double a = j * (2 * 3.14159265358979323846 / 64);
            if (!ref_object_overlaps_map(tiles, w, h, s, qx + r * cos(a), qy + r * sin(a))) return true;
        }
    return false;
}

/* The candidate-based reference against pure direction sampling, which knows nothing
 * of the geometry: single tiles, and small maps (the form tests/test_map.c uses). */
static void test_reference_crosscheck(void **state)
{
    (void)state;
    ref_rng rng = ref_rng_seed(99);
    int bad = 0, n = 0;
    char buf[96];
    for (int tile = 1; tile < NT_TILE_COUNT; tile++) {
        for (int kind = 0; kind < 3; kind++) { /* box, circle, point */
            int done = 0;
            for (int tries = 0; tries < 200 && done < 3; tries++) {
                ref_shape s = kind == 1 ? ref_circle(ref_rng_uniform(&rng, 0.02, 0.5))
                                        : ref_aabb(ref_rng_uniform(&rng, 0.02, 0.5), ref_rng_uniform(&rng, 0.02, 0.5));
                if (kind == 2) s = ref_aabb(0, 0);
                double cx = ref_rng_uniform(&rng, -0.3, 1.3), cy = ref_rng_uniform(&rng, -0.3, 1.3);
                if (!ref_object_overlaps_tile(tile, s, cx, cy)) continue;
                done++;
                n++;
                double dx, dy;
                double a = ref_mtv_tile(tile, s, cx, cy, &dx, &dy);
                double b = ref_mtv_tile_sampled(tile, s, cx, cy, 360, NULL, NULL);
                int ok = 1;
                /* The minimiser is a real free position (within 1e-7). */
                double qx = cx + dx, qy = cy + dy;
                if (ref_object_overlaps_tile(tile, s, qx, qy)) {
                    ok = 0;
                    for (int j = 0; j < 64 && !ok; j++) {
                        double an = j * (2 * 3.14159265358979323846 / 64);
                        ok = !ref_object_overlaps_tile(tile, s, qx + 1e-7 * cos(an), qy + 1e-7 * sin(an));
                    }
                }
                if (!(fabs(a - b) < 1e-7) || !ok) {
                    print_message("reference %s, %s at (%.17g, %.17g): candidates %.12g (witness %d), sampling %.12g\n",
                                  ref_tile_name(tile), shape_str(s, buf, sizeof buf), cx, cy, a, ok, b);
                    bad++;
                }
            }
        }
    }
    /* Large objects (half-sizes 0.5..4) near the tile, where the way out is shorter
     * than the sampler's 2.5 reach. */
    int large_n = 0;
    for (int tile = 1; tile < NT_TILE_COUNT; tile += 2) {
        for (int tries = 0, done = 0; tries < 400 && done < 2; tries++) {
            ref_shape s = large_shape(&rng, tries & 1);
            double cx = ref_rng_uniform(&rng, -0.3 - s.hw, 1.3 + s.hw), cy = ref_rng_uniform(&rng, -0.3 - s.hh, 1.3 + s.hh);
            if (!ref_object_overlaps_tile(tile, s, cx, cy)) continue;
            double dx, dy;
            double a = ref_mtv_tile(tile, s, cx, cy, &dx, &dy);
            if (a > 2) continue;
            done++;
            large_n++;
            double b = ref_mtv_tile_sampled(tile, s, cx, cy, 360, NULL, NULL);
            int ok = !ref_object_overlaps_tile(tile, s, cx + dx, cy + dy);
            for (int j = 0; j < 64 && !ok; j++) {
                double an = j * (2 * 3.14159265358979323846 / 64);
                ok = !ref_object_overlaps_tile(tile, s, cx + dx + 1e-7 * cos(an), cy + dy + 1e-7 * sin(an));
            }
            if (!(fabs(a - b) < 1e-7) || !ok) {
                print_message("reference (large) %s, %s at (%.17g, %.17g): candidates %.12g (witness %d), sampling %.12g\n",
                              ref_tile_name(tile), shape_str(s, buf, sizeof buf), cx, cy, a, ok, b);
                bad++;
            }
        }
    }
    assert_true(large_n >= 25);
    /* Maps of 3x3 random tiles inside the FULL border. Sampling can miss small pockets
     * of room (its scan steps over them), so it must never find anything closer, the
     * reference's answer must be a real free position, and most answers must agree. */
    int maps = 0, agree = 0;
    for (int i = 0; i < 48; i++) {
        int tiles[9];
        for (int k = 0; k < 9; k++) tiles[k] = ref_rng_int(&rng, 34);
        if (ref_rng_int(&rng, 2)) tiles[4] = 0; /* often some room in the middle */
        int circle = i & 1;
        ref_shape s = circle ? ref_circle(ref_rng_uniform(&rng, 0.05, 0.5))
                             : ref_aabb(ref_rng_uniform(&rng, 0.05, 0.5), ref_rng_uniform(&rng, 0.05, 0.5));
        double cx = ref_rng_uniform(&rng, 0.2, 2.8), cy = ref_rng_uniform(&rng, 0.2, 2.8);
        if (!ref_object_overlaps_map(tiles, 3, 3, s, cx, cy)) continue;
        maps++;
        double dx, dy;
        double a = ref_mtv_map(tiles, 3, 3, s, cx, cy, &dx, &dy);
        double b = ref_mtv_map_sampled(tiles, 3, 3, s, cx, cy, 720, 4.0, NULL, NULL);
        if (a < 0 && b < 0) { /* no room for the object anywhere: both agree */
            agree++;
            continue;
        }
        int witness = a > 0 && free_near(tiles, 3, 3, s, cx + dx, cy + dy, 1e-7) && fabs(hypot(dx, dy) - a) < 1e-12;
        if (!witness || (b >= 0 && b < a - 1e-9)) {
            print_message("reference map #%d, %s at (%.17g, %.17g): candidates %.12g (witness %d), sampling %.12g\n", i,
                          shape_str(s, buf, sizeof buf), cx, cy, a, witness, b);
            bad++;
        }
        agree += fabs(a - b) < 1e-7;
    }
    /* Large objects (half-size 0.5..2) in 6 x 6 maps, mostly EMPTY: the same checks. */
    int big_maps = 0, big_agree = 0;
    for (int i = 0; i < 120 && big_maps < 16; i++) {
        int tiles[36];
        for (int k = 0; k < 36; k++) tiles[k] = ref_rng_int(&rng, 3) ? 0 : ref_rng_int(&rng, 34);
        ref_shape s = i & 1 ? ref_circle(ref_rng_uniform(&rng, 0.5, 2)) : ref_aabb(ref_rng_uniform(&rng, 0.5, 2), ref_rng_uniform(&rng, 0.1, 2));
        double cx = ref_rng_uniform(&rng, s.hw, 6 - s.hw), cy = ref_rng_uniform(&rng, s.hh, 6 - s.hh);
        if (!ref_object_overlaps_map(tiles, 6, 6, s, cx, cy)) continue;
        double dx, dy;
        double a = ref_mtv_map(tiles, 6, 6, s, cx, cy, &dx, &dy);
        if (a < 0 || a > 1.5) continue; /* no room, or beyond what sampling reaches cheaply */
        big_maps++;
        double b = ref_mtv_map_sampled(tiles, 6, 6, s, cx, cy, 360, 2.0, NULL, NULL);
        int witness = free_near(tiles, 6, 6, s, cx + dx, cy + dy, 1e-7) && fabs(hypot(dx, dy) - a) < 1e-12;
        if (!witness || (b >= 0 && b < a - 1e-9)) {
            print_message("reference large map #%d, %s at (%.17g, %.17g): candidates %.12g (witness %d), sampling %.12g\n",
                          i, shape_str(s, buf, sizeof buf), cx, cy, a, witness, b);
            bad++;
        }
        big_agree += fabs(a - b) < 1e-7;
    }
    print_message("reference cross-check: %d tile cases, %d map cases (%d agree with sampling), %d large map cases (%d agree)\n",
                  n, maps, agree, big_maps, big_agree);
    assert_true(big_maps >= 12 && big_agree >= big_maps - 2);
    assert_true(maps >= 30 && agree >= maps * 8 / 10);
    assert_int_equal(bad, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference_crosscheck),
        cmocka_unit_test(test_hand_cases),
        cmocka_unit_test(test_empty_and_invalid_tiles),
        cmocka_unit_test(test_random_box),
        cmocka_unit_test(test_random_circle),
        cmocka_unit_test(test_random_small_near_surface),
        cmocka_unit_test(test_grid_placements),
        cmocka_unit_test(test_grid_placements_large),
        cmocka_unit_test(test_random_large_box),
        cmocka_unit_test(test_random_large_circle),
        cmocka_unit_test(test_large_near_vertices),
        cmocka_unit_test(test_near_vertices),
        cmocka_unit_test(test_pairs_touching),
        cmocka_unit_test(test_pairs_coincident),
        cmocka_unit_test(test_pairs_random),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
