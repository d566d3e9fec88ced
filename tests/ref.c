/* Independent geometric reference for the ntile tests (see ref.h).
 *
 * Written from the notes' text only: the tile shapes below are the notes' `pn`
 * shapes mirrored x -> 1-x when signx = -1 and y -> 1-y when signy = +1. Double
 * precision throughout; no engine call, no engine table. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ref.h"

#define REF_PI 3.14159265358979323846
/* Exact contact positions must count as free despite rounding: the MTV free test
 * shrinks the object by this much. */
#define REF_EPS 1e-9

/* ------------------------------------------------------------------ tiles */

typedef struct rseg {
    double ax, ay, bx, by;
} rseg;

/* Quarter arc of radius 1: the points o + (cos t, sin t) whose offset from o has the
 * signs (qx, qy) (a closed quadrant). End points o + (qx, 0) and o + (0, qy). */
typedef struct rarc {
    double ox, oy;
    int qx, qy;
} rarc;

typedef struct rtile {
    int kind;
    int sx, sy;
    int nv;            /* polygon vertices, in order (either orientation) / round: corners */
    double vx[4], vy[4];
    double orient;     /* polygon: sign of the shoelace area */
    int nseg;          /* boundary pieces */
    rseg seg[4];
    int has_arc;
    rarc arc;
} rtile;

static const char *const NAMES[34] = {
    "EMPTY", "FULL",
    "45DEGpn", "45DEGnn", "45DEGnp", "45DEGpp",
    "CONCAVEpn", "CONCAVEnn", "CONCAVEnp", "CONCAVEpp",
    "CONVEXpn", "CONVEXnn", "CONVEXnp", "CONVEXpp",
    "22DEGpnS", "22DEGnnS", "22DEGnpS", "22DEGppS",
    "22DEGpnB", "22DEGnnB", "22DEGnpB", "22DEGppB",
    "67DEGpnS", "67DEGnnS", "67DEGnpS", "67DEGppS",
    "67DEGpnB", "67DEGnnB", "67DEGnpB", "67DEGppB",
    "HALFd", "HALFr", "HALFu", "HALFl",
};

static rtile TILES[34];
static int tiles_ready;

static void set_polygon(rtile *t, int n, const double *xs, const double *ys)
{
    t->kind = REF_KIND_POLYGON;
    t->nv = n;
    double area2 = 0;
    for (int i = 0; i < n; i++) {
        int j = (i + 1) % n;
        t->vx[i] = xs[i];
        t->vy[i] = ys[i];
        area2 += xs[i] * ys[j] - xs[j] * ys[i];
        t->seg[i].ax = xs[i];
        t->seg[i].ay = ys[i];
        t->seg[i].bx = xs[j];
        t->seg[i].by = ys[j];
    }
    t->orient = area2 > 0 ? 1.0 : -1.0;
    t->nseg = n;
}

static void build_tile(int id, rtile *t)
{
    memset(t, 0, sizeof *t);
    if (id == 0) {
        t->kind = REF_KIND_EMPTY;
        return;
    }
    if (id == 1) {
        const double xs[4] = {0, 1, 1, 0}, ys[4] = {0, 0, 1, 1};
        set_polygon(t, 4, xs, ys);
        return;
    }
    if (id >= 30) {
        /* HALFd bottom half, HALFr right, HALFu top, HALFl left. */
        static const double H[4][2][4] = {
            {{0, 1, 1, 0}, {0.5, 0.5, 1, 1}},
            {{0.5, 1, 1, 0.5}, {0, 0, 1, 1}},
            {{0, 1, 1, 0}, {0, 0, 0.5, 0.5}},
            {{0, 0.5, 0.5, 0}, {0, 0, 1, 1}},
        };
        set_polygon(t, 4, H[id - 30][0], H[id - 30][1]);
        return;
    }
    /* Families of four: suffix pn, nn, np, pp = (signx, signy). */
    int base = 2 + ((id - 2) / 4) * 4, k = id - base;
    t->sx = (k == 0 || k == 3) ? 1 : -1;
    t->sy = (k <= 1) ? -1 : 1;
    const int mirx = t->sx < 0, miry = t->sy > 0;
#define MX(x) (mirx ? 1.0 - (x) : (x))
#define MY(y) (miry ? 1.0 - (y) : (y))
    if (base == 6 || base == 10) {
        /* Round tiles, canonical pn: CONVEX = quarter disc around (0,1); CONCAVE =
         * cell minus the disc around (1,0). Both have the straight sides x = 0 and y = 1
         * and an arc from (0,0) to (1,1). */
        t->kind = base == 6 ? REF_KIND_CONCAVE : REF_KIND_CONVEX;
        const double cx[3] = {0, 0, 1}, cy[3] = {0, 1, 1};
        t->nv = 3;
        for (int i = 0; i < 3; i++) {
            t->vx[i] = MX(cx[i]);
            t->vy[i] = MY(cy[i]);
        }
        t->nseg = 2;
        for (int i = 0; i < 2; i++) {
            t->seg[i].ax = t->vx[i];
            t->seg[i].ay = t->vy[i];
            t->seg[i].bx = t->vx[i + 1];
            t->seg[i].by = t->vy[i + 1];
        }
        t->has_arc = 1;
        double ox = base == 6 ? 1 : 0, oy = base == 6 ? 0 : 1;
        int qx = base == 6 ? -1 : 1, qy = base == 6 ? 1 : -1;
        t->arc.ox = MX(ox);
        t->arc.oy = MY(oy);
        t->arc.qx = mirx ? -qx : qx;
        t->arc.qy = miry ? -qy : qy;
        return;
    }
    /* The `pn` shapes of the sloped families, by first id (notes' table). */
    static const struct {
        int base, n;
        double x[4], y[4];
    } shapes[] = {
        {2, 3, {0, 0, 1}, {0, 1, 1}},               /* 45DEG: (0,0) (0,1) (1,1) */
        {14, 3, {0, 0, 1}, {0.5, 1, 1}},            /* 22DEG S: (0,0.5) (0,1) (1,1) */
        {18, 4, {0, 1, 1, 0}, {0, 0.5, 1, 1}},      /* 22DEG B: (0,0) (1,0.5) (1,1) (0,1) */
        {22, 3, {0, 0, 0.5}, {0, 1, 1}},            /* 67DEG S: (0,0) (0,1) (0.5,1) */
        {26, 4, {0, 0.5, 1, 0}, {0, 0, 1, 1}},      /* 67DEG B: (0,0) (0.5,0) (1,1) (0,1) */
    };
    int f = 0;
    while (f < 4 && shapes[f].base != base) f++; /* 26 when no other */
    double xs[4], ys[4];
    int n = shapes[f].n;
    memcpy(xs, shapes[f].x, sizeof xs);
    memcpy(ys, shapes[f].y, sizeof ys);
    for (int i = 0; i < n; i++) {
        xs[i] = MX(xs[i]);
        ys[i] = MY(ys[i]);
    }
#undef MX
#undef MY
    int sx = t->sx, sy = t->sy;
    set_polygon(t, n, xs, ys);
    t->sx = sx;
    t->sy = sy;
}

static const rtile *tile(int id)
{
    if (!tiles_ready) {
        for (int i = 0; i < 34; i++) build_tile(i, &TILES[i]);
        tiles_ready = 1;
    }
    if (id < 0 || id >= 34) return &TILES[0];
    return &TILES[id];
}

const char *ref_tile_name(int id) { return (id >= 0 && id < 34) ? NAMES[id] : NULL; }

int ref_tile_kind(int id) { return tile(id)->kind; }

void ref_tile_signs(int id, int *sx, int *sy)
{
    const rtile *t = tile(id);
    *sx = t->sx;
    *sy = t->sy;
}

int ref_tile_corners(int id, double *xs, double *ys)
{
    const rtile *t = tile(id);
    for (int i = 0; i < t->nv; i++) {
        xs[i] = t->vx[i];
        ys[i] = t->vy[i];
    }
    return t->nv;
}

bool ref_tile_arc_center(int id, double *ox, double *oy)
{
    const rtile *t = tile(id);
    if (!t->has_arc) return false;
    *ox = t->arc.ox;
    *oy = t->arc.oy;
    return true;
}

ref_shape ref_shape_grow(ref_shape s, double delta)
{
    s.hw += delta;
    s.hh += delta;
    if (s.hw < 0) s.hw = 0;
    if (s.hh < 0) s.hh = 0;
    return s;
}

/* ------------------------------------------------------------ point tests */

static bool tile_contains(const rtile *t, double x, double y)
{
    switch (t->kind) {
    case REF_KIND_POLYGON:
        /* Strictly on the inner side of every edge. Exact for float inputs: the
         * vertex coordinates are 0, 0.5 or 1. */
        for (int i = 0; i < t->nseg; i++) {
            const rseg *e = &t->seg[i];
            double cr = (e->bx - e->ax) * (y - e->ay) - (e->by - e->ay) * (x - e->ax);
            if (!(t->orient * cr > 0)) return false;
        }
        return true;
    case REF_KIND_CONVEX:
    case REF_KIND_CONCAVE: {
        if (!(x > 0 && x < 1 && y > 0 && y < 1)) return false;
        double dx = x - t->arc.ox, dy = y - t->arc.oy, d2 = dx * dx + dy * dy;
        return t->kind == REF_KIND_CONVEX ? d2 < 1 : d2 > 1;
    }
    default:
        return false;
    }
}

bool ref_point_in_tile(int id, double x, double y) { return tile_contains(tile(id), x, y); }

static double dist_seg(const rseg *e, double x, double y)
{
    double ex = e->bx - e->ax, ey = e->by - e->ay;
    double u = ((x - e->ax) * ex + (y - e->ay) * ey) / (ex * ex + ey * ey);
    if (u < 0) u = 0;
    if (u > 1) u = 1;
    double px = e->ax + u * ex - x, py = e->ay + u * ey - y;
    return sqrt(px * px + py * py);
}

static double dist_arc(const rarc *a, double x, double y)
{
    double vx = x - a->ox, vy = y - a->oy;
    if (vx * a->qx >= 0 && vy * a->qy >= 0) return fabs(sqrt(vx * vx + vy * vy) - 1);
    /* Outside the arc's quadrant the nearest arc point is an end point. */
    double d0 = hypot(vx - a->qx, vy), d1 = hypot(vx, vy - a->qy);
    return d0 < d1 ? d0 : d1;
}

static double tile_sd(const rtile *t, double x, double y)
{
    if (t->kind == REF_KIND_EMPTY) return INFINITY;
    double d = INFINITY;
    for (int i = 0; i < t->nseg; i++) {
        double e = dist_seg(&t->seg[i], x, y);
        if (e < d) d = e;
    }
    if (t->has_arc) {
        double e = dist_arc(&t->arc, x, y);
        if (e < d) d = e;
    }
    return tile_contains(t, x, y) ? -d : d;
}

double ref_tile_signed_distance(int id, double x, double y) { return tile_sd(tile(id), x, y); }

/* ---------------------------------------------------------- object tests */

/* Does the closed segment meet the open box? Separating axes x, y and the segment's
 * normal, with touching counted as separated. */
static bool seg_meets_box(const rseg *e, double cx, double cy, double hw, double hh)
{
    if (fmin(e->ax, e->bx) >= cx + hw || fmax(e->ax, e->bx) <= cx - hw) return false;
    if (fmin(e->ay, e->by) >= cy + hh || fmax(e->ay, e->by) <= cy - hh) return false;
    double nx = -(e->by - e->ay), ny = e->bx - e->ax;
    double proj = nx * (cx - e->ax) + ny * (cy - e->ay);
    double rad = fabs(nx) * hw + fabs(ny) * hh;
    return fabs(proj) < rad;
}

/* Does the closed quarter arc meet the open box? The arc is the graph of a strictly
 * monotone y = f(x) over [xlo, xhi]; the box's x span J meets that range, and f(J)
 * is an interval with end values f(J's ends), which must meet (cy - hh, cy + hh). */
static bool arc_meets_box(const rarc *a, double cx, double cy, double hw, double hh)
{
    double xlo = fmin(a->ox, a->ox + a->qx), xhi = fmax(a->ox, a->ox + a->qx);
    if (cx - hw >= xhi || cx + hw <= xlo) return false;
    double xa = fmax(cx - hw, xlo), xb = fmin(cx + hw, xhi);
    double ua = xa - a->ox, ub = xb - a->ox;
    double fa = a->oy + a->qy * sqrt(fmax(0.0, 1 - ua * ua));
    double fb = a->oy + a->qy * sqrt(fmax(0.0, 1 - ub * ub));
    return fmin(fa, fb) < cy + hh && fmax(fa, fb) > cy - hh;
}

/* Interiors of an open box and a tile meet iff the centre is inside the tile or a
 * boundary piece of the tile passes through the box (the tile is the closure of its
 * interior, and the box is connected). */
static bool box_overlaps(const rtile *t, double cx, double cy, double hw, double hh)
{
    if (t->kind == REF_KIND_EMPTY) return false;
    if (cx + hw <= 0 || cx - hw >= 1 || cy + hh <= 0 || cy - hh >= 1) return false;
    if (tile_contains(t, cx, cy)) return true;
    for (int i = 0; i < t->nseg; i++)
        if (seg_meets_box(&t->seg[i], cx, cy, hw, hh)) return true;
    return t->has_arc && arc_meets_box(&t->arc, cx, cy, hw, hh);
}

/* Tile-local overlap test with a tolerance: the object shrunk by eps (a point: inside
 * by more than eps). eps = 0 is the exact test. */
static bool obj_overlaps(const rtile *t, ref_shape s, double cx, double cy, double eps)
{
    if (t->kind == REF_KIND_EMPTY) return false;
    if (s.hw <= 0 && s.hh <= 0) {
        if (eps == 0) return tile_contains(t, cx, cy);
        return tile_sd(t, cx, cy) < -eps;
    }
    double hw = s.hw - eps, hh = s.hh - eps;
    if (s.is_circle) {
        if (cx + hw <= 0 || cx - hw >= 1 || cy + hw <= 0 || cy - hw >= 1) return false;
        return tile_sd(t, cx, cy) < hw;
    }
    return box_overlaps(t, cx, cy, hw, hh);
}

bool ref_object_overlaps_tile(int id, ref_shape s, double cx, double cy)
{
    return obj_overlaps(tile(id), s, cx, cy, 0);
}

/* ----------------------------------------------------------------- worlds */

/* A grid of tiles with cell size 1; `outside` is the tile of every cell beyond it. */
typedef struct world {
    const int *tiles;
    int w, h;
    int outside;
} world;

static int world_tile(const world *W, int x, int y)
{
    if (x < 0 || y < 0 || x >= W->w || y >= W->h) return W->outside;
    int id = W->tiles[(size_t)y * (size_t)W->w + (size_t)x];
    return (id >= 0 && id < 34) ? id : 0;
}

static bool world_overlaps(const world *W, ref_shape s, double cx, double cy, double eps)
{
    int x0 = (int)floor(cx - s.hw), x1 = (int)floor(cx + s.hw);
    int y0 = (int)floor(cy - s.hh), y1 = (int)floor(cy + s.hh);
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            int id = world_tile(W, x, y);
            if (id && obj_overlaps(tile(id), s, cx - x, cy - y, eps)) return true;
        }
    return false;
}

/* ------------------------------------------------- MTV by exhaustive candidates */

enum { C_LINE = 0, C_CIRCLE = 1, C_POINT = 2 };

typedef struct curve {
    int type;
    double a, b, k;   /* line a x + b y = k, (a, b) unit */
    double ox, oy, r; /* circle / point */
} curve;

typedef struct cand {
    double d2, x, y;
} cand;

typedef struct vec_curve {
    curve *v;
    size_t n, cap;
} vec_curve;

typedef struct vec_cand {
    cand *v;
    size_t n, cap;
} vec_cand;

static void *grow(void *p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap) return p;
    size_t c = *cap ? *cap * 2 : 64;
    while (c < need) c *= 2;
    void *q = realloc(p, c * elem);
    if (!q) abort();
    *cap = c;
    return q;
}

static void add_curve(vec_curve *V, curve c)
{
    if (c.type == C_LINE) { /* canonical sign, so duplicates compare equal */
        if (c.a < -1e-15 || (fabs(c.a) <= 1e-15 && c.b < 0)) {
            c.a = -c.a;
            c.b = -c.b;
            c.k = -c.k;
        }
    }
    for (size_t i = 0; i < V->n; i++) {
        const curve *o = &V->v[i];
        if (o->type != c.type) continue;
        if (c.type == C_LINE) {
            if (fabs(o->a - c.a) < 1e-12 && fabs(o->b - c.b) < 1e-12 && fabs(o->k - c.k) < 1e-12) return;
        } else if (fabs(o->ox - c.ox) < 1e-12 && fabs(o->oy - c.oy) < 1e-12 && fabs(o->r - c.r) < 1e-12) {
            return;
        }
    }
    V->v = grow(V->v, &V->cap, V->n + 1, sizeof(curve));
    V->v[V->n++] = c;
}

static curve mk_line(double a, double b, double k)
{
    curve c = {C_LINE, a, b, k, 0, 0, 0};
    return c;
}

static curve mk_circle(double ox, double oy, double r)
{
    curve c = {r > 0 ? C_CIRCLE : C_POINT, 0, 0, 0, ox, oy, r > 0 ? r : 0};
    return c;
}

/* Every line and circle on which the object's centre touches a feature of the tile
 * at offset (tx, ty): a superset of the boundary of the set of overlapping centres. */
static void tile_curves(vec_curve *V, const rtile *t, double tx, double ty, ref_shape s)
{
    if (t->kind == REF_KIND_EMPTY) return;
    double vx[10], vy[10];
    int nv = 0;
    for (int i = 0; i < t->nseg; i++) {
        vx[nv] = t->seg[i].ax + tx;
        vy[nv++] = t->seg[i].ay + ty;
        vx[nv] = t->seg[i].bx + tx;
        vy[nv++] = t->seg[i].by + ty;
    }
    if (t->has_arc) {
        vx[nv] = t->arc.ox + t->arc.qx + tx;
        vy[nv++] = t->arc.oy + ty;
        vx[nv] = t->arc.ox + tx;
        vy[nv++] = t->arc.oy + t->arc.qy + ty;
    }
    const int point = s.hw <= 0 && s.hh <= 0;
    if (point || s.is_circle) {
        double r = point ? 0 : s.hw;
        for (int i = 0; i < nv; i++) add_curve(V, mk_circle(vx[i], vy[i], r)); /* vertex */
        for (int i = 0; i < t->nseg; i++) {                                     /* edge offsets */
            const rseg *e = &t->seg[i];
            double ex = e->bx - e->ax, ey = e->by - e->ay, L = hypot(ex, ey);
            double nx = -ey / L, ny = ex / L, k = nx * (e->ax + tx) + ny * (e->ay + ty);
            add_curve(V, mk_line(nx, ny, k + r));
            if (r > 0) add_curve(V, mk_line(nx, ny, k - r));
        }
        if (t->has_arc) { /* arc from outside (1 + r) and inside (1 - r) */
            add_curve(V, mk_circle(t->arc.ox + tx, t->arc.oy + ty, 1 + r));
            if (r > 0) add_curve(V, mk_circle(t->arc.ox + tx, t->arc.oy + ty, fabs(1 - r)));
        }
        return;
    }
    const double hw = s.hw, hh = s.hh;
    for (int i = 0; i < nv; i++) { /* a tile vertex on a box side */
        add_curve(V, mk_line(1, 0, vx[i] + hw));
        add_curve(V, mk_line(1, 0, vx[i] - hw));
        add_curve(V, mk_line(0, 1, vy[i] + hh));
        add_curve(V, mk_line(0, 1, vy[i] - hh));
    }
    for (int i = 0; i < t->nseg; i++) { /* a box corner on a sloped edge */
        const rseg *e = &t->seg[i];
        double ex = e->bx - e->ax, ey = e->by - e->ay;
        if (ex == 0 || ey == 0) continue; /* same lines as the vertices' */
        double L = hypot(ex, ey), nx = -ey / L, ny = ex / L;
        double k = nx * (e->ax + tx) + ny * (e->ay + ty);
        for (int sxk = -1; sxk <= 1; sxk += 2)
            for (int syk = -1; syk <= 1; syk += 2) add_curve(V, mk_line(nx, ny, k - nx * sxk * hw - ny * syk * hh));
    }
    if (t->has_arc) /* a box corner on the arc */
        for (int sxk = -1; sxk <= 1; sxk += 2)
            for (int syk = -1; syk <= 1; syk += 2)
                add_curve(V, mk_circle(t->arc.ox + tx - sxk * hw, t->arc.oy + ty - syk * hh, 1));
}

static void add_cand(vec_cand *C, double cx, double cy, double x, double y)
{
    if (!isfinite(x) || !isfinite(y)) return;
    C->v = grow(C->v, &C->cap, C->n + 1, sizeof(cand));
    cand c = {(x - cx) * (x - cx) + (y - cy) * (y - cy), x, y};
    C->v[C->n++] = c;
}

static double curve_dist(const curve *c, double x, double y)
{
    if (c->type == C_LINE) return fabs(c->a * x + c->b * y - c->k);
    return fabs(hypot(x - c->ox, y - c->oy) - c->r);
}

/* Nearest points of a curve to (cx, cy). */
static void foot(vec_cand *C, const curve *c, double cx, double cy)
{
    if (c->type == C_LINE) {
        double s = c->a * cx + c->b * cy - c->k;
        add_cand(C, cx, cy, cx - s * c->a, cy - s * c->b);
    } else if (c->type == C_POINT) {
        add_cand(C, cx, cy, c->ox, c->oy);
    } else {
        double vx = cx - c->ox, vy = cy - c->oy, d = hypot(vx, vy);
        if (d > 1e-12) {
            add_cand(C, cx, cy, c->ox + c->r * vx / d, c->oy + c->r * vy / d);
        } else { /* every point is nearest: a few, the rest come from intersections */
            for (int i = 0; i < 8; i++) {
                double a = 0.3 + i * REF_PI / 4;
                add_cand(C, cx, cy, c->ox + c->r * cos(a), c->oy + c->r * sin(a));
            }
        }
    }
}

static void intersect(vec_cand *C, const curve *p, const curve *q, double cx, double cy)
{
    if (p->type == C_POINT || q->type == C_POINT) return; /* points are their own feet */
    if (p->type == C_CIRCLE && q->type == C_LINE) {
        const curve *t = p;
        p = q;
        q = t;
    }
    if (p->type == C_LINE && q->type == C_LINE) {
        double det = p->a * q->b - q->a * p->b;
        if (fabs(det) < 1e-13) return;
        add_cand(C, cx, cy, (p->k * q->b - q->k * p->b) / det, (p->a * q->k - q->a * p->k) / det);
    } else if (p->type == C_LINE) {
        double s = p->a * q->ox + p->b * q->oy - p->k;
        double h2 = q->r * q->r - s * s;
        if (h2 < -1e-10) return;
        double h = sqrt(fmax(0.0, h2));
        double fx = q->ox - s * p->a, fy = q->oy - s * p->b;
        add_cand(C, cx, cy, fx - h * p->b, fy + h * p->a);
        add_cand(C, cx, cy, fx + h * p->b, fy - h * p->a);
    } else {
        double dx = q->ox - p->ox, dy = q->oy - p->oy, d = hypot(dx, dy);
        if (d < 1e-13) return;
        double a = (p->r * p->r - q->r * q->r + d * d) / (2 * d);
        double h2 = p->r * p->r - a * a;
        if (h2 < -1e-10) return;
        double h = sqrt(fmax(0.0, h2));
        double mx = p->ox + a * dx / d, my = p->oy + a * dy / d;
        add_cand(C, cx, cy, mx - h * dy / d, my + h * dx / d);
        add_cand(C, cx, cy, mx + h * dy / d, my - h * dx / d);
    }
}

static int cmp_cand(const void *a, const void *b)
{
    double x = ((const cand *)a)->d2, y = ((const cand *)b)->d2;
    return x < y ? -1 : (x > y ? 1 : 0);
}

/* The nearest free candidate among C (sorted here) closer than sqrt(limit2). */
static int first_free(const world *W, ref_shape s, vec_cand *C, double limit2, cand *out)
{
    if (C->n) qsort(C->v, C->n, sizeof(cand), cmp_cand);
    for (size_t i = 0; i < C->n; i++) {
        if (C->v[i].d2 >= limit2) break;
        if (!world_overlaps(W, s, C->v[i].x, C->v[i].y, REF_EPS)) {
            *out = C->v[i];
            return 1;
        }
    }
    return 0;
}

/* Candidate search with the curves of the cells [x0,x1] x [y0,y1]. Returns the squared
 * distance (INFINITY when no candidate is free) and the point. */
static double mtv_window(const world *W, ref_shape s, double cx, double cy, int x0, int x1, int y0, int y1,
                         double *qx, double *qy)
{
    vec_curve V = {0};
    vec_cand C = {0};
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            int id = world_tile(W, x, y);
            if (id) tile_curves(&V, tile(id), x, y, s);
        }
    /* Upper bound from the feet of the perpendiculars alone. */
    for (size_t i = 0; i < V.n; i++) foot(&C, &V.v[i], cx, cy);
    cand best = {INFINITY, cx, cy};
    first_free(W, s, &C, INFINITY, &best);
    /* Then every pairwise intersection of the curves that come that close. */
    double U = sqrt(best.d2) + 1e-9;
    size_t m = 0;
    for (size_t i = 0; i < V.n; i++)
        if (curve_dist(&V.v[i], cx, cy) <= U) V.v[m++] = V.v[i];
    C.n = 0;
    for (size_t i = 0; i < m; i++)
        for (size_t j = i + 1; j < m; j++) intersect(&C, &V.v[i], &V.v[j], cx, cy);
    cand b2;
    if (first_free(W, s, &C, best.d2, &b2)) best = b2;
    free(V.v);
    free(C.v);
    *qx = best.x;
    *qy = best.y;
    return best.d2;
}

static double mtv_world(const world *W, ref_shape s, double cx, double cy, double *dx, double *dy)
{
    *dx = 0;
    *dy = 0;
    if (!world_overlaps(W, s, cx, cy, 0)) return 0;
    /* Cells that can matter: the grid, plus (FULL outside) one ring of border cells: an
     * object at a free position lies inside the grid, so it touches nothing farther. */
    int ring = W->outside ? 1 : 0;
    int gx0 = -ring, gy0 = -ring, gx1 = W->w - 1 + ring, gy1 = W->h - 1 + ring;
    double ext = fmax(s.hw, s.hh);
    int ix = (int)floor(cx), iy = (int)floor(cy);
    for (int K = 2;; K += 2) {
        int x0 = ix - K, x1 = ix + K, y0 = iy - K, y1 = iy + K;
        if (x0 < gx0) x0 = gx0;
        if (y0 < gy0) y0 = gy0;
        if (x1 > gx1) x1 = gx1;
        if (y1 > gy1) y1 = gy1;
        int all = x0 == gx0 && y0 == gy0 && x1 == gx1 && y1 == gy1;
        double qx = cx, qy = cy, d2 = INFINITY;
        if (x0 <= x1 && y0 <= y1) d2 = mtv_window(W, s, cx, cy, x0, x1, y0, y1, &qx, &qy);
        double d = sqrt(d2);
        /* Valid when every cell the object can touch within distance d is in the window
         * (or the window is everything that can matter). */
        int covered = isfinite(d) && ((floor(cx - d - ext - 1e-6) >= x0 || x0 == gx0) &&
                                      (floor(cx + d + ext + 1e-6) <= x1 || x1 == gx1) &&
                                      (floor(cy - d - ext - 1e-6) >= y0 || y0 == gy0) &&
                                      (floor(cy + d + ext + 1e-6) <= y1 || y1 == gy1));
        if (covered) {
            if (d > 0) {
                *dx = qx - cx;
                *dy = qy - cy;
            }
            return d;
        }
        if (all) return -1; /* no room anywhere */
    }
}

double ref_mtv_tile(int id, ref_shape s, double cx, double cy, double *dx, double *dy)
{
    world W = {&id, 1, 1, 0};
    double ddx, ddy;
    double d = mtv_world(&W, s, cx, cy, &ddx, &ddy);
    if (dx) *dx = ddx;
    if (dy) *dy = ddy;
    return d;
}

int ref_map_tile(const int *tiles, int w, int h, int x, int y)
{
    world W = {tiles, w, h, 1};
    return world_tile(&W, x, y);
}

bool ref_object_overlaps_map(const int *tiles, int w, int h, ref_shape s, double cx, double cy)
{
    world W = {tiles, w, h, 1};
    return world_overlaps(&W, s, cx, cy, 0);
}

double ref_mtv_map(const int *tiles, int w, int h, ref_shape s, double cx, double cy, double *dx, double *dy)
{
    world W = {tiles, w, h, 1};
    double ddx, ddy;
    double d = mtv_world(&W, s, cx, cy, &ddx, &ddy);
    if (dx) *dx = ddx;
    if (dy) *dy = ddy;
    return d;
}

/* ------------------------------------------------- MTV by direction sampling */

/* First t in (0, limit] along (ux, uy) at which the object is free: scan with a fixed
 * step, then bisect the first overlapping -> free step. INFINITY when none. */
static double ray_first_free(const world *W, ref_shape s, double cx, double cy, double ux, double uy, double limit)
{
    const double step = 1.0 / 128;
    double lo = 0;
    for (int j = 1;; j++) {
        double t = j * step;
        if (t > limit + step) return INFINITY;
        if (!world_overlaps(W, s, cx + t * ux, cy + t * uy, 0)) {
            double hi = t;
            for (int it = 0; it < 44; it++) {
                double mid = 0.5 * (lo + hi);
                if (world_overlaps(W, s, cx + mid * ux, cy + mid * uy, 0)) lo = mid;
                else hi = mid;
            }
            return hi;
        }
        lo = t;
    }
}

/* 2D pattern search from a free point p toward the centre: try points around p at
 * radius rho in many directions, move to the closest free one that is nearer the centre,
 * halve rho when none is. Reaches the tip of a thin free wedge, where rays from the
 * centre only cross short free chords that a scan steps over. */
static void polish(const world *W, ref_shape s, double cx, double cy, double *px, double *py, double rho)
{
    enum { ND = 360 };
    double bx = *px, by = *py, bd = hypot(bx - cx, by - cy);
    for (int it = 0; it < 4000 && rho > 1e-12; it++) {
        double nx = bx, ny = by, nd = bd;
        for (int j = 0; j < ND; j++) {
            double a = 0.0421 + j * (2 * REF_PI / ND);
            for (int f = 0; f < 3; f++) {
                double r = rho * (f == 0 ? 1 : f == 1 ? 0.3 : 0.1);
                double qx = bx + r * cos(a), qy = by + r * sin(a), qd = hypot(qx - cx, qy - cy);
                if (qd < nd && !world_overlaps(W, s, qx, qy, 0)) {
                    nx = qx;
                    ny = qy;
                    nd = qd;
                }
            }
        }
        if (nd < bd) {
            bx = nx;
            by = ny;
            bd = nd;
        } else {
            rho *= 0.5;
        }
    }
    *px = bx;
    *py = by;
}

static double sampled_world(const world *W, ref_shape s, double cx, double cy, int ndir, double max_dist,
                            double *dx, double *dy)
{
    *dx = 0;
    *dy = 0;
    if (!world_overlaps(W, s, cx, cy, 0)) return 0;
    if (ndir < 16) ndir = 16;
    const double theta0 = 0.1234567; /* no axis or known normal is sampled exactly */
    const double dth = 2 * REF_PI / ndir;
    double *t = malloc((size_t)ndir * sizeof(double));
    if (!t) abort();
    double best = INFINITY, limit = max_dist;
    /* Every 8th direction first, so the pruning limit drops early. */
    for (int pass = 0; pass < 2; pass++)
        for (int k = 0; k < ndir; k++) {
            if ((pass == 0) != (k % 8 == 0)) continue;
            double a = theta0 + k * dth;
            t[k] = ray_first_free(W, s, cx, cy, cos(a), sin(a), limit);
            if (t[k] < best) {
                best = t[k];
                limit = best;
            }
        }
    if (!isfinite(best)) {
        free(t);
        return -1;
    }
    double best_a = 0;
    for (int k = 0; k < ndir; k++)
        if (t[k] == best) best_a = theta0 + k * dth;
    /* Refine the angle around the few best local minima (golden section). */
    for (int pick = 0; pick < 3; pick++) {
        int kb = -1;
        for (int k = 0; k < ndir; k++) {
            double v = t[k];
            if (!isfinite(v)) continue;
            if (v > t[(k + 1) % ndir] || v > t[(k + ndir - 1) % ndir]) continue;
            if (kb < 0 || v < t[kb]) kb = k;
        }
        if (kb < 0) break;
        double lo = theta0 + (kb - 1) * dth, hi = theta0 + (kb + 1) * dth;
        const double g = 0.6180339887498949;
        double a1 = hi - g * (hi - lo), a2 = lo + g * (hi - lo);
        double lim = t[kb] * 1.5 + 0.02;
        double f1 = ray_first_free(W, s, cx, cy, cos(a1), sin(a1), lim);
        double f2 = ray_first_free(W, s, cx, cy, cos(a2), sin(a2), lim);
        for (int it = 0; it < 48; it++) {
            if (f1 <= f2) {
                hi = a2;
                a2 = a1;
                f2 = f1;
                a1 = hi - g * (hi - lo);
                f1 = ray_first_free(W, s, cx, cy, cos(a1), sin(a1), lim);
            } else {
                lo = a1;
                a1 = a2;
                f1 = f2;
                a2 = lo + g * (hi - lo);
                f2 = ray_first_free(W, s, cx, cy, cos(a2), sin(a2), lim);
            }
        }
        if (f1 < best) {
            best = f1;
            best_a = a1;
        }
        if (f2 < best) {
            best = f2;
            best_a = a2;
        }
        t[kb] = INFINITY; /* next pick: another local minimum */
    }
    free(t);
    double px = cx + best * cos(best_a), py = cy + best * sin(best_a);
    polish(W, s, cx, cy, &px, &py, 0.01);
    *dx = px - cx;
    *dy = py - cy;
    return hypot(*dx, *dy);
}

double ref_mtv_tile_sampled(int id, ref_shape s, double cx, double cy, int ndir, double *dx, double *dy)
{
    world W = {&id, 1, 1, 0};
    double ddx, ddy;
    double d = sampled_world(&W, s, cx, cy, ndir, 2.5, &ddx, &ddy);
    if (dx) *dx = ddx;
    if (dy) *dy = ddy;
    return d;
}

double ref_mtv_map_sampled(const int *tiles, int w, int h, ref_shape s, double cx, double cy, int ndir,
                           double max_dist, double *dx, double *dy)
{
    world W = {tiles, w, h, 1};
    double ddx, ddy;
    double d = sampled_world(&W, s, cx, cy, ndir, max_dist, &ddx, &ddy);
    if (dx) *dx = ddx;
    if (dy) *dy = ddy;
    return d;
}

/* -------------------------------------------------------------------- PRNG */

unsigned long long ref_rng_next(ref_rng *r)
{
    unsigned long long z = (r->state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

double ref_rng_uniform(ref_rng *r, double lo, double hi)
{
    double u = (double)(ref_rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
    return lo + (hi - lo) * u;
}

int ref_rng_int(ref_rng *r, int n) { return (int)(ref_rng_next(r) % (unsigned long long)n); }

/* ------------------------------------------------------------ brute-force casts */

bool ref_object_overlaps_map_eps(const int *tiles, int w, int h, ref_shape s, double cx, double cy, double eps)
{
    world W = {tiles, w, h, 1};
    return world_overlaps(&W, s, cx, cy, eps);
}

bool ref_objects_overlap(ref_shape a, double ax, double ay, ref_shape b, double bx, double by, double eps)
{
    double ahw = a.hw - eps, ahh = a.hh - eps;
    double dx = ax - bx, dy = ay - by;
    if (a.is_circle && b.is_circle) return sqrt(dx * dx + dy * dy) < ahw + b.hw;
    if (!a.is_circle && !b.is_circle) return fabs(dx) < ahw + b.hw && fabs(dy) < ahh + b.hh;
    /* A circle and a box: the circle's centre nearer than r to the box. */
    double r = a.is_circle ? ahw : b.hw, hw = a.is_circle ? b.hw : ahw, hh = a.is_circle ? b.hh : ahh;
    double qx = fabs(dx) - hw, qy = fabs(dy) - hh;
    double ox = qx > 0 ? qx : 0, oy = qy > 0 ? qy : 0;
    if (qx <= 0 && qy <= 0) return true;
    return sqrt(ox * ox + oy * oy) < r;
}

/* Scan, then bisect, a predicate "overlaps at t" that is false at t = 0. */
typedef bool (*at_fn)(const void *ctx, double t);

static bool first_true(at_fn f, const void *ctx, double len, double step, double *t)
{
    if (f(ctx, 0)) {
        *t = 0;
        return true;
    }
    long n = (long)ceil(len / step);
    if (n < 16) n = 16;
    double prev = 0;
    for (long k = 1; k <= n; k++) {
        double u = (double)k / (double)n;
        if (f(ctx, u)) {
            double lo = prev, hi = u;
            for (int it = 0; it < 60 && hi - lo > 1e-13; it++) {
                double mid = 0.5 * (lo + hi);
                if (f(ctx, mid)) hi = mid;
                else lo = mid;
            }
            *t = hi;
            return true;
        }
        prev = u;
    }
    return false;
}

typedef struct cast_map_ctx {
    world W;
    ref_shape s;
    double cx, cy, dx, dy, eps;
} cast_map_ctx;

static bool cast_map_at(const void *vctx, double t)
{
    const cast_map_ctx *c = (const cast_map_ctx *)vctx;
    return world_overlaps(&c->W, c->s, c->cx + c->dx * t, c->cy + c->dy * t, c->eps);
}

bool ref_cast_map(const int *tiles, int w, int h, ref_shape s, double cx, double cy, double dx, double dy, double eps,
                  double step, double *t)
{
    cast_map_ctx c = {{tiles, w, h, 1}, s, cx, cy, dx, dy, eps};
    return first_true(cast_map_at, &c, sqrt(dx * dx + dy * dy), step, t);
}

typedef struct cast_obj_ctx {
    ref_shape a, b;
    double ax, ay, dx, dy, bx, by, eps;
} cast_obj_ctx;

static bool cast_obj_at(const void *vctx, double t)
{
    const cast_obj_ctx *c = (const cast_obj_ctx *)vctx;
    return ref_objects_overlap(c->a, c->ax + c->dx * t, c->ay + c->dy * t, c->b, c->bx, c->by, c->eps);
}

bool ref_cast_object(ref_shape a, double ax, double ay, double dx, double dy, ref_shape b, double bx, double by,
                     double eps, double step, double *t)
{
    cast_obj_ctx c = {a, b, ax, ay, dx, dy, bx, by, eps};
    return first_true(cast_obj_at, &c, sqrt(dx * dx + dy * dy), step, t);
}
