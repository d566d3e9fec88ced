/* bench-peers — tile map outlines (see geometry.h).
 *
 * 1. Every solid cell (the map and a FULL ring around it) adds its tile's outline as
 *    directed edges, in cells. Edges on a cell side are cut into half-cell pieces (all
 *    tile corners on a side are at 0, 0.5 or 1), so that a piece shared by two solid
 *    cells appears once in each direction.
 * 2. Pieces present in both directions are seams inside the solid: both go.
 * 3. The rest is walked into loops (at a vertex with several ways on, the turn that
 *    stays closest to the solid side), collinear runs are merged, and points are
 *    scaled to scene units.
 */
#include "geometry.h"
#include <math.h>

#define PI 3.14159265358979323846
#include <stdlib.h>
#include <string.h>

typedef struct edge {
    geo_point a, b;
    long long ka, kb; /* quantised end points */
    int next_from;    /* next edge starting at the same point (hash chain) */
    int dead, used;
} edge;

typedef struct edge_set {
    edge *e;
    int n, cap;
    int *head; /* hash of start points */
    int hsize;
} edge_set;

static long long quant(geo_point p)
{
    /* points are at most a few thousand cells out; 1/4096 cell resolution */
    long long x = llround(p.x * 4096.0), y = llround(p.y * 4096.0);
    return (x + (1LL << 26)) * (1LL << 28) + (y + (1LL << 26));
}

static int add_edge(edge_set *s, geo_point a, geo_point b)
{
    if (a.x == b.x && a.y == b.y) return 1;
    if (s->n == s->cap) {
        int cap = s->cap ? 2 * s->cap : 1024;
        edge *e = realloc(s->e, sizeof *e * (size_t)cap);
        if (!e) return 0;
        s->e = e;
        s->cap = cap;
    }
    edge *e = &s->e[s->n++];
    memset(e, 0, sizeof *e);
    e->a = a;
    e->b = b;
    e->ka = quant(a);
    e->kb = quant(b);
    return 1;
}

/* An edge of a tile in cell (cx, cy), unit coordinates: cut into half-cell pieces when
 * it lies on a side of the cell. */
static int add_tile_edge(edge_set *s, int cx, int cy, nt_vec2 a, nt_vec2 b)
{
    geo_point pa = {cx + (double)a.x, cy + (double)a.y}, pb = {cx + (double)b.x, cy + (double)b.y};
    int on_side = (a.x == b.x && (a.x == 0 || a.x == 1)) || (a.y == b.y && (a.y == 0 || a.y == 1));
    if (!on_side) return add_edge(s, pa, pb);
    double len = fabs(pb.x - pa.x) + fabs(pb.y - pa.y);
    int pieces = (int)llround(len * 2);
    if (pieces < 1 || fabs(len * 2 - pieces) > 1e-9) return add_edge(s, pa, pb); /* a bit of an arc's tangent */
    for (int k = 0; k < pieces; k++) {
        double t0 = (double)k / pieces, t1 = (double)(k + 1) / pieces;
        geo_point p = {pa.x + (pb.x - pa.x) * t0, pa.y + (pb.y - pa.y) * t0};
        geo_point q = {pa.x + (pb.x - pa.x) * t1, pa.y + (pb.y - pa.y) * t1};
        if (!add_edge(s, p, q)) return 0;
    }
    return 1;
}

static int add_tile(edge_set *s, int tile, int cx, int cy)
{
    const nt_tile_info *t = nt_tile_get_info(tile);
    if (!t || t->cls == NT_CLASS_EMPTY) return 1;
    int n = t->vertex_count;
    int round = t->cls == NT_CLASS_CONVEX || t->cls == NT_CLASS_CONCAVE;
    /* straight edges; for round tiles the last one (v[n-1] -> v[0]) is the arc */
    for (int k = 0; k < (round ? n - 1 : n); k++)
        if (!add_tile_edge(s, cx, cy, t->vertices[k], t->vertices[(k + 1) % n])) return 0;
    if (!round) return 1;
    double ccx = (double)t->arc_center.x, ccy = (double)t->arc_center.y;
    double ax = (double)t->vertices[n - 1].x, ay = (double)t->vertices[n - 1].y;
    double bx = (double)t->vertices[0].x, by = (double)t->vertices[0].y;
    double ta = atan2(ay - ccy, ax - ccx), tb = atan2(by - ccy, bx - ccx);
    double sweep = tb - ta;
    while (sweep > PI) sweep -= 2 * PI;
    while (sweep < -PI) sweep += 2 * PI;
    double step = sweep / ARC_SEGMENTS;
    nt_vec2 prev = t->vertices[n - 1];
    if (t->cls == NT_CLASS_CONCAVE) {
        /* chords: points on the arc */
        for (int k = 1; k < ARC_SEGMENTS; k++) {
            double th = ta + step * k;
            nt_vec2 p = nt_v2((nt_real)(ccx + cos(th)), (nt_real)(ccy + sin(th)));
            if (!add_tile_edge(s, cx, cy, prev, p)) return 0;
            prev = p;
        }
    } else {
        /* tangents: corners at the middle angles, radius 1 / cos(step / 2) */
        double r = 1.0 / cos(step / 2);
        for (int k = 0; k < ARC_SEGMENTS; k++) {
            double th = ta + step * (k + 0.5);
            nt_vec2 p = nt_v2((nt_real)(ccx + r * cos(th)), (nt_real)(ccy + r * sin(th)));
            if (!add_tile_edge(s, cx, cy, prev, p)) return 0;
            prev = p;
        }
    }
    return add_tile_edge(s, cx, cy, prev, t->vertices[0]);
}

static unsigned hash_key(long long k, int size)
{
    unsigned long long h = (unsigned long long)k * 0x9E3779B97F4A7C15ull;
    return (unsigned)(h >> 32) % (unsigned)size;
}

static int build_hash(edge_set *s)
{
    s->hsize = 2 * s->n + 1;
    s->head = malloc(sizeof *s->head * (size_t)s->hsize);
    if (!s->head) return 0;
    for (int i = 0; i < s->hsize; i++) s->head[i] = -1;
    for (int i = 0; i < s->n; i++) {
        unsigned h = hash_key(s->e[i].ka, s->hsize);
        s->e[i].next_from = s->head[h];
        s->head[h] = i;
    }
    return 1;
}

int geo_build(const scene *s, geo_loops *out)
{
    memset(out, 0, sizeof *out);
    edge_set es = {0};
    for (int y = -1; y <= s->height; y++)
        for (int x = -1; x <= s->width; x++) {
            int inside = x >= 0 && y >= 0 && x < s->width && y < s->height;
            int tile = inside ? s->tiles[(size_t)y * (size_t)s->width + (size_t)x] : NT_TILE_FULL;
            if (!add_tile(&es, tile, x, y)) goto fail;
        }
    if (!build_hash(&es)) goto fail;
    /* seams: an edge whose reverse exists */
    for (int i = 0; i < es.n; i++) {
        edge *e = &es.e[i];
        if (e->dead) continue;
        for (int j = es.head[hash_key(e->kb, es.hsize)]; j >= 0; j = es.e[j].next_from) {
            edge *r = &es.e[j];
            if (!r->dead && r->ka == e->kb && r->kb == e->ka) {
                e->dead = r->dead = 1;
                break;
            }
        }
    }
    int alive = 0;
    for (int i = 0; i < es.n; i++) alive += !es.e[i].dead;
    out->points = malloc(sizeof *out->points * (size_t)(alive + 1));
    out->start = malloc(sizeof *out->start * (size_t)(alive + 2));
    if (!out->points || !out->start) goto fail;
    out->start[0] = 0;
    int np = 0;
    for (int i = 0; i < es.n; i++) {
        if (es.e[i].dead || es.e[i].used) continue;
        int loop_start = np, cur = i;
        while (cur >= 0 && !es.e[cur].used) {
            edge *e = &es.e[cur];
            e->used = 1;
            out->points[np++] = e->a;
            /* the way on: among unused edges from e->b, the turn most towards the solid
             * (the left, where the cross product of the directions is most negative) */
            double dx = e->b.x - e->a.x, dy = e->b.y - e->a.y, best = 1e9;
            int pick = -1;
            for (int j = es.head[hash_key(e->kb, es.hsize)]; j >= 0; j = es.e[j].next_from) {
                edge *f = &es.e[j];
                if (f->dead || f->used || f->ka != e->kb) continue;
                double fx = f->b.x - f->a.x, fy = f->b.y - f->a.y;
                double turn = atan2(dx * fy - dy * fx, dx * fx + dy * fy);
                if (turn < best) best = turn, pick = j;
            }
            cur = pick;
        }
        /* merge collinear runs (cyclically) */
        int n = np - loop_start, w = 0;
        geo_point *p = out->points + loop_start;
        for (int k = 0; k < n; k++) {
            geo_point prev = w > 0 ? p[w - 1] : p[n - 1], here = p[k], next = p[(k + 1) % n];
            double cr = (here.x - prev.x) * (next.y - here.y) - (here.y - prev.y) * (next.x - here.x);
            double dot = (here.x - prev.x) * (next.x - here.x) + (here.y - prev.y) * (next.y - here.y);
            if (fabs(cr) < 1e-12 && dot > 0) continue; /* straight through: drop */
            p[w++] = here;
        }
        np = loop_start + w;
        if (w >= 3) {
            out->count++;
            out->start[out->count] = np;
            out->edges += w;
        } else {
            np = loop_start;
        }
    }
    for (int i = 0; i < np; i++) {
        out->points[i].x *= s->cell;
        out->points[i].y *= s->cell;
    }
    free(es.e);
    free(es.head);
    return 1;
fail:
    free(es.e);
    free(es.head);
    geo_free(out);
    return 0;
}

void geo_free(geo_loops *g)
{
    free(g->start);
    free(g->points);
    memset(g, 0, sizeof *g);
}
