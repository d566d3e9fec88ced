/* ntile game layer (libntile-game) — a loaded level made playable, one tick at a time.
 *
 * This is a separate library beside the engine: it uses only the public engine API
 * (ntile.h), and the engine never includes it. The headless runner (`ntile run`)
 * and the SDL playground share it.
 *
 * A game owns a world built from a level (nt_level_create_world), the player (a
 * circle driven by a controller in the spirit of N's ninja), and the level's
 * objects: exits, gold and score regions that count, deadly bodies and kill zones,
 * spawners, and kinematic bodies moving along paths. nt_game_step advances it by
 * one tick from an input bitmask (NT_INPUT_* in replay.h). Everything is
 * deterministic: bodies are created and visited in a fixed order, and the random
 * source (nt_rng) is seeded from the level's seed or the replay's.
 *
 * Tick order: (1) paths set the kinematic velocities that land their bodies on the
 * path at the end of the tick; (2) spawners fire; (3) the controller steers the
 * player from the keys and what it met last tick, and moves it with the character
 * mover (nt_character_move: floor snap, slopes, steps, platforms, one-way floors);
 * (4) the world steps (the player is a character: the step does not move it, and
 * pushes the dynamic bodies it walked into); (5) touches (sensor and contact events,
 * and the solid static or kinematic bodies within a hundredth of a cell of the
 * player: gold, deadly bodies), then regions (exit, score, kill), are applied.
 *
 * The player: left/right run, jump (held: higher), a wall slide and wall jump, and
 * down + jump drops through the one-way floor underfoot. A dead player takes no
 * input: it falls and comes to rest. After each tick nt_body_get_velocity(player)
 * reads its velocity in the world's frame; a velocity set there between ticks
 * replaces the controller's.
 */
#ifndef NTILE_GAME_H
#define NTILE_GAME_H

#include "ntile.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------- random source */

/// A small deterministic random source (splitmix64). The same seed gives the same
/// numbers on every platform and in both scalar builds.
typedef struct nt_rng {
    uint64_t state;
} nt_rng;

/// Start the sequence at `seed`.
void nt_rng_seed(nt_rng *rng, uint64_t seed);

/// Next 32 random bits.
uint32_t nt_rng_next(nt_rng *rng);

/// A number in [lo, hi) made from 24 random bits (exact in float and double).
nt_real nt_rng_range(nt_rng *rng, nt_real lo, nt_real hi);

/* ---------------------------------------------------------------- the player */

/// Player controller constants, in cells and seconds (multiplied by the level's
/// cell size). Gravity is the world's. Defaults are tuned for N's scale: at
/// 24-unit cells and gravity 320 the ninja runs 150 units/s and a held jump rises
/// jump_speed^2 / (2 g jump_gravity_scale) = 3.5 cells.
typedef struct nt_player_def {
    nt_real radius;             ///< cells, > 0 and at most 0.5 (N's ninja: 10/24). The player stays
                                ///< small: its controller (floor probe, wall sensing) is tuned for
                                ///< a ninja; other bodies may be up to NT_MAX_HALF_CELLS cells.
    nt_real mass;               ///< > 0; the player is a character, infinitely heavy to what it pushes: kept for the body's record
    nt_real run_speed;          ///< cells/s, top speed from input
    nt_real ground_accel;       ///< cells/s^2 toward run speed on the ground
    nt_real ground_decel;       ///< cells/s^2 toward rest on the ground with no direction held
    nt_real skid_decel;         ///< cells/s^2 on the ground when the held direction opposes the motion
    nt_real air_accel;          ///< cells/s^2 in the air
    nt_real air_decel;          ///< cells/s^2 in the air with no direction held
    nt_real jump_speed;         ///< cells/s upwards
    nt_real jump_gravity_scale; ///< gravity multiplier while jump is held and the player rises (variable height)
    nt_real wall_slide_speed;   ///< cells/s: the fall speed while pressing into a wall
    nt_real wall_jump_speed_x;  ///< cells/s away from the wall
    nt_real wall_jump_speed_y;  ///< cells/s upwards
    nt_real max_fall_speed;     ///< cells/s
    nt_real grace_time;         ///< s: a jump still counts this long after leaving a floor or wall
    nt_real bouncy_threshold;   ///< tiles with bounce above this launch the player; others absorb its bounce
    nt_character_def mover;     ///< the character mover's settings (character.h; default nt_default_character_def()),
                                ///< checked like nt_character_create's (else NT_ERR_INVALID_ARGUMENT)
} nt_player_def;

/// The defaults described above.
nt_player_def nt_default_player_def(void);

/* ---------------------------------------------------------------- the game */

/// Game definition: fill with nt_default_game_def() then adjust.
typedef struct nt_game_def {
    bool override_seed;                 ///< use `seed` instead of the level's
    uint64_t seed;
    bool override_friction_model;       ///< use `friction_model` instead of the level's
    nt_friction_model friction_model;
    nt_player_def player;
} nt_game_def;

/// No overrides, the default player.
nt_game_def nt_default_game_def(void);

typedef struct nt_game nt_game;

/// What the game knows after the last tick.
typedef struct nt_game_state {
    int tick;           ///< ticks stepped so far
    int score;
    bool complete;      ///< the player reached an exit
    int complete_tick;  ///< the tick it happened, or -1
    bool has_player;
    bool alive;         ///< the player is alive (false without a player)
    int death_tick;     ///< the tick the player died, or -1
    int spawned;        ///< bodies created by spawners so far
    bool on_floor;      ///< the player stood on a floor (tile or body) after the last step
    bool wall_left, wall_right; ///< the player touched a wall after the last step
} nt_game_state;

/// Build a game from a level (which must outlive the game); def NULL: nt_default_game_def().
/// On failure *out is NULL.
/// Bodies on paths start where their path puts them at time 0: one above half a cell
/// must lie wholly inside the map there (else NT_ERR_OUT_OF_RANGE, as the world
/// requires); so must a large body a spawner creates (nt_game_step fails otherwise).
nt_status nt_game_create(const nt_level *level, const nt_game_def *def, nt_game **out);

/// Destroy a game and its world (NULL is ignored).
void nt_game_destroy(nt_game *game);

/// Advance one tick of dt seconds (in [NT_MIN_DT, NT_MAX_DT], else NT_ERR_OUT_OF_RANGE and
/// nothing changes) with the keys held (NT_INPUT_* bits). All or nothing: a step that
/// fails (NT_ERR_OUT_OF_MEMORY, NT_ERR_LIMIT from the world step) undoes what the tick
/// did before the world step (spawned bodies, the player's move, path velocities, the
/// tick, spawn counts, the random state): nt_game_hash is what it was, and the same call
/// can be made again. Memory comes from the allocator hook (nt_set_allocator).
nt_status nt_game_step(nt_game *game, uint32_t keys, nt_real dt);

/// The game's world, for drawing and queries. Change bodies and tiles through the
/// game (nt_game_add_body, nt_game_remove_body, nt_game_set_tile) so that its records
/// stay right; setting velocities, impulses or materials directly is fine.
nt_world *nt_game_get_world(const nt_game *game);

/// Create a body in the game's world and count it as the game's (nt_game_get_bodies,
/// score and kill regions); it has no level role. Any size the world accepts (half-size
/// up to NT_MAX_HALF_CELLS cells), as for level bodies. On failure (the statuses of
/// nt_body_create, e.g. NT_ERR_SHAPE_TOO_LARGE) nothing changes and *out is null.
nt_status nt_game_add_body(nt_game *game, const nt_body_def *def, nt_body_id *out);

/// Remove a body of the game (level, spawned or added) from the world and the game's
/// records. NT_ERR_INVALID_ID for a body that is not the game's or no longer exists;
/// NT_ERR_INVALID_ARGUMENT for the player, whom the controller needs.
nt_status nt_game_remove_body(nt_game *game, nt_body_id body);

/// Set the tile of cell (x, y) (nt_world_set_tile: edges refreshed, bodies around it woken).
nt_status nt_game_set_tile(nt_game *game, int x, int y, int tile);

/// The level the game was built from.
const nt_level *nt_game_get_level(const nt_game *game);

/// The player's body, or the null handle when the level has no player.
nt_body_id nt_game_get_player(const nt_game *game);

/// State after the last tick.
nt_game_state nt_game_get_state(const nt_game *game);

/// 64-bit FNV-1a over the world hash and the game's own state (tick, score, flags,
/// controller, spawner counts, random source). Same inputs give the same hash.
uint64_t nt_game_hash(const nt_game *game);

/// The first body created for the level body called `name` (null when unknown or removed).
nt_body_id nt_game_find_body(const nt_game *game, const char *name);

/// Every live body the game created, in creation order (level bodies, player,
/// spawned). Writes at most `cap` handles and returns how many there are.
int nt_game_get_bodies(const nt_game *game, nt_body_id *out, int cap);

/// True when the body's centre lies in region `region` (index into the level's
/// regions), edges included.
bool nt_game_body_in_region(const nt_game *game, nt_body_id body, int region);

/// True when region `region` is a switch the player has turned on (its exit and doors
/// are open, its trap doors closed).
bool nt_game_switch_is_on(const nt_game *game, int region);

/// The position of a path at `time` seconds from the start for a body with `phase`.
nt_vec2 nt_path_position(const nt_level_path *path, double time, double phase);

/* ---------------------------------------------------------------- running replays */

/// Most failure messages a report keeps (the count goes on).
#define NT_RUN_MAX_MESSAGES 16

/// The outcome of running a replay.
typedef struct nt_run_report {
    bool passed;
    int ticks;                ///< ticks run
    int failure_count;        ///< fact_failures + hash_failures
    int fact_failures;        ///< facts that did not hold (or could not be checked)
    int hash_failures;        ///< recorded hashes or trace values that differ
    int message_count;        ///< messages kept (at most NT_RUN_MAX_MESSAGES)
    char messages[NT_RUN_MAX_MESSAGES][320];
    bool message_is_hash[NT_RUN_MAX_MESSAGES]; ///< the message is about hashes, not facts
    uint64_t *hashes;         ///< hashes[t] = nt_game_hash after tick t, t = 0..ticks
    int first_divergence;     ///< first tick whose hash differs from the recorded trace or hashes, or -1
    nt_game_state final_state;
} nt_run_report;

/// Run a replay on a level (already loaded; the replay's `level` line is the caller's
/// business). Fills *report (free it with nt_run_report_free). Returns NT_OK when the
/// replay ran, whether or not its expectations held; an error when it could not run.
nt_status nt_run_replay(const nt_replay *replay, const nt_level *level, nt_run_report *report);

/// Free what a report owns.
void nt_run_report_free(nt_run_report *report);

#ifdef __cplusplus
}
#endif

#endif
