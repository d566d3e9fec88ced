/* Internals shared by the game layer's sources (game.c, player.c, runner.c). */
#ifndef NT_GAME_INTERNAL_H
#define NT_GAME_INTERNAL_H

#include "ntile/character.h"
#include "ntile/game.h"

#if defined(__FLT_EVAL_METHOD__) && __FLT_EVAL_METHOD__ != 0
#error "ntile needs FLT_EVAL_METHOD 0 (no excess precision): on 32-bit x86 build with -msse2 -mfpmath=sse"
#endif

/* What made a body. */
enum { GB_LEVEL = 0, GB_PLAYER = 1, GB_SPAWNED = 2, GB_ADDED = 3 };

typedef struct game_body {
    nt_body_id id;
    int source;     /* GB_* */
    int level_body; /* index into the level's bodies (level and spawned bodies), else -1 */
    bool alive;
} game_body;

/* The controller's memory between ticks. */
typedef struct player_state {
    bool jumping;        /* a jump is rising with the button held */
    int since_floor;     /* ticks since the player last stood on a floor */
    int since_wall;      /* ticks since it last touched a wall */
    int wall_away;       /* +1: the last wall was on the left (jump right); -1: on the right */
    bool on_floor, wall_left, wall_right; /* sensed after the last step */
    nt_vec2 vel;         /* the controller's velocity, relative to the floor body stood on */
    nt_real run;         /* the run speed along floors */
    nt_vec2 shown;       /* the velocity given to the body after the step (world frame) */
    nt_character_result move; /* the last move */
} player_state;

struct nt_game {
    const nt_level *level;
    nt_game_def def;
    nt_world *world;
    nt_real cell;
    game_body *bodies; /* creation order */
    int body_count, body_cap;
    int *slot_record;  /* body slot (index1 - 1) -> index in bodies, or -1 */
    int slot_cap;
    int *level_first;  /* level body -> record of its first instance, or -1 */
    int player_record; /* -1 without a player */
    player_state ps;
    uint32_t prev_keys;
    int *spawn_counts; /* per spawner */
    nt_rng rng;
    double time;       /* seconds stepped, for paths */
    int tick, score, complete_tick, death_tick, spawned;
    bool complete, dead;
    bool has_score_or_kill; /* some region acts on bodies other than the player */
    bool *switch_on;        /* per region: the switch is on; NULL when the level has no switch */
    bool has_one_way;       /* some level body is a one-way body of the game layer */
    /* Undo of a step that fails (nt_alloc'd; reserved before the step changes anything). */
    int *saved_spawn_counts;  /* per spawner */
    nt_vec2 *saved_path_vel;  /* per path body, in record order */
    int path_cap;
    nt_body_id *touched;      /* apply_events' copy of the player's touches */
    int touched_cap;
};

/* The record of a live body, or NULL. */
game_body *nt__game_record(const nt_game *g, nt_body_id id);

/* Read the player's surroundings after a step: floor (from the move), walls, timers (player.c). */
void nt__player_sense(nt_game *g);

/* Steer the player from the keys and move it with the character mover, before the world step (player.c). */
void nt__player_control(nt_game *g, uint32_t keys, nt_real dt);

/* The static and kinematic bodies (sensors aside) within a hundredth of a cell of the
 * player: the world step makes no contacts between them and a character, so touches
 * of solid gold and deadly bodies are found here (player.c). Writes at most cap, returns
 * how many there are. */
int nt__player_touches(const nt_game *g, nt_body_id *out, int cap);

#endif
