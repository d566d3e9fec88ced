/* Tiled JSON (.tmj maps, .tsj tilesets) -> the model, with jansson.
 *
 * jansson gives line and column for syntax errors; values carry no position, so
 * other problems name the element only ("FILE: layer "ground": ..."). */
#include <jansson.h>
#include <stdio.h>
#include <string.h>
#include "internal.h"

typedef struct jr {
    tl_ctx *c;
    const char *file;
} jr;

static tl_loc floc(const jr *r)
{
    tl_loc l = {r->file, 0, 0};
    return l;
}

static nt_status bad(const jr *r, const char *what, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

static nt_status bad(const jr *r, const char *what, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return tl_fail(r->c, floc(r), "%s: %s", what, msg);
}

static const char *jtype(const json_t *v)
{
    switch (json_typeof(v)) {
    case JSON_OBJECT: return "an object";
    case JSON_ARRAY: return "an array";
    case JSON_STRING: return "a string";
    case JSON_INTEGER: return "an integer";
    case JSON_REAL: return "a number";
    case JSON_TRUE: case JSON_FALSE: return "a boolean";
    default: return "null";
    }
}

/* An integer member (required when def is NULL). Reals with an integral value pass. */
static nt_status get_int(const jr *r, const json_t *o, const char *key, const char *what, const long long *def,
                         long long *out)
{
    json_t *v = json_object_get(o, key);
    if (!v) {
        if (def) {
            *out = *def;
            return NT_OK;
        }
        return bad(r, what, "missing \"%s\"", key);
    }
    if (json_is_integer(v)) {
        *out = (long long)json_integer_value(v);
        return NT_OK;
    }
    if (json_is_real(v)) {
        double d = json_real_value(v);
        if (d >= -9e15 && d <= 9e15 && d == (double)(long long)d) {
            *out = (long long)d;
            return NT_OK;
        }
    }
    return bad(r, what, "\"%s\" must be an integer, not %s", key, jtype(v));
}

static nt_status get_num(const jr *r, const json_t *o, const char *key, const char *what, double def, double *out)
{
    json_t *v = json_object_get(o, key);
    if (!v) {
        *out = def;
        return NT_OK;
    }
    if (!json_is_number(v)) return bad(r, what, "\"%s\" must be a number, not %s", key, jtype(v));
    *out = json_number_value(v);
    return NT_OK;
}

/* A string member copied into the arena; *out = def when missing. */
static nt_status get_str(const jr *r, const json_t *o, const char *key, const char *what, const char *def,
                         const char **out)
{
    json_t *v = json_object_get(o, key);
    if (!v) {
        *out = def;
        return NT_OK;
    }
    if (!json_is_string(v)) return bad(r, what, "\"%s\" must be a string, not %s", key, jtype(v));
    *out = tl_strndup(&r->c->arena, json_string_value(v), json_string_length(v));
    return *out ? NT_OK : tl_oom(r->c, r->file);
}

static nt_status get_bool(const jr *r, const json_t *o, const char *key, const char *what, int *out)
{
    json_t *v = json_object_get(o, key);
    *out = 0;
    if (!v) return NT_OK;
    if (!json_is_boolean(v)) return bad(r, what, "\"%s\" must be true or false, not %s", key, jtype(v));
    *out = json_is_true(v);
    return NT_OK;
}

static nt_status get_props(const jr *r, const json_t *o, const char *what, tl_props *out)
{
    json_t *a = json_object_get(o, "properties");
    out->v = NULL;
    out->n = 0;
    if (!a) return NT_OK;
    if (!json_is_array(a)) return bad(r, what, "\"properties\" must be an array, not %s", jtype(a));
    size_t n = json_array_size(a);
    if (n == 0) return NT_OK;
    out->v = tl_alloc(&r->c->arena, n * sizeof *out->v);
    if (!out->v) return tl_oom(r->c, r->file);
    for (size_t i = 0; i < n; i++) {
        json_t *p = json_array_get(a, i);
        tl_prop *q = &out->v[i];
        nt_status s;
        if (!json_is_object(p)) return bad(r, what, "property %zu must be an object, not %s", i + 1, jtype(p));
        if ((s = get_str(r, p, "name", what, NULL, &q->name)) != NT_OK) return s;
        if (!q->name) return bad(r, what, "property %zu has no \"name\"", i + 1);
        if ((s = get_str(r, p, "type", what, "string", &q->type)) != NT_OK) return s;
        q->loc = floc(r);
        json_t *v = json_object_get(p, "value");
        char buf[64];
        const char *text = buf;
        size_t len;
        if (!v || json_is_null(v)) {
            text = "";
        } else if (json_is_string(v)) {
            text = json_string_value(v);
        } else if (json_is_integer(v)) {
            snprintf(buf, sizeof buf, "%lld", (long long)json_integer_value(v));
        } else if (json_is_real(v)) {
            snprintf(buf, sizeof buf, "%.17g", json_real_value(v));
        } else if (json_is_boolean(v)) {
            text = json_is_true(v) ? "true" : "false";
        } else {
            text = NULL; /* class values */
        }
        if (text) {
            len = json_is_string(v) ? json_string_length(v) : strlen(text);
            if (!(q->value = tl_strndup(&r->c->arena, text, len))) return tl_oom(r->c, r->file);
        }
        out->n++;
    }
    return NT_OK;
}

/* The tiles of a tileset object (embedded, or the root of a .tsj). */
static nt_status read_tiles(const jr *r, const json_t *o, tl_tileset *ts)
{
    char what[128];
    nt_status s;
    const char *name;
    if ((s = get_str(r, o, "name", "tileset", "", &name)) != NT_OK) return s;
    ts->name = name;
    char q[64];
    snprintf(what, sizeof what, "tileset %s", tl_quote(q, name));
    long long none = -1;
    if ((s = get_int(r, o, "tilecount", what, &none, &ts->tilecount)) != NT_OK) return s;
    ts->def = floc(r);
    json_t *a = json_object_get(o, "tiles");
    if (!a) return NT_OK;
    if (!json_is_array(a)) return bad(r, what, "\"tiles\" must be an array, not %s", jtype(a));
    size_t n = json_array_size(a);
    if (n == 0) return NT_OK;
    if (n > 0x0fffffff) return bad(r, what, "too many tiles");
    ts->tiles = tl_alloc(&r->c->arena, n * sizeof *ts->tiles);
    if (!ts->tiles) return tl_oom(r->c, r->file);
    for (size_t i = 0; i < n; i++) {
        json_t *t = json_array_get(a, i);
        tl_tile *tt = &ts->tiles[i];
        if (!json_is_object(t)) return bad(r, what, "tile %zu must be an object, not %s", i + 1, jtype(t));
        if ((s = get_int(r, t, "id", what, NULL, &tt->id)) != NT_OK) return s;
        char twhat[160];
        snprintf(twhat, sizeof twhat, "%s: tile %lld", what, tt->id);
        if ((s = get_props(r, t, twhat, &tt->props)) != NT_OK) return s;
        tt->loc = floc(r);
        ts->ntiles++;
    }
    return NT_OK;
}

/* Line and byte column (1-based) of text[off]. */
static void text_line_col(const char *text, size_t off, int *line, int *col)
{
    int l = 1;
    size_t ls = 0;
    for (size_t i = 0; i < off; i++)
        if (text[i] == '\n') l++, ls = i + 1;
    *line = l;
    *col = (int)(off - ls) + 1;
}

/* The first key written twice in one object (as written: escapes are compared as
 * they stand), scanning the JSON text: its offset and the offset of its first
 * occurrence. 0 when there is none. Runs only after jansson has refused a duplicate,
 * to say where both are. */
static int first_duplicate_key(const char *text, size_t len, size_t *first, size_t *second, size_t *klen)
{
    enum { MAXK = 4096, MAXD = 256 };
    static size_t koff[MAXK], kl[MAXK];
    static int kdepth[MAXK];
    static char in_object[MAXD];
    int nk = 0, depth = 0;
    for (size_t i = 0; i < len; i++) {
        char ch = text[i];
        if (ch == '{' || ch == '[') {
            if (++depth >= MAXD) return 0;
            in_object[depth] = ch == '{';
        } else if (ch == '}' || ch == ']') {
            while (nk > 0 && kdepth[nk - 1] == depth) nk--;
            if (--depth < 0) return 0;
        } else if (ch == '"') {
            size_t start = i++;
            while (i < len && text[i] != '"') i += text[i] == '\\' ? 2 : 1;
            if (i >= len) return 0;
            size_t j = i + 1;
            while (j < len && (text[j] == ' ' || text[j] == '\t' || text[j] == '\r' || text[j] == '\n')) j++;
            if (depth > 0 && in_object[depth] && j < len && text[j] == ':') {
                size_t n = i + 1 - start;
                for (int k = nk - 1; k >= 0 && kdepth[k] == depth; k--)
                    if (kl[k] == n && memcmp(text + koff[k], text + start, n) == 0) {
                        *first = koff[k];
                        *second = start;
                        *klen = n;
                        return 1;
                    }
                if (nk == MAXK) return 0;
                koff[nk] = start;
                kl[nk] = n;
                kdepth[nk++] = depth;
            }
        }
    }
    return 0;
}

static json_t *load(const jr *r, const char *text, size_t len)
{
    json_error_t e;
    /* A UTF-8 byte order mark (as some editors save) is skipped. */
    size_t bom = len >= 3 && (unsigned char)text[0] == 0xef && (unsigned char)text[1] == 0xbb &&
                         (unsigned char)text[2] == 0xbf ? 3 : 0;
    /* Duplicate keys are refused: Tiled never writes them, and jansson would keep the
     * last one silently. */
    json_t *root = json_loadb(text + bom, len - bom, JSON_REJECT_DUPLICATES, &e);
    if (!root) {
        size_t a, b, n;
        if (strstr(e.text, "duplicate") && first_duplicate_key(text, len, &a, &b, &n)) {
            int l1, c1, l2, c2;
            text_line_col(text, a, &l1, &c1);
            text_line_col(text, b, &l2, &c2);
            tl_loc at = {r->file, l2, c2};
            tl_fail(r->c, at, "duplicate key %.*s (first at line %d, column %d)", n > 200 ? 200 : (int)n, text + b, l1, c1);
            return NULL;
        }
        tl_loc at = {r->file, e.line > 0 ? e.line : 0, e.line > 0 ? e.column : 0};
        if (at.line > 0 && at.col < 1) at.col = 1;
        tl_fail(r->c, at, "bad JSON: %s", e.text);
    }
    return root;
}

nt_status tl_json_tileset(tl_ctx *c, const char *file, const char *text, size_t len, tl_tileset *ts)
{
    jr r = {c, file};
    json_t *root = load(&r, text, len);
    if (!root) return NT_ERR_PARSE;
    nt_status s;
    if (!json_is_object(root)) {
        s = bad(&r, "tileset", "the file holds %s, not a Tiled tileset object", jtype(root));
    } else {
        json_t *type = json_object_get(root, "type");
        if (type && (!json_is_string(type) || strcmp(json_string_value(type), "tileset") != 0))
            s = bad(&r, "tileset", "not a Tiled tileset (\"type\" is not \"tileset\")");
        else
            s = read_tiles(&r, root, ts);
    }
    json_decref(root);
    return s;
}

static nt_status read_object(const jr *r, const json_t *o, const char *lwhat, tl_object *ob)
{
    nt_status s;
    long long zero = 0;
    if (!json_is_object(o)) return bad(r, lwhat, "an object must be a JSON object, not %s", jtype(o));
    if ((s = get_int(r, o, "id", lwhat, &zero, &ob->id)) != NT_OK) return s;
    if ((s = get_str(r, o, "name", lwhat, "", &ob->name)) != NT_OK) return s;
    char what[200], q[64];
    snprintf(what, sizeof what, "object %s (id %lld)", tl_quote(q, ob->name), ob->id);
    if ((s = get_str(r, o, "type", what, "", &ob->type)) != NT_OK) return s;
    if (!*ob->type && (s = get_str(r, o, "class", what, "", &ob->type)) != NT_OK) return s;
    if ((s = get_num(r, o, "x", what, 0, &ob->x)) != NT_OK || (s = get_num(r, o, "y", what, 0, &ob->y)) != NT_OK ||
        (s = get_num(r, o, "width", what, 0, &ob->w)) != NT_OK || (s = get_num(r, o, "height", what, 0, &ob->h)) != NT_OK ||
        (s = get_num(r, o, "rotation", what, 0, &ob->rotation)) != NT_OK)
        return s;
    if ((s = get_props(r, o, what, &ob->props)) != NT_OK) return s;
    ob->loc = floc(r);
    int flag;
    ob->shape = TL_RECT;
    if ((s = get_bool(r, o, "ellipse", what, &flag)) != NT_OK) return s;
    if (flag) ob->shape = TL_ELLIPSE;
    if ((s = get_bool(r, o, "point", what, &flag)) != NT_OK) return s;
    if (flag) ob->shape = TL_POINT;
    if (json_object_get(o, "text")) ob->shape = TL_TEXT;
    if (json_object_get(o, "gid")) ob->shape = TL_TILE_OBJECT;
    const char *pkey = json_object_get(o, "polygon") ? "polygon" : json_object_get(o, "polyline") ? "polyline" : NULL;
    if (pkey) {
        ob->shape = pkey[4] == 'g' ? TL_POLYGON : TL_POLYLINE;
        json_t *a = json_object_get(o, pkey);
        if (!json_is_array(a)) return bad(r, what, "\"%s\" must be an array, not %s", pkey, jtype(a));
        size_t n = json_array_size(a);
        if (n > 100000) return bad(r, what, "\"%s\" has too many points", pkey);
        ob->points = tl_alloc(&r->c->arena, (n ? n : 1) * 2 * sizeof *ob->points);
        if (!ob->points) return tl_oom(r->c, r->file);
        for (size_t i = 0; i < n; i++) {
            json_t *p = json_array_get(a, i);
            if (!json_is_object(p)) return bad(r, what, "point %zu must be an object {\"x\", \"y\"}", i + 1);
            if ((s = get_num(r, p, "x", what, 0, &ob->points[2 * i])) != NT_OK ||
                (s = get_num(r, p, "y", what, 0, &ob->points[2 * i + 1])) != NT_OK)
                return s;
        }
        ob->npoints = (int)n;
    }
    if (json_object_get(o, "template")) ob->shape = TL_TEMPLATE;
    return NT_OK;
}

static nt_status read_layers(const jr *r, const json_t *arr, double offx, double offy, int depth, tl_layer_list *L)
{
    if (!json_is_array(arr)) return bad(r, "map", "\"layers\" must be an array, not %s", jtype(arr));
    if (depth > TL_MAX_DEPTH) return bad(r, "map", "group layers nested more than %d deep", TL_MAX_DEPTH);
    for (size_t i = 0; i < json_array_size(arr); i++) {
        json_t *o = json_array_get(arr, i);
        nt_status s;
        if (!json_is_object(o)) return bad(r, "map", "layer %zu must be an object, not %s", i + 1, jtype(o));
        const char *name, *type;
        if ((s = get_str(r, o, "name", "layer", "", &name)) != NT_OK) return s;
        char what[128], q[64];
        snprintf(what, sizeof what, "layer %s", tl_quote(q, name));
        if ((s = get_str(r, o, "type", what, NULL, &type)) != NT_OK) return s;
        if (!type) return bad(r, what, "missing \"type\"");
        double ox = 0, oy = 0;
        if ((s = get_num(r, o, "offsetx", what, 0, &ox)) != NT_OK || (s = get_num(r, o, "offsety", what, 0, &oy)) != NT_OK)
            return s;
        if (strcmp(type, "group") == 0) {
            json_t *sub = json_object_get(o, "layers");
            if (!sub) continue;
            if ((s = read_layers(r, sub, offx + ox, offy + oy, depth + 1, L)) != NT_OK) return s;
            continue;
        }
        tl_layer *l = tl_new_layer(&r->c->arena, L);
        if (!l) return tl_oom(r->c, r->file);
        l->name = name;
        l->loc = floc(r);
        l->data_loc = l->text_loc = l->loc;
        l->offx = offx + ox;
        l->offy = offy + oy;
        if ((s = get_props(r, o, what, &l->props)) != NT_OK) return s;
        if (strcmp(type, "tilelayer") == 0) {
            l->kind = TL_LAYER_TILES;
            if (json_object_get(o, "chunks"))
                return bad(r, what, "chunked data (an infinite map) is not supported: turn off Map > Map Properties > Infinite");
            if ((s = get_int(r, o, "width", what, NULL, &l->width)) != NT_OK ||
                (s = get_int(r, o, "height", what, NULL, &l->height)) != NT_OK)
                return s;
            const char *enc;
            if ((s = get_str(r, o, "encoding", what, "csv", &enc)) != NT_OK ||
                (s = get_str(r, o, "compression", what, "", &l->compression)) != NT_OK)
                return s;
            json_t *d = json_object_get(o, "data");
            if (!d) return bad(r, what, "missing \"data\"");
            if (strcmp(enc, "csv") == 0) {
                if (!json_is_array(d)) return bad(r, what, "\"data\" must be an array of tile ids (encoding csv), not %s", jtype(d));
                size_t n = json_array_size(d);
                l->gids = tl_alloc(&r->c->arena, (n ? n : 1) * sizeof *l->gids);
                if (!l->gids) return tl_oom(r->c, r->file);
                for (size_t k = 0; k < n; k++) {
                    json_t *g = json_array_get(d, k);
                    if (!json_is_integer(g) || json_integer_value(g) < 0 || json_integer_value(g) > 0xffffffffLL)
                        return bad(r, what, "data item %zu is not a tile id (an integer 0..4294967295)", k + 1);
                    l->gids[k] = (uint32_t)json_integer_value(g);
                }
                l->ngids = n;
                l->has_gids = 1;
            } else if (strcmp(enc, "base64") == 0) {
                if (!json_is_string(d)) return bad(r, what, "\"data\" must be a base64 string, not %s", jtype(d));
                l->encoding = "base64";
                l->text = json_string_value(d);
                l->text_len = json_string_length(d);
                if (!(l->text = tl_strndup(&r->c->arena, l->text, l->text_len))) return tl_oom(r->c, r->file);
            } else {
                char q2[64];
                return bad(r, what, "unknown encoding %s (expected csv or base64)", tl_quote(q2, enc));
            }
        } else if (strcmp(type, "objectgroup") == 0) {
            l->kind = TL_LAYER_OBJECTS;
            json_t *a = json_object_get(o, "objects");
            if (!a) continue;
            if (!json_is_array(a)) return bad(r, what, "\"objects\" must be an array, not %s", jtype(a));
            size_t n = json_array_size(a);
            if (n > 1000000) return bad(r, what, "too many objects");
            l->objects = tl_alloc(&r->c->arena, (n ? n : 1) * sizeof *l->objects);
            if (!l->objects) return tl_oom(r->c, r->file);
            for (size_t k = 0; k < n; k++) {
                if ((s = read_object(r, json_array_get(a, k), what, &l->objects[k])) != NT_OK) return s;
                l->nobjects++;
            }
        } else {
            l->kind = TL_LAYER_OTHER;
        }
    }
    return NT_OK;
}

static nt_status read_map(const jr *r, const json_t *root, tl_map *m)
{
    nt_status s;
    if (!json_is_object(root)) return bad(r, "map", "the file holds %s, not a Tiled map object", jtype(root));
    json_t *type = json_object_get(root, "type");
    if (type && (!json_is_string(type) || strcmp(json_string_value(type), "map") != 0))
        return bad(r, "map", "not a Tiled map (\"type\" is not \"map\")");
    m->loc = floc(r);
    if ((s = get_str(r, root, "orientation", "map", "orthogonal", &m->orientation)) != NT_OK ||
        (s = get_bool(r, root, "infinite", "map", &m->infinite)) != NT_OK ||
        (s = get_int(r, root, "width", "map", NULL, &m->width)) != NT_OK ||
        (s = get_int(r, root, "height", "map", NULL, &m->height)) != NT_OK ||
        (s = get_int(r, root, "tilewidth", "map", NULL, &m->tilewidth)) != NT_OK ||
        (s = get_int(r, root, "tileheight", "map", NULL, &m->tileheight)) != NT_OK ||
        (s = get_props(r, root, "map", &m->props)) != NT_OK)
        return s;
    json_t *a = json_object_get(root, "tilesets");
    if (a) {
        if (!json_is_array(a)) return bad(r, "map", "\"tilesets\" must be an array, not %s", jtype(a));
        size_t n = json_array_size(a);
        if (n > 100000) return bad(r, "map", "too many tilesets");
        m->tilesets = tl_alloc(&r->c->arena, (n ? n : 1) * sizeof *m->tilesets);
        if (!m->tilesets) return tl_oom(r->c, r->file);
        for (size_t i = 0; i < n; i++) {
            json_t *o = json_array_get(a, i);
            tl_tileset *ts = &m->tilesets[i];
            char what[64];
            snprintf(what, sizeof what, "tileset %zu", i + 1);
            if (!json_is_object(o)) return bad(r, "map", "%s must be an object, not %s", what, jtype(o));
            ts->loc = floc(r);
            ts->tilecount = -1;
            if ((s = get_int(r, o, "firstgid", what, NULL, &ts->firstgid)) != NT_OK) return s;
            if ((s = get_str(r, o, "source", what, NULL, &ts->source)) != NT_OK) return s;
            if (!ts->source && (s = read_tiles(r, o, ts)) != NT_OK) return s;
            m->ntilesets++;
        }
    }
    tl_layer_list L = {NULL, 0, 0};
    json_t *layers = json_object_get(root, "layers");
    if (layers && (s = read_layers(r, layers, 0, 0, 0, &L)) != NT_OK) return s;
    m->layers = L.v;
    m->nlayers = L.n;
    return NT_OK;
}

nt_status tl_json_map(tl_ctx *c, const char *file, const char *text, size_t len, tl_map *m)
{
    jr r = {c, file};
    json_t *root = load(&r, text, len);
    if (!root) return NT_ERR_PARSE;
    nt_status s = read_map(&r, root, m);
    json_decref(root);
    return s;
}
