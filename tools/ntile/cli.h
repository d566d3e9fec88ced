/* ntile CLI — what the subcommand files share.
 *
 * main.c dispatches `ntile SUBCOMMAND ARGS...` to one function per subcommand.
 * Each gets argv with argv[0] = the subcommand name and returns the process exit
 * status: 0 success, 1 the input had errors (query), 2 usage error or I/O failure.
 */
#ifndef NTILE_CLI_H
#define NTILE_CLI_H

#include <stdio.h>

/* Exit statuses shared by every subcommand. */
enum { CLI_OK = 0, CLI_INPUT_ERRORS = 1, CLI_USAGE = 2 };

/* `ntile query [--max-line BYTES] [FILE|-]` (query.c); the usage functions print
 * that subcommand's part of the help text. */
int cli_query(int argc, char **argv);
void cli_query_usage(FILE *f);

/* `ntile bench SCENE [OPTIONS]` (bench.c). */
int cli_bench(int argc, char **argv);
void cli_bench_usage(FILE *f);

/* `ntile sheet [-o FILE.svg]` (sheet.c): the gizmo answer key as SVG. */
int cli_sheet(int argc, char **argv);
void cli_sheet_usage(FILE *f);

#endif
