/* Reliability: a short soak of the rain scene through `ntile soak` (the long one is
 * `make soak`), and the extremes: speeds beyond the limit, the smallest size the
 * no-tunnelling guarantee covers, bodies on tile vertices and edges, a thousand
 * bodies in one cell, a 4096 x 4096 map far from the origin, tile edits under a
 * resting pile, and the documented limits. Units: N's scale (cell 24) unless said. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "ntile/ntile.h"
#include "child.h"

#define R(x) ((nt_real)(x))
static const nt_real DT = R(1.0 / 40);

/* Every body finite, inside the map, and in solid by at most 1e-3 cell. */
static void check_bodies(const nt_world *w, const nt_body_id *ids, int n, const char *where)
{
    const nt_map *m = nt_world_get_map(w);
    double cell = (double)nt_map_get_cell_size(m), W = nt_map_get_width(m) * cell, H = nt_map_get_height(m) * cell;
    for (int i = 0; i < n; i++) {
        if (!nt_body_is_valid(w, ids[i])) continue;
        nt_vec2 p = nt_body_get_position(w, ids[i]), v = nt_body_get_velocity(w, ids[i]);
        if (!isfinite((double)p.x) || !isfinite((double)p.y) || !isfinite((double)v.x) || !isfinite((double)v.y))
            fail_msg("%s: body %d not finite", where, i);
        if (p.x < 0 || p.y < 0 || p.x > W || p.y > H) fail_msg("%s: body %d outside the map (%g, %g)", where, i, (double)p.x, (double)p.y);
        double pen = (double)nt_map_overlap_depth(m, p, nt_body_get_shape(w, ids[i])) / cell;
        if (pen > 1e-3) fail_msg("%s: body %d inside solid by %g cell", where, i, pen);
    }
}

static nt_world *world_of(int w, int h, nt_real cell)
{
    nt_world_def d = nt_default_world_def();
    d.map.width = w;
    d.map.height = h;
    d.map.cell_size = cell;
    nt_world *world = NULL;
    assert_int_equal(nt_world_create(&d, &world), NT_OK);
    return world;
}

static nt_body_id body(nt_world *w, nt_shape s, double x, double y, double vx, double vy)
{
    nt_body_def d = nt_default_body_def();
    d.shape = s;
    d.position = nt_v2(R(x), R(y));
    d.velocity = nt_v2(R(vx), R(vy));
    nt_body_id id;
    assert_int_equal(nt_body_create(w, &d, &id), NT_OK);
    return id;
}

/* ---------------------------------------------------------------- soak */

static void test_soak_short(void **state)
{
    (void)state;
    const char *exe = child_ntile();
    char cmd[4200];
    snprintf(cmd, sizeof cmd, "'%s' soak --steps 10000 --bodies 300 2>&1", exe);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    char out[4096] = "";
    size_t n = fread(out, 1, sizeof out - 1, p);
    out[n] = '\0';
    int st = pclose(p);
    print_message("%s", out);
    assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
    const char *s = strstr(out, "worst penetration ");
    assert_non_null(s);
    double pen = strtod(s + strlen("worst penetration "), NULL);
    assert_true(pen > 0 && pen <= 1e-3); /* resting contacts sit a skin deep: > 0 */
    const char *z = strstr(out, " sleeps");
    assert_non_null(z);
    assert_true(strstr(out, "10000 steps of rain with 300 bodies") != NULL);
}

/* ---------------------------------------------------------------- speed */

/* Far beyond the speed limit: clamped to max_cells_per_step, never through a half
 * tile; and a body of the smallest half-size the guarantee covers
 * (max_cells_per_step / 256 cells) at the limit is stopped too. */
static void test_beyond_the_speed_limit(void **state)
{
    (void)state;
    nt_world_def d = nt_default_world_def();
    double cell = (double)d.map.cell_size, vmax = (double)d.max_cells_per_step * cell / (double)DT;
    double halves[2] = {0.3 * cell, (double)d.max_cells_per_step / 256 * cell};
    double speeds[3] = {vmax, 10 * vmax, 1e6 * vmax};
    for (int k = 0; k < 2; k++)
        for (int s = 0; s < 3; s++)
            for (int shape = 0; shape < 2; shape++) {
                nt_world *w = world_of(40, 10, d.map.cell_size);
                /* A one-cell-thick wall of HALFl (left half solid) at column 20. */
                for (int y = 0; y < 10; y++) nt_world_set_tile(w, 20, y, NT_TILE_HALFl);
                nt_world_set_gravity(w, nt_v2(0, 0));
                nt_real h = R(halves[k]);
                nt_body_id id = body(w, shape ? nt_shape_circle(h) : nt_shape_aabb(h, h), 5.5 * cell, 5.5 * cell,
                                     speeds[s], 0);
                for (int t = 0; t < 40; t++) {
                    nt_vec2 before = nt_body_get_position(w, id);
                    assert_int_equal(nt_world_step(w, DT), NT_OK);
                    nt_vec2 p = nt_body_get_position(w, id), v = nt_body_get_velocity(w, id);
                    /* never more than the limit per step (a skin of slack) */
                    assert_true(fabs((double)p.x - (double)before.x) <= (double)d.max_cells_per_step * cell * 1.0001);
                    assert_true(hypot((double)v.x, (double)v.y) <= vmax * 1.0001);
                    if ((double)p.x > 20 * cell)
                        fail_msg("half %g cell at %g cells/step went through the wall (x = %g)", halves[k] / cell,
                                 speeds[s] * (double)DT / cell, (double)p.x / cell);
                }
                check_bodies(w, &id, 1, "speed");
                nt_world_destroy(w);
            }
}

/* ---------------------------------------------------------------- geometry */

/* Objects centred exactly on every vertex of every tile, and on the middle of each
 * cell side, in a map cell with a floor below: they end free (within 1e-3 cell),
 * finite and inside the map. */
static void test_on_vertices_and_edges(void **state)
{
    (void)state;
    int placed = 0;
    for (int tile = 1; tile < NT_TILE_COUNT; tile++) {
        const nt_tile_info *info = nt_tile_get_info(tile);
        nt_vec2 spots[12];
        int ns = 0;
        for (int v = 0; v < info->vertex_count && ns < 8; v++) spots[ns++] = info->vertices[v];
        spots[ns++] = nt_v2(R(0.5), 0);
        spots[ns++] = nt_v2(0, R(0.5));
        spots[ns++] = nt_v2(1, R(0.5));
        spots[ns++] = nt_v2(R(0.5), 1);
        for (int sp = 0; sp < ns; sp++)
            for (int shape = 0; shape < 2; shape++) {
                nt_world *w = world_of(9, 9, 24);
                nt_world_set_tile(w, 4, 4, tile);
                for (int x = 0; x < 9; x++) nt_world_set_tile(w, x, 8, NT_TILE_FULL);
                nt_real h = R(0.25 * 24);
                nt_body_id id = body(w, shape ? nt_shape_circle(h) : nt_shape_aabb(h, h), (4 + (double)spots[sp].x) * 24,
                                     (4 + (double)spots[sp].y) * 24, 0, 0);
                for (int t = 0; t < 80; t++) assert_int_equal(nt_world_step(w, DT), NT_OK);
                check_bodies(w, &id, 1, info->name);
                nt_world_destroy(w);
                placed++;
            }
    }
    assert_true(placed > 33 * 2 * 6);
}

/* A thousand bodies created at one point of one cell: the step copes (finite, inside
 * the map, out of the tiles), and they spread out. */
static void test_thousand_in_one_cell(void **state)
{
    (void)state;
    nt_world *w = world_of(64, 64, 24);
    for (int x = 0; x < 64; x++) nt_world_set_tile(w, x, 63, NT_TILE_FULL);
    static nt_body_id ids[1000];
    for (int i = 0; i < 1000; i++)
        ids[i] = body(w, (i & 1) ? nt_shape_circle(5) : nt_shape_aabb(5, 5), 32.5 * 24, 60.5 * 24, 0, 0);
    for (int t = 0; t < 400; t++) {
        assert_int_equal(nt_world_step(w, DT), NT_OK);
        if (t % 50 == 49) check_bodies(w, ids, 1000, "thousand");
    }
    /* Spread: the bodies no longer share one point. */
    double sx = 0, sx2 = 0;
    for (int i = 0; i < 1000; i++) {
        double x = (double)nt_body_get_position(w, ids[i]).x;
        sx += x;
        sx2 += x * x;
    }
    double sd = sqrt(sx2 / 1000 - (sx / 1000) * (sx / 1000));
    print_message("thousand in one cell: spread (sd of x) %.1f units after 400 steps\n", sd);
    assert_true(sd > 24);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- far from the origin */

/* The same little scenes (a floor and a 45-degree slope; a box dropped on the floor
 * and a circle thrown onto the slope, each alone) near the origin and near the far
 * corner of a 4096 x 4096 map: the trajectories relative to each scene agree to
 * within what the scalar resolves there. Float keeps 24 bits: at 4,090 cells of 24
 * units a position is good to 2^-7 units (3.3e-4 cell), and resting contacts keep a
 * skin of that unit there (2.5e-4 cell near the origin); the resolution itself is as
 * exact there as near the origin (it works from the corner of the body's cell):
 * measured 0.0024 cell apart after 300 steps, bound 0.01 (0.05 when the resolution's
 * rounding allowances and the skin grew with the coordinate). Double keeps 53 bits:
 * 4e-12 cell, bound 1e-9. Two bodies that collide with each
 * other amplify such differences (a chaotic system): kept out of this comparison. */
static void test_far_corner(void **state)
{
    (void)state;
    const int N = 4096;
    nt_world *w = world_of(N, N, 24);
    /* [near/far][box scene, circle scene]: the cell of each scene's origin */
    const int org[2][2][2] = {{{2, 2}, {20, 2}}, {{N - 32, N - 12}, {N - 14, N - 12}}};
    nt_body_id ids[2][2];
    for (int k = 0; k < 2; k++)
        for (int sc = 0; sc < 2; sc++) {
            int ox = org[k][sc][0], oy = org[k][sc][1];
            for (int x = 0; x < 10; x++) nt_world_set_tile(w, ox + x, oy + 8, NT_TILE_FULL);
            nt_world_set_tile(w, ox + 6, oy + 7, NT_TILE_45DEGnn);
            nt_world_set_tile(w, ox + 7, oy + 7, NT_TILE_FULL);
            ids[k][sc] = sc == 0 ? body(w, nt_shape_aabb(6, 6), (ox + 2.3) * 24, (oy + 2.5) * 24, 30, 0)
                                 : body(w, nt_shape_circle(7), (ox + 3.1) * 24, (oy + 1.5) * 24, 60, 0);
        }
    double worst = 0;
    for (int t = 0; t < 300; t++) {
        assert_int_equal(nt_world_step(w, DT), NT_OK);
        for (int sc = 0; sc < 2; sc++) {
            nt_vec2 p0 = nt_body_get_position(w, ids[0][sc]), p1 = nt_body_get_position(w, ids[1][sc]);
            double sx = (org[1][sc][0] - org[0][sc][0]) * 24.0, sy = (org[1][sc][1] - org[0][sc][1]) * 24.0;
            double dx = ((double)p1.x - sx) - (double)p0.x, dy = ((double)p1.y - sy) - (double)p0.y;
            worst = fmax(worst, hypot(dx, dy) / 24);
        }
    }
    double tol = NT_REAL_IS_DOUBLE ? 1e-9 : 0.01;
    print_message("far corner: trajectories differ by at most %.3g cell over 300 steps (%s; bound %g)\n", worst,
                  NT_REAL_IS_DOUBLE ? "double" : "float", tol);
    assert_true(worst <= tol);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- tile edits */

/* A resting pile on a floor whose tiles are removed and put back again and again
 * (also right through resting bodies): after every step everything is finite, inside
 * the map and out of the tiles. */
static void test_tile_edits_under_a_pile(void **state)
{
    (void)state;
    nt_world *w = world_of(20, 20, 24);
    for (int x = 0; x < 20; x++) nt_world_set_tile(w, x, 19, NT_TILE_FULL);
    for (int x = 0; x < 20; x++) nt_world_set_tile(w, x, 15, NT_TILE_FULL);
    nt_body_id ids[120];
    for (int i = 0; i < 120; i++)
        ids[i] = body(w, (i & 1) ? nt_shape_circle(8) : nt_shape_aabb(8, 8), (2 + i % 16) * 24 + 12, (8 + i / 16 % 6) * 24 + 4,
                      0, 0);
    for (int t = 0; t < 200; t++) assert_int_equal(nt_world_step(w, DT), NT_OK);
    check_bodies(w, ids, 120, "settled");
    unsigned seed = 12345;
    for (int round = 0; round < 60; round++) {
        seed = seed * 1664525u + 1013904223u;
        int x = 2 + (int)(seed >> 16) % 16;
        int row = (seed >> 8) & 1 ? 15 : 14; /* 14: right through the bodies resting on row 15 */
        int tile = (int)(seed >> 4) % NT_TILE_COUNT;
        assert_int_equal(nt_world_set_tile(w, x, row, nt_world_get_tile(w, x, row) == NT_TILE_EMPTY ? tile : NT_TILE_EMPTY),
                         NT_OK);
        for (int t = 0; t < 5; t++) {
            assert_int_equal(nt_world_step(w, DT), NT_OK);
            check_bodies(w, ids, 120, "after an edit");
        }
    }
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- limits */

static void test_documented_limits(void **state)
{
    (void)state;
    nt_world_def d = nt_default_world_def();
    nt_world *w = NULL;
    d.map.width = NT_MAP_MAX_SIDE + 1;
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_OUT_OF_RANGE);
    assert_null(w);
    d = nt_default_world_def();
    d.max_cells_per_step = 17;
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_OUT_OF_RANGE);
    d = nt_default_world_def();
    assert_int_equal(nt_world_create(&d, &w), NT_OK);
    nt_body_def b = nt_default_body_def();
    b.position = nt_v2(R(-24.0 * (NT_WORLD_REACH_CELLS + 1)), 0);
    nt_body_id id;
    assert_int_equal(nt_body_create(w, &b, &id), NT_ERR_OUT_OF_RANGE);
    b.position = nt_v2(100, 100);
    /* Half-sizes up to NT_MAX_HALF_CELLS (4) cells of 24: 96 at most, either side. */
    b.shape = nt_shape_circle(R(96.01));
    assert_int_equal(nt_body_create(w, &b, &id), NT_ERR_SHAPE_TOO_LARGE);
    b.shape = nt_shape_aabb(1, R(96.01));
    assert_int_equal(nt_body_create(w, &b, &id), NT_ERR_SHAPE_TOO_LARGE);
    assert_int_equal(nt_world_get_body_count(w), 0);
    b.shape = nt_shape_aabb(R(24.0 * NT_MAX_HALF_CELLS), 1);
    assert_int_equal(nt_body_create(w, &b, &id), NT_OK);
    assert_int_equal(nt_world_get_body_count(w), 1);
    nt_world_destroy(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_soak_short),
        cmocka_unit_test(test_beyond_the_speed_limit),
        cmocka_unit_test(test_on_vertices_and_edges),
        cmocka_unit_test(test_thousand_in_one_cell),
        cmocka_unit_test(test_far_corner),
        cmocka_unit_test(test_tile_edits_under_a_pile),
        cmocka_unit_test(test_documented_limits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
