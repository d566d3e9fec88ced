/* ntile convert — level conversions.
 *
 *   ntile convert tiled MAP.tmj|MAP.tmx [-o OUT.ntl]
 *       Convert a Tiled map (JSON or XML; external tilesets are read relative to
 *       the map) to .ntl (tools/tiled/, README "Importing Tiled maps"). Warnings
 *       go to standard error.
 *
 *   ntile convert n14 FILE [--index N] [-o OUT.ntl]
 *       Convert the N-th N v1.4 level string of FILE (default the first; one level
 *       per line) to .ntl, written to OUT.ntl or standard output. Objects ntile does
 *       not support are skipped with a warning on standard error.
 *   ntile convert n14 FILE --list
 *       List the levels of FILE: index and name.
 *
 * Exit status: 0 converted, 1 the input is not a valid N level (message
 * "FILE:LINE:COL: ..." on standard error), 2 usage error or I/O failure. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../tiled/tiled.h"
#include "cli.h"
#include "ntile/ntile.h"

void cli_convert_usage(FILE *f)
{
    fputs("  ntile convert n14 FILE [--index N] [-o OUT.ntl]\n"
          "      Convert an N v1.4 level string ($NAME#AUTHOR##TILES|OBJECTS#, one level a\n"
          "      line; --index picks the N-th, default 1) to .ntl on standard output or\n"
          "      OUT.ntl. Unsupported objects are skipped with a warning on stderr.\n"
          "  ntile convert n14 FILE --list\n"
          "      List the levels in FILE (index and name).\n"
          "  ntile convert tiled MAP.tmj|MAP.tmx [-o OUT.ntl]\n"
          "      Convert a Tiled map (orthogonal, square tiles; tile property 'ntile' names\n"
          "      the N tile) to .ntl on standard output or OUT.ntl. Warnings on stderr.\n",
          f);
}

static int usage_error(const char *fmt, const char *arg)
{
    fprintf(stderr, "ntile convert: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\nusage:\n");
    cli_convert_usage(stderr);
    return CLI_USAGE;
}

static void on_warning(const char *message, void *context)
{
    int *count = context;
    ++*count;
    fprintf(stderr, "%s\n", message);
}

static int list_levels(const char *path, const char *text, size_t len)
{
    int count = 0;
    nt_level *lv = NULL;
    nt_text_error e;
    if (nt_level_import_n14(path, text, len, 0, &lv, &count, &e, NULL, NULL) != NT_OK && count == 0) {
        fprintf(stderr, "%s\n", e.message);
        return CLI_INPUT_ERRORS;
    }
    nt_level_destroy(lv);
    int status = CLI_OK;
    for (int i = 0; i < count; i++) {
        if (nt_level_import_n14(path, text, len, i, &lv, NULL, &e, NULL, NULL) != NT_OK) {
            printf("%d\t(invalid: %s)\n", i + 1, e.message);
            status = CLI_INPUT_ERRORS;
            continue;
        }
        printf("%d\t%s\n", i + 1, lv->title);
        nt_level_destroy(lv);
    }
    return status;
}

/* Write the canonical text of lv to `out` (or standard output); frees nothing. */
static int write_level(const nt_level *lv, const char *out)
{
    char why[600];
    size_t n = nt_level_write(lv, NULL, 0);
    char *buf = malloc(n + 1);
    int status = CLI_OK;
    if (!buf) {
        fprintf(stderr, "ntile convert: out of memory\n");
        status = CLI_USAGE;
    } else {
        nt_level_write(lv, buf, n + 1);
        if (out) {
            if (!cli_write_file(out, buf, n, why, sizeof why)) {
                fprintf(stderr, "ntile convert: %s\n", why);
                status = CLI_USAGE;
            }
        } else if (fwrite(buf, 1, n, stdout) != n || fflush(stdout) != 0) {
            fprintf(stderr, "ntile convert: error writing the output\n");
            status = CLI_USAGE;
        }
    }
    free(buf);
    return status;
}

/* The arguments after the format: the input, -o, and for n14 --index and --list. */
typedef struct convert_args {
    const char *in, *out;
    long index; /* from 1 */
    int list;
} convert_args;

static int parse_args(int argc, char **argv, int n14, convert_args *a)
{
    a->in = a->out = NULL;
    a->index = 1;
    a->list = 0;
    for (int i = 2; i < argc; i++) {
        const char *arg = argv[i];
        if (strcmp(arg, "-o") == 0 || strcmp(arg, "--output") == 0) {
            if (i + 1 >= argc) return usage_error("%s needs a file name", arg);
            a->out = argv[++i];
        } else if (n14 && strcmp(arg, "--index") == 0) {
            char *end;
            if (i + 1 >= argc) return usage_error("%s needs a number", arg);
            errno = 0;
            a->index = strtol(argv[++i], &end, 10);
            if (end == argv[i] || *end || errno || a->index < 1 || a->index > 1000000000)
                return usage_error("--index needs a level number from 1, got '%s'", argv[i]);
        } else if (n14 && strcmp(arg, "--list") == 0) {
            a->list = 1;
        } else if (arg[0] == '-' && arg[1] != '\0') {
            return usage_error("unknown option '%s'", arg);
        } else if (a->in) {
            return usage_error("more than one input file ('%s')", arg);
        } else {
            a->in = arg;
        }
    }
    if (!a->in) return usage_error("%s", n14 ? "missing the input FILE" : "missing the input MAP.tmj or MAP.tmx");
    if (!n14 && strcmp(a->in, "-") == 0)
        return usage_error("%s", "a Tiled map is read from a file (its tilesets are found beside it), not '-'");
    return CLI_OK;
}

static int read_input(const char *in, char **text, size_t *len)
{
    char why[600];
    if (cli_read_file(in, text, len, why, sizeof why)) return CLI_OK;
    fprintf(stderr, "ntile convert: %s\n", why);
    return CLI_USAGE;
}

int cli_convert(int argc, char **argv)
{
    if (argc >= 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        printf("usage:\n");
        cli_convert_usage(stdout);
        return CLI_OK;
    }
    if (argc < 2) return usage_error("%s", "missing the format (n14 or tiled)");
    int n14 = strcmp(argv[1], "n14") == 0;
    if (!n14 && strcmp(argv[1], "tiled") != 0)
        return usage_error("unknown format '%s' (this ntile converts n14 and tiled)", argv[1]);
    for (int i = 2; i < argc; i++)
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            printf("usage:\n");
            cli_convert_usage(stdout);
            return CLI_OK;
        }
    convert_args a;
    char *text;
    size_t len;
    int st = parse_args(argc, argv, n14, &a);
    if (st == CLI_OK) st = read_input(a.in, &text, &len);
    if (st != CLI_OK) return st;
    if (a.list) {
        st = list_levels(a.in, text, len);
        free(text);
        return st;
    }
    nt_level *lv = NULL;
    nt_text_error e;
    int count = 0, warnings = 0;
    nt_status s = n14 ? nt_level_import_n14(a.in, text, len, (int)(a.index - 1), &lv, &count, &e, on_warning, &warnings)
                      : tiled_import(a.in, text, len, &lv, &e, on_warning, &warnings);
    free(text);
    if (s != NT_OK) {
        fprintf(stderr, "%s\n", e.message);
        return CLI_INPUT_ERRORS;
    }
    if (n14 && count > 1 && a.index == 1)
        fprintf(stderr, "ntile convert: %s holds %d levels; converted the first (choose one with --index N)\n", a.in,
                count);
    st = write_level(lv, a.out);
    nt_level_destroy(lv);
    return st;
}
