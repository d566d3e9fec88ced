/* tilegen [FILE]: write src/tile_tables.c (to FILE, or to standard output). */
#include <stdio.h>
#include "tilegen.h"

int main(int argc, char **argv)
{
    if (argc > 2) {
        fprintf(stderr, "usage: tilegen [FILE]\n");
        return 2;
    }
    FILE *out = argc == 2 ? fopen(argv[1], "w") : stdout;
    if (!out) {
        perror(argv[1]);
        return 1;
    }
    int bad = tilegen_write(out) != 0;
    if (argc == 2) bad |= fclose(out) != 0;
    else bad |= fflush(out) != 0;
    if (bad) fprintf(stderr, "tilegen: write error\n");
    return bad;
}
