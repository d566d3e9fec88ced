/* The playground's logic: levels, the game, fixed ticks, mouse tools, tuning,
 * saving (.ntl) and recording (.ntr). No SDL here (main.c), no drawing (render.c). */
#define _XOPEN_SOURCE 700 /* realpath */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "state.h"
#include "../common/levels.h"
#include "../common/stream.h"

const pg_gizmo_info pg_gizmos[PG_GZ_COUNT] = {
    {"tiles", 'T', "tile outlines"},
    {"edges", 'E', "edge states (red SOLID, yellow INTERESTING)"},
    {"grid", 'G', "loose-grid cells in use"},
    {"bodies", 'B', "body outlines by state (awake, asleep, static, kinematic, sensor)"},
    {"velocities", 'V', "velocity arrows (0.1 s)"},
    {"split", 'N', "velocity split against the surface: normal red, tangential green"},
    {"contacts", 'C', "contact normals (bodies white, tiles orange)"},
    {"projections", 'J', "projection vectors (Shift+J: magnification)"},
    {"rays", 'Y', "ray casts from the mouse (and from the player to the mouse)"},
    {"sleep", 'K', "sleeping bodies marked z"},
    {"sensors", 'O', "sensor overlaps"},
    {"stats", 'I', "the engine's counters"},
};

/* The levels shipped in levels/, in the order of the number keys. */
static const char *const shipped[] = {"tour", "ninja", "pachinko", "lab", "slopes", "stress"};
#define SHIPPED_COUNT ((int)(sizeof shipped / sizeof shipped[0]))

/* Thrown bodies' sizes in cells across, cycled by L; the first is the default. Bodies
 * may be up to 2 * NT_MAX_HALF_CELLS (8) cells across. */
static const double throw_sizes[] = {0.6, 1, 2, 4};
#define THROW_SIZES ((int)(sizeof throw_sizes / sizeof throw_sizes[0]))

double pg__throw_cells(const pg *p) { return throw_sizes[p->throw_size]; }
double pg__throw_half(const pg *p) { return 0.5 * pg__throw_cells(p) * (double)p->level->cell_size; }

/* Throws: world units per second of velocity per world unit dragged. */
#define THROW_GAIN 4.0

static double mono_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void say(pg *p, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void say(pg *p, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(p->msg, sizeof p->msg, fmt, ap);
    va_end(ap);
    p->msg_until = p->clock + 5.0;
}

int pg_parse_gizmos(const char *list, unsigned *out, char *why, size_t cap)
{
    unsigned set = 0;
    const char *s = list;
    while (*s) {
        const char *e = strchr(s, ',');
        size_t n = e ? (size_t)(e - s) : strlen(s);
        int found = 0;
        if (n == 3 && strncmp(s, "all", 3) == 0) set = (1u << PG_GZ_COUNT) - 1, found = 1;
        else if (n == 4 && strncmp(s, "none", 4) == 0) set = 0, found = 1;
        for (int g = 0; g < PG_GZ_COUNT && !found; g++)
            if (strlen(pg_gizmos[g].name) == n && strncmp(s, pg_gizmos[g].name, n) == 0) set |= 1u << g, found = 1;
        if (!found && n > 0) {
            snprintf(why, cap, "unknown gizmo '%.*s' (known: all, none", (int)(n > 40 ? 40 : n), s);
            for (int g = 0; g < PG_GZ_COUNT; g++) {
                size_t l = strlen(why);
                snprintf(why + l, cap - l, ", %s", pg_gizmos[g].name);
            }
            size_t l = strlen(why);
            snprintf(why + l, cap - l, ")");
            return 0;
        }
        s += n;
        if (*s == ',') s++;
    }
    *out = set;
    return 1;
}

/* ---------------------------------------------------------------- files and paths */

static int read_file(const char *path, char **out, size_t *len, char *why, size_t cap)
{
    return stream_read_file(path, 0, out, len, why, cap);
}

/* out = a + b + c; 0 (and out empty) when it does not fit. */
static int join(char *out, size_t cap, const char *a, const char *b, const char *c)
{
    size_t la = strlen(a), lb = strlen(b), lc = strlen(c);
    out[0] = '\0';
    if (la + lb + lc + 1 > cap) return 0;
    memcpy(out, a, la);
    memcpy(out + la, b, lb);
    memcpy(out + la + lb, c, lc + 1);
    return 1;
}

static int write_file(const char *path, const char *data, size_t len, char *why, size_t cap)
{
    return stream_write_file(path, data, len, (long)getpid(), why, cap);
}

static int file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

static int is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* Lexically: "tests/replays/../../levels/x.ntl" -> "levels/x.ntl" ("." parts go,
 * "name/.." pairs cancel; a leading "/" or leading ".." parts stay). */
static void normalise_path(char *path)
{
    char *parts[512];
    int n = 0;
    bool abs_path = path[0] == '/';
    char buf[PG_PATH_MAX];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *t = strtok(buf, "/"); t && n < 512; t = strtok(NULL, "/")) {
        if (strcmp(t, ".") == 0) continue;
        if (strcmp(t, "..") == 0 && n > 0 && strcmp(parts[n - 1], "..") != 0) {
            n--;
            continue;
        }
        if (strcmp(t, "..") == 0 && abs_path) continue;
        parts[n++] = t;
    }
    char out[PG_PATH_MAX];
    size_t k = 0;
    out[0] = '\0';
    if (abs_path) out[k++] = '/', out[k] = '\0';
    for (int i = 0; i < n; i++) {
        size_t l = strlen(parts[i]);
        if (k + l + 2 >= sizeof out) return; /* too long: leave it */
        if (i > 0) out[k++] = '/';
        memcpy(out + k, parts[i], l);
        k += l;
        out[k] = '\0';
    }
    if (k == 0) snprintf(out, sizeof out, ".");
    strcpy(path, out);
}

/* "a/b/c.ntl" -> "a/b" ("." without a slash). */
static void dir_name(const char *path, char *out, size_t cap)
{
    const char *s = strrchr(path, '/');
    if (!s) snprintf(out, cap, ".");
    else if (s == path) snprintf(out, cap, "/");
    else snprintf(out, cap, "%.*s", (int)(s - path), path);
}

/* "a/b/c.ntl" -> "c" */
static void base_name(const char *path, char *out, size_t cap)
{
    const char *b = strrchr(path, '/');
    b = b ? b + 1 : path;
    const char *dot = strrchr(b, '.');
    size_t n = dot && dot != b ? (size_t)(dot - b) : strlen(b);
    if (n >= cap) n = cap - 1;
    memcpy(out, b, n);
    out[n] = '\0';
}

/* The path of `file` relative to directory `dir` (both must exist). */
static int relative_path(const char *dir, const char *file, char *out, size_t cap)
{
    char a[PATH_MAX], b[PATH_MAX];
    if (!realpath(dir, a) || !realpath(file, b)) return 0;
    size_t i = 0, common = 0;
    /* Longest common prefix that ends at a directory boundary. */
    while (a[i] && b[i] && a[i] == b[i]) {
        i++;
        if (a[i] == '/' || a[i] == '\0') {
            if (b[i] == '/' || b[i] == '\0') common = i;
        }
    }
    if (a[i] == '\0' && b[i] == '/') common = i;
    if (strcmp(a, "/") == 0) common = 0;
    size_t n = 0;
    out[0] = '\0';
    for (const char *s = a + common; *s; s++)
        if (*s == '/') {
            if (n + 4 >= cap) return 0;
            memcpy(out + n, "../", 4);
            n += 3;
        }
    const char *rest = b + common;
    if (*rest == '/') rest++;
    if (n + strlen(rest) + 1 > cap) return 0;
    strcpy(out + n, rest);
    return 1;
}

/* ---------------------------------------------------------------- levels */

static int same_file(const char *a, const char *b)
{
    char ra[PATH_MAX], rb[PATH_MAX];
    return realpath(a, ra) && realpath(b, rb) && strcmp(ra, rb) == 0;
}

static void find_levels_dir(const pg_options *o, char *out, size_t cap)
{
    char buf[PG_PATH_MAX], probe[PG_PATH_MAX + 16];
    out[0] = '\0';
    if (o->levels_dir) {
        snprintf(out, cap, "%s", o->levels_dir);
        return;
    }
    /* Next to the given level, in ./levels, next to the program (build/../levels), or
     * installed (bin/../share/ntile/levels). */
    const char *cands[4] = {NULL, "levels", NULL, NULL};
    char lvdir[PG_PATH_MAX], exedir[PG_PATH_MAX], shared[PG_PATH_MAX];
    if (levels_installed_dir(shared, sizeof shared)) cands[3] = shared;
    if (o->level_path) {
        dir_name(o->level_path, lvdir, sizeof lvdir);
        cands[0] = lvdir;
    }
    ssize_t k = readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (k > 0) {
        buf[k] = '\0';
        dir_name(buf, exedir, sizeof exedir - 12);
        size_t l = strlen(exedir);
        snprintf(exedir + l, sizeof exedir - l, "/../levels");
        cands[2] = exedir;
    }
    for (int i = 0; i < 4; i++) {
        if (!cands[i]) continue;
        if (join(probe, sizeof probe, cands[i], "/ninja.ntl", "") && file_exists(probe)) {
            snprintf(out, cap, "%s", cands[i]);
            return;
        }
    }
}

static nt_status parse_level_file(const char *path, nt_level **out, char *why, size_t cap)
{
    char *text;
    size_t len;
    *out = NULL;
    if (!read_file(path, &text, &len, why, cap)) return NT_ERR_INVALID_ARGUMENT;
    nt_text_error e;
    nt_status s = nt_level_parse(path, text, len, out, &e);
    free(text);
    if (s != NT_OK) snprintf(why, cap, "%s", e.message);
    return s;
}

static void clear_world_extras(pg *p)
{
    p->selected = nt_null_body_id();
    p->joint = false;
    p->pair_n = 0;
    p->has_collision = false;
    p->acc = 0;
    p->drag = 0;
    for (int i = 0; i < p->prev_cap; i++) p->prev_gen[i] = 0;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t a = strlen(s), b = strlen(suffix);
    return a >= b && strcmp(s + a - b, suffix) == 0;
}

static void update_view_fit(pg *p);
static void pan(pg *p, double seconds);
static void history_clear(pg *p);
static void update_camera(pg *p);
static void seek(pg *p, int t);
static void jump_to_divergence(pg *p);
static void open_file(pg *p, const char *path);
static void undo(pg *p, bool redo);

/* ---------------------------------------------------------------- kinds of bodies */

static int kind_of_level_body(const nt_level_body *b)
{
    if (b->deadly) return PG_KIND_MINE;
    if (b->score > 0) return PG_KIND_GOLD;
    if (b->type == NT_BODY_KINEMATIC && b->path >= 0) return PG_KIND_PLATFORM;
    return PG_KIND_PLAIN;
}

static void set_kind(pg *p, nt_body_id id, int kind)
{
    int slot = id.index1 - 1;
    if (slot < 0) return;
    if (slot >= p->kind_cap) {
        int cap = p->kind_cap ? p->kind_cap : 256;
        while (cap <= slot) cap *= 2;
        unsigned char *nk = realloc(p->kind, (size_t)cap);
        if (!nk) return;
        p->kind = nk;
        uint32_t *ng = realloc(p->kind_gen, (size_t)cap * sizeof *ng);
        if (!ng) return;
        p->kind_gen = ng;
        for (int k = p->kind_cap; k < cap; k++) ng[k] = 0;
        p->kind_cap = cap;
    }
    p->kind[slot] = (unsigned char)kind;
    p->kind_gen[slot] = id.generation + 1;
}

/* A new game's bodies come in level order (repeats row by row, templates left out),
 * then the player (nt_game_get_bodies). */
static void classify_bodies(pg *p)
{
    for (int i = 0; i < p->kind_cap; i++) p->kind_gen[i] = 0;
    if (!p->game) return;
    nt_body_id *ids;
    int n = pg__bodies(p, &ids), k = 0;
    const nt_level *lv = p->level;
    for (int i = 0; i < lv->body_count && k < n; i++) {
        const nt_level_body *b = &lv->bodies[i];
        if (b->is_template) continue;
        for (int j = 0; j < b->repeat_x * b->repeat_y && k < n; j++) set_kind(p, ids[k++], kind_of_level_body(b));
    }
    free(ids);
    nt_body_id pl = nt_game_get_player(p->game);
    if (!nt_body_id_is_null(pl)) set_kind(p, pl, PG_KIND_PLAYER);
}

int pg__body_kind(pg *p, nt_body_id id)
{
    int slot = id.index1 - 1;
    if (slot >= 0 && slot < p->kind_cap && p->kind_gen[slot] == id.generation + 1) return p->kind[slot];
    /* A body made later: a spawner's copy of a template is what its template is. */
    int kind = PG_KIND_PLAIN;
    nt_world *w = nt_game_get_world(p->game);
    nt_shape s = nt_body_get_shape(w, id);
    nt_body_type t = nt_body_get_type(w, id);
    for (int i = 0; i < p->level->body_count; i++) {
        const nt_level_body *b = &p->level->bodies[i];
        if (b->is_template && b->type == t && b->shape.type == s.type && b->shape.half.x == s.half.x &&
            b->shape.half.y == s.half.y) {
            kind = kind_of_level_body(b);
            break;
        }
    }
    set_kind(p, id, kind);
    return kind;
}

/* Build a new game from the current level. */
static int rebuild(pg *p)
{
    nt_game *g = NULL;
    nt_status s = nt_game_create(p->level, &p->gdef, &g);
    if (s != NT_OK) {
        say(p, "cannot build the level: %s", nt_status_string(s));
        return 0;
    }
    nt_game_destroy(p->game);
    p->game = g;
    clear_world_extras(p);
    classify_bodies(p);
    return 1;
}

/* Replace the level with `lv` (taken over) read from `path`. */
static int install_level(pg *p, nt_level *lv, const char *path, char *why, size_t cap)
{
    nt_game *g = NULL;
    nt_game_def gd = p->gdef;
    nt_status s = nt_game_create(lv, &gd, &g);
    if (s != NT_OK) {
        snprintf(why, cap, "%s: cannot build the level: %s", path, nt_status_string(s));
        nt_level_destroy(lv);
        return 0;
    }
    nt_game_destroy(p->game);
    nt_level_destroy(p->level);
    p->game = g;
    p->level = lv;
    snprintf(p->level_path, sizeof p->level_path, "%s", path);
    history_clear(p);
    p->dirty = false;
    p->lab = ends_with(path, "/lab.ntl") || strcmp(path, "lab.ntl") == 0 || (lv->gravity.x == 0 && lv->gravity.y == 0);
    p->bounce = (double)lv->body_material.bounce;
    p->friction = (double)lv->body_material.friction;
    clear_world_extras(p);
    classify_bodies(p);
    p->zoom_fit = 0; /* a new level starts at its own fit */
    p->pan.x = p->pan.y = 0;
    update_view_fit(p);
    return 1;
}

static int load_level(pg *p, const char *path, char *why, size_t cap)
{
    nt_level *lv;
    if (parse_level_file(path, &lv, why, cap) != NT_OK) return 0;
    return install_level(p, lv, path, why, cap);
}

/* ---------------------------------------------------------------- recording */

static void record_stop(pg *p);

static int grow_rec(pg *p)
{
    if (p->rec_n < p->rec_cap) return 1;
    int cap = p->rec_cap ? p->rec_cap * 2 : 4096;
    uint32_t *k = realloc(p->rec_keys, (size_t)cap * sizeof *k);
    if (!k) return 0;
    p->rec_keys = k;
    uint32_t *t = realloc(p->rec_trace, (size_t)cap * sizeof *t);
    if (!t) return 0;
    p->rec_trace = t;
    p->rec_cap = cap;
    return 1;
}

/* ---------------------------------------------------------------- bodies */

int pg__bodies(const pg *p, nt_body_id **out)
{
    *out = NULL;
    if (!p->game) return 0;
    int n = nt_game_get_bodies(p->game, NULL, 0);
    nt_body_id *ids = malloc(((size_t)n + 1) * sizeof *ids);
    if (!ids) return 0;
    *out = ids;
    return nt_game_get_bodies(p->game, ids, n);
}

void pg__mechanics(const pg *p, double *px, double *py, double *ke)
{
    *px = *py = *ke = 0;
    if (!p->game) return;
    nt_world *w = nt_game_get_world(p->game);
    nt_body_id *ids;
    int n = pg__bodies(p, &ids);
    for (int i = 0; i < n; i++) {
        if (nt_body_get_type(w, ids[i]) != NT_BODY_DYNAMIC) continue;
        double m = (double)nt_body_get_mass(w, ids[i]);
        nt_vec2 v = nt_body_get_velocity(w, ids[i]);
        *px += m * (double)v.x;
        *py += m * (double)v.y;
        *ke += 0.5 * m * ((double)v.x * (double)v.x + (double)v.y * (double)v.y);
    }
    free(ids);
}

static void snapshot_positions(pg *p)
{
    nt_world *w = nt_game_get_world(p->game);
    nt_body_id *ids;
    int n = pg__bodies(p, &ids);
    for (int i = 0; i < n; i++) {
        int slot = ids[i].index1 - 1;
        if (slot >= p->prev_cap) {
            int cap = p->prev_cap ? p->prev_cap : 256;
            while (cap <= slot) cap *= 2;
            pg_vec *np = realloc(p->prev, (size_t)cap * sizeof *np);
            if (!np) break;
            p->prev = np;
            uint32_t *ng = realloc(p->prev_gen, (size_t)cap * sizeof *ng);
            if (!ng) break;
            p->prev_gen = ng;
            for (int k = p->prev_cap; k < cap; k++) ng[k] = 0;
            p->prev_cap = cap;
        }
        nt_vec2 q = nt_body_get_position(w, ids[i]);
        p->prev[slot].x = (double)q.x;
        p->prev[slot].y = (double)q.y;
        p->prev_gen[slot] = ids[i].generation + 1; /* 0 = nothing recorded */
    }
    free(ids);
}

/* Sensor overlaps: begin events add a pair, end events remove it; pairs whose bodies
 * are gone are dropped. */
static void update_pairs(pg *p)
{
    nt_world *w = nt_game_get_world(p->game);
    nt_sensor_events se = nt_world_get_sensor_events(w);
    for (int i = 0; i < se.end_count; i++)
        for (int k = 0; k < p->pair_n; k++)
            if (nt_body_id_equals(p->pairs[k].sensor, se.end_events[i].sensor) &&
                nt_body_id_equals(p->pairs[k].visitor, se.end_events[i].visitor)) {
                p->pairs[k] = p->pairs[--p->pair_n];
                break;
            }
    for (int i = 0; i < se.begin_count; i++) {
        if (p->pair_n == p->pair_cap) {
            int cap = p->pair_cap ? p->pair_cap * 2 : 64;
            pg_pair *np = realloc(p->pairs, (size_t)cap * sizeof *np);
            if (!np) break;
            p->pairs = np;
            p->pair_cap = cap;
        }
        p->pairs[p->pair_n].sensor = se.begin_events[i].sensor;
        p->pairs[p->pair_n].visitor = se.begin_events[i].visitor;
        p->pair_n++;
    }
    int m = 0;
    for (int k = 0; k < p->pair_n; k++)
        if (nt_body_is_valid(w, p->pairs[k].sensor) && nt_body_is_valid(w, p->pairs[k].visitor)) p->pairs[m++] = p->pairs[k];
    p->pair_n = m;
}

/* ---------------------------------------------------------------- the inspector */

/* The mouse joint, as Box2D's samples have it: a damped spring (3 Hz, critically
 * damped) pulls the selected body toward the mouse, through its velocity. */
static void mouse_joint(pg *p)
{
    if (!p->joint || !p->game) return;
    nt_world *w = nt_game_get_world(p->game);
    if (!nt_body_is_valid(w, p->selected) || nt_body_get_type(w, p->selected) != NT_BODY_DYNAMIC) {
        p->joint = false;
        return;
    }
    update_camera(p);
    pg_vec m = pg__to_world(p, p->mx, p->my);
    nt_vec2 x = nt_body_get_position(w, p->selected), v = nt_body_get_velocity(w, p->selected);
    double om = 2 * 3.141592653589793 * 3, k = om * om, c = 2 * om, dt = (double)p->dt;
    double vx = (double)v.x + (k * (m.x - (double)x.x) - c * (double)v.x) * dt;
    double vy = (double)v.y + (k * (m.y - (double)x.y) - c * (double)v.y) * dt;
    nt_body_set_velocity(w, p->selected, nt_v2((nt_real)vx, (nt_real)vy));
}

static const char *edge_letter(nt_edge e) { return e == NT_EDGE_SOLID ? "S" : e == NT_EDGE_INTERESTING ? "I" : "-"; }

void pg__inspect_cell(const pg *p, char *out, size_t cap)
{
    out[0] = '\0';
    if (!p->game || !p->mouse_seen || !pg__in_view(p, p->mx, p->my)) return;
    const nt_level *lv = p->level;
    pg_vec w = pg__to_world(p, p->mx, p->my);
    double cs = (double)lv->cell_size;
    int x = (int)floor(w.x / cs), y = (int)floor(w.y / cs);
    if (x < 0 || y < 0 || x >= lv->width || y >= lv->height) {
        snprintf(out, cap, "(%.0f, %.0f) outside the map", w.x, w.y);
        return;
    }
    size_t k = (size_t)y * (size_t)lv->width + (size_t)x;
    const nt_map *m = nt_world_get_map(nt_game_get_world(p->game));
    const nt_tile_info *ti = nt_tile_get_info(lv->tiles[k]);
    snprintf(out, cap, "cell (%d, %d) %s edges L%s R%s T%s B%s%s material %d", x, y, ti ? ti->name : "?",
             edge_letter(nt_map_get_edge(m, x, y, NT_SIDE_LEFT)), edge_letter(nt_map_get_edge(m, x, y, NT_SIDE_RIGHT)),
             edge_letter(nt_map_get_edge(m, x, y, NT_SIDE_TOP)), edge_letter(nt_map_get_edge(m, x, y, NT_SIDE_BOTTOM)),
             (lv->cell_flags[k] & NT_CELL_ONE_WAY) ? " one-way" : "", lv->cell_materials[k]);
}

void pg__inspect_body(const pg *p, char *out, size_t cap)
{
    out[0] = '\0';
    if (!p->game) return;
    nt_world *w = nt_game_get_world(p->game);
    nt_body_id id = p->selected;
    if (nt_body_id_is_null(id) || !nt_body_is_valid(w, id)) return;
    static const char *const types[] = {"static", "kinematic", "dynamic"};
    nt_body_type t = nt_body_get_type(w, id);
    nt_shape sh = nt_body_get_shape(w, id);
    nt_vec2 q = nt_body_get_position(w, id), v = nt_body_get_velocity(w, id);
    int contacts = 0;
    nt_body_get_contacts(w, id, NULL, 0, &contacts);
    nt_body_tile_contacts tc;
    memset(&tc, 0, sizeof tc);
    nt_body_get_tile_contacts(w, id, &tc);
    char shape[64];
    if (sh.type == NT_SHAPE_CIRCLE) snprintf(shape, sizeof shape, "circle r %g", (double)sh.half.x);
    else snprintf(shape, sizeof shape, "box %g x %g", 2 * (double)sh.half.x, 2 * (double)sh.half.y);
    snprintf(out, cap, "body %d.%u %s%s %s at (%.2f, %.2f) vel (%.2f, %.2f) contacts %d bodies, %d tiles%s %s",
             id.index1, (unsigned)id.generation, (unsigned)t < 3 ? types[t] : "?",
             nt_body_id_equals(id, nt_game_get_player(p->game)) ? " (player)" : "", shape, (double)q.x, (double)q.y, (double)v.x,
             (double)v.y, contacts, tc.count, tc.on_floor ? " (on a floor)" : "", nt_body_is_awake(w, id) ? "awake" : "asleep");
}

typedef struct pick_any {
    nt_body_id found;
    const nt_world *w;
} pick_any;

static bool pick_any_fn(nt_body_id id, void *ctx)
{
    pick_any *k = ctx;
    k->found = id;
    return false;
}

/* The body under a window point (sensors are not picked), or null. */
static nt_body_id body_at(const pg *p, double sx, double sy)
{
    nt_world *w = nt_game_get_world(p->game);
    pg_vec q = pg__to_world(p, sx, sy);
    pick_any k = {nt_null_body_id(), w};
    nt_world_query_point(w, nt_v2((nt_real)q.x, (nt_real)q.y), nt_default_query_filter(), pick_any_fn, &k);
    return k.found;
}

/* ---------------------------------------------------------------- ticks */

static void tick(pg *p)
{
    if (!p->game) return;
    nt_game_state st0 = nt_game_get_state(p->game);
    if (p->recording && p->rec_n >= NT_REPLAY_MAX_TICKS) {
        record_stop(p);
    }
    if (p->recording && !grow_rec(p)) {
        say(p, "out of memory: recording stopped");
        record_stop(p);
    }
    snapshot_positions(p);
    mouse_joint(p);
    double px0 = 0, py0 = 0, ke0 = 0;
    if (p->lab) pg__mechanics(p, &px0, &py0, &ke0);
    /* A replay's inputs while it lasts; then the keyboard takes over. */
    uint32_t keys = p->replay_on && st0.tick < p->replay->ticks ? nt_replay_keys_at(p->replay, st0.tick + 1) : p->keys;
    double t0 = mono_seconds();
    /* The panel's iterations, on whichever world the game holds now (a rebuild makes a
     * new one with the defaults). */
    nt_world *wi = nt_game_get_world(p->game);
    int vi, pi;
    nt_world_get_iterations(wi, &vi, &pi);
    if (vi != p->vel_iters || pi != p->pos_iters) nt_world_set_iterations(wi, p->vel_iters, p->pos_iters);
    nt_status s = nt_game_step(p->game, keys, p->dt);
    double us = (mono_seconds() - t0) * 1e6;
    p->step_us = p->step_us > 0 ? p->step_us * 0.9 + us * 0.1 : us;
    if (s != NT_OK) {
        say(p, "the game step failed: %s (paused)", nt_status_string(s));
        p->paused = true;
        return;
    }
    nt_world *w = nt_game_get_world(p->game);
    update_pairs(p);
    if (p->lab) {
        nt_contact_events ce = nt_world_get_contact_events(w);
        bool hit = false;
        for (int i = 0; i < ce.hit_count; i++)
            if (!nt_body_id_is_null(ce.hit_events[i].b)) hit = true;
        if (hit) {
            p->has_collision = true;
            p->coll_tick = st0.tick + 1;
            p->px_before = px0, p->py_before = py0, p->ke_before = ke0;
            pg__mechanics(p, &p->px_after, &p->py_after, &p->ke_after);
        }
    }
    if (p->recording) {
        uint64_t h = nt_game_hash(p->game);
        p->rec_keys[p->rec_n] = keys;
        p->rec_trace[p->rec_n] = nt_trace_fold(h);
        p->rec_last_hash = h;
        p->rec_n++;
    }
}

int pg_advance(pg *p, double seconds)
{
    p->fixed = false;
    if (!(seconds >= 0)) seconds = 0;
    p->clock += seconds < 3600 ? seconds : 3600;
    if (seconds > 0.25) seconds = 0.25; /* after a stall, do not try to catch up for ever */
    pan(p, seconds);
    if (p->paused) return 0;
    /* The first frame after a pause may hold a long sleep (pg_idle): not game time. */
    if (p->resumed && seconds > 1.0 / 60) seconds = 1.0 / 60;
    p->resumed = false;
    p->acc += seconds / p->slow;
    int n = 0;
    while (p->acc >= (double)p->dt && n < 8) {
        p->acc -= (double)p->dt;
        tick(p);
        n++;
    }
    if (p->acc > (double)p->dt) p->acc = (double)p->dt * 0.999; /* too slow to keep up: drop time */
    return n;
}

int pg_advance_frame(pg *p)
{
    p->fixed = true;
    p->clock += 1.0 / 60;
    pan(p, 1.0 / 60);
    p->frame++;
    p->acc = 0;
    if (p->paused || p->frame % p->slow != 0) return 0;
    tick(p);
    return 1;
}

bool pg_idle(const pg *p)
{
    return p->paused && p->drag == 0 && !(p->keys & (NT_INPUT_LEFT | NT_INPUT_RIGHT | NT_INPUT_UP | NT_INPUT_DOWN));
}

double pg__alpha(const pg *p)
{
    /* Fixed mode draws each tick as it is; real time draws between the last two ticks. */
    double a = p->paused ? 1.0 : p->fixed ? p->opt.fixed_alpha : p->acc / (double)p->dt;
    return a < 0 ? 0 : a > 1 ? 1 : a;
}

/* ---------------------------------------------------------------- view */

void pg__strip_rect(const pg *p, int *x0, int *cell, int *gap)
{
    int g = 4;
    int c = (p->win_h - 24 - g * (PG_STRIP_ROWS + 1)) / PG_STRIP_ROWS;
    if (c > 28) c = 28;
    if (c < 8) c = 8;
    *gap = g;
    *cell = c;
    *x0 = p->opt.hud ? p->win_w - (PG_STRIP_COLS * c + (PG_STRIP_COLS + 1) * g) : p->win_w;
}

int pg__text_scale(const pg *p) { return p->win_w >= 1600 ? 2 : 1; }

bool pg__in_view(const pg *p, double x, double y)
{
    return x >= p->view_x && x < p->view_x + p->view_w && y >= 0 && y < p->view_h;
}

/* The window, left to right: the panel (when on the left), the view, the panel (when
 * on the right), the tile strip. Without the HUD the view is the whole window. */
static void update_view_fit(pg *p)
{
    int x0, c, g;
    pg__strip_rect(p, &x0, &c, &g);
    int pw = p->opt.hud && p->panel != PG_PANEL_HIDDEN ? PG_PANEL_W * pg__text_scale(p) : 0;
    if (pw > x0 / 2) pw = x0 / 2;
    p->panel_w = pw;
    p->panel_x = p->panel == PG_PANEL_LEFT ? 0 : x0 - pw;
    p->view_x = p->panel == PG_PANEL_LEFT ? pw : 0;
    p->view_w = x0 - pw > 0 ? x0 - pw : 1;
    p->view_h = p->win_h > 0 ? p->win_h : 1;
    if (!p->level) return;
    double lw = p->level->width * (double)p->level->cell_size, lh = p->level->height * (double)p->level->cell_size;
    double z = fmin(p->view_w / lw, p->view_h / lh);
    if (z < 0.5) z = 0.5;
    if (z > 3) z = 3;
    double base = p->opt.has_zoom ? p->opt.zoom : z;
    if (p->zoom_fit > 0) p->zoom = p->zoom / p->zoom_fit * base; /* keep the user's zoom factor */
    else p->zoom = base;
    p->zoom_fit = base;
}

void pg_set_window(pg *p, int w, int h)
{
    p->win_w = w > 1 ? w : 1;
    p->win_h = h > 1 ? h : 1;
    update_view_fit(p);
}

pg_vec pg__player_pos(const pg *p, double alpha)
{
    pg_vec r = {0, 0};
    if (!p->game) return r;
    nt_body_id id = nt_game_get_player(p->game);
    nt_world *w = nt_game_get_world(p->game);
    if (!nt_body_is_valid(w, id)) return r;
    nt_vec2 q = nt_body_get_position(w, id);
    r.x = (double)q.x, r.y = (double)q.y;
    int slot = id.index1 - 1;
    if (slot < p->prev_cap && p->prev_gen[slot] == id.generation + 1) {
        r.x = p->prev[slot].x + (r.x - p->prev[slot].x) * alpha;
        r.y = p->prev[slot].y + (r.y - p->prev[slot].y) * alpha;
    }
    return r;
}

static bool has_player(const pg *p)
{
    return p->game && nt_body_is_valid(nt_game_get_world(p->game), nt_game_get_player(p->game));
}

static void clamp_pan(pg *p)
{
    double lw = p->level->width * (double)p->level->cell_size, lh = p->level->height * (double)p->level->cell_size;
    p->pan.x = fmin(fmax(p->pan.x, -lw), lw);
    p->pan.y = fmin(fmax(p->pan.y, -lh), lh);
}

/* Without a player the arrows (WASD) pan the view: 600 pixels a second. */
static void pan(pg *p, double seconds)
{
    if (has_player(p) || !p->level || p->opt.has_center) return;
    double d = 600 * seconds / p->zoom;
    if (p->keys & NT_INPUT_LEFT) p->pan.x -= d;
    if (p->keys & NT_INPUT_RIGHT) p->pan.x += d;
    if (p->keys & NT_INPUT_UP) p->pan.y -= d;
    if (p->keys & NT_INPUT_DOWN) p->pan.y += d;
    clamp_pan(p);
}

/* What the camera follows: the player (interpolated) or the level's centre. */
static pg_vec cam_base(const pg *p)
{
    pg_vec c = {p->level->width * (double)p->level->cell_size / 2, p->level->height * (double)p->level->cell_size / 2};
    if (has_player(p)) c = pg__player_pos(p, pg__alpha(p));
    return c;
}

/* The pan that puts the camera at `cam` (what the clamp left visible, moved by d). */
static void set_pan_from(pg *p, pg_vec cam, double dx, double dy)
{
    pg_vec b = cam_base(p);
    p->pan.x = cam.x + dx - b.x;
    p->pan.y = cam.y + dy - b.y;
    clamp_pan(p);
}

/* Camera: the player (interpolated) or the level's centre, moved by the pan (middle or
 * Space+drag, zoom at the cursor, the arrows without a player), kept inside the level
 * when the level is larger than the view; a level smaller than the view is centred. */
static void update_camera(pg *p)
{
    if (!p->level) return;
    double lw = p->level->width * (double)p->level->cell_size, lh = p->level->height * (double)p->level->cell_size;
    if (p->opt.has_center) {
        p->cam.x = p->opt.center_x;
        p->cam.y = p->opt.center_y;
        return;
    }
    pg_vec c = cam_base(p);
    c.x += p->pan.x, c.y += p->pan.y;
    double hw = p->view_w / p->zoom / 2, hh = p->view_h / p->zoom / 2;
    if (lw <= 2 * hw) c.x = lw / 2;
    else c.x = fmin(fmax(c.x, hw), lw - hw);
    if (lh <= 2 * hh) c.y = lh / 2;
    else c.y = fmin(fmax(c.y, hh), lh - hh);
    p->cam = c;
}

/* Zoom by `f` keeping the world point under window point (sx, sy) where it is. */
static void zoom_at(pg *p, double f, double sx, double sy)
{
    update_camera(p);
    pg_vec before = pg__to_world(p, sx, sy);
    p->zoom = fmin(16, fmax(0.1, p->zoom * f));
    update_camera(p);
    pg_vec after = pg__to_world(p, sx, sy);
    if (!p->opt.has_center) {
        set_pan_from(p, p->cam, before.x - after.x, before.y - after.y);
        update_camera(p);
    }
}

pg_vec pg__to_screen(const pg *p, double x, double y)
{
    pg_vec r = {(x - p->cam.x) * p->zoom + p->view_x + p->view_w / 2.0, (y - p->cam.y) * p->zoom + p->view_h / 2.0};
    return r;
}

pg_vec pg__to_world(const pg *p, double x, double y)
{
    pg_vec r = {(x - p->view_x - p->view_w / 2.0) / p->zoom + p->cam.x, (y - p->view_h / 2.0) / p->zoom + p->cam.y};
    return r;
}

/* ---------------------------------------------------------------- saving */

static int save_level(pg *p)
{
    char path[PG_PATH_MAX], base[256], why[600];
    base_name(p->level_path, base, sizeof base);
    if (p->opt.save_path) snprintf(path, sizeof path, "%s", p->opt.save_path);
    else if (ends_with(base, "-edit")) snprintf(path, sizeof path, "%s", p->level_path);
    else if (strlen(p->save_dir) + strlen(base) + 12 > sizeof path) {
        say(p, "the save directory's name is too long");
        return 0;
    } else snprintf(path, sizeof path, "%.3800s/%.200s-edit.ntl", p->save_dir, base);
    size_t n = nt_level_write(p->level, NULL, 0);
    char *text = malloc(n + 1);
    if (!text) {
        say(p, "out of memory saving the level");
        return 0;
    }
    nt_level_write(p->level, text, n + 1);
    int ok = write_file(path, text, n, why, sizeof why);
    free(text);
    if (!ok) {
        say(p, "%s", why);
        return 0;
    }
    snprintf(p->level_path, sizeof p->level_path, "%s", path);
    char *dup = strdup(path);
    if (dup) {
        free(p->levels[p->level_index]);
        p->levels[p->level_index] = dup;
    }
    p->save_mark = p->undo_pos;
    p->settings_dirty = false;
    p->dirty = false;
    say(p, "saved the level as %s", path);
    return 1;
}

static void keys_text(uint32_t keys, char *out)
{
    static const char letters[] = "LRUDJA";
    int n = 0;
    for (int k = 0; k < 6; k++)
        if (keys & (1u << k)) out[n++] = letters[k];
    if (n == 0) out[n++] = '.';
    out[n] = '\0';
}

static void record_start(pg *p)
{
    if (p->replay_on) {
        say(p, "recording is off while a replay plays (switch level or restart without --replay)");
        return;
    }
    if (!p->level) return;
    if (p->dt != p->dt_default) {
        say(p, "recording plays the replay format's tick, %g s: choose it in the panel (dt) first", (double)p->dt_default);
        return;
    }
    nt_world_def wdef = nt_default_world_def();
    if (p->vel_iters != wdef.velocity_iterations || p->pos_iters != wdef.position_iterations) {
        say(p, "recording plays the engine's default iterations (%d, %d): set them back in the panel first",
            wdef.velocity_iterations, wdef.position_iterations);
        return;
    }
    /* The replay names a level file: an edited level is saved first, so that the
     * file holds exactly what is played. */
    if (p->dirty && !save_level(p)) return;
    if (!rebuild(p)) return;
    p->recording = true;
    p->rec_n = 0;
    say(p, "recording from tick 0 (level restarted): mouse tools are off while recording; F5 stops and saves");
}

/* Choose the replay's file name: --record for the first one, else LEVEL-NNN.ntr. */
static int record_path(pg *p, char *out, size_t cap)
{
    if (p->opt.record_path && !p->rec_first_done) {
        snprintf(out, cap, "%s", p->opt.record_path);
        return 1;
    }
    char base[256];
    base_name(p->level_path, base, sizeof base);
    if (strlen(p->save_dir) + strlen(base) + 10 > cap) return 0;
    for (int i = 1; i < 1000; i++) {
        snprintf(out, cap, "%.3800s/%.200s-%03d.ntr", p->save_dir, base, i);
        if (!file_exists(out)) return 1;
    }
    return 0;
}

typedef struct sbuf {
    char *p;
    size_t n, cap;
    int oom;
} sbuf;

static void sb_printf(sbuf *b, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void sb_printf(sbuf *b, const char *fmt, ...)
{
    if (b->oom) return;
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int k = vsnprintf(b->p ? b->p + b->n : NULL, b->p ? b->cap - b->n : 0, fmt, ap);
        va_end(ap);
        if (k < 0) {
            b->oom = 1;
            return;
        }
        if (b->p && b->n + (size_t)k < b->cap) {
            b->n += (size_t)k;
            return;
        }
        size_t cap = b->cap ? b->cap * 2 : 4096;
        while (cap < b->n + (size_t)k + 1) cap *= 2;
        char *np = realloc(b->p, cap);
        if (!np) {
            b->oom = 1;
            return;
        }
        b->p = np;
        b->cap = cap;
    }
}

/* Names in a replay: letters, digits, '_', '-', '.'. */
static void clean_name(const char *s, char *out, size_t cap)
{
    size_t n = 0;
    for (; *s && n + 1 < cap && n < 40; s++) {
        char c = *s;
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
        out[n++] = ok ? c : '_';
    }
    if (n == 0 || !((out[0] >= 'a' && out[0] <= 'z') || (out[0] >= 'A' && out[0] <= 'Z') || out[0] == '_')) {
        memmove(out + 1, out, n < cap - 1 ? n : cap - 2);
        out[0] = 'r';
        n = n + 1 < cap ? n + 1 : cap - 1;
    }
    out[n] = '\0';
}

static void record_stop(pg *p)
{
    if (!p->recording) return;
    p->recording = false;
    if (p->rec_n == 0) {
        say(p, "recording stopped: no tick was played, nothing saved");
        return;
    }
    char path[PG_PATH_MAX], dir[PG_PATH_MAX], rel[PG_PATH_MAX], why[1200], name[64], base[256];
    if (!record_path(p, path, sizeof path)) {
        say(p, "recording stopped: no free file name in %s", p->save_dir);
        return;
    }
    dir_name(path, dir, sizeof dir);
    if (!relative_path(dir, p->level_path, rel, sizeof rel)) {
        say(p, "recording stopped: cannot name %s from %s", p->level_path, dir);
        return;
    }
    base_name(path, base, sizeof base);
    clean_name(base, name, sizeof name);
    int T = p->rec_n;
    nt_game_state st = nt_game_get_state(p->game);
    sbuf b = {0};
    sb_printf(&b, "ntile-replay 1\nname %s\nlevel \"%s\"\nticks %d\ninput", name, rel, T);
    char kt[8];
    for (int i = 0; i < T;) {
        int j = i;
        while (j < T && p->rec_keys[j] == p->rec_keys[i]) j++;
        keys_text(p->rec_keys[i], kt);
        sb_printf(&b, " %d%s", j - i, kt);
        i = j;
    }
    sb_printf(&b, "\n");
    /* What came out, as facts the runner checks (the hashes check everything else). */
    if (st.has_player) {
        if (st.complete) sb_printf(&b, "expect complete by %d\n", T);
        else sb_printf(&b, "expect not complete at %d\n", T);
        sb_printf(&b, "expect %salive at %d\n", st.alive ? "" : "not ", T);
    }
    sb_printf(&b, "expect score == %d at %d\n", st.score, T);
    sb_printf(&b, "expect bodies == %d at %d\n", nt_world_get_body_count(nt_game_get_world(p->game)), T);
    if (b.oom) {
        free(b.p);
        say(p, "out of memory writing the replay");
        return;
    }
    nt_replay *rp;
    nt_text_error e;
    nt_status s = nt_replay_parse(path, b.p, b.n, &rp, &e);
    free(b.p);
    if (s != NT_OK) {
        say(p, "recording: internal error: %s", e.message);
        return;
    }
    nt_replay_hash h;
    h.tick = T;
    h.is_double = NT_REAL_IS_DOUBLE;
    h.hash = p->rec_last_hash;
    h.line = 0;
    s = nt_replay_set_hashes(rp, NT_REAL_IS_DOUBLE, &h, 1, p->rec_trace, T);
    size_t n = s == NT_OK ? nt_replay_write(rp, NULL, 0) : 0;
    char *text = s == NT_OK ? malloc(n + 1) : NULL;
    if (!text) {
        nt_replay_destroy(rp);
        say(p, "out of memory writing the replay");
        return;
    }
    nt_replay_write(rp, text, n + 1);
    nt_replay_destroy(rp);
    int ok = write_file(path, text, n, why, sizeof why);
    free(text);
    if (!ok) {
        say(p, "%s", why);
        return;
    }
    p->rec_first_done = true;
    say(p, "recorded %d ticks to %s (check: build/ntile run %s)", T, path, path);
}

void pg_finish(pg *p)
{
    if (p && p->recording) record_stop(p);
}

/* ---------------------------------------------------------------- commands */

static void switch_level(pg *p, int index)
{
    if (index < 0 || index >= p->level_count) return;
    record_stop(p);
    char why[700];
    /* Leaving a replay: its seed, friction model and dt were for its own level. */
    nt_game_def saved = p->gdef;
    p->gdef = nt_default_game_def();
    if (!load_level(p, p->levels[index], why, sizeof why)) {
        p->gdef = saved;
        say(p, "%s", why);
        return;
    }
    p->level_index = index;
    p->replay_on = false;
    p->dt = p->dt_default;
    say(p, "level %d/%d: %s", index + 1, p->level_count, p->levels[index]);
}

static void switch_friction_model(pg *p)
{
    if (!p->level) return;
    if (p->replay_on) {
        say(p, "the replay fixes the friction model; switch level to play freely");
        return;
    }
    nt_level probe = *p->level;
    probe.friction_model = probe.friction_model == NT_FRICTION_N ? NT_FRICTION_COULOMB : NT_FRICTION_N;
    nt_text_error e;
    if (nt_level_validate(&probe, &e) != NT_OK) {
        say(p, "cannot switch the friction model: %s", e.message);
        return;
    }
    record_stop(p);
    p->level->friction_model = probe.friction_model;
    p->dirty = p->settings_dirty = true;
    if (probe.friction_model == NT_FRICTION_N && p->friction > 1) p->friction = 1;
    rebuild(p);
    say(p, "friction model %s: the model belongs to the world, so the world was rebuilt from the level",
        probe.friction_model == NT_FRICTION_N ? "N" : "Coulomb");
}

/* Gravity's y by a step (a tenth of 320 scaled to the cell), live in the world and in
 * the level model (F2 saves it). */
static void set_gravity(pg *p, int dir)
{
    if (!p->game) return;
    if (p->replay_on || p->recording) {
        say(p, "gravity is fixed while a replay plays or a recording runs");
        return;
    }
    nt_world *w = nt_game_get_world(p->game);
    nt_vec2 g = nt_world_get_gravity(w);
    double step = 32.0 * (double)p->level->cell_size / 24;
    g.y = (nt_real)(round(((double)g.y + dir * step) / step) * step);
    if (nt_world_set_gravity(w, g) != NT_OK) {
        say(p, "gravity out of range");
        return;
    }
    p->level->gravity = g;
    p->dirty = p->settings_dirty = true;
}

static const char *action_name(int cmd)
{
    return cmd == PG_CONFIRM_QUIT ? "quit" : cmd == PG_CMD_OPEN ? "open the file" : "switch level";
}

/* Before an action that would lose unsaved edits: true to go on; otherwise a
 * confirmation is shown and the action waits for its answer. */
static bool guard(pg *p, int cmd, int arg)
{
    if (!p->dirty) return true;
    p->confirm_cmd = cmd;
    p->confirm_arg = arg;
    return false;
}

bool pg_request_quit(pg *p)
{
    if (guard(p, PG_CONFIRM_QUIT, 0)) p->quit_now = true;
    return p->quit_now;
}

bool pg_should_quit(const pg *p) { return p->quit_now; }
bool pg_confirming(const pg *p) { return p->confirm_cmd >= 0; }

static void do_confirmed(pg *p, int cmd, int arg)
{
    if (cmd == PG_CONFIRM_QUIT) {
        p->quit_now = true;
        return;
    }
    bool dirty = p->dirty;
    p->dirty = false; /* the user chose: no second question */
    pg_command(p, (pg_cmd)cmd, arg);
    if (p->confirm_cmd >= 0) p->dirty = dirty;
}

void pg_command(pg *p, pg_cmd cmd, int arg)
{
    if (p->confirm_cmd >= 0 && cmd != PG_CMD_CONFIRM) return; /* a question waits for Y or N */
    switch (cmd) {
    case PG_CMD_UNDO: undo(p, false); break;
    case PG_CMD_SEEK: seek(p, arg); break;
    case PG_CMD_STEP_BACK:
        if (p->game) seek(p, nt_game_get_state(p->game).tick - 1);
        break;
    case PG_CMD_REPLAY_END:
        if (p->replay_on) seek(p, p->replay->ticks);
        break;
    case PG_CMD_DIVERGENCE: jump_to_divergence(p); break;
    case PG_CMD_OPEN:
        if (p->open_path && guard(p, cmd, arg)) open_file(p, p->open_path);
        break;
    case PG_CMD_TOOL:
        p->tool = arg >= 0 && arg < PG_TOOL_COUNT ? arg : (p->tool + (arg == -2 ? PG_TOOL_COUNT - 1 : 1)) % PG_TOOL_COUNT;
        say(p, "left button: %s", p->tool == PG_TOOL_THROW ? "throw bodies" : pg_tool_names[p->tool]);
        break;
    case PG_CMD_MATERIAL: p->material = (p->material + (arg < 0 ? 15 : 1)) % 16; break;
    case PG_CMD_REDO: undo(p, true); break;
    case PG_CMD_CONFIRM: {
        int c = p->confirm_cmd, a = p->confirm_arg;
        if (c < 0) break;
        p->confirm_cmd = -1;
        if (arg == 0) {
            say(p, "kept your edits");
        } else if (arg == 2) {
            if (save_level(p)) do_confirmed(p, c, a);
        } else {
            do_confirmed(p, c, a);
        }
        break;
    }
    case PG_CMD_RESTART:
        record_stop(p);
        if (rebuild(p)) say(p, "restarted");
        break;
    case PG_CMD_LEVEL:
        if (arg >= 0 && arg < p->level_count && guard(p, cmd, arg)) switch_level(p, arg);
        break;
    case PG_CMD_LEVEL_NEXT:
        if (guard(p, cmd, arg)) switch_level(p, (p->level_index + 1) % p->level_count);
        break;
    case PG_CMD_LEVEL_PREV:
        if (guard(p, cmd, arg)) switch_level(p, (p->level_index + p->level_count - 1) % p->level_count);
        break;
    case PG_CMD_PAUSE:
        p->paused = !p->paused;
        p->resumed = !p->paused;
        p->acc = 0;
        break;
    case PG_CMD_STEP:
        p->paused = true;
        p->acc = 0;
        tick(p);
        break;
    case PG_CMD_SLOW:
        p->slow = p->slow >= 8 ? 1 : p->slow * 2;
        break;
    case PG_CMD_HELP: p->help = !p->help; break;
    case PG_CMD_GIZMO:
        if (arg >= 0 && arg < PG_GZ_COUNT) p->gizmos ^= 1u << arg;
        break;
    case PG_CMD_PROJ_SCALE:
        p->proj_scale = p->proj_scale >= 10000 ? 1 : p->proj_scale * 10;
        say(p, "projection vectors x%g", p->proj_scale);
        break;
    case PG_CMD_THROW_SHAPE: p->throw_circle = !p->throw_circle; break;
    case PG_CMD_THROW_SIZE:
        p->throw_size = (p->throw_size + (arg < 0 ? THROW_SIZES - 1 : 1)) % THROW_SIZES;
        say(p, "thrown bodies: %g cell%s across", pg__throw_cells(p), pg__throw_cells(p) == 1 ? "" : "s");
        break;
    case PG_CMD_BOUNCE:
        p->bounce = fmin(1, fmax(0, round((p->bounce + 0.05 * arg) * 20) / 20));
        break;
    case PG_CMD_FRICTION: {
        double hi = p->level && p->level->friction_model == NT_FRICTION_COULOMB ? 2 : 1;
        p->friction = fmin(hi, fmax(0, round((p->friction + 0.05 * arg) * 20) / 20));
        break;
    }
    case PG_CMD_FRICTION_MODEL: switch_friction_model(p); break;
    case PG_CMD_TILE: p->tile = (p->tile + arg + NT_TILE_COUNT) % NT_TILE_COUNT; break;
    case PG_CMD_SAVE: save_level(p); break;
    case PG_CMD_RECORD:
        if (p->recording) record_stop(p);
        else record_start(p);
        break;
    case PG_CMD_PANEL:
        p->panel = (p->panel + 1) % 3;
        update_view_fit(p);
        break;
    case PG_CMD_GRAVITY: set_gravity(p, arg); break;
    case PG_CMD_DT: {
        static const double dts[] = {1.0 / 40, 1.0 / 60, 1.0 / 120, 1.0 / 20};
        if (p->replay_on || p->recording) {
            say(p, "the tick is fixed while a replay plays or a recording runs (replays hold 1/40 s ticks)");
            break;
        }
        int k = 0;
        while (k < 4 && fabs(dts[k] - (double)p->dt) > 1e-9) k++;
        p->dt = (nt_real)dts[(k + 1) % 4];
        p->acc = 0;
        say(p, "tick %.4g s (%.0f Hz)", (double)p->dt, 1 / (double)p->dt);
        break;
    }
    case PG_CMD_VEL_ITERS:
    case PG_CMD_POS_ITERS: {
        if (p->replay_on || p->recording) {
            say(p, "the iterations are fixed while a replay plays or a recording runs");
            break;
        }
        int *it = cmd == PG_CMD_VEL_ITERS ? &p->vel_iters : &p->pos_iters, lo = cmd == PG_CMD_VEL_ITERS ? 1 : 0;
        int v = arg > 0 ? (*it == 0 ? 1 : *it * 2) : (*it <= 1 ? 0 : *it / 2);
        *it = v < lo ? lo : v > 64 ? 64 : v;
        say(p, "iterations: %d velocity, %d position (from the next tick)", p->vel_iters, p->pos_iters);
        break;
    }
    case PG_CMD_SLEEP:
        if (p->replay_on) {
            say(p, "the replay fixes the world; switch level to play freely");
            break;
        }
        record_stop(p);
        p->level->enable_sleep = !p->level->enable_sleep;
        p->dirty = p->settings_dirty = true;
        rebuild(p);
        say(p, "sleeping %s: the world was rebuilt from the level", p->level->enable_sleep ? "on" : "off");
        break;
    case PG_CMD_ZOOM:
        if (arg == 0) {
            p->zoom = p->zoom_fit;
            p->pan.x = p->pan.y = 0;
        } else {
            zoom_at(p, arg > 0 ? 1.25 : 0.8, p->view_x + p->view_w / 2.0, p->view_h / 2.0);
        }
        break;
    }
}

void pg_set_keys(pg *p, uint32_t keys) { p->keys = keys; }

/* ---------------------------------------------------------------- mouse */

/* The palette swatch under a window point, or -1. */
static int strip_tile_at(const pg *p, double x, double y)
{
    int x0, c, g;
    pg__strip_rect(p, &x0, &c, &g);
    if (!p->opt.hud || x < x0) return -1;
    int col = (int)floor((x - x0 - g) / (c + g)), row = (int)floor((y - 24 - g) / (c + g));
    if (col < 0 || col >= PG_STRIP_COLS || row < 0 || row >= PG_STRIP_ROWS) return -1;
    int id = row * PG_STRIP_COLS + col;
    return id < NT_TILE_COUNT ? id : -1;
}

static bool mouse_tools_allowed(pg *p)
{
    if (!p->game) return false;
    if (p->recording) {
        say(p, "not while recording: throws, paint and deletes cannot be replayed (F5 stops the recording)");
        return false;
    }
    return true;
}

/* ---------------------------------------------------------------- editing, undo */

static void edit_free(pg_edit *e)
{
    free(e->cells);
    free(e->before);
    free(e->after);
    memset(e, 0, sizeof *e);
}

static void history_clear(pg *p)
{
    for (int i = 0; i < p->undo_n; i++) edit_free(&p->edits[i]);
    p->undo_n = p->undo_pos = p->save_mark = 0;
    p->stroke = false;
    p->settings_dirty = false;
}

static void update_dirty(pg *p) { p->dirty = p->undo_pos != p->save_mark || p->settings_dirty; }

/* Start an edit: what lies beyond the current position (redo) is dropped. */
static pg_edit *edit_begin(pg *p, const char *what)
{
    for (int i = p->undo_pos; i < p->undo_n; i++) edit_free(&p->edits[i]);
    p->undo_n = p->undo_pos;
    if (p->save_mark > p->undo_n) p->save_mark = -1; /* the saved state cannot come back by undo */
    if (p->undo_n == 1000) { /* keep the last thousand */
        edit_free(&p->edits[0]);
        memmove(p->edits, p->edits + 1, (size_t)(p->undo_n - 1) * sizeof *p->edits);
        p->undo_n--, p->undo_pos--;
        if (p->save_mark >= 0) p->save_mark--;
    }
    if (p->undo_n == p->undo_cap) {
        int cap = p->undo_cap ? p->undo_cap * 2 : 64;
        pg_edit *ne = realloc(p->edits, (size_t)cap * sizeof *ne);
        if (!ne) return NULL;
        p->edits = ne;
        p->undo_cap = cap;
    }
    pg_edit *e = &p->edits[p->undo_n++];
    memset(e, 0, sizeof *e);
    snprintf(e->what, sizeof e->what, "%s", what);
    p->undo_pos = p->undo_n;
    return e;
}

/* End an edit; one that changed nothing leaves no trace. */
static void edit_end(pg *p)
{
    p->stroke = false;
    if (p->undo_n > 0) {
        pg_edit *e = &p->edits[p->undo_n - 1];
        if (e->n == 0 && !e->before) {
            edit_free(e);
            p->undo_n--;
            p->undo_pos = p->undo_n;
        }
    }
    update_dirty(p);
}

/* Put a cell's tile, material and flags into the level model and the running world. */
static void apply_cell(pg *p, int x, int y, uint8_t tile, uint8_t mat, uint8_t flags)
{
    nt_level *lv = p->level;
    size_t k = (size_t)y * (size_t)lv->width + (size_t)x;
    nt_world *w = nt_game_get_world(p->game);
    if (lv->tiles[k] != tile && nt_game_set_tile(p->game, x, y, tile) == NT_OK) lv->tiles[k] = tile;
    if (lv->cell_materials && lv->cell_materials[k] != mat && nt_world_set_cell_material(w, x, y, mat) == NT_OK)
        lv->cell_materials[k] = mat;
    if (lv->cell_flags && lv->cell_flags[k] != flags && nt_world_set_cell_flags(w, x, y, flags) == NT_OK) lv->cell_flags[k] = flags;
}

/* The player's spawn must stay free: does cell (x, y) touch the spawned player? */
static bool spawn_cell(const pg *p, int x, int y)
{
    const nt_level *lv = p->level;
    if (!lv->has_player) return false;
    double cs = (double)lv->cell_size, r = (double)p->gdef.player.radius * cs;
    double px = (double)lv->player.x, py = (double)lv->player.y;
    double nx = fmax(x * cs, fmin(px, (x + 1) * cs)), ny = fmax(y * cs, fmin(py, (y + 1) * cs));
    return (nx - px) * (nx - px) + (ny - py) * (ny - py) < r * r;
}

/* Change one cell (tile, material, flags; -1 leaves that part) within the edit begun;
 * `search`: the cell may already be in this edit (strokes cross cells twice). */
static void edit_cell(pg *p, int x, int y, int tile, int mat, int flags, bool search)
{
    nt_level *lv = p->level;
    if (!p->game || p->undo_n == 0 || x < 0 || y < 0 || x >= lv->width || y >= lv->height) return;
    size_t k = (size_t)y * (size_t)lv->width + (size_t)x;
    uint8_t t0 = lv->tiles[k], m0 = lv->cell_materials ? lv->cell_materials[k] : 0, f0 = lv->cell_flags ? lv->cell_flags[k] : 0;
    uint8_t t1 = tile >= 0 ? (uint8_t)tile : t0, m1 = mat >= 0 ? (uint8_t)mat : m0, f1 = flags >= 0 ? (uint8_t)flags : f0;
    if (t0 == t1 && m0 == m1 && f0 == f1) return;
    if (t1 != NT_TILE_EMPTY && spawn_cell(p, x, y)) {
        say(p, "the player's spawn stays free: no tile over cell (%d, %d) (move the spawn first)", x, y);
        return;
    }
    apply_cell(p, x, y, t1, m1, f1);
    pg_edit *e = &p->edits[p->undo_n - 1];
    if (search)
        for (int i = e->n - 1; i >= 0; i--)
            if (e->cells[i].x == x && e->cells[i].y == y) {
                e->cells[i].tile1 = t1, e->cells[i].mat1 = m1, e->cells[i].flag1 = f1;
                return;
            }
    if (e->n == e->cap) {
        int cap = e->cap ? e->cap * 2 : 64;
        pg_cell_edit *nc = realloc(e->cells, (size_t)cap * sizeof *nc);
        if (!nc) return;
        e->cells = nc;
        e->cap = cap;
    }
    pg_cell_edit c = {x, y, t0, t1, m0, m1, f0, f1};
    e->cells[e->n++] = c;
}

static char *level_text(const nt_level *lv)
{
    size_t n = nt_level_write(lv, NULL, 0);
    char *t = malloc(n + 1);
    if (t) nt_level_write(lv, t, n + 1);
    return t;
}

/* Replace the level model by a text of it (undo and redo of object edits) and rebuild. */
static int set_level_text(pg *p, const char *text)
{
    nt_level *lv;
    nt_text_error e;
    if (nt_level_parse(p->level_path, text, strlen(text), &lv, &e) != NT_OK) {
        say(p, "internal error: %s", e.message);
        return 0;
    }
    nt_game *g = NULL;
    if (nt_game_create(lv, &p->gdef, &g) != NT_OK) {
        nt_level_destroy(lv);
        say(p, "cannot build the level");
        return 0;
    }
    nt_game_destroy(p->game);
    nt_level_destroy(p->level);
    p->game = g;
    p->level = lv;
    clear_world_extras(p);
    classify_bodies(p);
    return 1;
}

static void undo(pg *p, bool redo)
{
    if (p->recording) {
        say(p, "not while recording (F5 stops the recording)");
        return;
    }
    if (redo ? p->undo_pos >= p->undo_n : p->undo_pos <= 0) {
        say(p, "nothing to %s", redo ? "redo" : "undo");
        return;
    }
    pg_edit *e = &p->edits[redo ? p->undo_pos : p->undo_pos - 1];
    if (e->before) {
        if (!set_level_text(p, redo ? e->after : e->before)) return;
    } else if (redo) {
        for (int i = 0; i < e->n; i++) apply_cell(p, e->cells[i].x, e->cells[i].y, e->cells[i].tile1, e->cells[i].mat1, e->cells[i].flag1);
    } else {
        for (int i = e->n - 1; i >= 0; i--)
            apply_cell(p, e->cells[i].x, e->cells[i].y, e->cells[i].tile0, e->cells[i].mat0, e->cells[i].flag0);
    }
    p->undo_pos += redo ? 1 : -1;
    update_dirty(p);
    say(p, "%s: %s (%d of %d)", redo ? "redone" : "undone", e->what, p->undo_pos, p->undo_n);
}

/* The tile a right drag paints: the selected one, EMPTY with Shift (erase). */
static int paint_tile(const pg *p) { return (p->mods & PG_MOD_SHIFT) ? NT_TILE_EMPTY : p->tile; }

static void cell_at(const pg *p, double sx, double sy, int *x, int *y)
{
    pg_vec w = pg__to_world(p, sx, sy);
    double cs = (double)p->level->cell_size;
    *x = (int)floor(w.x / cs), *y = (int)floor(w.y / cs);
}

static void paint_to(pg *p, double sx, double sy)
{
    int x, y;
    cell_at(p, sx, sy, &x, &y);
    /* Every cell on the way from the last painted one, so a fast drag leaves no gaps. */
    int x0 = p->paint_x, y0 = p->paint_y;
    if (x0 == INT_MIN) x0 = x, y0 = y;
    int n = abs(x - x0) > abs(y - y0) ? abs(x - x0) : abs(y - y0);
    if (n > 4096) n = 0, x0 = x, y0 = y;
    for (int i = 0; i <= n; i++) {
        int cx = n ? x0 + (int)lround((double)(x - x0) * i / n) : x;
        int cy = n ? y0 + (int)lround((double)(y - y0) * i / n) : y;
        edit_cell(p, cx, cy, paint_tile(p), -1, -1, true);
    }
    p->paint_x = x, p->paint_y = y;
}

/* ---------------------------------------------------------------- objects */

const char *const pg_tool_names[PG_TOOL_COUNT] = {"throw", "gold", "mine", "exit", "spawn", "one-way", "material", "platform"};

/* A name for a new object: PREFIX1, PREFIX2, ... not yet in the level. */
static void fresh_name(const nt_level *lv, const char *prefix, char *out, size_t cap)
{
    for (int i = 1; i < 100000; i++) {
        snprintf(out, cap, "%s%d", prefix, i);
        if (nt_level_find_body(lv, out) < 0 && nt_level_find_region(lv, out) < 0 && nt_level_find_path(lv, out) < 0) return;
    }
}

/* An object edit: the level's text before, the change (on the level model), the text
 * after; the game is rebuilt from it (the level restarts). */
static pg_edit *object_edit_begin(pg *p, const char *what)
{
    pg_edit *e = edit_begin(p, what);
    if (!e) return NULL;
    e->before = level_text(p->level);
    if (!e->before) {
        edit_end(p);
        return NULL;
    }
    return e;
}

static void object_edit_end(pg *p, pg_edit *e, bool changed)
{
    if (changed) {
        e->after = level_text(p->level);
        if (!e->after || !set_level_text(p, e->after)) changed = false;
    }
    if (!changed) {
        set_level_text(p, e->before);
        free(e->before);
        e->before = NULL;
    }
    edit_end(p);
}

static bool cell_solid(const pg *p, int x, int y)
{
    const nt_level *lv = p->level;
    return x < 0 || y < 0 || x >= lv->width || y >= lv->height || lv->tiles[(size_t)y * (size_t)lv->width + (size_t)x] != NT_TILE_EMPTY;
}

/* Place an object of the tool's kind at world point w (cell x, y). */
static void place_object(pg *p, pg_vec w)
{
    nt_level *lv = p->level;
    double cs = (double)lv->cell_size;
    int x = (int)floor(w.x / cs), y = (int)floor(w.y / cs);
    if (x < 0 || y < 0 || x >= lv->width || y >= lv->height) return;
    nt_vec2 c = nt_v2((nt_real)((x + 0.5) * cs), (nt_real)((y + 0.5) * cs));
    if (p->tool == PG_TOOL_ONE_WAY || p->tool == PG_TOOL_MATERIAL) {
        size_t k = (size_t)y * (size_t)lv->width + (size_t)x;
        if (!edit_begin(p, p->tool == PG_TOOL_ONE_WAY ? "one-way flag" : "material")) return;
        if (p->tool == PG_TOOL_ONE_WAY) edit_cell(p, x, y, -1, -1, lv->cell_flags[k] ^ NT_CELL_ONE_WAY, false);
        else edit_cell(p, x, y, -1, lv->cell_materials[k] == p->material ? 0 : p->material, -1, false);
        edit_end(p);
        return;
    }
    char name[NT_LEVEL_NAME_MAX];
    nt_text_error err;
    nt_status s = NT_OK;
    pg_edit *e = object_edit_begin(p, pg_tool_names[p->tool]);
    if (!e) return;
    if (p->tool == PG_TOOL_SPAWN) {
        if (cell_solid(p, x, y)) {
            say(p, "the spawn must be in an empty cell");
            object_edit_end(p, e, false);
            return;
        }
        lv->has_player = true;
        lv->player = c;
    } else if (p->tool == PG_TOOL_EXIT) {
        int r = -1;
        for (int i = 0; i < lv->region_count && r < 0; i++)
            if (lv->regions[i].kind == NT_REGION_EXIT) r = i;
        nt_level_region g;
        memset(&g, 0, sizeof g);
        g.kind = NT_REGION_EXIT;
        double hw = 0.75 * cs, hh = cs;
        if (r >= 0) hw = 0.5 * (double)(lv->regions[r].hi.x - lv->regions[r].lo.x), hh = 0.5 * (double)(lv->regions[r].hi.y - lv->regions[r].lo.y);
        /* Standing on the floor of the cell clicked. */
        g.lo = nt_v2((nt_real)((x + 0.5) * cs - hw), (nt_real)((y + 1) * cs - 2 * hh));
        g.hi = nt_v2((nt_real)((x + 0.5) * cs + hw), (nt_real)((y + 1) * cs));
        if (r >= 0) {
            lv->regions[r].lo = g.lo, lv->regions[r].hi = g.hi;
        } else {
            fresh_name(lv, "exit", g.name, sizeof g.name);
            s = nt_level_add_region(lv, &g, &err);
        }
    } else {
        nt_level_body b = nt_level_default_body(lv);
        b.position = c;
        b.type = NT_BODY_STATIC;
        if (p->tool == PG_TOOL_GOLD) {
            fresh_name(lv, "gold", name, sizeof name);
            b.shape = nt_shape_circle((nt_real)(cs / 4));
            b.is_sensor = true;
            b.score = 1;
        } else if (p->tool == PG_TOOL_MINE) {
            fresh_name(lv, "mine", name, sizeof name);
            b.shape = nt_shape_circle((nt_real)(cs / 6));
            b.is_sensor = true;
            b.deadly = true;
        } else { /* a platform going up and down 4 cells above where it is placed */
            nt_level_path q;
            memset(&q, 0, sizeof q);
            fresh_name(lv, "plat", q.name, sizeof q.name);
            q.mode = NT_PATH_PINGPONG;
            q.speed = (nt_real)(2 * cs);
            q.wait = 1;
            q.point_count = 2;
            q.points[0] = c;
            q.points[1] = nt_v2(c.x, (nt_real)((double)c.y - 4 * cs));
            int pi = -1;
            s = nt_level_add_path(lv, &q, &pi, &err);
            snprintf(name, sizeof name, "%s", q.name);
            b.type = NT_BODY_KINEMATIC;
            b.shape = nt_shape_aabb((nt_real)(cs / 2), (nt_real)(cs / 6));
            b.path = pi;
        }
        snprintf(b.name, sizeof b.name, "%s", name);
        if (s == NT_OK) s = nt_level_add_body(lv, &b, NULL, &err);
    }
    if (s != NT_OK) say(p, "cannot place it: %s", err.message);
    else say(p, "placed %s at cell (%d, %d); the level restarted with it (Ctrl+Z undoes)", pg_tool_names[p->tool], x, y);
    object_edit_end(p, e, s == NT_OK);
}

/* The level object under world point w that the tools move: a gold, mine or platform
 * body, the exit, the spawn. Returns its tool kind and index, or 0. */
static int object_at(const pg *p, pg_vec w, int *index)
{
    const nt_level *lv = p->level;
    double cs = (double)lv->cell_size;
    if (lv->has_player && hypot(w.x - (double)lv->player.x, w.y - (double)lv->player.y) < 0.5 * cs) return *index = 0, PG_TOOL_SPAWN;
    for (int i = lv->body_count - 1; i >= 0; i--) {
        const nt_level_body *b = &lv->bodies[i];
        if (b->is_template || b->repeat_x * b->repeat_y != 1) continue;
        int k = kind_of_level_body(b);
        if (k == PG_KIND_PLAIN) continue;
        nt_vec2 at = b->path >= 0 ? nt_path_position(&lv->paths[b->path], 0, (double)b->phase) : b->position;
        double hx = fmax((double)b->shape.half.x, 0.3 * cs), hy = fmax((double)b->shape.half.y, 0.3 * cs);
        if (fabs(w.x - (double)at.x) <= hx && fabs(w.y - (double)at.y) <= hy) {
            *index = i;
            return k == PG_KIND_GOLD ? PG_TOOL_GOLD : k == PG_KIND_MINE ? PG_TOOL_MINE : PG_TOOL_PLATFORM;
        }
    }
    for (int i = 0; i < lv->region_count; i++) {
        const nt_level_region *g = &lv->regions[i];
        if (g->kind == NT_REGION_EXIT && w.x >= (double)g->lo.x && w.x <= (double)g->hi.x && w.y >= (double)g->lo.y &&
            w.y <= (double)g->hi.y)
            return *index = i, PG_TOOL_EXIT;
    }
    return 0;
}

/* Move the object grabbed (p->moving) by (dx, dy) world units. */
static void move_object(pg *p, double dx, double dy)
{
    nt_level *lv = p->level;
    dx = round(dx), dy = round(dy);
    if (dx == 0 && dy == 0) return;
    pg_edit *e = object_edit_begin(p, "move");
    if (!e) return;
    int i = p->moving_index;
    if (p->moving == PG_TOOL_SPAWN) {
        double cs = (double)lv->cell_size;
        double nx = (double)lv->player.x + dx, ny = (double)lv->player.y + dy;
        if (cell_solid(p, (int)floor(nx / cs), (int)floor(ny / cs))) {
            say(p, "the spawn must be in an empty cell");
            object_edit_end(p, e, false);
            return;
        }
        lv->player = nt_v2((nt_real)nx, (nt_real)ny);
    } else if (p->moving == PG_TOOL_EXIT) {
        nt_level_region *g = &lv->regions[i];
        g->lo = nt_v2((nt_real)((double)g->lo.x + dx), (nt_real)((double)g->lo.y + dy));
        g->hi = nt_v2((nt_real)((double)g->hi.x + dx), (nt_real)((double)g->hi.y + dy));
    } else {
        nt_level_body *b = &lv->bodies[i];
        b->position = nt_v2((nt_real)((double)b->position.x + dx), (nt_real)((double)b->position.y + dy));
        if (b->path >= 0) {
            nt_level_path *q = &lv->paths[b->path];
            for (int k = 0; k < q->point_count; k++)
                q->points[k] = nt_v2((nt_real)((double)q->points[k].x + dx), (nt_real)((double)q->points[k].y + dy));
            q->center = nt_v2((nt_real)((double)q->center.x + dx), (nt_real)((double)q->center.y + dy));
        }
    }
    nt_text_error err;
    bool ok = nt_level_validate(lv, &err) == NT_OK;
    if (!ok) say(p, "cannot move it there: %s", err.message);
    object_edit_end(p, e, ok);
}

/* Ctrl+right-drag: every cell of the rectangle from its first cell to (sx, sy). */
static void fill_rect_to(pg *p, double sx, double sy)
{
    int x, y;
    cell_at(p, sx, sy, &x, &y);
    const nt_level *lv = p->level;
    int x0 = p->rect_x < x ? p->rect_x : x, x1 = p->rect_x < x ? x : p->rect_x;
    int y0 = p->rect_y < y ? p->rect_y : y, y1 = p->rect_y < y ? y : p->rect_y;
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    if (x1 >= lv->width) x1 = lv->width - 1;
    if (y1 >= lv->height) y1 = lv->height - 1;
    if ((double)(x1 - x0 + 1) * (double)(y1 - y0 + 1) > 262144) {
        say(p, "a rectangle of at most 262,144 cells");
        return;
    }
    if (!edit_begin(p, "rectangle")) return;
    for (int cy = y0; cy <= y1; cy++)
        for (int cx = x0; cx <= x1; cx++) edit_cell(p, cx, cy, paint_tile(p), -1, -1, false);
    edit_end(p);
}

static void throw_body(pg *p, pg_vec from, pg_vec to)
{
    double cs = (double)p->level->cell_size;
    int fx = (int)floor(from.x / cs), fy = (int)floor(from.y / cs);
    if (fx < 0 || fy < 0 || fx >= p->level->width || fy >= p->level->height) {
        say(p, "cannot throw from outside the map");
        return;
    }
    if (p->level->tiles[(size_t)fy * (size_t)p->level->width + (size_t)fx] == NT_TILE_FULL) {
        say(p, "cannot throw from inside a solid tile (cell (%d, %d))", fx, fy);
        return;
    }
    nt_real h = (nt_real)pg__throw_half(p);
    nt_body_def d = nt_default_body_def();
    d.type = NT_BODY_DYNAMIC;
    d.shape = p->throw_circle ? nt_shape_circle(h) : nt_shape_aabb(h, h);
    d.position = nt_v2((nt_real)from.x, (nt_real)from.y);
    d.velocity = nt_v2((nt_real)((to.x - from.x) * THROW_GAIN), (nt_real)((to.y - from.y) * THROW_GAIN));
    d.mass = 1;
    d.material.friction = (nt_real)p->friction;
    d.material.bounce = (nt_real)p->bounce;
    nt_body_id id;
    nt_status s = nt_game_add_body(p->game, &d, &id);
    if (s == NT_ERR_OUT_OF_RANGE && (double)h > 0.5 * (double)p->level->cell_size)
        say(p, "cannot throw there: a body larger than half a cell must lie inside the map");
    else if (s != NT_OK) say(p, "cannot throw there: %s", nt_status_string(s));
}

typedef struct pick {
    nt_body_id player, found;
} pick;

static bool pick_fn(nt_body_id id, void *ctx)
{
    pick *k = ctx;
    if (nt_body_id_equals(id, k->player)) return true;
    k->found = id;
    return false;
}

static void delete_at(pg *p, double sx, double sy)
{
    nt_world *w = nt_game_get_world(p->game);
    pg_vec q = pg__to_world(p, sx, sy);
    pick k = {nt_game_get_player(p->game), nt_null_body_id()};
    int n = nt_world_query_point(w, nt_v2((nt_real)q.x, (nt_real)q.y), nt_default_query_filter(), pick_fn, &k);
    if (nt_body_id_is_null(k.found)) {
        say(p, n > 0 ? "the player cannot be deleted" : "no body there (sensors are not picked)");
        return;
    }
    nt_status s = nt_game_remove_body(p->game, k.found);
    if (s != NT_OK) say(p, "cannot delete that body: %s", nt_status_string(s));
}

void pg_set_mods(pg *p, unsigned mods) { p->mods = mods; }

void pg__timeline_rect(const pg *p, int *x0, int *y0, int *x1, int *y1)
{
    int h = 14 * pg__text_scale(p);
    *x0 = p->view_x + 8, *x1 = p->view_x + p->view_w - 8, *y1 = p->view_h - 6, *y0 = *y1 - h;
}

static bool in_timeline(const pg *p, double x, double y)
{
    if (!p->replay_on || !p->opt.hud) return false;
    int x0, y0, x1, y1;
    pg__timeline_rect(p, &x0, &y0, &x1, &y1);
    return x >= x0 && x < x1 && y >= y0 && y < y1;
}

static int timeline_tick(const pg *p, double x)
{
    int x0, y0, x1, y1;
    pg__timeline_rect(p, &x0, &y0, &x1, &y1);
    return (int)lround((x - x0) / (double)(x1 - x0 > 1 ? x1 - x0 : 1) * p->replay->ticks);
}

void pg_mouse_move(pg *p, double x, double y)
{
    update_camera(p); /* the view the mouse points into */
    p->mx = x, p->my = y;
    p->mouse_seen = true;
    if (p->drag == PG_MOUSE_TIMELINE) {
        seek(p, timeline_tick(p, x));
        return;
    }
    if (p->drag == PG_MOUSE_MIDDLE || p->drag == PG_MOUSE_PAN) {
        double dx = x - p->press_x, dy = y - p->press_y;
        if (fabs(dx) > 3 || fabs(dy) > 3) p->moved = true;
        set_pan_from(p, p->grab_cam, -dx / p->zoom, -dy / p->zoom);
        update_camera(p);
        return;
    }
    if (p->drag == PG_MOUSE_RIGHT && !p->rect && p->stroke && p->game && !p->recording && pg__in_view(p, x, y)) paint_to(p, x, y);
}

void pg_mouse_button(pg *p, int button, bool down, double x, double y)
{
    update_camera(p);
    p->mx = x, p->my = y;
    p->mouse_seen = true;
    if (down && button == PG_MOUSE_LEFT && p->panel_w > 0 && x >= p->panel_x && x < p->panel_x + p->panel_w) {
        for (int i = 0; i < p->widget_n; i++) {
            const struct pg_widget *wg = &p->widgets[i];
            if (x >= wg->x0 && x < wg->x1 && y >= wg->y0 && y < wg->y1) {
                pg_command(p, (pg_cmd)wg->cmd, wg->arg);
                break;
            }
        }
        return;
    }
    if (down && button == PG_MOUSE_LEFT && in_timeline(p, x, y)) {
        p->drag = PG_MOUSE_TIMELINE;
        seek(p, timeline_tick(p, x));
        return;
    }
    if (!down && p->drag == PG_MOUSE_TIMELINE && button == PG_MOUSE_LEFT) {
        p->drag = 0;
        return;
    }
    int t = strip_tile_at(p, x, y);
    if (down && t >= 0) {
        p->tile = t;
        return;
    }
    if (!down) {
        if (button == PG_MOUSE_LEFT && p->drag == PG_MOUSE_LEFT && p->moving) {
            pg_vec w = pg__to_world(p, x, y);
            move_object(p, w.x - p->moving_from.x, w.y - p->moving_from.y);
            p->moving = 0;
        } else if (button == PG_MOUSE_LEFT && p->drag == PG_MOUSE_LEFT && p->joint) {
            p->joint = false;
        } else if (button == PG_MOUSE_LEFT && p->drag == PG_MOUSE_LEFT && p->game && !p->recording &&
                   !p->press_selected) {
            throw_body(p, p->drag_from, pg__to_world(p, x, y));
        }
        if (button == PG_MOUSE_MIDDLE && p->drag == PG_MOUSE_MIDDLE && !p->moved && p->game && mouse_tools_allowed(p))
            delete_at(p, p->press_x, p->press_y); /* a click, not a pan */
        if (button == PG_MOUSE_RIGHT && p->drag == PG_MOUSE_RIGHT) {
            if (p->rect) fill_rect_to(p, x, y);
            else if (p->stroke) edit_end(p);
            p->rect = false;
        }
        if (button == p->drag) p->drag = 0;
        return;
    }
    if (!pg__in_view(p, x, y)) return;
    if (button == PG_MOUSE_MIDDLE || button == PG_MOUSE_PAN) { /* pan (a middle click deletes on release) */
        p->drag = button;
        p->grab_cam = p->cam;
        p->press_x = x, p->press_y = y;
        p->moved = false;
        return;
    }
    if (!mouse_tools_allowed(p)) return;
    if (button == PG_MOUSE_LEFT && p->tool != PG_TOOL_THROW) {
        pg_vec w = pg__to_world(p, x, y);
        int idx = 0, k = p->tool == PG_TOOL_ONE_WAY || p->tool == PG_TOOL_MATERIAL ? 0 : object_at(p, w, &idx);
        if (k) { /* grab it: moved where the button is released */
            p->drag = PG_MOUSE_LEFT;
            p->moving = k;
            p->moving_index = idx;
            p->moving_from = w;
        } else {
            place_object(p, w);
        }
        return;
    }
    if (button == PG_MOUSE_LEFT) {
        nt_body_id b = body_at(p, x, y);
        if (!nt_body_id_is_null(b)) { /* select it; a dynamic body follows the mouse on a spring */
            p->selected = b;
            p->press_selected = true;
            p->joint = nt_body_get_type(nt_game_get_world(p->game), b) == NT_BODY_DYNAMIC;
            p->drag = PG_MOUSE_LEFT;
            p->drag_from = pg__to_world(p, x, y);
            return;
        }
        p->press_selected = false;
        p->drag = PG_MOUSE_LEFT;
        p->drag_from = pg__to_world(p, x, y);
    } else if (button == PG_MOUSE_RIGHT) {
        int cx, cy;
        cell_at(p, x, y, &cx, &cy);
        if (p->mods & PG_MOD_ALT) { /* eyedropper */
            if (cx >= 0 && cy >= 0 && cx < p->level->width && cy < p->level->height) {
                p->tile = p->level->tiles[(size_t)cy * (size_t)p->level->width + (size_t)cx];
                const nt_tile_info *ti = nt_tile_get_info(p->tile);
                say(p, "picked %s from cell (%d, %d)", ti ? ti->name : "?", cx, cy);
            }
            return;
        }
        p->drag = PG_MOUSE_RIGHT;
        p->rect = (p->mods & PG_MOD_CTRL) != 0;
        if (p->rect) {
            p->rect_x = cx, p->rect_y = cy;
            return;
        }
        if (!edit_begin(p, (p->mods & PG_MOD_SHIFT) ? "erase" : "paint")) return;
        p->stroke = true;
        p->paint_x = INT_MIN;
        paint_to(p, x, y);
    }
}

/* The wheel zooms at the cursor (at the view's centre when the cursor is elsewhere). */
void pg_mouse_wheel(pg *p, double dy)
{
    if (dy == 0) return;
    double f = dy > 0 ? 1.25 : 0.8;
    if (p->mouse_seen && pg__in_view(p, p->mx, p->my)) zoom_at(p, f, p->mx, p->my);
    else zoom_at(p, f, p->view_x + p->view_w / 2.0, p->view_h / 2.0);
}

/* ---------------------------------------------------------------- replays */

/* Parse a replay file and the path of its level (relative to the replay, normalised). */
static int read_replay(const char *path, nt_replay **out, char *level, size_t lcap, char *why, size_t cap)
{
    char *text;
    size_t len;
    nt_text_error e;
    *out = NULL;
    if (!read_file(path, &text, &len, why, cap)) return 0;
    nt_status s = nt_replay_parse(path, text, len, out, &e);
    free(text);
    if (s != NT_OK) {
        snprintf(why, cap, "%s", e.message);
        return 0;
    }
    char dir[PG_PATH_MAX];
    dir_name(path, dir, sizeof dir);
    int fits = (*out)->level[0] == '/' ? join(level, lcap, (*out)->level, "", "") : join(level, lcap, dir, "/", (*out)->level);
    if (!fits) {
        snprintf(why, cap, "%s: the level path is too long", path);
        nt_replay_destroy(*out);
        *out = NULL;
        return 0;
    }
    normalise_path(level);
    return 1;
}

/* Play p->replay's inputs (its seed, friction model and tick) from now on. */
static void use_replay(pg *p, const char *path)
{
    snprintf(p->replay_path, sizeof p->replay_path, "%s", path);
    normalise_path(p->replay_path);
    p->gdef.override_seed = p->replay->has_seed;
    p->gdef.seed = p->replay->seed;
    p->gdef.override_friction_model = p->replay->has_friction_model;
    p->gdef.friction_model = p->replay->friction_model;
    p->dt = p->replay->dt;
    p->replay_on = true;
    p->divergence_known = false;
}

/* The index of `path` in the level list, added when it is not there (or -1). */
static int level_slot(pg *p, const char *path)
{
    for (int i = 0; i < p->level_count; i++)
        if (same_file(p->levels[i], path)) return i;
    if (p->level_count >= PG_MAX_LEVELS) return -1;
    char *d = strdup(path);
    if (!d) return -1;
    p->levels[p->level_count] = d;
    return p->level_count++;
}

/* Open a level (.ntl) or a replay (.ntr with its level), e.g. dropped on the window. */
static void open_file(pg *p, const char *path)
{
    char why[1200], level[PG_PATH_MAX];
    if (ends_with(path, ".ntr")) {
        nt_replay *rp;
        if (!read_replay(path, &rp, level, sizeof level, why, sizeof why)) {
            say(p, "%s", why);
            return;
        }
        nt_replay *old = p->replay;
        nt_game_def saved = p->gdef;
        nt_real dt = p->dt;
        bool was_on = p->replay_on;
        char old_path[PG_PATH_MAX];
        snprintf(old_path, sizeof old_path, "%s", p->replay_path);
        record_stop(p);
        p->replay = rp;
        p->gdef = nt_default_game_def();
        use_replay(p, path);
        if (!load_level(p, level, why, sizeof why)) {
            nt_replay_destroy(rp);
            p->replay = old, p->gdef = saved, p->dt = dt, p->replay_on = was_on;
            snprintf(p->replay_path, sizeof p->replay_path, "%s", old_path);
            say(p, "%s", why);
            return;
        }
        nt_replay_destroy(old);
        int k = level_slot(p, level);
        if (k >= 0) p->level_index = k;
        say(p, "replay %s on %s", p->replay_path, level);
        return;
    }
    snprintf(level, sizeof level, "%s", path);
    normalise_path(level);
    int k = level_slot(p, level);
    if (k < 0) {
        say(p, "too many levels open");
        return;
    }
    switch_level(p, k);
}

/* Go to tick t of the replay: forward by playing its inputs, back by playing them
 * again from the start (the game is deterministic: the same state as a fresh run). */
static void seek(pg *p, int t)
{
    if (!p->replay_on || !p->game) {
        say(p, "the timeline is for replays (--replay FILE.ntr, or drop one on the window)");
        return;
    }
    if (p->recording) return;
    int end = p->replay->ticks;
    if (t < 0) t = 0;
    if (t > end) t = end;
    int now = nt_game_get_state(p->game).tick;
    if (t < now) {
        if (!rebuild(p)) return;
        now = 0;
    }
    if (t > now && now >= end) return; /* after the replay the keyboard has it: nothing to play back */
    while (now < t) {
        tick(p);
        int after = nt_game_get_state(p->game).tick;
        if (after == now) break; /* a failed step (said why) */
        now = after;
    }
    p->paused = true;
    p->acc = 0;
}

/* The first tick whose hash differs from the replay's recorded ones (nt_run_replay). */
static void jump_to_divergence(pg *p)
{
    if (!p->replay_on) {
        say(p, "no replay playing");
        return;
    }
    if (!p->divergence_known) {
        nt_run_report rep;
        if (nt_run_replay(p->replay, p->level, &rep) != NT_OK) {
            say(p, "cannot run the replay");
            return;
        }
        p->divergence = rep.first_divergence;
        p->divergence_known = true;
        nt_run_report_free(&rep);
    }
    if (p->divergence < 0) {
        say(p, "no divergence: this build gives every recorded hash of the replay");
        return;
    }
    seek(p, p->divergence);
    say(p, "tick %d: the first whose state differs from the recorded hashes", p->divergence);
}

/* ---------------------------------------------------------------- create / destroy */

static nt_status make_palette(nt_world **out)
{
    nt_world_def wd = nt_default_world_def();
    wd.map.width = 2 * PG_STRIP_COLS + 1;
    wd.map.height = 2 * PG_STRIP_ROWS + 1;
    wd.map.cell_size = 24;
    nt_status s = nt_world_create(&wd, out);
    for (int id = 0; s == NT_OK && id < NT_TILE_COUNT; id++)
        s = nt_world_set_tile(*out, 1 + 2 * (id % PG_STRIP_COLS), 1 + 2 * (id / PG_STRIP_COLS), id);
    return s;
}

pg *pg_create(const pg_options *opt, char *why, size_t cap)
{
    pg *p = calloc(1, sizeof *p);
    if (!p) {
        snprintf(why, cap, "out of memory");
        return NULL;
    }
    p->opt = *opt;
    p->slow = 1;
    p->proj_scale = 10;
    p->gizmos = opt->gizmos;
    p->throw_circle = true;
    p->tile = NT_TILE_FULL;
    p->win_w = 1024, p->win_h = 640;
    p->gdef = nt_default_game_def();
    p->paint_x = INT_MIN;
    p->confirm_cmd = -1;
    p->material = 1;
    snprintf(p->save_dir, sizeof p->save_dir, "%s", opt->save_dir ? opt->save_dir : ".");
    nt_replay *tmp;
    if (nt_replay_create(1, &tmp) != NT_OK) {
        snprintf(why, cap, "out of memory");
        free(p);
        return NULL;
    }
    p->dt = p->dt_default = tmp->dt; /* the replay format's default tick: 1/40 s */
    nt_world_def wdef = nt_default_world_def();
    p->vel_iters = wdef.velocity_iterations;
    p->pos_iters = wdef.position_iterations;
    nt_replay_destroy(tmp);
    if (!is_dir(p->save_dir)) {
        snprintf(why, cap, "--save-dir '%s' is not a directory", p->save_dir);
        free(p);
        return NULL;
    }
    if (make_palette(&p->palette) != NT_OK) {
        snprintf(why, cap, "out of memory");
        pg_destroy(p);
        return NULL;
    }

    /* The level to start with: the replay's, the one given, or levels/ninja.ntl. */
    char first[PG_PATH_MAX];
    if (opt->replay_path) {
        if (!read_replay(opt->replay_path, &p->replay, first, sizeof first, why, cap)) {
            pg_destroy(p);
            return NULL;
        }
        use_replay(p, opt->replay_path);
    }
    pg_options o2 = *opt;
    char named[PG_PATH_MAX];
    if (opt->replay_path) o2.level_path = first;
    else if (opt->level_path) o2.level_path = levels_find(opt->level_path, named, sizeof named); /* or an installed level */
    char lvdir[PG_PATH_MAX];
    find_levels_dir(&o2, lvdir, sizeof lvdir);
    if (!opt->replay_path) {
        if (opt->level_path) {
            if (!join(first, sizeof first, o2.level_path, "", "")) {
                snprintf(why, cap, "the level path is too long");
                pg_destroy(p);
                return NULL;
            }
        } else if (lvdir[0] && join(first, sizeof first, lvdir, "/ninja.ntl", "")) {
        } else {
            snprintf(why, cap, "no level given and no levels/ directory found (run from the ntile directory, or pass LEVEL or --levels DIR)");
            pg_destroy(p);
            return NULL;
        }
    }
    int start = -1;
    for (int i = 0; lvdir[0] && i < SHIPPED_COUNT; i++) {
        char path[PG_PATH_MAX + 64], name[32];
        snprintf(name, sizeof name, "/%s.ntl", shipped[i]);
        if (!join(path, sizeof path, lvdir, name, "") || !file_exists(path)) continue;
        bool is_first = start < 0 && same_file(path, first);
        if (is_first) start = p->level_count;
        p->levels[p->level_count] = strdup(is_first ? first : path);
        p->level_count++;
    }
    if (start < 0) {
        start = p->level_count;
        p->levels[p->level_count++] = strdup(first);
    }
    for (int i = 0; i < p->level_count; i++)
        if (!p->levels[i]) {
            snprintf(why, cap, "out of memory");
            pg_destroy(p);
            return NULL;
        }
    p->level_index = start;
    if (!load_level(p, first, why, cap)) {
        pg_destroy(p);
        return NULL;
    }
    update_view_fit(p);
    return p;
}

void pg_destroy(pg *p)
{
    if (!p) return;
    nt_game_destroy(p->game);
    nt_level_destroy(p->level);
    nt_replay_destroy(p->replay);
    nt_world_destroy(p->palette);
    for (int i = 0; i < p->level_count; i++) free(p->levels[i]);
    free(p->rec_keys);
    free(p->rec_trace);
    free(p->prev);
    free(p->prev_gen);
    free(p->kind);
    free(p->kind_gen);
    history_clear(p);
    free(p->edits);
    free(p->open_path);
    free(p->pairs);
    free(p);
}

void pg_summary(const pg *p, char *out, size_t cap)
{
    nt_game_state st = nt_game_get_state(p->game);
    nt_world *w = nt_game_get_world(p->game);
    int n = snprintf(out, cap, "tick %d  bodies %d (awake %d)  score %d", st.tick, w ? nt_world_get_body_count(w) : 0,
                     w ? nt_world_get_awake_count(w) : 0, st.score);
    if (n > 0 && (size_t)n < cap && st.has_player)
        n += snprintf(out + n, cap - (size_t)n, "  player %s", st.complete ? "complete" : st.alive ? "alive" : "dead");
    if (n > 0 && (size_t)n < cap)
        n += snprintf(out + n, cap - (size_t)n, "  level %s%s", p->level_path, p->dirty ? " (edited)" : "");
    if (n > 0 && (size_t)n < cap && p->replay_on) {
        if (st.tick < p->replay->ticks)
            n += snprintf(out + n, cap - (size_t)n, "  replay %s tick %d of %d", p->replay_path, st.tick, p->replay->ticks);
        else
            n += snprintf(out + n, cap - (size_t)n, "  replay %s over (%d ticks): you have control", p->replay_path,
                          p->replay->ticks);
    }
    if (n > 0 && (size_t)n < cap && p->confirm_cmd >= 0)
        n += snprintf(out + n, cap - (size_t)n, "  asking: discard the edits and %s?", action_name(p->confirm_cmd));
    if (n > 0 && (size_t)n < cap && p->lab && p->has_collision)
        n += snprintf(out + n, cap - (size_t)n,
                 "  last collision tick %d: momentum (%.2f, %.2f) -> (%.2f, %.2f), kinetic energy %.1f -> %.1f",
                 p->coll_tick, p->px_before, p->py_before, p->px_after, p->py_after, p->ke_before, p->ke_after);
    if (n > 0 && (size_t)n < cap && w) {
        int vi, pi;
        nt_world_get_iterations(w, &vi, &pi);
        n += snprintf(out + n, cap - (size_t)n, "  iterations %d %d", vi, pi);
    }
    char ins[400];
    pg__inspect_body(p, ins, sizeof ins);
    if (n > 0 && (size_t)n < cap && ins[0]) n += snprintf(out + n, cap - (size_t)n, "  selected %s", ins);
    pg__inspect_cell(p, ins, sizeof ins);
    if (n > 0 && (size_t)n < cap && ins[0]) n += snprintf(out + n, cap - (size_t)n, "  under the mouse %s", ins);
}

const char *pg_message(const pg *p) { return p->clock < p->msg_until ? p->msg : ""; }

void pg_open(pg *p, const char *path)
{
    char *d = strdup(path);
    if (!d) return;
    free(p->open_path);
    p->open_path = d;
    pg_command(p, PG_CMD_OPEN, 0);
}

void pg_title(const pg *p, char *out, size_t cap)
{
    snprintf(out, cap, "ntile-play: %.100s (%.300s)%s", p->level->title[0] ? p->level->title : "untitled", p->level_path,
             p->dirty ? " *" : "");
}
nt_game *pg_game(const pg *p) { return p->game; }
int pg_tick_count(const pg *p) { return p->game ? nt_game_get_state(p->game).tick : 0; }

void pg__prepare_view(pg *p) { update_camera(p); }
