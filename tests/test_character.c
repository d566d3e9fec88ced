/* The character mover: slopes with floor snap, step-up, moving platforms, one-way
 * drops, floor/wall classification, bad input. N's scale: cell 24 units, gravity 900
 * units/s^2, dt 1/60 s; the character is a 1 x 2-cell box unless a test says otherwise. */
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
#include "failalloc.h"
#include "ntile/ntile.h"

#define R(x) ((nt_real)(x))
static const nt_real DT = R(1.0 / 60);
static const double CELL = 24, G = 900;

static nt_world *make_world(int w, int h)
{
    nt_world_def d = nt_default_world_def();
    d.map.width = w;
    d.map.height = h;
    d.map.cell_size = (nt_real)CELL;
    d.gravity = nt_v2(0, (nt_real)G);
    d.enable_sleep = false;
    nt_world *world = NULL;
    assert_int_equal(nt_world_create(&d, &world), NT_OK);
    return world;
}

static nt_body_id add_character(nt_world *w, nt_body_type type, nt_shape s, double x, double y)
{
    nt_body_id id = test_body(w, type, s, x, y);
    nt_character_def cd = nt_default_character_def();
    assert_int_equal(nt_character_create(w, id, &cd), NT_OK);
    return id;
}

/* One tick of a simple platformer controller: run at vx, fall under gravity, jump. */
typedef struct pad {
    nt_vec2 v;
    nt_character_result r;
} pad;

static void tick(nt_world *w, nt_body_id id, pad *p, double vx, bool jump)
{
    p->v.x = (nt_real)vx;
    p->v.y += (nt_real)(G * (double)DT);
    if (jump && p->r.on_floor) p->v.y = (nt_real)-400;
    assert_int_equal(nt_character_move(w, id, p->v, DT, &p->r), NT_OK);
    p->v = p->r.velocity;
    assert_int_equal(nt_world_step(w, DT), NT_OK);
}

/* ---------------------------------------------------------------- slopes */

/* A course of one slope kind: a plateau on row F - H, the slope going down H cells
 * (tiles of `kind` in the orientation descending to the right), a floor on row F. */
enum { SW = 80, SH = 20, SF = 16 };

/* Build a slope of 45 or 22 degrees (26.6: two cells across a cell of height)
 * descending to the right from x = 20, `drop` cells high, from a plateau onto the floor
 * (row SF). Returns the first flat cell at its foot. */
static int build_slope(nt_world *w, int kind, int drop)
{
    const int X0 = 20;
    for (int x = 0; x < SW; x++) nt_world_set_tile(w, x, SF, NT_TILE_FULL);
    int x = X0;
    /* The plateau: full cells on the rows above the floor, left of the slope. */
    for (int px = 0; px < X0; px++)
        for (int y = SF - drop; y < SF; y++) nt_world_set_tile(w, px, y, NT_TILE_FULL);
    for (int k = 0; k < drop; k++) {
        int y = SF - drop + k; /* the row this part of the slope crosses */
        if (kind == 45) {
            nt_world_set_tile(w, x, y, NT_TILE_45DEGpn);
            for (int yy = y + 1; yy < SF; yy++) nt_world_set_tile(w, x, yy, NT_TILE_FULL);
            x++;
        } else { /* 22: two cells across per cell of height */
            nt_world_set_tile(w, x, y, NT_TILE_22DEGpnB);
            nt_world_set_tile(w, x + 1, y, NT_TILE_22DEGpnS);
            for (int yy = y + 1; yy < SF; yy++) nt_world_set_tile(w, x, yy, NT_TILE_FULL), nt_world_set_tile(w, x + 1, yy, NT_TILE_FULL);
            x += 2;
        }
    }
    return x; /* the first flat cell at the foot */
}

static void mirror_map(nt_world *w)
{
    for (int y = 0; y < SH; y++)
        for (int x = 0; x < SW / 2; x++) {
            int a = nt_world_get_tile(w, x, y), b = nt_world_get_tile(w, SW - 1 - x, y);
            nt_world_set_tile(w, x, y, b);
            nt_world_set_tile(w, SW - 1 - x, y, a);
        }
}

/* The tile id mirrored in x (N's names: swap the sign of x, pn <-> nn, np <-> pp). */
static int mirror_x(int t)
{
    const nt_tile_info *info = nt_tile_get_info(t);
    if (!info || info->signx == 0) {
        if (t == NT_TILE_HALFr) return NT_TILE_HALFl;
        if (t == NT_TILE_HALFl) return NT_TILE_HALFr;
        return t;
    }
    char name[16];
    snprintf(name, sizeof name, "%s", info->name);
    size_t n = strlen(name);
    char *sx = name + n - (name[n - 1] == 'S' || name[n - 1] == 'B' ? 3 : 2);
    *sx = *sx == 'p' ? 'n' : 'p';
    return nt_tile_from_name(name);
}

static void mirror_tiles(nt_world *w)
{
    mirror_map(w);
    for (int y = 0; y < SH; y++)
        for (int x = 0; x < SW; x++) nt_world_set_tile(w, x, y, mirror_x(nt_world_get_tile(w, x, y)));
}

/* Down every floor slope (45 and 26.6 degrees, both ways) at 60 to 600 units/s with
 * the snap on, as a 1 x 2-cell box and as a circle (which pivots on the crest's corner
 * first): never airborne from the plateau to the foot, never stopped; back up without
 * stopping at a seam. */
static void test_slopes_run_down_and_up(void **state)
{
    (void)state;
    const int kinds[2] = {45, 22};
    const double speeds[] = {60, 150, 250, 400, 600};
    for (int shape = 0; shape < 2; shape++)
    for (int ki = 0; ki < 2; ki++)
        for (int mirror = 0; mirror < 2; mirror++)
            for (size_t si = 0; si < sizeof speeds / sizeof speeds[0]; si++) {
                nt_world *w = make_world(SW, SH);
                int foot = build_slope(w, kinds[ki], 3);
                if (mirror) mirror_tiles(w);
                double dir = mirror ? -1 : 1;
                double x0 = mirror ? (SW - 10) * CELL : 10 * CELL;
                nt_shape sh = shape ? nt_shape_circle(10) : nt_shape_aabb(12, 24);
                nt_body_id id = add_character(w, NT_BODY_DYNAMIC, sh, x0, (SF - 3) * CELL - (double)sh.half.y - 1);
                pad p;
                memset(&p, 0, sizeof p);
                for (int k = 0; k < 30; k++) tick(w, id, &p, 0, false); /* land on the plateau */
                assert_true(p.r.on_floor);
                int airborne = 0, stops = 0, ticks = 0;
                double end = mirror ? (SW - foot - 6) * CELL : (foot + 6) * CELL;
                while (ticks < 2000) {
                    double x = (double)nt_body_get_position(w, id).x;
                    if ((end - x) * dir <= 0) break;
                    tick(w, id, &p, dir * speeds[si], false);
                    ticks++;
                    double nx = (double)nt_body_get_position(w, id).x;
                    if (!p.r.on_floor) airborne++;
                    if ((nx - x) * dir < 0.5 * speeds[si] * (double)DT) stops++;
                }
                if (airborne || stops || ticks >= 2000)
                    fail_msg("%s down %d%s at %g: %d airborne ticks, %d stops in %d ticks", shape ? "circle" : "box", kinds[ki],
                             mirror ? " (mirrored)" : "", speeds[si], airborne, stops, ticks);
                /* And back up to the plateau. */
                double top = mirror ? (SW - 10) * CELL : 10 * CELL;
                stops = 0;
                ticks = 0;
                while (ticks < 2000) {
                    double x = (double)nt_body_get_position(w, id).x;
                    if ((x - top) * dir <= 0) break;
                    tick(w, id, &p, -dir * speeds[si], false);
                    ticks++;
                    double nx = (double)nt_body_get_position(w, id).x;
                    if ((x - nx) * dir < 0.3 * speeds[si] * (double)DT) stops++;
                }
                if (stops || ticks >= 2000)
                    fail_msg("%s up %d%s at %g: %d stops in %d ticks", shape ? "circle" : "box", kinds[ki], mirror ? " (mirrored)" : "",
                             speeds[si], stops, ticks);
                assert_true(p.r.on_floor);
                nt_world_destroy(w);
            }
}

/* The snap follows sloped floors down at any speed, but a ledge onto a flat floor
 * deeper than snap_cells is a fall, however fast the run: running off a one-cell
 * ledge at 60 to 600 units/s, the character is in the air until it lands. */
static void test_ledge_is_a_fall(void **state)
{
    (void)state;
    const double speeds[] = {60, 250, 600};
    for (size_t si = 0; si < sizeof speeds / sizeof speeds[0]; si++) {
        nt_world *w = make_world(SW, SH);
        for (int x = 0; x < SW; x++) nt_world_set_tile(w, x, SF, NT_TILE_FULL);
        for (int x = 0; x < 20; x++) nt_world_set_tile(w, x, SF - 1, NT_TILE_FULL);
        nt_body_id id = add_character(w, NT_BODY_DYNAMIC, nt_shape_circle(10), 15 * CELL, (SF - 1) * CELL - 11);
        pad p;
        memset(&p, 0, sizeof p);
        for (int k = 0; k < 30; k++) tick(w, id, &p, 0, false);
        assert_true(p.r.on_floor);
        int airborne = 0;
        for (int k = 0; k < 200 && (double)nt_body_get_position(w, id).x < 26 * CELL; k++) {
            tick(w, id, &p, speeds[si], false);
            airborne += !p.r.on_floor;
        }
        assert_true(airborne >= 3); /* a fall of a cell takes several ticks */
        assert_true(p.r.on_floor);
        assert_true(fabs((double)nt_body_get_position(w, id).y - (SF * CELL - 10)) < 0.05 * CELL);
        nt_world_destroy(w);
    }
}

/* A floor on row SF and a 1 x 2-cell character standing on it at cell 25. */
static nt_body_id floor_and_character(nt_world *w)
{
    for (int x = 0; x < SW; x++) nt_world_set_tile(w, x, SF, NT_TILE_FULL);
    return add_character(w, NT_BODY_DYNAMIC, nt_shape_aabb(12, 24), 25 * CELL, SF * CELL - 24 - 1);
}

/* A 63.4-degree slope is a wall with the default 50-degree floor angle: running into
 * it, the character is against a wall, not on a floor. A 45-degree slope is a floor only. */
static void test_floor_angle_classification(void **state)
{
    (void)state;
    nt_world *w = make_world(SW, SH);
    nt_body_id id = floor_and_character(w);
    /* A 67-degree slope rising to the right at x = 30 (B then S going up). */
    nt_world_set_tile(w, 30, SF - 1, NT_TILE_67DEGnnB);
    nt_world_set_tile(w, 30, SF - 2, NT_TILE_67DEGnnS);
    for (int y = SF - 2; y < SF; y++) nt_world_set_tile(w, 31, y, NT_TILE_FULL);
    pad p;
    memset(&p, 0, sizeof p);
    int wall = 0;
    for (int k = 0; k < 120; k++) {
        tick(w, id, &p, 150, false);
        if (p.r.on_wall) {
            wall++;
            assert_true(p.r.wall_normal.x < 0);
            assert_true(p.r.wall_normal.y > R(-0.643));
        }
    }
    assert_true(wall > 30);
    assert_true(p.r.on_floor); /* on the flat floor under it */
    assert_true(p.r.floor_normal.y < R(-0.999));
    nt_world_destroy(w);
}

/* A tile painted over a standing character: the next move frees it by the shortest
 * way (up onto the new tile), and it walks on. */
static void test_freed_from_painted_tile(void **state)
{
    (void)state;
    nt_world *w = make_world(SW, SH);
    nt_body_id id = floor_and_character(w);
    pad p;
    memset(&p, 0, sizeof p);
    for (int k = 0; k < 10; k++) tick(w, id, &p, 0, false);
    nt_world_set_tile(w, 25, SF - 1, NT_TILE_HALFd); /* half a cell into its feet */
    tick(w, id, &p, 0, false);
    nt_vec2 q = nt_body_get_position(w, id);
    assert_true((double)nt_map_overlap_depth(nt_world_get_map(w), q, nt_body_get_shape(w, id)) < 1e-3 * CELL);
    assert_true(fabs((double)q.y - ((SF - 0.5) * CELL - 24)) < 0.01 * CELL);
    for (int k = 0; k < 30; k++) tick(w, id, &p, 100, false);
    assert_true((double)nt_body_get_position(w, id).x > 26 * CELL);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- steps */

static void test_step_up(void **state)
{
    (void)state;
    for (int full = 0; full < 2; full++) {
        nt_world *w = make_world(SW, SH);
        nt_body_id id = floor_and_character(w);
        for (int x = 30; x < 40; x++) nt_world_set_tile(w, x, SF - 1, full ? NT_TILE_FULL : NT_TILE_HALFd);
        pad p;
        memset(&p, 0, sizeof p);
        int stepped = 0;
        for (int k = 0; k < 120; k++) {
            tick(w, id, &p, 150, false);
            stepped += p.r.stepped_up;
        }
        double x = (double)nt_body_get_position(w, id).x, y = (double)nt_body_get_position(w, id).y;
        if (full) {
            assert_int_equal(stepped, 0);
            assert_true(x < 30 * CELL - 12 + 1);
        } else {
            assert_int_equal(stepped, 1);
            assert_true(x > 31 * CELL);
            assert_true(fabs(y - ((SF - 0.5) * CELL - 24)) < 0.05 * CELL);
            assert_true(p.r.on_floor);
        }
        nt_world_destroy(w);
    }
}

/* ---------------------------------------------------------------- platforms */

/* A character standing on a 4 x 1-cell kinematic platform moving in 8 directions
 * (sinusoidally, 400 steps each) stays put relative to it within 1e-3 cell; jumping
 * off keeps the platform's velocity. */
static void test_rides_platforms(void **state)
{
    (void)state;
    for (int dir = 0; dir < 8; dir++) {
        nt_world *w = make_world(60, 40);
        nt_body_def pd = nt_default_body_def();
        pd.type = NT_BODY_KINEMATIC;
        pd.shape = nt_shape_aabb(2 * (nt_real)CELL, (nt_real)CELL / 2);
        pd.position = nt_v2((nt_real)(30 * CELL), (nt_real)(20 * CELL));
        nt_body_id plat;
        assert_int_equal(nt_body_create(w, &pd, &plat), NT_OK);
        nt_body_id id = add_character(w, NT_BODY_DYNAMIC, nt_shape_aabb(12, 24), 30 * CELL, 20 * CELL - 12 - 24 - 1);
        pad p;
        memset(&p, 0, sizeof p);
        for (int k = 0; k < 30; k++) tick(w, id, &p, 0, false);
        assert_true(p.r.on_floor && nt_body_id_equals(p.r.floor_body, plat));
        nt_vec2 rel0 = nt_v2(nt_body_get_position(w, id).x - nt_body_get_position(w, plat).x,
                             nt_body_get_position(w, id).y - nt_body_get_position(w, plat).y);
        double a = dir * 3.14159265358979 / 4, worst = 0;
        for (int k = 0; k < 400; k++) {
            double s = 150 * sin(k * (double)DT * 3);
            nt_body_set_velocity(w, plat, nt_v2((nt_real)(s * cos(a)), (nt_real)(s * sin(a))));
            tick(w, id, &p, 0, false);
            double rx = (double)nt_body_get_position(w, id).x - (double)nt_body_get_position(w, plat).x - (double)rel0.x;
            double ry = (double)nt_body_get_position(w, id).y - (double)nt_body_get_position(w, plat).y - (double)rel0.y;
            worst = fmax(worst, fmax(fabs(rx), fabs(ry)) / CELL);
        }
        if (worst > 1e-3) fail_msg("direction %d: drift %.3g cell", dir, worst);
        /* Jump off while the platform moves at a steady velocity: the platform's part stays. */
        nt_vec2 pv = nt_v2((nt_real)(100 * cos(a)), (nt_real)(100 * sin(a)));
        nt_body_set_velocity(w, plat, pv);
        tick(w, id, &p, 0, false);
        tick(w, id, &p, 0, true);
        assert_false(p.r.on_floor);
        assert_true(fabs((double)p.v.x - (double)pv.x) < 1e-3);
        nt_world_destroy(w);
    }
}

/* ---------------------------------------------------------------- one-way drops */

static void test_drop_through(void **state)
{
    (void)state;
    nt_world *w = make_world(40, 24);
    for (int x = 0; x < 40; x++) nt_world_set_tile(w, x, 20, NT_TILE_FULL);
    for (int x = 5; x < 15; x++) {
        nt_world_set_tile(w, x, 12, NT_TILE_HALFu);
        assert_int_equal(nt_world_set_cell_flags(w, x, 12, NT_CELL_ONE_WAY), NT_OK);
    }
    nt_body_id id = add_character(w, NT_BODY_DYNAMIC, nt_shape_aabb(12, 24), 10 * CELL, 12 * CELL - 24 - 2);
    pad p;
    memset(&p, 0, sizeof p);
    /* Standing on the one-way floor for 2 s: it holds. */
    for (int k = 0; k < 120; k++) tick(w, id, &p, 0, false);
    assert_true(p.r.on_floor);
    assert_true(fabs((double)nt_body_get_position(w, id).y - (12 * CELL - 24)) < 0.01 * CELL);
    /* Asked to drop: through it onto the floor below. */
    assert_int_equal(nt_character_drop_through(w, id), NT_OK);
    for (int k = 0; k < 120; k++) tick(w, id, &p, 0, false);
    assert_true(p.r.on_floor);
    assert_true(fabs((double)nt_body_get_position(w, id).y - (20 * CELL - 24)) < 0.01 * CELL);
    nt_world_destroy(w);
}

/* A one-way kinematic platform (is_one_way): the character jumps up through it from
 * below and lands on it; standing on it, it drops through only when asked. */
static void test_one_way_platform_body(void **state)
{
    (void)state;
    nt_world *w = make_world(40, 24);
    for (int x = 0; x < 40; x++) nt_world_set_tile(w, x, 20, NT_TILE_FULL);
    nt_body_def pd = nt_default_body_def();
    pd.type = NT_BODY_KINEMATIC;
    pd.shape = nt_shape_aabb((nt_real)(3 * CELL), 6);
    pd.position = nt_v2((nt_real)(20 * CELL), (nt_real)(17 * CELL)); /* a jump rises 3.7 cells */
    pd.is_one_way = true;
    nt_body_id plat;
    assert_int_equal(nt_body_create(w, &pd, &plat), NT_OK);
    nt_body_id id = add_character(w, NT_BODY_DYNAMIC, nt_shape_aabb(12, 24), 20 * CELL, 20 * CELL - 25);
    pad p;
    memset(&p, 0, sizeof p);
    for (int k = 0; k < 20; k++) tick(w, id, &p, 0, false);
    assert_true(p.r.on_floor);
    double top = 1e9;
    for (int k = 0; k < 120; k++) {
        tick(w, id, &p, 0, k == 0);
        top = fmin(top, (double)nt_body_get_position(w, id).y);
    }
    assert_true(top < 17 * CELL - 6 - 24); /* it rose above the platform */
    assert_true(p.r.on_floor && nt_body_id_equals(p.r.floor_body, plat));
    assert_true(fabs((double)nt_body_get_position(w, id).y - (17 * CELL - 6 - 24)) < 0.01 * CELL);
    assert_int_equal(nt_character_drop_through(w, id), NT_OK);
    for (int k = 0; k < 120; k++) tick(w, id, &p, 0, false);
    assert_true(fabs((double)nt_body_get_position(w, id).y - (20 * CELL - 24)) < 0.01 * CELL);
    nt_world_destroy(w);
}

/* Pushed, not overrun: a kinematic wall moving into a standing character pushes it
 * along (it was passed through: kinematic bodies make no contact with each other, and
 * casts from inside a body went nowhere); a body whose mask leaves the character out
 * does not stop it; a huge velocity moves it at the speed limit, not by nothing. */
static void test_pushed_masks_and_huge_velocity(void **state)
{
    (void)state;
    nt_world *w = make_world(SW, SH);
    nt_body_id id = floor_and_character(w);
    nt_body_def kd = nt_default_body_def();
    kd.type = NT_BODY_KINEMATIC;
    kd.shape = nt_shape_aabb(12, 48);
    kd.position = nt_v2((nt_real)(20 * CELL), (nt_real)(SF * CELL - 48 - 1));
    kd.velocity = nt_v2(120, 0);
    nt_body_id wall;
    assert_int_equal(nt_body_create(w, &kd, &wall), NT_OK);
    pad p;
    memset(&p, 0, sizeof p);
    for (int k = 0; k < 150; k++) {
        tick(w, id, &p, 0, false);
        double gap = (double)nt_body_get_position(w, id).x - (double)nt_body_get_position(w, wall).x;
        /* Never deeper in the wall than the wall's motion of the step since its move. */
        assert_true(gap > 24 - 120 * (double)DT - 0.01 * CELL);
    }
    assert_true((double)nt_body_get_position(w, id).x > 26 * CELL);
    assert_true(p.r.on_floor);
    nt_body_destroy(w, wall);
    /* A static block whose mask leaves the character's category out: walked through. */
    nt_body_def bd = nt_default_body_def();
    bd.type = NT_BODY_STATIC;
    bd.shape = nt_shape_aabb(12, 24);
    bd.mask = 2;
    double x0 = (double)nt_body_get_position(w, id).x;
    bd.position = nt_v2((nt_real)(x0 + 3 * CELL), (nt_real)(SF * CELL - 24));
    nt_body_id ghost;
    assert_int_equal(nt_body_create(w, &bd, &ghost), NT_OK);
    for (int k = 0; k < 60; k++) tick(w, id, &p, 150, false);
    assert_true((double)nt_body_get_position(w, id).x > x0 + 5 * CELL);
    /* A long step (100 s, longer than the limit's 96 units: seconds and units once got
     * compared) at a small speed moves by speed x dt, not by the speed limit. */
    {
        nt_world *v = make_world(SW, SH);
        nt_body_id c2 = floor_and_character(v);
        nt_character_result r2;
        double x2 = (double)nt_body_get_position(v, c2).x;
        assert_int_equal(nt_character_move(v, c2, nt_v2(R(0.1), 0), 100, &r2), NT_OK);
        assert_true(fabs((double)r2.position.x - x2 - 10) < 1e-3);
        nt_world_destroy(v);
    }
    /* 1e20 units/s: the speed limit's 4 cells in one move. */
    nt_character_result r;
    double before = (double)nt_body_get_position(w, id).x;
    assert_int_equal(nt_character_move(w, id, nt_v2((nt_real)1e20, 0), DT, &r), NT_OK);
    assert_true(fabs((double)r.position.x - before - 4 * CELL) < 1e-3 * CELL);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- bad input */

static void test_bad_input(void **state)
{
    (void)state;
    nt_world *w = make_world(20, 12);
    nt_body_def d = nt_default_body_def();
    d.type = NT_BODY_STATIC;
    d.position = nt_v2(100, 100);
    nt_body_id st;
    assert_int_equal(nt_body_create(w, &d, &st), NT_OK);
    nt_character_def cd = nt_default_character_def();
    assert_int_equal(nt_character_create(w, st, &cd), NT_ERR_INVALID_ARGUMENT);
    nt_body_id id = add_character(w, NT_BODY_DYNAMIC, nt_shape_aabb(12, 24), 200, 100);
    uint64_t h0 = nt_world_hash(w);
    nt_character_result r;
    assert_int_equal(nt_character_move(w, id, nt_v2((nt_real)NAN, 0), DT, &r), NT_ERR_NON_FINITE);
    assert_int_equal(nt_character_move(w, id, nt_v2(0, (nt_real)INFINITY), DT, &r), NT_ERR_NON_FINITE);
    assert_int_equal(nt_character_move(w, id, nt_v2(1, 0), (nt_real)NAN, &r), NT_ERR_NON_FINITE);
    assert_int_equal(nt_character_move(w, id, nt_v2(1, 0), 0, &r), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_character_move(w, id, nt_v2(1, 0), -1, &r), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_character_move(w, st, nt_v2(1, 0), DT, &r), NT_ERR_INVALID_ID);
    assert_int_equal(nt_character_move(w, id, nt_v2(1, 0), DT, NULL), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_character_move(NULL, id, nt_v2(1, 0), DT, &r), NT_ERR_INVALID_ARGUMENT);
    assert_true(nt_world_hash(w) == h0);
    cd.max_slides = 0;
    assert_int_equal(nt_character_create(w, id, &cd), NT_ERR_INVALID_ARGUMENT);
    cd = nt_default_character_def();
    cd.snap_cells = (nt_real)NAN;
    assert_int_equal(nt_character_create(w, id, &cd), NT_ERR_NON_FINITE);
    /* The body keeps its own type; destroying the character gives it back. */
    assert_int_equal(nt_body_get_type(w, id), NT_BODY_DYNAMIC);
    assert_true(nt_character_is_valid(w, id));
    assert_int_equal(nt_character_destroy(w, id), NT_OK);
    assert_false(nt_character_is_valid(w, id));
    assert_int_equal(nt_character_move(w, id, nt_v2(1, 0), DT, &r), NT_ERR_INVALID_ID);
    nt_world_destroy(w);
}

/* Out of memory while the character array grows (the first character, and the one
 * past its capacity): NT_ERR_OUT_OF_MEMORY, and the world as it was. */
static void test_create_out_of_memory(void **state)
{
    (void)state;
    nt_world *w = make_world(40, 12);
    nt_body_id ids[40];
    for (int i = 0; i < 40; i++) {
        nt_body_def d = nt_default_body_def();
        d.position = nt_v2((nt_real)(36 + 24 * i), 100);
        assert_int_equal(nt_body_create(w, &d, &ids[i]), NT_OK);
    }
    nt_character_def cd = nt_default_character_def();
    int made = 0, refused = 0;
    for (int i = 0; i < 40; i++) {
        uint64_t h = nt_world_hash(w);
        failalloc_begin(0);
        nt_status s = nt_character_create(w, ids[i], &cd);
        assert_int_equal(failalloc_end(), 0);
        if (s == NT_OK) {
            made++;
            continue;
        }
        assert_int_equal(s, NT_ERR_OUT_OF_MEMORY);
        assert_false(nt_character_is_valid(w, ids[i]));
        assert_true(nt_world_hash(w) == h);
        refused++;
        assert_int_equal(nt_character_create(w, ids[i], &cd), NT_OK); /* with memory: made */
    }
    assert_true(refused >= 2); /* the first, and at least one growth */
    assert_int_equal(made + refused, 40);
    for (int i = 0; i < 40; i++) assert_true(nt_character_is_valid(w, ids[i]));
    nt_world_destroy(w);
}

/* Dynamic bodies: a crate under its feet holds the character up (it stands on it,
 * carried by it) and is not squeezed into the floor or shoved off; walking off its
 * edge leaves it where it was; a ball in the way on the floor is pushed ahead. */
static void test_stands_on_crates_pushes_balls(void **state)
{
    (void)state;
    for (int shape = 0; shape < 2; shape++) {
        nt_world *w = make_world(SW, SH);
        for (int x = 0; x < SW; x++) nt_world_set_tile(w, x, SF, NT_TILE_FULL);
        nt_body_def bd = nt_default_body_def();
        bd.shape = nt_shape_aabb(12, 12);
        bd.position = nt_v2((nt_real)(20 * CELL), (nt_real)(SF * CELL - 12));
        nt_body_id crate, ball;
        assert_int_equal(nt_body_create(w, &bd, &crate), NT_OK);
        bd.shape = nt_shape_circle(5);
        bd.position = nt_v2((nt_real)(24 * CELL), (nt_real)(SF * CELL - 5));
        assert_int_equal(nt_body_create(w, &bd, &ball), NT_OK);
        nt_shape sh = shape ? nt_shape_circle(10) : nt_shape_aabb(8, 16);
        nt_body_id id = add_character(w, NT_BODY_DYNAMIC, sh, 20 * CELL, (SF - 4) * CELL);
        pad p;
        memset(&p, 0, sizeof p);
        for (int k = 0; k < 90; k++) tick(w, id, &p, 0, false);
        nt_vec2 c0 = nt_body_get_position(w, crate);
        assert_true(fabs((double)c0.y - (SF * CELL - 12)) < 0.05); /* on the floor, not pressed into it */
        assert_true(p.r.on_floor);
        assert_true(nt_body_id_equals(p.r.floor_body, crate));
        assert_true(fabs((double)nt_body_get_position(w, id).y - ((double)c0.y - 12 - (double)sh.half.y)) < 0.05);
        for (int k = 0; k < 120; k++) tick(w, id, &p, 150, false);
        nt_vec2 c1 = nt_body_get_position(w, crate);
        assert_true(fabs((double)c1.x - (double)c0.x) < 0.5 && fabs((double)c1.y - (double)c0.y) < 0.05);
        /* Off the crate, down on the floor, past where the ball was: it went ahead. */
        nt_vec2 q = nt_body_get_position(w, id);
        assert_true((double)q.x > 26 * CELL);
        assert_true(fabs((double)q.y - (SF * CELL - (double)sh.half.y)) < 0.05);
        assert_true((double)nt_body_get_position(w, ball).x > (double)q.x);
        nt_world_destroy(w);
    }
}

/* ---------------------------------------------------------------- determinism */

/* A scripted 2,000-tick run: three characters (one kinematic) running, jumping and
 * dropping over slopes, a step, a one-way floor and a lift, pushing crates. The same
 * inputs give the same bits (twice here; `make determinism` checks the golden hash
 * under gcc and clang at -O0, -O2 and -O3, float and double). */
static uint64_t scripted_run(void)
{
    nt_world *w = make_world(SW, SH);
    int foot = build_slope(w, 45, 3);
    for (int x = foot + 6; x < foot + 9; x++) nt_world_set_tile(w, x, SF - 1, NT_TILE_HALFd);
    for (int x = 50; x < 58; x++) {
        nt_world_set_tile(w, x, 10, NT_TILE_HALFu);
        nt_world_set_cell_flags(w, x, 10, NT_CELL_ONE_WAY);
    }
    nt_world_set_tile(w, 70, SF - 1, NT_TILE_22DEGnnS);
    nt_world_set_tile(w, 71, SF - 1, NT_TILE_22DEGnnB);
    for (int x = 72; x < SW; x++) nt_world_set_tile(w, x, SF - 1, NT_TILE_FULL);
    nt_body_def ld = nt_default_body_def();
    ld.type = NT_BODY_KINEMATIC;
    ld.shape = nt_shape_aabb((nt_real)(1.5 * CELL), (nt_real)(CELL / 4));
    ld.position = nt_v2((nt_real)(45 * CELL), (nt_real)(14 * CELL));
    nt_body_id lift;
    assert_int_equal(nt_body_create(w, &ld, &lift), NT_OK);
    nt_body_def cd = nt_default_body_def();
    cd.shape = nt_shape_aabb(10, 10);
    for (int k = 0; k < 4; k++) {
        cd.position = nt_v2((nt_real)((30 + 5 * k) * CELL), (nt_real)((SF - 1) * CELL));
        nt_body_id crate;
        assert_int_equal(nt_body_create(w, &cd, &crate), NT_OK);
    }
    /* The tiles that hold a character whatever it does: the one-way floor is left out
     * (it passes through it going up and dropping down). */
    const nt_map *wm = nt_world_get_map(w);
    nt_map_def md = nt_default_map_def();
    md.width = nt_map_get_width(wm);
    md.height = nt_map_get_height(wm);
    md.cell_size = nt_map_get_cell_size(wm);
    nt_map *solid = NULL;
    assert_int_equal(nt_map_create(&md, &solid), NT_OK);
    for (int y = 0; y < md.height; y++)
        for (int x = 0; x < md.width; x++)
            if (!(nt_world_get_cell_flags(w, x, y) & NT_CELL_ONE_WAY)) nt_map_set_tile(solid, x, y, nt_map_get_tile(wm, x, y));
    nt_body_id ch[3] = {add_character(w, NT_BODY_DYNAMIC, nt_shape_aabb(12, 24), 8 * CELL, (SF - 3) * CELL - 25),
                        add_character(w, NT_BODY_KINEMATIC, nt_shape_aabb(8, 16), 12 * CELL, (SF - 3) * CELL - 17),
                        add_character(w, NT_BODY_DYNAMIC, nt_shape_circle(11), 60 * CELL, SF * CELL - 12)};
    pad p[3];
    memset(p, 0, sizeof p);
    uint32_t rng = 12345;
    for (int t = 0; t < 2000; t++) {
        double ls = 60 * sin(t * 0.02);
        nt_body_set_velocity(w, lift, nt_v2(0, (nt_real)ls));
        for (int k = 0; k < 3; k++) {
            rng = rng * 1664525u + 1013904223u;
            double dir = ((t / (200 + 50 * k)) % 2) ? -1 : 1;
            bool jump = (rng >> 24) < 6;
            if ((rng >> 20) % 97 == 0) nt_character_drop_through(w, ch[k]);
            p[k].v.x = (nt_real)(dir * (120 + 40 * k));
            p[k].v.y += (nt_real)(G * (double)DT);
            if (jump && p[k].r.on_floor) p[k].v.y = (nt_real)-380;
            assert_int_equal(nt_character_move(w, ch[k], p[k].v, DT, &p[k].r), NT_OK);
            p[k].v = p[k].r.velocity;
        }
        assert_int_equal(nt_world_step(w, DT), NT_OK);
        for (int k = 0; k < 3; k++) {
            nt_vec2 q = nt_body_get_position(w, ch[k]);
            assert_true((double)nt_map_overlap_depth(solid, q, nt_body_get_shape(w, ch[k])) < 1e-3 * CELL);
        }
    }
    uint64_t h = nt_world_hash(w);
    nt_map_destroy(solid);
    nt_world_destroy(w);
    return h;
}

static void test_scripted_run_golden_hash(void **state)
{
    (void)state;
    uint64_t h = scripted_run();
    assert_true(scripted_run() == h);
    printf("character golden hash (%s): 0x%016llx\n", NT_REAL_IS_DOUBLE ? "double" : "float", (unsigned long long)h);
#if NT_REAL_IS_DOUBLE
    const uint64_t golden = 0x27cca9689aec0b22ull;
#else
    const uint64_t golden = 0x8280b2718e5f24e0ull;
#endif
    assert_true(h == golden);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_slopes_run_down_and_up),
        cmocka_unit_test(test_stands_on_crates_pushes_balls),
        cmocka_unit_test(test_ledge_is_a_fall),
        cmocka_unit_test(test_floor_angle_classification),
        cmocka_unit_test(test_freed_from_painted_tile),
        cmocka_unit_test(test_step_up),
        cmocka_unit_test(test_rides_platforms),
        cmocka_unit_test(test_drop_through),
        cmocka_unit_test(test_one_way_platform_body),
        cmocka_unit_test(test_pushed_masks_and_huge_velocity),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_create_out_of_memory),
        cmocka_unit_test(test_scripted_run_golden_hash),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
