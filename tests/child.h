/* Running a program of the project from a test (the CLIs, the playground): the
 * fork/exec, output capture and crash checks the CLI tests share. */
#ifndef NTILE_TESTS_CHILD_H
#define NTILE_TESTS_CHILD_H

#include <stddef.h>

typedef struct child_result {
    int status; /* exit status; 128 + signal when killed */
    char *out;  /* standard output, NUL-terminated */
    char *err;  /* standard error */
    size_t out_len, err_len;
} child_result;

/* Run exe with args (NULL-terminated; args[0] is the first argument), standard input
 * from /dev/null, both outputs captured in unlinked files made in dir. setup (may be
 * NULL) runs in the child just before exec, with ctx (environment changes). The test
 * fails when the program could not be run, was killed, reported a sanitizer error, or
 * exited with bad_status or more. */
void child_run(child_result *r, const char *dir, const char *exe, const char *const *args, void (*setup)(void *ctx),
               void *ctx, int bad_status);
/* The same with standard input from stdin_path (/dev/null when NULL). */
void child_run_input(child_result *r, const char *dir, const char *exe, const char *const *args,
                     const char *stdin_path, void (*setup)(void *ctx), void *ctx, int bad_status);
void child_free(child_result *r);

/* The ntile CLI named by $NTILE (make test sets it); the running test is skipped,
 * with a message saying so, when it is not set. */
const char *child_ntile(void);

#endif
