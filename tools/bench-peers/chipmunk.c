/* bench-peers — the Chipmunk2D 7 builder of a scene (see engine.h).
 *
 * Broad phase: Chipmunk's spatial hash, one tile cell per hash cell (its documented
 * choice for many objects of one size; its default tree was 10x slower on rain).
 * Units: the scene's own (24 per cell): Chipmunk is unit-free except its collision
 * slop (default 0.1), which suits pixel-like units. Tiles are static segments of
 * radius 0 along the map's outlines (geometry.h), each told its neighbours
 * (cpSegmentShapeSetNeighbors) so that seams are smoothed. Bodies have an infinite
 * moment: they never rotate. Materials: Chipmunk multiplies the two shapes' friction
 * and elasticity, ntile (and Box2D) take sqrt(f1 f2) and max(e1, e2); every shape
 * gets sqrt(friction), which gives the same pair friction; for bounce, shapes get
 * sqrt(bounce) when every shape has the same bounce, otherwise tiles get 1 and bodies
 * their own bounce (right for body-tile pairs when tiles bounce least, as here).
 * Sleeping: ntile's thresholds (0.5 s below 6 units/s) when the scene sleeps.
 */
#include <chipmunk/chipmunk.h>
#include <math.h>
#include <stdlib.h>
#include "engine.h"
#include "geometry.h"
#include "peers.h"

typedef struct cp_run {
    cpSpace *space;
    cpBody **bodies;
    cpShape **shapes;
    int n, nshapes, substeps;
    double dt;
} cp_run;

#define TILE_CATEGORY (1u << 31)

/* The space first (freeing it touches its bodies), then what it held. */
static void cp_destroy(void *p)
{
    cp_run *r = p;
    if (!r) return;
    if (r->space) cpSpaceFree(r->space);
    for (int i = 0; i < r->nshapes; i++) cpShapeFree(r->shapes[i]);
    for (int i = 0; i < r->n; i++)
        if (r->bodies[i]) cpBodyFree(r->bodies[i]);
    free(r->shapes);
    free(r->bodies);
    free(r);
}

static void *cp_create(const scene *s, const engine_setting *set)
{
    cp_run *r = calloc(1, sizeof *r);
    geo_loops g;
    if (!r || !geo_build(s, &g)) {
        free(r);
        return NULL;
    }
    r->n = s->nbodies;
    r->substeps = set->substeps > 1 ? set->substeps : 1;
    r->dt = s->dt / r->substeps;
    r->bodies = calloc((size_t)(r->n > 0 ? r->n : 1), sizeof *r->bodies);
    r->shapes = calloc((size_t)(g.edges + r->n + 1), sizeof *r->shapes);
    r->space = cpSpaceNew();
    if (!r->bodies || !r->shapes || !r->space) {
        geo_free(&g);
        cp_destroy(r);
        return NULL;
    }
    cpSpaceSetGravity(r->space, cpv(s->gx, s->gy));
    /* the spatial hash (cells of one tile cell) rather than the default bounding-box
     * tree: about 10x faster on rain at 10,000 bodies */
    cpSpaceUseSpatialHash(r->space, s->cell, 4 * (r->n + g.edges) + 1000);
    if (set->velocity_iterations > 0) cpSpaceSetIterations(r->space, set->velocity_iterations);
    if (set->slop >= 0) cpSpaceSetCollisionSlop(r->space, set->slop * s->cell);
    if (s->sleep) {
        cpSpaceSetSleepTimeThreshold(r->space, 0.5);
        cpSpaceSetIdleSpeedThreshold(r->space, 6.0 * s->cell / 24.0);
    }
    int same_bounce = 1;
    for (int i = 0; i < r->n; i++) same_bounce &= s->bodies[i].bounce == s->tile_bounce;
    double tile_e = same_bounce ? sqrt(s->tile_bounce) : 1.0;
    cpBody *ground = cpSpaceGetStaticBody(r->space);
    cpShapeFilter tile_filter = cpShapeFilterNew(CP_NO_GROUP, TILE_CATEGORY, CP_ALL_CATEGORIES);
    for (int k = 0; k < g.count; k++) {
        int a0 = g.start[k], n = g.start[k + 1] - a0;
        for (int i = 0; i < n; i++) {
            geo_point p = g.points[a0 + (i + n - 1) % n], a = g.points[a0 + i], b = g.points[a0 + (i + 1) % n],
                      q = g.points[a0 + (i + 2) % n];
            cpShape *seg = cpSegmentShapeNew(ground, cpv(a.x, a.y), cpv(b.x, b.y), 0);
            cpSegmentShapeSetNeighbors(seg, cpv(p.x, p.y), cpv(q.x, q.y));
            cpShapeSetFriction(seg, sqrt(s->tile_friction));
            cpShapeSetElasticity(seg, tile_e);
            cpShapeSetFilter(seg, tile_filter);
            cpSpaceAddShape(r->space, seg);
            r->shapes[r->nshapes++] = seg;
        }
    }
    geo_free(&g);
    for (int i = 0; i < r->n; i++) {
        const scene_body *sb = &s->bodies[i];
        cpBody *body = cpBodyNew(sb->mass, INFINITY);
        cpBodySetPosition(body, cpv(sb->x, sb->y));
        cpBodySetVelocity(body, cpv(sb->vx, sb->vy));
        cpSpaceAddBody(r->space, body);
        cpShape *shape = sb->circle ? cpCircleShapeNew(body, sb->hx, cpvzero) : cpBoxShapeNew(body, 2 * sb->hx, 2 * sb->hy, 0);
        cpShapeSetFriction(shape, sqrt(sb->friction));
        cpShapeSetElasticity(shape, same_bounce ? sqrt(sb->bounce) : sb->bounce);
        cpShapeSetFilter(shape, cpShapeFilterNew(CP_NO_GROUP, 1, sb->collide_bodies ? CP_ALL_CATEGORIES : TILE_CATEGORY));
        cpSpaceAddShape(r->space, shape);
        r->shapes[r->nshapes++] = shape;
        r->bodies[i] = body;
    }
    return r;
}

static int cp_step(void *p)
{
    cp_run *r = p;
    for (int k = 0; k < r->substeps; k++) cpSpaceStep(r->space, r->dt);
    return 1;
}

static void cp_read(void *p, body_state *out)
{
    cp_run *r = p;
    for (int i = 0; i < r->n; i++) {
        cpVect x = cpBodyGetPosition(r->bodies[i]), v = cpBodyGetVelocity(r->bodies[i]);
        out[i] = (body_state){x.x, x.y, v.x, v.y};
    }
}

static int cp_awake(void *p)
{
    cp_run *r = p;
    int n = 0;
    for (int i = 0; i < r->n; i++) n += !cpBodyIsSleeping(r->bodies[i]);
    return n;
}

/* The Makefile defines PEERS_CHIPMUNK_RELEASE when it links the release build
 * (tools/bench-peers/chipmunk-release.sh); Debian's library prints a start-up line
 * "(Debug Enabled)" at the first cpSpaceNew. */
#ifdef PEERS_CHIPMUNK_RELEASE
const char chipmunk_build[] = "release build (-O2 -DNDEBUG) of Debian's source package";
#else
const char chipmunk_build[] = "Debian's libchipmunk-dev, built with its debug assertions on";
#endif

const char *chipmunk_version(void)
{
    return cpVersionString;
}

const engine engine_chipmunk = {"chipmunk", cp_create, cp_step, cp_read, cp_awake, cp_destroy};
