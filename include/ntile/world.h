/* ntile — the world: bodies moving through a tile map.
 *
 * A world owns an nt_map and a set of bodies (boxes or circles of half-size up to
 * NT_MAX_HALF_CELLS cells, 8 cells across, never rotating). nt_world_step(world, dt) advances it by dt seconds:
 * gravity and drag, contact response against tiles (N's model or Coulomb
 * friction), body-body contacts, sleeping, events. Units are the map's world units
 * and seconds; y points down, so the default gravity (0, +g) pulls downwards.
 *
 * Bodies are named by small handles (index + generation), passed by value. A handle
 * whose body was destroyed is rejected with NT_ERR_INVALID_ID; getters given such a
 * handle return a zero value. Every call that can fail returns an nt_status and
 * leaves the world unchanged when it fails. Memory comes from the allocator hook
 * (nt_set_allocator); a step allocates only when a buffer has to grow.
 *
 * Speed limit: a body moves at most `max_cells_per_step` cells (default 4) in one
 * step; faster velocities are clamped. Within that limit a body never passes
 * through a tile: a step whose motion is longer than the body's smaller half-size h
 * is split into floor(distance / h) + 1 sub-steps for that body (only when the swept
 * cells hold a tile; at most 256, so this holds for half-sizes down to
 * max_cells_per_step / 256 cells). Body-body contacts are found once per step, for
 * pairs overlapping or closer than 0.05 cell plus the distance they close in on each
 * other during the step (speculative contacts, at most one cell): a fast pair is
 * stopped where it meets instead of being found inside each other. Pairs closing
 * faster than about a cell per step can still pass into each other.
 *
 * Contacts rest a "skin" deep (2.5e-4 cell), so that a resting contact is found
 * again every step: a body on a floor sits 2.5e-4 cell into it (a body thinner than
 * two skins, half its thickness). In float, where one unit in the last place of a
 * coordinate is more than that (never nearer than 2,097 cells to the origin; 2,731
 * cells for N's cell size of 24), the skin is that unit, so that the rounding of the
 * position cannot lift the body out of contact: at most 5e-4 cell on the largest map. nt_map_overlap_depth of any body
 * stays below 1e-3 cell everywhere on the largest map (tests/test_far.c: 150 bodies
 * thrown at the speed limit, deepest 2.5e-4 cell near the origin and 7.1e-4 cell at
 * the far corner of a 4096 x 4096 map in float, 2.5e-4 in double).
 *
 * Large bodies: a body above half a cell sits in a coarser level of the loose grid
 * (cells 2, 4 or 8 map cells wide), meets the tiles over every cell its box covers
 * (the same exact resolution and seam handling as small bodies) and must lie wholly
 * inside the map where it is created or placed (NT_ERR_OUT_OF_RANGE otherwise).
 * Worlds without such bodies do exactly the work they did without them.
 *
 * Riders: a dynamic body resting on a kinematic one is carried by their contact
 * alone. It follows the platform exactly (to rounding) while the platform accelerates
 * downwards less than gravity and sideways less than friction allows (Coulomb: mu
 * times gravity); a sharper change makes it slip or lift off as a real body would, and
 * it lands back on the platform.
 *
 * Friction: tile contacts use the world's model. Body-body contacts use Coulomb
 * friction in the Coulomb model and N's rule on the relative velocity in the N
 * model. Resting on a tile, a body's friction comes from its own weight only (the
 * weight of bodies stacked on it does not add to it).
 */
#ifndef NTILE_WORLD_H
#define NTILE_WORLD_H

#include "base.h"
#include "map.h"
#include "tiles.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct nt_world nt_world;

/// A body handle, naming its world as well as the body: a handle used with another
/// world than its own is refused (NT_ERR_INVALID_ID, false, zero), as is a handle of a
/// destroyed body. The zero value is the null handle.
typedef struct nt_body_id {
    int32_t index1;      ///< body slot + 1; 0 for the null handle
    uint32_t world0;     ///< the tag of the world that made it (never 0 for a body)
    uint32_t generation; ///< bumped each time the slot is reused
} nt_body_id;

/// The null body handle (also used for "a tile" in events and ray hits).
static inline nt_body_id nt_null_body_id(void)
{
    nt_body_id id;
    id.index1 = 0;
    id.world0 = 0;
    id.generation = 0;
    return id;
}

/// True for the null handle.
static inline bool nt_body_id_is_null(nt_body_id id) { return id.index1 == 0; }

/// True when two handles name the same body.
static inline bool nt_body_id_equals(nt_body_id a, nt_body_id b)
{
    return a.index1 == b.index1 && a.world0 == b.world0 && a.generation == b.generation;
}

/// How a body moves.
typedef enum nt_body_type {
    NT_BODY_STATIC = 0,    ///< never moves; infinite mass
    NT_BODY_KINEMATIC = 1, ///< moves by its velocity only, ignores tiles and gravity; infinite mass, pushes dynamic bodies
    NT_BODY_DYNAMIC = 2    ///< gravity, drag, tiles and contacts
} nt_body_type;

/// How friction and bounce act at a contact.
typedef enum nt_friction_model {
    /// N's model: when a body moves into a surface, v' = -bounce * vn + (1 - friction) * vt.
    /// friction is in [0, 1].
    NT_FRICTION_N = 0,
    /// Coulomb: the tangential velocity change is at most friction * the normal velocity
    /// change; below that the body sticks. friction (mu) is >= 0.
    NT_FRICTION_COULOMB = 1
} nt_friction_model;

/// Surface properties. Two surfaces combine to max(bounce) and sqrt(friction_a * friction_b).
/// Two bodies meeting with a combined bounce of 1, neither resting on the ground (in flight,
/// or without gravity), collide as two free bodies: momentum and kinetic energy are kept
/// exactly, and the impact passes on along a row of such bodies. Other bounces are
/// restitution targets of the contact solver, which loses or gains a little energy where
/// several bodies meet in one step.
typedef struct nt_material {
    nt_real friction; ///< see nt_friction_model
    nt_real bounce;   ///< restitution in [0, 1]
} nt_material;

/// Body positions (creation, nt_body_set_position) must lie within this many cells of
/// the map, else NT_ERR_OUT_OF_RANGE: the tile resolution brings a body back into the
/// map from at most that far.
#define NT_WORLD_REACH_CELLS 64

/// A dynamic body's mass must lie in [NT_MIN_MASS, NT_MAX_MASS] (else NT_ERR_OUT_OF_RANGE):
/// the solver multiplies by its inverse, which must stay well scaled in float.
#define NT_MIN_MASS 1e-12f
#define NT_MAX_MASS 1e12f

/// A step's dt must lie in [NT_MIN_DT, NT_MAX_DT] seconds (else NT_ERR_OUT_OF_RANGE), in
/// nt_world_step, the game layer, replays and the CLI alike: the solver divides by dt
/// and scales warm-started impulses by the ratio of consecutive dts.
#define NT_MIN_DT 1e-6f
#define NT_MAX_DT 1.0f

/// Each component of the world's gravity must lie in [-NT_MAX_GRAVITY, NT_MAX_GRAVITY]
/// world units / s^2, and a body's gravity scale in [-NT_MAX_GRAVITY_SCALE,
/// NT_MAX_GRAVITY_SCALE] (else NT_ERR_OUT_OF_RANGE): their product times NT_MAX_DT and
/// its square stay finite in float (a huge finite gravity would launch resting bodies).
#define NT_MAX_GRAVITY 1e12f
#define NT_MAX_GRAVITY_SCALE 1e6f

/// Most body contacts (pairs within the contact margin, sensor overlaps included) a step
/// may hold: a step that would find more (thousands of bodies piled at one point: 1,450
/// overlapping bodies make a million pairs) returns NT_ERR_LIMIT before it changes
/// anything, instead of exhausting memory (about 150 MB of contact arrays at the cap).
#define NT_MAX_CONTACTS (1 << 20)

/// The most bodies a world holds at once (2^30): nt_body_create returns NT_ERR_LIMIT
/// beyond it. (The velocity solver names its bodies by 32-bit offsets.)
#define NT_MAX_BODIES (1 << 30)

/// Number of tile materials a world holds; cells name one by index (0 = the default).
#define NT_MAX_MATERIALS 16

/// Cell flag: the cell's tile is one-way. It stops a body only through a contact whose
/// normal points up (normal.y < 0), and only when the body did not already overlap the
/// tile before that move; otherwise bodies pass through it.
#define NT_CELL_ONE_WAY 1u

/// World definition: fill with nt_default_world_def() then adjust.
typedef struct nt_world_def {
    nt_map_def map;                   ///< the tile map (all EMPTY at creation)
    nt_vec2 gravity;                  ///< world units / s^2; y down; each part within NT_MAX_GRAVITY
    nt_friction_model friction_model; ///< for every contact of the world
    nt_material tile_material;        ///< material 0, used by every cell until told otherwise
    nt_real restitution_threshold;    ///< approach speeds below this do not bounce (units/s, >= 0)
    nt_real hit_event_threshold;      ///< approach speed that makes a hit event (units/s, >= 0)
    bool enable_sleep;                ///< let resting bodies sleep (kinematic bodies never do)
    nt_real sleep_speed;              ///< a body slower than this (units/s) counts as resting
    nt_real sleep_time;               ///< a group of touching bodies resting this long (s) falls asleep
    nt_real max_cells_per_step;       ///< speed limit in cells per step, in [1, 16]
    int velocity_iterations;          ///< body-contact velocity iterations, 1..64 (then one pass up the stack)
    int position_iterations;          ///< body-overlap position iterations, 0..64 (also each body's turns in the correction after the move)
    nt_real floor_angle;              ///< radians in [0, pi/2]: steepest tile surface nt_body_get_tile_contacts calls a floor (default 50 degrees)
    int body_capacity;                ///< bodies to reserve room for (grows as needed)
    void *user_data;
} nt_world_def;

/// Defaults for N's scale (cell 24, 31 x 23 cells, 40 Hz feel): gravity (0, 320),
/// NT_FRICTION_N, tile material {friction 0.05, bounce 0.3}, restitution and hit
/// thresholds 24 units/s, sleep after 0.5 s below 6 units/s, 4 cells/step, 8 velocity
/// and 4 position iterations. Speeds are world units: scale them with cell_size.
nt_world_def nt_default_world_def(void);

/// Create a world. Errors: NT_ERR_NON_FINITE, NT_ERR_INVALID_ARGUMENT, NT_ERR_OUT_OF_RANGE
/// (a map the map refuses, gravity beyond NT_MAX_GRAVITY, iterations or speed limit out of
/// range), NT_ERR_OUT_OF_MEMORY. On failure *out is NULL.
nt_status nt_world_create(const nt_world_def *def, nt_world **out);

/// Destroy a world and every body in it (NULL is ignored).
void nt_world_destroy(nt_world *world);

/// Advance the world by dt seconds, dt in [NT_MIN_DT, NT_MAX_DT] (NT_ERR_NON_FINITE,
/// NT_ERR_INVALID_ARGUMENT for dt <= 0, NT_ERR_OUT_OF_RANGE otherwise; the world is then
/// unchanged). NT_ERR_LIMIT: the step would hold more than NT_MAX_CONTACTS contacts (the
/// world is unchanged; separate the bodies). Events of the previous step are discarded.
/// Static bodies never get a velocity.
nt_status nt_world_step(nt_world *world, nt_real dt);

/// The world's tile map, for map queries. Change tiles through the world.
const nt_map *nt_world_get_map(const nt_world *world);

/// Set a cell's tile (as nt_map_set_tile) and wake the bodies near it.
nt_status nt_world_set_tile(nt_world *world, int x, int y, int tile);

/// Set every tile (as nt_map_set_tiles) and wake every body.
nt_status nt_world_set_tiles(nt_world *world, const uint8_t *tiles, size_t count);

/// A cell's tile; outside the map NT_TILE_FULL.
int nt_world_get_tile(const nt_world *world, int x, int y);

/// Set tile material `index` (0..NT_MAX_MATERIALS-1). Friction must suit the world's model.
nt_status nt_world_set_material(nt_world *world, int index, nt_material material);

/// Read tile material `index`; an invalid index gives {0, 0}.
nt_material nt_world_get_material(const nt_world *world, int index);

/// Make a cell use tile material `index`. Cells outside the map use material 0.
nt_status nt_world_set_cell_material(nt_world *world, int x, int y, int index);

/// The material index of a cell (0 outside the map).
int nt_world_get_cell_material(const nt_world *world, int x, int y);

/// Set a cell's flags (NT_CELL_ONE_WAY); wakes the bodies near it.
nt_status nt_world_set_cell_flags(nt_world *world, int x, int y, uint32_t flags);

/// A cell's flags (0 outside the map).
uint32_t nt_world_get_cell_flags(const nt_world *world, int x, int y);

/// Change gravity (finite, each part within NT_MAX_GRAVITY, else NT_ERR_OUT_OF_RANGE); wakes every body.
nt_status nt_world_set_gravity(nt_world *world, nt_vec2 gravity);

/// The world's gravity.
nt_vec2 nt_world_get_gravity(const nt_world *world);

/// Change the solver's iterations from the next step: velocity 1..64, position 0..64
/// (as in nt_world_def), else NT_ERR_OUT_OF_RANGE and nothing changes.
nt_status nt_world_set_iterations(nt_world *world, int velocity_iterations, int position_iterations);

/// The solver's iterations (zeros for a NULL world).
void nt_world_get_iterations(const nt_world *world, int *velocity_iterations, int *position_iterations);

/// Number of live bodies.
int nt_world_get_body_count(const nt_world *world);

/// Number of awake dynamic and kinematic bodies.
int nt_world_get_awake_count(const nt_world *world);

/// The user pointer of the world definition.
void *nt_world_get_user_data(const nt_world *world);

/// Work done by the last step, for profiling.
typedef struct nt_world_counters {
    int body_count;    ///< live bodies
    int awake_count;   ///< bodies simulated
    int contact_count; ///< body pairs overlapping (and sensor overlaps)
    int substep_count; ///< body moves, sub-steps included
    int pair_tests;    ///< candidate pairs tested by the broad phase
    int tile_resolutions; ///< exact tile resolutions (nt_map_resolve) the step needed: bodies in open
                          ///< air, resting where they rested, or gliding along a flat surface they
                          ///< touched (within the skin) need none
    int bodies_held;      ///< bodies resting on tiles whose gravity and surfaces were answered from
                          ///< the step before (the same forces against the same surfaces: stopped
                          ///< again), in steps without body contacts
} nt_world_counters;

/// Counters of the last step.
nt_world_counters nt_world_get_counters(const nt_world *world);

/// Wall-clock time of the last step by phase, in milliseconds (C's timespec_get:
/// the monotonic clock with a C23 library, else the calendar clock, where a phase
/// during which the clock is set back counts 0), while profiling is on; all zero
/// otherwise. The phases run in this order; `step` is their sum.
typedef struct nt_world_profile {
    double pairs;    ///< broad phase: body pairs closer than the contact margin
    double contacts; ///< matching them with the last step's: begin/end events, wake-ups
    double correct;  ///< position correction (and the tile resolution of pushed bodies)
    double solve;    ///< the velocity solver, with the gravity, drag and resting tile contacts of the bodies in body contacts
    double move;     ///< integration and tile resolution of every moving body (with the others' gravity, drag and resting tile contacts, and each body's rest time)
    double sleep;    ///< sleep islands (of bodies that have rested long enough)
    double step;     ///< the whole step: the sum of the above
} nt_world_profile;

/// Time each step's phases from now on (enable) or stop (off by default: the clock
/// is read seven times a step, which shows in a world of a few bodies).
void nt_world_enable_profile(nt_world *world, bool enable);

/// The phase times of the last step (zero while profiling is off).
nt_world_profile nt_world_get_profile(const nt_world *world);

/// 64-bit FNV-1a over every live body's position and velocity (the bytes of x, y,
/// vx, vy as nt_real) in creation order. Same inputs give the same hash.
uint64_t nt_world_hash(const nt_world *world);

/* ---------------------------------------------------------------- bodies */

/// Body definition: fill with nt_default_body_def() then adjust.
typedef struct nt_body_def {
    nt_body_type type;     ///< default NT_BODY_DYNAMIC
    nt_shape shape;        ///< default box of half-size 6 x 6; > 0 and at most NT_MAX_HALF_CELLS cells
    nt_vec2 position;      ///< centre
    nt_vec2 velocity;      ///< units/s (ignored for static bodies)
    nt_real mass;          ///< > 0 for dynamic bodies; ignored otherwise
    nt_real gravity_scale; ///< multiplies the world's gravity; within NT_MAX_GRAVITY_SCALE
    nt_real linear_drag;   ///< >= 0: v *= 1 / (1 + drag * dt) each step
    nt_material material;  ///< default {0.05, 0.3} (N's values)
    uint32_t category;     ///< bits this body is (default 1)
    uint32_t mask;         ///< bits it collides with (default all). Two bodies collide when
                           ///< each one's category meets the other's mask. Mask 0: tiles only.
    bool is_sensor;        ///< reports overlaps (sensor events) instead of colliding with bodies
    bool is_one_way;       ///< a one-way platform: stops bodies (and shape casts) only from above, through a
                           ///< contact whose normal points up from it, and not while they overlap it
    bool enable_sleep;     ///< may fall asleep (default true)
    bool is_awake;         ///< starts awake (default true)
    bool enable_hit_events;///< report hit events (default true)
    void *user_data;
} nt_body_def;

/// Default body definition (a dynamic 12 x 12 box of mass 1 at the origin).
nt_body_def nt_default_body_def(void);

/// Add a body. Errors: NT_ERR_NON_FINITE, NT_ERR_SHAPE_TOO_LARGE (half-size or radius above
/// NT_MAX_HALF_CELLS cells), NT_ERR_OUT_OF_RANGE (position farther than NT_WORLD_REACH_CELLS
/// from the map; a body above half a cell not wholly inside the map; a dynamic body's mass
/// outside [NT_MIN_MASS, NT_MAX_MASS]; a gravity scale beyond NT_MAX_GRAVITY_SCALE), NT_ERR_INVALID_ARGUMENT (size <= 0, circle with
/// unequal halves, mass <= 0 for a dynamic body, negative drag, friction or bounce out of range, unknown enum),
/// NT_ERR_LIMIT (NT_MAX_BODIES bodies), NT_ERR_OUT_OF_MEMORY. On failure *out is the null id.
nt_status nt_body_create(nt_world *world, const nt_body_def *def, nt_body_id *out);

/// Remove a body; bodies touching it wake up.
nt_status nt_body_destroy(nt_world *world, nt_body_id id);

/// True when the handle names a live body of this world.
bool nt_body_is_valid(const nt_world *world, nt_body_id id);

/// The body's type.
nt_body_type nt_body_get_type(const nt_world *world, nt_body_id id);

/// The body's shape.
nt_shape nt_body_get_shape(const nt_world *world, nt_body_id id);

/// The body's mass (0 for static and kinematic bodies).
nt_real nt_body_get_mass(const nt_world *world, nt_body_id id);

/// Centre position.
nt_vec2 nt_body_get_position(const nt_world *world, nt_body_id id);

/// Move the body to a new centre (no collision on the way); wakes it. NT_ERR_OUT_OF_RANGE
/// farther than NT_WORLD_REACH_CELLS cells from the map, or, for a body above half a cell,
/// not wholly inside the map.
nt_status nt_body_set_position(nt_world *world, nt_body_id id, nt_vec2 position);

/// Velocity in units/s.
nt_vec2 nt_body_get_velocity(const nt_world *world, nt_body_id id);

/// Set the velocity (dynamic or kinematic); wakes the body.
nt_status nt_body_set_velocity(nt_world *world, nt_body_id id, nt_vec2 velocity);

/// Change a dynamic body's velocity by impulse / mass; wakes it.
nt_status nt_body_apply_impulse(nt_world *world, nt_body_id id, nt_vec2 impulse);

/// The body's material.
nt_material nt_body_get_material(const nt_world *world, nt_body_id id);

/// Set the body's material (checked against the world's friction model).
nt_status nt_body_set_material(nt_world *world, nt_body_id id, nt_material material);

/// Set gravity scale (finite, within NT_MAX_GRAVITY_SCALE, else NT_ERR_OUT_OF_RANGE).
nt_status nt_body_set_gravity_scale(nt_world *world, nt_body_id id, nt_real scale);

/// Set linear drag (finite, >= 0).
nt_status nt_body_set_linear_drag(nt_world *world, nt_body_id id, nt_real drag);

/// Set collision category and mask bits; wakes the body.
nt_status nt_body_set_filter(nt_world *world, nt_body_id id, uint32_t category, uint32_t mask);

/// Category bits.
uint32_t nt_body_get_category(const nt_world *world, nt_body_id id);

/// Mask bits.
uint32_t nt_body_get_mask(const nt_world *world, nt_body_id id);

/// True when the body is simulated (false for static bodies and sleeping ones).
bool nt_body_is_awake(const nt_world *world, nt_body_id id);

/// Wake a body (with every body asleep in its group), or put this body alone to sleep
/// (bodies touching it stay awake and treat it as static until it wakes).
nt_status nt_body_set_awake(nt_world *world, nt_body_id id, bool awake);

/// Allow or forbid sleeping for this body; forbidding wakes it.
nt_status nt_body_enable_sleep(nt_world *world, nt_body_id id, bool enable);

/// The user pointer.
void *nt_body_get_user_data(const nt_world *world, nt_body_id id);

/// Set the user pointer.
nt_status nt_body_set_user_data(nt_world *world, nt_body_id id, void *user_data);

/// What a body touched in the tiles during the last step. Each surface is one of: a
/// floor (its normal within the world's floor_angle of straight up: by default slopes
/// up to 50 degrees, so 45 is a floor and 63.4 a wall), a ceiling (within floor_angle
/// of straight down), or a wall: on the left when it pushes to the right (normal x > 0),
/// on the right otherwise.
typedef struct nt_body_tile_contacts {
    bool on_floor;
    nt_vec2 floor_normal; ///< the floor's normal when on_floor, else (0, 0)
    bool on_ceiling;
    bool wall_left;
    bool wall_right;
    int count;                      ///< 0, 1 or 2 surfaces
    nt_tile_contact contacts[2];    ///< normal, depth at detection, cell
} nt_body_tile_contacts;

/// The tile contacts of the body after the last step.
nt_status nt_body_get_tile_contacts(const nt_world *world, nt_body_id id, nt_body_tile_contacts *out);

/// A contact between two bodies, as one of them sees it.
typedef struct nt_body_contact {
    nt_body_id other; ///< the other body
    nt_vec2 normal;   ///< unit normal pushing this body away from the other (y < 0: the other is below)
    nt_real depth;    ///< overlap when the contact was found (world units; slightly negative within the skin)
} nt_body_contact;

/// The bodies touching this one after the last step (overlapping, within the skin, or
/// met this step: those that begin events report; sensor overlaps are not listed), in
/// the order of the other body's slot. Writes at most `capacity` of them to `out` (NULL
/// with capacity 0 only counts) and the number there are to *count. A sleeping body
/// keeps its contacts. Costs a pass over the world's contacts.
nt_status nt_body_get_contacts(const nt_world *world, nt_body_id id, nt_body_contact *out, int capacity, int *count);

/* ---------------------------------------------------------------- events */

/// Two bodies started to touch: overlap, come closer than the skin, or close the gap
/// between them during this step (reported in the step the collision happens).
typedef struct nt_contact_begin_event {
    nt_body_id a, b;  ///< a was created in the lower slot
    nt_vec2 normal;   ///< from a towards b
    nt_real depth;
} nt_contact_begin_event;

/// Two bodies stopped touching, or one of them was destroyed (ids as they were).
typedef struct nt_contact_end_event {
    nt_body_id a, b;
} nt_contact_end_event;

/// A body hit a tile (b is null) or another body with an approach speed of at least
/// the world's hit_event_threshold.
typedef struct nt_hit_event {
    nt_body_id a, b;
    int cell_x, cell_y; ///< the tile's cell (tile hits)
    nt_vec2 normal;     ///< tile: the surface normal; bodies: from a towards b
    nt_real speed;      ///< approach speed along the normal
} nt_hit_event;

/// The contact events of the last step. Begin and end events are sorted by
/// (a's slot, b's slot); hit events come in a fixed order. Valid until the next call
/// that changes the world.
typedef struct nt_contact_events {
    const nt_contact_begin_event *begin_events;
    int begin_count;
    const nt_contact_end_event *end_events;
    int end_count;
    const nt_hit_event *hit_events;
    int hit_count;
} nt_contact_events;

/// Contact events of the last step.
nt_contact_events nt_world_get_contact_events(const nt_world *world);

/// A body started or stopped overlapping a sensor (strict overlap). A sensor sees
/// every non-sensor body its filter accepts; it exerts no force and feels none from
/// bodies (its type still decides how it moves).
typedef struct nt_sensor_event {
    nt_body_id sensor, visitor;
} nt_sensor_event;

/// The sensor events of the last step, sorted like contact events.
typedef struct nt_sensor_events {
    const nt_sensor_event *begin_events;
    int begin_count;
    const nt_sensor_event *end_events;
    int end_count;
} nt_sensor_events;

/// Sensor events of the last step.
nt_sensor_events nt_world_get_sensor_events(const nt_world *world);

/* ---------------------------------------------------------------- queries */

/// Most bodies a query filter can name in `ignore`.
#define NT_QUERY_IGNORE_MAX 4

/// Which bodies a query sees: those whose category meets `mask` (sensors never), that
/// are not named in `ignore` and that `accept` (when set) returns true for. Bodies with
/// a zero mask or category are not in the broad phase and are never reported. Start
/// from nt_default_query_filter(), or name only mask and tiles in an initializer: the
/// fields after `tiles` are then zero (no ignored body, no callback, one-way cells
/// honoured). Used by ray casts, point and box queries and shape casts (a moving body
/// names itself in `ignore`, so that it never hits itself).
typedef struct nt_query_filter {
    uint32_t mask;
    bool tiles;       ///< ray casts and shape casts: include the tiles
    int ignore_count; ///< how many of ignore[] are used, 0..NT_QUERY_IGNORE_MAX (others: none)
    nt_body_id ignore[NT_QUERY_IGNORE_MAX]; ///< bodies the query never reports
    /// Called for each body that passes the tests above, before any geometry test (a
    /// shape cast may ask twice about a body); return false to skip the body. NULL:
    /// every such body is seen. It must not change the world.
    bool (*accept)(nt_body_id id, void *context);
    void *accept_context; ///< passed to accept
    bool one_way_off;     ///< shape casts: one-way cells and one-way bodies stop nothing (a character dropping through them)
} nt_query_filter;

/// All bodies and the tiles, nothing ignored, no callback.
nt_query_filter nt_default_query_filter(void);

/// A world ray hit: a tile (body is null) or a body.
typedef struct nt_world_ray_hit {
    nt_body_id body;
    nt_real fraction;   ///< t in [0, 1] along p0 -> p1
    nt_vec2 point;
    nt_vec2 normal;     ///< outward normal; (0, 0) when p0 is inside
    int cell_x, cell_y; ///< the tile's cell (tile hits)
} nt_world_ray_hit;

/// Closest thing the segment p0 -> p1 enters (touching is not entering). False when none.
bool nt_world_raycast(const nt_world *world, nt_vec2 p0, nt_vec2 p1, nt_query_filter filter, nt_world_ray_hit *out);

/// Called for each body found by an overlap query; return false to stop the query.
typedef bool nt_query_fn(nt_body_id id, void *context);

/// Report every body whose shape strictly contains the point. Returns how many were reported.
int nt_world_query_point(const nt_world *world, nt_vec2 point, nt_query_filter filter, nt_query_fn *fn, void *context);

/// Report every body whose shape's interior overlaps the box lo..hi. Returns how many were reported.
int nt_world_overlap_aabb(const nt_world *world, nt_vec2 lo, nt_vec2 hi, nt_query_filter filter, nt_query_fn *fn,
                          void *context);

/* ---------------------------------------------------------------- debug draw */

/// A ray to draw with the world (the world does not remember queries: pass the ones
/// you made, with what nt_world_raycast answered).
typedef struct nt_debug_ray {
    nt_vec2 p0, p1;
    bool hit;             ///< nt_world_raycast returned true
    nt_world_ray_hit result;
} nt_debug_ray;

/// Colours are 0xRRGGBB. Any callback may be NULL: what needs it is skipped.
/// Colours of bodies: awake dynamic 0xe6b34d, asleep 0x808080, static 0x80e680,
/// kinematic 0x8080e6, sensor 0xe680e6.
typedef struct nt_debug_draw {
    /// Closed outline (tiles, broad-phase cells).
    void (*draw_polygon)(const nt_vec2 *vertices, int count, uint32_t color, void *context);
    /// Axis-aligned box (box bodies).
    void (*draw_box)(nt_vec2 lo, nt_vec2 hi, uint32_t color, void *context);
    /// Circle outline (circle bodies).
    void (*draw_circle)(nt_vec2 center, nt_real radius, uint32_t color, void *context);
    /// Line segment (edges, rays).
    void (*draw_segment)(nt_vec2 p0, nt_vec2 p1, uint32_t color, void *context);
    /// Vector from p0 with its tip at p1 (normals, projections, velocities).
    void (*draw_arrow)(nt_vec2 p0, nt_vec2 p1, uint32_t color, void *context);
    /// A point (ray hits, contact points).
    void (*draw_point)(nt_vec2 p, uint32_t color, void *context);
    /// A short text at p (statistics).
    void (*draw_text)(nt_vec2 p, const char *text, uint32_t color, void *context);
    /// Only draw what overlaps lo..hi when use_bounds is set.
    nt_vec2 bounds_lo, bounds_hi;
    bool use_bounds;
    bool draw_tiles;           ///< tile outlines
    bool draw_edges;           ///< SOLID edges (red) and INTERESTING edges (yellow)
    bool draw_grid;            ///< broad-phase cells that hold bodies (coarser levels a lighter blue)
    bool draw_bodies;          ///< bodies, coloured by type and state
    bool draw_velocities;      ///< velocity x 0.1 s (arrow, else segment)
    bool draw_velocity_split;  ///< for bodies on a tile: normal and tangential parts of the velocity
    bool draw_contacts;        ///< body contact normals (from a towards b) at the midpoint
    bool draw_tile_contacts;   ///< tile contact normals, half a cell long
    bool draw_projections;     ///< last projection vector per contact: normal x depth x projection_scale
    bool draw_stats;           ///< one line of counters at bounds_lo (or the origin)
    nt_real projection_scale;  ///< see draw_projections (default 1: true length)
    const nt_debug_ray *rays;  ///< rays to draw: segment, hit point and normal
    int ray_count;
    void *context;
} nt_debug_draw;

/// No callbacks, no rays; tiles and bodies on, everything else off; projection_scale 1.
nt_debug_draw nt_default_debug_draw(void);

/// Draw the world through the callbacks. The world is locked while they run.
void nt_world_draw(const nt_world *world, const nt_debug_draw *draw);

/// True while the world runs one of its callbacks (nt_world_draw's, a query's nt_query_fn,
/// a query filter's accept in ray casts, shape casts and overlap queries), as Box2D's
/// b2World_IsLocked. Every call that would change the world made then (creating or
/// destroying bodies, setters, tiles, materials, steps, characters) returns
/// NT_ERR_LOCKED and changes nothing; nt_world_destroy and nt_world_enable_profile are
/// ignored. Reading the world and nested queries are allowed.
bool nt_world_is_locked(const nt_world *world);

#ifdef __cplusplus
}
#endif

#endif
