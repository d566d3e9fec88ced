/* libFuzzer harness: the Tiled importer (tools/tiled) on one map text, JSON or XML
 * by its first character. An imported level must write a canonical text that
 * parses. External tilesets named by the input are read if they exist (regular
 * files only). Built by `make fuzz`. */
#include <stdint.h>
#include <stdlib.h>
#include "level_text.h"
#include "ntile/ntile.h"
#include "tiled/tiled.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    nt_level *a = NULL;
    nt_text_error err;
    /* No extension: the importer picks the format from the text. */
    if (tiled_import("fuzz-map", (const char *)data, size, &a, &err, fuzz_quiet, NULL) != NT_OK) {
        if (a) abort();
        return 0;
    }
    fuzz_check_import(a);
    nt_level_destroy(a);
    return 0;
}
