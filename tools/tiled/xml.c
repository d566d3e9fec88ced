/* Tiled XML (.tmx maps, .tsx tilesets) -> the model, with expat.
 *
 * expat builds a small tree (elements, attributes, text, line and column of each
 * element) in the import's arena; the readers walk it. Every message carries the
 * line and column of the element at fault. */
#include <errno.h>
#include <expat.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"

typedef struct xnode xnode;
struct xnode {
    const char *name;
    const char **attr; /* name, value, ..., NULL */
    xnode *parent, *first, *last, *next;
    char *text;
    size_t tlen, tcap;
    tl_loc loc, tloc; /* the element; the start of its text */
};

typedef struct xb {
    tl_ctx *c;
    const char *file;
    XML_Parser p;
    xnode root; /* a holder for the document element */
    xnode *cur;
    int depth;
    int oom, too_deep;
} xb;

static tl_loc here(xb *b)
{
    tl_loc l;
    l.file = b->file;
    l.line = (int)XML_GetCurrentLineNumber(b->p);
    l.col = (int)XML_GetCurrentColumnNumber(b->p) + 1;
    return l;
}

static void XMLCALL on_start(void *ud, const XML_Char *name, const XML_Char **attr)
{
    xb *b = ud;
    if (b->oom || b->too_deep) return;
    if (++b->depth > TL_MAX_DEPTH + 8) {
        b->too_deep = 1;
        XML_StopParser(b->p, XML_FALSE);
        return;
    }
    xnode *n = tl_alloc(&b->c->arena, sizeof *n);
    size_t na = 0;
    while (attr[na]) na++;
    if (n) n->attr = tl_alloc(&b->c->arena, (na + 1) * sizeof *n->attr);
    if (n && n->attr) n->name = tl_strndup(&b->c->arena, name, strlen(name));
    for (size_t i = 0; n && n->attr && n->name && i < na; i++)
        if (!(n->attr[i] = tl_strndup(&b->c->arena, attr[i], strlen(attr[i])))) n->name = NULL;
    if (!n || !n->attr || !n->name) {
        b->oom = 1;
        XML_StopParser(b->p, XML_FALSE);
        return;
    }
    n->loc = here(b);
    n->parent = b->cur;
    if (b->cur->last) b->cur->last->next = n;
    else b->cur->first = n;
    b->cur->last = n;
    b->cur = n;
}

static void XMLCALL on_end(void *ud, const XML_Char *name)
{
    xb *b = ud;
    (void)name;
    if (b->oom || b->too_deep) return;
    b->depth--;
    b->cur = b->cur->parent;
}

static void XMLCALL on_text(void *ud, const XML_Char *s, int len)
{
    xb *b = ud;
    xnode *n = b->cur;
    if (b->oom || b->too_deep || n == &b->root || len <= 0) return;
    if (n->tlen == 0) n->tloc = here(b);
    if (n->tlen + (size_t)len + 1 > n->tcap) {
        size_t cap = n->tcap ? n->tcap : 64;
        while (cap < n->tlen + (size_t)len + 1) cap *= 2;
        char *t = tl_alloc(&b->c->arena, cap);
        if (!t) {
            b->oom = 1;
            XML_StopParser(b->p, XML_FALSE);
            return;
        }
        if (n->tlen) memcpy(t, n->text, n->tlen);
        n->text = t;
        n->tcap = cap;
    }
    memcpy(n->text + n->tlen, s, (size_t)len);
    n->tlen += (size_t)len;
    n->text[n->tlen] = '\0';
}

/* Parse the whole text into b->root; NT_OK or the error (set). */
static nt_status build(xb *b, const char *text, size_t len)
{
    b->p = XML_ParserCreate(NULL);
    if (!b->p) return tl_oom(b->c, b->file);
    b->cur = &b->root;
    XML_SetUserData(b->p, b);
    XML_SetElementHandler(b->p, on_start, on_end);
    XML_SetCharacterDataHandler(b->p, on_text);
    nt_status s = NT_OK;
    size_t off = 0;
    do {
        size_t chunk = len - off > (size_t)INT_MAX / 2 ? (size_t)INT_MAX / 2 : len - off;
        int last = off + chunk == len;
        if (XML_Parse(b->p, text + off, (int)chunk, last) != XML_STATUS_OK) {
            if (b->oom) s = tl_oom(b->c, b->file);
            else if (b->too_deep) s = tl_fail(b->c, here(b), "bad XML: elements nested more than %d deep", TL_MAX_DEPTH);
            else s = tl_fail(b->c, here(b), "bad XML: %s", XML_ErrorString(XML_GetErrorCode(b->p)));
            break;
        }
        off += chunk;
    } while (off < len);
    XML_ParserFree(b->p);
    b->p = NULL;
    return s;
}

/* ---------------------------------------------------------------- the tree */

static const char *attr(const xnode *n, const char *name)
{
    for (size_t i = 0; n->attr[i]; i += 2)
        if (strcmp(n->attr[i], name) == 0) return n->attr[i + 1];
    return NULL;
}

static int is(const xnode *n, const char *name) { return strcmp(n->name, name) == 0; }

static const xnode *child(const xnode *n, const char *name)
{
    for (const xnode *k = n->first; k; k = k->next)
        if (is(k, name)) return k;
    return NULL;
}

static nt_status bad(xb *b, const xnode *n, const char *what, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

static nt_status bad(xb *b, const xnode *n, const char *what, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return tl_fail(b->c, n->loc, "%s: %s", what, msg);
}

static nt_status get_int(xb *b, const xnode *n, const char *key, const char *what, const long long *def, long long *out)
{
    const char *v = attr(n, key);
    if (!v) {
        if (def) {
            *out = *def;
            return NT_OK;
        }
        return bad(b, n, what, "missing attribute \"%s\"", key);
    }
    char *end;
    errno = 0;
    long long x = strtoll(v, &end, 10);
    if (end == v || *end || errno) {
        char q[64];
        return bad(b, n, what, "attribute \"%s\" must be an integer, not %s", key, tl_quote(q, v));
    }
    *out = x;
    return NT_OK;
}

static nt_status get_num(xb *b, const xnode *n, const char *key, const char *what, double *out)
{
    const char *v = attr(n, key);
    *out = 0;
    if (!v) return NT_OK;
    char *end;
    double x = strtod(v, &end);
    if (end == v || *end || !isfinite(x)) {
        char q[64];
        return bad(b, n, what, "attribute \"%s\" must be a number, not %s", key, tl_quote(q, v));
    }
    *out = x;
    return NT_OK;
}

static const char *str_or(const char *s, const char *def) { return s ? s : def; }

static nt_status get_props(xb *b, const xnode *n, tl_props *out)
{
    out->v = NULL;
    out->n = 0;
    const xnode *ps = child(n, "properties");
    if (!ps) return NT_OK;
    int count = 0;
    for (const xnode *k = ps->first; k; k = k->next) count += is(k, "property");
    if (!count) return NT_OK;
    out->v = tl_alloc(&b->c->arena, (size_t)count * sizeof *out->v);
    if (!out->v) return tl_oom(b->c, b->file);
    for (const xnode *k = ps->first; k; k = k->next) {
        if (!is(k, "property")) continue;
        tl_prop *p = &out->v[out->n++];
        p->name = attr(k, "name");
        if (!p->name) return bad(b, k, "property", "missing attribute \"name\"");
        p->type = str_or(attr(k, "type"), "string");
        p->loc = k->loc;
        p->value = attr(k, "value");
        if (!p->value && strcmp(p->type, "class") != 0) p->value = k->text ? k->text : ""; /* multi-line strings */
    }
    return NT_OK;
}

static nt_status read_tiles(xb *b, const xnode *n, tl_tileset *ts)
{
    char what[128], q[64];
    nt_status s;
    ts->name = str_or(attr(n, "name"), "");
    snprintf(what, sizeof what, "tileset %s", tl_quote(q, ts->name));
    long long none = -1;
    if ((s = get_int(b, n, "tilecount", what, &none, &ts->tilecount)) != NT_OK) return s;
    ts->def = n->loc;
    int count = 0;
    for (const xnode *k = n->first; k; k = k->next) count += is(k, "tile");
    if (!count) return NT_OK;
    ts->tiles = tl_alloc(&b->c->arena, (size_t)count * sizeof *ts->tiles);
    if (!ts->tiles) return tl_oom(b->c, b->file);
    for (const xnode *k = n->first; k; k = k->next) {
        if (!is(k, "tile")) continue;
        tl_tile *t = &ts->tiles[ts->ntiles];
        if ((s = get_int(b, k, "id", what, NULL, &t->id)) != NT_OK) return s;
        if ((s = get_props(b, k, &t->props)) != NT_OK) return s;
        t->loc = k->loc;
        ts->ntiles++;
    }
    return NT_OK;
}

/* Parse a document whose element must be <kind> (tileset or map); *root = it. */
static nt_status open_document(xb *b, tl_ctx *c, const char *file, const char *text, size_t len, const char *kind,
                               const xnode **root)
{
    *root = NULL;
    memset(b, 0, sizeof *b);
    b->c = c;
    b->file = file;
    nt_status s = build(b, text, len);
    if (s != NT_OK) return s;
    const xnode *r = b->root.first;
    if (!r || !is(r, kind)) {
        tl_loc at = r ? r->loc : (tl_loc){file, 0, 0};
        return tl_fail(c, at, "%s: not a Tiled %s (the document element is <%s>, expected <%s>)", kind, kind,
                       r ? r->name : "", kind);
    }
    *root = r;
    return NT_OK;
}

nt_status tl_xml_tileset(tl_ctx *c, const char *file, const char *text, size_t len, tl_tileset *ts)
{
    xb b;
    const xnode *r = NULL;
    nt_status s = open_document(&b, c, file, text, len, "tileset", &r);
    if (s != NT_OK) return s;
    return read_tiles(&b, r, ts);
}

/* "x,y x,y ..." of a polygon or polyline. */
static nt_status read_points(xb *b, const xnode *n, const char *what, tl_object *ob)
{
    const char *s = attr(n, "points");
    if (!s) return bad(b, n, what, "missing attribute \"points\"");
    size_t count = 0;
    for (const char *p = s; *p; p++) count += *p == ',';
    ob->points = tl_alloc(&b->c->arena, (count ? count : 1) * 2 * sizeof *ob->points);
    if (!ob->points) return tl_oom(b->c, b->file);
    const char *p = s;
    int k = 0;
    for (;;) {
        while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') p++;
        if (!*p) break;
        char *end;
        double x = strtod(p, &end);
        if (end == p || *end != ',') goto fail;
        p = end + 1;
        double y = strtod(p, &end);
        if (end == p || !(*end == '\0' || *end == ' ' || *end == '\t' || *end == '\n' || *end == '\r')) goto fail;
        if (!isfinite(x) || !isfinite(y) || (size_t)k >= count) goto fail;
        ob->points[2 * k] = x;
        ob->points[2 * k + 1] = y;
        k++;
        p = end;
    }
    ob->npoints = k;
    return NT_OK;
fail: {
    char q[64];
    return bad(b, n, what, "bad \"points\" %s (expected x,y pairs separated by spaces)", tl_quote(q, s));
}
}

static nt_status read_object(xb *b, const xnode *n, tl_object *ob)
{
    nt_status s;
    long long zero = 0;
    ob->name = str_or(attr(n, "name"), "");
    char what[200], q[64];
    if ((s = get_int(b, n, "id", "object", &zero, &ob->id)) != NT_OK) return s;
    snprintf(what, sizeof what, "object %s (id %lld)", tl_quote(q, ob->name), ob->id);
    ob->type = str_or(attr(n, "type"), str_or(attr(n, "class"), ""));
    if ((s = get_num(b, n, "x", what, &ob->x)) != NT_OK || (s = get_num(b, n, "y", what, &ob->y)) != NT_OK ||
        (s = get_num(b, n, "width", what, &ob->w)) != NT_OK || (s = get_num(b, n, "height", what, &ob->h)) != NT_OK ||
        (s = get_num(b, n, "rotation", what, &ob->rotation)) != NT_OK)
        return s;
    if ((s = get_props(b, n, &ob->props)) != NT_OK) return s;
    ob->loc = n->loc;
    ob->shape = TL_RECT;
    if (attr(n, "gid")) ob->shape = TL_TILE_OBJECT;
    for (const xnode *k = n->first; k; k = k->next) {
        if (is(k, "ellipse")) ob->shape = TL_ELLIPSE;
        else if (is(k, "point")) ob->shape = TL_POINT;
        else if (is(k, "text")) ob->shape = TL_TEXT;
        else if (is(k, "polygon") || is(k, "polyline")) {
            ob->shape = is(k, "polygon") ? TL_POLYGON : TL_POLYLINE;
            if ((s = read_points(b, k, what, ob)) != NT_OK) return s;
        }
    }
    if (attr(n, "template")) ob->shape = TL_TEMPLATE;
    return NT_OK;
}

/* <data>: encoded text, or <tile gid="..."/> elements when there is no encoding. */
static nt_status read_data(xb *b, const xnode *d, const char *what, tl_layer *l)
{
    const char *enc = attr(d, "encoding");
    l->data_loc = d->loc;
    l->compression = str_or(attr(d, "compression"), "");
    if (child(d, "chunk"))
        return bad(b, d, what, "chunked data (an infinite map) is not supported: turn off Map > Map Properties > Infinite");
    if (!enc) {
        size_t count = 0;
        for (const xnode *k = d->first; k; k = k->next) count += is(k, "tile");
        l->gids = tl_alloc(&b->c->arena, (count ? count : 1) * sizeof *l->gids);
        if (!l->gids) return tl_oom(b->c, b->file);
        for (const xnode *k = d->first; k; k = k->next) {
            if (!is(k, "tile")) continue;
            long long g, zero = 0;
            nt_status s = get_int(b, k, "gid", what, &zero, &g);
            if (s != NT_OK) return s;
            if (g < 0 || g > 0xffffffffLL) return bad(b, k, what, "gid %lld is not a tile id (0..4294967295)", g);
            l->gids[l->ngids++] = (uint32_t)g;
        }
        l->has_gids = 1;
        return NT_OK;
    }
    if (strcmp(enc, "csv") != 0 && strcmp(enc, "base64") != 0) {
        char q[64];
        return bad(b, d, what, "unknown encoding %s (expected csv or base64)", tl_quote(q, enc));
    }
    l->encoding = strcmp(enc, "csv") == 0 ? "csv" : "base64";
    l->text = d->text ? d->text : "";
    l->text_len = d->tlen;
    l->text_loc = d->text ? d->tloc : d->loc;
    return NT_OK;
}

static nt_status read_layers(xb *b, const xnode *parent, double offx, double offy, int depth, tl_layer_list *L)
{
    if (depth > TL_MAX_DEPTH) return bad(b, parent, "map", "group layers nested more than %d deep", TL_MAX_DEPTH);
    for (const xnode *n = parent->first; n; n = n->next) {
        int tiles = is(n, "layer"), objects = is(n, "objectgroup"), group = is(n, "group"), image = is(n, "imagelayer");
        if (!tiles && !objects && !group && !image) continue;
        nt_status s;
        const char *name = str_or(attr(n, "name"), "");
        char what[128], q[64];
        snprintf(what, sizeof what, "layer %s", tl_quote(q, name));
        double ox = 0, oy = 0;
        if ((s = get_num(b, n, "offsetx", what, &ox)) != NT_OK || (s = get_num(b, n, "offsety", what, &oy)) != NT_OK)
            return s;
        if (group) {
            if ((s = read_layers(b, n, offx + ox, offy + oy, depth + 1, L)) != NT_OK) return s;
            continue;
        }
        tl_layer *l = tl_new_layer(&b->c->arena, L);
        if (!l) return tl_oom(b->c, b->file);
        l->name = name;
        l->loc = l->data_loc = l->text_loc = n->loc;
        l->offx = offx + ox;
        l->offy = offy + oy;
        if ((s = get_props(b, n, &l->props)) != NT_OK) return s;
        if (tiles) {
            l->kind = TL_LAYER_TILES;
            if ((s = get_int(b, n, "width", what, NULL, &l->width)) != NT_OK ||
                (s = get_int(b, n, "height", what, NULL, &l->height)) != NT_OK)
                return s;
            const xnode *d = child(n, "data");
            if (!d) return bad(b, n, what, "missing <data>");
            if ((s = read_data(b, d, what, l)) != NT_OK) return s;
        } else if (objects) {
            l->kind = TL_LAYER_OBJECTS;
            int count = 0;
            for (const xnode *k = n->first; k; k = k->next) count += is(k, "object");
            if (!count) continue;
            l->objects = tl_alloc(&b->c->arena, (size_t)count * sizeof *l->objects);
            if (!l->objects) return tl_oom(b->c, b->file);
            for (const xnode *k = n->first; k; k = k->next) {
                if (!is(k, "object")) continue;
                if ((s = read_object(b, k, &l->objects[l->nobjects])) != NT_OK) return s;
                l->nobjects++;
            }
        } else {
            l->kind = TL_LAYER_OTHER;
        }
    }
    return NT_OK;
}

nt_status tl_xml_map(tl_ctx *c, const char *file, const char *text, size_t len, tl_map *m)
{
    xb b;
    const xnode *r = NULL;
    nt_status s = open_document(&b, c, file, text, len, "map", &r);
    if (s != NT_OK) return s;
    m->loc = r->loc;
    m->orientation = str_or(attr(r, "orientation"), "orthogonal");
    long long zero = 0, inf;
    if ((s = get_int(&b, r, "infinite", "map", &zero, &inf)) != NT_OK) return s;
    m->infinite = inf != 0;
    if ((s = get_int(&b, r, "width", "map", NULL, &m->width)) != NT_OK ||
        (s = get_int(&b, r, "height", "map", NULL, &m->height)) != NT_OK ||
        (s = get_int(&b, r, "tilewidth", "map", NULL, &m->tilewidth)) != NT_OK ||
        (s = get_int(&b, r, "tileheight", "map", NULL, &m->tileheight)) != NT_OK ||
        (s = get_props(&b, r, &m->props)) != NT_OK)
        return s;
    int count = 0;
    for (const xnode *k = r->first; k; k = k->next) count += is(k, "tileset");
    if (count) {
        m->tilesets = tl_alloc(&c->arena, (size_t)count * sizeof *m->tilesets);
        if (!m->tilesets) return tl_oom(c, file);
    }
    for (const xnode *k = r->first; k; k = k->next) {
        if (!is(k, "tileset")) continue;
        tl_tileset *ts = &m->tilesets[m->ntilesets];
        char what[64];
        snprintf(what, sizeof what, "tileset %d", m->ntilesets + 1);
        ts->loc = k->loc;
        ts->tilecount = -1;
        if ((s = get_int(&b, k, "firstgid", what, NULL, &ts->firstgid)) != NT_OK) return s;
        ts->source = attr(k, "source");
        if (!ts->source && (s = read_tiles(&b, k, ts)) != NT_OK) return s;
        m->ntilesets++;
    }
    tl_layer_list L = {NULL, 0, 0};
    if ((s = read_layers(&b, r, 0, 0, 0, &L)) != NT_OK) return s;
    m->layers = L.v;
    m->nlayers = L.n;
    return NT_OK;
}
