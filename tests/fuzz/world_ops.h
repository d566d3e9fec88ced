/* The world API fuzzer's interpreter, shared by the libFuzzer harness
 * (tests/fuzz/fuzz_world.c) and the seeded cmocka test (tests/test_world_fuzz.c).
 *
 * The input bytes are a program: a world definition, then operations (create and
 * destroy bodies, set tiles and cell flags, velocities and positions including huge
 * and non-finite ones, steps with good and bad dt, queries, ray casts). Numbers come
 * either from a small table of ordinary values or as raw float bits (NaN, infinities,
 * denormals, 1e38). After every operation the checks hold or world_ops_run returns 1
 * with a message:
 *   - every live body's position and velocity are finite;
 *   - after a successful step every dynamic body's centre is inside the map, unless
 *     no EMPTY cell lies within the reach of the resolution (64 cells);
 *   - a call that reports an error left the body it was given unchanged.
 */
#ifndef NTILE_WORLD_OPS_H
#define NTILE_WORLD_OPS_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include "ntile/ntile.h"

#define WOPS_MAX_IDS 64

typedef struct wops_in {
    const uint8_t *p;
    size_t n, at;
} wops_in;

static uint8_t wops_byte(wops_in *in) { return in->at < in->n ? in->p[in->at++] : 0; }

static uint32_t wops_u32(wops_in *in)
{
    uint32_t v = 0;
    for (int i = 0; i < 4; i++) v = (v << 8) | wops_byte(in);
    return v;
}

/* A number: mostly ordinary (scaled into [-4, 4] map widths), sometimes raw bits. */
static double wops_num(wops_in *in, double scale)
{
    uint8_t sel = wops_byte(in);
    if (sel < 200) return ((double)wops_byte(in) / 255.0 * 1.5 - 0.25) * scale; /* mostly in and near the map */
    if (sel < 230) {
        static const double special[] = {0, -0.0, 1e-30, -1e-30, 1e30, -1e30, 3.0e38, -3.0e38, 1e-45, 0.5, 1, -1};
        return special[wops_byte(in) % (sizeof special / sizeof special[0])];
    }
    uint32_t bits = wops_u32(in);
    float f;
    memcpy(&f, &bits, sizeof f);
    return (double)f; /* NaN, infinities, anything */
}

/* A vector of two numbers read x first: the two reads are sequenced (the arguments of
 * one call are not, so nt_v2(wops_num(), wops_num()) reads differently with gcc and
 * clang, and a fuzz input would mean another program under each). */
static nt_vec2 wops_vec(wops_in *in, double sx, double sy)
{
    nt_real x = (nt_real)wops_num(in, sx);
    nt_real y = (nt_real)wops_num(in, sy);
    return nt_v2(x, y);
}

static int wops_finite2(nt_vec2 v) { return isfinite((double)v.x) && isfinite((double)v.y); }

/* Is there an EMPTY cell within 64 cells (Chebyshev) of the cell nearest to p? */
/* Is there room for the body in the map? A body up to half a cell fits in any EMPTY
 * cell (one within 64 cells of p is asked for); a larger one needs a place inside the
 * map where its shape overlaps no tile, looked for on a half-cell lattice. */
static int wops_room_near(const nt_world *w, nt_vec2 p, nt_shape shape, nt_real cell)
{
    const nt_map *m = nt_world_get_map(w);
    int W = nt_map_get_width(m), H = nt_map_get_height(m);
    if (shape.half.x > cell / 2 || shape.half.y > cell / 2) {
        double q = (double)cell / 2, hx = (double)shape.half.x, hy = (double)shape.half.y;
        for (double y = hy; y <= H * (double)cell - hy; y += q)
            for (double x = hx; x <= W * (double)cell - hx; x += q)
                if (nt_map_overlap_depth(m, nt_v2((nt_real)x, (nt_real)y), shape) == 0) return 1;
        return 0;
    }
    double fx = floor((double)p.x / (double)cell), fy = floor((double)p.y / (double)cell);
    int cx = fx < 0 ? 0 : fx > W - 1 ? W - 1 : (int)fx, cy = fy < 0 ? 0 : fy > H - 1 ? H - 1 : (int)fy;
    for (int y = cy - 64; y <= cy + 64; y++)
        for (int x = cx - 64; x <= cx + 64; x++)
            if (x >= 0 && y >= 0 && x < W && y < H && nt_map_get_tile(m, x, y) == NT_TILE_EMPTY) return 1;
    return 0;
}

static int world_ops_run(const uint8_t *data, size_t size, char *msg, size_t msglen)
{
    wops_in in = {data, size, 0};
    static const nt_real cells[] = {1, 24, 0.5f, 3};
    nt_world_def d = nt_default_world_def();
    d.map.width = 4 + wops_byte(&in) % 29;
    d.map.height = 4 + wops_byte(&in) % 21;
    d.map.cell_size = cells[wops_byte(&in) % 4];
    nt_real cell = d.map.cell_size;
    d.friction_model = (wops_byte(&in) & 1) ? NT_FRICTION_COULOMB : NT_FRICTION_N;
    d.enable_sleep = (wops_byte(&in) & 1) != 0;
    d.gravity = nt_v2(0, 320 * cell / 24);
    nt_world *w = NULL;
    if (nt_world_create(&d, &w) != NT_OK) return 0;
#ifdef WOPS_TRACE
    fprintf(stderr, "world %d x %d cell %g model %d sleep %d\n", d.map.width, d.map.height, (double)cell,
            (int)d.friction_model, (int)d.enable_sleep);
#endif
    double mw = (double)d.map.width * (double)cell, mh = (double)d.map.height * (double)cell;
    nt_body_id ids[WOPS_MAX_IDS];
    int nids = 0, bad = 0;
    for (int op = 0; op < 400 && in.at < in.n && !bad; op++) {
        uint8_t code = wops_byte(&in) % 16;
        nt_body_id id = nids ? ids[wops_byte(&in) % nids] : nt_null_body_id();
#ifdef WOPS_TRACE
        fprintf(stderr, "op %d code %d body %d\n", op, code, id.index1);
        for (int k = 0; k < nids; k++)
            if (nt_body_is_valid(w, ids[k]))
                fprintf(stderr, "   body %d type %d p (%g, %g) v (%g, %g)\n", ids[k].index1, nt_body_get_type(w, ids[k]),
                        (double)nt_body_get_position(w, ids[k]).x, (double)nt_body_get_position(w, ids[k]).y,
                        (double)nt_body_get_velocity(w, ids[k]).x, (double)nt_body_get_velocity(w, ids[k]).y);
#endif
        switch (code) {
        case 0:
        case 1: { /* create */
            nt_body_def b = nt_default_body_def();
            b.type = (nt_body_type)(wops_byte(&in) % 4); /* 3 is not a type */
            /* Mostly up to 0.6 cell (the small-body cap is 0.5); a quarter up to 4.5
             * cells (the large-body cap is NT_MAX_HALF_CELLS); boxes of unequal halves. */
            unsigned sz = wops_byte(&in);
            double half = sz < 192 ? (double)sz / 191.0 * 0.6 * (double)cell
                                   : (double)(sz - 192) / 63.0 * 4.5 * (double)cell;
            /* The other half-size down to a sixteenth of it: thinner, a float body
             * far from the origin is thinner than the rounding of its own position
             * (a 1.2e-5-cell plank 16 cells out sank below the map's edge by rounding
             * alone), which no float engine resolves. */
            double half_y = (sz & 4) ? half : half * (1.0 + 15.0 * (double)wops_byte(&in) / 255.0) / 16.0;
            b.shape = (wops_byte(&in) & 1) ? nt_shape_circle((nt_real)half)
                                           : nt_shape_aabb((nt_real)half, (nt_real)half_y);
            b.position = wops_vec(&in, mw, mh);
            b.velocity = wops_vec(&in, 200 * (double)cell, 200 * (double)cell);
            b.mass = (nt_real)wops_num(&in, 4);
            b.is_sensor = (wops_byte(&in) & 7) == 0;
            b.category = wops_byte(&in) & 3;
            b.mask = wops_byte(&in) & 3;
            b.material.bounce = (nt_real)((double)wops_byte(&in) / 200.0);
            nt_body_id nid;
            if (nt_body_create(w, &b, &nid) == NT_OK && nids < WOPS_MAX_IDS) ids[nids++] = nid;
            break;
        }
        case 2: nt_body_destroy(w, id); break;
        case 3: case 4: { /* tiles */
            int x = (int)(wops_byte(&in) % (d.map.width + 2)) - 1, y = (int)(wops_byte(&in) % (d.map.height + 2)) - 1;
            nt_world_set_tile(w, x, y, wops_byte(&in) % 36);
            break;
        }
        case 5: case 6: { /* velocity: an error must leave the body as it was */
            nt_vec2 before = nt_body_get_velocity(w, id);
            nt_vec2 v = wops_vec(&in, 400 * (double)cell, 400 * (double)cell);
            if (nt_body_set_velocity(w, id, v) != NT_OK) {
                nt_vec2 after = nt_body_get_velocity(w, id);
                if (memcmp(&before, &after, sizeof before) != 0) {
                    snprintf(msg, msglen, "op %d: failed set_velocity changed the body", op);
                    bad = 1;
                }
            }
            break;
        }
        case 7: { /* position */
            nt_vec2 before = nt_body_get_position(w, id);
            nt_vec2 p = wops_vec(&in, mw, mh);
            if (nt_body_set_position(w, id, p) != NT_OK) {
                nt_vec2 after = nt_body_get_position(w, id);
                if (memcmp(&before, &after, sizeof before) != 0) {
                    snprintf(msg, msglen, "op %d: failed set_position changed the body", op);
                    bad = 1;
                }
            }
            break;
        }
        case 8: case 9: case 10: { /* steps */
            static const nt_real dts[] = {1.0f / 60, 1.0f / 40, 1.0f / 60, 0, -1, 1e-6f, 0.5f, 1.0f / 240};
            nt_real dt = dts[wops_byte(&in) % 8];
            int n = 1 + wops_byte(&in) % 4;
#ifdef WOPS_TRACE
            fprintf(stderr, "   step dt %g x %d\n", (double)dt, n);
#endif
            for (int s = 0; s < n && !bad; s++) {
                if (nt_world_step(w, dt) != NT_OK) break;
                for (int k = 0; k < nids && !bad; k++) {
                    if (!nt_body_is_valid(w, ids[k])) continue;
                    nt_vec2 p = nt_body_get_position(w, ids[k]);
                    if (nt_body_get_type(w, ids[k]) != NT_BODY_DYNAMIC) continue;
                    if (p.x < 0 || p.y < 0 || (double)p.x > mw || (double)p.y > mh) {
                        if (wops_room_near(w, p, nt_body_get_shape(w, ids[k]), cell)) {
                            snprintf(msg, msglen, "op %d: dynamic body %d outside the map at (%g, %g)", op,
                                     ids[k].index1, (double)p.x, (double)p.y);
                            bad = 1;
                        }
                    }
                }
            }
            break;
        }
        case 11: { /* queries */
            nt_world_ray_hit hit;
            nt_vec2 a = wops_vec(&in, mw, mh);
            nt_vec2 b = wops_vec(&in, mw, mh);
            if (nt_world_raycast(w, a, b, nt_default_query_filter(), &hit) &&
                (!wops_finite2(hit.point) || !(hit.fraction >= 0 && hit.fraction <= 1))) {
                snprintf(msg, msglen, "op %d: ray hit with t %g", op, (double)hit.fraction);
                bad = 1;
            }
            nt_world_query_point(w, a, nt_default_query_filter(), NULL, NULL);
            nt_world_overlap_aabb(w, a, b, nt_default_query_filter(), NULL, NULL);
            break;
        }
        case 12: { /* cell flags and materials */
            int x = (int)(wops_byte(&in) % (d.map.width + 2)) - 1, y = (int)(wops_byte(&in) % (d.map.height + 2)) - 1;
            nt_world_set_cell_flags(w, x, y, wops_byte(&in) % 3);
            nt_world_set_cell_material(w, x, y, (int)(wops_byte(&in) % 18) - 1);
            nt_material mat;
            mat.friction = (nt_real)wops_num(&in, 1); /* one after the other: the order the bytes are read in */
            mat.bounce = (nt_real)wops_num(&in, 1);
            nt_world_set_material(w, wops_byte(&in) % 17, mat);
            break;
        }
        case 13: { /* gravity, gravity scale, drag */
            nt_world_set_gravity(w, wops_vec(&in, 1000, 1000));
            nt_body_set_gravity_scale(w, id, (nt_real)wops_num(&in, 10));
            nt_body_set_linear_drag(w, id, (nt_real)wops_num(&in, 10));
            break;
        }
        case 14: /* impulses, sleep, filters */
            nt_body_apply_impulse(w, id, wops_vec(&in, 100, 100));
            nt_body_set_awake(w, id, (wops_byte(&in) & 1) != 0);
            nt_body_enable_sleep(w, id, (wops_byte(&in) & 1) != 0);
            uint32_t cat = wops_byte(&in) & 3u, mask = wops_byte(&in) & 3u; /* read in this order */
            nt_body_set_filter(w, id, cat, mask);
            break;
        default: { /* a bulk tile pattern */
            size_t n = (size_t)d.map.width * (size_t)d.map.height;
            uint8_t tiles[32 * 24];
            uint8_t a = wops_byte(&in), b = wops_byte(&in);
            for (size_t k = 0; k < n; k++) tiles[k] = (uint8_t)(((k * a) >> 3) % 7 == 0 ? b % 35 : 0);
            nt_world_set_tiles(w, tiles, n - (wops_byte(&in) & 1)); /* sometimes the wrong count */
            break;
        }
        }
        for (int k = 0; k < nids && !bad; k++) {
            if (!nt_body_is_valid(w, ids[k])) continue;
            if (!wops_finite2(nt_body_get_position(w, ids[k])) || !wops_finite2(nt_body_get_velocity(w, ids[k]))) {
                snprintf(msg, msglen, "op %d (code %d): body %d not finite", op, code, ids[k].index1);
                bad = 1;
            }
        }
    }
    nt_world_destroy(w);
    return bad;
}

#endif
