/* Fixed colours of the playground's own drawing (the gizmos use the engine's
 * debug-draw colours). tests/test_play.c checks screenshot pixels against these. */
#ifndef PG_COLORS_H
#define PG_COLORS_H

#define PG_COLOR_BG 0x14181eu          /* empty space */
#define PG_COLOR_OUTSIDE 0x0a0c10u     /* beyond the map */
#define PG_COLOR_TILE 0x4f5966u        /* fill of straight-edged tiles (engine outline 0x9fa8b3) */
#define PG_COLOR_TILE_ROUND 0x665a4fu  /* fill of round tiles (engine outline 0xb3a89f) */
#define PG_COLOR_PLAYER 0xf2f2f2u      /* fill of the player */
#define PG_COLOR_PLAYER_DEAD 0x8c2a2au /* fill of a dead player (crossed out in PG_COLOR_DEAD_MARK) */
#define PG_COLOR_DEAD_MARK 0xffd0d0u
#define PG_COLOR_PANEL 0x000000u       /* backgrounds blended over the level (help, banner) */
#define PG_COLOR_PANEL_BG 0x181d24u    /* the side panel's background */
#define PG_COLOR_HEADING 0x2a3440u     /* the panel's section headings */
#define PG_PANEL_W 232                 /* the side panel's width at text scale 1 */
#define PG_COLOR_TEXT 0xe8e8e8u
#define PG_COLOR_STRIP 0x1c222au       /* the tile palette's background */
#define PG_COLOR_TIMELINE 0x4080d0u    /* the replay timeline's played part */
#define PG_COLOR_CONFIRM 0xffa040u     /* the question before discarding edits */
#define PG_COLOR_SELECT 0xffd040u      /* the selected palette tile, the painting cursor */
/* Level objects, each in its own colour and shape (render.c). */
#define PG_COLOR_GOLD 0xf0c020u        /* gold: a gold disc with a darker rim */
#define PG_COLOR_GOLD_RIM 0x9a7410u
#define PG_COLOR_MINE 0xd82828u        /* mines: a red disc with spikes */
#define PG_COLOR_MINE_CORE 0x400808u
#define PG_COLOR_DOOR 0x3c9a50u        /* the exit door, closed */
#define PG_COLOR_DOOR_OPEN 0x0c1a10u   /* the doorway once the level is complete */
#define PG_COLOR_ONEWAY 0x5aa8e6u      /* one-way cells: top line and arrow */
#define PG_COLOR_ZONE 0x8090a8u        /* zones: dashed outline and name */
#define PG_COLOR_SWITCH 0xe0b030u      /* switches: a button, lit once pressed */
#define PG_COLOR_BIN 0xe0c040u         /* score regions (bins) and their value */
#define PG_COLOR_KILL 0xe04040u        /* kill regions */
#define PG_COLOR_PATH 0x7c6cc8u        /* kinematic paths (dotted) */
#define PG_COLOR_SPAWNER 0x40d0c0u     /* spawner marks */
#define PG_COLOR_PLATFORM 0x8a78e0u    /* kinematic bodies on a path */
#define PG_COLOR_BANNER_WIN 0x50e070u  /* COMPLETE */
#define PG_COLOR_BANNER_DEAD 0xff4040u /* DEAD */
/* Tile tints of materials 1..15 (material 0 is the plain tile colour). */
#define PG_MATERIAL_TINTS \
    {0, 0x3a8fd8u, 0xd8703au, 0x58c050u, 0xc050b8u, 0xd8c83au, 0x3ad8c8u, 0xa0a0ffu, 0xff9090u, \
     0x90ff90u, 0xffd090u, 0x9060ffu, 0x60ffd0u, 0xff60a0u, 0xc0c0c0u, 0x806040u}
/* A body's fill is its debug-draw colour at half brightness. */
#define PG_BODY_FILL(c) (((c) >> 1) & 0x7f7f7fu)
/* Engine debug-draw colours the tests look for (see world.h). */
#define PG_ENGINE_VELOCITY 0x40c0c0u
#define PG_ENGINE_AWAKE 0xe6b34du

#endif
