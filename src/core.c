/* Status strings, the allocator hook and the assert hook. */
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include "core_internal.h"

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
/* nt_real_float_library or nt_real_double_library: what base.h makes every user refer to. */
const int NT_REAL_LIBRARY = (int)sizeof(nt_real);

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

/* ---------------------------------------------------------------- cosine and sine
 * fdlibm's kernels (Sun Microsystems, 1993: "Permission to use, copy, modify, and
 * distribute this software is freely granted, provided that this notice is
 * preserved"), on a reduced argument |r| <= pi/4 + a little, with a Cody-Waite
 * reduction by pi/2 in three parts: no fused operations (the build forbids
 * contraction), so the result is the same everywhere. */
static double kernel_sin(double x)
{
    const double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03, S3 = -1.98412698298579493134e-04,
                 S4 = 2.75573137070700676789e-06, S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
    double z = x * x, v = z * x;
    double r = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    return x + v * (S1 + z * r);
}

static double kernel_cos(double x)
{
    const double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03, C3 = 2.48015872894767294178e-05,
                 C4 = -2.75573143513906633035e-07, C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;
    double z = x * x;
    double r = z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    double hz = 0.5 * z, w = 1.0 - hz;
    return w + (((1.0 - w) - hz) + z * r);
}

nt_cos_sin nt_compute_cos_sin(double x)
{
    nt_cos_sin cs;
    if (!isfinite(x)) {
        cs.cosine = cs.sine = NAN;
        return cs;
    }
    if (fabs(x) > 1e6) x = fmod(x, 6.283185307179586); /* exact: the same everywhere */
    /* n = x / (pi/2) rounded to nearest (|n| < 2^20, so n * P1 is exact). */
    const double inv_pio2 = 6.36619772367581382433e-01, P1 = 1.57079632673412561417e+00,
                 P2 = 6.07710050630396597660e-11, P2T = 2.02226624879595063154e-21;
    double fn = x * inv_pio2;
    fn = fn >= 0 ? floor(fn + 0.5) : -floor(0.5 - fn);
    long n = (long)fn;
    double r = (x - fn * P1) - fn * P2;
    r = r - fn * P2T;
    double s = kernel_sin(r), c = kernel_cos(r);
    switch (n & 3) {
    case 0: cs.cosine = c, cs.sine = s; break;
    case 1: cs.cosine = -s, cs.sine = c; break;
    case 2: cs.cosine = -c, cs.sine = -s; break;
    default: cs.cosine = s, cs.sine = -c; break;
    }
    return cs;
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
        x = nt__fabs(x) > NT_REAL_MAX ? (x > 0 ? (nt_real)1 : (nt_real)-1) : 0;
        y = nt__fabs(y) > NT_REAL_MAX ? (y > 0 ? (nt_real)1 : (nt_real)-1) : 0;
    }
    nt_real m = nt__max(nt__fabs(x), nt__fabs(y));
    if (m == 0) return nt_v2(0, 0);
    x /= m;
    y /= m;
    nt_real l = nt__sqrt(x * x + y * y);
    return nt_v2(x / l * vmax, y / l * vmax);
}

void *nt__grow(void *old, int used, int *cap, int need, size_t elem)
{
    if (need <= *cap) return old;
    long long want = (long long)*cap * 2;
    if (want < need) want = need;
    if (want < 16) want = 16;
    if (want > 0x7fffffff) want = 0x7fffffff;
    if (want < need || (unsigned long long)want > (unsigned long long)(SIZE_MAX / elem)) return NULL;
    void *p = nt__alloc((size_t)want * elem);
    if (!p) return NULL;
    if (old && used > 0) memcpy(p, old, (size_t)used * elem);
    nt__free(old);
    *cap = (int)want;
    return p;
}
