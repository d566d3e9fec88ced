/* Drawing a frame: the world through the engine's debug-draw callbacks
 * (nt_world_draw), then the HUD, the tile palette and the help. */
#include <math.h>
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
    int used, player;
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

static void iput(imap *m, nt_real x, nt_real y, double dx, double dy, int player)
{
    size_t k = ikey(x, y, m->cap);
    while (m->e[k].used) {
        if (m->e[k].x == x && m->e[k].y == y) return;
        k = (k + 1) & (m->cap - 1);
    }
    ientry *e = &m->e[k];
    e->x = x, e->y = y, e->dx = dx, e->dy = dy, e->used = 1, e->player = player;
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

static void build_imap(const pg *p, imap *m, double alpha)
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
    nt_body_id player = nt_game_get_player(p->game);
    for (int i = 0; i < n; i++) {
        nt_vec2 q = nt_body_get_position(w, ids[i]);
        nt_shape s = nt_body_get_shape(w, ids[i]);
        int slot = ids[i].index1 - 1;
        double dx = 0, dy = 0;
        if (slot < p->prev_cap && p->prev_gen[slot] == ids[i].generation + 1) {
            dx = (alpha - 1) * ((double)q.x - p->prev[slot].x);
            dy = (alpha - 1) * ((double)q.y - p->prev[slot].y);
        }
        int isp = nt_body_id_equals(ids[i], player);
        iput(m, q.x, q.y, dx, dy, isp);
        if (s.type == NT_SHAPE_AABB) iput(m, q.x - s.half.x, q.y - s.half.y, dx, dy, isp);
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

static void offset_of(const rctx *r, nt_vec2 key, double *dx, double *dy, int *player)
{
    const ientry *e = iget(&r->map, key);
    *dx = e ? e->dx : 0;
    *dy = e ? e->dy : 0;
    if (player) *player = e ? e->player : 0;
}

static int is_tile_color(uint32_t c) { return c == 0x9fa8b3u || c == 0xb3a89fu; }

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
        if (is_tile_color(color)) pg_fill_polygon(r->c, xy, n, color == 0x9fa8b3u ? PG_COLOR_TILE : PG_COLOR_TILE_ROUND);
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

static void cb_box(nt_vec2 lo, nt_vec2 hi, uint32_t color, void *ctx)
{
    rctx *r = ctx;
    double dx, dy, xy[8];
    offset_of(r, lo, &dx, &dy, NULL);
    box_xy(r, lo, hi, dx, dy, xy);
    if (r->mode == MODE_BASE) {
        pg_fill_polygon(r->c, xy, 4, PG_BODY_FILL(color));
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
    int player;
    offset_of(r, center, &dx, &dy, &player);
    double x = sx_of(r, (double)center.x + dx), y = sy_of(r, (double)center.y + dy), rad = (double)radius * r->scale;
    if (r->mode == MODE_BASE) {
        /* A dead player: dark red and crossed out, so that nobody takes it for alive. */
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
    pg_blend_rect(r->c, 0, y - 3, pg_text_width(text, r->text_scale) + 8, y + h, PG_COLOR_PANEL, 170);
    pg_text(r->c, 4, y, text, color, r->text_scale);
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

static void draw_regions(rctx *r)
{
    const nt_level *lv = r->p->level;
    for (int i = 0; i < lv->region_count; i++) {
        const nt_level_region *g = &lv->regions[i];
        static const uint32_t colors[4] = {0x50606eu, 0x40d060u, 0xe0c040u, 0xe04040u};
        static const char *const labels[4] = {NULL, "EXIT", "SCORE", "KILL"};
        if (g->kind == NT_REGION_ZONE) continue; /* names an area only */
        int x0 = (int)floor(sx_of(r, (double)g->lo.x)), y0 = (int)floor(sy_of(r, (double)g->lo.y));
        int x1 = (int)floor(sx_of(r, (double)g->hi.x)), y1 = (int)floor(sy_of(r, (double)g->hi.y));
        pg_blend_rect(r->c, x0, y0, x1, y1, colors[g->kind], 40);
        pg_rect(r->c, x0, y0, x1, y1, colors[g->kind]);
        pg_text(r->c, x0 + 2, y0 + 2, labels[g->kind], colors[g->kind], 1);
    }
}

static int make_rays(const pg *p, nt_debug_ray *rays)
{
    if (!p->game || !p->mouse_seen || p->mx >= p->view_w) return 0;
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
    if (!p->mouse_seen || !p->game) return;
    if (p->drag == PG_MOUSE_LEFT) {
        pg_vec a = pg__to_screen(p, p->drag_from.x, p->drag_from.y);
        pg_arrow(r->c, a.x, a.y, p->mx, p->my, 7, PG_COLOR_SELECT);
        double rad = pg__throw_half(p) * p->zoom;
        if (p->throw_circle) pg_circle(r->c, a.x, a.y, rad, PG_COLOR_SELECT);
        else pg_rect(r->c, (int)(a.x - rad), (int)(a.y - rad), (int)(a.x + rad), (int)(a.y + rad), PG_COLOR_SELECT);
    }
    if (p->mx < p->view_w && !p->recording) {
        /* The cell a right-click paints. */
        pg_vec w = pg__to_world(p, p->mx, p->my);
        double cs = (double)p->level->cell_size;
        double cx = floor(w.x / cs) * cs, cy = floor(w.y / cs) * cs;
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

static void draw_hud(pg *p, pg_canvas *c, double fps, int ts)
{
    char lines[8][320];
    int n = 0;
    nt_game_state st = p->game ? nt_game_get_state(p->game) : (nt_game_state){0};
    nt_world *w = p->game ? nt_game_get_world(p->game) : NULL;
    const char *title = p->level->title[0] ? p->level->title : "untitled";
    snprintf(lines[n++], sizeof lines[0], "%.100s  (%.120s%s, level %d/%d: PgUp/PgDn, 1-%d)  tick %d%s%s", title,
             p->level_path, p->dirty ? " *edited*" : "", p->level_index + 1, p->level_count,
             p->level_count < 9 ? p->level_count : 9, st.tick, p->paused ? "  PAUSED (P, . steps)" : "",
             p->slow > 1 ? (p->slow == 2 ? "  SLOW 1/2" : p->slow == 4 ? "  SLOW 1/4" : "  SLOW 1/8") : "");
    char state[80] = "";
    if (st.has_player)
        snprintf(state, sizeof state, "  %s", st.complete ? "COMPLETE" : !st.alive ? "DEAD (R restarts)" : "alive");
    snprintf(lines[n++], sizeof lines[0], "fps %.0f  step %.0f us  bodies %d (awake %d)  score %d%s", fps, p->step_us,
             w ? nt_world_get_body_count(w) : 0, w ? nt_world_get_awake_count(w) : 0, st.score, state);
    double across = pg__throw_cells(p);
    snprintf(lines[n++], sizeof lines[0],
             "throw %s (Q) %g cell%s across (L)  bounce %.2f ([ ])  friction %.2f (; ')  friction model %s (F: rebuilds the "
             "world from the level)",
             p->throw_circle ? "ball" : "box", across, across == 1 ? "" : "s", p->bounce, p->friction,
             model_name(p->level->friction_model));
    char gl[200] = "";
    for (int g = 0; g < PG_GZ_COUNT; g++)
        if (gz(p, g)) {
            size_t l = strlen(gl);
            snprintf(gl + l, sizeof gl - l, " %s", pg_gizmos[g].name);
        }
    const nt_tile_info *ti = nt_tile_get_info(p->tile);
    snprintf(lines[n++], sizeof lines[0], "paint %s (Tab, strip)  gizmos:%s  H: help", ti ? ti->name : "?",
             gl[0] ? gl : " none");
    if (p->replay_on)
        snprintf(lines[n++], sizeof lines[0], "REPLAY %.160s: tick %d of %d", p->replay_path, st.tick, p->replay->ticks);
    if (p->recording)
        snprintf(lines[n++], sizeof lines[0], "REC %d ticks (F5 stops and saves; mouse tools are off)", p->rec_n);
    if (p->lab) {
        if (p->has_collision)
            snprintf(lines[n++], sizeof lines[0],
                     "last collision (tick %d): momentum (%.2f, %.2f) -> (%.2f, %.2f)  kinetic energy %.1f -> %.1f", p->coll_tick,
                     p->px_before, p->py_before, p->px_after, p->py_after, p->ke_before, p->ke_after);
        else {
            double px, py, ke;
            pg__mechanics(p, &px, &py, &ke);
            snprintf(lines[n++], sizeof lines[0], "momentum (%.2f, %.2f)  kinetic energy %.1f  (no collision yet)", px, py, ke);
        }
    }
    const char *m = pg_message(p);
    if (m[0]) snprintf(lines[n++], sizeof lines[0], "%s", m);
    int lh = PG_CHAR_H * ts, wmax = 0;
    for (int i = 0; i < n; i++) {
        int tw = pg_text_width(lines[i], ts);
        if (tw > wmax) wmax = tw;
    }
    pg_clip(c, 0, 0, p->view_w, p->view_h);
    pg_blend_rect(c, 0, 0, wmax + 10, n * lh + 8, PG_COLOR_PANEL, 160);
    for (int i = 0; i < n; i++) {
        uint32_t col = PG_COLOR_TEXT;
        if (m[0] && i == n - 1) col = PG_COLOR_SELECT;
        else if (p->recording && strncmp(lines[i], "REC", 3) == 0) col = 0xff6060u;
        pg_text(c, 5, 4 + i * lh, lines[i], col, ts);
    }
    pg_unclip(c);
}

static void draw_help(pg *p, pg_canvas *c, int ts)
{
    char text[4096];
    int n = snprintf(text, sizeof text,
                     "ntile-play - keys and mouse                                  (H closes)\n"
                     "\n"
                     "Arrows / WASD   move (pan the view in a level without a player)\n"
                     "Z / Space  jump      Down + jump  drop through a one-way floor\n"
                     "X  act (spawners)\n"
                     "R  restart      PgUp / PgDn, 1-9  switch level      Esc  quit\n"
                     "P  pause        .  single step         M  slow motion (1, 1/2, 1/4, 1/8)\n"
                     "+ / -, wheel  zoom     Home  reset zoom\n"
                     "\n"
                     "Mouse:  left-drag   throw a ball or box, the drag is its velocity\n"
                     "        right-drag  paint the selected tile (edge states update live)\n"
                     "        middle      delete the body under the mouse\n"
                     "        click the strip on the right to select a tile; Tab / Shift+Tab cycle\n"
                     "\n"
                     "Q  ball / box    L  size 0.6 / 1 / 2 / 4 cells across\n"
                     "[ ]  bounce -/+    ; '  friction -/+    (of new bodies)\n"
                     "F  friction model N / Coulomb: the model belongs to the world,\n"
                     "   so switching rebuilds the world from the level (thrown bodies go)\n"
                     "F2  save the level (.ntl, with your paint)\n"
                     "F5  record / stop: restarts the level and writes a replay (.ntr) that\n"
                     "    `ntile run` replays bit for bit; mouse tools are off while recording\n"
                     "\n"
                     "Gizmos:\n");
    for (int g = 0; g < PG_GZ_COUNT && n > 0 && (size_t)n < sizeof text; g++)
        n += snprintf(text + n, sizeof text - (size_t)n, "  %c  [%c] %s\n", pg_gizmos[g].key, gz(p, g) ? 'x' : ' ',
                      pg_gizmos[g].what);
    if (n > 0 && (size_t)n < sizeof text)
        snprintf(text + n, sizeof text - (size_t)n, "  Shift+J  projection magnification (now x%g)", p->proj_scale);
    int tw = pg_text_width(text, ts), lines = 1;
    for (const char *s = text; *s; s++) lines += *s == '\n';
    int th = lines * PG_CHAR_H * ts;
    int x = (p->view_w - tw) / 2, y = (p->view_h - th) / 2;
    if (x < 8) x = 8;
    if (y < 8) y = 8;
    pg_blend_rect(c, x - 10, y - 10, x + tw + 10, y + th + 10, PG_COLOR_PANEL, 215);
    pg_rect(c, x - 10, y - 10, x + tw + 10, y + th + 10, 0x6a7380u);
    pg_text(c, x, y, text, PG_COLOR_TEXT, ts);
}

/* ---------------------------------------------------------------- the frame */

void pg_render(pg *p, pg_canvas *c, double fps)
{
    pg__prepare_view(p);
    int ts = p->win_w >= 1600 ? 2 : 1;
    pg_unclip(c);
    pg_clear(c, PG_COLOR_OUTSIDE);
    pg_clip(c, 0, 0, p->view_w, p->view_h);
    rctx r;
    memset(&r, 0, sizeof r);
    r.p = p;
    r.c = c;
    r.scale = p->zoom;
    r.ox = p->view_w / 2.0 - p->cam.x * p->zoom;
    r.oy = p->view_h / 2.0 - p->cam.y * p->zoom;
    r.text_scale = ts;
    double cs = (double)p->level->cell_size;
    pg_fill_rect(c, (int)ceil(sx_of(&r, 0) - 0.5), (int)ceil(sy_of(&r, 0) - 0.5),
                 (int)ceil(sx_of(&r, p->level->width * cs) - 0.5), (int)ceil(sy_of(&r, p->level->height * cs) - 0.5),
                 PG_COLOR_BG);
    if (p->game) {
        nt_world *w = nt_game_get_world(p->game);
        build_imap(p, &r.map, pg__alpha(p));
        pg_vec lo = pg__to_world(p, 0, 0), hi = pg__to_world(p, p->view_w, p->view_h);
        nt_debug_draw dd = make_dd(&r);
        dd.use_bounds = true;
        dd.bounds_lo = nt_v2((nt_real)(lo.x - cs), (nt_real)(lo.y - cs));
        dd.bounds_hi = nt_v2((nt_real)(hi.x + cs), (nt_real)(hi.y + cs));
        dd.projection_scale = (nt_real)p->proj_scale;
        /* The picture: filled tiles, the level's regions, filled bodies. */
        r.mode = MODE_BASE;
        dd.draw_tiles = true;
        nt_world_draw(w, &dd);
        draw_regions(&r);
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
    pg_unclip(c);
    if (p->opt.hud) {
        draw_palette(p, c, ts);
        draw_hud(p, c, fps, ts);
        if (p->help) draw_help(p, c, ts);
    }
}
