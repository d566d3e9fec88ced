/* ntile — moving a character: exact shape casts and the character mover.
 *
 * THE CHARACTER MOVER
 *
 * A character is a dynamic or kinematic body that the game moves itself, once a step,
 * the way Godot's CharacterBody2D.move_and_slide and Box2D's mover do: cast and slide.
 *
 *     nt_character_def cd = nt_default_character_def();   // 50-degree floors, snap, step-up
 *     nt_character_create(world, player, &cd);
 *     ...each step:
 *     vel.x = input * run_speed;
 *     vel.y += gravity * dt;                                 // your gravity, your jump
 *     if (jump && on_floor) vel.y = -jump_speed;
 *     nt_character_result r;
 *     nt_character_move(world, player, vel, dt, &r);
 *     vel = r.velocity;                                      // slid along what it met
 *     on_floor = r.on_floor;
 *     nt_world_step(world, dt);
 *
 * nt_character_move moves the body by velocity * dt at once: cast against the tiles
 * (edge states: seams never stop it; one-way cells from above only) and the bodies that
 * stop it, sliding along what it meets (at most max_slides casts). Then:
 *  - Floors, walls, ceilings: a surface is a floor when its normal is within
 *    floor_angle of straight up (default 50 degrees: 45-degree slopes are floors,
 *    63.4-degree ones walls), a ceiling within floor_angle of straight down, else a wall.
 *  - Stop on slope (default on): on a floor the downward part of the motion is the
 *    floor's to carry, so standing still on a slope does not slide down, and running
 *    up or down it goes along it. Constant speed on slopes (default off): the motion
 *    along a floor keeps the horizontal length it had.
 *  - Step-up: a wall met while on a floor that is a step no higher than step_cells
 *    (default half a cell: a HALF tile's edge) is climbed without a jump.
 *  - Floor snap: a character that stood on a floor and is not moving up is moved down
 *    onto the floor below, up to snap_cells (default half a cell), and onto a sloped
 *    floor up to as much more as that floor falls under the move's horizontal travel
 *    (|dx| |n.x / n.y| for the floor's normal n, within floor_angle): it runs down
 *    ramps without leaving them at any speed, while a ledge onto a flat floor more
 *    than snap_cells below is a fall.
 *  - Moving platforms: standing on a body (a kinematic platform, a crate), it is carried
 *    by that body's velocity over the step (the body moves as much in the world step),
 *    horizontally, vertically and diagonally, down included; leaving it (a jump, a walk
 *    off its edge) adds its velocity to the returned velocity.
 *  - Pushing: dynamic bodies do not stop a character (unless collide_dynamic); the
 *    world step then pushes those it overlaps out of its way, the character counting as
 *    infinitely heavy (as a kinematic body does). A dynamic body wholly below its feet
 *    where a move starts (its top no higher than the character's bottom, within
 *    NT_CAST_START_TOLERANCE) is the exception: it stands on it (a crate), carried by
 *    its velocity. Static and kinematic bodies stop it.
 *  - One-way floors: cells flagged NT_CELL_ONE_WAY and bodies created with is_one_way
 *    (a one-way kinematic platform) hold it from above only; it jumps up through them.
 *    nt_character_drop_through lets it fall through the one it stands on, until it is
 *    clear of every one-way cell and body.
 * A character found inside the tiles (one painted over it, a teleport into a wall) is
 * first freed by the shortest way out (nt_map_resolve; one-way cells do not count).
 * A body that stops it and overlaps it (a kinematic wall moved into it, a body placed on
 * it) pushes it out by the shortest way at its next move.
 * A move that left the character where it was (standing still, wedged), on no body, is
 * kept: the next move with the same velocity and dt is answered from it, bit for bit the
 * same, while the tiles, the body's position and mask, the settings and drop-through stay
 * and no body it could meet comes within reach. Idle characters then cost next to nothing.
 * While it is a character, the world step treats the body as kinematic and does not move
 * it (no gravity, no tiles: the mover did that); nt_body_get_type still says what it was
 * created as, but impulses are refused (NT_ERR_INVALID_ARGUMENT) and a velocity set with
 * nt_body_set_velocity only lasts until the next move: the game's velocity is the one it
 * passes to nt_character_move. nt_character_destroy gives the body back to the world step.
 *
 * A shape cast sweeps a box or circle (half-size up to NT_MAX_HALF_CELLS cells, never
 * rotating) from `pos` along `translation` and reports the first thing it meets: the
 * fraction t in [0, 1] of the translation at which its centre's segment enters the
 * interior of the Minkowski region of the shape and what it hits (tile: its exact
 * shape, lines and circular arcs; body: its box or circle). The time is computed, not
 * sampled: the segment is cut at every line and circle that can bound that region,
 * the exact overlap test at the middle of each piece says whether it is inside, and a
 * stretch inside counts when it gets deeper than rounding (16 units in the last place
 * of the start's coordinates in cells up to 256 cells from the origin, 4.9e-4 cell
 * beyond, 4 units from 1,024 cells on: 2e-3 cell at 4,096; plus 16 units of the
 * distance travelled). Touching is not hitting: a shape that slides along a surface,
 * or grazes a corner, goes on. Measured against a brute-force reference (bisection on
 * an independent overlap test): within 1e-8 cell of travel in double builds, 1e-5 in
 * float builds near the origin; far from it, float rounds the start to cells (1.8e-4
 * cell of travel at 1,000 cells, 7.6e-4 at the far corner of a 4096 x 4096 map:
 * tests/test_far.c, which also runs a character down and up slopes there).
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
/// is a start inside solid: t = 0, zero normal). In float, twice the start's rounding
/// allowance where that is more: from 1,049 cells from the origin (3.9e-3 cell at 4,096).
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

/// Character settings: fill with nt_default_character_def() then adjust.
typedef struct nt_character_def {
    nt_real floor_angle;           ///< radians in [0, pi/2]: steepest surface that is a floor (default 50 degrees)
    nt_real snap_cells;            ///< floor snap distance in cells, [0, 8] (default 0.5), plus a sloped floor's fall under the move; 0: no snap
    nt_real step_cells;            ///< highest step climbed without a jump, cells, [0, 8] (default 0.5); 0: none
    bool stop_on_slope;            ///< standing still on a slope does not slide down (default true)
    bool constant_speed_on_slopes; ///< motion along a floor keeps its horizontal length (default false)
    bool slide_on_walls;           ///< on a floor, slide along walls met at an angle (default true)
    bool collide_dynamic;          ///< dynamic bodies stop the character like walls (default false: it pushes them, and stands on those under its feet)
    int max_slides;                ///< casts per move, 1..16 (default 4)
} nt_character_def;

/// Defaults: 50-degree floors, snap and step-up of half a cell, stop on slope, 4 slides.
nt_character_def nt_default_character_def(void);

/// Make a dynamic or kinematic body a character (or change its settings). Errors:
/// NT_ERR_INVALID_ID, NT_ERR_INVALID_ARGUMENT (a static body or a sensor, NULL, settings
/// out of range), NT_ERR_NON_FINITE, NT_ERR_OUT_OF_MEMORY. Destroying the body ends it.
nt_status nt_character_create(nt_world *world, nt_body_id id, const nt_character_def *def);

/// Give a character back to the world step as the body it was created as.
nt_status nt_character_destroy(nt_world *world, nt_body_id id);

/// True when the handle names a live body that is a character.
bool nt_character_is_valid(const nt_world *world, nt_body_id id);

/// What a character move did and met.
typedef struct nt_character_result {
    nt_vec2 position;       ///< where it ended
    nt_vec2 velocity;       ///< the velocity to keep: slid along what it met, with no vertical part on a floor (plus a platform's when leaving it)
    bool on_floor, on_wall, on_ceiling;
    nt_vec2 floor_normal, wall_normal, ceiling_normal; ///< of the surfaces met (zero when not)
    nt_body_id floor_body;  ///< the body it stands on; null for a tile or no floor
    int floor_cell_x, floor_cell_y; ///< the floor tile's cell (floor_body null, on_floor)
    nt_vec2 floor_velocity; ///< the floor body's velocity (a moving platform's); zero for tiles
    bool snapped;           ///< moved down onto the floor by the snap
    bool stepped_up;        ///< climbed a step
    bool landed;            ///< on a floor now, not before this move
    int slide_count;        ///< surfaces met while sliding
} nt_character_result;

/// Move a character by velocity * dt (world units per second, clamped to the world's
/// speed limit), sliding, stepping up and snapping as its settings say, carried by the
/// body it stands on (see the top of this header). Sets the body's position, and its
/// velocity to the displacement over dt for the world step's contacts. Errors:
/// NT_ERR_INVALID_ARGUMENT (NULL, dt <= 0), NT_ERR_NON_FINITE, NT_ERR_INVALID_ID (not a
/// character); the world is then unchanged and *out zero.
nt_status nt_character_move(nt_world *world, nt_body_id id, nt_vec2 velocity, nt_real dt, nt_character_result *out);

/// Let the character fall through the one-way floor it stands on: one-way cells do not
/// stop it until it is clear of them.
nt_status nt_character_drop_through(nt_world *world, nt_body_id id);

#ifdef __cplusplus
}
#endif

#endif
