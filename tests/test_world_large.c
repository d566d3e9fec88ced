/* Bodies larger than half a cell (up to NT_MAX_HALF_CELLS): the broad phase's coarser
 * levels against brute force, kinematic platforms carrying riders, walking over
 * seams and slopes, firing at every tile shape, a mixed pile, and bad input.
 * Units: cell 1 unless a test says otherwise, seconds, g = 10 cells/s^2, dt = 1/60. */
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

#include "../src/core.h" /* the broad phase's pair list, for the brute-force comparison */

static const nt_real DT = R(1.0 / 60);

static nt_world *make_world(int w, int h, nt_real cell, nt_vec2 gravity, nt_friction_model model, bool sleep)
{
    nt_world_def d = nt_default_world_def();
    d.map.width = w;
    d.map.height = h;
    d.map.cell_size = cell;
    d.gravity = gravity;
    d.friction_model = model;
    d.tile_material.friction = model == NT_FRICTION_COULOMB ? R(0.5) : R(0.05);
    d.tile_material.bounce = 0;
    d.restitution_threshold = R(0.5) * cell;
    d.hit_event_threshold = R(0.5) * cell;
    d.enable_sleep = sleep;
    d.sleep_speed = R(0.05) * cell;
    d.sleep_time = R(0.5);
    nt_world *world = NULL;
    assert_int_equal(nt_world_create(&d, &world), NT_OK);
    return world;
}

static nt_body_id add_body(nt_world *w, nt_body_type type, nt_shape s, nt_vec2 p, nt_vec2 v, nt_real friction)
{
    nt_body_def d = nt_default_body_def();
    d.type = type;
    d.shape = s;
    d.position = p;
    d.velocity = v;
    d.material.friction = friction;
    d.material.bounce = 0;
    nt_body_id id;
    assert_int_equal(nt_body_create(w, &d, &id), NT_OK);
    return id;
}

/* ---------------------------------------------------------------- bad input */

static void test_bad_input(void **state)
{
    (void)state;
    nt_world *w = make_world(20, 12, 2, nt_v2(0, 20), NT_FRICTION_N, true);
    nt_body_id keep = add_body(w, NT_BODY_DYNAMIC, nt_shape_aabb(1, 2), nt_v2(10, 10), nt_v2(1, 0), R(0.1));
    uint64_t h0 = nt_world_hash(w);
    nt_real cap = R(2) * NT_MAX_HALF_CELLS; /* cell 2 */
    struct {
        nt_shape s;
        nt_vec2 p;
        nt_status want;
    } cases[] = {
        {nt_shape_aabb(cap * R(1.0001), 1), nt_v2(20, 12), NT_ERR_SHAPE_TOO_LARGE},
        {nt_shape_aabb(1, cap * R(1.0001)), nt_v2(20, 12), NT_ERR_SHAPE_TOO_LARGE},
        {nt_shape_circle(cap * R(1.0001)), nt_v2(20, 12), NT_ERR_SHAPE_TOO_LARGE},
        {nt_shape_aabb((nt_real)NAN, 3), nt_v2(20, 12), NT_ERR_NON_FINITE},
        {nt_shape_circle((nt_real)INFINITY), nt_v2(20, 12), NT_ERR_NON_FINITE},
        {nt_shape_aabb(3, 0), nt_v2(20, 12), NT_ERR_INVALID_ARGUMENT},
        {nt_shape_aabb(3, 1), nt_v2((nt_real)NAN, 12), NT_ERR_NON_FINITE},
        /* Large bodies reaching over the map's edge (map 40 x 24 units). */
        {nt_shape_aabb(3, 1), nt_v2(2, 12), NT_ERR_OUT_OF_RANGE},
        {nt_shape_aabb(3, 1), nt_v2(38, 12), NT_ERR_OUT_OF_RANGE},
        {nt_shape_circle(2), nt_v2(20, R(1.5)), NT_ERR_OUT_OF_RANGE},
        {nt_shape_circle(2), nt_v2(20, R(22.5)), NT_ERR_OUT_OF_RANGE},
        {nt_shape_aabb(8, 8), nt_v2(-30, 12), NT_ERR_OUT_OF_RANGE},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        for (int type = 0; type < 3; type++) {
            nt_body_def d = nt_default_body_def();
            d.type = (nt_body_type)type;
            d.shape = cases[k].s;
            d.position = cases[k].p;
            nt_body_id id;
            nt_status s = nt_body_create(w, &d, &id);
            if (s != cases[k].want) fail_msg("case %zu type %d: status %d, want %d", k, type, (int)s, (int)cases[k].want);
            assert_true(nt_body_id_is_null(id));
        }
        assert_int_equal(nt_world_get_body_count(w), 1);
        assert_true(nt_world_hash(w) == h0);
    }
    /* The cap itself, and a body touching the map's edge, are allowed. */
    nt_body_id big = add_body(w, NT_BODY_STATIC, nt_shape_aabb(cap, 2), nt_v2(cap, 20), nt_v2(0, 0), 0);
    nt_body_id round = add_body(w, NT_BODY_KINEMATIC, nt_shape_circle(cap / 2), nt_v2(40 - cap / 2, 12), nt_v2(0, 0), 0);
    /* Moving a large body over the edge is refused, and changes nothing. */
    nt_vec2 p0 = nt_body_get_position(w, round);
    assert_int_equal(nt_body_set_position(w, round, nt_v2(39, 12)), NT_ERR_OUT_OF_RANGE);
    assert_true(nt_body_get_position(w, round).x == p0.x);
    assert_int_equal(nt_body_set_position(w, keep, nt_v2(R(0.5), 10)), NT_ERR_OUT_OF_RANGE);
    assert_int_equal(nt_body_set_position(w, keep, nt_v2(R(1.0), 10)), NT_OK);
    assert_true(nt_body_get_shape(w, big).half.x == cap);
    assert_string_equal(nt_status_string(NT_ERR_SHAPE_TOO_LARGE), nt_status_string(NT_ERR_SHAPE_TOO_LARGE));
    nt_world_destroy(w);
}

/* ---------------------------------------------------------------- broad phase */

/* Exact distance between two shapes (negative or zero when they overlap), written
 * here apart from the engine. */
static double shape_distance(nt_shape a, nt_vec2 pa, nt_shape b, nt_vec2 pb)
{
    double dx = (double)pb.x - (double)pa.x, dy = (double)pb.y - (double)pa.y;
    if (a.type == NT_SHAPE_CIRCLE && b.type == NT_SHAPE_CIRCLE)
        return sqrt(dx * dx + dy * dy) - (double)a.half.x - (double)b.half.x;
    if (a.type == NT_SHAPE_AABB && b.type == NT_SHAPE_AABB) {
        double gx = fabs(dx) - (double)a.half.x - (double)b.half.x, gy = fabs(dy) - (double)a.half.y - (double)b.half.y;
        if (gx <= 0 && gy <= 0) return fmax(gx, gy);
        return sqrt(fmax(gx, 0) * fmax(gx, 0) + fmax(gy, 0) * fmax(gy, 0));
    }
    /* Box and circle: the circle's centre to the box. */
    const nt_shape *box = a.type == NT_SHAPE_AABB ? &a : &b, *cir = a.type == NT_SHAPE_AABB ? &b : &a;
    double cx = a.type == NT_SHAPE_AABB ? dx : -dx, cy = a.type == NT_SHAPE_AABB ? dy : -dy;
    double gx = fabs(cx) - (double)box->half.x, gy = fabs(cy) - (double)box->half.y;
    double d = (gx <= 0 && gy <= 0) ? fmax(gx, gy) : sqrt(fmax(gx, 0) * fmax(gx, 0) + fmax(gy, 0) * fmax(gy, 0));
    return d - (double)cir->half.x;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* Random mixes of sizes (a twentieth of a cell to NT_MAX_HALF_CELLS), shapes, types
 * and states: the pairs found must hold every pair overlapping or within the base
 * contact margin (0.05 cell), each once, and nothing farther apart than the margin
 * with the pair's closing speed. Small bodies stay below 0.45 cell so that the
 * base margin lies within N's 3 x 3 neighbourhood. */
static void test_broad_phase_vs_brute_force(void **state)
{
    (void)state;
    ref_rng rng = ref_rng_seed(1800);
    for (int round = 0; round < 24; round++) {
        const nt_real cell = round % 3 == 0 ? R(1) : R(24);
        const int W = 24 + ref_rng_int(&rng, 20), H = 18 + ref_rng_int(&rng, 12);
        nt_world *w = make_world(W, H, cell, nt_v2(0, 0), NT_FRICTION_COULOMB, true);
        int n = 60 + ref_rng_int(&rng, 200);
        nt_body_id *ids = (nt_body_id *)calloc((size_t)n, sizeof *ids);
        double large_share = round % 4 == 3 ? 0.0 : ref_rng_uniform(&rng, 0.1, 0.9);
        for (int k = 0; k < n; k++) {
            nt_body_def d = nt_default_body_def();
            int large = ref_rng_uniform(&rng, 0, 1) < large_share;
            double hx = large ? ref_rng_uniform(&rng, 0.5, NT_MAX_HALF_CELLS) : ref_rng_uniform(&rng, 0.05, 0.45);
            double hy = large ? ref_rng_uniform(&rng, 0.05, NT_MAX_HALF_CELLS) : ref_rng_uniform(&rng, 0.05, 0.45);
            if (ref_rng_int(&rng, 2)) hy = hx, d.shape = nt_shape_circle((nt_real)hx * cell);
            else if (ref_rng_int(&rng, 2)) d.shape = nt_shape_aabb((nt_real)hx * cell, (nt_real)hy * cell);
            else d.shape = nt_shape_aabb((nt_real)hy * cell, (nt_real)hx * cell);
            /* Clustered around a few spots, so that many pairs are close. */
            double mx = fmax(d.shape.half.x / cell, 0.0), my = fmax(d.shape.half.y / cell, 0.0);
            double x = ref_rng_uniform(&rng, mx, W - mx), y = ref_rng_uniform(&rng, my, H - my);
            if (k % 3) {
                double sx = W / 2.0 + ref_rng_uniform(&rng, -6, 6), sy = H / 2.0 + ref_rng_uniform(&rng, -5, 5);
                x = fmin(fmax(sx, mx), W - mx);
                y = fmin(fmax(sy, my), H - my);
            }
            d.position = nt_v2((nt_real)x * cell, (nt_real)y * cell);
            int kind = ref_rng_int(&rng, 10);
            d.type = kind < 6 ? NT_BODY_DYNAMIC : kind < 8 ? NT_BODY_STATIC : NT_BODY_KINEMATIC;
            d.is_awake = !(kind == 5);
            double speed = ref_rng_uniform(&rng, 0, 0.6) * cell / (double)DT, ang = ref_rng_uniform(&rng, 0, 6.2832);
            d.velocity = nt_v2((nt_real)(speed * cos(ang)), (nt_real)(speed * sin(ang)));
            if (ref_rng_int(&rng, 12) == 0) d.category = 2, d.mask = 2;
            assert_int_equal(nt_body_create(w, &d, &ids[k]), NT_OK);
        }
        assert_int_equal(nt__grid_find_pairs(w, DT), NT_OK);
        int nf = w->con_new_count;
        uint64_t *found = (uint64_t *)malloc(((size_t)nf + 1) * sizeof *found);
        for (int k = 0; k < nf; k++) found[k] = w->con_new[k].key;
        qsort(found, (size_t)nf, sizeof *found, cmp_u64);
        for (int k = 1; k < nf; k++)
            if (found[k] == found[k - 1]) fail_msg("round %d: pair %llx found twice", round, (unsigned long long)found[k]);
        int required = 0;
        for (int a = 0; a < n; a++)
            for (int b = a + 1; b < n; b++) {
                int32_t ia = ids[a].index1 - 1, ib = ids[b].index1 - 1;
                nt_body_type ta = nt_body_get_type(w, ids[a]), tb = nt_body_get_type(w, ids[b]);
                bool awa = nt_body_is_awake(w, ids[a]) || ta == NT_BODY_KINEMATIC;
                bool awb = nt_body_is_awake(w, ids[b]) || tb == NT_BODY_KINEMATIC;
                bool filt = (nt_body_get_category(w, ids[a]) & nt_body_get_mask(w, ids[b])) &&
                            (nt_body_get_category(w, ids[b]) & nt_body_get_mask(w, ids[a]));
                bool eligible = (awa || awb) && filt && (ta == NT_BODY_DYNAMIC || tb == NT_BODY_DYNAMIC);
                nt_vec2 pa = nt_body_get_position(w, ids[a]), pb = nt_body_get_position(w, ids[b]);
                nt_vec2 va = awa ? nt_body_get_velocity(w, ids[a]) : nt_v2(0, 0);
                nt_vec2 vb = awb ? nt_body_get_velocity(w, ids[b]) : nt_v2(0, 0);
                double dist = shape_distance(nt_body_get_shape(w, ids[a]), pa, nt_body_get_shape(w, ids[b]), pb);
                double dvx = (double)vb.x - (double)va.x, dvy = (double)vb.y - (double)va.y;
                double base = 0.05 * (double)cell;
                double reach = fmin(base + (double)DT * sqrt(dvx * dvx + dvy * dvy), (double)cell);
                int32_t lo = ia < ib ? ia : ib, hi = ia < ib ? ib : ia;
                uint64_t key = ((uint64_t)(uint32_t)lo << 32) | (uint32_t)hi;
                bool got = bsearch(&key, found, (size_t)nf, sizeof *found, cmp_u64) != NULL;
                bool must = eligible && dist < base * (1 - 1e-3);
                bool may = eligible && dist < reach + 1e-3 * (double)cell;
                required += must;
                if (must && !got)
                    fail_msg("round %d: pair %d-%d at distance %g cell not found", round, a, b, dist / (double)cell);
                if (got && !may)
                    fail_msg("round %d: pair %d-%d at distance %g cell (reach %g) found", round, a, b,
                             dist / (double)cell, reach / (double)cell);
            }
        if (round == 0) print_message("  round 0: %d bodies, %d pairs found, %d required\n", n, nf, required);
        free(found);
        free(ids);
        nt_world_destroy(w);
    }
}

/* ---------------------------------------------------------------- kinematic riders */

/* A 4 x 1-cell kinematic platform moving smoothly (accelerations below mu g and g,
 * so friction and gravity can follow it) carries a 1 x 2-cell box and a small circle
 * resting on it: their positions relative to the platform stay within 1e-3 cell. */
static void test_kinematic_platform_carries_riders(void **state)
{
    (void)state;
    const double dirs[3][2] = {{1, 0}, {0, 1}, {0.6, 0.8}};
    for (int m = 0; m < 3; m++) {
        nt_world *w = make_world(80, 60, 1, nt_v2(0, 10), NT_FRICTION_COULOMB, true);
        nt_body_id plat = add_body(w, NT_BODY_KINEMATIC, nt_shape_aabb(2, R(0.5)), nt_v2(40, 30), nt_v2(0, 0), 1);
        nt_real skin = R(2.5e-4);
        nt_body_id box = add_body(w, NT_BODY_DYNAMIC, nt_shape_aabb(R(0.5), 1), nt_v2(39, R(28.5) + skin), nt_v2(0, 0), 1);
        nt_body_id ball = add_body(w, NT_BODY_DYNAMIC, nt_shape_circle(R(0.3)), nt_v2(R(41.2), R(29.2) + skin),
                                   nt_v2(0, 0), 1);
        /* Settle at rest first. */
        for (int k = 0; k < 60; k++) assert_int_equal(nt_world_step(w, DT), NT_OK);
        nt_vec2 p0 = nt_body_get_position(w, plat);
        nt_vec2 rb = nt__sub(nt_body_get_position(w, box), p0), rc = nt__sub(nt_body_get_position(w, ball), p0);
        double worst = 0;
        for (int k = 0; k < 400; k++) {
            /* v(t) = A sin(wt): peak acceleration A w = 2 * 3.14 = 6.3 cells/s^2 < mu g = g = 10. */
            double t = (double)k * (double)DT, s = 2 * sin(3.14159265 * t);
            assert_int_equal(nt_body_set_velocity(w, plat, nt_v2((nt_real)(s * dirs[m][0]), (nt_real)(s * dirs[m][1]))), NT_OK);
            assert_int_equal(nt_world_step(w, DT), NT_OK);
            nt_vec2 pp = nt_body_get_position(w, plat);
            nt_vec2 db = nt__sub(nt__sub(nt_body_get_position(w, box), pp), rb);
            nt_vec2 dc = nt__sub(nt__sub(nt_body_get_position(w, ball), pp), rc);
            worst = fmax(worst, fmax(fmax(fabs((double)db.x), fabs((double)db.y)), fmax(fabs((double)dc.x), fabs((double)dc.y))));
        }
        print_message("  direction %d: worst drift relative to the platform %.3g cell\n", m, worst);
        assert_true(worst < 1e-3);
        nt_world_destroy(w);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_broad_phase_vs_brute_force),
        cmocka_unit_test(test_kinematic_platform_carries_riders),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
