/* ntile bench — the ntile builder of a scene (see engine.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "engine.h"

typedef struct ntile_run {
    nt_world *world;
    nt_body_id *ids;
    int n, substeps;
    nt_real dt;
} ntile_run;

static nt_real R(double v) { return (nt_real)v; }

static void ntile_destroy(void *p)
{
    ntile_run *r = p;
    if (!r) return;
    nt_world_destroy(r->world);
    free(r->ids);
    free(r);
}

static int ok(nt_status st, const char *what)
{
    if (st == NT_OK) return 1;
    fprintf(stderr, "bench (ntile): %s failed: %s\n", what, nt_status_string(st));
    return 0;
}

nt_world *ntile_scene_world(const scene *s, nt_body_id *ids)
{
    nt_world *w = NULL;
    nt_world_def d = nt_default_world_def();
    d.map.width = s->width;
    d.map.height = s->height;
    d.map.cell_size = R(s->cell);
    d.gravity = nt_v2(R(s->gx), R(s->gy));
    d.friction_model = s->coulomb ? NT_FRICTION_COULOMB : NT_FRICTION_N;
    d.tile_material.friction = R(s->tile_friction);
    d.tile_material.bounce = R(s->tile_bounce);
    d.restitution_threshold = R(s->restitution_threshold);
    d.enable_sleep = s->sleep != 0;
    d.velocity_iterations = s->velocity_iterations;
    d.position_iterations = s->position_iterations;
    d.body_capacity = s->nbodies > 0 ? s->nbodies : 1;
    if (!ok(nt_world_create(&d, &w), "nt_world_create") ||
        !ok(nt_world_set_tiles(w, s->tiles, (size_t)s->width * (size_t)s->height), "nt_world_set_tiles")) {
        nt_world_destroy(w);
        return NULL;
    }
    for (int i = 0; i < s->nbodies; i++) {
        const scene_body *sb = &s->bodies[i];
        nt_body_def b = nt_default_body_def();
        b.shape = sb->circle ? nt_shape_circle(R(sb->hx)) : nt_shape_aabb(R(sb->hx), R(sb->hy));
        b.position = nt_v2(R(sb->x), R(sb->y));
        b.velocity = nt_v2(R(sb->vx), R(sb->vy));
        b.mass = R(sb->mass);
        b.material.friction = R(sb->friction);
        b.material.bounce = R(sb->bounce);
        b.mask = sb->collide_bodies ? 0xFFFFFFFFu : 0;
        if (!ok(nt_body_create(w, &b, &ids[i]), "nt_body_create")) {
            nt_world_destroy(w);
            return NULL;
        }
    }
    return w;
}

static void *ntile_create(const scene *s, const engine_setting *set)
{
    (void)set;
    ntile_run *r = calloc(1, sizeof *r);
    if (!r) return NULL;
    r->n = s->nbodies;
    r->substeps = s->substeps > 1 ? s->substeps : 1;
    r->dt = R(s->dt / r->substeps);
    r->ids = malloc(sizeof *r->ids * (size_t)(r->n > 0 ? r->n : 1));
    if (!r->ids || !(r->world = ntile_scene_world(s, r->ids))) {
        ntile_destroy(r);
        return NULL;
    }
    return r;
}

long long ntile_body_steps;

static int ntile_step(void *p)
{
    ntile_run *r = p;
    for (int k = 0; k < r->substeps; k++) {
        ntile_body_steps += nt_world_get_body_count(r->world);
        if (!ok(nt_world_step(r->world, r->dt), "nt_world_step")) return 0;
    }
    return 1;
}

static void ntile_read(void *p, body_state *out)
{
    ntile_run *r = p;
    for (int i = 0; i < r->n; i++) {
        nt_vec2 x = nt_body_get_position(r->world, r->ids[i]), v = nt_body_get_velocity(r->world, r->ids[i]);
        out[i] = (body_state){(double)x.x, (double)x.y, (double)v.x, (double)v.y};
    }
}

static int ntile_awake(void *p) { return nt_world_get_awake_count(((ntile_run *)p)->world); }

int ntile_scene_profile(const scene *s, nt_world_profile *out)
{
    memset(out, 0, sizeof *out);
    int warm;
    ntile_run *r = bench_warmed(&engine_ntile, NULL, s, &warm, NULL, NULL);
    if (!r) return 0;
    int stepped = 1;
    nt_world_enable_profile(r->world, true);
    for (int k = 0; stepped && k < s->steps; k++)
        for (int q = 0; stepped && q < r->substeps; q++) {
            ntile_body_steps += nt_world_get_body_count(r->world);
            stepped = ok(nt_world_step(r->world, r->dt), "nt_world_step");
            nt_world_profile p = nt_world_get_profile(r->world);
            out->pairs += p.pairs;
            out->contacts += p.contacts;
            out->correct += p.correct;
            out->solve += p.solve;
            out->move += p.move;
            out->sleep += p.sleep;
            out->step += p.step;
        }
    ntile_destroy(r);
    return stepped;
}

const engine engine_ntile = {"ntile", ntile_create, ntile_step, ntile_read, ntile_awake, ntile_destroy};
