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
#include <poll.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include "cli.h"
#include "../common/levels.h"
#include "../common/stream.h"
#include "ntile/game.h"

/* ---------------------------------------------------------------- files */

int cli_read_file(const char *path, char **out, size_t *len, char *why, size_t why_cap)
{
    return stream_read_file(path, 1, out, len, why, why_cap);
}

int cli_write_file(const char *path, const char *data, size_t len, char *why, size_t why_cap)
{
    return stream_write_file(path, data, len, (long)(clock() % 100000), why, why_cap);
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
    char tmp[1024];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    if (n > 0) sb_put(b, tmp, (size_t)n < sizeof tmp ? (size_t)n : sizeof tmp - 1);
}

/* Rewrite the replay text: every line but the hash block is kept in place; the
 * block at the end holds this build's new hashes (at the ticks it had, else the
 * other build's ticks, else the last tick) and a trace of every tick, and the
 * other build's lines unchanged. Says what changed in `say`. Returns 0 on a write error. */
static int record(const char *path, const char *text, size_t len, const nt_replay *rp, const nt_run_report *rep,
                  strbuf *say)
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
        if (!old) sb_printf(say, "    %s hash at tick %d: added 0x%016llx\n", scalar, t, (unsigned long long)h);
        else if (old->hash != h)
            sb_printf(say, "    %s hash at tick %d: 0x%016llx -> 0x%016llx\n", scalar, t, (unsigned long long)old->hash,
                   (unsigned long long)h);
        else sb_printf(say, "    %s hash at tick %d: unchanged\n", scalar, t);
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
    if (trn == 0) sb_printf(say, "    %s trace: added (%d ticks)\n", scalar, ticks);
    else if (changed == 0 && trn == ticks) sb_printf(say, "    %s trace: unchanged (%d ticks)\n", scalar, ticks);
    else sb_printf(say, "    %s trace: %d of %d ticks changed, first at tick %d\n", scalar, changed, ticks, first);
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

/* What one replay gave: its verdict, and the block `ntile run` prints for it. */
typedef struct replay_result {
    int ok;        /* passed */
    int load;      /* failed before running: unreadable, malformed, no level */
    int io_error;  /* --record-hashes could not write the file */
    int ticks;
    double ms;
    char name[96];
    strbuf text;   /* the "ok"/"not ok" line and the indented lines under it */
    strbuf why;    /* the reasons of a failure (the indented lines, unindented) */
} replay_result;

static void result_line(replay_result *r, int ok, int ticks, double ms)
{
    r->ok = ok;
    r->ticks = ticks;
    r->ms = ms;
    sb_printf(&r->text, "%-6s %-30s %8d ticks %9.1f ms\n", ok ? "ok" : "not ok", r->name, ticks, ms);
}

static void result_reason(replay_result *r, const char *msg)
{
    sb_printf(&r->text, "    %s\n", msg);
    sb_printf(&r->why, "%s\n", msg);
}

static void run_file(const char *path, int record_hashes, replay_result *res)
{
    char why[600];
    memset(res, 0, sizeof *res);
    base_name(path, res->name, sizeof res->name);
    char *text = NULL;
    size_t len = 0;
    nt_replay *rp = NULL;
    nt_level *lv = NULL;
    char *lpath = NULL;
    res->load = 1;
    if (!cli_read_file(path, &text, &len, why, sizeof why)) {
        result_line(res, 0, 0, 0);
        result_reason(res, why);
        return;
    }
    nt_text_error e;
    if (nt_replay_parse(path, text, len, &rp, &e) != NT_OK) {
        result_line(res, 0, 0, 0);
        result_reason(res, e.message);
        /* A level given where a replay is expected: say how to run a level. */
        size_t pl = strlen(path);
        char head[257];
        snprintf(head, sizeof head, "%.*s", (int)(len < 256 ? len : 256), text);
        if ((pl > 4 && strcmp(path + pl - 4, ".ntl") == 0) || strstr(head, "ntile-level")) {
            snprintf(why, sizeof why, "%s is a level, not a replay: run it with ntile run --level %s --ticks N", path,
                     path);
            result_reason(res, why);
        }
        free(text);
        return;
    }
    if (rp->name[0]) snprintf(res->name, sizeof res->name, "%s", rp->name);
    lpath = relative_to(path, rp->level);
    if (!lpath || load_level(lpath, &lv, why, sizeof why) != NT_OK) {
        result_line(res, 0, 0, 0);
        result_reason(res, lpath ? why : "out of memory");
    } else {
        nt_run_report rep;
        double t0 = now_ms();
        nt_status s = nt_run_replay(rp, lv, &rep);
        double ms = now_ms() - t0;
        if (s != NT_OK) {
            result_line(res, 0, rep.ticks, ms);
            snprintf(why, sizeof why, "cannot run: %s", nt_status_string(s));
            result_reason(res, why);
        } else {
            res->load = 0;
            /* Recording rewrites the hashes: only the facts decide the verdict. */
            int ok = record_hashes ? rep.fact_failures == 0 : rep.passed;
            result_line(res, ok, rep.ticks, ms);
            for (int i = 0; i < rep.message_count; i++)
                if (!record_hashes || !rep.message_is_hash[i]) result_reason(res, rep.messages[i]);
            if (rep.failure_count > rep.message_count && !record_hashes) {
                snprintf(why, sizeof why, "... and %d more", rep.failure_count - rep.message_count);
                result_reason(res, why);
            }
            if (record_hashes && !record(path, text, len, rp, &rep, &res->text)) res->io_error = 1;
            nt_run_report_free(&rep);
        }
    }
    free(lpath);
    nt_level_destroy(lv);
    nt_replay_destroy(rp);
    free(text);
}

static void result_free(replay_result *r)
{
    free(r->text.p);
    free(r->why.p);
    r->text.p = r->why.p = NULL;
}

/* ---------------------------------------------------------------- -j: child processes */

/* A result crosses the pipe as a header and three strings. */
typedef struct wire_head {
    int ok, load, io_error, ticks;
    double ms;
    size_t name_len, text_len, why_len;
} wire_head;

static int write_all(int fd, const void *p, size_t n)
{
    const char *c = p;
    while (n > 0) {
        ssize_t w = write(fd, c, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return 0;
        c += w;
        n -= (size_t)w;
    }
    return 1;
}

static void wire_send(int fd, const replay_result *r)
{
    wire_head h = {r->ok, r->load, r->io_error, r->ticks, r->ms, strlen(r->name), r->text.n, r->why.n};
    if (r->text.oom || r->why.oom) h.text_len = h.why_len = 0;
    (void)(write_all(fd, &h, sizeof h) && write_all(fd, r->name, h.name_len) &&
           write_all(fd, r->text.p ? r->text.p : "", h.text_len) && write_all(fd, r->why.p ? r->why.p : "", h.why_len));
}

/* Decode what a child sent; 0 when it is incomplete (the child died). */
static int wire_receive(const strbuf *in, replay_result *r)
{
    memset(r, 0, sizeof *r);
    wire_head h;
    if (in->n < sizeof h) return 0;
    memcpy(&h, in->p, sizeof h);
    if (h.name_len >= sizeof r->name || in->n != sizeof h + h.name_len + h.text_len + h.why_len) return 0;
    r->ok = h.ok;
    r->load = h.load;
    r->io_error = h.io_error;
    r->ticks = h.ticks;
    r->ms = h.ms;
    const char *p = in->p + sizeof h;
    memcpy(r->name, p, h.name_len);
    r->name[h.name_len] = '\0';
    p += h.name_len;
    sb_put(&r->text, p, h.text_len);
    sb_put(&r->why, p + h.text_len, h.why_len);
    return !r->text.oom && !r->why.oom;
}

typedef struct worker {
    pid_t pid;
    int fd;    /* read end of its pipe, -1 when done */
    int index; /* the file it runs */
    strbuf in;
} worker;

/* Finish a worker whose pipe closed: reap it and decode its result. */
static void worker_finish(worker *w, const char *path, replay_result *out)
{
    int st = 0;
    close(w->fd);
    w->fd = -1;
    while (waitpid(w->pid, &st, 0) < 0 && errno == EINTR) {
    }
    if (!(WIFEXITED(st) && WEXITSTATUS(st) == 0) || !wire_receive(&w->in, out)) {
        result_free(out);
        memset(out, 0, sizeof *out);
        base_name(path, out->name, sizeof out->name);
        out->load = 1;
        result_line(out, 0, 0, 0);
        char why[128];
        if (WIFSIGNALED(st)) snprintf(why, sizeof why, "the process running it was killed by signal %d", WTERMSIG(st));
        else snprintf(why, sizeof why, "the process running it failed (exit status %d)", WIFEXITED(st) ? WEXITSTATUS(st) : -1);
        result_reason(out, why);
    }
    free(w->in.p);
    memset(&w->in, 0, sizeof w->in);
}

/* Run files[0..n) in up to `jobs` child processes, one process per replay; results
 * land in res[] in the files' order. Calls `done` with each result as soon as it and
 * every result before it are in, so the output keeps the order of a plain run.
 * Returns 0 when a process or pipe could not be made. */
static int run_parallel(char **files, int n, int jobs, int record_hashes, replay_result *res,
                        void (*done)(replay_result *r, void *ctx), void *ctx)
{
    worker *ws = calloc((size_t)jobs, sizeof *ws);
    char *have = calloc((size_t)n + 1, 1);
    if (!ws || !have) {
        free(ws);
        free(have);
        return 0;
    }
    for (int k = 0; k < jobs; k++) ws[k].fd = -1;
    int next = 0, running = 0, shown = 0, ok = 1;
    while (shown < n) {
        while (ok && running < jobs && next < n) {
            int k = 0;
            while (ws[k].fd >= 0) k++;
            int pfd[2];
            if (pipe(pfd) != 0) {
                ok = 0;
                break;
            }
            fflush(stdout);
            fflush(stderr);
            pid_t pid = fork();
            if (pid < 0) {
                close(pfd[0]);
                close(pfd[1]);
                ok = 0;
                break;
            }
            if (pid == 0) {
                close(pfd[0]);
                for (int o = 0; o < jobs; o++)
                    if (ws[o].fd >= 0) close(ws[o].fd);
                replay_result r;
                run_file(files[next], record_hashes, &r);
                wire_send(pfd[1], &r);
                result_free(&r);
                for (int o = 0; o < n; o++) result_free(&res[o]);
                for (int o = 0; o < jobs; o++) free(ws[o].in.p);
                free(ws);
                free(have);
                _exit(0);
            }
            close(pfd[1]);
            ws[k].pid = pid;
            ws[k].fd = pfd[0];
            ws[k].index = next++;
            running++;
        }
        if (running == 0) break; /* !ok: nothing more can start */
        struct pollfd pf[64];
        int map[64], np = 0;
        for (int k = 0; k < jobs && np < 64; k++)
            if (ws[k].fd >= 0) {
                pf[np].fd = ws[k].fd;
                pf[np].events = POLLIN;
                map[np++] = k;
            }
        if (poll(pf, (nfds_t)np, -1) < 0) {
            if (errno == EINTR) continue;
            ok = 0;
            break;
        }
        for (int i = 0; i < np; i++) {
            if (!(pf[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
            worker *w = &ws[map[i]];
            char buf[65536];
            ssize_t got = read(w->fd, buf, sizeof buf);
            if (got < 0 && errno == EINTR) continue;
            if (got > 0) {
                sb_put(&w->in, buf, (size_t)got);
                continue;
            }
            worker_finish(w, files[w->index], &res[w->index]);
            have[w->index] = 1;
            running--;
        }
        while (shown < n && have[shown]) done(&res[shown], ctx), shown++;
    }
    /* After a failure to start more: let the running ones finish. */
    for (int k = 0; k < jobs; k++)
        if (ws[k].fd >= 0) {
            char buf[65536];
            ssize_t got;
            while ((got = read(ws[k].fd, buf, sizeof buf)) > 0 || (got < 0 && errno == EINTR))
                if (got > 0) sb_put(&ws[k].in, buf, (size_t)got);
            worker_finish(&ws[k], files[ws[k].index], &res[ws[k].index]);
            have[ws[k].index] = 1;
        }
    while (shown < n && have[shown]) done(&res[shown], ctx), shown++;
    free(ws);
    free(have);
    return ok && shown == n;
}

/* ---------------------------------------------------------------- JUnit XML */

/* Text made safe for XML: markup characters escaped; control bytes other than tab and
 * newline, and bytes outside ASCII, become '?' (the report stays valid UTF-8). */
static void xml_text(FILE *f, const char *s, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c == '&') fputs("&amp;", f);
        else if (c == '<') fputs("&lt;", f);
        else if (c == '>') fputs("&gt;", f);
        else if (c == '"') fputs("&quot;", f);
        else if (c == '\n' || c == '\t') fputc(c, f);
        else if (c < 0x20 || c >= 0x7f) fputc('?', f);
        else fputc(c, f);
    }
}

static void xml_attr(FILE *f, const char *name, const char *s)
{
    fprintf(f, " %s=\"", name);
    xml_text(f, s, strlen(s));
    fputc('"', f);
}

/* The JUnit report of a run: one testsuite, one testcase per replay (a replay whose
 * facts or hashes fail: <failure>; one that could not be loaded or run: <error>).
 * Written through a temporary file and a rename. Returns 0 on a write error. */
static int write_junit(const char *path, char **files, const replay_result *res, int n, const char *suite,
                       double total_ms)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    if (!f) return 0;
    int failures = 0, errors = 0;
    for (int i = 0; i < n; i++) {
        if (res[i].ok) continue;
        if (res[i].load) errors++;
        else failures++;
    }
    fputs("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites", f);
    xml_attr(f, "name", suite);
    fprintf(f, " tests=\"%d\" failures=\"%d\" errors=\"%d\" time=\"%.6f\">\n", n, failures, errors, total_ms / 1000);
    fputs("  <testsuite", f);
    xml_attr(f, "name", suite);
    fprintf(f, " tests=\"%d\" failures=\"%d\" errors=\"%d\" skipped=\"0\" time=\"%.6f\">\n", n, failures, errors,
            total_ms / 1000);
    for (int i = 0; i < n; i++) {
        const replay_result *r = &res[i];
        fputs("    <testcase", f);
        xml_attr(f, "name", r->name);
        xml_attr(f, "classname", "ntile.replay");
        xml_attr(f, "file", files[i]);
        fprintf(f, " time=\"%.6f\"", r->ms / 1000);
        if (r->ok) {
            fputs("/>\n", f);
            continue;
        }
        const char *why = r->why.p ? r->why.p : "";
        size_t first = strcspn(why, "\n");
        char msg[512];
        snprintf(msg, sizeof msg, "%.*s", (int)(first < sizeof msg - 1 ? first : sizeof msg - 1), why);
        fprintf(f, ">\n      <%s", r->load ? "error" : "failure");
        xml_attr(f, "message", msg[0] ? msg : "failed");
        xml_attr(f, "type", r->load ? "load" : "replay");
        fputc('>', f);
        xml_text(f, why, r->why.n);
        fprintf(f, "</%s>\n    </testcase>\n", r->load ? "error" : "failure");
    }
    fputs("  </testsuite>\n</testsuites>\n", f);
    int ok = fclose(f) == 0 && buf;
    char why[600];
    if (ok && !cli_write_file(path, buf, len, why, sizeof why)) {
        fprintf(stderr, "ntile run: %s\n", why);
        ok = 0;
    }
    free(buf);
    return ok;
}

/* Print one result and count it. */
typedef struct tally {
    int passed, failed, io_errors;
} tally;

static void show_result(replay_result *r, void *ctx)
{
    tally *tl = ctx;
    if (r->text.oom) printf("%-6s %-30s (out of memory)\n", "not ok", r->name);
    else if (r->text.p) fputs(r->text.p, stdout);
    fflush(stdout);
    if (r->ok) tl->passed++;
    else tl->failed++;
    if (r->io_error) tl->io_errors++;
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
        size_t pl = strlen(level_path);
        if (ls == NT_ERR_PARSE && pl > 4 && strcmp(level_path + pl - 4, ".ntr") == 0)
            fprintf(stderr, "ntile run: %s is a replay, not a level: run it with ntile run %s\n", level_path, level_path);
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
    fputs("  ntile run [--record-hashes] [-j N] [--shard I/N] [--junit FILE.xml] FILE.ntr...\n"
          "      Replay each file headless: one line per replay (ok / not ok, name,\n"
          "      ticks, ms), the reasons of failures indented below it, then\n"
          "      \"N passed, N failed\". A hash mismatch names the first tick that\n"
          "      diverges. --record-hashes rewrites the files' hash and trace lines with\n"
          "      this run's values (other lines are kept) and prints what changed.\n"
          "      -j N (--jobs N): up to N replays at once, in child processes (1..64);\n"
          "      the output is the same, in the same order. --shard I/N: only the I-th of\n"
          "      N slices of the file list (files I, I+N, I+2N, ... counting from 1), for\n"
          "      spreading a corpus over CI machines. --junit FILE.xml: also write a JUnit\n"
          "      XML report (one testcase per replay).\n"
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
    const char *level = NULL, *input = NULL, *junit = NULL;
    long long ticks = -1, every = 0, seed = 0, jobs = 1, shard_i = 1, shard_n = 1;
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
        } else if (options && (strcmp(a, "-j") == 0 || strcmp(a, "--jobs") == 0 || strcmp(a, "--shard") == 0 ||
                               strcmp(a, "--junit") == 0)) {
            if (!val) {
                status = usage_error("%s needs a value", a);
                break;
            }
            i++;
            if (strcmp(a, "--junit") == 0) {
                junit = val;
            } else if (strcmp(a, "--shard") == 0) {
                const char *slash = strchr(val, '/');
                char first[32];
                size_t fl = slash ? (size_t)(slash - val) : 0;
                if (slash && fl < sizeof first) {
                    memcpy(first, val, fl);
                    first[fl] = '\0';
                }
                if (!slash || fl >= sizeof first || !parse_ll(first, 1, 1000000, &shard_i) ||
                    !parse_ll(slash + 1, 1, 1000000, &shard_n) || shard_i > shard_n)
                    status = usage_error("--shard needs I/N with 1 <= I <= N (e.g. 2/4), got '%s'", val);
            } else if (!parse_ll(val, 1, 64, &jobs)) {
                status = usage_error("-j needs a number of processes in 1..64, got '%s'", val);
            }
        } else if (options && strncmp(a, "-j", 2) == 0 && a[2] >= '0' && a[2] <= '9') {
            if (!parse_ll(a + 2, 1, 64, &jobs)) status = usage_error("-j needs a number of processes in 1..64, got '%s'", a + 2);
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
        else if (junit || jobs > 1 || shard_n > 1) status = usage_error("%s", "-j, --shard and --junit go with replay files, not --level");
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
    /* The shard: files I, I+N, ... (from 1) of the list as given. */
    int nrun = 0;
    for (int i = 0; i < nfiles; i++)
        if (i % shard_n == shard_i - 1) files[nrun++] = files[i];
    replay_result *res = calloc((size_t)(nrun > 0 ? nrun : 1), sizeof *res);
    if (!res) {
        free(files);
        fprintf(stderr, "ntile run: out of memory\n");
        return CLI_USAGE;
    }
    tally tl = {0, 0, 0};
    double t0 = now_ms();
    if (jobs > 1 && nrun > 1) {
        if (!run_parallel(files, nrun, (int)(jobs < nrun ? jobs : nrun), record_hashes, res, show_result, &tl)) {
            fprintf(stderr, "ntile run: cannot start the processes for -j: %s\n", strerror(errno));
            tl.io_errors++;
        }
    } else {
        for (int i = 0; i < nrun; i++) {
            run_file(files[i], record_hashes, &res[i]);
            show_result(&res[i], &tl);
        }
    }
    double total_ms = now_ms() - t0;
    printf("%d passed, %d failed\n", tl.passed, tl.failed);
    if (junit) {
        char suite[64] = "ntile run";
        if (shard_n > 1) snprintf(suite, sizeof suite, "ntile run (shard %lld/%lld)", shard_i, shard_n);
        if (!write_junit(junit, files, res, nrun, suite, total_ms)) {
            fprintf(stderr, "ntile run: cannot write the JUnit report '%s'\n", junit);
            tl.io_errors++;
        }
    }
    for (int i = 0; i < nrun; i++) result_free(&res[i]);
    free(res);
    free(files);
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "ntile run: error writing the output\n");
        return CLI_USAGE;
    }
    if (tl.io_errors) return CLI_USAGE;
    return tl.failed ? CLI_INPUT_ERRORS : CLI_OK;
}
