/* Far from the origin (issues 20 and 21): the same little scenes near the origin, at
 * 1,000 cells and at the far corner of a 4096 x 4096 map (cell 24), against the
 * independent reference of tests/ref.c (double, cell 1, the scene's own cells):
 *  - nt_map_resolve: the push is the reference's shortest way out of the union for
 *    the position as the map sees it in cells (so exact up to that position's own
 *    rounding, one unit in the last place of the cell coordinate), and the moved
 *    position is out of the tiles up to that and its rounding as a coordinate;
 *  - nt_map_raycast: the hit fraction is the reference's first entry, however far;
 *  - nt_map_cast_shape: the stop is the reference's up to the rounding of the start
 *    in cells, and a character runs down and up slopes without stopping there;
 *  - the world: bodies thrown about at the speed limit never sit deeper in the
 *    tiles than world.h promises (1e-3 cell), near the origin and at the far corner.
 * The reference works on the actual float position (its offset from the scene's
 * cell, exact in double): what is measured is the engine's arithmetic, not the
 * rounding of the input. */
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

enum { SIDE = 4096, PAT = 8 };
static const double CELL = 24;
/* Scene origins (cells): near the origin, 1,000 cells out, the far corner. */
static const int ORG[3] = {8, 1000, SIDE - PAT - 2};
static const char *const ORG_NAME[3] = {"near the origin", "at 1,000 cells", "at the far corner"};

/* Half a unit in the last place of a coordinate of magnitude x, in cells: what
 * storing a position of that size rounds away. */
static double half_ulp_cells(double x)
{
    nt_real v = (nt_real)x;
    double up = (double)nextafterf((float)v, INFINITY);
#if NT_REAL_IS_DOUBLE
    up = nextafter((double)v, INFINITY);
#endif
    return 0.5 * (up - (double)v) / CELL;
}

/* A point stored as nt_real coordinates. Through a volatile: gcc 12 at -O2 was seen
 * to read (double)p.x back as the double it was rounded from. */
static nt_vec2 stored(double x, double y)
{
    volatile nt_real vx = (nt_real)x, vy = (nt_real)y;
    return nt_v2(vx, vy);
}

/* One unit in the last place of a coordinate of x cells, in cells: how finely a
 * position is known in cell units (nt_real coordinates in cells; 6.1e-5 at 1,000
 * cells, 2.4e-4 just below 4,096 in float). */
static double cell_ulp(double x)
{
#if NT_REAL_IS_DOUBLE
    return nextafter(x, INFINITY) - x;
#else
    float v = (float)x;
    return (double)nextafterf(v, INFINITY) - (double)v;
#endif
}

static nt_map *big_map(void)
{
    nt_map_def d = nt_default_map_def();
    d.width = d.height = SIDE;
    d.cell_size = R(CELL);
    nt_map *m = NULL;
    assert_int_equal(nt_map_create(&d, &m), NT_OK);
    return m;
}

/* A random PAT x PAT pattern of tiles: 40 % empty, then FULL or any tile. */
static void random_pattern(ref_rng *g, int *tiles)
{
    for (int i = 0; i < PAT * PAT; i++) {
        double u = ref_rng_uniform(g, 0, 1);
        tiles[i] = u < 0.4 ? 0 : (u < 0.55 ? 1 : 1 + ref_rng_int(g, 33));
    }
}

static void put_pattern(nt_map *m, int o, const int *tiles)
{
    for (int y = 0; y < PAT; y++)
        for (int x = 0; x < PAT; x++) assert_int_equal(nt_map_set_tile(m, o + x, o + y, tiles ? tiles[y * PAT + x] : 0), NT_OK);
}

/* ---------------------------------------------------------------- resolution */

/* Random objects (half-size 0.05 .. 0.45 cell) 1e-3 .. 0.5 cell deep in random
 * patterns, the same local scenes at each origin. Per origin: the worst push error
 * (its length against the reference's, and the overlap the reference finds left at
 * the pushed position, unrounded), and the worst overlap of the moved position once
 * rounded to a coordinate. */
static void test_resolve_far(void **state)
{
    (void)state;
    nt_map *m = big_map();
    double worst_push[3] = {0, 0, 0}, worst_moved[3] = {0, 0, 0}, bound_push[3], bound_moved[3];
    int checked[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++) {
        ref_rng g = ref_rng_seed(20);
        int tiles[PAT * PAT];
        const int o = ORG[k];
        for (int pattern = 0; pattern < 60; pattern++) {
            random_pattern(&g, tiles);
            put_pattern(m, o, tiles);
            for (int trial = 0; trial < 60; trial++) {
                int circle = ref_rng_int(&g, 2);
                double hw = ref_rng_uniform(&g, 0.05, 0.45), hh = circle ? hw : ref_rng_uniform(&g, 0.05, 0.45);
                ref_shape rs = circle ? ref_circle(hw) : ref_aabb(hw, hh);
                nt_shape sh = circle ? nt_shape_circle(R(hw * CELL)) : nt_shape_aabb(R(hw * CELL), R(hh * CELL));
                rs.hw = (double)sh.half.x / CELL;
                rs.hh = (double)sh.half.y / CELL;
                double lx = ref_rng_uniform(&g, 3, 5), ly = ref_rng_uniform(&g, 3, 5);
                nt_vec2 pos = stored((o + lx) * CELL, (o + ly) * CELL);
                lx = (double)pos.x / CELL - o; /* the position as stored, exact in double */
                ly = (double)pos.y / CELL - o;
                double rdx, rdy;
                double rlen = ref_mtv_map(tiles, PAT, PAT, rs, lx, ly, &rdx, &rdy);
                if (rlen < 1e-3 || rlen > 0.5) continue;
                nt_resolution r;
                if (!nt_map_resolve(m, pos, sh, &r)) fail_msg("%s: no push at (%.9g, %.9g)", ORG_NAME[k], lx, ly);
                double px = (double)r.push.x / CELL, py = (double)r.push.y / CELL;
                double len = hypot(px, py);
                double left = ref_mtv_map(tiles, PAT, PAT, rs, lx + px, ly + py, NULL, NULL);
                double e = fmax(fabs(len - rlen), left);
                if (e > worst_push[k]) worst_push[k] = e;
                nt_vec2 q = stored((double)(nt_real)(pos.x + r.push.x), (double)(nt_real)(pos.y + r.push.y));
                double moved = ref_mtv_map(tiles, PAT, PAT, rs, (double)q.x / CELL - o, (double)q.y / CELL - o, NULL, NULL);
                if (moved > worst_moved[k]) worst_moved[k] = moved;
                checked[k]++;
            }
        }
        put_pattern(m, o, NULL);
        /* The push is exact for the position as the map sees it, in cells: to 1e-5
         * cell (1e-9 in double) plus that position's rounding (one unit in the last
         * place of the cell coordinate, each axis); the moved body, plus the rounding
         * of its new world position (half a unit, each axis). */
        double tol = NT_REAL_IS_DOUBLE ? 1e-9 : 1e-5;
        bound_push[k] = sqrt(2) * cell_ulp(o + PAT) + tol;
        bound_moved[k] = bound_push[k] + sqrt(2) * half_ulp_cells((o + PAT) * CELL);
        print_message("resolve %s: %d placements, worst push error %.2g cell (bound %.2g), moved body left %.2g cell "
                      "deep (bound %.2g)\n",
                      ORG_NAME[k], checked[k], worst_push[k], bound_push[k], worst_moved[k], bound_moved[k]);
    }
    for (int k = 0; k < 3; k++) {
        assert_true(checked[k] > 1000);
        assert_true(worst_push[k] <= bound_push[k]);
        assert_true(worst_moved[k] <= bound_moved[k]);
    }
    nt_map_destroy(m);
}

/* ---------------------------------------------------------------- ray casts */

/* First entry of the segment into the pattern's solid (a point object), by scanning
 * in steps of 1e-3 cell and bisecting; -1 when none. */
static double ref_ray(const int *tiles, double x, double y, double dx, double dy)
{
    ref_shape pt = ref_aabb(0, 0);
    double len = hypot(dx, dy);
    int n = (int)(len / 1e-3) + 1;
    double prev = 0;
    for (int i = 1; i <= n; i++) {
        double t = (double)i / n;
        if (ref_object_overlaps_map(tiles, PAT, PAT, pt, x + t * dx, y + t * dy)) {
            double lo = prev, hi = t;
            for (int it = 0; it < 60; it++) {
                double mid = 0.5 * (lo + hi);
                if (ref_object_overlaps_map(tiles, PAT, PAT, pt, x + mid * dx, y + mid * dy)) hi = mid;
                else lo = mid;
            }
            return hi;
        }
        prev = t;
    }
    return -1;
}

/* Rays from free points of random patterns, up to 3 cells long: where the reference
 * enters the solid for good (still inside 2e-3 cell further on), the engine's hit
 * fraction, as a distance along the ray, is the reference's; and the reported point,
 * a coordinate, is that place up to its own rounding. */
static void test_raycast_far(void **state)
{
    (void)state;
    nt_map *m = big_map();
    double worst_t[3] = {0, 0, 0}, worst_pt[3] = {0, 0, 0};
    int checked[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++) {
        ref_rng g = ref_rng_seed(21);
        int tiles[PAT * PAT];
        const int o = ORG[k];
        for (int pattern = 0; pattern < 40; pattern++) {
            random_pattern(&g, tiles);
            put_pattern(m, o, tiles);
            for (int trial = 0; trial < 30; trial++) {
                double lx = ref_rng_uniform(&g, 2.5, 5.5), ly = ref_rng_uniform(&g, 2.5, 5.5);
                double a = ref_rng_uniform(&g, 0, 6.283185307179586), l = ref_rng_uniform(&g, 0.2, 2.4);
                nt_vec2 p0 = stored((o + lx) * CELL, (o + ly) * CELL);
                nt_vec2 p1 = stored((double)p0.x + cos(a) * l * CELL, (double)p0.y + sin(a) * l * CELL);
                lx = (double)p0.x / CELL - o;
                ly = (double)p0.y / CELL - o;
                double dx = ((double)p1.x - (double)p0.x) / CELL, dy = ((double)p1.y - (double)p0.y) / CELL;
                if (ref_object_overlaps_map(tiles, PAT, PAT, ref_aabb(0, 0), lx, ly)) continue;
                double t = ref_ray(tiles, lx, ly, dx, dy);
                double dl = hypot(dx, dy);
                if (t < 0 || t + 2e-3 / dl > 1) continue;
                if (!ref_object_overlaps_map(tiles, PAT, PAT, ref_aabb(0, 0), lx + (t + 2e-3 / dl) * dx,
                                             ly + (t + 2e-3 / dl) * dy))
                    continue; /* a graze: hit or miss is a matter of rounding */
                nt_ray_hit hit;
                if (!nt_map_raycast(m, p0, p1, &hit))
                    fail_msg("%s: ray from (%.9g, %.9g) by (%.9g, %.9g) missed (reference t %.9g)", ORG_NAME[k], lx, ly,
                             dx, dy, t);
                double et = fabs((double)hit.fraction - t) * dl;
                if (et > worst_t[k]) worst_t[k] = et;
                double hx = (double)hit.point.x / CELL - o, hy = (double)hit.point.y / CELL - o;
                double ep = hypot(hx - (lx + t * dx), hy - (ly + t * dy));
                if (ep > worst_pt[k]) worst_pt[k] = ep;
                checked[k]++;
            }
        }
        put_pattern(m, o, NULL);
        print_message("raycast %s: %d rays, worst hit error %.2g cell along the ray, hit point %.2g cell off "
                      "(its rounding: %.2g)\n",
                      ORG_NAME[k], checked[k], worst_t[k], worst_pt[k], sqrt(2) * half_ulp_cells((o + PAT) * CELL));
    }
    double tol = NT_REAL_IS_DOUBLE ? 1e-9 : 2e-5;
    for (int k = 0; k < 3; k++) {
        assert_true(checked[k] > 300);
        assert_true(worst_t[k] <= tol);
        assert_true(worst_pt[k] <= sqrt(2) * half_ulp_cells((ORG[k] + PAT) * CELL) + tol);
    }
    nt_map_destroy(m);
}

/* ---------------------------------------------------------------- shape casts */

/* Boxes and circles (half-size 0.05 .. 0.45 cell) starting 1e-4 cell clear of the
 * tiles, swept up to 2.5 cells: where the reference (brute force, tests/ref.c) is not
 * a graze (the same with the shape shrunk by 1e-5 cell), the engine stops where it
 * does, to 1e-5 cell of travel plus four units in the last place of the start's
 * coordinates in cells (1e-8 in double). With a rounding allowance of 16 units of the
 * start's coordinates (7.8e-3 cell at the far corner) the cast missed shallow hits at
 * the end of its way there (an error of the whole way). */
static void test_cast_far(void **state)
{
    (void)state;
    nt_map *m = big_map();
    double worst[3] = {0, 0, 0};
    int checked[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++) {
        ref_rng g = ref_rng_seed(22);
        int tiles[PAT * PAT];
        const int o = ORG[k];
        for (int pattern = 0; pattern < 40; pattern++) {
            random_pattern(&g, tiles);
            put_pattern(m, o, tiles);
            for (int trial = 0; trial < 30; trial++) {
                int circle = ref_rng_int(&g, 2);
                double hw = ref_rng_uniform(&g, 0.05, 0.45), hh = circle ? hw : ref_rng_uniform(&g, 0.05, 0.45);
                nt_shape sh = circle ? nt_shape_circle(R(hw * CELL)) : nt_shape_aabb(R(hw * CELL), R(hh * CELL));
                ref_shape rs = circle ? ref_circle((double)sh.half.x / CELL)
                                      : ref_aabb((double)sh.half.x / CELL, (double)sh.half.y / CELL);
                double lx = ref_rng_uniform(&g, 3, 5), ly = ref_rng_uniform(&g, 3, 5);
                double a = ref_rng_uniform(&g, 0, 6.283185307179586), l = ref_rng_uniform(&g, 0.2, 2.5);
                nt_vec2 pos = stored((o + lx) * CELL, (o + ly) * CELL);
                nt_vec2 tr = stored(cos(a) * l * CELL, sin(a) * l * CELL);
                lx = (double)pos.x / CELL - o;
                ly = (double)pos.y / CELL - o;
                double dx = (double)tr.x / CELL, dy = (double)tr.y / CELL, len = hypot(dx, dy);
                if (ref_object_overlaps_map_eps(tiles, PAT, PAT, rs, lx, ly, -1e-4)) continue;
                double t0, t1;
                bool r0 = ref_cast_map(tiles, PAT, PAT, rs, lx, ly, dx, dy, 1e-9, 1e-3, &t0);
                bool r1 = ref_cast_map(tiles, PAT, PAT, rs, lx, ly, dx, dy, 1e-5, 1e-3, &t1);
                if (r0 != r1 || (r0 && (t1 - t0) * len > 1e-4)) continue;
                nt_shape_cast_hit hit;
                bool e = nt_map_cast_shape(m, pos, sh, tr, &hit);
                double err = e != r0 ? 1 : (e ? fabs((double)hit.fraction - t0) * len : 0);
                if (err > worst[k]) worst[k] = err;
                checked[k]++;
            }
        }
        put_pattern(m, o, NULL);
        print_message("cast %s: %d casts, worst stop error %.2g cell of travel\n", ORG_NAME[k], checked[k], worst[k]);
    }
    for (int k = 0; k < 3; k++) {
        assert_true(checked[k] > 300);
        assert_true(worst[k] <= (NT_REAL_IS_DOUBLE ? 1e-8 : 1e-5 + 4 * cell_ulp(ORG[k] + PAT)));
    }
    nt_map_destroy(m);
}

/* ---------------------------------------------------------------- the character */

/* The slope course of tests/test_character.c (a plateau, a slope of 45 or 26.6
 * degrees going down three cells, a floor), near the origin and at the far corner of
 * one 4096 x 4096 world (cell 24, g 900, dt 1/60): a 1 x 2-cell box and a circle run
 * down it at 60 to 600 units/s with the floor snap, never airborne, never stopped, and
 * back up without stopping. At the far corner a cast's rounding allowance of 16 units
 * in the last place of the coordinates (7.8e-3 cell) stopped 6 of the 20 runs. */
enum { CW = 80, CF = 16 };

static void course_tile(nt_world *w, int o[2], int x, int y, int t) { nt_world_set_tile(w, o[0] + x, o[1] + y, t); }

static int build_course(nt_world *w, int o[2], int kind)
{
    const int X0 = 20, drop = 3;
    for (int x = 0; x < CW; x++) course_tile(w, o, x, CF, NT_TILE_FULL);
    int x = X0;
    for (int px = 0; px < X0; px++)
        for (int y = CF - drop; y < CF; y++) course_tile(w, o, px, y, NT_TILE_FULL);
    for (int k = 0; k < drop; k++) {
        int y = CF - drop + k;
        if (kind == 45) {
            course_tile(w, o, x, y, NT_TILE_45DEGpn);
            for (int yy = y + 1; yy < CF; yy++) course_tile(w, o, x, yy, NT_TILE_FULL);
            x++;
        } else {
            course_tile(w, o, x, y, NT_TILE_22DEGpnB);
            course_tile(w, o, x + 1, y, NT_TILE_22DEGpnS);
            for (int yy = y + 1; yy < CF; yy++) course_tile(w, o, x, yy, NT_TILE_FULL), course_tile(w, o, x + 1, yy, NT_TILE_FULL);
            x += 2;
        }
    }
    return x;
}

static void character_tick(nt_world *w, nt_body_id id, nt_vec2 *v, nt_character_result *r, double vx)
{
    const nt_real dt = R(1.0 / 60);
    v->x = R(vx);
    v->y += R(900.0 / 60);
    assert_int_equal(nt_character_move(w, id, *v, dt, r), NT_OK);
    *v = r->velocity;
    assert_int_equal(nt_world_step(w, dt), NT_OK);
}

static void test_character_far(void **state)
{
    (void)state;
    nt_world_def d = nt_default_world_def();
    d.map.width = d.map.height = SIDE;
    d.map.cell_size = R(CELL);
    d.gravity = nt_v2(0, 900);
    d.enable_sleep = false;
    nt_world *w = NULL;
    assert_int_equal(nt_world_create(&d, &w), NT_OK);
    /* [near, far][45, 22]: the corner of each course */
    int org[2][2][2] = {{{2, 2}, {2, 24}}, {{SIDE - CW - 4, SIDE - 44}, {SIDE - CW - 4, SIDE - 22}}};
    int foot[2][2];
    const int kinds[2] = {45, 22};
    for (int k = 0; k < 2; k++)
        for (int ki = 0; ki < 2; ki++) foot[k][ki] = build_course(w, org[k][ki], kinds[ki]);
    const double speeds[] = {60, 150, 250, 400, 600};
    int bad[2] = {0, 0};
    for (int k = 0; k < 2; k++)
        for (int shape = 0; shape < 2; shape++)
            for (int ki = 0; ki < 2; ki++)
                for (int si = 0; si < 5; si++) {
                    const int *o = org[k][ki];
                    nt_shape sh = shape ? nt_shape_circle(10) : nt_shape_aabb(12, 24);
                    nt_body_def bd = nt_default_body_def();
                    bd.shape = sh;
                    bd.position = nt_v2(R((o[0] + 10) * CELL), R((o[1] + CF - 3) * CELL - (double)sh.half.y - 1));
                    nt_body_id id;
                    assert_int_equal(nt_body_create(w, &bd, &id), NT_OK);
                    nt_character_def cd = nt_default_character_def();
                    assert_int_equal(nt_character_create(w, id, &cd), NT_OK);
                    nt_vec2 v = nt_v2(0, 0);
                    nt_character_result r;
                    memset(&r, 0, sizeof r);
                    for (int t = 0; t < 30; t++) character_tick(w, id, &v, &r, 0); /* land on the plateau */
                    int airborne = !r.on_floor, stops = 0, down = 0, up = 0;
                    const double end = (o[0] + foot[k][ki] + 6) * CELL, top = (o[0] + 10) * CELL, s = speeds[si];
                    for (; down < 2000; down++) {
                        double x = (double)nt_body_get_position(w, id).x;
                        if (x >= end) break;
                        character_tick(w, id, &v, &r, s);
                        if (!r.on_floor) airborne++;
                        if ((double)nt_body_get_position(w, id).x - x < 0.5 * s / 60) stops++;
                    }
                    for (; up < 2000; up++) {
                        double x = (double)nt_body_get_position(w, id).x;
                        if (x <= top) break;
                        character_tick(w, id, &v, &r, -s);
                        if (x - (double)nt_body_get_position(w, id).x < 0.3 * s / 60) stops++;
                    }
                    if (airborne || stops || down >= 2000 || up >= 2000) {
                        bad[k]++;
                        print_message("%s: %s on the %d-degree course at %g units/s: %d airborne ticks, %d stops\n",
                                      k ? "far corner" : "near the origin", shape ? "circle" : "box", kinds[ki], s,
                                      airborne, stops);
                    }
                    nt_body_destroy(w, id);
                }
    print_message("character on slopes: %d of 20 runs stopped near the origin, %d at the far corner\n", bad[0], bad[1]);
    assert_int_equal(bad[0], 0);
    assert_int_equal(bad[1], 0);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- the world */

/* Two arenas of 24 x 24 cells (walls, a floor, slopes, round tiles and halves strewn
 * inside), one near the origin and one in the far corner, each with the same 150
 * boxes and circles thrown at the speed limit: after every step no body is deeper
 * than 1e-3 cell in the tiles (world.h's promise) at either place. */
static void test_world_far_corner(void **state)
{
    (void)state;
    enum { A = 24, BODIES = 150, STEPS = 1200 };
    nt_world_def d = nt_default_world_def();
    d.map.width = d.map.height = SIDE;
    d.map.cell_size = R(CELL);
    d.body_capacity = 2 * BODIES;
    nt_world *w = NULL;
    assert_int_equal(nt_world_create(&d, &w), NT_OK);
    const int org[2] = {2, SIDE - A - 2};
    nt_body_id ids[2][BODIES];
    nt_real vmax = R(4 * CELL * 40);
    for (int k = 0; k < 2; k++) {
        ref_rng g = ref_rng_seed(2121);
        int o = org[k];
        for (int i = 0; i < A; i++) {
            nt_world_set_tile(w, o + i, o, NT_TILE_FULL);
            nt_world_set_tile(w, o + i, o + A - 1, NT_TILE_FULL);
            nt_world_set_tile(w, o, o + i, NT_TILE_FULL);
            nt_world_set_tile(w, o + A - 1, o + i, NT_TILE_FULL);
        }
        for (int n = 0; n < 70; n++)
            nt_world_set_tile(w, o + 2 + ref_rng_int(&g, A - 4), o + 4 + ref_rng_int(&g, A - 6), 1 + ref_rng_int(&g, 33));
        for (int i = 0; i < BODIES; i++) {
            nt_body_def b = nt_default_body_def();
            double hw = ref_rng_uniform(&g, 0.15, 0.45), hh = ref_rng_uniform(&g, 0.15, 0.45);
            b.shape = ref_rng_int(&g, 2) ? nt_shape_circle(R(hw * CELL)) : nt_shape_aabb(R(hw * CELL), R(hh * CELL));
            b.position = nt_v2(R((o + 1.5 + (i % 20) * 1.05) * CELL), R((o + 1.5 + (i / 20) * 0.4) * CELL));
            double a = ref_rng_uniform(&g, 0, 6.283185307179586);
            b.velocity = nt_v2(R(cos(a) * (double)vmax), R(sin(a) * (double)vmax));
            b.material.bounce = R(0.5);
            assert_int_equal(nt_body_create(w, &b, &ids[k][i]), NT_OK);
        }
    }
    const nt_map *m = nt_world_get_map(w);
    double worst[2] = {0, 0};
    long over[2] = {0, 0};
    for (int s = 0; s < STEPS; s++) {
        assert_int_equal(nt_world_step(w, R(1.0 / 40)), NT_OK);
        for (int k = 0; k < 2; k++)
            for (int i = 0; i < BODIES; i++) {
                /* Kicked back up to the speed limit now and then, so that they keep hitting hard. */
                if (s % 100 == 99 && i % 3 == 0) {
                    double a = (double)(i * 7 + s) * 0.37;
                    nt_body_set_velocity(w, ids[k][i], nt_v2(R(cos(a) * (double)vmax), R(sin(a) * (double)vmax)));
                }
                nt_vec2 p = nt_body_get_position(w, ids[k][i]);
                double pen = (double)nt_map_overlap_depth(m, p, nt_body_get_shape(w, ids[k][i])) / CELL;
                if (pen > worst[k]) worst[k] = pen;
                if (pen > 1e-3) over[k]++;
            }
    }
    for (int k = 0; k < 2; k++)
        print_message("world %s: deepest body in the tiles %.3g cell, %ld body-steps over 1e-3 cell (%d steps of %d bodies)\n",
                      k ? "at the far corner" : "near the origin", worst[k], over[k], STEPS, BODIES);
    assert_true(worst[0] <= 1e-3);
    assert_true(worst[1] <= 1e-3);
    nt_world_destroy(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_resolve_far),
        cmocka_unit_test(test_raycast_far),
        cmocka_unit_test(test_cast_far),
        cmocka_unit_test(test_character_far),
        cmocka_unit_test(test_world_far_corner),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
