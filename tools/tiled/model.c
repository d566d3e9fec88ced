/* Tiled import: what the readers (json.c, xml.c) and the builder (tiled.c) share:
 * the arena everything of one import lives in, the layer lists of the model, and
 * messages with the file, line and column they are about. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"

/* ---------------------------------------------------------------- arena */

struct tl_block {
    tl_block *next;
    size_t used, cap;
    max_align_t data[];
};

#define TL_BLOCK_BYTES 65536

void *tl_alloc(tl_arena *a, size_t size)
{
    size_t align = sizeof(max_align_t);
    if (size > ((size_t)-1) / 2) return NULL;
    size = (size + align - 1) / align * align;
    if (size == 0) size = align;
    if (size > TL_BLOCK_BYTES / 4) { /* a block of its own, kept behind the current one */
        tl_block *b = malloc(sizeof *b + size);
        if (!b) return NULL;
        b->used = b->cap = size;
        if (a->head) {
            b->next = a->head->next;
            a->head->next = b;
        } else {
            b->next = NULL;
            a->head = b;
        }
        memset(b->data, 0, size);
        return b->data;
    }
    if (!a->head || a->head->cap - a->head->used < size) {
        tl_block *b = malloc(sizeof *b + TL_BLOCK_BYTES);
        if (!b) return NULL;
        b->used = 0;
        b->cap = TL_BLOCK_BYTES;
        b->next = a->head;
        a->head = b;
    }
    void *p = (char *)a->head->data + a->head->used;
    a->head->used += size;
    memset(p, 0, size);
    return p;
}

tl_layer *tl_new_layer(tl_arena *a, tl_layer_list *L)
{
    if (L->n == L->cap) {
        int cap = L->cap ? L->cap * 2 : 8;
        tl_layer *v = tl_alloc(a, (size_t)cap * sizeof *v);
        if (!v) return NULL;
        if (L->n) memcpy(v, L->v, (size_t)L->n * sizeof *v);
        L->v = v;
        L->cap = cap;
    }
    tl_layer *l = &L->v[L->n++];
    memset(l, 0, sizeof *l);
    return l;
}

char *tl_strndup(tl_arena *a, const char *s, size_t n)
{
    if (n == (size_t)-1) return NULL;
    char *d = tl_alloc(a, n + 1);
    if (d) {
        memcpy(d, s, n);
        d[n] = '\0';
    }
    return d;
}

void tl_arena_free(tl_arena *a)
{
    while (a->head) {
        tl_block *b = a->head;
        a->head = b->next;
        free(b);
    }
}

/* ---------------------------------------------------------------- messages */

static void loc_prefix(char *buf, size_t cap, tl_loc at)
{
    if (at.line > 0) snprintf(buf, cap, "%s:%d:%d", at.file, at.line, at.col > 0 ? at.col : 1);
    else snprintf(buf, cap, "%s", at.file);
}

nt_status tl_vfail(tl_ctx *c, tl_loc at, const char *fmt, va_list ap)
{
    if (!c->err) return NT_ERR_PARSE;
    char *m = c->err->message;
    size_t cap = sizeof c->err->message;
    loc_prefix(m, cap - 64, at);
    size_t n = strlen(m);
    m[n++] = ':';
    m[n++] = ' ';
    vsnprintf(m + n, cap - n, fmt, ap);
    c->err->line = at.line > 0 ? at.line : 0;
    c->err->column = at.line > 0 ? (at.col > 0 ? at.col : 1) : 0;
    return NT_ERR_PARSE;
}

nt_status tl_fail(tl_ctx *c, tl_loc at, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    nt_status s = tl_vfail(c, at, fmt, ap);
    va_end(ap);
    return s;
}

nt_status tl_oom(tl_ctx *c, const char *file)
{
    if (c->err) {
        snprintf(c->err->message, sizeof c->err->message, "%s: out of memory", file);
        c->err->line = c->err->column = 0;
    }
    return NT_ERR_OUT_OF_MEMORY;
}

void tl_warn(tl_ctx *c, tl_loc at, const char *fmt, ...)
{
    c->warnings++;
    if (!c->warn) return;
    char all[900];
    loc_prefix(all, 400, at);
    size_t n = strlen(all);
    memcpy(all + n, ": warning: ", 12);
    n += 11;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(all + n, sizeof all - n, fmt, ap);
    va_end(ap);
    c->warn(all, c->wctx);
}

const char *tl_quote(char buf[64], const char *s)
{
    size_t k = 0;
    buf[k++] = '"';
    for (size_t i = 0; s[i] && k < 56; i++) {
        unsigned char ch = (unsigned char)s[i];
        if (ch < 0x20 || ch == 0x7f) k += (size_t)snprintf(buf + k, 64 - k, "\\x%02x", ch);
        else buf[k++] = (char)ch;
        if (s[i + 1] && k >= 56) {
            memcpy(buf + k, "...", 3);
            k += 3;
            break;
        }
    }
    buf[k++] = '"';
    buf[k] = '\0';
    return buf;
}

