/* libFuzzer harness: the .ntl level parser. A level that parses must write back to a
 * text that parses to the same text again (the canonical writer), and small levels
 * must build a world that steps. Built by `make fuzz`. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "level_text.h"
#include "ntile/ntile.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    nt_level *a = NULL, *b = NULL;
    nt_text_error err;
    if (nt_level_parse("fuzz.ntl", (const char *)data, size, &a, &err) != NT_OK) {
        if (a) abort(); /* a failed parse leaves nothing */
        return 0;
    }
    size_t n1, n2;
    char *t1 = fuzz_write_level(a, &n1);
    if (nt_level_parse("again.ntl", t1, n1, &b, &err) != NT_OK) {
        fprintf(stderr, "canonical text does not parse: %s\n", err.message);
        abort();
    }
    char *t2 = fuzz_write_level(b, &n2);
    if (n1 != n2 || memcmp(t1, t2, n1) != 0) {
        fprintf(stderr, "load -> save -> load -> save differs\n");
        abort();
    }
    if (nt_level_instance_count(a) <= 256) {
        nt_world *w = NULL;
        if (nt_level_create_world(a, &w, NULL, 0) == NT_OK) {
            for (int s = 0; s < 4; s++) nt_world_step(w, (nt_real)1 / 40);
            nt_world_destroy(w);
        }
    }
    free(t1);
    free(t2);
    nt_level_destroy(a);
    nt_level_destroy(b);
    return 0;
}
