/* ntile bench — error metrics (see metrics.h). Everything here runs outside the
 * timed steps, in double, with ntile's exact tile routines. */
#include "metrics.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_APEX 3

struct metrics_tracker {
    const scene *s;
    nt_map *map;
    int n, step;
    body_state *prev, *rest_ref, *incline_ref;
    uint8_t *tunnelled, *ghost;
    int *apex_count;
    int *cell_head, *next; /* body-body overlap grid: one list per cell */
    double *step_overlap;  /* each step's deepest overlap (for the percentile) */
    int step_overlap_cap;
    double e0;
    int has_energy, has_slide, has_rest, has_bounce, has_incline, has_flight, has_collide;
    metrics m;
};

static nt_real R(double v) { return (nt_real)v; }

static nt_shape body_shape(const scene_body *b)
{
    return b->circle ? nt_shape_circle(R(b->hx)) : nt_shape_aabb(R(b->hx), R(b->hy));
}

nt_map *metrics_scene_map(const scene *s)
{
    nt_map_def d = nt_default_map_def();
    d.width = s->width;
    d.height = s->height;
    d.cell_size = R(s->cell);
    nt_map *map = NULL;
    if (nt_map_create(&d, &map) != NT_OK) return NULL;
    if (nt_map_set_tiles(map, s->tiles, (size_t)s->width * (size_t)s->height) != NT_OK) {
        nt_map_destroy(map);
        return NULL;
    }
    return map;
}

double metrics_penetration(const nt_map *map, const scene_body *b, double x, double y)
{
    return (double)nt_map_overlap_depth(map, nt_v2(R(x), R(y)), body_shape(b)) / (double)nt_map_get_cell_size(map);
}

int metrics_centre_in_solid(const nt_map *map, double x, double y)
{
    double cs = (double)nt_map_get_cell_size(map);
    double u = x / cs, v = y / cs;
    if (!(u > 0 && v > 0 && u < nt_map_get_width(map) && v < nt_map_get_height(map))) return 1; /* outside (or NaN) */
    int cx = (int)floor(u), cy = (int)floor(v);
    return nt_tile_contains_point(nt_map_get_tile(map, cx, cy), nt_v2(R(u - cx), R(v - cy)));
}

int metrics_path_tunnels(const nt_map *map, double x0, double y0, double x1, double y1, double min_half)
{
    nt_ray_hit in, out;
    nt_vec2 p0 = nt_v2(R(x0), R(y0)), p1 = nt_v2(R(x1), R(y1));
    if (!nt_map_raycast(map, p0, p1, &in)) return 0;
    if (!nt_map_raycast(map, p1, p0, &out)) return 0; /* cannot happen unless p1 is on a boundary */
    /* from the first entry (from p0) to the last exit (the first entry from p1) */
    double len = hypot(x1 - x0, y1 - y0) * (1.0 - (double)in.fraction - (double)out.fraction);
    return len > min_half;
}

double metrics_energy(const scene *s, const scene_body *b, const body_state *st)
{
    /* potential: m g . (p - p_rest), p_rest on the floor at y = role_a (gravity is along y here) */
    double kinetic = 0.5 * b->mass * (st->vx * st->vx + st->vy * st->vy);
    return kinetic + b->mass * (s->gy * (b->role_a - st->y) - s->gx * st->x);
}

static double total_energy(const metrics_tracker *t, const body_state *st)
{
    double e = 0;
    for (int i = 0; i < t->n; i++)
        if (t->s->bodies[i].role == ROLE_ENERGY) e += metrics_energy(t->s, &t->s->bodies[i], &st[i]);
    return e;
}

static double maxd(double a, double b) { return a > b ? a : b; }

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

metrics_tracker *metrics_begin(const scene *s)
{
    metrics_tracker *t = calloc(1, sizeof *t);
    if (!t) return NULL;
    t->s = s;
    t->n = s->nbodies;
    size_t n = (size_t)(s->nbodies > 0 ? s->nbodies : 1), cells = (size_t)s->width * (size_t)s->height;
    t->map = metrics_scene_map(s);
    t->prev = calloc(n, sizeof *t->prev);
    t->rest_ref = calloc(n, sizeof *t->rest_ref);
    t->incline_ref = calloc(n, sizeof *t->incline_ref);
    t->tunnelled = calloc(n, 1);
    t->ghost = calloc(n, 1);
    t->apex_count = calloc(n, sizeof *t->apex_count);
    t->cell_head = malloc(cells * sizeof *t->cell_head);
    t->next = malloc(n * sizeof *t->next);
    if (!t->map || !t->prev || !t->rest_ref || !t->incline_ref || !t->tunnelled || !t->ghost || !t->apex_count ||
        !t->cell_head || !t->next) {
        metrics_end(t);
        return NULL;
    }
    memset(&t->m, 0, sizeof t->m);
    for (int i = 0; i < t->n; i++) {
        const scene_body *b = &s->bodies[i];
        t->prev[i] = (body_state){b->x, b->y, b->vx, b->vy};
        t->has_energy |= b->role == ROLE_ENERGY;
        t->has_slide |= b->role == ROLE_SLIDE;
        t->has_rest |= b->role == ROLE_REST;
        t->has_bounce |= b->role == ROLE_BOUNCE;
        t->has_incline |= b->role == ROLE_INCLINE;
        t->has_flight |= b->role == ROLE_FLIGHT;
        t->has_collide |= b->collide_bodies;
    }
    t->e0 = total_energy(t, t->prev);
    return t;
}

void metrics_end(metrics_tracker *t)
{
    if (!t) return;
    nt_map_destroy(t->map);
    free(t->prev);
    free(t->rest_ref);
    free(t->incline_ref);
    free(t->tunnelled);
    free(t->ghost);
    free(t->apex_count);
    free(t->cell_head);
    free(t->next);
    free(t->step_overlap);
    free(t);
}

/* Deepest overlap between two bodies that collide, through a grid of cells: bodies are
 * at most a cell across, so overlapping ones have centres in neighbouring cells. *deep
 * gets the pairs overlapping by DEEP_OVERLAP or more. */
static double body_overlap(metrics_tracker *t, const body_state *st, long *deep)
{
    const scene *s = t->s;
    int w = s->width, h = s->height;
    for (size_t k = 0; k < (size_t)w * (size_t)h; k++) t->cell_head[k] = -1;
    for (int i = 0; i < t->n; i++) {
        if (!s->bodies[i].collide_bodies) continue;
        int cx = (int)floor(st[i].x / s->cell), cy = (int)floor(st[i].y / s->cell);
        cx = cx < 0 ? 0 : cx >= w ? w - 1 : cx;
        cy = cy < 0 ? 0 : cy >= h ? h - 1 : cy;
        size_t k = (size_t)cy * (size_t)w + (size_t)cx;
        t->next[i] = t->cell_head[k];
        t->cell_head[k] = i;
    }
    double worst = 0;
    *deep = 0;
    for (int i = 0; i < t->n; i++) {
        const scene_body *a = &s->bodies[i];
        if (!a->collide_bodies) continue;
        int cx = (int)floor(st[i].x / s->cell), cy = (int)floor(st[i].y / s->cell);
        for (int y = cy - 1; y <= cy + 1; y++)
            for (int x = cx - 1; x <= cx + 1; x++) {
                if (x < 0 || y < 0 || x >= w || y >= h) continue;
                for (int j = t->cell_head[(size_t)y * (size_t)w + (size_t)x]; j >= 0; j = t->next[j]) {
                    if (j <= i) continue;
                    nt_mtv m;
                    if (nt_collide_shapes(nt_v2(R(st[i].x), R(st[i].y)), body_shape(a), nt_v2(R(st[j].x), R(st[j].y)),
                                          body_shape(&s->bodies[j]), &m)) {
                        double d = (double)m.depth / s->cell;
                        worst = maxd(worst, d);
                        *deep += d >= DEEP_OVERLAP;
                    }
                }
            }
    }
    return worst;
}

void metrics_step(metrics_tracker *t, const body_state *st)
{
    const scene *s = t->s;
    double cell = s->cell;
    t->step++;
    for (int i = 0; i < t->n; i++) {
        const scene_body *b = &s->bodies[i];
        const body_state *p = &st[i], *q = &t->prev[i];
        t->m.penetration = maxd(t->m.penetration, metrics_penetration(t->map, b, p->x, p->y));
        if (!t->tunnelled[i] && (metrics_centre_in_solid(t->map, p->x, p->y) ||
                                 metrics_path_tunnels(t->map, q->x, q->y, p->x, p->y, b->hx < b->hy ? b->hx : b->hy))) {
            t->tunnelled[i] = 1;
            t->m.tunnelled++;
        }
        switch (b->role) {
        case ROLE_SLIDE:
            if (p->x >= b->role_a) {
                double up = -p->vy / cell;
                t->m.max_up = maxd(t->m.max_up, up);
                if (up > GHOST_SPEED && !t->ghost[i]) {
                    t->ghost[i] = 1;
                    t->m.ghost_bumps++;
                }
            }
            if (b->role_b != 0) t->m.speed_loss = maxd(t->m.speed_loss, 1 - fabs(p->vx) / fabs(b->vx));
            break;
        case ROLE_REST:
            if (t->step == s->rest_from) t->rest_ref[i] = *p;
            if (t->step > s->rest_from || s->rest_from == 0) {
                const body_state *r = s->rest_from == 0 ? &(body_state){b->x, b->y, 0, 0} : &t->rest_ref[i];
                t->m.jitter = maxd(t->m.jitter, hypot(p->x - r->x, p->y - r->y) / cell);
                t->m.rest_speed = maxd(t->m.rest_speed, hypot(p->vx, p->vy) / cell);
            }
            break;
        case ROLE_BOUNCE:
            /* apex: moving up before this step, not any more */
            if (q->vy < 0 && p->vy >= 0 && t->apex_count[i] < MAX_APEX) {
                int k = ++t->apex_count[i];
                double h0 = b->role_a - b->y, expect = h0 * pow(b->bounce, 2.0 * k);
                double got = b->role_a - (p->y < q->y ? p->y : q->y);
                t->m.bounce_error = maxd(t->m.bounce_error, fabs(got - expect) / expect);
            }
            break;
        case ROLE_INCLINE:
            if (t->step == s->rest_from) t->incline_ref[i] = *p;
            break;
        case ROLE_FLIGHT: /* judged at the end (metrics_get) */
            break;
        default:
            break;
        }
        t->prev[i] = *p;
    }
    if (t->has_energy && t->e0 != 0)
        t->m.energy_drift = maxd(t->m.energy_drift, fabs(total_energy(t, st) - t->e0) / fabs(t->e0));
    if (t->has_collide) {
        long deep;
        double worst = body_overlap(t, st, &deep);
        t->m.overlap = maxd(t->m.overlap, worst);
        if (t->step * s->dt > SETTLE_TIME + 1e-9) t->m.settled = maxd(t->m.settled, worst);
        t->m.deep_pairs += deep;
        if (t->step > t->step_overlap_cap) { /* on failure the percentile leaves the step out */
            int cap = t->step_overlap_cap ? 2 * t->step_overlap_cap : 1024;
            double *p = realloc(t->step_overlap, (size_t)cap * sizeof *p);
            if (p) t->step_overlap = p, t->step_overlap_cap = cap;
        }
        if (t->step <= t->step_overlap_cap) t->step_overlap[t->step - 1] = worst;
    }
}

/* The 99th percentile of the steps' deepest overlaps (nearest rank). */
static double overlap_p99(const metrics_tracker *t)
{
    int n = t->step < t->step_overlap_cap ? t->step : t->step_overlap_cap;
    if (n <= 0) return 0;
    double *v = malloc((size_t)n * sizeof *v);
    if (!v) return -1;
    memcpy(v, t->step_overlap, (size_t)n * sizeof *v);
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    int k = (int)ceil(0.99 * n) - 1;
    double p = v[k < 0 ? 0 : k];
    free(v);
    return p;
}

metrics metrics_get(const metrics_tracker *t)
{
    metrics m = t->m;
    const scene *s = t->s;
    if (t->has_incline) {
        m.incline_error = 0;
        double time = (t->step - s->rest_from) * s->dt;
        for (int i = 0; i < t->n && time > 0; i++) {
            const scene_body *b = &s->bodies[i];
            if (b->role != ROLE_INCLINE) continue;
            const body_state *p = &t->prev[i], *r = &t->incline_ref[i];
            double a = ((p->vx - r->vx) * b->role_a + (p->vy - r->vy) * b->role_b) / time;
            m.incline_error = maxd(m.incline_error, fabs(a - b->accel) / b->accel);
        }
    } else {
        m.incline_error = -1;
    }
    if (t->has_flight) { /* displacement at the end against the exact one */
        double time = t->step * s->dt;
        for (int i = 0; i < t->n; i++) {
            const scene_body *b = &s->bodies[i];
            if (b->role != ROLE_FLIGHT) continue;
            double ex = b->vx * time + 0.5 * s->gx * time * time, ey = b->vy * time + 0.5 * s->gy * time * time;
            /* relative to the fall g t^2 / 2 (the part integrators get wrong), else to the travel */
            double scale = 0.5 * hypot(s->gx, s->gy) * time * time;
            if (scale == 0) scale = hypot(ex, ey);
            if (scale > 0)
                m.flight_error = maxd(m.flight_error, hypot(t->prev[i].x - b->x - ex, t->prev[i].y - b->y - ey) / scale);
        }
    }
    for (int i = 0; i < t->n; i++) /* an apex that never came is a 100 % error */
        if (s->bodies[i].role == ROLE_BOUNCE && t->apex_count[i] < MAX_APEX) m.bounce_error = maxd(m.bounce_error, 1);
    if (t->has_collide) m.overlap_p99 = overlap_p99(t);
    else m.overlap = -1, m.overlap_p99 = -1, m.deep_pairs = -1;
    if (!t->has_collide || !(t->step * s->dt > SETTLE_TIME + 1e-9)) m.settled = -1;
    if (!t->has_slide) m.ghost_bumps = -1, m.max_up = -1, m.speed_loss = -1;
    if (!t->has_energy) m.energy_drift = -1;
    if (!t->has_rest) m.jitter = -1, m.rest_speed = -1;
    if (!t->has_bounce) m.bounce_error = -1;
    if (!t->has_flight) m.flight_error = -1;
    return m;
}
