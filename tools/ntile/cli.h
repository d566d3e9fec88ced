/* ntile CLI — what the subcommand files share.
 *
 * main.c dispatches `ntile SUBCOMMAND ARGS...` to one function per subcommand.
 * Each gets argv with argv[0] = the subcommand name and returns the process exit
 * status: 0 success, 1 the input had errors (query, convert) or a replay failed (run),
 * 2 usage error or I/O failure.
 */
#ifndef NTILE_CLI_H
#define NTILE_CLI_H

#include <stdio.h>

/* Exit statuses shared by every subcommand. */
enum { CLI_OK = 0, CLI_INPUT_ERRORS = 1, CLI_USAGE = 2 };

/* `ntile query [--max-line BYTES] [FILE|-]` (query.c); the usage functions print
 * that subcommand's part of the help text. */
int cli_query(int argc, char **argv);
/* The same protocol over a buffer (the fuzz harness): answers go to out; max_line 0
 * means the default limit. Returns the exit status. */
int cli_query_buffer(const void *buf, size_t len, FILE *out, size_t max_line);
void cli_query_usage(FILE *f);

/* `ntile soak [--steps N] [--bodies N]` (soak.c): the long-run checks. */
int cli_soak(int argc, char **argv);
void cli_soak_usage(FILE *f);

/* `ntile bench SCENE [OPTIONS]` (bench.c). */
int cli_bench(int argc, char **argv);
void cli_bench_usage(FILE *f);

/* `ntile run FILE.ntr...` and `ntile run --level FILE.ntl --ticks N ...` (run.c). */
int cli_run(int argc, char **argv);
void cli_run_usage(FILE *f);

/* `ntile convert n14 FILE [--index N] [-o OUT.ntl]` (convert.c). */
int cli_convert(int argc, char **argv);
void cli_convert_usage(FILE *f);

/* Whole files (run.c). "-" reads standard input. On failure `why` holds a message
 * and the functions return 0. Writing goes through a temporary file and a rename. */
int cli_read_file(const char *path, char **out, size_t *len, char *why, size_t why_cap);
int cli_write_file(const char *path, const char *data, size_t len, char *why, size_t why_cap);

/* `ntile sheet [-o FILE.svg]` (sheet.c): the gizmo answer key as SVG. */
int cli_sheet(int argc, char **argv);
void cli_sheet_usage(FILE *f);

#endif
