/* The SDL2 playground (build/ntile-play, named by NTILE_PLAY; make test sets it when
 * SDL2 is installed, and every test here is skipped with a message when it is not).
 *
 * The playground runs headless (SDL_VIDEODRIVER=dummy, one tick per frame) and saves
 * frames; the tests read the pixels back and check them against what the engine
 * says: a tile's colour where the level has a tile, a body where the replay puts it
 * (computed here with the game API), a gizmo present when enabled and absent when
 * not, edge states after painting, throws and deletes. Scripted input (--script)
 * goes through SDL's event queue, the path a keyboard takes: a replay recorded that
 * way must be replayed bit for bit by `ntile run` (NTILE) and by nt_run_replay, and
 * must fail once an input is changed. Also: PNG output equals the BMP (decoded here),
 * the offscreen driver gives the same frame, and bad input gives clear errors. */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "../tools/ntile-play/canvas.h"
#include "../tools/ntile-play/colors.h"
#include "child.h"
#include "scratch.h"
#include "ntile/game.h"

/* ---------- temporary files (scratch.h) ---------- */

static int group_setup(void **state)
{
    (void)state;
    if (scratch_create("play") != 0) return -1;
    /* No display needed: SDL's dummy video driver (a test may choose another). */
    setenv("SDL_VIDEODRIVER", "dummy", 1);
    setenv("SDL_AUDIODRIVER", "dummy", 1);
    return 0;
}

static int group_teardown(void **state)
{
    (void)state;
    scratch_remove();
    return 0;
}

/* ---------- running programs ---------- */

typedef child_result run_result;

/* The video driver of the next child run (NULL: the group's, dummy; "": none and no display). */
static const char *g_child_driver;

static const char *play_exe(void)
{
    const char *exe = getenv("NTILE_PLAY");
    static bool said;
    if (!exe || !*exe) {
        if (said) skip();
        said = true;
        print_message("skipped: the SDL2 playground was not built (SDL2's development files are missing: "
                      "tools/deps.sh sdl2 installs libsdl2-dev); NTILE_PLAY names it when it is\n");
        skip();
    }
    return exe;
}

/* In the child: the video driver asked for (ctx), or no display at all (""). */
static void set_driver(void *ctx)
{
    const char *driver = ctx;
    if (driver && *driver) setenv("SDL_VIDEODRIVER", driver, 1);
    if (driver && !*driver) { /* "": no display at all, no driver asked for */
        unsetenv("SDL_VIDEODRIVER");
        unsetenv("DISPLAY");
        unsetenv("WAYLAND_DISPLAY");
    }
}

/* Run a program (argv NULL-terminated), capturing both outputs. */
static void run_exe(run_result *r, const char *exe, const char *const *args)
{
    const char *driver = g_child_driver;
    g_child_driver = NULL; /* one run only, even if this one fails */
    child_run(r, scratch_dir(), exe, args, set_driver, (void *)driver, 99);
}

static void run_play(run_result *r, const char *const *args) { run_exe(r, play_exe(), args); }

static void run_free(run_result *r) { child_free(r); }

static void expect_status(const run_result *r, int status)
{
    if (r->status != status) fail_msg("exit status %d, expected %d\nstdout:\n%s\nstderr:\n%s", r->status, status, r->out, r->err);
}

static void expect_in(const char *text, const char *needle)
{
    if (!strstr(text, needle)) fail_msg("expected to find:\n%s\nin:\n%s", needle, text);
}

/* Run the playground and expect success. */
static void play_ok(const char *const *args)
{
    run_result r;
    run_play(&r, args);
    expect_status(&r, 0);
    run_free(&r);
}

/* ---------- images ---------- */

typedef struct image {
    int w, h;
    uint32_t *px; /* 0x00RRGGBB, top row first */
} image;

static uint32_t le32(const unsigned char *p) { return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24; }

/* 24- or 32-bit uncompressed (or BITFIELDS) BMP, bottom-up or top-down. */
static image load_bmp(const char *path)
{
    size_t n;
    unsigned char *b = (unsigned char *)scratch_read(path, &n);
    if (n < 54 || b[0] != 'B' || b[1] != 'M') fail_msg("%s is not a BMP", path);
    uint32_t off = le32(b + 10);
    int32_t w = (int32_t)le32(b + 18), h = (int32_t)le32(b + 22);
    int bpp = b[28] | b[29] << 8;
    uint32_t comp = le32(b + 30);
    if ((bpp != 24 && bpp != 32) || (comp != 0 && comp != 3) || w <= 0 || h == 0) fail_msg("%s: unsupported BMP (%d bpp, compression %u)", path, bpp, comp);
    bool top_down = h < 0;
    if (h < 0) h = -h;
    size_t stride = ((size_t)w * (size_t)(bpp / 8) + 3) & ~(size_t)3;
    if (off + stride * (size_t)h > n) fail_msg("%s: truncated BMP", path);
    image im = {w, h, malloc((size_t)w * (size_t)h * 4)};
    assert_non_null(im.px);
    for (int y = 0; y < h; y++) {
        const unsigned char *row = b + off + stride * (size_t)(top_down ? y : h - 1 - y);
        for (int x = 0; x < w; x++) {
            const unsigned char *q = row + (size_t)x * (size_t)(bpp / 8);
            im.px[(size_t)y * (size_t)w + (size_t)x] = (uint32_t)q[2] << 16 | (uint32_t)q[1] << 8 | q[0];
        }
    }
    free(b);
    return im;
}

static uint32_t pixel(const image *im, int x, int y)
{
    if (x < 0 || y < 0 || x >= im->w || y >= im->h) fail_msg("pixel (%d, %d) is outside the %dx%d image", x, y, im->w, im->h);
    return im->px[(size_t)y * (size_t)im->w + (size_t)x];
}

static void expect_pixel(const image *im, int x, int y, uint32_t color, const char *what)
{
    uint32_t c = pixel(im, x, y);
    if (c != color) fail_msg("%s: pixel (%d, %d) is 0x%06x, expected 0x%06x", what, x, y, c, color);
}

/* Pixels of exactly `color` in [x0, x1) x [y0, y1) (clipped). */
static int count_color(const image *im, int x0, int y0, int x1, int y1, uint32_t color)
{
    int n = 0;
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    if (x1 > im->w) x1 = im->w;
    if (y1 > im->h) y1 = im->h;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) n += im->px[(size_t)y * (size_t)im->w + (size_t)x] == color;
    return n;
}

/* A 24-bit BMP of one colour, for --image-stats. */
static void write_flat_bmp(const char *path, int w, int h, uint32_t color)
{
    size_t stride = ((size_t)w * 3 + 3) & ~(size_t)3, size = 54 + stride * (size_t)h;
    unsigned char *b = calloc(1, size);
    assert_non_null(b);
    b[0] = 'B', b[1] = 'M';
    for (int i = 0; i < 4; i++) {
        b[2 + i] = (unsigned char)(size >> (8 * i));
        b[18 + i] = (unsigned char)((uint32_t)w >> (8 * i));
        b[22 + i] = (unsigned char)((uint32_t)h >> (8 * i));
    }
    b[10] = 54, b[14] = 40, b[26] = 1, b[28] = 24;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            unsigned char *q = b + 54 + stride * (size_t)y + (size_t)x * 3;
            q[0] = (unsigned char)color, q[1] = (unsigned char)(color >> 8), q[2] = (unsigned char)(color >> 16);
        }
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(b, 1, size, f), size);
    fclose(f);
    free(b);
}

/* ---------- a small inflate (stored and fixed-Huffman blocks: what ntile-play writes) ---------- */

typedef struct bits {
    const unsigned char *p;
    size_t n, pos; /* pos in bits */
} bits;

static unsigned getbits(bits *b, int k)
{
    unsigned v = 0;
    for (int i = 0; i < k; i++, b->pos++) {
        if (b->pos / 8 >= b->n) fail_msg("inflate: out of data");
        v |= (unsigned)((b->p[b->pos / 8] >> (b->pos % 8)) & 1u) << i;
    }
    return v;
}

/* A fixed-code symbol: codes are read most significant bit first. */
static unsigned fixed_literal(bits *b)
{
    unsigned code = 0;
    for (int len = 1; len <= 9; len++) {
        code = code << 1 | getbits(b, 1);
        if (len == 7 && code <= 0x17) return code + 256;
        if (len == 8 && code >= 0x30 && code <= 0xbf) return code - 0x30;
        if (len == 8 && code >= 0xc0 && code <= 0xc7) return code - 0xc0 + 280;
        if (len == 9 && code >= 0x190) return code - 0x190 + 144;
    }
    fail_msg("inflate: bad fixed code");
    return 0;
}

static size_t inflate_simple(const unsigned char *src, size_t n, unsigned char *out, size_t cap)
{
    static const unsigned short lbase[29] = {3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
    static const unsigned char lext[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
    static const unsigned short dbase[30] = {1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
    static const unsigned char dext[30] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};
    bits b = {src, n, 0};
    size_t o = 0;
    for (;;) {
        unsigned final = getbits(&b, 1), type = getbits(&b, 2);
        if (type == 0) {
            b.pos = (b.pos + 7) & ~(size_t)7;
            unsigned len = getbits(&b, 16), nlen = getbits(&b, 16);
            if ((len ^ 0xffffu) != nlen) fail_msg("inflate: bad stored block");
            for (unsigned i = 0; i < len; i++) {
                if (o >= cap) fail_msg("inflate: too much output");
                out[o++] = (unsigned char)getbits(&b, 8);
            }
        } else if (type == 1) {
            for (;;) {
                unsigned s = fixed_literal(&b);
                if (s < 256) {
                    if (o >= cap) fail_msg("inflate: too much output");
                    out[o++] = (unsigned char)s;
                } else if (s == 256) {
                    break;
                } else {
                    s -= 257;
                    if (s >= 29) fail_msg("inflate: bad length code");
                    unsigned len = lbase[s] + getbits(&b, lext[s]);
                    unsigned dc = 0;
                    for (int i = 0; i < 5; i++) dc = dc << 1 | getbits(&b, 1);
                    if (dc >= 30) fail_msg("inflate: bad distance code");
                    size_t dist = dbase[dc] + getbits(&b, dext[dc]);
                    if (dist > o || o + len > cap) fail_msg("inflate: bad match");
                    for (unsigned i = 0; i < len; i++, o++) out[o] = out[o - dist];
                }
            }
        } else {
            fail_msg("inflate: block type %u (ntile-play writes only stored and fixed blocks)", type);
        }
        if (final) break;
    }
    return o;
}

static uint32_t be32(const unsigned char *p) { return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3]; }

static uint32_t crc32_of(const unsigned char *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++) c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
    }
    return ~c;
}

static image load_png(const char *path)
{
    size_t n;
    unsigned char *d = (unsigned char *)scratch_read(path, &n);
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (n < 8 || memcmp(d, sig, 8) != 0) fail_msg("%s: not a PNG", path);
    size_t at = 8, zn = 0;
    unsigned char *z = NULL;
    int w = 0, h = 0;
    bool end = false;
    while (at + 12 <= n && !end) {
        uint32_t len = be32(d + at);
        if (at + 12 + len > n) fail_msg("%s: truncated chunk", path);
        const unsigned char *type = d + at + 4, *body = d + at + 8;
        if (crc32_of(type, len + 4) != be32(body + len)) fail_msg("%s: bad CRC in %.4s", path, (const char *)type);
        if (memcmp(type, "IHDR", 4) == 0) {
            w = (int)be32(body), h = (int)be32(body + 4);
            if (body[8] != 8 || body[9] != 2 || body[12] != 0) fail_msg("%s: expected 8-bit RGB, no interlace", path);
        } else if (memcmp(type, "IDAT", 4) == 0) {
            z = realloc(z, zn + len);
            assert_non_null(z);
            memcpy(z + zn, body, len);
            zn += len;
        } else if (memcmp(type, "IEND", 4) == 0) {
            end = true;
        }
        at += 12 + len;
    }
    if (!end || w <= 0 || h <= 0 || zn < 6) fail_msg("%s: incomplete PNG", path);
    if ((z[0] & 0x0f) != 8 || ((unsigned)z[0] << 8 | z[1]) % 31 != 0) fail_msg("%s: bad zlib header", path);
    size_t row = (size_t)w * 3 + 1, rawn = row * (size_t)h;
    unsigned char *raw = malloc(rawn);
    assert_non_null(raw);
    size_t got = inflate_simple(z + 2, zn - 6, raw, rawn);
    assert_int_equal(got, rawn);
    /* Adler-32 of the inflated data. */
    uint32_t a = 1, bsum = 0;
    for (size_t i = 0; i < rawn; i++) a = (a + raw[i]) % 65521u, bsum = (bsum + a) % 65521u;
    assert_int_equal(bsum << 16 | a, be32(z + zn - 4));
    image im = {w, h, malloc((size_t)w * (size_t)h * 4)};
    assert_non_null(im.px);
    for (int y = 0; y < h; y++) {
        unsigned char *r = raw + (size_t)y * row, *prev = y ? raw + (size_t)(y - 1) * row : NULL;
        for (size_t i = 1; i < row; i++) {
            unsigned left = i > 3 ? r[i - 3] : 0, up = prev ? prev[i] : 0, ul = prev && i > 3 ? prev[i - 3] : 0;
            switch (r[0]) {
            case 0: break;
            case 1: r[i] = (unsigned char)(r[i] + left); break;
            case 2: r[i] = (unsigned char)(r[i] + up); break;
            case 3: r[i] = (unsigned char)(r[i] + (left + up) / 2); break;
            case 4: {
                int pa = abs((int)up - (int)ul), pb = abs((int)left - (int)ul), pc = abs((int)left + (int)up - 2 * (int)ul);
                unsigned pr = (pa <= pb && pa <= pc) ? left : pb <= pc ? up : ul;
                r[i] = (unsigned char)(r[i] + pr);
                break;
            }
            default: fail_msg("%s: bad filter %d", path, r[0]);
            }
        }
        for (int x = 0; x < w; x++)
            im.px[(size_t)y * (size_t)w + (size_t)x] = (uint32_t)r[1 + 3 * x] << 16 | (uint32_t)r[2 + 3 * x] << 8 | r[3 + 3 * x];
    }
    free(raw);
    free(z);
    free(d);
    return im;
}

/* ---------- the game, headless, for where things should be ---------- */

static nt_level *load_level(const char *path)
{
    char *text = scratch_read(path, NULL);
    nt_level *lv = NULL;
    nt_text_error e;
    if (nt_level_parse(path, text, strlen(text), &lv, &e) != NT_OK) fail_msg("%s", e.message);
    free(text);
    return lv;
}

/* The position of a level body after `ticks` ticks with no keys. */
static nt_vec2 body_after(const char *level, const char *name, int ticks)
{
    nt_level *lv = load_level(level);
    nt_game *g;
    assert_int_equal(nt_game_create(lv, NULL, &g), NT_OK);
    for (int t = 0; t < ticks; t++) assert_int_equal(nt_game_step(g, 0, (nt_real)0.025), NT_OK);
    nt_body_id id = nt_game_find_body(g, name);
    assert_false(nt_body_id_is_null(id));
    nt_vec2 p = nt_body_get_position(nt_game_get_world(g), id);
    nt_game_destroy(g);
    nt_level_destroy(lv);
    return p;
}

/* The lab (20 x 12 cells of 24) drawn at 2 pixels per unit with the camera at its
 * centre: world (x, y) is pixel (2x, 2y). */
#define LAB_VIEW "--no-hud", "--size", "960x576", "--zoom", "2", "--center", "240", "144"
#define LAB_PX(v) ((int)floor(2 * (double)(v)))

/* ---------- tests ---------- */

/* A tile's colour where the level has a tile; a body where the replay puts it and
 * not where it started; empty space elsewhere. */
static void test_tiles_and_bodies(void **state)
{
    (void)state;
    const char *out = scratch_path("lab40.bmp");
    play_ok((const char *[]){"--replay", "tests/replays/lab.ntr", "--frames", "40", LAB_VIEW, "--screenshot", out, NULL});
    image im = load_bmp(out);
    assert_int_equal(im.w, 960);
    assert_int_equal(im.h, 576);
    expect_pixel(&im, 24, 24, PG_COLOR_TILE, "the FULL tile in cell (0, 0)");
    expect_pixel(&im, 2 * 24 * 19 + 24, 2 * 24 * 11 + 24, PG_COLOR_TILE, "the FULL tile in cell (19, 11)");
    expect_pixel(&im, 2 * 60, 2 * 60, PG_COLOR_BG, "the empty cell (2, 2)");
    nt_vec2 a = body_after("levels/lab.ntl", "puck_a", 40), b = body_after("levels/lab.ntl", "puck_b", 40);
    assert_true(a.x > 200); /* it moved (it starts at x = 120) */
    uint32_t fill = PG_BODY_FILL(PG_ENGINE_AWAKE);
    expect_pixel(&im, LAB_PX(a.x), LAB_PX(a.y), fill, "puck_a where the replay puts it at tick 40");
    expect_pixel(&im, LAB_PX(b.x), LAB_PX(b.y), fill, "puck_b where the replay puts it at tick 40");
    expect_pixel(&im, LAB_PX(a.x) + 2 * 10 - 3, LAB_PX(a.y), fill, "inside puck_a's radius (10)");
    expect_pixel(&im, LAB_PX(a.x) + 2 * 10 + 3, LAB_PX(a.y), PG_COLOR_BG, "just outside puck_a");
    expect_pixel(&im, LAB_PX(120), LAB_PX(144), PG_COLOR_BG, "where puck_a started");
    free(im.px);
}

/* The lab's HUD figures (printed on exit in automation): the pucks close a 220-unit
 * gap at 140 units/s, so they meet 1.571 s in, during the 63rd tick of 1/40 s, and the
 * collision is handled in that tick; momentum stays (60, 0) and the kinetic energy
 * falls from 7800 to the analytic 2287.5 (bounce 0.5; levels/lab.ntl works it out). */
static void test_lab_collision_figures(void **state)
{
    (void)state;
    run_result r;
    run_play(&r, (const char *[]){"--replay", "tests/replays/lab.ntr", "--frames", "62", "--no-hud", NULL});
    expect_status(&r, 0);
    if (strstr(r.out, "last collision")) fail_msg("no collision should be reported before tick 63:\n%s", r.out);
    run_free(&r);
    run_play(&r, (const char *[]){"--replay", "tests/replays/lab.ntr", "--frames", "70", "--no-hud", NULL});
    expect_status(&r, 0);
    expect_in(r.out, "tick 70  bodies 2 (awake 2)  score 0");
    expect_in(r.out, "last collision tick 63: momentum (60.00, 0.00) -> (60.00, 0.00), kinetic energy 7800.0 -> 2287.5");
    run_free(&r);
}

/* Render interpolation: with --alpha A a body is drawn A of the way from where it
 * was before the last tick to where it is (its arrows move with it). */
static void test_interpolation(void **state)
{
    (void)state;
    const char *a0 = scratch_path("alpha0.bmp"), *a5 = scratch_path("alpha5.bmp");
    play_ok((const char *[]){"--replay", "tests/replays/lab.ntr", "--frames", "40", LAB_VIEW, "--alpha", "0", "--screenshot", a0, NULL});
    play_ok((const char *[]){"--replay", "tests/replays/lab.ntr", "--frames", "40", LAB_VIEW, "--alpha", "0.5", "--screenshot", a5, NULL});
    image i0 = load_bmp(a0), i5 = load_bmp(a5);
    nt_vec2 p39 = body_after("levels/lab.ntl", "puck_a", 39), p40 = body_after("levels/lab.ntl", "puck_a", 40);
    assert_true(p40.x - p39.x > 2.9f); /* 3 units (6 pixels) a tick */
    uint32_t fill = PG_BODY_FILL(PG_ENGINE_AWAKE);
    /* Radius 10 units = 20 pixels: the right edge is where the centre drawn puts it. */
    expect_pixel(&i0, LAB_PX(p39.x) + 18, LAB_PX(p39.y), fill, "alpha 0: inside the puck at its tick-39 place");
    expect_pixel(&i0, LAB_PX(p40.x) + 18, LAB_PX(p40.y), PG_COLOR_BG, "alpha 0: not at its tick-40 place");
    double mid = 0.5 * ((double)p39.x + (double)p40.x);
    expect_pixel(&i5, LAB_PX(mid) + 18, LAB_PX(p40.y), fill, "alpha 0.5: inside the puck half way");
    expect_pixel(&i5, LAB_PX(mid) + 22, LAB_PX(p40.y), PG_COLOR_BG, "alpha 0.5: just outside it");
    free(i0.px);
    free(i5.px);
}

/* A resize (scripted, as a window manager would) gives frames of the new size, the
 * strip on the new right edge. */
static void test_resize(void **state)
{
    (void)state;
    scratch_write_text("resize.script", "2 resize 640 400\n");
    const char *out = scratch_path("resized.bmp");
    play_ok((const char *[]){"levels/ninja.ntl", "--script", scratch_path("resize.script"), "--frames", "4", "--screenshot", out, NULL});
    image im = load_bmp(out);
    assert_int_equal(im.w, 640);
    assert_int_equal(im.h, 400);
    expect_pixel(&im, 639, 399, PG_COLOR_STRIP, "the strip's background at the new size");
    assert_true(count_color(&im, 0, 0, 560, 400, PG_COLOR_TILE) > 10000); /* the level, scaled to fit */
    free(im.px);
}

/* The velocity gizmo: arrows in the engine's colour from each puck's centre along
 * its velocity when enabled, none anywhere when not; the same for edge states. */
static void test_gizmo_on_off(void **state)
{
    (void)state;
    const char *on = scratch_path("gz-on.bmp"), *off = scratch_path("gz-off.bmp");
    play_ok((const char *[]){"--replay", "tests/replays/lab.ntr", "--frames", "40", LAB_VIEW, "--gizmos", "velocities,edges",
                             "--screenshot", on, NULL});
    play_ok((const char *[]){"--replay", "tests/replays/lab.ntr", "--frames", "40", LAB_VIEW, "--screenshot", off, NULL});
    image a = load_bmp(on), b = load_bmp(off);
    nt_vec2 pa = body_after("levels/lab.ntl", "puck_a", 40);
    int cx = LAB_PX(pa.x), cy = LAB_PX(pa.y);
    /* puck_a moves right at 120 units/s: its arrow is 12 units (24 pixels) long. */
    int along = count_color(&a, cx, cy - 1, cx + 26, cy + 2, PG_ENGINE_VELOCITY);
    int behind = count_color(&a, cx - 26, cy - 1, cx - 1, cy + 2, PG_ENGINE_VELOCITY);
    if (along < 20) fail_msg("velocity arrow: %d pixels of 0x%06x to the right of puck_a, expected >= 20", along, PG_ENGINE_VELOCITY);
    assert_int_equal(behind, 0);
    assert_int_equal(count_color(&b, 0, 0, b.w, b.h, PG_ENGINE_VELOCITY), 0);
    /* Edge states: the SOLID edges (red) line the inside of the wall, never its seams. */
    assert_true(count_color(&a, 0, 47, a.w, 50, 0xe04040u) > 600); /* the top wall's lower edge, y = 24 units */
    expect_pixel(&a, LAB_PX(24 * 5), 24, PG_COLOR_TILE, "inside the top wall (seams are OFF)");
    assert_int_equal(count_color(&b, 0, 0, b.w, b.h, 0xe04040u), 0);
    free(a.px);
    free(b.px);
}

/* The HUD and the tile strip: strip background, the FULL swatch filled and selected;
 * Tab (through SDL's event queue) moves the selection to the next tile. */
static void test_hud_and_palette(void **state)
{
    (void)state;
    const char *out = scratch_path("hud.bmp"), *out2 = scratch_path("hud-tab.bmp");
    scratch_write_text("tab.script", "1 press Tab\n");
    play_ok((const char *[]){"levels/ninja.ntl", "--frames", "2", "--size", "1024x640", "--screenshot", out, NULL});
    play_ok((const char *[]){"levels/ninja.ntl", "--frames", "2", "--size", "1024x640", "--script", scratch_path("tab.script"),
                             "--screenshot", out2, NULL});
    image a = load_bmp(out), b = load_bmp(out2);
    /* The strip's geometry (render.c): cells of c pixels with 4-pixel gaps below a 24-pixel title. */
    int g = 4, c = (640 - 24 - g * 18) / 17;
    if (c > 28) c = 28;
    int x0 = 1024 - (2 * c + 3 * g);
    expect_pixel(&a, 1023, 639, PG_COLOR_STRIP, "the strip's background");
    int sx1 = x0 + g + (c + g), sy0 = 24 + g; /* FULL: column 1, row 0 */
    expect_pixel(&a, sx1 + c / 2, sy0 + c / 2, PG_COLOR_TILE, "the FULL swatch");
    expect_pixel(&a, sx1 - 2, sy0 + c / 2, PG_COLOR_SELECT, "the selection around FULL");
    int sx0 = x0 + g, sy1 = 24 + g + (c + g); /* 45DEGpn: column 0, row 1 */
    expect_pixel(&a, sx0 - 2, sy1 + c / 2, PG_COLOR_STRIP, "no selection around 45DEGpn before Tab");
    expect_pixel(&b, sx0 - 2, sy1 + c / 2, PG_COLOR_SELECT, "the selection around 45DEGpn after Tab");
    expect_pixel(&b, sx1 - 2, sy0 + c / 2, PG_COLOR_STRIP, "no selection around FULL after Tab");
    /* The side panel on the left, beside the level and never over it: its text, its
     * background down to the bottom, and the level's outer wall just right of it. */
    assert_true(count_color(&a, 0, 0, PG_PANEL_W, 640, PG_COLOR_TEXT) > 1000);
    expect_pixel(&a, 2, 630, PG_COLOR_PANEL_BG, "the panel's background");
    assert_int_equal(count_color(&a, PG_PANEL_W, 0, x0, 640, PG_COLOR_TEXT), 0);
    free(a.px);
    free(b.px);
}

/* Record with F5 through scripted key events (a throw attempted while recording is
 * refused), then check the replay with `ntile run` and nt_run_replay; one input
 * changed must fail. */
static void test_record_replay(void **state)
{
    (void)state;
    scratch_write_text("rec.script", "1 press F5\n"
                             "2 down Right\n"
                             "40 down Z\n"
                             "48 up Z\n"
                             "60 mouse down left 300 300\n"
                             "62 mouse up left 360 300\n"
                             "70 up Right\n"
                             "75 down Left\n"
                             "76 down Space\n"
                             "90 up Space\n"
                             "100 up Left\n"
                             "120 press F5\n");
    const char *rec = scratch_path("rec.ntr");
    run_result r;
    run_play(&r, (const char *[]){"levels/ninja.ntl", "--script", scratch_path("rec.script"), "--frames", "130", "--record", rec,
                                  "--save-dir", scratch_dir(), NULL});
    expect_status(&r, 0);
    expect_in(r.out, "recorded 119 ticks");
    run_free(&r);
    char *text = scratch_read(rec, NULL);
    expect_in(text, "ticks 119\n");
    expect_in(text, "input 1. 38R 8RJ 22R 5. 1L 14LJ 10L 20.\n");
    expect_in(text, NT_REAL_IS_DOUBLE ? "hash double 119 0x" : "hash float 119 0x");
    expect_in(text, "expect alive at 119\n");

    const char *ntile = getenv("NTILE");
    if (ntile && *ntile) {
        run_exe(&r, ntile, (const char *[]){"run", rec, NULL});
        expect_status(&r, 0);
        expect_in(r.out, "1 passed, 0 failed");
        run_free(&r);
    }
    /* The runner API: the same check in this process. */
    nt_replay *rp;
    nt_text_error e;
    if (nt_replay_parse(rec, text, strlen(text), &rp, &e) != NT_OK) fail_msg("%s", e.message);
    nt_level *lv = load_level("levels/ninja.ntl");
    nt_run_report rep;
    assert_int_equal(nt_run_replay(rp, lv, &rep), NT_OK);
    if (!rep.passed) fail_msg("the recorded replay failed: %s", rep.message_count ? rep.messages[0] : "?");
    assert_int_equal(rep.ticks, 119);
    assert_int_equal(rep.hash_failures, 0);
    nt_run_report_free(&rep);
    /* One tick of input moved from "right" to "nothing": the run must diverge. */
    char *bad = strdup(text);
    assert_non_null(bad);
    char *at = strstr(bad, "input 1. 38R");
    assert_non_null(at);
    memcpy(at, "input 2. 37R", 12);
    nt_replay *rp2;
    if (nt_replay_parse(rec, bad, strlen(bad), &rp2, &e) != NT_OK) fail_msg("%s", e.message);
    assert_int_equal(nt_run_replay(rp2, lv, &rep), NT_OK);
    assert_false(rep.passed);
    assert_true(rep.hash_failures > 0);
    assert_int_equal(rep.first_divergence, 2);
    nt_run_report_free(&rep);
    scratch_write_text("rec-bad.ntr", bad);
    if (ntile && *ntile) {
        /* The level path in the file is relative to the replay's directory: same directory. */
        run_exe(&r, ntile, (const char *[]){"run", scratch_path("rec-bad.ntr"), NULL});
        expect_status(&r, 1);
        expect_in(r.out, "first tick that diverges: 2");
        run_free(&r);
    }
    nt_replay_destroy(rp);
    nt_replay_destroy(rp2);
    nt_level_destroy(lv);
    free(bad);
    free(text);
}

/* Recording an edited level (painted, and switched to Coulomb friction) saves the
 * level first, so that the replay names a file holding exactly what was played. */
static void test_record_edited_level(void **state)
{
    (void)state;
    /* In the lab (20 x 12 cells, drawn at 2 pixels a unit): paint cell (9, 5) in the
     * path of the pucks, switch the friction model, record 81 ticks. */
    scratch_write_text("edit.script", "1 mouse down right 456 264\n"
                              "1 mouse up right 456 264\n"
                              "2 press F\n"
                              "3 press F5\n"
                              "84 press F5\n");
    run_result r;
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("edit.script"), "--frames", "85", LAB_VIEW,
                                  "--save-dir", scratch_dir(), NULL});
    expect_status(&r, 0);
    run_free(&r);
    nt_level *lv = load_level(scratch_path("lab-edit.ntl"));
    assert_int_equal(lv->tiles[5 * lv->width + 9], NT_TILE_FULL);
    assert_int_equal(lv->friction_model, NT_FRICTION_COULOMB);
    nt_level_destroy(lv);
    char *text = scratch_read(scratch_path("lab-edit-001.ntr"), NULL);
    expect_in(text, "level lab-edit.ntl\n");
    expect_in(text, "ticks 81\n"); /* frames 3 .. 83 */
    free(text);
    const char *ntile = getenv("NTILE");
    if (ntile && *ntile) {
        run_exe(&r, ntile, (const char *[]){"run", scratch_path("lab-edit-001.ntr"), NULL});
        expect_status(&r, 0);
        run_free(&r);
        /* Against the original level the same inputs do not give the same run. */
        char *t2 = scratch_read(scratch_path("lab-edit-001.ntr"), NULL);
        char *at = strstr(t2, "level lab-edit.ntl");
        assert_non_null(at);
        char cwd[4096], line[4400];
        assert_non_null(getcwd(cwd, sizeof cwd));
        snprintf(line, sizeof line, "level \"%s/levels/lab.ntl\"", cwd);
        size_t head = (size_t)(at - t2);
        char *t3 = malloc(strlen(t2) + strlen(line) + 1);
        assert_non_null(t3);
        memcpy(t3, t2, head);
        strcpy(t3 + head, line);
        strcat(t3, at + strlen("level lab-edit.ntl"));
        scratch_write_text("lab-orig.ntr", t3);
        run_exe(&r, ntile, (const char *[]){"run", scratch_path("lab-orig.ntr"), NULL});
        expect_status(&r, 1);
        run_free(&r);
        free(t2);
        free(t3);
    }
}

/* Right-drag paints FULL tiles across three cells; the edge states update at once (a
 * SOLID edge above them, no edge on the seams between them); F2 saves the level with
 * the paint and nothing else changed. */
static void test_paint_and_save(void **state)
{
    (void)state;
    /* Cells (5, 5) .. (7, 5): centres at world (132, 132) .. (180, 132). */
    scratch_write_text("paint.script", "1 mouse down right 264 264\n"
                               "2 mouse move 312 264\n"
                               "3 mouse move 360 264\n"
                               "3 mouse up right 360 264\n"
                               "4 press F2\n");
    const char *out = scratch_path("paint.bmp"), *saved = scratch_path("painted.ntl");
    run_result r;
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("paint.script"), "--frames", "6", LAB_VIEW,
                                  "--gizmos", "edges", "--save", saved, "--screenshot", out, NULL});
    expect_status(&r, 0);
    run_free(&r);
    image im = load_bmp(out);
    for (int x = 5; x <= 7; x++) expect_pixel(&im, 2 * (24 * x + 12), 2 * 132, PG_COLOR_TILE, "a painted FULL tile");
    expect_pixel(&im, 2 * (24 * 4 + 12), 2 * 132, PG_COLOR_BG, "the cell left of the paint");
    /* Top edge of cell (6, 5) at y = 120 units: SOLID (red). */
    assert_true(count_color(&im, 2 * 150, 2 * 120 - 1, 2 * 162, 2 * 120 + 2, 0xe04040u) >= 10);
    /* The seam between (5, 5) and (6, 5) at x = 144 units: OFF (no edge drawn). */
    assert_int_equal(count_color(&im, 2 * 144 - 1, 2 * 124, 2 * 144 + 2, 2 * 140, 0xe04040u), 0);
    free(im.px);
    nt_level *lv = load_level(saved), *orig = load_level("levels/lab.ntl");
    assert_int_equal(lv->width, orig->width);
    for (int y = 0; y < lv->height; y++)
        for (int x = 0; x < lv->width; x++) {
            int want = (y == 5 && x >= 5 && x <= 7) ? NT_TILE_FULL : orig->tiles[y * orig->width + x];
            if (lv->tiles[y * lv->width + x] != want) fail_msg("saved tile (%d, %d) is %d, expected %d", x, y, lv->tiles[y * lv->width + x], want);
        }
    assert_int_equal(lv->body_count, orig->body_count);
    nt_level_destroy(lv);
    nt_level_destroy(orig);
}

/* A left click with no drag throws a ball at rest (the lab has no gravity); a middle
 * click deletes it. */
static void test_throw_and_delete(void **state)
{
    (void)state;
    scratch_write_text("throw.script", "1 mouse down left 120 120\n1 mouse up left 120 120\n");
    scratch_write_text("delete.script", "1 mouse down left 120 120\n1 mouse up left 120 120\n5 mouse down middle 120 120\n"
                                "5 mouse up middle 120 120\n");
    const char *a = scratch_path("throw.bmp"), *b = scratch_path("delete.bmp");
    play_ok((const char *[]){"levels/lab.ntl", "--script", scratch_path("throw.script"), "--frames", "8", LAB_VIEW, "--screenshot", a, NULL});
    play_ok((const char *[]){"levels/lab.ntl", "--script", scratch_path("delete.script"), "--frames", "8", LAB_VIEW, "--screenshot", b, NULL});
    image ia = load_bmp(a), ib = load_bmp(b);
    expect_pixel(&ia, 120, 120, PG_BODY_FILL(PG_ENGINE_AWAKE), "the thrown ball");
    expect_pixel(&ia, 120 + 2 * 6, 120, PG_BODY_FILL(PG_ENGINE_AWAKE), "inside the ball (radius 0.3 cell)");
    expect_pixel(&ib, 120, 120, PG_COLOR_BG, "the deleted ball");
    free(ia.px);
    free(ib.px);
}

/* L cycles the thrown body's size (0.6, 1, 2, 4 cells across, then back): the
 * message says it, and the throw preview (left button held) has that size. */
static void test_throw_size_key(void **state)
{
    (void)state;
    scratch_write_text("size.script", "1 press L\n2 press L\n3 press L\n4 mouse down left 480 288\n");
    const char *a = scratch_path("size.bmp");
    run_result r;
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("size.script"), "--frames", "6", LAB_VIEW,
                                  "--screenshot", a, NULL});
    expect_status(&r, 0);
    expect_in(r.out, "thrown bodies: 4 cells across");
    run_free(&r);
    /* Zoom 2: a ball 4 cells (96 units) across is a circle of radius 96 pixels. */
    image im = load_bmp(a);
    assert_true(count_color(&im, 480 + 94, 286, 480 + 99, 291, PG_COLOR_SELECT) > 0);
    assert_true(count_color(&im, 480 - 99, 286, 480 - 94, 291, PG_COLOR_SELECT) > 0);
    assert_int_equal(count_color(&im, 480 + 10, 282, 480 + 20, 294, PG_COLOR_SELECT), 0); /* not the default 0.6 cells */
    free(im.px);
    /* A fourth press comes back to the default. */
    scratch_write_text("size4.script", "1 press L\n2 press L\n3 press L\n4 press L\n");
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("size4.script"), "--frames", "6", LAB_VIEW, NULL});
    expect_status(&r, 0);
    expect_in(r.out, "thrown bodies: 0.6 cells across");
    run_free(&r);
    /* A 4-cell ball thrown at world (30, 30), in the room by the corner, would reach
     * outside the map: refused, said why. */
    scratch_write_text("edge.script", "1 press L\n2 press L\n3 press L\n4 mouse down left 60 60\n4 mouse up left 60 60\n");
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("edge.script"), "--frames", "6", LAB_VIEW, NULL});
    expect_status(&r, 0);
    expect_in(r.out, "cannot throw there: a body larger than half a cell must lie inside the map");
    expect_in(r.out, "bodies 2 ");
    run_free(&r);
}

/* A 20 x 12 room of cells of 24, a FULL floor at row 8 (top y = 192) over an empty
 * gap, and the bottom row FULL (top y = 264). */
static const char shelf_level[] = "ntile-level 1\nsize 20 12\ncell 24\ntiles\n"
                                  "|####################|\n|#..................#|\n|#..................#|\n"
                                  "|#..................#|\n|#..................#|\n|#..................#|\n"
                                  "|#..................#|\n|#..................#|\n|####################|\n"
                                  "|#..................#|\n|#..................#|\n|####################|\n";

/* A large thrown box (4 cells across) falls asleep on the floor; painting the floor
 * under it away wakes it and it drops to the bottom row (needs the engine to accept
 * large bodies). */
static void test_large_throw_and_paint(void **state)
{
    (void)state;
    scratch_write_text("shelf.ntl", shelf_level);
    /* Q: box; L x 3: 4 cells across; a click at world (240, 120) throws it at rest. */
    static const char throw_lines[] = "1 press Q\n1 press L\n1 press L\n1 press L\n2 mouse down left 480 240\n"
                                      "2 mouse up left 480 240\n";
    scratch_write_text("big.script", throw_lines);
    /* Then Tab x 33 (FULL -> EMPTY) and a right-drag along row 8, cells 1..18. */
    char paint[4096];
    int n = snprintf(paint, sizeof paint, "%s", throw_lines);
    for (int i = 0; i < NT_TILE_COUNT - 1; i++) n += snprintf(paint + n, sizeof paint - (size_t)n, "3 press Tab\n");
    snprintf(paint + n, sizeof paint - (size_t)n, "100 mouse down right 72 408\n101 mouse move 888 408\n101 mouse up right 888 408\n");
    scratch_write_text("bigpaint.script", paint);
    const char *a = scratch_path("big.bmp"), *b = scratch_path("bigpaint.bmp");
    const char *view[] = {"--no-hud", "--size", "960x576", "--zoom", "2", "--center", "240", "144"};
    run_result r;
    run_play(&r, (const char *[]){scratch_path("shelf.ntl"), "--script", scratch_path("big.script"), "--frames", "100", view[0],
                                  view[1], view[2], view[3], view[4], view[5], view[6], view[7], "--screenshot", a, NULL});
    expect_status(&r, 0);
    expect_in(r.out, "bodies 1 (awake 0)");
    run_free(&r);
    run_play(&r, (const char *[]){scratch_path("shelf.ntl"), "--script", scratch_path("bigpaint.script"), "--frames", "180",
                                  view[0], view[1], view[2], view[3], view[4], view[5], view[6], view[7], "--screenshot", b, NULL});
    expect_status(&r, 0);
    run_free(&r);
    image ia = load_bmp(a), ib = load_bmp(b);
    /* Asleep on the floor: centre (240, 144), 48 units each way (the painting cursor
     * outlines cell (10, 5), where the click was: looked at beside it). */
    expect_pixel(&ia, 2 * 230, 2 * 150, PG_BODY_FILL(0x808080u), "the large box asleep on the floor");
    expect_pixel(&ia, 480 + 2 * 44, 2 * 110, PG_BODY_FILL(0x808080u), "inside the large box (48 units half-size)");
    expect_pixel(&ia, 480, 2 * 204, PG_COLOR_TILE, "the floor under it");
    /* The floor painted away: it fell to the bottom row (centre y 216, spans 168..264). */
    expect_pixel(&ib, 2 * 84, 2 * 204, PG_COLOR_BG, "a painted floor cell (3, 8)");
    expect_pixel(&ib, 480, 2 * 120, PG_COLOR_BG, "where the box was");
    uint32_t c = pixel(&ib, 480, 2 * 240);
    if (c != PG_BODY_FILL(0x808080u) && c != PG_BODY_FILL(PG_ENGINE_AWAKE))
        fail_msg("the large box on the bottom row: pixel is 0x%06x", c);
    free(ia.px);
    free(ib.px);
}

/* F switches the friction model: the world is rebuilt from the level, and F2 saves
 * the level with the new model. */
static void test_friction_model_switch(void **state)
{
    (void)state;
    scratch_write_text("model.script", "1 press F\n2 press F2\n");
    const char *saved = scratch_path("coulomb.ntl");
    run_result r;
    run_play(&r, (const char *[]){"levels/slopes.ntl", "--script", scratch_path("model.script"), "--frames", "3", "--save", saved, NULL});
    expect_status(&r, 0);
    run_free(&r);
    nt_level *lv = load_level(saved);
    assert_int_equal(lv->friction_model, NT_FRICTION_COULOMB);
    nt_level_destroy(lv);
}

/* PNG output (own encoder) holds exactly the BMP's pixels; frames are deterministic. */
static void test_png_and_determinism(void **state)
{
    (void)state;
    const char *bmp = scratch_path("n.bmp"), *bmp2 = scratch_path("n2.bmp"), *png = scratch_path("n.png");
    const char *args = "edges,velocities,split,contacts,rays,grid,tiles,bodies,projections,sleep,sensors,stats";
    play_ok((const char *[]){"--replay", "tests/replays/ninja.ntr", "--frames", "120", "--gizmos", args, "--mouse", "400", "200",
                             "--screenshot", bmp, NULL});
    play_ok((const char *[]){"--replay", "tests/replays/ninja.ntr", "--frames", "120", "--gizmos", args, "--mouse", "400", "200",
                             "--screenshot", png, NULL});
    play_ok((const char *[]){"--replay", "tests/replays/ninja.ntr", "--frames", "120", "--gizmos", args, "--mouse", "400", "200",
                             "--screenshot", bmp2, NULL});
    image a = load_bmp(bmp), b = load_png(png), c = load_bmp(bmp2);
    assert_int_equal(a.w, b.w);
    assert_int_equal(a.h, b.h);
    size_t png_size;
    free(scratch_read(png, &png_size));
    assert_true(png_size < (size_t)a.w * (size_t)a.h); /* compressed: under a byte per pixel */
    /* The panel's fps and step time are wall-clock, alone on its bottom line: compare
     * everything else. */
    for (int y = 0; y < a.h; y++)
        for (int x = 0; x < a.w; x++) {
            if (x < PG_PANEL_W && y >= a.h - PG_CHAR_H - 4) continue;
            if (pixel(&a, x, y) != pixel(&b, x, y)) fail_msg("PNG and BMP differ at (%d, %d)", x, y);
            if (pixel(&a, x, y) != pixel(&c, x, y)) fail_msg("two runs differ at (%d, %d)", x, y);
        }
    free(a.px);
    free(b.px);
    free(c.px);
}

/* SDL's offscreen driver gives the same frame as the dummy driver. */
static void test_offscreen_driver(void **state)
{
    (void)state;
    const char *a = scratch_path("dummy.bmp"), *b = scratch_path("offscreen.bmp");
    play_ok((const char *[]){"--replay", "tests/replays/lab.ntr", "--frames", "30", LAB_VIEW, "--screenshot", a, NULL});
    run_result r;
    g_child_driver = "offscreen";
    run_play(&r, (const char *[]){"--replay", "tests/replays/lab.ntr", "--frames", "30", LAB_VIEW, "--screenshot", b, NULL});
    if (r.status != 0 && strstr(r.err, "cannot")) {
        print_message("skipped: SDL's offscreen video driver is not available here: %s", r.err);
        run_free(&r);
        skip();
    }
    expect_status(&r, 0);
    run_free(&r);
    size_t na, nb;
    unsigned char *da = (unsigned char *)scratch_read(a, &na), *db = (unsigned char *)scratch_read(b, &nb);
    assert_int_equal(na, nb);
    assert_memory_equal(da, db, na);
    free(da);
    free(db);
}

/* --image-stats tells a picture from a blank frame (CI uses it on the Xvfb run). */
static void test_image_stats(void **state)
{
    (void)state;
    const char *flat = scratch_path("flat.bmp"), *shot = scratch_path("stats.bmp");
    write_flat_bmp(flat, 64, 48, 0x102030u);
    run_result r;
    run_play(&r, (const char *[]){"--image-stats", flat, NULL});
    expect_status(&r, 3);
    expect_in(r.out, "blank");
    run_free(&r);
    play_ok((const char *[]){"--replay", "tests/replays/ninja.ntr", "--frames", "5", "--screenshot", shot, NULL});
    run_play(&r, (const char *[]){"--image-stats", shot, NULL});
    expect_status(&r, 0);
    expect_in(r.out, "not blank");
    run_free(&r);
    run_play(&r, (const char *[]){"--image-stats", scratch_path("missing.bmp"), NULL});
    expect_status(&r, 1);
    run_free(&r);
}

/* The player is drawn as it is: white while alive; dark red and crossed out once
 * dead (ninja-mine.ntr walks onto the mine and dies by tick 40). */
static void test_dead_player_drawn(void **state)
{
    (void)state;
    const char *alive = scratch_path("alive.bmp"), *dead = scratch_path("dead.bmp");
    play_ok((const char *[]){"--replay", "tests/replays/ninja-mine.ntr", "--frames", "5", "--screenshot", alive, NULL});
    play_ok((const char *[]){"--replay", "tests/replays/ninja-mine.ntr", "--frames", "120", "--screenshot", dead, NULL});
    image a = load_bmp(alive), d = load_bmp(dead);
    assert_true(count_color(&a, 0, 0, a.w, a.h, PG_COLOR_PLAYER) > 50);
    assert_int_equal(count_color(&a, 0, 0, a.w, a.h, PG_COLOR_PLAYER_DEAD), 0);
    assert_int_equal(count_color(&d, 0, 0, d.w, d.h, PG_COLOR_PLAYER), 0);
    assert_true(count_color(&d, 0, 0, d.w, d.h, PG_COLOR_PLAYER_DEAD) > 20);
    assert_true(count_color(&d, 0, 0, d.w, d.h, PG_COLOR_DEAD_MARK) > 5);
    /* At rest: 80 ticks later the dead player covers the same pixels (the whole level
     * is in view, the camera does not move). */
    const char *later = scratch_path("dead-later.bmp");
    play_ok((const char *[]){"--replay", "tests/replays/ninja-mine.ntr", "--frames", "200", "--screenshot", later, NULL});
    image l = load_bmp(later);
    for (int y = 0; y < d.h; y++)
        for (int x = PG_PANEL_W; x < d.w - 80; x++)
            if ((pixel(&d, x, y) == PG_COLOR_PLAYER_DEAD) != (pixel(&l, x, y) == PG_COLOR_PLAYER_DEAD))
                fail_msg("the dead player moved between ticks 120 and 200 (pixel (%d, %d))", x, y);
    free(l.px);
    /* The DEAD banner, large, only once dead. */
    assert_int_equal(count_color(&a, 0, 0, a.w, a.h, PG_COLOR_BANNER_DEAD), 0);
    assert_true(count_color(&d, 0, 0, d.w, d.h, PG_COLOR_BANNER_DEAD) > 500);
    free(a.px);
    free(d.px);
}


/* ---------- readable levels ---------- */

/* Every kind of object in one small level, drawn at 1 pixel per unit with the camera
 * at its centre (world (x, y) is pixel (x, y)). */
/* The objects level with the player at its start (0), in the exit (1) or on the
 * switch (2). */
static const char *objects_level(int where)
{
    static const char *const names[] = {"objects.ntl", "objects-exit.ntl", "objects-switch.ntl"};
    static const char *const places[] = {"48 200", "432 200", "36 132"};
    const char *name = names[where];
    char text[4096];
    snprintf(text, sizeof text,
             "ntile-level 1\nsize 20 10\ncell 24\nmaterial 1 0.05 0.9\ntiles\n"
             "|####################|\n|#..................#|\n|#..................#|\n|#..................#|\n"
             "|#..................#|\n|#..................#|\n|#..................#|\n|#.....#.#..#.......#|\n"
             "|#..................#|\n|####################|\n"
             "materials\n"
             "|....................|\n|....................|\n|....................|\n|....................|\n"
             "|....................|\n|....................|\n|....................|\n|......1.............|\n"
             "|....................|\n|....................|\n"
             "flags\n"
             "|....................|\n|....................|\n|....................|\n|....................|\n"
             "|....................|\n|....................|\n|....................|\n|...........-........|\n"
             "|....................|\n|....................|\n"
             "player %s\n"
             "region door exit 420 168 444 216\n"
             "region bin score 300 150 348 198 value 25\n"
             "region pit kill 24 24 96 72\n"
             "region area zone 120 24 200 80\n"
             "path p pingpong speed 10 points 120 120 200 120\n"
             "body g static circle 8 at 216 60 sensor score 1\n"
             "body m static circle 6 at 264 60 sensor deadly\n"
             "body plat kinematic box 12 4 at 120 120 path p\n"
             "body ball dynamic circle 5 at 360 60 template\n"
             "spawner sp ball every 1000 limit 1\n"
             "region sw switch 24 120 48 144\n",
             places[where]);
    scratch_write_text(name, text);
    return scratch_path(name);
}

static uint32_t mix(uint32_t a, uint32_t b, int alpha) /* render.c's pg_mix */
{
    uint32_t out = 0;
    for (int s = 0; s <= 16; s += 8) {
        int ca = (int)((a >> s) & 0xffu), cb = (int)((b >> s) & 0xffu);
        out |= (uint32_t)(ca + ((cb - ca) * alpha) / 255) << s;
    }
    return out;
}

/* Each object kind in its own colour and shape where the level puts it. */
static void test_object_kinds(void **state)
{
    (void)state;
    const char *out = scratch_path("objects.bmp"), *out2 = scratch_path("objects-exit.bmp");
    const char *view[] = {"--no-hud", "--size", "480x240", "--zoom", "1", "--center", "240", "120", "--frames", "1"};
    play_ok((const char *[]){objects_level(0), view[0], view[1], view[2], view[3], view[4], view[5], view[6], view[7], view[8],
                             view[9], "--screenshot", out, NULL});
    play_ok((const char *[]){objects_level(1), view[0], view[1], view[2], view[3], view[4], view[5], view[6], view[7], view[8],
                             view[9], "--screenshot", out2, NULL});
    const char *out3 = scratch_path("objects-switch.bmp");
    play_ok((const char *[]){objects_level(2), view[0], view[1], view[2], view[3], view[4], view[5], view[6], view[7], view[8],
                             view[9], "--screenshot", out3, NULL});
    image a = load_bmp(out), b = load_bmp(out2), sw = load_bmp(out3);
    /* The switch (24..48, 120..144): a plate with a hollow button, and a label
     * that says "on" once the player has pressed it (the player then hides the
     * button). */
    assert_true(count_color(&a, 24, 120, 49, 121, PG_COLOR_SWITCH) >= 20);
    expect_pixel(&a, 36, 132, PG_COLOR_BG, "the unpressed switch's hollow button");
    int label_off = count_color(&a, 24, 120 - PG_CHAR_H - 1, 90, 120, PG_COLOR_SWITCH);
    int label_on = count_color(&sw, 24, 120 - PG_CHAR_H - 1, 90, 120, PG_COLOR_SWITCH);
    assert_true(label_off > 20);
    assert_true(label_on > label_off + 5); /* "SWITCH on" */
    free(sw.px);
    /* Gold: a gold disc with a darker rim. */
    expect_pixel(&a, 216, 60, PG_COLOR_GOLD, "the gold's centre");
    assert_true(count_color(&a, 205, 49, 228, 72, PG_COLOR_GOLD_RIM) > 20);
    /* The mine: a dark core, a red disc and red spikes beyond its radius (6). */
    expect_pixel(&a, 264, 60, PG_COLOR_MINE_CORE, "the mine's core");
    expect_pixel(&a, 268, 60, PG_COLOR_MINE, "the mine's disc");
    expect_pixel(&a, 264 + 9, 60, PG_COLOR_MINE, "the mine's right spike");
    expect_pixel(&a, 264, 60 - 9, PG_COLOR_MINE, "the mine's top spike");
    expect_pixel(&a, 264 + 7, 60 + 3, PG_COLOR_BG, "between two spikes");
    /* The exit: a closed door, open once the level is complete (the player starts in it). */
    expect_pixel(&a, 422, 180, PG_COLOR_DOOR, "the closed door");
    assert_int_equal(count_color(&a, 420, 168, 444, 216, PG_COLOR_DOOR_OPEN), 0);
    assert_true(count_color(&b, 420, 168, 444, 216, PG_COLOR_DOOR_OPEN) > 200);
    /* One-way cell (11, 7): its top in the one-way colour, an arrow up inside. */
    assert_true(count_color(&a, 264, 168, 288, 170, PG_COLOR_ONEWAY) >= 40);
    assert_true(count_color(&a, 270, 172, 282, 192, PG_COLOR_ONEWAY) >= 10);
    assert_int_equal(count_color(&a, 192, 168, 216, 192, PG_COLOR_ONEWAY), 0); /* (8, 7): an ordinary FULL */
    /* The material of cell (6, 7) tints it; (8, 7) has the plain fill. */
    expect_pixel(&a, 8 * 24 + 12, 7 * 24 + 12, PG_COLOR_TILE, "a tile of material 0");
    uint32_t tints[16] = PG_MATERIAL_TINTS;
    expect_pixel(&a, 6 * 24 + 12, 7 * 24 + 12, mix(PG_COLOR_TILE, tints[1], 110), "a tile of material 1");
    /* The bin: walls in its colour; the kill region hatched; the zone's dashed outline. */
    assert_true(count_color(&a, 300, 150, 302, 198, PG_COLOR_BIN) >= 90);
    assert_true(count_color(&a, 24, 24, 96, 72, PG_COLOR_KILL) > 200);
    assert_true(count_color(&a, 120, 24, 200, 25, PG_COLOR_ZONE) > 30);
    assert_true(count_color(&a, 120, 24, 200, 25, PG_COLOR_ZONE) < 70); /* dashed, not solid */
    /* The platform on its dotted path; the spawner's mark above the template. */
    expect_pixel(&a, 121, 120, PG_COLOR_PLATFORM, "the platform");
    assert_true(count_color(&a, 140, 117, 200, 124, PG_COLOR_PATH) > 10);
    assert_true(count_color(&a, 352, 48, 368, 60, PG_COLOR_SPAWNER) > 10);
    /* No banner while playing; COMPLETE once in the exit. */
    assert_int_equal(count_color(&a, 0, 0, a.w, a.h, PG_COLOR_BANNER_WIN), 0);
    assert_true(count_color(&b, 0, 0, b.w, b.h, PG_COLOR_BANNER_WIN) > 300);
    free(a.px);
    free(b.px);
}



/* ---------- editing ---------- */

/* Five edits of the lab through scripted input: a painted stroke, an erase
 * (Shift+right), a rectangle (Ctrl+right-drag), a one-way flag and a material (the
 * left button's tools, F6). */
#define EDITS_SCRIPT                                                                                                          \
    "1 mouse down right 264 264\n2 mouse move 312 264\n3 mouse move 360 264\n4 mouse up right 360 264\n"                     \
    "5 down LShift\n6 mouse down right 24 264\n7 mouse up right 24 264\n8 up LShift\n"                                      \
    "9 down LCtrl\n10 mouse down right 504 120\n11 mouse move 600 168\n12 mouse up right 600 168\n13 up LCtrl\n"            \
    "14 press F6\n16 press F6\n18 press F6\n20 press F6\n22 press F6\n24 mouse down left 504 120\n24 mouse up left 504 120\n" \
    "26 press F6\n28 mouse down left 552 120\n28 mouse up left 552 120\n"

static char *save_after(const char *name, const char *script)
{
    char sname[64], lname[64];
    snprintf(sname, sizeof sname, "%s.script", name);
    snprintf(lname, sizeof lname, "%s.ntl", name);
    scratch_write_text(sname, script);
    play_ok((const char *[]){"levels/lab.ntl", "--script", scratch_path(sname), "--frames", "60", LAB_VIEW, "--save",
                             scratch_path(lname), NULL});
    return scratch_read(scratch_path(lname), NULL);
}

/* Undo takes every edit back: the level saved after five edits and five Ctrl+Z is
 * byte for byte the one saved without edits; five Ctrl+Y give the edited one again. */
static void test_undo_redo_round_trip(void **state)
{
    (void)state;
    char *orig = save_after("rt0", "55 press F2\n");
    char *edited = save_after("rt1", EDITS_SCRIPT "55 press F2\n");
    char *undone = save_after("rt2", EDITS_SCRIPT "30 down LCtrl\n31 press Z\n33 press Z\n35 press Z\n37 press Z\n39 press Z\n"
                                                  "41 up LCtrl\n55 press F2\n");
    char *redone = save_after("rt3", EDITS_SCRIPT "30 down LCtrl\n31 press Z\n33 press Z\n35 press Z\n37 press Z\n39 press Z\n"
                                                  "41 press Y\n43 press Y\n45 press Y\n47 press Y\n49 press Y\n51 up LCtrl\n"
                                                  "55 press F2\n");
    if (strcmp(orig, edited) == 0) fail_msg("the edits changed nothing:\n%s", edited);
    /* Each edit is in the saved text: the paint, the erased wall, the rectangle, the flag, the material. */
    nt_level *lv = load_level(scratch_path("rt1.ntl"));
    assert_int_equal(lv->tiles[5 * lv->width + 6], NT_TILE_FULL);
    assert_int_equal(lv->tiles[5 * lv->width + 0], NT_TILE_EMPTY);
    assert_int_equal(lv->tiles[3 * lv->width + 12], NT_TILE_FULL);
    assert_int_equal(lv->cell_flags[2 * lv->width + 10], NT_CELL_ONE_WAY);
    assert_int_equal(lv->cell_materials[2 * lv->width + 11], 1);
    nt_level_destroy(lv);
    if (strcmp(orig, undone) != 0) fail_msg("after undoing every edit the level differs:\n%s\nexpected:\n%s", undone, orig);
    if (strcmp(edited, redone) != 0) fail_msg("after redoing every edit the level differs:\n%s\nexpected:\n%s", redone, edited);
    free(orig);
    free(edited);
    free(undone);
    free(redone);
}

/* A level switch or Esc with unsaved edits asks first (the question drawn over the
 * view); N keeps the edits, Y goes on; without edits nothing is asked. */
static void test_confirm_before_discard(void **state)
{
    (void)state;
    const char *shot = scratch_path("confirm.bmp");
    scratch_write_text("ask.script", "1 mouse down right 264 264\n1 mouse up right 264 264\n3 press 2\n");
    scratch_write_text("no.script", "1 mouse down right 264 264\n1 mouse up right 264 264\n3 press 2\n6 press N\n");
    scratch_write_text("yes.script", "1 mouse down right 264 264\n1 mouse up right 264 264\n3 press 2\n6 press Y\n");
    scratch_write_text("esc.script", "1 mouse down right 264 264\n1 mouse up right 264 264\n3 press Escape\n");
    scratch_write_text("esc-clean.script", "3 press Escape\n");
    run_result r;
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("ask.script"), "--frames", "8", LAB_VIEW,
                                  "--screenshot", shot, NULL});
    expect_status(&r, 0);
    expect_in(r.out, "level levels/lab.ntl (edited)  asking: discard the edits and switch level?");
    run_free(&r);
    image im = load_bmp(shot);
    assert_true(count_color(&im, 0, 0, im.w, im.h, PG_COLOR_CONFIRM) > 500);
    free(im.px);
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("no.script"), "--frames", "8", LAB_VIEW, NULL});
    expect_status(&r, 0);
    expect_in(r.out, "level levels/lab.ntl (edited)");
    if (strstr(r.out, "asking")) fail_msg("N should have closed the question:\n%s", r.out);
    run_free(&r);
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("yes.script"), "--frames", "8", LAB_VIEW, NULL});
    expect_status(&r, 0);
    expect_in(r.out, "level levels/ninja.ntl  ");
    run_free(&r);
    /* Esc: asked (the run goes on to frame 10), or quits at once without edits. */
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("esc.script"), "--frames", "10", LAB_VIEW, NULL});
    expect_status(&r, 0);
    expect_in(r.out, "tick 10 ");
    expect_in(r.out, "asking: discard the edits and quit?");
    run_free(&r);
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("esc-clean.script"), "--frames", "10", LAB_VIEW, NULL});
    expect_status(&r, 0);
    if (strstr(r.out, "tick 10 ") || strstr(r.out, "asking")) fail_msg("Esc without edits should quit at once:\n%s", r.out);
    run_free(&r);
}

/* No tile over the player's spawn (a message says why); other cells paint; the
 * eyedropper (Alt+right-click) picks a cell's tile for the next paint. */
static void test_spawn_free_and_eyedropper(void **state)
{
    (void)state;
    scratch_write_text("spawn.script", "1 mouse down right 132 204\n1 mouse up right 132 204\n"
                                       "3 mouse down right 60 204\n3 mouse up right 60 204\n5 press F2\n");
    const char *saved = scratch_path("spawn-saved.ntl");
    run_result r;
    run_play(&r, (const char *[]){objects_level(0), "--no-hud", "--size", "480x240", "--zoom", "1", "--center", "240", "120",
                                  "--script", scratch_path("spawn.script"), "--frames", "8", "--save", saved, NULL});
    expect_status(&r, 0);
    run_free(&r);
    scratch_write_text("spawn2.script", "1 mouse down right 60 204\n1 mouse up right 60 204\n");
    run_play(&r, (const char *[]){objects_level(0), "--no-hud", "--size", "480x240", "--zoom", "1", "--center", "240", "120",
                                  "--script", scratch_path("spawn2.script"), "--frames", "4", NULL});
    expect_status(&r, 0);
    expect_in(r.out, "the player's spawn stays free: no tile over cell (2, 8)");
    expect_in(r.out, "level"); /* not edited: nothing changed */
    if (strstr(r.out, "(edited)")) fail_msg("a refused paint left the level edited:\n%s", r.out);
    run_free(&r);
    nt_level *lv = load_level(saved);
    assert_int_equal(lv->tiles[8 * lv->width + 5], NT_TILE_FULL);  /* painted */
    assert_int_equal(lv->tiles[8 * lv->width + 2], NT_TILE_EMPTY); /* the spawn's cell: refused */
    nt_level_destroy(lv);
    /* Tab selects the tile after FULL; Alt+right-click on a wall picks FULL again. */
    scratch_write_text("pick.script", "1 press Tab\n3 down LAlt\n4 mouse down right 24 24\n4 mouse up right 24 24\n5 up LAlt\n"
                                      "6 mouse down right 264 264\n6 mouse up right 264 264\n8 press F2\n"
                                      "10 press Tab\n12 mouse down right 312 264\n12 mouse up right 312 264\n14 press F2\n");
    saved = scratch_path("pick-saved.ntl");
    play_ok((const char *[]){"levels/lab.ntl", "--script", scratch_path("pick.script"), "--frames", "16", LAB_VIEW, "--save", saved, NULL});
    lv = load_level(saved);
    assert_int_equal(lv->tiles[5 * lv->width + 5], NT_TILE_FULL);     /* after the pick */
    assert_int_equal(lv->tiles[5 * lv->width + 6], NT_TILE_FULL + 1); /* Tab without a pick: the next tile */
    nt_level_destroy(lv);
}

/* The wheel zooms at the cursor (the wall corner under it stays put); a middle drag
 * pans by the drag. The lab fits a 960 x 576 view at 2 pixels per unit. */
static void test_zoom_at_cursor_and_pan(void **state)
{
    (void)state;
    scratch_write_text("zoom.script", "1 mouse move 48 48\n2 wheel 1\n");
    scratch_write_text("pan.script", "1 mouse move 48 48\n2 wheel 1\n4 mouse down middle 300 300\n5 mouse move 280 300\n"
                                     "6 mouse up middle 280 300\n");
    const char *a = scratch_path("zoom.bmp"), *b = scratch_path("pan.bmp");
    play_ok((const char *[]){"levels/lab.ntl", "--no-hud", "--size", "960x576", "--zoom", "2", "--script", scratch_path("zoom.script"),
                             "--frames", "8", "--screenshot", a, NULL});
    play_ok((const char *[]){"levels/lab.ntl", "--no-hud", "--size", "960x576", "--zoom", "2", "--script", scratch_path("pan.script"),
                             "--frames", "8", "--screenshot", b, NULL});
    image ia = load_bmp(a), ib = load_bmp(b);
    /* x2.5 about (48, 48), where the wall's inner corner (24, 24) is. */
    expect_pixel(&ia, 46, 46, PG_COLOR_TILE, "the wall just above-left of the cursor");
    expect_pixel(&ia, 50, 50, PG_COLOR_BG, "the room just below-right of the cursor");
    expect_pixel(&ia, 100, 46, PG_COLOR_TILE, "the top wall, 52 pixels right of the cursor");
    /* Dragged 20 pixels left: the corner at (28, 48). */
    expect_pixel(&ib, 26, 46, PG_COLOR_TILE, "the wall, panned");
    expect_pixel(&ib, 30, 50, PG_COLOR_BG, "the room, panned");
    expect_pixel(&ib, 46, 50, PG_COLOR_BG, "where the corner was");
    free(ia.px);
    free(ib.px);
}

/* The gold tool (F6) places gold where clicked (the level restarts with it, F2 saves
 * it); dragging it moves it; Ctrl+Z takes the placement back. */
static void test_place_and_move_objects(void **state)
{
    (void)state;
    scratch_write_text("place.script", "1 press F6\n3 mouse down left 264 168\n3 mouse up left 264 168\n5 press F2\n");
    scratch_write_text("move.script", "1 press F6\n3 mouse down left 264 168\n3 mouse up left 264 168\n"
                                      "5 mouse down left 264 168\n6 mouse move 360 168\n7 mouse up left 360 168\n");
    scratch_write_text("unplace.script", "1 press F6\n3 mouse down left 264 168\n3 mouse up left 264 168\n"
                                         "5 down LCtrl\n6 press Z\n8 up LCtrl\n");
    const char *a = scratch_path("place.bmp"), *b = scratch_path("move.bmp"), *c = scratch_path("unplace.bmp");
    const char *saved = scratch_path("placed.ntl");
    play_ok((const char *[]){"levels/lab.ntl", "--script", scratch_path("place.script"), "--frames", "10", LAB_VIEW, "--save", saved,
                             "--screenshot", a, NULL});
    play_ok((const char *[]){"levels/lab.ntl", "--script", scratch_path("move.script"), "--frames", "10", LAB_VIEW, "--screenshot", b, NULL});
    play_ok((const char *[]){"levels/lab.ntl", "--script", scratch_path("unplace.script"), "--frames", "10", LAB_VIEW, "--screenshot", c, NULL});
    image ia = load_bmp(a), ib = load_bmp(b), ic = load_bmp(c);
    /* Cell (5, 3): centre (132, 84) units, (264, 168) pixels. */
    expect_pixel(&ia, 264, 168, PG_COLOR_GOLD, "the gold placed");
    expect_pixel(&ib, 360, 168, PG_COLOR_GOLD, "the gold moved 48 units right");
    expect_pixel(&ib, 264, 168, PG_COLOR_BG, "where the gold was");
    expect_pixel(&ic, 264, 168, PG_COLOR_BG, "the placement undone");
    free(ia.px);
    free(ib.px);
    free(ic.px);
    nt_level *lv = load_level(saved);
    int g = nt_level_find_body(lv, "gold1");
    assert_true(g >= 0);
    assert_int_equal(lv->bodies[g].score, 1);
    assert_true(lv->bodies[g].position.x == 132 && lv->bodies[g].position.y == 84);
    nt_level_destroy(lv);
}


/* ---------- the inspector ---------- */

/* Scripted mouse: a left press on puck_a selects it (the inspector says what it is)
 * and drags it on a spring toward the mouse, 56 units below (the lab has no gravity:
 * alone it would stay at y = 144); a press inside the wall throws nothing. */
static void test_select_and_drag_body(void **state)
{
    (void)state;
    /* puck_a starts at (120, 144) at 120 units/s: (123, 144) after the first tick. */
    scratch_write_text("joint.script", "1 mouse move 246 288\n2 mouse down left 246 288\n3 mouse move 246 400\n"
                                       "14 mouse up left 246 400\n");
    scratch_write_text("select.script", "1 mouse move 246 288\n2 mouse down left 246 288\n2 mouse up left 246 288\n"
                                        "4 mouse down left 20 200\n4 mouse up left 20 200\n");
    const char *shot = scratch_path("joint.bmp");
    run_result r;
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("joint.script"), "--frames", "16", LAB_VIEW,
                                  "--screenshot", shot, NULL});
    expect_status(&r, 0);
    expect_in(r.out, "selected body 1.1 dynamic circle r 10 at (123.00, ");
    const char *at = strstr(r.out, "selected body 1.1 dynamic circle r 10 at (123.00, ");
    double y = atof(at + strlen("selected body 1.1 dynamic circle r 10 at (123.00, "));
    if (!(y > 185 && y < 215)) fail_msg("the dragged puck is at y = %g, expected near the mouse (200):\n%s", y, r.out);
    run_free(&r);
    /* The selection ring around the puck. */
    image im = load_bmp(shot);
    assert_true(count_color(&im, LAB_PX(123) - 30, LAB_PX(y) - 30, LAB_PX(123) + 30, LAB_PX(y) + 30, PG_COLOR_SELECT) > 60);
    free(im.px);
    /* A click selects without dragging: puck_a goes on at 120 units/s; the wall throws nothing. */
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("select.script"), "--frames", "10", LAB_VIEW, NULL});
    expect_status(&r, 0);
    expect_in(r.out, "bodies 2 ");
    expect_in(r.out, "selected body 1.1 dynamic circle r 10 at (150.00, 144.00) vel (120.00, 0.00) contacts 0 bodies, 0 tiles awake");
    expect_in(r.out, "cannot throw from inside a solid tile");
    run_free(&r);
}


/* ---------- replays in the window ---------- */

/* Stepping back (the comma key, paused) plays the replay again from the start: five
 * steps back from tick 29 give exactly the frame of a fresh run to tick 24. A click on
 * the timeline goes to the tick under it. */
static void test_replay_step_back(void **state)
{
    (void)state;
    scratch_write_text("back.script", "30 press P\n32 press ,\n34 press ,\n36 press ,\n38 press ,\n40 press ,\n");
    const char *a = scratch_path("back.bmp"), *b = scratch_path("fresh24.bmp");
    run_result r;
    run_play(&r, (const char *[]){"--replay", "tests/replays/ninja.ntr", "--no-hud", "--script", scratch_path("back.script"),
                                  "--frames", "45", "--screenshot", a, NULL});
    expect_status(&r, 0);
    expect_in(r.out, "tick 24 ");
    run_free(&r);
    play_ok((const char *[]){"--replay", "tests/replays/ninja.ntr", "--no-hud", "--frames", "24", "--screenshot", b, NULL});
    image ia = load_bmp(a), ib = load_bmp(b);
    for (int y = 0; y < ia.h; y++)
        for (int x = 0; x < ia.w; x++)
            if (pixel(&ia, x, y) != pixel(&ib, x, y)) fail_msg("stepped back to tick 24 and a fresh run differ at (%d, %d)", x, y);
    free(ia.px);
    free(ib.px);
    /* The timeline (1024 x 640 window): from x = 240 to 948 at the bottom; its middle is tick 310 of 620. */
    scratch_write_text("scrub.script", "30 press P\n32 mouse down left 594 627\n32 mouse up left 594 627\n");
    run_play(&r, (const char *[]){"tests/replays/ninja.ntr", "--script", scratch_path("scrub.script"), "--frames", "34", NULL});
    expect_status(&r, 0);
    expect_in(r.out, "tick 310 ");
    expect_in(r.out, "replay tests/replays/ninja.ntr tick 310 of 620");
    run_free(&r);
}

/* After the replay's last tick the keyboard has the game, and the playground says so;
 * a replay dropped on the window plays on its level; F7 goes to the first tick whose
 * state differs from a replay's recorded hashes (here: one input changed). */
static void test_replay_over_drop_and_divergence(void **state)
{
    (void)state;
    run_result r;
    run_play(&r, (const char *[]){"tests/replays/ninja-mine.ntr", "--frames", "205", NULL});
    expect_status(&r, 0);
    expect_in(r.out, "replay tests/replays/ninja-mine.ntr over (200 ticks): you have control");
    run_free(&r);
    scratch_write_text("drop.script", "2 drop tests/replays/ninja-mine.ntr\n");
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("drop.script"), "--frames", "10", NULL});
    expect_status(&r, 0);
    expect_in(r.out, "level levels/ninja.ntl");
    expect_in(r.out, "replay tests/replays/ninja-mine.ntr tick ");
    run_free(&r);
    /* ninja.ntr with the first run shortened by one tick (300R -> 299R 1.). */
    char *text = scratch_read("tests/replays/ninja.ntr", NULL);
    char *at = strstr(text, "input 300R ");
    assert_non_null(at);
    char *changed = malloc(strlen(text) + 16);
    assert_non_null(changed);
    size_t head = (size_t)(at - text);
    memcpy(changed, text, head);
    strcpy(changed + head, "input 299R 1. ");
    strcat(changed, at + strlen("input 300R "));
    char cwd[4096];
    assert_non_null(getcwd(cwd, sizeof cwd));
    char *lv = strstr(changed, "level ../../levels/ninja.ntl");
    assert_non_null(lv);
    char *fixed = malloc(strlen(changed) + strlen(cwd) + 64);
    assert_non_null(fixed);
    memcpy(fixed, changed, (size_t)(lv - changed));
    sprintf(fixed + (lv - changed), "level \"%s/levels/ninja.ntl\"%s", cwd, lv + strlen("level ../../levels/ninja.ntl"));
    scratch_write_text("diverge.ntr", fixed);
    /* Where nt_run_replay says it diverges. */
    nt_replay *rp;
    nt_text_error e;
    if (nt_replay_parse("diverge.ntr", fixed, strlen(fixed), &rp, &e) != NT_OK) fail_msg("%s", e.message);
    nt_level *level = load_level("levels/ninja.ntl");
    nt_run_report rep;
    assert_int_equal(nt_run_replay(rp, level, &rep), NT_OK);
    int want = rep.first_divergence;
    nt_run_report_free(&rep);
    nt_replay_destroy(rp);
    nt_level_destroy(level);
    assert_true(want > 0);
    scratch_write_text("f7.script", "2 press F7\n");
    run_play(&r, (const char *[]){scratch_path("diverge.ntr"), "--script", scratch_path("f7.script"), "--frames", "4", NULL});
    expect_status(&r, 0);
    char expect[64];
    snprintf(expect, sizeof expect, "tick %d ", want);
    expect_in(r.out, expect);
    run_free(&r);
    free(text);
    free(changed);
    free(fixed);
}


/* ---------- text ---------- */

/* The font has descenders, at 1x and at 2x (windows 1600 pixels wide and more): the
 * panel's first line is the level's title, "Ninja", at (4, 4), in the selection
 * colour; the j's hook goes two font rows below the baseline (rows 7 and 8, under
 * row 6), the N's does not. */
static void test_font_descenders(void **state)
{
    (void)state;
    const char *a = scratch_path("font1.bmp"), *b = scratch_path("font2.bmp");
    play_ok((const char *[]){"levels/ninja.ntl", "--frames", "1", "--screenshot", a, NULL});
    play_ok((const char *[]){"levels/ninja.ntl", "--size", "1700x1000", "--frames", "1", "--screenshot", b, NULL});
    image i1 = load_bmp(a), i2 = load_bmp(b);
    for (int s = 1; s <= 2; s++) {
        const image *im = s == 1 ? &i1 : &i2;
        int jx = 4 + 3 * PG_CHAR_W * s, base = 4 + 7 * s; /* j: the fourth letter; the first row under the baseline */
        /* Row 7 of 'j': columns 0 and 3; row 8: columns 1 and 2. */
        expect_pixel(im, jx, base, PG_COLOR_SELECT, "the j's hook, one row under the baseline");
        expect_pixel(im, jx + 3 * s, base, PG_COLOR_SELECT, "the j's stem, one row under the baseline");
        expect_pixel(im, jx + s, base + s, PG_COLOR_SELECT, "the j's hook, two rows under the baseline");
        assert_int_equal(count_color(im, jx, base + 2 * s, jx + 5 * s, base + 4 * s, PG_COLOR_SELECT), 0); /* nine rows, no more */
        assert_int_equal(count_color(im, 4, base, 4 + 5 * s, base + 2 * s, PG_COLOR_SELECT), 0);        /* N: none */
        assert_true(count_color(im, 4, 4, 4 + 5 * s, base, PG_COLOR_SELECT) >= 13 * s * s);             /* N above it */
    }
    free(i1.px);
    free(i2.px);
}


/* Circles: the outline (the bodies gizmo) is the edge of the filled disc, so no fill
 * pixel touches the background around a puck, and the ring is closed and smooth. */
static void test_circle_outline(void **state)
{
    (void)state;
    const char *out = scratch_path("circle.bmp");
    play_ok((const char *[]){"--replay", "tests/replays/lab.ntr", "--frames", "40", LAB_VIEW, "--gizmos", "bodies", "--screenshot", out, NULL});
    image im = load_bmp(out);
    nt_vec2 pa = body_after("levels/lab.ntl", "puck_a", 40);
    int cx = LAB_PX(pa.x), cy = LAB_PX(pa.y), fill = 0, poke = 0;
    uint32_t f = PG_BODY_FILL(PG_ENGINE_AWAKE);
    for (int y = cy - 26; y <= cy + 26; y++)
        for (int x = cx - 26; x <= cx + 26; x++) {
            if (pixel(&im, x, y) != f) continue;
            fill++;
            if (pixel(&im, x + 1, y) == PG_COLOR_BG || pixel(&im, x - 1, y) == PG_COLOR_BG || pixel(&im, x, y + 1) == PG_COLOR_BG ||
                pixel(&im, x, y - 1) == PG_COLOR_BG)
                poke++;
        }
    assert_true(fill > 900); /* radius 20 pixels: about 1250 inside the ring */
    if (poke) fail_msg("%d fill pixels of the puck touch the background outside its outline", poke);
    /* The ring: one pixel wide, about 2 pi r of them. */
    int ring = count_color(&im, cx - 22, cy - 22, cx + 23, cy + 23, PG_ENGINE_AWAKE);
    assert_true(ring > 100 && ring < 200);
    free(im.px);
}


/* The panel's gizmo checkboxes are clickable: a click on "V velocities" (the fifth box
 * under the fourth heading, "Gizmos") turns the velocity arrows on. */
static void test_panel_checkbox_click(void **state)
{
    (void)state;
    const char *before = scratch_path("panel0.bmp"), *after = scratch_path("panel1.bmp");
    play_ok((const char *[]){"--replay", "tests/replays/lab.ntr", "--frames", "20", "--screenshot", before, NULL});
    image a = load_bmp(before);
    /* The headings' bands down the panel's left edge. */
    int y = 0, found = 0, top = -1, bottom = -1;
    while (y < a.h && found < 4) {
        if (pixel(&a, 1, y) == PG_COLOR_HEADING) {
            top = y;
            while (y < a.h && pixel(&a, 1, y) == PG_COLOR_HEADING) y++;
            bottom = y;
            found++;
        } else {
            y++;
        }
    }
    if (found < 4) fail_msg("found %d headings in the panel, expected at least 4", found);
    assert_int_equal(bottom - top, PG_CHAR_H);
    assert_int_equal(count_color(&a, 0, 0, a.w, a.h, PG_ENGINE_VELOCITY), 0);
    /* Checkbox rows follow the heading 2 pixels down, one text line each. */
    int cy = bottom + 2 + 4 * PG_CHAR_H + 3;
    char script[128];
    snprintf(script, sizeof script, "2 mouse down left 10 %d\n2 mouse up left 10 %d\n", cy, cy);
    scratch_write_text("panel.script", script);
    play_ok((const char *[]){"--replay", "tests/replays/lab.ntr", "--frames", "20", "--script", scratch_path("panel.script"),
                             "--screenshot", after, NULL});
    image b = load_bmp(after);
    assert_true(count_color(&b, PG_PANEL_W, 0, b.w, b.h, PG_ENGINE_VELOCITY) > 20); /* arrows on the pucks */
    assert_true(count_color(&b, 4, cy - 4, 4 + 7, cy + 4, PG_COLOR_SELECT) > 4);    /* the box ticked */
    assert_int_equal(count_color(&a, 4, cy - 4, 4 + 7, cy + 4, PG_COLOR_SELECT), 0);
    free(a.px);
    free(b.px);
}


/* The panel's iteration steppers set the world's solver iterations live: a scripted
 * click on the velocity iterations' "+" doubles them (8 -> 16), as the world reports. */
static void test_panel_iterations(void **state)
{
    (void)state;
    const char *before = scratch_path("iters.bmp");
    play_ok((const char *[]){"levels/lab.ntl", "--frames", "2", "--screenshot", before, NULL});
    image a = load_bmp(before);
    /* The first heading (World), then its steppers: a "+" box whose right edge stands
     * 3 pixels in from the widgets' last column (a button's edge is that column). */
    int y = 0;
    while (y < a.h && pixel(&a, 1, y) != PG_COLOR_HEADING) y++;
    while (y < a.h && pixel(&a, 1, y) == PG_COLOR_HEADING) y++;
    int x1 = PG_PANEL_W - 4, found = 0, plus_y = -1;
    for (; y + 4 < a.h && found < 2; y++) {
        if (pixel(&a, x1 - 8, y) == 0x8090a0u && pixel(&a, x1 - 4, y + 3) == 0x8090a0u && pixel(&a, x1 - 1, y + 3) != 0x8090a0u) {
            found++; /* gravity's, then the velocity iterations' */
            plus_y = y + 4;
            y += 6;
        }
    }
    if (found < 2) fail_msg("found %d steppers under the World heading, expected at least 2", found);
    char script[128];
    snprintf(script, sizeof script, "2 mouse down left %d %d\n2 mouse up left %d %d\n", x1 - 8, plus_y, x1 - 8, plus_y);
    scratch_write_text("iters.script", script);
    run_result r;
    run_play(&r, (const char *[]){"levels/lab.ntl", "--frames", "6", "--script", scratch_path("iters.script"), NULL});
    expect_status(&r, 0);
    if (!strstr(r.out, "iterations 16 4")) fail_msg("expected iterations 16 4 after the click, got: %s", r.out);
    run_free(&r);
    run_play(&r, (const char *[]){"levels/lab.ntl", "--frames", "6", NULL});
    expect_status(&r, 0);
    if (!strstr(r.out, "iterations 8 4")) fail_msg("expected the default iterations 8 4, got: %s", r.out);
    run_free(&r);
    free(a.px);
}

/* F3 moves the panel to the right of the view, then hides it (the view grows), then
 * brings it back on the left. */
static void test_panel_moves_and_hides(void **state)
{
    (void)state;
    const char *shots[3] = {scratch_path("f3-1.bmp"), scratch_path("f3-2.bmp"), scratch_path("f3-3.bmp")};
    const char *scripts[3] = {"1 press F3\n", "1 press F3\n3 press F3\n", "1 press F3\n3 press F3\n5 press F3\n"};
    int g = 4, c = (640 - 24 - g * 18) / 17;
    if (c > 28) c = 28;
    int x0 = 1024 - (2 * c + 3 * g); /* the strip's left edge */
    for (int i = 0; i < 3; i++) {
        char name[32];
        snprintf(name, sizeof name, "f3-%d.script", i + 1);
        scratch_write_text(name, scripts[i]);
        play_ok((const char *[]){"levels/ninja.ntl", "--script", scratch_path(name), "--frames", "8", "--screenshot", shots[i], NULL});
    }
    image r = load_bmp(shots[0]), h = load_bmp(shots[1]), l = load_bmp(shots[2]);
    expect_pixel(&r, x0 - PG_PANEL_W + 2, 630, PG_COLOR_PANEL_BG, "the panel on the right");
    assert_int_equal(count_color(&r, 0, 0, x0 - PG_PANEL_W, 640, PG_COLOR_PANEL_BG), 0);
    assert_int_equal(count_color(&h, 0, 0, h.w, h.h, PG_COLOR_PANEL_BG), 0); /* hidden */
    assert_true(count_color(&h, 0, 0, x0, 640, PG_COLOR_TILE) > count_color(&r, 0, 0, x0, 640, PG_COLOR_TILE)); /* a larger level */
    expect_pixel(&l, 2, 630, PG_COLOR_PANEL_BG, "the panel back on the left");
    free(r.px);
    free(h.px);
    free(l.px);
}

/* ---------- CPU use when paused, in a real window under Xvfb ---------- */

/* utime + stime (clock ticks) of the first process called `comm` below `root`, or -1. */
static void sleep_ms(long ms)
{
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {
    }
}

static long cpu_ticks_below(pid_t root, const char *comm, pid_t *found)
{
    DIR *d = opendir("/proc");
    if (!d) return -1;
    struct dirent *e;
    long ticks = -1;
    while (ticks < 0 && (e = readdir(d))) {
        char path[300], buf[1024];
        if (e->d_name[0] < '0' || e->d_name[0] > '9') continue;
        snprintf(path, sizeof path, "/proc/%s/stat", e->d_name);
        FILE *f = fopen(path, "r");
        if (!f) continue;
        size_t n = fread(buf, 1, sizeof buf - 1, f);
        fclose(f);
        buf[n] = '\0';
        char *open = strchr(buf, '('), *close = strrchr(buf, ')');
        if (!open || !close || (size_t)(close - open - 1) != strlen(comm) || strncmp(open + 1, comm, strlen(comm)) != 0) continue;
        /* Fields after the name: state ppid ... utime (14th field) stime (15th). */
        long pid = atol(buf);
        char state;
        long ppid;
        unsigned long ut, st;
        if (sscanf(close + 2, "%c %ld %*d %*d %*d %*d %*u %*u %*u %*u %*u %lu %lu", &state, &ppid, &ut, &st) != 4) continue;
        /* A descendant of root? */
        long up = ppid;
        for (int hops = 0; hops < 8 && up > 1 && up != (long)root; hops++) {
            char pp[64], b2[1024];
            snprintf(pp, sizeof pp, "/proc/%ld/stat", up);
            FILE *g = fopen(pp, "r");
            if (!g) break;
            size_t m = fread(b2, 1, sizeof b2 - 1, g);
            fclose(g);
            b2[m] = '\0';
            char *c2 = strrchr(b2, ')');
            long next;
            if (!c2 || sscanf(c2 + 2, "%*c %ld", &next) != 1) break;
            up = next;
        }
        if (up != (long)root) continue;
        ticks = (long)(ut + st);
        *found = (pid_t)pid;
    }
    closedir(d);
    return ticks;
}

/* CPU seconds the playground uses from 1.5 s to 6.5 s after its start, in an X11
 * window under xvfb-run (with `script`, or none). */
static double cpu_share_under_xvfb(const char *script)
{
    const char *exe = play_exe();
    pid_t child = fork();
    assert_true(child >= 0);
    if (child == 0) {
        int nul = open("/dev/null", O_RDWR);
        if (nul >= 0) dup2(nul, 1), dup2(nul, 2);
        unsetenv("SDL_VIDEODRIVER");
        /* In a sanitizer build: memory errors still fail (exit code 99), but leaks are
         * not checked in this run: the system libraries SDL's X11 driver loads (D-Bus
         * among them) keep allocations at exit. The dummy-driver runs of the other
         * tests keep the leak check. */
        setenv("ASAN_OPTIONS", "detect_leaks=0:exitcode=99", 1);
        setenv("UBSAN_OPTIONS", "exitcode=99:print_stacktrace=1", 0);
        if (script)
            execlp("xvfb-run", "xvfb-run", "-a", "-s", "-screen 0 1280x800x24", exe, "levels/ninja.ntl", "--seconds", "8",
                   "--script", script, (char *)NULL);
        else
            execlp("xvfb-run", "xvfb-run", "-a", "-s", "-screen 0 1280x800x24", exe, "levels/ninja.ntl", "--seconds", "8",
                   (char *)NULL);
        _exit(127);
    }
    pid_t play = 0;
    long t0 = -1;
    for (int i = 0; i < 150 && t0 < 0; i++) { /* wait for the playground to start (up to 3 s) */
        sleep_ms(20);
        t0 = cpu_ticks_below(child, "ntile-play", &play);
    }
    if (t0 < 0) fail_msg("ntile-play did not start under xvfb-run");
    sleep_ms(1500);
    t0 = cpu_ticks_below(child, "ntile-play", &play);
    sleep_ms(5000);
    long t1 = cpu_ticks_below(child, "ntile-play", &play);
    int status;
    waitpid(child, &status, 0);
    if (t0 < 0 || t1 < 0) fail_msg("ntile-play ended before the measurement did");
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) fail_msg("xvfb-run ntile-play: status %d", status);
    return (double)(t1 - t0) / (double)sysconf(_SC_CLK_TCK) / 5.0;
}

/* Paused, the playground sleeps until an event: below 2 % of a core over 5 s; playing,
 * it draws about 60 frames a second (well above that: the measurement can tell). */
static void test_paused_cpu(void **state)
{
    (void)state;
    play_exe();
    if (system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        print_message("skipped: xvfb-run is not installed (Debian's xvfb)\n");
        skip();
    }
    const char *pre = getenv("LD_PRELOAD");
    if (pre && strstr(pre, "vgpreload")) {
        print_message("skipped: CPU use is not measured under valgrind\n");
        skip();
    }
    scratch_write_text("pause.script", "1 press P\n");
    double paused = cpu_share_under_xvfb(scratch_path("pause.script"));
    double playing = cpu_share_under_xvfb(NULL);
    print_message("CPU use under Xvfb: paused %.2f %% of a core, playing %.1f %%\n", 100 * paused, 100 * playing);
    if (paused >= 0.02) fail_msg("paused, the playground used %.2f %% of a core (expected below 2 %%)", 100 * paused);
    if (playing < 0.03) fail_msg("playing, the playground used only %.2f %% of a core: is it drawing?", 100 * playing);
}

/* Bad input: clear messages, non-zero exit, no crash. */
static void test_errors(void **state)
{
    (void)state;
    static const struct {
        const char *args[8];
        int status;
        const char *msg;
    } cases[] = {
        {{"--frobnicate"}, 2, "unknown option '--frobnicate'"},
        {{"--gizmos", "velocities,bogus"}, 2, "unknown gizmo 'bogus'"},
        {{"--frames", "0"}, 2, "--frames '0'"},
        {{"--frames"}, 2, "--frames needs 1 argument"},
        {{"--size", "12x9000"}, 2, "--size '12x9000'"},
        {{"--zoom", "nan"}, 2, "--zoom 'nan'"},
        {{"--alpha", "2"}, 2, "--alpha '2'"},
        {{"a.ntl", "b.ntl"}, 2, "more than one level"},
        {{"levels/ninja.ntl", "--replay", "tests/replays/lab.ntr"}, 2, "not both"},
        {{"no/such/level.ntl", "--frames", "1"}, 1, "cannot open 'no/such/level.ntl'"},
        {{"--replay", "no/such.ntr", "--frames", "1"}, 1, "cannot open 'no/such.ntr'"},
        {{"--save-dir", "no/such/dir", "--frames", "1"}, 1, "not a directory"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        run_result r;
        run_play(&r, cases[i].args);
        expect_status(&r, cases[i].status);
        expect_in(r.err, cases[i].msg);
        run_free(&r);
    }
    /* No display and no driver asked for: an error, not a window nobody sees. */
    {
        run_result r;
        g_child_driver = "";
        run_play(&r, (const char *[]){"levels/ninja.ntl", NULL});
        expect_status(&r, 1);
        if (!strstr(r.err, "no display found") && !strstr(r.err, "cannot start SDL video"))
            fail_msg("expected a message about the missing display, got:\n%s", r.err);
        run_free(&r);
    }
    /* A malformed level: the parser's FILE:LINE:COL message. */
    scratch_write_text("bad.ntl", "ntile-level 1\nsize 4 2\ntiles\n|####|\n|#z.#|\n");
    run_result r;
    run_play(&r, (const char *[]){scratch_path("bad.ntl"), "--frames", "1", NULL});
    expect_status(&r, 1);
    expect_in(r.err, "bad.ntl:5:3: unknown tile code 'z'");
    run_free(&r);
    /* A malformed script: its line. */
    scratch_write_text("bad.script", "1 press Right\n2 press NoSuchKey\n");
    run_play(&r, (const char *[]){"levels/lab.ntl", "--script", scratch_path("bad.script"), "--frames", "1", NULL});
    expect_status(&r, 2);
    expect_in(r.err, "bad.script:2: unknown key name");
    run_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tiles_and_bodies),   cmocka_unit_test(test_lab_collision_figures),
        cmocka_unit_test(test_interpolation),
        cmocka_unit_test(test_resize),             cmocka_unit_test(test_gizmo_on_off),
        cmocka_unit_test(test_hud_and_palette),    cmocka_unit_test(test_record_replay),
        cmocka_unit_test(test_record_edited_level), cmocka_unit_test(test_paint_and_save),     cmocka_unit_test(test_throw_and_delete),
        cmocka_unit_test(test_throw_size_key),     cmocka_unit_test(test_large_throw_and_paint),
        cmocka_unit_test(test_friction_model_switch), cmocka_unit_test(test_png_and_determinism),
        cmocka_unit_test(test_offscreen_driver),   cmocka_unit_test(test_image_stats),
        cmocka_unit_test(test_dead_player_drawn),  cmocka_unit_test(test_object_kinds),
        cmocka_unit_test(test_paused_cpu),         cmocka_unit_test(test_undo_redo_round_trip),
        cmocka_unit_test(test_confirm_before_discard), cmocka_unit_test(test_spawn_free_and_eyedropper),
        cmocka_unit_test(test_zoom_at_cursor_and_pan), cmocka_unit_test(test_place_and_move_objects),
        cmocka_unit_test(test_select_and_drag_body), cmocka_unit_test(test_replay_step_back),
        cmocka_unit_test(test_replay_over_drop_and_divergence), cmocka_unit_test(test_font_descenders),
        cmocka_unit_test(test_circle_outline),      cmocka_unit_test(test_panel_checkbox_click),
        cmocka_unit_test(test_panel_moves_and_hides), cmocka_unit_test(test_panel_iterations),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
