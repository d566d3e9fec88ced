/* The committed tile tables (src/tile_tables.c) are exactly what tools/tilegen writes
 * from the canonical shapes (`make tiles` rewrites the file). Their values are checked
 * against the independent reference in test_tiles.c. Run from the top of the tree. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tilegen/tilegen.h"

#define TABLES "src/tile_tables.c"

/* The whole stream, from malloc, NUL-terminated; *len its length. */
static char *slurp(FILE *f, size_t *len)
{
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    assert_non_null(buf);
    size_t got;
    while ((got = fread(buf + n, 1, cap - n, f)) > 0) {
        n += got;
        if (n == cap) {
            cap *= 2;
            buf = realloc(buf, cap + 1);
            assert_non_null(buf);
        }
    }
    assert_false(ferror(f));
    buf[n] = '\0';
    *len = n;
    return buf;
}

static char *generate(size_t *len)
{
    FILE *f = tmpfile();
    assert_non_null(f);
    assert_int_equal(tilegen_write(f), 0);
    rewind(f);
    char *text = slurp(f, len);
    fclose(f);
    return text;
}

/* Offset of the first byte where a and b differ (the shorter one's end counts), or -1. */
static long first_difference(const char *a, size_t na, const char *b, size_t nb)
{
    size_t n = na < nb ? na : nb;
    for (size_t i = 0; i < n; i++)
        if (a[i] != b[i]) return (long)i;
    return na == nb ? -1 : (long)n;
}

static int line_of(const char *s, long off)
{
    int line = 1;
    for (long i = 0; i < off; i++) line += s[i] == '\n';
    return line;
}

static void test_committed_tables_are_the_generators_output(void **state)
{
    (void)state;
    size_t ng, nc;
    char *gen = generate(&ng);
    FILE *f = fopen(TABLES, "rb");
    if (!f) fail_msg("%s: cannot open (run the test from the top of the tree)", TABLES);
    char *committed = slurp(f, &nc);
    fclose(f);
    long d = first_difference(gen, ng, committed, nc);
    if (d >= 0)
        fail_msg("%s differs from tools/tilegen's output from line %d on (%zu bytes against %zu): run make tiles, "
                 "or change the generator instead of the file", TABLES, line_of(committed, d), nc, ng);
    /* The three tables, all 34 tiles each. */
    assert_non_null(strstr(gen, "const nt_tile_info nt__tiles[NT_TILE_COUNT] = {"));
    assert_non_null(strstr(gen, "const nt__tile_geom nt__geom[NT_TILE_COUNT] = {"));
    assert_non_null(strstr(gen, "const nt__poly nt__polys[NT_TILE_COUNT] = {"));
    int names = 0;
    for (const char *p = gen; (p = strstr(p, "/* HALFl */")) != NULL; p++) names++;
    assert_int_equal(names, 2); /* the last tile, in nt__geom and nt__polys */
    free(gen);
    free(committed);
}

static void test_generator_is_deterministic(void **state)
{
    (void)state;
    size_t na, nb;
    char *a = generate(&na), *b = generate(&nb);
    assert_true(na > 10000);
    assert_int_equal(first_difference(a, na, b, nb), -1);
    free(a);
    free(b);
}

/* The comparison itself sees one changed byte, and a missing last byte. */
static void test_comparison_sees_a_change(void **state)
{
    (void)state;
    size_t n;
    char *a = generate(&n);
    char *b = malloc(n + 1);
    assert_non_null(b);
    memcpy(b, a, n + 1);
    long at = (long)(n / 2);
    b[at] ^= 1;
    assert_int_equal(first_difference(a, n, b, n), at);
    b[at] ^= 1;
    assert_int_equal(first_difference(a, n, b, n), -1);
    assert_int_equal(first_difference(a, n, b, n - 1), (long)n - 1);
    free(a);
    free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_committed_tables_are_the_generators_output),
        cmocka_unit_test(test_generator_is_deterministic),
        cmocka_unit_test(test_comparison_sees_a_change),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
