/* Internal helpers for the text formats (.ntl levels, .ntr replays, N v1.4 import):
 * a line reader with positions, field splitting, strict number parsing, error
 * messages "NAME:LINE:COL: ...", and an output sink for the canonical writers.
 * Not installed. */
#ifndef NT_TEXT_H
#define NT_TEXT_H

#include <stdarg.h>
#include "core_internal.h"
#include "ntile/level.h"

/* Most fields on one line (a path with 64 waypoints needs about 140). */
#define NT__MAX_FIELDS 256

typedef struct nt__field {
    const char *s; /* not NUL-terminated */
    size_t n;
    int col;       /* 1-based */
} nt__field;

typedef struct nt__text {
    const char *name;
    const char *buf;
    size_t len;
    size_t next;       /* offset of the next line */
    int line;          /* number of the current line (0 before the first) */
    const char *ls;    /* the current line, without its end (LF or CR LF) */
    size_t ll;
    nt__field f[NT__MAX_FIELDS];
    int nf;
    nt_text_error *err;
} nt__text;

void nt__text_init(nt__text *t, const char *name, const char *buf, size_t len, nt_text_error *err);

/* Next line: 1 read, 0 end of input, -1 error (a NUL byte; message set). */
int nt__text_next_line(nt__text *t);

/* Split the current line into fields: blanks separate them, a field starting with
 * '#' ends the line, "..." is one field (quotes kept). 0 on error (message set). */
int nt__text_split(nt__text *t);

/* Column just after the current line's last byte (for "missing ..." messages). */
int nt__text_eol_col(const nt__text *t);

/* Position of the end of the input: line and column where more text was expected. */
void nt__text_eof_pos(const nt__text *t, int *line, int *col);

/* Set the error message; always returns NT_ERR_PARSE. */
nt_status nt__fail(nt__text *t, int line, int col, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
/* The same at column `col` of the current line. */
nt_status nt__fail_col(nt__text *t, int col, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
void nt__error_set(nt_text_error *err, const char *name, int line, int col, const char *fmt, va_list ap);
/* An error without position ("NAME: message"). */
nt_status nt__error_plain(nt_text_error *err, nt_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* A field made printable for a message: quotes kept, control bytes as \xNN, long
 * fields cut with "...". buf must hold NT__QUOTE_MAX bytes. */
#define NT__QUOTE_MAX 72
const char *nt__quote(char *buf, const char *s, size_t n);

int nt__field_is(const nt__field *f, const char *word);

/* Numbers. A real is [+-]digits[.digits][e[+-]digits] (or .digits); 'inf' and 'nan'
 * are recognised to be rejected as non-finite. Each returns NT_OK or the error. */
nt_status nt__field_real(nt__text *t, const nt__field *f, const char *what, nt_real *out);
/* The same number kept as a double (replay fact values). */
nt_status nt__field_double(nt__text *t, const nt__field *f, const char *what, double *out);
nt_status nt__field_int(nt__text *t, const nt__field *f, const char *what, long long lo, long long hi, long long *out);
/* An unsigned 32-bit value, decimal or 0x hex. */
nt_status nt__field_u32(nt__text *t, const nt__field *f, const char *what, uint32_t *out);
/* 0x followed by exactly `digits` hex digits (hash values). */
nt_status nt__field_hex(nt__text *t, const nt__field *f, const char *what, int digits, uint64_t *out);
/* A name: a letter or '_', then letters, digits, '_', '-', '.'; shorter than NT_LEVEL_NAME_MAX. */
nt_status nt__field_name(nt__text *t, const nt__field *f, const char *what, char *out);
/* A "quoted" string (no '"' or '\\' inside) shorter than cap, or a bare word when bare_ok. */
nt_status nt__field_string(nt__text *t, const nt__field *f, const char *what, char *out, size_t cap, int bare_ok);

/* Read the first line, which must be exactly "MAGIC VERSION". */
nt_status nt__read_header(nt__text *t, const char *magic, int version);

/* The next line that holds fields, split (blank and comment-only lines skipped):
 * 1 read (t->nf > 0), 0 end of input, -1 error (message set). */
int nt__text_next_fields(nt__text *t);

/* Make room for one more item in *arr (count used, *cap allocated, doubling from 8).
 * 0 when out of memory (the array is unchanged). */
int nt__grow_array(void **arr, int count, int *cap, size_t size);

/* Exactly n fields on the line, or a message naming the expected form. */
nt_status nt__expect_fields(nt__text *t, int n, const char *form);

/* A string is a valid name / quoted text. */
int nt__valid_name(const char *s); /* s: a name field of NT_LEVEL_NAME_MAX bytes */
int nt__valid_text(const char *s, size_t cap);

/* ---- output ---- */

typedef struct nt__sink {
    char *buf;
    size_t cap;
    size_t len; /* full length, even beyond cap */
} nt__sink;

void nt__sink_init(nt__sink *s, char *buf, size_t cap);
void nt__sink_put(nt__sink *s, const char *p, size_t n);
void nt__sink_puts(nt__sink *s, const char *p);
void nt__sink_printf(nt__sink *s, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* The shortest decimal that reads back as the same nt_real. */
void nt__sink_real(nt__sink *s, nt_real v);
/* NUL-terminate and return the full length. */
size_t nt__sink_finish(nt__sink *s);
/* The first line of a canonical text, "MAGIC VERSION" (read back by nt__read_header). */
void nt__sink_header(nt__sink *s, const char *magic, int version);

/* Shortest round-trip decimal of v into buf (at least 32 bytes). */
void nt__format_real(char *buf, nt_real v);
void nt__sink_double(nt__sink *s, double v);

#endif
