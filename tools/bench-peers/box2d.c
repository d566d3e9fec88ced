/* bench-peers — the Box2D 2.4 builder of a scene (see engine.h), through the C shim.
 *
 * Units: Box2D is tuned for metres (its slop and skin are 5 mm and 1 cm, its speed
 * limit 2 m per step), so one cell is one metre: bodies of 0.4..0.9 m. Frame: the
 * scene's, y down (gravity +y). Tiles are closed chain shapes along the map's
 * outlines (geometry.h): Box2D's edges know their neighbours through the chain.
 * Chains are one-sided: Box2D takes the side right of a->b (normal (e.y, -e.x)) as
 * the outside, ours is the left, so loops are given reversed. Bodies have fixed
 * rotation and the scene's mass (density = mass / area). Materials combine as in
 * ntile (sqrt of frictions, max of bounces); restitution threshold as the scene's.
 * Tiles are category 1; bodies category 2, colliding with bodies only if the scene
 * says so. Continuous collision against static shapes is Box2D's default; a setting
 * can turn it off (its cost grows faster than the body count: every time-of-impact
 * event scans every contact).
 */
#include <stdlib.h>
#include "box2d_shim.h"
#include "geometry.h"
#include "peers.h"

typedef struct b2_run {
    b2s_world *w;
    double *buf, cell;
    int n, substeps, vi, pi;
    double dt;
} b2_run;

static void b2_destroy(void *p)
{
    b2_run *r = p;
    if (!r) return;
    b2s_destroy(r->w);
    free(r->buf);
    free(r);
}

static void *b2_create(const scene *s, const engine_setting *set)
{
    b2_run *r = calloc(1, sizeof *r);
    geo_loops g;
    if (!r || !geo_build(s, &g)) {
        free(r);
        return NULL;
    }
    double c = s->cell;
    r->cell = c;
    r->n = s->nbodies;
    r->substeps = set->substeps > 1 ? set->substeps : 1;
    r->dt = s->dt / r->substeps;
    r->vi = set->velocity_iterations > 0 ? set->velocity_iterations : 8; /* the manual's recommended 8 and 3 */
    r->pi = set->position_iterations > 0 ? set->position_iterations : 3;
    r->buf = malloc(sizeof *r->buf * 4 * (size_t)(r->n > 0 ? r->n : 1));
    double *xy = malloc(sizeof *xy * 2 * (size_t)(g.start[g.count] + 1));
    r->w = b2s_create(s->gx / c, s->gy / c, s->sleep, !set->no_ccd, r->n);
    if (!r->buf || !xy || !r->w) {
        free(xy);
        geo_free(&g);
        b2_destroy(r);
        return NULL;
    }
    double threshold = s->restitution_threshold / c;
    for (int k = 0; k < g.count; k++) {
        int a0 = g.start[k], n = g.start[k + 1] - a0;
        for (int i = 0; i < n; i++) { /* reversed */
            xy[2 * i] = g.points[a0 + n - 1 - i].x / c;
            xy[2 * i + 1] = g.points[a0 + n - 1 - i].y / c;
        }
        b2s_add_loop(r->w, xy, n, s->tile_friction, s->tile_bounce, threshold, 1);
    }
    free(xy);
    geo_free(&g);
    for (int i = 0; i < r->n; i++) {
        const scene_body *b = &s->bodies[i];
        b2s_add_body(r->w, b->circle, b->hx / c, b->hy / c, b->x / c, b->y / c, b->vx / c, b->vy / c, b->mass,
                     b->friction, b->bounce, threshold, 2, b->collide_bodies ? 0xFFFF : 1, s->sleep);
    }
    return r;
}

static int b2_step(void *p)
{
    b2_run *r = p;
    for (int k = 0; k < r->substeps; k++) b2s_step(r->w, r->dt, r->vi, r->pi);
    return 1;
}

static void b2_read(void *p, body_state *out)
{
    b2_run *r = p;
    b2s_read(r->w, r->buf);
    for (int i = 0; i < r->n; i++)
        out[i] = (body_state){r->buf[4 * i] * r->cell, r->buf[4 * i + 1] * r->cell, r->buf[4 * i + 2] * r->cell,
                              r->buf[4 * i + 3] * r->cell};
}

static int b2_awake(void *p) { return b2s_awake(((b2_run *)p)->w); }

const engine engine_box2d = {"box2d", b2_create, b2_step, b2_read, b2_awake, b2_destroy};
