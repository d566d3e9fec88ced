/* Tests of the CLI `ntile query` protocol (and the CLI's usage errors and bench).
 *
 * Each test writes its input into a private temporary directory, runs the binary
 * named by the NTILE environment variable (`make test` sets it) with fork/exec, and
 * checks its standard output line by line and its exit status. Expected numbers are
 * worked out by hand from the tile geometry in the comments and compared with a
 * tolerance; words (ok, miss, hit, error:) are compared exactly.
 */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "child.h"
#include "scratch.h"
#include "ntile/ntile.h"

#define TOL 2e-5

/* ---------- temporary files (scratch.h) ---------- */

static int group_setup(void **state)
{
    (void)state;
    return scratch_create("query");
}

static int group_teardown(void **state)
{
    (void)state;
    scratch_remove();
    return 0;
}

static const char *write_bytes(const void *data, size_t len) { return scratch_new(data, len); }
static const char *write_text(const char *text) { return scratch_new(text, strlen(text)); }

/* ---------- running the CLI ---------- */

typedef struct run_result {
    int status;   /* exit status; 128 + signal when killed */
    char *out;    /* standard output, NUL-terminated */
    size_t out_len;
    char *err;    /* standard error */
    size_t err_len;
    char *split;  /* a copy of out cut into lines */
    char **lines; /* the lines of standard output (each ended with '\n') */
    size_t nlines;
} run_result;

/* Run `ntile ARGS...` (NULL-terminated) with standard input from stdin_path (or
 * /dev/null), capturing both outputs; the CLI must not crash, report a sanitizer
 * error or exit above 2. */
static void run_cli(run_result *r, const char *stdin_path, const char *const *args)
{
    child_result c;
    child_run_input(&c, scratch_dir(), child_ntile(), args, stdin_path, NULL, NULL, 3);
    r->status = c.status;
    r->out = c.out;
    r->out_len = c.out_len;
    r->err = c.err;
    r->err_len = c.err_len;
    /* Split the output: every line ends with '\n', and none holds a NUL. */
    assert_int_equal(strlen(r->out), r->out_len);
    assert_true(r->out_len == 0 || r->out[r->out_len - 1] == '\n');
    size_t count = 0;
    for (size_t i = 0; i < r->out_len; i++) count += r->out[i] == '\n';
    r->lines = calloc(count + 1, sizeof *r->lines);
    assert_non_null(r->lines);
    r->nlines = 0;
    r->split = malloc(r->out_len + 1);
    assert_non_null(r->split);
    memcpy(r->split, r->out, r->out_len + 1);
    char *s = r->split;
    for (size_t i = 0; i < count; i++) {
        char *nl = strchr(s, '\n');
        *nl = '\0';
        r->lines[r->nlines++] = s;
        s = nl + 1;
    }
}

static void run_free(run_result *r)
{
    free(r->out);
    free(r->err);
    free(r->split);
    free(r->lines);
    memset(r, 0, sizeof *r);
}

/* `ntile query FILE` on the given text. */
static void run_query_text(run_result *r, const char *text)
{
    const char *path = write_text(text);
    const char *args[] = {"query", path, NULL};
    run_cli(r, NULL, args);
}

/* ---------- checking answers ---------- */

/* Parse exactly n numbers separated by single spaces. */
static void parse_numbers(const char *s, double *v, int n)
{
    for (int i = 0; i < n; i++) {
        char *end;
        v[i] = strtod(s, &end);
        if (end == s) fail_msg("expected %d numbers, got '%s'", n, s);
        assert_true(isfinite(v[i]));
        s = end;
        if (i + 1 < n) {
            if (*s != ' ') fail_msg("expected a space after number %d in '%s'", i + 1, s);
            s++;
        }
    }
    if (*s) fail_msg("trailing text '%s' after %d numbers", s, n);
}

static void assert_close(double got, double want, const char *what)
{
    if (!(fabs(got - want) <= TOL)) fail_msg("%s: got %.9g, want %.9g", what, got, want);
}

static void expect_vec(const char *line, double dx, double dy)
{
    double v[2];
    parse_numbers(line, v, 2);
    assert_close(v[0], dx, "DX");
    assert_close(v[1], dy, "DY");
}

static void expect_hit(const char *line, double t, double nx, double ny)
{
    if (strncmp(line, "hit ", 4) != 0) fail_msg("expected 'hit ...', got '%s'", line);
    double v[3];
    parse_numbers(line + 4, v, 3);
    assert_close(v[0], t, "T");
    assert_close(v[1], nx, "NX");
    assert_close(v[2], ny, "NY");
}

/* `error: line N: ...` naming the right line, with a non-empty reason containing `needle`. */
static void expect_error(const char *line, unsigned long lineno, const char *needle)
{
    char prefix[64];
    snprintf(prefix, sizeof prefix, "error: line %lu: ", lineno);
    if (strncmp(line, prefix, strlen(prefix)) != 0) fail_msg("expected '%s...', got '%s'", prefix, line);
    if (strlen(line) <= strlen(prefix) + 3) fail_msg("error reason too short: '%s'", line);
    if (needle && !strstr(line, needle)) fail_msg("expected '%s' in '%s'", needle, line);
}

/* One input line and what it must print:
 *   NULL            nothing (blank or comment)
 *   "ok", "miss"    that exact word
 *   "v DX DY"       a vector
 *   "h T NX NY"     a ray hit
 *   "e TEXT"        an error on this line whose reason contains TEXT */
typedef struct qa {
    const char *in;
    const char *expect;
} qa;

static void check_answers(const run_result *r, const qa *cases, size_t n)
{
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        const char *e = cases[i].expect;
        if (!e) continue;
        if (k >= r->nlines) fail_msg("no output for line %zu '%s'", i + 1, cases[i].in);
        const char *got = r->lines[k++];
        if (e[0] == 'v') {
            double v[2];
            parse_numbers(e + 2, v, 2);
            expect_vec(got, v[0], v[1]);
        } else if (e[0] == 'h') {
            double v[3];
            parse_numbers(e + 2, v, 3);
            expect_hit(got, v[0], v[1], v[2]);
        } else if (e[0] == 'e') {
            expect_error(got, (unsigned long)i + 1, e + 2);
        } else if (strcmp(got, e) != 0) {
            fail_msg("line %zu '%s': expected '%s', got '%s'", i + 1, cases[i].in, e, got);
        }
    }
    assert_int_equal(r->nlines, k);
}

/* Run the cases as one file and check every answer and the exit status. */
static void run_cases(const qa *cases, size_t n)
{
    size_t len = 1;
    for (size_t i = 0; i < n; i++) len += strlen(cases[i].in) + 1;
    char *text = malloc(len);
    assert_non_null(text);
    text[0] = '\0';
    int errors = 0;
    for (size_t i = 0; i < n; i++) {
        strcat(text, cases[i].in);
        strcat(text, "\n");
        errors |= cases[i].expect && cases[i].expect[0] == 'e';
    }
    run_result r;
    run_query_text(&r, text);
    check_answers(&r, cases, n);
    assert_int_equal(r.status, errors ? 1 : 0);
    run_free(&r);
    free(text);
}

#define RUN_CASES(c) run_cases(c, sizeof(c) / sizeof((c)[0]))

/* ---------- answers ---------- */

static void test_tile_answers(void **state)
{
    (void)state;
    static const qa cases[] = {
        {"# one tile alone in cell (0,0)", NULL},
        /* Box y span [-0.15, 0.35]: 0.35 into the top of FULL; the other ways out are 0.75+. */
        {"tile FULL aabb 0.5 0.1 0.25 0.25", "v 0 -0.35"},
        /* Touching the top face is not overlapping. */
        {"tile FULL aabb 0.5 -0.25 0.25 0.25", "v 0 0"},
        {"tile EMPTY aabb 0.5 0.5 0.25 0.25", "v 0 0"},
        /* Numeric id 1 = FULL; circle 0.1 into the top. */
        {"tile 1 circle 0.5 -0.1 0.2", "v 0 -0.1"},
        /* 45DEGpn: solid where x < y, outward normal (1,-1)/sqrt2. Centre (0.3,0.5) is
         * inside, 0.2/sqrt2 from the slope: leaves by 0.2 + 0.2/sqrt2 along the normal,
         * i.e. DX = 0.2/sqrt2 + 0.1 (the left face would need 0.5, the bottom 0.7). */
        {"tile 45DEGpn circle 0.3 0.5 0.2", "v 0.2414213562 -0.2414213562"},
        /* Centre (0.6,0.4) outside, 0.2/sqrt2 from the slope, nearest point (0.5,0.5)
         * on it: depth 0.2 - 0.2/sqrt2, DX = 0.2/sqrt2 - 0.1. */
        {"tile 45DEGpn circle 0.6 0.4 0.2", "v 0.0414213562 -0.0414213562"},
        /* 22DEGpnS: solid below y = 0.5 + x/2, normal (1,-2)/sqrt5. Box corner (0.4,0.8)
         * is 0.1 below the line at x = 0.4: depth 0.2/sqrt5 -> (0.04, -0.08). */
        {"tile 22DEGpnS aabb 0.5 0.7 0.1 0.1", "v 0.04 -0.08"},
        /* Larger than the cell. A 4 x 2 box, y span [-0.7, 1.3]: up by 1.3 (down 1.7,
         * sideways 2.5). */
        {"tile FULL aabb 0.5 0.3 2 1", "v 0 -1.3"},
        /* The 45DEGpn circle above with radius 2: out along the normal by 2 + 0.2/sqrt2,
         * i.e. DX = (2 + 0.2/sqrt2)/sqrt2 = sqrt2 + 0.1. */
        {"tile 45DEGpn circle 0.3 0.5 2", "v 1.5142135624 -1.5142135624"},
        /* 67DEGpnS: solid where x < y/2, normal (2,-1)/sqrt5. Centre (0.2,0.6) is inside
         * by 0.2/sqrt5; out by 0.1 + 0.2/sqrt5 -> (0.2/sqrt5 + 0.08, -0.1/sqrt5 - 0.04). */
        {"tile 67DEGpnS circle 0.2 0.6 0.1", "v 0.1694427191 -0.0847213595"},
        /* CONVEXpn: quarter disc of radius 1 around (0,1). Centre (0.5,0.5) is 1/sqrt2
         * from (0,1): out along (1,-1)/sqrt2 by 1 - 1/sqrt2 + 0.1 = 0.39289. */
        {"tile CONVEXpn circle 0.5 0.5 0.1", "v 0.2778174593 -0.2778174593"},
        /* CONVEXnn is the mirror image (disc around (1,1)): same push, x mirrored. */
        {"tile CONVEXnn circle 0.5 0.5 0.1", "v -0.2778174593 -0.2778174593"},
        /* CONCAVEpn: cell minus the disc of radius 1 around (1,0). Centre (0.2,0.8) is
         * 0.8*sqrt2 from (1,0); the circle fits back into the disc after moving
         * 0.8*sqrt2 - 0.9 toward (1,0) (the left and bottom faces need 0.3). */
        {"tile CONCAVEpn circle 0.2 0.8 0.1", "v 0.1636038969 -0.1636038969"},
        /* HALFd fills y >= 0.5: a point (size 0) at y = 0.6 leaves up by 0.1. */
        {"tile HALFd aabb 0.5 0.6 0 0", "v 0 -0.1"},
        /* HALFl fills x <= 0.5: a box spanning x in [0.45, 0.95] leaves right by 0.05. */
        {"tile HALFl aabb 0.7 0.5 0.25 0.1", "v 0.05 0"},
        {"tile FULL circle 0.5 0.1 0", "v 0 -0.1"},
        /* A point on the boundary touches only. */
        {"tile FULL aabb 0 0.5 0 0", "v 0 0"},
    };
    RUN_CASES(cases);
}

static void test_pair_answers(void **state)
{
    (void)state;
    static const qa cases[] = {
        /* Centres 0.6 apart, radii 0.5: the first moves 0.4 away from the second. */
        {"pair circle 0 0 0.5 circle 0.6 0 0.5", "v -0.4 0"},
        /* Box [-0.2,0.2]^2 vs circle at (0.5,0) r 0.4: nearest box point (0.2,0) is 0.3
         * from the centre, depth 0.1; the box moves left, the circle right. */
        {"pair aabb 0 0 0.2 0.2 circle 0.5 0 0.4", "v -0.1 0"},
        {"pair circle 0.5 0 0.4 aabb 0 0 0.2 0.2", "v 0.1 0"},
        /* Boxes: x overlap 0.6 - 0.5 = 0.1, y overlap 0.4 - 0.1 = 0.3: along x. */
        {"pair aabb 0 0 0.3 0.2 aabb 0.5 0.1 0.3 0.2", "v -0.1 0"},
        /* Same boxes shifted so y is the shallow axis: the first moves down. */
        {"pair aabb 0 0.35 0.3 0.2 aabb 0.1 0 0.3 0.2", "v 0 0.05"},
        {"pair circle 0 0 0.2 circle 1 0 0.2", "v 0 0"},
        /* Touching circles do not overlap. */
        {"pair circle 0 0 0.25 circle 0 0.5 0.25", "v 0 0"},
        /* A zero-radius circle 0.3 inside a circle of radius 0.5: out by 0.2. */
        {"pair circle 0 0 0 circle 0.3 0 0.5", "v -0.2 0"},
    };
    RUN_CASES(cases);
}

/* A 4 x 3 map: rows 0 and 1 empty, row 2 a FULL floor (its top at y = 2). */
#define FLOOR_MAP "map 4 3 EMPTY,EMPTY,EMPTY,EMPTY,EMPTY,EMPTY,EMPTY,EMPTY,FULL,FULL,FULL,FULL"

static void test_map_resolve_and_ray(void **state)
{
    (void)state;
    static const qa cases[] = {
        {FLOOR_MAP, "ok"},
        /* A box on the seam x = 2 between two floor tiles, 0.1 into the floor: up. */
        {"resolve aabb 2 1.9 0.3 0.2", "v 0 -0.1"},
        /* Tall box sunk 0.25, just right of the seam: tile (2,2) alone would push it
         * 0.12 left and tile (1,2) 0.08 right, but the seam is no edge: up by 0.25. */
        {"resolve aabb 2.02 1.8 0.1 0.45", "v 0 -0.25"},
        {"resolve circle 2 1.8 0.3", "v 0 -0.1"},
        /* Resting exactly on the floor: touching only. */
        {"resolve aabb 1.5 1.75 0.25 0.25", "v 0 0"},
        {"resolve circle 1.5 1.0 0.4", "v 0 0"},
        /* Outside the map is solid: a box 0.1 into the top border (y < 0) goes down. */
        {"resolve aabb 1.5 0.15 0.25 0.25", "v 0 0.1"},
        /* Straight down from y = 0.5 to y = 2.5 meets the floor at y = 2: T = 0.75. */
        {"ray 0.5 0.5 0.5 2.5", "h 0.75 0 -1"},
        /* Diagonal (2,2) from (0.5,1): reaches y = 2 at T = 0.5. */
        {"ray 0.5 1 2.5 3", "h 0.5 0 -1"},
        /* Left into the border at x = 0: T = 0.5, normal (1,0). */
        {"ray 0.5 0.5 -0.5 0.5", "h 0.5 1 0"},
        {"ray 0.5 0.5 3.5 0.5", "miss"},
        /* Starting inside the floor. */
        {"ray 1.5 2.5 3.5 2.5", "h 0 0 0"},
        /* The same floor by ids, the list split into rows, replaces the map. */
        {"map 4 3 0,0,0,0 0,0,0,0 1,1,1,1", "ok"},
        {"resolve aabb 2 1.9 0.3 0.2", "v 0 -0.1"},
        /* An open map, one cell wide and tall: only the border. */
        {"map 1 1 EMPTY", "ok"},
        {"ray 0.5 0.5 0.5 0.9", "miss"},
        {"ray 0.5 0.5 0.5 1.5", "h 0.5 0 -1"},
        /* A map line that fails keeps the current map. */
        {"map 1 1 BOGUS", "e 'BOGUS'"},
        {"ray 0.5 0.5 0.5 1.5", "h 0.5 0 -1"},
    };
    RUN_CASES(cases);
}

static void test_no_negative_zero(void **state)
{
    (void)state;
    /* CONVEXnn is CONVEXpn mirrored in x; a push straight down out of its bottom face
     * (0.1 deep) has a mirrored zero x component, which must print as 0, not -0. */
    run_result r;
    run_query_text(&r, "tile CONVEXnn circle 0.5 1.1 0.2\npair aabb 0 0 0.1 0.1 aabb 0 0.15 0.1 0.1\n");
    assert_int_equal(r.status, 0);
    assert_int_equal(r.nlines, 2);
    expect_vec(r.lines[0], 0, 0.1);
    expect_vec(r.lines[1], 0, -0.05);
    for (size_t i = 0; i < r.nlines; i++) {
        char copy[256];
        snprintf(copy, sizeof copy, "%s", r.lines[i]);
        for (char *tok = strtok(copy, " "); tok; tok = strtok(NULL, " "))
            if (strcmp(tok, "-0") == 0) fail_msg("negative zero printed: '%s'", r.lines[i]);
    }
    run_free(&r);
}

/* ---------- shortest numbers, line numbers, tile names ---------- */

/* A printed number's significant digits ("-0.0350" -> 3, "100" -> 1, "1.5e-07" -> 2). */
static int significant_digits(const char *tok)
{
    int n = 0, trailing_zeros = 0, started = 0;
    for (const char *p = tok; *p && *p != 'e' && *p != 'E'; p++) {
        if (*p < '0' || *p > '9') continue;
        if (*p == '0' && !started) continue;
        started = 1;
        n++;
        trailing_zeros = *p == '0' ? trailing_zeros + 1 : 0;
    }
    return n - trailing_zeros;
}

/* tok reads back as exactly v (as nt_real), and no decimal with fewer significant
 * digits does. */
static void expect_shortest(const char *tok, nt_real v)
{
    if (v == 0) v = 0;
#if NT_REAL_IS_DOUBLE
    nt_real back = strtod(tok, NULL);
#else
    nt_real back = strtof(tok, NULL);
#endif
    if (memcmp(&back, &v, sizeof v) != 0) fail_msg("'%s' does not read back as %.17g", tok, (double)v);
    int digits = significant_digits(tok);
    if (digits >= 2) {
        char shorter[64];
        snprintf(shorter, sizeof shorter, "%.*e", digits - 2, (double)v);
#if NT_REAL_IS_DOUBLE
        nt_real b2 = strtod(shorter, NULL);
#else
        nt_real b2 = strtof(shorter, NULL);
#endif
        if (memcmp(&b2, &v, sizeof v) == 0) fail_msg("'%s' is not the shortest form: '%s' reads back the same", tok, shorter);
    }
    if (strchr(tok, 'e') && fabs((double)v) >= 1e-5 && fabs((double)v) < 1e16)
        fail_msg("'%s' has an exponent although it is between 1e-5 and 1e16", tok);
}

static void test_shortest_numbers(void **state)
{
    (void)state;
    /* The README's example: -0.35, not -0.349999994. */
    run_result r;
    run_query_text(&r, "tile FULL aabb 0.5 0.1 0.25 0.25\n");
    assert_int_equal(r.nlines, 1);
    assert_string_equal(r.lines[0], "0 -0.35");
    run_free(&r);
    /* Random tile and pair queries: every number the shortest that reads back as the
     * engine's own answer. */
    enum { N = 400 };
    static char text[N * 96];
    static nt_real want[N][2];
    size_t o = 0;
    uint64_t seed = 12345;
    for (int i = 0; i < N; i++) {
        double v[5];
        for (int k = 0; k < 5; k++) {
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            v[k] = (double)(seed >> 11) * 0x1.0p-53;
        }
        char line[96];
        int tile = 1 + i % (NT_TILE_COUNT - 1);
        nt_mtv m;
        bool hit;
        if (i % 2) {
            snprintf(line, sizeof line, "tile %s circle %.6f %.6f %.6f\n", nt_tile_get_info(tile)->name, v[0] * 1.4 - 0.2,
                     v[1] * 1.4 - 0.2, v[2] * 0.5 + 0.01);
        } else {
            snprintf(line, sizeof line, "pair aabb 0 0 %.6f %.6f circle %.6f %.6f %.6f\n", v[0] + 0.1, v[1] + 0.1,
                     v[2] - 0.5, v[3] - 0.5, v[4] + 0.1);
        }
        /* The same arithmetic as the CLI, from the same text. */
        char copy[96], *f[10];
        int nf = 0;
        snprintf(copy, sizeof copy, "%s", line);
        for (char *t = strtok(copy, " \n"); t && nf < 10; t = strtok(NULL, " \n")) f[nf++] = t;
        if (i % 2) {
            hit = nt_tile_collide_shape(tile, nt_v2((nt_real)strtod(f[3], NULL), (nt_real)strtod(f[4], NULL)),
                                        nt_shape_circle((nt_real)strtod(f[5], NULL)), &m);
        } else {
            hit = nt_collide_shapes(nt_v2(0, 0), nt_shape_aabb((nt_real)strtod(f[4], NULL), (nt_real)strtod(f[5], NULL)),
                                    nt_v2((nt_real)strtod(f[7], NULL), (nt_real)strtod(f[8], NULL)),
                                    nt_shape_circle((nt_real)strtod(f[9], NULL)), &m);
        }
        want[i][0] = hit ? m.normal.x * m.depth : 0;
        want[i][1] = hit ? m.normal.y * m.depth : 0;
        memcpy(text + o, line, strlen(line));
        o += strlen(line);
    }
    text[o] = '\0';
    run_query_text(&r, text);
    assert_int_equal(r.status, 0);
    assert_int_equal(r.nlines, N);
    int hits = 0;
    for (int i = 0; i < N; i++) {
        char copy[128];
        snprintf(copy, sizeof copy, "%s", r.lines[i]);
        char *a = strtok(copy, " "), *b = strtok(NULL, " ");
        if (!a || !b || strtok(NULL, " ")) fail_msg("line %d: expected 'DX DY', got '%s'", i + 1, r.lines[i]);
        expect_shortest(a, want[i][0]);
        expect_shortest(b, want[i][1]);
        hits += want[i][0] != 0 || want[i][1] != 0;
    }
    assert_true(hits > N / 4); /* the sample really exercises the formatter */
    run_free(&r);
}

static void test_line_numbers(void **state)
{
    (void)state;
    const char *in = write_text("# a comment\n\ntile FULL aabb 0.5 0.1 0.25 0.25\nbogus\nmap 1 3 empty,full,empty\n"
                                "ray 0.5 0.5 0.5 2.5\nray 0.5 0.2 0.5 0.8\n");
    const char *forms[][3] = {{"query", "-n", NULL}, {"query", "--line-numbers", NULL}};
    for (size_t i = 0; i < 2; i++) {
        run_result r;
        const char *args[] = {forms[i][0], forms[i][1], in, NULL};
        run_cli(&r, NULL, args);
        assert_int_equal(r.status, 1);
        assert_int_equal(r.nlines, 5);
        assert_string_equal(r.lines[0], "3: 0 -0.35");
        if (strncmp(r.lines[1], "4: error: line 4: unknown command 'bogus'", 41) != 0) fail_msg("got '%s'", r.lines[1]);
        assert_string_equal(r.lines[2], "5: ok");
        assert_string_equal(r.lines[3], "6: hit 0.25 0 -1");
        assert_string_equal(r.lines[4], "7: miss");
        run_free(&r);
    }
}

static void test_tile_names(void **state)
{
    (void)state;
    run_result r;
    /* Any case is the same tile; a near miss gets a hint, a far one the list. */
    run_query_text(&r, "tile full aabb 0.5 0.1 0.25 0.25\ntile FuLl aabb 0.5 0.1 0.25 0.25\n"
                       "tile 45degPN aabb 0.2 0.2 0.1 0.1\ntile 45DEGpn aabb 0.2 0.2 0.1 0.1\n"
                       "tile FUL aabb 0 0 1 1\ntile 45DGEpn aabb 0 0 1 1\ntile halfy aabb 0 0 1 1\n"
                       "tile wobble aabb 0 0 1 1\nmap 2 1 Full,EMTPY\nmap 2 1 full,empty\n");
    assert_int_equal(r.status, 1);
    assert_int_equal(r.nlines, 10);
    assert_string_equal(r.lines[0], "0 -0.35");
    assert_string_equal(r.lines[1], "0 -0.35");
    assert_string_equal(r.lines[2], r.lines[3]);
    expect_error(r.lines[4], 5, "unknown tile name 'FUL' (did you mean 'FULL'?)");
    expect_error(r.lines[5], 6, "(did you mean '45DEGpn'?)");
    expect_error(r.lines[6], 7, "unknown tile name 'halfy' (expected an N tile name");
    expect_error(r.lines[7], 8, "unknown tile name 'wobble' (expected an N tile name");
    expect_error(r.lines[8], 9, "unknown tile name 'EMTPY' (map tile 2) (did you mean 'EMPTY'?)");
    assert_string_equal(r.lines[9], "ok");
    run_free(&r);
}

/* Every subcommand and sub-subcommand answers --help (and -h) with its usage on
 * standard output and status 0; no subcommand at all is a usage error. */
static void test_help_everywhere(void **state)
{
    (void)state;
    static const char *const cmds[][4] = {
        {"query", NULL},           {"run", NULL},           {"sheet", NULL},         {"soak", NULL},
        {"bench", NULL},           {"bench", "world", NULL}, {"bench", "narrow", NULL}, {"bench", "scaling", NULL},
        {"bench", "character", NULL}, {"bench", "sweep", NULL}, {"bench", "plot", NULL}, {"convert", NULL},
        {"convert", "n14", NULL},  {"convert", "tiled", NULL},
    };
    static const char *const flags[] = {"--help", "-h"};
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++) {
        for (size_t k = 0; k < 2; k++) {
            const char *args[6];
            int n = 0;
            for (int j = 0; cmds[i][j]; j++) args[n++] = cmds[i][j];
            args[n++] = flags[k];
            args[n] = NULL;
            run_result r;
            run_cli(&r, NULL, args);
            if (r.status != 0) fail_msg("ntile %s %s %s: status %d\n%s", cmds[i][0], cmds[i][1] ? cmds[i][1] : "", flags[k], r.status, r.err);
            char want[64];
            snprintf(want, sizeof want, "ntile %s", cmds[i][0]);
            if (!strstr(r.out, "usage") || !strstr(r.out, want))
                fail_msg("ntile %s %s %s: no usage on stdout: '%s'", cmds[i][0], cmds[i][1] ? cmds[i][1] : "", flags[k], r.out);
            run_free(&r);
        }
    }
    const char *none[] = {NULL};
    run_result r;
    run_cli(&r, NULL, none);
    assert_int_equal(r.status, 2);
    assert_int_equal(r.out_len, 0);
    if (!strstr(r.err, "usage: ntile SUBCOMMAND") || !strstr(r.err, "ntile query")) fail_msg("no usage on stderr: '%s'", r.err);
    run_free(&r);
}

/* ---------- errors ---------- */

static void test_error_lines(void **state)
{
    (void)state;
    static const qa cases[] = {
        {"# every error is followed by a line that must still be answered", NULL},
        {"frobnicate 1 2 3", "e 'frobnicate'"},
        {"tile FULL aabb 0.5 0.1 0.25 0.25", "v 0 -0.35"},
        {"tile FOO aabb 0.5 0.5 0.1 0.1", "e unknown tile name 'FOO'"},
        {"tile 34 circle 0.5 0.5 0.1", "e '34'"},
        {"tile FULL box 0.5 0.5 0.1 0.1", "e 'box'"},
        {"tile FULL aabb 0.5 0.1 0.25", "e fields"},
        {"tile FULL circle 0.5 0.1 0.25 0.25", "e fields"},
        {"tile FULL", "e fields"},
        {"ray 1 2 3", "e fields"},
        {"pair aabb 0 0 0.1 0.1", "e fields"},
        {"pair aabb 0 0 0.1 0.1 circle 0 0 0.1 7", "e fields"},
        {"resolve circle 1 1 0.1 0.1", "e fields"},
        {"map 2 1", "e fields"},
        {"tile 1 circle 0.5 -0.1 0.2", "v 0 -0.1"},
        {"tile FULL aabb 0.5 abc 0.1 0.1", "e 'abc'"},
        {"tile FULL aabb 0.5 1.5x 0.1 0.1", "e '1.5x'"},
        {"pair circle 0 0 0.1 circle 0 0 0,1", "e '0,1'"},
        {"tile FULL aabb nan 0.5 0.1 0.1", "e 'nan'"},
        {"tile FULL aabb 0.5 inf 0.1 0.1", "e 'inf'"},
        {"tile FULL circle -infinity 0.5 0.1", "e '-infinity'"},
        {"tile FULL circle 1e999 0.5 0.1", "e '1e999'"},
        {"pair circle 0 0 0.5 circle 0.6 0 0.5", "v -0.4 0"},
        {"tile FULL aabb 0.5 0.5 -0.1 0.1", "e negative"},
        {"tile FULL aabb 0.5 0.5 0.1 -0.1", "e negative"},
        {"pair circle 0 0 -0.001 circle 0 0 0.1", "e negative"},
        /* Half-sizes up to NT_MAX_HALF_CELLS (4) cells: bodies up to 8 cells across. */
        {"tile FULL aabb 0.5 0.5 4.5 0.1", "e half-width '4.5' is larger than the largest half-size (4)"},
        {"tile FULL aabb 0.5 0.5 0.1 4.0000005", "e larger than the largest half-size (4)"},
        {"tile FULL circle 0.5 0.5 4.01", "e radius '4.01' is larger than the largest half-size (4)"},
        {"pair aabb 0 0 0.1 0.1 circle 0 0 1e6", "e '1e6' is larger than the largest half-size (4)"},
        /* Half a cell, as before. Ways out: down 1 + 0.5 - 0.6 = 0.9, left/right 1.0, up 1.1. */
        {"tile FULL circle 0.5 0.6 0.5", "v 0 0.9"},
        /* Exactly the cap: down 1 - 0.6 + 4 = 4.4, left/right 4.5, up 4.6. */
        {"tile FULL circle 0.5 0.6 4", "v 0 4.4"},
        {"map 0 1 FULL", "e '0'"},
        {"map 4097 1 FULL", "e '4097'"},
        {"map 1 -1 FULL", "e '-1'"},
        {"map 1.5 1 FULL", "e '1.5'"},
        {"map 2 2 FULL,FULL,FULL", "e 4"},
        {"map 2 1 FULL,FULL,FULL", "e 2"},
        {"map 2 1 FULL,", "e empty"},
        {"map 2 1 FULL,NOPE", "e 'NOPE'"},
        {"map 2 1 FULL,34", "e '34'"},
        {"pair aabb 0 0 0.2 0.2 circle 0.5 0 0.4", "v -0.1 0"},
        {"   # an indented comment", NULL},
        {"", NULL},
        {" \t ", NULL},
        {"tile FULL aabb 0.5 0.1 0.25 0.25 # a trailing comment", "v 0 -0.35"},
    };
    RUN_CASES(cases);
}

/* Objects larger than a cell against a map (issue 18): an 8 x 6 box of cells, its
 * bottom row FULL (top at y = 5); outside the map is solid. */
static void test_resolve_large(void **state)
{
    (void)state;
    static const qa cases[] = {
        {"map 8 6 0,0,0,0,0,0,0,0 0,0,0,0,0,0,0,0 0,0,0,0,0,0,0,0 0,0,0,0,0,0,0,0 0,0,0,0,0,0,0,0 1,1,1,1,1,1,1,1", "ok"},
        /* A 4 x 2.4 box sunk 0.1 into the floor across four seams: up. */
        {"resolve aabb 4 3.9 2 1.2", "v 0 -0.1"},
        /* A circle 3 across sunk 0.1: up. */
        {"resolve circle 4 3.6 1.5", "v 0 -0.1"},
        /* 0.1 into the left border: right. */
        {"resolve aabb 1.9 2 2 1", "v 0.1 0"},
        /* The largest box, 8 x 8 cells, in the air between border and floor: touching only. */
        {"resolve aabb 4 1 4 1", "v 0 0"},
    };
    RUN_CASES(cases);
}

static void test_resolve_and_ray_need_a_map(void **state)
{
    (void)state;
    static const qa cases[] = {
        {"resolve aabb 1 1 0.1 0.1", "e map"},
        {"resolve circle 1 1 0.1", "e map"},
        {"ray 0.5 0.5 0.5 1.5", "e map"},
        {"tile FULL aabb 0.5 0.1 0.25 0.25", "v 0 -0.35"},
        {"map 1 1 FOO", "e 'FOO'"},
        {"ray 0.5 0.5 0.5 1.5", "e map"},
        {"map 1 1 EMPTY", "ok"},
        {"ray 0.5 0.5 0.5 1.5", "h 0.5 0 -1"},
        {"resolve aabb 0.5 0.5 0.1 0.1", "v 0 0"},
    };
    RUN_CASES(cases);
}

/* ---------- exit status and usage ---------- */

static void test_exit_status(void **state)
{
    (void)state;
    run_result r;
    /* All fine: 0, one line per non-comment line. */
    run_query_text(&r, "# fine\n\ntile FULL aabb 0.5 0.1 0.25 0.25\n  \n# x\npair circle 0 0 0.5 circle 0.6 0 0.5\n");
    assert_int_equal(r.status, 0);
    assert_int_equal(r.nlines, 2);
    run_free(&r);
    /* Only comments: no output, 0. */
    run_query_text(&r, "# nothing\n\n");
    assert_int_equal(r.status, 0);
    assert_int_equal(r.nlines, 0);
    run_free(&r);
    /* One error among good lines: 1, and every line still answered. */
    run_query_text(&r, "tile FULL aabb 0.5 0.1 0.25 0.25\nbogus\ntile FULL aabb 0.5 0.1 0.25 0.25\n");
    assert_int_equal(r.status, 1);
    assert_int_equal(r.nlines, 3);
    expect_error(r.lines[1], 2, "'bogus'");
    expect_vec(r.lines[2], 0, -0.35);
    run_free(&r);
}

static void test_usage_errors(void **state)
{
    (void)state;
    run_result r;
    const char *ok_file = write_text("tile FULL aabb 0.5 0.1 0.25 0.25\n");
    char missing[4200];
    snprintf(missing, sizeof missing, "%s/does-not-exist.query", scratch_dir());

    const char *a1[] = {"query", ok_file, ok_file, NULL};
    run_cli(&r, NULL, a1);
    assert_int_equal(r.status, 2);
    assert_int_equal(r.out_len, 0);
    assert_true(r.err_len > 0);
    run_free(&r);

    const char *a2[] = {"query", missing, NULL};
    run_cli(&r, NULL, a2);
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "does-not-exist"));
    run_free(&r);

    const char *a3[] = {"query", scratch_dir(), NULL}; /* a directory cannot be read */
    run_cli(&r, NULL, a3);
    assert_int_equal(r.status, 2);
    assert_true(r.err_len > 0);
    run_free(&r);

    const char *a4[] = {"query", "--bogus", ok_file, NULL};
    run_cli(&r, NULL, a4);
    assert_int_equal(r.status, 2);
    run_free(&r);

    const char *a5[] = {"query", "--max-line", "0", ok_file, NULL};
    run_cli(&r, NULL, a5);
    assert_int_equal(r.status, 2);
    run_free(&r);

    const char *a6[] = {"frobnicate", NULL};
    run_cli(&r, NULL, a6);
    assert_int_equal(r.status, 2);
    assert_int_equal(r.out_len, 0);
    assert_non_null(strstr(r.err, "frobnicate"));
    assert_non_null(strstr(r.err, "query"));
    assert_non_null(strstr(r.err, "bench"));
    run_free(&r);

    const char *a7[] = {"bench", "nosuch", NULL};
    run_cli(&r, NULL, a7);
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "nosuch"));
    assert_non_null(strstr(r.err, "narrow")); /* the list of known benchmarks */
    run_free(&r);

    const char *a8[] = {"bench", NULL};
    run_cli(&r, NULL, a8);
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "narrow"));
    run_free(&r);

    /* An option the benchmark does not read is refused, not ignored (before any timing:
     * nothing on stdout). */
    const char *refused[][6] = {{"bench", "narrow", "--profile", NULL},
                                {"bench", "scaling", "--wide", NULL},
                                {"bench", "character", "--out", "x.csv", NULL},
                                {"bench", "world", "rain", "--out", "x.csv", NULL}};
    const char *why[] = {"ntile bench narrow: --profile does not apply", "ntile bench scaling: --wide does not apply",
                         "ntile bench character: --out does not apply", "ntile bench world: --out does not apply"};
    for (size_t i = 0; i < sizeof refused / sizeof refused[0]; i++) {
        run_cli(&r, NULL, refused[i]);
        assert_int_equal(r.status, 2);
        assert_int_equal(r.out_len, 0);
        assert_non_null(strstr(r.err, why[i])); /* the benchmark and the option named */
        run_free(&r);
    }

    /* Help: usage on stdout, status 0. */
    const char *helps[][2] = {{"--help", NULL}, {"help", NULL}, {"-h", NULL}};
    for (size_t i = 0; i < sizeof helps / sizeof helps[0]; i++) {
        run_cli(&r, NULL, helps[i]);
        assert_int_equal(r.status, 0);
        if (!strstr(r.out, "ntile query") || !strstr(r.out, "ntile bench"))
            fail_msg("help %zu: no usage text on stdout: '%s'", i, r.out);
        run_free(&r);
    }
}

/* ---------- input forms ---------- */

static void test_stdin(void **state)
{
    (void)state;
    const char *in = write_text("tile FULL aabb 0.5 0.1 0.25 0.25\nbogus\n");
    const char *forms[][3] = {{"query", NULL, NULL}, {"query", "-", NULL}};
    for (size_t i = 0; i < 2; i++) {
        run_result r;
        run_cli(&r, in, forms[i]);
        assert_int_equal(r.status, 1);
        assert_int_equal(r.nlines, 2);
        expect_vec(r.lines[0], 0, -0.35);
        expect_error(r.lines[1], 2, "'bogus'");
        run_free(&r);
    }
}

/* Read one line from a pipe, waiting at most 10 s for it. */
static void read_answer(int fd, char *buf, size_t cap)
{
    size_t n = 0;
    while (n + 1 < cap) {
        struct pollfd p = {fd, POLLIN, 0};
        int ready = poll(&p, 1, 10000);
        if (ready == 0) fail_msg("no answer within 10 s (got '%.*s'): is the output flushed?", (int)n, buf);
        assert_true(ready > 0);
        ssize_t k = read(fd, buf + n, 1);
        assert_true(k == 1);
        if (buf[n] == '\n') break;
        n++;
    }
    buf[n] = '\0';
}

static void test_pipe_dialogue(void **state)
{
    (void)state;
    /* A program drives the CLI through pipes: each answer arrives before the next
     * question is written and before standard input is closed. */
    const char *exe = child_ntile();
    int to_cli[2], from_cli[2];
    assert_int_equal(pipe(to_cli), 0);
    assert_int_equal(pipe(from_cli), 0);
    fflush(NULL);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        if (dup2(to_cli[0], 0) < 0 || dup2(from_cli[1], 1) < 0) _exit(125);
        close(to_cli[0]);
        close(to_cli[1]);
        close(from_cli[0]);
        close(from_cli[1]);
        execl(exe, exe, "query", (char *)NULL);
        _exit(126);
    }
    close(to_cli[0]);
    close(from_cli[1]);
    void (*old_pipe)(int) = signal(SIGPIPE, SIG_IGN);
    static const char *const questions[] = {"tile FULL aabb 0.5 0.1 0.25 0.25\n", "# no answer\nbogus\n",
                                            FLOOR_MAP "\n", "ray 0.5 0.5 0.5 2.5\n"};
    char answer[256];
    for (size_t i = 0; i < sizeof questions / sizeof questions[0]; i++) {
        size_t len = strlen(questions[i]);
        assert_int_equal(write(to_cli[1], questions[i], len), (ssize_t)len);
        read_answer(from_cli[0], answer, sizeof answer);
        if (i == 0) expect_vec(answer, 0, -0.35);
        if (i == 1) expect_error(answer, 3, "'bogus'");
        if (i == 2) assert_string_equal(answer, "ok");
        if (i == 3) expect_hit(answer, 0.75, 0, -1);
    }
    close(to_cli[1]);
    int ws;
    while (waitpid(pid, &ws, 0) < 0) assert_int_equal(errno, EINTR);
    signal(SIGPIPE, old_pipe);
    close(from_cli[0]);
    assert_true(WIFEXITED(ws));
    assert_int_equal(WEXITSTATUS(ws), 1);
}

static void test_crlf_and_last_line(void **state)
{
    (void)state;
    run_result r;
    run_query_text(&r, "# crlf\r\n\r\ntile FULL aabb 0.5 0.1 0.25 0.25\r\n" FLOOR_MAP "\r\n"
                       "ray 0.5 0.5 0.5 2.5\r\nresolve circle 2 1.8 0.3");
    assert_int_equal(r.status, 0);
    assert_int_equal(r.nlines, 4);
    expect_vec(r.lines[0], 0, -0.35);
    assert_string_equal(r.lines[1], "ok");
    expect_hit(r.lines[2], 0.75, 0, -1);
    expect_vec(r.lines[3], 0, -0.1);
    run_free(&r);
    /* A final line without a newline, and one ending in a lone CR. */
    run_query_text(&r, "tile FULL circle 0.5 -0.1 0.2\ntile FULL circle 0.5 -0.1 0.2\r");
    assert_int_equal(r.status, 0);
    assert_int_equal(r.nlines, 2);
    expect_vec(r.lines[1], 0, -0.1);
    run_free(&r);
}

static void test_long_lines(void **state)
{
    (void)state;
    run_result r;
    /* A valid 256 x 256 map on one line of about 400 KB: empty but the bottom row. */
    const int side = 256;
    size_t cap = (size_t)side * side * 7 + 64;
    char *text = malloc(cap + 256);
    assert_non_null(text);
    size_t n = (size_t)sprintf(text, "map %d %d ", side, side);
    for (int i = 0; i < side * side; i++) {
        const char *name = i >= side * (side - 1) ? "FULL" : "EMPTY";
        n += (size_t)sprintf(text + n, "%s%s", i ? "," : "", name);
    }
    /* Box 0.1 into the floor at y = 255; then a garbage line of 2 MB. */
    n += (size_t)sprintf(text + n, "\nresolve aabb 100 254.85 0.25 0.25\n");
    assert_true(n < cap);
    char *big = malloc(n + (2u << 20) + 64);
    assert_non_null(big);
    memcpy(big, text, n);
    memset(big + n, 'x', 2u << 20);
    n += 2u << 20;
    n += (size_t)sprintf(big + n, "\nresolve aabb 100 254.85 0.25 0.25\n");
    const char *path = write_bytes(big, n);
    const char *args[] = {"query", path, NULL};
    run_cli(&r, NULL, args);
    assert_int_equal(r.status, 1);
    assert_int_equal(r.nlines, 4);
    assert_string_equal(r.lines[0], "ok");
    expect_vec(r.lines[1], 0, -0.1);
    expect_error(r.lines[2], 3, "unknown command");
    expect_vec(r.lines[3], 0, -0.1);
    run_free(&r);
    free(big);

    /* Many fields on one line: one error, not several. */
    n = (size_t)sprintf(text, "tile FULL aabb");
    for (int i = 0; i < 100000; i++) n += (size_t)sprintf(text + n, " 1");
    sprintf(text + n, "\ntile FULL aabb 0.5 0.1 0.25 0.25\n");
    run_query_text(&r, text);
    assert_int_equal(r.status, 1);
    assert_int_equal(r.nlines, 2);
    expect_error(r.lines[0], 1, "fields");
    expect_vec(r.lines[1], 0, -0.35);
    run_free(&r);

    /* Over the line limit: one error for the whole line, then the next line answers;
     * a long comment stays a comment. */
    n = (size_t)sprintf(text, "tile FULL aabb 0.5 0.1 0.25 0.25%300s\n#%300s\n", "", "");
    n += (size_t)sprintf(text + n, "%100s\ntile FULL aabb 0.5 0.1 0.25 0.25\n", "tile FULL aabb 0.5 0.1 0.25 0.25");
    path = write_text(text);
    const char *limited[] = {"query", "--max-line", "64", path, NULL};
    run_cli(&r, NULL, limited);
    assert_int_equal(r.status, 1);
    assert_int_equal(r.nlines, 3);
    expect_error(r.lines[0], 1, "longer than 64");
    expect_error(r.lines[1], 3, "longer than 64");
    expect_vec(r.lines[2], 0, -0.35);
    run_free(&r);

    /* The limit counts the bytes before the line end: 32 fit, with LF or CR LF; 33 do not. */
    path = write_text("tile FULL aabb 0.5 0.1 0.25 0.25\n"
                      "tile FULL aabb 0.5 0.1 0.25 0.25\r\n"
                      "tile FULL aabb 0.5 0.1 0.25 0.25 \n"
                      "tile FULL aabb 0.5 0.1 0.25 0.25");
    const char *exact[] = {"query", "--max-line", "32", path, NULL};
    run_cli(&r, NULL, exact);
    assert_int_equal(r.status, 1);
    assert_int_equal(r.nlines, 4);
    expect_vec(r.lines[0], 0, -0.35);
    expect_vec(r.lines[1], 0, -0.35);
    expect_error(r.lines[2], 3, "longer than 32");
    expect_vec(r.lines[3], 0, -0.35);
    run_free(&r);
    free(text);
}

static void test_nul_bytes(void **state)
{
    (void)state;
    static const char input[] = "tile FULL\0 aabb 0.5 0.1 0.25 0.25\n"
                                "\0\n"
                                "# a comment may hold \0 anything\n"
                                "tile FULL aabb 0.5 0.1 0.25 0.25\n"
                                "tile FULL aabb 0.5 0.1 0.25 0.25\0";
    const char *path = write_bytes(input, sizeof input - 1);
    const char *args[] = {"query", path, NULL};
    run_result r;
    run_cli(&r, NULL, args);
    assert_int_equal(r.status, 1);
    assert_int_equal(r.nlines, 4);
    expect_error(r.lines[0], 1, "NUL");
    expect_error(r.lines[1], 2, "NUL");
    expect_vec(r.lines[2], 0, -0.35);
    expect_error(r.lines[3], 5, "NUL");
    run_free(&r);
}

/* Whitespace as the query reader sees it. */
static int blank_byte(unsigned char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

static void test_random_bytes(void **state)
{
    (void)state;
    /* 64 KB of pseudo-random bytes, newlines, blanks and NULs made common: every line that is not
     * blank or a comment gives exactly one line, and here that is an error. */
    size_t len = 1u << 16;
    unsigned char *buf = malloc(len);
    assert_non_null(buf);
    uint32_t s = 12345;
    for (size_t i = 0; i < len; i++) {
        s = s * 1664525u + 1013904223u;
        unsigned v = s >> 24;
        buf[i] = (unsigned char)(v < 8 ? '\n' : v < 24 ? ' ' : v < 28 ? '\0' : v < 30 ? '\r' : v);
    }
    /* Expected output lines: the numbers of the lines that are not blank or comments. */
    unsigned long *expect = malloc(sizeof *expect * (len + 1));
    assert_non_null(expect);
    size_t nexpect = 0;
    unsigned long lineno = 0;
    for (size_t i = 0; i < len;) {
        size_t j = i;
        while (j < len && buf[j] != '\n') j++;
        lineno++;
        size_t k = i;
        while (k < j && blank_byte(buf[k])) k++;
        if (k < j && buf[k] != '#') expect[nexpect++] = lineno;
        i = j + 1;
    }
    const char *path = write_bytes(buf, len);
    const char *args[] = {"query", path, NULL};
    run_result r;
    run_cli(&r, NULL, args);
    assert_int_equal(r.status, 1);
    assert_int_equal(r.nlines, nexpect);
    for (size_t i = 0; i < nexpect; i++) expect_error(r.lines[i], expect[i], NULL);
    run_free(&r);
    free(expect);
    free(buf);
}

static void test_demo_file(void **state)
{
    (void)state;
    const char *demo = "levels/demo.query";
    FILE *f = fopen(demo, "rb");
    if (!f) {
        print_message("%s not found (run from the project root); skipping\n", demo);
        skip();
    }
    size_t want = 0;
    char line[4096];
    while (fgets(line, sizeof line, f)) {
        const char *p = line;
        while (*p && (blank_byte((unsigned char)*p) || *p == '\n')) p++;
        want += *p && *p != '#';
    }
    fclose(f);
    const char *args[] = {"query", demo, NULL};
    run_result r;
    run_cli(&r, NULL, args);
    assert_int_equal(r.status, 0);
    assert_int_equal(r.nlines, want);
    for (size_t i = 0; i < r.nlines; i++)
        if (strncmp(r.lines[i], "error", 5) == 0) fail_msg("demo line answered '%s'", r.lines[i]);
    run_free(&r);
}

static void test_bench_narrow(void **state)
{
    (void)state;
    const char *args[] = {"bench", "narrow", "--runs", "1", "--min-ms", "0", NULL};
    run_result r;
    run_cli(&r, NULL, args);
    assert_int_equal(r.status, 0);
    const char *scalar = NT_REAL_IS_DOUBLE ? "double" : "float";
    static const char *const kinds[] = {"narrow aabb-vs-tile ", "narrow circle-vs-tile "};
    for (size_t k = 0; k < 2; k++) {
        int found = 0;
        for (size_t i = 0; i < r.nlines; i++) {
            if (strncmp(r.lines[i], kinds[k], strlen(kinds[k])) != 0 || !strstr(r.lines[i], "median")) continue;
            double ns = strtod(r.lines[i] + strlen(kinds[k]), NULL);
            assert_true(ns > 0 && ns < 1e6);
            assert_non_null(strstr(r.lines[i], "ns/test"));
            assert_non_null(strstr(r.lines[i], scalar));
            found = 1;
        }
        if (!found) fail_msg("no '%s... median' line in:\n%s", kinds[k], r.out);
    }
    run_free(&r);
}

/* `bench world` on two quick scenes: a progress line per scene on stderr, the narrow
 * table with a PASS/FAIL per check, the phase rows only with --profile, every error
 * column with --wide. */
static void test_bench_world_table(void **state)
{
    (void)state;
    const char *a1[] = {"bench", "world", "bounce", "flight", "--runs", "1", "--min-ms", "0", NULL};
    run_result r;
    run_cli(&r, NULL, a1);
    assert_int_equal(r.status, 0);
    if (!strstr(r.err, "ntile bench world: [1/2] bounce ...\n") || !strstr(r.err, "ntile bench world: [2/2] flight ...\n"))
        fail_msg("no progress lines on stderr: '%s'", r.err);
    int header = 0, apex = 0, path = 0;
    for (size_t i = 0; i < r.nlines; i++) {
        const char *l = r.lines[i];
        if (strlen(l) > 100) fail_msg("line wider than 100 columns: '%s'", l);
        if (strstr(l, "phases, ns/body-step")) fail_msg("phase rows without --profile: '%s'", l);
        header |= strncmp(l, "scene ", 6) == 0 && strstr(l, "check") && strstr(l, "result") != NULL;
        if (strstr(l, "apex error")) {
            apex = 1;
            if (!strstr(l, "<= 0.05") || (!strstr(l, "PASS") && !strstr(l, "FAIL"))) fail_msg("apex row: '%s'", l);
        }
        if (strstr(l, "path error")) {
            path = 1;
            if (!strstr(l, "<= 0.0001") || (!strstr(l, "PASS") && !strstr(l, "FAIL"))) fail_msg("path row: '%s'", l);
        }
    }
    if (!header || !apex || !path) fail_msg("missing header (%d), apex (%d) or path (%d) row in:\n%s", header, apex, path, r.out);
    if (!strstr(r.out, "bounce ") || !strstr(r.out, "body-steps inside nt_world_step: ")) fail_msg("%s", r.out);
    if (!strstr(r.out, "\n# checks: ")) fail_msg("no checks summary in:\n%s", r.out);
    run_free(&r);
    const char *a2[] = {"bench", "world", "bounce", "--runs", "1", "--min-ms", "0", "--profile", "--wide", NULL};
    run_cli(&r, NULL, a2);
    assert_int_equal(r.status, 0);
    if (!strstr(r.out, "#  bounce           phases, ns/body-step: pairs ")) fail_msg("no phase row with --profile:\n%s", r.out);
    if (!strstr(r.out, "# pen: deepest penetration") || !strstr(r.out, "analytic")) fail_msg("no wide table:\n%s", r.out);
    if (!strstr(r.out, "apex error") || !strstr(r.out, "PASS")) fail_msg("no checks with --wide:\n%s", r.out);
    run_free(&r);
}

/* `bench world` argument errors (the scenes themselves take seconds: not run here). */
static void test_bench_world_usage(void **state)
{
    (void)state;
    const char *a1[] = {"bench", "world", "nosuch", NULL};
    run_result r;
    run_cli(&r, NULL, a1);
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "unknown scene 'nosuch'"));
    assert_int_equal(r.nlines, 0);
    run_free(&r);
    const char *a2[] = {"bench", "world", "rain", "--runs", "0", NULL};
    run_cli(&r, NULL, a2);
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "--runs needs a number in 1..1001"));
    run_free(&r);
    const char *a3[] = {"bench", "narrow", "extra", NULL};
    run_cli(&r, NULL, a3);
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "unexpected argument 'extra'"));
    run_free(&r);
    const char *a4[] = {"bench", "world", "--bogus", NULL};
    run_cli(&r, NULL, a4);
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "unknown option '--bogus'"));
    run_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tile_answers),
        cmocka_unit_test(test_pair_answers),
        cmocka_unit_test(test_map_resolve_and_ray),
        cmocka_unit_test(test_no_negative_zero),
        cmocka_unit_test(test_shortest_numbers),
        cmocka_unit_test(test_line_numbers),
        cmocka_unit_test(test_tile_names),
        cmocka_unit_test(test_help_everywhere),
        cmocka_unit_test(test_error_lines),
        cmocka_unit_test(test_resolve_large),
        cmocka_unit_test(test_resolve_and_ray_need_a_map),
        cmocka_unit_test(test_exit_status),
        cmocka_unit_test(test_usage_errors),
        cmocka_unit_test(test_stdin),
        cmocka_unit_test(test_pipe_dialogue),
        cmocka_unit_test(test_crlf_and_last_line),
        cmocka_unit_test(test_long_lines),
        cmocka_unit_test(test_nul_bytes),
        cmocka_unit_test(test_random_bytes),
        cmocka_unit_test(test_demo_file),
        cmocka_unit_test(test_bench_narrow),
        cmocka_unit_test(test_bench_world_table),
        cmocka_unit_test(test_bench_world_usage),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
