/* Shape casts (character.h): nt_map_cast_shape and nt_world_cast_shape against the
 * brute-force reference (tests/ref.c: a fine scan and bisection on the independent
 * overlap test), resting starts along floors and slope joins, bodies of every size,
 * the query filter's ignore list and callback, one-way cells, and bad input.
 * Cell size 24 unless a test says otherwise; distances are compared in cells. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bodies.h"
#include "ntile/ntile.h"
#include "ref.h"

#define CELL 24.0
/* Travel error allowed against the reference, in cells. */
#define TOL 1e-5
/* Reference scan step (cells of travel) and the shrink that marks a graze as one. */
#define STEP (1.0 / 2048)
#define GRAZE 1e-4
/* The relative rounding unit of nt_real. */
#define ULP (sizeof(nt_real) == sizeof(float) ? 1.1920929e-7 : 2.220446049250313e-16)

static double worst_err = 0;
/* Engine hits earlier than the reference's scan found, confirmed by the reference. */
static int scan_missed = 0;

static nt_map *make_map(int w, int h, const int *tiles)
{
    nt_map_def d = nt_default_map_def();
    d.width = w;
    d.height = h;
    d.cell_size = (nt_real)CELL;
    nt_map *m = NULL;
    assert_int_equal(nt_map_create(&d, &m), NT_OK);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            if (tiles[y * w + x]) assert_int_equal(nt_map_set_tile(m, x, y, tiles[y * w + x]), NT_OK);
    return m;
}

static nt_shape to_nt(ref_shape s)
{
    return s.is_circle ? nt_shape_circle((nt_real)(s.hw * CELL)) : nt_shape_aabb((nt_real)(s.hw * CELL), (nt_real)(s.hh * CELL));
}

static ref_shape random_shape(ref_rng *r, double max_half)
{
    if (ref_rng_int(r, 2)) return ref_circle(ref_rng_uniform(r, 0.05, max_half));
    return ref_aabb(ref_rng_uniform(r, 0.05, max_half), ref_rng_uniform(r, 0.05, max_half));
}

/* One cast compared with the reference (start free by 1e-4 cell). Returns 1 when
 * checked, 0 when skipped because the start is not free, 2 because the path grazes
 * something within GRAZE (then either answer is right). */
static int check_cast(const nt_map *m, const int *tiles, int w, int h, ref_shape s, double cx, double cy, double dx,
                      double dy)
{
    if (ref_object_overlaps_map_eps(tiles, w, h, s, cx, cy, -1e-4)) return 0;
    double len = sqrt(dx * dx + dy * dy);
    double t0 = 0, t1 = 0;
    bool r0 = ref_cast_map(tiles, w, h, s, cx, cy, dx, dy, 1e-9, STEP, &t0);
    bool r1 = ref_cast_map(tiles, w, h, s, cx, cy, dx, dy, GRAZE, STEP, &t1);
    if (r0 != r1 || (r0 && (t1 - t0) * len > 10 * GRAZE)) return 2;
    nt_shape_cast_hit hit;
    bool e = nt_map_cast_shape(m, nt_v2((nt_real)(cx * CELL), (nt_real)(cy * CELL)), to_nt(s),
                               nt_v2((nt_real)(dx * CELL), (nt_real)(dy * CELL)), &hit);
    if (e != r0) {
        fprintf(stderr, "cast %s %.9g x %.9g from (%.9g, %.9g) by (%.9g, %.9g): engine %d (t %.9g) ref %d (t %.9g)\n",
                s.is_circle ? "circle" : "box", s.hw, s.hh, cx, cy, dx, dy, e, (double)hit.fraction, r0, t0);
        /* The reference's scan may step over a chord shorter than STEP: accept an engine
         * hit that the reference confirms just after it. */
        if (e && !r0) {
            double u = (double)hit.fraction + TOL / len;
            assert_true(ref_object_overlaps_map_eps(tiles, w, h, s, cx + dx * u, cy + dy * u, 1e-9));
            scan_missed++;
            return 1;
        }
        fail();
    }
    if (!e) return 1;
    double err = ((double)hit.fraction - t0) * len;
    if (err < -TOL) {
        double u = (double)hit.fraction + TOL / len;
        if (!ref_object_overlaps_map_eps(tiles, w, h, s, cx + dx * u, cy + dy * u, 1e-9)) {
            fprintf(stderr, "early: %s %.9g x %.9g from (%.9g, %.9g) by (%.9g, %.9g): engine t %.9g ref %.9g\n",
                    s.is_circle ? "circle" : "box", s.hw, s.hh, cx, cy, dx, dy, (double)hit.fraction, t0);
            fail();
        }
        scan_missed++;
        return 1;
    }
    if (err > TOL)
        fprintf(stderr, "late: %s %.9g x %.9g from (%.9g, %.9g) by (%.9g, %.9g): engine t %.9g ref %.9g n (%.6g, %.6g)\n",
                s.is_circle ? "circle" : "box", s.hw, s.hh, cx, cy, dx, dy, (double)hit.fraction, t0,
                (double)hit.normal.x, (double)hit.normal.y);
    assert_true(err <= TOL);
    if (fabs(err) > worst_err) worst_err = fabs(err);
    /* A unit normal, against the motion. */
    double nl = sqrt((double)hit.normal.x * hit.normal.x + (double)hit.normal.y * hit.normal.y);
    if (fabs(nl - 1) >= 1e-5)
        fprintf(stderr, "normal (%.9g, %.9g): %s %.9g x %.9g from (%.9g, %.9g) by (%.9g, %.9g): t %.9g\n",
                (double)hit.normal.x, (double)hit.normal.y, s.is_circle ? "circle" : "box", s.hw, s.hh, cx, cy, dx,
                dy, (double)hit.fraction);
    assert_true(fabs(nl - 1) < 1e-5);
    assert_true((double)hit.normal.x * dx + (double)hit.normal.y * dy <= 1e-6 * len);
    assert_true(hit.fraction >= 0 && hit.fraction <= 1);
    /* The point is on the shape's outline at t, within the cell hit (or on its edge). */
    double qx = cx + dx * (double)hit.fraction, qy = cy + dy * (double)hit.fraction;
    double px = (double)hit.point.x / CELL, py = (double)hit.point.y / CELL;
    double on = s.is_circle ? sqrt((px - qx) * (px - qx) + (py - qy) * (py - qy)) / s.hw
                            : fmax(fabs(px - qx) / s.hw, fabs(py - qy) / s.hh);
    assert_true(fabs(on - 1) < 1e-4);
    assert_true(px >= hit.cell_x - 1e-4 && px <= hit.cell_x + 1 + 1e-4);
    assert_true(py >= hit.cell_y - 1e-4 && py <= hit.cell_y + 1 + 1e-4);
    return 1;
}

/* Every tile alone in the middle of an empty 24 x 24 map (FULL border beyond), shapes
 * up to 4 cells half-size, from every side. */
static void test_every_tile_against_reference(void **state)
{
    (void)state;
    enum { W = 24, H = 24 };
    static int tiles[W * H];
    ref_rng r = ref_rng_seed(19);
    int checked = 0, skipped = 0, grazes = 0;
    for (int id = 1; id < 34; id++) {
        memset(tiles, 0, sizeof tiles);
        tiles[12 * W + 12] = id;
        nt_map *m = make_map(W, H, tiles);
        int done = 0;
        for (int k = 0; k < 4000 && done < 160; k++) {
            double mh = k % 4 == 0 ? 4.0 : (k % 4 == 1 ? 1.5 : 0.5);
            ref_shape s = random_shape(&r, mh);
            double reach = s.hw + s.hh + 2;
            double cx = 12.5 + ref_rng_uniform(&r, -reach, reach), cy = 12.5 + ref_rng_uniform(&r, -reach, reach);
            /* Aim near the tile most of the time. */
            double tx = 12.5 + ref_rng_uniform(&r, -0.7, 0.7) - cx, ty = 12.5 + ref_rng_uniform(&r, -0.7, 0.7) - cy;
            double scale = ref_rng_uniform(&r, 0.3, 1.6);
            if (k % 5 == 4) { /* axis-aligned shots */
                if (fabs(tx) > fabs(ty)) ty = 0;
                else tx = 0;
            }
            int c = check_cast(m, tiles, W, H, s, cx, cy, tx * scale, ty * scale);
            if (c == 1) done++, checked++;
            else if (c == 2) grazes++;
            else skipped++;
        }
        assert_true(done >= 100);
        nt_map_destroy(m);
    }
    printf("every tile: %d casts checked, skipped: %d starts not free, %d grazes; worst |error| %.3g cell\n", checked,
           skipped, grazes, worst_err);
    assert_true(grazes * 20 < checked);
}

/* Small random maps. */
static void test_random_maps_against_reference(void **state)
{
    (void)state;
    enum { W = 14, H = 12 };
    int tiles[W * H];
    ref_rng r = ref_rng_seed(7);
    int checked = 0;
    for (int map = 0; map < 40; map++) {
        for (int i = 0; i < W * H; i++) tiles[i] = ref_rng_int(&r, 4) == 0 ? 1 + ref_rng_int(&r, 33) : 0;
        nt_map *m = make_map(W, H, tiles);
        for (int k = 0; k < 300; k++) {
            ref_shape s = random_shape(&r, k % 3 == 0 ? 2.0 : 0.6);
            double cx = ref_rng_uniform(&r, 0, W), cy = ref_rng_uniform(&r, 0, H);
            double a = ref_rng_uniform(&r, 0, 6.283185307179586), l = ref_rng_uniform(&r, 0.1, 5);
            checked += check_cast(m, tiles, W, H, s, cx, cy, l * cos(a), l * sin(a)) == 1;
        }
        nt_map_destroy(m);
    }
    assert_true(checked > 1500);
    printf("random maps: %d casts checked, worst |error| so far %.3g cell; %d hits the reference's scan stepped over\n",
           checked, worst_err, scan_missed);
}

/* A floor of 30 FULL tiles (row 10, x 5..34): shapes resting on it at depths up to the
 * tolerance slide its whole length; pushed into it they stop at once; lifted they go. */
static void test_floor_never_stops_a_slide(void **state)
{
    (void)state;
    enum { W = 40, H = 14 };
    int tiles[W * H];
    memset(tiles, 0, sizeof tiles);
    for (int x = 5; x < 35; x++) tiles[10 * W + x] = NT_TILE_FULL;
    nt_map *m = make_map(W, H, tiles);
    const double depths[] = {0, 1e-6, 1e-4, 2.5e-4, 9e-4};
    const ref_shape shapes[] = {ref_aabb(0.5, 1.0), ref_aabb(3.7, 0.4), ref_aabb(0.2, 0.2), ref_circle(0.45),
                                ref_circle(2.5)};
    for (int si = 0; si < 5; si++)
        for (int di = 0; di < 5; di++) {
            ref_shape s = shapes[si];
            double y = 10 - s.hh + depths[di];
            double x0 = 5 + s.hw + 0.013, x1 = 35 - s.hw - 0.017;
            nt_shape_cast_hit hit;
            nt_vec2 p = nt_v2((nt_real)(x0 * CELL), (nt_real)(y * CELL));
            /* Boxes slide the whole floor; a circle touches one point, the same. */
            assert_false(nt_map_cast_shape(m, p, to_nt(s), nt_v2((nt_real)((x1 - x0) * CELL), 0), &hit));
            nt_vec2 q = nt_v2((nt_real)(x1 * CELL), (nt_real)(y * CELL));
            assert_false(nt_map_cast_shape(m, q, to_nt(s), nt_v2((nt_real)((x0 - x1) * CELL), 0), &hit));
            /* Short steps, as a mover makes them. */
            for (double x = x0; x < x1 - 0.3; x += 0.29)
                assert_false(nt_map_cast_shape(m, nt_v2((nt_real)(x * CELL), (nt_real)(y * CELL)), to_nt(s),
                                               nt_v2((nt_real)(0.3 * CELL), 0), &hit));
            /* Up and away: free. */
            assert_false(nt_map_cast_shape(m, p, to_nt(s), nt_v2((nt_real)(2 * CELL), (nt_real)(-0.5 * CELL)), &hit));
            if (depths[di] > 1e-5) {
                /* Into the floor: stopped at once, by the floor. */
                assert_true(nt_map_cast_shape(m, p, to_nt(s), nt_v2((nt_real)(2 * CELL), (nt_real)(0.01 * CELL)), &hit));
                assert_true(hit.fraction == 0);
                assert_true(fabs((double)hit.normal.x) < 1e-6 && fabs((double)hit.normal.y + 1) < 1e-6);
                assert_int_equal(hit.cell_y, 10);
            } else if (depths[di] == 0) {
                /* From exactly on it, straight down: stopped at once. */
                assert_true(nt_map_cast_shape(m, p, to_nt(s), nt_v2(0, (nt_real)(0.5 * CELL)), &hit));
                assert_true((double)hit.fraction * 0.5 < 1e-5);
                assert_true(fabs((double)hit.normal.y + 1) < 1e-6);
            }
        }
    nt_map_destroy(m);
}

/* Slope-to-flat joins, each slope tile of the pn family (22, 45, 67 degrees, small and
 * big), shapes resting skin-deep (2.5e-4 cell): a crest is passed (flat onto the
 * falling slope, and up the slope onto the flat); at a foot the slope or the flat
 * stops the shape where it meets it, with that surface's normal, not before. */
/* Resting on a crest's corner: a circle touching the corner where a 45-degree slope
 * meets a FULL tile (the tile's side towards the slope is a seam) from any direction
 * between the flat's normal and the slope's. Only the corner holds it: no cast starts
 * inside, and each stops where the reference (the shape made smaller by its start
 * depth) stops. Regression: the seam made the FULL tile alone look a third of the
 * radius deep, and a character running up the slope stuck at its crest. */
static void test_crest_corner(void **state)
{
    (void)state;
    enum { W = 20, H = 12 };
    int tiles[W * H];
    memset(tiles, 0, sizeof tiles);
    for (int x = 0; x < W; x++) tiles[9 * W + x] = NT_TILE_FULL;
    for (int x = 0; x < 10; x++) tiles[8 * W + x] = NT_TILE_FULL;
    tiles[8 * W + 10] = NT_TILE_45DEGpn; /* falls to the right from the corner (10, 8) */
    nt_map *m = make_map(W, H, tiles);
    const double dirs[][2] = {{1, 0}, {0.7071067811865476, 0.7071067811865476}, {0, -1}, {-1, 0}, {1, -0.3}};
    int resting = 0;
    for (int ri = 0; ri < 4; ri++) {
        double r = 0.2 + 0.1 * ri;
        /* From 10 degrees off straight up toward the slope's normal: nearer the vertical
         * the flat's top is within the resting tolerance, and the cast rests on it. */
        for (int ai = 2; ai < 9; ai++) {
            double a = 0.7853981633974483 * ai / 9;
            double cx = 10 + (r - 1e-5) * sin(a), cy = 8 - (r - 1e-5) * cos(a);
            ref_shape s = ref_circle(r);
            double d0 = ref_mtv_map(tiles, W, H, s, cx, cy, NULL, NULL);
            assert_true(d0 < 2e-5); /* the reference: it only touches the corner */
            for (int di = 0; di < 5; di++) {
                double dx = dirs[di][0] * 0.5, dy = dirs[di][1] * 0.5;
                nt_shape_cast_hit hit;
                bool e = nt_map_cast_shape(m, nt_v2((nt_real)(cx * CELL), (nt_real)(cy * CELL)), to_nt(s),
                                           nt_v2((nt_real)(dx * CELL), (nt_real)(dy * CELL)), &hit);
                double tr = 0;
                bool rr = ref_cast_map(tiles, W, H, ref_shape_grow(s, -d0 - 1e-6), cx, cy, dx, dy, 1e-9, STEP, &tr);
                assert_int_equal(e, rr);
                if (!e) continue;
                assert_false(hit.normal.x == 0 && hit.normal.y == 0); /* not "inside" */
                resting += hit.fraction == 0;
                assert_true(fabs((double)hit.fraction - tr) * 0.5 < 1e-3);
            }
        }
    }
    assert_true(resting > 0); /* moving into the corner or the flat stops it at once */
    nt_map_destroy(m);
}

static void test_slope_joins(void **state)
{
    (void)state;
    enum { W = 30, H = 14 };
    const int slopes[] = {NT_TILE_45DEGpn, NT_TILE_22DEGpnS, NT_TILE_22DEGpnB, NT_TILE_67DEGpnS, NT_TILE_67DEGpnB};
    const double skin = 2.5e-4;
    int valley_hits = 0;
    for (int k = 0; k < 5; k++) {
        int id = slopes[k];
        /* Crest: FULL row 8 for x < 10, slope tile at (10, 8) falling to the right,
         * floor of row 9 everywhere below. */
        int tiles[W * H];
        memset(tiles, 0, sizeof tiles);
        for (int x = 0; x < W; x++) tiles[9 * W + x] = NT_TILE_FULL;
        for (int x = 0; x < 10; x++) tiles[8 * W + x] = NT_TILE_FULL;
        tiles[8 * W + 10] = id;
        nt_map *m = make_map(W, H, tiles);
        const nt_tile_info *ti = nt_tile_get_info(id);
        ref_shape shapes[] = {ref_aabb(0.5, 1.0), ref_aabb(0.3, 0.3), ref_circle(0.4), ref_aabb(1.5, 0.5)};
        for (int si = 0; si < 4; si++) {
            ref_shape s = shapes[si];
            nt_shape_cast_hit hit;
            /* On the flat top, moving right off the crest (and on, over the slope, in the air). */
            double y = 8 - s.hh + skin;
            nt_vec2 p = nt_v2((nt_real)((8.5 - s.hw) * CELL), (nt_real)(y * CELL));
            bool e = nt_map_cast_shape(m, p, to_nt(s), nt_v2((nt_real)(3.0 * CELL), 0), &hit);
            /* Nothing ahead but air: the crest and the seams do not stop it. */
            assert_false(e);
            /* Resting on the slope (found by the reference: the lowest free y above the
             * slope at this x, then a skin deeper), moving up the slope onto the flat. */
            double nx = (double)ti->normal.x, ny = (double)ti->normal.y;
            double tx = ny, ty = -nx; /* along the slope, rightwards and down */
            if (tx < 0) tx = -tx, ty = -ty;
            double cx = 10.5 + 0.2, lo = 0, hi = 9;
            for (int it = 0; it < 80; it++) {
                double mid = 0.5 * (lo + hi);
                if (ref_object_overlaps_map(tiles, W, H, s, cx, mid)) hi = mid;
                else lo = mid;
            }
            double cy = lo + skin;
            int n = 0;
            for (int it = 0; it < 8; it++) {
                double u = 0.4 + 0.1 * it; /* cells along the slope, up-left */
                nt_vec2 q = nt_v2((nt_real)(cx * CELL), (nt_real)(cy * CELL));
                e = nt_map_cast_shape(m, q, to_nt(s), nt_v2((nt_real)(-tx * u * CELL), (nt_real)(-ty * u * CELL)), &hit);
                if (e) {
                    /* Only a real surface ahead may stop it: check with the reference
                     * that the shape a little further overlaps something beyond the skin. */
                    double f = (double)hit.fraction * u + 2e-3;
                    assert_true(ref_object_overlaps_map_eps(tiles, W, H, s, cx - tx * f, cy - ty * f, 2 * skin));
                    n++;
                }
            }
            (void)n;
            /* Down the slope into the valley (or off it onto the floor): stopped where the
             * reference stops the shape made smaller by its start depth, not before. */
            double d0 = ref_mtv_map(tiles, W, H, s, cx, cy, NULL, NULL);
            double tr = 0;
            bool rr = ref_cast_map(tiles, W, H, ref_shape_grow(s, -d0), cx, cy, tx * 2.5, ty * 2.5, 1e-9, STEP, &tr);
            e = nt_map_cast_shape(m, nt_v2((nt_real)(cx * CELL), (nt_real)(cy * CELL)), to_nt(s),
                                  nt_v2((nt_real)(tx * 2.5 * CELL), (nt_real)(ty * 2.5 * CELL)), &hit);
            assert_int_equal(e, rr);
            valley_hits += e;
            if (e) {
                double anx = fabs((double)hit.normal.x), any = fabs((double)hit.normal.y);
                double cosa = fabs((double)hit.normal.x * tx + (double)hit.normal.y * ty);
                double err = fabs((double)hit.fraction - tr) * 2.5 - 16 * 16 * ULP * (anx + any) / fmax(cosa, 0.1);
                if (err >= 2e-5)
                    fprintf(stderr, "valley %s: %s %g x %g: t %.9g ref %.9g\n", ti->name, s.is_circle ? "circle" : "box",
                            s.hw, s.hh, (double)hit.fraction, tr);
                assert_true(err < 2e-5);
            }
            nt_map_destroy(m);
            m = make_map(W, H, tiles);
        }
        nt_map_destroy(m);

        /* Foot: floor row 9, the mirrored slope (rising to the right) at (15, 8). A
         * shape resting on the floor moving right meets the slope: stopped with the
         * slope's normal, within the skin of where the reference meets it. */
        memset(tiles, 0, sizeof tiles);
        for (int x = 0; x < W; x++) tiles[9 * W + x] = NT_TILE_FULL;
        int mirrored = id + 1; /* nn: solid to the lower right, rising to the right */
        tiles[8 * W + 15] = mirrored;
        tiles[8 * W + 16] = NT_TILE_FULL;
        m = make_map(W, H, tiles);
        const nt_tile_info *tm = nt_tile_get_info(mirrored);
        for (int si = 0; si < 3; si++) {
            ref_shape s = shapes[si];
            double y = 9 - s.hh + skin, x0 = 12 - s.hw;
            nt_shape_cast_hit hit;
            assert_true(nt_map_cast_shape(m, nt_v2((nt_real)(x0 * CELL), (nt_real)(y * CELL)), to_nt(s),
                                          nt_v2((nt_real)(4 * CELL), 0), &hit));
            double tr = 0;
            /* The reference on the shape a skin smaller, as documented. */
            ref_shape small = ref_shape_grow(s, -(skin + 1e-6));
            assert_true(ref_cast_map(tiles, W, H, small, x0, y, 4, 0, 1e-9, STEP, &tr));
            /* The shrink is the resting depth plus 16 units in the last place of the
             * coordinates (up to 16 cells): allowed for here, moved along the normal
             * (|nx| + |ny|: a box shrinks on both axes) over the approach's cosine. */
            double anx = fabs((double)hit.normal.x), any = fabs((double)hit.normal.y);
            double err = fabs((double)hit.fraction - tr) * 4 - 16 * 16 * ULP * (anx + any) / (anx > 0.1 ? anx : 0.1);
            if (err >= 2e-5)
                fprintf(stderr, "foot %s: %s %g x %g: t %.9g ref %.9g normal (%.6g, %.6g)\n", tm->name,
                        s.is_circle ? "circle" : "box", s.hw, s.hh, (double)hit.fraction, tr, (double)hit.normal.x,
                        (double)hit.normal.y);
            assert_true(err < 2e-5);
            if (!s.is_circle) {
                /* The B tiles rise from a step (a wall of half a cell or more) at the foot. */
                int step = tm->cover_lo[NT_SIDE_LEFT] < tm->cover_hi[NT_SIDE_LEFT];
                double ex = step ? -1 : (double)tm->normal.x, ey = step ? 0 : (double)tm->normal.y;
                assert_true(fabs((double)hit.normal.x - ex) < 1e-5);
                assert_true(fabs((double)hit.normal.y - ey) < 1e-5);
            }
        }
        nt_map_destroy(m);
    }
    assert_true(valley_hits >= 15); /* of 20: a wide box can rest on the flat beyond the slope */
}

/* ---- the world ---- */

static nt_world *make_world(int w, int h)
{
    nt_world_def d = nt_default_world_def();
    d.map.width = w;
    d.map.height = h;
    d.map.cell_size = (nt_real)CELL;
    nt_world *world = NULL;
    assert_int_equal(nt_world_create(&d, &world), NT_OK);
    return world;
}

static nt_body_id add_body(nt_world *w, nt_body_type type, ref_shape s, double x, double y)
{
    return test_body(w, type, to_nt(s), x * CELL, y * CELL);
}

typedef struct rbody {
    ref_shape s;
    double x, y;
    nt_body_id id;
} rbody;

/* Bodies of every size and type (no tiles in the filter): the first hit against brute
 * force over all bodies. */
static void test_world_bodies_against_reference(void **state)
{
    (void)state;
    enum { W = 40, H = 40, N = 40 };
    nt_world *w = make_world(W, H);
    ref_rng r = ref_rng_seed(23);
    rbody b[N];
    const nt_body_type types[3] = {NT_BODY_STATIC, NT_BODY_KINEMATIC, NT_BODY_DYNAMIC};
    for (int i = 0; i < N; i++) {
        b[i].s = random_shape(&r, i % 4 == 0 ? 4.0 : 0.8);
        b[i].x = ref_rng_uniform(&r, 5, W - 5);
        b[i].y = ref_rng_uniform(&r, 5, H - 5);
        b[i].id = add_body(w, types[i % 3], b[i].s, b[i].x, b[i].y);
    }
    nt_query_filter f = nt_default_query_filter();
    f.tiles = false;
    int checked = 0, hits = 0;
    double worst = 0;
    for (int k = 0; k < 600; k++) {
        ref_shape s = random_shape(&r, k % 3 == 0 ? 3.0 : 0.7);
        double cx = ref_rng_uniform(&r, 4, W - 4), cy = ref_rng_uniform(&r, 4, H - 4);
        double a = ref_rng_uniform(&r, 0, 6.283185307179586), l = ref_rng_uniform(&r, 0.5, 12);
        double dx = l * cos(a), dy = l * sin(a);
        int bad = 0, graze = 0, first = -1;
        double tbest = 2;
        for (int i = 0; i < N; i++) {
            if (ref_objects_overlap(s, cx, cy, b[i].s, b[i].x, b[i].y, -1e-4)) bad = 1;
            double t0, t1;
            bool r0 = ref_cast_object(s, cx, cy, dx, dy, b[i].s, b[i].x, b[i].y, 1e-9, STEP, &t0);
            bool r1 = ref_cast_object(s, cx, cy, dx, dy, b[i].s, b[i].x, b[i].y, GRAZE, STEP, &t1);
            if (r0 != r1 || (r0 && (t1 - t0) * l > 10 * GRAZE)) graze = 1;
            if (r0 && t0 < tbest) tbest = t0, first = i;
        }
        if (bad || graze) continue;
        nt_world_shape_hit hit;
        bool e = nt_world_cast_shape(w, nt_v2((nt_real)(cx * CELL), (nt_real)(cy * CELL)), to_nt(s),
                                     nt_v2((nt_real)(dx * CELL), (nt_real)(dy * CELL)), f, &hit);
        assert_int_equal(e, first >= 0);
        checked++;
        if (!e) continue;
        hits++;
        double err = fabs((double)hit.fraction - tbest) * l;
        if (err > TOL)
            fprintf(stderr, "body: %s %.9g x %.9g from (%.9g, %.9g) by (%.9g, %.9g): t %.9g ref %.9g n (%.6g, %.6g)\n",
                    s.is_circle ? "circle" : "box", s.hw, s.hh, cx, cy, dx, dy, (double)hit.fraction, tbest,
                    (double)hit.normal.x, (double)hit.normal.y);
        if (err > TOL)
            fprintf(stderr, "  body %s %.9g x %.9g at (%.9g, %.9g)\n", b[first].s.is_circle ? "circle" : "box",
                    b[first].s.hw, b[first].s.hh, b[first].x, b[first].y);
        if (err > worst) worst = err;
        assert_true(err <= TOL);
        /* The body hit (another at the same time would be a tie: none in practice). */
        assert_true(nt_body_id_equals(hit.body, b[first].id));
        double nl = sqrt((double)hit.normal.x * hit.normal.x + (double)hit.normal.y * hit.normal.y);
        assert_true(fabs(nl - 1) < 1e-5);
    }
    assert_true(checked > 300 && hits > 100);
    printf("world bodies: %d casts checked, %d hits, worst |error| %.3g cell\n", checked, hits, worst);
    nt_world_destroy(w);
}

/* Tiles and bodies together: the world cast answers the earlier of the map cast on the
 * world's map and the brute-force body cast, a tile on ties. */
static void test_world_tiles_and_bodies(void **state)
{
    (void)state;
    enum { W = 24, H = 18, N = 12 };
    nt_world *w = make_world(W, H);
    ref_rng r = ref_rng_seed(31);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            if (ref_rng_int(&r, 6) == 0) assert_int_equal(nt_world_set_tile(w, x, y, 1 + ref_rng_int(&r, 33)), NT_OK);
    rbody b[N];
    for (int i = 0; i < N; i++) {
        b[i].s = random_shape(&r, i % 3 == 0 ? 2.0 : 0.5);
        b[i].x = ref_rng_uniform(&r, 3, W - 3);
        b[i].y = ref_rng_uniform(&r, 3, H - 3);
        b[i].id = add_body(w, NT_BODY_STATIC, b[i].s, b[i].x, b[i].y);
    }
    int tile_hits = 0, body_hits = 0;
    for (int k = 0; k < 400; k++) {
        ref_shape s = random_shape(&r, k % 4 == 0 ? 1.5 : 0.5);
        double cx = ref_rng_uniform(&r, 2, W - 2), cy = ref_rng_uniform(&r, 2, H - 2);
        double a = ref_rng_uniform(&r, 0, 6.283185307179586), l = ref_rng_uniform(&r, 0.5, 6);
        nt_vec2 p = nt_v2((nt_real)(cx * CELL), (nt_real)(cy * CELL));
        nt_vec2 t = nt_v2((nt_real)(l * cos(a) * CELL), (nt_real)(l * sin(a) * CELL));
        nt_shape_cast_hit mh;
        bool m = nt_map_cast_shape(nt_world_get_map(w), p, to_nt(s), t, &mh);
        double tb = 2;
        int bad = 0;
        for (int i = 0; i < N; i++) {
            double ti;
            if (ref_objects_overlap(s, cx, cy, b[i].s, b[i].x, b[i].y, -1e-4)) bad = 1;
            if (ref_cast_object(s, cx, cy, l * cos(a), l * sin(a), b[i].s, b[i].x, b[i].y, 1e-9, STEP, &ti) && ti < tb)
                tb = ti;
        }
        if (bad || (m && mh.fraction == 0)) continue;
        nt_world_shape_hit wh;
        bool e = nt_world_cast_shape(w, p, to_nt(s), t, nt_default_query_filter(), &wh);
        double want = m ? (double)mh.fraction : 2;
        if (tb < want - 1e-4 / l) want = tb;
        assert_int_equal(e, want <= 1);
        if (!e) continue;
        assert_true(fabs((double)wh.fraction - want) * l < 2 * TOL);
        if (nt_body_id_is_null(wh.body)) {
            tile_hits++;
            assert_true(m && wh.fraction == mh.fraction && wh.cell_x == mh.cell_x && wh.cell_y == mh.cell_y);
        } else {
            body_hits++;
        }
    }
    assert_true(tile_hits > 50 && body_hits > 20);
    nt_world_destroy(w);
}

static bool accept_not(nt_body_id id, void *ctx)
{
    return !nt_body_id_equals(id, *(const nt_body_id *)ctx);
}

/* The filter: a body never hits itself when it names itself; the callback decides;
 * the same filter serves ray casts, point and box queries. */
static void test_filter(void **state)
{
    (void)state;
    nt_world *w = make_world(30, 20);
    /* A row of three boxes along x, and the caster inside the first. */
    nt_body_id a = add_body(w, NT_BODY_DYNAMIC, ref_aabb(0.5, 1.0), 5, 10);
    nt_body_id b = add_body(w, NT_BODY_STATIC, ref_aabb(0.5, 0.5), 8, 10);
    nt_body_id c = add_body(w, NT_BODY_STATIC, ref_circle(0.5), 12, 10);
    nt_shape sh = nt_shape_aabb((nt_real)(0.5 * CELL), (nt_real)(1.0 * CELL));
    nt_vec2 p = nt_v2((nt_real)(5 * CELL), (nt_real)(10 * CELL)), tr = nt_v2((nt_real)(10 * CELL), 0);
    nt_query_filter f = nt_default_query_filter();
    f.tiles = false;
    nt_world_shape_hit hit;
    /* Without the ignore list it starts inside itself. */
    assert_true(nt_world_cast_shape(w, p, sh, tr, f, &hit));
    assert_true(hit.fraction == 0 && hit.normal.x == 0 && hit.normal.y == 0);
    assert_true(nt_body_id_equals(hit.body, a));
    f.ignore[0] = a;
    f.ignore_count = 1;
    assert_true(nt_world_cast_shape(w, p, sh, tr, f, &hit));
    assert_true(nt_body_id_equals(hit.body, b));
    assert_true(fabs((double)hit.fraction - 0.2) < 1e-6); /* 2 cells of 10 */
    assert_true(hit.normal.x == -1 && hit.normal.y == 0);
    f.ignore[1] = b;
    f.ignore_count = 2;
    assert_true(nt_world_cast_shape(w, p, sh, tr, f, &hit));
    assert_true(nt_body_id_equals(hit.body, c));
    assert_true(fabs((double)hit.fraction - 0.6) < 1e-6); /* the circle's left at 11.5 */
    /* The callback: skip c as well. */
    f.accept = accept_not;
    f.accept_context = &c;
    assert_false(nt_world_cast_shape(w, p, sh, tr, f, &hit));
    /* ignore_count beyond the array reads only the array. */
    f.accept = NULL;
    f.ignore_count = 100;
    assert_true(nt_world_cast_shape(w, p, sh, tr, f, &hit));
    assert_true(nt_body_id_equals(hit.body, c));
    /* Ray cast, point and box queries. */
    nt_query_filter g = nt_default_query_filter();
    nt_world_ray_hit rh;
    assert_true(nt_world_raycast(w, p, nt_v2((nt_real)(20 * CELL), (nt_real)(10 * CELL)), g, &rh));
    assert_true(nt_body_id_equals(rh.body, a));
    g.ignore[0] = a;
    g.ignore_count = 1;
    assert_true(nt_world_raycast(w, p, nt_v2((nt_real)(20 * CELL), (nt_real)(10 * CELL)), g, &rh));
    assert_true(nt_body_id_equals(rh.body, b));
    g.accept = accept_not;
    g.accept_context = &b;
    assert_true(nt_world_raycast(w, p, nt_v2((nt_real)(20 * CELL), (nt_real)(10 * CELL)), g, &rh));
    assert_true(nt_body_id_equals(rh.body, c));
    assert_int_equal(nt_world_query_point(w, p, g, NULL, NULL), 0);
    assert_int_equal(nt_world_query_point(w, p, nt_default_query_filter(), NULL, NULL), 1);
    nt_vec2 lo = nt_v2(0, 0), hi = nt_v2((nt_real)(30 * CELL), (nt_real)(20 * CELL));
    assert_int_equal(nt_world_overlap_aabb(w, lo, hi, nt_default_query_filter(), NULL, NULL), 3);
    assert_int_equal(nt_world_overlap_aabb(w, lo, hi, g, NULL, NULL), 1);
    /* A filter written as before (naming mask and tiles only) behaves as before. */
    nt_query_filter old = {.mask = 0xffffffffu, .tiles = true};
    assert_int_equal(nt_world_overlap_aabb(w, lo, hi, old, NULL, NULL), 3);
    nt_world_destroy(w);
}

/* One-way cells stop a shape coming down onto them only, and not one that starts in them. */
static void test_one_way(void **state)
{
    (void)state;
    nt_world *w = make_world(20, 20);
    for (int x = 5; x < 12; x++) {
        assert_int_equal(nt_world_set_tile(w, x, 10, NT_TILE_HALFu), NT_OK);
        assert_int_equal(nt_world_set_cell_flags(w, x, 10, NT_CELL_ONE_WAY), NT_OK);
    }
    nt_shape sh = nt_shape_aabb((nt_real)(0.4 * CELL), (nt_real)(0.6 * CELL));
    nt_query_filter f = nt_default_query_filter();
    nt_world_shape_hit hit;
    /* Down from above: stopped on top (y = 10), normal up. */
    assert_true(nt_world_cast_shape(w, nt_v2((nt_real)(8.5 * CELL), (nt_real)(7 * CELL)), sh,
                                    nt_v2(0, (nt_real)(4 * CELL)), f, &hit));
    assert_true(fabs((double)hit.fraction - (10 - 0.6 - 7) / 4.0) < 1e-6);
    assert_true(hit.normal.x == 0 && hit.normal.y == -1);
    assert_int_equal(hit.cell_x, 8);
    assert_int_equal(hit.cell_y, 10);
    /* Up from below: through it (to the map's top border at y = 0, far beyond). */
    assert_false(nt_world_cast_shape(w, nt_v2((nt_real)(8 * CELL), (nt_real)(13 * CELL)), sh,
                                     nt_v2(0, (nt_real)(-6 * CELL)), f, &hit));
    /* Sideways into it: through. */
    assert_false(nt_world_cast_shape(w, nt_v2((nt_real)(2 * CELL), (nt_real)(10.3 * CELL)), sh,
                                     nt_v2((nt_real)(14 * CELL), 0), f, &hit));
    /* Starting inside it, moving down: through (the floor of the map is far). */
    assert_false(nt_world_cast_shape(w, nt_v2((nt_real)(8 * CELL), (nt_real)(10.2 * CELL)), sh,
                                     nt_v2(0, (nt_real)(3 * CELL)), f, &hit));
    /* Resting on it skin-deep: sliding goes, pressing down stops at once. */
    nt_vec2 rest = nt_v2((nt_real)(6 * CELL), (nt_real)((10 - 0.6 + 2.5e-4) * CELL));
    assert_false(nt_world_cast_shape(w, rest, sh, nt_v2((nt_real)(4 * CELL), 0), f, &hit));
    assert_true(nt_world_cast_shape(w, rest, sh, nt_v2((nt_real)(1 * CELL), (nt_real)(0.1 * CELL)), f, &hit));
    assert_true(hit.fraction == 0 && hit.normal.y == -1);
    /* Without tiles in the filter nothing is hit. */
    f.tiles = false;
    assert_false(nt_world_cast_shape(w, nt_v2((nt_real)(8 * CELL), (nt_real)(7 * CELL)), sh,
                                     nt_v2(0, (nt_real)(4 * CELL)), f, &hit));
    nt_world_destroy(w);
}

/* A body settled by the world on a floor of tiles casts itself along the floor. */
static void test_world_resting_body_slides(void **state)
{
    (void)state;
    nt_world *w = make_world(40, 14);
    for (int x = 0; x < 40; x++) assert_int_equal(nt_world_set_tile(w, x, 10, NT_TILE_FULL), NT_OK);
    const ref_shape shapes[] = {ref_aabb(0.45, 0.5), ref_circle(0.4), ref_aabb(0.5, 0.25)};
    for (int i = 0; i < 3; i++) {
        nt_body_id id = add_body(w, NT_BODY_DYNAMIC, shapes[i], 6 + 10 * i, 10 - shapes[i].hh - 0.2);
        for (int k = 0; k < 240; k++) assert_int_equal(nt_world_step(w, (nt_real)(1.0 / 60)), NT_OK);
        nt_vec2 p = nt_body_get_position(w, id);
        nt_query_filter f = nt_default_query_filter();
        f.ignore[0] = id;
        f.ignore_count = 1;
        nt_world_shape_hit hit;
        nt_shape sh = nt_body_get_shape(w, id);
        assert_false(nt_world_cast_shape(w, p, sh, nt_v2((nt_real)(3 * CELL), 0), f, &hit));
        assert_false(nt_world_cast_shape(w, p, sh, nt_v2((nt_real)(-3 * CELL), 0), f, &hit));
        assert_true(nt_world_cast_shape(w, p, sh, nt_v2(0, (nt_real)(1 * CELL)), f, &hit));
        assert_true(hit.fraction == 0 && hit.normal.y == -1);
        assert_int_equal(nt_body_destroy(w, id), NT_OK);
    }
    nt_world_destroy(w);
}

/* Very long casts: from inside the map one stops at the border (everything outside is
 * FULL) where a short one does; from deep in the border one stops at once. Neither may
 * take long: the walk ends at the first hit. */
static void test_long_casts(void **state)
{
    (void)state;
    int tiles[20 * 20] = {0};
    nt_map *m = make_map(20, 20, tiles);
    const ref_shape shapes[] = {ref_aabb(0.5, 1.0), ref_circle(0.3), ref_aabb(3.5, 2.0)};
    for (int i = 0; i < 3; i++) {
        ref_shape s = shapes[i];
        nt_vec2 p = nt_v2((nt_real)(10 * CELL), (nt_real)(10 * CELL));
        const double lens[3] = {20, 1e4, 1e7};
        for (int k = 0; k < 3; k++) {
            nt_shape_cast_hit hit;
            assert_true(nt_map_cast_shape(m, p, to_nt(s), nt_v2((nt_real)(lens[k] * CELL), 0), &hit));
            assert_true(fabs((double)hit.fraction * lens[k] - (10 - s.hw)) < 1e-3);
            assert_true(hit.normal.x == -1 && hit.normal.y == 0);
            assert_int_equal(hit.cell_x, 20);
            assert_true(nt_map_cast_shape(m, p, to_nt(s), nt_v2((nt_real)(-lens[k] * CELL), (nt_real)(-lens[k] * CELL)), &hit));
            assert_true(fabs((double)hit.fraction * lens[k] - (10 - fmax(s.hw, s.hh))) < 1e-3);
            /* Deep in the border, far out: t = 0, no normal. */
            assert_true(nt_map_cast_shape(m, nt_v2((nt_real)(-30 * CELL), (nt_real)(50 * CELL)), to_nt(s),
                                          nt_v2((nt_real)(lens[k] * CELL), (nt_real)(-lens[k] * CELL)), &hit));
            assert_true(hit.fraction == 0 && hit.normal.x == 0 && hit.normal.y == 0);
        }
    }
    nt_map_destroy(m);
}

/* Both casts refuse the input: false, and the result zeroed over garbage. */
static void expect_refused(const nt_map *m, const nt_world *w, nt_vec2 p, nt_shape s, nt_vec2 t)
{
    nt_shape_cast_hit h, zero;
    nt_world_shape_hit wh, wzero;
    memset(&zero, 0, sizeof zero);
    memset(&wzero, 0, sizeof wzero);
    memset(&h, 0x5a, sizeof h);
    memset(&wh, 0x5a, sizeof wh);
    assert_false(nt_map_cast_shape(m, p, s, t, &h));
    assert_memory_equal(&h, &zero, sizeof h);
    assert_false(nt_world_cast_shape(w, p, s, t, nt_default_query_filter(), &wh));
    assert_memory_equal(&wh, &wzero, sizeof wh);
}

/* Bad input: false, a zero result, nothing changed. */
static void test_bad_input(void **state)
{
    (void)state;
    int tiles[4 * 4] = {0};
    nt_map *m = make_map(4, 4, tiles);
    nt_world *w = make_world(10, 10);
    uint64_t hash = nt_world_hash(w);
    nt_shape ok = nt_shape_aabb(4, 4);
    nt_vec2 p = nt_v2(48, 48), t = nt_v2(10, 0);
    const nt_real nan = (nt_real)NAN, inf = (nt_real)INFINITY;
    nt_shape bad[6] = {nt_shape_aabb(0, 4), nt_shape_aabb(4, -1), nt_shape_circle((nt_real)(4 * CELL + 0.01)),
                       nt_shape_aabb(nan, 4), nt_shape_aabb(4, inf), ok};
    bad[5].type = (nt_shape_type)7;
    nt_shape uneven = nt_shape_circle(4);
    uneven.half.y = 5;
    for (int i = 0; i < 7; i++) expect_refused(m, w, p, i < 6 ? bad[i] : uneven, t);
    nt_vec2 nans[4] = {nt_v2(nan, 48), nt_v2(48, inf), nt_v2(48, 48), nt_v2(48, 48)};
    nt_vec2 nant[4] = {t, t, nt_v2(nan, 0), nt_v2(0, -inf)};
    for (int i = 0; i < 4; i++) expect_refused(m, w, nans[i], ok, nant[i]);
    expect_refused(NULL, NULL, p, ok, t);
    /* NULL out is allowed; the answer is still given. */
    assert_true(nt_map_cast_shape(m, p, ok, nt_v2(200, 0), NULL));
    assert_false(nt_map_cast_shape(m, p, ok, nt_v2(10, 0), NULL));
    /* Zero translation: nothing approached, nothing hit; from deep inside: t = 0. */
    nt_shape_cast_hit h;
    assert_false(nt_map_cast_shape(m, p, ok, nt_v2(0, 0), &h));
    assert_true(nt_map_cast_shape(m, nt_v2(-24, 48), ok, nt_v2(0, 0), &h));
    assert_true(h.fraction == 0 && h.normal.x == 0 && h.normal.y == 0);
    assert_true(nt_world_hash(w) == hash);
    nt_world_destroy(w);
    nt_map_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_tile_against_reference),
        cmocka_unit_test(test_random_maps_against_reference),
        cmocka_unit_test(test_floor_never_stops_a_slide),
        cmocka_unit_test(test_slope_joins),
        cmocka_unit_test(test_crest_corner),
        cmocka_unit_test(test_world_bodies_against_reference),
        cmocka_unit_test(test_world_tiles_and_bodies),
        cmocka_unit_test(test_filter),
        cmocka_unit_test(test_one_way),
        cmocka_unit_test(test_world_resting_body_slides),
        cmocka_unit_test(test_long_casts),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
