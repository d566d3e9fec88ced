/* libFuzzer harness: the .ntr replay parser and its canonical writer (a replay that
 * parses writes back to a text that parses to the same text). Built by `make fuzz`. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "ntile/ntile.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char *write_replay(const nt_replay *r, size_t *n)
{
    *n = nt_replay_write(r, NULL, 0);
    char *t = malloc(*n + 1);
    if (t) nt_replay_write(r, t, *n + 1);
    return t;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    nt_replay *a = NULL, *b = NULL;
    nt_text_error err;
    if (nt_replay_parse("fuzz.ntr", (const char *)data, size, &a, &err) != NT_OK) {
        if (a) abort();
        return 0;
    }
    size_t n1, n2;
    char *t1 = write_replay(a, &n1);
    if (!t1) abort();
    if (nt_replay_parse("again.ntr", t1, n1, &b, &err) != NT_OK) {
        fprintf(stderr, "canonical text does not parse: %s\n", err.message);
        abort();
    }
    char *t2 = write_replay(b, &n2);
    if (!t2 || n1 != n2 || memcmp(t1, t2, n1) != 0) {
        fprintf(stderr, "load -> save -> load -> save differs\n");
        abort();
    }
    free(t1);
    free(t2);
    nt_replay_destroy(a);
    nt_replay_destroy(b);
    return 0;
}
