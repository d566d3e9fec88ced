/* A private scratch directory for a test program: the files its tests write, and
 * reading files back. Shared by the tests that run the CLIs and the importers. */
#ifndef NTILE_TESTS_SCRATCH_H
#define NTILE_TESTS_SCRATCH_H

#include <stddef.h>

/* Make $TMPDIR/ntile-test-TAG-XXXXXX (/tmp without TMPDIR). 0 on success, -1 when
 * it cannot be made: the value a cmocka group setup returns. Until scratch_remove,
 * SIGTERM, SIGINT and SIGHUP remove the directory before the program dies. */
int scratch_create(const char *tag);
/* Remove the directory and everything in it (subdirectories included). */
void scratch_remove(void);
/* The directory. */
const char *scratch_dir(void);
/* DIR/name, in one of 64 buffers used in turn (so a few may be live at once). */
const char *scratch_path(const char *name);
/* Write a file in the directory; the test fails when it cannot. */
void scratch_write(const char *name, const void *data, size_t len);
void scratch_write_text(const char *name, const char *text);
/* A new file of its own (f-0000, f-0001, ...) holding data; returns its path. */
const char *scratch_new(const void *data, size_t len);
/* A whole file, NUL-terminated, from malloc (len may be NULL); the test fails when
 * it cannot be read. */
char *scratch_read(const char *path, size_t *len);

#endif
