/* The world API fuzzer's interpreter (tests/fuzz/world_ops.h) on seeded random
 * programs, so that every `make test` runs a few thousand hostile call sequences
 * without libFuzzer (`make fuzz` explores further). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include "fuzz/world_ops.h"

static uint64_t next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static void test_random_programs(void **state)
{
    (void)state;
    uint64_t seed = 0x776f726c64ull; /* "world" */
    static uint8_t prog[2048];
    int failures = 0;
    for (int run = 0; run < 1000; run++) {
        size_t n = 64 + next(&seed) % (sizeof prog - 64);
        for (size_t i = 0; i < n; i++) prog[i] = (uint8_t)next(&seed);
        char msg[256] = "";
        if (world_ops_run(prog, n, msg, sizeof msg)) {
            print_error("program %d: %s\n", run, msg);
            failures++;
        }
    }
    assert_int_equal(failures, 0);
}

/* The committed seed corpus of `make fuzz`, replayed. */
static void test_empty_and_tiny_programs(void **state)
{
    (void)state;
    char msg[256] = "";
    assert_int_equal(world_ops_run(NULL, 0, msg, sizeof msg), 0);
    const uint8_t one[] = {0};
    assert_int_equal(world_ops_run(one, sizeof one, msg, sizeof msg), 0);
    /* create a body, then step with every dt in the table */
    const uint8_t prog[] = {8, 8, 0, 0, 1, 0, 2, 128, 1, 0, 100, 0, 100, 0, 0, 0, 0, 0, 1, 1, 1, 0, 0,
                            8, 0, 0, 3, 8, 0, 1, 3, 8, 0, 2, 3, 8, 0, 3, 3, 8, 0, 4, 3, 8, 0, 5, 3};
    assert_int_equal(world_ops_run(prog, sizeof prog, msg, sizeof msg), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_programs),
        cmocka_unit_test(test_empty_and_tiny_programs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
