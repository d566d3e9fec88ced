/* libFuzzer harness: the Tiled importer (tools/tiled) on one map text, JSON or XML
 * by its first character. An imported level must write a canonical text that
 * parses. External tilesets named by the input are read if they exist (regular
 * files only). Built by `make fuzz`. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include "ntile/ntile.h"
#include "tiled/tiled.h"

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
    /* No extension: the importer picks the format from the text. */
    if (tiled_import("fuzz-map", (const char *)data, size, &a, &err, quiet, NULL) != NT_OK) {
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
