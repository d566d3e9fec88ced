/* Internal helpers shared by the engine's sources. Not installed. */
#ifndef NT_CORE_H
#define NT_CORE_H

#include <math.h>
#include <stdlib.h>
#include "ntile/ntile.h"

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

#define R(x) ((nt_real)(x))

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
static inline nt_real nt__clamp(nt_real v, nt_real lo, nt_real hi) { return v < lo ? lo : (v > hi ? hi : v); }

/* --- tile tables (tiles.c) --- */

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

/* --- narrow phase with side masks (narrow.c) ---
 * mask: bit (1 << side) set = that side of the tile is a seam with the neighbour,
 * so a push through it would only enter the neighbour's solid: it is not a way out.
 * Returns NT__SEPARATE, NT__PUSH (out set) or NT__MASKED (overlapping, but every
 * way out of this tile alone goes through a masked side). */
enum { NT__SEPARATE = 0, NT__PUSH = 1, NT__MASKED = 2 };
int nt__collide_tile_aabb_m(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out);
int nt__collide_tile_circle_m(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out);

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
    nt__cell *cells;
};

/* Cell data for any coordinate: cells outside the map are FULL border cells. */
nt__cell nt__map_cell(const nt_map *map, int x, int y);

static inline int nt__map_tile(const nt_map *map, int x, int y)
{
    if (x < 0 || y < 0 || x >= map->w || y >= map->h) return NT_TILE_FULL;
    return map->cells[(size_t)y * (size_t)map->w + (size_t)x].tile;
}

static inline int nt__floor_int(nt_real v)
{
    nt_real f = nt__floor(v);
    if (f < -1e9) return -1000000000;
    if (f > 1e9) return 1000000000;
    return (int)f;
}

#endif /* NT_CORE_H */
