/* Software rasteriser: lines, circles, polygons and text into a 32-bit buffer. */
#include "canvas.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int pg_canvas_resize(pg_canvas *c, int w, int h)
{
    if (w <= 0 || h <= 0 || w > 16384 || h > 16384) return 0;
    if (w != c->w || h != c->h || !c->px) {
        uint32_t *p = realloc(c->px, (size_t)w * (size_t)h * sizeof *p);
        if (!p) return 0;
        c->px = p;
        c->w = w;
        c->h = h;
    }
    pg_unclip(c);
    return 1;
}

void pg_canvas_free(pg_canvas *c)
{
    free(c->px);
    memset(c, 0, sizeof *c);
}

void pg_clip(pg_canvas *c, int x0, int y0, int x1, int y1)
{
    c->cx0 = x0 < 0 ? 0 : x0;
    c->cy0 = y0 < 0 ? 0 : y0;
    c->cx1 = x1 > c->w ? c->w : x1;
    c->cy1 = y1 > c->h ? c->h : y1;
    if (c->cx1 < c->cx0) c->cx1 = c->cx0;
    if (c->cy1 < c->cy0) c->cy1 = c->cy0;
}

void pg_unclip(pg_canvas *c) { pg_clip(c, 0, 0, c->w, c->h); }

void pg_clear(pg_canvas *c, uint32_t color)
{
    size_t n = (size_t)c->w * (size_t)c->h;
    for (size_t i = 0; i < n; i++) c->px[i] = color;
}

void pg_pixel(pg_canvas *c, int x, int y, uint32_t color)
{
    if (x < c->cx0 || x >= c->cx1 || y < c->cy0 || y >= c->cy1) return;
    c->px[(size_t)y * (size_t)c->w + (size_t)x] = color;
}

uint32_t pg_mix(uint32_t a, uint32_t b, int alpha)
{
    uint32_t out = 0;
    for (int s = 0; s <= 16; s += 8) {
        int ca = (int)((a >> s) & 0xffu), cb = (int)((b >> s) & 0xffu);
        out |= (uint32_t)(ca + ((cb - ca) * alpha) / 255) << s;
    }
    return out;
}

/* Span [x0, x1) of row y, clipped. */
static void span(pg_canvas *c, int y, int x0, int x1, uint32_t color)
{
    if (y < c->cy0 || y >= c->cy1) return;
    if (x0 < c->cx0) x0 = c->cx0;
    if (x1 > c->cx1) x1 = c->cx1;
    uint32_t *row = c->px + (size_t)y * (size_t)c->w;
    for (int x = x0; x < x1; x++) row[x] = color;
}

void pg_fill_rect(pg_canvas *c, int x0, int y0, int x1, int y1, uint32_t color)
{
    if (y0 < c->cy0) y0 = c->cy0;
    if (y1 > c->cy1) y1 = c->cy1;
    for (int y = y0; y < y1; y++) span(c, y, x0, x1, color);
}

void pg_blend_rect(pg_canvas *c, int x0, int y0, int x1, int y1, uint32_t color, int alpha)
{
    if (x0 < c->cx0) x0 = c->cx0;
    if (y0 < c->cy0) y0 = c->cy0;
    if (x1 > c->cx1) x1 = c->cx1;
    if (y1 > c->cy1) y1 = c->cy1;
    for (int y = y0; y < y1; y++) {
        uint32_t *row = c->px + (size_t)y * (size_t)c->w;
        for (int x = x0; x < x1; x++) row[x] = pg_mix(row[x], color, alpha);
    }
}

void pg_rect(pg_canvas *c, int x0, int y0, int x1, int y1, uint32_t color)
{
    if (x1 <= x0 || y1 <= y0) return;
    pg_fill_rect(c, x0, y0, x1, y0 + 1, color);
    pg_fill_rect(c, x0, y1 - 1, x1, y1, color);
    pg_fill_rect(c, x0, y0, x0 + 1, y1, color);
    pg_fill_rect(c, x1 - 1, y0, x1, y1, color);
}

/* Liang-Barsky: clip the segment to [lo, hi] boxes; 0 when nothing is left. */
static int clip_segment(double *x0, double *y0, double *x1, double *y1, double xl, double yl, double xh, double yh)
{
    double t0 = 0, t1 = 1, dx = *x1 - *x0, dy = *y1 - *y0;
    const double p[4] = {-dx, dx, -dy, dy};
    const double q[4] = {*x0 - xl, xh - *x0, *y0 - yl, yh - *y0};
    for (int i = 0; i < 4; i++) {
        if (p[i] == 0) {
            if (q[i] < 0) return 0;
            continue;
        }
        double r = q[i] / p[i];
        if (p[i] < 0) {
            if (r > t1) return 0;
            if (r > t0) t0 = r;
        } else {
            if (r < t0) return 0;
            if (r < t1) t1 = r;
        }
    }
    double ax = *x0 + t0 * dx, ay = *y0 + t0 * dy, bx = *x0 + t1 * dx, by = *y0 + t1 * dy;
    *x0 = ax, *y0 = ay, *x1 = bx, *y1 = by;
    return 1;
}

static int finite4(double a, double b, double c, double d) { return isfinite(a) && isfinite(b) && isfinite(c) && isfinite(d); }

void pg_line(pg_canvas *c, double x0, double y0, double x1, double y1, uint32_t color)
{
    if (!finite4(x0, y0, x1, y1)) return;
    if (!clip_segment(&x0, &y0, &x1, &y1, c->cx0 - 2.0, c->cy0 - 2.0, c->cx1 + 2.0, c->cy1 + 2.0)) return;
    int ix0 = (int)floor(x0), iy0 = (int)floor(y0), ix1 = (int)floor(x1), iy1 = (int)floor(y1);
    int dx = abs(ix1 - ix0), dy = -abs(iy1 - iy0), sx = ix0 < ix1 ? 1 : -1, sy = iy0 < iy1 ? 1 : -1;
    int err = dx + dy;
    for (;;) {
        pg_pixel(c, ix0, iy0, color);
        if (ix0 == ix1 && iy0 == iy1) break;
        int e2 = 2 * err;
        if (e2 >= dy) {
            err += dy;
            ix0 += sx;
        }
        if (e2 <= dx) {
            err += dx;
            iy0 += sy;
        }
    }
}

void pg_thick_line(pg_canvas *c, double x0, double y0, double x1, double y1, int width, uint32_t color)
{
    if (width <= 1) {
        pg_line(c, x0, y0, x1, y1, color);
        return;
    }
    double lo = -(width - 1) / 2.0;
    for (int i = 0; i < width; i++)
        for (int j = 0; j < width; j++) pg_line(c, x0 + lo + i, y0 + lo + j, x1 + lo + i, y1 + lo + j, color);
}

void pg_arrow(pg_canvas *c, double x0, double y0, double x1, double y1, double head, uint32_t color)
{
    pg_line(c, x0, y0, x1, y1, color);
    double dx = x1 - x0, dy = y1 - y0, len = sqrt(dx * dx + dy * dy);
    if (!(len > 0.5)) return;
    if (head > len * 0.5) head = len * 0.5;
    double ux = dx / len, uy = dy / len;
    /* Two barbs at +-30 degrees from the shaft. */
    const double cs = 0.8660254037844386, sn = 0.5;
    double ax = -ux * cs + uy * sn, ay = -uy * cs - ux * sn;
    double bx = -ux * cs - uy * sn, by = -uy * cs + ux * sn;
    pg_line(c, x1, y1, x1 + ax * head, y1 + ay * head, color);
    pg_line(c, x1, y1, x1 + bx * head, y1 + by * head, color);
}

/* The pixels of row y whose centres lie in the disc: [*a, *b]; 0 when none. The fill
 * and the outline share it, so an outline is exactly the fill's edge. */
static int disc_span(double cx, double cy, double r, int y, int *a, int *b)
{
    double dy = y + 0.5 - cy, h2 = r * r - dy * dy;
    if (h2 < 0) return 0;
    double hw = sqrt(h2);
    double lo = ceil(cx - hw - 0.5), hi = floor(cx + hw - 0.5);
    if (hi < lo) return 0;
    *a = (int)lo, *b = (int)hi;
    return 1;
}

/* The outline of a disc: the pixels of pg_fill_circle's disc that have a 4-neighbour
 * outside it (smooth at any radius, and the fill never pokes out of it). */
void pg_circle(pg_canvas *c, double cx, double cy, double r, uint32_t color)
{
    if (!finite4(cx, cy, r, 0) || r < 0 || r > 1e6) return;
    if (cx + r < c->cx0 - 1 || cx - r > c->cx1 + 1 || cy + r < c->cy0 - 1 || cy - r > c->cy1 + 1) return;
    if (r < 0.75) {
        pg_pixel(c, (int)floor(cx), (int)floor(cy), color);
        return;
    }
    int y0 = (int)floor(cy - r) - 1, y1 = (int)ceil(cy + r) + 1;
    if (y0 < c->cy0 - 1) y0 = c->cy0 - 1;
    if (y1 > c->cy1 + 1) y1 = c->cy1 + 1;
    for (int y = y0; y < y1; y++) {
        int a, b, ua, ub, da, db;
        if (!disc_span(cx, cy, r, y, &a, &b)) continue;
        int up = disc_span(cx, cy, r, y - 1, &ua, &ub), dn = disc_span(cx, cy, r, y + 1, &da, &db);
        if (!up || !dn) { /* the top or bottom row: all of it */
            span(c, y, a, b + 1, color);
            continue;
        }
        /* Inside where both neighbour rows cover x too (and not an end of the row). */
        int ia = ua > da ? ua : da, ib = ub < db ? ub : db;
        if (ia < a + 1) ia = a + 1;
        if (ib > b - 1) ib = b - 1;
        if (ib < ia) {
            span(c, y, a, b + 1, color);
            continue;
        }
        span(c, y, a, ia, color);
        span(c, y, ib + 1, b + 1, color);
    }
}

void pg_fill_circle(pg_canvas *c, double cx, double cy, double r, uint32_t color)
{
    if (!finite4(cx, cy, r, 0) || r <= 0) return;
    int y0 = (int)floor(cy - r), y1 = (int)ceil(cy + r);
    if (y0 < c->cy0) y0 = c->cy0;
    if (y1 > c->cy1) y1 = c->cy1;
    for (int y = y0; y < y1; y++) {
        int a, b;
        if (!disc_span(cx, cy, r, y, &a, &b)) continue;
        if (a < c->cx0) a = c->cx0;
        if (b > c->cx1 - 1) b = c->cx1 - 1;
        if (b >= a) span(c, y, a, b + 1, color);
    }
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void pg_fill_polygon(pg_canvas *c, const double *xy, int n, uint32_t color)
{
    if (n < 3 || n > 64) return;
    double ylo = xy[1], yhi = xy[1];
    for (int i = 0; i < n; i++) {
        if (!finite4(xy[2 * i], xy[2 * i + 1], 0, 0)) return;
        if (xy[2 * i + 1] < ylo) ylo = xy[2 * i + 1];
        if (xy[2 * i + 1] > yhi) yhi = xy[2 * i + 1];
    }
    int y0 = (int)floor(ylo), y1 = (int)ceil(yhi);
    if (y0 < c->cy0) y0 = c->cy0;
    if (y1 > c->cy1) y1 = c->cy1;
    double xs[64];
    for (int y = y0; y < y1; y++) {
        double sy = y + 0.5;
        int m = 0;
        for (int i = 0; i < n; i++) {
            double ax = xy[2 * i], ay = xy[2 * i + 1];
            double bx = xy[2 * ((i + 1) % n)], by = xy[2 * ((i + 1) % n) + 1];
            /* Half-open in y: a vertex on the scan line counts once. */
            if ((ay <= sy && by > sy) || (by <= sy && ay > sy)) xs[m++] = ax + (sy - ay) * (bx - ax) / (by - ay);
        }
        qsort(xs, (size_t)m, sizeof xs[0], cmp_double);
        for (int k = 0; k + 1 < m; k += 2) {
            double a = ceil(xs[k] - 0.5), b = ceil(xs[k + 1] - 0.5); /* centres in [xs[k], xs[k+1]) */
            if (a < c->cx0) a = c->cx0;
            if (b > c->cx1) b = c->cx1;
            if (b > a) span(c, y, (int)a, (int)b, color);
        }
    }
}

void pg_polygon(pg_canvas *c, const double *xy, int n, uint32_t color)
{
    for (int i = 0; i < n; i++) {
        int j = (i + 1) % n;
        pg_line(c, xy[2 * i], xy[2 * i + 1], xy[2 * j], xy[2 * j + 1], color);
    }
}

int pg_text(pg_canvas *c, int x, int y, const char *text, uint32_t color, int scale)
{
    if (scale < 1) scale = 1;
    int cx = x, width = 0;
    for (const unsigned char *s = (const unsigned char *)text; *s; s++) {
        if (*s == '\n') {
            if (cx - x > width) width = cx - x;
            cx = x;
            y += PG_CHAR_H * scale;
            continue;
        }
        unsigned ch = (*s >= 32 && *s < 127) ? *s : '?';
        const unsigned char *g = pg_font[ch - 32];
        for (int row = 0; row < PG_FONT_ROWS; row++)
            for (int col = 0; col < 5; col++)
                if (g[row] & (0x10u >> col))
                    pg_fill_rect(c, cx + col * scale, y + row * scale, cx + (col + 1) * scale, y + (row + 1) * scale, color);
        cx += PG_CHAR_W * scale;
    }
    if (cx - x > width) width = cx - x;
    return width;
}

int pg_text_width(const char *text, int scale)
{
    int n = 0, best = 0;
    for (const char *s = text; *s; s++) {
        if (*s == '\n') n = 0;
        else if (++n > best) best = n;
    }
    return best * PG_CHAR_W * (scale < 1 ? 1 : scale);
}
