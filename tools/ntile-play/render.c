/* Drawing a frame: the world through the engine's debug-draw callbacks
 * (nt_world_draw), then the HUD, the tile palette and the help. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "state.h"

/* ---------------------------------------------------------------- interpolation map
 * The debug draw gives positions, not bodies. To draw each body between its
 * positions before and after the last tick, every body's current centre (and a box's
 * lower corner, as the engine computes it) is a key to the offset that moves it back
 * to its interpolated place. The same offset moves the arrows drawn from its centre. */

typedef struct ientry {
    nt_real x, y;
    double dx, dy;
    int used, kind; /* PG_KIND_* */
} ientry;

typedef struct imap {
    ientry *e;
    size_t cap; /* power of two */
} imap;

static uint64_t bits_of(nt_real v)
{
    uint64_t b = 0;
    if (v == 0) v = 0; /* -0 and +0 alike */
    memcpy(&b, &v, sizeof v);
    return b;
}

static size_t ikey(nt_real x, nt_real y, size_t cap)
{
    uint64_t h = bits_of(x) * 0x9E3779B97F4A7C15ull ^ (bits_of(y) + 0x632BE59BD9B4E019ull) * 0xC2B2AE3D27D4EB4Full;
    h ^= h >> 29;
    return (size_t)h & (cap - 1);
}

static void iput(imap *m, nt_real x, nt_real y, double dx, double dy, int kind)
{
    size_t k = ikey(x, y, m->cap);
    while (m->e[k].used) {
        if (m->e[k].x == x && m->e[k].y == y) return;
        k = (k + 1) & (m->cap - 1);
    }
    ientry *e = &m->e[k];
    e->x = x, e->y = y, e->dx = dx, e->dy = dy, e->used = 1, e->kind = kind;
}

static const ientry *iget(const imap *m, nt_vec2 p)
{
    if (!m->e) return NULL;
    size_t k = ikey(p.x, p.y, m->cap);
    while (m->e[k].used) {
        if (m->e[k].x == p.x && m->e[k].y == p.y) return &m->e[k];
        k = (k + 1) & (m->cap - 1);
    }
    return NULL;
}

static void build_imap(pg *p, imap *m, double alpha)
{
    m->e = NULL;
    m->cap = 0;
    if (!p->game) return;
    nt_world *w = nt_game_get_world(p->game);
    nt_body_id *ids;
    int n = pg__bodies(p, &ids);
    size_t cap = 16;
    while (cap < (size_t)n * 4 + 4) cap *= 2;
    m->e = calloc(cap, sizeof *m->e);
    if (!m->e) {
        free(ids);
        return;
    }
    m->cap = cap;
    for (int i = 0; i < n; i++) {
        nt_vec2 q = nt_body_get_position(w, ids[i]);
        nt_shape s = nt_body_get_shape(w, ids[i]);
        int slot = ids[i].index1 - 1;
        double dx = 0, dy = 0;
        if (slot < p->prev_cap && p->prev_gen[slot] == ids[i].generation + 1) {
            dx = (alpha - 1) * ((double)q.x - p->prev[slot].x);
            dy = (alpha - 1) * ((double)q.y - p->prev[slot].y);
        }
        int kind = pg__body_kind(p, ids[i]);
        iput(m, q.x, q.y, dx, dy, kind);
        if (s.type == NT_SHAPE_AABB) iput(m, q.x - s.half.x, q.y - s.half.y, dx, dy, kind);
    }
    free(ids);
}

/* ---------------------------------------------------------------- debug-draw callbacks */

enum { MODE_BASE, MODE_GIZMO, MODE_SLEEP, MODE_PALETTE };

typedef struct rctx {
    pg *p;
    pg_canvas *c;
    int mode;
    double scale, ox, oy; /* screen = world * scale + o */
    imap map;
    int text_scale;
} rctx;

static double sx_of(const rctx *r, double x) { return x * r->scale + r->ox; }
static double sy_of(const rctx *r, double y) { return y * r->scale + r->oy; }

static void offset_of(const rctx *r, nt_vec2 key, double *dx, double *dy, int *kind)
{
    const ientry *e = iget(&r->map, key);
    *dx = e ? e->dx : 0;
    *dy = e ? e->dy : 0;
    if (kind) *kind = e ? e->kind : PG_KIND_PLAIN;
}

static int is_tile_color(uint32_t c) { return c == 0x9fa8b3u || c == 0xb3a89fu; }

static const uint32_t material_tints[16] = PG_MATERIAL_TINTS;

/* The material of the cell a tile polygon lies in (its vertices' mean), or 0. */
static int polygon_material(const pg *p, const nt_vec2 *v, int n)
{
    const nt_level *lv = p->level;
    if (!lv || !lv->cell_materials || n <= 0) return 0;
    double x = 0, y = 0;
    for (int i = 0; i < n; i++) x += (double)v[i].x, y += (double)v[i].y;
    double cs = (double)lv->cell_size;
    int cx = (int)floor(x / n / cs), cy = (int)floor(y / n / cs);
    if (cx < 0 || cy < 0 || cx >= lv->width || cy >= lv->height) return 0;
    return lv->cell_materials[(size_t)cy * (size_t)lv->width + (size_t)cx] & 15;
}


static void cb_polygon(const nt_vec2 *v, int n, uint32_t color, void *ctx)
{
    rctx *r = ctx;
    double xy[2 * 16];
    if (n > 16) n = 16;
    for (int i = 0; i < n; i++) {
        xy[2 * i] = sx_of(r, (double)v[i].x);
        xy[2 * i + 1] = sy_of(r, (double)v[i].y);
    }
    if (r->mode == MODE_BASE || r->mode == MODE_PALETTE) {
        uint32_t fill = color == 0x9fa8b3u ? PG_COLOR_TILE : PG_COLOR_TILE_ROUND;
        int m = r->mode == MODE_BASE && is_tile_color(color) ? polygon_material(r->p, v, n) : 0;
        if (m) fill = pg_mix(fill, material_tints[m], 110);
        if (is_tile_color(color)) pg_fill_polygon(r->c, xy, n, fill);
        if (r->mode == MODE_PALETTE) pg_polygon(r->c, xy, n, color);
    } else if (r->mode == MODE_GIZMO) {
        pg_polygon(r->c, xy, n, color);
    }
}

static void box_xy(const rctx *r, nt_vec2 lo, nt_vec2 hi, double dx, double dy, double *xy)
{
    double x0 = sx_of(r, (double)lo.x + dx), y0 = sy_of(r, (double)lo.y + dy);
    double x1 = sx_of(r, (double)hi.x + dx), y1 = sy_of(r, (double)hi.y + dy);
    double q[8] = {x0, y0, x1, y0, x1, y1, x0, y1};
    memcpy(xy, q, sizeof q);
}

static void sleep_mark(rctx *r, double x, double y)
{
    pg_text(r->c, (int)x + 2, (int)y - 10, "z", 0x9ad0ffu, 1);
}

/* A mine: a red disc with eight spikes and a dark core. */
static void draw_mine(pg_canvas *c, double x, double y, double rad)
{
    int wd = rad > 6 ? 2 : 1;
    for (int k = 0; k < 8; k++) {
        double a = 0.7853981633974483 * k;
        pg_thick_line(c, x, y, x + 1.7 * rad * cos(a), y + 1.7 * rad * sin(a), wd, PG_COLOR_MINE);
    }
    pg_fill_circle(c, x, y, rad, PG_COLOR_MINE);
    pg_fill_circle(c, x, y, rad * 0.4, PG_COLOR_MINE_CORE);
}

static void cb_box(nt_vec2 lo, nt_vec2 hi, uint32_t color, void *ctx)
{
    rctx *r = ctx;
    double dx, dy, xy[8];
    offset_of(r, lo, &dx, &dy, NULL);
    box_xy(r, lo, hi, dx, dy, xy);
    if (r->mode == MODE_BASE) {
        int kind;
        offset_of(r, lo, &dx, &dy, &kind);
        if (kind == PG_KIND_GOLD) {
            pg_fill_polygon(r->c, xy, 4, PG_COLOR_GOLD);
            pg_polygon(r->c, xy, 4, PG_COLOR_GOLD_RIM);
        } else if (kind == PG_KIND_MINE) {
            draw_mine(r->c, 0.5 * (xy[0] + xy[2]), 0.5 * (xy[1] + xy[5]), 0.5 * fabs(xy[2] - xy[0]));
        } else if (kind == PG_KIND_PLATFORM) {
            pg_fill_polygon(r->c, xy, 4, PG_COLOR_PLATFORM);
            pg_polygon(r->c, xy, 4, pg_mix(PG_COLOR_PLATFORM, 0xffffffu, 120));
        } else {
            pg_fill_polygon(r->c, xy, 4, PG_BODY_FILL(color));
        }
    } else if (r->mode == MODE_GIZMO) {
        pg_polygon(r->c, xy, 4, color);
    } else if (r->mode == MODE_SLEEP && color == 0x808080u) {
        pg_polygon(r->c, xy, 4, 0x9ad0ffu);
        sleep_mark(r, xy[2], xy[3]);
    }
}

static void cb_circle(nt_vec2 center, nt_real radius, uint32_t color, void *ctx)
{
    rctx *r = ctx;
    double dx, dy;
    int kind;
    offset_of(r, center, &dx, &dy, &kind);
    double x = sx_of(r, (double)center.x + dx), y = sy_of(r, (double)center.y + dy), rad = (double)radius * r->scale;
    if (r->mode == MODE_BASE) {
        if (kind == PG_KIND_GOLD) {
            pg_fill_circle(r->c, x, y, rad, PG_COLOR_GOLD);
            pg_circle(r->c, x, y, rad, PG_COLOR_GOLD_RIM);
            pg_fill_circle(r->c, x - rad * 0.3, y - rad * 0.3, rad * 0.25, pg_mix(PG_COLOR_GOLD, 0xffffffu, 150));
            return;
        }
        if (kind == PG_KIND_MINE) {
            draw_mine(r->c, x, y, rad);
            return;
        }
        /* A dead player: dark red and crossed out, so that nobody takes it for alive. */
        int player = kind == PG_KIND_PLAYER;
        int dead = player && r->p->game && !nt_game_get_state(r->p->game).alive;
        pg_fill_circle(r->c, x, y, rad, !player ? PG_BODY_FILL(color) : dead ? PG_COLOR_PLAYER_DEAD : PG_COLOR_PLAYER);
        if (dead) {
            double k = rad * 0.6;
            int wd = rad > 8 ? 2 : 1;
            pg_thick_line(r->c, x - k, y - k, x + k, y + k, wd, PG_COLOR_DEAD_MARK);
            pg_thick_line(r->c, x - k, y + k, x + k, y - k, wd, PG_COLOR_DEAD_MARK);
        }
    } else if (r->mode == MODE_GIZMO) {
        pg_circle(r->c, x, y, rad, color);
    } else if (r->mode == MODE_SLEEP && color == 0x808080u) {
        pg_circle(r->c, x, y, rad + 1, 0x9ad0ffu);
        sleep_mark(r, x + rad * 0.7, y - rad * 0.7);
    }
}

static void cb_segment(nt_vec2 a, nt_vec2 b, uint32_t color, void *ctx)
{
    rctx *r = ctx;
    if (r->mode != MODE_GIZMO) return;
    pg_line(r->c, sx_of(r, (double)a.x), sy_of(r, (double)a.y), sx_of(r, (double)b.x), sy_of(r, (double)b.y), color);
}

static void cb_arrow(nt_vec2 a, nt_vec2 b, uint32_t color, void *ctx)
{
    rctx *r = ctx;
    if (r->mode != MODE_GIZMO) return;
    double dx, dy;
    offset_of(r, a, &dx, &dy, NULL); /* arrows drawn from a body's centre move with it */
    pg_arrow(r->c, sx_of(r, (double)a.x + dx), sy_of(r, (double)a.y + dy), sx_of(r, (double)b.x + dx),
             sy_of(r, (double)b.y + dy), 5, color);
}

static void cb_point(nt_vec2 a, uint32_t color, void *ctx)
{
    rctx *r = ctx;
    if (r->mode != MODE_GIZMO) return;
    double x = sx_of(r, (double)a.x), y = sy_of(r, (double)a.y);
    pg_fill_rect(r->c, (int)floor(x) - 2, (int)floor(y) - 2, (int)floor(x) + 3, (int)floor(y) + 3, color);
}

/* The engine's counter line goes to the bottom of the view. */
static void cb_text(nt_vec2 at, const char *text, uint32_t color, void *ctx)
{
    rctx *r = ctx;
    (void)at;
    if (r->mode != MODE_GIZMO) return;
    int h = PG_CHAR_H * r->text_scale;
    int y = r->p->view_h - h - 4;
    int x = r->p->view_x;
    pg_blend_rect(r->c, x, y - 3, x + pg_text_width(text, r->text_scale) + 8, y + h, PG_COLOR_PANEL, 170);
    pg_text(r->c, x + 4, y, text, color, r->text_scale);
}

static nt_debug_draw make_dd(rctx *r)
{
    nt_debug_draw dd = nt_default_debug_draw();
    dd.draw_polygon = cb_polygon;
    dd.draw_box = cb_box;
    dd.draw_circle = cb_circle;
    dd.draw_segment = cb_segment;
    dd.draw_arrow = cb_arrow;
    dd.draw_point = cb_point;
    dd.draw_text = cb_text;
    dd.context = r;
    dd.draw_tiles = false;
    dd.draw_bodies = false;
    return dd;
}

/* ---------------------------------------------------------------- pieces */

static bool gz(const pg *p, int g) { return (p->gizmos >> g) & 1u; }

/* A dashed outline: 4 pixels on, 3 off. */
static void dashed_rect(pg_canvas *c, int x0, int y0, int x1, int y1, uint32_t color)
{
    for (int x = x0; x < x1; x++)
        if ((x - x0) % 7 < 4) pg_pixel(c, x, y0, color), pg_pixel(c, x, y1 - 1, color);
    for (int y = y0; y < y1; y++)
        if ((y - y0) % 7 < 4) pg_pixel(c, x0, y, color), pg_pixel(c, x1 - 1, y, color);
}

static void dotted_line(pg_canvas *c, double x0, double y0, double x1, double y1, uint32_t color)
{
    double dx = x1 - x0, dy = y1 - y0, len = sqrt(dx * dx + dy * dy);
    int n = (int)(len / 5);
    if (n > 4000) n = 4000;
    for (int k = 0; k <= n; k++) {
        double t = n ? (double)k / n : 0;
        double x = x0 + dx * t, y = y0 + dy * t;
        pg_fill_rect(c, (int)floor(x), (int)floor(y), (int)floor(x) + 2, (int)floor(y) + 2, color);
    }
}

/* The exit as a door (closed; open once the level is complete), score regions as bins
 * with their value, kill regions hatched, zones outlined and named. */
static void draw_regions(rctx *r)
{
    const nt_level *lv = r->p->level;
    bool complete = r->p->game && nt_game_get_state(r->p->game).complete;
    pg_canvas *c = r->c;
    int vx0 = c->cx0, vy0 = c->cy0, vx1 = c->cx1, vy1 = c->cy1;
    for (int i = 0; i < lv->region_count; i++) {
        const nt_level_region *g = &lv->regions[i];
        int x0 = (int)floor(sx_of(r, (double)g->lo.x)), y0 = (int)floor(sy_of(r, (double)g->lo.y));
        int x1 = (int)floor(sx_of(r, (double)g->hi.x)), y1 = (int)floor(sy_of(r, (double)g->hi.y));
        int w = x1 - x0, h = y1 - y0;
        switch (g->kind) {
        case NT_REGION_EXIT:
            if (complete) {
                pg_fill_rect(c, x0, y0, x1, y1, PG_COLOR_DOOR_OPEN);
                double q[8] = {x0, y0, x0 + w * 0.3, y0 + h * 0.1, x0 + w * 0.3, y1 - h * 0.1, x0, y1};
                pg_fill_polygon(c, q, 4, PG_COLOR_DOOR);
            } else {
                pg_fill_rect(c, x0, y0, x1, y1, PG_COLOR_DOOR);
                pg_rect(c, x0 + w / 6, y0 + h / 8, x1 - w / 6, y0 + h / 2 - 1, pg_mix(PG_COLOR_DOOR, 0, 90));
                pg_rect(c, x0 + w / 6, y0 + h / 2 + 1, x1 - w / 6, y1 - h / 8, pg_mix(PG_COLOR_DOOR, 0, 90));
                pg_fill_circle(c, x1 - w * 0.22, y0 + h * 0.55, w > 12 ? 2 : 1, 0xf0e080u);
            }
            pg_rect(c, x0 - 1, y0 - 1, x1 + 1, y1 + 1, pg_mix(PG_COLOR_DOOR, 0xffffffu, 110));
            pg_text(c, x0 + (w - pg_text_width("EXIT", 1)) / 2, y0 - PG_CHAR_H - 1, "EXIT", pg_mix(PG_COLOR_DOOR, 0xffffffu, 110), 1);
            break;
        case NT_REGION_SCORE: {
            char v[32];
            snprintf(v, sizeof v, "+%d", g->value);
            pg_blend_rect(c, x0, y0, x1, y1, PG_COLOR_BIN, 40);
            pg_fill_rect(c, x0, y0, x0 + 2, y1, PG_COLOR_BIN);
            pg_fill_rect(c, x1 - 2, y0, x1, y1, PG_COLOR_BIN);
            pg_fill_rect(c, x0, y1 - 2, x1, y1, PG_COLOR_BIN);
            int ts = w >= 60 && h >= 40 ? 2 : 1;
            pg_text(c, x0 + (w - pg_text_width(v, ts)) / 2, y0 + (h - 7 * ts) / 2, v, PG_COLOR_BIN, ts);
            break;
        }
        case NT_REGION_KILL:
            pg_blend_rect(c, x0, y0, x1, y1, PG_COLOR_KILL, 50);
            pg_clip(c, x0 > vx0 ? x0 : vx0, y0 > vy0 ? y0 : vy0, x1 < vx1 ? x1 : vx1, y1 < vy1 ? y1 : vy1);
            for (int d = -h; d < w; d += 8) pg_line(c, x0 + d, y1, x0 + d + h, y0, PG_COLOR_KILL);
            pg_clip(c, vx0, vy0, vx1, vy1);
            pg_rect(c, x0, y0, x1, y1, PG_COLOR_KILL);
            pg_text(c, x0 + 2, y0 + 2, "KILL", PG_COLOR_KILL, 1);
            break;
        case NT_REGION_SWITCH: {
            /* A button on a plate: hollow until the player has pressed it, then lit. */
            bool on = r->p->game && nt_game_switch_is_on(r->p->game, i);
            int cx = (x0 + x1) / 2, cy = (y0 + y1) / 2, rad = (w < h ? w : h) / 3;
            pg_rect(c, x0, y0, x1, y1, PG_COLOR_SWITCH);
            if (on) pg_fill_circle(c, cx, cy, rad > 1 ? rad : 1, PG_COLOR_SWITCH);
            else pg_circle(c, cx, cy, rad > 1 ? rad : 1, PG_COLOR_SWITCH);
            pg_text(c, x0 + 2, y0 - PG_CHAR_H - 1, on ? "SWITCH on" : "SWITCH", PG_COLOR_SWITCH, 1);
            break;
        }
        default:
            dashed_rect(c, x0, y0, x1, y1, PG_COLOR_ZONE);
            pg_text(c, x0 + 3, y0 + 3, g->name, PG_COLOR_ZONE, 1);
            break;
        }
    }
}

/* One-way cells: a bright top and an arrow up (bodies pass upwards, stop from above). */
static void draw_one_way(rctx *r)
{
    const nt_level *lv = r->p->level;
    if (!lv->cell_flags) return;
    pg *p = r->p;
    double cs = (double)lv->cell_size;
    pg_vec lo = pg__to_world(p, p->view_x, 0), hi = pg__to_world(p, p->view_x + p->view_w, p->view_h);
    int cx0 = (int)floor(lo.x / cs) - 1, cy0 = (int)floor(lo.y / cs) - 1, cx1 = (int)ceil(hi.x / cs) + 1, cy1 = (int)ceil(hi.y / cs) + 1;
    if (cx0 < 0) cx0 = 0;
    if (cy0 < 0) cy0 = 0;
    if (cx1 > lv->width) cx1 = lv->width;
    if (cy1 > lv->height) cy1 = lv->height;
    for (int y = cy0; y < cy1; y++)
        for (int x = cx0; x < cx1; x++) {
            if (!(lv->cell_flags[(size_t)y * (size_t)lv->width + (size_t)x] & NT_CELL_ONE_WAY)) continue;
            double ax = sx_of(r, x * cs), ay = sy_of(r, y * cs), bx = sx_of(r, (x + 1) * cs), by = sy_of(r, (y + 1) * cs);
            pg_fill_rect(r->c, (int)floor(ax), (int)floor(ay), (int)floor(bx), (int)floor(ay) + 2, PG_COLOR_ONEWAY);
            double mx = 0.5 * (ax + bx), h = by - ay;
            if (h >= 8) pg_arrow(r->c, mx, ay + h * 0.85, mx, ay + h * 0.2, h * 0.3, PG_COLOR_ONEWAY);
        }
}

/* Kinematic paths dotted, waypoints marked; spawners where they spawn. */
static void draw_paths_and_spawners(rctx *r)
{
    pg *p = r->p;
    const nt_level *lv = p->level;
    pg_canvas *c = r->c;
    for (int i = 0; i < lv->path_count; i++) {
        const nt_level_path *q = &lv->paths[i];
        if (q->mode == NT_PATH_ORBIT) {
            double cx = sx_of(r, (double)q->center.x), cy = sy_of(r, (double)q->center.y), rad = (double)q->radius * r->scale;
            int n = (int)(rad * 6.283 / 6) + 8;
            for (int k = 0; k < n && n < 4000; k++) {
                double a = 6.283185307179586 * k / n;
                pg_fill_rect(c, (int)floor(cx + rad * cos(a)), (int)floor(cy + rad * sin(a)), (int)floor(cx + rad * cos(a)) + 2,
                             (int)floor(cy + rad * sin(a)) + 2, PG_COLOR_PATH);
            }
            pg_fill_circle(c, cx, cy, 2, PG_COLOR_PATH);
        } else {
            for (int k = 0; k + 1 < q->point_count; k++)
                dotted_line(c, sx_of(r, (double)q->points[k].x), sy_of(r, (double)q->points[k].y),
                            sx_of(r, (double)q->points[k + 1].x), sy_of(r, (double)q->points[k + 1].y), PG_COLOR_PATH);
            if (q->mode == NT_PATH_LOOP && q->point_count > 2)
                dotted_line(c, sx_of(r, (double)q->points[q->point_count - 1].x), sy_of(r, (double)q->points[q->point_count - 1].y),
                            sx_of(r, (double)q->points[0].x), sy_of(r, (double)q->points[0].y), PG_COLOR_PATH);
            for (int k = 0; k < q->point_count; k++)
                pg_circle(c, sx_of(r, (double)q->points[k].x), sy_of(r, (double)q->points[k].y), 3, PG_COLOR_PATH);
        }
    }
    nt_world *w = p->game ? nt_game_get_world(p->game) : NULL;
    for (int i = 0; i < lv->spawner_count && w; i++) {
        const nt_level_spawner *sp = &lv->spawners[i];
        nt_vec2 at = lv->bodies[sp->template_body].position;
        if (sp->attach >= 0) {
            nt_body_id a = nt_game_find_body(p->game, lv->bodies[sp->attach].name);
            if (nt_body_id_is_null(a)) continue;
            double dx, dy;
            at = nt_body_get_position(w, a);
            offset_of(r, at, &dx, &dy, NULL);
            at.x = (nt_real)((double)at.x + dx);
            at.y = (nt_real)((double)at.y + dy);
        }
        double x = sx_of(r, (double)at.x + (double)sp->offset.x), y = sy_of(r, (double)at.y + (double)sp->offset.y);
        double tri[6] = {x - 5, y - 9, x + 5, y - 9, x, y - 2};
        pg_fill_polygon(c, tri, 3, PG_COLOR_SPAWNER);
        char label[64];
        snprintf(label, sizeof label, "%.31s%s", sp->name, sp->trigger == NT_SPAWN_ACTION ? " (X)" : "");
        pg_text(c, (int)x + 7, (int)y - 12, label, PG_COLOR_SPAWNER, 1);
    }
}

/* COMPLETE or DEAD, large, with the keys that go on. */
static void draw_banner(pg *p, pg_canvas *c, int ts)
{
    if (!p->game) return;
    nt_game_state st = nt_game_get_state(p->game);
    if (!st.has_player || (st.alive && !st.complete)) return;
    const char *big = st.complete ? "COMPLETE" : "DEAD";
    uint32_t col = st.complete ? PG_COLOR_BANNER_WIN : PG_COLOR_BANNER_DEAD;
    const char *keys = st.complete ? "R: play again    PgDn: next level" : "R: restart    PgDn: next level";
    int bs = 5 * ts, ks = 2 * ts;
    int bw = pg_text_width(big, bs), kw = pg_text_width(keys, ks);
    int h = 7 * bs + 12 * ts + 7 * ks;
    int cy = p->view_h / 3, x = p->view_x + p->view_w / 2;
    pg_blend_rect(c, p->view_x, cy - 12 * ts, p->view_x + p->view_w, cy + h + 12 * ts, PG_COLOR_PANEL, 170);
    pg_text(c, x - bw / 2, cy, big, col, bs);
    pg_text(c, x - kw / 2, cy + 7 * bs + 12 * ts, keys, PG_COLOR_TEXT, ks);
}

static int make_rays(const pg *p, nt_debug_ray *rays)
{
    if (!p->game || !p->mouse_seen || !pg__in_view(p, p->mx, p->my)) return 0;
    nt_world *w = nt_game_get_world(p->game);
    pg_vec m = pg__to_world(p, p->mx, p->my);
    double len = 5 * (double)p->level->cell_size;
    int n = 0;
    nt_query_filter f = nt_default_query_filter();
    for (int k = 0; k < 16; k++) {
        double a = 6.283185307179586 * k / 16 + 0.1;
        nt_debug_ray *ray = &rays[n++];
        ray->p0 = nt_v2((nt_real)m.x, (nt_real)m.y);
        ray->p1 = nt_v2((nt_real)(m.x + len * cos(a)), (nt_real)(m.y + len * sin(a)));
        ray->hit = nt_world_raycast(w, ray->p0, ray->p1, f, &ray->result);
    }
    nt_body_id pl = nt_game_get_player(p->game);
    if (nt_body_is_valid(w, pl)) {
        /* From the player's centre to the mouse; the filter ignores the player itself. */
        nt_query_filter self = f;
        self.ignore_count = 1;
        self.ignore[0] = pl;
        nt_vec2 c = nt_body_get_position(w, pl), to = nt_v2((nt_real)m.x, (nt_real)m.y);
        if (c.x != to.x || c.y != to.y) { /* none when the mouse is on its centre */
            nt_debug_ray *ray = &rays[n++];
            ray->p0 = c;
            ray->p1 = to;
            ray->hit = nt_world_raycast(w, ray->p0, ray->p1, self, &ray->result);
        }
    }
    return n;
}

static void draw_sensor_pairs(rctx *r)
{
    pg *p = r->p;
    nt_world *w = nt_game_get_world(p->game);
    for (int k = 0; k < p->pair_n; k++) {
        if (!nt_body_is_valid(w, p->pairs[k].sensor) || !nt_body_is_valid(w, p->pairs[k].visitor)) continue;
        nt_vec2 a = nt_body_get_position(w, p->pairs[k].sensor), b = nt_body_get_position(w, p->pairs[k].visitor);
        double adx, ady, bdx, bdy;
        offset_of(r, a, &adx, &ady, NULL);
        offset_of(r, b, &bdx, &bdy, NULL);
        double ax = sx_of(r, (double)a.x + adx), ay = sy_of(r, (double)a.y + ady);
        double bx = sx_of(r, (double)b.x + bdx), by = sy_of(r, (double)b.y + bdy);
        double rad = (double)nt_body_get_shape(w, p->pairs[k].sensor).half.x * r->scale;
        pg_line(r->c, ax, ay, bx, by, 0xe680e6u);
        pg_circle(r->c, ax, ay, rad + 3, 0xe680e6u);
        pg_circle(r->c, ax, ay, rad + 4, 0xe680e6u);
    }
}

static void draw_tools(rctx *r)
{
    pg *p = r->p;
    if (!p->game) return;
    nt_world *w = nt_game_get_world(p->game);
    if (!nt_body_id_is_null(p->selected) && nt_body_is_valid(w, p->selected)) {
        nt_vec2 q = nt_body_get_position(w, p->selected);
        nt_shape sh = nt_body_get_shape(w, p->selected);
        double dx, dy;
        offset_of(r, q, &dx, &dy, NULL);
        double x = sx_of(r, (double)q.x + dx), y = sy_of(r, (double)q.y + dy);
        double hx = (double)sh.half.x * r->scale + 3, hy = (double)sh.half.y * r->scale + 3;
        if (sh.type == NT_SHAPE_CIRCLE) {
            pg_circle(r->c, x, y, hx, PG_COLOR_SELECT);
            pg_circle(r->c, x, y, hx + 1, PG_COLOR_SELECT);
        } else {
            pg_rect(r->c, (int)(x - hx), (int)(y - hy), (int)(x + hx), (int)(y + hy), PG_COLOR_SELECT);
            pg_rect(r->c, (int)(x - hx) - 1, (int)(y - hy) - 1, (int)(x + hx) + 1, (int)(y + hy) + 1, PG_COLOR_SELECT);
        }
        if (p->joint && p->mouse_seen) { /* the spring of the mouse joint */
            pg_line(r->c, x, y, p->mx, p->my, PG_COLOR_SELECT);
            pg_fill_circle(r->c, p->mx, p->my, 3, PG_COLOR_SELECT);
        }
    }
    if (!p->mouse_seen) return;
    if (p->drag == PG_MOUSE_LEFT && !p->press_selected && !p->moving && p->tool == PG_TOOL_THROW) {
        pg_vec a = pg__to_screen(p, p->drag_from.x, p->drag_from.y);
        pg_arrow(r->c, a.x, a.y, p->mx, p->my, 7, PG_COLOR_SELECT);
        double rad = pg__throw_half(p) * p->zoom;
        if (p->throw_circle) pg_circle(r->c, a.x, a.y, rad, PG_COLOR_SELECT);
        else pg_rect(r->c, (int)(a.x - rad), (int)(a.y - rad), (int)(a.x + rad), (int)(a.y + rad), PG_COLOR_SELECT);
    }
    if (p->drag == PG_MOUSE_RIGHT && p->rect) {
        double cs = (double)p->level->cell_size;
        pg_vec m = pg__to_world(p, p->mx, p->my);
        int cx = (int)floor(m.x / cs), cy = (int)floor(m.y / cs);
        int x0 = cx < p->rect_x ? cx : p->rect_x, x1 = cx < p->rect_x ? p->rect_x : cx;
        int y0 = cy < p->rect_y ? cy : p->rect_y, y1 = cy < p->rect_y ? p->rect_y : cy;
        pg_vec a = pg__to_screen(p, x0 * cs, y0 * cs), b = pg__to_screen(p, (x1 + 1) * cs, (y1 + 1) * cs);
        pg_rect(r->c, (int)floor(a.x), (int)floor(a.y), (int)floor(b.x) + 1, (int)floor(b.y) + 1, PG_COLOR_SELECT);
    }
    if (pg__in_view(p, p->mx, p->my) && !p->recording) {
        /* The cell a right-click paints. */
        pg_vec mw = pg__to_world(p, p->mx, p->my);
        double cs = (double)p->level->cell_size;
        double cx = floor(mw.x / cs) * cs, cy = floor(mw.y / cs) * cs;
        if (cx >= 0 && cy >= 0 && cx < p->level->width * cs && cy < p->level->height * cs) {
            pg_vec a = pg__to_screen(p, cx, cy), b = pg__to_screen(p, cx + cs, cy + cs);
            pg_rect(r->c, (int)floor(a.x), (int)floor(a.y), (int)floor(b.x) + 1, (int)floor(b.y) + 1, 0x5a6270u);
        }
    }
}

static void draw_palette(pg *p, pg_canvas *c, int text_scale)
{
    int x0, cell, gap;
    pg__strip_rect(p, &x0, &cell, &gap);
    pg_fill_rect(c, x0, 0, p->win_w, p->win_h, PG_COLOR_STRIP);
    pg_text(c, x0 + gap, 6, "paint", 0xa0a8b0u, 1);
    (void)text_scale;
    rctx r;
    memset(&r, 0, sizeof r);
    r.p = p;
    r.c = c;
    r.mode = MODE_PALETTE;
    r.scale = cell / 24.0;
    nt_debug_draw dd = make_dd(&r);
    dd.draw_tiles = true;
    dd.use_bounds = true;
    for (int id = 0; id < NT_TILE_COUNT; id++) {
        int col = id % PG_STRIP_COLS, row = id / PG_STRIP_COLS;
        int sx = x0 + gap + col * (cell + gap), sy = 24 + gap + row * (cell + gap);
        pg_fill_rect(c, sx, sy, sx + cell, sy + cell, PG_COLOR_BG);
        double wx = 24.0 * (1 + 2 * col), wy = 24.0 * (1 + 2 * row);
        r.ox = sx - wx * r.scale;
        r.oy = sy - wy * r.scale;
        dd.bounds_lo = nt_v2((nt_real)(wx + 1), (nt_real)(wy + 1));
        dd.bounds_hi = nt_v2((nt_real)(wx + 23), (nt_real)(wy + 23));
        pg_clip(c, sx, sy, sx + cell, sy + cell);
        nt_world_draw(p->palette, &dd);
        pg_unclip(c);
        if (id == p->tile) {
            pg_rect(c, sx - 2, sy - 2, sx + cell + 2, sy + cell + 2, PG_COLOR_SELECT);
            pg_rect(c, sx - 3, sy - 3, sx + cell + 3, sy + cell + 3, PG_COLOR_SELECT);
        }
    }
}

static const char *model_name(nt_friction_model m) { return m == NT_FRICTION_N ? "N" : "Coulomb"; }

/* ---------------------------------------------------------------- the side panel
 * Box2D's samples app style: sections of text, checkboxes and small buttons drawn with
 * the rasteriser; each clickable part is remembered (p->widgets) for pg_mouse_button. */

typedef struct panel {
    pg *p;
    pg_canvas *c;
    int x, y, w, ts, lh;
} panel;

static void widget(panel *k, int x0, int y0, int x1, int y1, int cmd, int arg)
{
    pg *p = k->p;
    if (p->widget_n >= (int)(sizeof p->widgets / sizeof p->widgets[0])) return;
    struct pg_widget *w = &p->widgets[p->widget_n++];
    w->x0 = x0, w->y0 = y0, w->x1 = x1, w->y1 = y1, w->cmd = cmd, w->arg = arg;
}

static void heading(panel *k, const char *text)
{
    k->y += k->lh / 3;
    pg_fill_rect(k->c, k->x, k->y, k->x + k->w, k->y + k->lh, PG_COLOR_HEADING);
    pg_text(k->c, k->x + 4, k->y + 1, text, 0xb0c8e8u, k->ts);
    k->y += k->lh + 2;
}

/* Text wrapped at the panel's width. */
static void para(panel *k, const char *text, uint32_t color)
{
    int cols = (k->w - 8) / (PG_CHAR_W * k->ts);
    if (cols < 8) cols = 8;
    const char *s = text;
    while (*s) {
        int n = (int)strlen(s);
        if (n > cols) {
            n = cols;
            while (n > cols / 2 && s[n] != ' ') n--;
            if (s[n] != ' ') n = cols;
        }
        char line[256];
        snprintf(line, sizeof line, "%.*s", n < 255 ? n : 255, s);
        pg_text(k->c, k->x + 4, k->y, line, color, k->ts);
        k->y += k->lh;
        s += n;
        while (*s == ' ') s++;
    }
}

static void linef(panel *k, uint32_t color, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

static void linef(panel *k, uint32_t color, const char *fmt, ...)
{
    char buf[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    para(k, buf, color);
}

static void checkbox(panel *k, bool on, const char *label, int cmd, int arg)
{
    int s = 7 * k->ts, x = k->x + 4, y = k->y;
    pg_rect(k->c, x, y, x + s, y + s, 0xa0a8b0u);
    if (on) pg_fill_rect(k->c, x + 2, y + 2, x + s - 2, y + s - 2, PG_COLOR_SELECT);
    pg_text(k->c, x + s + 5, y, label, on ? PG_COLOR_TEXT : 0x98a0a8u, k->ts);
    widget(k, k->x, y - 1, k->x + k->w, y + k->lh - 1, cmd, arg);
    k->y += k->lh;
}

/* "label  value  [-] [+]" */
static void stepper(panel *k, const char *label, int cmd)
{
    int bw = 11 * k->ts, x1 = k->x + k->w - 4;
    pg_text(k->c, k->x + 4, k->y, label, PG_COLOR_TEXT, k->ts);
    for (int b = 0; b < 2; b++) {
        int bx = x1 - (2 - b) * (bw + 3);
        pg_rect(k->c, bx, k->y - 1, bx + bw, k->y + 8 * k->ts, 0x8090a0u);
        pg_text(k->c, bx + 3 * k->ts, k->y, b ? "+" : "-", PG_COLOR_TEXT, k->ts);
        widget(k, bx, k->y - 1, bx + bw, k->y + 8 * k->ts, cmd, b ? 1 : -1);
    }
    k->y += k->lh + 1;
}

/* "label  [button]" */
static void button(panel *k, const char *label, const char *text, int cmd, int arg)
{
    int tw = pg_text_width(text, k->ts) + 6 * k->ts, x1 = k->x + k->w - 4;
    pg_text(k->c, k->x + 4, k->y, label, PG_COLOR_TEXT, k->ts);
    pg_rect(k->c, x1 - tw, k->y - 1, x1, k->y + 8 * k->ts, 0x8090a0u);
    pg_text(k->c, x1 - tw + 3 * k->ts, k->y, text, PG_COLOR_TEXT, k->ts);
    widget(k, x1 - tw, k->y - 1, x1, k->y + 8 * k->ts, cmd, arg);
    k->y += k->lh + 1;
}

static void draw_panel(pg *p, pg_canvas *c, double fps, int ts)
{
    p->widget_n = 0;
    if (p->panel_w <= 0) return;
    panel k = {p, c, p->panel_x, 4, p->panel_w, ts, PG_CHAR_H * ts};
    pg_fill_rect(c, p->panel_x, 0, p->panel_x + p->panel_w, p->win_h, PG_COLOR_PANEL_BG);
    pg_fill_rect(c, p->panel_x + (p->panel == PG_PANEL_LEFT ? p->panel_w - 1 : 0), 0,
                 p->panel_x + (p->panel == PG_PANEL_LEFT ? p->panel_w : 1), p->win_h, 0x3a4452u);
    pg_clip(c, p->panel_x, 0, p->panel_x + p->panel_w - 1, p->win_h);
    nt_game_state st = p->game ? nt_game_get_state(p->game) : (nt_game_state){0};
    nt_world *w = p->game ? nt_game_get_world(p->game) : NULL;
    const nt_level *lv = p->level;

    linef(&k, PG_COLOR_SELECT, "%.60s", lv->title[0] ? lv->title : "untitled");
    linef(&k, 0xa0a8b0u, "%.200s%s", p->level_path, p->dirty ? " *edited*" : "");
    linef(&k, 0xa0a8b0u, "level %d/%d (PgUp/PgDn, 1-%d)", p->level_index + 1, p->level_count,
          p->level_count < 9 ? p->level_count : 9);
    linef(&k, PG_COLOR_TEXT, "tick %d%s%s", st.tick, p->paused ? "  PAUSED" : "",
          p->slow > 1 ? (p->slow == 2 ? "  SLOW 1/2" : p->slow == 4 ? "  SLOW 1/4" : "  SLOW 1/8") : "");
    if (st.has_player)
        linef(&k, st.complete ? PG_COLOR_BANNER_WIN : !st.alive ? PG_COLOR_BANNER_DEAD : PG_COLOR_TEXT, "player %s   score %d",
              st.complete ? "COMPLETE" : !st.alive ? "DEAD" : "alive", st.score);
    else
        linef(&k, PG_COLOR_TEXT, "score %d", st.score);
    if (p->replay_on) {
        if (st.tick < p->replay->ticks)
            linef(&k, 0x80d0ffu, "REPLAY tick %d of %d", st.tick, p->replay->ticks);
        else
            linef(&k, PG_COLOR_BANNER_WIN, "replay over (%d ticks): you have control", p->replay->ticks);
    }
    if (p->recording) linef(&k, 0xff6060u, "REC %d ticks (F5 stops and saves)", p->rec_n);
    checkbox(&k, p->paused, "pause (P; . steps)", PG_CMD_PAUSE, 0);

    heading(&k, "World");
    nt_vec2 gv = w ? nt_world_get_gravity(w) : lv->gravity;
    char buf[128];
    snprintf(buf, sizeof buf, "gravity %g %g", (double)gv.x, (double)gv.y);
    stepper(&k, buf, PG_CMD_GRAVITY);
    snprintf(buf, sizeof buf, "dt %.4g s (%.0f Hz)", (double)p->dt, 1.0 / (double)p->dt);
    button(&k, buf, "change", PG_CMD_DT, 0);
    snprintf(buf, sizeof buf, "velocity iterations %d", p->vel_iters);
    stepper(&k, buf, PG_CMD_VEL_ITERS);
    snprintf(buf, sizeof buf, "position iterations %d", p->pos_iters);
    stepper(&k, buf, PG_CMD_POS_ITERS);
    checkbox(&k, lv->enable_sleep, "sleep (rebuilds the world)", PG_CMD_SLEEP, 0);
    button(&k, "friction model (F)", model_name(lv->friction_model), PG_CMD_FRICTION_MODEL, 0);

    heading(&k, "Thrown body (left-drag)");
    button(&k, "shape (Q)", p->throw_circle ? "ball" : "box", PG_CMD_THROW_SHAPE, 0);
    snprintf(buf, sizeof buf, "size %g cells (L)", pg__throw_cells(p));
    stepper(&k, buf, PG_CMD_THROW_SIZE);
    snprintf(buf, sizeof buf, "bounce %.2f ([ ])", p->bounce);
    stepper(&k, buf, PG_CMD_BOUNCE);
    snprintf(buf, sizeof buf, "friction %.2f (; ')", p->friction);
    stepper(&k, buf, PG_CMD_FRICTION);
    heading(&k, "Edit (Ctrl+Z undo, Ctrl+Y redo)");
    const nt_tile_info *ti = nt_tile_get_info(p->tile);
    linef(&k, PG_COLOR_TEXT, "paint %s (Tab, strip)", ti ? ti->name : "?");
    for (int t = 0; t < PG_TOOL_COUNT; t++) {
        char lab[64];
        snprintf(lab, sizeof lab, "%s%s", t == 0 ? "left: throw / inspect" : "place / move ", t == 0 ? "" : pg_tool_names[t]);
        checkbox(&k, p->tool == t, lab, PG_CMD_TOOL, t);
    }
    snprintf(buf, sizeof buf, "material %d: f %.2f b %.2f", p->material, (double)lv->materials[p->material].friction,
             (double)lv->materials[p->material].bounce);
    stepper(&k, buf, PG_CMD_MATERIAL);
    linef(&k, 0x98a0a8u, "undo %d / %d", p->undo_pos, p->undo_n);

    heading(&k, "Gizmos");
    for (int g = 0; g < PG_GZ_COUNT; g++) {
        snprintf(buf, sizeof buf, "%c %s", pg_gizmos[g].key, pg_gizmos[g].name);
        checkbox(&k, gz(p, g), buf, PG_CMD_GIZMO, g);
    }

    heading(&k, "Inspector (hover a cell, click a body)");
    char ins[400];
    pg__inspect_cell(p, ins, sizeof ins);
    para(&k, ins[0] ? ins : "the mouse is not over the level", ins[0] ? PG_COLOR_TEXT : 0x98a0a8u);
    pg__inspect_body(p, ins, sizeof ins);
    if (ins[0]) para(&k, ins, PG_COLOR_SELECT);

    heading(&k, "Counters");
    if (w) {
        nt_world_counters wc = nt_world_get_counters(w);
        linef(&k, PG_COLOR_TEXT, "bodies %d (awake %d)", wc.body_count, wc.awake_count);
        linef(&k, PG_COLOR_TEXT, "contacts %d  pair tests %d", wc.contact_count, wc.pair_tests);
        linef(&k, PG_COLOR_TEXT, "moves %d", wc.substep_count);
    }
    if (p->lab) {
        if (p->has_collision)
            linef(&k, PG_COLOR_TEXT, "last collision (tick %d): momentum (%.2f, %.2f) -> (%.2f, %.2f), kinetic energy %.1f -> %.1f",
                  p->coll_tick, p->px_before, p->py_before, p->px_after, p->py_after, p->ke_before, p->ke_after);
        else {
            double px, py, ke;
            pg__mechanics(p, &px, &py, &ke);
            linef(&k, PG_COLOR_TEXT, "momentum (%.2f, %.2f) kinetic energy %.1f (no collision yet)", px, py, ke);
        }
    }
    /* Materials in use: the legend of the tints. */
    bool used[16] = {false};
    for (size_t i = 0; lv->cell_materials && i < (size_t)lv->width * (size_t)lv->height; i++) used[lv->cell_materials[i] & 15] = true;
    bool any = false;
    for (int m = 1; m < 16; m++) any = any || used[m];
    if (any) {
        heading(&k, "Materials");
        for (int m = 1; m < 16; m++) {
            if (!used[m]) continue;
            int s = 7 * ts;
            pg_fill_rect(c, k.x + 4, k.y, k.x + 4 + s, k.y + s, pg_mix(PG_COLOR_TILE, material_tints[m], 110));
            snprintf(buf, sizeof buf, "%d: friction %.2f bounce %.2f", m, (double)lv->materials[m].friction,
                     (double)lv->materials[m].bounce);
            pg_text(c, k.x + 8 + s, k.y, buf, PG_COLOR_TEXT, ts);
            k.y += k.lh;
        }
    }
    const char *m = pg_message(p);
    if (m[0]) {
        k.y += k.lh / 2;
        para(&k, m, PG_COLOR_SELECT);
    }
    k.y += k.lh / 2;
    para(&k, "H: help  F3: panel left/right/off", 0x808890u);
    /* The wall-clock figures, alone on the bottom line (frames differ only there). */
    char clock[96];
    snprintf(clock, sizeof clock, "fps %.0f  step %.0f us", fps, p->step_us);
    pg_fill_rect(c, k.x, p->win_h - k.lh - 2, k.x + k.w - 1, p->win_h, PG_COLOR_PANEL_BG);
    pg_text(c, k.x + 4, p->win_h - k.lh, clock, 0x98a0a8u, ts);
    pg_unclip(c);
}

static void draw_help(pg *p, pg_canvas *c, int ts)
{
    char text[4096];
    int last = p->level_count < 9 ? p->level_count : 9;
    int n = snprintf(text, sizeof text,
                     "ntile-play - keys and mouse                                       (H closes)\n"
                     "\n"
                     "Arrows / WASD  move (pan the view in a level without a player)\n"
                     "Z / Space  jump     Down + jump  drop through a one-way floor     X  act\n"
                     "R  restart (keeps your edits)   PgUp / PgDn, 1-%d  switch level   Esc  quit\n"
                     "P  pause   .  one tick   ,  one tick back (a replay, played again from the\n"
                     "   start)   End  the replay's last tick   F7  its first diverging tick;\n"
                     "   click or drag the timeline at the bottom; drop a .ntl or .ntr here\n"
                     "+ / -  zoom   wheel  zoom at the cursor   Home  reset the view\n"
                     "middle-drag, Space+drag  pan     F3  panel left / right / hidden\n"
                     "Ctrl+Z / Ctrl+Y  undo / redo   F2  save   F5  record / stop\n"
                     "F6 / Shift+F6  the left button: throw, gold, mine, exit, spawn,\n"
                     "               one-way, material, platform (or click in the panel)\n"
                     "\n"
                     "Mouse: left-drag   throw (the drag is the velocity); on a body: select\n"
                     "                   it and drag it on a spring; with a tool: place, move\n"
                     "       right-drag  paint the tile   Shift erase   Ctrl rectangle\n"
                     "       Alt+right   pick the tile under the mouse\n"
                     "       middle      click: delete the body there; drag: pan\n"
                     "       the strip on the right: choose a tile (Tab / Shift+Tab cycle)\n"
                     "\n"
                     "Q ball / box  L size  [ ] bounce  ; ' friction  F friction model N / Coulomb\n"
                     "\n"
                     "Gizmos (or click them in the panel):\n",
                     last);
    for (int g = 0; g < PG_GZ_COUNT && n > 0 && (size_t)n < sizeof text; g++)
        n += snprintf(text + n, sizeof text - (size_t)n, "  %c  [%c] %s\n", pg_gizmos[g].key, gz(p, g) ? 'x' : ' ',
                      pg_gizmos[g].what);
    if (n > 0 && (size_t)n < sizeof text)
        snprintf(text + n, sizeof text - (size_t)n, "  Shift+J  projection magnification (now x%g)", p->proj_scale);
    int tw = pg_text_width(text, ts), lines = 1;
    for (const char *s = text; *s; s++) lines += *s == '\n';
    int th = lines * PG_CHAR_H * ts;
    int x = p->view_x + (p->view_w - tw) / 2, y = (p->view_h - th) / 2;
    if (x < 8) x = 8;
    if (y < 8) y = 8;
    pg_blend_rect(c, x - 10, y - 10, x + tw + 10, y + th + 10, PG_COLOR_PANEL, 215);
    pg_rect(c, x - 10, y - 10, x + tw + 10, y + th + 10, 0x6a7380u);
    pg_text(c, x, y, text, PG_COLOR_TEXT, ts);
}

/* The replay's timeline: ticks played, the replay's length, the handle; after the
 * replay's end, "you have control". Click or drag it to go to a tick. */
static void draw_timeline(pg *p, pg_canvas *c, int ts)
{
    if (!p->replay_on || !p->game) return;
    int x0, y0, x1, y1;
    pg__timeline_rect(p, &x0, &y0, &x1, &y1);
    int t = nt_game_get_state(p->game).tick, n = p->replay->ticks > 0 ? p->replay->ticks : 1;
    pg_blend_rect(c, x0, y0, x1, y1, PG_COLOR_PANEL, 170);
    int hx = x0 + (int)((double)(t < n ? t : n) / n * (x1 - x0 - 1));
    pg_fill_rect(c, x0, y1 - 3 * ts, hx, y1, t < n ? PG_COLOR_TIMELINE : PG_COLOR_BANNER_WIN);
    pg_fill_rect(c, hx - ts, y0, hx + ts + 1, y1, PG_COLOR_SELECT);
    char text[160];
    if (t < n) snprintf(text, sizeof text, "replay tick %d of %d   , back  . step  End  F7 first divergence", t, n);
    else snprintf(text, sizeof text, "replay over (%d ticks): you have control   , back into the replay", n);
    pg_text(c, x0 + 4, y0 + 2 * ts, text, t < n ? PG_COLOR_TEXT : PG_COLOR_BANNER_WIN, ts);
}

/* The question before discarding edits. */
static void draw_confirm(pg *p, pg_canvas *c, int ts)
{
    if (p->confirm_cmd < 0) return;
    char text[600];
    const char *act = p->confirm_cmd == PG_CONFIRM_QUIT ? "quit" : "switch level";
    snprintf(text, sizeof text,
             "Unsaved edits to %.200s\n\nY       discard them and %s\nN, Esc  keep editing\nF2      save them, then %s", p->level_path,
             act, act);
    int tw = pg_text_width(text, ts), th = 5 * PG_CHAR_H * ts;
    int x = p->view_x + (p->view_w - tw) / 2, y = (p->view_h - th) / 2;
    if (x < 8) x = 8;
    pg_fill_rect(c, x - 14, y - 14, x + tw + 14, y + th + 14, PG_COLOR_PANEL_BG);
    pg_rect(c, x - 14, y - 14, x + tw + 14, y + th + 14, PG_COLOR_CONFIRM);
    pg_rect(c, x - 13, y - 13, x + tw + 13, y + th + 13, PG_COLOR_CONFIRM);
    pg_text(c, x, y, text, PG_COLOR_CONFIRM, ts);
}

/* ---------------------------------------------------------------- the frame */

void pg_render(pg *p, pg_canvas *c, double fps)
{
    pg__prepare_view(p);
    int ts = pg__text_scale(p);
    pg_unclip(c);
    pg_clear(c, PG_COLOR_OUTSIDE);
    pg_clip(c, p->view_x, 0, p->view_x + p->view_w, p->view_h);
    rctx r;
    memset(&r, 0, sizeof r);
    r.p = p;
    r.c = c;
    r.scale = p->zoom;
    r.ox = p->view_x + p->view_w / 2.0 - p->cam.x * p->zoom;
    r.oy = p->view_h / 2.0 - p->cam.y * p->zoom;
    r.text_scale = ts;
    double cs = (double)p->level->cell_size;
    pg_fill_rect(c, (int)ceil(sx_of(&r, 0) - 0.5), (int)ceil(sy_of(&r, 0) - 0.5),
                 (int)ceil(sx_of(&r, p->level->width * cs) - 0.5), (int)ceil(sy_of(&r, p->level->height * cs) - 0.5),
                 PG_COLOR_BG);
    if (p->game) {
        nt_world *w = nt_game_get_world(p->game);
        build_imap(p, &r.map, pg__alpha(p));
        pg_vec lo = pg__to_world(p, p->view_x, 0), hi = pg__to_world(p, p->view_x + p->view_w, p->view_h);
        nt_debug_draw dd = make_dd(&r);
        dd.use_bounds = true;
        dd.bounds_lo = nt_v2((nt_real)(lo.x - cs), (nt_real)(lo.y - cs));
        dd.bounds_hi = nt_v2((nt_real)(hi.x + cs), (nt_real)(hi.y + cs));
        dd.projection_scale = (nt_real)p->proj_scale;
        /* The picture: filled tiles, the level's regions, filled bodies. */
        r.mode = MODE_BASE;
        dd.draw_tiles = true;
        nt_world_draw(w, &dd);
        draw_one_way(&r);
        draw_regions(&r);
        draw_paths_and_spawners(&r);
        dd.draw_tiles = false;
        dd.draw_bodies = true;
        nt_world_draw(w, &dd);
        /* The gizmos, all through the engine's debug draw. */
        r.mode = MODE_GIZMO;
        dd.draw_tiles = gz(p, PG_GZ_TILES);
        dd.draw_edges = gz(p, PG_GZ_EDGES);
        dd.draw_grid = gz(p, PG_GZ_GRID);
        dd.draw_bodies = gz(p, PG_GZ_BODIES);
        dd.draw_velocities = gz(p, PG_GZ_VELOCITIES);
        dd.draw_velocity_split = gz(p, PG_GZ_SPLIT);
        dd.draw_contacts = dd.draw_tile_contacts = gz(p, PG_GZ_CONTACTS);
        dd.draw_projections = gz(p, PG_GZ_PROJECTIONS);
        dd.draw_stats = gz(p, PG_GZ_STATS);
        nt_debug_ray rays[PG_MAX_RAYS];
        if (gz(p, PG_GZ_RAYS)) {
            dd.ray_count = make_rays(p, rays);
            dd.rays = rays;
        }
        nt_world_draw(w, &dd);
        if (gz(p, PG_GZ_SLEEP)) {
            nt_debug_draw ds = make_dd(&r);
            ds.use_bounds = true;
            ds.bounds_lo = dd.bounds_lo;
            ds.bounds_hi = dd.bounds_hi;
            ds.draw_bodies = true;
            r.mode = MODE_SLEEP;
            nt_world_draw(w, &ds);
            r.mode = MODE_GIZMO;
        }
        if (gz(p, PG_GZ_SENSORS)) draw_sensor_pairs(&r);
        draw_tools(&r);
        free(r.map.e);
    }
    draw_banner(p, c, ts);
    if (p->opt.hud) draw_timeline(p, c, ts);
    pg_unclip(c);
    if (p->opt.hud) {
        draw_palette(p, c, ts);
        draw_panel(p, c, fps, ts);
        if (p->help) draw_help(p, c, ts);
    }
    draw_confirm(p, c, ts);
}
