/* ntile-play: the playground's core, without SDL. main.c owns the window and turns
 * SDL events into the calls below; play.c owns the level, the game, time, the mouse
 * tools, recording and saving; render.c draws a frame into a pg_canvas through the
 * engine's debug-draw callbacks (nt_world_draw), never by reading engine internals.
 *
 * Time: the simulation advances in fixed ticks of the replay dt (1/40 s). In real
 * time, pg_advance adds wall-clock seconds (scaled by the slow-motion factor) to an
 * accumulator and runs whole ticks; the remainder is the render interpolation
 * factor. In fixed mode (automation) every frame is one tick. The game never sees
 * the wall clock. */
#ifndef PG_PLAY_H
#define PG_PLAY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "canvas.h"
#include "ntile/game.h"

#include "colors.h"

/* ---------------------------------------------------------------- gizmos */

enum {
    PG_GZ_TILES,       /* tile outlines */
    PG_GZ_EDGES,       /* edge states: SOLID red, INTERESTING yellow */
    PG_GZ_GRID,        /* loose-grid cells in use */
    PG_GZ_BODIES,      /* body outlines coloured by state */
    PG_GZ_VELOCITIES,  /* velocity arrows */
    PG_GZ_SPLIT,       /* normal (red) / tangential (green) split against the surface */
    PG_GZ_CONTACTS,    /* body and tile contact normals */
    PG_GZ_PROJECTIONS, /* projection vectors, magnified */
    PG_GZ_RAYS,        /* ray casts from the mouse */
    PG_GZ_SLEEP,       /* sleeping bodies marked */
    PG_GZ_SENSORS,     /* sensor overlaps */
    PG_GZ_STATS,       /* the engine's counter line */
    PG_GZ_COUNT
};

typedef struct pg_gizmo_info {
    const char *name; /* for --gizmos */
    char key;         /* the key that toggles it */
    const char *what; /* for the help */
} pg_gizmo_info;

extern const pg_gizmo_info pg_gizmos[PG_GZ_COUNT];

/* Parse "velocities,edges" / "all" / "none" into a bit set; 0 on an unknown name (why says which). */
int pg_parse_gizmos(const char *list, unsigned *out, char *why, size_t cap);

/* ---------------------------------------------------------------- commands */

typedef enum pg_cmd {
    PG_CMD_RESTART,
    PG_CMD_LEVEL,       /* arg: index into the level list */
    PG_CMD_LEVEL_NEXT,
    PG_CMD_LEVEL_PREV,
    PG_CMD_PAUSE,
    PG_CMD_STEP,        /* one tick (pauses) */
    PG_CMD_SLOW,        /* cycle 1, 1/2, 1/4, 1/8 speed */
    PG_CMD_HELP,
    PG_CMD_GIZMO,       /* arg: PG_GZ_* */
    PG_CMD_PROJ_SCALE,  /* cycle projection magnification */
    PG_CMD_THROW_SHAPE,
    PG_CMD_THROW_SIZE,  /* cycle the thrown body's size: 0.6, 1, 2, 4 cells across */
    PG_CMD_BOUNCE,      /* arg: +1 / -1 */
    PG_CMD_FRICTION,    /* arg: +1 / -1 */
    PG_CMD_FRICTION_MODEL,
    PG_CMD_TILE,        /* arg: +1 / -1: palette selection */
    PG_CMD_SAVE,
    PG_CMD_RECORD,
    PG_CMD_ZOOM,        /* arg: +1 / -1 / 0 (reset) */
    PG_CMD_PANEL,       /* the side panel: left, right, hidden */
    PG_CMD_GRAVITY,     /* arg: +1 / -1: gravity's y by a tenth of the level's (or 32) */
    PG_CMD_DT,          /* cycle the tick: 1/40, 1/60, 1/120, 1/20 s */
    PG_CMD_SLEEP,       /* sleeping on / off (rebuilds the world) */
    PG_CMD_VEL_ITERS,   /* arg: +1 / -1: velocity iterations 1, 2, 4 ... 64 (live) */
    PG_CMD_POS_ITERS,   /* arg: +1 / -1: position iterations 0, 1, 2, 4 ... 64 (live) */
    PG_CMD_UNDO,
    PG_CMD_REDO,
    PG_CMD_CONFIRM,     /* arg: 1 yes (discard and go on), 0 no (keep the edits), 2 save first */
    PG_CMD_TOOL,        /* arg: a PG_TOOL_*, or -1 / -2: next / previous (F6 / Shift+F6) */
    PG_CMD_MATERIAL,    /* arg: +1 / -1: the material tool's material */
    PG_CMD_SEEK,        /* arg: the replay's tick to go to (back: played again from the start) */
    PG_CMD_STEP_BACK,   /* one tick back (pauses) */
    PG_CMD_REPLAY_END,  /* the replay's last tick */
    PG_CMD_DIVERGENCE,  /* the first tick whose hash differs from the replay's */
    PG_CMD_OPEN,        /* open the file pg_open named */
} pg_cmd;

enum { PG_MOUSE_LEFT = 1, PG_MOUSE_MIDDLE = 2, PG_MOUSE_RIGHT = 3, PG_MOUSE_PAN = 4 /* Space + left */, PG_MOUSE_TIMELINE = 5 };
/* Modifier keys held (pg_set_mods): Shift+right-drag erases, Ctrl+right-drag fills a
 * rectangle, Alt+right-click picks the tile under the mouse (eyedropper). */
enum { PG_MOD_SHIFT = 1, PG_MOD_CTRL = 2, PG_MOD_ALT = 4 };
/* Tools of the left button (PG_CMD_TOOL): throw bodies (and inspect them), or place and
 * move level objects. */
enum { PG_TOOL_THROW, PG_TOOL_GOLD, PG_TOOL_MINE, PG_TOOL_EXIT, PG_TOOL_SPAWN, PG_TOOL_ONE_WAY, PG_TOOL_MATERIAL,
       PG_TOOL_PLATFORM, PG_TOOL_COUNT };
extern const char *const pg_tool_names[PG_TOOL_COUNT];
/* pg_command's confirmation target for quitting. */
#define PG_CONFIRM_QUIT 1000

/* ---------------------------------------------------------------- options */

typedef struct pg_options {
    const char *level_path;  /* NULL: levels/ninja.ntl */
    const char *levels_dir;  /* where the shipped levels are; NULL: found next to level_path or the program */
    const char *replay_path; /* play this replay's inputs */
    const char *save_dir;    /* F2 and F5 write here; NULL: "." */
    const char *save_path;   /* F2 writes exactly this file */
    const char *record_path; /* the first F5 recording goes exactly here */
    unsigned gizmos;
    bool hud;                /* HUD, palette strip and help */
    bool has_zoom, has_center;
    double zoom, center_x, center_y;
    double fixed_alpha;      /* fixed mode: draw bodies this far from the previous tick to the current one (1) */
} pg_options;

/* ---------------------------------------------------------------- the playground */

typedef struct pg_vec {
    double x, y;
} pg_vec;

typedef struct pg_pair {
    nt_body_id sensor, visitor;
} pg_pair;

typedef struct pg pg;

/* Create the playground and load the first level (or the replay). On failure returns
 * NULL and writes the reason to why. */
pg *pg_create(const pg_options *opt, char *why, size_t cap);
void pg_destroy(pg *p);

/* The window (or the screenshot) size in pixels; the view is what the palette strip leaves. */
void pg_set_window(pg *p, int w, int h);

/* Keys held (NT_INPUT_* bits) for the coming ticks (ignored while a replay plays); in a
 * level without a player, the direction keys also pan the view. */
void pg_set_keys(pg *p, uint32_t keys);

void pg_command(pg *p, pg_cmd cmd, int arg);

void pg_set_mods(pg *p, unsigned mods);

/* Ask to quit: true when nothing would be lost (or the user confirmed); otherwise a
 * confirmation is shown and pg_should_quit turns true once it is answered yes. */
bool pg_request_quit(pg *p);
bool pg_should_quit(const pg *p);
/* A confirmation is waiting: keys go to it (Y, N / Esc, F2). */
bool pg_confirming(const pg *p);

/* Mouse in window pixels. */
void pg_mouse_move(pg *p, double x, double y);
void pg_mouse_button(pg *p, int button, bool down, double x, double y);
void pg_mouse_wheel(pg *p, double dy);

/* Real time: add `seconds` of wall clock; runs the ticks due. Fixed: one frame's worth (a
 * tick, or none when paused or between slow-motion ticks). Returns the ticks run. */
int pg_advance(pg *p, double seconds);
int pg_advance_frame(pg *p);

/* Nothing changes without input: paused (or the level stands still), no drag, no
 * key that pans. The window loop then sleeps until an event. */
bool pg_idle(const pg *p);

/* Draw the current state. fps: the frame rate to show. */
void pg_render(pg *p, pg_canvas *c, double fps);

/* Stop a recording in progress (saving it), e.g. before quitting. */
void pg_finish(pg *p);

/* One line of state for automation: tick, score, bodies, player; in the lab, the last
 * collision's momentum and kinetic energy before and after (as the HUD shows them). */
void pg_summary(const pg *p, char *out, size_t cap);

/* Open a level (.ntl) or a replay (.ntr) — dropped on the window; asks first when
 * edits would be lost. */
void pg_open(pg *p, const char *path);

/* The window's title: the level's title and its (normalised) path, "*" when edited. */
void pg_title(const pg *p, char *out, size_t cap);

/* State for main.c and the tests. */
const char *pg_message(const pg *p);
nt_game *pg_game(const pg *p);
int pg_tick_count(const pg *p);

#endif
