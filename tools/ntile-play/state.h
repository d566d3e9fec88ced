/* The playground's state, shared by play.c (logic) and render.c (drawing). */
#ifndef PG_STATE_H
#define PG_STATE_H

#include "play.h"

#define PG_MAX_LEVELS 16
#define PG_PATH_MAX 4096
#define PG_MAX_RAYS 24

/* Strip of tile swatches on the right of the window. */
#define PG_STRIP_COLS 2
#define PG_STRIP_ROWS 17

/* One cell's change, for undo. */
typedef struct pg_cell_edit {
    int x, y;
    uint8_t tile0, tile1, mat0, mat1, flag0, flag1;
} pg_cell_edit;

/* One undoable edit: cell changes (applied to the running game), or a change of the
 * level's objects (the level's text before and after; undoing rebuilds the game). */
typedef struct pg_edit {
    pg_cell_edit *cells;
    int n, cap;
    char *before, *after;
    char what[48];
} pg_edit;

struct pg {
    pg_options opt;
    char save_dir[PG_PATH_MAX];

    /* Level list: the shipped levels and the one given on the command line. */
    char *levels[PG_MAX_LEVELS];
    int level_count, level_index;

    /* The level being played: the model kept in sync with painting and the friction
     * model switch (F2 writes it), the file it came from, and the game built from it. */
    nt_level *level;
    char level_path[PG_PATH_MAX];
    bool dirty;
    bool lab; /* show momentum and energy (lab.ntl or a level without gravity) */
    nt_game *game;
    nt_game_def gdef;
    nt_real dt, dt_default; /* the tick: the replay's while one plays, else the format's 1/40 s */
    int vel_iters, pos_iters; /* the solver's iterations, set on every world before it steps */

    /* Replay playback (--replay): its inputs drive the game. */
    nt_replay *replay;
    char replay_path[PG_PATH_MAX];
    bool replay_on;
    bool divergence_known;
    int divergence; /* the first tick whose hash differs from the recorded ones, -1: none */
    char *open_path; /* a file to open (dropped on the window) once edits are saved or discarded */

    /* Time. */
    double acc;    /* seconds of simulation owed, < dt */
    bool paused;
    bool resumed;  /* unpaused since the last advance */
    int slow;      /* slow-motion divisor: 1, 2, 4, 8 */
    int frame;     /* frames advanced in fixed mode */
    double step_us; /* smoothed time of one tick */
    uint32_t keys;

    /* Recording (F5). */
    bool recording;
    uint32_t *rec_keys;  /* keys of ticks 1..rec_n */
    uint32_t *rec_trace; /* folded game hash after each tick */
    uint64_t rec_last_hash;
    int rec_n, rec_cap;
    bool rec_first_done;

    /* Tuning of thrown bodies. */
    bool throw_circle;
    int throw_size; /* index into the sizes pg__throw_cells gives */
    double bounce, friction;
    int tile; /* palette selection */

    /* Editing: undo history (edits[0 .. undo_n), the first undo_pos of them applied),
     * the position of the last save, an edit in progress (a stroke). */
    pg_edit *edits;
    int undo_n, undo_pos, undo_cap, save_mark;
    bool stroke, settings_dirty;
    /* A confirmation waiting for Y / N (discarding edits): the action to do on Y. */
    int confirm_cmd, confirm_arg; /* PG_CMD_* or PG_CONFIRM_QUIT; -1: none */
    bool quit_now;

    /* The left button's tool: throw (and inspect), or place / move a kind of object. */
    int tool;      /* PG_TOOL_* */
    int material;  /* the material the material tool paints, 1..15 (0 clears) */
    int moving;    /* an object being moved: PG_TOOL_* of it, or 0 */
    int moving_index; /* its index (level body or region) */
    pg_vec moving_from;

    /* The inspector: the body selected (left click on it), dragged by a spring toward
     * the mouse while the button is held (a mouse joint). */
    nt_body_id selected;
    bool joint, press_selected;

    /* Mouse. */
    unsigned mods;      /* PG_MOD_* held */
    bool rect;          /* the right drag fills a rectangle (Ctrl) */
    int rect_x, rect_y; /* its first cell */
    pg_vec grab_cam;    /* camera and pointer when a pan drag started */
    double press_x, press_y;
    bool moved;
    double mx, my;      /* window pixels */
    bool mouse_seen;
    int drag;           /* button held in the view: 0, PG_MOUSE_LEFT, PG_MOUSE_RIGHT */
    pg_vec drag_from;   /* world point where a throw started */
    int paint_x, paint_y;

    /* View. */
    int win_w, win_h, view_x, view_w, view_h;
    int panel;          /* the side panel: PG_PANEL_LEFT, PG_PANEL_RIGHT or PG_PANEL_HIDDEN (F3 cycles) */
    int panel_x, panel_w;
    double zoom, zoom_fit;
    pg_vec cam;
    pg_vec pan;         /* levels without a player: the arrows move the view from the centre */
    bool follow;

    /* Render interpolation: every body's position before the last tick, by slot. */
    pg_vec *prev;
    uint32_t *prev_gen;
    int prev_cap;

    /* What each body is in the level (PG_KIND_*), by slot (generation + 1 in kind_gen). */
    unsigned char *kind;
    uint32_t *kind_gen;
    int kind_cap;

    /* Gizmos. */
    unsigned gizmos;
    double proj_scale;
    bool help;

    /* Sensor overlaps, from the sensor events. */
    pg_pair *pairs;
    int pair_n, pair_cap;

    /* The last collision between bodies (lab). */
    bool has_collision;
    int coll_tick;
    double ke_before, ke_after, px_before, py_before, px_after, py_after;

    /* Palette world: each tile alone in a cell, drawn through nt_world_draw. */
    nt_world *palette;

    /* Clickable parts of the side panel, as the last frame drew them. */
    struct pg_widget {
        int x0, y0, x1, y1;
        int cmd, arg;
    } widgets[64];
    int widget_n;

    char msg[256];
    double msg_until; /* wall-clock seconds */
    double clock;     /* wall-clock seconds seen (for messages only) */
    bool fixed;       /* the last advance was a fixed frame (automation) */
};

enum { PG_PANEL_LEFT, PG_PANEL_RIGHT, PG_PANEL_HIDDEN };

/* Kinds of bodies, each drawn its own way. */
enum { PG_KIND_PLAIN, PG_KIND_GOLD, PG_KIND_MINE, PG_KIND_PLATFORM, PG_KIND_PLAYER };

/* play.c helpers render.c uses. */
int pg__body_kind(pg *p, nt_body_id id);
int pg__bodies(const pg *p, nt_body_id **out); /* every live body of the game (thrown ones too); caller frees */
pg_vec pg__to_screen(const pg *p, double x, double y);
pg_vec pg__to_world(const pg *p, double x, double y);
pg_vec pg__player_pos(const pg *p, double alpha); /* interpolated */
double pg__alpha(const pg *p);
void pg__strip_rect(const pg *p, int *x0, int *cell, int *gap);
int pg__text_scale(const pg *p);
/* The inspector's lines: the cell under the mouse, the body selected ("" when none). */
void pg__inspect_cell(const pg *p, char *out, size_t cap);
void pg__inspect_body(const pg *p, char *out, size_t cap);
/* The replay timeline's bar at the bottom of the view. */
void pg__timeline_rect(const pg *p, int *x0, int *y0, int *x1, int *y1);
bool pg__in_view(const pg *p, double x, double y);
/* Width (and height) of a thrown body, in cells, and the half-size in world units. */
double pg__throw_cells(const pg *p);
double pg__throw_half(const pg *p);
/* Place the camera for this frame (render.c calls it first). */
void pg__prepare_view(pg *p);
/* Momentum and kinetic energy of the dynamic bodies. */
void pg__mechanics(const pg *p, double *px, double *py, double *ke);

#endif
