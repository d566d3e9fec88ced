/* See scratch.h. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scratch.h"

static char g_dir[4096];
static int g_count;

static void remove_tree(const char *dir);

/* A test run stopped by a signal (a timeout, ^C) still removes its files. */
static void on_signal(int sig)
{
    remove_tree(g_dir);
    signal(sig, SIG_DFL);
    raise(sig);
}

int scratch_create(const char *tag)
{
    const char *tmp = getenv("TMPDIR");
    snprintf(g_dir, sizeof g_dir, "%s/ntile-test-%s-XXXXXX", tmp && *tmp ? tmp : "/tmp", tag);
    if (!mkdtemp(g_dir)) return -1;
    signal(SIGTERM, on_signal);
    signal(SIGINT, on_signal);
    signal(SIGHUP, on_signal);
    return 0;
}

static void remove_tree(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d) return;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
        char p[4400];
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        struct stat st;
        if (lstat(p, &st) == 0 && S_ISDIR(st.st_mode)) remove_tree(p);
        else unlink(p);
    }
    closedir(d);
    rmdir(dir);
}

void scratch_remove(void)
{
    signal(SIGTERM, SIG_DFL);
    signal(SIGINT, SIG_DFL);
    signal(SIGHUP, SIG_DFL);
    if (g_dir[0]) remove_tree(g_dir);
}

const char *scratch_dir(void) { return g_dir; }

const char *scratch_path(const char *name)
{
    static char buf[64][4400];
    static int k;
    char *p = buf[k++ % 64];
    snprintf(p, sizeof buf[0], "%s/%s", g_dir, name);
    return p;
}

void scratch_write(const char *name, const void *data, size_t len)
{
    const char *path = scratch_path(name);
    FILE *f = fopen(path, "wb");
    if (!f) fail_msg("cannot create %s: %s", path, strerror(errno));
    assert_int_equal(fwrite(data, 1, len, f), len);
    assert_int_equal(fclose(f), 0);
}

void scratch_write_text(const char *name, const char *text) { scratch_write(name, text, strlen(text)); }

const char *scratch_new(const void *data, size_t len)
{
    char name[32];
    snprintf(name, sizeof name, "f-%04d", g_count++);
    scratch_write(name, data, len);
    return scratch_path(name);
}

char *scratch_read(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f) fail_msg("cannot open %s: %s", path, strerror(errno));
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    assert_non_null(buf);
    for (;;) {
        if (n == cap) {
            cap *= 2;
            buf = realloc(buf, cap + 1);
            assert_non_null(buf);
        }
        size_t k = fread(buf + n, 1, cap - n, f);
        if (k == 0) break;
        n += k;
    }
    fclose(f);
    buf[n] = '\0';
    if (len) *len = n;
    return buf;
}
