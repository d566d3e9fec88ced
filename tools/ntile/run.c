/* ntile run — replay .ntr files headless, or run a level for N ticks.
 *
 *   ntile run [--record-hashes] FILE.ntr...
 *       One line per replay: "ok" or "not ok", its name, ticks run, milliseconds;
 *       the reasons of a failure follow, indented; then "N passed, N failed".
 *       --record-hashes rewrites each file's hash lines and per-tick trace with the
 *       values of this run, keeping every other line, and says what changed.
 *   ntile run --level FILE.ntl --ticks N [--input KEYS] [--seed S] [--dt SECONDS]
 *             [--friction-model n|coulomb] [--print-every K]
 *       Prints "hash 0x..." (the game hash after the last tick) and a summary.
 *
 * Exit status: 0 every replay passed (and every file was written), 1 a replay
 * failed or could not be loaded, 2 usage error or unreadable/unwritable file. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "cli.h"
#include "../common/levels.h"
#include "../common/stream.h"
#include "ntile/game.h"

/* ---------------------------------------------------------------- files */

int cli_read_file(const char *path, char **out, size_t *len, char *why, size_t why_cap)
{
    *out = NULL;
    *len = 0;
    FILE *f = strcmp(path, "-") == 0 ? stdin : stream_open_regular(path, STREAM_MAX_FILE, why, why_cap);
    if (!f) return 0;
    int r = stream_read_all(f, STREAM_MAX_FILE, out, len);
    if (f != stdin) fclose(f);
    if (r == STREAM_NO_MEMORY) {
        snprintf(why, why_cap, "out of memory reading '%s' (or larger than %zu bytes)", path, STREAM_MAX_FILE);
        return 0;
    }
    if (r == STREAM_READ_ERROR) {
        snprintf(why, why_cap, "error reading '%s'", path);
        return 0;
    }
    return 1;
}

int cli_write_file(const char *path, const char *data, size_t len, char *why, size_t why_cap)
{
    /* Write a sibling file and rename it over the target: a failed write leaves the
     * old file as it was. */
    size_t pl = strlen(path);
    char *tmp = malloc(pl + 16);
    if (!tmp) {
        snprintf(why, why_cap, "out of memory writing '%s'", path);
        return 0;
    }
    snprintf(tmp, pl + 16, "%s.tmp%ld", path, (long)(clock() % 100000));
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        snprintf(why, why_cap, "cannot write '%s': %s", tmp, strerror(errno));
        free(tmp);
        return 0;
    }
    int ok = fwrite(data, 1, len, f) == len;
    ok = (fclose(f) == 0) && ok;
    if (ok && rename(tmp, path) != 0) ok = 0;
    if (!ok) {
        snprintf(why, why_cap, "cannot write '%s': %s", path, strerror(errno));
        remove(tmp);
    }
    free(tmp);
    return ok;
}

/* "dir/of/replay.ntr" + "../levels/x.ntl" -> "dir/of/../levels/x.ntl" (absolute paths stay). */
static char *relative_to(const char *file, const char *path)
{
    const char *slash = strrchr(file, '/');
    size_t dl = (path[0] == '/' || !slash) ? 0 : (size_t)(slash - file) + 1;
    char *out = malloc(dl + strlen(path) + 1);
    if (!out) return NULL;
    memcpy(out, file, dl);
    strcpy(out + dl, path);
    return out;
}

/* The file name without directory and extension. */
static void base_name(const char *path, char *out, size_t cap)
{
    const char *b = strrchr(path, '/');
    b = b ? b + 1 : path;
    const char *dot = strrchr(b, '.');
    size_t n = dot && dot != b ? (size_t)(dot - b) : strlen(b);
    if (n >= cap) n = cap - 1;
    memcpy(out, b, n);
    out[n] = '\0';
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

static nt_status load_level(const char *path, nt_level **out, char *why, size_t cap)
{
    char *text;
    size_t len;
    *out = NULL;
    if (!cli_read_file(path, &text, &len, why, cap)) return NT_ERR_INVALID_ARGUMENT;
    nt_text_error e;
    nt_status s = nt_level_parse(path, text, len, out, &e);
    free(text);
    if (s != NT_OK) snprintf(why, cap, "%s", e.message);
    return s;
}

/* ---------------------------------------------------------------- recording hashes */

/* What a replay line is, for rewriting: 0 other, 1 our marker comment, 2 a float
 * hash or trace line, 3 a double one. */
static int hash_line_kind(const char *s, size_t n)
{
    static const char marker[] = "# state hashes:";
    size_t i = 0;
    while (i < n && (s[i] == ' ' || s[i] == '\t')) i++;
    s += i;
    n -= i;
    if (n >= sizeof marker - 1 && memcmp(s, marker, sizeof marker - 1) == 0) return 1;
    size_t w = 0;
    if (n >= 5 && memcmp(s, "hash", 4) == 0 && (s[4] == ' ' || s[4] == '\t')) w = 4;
    else if (n >= 6 && memcmp(s, "trace", 5) == 0 && (s[5] == ' ' || s[5] == '\t')) w = 5;
    else return 0;
    while (w < n && (s[w] == ' ' || s[w] == '\t')) w++;
    if (n - w >= 6 && memcmp(s + w, "double", 6) == 0) return 3;
    return 2; /* float, or malformed (the parser rejected those already) */
}

typedef struct strbuf {
    char *p;
    size_t n, cap;
    int oom;
} strbuf;

static void sb_put(strbuf *b, const char *s, size_t n)
{
    if (b->oom) return;
    if (b->n + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < b->n + n + 1) cap *= 2;
        char *p = realloc(b->p, cap);
        if (!p) {
            b->oom = 1;
            return;
        }
        b->p = p;
        b->cap = cap;
    }
    memcpy(b->p + b->n, s, n);
    b->n += n;
    b->p[b->n] = '\0';
}

static void sb_printf(strbuf *b, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void sb_printf(strbuf *b, const char *fmt, ...)
{
    char tmp[256];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    if (n > 0) sb_put(b, tmp, (size_t)n < sizeof tmp ? (size_t)n : sizeof tmp - 1);
}

/* Rewrite the replay text: every line but the hash block is kept in place; the
 * block at the end holds this build's new hashes (at the ticks it had, else the
 * other build's ticks, else the last tick) and a trace of every tick, and the
 * other build's lines unchanged. Prints what changed. Returns 0 on a write error. */
static int record(const char *path, const char *text, size_t len, const nt_replay *rp, const nt_run_report *rep)
{
    const int me = NT_REAL_IS_DOUBLE;
    const char *scalar = me ? "double" : "float";
    strbuf b = {0}, other = {0};
    size_t i = 0;
    while (i < len) {
        const char *nl = memchr(text + i, '\n', len - i);
        size_t n = nl ? (size_t)(nl - (text + i)) : len - i;
        int kind = hash_line_kind(text + i, n);
        strbuf *dst = kind == 0 ? &b : kind == 3 - me ? &other : NULL;
        if (dst) {
            sb_put(dst, text + i, n);
            sb_put(dst, "\n", 1);
        }
        i += n + (nl ? 1 : 0);
    }
    while (b.n >= 2 && b.p[b.n - 1] == '\n' && b.p[b.n - 2] == '\n') b.p[--b.n] = '\0';
    static const char marker[] =
        "\n# state hashes: written by `ntile run --record-hashes`; re-record after an intended physics change\n";
    sb_put(&b, marker, sizeof marker - 1);
    if (me == 1 && other.n) sb_put(&b, other.p, other.n);
    /* The ticks to hash: this build's, else the other build's, else the last tick. */
    int mine = 0;
    for (int k = 0; k < rp->hash_count; k++) mine += rp->hashes[k].is_double == (me == 1);
    int ticks = rep->ticks;
    int want = rp->hash_count > 0 ? rp->hash_count : 1;
    for (int k = 0; k < want; k++) {
        int t = ticks;
        const nt_replay_hash *old = NULL;
        if (rp->hash_count > 0) {
            const nt_replay_hash *h = &rp->hashes[k];
            if (mine > 0 ? h->is_double != (me == 1) : h->is_double == (me == 1)) continue;
            t = h->tick;
            if (mine > 0) old = h;
        }
        if (t > ticks) continue;
        uint64_t h = rep->hashes[t];
        sb_printf(&b, "hash %s %d 0x%016llx\n", scalar, t, (unsigned long long)h);
        if (!old) printf("    %s hash at tick %d: added 0x%016llx\n", scalar, t, (unsigned long long)h);
        else if (old->hash != h)
            printf("    %s hash at tick %d: 0x%016llx -> 0x%016llx\n", scalar, t, (unsigned long long)old->hash,
                   (unsigned long long)h);
        else printf("    %s hash at tick %d: unchanged\n", scalar, t);
    }
    const uint32_t *tr = rp->trace[me];
    int trn = rp->trace_count[me];
    int changed = 0, first = -1;
    for (int t = 1; t <= ticks; t++) {
        uint32_t v = nt_trace_fold(rep->hashes[t]);
        if ((t - 1) % 8 == 0) sb_printf(&b, "trace %s %d", scalar, t);
        sb_printf(&b, " %08lx", (unsigned long)v);
        if ((t - 1) % 8 == 7 || t == ticks) sb_put(&b, "\n", 1);
        if (t > trn || tr[t - 1] != v) {
            changed++;
            if (first < 0) first = t;
        }
    }
    if (trn == 0) printf("    %s trace: added (%d ticks)\n", scalar, ticks);
    else if (changed == 0 && trn == ticks) printf("    %s trace: unchanged (%d ticks)\n", scalar, ticks);
    else printf("    %s trace: %d of %d ticks changed, first at tick %d\n", scalar, changed, ticks, first);
    if (me == 0 && other.n) sb_put(&b, other.p, other.n);
    int ok = 1;
    if (b.oom || other.oom) {
        fprintf(stderr, "ntile run: out of memory recording '%s'\n", path);
        ok = 0;
    } else if (b.n != len || memcmp(b.p, text, len) != 0) {
        char why[512];
        ok = cli_write_file(path, b.p, b.n, why, sizeof why);
        if (!ok) fprintf(stderr, "ntile run: %s\n", why);
    }
    free(b.p);
    free(other.p);
    return ok;
}

/* ---------------------------------------------------------------- replays */

typedef struct tally {
    int passed, failed, io_errors;
} tally;

static void print_line(int ok, const char *name, int ticks, double ms)
{
    printf("%-6s %-30s %8d ticks %9.1f ms\n", ok ? "ok" : "not ok", name, ticks, ms);
}

static void run_file(const char *path, int record_hashes, tally *tl)
{
    char name[96], why[600];
    base_name(path, name, sizeof name);
    char *text = NULL;
    size_t len = 0;
    nt_replay *rp = NULL;
    nt_level *lv = NULL;
    char *lpath = NULL;
    if (!cli_read_file(path, &text, &len, why, sizeof why)) {
        print_line(0, name, 0, 0);
        printf("    %s\n", why);
        tl->failed++;
        return;
    }
    nt_text_error e;
    if (nt_replay_parse(path, text, len, &rp, &e) != NT_OK) {
        print_line(0, name, 0, 0);
        printf("    %s\n", e.message);
        tl->failed++;
        free(text);
        return;
    }
    if (rp->name[0]) snprintf(name, sizeof name, "%s", rp->name);
    lpath = relative_to(path, rp->level);
    if (!lpath || load_level(lpath, &lv, why, sizeof why) != NT_OK) {
        print_line(0, name, 0, 0);
        printf("    %s\n", lpath ? why : "out of memory");
        tl->failed++;
    } else {
        nt_run_report rep;
        double t0 = now_ms();
        nt_status s = nt_run_replay(rp, lv, &rep);
        double ms = now_ms() - t0;
        if (s != NT_OK) {
            print_line(0, name, rep.ticks, ms);
            printf("    cannot run: %s\n", nt_status_string(s));
            tl->failed++;
        } else {
            /* Recording rewrites the hashes: only the facts decide the verdict. */
            int ok = record_hashes ? rep.fact_failures == 0 : rep.passed;
            print_line(ok, name, rep.ticks, ms);
            for (int i = 0; i < rep.message_count; i++)
                if (!record_hashes || !rep.message_is_hash[i]) printf("    %s\n", rep.messages[i]);
            if (rep.failure_count > rep.message_count && !record_hashes)
                printf("    ... and %d more\n", rep.failure_count - rep.message_count);
            if (ok) tl->passed++;
            else tl->failed++;
            if (record_hashes && !record(path, text, len, rp, &rep)) tl->io_errors++;
            nt_run_report_free(&rep);
        }
    }
    free(lpath);
    nt_level_destroy(lv);
    nt_replay_destroy(rp);
    free(text);
}

/* ---------------------------------------------------------------- --level */

static const char *const keys_order = "LRUDJA";

static void print_state(const nt_game *g, const char *prefix)
{
    nt_game_state st = nt_game_get_state(g);
    nt_world *w = nt_game_get_world(g);
    printf("%stick %d  bodies %d  score %d  spawned %d  complete %s", prefix, st.tick, nt_world_get_body_count(w), st.score,
           st.spawned, st.complete ? "yes" : "no");
    if (st.complete) printf(" (tick %d)", st.complete_tick);
    if (st.has_player) {
        nt_body_id p = nt_game_get_player(g);
        nt_vec2 pos = nt_body_get_position(w, p), v = nt_body_get_velocity(w, p);
        printf("  player %s at %.2f %.2f  v %.2f %.2f%s%s%s", st.alive ? "alive" : "dead", (double)pos.x, (double)pos.y,
               (double)v.x, (double)v.y, st.on_floor ? "  floor" : "", st.wall_left ? "  wall-left" : "",
               st.wall_right ? "  wall-right" : "");
    }
    printf("\n");
}

static int run_level(const char *level_path, long long ticks, const char *input, int has_seed, unsigned long long seed,
                     nt_real dt, int model, long long every)
{
    char why[600], named[4096];
    nt_level *lv = NULL;
    nt_status ls = load_level(levels_find(level_path, named, sizeof named), &lv, why, sizeof why); /* or an installed level */
    if (ls != NT_OK) {
        fprintf(stderr, "ntile run: %s\n", why);
        return ls == NT_ERR_PARSE ? CLI_INPUT_ERRORS : CLI_USAGE; /* a bad level, or no file */
    }
    nt_replay *rp = NULL;
    nt_text_error e;
    int status = CLI_OK;
    if (nt_replay_create((int)ticks, &rp) != NT_OK) {
        fprintf(stderr, "ntile run: out of memory\n");
        nt_level_destroy(lv);
        return CLI_USAGE;
    }
    if (input && nt_replay_set_inputs(rp, "--input", input, strlen(input), &e) != NT_OK) {
        fprintf(stderr, "ntile run: %s\n", e.message);
        nt_replay_destroy(rp);
        nt_level_destroy(lv);
        return CLI_USAGE;
    }
    nt_game_def gd = nt_default_game_def();
    gd.override_seed = has_seed != 0;
    gd.seed = seed;
    gd.override_friction_model = model >= 0;
    gd.friction_model = model >= 0 ? (nt_friction_model)model : NT_FRICTION_N;
    nt_game *g = NULL;
    nt_status s = nt_game_create(lv, &gd, &g);
    if (s != NT_OK) {
        fprintf(stderr, "ntile run: %s: cannot build the game: %s\n", level_path, nt_status_string(s));
        nt_replay_destroy(rp);
        nt_level_destroy(lv);
        return CLI_INPUT_ERRORS;
    }
    double t0 = now_ms();
    int k = 0, left = rp->input_count > 0 ? rp->inputs[0].count : 0;
    for (long long t = 1; t <= ticks && s == NT_OK; t++) {
        while (k < rp->input_count && left == 0) {
            k++;
            left = k < rp->input_count ? rp->inputs[k].count : 0;
        }
        uint32_t keys = k < rp->input_count ? rp->inputs[k].keys : 0;
        if (left > 0) left--;
        s = nt_game_step(g, keys, dt);
        if (every > 0 && t % every == 0) {
            char prefix[16] = "  ";
            int o = 2;
            for (int b = 0; b < 6; b++)
                if (keys & (1u << b)) prefix[o++] = keys_order[b];
            if (o == 2) prefix[o++] = '.';
            prefix[o++] = ' ';
            prefix[o] = '\0';
            print_state(g, prefix);
        }
    }
    double ms = now_ms() - t0;
    if (s != NT_OK) {
        fprintf(stderr, "ntile run: the step failed: %s\n", nt_status_string(s));
        status = CLI_INPUT_ERRORS;
    } else {
        printf("hash 0x%016llx\n", (unsigned long long)nt_game_hash(g));
        print_state(g, "");
        printf("%lld ticks in %.1f ms\n", ticks, ms);
    }
    nt_game_destroy(g);
    nt_replay_destroy(rp);
    nt_level_destroy(lv);
    return status;
}

/* ---------------------------------------------------------------- the subcommand */

void cli_run_usage(FILE *f)
{
    fputs("  ntile run [--record-hashes] FILE.ntr...\n"
          "      Replay each file headless: one line per replay (ok / not ok, name,\n"
          "      ticks, ms), the reasons of failures indented below it, then\n"
          "      \"N passed, N failed\". A hash mismatch names the first tick that\n"
          "      diverges. --record-hashes rewrites the files' hash and trace lines with\n"
          "      this run's values (other lines are kept) and prints what changed.\n"
          "  ntile run --level FILE.ntl --ticks N [--input KEYS] [--seed S] [--dt SECONDS]\n"
          "            [--friction-model n|coulomb] [--print-every K]\n"
          "      Run a level without a replay; print \"hash 0x...\" and a summary.\n"
          "      KEYS is run-length encoded: \"30R 8RJ 12.\" (count, then keys L R U D J A,\n"
          "      '.' for none); no --input means no keys. dt defaults to 1/40 s.\n",
          f);
}

static int usage_error(const char *fmt, const char *arg)
{
    fprintf(stderr, "ntile run: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\nusage:\n");
    cli_run_usage(stderr);
    return CLI_USAGE;
}

static int parse_ll(const char *s, long long lo, long long hi, long long *out)
{
    char *end;
    errno = 0;
    long long v = strtoll(s, &end, 10);
    if (end == s || *end || errno == ERANGE || v < lo || v > hi) return 0;
    *out = v;
    return 1;
}

int cli_run(int argc, char **argv)
{
    int record_hashes = 0, has_seed = 0, model = -1;
    const char *level = NULL, *input = NULL;
    long long ticks = -1, every = 0, seed = 0;
    nt_real dt = (nt_real)0.025;
    int nfiles = 0;
    char **files = calloc((size_t)argc, sizeof *files);
    if (!files) return CLI_USAGE;
    int options = 1, status = CLI_OK;
    for (int i = 1; i < argc && status == CLI_OK; i++) {
        const char *a = argv[i];
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (options && strcmp(a, "--") == 0) {
            options = 0;
        } else if (options && (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)) {
            printf("usage:\n");
            cli_run_usage(stdout);
            free(files);
            return CLI_OK;
        } else if (options && strcmp(a, "--record-hashes") == 0) {
            record_hashes = 1;
        } else if (options && (strcmp(a, "--level") == 0 || strcmp(a, "--input") == 0 || strcmp(a, "--ticks") == 0 ||
                               strcmp(a, "--seed") == 0 || strcmp(a, "--dt") == 0 || strcmp(a, "--friction-model") == 0 ||
                               strcmp(a, "--print-every") == 0)) {
            if (!val) {
                status = usage_error("%s needs a value", a);
                break;
            }
            i++;
            if (strcmp(a, "--level") == 0) level = val;
            else if (strcmp(a, "--input") == 0) input = val;
            else if (strcmp(a, "--ticks") == 0) {
                if (!parse_ll(val, 1, NT_REPLAY_MAX_TICKS, &ticks)) status = usage_error("--ticks needs a number of ticks (1..100000000), got '%s'", val);
            } else if (strcmp(a, "--print-every") == 0) {
                if (!parse_ll(val, 1, NT_REPLAY_MAX_TICKS, &every)) status = usage_error("--print-every needs a positive number of ticks, got '%s'", val);
            } else if (strcmp(a, "--seed") == 0) {
                if (!parse_ll(val, 0, 0x7fffffffffffffffLL, &seed)) status = usage_error("--seed needs a non-negative integer, got '%s'", val);
                has_seed = 1;
            } else if (strcmp(a, "--dt") == 0) {
                char *end;
                double d = strtod(val, &end);
                if (end == val || *end || !((nt_real)d >= (nt_real)NT_MIN_DT && (nt_real)d <= (nt_real)NT_MAX_DT))
                    status = usage_error("--dt needs a number of seconds in 1e-06 .. 1 (NT_MIN_DT .. NT_MAX_DT), got '%s'", val);
                dt = (nt_real)d;
            } else {
                if (strcmp(val, "n") == 0) model = NT_FRICTION_N;
                else if (strcmp(val, "coulomb") == 0) model = NT_FRICTION_COULOMB;
                else status = usage_error("--friction-model is n or coulomb, got '%s'", val);
            }
        } else if (options && a[0] == '-' && a[1] != '\0') {
            status = usage_error("unknown option '%s'", a);
        } else {
            files[nfiles++] = argv[i];
        }
    }
    if (status != CLI_OK) {
        free(files);
        return status;
    }
    if (level) {
        if (nfiles > 0 || record_hashes) status = usage_error("%s", "--level runs a level without replay files (give one or the other)");
        else if (ticks < 0) status = usage_error("%s", "--level needs --ticks N");
        else status = run_level(level, ticks, input, has_seed, (unsigned long long)seed, dt, model, every);
        free(files);
        return status;
    }
    if (input || ticks >= 0 || has_seed || model >= 0 || every > 0) {
        free(files);
        return usage_error("%s", "--input, --ticks, --seed, --dt, --friction-model and --print-every go with --level");
    }
    if (nfiles == 0) {
        free(files);
        return usage_error("%s", "no replay files");
    }
    tally tl = {0, 0, 0};
    for (int i = 0; i < nfiles; i++) run_file(files[i], record_hashes, &tl);
    printf("%d passed, %d failed\n", tl.passed, tl.failed);
    free(files);
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "ntile run: error writing the output\n");
        return CLI_USAGE;
    }
    if (tl.io_errors) return CLI_USAGE;
    return tl.failed ? CLI_INPUT_ERRORS : CLI_OK;
}
