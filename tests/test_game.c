/* The game layer: the random source, the player controller (run, skid, jump height
 * against the analytic value from the controller's own constants, standing on a
 * slope, wall slide and wall jump), riders on moving platforms, level objects
 * (gold, mines, exits, kill and score regions, spawners), paths, the game hash, and
 * the replay runner's facts, hashes and divergence report. Levels are written here. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "ntile/game.h"

#define R(x) ((nt_real)(x))
static const nt_real DT = R(0.025);

static nt_level *level_from(const char *text)
{
    nt_level *lv = NULL;
    nt_text_error e;
    nt_status s = nt_level_parse("g.ntl", text, strlen(text), &lv, &e);
    if (s != NT_OK) fprintf(stderr, "%s\n", e.message);
    assert_int_equal(s, NT_OK);
    return lv;
}

static nt_game *game_from(const nt_level *lv, const nt_game_def *def)
{
    nt_game *g = NULL;
    assert_int_equal(nt_game_create(lv, def, &g), NT_OK);
    return g;
}

static void steps(nt_game *g, uint32_t keys, int n)
{
    for (int i = 0; i < n; i++) assert_int_equal(nt_game_step(g, keys, DT), NT_OK);
}

static nt_vec2 ppos(const nt_game *g) { return nt_body_get_position(nt_game_get_world(g), nt_game_get_player(g)); }
static nt_vec2 pvel(const nt_game *g) { return nt_body_get_velocity(nt_game_get_world(g), nt_game_get_player(g)); }

/* A room 16 x 10 cells of 24 with a floor at row 9 (top y = 216) and walls. */
#define ROOM_TILES \
    "ntile-level 1\nsize 16 10\n" \
    "tiles\n" \
    "|################|\n" \
    "|#..............#|\n" \
    "|#..............#|\n" \
    "|#..............#|\n" \
    "|#..............#|\n" \
    "|#..............#|\n" \
    "|#..............#|\n" \
    "|#..............#|\n" \
    "|#..............#|\n" \
    "|################|\n"
static const char room[] = ROOM_TILES "player 192 200\n";

/* ---------------------------------------------------------------- random source */

static void test_rng(void **state)
{
    (void)state;
    /* splitmix64's published first outputs for seed 0 (high 32 bits of each). */
    nt_rng r;
    nt_rng_seed(&r, 0);
    assert_int_equal(nt_rng_next(&r), 0xe220a839u);
    assert_int_equal(nt_rng_next(&r), 0x6e789e6au);
    assert_int_equal(nt_rng_next(&r), 0x06c45d18u);
    nt_rng a, b;
    nt_rng_seed(&a, 77);
    nt_rng_seed(&b, 77);
    double lo = 1, hi = 0;
    for (int i = 0; i < 10000; i++) {
        nt_real x = nt_rng_range(&a, -2, 3);
        assert_true(x == nt_rng_range(&b, -2, 3));
        assert_true(x >= -2 && x < 3);
        double u = ((double)x + 2) / 5;
        lo = fmin(lo, u);
        hi = fmax(hi, u);
    }
    assert_true(lo < 0.001 && hi > 0.999); /* covers the range */
}

/* ---------------------------------------------------------------- the controller */

static void settle(nt_game *g) { steps(g, 0, 40); }

static void test_run_and_skid(void **state)
{
    (void)state;
    nt_level *lv = level_from(room);
    nt_game *g = game_from(lv, NULL);
    nt_player_def pd = nt_default_player_def();
    const double c = 24;
    settle(g);
    assert_true(nt_game_get_state(g).on_floor);
    assert_true(fabs((double)pvel(g).x) < 1e-6);
    steps(g, NT_INPUT_RIGHT, 1);
    assert_true(fabs((double)pvel(g).x - (double)pd.ground_accel * c * (double)DT) < 1e-3);
    steps(g, NT_INPUT_RIGHT, 20);
    assert_true(fabs((double)pvel(g).x - (double)pd.run_speed * c) < 1e-3); /* capped at run speed */
    steps(g, NT_INPUT_LEFT, 1);                                             /* skid */
    assert_true(fabs((double)pvel(g).x - ((double)pd.run_speed - (double)pd.skid_decel * (double)DT) * c) < 1e-3);
    steps(g, 0, 1); /* no key: ground deceleration */
    assert_true(fabs((double)pvel(g).x -
                     ((double)pd.run_speed - ((double)pd.skid_decel + (double)pd.ground_decel) * (double)DT) * c) < 1e-3);
    steps(g, 0, 20);
    assert_true(fabs((double)pvel(g).x) < 1e-6);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

/* Rise of a jump from the floor: highest point above the standing height. */
static double jump_rise(const nt_level *lv, const nt_game_def *def, int hold)
{
    nt_game *g = game_from(lv, def);
    settle(g);
    double y0 = (double)ppos(g).y, top = y0;
    for (int i = 0; i < 150; i++) {
        steps(g, i < hold ? NT_INPUT_JUMP : 0, 1);
        top = fmin(top, (double)ppos(g).y);
    }
    nt_game_destroy(g);
    return y0 - top;
}

static void test_jump_height(void **state)
{
    (void)state;
    nt_level *lv = level_from(room);
    const double c = 24, g = 320;
    for (int variant = 0; variant < 2; variant++) {
        nt_game_def def = nt_default_game_def();
        if (variant) {
            def.player.jump_speed = 4;
            def.player.jump_gravity_scale = R(0.5);
        }
        double v0 = (double)def.player.jump_speed * c;
        /* Held: gravity is scaled while it rises, so h = v0^2 / (2 g s). */
        double held = jump_rise(lv, &def, 150);
        double want_held = v0 * v0 / (2 * g * (double)def.player.jump_gravity_scale);
        /* Tapped: full gravity from the second tick on, so h = v0^2 / (2 g). */
        double tap = jump_rise(lv, &def, 1);
        double want_tap = v0 * v0 / (2 * g);
        /* Semi-implicit Euler lands within one tick of motion of the analytic apex. */
        double tol = v0 * (double)DT;
        assert_true(fabs(held - want_held) <= tol);
        assert_true(fabs(tap - want_tap) <= tol);
        assert_true(held > want_tap + 2 * tol); /* variable height: holding matters */
    }
    nt_level_destroy(lv);
}

static void test_stand_on_slope(void **state)
{
    (void)state;
    /* A 45-degree floor (45DEGnn, rising to the right) under the player. */
    nt_level *lv = level_from("ntile-level 1\nsize 8 6\ntiles\n|########|\n|#......#|\n|#......#|\n|#...33.#|\n|#..3##3#|\n"
                              "|########|\nplayer 108 70\n");
    nt_game *g = game_from(lv, NULL);
    steps(g, 0, 60);
    nt_game_state st = nt_game_get_state(g);
    assert_true(st.on_floor);
    nt_vec2 p0 = ppos(g);
    steps(g, 0, 120);
    nt_vec2 p1 = ppos(g);
    /* Without the controller it would slide down at g sin 45 (about 200 px in 3 s). */
    assert_true(fabs((double)p1.x - (double)p0.x) < 0.5 && fabs((double)p1.y - (double)p0.y) < 0.5);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

static void test_wall_slide_and_wall_jump(void **state)
{
    (void)state;
    nt_level *lv = level_from(room);
    nt_player_def pd = nt_default_player_def();
    const double c = 24, g = 320;
    nt_game *gm = game_from(lv, NULL);
    settle(gm);
    steps(gm, NT_INPUT_RIGHT, 60); /* against the right wall (x = 360 - 10) */
    assert_true(nt_game_get_state(gm).wall_right);
    double floor_y = (double)ppos(gm).y;
    /* A held jump along the wall, then, falling, a new press: a wall jump. */
    double top = floor_y;
    int t = 0;
    for (; t < 80; t++) {
        steps(gm, NT_INPUT_RIGHT | NT_INPUT_JUMP, 1);
        top = fmin(top, (double)ppos(gm).y);
        if (pvel(gm).y > 0) break; /* past the apex */
    }
    double first = floor_y - top;
    /* Sliding: pressing into the wall caps the fall speed. */
    steps(gm, NT_INPUT_RIGHT, 12);
    assert_true(nt_game_get_state(gm).wall_right);
    assert_true(fabs((double)pvel(gm).y - (double)pd.wall_slide_speed * c) < 1e-3);
    double x_before = (double)ppos(gm).x;
    steps(gm, NT_INPUT_JUMP, 1);
    nt_vec2 v = pvel(gm);
    assert_true(fabs((double)v.x + (double)pd.wall_jump_speed_x * c) < 1e-3);
    assert_true(fabs((double)v.y - (-(double)pd.wall_jump_speed_y * c + g * (double)pd.jump_gravity_scale * (double)DT)) < 1e-3);
    assert_true((double)ppos(gm).x < x_before);
    for (int i = 0; i < 80; i++) {
        steps(gm, NT_INPUT_JUMP, 1);
        top = fmin(top, (double)ppos(gm).y);
    }
    /* The wall jump took the player higher than any jump from the floor can. */
    double v0 = (double)pd.jump_speed * c;
    double max_floor_jump = v0 * v0 / (2 * g * (double)pd.jump_gravity_scale) + v0 * (double)DT;
    assert_true(floor_y - top > max_floor_jump);
    assert_true(floor_y - top > first + 30);
    nt_game_destroy(gm);
    nt_level_destroy(lv);
}

static void test_no_jump_in_the_air(void **state)
{
    (void)state;
    nt_level *lv = level_from(room);
    nt_game *g = game_from(lv, NULL);
    settle(g);
    steps(g, NT_INPUT_JUMP, 1);
    steps(g, 0, 10); /* falling back, far from walls and floor */
    double vy = (double)pvel(g).y;
    steps(g, NT_INPUT_JUMP, 1);
    assert_true((double)pvel(g).y > vy); /* a press in the air does nothing: gravity goes on */
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

/* ---------------------------------------------------------------- riders */

static void test_riders_on_moving_platform(void **state)
{
    (void)state;
    nt_level *lv = level_from("ntile-level 1\nsize 30 12\ntiles\n"
                              "|##############################|\n"
                              "|#............................#|\n|#............................#|\n"
                              "|#............................#|\n|#............................#|\n"
                              "|#............................#|\n|#............................#|\n"
                              "|#............................#|\n|#............................#|\n"
                              "|#............................#|\n|#............................#|\n"
                              "|##############################|\n"
                              "player 100 170\n"
                              "path ride pingpong speed 60 wait 1 points 100 186 600 186\n"
                              "body plat1 kinematic box 12 6 at 88 186 path ride\n"
                              "path ride2 pingpong speed 60 wait 1 points 124 186 624 186\n"
                              "body plat2 kinematic box 12 6 at 112 186 path ride2\n"
                              "body crate dynamic box 5 5 at 130 170 material 1 0\n");
    nt_game *g = game_from(lv, NULL);
    nt_world *w = nt_game_get_world(g);
    nt_body_id plat = nt_game_find_body(g, "plat1"), crate = nt_game_find_body(g, "crate");
    assert_false(nt_body_id_is_null(plat));
    steps(g, 0, 30); /* the platform waits 1 s: both settle on it */
    assert_true(nt_game_get_state(g).on_floor);
    double rel0 = (double)ppos(g).x - (double)nt_body_get_position(w, plat).x;
    double crate0 = (double)nt_body_get_position(w, crate).x - (double)nt_body_get_position(w, plat).x;
    double worst = 0, x_start = (double)nt_body_get_position(w, plat).x;
    for (int i = 0; i < 200; i++) {
        steps(g, 0, 1);
        double rel = (double)ppos(g).x - (double)nt_body_get_position(w, plat).x;
        worst = fmax(worst, fabs(rel - rel0));
        assert_true(nt_game_get_state(g).on_floor);
    }
    assert_true((double)nt_body_get_position(w, plat).x - x_start > 200); /* it did move */
    assert_true(worst < 0.5);                                             /* and the player rode it */
    /* The crate rides by friction: it may slip at the start, then moves with the platform. */
    double crate1 = (double)nt_body_get_position(w, crate).x - (double)nt_body_get_position(w, plat).x;
    assert_true(fabs(crate1 - crate0) < 24);
    assert_true(fabs((double)nt_body_get_velocity(w, crate).x - (double)nt_body_get_velocity(w, plat).x) < 1);
    /* Walking on the platform is relative to it: three ticks of ground acceleration. */
    double vplat = (double)nt_body_get_velocity(w, plat).x;
    assert_true(fabs(vplat - 60) < 0.01);
    steps(g, NT_INPUT_LEFT, 3);
    double accel = (double)nt_default_player_def().ground_accel * 24;
    assert_true(fabs((double)pvel(g).x - (vplat - 3 * accel * (double)DT)) < 0.01);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

static void test_elevator(void **state)
{
    (void)state;
    nt_level *lv = level_from("ntile-level 1\nsize 6 14\ntiles\n|######|\n|#....#|\n|#....#|\n|#....#|\n|#....#|\n"
                              "|#....#|\n|#....#|\n|#....#|\n|#....#|\n|#....#|\n|#....#|\n|#....#|\n|#....#|\n|######|\n"
                              "player 72 270\n"
                              "path up pingpong speed 30 wait 0.5 points 72 286 72 100\n"
                              "body lift kinematic box 12 6 at 72 286 path up\n");
    nt_game *g = game_from(lv, NULL);
    nt_world *w = nt_game_get_world(g);
    nt_body_id lift = nt_game_find_body(g, "lift");
    steps(g, 0, 20);
    double worst = 0;
    /* Up (6.2 s), a wait, and down at 30 units/s, slower than a fall: the rider stays
     * on top the whole way. When the lift stops at the top the rider coasts up by
     * u^2 / (2 g) = 1.4 units and lands again. */
    for (int i = 0; i < 400; i++) {
        steps(g, 0, 1);
        double gap = (double)nt_body_get_position(w, lift).y - 6 - ((double)ppos(g).y + 10);
        worst = fmax(worst, fabs(gap));
    }
    assert_true(worst < 30.0 * 30.0 / (2 * 320) + 0.5);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

/* ---------------------------------------------------------------- the mover's gifts */

/* A 40 x 12-cell room: floor row 11, walls at columns 0 and 39. */
static nt_level *wide_room(const char *head, const char *extra)
{
    char text[4096];
    int n = snprintf(text, sizeof text, "ntile-level 1\nsize 40 12\n%stiles\n", head);
    for (int y = 0; y < 12; y++) {
        text[n++] = '|';
        for (int x = 0; x < 40; x++) text[n++] = (y == 0 || y == 11 || x == 0 || x == 39) ? '#' : '.';
        text[n++] = '|';
        text[n++] = '\n';
    }
    snprintf(text + n, sizeof text - (size_t)n, "%s", extra);
    return level_from(text);
}

/* A plateau 3 cells high and a slope of 45 or 26.6 degrees down onto the floor,
 * descending toward the room's middle from the left (dir +1) or the right (dir -1).
 * Returns the column of the first flat cell at the foot. */
static int build_ramp(nt_game *g, int kind, int dir)
{
    const int drop = 3, X0 = 12, F = 11;
    int x = X0;
    for (int px = 1; px < X0; px++)
        for (int y = F - drop; y < F; y++) assert_int_equal(nt_game_set_tile(g, dir > 0 ? px : 39 - px, y, NT_TILE_FULL), NT_OK);
    for (int k = 0; k < drop; k++) {
        int y = F - drop + k, w = kind == 45 ? 1 : 2;
        for (int j = 0; j < w; j++) {
            int t = kind == 45 ? (dir > 0 ? NT_TILE_45DEGpn : NT_TILE_45DEGnn)
                               : j == 0 ? (dir > 0 ? NT_TILE_22DEGpnB : NT_TILE_22DEGnnB)
                                        : (dir > 0 ? NT_TILE_22DEGpnS : NT_TILE_22DEGnnS);
            int cx = dir > 0 ? x + j : 39 - (x + j);
            assert_int_equal(nt_game_set_tile(g, cx, y, t), NT_OK);
            for (int yy = y + 1; yy < F; yy++) assert_int_equal(nt_game_set_tile(g, cx, yy, NT_TILE_FULL), NT_OK);
        }
        x += w;
    }
    return dir > 0 ? x : 39 - x;
}

/* The complaint: running down a ramp from a plateau, the old player flew off
 * it for 15 ticks. On the mover it stays on the floor every tick, down 45 and 26.6
 * degrees, both ways, at 60 to 400 units/s; and it climbs back up. */
static void test_player_runs_down_slopes(void **state)
{
    (void)state;
    const double speeds[] = {2.5, 6.25, 10, 16.7}; /* cells/s: 60, 150, 240, 400 units/s */
    for (int kind = 22; kind <= 45; kind += 23)
        for (int dir = -1; dir <= 1; dir += 2)
            for (int si = 0; si < 4; si++) {
                nt_level *lv = wide_room("", dir > 0 ? "player 96 150\n" : "player 864 150\n");
                nt_game_def def = nt_default_game_def();
                def.player.run_speed = (nt_real)speeds[si];
                def.player.ground_accel = 100;
                nt_game *g = game_from(lv, &def);
                int foot = build_ramp(g, kind, dir);
                steps(g, 0, 40);
                assert_true(nt_game_get_state(g).on_floor); /* on the plateau */
                uint32_t key = dir > 0 ? NT_INPUT_RIGHT : NT_INPUT_LEFT;
                double foot_x = (foot + (dir > 0 ? 3 : -2)) * 24.0;
                int t = 0, airborne = 0;
                while ((dir > 0 ? (double)ppos(g).x < foot_x : (double)ppos(g).x > foot_x) && t < 400) {
                    steps(g, key, 1);
                    airborne += !nt_game_get_state(g).on_floor;
                    t++;
                }
                assert_true(t < 400);
                assert_int_equal(airborne, 0);
                assert_true((double)ppos(g).y > 250); /* down on the floor (its top: y 264) */
                /* And back up onto the plateau, on the floor all the way. */
                key = dir > 0 ? NT_INPUT_LEFT : NT_INPUT_RIGHT;
                for (t = 0; t < 600 && (double)ppos(g).y > 192 - 9; t++) {
                    steps(g, key, 1);
                    airborne += !nt_game_get_state(g).on_floor;
                }
                assert_int_equal(airborne, 0);
                assert_true((double)ppos(g).y < 192 - 9); /* on the plateau (its top: y 192) */
                nt_game_destroy(g);
                nt_level_destroy(lv);
            }
}

/* Down + jump drops through the one-way floor underfoot onto the solid floor below;
 * nothing else does (standing, jumping, down alone); a jump from below goes up
 * through it and lands on it. */
static void test_player_drops_through_one_way(void **state)
{
    (void)state;
    nt_level *lv = wide_room("", "player 200 100\n");
    nt_game *g = game_from(lv, NULL);
    nt_world *w = nt_game_get_world(g);
    for (int x = 5; x < 12; x++) {
        assert_int_equal(nt_game_set_tile(g, x, 8, NT_TILE_HALFu), NT_OK); /* top half solid: y 192..204 */
        assert_int_equal(nt_world_set_cell_flags(w, x, 8, NT_CELL_ONE_WAY), NT_OK);
    }
    steps(g, 0, 40);
    assert_true(nt_game_get_state(g).on_floor);
    assert_true(fabs((double)ppos(g).y - 182) < 0.1); /* standing on the one-way floor */
    steps(g, NT_INPUT_DOWN, 20);
    steps(g, NT_INPUT_JUMP, 1);
    steps(g, 0, 60);
    assert_true(fabs((double)ppos(g).y - 182) < 0.1);
    steps(g, NT_INPUT_JUMP, 30);
    steps(g, 0, 60);
    assert_true(fabs((double)ppos(g).y - 182) < 0.1); /* still on it */
    steps(g, NT_INPUT_DOWN | NT_INPUT_JUMP, 1);
    steps(g, 0, 60);
    assert_true(nt_game_get_state(g).on_floor);
    assert_true(fabs((double)ppos(g).y - 254) < 0.1); /* on the solid floor (top y 264) */
    /* A held jump from below rises 3.5 cells (3 are enough): up through the one-way floor, onto it. */
    for (int i = 0; i < 60; i++) steps(g, NT_INPUT_JUMP, 1);
    steps(g, 0, 40);
    assert_true(nt_game_get_state(g).on_floor);
    assert_true(fabs((double)ppos(g).y - 182) < 0.1);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

/* A launch pad: a floor tile with a material bouncier than bouncy_threshold throws
 * the landing player back up at its bounce times the landing speed; an ordinary floor
 * takes the landing in. */
static void test_player_launch_pad(void **state)
{
    (void)state;
    nt_level *lv = wide_room("material 1 0 0.8\n", "player 200 60\n");
    nt_game *g = game_from(lv, NULL);
    nt_world *w = nt_game_get_world(g);
    for (int x = 6; x < 11; x++) assert_int_equal(nt_world_set_cell_material(w, x, 11, 1), NT_OK);
    /* Falling 194 units onto the pad: about sqrt(2 g h) = 352 units/s when it lands. */
    double vy = 0, up = 0;
    for (int i = 0; i < 60; i++) {
        steps(g, 0, 1);
        double v = (double)pvel(g).y;
        if (vy > 100 && v < 0) {
            up = -v;
            break;
        }
        vy = v;
    }
    /* Thrown back at 0.8 of the landing speed, less a tick of gravity. */
    assert_true(up > 0);
    assert_true(fabs(up - 0.8 * vy) < 0.8 * 320 * (double)DT + 1);
    assert_false(nt_game_get_state(g).on_floor);
    nt_game_destroy(g);
    /* The same fall onto the ordinary floor next to it: it lands and stays. */
    nt_level_destroy(lv);
    lv = wide_room("material 1 0 0.8\n", "player 600 60\n");
    g = game_from(lv, NULL);
    steps(g, 0, 60);
    assert_true(nt_game_get_state(g).on_floor);
    assert_true(fabs((double)pvel(g).y) < 1e-6);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

/* Solid bodies (not sensors) that are static or kinematic make no contact with the
 * player (a character, kinematic to the world step): the game finds their touches
 * itself. A deadly spike of each type kills the player landing on it. (Score bodies
 * are sensors: the level format says so.) */
static void test_solid_deadly(void **state)
{
    (void)state;
    const char *types[3] = {"static", "kinematic", "dynamic"};
    for (int k = 0; k < 3; k++) {
        char extra[256];
        snprintf(extra, sizeof extra, "player 200 150\nbody spike %s box 12 5 at 200 259 deadly\n", types[k]);
        nt_level *lv = wide_room("", extra);
        nt_game *g = game_from(lv, NULL);
        steps(g, 0, 60);
        assert_false(nt_game_get_state(g).alive);
        nt_game_destroy(g);
        nt_level_destroy(lv);
    }
}

/* Standing on a launch pad is standing: on the floor every tick, and a jump from it
 * rises as high as from any floor (only impacts faster than the restitution threshold
 * bounce). */
static void test_rest_on_launch_pad(void **state)
{
    (void)state;
    nt_level *lv = wide_room("material 1 0 0.8\n", "player 200 254\n");
    nt_game *g = game_from(lv, NULL);
    nt_world *w = nt_game_get_world(g);
    for (int x = 6; x < 11; x++) assert_int_equal(nt_world_set_cell_material(w, x, 11, 1), NT_OK);
    steps(g, 0, 40); /* any first hop dies out */
    int on = 0;
    for (int i = 0; i < 100; i++) {
        steps(g, 0, 1);
        on += nt_game_get_state(g).on_floor;
    }
    assert_int_equal(on, 100);
    double y0 = (double)ppos(g).y, top = y0;
    for (int i = 0; i < 80; i++) {
        steps(g, NT_INPUT_JUMP, 1);
        top = fmin(top, (double)ppos(g).y);
    }
    double v0 = (double)nt_default_player_def().jump_speed * 24;
    double want = v0 * v0 / (2 * 320 * (double)nt_default_player_def().jump_gravity_scale);
    assert_true(fabs((y0 - top) - want) <= v0 * (double)DT);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

/* ---------------------------------------------------------------- level objects */

static const char objects_level[] = "ntile-level 1\nsize 20 6\ntiles\n"
                                    "|####################|\n|#..................#|\n|#..................#|\n"
                                    "|#..................#|\n|#..................#|\n|####################|\n"
                                    "player 60 110\n"
                                    "region door exit 400 72 430 120\n"
                                    "region pit kill 300 100 320 120\n"
                                    "region bin score 24 24 72 60 value 25\n"
                                    "region drain kill 432 24 456 60\n"
                                    "body coin static circle 6 at 120 110 sensor score 5\n"
                                    "body coin2 static circle 6 at 150 110 sensor score 5\n"
                                    "body ball dynamic circle 5 at 48 30\n"
                                    "body ball2 dynamic circle 5 at 444 30\n";

static void test_gold_exit_and_regions(void **state)
{
    (void)state;
    nt_level *lv = level_from(objects_level);
    /* The pit is in the way: remove it for the first run. */
    lv->regions[1].lo.y = 0;
    lv->regions[1].hi.y = 10;
    nt_game *g = game_from(lv, NULL);
    nt_world *w = nt_game_get_world(g);
    int bodies0 = nt_world_get_body_count(w);
    steps(g, 0, 2);
    /* Both balls fell into their regions at once: the bin scores 25, the drain just removes. */
    nt_game_state st = nt_game_get_state(g);
    assert_int_equal(st.score, 25);
    assert_int_equal(nt_world_get_body_count(w), bodies0 - 2);
    assert_true(nt_body_id_is_null(nt_game_find_body(g, "ball")));
    steps(g, NT_INPUT_RIGHT, 40); /* over the coins */
    st = nt_game_get_state(g);
    assert_int_equal(st.score, 35);
    assert_true(nt_body_id_is_null(nt_game_find_body(g, "coin2")));
    assert_false(st.complete);
    int t = st.tick;
    while (!nt_game_get_state(g).complete && t < 200) {
        steps(g, NT_INPUT_RIGHT, 1);
        t++;
    }
    st = nt_game_get_state(g);
    assert_true(st.complete && st.alive);
    assert_int_equal(st.complete_tick, t);
    assert_true((double)ppos(g).x >= 400);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

/* A corridor of 12 x 5 cells: floor at y 96, walls at x 24 and 264. */
#define CORRIDOR \
    "ntile-level 1\nsize 12 5\ntiles\n" \
    "|############|\n|#..........#|\n|#..........#|\n|#..........#|\n|############|\n"

/* Step with `keys` until the player's x passes `x` (from below when dir > 0, from above
 * when dir < 0) or `most` ticks went by; the ticks taken. */
static int run_until(nt_game *g, uint32_t keys, double x, int dir, int most)
{
    int n = 0;
    while (n < most && (dir > 0 ? (double)ppos(g).x < x : (double)ppos(g).x > x)) {
        steps(g, keys, 1);
        n++;
    }
    return n;
}

/* An exit that needs its switch completes nothing until the switch is on; the same
 * exit without the switch completes at the first pass. */
static void test_exit_switch(void **state)
{
    (void)state;
    static const char with[] = CORRIDOR "player 40 86\nregion sw switch 200 24 230 96\n"
                                        "region door exit 90 24 110 96 needs sw\n";
    static const char without[] = CORRIDOR "player 40 86\nregion sw switch 200 24 230 96\nregion door exit 90 24 110 96\n";
    nt_level *lv = level_from(without);
    nt_game *g = game_from(lv, NULL);
    run_until(g, NT_INPUT_RIGHT, 150, 1, 200);
    assert_true(nt_game_get_state(g).complete); /* the control: an exit without a switch */
    nt_game_destroy(g);
    nt_level_destroy(lv);

    lv = level_from(with);
    assert_int_equal(lv->regions[1].needs, 1);
    g = game_from(lv, NULL);
    assert_false(nt_game_switch_is_on(g, 0));
    assert_true(run_until(g, NT_INPUT_RIGHT, 150, 1, 200) < 200);
    assert_false(nt_game_get_state(g).complete); /* through the exit: closed */
    assert_true(run_until(g, NT_INPUT_RIGHT, 215, 1, 200) < 200);
    assert_true(nt_game_switch_is_on(g, 0));
    assert_false(nt_game_switch_is_on(g, 1)); /* an exit is no switch */
    assert_false(nt_game_get_state(g).complete);
    assert_true(run_until(g, NT_INPUT_LEFT, 100, -1, 200) < 200);
    nt_game_state st = nt_game_get_state(g);
    assert_true(st.complete && st.alive);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

/* Doors: a locked door holds the player until its switch is on, then is gone; a trap
 * door lets the player through and closes behind it when its switch goes on; a plain
 * door opens at the player's touch. */
static void test_doors(void **state)
{
    (void)state;
    static const char locked[] = CORRIDOR "player 100 86\nregion sw switch 24 24 48 96\n"
                                          "body gate static box 3 36 at 150 60 opened-by sw\n";
    nt_level *lv = level_from(locked);
    nt_game *g = game_from(lv, NULL);
    steps(g, NT_INPUT_RIGHT, 60);
    assert_true((double)ppos(g).x < 150 - 3 - 9); /* held by the door */
    assert_false(nt_body_id_is_null(nt_game_find_body(g, "gate")));
    assert_true(run_until(g, NT_INPUT_LEFT, 45, -1, 200) < 200);
    assert_true(nt_game_switch_is_on(g, 0));
    assert_true(nt_body_id_is_null(nt_game_find_body(g, "gate"))); /* opened */
    assert_true(run_until(g, NT_INPUT_RIGHT, 200, 1, 200) < 200);
    nt_game_destroy(g);
    nt_level_destroy(lv);

    static const char trap[] = CORRIDOR "player 40 86\nregion sw switch 200 24 230 96\n"
                                        "body gate static box 3 36 at 150 60 closed-by sw\n";
    lv = level_from(trap);
    g = game_from(lv, NULL);
    nt_world *w = nt_game_get_world(g);
    nt_body_id gate = nt_game_find_body(g, "gate");
    assert_int_equal(nt_body_get_mask(w, gate), 0); /* open: it collides with nothing */
    assert_true(run_until(g, NT_INPUT_RIGHT, 215, 1, 200) < 200); /* through the open door, onto the switch */
    assert_true(nt_game_switch_is_on(g, 0));
    assert_int_equal(nt_body_get_category(w, gate), 1);
    assert_int_equal(nt_body_get_mask(w, gate), 0xffffffffu);
    steps(g, NT_INPUT_LEFT, 80);
    assert_true((double)ppos(g).x > 150 + 3 + 9); /* shut in */
    nt_game_destroy(g);
    nt_level_destroy(lv);

    static const char plain[] = CORRIDOR "player 40 86\nbody gate static box 3 36 at 150 60 door\n";
    lv = level_from(plain);
    g = game_from(lv, NULL);
    assert_true(run_until(g, NT_INPUT_RIGHT, 200, 1, 200) < 200);
    assert_true(nt_body_id_is_null(nt_game_find_body(g, "gate")));
    nt_game_destroy(g);
    nt_level_destroy(lv);

    /* Without the door the level plays the same up to the door: the door is what held the player. */
    static const char open[] = CORRIDOR "player 100 86\nregion sw switch 24 24 48 96\n";
    lv = level_from(open);
    g = game_from(lv, NULL);
    steps(g, NT_INPUT_RIGHT, 60);
    assert_true((double)ppos(g).x > 200);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

/* One-way bodies of the game layer facing right and left: passable from behind, solid
 * to a player wholly on the side they face. */
static void test_one_way_sides(void **state)
{
    (void)state;
    static const char right[] = CORRIDOR "player 40 86\nbody w static box 6 36 at 150 60 one-way right\n";
    nt_level *lv = level_from(right);
    nt_game *g = game_from(lv, NULL);
    assert_true(run_until(g, NT_INPUT_RIGHT, 200, 1, 200) < 200); /* through it from behind */
    steps(g, NT_INPUT_LEFT, 80);
    assert_true((double)ppos(g).x >= 156 + 10 - 0.5); /* stopped on its face */
    assert_true((double)ppos(g).x < 175);
    nt_game_destroy(g);
    nt_level_destroy(lv);

    static const char left[] = CORRIDOR "player 40 86\nbody w static box 6 36 at 150 60 one-way left\n";
    lv = level_from(left);
    g = game_from(lv, NULL);
    steps(g, NT_INPUT_RIGHT, 80);
    assert_true((double)ppos(g).x <= 144 - 10 + 0.5); /* stopped on its face */
    assert_true((double)ppos(g).x > 120);
    nt_game_destroy(g);
    nt_level_destroy(lv);
    /* From the other side the left-facing one lets the player through. */
    static const char left2[] = CORRIDOR "player 230 86\nbody w static box 6 36 at 150 60 one-way left\n";
    lv = level_from(left2);
    g = game_from(lv, NULL);
    assert_true(run_until(g, NT_INPUT_LEFT, 100, -1, 200) < 200);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

/* Bodies and tiles changed through the game: added bodies count as the game's, bad
 * input changes nothing, the player cannot be removed, tile edits act at once. */
static void test_changes_through_the_game(void **state)
{
    (void)state;
    nt_level *lv = level_from(objects_level);
    lv->regions[1].lo.y = 0; /* no pit */
    lv->regions[1].hi.y = 10;
    nt_game *g = game_from(lv, NULL);
    nt_world *w = nt_game_get_world(g);
    steps(g, 0, 2); /* the level's balls fall into the bin and the drain */
    assert_int_equal(nt_game_get_state(g).score, 25);
    int n0 = nt_game_get_bodies(g, NULL, 0), w0 = nt_world_get_body_count(w);
    uint64_t h0 = nt_game_hash(g);

    nt_body_def d = nt_default_body_def();
    d.shape = nt_shape_circle(5);
    d.position = nt_v2(R(NAN), 30);
    nt_body_id id = nt_game_get_player(g);
    assert_int_equal(nt_game_add_body(g, &d, &id), NT_ERR_NON_FINITE);
    assert_true(nt_body_id_is_null(id));
    assert_int_equal(nt_game_add_body(g, NULL, &id), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_game_add_body(NULL, &d, &id), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_game_get_bodies(g, NULL, 0), n0);
    assert_int_equal(nt_world_get_body_count(w), w0);
    assert_true(nt_game_hash(g) == h0);

    /* An added ball dropped into the bin scores like the level's balls. */
    d.position = nt_v2(48, 30);
    assert_int_equal(nt_game_add_body(g, &d, &id), NT_OK);
    assert_true(nt_body_is_valid(w, id));
    assert_int_equal(nt_world_get_body_count(w), w0 + 1);
    nt_body_id all[64];
    int n = nt_game_get_bodies(g, all, 64);
    assert_int_equal(n, n0 + 1);
    assert_true(nt_body_id_equals(all[n - 1], id)); /* creation order */
    steps(g, 0, 1);
    assert_int_equal(nt_game_get_state(g).score, 50);
    assert_false(nt_body_is_valid(w, id));
    assert_int_equal(nt_game_get_bodies(g, NULL, 0), n0);
    assert_int_equal(nt_game_remove_body(g, id), NT_ERR_INVALID_ID);

    /* Removing: a level body once, not twice; never the player; never a body the game
     * did not make. */
    nt_body_id coin = nt_game_find_body(g, "coin");
    assert_false(nt_body_id_is_null(coin));
    assert_int_equal(nt_game_remove_body(g, coin), NT_OK);
    assert_false(nt_body_is_valid(w, coin));
    assert_true(nt_body_id_is_null(nt_game_find_body(g, "coin")));
    assert_int_equal(nt_game_get_bodies(g, NULL, 0), n0 - 1);
    assert_int_equal(nt_game_remove_body(g, coin), NT_ERR_INVALID_ID);
    assert_int_equal(nt_game_remove_body(g, nt_game_get_player(g)), NT_ERR_INVALID_ARGUMENT);
    assert_true(nt_body_is_valid(w, nt_game_get_player(g)));
    nt_body_id foreign;
    assert_int_equal(nt_body_create(w, &d, &foreign), NT_OK);
    assert_int_equal(nt_game_remove_body(g, foreign), NT_ERR_INVALID_ID);
    assert_true(nt_body_is_valid(w, foreign));
    assert_int_equal(nt_game_remove_body(NULL, coin), NT_ERR_INVALID_ARGUMENT);

    /* Tiles: bad cells and tiles are refused and change nothing; opening the floor
     * cell under the player lets it fall into the hole. */
    const nt_map *m = nt_world_get_map(w);
    assert_int_equal(nt_map_get_tile(m, 2, 5), NT_TILE_FULL);
    assert_int_not_equal(nt_game_set_tile(g, 2, 5, NT_TILE_COUNT), NT_OK);
    assert_int_not_equal(nt_game_set_tile(g, -1, 5, NT_TILE_EMPTY), NT_OK);
    assert_int_not_equal(nt_game_set_tile(g, 20, 5, NT_TILE_EMPTY), NT_OK);
    assert_int_equal(nt_game_set_tile(NULL, 2, 5, NT_TILE_EMPTY), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_map_get_tile(m, 2, 5), NT_TILE_FULL);
    nt_body_set_position(w, nt_game_get_player(g), nt_v2(60, 110));
    nt_body_set_velocity(w, nt_game_get_player(g), nt_v2(0, 0));
    steps(g, 0, 10);
    assert_true(fabs((double)ppos(g).y - 110) < 0.1); /* standing on the floor */
    assert_int_equal(nt_game_set_tile(g, 2, 5, NT_TILE_EMPTY), NT_OK);
    assert_int_equal(nt_map_get_tile(m, 2, 5), NT_TILE_EMPTY);
    steps(g, 0, 20);
    assert_true((double)ppos(g).y > 125); /* in the hole, below the floor's top (y 120) */
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

static void test_death(void **state)
{
    (void)state;
    nt_level *lv = level_from(objects_level);
    nt_game *g = game_from(lv, NULL);
    int t = 0;
    while (nt_game_get_state(g).alive && t < 200) {
        steps(g, NT_INPUT_RIGHT, 1);
        t++;
    }
    nt_game_state st = nt_game_get_state(g);
    assert_false(st.alive);
    assert_int_equal(st.death_tick, t);
    assert_true((double)ppos(g).x >= 300 && (double)ppos(g).x <= 320); /* in the pit region */
    /* A dead player is not controlled: pressing left does not turn it round, it
     * slows down at the ground deceleration (not the skid's) and comes to rest. */
    double vx = (double)pvel(g).x;
    assert_true(vx > 0);
    steps(g, NT_INPUT_LEFT, 1);
    double decel = (double)nt_default_player_def().ground_decel * 24;
    assert_true(fabs((double)pvel(g).x - fmax(vx - decel * (double)DT, 0)) < 1e-3);
    steps(g, NT_INPUT_LEFT | NT_INPUT_JUMP, 40);
    assert_true((double)pvel(g).x == 0 && (double)pvel(g).y == 0);
    nt_vec2 rest = ppos(g);
    /* Nor does it finish the level by drifting into the exit. */
    steps(g, NT_INPUT_RIGHT, 100);
    assert_false(nt_game_get_state(g).complete);
    assert_true(ppos(g).x == rest.x && ppos(g).y == rest.y); /* at rest, whatever the keys */
    nt_game_destroy(g);
    nt_level_destroy(lv);
    /* A deadly body kills on touch. */
    lv = level_from("ntile-level 1\nsize 8 4\ntiles\n|########|\n|#......#|\n|#......#|\n|########|\n"
                    "player 40 60\nbody mine static circle 4 at 110 68 sensor deadly\n");
    g = game_from(lv, NULL);
    steps(g, NT_INPUT_RIGHT, 40);
    assert_false(nt_game_get_state(g).alive);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

static const char spawn_level[] = "ntile-level 1\nsize 12 8\ngravity 0 0\ntiles\n"
                                  "|############|\n|#..........#|\n|#..........#|\n|#..........#|\n|#..........#|\n"
                                  "|#..........#|\n|#..........#|\n|############|\n"
                                  "path rail loop speed 30 points 60 40 200 40\n"
                                  "body cart kinematic box 8 4 at 60 40 path rail\n"
                                  "body drop dynamic circle 3 at 100 100 template\n"
                                  "spawner clock drop every 7 start 3 limit 4 offset 10 0\n"
                                  "spawner button drop action limit 3 attach cart offset 0 12 jitter 20\n";

static void test_spawners(void **state)
{
    (void)state;
    nt_level *lv = level_from(spawn_level);
    nt_game *g = game_from(lv, NULL);
    nt_world *w = nt_game_get_world(g);
    int base = nt_world_get_body_count(w);
    /* Every 7 ticks from tick 3, at most 4: ticks 3, 10, 17, 24. */
    int expect_at[30];
    for (int t = 1; t < 30; t++) expect_at[t] = t < 3 ? 0 : ((t - 3) / 7 + 1 > 4 ? 4 : (t - 3) / 7 + 1);
    for (int t = 1; t < 30; t++) {
        steps(g, 0, 1);
        assert_int_equal(nt_game_get_state(g).spawned, expect_at[t]);
        if (t == 3) {
            /* At the template's place + offset: (110, 100); nothing moves it (no gravity). */
            nt_body_id all[8];
            int k = nt_game_get_bodies(g, all, 8);
            nt_vec2 p = nt_body_get_position(w, all[k - 1]);
            assert_true(p.x == 110 && p.y == 100);
        }
    }
    /* The action spawner fires on presses, not while the key is held. */
    steps(g, NT_INPUT_ACTION, 10);
    assert_int_equal(nt_game_get_state(g).spawned, 5);
    nt_body_id ids[64];
    int n = nt_game_get_bodies(g, ids, 64);
    assert_int_equal(n, base + 5);
    nt_body_id last = ids[n - 1];
    /* Spawned from the cart: 12 below it, same x as the cart was at that tick. */
    nt_vec2 lp = nt_body_get_position(w, last), lv_ = nt_body_get_velocity(w, last);
    nt_vec2 cart = nt_body_get_position(w, nt_game_find_body(g, "cart"));
    assert_true(fabs((double)lv_.x) <= 20);
    assert_true(fabs((double)lp.y - ((double)cart.y + 12)) < 1e-3); /* no gravity here */
    for (int i = 0; i < 4; i++) {
        steps(g, 0, 1);
        steps(g, NT_INPUT_ACTION, 1);
    }
    assert_int_equal(nt_game_get_state(g).spawned, 4 + 3); /* the button's limit is 3 */
    assert_int_equal(nt_world_get_body_count(w), base + 7);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

static void test_jitter_follows_the_seed(void **state)
{
    (void)state;
    nt_level *lv = level_from(spawn_level);
    double vx[3][3];
    for (int run = 0; run < 3; run++) {
        nt_game_def def = nt_default_game_def();
        def.override_seed = true;
        def.seed = run == 2 ? 8 : 7;
        nt_game *g = game_from(lv, &def);
        for (int k = 0; k < 3; k++) {
            steps(g, NT_INPUT_ACTION, 1);
            steps(g, 0, 1);
            nt_body_id ids[64];
            int n = nt_game_get_bodies(g, ids, 64);
            vx[run][k] = (double)nt_body_get_velocity(nt_game_get_world(g), ids[n - 1]).x;
        }
        nt_game_destroy(g);
    }
    for (int k = 0; k < 3; k++) {
        assert_true(vx[0][k] == vx[1][k]);
        assert_true(fabs(vx[0][k]) <= 20);
    }
    assert_true(vx[0][0] != vx[2][0] || vx[0][1] != vx[2][1]);
    nt_level_destroy(lv);
}

/* ---------------------------------------------------------------- paths */

static void test_path_positions(void **state)
{
    (void)state;
    nt_level_path p;
    memset(&p, 0, sizeof p);
    p.mode = NT_PATH_LOOP;
    p.speed = 10;
    p.point_count = 4;
    p.points[0] = nt_v2(0, 0);
    p.points[1] = nt_v2(10, 0);
    p.points[2] = nt_v2(10, 10);
    p.points[3] = nt_v2(0, 10);
    nt_vec2 q = nt_path_position(&p, 1.5, 0); /* 15 along: (10, 5) */
    assert_true(q.x == 10 && q.y == 5);
    q = nt_path_position(&p, 4.25, 0); /* 42.5 = one lap + 2.5 */
    assert_true(q.x == R(2.5) && q.y == 0);
    q = nt_path_position(&p, 0, 0.5); /* half a lap: (10, 10) */
    assert_true(q.x == 10 && q.y == 10);
    p.mode = NT_PATH_PINGPONG;
    p.point_count = 2;
    p.wait = 1;
    /* wait 1 at p0, 1 s to p1, wait 1, 1 s back: a 4 s cycle */
    q = nt_path_position(&p, 0.5, 0);
    assert_true(q.x == 0);
    q = nt_path_position(&p, 1.5, 0);
    assert_true(q.x == 5);
    q = nt_path_position(&p, 2.5, 0);
    assert_true(q.x == 10);
    q = nt_path_position(&p, 3.75, 0);
    assert_true(q.x == R(2.5));
    q = nt_path_position(&p, 4.5, 0);
    assert_true(q.x == 0);
    p.mode = NT_PATH_ORBIT;
    p.wait = 0;
    p.center = nt_v2(5, 5);
    p.radius = 2;
    p.speed = R(3.14159265358979); /* a quarter turn (pi units at radius 2) a second */
    q = nt_path_position(&p, 1, 0);
    assert_true(fabs((double)q.x - 5) < 1e-5 && fabs((double)q.y - 7) < 1e-5); /* clockwise on screen: down */
    q = nt_path_position(&p, 0, 0.5);
    assert_true(fabs((double)q.x - 3) < 1e-5 && fabs((double)q.y - 5) < 1e-5);
}

static void test_kinematic_follows_path_without_drift(void **state)
{
    (void)state;
    nt_level *lv = level_from("ntile-level 1\nsize 20 20\ngravity 0 0\ntiles\n"
                              "|....................|\n|....................|\n|....................|\n|....................|\n"
                              "|....................|\n|....................|\n|....................|\n|....................|\n"
                              "|....................|\n|....................|\n|....................|\n|....................|\n"
                              "|....................|\n|....................|\n|....................|\n|....................|\n"
                              "|....................|\n|....................|\n|....................|\n|....................|\n"
                              "path spin orbit speed 77 center 240 240 radius 100\n"
                              "path tri loop speed 123 wait 0.3 points 30 30 400 60 200 300\n"
                              "body a kinematic box 6 6 at 0 0 path spin phase 0.3\n"
                              "body b kinematic circle 6 at 0 0 path tri phase 0.7\n");
    nt_game *g = game_from(lv, NULL);
    nt_world *w = nt_game_get_world(g);
    for (int t = 1; t <= 2000; t++) {
        steps(g, 0, 1);
        if (t % 250) continue;
        double time = t * (double)DT;
        for (int k = 0; k < 2; k++) {
            nt_vec2 want = nt_path_position(&lv->paths[k], time, (double)lv->bodies[k].phase);
            nt_vec2 got = nt_body_get_position(w, nt_game_find_body(g, k ? "b" : "a"));
            assert_true(fabs((double)got.x - (double)want.x) < 1e-2 && fabs((double)got.y - (double)want.y) < 1e-2);
        }
    }
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

/* ---------------------------------------------------------------- determinism */

static void test_hash_is_deterministic(void **state)
{
    (void)state;
    nt_level *lv = level_from(objects_level);
    nt_game *a = game_from(lv, NULL), *b = game_from(lv, NULL), *c = game_from(lv, NULL);
    assert_true(nt_game_hash(a) == nt_game_hash(b));
    int differ = 0;
    for (int t = 0; t < 100; t++) {
        uint32_t keys = (t / 10) % 2 ? NT_INPUT_RIGHT : NT_INPUT_JUMP;
        steps(a, keys, 1);
        steps(b, keys, 1);
        steps(c, t == 50 ? NT_INPUT_LEFT : keys, 1);
        assert_true(nt_game_hash(a) == nt_game_hash(b));
        if (t >= 50) differ += nt_game_hash(a) != nt_game_hash(c);
    }
    assert_int_equal(differ, 50); /* one different input changes every later state */
    nt_game_destroy(a);
    nt_game_destroy(b);
    nt_game_destroy(c);
    nt_level_destroy(lv);
}

/* ---------------------------------------------------------------- the runner */

static nt_replay *replay_from(const char *text)
{
    nt_replay *rp = NULL;
    nt_text_error e;
    nt_status s = nt_replay_parse("r.ntr", text, strlen(text), &rp, &e);
    if (s != NT_OK) fprintf(stderr, "%s\n", e.message);
    assert_int_equal(s, NT_OK);
    return rp;
}

static void test_runner_facts(void **state)
{
    (void)state;
    nt_level *lv = level_from(objects_level);
    lv->regions[1].lo.y = 0; /* no pit */
    lv->regions[1].hi.y = 10;
    nt_replay *rp = replay_from("ntile-replay 1\nlevel x\nticks 120\ninput 120R\n"
                                "expect complete by 110\nexpect score >= 35 at 120\nexpect alive always\n"
                                "expect inside door by 120\nexpect bodies == 1 at 120\nexpect no-body-in-solid always\n"
                                "expect not complete at 10\n");
    nt_run_report rep;
    assert_int_equal(nt_run_replay(rp, lv, &rep), NT_OK);
    for (int i = 0; i < rep.message_count; i++) fprintf(stderr, "%s\n", rep.messages[i]);
    assert_true(rep.passed);
    assert_int_equal(rep.ticks, 120);
    assert_true(rep.final_state.complete);
    nt_run_report_free(&rep);
    nt_replay_destroy(rp);
    /* The same run against facts that do not hold: each says why. */
    rp = replay_from("ntile-replay 1\nlevel x\nticks 120\ninput 120R\n"
                     "expect complete by 5\nexpect score >= 36 at 120\nexpect not alive by 120\n"
                     "expect inside nowhere at 3\nexpect inside door body ghost at 3\nexpect energy-ratio <= 1 at 10\n");
    assert_int_equal(nt_run_replay(rp, lv, &rep), NT_OK);
    assert_false(rep.passed);
    assert_int_equal(rep.fact_failures, 6);
    assert_int_equal(rep.hash_failures, 0);
    const char *want[6] = {
        "line 8: expect inside nowhere at 3: the level has no region 'nowhere'",
        "line 9: expect inside door body ghost at 3: the level has no body 'ghost'",
        "line 5: expect complete by 5: never true in ticks 0..5 (at tick 5: not complete)",
        "line 10: expect energy-ratio <= 1 at 10: cannot be checked at tick 10: the kinetic energy at tick 0 is zero",
        "line 6: expect score >= 36 at 120: false at tick 120 (score is 35)",
        "line 7: expect not alive by 120: never true in ticks 0..120 (at tick 120: alive)",
    };
    assert_int_equal(rep.message_count, 6);
    for (int i = 0; i < 6; i++) assert_string_equal(rep.messages[i], want[i]);
    nt_run_report_free(&rep);
    nt_replay_destroy(rp);
    nt_level_destroy(lv);
}

static void test_runner_hashes_and_divergence(void **state)
{
    (void)state;
    nt_level *lv = level_from(objects_level);
    nt_replay *rp = replay_from("ntile-replay 1\nlevel x\nticks 80\ninput 30R 10J 40R\n");
    nt_run_report rep;
    assert_int_equal(nt_run_replay(rp, lv, &rep), NT_OK);
    assert_true(rep.passed);
    /* Record: hashes at 40 and 80, the trace of every tick. */
    uint32_t trace[80];
    for (int t = 1; t <= 80; t++) trace[t - 1] = nt_trace_fold(rep.hashes[t]);
    nt_replay_hash h[2] = {{40, false, rep.hashes[40], 0}, {80, false, rep.hashes[80], 0}};
    assert_int_equal(nt_replay_set_hashes(rp, NT_REAL_IS_DOUBLE, h, 2, trace, 80), NT_OK);
    /* The other build's hashes are ignored here. */
    nt_replay_hash other = {80, !NT_REAL_IS_DOUBLE, 0x1234, 0};
    assert_int_equal(nt_replay_set_hashes(rp, !NT_REAL_IS_DOUBLE, &other, 1, NULL, 0), NT_OK);
    nt_run_report_free(&rep);
    assert_int_equal(nt_run_replay(rp, lv, &rep), NT_OK);
    assert_true(rep.passed);
    assert_int_equal(rep.first_divergence, -1);
    nt_run_report_free(&rep);
    /* The same inputs up to tick 50, then left instead of right at tick 51: the trace
     * finds that tick. */
    nt_text_error e;
    assert_int_equal(nt_replay_set_inputs(rp, "in", "30R 10J 10R 1L 29R", 18, &e), NT_OK);
    assert_int_equal(nt_run_replay(rp, lv, &rep), NT_OK);
    assert_false(rep.passed);
    assert_int_equal(rep.first_divergence, 51);
    assert_int_equal(rep.hash_failures, 1); /* tick 40 still matches, 80 does not */
    assert_int_equal(rep.fact_failures, 0);
    char want[160];
    snprintf(want, sizeof want, "first tick that diverges: 51 (trace: expected %08lx, got %08lx)", (unsigned long)trace[50],
             (unsigned long)nt_trace_fold(rep.hashes[51]));
    assert_string_equal(rep.messages[rep.message_count - 1], want);
    assert_true(rep.message_is_hash[rep.message_count - 1]);
    nt_run_report_free(&rep);
    /* Without a trace the report brackets the divergence between checkpoints. */
    assert_int_equal(nt_replay_set_hashes(rp, NT_REAL_IS_DOUBLE, h, 2, NULL, 0), NT_OK);
    assert_int_equal(nt_run_replay(rp, lv, &rep), NT_OK);
    assert_string_equal(rep.messages[rep.message_count - 1],
                        "diverges after tick 40 and by tick 80; no trace covers it (record one with --record-hashes)");
    nt_run_report_free(&rep);
    nt_replay_destroy(rp);
    nt_level_destroy(lv);
}

/* Bodies larger than a cell (issue 18): a 1 x 2-cell crate falls to the floor, the
 * player rides a 4-cell-wide kinematic platform, and a 4 x 4-cell box added through
 * the game lands; a body above the cap is refused and changes nothing. */
static void test_large_bodies(void **state)
{
    (void)state;
    nt_level *lv = level_from(ROOM_TILES "player 250 120\n"
                              "path slide pingpong speed 20 wait 1 points 250 150 300 150\n"
                              "body crate dynamic box 12 24 at 60 150\n"
                              "body platform kinematic box 48 6 at 250 150 path slide material 0.5 0\n");
    nt_game *g = game_from(lv, NULL);
    nt_world *w = nt_game_get_world(g);
    nt_body_id crate = nt_game_find_body(g, "crate"), plat = nt_game_find_body(g, "platform");
    assert_true(nt_body_get_shape(w, crate).half.y == 24);
    assert_true(nt_body_get_shape(w, plat).half.x == 48);
    steps(g, 0, 30); /* the platform waits 1 s: the player lands on it */
    assert_true(nt_game_get_state(g).on_floor);
    double rel0 = (double)ppos(g).x - (double)nt_body_get_position(w, plat).x;
    for (int i = 0; i < 60; i++) {
        steps(g, 0, 1);
        nt_vec2 pp = nt_body_get_position(w, plat);
        assert_true(nt_game_get_state(g).on_floor);
        assert_true(fabs((double)ppos(g).y - ((double)pp.y - 6 - 10)) < 0.5); /* on its top */
        assert_true(fabs((double)ppos(g).x - (double)pp.x - rel0) < 0.5);      /* riding it */
    }
    assert_true((double)nt_body_get_position(w, plat).x > 265); /* it did move */
    /* The crate stands on the floor (top y = 216): centre 24 above it. */
    assert_true(fabs((double)nt_body_get_position(w, crate).y - 192) < 0.5);

    /* Added through the game: a 4 x 4-cell box between the crate and the platform; one
     * above the cap changes nothing. */
    nt_body_def d = nt_default_body_def();
    d.shape = nt_shape_aabb(48, 48);
    d.position = nt_v2(130, 60);
    nt_body_id big = nt_null_body_id(), id = nt_game_get_player(g);
    int n0 = nt_game_get_bodies(g, NULL, 0), w0 = nt_world_get_body_count(w);
    nt_body_def huge = d;
    huge.shape = nt_shape_circle(R(96.5)); /* above NT_MAX_HALF_CELLS (4) cells of 24 */
    assert_int_equal(nt_game_add_body(g, &huge, &id), NT_ERR_SHAPE_TOO_LARGE);
    assert_true(nt_body_id_is_null(id));
    assert_int_equal(nt_game_get_bodies(g, NULL, 0), n0);
    assert_int_equal(nt_world_get_body_count(w), w0);
    assert_int_equal(nt_game_add_body(g, &d, &big), NT_OK);
    assert_int_equal(nt_game_get_bodies(g, NULL, 0), n0 + 1);
    steps(g, 0, 80);
    nt_vec2 bp = nt_body_get_position(w, big);
    nt_game_destroy(g);
    g = NULL;
    assert_true(fabs((double)bp.y - (216 - 48)) < 0.5); /* on the floor */
    assert_true(bp.x > 100 && bp.x < 160);
    nt_level_destroy(lv);
    /* A large body on a path starts where the path puts it: it must fit the map there. */
    lv = level_from(ROOM_TILES "path out pingpong speed 20 points 30 150 300 150\n"
                               "body platform kinematic box 48 6 at 250 150 path out\n");
    assert_int_equal(nt_game_create(lv, NULL, &g), NT_ERR_OUT_OF_RANGE);
    assert_null(g);
    nt_level_destroy(lv);
}

static void test_game_errors(void **state)
{
    (void)state;
    nt_level *lv = level_from(room);
    nt_game *g = NULL;
    nt_game_def def = nt_default_game_def();
    def.player.radius = R(0.6); /* larger than half a cell: the player stays small (game.h) */
    assert_int_equal(nt_game_create(lv, &def, &g), NT_ERR_INVALID_ARGUMENT);
    assert_null(g);
    def = nt_default_game_def();
    def.player.jump_speed = R(NAN);
    assert_int_equal(nt_game_create(lv, &def, &g), NT_ERR_INVALID_ARGUMENT);
    def = nt_default_game_def();
    def.player.mover.max_slides = 0; /* the mover's settings are checked up front */
    assert_int_equal(nt_game_create(lv, &def, &g), NT_ERR_INVALID_ARGUMENT);
    def = nt_default_game_def();
    def.player.mover.floor_angle = R(2);
    assert_int_equal(nt_game_create(lv, &def, &g), NT_ERR_INVALID_ARGUMENT);
    assert_null(g);
    /* A friction-model override must suit the level's materials. */
    lv->materials[2].friction = 2;
    lv->friction_model = NT_FRICTION_COULOMB;
    def = nt_default_game_def();
    def.override_friction_model = true;
    def.friction_model = NT_FRICTION_N;
    assert_int_equal(nt_game_create(lv, &def, &g), NT_ERR_INVALID_ARGUMENT);
    lv->materials[2].friction = 1;
    assert_int_equal(nt_game_create(lv, &def, &g), NT_OK);
    assert_int_equal(nt_game_step(g, 0, 0), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_game_step(g, 0, R(INFINITY)), NT_ERR_NON_FINITE);
    nt_game_destroy(g);
    nt_level_destroy(lv);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rng),
        cmocka_unit_test(test_run_and_skid),
        cmocka_unit_test(test_jump_height),
        cmocka_unit_test(test_stand_on_slope),
        cmocka_unit_test(test_wall_slide_and_wall_jump),
        cmocka_unit_test(test_no_jump_in_the_air),
        cmocka_unit_test(test_riders_on_moving_platform),
        cmocka_unit_test(test_elevator),
        cmocka_unit_test(test_player_runs_down_slopes),
        cmocka_unit_test(test_player_drops_through_one_way),
        cmocka_unit_test(test_player_launch_pad),
        cmocka_unit_test(test_solid_deadly),
        cmocka_unit_test(test_rest_on_launch_pad),
        cmocka_unit_test(test_gold_exit_and_regions),
        cmocka_unit_test(test_changes_through_the_game),
        cmocka_unit_test(test_death),
        cmocka_unit_test(test_spawners),
        cmocka_unit_test(test_jitter_follows_the_seed),
        cmocka_unit_test(test_path_positions),
        cmocka_unit_test(test_kinematic_follows_path_without_drift),
        cmocka_unit_test(test_hash_is_deterministic),
        cmocka_unit_test(test_runner_facts),
        cmocka_unit_test(test_runner_hashes_and_divergence),
        cmocka_unit_test(test_large_bodies),
        cmocka_unit_test(test_game_errors),
        cmocka_unit_test(test_exit_switch),
        cmocka_unit_test(test_doors),
        cmocka_unit_test(test_one_way_sides),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
