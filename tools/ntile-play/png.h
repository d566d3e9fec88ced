/* A minimal PNG writer (no zlib): 8-bit RGB, each row filtered with "Sub", deflated
 * with LZ77 (hash chains, 32 KiB window) and DEFLATE's fixed Huffman codes. Enough to
 * keep the README's screenshot small; not a general-purpose encoder. */
#ifndef PG_PNG_H
#define PG_PNG_H

#include <stddef.h>
#include <stdint.h>

/* Encode w x h pixels (0x00RRGGBB, row-major, `stride` pixels per row) as a PNG file in
 * memory. Returns a malloc'ed buffer and its size in *size, or NULL when out of memory. */
unsigned char *pg_png_encode(const uint32_t *px, int w, int h, int stride, size_t *size);

/* The same, written to `path`. 1 on success. */
int pg_png_write(const char *path, const uint32_t *px, int w, int h, int stride);

/* CRC-32 (PNG's, ISO-HDLC) of n bytes, continuing from crc (start with 0). */
uint32_t pg_crc32(uint32_t crc, const unsigned char *p, size_t n);

#endif
