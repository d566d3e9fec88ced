/* An allocator hook for out-of-memory tests: it fails every allocation after a
 * budget and counts the blocks still allocated, so a test can check that a failed
 * call left nothing behind. */
#ifndef NTILE_TEST_FAILALLOC_H
#define NTILE_TEST_FAILALLOC_H

/* Route the library's allocations through the hook: the first `budget` succeed,
 * the rest fail (budget < 0: none fail). Resets the count of live blocks. */
void failalloc_begin(long budget);

/* Restore malloc/free; returns how many blocks allocated through the hook are
 * still live. */
long failalloc_end(void);

#endif
