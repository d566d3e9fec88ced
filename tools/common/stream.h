/* Reading a whole stream into memory, and reading and writing whole files: what the
 * ntile CLI, the playground and the Tiled importer share. Header only, so that each
 * program keeps its own link line. */
#ifndef NTILE_TOOLS_STREAM_H
#define NTILE_TOOLS_STREAM_H

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* A message into why (cap bytes), cut to fit: a long path shortens the message, never
 * overflows it. */
static inline void stream_say(char *why, size_t cap, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, cap, fmt, ap);
    va_end(ap);
}

/* The largest file any ntile tool reads (levels, replays, Tiled maps, scripts, CSVs):
 * 256 MiB, above the largest level (4096 x 4096 cells with materials and flags). */
#define STREAM_MAX_FILE ((size_t)1 << 28)

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

/* 1 when the open stream f (of `path`) is a regular file of at most `limit` bytes;
 * otherwise 0 and a message naming the path in why ("'levels' is a directory, not a
 * file", "'/dev/zero' is not a regular file", "... is larger than N bytes"). */
static inline int stream_check_regular(FILE *f, const char *path, size_t limit, char *why, size_t cap)
{
    struct stat st;
    if (fstat(fileno(f), &st) != 0) {
        stream_say(why, cap, "cannot read '%s': %s", path, strerror(errno));
        return 0;
    }
    if (!S_ISREG(st.st_mode)) {
        stream_say(why, cap, S_ISDIR(st.st_mode) ? "'%s' is a directory, not a file" : "'%s' is not a regular file",
                 path);
        return 0;
    }
    if ((unsigned long long)st.st_size > (unsigned long long)limit) {
        stream_say(why, cap, "'%s' is larger than %zu bytes", path, limit);
        return 0;
    }
    return 1;
}

/* Opens `path` for reading when it is a regular file of at most `limit` bytes; otherwise
 * NULL and why says so, naming the path (or why it would not open). Every file reader
 * of the tools goes through here or stream_check_regular: a device, a FIFO or a
 * directory is never read, and nothing is read without a limit. */
static inline FILE *stream_open_regular(const char *path, size_t limit, char *why, size_t cap)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        stream_say(why, cap, "cannot open '%s': %s", path, strerror(errno));
        return NULL;
    }
    if (!stream_check_regular(f, path, limit, why, cap)) {
        fclose(f);
        return NULL;
    }
    return f;
}

/* Reads the whole file at `path` ("-": standard input, when allow_stdin) into a
 * NUL-terminated buffer from malloc: 1, or 0 with *out NULL and why saying what went
 * wrong, naming the path. */
static inline int stream_read_file(const char *path, int allow_stdin, char **out, size_t *len, char *why, size_t cap)
{
    *out = NULL;
    *len = 0;
    FILE *f = allow_stdin && strcmp(path, "-") == 0 ? stdin : stream_open_regular(path, STREAM_MAX_FILE, why, cap);
    if (!f) return 0;
    int r = stream_read_all(f, STREAM_MAX_FILE, out, len);
    if (f != stdin) fclose(f);
    if (r == STREAM_NO_MEMORY) {
        stream_say(why, cap, "out of memory reading '%s' (or larger than %zu bytes)", path, STREAM_MAX_FILE);
        return 0;
    }
    if (r == STREAM_READ_ERROR) {
        stream_say(why, cap, "error reading '%s'", path);
        return 0;
    }
    return 1;
}

/* Writes data to `path` through a sibling file renamed over it, so that a failed write
 * leaves the old file as it was: 1, or 0 and why. `tag` makes the sibling's name
 * (path.tmpTAG) differ between writers. */
static inline int stream_write_file(const char *path, const char *data, size_t len, long tag, char *why, size_t cap)
{
    size_t pl = strlen(path);
    char *tmp = malloc(pl + 32);
    if (!tmp) {
        stream_say(why, cap, "out of memory writing '%s'", path);
        return 0;
    }
    snprintf(tmp, pl + 32, "%s.tmp%ld", path, tag);
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        stream_say(why, cap, "cannot write '%s': %s", path, strerror(errno));
        free(tmp);
        return 0;
    }
    int ok = fwrite(data, 1, len, f) == len;
    ok = (fclose(f) == 0) && ok;
    if (ok && rename(tmp, path) != 0) ok = 0;
    if (!ok) {
        stream_say(why, cap, "cannot write '%s': %s", path, strerror(errno));
        remove(tmp);
    }
    free(tmp);
    return ok;
}

#endif
