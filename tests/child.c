/* See child.h. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "child.h"

/* The whole content of fd, from its start, NUL-terminated; its length in *len. */
static char *slurp(int fd, size_t *len)
{
    size_t cap = 4096, n = 0;
    char *buf = malloc(cap + 1);
    assert_non_null(buf);
    assert_int_equal(lseek(fd, 0, SEEK_SET), 0);
    for (;;) {
        if (n == cap) {
            cap *= 2;
            buf = realloc(buf, cap + 1);
            assert_non_null(buf);
        }
        ssize_t k = read(fd, buf + n, cap - n);
        assert_true(k >= 0);
        if (k == 0) break;
        n += (size_t)k;
    }
    buf[n] = '\0';
    *len = n;
    return buf;
}

/* An unlinked temporary file in dir. */
static int temp_fd(const char *dir)
{
    char p[4400];
    snprintf(p, sizeof p, "%s/io-XXXXXX", dir);
    int fd = mkstemp(p);
    assert_true(fd >= 0);
    unlink(p);
    return fd;
}

void child_run(child_result *r, const char *dir, const char *exe, const char *const *args, void (*setup)(void *ctx),
               void *ctx, int bad_status)
{
    child_run_input(r, dir, exe, args, NULL, setup, ctx, bad_status);
}

void child_run_input(child_result *r, const char *dir, const char *exe, const char *const *args,
                     const char *stdin_path, void (*setup)(void *ctx), void *ctx, int bad_status)
{
    const char *argv[96];
    size_t n = 0;
    argv[n++] = exe;
    for (; args[n - 1]; n++) {
        assert_true(n < 95);
        argv[n] = args[n - 1];
    }
    argv[n] = NULL;
    int out_fd = temp_fd(dir), err_fd = temp_fd(dir);
    fflush(NULL);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        int in_fd = open(stdin_path ? stdin_path : "/dev/null", O_RDONLY);
        if (in_fd < 0 || dup2(in_fd, 0) < 0 || dup2(out_fd, 1) < 0 || dup2(err_fd, 2) < 0) _exit(125);
        /* Under the sanitizers, a report must not pass for the program's own status. */
        setenv("ASAN_OPTIONS", "exitcode=99", 0);
        setenv("UBSAN_OPTIONS", "exitcode=99:print_stacktrace=1", 0);
        if (setup) setup(ctx);
        execv(exe, (char *const *)argv);
        _exit(126);
    }
    int ws;
    while (waitpid(pid, &ws, 0) < 0) assert_int_equal(errno, EINTR);
    r->status = WIFEXITED(ws) ? WEXITSTATUS(ws) : 128 + (WIFSIGNALED(ws) ? WTERMSIG(ws) : 0);
    if (r->status == 125) fail_msg("%s: could not redirect its input or output", exe);
    if (r->status == 126) fail_msg("could not run %s", exe);
    r->out = slurp(out_fd, &r->out_len);
    r->err = slurp(err_fd, &r->err_len);
    close(out_fd);
    close(err_fd);
    if (r->status >= bad_status || strstr(r->err, "Sanitizer") || strstr(r->err, "runtime error"))
        fail_msg("%s failed badly (status %d):\n%s", exe, r->status, r->err);
}

void child_free(child_result *r)
{
    free(r->out);
    free(r->err);
    r->out = r->err = NULL;
}

const char *child_ntile(void)
{
    const char *exe = getenv("NTILE");
    if (!exe || !*exe) {
        print_message("NTILE is not set: it must name the ntile CLI binary (make test sets it); skipping\n");
        skip();
    }
    return exe;
}
