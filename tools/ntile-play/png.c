/* Minimal PNG writer: see png.h. */
#include "png.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------- byte and bit output */

typedef struct out {
    unsigned char *p;
    size_t n, cap;
    int oom;
    uint32_t bits; /* pending bits, LSB first */
    int nbits;
} out;

static void put(out *o, const void *data, size_t n)
{
    if (o->oom || n == 0) return;
    if (o->n + n > o->cap) {
        size_t cap = o->cap ? o->cap : 4096;
        while (cap < o->n + n) cap *= 2;
        unsigned char *p = realloc(o->p, cap);
        if (!p) {
            o->oom = 1;
            return;
        }
        o->p = p;
        o->cap = cap;
    }
    memcpy(o->p + o->n, data, n);
    o->n += n;
}

static void put_byte(out *o, unsigned v)
{
    unsigned char b = (unsigned char)v;
    put(o, &b, 1);
}

static void put_be32(out *o, uint32_t v)
{
    unsigned char b[4] = {(unsigned char)(v >> 24), (unsigned char)(v >> 16), (unsigned char)(v >> 8), (unsigned char)v};
    put(o, b, 4);
}

/* n bits of v, least significant first (DEFLATE's order for everything but Huffman codes). */
static void put_bits(out *o, uint32_t v, int n)
{
    o->bits |= v << o->nbits;
    o->nbits += n;
    while (o->nbits >= 8) {
        put_byte(o, o->bits & 0xffu);
        o->bits >>= 8;
        o->nbits -= 8;
    }
}

/* A Huffman code: its bits go most significant first. */
static void put_code(out *o, uint32_t code, int n)
{
    uint32_t r = 0;
    for (int i = 0; i < n; i++) r |= ((code >> i) & 1u) << (n - 1 - i);
    put_bits(o, r, n);
}

static void flush_bits(out *o)
{
    if (o->nbits > 0) put_byte(o, o->bits & 0xffu);
    o->bits = 0;
    o->nbits = 0;
}

/* ---------------------------------------------------------------- checksums */

uint32_t pg_crc32(uint32_t crc, const unsigned char *p, size_t n)
{
    static uint32_t table[256];
    static int ready;
    if (!ready) {
        for (uint32_t i = 0; i < 256; i++) {
            uint32_t c = i;
            for (int k = 0; k < 8; k++) c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
            table[i] = c;
        }
        ready = 1;
    }
    crc = ~crc;
    for (size_t i = 0; i < n; i++) crc = table[(crc ^ p[i]) & 0xffu] ^ (crc >> 8);
    return ~crc;
}

static uint32_t adler32(const unsigned char *p, size_t n)
{
    uint32_t a = 1, b = 0;
    for (size_t i = 0; i < n; i++) {
        a = (a + p[i]) % 65521u;
        b = (b + a) % 65521u;
    }
    return b << 16 | a;
}

/* ---------------------------------------------------------------- deflate, fixed codes */

static void put_literal(out *o, unsigned lit)
{
    if (lit < 144) put_code(o, 0x30u + lit, 8);
    else if (lit < 256) put_code(o, 0x190u + (lit - 144), 9);
    else if (lit < 280) put_code(o, lit - 256, 7);
    else put_code(o, 0xc0u + (lit - 280), 8);
}

static const unsigned short len_base[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                            31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
static const unsigned char len_extra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                            2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
static const unsigned short dist_base[30] = {1,   2,   3,   4,   5,   7,    9,    13,   17,   25,   33,   49,   65,    97,    129,
                                             193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
static const unsigned char dist_extra[30] = {0, 0, 0, 0, 1, 1, 2, 2,  3,  3,  4,  4,  5,  5,  6,
                                             6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};

static void put_match(out *o, int len, int dist)
{
    int i = 28;
    while (len_base[i] > len) i--;
    put_literal(o, 257u + (unsigned)i);
    put_bits(o, (uint32_t)(len - len_base[i]), len_extra[i]);
    int d = 29;
    while (dist_base[d] > dist) d--;
    put_code(o, (uint32_t)d, 5);
    put_bits(o, (uint32_t)(dist - dist_base[d]), dist_extra[d]);
}

#define HASH_BITS 15
#define WINDOW 32768
#define MAX_CHAIN 48

static unsigned hash3(const unsigned char *p) { return ((p[0] << 10) ^ (p[1] << 5) ^ p[2]) & ((1u << HASH_BITS) - 1); }

/* One final block with fixed Huffman codes: greedy LZ77 with hash chains. */
static int deflate_fixed(out *o, const unsigned char *src, size_t n)
{
    int *head = malloc(sizeof(int) << HASH_BITS);
    int *prev = malloc(sizeof(int) * WINDOW);
    if (!head || !prev) {
        free(head);
        free(prev);
        return 0;
    }
    for (int i = 0; i < (1 << HASH_BITS); i++) head[i] = -1;
    put_bits(o, 1, 1); /* BFINAL */
    put_bits(o, 1, 2); /* BTYPE = 01, fixed codes */
    size_t i = 0;
    while (i < n) {
        int best = 0, best_dist = 0;
        if (i + 3 <= n) {
            unsigned h = hash3(src + i);
            int cand = head[h], chain = 0;
            size_t max = n - i < 258 ? n - i : 258;
            while (cand >= 0 && i - (size_t)cand <= WINDOW && chain++ < MAX_CHAIN) {
                const unsigned char *a = src + cand, *b = src + i;
                size_t l = 0;
                while (l < max && a[l] == b[l]) l++;
                if ((int)l > best) {
                    best = (int)l;
                    best_dist = (int)(i - (size_t)cand);
                    if (l == max) break;
                }
                cand = prev[cand % WINDOW];
            }
        }
        size_t step = best >= 3 ? (size_t)best : 1;
        if (best >= 3) put_match(o, best, best_dist);
        else put_literal(o, src[i]);
        for (size_t k = 0; k < step; k++, i++) {
            if (i + 3 <= n) {
                unsigned h = hash3(src + i);
                prev[i % WINDOW] = head[h];
                head[h] = (int)i;
            }
        }
    }
    put_literal(o, 256); /* end of block */
    flush_bits(o);
    free(head);
    free(prev);
    return 1;
}

/* ---------------------------------------------------------------- PNG */

static void chunk(out *o, const char *type, const unsigned char *data, size_t n)
{
    put_be32(o, (uint32_t)n);
    size_t at = o->n;
    put(o, type, 4);
    put(o, data, n);
    if (!o->oom) put_be32(o, pg_crc32(0, o->p + at, n + 4));
}

unsigned char *pg_png_encode(const uint32_t *px, int w, int h, int stride, size_t *size)
{
    *size = 0;
    if (w <= 0 || h <= 0 || stride < w) return NULL;
    size_t row = (size_t)w * 3 + 1, raw_n = row * (size_t)h;
    unsigned char *raw = malloc(raw_n);
    if (!raw) return NULL;
    for (int y = 0; y < h; y++) {
        unsigned char *r = raw + (size_t)y * row;
        r[0] = 1; /* filter: Sub (each byte minus the byte 3 to its left) */
        const uint32_t *s = px + (size_t)y * (size_t)stride;
        uint32_t left = 0;
        for (int x = 0; x < w; x++) {
            uint32_t c = s[x] & 0xffffffu;
            for (int k = 0; k < 3; k++) {
                int sh = 16 - 8 * k;
                r[1 + 3 * x + k] = (unsigned char)(((c >> sh) - (left >> sh)) & 0xffu);
            }
            left = c;
        }
    }
    out z = {0}, o = {0};
    put_byte(&z, 0x78); /* zlib: deflate, 32 KiB window */
    put_byte(&z, 0x01); /* no dictionary, fastest; (0x78 << 8 | 0x01) % 31 == 0 */
    int ok = deflate_fixed(&z, raw, raw_n);
    put_be32(&z, adler32(raw, raw_n));
    free(raw);
    if (!ok || z.oom) {
        free(z.p);
        return NULL;
    }
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    put(&o, sig, 8);
    unsigned char ihdr[13] = {(unsigned char)(w >> 24), (unsigned char)(w >> 16), (unsigned char)(w >> 8), (unsigned char)w,
                              (unsigned char)(h >> 24), (unsigned char)(h >> 16), (unsigned char)(h >> 8), (unsigned char)h,
                              8, 2, 0, 0, 0}; /* 8 bits, RGB, deflate, adaptive filters, no interlace */
    chunk(&o, "IHDR", ihdr, sizeof ihdr);
    chunk(&o, "IDAT", z.p, z.n);
    chunk(&o, "IEND", NULL, 0);
    free(z.p);
    if (o.oom) {
        free(o.p);
        return NULL;
    }
    *size = o.n;
    return o.p;
}

int pg_png_write(const char *path, const uint32_t *px, int w, int h, int stride)
{
    size_t n;
    unsigned char *data = pg_png_encode(px, w, h, stride, &n);
    if (!data) return 0;
    FILE *f = fopen(path, "wb");
    int ok = f && fwrite(data, 1, n, f) == n;
    if (f && fclose(f) != 0) ok = 0;
    free(data);
    return ok;
}
