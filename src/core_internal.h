/* The engine's internal helpers, for every source of src/: scalar arithmetic (the
 * precision guard, nt_real's limits, vector helpers), asserts, the allocator hook,
 * the tile tables' types (tile_tables.c) and the tile map's layout (map.c).
 * The world's internals are in simulation.h. Not installed. */
#ifndef NT_CORE_INTERNAL_H
#define NT_CORE_INTERNAL_H

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "ntile/ntile.h"

/* Same inputs, same bits: arithmetic in the precision of its type. x87 code (32-bit x86
 * without SSE) keeps excess precision and diverges from every other target's replays;
 * the Makefile builds 32-bit x86 with -msse2 -mfpmath=sse. */
#if defined(__FLT_EVAL_METHOD__) && __FLT_EVAL_METHOD__ != 0
#error "ntile needs FLT_EVAL_METHOD 0 (no excess precision): on 32-bit x86 build with -msse2 -mfpmath=sse"
#endif

/* Everything declared here is internal: hidden from libntile.so's exports, and
 * reached without a trip through the global offset table (the narrow phase's
 * tables are read on every call). */
#if defined(__GNUC__)
#pragma GCC visibility push(hidden)
#endif

/* Three strengths of assert, as in Chipmunk:
 *   NT_ASSERT_HARD  always checked: a broken invariant that would corrupt memory;
 *   NT_ASSERT       checked unless NDEBUG: a precondition the public API documents;
 *   NT_WARN         checked unless NDEBUG: prints, never stops. */
int nt__assert_fail(const char *cond, const char *file, int line);
void nt__warn(const char *cond, const char *file, int line);
#define NT_ASSERT_HARD(c) ((c) ? (void)0 : (nt__assert_fail(#c, __FILE__, __LINE__) ? abort() : (void)0))
#ifdef NDEBUG
#define NT_ASSERT(c) ((void)0)
#define NT_WARN(c) ((void)0)
#else
#define NT_ASSERT(c) NT_ASSERT_HARD(c)
#define NT_WARN(c) ((c) ? (void)0 : nt__warn(#c, __FILE__, __LINE__))
#endif

void *nt__alloc(size_t size);
void nt__free(void *ptr);

/* A velocity whose square overflows, at speed vmax (the step's speed limit, a
 * character's move). */
nt_vec2 nt__clamp_overflow(nt_vec2 v, nt_real vmax);

/* core.c: array growth through the allocator hook: returns the (possibly new) array
 * with room for `need` elements and the first `used` kept, or NULL (old array
 * untouched). */
void *nt__grow(void *old, int used, int *cap, int need, size_t elem);
/* Room for `need` elements in the array whose pointer is at arr_p (the first `used`
 * kept, *cap allocated), through nt__grow: false when out of memory, the array then
 * unchanged. The pointer is read and written with memcpy, so any T ** will do:
 *     if (!nt__reserve(&w->chars, w->char_count, &w->char_cap, n, sizeof *w->chars)) ... */
static inline bool nt__reserve(void *arr_p, int used, int *cap, int need, size_t elem)
{
    if (need <= *cap) return true;
    void *old;
    memcpy(&old, arr_p, sizeof old);
    void *p = nt__grow(old, used, cap, need, elem);
    if (!p) return false;
    memcpy(arr_p, &p, sizeof p);
    return true;
}

/* Keeps a rarely taken path out of its caller (a smaller hot loop). NT__PREFETCH:
 * asks for the cache line at p ahead of its use (a hint: no effect on results). */
#if defined(__GNUC__)
#define NT__NOINLINE __attribute__((noinline))
#define NT__PREFETCH(p) __builtin_prefetch(p)
#else
#define NT__NOINLINE
#define NT__PREFETCH(p) ((void)(p))
#endif
/* Inline although the compiler would not (a small function whose call, measured,
 * costs more than its body; say where it is used). */
#if defined(__GNUC__)
#define NT__INLINE __attribute__((always_inline)) inline
#else
#define NT__INLINE inline
#endif

#if NT_REAL_IS_DOUBLE
#define nt__sqrt sqrt
#define nt__fabs fabs
#define nt__floor floor
#define NT_REAL_MAX 1.7976931348623157e308
#define NT_REAL_EPS 2.220446049250313e-16
#else
#define nt__sqrt sqrtf
#define nt__fabs fabsf
#define nt__floor floorf
#define NT_REAL_MAX 3.40282347e38f
#define NT_REAL_EPS 1.1920929e-7f
#endif

static inline int nt__finite(nt_real x) { return isfinite(x); }
static inline nt_vec2 nt__add(nt_vec2 a, nt_vec2 b) { return nt_v2(a.x + b.x, a.y + b.y); }
static inline nt_vec2 nt__sub(nt_vec2 a, nt_vec2 b) { return nt_v2(a.x - b.x, a.y - b.y); }
static inline nt_vec2 nt__scale(nt_vec2 a, nt_real s) { return nt_v2(a.x * s, a.y * s); }
static inline nt_real nt__dot(nt_vec2 a, nt_vec2 b) { return a.x * b.x + a.y * b.y; }
static inline nt_real nt__len(nt_vec2 a) { return nt__sqrt(a.x * a.x + a.y * a.y); }
static inline nt_real nt__min(nt_real a, nt_real b) { return a < b ? a : b; }
static inline nt_real nt__max(nt_real a, nt_real b) { return a > b ? a : b; }
/* nt__max as the SSE max instruction, which is exactly that select (the second
 * operand when they are equal or either is NaN): for comparisons that go either way
 * at random (a contact's impulse clamped at 0), where a compiler may still branch.
 * Only the low lane counts: float operands are broadcast (one shuffle, where gcc
 * builds _mm_set_ss with two moves through a general register). */
#if NT_REAL_IS_DOUBLE && defined(__SSE2__)
#include <emmintrin.h>
static inline nt_real nt__max_sel(nt_real a, nt_real b) { return _mm_cvtsd_f64(_mm_max_sd(_mm_set_sd(a), _mm_set_sd(b))); }
#elif !NT_REAL_IS_DOUBLE && defined(__SSE__)
#include <xmmintrin.h>
static inline nt_real nt__max_sel(nt_real a, nt_real b) { return _mm_cvtss_f32(_mm_max_ss(_mm_set1_ps(a), _mm_set1_ps(b))); }
#else
static inline nt_real nt__max_sel(nt_real a, nt_real b) { return a > b ? a : b; }
#endif
/* lo <= hi. Two selects, each a single comparison, so compilers emit max/min
 * instructions instead of branches. */
static inline nt_real nt__clamp(nt_real v, nt_real lo, nt_real hi)
{
    v = v < lo ? lo : v;
    return v > hi ? hi : v;
}

/* --- tile tables (tile_tables.c, generated by tools/tilegen) --- */

/* One straight edge of a tile, unit cell coordinates. Inside/outside decisions use
 * the integer normal (ux, uy) and offset ud, exact for the tile's own vertices and
 * for dyadic inputs; distances scale by inv = 1 / |(ux, uy)|. */
typedef struct nt__edge {
    nt_real ux, uy, ud;   /* inside iff ux*x + uy*y < ud */
    nt_real inv;          /* 1 / |(ux, uy)| */
    nt_real nx, ny;       /* unit outward normal */
    nt_real ax, ay;       /* start point */
    nt_real tx, ty, len;  /* unit direction and length */
    int side;             /* the cell side it lies on (nt_side), or -1 */
} nt__edge;

typedef struct nt__tile_geom {
    int edge_count;       /* straight edges (round tiles: the two straight sides) */
    int has_slope;        /* polygon with one non-axis-aligned edge */
    nt_real slope[6];     /* its ux, uy, ud, inv, nx, ny */
    nt__edge edges[4];
} nt__tile_geom;

extern const nt_tile_info nt__tiles[NT_TILE_COUNT];
extern const nt__tile_geom nt__geom[NT_TILE_COUNT];
/* A polygon tile's face for the narrow phase. */
typedef struct nt__face {
    nt_real nx, ny;       /* unit outward normal */
    nt_real tx, ty;       /* unit direction, from end 0 to end 1 */
    nt_real vx[2], vy[2]; /* end 0 and end 1 (apart: paired, compilers load a
                           * point as one vector after storing its halves) */
} nt__face;

/* A polygon tile's faces (3 or 4, then unused ones), ordered for the narrow phase;
 * face i's separation is s = (ux[i]*x + uy[i]*y - ud[i]) * inv[i]. */
typedef struct nt__poly {
    nt_real ux[4], uy[4], ud[4], inv[4];
    nt__face face[4];
} nt__poly;

extern const nt__poly nt__polys[NT_TILE_COUNT];

/* --- narrow phase with side masks (narrow.c) ---
 * mask: bit (1 << side) set = that side of the tile is a seam with the neighbour,
 * so a push through it would only enter the neighbour's solid: it is not a way out.
 * Returns NT__SEPARATE, NT__PUSH (out set) or NT__MASKED (overlapping, but every
 * way out of this tile alone goes through a masked side). */
enum { NT__SEPARATE = 0, NT__PUSH = 1, NT__MASKED = 2 };
int nt__collide_tile_aabb_m(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out);
int nt__collide_tile_circle_m(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out);
/* The same for a tile id known to be valid (a map's cells), without checking it. */
int nt__collide_map_tile_aabb_m(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out);
int nt__collide_map_tile_circle_m(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out);
/* Distance from c to a CONCAVE tile's solid (0 inside): r minus it bounds a circle's
 * depth from below, without the search for the way out. */
nt_real nt__concave_gap(int tile, nt_vec2 c);

/* --- the tile map (map.c) --- */

typedef struct nt__cell {
    uint8_t tile;
    uint8_t edges;  /* nt_edge per side, 2 bits each: (edges >> (2 * side)) & 3 */
    uint8_t seams;  /* bit per side: this tile's face there is covered by the neighbour's */
    uint8_t walls;  /* bit per side: the neighbour's solid covers the whole shared edge */
} nt__cell;

struct nt_map {
    int w, h;
    nt_real cell, inv_cell;
    /* (nt_real)w + 2 and (nt_real)h + 2: nt__map_resolve's bound of "far outside". */
    nt_real far_w, far_h;
    nt__cell *cells;
    /* Bit per cell: the cell and its 8 neighbours are all EMPTY cells of the map, so
     * an object centred in it (at most half a cell) touches nothing. Small enough to
     * stay in L1 for big maps: the test every body in the air makes each step. */
    uint64_t *open3;
    /* Per cell, which of the 3 x 3 cells around it (bit 3 (dy + 1) + dx + 1) are not
     * EMPTY cells of the map: a body near tiles finds from it whether the cells its
     * box covers are all EMPTY without reading them. */
    uint16_t *near9;
    /* Per block of NT__BLOCK x NT__BLOCK cells (bw x bh blocks): how many of its cells
     * are EMPTY, and how many are not FULL. The escape searches skip what holds
     * nothing they look for, so their work is bounded in solid masses. */
    int bw, bh;
    uint8_t *blk_empty, *blk_open;
};
#define NT__BLOCK 8

/* Locking around user callbacks. The world is never a const object (it is allocated),
 * so a const query may count its lock. */
#define NT__LOCK(w) (((nt_world *)(w))->locked++)
#define NT__UNLOCK(w) (((nt_world *)(w))->locked--)
#define NT__CHECK_LOCK(w)                                                                                              \
    do {                                                                                                               \
        if ((w) && (w)->locked) return NT_ERR_LOCKED;                                                                  \
    } while (0)

/* (x, y) is a cell of the map: one unsigned comparison per axis (w, h > 0). */
static inline int nt__map_in(const nt_map *map, int x, int y)
{
    return (unsigned)x < (unsigned)map->w && (unsigned)y < (unsigned)map->h;
}

static inline int nt__map_open3(const nt_map *map, int x, int y)
{
    if (!nt__map_in(map, x, y)) return 0;
    size_t i = (size_t)y * (size_t)map->w + (size_t)x;
    return (int)((map->open3[i >> 6] >> (i & 63)) & 1u);
}

/* Cell data for any coordinate: cells outside the map are FULL border cells. */
nt__cell nt__map_cell(const nt_map *map, int x, int y);
/* nt_map_resolve for a shape nt_map_check_shape accepts (a body's: checked when it was
 * set), without checking it again; map and out not NULL, out always written (map.c). */
bool nt__map_resolve(const nt_map *map, nt_vec2 pos, const nt_shape *shape, nt_resolution *out);
/* nt_map_overlap_depth(map, pos, shape) > limit, for limit >= 0 (map.c). */
int nt__map_depth_exceeds(const nt_map *map, nt_vec2 pos, const nt_shape *shape, nt_real limit); /* shape by pointer: no struct in registers */
/* An object of at most half a cell gliding along flat surfaces it touched last step:
 * true when every tile it overlaps at pos pushes it along n (within 0.999) by a depth
 * in [lo, hi] (world units), *out the deepest such contact (map.c). */
bool nt__map_glides(const nt_map *map, nt_vec2 pos, const nt_shape *shape, nt_vec2 n, nt_real lo, nt_real hi,
                    nt_tile_contact *out);

static inline int nt__map_tile(const nt_map *map, int x, int y)
{
    if (!nt__map_in(map, x, y)) return NT_TILE_FULL;
    return map->cells[(size_t)y * (size_t)map->w + (size_t)x].tile;
}

/* Index of the lowest set bit (bits != 0). */
static inline int nt__ctz64(uint64_t bits)
{
#if defined(__GNUC__)
    return __builtin_ctzll(bits);
#else
    int n = 0;
    while (!(bits & 1)) bits >>= 1, n++;
    return n;
#endif
}

/* floor(v) as an int, clamped to +-1e9 (NaN: -1e9), without a libm call: baseline
 * x86-64 has no rounding instruction, and this runs for every cell range. Maps lie at
 * non-negative coordinates, where truncation is the floor: that case first (1e9 is
 * exact in float and double). */
static inline int nt__floor_int(nt_real v)
{
    if (v >= 0 && v < (nt_real)1e9) return (int)v;
    if (v < 0 && v > (nt_real)-1e9) {
        int i = (int)v;
        return i - ((nt_real)i > v);
    }
    return v >= (nt_real)1e9 ? 1000000000 : -1000000000;
}

#if defined(__GNUC__)
#pragma GCC visibility pop
#endif

#endif /* NT_CORE_INTERNAL_H */
