/* libFuzzer harness: the N v1.4 importer. An imported level must write a canonical
 * text that parses. Built by `make fuzz`. */
#include <stdint.h>
#include <stdlib.h>
#include "level_text.h"
#include "ntile/ntile.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    nt_level *a = NULL;
    nt_text_error err;
    int count = 0;
    if (nt_level_import_n14("fuzz.txt", (const char *)data, size, 0, &a, &count, &err, fuzz_quiet, NULL) != NT_OK) {
        if (a) abort();
        return 0;
    }
    fuzz_check_import(a);
    nt_level_destroy(a);
    return 0;
}
