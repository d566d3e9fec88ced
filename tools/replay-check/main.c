/* replay-check: run replays and check their recorded hashes, with nothing but the
 * engine, the game layer and libc (no Tiled libraries, no cmocka): the program
 * `make determinism` builds for targets where only a C compiler and libc exist, such
 * as 32-bit x86 through gcc-multilib.
 *
 *   replay-check FILE.ntr...    exit 0 when every replay passes, 1 otherwise */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../common/stream.h"
#include "ntile/game.h"
#include "ntile/level.h"
#include "ntile/replay.h"

static char *read_text(const char *path, size_t *len)
{
    char why[600];
    FILE *f = stream_open_regular(path, STREAM_MAX_FILE, why, sizeof why);
    if (!f) {
        fprintf(stderr, "replay-check: %s\n", why);
        return NULL;
    }
    char *text = NULL;
    int r = stream_read_all(f, STREAM_MAX_FILE, &text, len);
    fclose(f);
    if (r != STREAM_OK) fprintf(stderr, "replay-check: cannot read '%s'\n", path);
    return r == STREAM_OK ? text : NULL;
}

static int check(const char *path)
{
    size_t len;
    char *text = read_text(path, &len);
    if (!text) return 0;
    nt_replay *rp = NULL;
    nt_text_error e;
    int ok = 0;
    if (nt_replay_parse(path, text, len, &rp, &e) != NT_OK) {
        printf("not ok %s: %s\n", path, e.message);
        free(text);
        return 0;
    }
    free(text);
    /* The level, relative to the replay's directory. */
    const char *slash = strrchr(path, '/');
    size_t dir = rp->level[0] == '/' || !slash ? 0 : (size_t)(slash - path) + 1;
    char *lpath = malloc(dir + strlen(rp->level) + 1);
    nt_level *lv = NULL;
    if (lpath) {
        memcpy(lpath, path, dir);
        strcpy(lpath + dir, rp->level);
        char *lt = read_text(lpath, &len);
        if (lt && nt_level_parse(lpath, lt, len, &lv, &e) != NT_OK) printf("not ok %s: %s\n", path, e.message);
        free(lt);
    }
    if (lv) {
        nt_run_report rep;
        if (nt_run_replay(rp, lv, &rep) == NT_OK) {
            ok = rep.passed;
            printf("%s %s (%d ticks)\n", ok ? "ok    " : "not ok", path, rep.ticks);
            for (int i = 0; i < rep.message_count; i++) printf("    %s\n", rep.messages[i]);
            nt_run_report_free(&rep);
        } else {
            printf("not ok %s: could not run\n", path);
        }
    }
    nt_level_destroy(lv);
    free(lpath);
    nt_replay_destroy(rp);
    return ok;
}

int main(int argc, char **argv)
{
    int passed = 0, failed = 0;
    for (int i = 1; i < argc; i++) check(argv[i]) ? passed++ : failed++;
    printf("%d passed, %d failed\n", passed, failed);
    return failed == 0 && passed > 0 ? 0 : 1;
}
