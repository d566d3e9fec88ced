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
#define PG_COLOR_PANEL 0x000000u       /* HUD background (blended) */
#define PG_COLOR_TEXT 0xe8e8e8u
#define PG_COLOR_STRIP 0x1c222au       /* the tile palette's background */
#define PG_COLOR_SELECT 0xffd040u      /* the selected palette tile, the painting cursor */
/* A body's fill is its debug-draw colour at half brightness. */
#define PG_BODY_FILL(c) (((c) >> 1) & 0x7f7f7fu)
/* Engine debug-draw colours the tests look for (see world.h). */
#define PG_ENGINE_VELOCITY 0x40c0c0u
#define PG_ENGINE_AWAKE 0xe6b34du

#endif
