/* ntile — headless command-line tool: the query protocol, benchmarks, replays and
 * level conversion.
 *
 *   ntile query [FILE]     answer collision queries, one output line per input line
 *   ntile bench SCENE      time a part of the engine
 *   ntile run FILE.ntr...  replay levels headless and check their expectations
 *   ntile convert n14 FILE convert an N v1.4 level to .ntl
 *   ntile convert tiled MAP  convert a Tiled map (.tmx, .tmj) to .ntl
 *   ntile sheet [-o FILE]  the answer-key sheet (SVG)
 *   ntile help             this text (no arguments: the same on stderr, exit 2)
 */
#include <stdio.h>
#include <string.h>
#include "cli.h"
#include "ntile/ntile.h"

static void usage(FILE *f)
{
    fprintf(f, "ntile %d.%d.%d (%s) - headless tool for the ntile collision engine\n\n", NT_VERSION_MAJOR,
            NT_VERSION_MINOR, NT_VERSION_PATCH, NT_REAL_IS_DOUBLE ? "double" : "float");
    fputs("usage: ntile SUBCOMMAND [ARGS...]\n\n", f);
    cli_query_usage(f);
    cli_bench_usage(f);
    cli_soak_usage(f);
    cli_run_usage(f);
    cli_convert_usage(f);
    cli_sheet_usage(f);
    fputs("  ntile help\n      This text (also --help or -h; with no arguments it goes to stderr, exit 2).\n"
          "  ntile SUBCOMMAND --help\n      The usage of one subcommand (exit 0).\n", f);
}

int main(int argc, char **argv)
{
    if (argc < 2) { /* no subcommand: a usage error */
        usage(stderr);
        return CLI_USAGE;
    }
    if (strcmp(argv[1], "help") == 0 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        usage(stdout);
        return CLI_OK;
    }
    if (nt_real_size() != (int)sizeof(nt_real)) {
        fprintf(stderr, "ntile: built against a library with a different scalar type (NT_DOUBLE mismatch)\n");
        return CLI_USAGE;
    }
    if (strcmp(argv[1], "query") == 0) return cli_query(argc - 1, argv + 1);
    if (strcmp(argv[1], "bench") == 0) return cli_bench(argc - 1, argv + 1);
    if (strcmp(argv[1], "soak") == 0) return cli_soak(argc - 1, argv + 1);
    if (strcmp(argv[1], "run") == 0) return cli_run(argc - 1, argv + 1);
    if (strcmp(argv[1], "convert") == 0) return cli_convert(argc - 1, argv + 1);
    if (strcmp(argv[1], "sheet") == 0) return cli_sheet(argc - 1, argv + 1);
    fprintf(stderr, "ntile: unknown subcommand '%s'\n\n", argv[1]);
    usage(stderr);
    return CLI_USAGE;
}
