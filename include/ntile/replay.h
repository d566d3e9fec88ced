/* ntile — replays: the .ntr text format (parser and canonical writer).
 *
 * A replay names a level file, the random seed, the step dt, the number of ticks and
 * the input bitmask of every tick (run-length encoded), plus what must come out:
 * facts ("level complete by tick N", "player inside region R at tick N", "score at
 * least K", "no body inside solid", "momentum conserved within X", ...) and state
 * hashes at chosen ticks, optionally with a per-tick trace of 32-bit hashes that
 * locates the first tick where a run diverges. Running one is the game layer's job
 * (nt_run_replay in ntile/game.h; `ntile run` on the command line); this part is
 * plain data and text, with no file system access. Errors are reported as by the
 * level parser (level.h): "NAME:LINE:COL: message" in an nt_text_error.
 *
 * THE .ntr FORMAT (version NT_REPLAY_VERSION)
 *
 * Text, one statement a line, fields separated by spaces, '#' starts a comment; a
 * UTF-8 byte order mark at the start is skipped. The first line is the header:
 *     ntile-replay 1
 * Settings, each at most once, in any order:
 *     level PATH                      required: the .ntl file, relative to this file
 *     ticks N                         required, before any input, expect, hash or
 *                                     trace line: 1..NT_REPLAY_MAX_TICKS
 *     name NAME                       shown by the runner [the file name]
 *     seed N                          overrides the level's seed
 *     dt SECONDS                      seconds per tick, NT_MIN_DT..NT_MAX_DT [1/40]
 *     friction-model n|coulomb        overrides the level's model
 * PATH and NAME are bare words or "quoted" (no escapes, no '"' inside).
 *
 * Inputs (any number of lines, appended in order):
 *     input COUNTKEYS ...             COUNT ticks holding KEYS: letters L R U D J A
 *                                     (left, right, up, down, jump, action; the
 *                                     NT_INPUT_* bits), or '.' for none
 * "30R 8RJ 12." is 30 ticks of right, 8 of right + jump, 12 of nothing. Ticks after
 * the last input have no keys. Actions happen on presses: holding J jumps once.
 *
 * Facts:
 *     expect [not] FACT WHEN
 * WHEN is `at T`, `by T` (at some tick from 0 to T) or `always`; tick 0 is the state
 * before the first step. FACT is one of
 *     complete                        the player has reached an exit
 *     alive                           the player is alive
 *     inside REGION [body NAME]       the player's (or the level body's) centre is in REGION
 *     no-body-in-solid                no dynamic body more than 1e-3 cell inside a tile
 *                                     (one-way cells excluded)
 *     score OP V                      OP is >=, <= or ==
 *     bodies OP V                     live bodies
 *     spawned OP V                    bodies spawned so far
 *     energy-ratio OP V               kinetic energy of the dynamic bodies / its value at tick 0
 *     momentum-drift OP V             |P - P0| / sum(m |v0|) over the dynamic bodies
 *
 * State hashes, one set per scalar build (float and double builds compute different
 * bits; a build checks only its own lines), written by `ntile run --record-hashes`:
 *     hash float|double TICK 0xHHHHHHHHHHHHHHHH    nt_game_hash after tick TICK
 *     trace float|double FIRST H1 H2 ...           32-bit hashes (8 hex digits, no 0x,
 *                                                  nt_trace_fold) of ticks FIRST,
 *                                                  FIRST+1, ...; lines follow on
 *
 * Example (tests/replays/ninja.ntr, trace lines cut):
 *     ntile-replay 1
 *     name ninja
 *     level ../../levels/ninja.ntl
 *     ticks 620
 *     input 300R 40J 30. 40J 30. 25LJ 15L 30RJ 80R
 *     expect complete by 600
 *     expect score >= 7 at 620
 *     expect alive always
 *     expect inside lift_top at 262
 *     expect no-body-in-solid always
 *     hash float 620 0x37faa18dac3ee1bb
 *     trace float 1 a994df19 01f53ad5 5a66c872 4c3336b0 a54dc7b9 2b08020c 1badf5f9 6a21770b
 *
 * nt_replay_write gives the canonical text (same contract as nt_level_write).
 */
#ifndef NTILE_REPLAY_H
#define NTILE_REPLAY_H

#include "base.h"
#include "level.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Format version written by nt_replay_write and accepted by nt_replay_parse.
#define NT_REPLAY_VERSION 1
/// Longest level path plus its NUL.
#define NT_REPLAY_PATH_MAX 1024
/// Most ticks in one replay.
#define NT_REPLAY_MAX_TICKS 100000000

/// Input bits: one per key, as the replay letters L R U D J A.
enum {
    NT_INPUT_LEFT = 1u << 0,   ///< L
    NT_INPUT_RIGHT = 1u << 1,  ///< R
    NT_INPUT_UP = 1u << 2,     ///< U
    NT_INPUT_DOWN = 1u << 3,   ///< D
    NT_INPUT_JUMP = 1u << 4,   ///< J
    NT_INPUT_ACTION = 1u << 5  ///< A
};

/// `count` consecutive ticks with the same keys.
typedef struct nt_replay_input {
    int count;
    uint32_t keys;
} nt_replay_input;

/// What a fact is about.
typedef enum nt_fact_kind {
    NT_FACT_COMPLETE = 0,        ///< the level is complete (player reached an exit)
    NT_FACT_ALIVE = 1,           ///< the player is alive
    NT_FACT_INSIDE = 2,          ///< the player's (or `body`'s) centre is inside `region`
    NT_FACT_NO_BODY_IN_SOLID = 3,///< no dynamic body is more than 1e-3 cell inside a solid tile
    NT_FACT_SCORE = 4,           ///< score OP value
    NT_FACT_BODIES = 5,          ///< live body count OP value
    NT_FACT_SPAWNED = 6,         ///< bodies spawned so far OP value
    NT_FACT_ENERGY_RATIO = 7,    ///< kinetic energy / kinetic energy at tick 0 OP value
    NT_FACT_MOMENTUM_DRIFT = 8   ///< |P - P0| / sum(m |v0|) OP value (dynamic bodies)
} nt_fact_kind;

/// When a fact is checked.
typedef enum nt_fact_when {
    NT_WHEN_AT = 0,    ///< at tick `tick`
    NT_WHEN_BY = 1,    ///< at some tick from 0 to `tick`
    NT_WHEN_ALWAYS = 2 ///< at every tick of the replay
} nt_fact_when;

/// How a numeric fact compares.
typedef enum nt_fact_op { NT_OP_GE = 0, NT_OP_LE = 1, NT_OP_EQ = 2 } nt_fact_op;

/// One `expect` line.
typedef struct nt_replay_fact {
    nt_fact_kind kind;
    bool negate;                      ///< `expect not ...`
    nt_fact_when when;
    int tick;
    nt_fact_op op;                    ///< numeric facts
    double value;                     ///< numeric facts
    char region[NT_LEVEL_NAME_MAX];   ///< NT_FACT_INSIDE
    char body[NT_LEVEL_NAME_MAX];     ///< NT_FACT_INSIDE: a level body, or "" for the player
    int line;                         ///< source line (for messages), 0 if built by hand
} nt_replay_fact;

/// The state hash expected after tick `tick` (0 = before the first step) in one
/// scalar build: float and double builds compute different bits, so a replay keeps
/// a set of hashes (and a trace) for each, and a build checks its own.
typedef struct nt_replay_hash {
    int tick;
    bool is_double; ///< written `hash double TICK ...`, else `hash float TICK ...`
    uint64_t hash;
    int line;
} nt_replay_hash;

/// A replay. Build one with nt_replay_parse or nt_replay_create.
typedef struct nt_replay {
    char name[NT_LEVEL_NAME_MAX + 32];  ///< shown by the runner ("" = use the file name)
    char level[NT_REPLAY_PATH_MAX];     ///< level file, relative to the replay's directory
    bool has_seed;
    uint64_t seed;                      ///< overrides the level's seed when has_seed
    nt_real dt;                         ///< seconds per tick, in [NT_MIN_DT, NT_MAX_DT] (default 1/40)
    int ticks;                          ///< ticks to run, 1..NT_REPLAY_MAX_TICKS
    bool has_friction_model;
    nt_friction_model friction_model;   ///< overrides the level's when has_friction_model
    int input_count, fact_count, hash_count;
    nt_replay_input *inputs;            ///< cover at most `ticks` ticks; later ticks have no keys
    nt_replay_fact *facts;
    nt_replay_hash *hashes;             ///< float ones first, then double ones; ticks increase within each
    int trace_count[2];                 ///< [0] float build, [1] double build; at most `ticks`
    uint32_t *trace[2];                 ///< trace[b][k] = 32-bit hash after tick k + 1 in build b
} nt_replay;

/// An empty replay of `ticks` ticks at dt 1/40 with no level, inputs or expectations.
nt_status nt_replay_create(int ticks, nt_replay **out);

/// Free a replay (NULL is ignored).
void nt_replay_destroy(nt_replay *replay);

/// Parse a .ntr text; on failure *out is NULL and `error` says where and why.
/// A UTF-8 byte order mark at the start of the text is skipped.
nt_status nt_replay_parse(const char *name, const char *text, size_t length, nt_replay **out, nt_text_error *error);

/// Write the canonical .ntr text (same contract as nt_level_write).
size_t nt_replay_write(const nt_replay *replay, char *buf, size_t cap);

/// Replace the replay's inputs with those of an input string ("30R 8RJ 12." : COUNT then
/// key letters, '.' for none), as on an `input` line. An empty string means no keys.
nt_status nt_replay_set_inputs(nt_replay *replay, const char *name, const char *text, size_t length, nt_text_error *error);

/// Replace the expected hashes and the trace of one scalar build (0 float, 1 double)
/// with copies; the other build's are kept. trace may be NULL with count 0.
nt_status nt_replay_set_hashes(nt_replay *replay, int is_double, const nt_replay_hash *hashes, int hash_count,
                               const uint32_t *trace, int trace_count);

/// Keys of tick `tick` (1-based: the keys held during the tick-th step).
uint32_t nt_replay_keys_at(const nt_replay *replay, int tick);

/// The 32-bit trace value of a 64-bit state hash (high half xor low half).
static inline uint32_t nt_trace_fold(uint64_t hash) { return (uint32_t)(hash >> 32) ^ (uint32_t)hash; }

#ifdef __cplusplus
}
#endif

#endif
