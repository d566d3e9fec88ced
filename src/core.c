/* Status strings, the allocator hook and the assert hook. */
#include <stdio.h>
#include <stdlib.h>
#include "core.h"

#define CAP_TEXT_(n) #n
#define CAP_TEXT(n) CAP_TEXT_(n)

const char *nt_status_string(nt_status status)
{
    switch (status) {
    case NT_OK: return "ok";
    case NT_ERR_INVALID_ARGUMENT: return "invalid argument";
    case NT_ERR_NON_FINITE: return "non-finite number";
    case NT_ERR_SHAPE_TOO_LARGE: return "shape larger than the largest half-size (" CAP_TEXT(NT_MAX_HALF_CELLS) " cells)";
    case NT_ERR_OUT_OF_RANGE: return "out of range";
    case NT_ERR_OUT_OF_MEMORY: return "out of memory";
    case NT_ERR_INVALID_ID: return "invalid or stale id";
    case NT_ERR_PARSE: return "parse error";
    case NT_ERR_LIMIT: return "limit reached";
    case NT_ERR_LOCKED: return "world locked (called from inside a callback)";
    }
    return "unknown status";
}

int nt_real_size(void) { return (int)sizeof(nt_real); }

static void *default_alloc(size_t size, void *user) { (void)user; return malloc(size); }
static void default_free(void *ptr, void *user) { (void)user; free(ptr); }

static nt_alloc_fn *g_alloc = default_alloc;
static nt_free_fn *g_free = default_free;
static void *g_alloc_user = NULL;

void nt_set_allocator(nt_alloc_fn *alloc_fn, nt_free_fn *free_fn, void *user)
{
    if (alloc_fn && free_fn) {
        g_alloc = alloc_fn;
        g_free = free_fn;
        g_alloc_user = user;
    } else {
        g_alloc = default_alloc;
        g_free = default_free;
        g_alloc_user = NULL;
    }
}

void *nt__alloc(size_t size) { return size ? g_alloc(size, g_alloc_user) : NULL; }
void nt__free(void *ptr)
{
    if (ptr) g_free(ptr, g_alloc_user);
}

void *nt_alloc(size_t size) { return nt__alloc(size); }
void nt_free(void *ptr) { nt__free(ptr); }

static int default_assert(const char *cond, const char *file, int line)
{
    fprintf(stderr, "ntile: assertion failed: %s (%s:%d)\n", cond, file, line);
    return 1;
}

static nt_assert_fn *g_assert = default_assert;

void nt_set_assert_fn(nt_assert_fn *fn) { g_assert = fn ? fn : default_assert; }

int nt__assert_fail(const char *cond, const char *file, int line) { return g_assert(cond, file, line); }

void nt__warn(const char *cond, const char *file, int line)
{
    fprintf(stderr, "ntile: warning: %s (%s:%d)\n", cond, file, line);
}

/* A velocity whose squared length overflows (huge gravity times a huge gravity
 * scale, say): keep its direction at speed vmax; NaN parts become 0. */
nt_vec2 nt__clamp_overflow(nt_vec2 v, nt_real vmax)
{
    nt_real x = v.x == v.x ? v.x : 0, y = v.y == v.y ? v.y : 0;
    if (nt__fabs(x) > NT_REAL_MAX || nt__fabs(y) > NT_REAL_MAX) { /* an infinity: its sign is the direction */
        x = nt__fabs(x) > NT_REAL_MAX ? (x > 0 ? R(1) : R(-1)) : 0;
        y = nt__fabs(y) > NT_REAL_MAX ? (y > 0 ? R(1) : R(-1)) : 0;
    }
    nt_real m = nt__max(nt__fabs(x), nt__fabs(y));
    if (m == 0) return nt_v2(0, 0);
    x /= m;
    y /= m;
    nt_real l = nt__sqrt(x * x + y * y);
    return nt_v2(x / l * vmax, y / l * vmax);
}
