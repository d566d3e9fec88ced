/* Reading a whole stream into memory: the one loop the ntile CLI, the playground and
 * the Tiled importer share (each words its own messages). Header only, so that each
 * program keeps its own link line. */
#ifndef NTILE_TOOLS_STREAM_H
#define NTILE_TOOLS_STREAM_H

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>

enum { STREAM_OK, STREAM_NO_MEMORY, STREAM_READ_ERROR };

/* Reads f to its end into a NUL-terminated buffer from malloc (*out, *len). The buffer
 * starts at 64 KiB and doubles while smaller than `limit` bytes; a stream that needs
 * more, or memory running out, gives STREAM_NO_MEMORY. A read error gives
 * STREAM_READ_ERROR with errno as fread left it. On failure *out is NULL and nothing
 * stays allocated. f is not closed. */
static inline int stream_read_all(FILE *f, size_t limit, char **out, size_t *len)
{
    *out = NULL;
    *len = 0;
    size_t cap = (size_t)1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    if (!buf) return STREAM_NO_MEMORY;
    for (;;) {
        if (n == cap) {
            char *nb = cap < limit ? realloc(buf, cap * 2 + 1) : NULL;
            if (!nb) {
                free(buf);
                return STREAM_NO_MEMORY;
            }
            buf = nb;
            cap *= 2;
        }
        size_t k = fread(buf + n, 1, cap - n, f);
        n += k;
        if (k == 0) break;
    }
    if (ferror(f)) {
        int e = errno;
        free(buf);
        errno = e;
        return STREAM_READ_ERROR;
    }
    buf[n] = '\0';
    *out = buf;
    *len = n;
    return STREAM_OK;
}

#endif
