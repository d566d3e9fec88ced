/* Shared by the level harnesses (fuzz_level.c, fuzz_n14.c, fuzz_tiled.c): a level's
 * canonical text, and the check every importer's output must pass. */
#ifndef NT_FUZZ_LEVEL_TEXT_H
#define NT_FUZZ_LEVEL_TEXT_H

#include <stdio.h>
#include <stdlib.h>
#include "ntile/ntile.h"

/* The canonical text of l (malloc'd, *n bytes without the terminator); aborts when
 * memory runs out, which a harness must not mistake for a finding. */
static inline char *fuzz_write_level(const nt_level *l, size_t *n)
{
    *n = nt_level_write(l, NULL, 0);
    char *t = malloc(*n + 1);
    if (!t) abort();
    nt_level_write(l, t, *n + 1);
    return t;
}

/* An imported level must write a canonical text that parses. */
static inline void fuzz_check_import(const nt_level *imported)
{
    size_t n;
    char *t = fuzz_write_level(imported, &n);
    nt_level *b = NULL;
    nt_text_error err;
    if (nt_level_parse("imported.ntl", t, n, &b, &err) != NT_OK) {
        fprintf(stderr, "imported level does not parse: %s\n", err.message);
        abort();
    }
    free(t);
    nt_level_destroy(b);
}

/* Importers' warnings are expected: dropped. */
static inline void fuzz_quiet(const char *message, void *context)
{
    (void)message;
    (void)context;
}

#endif
