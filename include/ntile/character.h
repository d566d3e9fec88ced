/* ntile — moving a character: exact shape casts (the character mover will follow).
 *
 * A shape cast sweeps a box or circle (half-size up to NT_MAX_HALF_CELLS cells, never
 * rotating) from `pos` along `translation` and reports the first thing it meets: the
 * fraction t in [0, 1] of the translation at which its centre's segment enters the
 * interior of the Minkowski region of the shape and what it hits (tile: its exact
 * shape, lines and circular arcs; body: its box or circle). The time is computed, not
 * sampled: the segment is cut at every line and circle that can bound that region,
 * the exact overlap test at the middle of each piece says whether it is inside, and a
 * stretch inside counts when it gets deeper than rounding (16 units in the last place
 * of the start's coordinates, plus as much of the distance travelled). Touching is not
 * hitting: a shape that slides along a surface, or grazes a corner, goes on.
 * Measured against a brute-force reference (bisection on an independent overlap test):
 * within 1e-8 cell of travel in double builds, 1e-5 in float builds near the origin.
 *
 * Where the cast starts:
 *  - Free (overlapping nothing by more than rounding): t is exact, as above.
 *  - Resting: overlapping surfaces by at most NT_CAST_START_TOLERANCE cells, such as a
 *    body of the world, which rests a skin (2.5e-4 cell) deep on what carries it. The
 *    depth is measured as nt_map_resolve does, with seams between solid tiles ignored.
 *    When the translation approaches one of those surfaces (normal . translation < 0)
 *    the cast stops at t = 0 with that surface's normal. Otherwise the whole cast is
 *    made with the shape smaller by that depth (and rounding) on every side, so that
 *    the surfaces it rests on never stop it: a box sliding along a floor of many tiles,
 *    or from a slope onto a flat, goes the whole way; what it meets later is met up to
 *    that depth late (at most the tolerance over the cosine of the approach angle).
 *    A concave arc (a quarter pipe) curves into a path along its tangent: moving along
 *    one it rests on meets it at once.
 *  - Deeper than the tolerance in anything: t = 0 and a zero normal.
 * Seams between solid tiles never stop a cast; cells outside the map are FULL, as for
 * nt_map_resolve. Nothing is allocated; the cost grows with the cells the swept shape
 * covers up to the hit (about 90 ns for a 1 x 2-cell box moving a quarter cell along a
 * floor). Same inputs, same bits.
 */
#ifndef NTILE_CHARACTER_H
#define NTILE_CHARACTER_H

#include "base.h"
#include "map.h"
#include "tiles.h"
#include "world.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Largest start overlap, in cells, that a shape cast treats as resting contact (more
/// is a start inside solid: t = 0, zero normal).
#define NT_CAST_START_TOLERANCE 1e-3

/// What a tile shape cast hit.
typedef struct nt_shape_cast_hit {
    nt_real fraction;   ///< t in [0, 1]: the shape stops at pos + t * translation
    nt_vec2 point;      ///< where the shape touches what it hit at t (world units)
    nt_vec2 normal;     ///< unit normal of the surface hit, pointing at the shape; (0, 0) when it starts inside
    int cell_x, cell_y; ///< the tile's cell (may be outside the map: border)
} nt_shape_cast_hit;

/// Sweep a box or circle (centre `pos`, world units) along `translation` against the
/// map's tiles. Returns true and the first hit (see the top of this header), false
/// (and a zero result) when the shape travels the whole way, or for bad input: a NULL
/// map, a non-finite number, a half-size not in (0, NT_MAX_HALF_CELLS cells], a circle
/// with unequal halves, an unknown shape type. `out` may be NULL.
bool nt_map_cast_shape(const nt_map *map, nt_vec2 pos, nt_shape shape, nt_vec2 translation, nt_shape_cast_hit *out);

/// What a world shape cast hit: a tile (body is null) or a body.
typedef struct nt_world_shape_hit {
    nt_body_id body;    ///< the body hit; null for a tile
    nt_real fraction;   ///< t in [0, 1]
    nt_vec2 point;      ///< where the shape touches what it hit at t (world units)
    nt_vec2 normal;     ///< unit normal pointing at the shape; (0, 0) when it starts inside
    int cell_x, cell_y; ///< the tile's cell (tile hits), else 0
} nt_world_shape_hit;

/// The same as nt_map_cast_shape against the world's tiles (when filter.tiles) and the
/// bodies the filter sees (every size, through every level of the broad phase; a body
/// is hit exactly, as a box or circle). One-way cells (NT_CELL_ONE_WAY) stop the cast
/// only through a surface whose normal points up (normal.y < 0), and are ignored when
/// the shape already overlaps them at the start (more than resting on them). At equal
/// times a tile is reported before a body. Bad input as for nt_map_cast_shape (and a
/// NULL world) returns false with a zero result.
bool nt_world_cast_shape(const nt_world *world, nt_vec2 pos, nt_shape shape, nt_vec2 translation,
                         nt_query_filter filter, nt_world_shape_hit *out);

#ifdef __cplusplus
}
#endif

#endif
