/* libFuzzer harness: random programs of world API calls (see world_ops.h). Any
 * broken check aborts, so the fuzzer keeps the input. Built by `make fuzz`. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include "world_ops.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char msg[256] = "";
    if (world_ops_run(data, size, msg, sizeof msg)) {
        fprintf(stderr, "world_ops: %s\n", msg);
        abort();
    }
    return 0;
}
