/* World API: creation, definitions and validation, body handles, the allocator
 * hook and out-of-memory behaviour, the state hash (checked against an independent
 * FNV-1a), queries, debug drawing. The physics is in test_world_physics.c, stacks
 * and sleeping in test_world_stack.c, sensors/filters/one-way/kinematic/events in
 * test_world_features.c. */
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

/* ---------------------------------------------------------------- helpers */

static nt_world *make_world(int w, int h, nt_real cell)
{
    nt_world_def d = nt_default_world_def();
    d.map.width = w;
    d.map.height = h;
    d.map.cell_size = cell;
    nt_world *world = NULL;
    assert_int_equal(nt_world_create(&d, &world), NT_OK);
    assert_non_null(world);
    return world;
}

static nt_body_id add_box(nt_world *w, nt_real x, nt_real y, nt_real hw, nt_real hh)
{
    nt_body_def d = nt_default_body_def();
    d.position = nt_v2(x, y);
    d.shape = nt_shape_aabb(hw, hh);
    nt_body_id id;
    assert_int_equal(nt_body_create(w, &d, &id), NT_OK);
    assert_false(nt_body_id_is_null(id));
    return id;
}

static uint64_t fnv_bytes(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    for (size_t i = 0; i < n; i++) {
        h ^= b[i];
        h *= 1099511628211ull;
    }
    return h;
}

/* The documented hash, computed from the public getters in the given order. */
static uint64_t expected_hash(const nt_world *w, const nt_body_id *ids, int n)
{
    uint64_t h = 14695981039346656037ull;
    for (int i = 0; i < n; i++) {
        nt_vec2 p = nt_body_get_position(w, ids[i]), v = nt_body_get_velocity(w, ids[i]);
        h = fnv_bytes(h, &p.x, sizeof p.x);
        h = fnv_bytes(h, &p.y, sizeof p.y);
        h = fnv_bytes(h, &v.x, sizeof v.x);
        h = fnv_bytes(h, &v.y, sizeof v.y);
    }
    return h;
}

/* ---------------------------------------------------------------- world */

static void test_defaults(void **state)
{
    (void)state;
    nt_world_def d = nt_default_world_def();
    assert_int_equal(d.map.width, 31);
    assert_int_equal(d.map.height, 23);
    assert_true(d.map.cell_size == R(24));
    assert_true(d.gravity.x == 0 && d.gravity.y > 0); /* y down */
    assert_int_equal(d.friction_model, NT_FRICTION_N);
    assert_true(d.max_cells_per_step >= 4);
    nt_body_def b = nt_default_body_def();
    assert_int_equal(b.type, NT_BODY_DYNAMIC);
    assert_true(b.mass > 0);
    assert_true(b.shape.half.x <= d.map.cell_size / 2);
    assert_true(b.mask == 0xffffffffu && b.category == 1u);
    nt_world *w = make_world(31, 23, 24);
    assert_int_equal(nt_world_get_body_count(w), 0);
    assert_int_equal(nt_map_get_width(nt_world_get_map(w)), 31);
    assert_int_equal(nt_world_step(w, R(1.0 / 60)), NT_OK);
    nt_world_destroy(w);
    nt_world_destroy(NULL);
}

static void test_world_def_errors(void **state)
{
    (void)state;
    nt_world *w = (nt_world *)&w; /* must be reset to NULL on failure */
    nt_world_def d = nt_default_world_def();
    assert_int_equal(nt_world_create(NULL, &w), NT_ERR_INVALID_ARGUMENT);
    assert_null(w);
    assert_int_equal(nt_world_create(&d, NULL), NT_ERR_INVALID_ARGUMENT);
    d.gravity.y = (nt_real)NAN;
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_NON_FINITE);
    d = nt_default_world_def();
    d.map.cell_size = (nt_real)INFINITY;
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_NON_FINITE);
    d = nt_default_world_def();
    d.map.width = 0;
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_OUT_OF_RANGE);
    d = nt_default_world_def();
    d.friction_model = (nt_friction_model)7;
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_INVALID_ARGUMENT);
    d = nt_default_world_def();
    d.tile_material.friction = R(1.5); /* N's friction is a fraction */
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_INVALID_ARGUMENT);
    d.friction_model = NT_FRICTION_COULOMB; /* but a fine Coulomb mu */
    assert_int_equal(nt_world_create(&d, &w), NT_OK);
    nt_world_destroy(w);
    d = nt_default_world_def();
    d.tile_material.bounce = R(-0.1);
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_INVALID_ARGUMENT);
    d = nt_default_world_def();
    d.max_cells_per_step = R(0.5);
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_OUT_OF_RANGE);
    d = nt_default_world_def();
    d.velocity_iterations = 0;
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_OUT_OF_RANGE);
    d = nt_default_world_def();
    d.sleep_time = R(-1);
    assert_int_equal(nt_world_create(&d, &w), NT_ERR_INVALID_ARGUMENT);
    assert_null(w);
}

static void test_step_errors(void **state)
{
    (void)state;
    nt_world *w = make_world(8, 8, 1);
    add_box(w, 4, 2, R(0.25), R(0.25));
    uint64_t h = nt_world_hash(w);
    assert_int_equal(nt_world_step(w, 0), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_world_step(w, R(-0.1)), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_world_step(w, (nt_real)NAN), NT_ERR_NON_FINITE);
    assert_int_equal(nt_world_step(w, (nt_real)INFINITY), NT_ERR_NON_FINITE);
    assert_int_equal(nt_world_step(NULL, R(0.1)), NT_ERR_INVALID_ARGUMENT);
    assert_true(nt_world_hash(w) == h);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- bodies */

static void test_body_create_and_read_back(void **state)
{
    (void)state;
    nt_world *w = make_world(10, 10, 2);
    nt_body_def d = nt_default_body_def();
    int tag = 5;
    d.position = nt_v2(3, 4);
    d.velocity = nt_v2(R(0.5), R(-1));
    d.shape = nt_shape_circle(R(0.75));
    d.mass = 3;
    d.material.friction = R(0.2);
    d.material.bounce = R(0.7);
    d.category = 4;
    d.mask = 6;
    d.user_data = &tag;
    nt_body_id id;
    assert_int_equal(nt_body_create(w, &d, &id), NT_OK);
    assert_true(nt_body_is_valid(w, id));
    assert_int_equal(nt_world_get_body_count(w), 1);
    assert_int_equal(nt_body_get_type(w, id), NT_BODY_DYNAMIC);
    nt_vec2 p = nt_body_get_position(w, id), v = nt_body_get_velocity(w, id);
    assert_true(p.x == 3 && p.y == 4 && v.x == R(0.5) && v.y == -1);
    nt_shape s = nt_body_get_shape(w, id);
    assert_int_equal(s.type, NT_SHAPE_CIRCLE);
    assert_true(s.half.x == R(0.75));
    assert_true(nt_body_get_mass(w, id) == 3);
    nt_material m = nt_body_get_material(w, id);
    assert_true(m.friction == R(0.2) && m.bounce == R(0.7));
    assert_int_equal(nt_body_get_category(w, id), 4);
    assert_int_equal(nt_body_get_mask(w, id), 6);
    assert_ptr_equal(nt_body_get_user_data(w, id), &tag);
    assert_true(nt_body_is_awake(w, id));
    /* Setters. */
    assert_int_equal(nt_body_set_position(w, id, nt_v2(5, 6)), NT_OK);
    assert_true(nt_body_get_position(w, id).x == 5);
    assert_int_equal(nt_body_set_velocity(w, id, nt_v2(1, 2)), NT_OK);
    assert_int_equal(nt_body_apply_impulse(w, id, nt_v2(3, 0)), NT_OK);
    assert_true(nt_body_get_velocity(w, id).x == 2); /* 1 + 3 / 3 */
    assert_int_equal(nt_body_set_user_data(w, id, NULL), NT_OK);
    assert_null(nt_body_get_user_data(w, id));
    /* Static and kinematic bodies have no mass and static ones no velocity. */
    d = nt_default_body_def();
    d.type = NT_BODY_STATIC;
    d.shape = nt_shape_aabb(R(0.5), R(0.5));
    d.mass = 0;
    d.velocity = nt_v2(9, 9);
    nt_body_id st;
    assert_int_equal(nt_body_create(w, &d, &st), NT_OK);
    assert_true(nt_body_get_mass(w, st) == 0);
    assert_true(nt_body_get_velocity(w, st).x == 0);
    assert_false(nt_body_is_awake(w, st));
    assert_int_equal(nt_body_set_velocity(w, st, nt_v2(1, 0)), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_body_apply_impulse(w, st, nt_v2(1, 0)), NT_ERR_INVALID_ARGUMENT);
    nt_world_destroy(w);
}

/* Every bad definition is rejected with its status and changes nothing. */
static void test_body_def_errors(void **state)
{
    (void)state;
    nt_world *w = make_world(10, 10, 1);
    nt_body_id keep = add_box(w, 5, 5, R(0.25), R(0.25));
    uint64_t h = nt_world_hash(w);
    struct {
        nt_status want;
        int field;
    } cases[] = {
        {NT_ERR_NON_FINITE, 0},       /* NaN position */
        {NT_ERR_NON_FINITE, 1},       /* infinite velocity */
        {NT_ERR_NON_FINITE, 2},       /* NaN mass */
        {NT_ERR_SHAPE_TOO_LARGE, 3},  /* half-width above NT_MAX_HALF_CELLS */
        {NT_ERR_SHAPE_TOO_LARGE, 4},  /* radius above NT_MAX_HALF_CELLS */
        {NT_ERR_INVALID_ARGUMENT, 5}, /* zero size */
        {NT_ERR_INVALID_ARGUMENT, 6}, /* negative size */
        {NT_ERR_INVALID_ARGUMENT, 7}, /* zero mass, dynamic */
        {NT_ERR_INVALID_ARGUMENT, 8}, /* negative mass, dynamic */
        {NT_ERR_INVALID_ARGUMENT, 9}, /* unknown body type */
        {NT_ERR_INVALID_ARGUMENT, 10}, /* unknown shape type */
        {NT_ERR_INVALID_ARGUMENT, 11}, /* circle with unequal halves */
        {NT_ERR_INVALID_ARGUMENT, 12}, /* negative drag */
        {NT_ERR_INVALID_ARGUMENT, 13}, /* bounce above 1 */
        {NT_ERR_INVALID_ARGUMENT, 14}, /* N friction above 1 */
        {NT_ERR_NON_FINITE, 15},      /* NaN gravity scale */
        {NT_ERR_NON_FINITE, 16},      /* infinite half-size */
        {NT_ERR_OUT_OF_RANGE, 17},    /* beyond NT_WORLD_REACH_CELLS to the left */
        {NT_ERR_OUT_OF_RANGE, 18},    /* far below the map */
        {NT_ERR_OUT_OF_RANGE, 19},    /* a denormal mass (its inverse overflows: NaN positions) */
        {NT_ERR_OUT_OF_RANGE, 20},    /* a mass above NT_MAX_MASS */
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        nt_body_def d = nt_default_body_def();
        d.position = nt_v2(2, 2);
        d.shape = nt_shape_aabb(R(0.25), R(0.25));
        switch (cases[k].field) {
        case 0: d.position.x = (nt_real)NAN; break;
        case 1: d.velocity.y = (nt_real)INFINITY; break;
        case 2: d.mass = (nt_real)NAN; break;
        case 3: d.shape = nt_shape_aabb(R(NT_MAX_HALF_CELLS + 0.01), R(0.25)); break;
        case 4: d.shape = nt_shape_circle(R(NT_MAX_HALF_CELLS + 0.0001)); break;
        case 5: d.shape = nt_shape_aabb(0, R(0.25)); break;
        case 6: d.shape = nt_shape_circle(R(-0.1)); break;
        case 7: d.mass = 0; break;
        case 8: d.mass = -2; break;
        case 9: d.type = (nt_body_type)9; break;
        case 10: d.shape.type = (nt_shape_type)3; break;
        case 11: d.shape = nt_shape_circle(R(0.2)), d.shape.half.y = R(0.3); break;
        case 12: d.linear_drag = -1; break;
        case 13: d.material.bounce = R(1.01); break;
        case 14: d.material.friction = R(1.01); break;
        case 15: d.gravity_scale = (nt_real)NAN; break;
        case 16: d.shape.half.x = (nt_real)INFINITY; break;
        case 17: d.position.x = R(-NT_WORLD_REACH_CELLS - 0.01); break;
        case 18: d.position.y = R(1e30); break;
        case 19: d.mass = (nt_real)1.4e-45; break;
        case 20: d.mass = (nt_real)(NT_MAX_MASS * 2); break;
        }
        nt_body_id id = {.index1 = 7, .world0 = 7, .generation = 7};
        assert_int_equal(nt_body_create(w, &d, &id), cases[k].want);
        assert_true(nt_body_id_is_null(id));
        assert_int_equal(nt_world_get_body_count(w), 1);
        assert_true(nt_world_hash(w) == h);
    }
    /* Within reach outside the map is allowed; moving a body beyond it is not. */
    nt_body_def far = nt_default_body_def();
    far.shape = nt_shape_aabb(R(0.25), R(0.25));
    far.type = NT_BODY_STATIC;
    far.position = nt_v2(R(-NT_WORLD_REACH_CELLS + 0.5), R(10 + NT_WORLD_REACH_CELLS - 0.5));
    nt_body_id fid;
    assert_int_equal(nt_body_create(w, &far, &fid), NT_OK);
    nt_vec2 before = nt_body_get_position(w, keep);
    assert_int_equal(nt_body_set_position(w, keep, nt_v2(R(5), R(-3e38))), NT_ERR_OUT_OF_RANGE);
    assert_true(nt_body_get_position(w, keep).x == before.x && nt_body_get_position(w, keep).y == before.y);
    assert_int_equal(nt_body_destroy(w, fid), NT_OK);
    /* Exactly half a cell is allowed, and static bodies need no mass. */
    nt_body_def d = nt_default_body_def();
    d.shape = nt_shape_aabb(R(0.5), R(0.5));
    d.position = nt_v2(2, 2);
    nt_body_id id;
    assert_int_equal(nt_body_create(w, &d, &id), NT_OK);
    d.type = NT_BODY_STATIC;
    d.mass = 0;
    d.position = nt_v2(7, 7);
    assert_int_equal(nt_body_create(w, &d, &id), NT_OK);
    assert_int_equal(nt_body_create(NULL, &d, &id), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_body_create(w, NULL, &id), NT_ERR_INVALID_ARGUMENT);
    /* Setter errors leave the body as it was. */
    nt_vec2 p = nt_body_get_position(w, keep);
    assert_int_equal(nt_body_set_position(w, keep, nt_v2((nt_real)NAN, 0)), NT_ERR_NON_FINITE);
    assert_int_equal(nt_body_set_velocity(w, keep, nt_v2(0, (nt_real)INFINITY)), NT_ERR_NON_FINITE);
    assert_int_equal(nt_body_apply_impulse(w, keep, nt_v2((nt_real)NAN, 0)), NT_ERR_NON_FINITE);
    nt_material bad = {R(2), R(0.5)};
    assert_int_equal(nt_body_set_material(w, keep, bad), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_body_set_linear_drag(w, keep, -1), NT_ERR_INVALID_ARGUMENT);
    assert_true(nt_body_get_position(w, keep).x == p.x);
    assert_true(nt_body_get_material(w, keep).friction == R(0.05));
    nt_world_destroy(w);
}

/* A handle names its world: the same slot and generation in another world is
 * refused there, and that world is left as it was. */
static void test_ids_name_their_world(void **state)
{
    (void)state;
    nt_world *w1 = make_world(10, 10, 1), *w2 = make_world(10, 10, 1);
    nt_body_id a = add_box(w1, 2, 2, R(0.2), R(0.2));
    nt_body_id b = add_box(w2, 5, 2, R(0.2), R(0.2));
    assert_int_equal(a.index1, b.index1);
    assert_true(a.generation == b.generation);
    assert_true(a.world0 != 0 && b.world0 != 0 && a.world0 != b.world0);
    assert_false(nt_body_id_equals(a, b));
    uint64_t h2 = nt_world_hash(w2);
    assert_false(nt_body_is_valid(w2, a));
    assert_int_equal(nt_body_set_position(w2, a, nt_v2(1, 1)), NT_ERR_INVALID_ID);
    assert_int_equal(nt_body_set_velocity(w2, a, nt_v2(1, 1)), NT_ERR_INVALID_ID);
    assert_int_equal(nt_body_destroy(w2, a), NT_ERR_INVALID_ID);
    assert_true(nt_body_get_position(w2, a).x == 0);
    assert_true(nt_world_hash(w2) == h2);
    assert_int_equal(nt_world_get_body_count(w2), 1);
    assert_true(nt_body_is_valid(w2, b));
    assert_true(nt_body_is_valid(w1, a));
    /* Event and query handles name their world too. */
    nt_world_ray_hit hit;
    assert_true(nt_world_raycast(w2, nt_v2(5, 0), nt_v2(5, 4), nt_default_query_filter(), &hit));
    assert_true(nt_body_id_equals(hit.body, b));
    nt_world_destroy(w1);
    nt_world_destroy(w2);
}

/* A stack of boxes on a floor, for the iteration tests: 12 boxes falling onto each other. */
static nt_world *iteration_stack(int velocity_iterations, int position_iterations)
{
    nt_world_def d = nt_default_world_def();
    d.map.width = 8;
    d.map.height = 20;
    d.map.cell_size = 1;
    d.gravity = nt_v2(0, 10);
    d.velocity_iterations = velocity_iterations;
    d.position_iterations = position_iterations;
    d.enable_sleep = false;
    nt_world *w = NULL;
    assert_int_equal(nt_world_create(&d, &w), NT_OK);
    for (int x = 0; x < 8; x++) assert_int_equal(nt_world_set_tile(w, x, 19, NT_TILE_FULL), NT_OK);
    for (int k = 0; k < 12; k++) add_box(w, 4, (nt_real)(18.6 - 0.85 * k), R(0.4), R(0.4));
    return w;
}

/* Iterations changed on a live world act from the next step exactly as if the world
 * had been made with them; values out of range are refused and change nothing. */
static void test_set_iterations(void **state)
{
    (void)state;
    nt_world *a = iteration_stack(8, 4), *b = iteration_stack(1, 0), *c = iteration_stack(8, 4);
    int vi = -1, pi = -1;
    nt_world_get_iterations(a, &vi, &pi);
    assert_int_equal(vi, 8);
    assert_int_equal(pi, 4);
    assert_int_equal(nt_world_set_iterations(a, 1, 0), NT_OK);
    nt_world_get_iterations(a, &vi, &pi);
    assert_int_equal(vi, 1);
    assert_int_equal(pi, 0);
    for (int k = 0; k < 120; k++) {
        assert_int_equal(nt_world_step(a, R(1.0 / 60)), NT_OK);
        assert_int_equal(nt_world_step(b, R(1.0 / 60)), NT_OK);
        assert_int_equal(nt_world_step(c, R(1.0 / 60)), NT_OK);
    }
    assert_true(nt_world_hash(a) == nt_world_hash(b)); /* as if made with them */
    assert_true(nt_world_hash(a) != nt_world_hash(c)); /* and they do change the answer */
    const int bad[][2] = {{0, 4}, {65, 4}, {8, -1}, {8, 65}};
    for (int k = 0; k < 4; k++) {
        assert_int_equal(nt_world_set_iterations(a, bad[k][0], bad[k][1]), NT_ERR_OUT_OF_RANGE);
        nt_world_get_iterations(a, &vi, &pi);
        assert_int_equal(vi, 1);
        assert_int_equal(pi, 0);
    }
    assert_int_equal(nt_world_set_iterations(NULL, 8, 4), NT_ERR_INVALID_ARGUMENT);
    nt_world_get_iterations(NULL, &vi, &pi);
    assert_int_equal(vi, 0);
    nt_world_destroy(a);
    nt_world_destroy(b);
    nt_world_destroy(c);
}

static void test_stale_ids(void **state)
{
    (void)state;
    nt_world *w = make_world(10, 10, 1);
    nt_body_id a = add_box(w, 2, 2, R(0.2), R(0.2));
    nt_body_id b = add_box(w, 5, 2, R(0.2), R(0.2));
    assert_false(nt_body_id_equals(a, b));
    assert_int_equal(nt_body_destroy(w, a), NT_OK);
    assert_false(nt_body_is_valid(w, a));
    assert_int_equal(nt_body_destroy(w, a), NT_ERR_INVALID_ID);
    assert_int_equal(nt_world_get_body_count(w), 1);
    /* The slot is reused with a new generation: the old handle stays dead. */
    nt_body_id c = add_box(w, 7, 2, R(0.2), R(0.2));
    assert_int_equal(c.index1, a.index1);
    assert_true(c.generation != a.generation);
    assert_false(nt_body_is_valid(w, a));
    assert_true(nt_body_is_valid(w, c));
    assert_int_equal(nt_body_set_position(w, a, nt_v2(1, 1)), NT_ERR_INVALID_ID);
    assert_int_equal(nt_body_set_velocity(w, a, nt_v2(1, 1)), NT_ERR_INVALID_ID);
    assert_int_equal(nt_body_apply_impulse(w, a, nt_v2(1, 1)), NT_ERR_INVALID_ID);
    assert_int_equal(nt_body_set_filter(w, a, 1, 1), NT_ERR_INVALID_ID);
    assert_int_equal(nt_body_set_awake(w, a, true), NT_ERR_INVALID_ID);
    nt_body_tile_contacts tc;
    assert_int_equal(nt_body_get_tile_contacts(w, a, &tc), NT_ERR_INVALID_ID);
    /* Getters give zero values for dead, null and never-issued handles. */
    assert_true(nt_body_get_position(w, a).x == 0);
    assert_true(nt_body_get_mass(w, a) == 0);
    nt_body_id never = {.index1 = 1000, .world0 = a.world0, .generation = 1};
    assert_false(nt_body_is_valid(w, never));
    assert_false(nt_body_is_valid(w, nt_null_body_id()));
    assert_int_equal(nt_body_destroy(w, never), NT_ERR_INVALID_ID);
    assert_int_equal(nt_body_destroy(w, nt_null_body_id()), NT_ERR_INVALID_ID);
    /* c did not inherit a's state. */
    assert_true(nt_body_get_position(w, c).x == 7);
    assert_true(nt_body_is_valid(w, b));
    nt_world_destroy(w);
}

/* Many bodies (growth of every array), destroyed in a scattered order. */
static void test_many_bodies(void **state)
{
    (void)state;
    nt_world *w = make_world(64, 64, 1);
    enum { N = 3000 };
    static nt_body_id ids[N];
    for (int i = 0; i < N; i++) ids[i] = add_box(w, R(1.5) + (nt_real)(i % 60), R(1.5) + (nt_real)(i / 60), R(0.2), R(0.2));
    assert_int_equal(nt_world_get_body_count(w), N);
    for (int i = 0; i < N; i += 3) assert_int_equal(nt_body_destroy(w, ids[i]), NT_OK);
    for (int i = 0; i < N; i++) assert_int_equal(nt_body_is_valid(w, ids[i]), i % 3 != 0);
    for (int s = 0; s < 5; s++) assert_int_equal(nt_world_step(w, R(1.0 / 60)), NT_OK);
    assert_int_equal(nt_world_get_body_count(w), N - N / 3);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- allocator */

static struct {
    long allocs, frees, live, fail_after; /* fail_after < 0: never fail */
} g_alloc;

static void *count_alloc(size_t size, void *user)
{
    (void)user;
    if (g_alloc.fail_after == 0) return NULL;
    if (g_alloc.fail_after > 0) g_alloc.fail_after--;
    g_alloc.allocs++;
    g_alloc.live++;
    return malloc(size);
}

static void count_free(void *p, void *user)
{
    (void)user;
    g_alloc.frees++;
    g_alloc.live--;
    free(p);
}

static void test_allocator_hook(void **state)
{
    (void)state;
    memset(&g_alloc, 0, sizeof g_alloc);
    g_alloc.fail_after = -1;
    nt_set_allocator(count_alloc, count_free, NULL);
    nt_world *w = make_world(20, 20, 1);
    for (int i = 0; i < 200; i++) add_box(w, R(2) + (nt_real)(i % 16), R(2) + (nt_real)(i / 16), R(0.3), R(0.3));
    for (int s = 0; s < 60; s++) assert_int_equal(nt_world_step(w, R(1.0 / 60)), NT_OK);
    assert_true(g_alloc.allocs > 0);
    nt_world_destroy(w);
    nt_set_allocator(NULL, NULL, NULL);
    assert_int_equal(g_alloc.live, 0);
    assert_int_equal(g_alloc.allocs, g_alloc.frees);
}

/* Out of memory: creation and stepping fail with a status and change nothing. */
static void test_out_of_memory(void **state)
{
    (void)state;
    memset(&g_alloc, 0, sizeof g_alloc);
    g_alloc.fail_after = -1;
    nt_set_allocator(count_alloc, count_free, NULL);
    nt_world_def d = nt_default_world_def();
    d.map.width = 8;
    d.map.height = 8;
    d.map.cell_size = 1;
    d.gravity = nt_v2(0, 0);
    d.body_capacity = 2;
    /* World creation fails cleanly at every allocation. */
    for (long k = 0; k < 4; k++) {
        g_alloc.fail_after = k;
        nt_world *bad = (nt_world *)&bad;
        nt_status s = nt_world_create(&d, &bad);
        if (s == NT_OK) {
            nt_world_destroy(bad);
            break;
        }
        assert_int_equal(s, NT_ERR_OUT_OF_MEMORY);
        assert_null(bad);
    }
    g_alloc.fail_after = -1;
    nt_world *w = NULL;
    assert_int_equal(nt_world_create(&d, &w), NT_OK);
    nt_body_id a = add_box(w, 2, 4, R(0.3), R(0.3));
    nt_body_id b = add_box(w, R(2.5), 4, R(0.3), R(0.3)); /* overlapping a: the step needs contacts */
    assert_int_equal(nt_body_set_velocity(w, a, nt_v2(1, 0)), NT_OK);
    /* A third body needs the body arrays to grow. */
    uint64_t h = nt_world_hash(w);
    g_alloc.fail_after = 0;
    nt_body_def bd = nt_default_body_def();
    bd.shape = nt_shape_aabb(R(0.3), R(0.3));
    bd.position = nt_v2(6, 6);
    nt_body_id c;
    assert_int_equal(nt_body_create(w, &bd, &c), NT_ERR_OUT_OF_MEMORY);
    assert_true(nt_body_id_is_null(c));
    assert_int_equal(nt_world_get_body_count(w), 2);
    assert_true(nt_world_hash(w) == h);
    /* The first step with a contact needs its buffers. */
    assert_int_equal(nt_world_step(w, R(0.01)), NT_ERR_OUT_OF_MEMORY);
    assert_true(nt_world_hash(w) == h);
    assert_int_equal(nt_world_get_contact_events(w).begin_count, 0);
    g_alloc.fail_after = -1;
    assert_int_equal(nt_world_step(w, R(0.01)), NT_OK);
    assert_true(nt_world_hash(w) != h);
    assert_int_equal(nt_world_get_contact_events(w).begin_count, 1);
    assert_int_equal(nt_body_create(w, &bd, &c), NT_OK);
    (void)b;
    nt_world_destroy(w);
    nt_set_allocator(NULL, NULL, NULL);
    assert_int_equal(g_alloc.live, 0);
}

/* ---------------------------------------------------------------- hash */

static void test_hash_matches_definition(void **state)
{
    (void)state;
    nt_world *w = make_world(20, 20, 1);
    nt_body_id ids[4];
    ids[0] = add_box(w, 3, 3, R(0.3), R(0.3));
    ids[1] = add_box(w, 6, 3, R(0.3), R(0.3));
    ids[2] = add_box(w, 9, 3, R(0.3), R(0.3));
    for (int s = 0; s < 10; s++) nt_world_step(w, R(1.0 / 60));
    assert_true(nt_world_hash(w) == expected_hash(w, ids, 3));
    /* Creation order, not slot order: a reused slot goes last. */
    assert_int_equal(nt_body_destroy(w, ids[0]), NT_OK);
    ids[3] = add_box(w, 12, 3, R(0.3), R(0.3));
    assert_int_equal(ids[3].index1, ids[0].index1);
    assert_true(nt_world_hash(w) == expected_hash(w, ids + 1, 3));
    nt_body_id swapped[3] = {ids[3], ids[1], ids[2]};
    assert_true(nt_world_hash(w) != expected_hash(w, swapped, 3));
    nt_world_destroy(w);
    /* An empty world hashes to the FNV offset basis. */
    w = make_world(4, 4, 1);
    assert_true(nt_world_hash(w) == 14695981039346656037ull);
    nt_world_destroy(w);
}

/* A scene with tiles, bodies of both shapes, contacts and sleeping. */
static nt_world *golden_scene(void)
{
    nt_world_def d = nt_default_world_def();
    d.map.width = 16;
    d.map.height = 12;
    d.friction_model = NT_FRICTION_COULOMB;
    d.tile_material.friction = R(0.4);
    nt_world *w = NULL;
    assert_int_equal(nt_world_create(&d, &w), NT_OK);
    for (int x = 0; x < 16; x++) nt_world_set_tile(w, x, 11, NT_TILE_FULL);
    nt_world_set_tile(w, 3, 10, NT_TILE_45DEGnn);
    nt_world_set_tile(w, 12, 10, NT_TILE_CONVEXpn);
    nt_world_set_tile(w, 8, 6, NT_TILE_HALFd);
    unsigned seed = 7;
    for (int i = 0; i < 40; i++) {
        nt_body_def b = nt_default_body_def();
        seed = seed * 1664525u + 1013904223u;
        nt_real r = R(4) + (nt_real)(seed >> 24) / 32;
        b.shape = (i & 1) ? nt_shape_circle(r) : nt_shape_aabb(r, R(10) - r / 2);
        b.position = nt_v2(R(30) + (nt_real)(i % 10) * 32, R(20) + (nt_real)(i / 10) * 30);
        b.velocity = nt_v2((nt_real)((int)(seed >> 16 & 63) - 32), 0);
        b.material.friction = R(0.4);
        b.mass = R(1) + (nt_real)(i % 3);
        nt_body_id id;
        assert_int_equal(nt_body_create(w, &b, &id), NT_OK);
    }
    return w;
}

/* Same inputs, same bits; and the bits of this build are pinned (a change in any
 * result of the simulation, the map's resolution included, shows up here first).
 * The same values come out of gcc and clang at -O0, -O2 and -O3 (checked by hand;
 * `make` builds only one configuration). Update both constants, from the printed
 * line, only for an intended change of behaviour. */
static void test_determinism_and_golden_hash(void **state)
{
    (void)state;
    nt_world *w1 = golden_scene(), *w2 = golden_scene();
    for (int s = 0; s < 300; s++) {
        assert_int_equal(nt_world_step(w1, R(1.0 / 40)), NT_OK);
        assert_int_equal(nt_world_step(w2, R(1.0 / 40)), NT_OK);
    }
    uint64_t h = nt_world_hash(w1);
    assert_true(h == nt_world_hash(w2));
    printf("golden hash (%s): 0x%016llx\n", NT_REAL_IS_DOUBLE ? "double" : "float", (unsigned long long)h);
#if NT_REAL_IS_DOUBLE
    const uint64_t golden = 0xb79d9ece8afe4a4eull;
#else
    const uint64_t golden = 0x998b05d3e2629ba1ull;
#endif
    assert_true(h == golden);
    nt_world_destroy(w1);
    nt_world_destroy(w2);
}

/* The profile: zero until enabled; then each step's phases, none negative, adding
 * up to the step, and some time in all; zero again when disabled; the same hash
 * either way (timing never feeds the simulation). */
static void test_profile(void **state)
{
    (void)state;
    nt_world *w = golden_scene(), *plain = golden_scene();
    nt_world_profile p = nt_world_get_profile(w);
    assert_true(p.step == 0 && p.pairs == 0 && p.move == 0);
    assert_int_equal(nt_world_step(w, R(1.0 / 40)), NT_OK);
    assert_int_equal(nt_world_step(plain, R(1.0 / 40)), NT_OK);
    assert_true(nt_world_get_profile(w).step == 0);
    nt_world_enable_profile(w, true);
    double total = 0;
    for (int s = 0; s < 50; s++) {
        assert_int_equal(nt_world_step(w, R(1.0 / 40)), NT_OK);
        assert_int_equal(nt_world_step(plain, R(1.0 / 40)), NT_OK);
        p = nt_world_get_profile(w);
        double parts[6] = {p.pairs, p.contacts, p.correct, p.solve, p.move, p.sleep}, sum = 0;
        for (int k = 0; k < 6; k++) {
            assert_true(parts[k] >= 0);
            sum += parts[k];
        }
        assert_true(fabs(sum - p.step) <= 1e-9 * (1 + p.step));
        total += p.step;
    }
    assert_true(total > 0); /* 50 steps of a few hundred bodies take measurable time */
    assert_true(nt_world_hash(w) == nt_world_hash(plain));
    nt_world_enable_profile(w, false);
    p = nt_world_get_profile(w);
    assert_true(p.step == 0 && p.solve == 0);
    assert_int_equal(nt_world_step(w, R(1.0 / 40)), NT_OK);
    assert_true(nt_world_get_profile(w).step == 0);
    p = nt_world_get_profile(NULL);
    assert_true(p.step == 0);
    nt_world_enable_profile(NULL, true); /* ignored */
    nt_world_destroy(w);
    nt_world_destroy(plain);
}

/* Huge gravity times a huge gravity scale overflows the velocity: the step keeps it
 * finite, at the speed limit, pointing the way gravity pulls (found by the fuzzer). */
static void test_velocity_overflow(void **state)
{
    (void)state;
    nt_world *w = make_world(10, 40, 1);
    nt_body_id id = add_box(w, 5, 5, R(0.25), R(0.25));
    /* Gravity and scale beyond their ranges are refused; at the largest of both the
     * velocity after a step is 1e18 / 60, far beyond the limit. */
    assert_int_equal(nt_world_set_gravity(w, nt_v2(0, R(3e38))), NT_ERR_OUT_OF_RANGE);
    assert_int_equal(nt_body_set_gravity_scale(w, id, R(3e38)), NT_ERR_OUT_OF_RANGE);
    assert_int_equal(nt_world_set_gravity(w, nt_v2(0, (nt_real)NT_MAX_GRAVITY)), NT_OK);
    assert_int_equal(nt_body_set_gravity_scale(w, id, (nt_real)NT_MAX_GRAVITY_SCALE), NT_OK);
    nt_world_def d = nt_default_world_def();
    nt_real dt = R(1.0 / 60);
    assert_int_equal(nt_world_step(w, dt), NT_OK);
    nt_vec2 v = nt_body_get_velocity(w, id), p = nt_body_get_position(w, id);
    assert_true(isfinite((double)v.x) && isfinite((double)v.y) && isfinite((double)p.y));
    assert_true(v.x == 0 && v.y > 0);
    /* The body moved down by the speed limit, max_cells_per_step cells (cell 1). */
    assert_true(fabs((double)p.y - 5 - (double)d.max_cells_per_step) < 1e-4);
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- queries */

static int g_found[16], g_nfound;

static bool collect(nt_body_id id, void *ctx)
{
    (void)ctx;
    if (g_nfound < 16) g_found[g_nfound++] = id.index1;
    return true;
}

static bool stop_at_first(nt_body_id id, void *ctx)
{
    (void)id;
    (*(int *)ctx)++;
    return false;
}

static void test_point_and_aabb_queries(void **state)
{
    (void)state;
    nt_world *w = make_world(20, 20, 1);
    nt_body_id box = add_box(w, 5, 5, R(0.25), R(0.25));
    nt_body_def d = nt_default_body_def();
    d.shape = nt_shape_circle(R(0.5));
    d.position = nt_v2(8, 5);
    nt_body_id circ;
    assert_int_equal(nt_body_create(w, &d, &circ), NT_OK);
    nt_query_filter f = nt_default_query_filter();
    g_nfound = 0;
    assert_int_equal(nt_world_query_point(w, nt_v2(R(5.2), R(4.8)), f, collect, NULL), 1);
    assert_int_equal(g_found[0], box.index1);
    /* The boundary is not inside. */
    assert_int_equal(nt_world_query_point(w, nt_v2(R(5.25), 5), f, NULL, NULL), 0);
    assert_int_equal(nt_world_query_point(w, nt_v2(R(8.5), 5), f, NULL, NULL), 0);
    assert_int_equal(nt_world_query_point(w, nt_v2(R(8.3), R(5.3)), f, NULL, NULL), 1);
    assert_int_equal(nt_world_query_point(w, nt_v2(R(8.4), R(5.4)), f, NULL, NULL), 0); /* outside the circle's corner */
    /* Boxes: touching is not overlapping. */
    assert_int_equal(nt_world_overlap_aabb(w, nt_v2(R(5.25), 0), nt_v2(8, R(4.5)), f, NULL, NULL), 0);
    assert_int_equal(nt_world_overlap_aabb(w, nt_v2(R(5.2), 0), nt_v2(R(7.4), 5), f, NULL, NULL), 1);
    g_nfound = 0;
    assert_int_equal(nt_world_overlap_aabb(w, nt_v2(0, 0), nt_v2(19, 19), f, collect, NULL), 2);
    /* The corner of the box is 0.5 * sqrt(2) * ... from the circle centre: outside. */
    assert_int_equal(nt_world_overlap_aabb(w, nt_v2(R(8.4), R(5.4)), nt_v2(9, 6), f, NULL, NULL), 0);
    assert_int_equal(nt_world_overlap_aabb(w, nt_v2(R(8.3), R(5.3)), nt_v2(9, 6), f, NULL, NULL), 1);
    /* Filters and early stop. */
    f.mask = 2;
    assert_int_equal(nt_world_overlap_aabb(w, nt_v2(0, 0), nt_v2(19, 19), f, NULL, NULL), 0);
    f = nt_default_query_filter();
    int calls = 0;
    assert_int_equal(nt_world_overlap_aabb(w, nt_v2(0, 0), nt_v2(19, 19), f, stop_at_first, &calls), 1);
    assert_int_equal(calls, 1);
    /* Bodies outside the map are still found. */
    nt_body_id far = add_box(w, -30, 5, R(0.25), R(0.25));
    assert_int_equal(nt_world_query_point(w, nt_v2(-30, 5), f, NULL, NULL), 1);
    (void)far;
    nt_world_destroy(w);
}

static void test_raycast(void **state)
{
    (void)state;
    nt_world *w = make_world(20, 10, 1);
    nt_world_set_tile(w, 15, 5, NT_TILE_FULL);
    nt_body_id box = add_box(w, 5, R(5.5), R(0.25), R(0.25));
    nt_body_def d = nt_default_body_def();
    d.shape = nt_shape_circle(R(0.5));
    d.position = nt_v2(10, R(5.5));
    nt_body_id circ;
    assert_int_equal(nt_body_create(w, &d, &circ), NT_OK);
    nt_query_filter f = nt_default_query_filter();
    nt_world_ray_hit hit;
    /* Along y = 5.5 from x = 1: the box's left face at x = 4.75. */
    assert_true(nt_world_raycast(w, nt_v2(1, R(5.5)), nt_v2(19, R(5.5)), f, &hit));
    assert_true(nt_body_id_equals(hit.body, box));
    assert_true(fabs((double)hit.fraction - 3.75 / 18) < 1e-6);
    assert_true(hit.normal.x == -1 && hit.normal.y == 0);
    /* From x = 6 the circle comes first, at x = 9.5. */
    assert_true(nt_world_raycast(w, nt_v2(6, R(5.5)), nt_v2(19, R(5.5)), f, &hit));
    assert_true(nt_body_id_equals(hit.body, circ));
    assert_true(fabs((double)hit.point.x - 9.5) < 1e-5);
    /* From x = 11 only the tile remains: its left edge x = 15. */
    assert_true(nt_world_raycast(w, nt_v2(11, R(5.5)), nt_v2(19, R(5.5)), f, &hit));
    assert_true(nt_body_id_is_null(hit.body));
    assert_true(fabs((double)hit.point.x - 15) < 1e-5);
    assert_int_equal(hit.cell_x, 15);
    f.tiles = false;
    assert_false(nt_world_raycast(w, nt_v2(11, R(5.5)), nt_v2(19, R(5.5)), f, &hit));
    f = nt_default_query_filter();
    /* Grazing the box's top edge (y = 5.25) is not a hit. */
    assert_false(nt_world_raycast(w, nt_v2(1, R(5.25)), nt_v2(R(7.5), R(5.25)), f, &hit));
    /* Tangent to the circle (y = 5) is not a hit; a little lower is. */
    assert_false(nt_world_raycast(w, nt_v2(7, 5), nt_v2(13, 5), f, &hit));
    assert_true(nt_world_raycast(w, nt_v2(7, R(5.01)), nt_v2(13, R(5.01)), f, &hit));
    /* Starting inside a body: t = 0 and no normal. */
    assert_true(nt_world_raycast(w, nt_v2(5, R(5.5)), nt_v2(5, 1), f, &hit));
    assert_true(hit.fraction == 0 && hit.normal.x == 0 && hit.normal.y == 0);
    /* Diagonal ray at the circle: first point on it, normal from the centre. */
    assert_true(nt_world_raycast(w, nt_v2(7, R(2.5)), nt_v2(13, R(8.5)), f, &hit));
    nt_vec2 q = hit.point;
    assert_true(fabs(sqrt((double)((q.x - 10) * (q.x - 10) + (q.y - R(5.5)) * (q.y - R(5.5)))) - 0.5) < 1e-5);
    assert_true(fabs((double)hit.normal.x - (double)(q.x - 10) / 0.5) < 1e-4);
    /* Too short. */
    assert_false(nt_world_raycast(w, nt_v2(1, R(5.5)), nt_v2(4, R(5.5)), f, &hit));
    nt_world_destroy(w);
}

/* Rays with far-away ends cost a walk over the map only, and still see bodies that
 * lie outside the map (found by the fuzzer: a walk through 1e9 empty cells). */
static void test_far_rays(void **state)
{
    (void)state;
    nt_world *w = make_world(20, 10, 1);
    nt_body_id in = add_box(w, 5, R(5.5), R(0.25), R(0.25));
    nt_body_def d = nt_default_body_def();
    d.type = NT_BODY_STATIC;
    d.shape = nt_shape_circle(R(0.5));
    d.position = nt_v2(-30, R(2.5)); /* outside the map, within reach */
    nt_body_id out;
    assert_int_equal(nt_body_create(w, &d, &out), NT_OK);
    nt_query_filter f = nt_default_query_filter();
    f.tiles = false;
    nt_world_ray_hit hit;
    /* From far left to far right through the box (as far as float still resolves a
     * quarter cell there): it enters at x = 4.75. */
    assert_true(nt_world_raycast(w, nt_v2(R(-1e5), R(5.5)), nt_v2(R(1e5), R(5.5)), f, &hit));
    assert_true(nt_body_id_equals(hit.body, in));
    assert_true(fabs((double)hit.point.x - 4.75) < 0.02);
    assert_true(hit.normal.x == -1 && hit.normal.y == 0);
    /* Along y = 2.5 from far left: the circle outside the map comes first. */
    assert_true(nt_world_raycast(w, nt_v2(R(-1e3), R(2.5)), nt_v2(R(1e3), R(2.5)), f, &hit));
    assert_true(nt_body_id_equals(hit.body, out));
    assert_true(hit.normal.x < -0.99f);
    /* Far segments that never come near the map miss, at once (not a walk through
     * 1e29 cells). */
    assert_false(nt_world_raycast(w, nt_v2(R(-1e30), R(5.5)), nt_v2(R(-1e29), R(5.5)), f, &hit));
    assert_false(nt_world_raycast(w, nt_v2(R(-1e30), R(-1e30)), nt_v2(R(-1e29), R(-1e30)), f, &hit));
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- draw */

typedef struct draw_log {
    int polygons, boxes, circles, segments;
    int max_vertices;
    double max_arc_error; /* round tiles: arc points off the radius-1 circle (cells) */
} draw_log;

static void d_polygon(const nt_vec2 *v, int n, uint32_t color, void *ctx)
{
    draw_log *l = (draw_log *)ctx;
    (void)color;
    l->polygons++;
    if (n > l->max_vertices) l->max_vertices = n;
    if (n > 4) {
        /* The CONVEXpn tile at cell (2, 2), size 2: arc centred on (2*2, 2*2 + 2). */
        for (int k = 3; k < n; k++) {
            double dx = (double)v[k].x - 4, dy = (double)v[k].y - 6;
            double e = fabs(sqrt(dx * dx + dy * dy) - 2);
            if (e > l->max_arc_error) l->max_arc_error = e;
        }
    }
}
static void d_box(nt_vec2 lo, nt_vec2 hi, uint32_t c, void *ctx)
{
    (void)lo, (void)hi, (void)c;
    ((draw_log *)ctx)->boxes++;
}
static void d_circle(nt_vec2 p, nt_real r, uint32_t c, void *ctx)
{
    (void)p, (void)r, (void)c;
    ((draw_log *)ctx)->circles++;
}
static void d_segment(nt_vec2 a, nt_vec2 b, uint32_t c, void *ctx)
{
    (void)a, (void)b, (void)c;
    ((draw_log *)ctx)->segments++;
}

static void test_debug_draw(void **state)
{
    (void)state;
    nt_world *w = make_world(10, 10, 2);
    nt_world_set_tile(w, 5, 5, NT_TILE_FULL);
    nt_world_set_tile(w, 2, 2, NT_TILE_CONVEXpn);
    add_box(w, 15, 3, R(0.5), R(0.5));
    nt_body_def d = nt_default_body_def();
    d.shape = nt_shape_circle(R(0.5));
    d.position = nt_v2(3, 15);
    nt_body_id id;
    assert_int_equal(nt_body_create(w, &d, &id), NT_OK);
    draw_log log;
    memset(&log, 0, sizeof log);
    nt_debug_draw dd = nt_default_debug_draw();
    dd.draw_polygon = d_polygon;
    dd.draw_box = d_box;
    dd.draw_circle = d_circle;
    dd.draw_segment = d_segment;
    dd.context = &log;
    nt_world_draw(w, &dd);
    assert_int_equal(log.polygons, 2);
    assert_int_equal(log.boxes, 1);
    assert_int_equal(log.circles, 1);
    assert_int_equal(log.segments, 0);
    assert_true(log.max_vertices > 4);
    assert_true(log.max_arc_error < 1e-4);
    /* Edges: the FULL tile has 4 SOLID edges seen from its 4 neighbours... */
    memset(&log, 0, sizeof log);
    dd.draw_tiles = false;
    dd.draw_bodies = false;
    dd.draw_edges = true;
    nt_world_draw(w, &dd);
    assert_true(log.segments >= 4);
    /* ...and a bounds box that holds nothing draws nothing. */
    memset(&log, 0, sizeof log);
    dd = nt_default_debug_draw();
    dd.draw_polygon = d_polygon;
    dd.draw_box = d_box;
    dd.draw_circle = d_circle;
    dd.context = &log;
    dd.use_bounds = true;
    dd.bounds_lo = nt_v2(16, 16);
    dd.bounds_hi = nt_v2(19, 19);
    nt_world_draw(w, &dd);
    assert_int_equal(log.polygons + log.boxes + log.circles, 0);
    /* NULL callbacks are skipped. */
    nt_debug_draw none = nt_default_debug_draw();
    none.draw_contacts = none.draw_grid = none.draw_velocities = none.draw_tile_contacts = true;
    nt_world_draw(w, &none);
    nt_world_destroy(w);
}

/* Gizmos: arrows, points, text, rays, projections and the velocity split, checked
 * against what the world reports through its own getters and the ray cast. */
typedef struct gizmo_log {
    int arrows, points, texts, segments;
    nt_vec2 a0[64], a1[64];
    uint32_t acolor[64];
    nt_vec2 point;
    char text[200];
} gizmo_log;

static void g_arrow(nt_vec2 a, nt_vec2 b, uint32_t c, void *ctx)
{
    gizmo_log *l = (gizmo_log *)ctx;
    if (l->arrows < 64) {
        l->a0[l->arrows] = a;
        l->a1[l->arrows] = b;
        l->acolor[l->arrows] = c;
    }
    l->arrows++;
}
static void g_point(nt_vec2 p, uint32_t c, void *ctx)
{
    (void)c;
    ((gizmo_log *)ctx)->points++;
    ((gizmo_log *)ctx)->point = p;
}
static void g_text(nt_vec2 p, const char *t, uint32_t c, void *ctx)
{
    (void)p, (void)c;
    gizmo_log *l = (gizmo_log *)ctx;
    l->texts++;
    snprintf(l->text, sizeof l->text, "%s", t);
}
static void g_segment(nt_vec2 a, nt_vec2 b, uint32_t c, void *ctx)
{
    (void)a, (void)b, (void)c;
    ((gizmo_log *)ctx)->segments++;
}

/* The arrow of colour c (the last one drawn), as a vector. */
static nt_vec2 arrow_of(const gizmo_log *l, uint32_t c, int *found)
{
    nt_vec2 v = nt_v2(0, 0);
    *found = 0;
    for (int i = 0; i < l->arrows && i < 64; i++)
        if (l->acolor[i] == c) {
            v = nt_v2(l->a1[i].x - l->a0[i].x, l->a1[i].y - l->a0[i].y);
            *found = 1;
        }
    return v;
}

static void test_debug_draw_gizmos(void **state)
{
    (void)state;
    nt_world *w = make_world(10, 10, 2); /* cell 2: floor top at y = 10 */
    for (int x = 0; x < 10; x++) nt_world_set_tile(w, x, 5, NT_TILE_FULL);
    nt_body_id id = add_box(w, 5, R(9.4), R(0.5), R(0.5));
    assert_int_equal(nt_body_set_velocity(w, id, nt_v2(6, 0)), NT_OK);
    for (int s = 0; s < 10; s++) assert_int_equal(nt_world_step(w, R(1.0 / 60)), NT_OK);
    nt_body_tile_contacts tc;
    assert_int_equal(nt_body_get_tile_contacts(w, id, &tc), NT_OK);
    assert_true(tc.on_floor && tc.count == 1);
    nt_vec2 v = nt_body_get_velocity(w, id);
    assert_true(v.x > 1); /* still sliding */

    nt_debug_ray ray;
    memset(&ray, 0, sizeof ray);
    ray.p0 = nt_v2(1, 1);
    ray.p1 = nt_v2(1, 15);
    ray.hit = nt_world_raycast(w, ray.p0, ray.p1, nt_default_query_filter(), &ray.result);
    assert_true(ray.hit);

    gizmo_log log;
    memset(&log, 0, sizeof log);
    nt_debug_draw dd = nt_default_debug_draw();
    dd.draw_tiles = dd.draw_bodies = false;
    dd.draw_arrow = g_arrow;
    dd.draw_point = g_point;
    dd.draw_text = g_text;
    dd.draw_segment = g_segment;
    dd.draw_tile_contacts = dd.draw_projections = dd.draw_velocity_split = dd.draw_stats = true;
    dd.rays = &ray;
    dd.ray_count = 1;
    dd.context = &log;
    nt_world_draw(w, &dd);
    int f;
    /* Tile contact normal: up, half a cell long. */
    nt_vec2 n = arrow_of(&log, 0xe08040u, &f);
    assert_true(f && fabs((double)n.x) < 1e-6 && fabs((double)n.y + 1) < 1e-6);
    /* Projection: along the normal, the contact's depth long (a skin: tiny but > 0). */
    nt_vec2 pr = arrow_of(&log, 0xffe040u, &f);
    assert_true(f && pr.x == 0 && pr.y < 0 && pr.y > -0.01);
    /* Velocity split against the floor: no normal part, the tangential part is v * 0.1 s. */
    nt_vec2 vn = arrow_of(&log, 0xe04040u, &f);
    assert_true(f && fabs((double)vn.x) < 1e-6 && fabs((double)vn.y) < 1e-6);
    nt_vec2 vt = arrow_of(&log, 0x40e040u, &f);
    assert_true(f && fabs((double)vt.x - 0.1 * (double)v.x) < 1e-5 && fabs((double)vt.y - 0.1 * (double)v.y) < 1e-5);
    /* The ray: a segment to the hit, the hit point on the floor, its normal. */
    assert_int_equal(log.segments, 1);
    assert_int_equal(log.points, 1);
    assert_true(fabs((double)log.point.y - 10) < 1e-5 && fabs((double)log.point.x - 1) < 1e-6);
    nt_vec2 rn = arrow_of(&log, 0xff6060u, &f);
    assert_true(f && rn.x == 0 && rn.y < 0);
    /* Statistics. */
    assert_int_equal(log.texts, 1);
    assert_non_null(strstr(log.text, "bodies 1"));
    /* A larger projection scale lengthens the projection arrow in proportion. */
    memset(&log, 0, sizeof log);
    dd.projection_scale = 1000;
    nt_world_draw(w, &dd);
    nt_vec2 pr2 = arrow_of(&log, 0xffe040u, &f);
    assert_true(f && fabs((double)pr2.y - 1000 * (double)pr.y) < 1e-3 * fabs(1000 * (double)pr.y));
    /* Without an arrow callback, vectors come as segments. */
    memset(&log, 0, sizeof log);
    dd.draw_arrow = NULL;
    dd.ray_count = 0;
    nt_world_draw(w, &dd);
    assert_int_equal(log.arrows, 0);
    assert_int_equal(log.segments, 4); /* tile normal, projection, normal and tangential parts */
    nt_world_destroy(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_world_def_errors),
        cmocka_unit_test(test_step_errors),
        cmocka_unit_test(test_body_create_and_read_back),
        cmocka_unit_test(test_body_def_errors),
        cmocka_unit_test(test_ids_name_their_world),
        cmocka_unit_test(test_set_iterations),
        cmocka_unit_test(test_stale_ids),
        cmocka_unit_test(test_many_bodies),
        cmocka_unit_test(test_allocator_hook),
        cmocka_unit_test(test_out_of_memory),
        cmocka_unit_test(test_hash_matches_definition),
        cmocka_unit_test(test_determinism_and_golden_hash),
        cmocka_unit_test(test_point_and_aabb_queries),
        cmocka_unit_test(test_raycast),
        cmocka_unit_test(test_debug_draw),
        cmocka_unit_test(test_debug_draw_gizmos),
        cmocka_unit_test(test_velocity_overflow),
        cmocka_unit_test(test_far_rays),
        cmocka_unit_test(test_profile),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
