/* The Tiled importer (tools/tiled, `ntile convert tiled`): maps written here in both
 * formats (TMX and TMJ), every tile layer encoding (CSV, XML <tile> elements,
 * base64 plain / zlib / gzip, compressed here with zlib), flips checked against the
 * tile geometry, several tilesets (embedded, external .tsx and .tsj), tile and
 * layer properties, objects, warnings, malformed files with their messages and
 * positions, allocation failures, and the CLI. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include "child.h"
#include "scratch.h"
#include "failalloc.h"
#include "ntile/ntile.h"
#include "tiled/tiled.h"

/* ---------- temporary files (scratch.h) ---------- */

static int group_setup(void **state)
{
    (void)state;
    if (scratch_create("tiled") != 0) return -1;
    return mkdir(scratch_path("ts"), 0700); /* external tilesets live in a subdirectory */
}

static int group_teardown(void **state)
{
    (void)state;
    scratch_remove();
    return 0;
}

/* ---------------------------------------------------------------- strings */

typedef struct sbuf {
    char *s;
    size_t n, cap;
} sbuf;

static void sb_printf(sbuf *b, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void sb_printf(sbuf *b, const char *fmt, ...)
{
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        size_t room = b->cap - b->n;
        int k = vsnprintf(b->s ? b->s + b->n : NULL, b->s ? room : 0, fmt, ap);
        va_end(ap);
        assert_true(k >= 0);
        if (b->s && (size_t)k < room) {
            b->n += (size_t)k;
            return;
        }
        b->cap = (b->cap + (size_t)k + 1) * 2;
        b->s = realloc(b->s, b->cap);
        assert_non_null(b->s);
    }
}

static void b64(sbuf *b, const unsigned char *d, size_t n)
{
    static const char a[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (size_t i = 0; i < n; i += 3) {
        unsigned v = (unsigned)d[i] << 16 | (i + 1 < n ? (unsigned)d[i + 1] << 8 : 0) | (i + 2 < n ? d[i + 2] : 0);
        sb_printf(b, "%c%c%c%c", a[v >> 18 & 63], a[v >> 12 & 63], i + 1 < n ? a[v >> 6 & 63] : '=', i + 2 < n ? a[v & 63] : '=');
    }
}

/* zlib (gzip = 0) or gzip (gzip = 1) stream of the data; *n receives its length. */
static unsigned char *deflate_bytes(const unsigned char *d, size_t len, int gzip, size_t *n)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    assert_int_equal(deflateInit2(&z, 9, Z_DEFLATED, gzip ? 31 : 15, 8, Z_DEFAULT_STRATEGY), Z_OK);
    size_t cap = deflateBound(&z, (uLong)len) + 64;
    unsigned char *out = malloc(cap);
    assert_non_null(out);
    z.next_in = (unsigned char *)(uintptr_t)d;
    z.avail_in = (uInt)len;
    z.next_out = out;
    z.avail_out = (uInt)cap;
    assert_int_equal(deflate(&z, Z_FINISH), Z_STREAM_END);
    *n = z.total_out;
    deflateEnd(&z);
    return out;
}

static void pos_of(const char *text, const char *needle, int *line, int *col)
{
    const char *p = strstr(text, needle);
    if (!p) fail_msg("'%s' not in the text", needle);
    *line = 1;
    *col = 1;
    for (const char *q = text; q < p; q++) {
        if (*q == '\n') {
            ++*line;
            *col = 1;
        } else {
            ++*col;
        }
    }
}

/* ---------------------------------------------------------------- map specs */

/* A property: type NULL = untyped (a string, written without a type). */
typedef struct pspec {
    const char *name, *type, *value;
} pspec;
#define MAXP 8

typedef struct tspec {
    int id;
    pspec props[MAXP];
} tspec;

typedef struct tsspec {
    int firstgid;
    const char *name;
    int tilecount;
    tspec tiles[12];
    const char *external; /* file under the test directory: .tsx (XML) or .tsj (JSON) */
} tsspec;

enum { O_RECT, O_ELLIPSE, O_POINT, O_POLYLINE, O_POLYGON, O_TEXT };

typedef struct ospec {
    int id;
    const char *name;
    int kind;
    double x, y, w, h;
    const char *points; /* "x,y x,y ..." */
    pspec props[MAXP];
    double rotation;
    const char *tmpl; /* an object template file (.tx) */
} ospec;

enum { L_TILES, L_OBJECTS, L_GROUP, L_END_GROUP };
enum { E_CSV, E_TILES, E_B64, E_ZLIB, E_GZIP, E_ZSTD, E_COUNT };
static const char *const enc_names[E_COUNT] = {"csv", "xml-tiles", "base64", "base64-zlib", "base64-gzip", "zstd"};

typedef struct lspec {
    const char *name;
    int kind;
    int enc;
    const uint32_t *gids;
    pspec props[MAXP];
    ospec objs[12];
    double offx, offy;
} lspec;

typedef struct mspec {
    int w, h, tw, th;
    const char *orientation;
    pspec props[MAXP];
    tsspec sets[4];
    lspec layers[8];
} mspec;

enum { F_TMX, F_TMJ };

static int nprops(const pspec *p)
{
    int n = 0;
    while (n < MAXP && p[n].name) n++;
    return n;
}

static void xml_props(sbuf *b, const pspec *p, const char *indent)
{
    int n = nprops(p);
    if (!n) return;
    sb_printf(b, "%s<properties>\n", indent);
    for (int i = 0; i < n; i++) {
        if (p[i].type) sb_printf(b, "%s <property name=\"%s\" type=\"%s\" value=\"%s\"/>\n", indent, p[i].name, p[i].type, p[i].value);
        else sb_printf(b, "%s <property name=\"%s\" value=\"%s\"/>\n", indent, p[i].name, p[i].value);
    }
    sb_printf(b, "%s</properties>\n", indent);
}

static void json_props(sbuf *b, const pspec *p)
{
    int n = nprops(p);
    if (!n) return;
    sb_printf(b, ",\n \"properties\":[");
    for (int i = 0; i < n; i++) {
        const char *t = p[i].type;
        int raw = t && (strcmp(t, "bool") == 0 || strcmp(t, "int") == 0 || strcmp(t, "float") == 0 || strcmp(t, "object") == 0);
        sb_printf(b, "%s{\"name\":\"%s\",\"type\":\"%s\",\"value\":%s%s%s}", i ? "," : "", p[i].name, t ? t : "string",
                  raw ? "" : "\"", p[i].value, raw ? "" : "\"");
    }
    sb_printf(b, "]");
}

static void tileset_xml(sbuf *b, const tsspec *t, int in_map)
{
    sb_printf(b, "%s<tileset%s name=\"%s\" tilewidth=\"16\" tileheight=\"16\" tilecount=\"%d\" columns=\"4\">\n",
              in_map ? " " : "", in_map ? "" : " version=\"1.10\"", t->name, t->tilecount);
    for (int i = 0; i < 12 && (t->tiles[i].id || nprops(t->tiles[i].props)); i++) {
        sb_printf(b, "  <tile id=\"%d\">\n", t->tiles[i].id);
        xml_props(b, t->tiles[i].props, "   ");
        sb_printf(b, "  </tile>\n");
    }
    sb_printf(b, "%s</tileset>\n", in_map ? " " : "");
}

static void tileset_json(sbuf *b, const tsspec *t)
{
    sb_printf(b, "\"name\":\"%s\", \"tilewidth\":16, \"tileheight\":16, \"tilecount\":%d, \"columns\":4, \"tiles\":[", t->name,
              t->tilecount);
    for (int i = 0; i < 12 && (t->tiles[i].id || nprops(t->tiles[i].props)); i++) {
        sb_printf(b, "%s\n {\"id\":%d", i ? "," : "", t->tiles[i].id);
        json_props(b, t->tiles[i].props);
        sb_printf(b, "}");
    }
    sb_printf(b, "]");
}

/* The layer's data as TMX/TMJ wants it. */
static void layer_data(sbuf *b, const mspec *m, const lspec *l, int fmt)
{
    size_t n = (size_t)m->w * (size_t)m->h;
    if (l->enc == E_CSV || l->enc == E_TILES) {
        if (fmt == F_TMJ) {
            sb_printf(b, ", \"encoding\":\"csv\", \"data\":[");
            for (size_t k = 0; k < n; k++) sb_printf(b, "%s%u", k ? "," : "", l->gids[k]);
            sb_printf(b, "]");
        } else if (l->enc == E_CSV) {
            sb_printf(b, "  <data encoding=\"csv\">\n");
            for (size_t k = 0; k < n; k++) sb_printf(b, "%u%s", l->gids[k], k + 1 == n ? "\n" : (k + 1) % (size_t)m->w ? "," : ",\n");
            sb_printf(b, "</data>\n");
        } else {
            sb_printf(b, "  <data>\n");
            for (size_t k = 0; k < n; k++) {
                if (l->gids[k]) sb_printf(b, "   <tile gid=\"%u\"/>\n", l->gids[k]);
                else sb_printf(b, "   <tile/>\n");
            }
            sb_printf(b, "  </data>\n");
        }
        return;
    }
    unsigned char *bytes = malloc(n * 4 + 1);
    assert_non_null(bytes);
    for (size_t k = 0; k < n; k++)
        for (int j = 0; j < 4; j++) bytes[4 * k + (size_t)j] = (unsigned char)(l->gids[k] >> (8 * j));
    unsigned char *data = bytes;
    size_t dn = n * 4;
    const char *comp = "";
    if (l->enc == E_ZLIB || l->enc == E_GZIP) {
        data = deflate_bytes(bytes, n * 4, l->enc == E_GZIP, &dn);
        comp = l->enc == E_GZIP ? "gzip" : "zlib";
    } else if (l->enc == E_ZSTD) {
        comp = "zstd";
    }
    if (fmt == F_TMJ) {
        sb_printf(b, ", \"encoding\":\"base64\"%s%s%s, \"data\":\"", *comp ? ", \"compression\":\"" : "", comp, *comp ? "\"" : "");
        b64(b, data, dn);
        sb_printf(b, "\"");
    } else {
        sb_printf(b, "  <data encoding=\"base64\"%s%s%s>\n   ", *comp ? " compression=\"" : "", comp, *comp ? "\"" : "");
        b64(b, data, dn);
        sb_printf(b, "\n  </data>\n");
    }
    if (data != bytes) free(data);
    free(bytes);
}

static const char *const okind_names[] = {"rect", "ellipse", "point", "polyline", "polygon", "text"};

static void object_xml(sbuf *b, const ospec *o)
{
    sb_printf(b, "  <object id=\"%d\"", o->id);
    if (o->name) sb_printf(b, " name=\"%s\"", o->name);
    sb_printf(b, " x=\"%g\" y=\"%g\"", o->x, o->y);
    if (o->w || o->h) sb_printf(b, " width=\"%g\" height=\"%g\"", o->w, o->h);
    if (o->rotation) sb_printf(b, " rotation=\"%g\"", o->rotation);
    if (o->tmpl) sb_printf(b, " template=\"%s\"", o->tmpl);
    sb_printf(b, ">\n");
    xml_props(b, o->props, "   ");
    if (o->kind == O_ELLIPSE) sb_printf(b, "   <ellipse/>\n");
    if (o->kind == O_POINT) sb_printf(b, "   <point/>\n");
    if (o->kind == O_TEXT) sb_printf(b, "   <text>hello</text>\n");
    if (o->kind == O_POLYLINE || o->kind == O_POLYGON) sb_printf(b, "   <%s points=\"%s\"/>\n", okind_names[o->kind], o->points);
    sb_printf(b, "  </object>\n");
}

static void object_json(sbuf *b, const ospec *o)
{
    sb_printf(b, "\n {\"id\":%d, \"name\":\"%s\", \"x\":%g, \"y\":%g, \"width\":%g, \"height\":%g, \"rotation\":%g, \"visible\":true",
              o->id, o->name ? o->name : "", o->x, o->y, o->w, o->h, o->rotation);
    if (o->tmpl) sb_printf(b, ", \"template\":\"%s\"", o->tmpl);
    if (o->kind == O_ELLIPSE) sb_printf(b, ", \"ellipse\":true");
    if (o->kind == O_POINT) sb_printf(b, ", \"point\":true");
    if (o->kind == O_TEXT) sb_printf(b, ", \"text\":{\"text\":\"hello\"}");
    if (o->kind == O_POLYLINE || o->kind == O_POLYGON) {
        sb_printf(b, ", \"%s\":[", okind_names[o->kind]);
        const char *p = o->points;
        int first = 1;
        while (*p) {
            char *end;
            double x = strtod(p, &end);
            double y = strtod(end + 1, &end);
            sb_printf(b, "%s{\"x\":%g,\"y\":%g}", first ? "" : ",", x, y);
            first = 0;
            p = end;
            while (*p == ' ') p++;
        }
        sb_printf(b, "]");
    }
    json_props(b, o->props);
    sb_printf(b, "}");
}

static int nobjs(const lspec *l)
{
    int n = 0;
    while (n < 12 && l->objs[n].id) n++;
    return n;
}

static int nlayers(const mspec *m)
{
    int n = 0;
    while (n < 8 && (m->layers[n].name || m->layers[n].kind == L_END_GROUP)) n++;
    return n;
}

/* Write the map (m.tmx or m.tmj) and its external tilesets; returns the map text (free it). */
static char *emit(const mspec *m, int fmt, const char *file)
{
    sbuf b = {NULL, 0, 0};
    int nl = nlayers(m);
    for (int i = 0; i < 4 && m->sets[i].firstgid; i++) {
        const tsspec *t = &m->sets[i];
        if (!t->external) continue;
        sbuf e = {NULL, 0, 0};
        size_t len = strlen(t->external);
        if (strcmp(t->external + len - 4, ".tsx") == 0) {
            sb_printf(&e, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
            tileset_xml(&e, t, 0);
        } else {
            sb_printf(&e, "{ \"type\":\"tileset\", \"version\":\"1.10\", ");
            tileset_json(&e, t);
            sb_printf(&e, "}\n");
        }
        scratch_write_text(t->external, e.s);
        free(e.s);
    }
    if (fmt == F_TMX) {
        sb_printf(&b, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
        sb_printf(&b, "<map version=\"1.10\" tiledversion=\"1.10.2\" orientation=\"%s\" renderorder=\"right-down\" width=\"%d\" "
                      "height=\"%d\" tilewidth=\"%d\" tileheight=\"%d\" infinite=\"0\" nextlayerid=\"9\" nextobjectid=\"99\">\n",
                  m->orientation ? m->orientation : "orthogonal", m->w, m->h, m->tw, m->th);
        xml_props(&b, m->props, " ");
        for (int i = 0; i < 4 && m->sets[i].firstgid; i++) {
            const tsspec *t = &m->sets[i];
            if (t->external) {
                const char *rel = t->external;
                sb_printf(&b, " <tileset firstgid=\"%d\" source=\"%s\"/>\n", t->firstgid, rel);
            } else {
                sb_printf(&b, " <tileset firstgid=\"%d\"", t->firstgid);
                sbuf e = {NULL, 0, 0};
                tileset_xml(&e, t, 1);
                sb_printf(&b, "%s", e.s + strlen(" <tileset"));
                free(e.s);
            }
        }
        for (int i = 0; i < nl; i++) {
            const lspec *l = &m->layers[i];
            if (l->kind == L_END_GROUP) {
                sb_printf(&b, " </group>\n");
                continue;
            }
            const char *tag = l->kind == L_TILES ? "layer" : l->kind == L_OBJECTS ? "objectgroup" : "group";
            sb_printf(&b, " <%s id=\"%d\" name=\"%s\"", tag, i + 1, l->name);
            if (l->kind == L_TILES) sb_printf(&b, " width=\"%d\" height=\"%d\"", m->w, m->h);
            if (l->offx || l->offy) sb_printf(&b, " offsetx=\"%g\" offsety=\"%g\"", l->offx, l->offy);
            sb_printf(&b, ">\n");
            xml_props(&b, l->props, "  ");
            if (l->kind == L_GROUP) continue;
            if (l->kind == L_TILES) layer_data(&b, m, l, fmt);
            for (int k = 0; k < nobjs(l); k++) object_xml(&b, &l->objs[k]);
            sb_printf(&b, " </%s>\n", tag);
        }
        sb_printf(&b, "</map>\n");
    } else {
        sb_printf(&b, "{ \"type\":\"map\", \"version\":\"1.10\", \"orientation\":\"%s\", \"renderorder\":\"right-down\",\n"
                      " \"width\":%d, \"height\":%d, \"tilewidth\":%d, \"tileheight\":%d, \"infinite\":false",
                  m->orientation ? m->orientation : "orthogonal", m->w, m->h, m->tw, m->th);
        json_props(&b, m->props);
        sb_printf(&b, ",\n \"tilesets\":[");
        for (int i = 0; i < 4 && m->sets[i].firstgid; i++) {
            const tsspec *t = &m->sets[i];
            sb_printf(&b, "%s\n  {\"firstgid\":%d, ", i ? "," : "", t->firstgid);
            if (t->external) sb_printf(&b, "\"source\":\"%s\"", t->external);
            else tileset_json(&b, t);
            sb_printf(&b, "}");
        }
        sb_printf(&b, "],\n \"layers\":[");
        int first = 1;
        for (int i = 0; i < nl; i++) {
            const lspec *l = &m->layers[i];
            if (l->kind == L_END_GROUP) {
                sb_printf(&b, "]}");
                first = 0;
                continue;
            }
            sb_printf(&b, "%s\n {\"id\":%d, \"name\":\"%s\", \"type\":\"%s\", \"visible\":true, \"opacity\":1, \"x\":0, \"y\":0",
                      first ? "" : ",", i + 1, l->name,
                      l->kind == L_TILES ? "tilelayer" : l->kind == L_OBJECTS ? "objectgroup" : "group");
            if (l->offx || l->offy) sb_printf(&b, ", \"offsetx\":%g, \"offsety\":%g", l->offx, l->offy);
            json_props(&b, l->props);
            if (l->kind == L_GROUP) {
                sb_printf(&b, ", \"layers\":[");
                first = 1;
                continue;
            }
            if (l->kind == L_TILES) {
                sb_printf(&b, ", \"width\":%d, \"height\":%d", m->w, m->h);
                layer_data(&b, m, l, fmt);
            } else {
                sb_printf(&b, ", \"draworder\":\"topdown\", \"objects\":[");
                for (int k = 0; k < nobjs(l); k++) {
                    if (k) sb_printf(&b, ",");
                    object_json(&b, &l->objs[k]);
                }
                sb_printf(&b, "]");
            }
            sb_printf(&b, "}");
            first = 0;
        }
        sb_printf(&b, "]\n}\n");
    }
    scratch_write_text(file, b.s);
    return b.s;
}

/* ---------------------------------------------------------------- importing */

typedef struct warnings {
    int count;
    char text[16][600];
} warnings;

static void on_warning(const char *message, void *ctx)
{
    warnings *w = ctx;
    if (w->count < 16) snprintf(w->text[w->count], sizeof w->text[0], "%s", message);
    w->count++;
}

static nt_status import_file(const char *name, nt_level **lv, nt_text_error *e, warnings *w)
{
    size_t len;
    char *text = scratch_read(scratch_path(name), &len);
    nt_status s = tiled_import(scratch_path(name), text, len, lv, e, w ? on_warning : NULL, w);
    free(text);
    return s;
}

static const char *map_name(int fmt) { return fmt == F_TMX ? "m.tmx" : "m.tmj"; }

static nt_level *import_ok(const mspec *m, int fmt, warnings *w)
{
    free(emit(m, fmt, map_name(fmt)));
    nt_level *lv = NULL;
    nt_text_error e;
    nt_status s = import_file(map_name(fmt), &lv, &e, w);
    if (s != NT_OK) fail_msg("import failed (%s): %s", fmt == F_TMX ? "tmx" : "tmj", e.message);
    assert_non_null(lv);
    return lv;
}

/* The message after the directory of the test files ("m.tmx:3:4: ..."). */
static const char *short_msg(const nt_text_error *e)
{
    size_t n = strlen(scratch_dir());
    return strncmp(e->message, scratch_dir(), n) == 0 && e->message[n] == '/' ? e->message + n + 1 : e->message;
}

/* Import the file and expect an error whose message (after the directory) is `want`. */
static void expect_error_file(const char *name, const char *want)
{
    nt_level *lv = (nt_level *)&lv;
    nt_text_error e;
    nt_status s = import_file(name, &lv, &e, NULL);
    if (s == NT_OK) fail_msg("import of %s succeeded, expected: %s", name, want);
    assert_int_equal(s, NT_ERR_PARSE);
    assert_null(lv);
    if (strcmp(short_msg(&e), want) != 0) fail_msg("message:\n  %s\nexpected:\n  %s", short_msg(&e), want);
}

static void expect_error(const mspec *m, int fmt, const char *want)
{
    free(emit(m, fmt, map_name(fmt)));
    expect_error_file(map_name(fmt), want);
}

static char *level_text(const nt_level *lv)
{
    size_t n = nt_level_write(lv, NULL, 0);
    char *s = malloc(n + 1);
    assert_non_null(s);
    nt_level_write(lv, s, n + 1);
    return s;
}

static void expect_in(const char *text, const char *needle)
{
    if (!strstr(text, needle)) fail_msg("expected to find:\n%s\nin:\n%s", needle, text);
}

/* The level's text parses back to the same text, and builds a world. */
static void check_roundtrip_and_world(const nt_level *lv)
{
    char *t = level_text(lv);
    nt_level *back = NULL;
    nt_text_error e;
    if (nt_level_parse("back.ntl", t, strlen(t), &back, &e) != NT_OK) fail_msg("reparse: %s\n%s", e.message, t);
    char *t2 = level_text(back);
    assert_string_equal(t, t2);
    nt_world *w = NULL;
    assert_int_equal(nt_level_create_world(lv, &w, NULL, 0), NT_OK);
    for (int y = 0; y < lv->height; y++)
        for (int x = 0; x < lv->width; x++) {
            size_t k = (size_t)y * (size_t)lv->width + (size_t)x;
            assert_int_equal(nt_world_get_tile(w, x, y), lv->tiles[k]);
            assert_int_equal(nt_world_get_cell_material(w, x, y), lv->cell_materials[k]);
            assert_int_equal(nt_world_get_cell_flags(w, x, y), lv->cell_flags[k]);
        }
    nt_world_destroy(w);
    nt_level_destroy(back);
    free(t);
    free(t2);
}

#define TILE(x, y) (lv->tiles[(size_t)(y) * (size_t)lv->width + (size_t)(x)])

/* ---------------------------------------------------------------- flips vs geometry */

/* Sample points: a 32 x 32 grid of dyadic points, exact under x -> 1 - x and x <-> y. */
static int shows(int tile, uint32_t flags, double qx, double qy)
{
    /* The displayed tile at q is the source at T^-1(q), T = H . V . D (D first). */
    double x = qx, y = qy;
    if (flags & TILED_FLIP_H) x = 1 - x;
    if (flags & TILED_FLIP_V) y = 1 - y;
    if (flags & TILED_FLIP_D) {
        double t = x;
        x = y;
        y = t;
    }
    return nt_tile_contains_point(tile, nt_v2((nt_real)x, (nt_real)y));
}

static void test_flip_geometry(void **state)
{
    (void)state;
    for (int t = 0; t < NT_TILE_COUNT; t++) {
        for (uint32_t f = 0; f < 8; f++) {
            uint32_t flags = (f & 1 ? TILED_FLIP_H : 0) | (f & 2 ? TILED_FLIP_V : 0) | (f & 4 ? TILED_FLIP_D : 0);
            /* Which N tiles show exactly the flipped shape (at every sample)? */
            int match = -1, matches = 0;
            for (int u = 0; u < NT_TILE_COUNT; u++) {
                int same = 1;
                for (int i = 0; i < 32 && same; i++)
                    for (int j = 0; j < 32 && same; j++) {
                        double qx = (i + 0.5) / 32, qy = (j + 0.5) / 32;
                        same = shows(t, flags, qx, qy) == nt_tile_contains_point(u, nt_v2((nt_real)qx, (nt_real)qy));
                    }
                if (same) match = u, matches++;
            }
            assert_int_equal(matches, 1); /* the N set is closed under all eight flips */
            int got = tiled_flip_tile(t, flags);
            if (got != match)
                fail_msg("%s flipped (H %d V %d D %d): importer says %s, geometry says %s", nt_tile_get_info(t)->name, f & 1,
                         f >> 1 & 1, f >> 2 & 1, got >= 0 ? nt_tile_get_info(got)->name : "none", nt_tile_get_info(match)->name);
            /* The hexagonal flag means nothing on orthogonal maps. */
            assert_int_equal(tiled_flip_tile(t, flags | TILED_FLIP_HEX), got);
        }
    }
    /* A few by name, as a Tiled user sees them. */
    assert_int_equal(tiled_flip_tile(NT_TILE_45DEGpn, TILED_FLIP_H), NT_TILE_45DEGnn);
    assert_int_equal(tiled_flip_tile(NT_TILE_22DEGpnS, TILED_FLIP_D), NT_TILE_67DEGnpS);
    assert_int_equal(tiled_flip_tile(NT_TILE_22DEGppB, TILED_FLIP_D), NT_TILE_67DEGppB);
    assert_int_equal(tiled_flip_tile(NT_TILE_HALFd, TILED_FLIP_D), NT_TILE_HALFr);
    assert_int_equal(tiled_flip_tile(NT_TILE_HALFd, TILED_FLIP_D | TILED_FLIP_H), NT_TILE_HALFl); /* rotated 90° clockwise */
    assert_int_equal(tiled_flip_tile(NT_TILE_CONVEXpn, TILED_FLIP_H | TILED_FLIP_V), NT_TILE_CONVEXnp);
    assert_int_equal(tiled_flip_tile(-1, 0), -1);
    assert_int_equal(tiled_flip_tile(NT_TILE_COUNT, 0), -1);
}

/* ---------------------------------------------------------------- a base map */

/* 6 x 4 cells of 16: tileset "n" (firstgid 1): tile 0 plain (no property), 1 45DEGpn,
 * 2 HALFu one-way, 3 22DEGpnS material 2, 4 FULL material 1, 5 CONVEXpn. */
static const uint32_t base_gids[24] = {
    1, 1, 1, 1, 1, 1,
    1, 0, 2, 0, 3, 1,
    1, 4 | TILED_FLIP_H, 0, 5, 0, 1,
    1, 1, 6 | TILED_FLIP_D | TILED_FLIP_H, 1, 1, 1,
};

static mspec base_map(int enc)
{
    mspec m = {
        .w = 6, .h = 4, .tw = 16, .th = 16,
        .props = {{"title", NULL, "Base"}, {"gravity_y", "float", "200"}},
        .sets = {{.firstgid = 1, .name = "n", .tilecount = 8,
                  .tiles = {{1, {{"ntile", NULL, "45DEGpn"}}},
                            {2, {{"ntile", NULL, "HALFu"}, {"one_way", "bool", "true"}}},
                            {3, {{"ntile", NULL, "22DEGpnS"}, {"material", "int", "2"}}},
                            {4, {{"ntile", NULL, "FULL"}, {"material", "int", "1"}}},
                            {5, {{"ntile", NULL, "CONVEXpn"}}}}}},
        .layers = {{.name = "ground", .kind = L_TILES, .enc = enc, .gids = base_gids, .props = {{"solid", "bool", "true"}}}},
    };
    return m;
}

static void check_base(const nt_level *lv)
{
    assert_int_equal(lv->width, 6);
    assert_int_equal(lv->height, 4);
    assert_true(lv->cell_size == 16);
    assert_string_equal(lv->title, "Base");
    assert_true(lv->gravity.y == 200);
    char *t = level_text(lv);
    /* gid 1 = tile 0 (no property: FULL, the layer is solid); 2 45DEGpn; 3 HALFu one-way;
     * 4|H = 22DEGpnS mirrored = 22DEGnnS ('?'), material 2; 5 FULL material 1;
     * 6|D|H = CONVEXpn turned 90° clockwise = CONVEXpp ('='). */
    expect_in(t, "tiles\n|######|\n|#.2.P#|\n|#?.#.#|\n|##=###|\n");
    expect_in(t, "materials\n|......|\n|......|\n|.2.1..|\n|......|\n");
    expect_in(t, "flags\n|......|\n|....-.|\n|......|\n|......|\n");
    free(t);
    check_roundtrip_and_world(lv);
}

static void test_encodings(void **state)
{
    (void)state;
    char *first = NULL;
    for (int fmt = F_TMX; fmt <= F_TMJ; fmt++) {
        for (int enc = E_CSV; enc <= E_GZIP; enc++) {
            mspec m = base_map(enc);
            warnings w = {0};
            nt_level *lv = import_ok(&m, fmt, &w);
            if (w.count) fail_msg("%s %s: unexpected warning %s", map_name(fmt), enc_names[enc], w.text[0]);
            check_base(lv);
            char *t = level_text(lv);
            if (!first) first = t;
            else {
                assert_string_equal(t, first); /* the same level from every format and encoding */
                free(t);
            }
            nt_level_destroy(lv);
        }
    }
    free(first);
}

/* Tiles without an "ntile" property: FULL in a solid layer, EMPTY otherwise; several
 * layers: the topmost solid tile decides a cell, empty ones never clear it. */
static void test_layers_and_missing_properties(void **state)
{
    (void)state;
    /* gids: 1 = tile 0 (no property), 2 = tile 1 (HALFd), 3 = tile 2 (material 3 only),
     * 4 = tile 3 (HALFd with its own material 3 and one_way false). */
    static const uint32_t under[24] = {1, 1, 1, 0, 0, 0, 3, 0, 0, 0, 0, 0, 2, 2, 2, 2, 2, 2, 0, 0, 0, 0, 0, 0};
    static const uint32_t deco[24] = {1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 0, 0, 0};
    static const uint32_t over[24] = {0, 2, 3, 0, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int fmt = F_TMX; fmt <= F_TMJ; fmt++) {
        mspec m = {
            .w = 6, .h = 4, .tw = 16, .th = 16,
            .sets = {{.firstgid = 1, .name = "t", .tilecount = 4,
                      .tiles = {{1, {{"ntile", NULL, "HALFd"}}}, {2, {{"material", "int", "3"}}},
                                {3, {{"ntile", NULL, "HALFd"}, {"material", "int", "3"}, {"one_way", "bool", "false"}}}}}},
            .layers = {{.name = "walls", .kind = L_TILES, .enc = E_CSV, .gids = under, .props = {{"solid", "bool", "true"}}},
                       {.name = "decoration", .kind = L_TILES, .enc = E_B64, .gids = deco},
                       {.name = "ledges", .kind = L_TILES, .enc = E_ZLIB, .gids = over,
                        .props = {{"one_way", "bool", "true"}, {"material", "int", "5"}}}},
        };
        nt_level *lv = import_ok(&m, fmt, NULL);
        char *t = level_text(lv);
        /* Row 0: the walls are FULL (tile 0 has no property, the layer is solid); the
         * decoration layer is not solid, so its plain tiles are EMPTY and clear nothing;
         * the ledges (on top) put HALFd at x = 1 (the layer's material 5 and one-way)
         * and x = 4 (the tile's own material 3 and one_way false beat the layer's);
         * their tile 2 at x = 2 has no shape in a non-solid layer: the wall stays.
         * Row 1: tile 2 in the solid layer is FULL with its material 3. */
        expect_in(t, "tiles\n|#N#.N.|\n|#.....|\n|NNNNNN|\n|......|\n");
        expect_in(t, "materials\n|.5..3.|\n|3.....|\n|......|\n|......|\n");
        expect_in(t, "flags\n|.-....|\n|......|\n|......|\n|......|\n");
        free(t);
        check_roundtrip_and_world(lv);
        nt_level_destroy(lv);
    }
}

/* Tilesets: embedded, external .tsx and .tsj (in a subdirectory), in any order. */
static void test_tilesets(void **state)
{
    (void)state;
    static const uint32_t gids[6] = {2, 11, 20, 12 | TILED_FLIP_V, 21 | TILED_FLIP_H, 0};
    for (int fmt = F_TMX; fmt <= F_TMJ; fmt++) {
        mspec m = {
            .w = 6, .h = 1, .tw = 24, .th = 24,
            .sets = {{.firstgid = 20, .name = "json", .tilecount = 5, .external = "ts/slopes.tsj",
                      .tiles = {{0, {{"ntile", NULL, "67DEGpnB"}}}, {1, {{"ntile", NULL, "CONCAVEpp"}, {"material", "int", "4"}}}}},
                     {.firstgid = 1, .name = "inline", .tilecount = 9, .tiles = {{1, {{"ntile", NULL, "HALFl"}}}}},
                     {.firstgid = 10, .name = "xml", .tilecount = 10, .external = "ts/halves.tsx",
                      .tiles = {{1, {{"ntile", NULL, "HALFr"}}}, {2, {{"ntile", NULL, "45DEGnp"}, {"one_way", "bool", "true"}}}}}},
            .layers = {{.name = "l", .kind = L_TILES, .enc = E_GZIP, .gids = gids}},
        };
        nt_level *lv = import_ok(&m, fmt, NULL);
        assert_int_equal(TILE(0, 0), NT_TILE_HALFl);
        assert_int_equal(TILE(1, 0), NT_TILE_HALFr);
        assert_int_equal(TILE(2, 0), NT_TILE_67DEGpnB);
        assert_int_equal(TILE(3, 0), NT_TILE_45DEGnn); /* 45DEGnp flipped vertically */
        assert_int_equal(lv->cell_flags[3], NT_CELL_ONE_WAY);
        assert_int_equal(TILE(4, 0), NT_TILE_CONCAVEnp); /* CONCAVEpp flipped horizontally */
        assert_int_equal(lv->cell_materials[4], 4);
        check_roundtrip_and_world(lv);
        nt_level_destroy(lv);
    }
}

/* Image collections number their tiles freely: an id past the tile count is known
 * when the tileset defines it, unknown otherwise. */
static void test_sparse_tile_ids(void **state)
{
    (void)state;
    static const uint32_t ok[2] = {1, 8};
    static const uint32_t bad[2] = {1, 6};
    for (int fmt = F_TMX; fmt <= F_TMJ; fmt++) {
        mspec m = {.w = 2, .h = 1, .tw = 16, .th = 16,
                   .sets = {{.firstgid = 1, .name = "pics", .tilecount = 2,
                             .tiles = {{0, {{"ntile", NULL, "HALFl"}}}, {7, {{"ntile", NULL, "HALFr"}}}}}},
                   .layers = {{.name = "l", .kind = L_TILES, .enc = E_CSV, .gids = ok}}};
        nt_level *lv = import_ok(&m, fmt, NULL);
        assert_int_equal(TILE(0, 0), NT_TILE_HALFl);
        assert_int_equal(TILE(1, 0), NT_TILE_HALFr);
        nt_level_destroy(lv);
        m.layers[0].gids = bad;
        nt_text_error e;
        free(emit(&m, fmt, map_name(fmt)));
        assert_int_equal(import_file(map_name(fmt), &lv, &e, NULL), NT_ERR_PARSE);
        expect_in(e.message, "layer \"l\": cell (1, 0): unknown tile id 6 (the tilesets hold ids 1..2)");
    }
}

/* Every flip combination in a map, checked against tiled_flip_tile (itself checked
 * against the geometry above). */
static void test_flips_in_map(void **state)
{
    (void)state;
    static uint32_t gids[8 * 4];
    static const int shapes[4] = {NT_TILE_22DEGnpB, NT_TILE_67DEGppS, NT_TILE_CONCAVEnn, NT_TILE_HALFu};
    for (int s = 0; s < 4; s++)
        for (uint32_t f = 0; f < 8; f++)
            gids[s * 8 + (int)f] = (uint32_t)(s + 1) | (f & 1 ? TILED_FLIP_H : 0) | (f & 2 ? TILED_FLIP_V : 0) |
                                   (f & 4 ? TILED_FLIP_D : 0) | (s == 3 ? TILED_FLIP_HEX : 0);
    for (int fmt = F_TMX; fmt <= F_TMJ; fmt++) {
        mspec m = {
            .w = 8, .h = 4, .tw = 16, .th = 16,
            .sets = {{.firstgid = 1, .name = "s", .tilecount = 4,
                      .tiles = {{0, {{"ntile", NULL, "22DEGnpB"}}}, {1, {{"ntile", NULL, "67DEGppS"}}},
                                {2, {{"ntile", NULL, "CONCAVEnn"}}}, {3, {{"ntile", NULL, "HALFu"}}}}}},
            .layers = {{.name = "l", .kind = L_TILES, .enc = fmt == F_TMX ? E_TILES : E_B64, .gids = gids}},
        };
        nt_level *lv = import_ok(&m, fmt, NULL);
        for (int s = 0; s < 4; s++)
            for (uint32_t f = 0; f < 8; f++) {
                uint32_t flags = gids[s * 8 + (int)f] & ~TILED_GID_MASK;
                assert_int_equal(TILE((int)f, s), tiled_flip_tile(shapes[s], flags));
            }
        nt_level_destroy(lv);
    }
}

/* ---------------------------------------------------------------- objects */

static void test_objects(void **state)
{
    (void)state;
    static const uint32_t floor_gids[10 * 5] = {0};
    for (int fmt = F_TMX; fmt <= F_TMJ; fmt++) {
        mspec m = {
            .w = 10, .h = 5, .tw = 24, .th = 24,
            .props = {{"friction_model", NULL, "coulomb"}, {"material1", NULL, "0.5 0.9"}, {"seed", "int", "7"}},
            .sets = {{.firstgid = 1, .name = "t", .tilecount = 1}},
            .layers = {
                {.name = "floor", .kind = L_TILES, .enc = E_CSV, .gids = floor_gids},
                {.name = "things", .kind = L_OBJECTS,
                 .objs = {
                     {.id = 1, .name = "spawn", .kind = O_POINT, .x = 36, .y = 84},
                     {.id = 2, .name = "crate", .kind = O_RECT, .x = 100, .y = 40, .w = 20, .h = 10,
                      .props = {{"type", NULL, "dynamic"}, {"mass", "float", "2.5"}, {"bounce", "float", "0.5"}, {"friction", "float", "1.5"}}},
                     {.id = 3, .kind = O_ELLIPSE, .x = 10, .y = 10, .w = 12, .h = 12,
                      .props = {{"type", NULL, "static"}, {"sensor", "bool", "true"}, {"score", "int", "3"}}},
                     {.id = 4, .name = "door", .kind = O_RECT, .x = 200, .y = 48, .w = 24, .h = 48, .props = {{"region", NULL, "exit"}}},
                     {.id = 5, .name = "bin", .kind = O_RECT, .x = 0, .y = 96, .w = 48, .h = 24,
                      .props = {{"region", NULL, "score"}, {"value", "int", "5"}}},
                     {.id = 6, .name = "lift", .kind = O_RECT, .x = 54, .y = 96, .w = 12, .h = 8,
                      .props = {{"type", NULL, "kinematic"}, {"path", NULL, "rail"}, {"phase", "float", "0.25"}}},
                     {.id = 7, .name = "spinner", .kind = O_ELLIPSE, .x = 120, .y = 80, .w = 8, .h = 8,
                      .props = {{"type", NULL, "kinematic"}, {"path", "object", "9"}}},
                     {.id = 8, .name = "mine", .kind = O_ELLIPSE, .x = 150, .y = 20, .w = 8, .h = 6,
                      .props = {{"type", NULL, "static"}, {"sensor", "bool", "true"}, {"deadly", "bool", "true"}}},
                 }},
                {.name = "g", .kind = L_GROUP, .offx = 4, .offy = -2},
                {.name = "paths", .kind = L_OBJECTS, .offx = 1, .offy = 1,
                 .objs = {
                     {.id = 10, .name = "rail", .kind = O_POLYLINE, .x = 55, .y = 99, .points = "0,0 40,0 40,-40",
                      .props = {{"path", NULL, ""}, {"speed", "float", "30"}, {"wait", "float", "0.5"}}},
                     {.id = 9, .name = "wheel", .kind = O_ELLIPSE, .x = 95, .y = 50, .w = 40, .h = 40,
                      .props = {{"path", NULL, "orbit"}, {"speed", "int", "20"}}},
                     {.id = 11, .name = "square", .kind = O_POLYGON, .x = 10, .y = 10, .points = "0,0 10,0 10,10 0,10",
                      .props = {{"path", NULL, ""}, {"speed", "float", "5"}}},
                 }},
                {.kind = L_END_GROUP},
            },
        };
        warnings w = {0};
        nt_level *lv = import_ok(&m, fmt, &w);
        char *t = level_text(lv);
        expect_in(t, "friction-model coulomb\n");
        expect_in(t, "material 1 0.5 0.9\n");
        expect_in(t, "seed 7\n");
        expect_in(t, "player 36 84\n");
        expect_in(t, "region door exit 200 48 224 96\n");
        expect_in(t, "region bin score 0 96 48 120 value 5\n");
        expect_in(t, "path rail pingpong speed 30 wait 0.5 points 60 98 100 98 100 58\n"); /* offsets 4+1, -2+1 */
        expect_in(t, "path wheel orbit speed 20 center 120 69 radius 20\n");
        expect_in(t, "path square loop speed 5 points 15 9 25 9 25 19 15 19\n");
        expect_in(t, "body crate dynamic box 10 5 at 110 45 mass 2.5 material 1.5 0.5\n");
        expect_in(t, "body body3 static circle 6 at 16 16 sensor score 3\n");
        expect_in(t, "body lift kinematic box 6 4 at 60 100 path rail phase 0.25\n");
        expect_in(t, "body spinner kinematic circle 4 at 124 84 path wheel\n");
        expect_in(t, "body mine static circle 3 at 154 23 sensor deadly\n");
        free(t);
        /* The one warning: the mine's ellipse is not a circle. */
        assert_int_equal(w.count, 1);
        expect_in(w.text[0], "warning: layer \"things\": object \"mine\" (id 8): the ellipse is 8 x 6, not a circle; the body is a circle of diameter 6");
        if (fmt == F_TMX) expect_in(w.text[0], "m.tmx:");
        /* The world: bodies where the level says, of the right kinds. */
        nt_world *world = NULL;
        nt_body_id ids[16];
        assert_int_equal(nt_level_instance_count(lv), 5);
        assert_int_equal(nt_level_create_world(lv, &world, ids, 16), NT_OK);
        assert_int_equal(nt_world_get_body_count(world), 5);
        nt_vec2 p = nt_body_get_position(world, ids[0]);
        assert_true(p.x == 110 && p.y == 45);
        assert_int_equal(nt_body_get_type(world, ids[0]), NT_BODY_DYNAMIC);
        assert_true(nt_body_get_mass(world, ids[0]) == (nt_real)2.5);
        nt_shape sh = nt_body_get_shape(world, ids[1]);
        assert_int_equal(sh.type, NT_SHAPE_CIRCLE);
        assert_true(sh.half.x == 6);
        assert_int_equal(nt_body_get_type(world, ids[1]), NT_BODY_STATIC);
        nt_world_destroy(world);
        check_roundtrip_and_world(lv);
        nt_level_destroy(lv);
    }
}

/* Objects larger than a cell become large bodies (issue 18), up to 8 cells across. */
static void test_large_objects(void **state)
{
    (void)state;
    static const uint32_t g[12 * 9] = {0};
    for (int fmt = F_TMX; fmt <= F_TMJ; fmt++) {
        mspec m = {
            .w = 12, .h = 9, .tw = 24, .th = 24,
            .layers = {
                {.name = "floor", .kind = L_TILES, .enc = E_CSV, .gids = g},
                {.name = "things", .kind = L_OBJECTS,
                 .objs = {
                     {.id = 1, .name = "crate", .kind = O_RECT, .x = 24, .y = 48, .w = 24, .h = 48, .props = {{"type", NULL, "dynamic"}}},
                     {.id = 2, .name = "platform", .kind = O_RECT, .x = 120, .y = 60, .w = 96, .h = 12,
                      .props = {{"type", NULL, "static"}}},
                     {.id = 3, .name = "boulder", .kind = O_ELLIPSE, .x = 0, .y = 0, .w = 192, .h = 192,
                      .props = {{"type", NULL, "dynamic"}}},
                     {.id = 4, .name = "slab", .kind = O_RECT, .x = 0, .y = 130, .w = 192, .h = 1, .props = {{"type", NULL, "static"}}},
                 }},
            },
        };
        nt_level *lv = import_ok(&m, fmt, NULL);
        char *t = level_text(lv);
        expect_in(t, "body crate dynamic box 12 24 at 36 72\n");          /* 1 x 2 cells */
        expect_in(t, "body platform static box 48 6 at 168 66\n");        /* 4 cells wide */
        expect_in(t, "body boulder dynamic circle 96 at 96 96\n");        /* 8 cells across: the cap */
        expect_in(t, "body slab static box 96 0.5 at 96 130.5\n");
        free(t);
        assert_int_equal(nt_level_validate(lv, NULL), NT_OK);
        nt_world *w = NULL;
        assert_int_equal(nt_level_create_world(lv, &w, NULL, 0), NT_OK);
        assert_int_equal(nt_world_get_body_count(w), 4);
        nt_world_destroy(w);
        nt_level_destroy(lv);
    }
}

static void test_object_warnings(void **state)
{
    (void)state;
    static const uint32_t g[4] = {0};
    for (int fmt = F_TMX; fmt <= F_TMJ; fmt++) {
        mspec m = {
            .w = 2, .h = 2, .tw = 32, .th = 32,
            .layers = {{.name = "l", .kind = L_TILES, .enc = E_CSV, .gids = g},
                       {.name = "o", .kind = L_OBJECTS,
                        .objs = {{.id = 1, .name = "spawn", .kind = O_POINT, .x = 10, .y = 20},
                                 {.id = 2, .name = "spawn", .kind = O_POINT, .x = 30, .y = 20},
                                 {.id = 3, .name = "marker", .kind = O_POINT, .x = 1, .y = 2},
                                 {.id = 4, .name = "line", .kind = O_POLYLINE, .points = "0,0 5,5"},
                                 {.id = 5, .name = "label", .kind = O_TEXT, .x = 1, .y = 1, .w = 10, .h = 10},
                                 {.id = 6, .name = "box", .kind = O_RECT, .x = 1, .y = 1, .w = 10, .h = 10, .rotation = 45},
                                 {.id = 7, .name = "copy", .kind = O_RECT, .x = 1, .y = 1, .tmpl = "crate.tx"}}}},
        };
        warnings w = {0};
        nt_level *lv = import_ok(&m, fmt, &w);
        assert_int_equal(w.count, 6);
        expect_in(w.text[0], "object \"spawn\" (id 2): a second player spawn; skipped");
        expect_in(w.text[1], "object \"marker\" (id 3): a point that is not named spawn; skipped");
        expect_in(w.text[2], "object \"line\" (id 4): a polyline without a \"path\" property; skipped");
        expect_in(w.text[3], "object \"label\" (id 5): text objects are not imported; skipped");
        expect_in(w.text[4], "object \"box\" (id 6): rotation ignored (ntile bodies never rotate)");
        expect_in(w.text[5], "object \"copy\" (id 7): objects from templates (.tx) are not imported (detach the template); skipped");
        if (fmt == F_TMX) {
            char *text = emit(&m, fmt, "m.tmx");
            int line, col;
            pos_of(text, "<object id=\"2\"", &line, &col);
            char want[64];
            snprintf(want, sizeof want, "m.tmx:%d:%d: warning: ", line, col);
            expect_in(w.text[0], want);
            free(text);
        }
        assert_true(lv->has_player);
        assert_true(lv->player.x == 10 && lv->player.y == 20);
        nt_level_destroy(lv);
    }
}

/* ---------------------------------------------------------------- errors */

static void test_errors_in_specs(void **state)
{
    (void)state;
    static const uint32_t one[4] = {1, 0, 0, 0};
    static const uint32_t unknown[4] = {0, 0, 0, 9};
    for (int fmt = F_TMX; fmt <= F_TMJ; fmt++) {
        const char *f = map_name(fmt);
        char want[600];
        mspec m = base_map(E_CSV);
        /* Non-orthogonal, non-square tiles. */
        m.orientation = "isometric";
        snprintf(want, sizeof want, "%s%s: map: orientation \"isometric\" is not supported (only orthogonal maps)", f,
                 fmt == F_TMX ? ":2:1" : "");
        expect_error(&m, fmt, want);
        m = base_map(E_CSV);
        m.th = 8;
        snprintf(want, sizeof want, "%s%s: map: tiles are 16 x 8, but ntile cells are square (tilewidth must equal tileheight)",
                 f, fmt == F_TMX ? ":2:1" : "");
        expect_error(&m, fmt, want);
        /* zstd. */
        m = base_map(E_ZSTD);
        char *text = emit(&m, fmt, f);
        int line, col;
        char at[32] = "";
        if (fmt == F_TMX) {
            pos_of(text, "<data", &line, &col);
            snprintf(at, sizeof at, ":%d:%d", line, col);
        }
        free(text);
        snprintf(want, sizeof want, "%s%s: layer \"ground\": zstd compression is not supported; save the map with CSV, "
                 "base64 (uncompressed), base64 (zlib) or base64 (gzip) as the tile layer format (Map > Map Properties)", f, at);
        expect_error_file(f, want);
        /* Unknown gid. */
        mspec u = {.w = 2, .h = 2, .tw = 8, .th = 8, .sets = {{.firstgid = 1, .name = "a", .tilecount = 4}, {.firstgid = 5, .name = "b", .tilecount = 3}},
                   .layers = {{.name = "ground", .kind = L_TILES, .enc = E_B64, .gids = unknown}}};
        text = emit(&u, fmt, f);
        at[0] = '\0';
        if (fmt == F_TMX) {
            pos_of(text, "<data", &line, &col);
            snprintf(at, sizeof at, ":%d:%d", line, col);
        }
        free(text);
        snprintf(want, sizeof want, "%s%s: layer \"ground\": cell (1, 1): unknown tile id 9 (the tilesets hold ids 1..7)", f, at);
        expect_error_file(f, want);
        /* A tile with an unknown N name, a property of the wrong type. */
        mspec t = {.w = 2, .h = 2, .tw = 8, .th = 8,
                   .sets = {{.firstgid = 1, .name = "a", .tilecount = 4, .tiles = {{0, {{"ntile", NULL, "45degpn"}}}}}},
                   .layers = {{.name = "ground", .kind = L_TILES, .enc = E_CSV, .gids = one}}};
        text = emit(&t, fmt, f);
        at[0] = '\0';
        if (fmt == F_TMX) {
            pos_of(text, "<property name=\"ntile\"", &line, &col);
            snprintf(at, sizeof at, ":%d:%d", line, col);
        }
        free(text);
        snprintf(want, sizeof want, "%s%s: tileset \"a\": tile 0: property \"ntile\": unknown tile name \"45degpn\" (did you "
                 "mean \"45DEGpn\"? names are case-sensitive)", f, at);
        expect_error_file(f, want);
        t.sets[0].tiles[0].props[0] = (pspec){"ntile", NULL, "BANANA"};
        free(emit(&t, fmt, f));
        nt_level *lv = NULL;
        nt_text_error e;
        assert_int_equal(import_file(f, &lv, &e, NULL), NT_ERR_PARSE);
        expect_in(e.message, "unknown tile name \"BANANA\" (expected an N tile name: EMPTY, FULL, 45DEGpn, ..., HALFl;");
        t.sets[0].tiles[0].props[0] = (pspec){"one_way", "int", "3"};
        free(emit(&t, fmt, f));
        assert_int_equal(import_file(f, &lv, &e, NULL), NT_ERR_PARSE);
        expect_in(e.message, "tileset \"a\": tile 0: property \"one_way\" must be a bool (true or false), not int \"3\"");
        t.sets[0].tiles[0].props[0] = (pspec){"material", "int", "16"};
        free(emit(&t, fmt, f));
        assert_int_equal(import_file(f, &lv, &e, NULL), NT_ERR_PARSE);
        expect_in(e.message, "tileset \"a\": tile 0: property \"material\" must be an integer in 0..15, not int \"16\"");
        t.sets[0].tiles[0].props[0] = (pspec){0};
        t.layers[0].props[0] = (pspec){"solid", NULL, "yes"};
        free(emit(&t, fmt, f));
        assert_int_equal(import_file(f, &lv, &e, NULL), NT_ERR_PARSE);
        expect_in(e.message, "layer \"ground\": property \"solid\" must be a bool (true or false), not string \"yes\"");
        /* A missing external tileset. */
        t.layers[0].props[0] = (pspec){0};
        t.sets[0].external = "ts/gone.tsx";
        free(emit(&t, fmt, f));
        unlink(scratch_path("ts/gone.tsx"));
        assert_int_equal(import_file(f, &lv, &e, NULL), NT_ERR_PARSE);
        snprintf(want, sizeof want, "tileset 1: cannot read \"ts/gone.tsx\" (%s): No such file or directory", scratch_path("ts/gone.tsx"));
        expect_in(e.message, want);
        assert_null(lv);
    }
}

static void test_object_errors(void **state)
{
    (void)state;
    static const uint32_t g[4] = {0};
    /* Each message points at the object, or at the property at fault (TMX). */
    struct {
        ospec o;
        const char *want;
        const char *at;
    } cases[] = {
        /* Cells of 16: bodies up to 8 cells (128) across. */
        {{.id = 3, .name = "big", .kind = O_RECT, .x = 1, .y = 1, .w = 129, .h = 4},
         "layer \"o\": object \"big\" (id 3): a box of 129 x 4 is larger than a body can be (at most 128 x 128, 8 x 8 cells)", NULL},
        {{.id = 4, .name = "ball", .kind = O_ELLIPSE, .x = 1, .y = 1, .w = 130, .h = 130},
         "layer \"o\": object \"ball\" (id 4): a circle of diameter 130 is larger than a body can be (diameter at most 128, 8 cells)", NULL},
        {{.id = 17, .name = "tall", .kind = O_RECT, .x = 1, .y = 1, .w = 16, .h = 128.5},
         "layer \"o\": object \"tall\" (id 17): a box of 16 x 128.5 is larger than a body can be (at most 128 x 128, 8 x 8 cells)", NULL},
        /* Above half a cell, a body lies wholly inside the map (32 x 32 here). */
        {{.id = 18, .name = "edge", .kind = O_RECT, .x = 20, .y = 1, .w = 20, .h = 4},
         "layer \"o\": object \"edge\" (id 18): the body is larger than half a cell, so it must lie inside the map (0 0 .. 32 32)", NULL},
        {{.id = 5, .name = "my crate", .kind = O_RECT, .x = 1, .y = 1, .w = 4, .h = 4},
         "layer \"o\": object \"my crate\" (id 5): \"my crate\" is not an ntile name (a letter or '_', then letters, digits, '_', '-' or '.', at most 31 characters)", NULL},
        {{.id = 6, .name = "a", .kind = O_RECT, .x = 1, .y = 1, .w = 4, .h = 4, .props = {{"type", NULL, "floating"}}},
         "layer \"o\": object \"a\" (id 6): property \"type\": \"floating\" is not static, kinematic or dynamic", "<property name=\"type\""},
        {{.id = 7, .name = "a", .kind = O_RECT, .x = 1, .y = 1, .w = 4, .h = 4, .props = {{"mass", "float", "0"}}},
         "layer \"o\": object \"a\" (id 7): property \"mass\" must be > 0", "<property name=\"mass\""},
        {{.id = 8, .name = "a", .kind = O_RECT, .x = 1, .y = 1, .w = 4, .h = 4, .props = {{"friction", "float", "2"}}},
         "layer \"o\": object \"a\" (id 8): property \"friction\" must be in 0..1 (the limit of the N friction model)", "<property name=\"friction\""},
        {{.id = 9, .name = "r", .kind = O_RECT, .x = 1, .y = 1, .w = 4, .h = 4, .props = {{"region", NULL, "score"}}},
         "layer \"o\": object \"r\" (id 9): a score region needs a \"value\" property (points per body, 1..1000000)", NULL},
        {{.id = 10, .name = "r", .kind = O_RECT, .x = 1, .y = 1, .w = 4, .h = 4, .props = {{"region", NULL, "lava"}}},
         "layer \"o\": object \"r\" (id 10): property \"region\": \"lava\" is not zone, exit, score or kill", "<property name=\"region\""},
        {{.id = 11, .name = "p", .kind = O_POLYLINE, .points = "0,0 4,4", .props = {{"path", NULL, ""}}},
         "layer \"o\": object \"p\" (id 11): a path needs a \"speed\" property (units per second, > 0)", NULL},
        {{.id = 12, .name = "p", .kind = O_POLYLINE, .points = "0,0", .props = {{"path", NULL, ""}, {"speed", "int", "3"}}},
         "layer \"o\": object \"p\" (id 12): a path needs 2 to 64 points, this one has 1", NULL},
        {{.id = 13, .name = "b", .kind = O_RECT, .x = 1, .y = 1, .w = 4, .h = 4, .props = {{"path", NULL, "nowhere"}}},
         "layer \"o\": object \"b\" (id 13): property \"path\": no path is called \"nowhere\"", "<property name=\"path\""},
        {{.id = 14, .name = "b", .kind = O_RECT, .x = 1, .y = 1, .w = 4, .h = 4, .props = {{"sensor", "bool", "false"}, {"score", "int", "2"}}},
         "layer \"o\": object \"b\" (id 14): a body with a score must be a sensor (set \"sensor\")", NULL},
        {{.id = 15, .name = "b", .kind = O_RECT, .x = 5000, .y = 1, .w = 4, .h = 4},
         "layer \"o\": object \"b\" (id 15): the body lies more than 64 cells outside the map", NULL},
        {{.id = 16, .name = "b", .kind = O_RECT, .x = 1, .y = 1, .w = 0, .h = 4},
         "layer \"o\": object \"b\" (id 16): a body needs a width and a height", NULL},
    };
    for (int fmt = F_TMX; fmt <= F_TMJ; fmt++) {
        for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
            mspec m = {.w = 2, .h = 2, .tw = 16, .th = 16,
                       .layers = {{.name = "l", .kind = L_TILES, .enc = E_CSV, .gids = g}, {.name = "o", .kind = L_OBJECTS}}};
            m.layers[1].objs[0] = cases[i].o;
            char *text = emit(&m, fmt, map_name(fmt));
            char want[800];
            if (fmt == F_TMX) {
                char needle[32];
                int line, col;
                snprintf(needle, sizeof needle, "<object id=\"%d\"", cases[i].o.id);
                pos_of(text, cases[i].at ? cases[i].at : needle, &line, &col);
                snprintf(want, sizeof want, "m.tmx:%d:%d: %s", line, col, cases[i].want);
            } else {
                snprintf(want, sizeof want, "m.tmj: %s", cases[i].want);
            }
            free(text);
            expect_error_file(map_name(fmt), want);
        }
        /* Two objects with one name. */
        mspec m = {.w = 2, .h = 2, .tw = 16, .th = 16,
                   .layers = {{.name = "o", .kind = L_OBJECTS,
                               .objs = {{.id = 1, .name = "x", .kind = O_RECT, .x = 1, .y = 1, .w = 4, .h = 4},
                                        {.id = 2, .name = "x", .kind = O_RECT, .x = 9, .y = 1, .w = 4, .h = 4,
                                         .props = {{"region", NULL, "zone"}}}}}}};
        free(emit(&m, fmt, map_name(fmt)));
        nt_level *lv = NULL;
        nt_text_error e;
        assert_int_equal(import_file(map_name(fmt), &lv, &e, NULL), NT_ERR_PARSE);
        expect_in(e.message, "object \"x\" (id 2): the name \"x\" is already used by another object");
    }
}

/* A UTF-8 byte order mark before the JSON is skipped (as before the XML); a key
 * written twice in one object is an error naming the key and both places. */
static void test_bom_and_duplicate_keys(void **state)
{
    (void)state;
    mspec m = base_map(0);
    char *text = emit(&m, F_TMJ, "plain.tmj");
    size_t n = strlen(text);
    char *bom = malloc(n + 4);
    assert_non_null(bom);
    memcpy(bom, "\xef\xbb\xbf", 3);
    memcpy(bom + 3, text, n + 1);
    scratch_write("bom.tmj", bom, n + 3);
    nt_level *lv = NULL;
    nt_text_error e;
    nt_status s = import_file("bom.tmj", &lv, &e, NULL);
    if (s != NT_OK) fail_msg("BOM: %s", e.message);
    nt_level_destroy(lv);
    free(bom);
    free(text);
    scratch_write_text("dup.tmj", "{\n \"width\": 2,\n \"layers\": [{\"a\": 1, \"b\": {\"a\": 2}}],\n  \"width\": 3\n}\n");
    expect_error_file("dup.tmj", "dup.tmj:4:3: duplicate key \"width\" (first at line 2, column 2)");
}

/* Hand-written malformed files: syntax errors with their positions, bad data. */
static void test_malformed_files(void **state)
{
    (void)state;
    scratch_write_text("bad.tmj", "{\n \"width\": 2,\n \"height\": ,\n}\n");
    nt_level *lv = NULL;
    nt_text_error e;
    assert_int_equal(import_file("bad.tmj", &lv, &e, NULL), NT_ERR_PARSE);
    assert_int_equal(e.line, 3);
    assert_true(e.column >= 11 && e.column <= 13);
    expect_in(short_msg(&e), "bad.tmj:3:");
    expect_in(e.message, ": bad JSON: ");
    scratch_write_text("bad.tmx", "<?xml version=\"1.0\"?>\n<map width=\"2\" height=\"2\">\n  <layer name=\"a\">\n  </lay>\n</map>\n");
    expect_error_file("bad.tmx", "bad.tmx:4:5: bad XML: mismatched tag");
    scratch_write_text("empty.tmx", "");
    assert_int_equal(import_file("empty.tmx", &lv, &e, NULL), NT_ERR_PARSE);
    expect_in(e.message, "empty.tmx:1:1: bad XML: ");
    scratch_write_text("notmap.tmx", "<?xml version=\"1.0\"?>\n<tileset name=\"x\"/>\n");
    expect_error_file("notmap.tmx", "notmap.tmx:2:1: map: not a Tiled map (the document element is <tileset>, expected <map>)");
    scratch_write_text("array.tmj", "[1, 2]");
    expect_error_file("array.tmj", "array.tmj: map: the file holds an array, not a Tiled map object");
    scratch_write_text("nowidth.tmj", "{\"type\":\"map\", \"height\":2, \"tilewidth\":8, \"tileheight\":8}");
    expect_error_file("nowidth.tmj", "nowidth.tmj: map: missing \"width\"");
    scratch_write_text("inf.tmx", "<map orientation=\"orthogonal\" width=\"2\" height=\"2\" tilewidth=\"8\" tileheight=\"8\" infinite=\"1\"/>");
    expect_error_file("inf.tmx", "inf.tmx:1:1: map: infinite maps are not supported (turn off Map > Map Properties > Infinite)");
    scratch_write_text("big.tmj", "{\"width\":5000, \"height\":2, \"tilewidth\":8, \"tileheight\":8}");
    expect_error_file("big.tmj", "big.tmj: map: 5000 x 2 tiles; ntile maps have 1..4096 tiles a side");
    /* Data: a bad base64 character (its line and column), wrong lengths, bad zlib. */
    const char *head = "<map orientation=\"orthogonal\" width=\"2\" height=\"2\" tilewidth=\"8\" tileheight=\"8\">\n"
                       " <tileset firstgid=\"1\" name=\"t\" tilecount=\"4\"/>\n <layer name=\"g\" width=\"2\" height=\"2\">\n";
    char buf[2048];
    snprintf(buf, sizeof buf, "%s  <data encoding=\"base64\">\n   AQAAAAAA*AAAAAAAAAAAAA==\n  </data>\n </layer>\n</map>\n", head);
    scratch_write_text("b64.tmx", buf);
    expect_error_file("b64.tmx", "b64.tmx:5:12: layer \"g\": bad base64 data: invalid character \"*\" at byte 13");
    snprintf(buf, sizeof buf, "%s  <data encoding=\"base64\">AQAAAAAAAAAAAAAA</data>\n </layer>\n</map>\n", head);
    scratch_write_text("short.tmx", buf);
    expect_error_file("short.tmx", "short.tmx:4:3: layer \"g\": wrong data length: 12 bytes, expected 16 (2 x 2 tiles of 4 bytes)");
    snprintf(buf, sizeof buf, "%s  <data encoding=\"base64\">AQA</data>\n </layer>\n</map>\n", head);
    scratch_write_text("trunc.tmx", buf);
    expect_error_file("trunc.tmx", "trunc.tmx:4:3: layer \"g\": wrong data length: 2 bytes, expected 16 (2 x 2 tiles of 4 bytes)");
    snprintf(buf, sizeof buf, "%s  <data encoding=\"base64\">AQ=A</data>\n </layer>\n</map>\n", head);
    scratch_write_text("pad.tmx", buf);
    expect_error_file("pad.tmx", "pad.tmx:4:30: layer \"g\": bad base64 data: data after the '=' padding: \"A\" at byte 4");
    snprintf(buf, sizeof buf, "%s  <data encoding=\"csv\">\n1,2,\n3\n</data>\n </layer>\n</map>\n", head);
    scratch_write_text("csv3.tmx", buf);
    expect_error_file("csv3.tmx", "csv3.tmx:4:3: layer \"g\": wrong data length: 3 tiles, expected 4 (2 x 2)");
    snprintf(buf, sizeof buf, "%s  <data encoding=\"csv\">\n1,2,\n3,x4\n</data>\n </layer>\n</map>\n", head);
    scratch_write_text("csvx.tmx", buf);
    expect_error_file("csvx.tmx", "csvx.tmx:6:3: layer \"g\": bad CSV data: \"x4\" is not a tile id (item 4)");
    snprintf(buf, sizeof buf, "%s  <data encoding=\"base64\" compression=\"zlib\">AQAAAAAAAAAAAAAA</data>\n </layer>\n</map>\n", head);
    scratch_write_text("zbad.tmx", buf);
    assert_int_equal(import_file("zbad.tmx", &lv, &e, NULL), NT_ERR_PARSE);
    expect_in(e.message, "zbad.tmx:4:3: layer \"g\": bad zlib data: ");
    snprintf(buf, sizeof buf, "%s  <data encoding=\"base64\" compression=\"lz4\">AQAAAAAAAAAAAAAA</data>\n </layer>\n</map>\n", head);
    scratch_write_text("lz4.tmx", buf);
    expect_error_file("lz4.tmx", "lz4.tmx:4:3: layer \"g\": unknown compression \"lz4\" (expected zlib, gzip or none)");
    snprintf(buf, sizeof buf, "%s  <data encoding=\"hex\">00</data>\n </layer>\n</map>\n", head);
    scratch_write_text("hex.tmx", buf);
    expect_error_file("hex.tmx", "hex.tmx:4:3: layer \"g\": unknown encoding \"hex\" (expected csv or base64)");
    /* Compressed data of the wrong length (longer, shorter, cut off), JSON too. */
    unsigned char raw[20];
    memset(raw, 0, sizeof raw);
    for (int len = 12; len <= 20; len += 4) {
        for (int gz = 0; gz < 2; gz++) {
            size_t n;
            unsigned char *z = deflate_bytes(raw, (size_t)len, gz, &n);
            sbuf b = {NULL, 0, 0};
            sb_printf(&b, "{\"width\":2, \"height\":2, \"tilewidth\":8, \"tileheight\":8, \"tilesets\":[{\"firstgid\":1, \"tilecount\":1}],"
                          "\"layers\":[{\"name\":\"g\", \"type\":\"tilelayer\", \"width\":2, \"height\":2, \"encoding\":\"base64\","
                          "\"compression\":\"%s\", \"data\":\"", gz ? "gzip" : "zlib");
            b64(&b, z, len == 16 ? n - 3 : n);
            sb_printf(&b, "\"}]}");
            scratch_write_text("z.tmj", b.s);
            free(b.s);
            free(z);
            char want[200];
            if (len == 12) snprintf(want, sizeof want, "z.tmj: layer \"g\": wrong data length: 3 tiles, expected 4 (2 x 2)");
            else if (len == 16) snprintf(want, sizeof want, "z.tmj: layer \"g\": bad %s data: the compressed data is truncated", gz ? "gzip" : "zlib");
            else snprintf(want, sizeof want, "z.tmj: layer \"g\": bad %s data: the data holds more than 4 tiles", gz ? "gzip" : "zlib");
            expect_error_file("z.tmj", want);
        }
    }
    /* JSON arrays of the wrong length, non-integer ids. */
    scratch_write_text("arr.tmj", "{\"width\":2, \"height\":2, \"tilewidth\":8, \"tileheight\":8,"
                          "\"layers\":[{\"name\":\"g\", \"type\":\"tilelayer\", \"width\":2, \"height\":2, \"data\":[0,0,0]}]}");
    expect_error_file("arr.tmj", "arr.tmj: layer \"g\": wrong data length: 3 tiles, expected 4 (2 x 2)");
    scratch_write_text("arr2.tmj", "{\"width\":2, \"height\":2, \"tilewidth\":8, \"tileheight\":8,"
                           "\"layers\":[{\"name\":\"g\", \"type\":\"tilelayer\", \"width\":2, \"height\":2, \"data\":[0,0,\"1\",0]}]}");
    expect_error_file("arr2.tmj", "arr2.tmj: layer \"g\": data item 3 is not a tile id (an integer 0..4294967295)");
    scratch_write_text("lsize.tmj", "{\"width\":2, \"height\":2, \"tilewidth\":8, \"tileheight\":8,"
                            "\"layers\":[{\"name\":\"g\", \"type\":\"tilelayer\", \"width\":3, \"height\":2, \"data\":[0,0,0,0,0,0]}]}");
    expect_error_file("lsize.tmj", "lsize.tmj: layer \"g\": 3 x 2 tiles, but the map is 2 x 2");
    scratch_write_text("chunks.tmj", "{\"width\":2, \"height\":2, \"tilewidth\":8, \"tileheight\":8,"
                             "\"layers\":[{\"name\":\"g\", \"type\":\"tilelayer\", \"width\":2, \"height\":2, \"chunks\":[]}]}");
    expect_error_file("chunks.tmj", "chunks.tmj: layer \"g\": chunked data (an infinite map) is not supported: turn off Map > Map Properties > Infinite");
    /* A broken external tileset: its own file and position. */
    scratch_write_text("ts/broken.tsx", "<?xml version=\"1.0\"?>\n<tileset name=\"b\" tilecount=\"2\">\n <tile id=\"zero\"/>\n</tileset>\n");
    scratch_write_text("ts/broken.tsj", "{\"name\":\"b\",\n \"tiles\": [\n {\"id\": 0,}]}");
    scratch_write_text("ext.tmx", "<map width=\"1\" height=\"1\" tilewidth=\"8\" tileheight=\"8\">\n <tileset firstgid=\"1\" source=\"ts/broken.tsx\"/>\n</map>\n");
    char want[800];
    snprintf(want, sizeof want, "%s:3:2: tileset \"b\": attribute \"id\" must be an integer, not \"zero\"", scratch_path("ts/broken.tsx"));
    assert_int_equal(import_file("ext.tmx", &lv, &e, NULL), NT_ERR_PARSE);
    assert_string_equal(e.message, want);
    /* An external .tsx whose document is not a tileset. */
    scratch_write_text("ts/notts.tsx", "<?xml version=\"1.0\"?>\n<map width=\"1\"/>\n");
    scratch_write_text("ext2.tmx", "<map width=\"1\" height=\"1\" tilewidth=\"8\" tileheight=\"8\">\n <tileset firstgid=\"1\" source=\"ts/notts.tsx\"/>\n</map>\n");
    snprintf(want, sizeof want, "%s:2:1: tileset: not a Tiled tileset (the document element is <map>, expected <tileset>)",
             scratch_path("ts/notts.tsx"));
    assert_int_equal(import_file("ext2.tmx", &lv, &e, NULL), NT_ERR_PARSE);
    assert_string_equal(e.message, want);
    scratch_write_text("ext.tmj", "{\"width\":1, \"height\":1, \"tilewidth\":8, \"tileheight\":8, \"tilesets\":[{\"firstgid\":1, \"source\":\"ts/broken.tsj\"}]}");
    assert_int_equal(import_file("ext.tmj", &lv, &e, NULL), NT_ERR_PARSE);
    snprintf(want, sizeof want, "%s:3:", scratch_path("ts/broken.tsj"));
    expect_in(e.message, want);
    expect_in(e.message, "bad JSON");
    /* NUL bytes and binary junk never crash. */
    unsigned char junk[64];
    for (int i = 0; i < 64; i++) junk[i] = (unsigned char)(i * 37 + 11);
    scratch_write("junk.tmx", junk, sizeof junk);
    assert_int_equal(import_file("junk.tmx", &lv, &e, NULL), NT_ERR_PARSE);
    scratch_write("junk.tmj", junk, sizeof junk);
    assert_int_equal(import_file("junk.tmj", &lv, &e, NULL), NT_ERR_PARSE);
    assert_null(lv);
}

/* Allocation failures in the level (the engine's allocator): an error, nothing left. */
static void test_out_of_memory(void **state)
{
    (void)state;
    mspec m = base_map(E_GZIP);
    m.layers[1] = (lspec){.name = "o", .kind = L_OBJECTS,
                          .objs = {{.id = 1, .name = "a", .kind = O_RECT, .x = 20, .y = 20, .w = 4, .h = 4},
                                   {.id = 2, .name = "r", .kind = O_RECT, .x = 20, .y = 20, .w = 4, .h = 4, .props = {{"region", NULL, "zone"}}}}};
    free(emit(&m, F_TMX, "oom.tmx"));
    size_t len;
    char *text = scratch_read(scratch_path("oom.tmx"), &len);
    int ok = 0;
    for (long budget = 0; budget < 200 && !ok; budget++) {
        nt_level *lv = NULL;
        nt_text_error e;
        failalloc_begin(budget);
        nt_status s = tiled_import(scratch_path("oom.tmx"), text, len, &lv, &e, NULL, NULL);
        if (s == NT_OK) {
            ok = 1;
            nt_level_destroy(lv);
        } else {
            assert_int_equal(s, NT_ERR_OUT_OF_MEMORY);
            assert_null(lv);
            expect_in(e.message, "oom.tmx: out of memory");
        }
        assert_int_equal(failalloc_end(), 0);
    }
    assert_true(ok);
    free(text);
    /* Bad arguments. */
    nt_level *lv = NULL;
    nt_text_error e;
    assert_int_equal(tiled_import("x", NULL, 3, &lv, &e, NULL, NULL), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(tiled_import("x", "", 0, NULL, &e, NULL, NULL), NT_ERR_INVALID_ARGUMENT);
}

/* ---------------------------------------------------------------- the CLI */

typedef child_result run_result;

static void run_cli(run_result *r, const char *const *args)
{
    child_run(r, scratch_dir(), child_ntile(), args, NULL, NULL, 125);
}

static void test_cli(void **state)
{
    (void)state;
    mspec m = base_map(E_ZLIB);
    m.layers[1] = (lspec){.name = "o", .kind = L_OBJECTS,
                          .objs = {{.id = 1, .name = "egg", .kind = O_ELLIPSE, .x = 20, .y = 20, .w = 6, .h = 4}}};
    free(emit(&m, F_TMJ, "cli.tmj"));
    run_result r;
    const char *a1[] = {"convert", "tiled", scratch_path("cli.tmj"), NULL};
    run_cli(&r, a1);
    assert_int_equal(r.status, 0);
    nt_level *lv = NULL;
    nt_text_error e;
    assert_int_equal(nt_level_parse("out", r.out, strlen(r.out), &lv, &e), NT_OK);
    check_base(lv);
    nt_level_destroy(lv);
    expect_in(r.err, "cli.tmj: warning: layer \"o\": object \"egg\" (id 1): the ellipse is 6 x 4, not a circle");
    char *first = r.out;
    free(r.err);
    const char *a2[] = {"convert", "tiled", scratch_path("cli.tmj"), "-o", scratch_path("cli.ntl"), NULL};
    run_cli(&r, a2);
    assert_int_equal(r.status, 0);
    assert_string_equal(r.out, "");
    size_t len;
    char *written = scratch_read(scratch_path("cli.ntl"), &len);
    assert_string_equal(written, first);
    free(written);
    free(first);
    free(r.out);
    free(r.err);
    /* Input errors: 1; usage and unreadable files: 2. */
    scratch_write_text("cli-bad.tmx", "<map orientation=\"hexagonal\" width=\"1\" height=\"1\" tilewidth=\"8\" tileheight=\"8\"/>\n");
    const char *a3[] = {"convert", "tiled", scratch_path("cli-bad.tmx"), NULL};
    run_cli(&r, a3);
    assert_int_equal(r.status, 1);
    expect_in(r.err, "cli-bad.tmx:1:1: map: orientation \"hexagonal\" is not supported (only orthogonal maps)\n");
    assert_string_equal(r.out, "");
    free(r.out);
    free(r.err);
    const char *a4[] = {"convert", "tiled", scratch_path("none.tmx"), NULL};
    run_cli(&r, a4);
    assert_int_equal(r.status, 2);
    expect_in(r.err, "ntile convert: cannot open '");
    free(r.out);
    free(r.err);
    const char *a5[] = {"convert", "tiled", NULL};
    run_cli(&r, a5);
    assert_int_equal(r.status, 2);
    expect_in(r.err, "ntile convert: missing the input MAP.tmj or MAP.tmx\n");
    free(r.out);
    free(r.err);
    const char *a6[] = {"convert", "tiled", "a.tmx", "--index", "2", NULL};
    run_cli(&r, a6);
    assert_int_equal(r.status, 2);
    expect_in(r.err, "ntile convert: unknown option '--index'\n");
    free(r.out);
    free(r.err);
    const char *a7[] = {"convert", "--help", NULL};
    run_cli(&r, a7);
    assert_int_equal(r.status, 0);
    expect_in(r.out, "ntile convert tiled MAP.tmj|MAP.tmx [-o OUT.ntl]");
    free(r.out);
    free(r.err);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_flip_geometry),
        cmocka_unit_test(test_encodings),
        cmocka_unit_test(test_layers_and_missing_properties),
        cmocka_unit_test(test_tilesets),
        cmocka_unit_test(test_flips_in_map),
        cmocka_unit_test(test_sparse_tile_ids),
        cmocka_unit_test(test_objects),
        cmocka_unit_test(test_large_objects),
        cmocka_unit_test(test_object_warnings),
        cmocka_unit_test(test_errors_in_specs),
        cmocka_unit_test(test_object_errors),
        cmocka_unit_test(test_malformed_files),
        cmocka_unit_test(test_bom_and_duplicate_keys),
        cmocka_unit_test(test_out_of_memory),
        cmocka_unit_test(test_cli),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
