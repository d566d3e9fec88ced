/* World features: the broad phase against brute force (filters, types, sensors,
 * bodies outside the map, fast bodies), contact and sensor events and their order, hit events,
 * category/mask filtering, one-way tiles, kinematic bodies pushing and carrying,
 * per-cell materials, the tile-contact summary. Units: cell 1, seconds. */
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
static const nt_real DT = R(1.0 / 60);

static nt_world *make_world(int w, int h, double g, nt_friction_model model, nt_real friction)
{
    nt_world_def d = nt_default_world_def();
    d.map.width = w;
    d.map.height = h;
    d.map.cell_size = 1;
    d.gravity = nt_v2(0, (nt_real)g);
    d.friction_model = model;
    d.tile_material.friction = friction;
    d.tile_material.bounce = 0;
    d.restitution_threshold = R(0.5);
    d.hit_event_threshold = R(1);
    d.enable_sleep = false;
    nt_world *world = NULL;
    assert_int_equal(nt_world_create(&d, &world), NT_OK);
    return world;
}

typedef struct spec {
    nt_body_type type;
    nt_shape shape;
    double x, y, vx, vy;
    uint32_t category, mask;
    bool sensor;
    double friction, bounce;
} spec;

static nt_body_id add(nt_world *w, spec s)
{
    nt_body_def d = nt_default_body_def();
    d.type = s.type;
    d.shape = s.shape;
    d.position = nt_v2((nt_real)s.x, (nt_real)s.y);
    d.velocity = nt_v2((nt_real)s.vx, (nt_real)s.vy);
    d.category = s.category;
    d.mask = s.mask;
    d.is_sensor = s.sensor;
    d.material.friction = (nt_real)s.friction;
    d.material.bounce = (nt_real)s.bounce;
    nt_body_id id;
    assert_int_equal(nt_body_create(w, &d, &id), NT_OK);
    return id;
}

static spec dyn(nt_shape shape, double x, double y)
{
    spec s;
    memset(&s, 0, sizeof s);
    s.type = NT_BODY_DYNAMIC;
    s.shape = shape;
    s.x = x;
    s.y = y;
    s.category = 1;
    s.mask = 0xffffffffu;
    return s;
}

static void fill(nt_world *w, int x0, int y0, int x1, int y1, int tile)
{
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) assert_int_equal(nt_world_set_tile(w, x, y, tile), NT_OK);
}

/* ---------------------------------------------------------------- broad phase */

static uint32_t rnd(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

static int overlaps(const spec *a, const spec *b, double grow)
{
    nt_shape sa = a->shape;
    sa.half.x += (nt_real)grow;
    sa.half.y += (nt_real)grow;
    nt_mtv m;
    return nt_collide_shapes(nt_v2((nt_real)a->x, (nt_real)a->y), sa, nt_v2((nt_real)b->x, (nt_real)b->y), b->shape, &m);
}

static int find_event(const nt_contact_events *ce, const nt_sensor_events *se, nt_body_id a, nt_body_id b, int sensor)
{
    int found = 0;
    if (sensor) {
        for (int k = 0; k < se->begin_count; k++)
            if (nt_body_id_equals(se->begin_events[k].sensor, a) && nt_body_id_equals(se->begin_events[k].visitor, b))
                found++;
    } else {
        for (int k = 0; k < ce->begin_count; k++)
            if (nt_body_id_equals(ce->begin_events[k].a, a) && nt_body_id_equals(ce->begin_events[k].b, b)) found++;
    }
    return found;
}

/* Begin events of the first step = every pair that may collide and touches (its
 * shapes overlap, or for non-sensors come within the 2.5e-4-cell skin), found by
 * testing all pairs; sensor events likewise; both sorted by slot. */
static void test_broad_phase_matches_brute_force(void **state)
{
    (void)state;
    enum { N = 400 };
    uint32_t seed = 99;
    for (int round = 0; round < 3; round++) {
        nt_world *w = make_world(30, 30, 0, NT_FRICTION_COULOMB, R(0.5));
        static spec specs[N];
        static nt_body_id ids[N];
        for (int i = 0; i < N; i++) {
            double r = 0.05 + 0.45 * (double)(rnd(&seed) % 1000) / 1000;
            nt_shape sh = rnd(&seed) % 2 ? nt_shape_circle((nt_real)r) : nt_shape_aabb((nt_real)r, (nt_real)(0.05 + 0.45 * (double)(rnd(&seed) % 1000) / 1000));
            /* Clustered, some outside the map (they live in its edge cells). */
            double x = -3 + 36 * (double)(rnd(&seed) % 10000) / 10000, y = -3 + 36 * (double)(rnd(&seed) % 10000) / 10000;
            if (round == 2) x = 14 + 2 * (double)(rnd(&seed) % 1000) / 1000, y = 14 + 2 * (double)(rnd(&seed) % 1000) / 1000;
            spec s = dyn(sh, x, y);
            uint32_t t = rnd(&seed) % 10;
            s.type = t < 6 ? NT_BODY_DYNAMIC : t < 8 ? NT_BODY_STATIC : NT_BODY_KINEMATIC;
            s.category = 1u << (rnd(&seed) % 3);
            s.mask = rnd(&seed) % 5 == 0 ? 0u : (rnd(&seed) % 2 ? 0xffffffffu : (1u | (1u << (rnd(&seed) % 3))));
            s.sensor = rnd(&seed) % 10 == 0;
            specs[i] = s;
            ids[i] = add(w, s);
        }
        assert_int_equal(nt_world_step(w, DT), NT_OK);
        nt_contact_events ce = nt_world_get_contact_events(w);
        nt_sensor_events se = nt_world_get_sensor_events(w);
        int sure_c = 0, maybe_c = 0, sure_s = 0;
        for (int i = 0; i < N; i++)
            for (int j = i + 1; j < N; j++) {
                const spec *a = &specs[i], *b = &specs[j];
                int may = (a->category & b->mask) && (b->category & a->mask) && !(a->sensor && b->sensor) &&
                          !(a->type == NT_BODY_STATIC && b->type == NT_BODY_STATIC) &&
                          (a->sensor || b->sensor || a->type == NT_BODY_DYNAMIC || b->type == NT_BODY_DYNAMIC);
                int sensor = a->sensor || b->sensor;
                nt_body_id s = a->sensor ? ids[i] : ids[j], v = a->sensor ? ids[j] : ids[i];
                int found = sensor ? find_event(&ce, &se, s, v, 1) : find_event(&ce, &se, ids[i], ids[j], 0);
                assert_true(found <= 1);
                if (!may || !overlaps(a, b, sensor ? 0 : 1e-3)) {
                    assert_int_equal(found, 0); /* clearly apart, or not allowed to meet */
                } else if (overlaps(a, b, 0)) {
                    assert_int_equal(found, 1); /* overlapping */
                    if (sensor) sure_s++;
                    else sure_c++;
                } else {
                    maybe_c += found; /* within 1e-3: touching if within the skin */
                }
            }
        assert_int_equal(se.begin_count, sure_s);
        assert_int_equal(ce.begin_count, sure_c + maybe_c);
        printf("  round %d: %d contacts (%d within the skin), %d sensor overlaps\n", round, sure_c + maybe_c, maybe_c, sure_s);
        assert_true(sure_c > 10);
        /* Sorted by (a slot, b slot), a below b. */
        for (int k = 0; k < ce.begin_count; k++) {
            assert_true(ce.begin_events[k].a.index1 < ce.begin_events[k].b.index1);
            if (k) {
                const nt_contact_begin_event *p = &ce.begin_events[k - 1], *q = &ce.begin_events[k];
                assert_true(p->a.index1 < q->a.index1 || (p->a.index1 == q->a.index1 && p->b.index1 < q->b.index1));
            }
        }
        nt_world_destroy(w);
    }
}

/* Moving circles: the first step's begin events are exactly the pairs the contact
 * rule (README, The world) makes touching, worked out here for every pair: boxes
 * within 0.05 cell plus, on each axis they approach along, what they close in one
 * step (at most a cell); centres' gap below 0.05 cell plus |dv| dt (at most a cell);
 * touching when the gap is below the 2.5e-4-cell skin or the closing speed covers
 * it within the step. Pairs within 1e-4 of a threshold are not judged. The fast
 * bodies make the broad phase's reach matter, not only its margin. */
static void test_broad_phase_speculative_matches_brute_force(void **state)
{
    (void)state;
    enum { N = 700 };
    const double pm = 0.05, skin = 2.5e-4, dt = (double)DT, vmax = 15, amb = 1e-4;
    uint32_t seed = 7;
    static spec specs[N];
    static nt_body_id ids[N];
    nt_world *w = make_world(30, 30, 0, NT_FRICTION_COULOMB, R(0.5));
    for (int i = 0; i < N; i++) {
        double r = 0.05 + 0.4 * (double)(rnd(&seed) % 1000) / 1000;
        spec s = dyn(nt_shape_circle((nt_real)r), 2 + 26 * (double)(rnd(&seed) % 10000) / 10000,
                     2 + 26 * (double)(rnd(&seed) % 10000) / 10000);
        s.vx = vmax * (2 * (double)(rnd(&seed) % 1000) / 1000 - 1);
        s.vy = vmax * (2 * (double)(rnd(&seed) % 1000) / 1000 - 1);
        /* Positions and velocities as the world stores them. */
        s.x = (double)(nt_real)s.x;
        s.y = (double)(nt_real)s.y;
        s.vx = (double)(nt_real)s.vx;
        s.vy = (double)(nt_real)s.vy;
        specs[i] = s;
        ids[i] = add(w, s);
    }
    assert_int_equal(nt_world_step(w, DT), NT_OK);
    nt_contact_events ce = nt_world_get_contact_events(w);
    nt_sensor_events se = nt_world_get_sensor_events(w);
    int want_total = 0, judged = 0, by_speed = 0, skipped = 0;
    for (int i = 0; i < N; i++)
        for (int j = i + 1; j < N; j++) {
            const spec *a = &specs[i], *b = &specs[j];
            double ra = (double)a->shape.half.x, rb = (double)b->shape.half.x;
            double d[2] = {b->x - a->x, b->y - a->y}, dv[2] = {b->vx - a->vx, b->vy - a->vy};
            int box = 1, unsure = 0;
            for (int k = 0; k < 2; k++) {
                double reach = pm + (d[k] * dv[k] < 0 ? fabs(dv[k]) * dt : 0);
                double lim = ra + rb + (reach < 1 ? reach : 1);
                if (fabs(fabs(d[k]) - lim) < amb) unsure = 1;
                if (!(fabs(d[k]) < lim)) box = 0;
            }
            double len = sqrt(d[0] * d[0] + d[1] * d[1]), gap = len - ra - rb;
            double speed = sqrt(dv[0] * dv[0] + dv[1] * dv[1]);
            double margin = pm + dt * speed < 1 ? pm + dt * speed : 1;
            double closing = -(dv[0] * d[0] + dv[1] * d[1]) / len;
            if (fabs(gap - margin) < amb || fabs(gap - skin) < amb || fabs(closing * dt - gap) < amb || fabs(gap) < amb)
                unsure = 1;
            int contact = box && (gap < 0 || gap < margin);
            int touch = contact && (gap < skin || closing * dt > gap);
            if (!box && !unsure) {
                judged++; /* apart: an event here would show in the total below */
                continue;
            }
            int found = find_event(&ce, &se, ids[i], ids[j], 0);
            assert_true(found <= 1);
            if (unsure) {
                skipped++;
                want_total += found; /* counted as the world judged it */
                continue;
            }
            judged++;
            if (found != touch)
                fail_msg("pair %d-%d: gap %.6g closing*dt %.6g margin %.6g box %d: found %d, want %d", i, j, gap,
                         closing * dt, margin, box, found, touch);
            want_total += touch;
            if (touch && gap >= skin) by_speed++;
        }
    assert_int_equal(ce.begin_count, want_total);
    printf("  %d pairs judged, %d touching only by their closing speed, %d near a threshold not judged\n", judged,
           by_speed, skipped);
    assert_true(by_speed > 20);
    nt_world_destroy(w);
}

/* Nothing can collide: the broad phase is skipped. */
static void test_broad_phase_skipped(void **state)
{
    (void)state;
    nt_world *w = make_world(20, 20, 10, NT_FRICTION_COULOMB, 0);
    fill(w, 0, 19, 19, 19, NT_TILE_FULL);
    for (int i = 0; i < 200; i++) {
        spec s = dyn(nt_shape_circle(R(0.1)), 1 + (i % 18), 1 + (i / 18) * 0.2);
        s.mask = 0; /* particles: tiles only */
        add(w, s);
    }
    nt_world_step(w, DT);
    assert_int_equal(nt_world_get_counters(w).pair_tests, 0);
    /* Categories that no mask accepts: still nothing to test. */
    for (int i = 0; i < 50; i++) {
        spec s = dyn(nt_shape_circle(R(0.2)), 3 + (i % 10), 5 + (i / 10));
        s.category = 2;
        s.mask = 4;
        add(w, s);
    }
    nt_world_step(w, DT);
    assert_int_equal(nt_world_get_counters(w).pair_tests, 0);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- filtering */

static void test_filtering(void **state)
{
    (void)state;
    nt_world *w = make_world(30, 10, 0, NT_FRICTION_COULOMB, 0);
    spec a = dyn(nt_shape_aabb(R(0.4), R(0.4)), 5, 5), b = dyn(nt_shape_circle(R(0.4)), 10, 5);
    a.vx = 3;
    b.vx = -3;
    a.category = 2;
    a.mask = 1;
    b.category = 1;
    b.mask = 1; /* b does not accept a */
    nt_body_id ia = add(w, a), ib = add(w, b);
    int contacts = 0;
    for (int i = 0; i < 120; i++) {
        nt_world_step(w, DT);
        contacts += nt_world_get_contact_events(w).begin_count;
    }
    assert_int_equal(contacts, 0);
    /* They passed through each other untouched. */
    assert_true(nt_body_get_velocity(w, ia).x == 3 && nt_body_get_velocity(w, ib).x == -3);
    assert_true(nt_body_get_position(w, ia).x > nt_body_get_position(w, ib).x);
    /* Accept each other: they collide. */
    assert_int_equal(nt_body_set_filter(w, ib, 1, 3), NT_OK);
    assert_int_equal(nt_body_set_velocity(w, ia, nt_v2(-3, 0)), NT_OK);
    assert_int_equal(nt_body_set_velocity(w, ib, nt_v2(3, 0)), NT_OK);
    for (int i = 0; i < 120; i++) {
        nt_world_step(w, DT);
        contacts += nt_world_get_contact_events(w).begin_count;
    }
    assert_int_equal(contacts, 1);
    assert_true(nt_body_get_position(w, ia).x > nt_body_get_position(w, ib).x);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- sensors */

static void test_sensor_events(void **state)
{
    (void)state;
    nt_world *w = make_world(10, 40, 10, NT_FRICTION_COULOMB, 0);
    spec s;
    memset(&s, 0, sizeof s);
    s.type = NT_BODY_STATIC;
    s.shape = nt_shape_aabb(R(0.5), R(0.5));
    s.x = 5;
    s.y = 20;
    s.category = 1;
    s.mask = 0xffffffffu;
    s.sensor = true;
    nt_body_id sensor = add(w, s);
    nt_body_id ball = add(w, dyn(nt_shape_circle(R(0.2)), 5, 10));
    spec ghost_s = dyn(nt_shape_circle(R(0.2)), R(5.1), 10);
    ghost_s.category = 8;
    ghost_s.mask = 8; /* not seen by the sensor */
    nt_body_id ghost = add(w, ghost_s);
    int begins = 0, ends = 0, begin_step = -1, end_step = -1;
    for (int i = 0; i < 120; i++) {
        nt_world_step(w, DT);
        nt_sensor_events se = nt_world_get_sensor_events(w);
        for (int k = 0; k < se.begin_count; k++) {
            assert_true(nt_body_id_equals(se.begin_events[k].sensor, sensor));
            assert_true(nt_body_id_equals(se.begin_events[k].visitor, ball));
            begins++;
            begin_step = i;
        }
        for (int k = 0; k < se.end_count; k++) {
            assert_true(nt_body_id_equals(se.end_events[k].visitor, ball));
            ends++;
            end_step = i;
        }
        assert_int_equal(nt_world_get_contact_events(w).begin_count, 0); /* sensors make no contacts */
    }
    assert_int_equal(begins, 1);
    assert_int_equal(ends, 1);
    /* The ball fell freely through it, on the parabola: y_n = 10 + g (n dt)^2 / 2. Its
     * top crossed the sensor's top (y = 19.5, ball bottom at 19.5) during the step
     * before the begin event was reported (events are found at the start of a step). */
    double n = 120, want = 10 + 10.0 / 3600 * n * n / 2;
    assert_true(fabs((double)nt_body_get_position(w, ball).y - want) < 1e-3);
    double yb = 10 + 10.0 / 3600 * (begin_step) * (begin_step) / 2; /* before the step that reported it */
    assert_true(yb + 0.2 > 19.5 && yb - 0.2 < 20.5);
    assert_true(end_step > begin_step);
    (void)ghost;
    /* A visitor destroyed inside a sensor ends its overlap. */
    nt_body_id inside = add(w, dyn(nt_shape_circle(R(0.1)), 5, 20));
    assert_int_equal(nt_world_set_gravity(w, nt_v2(0, 0)), NT_OK);
    nt_world_step(w, DT);
    assert_int_equal(nt_world_get_sensor_events(w).begin_count, 1);
    assert_int_equal(nt_body_destroy(w, inside), NT_OK);
    nt_world_step(w, DT);
    nt_sensor_events se = nt_world_get_sensor_events(w);
    assert_int_equal(se.end_count, 1);
    assert_true(nt_body_id_equals(se.end_events[0].visitor, inside)); /* the stale id, as it was */
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- events */

static void test_contact_event_order_and_hits(void **state)
{
    (void)state;
    nt_world *w = make_world(20, 12, 10, NT_FRICTION_COULOMB, R(0.5));
    fill(w, 0, 11, 19, 11, NT_TILE_FULL);
    /* Three pairs that meet in the same step, created in a scrambled order. */
    nt_body_id ids[6];
    double xs[6] = {12, 3, 8, 12.5, 3.5, 8.5};
    for (int i = 0; i < 6; i++) ids[i] = add(w, dyn(nt_shape_aabb(R(0.3), R(0.3)), xs[i], R(10.69)));
    assert_int_equal(nt_world_step(w, DT), NT_OK);
    nt_contact_events ce = nt_world_get_contact_events(w);
    assert_int_equal(ce.begin_count, 3);
    int want[3][2] = {{0, 3}, {1, 4}, {2, 5}};
    for (int k = 0; k < 3; k++) {
        assert_true(nt_body_id_equals(ce.begin_events[k].a, ids[want[k][0]]));
        assert_true(nt_body_id_equals(ce.begin_events[k].b, ids[want[k][1]]));
        assert_true(ce.begin_events[k].normal.x == 1 && ce.begin_events[k].normal.y == 0);
    }
    /* Pull them apart: end events, same order. */
    for (int i = 3; i < 6; i++) nt_body_set_position(w, ids[i], nt_v2((nt_real)xs[i] + 1, R(10.69)));
    assert_int_equal(nt_world_step(w, DT), NT_OK);
    ce = nt_world_get_contact_events(w);
    assert_int_equal(ce.end_count, 3);
    for (int k = 0; k < 3; k++) assert_true(nt_body_id_equals(ce.end_events[k].a, ids[want[k][0]]));
    /* A ball dropped from 8 cells hits the floor at about sqrt(2 g h). */
    spec b = dyn(nt_shape_circle(R(0.25)), 16, 2.75);
    nt_body_id ball = add(w, b);
    int hits = 0;
    for (int i = 0; i < 120; i++) {
        nt_world_step(w, DT);
        nt_contact_events e = nt_world_get_contact_events(w);
        for (int k = 0; k < e.hit_count; k++)
            if (nt_body_id_equals(e.hit_events[k].a, ball)) {
                assert_true(nt_body_id_is_null(e.hit_events[k].b));
                assert_int_equal(e.hit_events[k].cell_y, 11);
                assert_true(e.hit_events[k].normal.y == -1);
                assert_true(fabs((double)e.hit_events[k].speed - sqrt(2 * 10 * 8.0)) < 0.05 * sqrt(160.0));
                hits++;
            }
    }
    assert_int_equal(hits, 1);
    /* Two bodies meeting at relative speed 6: one body hit event with speed 6. */
    nt_world_set_gravity(w, nt_v2(0, 0));
    spec p = dyn(nt_shape_circle(R(0.3)), 4, 4), q = dyn(nt_shape_circle(R(0.3)), 8, 4);
    p.vx = 3;
    q.vx = -3;
    nt_body_id ip = add(w, p), iq = add(w, q);
    hits = 0;
    for (int i = 0; i < 60; i++) {
        nt_world_step(w, DT);
        nt_contact_events e = nt_world_get_contact_events(w);
        for (int k = 0; k < e.hit_count; k++)
            if (nt_body_id_equals(e.hit_events[k].a, ip)) {
                assert_true(nt_body_id_equals(e.hit_events[k].b, iq));
                assert_true(fabs((double)e.hit_events[k].speed - 6) < 1e-4);
                hits++;
            }
    }
    assert_int_equal(hits, 1);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- one-way tiles */

static void test_one_way_tiles(void **state)
{
    (void)state;
    nt_world *w = make_world(12, 20, 10, NT_FRICTION_COULOMB, R(0.5));
    fill(w, 0, 19, 11, 19, NT_TILE_FULL);
    fill(w, 3, 10, 8, 10, NT_TILE_HALFu); /* a thin platform: solid top half of row 10 */
    for (int x = 3; x <= 8; x++) assert_int_equal(nt_world_set_cell_flags(w, x, 10, NT_CELL_ONE_WAY), NT_OK);
    assert_int_equal(nt_world_get_cell_flags(w, 5, 10), NT_CELL_ONE_WAY);
    assert_int_equal(nt_world_set_cell_flags(w, 5, 10, 8), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_world_set_cell_flags(w, 50, 10, 0), NT_ERR_OUT_OF_RANGE);
    /* Thrown up from the floor, it passes through the platform from below. */
    spec s = dyn(nt_shape_aabb(R(0.3), R(0.3)), 5.5, 18.7);
    s.vy = -16; /* rises about 12.8 cells */
    nt_body_id id = add(w, s);
    double top = 100;
    for (int i = 0; i < 200; i++) {
        nt_world_step(w, DT);
        top = fmin(top, (double)nt_body_get_position(w, id).y);
    }
    assert_true(top < 9);
    /* ...and lands on it coming down: resting on y = 10 (its top). */
    nt_vec2 p = nt_body_get_position(w, id);
    assert_true(fabs((double)p.y - (10 - 0.3)) < 1e-3);
    nt_body_tile_contacts tc;
    nt_body_get_tile_contacts(w, id, &tc);
    assert_true(tc.on_floor);
    /* Sideways into the platform: passes (the platform only holds from above). */
    spec side = dyn(nt_shape_aabb(R(0.2), R(0.2)), 1.5, 10.25);
    side.vx = 6;
    nt_world_set_gravity(w, nt_v2(0, 0));
    nt_body_id sid = add(w, side);
    for (int i = 0; i < 90; i++) nt_world_step(w, DT);
    assert_true((double)nt_body_get_position(w, sid).x > 9);
    /* Without the flag the platform is solid from below too. */
    for (int x = 3; x <= 8; x++) assert_int_equal(nt_world_set_cell_flags(w, x, 10, 0), NT_OK);
    nt_world_set_gravity(w, nt_v2(0, 10));
    nt_body_destroy(w, id);
    nt_body_destroy(w, sid);
    s.x = 6.5;
    id = add(w, s);
    top = 100;
    for (int i = 0; i < 200; i++) {
        nt_world_step(w, DT);
        top = fmin(top, (double)nt_body_get_position(w, id).y);
    }
    assert_true(top > 10.5 - 1e-3 + 0.3 - 0.01);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- kinematic */

static void test_kinematic_pushes(void **state)
{
    (void)state;
    nt_world *w = make_world(40, 10, 10, NT_FRICTION_COULOMB, R(0.3));
    fill(w, 0, 9, 39, 9, NT_TILE_FULL);
    spec k;
    memset(&k, 0, sizeof k);
    k.type = NT_BODY_KINEMATIC;
    k.shape = nt_shape_aabb(R(0.5), R(0.5));
    k.x = 2;
    k.y = 8.5;
    k.vx = 4;
    k.category = 1;
    k.mask = 0xffffffffu;
    nt_body_id kin = add(w, k);
    nt_body_id box = add(w, dyn(nt_shape_aabb(R(0.3), R(0.3)), 6, 8.7));
    for (int i = 1; i <= 240; i++) {
        nt_world_step(w, DT);
        /* The kinematic body goes its way exactly, through anything. */
        nt_vec2 pk = nt_body_get_position(w, kin);
        assert_true(fabs((double)pk.x - (2 + 4.0 * i / 60)) < 1e-4);
        assert_true(pk.y == R(8.5));
        /* The box is pushed ahead of it, never left inside. */
        nt_vec2 pb = nt_body_get_position(w, box);
        if (i > 60) assert_true((double)pb.x - (double)pk.x >= 0.8 - 0.08);
    }
    assert_true((double)nt_body_get_velocity(w, box).x >= 4 - 1e-3);
    /* Into the wall of tiles: the kinematic body passes through tiles. */
    nt_world_destroy(w);
}

static void test_kinematic_carries_riders(void **state)
{
    (void)state;
    const double u = 2, mu = 0.5, g = 10;
    nt_world *w = make_world(60, 20, g, NT_FRICTION_COULOMB, R(0.5));
    spec k;
    memset(&k, 0, sizeof k);
    k.type = NT_BODY_KINEMATIC;
    k.shape = nt_shape_aabb(R(0.5), R(0.2));
    k.x = 5;
    k.y = 10;
    k.category = 1;
    k.mask = 0xffffffffu;
    k.friction = mu;
    nt_body_id plat = add(w, k);
    spec r = dyn(nt_shape_aabb(R(0.2), R(0.2)), 5, 10 - 0.4 - 0.001);
    r.friction = mu;
    nt_body_id rider = add(w, r);
    for (int i = 0; i < 30; i++) nt_world_step(w, DT);
    /* Start moving: the rider slips for u / (mu g) = 0.4 s, then moves with it. */
    nt_body_set_velocity(w, plat, nt_v2((nt_real)u, 0));
    for (int i = 0; i < 60; i++) nt_world_step(w, DT);
    assert_true(fabs((double)nt_body_get_velocity(w, rider).x - u) < 1e-4 * u);
    double rel = (double)nt_body_get_position(w, rider).x - (double)nt_body_get_position(w, plat).x;
    /* Slip distance u^2 / (2 mu g) = 0.4 behind (to within a step of motion). */
    assert_true(fabs(rel - (-u * u / (2 * mu * g))) < u * (double)DT + 0.01);
    for (int i = 0; i < 120; i++) nt_world_step(w, DT);
    double rel2 = (double)nt_body_get_position(w, rider).x - (double)nt_body_get_position(w, plat).x;
    assert_true(fabs(rel2 - rel) < 1e-4);
    /* An elevator: up at 1.5 cells/s, then down at 1.5 cells/s: the rider stays on. */
    nt_body_set_velocity(w, plat, nt_v2(0, R(-1.5)));
    for (int i = 0; i < 120; i++) nt_world_step(w, DT);
    double gap = (double)nt_body_get_position(w, plat).y - (double)nt_body_get_position(w, rider).y;
    assert_true(fabs(gap - 0.4) < 2e-3);
    assert_true(fabs((double)nt_body_get_velocity(w, rider).y + 1.5) < 1e-3);
    /* Stop, then go down at 1.5: the rider falls after it (the gap opens to at most
     * 1.5^2 / (2 g) = 0.1125 above contact) and rides down with it. */
    nt_body_set_velocity(w, plat, nt_v2(0, 0));
    for (int i = 0; i < 60; i++) nt_world_step(w, DT);
    nt_body_set_velocity(w, plat, nt_v2(0, R(1.5)));
    double worst = 0;
    for (int i = 0; i < 120; i++) {
        nt_world_step(w, DT);
        gap = (double)nt_body_get_position(w, plat).y - (double)nt_body_get_position(w, rider).y;
        worst = fmax(worst, gap - 0.4);
    }
    assert_true(worst > 0.05 && worst < 0.1125 + 0.03);
    assert_true(fabs(gap - 0.4) < 2e-3);
    assert_true(fabs((double)nt_body_get_velocity(w, rider).y - 1.5) < 1e-3);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- materials */

/* Cell materials: bounce is the larger of body and cell; friction the geometric mean. */
static void test_cell_materials(void **state)
{
    (void)state;
    nt_world *w = make_world(40, 22, 10, NT_FRICTION_COULOMB, R(0.5));
    nt_material ice = {0, 0}, rough = {R(0.64), 0}, springy = {R(0.5), R(0.8)};
    assert_int_equal(nt_world_set_material(w, 1, ice), NT_OK);
    assert_int_equal(nt_world_set_material(w, 2, rough), NT_OK);
    assert_int_equal(nt_world_set_material(w, 3, springy), NT_OK);
    assert_int_equal(nt_world_set_material(w, NT_MAX_MATERIALS, ice), NT_ERR_OUT_OF_RANGE);
    nt_material bad = {R(-1), 0};
    assert_int_equal(nt_world_set_material(w, 1, bad), NT_ERR_INVALID_ARGUMENT);
    assert_true(nt_world_get_material(w, 2).friction == R(0.64));
    fill(w, 0, 21, 39, 21, NT_TILE_FULL);
    for (int x = 0; x < 20; x++) nt_world_set_cell_material(w, x, 21, 1);
    for (int x = 20; x < 36; x++) nt_world_set_cell_material(w, x, 21, 2);
    for (int x = 36; x < 40; x++) nt_world_set_cell_material(w, x, 21, 3);
    assert_int_equal(nt_world_get_cell_material(w, 25, 21), 2);
    assert_int_equal(nt_world_set_cell_material(w, 25, 21, 99), NT_ERR_OUT_OF_RANGE);
    /* On ice it keeps its speed; on the rough part it slows at sqrt(0.25 * 0.64) g. */
    spec s = dyn(nt_shape_aabb(R(0.3), R(0.3)), 2, 20.7);
    s.vx = 6;
    s.friction = 0.25;
    nt_body_id id = add(w, s);
    for (int i = 0; i < 60; i++) nt_world_step(w, DT);
    assert_true(fabs((double)nt_body_get_velocity(w, id).x - 6) < 1e-5);
    while ((double)nt_body_get_position(w, id).x < 20.5) nt_world_step(w, DT);
    double v1 = (double)nt_body_get_velocity(w, id).x;
    for (int i = 0; i < 30; i++) nt_world_step(w, DT);
    double v2 = (double)nt_body_get_velocity(w, id).x;
    assert_true(fabs((v1 - v2) / 0.5 - 0.4 * 10) < 0.01 * 4);
    /* A ball of bounce 0.2 dropped on the springy cells rises to 0.8^2 of its drop
     * (dt = 1 ms for 1%, see test_world_physics.c). */
    spec b = dyn(nt_shape_circle(R(0.25)), 38, 21 - 0.25 - 6);
    b.bounce = 0.2;
    nt_body_id ball = add(w, b);
    double top = 100, prev = 0;
    int n = 0;
    for (int i = 0; i < 10000 && n < 2; i++) {
        nt_world_step(w, R(0.001));
        nt_vec2 p = nt_body_get_position(w, ball), v = nt_body_get_velocity(w, ball);
        top = fmin(top, (double)p.y);
        if (prev < 0 && v.y >= 0) {
            if (n == 1) assert_true(fabs((21 - 0.25 - top) - 6 * 0.64) < 0.01 * 6 * 0.64);
            n++;
            top = 100;
        }
        prev = (double)v.y;
    }
    assert_int_equal(n, 2);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- contact summary */

static void test_tile_contact_summary(void **state)
{
    (void)state;
    nt_world *w = make_world(10, 10, 10, NT_FRICTION_COULOMB, R(0.5));
    fill(w, 0, 9, 9, 9, NT_TILE_FULL);
    fill(w, 0, 0, 0, 9, NT_TILE_FULL);
    fill(w, 9, 0, 9, 9, NT_TILE_FULL);
    nt_world_set_tile(w, 5, 8, NT_TILE_45DEGnn);
    /* Corner: floor and the wall on the left. */
    spec sa = dyn(nt_shape_aabb(R(0.3), R(0.3)), 1.4, 8.6);
    sa.vx = -2;
    nt_body_id a = add(w, sa);
    spec sb = dyn(nt_shape_aabb(R(0.3), R(0.3)), 8.6, 8.7);
    sb.vx = 2;
    nt_body_id b = add(w, sb);
    nt_body_id c = add(w, dyn(nt_shape_circle(R(0.25)), 5.6, 7.6)); /* on the 45-degree slope */
    for (int i = 0; i < 30; i++) nt_world_step(w, DT);
    nt_body_tile_contacts t;
    assert_int_equal(nt_body_get_tile_contacts(w, a, &t), NT_OK);
    assert_true(t.on_floor && t.wall_left && !t.wall_right && !t.on_ceiling);
    assert_true(t.floor_normal.x == 0 && t.floor_normal.y == -1);
    assert_int_equal(nt_body_get_tile_contacts(w, b, &t), NT_OK);
    assert_true(t.on_floor && t.wall_right && !t.wall_left);
    assert_int_equal(nt_body_get_tile_contacts(w, c, &t), NT_OK);
    if (t.on_floor && t.floor_normal.x != 0) {
        assert_true(fabs((double)t.floor_normal.x + 0.70710678) < 1e-5);
        assert_true(fabs((double)t.floor_normal.y + 0.70710678) < 1e-5);
    }
    assert_true(t.on_floor);
    /* 45 degrees is a floor only (the default floor angle is 50 degrees), not a wall. */
    assert_false(t.wall_left || t.wall_right);
    /* Gravity up: the border above the map is the ceiling. */
    nt_world_set_gravity(w, nt_v2(0, -10));
    for (int i = 0; i < 120; i++) nt_world_step(w, DT);
    assert_int_equal(nt_body_get_tile_contacts(w, a, &t), NT_OK);
    assert_true(t.on_ceiling && !t.on_floor);
    assert_true(fabs((double)nt_body_get_position(w, a).y - 0.3) < 1e-3);
    nt_world_destroy(w);
}

/* A world definition: cell 1, gravity 10 down, Coulomb friction on the tiles. */
static nt_world_def coulomb_def(int w, int h, nt_real friction)
{
    nt_world_def d = nt_default_world_def();
    d.map.width = w;
    d.map.height = h;
    d.map.cell_size = 1;
    d.gravity = nt_v2(0, 10);
    d.friction_model = NT_FRICTION_COULOMB;
    d.tile_material.friction = friction;
    return d;
}

/* The floor angle decides floor / wall / ceiling: a box resting in a 45-degree V (two
 * slopes) is on a floor with 50 degrees, against two walls with 40; a 63.4-degree slope
 * is a wall by default, a floor with 70 degrees. Out-of-range angles are refused. */
static void test_floor_angle(void **state)
{
    (void)state;
    const double angles[3] = {50, 40, 70};
    for (int k = 0; k < 3; k++) {
        nt_world_def d = coulomb_def(12, 10, R(1.2));
        d.floor_angle = (nt_real)(angles[k] * 3.14159265358979 / 180);
        nt_world *w = NULL;
        assert_int_equal(nt_world_create(&d, &w), NT_OK);
        fill(w, 0, 9, 11, 9, NT_TILE_FULL);
        nt_world_set_tile(w, 2, 8, NT_TILE_45DEGpn); /* a V: down to the right, then up */
        nt_world_set_tile(w, 3, 8, NT_TILE_45DEGnn);
        nt_world_set_tile(w, 8, 8, NT_TILE_67DEGnnB); /* 63.4 degrees rising to the right */
        nt_world_set_tile(w, 8, 7, NT_TILE_67DEGnnS);
        nt_body_id v = add(w, dyn(nt_shape_aabb(R(0.2), R(0.2)), 3, 7.9));
        spec ss = dyn(nt_shape_aabb(R(0.1), R(0.1)), 8.45, 8.0);
        ss.friction = 1.2;
        nt_body_id st = add(w, ss);
        for (int i = 0; i < 60; i++) nt_world_step(w, DT);
        nt_body_tile_contacts t;
        assert_int_equal(nt_body_get_tile_contacts(w, v, &t), NT_OK);
        assert_int_equal(t.count, 2);
        if (angles[k] >= 45) assert_true(t.on_floor && !t.wall_left && !t.wall_right);
        else assert_true(!t.on_floor && t.wall_left && t.wall_right);
        assert_int_equal(nt_body_get_tile_contacts(w, st, &t), NT_OK);
        assert_true(t.count >= 1);
        int steep = 0;
        for (int c = 0; c < t.count; c++) steep |= t.contacts[c].normal.y > R(-0.5);
        assert_true(steep); /* it rests on the steep slope */
        if (angles[k] >= 63.5) assert_true(t.on_floor);
        else assert_true(t.wall_right);
        nt_world_destroy(w);
    }
    nt_world_def d = nt_default_world_def();
    nt_world *w = NULL;
    d.floor_angle = R(-0.1);
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_INVALID_ARGUMENT);
    d.floor_angle = R(1.6);
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_INVALID_ARGUMENT);
    d.floor_angle = (nt_real)NAN;
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_NON_FINITE);
    assert_null(w);
}

/* A one-way kinematic platform (is_one_way): a box thrown up from below passes
 * through it and lands on it; a box sliding in sideways passes; the same platform
 * without the flag stops the box from below. */
static void test_one_way_bodies(void **state)
{
    (void)state;
    for (int flag = 1; flag >= 0; flag--) {
        nt_world *w = make_world(20, 20, 10, NT_FRICTION_COULOMB, R(0.5));
        fill(w, 0, 19, 19, 19, NT_TILE_FULL);
        nt_body_def pd = nt_default_body_def();
        pd.type = NT_BODY_KINEMATIC;
        pd.shape = nt_shape_aabb(3, R(0.25));
        pd.position = nt_v2(10, 10);
        pd.is_one_way = flag;
        nt_body_id plat;
        assert_int_equal(nt_body_create(w, &pd, &plat), NT_OK);
        spec s = dyn(nt_shape_aabb(R(0.3), R(0.3)), 10, 18.69);
        s.vy = -16;
        nt_body_id id = add(w, s);
        double top = 100;
        for (int i = 0; i < 200; i++) {
            nt_world_step(w, DT);
            top = fmin(top, (double)nt_body_get_position(w, id).y);
        }
        nt_vec2 p = nt_body_get_position(w, id);
        if (flag) {
            assert_true(top < 9); /* through it from below */
            assert_true(fabs((double)p.y - (10 - 0.25 - 0.3)) < 2e-3); /* and resting on it */
        } else {
            assert_true(top > 10.25 + 0.3 - 0.01); /* stopped under it */
        }
        nt_world_destroy(w);
    }
    /* Sideways into a one-way platform: passes. */
    nt_world *w = make_world(20, 20, 0, NT_FRICTION_COULOMB, R(0.5));
    nt_body_def pd = nt_default_body_def();
    pd.type = NT_BODY_STATIC;
    pd.shape = nt_shape_aabb(1, 1);
    pd.position = nt_v2(10, 10);
    pd.is_one_way = true;
    nt_body_id plat;
    assert_int_equal(nt_body_create(w, &pd, &plat), NT_OK);
    spec side = dyn(nt_shape_aabb(R(0.2), R(0.2)), 5, 10);
    side.vx = 6;
    nt_body_id sid = add(w, side);
    for (int i = 0; i < 120; i++) nt_world_step(w, DT);
    assert_true((double)nt_body_get_position(w, sid).x > 14);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- body contacts */

/* nt_body_get_contacts: a box resting on a static slab, a box on it and a circle
 * leaning on its side: each body lists exactly the bodies it touches (by brute force
 * on the shapes, grown by the skin), ordered by slot, with normals pushing it away
 * from the other; the list survives sleep; capacity, counting and bad input. */
static void test_body_contact_list(void **state)
{
    (void)state;
    nt_world_def d = coulomb_def(20, 12, R(0.5));
    d.tile_material.bounce = 0;
    d.restitution_threshold = R(0.5);
    d.sleep_speed = R(0.05);
    nt_world *w = NULL;
    assert_int_equal(nt_world_create(&d, &w), NT_OK);
    spec slab = dyn(nt_shape_aabb(3, R(0.5)), 10, 10);
    slab.type = NT_BODY_STATIC;
    slab.friction = 0.8;
    spec lower = dyn(nt_shape_aabb(R(0.4), R(0.4)), 10, R(9.1));
    lower.friction = 0.8;
    spec upper = dyn(nt_shape_aabb(R(0.3), R(0.3)), R(10.05), R(8.4));
    upper.friction = 0.8;
    spec ball = dyn(nt_shape_circle(R(0.25)), R(10.65), R(9.25));
    ball.friction = 0.8;
    nt_body_id ids[4] = {add(w, slab), add(w, lower), add(w, upper), add(w, ball)};
    const spec *specs[4] = {&slab, &lower, &upper, &ball};
    for (int k = 0; k < 120; k++) assert_int_equal(nt_world_step(w, DT), NT_OK);
    for (int pass = 0; pass < 2; pass++) {
        for (int i = 0; i < 4; i++) {
            nt_body_contact got[4];
            int n = -1;
            assert_int_equal(nt_body_get_contacts(w, ids[i], got, 4, &n), NT_OK);
            int want = 0;
            for (int j = 0; j < 4; j++) {
                if (j == i) continue;
                spec a = *specs[i], b = *specs[j];
                nt_vec2 pa = nt_body_get_position(w, ids[i]), pb = nt_body_get_position(w, ids[j]);
                a.x = (double)pa.x, a.y = (double)pa.y, b.x = (double)pb.x, b.y = (double)pb.y;
                if (!overlaps(&a, &b, 1e-3) || (a.type == NT_BODY_STATIC && b.type == NT_BODY_STATIC)) continue;
                /* Listed, in slot order, with the normal from j towards i. */
                assert_true(want < n);
                assert_true(nt_body_id_equals(got[want].other, ids[j]));
                double dx = a.x - b.x, dy = a.y - b.y, nx = (double)got[want].normal.x, ny = (double)got[want].normal.y;
                assert_true(fabs(hypot(nx, ny) - 1) < 1e-5);
                assert_true(nx * dx + ny * dy > 0);
                assert_true((double)got[want].depth > -1e-3 && (double)got[want].depth < 1e-2);
                want++;
            }
            assert_int_equal(n, want);
        }
        /* The lower box has the slab under it (normal up) and the upper box on it (down). */
        nt_body_contact c[4];
        int n = 0;
        assert_int_equal(nt_body_get_contacts(w, ids[1], c, 4, &n), NT_OK);
        assert_int_equal(n, 3);
        assert_true(c[0].normal.y < R(-0.99) && c[1].normal.y > R(0.99));
        /* Asleep, the contacts stay listed. */
        for (int k = 0; k < 240 && nt_world_get_awake_count(w) > 0; k++) nt_world_step(w, DT);
        assert_int_equal(nt_world_get_awake_count(w), 0);
    }
    /* Capacity: the first ones by slot; a NULL list counts. */
    nt_body_contact one;
    int n = 0;
    assert_int_equal(nt_body_get_contacts(w, ids[1], &one, 1, &n), NT_OK);
    assert_int_equal(n, 3);
    assert_true(nt_body_id_equals(one.other, ids[0]));
    assert_int_equal(nt_body_get_contacts(w, ids[1], NULL, 0, &n), NT_OK);
    assert_int_equal(n, 3);
    assert_int_equal(nt_body_get_contacts(w, ids[1], NULL, 2, &n), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_body_get_contacts(w, ids[1], &one, 1, NULL), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_body_get_contacts(w, ids[1], &one, -1, &n), NT_ERR_INVALID_ARGUMENT);
    nt_body_id bad = ids[3];
    assert_int_equal(nt_body_destroy(w, bad), NT_OK);
    assert_int_equal(nt_body_get_contacts(w, bad, &one, 1, &n), NT_ERR_INVALID_ID);
    assert_int_equal(n, 0);
    assert_int_equal(nt_body_get_contacts(NULL, ids[1], &one, 1, &n), NT_ERR_INVALID_ARGUMENT);
    nt_world_destroy(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_broad_phase_matches_brute_force),
        cmocka_unit_test(test_broad_phase_speculative_matches_brute_force),
        cmocka_unit_test(test_broad_phase_skipped),
        cmocka_unit_test(test_filtering),
        cmocka_unit_test(test_sensor_events),
        cmocka_unit_test(test_contact_event_order_and_hits),
        cmocka_unit_test(test_one_way_tiles),
        cmocka_unit_test(test_kinematic_pushes),
        cmocka_unit_test(test_kinematic_carries_riders),
        cmocka_unit_test(test_cell_materials),
        cmocka_unit_test(test_tile_contact_summary),
        cmocka_unit_test(test_floor_angle),
        cmocka_unit_test(test_one_way_bodies),
        cmocka_unit_test(test_body_contact_list),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
