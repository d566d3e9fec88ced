/* ntile query — a line protocol for asking the engine questions.
 *
 * Each input line that is not blank and not a comment (first field starts with '#')
 * gives exactly one output line, in order: the answer, or `error: line N: REASON`.
 * A field starting with '#' also ends a line early (trailing comment). Fields are
 * separated by spaces or tabs; a line ends at LF, CR LF, or the end of the input.
 * Cell size is 1, y points down, numbers are what strtod accepts (finite only);
 * tile names match ignoring case. Output numbers are the shortest decimals that read
 * back as the same nt_real (float or double: -0.35, not -0.349999994), +0 for -0.
 * With -n (--line-numbers) every output line starts with "N: ", the input line it
 * answers.
 *
 *   tile NAME aabb CX CY HW HH      -> DX DY   (box out of tile NAME alone in cell (0,0))
 *   tile NAME circle CX CY R        -> DX DY
 *   map W H T1,T2,...               -> ok      (W*H names or ids 0..33, row-major; the
 *                                               list may be split over several fields)
 *   resolve aabb CX CY HW HH        -> DX DY   (nt_map_resolve against the current map)
 *   resolve circle CX CY R          -> DX DY
 *   ray X0 Y0 X1 Y1                 -> hit T NX NY | miss
 *   pair SHAPE... SHAPE...          -> DX DY   (first shape out of the second)
 *
 * A line that fails leaves the state (the current map) unchanged. Exit status: 0 when
 * every line was answered, 1 when some line was an error, 2 for a usage error or an
 * unreadable input (message on stderr).
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "../common/tilename.h"
#include "cli.h"
#include "ntile/ntile.h"

/* Longest accepted line. Large enough for a 4096 x 4096 map written with names. */
#define QUERY_DEFAULT_MAX_LINE ((size_t)1 << 28)

/* ---------- reading lines ---------- */

/* Input is read with read(2), which returns whatever is available: the answers so far
 * are flushed before each read, so a program can drive the CLI through pipes one
 * line at a time, while files are still read in large blocks. */
typedef struct reader {
    int fd;         /* -1: read from mem instead */
    const unsigned char *mem;
    size_t mem_left;
    FILE *flush;    /* flushed before waiting for input */
    size_t pos, len;
    int eof;
    int error;      /* errno of a failed read, or 0 */
    unsigned char buf[1 << 16];
} reader;

/* Refill the buffer. Returns 0 at the end of the input or on a read error. */
static int reader_fill(reader *r)
{
    if (r->eof) return 0;
    if (r->fd < 0) {
        size_t n = r->mem_left < sizeof r->buf ? r->mem_left : sizeof r->buf;
        if (n == 0) {
            r->eof = 1;
            return 0;
        }
        memcpy(r->buf, r->mem, n);
        r->mem += n;
        r->mem_left -= n;
        r->pos = 0;
        r->len = n;
        return 1;
    }
    fflush(r->flush);
    for (;;) {
        ssize_t n = read(r->fd, r->buf, sizeof r->buf);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            r->error = n < 0 ? errno : 0;
            r->eof = 1;
            return 0;
        }
        r->pos = 0;
        r->len = (size_t)n;
        return 1;
    }
}

typedef struct line {
    char *text;     /* NUL-terminated copy of the line, without its end (LF, CR LF) */
    size_t len;     /* bytes in text, which may itself contain NULs */
    size_t cap;
    int too_long;   /* longer than the limit: text holds only a prefix */
    int no_memory;  /* allocation failed: text holds only a prefix */
} line;

/* Append n bytes, or as many as fit within max and set too_long (the prefix still
 * tells whether the line is a comment). */
static void line_append(line *l, const unsigned char *p, size_t n, size_t max)
{
    if (l->too_long || l->no_memory) return;
    if (n > max - l->len) {
        n = max - l->len;
        l->too_long = 1;
        if (n == 0) return;
    }
    if (l->len + n + 1 > l->cap) {
        size_t cap = l->cap ? l->cap : 256;
        while (cap < l->len + n + 1) cap = cap > SIZE_MAX / 2 ? SIZE_MAX : cap * 2;
        char *t = realloc(l->text, cap);
        if (!t) {
            l->no_memory = 1;
            return;
        }
        l->text = t;
        l->cap = cap;
    }
    memcpy(l->text + l->len, p, n);
    l->len += n;
    l->text[l->len] = '\0';
}

/* Read the next line. Returns 1 when a line was read (possibly empty, possibly the
 * last one without a newline), 0 at the end of the input or on a read error. */
static int read_line(reader *r, line *l, size_t max)
{
    int got = 0;
    l->len = 0;
    l->too_long = 0;
    l->no_memory = 0;
    if (l->text) l->text[0] = '\0';
    for (;;) {
        if (r->pos == r->len && !reader_fill(r)) break;
        got = 1;
        const unsigned char *start = r->buf + r->pos;
        size_t avail = r->len - r->pos;
        const unsigned char *nl = memchr(start, '\n', avail);
        size_t n = nl ? (size_t)(nl - start) : avail;
        line_append(l, start, n, max + 1); /* room for a CR before the LF */
        r->pos += nl ? n + 1 : n;
        if (nl) break;
    }
    if (!got) return 0;
    if (!l->too_long && !l->no_memory && l->len > 0 && l->text[l->len - 1] == '\r') l->text[--l->len] = '\0';
    if (l->len > max) l->too_long = 1;
    return 1;
}

/* ---------- the query state and error messages ---------- */

typedef struct query {
    FILE *out;
    int line_numbers; /* -n: "N: " before each output line */
    unsigned long long lineno;
    unsigned long long errors;
    nt_map *map;
    char **fields;
    size_t nfields, cap_fields;
} query;

/* Print `error: line N: ...` as this line's output. Always returns 0. */
static int fail(query *q, const char *fmt, ...)
{
    va_list ap;
    if (q->line_numbers) fprintf(q->out, "%llu: ", q->lineno);
    fprintf(q->out, "error: line %llu: ", q->lineno);
    va_start(ap, fmt);
    vfprintf(q->out, fmt, ap);
    va_end(ap);
    fputc('\n', q->out);
    q->errors++;
    return 0;
}

/* A field made printable for a message: control and non-ASCII bytes escaped as \xNN,
 * long fields cut with "...". The buffer must hold QUOTE_MAX bytes. */
#define QUOTE_MAX 96
static const char *quote(char *buf, const char *s)
{
    size_t o = 0;
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (o + 8 > QUOTE_MAX) {
            memcpy(buf + o, "...", 4);
            return buf;
        }
        if (c >= 0x20 && c < 0x7f && c != '\\') buf[o++] = (char)c;
        else o += (size_t)sprintf(buf + o, "\\x%02x", c);
    }
    buf[o] = '\0';
    return buf;
}

/* ---------- fields and values ---------- */

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/* Split the line in place. Returns 0 only when the field array cannot grow. */
static int split_fields(query *q, char *s)
{
    q->nfields = 0;
    for (;;) {
        while (is_space(*s)) s++;
        if (!*s || *s == '#') return 1;
        if (q->nfields == q->cap_fields) {
            size_t cap = q->cap_fields ? q->cap_fields * 2 : 16;
            char **f = realloc(q->fields, cap * sizeof *f);
            if (!f) return 0;
            q->fields = f;
            q->cap_fields = cap;
        }
        q->fields[q->nfields++] = s;
        while (*s && !is_space(*s)) s++;
        if (*s) *s++ = '\0';
    }
}

/* A finite number (as nt_real too). `what` names it in the message. */
static int parse_number(query *q, const char *s, const char *what, nt_real *out)
{
    char qb[QUOTE_MAX];
    char *end;
    double v = strtod(s, &end);
    if (end == s || *end) return fail(q, "%s '%s' is not a number", what, quote(qb, s));
    if (!isfinite(v)) return fail(q, "%s '%s' is not a finite number", what, quote(qb, s));
    nt_real r = (nt_real)v;
    if (!isfinite(r))
        return fail(q, "%s '%s' is too large for %s", what, quote(qb, s), NT_REAL_IS_DOUBLE ? "double" : "float");
    *out = r;
    return 1;
}

/* A size: half-width, half-height or radius, in [0, NT_MAX_HALF_CELLS] cells (bodies
 * up to 8 cells across). */
static int parse_size(query *q, const char *s, const char *what, nt_real *out)
{
    char qb[QUOTE_MAX];
    if (!parse_number(q, s, what, out)) return 0;
    if (*out < 0) return fail(q, "negative %s '%s'", what, quote(qb, s));
    if (*out > (nt_real)NT_MAX_HALF_CELLS)
        return fail(q, "%s '%s' is larger than the largest half-size (%d)", what, quote(qb, s), NT_MAX_HALF_CELLS);
    return 1;
}

/* A tile by N name or numeric id 0..33; -1 when unknown. */
static int tile_id(const char *s)
{
    size_t n = strlen(s);
    if (n >= 1 && n <= 2 && strspn(s, "0123456789") == n) {
        int id = atoi(s);
        return id < NT_TILE_COUNT ? id : -1;
    }
    return tilename_lookup(s);
}

/* "unknown tile name 'X'" with a hint: the closest name, else where the names are. */
static int fail_tile(query *q, const char *s, const char *where)
{
    char qb[QUOTE_MAX];
    const char *near = tilename_suggest(s);
    if (near) return fail(q, "unknown tile name '%s'%s (did you mean '%s'?)", quote(qb, s), where, near);
    return fail(q, "unknown tile name '%s'%s (expected an N tile name or id 0..%d: EMPTY, FULL, 45DEGpn, ..., HALFl, "
                "any case; see the tile table in README.md)", quote(qb, s), where, NT_TILE_COUNT - 1);
}

/* A map side: a decimal integer in 1..NT_MAP_MAX_SIDE. */
static int parse_side(query *q, const char *s, const char *what, int *out)
{
    char qb[QUOTE_MAX];
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s || *end) return fail(q, "map %s '%s' is not an integer", what, quote(qb, s));
    if (errno == ERANGE || v < 1 || v > NT_MAP_MAX_SIDE)
        return fail(q, "map %s '%s' is out of range 1..%d", what, quote(qb, s), NT_MAP_MAX_SIDE);
    *out = (int)v;
    return 1;
}

typedef struct placed {
    nt_vec2 pos;
    nt_shape shape;
} placed;

/* Parse `aabb CX CY HW HH` or `circle CX CY R` at fields[i]. Returns the number of
 * fields used, 0 after printing an error. `cmd` names the command in messages; when
 * `last` is set the shape must end the line. */
static size_t parse_shape(query *q, size_t i, const char *cmd, int last, placed *out)
{
    char qb[QUOTE_MAX];
    if (i >= q->nfields) return fail(q, "wrong number of fields: '%s' is missing a shape (aabb or circle)", cmd);
    const char *word = q->fields[i];
    int box = strcmp(word, "aabb") == 0;
    if (!box && strcmp(word, "circle") != 0)
        return fail(q, "unknown shape '%s' (expected aabb or circle)", quote(qb, word));
    size_t need = box ? 4 : 3;
    size_t have = q->nfields - i - 1;
    if (have < need || (last && have > need))
        return fail(q, "wrong number of fields: '%s %s' takes %s, got %zu field%s after '%s'", cmd, word,
                    box ? "CX CY HW HH" : "CX CY R", have, have == 1 ? "" : "s", word);
    char **f = q->fields + i + 1;
    nt_real cx = 0, cy = 0, a = 0, b = 0;
    if (!parse_number(q, f[0], "x", &cx) || !parse_number(q, f[1], "y", &cy)) return 0;
    if (box) {
        if (!parse_size(q, f[2], "half-width", &a) || !parse_size(q, f[3], "half-height", &b)) return 0;
        out->shape = nt_shape_aabb(a, b);
    } else {
        if (!parse_size(q, f[2], "radius", &a)) return 0;
        out->shape = nt_shape_circle(a);
    }
    out->pos = nt_v2(cx, cy);
    return need + 1;
}

/* Exactly n fields, or an error naming the expected form. */
static int expect_fields(query *q, size_t n, const char *form)
{
    if (q->nfields == n) return 1;
    return fail(q, "wrong number of fields: expected '%s' (%zu fields), got %zu", form, n, q->nfields);
}

/* ---------- output ---------- */

/* The shortest decimal that reads back as the same nt_real: the fewest significant
 * digits (1..9 for float, 1..17 for double) whose %e form strtof / strtod turns into
 * the same bits; printed without an exponent when it lies in 1e-5 .. 1e17. +0 for -0. */
static void format_real(char *buf, size_t cap, nt_real v)
{
    if (v == 0) v = 0; /* +0, never -0 */
    const int max_digits = NT_REAL_IS_DOUBLE ? 17 : 9;
    int digits = max_digits;
    for (int p = 1; p <= max_digits; p++) {
        snprintf(buf, cap, "%.*e", p - 1, (double)v);
#if NT_REAL_IS_DOUBLE
        nt_real back = strtod(buf, NULL);
#else
        nt_real back = strtof(buf, NULL);
#endif
        if (memcmp(&back, &v, sizeof v) == 0) {
            digits = p;
            break;
        }
    }
    snprintf(buf, cap, "%.*e", digits - 1, (double)v);
    const char *e = strchr(buf, 'e');
    int exp10 = e ? atoi(e + 1) : 0;
    if (exp10 >= -5 && exp10 < 17) snprintf(buf, cap, "%.*f", digits - 1 - exp10 > 0 ? digits - 1 - exp10 : 0, (double)v);
}

static void put_num(FILE *o, nt_real v)
{
    char buf[64];
    format_real(buf, sizeof buf, v);
    fputs(buf, o);
}

/* The "N: " of -n before an answer. */
static void put_prefix(query *q)
{
    if (q->line_numbers) fprintf(q->out, "%llu: ", q->lineno);
}

static void put_vec(query *q, nt_real x, nt_real y)
{
    put_prefix(q);
    put_num(q->out, x);
    fputc(' ', q->out);
    put_num(q->out, y);
    fputc('\n', q->out);
}

static void put_mtv(query *q, bool hit, const nt_mtv *m)
{
    if (hit) put_vec(q, m->normal.x * m->depth, m->normal.y * m->depth);
    else put_vec(q, 0, 0);
}

/* ---------- commands ---------- */

static void cmd_tile(query *q)
{
    if (q->nfields < 3) {
        fail(q, "wrong number of fields: expected 'tile NAME aabb CX CY HW HH' or 'tile NAME circle CX CY R'");
        return;
    }
    int tile = tile_id(q->fields[1]);
    if (tile < 0) {
        fail_tile(q, q->fields[1], "");
        return;
    }
    placed p;
    if (!parse_shape(q, 2, "tile NAME", 1, &p)) return;
    nt_mtv m;
    bool hit = nt_tile_collide_shape(tile, p.pos, p.shape, &m);
    put_mtv(q, hit, &m);
}

static void cmd_pair(query *q)
{
    placed a, b;
    size_t used = parse_shape(q, 1, "pair", 0, &a);
    if (!used || !parse_shape(q, 1 + used, "pair", 1, &b)) return;
    nt_mtv m;
    bool hit = nt_collide_shapes(a.pos, a.shape, b.pos, b.shape, &m);
    put_mtv(q, hit, &m);
}

static void cmd_resolve(query *q)
{
    placed p;
    if (!parse_shape(q, 1, "resolve", 1, &p)) return;
    if (!q->map) {
        fail(q, "'resolve' before any 'map' line");
        return;
    }
    nt_resolution r;
    if (nt_map_resolve(q->map, p.pos, p.shape, &r)) put_vec(q, r.push.x, r.push.y);
    else put_vec(q, 0, 0);
}

static void cmd_ray(query *q)
{
    if (!expect_fields(q, 5, "ray X0 Y0 X1 Y1")) return;
    nt_real v[4];
    static const char *const names[4] = {"x0", "y0", "x1", "y1"};
    for (int i = 0; i < 4; i++)
        if (!parse_number(q, q->fields[1 + i], names[i], &v[i])) return;
    if (!q->map) {
        fail(q, "'ray' before any 'map' line");
        return;
    }
    nt_ray_hit h;
    put_prefix(q);
    if (!nt_map_raycast(q->map, nt_v2(v[0], v[1]), nt_v2(v[2], v[3]), &h)) {
        fputs("miss\n", q->out);
        return;
    }
    fputs("hit ", q->out);
    put_num(q->out, h.fraction);
    fputc(' ', q->out);
    put_num(q->out, h.normal.x);
    fputc(' ', q->out);
    put_num(q->out, h.normal.y);
    fputc('\n', q->out);
}

static void cmd_map(query *q)
{
    if (q->nfields < 4) {
        fail(q, "wrong number of fields: expected 'map W H T1,T2,...'");
        return;
    }
    int w, h;
    if (!parse_side(q, q->fields[1], "width", &w) || !parse_side(q, q->fields[2], "height", &h)) return;
    size_t want = (size_t)w * (size_t)h, count = 0;
    for (size_t i = 3; i < q->nfields; i++) {
        count++;
        for (const char *s = q->fields[i]; *s; s++) count += *s == ',';
    }
    if (count != want) {
        fail(q, "map %dx%d needs %zu tiles, got %zu", w, h, want, count);
        return;
    }
    uint8_t *tiles = malloc(want);
    if (!tiles) {
        fail(q, "out of memory for a %dx%d map", w, h);
        return;
    }
    size_t k = 0;
    for (size_t i = 3; i < q->nfields; i++) {
        char *s = q->fields[i];
        for (;;) {
            char *comma = strchr(s, ',');
            if (comma) *comma = '\0';
            int id = *s ? tile_id(s) : -1;
            if (id < 0) {
                char where[48];
                snprintf(where, sizeof where, " (map tile %zu)", k + 1);
                if (*s) fail_tile(q, s, where);
                else fail(q, "empty tile name (map tile %zu)", k + 1);
                free(tiles);
                return;
            }
            tiles[k++] = (uint8_t)id;
            if (!comma) break;
            s = comma + 1;
        }
    }
    nt_map_def def = nt_default_map_def();
    def.width = w;
    def.height = h;
    def.cell_size = 1;
    nt_map *map = NULL;
    nt_status st = nt_map_create(&def, &map);
    if (st == NT_OK) {
        st = nt_map_set_tiles(map, tiles, want);
        if (st != NT_OK) nt_map_destroy(map);
    }
    free(tiles);
    if (st != NT_OK) {
        fail(q, "cannot create the map: %s", nt_status_string(st));
        return;
    }
    nt_map_destroy(q->map);
    q->map = map;
    put_prefix(q);
    fputs("ok\n", q->out);
}

typedef struct command {
    const char *name;
    void (*run)(query *q);
} command;

static const command commands[] = {
    {"tile", cmd_tile}, {"map", cmd_map}, {"resolve", cmd_resolve}, {"ray", cmd_ray}, {"pair", cmd_pair},
};

/* Answer one line (which has no embedded NUL). Blank and comment lines print nothing. */
static void run_line(query *q, char *text)
{
    char qb[QUOTE_MAX];
    if (!split_fields(q, text)) {
        fail(q, "out of memory splitting the line");
        return;
    }
    if (q->nfields == 0) return;
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++) {
        if (strcmp(q->fields[0], commands[i].name) == 0) {
            commands[i].run(q);
            return;
        }
    }
    fail(q, "unknown command '%s' (expected tile, map, resolve, ray or pair)", quote(qb, q->fields[0]));
}

/* ---------- the subcommand ---------- */

/* Answer every line of r on out. Returns the exit status. */
static int query_run(reader *r, FILE *out, size_t max_line, const char *label, int line_numbers)
{
    r->flush = out;
    r->pos = r->len = 0;
    r->eof = 0;
    r->error = 0;
    query q = {0};
    q.out = out;
    q.line_numbers = line_numbers;
    line l = {0};
    while (read_line(r, &l, max_line)) {
        q.lineno++;
        /* Blank and comment lines are judged by their first non-blank byte, even when
         * the line is too long to keep whole. */
        size_t first = 0;
        while (first < l.len && is_space(l.text[first])) first++;
        if (first < l.len && l.text[first] == '#') continue;
        const char *nul = l.len ? memchr(l.text, '\0', l.len) : NULL;
        if (l.too_long) fail(&q, "line longer than %zu bytes", max_line);
        else if (l.no_memory) fail(&q, "out of memory reading the line");
        else if (first == l.len) continue;
        else if (nul) fail(&q, "embedded NUL byte at column %zu", (size_t)(nul - l.text) + 1);
        else run_line(&q, l.text);
    }
    int status = q.errors ? CLI_INPUT_ERRORS : CLI_OK;
    if (r->error) {
        fprintf(stderr, "ntile query: error reading %s: %s\n", label, strerror(r->error));
        status = CLI_USAGE;
    }
    if (fflush(out) != 0 || ferror(out)) {
        fprintf(stderr, "ntile query: error writing the output\n");
        status = CLI_USAGE;
    }
    nt_map_destroy(q.map);
    free(q.fields);
    free(l.text);
    return status;
}

void cli_query_usage(FILE *f)
{
    fputs("  ntile query [-n] [--max-line BYTES] [FILE|-]\n"
          "      Answer collision queries read from FILE (default: standard input). Cells\n"
          "      have size 1, y points down. Every line that is not blank or a # comment\n"
          "      gets one output line (-n, --line-numbers: led by \"N: \", its input line):\n"
          "        tile NAME aabb CX CY HW HH    -> DX DY   box out of tile NAME in cell (0,0)\n"
          "        tile NAME circle CX CY R      -> DX DY\n"
          "        map W H T1,T2,...             -> ok      W*H tile names or ids, row-major\n"
          "        resolve aabb CX CY HW HH      -> DX DY   push out of the current map\n"
          "        resolve circle CX CY R        -> DX DY\n"
          "        ray X0 Y0 X1 Y1               -> hit T NX NY | miss\n"
          "        pair SHAPE... SHAPE...        -> DX DY   first shape out of the second\n"
          "      Tile names match ignoring case. Numbers are printed in the shortest form that\n"
          "      reads back as the same float (or double). A bad line prints\n"
          "      \"error: line N: REASON\". Exit status: 0 every line was\n"
          "      answered, 1 some line failed, 2 usage or read error. Lines longer than\n"
          "      BYTES (default 256 MiB) are errors.\n",
          f);
}

int cli_query(int argc, char **argv)
{
    const char *path = NULL;
    size_t max_line = QUERY_DEFAULT_MAX_LINE;
    int options = 1, line_numbers = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (options && strcmp(a, "--") == 0) {
            options = 0;
        } else if (options && (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)) {
            printf("usage:\n");
            cli_query_usage(stdout);
            return CLI_OK;
        } else if (options && (strcmp(a, "-n") == 0 || strcmp(a, "--line-numbers") == 0)) {
            line_numbers = 1;
        } else if (options && strcmp(a, "--max-line") == 0) {
            char *end;
            unsigned long long v = i + 1 < argc ? strtoull(argv[i + 1], &end, 10) : 0;
            if (i + 1 >= argc || end == argv[i + 1] || *end || argv[i + 1][0] == '-' || v == 0 || v > SIZE_MAX / 4) {
                fprintf(stderr, "ntile query: --max-line needs a positive number of bytes\n");
                return CLI_USAGE;
            }
            max_line = (size_t)v;
            i++;
        } else if (options && a[0] == '-' && a[1] != '\0') {
            fprintf(stderr, "ntile query: unknown option '%s'\nusage:\n", a);
            cli_query_usage(stderr);
            return CLI_USAGE;
        } else if (path) {
            fprintf(stderr, "ntile query: more than one input file ('%s', '%s')\nusage:\n", path, a);
            cli_query_usage(stderr);
            return CLI_USAGE;
        } else {
            path = a;
        }
    }
    int fd = STDIN_FILENO;
    const char *label = "standard input";
    if (path && strcmp(path, "-") != 0) {
        fd = open(path, O_RDONLY);
        if (fd < 0) {
            fprintf(stderr, "ntile query: cannot open '%s': %s\n", path, strerror(errno));
            return CLI_USAGE;
        }
        label = path;
    }
    reader *r = malloc(sizeof *r);
    if (!r) {
        fprintf(stderr, "ntile query: out of memory\n");
        if (fd != STDIN_FILENO) close(fd);
        return CLI_USAGE;
    }
    r->fd = fd;
    r->mem = NULL;
    r->mem_left = 0;
    int status = query_run(r, stdout, max_line, label, line_numbers);
    if (fd != STDIN_FILENO) close(fd);
    free(r);
    return status;
}

int cli_query_buffer(const void *buf, size_t len, FILE *out, size_t max_line)
{
    reader *r = malloc(sizeof *r);
    if (!r) return CLI_USAGE;
    r->fd = -1;
    r->mem = (const unsigned char *)buf;
    r->mem_left = len;
    int status = query_run(r, out, max_line ? max_line : QUERY_DEFAULT_MAX_LINE, "the buffer", 0);
    free(r);
    return status;
}
