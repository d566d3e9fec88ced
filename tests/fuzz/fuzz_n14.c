/* libFuzzer harness: the N v1.4 importer. An imported level must write a canonical
 * text that parses. Built by `make fuzz`. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include "ntile/ntile.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void quiet(const char *message, void *context)
{
    (void)message;
    (void)context;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    nt_level *a = NULL, *b = NULL;
    nt_text_error err;
    int count = 0;
    if (nt_level_import_n14("fuzz.txt", (const char *)data, size, 0, &a, &count, &err, quiet, NULL) != NT_OK) {
        if (a) abort();
        return 0;
    }
    size_t n = nt_level_write(a, NULL, 0);
    char *t = malloc(n + 1);
    if (!t) abort();
    nt_level_write(a, t, n + 1);
    if (nt_level_parse("imported.ntl", t, n, &b, &err) != NT_OK) {
        fprintf(stderr, "imported level does not parse: %s\n", err.message);
        abort();
    }
    free(t);
    nt_level_destroy(a);
    nt_level_destroy(b);
    return 0;
}
