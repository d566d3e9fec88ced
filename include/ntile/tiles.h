/* ntile — the N tile set and the narrow phase.
 *
 * The 34 tiles of N v1.4, with N's numeric ids (0-33, also the level-string
 * character '0' + id) and names. Geometry is given in the unit cell [0,1]^2 with
 * y pointing down; a tile's solid region is closed, and "overlap" always means the
 * interiors intersect: touching is not overlapping.
 *
 * The narrow-phase routines work in the unit cell: pass the object's centre
 * relative to the cell's top-left corner, divided by the cell size, and its
 * half-size (or radius) divided by the cell size. They return the exact minimum
 * translation (unit direction + depth) that moves the object out of the tile
 * when it is alone in the world.
 */
#ifndef NTILE_TILES_H
#define NTILE_TILES_H

#include "base.h"

#ifdef __cplusplus
extern "C" {
#endif

/// N's tile ids. Suffix pn/nn/np/pp = signs (x, y) of the surface's outward normal, y down.
typedef enum nt_tile_id {
    NT_TILE_EMPTY = 0,
    NT_TILE_FULL = 1,
    NT_TILE_45DEGpn = 2, NT_TILE_45DEGnn = 3, NT_TILE_45DEGnp = 4, NT_TILE_45DEGpp = 5,
    NT_TILE_CONCAVEpn = 6, NT_TILE_CONCAVEnn = 7, NT_TILE_CONCAVEnp = 8, NT_TILE_CONCAVEpp = 9,
    NT_TILE_CONVEXpn = 10, NT_TILE_CONVEXnn = 11, NT_TILE_CONVEXnp = 12, NT_TILE_CONVEXpp = 13,
    NT_TILE_22DEGpnS = 14, NT_TILE_22DEGnnS = 15, NT_TILE_22DEGnpS = 16, NT_TILE_22DEGppS = 17,
    NT_TILE_22DEGpnB = 18, NT_TILE_22DEGnnB = 19, NT_TILE_22DEGnpB = 20, NT_TILE_22DEGppB = 21,
    NT_TILE_67DEGpnS = 22, NT_TILE_67DEGnnS = 23, NT_TILE_67DEGnpS = 24, NT_TILE_67DEGppS = 25,
    NT_TILE_67DEGpnB = 26, NT_TILE_67DEGnnB = 27, NT_TILE_67DEGnpB = 28, NT_TILE_67DEGppB = 29,
    NT_TILE_HALFd = 30, NT_TILE_HALFr = 31, NT_TILE_HALFu = 32, NT_TILE_HALFl = 33,
    NT_TILE_COUNT = 34
} nt_tile_id;

/// Shape classes: the narrow phase has one routine per class, the table supplies the rest.
typedef enum nt_tile_class {
    NT_CLASS_EMPTY = 0,
    NT_CLASS_POLYGON, ///< FULL, 45, 22, 67 and HALF tiles: a convex polygon
    NT_CLASS_CONVEX,  ///< quarter disc of radius 1 centred on a cell corner
    NT_CLASS_CONCAVE  ///< the cell minus a disc of radius 1 centred on a cell corner
} nt_tile_class;

/// Cell sides, used for edge states and tile coverage.
typedef enum nt_side { NT_SIDE_LEFT = 0, NT_SIDE_RIGHT = 1, NT_SIDE_TOP = 2, NT_SIDE_BOTTOM = 3 } nt_side;

/// Everything the table knows about a tile, in unit-cell coordinates (y down).
typedef struct nt_tile_info {
    const char *name;        ///< N's name, e.g. "45DEGpn"
    nt_tile_class cls;       ///< shape class
    int8_t signx, signy;     ///< signs of the surface normal (0 for EMPTY, FULL, HALF)
    nt_vec2 normal;          ///< unit outward normal of the surface; round tiles: at the middle of the arc; (0,0) for EMPTY and FULL
    int vertex_count;        ///< polygon corners (POLYGON), or the straight corners of a round tile
    nt_vec2 vertices[4];     ///< counter-clockwise on screen (y down): edge a->b has outward normal (-(b.y-a.y), b.x-a.x)
    nt_vec2 arc_center;      ///< round tiles: centre of the radius-1 arc (a cell corner)
    nt_vec2 bounds_min;      ///< axis-aligned bounds of the solid part
    nt_vec2 bounds_max;
    /// How the solid meets each side (indexed by nt_side): the covered interval
    /// [cover_lo, cover_hi] along the side (x for top/bottom, y for left/right), or
    /// cover_lo > cover_hi when the solid does not touch that side. A point contact
    /// has cover_lo == cover_hi.
    nt_real cover_lo[4], cover_hi[4];
} nt_tile_info;

/// The table entry for a tile id, or NULL when id is outside 0..33.
const nt_tile_info *nt_tile_get_info(int id);

/// The tile id for an N name ("FULL", "45DEGpn", ...), or -1 when unknown. Case-sensitive.
int nt_tile_from_name(const char *name);

/// True when the point is strictly inside the tile's solid (unit cell coordinates).
bool nt_tile_contains_point(int tile, nt_vec2 p);

/// Object shapes. An object never rotates; its half-size (or radius) is at most
/// NT_MAX_HALF_CELLS cells (map.h).
typedef enum nt_shape_type { NT_SHAPE_AABB = 0, NT_SHAPE_CIRCLE = 1 } nt_shape_type;

/// An axis-aligned box or a circle, centred on the object's position.
typedef struct nt_shape {
    nt_shape_type type;
    nt_vec2 half; ///< half-width and half-height; for a circle both equal the radius
} nt_shape;

/// A box shape of the given half-width and half-height.
static inline nt_shape nt_shape_aabb(nt_real hw, nt_real hh)
{
    nt_shape s;
    s.type = NT_SHAPE_AABB;
    s.half.x = hw;
    s.half.y = hh;
    return s;
}

/// A circle shape of the given radius.
static inline nt_shape nt_shape_circle(nt_real r)
{
    nt_shape s;
    s.type = NT_SHAPE_CIRCLE;
    s.half.x = r;
    s.half.y = r;
    return s;
}

/// A minimum translation: move the object by normal * depth to separate it.
typedef struct nt_mtv {
    nt_vec2 normal; ///< unit direction in which to move the object
    nt_real depth;  ///< > 0 when overlapping
} nt_mtv;

/// Box (centre, half-size, unit cell coordinates) against one tile alone.
/// Returns true and the exact minimum translation when the interiors overlap. Exact for
/// any half-size up to NT_MAX_HALF_CELLS (map.h) and tested so; larger sizes take the
/// same routines, untested.
bool nt_tile_collide_aabb(int tile, nt_vec2 center, nt_vec2 half, nt_mtv *out);

/// Circle against one tile alone (unit cell coordinates). See nt_tile_collide_aabb.
bool nt_tile_collide_circle(int tile, nt_vec2 center, nt_real radius, nt_mtv *out);

/// Either shape against one tile alone (unit cell coordinates).
bool nt_tile_collide_shape(int tile, nt_vec2 center, nt_shape shape, nt_mtv *out);

/// Minimum translation moving box A out of box B. Coincident centres push along -y.
bool nt_collide_aabbs(nt_vec2 ca, nt_vec2 ha, nt_vec2 cb, nt_vec2 hb, nt_mtv *out);

/// Minimum translation moving circle A out of circle B. Coincident centres push along -y.
bool nt_collide_circles(nt_vec2 ca, nt_real ra, nt_vec2 cb, nt_real rb, nt_mtv *out);

/// Minimum translation moving box A out of circle B.
bool nt_collide_aabb_circle(nt_vec2 ca, nt_vec2 ha, nt_vec2 cb, nt_real rb, nt_mtv *out);

/// Minimum translation moving shape A (at pa) out of shape B (at pb), any combination.
bool nt_collide_shapes(nt_vec2 pa, nt_shape a, nt_vec2 pb, nt_shape b, nt_mtv *out);

/// Segment p0 + t*d, t in [0, tmax], against one tile (unit cell coordinates).
/// Returns true with the first t at which the segment enters the solid's interior and
/// the outward surface normal there. A segment starting inside hits at t = 0 with normal (0,0).
bool nt_tile_raycast(int tile, nt_vec2 p0, nt_vec2 d, nt_real tmax, nt_real *t_out, nt_vec2 *normal_out);

#ifdef __cplusplus
}
#endif

#endif
