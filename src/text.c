/* Text helpers shared by the level, replay and N v1.4 parsers and the writers. */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include "text.h"

void nt__text_init(nt__text *t, const char *name, const char *buf, size_t len, nt_text_error *err)
{
    memset(t, 0, sizeof *t);
    t->name = name ? name : "(text)";
    t->buf = buf ? buf : "";
    t->len = buf ? len : 0;
    /* A UTF-8 byte order mark (as some editors save) is skipped: columns count from
     * after it, as editors show them. */
    if (t->len >= 3 && (unsigned char)t->buf[0] == 0xef && (unsigned char)t->buf[1] == 0xbb &&
        (unsigned char)t->buf[2] == 0xbf)
        t->next = 3;
    t->err = err;
    if (err) {
        err->line = 0;
        err->column = 0;
        err->message[0] = '\0';
    }
}

int nt__text_next_line(nt__text *t)
{
    if (t->next >= t->len) return 0;
    const char *start = t->buf + t->next;
    size_t avail = t->len - t->next;
    const char *nl = memchr(start, '\n', avail);
    size_t n = nl ? (size_t)(nl - start) : avail;
    t->next += nl ? n + 1 : n;
    t->line++;
    t->ls = start;
    t->ll = n;
    if (n > 0 && start[n - 1] == '\r') t->ll--;
    t->nf = 0;
    const char *nul = memchr(start, '\0', t->ll);
    if (nul) {
        nt__fail_col(t, (int)(nul - start) + 1, "NUL byte in the text");
        return -1;
    }
    return 1;
}

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

int nt__text_split(nt__text *t)
{
    size_t i = 0;
    t->nf = 0;
    for (;;) {
        while (i < t->ll && is_blank(t->ls[i])) i++;
        if (i >= t->ll || t->ls[i] == '#') return 1;
        if (t->nf == NT__MAX_FIELDS) {
            nt__fail_col(t, (int)i + 1, "too many fields on one line (at most %d)", NT__MAX_FIELDS);
            return 0;
        }
        size_t start = i;
        if (t->ls[i] == '"') {
            const char *close = memchr(t->ls + i + 1, '"', t->ll - i - 1);
            if (!close) {
                nt__fail_col(t, (int)start + 1, "unterminated string (no closing '\"' on this line)");
                return 0;
            }
            i = (size_t)(close - t->ls) + 1;
            if (i < t->ll && !is_blank(t->ls[i])) {
                nt__fail_col(t, (int)i + 1, "text right after a closing quote");
                return 0;
            }
        } else {
            while (i < t->ll && !is_blank(t->ls[i])) i++;
        }
        nt__field *f = &t->f[t->nf++];
        f->s = t->ls + start;
        f->n = i - start;
        f->col = (int)start + 1;
    }
}

int nt__text_eol_col(const nt__text *t)
{
    size_t n = t->ll;
    while (n > 0 && is_blank(t->ls[n - 1])) n--;
    /* Point after the last field, before any trailing comment. */
    if (t->nf > 0) {
        const nt__field *f = &t->f[t->nf - 1];
        return f->col + (int)f->n;
    }
    return (int)n + 1;
}

void nt__text_eof_pos(const nt__text *t, int *line, int *col)
{
    if (t->len == 0) {
        *line = 1;
        *col = 1;
    } else if (t->buf[t->len - 1] == '\n') {
        *line = t->line + 1;
        *col = 1;
    } else {
        *line = t->line;
        *col = (int)t->ll + 1;
    }
}

void nt__error_set(nt_text_error *err, const char *name, int line, int col, const char *fmt, va_list ap)
{
    if (!err) return;
    err->line = line;
    err->column = col;
    int n;
    if (line > 0) n = snprintf(err->message, sizeof err->message, "%s:%d:%d: ", name, line, col);
    else n = snprintf(err->message, sizeof err->message, "%s: ", name);
    if (n < 0) n = 0;
    if ((size_t)n < sizeof err->message) vsnprintf(err->message + n, sizeof err->message - (size_t)n, fmt, ap);
}

nt_status nt__fail(nt__text *t, int line, int col, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    nt__error_set(t->err, t->name, line, col, fmt, ap);
    va_end(ap);
    return NT_ERR_PARSE;
}

nt_status nt__fail_col(nt__text *t, int col, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    nt__error_set(t->err, t->name, t->line, col, fmt, ap);
    va_end(ap);
    return NT_ERR_PARSE;
}

nt_status nt__error_plain(nt_text_error *err, nt_status status, const char *fmt, ...)
{
    if (!err) return status;
    va_list ap;
    va_start(ap, fmt);
    err->line = 0;
    err->column = 0;
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    return status;
}

const char *nt__quote(char *buf, const char *s, size_t n)
{
    size_t o = 0;
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        if (o + 8 > NT__QUOTE_MAX) {
            memcpy(buf + o, "...", 4);
            return buf;
        }
        if (c >= 0x20 && c < 0x7f && c != '\\') buf[o++] = (char)c;
        else o += (size_t)snprintf(buf + o, NT__QUOTE_MAX - o, "\\x%02x", c);
    }
    buf[o] = '\0';
    return buf;
}

int nt__field_is(const nt__field *f, const char *word)
{
    size_t n = strlen(word);
    return f->n == n && memcmp(f->s, word, n) == 0;
}

static int ieq(const char *s, size_t n, const char *word)
{
    if (strlen(word) != n) return 0;
    for (size_t i = 0; i < n; i++) {
        char c = s[i];
        if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
        if (c != word[i]) return 0;
    }
    return 1;
}

static int is_digit(char c) { return c >= '0' && c <= '9'; }

/* Strict decimal syntax: [+-] (digits [. digits*] | . digits) [(e|E) [+-] digits]. */
static int decimal_syntax(const char *s, size_t n)
{
    size_t i = 0, d = 0;
    if (i < n && (s[i] == '+' || s[i] == '-')) i++;
    while (i < n && is_digit(s[i])) i++, d++;
    if (i < n && s[i] == '.') {
        i++;
        while (i < n && is_digit(s[i])) i++, d++;
    }
    if (d == 0) return 0;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        if (i < n && (s[i] == '+' || s[i] == '-')) i++;
        size_t e = 0;
        while (i < n && is_digit(s[i])) i++, e++;
        if (e == 0) return 0;
    }
    return i == n;
}

nt_status nt__field_real(nt__text *t, const nt__field *f, const char *what, nt_real *out)
{
    double v;
    nt_status s = nt__field_double(t, f, what, &v);
    if (s != NT_OK) return s;
    nt_real r = (nt_real)v;
    if (!isfinite(r)) {
        char q[NT__QUOTE_MAX];
        return nt__fail_col(t, f->col, "%s '%s' is too large for %s", what, nt__quote(q, f->s, f->n),
                            NT_REAL_IS_DOUBLE ? "double" : "float");
    }
    *out = r;
    return NT_OK;
}

nt_status nt__field_double(nt__text *t, const nt__field *f, const char *what, double *out)
{
    char q[NT__QUOTE_MAX], buf[80];
    const char *s = f->s;
    size_t n = f->n, k = (n > 0 && (s[0] == '+' || s[0] == '-')) ? 1 : 0;
    if (ieq(s + k, n - k, "inf") || ieq(s + k, n - k, "infinity") || ieq(s + k, n - k, "nan"))
        return nt__fail_col(t, f->col, "%s '%s' is not a finite number", what, nt__quote(q, s, n));
    if (!decimal_syntax(s, n)) return nt__fail_col(t, f->col, "%s '%s' is not a number", what, nt__quote(q, s, n));
    if (n >= sizeof buf) return nt__fail_col(t, f->col, "%s '%s' is too long for a number", what, nt__quote(q, s, n));
    memcpy(buf, s, n);
    buf[n] = '\0';
    double v = strtod(buf, NULL);
    if (!isfinite(v)) return nt__fail_col(t, f->col, "%s '%s' is not a finite number", what, nt__quote(q, s, n));
    *out = v;
    return NT_OK;
}

nt_status nt__field_int(nt__text *t, const nt__field *f, const char *what, long long lo, long long hi, long long *out)
{
    char q[NT__QUOTE_MAX], buf[32];
    size_t i = 0;
    if (f->n > 0 && (f->s[0] == '+' || f->s[0] == '-')) i = 1;
    if (i == f->n) return nt__fail_col(t, f->col, "%s '%s' is not an integer", what, nt__quote(q, f->s, f->n));
    for (size_t k = i; k < f->n; k++)
        if (!is_digit(f->s[k])) return nt__fail_col(t, f->col, "%s '%s' is not an integer", what, nt__quote(q, f->s, f->n));
    long long v = 0;
    int range = f->n >= sizeof buf;
    if (!range) {
        memcpy(buf, f->s, f->n);
        buf[f->n] = '\0';
        errno = 0;
        v = strtoll(buf, NULL, 10);
        range = errno == ERANGE;
    }
    if (range || v < lo || v > hi)
        return nt__fail_col(t, f->col, "%s '%s' is out of range %lld..%lld", what, nt__quote(q, f->s, f->n), lo, hi);
    *out = v;
    return NT_OK;
}

static int hex_value(char c)
{
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

nt_status nt__field_u32(nt__text *t, const nt__field *f, const char *what, uint32_t *out)
{
    char q[NT__QUOTE_MAX];
    if (f->n > 2 && f->s[0] == '0' && (f->s[1] == 'x' || f->s[1] == 'X')) {
        uint64_t v = 0;
        if (f->n > 10) return nt__fail_col(t, f->col, "%s '%s' is out of range (32 bits)", what, nt__quote(q, f->s, f->n));
        for (size_t i = 2; i < f->n; i++) {
            int h = hex_value(f->s[i]);
            if (h < 0) return nt__fail_col(t, f->col, "%s '%s' is not a number", what, nt__quote(q, f->s, f->n));
            v = v * 16 + (uint64_t)h;
        }
        *out = (uint32_t)v;
        return NT_OK;
    }
    long long v;
    nt_status s = nt__field_int(t, f, what, 0, 0xffffffffLL, &v);
    if (s == NT_OK) *out = (uint32_t)v;
    return s;
}

nt_status nt__field_hex(nt__text *t, const nt__field *f, const char *what, int digits, uint64_t *out)
{
    char q[NT__QUOTE_MAX];
    size_t skip = (f->n >= 2 && f->s[0] == '0' && f->s[1] == 'x') ? 2 : 0;
    if (f->n != skip + (size_t)digits)
        return nt__fail_col(t, f->col, "%s '%s' must be %s%d hex digits", what, nt__quote(q, f->s, f->n),
                            skip ? "0x and " : "", digits);
    uint64_t v = 0;
    for (size_t i = skip; i < f->n; i++) {
        int h = hex_value(f->s[i]);
        if (h < 0) return nt__fail_col(t, f->col, "%s '%s' is not a hex number", what, nt__quote(q, f->s, f->n));
        v = v * 16 + (uint64_t)h;
    }
    *out = v;
    return NT_OK;
}

static int name_char(char c, int first)
{
    if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_') return 1;
    if (first) return 0;
    return is_digit(c) || c == '-' || c == '.';
}

static int valid_name_n(const char *s, size_t n)
{
    if (n == 0 || n >= NT_LEVEL_NAME_MAX) return 0;
    for (size_t i = 0; i < n; i++)
        if (!name_char(s[i], i == 0)) return 0;
    return 1;
}

/* s is a name field of NT_LEVEL_NAME_MAX bytes, filled by hand perhaps: it must hold
 * its terminator, and nothing past the field is read. */
int nt__valid_name(const char *s)
{
    const char *end = memchr(s, '\0', NT_LEVEL_NAME_MAX);
    return end && valid_name_n(s, (size_t)(end - s));
}

int nt__valid_text(const char *s, size_t cap)
{
    /* The terminator must lie within the field; nothing past it is read. */
    const char *end = memchr(s, '\0', cap);
    if (!end) return 0;
    size_t n = (size_t)(end - s);
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c < 0x20 || c == 0x7f || c == '"' || c == '\\') return 0;
    }
    return 1;
}

nt_status nt__field_name(nt__text *t, const nt__field *f, const char *what, char *out)
{
    char q[NT__QUOTE_MAX];
    if (!valid_name_n(f->s, f->n))
        return nt__fail_col(t, f->col,
                            "%s '%s' is not a valid name (a letter or '_', then letters, digits, '_', '-' or '.'; "
                            "at most %d characters)",
                            what, nt__quote(q, f->s, f->n), NT_LEVEL_NAME_MAX - 1);
    memcpy(out, f->s, f->n);
    out[f->n] = '\0';
    return NT_OK;
}

nt_status nt__field_string(nt__text *t, const nt__field *f, const char *what, char *out, size_t cap, int bare_ok)
{
    char q[NT__QUOTE_MAX];
    const char *s = f->s;
    size_t n = f->n;
    if (n >= 2 && s[0] == '"') {
        s++;
        n -= 2;
    } else if (!bare_ok) {
        return nt__fail_col(t, f->col, "%s must be a quoted string, got '%s'", what, nt__quote(q, f->s, f->n));
    }
    if (n >= cap) return nt__fail_col(t, f->col, "%s is longer than %zu bytes", what, cap - 1);
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)s[i];
        /* No escapes exist: a '"' could not be written back inside the quotes. */
        if (c < 0x20 || c == 0x7f || c == '\\' || c == '"')
            return nt__fail_col(t, f->col + (int)(s - f->s) + (int)i, "%s holds a control character, '\\' or '\"'",
                                what);
    }
    memcpy(out, s, n);
    out[n] = '\0';
    return NT_OK;
}

nt_status nt__read_header(nt__text *t, const char *magic, int version)
{
    int r = nt__text_next_line(t);
    if (r < 0) return NT_ERR_PARSE;
    if (r == 0) return nt__fail(t, 1, 1, "empty file: expected '%s %d' on the first line", magic, version);
    if (!nt__text_split(t)) return NT_ERR_PARSE;
    if (t->nf < 1 || !nt__field_is(&t->f[0], magic))
        return nt__fail_col(t, t->nf ? t->f[0].col : 1, "expected '%s %d' on the first line", magic, version);
    char form[64];
    snprintf(form, sizeof form, "%s VERSION", magic);
    nt_status s = nt__expect_fields(t, 2, form);
    if (s != NT_OK) return s;
    long long v;
    if ((s = nt__field_int(t, &t->f[1], "version", 0, 1000000, &v)) != NT_OK) return s;
    if (v != version)
        return nt__fail_col(t, t->f[1].col, "unsupported %s version %lld (this ntile reads version %d)", magic, v, version);
    return NT_OK;
}

int nt__text_next_fields(nt__text *t)
{
    for (;;) {
        int r = nt__text_next_line(t);
        if (r <= 0) return r;
        if (!nt__text_split(t)) return -1;
        if (t->nf > 0) return 1;
    }
}

void nt__sink_header(nt__sink *s, const char *magic, int version) { nt__sink_printf(s, "%s %d\n", magic, version); }

int nt__grow_array(void **arr, int count, int *cap, size_t size)
{
    if (count < *cap) return 1;
    int ncap = *cap ? *cap * 2 : 8;
    void *p = nt__alloc((size_t)ncap * size);
    if (!p) return 0;
    if (count > 0) memcpy(p, *arr, (size_t)count * size);
    nt__free(*arr);
    *arr = p;
    *cap = ncap;
    return 1;
}

nt_status nt__expect_fields(nt__text *t, int n, const char *form)
{
    if (t->nf == n) return NT_OK;
    if (t->nf < n) return nt__fail_col(t, nt__text_eol_col(t), "missing fields: expected '%s'", form);
    return nt__fail_col(t, t->f[n].col, "unexpected field: expected '%s'", form);
}

/* ---------------------------------------------------------------- output */

void nt__sink_init(nt__sink *s, char *buf, size_t cap)
{
    s->buf = buf;
    s->cap = buf ? cap : 0;
    s->len = 0;
    if (s->cap > 0) s->buf[0] = '\0';
}

void nt__sink_put(nt__sink *s, const char *p, size_t n)
{
    if (s->len < s->cap) {
        size_t room = s->cap - 1 - s->len; /* keep a byte for the NUL */
        size_t k = n < room ? n : room;
        memcpy(s->buf + s->len, p, k);
    }
    s->len += n;
}

void nt__sink_puts(nt__sink *s, const char *p) { nt__sink_put(s, p, strlen(p)); }

void nt__sink_printf(nt__sink *s, const char *fmt, ...)
{
    char small[256];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    va_end(ap);
    if (n < 0) return;
    if ((size_t)n < sizeof small) {
        nt__sink_put(s, small, (size_t)n);
        return;
    }
    char *big = (char *)nt__alloc((size_t)n + 1);
    if (!big) {
        s->len += (size_t)n; /* the length stays right; the text is cut */
        return;
    }
    va_start(ap, fmt);
    vsnprintf(big, (size_t)n + 1, fmt, ap);
    va_end(ap);
    nt__sink_put(s, big, (size_t)n);
    nt__free(big);
}

void nt__format_real(char *buf, nt_real v)
{
    double d = (double)v;
    /* Whole numbers print without an exponent (100, not 1e+02). */
    if (d == nt__floor(v) && fabs(d) < 1e15 && !(d == 0 && signbit(d))) {
        snprintf(buf, 32, "%.0f", d);
        return;
    }
    for (int p = 1; p <= 17; p++) {
        snprintf(buf, 32, "%.*g", p, d);
        nt_real back = (nt_real)strtod(buf, NULL);
        if (memcmp(&back, &v, sizeof v) == 0) return;
    }
}

void nt__sink_double(nt__sink *s, double v)
{
    char buf[40];
    if (v == floor(v) && fabs(v) < 1e15 && !(v == 0 && signbit(v))) {
        snprintf(buf, sizeof buf, "%.0f", v);
    } else {
        for (int p = 1; p <= 17; p++) {
            snprintf(buf, sizeof buf, "%.*g", p, v);
            if (strtod(buf, NULL) == v) break;
        }
    }
    nt__sink_puts(s, buf);
}

void nt__sink_real(nt__sink *s, nt_real v)
{
    char buf[32];
    nt__format_real(buf, v);
    nt__sink_puts(s, buf);
}

size_t nt__sink_finish(nt__sink *s)
{
    if (s->cap > 0) s->buf[s->len < s->cap ? s->len : s->cap - 1] = '\0';
    return s->len;
}
