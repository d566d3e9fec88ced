/* Tile map: edge states on hand-built maps, resolution on seams and slope joins,
 * and resolution against a brute-force minimum translation out of the union of
 * tiles (tests/ref.c). */
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

#define R(x) ((nt_real)(x))

enum { E_OFF = NT_EDGE_OFF, E_SOL = NT_EDGE_SOLID, E_INT = NT_EDGE_INTERESTING };

/* Build a map from rows of characters: '.' EMPTY, '#' FULL, digits/letters via a legend. */
static int tile_of(char c)
{
    switch (c) {
    case '.': return NT_TILE_EMPTY;
    case '#': return NT_TILE_FULL;
    case '\\': return NT_TILE_45DEGpn; /* solid lower-left, surface going down to the right */
    case '/': return NT_TILE_45DEGnn;  /* solid lower-right */
    case 'd': return NT_TILE_HALFd;
    case 'u': return NT_TILE_HALFu;
    case 'l': return NT_TILE_HALFl;
    case 'r': return NT_TILE_HALFr;
    case 'c': return NT_TILE_CONCAVEpn;
    case 'o': return NT_TILE_CONVEXpn;
    case 'B': return NT_TILE_22DEGpnB;
    case 'S': return NT_TILE_22DEGpnS;
    case 'b': return NT_TILE_22DEGnnB;
    case 's': return NT_TILE_22DEGnnS;
    default: return -1;
    }
}

static nt_map *empty_map(int w, int h, nt_real cell)
{
    nt_map_def d = nt_default_map_def();
    d.width = w;
    d.height = h;
    d.cell_size = cell;
    nt_map *m = NULL;
    assert_int_equal(nt_map_create(&d, &m), NT_OK);
    return m;
}

static nt_map *make_map(int w, int h, nt_real cell, const char *const *rows)
{
    nt_map *m = empty_map(w, h, cell);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int t = tile_of(rows[y][x]);
            assert_true(t >= 0);
            assert_int_equal(nt_map_set_tile(m, x, y, t), NT_OK);
        }
    return m;
}

static void expect_edges(const nt_map *m, int x, int y, int l, int r, int t, int b)
{
    int got[4] = {nt_map_get_edge(m, x, y, NT_SIDE_LEFT), nt_map_get_edge(m, x, y, NT_SIDE_RIGHT),
                  nt_map_get_edge(m, x, y, NT_SIDE_TOP), nt_map_get_edge(m, x, y, NT_SIDE_BOTTOM)};
    int want[4] = {l, r, t, b};
    for (int s = 0; s < 4; s++) {
        if (got[s] != want[s]) {
            print_error("cell (%d,%d) side %d: edge %d, expected %d\n", x, y, s, got[s], want[s]);
            fail();
        }
    }
}

static void test_create_errors(void **state)
{
    (void)state;
    nt_map *m = (nt_map *)1;
    nt_map_def d = nt_default_map_def();
    assert_int_equal(d.width, 31);
    assert_int_equal(d.height, 23);
    d.width = 0;
    assert_int_equal(nt_map_create(&d, &m), NT_ERR_OUT_OF_RANGE);
    assert_null(m);
    d = nt_default_map_def();
    d.height = NT_MAP_MAX_SIDE + 1;
    assert_int_equal(nt_map_create(&d, &m), NT_ERR_OUT_OF_RANGE);
    d = nt_default_map_def();
    d.cell_size = 0;
    assert_int_equal(nt_map_create(&d, &m), NT_ERR_INVALID_ARGUMENT);
    d.cell_size = (nt_real)NAN;
    assert_int_equal(nt_map_create(&d, &m), NT_ERR_NON_FINITE);
    d.cell_size = (nt_real)INFINITY;
    assert_int_equal(nt_map_create(&d, &m), NT_ERR_NON_FINITE);
    assert_int_equal(nt_map_create(NULL, &m), NT_ERR_INVALID_ARGUMENT);

    d = nt_default_map_def();
    assert_int_equal(nt_map_create(&d, &m), NT_OK);
    assert_int_equal(nt_map_get_width(m), 31);
    assert_int_equal(nt_map_get_height(m), 23);
    assert_true(nt_map_get_cell_size(m) == 24);
    /* Bad edits leave the map unchanged. */
    assert_int_equal(nt_map_set_tile(m, 3, 3, NT_TILE_FULL), NT_OK);
    assert_int_equal(nt_map_set_tile(m, 3, 3, 34), NT_ERR_OUT_OF_RANGE);
    assert_int_equal(nt_map_set_tile(m, 3, 3, -1), NT_ERR_OUT_OF_RANGE);
    assert_int_equal(nt_map_set_tile(m, -1, 3, NT_TILE_FULL), NT_ERR_OUT_OF_RANGE);
    assert_int_equal(nt_map_set_tile(m, 31, 3, NT_TILE_FULL), NT_ERR_OUT_OF_RANGE);
    assert_int_equal(nt_map_get_tile(m, 3, 3), NT_TILE_FULL);
    uint8_t *tiles = calloc(31 * 23, 1);
    tiles[5] = 40;
    assert_int_equal(nt_map_set_tiles(m, tiles, 31 * 23), NT_ERR_OUT_OF_RANGE);
    assert_int_equal(nt_map_set_tiles(m, tiles, 31 * 22), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_map_get_tile(m, 3, 3), NT_TILE_FULL);
    free(tiles);
    /* Outside the map is FULL border. */
    assert_int_equal(nt_map_get_tile(m, -1, 0), NT_TILE_FULL);
    assert_int_equal(nt_map_get_tile(m, 31, 22), NT_TILE_FULL);
    assert_int_equal(nt_map_get_tile(m, 0, 23), NT_TILE_FULL);
    nt_map_destroy(m);
    nt_map_destroy(NULL);
}

static void test_edges_floor_and_wall(void **state)
{
    (void)state;
    const char *rows[] = {
        "....",
        ".##.",
        "####",
    };
    nt_map *m = make_map(4, 3, 1, rows);
    /*                 L      R      T      B */
    expect_edges(m, 1, 1, E_SOL, E_OFF, E_SOL, E_OFF); /* FULL, FULL to the right and below */
    expect_edges(m, 2, 1, E_OFF, E_SOL, E_SOL, E_OFF);
    expect_edges(m, 0, 1, E_SOL, E_SOL, E_OFF, E_SOL); /* empty: border left, FULL right and below */
    expect_edges(m, 0, 0, E_SOL, E_OFF, E_SOL, E_OFF); /* border on two sides */
    expect_edges(m, 1, 2, E_OFF, E_OFF, E_OFF, E_OFF); /* buried: every seam gone */
    expect_edges(m, 0, 2, E_OFF, E_OFF, E_SOL, E_OFF);
    expect_edges(m, 3, 1, E_SOL, E_SOL, E_OFF, E_SOL);
    /* Digging a hole updates the cell and its four neighbours. */
    assert_int_equal(nt_map_set_tile(m, 1, 2, NT_TILE_EMPTY), NT_OK);
    expect_edges(m, 1, 2, E_SOL, E_SOL, E_SOL, E_SOL);
    expect_edges(m, 0, 2, E_OFF, E_SOL, E_SOL, E_OFF);
    expect_edges(m, 2, 2, E_SOL, E_OFF, E_OFF, E_OFF);
    expect_edges(m, 1, 1, E_SOL, E_OFF, E_SOL, E_SOL);
    nt_map_destroy(m);
}

static void test_edges_slopes_halves_round(void **state)
{
    (void)state;
    const char *rows[] = {
        ".....",
        "\\..dd",
        "###c#",
        "#####",
    };
    nt_map *m = make_map(5, 4, 1, rows);
    /* 45DEGpn: covers its left and bottom sides whole, touches top and right at a point. */
    expect_edges(m, 0, 1, E_OFF, E_INT, E_INT, E_OFF);
    expect_edges(m, 1, 1, E_INT, E_OFF, E_OFF, E_SOL);
    expect_edges(m, 0, 0, E_SOL, E_OFF, E_SOL, E_INT);
    /* HALFd beside HALFd: partial covers on both sides. HALFd over CONCAVEpn: the
     * concave tile touches its top only at the cusp (0,0). */
    expect_edges(m, 3, 1, E_INT, E_INT, E_OFF, E_SOL);
    expect_edges(m, 4, 1, E_INT, E_SOL, E_OFF, E_OFF);
    /* CONCAVEpn: whole left and bottom sides, point contacts top and right. */
    expect_edges(m, 3, 2, E_OFF, E_SOL, E_SOL, E_OFF);
    expect_edges(m, 2, 2, E_OFF, E_OFF, E_SOL, E_OFF);
    nt_map_destroy(m);

    const char *rows2[] = {
        "o.",
        "..",
    };
    m = make_map(2, 2, 1, rows2);
    /* CONVEXpn: quarter disc around (0,1): whole left and bottom, points top and right. */
    expect_edges(m, 0, 0, E_OFF, E_INT, E_SOL, E_SOL);
    expect_edges(m, 1, 0, E_INT, E_SOL, E_SOL, E_OFF);
    expect_edges(m, 0, 1, E_SOL, E_OFF, E_SOL, E_SOL);
    nt_map_destroy(m);
}

/* Bulk set_tiles and cell-by-cell set_tile agree on every edge of a random map. */
static void test_edges_bulk_matches_incremental(void **state)
{
    (void)state;
    enum { W = 13, H = 9 };
    uint64_t s = 0x1234567ULL;
    uint8_t tiles[W * H];
    for (int i = 0; i < W * H; i++) {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        int r = (int)((s >> 33) % 100);
        tiles[i] = (uint8_t)(r < 45 ? 0 : (r < 60 ? 1 : (int)((s >> 40) % NT_TILE_COUNT)));
    }
    nt_map_def d = nt_default_map_def();
    d.width = W;
    d.height = H;
    nt_map *a, *b;
    assert_int_equal(nt_map_create(&d, &a), NT_OK);
    assert_int_equal(nt_map_create(&d, &b), NT_OK);
    assert_int_equal(nt_map_set_tiles(a, tiles, W * H), NT_OK);
    /* Incremental in a scrambled order, with a detour through FULL for some cells. */
    for (int k = 0; k < W * H; k++) {
        int i = (k * 37) % (W * H);
        if (k % 3 == 0) assert_int_equal(nt_map_set_tile(b, i % W, i / W, NT_TILE_FULL), NT_OK);
        assert_int_equal(nt_map_set_tile(b, i % W, i / W, tiles[i]), NT_OK);
    }
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            assert_int_equal(nt_map_get_tile(a, x, y), tiles[y * W + x]);
            for (int side = 0; side < 4; side++)
                assert_int_equal(nt_map_get_edge(a, x, y, (nt_side)side), nt_map_get_edge(b, x, y, (nt_side)side));
        }
    nt_map_destroy(a);
    nt_map_destroy(b);
}

static void check_push(const nt_map *m, nt_vec2 p, nt_shape sh, nt_real ex, nt_real ey, nt_real tol)
{
    nt_resolution r;
    bool hit = nt_map_resolve(m, p, sh, &r);
    if (!hit || fabs((double)(r.push.x - ex)) > tol || fabs((double)(r.push.y - ey)) > tol) {
        print_error("resolve %s at (%.6f, %.6f): hit %d push (%.7f, %.7f), expected (%.7f, %.7f)\n",
                    sh.type == NT_SHAPE_CIRCLE ? "circle" : "aabb", (double)p.x, (double)p.y, hit, (double)r.push.x,
                    (double)r.push.y, (double)ex, (double)ey);
        fail();
    }
    assert_true(r.contact_count >= 1);
}

/* A box or circle anywhere along a long flat floor of FULL tiles, seams included,
 * goes straight up by its penetration. */
static void test_resolve_flat_floor_seams(void **state)
{
    (void)state;
    const nt_real cells[2] = {1, 24};
    for (int ci = 0; ci < 2; ci++) {
        nt_real cs = cells[ci];
        const char *rows[] = {"..........", "..........", "##########"};
        nt_map *m = make_map(10, 3, cs, rows);
        for (int shape = 0; shape < 2; shape++)
            for (int i = 0; i <= 400; i++) {
                nt_real half = R(0.1) + R(0.4) * (nt_real)(i % 7) / 6;
                if (half > R(0.5)) half = R(0.5); /* rounding must not exceed the largest allowed size */
                nt_shape sh = shape ? nt_shape_circle(half * cs) : nt_shape_aabb(half * cs, half * R(0.6) * cs);
                nt_real x = (R(1) + R(8) * (nt_real)i / 400) * cs; /* crosses every seam, lands on some exactly */
                nt_real pen = (R(0.002) + R(0.25) * (nt_real)((i * 7) % 13) / 12) * half * R(0.6);
                nt_real y = 2 * cs - sh.half.y + pen * cs;
                check_push(m, nt_v2(x, y), sh, 0, -pen * cs, R(2e-4) * cs);
            }
        nt_map_destroy(m);
    }
}

/* A box slides down a 45-degree slope onto a flat floor: the corner where they
 * meet never pushes it back up the slope or sideways. */
static void test_resolve_slope_to_floor(void **state)
{
    (void)state;
    const char *rows[] = {
        "......",
        "\\.....",
        "######",
    };
    nt_map *m = make_map(6, 3, 1, rows);
    for (int shape = 0; shape < 2; shape++) {
        nt_real hw = R(0.3);
        nt_shape sh = shape ? nt_shape_circle(hw) : nt_shape_aabb(hw, hw);
        for (int i = 0; i <= 300; i++) {
            /* Track of the object's lowest point: along the slope x + ... then the floor y = 2. */
            nt_real s = R(-0.2) + R(2.2) * (nt_real)i / 300; /* x of the contact point */
            nt_real pen = R(0.01);
            nt_vec2 p;
            if (shape == 0) {
                /* Box: its bottom-left corner rides the slope y = 1 + x (x in [0,1]), then y = 2. */
                nt_real cy = s < 1 ? 1 + s : 2;
                p = nt_v2(s + hw, cy - hw + pen);
            } else {
                /* Circle: rides the slope at distance r along the normal, then the floor. */
                nt_real n = R(0.70710678118654752);
                nt_vec2 on = s < 1 ? nt_v2(s + (hw - pen) * n, 1 + s - (hw - pen) * n) : nt_v2(s, 2 - hw + pen);
                p = on;
            }
            nt_resolution r;
            if (!nt_map_resolve(m, p, sh, &r)) continue;
            /* Never a push to the left (up the slope backwards) and never a push that
             * is neither the slope normal nor straight up. */
            if (r.push.x < -1e-6) {
                print_error("%s at (%.4f, %.4f): pushed left (%.6f, %.6f)\n", shape ? "circle" : "box",
                            (double)p.x, (double)p.y, (double)r.push.x, (double)r.push.y);
                fail();
            }
            assert_true(r.push.y <= R(1e-6));
            assert_true(nt_map_overlap_depth(m, nt_v2(p.x + r.push.x, p.y + r.push.y), sh) <= R(1e-4));
            if (s > R(1.35)) /* wholly over the floor: straight up */
                check_push(m, p, sh, 0, -pen, R(1e-4));
        }
    }
    nt_map_destroy(m);
}

/* A 22-degree slope made of 22DEGpnB then 22DEGpnS is one straight line, so an
 * object sunk by `pen` into it leaves along the line's normal by exactly `pen`
 * (analytic), also where the nearest point of one tile alone is its vertex: a
 * shorter push that frees that tile leaves the object inside the other. */
static void test_resolve_joined_22_slope(void **state)
{
    (void)state;
    const char *rows[] = {"......", "......", "......", "..BS..", "######"};
    nt_map *m = make_map(6, 5, 1, rows);
    /* The surface: y = 3 + (x - 2) / 2 for x in [2, 4]; outward normal (1, -2) / sqrt 5. */
    const double nx = 1 / sqrt(5.0), ny = -2 / sqrt(5.0);
    const double pens[] = {1e-4, 2.5e-4, 1e-3, 1e-2};
    int checked = 0;
    for (int shape = 0; shape < 2; shape++)
        for (int k = 0; k < 4; k++)
            for (int i = 0; i <= 200; i++) {
                double r = 0.25, pen = pens[k];
                double sx = 2.6 + 0.8 * i / 200.0, sy = 3 + (sx - 2) / 2; /* a point of the surface */
                double cx, cy;
                if (shape) { /* circle: centre at r - pen along the normal */
                    cx = sx + nx * (r - pen);
                    cy = sy + ny * (r - pen);
                } else { /* box: its bottom-left corner sunk by pen */
                    cx = sx - nx * pen + r;
                    cy = sy - ny * pen - r;
                }
                nt_shape sh = shape ? nt_shape_circle(R(r)) : nt_shape_aabb(R(r), R(r));
                nt_vec2 p = nt_v2((nt_real)cx, (nt_real)cy);
                /* The exact sink of the rounded position. */
                double want = shape ? r - (((double)p.x - 2) * nx + ((double)p.y - 3) * ny)
                                    : -((((double)p.x - r) - 2) * nx + (((double)p.y + r) - 3) * ny);
                nt_resolution res;
                assert_true(nt_map_resolve(m, p, sh, &res));
                double ex = (double)res.push.x - want * nx, ey = (double)res.push.y - want * ny;
                if (sqrt(ex * ex + ey * ey) > 5e-6) {
                    print_error("%s at (%.7f, %.7f) pen %g: push (%.9g, %.9g), expected (%.9g, %.9g)\n",
                                shape ? "circle" : "box", cx, cy, pen, (double)res.push.x, (double)res.push.y,
                                want * nx, want * ny);
                    fail();
                }
                checked++;
            }
    assert_int_equal(checked, 2 * 4 * 201);
    nt_map_destroy(m);
}

/* A circle resting on a flat floor across the seam of two FULL tiles, far from the
 * origin (where float's rounding tolerance is coarse): the tiles' corners at the
 * seam are no corners of the floor, so the push is straight up everywhere. */
static void test_resolve_seam_far_from_origin(void **state)
{
    (void)state;
    nt_map_def d = nt_default_map_def();
    d.width = d.height = 4096;
    nt_map *m = NULL;
    assert_int_equal(nt_map_create(&d, &m), NT_OK);
    int ox = 4080, oy = 4090;
    for (int x = 0; x < 10; x++) assert_int_equal(nt_map_set_tile(m, ox + x, oy, NT_TILE_FULL), NT_OK);
    int pushes = 0;
    for (int k = -40; k <= 40; k++) {
        nt_real x = R((ox + 5) * 24.0 + k * 0.05), y = R(oy * 24.0 - 7 + 0.09);
        nt_resolution r;
        if (!nt_map_resolve(m, nt_v2(x, y), nt_shape_circle(7), &r)) continue;
        pushes++;
        if (r.push.x != 0 || !(r.push.y < 0)) {
            print_error("seam offset %g: push (%g, %g)\n", k * 0.05, (double)r.push.x, (double)r.push.y);
            fail();
        }
    }
    assert_int_equal(pushes, 81);
    nt_map_destroy(m);
}

/* Inside an L-shaped corner (floor + wall) the way out is the corner point. */
static void test_resolve_concave_corner(void **state)
{
    (void)state;
    const char *rows[] = {"#...", "#...", "####"};
    nt_map *m = make_map(4, 3, 1, rows);
    check_push(m, nt_v2(R(1.2), R(1.8)), nt_shape_aabb(R(0.25), R(0.25)), R(0.05), R(-0.05), R(1e-5));
    check_push(m, nt_v2(R(1.22), R(1.77)), nt_shape_aabb(R(0.25), R(0.25)), R(0.03), R(-0.02), R(1e-5));
    /* A circle in the corner leaves along both faces as well. */
    check_push(m, nt_v2(R(1.2), R(1.8)), nt_shape_circle(R(0.25)), R(0.05), R(-0.05), R(1e-5));
    nt_map_destroy(m);
}

static void test_resolve_free_and_border(void **state)
{
    (void)state;
    const char *rows[] = {"....", "....", "...."};
    nt_map *m = make_map(4, 3, 1, rows);
    nt_resolution r;
    r.push = nt_v2(5, 5);
    assert_false(nt_map_resolve(m, nt_v2(R(2.0), R(1.5)), nt_shape_aabb(R(0.4), R(0.4)), &r));
    assert_true(r.push.x == 0 && r.push.y == 0 && r.contact_count == 0);
    assert_true(nt_map_overlap_depth(m, nt_v2(R(2.0), R(1.5)), nt_shape_circle(R(0.4))) == 0);
    /* Touching the border is not overlapping. */
    assert_false(nt_map_resolve(m, nt_v2(R(0.4), R(1.5)), nt_shape_aabb(R(0.4), R(0.4)), &r));
    /* Outside the map is solid: poking into the left border pushes right. */
    check_push(m, nt_v2(R(0.3), R(1.5)), nt_shape_aabb(R(0.4), R(0.4)), R(0.1), 0, R(1e-5));
    check_push(m, nt_v2(R(2.0), R(2.8)), nt_shape_circle(R(0.3)), 0, R(-0.1), R(1e-5));
    /* Non-finite positions are rejected quietly. */
    assert_false(nt_map_resolve(m, nt_v2((nt_real)NAN, 1), nt_shape_circle(R(0.3)), &r));
    nt_map_destroy(m);
}

/* ---- against the brute-force union reference ---- */

static uint64_t rng_state = 0x9E3779B97F4A7C15ULL;
static double urand(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : (x > y ? 1 : 0);
}

/* Random 4x4 maps, random overlapping placements: the push frees the object and
 * is the shortest way out of the union of the tiles (median exact, >= 99 % within 5 %). */
static void test_resolve_vs_union_reference(void **state)
{
    (void)state;
    enum { W = 4, H = 4, TRIALS = 1500 };
    double *rel = malloc(sizeof(double) * TRIALS);
    int n = 0, not_freed = 0, checked_free = 0;
    int tiles[W * H];
    uint8_t t8[W * H];
    nt_map *m = empty_map(W, H, 1);
    for (int attempt = 0; n < TRIALS && attempt < 20 * TRIALS; attempt++) {
        for (int i = 0; i < W * H; i++) {
            double u = urand();
            tiles[i] = u < 0.4 ? 0 : (u < 0.55 ? 1 : 1 + (int)(urand() * 33));
            if (tiles[i] > 33) tiles[i] = 33;
            t8[i] = (uint8_t)tiles[i];
        }
        assert_int_equal(nt_map_set_tiles(m, t8, W * H), NT_OK);
        for (int k = 0; k < 20 && n < TRIALS; k++) {
            int circle = urand() < 0.5;
            ref_shape rs;
            nt_shape sh;
            double hw = 0.05 + 0.45 * urand(), hh = 0.05 + 0.45 * urand();
            if (circle) {
                rs = ref_circle(hw);
                sh = nt_shape_circle((nt_real)hw);
            } else {
                rs = ref_aabb(hw, hh);
                sh = nt_shape_aabb((nt_real)hw, (nt_real)hh);
            }
            double x = 1 + 2 * urand(), y = 1 + 2 * urand();
            double rdx, rdy;
            ref_mtv_map(tiles, W, H, rs, x, y, &rdx, &rdy);
            double rlen = sqrt(rdx * rdx + rdy * rdy);
            if (rlen < 1e-3 || rlen > 0.3) continue; /* free, or deeper than the promise covers */
            nt_resolution r;
            bool hit = nt_map_resolve(m, nt_v2((nt_real)x, (nt_real)y), sh, &r);
            assert_true(hit);
            double len = sqrt((double)r.push.x * r.push.x + (double)r.push.y * r.push.y);
            double resid = (double)nt_map_overlap_depth(m, nt_v2((nt_real)(x + r.push.x), (nt_real)(y + r.push.y)), sh);
            checked_free++;
            if (resid > 1e-4) {
                not_freed++;
                print_error("not freed: %s %.4f %.4f at (%.5f, %.5f) push (%.5f, %.5f) residual %.2g\n",
                            circle ? "circle" : "aabb", hw, hh, x, y, (double)r.push.x, (double)r.push.y, resid);
            }
            rel[n++] = (len - rlen) / rlen;
        }
    }
    assert_true(n >= TRIALS / 2);
    qsort(rel, (size_t)n, sizeof(double), cmp_double);
    int within = 0;
    for (int i = 0; i < n; i++)
        if (fabs(rel[i]) <= 0.05) within++;
    double median = rel[n / 2];
    print_message("resolve vs union reference: %d placements, median rel. error %.2e, within 5%%: %.2f%%, "
                  "worst %.3f, not freed %d/%d\n",
                  n, median, 100.0 * within / n, rel[n - 1], not_freed, checked_free);
    assert_int_equal(not_freed, 0);
    assert_true(fabs(median) <= 1e-3);
    assert_true(within >= (int)(0.99 * n));
    nt_map_destroy(m);
    free(rel);
}

/* ---- large objects (issue 18: half-sizes up to NT_MAX_HALF_CELLS) ---- */

/* Engine tolerance on a push length: float rounds positions of a few cells at ~1e-6. */
static const double BIG_TOL = NT_REAL_IS_DOUBLE ? 1e-9 : 2e-5;

/* The map's tiles as ints for the reference. */
static void map_ints(const nt_map *m, int *tiles)
{
    int w = nt_map_get_width(m), h = nt_map_get_height(m);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) tiles[y * w + x] = nt_map_get_tile(m, x, y);
}

/* One placement (cell size 1) against the reference: the push frees the object (the
 * reference's overlap test, object shrunk by `tol`) and is as short as the reference's
 * (within tol). Returns 1 when checked, 0 when skipped (free, or no room at all); a
 * failure is printed and counted. *len_out receives the reference length. */
static int big_check(const nt_map *m, const int *tiles, ref_shape rs, double x, double y, double tol, int *bad,
                     double *len_out, nt_resolution *res_out)
{
    int w = nt_map_get_width(m), h = nt_map_get_height(m);
    double rdx, rdy;
    double rlen = ref_mtv_map(tiles, w, h, rs, x, y, &rdx, &rdy);
    if (len_out) *len_out = rlen;
    if (rlen <= 0) return 0;
    nt_shape sh = rs.is_circle ? nt_shape_circle((nt_real)rs.hw) : nt_shape_aabb((nt_real)rs.hw, (nt_real)rs.hh);
    nt_resolution r;
    bool hit = nt_map_resolve(m, nt_v2((nt_real)x, (nt_real)y), sh, &r);
    if (res_out) *res_out = r;
    double len = sqrt((double)r.push.x * r.push.x + (double)r.push.y * r.push.y);
    double qx = x + (double)r.push.x, qy = y + (double)r.push.y;
    const char *why = NULL;
    if (!hit) why = "no push";
    else if (ref_object_overlaps_map(tiles, w, h, ref_shape_grow(rs, -tol), qx, qy)) why = "not freed";
    else if (len > rlen + tol) why = "longer than the shortest push";
    else if (len < rlen - tol) why = "shorter than the reference (freed within tolerance only)";
    else if (r.contact_count < 1 || r.contact_count > 2) why = "no contact";
    else
        for (int i = 0; i < r.contact_count && !why; i++)
            if (fabs(hypot((double)r.contacts[i].normal.x, (double)r.contacts[i].normal.y) - 1) > 1e-4)
                why = "a contact normal is not unit length";
    if (why) {
        if ((*bad)++ < 10)
            print_error("%s: %s %.17g x %.17g at (%.17g, %.17g): push (%.9g, %.9g) len %.9g, reference (%.9g, %.9g) len %.9g\n",
                        why, rs.is_circle ? "circle" : "box", rs.hw, rs.hh, x, y, (double)r.push.x, (double)r.push.y,
                        len, rdx, rdy, rlen);
    }
    return 1;
}

/* Tiny bodies (half-size 0.003..0.02 cell) buried anywhere in random 5 x 5 maps, as
 * deep as a cell: the push is the reference's shortest way out of the union. Across a
 * masked seam a neighbour's free pocket may be the nearest way out; the first case is
 * the one issue 20 found (ntile pushed (0.988, 0) out of the FULL tile, the pocket of
 * the 22-degree tile beside it is 0.038 away). */
static void test_resolve_tiny_buried_vs_reference(void **state)
{
    (void)state;
    enum { W = 5, H = 5 };
    static const char *const names[W * H] = {"CONVEXpp", "EMPTY",    "45DEGpn", "EMPTY",   "67DEGpnB",
                                             "67DEGnpS", "67DEGnpB", "EMPTY",   "EMPTY",   "22DEGpnB",
                                             "FULL",     "EMPTY",    "22DEGnpB", "FULL",   "EMPTY",
                                             "EMPTY",    "CONCAVEpn", "FULL",   "HALFu",   "45DEGnn",
                                             "CONCAVEnn", "FULL",    "FULL",    "45DEGnp", "FULL"};
    int tiles[W * H];
    uint8_t t8[W * H];
    for (int i = 0; i < W * H; i++) {
        tiles[i] = nt_tile_from_name(names[i]);
        assert_true(tiles[i] >= 0);
        t8[i] = (uint8_t)tiles[i];
    }
    nt_map *m = empty_map(W, H, 1);
    assert_int_equal(nt_map_set_tiles(m, t8, W * H), NT_OK);
    int bad = 0, checked = 0;
    checked += big_check(m, tiles, ref_circle(0.005), 3.016791, 2.989300, BIG_TOL, &bad, NULL, NULL);
    assert_int_equal(bad, 0);
    for (int attempt = 0; attempt < 300; attempt++) {
        for (int i = 0; i < W * H; i++) {
            double u = urand();
            tiles[i] = u < 0.3 ? 0 : (u < 0.5 ? 1 : 1 + (int)(urand() * 33));
            if (tiles[i] > 33) tiles[i] = 33;
            t8[i] = (uint8_t)tiles[i];
        }
        assert_int_equal(nt_map_set_tiles(m, t8, W * H), NT_OK);
        for (int k = 0; k < 10; k++) {
            double hw = 0.003 + 0.017 * urand(), hh = 0.003 + 0.017 * urand();
            ref_shape rs = urand() < 0.5 ? ref_circle(hw) : ref_aabb(hw, hh);
            int b0 = bad;
            checked += big_check(m, tiles, rs, 1 + 3 * urand(), 1 + 3 * urand(), BIG_TOL, &bad, NULL, NULL);
            for (int i = 0; bad != b0 && i < W * H; i++) /* the map, to reproduce */
                print_message("%s%s", tiles[i] ? nt_tile_get_info(tiles[i])->name : "EMPTY", i % W == W - 1 ? "\n" : ",");
        }
    }
    print_message("tiny buried bodies vs union reference: %d placements, %d wrong\n", checked, bad);
    assert_true(checked > 1000);
    assert_int_equal(bad, 0);
    nt_map_destroy(m);
}

/* Random 12 x 12 maps (most cells EMPTY, the rest any tile, slopes and round tiles
 * included), objects of half-size 0.5..4 (boxes also thin one way), random centres:
 * the push is the reference's shortest way out of the union, and frees the object. */
static void test_resolve_large_vs_union_reference(void **state)
{
    (void)state;
    enum { W = 12, H = 12, TRIALS = 200 }; /* the reference costs ~20 ms a placement */
    int tiles[W * H], n = 0, bad = 0, deep = 0;
    uint8_t t8[W * H];
    nt_map *m = empty_map(W, H, 1);
    ref_rng rng = ref_rng_seed(1818);
    for (int attempt = 0; n < TRIALS && attempt < 40 * TRIALS; attempt++) {
        if (attempt % 10 == 0) {
            double empty = ref_rng_uniform(&rng, 0.55, 0.85);
            for (int i = 0; i < W * H; i++) {
                tiles[i] = ref_rng_uniform(&rng, 0, 1) < empty ? 0 : 1 + ref_rng_int(&rng, 33);
                t8[i] = (uint8_t)tiles[i];
            }
            assert_int_equal(nt_map_set_tiles(m, t8, W * H), NT_OK);
        }
        int circle = ref_rng_int(&rng, 2);
        double a = (double)(nt_real)ref_rng_uniform(&rng, 0.5, NT_MAX_HALF_CELLS);
        double b = (double)(nt_real)ref_rng_uniform(&rng, 0.5, NT_MAX_HALF_CELLS);
        if (!circle && ref_rng_int(&rng, 3) == 0) b = (double)(nt_real)ref_rng_uniform(&rng, 0.05, 0.5);
        if (!circle && ref_rng_int(&rng, 2)) {
            double t = a;
            a = b;
            b = t;
        }
        ref_shape rs = circle ? ref_circle(a) : ref_aabb(a, b);
        double x = (double)(nt_real)ref_rng_uniform(&rng, rs.hw, W - rs.hw);
        double y = (double)(nt_real)ref_rng_uniform(&rng, rs.hh, H - rs.hh);
        double rlen;
        if (!ref_object_overlaps_map(tiles, W, H, rs, x, y)) continue;
        n += big_check(m, tiles, rs, x, y, BIG_TOL, &bad, &rlen, NULL);
        deep += rlen > 1;
    }
    print_message("large resolve vs union reference: %d placements (%d deeper than a cell), %d failures\n", n, deep,
                  bad);
    assert_true(n >= TRIALS / 2);
    assert_int_equal(bad, 0);
    nt_map_destroy(m);
}

/* Rest height of the object at x (cell size 1): the largest y at which it is free,
 * from the reference alone (bisection from a free height above). */
static double rest_y(const int *tiles, int w, int h, ref_shape rs, double x, double y_free)
{
    double lo = y_free, hi = h + 1.0;
    for (int it = 0; it < 60; it++) {
        double mid = 0.5 * (lo + hi);
        if (ref_object_overlaps_map(tiles, w, h, rs, x, mid)) hi = mid;
        else lo = mid;
    }
    return lo;
}

/* A long box (half 4 x 0.5, and others) sunk skin-deep at many x along a 30-tile FULL
 * floor, in cells of 1 and 24 units: straight up by the skin, whatever the seams under it. */
static void test_resolve_large_long_floor(void **state)
{
    (void)state;
    const nt_real cells[2] = {1, 24};
    const double halves[3][2] = {{4, 0.5}, {3.3, 1.7}, {NT_MAX_HALF_CELLS, NT_MAX_HALF_CELLS}};
    int checked = 0;
    for (int ci = 0; ci < 2; ci++) {
        nt_real cs = cells[ci];
        nt_map *m = empty_map(34, 10, cs);
        for (int x = 2; x < 32; x++) assert_int_equal(nt_map_set_tile(m, x, 9, NT_TILE_FULL), NT_OK);
        for (int k = 0; k < 4; k++)
            for (int i = 0; i <= 300; i++) {
                int circle = k == 3;
                double hw = circle ? 2.5 : halves[k][0], hh = circle ? 2.5 : halves[k][1];
                nt_shape sh = circle ? nt_shape_circle((nt_real)hw * cs) : nt_shape_aabb((nt_real)hw * cs, (nt_real)hh * cs);
                double x = 2 + hw + (30 - 2 * hw) * i / 300.0; /* lands on seams too */
                if (circle) x = 2.5 + 29 * i / 300.0;          /* circles also past the floor's ends */
                double skin = 1e-3 + 0.2 * ((i * 7) % 13) / 12.0;
                nt_vec2 p = nt_v2((nt_real)(x * cs), (nt_real)((9 - hh + skin) * cs));
                double want = (double)(9 * cs) - ((double)p.y + (double)sh.half.y); /* the sink of the rounded position */
                nt_resolution r;
                assert_true(nt_map_resolve(m, p, sh, &r));
                int ends = circle && (x < 2 || x > 32);
                if (!ends && (fabs((double)r.push.x) > BIG_TOL * cs || fabs((double)r.push.y - want) > 4 * BIG_TOL * cs)) {
                    print_error("cell %g, %s %g x %g at x %.6f skin %g: push (%.9g, %.9g), expected (0, %.9g)\n", (double)cs,
                                circle ? "circle" : "box", hw, hh, x, skin, (double)r.push.x, (double)r.push.y, want);
                    fail();
                }
                checked++;
            }
        nt_map_destroy(m);
    }
    assert_int_equal(checked, 2 * 4 * 301);
}

/* Long objects along a floor of flats joined by 45 and 22 degree slopes (both ways),
 * sunk skin-deep below their rest height at many x: the push is the reference's
 * shortest, frees the object, and goes along a surface normal of the floor (up, or a
 * slope's normal), never sideways or up the slope by a seam. */
static void test_resolve_large_slope_joins(void **state)
{
    (void)state;
    const char *rows[] = {
        "..................................", "..................................", "..................................",
        "..................................", "..................................", "..................................",
        "..................................", "..................................", "..................................",
        "....../######\\.....sb######BS.....", "##################################", "##################################",
    };
    enum { W = 34, H = 12 };
    nt_map *m = make_map(W, H, 1, rows);
    int tiles[W * H];
    map_ints(m, tiles);
    const double s45 = sqrt(0.5), s22 = 1 / sqrt(5.0);
    const double normals[5][2] = {{0, -1}, {s45, -s45}, {-s45, -s45}, {s22, -2 * s22}, {-s22, -2 * s22}};
    const double shapes[4][3] = {{0, 4, 0.5}, {0, 2.5, 1.5}, {0, 0.75, 0.6}, {1, 3, 3}};
    int n = 0, bad = 0, off_normal = 0;
    for (int k = 0; k < 4; k++)
        for (int i = 0; i <= 400; i++) {
            ref_shape rs = shapes[k][0] > 0 ? ref_circle(shapes[k][1]) : ref_aabb(shapes[k][1], shapes[k][2]);
            double x = (double)(nt_real)(rs.hw + (W - 2 * rs.hw) * i / 400.0);
            double skin = 1e-3 + 0.05 * ((i * 5) % 11) / 10.0;
            double y = (double)(nt_real)(rest_y(tiles, W, H, rs, x, rs.hh) + skin);
            nt_resolution r;
            double rlen;
            if (!big_check(m, tiles, rs, x, y, BIG_TOL, &bad, &rlen, &r)) continue;
            n++;
            double len = sqrt((double)r.push.x * r.push.x + (double)r.push.y * r.push.y), best = 2;
            for (int j = 0; j < 5; j++)
                best = fmin(best, hypot((double)r.push.x / len - normals[j][0], (double)r.push.y / len - normals[j][1]));
            /* A push between two normals is a corner of the floor (two contacts) or a
             * convex vertex of the floor (the reference's way too), not a seam. */
            double rdx, rdy;
            ref_mtv_map(tiles, W, H, rs, x, y, &rdx, &rdy);
            double as_ref = hypot((double)r.push.x - rdx, (double)r.push.y - rdy); /* float: rounding of ~20 */
            if (best > 1e-4 && r.contact_count < 2 && as_ref > 5 * BIG_TOL) {
                if (off_normal++ < 10)
                    print_error("%s %g x %g at (%.6f, %.6f): push (%.9g, %.9g) is no surface normal (reference (%.9g, %.9g))\n",
                                rs.is_circle ? "circle" : "box", rs.hw, rs.hh, x, y, (double)r.push.x, (double)r.push.y,
                                rdx, rdy);
            }
        }
    print_message("large objects on slope joins: %d placements, %d failures, %d pushes off the normals\n", n, bad,
                  off_normal);
    assert_true(n > 1400);
    assert_int_equal(bad, 0);
    assert_int_equal(off_normal, 0);
    nt_map_destroy(m);
}

/* Large objects with their centre deep in the border (outside the map, FULL) or
 * in a map too small for them: freed when the map has room (the reference's
 * overlap test), a zero push when it has none. */
static void test_resolve_large_far_outside(void **state)
{
    (void)state;
    enum { W = 12, H = 10 };
    nt_map *m = empty_map(W, H, 1);
    for (int x = 0; x < W; x++) assert_int_equal(nt_map_set_tile(m, x, H - 1, NT_TILE_FULL), NT_OK);
    int tiles[W * H];
    map_ints(m, tiles);
    const double pos[6][2] = {{-9, 4}, {20, 3}, {5, -12}, {6, 30}, {-7, -7}, {25, 25}};
    for (int k = 0; k < 6; k++)
        for (int circle = 0; circle < 2; circle++) {
            ref_shape rs = circle ? ref_circle(3.5) : ref_aabb(NT_MAX_HALF_CELLS, 2.25);
            nt_shape sh = circle ? nt_shape_circle(R(3.5)) : nt_shape_aabb(R(NT_MAX_HALF_CELLS), R(2.25));
            nt_resolution r;
            assert_true(nt_map_resolve(m, nt_v2((nt_real)pos[k][0], (nt_real)pos[k][1]), sh, &r));
            double qx = pos[k][0] + (double)r.push.x, qy = pos[k][1] + (double)r.push.y;
            if (ref_object_overlaps_map(tiles, W, H, ref_shape_grow(rs, -BIG_TOL), qx, qy)) {
                print_error("%s from (%g, %g): push (%g, %g) does not free it\n", circle ? "circle" : "box", pos[k][0],
                            pos[k][1], (double)r.push.x, (double)r.push.y);
                fail();
            }
        }
    nt_map_destroy(m);
    /* No room: a 4 x 4 map is narrower than the box. */
    nt_map *small = empty_map(4, 4, 1);
    nt_resolution r;
    assert_true(nt_map_resolve(small, nt_v2(2, 2), nt_shape_aabb(R(3), R(3)), &r));
    assert_true(r.push.x == 0 && r.push.y == 0 && r.contact_count == 1);
    nt_map_destroy(small);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_create_errors),
        cmocka_unit_test(test_edges_floor_and_wall),
        cmocka_unit_test(test_edges_slopes_halves_round),
        cmocka_unit_test(test_edges_bulk_matches_incremental),
        cmocka_unit_test(test_resolve_flat_floor_seams),
        cmocka_unit_test(test_resolve_slope_to_floor),
        cmocka_unit_test(test_resolve_joined_22_slope),
        cmocka_unit_test(test_resolve_seam_far_from_origin),
        cmocka_unit_test(test_resolve_concave_corner),
        cmocka_unit_test(test_resolve_free_and_border),
        cmocka_unit_test(test_resolve_vs_union_reference),
        cmocka_unit_test(test_resolve_tiny_buried_vs_reference),
        cmocka_unit_test(test_resolve_large_long_floor),
        cmocka_unit_test(test_resolve_large_slope_joins),
        cmocka_unit_test(test_resolve_large_vs_union_reference),
        cmocka_unit_test(test_resolve_large_far_outside),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
