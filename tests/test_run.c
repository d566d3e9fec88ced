/* The CLI's `ntile run` and `ntile convert`, driven through the binary named by
 * NTILE (make test sets it): every shipped replay in tests/replays must pass; the
 * output format; failures and load errors; --record-hashes (what it writes, what
 * it keeps, what it says); --level runs; usage errors; N v1.4 conversion. Files are
 * written to a private temporary directory. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "child.h"
#include "scratch.h"
#include "ntile/ntile.h"

/* ---------- temporary files (scratch.h) ---------- */

static int group_setup(void **state)
{
    (void)state;
    return scratch_create("run");
}

static int group_teardown(void **state)
{
    (void)state;
    scratch_remove();
    return 0;
}

/* ---------- running the CLI ---------- */

typedef child_result run_result;

/* Run `ntile ARGS...` (NULL-terminated), capturing both outputs. */
static void run_cli(run_result *r, const char *const *args)
{
    child_run(r, scratch_dir(), child_ntile(), args, NULL, NULL, 125);
}

static void run_free(run_result *r) { child_free(r); }

static void expect_status(const run_result *r, int status)
{
    if (r->status != status) fail_msg("exit status %d, expected %d\nstdout:\n%s\nstderr:\n%s", r->status, status, r->out, r->err);
}

static void expect_in(const char *text, const char *needle)
{
    if (!strstr(text, needle)) fail_msg("expected to find:\n%s\nin:\n%s", needle, text);
}

/* ---------- the shipped replays ---------- */

static int by_name(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

static void test_shipped_replays(void **state)
{
    (void)state;
    const char *dir = getenv("NTILE_REPLAYS");
    if (!dir || !*dir) dir = "tests/replays";
    DIR *d = opendir(dir);
    if (!d) fail_msg("cannot open %s (run the tests from the source tree, or set NTILE_REPLAYS)", dir);
    char *files[256];
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        size_t l = strlen(e->d_name);
        if (l < 5 || strcmp(e->d_name + l - 4, ".ntr") != 0) continue;
        assert_true(n < 250);
        files[n] = malloc(strlen(dir) + l + 2);
        sprintf(files[n++], "%s/%s", dir, e->d_name);
    }
    closedir(d);
    assert_true(n >= 6); /* at least one replay for each shipped level */
    qsort(files, (size_t)n, sizeof files[0], by_name);
    const char *args[260];
    args[0] = "run";
    for (int i = 0; i < n; i++) args[i + 1] = files[i];
    args[n + 1] = NULL;
    run_result r;
    run_cli(&r, args);
    print_message("%s", r.out);
    expect_status(&r, 0);
    char closing[64];
    snprintf(closing, sizeof closing, "\n%d passed, 0 failed\n", n);
    expect_in(r.out, closing);
    /* One "ok" line per replay, in the order given. */
    const char *p = r.out;
    for (int i = 0; i < n; i++) {
        if (strncmp(p, "ok ", 3) != 0) fail_msg("line %d is not 'ok ...': %s", i + 1, p);
        p = strchr(p, '\n') + 1;
    }
    run_free(&r);
    for (int i = 0; i < n; i++) free(files[i]);
}

/* ---------- a small level of our own ---------- */

static const char level_text[] = "ntile-level 1\nsize 12 5\ntiles\n"
                                 "|############|\n|#..........#|\n|#..........#|\n|#..........#|\n|############|\n"
                                 "player 36 86\nregion door exit 220 48 250 96\nbody coin static circle 6 at 120 86 sensor score 2\n";

static const char replay_ok[] = "ntile-replay 1\n# reaches the door\nname walk\nlevel lvl.ntl\nticks 60\ninput 60R\n"
                                "expect complete by 60\nexpect score >= 2 at 60\n";

static void test_output_format(void **state)
{
    (void)state;
    scratch_write_text("lvl.ntl", level_text);
    scratch_write_text("ok.ntr", replay_ok);
    const char *args[] = {"run", scratch_path("ok.ntr"), NULL};
    run_result r;
    run_cli(&r, args);
    expect_status(&r, 0);
    char word[16], name[64], ticks_word[16], ms_word[16];
    int ticks;
    double ms;
    assert_int_equal(sscanf(r.out, "%15s %63s %d %15s %lf %15s", word, name, &ticks, ticks_word, &ms, ms_word), 6);
    assert_string_equal(word, "ok");
    assert_string_equal(name, "walk");
    assert_int_equal(ticks, 60);
    assert_string_equal(ticks_word, "ticks");
    assert_true(ms >= 0);
    assert_string_equal(ms_word, "ms");
    expect_in(r.out, "\n1 passed, 0 failed\n");
    run_free(&r);
}

static void test_failures_are_reported(void **state)
{
    (void)state;
    scratch_write_text("lvl.ntl", level_text);
    scratch_write_text("bad.ntr", "ntile-replay 1\nlevel lvl.ntl\nticks 60\ninput 60L\nexpect complete by 60\n");
    scratch_write_text("noname.ntr", "ntile-replay 1\nlevel missing.ntl\nticks 10\n");
    scratch_write_text("syntax.ntr", "ntile-replay 1\nlevel lvl.ntl\nticks 10\nexpect happy at 3\n");
    scratch_write_text("badlevel.ntr", "ntile-replay 1\nlevel broken.ntl\nticks 10\n");
    scratch_write_text("broken.ntl", "ntile-level 1\nsize 3 1\ntiles\n|#x#|\n");
    scratch_write_text("ok.ntr", replay_ok);
    const char *args[] = {"run",
                          scratch_path("bad.ntr"),
                          scratch_path("noname.ntr"),
                          scratch_path("syntax.ntr"),
                          scratch_path("badlevel.ntr"),
                          scratch_path("nothere.ntr"),
                          scratch_path("ok.ntr"),
                          NULL};
    run_result r;
    run_cli(&r, args);
    expect_status(&r, 1);
    expect_in(r.out, "not ok bad ");
    expect_in(r.out, "\n    line 5: expect complete by 60: never true in ticks 0..60 (at tick 60: not complete)\n");
    char want[5000];
    snprintf(want, sizeof want, "\n    cannot open '%s/missing.ntl': No such file or directory\n", scratch_dir());
    expect_in(r.out, want);
    snprintf(want, sizeof want,
             "\n    %s/syntax.ntr:4:8: unknown fact 'happy' (expected complete, alive, inside, no-body-in-solid, score, "
             "bodies, spawned, energy-ratio or momentum-drift)\n",
             scratch_dir());
    expect_in(r.out, want);
    snprintf(want, sizeof want,
             "\n    %s/broken.ntl:4:3: unknown tile code 'x' (expected '.', '#' or an N code '2'..'Q', see the legend)\n",
             scratch_dir());
    expect_in(r.out, want);
    snprintf(want, sizeof want, "\n    cannot open '%s/nothere.ntr': No such file or directory\n", scratch_dir());
    expect_in(r.out, want);
    expect_in(r.out, "\nok     walk ");
    expect_in(r.out, "\n1 passed, 5 failed\n");
    run_free(&r);
}

/* ---------- --record-hashes ---------- */

static const char *scalar(void) { return NT_REAL_IS_DOUBLE ? "double" : "float"; }

static void test_record_hashes(void **state)
{
    (void)state;
    scratch_write_text("lvl.ntl", level_text);
    /* A line for the other scalar build must survive recording untouched. */
    char text[1024];
    snprintf(text, sizeof text, "%shash %s 60 0x0123456789abcdef\n", replay_ok, NT_REAL_IS_DOUBLE ? "float" : "double");
    scratch_write_text("rec.ntr", text);
    const char *rec[] = {"run", "--record-hashes", scratch_path("rec.ntr"), NULL};
    const char *run[] = {"run", scratch_path("rec.ntr"), NULL};
    run_result r;
    run_cli(&r, rec);
    expect_status(&r, 0);
    char want[256];
    snprintf(want, sizeof want, "\n    %s hash at tick 60: added 0x", scalar());
    expect_in(r.out, want);
    snprintf(want, sizeof want, "\n    %s trace: added (60 ticks)\n", scalar());
    expect_in(r.out, want);
    run_free(&r);
    char *after = scratch_read(scratch_path("rec.ntr"), NULL);
    expect_in(after, "# reaches the door\n");     /* comments kept */
    expect_in(after, "expect score >= 2 at 60\n"); /* facts kept */
    snprintf(want, sizeof want, "hash %s 60 0x0123456789abcdef\n", NT_REAL_IS_DOUBLE ? "float" : "double");
    expect_in(after, want);
    snprintf(want, sizeof want, "\ntrace %s 57 ", scalar());
    expect_in(after, want);
    /* It now passes, and recording again changes nothing. */
    run_cli(&r, run);
    expect_status(&r, 0);
    run_free(&r);
    run_cli(&r, rec);
    expect_status(&r, 0);
    snprintf(want, sizeof want, "\n    %s hash at tick 60: unchanged\n    %s trace: unchanged (60 ticks)\n", scalar(), scalar());
    expect_in(r.out, want);
    run_free(&r);
    char *again = scratch_read(scratch_path("rec.ntr"), NULL);
    assert_string_equal(again, after);
    free(again);
    /* A change (the coin is worth 3) shows up when the coin is taken; the facts still hold. */
    char changed[sizeof level_text];
    snprintf(changed, sizeof changed, "%s", level_text);
    *strstr(changed, "score 2") = '\0';
    strcat(changed, "score 3\n");
    scratch_write_text("lvl.ntl", changed);
    run_cli(&r, run);
    expect_status(&r, 1);
    snprintf(want, sizeof want, ": %s hash at tick 60: expected 0x", scalar());
    expect_in(r.out, want);
    const char *first = strstr(r.out, "\n    first tick that diverges: ");
    assert_non_null(first);
    int tick = atoi(first + strlen("\n    first tick that diverges: "));
    assert_true(tick > 10 && tick < 60); /* when the player reaches the coin at x = 120 */
    run_free(&r);
    /* Re-recording says what changed, and then it passes again. */
    run_cli(&r, rec);
    expect_status(&r, 0);
    snprintf(want, sizeof want, "\n    %s trace: %d of 60 ticks changed, first at tick %d\n", scalar(), 61 - tick, tick);
    expect_in(r.out, want);
    snprintf(want, sizeof want, "\n    %s hash at tick 60: 0x", scalar());
    expect_in(r.out, want);
    expect_in(r.out, " -> 0x");
    run_free(&r);
    run_cli(&r, run);
    expect_status(&r, 0);
    run_free(&r);
    /* A fact that fails is reported while recording, and the status says so. */
    scratch_write_text("lvl.ntl", level_text);
    scratch_write_text("rec2.ntr", "ntile-replay 1\nlevel lvl.ntl\nticks 20\nexpect complete by 20\n");
    const char *rec2[] = {"run", "--record-hashes", scratch_path("rec2.ntr"), NULL};
    run_cli(&r, rec2);
    expect_status(&r, 1);
    expect_in(r.out, "not ok rec2 ");
    expect_in(r.out, "\n    line 4: expect complete by 20: never true in ticks 0..20 (at tick 20: not complete)\n");
    run_free(&r);
    free(after);
}

/* ---------- --level ---------- */

static void test_level_mode(void **state)
{
    (void)state;
    scratch_write_text("lvl.ntl", level_text);
    const char *args[] = {"run", "--level", scratch_path("lvl.ntl"), "--ticks", "50", "--input", "30R 20.", NULL};
    run_result r;
    run_cli(&r, args);
    expect_status(&r, 0);
    unsigned long long h = 0;
    assert_int_equal(sscanf(r.out, "hash 0x%16llx\n", &h), 1);
    expect_in(r.out, "\ntick 50  bodies 1  score 2  spawned 0  complete no  player alive at ");
    run_free(&r);
    /* A replay of the same inputs records the same hash. */
    scratch_write_text("same.ntr", "ntile-replay 1\nlevel lvl.ntl\nticks 50\ninput 30R 20.\n");
    const char *rec[] = {"run", "--record-hashes", scratch_path("same.ntr"), NULL};
    run_cli(&r, rec);
    expect_status(&r, 0);
    run_free(&r);
    char *text = scratch_read(scratch_path("same.ntr"), NULL);
    char want[128];
    snprintf(want, sizeof want, "hash %s 50 0x%016llx\n", scalar(), h);
    expect_in(text, want);
    free(text);
    /* No --input: no keys. */
    const char *idle[] = {"run", "--level", scratch_path("lvl.ntl"), "--ticks", "5", "--print-every", "5", NULL};
    run_cli(&r, idle);
    expect_status(&r, 0);
    expect_in(r.out, "  . tick 5  bodies 2  score 0");
    run_free(&r);
}

static void test_usage_errors(void **state)
{
    (void)state;
    scratch_write_text("lvl.ntl", level_text);
    struct {
        const char *args[8];
        int status;
        const char *message;
    } cases[] = {
        {{"run", NULL}, 2, "ntile run: no replay files\n"},
        {{"run", "--level", "x.ntl", NULL}, 2, "ntile run: --level needs --ticks N\n"},
        {{"run", "--frobnicate", NULL}, 2, "ntile run: unknown option '--frobnicate'\n"},
        {{"run", "--ticks", NULL}, 2, "ntile run: --ticks needs a value\n"},
        {{"run", "--level", "x", "--ticks", "0", NULL}, 2, "ntile run: --ticks needs a number of ticks (1..100000000), got '0'\n"},
        {{"run", "--ticks", "5", "a.ntr", NULL}, 2,
         "ntile run: --input, --ticks, --seed, --dt, --friction-model and --print-every go with --level\n"},
        {{"run", "--level", scratch_path("lvl.ntl"), "--ticks", "5", "--input", "3Q", NULL}, 2,
         "ntile run: --input:1:2: unknown key 'Q' (keys are L R U D J A; '.' alone means none)\n"},
        {{"run", "--level", scratch_path("nope.ntl"), "--ticks", "5", NULL}, 2, "ntile run: cannot open '"},
        {{"convert", "n15", "x", NULL}, 2, "ntile convert: unknown format 'n15' (this ntile converts n14 and tiled)\n"},
        {{"convert", "n14", NULL}, 2, "ntile convert: missing the input FILE\n"},
        {{"convert", "n14", scratch_path("nope.txt"), NULL}, 2, "ntile convert: cannot open '"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        run_result r;
        run_cli(&r, cases[i].args);
        expect_status(&r, cases[i].status);
        if (strncmp(r.err, cases[i].message, strlen(cases[i].message)) != 0)
            fail_msg("case %zu: stderr\n%s\ndoes not start with\n%s", i, r.err, cases[i].message);
        run_free(&r);
    }
}

/* ---------- convert ---------- */

static void n14_line(char *out, size_t cap, const char *name, int solid_col, const char *objects)
{
    char tiles[714];
    memset(tiles, '0', 713);
    tiles[713] = '\0';
    for (int row = 0; row < 23; row++) tiles[solid_col * 23 + row] = '1';
    snprintf(out, cap, "$%s#tester##%s|%s#\n", name, tiles, objects);
}

static void test_convert(void **state)
{
    (void)state;
    char a[1024], b[1024], both[2048];
    n14_line(a, sizeof a, "first", 3, "5^60,100!3^200,200");
    n14_line(b, sizeof b, "second", 9, "0^120,120");
    snprintf(both, sizeof both, "%s%s", a, b);
    scratch_write_text("levels.txt", both);
    const char *conv[] = {"convert", "n14", scratch_path("levels.txt"), "-o", scratch_path("first.ntl"), NULL};
    run_result r;
    run_cli(&r, conv);
    expect_status(&r, 0);
    char want[5000];
    snprintf(want, sizeof want, "%s/levels.txt:1:739: warning: N object type 3 is not supported; skipped\n", scratch_dir());
    expect_in(r.err, want);
    snprintf(want, sizeof want, "holds 2 levels; converted the first (choose one with --index N)\n");
    expect_in(r.err, want);
    run_free(&r);
    char *text = scratch_read(scratch_path("first.ntl"), NULL);
    nt_level *lv = NULL;
    assert_int_equal(nt_level_parse("first.ntl", text, strlen(text), &lv, NULL), NT_OK);
    assert_string_equal(lv->title, "first");
    assert_int_equal(lv->tiles[10 * 33 + 4], NT_TILE_FULL); /* playable column 3 is map column 4 */
    assert_true(lv->has_player);
    nt_level_destroy(lv);
    free(text);
    /* --index 2 to standard output */
    const char *second[] = {"convert", "n14", scratch_path("levels.txt"), "--index", "2", NULL};
    run_cli(&r, second);
    expect_status(&r, 0);
    expect_in(r.out, "title \"second\"\n");
    expect_in(r.out, "body gold1 static circle 6 at 120 120 sensor score 1\n");
    run_free(&r);
    const char *third[] = {"convert", "n14", scratch_path("levels.txt"), "--index", "3", NULL};
    run_cli(&r, third);
    expect_status(&r, 1);
    snprintf(want, sizeof want, "%s/levels.txt:3:1: level 3 asked for, but the text holds 2 levels\n", scratch_dir());
    assert_string_equal(r.err, want);
    run_free(&r);
    const char *list[] = {"convert", "n14", scratch_path("levels.txt"), "--list", NULL};
    run_cli(&r, list);
    expect_status(&r, 0);
    assert_string_equal(r.out, "1\tfirst\n2\tsecond\n");
    run_free(&r);
    scratch_write_text("junk.txt", "this is not N\n");
    const char *junk[] = {"convert", "n14", scratch_path("junk.txt"), NULL};
    run_cli(&r, junk);
    expect_status(&r, 1);
    snprintf(want, sizeof want, "%s/junk.txt:1:1: an N level starts with '$' ($NAME#AUTHOR##TILES|OBJECTS#)\n", scratch_dir());
    assert_string_equal(r.err, want);
    assert_string_equal(r.out, "");
    run_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shipped_replays),
        cmocka_unit_test(test_output_format),
        cmocka_unit_test(test_failures_are_reported),
        cmocka_unit_test(test_record_hashes),
        cmocka_unit_test(test_level_mode),
        cmocka_unit_test(test_usage_errors),
        cmocka_unit_test(test_convert),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
