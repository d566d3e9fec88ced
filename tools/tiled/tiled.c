/* Tiled maps -> nt_level: the builder, shared by both formats.
 *
 * json.c and xml.c turn a map into the model (internal.h); this file reads the
 * external tilesets, decodes tile layer data (CSV, base64 plain / zlib / gzip),
 * resolves tile ids and flips to N tiles, turns objects into bodies, regions,
 * paths and the player spawn, and checks the result. Everything one import
 * allocates lives in one arena, freed on every way out. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <zlib.h>
#include "internal.h"
#include "../common/stream.h"
#include "../common/tilename.h"

/* ---------------------------------------------------------------- flips */

/* N's tiles come in families of four orientations (suffix pn, nn, np, pp: signs of
 * the surface normal, y down), in that order: ids 2-5 45°, 6-9 concave, 10-13
 * convex, 14-17 22° small, 18-21 22° big, 22-25 67° small, 26-29 67° big. A
 * horizontal flip negates the normal's x, a vertical flip its y, and the diagonal
 * flip (the transpose x <-> y) swaps them, which turns a 22° slope into the 67°
 * slope of the same size class. HALF tiles (d, r, u, l: the solid's side) flip
 * among themselves. tests/test_tiled.c checks every case against the geometry. */
static int flip_h(int t)
{
    if (t >= 2 && t <= 29) return 2 + (t - 2) / 4 * 4 + "\1\0\3\2"[(t - 2) % 4];
    if (t == NT_TILE_HALFr) return NT_TILE_HALFl;
    if (t == NT_TILE_HALFl) return NT_TILE_HALFr;
    return t;
}

static int flip_v(int t)
{
    if (t >= 2 && t <= 29) return 2 + (t - 2) / 4 * 4 + "\3\2\1\0"[(t - 2) % 4];
    if (t == NT_TILE_HALFd) return NT_TILE_HALFu;
    if (t == NT_TILE_HALFu) return NT_TILE_HALFd;
    return t;
}

static int flip_d(int t)
{
    if (t >= 2 && t <= 29) {
        int family = (t - 2) / 4, sign = "\2\1\0\3"[(t - 2) % 4];
        if (family >= 3) family = family >= 5 ? family - 2 : family + 2; /* 22 <-> 67, small and big kept */
        return 2 + family * 4 + sign;
    }
    static const int half[4] = {NT_TILE_HALFr, NT_TILE_HALFd, NT_TILE_HALFl, NT_TILE_HALFu};
    if (t >= NT_TILE_HALFd && t <= NT_TILE_HALFl) return half[t - NT_TILE_HALFd];
    return t;
}

int tiled_flip_tile(int tile, uint32_t flags)
{
    if (tile < 0 || tile >= NT_TILE_COUNT) return -1;
    int t = tile;
    if (flags & TILED_FLIP_D) t = flip_d(t); /* Tiled applies the diagonal flip first */
    if (flags & TILED_FLIP_V) t = flip_v(t);
    if (flags & TILED_FLIP_H) t = flip_h(t);
    return t;
}

/* ---------------------------------------------------------------- properties */

static const tl_prop *prop(const tl_props *ps, const char *name)
{
    for (int i = 0; i < ps->n; i++)
        if (strcmp(ps->v[i].name, name) == 0) return &ps->v[i];
    return NULL;
}

static nt_status prop_type_error(tl_ctx *c, const char *what, const tl_prop *p, const char *expected)
{
    char q[64];
    if (!p->value) return tl_fail(c, p->loc, "%s: property \"%s\" must be %s, not a class", what, p->name, expected);
    return tl_fail(c, p->loc, "%s: property \"%s\" must be %s, not %s %s", what, p->name, expected, p->type,
                   tl_quote(q, p->value));
}

/* Each getter leaves *out alone when the property is absent and returns 1 in *found. */
static nt_status prop_bool(tl_ctx *c, const char *what, const tl_props *ps, const char *name, int *out)
{
    const tl_prop *p = prop(ps, name);
    if (!p) return NT_OK;
    if (p->value && (strcmp(p->type, "bool") == 0 || strcmp(p->type, "string") == 0)) {
        if (strcmp(p->value, "true") == 0) {
            *out = 1;
            return NT_OK;
        }
        if (strcmp(p->value, "false") == 0) {
            *out = 0;
            return NT_OK;
        }
    }
    return prop_type_error(c, what, p, "a bool (true or false)");
}

static nt_status prop_real(tl_ctx *c, const char *what, const tl_props *ps, const char *name, double *out)
{
    const tl_prop *p = prop(ps, name);
    if (!p) return NT_OK;
    if (p->value && (strcmp(p->type, "float") == 0 || strcmp(p->type, "int") == 0 || strcmp(p->type, "string") == 0)) {
        char *end;
        double x = strtod(p->value, &end);
        if (end != p->value && *end == '\0' && isfinite(x)) {
            *out = x;
            return NT_OK;
        }
    }
    return prop_type_error(c, what, p, "a finite number");
}

static nt_status prop_int(tl_ctx *c, const char *what, const tl_props *ps, const char *name, long long lo, long long hi,
                          long long *out)
{
    const tl_prop *p = prop(ps, name);
    if (!p) return NT_OK;
    char expected[96];
    snprintf(expected, sizeof expected, "an integer in %lld..%lld", lo, hi);
    if (p->value && (strcmp(p->type, "int") == 0 || strcmp(p->type, "float") == 0 || strcmp(p->type, "string") == 0 ||
                     strcmp(p->type, "object") == 0)) {
        char *end;
        errno = 0;
        long long x = strtoll(p->value, &end, 10);
        if (end != p->value && *end == '\0' && !errno && x >= lo && x <= hi) {
            *out = x;
            return NT_OK;
        }
        double d = strtod(p->value, &end); /* 3.0 written by a float property */
        if (end != p->value && *end == '\0' && d >= (double)lo && d <= (double)hi && d == floor(d)) {
            *out = (long long)d;
            return NT_OK;
        }
    }
    return prop_type_error(c, what, p, expected);
}

static nt_status prop_string(tl_ctx *c, const char *what, const tl_props *ps, const char *name, const char **out)
{
    const tl_prop *p = prop(ps, name);
    if (!p) return NT_OK;
    if (!p->value) return prop_type_error(c, what, p, "a string");
    *out = p->value;
    return NT_OK;
}

/* ---------------------------------------------------------------- files */

static int read_whole(const char *path, char **out, size_t *len, char *why, size_t cap)
{
    *out = NULL;
    *len = 0;
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(why, cap, "%s", strerror(errno));
        return 0;
    }
    if (!stream_check_regular(f, path, STREAM_MAX_FILE, why, cap)) { /* not /dev/zero, a FIFO or a directory */
        fclose(f);
        return 0;
    }
    int r = stream_read_all(f, STREAM_MAX_FILE, out, len);
    if (r == STREAM_READ_ERROR) snprintf(why, cap, "%s", strerror(errno));
    fclose(f);
    if (r == STREAM_NO_MEMORY) snprintf(why, cap, "out of memory");
    return r == STREAM_OK;
}

static int ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), m = strlen(tail);
    return n >= m && strcasecmp(s + n - m, tail) == 0;
}

/* JSON when the name says so or the text starts with '{'. */
static int looks_json(const char *name, const char *text, size_t len)
{
    if (ends_with(name, ".tmj") || ends_with(name, ".tsj") || ends_with(name, ".json")) return 1;
    if (ends_with(name, ".tmx") || ends_with(name, ".tsx") || ends_with(name, ".xml")) return 0;
    size_t i = 0;
    if (len >= 3 && (unsigned char)text[0] == 0xef && (unsigned char)text[1] == 0xbb && (unsigned char)text[2] == 0xbf) i = 3;
    while (i < len && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r' || text[i] == '\n')) i++;
    return i < len && text[i] == '{';
}

static nt_status load_external(tl_ctx *c, const char *map_path, tl_tileset *ts, int index)
{
    const char *slash = strrchr(map_path, '/');
    size_t dir = ts->source[0] == '/' || !slash ? 0 : (size_t)(slash - map_path) + 1;
    size_t n = dir + strlen(ts->source);
    char *path = tl_alloc(&c->arena, n + 1);
    if (!path) return tl_oom(c, map_path);
    memcpy(path, map_path, dir);
    strcpy(path + dir, ts->source);
    char *text;
    size_t len;
    char why[200], q[64];
    if (!read_whole(path, &text, &len, why, sizeof why))
        return tl_fail(c, ts->loc, "tileset %d: cannot read %s (%s): %s", index, tl_quote(q, ts->source), path, why);
    nt_status s = looks_json(path, text, len) ? tl_json_tileset(c, path, text, len, ts) : tl_xml_tileset(c, path, text, len, ts);
    free(text);
    return s;
}

/* ---------------------------------------------------------------- tile data */

/* Line and column of byte `off` of a layer's text (its file position when known). */
static tl_loc text_pos(const tl_layer *l, size_t off)
{
    tl_loc at = l->text_loc;
    if (at.line <= 0) return l->data_loc;
    for (size_t i = 0; i < off && i < l->text_len; i++) {
        if (l->text[i] == '\n') {
            at.line++;
            at.col = 1;
        } else {
            at.col++;
        }
    }
    return at;
}

static int b64_value(unsigned char ch)
{
    if (ch >= 'A' && ch <= 'Z') return ch - 'A';
    if (ch >= 'a' && ch <= 'z') return ch - 'a' + 26;
    if (ch >= '0' && ch <= '9') return ch - '0' + 52;
    if (ch == '+') return 62;
    if (ch == '/') return 63;
    return -1;
}

static int blank(unsigned char ch) { return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\n'; }

/* Decode base64 (blanks ignored, '=' padding optional at the end) into the arena. */
static nt_status base64_decode(tl_ctx *c, const tl_layer *l, const char *what, unsigned char **out, size_t *len)
{
    unsigned char *buf = tl_alloc(&c->arena, l->text_len / 4 * 3 + 3);
    if (!buf) return tl_oom(c, l->loc.file);
    size_t n = 0, pad = 0;
    unsigned acc = 0;
    int bits = 0, digits = 0;
    for (size_t i = 0; i < l->text_len; i++) {
        unsigned char ch = (unsigned char)l->text[i];
        if (blank(ch)) continue;
        if (ch == '=') {
            pad++;
            continue;
        }
        int v = b64_value(ch);
        if (v < 0 || pad) {
            char q[64], s[2] = {(char)ch, 0};
            return tl_fail(c, text_pos(l, i), "%s: bad base64 data: %s %s at byte %zu", what,
                           pad ? "data after the '=' padding:" : "invalid character", tl_quote(q, s), i + 1);
        }
        acc = (acc << 6) | (unsigned)v;
        bits += 6;
        digits++;
        if (bits >= 8) {
            bits -= 8;
            buf[n++] = (unsigned char)(acc >> bits);
            acc &= (1u << bits) - 1;
        }
    }
    if (digits % 4 == 1 || pad > 2 || (pad && (digits + pad) % 4 != 0))
        return tl_fail(c, l->data_loc, "%s: bad base64 data: truncated (%d digits and %zu '=')", what, digits, pad);
    *out = buf;
    *len = n;
    return NT_OK;
}

/* Inflate zlib or gzip data (the header tells which) into exactly `want` bytes. */
static nt_status inflate_exact(tl_ctx *c, const tl_layer *l, const char *what, const unsigned char *in, size_t inlen,
                               unsigned char *outbuf, size_t want)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit2(&z, 15 + 32) != Z_OK) return tl_oom(c, l->loc.file);
    unsigned char extra;
    size_t got = 0, used = 0;
    int r = Z_OK;
    while (r == Z_OK) {
        size_t in_chunk = inlen - used > 1u << 30 ? 1u << 30 : inlen - used;
        z.next_in = (unsigned char *)(uintptr_t)(in + used);
        z.avail_in = (uInt)in_chunk;
        if (got < want) {
            size_t out_chunk = want - got > 1u << 30 ? 1u << 30 : want - got;
            z.next_out = outbuf + got;
            z.avail_out = (uInt)out_chunk;
        } else { /* room for one more byte: is there more than expected? */
            z.next_out = &extra;
            z.avail_out = 1;
        }
        size_t before_out = z.total_out, before_in = z.total_in;
        r = inflate(&z, Z_NO_FLUSH);
        got += z.total_out - before_out;
        used += z.total_in - before_in;
        if (got > want) break;
        if (r == Z_BUF_ERROR && used < inlen) r = Z_OK;
    }
    const char *zmsg = z.msg;
    char why[200];
    int ok = 0;
    if (got > want) snprintf(why, sizeof why, "the data holds more than %zu tiles", want / 4);
    else if (r == Z_STREAM_END) ok = 1;
    else if (r == Z_BUF_ERROR || (r == Z_OK && used >= inlen)) snprintf(why, sizeof why, "the compressed data is truncated");
    else if (r == Z_MEM_ERROR) {
        inflateEnd(&z);
        return tl_oom(c, l->loc.file);
    } else snprintf(why, sizeof why, "%s", zmsg ? zmsg : "corrupt data");
    inflateEnd(&z);
    if (!ok) return tl_fail(c, l->data_loc, "%s: bad %s data: %s", what, l->compression, why);
    if (got != want)
        return tl_fail(c, l->data_loc, "%s: wrong data length: %zu tiles, expected %zu (%lld x %lld)", what, got / 4,
                       want / 4, l->width, l->height);
    return NT_OK;
}

static nt_status csv_decode(tl_ctx *c, const tl_layer *l, const char *what, uint32_t *gids, size_t want)
{
    size_t n = 0, i = 0;
    const char *s = l->text;
    for (;;) {
        while (i < l->text_len && blank((unsigned char)s[i])) i++;
        if (i == l->text_len) break;
        size_t start = i;
        unsigned long long v = 0;
        while (i < l->text_len && s[i] >= '0' && s[i] <= '9' && v <= 0xffffffffULL) v = v * 10 + (unsigned)(s[i++] - '0');
        if (i == start || v > 0xffffffffULL || (i < l->text_len && s[i] != ',' && !blank((unsigned char)s[i]))) {
            size_t e = start;
            while (e < l->text_len && s[e] != ',' && !blank((unsigned char)s[e]) && e - start < 20) e++;
            char q[64], word[24];
            snprintf(word, sizeof word, "%.*s", (int)(e - start), s + start);
            return tl_fail(c, text_pos(l, start), "%s: bad CSV data: %s is not a tile id (item %zu)", what,
                           tl_quote(q, word), n + 1);
        }
        if (n < want) gids[n] = (uint32_t)v;
        n++;
        while (i < l->text_len && blank((unsigned char)s[i])) i++;
        if (i < l->text_len && s[i] == ',') i++;
    }
    if (n != want)
        return tl_fail(c, l->data_loc, "%s: wrong data length: %zu tiles, expected %zu (%lld x %lld)", what, n, want,
                       l->width, l->height);
    return NT_OK;
}

/* The layer's global tile ids, width * height of them, row by row. */
static nt_status layer_gids(tl_ctx *c, const tl_layer *l, const char *what, uint32_t **out)
{
    size_t want = (size_t)l->width * (size_t)l->height;
    if (l->has_gids) {
        if (l->ngids != want)
            return tl_fail(c, l->data_loc, "%s: wrong data length: %zu tiles, expected %zu (%lld x %lld)", what, l->ngids,
                           want, l->width, l->height);
        *out = l->gids;
        return NT_OK;
    }
    const char *comp = l->compression ? l->compression : "";
    if (strcmp(l->encoding, "csv") == 0) {
        if (*comp) return tl_fail(c, l->data_loc, "%s: CSV data cannot be compressed (compression \"%s\")", what, comp);
        uint32_t *g = tl_alloc(&c->arena, (want ? want : 1) * sizeof *g);
        if (!g) return tl_oom(c, l->loc.file);
        nt_status s = csv_decode(c, l, what, g, want);
        *out = g;
        return s;
    }
    if (strcmp(comp, "zstd") == 0)
        return tl_fail(c, l->data_loc,
                       "%s: zstd compression is not supported; save the map with CSV, base64 (uncompressed), "
                       "base64 (zlib) or base64 (gzip) as the tile layer format (Map > Map Properties)",
                       what);
    if (*comp && strcmp(comp, "zlib") != 0 && strcmp(comp, "gzip") != 0) {
        char q[64];
        return tl_fail(c, l->data_loc, "%s: unknown compression %s (expected zlib, gzip or none)", what, tl_quote(q, comp));
    }
    unsigned char *raw = NULL;
    size_t rawlen = 0;
    nt_status s = base64_decode(c, l, what, &raw, &rawlen);
    if (s != NT_OK) return s;
    unsigned char *bytes = raw;
    if (*comp) {
        bytes = tl_alloc(&c->arena, want * 4 + 1);
        if (!bytes) return tl_oom(c, l->loc.file);
        if ((s = inflate_exact(c, l, what, raw, rawlen, bytes, want * 4)) != NT_OK) return s;
    } else if (rawlen != want * 4) {
        return tl_fail(c, l->data_loc, "%s: wrong data length: %zu bytes, expected %zu (%lld x %lld tiles of 4 bytes)",
                       what, rawlen, want * 4, l->width, l->height);
    }
    uint32_t *g = tl_alloc(&c->arena, (want ? want : 1) * sizeof *g);
    if (!g) return tl_oom(c, l->loc.file);
    for (size_t k = 0; k < want; k++)
        g[k] = (uint32_t)bytes[4 * k] | (uint32_t)bytes[4 * k + 1] << 8 | (uint32_t)bytes[4 * k + 2] << 16 |
               (uint32_t)bytes[4 * k + 3] << 24;
    *out = g;
    return NT_OK;
}

/* ---------------------------------------------------------------- tilesets */

/* What a tile of a tileset says: its N tile (-1: none), one-way (-1: not said),
 * material (-1: not said). */
typedef struct tile_info {
    long long id;
    int shape, one_way, material;
} tile_info;

typedef struct tset {
    const tl_tileset *ts;
    tile_info *tiles; /* sorted by id */
    int n;
} tset;

static int by_id(const void *a, const void *b)
{
    long long x = ((const tile_info *)a)->id, y = ((const tile_info *)b)->id;
    return (x > y) - (x < y);
}

static int by_firstgid(const void *a, const void *b)
{
    long long x = ((const tset *)a)->ts->firstgid, y = ((const tset *)b)->ts->firstgid;
    return (x > y) - (x < y);
}

static nt_status tile_name(tl_ctx *c, const char *what, const tl_prop *p, int *out)
{
    if (!p->value) return prop_type_error(c, what, p, "an N tile name");
    int t = nt_tile_from_name(p->value);
    if (t >= 0) {
        *out = t;
        return NT_OK;
    }
    char q[64];
    int same = tilename_lookup(p->value);
    if (same >= 0)
        return tl_fail(c, p->loc, "%s: property \"ntile\": unknown tile name %s (did you mean \"%s\"? names are case-sensitive)",
                       what, tl_quote(q, p->value), nt_tile_get_info(same)->name);
    const char *near = tilename_suggest(p->value);
    if (near)
        return tl_fail(c, p->loc, "%s: property \"ntile\": unknown tile name %s (did you mean \"%s\"?)", what,
                       tl_quote(q, p->value), near);
    return tl_fail(c, p->loc, "%s: property \"ntile\": unknown tile name %s (expected an N tile name: EMPTY, FULL, "
                   "45DEGpn, ..., HALFl; see the tile table in README.md)", what, tl_quote(q, p->value));
}

static nt_status resolve_tileset(tl_ctx *c, const tl_tileset *ts, tset *out)
{
    out->ts = ts;
    out->n = 0;
    out->tiles = tl_alloc(&c->arena, (size_t)(ts->ntiles ? ts->ntiles : 1) * sizeof *out->tiles);
    if (!out->tiles) return tl_oom(c, ts->def.file ? ts->def.file : ts->loc.file);
    char q[64];
    for (int i = 0; i < ts->ntiles; i++) {
        const tl_tile *t = &ts->tiles[i];
        char what[160];
        snprintf(what, sizeof what, "tileset %s: tile %lld", tl_quote(q, ts->name ? ts->name : ""), t->id);
        tile_info *ti = &out->tiles[out->n++];
        ti->id = t->id;
        ti->shape = ti->one_way = ti->material = -1;
        const tl_prop *p = prop(&t->props, "ntile");
        nt_status s;
        if (p && (s = tile_name(c, what, p, &ti->shape)) != NT_OK) return s;
        if ((s = prop_bool(c, what, &t->props, "one_way", &ti->one_way)) != NT_OK) return s;
        long long m = -1;
        if ((s = prop_int(c, what, &t->props, "material", 0, NT_MAX_MATERIALS - 1, &m)) != NT_OK) return s;
        ti->material = (int)m;
        if (t->id < 0) return tl_fail(c, t->loc, "%s: negative tile id", what);
    }
    qsort(out->tiles, (size_t)out->n, sizeof *out->tiles, by_id);
    for (int i = 1; i < out->n; i++)
        if (out->tiles[i].id == out->tiles[i - 1].id)
            return tl_fail(c, ts->def, "tileset %s: tile %lld is defined twice", tl_quote(q, ts->name ? ts->name : ""),
                           out->tiles[i].id);
    return NT_OK;
}

/* ---------------------------------------------------------------- the builder */

typedef struct builder {
    tl_ctx *c;
    const char *path;
    tl_map m;
    tset *sets;
    int nsets;
    nt_level *lv;
    long long *path_ids; /* Tiled object id of each path, by path index */
} builder;

/* The tileset holding gid (flags removed), or NULL. */
static const tset *find_set(const builder *b, uint32_t gid)
{
    int lo = 0, hi = b->nsets - 1, k = -1;
    while (lo <= hi) {
        int mid = (lo + hi) / 2;
        if (b->sets[mid].ts->firstgid <= (long long)gid) {
            k = mid;
            lo = mid + 1;
        } else {
            hi = mid - 1;
        }
    }
    return k < 0 ? NULL : &b->sets[k];
}

static const tile_info *find_tile(const tset *s, long long id)
{
    tile_info key;
    key.id = id;
    return bsearch(&key, s->tiles, (size_t)s->n, sizeof *s->tiles, by_id);
}

static void clean_text(char *dst, const char *s)
{
    size_t n = strlen(s);
    if (n >= NT_LEVEL_TEXT_MAX) n = NT_LEVEL_TEXT_MAX - 1;
    for (size_t i = 0; i < n; i++) {
        unsigned char ch = (unsigned char)s[i];
        dst[i] = (ch < 0x20 || ch == 0x7f || ch == '"' || ch == '\\') ? '_' : (char)ch;
    }
    dst[n] = '\0';
}

static nt_status map_settings(builder *b)
{
    tl_ctx *c = b->c;
    nt_level *lv = b->lv;
    const tl_props *ps = &b->m.props;
    nt_status s;
    const char *str = NULL;
    if ((s = prop_string(c, "map", ps, "title", &str)) != NT_OK) return s;
    if (str) clean_text(lv->title, str);
    str = NULL;
    if ((s = prop_string(c, "map", ps, "author", &str)) != NT_OK) return s;
    if (str) clean_text(lv->author, str);
    double gx = lv->gravity.x, gy = lv->gravity.y;
    if ((s = prop_real(c, "map", ps, "gravity_x", &gx)) != NT_OK || (s = prop_real(c, "map", ps, "gravity_y", &gy)) != NT_OK)
        return s;
    lv->gravity = nt_v2((nt_real)gx, (nt_real)gy);
    str = NULL;
    if ((s = prop_string(c, "map", ps, "friction_model", &str)) != NT_OK) return s;
    if (str) {
        if (strcmp(str, "n") == 0) lv->friction_model = NT_FRICTION_N;
        else if (strcmp(str, "coulomb") == 0) lv->friction_model = NT_FRICTION_COULOMB;
        else {
            char q[64];
            return tl_fail(c, prop(ps, "friction_model")->loc, "map: property \"friction_model\": %s is not n or coulomb",
                           tl_quote(q, str));
        }
    }
    int sleep = lv->enable_sleep;
    if ((s = prop_bool(c, "map", ps, "sleep", &sleep)) != NT_OK) return s;
    lv->enable_sleep = sleep != 0;
    long long seed = (long long)lv->seed;
    if ((s = prop_int(c, "map", ps, "seed", 0, 9007199254740991LL, &seed)) != NT_OK) return s;
    lv->seed = (uint64_t)seed;
    for (int i = 0; i < NT_MAX_MATERIALS; i++) {
        char name[32];
        snprintf(name, sizeof name, "material%d", i);
        const tl_prop *p = prop(ps, name);
        if (!p) continue;
        double f, bo;
        char tail;
        if (!p->value || sscanf(p->value, "%lf %lf %c", &f, &bo, &tail) != 2 || !isfinite(f) || !isfinite(bo) || f < 0 ||
            bo < 0 || bo > 1)
            return prop_type_error(c, "map", p, "\"FRICTION BOUNCE\" (friction >= 0, bounce in 0..1)");
        lv->materials[i].friction = (nt_real)f;
        lv->materials[i].bounce = (nt_real)bo;
    }
    return NT_OK;
}

static nt_status tile_layer(builder *b, const tl_layer *l)
{
    tl_ctx *c = b->c;
    nt_level *lv = b->lv;
    char what[128], q[64];
    snprintf(what, sizeof what, "layer %s", tl_quote(q, l->name));
    if (l->width != lv->width || l->height != lv->height)
        return tl_fail(c, l->loc, "%s: %lld x %lld tiles, but the map is %d x %d", what, l->width, l->height, lv->width,
                       lv->height);
    int solid = 0, one_way = 0;
    long long material = 0;
    nt_status s;
    if ((s = prop_bool(c, what, &l->props, "solid", &solid)) != NT_OK ||
        (s = prop_bool(c, what, &l->props, "one_way", &one_way)) != NT_OK ||
        (s = prop_int(c, what, &l->props, "material", 0, NT_MAX_MATERIALS - 1, &material)) != NT_OK)
        return s;
    if (l->offx != 0 || l->offy != 0)
        tl_warn(c, l->loc, "%s: the layer's offset (%g, %g) is ignored: tiles stay on the map's grid", what, l->offx, l->offy);
    uint32_t *gids = NULL;
    if ((s = layer_gids(c, l, what, &gids)) != NT_OK) return s;
    int flip_warned = 0;
    for (int y = 0; y < lv->height; y++) {
        for (int x = 0; x < lv->width; x++) {
            size_t k = (size_t)y * (size_t)lv->width + (size_t)x;
            uint32_t raw = gids[k], gid = raw & TILED_GID_MASK;
            if (gid == 0) continue;
            const tset *set = find_set(b, gid);
            const tile_info *ti = set ? find_tile(set, (long long)gid - set->ts->firstgid) : NULL;
            /* Past the tile count is unknown, unless the tileset defines that id (image
             * collections may number their tiles beyond their count). */
            if (!set || (!ti && set->ts->tilecount >= 0 && (long long)gid - set->ts->firstgid >= set->ts->tilecount)) {
                char range[160] = "the map has no tilesets";
                if (b->nsets) {
                    const tset *last = &b->sets[b->nsets - 1];
                    if (last->ts->tilecount >= 0)
                        snprintf(range, sizeof range, "the tilesets hold ids %lld..%lld", b->sets[0].ts->firstgid,
                                 last->ts->firstgid + last->ts->tilecount - 1);
                    else
                        snprintf(range, sizeof range, "the first tileset starts at %lld", b->sets[0].ts->firstgid);
                }
                return tl_fail(c, l->data_loc, "%s: cell (%d, %d): unknown tile id %u (%s)", what, x, y, gid, range);
            }
            int shape = ti && ti->shape >= 0 ? ti->shape : solid ? NT_TILE_FULL : NT_TILE_EMPTY;
            if (shape == NT_TILE_EMPTY) continue;
            uint32_t flags = raw & (TILED_FLIP_H | TILED_FLIP_V | TILED_FLIP_D);
            int t = tiled_flip_tile(shape, flags);
            if (t < 0) {
                if (!flip_warned++)
                    tl_warn(c, l->data_loc, "%s: cell (%d, %d): flipped %s is not an N tile; kept unflipped", what, x, y,
                            nt_tile_get_info(shape)->name);
                t = shape;
            }
            lv->tiles[k] = (uint8_t)t;
            lv->cell_materials[k] = (uint8_t)(ti && ti->material >= 0 ? ti->material : material);
            lv->cell_flags[k] = (ti && ti->one_way >= 0 ? ti->one_way : one_way) ? NT_CELL_ONE_WAY : 0;
        }
    }
    return NT_OK;
}

/* ---------------------------------------------------------------- objects */

static int name_char(char ch, int first)
{
    if ((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || ch == '_') return 1;
    return !first && ((ch >= '0' && ch <= '9') || ch == '-' || ch == '.');
}

static int name_taken(const nt_level *lv, const char *name)
{
    return nt_level_find_body(lv, name) >= 0 || nt_level_find_region(lv, name) >= 0 || nt_level_find_path(lv, name) >= 0;
}

/* The object's ntile name: its Tiled name, or PREFIX + its id when unnamed. */
static nt_status object_name(builder *b, const tl_object *o, const char *what, const char *prefix, char out[NT_LEVEL_NAME_MAX])
{
    char q[64];
    if (!*o->name) {
        snprintf(out, NT_LEVEL_NAME_MAX, "%s%lld", prefix, o->id);
    } else {
        size_t n = strlen(o->name);
        int ok = n < NT_LEVEL_NAME_MAX;
        for (size_t i = 0; ok && i < n; i++) ok = name_char(o->name[i], i == 0);
        if (!ok)
            return tl_fail(b->c, o->loc,
                           "%s: %s is not an ntile name (a letter or '_', then letters, digits, '_', '-' or '.', "
                           "at most %d characters)",
                           what, tl_quote(q, o->name), NT_LEVEL_NAME_MAX - 1);
        memcpy(out, o->name, n + 1);
    }
    if (name_taken(b->lv, out))
        return tl_fail(b->c, o->loc, "%s: the name %s is already used by another object (names are shared by bodies, "
                       "regions and paths)", what, tl_quote(q, out));
    return NT_OK;
}

static const char *status_text(nt_status s) { return nt_status_string(s); }

/* Pass 1: polylines, polygons and ellipses with a "path" property. */
static nt_status object_path(builder *b, const tl_layer *l, const tl_object *o, const char *what)
{
    tl_ctx *c = b->c;
    const char *mode = NULL;
    nt_status s;
    if ((s = prop_string(c, what, &o->props, "path", &mode)) != NT_OK) return s;
    nt_level_path p;
    memset(&p, 0, sizeof p);
    if ((s = object_name(b, o, what, "path", p.name)) != NT_OK) return s;
    double speed = 0, wait = 0;
    if (!prop(&o->props, "speed")) return tl_fail(c, o->loc, "%s: a path needs a \"speed\" property (units per second, > 0)", what);
    if ((s = prop_real(c, what, &o->props, "speed", &speed)) != NT_OK || (s = prop_real(c, what, &o->props, "wait", &wait)) != NT_OK)
        return s;
    if (!(speed > 0)) return tl_fail(c, o->loc, "%s: the path's speed must be > 0", what);
    if (wait < 0) return tl_fail(c, o->loc, "%s: the path's wait must be >= 0", what);
    p.speed = (nt_real)speed;
    p.wait = (nt_real)wait;
    char q[64];
    if (o->shape == TL_ELLIPSE) {
        if (wait != 0) return tl_fail(c, o->loc, "%s: an orbit has no waypoints to wait at (remove \"wait\")", what);
        if (!(o->w > 0)) return tl_fail(c, o->loc, "%s: an orbit needs a width (its diameter)", what);
        if (o->w != o->h) tl_warn(c, o->loc, "%s: the ellipse is %g x %g; the orbit is a circle of diameter %g", what, o->w, o->h, o->w);
        p.mode = NT_PATH_ORBIT;
        p.center = nt_v2((nt_real)(o->x + l->offx + o->w / 2), (nt_real)(o->y + l->offy + o->w / 2));
        p.radius = (nt_real)(o->w / 2);
    } else {
        if (!*mode) p.mode = o->shape == TL_POLYGON ? NT_PATH_LOOP : NT_PATH_PINGPONG;
        else if (strcmp(mode, "loop") == 0) p.mode = NT_PATH_LOOP;
        else if (strcmp(mode, "pingpong") == 0) p.mode = NT_PATH_PINGPONG;
        else return tl_fail(c, o->loc, "%s: property \"path\": %s is not loop or pingpong", what, tl_quote(q, mode));
        if (o->npoints < 2 || o->npoints > NT_LEVEL_MAX_PATH_POINTS)
            return tl_fail(c, o->loc, "%s: a path needs 2 to %d points, this one has %d", what, NT_LEVEL_MAX_PATH_POINTS,
                           o->npoints);
        p.point_count = o->npoints;
        for (int i = 0; i < o->npoints; i++)
            p.points[i] = nt_v2((nt_real)(o->x + l->offx + o->points[2 * i]), (nt_real)(o->y + l->offy + o->points[2 * i + 1]));
    }
    int index;
    nt_text_error e;
    s = nt_level_add_path(b->lv, &p, &index, &e);
    if (s == NT_ERR_OUT_OF_MEMORY) return tl_oom(c, b->path);
    if (s != NT_OK) return tl_fail(c, o->loc, "%s: cannot add the %s", what, e.message);
    b->path_ids[index] = o->id;
    return NT_OK;
}

static nt_status object_region(builder *b, const tl_layer *l, const tl_object *o, const char *what)
{
    tl_ctx *c = b->c;
    const char *kind = NULL;
    nt_status s;
    char q[64];
    if ((s = prop_string(c, what, &o->props, "region", &kind)) != NT_OK) return s;
    nt_level_region r;
    memset(&r, 0, sizeof r);
    if (strcmp(kind, "zone") == 0 || !*kind) r.kind = NT_REGION_ZONE;
    else if (strcmp(kind, "exit") == 0) r.kind = NT_REGION_EXIT;
    else if (strcmp(kind, "score") == 0) r.kind = NT_REGION_SCORE;
    else if (strcmp(kind, "kill") == 0) r.kind = NT_REGION_KILL;
    else return tl_fail(c, prop(&o->props, "region")->loc, "%s: property \"region\": %s is not zone, exit, score or kill", what,
                        tl_quote(q, kind));
    if (o->shape != TL_RECT) return tl_fail(c, o->loc, "%s: a region must be a rectangle", what);
    if (!(o->w > 0 && o->h > 0)) return tl_fail(c, o->loc, "%s: a region needs a width and a height", what);
    long long value = 0;
    if ((s = prop_int(c, what, &o->props, "value", 1, 1000000, &value)) != NT_OK) return s;
    if (r.kind == NT_REGION_SCORE && !prop(&o->props, "value"))
        return tl_fail(c, o->loc, "%s: a score region needs a \"value\" property (points per body, 1..1000000)", what);
    if (r.kind != NT_REGION_SCORE && prop(&o->props, "value"))
        return tl_fail(c, o->loc, "%s: only score regions have a \"value\"", what);
    r.value = (int)value;
    if (o->rotation != 0) tl_warn(c, o->loc, "%s: rotation ignored (regions are axis-aligned)", what);
    if ((s = object_name(b, o, what, "region", r.name)) != NT_OK) return s;
    r.lo = nt_v2((nt_real)(o->x + l->offx), (nt_real)(o->y + l->offy));
    r.hi = nt_v2((nt_real)(o->x + l->offx + o->w), (nt_real)(o->y + l->offy + o->h));
    nt_text_error e;
    s = nt_level_add_region(b->lv, &r, &e);
    if (s == NT_ERR_OUT_OF_MEMORY) return tl_oom(c, b->path);
    if (s != NT_OK) return tl_fail(c, o->loc, "%s: cannot add the %s", what, e.message);
    return NT_OK;
}

static int in_reach(const nt_level *lv, double x, double y)
{
    double m = (double)lv->cell_size * NT_WORLD_REACH_CELLS;
    return x >= -m && y >= -m && x <= lv->width * (double)lv->cell_size + m && y <= lv->height * (double)lv->cell_size + m;
}

static nt_status object_body(builder *b, const tl_layer *l, const tl_object *o, const char *what)
{
    tl_ctx *c = b->c;
    nt_level *lv = b->lv;
    nt_level_body body = nt_level_default_body(lv);
    nt_status s;
    char q[64];
    /* Bodies may be up to 2 * NT_MAX_HALF_CELLS cells across (the level's check). */
    nt_real cap = lv->cell_size * NT_MAX_HALF_CELLS;
    double most = 2 * (double)cap, cx, cy;
    if (!(o->w > 0 && o->h > 0)) return tl_fail(c, o->loc, "%s: a body needs a width and a height", what);
    if (o->shape == TL_ELLIPSE) {
        double d = o->w < o->h ? o->w : o->h;
        if (o->w != o->h)
            tl_warn(c, o->loc, "%s: the ellipse is %g x %g, not a circle; the body is a circle of diameter %g", what, o->w,
                    o->h, d);
        if ((nt_real)(d / 2) > cap)
            return tl_fail(c, o->loc, "%s: a circle of diameter %g is larger than a body can be (diameter at most %g, %d cells)",
                           what, d, most, 2 * NT_MAX_HALF_CELLS);
        body.shape = nt_shape_circle((nt_real)(d / 2));
        cx = o->x + o->w / 2;
        cy = o->y + o->h / 2;
    } else {
        if ((nt_real)(o->w / 2) > cap || (nt_real)(o->h / 2) > cap)
            return tl_fail(c, o->loc, "%s: a box of %g x %g is larger than a body can be (at most %g x %g, %d x %d cells)", what,
                           o->w, o->h, most, most, 2 * NT_MAX_HALF_CELLS, 2 * NT_MAX_HALF_CELLS);
        body.shape = nt_shape_aabb((nt_real)(o->w / 2), (nt_real)(o->h / 2));
        cx = o->x + o->w / 2;
        cy = o->y + o->h / 2;
    }
    if (o->rotation != 0) tl_warn(c, o->loc, "%s: rotation ignored (ntile bodies never rotate)", what);
    cx += l->offx;
    cy += l->offy;
    if (!in_reach(lv, cx, cy))
        return tl_fail(c, o->loc, "%s: the body lies more than %d cells outside the map", what, NT_WORLD_REACH_CELLS);
    body.position = nt_v2((nt_real)cx, (nt_real)cy);
    /* The world's rule: a body above half a cell lies wholly inside the map. */
    nt_vec2 h = body.shape.half, p = body.position;
    nt_real lim = lv->cell_size * (nt_real)0.5, mw = (nt_real)lv->width * lv->cell_size, mh = (nt_real)lv->height * lv->cell_size;
    if ((h.x > lim || h.y > lim) && !(p.x - h.x >= 0 && p.y - h.y >= 0 && p.x + h.x <= mw && p.y + h.y <= mh))
        return tl_fail(c, o->loc, "%s: the body is larger than half a cell, so it must lie inside the map (0 0 .. %g %g)", what,
                       (double)mw, (double)mh);
    /* type: the property, else Tiled's class field when it names a type. */
    const char *type = NULL;
    if ((s = prop_string(c, what, &o->props, "type", &type)) != NT_OK) return s;
    if (!type && (strcmp(o->type, "static") == 0 || strcmp(o->type, "kinematic") == 0 || strcmp(o->type, "dynamic") == 0))
        type = o->type;
    if (type) {
        if (strcmp(type, "static") == 0) body.type = NT_BODY_STATIC;
        else if (strcmp(type, "kinematic") == 0) body.type = NT_BODY_KINEMATIC;
        else if (strcmp(type, "dynamic") == 0) body.type = NT_BODY_DYNAMIC;
        else return tl_fail(c, prop(&o->props, "type")->loc, "%s: property \"type\": %s is not static, kinematic or dynamic",
                            what, tl_quote(q, type));
    }
    int sensor = 0, deadly = 0;
    double mass = (double)body.mass, bounce = (double)body.material.bounce, friction = (double)body.material.friction;
    double phase = 0;
    long long score = 0;
    if ((s = prop_bool(c, what, &o->props, "sensor", &sensor)) != NT_OK ||
        (s = prop_bool(c, what, &o->props, "deadly", &deadly)) != NT_OK ||
        (s = prop_real(c, what, &o->props, "mass", &mass)) != NT_OK ||
        (s = prop_real(c, what, &o->props, "bounce", &bounce)) != NT_OK ||
        (s = prop_real(c, what, &o->props, "friction", &friction)) != NT_OK ||
        (s = prop_real(c, what, &o->props, "phase", &phase)) != NT_OK ||
        (s = prop_int(c, what, &o->props, "score", 0, 1000000, &score)) != NT_OK)
        return s;
    if (!(mass > 0)) return tl_fail(c, prop(&o->props, "mass")->loc, "%s: property \"mass\" must be > 0", what);
    if (bounce < 0 || bounce > 1) return tl_fail(c, prop(&o->props, "bounce")->loc, "%s: property \"bounce\" must be in 0..1", what);
    if (friction < 0 || (lv->friction_model == NT_FRICTION_N && friction > 1))
        return tl_fail(c, prop(&o->props, "friction")->loc, "%s: property \"friction\" must be in 0..1%s", what,
                       lv->friction_model == NT_FRICTION_N ? " (the limit of the N friction model)" : "");
    if (score > 0 && !sensor) return tl_fail(c, o->loc, "%s: a body with a score must be a sensor (set \"sensor\")", what);
    if (phase < 0 || phase >= 1) return tl_fail(c, prop(&o->props, "phase")->loc, "%s: property \"phase\" must be in [0, 1)", what);
    body.is_sensor = sensor != 0;
    body.deadly = deadly != 0;
    body.mass = (nt_real)mass;
    body.material.bounce = (nt_real)bounce;
    body.material.friction = (nt_real)friction;
    body.phase = (nt_real)phase;
    body.score = (int)score;
    const tl_prop *pp = prop(&o->props, "path");
    if (pp) {
        if (!pp->value) return prop_type_error(c, what, pp, "a path's name or an object reference");
        int index = -1;
        if (strcmp(pp->type, "object") == 0) {
            long long id = strtoll(pp->value, NULL, 10);
            for (int i = 0; i < lv->path_count; i++)
                if (b->path_ids[i] == id) index = i;
            if (index < 0) return tl_fail(c, pp->loc, "%s: property \"path\" refers to object %lld, which is not a path", what, id);
        } else {
            index = nt_level_find_path(lv, pp->value);
            if (index < 0) return tl_fail(c, pp->loc, "%s: property \"path\": no path is called %s", what, tl_quote(q, pp->value));
        }
        if (body.type != NT_BODY_KINEMATIC)
            return tl_fail(c, pp->loc, "%s: only kinematic bodies follow paths (set \"type\" to kinematic)", what);
        body.path = index;
    }
    if ((s = object_name(b, o, what, "body", body.name)) != NT_OK) return s;
    nt_text_error e;
    s = nt_level_add_body(lv, &body, NULL, &e);
    if (s == NT_ERR_OUT_OF_MEMORY) return tl_oom(c, b->path);
    if (s != NT_OK) return tl_fail(c, o->loc, "%s: cannot add the %s", what, e.message);
    return NT_OK;
}

static nt_status object_other(builder *b, const tl_layer *l, const tl_object *o, const char *what)
{
    tl_ctx *c = b->c;
    nt_level *lv = b->lv;
    switch (o->shape) {
    case TL_POINT:
        if (strcmp(o->name, "spawn") != 0) {
            tl_warn(c, o->loc, "%s: a point that is not named spawn; skipped", what);
            return NT_OK;
        }
        if (lv->has_player) {
            tl_warn(c, o->loc, "%s: a second player spawn; skipped", what);
            return NT_OK;
        }
        if (!in_reach(lv, o->x + l->offx, o->y + l->offy))
            return tl_fail(c, o->loc, "%s: the spawn lies more than %d cells outside the map", what, NT_WORLD_REACH_CELLS);
        lv->has_player = true;
        lv->player = nt_v2((nt_real)(o->x + l->offx), (nt_real)(o->y + l->offy));
        return NT_OK;
    case TL_RECT:
        if (prop(&o->props, "region")) return object_region(b, l, o, what);
        return object_body(b, l, o, what);
    case TL_ELLIPSE:
        if (prop(&o->props, "region")) return tl_fail(c, o->loc, "%s: a region must be a rectangle", what);
        return object_body(b, l, o, what);
    case TL_POLYLINE:
    case TL_POLYGON:
        tl_warn(c, o->loc, "%s: a %s without a \"path\" property; skipped", what, o->shape == TL_POLYGON ? "polygon" : "polyline");
        return NT_OK;
    case TL_TEXT:
        tl_warn(c, o->loc, "%s: text objects are not imported; skipped", what);
        return NT_OK;
    case TL_TEMPLATE:
        tl_warn(c, o->loc, "%s: objects from templates (.tx) are not imported (detach the template); skipped", what);
        return NT_OK;
    default:
        tl_warn(c, o->loc, "%s: tile objects are not imported (draw a rectangle or an ellipse); skipped", what);
        return NT_OK;
    }
}

/* Polylines and polygons with a "path" property, and ellipses whose "path" is
 * "orbit", are paths; an ellipse with any other "path" is a body following it. */
static int is_path_object(const tl_object *o)
{
    const tl_prop *p = prop(&o->props, "path");
    if (!p || !p->value) return 0;
    if (o->shape == TL_ELLIPSE) return strcmp(p->value, "orbit") == 0;
    return o->shape == TL_POLYLINE || o->shape == TL_POLYGON;
}

static nt_status objects(builder *b)
{
    int total = 0;
    for (int i = 0; i < b->m.nlayers; i++) total += b->m.layers[i].kind == TL_LAYER_OBJECTS ? b->m.layers[i].nobjects : 0;
    b->path_ids = tl_alloc(&b->c->arena, (size_t)(total ? total : 1) * sizeof *b->path_ids);
    if (!b->path_ids) return tl_oom(b->c, b->path);
    for (int pass = 0; pass < 2; pass++) {
        for (int i = 0; i < b->m.nlayers; i++) {
            const tl_layer *l = &b->m.layers[i];
            if (l->kind != TL_LAYER_OBJECTS) continue;
            for (int k = 0; k < l->nobjects; k++) {
                const tl_object *o = &l->objects[k];
                char what[300], q1[64], q2[64];
                snprintf(what, sizeof what, "layer %s: object %s (id %lld)", tl_quote(q1, l->name), tl_quote(q2, o->name), o->id);
                int path = is_path_object(o);
                if (path != (pass == 0)) continue;
                nt_status s = path ? object_path(b, l, o, what) : object_other(b, l, o, what);
                if (s != NT_OK) return s;
            }
        }
    }
    return NT_OK;
}

static nt_status build(builder *b, const char *text, size_t len)
{
    tl_ctx *c = b->c;
    tl_map *m = &b->m;
    nt_status s = looks_json(b->path, text, len) ? tl_json_map(c, b->path, text, len, m) : tl_xml_map(c, b->path, text, len, m);
    if (s != NT_OK) return s;
    char q[64];
    if (strcmp(m->orientation, "orthogonal") != 0)
        return tl_fail(c, m->loc, "map: orientation %s is not supported (only orthogonal maps)", tl_quote(q, m->orientation));
    if (m->infinite)
        return tl_fail(c, m->loc, "map: infinite maps are not supported (turn off Map > Map Properties > Infinite)");
    if (m->tilewidth != m->tileheight)
        return tl_fail(c, m->loc, "map: tiles are %lld x %lld, but ntile cells are square (tilewidth must equal tileheight)",
                       m->tilewidth, m->tileheight);
    if (m->tilewidth < 1 || m->tilewidth > 1000000)
        return tl_fail(c, m->loc, "map: tile size %lld is outside 1..1000000", m->tilewidth);
    if (m->width < 1 || m->height < 1 || m->width > NT_MAP_MAX_SIDE || m->height > NT_MAP_MAX_SIDE)
        return tl_fail(c, m->loc, "map: %lld x %lld tiles; ntile maps have 1..%d tiles a side", m->width, m->height,
                       NT_MAP_MAX_SIDE);
    /* Tilesets: external ones read, each resolved, sorted by firstgid. */
    b->sets = tl_alloc(&c->arena, (size_t)(m->ntilesets ? m->ntilesets : 1) * sizeof *b->sets);
    if (!b->sets) return tl_oom(c, b->path);
    for (int i = 0; i < m->ntilesets; i++) {
        tl_tileset *ts = &m->tilesets[i];
        if (ts->firstgid < 1 || ts->firstgid > (long long)TILED_GID_MASK)
            return tl_fail(c, ts->loc, "tileset %d: firstgid %lld is outside 1..%u", i + 1, ts->firstgid, TILED_GID_MASK);
        if (ts->source && (s = load_external(c, b->path, ts, i + 1)) != NT_OK) return s;
        if ((s = resolve_tileset(c, ts, &b->sets[b->nsets])) != NT_OK) return s;
        b->nsets++;
    }
    qsort(b->sets, (size_t)b->nsets, sizeof *b->sets, by_firstgid);
    for (int i = 1; i < b->nsets; i++)
        if (b->sets[i].ts->firstgid == b->sets[i - 1].ts->firstgid)
            return tl_fail(c, b->sets[i].ts->loc, "tileset: two tilesets start at firstgid %lld", b->sets[i].ts->firstgid);
    s = nt_level_create((int)m->width, (int)m->height, (nt_real)m->tilewidth, &b->lv);
    if (s == NT_ERR_OUT_OF_MEMORY) return tl_oom(c, b->path);
    if (s != NT_OK) return tl_fail(c, m->loc, "map: cannot create the level: %s", status_text(s));
    if ((s = map_settings(b)) != NT_OK) return s;
    for (int i = 0; i < m->nlayers; i++)
        if (m->layers[i].kind == TL_LAYER_TILES && (s = tile_layer(b, &m->layers[i])) != NT_OK) return s;
    if ((s = objects(b)) != NT_OK) return s;
    nt_text_error e;
    s = nt_level_validate(b->lv, &e);
    if (s == NT_ERR_OUT_OF_MEMORY) return tl_oom(c, b->path);
    if (s != NT_OK) return tl_fail(c, m->loc, "map: the imported level is not valid: %s", e.message);
    return NT_OK;
}

nt_status tiled_import(const char *path, const char *text, size_t length, nt_level **out, nt_text_error *error,
                       nt_warning_fn *warn, void *context)
{
    if (out) *out = NULL;
    if (error) {
        error->line = error->column = 0;
        error->message[0] = '\0';
    }
    if (!out || !path || (!text && length > 0)) {
        if (error) snprintf(error->message, sizeof error->message, "tiled_import: bad argument");
        return NT_ERR_INVALID_ARGUMENT;
    }
    tl_ctx c;
    memset(&c, 0, sizeof c);
    c.err = error;
    c.warn = warn;
    c.wctx = context;
    builder b;
    memset(&b, 0, sizeof b);
    b.c = &c;
    b.path = path;
    nt_status s = build(&b, text ? text : "", length);
    if (s == NT_OK) *out = b.lv;
    else nt_level_destroy(b.lv);
    tl_arena_free(&c.arena);
    return s;
}
