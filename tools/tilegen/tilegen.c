/* tilegen: N's 34 tiles (include/ntile/tiles.h) from their canonical `pn` shapes,
 * to the three tables of src/tile_tables.c:
 *   nt__tiles  the public table: names, classes, normals, vertices, arcs, bounds and
 *              side coverage;
 *   nt__geom   the straight edges the narrow phase and the map walk;
 *   nt__polys  polygon tiles' faces, ordered for the narrow phase.
 * Each shape is given once, for `pn` (signs of the surface normal (+1, -1), y down);
 * the other orientations mirror it: x -> 1-x when signx = -1, y -> 1-y when signy = +1,
 * and a single mirror reverses the vertex order so that the winding is kept
 * (counter-clockwise on screen). Every number is computed in double and written as the
 * shortest decimal that reads back as the same double; the compiler converts it to
 * nt_real (a float build rounds each once, as (nt_real)x does). */
#include "tilegen.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct pt {
    double x, y;
} pt;

/* A straight edge from a to b. Inside iff ux*x + uy*y < ud, (ux, uy) the outward
 * normal scaled to small integers; n its unit form, t the unit direction. */
typedef struct edge {
    double ux, uy, ud, inv, nx, ny;
    pt a, b;
    double tx, ty, len;
    int side; /* nt_side of the cell side it lies on, or -1 */
} edge;

enum { LEFT = 0, RIGHT = 1, TOP = 2, BOTTOM = 3 };

typedef struct tile {
    char name[16];
    const char *cls; /* NT_CLASS_... */
    int sx, sy;
    int n;           /* vertices */
    pt v[4];
    int round;
    pt arc;
    double nx, ny;   /* the surface's unit outward normal */
    pt bmin, bmax;
    double lo[4], hi[4];
    int ne;          /* straight edges */
    edge e[4];
    int has_slope;
    edge slope;
} tile;

/* A shape in its `pn` orientation; vertices counter-clockwise on screen (y down). */
typedef struct family {
    const char *base, *suffix, *cls;
    int n;
    pt v[4];
    int round;
    pt arc;
} family;

#define TRI45 {{0, 0}, {0, 1}, {1, 1}}
static const family families[] = {
    {"45DEG", "", "NT_CLASS_POLYGON", 3, TRI45, 0, {0, 0}},
    /* round tiles: the straight corners are the 45-degree triangle's */
    {"CONCAVE", "", "NT_CLASS_CONCAVE", 3, TRI45, 1, {1, 0}}, /* cell minus the disc on (1,0) */
    {"CONVEX", "", "NT_CLASS_CONVEX", 3, TRI45, 1, {0, 1}},   /* quarter disc on (0,1) */
    {"22DEG", "S", "NT_CLASS_POLYGON", 3, {{0, 0.5}, {0, 1}, {1, 1}}, 0, {0, 0}},
    {"22DEG", "B", "NT_CLASS_POLYGON", 4, {{0, 0}, {0, 1}, {1, 1}, {1, 0.5}}, 0, {0, 0}},
    {"67DEG", "S", "NT_CLASS_POLYGON", 3, {{0, 0}, {0, 1}, {0.5, 1}}, 0, {0, 0}},
    {"67DEG", "B", "NT_CLASS_POLYGON", 4, {{0, 0}, {0, 1}, {1, 1}, {0.5, 0}}, 0, {0, 0}},
};
#undef TRI45

/* Orientations in id order. */
static const struct {
    const char *name;
    int sx, sy;
} orients[4] = {{"pn", 1, -1}, {"nn", -1, -1}, {"np", -1, 1}, {"pp", 1, 1}};

/* Rectangles [x0, x1] x [y0, y1]: FULL and the half tiles (d = bottom half solid). */
static const struct {
    const char *name;
    double x0, y0, x1, y1;
} rects[] = {{"FULL", 0, 0, 1, 1}, {"HALFd", 0, 0.5, 1, 1}, {"HALFr", 0.5, 0, 1, 1},
             {"HALFu", 0, 0, 1, 0.5}, {"HALFl", 0, 0, 0.5, 1}};

static double pos0(double v) { return v == 0 ? 0.0 : v; } /* no -0 in the tables */

static edge make_edge(pt a, pt b)
{
    edge e;
    double dx = b.x - a.x, dy = b.y - a.y;
    double rx = -dy, ry = dx; /* outward for counter-clockwise on screen */
    double m = rx == 0 ? fabs(ry) : ry == 0 ? fabs(rx) : fmin(fabs(rx), fabs(ry));
    e.ux = pos0(rx / m);
    e.uy = pos0(ry / m);
    e.ud = pos0(e.ux * a.x + e.uy * a.y);
    e.inv = 1 / sqrt(e.ux * e.ux + e.uy * e.uy);
    e.nx = pos0(e.ux * e.inv);
    e.ny = pos0(e.uy * e.inv);
    e.a = a;
    e.b = b;
    e.len = sqrt(dx * dx + dy * dy);
    e.tx = pos0(dx / e.len);
    e.ty = pos0(dy / e.len);
    e.side = a.x == 0 && b.x == 0 ? LEFT : a.x == 1 && b.x == 1 ? RIGHT : a.y == 0 && b.y == 0 ? TOP
           : a.y == 1 && b.y == 1 ? BOTTOM : -1;
    return e;
}

static int is_axis(const edge *e) { return e->ux == 0 || e->uy == 0; }

/* Everything else from the name, class, signs and vertices. */
static void finish(tile *t)
{
    t->bmin = (pt){1, 1}; /* empty: min > max */
    t->bmax = (pt){0, 0};
    for (int s = 0; s < 4; s++) {
        t->lo[s] = 1;
        t->hi[s] = 0;
    }
    for (int i = 0; i < t->n; i++) {
        pt p = t->v[i];
        t->bmin.x = fmin(t->bmin.x, p.x);
        t->bmin.y = fmin(t->bmin.y, p.y);
        t->bmax.x = fmax(t->bmax.x, p.x);
        t->bmax.y = fmax(t->bmax.y, p.y);
        /* the solid meets a side along the span of its corners on that side */
        double along[4] = {p.y, p.y, p.x, p.x};
        int on[4] = {p.x == 0, p.x == 1, p.y == 0, p.y == 1};
        for (int s = 0; s < 4; s++)
            if (on[s]) {
                t->lo[s] = fmin(t->lo[s], along[s]);
                t->hi[s] = fmax(t->hi[s], along[s]);
            }
    }
    t->ne = 0;
    t->has_slope = 0;
    t->nx = t->ny = 0;
    for (int i = 0; i < t->n; i++) {
        edge e = make_edge(t->v[i], t->v[(i + 1) % t->n]);
        if (!is_axis(&e)) {
            t->has_slope = 1;
            t->slope = e;
            t->nx = e.nx;
            t->ny = e.ny;
        } else if (e.side < 0) { /* a half tile's cut */
            t->nx = e.nx;
            t->ny = e.ny;
        }
        /* round tiles keep only the straight sides */
        if (!t->round || e.side >= 0) t->e[t->ne++] = e;
    }
    if (t->round) { /* the arc replaces the slope */
        t->has_slope = 0;
        memset(&t->slope, 0, sizeof t->slope);
    }
}

static void rect_tile(tile *t, int r)
{
    strcpy(t->name, rects[r].name);
    t->cls = "NT_CLASS_POLYGON";
    t->n = 4;
    t->v[0] = (pt){rects[r].x0, rects[r].y0};
    t->v[1] = (pt){rects[r].x0, rects[r].y1};
    t->v[2] = (pt){rects[r].x1, rects[r].y1};
    t->v[3] = (pt){rects[r].x1, rects[r].y0};
    finish(t);
}

static void family_tile(tile *t, const family *fa, int o)
{
    snprintf(t->name, sizeof t->name, "%s%s%s", fa->base, orients[o].name, fa->suffix);
    t->cls = fa->cls;
    t->sx = orients[o].sx;
    t->sy = orients[o].sy;
    t->n = fa->n;
    int mx = t->sx < 0, my = t->sy > 0;
    for (int i = 0; i < fa->n; i++) {
        pt p = fa->v[(mx != my) ? fa->n - 1 - i : i]; /* one mirror: reversed, to keep the winding */
        t->v[i] = (pt){mx ? 1 - p.x : p.x, my ? 1 - p.y : p.y};
    }
    t->round = fa->round;
    if (fa->round) t->arc = (pt){mx ? 1 - fa->arc.x : fa->arc.x, my ? 1 - fa->arc.y : fa->arc.y};
    finish(t);
}

/* The tiles in id order: EMPTY, FULL, the sloped and round families (4 orientations
 * each), the half tiles. */
static int build(tile tiles[34])
{
    int k = 0;
    memset(tiles, 0, 34 * sizeof *tiles);
    strcpy(tiles[k].name, "EMPTY");
    tiles[k].cls = "NT_CLASS_EMPTY";
    finish(&tiles[k++]);
    rect_tile(&tiles[k++], 0);
    for (size_t f = 0; f < sizeof families / sizeof families[0]; f++)
        for (int o = 0; o < 4; o++) family_tile(&tiles[k++], &families[f], o);
    for (size_t r = 1; r < sizeof rects / sizeof rects[0]; r++) rect_tile(&tiles[k++], (int)r);
    return k;
}

/* ---------------------------------------------------------------- output */

/* The shortest decimal that reads back as v; integers without a point. */
static const char *num(double v)
{
    static char bufs[16][40];
    static int next;
    char *b = bufs[next++ & 15];
    if (v == floor(v) && fabs(v) < 1e9) {
        snprintf(b, 40, "%d", (int)v);
        return b;
    }
    for (int prec = 15; prec <= 17; prec++) {
        snprintf(b, 40, "%.*g", prec, v);
        if (strtod(b, NULL) == v) break;
    }
    return b;
}

static void put_edge(FILE *out, const edge *e)
{
    fprintf(out, "{%s, %s, %s, %s, %s, %s, %s, %s, %s, %s, %s, %d}", num(e->ux), num(e->uy), num(e->ud),
            num(e->inv), num(e->nx), num(e->ny), num(e->a.x), num(e->a.y), num(e->tx), num(e->ty), num(e->len),
            e->side);
}

static void put_tiles(FILE *out, const tile *ts, int count)
{
    fprintf(out, "const nt_tile_info nt__tiles[NT_TILE_COUNT] = {\n");
    for (int i = 0; i < count; i++) {
        const tile *t = &ts[i];
        fprintf(out, "    {\"%s\", %s, %d, %d, {%s, %s}, %d,\n     {", t->name, t->cls, t->sx, t->sy, num(t->nx),
                num(t->ny), t->n);
        for (int j = 0; j < 4; j++) fprintf(out, "%s{%s, %s}", j ? ", " : "", num(t->v[j].x), num(t->v[j].y));
        fprintf(out, "},\n     {%s, %s}, {%s, %s}, {%s, %s},\n     {", num(t->arc.x), num(t->arc.y), num(t->bmin.x),
                num(t->bmin.y), num(t->bmax.x), num(t->bmax.y));
        for (int s = 0; s < 4; s++) fprintf(out, "%s%s", s ? ", " : "", num(t->lo[s]));
        fprintf(out, "}, {");
        for (int s = 0; s < 4; s++) fprintf(out, "%s%s", s ? ", " : "", num(t->hi[s]));
        fprintf(out, "}},\n");
    }
    fprintf(out, "};\n\n");
}

static void put_geom(FILE *out, const tile *ts, int count)
{
    fprintf(out, "const nt__tile_geom nt__geom[NT_TILE_COUNT] = {\n");
    for (int i = 0; i < count; i++) {
        const tile *t = &ts[i];
        const edge *s = &t->slope;
        fprintf(out, "    /* %s */ {%d, %d, {%s, %s, %s, %s, %s, %s},\n     {", t->name, t->ne, t->has_slope,
                num(s->ux), num(s->uy), num(s->ud), num(s->inv), num(s->nx), num(s->ny));
        if (t->ne == 0) {
            edge none;
            memset(&none, 0, sizeof none);
            none.side = -1;
            put_edge(out, &none);
        }
        for (int j = 0; j < t->ne; j++) {
            if (j) fprintf(out, ",\n      ");
            put_edge(out, &t->e[j]);
        }
        fprintf(out, "}},\n");
    }
    fprintf(out, "};\n\n");
}

/* The narrow phase's tie order: the slope, then outward normals -y, +y, -x, +x. */
static int face_rank(const edge *e)
{
    if (!is_axis(e)) return 0;
    return e->ux == 0 ? (e->uy < 0 ? 1 : 2) : (e->ux < 0 ? 3 : 4);
}

static void put_polys(FILE *out, const tile *ts, int count)
{
    fprintf(out, "/* Polygon tiles' faces for the narrow phase, in the order the circle routine\n"
                 " * breaks ties: the slope, then the faces whose outward normals are -y, +y, -x, +x.\n"
                 " * The separation rows come first, four faces side by side so the four separations\n"
                 " * vectorise. Triangles end with an unused face that is never the farthest\n"
                 " * (ud = NT_REAL_MAX: a separation of -NT_REAL_MAX); round tiles and EMPTY have\n"
                 " * only unused faces. */\n"
                 "#define NT__NO_FACE {0, 0, 0, 0, {0, 0}, {0, 0}}\n"
                 "#define NT__NO_POLY {{0, 0, 0, 0}, {0, 0, 0, 0}, \\\n"
                 "    {NT_REAL_MAX, NT_REAL_MAX, NT_REAL_MAX, NT_REAL_MAX}, {1, 1, 1, 1}, \\\n"
                 "    {NT__NO_FACE, NT__NO_FACE, NT__NO_FACE, NT__NO_FACE}}\n"
                 "const nt__poly nt__polys[NT_TILE_COUNT] = {\n");
    for (int i = 0; i < count; i++) {
        const tile *t = &ts[i];
        if (t->n == 0 || t->round) {
            fprintf(out, "    /* %s */ NT__NO_POLY,\n", t->name);
            continue;
        }
        const edge *f[4];
        int nf = 0;
        for (int r = 0; r <= 4; r++)
            for (int j = 0; j < t->ne; j++)
                if (face_rank(&t->e[j]) == r) f[nf++] = &t->e[j];
        fprintf(out, "    /* %s */ {", t->name);
        for (int row = 0; row < 4; row++) { /* ux, uy, ud, inv; an unused face: 0, 0, NT_REAL_MAX, 1 */
            fprintf(out, "%s{", row ? ",\n     " : "");
            for (int j = 0; j < 4; j++) {
                const char *v = row == 2 ? "NT_REAL_MAX" : row == 3 ? "1" : "0";
                if (j < nf) {
                    const double rv[4] = {f[j]->ux, f[j]->uy, f[j]->ud, f[j]->inv};
                    v = num(rv[row]);
                }
                fprintf(out, "%s%s", j ? ", " : "", v);
            }
            fprintf(out, "}");
        }
        fprintf(out, ",\n     {");
        for (int j = 0; j < 4; j++) {
            if (j) fprintf(out, ",\n      ");
            if (j >= nf) {
                fprintf(out, "NT__NO_FACE");
                continue;
            }
            const edge *e = f[j];
            fprintf(out, "{%s, %s, %s, %s, {%s, %s}, {%s, %s}}", num(e->nx), num(e->ny), num(e->tx), num(e->ty),
                    num(e->a.x), num(e->b.x), num(e->a.y), num(e->b.y));
        }
        fprintf(out, "}},\n");
    }
    fprintf(out, "};\n#undef NT__NO_POLY\n#undef NT__NO_FACE\n");
}

int tilegen_write(FILE *out)
{
    tile tiles[34];
    int count = build(tiles);
    if (count != 34) return -1;
    fprintf(out, "/* The N v1.4 tile set as data. GENERATED by tools/tilegen (make tiles) from the\n"
                 " * canonical `pn` shapes: edit the generator, not this file (tests/test_tilegen.c\n"
                 " * checks that the two agree byte for byte).\n"
                 " * nt__tiles: the public table (names, classes, normals, vertices, arcs, bounds,\n"
                 " * side coverage); nt__geom: the straight edges the narrow phase and the map walk;\n"
                 " * nt__polys: polygon tiles' faces for the narrow phase. Numbers are double\n"
                 " * constants, converted to nt_real (float or double) at compile time. */\n"
                 "#include \"core_internal.h\"\n\n");
    put_tiles(out, tiles, count);
    put_geom(out, tiles, count);
    put_polys(out, tiles, count);
    return ferror(out) ? -1 : 0;
}
