/* libFuzzer harness: the `ntile query` line protocol over a byte buffer (the same
 * code as the CLI; answers go to /dev/null). Built by `make fuzz`. */
#include <stdint.h>
#include <stdio.h>
#include "../../tools/ntile/cli.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static FILE *sink;
    if (!sink) sink = fopen("/dev/null", "w");
    if (!sink) return 0;
    /* A small line limit keeps each input fast; the limit's own path is exercised too. */
    cli_query_buffer(data, size, sink, (size_t)1 << 16);
    return 0;
}
