/* ntile — levels: the .ntl text format, its canonical writer, N v1.4 import, and
 * building a world from a level.
 *
 * A level is plain data (nt_level): map size and cell size, the tile grid, per-cell
 * materials and one-way flags, world settings, bodies, named regions, kinematic
 * paths, spawners and the player spawn. The engine uses the map, the settings and
 * the bodies (nt_level_create_world); regions, paths, spawners and the player are
 * read by the game layer (ntile/game.h, a separate library).
 *
 * Parsers take a name (used in messages only), a buffer and its length: nothing
 * here touches the file system. A parser that fails returns NT_ERR_PARSE (or
 * NT_ERR_OUT_OF_MEMORY), sets *out to NULL, frees everything it built, and fills an
 * nt_text_error with "NAME:LINE:COL: message" pointing at the field at fault, e.g.
 *     levels/x.ntl:7:3: unknown tile code 'z' (expected '.', '#' or an N code '2'..'Q', see the legend)
 *     levels/x.ntl:12:23: radius '99' is larger than the largest half-size, 4 cells (96)
 *     levels/x.ntl:14:6: duplicate name 'lift' (first defined at line 11)
 *     levels/x.ntl:26:1: unexpected end of file: the 'tiles' block has 20 of 25 rows
 *
 * THE .ntl FORMAT (version NT_LEVEL_VERSION)
 *
 * Text, one statement a line, fields separated by spaces. '#' starts a comment to
 * the end of the line (outside grid rows, where '#' is the FULL tile). Strings are
 * "quoted" (no escapes, no '"' inside). Numbers are decimal (finite: nan, inf and
 * 1e999 are errors); category and mask also take 0x hex. A UTF-8 byte order mark at
 * the start is skipped (columns count from after it). Order: the header line,
 * settings, the grid blocks, then objects.
 *
 *     ntile-level 1
 *
 * Settings (before `tiles`, each at most once; [default]):
 *     title "TEXT"                    [""]      at most NT_LEVEL_TEXT_MAX - 1 bytes
 *     author "TEXT"                   [""]
 *     size W H                        required  cells, 1..NT_MAP_MAX_SIDE (4096)
 *     cell S                          [24]      world units per cell,
 *                                               NT_MIN_CELL_SIZE..NT_MAX_CELL_SIZE
 *     gravity X Y                     [0 320]   units/s^2, y down; each part within NT_MAX_GRAVITY
 *     friction-model n|coulomb        [n]       N's rule or Coulomb's (world.h)
 *     sleep on|off                    [on]
 *     seed N                          [1]       the game layer's random source
 *     material I FRICTION BOUNCE      [0.05 0.3] tile material I in 0..15 (NT_MAX_MATERIALS);
 *                                               unset ones copy material 0; friction at
 *                                               most 1 under the n model
 *     body-material FRICTION BOUNCE   [0.05 0.3] bodies' default material
 *     body-drag D                     [0]       bodies' default linear drag
 *
 * Grid blocks: a keyword line, then exactly H rows of the form |CODES| with W codes
 * (blank lines and comment lines may sit between rows). `tiles` is required;
 * `materials` and `flags` are optional and follow it, same shape.
 *     tiles       '.' EMPTY, '#' FULL, any other tile by N's code '0' + id:
 *                 '2'..'5' 45DEG pn nn np pp, '6'..'9' CONCAVE, ':' ';' '<' '=' CONVEX,
 *                 '>' '?' '@' 'A' 22DEG..S, 'B'..'E' 22DEG..B, 'F'..'I' 67DEG..S,
 *                 'J'..'M' 67DEG..B, 'N' HALFd, 'O' HALFr, 'P' HALFu, 'Q' HALFl
 *                 (nt_level_tile_char, nt_level_tile_from_char; ids and names in tiles.h)
 *     materials   '.' material 0, '1'..'9' and 'a'..'f' materials 1..15
 *     flags       '.' none, '-' one-way (the cell stops bodies from above only)
 *
 * Objects (after the grids). Names: a letter or '_', then letters, digits, '_', '-',
 * '.', at most NT_LEVEL_NAME_MAX - 1 characters; one namespace for all objects; a
 * line can name only objects defined above it.
 *     player X Y
 *         the player's spawn (centre)
 *     region NAME zone|exit|score|kill|switch X0 Y0 X1 Y1 [value N] [needs SWITCH]
 *         exit: the level is complete when the player's centre enters (with needs
 *         SWITCH, a switch region above it: only once that switch is on); score (needs
 *         value): N points for each dynamic body whose centre enters, which is
 *         removed; kill: kills the player, removes other bodies; switch: goes on for
 *         good when the player's centre enters, opening its exits and doors; zone:
 *         only a name
 *     path NAME loop|pingpong speed S [wait W] points X Y X Y ...
 *         2..NT_LEVEL_MAX_PATH_POINTS waypoints; wait: seconds at each
 *     path NAME orbit speed S center X Y radius R
 *         a circle, clockwise on screen
 *     body NAME static|kinematic|dynamic box HW HH|circle R at X Y [OPTIONS]
 *         half-sizes and radius > 0 and at most NT_MAX_HALF_CELLS (4) cells; a body
 *         above half a cell (every copy of a repeat) lies wholly inside the map
 *     spawner NAME TEMPLATE action|every N [start T] limit K [attach BODY]
 *             [offset DX DY] [jitter J]
 *         copies of a template body on each press of the action key, or every N
 *         ticks from tick T; at most K; at BODY's position + offset, else at the
 *         template's; jitter: a random x velocity in [-J, J] (the level's random source)
 *
 * Body options: vel VX VY, mass M, material FRICTION BOUNCE, drag D,
 * gravity-scale S, category C, mask M, sensor, no-sleep, asleep,
 * path NAME [phase P] (kinematic bodies; P in [0, 1) of the path's cycle),
 * score N (a sensor the player collects), deadly (touching it kills the player),
 * template (not created; for spawners), repeat NX NY DX DY (NX x NY copies, DX DY
 * apart; at most NT_LEVEL_MAX_BODIES instances in a level, repeats counted).
 * Doors, one of (solid static or kinematic bodies, not sensors or templates):
 * door (goes away when the player touches it), opened-by SWITCH (a locked door:
 * solid until the switch region is on, then gone), closed-by SWITCH (a trap door:
 * collides with nothing until the switch is on, then solid). one-way
 * right|down|left|up (a solid static or kinematic body, not a door: solid to a
 * player wholly on that side of it, passable for the player from the others;
 * one-way cells, the flags block, stop bodies from above only).
 *
 * A small complete level:
 *     ntile-level 1
 *     title "Hello"
 *     size 8 5
 *     material 1 0.05 1
 *     tiles
 *     |########|
 *     |#......#|
 *     |#...2..#|
 *     |#..2##P#|
 *     |########|
 *     materials
 *     |........|
 *     |........|
 *     |........|
 *     |......1.|
 *     |........|
 *     flags
 *     |........|
 *     |........|
 *     |........|
 *     |......-.|
 *     |........|
 *     player 36 86
 *     region door exit 144 48 168 96
 *     path lift pingpong speed 40 wait 1 points 60 100 60 40
 *     body coin static circle 6 at 100 86 sensor score 1
 *     body lift1 kinematic box 12 4 at 60 100 path lift
 *     body ball dynamic circle 5 at 0 0 template
 *     spawner dropper ball every 40 limit 3 attach lift1 offset 0 -12
 *
 * nt_level_write gives the canonical text: settings in a fixed order, defaults left
 * out, numbers in their shortest exact form, comments not kept; parse, write, parse
 * gives the same level and the same text.
 *
 * N v1.4 IMPORT (nt_level_import_n14). A level is one line $NAME#AUTHOR##TILES|OBJECTS#:
 * 713 tile characters for the 31 x 23 playable cells, column by column, then
 * TYPE^X,Y,... objects in pixels of the 33 x 25 grid. The result is a 33 x 25 level of
 * 24-unit cells with the one-cell FULL border. Objects: player spawn (5) -> player;
 * exit door (11) -> switch region "exitswitch" (one cell around N's switch) and
 * region "exit" (one cell around the door) that needs it; door (9,
 * SX,SY,TRAP,LOCKED,CX,CY,UPRIGHT,OX,OY) -> a static box a cell long and a quarter
 * cell thick through the centre of cell (CX+OX, CY+OY), upright when UPRIGHT is 1: a
 * locked door (opened-by) or trap door (closed-by) with its switch region
 * "doorswitchN" one cell around SX,SY, else a plain door; gold (0) -> static sensor
 * circle r 6, score 1; mine (12) -> static deadly sensor circle r 4; bounce block (1)
 * -> dynamic box 9.6 x 9.6; launch pad (2) -> the tile behind it gets material 1
 * (bounce 1); one-way platform (7) facing up (N's direction 3) -> a one-way HALFu
 * cell, facing right, down or left (0, 1, 2) -> a static box over that half of the
 * cell with one-way right|down|left. The types ntile does not have (gauss turret,
 * floor guard, drone, thwump, rocket launcher) are skipped with a warning that names
 * them, "NAME:LINE:COL: warning: N object type 8 (thwump) is not supported; skipped".
 */
#ifndef NTILE_LEVEL_H
#define NTILE_LEVEL_H

#include "base.h"
#include "map.h"
#include "tiles.h"
#include "world.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Format version written by nt_level_write and accepted by nt_level_parse.
#define NT_LEVEL_VERSION 1
/// Longest object name plus its NUL (names: a letter or '_', then letters, digits, '_', '-', '.').
#define NT_LEVEL_NAME_MAX 32
/// Longest title or author plus its NUL.
#define NT_LEVEL_TEXT_MAX 128
/// Most waypoints in one path.
#define NT_LEVEL_MAX_PATH_POINTS 64
/// Most body instances in one level (repeats counted).
#define NT_LEVEL_MAX_BODIES 1000000
/// Most regions, paths or spawners (each).
#define NT_LEVEL_MAX_OBJECTS 4096

/// Where and why a text input was rejected.
typedef struct nt_text_error {
    int line;          ///< 1-based line, 0 when the error has no position
    int column;        ///< 1-based byte column
    char message[512]; ///< "NAME:LINE:COL: what is wrong", NUL-terminated
} nt_text_error;

/// What a region does (the game layer acts on it; NT_REGION_ZONE only names an area).
typedef enum nt_region_kind {
    NT_REGION_ZONE = 0,  ///< a named area, for expectations
    NT_REGION_EXIT = 1,  ///< the player's centre inside: level complete
    NT_REGION_SCORE = 2, ///< a body's centre inside: score += value once, the body is removed
    NT_REGION_KILL = 3,  ///< the player's centre inside: dead; other dynamic bodies are removed
    NT_REGION_SWITCH = 4 ///< the player's centre inside: the switch is on (for good); it opens exits and doors
} nt_region_kind;

/// A named axis-aligned area, lo..hi in world units.
typedef struct nt_level_region {
    char name[NT_LEVEL_NAME_MAX];
    nt_region_kind kind;
    nt_vec2 lo, hi;
    int value; ///< score regions: points per body
    int needs; ///< exit regions: 1 + index of the switch region that opens it (0: open from the start)
} nt_level_region;

/// What a door body does (nt_level_body.door). Doors are solid static or kinematic bodies.
typedef enum nt_door_kind {
    NT_DOOR_NONE = 0,   ///< not a door
    NT_DOOR_PLAIN = 1,  ///< opens (goes away) when the player touches it
    NT_DOOR_LOCKED = 2, ///< solid until its switch is on, then goes away
    NT_DOOR_TRAP = 3    ///< open (collides with nothing) until its switch is on, then solid
} nt_door_kind;

/// How a kinematic body follows its path.
typedef enum nt_path_mode {
    NT_PATH_LOOP = 0,     ///< waypoints in order, back to the first, forever
    NT_PATH_PINGPONG = 1, ///< to the last waypoint and back (p0 .. pn-1 .. p1, then again)
    NT_PATH_ORBIT = 2     ///< a circle around `center` of `radius`, clockwise on screen
} nt_path_mode;

/// A path for kinematic bodies: positions are a function of time (no drift).
typedef struct nt_level_path {
    char name[NT_LEVEL_NAME_MAX];
    nt_path_mode mode;
    nt_real speed; ///< world units per second along the path, > 0
    nt_real wait;  ///< LOOP, PINGPONG: seconds the body rests at each waypoint, >= 0
    int point_count;
    nt_vec2 points[NT_LEVEL_MAX_PATH_POINTS]; ///< LOOP, PINGPONG: 2 or more waypoints
    nt_vec2 center;                           ///< ORBIT
    nt_real radius;                           ///< ORBIT, > 0
} nt_level_path;

/// The side a one-way body of the game layer stops the player from (nt_level_body.one_way).
typedef enum nt_one_way_side {
    NT_ONE_WAY_NONE = 0,  ///< an ordinary body
    NT_ONE_WAY_RIGHT = 1, ///< solid to a player wholly to its right, passable from elsewhere
    NT_ONE_WAY_DOWN = 2,  ///< solid to a player wholly below it
    NT_ONE_WAY_LEFT = 3,  ///< solid to a player wholly to its left
    NT_ONE_WAY_UP = 4     ///< solid to a player wholly above it
} nt_one_way_side;

/// A body of the level (or, with repeat_x * repeat_y > 1, a grid of identical ones).
typedef struct nt_level_body {
    char name[NT_LEVEL_NAME_MAX];
    nt_body_type type;
    nt_shape shape;  ///< half-size or radius > 0 and at most NT_MAX_HALF_CELLS cells (8 cells across);
                     ///< above half a cell the body (each repeat) lies wholly inside the map
    nt_vec2 position;
    nt_vec2 velocity;
    nt_real mass;
    nt_real gravity_scale;
    nt_real linear_drag;
    nt_material material;
    uint32_t category, mask;
    bool is_sensor;
    bool enable_sleep; ///< may fall asleep
    bool is_awake;    ///< starts awake
    int path;         ///< index into paths (kinematic bodies), or -1
    nt_real phase;    ///< where on the path it starts, fraction of the path in [0, 1)
    int score;        ///< > 0: a sensor the player collects for this many points
    bool deadly;      ///< touching it kills the player
    bool is_template; ///< not created with the level; spawners copy it
    int repeat_x, repeat_y; ///< instances in a grid (1 x 1 = one body)
    nt_vec2 repeat_step;    ///< spacing of the grid
    nt_door_kind door;      ///< a door of the game layer (static or kinematic, not a sensor or template)
    int door_switch;        ///< NT_DOOR_LOCKED, NT_DOOR_TRAP: 1 + index of the switch region (0 otherwise)
    nt_one_way_side one_way; ///< a one-way platform of the game layer facing that side (static or
                             ///< kinematic, not a door): it collides with nothing while the player is
                             ///< not wholly on that side of it
} nt_level_body;

/// When a spawner creates a body.
typedef enum nt_spawn_trigger {
    NT_SPAWN_ACTION = 0, ///< each time the action input is pressed
    NT_SPAWN_EVERY = 1   ///< every `every` ticks from tick `start`
} nt_spawn_trigger;

/// Creates copies of a template body, at most `limit` of them.
typedef struct nt_level_spawner {
    char name[NT_LEVEL_NAME_MAX];
    int template_body; ///< index into bodies (a template)
    nt_spawn_trigger trigger;
    int every, start;  ///< NT_SPAWN_EVERY: period and first tick (ticks >= 1)
    int limit;         ///< most bodies it creates, >= 1
    int attach;        ///< index into bodies: spawn at that body's position + offset; -1: at the template's position
    nt_vec2 offset;
    nt_real jitter;    ///< random extra x velocity in [-jitter, jitter] (units/s, the level's RNG)
} nt_level_spawner;

/// A level. Build one with nt_level_parse, nt_level_import_n14 or nt_level_create.
typedef struct nt_level {
    char title[NT_LEVEL_TEXT_MAX];
    char author[NT_LEVEL_TEXT_MAX];
    int width, height;      ///< cells, 1..NT_MAP_MAX_SIDE
    nt_real cell_size;      ///< world units, > 0
    nt_vec2 gravity;
    nt_friction_model friction_model;
    bool enable_sleep;      ///< world.enable_sleep
    uint64_t seed;          ///< the game layer's random source starts here
    nt_material materials[NT_MAX_MATERIALS]; ///< tile materials; 0 is the default
    nt_material body_material; ///< default material of bodies
    nt_real body_linear_drag;  ///< default linear drag of bodies
    uint8_t *tiles;          ///< width * height tile ids, row-major, row 0 first
    uint8_t *cell_materials; ///< width * height material indices
    uint8_t *cell_flags;     ///< width * height NT_CELL_* flags
    bool has_player;
    nt_vec2 player;          ///< the player's spawn (centre)
    int body_count, region_count, path_count, spawner_count;
    nt_level_body *bodies;
    nt_level_region *regions;
    nt_level_path *paths;
    nt_level_spawner *spawners;
} nt_level;

/// An empty level (all EMPTY tiles, N's world defaults, no objects) of width x height cells.
nt_status nt_level_create(int width, int height, nt_real cell_size, nt_level **out);

/// Free a level and everything it owns (NULL is ignored).
void nt_level_destroy(nt_level *level);

/// Parse a .ntl text. `name` is used only in messages. On failure *out is NULL and
/// `error` (may be NULL) says where and why.
/// A UTF-8 byte order mark at the start of the text is skipped.
nt_status nt_level_parse(const char *name, const char *text, size_t length, nt_level **out, nt_text_error *error);

/// Write the canonical .ntl text of a level into buf (at most cap bytes, always
/// NUL-terminated when cap > 0). Returns the full length (without the NUL), so a
/// call with cap = 0 measures it. Parsing the output gives back an identical level.
size_t nt_level_write(const nt_level *level, char *buf, size_t cap);

/// Check a level built by hand (ranges, names, references, shapes against the cell
/// size: half-sizes up to NT_MAX_HALF_CELLS cells, a body above half a cell inside the
/// map). NT_OK or the first problem, described in `error` (no position).
nt_status nt_level_validate(const nt_level *level, nt_text_error *error);

/// Add a body (copied) to the level; *index (may be NULL) receives its index. Checked
/// as by nt_level_validate (its problem described in `error`, which may be NULL; no
/// position); the level is unchanged on failure.
nt_status nt_level_add_body(nt_level *level, const nt_level_body *body, int *index, nt_text_error *error);

/// Add a region (copied); checked and reported as nt_level_add_body.
nt_status nt_level_add_region(nt_level *level, const nt_level_region *region, nt_text_error *error);

/// Add a path (copied); *index (may be NULL) receives its index. Checked and reported
/// as nt_level_add_body.
nt_status nt_level_add_path(nt_level *level, const nt_level_path *path, int *index, nt_text_error *error);

/// Add a spawner (copied); checked and reported as nt_level_add_body.
nt_status nt_level_add_spawner(nt_level *level, const nt_level_spawner *spawner, nt_text_error *error);

/// A body with the level's defaults (dynamic 12 x 12 box, mass 1, the level's body
/// material and drag, category 1, mask all, no path, 1 x 1).
nt_level_body nt_level_default_body(const nt_level *level);

/// Index of the body called `name`, or -1.
int nt_level_find_body(const nt_level *level, const char *name);
/// Index of the region called `name`, or -1.
int nt_level_find_region(const nt_level *level, const char *name);
/// Index of the path called `name`, or -1.
int nt_level_find_path(const nt_level *level, const char *name);

/// Number of bodies nt_level_create_world creates (templates excluded, repeats counted).
int nt_level_instance_count(const nt_level *level);

/// Create a world from the level: map, tiles, materials, cell flags, settings, and
/// every non-template body (repeats expanded row by row) in level order. The world
/// definition's speeds given for 24-unit cells (restitution and hit thresholds,
/// sleep speed) are scaled by cell_size / 24. `ids` (may be NULL) receives
/// nt_level_instance_count(level) handles. On failure *out is NULL and nothing is
/// left behind.
nt_status nt_level_create_world(const nt_level *level, nt_world **out, nt_body_id *ids, size_t id_count);

/// The body definition of one body of the level (instance `k` of its repeat grid, row by row).
nt_body_def nt_level_body_def(const nt_level_body *body, int k);

/// Called for each warning of an import (skipped objects); `message` is "NAME:LINE:COL: text".
typedef void nt_warning_fn(const char *message, void *context);

/// Import level number `index` (0-based: the index-th line that holds a level) of an N
/// v1.4 text: `$name#author##TILES|OBJECTS#`, 713 tile characters stored column by
/// column. Gives a 33 x 25 level of cell 24 with the one-cell FULL border, the player
/// spawn, the exit door (region "exit" that needs its switch region "exitswitch"),
/// doors (plain, locked and trap doors with their switches), gold (score sensors),
/// mines (deadly sensors), one-way platforms (cells facing up, one-way bodies facing
/// the other ways), bounce blocks (dynamic boxes)
/// and launch pads (bouncy cells). Unknown or unsupported objects are skipped with a
/// warning that names them. *count (may be NULL)
/// receives the number of levels in the text.
nt_status nt_level_import_n14(const char *name, const char *text, size_t length, int index, nt_level **out,
                              int *count, nt_text_error *error, nt_warning_fn *warn, void *context);

/// The character that stands for a tile id in the .ntl grid ('.', '#', or N's '0' + id), or 0.
char nt_level_tile_char(int tile);

/// The tile id of a .ntl grid character, or -1.
int nt_level_tile_from_char(char c);

#ifdef __cplusplus
}
#endif

#endif
