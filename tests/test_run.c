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

/* ---------- -j, --shard, --junit ---------- */

/* The output without the milliseconds (they differ from run to run): each result
 * line "... N ticks   T ms" is cut after "ticks". */
static char *without_times(const char *out)
{
    char *copy = malloc(strlen(out) + 1);
    assert_non_null(copy);
    char *o = copy;
    for (const char *line = out; *line;) {
        const char *nl = strchr(line, '\n');
        size_t n = nl ? (size_t)(nl - line) + 1 : strlen(line);
        const char *t = strstr(line, " ticks ");
        if (t && t < line + n && n >= 4 && strncmp(line + n - 4, " ms\n", 4) == 0) {
            size_t keep = (size_t)(t - line) + 6;
            memcpy(o, line, keep);
            o += keep;
            *o++ = '\n';
        } else {
            memcpy(o, line, n);
            o += n;
        }
        line += n;
    }
    *o = '\0';
    return copy;
}

/* The replays for the parallel tests: a slow one first (so that later ones finish
 * before it under -j), passing and failing ones, and ones that cannot be loaded. */
#define PAR_FILES 9
static const char *par_files[PAR_FILES];

static void write_par_files(void)
{
    scratch_write_text("lvl.ntl", level_text);
    scratch_write_text("ok.ntr", replay_ok);
    scratch_write_text("slow.ntr", "ntile-replay 1\nname slow\nlevel lvl.ntl\nticks 20000\ninput 60R 100L\n"
                                   "expect alive always\n");
    scratch_write_text("bad.ntr", "ntile-replay 1\nlevel lvl.ntl\nticks 60\ninput 60L\nexpect complete by 60\n");
    scratch_write_text("syntax.ntr", "ntile-replay 1\nlevel lvl.ntl\nticks 10\nexpect happy at 3\n");
    scratch_write_text("stay.ntr", "ntile-replay 1\nname stay\nlevel lvl.ntl\nticks 30\nexpect not complete at 30\n");
    scratch_write_text("left.ntr", "ntile-replay 1\nname left\nlevel lvl.ntl\nticks 90\ninput 90L\n"
                                   "expect score == 0 at 90\n");
    static const char *const names[PAR_FILES] = {"slow.ntr", "ok.ntr",  "bad.ntr", "nothere.ntr", "stay.ntr",
                                                 "syntax.ntr", "left.ntr", "lvl.ntl", "ok.ntr"};
    for (int i = 0; i < PAR_FILES; i++) par_files[i] = scratch_path(names[i]);
}

/* `ntile run OPTIONS... FILES...` */
static void run_files(run_result *r, const char *const *options, int nfiles, const char *const *files)
{
    const char *args[32];
    int n = 0;
    args[n++] = "run";
    for (; *options; options++) args[n++] = *options;
    for (int i = 0; i < nfiles; i++) args[n++] = files[i];
    args[n] = NULL;
    run_cli(r, args);
}

static void test_parallel_same_output(void **state)
{
    (void)state;
    write_par_files();
    const char *none[] = {NULL};
    run_result plain;
    run_files(&plain, none, PAR_FILES, par_files);
    expect_status(&plain, 1);
    expect_in(plain.out, "\n5 passed, 4 failed\n");
    char *want = without_times(plain.out);
    /* The slow replay is first, the level file gets a hint towards --level. */
    if (strncmp(want, "ok     slow ", 12) != 0) fail_msg("first line is not the slow replay:\n%s", want);
    expect_in(want, "is a level, not a replay: run it with ntile run --level ");
    static const char *const jobs[] = {"2", "3", "9", "64"};
    for (size_t k = 0; k < sizeof jobs / sizeof jobs[0]; k++) {
        const char *opts[] = {"-j", jobs[k], NULL};
        run_result r;
        run_files(&r, opts, PAR_FILES, par_files);
        expect_status(&r, 1);
        char *got = without_times(r.out);
        if (strcmp(got, want) != 0) fail_msg("-j %s: output\n%s\ndiffers from the plain run's\n%s", jobs[k], got, want);
        free(got);
        run_free(&r);
    }
    const char *glued[] = {"-j4", NULL};
    run_result r;
    run_files(&r, glued, PAR_FILES, par_files);
    char *got = without_times(r.out);
    assert_string_equal(got, want);
    free(got);
    run_free(&r);
    /* All passing: exit 0 with -j too. */
    const char *two[] = {par_files[0], par_files[1]};
    const char *opts[] = {"-j", "2", NULL};
    run_files(&r, opts, 2, two);
    expect_status(&r, 0);
    expect_in(r.out, "\n2 passed, 0 failed\n");
    run_free(&r);
    free(want);
    run_free(&plain);
}

/* The result lines of an output (the "ok" / "not ok" lines and what is indented under
 * them), without times and without the closing count. */
static char *results_only(const char *out)
{
    char *t = without_times(out);
    char *last = strstr(t, " passed, ");
    if (last) {
        while (last > t && last[-1] != '\n') last--;
        *last = '\0';
    }
    return t;
}

static void test_shards(void **state)
{
    (void)state;
    write_par_files();
    const char *none[] = {NULL};
    for (int n = 1; n <= 4; n++) {
        int passed = 0, failed = 0;
        for (int i = 1; i <= n; i++) {
            char shard[16];
            snprintf(shard, sizeof shard, "%d/%d", i, n);
            /* What the shard must print: the plain run of files i, i+n, ... */
            const char *mine[PAR_FILES];
            int m = 0;
            for (int k = i - 1; k < PAR_FILES; k += n) mine[m++] = par_files[k];
            run_result want_r, r;
            run_files(&want_r, none, m, mine);
            for (int j = 0; j < 2; j++) {
                const char *opts[] = {"--shard", shard, j ? "-j" : NULL, "3", NULL};
                run_files(&r, opts, PAR_FILES, par_files);
                expect_status(&r, want_r.status);
                char *got = results_only(r.out), *want = results_only(want_r.out);
                if (strcmp(got, want) != 0) fail_msg("--shard %s%s: output\n%s\nexpected\n%s", shard, j ? " -j 3" : "", got, want);
                int p = 0, f = 0;
                const char *tail = strstr(r.out, " passed, ");
                assert_non_null(tail);
                while (tail > r.out && tail[-1] != '\n') tail--;
                assert_int_equal(sscanf(tail, "%d passed, %d failed", &p, &f), 2);
                if (j == 0) {
                    passed += p;
                    failed += f;
                }
                free(got);
                free(want);
                run_free(&r);
            }
            run_free(&want_r);
        }
        /* The shards together ran every file once. */
        assert_int_equal(passed, 5);
        assert_int_equal(failed, 4);
    }
    /* A replay given to --level: the hint goes the other way. */
    const char *rev[] = {"run", "--level", scratch_path("ok.ntr"), "--ticks", "5", NULL};
    run_result rr;
    run_cli(&rr, rev);
    expect_status(&rr, 1);
    expect_in(rr.err, "ok.ntr is a replay, not a level: run it with ntile run ");
    run_free(&rr);
    /* More shards than files: an empty shard passes with nothing run. */
    const char *opts[] = {"--shard", "3/3", NULL};
    run_result r;
    run_files(&r, opts, 2, par_files);
    expect_status(&r, 0);
    assert_string_equal(r.out, "0 passed, 0 failed\n");
    run_free(&r);
    static const char *const bad[] = {"0/3", "4/3", "3", "a/b", "1/0", "/2", "2/", "-1/2"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        const char *o[] = {"--shard", bad[k], NULL};
        run_files(&r, o, 1, par_files);
        expect_status(&r, 2);
        expect_in(r.err, "--shard needs I/N");
        run_free(&r);
    }
    static const char *const badj[] = {"0", "65", "x", ""};
    for (size_t k = 0; k < sizeof badj / sizeof badj[0]; k++) {
        const char *o[] = {"-j", badj[k], NULL};
        run_files(&r, o, 1, par_files);
        expect_status(&r, 2);
        expect_in(r.err, "-j needs a number of processes in 1..64");
        run_free(&r);
    }
    const char *lv[] = {"run", "--level", par_files[7], "--ticks", "5", "-j", "2", NULL};
    run_cli(&r, lv);
    expect_status(&r, 2);
    expect_in(r.err, "-j, --shard and --junit go with replay files");
    run_free(&r);
}

/* xmllint from PATH (Debian's libxml2-utils; `make test` installs it). */
static const char *find_xmllint(void)
{
    static char found[4096];
    const char *path = getenv("PATH");
    if (!path || !*path) path = "/usr/bin:/bin";
    while (*path) {
        size_t n = strcspn(path, ":");
        snprintf(found, sizeof found, "%.*s/xmllint", (int)n, path);
        if (access(found, X_OK) == 0) return found;
        path += n + (path[n] == ':');
    }
    fail_msg("xmllint not found in PATH: install Debian's libxml2-utils (tools/deps.sh xmllint)");
    return NULL;
}

/* Validate a report against tests/junit.xsd; the test fails with xmllint's words. */
static void expect_valid_junit(const char *report)
{
    const char *xsd = getenv("NTILE_JUNIT_XSD");
    if (!xsd || !*xsd) xsd = "tests/junit.xsd";
    char abs_xsd[4096];
    if (xsd[0] != '/') {
        char cwd[2048];
        assert_non_null(getcwd(cwd, sizeof cwd));
        snprintf(abs_xsd, sizeof abs_xsd, "%s/%s", cwd, xsd);
        xsd = abs_xsd;
    }
    if (access(xsd, R_OK) != 0) fail_msg("cannot read %s (run the tests from the source tree)", xsd);
    const char *args[] = {"--noout", "--schema", xsd, report, NULL};
    run_result r;
    child_run(&r, scratch_dir(), find_xmllint(), args, NULL, NULL, 256);
    if (r.status != 0) fail_msg("%s does not validate against %s:\n%s%s", report, xsd, r.out, r.err);
    run_free(&r);
}

static void test_junit(void **state)
{
    (void)state;
    write_par_files();
    /* A replay whose name needs escaping, and a file name outside ASCII. */
    scratch_write_text("amp.ntr", "ntile-replay 1\nname a&b<c>\nlevel lvl.ntl\nticks 10\nexpect complete at 10\n");
    const char *files[PAR_FILES + 2];
    for (int i = 0; i < PAR_FILES; i++) files[i] = par_files[i];
    files[PAR_FILES] = scratch_path("amp.ntr");
    files[PAR_FILES + 1] = scratch_path("caf\xc3\xa9 & <x>.ntr");
    const char *report = scratch_path("report.xml");
    const char *opts[] = {"--junit", report, NULL};
    run_result r;
    run_files(&r, opts, PAR_FILES + 2, files);
    expect_status(&r, 1);
    expect_valid_junit(report);
    char *xml = scratch_read(report, NULL);
    expect_in(xml, "<testsuite name=\"ntile run\" tests=\"11\" failures=\"");
    /* Failures: the facts of bad and amp; errors: nothere, syntax, lvl.ntl and the café file. */
    expect_in(xml, " tests=\"11\" failures=\"2\" errors=\"4\" ");
    expect_in(xml, "<testcase name=\"a&amp;b&lt;c&gt;\" ");
    expect_in(xml, "<testcase name=\"caf?? &amp; &lt;x&gt;\" ");
    expect_in(xml, "<testcase name=\"slow\" classname=\"ntile.replay\" file=\"");
    expect_in(xml, "<failure message=\"line 5: expect complete by 60: never true in ticks 0..60");
    expect_in(xml, "<error message=\"cannot open '");
    expect_in(xml, "is a level, not a replay: run it with ntile run --level ");
    free(xml);
    run_free(&r);
    /* -j and --shard write the same kind of report: validated, and each shard counts its own. */
    const char *opts2[] = {"--junit", report, "-j", "3", "--shard", "2/2", NULL};
    run_files(&r, opts2, PAR_FILES + 2, files);
    expect_valid_junit(report);
    xml = scratch_read(report, NULL);
    expect_in(xml, "<testsuite name=\"ntile run (shard 2/2)\" tests=\"5\" ");
    free(xml);
    run_free(&r);
    /* An unwritable report is an I/O error (status 2). */
    const char *opts3[] = {"--junit", scratch_path("no/such/dir/report.xml"), NULL};
    run_files(&r, opts3, 1, files + 1);
    expect_status(&r, 2);
    expect_in(r.err, "cannot write");
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
    snprintf(want, sizeof want, "%s/levels.txt:1:739: warning: N object type 3 (gauss turret) is not supported; skipped\n", scratch_dir());
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
        cmocka_unit_test(test_parallel_same_output),
        cmocka_unit_test(test_shards),
        cmocka_unit_test(test_junit),
        cmocka_unit_test(test_record_hashes),
        cmocka_unit_test(test_level_mode),
        cmocka_unit_test(test_usage_errors),
        cmocka_unit_test(test_convert),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
