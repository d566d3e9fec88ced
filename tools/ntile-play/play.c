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
    *out = NULL;
    *len = 0;
    FILE *f = stream_open_regular(path, STREAM_MAX_FILE, why, cap);
    if (!f) return 0;
    int r = stream_read_all(f, STREAM_MAX_FILE, out, len);
    fclose(f);
    if (r != STREAM_OK) {
        snprintf(why, cap, "cannot read '%s'%s", path, r == STREAM_NO_MEMORY ? ": out of memory or too large" : "");
        return 0;
    }
    return 1;
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

/* Write through a temporary sibling and rename: a failed write leaves the old file. */
static int write_file(const char *path, const char *data, size_t len, char *why, size_t cap)
{
    char tmp[PG_PATH_MAX + 32];
    char suffix[32];
    snprintf(suffix, sizeof suffix, ".tmp%ld", (long)getpid());
    if (!join(tmp, sizeof tmp, path, suffix, "")) {
        snprintf(why, cap, "cannot write '%.200s': the name is too long", path);
        return 0;
    }
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        snprintf(why, cap, "cannot write '%s': %s", path, strerror(errno));
        return 0;
    }
    int ok = fwrite(data, 1, len, f) == len;
    ok = fclose(f) == 0 && ok;
    if (ok && rename(tmp, path) != 0) ok = 0;
    if (!ok) {
        snprintf(why, cap, "cannot write '%s': %s", path, strerror(errno));
        remove(tmp);
    }
    return ok;
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
    /* Next to the given level, in ./levels, or next to the program (build/../levels). */
    const char *cands[3] = {NULL, "levels", NULL};
    char lvdir[PG_PATH_MAX], exedir[PG_PATH_MAX];
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
    for (int i = 0; i < 3; i++) {
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
    double px0 = 0, py0 = 0, ke0 = 0;
    if (p->lab) pg__mechanics(p, &px0, &py0, &ke0);
    /* A replay's inputs while it lasts; then the keyboard takes over. */
    uint32_t keys = p->replay_on && st0.tick < p->replay->ticks ? nt_replay_keys_at(p->replay, st0.tick + 1) : p->keys;
    double t0 = mono_seconds();
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

/* Without a player the arrows (WASD) pan the view: 600 pixels a second. */
static void pan(pg *p, double seconds)
{
    if (has_player(p) || !p->level || p->opt.has_center) return;
    double d = 600 * seconds / p->zoom;
    if (p->keys & NT_INPUT_LEFT) p->pan.x -= d;
    if (p->keys & NT_INPUT_RIGHT) p->pan.x += d;
    if (p->keys & NT_INPUT_UP) p->pan.y -= d;
    if (p->keys & NT_INPUT_DOWN) p->pan.y += d;
    double lw = p->level->width * (double)p->level->cell_size, lh = p->level->height * (double)p->level->cell_size;
    p->pan.x = fmin(fmax(p->pan.x, -lw / 2), lw / 2);
    p->pan.y = fmin(fmax(p->pan.y, -lh / 2), lh / 2);
}

/* Camera: the player (interpolated), kept inside the level when the level is larger
 * than the view; a level smaller than the view is centred. */
static void update_camera(pg *p)
{
    if (!p->level) return;
    double lw = p->level->width * (double)p->level->cell_size, lh = p->level->height * (double)p->level->cell_size;
    if (p->opt.has_center) {
        p->cam.x = p->opt.center_x;
        p->cam.y = p->opt.center_y;
        return;
    }
    pg_vec c = {lw / 2 + p->pan.x, lh / 2 + p->pan.y};
    if (has_player(p)) c = pg__player_pos(p, pg__alpha(p));
    double hw = p->view_w / p->zoom / 2, hh = p->view_h / p->zoom / 2;
    if (lw <= 2 * hw) c.x = lw / 2;
    else c.x = fmin(fmax(c.x, hw), lw - hw);
    if (lh <= 2 * hh) c.y = lh / 2;
    else c.y = fmin(fmax(c.y, hh), lh - hh);
    p->cam = c;
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
    p->dirty = true;
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
    p->dirty = true;
}

void pg_command(pg *p, pg_cmd cmd, int arg)
{
    switch (cmd) {
    case PG_CMD_RESTART:
        record_stop(p);
        if (rebuild(p)) say(p, "restarted");
        break;
    case PG_CMD_LEVEL: switch_level(p, arg); break;
    case PG_CMD_LEVEL_NEXT: switch_level(p, (p->level_index + 1) % p->level_count); break;
    case PG_CMD_LEVEL_PREV: switch_level(p, (p->level_index + p->level_count - 1) % p->level_count); break;
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
    case PG_CMD_SLEEP:
        if (p->replay_on) {
            say(p, "the replay fixes the world; switch level to play freely");
            break;
        }
        record_stop(p);
        p->level->sleep = !p->level->sleep;
        p->dirty = true;
        rebuild(p);
        say(p, "sleeping %s: the world was rebuilt from the level", p->level->sleep ? "on" : "off");
        break;
    case PG_CMD_ZOOM: {
        double f = arg > 0 ? 1.25 : arg < 0 ? 0.8 : 0;
        p->zoom = f > 0 ? p->zoom * f : p->zoom_fit;
        if (p->zoom < 0.1) p->zoom = 0.1;
        if (p->zoom > 16) p->zoom = 16;
        break;
    }
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

static void paint_cell(pg *p, int x, int y)
{
    nt_level *lv = p->level;
    if (x < 0 || y < 0 || x >= lv->width || y >= lv->height) return;
    size_t k = (size_t)y * (size_t)lv->width + (size_t)x;
    if (lv->tiles[k] == p->tile) return;
    if (nt_game_set_tile(p->game, x, y, p->tile) != NT_OK) return;
    lv->tiles[k] = (uint8_t)p->tile; /* keep the level model in sync: F2 writes it */
    p->dirty = true;
}

static void paint_to(pg *p, double sx, double sy)
{
    pg_vec w = pg__to_world(p, sx, sy);
    double cs = (double)p->level->cell_size;
    int x = (int)floor(w.x / cs), y = (int)floor(w.y / cs);
    /* Every cell on the way from the last painted one, so a fast drag leaves no gaps. */
    int x0 = p->paint_x, y0 = p->paint_y;
    if (x0 == INT_MIN) x0 = x, y0 = y;
    int n = abs(x - x0) > abs(y - y0) ? abs(x - x0) : abs(y - y0);
    if (n > 4096) n = 0, x0 = x, y0 = y;
    for (int i = 0; i <= n; i++) {
        int cx = n ? x0 + (int)lround((double)(x - x0) * i / n) : x;
        int cy = n ? y0 + (int)lround((double)(y - y0) * i / n) : y;
        paint_cell(p, cx, cy);
    }
    p->paint_x = x, p->paint_y = y;
}

static void throw_body(pg *p, pg_vec from, pg_vec to)
{
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

void pg_mouse_move(pg *p, double x, double y)
{
    update_camera(p); /* the view the mouse points into */
    p->mx = x, p->my = y;
    p->mouse_seen = true;
    if (p->drag == PG_MOUSE_RIGHT && p->game && !p->recording && pg__in_view(p, x, y)) paint_to(p, x, y);
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
    int t = strip_tile_at(p, x, y);
    if (down && t >= 0) {
        p->tile = t;
        return;
    }
    if (!down) {
        if (button == PG_MOUSE_LEFT && p->drag == PG_MOUSE_LEFT && p->game && !p->recording)
            throw_body(p, p->drag_from, pg__to_world(p, x, y));
        if (button == p->drag) p->drag = 0;
        return;
    }
    if (!pg__in_view(p, x, y)) return;
    if (!mouse_tools_allowed(p)) return;
    if (button == PG_MOUSE_LEFT) {
        p->drag = PG_MOUSE_LEFT;
        p->drag_from = pg__to_world(p, x, y);
    } else if (button == PG_MOUSE_RIGHT) {
        p->drag = PG_MOUSE_RIGHT;
        p->paint_x = INT_MIN;
        paint_to(p, x, y);
    } else if (button == PG_MOUSE_MIDDLE) {
        delete_at(p, x, y);
    }
}

void pg_mouse_wheel(pg *p, double dy)
{
    if (dy > 0) pg_command(p, PG_CMD_ZOOM, 1);
    else if (dy < 0) pg_command(p, PG_CMD_ZOOM, -1);
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
    snprintf(p->save_dir, sizeof p->save_dir, "%s", opt->save_dir ? opt->save_dir : ".");
    nt_replay *tmp;
    if (nt_replay_create(1, &tmp) != NT_OK) {
        snprintf(why, cap, "out of memory");
        free(p);
        return NULL;
    }
    p->dt = p->dt_default = tmp->dt; /* the replay format's default tick: 1/40 s */
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
        char *text;
        size_t len;
        nt_text_error e;
        if (!read_file(opt->replay_path, &text, &len, why, cap)) {
            pg_destroy(p);
            return NULL;
        }
        nt_status s = nt_replay_parse(opt->replay_path, text, len, &p->replay, &e);
        free(text);
        if (s != NT_OK) {
            snprintf(why, cap, "%s", e.message);
            pg_destroy(p);
            return NULL;
        }
        char dir[PG_PATH_MAX];
        dir_name(opt->replay_path, dir, sizeof dir);
        int fits = p->replay->level[0] == '/' ? join(first, sizeof first, p->replay->level, "", "")
                                               : join(first, sizeof first, dir, "/", p->replay->level);
        if (!fits) {
            snprintf(why, cap, "%s: the level path is too long", opt->replay_path);
            pg_destroy(p);
            return NULL;
        }
        snprintf(p->replay_path, sizeof p->replay_path, "%s", opt->replay_path);
        p->gdef.override_seed = p->replay->has_seed;
        p->gdef.seed = p->replay->seed;
        p->gdef.override_friction_model = p->replay->has_friction_model;
        p->gdef.friction_model = p->replay->friction_model;
        p->dt = p->replay->dt;
        p->replay_on = true;
    }
    pg_options o2 = *opt;
    if (opt->replay_path) o2.level_path = first;
    char lvdir[PG_PATH_MAX];
    find_levels_dir(&o2, lvdir, sizeof lvdir);
    if (!opt->replay_path) {
        if (opt->level_path) {
            if (!join(first, sizeof first, opt->level_path, "", "")) {
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
    if (n > 0 && (size_t)n < cap && p->lab && p->has_collision)
        snprintf(out + n, cap - (size_t)n,
                 "  last collision tick %d: momentum (%.2f, %.2f) -> (%.2f, %.2f), kinetic energy %.1f -> %.1f",
                 p->coll_tick, p->px_before, p->py_before, p->px_after, p->py_after, p->ke_before, p->ke_after);
}

const char *pg_message(const pg *p) { return p->clock < p->msg_until ? p->msg : ""; }
nt_game *pg_game(const pg *p) { return p->game; }
int pg_tick_count(const pg *p) { return p->game ? nt_game_get_state(p->game).tick : 0; }

void pg__prepare_view(pg *p) { update_camera(p); }
