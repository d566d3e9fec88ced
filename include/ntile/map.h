/* ntile — the tile map: cells, edge states, resolution and ray casts.
 *
 * A map is W x H square cells of side `cell_size` (world units; N used 24).
 * Cell (i, j) covers [i*s, (i+1)*s] x [j*s, (j+1)*s]; x right, y down. Everything
 * outside the map behaves as FULL tiles (N's border).
 *
 * Each cell keeps its tile id and, per side, an edge state as in N:
 *   NT_EDGE_SOLID       the neighbour's solid covers the whole shared edge and this
 *                       cell's does not (crossing it meets a flat wall);
 *   NT_EDGE_INTERESTING solid touches the shared edge from either side without that
 *                       (a partial cover, a slope tip, a point contact);
 *   NT_EDGE_OFF         nothing touches the edge, or both sides cover it whole: the
 *                       seam between two solid tiles does not exist.
 * Edge states are kept correct by nt_map_set_tile (the cell and its 4 neighbours).
 */
#ifndef NTILE_MAP_H
#define NTILE_MAP_H

#include "base.h"
#include "tiles.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Largest map side in cells.
#define NT_MAP_MAX_SIDE 4096

/// Largest half-size (or radius) of a body or a resolved object, in cells: a body
/// can be up to 8 cells across. Larger shapes are refused with NT_ERR_SHAPE_TOO_LARGE.
#define NT_MAX_HALF_CELLS 4

/// Smallest and largest cell size (world units; NT_ERR_OUT_OF_RANGE outside, maps,
/// worlds and levels alike): speeds, gravity and squared distances in cell units stay
/// well inside float's range (a denormal cell size would put bodies outside the map).
#define NT_MIN_CELL_SIZE 1e-3f
#define NT_MAX_CELL_SIZE 1e6f

typedef struct nt_map nt_map;

/// Edge states, as in N.
typedef enum nt_edge { NT_EDGE_OFF = 0, NT_EDGE_SOLID = 1, NT_EDGE_INTERESTING = 2 } nt_edge;

/// Map definition: fill with nt_default_map_def() then adjust.
typedef struct nt_map_def {
    int width;          ///< cells, 1..NT_MAP_MAX_SIDE
    int height;         ///< cells, 1..NT_MAP_MAX_SIDE
    nt_real cell_size;  ///< world units per cell, in [NT_MIN_CELL_SIZE, NT_MAX_CELL_SIZE]
} nt_map_def;

/// Default map definition: 31 x 23 cells of size 24 (N's playable area), all EMPTY.
nt_map_def nt_default_map_def(void);

/// Create an empty map. Errors: NT_ERR_NON_FINITE, NT_ERR_INVALID_ARGUMENT (cell size <= 0),
/// NT_ERR_OUT_OF_RANGE (a side outside 1..NT_MAP_MAX_SIDE, a cell size outside
/// [NT_MIN_CELL_SIZE, NT_MAX_CELL_SIZE]), NT_ERR_OUT_OF_MEMORY. On failure *out is set to NULL.
nt_status nt_map_create(const nt_map_def *def, nt_map **out);

/// Destroy a map (NULL is ignored).
void nt_map_destroy(nt_map *map);

/// Map width in cells.
int nt_map_get_width(const nt_map *map);
/// Map height in cells.
int nt_map_get_height(const nt_map *map);
/// Cell size in world units.
nt_real nt_map_get_cell_size(const nt_map *map);

/// Set one cell's tile and update the edge states of the cell and its 4 neighbours.
nt_status nt_map_set_tile(nt_map *map, int x, int y, int tile);

/// Set every cell from `tiles` (width*height ids, row-major, row 0 first) in one pass.
/// Nothing changes unless every id is valid.
nt_status nt_map_set_tiles(nt_map *map, const uint8_t *tiles, size_t count);

/// The tile at a cell; cells outside the map are NT_TILE_FULL.
int nt_map_get_tile(const nt_map *map, int x, int y);

/// The edge state of a cell side. Outside the map: NT_EDGE_OFF.
nt_edge nt_map_get_edge(const nt_map *map, int x, int y, nt_side side);

/// One surface that the resolution pushed the object away from.
typedef struct nt_tile_contact {
    nt_vec2 normal;     ///< unit normal of the surface (direction of the push)
    nt_real depth;      ///< penetration along normal, world units
    int cell_x, cell_y; ///< the cell whose tile it is (may be outside the map: border)
} nt_tile_contact;

/// The result of nt_map_resolve.
typedef struct nt_resolution {
    nt_vec2 push;                 ///< displacement that frees the object, world units
    int contact_count;            ///< 0, 1 or 2 surfaces that define the push
    nt_tile_contact contacts[2];
    nt_status status;             ///< NT_OK, or why the shape was refused (see nt_map_check_shape)
} nt_resolution;

/// Whether the map's queries accept this shape: NT_ERR_INVALID_ARGUMENT (NULL map,
/// unknown shape type, negative half-size), NT_ERR_NON_FINITE, NT_ERR_SHAPE_TOO_LARGE
/// (half-size or radius above NT_MAX_HALF_CELLS cells), else NT_OK.
nt_status nt_map_check_shape(const nt_map *map, nt_shape shape);

/// Compute the displacement that frees a box or circle (centre `pos`, world units)
/// from every tile of the map: the shortest way out of the union of the tiles. Seams
/// between solid tiles never push. Returns false (and a zero result) when the object
/// overlaps nothing. A shape nt_map_check_shape refuses (half-size above
/// NT_MAX_HALF_CELLS cells, say) is refused before any work, whatever the assert hook
/// does: false, a zero push, and the reason in out->status. Objects
/// up to half a cell take the fast path; larger ones cost more: a long box on a floor
/// stays cheap (one push for all the tiles under it), a box wedged in a corner or sunk
/// deep in a mass of tiles searches the boundary curves within reach of its depth.
/// Far from the origin: the resolution works in cell units from the corner of the
/// object's cell, so that only the position's rounding to cells grows with the
/// distance (one unit in the last place of the coordinate in cells, per axis: in
/// float 6.1e-5 cell at 1,000 cells, 2.4e-4 cell below 4,096); the push is exact
/// for that position to 1e-5 cell in float, 1e-9 in double (tests/test_far.c).
bool nt_map_resolve(const nt_map *map, nt_vec2 pos, nt_shape shape, nt_resolution *out);

/// Largest single-tile penetration depth (world units) of the object at `pos`; 0 when free,
/// and 0 without any work for a shape nt_map_check_shape refuses.
nt_real nt_map_overlap_depth(const nt_map *map, nt_vec2 pos, nt_shape shape);

/// A ray-cast result.
typedef struct nt_ray_hit {
    nt_real fraction;   ///< t in [0, 1] along the segment
    nt_vec2 point;      ///< p0 + t * (p1 - p0)
    nt_vec2 normal;     ///< outward surface normal; (0,0) when the segment starts inside solid
    int cell_x, cell_y; ///< the cell that was hit
} nt_ray_hit;

/// First point where the segment p0 -> p1 (world units) enters solid, walking the grid
/// cell by cell. Returns false when it reaches p1 without entering solid. The walk
/// works from the corner of p0's cell, with p0 exact relative to it: the fraction is
/// exact to 2e-5 cell of travel in float (1e-9 in double) however far from the origin
/// on the largest map; the point is then rounded as a coordinate (tests/test_far.c).
bool nt_map_raycast(const nt_map *map, nt_vec2 p0, nt_vec2 p1, nt_ray_hit *out);

#ifdef __cplusplus
}
#endif

#endif
