/* A small software rasteriser for the playground: everything is drawn into a 32-bit
 * 0x00RRGGBB pixel buffer that main.c copies to the window, so that a frame is the
 * same pixels on every video driver (a real X11 window, Xvfb, SDL's offscreen or
 * dummy drivers) and a screenshot is the buffer itself. No SDL here.
 *
 * Coordinates are pixels as doubles: pixel (i, j) covers [i, i+1) x [j, j+1); filled
 * shapes cover the pixels whose centres they contain. Everything is clipped to the
 * clip rectangle. */
#ifndef PG_CANVAS_H
#define PG_CANVAS_H

#include <stdint.h>

typedef struct pg_canvas {
    uint32_t *px; /* w * h pixels, row-major, 0x00RRGGBB */
    int w, h;
    int cx0, cy0, cx1, cy1; /* clip rectangle, [cx0, cx1) x [cy0, cy1) */
} pg_canvas;

/* Resize (contents undefined afterwards) and reset the clip. 0 on failure (out of memory or bad size). */
int pg_canvas_resize(pg_canvas *c, int w, int h);
void pg_canvas_free(pg_canvas *c);

/* Clip to [x0, x1) x [y0, y1) (intersected with the canvas); pg_unclip restores the whole canvas. */
void pg_clip(pg_canvas *c, int x0, int y0, int x1, int y1);
void pg_unclip(pg_canvas *c);

void pg_clear(pg_canvas *c, uint32_t color);
void pg_pixel(pg_canvas *c, int x, int y, uint32_t color);
/* Filled rectangle [x0, x1) x [y0, y1). */
void pg_fill_rect(pg_canvas *c, int x0, int y0, int x1, int y1, uint32_t color);
/* The same, mixed with what is there: alpha 0 (nothing) .. 255 (opaque). */
void pg_blend_rect(pg_canvas *c, int x0, int y0, int x1, int y1, uint32_t color, int alpha);
/* One-pixel outline of [x0, x1) x [y0, y1). */
void pg_rect(pg_canvas *c, int x0, int y0, int x1, int y1, uint32_t color);

/* One-pixel line between two points (both ends drawn). */
void pg_line(pg_canvas *c, double x0, double y0, double x1, double y1, uint32_t color);
/* A line `width` pixels wide (square brush). */
void pg_thick_line(pg_canvas *c, double x0, double y0, double x1, double y1, int width, uint32_t color);
/* A line with an arrow head of `head` pixels at (x1, y1). */
void pg_arrow(pg_canvas *c, double x0, double y0, double x1, double y1, double head, uint32_t color);

void pg_circle(pg_canvas *c, double cx, double cy, double r, uint32_t color);
void pg_fill_circle(pg_canvas *c, double cx, double cy, double r, uint32_t color);
/* Even-odd fill of a polygon of n points (xy[2k], xy[2k+1]); n <= 64. */
void pg_fill_polygon(pg_canvas *c, const double *xy, int n, uint32_t color);
/* Closed outline of the same. */
void pg_polygon(pg_canvas *c, const double *xy, int n, uint32_t color);

/* Text in the 5 x 9 font, `scale` pixels per font pixel, top-left at (x, y); '\n'
 * starts a new line. Returns the width in pixels of the longest line. */
int pg_text(pg_canvas *c, int x, int y, const char *text, uint32_t color, int scale);
int pg_text_width(const char *text, int scale);
/* Advance and line height of the font at a scale. */
#define PG_CHAR_W 6
#define PG_CHAR_H 11

/* Colour helpers. */
uint32_t pg_mix(uint32_t a, uint32_t b, int alpha); /* a + (b - a) * alpha / 255 */

/* The font: 5 columns, PG_FONT_ROWS rows (the baseline under row 7, descenders below). */
#define PG_FONT_ROWS 9
extern const unsigned char pg_font[95][PG_FONT_ROWS];

#endif
