/* N v1.4 level strings -> nt_level.
 *
 * A level is one line: $NAME#AUTHOR##TILES|OBJECTS#. TILES is 713 characters,
 * '0' + tile id, for the 31 x 23 playable cells stored column by column (column 0
 * rows 0..22, then column 1, ...). OBJECTS is a '!'-separated list of TYPE^A,B,...
 * with coordinates in pixels of the whole 33 x 25 grid (border included), which is
 * exactly the world space of the imported level (cell 24).
 *
 * Object mapping (N's numeric types):
 *   0 gold           static sensor circle r 6, score 1
 *   1 bounce block   dynamic box 9.6 x 9.6
 *   2 launch pad     (x, y, nx, ny): the tile behind the pad gets material 1 (bounce 1)
 *   5 player spawn   the level's player
 *   7 one-way        (x, y, dir): dir 3 (facing up, N's 0 right 1 down 2 left 3 up) ->
 *                    a HALFu tile with the one-way flag; the other directions -> a
 *                    static box over the half of the cell on that side, a one-way
 *                    body of the game layer (nt_level_body.one_way)
 *   9 door           (sx, sy, trap, locked, cx, cy, vertical, ox, oy): a static box a
 *                    cell long and a quarter cell thick through the centre of cell
 *                    (cx + ox, cy + oy) of the 33 x 25 grid, upright when `vertical` is
 *                    1. A locked door (locked 1) is solid until its switch (region
 *                    "doorswitchN", one cell around sx, sy) is on; a trap door (trap 1)
 *                    closes when it is on; a plain door opens at the player's touch
 *  11 exit door      (x, y, sx, sy): a switch region "exitswitch" (one cell around sx, sy)
 *                    and region "exit" (one cell around the door) that needs it: the
 *                    exit opens only after its switch
 *  12 mine           static sensor circle r 4, deadly
 * Anything else (3 gauss turret, 4 floor guard, 6 drone, 8 thwump, 10 rocket launcher)
 * is skipped with a warning that names it. */
#include <stdio.h>
#include <string.h>
#include "text.h"

#define N14_COLS 31
#define N14_ROWS 23
#define N14_TILES (N14_COLS * N14_ROWS)
#define N14_CELL 24

typedef struct importer {
    nt__text t;
    nt_level *lv;
    nt_warning_fn *warn;
    void *ctx;
    int counts[16]; /* names: gold1, gold2, ... */
} importer;

/* N's names of its object types, for warnings. */
static const char *object_name(long long type)
{
    static const char *const names[] = {"gold",       "bounce block", "launch pad",      "gauss turret", "floor guard",
                                        "player spawn", "drone",       "one-way platform", "thwump",       "door",
                                        "rocket launcher", "exit door", "mine"};
    return type >= 0 && type < (long long)(sizeof names / sizeof names[0]) ? names[type] : NULL;
}

static void warn_at(importer *im, int col, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

static void warn_at(importer *im, int col, const char *fmt, ...)
{
    if (!im->warn) return;
    nt_text_error e;
    va_list ap;
    va_start(ap, fmt);
    nt__error_set(&e, im->t.name, im->t.line, col, fmt, ap);
    va_end(ap);
    /* nt__error_set writes "NAME:LINE:COL: text"; warnings say so. */
    char msg[600];
    const char *tail = e.message;
    size_t prefix = 0;
    for (int colons = 0; tail[prefix] && colons < 3; prefix++)
        if (tail[prefix] == ':') colons++;
    snprintf(msg, sizeof msg, "%.*s warning:%s", (int)prefix, e.message, e.message + prefix);
    im->warn(msg, im->ctx);
}

/* Copy N text into a level title: quotes, backslashes and control bytes become '_'. */
static void clean_text(char *dst, const char *s, size_t n)
{
    if (n >= NT_LEVEL_TEXT_MAX) n = NT_LEVEL_TEXT_MAX - 1;
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        dst[i] = (c < 0x20 || c == 0x7f || c == '"' || c == '\\') ? '_' : (char)c;
    }
    dst[n] = '\0';
}

static nt_status add_body(importer *im, const char *prefix, int kind, nt_level_body *b, int col)
{
    snprintf(b->name, sizeof b->name, "%s%d", prefix, ++im->counts[kind]);
    nt_text_error e;
    nt_status s = nt_level_add_body(im->lv, b, NULL, &e);
    if (s == NT_ERR_OUT_OF_MEMORY) return s;
    if (s != NT_OK) return nt__fail_col(&im->t, col, "cannot add %s", e.message);
    return NT_OK;
}

/* A one-cell region around c named base (base2, base3, ... after the first; numbered from
 * the first when `numbered`); needs: 1 + the switch region an exit needs, or 0. */
static nt_status add_region(importer *im, const char *base, nt_region_kind kind, nt_vec2 c, int *counter, int col,
                            int numbered, int needs)
{
    nt_level_region r;
    memset(&r, 0, sizeof r);
    ++*counter;
    if (*counter == 1 && !numbered) snprintf(r.name, sizeof r.name, "%s", base);
    else snprintf(r.name, sizeof r.name, "%s%d", base, *counter);
    r.kind = kind;
    r.needs = needs;
    r.lo = nt_v2(c.x - N14_CELL / 2, c.y - N14_CELL / 2);
    r.hi = nt_v2(c.x + N14_CELL / 2, c.y + N14_CELL / 2);
    nt_text_error e;
    nt_status s = nt_level_add_region(im->lv, &r, &e);
    if (s == NT_ERR_OUT_OF_MEMORY) return s;
    if (s != NT_OK) return nt__fail_col(&im->t, col, "cannot add %s", e.message);
    return NT_OK;
}

static int cell_of(nt_real v) { return nt__floor_int(v / N14_CELL); } /* clamped: coordinates may be huge */

static int in_map(const nt_level *lv, int x, int y) { return x >= 0 && y >= 0 && x < lv->width && y < lv->height; }

/* One object TYPE^A,B,... at s[0..n) (column col). */
static nt_status import_object(importer *im, const char *s, size_t n, int col)
{
    nt__text *t = &im->t;
    nt_level *lv = im->lv;
    char q[NT__QUOTE_MAX];
    const char *caret = memchr(s, '^', n);
    if (!caret) return nt__fail_col(t, col, "object '%s' has no '^' (expected TYPE^X,Y,...)", nt__quote(q, s, n));
    nt__field f;
    f.s = s;
    f.n = (size_t)(caret - s);
    f.col = col;
    long long type;
    nt_status st = nt__field_int(t, &f, "object type", 0, 1000, &type);
    if (st != NT_OK) return st;
    nt_real v[16];
    int nv = 0;
    const char *p = caret + 1, *end = s + n;
    for (;;) {
        const char *comma = memchr(p, ',', (size_t)(end - p));
        const char *stop = comma ? comma : end;
        if (nv == 16) return nt__fail_col(t, col + (int)(p - s), "too many values in one object (at most 16)");
        f.s = p;
        f.n = (size_t)(stop - p);
        f.col = col + (int)(p - s);
        if ((st = nt__field_real(t, &f, "object value", &v[nv])) != NT_OK) return st;
        nv++;
        if (!comma) break;
        p = comma + 1;
    }
    static const int need[13] = {2, 2, 4, -1, -1, 2, -1, 3, -1, 9, -1, 4, 2};
    int known = type < 13 && need[type] > 0;
    if (!known) {
        if (object_name(type)) warn_at(im, col, "N object type %lld (%s) is not supported; skipped", type, object_name(type));
        else warn_at(im, col, "N object type %lld is not an N object; skipped", type);
        return NT_OK;
    }
    if (nv < need[type])
        return nt__fail_col(t, col, "object type %lld (%s) needs %d values, got %d", type, object_name(type), need[type], nv);
    nt_vec2 pos = nt_v2(v[0], v[1]);
    /* N places every object inside its 33 x 25 playfield: one outside is a broken
     * level, and could not be built as a world (nothing may sit that far out). */
    if (!(pos.x >= 0 && pos.y >= 0 && pos.x <= (nt_real)lv->width * N14_CELL && pos.y <= (nt_real)lv->height * N14_CELL)) {
        warn_at(im, col, "%s at %g,%g lies outside the level; skipped", object_name(type), (double)pos.x, (double)pos.y);
        return NT_OK;
    }
    nt_level_body b = nt_level_default_body(lv);
    b.position = pos;
    switch (type) {
    case 0: /* gold */
        b.type = NT_BODY_STATIC;
        b.shape = nt_shape_circle(6);
        b.is_sensor = true;
        b.score = 1;
        return add_body(im, "gold", 0, &b, col);
    case 1: /* bounce block */
        b.type = NT_BODY_DYNAMIC;
        b.shape = nt_shape_aabb((nt_real)9.6, (nt_real)9.6);
        return add_body(im, "block", 1, &b, col);
    case 2: { /* launch pad: the cell behind the pad, against its normal */
        nt_real nx = v[2], ny = v[3];
        int cx = cell_of(pos.x - nx * 6), cy = cell_of(pos.y - ny * 6);
        if (!in_map(lv, cx, cy) || lv->tiles[(size_t)cy * (size_t)lv->width + (size_t)cx] == NT_TILE_EMPTY) {
            warn_at(im, col, "launch pad at %g,%g has no tile behind it; skipped", (double)pos.x, (double)pos.y);
            return NT_OK;
        }
        lv->cell_materials[(size_t)cy * (size_t)lv->width + (size_t)cx] = 1;
        return NT_OK;
    }
    case 5: /* player */
        if (lv->has_player) {
            warn_at(im, col, "a second player spawn at %g,%g; skipped", (double)pos.x, (double)pos.y);
            return NT_OK;
        }
        lv->has_player = true;
        lv->player = pos;
        return NT_OK;
    case 7: { /* one-way platform */
        static const char *const dirs[4] = {"right", "down", "left", "up"};
        int dir = v[2] >= 0 && v[2] <= 3 ? (int)v[2] : -1; /* range first: the cast of a huge value is undefined */
        if ((nt_real)dir != v[2] || dir < 0 || dir > 3) {
            warn_at(im, col, "one-way platform with direction %g (expected 0..3); skipped", (double)v[2]);
            return NT_OK;
        }
        int cx = cell_of(pos.x), cy = cell_of(pos.y);
        size_t k = (size_t)cy * (size_t)lv->width + (size_t)cx;
        if (!in_map(lv, cx, cy) || lv->tiles[k] != NT_TILE_EMPTY) {
            warn_at(im, col, "one-way platform facing %s at %g,%g is not in an empty cell; skipped", dirs[dir],
                    (double)pos.x, (double)pos.y);
            return NT_OK;
        }
        if (dir != 3) { /* the half of the cell on its side: a one-way body of the game layer */
            static const nt_one_way_side sides[3] = {NT_ONE_WAY_RIGHT, NT_ONE_WAY_DOWN, NT_ONE_WAY_LEFT};
            static const int ox[3] = {18, 12, 6}, oy[3] = {12, 18, 12};
            b.type = NT_BODY_STATIC;
            b.position = nt_v2((nt_real)(cx * N14_CELL + ox[dir]), (nt_real)(cy * N14_CELL + oy[dir]));
            b.shape = dir == 1 ? nt_shape_aabb(N14_CELL / 2, N14_CELL / 4) : nt_shape_aabb(N14_CELL / 4, N14_CELL / 2);
            b.one_way = sides[dir];
            return add_body(im, "oneway", 7, &b, col);
        }
        lv->tiles[k] = NT_TILE_HALFu;
        lv->cell_flags[k] = NT_CELL_ONE_WAY;
        return NT_OK;
    }
    case 9: { /* door: the switch first (the door names it), then the door */
        int trap = v[2] != 0, locked = v[3] != 0;
        nt_real cx = v[4] + v[7], cy = v[5] + v[8];
        if (!(cx >= 0 && cy >= 0 && cx < (nt_real)lv->width && cy < (nt_real)lv->height) || cx != (nt_real)(int)cx ||
            cy != (nt_real)(int)cy) {
            warn_at(im, col, "door in cell %g,%g lies outside the level; skipped", (double)cx, (double)cy);
            return NT_OK;
        }
        if (trap && locked) {
            warn_at(im, col, "door at cell %g,%g is both a trap door and a locked door; skipped", (double)cx, (double)cy);
            return NT_OK;
        }
        b.type = NT_BODY_STATIC;
        b.position = nt_v2(cx * N14_CELL + N14_CELL / 2, cy * N14_CELL + N14_CELL / 2);
        b.shape = v[6] != 0 ? nt_shape_aabb(3, N14_CELL / 2) : nt_shape_aabb(N14_CELL / 2, 3);
        b.door = trap ? NT_DOOR_TRAP : locked ? NT_DOOR_LOCKED : NT_DOOR_PLAIN;
        if (trap || locked) {
            st = add_region(im, "doorswitch", NT_REGION_SWITCH, pos, &im->counts[14], col, 1, 0);
            if (st != NT_OK) return st;
            b.door_switch = lv->region_count; /* 1 + the switch's index */
        }
        return add_body(im, trap ? "trapdoor" : locked ? "lockeddoor" : "door", trap ? 15 : locked ? 10 : 9, &b, col);
    }
    case 11: { /* exit door and its switch: the switch first, the exit needs it */
        st = add_region(im, "exitswitch", NT_REGION_SWITCH, nt_v2(v[2], v[3]), &im->counts[13], col, 0, 0);
        if (st != NT_OK) return st;
        return add_region(im, "exit", NT_REGION_EXIT, pos, &im->counts[11], col, 0, lv->region_count);
    }
    case 12: /* mine */
        b.type = NT_BODY_STATIC;
        b.shape = nt_shape_circle(4);
        b.is_sensor = true;
        b.deadly = true;
        return add_body(im, "mine", 12, &b, col);
    }
    return NT_OK;
}

static nt_status import_line(importer *im)
{
    nt__text *t = &im->t;
    nt_level *lv = im->lv;
    const char *s = t->ls;
    size_t n = t->ll;
    while (n > 0 && (s[n - 1] == ' ' || s[n - 1] == '\t')) n--;
    if (n == 0 || s[0] != '$') return nt__fail_col(t, 1, "an N level starts with '$' ($NAME#AUTHOR##TILES|OBJECTS#)");
    const char *h1 = memchr(s + 1, '#', n - 1);
    if (!h1) return nt__fail_col(t, (int)n + 1, "missing '#' after the level name");
    const char *h2 = memchr(h1 + 1, '#', n - (size_t)(h1 + 1 - s));
    if (!h2) return nt__fail_col(t, (int)n + 1, "missing '#' after the author");
    if ((size_t)(h2 + 1 - s) >= n || h2[1] != '#')
        return nt__fail_col(t, (int)(h2 - s) + 2, "expected '##' before the tiles");
    const char *tiles = h2 + 2;
    const char *bar = memchr(tiles, '|', n - (size_t)(tiles - s));
    if (!bar) return nt__fail_col(t, (int)n + 1, "missing '|' after the %d tile characters", N14_TILES);
    size_t nt = (size_t)(bar - tiles);
    if (nt != N14_TILES)
        return nt__fail_col(t, (int)(bar - s) + 1, "the tiles have %zu characters, expected %d (31 x 23)", nt, N14_TILES);
    if (s[n - 1] != '#' || n - 1 < (size_t)(bar - s) + 1)
        return nt__fail_col(t, (int)n + 1, "missing the closing '#' after the objects");
    clean_text(lv->title, s + 1, (size_t)(h1 - s - 1));
    clean_text(lv->author, h1 + 1, (size_t)(h2 - h1 - 1));
    for (int k = 0; k < N14_TILES; k++) {
        int id = tiles[k] - '0';
        if (id < 0 || id >= NT_TILE_COUNT) {
            char q[NT__QUOTE_MAX];
            return nt__fail_col(t, (int)(tiles - s) + k + 1, "unknown N tile character '%s' (expected '0'..'Q')",
                                nt__quote(q, tiles + k, 1));
        }
        int x = k / N14_ROWS + 1, y = k % N14_ROWS + 1;
        lv->tiles[(size_t)y * (size_t)lv->width + (size_t)x] = (uint8_t)id;
    }
    const char *obj = bar + 1, *oend = s + n - 1;
    while (obj < oend) {
        const char *bang = memchr(obj, '!', (size_t)(oend - obj));
        const char *stop = bang ? bang : oend;
        if (stop > obj) {
            nt_status st = import_object(im, obj, (size_t)(stop - obj), (int)(obj - s) + 1);
            if (st != NT_OK) return st;
        }
        obj = stop + 1;
    }
    return NT_OK;
}

static int blank_line(const nt__text *t)
{
    for (size_t i = 0; i < t->ll; i++)
        if (t->ls[i] != ' ' && t->ls[i] != '\t' && t->ls[i] != '\r') return 0;
    return 1;
}

nt_status nt_level_import_n14(const char *name, const char *text, size_t length, int index, nt_level **out, int *count,
                              nt_text_error *err, nt_warning_fn *warn, void *context)
{
    if (out) *out = NULL;
    if (count) *count = 0;
    if (!out || (!text && length > 0) || index < 0)
        return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "nt_level_import_n14: bad argument");
    importer *im = (importer *)nt__alloc(sizeof *im);
    if (!im) return nt__error_plain(err, NT_ERR_OUT_OF_MEMORY, "%s: out of memory", name ? name : "(text)");
    memset(im, 0, sizeof *im);
    nt__text_init(&im->t, name, text, length, err);
    im->warn = warn;
    im->ctx = context;
    nt_status s = NT_OK;
    int levels = 0, found = 0;
    for (;;) {
        int r = nt__text_next_line(&im->t);
        if (r < 0) {
            s = NT_ERR_PARSE;
            break;
        }
        if (r == 0) break;
        if (blank_line(&im->t)) continue;
        if (levels++ != index || found) continue;
        found = 1;
        s = nt_level_create(N14_COLS + 2, N14_ROWS + 2, N14_CELL, &im->lv);
        if (s != NT_OK) break;
        nt_level *lv = im->lv;
        for (int y = 0; y < lv->height; y++)
            for (int x = 0; x < lv->width; x++)
                if (x == 0 || y == 0 || x == lv->width - 1 || y == lv->height - 1)
                    lv->tiles[(size_t)y * (size_t)lv->width + (size_t)x] = NT_TILE_FULL;
        lv->materials[1].friction = lv->materials[0].friction;
        lv->materials[1].bounce = 1; /* launch pads */
        s = import_line(im);
        if (s != NT_OK) break;
    }
    if (s == NT_OK && !found) {
        int line, col;
        nt__text_eof_pos(&im->t, &line, &col);
        if (levels == 0) s = nt__fail(&im->t, line, col, "no N level in the text");
        else s = nt__fail(&im->t, line, col, "level %d asked for, but the text holds %d level%s", index + 1, levels,
                          levels == 1 ? "" : "s");
    }
    if (s == NT_ERR_OUT_OF_MEMORY) nt__error_plain(err, s, "%s: out of memory", im->t.name);
    if (count) *count = levels;
    if (s != NT_OK) {
        nt_level_destroy(im->lv);
    } else {
        *out = im->lv;
    }
    nt__free(im);
    return s;
}
