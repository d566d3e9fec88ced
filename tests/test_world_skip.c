/* The step skips the exact tile resolution where its answer is already known, and
 * the answers stay right: bodies in open air, bodies resting where they rested, and
 * bodies gliding along a flat surface they touched need no resolution
 * (nt_world_counters.tile_resolutions), while their positions follow the analytic
 * path (the floor at its depth within the skin, x advancing by v dt, the slope's
 * line) and a wall or a curve at the end of a glide still stops or steers them. The
 * map-level glide test (core_internal.h) is checked against the exact resolution,
 * nt_map_resolve, at random places on every tile. Units: cell size 1, seconds;
 * y points down. */
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
#include "../src/simulation.h"

static const double DT = 1.0 / 60;
/* The resting skin (response.c): 2.5e-4 cell at cell size 1 near the origin; a body
 * counts as held within an eighth of it either way. */
static const double SKIN = 2.5e-4;

static nt_world *make_world(int w, int h, double gravity)
{
    nt_world_def d = nt_default_world_def();
    d.map.width = w;
    d.map.height = h;
    d.map.cell_size = 1;
    d.gravity = nt_v2(0, (nt_real)gravity);
    d.tile_material.friction = 0;
    d.tile_material.bounce = 0;
    d.restitution_threshold = 0;
    d.enable_sleep = false;
    nt_world *world = NULL;
    assert_int_equal(nt_world_create(&d, &world), NT_OK);
    return world;
}

static nt_body_id add_body(nt_world *w, nt_shape s, double x, double y, double vx, double vy)
{
    nt_body_def d = nt_default_body_def();
    d.shape = s;
    d.position = nt_v2((nt_real)x, (nt_real)y);
    d.velocity = nt_v2((nt_real)vx, (nt_real)vy);
    d.material.friction = 0;
    d.material.bounce = 0;
    nt_body_id id;
    assert_int_equal(nt_body_create(w, &d, &id), NT_OK);
    return id;
}

static void fill(nt_world *w, int x0, int y0, int x1, int y1, int tile)
{
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) assert_int_equal(nt_world_set_tile(w, x, y, tile), NT_OK);
}

static int resolutions(const nt_world *w) { return nt_world_get_counters(w).tile_resolutions; }

/* Boxes and circles of many sizes set on a FULL floor, and circles in V notches
 * (two slopes: no glide, the full resolution), at N's scale (cell 24 units, where a
 * position's rounding is a sizeable part of the skin): after they settle, no step
 * resolves them again and none moves by a bit; each sits in its surfaces by the
 * skin. */
static void test_resting_bodies_need_no_resolution(void **state)
{
    (void)state;
    nt_world_def d = nt_default_world_def();
    d.map.width = 130;
    d.map.height = 12;
    d.enable_sleep = false;
    nt_world *w = NULL;
    assert_int_equal(nt_world_create(&d, &w), NT_OK);
    double cell = (double)d.map.cell_size, skin = SKIN * cell, c = sqrt(0.5);
    enum { NF = 120, NV = 60, N = NF + NV };
    nt_body_id id[N];
    double half[N];
    fill(w, 0, 5, 129, 5, NT_TILE_FULL);
    /* The notches: 45DEGpn then 45DEGnn on row 9, FULL below; notch j's bottom is the
     * point (2j + 1, 10) (cells), its sides the lines y - 10 = +-(x - (2j + 1)). */
    for (int x = 0; x < 130; x += 2) {
        assert_int_equal(nt_world_set_tile(w, x, 9, NT_TILE_45DEGpn), NT_OK);
        assert_int_equal(nt_world_set_tile(w, x + 1, 9, NT_TILE_45DEGnn), NT_OK);
    }
    fill(w, 0, 10, 129, 11, NT_TILE_FULL);
    for (int i = 0; i < N; i++) {
        half[i] = cell * (0.2 + 0.25 * (double)((i * 37) % 101) / 100);
        int circle = i >= NF || (i & 1);
        nt_shape s = circle ? nt_shape_circle((nt_real)half[i]) : nt_shape_aabb((nt_real)half[i], (nt_real)half[i]);
        nt_body_def bd = nt_default_body_def();
        bd.shape = s;
        if (i < NF) {
            bd.position = nt_v2((nt_real)(cell * (4 + i) + 0.37 * i), (nt_real)(cell * 5 - half[i]));
        } else {
            int j = (i - NF) + 2;
            bd.position = nt_v2((nt_real)(cell * (2 * j + 1)), (nt_real)(cell * 10 - half[i] / c - 0.5));
        }
        assert_int_equal(nt_body_create(w, &bd, &id[i]), NT_OK);
    }
    for (int k = 0; k < 80; k++) assert_int_equal(nt_world_step(w, (nt_real)(1.0 / 40)), NT_OK);
    nt_vec2 before[N];
    for (int i = 0; i < N; i++) before[i] = nt_body_get_position(w, id[i]);
    for (int k = 0; k < 50; k++) {
        assert_int_equal(nt_world_step(w, (nt_real)(1.0 / 40)), NT_OK);
        assert_int_equal(resolutions(w), 0);
        for (int i = 0; i < N; i++) {
            nt_vec2 p = nt_body_get_position(w, id[i]);
            assert_true(p.x == before[i].x && p.y == before[i].y);
            if (i < NF) {
                double depth = (double)p.y + half[i] - cell * 5;
                assert_true(depth >= skin * 0.875 - 1e-5 && depth <= skin * 1.125 + 1e-5);
            } else {
                /* Each side's line holds the circle r - skin from its centre. */
                int j = (i - NF) + 2;
                double bx = cell * (2 * j + 1), by = cell * 10;
                double dl = (by - (double)p.y - (bx - (double)p.x)) * c; /* from y - by = -(x - bx) */
                double dr = (by - (double)p.y - ((double)p.x - bx)) * c; /* from y - by = x - bx */
                assert_true(fabs(dl - (half[i] - skin)) <= skin * 0.125 + 1e-5);
                assert_true(fabs(dr - (half[i] - skin)) <= skin * 0.125 + 1e-5);
            }
        }
    }
    nt_world_destroy(w);
}

/* Bodies drifting through an empty map: no resolution, and x_n = x_0 + n (v dt) as
 * float adds it. */
static void test_open_air_needs_no_resolution(void **state)
{
    (void)state;
    nt_world *w = make_world(64, 64, 0);
    enum { N = 50 };
    nt_body_id id[N];
    nt_real x[N], y[N], vx[N], vy[N];
    for (int i = 0; i < N; i++) {
        vx[i] = (nt_real)(0.5 + 0.1 * (i % 7) - 0.3);
        vy[i] = (nt_real)(0.2 - 0.05 * (i % 5));
        x[i] = (nt_real)(8 + i % 10 * 4 + 0.25);
        y[i] = (nt_real)(8 + i / 10 * 8 + 0.5);
        nt_shape s = (i & 1) ? nt_shape_circle((nt_real)0.3) : nt_shape_aabb((nt_real)0.4, (nt_real)0.25);
        id[i] = add_body(w, s, (double)x[i], (double)y[i], (double)vx[i], (double)vy[i]);
    }
    for (int k = 0; k < 120; k++) {
        assert_int_equal(nt_world_step(w, (nt_real)DT), NT_OK);
        assert_int_equal(resolutions(w), 0);
        for (int i = 0; i < N; i++) {
            x[i] += vx[i] * (nt_real)DT;
            y[i] += vy[i] * (nt_real)DT;
            nt_vec2 p = nt_body_get_position(w, id[i]);
            assert_true(p.x == x[i] && p.y == y[i]);
        }
    }
    nt_world_destroy(w);
}

/* A box and a circle slide without friction along a FULL floor of many tiles (seams
 * every cell) into a FULL wall: along the floor no step resolves them, y stays at the
 * floor's depth, x advances by v dt; the wall still stops them at its face. */
static void test_glide_along_floor_into_wall(void **state)
{
    (void)state;
    for (int shape = 0; shape < 2; shape++) {
        nt_world *w = make_world(40, 6, 10);
        fill(w, 0, 5, 39, 5, NT_TILE_FULL);
        fill(w, 30, 0, 30, 4, NT_TILE_FULL);
        nt_shape s = shape ? nt_shape_circle((nt_real)0.3) : nt_shape_aabb((nt_real)0.4, (nt_real)0.3);
        double hx = (double)s.half.x, hy = (double)s.half.y;
        nt_body_id id = add_body(w, s, 2, 5 - hy, 6, 0);
        for (int k = 0; k < 5; k++) assert_int_equal(nt_world_step(w, (nt_real)DT), NT_OK);
        int glided = 0;
        double max_pen = 0;
        for (int k = 0; k < 400; k++) {
            nt_vec2 p0 = nt_body_get_position(w, id), v0 = nt_body_get_velocity(w, id);
            assert_int_equal(nt_world_step(w, (nt_real)DT), NT_OK);
            nt_vec2 p = nt_body_get_position(w, id);
            double depth = (double)p.y + hy - 5;
            assert_true(depth >= SKIN * 0.875 - 1e-6 && depth <= SKIN * 1.125 + 1e-6);
            max_pen = fmax(max_pen, (double)p.x + hx - 30);
            if ((double)p0.x + hx + (double)v0.x * DT < 30 - 0.01) {
                /* Far from the wall: a glide, exactly v dt along. */
                assert_int_equal(resolutions(w), 0);
                assert_true(p.x == p0.x + v0.x * (nt_real)DT);
                assert_true(v0.x > 5.99);
                glided++;
            }
        }
        assert_true(glided > 100);
        /* Stopped at the wall, in it by no more than the skin (and rounding). */
        nt_vec2 p = nt_body_get_position(w, id);
        assert_true(fabs((double)p.x + hx - 30 - SKIN) < 2e-4);
        assert_true(max_pen < SKIN * 1.125 + 1e-5);
        assert_true(fabs((double)nt_body_get_velocity(w, id).x) < 1e-6);
        nt_world_destroy(w);
    }
}

/* A circle glides down a run of 45-degree tiles (the line y = x + 2, solid below it)
 * onto a FULL floor at row 14. On the slope its centre stays r - skin from the line,
 * and the joint with the floor (another normal: no glide) never lets it sink. */
static void test_glide_down_slope_onto_floor(void **state)
{
    (void)state;
    int W = 24, H = 20, floor_row = 14;
    nt_world *w = make_world(W, H, 10);
    for (int x = 0; x < W; x++) {
        int y0 = 2 + x;
        if (y0 < floor_row) assert_int_equal(nt_world_set_tile(w, x, y0, NT_TILE_45DEGpn), NT_OK);
        for (int y = y0 + 1; y < H; y++) assert_int_equal(nt_world_set_tile(w, x, y, NT_TILE_FULL), NT_OK);
    }
    fill(w, 0, floor_row, W - 1, H - 1, NT_TILE_FULL);
    double r = 0.3, c = sqrt(0.5);
    /* Just above the slope near its top. */
    double sx = 1.5, sy = sx + 2 - r / c - 0.02;
    nt_body_id id = add_body(w, nt_shape_circle((nt_real)r), sx, sy, 0, 0);
    int glided = 0, on_slope = 0;
    for (int k = 0; k < 300; k++) {
        assert_int_equal(nt_world_step(w, (nt_real)DT), NT_OK);
        nt_vec2 p = nt_body_get_position(w, id);
        double dist = ((double)p.x - (double)p.y + 2) * c; /* from the slope's line, outside positive */
        nt_body_tile_contacts tc;
        nt_body_get_tile_contacts(w, id, &tc);
        int slope_contact = tc.count == 1 && fabs((double)tc.contacts[0].normal.x - c) < 1e-3 &&
                            fabs((double)tc.contacts[0].normal.y + c) < 1e-3;
        if (slope_contact && (double)p.y + r < floor_row - 0.5) {
            on_slope++;
            assert_true(fabs(dist - (r - SKIN)) <= SKIN * 0.125 + 2e-6);
            if (resolutions(w) == 0) glided++;
        }
        /* Never into the floor by more than the skin (and rounding). */
        assert_true((double)p.y + r - floor_row <= SKIN * 1.125 + 1e-5);
    }
    assert_true(on_slope > 20);
    assert_true(glided > on_slope / 2);
    /* On the floor at the end, at its depth. */
    nt_vec2 p = nt_body_get_position(w, id);
    assert_true(fabs((double)p.y + r - floor_row - SKIN) <= SKIN * 0.125 + 1e-5);
    nt_world_destroy(w);
}

/* The map-level glide test against the exact resolution: at random places of boxes
 * and circles in a row of each tile over FULL tiles, whenever
 * the glide test answers, nt_map_resolve frees the object along that normal by a
 * depth within the band (the glide test's answer is the resolution's). */
static void test_glide_agrees_with_resolution(void **state)
{
    (void)state;
    nt_map_def md = nt_default_map_def();
    md.width = 6;
    md.height = 6;
    md.cell_size = 1;
    uint64_t rng = 0x676c696465ull;
    int answered = 0;
    for (int t = 0; t < NT_TILE_COUNT; t++) {
        if (t == NT_TILE_EMPTY) continue;
        nt_map *map;
        assert_int_equal(nt_map_create(&md, &map), NT_OK);
        /* The tile in a row of its own kind, FULL below. */
        for (int x = 0; x < 6; x++) {
            assert_int_equal(nt_map_set_tile(map, x, 3, t), NT_OK);
            assert_int_equal(nt_map_set_tile(map, x, 4, NT_TILE_FULL), NT_OK);
        }
        for (int k = 0; k < 4000; k++) {
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            double u1 = (double)(rng >> 40) / (double)(1 << 24);
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            double u2 = (double)(rng >> 40) / (double)(1 << 24);
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            double u3 = (double)(rng >> 40) / (double)(1 << 24);
            double half = 0.15 + 0.3 * u3;
            nt_shape s = (k & 1) ? nt_shape_circle((nt_real)half) : nt_shape_aabb((nt_real)half, (nt_real)(half * 0.8));
            nt_vec2 pos = nt_v2((nt_real)(1.5 + 3 * u1), (nt_real)(2 + 2 * u2));
            /* Find the exact resolution first; take its normal as the remembered one. */
            nt_resolution res;
            if (!nt_map_resolve(map, pos, s, &res) || res.contact_count != 1) continue;
            nt_vec2 n = res.contacts[0].normal;
            /* Move the object out so that it sits at a depth about the skin. */
            double want = SKIN * (0.8 + 0.4 * u3);
            double out = (double)res.contacts[0].depth - want;
            nt_vec2 q = nt_v2((nt_real)((double)pos.x + (double)n.x * out), (nt_real)((double)pos.y + (double)n.y * out));
            nt_tile_contact c;
            nt_real lo = (nt_real)(SKIN * 0.875), hi = (nt_real)(SKIN * 1.125);
            if (!nt__map_glides(map, q, &s, n, lo, hi, &c)) continue;
            /* Never along a curve: its normal turns as the object moves. */
            assert_int_equal(nt__tiles[nt_map_get_tile(map, c.cell_x, c.cell_y)].cls, NT_CLASS_POLYGON);
            answered++;
            nt_resolution exact;
            assert_true(nt_map_resolve(map, q, s, &exact));
            double len = sqrt((double)exact.push.x * exact.push.x + (double)exact.push.y * exact.push.y);
            assert_true(len >= (double)lo - 1e-6 && len <= (double)hi + 1e-6);
            assert_true((double)exact.push.x * n.x + (double)exact.push.y * n.y > 0.999 * len);
            assert_true(fabs((double)c.depth - len) < 1e-6);
        }
        nt_map_destroy(map);
    }
    assert_true(answered > 1000);
}

/* A body set back where it rests loses its remembered contacts: the next step finds
 * them again (it is not answered from memory with none). Weightless, so that nothing
 * but the resolution can give them back. */
static void test_set_position_forgets_rest(void **state)
{
    (void)state;
    nt_world *w = make_world(8, 8, 20);
    fill(w, 0, 6, 7, 6, NT_TILE_FULL);
    nt_body_def d = nt_default_body_def();
    d.shape = nt_shape_aabb((nt_real)0.3, (nt_real)0.3);
    d.position = nt_v2((nt_real)3.5, (nt_real)5.5);
    d.velocity = nt_v2(0, 1);
    d.gravity_scale = 0;
    d.material.bounce = 0;
    nt_body_id id;
    assert_int_equal(nt_body_create(w, &d, &id), NT_OK);
    for (int k = 0; k < 30; k++) assert_int_equal(nt_world_step(w, (nt_real)DT), NT_OK);
    assert_int_equal(nt_body_set_velocity(w, id, nt_v2(0, 0)), NT_OK);
    for (int k = 0; k < 3; k++) assert_int_equal(nt_world_step(w, (nt_real)DT), NT_OK);
    nt_body_tile_contacts tc;
    assert_int_equal(nt_body_get_tile_contacts(w, id, &tc), NT_OK);
    assert_int_equal(tc.count, 1);
    assert_int_equal(nt_body_set_position(w, id, nt_body_get_position(w, id)), NT_OK);
    assert_int_equal(nt_world_step(w, (nt_real)DT), NT_OK);
    assert_int_equal(resolutions(w), 1);
    for (int k = 0; k < 20; k++) assert_int_equal(nt_world_step(w, (nt_real)DT), NT_OK);
    assert_int_equal(nt_body_get_tile_contacts(w, id, &tc), NT_OK);
    assert_int_equal(tc.count, 1);
    assert_true(tc.on_floor);
    nt_world_destroy(w);
}

static int held(const nt_world *w) { return nt_world_get_counters(w).bodies_held; }

/* Three bodies dropped onto a FULL floor, no body contacts, no friction.
 * Built twice: in `a` the step answers their gravity and surfaces from the step before
 * (bodies_held) once they have settled; in `b` every body's velocity is set to itself
 * before each step, which forgets that answer, so each step computes it. Both must
 * agree to the bit. Then each change that alters the answer is seen at once. */
static nt_world *held_world(nt_body_id id[3])
{
    nt_world *w = make_world(16, 10, 20);
    fill(w, 0, 8, 15, 8, NT_TILE_FULL);
    id[0] = add_body(w, nt_shape_aabb((nt_real)0.3, (nt_real)0.3), 2.5, 7.6, 0, 0);
    id[1] = add_body(w, nt_shape_circle((nt_real)0.25), 5.5, 7.6, 0, 0);
    id[2] = add_body(w, nt_shape_aabb((nt_real)0.2, (nt_real)0.2), 9.5, 7.6, 0, 0);
    return w;
}

static void assert_same_bodies(const nt_world *a, const nt_world *b, const nt_body_id *ia, const nt_body_id *ib, int n)
{
    for (int i = 0; i < n; i++) {
        nt_vec2 pa = nt_body_get_position(a, ia[i]), pb = nt_body_get_position(b, ib[i]);
        nt_vec2 va = nt_body_get_velocity(a, ia[i]), vb = nt_body_get_velocity(b, ib[i]);
        assert_memory_equal(&pa, &pb, sizeof pa);
        assert_memory_equal(&va, &vb, sizeof va);
        nt_body_tile_contacts ca, cb;
        assert_int_equal(nt_body_get_tile_contacts(a, ia[i], &ca), NT_OK);
        assert_int_equal(nt_body_get_tile_contacts(b, ib[i], &cb), NT_OK);
        assert_int_equal(ca.count, cb.count);
        assert_true(ca.on_floor && cb.on_floor);
    }
}

static void test_resting_forces_held(void **state)
{
    (void)state;
    nt_body_id ia[3], ib[3];
    nt_world *a = held_world(ia), *b = held_world(ib);
    const nt_real dt = (nt_real)DT;
    for (int k = 0; k < 60; k++) {
        assert_int_equal(nt_world_step(a, dt), NT_OK);
        for (int i = 0; i < 3; i++)
            assert_int_equal(nt_body_set_velocity(b, ib[i], nt_body_get_velocity(b, ib[i])), NT_OK);
        assert_int_equal(nt_world_step(b, dt), NT_OK);
        assert_int_equal(held(b), 0);
    }
    assert_int_equal(held(a), 3);
    assert_same_bodies(a, b, ia, ib, 3);
    nt_vec2 p0[3];
    for (int i = 0; i < 3; i++) p0[i] = nt_body_get_position(a, ia[i]);

    /* The step's length changes: answered again once, then from memory. */
    assert_int_equal(nt_world_step(a, dt / 2), NT_OK);
    assert_int_equal(held(a), 0);
    assert_int_equal(nt_world_step(a, dt / 2), NT_OK);
    assert_int_equal(held(a), 3);
    /* A body's own velocity, material or drag set (even to what it was): that body only. */
    assert_int_equal(nt_body_set_velocity(a, ia[0], nt_v2(0, 0)), NT_OK);
    nt_material m = nt_body_get_material(a, ia[1]);
    assert_int_equal(nt_body_set_material(a, ia[1], m), NT_OK);
    assert_int_equal(nt_world_step(a, dt / 2), NT_OK);
    assert_int_equal(held(a), 1);
    assert_int_equal(nt_body_set_linear_drag(a, ia[2], 0), NT_OK);
    assert_int_equal(nt_world_step(a, dt / 2), NT_OK);
    assert_int_equal(held(a), 2);
    /* The world's materials set: every body. */
    assert_int_equal(nt_world_set_material(a, 0, nt_world_get_material(a, 0)), NT_OK);
    assert_int_equal(nt_world_step(a, dt / 2), NT_OK);
    assert_int_equal(held(a), 0);
    assert_int_equal(nt_world_step(a, dt / 2), NT_OK);
    assert_int_equal(held(a), 3);
    for (int i = 0; i < 3; i++) {
        nt_vec2 p = nt_body_get_position(a, ia[i]);
        assert_memory_equal(&p, &p0[i], sizeof p);
    }

    /* A gravity scale of -1: the box leaves the floor in the next step. */
    assert_int_equal(nt_body_set_gravity_scale(a, ia[0], -1), NT_OK);
    assert_int_equal(nt_world_step(a, dt / 2), NT_OK);
    assert_int_equal(held(a), 2);
    assert_true(nt_body_get_position(a, ia[0]).y < p0[0].y);
    /* The world's gravity turns: both slide. */
    assert_int_equal(nt_world_set_gravity(a, nt_v2(30, 20)), NT_OK);
    assert_int_equal(nt_world_step(a, dt / 2), NT_OK);
    assert_int_equal(held(a), 0);
    for (int i = 1; i < 3; i++) assert_true(nt_body_get_position(a, ia[i]).x > p0[i].x);

    /* A step with a body contact answers every body's forces in the solve. */
    assert_int_equal(nt_world_set_gravity(a, nt_v2(0, 20)), NT_OK);
    assert_int_equal(nt_body_set_gravity_scale(a, ia[0], 1), NT_OK);
    for (int i = 0; i < 3; i++) assert_int_equal(nt_body_set_velocity(a, ia[i], nt_v2(0, 0)), NT_OK);
    for (int k = 0; k < 150; k++) assert_int_equal(nt_world_step(a, dt), NT_OK);
    assert_int_equal(held(a), 3);
    nt_vec2 q = nt_body_get_position(a, ia[2]);
    (void)add_body(a, nt_shape_aabb((nt_real)0.2, (nt_real)0.2), q.x, q.y - (nt_real)0.41, 0, 0);
    assert_int_equal(nt_world_step(a, dt), NT_OK);
    assert_true(nt_world_get_counters(a).contact_count > 0);
    assert_int_equal(held(a), 0);
    nt_world_destroy(a);
    nt_world_destroy(b);
}

/* The grid lists a body under the cell of its centre after every step (clamped into
 * the grid): bodies bouncing fast among random tiles, whose open-air test fails at the
 * place they fly to and whose move ends elsewhere. */
static void test_grid_cell_follows_body(void **state)
{
    (void)state;
    unsigned rng = 12345u;
    int checked = 0;
    for (int seed = 0; seed < 40; seed++) {
        nt_world_def wd = nt_default_world_def();
        wd.map.width = 12;
        wd.map.height = 10;
        wd.map.cell_size = 24;
        nt_world *w = NULL;
        assert_int_equal(nt_world_create(&wd, &w), NT_OK);
        for (int y = 0; y < 10; y++)
            for (int x = 0; x < 12; x++) {
                rng = rng * 1103515245u + 12345u;
                int t = NT_TILE_EMPTY;
                if (y == 9 || x == 0 || x == 11) t = NT_TILE_FULL;
                else if (y >= 4 && (rng >> 8) % 3 == 0) t = 2 + (int)((rng >> 12) % 32);
                assert_int_equal(nt_world_set_tile(w, x, y, t), NT_OK);
            }
        for (int k = 0; k < 12; k++) {
            rng = rng * 1103515245u + 12345u;
            nt_body_def bd = nt_default_body_def();
            double hx = 3 + (rng >> 8) % 9, hy = 3 + (rng >> 12) % 9;
            bd.shape = (rng >> 20) & 1 ? nt_shape_circle((nt_real)hx) : nt_shape_aabb((nt_real)hx, (nt_real)hy);
            bd.position = nt_v2((nt_real)(30 + (rng >> 4) % 230), (nt_real)(20 + (rng >> 9) % 60));
            bd.velocity = nt_v2((nt_real)((int)((rng >> 3) % 600) - 300), (nt_real)((int)((rng >> 11) % 600) - 300));
            bd.material.bounce = 1;
            nt_body_id id;
            assert_int_equal(nt_body_create(w, &bd, &id), NT_OK);
        }
        for (int s = 0; s < 60; s++) {
            assert_int_equal(nt_world_step(w, (nt_real)DT), NT_OK);
            for (int i = 0; i < w->body_hwm; i++) {
                const nt__body *b = &w->bodies[i];
                if (!(b->flags & NT__BF_ALIVE) || b->gcell < 0 || b->level) continue;
                int cx = nt__ifloor(b->p.x * w->inv_cell), cy = nt__ifloor(b->p.y * w->inv_cell);
                cx = cx < 0 ? 0 : cx >= w->grid_w ? w->grid_w - 1 : cx;
                cy = cy < 0 ? 0 : cy >= w->grid_h ? w->grid_h - 1 : cy;
                assert_int_equal(b->gcell >> 1, cy * w->grid_w + cx);
                checked++;
            }
        }
        nt_world_destroy(w);
    }
    assert_true(checked > 20000);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_resting_bodies_need_no_resolution),
        cmocka_unit_test(test_open_air_needs_no_resolution),
        cmocka_unit_test(test_glide_along_floor_into_wall),
        cmocka_unit_test(test_glide_down_slope_onto_floor),
        cmocka_unit_test(test_glide_agrees_with_resolution),
        cmocka_unit_test(test_set_position_forgets_rest),
        cmocka_unit_test(test_resting_forces_held),
        cmocka_unit_test(test_grid_cell_follows_body),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
