/* ntile — base types, status codes, hooks.
 *
 * Every ntile header includes this one. It defines the scalar type `nt_real`
 * (float by default, double when the library and its users are compiled with
 * -DNT_DOUBLE), the 2D vector, the status codes every fallible call returns, and
 * the two process-wide hooks: the allocator and the assert handler.
 */
#ifndef NTILE_BASE_H
#define NTILE_BASE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define NT_VERSION_MAJOR 0
#define NT_VERSION_MINOR 2
#define NT_VERSION_PATCH 0

#ifdef NT_DOUBLE
typedef double nt_real;
#define NT_REAL_IS_DOUBLE 1
#else
typedef float nt_real;
#define NT_REAL_IS_DOUBLE 0
#endif

/// A 2D vector in world units. x grows to the right, y grows downwards.
typedef struct nt_vec2 {
    nt_real x, y;
} nt_vec2;

/// Status returned by every call that can fail. A call that fails leaves its
/// object unchanged.
typedef enum nt_status {
    NT_OK = 0,
    NT_ERR_INVALID_ARGUMENT = -1, ///< null pointer, negative size, unknown enum value
    NT_ERR_NON_FINITE = -2,       ///< NaN or infinity where a finite number is needed
    NT_ERR_SHAPE_TOO_LARGE = -3,  ///< half-size or radius above NT_MAX_HALF_CELLS (4) cells
    NT_ERR_OUT_OF_RANGE = -4,     ///< cell coordinate or tile id outside its range
    NT_ERR_OUT_OF_MEMORY = -5,    ///< the allocator returned NULL
    NT_ERR_INVALID_ID = -6,       ///< stale or never-issued handle
    NT_ERR_PARSE = -7,            ///< malformed text input
    NT_ERR_LIMIT = -8,            ///< a documented capacity limit was reached
    NT_ERR_LOCKED = -9            ///< the world is locked: called from inside one of its callbacks
} nt_status;

/// A short English description of a status code ("ok", "non-finite number", ...).
const char *nt_status_string(nt_status status);

/// Size in bytes of nt_real in the compiled library: lets a program check that it
/// was compiled with the same NT_DOUBLE setting as the library it links.
int nt_real_size(void);

/// The same check at link time (as Box2D renames a symbol per precision): the library
/// defines nt_real_float_library or nt_real_double_library, after the NT_DOUBLE it was
/// built with, and every file that includes this header refers to the one of its own
/// setting (GCC and Clang), so a program compiled with the other setting fails to link:
/// "undefined reference to `nt_real_double_library'" means the program was compiled
/// with -DNT_DOUBLE and the library without it (build it with make NT_DOUBLE=1).
#ifdef NT_DOUBLE
#define NT_REAL_LIBRARY nt_real_double_library
#else
#define NT_REAL_LIBRARY nt_real_float_library
#endif
extern const int NT_REAL_LIBRARY;
#if defined(__GNUC__)
static const int *const nt__real_library_check __attribute__((used)) = &NT_REAL_LIBRARY;
#endif

/// Allocation hook: returns size bytes or NULL. `user` is the pointer given to nt_set_allocator.
typedef void *nt_alloc_fn(size_t size, void *user);
/// Release hook for memory returned by nt_alloc_fn. Never called with NULL.
typedef void nt_free_fn(void *ptr, void *user);

/// Route every allocation of the library through these functions (NULL, NULL restores
/// malloc/free). Set it before creating any object; memory is freed through the hook
/// that allocated it only if the hook is not changed while objects are alive.
void nt_set_allocator(nt_alloc_fn *alloc_fn, nt_free_fn *free_fn, void *user);

/// Allocate size bytes through the allocation hook (NULL for size 0 or when it fails),
/// for layers built on ntile (the game layer) whose memory should obey the same hook.
void *nt_alloc(size_t size);

/// Release memory from nt_alloc (NULL is ignored).
void nt_free(void *ptr);

/// Assert hook: called when an internal consistency check fails. Return non-zero to
/// abort (the default), zero to carry on.
typedef int nt_assert_fn(const char *condition, const char *file, int line);

/// Replace the assert handler (NULL restores the default, which prints and aborts).
void nt_set_assert_fn(nt_assert_fn *fn);

/// Cosine and sine of one angle (see nt_compute_cos_sin).
typedef struct nt_cos_sin {
    double cosine, sine;
} nt_cos_sin;

/// Cosine and sine of `radians`, computed by ntile itself (as Box2D v3's b2ComputeCosSin)
/// with IEEE additions, multiplications and an exact fmod only: the same bits on every
/// compiler, libm and platform, where libm's sin and cos may differ in the last place.
/// Within 2e-16 of the true values for |radians| <= 1e6 (a Cody-Waite reduction by
/// pi/2 and fdlibm's minimax polynomials); beyond that the angle is first reduced
/// modulo the double nearest 2 pi. Non-finite input gives NaN for both.
nt_cos_sin nt_compute_cos_sin(double radians);

/// Construct a vector.
static inline nt_vec2 nt_v2(nt_real x, nt_real y)
{
    nt_vec2 v;
    v.x = x;
    v.y = y;
    return v;
}

#ifdef __cplusplus
}
#endif

#endif
