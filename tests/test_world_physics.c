/* World physics against analytic answers: free fall and drag (exact discrete
 * formulas), the speed limit, momentum and energy in body collisions, bounce
 * heights on a floor, Coulomb friction on every slope of the tile set and its
 * mirror, N's terminal speed on a slope, sliding across seams and slope-to-flat
 * joins without ghost bumps, and no tunnelling through any face of any tile at the
 * speed limit. Units: cell size 1, seconds; y points down. */
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
#include "ntile/world.h"

#define R(x) ((nt_real)(x))

static const double G = 10; /* cells / s^2 */

static nt_world *make_world(int w, int h, double gravity, nt_friction_model model)
{
    nt_world_def d = nt_default_world_def();
    d.map.width = w;
    d.map.height = h;
    d.map.cell_size = 1;
    d.gravity = nt_v2(0, (nt_real)gravity);
    d.friction_model = model;
    d.tile_material.friction = 0;
    d.tile_material.bounce = 0;
    d.restitution_threshold = 0;
    d.hit_event_threshold = 0;
    d.enable_sleep = false;
    nt_world *world = NULL;
    assert_int_equal(nt_world_create(&d, &world), NT_OK);
    return world;
}

static nt_body_id add_body(nt_world *w, nt_shape s, double x, double y, double vx, double vy, double mass,
                           double friction, double bounce)
{
    nt_body_def d = nt_default_body_def();
    d.shape = s;
    d.position = nt_v2((nt_real)x, (nt_real)y);
    d.velocity = nt_v2((nt_real)vx, (nt_real)vy);
    d.mass = (nt_real)mass;
    d.material.friction = (nt_real)friction;
    d.material.bounce = (nt_real)bounce;
    nt_body_id id;
    assert_int_equal(nt_body_create(w, &d, &id), NT_OK);
    return id;
}

static void fill(nt_world *w, int x0, int y0, int x1, int y1, int tile)
{
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) assert_int_equal(nt_world_set_tile(w, x, y, tile), NT_OK);
}

static double speed(nt_vec2 v) { return sqrt((double)v.x * v.x + (double)v.y * v.y); }

/* ---------------------------------------------------------------- integration */

/* Free flight is the exact parabola: from rest, v_n = n g dt and y_n = y_0 + g (n dt)^2 / 2
 * (semi-implicit Euler would give g dt^2 n (n + 1) / 2, off by g n dt^2 / 2). */
static void test_free_fall_and_gravity_scale(void **state)
{
    (void)state;
    nt_world *w = make_world(10, 200, G, NT_FRICTION_COULOMB);
    nt_body_id a = add_body(w, nt_shape_aabb(R(0.25), R(0.25)), 3, 2, 0, 0, 1, 0, 0);
    nt_body_def d = nt_default_body_def();
    d.shape = nt_shape_circle(R(0.25));
    d.position = nt_v2(6, 2);
    d.gravity_scale = R(0.5);
    nt_body_id b;
    assert_int_equal(nt_body_create(w, &d, &b), NT_OK);
    const double dt = 1.0 / 60;
    const int n = 240;
    for (int i = 0; i < n; i++) assert_int_equal(nt_world_step(w, (nt_real)dt), NT_OK);
    double fall = G * dt * dt * n * n / 2;
    assert_true(fabs((double)nt_body_get_position(w, a).y - (2 + fall)) < 1e-5 * (2 + fall));
    assert_true(fabs((double)nt_body_get_velocity(w, a).y - n * G * dt) < 1e-5 * n * G * dt);
    assert_true(fabs((double)nt_body_get_position(w, b).y - (2 + fall / 2)) < 1e-5 * (2 + fall));
    assert_true(nt_body_get_position(w, a).x == 3); /* no sideways drift at all */
    nt_world_destroy(w);
}

/* Drag: v_n = v_0 / (1 + c dt)^n. */
static void test_linear_drag(void **state)
{
    (void)state;
    nt_world *w = make_world(400, 10, 0, NT_FRICTION_COULOMB);
    nt_body_def d = nt_default_body_def();
    d.shape = nt_shape_aabb(R(0.25), R(0.25));
    d.position = nt_v2(5, 5);
    d.velocity = nt_v2(20, 0);
    d.linear_drag = R(0.8);
    nt_body_id id;
    assert_int_equal(nt_body_create(w, &d, &id), NT_OK);
    const double dt = 1.0 / 50;
    for (int i = 0; i < 100; i++) nt_world_step(w, (nt_real)dt);
    double want = 20 / pow(1 + 0.8 * dt, 100);
    assert_true(fabs((double)nt_body_get_velocity(w, id).x - want) < 1e-5 * want);
    nt_world_destroy(w);
}

/* Faster than max_cells_per_step: clamped to exactly that many cells per step. */
static void test_speed_limit(void **state)
{
    (void)state;
    nt_world *w = make_world(100, 100, 0, NT_FRICTION_COULOMB);
    const double dt = 0.1;
    nt_body_id id = add_body(w, nt_shape_circle(R(0.3)), 10, 10, 300, 400, 1, 0, 0); /* 50 cells/step */
    nt_world_step(w, (nt_real)dt);
    nt_vec2 p = nt_body_get_position(w, id), v = nt_body_get_velocity(w, id);
    assert_true(fabs(speed(v) * dt - 4) < 1e-5);
    assert_true(fabs(((double)p.x - 10) - 4 * 0.6) < 1e-4 && fabs(((double)p.y - 10) - 4 * 0.8) < 1e-4);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- body collisions */

typedef struct pair_run {
    double p0[2], p1[2], ke0, ke1;
    double dva[2];       /* velocity change of a: along the impulse */
    double vrel0[2], vrel1[2];
} pair_run;

/* Two bodies meet in empty space; returns momenta and energies before and after. */
static pair_run collide_pair(nt_shape sa, nt_shape sb, double ma, double mb, double ya, double yb, double va,
                             double vb, double bounce)
{
    nt_world *w = make_world(60, 30, 0, NT_FRICTION_COULOMB);
    nt_body_id a = add_body(w, sa, 20, ya, va, 0, ma, 0, bounce);
    nt_body_id b = add_body(w, sb, 26, yb, vb, 0, mb, 0, bounce);
    pair_run r;
    nt_vec2 a0 = nt_body_get_velocity(w, a), b0 = nt_body_get_velocity(w, b);
    r.p0[0] = ma * a0.x + mb * b0.x;
    r.p0[1] = ma * a0.y + mb * b0.y;
    r.ke0 = 0.5 * ma * (a0.x * a0.x + a0.y * a0.y) + 0.5 * mb * (b0.x * b0.x + b0.y * b0.y);
    for (int i = 0; i < 200; i++) assert_int_equal(nt_world_step(w, R(1.0 / 60)), NT_OK);
    nt_vec2 a1 = nt_body_get_velocity(w, a), b1 = nt_body_get_velocity(w, b);
    r.p1[0] = ma * a1.x + mb * b1.x;
    r.p1[1] = ma * a1.y + mb * b1.y;
    r.ke1 = 0.5 * ma * (a1.x * a1.x + a1.y * a1.y) + 0.5 * mb * (b1.x * b1.x + b1.y * b1.y);
    r.dva[0] = a1.x - a0.x;
    r.dva[1] = a1.y - a0.y;
    r.vrel0[0] = b0.x - a0.x;
    r.vrel0[1] = b0.y - a0.y;
    r.vrel1[0] = b1.x - a1.x;
    r.vrel1[1] = b1.y - a1.y;
    /* They met. */
    assert_true(fabs(r.dva[0]) + fabs(r.dva[1]) > 0.1);
    nt_world_destroy(w);
    return r;
}

static void check_momentum(const pair_run *r, double scale)
{
    assert_true(fabs(r->p1[0] - r->p0[0]) <= 1e-5 * scale);
    assert_true(fabs(r->p1[1] - r->p0[1]) <= 1e-5 * scale);
}

/* Relative velocity along the impulse: after = -e * before; across it: unchanged. */
static void check_restitution(const pair_run *r, double e)
{
    double len = sqrt(r->dva[0] * r->dva[0] + r->dva[1] * r->dva[1]);
    double n[2] = {-r->dva[0] / len, -r->dva[1] / len}; /* a was pushed along -n */
    double vn0 = r->vrel0[0] * n[0] + r->vrel0[1] * n[1], vn1 = r->vrel1[0] * n[0] + r->vrel1[1] * n[1];
    double vt0 = -r->vrel0[0] * n[1] + r->vrel0[1] * n[0], vt1 = -r->vrel1[0] * n[1] + r->vrel1[1] * n[0];
    assert_true(vn0 < 0);
    if (!(fabs(vn1 + e * vn0) <= 1e-5 * fabs(vn0))) fail_msg("e %g vn0 %.9f vn1 %.9f", e, vn0, vn1);
    assert_true(fabs(vt1 - vt0) <= 1e-5 * fabs(vn0));
}

static void test_momentum_head_on(void **state)
{
    (void)state;
    const double ma = 1, mb = 3.5, va = 4, vb = -1.5;
    double scale = ma * fabs(va) + mb * fabs(vb);
    nt_shape shapes[2] = {nt_shape_aabb(R(0.3), R(0.4)), nt_shape_circle(R(0.35))};
    for (int s = 0; s < 4; s++) {
        nt_shape sa = shapes[s & 1], sb = shapes[s >> 1];
        for (int k = 0; k < 3; k++) {
            double e = k * 0.5;
            pair_run r = collide_pair(sa, sb, ma, mb, 10, 10, va, vb, e);
            check_momentum(&r, scale);
            check_restitution(&r, e);
            if (k == 2) assert_true(fabs(r.ke1 - r.ke0) <= 1e-5 * r.ke0);
            /* Head on: everything stays on the x axis. */
            assert_true(fabs(r.p1[1]) < 1e-6 * scale);
        }
    }
}

static void test_momentum_angled(void **state)
{
    (void)state;
    const double ma = 2, mb = 0.7, va = 3, vb = -2;
    double scale = ma * fabs(va) + mb * fabs(vb);
    double offsets[3] = {0.2, 0.45, -0.55};
    for (int o = 0; o < 3; o++)
        for (int k = 0; k < 3; k++) {
            double e = k * 0.5;
            /* Circles: the normal is the line of centres, at an angle. */
            pair_run r = collide_pair(nt_shape_circle(R(0.4)), nt_shape_circle(R(0.3)), ma, mb, 10, 10 + offsets[o], va,
                                      vb, e);
            check_momentum(&r, scale);
            check_restitution(&r, e);
            assert_true(fabs(r.dva[1]) > 1e-3); /* really angled */
            if (k == 2) assert_true(fabs(r.ke1 - r.ke0) <= 1e-5 * r.ke0);
            /* Box against circle, hitting near the box's corner. */
            r = collide_pair(nt_shape_aabb(R(0.3), R(0.3)), nt_shape_circle(R(0.3)), ma, mb, 10, 10 + offsets[o], va, vb,
                             e);
            check_momentum(&r, scale);
            check_restitution(&r, e);
            if (k == 2) assert_true(fabs(r.ke1 - r.ke0) <= 1e-5 * r.ke0);
        }
}

/* ---------------------------------------------------------------- bounce heights */

/* A ball dropped from h0 = 10 cells (g = 10 cells/s^2) on a floor rises to
 * h_n = e^(2n) h0: free flight is the exact parabola and the bounce happens at the
 * time of impact, so all five bounces are within 1% at game step lengths (1/60 and
 * 1/40 s) as well as at 1 ms. */
static void run_bounces(nt_friction_model model, double e, nt_shape shape, double dt)
{
    nt_world *w = make_world(8, 20, G, model);
    fill(w, 0, 19, 7, 19, NT_TILE_FULL);
    const double h0 = 10, half = (double)shape.half.y, floor_y = 19;
    nt_body_id id = add_body(w, shape, 4.5, floor_y - half - h0, 0, 0, 1, 0, e);
    double top = 1e9, prev_vy = 0;
    int n = 0;
    for (int i = 0; i < 100000 && n <= 5; i++) {
        assert_int_equal(nt_world_step(w, (nt_real)dt), NT_OK);
        nt_vec2 p = nt_body_get_position(w, id), v = nt_body_get_velocity(w, id);
        if (p.y < top) top = p.y;
        if (prev_vy < 0 && v.y >= 0) { /* apex */
            double h = floor_y - half - top, want = h0 * pow(e, 2 * n);
            if (fabs(h - want) > 0.01 * want) printf("bounce %d: h %g want %g\n", n, h, want);
            assert_true(fabs(h - want) <= 0.01 * want);
            n++;
            top = 1e9;
        }
        prev_vy = v.y;
    }
    assert_int_equal(n, 6); /* h0 and 5 bounces */
    nt_world_destroy(w);
}

static void test_bounce_heights(void **state)
{
    (void)state;
    run_bounces(NT_FRICTION_COULOMB, 0.9, nt_shape_circle(R(0.25)), 0.001);
    run_bounces(NT_FRICTION_N, 0.8, nt_shape_aabb(R(0.3), R(0.2)), 0.0005);
    run_bounces(NT_FRICTION_COULOMB, 0.9, nt_shape_circle(R(0.25)), 1.0 / 60);
    run_bounces(NT_FRICTION_N, 0.8, nt_shape_aabb(R(0.3), R(0.2)), 1.0 / 40);
}

/* Bounce 1 keeps the energy: a ball dropped from 10 cells comes back to 10 cells,
 * within 0.2 %, at every one of 30 bounces (dt 1/40 s). */
static void test_elastic_bounce_keeps_energy(void **state)
{
    (void)state;
    nt_world *w = make_world(8, 20, G, NT_FRICTION_COULOMB);
    fill(w, 0, 19, 7, 19, NT_TILE_FULL);
    const double h0 = 10, floor_y = 19;
    nt_body_id id = add_body(w, nt_shape_circle(R(0.25)), 4.5, floor_y - 0.25 - h0, 0, 0, 1, 0, 1);
    double top = 1e9, prev_vy = 0, worst = 0;
    int n = 0;
    for (int i = 0; i < 100000 && n < 30; i++) {
        assert_int_equal(nt_world_step(w, R(1.0 / 40)), NT_OK);
        nt_vec2 p = nt_body_get_position(w, id), v = nt_body_get_velocity(w, id);
        if (p.y < top) top = p.y;
        if (prev_vy < 0 && v.y >= 0) {
            worst = fmax(worst, fabs(floor_y - 0.25 - top - h0) / h0);
            n++;
            top = 1e9;
        }
        prev_vy = v.y;
    }
    assert_int_equal(n, 30);
    assert_true(worst < 2e-3);
    nt_world_destroy(w);
}

/* A gas of bounce-1 bodies (boxes and circles of unequal masses, no friction, no
 * gravity) in a closed room with bounce-1 walls: every collision, body-body or
 * body-wall, is elastic, so the kinetic energy stays what the bodies were created
 * with (sum of m v^2 / 2 over their definitions) at every step, within 1e-4, through
 * hundreds of collisions, many of them with several bodies at once (dt 1/40 s). */
static void test_elastic_gas_keeps_energy(void **state)
{
    (void)state;
    enum { W = 24, N = 160, STEPS = 400 };
    nt_world *w = make_world(W, W, 0, NT_FRICTION_COULOMB);
    nt_material wall = {0, 1};
    assert_int_equal(nt_world_set_material(w, 0, wall), NT_OK);
    fill(w, 0, 0, W - 1, 0, NT_TILE_FULL);
    fill(w, 0, W - 1, W - 1, W - 1, NT_TILE_FULL);
    fill(w, 0, 1, 0, W - 2, NT_TILE_FULL);
    fill(w, W - 1, 1, W - 1, W - 2, NT_TILE_FULL);
    nt_body_id ids[N];
    uint64_t rng = 0x9e3779b97f4a7c15ull;
    double e0 = 0;
    for (int i = 0; i < N; i++) {
        double u[4];
        for (int k = 0; k < 4; k++) {
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            u[k] = (double)(rng >> 11) / 9007199254740992.0;
        }
        double half = 0.2 + 0.15 * u[0], mass = 0.5 + 1.5 * u[1], sp = 2 + 4 * u[2], a = 6.283185307179586 * u[3];
        nt_shape s = i & 1 ? nt_shape_circle(R(half)) : nt_shape_aabb(R(half), R(half));
        double x = 2 + (i % 16) * 1.3, y = 2 + (i / 16) * 2.0;
        ids[i] = add_body(w, s, x, y, sp * cos(a), sp * sin(a), mass, 0, 1);
        nt_vec2 v = nt_body_get_velocity(w, ids[i]); /* as the world holds it */
        e0 += 0.5 * mass * ((double)v.x * v.x + (double)v.y * v.y);
    }
    double worst = 0;
    for (int t = 0; t < STEPS; t++) {
        assert_int_equal(nt_world_step(w, R(1.0 / 40)), NT_OK);
        double e = 0;
        for (int i = 0; i < N; i++) {
            nt_vec2 v = nt_body_get_velocity(w, ids[i]);
            e += 0.5 * (double)nt_body_get_mass(w, ids[i]) * ((double)v.x * v.x + (double)v.y * v.y);
        }
        worst = fmax(worst, fabs(e - e0) / e0);
    }
    if (!(worst <= 1e-4)) fail_msg("kinetic energy drifted by %g of its start", worst);
    nt_world_destroy(w);
}

/* Newton's cradle: a ball rolling (no gravity, bounce 1) into a row of three equal
 * balls at rest, a hair apart, leaves the first two at rest and the last one moving
 * off at its speed. */
static void test_newtons_cradle(void **state)
{
    (void)state;
    nt_world *w = make_world(40, 8, 0, NT_FRICTION_COULOMB);
    const double r = 0.4, v0 = 3, gap = 0.01;
    nt_body_id ball = add_body(w, nt_shape_circle(R(r)), 5, 4, v0, 0, 1, 0, 1), row[3];
    for (int k = 0; k < 3; k++) row[k] = add_body(w, nt_shape_circle(R(r)), 10 + k * (2 * r + gap), 4, 0, 0, 1, 0, 1);
    for (int t = 0; t < 80; t++) assert_int_equal(nt_world_step(w, R(1.0 / 40)), NT_OK);
    nt_vec2 v[4] = {nt_body_get_velocity(w, ball), nt_body_get_velocity(w, row[0]), nt_body_get_velocity(w, row[1]),
                    nt_body_get_velocity(w, row[2])};
    for (int k = 0; k < 3; k++)
        if (!(speed(v[k]) <= 1e-4 * v0)) fail_msg("ball %d still moves at %g", k, speed(v[k]));
    if (!(fabs((double)v[3].x - v0) <= 1e-4 * v0 && fabs((double)v[3].y) <= 1e-4 * v0))
        fail_msg("last ball leaves at (%g, %g), want (%g, 0)", (double)v[3].x, (double)v[3].y, v0);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- slopes */

enum { S22 = 0, S45 = 1, S67 = 2 };

/* A straight slope from column 0 going down to the right (mirror: to the left),
 * everything under it FULL. Returns tan(theta). The surface passes through
 * (0, 2) and falls 1 cell every `run` cells. */
static double build_slope(nt_world *w, int W, int H, int kind, int mirror)
{
    for (int x = 0; x < W; x++) {
        int mx = mirror ? W - 1 - x : x;
        int t0 = -1, t1 = -1, y0 = 0;
        if (kind == S45) {
            y0 = 2 + x;
            t0 = mirror ? NT_TILE_45DEGnn : NT_TILE_45DEGpn;
        } else if (kind == S22) {
            y0 = 2 + x / 2;
            t0 = (x % 2 == 0) ? (mirror ? NT_TILE_22DEGnnB : NT_TILE_22DEGpnB) : (mirror ? NT_TILE_22DEGnnS : NT_TILE_22DEGpnS);
        } else {
            y0 = 2 + 2 * x;
            t0 = mirror ? NT_TILE_67DEGnnS : NT_TILE_67DEGpnS;
            t1 = mirror ? NT_TILE_67DEGnnB : NT_TILE_67DEGpnB;
        }
        if (y0 >= H) continue;
        nt_world_set_tile(w, mx, y0, t0);
        int below = y0 + 1;
        if (t1 >= 0 && below < H) nt_world_set_tile(w, mx, below++, t1);
        for (int y = below; y < H; y++) nt_world_set_tile(w, mx, y, NT_TILE_FULL);
    }
    return kind == S45 ? 1.0 : kind == S22 ? 0.5 : 2.0;
}

/* Put a body just above the slope at distance `along` cells (in x) from its top. */
static nt_body_id drop_on_slope(nt_world *w, int W, int mirror, nt_shape s, double along, double mu, double tan_t)
{
    double x = along, surface = 2 + x * tan_t;
    /* Clearance: a box touches with its lower corner, a circle at r / cos. */
    double h = (double)s.half.x;
    double lift = s.type == NT_SHAPE_CIRCLE ? h * sqrt(1 + tan_t * tan_t) : h + h * tan_t;
    return add_body(w, s, mirror ? W - x : x, surface - lift - 0.02, 0, 0, 1, mu, 0);
}

/* Sliding: a = g (sin - mu cos) within 1%. Sticking: no drift over 10,000 steps. */
static void test_coulomb_incline(void **state)
{
    (void)state;
    const double dt = 1.0 / 120;
    for (int kind = 0; kind < 3; kind++)
        for (int mirror = 0; mirror < 2; mirror++)
            for (int shape = 0; shape < 2; shape++) {
                int W = kind == S22 ? 70 : kind == S45 ? 40 : 24, H = kind == S67 ? 60 : 40;
                nt_shape s = shape ? nt_shape_circle(R(0.25)) : nt_shape_aabb(R(0.25), R(0.25));
                /* Sliding, mu = tan / 2. */
                nt_world *w = make_world(W, H, G, NT_FRICTION_COULOMB);
                nt_world_set_material(w, 0, (nt_material){R(1), 0});
                double tan_t = build_slope(w, W, H, kind, mirror);
                double th = atan(tan_t), mu = tan_t / 2;
                /* Body friction mu^2 with tile friction 1: the combination is mu. */
                nt_body_id id = drop_on_slope(w, W, mirror, s, 3.2, mu * mu, tan_t);
                for (int i = 0; i < 30; i++) nt_world_step(w, (nt_real)dt);
                double v1 = speed(nt_body_get_velocity(w, id));
                const int K = kind == S67 ? 40 : 80;
                for (int i = 0; i < K; i++) nt_world_step(w, (nt_real)dt);
                double v2 = speed(nt_body_get_velocity(w, id));
                double a = (v2 - v1) / (K * dt), want = G * (sin(th) - mu * cos(th));
                if (fabs(a - want) > 0.01 * want)
                    printf("incline kind %d mirror %d shape %d: a = %g, want %g\n", kind, mirror, shape, a, want);
                assert_true(fabs(a - want) <= 0.01 * want);
                /* Moving along the slope, down and away from the top. */
                nt_vec2 v = nt_body_get_velocity(w, id);
                assert_true(fabs((double)v.y / fabs((double)v.x) - tan_t) < 1e-3 * tan_t);
                assert_true(mirror ? v.x < 0 : v.x > 0);
                nt_world_destroy(w);

                /* Sticking, mu = 1.5 tan. */
                w = make_world(W, H, G, NT_FRICTION_COULOMB);
                nt_world_set_material(w, 0, (nt_material){R(1), 0});
                build_slope(w, W, H, kind, mirror);
                mu = 1.5 * tan_t;
                id = drop_on_slope(w, W, mirror, s, 3.2, mu * mu, tan_t);
                for (int i = 0; i < 60; i++) nt_world_step(w, (nt_real)dt);
                nt_vec2 p0 = nt_body_get_position(w, id);
                nt_body_tile_contacts tc;
                assert_int_equal(nt_body_get_tile_contacts(w, id, &tc), NT_OK);
                assert_true(tc.count >= 1);
                for (int i = 0; i < 10000; i++) nt_world_step(w, (nt_real)dt);
                nt_vec2 p1 = nt_body_get_position(w, id);
                double drift = hypot((double)p1.x - p0.x, (double)p1.y - p0.y);
                assert_true(drift < 1e-6);
                assert_true(nt_map_overlap_depth(nt_world_get_map(w), p1, s) < 1e-3);
                nt_world_destroy(w);
            }
}

/* N's model on a slope: each step gravity adds g sin dt along the slope, then the
 * body loses `friction` of its tangential speed, so the speed after a step tends
 * to v* = (1 - f) g sin dt / f. */
static void test_n_model_terminal_speed(void **state)
{
    (void)state;
    const double dt = 1.0 / 60;
    for (int kind = 0; kind < 3; kind++)
        for (int mirror = 0; mirror < 2; mirror++) {
            int W = kind == S22 ? 70 : kind == S45 ? 40 : 24, H = kind == S67 ? 60 : 40;
            nt_world *w = make_world(W, H, G, NT_FRICTION_N);
            nt_world_set_material(w, 0, (nt_material){R(1), 0});
            double tan_t = build_slope(w, W, H, kind, mirror), th = atan(tan_t);
            const double f = 0.3;
            nt_body_id id = drop_on_slope(w, W, mirror, nt_shape_aabb(R(0.2), R(0.2)), 3.2, f * f, tan_t);
            for (int i = 0; i < 150; i++) nt_world_step(w, (nt_real)dt);
            double want = (1 - f) * G * sin(th) * dt / f;
            double got = speed(nt_body_get_velocity(w, id));
            assert_true(fabs(got - want) <= 0.01 * want);
            nt_world_destroy(w);
        }
}

/* ---------------------------------------------------------------- ghost bumps */

/* Sliding along 200 FULL tiles: the seams never push. */
static void test_flat_floor_no_ghost_bumps(void **state)
{
    (void)state;
    for (int model = 0; model < 2; model++)
        for (int shape = 0; shape < 2; shape++) {
            nt_world *w = make_world(204, 8, G, (nt_friction_model)model);
            fill(w, 0, 7, 203, 7, NT_TILE_FULL);
            nt_shape s = shape ? nt_shape_circle(R(0.3)) : nt_shape_aabb(R(0.45), R(0.3));
            double rest_y = 7 - (double)s.half.y;
            nt_body_id id = add_body(w, s, 2, rest_y - 0.01, 12, 0, 1, 0, 0);
            for (int i = 0; i < 10; i++) nt_world_step(w, R(1.0 / 60));
            double y_ref = (double)nt_body_get_position(w, id).y;
            assert_true(fabs(y_ref - rest_y) < 1e-3);
            double vx0 = (double)nt_body_get_velocity(w, id).x;
            double max_dy = 0, min_vy = 0;
            while ((double)nt_body_get_position(w, id).x < 200) {
                assert_int_equal(nt_world_step(w, R(1.0 / 60)), NT_OK);
                nt_vec2 p = nt_body_get_position(w, id), v = nt_body_get_velocity(w, id);
                max_dy = fmax(max_dy, fabs((double)p.y - y_ref));
                min_vy = fmin(min_vy, (double)v.y);
                nt_body_tile_contacts tc;
                nt_body_get_tile_contacts(w, id, &tc);
                assert_true(tc.on_floor);
                assert_true(tc.floor_normal.x == 0 && tc.floor_normal.y == -1);
            }
            assert_true(max_dy < 1e-5);
            assert_true(min_vy > -1e-6); /* never kicked upwards */
            assert_true(fabs((double)nt_body_get_velocity(w, id).x - vx0) < 1e-6 * vx0); /* frictionless */
            nt_world_destroy(w);
        }
}

/* Down a slope onto the flat, and across the seams inside slopes: never upwards,
 * never off the surface. */
static void test_slope_to_flat_no_bump(void **state)
{
    (void)state;
    for (int kind = 0; kind < 3; kind++)
        for (int mirror = 0; mirror < 2; mirror++)
            for (int shape = 0; shape < 2; shape++) {
                int W = 40, H = 30;
                nt_world *w = make_world(W, H, G, NT_FRICTION_COULOMB);
                double tan_t = build_slope(w, W, H, kind, mirror);
                /* Cut the slope at row 12: flat FULL floor from there on. */
                int flat_row = 12;
                for (int x = 0; x < W; x++)
                    for (int y = flat_row; y < H; y++) nt_world_set_tile(w, x, y, NT_TILE_FULL);
                nt_shape s = shape ? nt_shape_circle(R(0.25)) : nt_shape_aabb(R(0.25), R(0.25));
                nt_body_id id = drop_on_slope(w, W, mirror, s, 1.2, 0, tan_t);
                double min_vy = 1e9;
                int on_flat = 0, steps = 0, landed = 0;
                double rest_y = flat_row - (double)s.half.y;
                for (; steps < 600; steps++) {
                    assert_int_equal(nt_world_step(w, R(1.0 / 120)), NT_OK);
                    nt_vec2 p = nt_body_get_position(w, id), v = nt_body_get_velocity(w, id);
                    nt_body_tile_contacts tc;
                    nt_body_get_tile_contacts(w, id, &tc);
                    /* Once on the slope it stays on the surface (no hop) and never
                     * moves upwards. */
                    if (tc.count) landed = 1;
                    if (landed) {
                        assert_true(tc.count >= 1); /* 67-degree slopes are walls, not floors */
                        min_vy = fmin(min_vy, (double)v.y);
                    }
                    if (fabs((double)p.y - rest_y) < 1e-3 && v.y == 0) on_flat++;
                    if (on_flat > 60) break;
                }
                assert_true(min_vy >= -1e-6);
                assert_true(on_flat > 60);
                /* On the flat it keeps its speed: frictionless, and no bump took any. */
                nt_vec2 v = nt_body_get_velocity(w, id);
                assert_true(fabs((double)v.x) > 1);
                nt_world_destroy(w);
            }
}

/* ---------------------------------------------------------------- tunnelling */

/* Fire bodies at the speed limit, perpendicular to every face (straight edges and
 * the middle of arcs) of every tile, alone in the middle of the map; they must end
 * outside the tile, on the face's side. */
static void test_no_tunnelling(void **state)
{
    (void)state;
    const double dt = 1.0 / 60, vmax = 4 / dt; /* 4 cells per step */
    int shots = 0;
    for (int tile = 1; tile < NT_TILE_COUNT; tile++) {
        const nt_tile_info *info = nt_tile_get_info(tile);
        /* Faces: (midpoint, outward normal). */
        double face[8][4];
        int nf = 0;
        int nv = info->vertex_count;
        int round = info->cls == NT_CLASS_CONVEX || info->cls == NT_CLASS_CONCAVE;
        for (int k = 0; k < nv; k++) {
            if (round && k == nv - 1) break; /* the arc closes round tiles */
            nt_vec2 a = info->vertices[k], b = info->vertices[(k + 1) % nv];
            double ex = (double)b.x - a.x, ey = (double)b.y - a.y, len = sqrt(ex * ex + ey * ey);
            if (len < 1e-9) continue;
            face[nf][0] = 0.5 * ((double)a.x + b.x);
            face[nf][1] = 0.5 * ((double)a.y + b.y);
            face[nf][2] = -ey / len;
            face[nf][3] = ex / len;
            nf++;
        }
        if (round) {
            double nx = (double)info->normal.x, ny = (double)info->normal.y;
            double cx = (double)info->arc_center.x, cy = (double)info->arc_center.y;
            double sgn = info->cls == NT_CLASS_CONVEX ? 1 : -1;
            face[nf][0] = cx + sgn * nx;
            face[nf][1] = cy + sgn * ny;
            face[nf][2] = nx;
            face[nf][3] = ny;
            nf++;
        }
        for (int f = 0; f < nf; f++)
            for (int shape = 0; shape < 2; shape++)
                for (int size = 0; size < 3; size++)
                    for (int phase = 0; phase < 3; phase++) {
                        nt_world *w = make_world(21, 21, 0, NT_FRICTION_COULOMB);
                        nt_world_set_tile(w, 10, 10, tile);
                        double h = size == 0 ? 0.1 : size == 1 ? 0.25 : 0.45;
                        nt_shape s = shape ? nt_shape_circle((nt_real)h) : nt_shape_aabb((nt_real)h, (nt_real)h);
                        double mx = 10 + face[f][0], my = 10 + face[f][1], nx = face[f][2], ny = face[f][3];
                        double start = 6 + 0.37 * phase;
                        double speed_k = phase == 2 ? 0.93 : 1;
                        nt_body_id id = add_body(w, s, mx + nx * start, my + ny * start, -nx * vmax * speed_k,
                                                 -ny * vmax * speed_k, 1, 0, 0);
                        for (int i = 0; i < 4; i++) nt_world_step(w, (nt_real)dt);
                        nt_vec2 p = nt_body_get_position(w, id);
                        double side = ((double)p.x - mx) * nx + ((double)p.y - my) * ny;
                        double depth = (double)nt_map_overlap_depth(nt_world_get_map(w), p, s);
                        if (!(side > 0 && depth < 1e-3))
                            printf("tunnel: tile %s face %d shape %d h %.2f phase %d: side %g depth %g at (%g %g)\n",
                                   info->name, f, shape, h, phase, side, depth, (double)p.x, (double)p.y);
                        assert_true(side > 0);
                        assert_true(depth < 1e-3);
                        shots++;
                        nt_world_destroy(w);
                    }
    }
    assert_true(shots > 33 * 3 * 2 * 3 * 3);
}

/* A resting contact does not bounce because the step got longer (issue 21): a box
 * resting on a static box, and a box resting on a box on a FULL floor, both of bounce
 * 0.5, restitution threshold 0.5 units/s, gravity 10: after 120 steps of 1/60 s one
 * step of 1/10 s (g dt = 1, twice the threshold) and more of 1/60 s. The top box must
 * stay where it rests (within 0.01 cell, moving up at most 0.05 cell/s): it once hopped
 * at e g dt = 0.5 units/s. */
static void test_longer_step_no_hop(void **state)
{
    (void)state;
    for (int dynamic_base = 0; dynamic_base < 2; dynamic_base++) {
        nt_world_def wd = nt_default_world_def();
        wd.map.width = wd.map.height = 10;
        wd.map.cell_size = 1;
        wd.gravity = nt_v2(0, 10);
        wd.friction_model = NT_FRICTION_COULOMB;
        wd.restitution_threshold = R(0.5);
        wd.enable_sleep = false;
        nt_world *w = NULL;
        assert_int_equal(nt_world_create(&wd, &w), NT_OK);
        fill(w, 0, 9, 9, 9, NT_TILE_FULL);
        nt_body_def d = nt_default_body_def();
        d.type = dynamic_base ? NT_BODY_DYNAMIC : NT_BODY_STATIC;
        d.shape = nt_shape_aabb(R(0.4), R(0.4));
        d.position = nt_v2(5, R(9 - 0.4));
        d.material.bounce = R(0.5);
        d.material.friction = R(0.5);
        nt_body_id base;
        assert_int_equal(nt_body_create(w, &d, &base), NT_OK);
        nt_body_id top = add_body(w, nt_shape_aabb(R(0.4), R(0.4)), 5, 9 - 1.2, 0, 0, 1, 0.5, 0.5);
        for (int s = 0; s < 120; s++) assert_int_equal(nt_world_step(w, R(1.0 / 60)), NT_OK);
        double rest_y = (double)nt_body_get_position(w, top).y, worst_up = 0, worst_move = 0;
        for (int s = 0; s < 60; s++) {
            assert_int_equal(nt_world_step(w, R(s == 0 ? 0.1 : 1.0 / 60)), NT_OK);
            worst_up = fmax(worst_up, -(double)nt_body_get_velocity(w, top).y);
            worst_move = fmax(worst_move, fabs((double)nt_body_get_position(w, top).y - rest_y));
        }
        printf("  %s base: after a longer step the top box moved %.3g cell, up at %.3g cell/s at most\n",
               dynamic_base ? "dynamic" : "static", worst_move, worst_up);
        assert_true(worst_move < 0.01);
        assert_true(worst_up < 0.05);
        nt_world_destroy(w);
    }
}

/* A floor of every tile shape (a row of the tile over FULL), hit from above at the
 * speed limit with gravity: nothing falls through. */
static void test_no_fall_through_floors(void **state)
{
    (void)state;
    const double dt = 1.0 / 60;
    for (int tile = 1; tile < NT_TILE_COUNT; tile++) {
        const nt_tile_info *info = nt_tile_get_info(tile);
        if (info->signy > 0 || tile == NT_TILE_HALFu || tile == NT_TILE_HALFl || tile == NT_TILE_HALFr) continue;
        nt_world *w = make_world(12, 30, G, NT_FRICTION_COULOMB);
        fill(w, 0, 20, 11, 20, tile);
        fill(w, 0, 21, 11, 29, NT_TILE_FULL);
        for (int shape = 0; shape < 2; shape++)
            for (int k = 0; k < 5; k++) {
                nt_shape s = shape ? nt_shape_circle(R(0.15)) : nt_shape_aabb(R(0.15), R(0.2));
                nt_body_id id = add_body(w, s, 1.3 + 2 * k + 0.1 * shape, 2, 0, 4 / dt, 1, 0.5, 0);
                for (int i = 0; i < 20; i++) nt_world_step(w, (nt_real)dt);
                nt_vec2 p = nt_body_get_position(w, id);
                assert_true((double)p.y < 21);
                assert_true(nt_map_overlap_depth(nt_world_get_map(w), p, s) < 1e-3);
                nt_body_destroy(w, id);
            }
        nt_world_destroy(w);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_free_fall_and_gravity_scale),
        cmocka_unit_test(test_linear_drag),
        cmocka_unit_test(test_speed_limit),
        cmocka_unit_test(test_momentum_head_on),
        cmocka_unit_test(test_momentum_angled),
        cmocka_unit_test(test_bounce_heights),
        cmocka_unit_test(test_elastic_bounce_keeps_energy),
        cmocka_unit_test(test_elastic_gas_keeps_energy),
        cmocka_unit_test(test_newtons_cradle),
        cmocka_unit_test(test_coulomb_incline),
        cmocka_unit_test(test_n_model_terminal_speed),
        cmocka_unit_test(test_flat_floor_no_ghost_bumps),
        cmocka_unit_test(test_slope_to_flat_no_bump),
        cmocka_unit_test(test_no_tunnelling),
        cmocka_unit_test(test_no_fall_through_floors),
        cmocka_unit_test(test_longer_step_no_hop),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
