/* ntile sheet — the gizmo answer key: what the engine does with sample objects on
 * every tile, drawn as SVG from the engine's own answers.
 *
 * The sheet is a grid of panels. One per solid tile (ids 1..33), a group
 * <g id="tile-NAME"> holding:
 *   - the cell, in a group scaled so that every number inside it is in unit-cell
 *     coordinates (y down, as nt_collide_tile_* take them): the tile's solid and the
 *     edge states the map gives the tile alone in an empty neighbourhood (one line
 *     per side, class e0 OFF, e1 SOLID, e2 INTERESTING, as the nt_edge values);
 *   - sample boxes and circles overlapping the tile, each a <g class="sample">: the
 *     object (class "obj"), its projection vector (class "pv", the path
 *     "M cx cy l dx dy" where (dx, dy) is exactly nt_tile_collide_aabb/circle's
 *     normal * depth), its resolved position (class "res", dashed: nt_map_resolve of
 *     the object against the tile alone in a 5 x 5 map) and, at the resolved
 *     position, each contact normal the resolution reports (class "cn", drawn from
 *     the contact point);
 *   - the tile in a ring of FULL tiles, with the edge states the map gives it there
 *     (a side the tile covers whole becomes an OFF seam, the others SOLID).
 * Then a legend, and one panel per friction model: a box hits a 45-degree slope in a
 * world without gravity; its velocity before one step and after it (read from the
 * world) is split into normal and tangential parts along the contact normal the
 * world reports.
 *
 * Numbers a reader may want back (object geometry, vectors, velocities) are printed
 * with %.9g, which round-trips a float; the samples sit on a 1/64 grid so that their
 * printed positions are exact. Everything else is layout.
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "cli.h"
#include "ntile/ntile.h"

/* ---------- layout (pixels) ---------- */

#define COLS 6
#define SLOT_W 290
#define SLOT_H 240
#define MARGIN 10
#define HEADER 44
#define SCALE 90.0       /* pixels per unit in a tile panel */
#define VIEW_LO (-0.6)   /* the tile panel shows [VIEW_LO, VIEW_HI]^2 around the cell */
#define VIEW_HI 1.6
#define RING_SCALE 20.0  /* pixels per cell in the ring panel */

/* The 33 tiles fill five rows and half of a sixth, the legend the other half; the two
 * friction panels share a seventh row. */
#define TILE_PANELS (NT_TILE_COUNT - 1)
#define HALF_ROW (COLS / 2)
#define ROWS 7
#define PANEL_W (HALF_ROW * SLOT_W) /* legend and friction panels */

/* Sample objects, in cells: depth is how far each is placed into the surface it samples. */
#define BOX_HW 0.1875
#define BOX_HH 0.125
#define CIRCLE_R 0.15625
#define VERTEX_R 0.125
#define SAMPLE_DEPTH 0.14
#define VERTEX_DEPTH 0.07
#define MAX_SAMPLES 8

/* The friction scene, in N's units (cell 24). */
#define FR_CELL 24.0
#define FR_HALF 6.0
#define FR_FRICTION 0.3
#define FR_BOUNCE 0.5
#define FR_DT (1.0 / 40)
#define FR_VX 20.0
#define FR_VY 140.0

typedef struct sheet {
    FILE *f;
    const char *error; /* first engine failure, for the message */
} sheet;

/* -0 prints as 0: the file should not depend on the sign of a zero. */
static double z(double v) { return v == 0 ? 0 : v; }

/* ---------- samples ---------- */

typedef struct sample {
    int circle;
    nt_vec2 c;    /* centre, unit cell coordinates */
    nt_vec2 half; /* half-size; both the radius for a circle */
} sample;

static nt_real q64(double v) { return (nt_real)(floor(v * 64 + 0.5) / 64); }

static nt_vec2 unit(double x, double y)
{
    double l = sqrt(x * x + y * y);
    return l > 0 ? nt_v2((nt_real)(x / l), (nt_real)(y / l)) : nt_v2(0, 0);
}

/* Outward normal of the straight edge a -> b (tiles list corners counter-clockwise on screen). */
static nt_vec2 edge_normal(nt_vec2 a, nt_vec2 b) { return unit(-(double)(b.y - a.y), (double)(b.x - a.x)); }

/* Place an object so that it reaches `depth` past the surface point p of outward normal n. */
static sample place(int circle, nt_vec2 p, nt_vec2 n, double depth, double r)
{
    sample s;
    s.circle = circle;
    s.half = circle ? nt_v2((nt_real)r, (nt_real)r) : nt_v2((nt_real)BOX_HW, (nt_real)BOX_HH);
    double support = circle ? r : BOX_HW * fabs(n.x) + BOX_HH * fabs(n.y);
    s.c = nt_v2(q64(p.x + n.x * (support - depth)), q64(p.y + n.y * (support - depth)));
    return s;
}

static int overlaps(int tile, const sample *s, nt_mtv *m)
{
    return s->circle ? nt_tile_collide_circle(tile, s->c, s->half.x, m) : nt_tile_collide_aabb(tile, s->c, s->half, m);
}

/* One object per straight side (boxes and circles alternating), two on an arc, and a
 * small circle off the sharpest corner. Only objects that overlap the tile are kept. */
static int tile_samples(int tile, sample *out)
{
    const nt_tile_info *info = nt_tile_get_info(tile);
    int n = info->vertex_count, round = info->cls != NT_CLASS_POLYGON, count = 0;
    int edges = round ? n - 1 : n;
    sample cand[MAX_SAMPLES];
    int nc = 0;
    for (int k = 0; k < edges; k++) {
        nt_vec2 a = info->vertices[k], b = info->vertices[(k + 1) % n], nrm = edge_normal(a, b);
        int circle = k % 2;
        double t = circle ? 0.3 : 0.5;
        nt_vec2 p = nt_v2(a.x + (b.x - a.x) * (nt_real)t, a.y + (b.y - a.y) * (nt_real)t);
        cand[nc++] = place(circle, p, nrm, SAMPLE_DEPTH, CIRCLE_R);
    }
    if (round) {
        /* Arc from the last corner back to the first, radius 1 around arc_center. */
        nt_vec2 c = info->arc_center, u0 = info->vertices[n - 1], u1 = info->vertices[0];
        double a0 = atan2(u0.y - c.y, u0.x - c.x), a1 = atan2(u1.y - c.y, u1.x - c.x);
        double da = remainder(a1 - a0, 2 * 3.14159265358979323846);
        for (int k = 0; k < 2; k++) {
            double ang = a0 + da * (k ? 0.2 : 0.5);
            nt_vec2 p = nt_v2(c.x + (nt_real)cos(ang), c.y + (nt_real)sin(ang));
            nt_vec2 nrm = unit(cos(ang), sin(ang));
            if (info->cls == NT_CLASS_CONCAVE) nrm = nt_v2(-nrm.x, -nrm.y); /* the solid is outside the disc */
            cand[nc++] = place(k, p, nrm, SAMPLE_DEPTH, CIRCLE_R);
        }
    }
    /* The corner with the smallest angle; on a round tile the one between its straight sides. */
    int best = 1;
    double best_cos = -2;
    if (!round)
        for (int k = 0; k < n; k++) {
            nt_vec2 v = info->vertices[k], p = info->vertices[(k + n - 1) % n], q = info->vertices[(k + 1) % n];
            nt_vec2 e1 = unit(p.x - v.x, p.y - v.y), e2 = unit(q.x - v.x, q.y - v.y);
            double cs = (double)e1.x * e2.x + (double)e1.y * e2.y;
            if (cs > best_cos + 1e-9) best_cos = cs, best = k;
        }
    {
        nt_vec2 v = info->vertices[best], p = info->vertices[(best + n - 1) % n], q = info->vertices[(best + 1) % n];
        nt_vec2 n1 = edge_normal(p, v), n2 = edge_normal(v, q);
        nt_vec2 bis = unit((double)n1.x + n2.x, (double)n1.y + n2.y);
        cand[nc++] = place(1, v, bis, VERTEX_DEPTH, VERTEX_R);
    }
    for (int k = 0; k < nc; k++) {
        nt_mtv m;
        if (overlaps(tile, &cand[k], &m)) out[count++] = cand[k];
    }
    return count;
}

/* The point where the object at centre r touches a surface of normal n (unit cell). */
static nt_vec2 contact_point(const sample *s, nt_vec2 r, nt_vec2 n, const nt_tile_info *info)
{
    if (s->circle) return nt_v2(r.x - s->half.x * n.x, r.y - s->half.x * n.y);
    /* A box touches with a corner, or along a side: then the middle of what it shares with the tile. */
    nt_real lo[2] = {r.x - s->half.x, r.y - s->half.y}, hi[2] = {r.x + s->half.x, r.y + s->half.y};
    nt_real nn[2] = {n.x, n.y}, bl[2] = {info->bounds_min.x, info->bounds_min.y},
            bh[2] = {info->bounds_max.x, info->bounds_max.y}, out[2];
    for (int a = 0; a < 2; a++) {
        if (nn[a] > (nt_real)1e-6) out[a] = lo[a];
        else if (nn[a] < (nt_real)-1e-6) out[a] = hi[a];
        else {
            nt_real l = lo[a] > bl[a] ? lo[a] : bl[a], h = hi[a] < bh[a] ? hi[a] : bh[a];
            out[a] = l <= h ? (l + h) / 2 : (lo[a] + hi[a]) / 2;
        }
    }
    return nt_v2(out[0], out[1]);
}

/* ---------- drawing helpers ---------- */

/* The tile's solid as a path, offset by (ox, oy) cells. */
static void tile_path(FILE *f, int tile, double ox, double oy)
{
    const nt_tile_info *info = nt_tile_get_info(tile);
    int n = info->vertex_count;
    fputs("d=\"", f);
    for (int k = 0; k < n; k++)
        fprintf(f, "%s%g %g", k ? "L" : "M", z(ox + info->vertices[k].x), z(oy + info->vertices[k].y));
    if (info->cls != NT_CLASS_POLYGON) {
        nt_vec2 c = info->arc_center, u0 = info->vertices[n - 1], u1 = info->vertices[0];
        double cross = (double)(u0.x - c.x) * (u1.y - c.y) - (double)(u0.y - c.y) * (u1.x - c.x);
        /* A quarter circle: the short way, clockwise on screen when the turn is positive. */
        fprintf(f, "A1 1 0 0 %d %g %g", cross > 0 ? 1 : 0, z(ox + u1.x), z(oy + u1.y));
    }
    fputs("Z\"", f);
}

static const char *const side_names[4] = {"left", "right", "top", "bottom"};

/* One line per side of the cell at (ox, oy), classed by its edge state. */
static void edge_lines(FILE *f, const nt_map *map, int cx, int cy, double ox, double oy)
{
    static const double seg[4][4] = {{0, 0, 0, 1}, {1, 0, 1, 1}, {0, 0, 1, 0}, {0, 1, 1, 1}};
    for (int s = 0; s < 4; s++)
        fprintf(f, "<line class=\"e%d\" data-side=\"%s\" x1=\"%g\" y1=\"%g\" x2=\"%g\" y2=\"%g\"/>\n",
                (int)nt_map_get_edge(map, cx, cy, (nt_side)s), side_names[s], ox + seg[s][0], oy + seg[s][1],
                ox + seg[s][2], oy + seg[s][3]);
}

static void shape_elem(FILE *f, const char *cls, const sample *s, nt_vec2 c)
{
    if (s->circle)
        fprintf(f, "<circle class=\"%s\" cx=\"%.9g\" cy=\"%.9g\" r=\"%.9g\"/>\n", cls, z(c.x), z(c.y), z(s->half.x));
    else
        fprintf(f, "<rect class=\"%s\" x=\"%.9g\" y=\"%.9g\" width=\"%.9g\" height=\"%.9g\"/>\n", cls,
                z(c.x - s->half.x), z(c.y - s->half.y), z(2 * s->half.x), z(2 * s->half.y));
}

/* ---------- tile panels ---------- */

static int tile_panel(sheet *sh, int tile, double x0, double y0)
{
    FILE *f = sh->f;
    const nt_tile_info *info = nt_tile_get_info(tile);
    nt_map *alone = NULL, *ring = NULL;
    nt_map_def d = nt_default_map_def();
    d.width = d.height = 5;
    d.cell_size = 1;
    nt_map_def dr = d;
    dr.width = dr.height = 3;
    if (nt_map_create(&d, &alone) != NT_OK || nt_map_create(&dr, &ring) != NT_OK ||
        nt_map_set_tile(alone, 2, 2, tile) != NT_OK) {
        nt_map_destroy(alone);
        nt_map_destroy(ring);
        sh->error = "cannot create a map";
        return 0;
    }
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 3; x++) nt_map_set_tile(ring, x, y, x == 1 && y == 1 ? tile : NT_TILE_FULL);

    fprintf(f, "<g id=\"tile-%s\" class=\"tile\" data-tile=\"%d\" transform=\"translate(%g %g)\">\n", info->name, tile,
            x0, y0);
    /* The level-string character as a character reference: it may be '<' or '>'. */
    fprintf(f, "<text class=\"h\" x=\"4\" y=\"14\">%d &#8216;&#%d;&#8217; %s</text>\n", tile, '0' + tile, info->name);
    fprintf(f, "<g class=\"cell\" transform=\"translate(%g %g) scale(%g)\">\n", 4 - VIEW_LO * SCALE, 20 - VIEW_LO * SCALE,
            SCALE);
    fputs("<rect class=\"bg\" x=\"0\" y=\"0\" width=\"1\" height=\"1\"/>\n<path class=\"solid\" ", f);
    tile_path(f, tile, 0, 0);
    fputs("/>\n", f);
    edge_lines(f, alone, 2, 2, 0, 0);

    sample smp[MAX_SAMPLES];
    int ns = tile_samples(tile, smp);
    for (int k = 0; k < ns; k++) {
        const sample *s = &smp[k];
        nt_mtv m;
        overlaps(tile, s, &m);
        nt_shape shape = s->circle ? nt_shape_circle(s->half.x) : nt_shape_aabb(s->half.x, s->half.y);
        nt_resolution res;
        if (!nt_map_resolve(alone, nt_v2(s->c.x + 2, s->c.y + 2), shape, &res)) memset(&res, 0, sizeof res);
        nt_vec2 r = nt_v2(s->c.x + res.push.x, s->c.y + res.push.y);
        fprintf(f, "<g class=\"sample\" data-shape=\"%s\">\n", s->circle ? "circle" : "aabb");
        shape_elem(f, "obj", s, s->c);
        shape_elem(f, "res", s, r);
        fprintf(f, "<path class=\"pv\" d=\"M%.9g %.9gl%.9g %.9g\"/>\n", z(s->c.x), z(s->c.y), z(m.normal.x * m.depth),
                z(m.normal.y * m.depth));
        for (int c = 0; c < res.contact_count; c++) {
            nt_vec2 n = res.contacts[c].normal, p = contact_point(s, r, n, info);
            fprintf(f, "<circle class=\"cp\" cx=\"%.5g\" cy=\"%.5g\" r=\".018\"/>\n", z(p.x), z(p.y));
            fprintf(f, "<path class=\"cn\" d=\"M%.9g %.9gl%.9g %.9g\"/>\n", z(p.x), z(p.y), z(n.x * 0.2),
                    z(n.y * 0.2));
        }
        fputs("</g>\n", f);
    }
    fputs("</g>\n", f);

    /* The ring panel: 3 x 3 cells, the tile in the middle. */
    double rx = 4 + (VIEW_HI - VIEW_LO) * SCALE + 12, ry = 36;
    fprintf(f, "<text class=\"s\" x=\"%g\" y=\"%g\">in FULL</text>\n", rx, ry - 6);
    fprintf(f, "<g class=\"ring\" transform=\"translate(%g %g) scale(%g)\">\n", rx, ry, RING_SCALE);
    for (int y = 0; y < 3; y++)
        for (int x = 0; x < 3; x++)
            if (x != 1 || y != 1)
                fprintf(f, "<rect class=\"solid\" x=\"%d\" y=\"%d\" width=\"1\" height=\"1\"/>\n", x, y);
    fputs("<rect class=\"bg\" x=\"1\" y=\"1\" width=\"1\" height=\"1\"/>\n<path class=\"solid\" ", f);
    tile_path(f, tile, 1, 1);
    fputs("/>\n", f);
    edge_lines(f, ring, 1, 1, 1, 1);
    fputs("</g>\n</g>\n", f);
    nt_map_destroy(alone);
    nt_map_destroy(ring);
    return 1;
}

/* ---------- legend ---------- */

static void legend_panel(FILE *f, double x0, double y0)
{
    fprintf(f, "<g id=\"legend\" transform=\"translate(%g %g)\">\n", x0, y0);
    fputs("<text class=\"h\" x=\"4\" y=\"14\">Legend (unit cell, y down)</text>\n"
          "<g transform=\"translate(14 34) scale(80)\">\n"
          "<rect class=\"bg\" x=\"0\" y=\"0\" width=\"1\" height=\"1\"/>\n"
          "<path class=\"solid\" d=\"M0 .5L0 1L1 1L1 .5Z\"/>\n"
          "<rect class=\"obj\" x=\".3\" y=\".2\" width=\".4\" height=\".4\"/>\n"
          "<rect class=\"res\" x=\".3\" y=\".1\" width=\".4\" height=\".4\"/>\n"
          "<path class=\"pv\" d=\"M.5 .4l0 -.1\"/>\n"
          "<circle class=\"cp\" cx=\".5\" cy=\".5\" r=\".018\"/>\n"
          "<path class=\"cn\" d=\"M.5 .5l0 -.2\"/>\n"
          "</g>\n",
          f);
    static const char *const rows[][2] = {
        {"obj", "sample object (box or circle) overlapping the tile"},
        {"pv", "projection vector: nt_tile_collide_aabb / _circle, the tile alone"},
        {"res", "resolved position: nt_map_resolve, the tile alone in a 5\xc3\x97" "5 map"},
        {"cn", "contact normal of the resolution, at the contact point"},
        {"e1", "SOLID edge"},
        {"e2", "INTERESTING edge"},
        {"e0", "OFF edge"},
    };
    for (int k = 0; k < 7; k++) {
        double x = 120, y = 36 + 15 * k;
        const char *c = rows[k][0];
        if (c[0] == 'e')
            fprintf(f, "<line class=\"%s\" x1=\"%g\" y1=\"%g\" x2=\"%g\" y2=\"%g\" style=\"stroke-width:%s\"/>\n", c,
                    x, y - 4, x + 30, y - 4, c[1] == '0' ? "1.5;stroke-dasharray:4 3" : "4");
        else if (c[0] == 'o' || c[0] == 'r')
            fprintf(f, "<rect class=\"%s\" x=\"%g\" y=\"%g\" width=\"22\" height=\"10\" style=\"stroke-width:1%s\"/>\n",
                    c, x + 4, y - 10, c[0] == 'r' ? ";stroke-dasharray:3 2" : "");
        else
            fprintf(f, "<path class=\"%s\" d=\"M%g %gl28 0\" style=\"stroke-width:1.5\"/>\n", c, x, y - 4);
        fprintf(f, "<text class=\"s\" x=\"%g\" y=\"%g\">%s</text>\n", x + 38, y, rows[k][1]);
    }
    static const char *const notes[] = {
        "Samples: a box or a circle pushed into each straight side (alternating), two into the arc of a",
        "round tile, a small circle off the sharpest corner; all on a 1/64 grid, sizes at most 0.19 cell.",
        "Edges of the big cell: nt_map_get_edge for the tile alone among EMPTY cells (a side the solid covers",
        "whole is SOLID, one it touches in part or at a point INTERESTING). The small panel puts the tile in",
        "a ring of FULL tiles: a side both cover is an OFF seam, which never pushes; the others turn SOLID.",
        "Friction panels (below): the world\xe2\x80\x99s velocity before and after one step, split along the contact",
        "normal into the normal part (red) and the tangential part (green).",
    };
    for (int k = 0; k < 7; k++) fprintf(f, "<text class=\"s\" x=\"14\" y=\"%d\">%s</text>\n", 146 + 13 * k, notes[k]);
    fputs("</g>\n", f);
}

/* ---------- friction panels ---------- */

typedef struct friction_run {
    nt_vec2 p0, p1, v0, v1, n;
} friction_run;

/* A box hits the middle 45-degree slope tile of a small world without gravity:
 * one step, velocity before and after. */
static int run_friction(nt_friction_model model, friction_run *out)
{
    nt_world_def wd = nt_default_world_def();
    wd.map.width = 5;
    wd.map.height = 5;
    wd.map.cell_size = (nt_real)FR_CELL;
    wd.gravity = nt_v2(0, 0);
    wd.friction_model = model;
    wd.tile_material.friction = (nt_real)FR_FRICTION;
    wd.tile_material.bounce = (nt_real)FR_BOUNCE;
    wd.restitution_threshold = 1;
    wd.enable_sleep = false;
    nt_world *w;
    if (nt_world_create(&wd, &w) != NT_OK) return 0;
    /* A slope down to the right along the diagonal, solid beneath it. */
    for (int y = 0; y < 5; y++)
        for (int x = 0; x < 5; x++)
            nt_world_set_tile(w, x, y, x == y ? NT_TILE_45DEGpn : x < y ? NT_TILE_FULL : NT_TILE_EMPTY);
    double s = sqrt(0.5), cx = 2.5 * FR_CELL, cy = 2.5 * FR_CELL; /* the middle of the slope */
    double gap = FR_HALF * 2 * s + 1.0;                              /* 1 unit clear of the surface */
    nt_body_def bd = nt_default_body_def();
    bd.shape = nt_shape_aabb((nt_real)FR_HALF, (nt_real)FR_HALF);
    bd.position = nt_v2((nt_real)(cx + s * gap), (nt_real)(cy - s * gap));
    bd.velocity = nt_v2((nt_real)FR_VX, (nt_real)FR_VY);
    bd.material.friction = (nt_real)FR_FRICTION;
    bd.material.bounce = (nt_real)FR_BOUNCE;
    nt_body_id id;
    int ok = 0;
    if (nt_body_create(w, &bd, &id) == NT_OK) {
        out->p0 = nt_body_get_position(w, id);
        out->v0 = nt_body_get_velocity(w, id);
        nt_body_tile_contacts tc;
        if (nt_world_step(w, (nt_real)FR_DT) == NT_OK && nt_body_get_tile_contacts(w, id, &tc) == NT_OK &&
            tc.count > 0) {
            out->p1 = nt_body_get_position(w, id);
            out->v1 = nt_body_get_velocity(w, id);
            out->n = tc.contacts[0].normal;
            ok = 1;
        }
    }
    nt_world_destroy(w);
    return ok;
}

/* An arrow from the diagram's origin by v * k (pixels). */
static void varrow(FILE *f, const char *cls, nt_vec2 v, double k)
{
    fprintf(f, "<path class=\"%s\" d=\"M0 0l%.9g %.9g\"/>\n", cls, z(v.x * k), z(v.y * k));
}

/* v split along the unit normal n: v.n, v.t with t = (-n.y, n.x), and the two parts. */
static void split(nt_vec2 v, nt_vec2 n, nt_vec2 *vn, nt_vec2 *vt, double *a, double *b)
{
    double an = (double)v.x * n.x + (double)v.y * n.y, bt = (double)v.x * -n.y + (double)v.y * n.x;
    *vn = nt_v2((nt_real)(an * n.x), (nt_real)(an * n.y));
    *vt = nt_v2((nt_real)(bt * -n.y), (nt_real)(bt * n.x));
    *a = an;
    *b = bt;
}

/* A vector diagram: the surface line through the origin, the normal (dashed), v and its parts. */
static void vdiagram(FILE *f, const char *when, const char *title, nt_vec2 v, nt_vec2 n, double x, double y)
{
    const double k = 0.45; /* pixels per unit/s */
    nt_vec2 vn, vt;
    double a, b;
    split(v, n, &vn, &vt, &a, &b);
    fprintf(f, "<text class=\"s\" x=\"%g\" y=\"%g\" text-anchor=\"middle\">%s</text>\n", x, y - 72, title);
    fprintf(f, "<g class=\"vdiag\" data-when=\"%s\" data-k=\"%g\" transform=\"translate(%g %g)\">\n", when, k, x, y);
    fprintf(f, "<path class=\"ax\" d=\"M%.4g %.4gL%.4g %.4g\"/>\n", z(70 * n.y), z(-70 * n.x), z(-70 * n.y), z(70 * n.x));
    fprintf(f, "<path class=\"ax\" d=\"M0 0L%.4g %.4g\" style=\"stroke-dasharray:3 3\"/>\n", z(45 * n.x), z(45 * n.y));
    char c[8];
    snprintf(c, sizeof c, "v%s", when);
    varrow(f, c, v, k);
    snprintf(c, sizeof c, "vn%s", when);
    varrow(f, c, vn, k);
    snprintf(c, sizeof c, "vt%s", when);
    varrow(f, c, vt, k);
    fputs("</g>\n", f);
    fprintf(f, "<text class=\"s\" x=\"%g\" y=\"%g\" text-anchor=\"middle\">v = (%.2f, %.2f)</text>\n", x, y + 84, z(v.x),
            z(v.y));
    fprintf(f, "<text class=\"s\" x=\"%g\" y=\"%g\" text-anchor=\"middle\"><tspan class=\"tn\">v&#183;n = %.2f</tspan> "
               "<tspan class=\"tt\">v&#183;t = %.2f</tspan></text>\n",
            x, y + 98, z(a), z(b));
}

static int friction_panel(sheet *sh, nt_friction_model model, double x0, double y0)
{
    FILE *f = sh->f;
    friction_run r;
    if (!run_friction(model, &r)) {
        sh->error = "the friction scene did not make contact";
        return 0;
    }
    int nm = model == NT_FRICTION_N;
    fprintf(f, "<g id=\"friction-%s\" class=\"friction\" data-friction=\"%g\" data-bounce=\"%g\" "
               "data-v0=\"%.9g %.9g\" data-v1=\"%.9g %.9g\" data-normal=\"%.9g %.9g\" transform=\"translate(%g %g)\">\n",
            nm ? "N" : "Coulomb", FR_FRICTION, FR_BOUNCE, z(r.v0.x), z(r.v0.y), z(r.v1.x), z(r.v1.y), z(r.n.x), z(r.n.y),
            x0, y0);
    if (nm)
        fprintf(f, "<text class=\"h\" x=\"4\" y=\"14\">Friction model NT_FRICTION_N (N&#8217;s): friction %g, "
                   "bounce %g</text>\n",
                FR_FRICTION, FR_BOUNCE);
    else
        fprintf(f, "<text class=\"h\" x=\"4\" y=\"14\">Friction model NT_FRICTION_COULOMB: &#956; = %g, bounce %g</text>\n",
                FR_FRICTION, FR_BOUNCE);
    /* The scene: cells 1..3 of the slope, 2.2 px per unit. */
    const double ps = 2.2, ox = 4 - FR_CELL * ps, oy = 26 - FR_CELL * ps;
    fprintf(f, "<g class=\"scene\" transform=\"translate(%g %g) scale(%g)\">\n", ox, oy, ps);
    fprintf(f, "<rect class=\"bg\" x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" style=\"stroke-width:.4\"/>\n", FR_CELL,
            FR_CELL, 3 * FR_CELL, 3 * FR_CELL);
    fprintf(f, "<path class=\"solid\" d=\"M%g %gL%g %gL%g %gZ\" style=\"stroke-width:.4\"/>\n", FR_CELL, FR_CELL,
            4 * FR_CELL, 4 * FR_CELL, FR_CELL, 4 * FR_CELL);
    fprintf(f, "<rect class=\"obj\" x=\"%.9g\" y=\"%.9g\" width=\"%g\" height=\"%g\" style=\"stroke-width:.4\"/>\n",
            z(r.p0.x - FR_HALF), z(r.p0.y - FR_HALF), 2 * FR_HALF, 2 * FR_HALF);
    fprintf(f, "<rect class=\"res\" x=\"%.9g\" y=\"%.9g\" width=\"%g\" height=\"%g\" style=\"stroke-width:.4;"
               "stroke-dasharray:1.2 .9\"/>\n",
            z(r.p1.x - FR_HALF), z(r.p1.y - FR_HALF), 2 * FR_HALF, 2 * FR_HALF);
    fprintf(f, "<path class=\"v\" d=\"M%.9g %.9gl%.9g %.9g\" style=\"stroke-width:.6\"/>\n", z(r.p0.x), z(r.p0.y),
            z(r.v0.x * 0.1), z(r.v0.y * 0.1));
    fprintf(f, "<path class=\"v\" d=\"M%.9g %.9gl%.9g %.9g\" style=\"stroke-width:.6\"/>\n", z(r.p1.x), z(r.p1.y),
            z(r.v1.x * 0.1), z(r.v1.y * 0.1));
    fputs("</g>\n", f);
    double cy = 26 + 3 * FR_CELL * ps;
    fprintf(f, "<text class=\"s\" x=\"4\" y=\"%g\">box 12&#215;12 (cell 24), gravity 0,</text>\n"
               "<text class=\"s\" x=\"4\" y=\"%g\">one step of 1/40 s; solid: before,</text>\n"
               "<text class=\"s\" x=\"4\" y=\"%g\">dashed: after; arrows v &#215; 0.1 s</text>\n",
            cy + 14, cy + 27, cy + 40);
    vdiagram(f, "0", "before the step", r.v0, r.n, 320, 110);
    vdiagram(f, "1", "after the step (engine)", r.v1, r.n, 480, 110);
    /* What the documented formula gives, next to what the engine did. */
    nt_vec2 vn, vt;
    double a0, b0, a1, b1;
    split(r.v0, r.n, &vn, &vt, &a0, &b0);
    split(r.v1, r.n, &vn, &vt, &a1, &b1);
    double ea = -FR_BOUNCE * a0, eb;
    const double tx = 578;
    fprintf(f, "<text class=\"s\" x=\"%g\" y=\"40\">n = (%.4f, %.4f): the world&#8217;s contact normal</text>\n", tx,
            z(r.n.x), z(r.n.y));
    fprintf(f, "<text class=\"s\" x=\"%g\" y=\"54\">t = (&#8722;n.y, n.x)</text>\n", tx);
    if (nm) {
        eb = (1 - FR_FRICTION) * b0;
        fprintf(f, "<text class=\"s\" x=\"%g\" y=\"80\">Moving into the surface:</text>\n"
                   "<text class=\"s\" x=\"%g\" y=\"94\">v&#8217; = &#8722;bounce&#183;vn + (1 &#8722; friction)&#183;vt</text>\n",
                tx, tx);
        fprintf(f, "<text class=\"s\" x=\"%g\" y=\"120\">formula: <tspan class=\"tn\">v&#8217;&#183;n = &#8722;%g &#215; "
                   "(%.2f) = %.2f</tspan></text>\n",
                tx, FR_BOUNCE, z(a0), z(ea));
        fprintf(f, "<text class=\"s\" x=\"%g\" y=\"134\"><tspan class=\"tt\">v&#8217;&#183;t = %g &#215; %.2f = %.2f</tspan>"
                   "</text>\n",
                tx + 48, 1 - FR_FRICTION, z(b0), z(eb));
    } else {
        double limit = FR_FRICTION * (ea - a0);
        eb = fabs(b0) <= limit ? 0 : (b0 > 0 ? b0 - limit : b0 + limit);
        fprintf(f, "<text class=\"s\" x=\"%g\" y=\"80\">vn&#8217; = &#8722;bounce&#183;vn; the tangential change is at</text>\n"
                   "<text class=\"s\" x=\"%g\" y=\"94\">most &#956; &#215; the normal change (sticks below that)</text>\n",
                tx, tx);
        fprintf(f, "<text class=\"s\" x=\"%g\" y=\"120\">formula: <tspan class=\"tn\">v&#8217;&#183;n = &#8722;%g &#215; "
                   "(%.2f) = %.2f</tspan></text>\n",
                tx, FR_BOUNCE, z(a0), z(ea));
        fprintf(f, "<text class=\"s\" x=\"%g\" y=\"134\"><tspan class=\"tt\">v&#8217;&#183;t = %.2f &#8722; %g &#215; %.2f "
                   "= %.2f</tspan></text>\n",
                tx + 48, z(b0), FR_FRICTION, z(ea - a0), z(eb));
    }
    fprintf(f, "<text class=\"s\" x=\"%g\" y=\"154\">engine: <tspan class=\"tn\">v&#8217;&#183;n = %.2f</tspan> "
               "<tspan class=\"tt\">v&#8217;&#183;t = %.2f</tspan></text>\n",
            tx, z(a1), z(b1));
    fputs("</g>\n", f);
    return 1;
}

/* ---------- the sheet ---------- */

static int write_sheet(sheet *sh)
{
    FILE *f = sh->f;
    int w = MARGIN * 2 + COLS * SLOT_W, h = HEADER + MARGIN + ROWS * SLOT_H;
    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
               "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
               "font-family=\"sans-serif\" font-size=\"12\">\n",
            w, h, w, h);
    fprintf(f, "<title>ntile %d.%d.%d answer key (%s)</title>\n", NT_VERSION_MAJOR, NT_VERSION_MINOR, NT_VERSION_PATCH,
            NT_REAL_IS_DOUBLE ? "double" : "float");
    /* Stroke widths are in the units of the group they are drawn in: a tile panel is scaled by SCALE. */
    fputs("<style>\n"
          ".h{font-weight:bold}.s{font-size:11px}\n"
          ".bg{fill:#f6f6f6;stroke:#c8c8c8;stroke-width:.01}\n"
          ".solid{fill:#9fa8b3;stroke:#5d6670;stroke-width:.012}\n"
          ".e0{stroke:#8a8a8a;stroke-width:.012;stroke-dasharray:.04 .04}\n"
          ".e1{stroke:#d62728;stroke-width:.045}\n"
          ".e2{stroke:#f0b000;stroke-width:.045}\n"
          ".ring .e0{stroke-width:.05;stroke-dasharray:.15 .15}.ring .e1,.ring .e2{stroke-width:.16}\n"
          ".ring .solid{stroke-width:.04}.ring .bg{stroke-width:.04}\n"
          ".obj{fill:#1f77b4;fill-opacity:.15;stroke:#1f77b4;stroke-width:.012}\n"
          ".res{fill:none;stroke:#1f77b4;stroke-width:.012;stroke-dasharray:.03 .02}\n"
          ".pv{fill:none;stroke:#e67e22;stroke-width:.02;marker-end:url(#ah-pv)}\n"
          ".cn{fill:none;stroke:#c0392b;stroke-width:.012;marker-end:url(#ah-cn)}\n"
          ".cp{fill:#c0392b}\n"
          ".ax{fill:none;stroke:#aaa;stroke-width:1}\n"
          ".v,.v0,.v1{fill:none;stroke:#222;stroke-width:1.5;marker-end:url(#ah-v)}\n"
          ".vn0,.vn1{fill:none;stroke:#d62728;stroke-width:1.5;marker-end:url(#ah-n)}\n"
          ".vt0,.vt1{fill:none;stroke:#2ca02c;stroke-width:1.5;marker-end:url(#ah-t)}\n"
          ".tn{fill:#d62728}.tt{fill:#2ca02c}\n"
          "</style>\n<defs>\n",
          f);
    static const char *const marks[][2] = {
        {"ah-pv", "#e67e22"}, {"ah-cn", "#c0392b"}, {"ah-v", "#222"}, {"ah-n", "#d62728"}, {"ah-t", "#2ca02c"}};
    for (int k = 0; k < 5; k++)
        fprintf(f, "<marker id=\"%s\" viewBox=\"0 0 10 10\" refX=\"10\" refY=\"5\" markerWidth=\"%d\" "
                   "markerHeight=\"%d\" orient=\"auto\"><path d=\"M0 0L10 5L0 10Z\" fill=\"%s\"/></marker>\n",
                marks[k][0], k < 2 ? 4 : 5, k < 2 ? 4 : 5, marks[k][1]);
    fprintf(f, "</defs>\n<rect width=\"%d\" height=\"%d\" fill=\"#fff\"/>\n", w, h);
    fprintf(f, "<text x=\"%d\" y=\"22\" font-size=\"16\" font-weight=\"bold\">ntile answer key: exact projection "
               "vectors, resolution and edge states of every tile, generated by the engine (ntile sheet)</text>\n",
            MARGIN);
    fprintf(f, "<text class=\"s\" x=\"%d\" y=\"37\">Each panel: the tile in its unit cell with sample objects; the "
               "arrow moves an object out of the tile alone; the dashed outline is where the map puts it.</text>\n",
            MARGIN);
    _Static_assert(TILE_PANELS % COLS == HALF_ROW && TILE_PANELS / COLS + 2 == ROWS, "layout");
    int slot = 0;
    for (int tile = 1; tile < NT_TILE_COUNT; tile++, slot++)
        if (!tile_panel(sh, tile, MARGIN + (slot % COLS) * SLOT_W, HEADER + (slot / COLS) * SLOT_H)) return 0;
    legend_panel(f, MARGIN + HALF_ROW * SLOT_W, HEADER + (ROWS - 2) * SLOT_H);
    for (int m = 0; m < 2; m++)
        if (!friction_panel(sh, m ? NT_FRICTION_COULOMB : NT_FRICTION_N, MARGIN + m * PANEL_W,
                            HEADER + (ROWS - 1) * SLOT_H))
            return 0;
    fputs("</svg>\n", f);
    return 1;
}

/* ---------- the subcommand ---------- */

void cli_sheet_usage(FILE *f)
{
    fputs("  ntile sheet [-o FILE.svg]\n"
          "      Write the answer-key sheet as SVG (default: standard output): every solid\n"
          "      tile with its edge states and sample boxes and circles, their exact\n"
          "      projection vectors, resolved positions and contact normals, and the two\n"
          "      friction models on a 45-degree slope. Exit status 2 on a usage or write error.\n",
          f);
}

int cli_sheet(int argc, char **argv)
{
    const char *path = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            printf("usage:\n");
            cli_sheet_usage(stdout);
            return CLI_OK;
        } else if (strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0) {
            if (i + 1 >= argc || argv[i + 1][0] == '\0') {
                fprintf(stderr, "ntile sheet: %s needs a file name\nusage:\n", a);
                cli_sheet_usage(stderr);
                return CLI_USAGE;
            }
            if (path) {
                fprintf(stderr, "ntile sheet: more than one output file\nusage:\n");
                cli_sheet_usage(stderr);
                return CLI_USAGE;
            }
            path = argv[++i];
        } else {
            fprintf(stderr, "ntile sheet: unexpected argument '%s'\nusage:\n", a);
            cli_sheet_usage(stderr);
            return CLI_USAGE;
        }
    }
    int to_stdout = !path || strcmp(path, "-") == 0;
    sheet sh = {0};
    sh.f = to_stdout ? stdout : fopen(path, "w");
    if (!sh.f) {
        fprintf(stderr, "ntile sheet: cannot write '%s': %s\n", path, strerror(errno));
        return CLI_USAGE;
    }
    int ok = write_sheet(&sh);
    int werr = to_stdout ? (fflush(stdout) != 0 || ferror(stdout)) : (ferror(sh.f) | (fclose(sh.f) != 0));
    if (!ok) fprintf(stderr, "ntile sheet: %s\n", sh.error ? sh.error : "engine failure");
    else if (werr) fprintf(stderr, "ntile sheet: error writing %s\n", to_stdout ? "standard output" : path);
    /* No half-written sheet left behind; but never remove what is not a plain file (/dev/full). */
    struct stat st;
    if ((!ok || werr) && !to_stdout && stat(path, &st) == 0 && S_ISREG(st.st_mode)) remove(path);
    return ok && !werr ? CLI_OK : CLI_USAGE;
}
