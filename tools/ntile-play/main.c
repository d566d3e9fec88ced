/* ntile-play — the SDL2 playground: play any .ntl level, paint tiles, throw bodies,
 * see every gizmo of the engine's debug draw, save levels and record replays.
 *
 * This file is the SDL side: options, the window, the frame loop, turning SDL events
 * into the playground's calls (play.h), scripted input (--script pushes synthetic SDL
 * events into SDL's queue, so scripts drive the same input path as a keyboard),
 * screenshots. Everything is drawn by render.c into a pixel buffer that is copied to
 * the window surface, so a frame is the same on every video driver. */
#define _POSIX_C_SOURCE 200809L
#include <SDL.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "play.h"
#include "../common/stream.h"
#include "png.h"

enum { EXIT_USAGE = 2 };

static void usage(FILE *f)
{
    fputs("usage: ntile-play [LEVEL.ntl | REPLAY.ntr] [options]\n"
          "\n"
          "Plays a level (default levels/ninja.ntl) in a window: arrows/WASD move, Z/space jump,\n"
          "X act, H shows every key. Options:\n"
          "  --replay FILE.ntr    play a replay's inputs on its level (seed, dt, friction model)\n"
          "  --frames N           stop after N frames; without --realtime each frame is one tick\n"
          "  --seconds S          stop after S seconds of wall-clock time (implies --realtime)\n"
          "  --realtime           advance by the wall clock even with --frames or --script\n"
          "  --screenshot OUT     save the last frame: OUT.bmp (BMP) or OUT.png (PNG)\n"
          "  --gizmos LIST        gizmos on at start: comma list of tiles, edges, grid, bodies,\n"
          "                       velocities, split, contacts, projections, rays, sleep, sensors,\n"
          "                       stats; or all, none\n"
          "  --script FILE        scripted input, one event per line (see below)\n"
          "  --size WxH           window size in pixels (default 1024x640)\n"
          "  --zoom Z             pixels per world unit (default: the level fits)\n"
          "  --center X Y         fixed camera centre in world units (default: follow the player)\n"
          "  --mouse X Y          initial mouse position in window pixels (for the ray gizmo)\n"
          "  --no-hud             no HUD, tile strip or help: the view fills the window\n"
          "  --alpha A            one tick per frame: draw bodies the fraction A (0..1) of the way\n"
          "                       from their previous tick to the last one (default 1; tests the\n"
          "                       render interpolation, which real time does by the clock)\n"
          "  --levels DIR         where the shipped levels are (default: found next to LEVEL,\n"
          "                       in ./levels, or next to the program)\n"
          "  --save-dir DIR       where F2 and F5 write (default: .)\n"
          "  --save FILE.ntl      F2 writes exactly this file\n"
          "  --record FILE.ntr    the first F5 recording goes exactly here\n"
          "  --image-stats FILE   print a BMP's size and colours; exit 0 when it is not blank\n"
          "                       (at least 8 colours, none over 97 %), 3 when it is\n"
          "  --help               this text\n"
          "\n"
          "Script lines (FRAME counts from 1; events are handled at the start of that frame):\n"
          "  FRAME down KEY | FRAME up KEY | FRAME press KEY     (SDL key names: Right, Z, F5, ...;\n"
          "                                                     LShift, LCtrl, LAlt for the modifiers)\n"
          "  FRAME mouse down|up left|middle|right X Y | FRAME mouse move X Y | FRAME wheel DY\n"
          "  FRAME resize W H | FRAME drop FILE (a level or replay dropped on the window) | FRAME quit\n"
          "\n"
          "Exit status: 0 ok, 1 runtime error (level, replay, window, file), 2 usage error.\n"
          "Without a display: SDL_VIDEODRIVER=dummy (or offscreen) with --frames and --screenshot.\n",
          f);
}

/* ---------------------------------------------------------------- scripts */

typedef struct script_event {
    int frame, order;
    char *drop; /* a file dropped on the window (the event gets a copy SDL can free) */
    int resize_w, resize_h; /* > 0: resize the window instead of pushing ev */
    SDL_Event ev;
} script_event;

typedef struct script {
    script_event *e;
    int n, cap, next;
} script;

static int script_add(script *s, int frame, const SDL_Event *ev, int resize_w, int resize_h)
{
    if (s->n == s->cap) {
        int cap = s->cap ? s->cap * 2 : 64;
        script_event *ne = realloc(s->e, (size_t)cap * sizeof *ne);
        if (!ne) return 0;
        s->e = ne;
        s->cap = cap;
    }
    s->e[s->n].frame = frame;
    s->e[s->n].order = s->n;
    s->e[s->n].resize_w = resize_w;
    s->e[s->n].resize_h = resize_h;
    s->e[s->n].drop = NULL;
    s->e[s->n].ev = *ev;
    s->n++;
    return 1;
}

static void script_free(script *s)
{
    for (int i = 0; i < s->n; i++) free(s->e[i].drop);
    free(s->e);
    s->e = NULL;
    s->n = 0;
}

static int cmp_event(const void *a, const void *b)
{
    const script_event *x = a, *y = b;
    if (x->frame != y->frame) return x->frame < y->frame ? -1 : 1;
    return x->order < y->order ? -1 : x->order > y->order; /* file order within a frame */
}

static int parse_int(const char *s, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi) return 0;
    *out = v;
    return 1;
}

static int parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || *end || v != v || v > 1e9 || v < -1e9) return 0;
    *out = v;
    return 1;
}

static int load_script(const char *path, script *s)
{
    char open_why[600];
    FILE *f = stream_open_regular(path, STREAM_MAX_FILE, open_why, sizeof open_why);
    if (!f) {
        fprintf(stderr, "ntile-play: script: %s\n", open_why);
        return 0;
    }
    char line[512];
    int ln = 0, ok = 1;
    while (ok && fgets(line, sizeof line, f)) {
        ln++;
        char *w[8];
        int n = 0;
        for (char *t = strtok(line, " \t\r\n"); t && n < 8; t = strtok(NULL, " \t\r\n")) w[n++] = t;
        if (n == 0 || w[0][0] == '#') continue;
        long frame;
        SDL_Event ev;
        memset(&ev, 0, sizeof ev);
        const char *why = NULL;
        if (!parse_int(w[0], 1, 100000000, &frame)) why = "the frame must be a number from 1";
        else if (n == 2 && strcmp(w[1], "quit") == 0) {
            ev.type = SDL_QUIT;
            ok = script_add(s, (int)frame, &ev, 0, 0);
        } else if (n == 3 && (strcmp(w[1], "down") == 0 || strcmp(w[1], "up") == 0 || strcmp(w[1], "press") == 0)) {
            /* SDL's names of the modifiers hold a space: one-word aliases. */
            static const struct {
                const char *alias;
                SDL_Keycode key;
            } aliases[] = {{"LShift", SDLK_LSHIFT}, {"RShift", SDLK_RSHIFT}, {"LCtrl", SDLK_LCTRL},
                           {"RCtrl", SDLK_RCTRL},   {"LAlt", SDLK_LALT},     {"RAlt", SDLK_RALT}};
            SDL_Keycode k = SDLK_UNKNOWN;
            for (size_t i = 0; i < sizeof aliases / sizeof aliases[0]; i++)
                if (strcmp(w[2], aliases[i].alias) == 0) k = aliases[i].key;
            if (k == SDLK_UNKNOWN) k = SDL_GetKeyFromName(w[2]);
            if (k == SDLK_UNKNOWN) why = "unknown key name (SDL names: Left, Right, Up, Down, Z, Space, F5, ...)";
            else {
                ev.key.keysym.sym = k;
                ev.key.keysym.scancode = SDL_GetScancodeFromKey(k);
                ev.key.keysym.mod = KMOD_NONE;
                ev.type = strcmp(w[1], "up") == 0 ? SDL_KEYUP : SDL_KEYDOWN;
                ev.key.state = ev.type == SDL_KEYDOWN ? SDL_PRESSED : SDL_RELEASED;
                ok = script_add(s, (int)frame, &ev, 0, 0);
                if (ok && strcmp(w[1], "press") == 0) {
                    ev.type = SDL_KEYUP;
                    ev.key.state = SDL_RELEASED;
                    ok = script_add(s, (int)frame + 1, &ev, 0, 0);
                }
            }
        } else if (n >= 2 && strcmp(w[1], "mouse") == 0) {
            double x, y;
            if (n == 5 && strcmp(w[2], "move") == 0 && parse_double(w[3], &x) && parse_double(w[4], &y)) {
                ev.type = SDL_MOUSEMOTION;
                ev.motion.x = (int)x;
                ev.motion.y = (int)y;
                ok = script_add(s, (int)frame, &ev, 0, 0);
            } else if (n == 6 && (strcmp(w[2], "down") == 0 || strcmp(w[2], "up") == 0) && parse_double(w[4], &x) &&
                       parse_double(w[5], &y)) {
                int b = strcmp(w[3], "left") == 0 ? SDL_BUTTON_LEFT
                        : strcmp(w[3], "middle") == 0 ? SDL_BUTTON_MIDDLE
                        : strcmp(w[3], "right") == 0 ? SDL_BUTTON_RIGHT
                                                     : 0;
                if (!b) why = "mouse buttons are left, middle, right";
                else {
                    ev.type = strcmp(w[2], "down") == 0 ? SDL_MOUSEBUTTONDOWN : SDL_MOUSEBUTTONUP;
                    ev.button.button = (Uint8)b;
                    ev.button.state = ev.type == SDL_MOUSEBUTTONDOWN ? SDL_PRESSED : SDL_RELEASED;
                    ev.button.x = (int)x;
                    ev.button.y = (int)y;
                    ok = script_add(s, (int)frame, &ev, 0, 0);
                }
            } else why = "expected 'mouse move X Y' or 'mouse down|up BUTTON X Y'";
        } else if (n == 4 && strcmp(w[1], "resize") == 0) {
            long rw, rh;
            if (!parse_int(w[2], 160, 8192, &rw) || !parse_int(w[3], 120, 8192, &rh))
                why = "resize needs a width (160..8192) and a height (120..8192)";
            else
                ok = script_add(s, (int)frame, &ev, (int)rw, (int)rh); /* the window is resized, as a user would */
        } else if (n == 3 && strcmp(w[1], "drop") == 0) {
            ev.type = SDL_DROPFILE;
            ev.drop.file = NULL;
            ok = script_add(s, (int)frame, &ev, 0, 0);
            if (ok) {
                s->e[s->n - 1].drop = strdup(w[2]);
                ok = s->e[s->n - 1].drop != NULL;
            }
        } else if (n == 3 && strcmp(w[1], "wheel") == 0) {
            double dy;
            if (!parse_double(w[2], &dy)) why = "wheel needs a number";
            else {
                ev.type = SDL_MOUSEWHEEL;
                ev.wheel.y = (Sint32)dy;
                ok = script_add(s, (int)frame, &ev, 0, 0);
            }
        } else why = "expected FRAME down|up|press KEY, FRAME mouse ..., FRAME wheel DY or FRAME quit";
        if (why) {
            fprintf(stderr, "ntile-play: %s:%d: %s\n", path, ln, why);
            ok = 0;
        } else if (!ok) {
            fprintf(stderr, "ntile-play: out of memory reading the script\n");
        }
    }
    fclose(f);
    if (ok) qsort(s->e, (size_t)s->n, sizeof *s->e, cmp_event);
    return ok;
}

/* ---------------------------------------------------------------- keys */

typedef struct hold_key {
    SDL_Keycode key;
    uint32_t bit;
    bool down;
} hold_key;

static hold_key holds[] = {
    {SDLK_LEFT, NT_INPUT_LEFT, false},  {SDLK_a, NT_INPUT_LEFT, false},     {SDLK_RIGHT, NT_INPUT_RIGHT, false},
    {SDLK_d, NT_INPUT_RIGHT, false},    {SDLK_UP, NT_INPUT_UP, false},      {SDLK_w, NT_INPUT_UP, false},
    {SDLK_DOWN, NT_INPUT_DOWN, false},  {SDLK_s, NT_INPUT_DOWN, false},     {SDLK_z, NT_INPUT_JUMP, false},
    {SDLK_SPACE, NT_INPUT_JUMP, false}, {SDLK_x, NT_INPUT_ACTION, false},
};
#define HOLD_COUNT ((int)(sizeof holds / sizeof holds[0]))

static uint32_t held_keys(void)
{
    uint32_t k = 0;
    for (int i = 0; i < HOLD_COUNT; i++)
        if (holds[i].down) k |= holds[i].bit;
    return k;
}

static bool holds_space(void)
{
    for (int i = 0; i < HOLD_COUNT; i++)
        if (holds[i].key == SDLK_SPACE) return holds[i].down;
    return false;
}

/* A key press: 0 to go on, 1 to quit. */
static int key_down(pg *p, SDL_Keycode k, Uint16 mod, bool repeat)
{
    bool shift = (mod & KMOD_SHIFT) != 0;
    /* Keys that may repeat while held. */
    switch (k) {
    case SDLK_PLUS:
    case SDLK_EQUALS:
    case SDLK_KP_PLUS: pg_command(p, PG_CMD_ZOOM, 1); return 0;
    case SDLK_MINUS:
    case SDLK_KP_MINUS: pg_command(p, PG_CMD_ZOOM, -1); return 0;
    case SDLK_LEFTBRACKET: pg_command(p, PG_CMD_BOUNCE, -1); return 0;
    case SDLK_RIGHTBRACKET: pg_command(p, PG_CMD_BOUNCE, 1); return 0;
    case SDLK_SEMICOLON: pg_command(p, PG_CMD_FRICTION, -1); return 0;
    case SDLK_QUOTE: pg_command(p, PG_CMD_FRICTION, 1); return 0;
    case SDLK_TAB: pg_command(p, PG_CMD_TILE, shift ? -1 : 1); return 0;
    case SDLK_PERIOD: pg_command(p, PG_CMD_STEP, 0); return 0;
    case SDLK_COMMA: pg_command(p, PG_CMD_STEP_BACK, 0); return 0;
    default: break;
    }
    if (repeat) return 0;
    for (int g = 0; g < PG_GZ_COUNT; g++)
        if (k == (SDL_Keycode)(pg_gizmos[g].key - 'A' + 'a')) {
            if (g == PG_GZ_PROJECTIONS && shift) pg_command(p, PG_CMD_PROJ_SCALE, 0);
            else pg_command(p, PG_CMD_GIZMO, g);
            return 0;
        }
    if (k >= SDLK_1 && k <= SDLK_9) {
        pg_command(p, PG_CMD_LEVEL, (int)(k - SDLK_1));
        return 0;
    }
    switch (k) {
    case SDLK_ESCAPE: return pg_request_quit(p);
    case SDLK_r: pg_command(p, PG_CMD_RESTART, 0); break;
    case SDLK_PAGEUP: pg_command(p, PG_CMD_LEVEL_PREV, 0); break;
    case SDLK_PAGEDOWN: pg_command(p, PG_CMD_LEVEL_NEXT, 0); break;
    case SDLK_p: pg_command(p, PG_CMD_PAUSE, 0); break;
    case SDLK_m: pg_command(p, PG_CMD_SLOW, 0); break;
    case SDLK_h:
    case SDLK_F1: pg_command(p, PG_CMD_HELP, 0); break;
    case SDLK_q: pg_command(p, PG_CMD_THROW_SHAPE, 0); break;
    case SDLK_l: pg_command(p, PG_CMD_THROW_SIZE, 0); break;
    case SDLK_f: pg_command(p, PG_CMD_FRICTION_MODEL, 0); break;
    case SDLK_F2: pg_command(p, PG_CMD_SAVE, 0); break;
    case SDLK_F5: pg_command(p, PG_CMD_RECORD, 0); break;
    case SDLK_F3: pg_command(p, PG_CMD_PANEL, 0); break;
    case SDLK_F6: pg_command(p, PG_CMD_TOOL, shift ? -2 : -1); break;
    case SDLK_F7: pg_command(p, PG_CMD_DIVERGENCE, 0); break;
    case SDLK_END: pg_command(p, PG_CMD_REPLAY_END, 0); break;
    case SDLK_HOME: pg_command(p, PG_CMD_ZOOM, 0); break;
    default: break;
    }
    return 0;
}

/* The window has the keyboard focus (assumed until SDL says otherwise: a window
 * manager-less X server such as Xvfb never gives it). */
static bool focused = true;
/* Modifier keys held, as the key events said (PG_MOD_*). */
static unsigned mods;

/* One SDL event: 0 to go on, 1 to quit. */
static int handle_event(pg *p, const SDL_Event *e, int *resized)
{
    switch (e->type) {
    case SDL_QUIT: return pg_request_quit(p);
    case SDL_KEYDOWN:
    case SDL_KEYUP: {
        bool down = e->type == SDL_KEYDOWN;
        SDL_Keycode sym = e->key.keysym.sym;
        /* Modifiers: SDL's, or the events' own (scripted events carry none). */
        unsigned bit = sym == SDLK_LSHIFT || sym == SDLK_RSHIFT ? PG_MOD_SHIFT
                       : sym == SDLK_LCTRL || sym == SDLK_RCTRL ? PG_MOD_CTRL
                       : sym == SDLK_LALT || sym == SDLK_RALT   ? PG_MOD_ALT
                                                                : 0;
        if (bit) mods = down ? mods | bit : mods & ~bit;
        unsigned m = mods | ((e->key.keysym.mod & KMOD_SHIFT) ? PG_MOD_SHIFT : 0) |
                     ((e->key.keysym.mod & KMOD_CTRL) ? PG_MOD_CTRL : 0) | ((e->key.keysym.mod & KMOD_ALT) ? PG_MOD_ALT : 0);
        pg_set_mods(p, m);
        if (pg_confirming(p) && down) { /* a question waits: Y, N / Esc, F2 */
            if (!e->key.repeat) {
                if (sym == SDLK_y) pg_command(p, PG_CMD_CONFIRM, 1);
                else if (sym == SDLK_n || sym == SDLK_ESCAPE) pg_command(p, PG_CMD_CONFIRM, 0);
                else if (sym == SDLK_F2) pg_command(p, PG_CMD_CONFIRM, 2);
            }
            return pg_should_quit(p);
        }
        if (down && (m & PG_MOD_CTRL) && (sym == SDLK_z || sym == SDLK_y)) {
            pg_command(p, sym == SDLK_y || (m & PG_MOD_SHIFT) ? PG_CMD_REDO : PG_CMD_UNDO, 0);
            return 0;
        }
        bool held = false;
        for (int i = 0; i < HOLD_COUNT; i++)
            if (holds[i].key == e->key.keysym.sym) {
                holds[i].down = down;
                held = true;
            }
        pg_set_keys(p, held_keys());
        if (down && !held) return key_down(p, e->key.keysym.sym, e->key.keysym.mod, e->key.repeat != 0);
        return 0;
    }
    case SDL_MOUSEMOTION: pg_mouse_move(p, e->motion.x, e->motion.y); return 0;
    case SDL_MOUSEBUTTONDOWN:
    case SDL_MOUSEBUTTONUP: {
        int b = e->button.button == SDL_BUTTON_LEFT ? PG_MOUSE_LEFT
                : e->button.button == SDL_BUTTON_MIDDLE ? PG_MOUSE_MIDDLE
                : e->button.button == SDL_BUTTON_RIGHT ? PG_MOUSE_RIGHT
                                                        : 0;
        /* Space + left drag pans (Space is also the jump key). */
        static bool space_pan;
        if (b == PG_MOUSE_LEFT && e->type == SDL_MOUSEBUTTONDOWN) space_pan = holds_space();
        if (b == PG_MOUSE_LEFT && space_pan) b = PG_MOUSE_PAN;
        if (b) pg_mouse_button(p, b, e->type == SDL_MOUSEBUTTONDOWN, e->button.x, e->button.y);
        return 0;
    }
    case SDL_MOUSEWHEEL: pg_mouse_wheel(p, e->wheel.y); return 0;
    case SDL_DROPFILE: /* a level or a replay dropped on the window */
        if (e->drop.file) pg_open(p, e->drop.file);
        SDL_free(e->drop.file);
        return 0;
    case SDL_WINDOWEVENT:
        if (e->window.event == SDL_WINDOWEVENT_SIZE_CHANGED || e->window.event == SDL_WINDOWEVENT_RESIZED) *resized = 1;
        if (e->window.event == SDL_WINDOWEVENT_FOCUS_GAINED) focused = true;
        if (e->window.event == SDL_WINDOWEVENT_FOCUS_LOST) {
            focused = false;
            /* Key releases go to the other window: nothing stays held. */
            for (int i = 0; i < HOLD_COUNT; i++) holds[i].down = false;
            pg_set_keys(p, 0);
        }
        return 0;
    default: return 0;
    }
}

/* ---------------------------------------------------------------- images */

static SDL_Surface *canvas_surface(pg_canvas *c)
{
    return SDL_CreateRGBSurfaceWithFormatFrom(c->px, c->w, c->h, 32, c->w * 4, SDL_PIXELFORMAT_RGB888);
}

static int save_screenshot(pg_canvas *c, const char *path)
{
    size_t n = strlen(path);
    if (n >= 4 && (strcmp(path + n - 4, ".png") == 0 || strcmp(path + n - 4, ".PNG") == 0)) {
        if (!pg_png_write(path, c->px, c->w, c->h, c->w)) {
            fprintf(stderr, "ntile-play: cannot write '%s': %s\n", path, strerror(errno));
            return 0;
        }
        return 1;
    }
    SDL_Surface *s = canvas_surface(c);
    int ok = s && SDL_SaveBMP(s, path) == 0;
    if (!ok) fprintf(stderr, "ntile-play: cannot write '%s': %s\n", path, SDL_GetError());
    SDL_FreeSurface(s);
    return ok;
}

/* Colour statistics of a BMP: is it a picture or a blank frame? */
static int image_stats(const char *path)
{
    SDL_Surface *raw = SDL_LoadBMP(path);
    if (!raw) {
        fprintf(stderr, "ntile-play: cannot read '%s': %s\n", path, SDL_GetError());
        return 1;
    }
    SDL_Surface *s = SDL_ConvertSurfaceFormat(raw, SDL_PIXELFORMAT_RGB888, 0);
    SDL_FreeSurface(raw);
    if (!s) {
        fprintf(stderr, "ntile-play: cannot convert '%s': %s\n", path, SDL_GetError());
        return 1;
    }
    /* Distinct colours by an open-addressing set of 2^16 slots (enough to tell). */
    enum { CAP = 1 << 16 };
    uint32_t *key = calloc(CAP, sizeof *key), *count = calloc(CAP, sizeof *count);
    int colors = 0, rc = 1;
    if (key && count) {
        long total = (long)s->w * s->h, best = 0;
        uint32_t best_color = 0;
        SDL_LockSurface(s);
        for (int y = 0; y < s->h; y++) {
            const uint32_t *row = (const uint32_t *)((const unsigned char *)s->pixels + (size_t)y * (size_t)s->pitch);
            for (int x = 0; x < s->w; x++) {
                uint32_t c = (row[x] & 0xffffffu) | 0x1000000u; /* 0 marks an empty slot */
                uint32_t h = (c * 2654435761u) >> 16;
                int probes = 0;
                while (key[h] && key[h] != c && probes++ < CAP) h = (h + 1) & (CAP - 1);
                if (probes >= CAP) continue;
                if (!key[h]) {
                    key[h] = c;
                    colors++;
                }
                if (++count[h] > (uint32_t)best) {
                    best = count[h];
                    best_color = c & 0xffffffu;
                }
            }
        }
        SDL_UnlockSurface(s);
        double share = total ? 100.0 * (double)best / (double)total : 100;
        int blank = colors < 8 || share > 97;
        printf("%s: %dx%d, %d colours, most common 0x%06x covers %.1f %% of the pixels: %s\n", path, s->w, s->h, colors,
               (unsigned)best_color, share, blank ? "blank" : "not blank");
        rc = blank ? 3 : 0;
    } else {
        fprintf(stderr, "ntile-play: out of memory\n");
    }
    free(key);
    free(count);
    SDL_FreeSurface(s);
    return rc;
}

/* ---------------------------------------------------------------- main */

typedef struct args {
    pg_options o;
    long frames;
    double seconds;
    bool realtime;
    const char *screenshot, *script;
    int w, h;
    bool has_mouse;
    double mouse_x, mouse_y;
} args;

static int need(int argc, char **argv, int i, int n)
{
    if (i + n >= argc) {
        fprintf(stderr, "ntile-play: %s needs %d argument%s (see --help)\n", argv[i], n, n > 1 ? "s" : "");
        return 0;
    }
    return 1;
}

static int bad(const char *opt, const char *v, const char *what)
{
    fprintf(stderr, "ntile-play: %s '%s': %s\n", opt, v, what);
    return 0;
}

static int parse_args(int argc, char **argv, args *a)
{
    memset(a, 0, sizeof *a);
    a->o.hud = true;
    a->o.gizmos = 0;
    a->o.fixed_alpha = 1;
    a->w = 1024, a->h = 640;
    for (int i = 1; i < argc; i++) {
        const char *s = argv[i];
        if (strcmp(s, "--replay") == 0) {
            if (!need(argc, argv, i, 1)) return 0;
            a->o.replay_path = argv[++i];
        } else if (strcmp(s, "--frames") == 0) {
            if (!need(argc, argv, i, 1)) return 0;
            if (!parse_int(argv[++i], 1, 100000000, &a->frames)) return bad(s, argv[i], "expected a number of frames >= 1");
        } else if (strcmp(s, "--seconds") == 0) {
            if (!need(argc, argv, i, 1)) return 0;
            if (!parse_double(argv[++i], &a->seconds) || !(a->seconds > 0))
                return bad(s, argv[i], "expected a number of seconds > 0");
            a->realtime = true;
        } else if (strcmp(s, "--realtime") == 0) {
            a->realtime = true;
        } else if (strcmp(s, "--screenshot") == 0) {
            if (!need(argc, argv, i, 1)) return 0;
            a->screenshot = argv[++i];
        } else if (strcmp(s, "--gizmos") == 0) {
            if (!need(argc, argv, i, 1)) return 0;
            char why[400];
            if (!pg_parse_gizmos(argv[++i], &a->o.gizmos, why, sizeof why)) return bad(s, argv[i], why);
        } else if (strcmp(s, "--script") == 0) {
            if (!need(argc, argv, i, 1)) return 0;
            a->script = argv[++i];
        } else if (strcmp(s, "--size") == 0) {
            if (!need(argc, argv, i, 1)) return 0;
            const char *v = argv[++i];
            char wbuf[32];
            const char *x = strchr(v, 'x');
            long w, h;
            if (!x || (size_t)(x - v) >= sizeof wbuf) return bad(s, v, "expected WIDTHxHEIGHT, e.g. 800x600");
            memcpy(wbuf, v, (size_t)(x - v));
            wbuf[x - v] = '\0';
            if (!parse_int(wbuf, 160, 8192, &w) || !parse_int(x + 1, 120, 8192, &h))
                return bad(s, v, "expected WIDTHxHEIGHT with 160 <= WIDTH <= 8192 and 120 <= HEIGHT <= 8192");
            a->w = (int)w, a->h = (int)h;
        } else if (strcmp(s, "--zoom") == 0) {
            if (!need(argc, argv, i, 1)) return 0;
            if (!parse_double(argv[++i], &a->o.zoom) || !(a->o.zoom >= 0.05 && a->o.zoom <= 64))
                return bad(s, argv[i], "expected pixels per world unit in 0.05..64");
            a->o.has_zoom = true;
        } else if (strcmp(s, "--center") == 0) {
            if (!need(argc, argv, i, 2)) return 0;
            if (!parse_double(argv[i + 1], &a->o.center_x) || !parse_double(argv[i + 2], &a->o.center_y))
                return bad(s, argv[i + 1], "expected two numbers X Y");
            a->o.has_center = true;
            i += 2;
        } else if (strcmp(s, "--mouse") == 0) {
            if (!need(argc, argv, i, 2)) return 0;
            if (!parse_double(argv[i + 1], &a->mouse_x) || !parse_double(argv[i + 2], &a->mouse_y))
                return bad(s, argv[i + 1], "expected two numbers X Y");
            a->has_mouse = true;
            i += 2;
        } else if (strcmp(s, "--alpha") == 0) {
            if (!need(argc, argv, i, 1)) return 0;
            if (!parse_double(argv[++i], &a->o.fixed_alpha) || !(a->o.fixed_alpha >= 0 && a->o.fixed_alpha <= 1))
                return bad(s, argv[i], "expected a fraction in 0..1");
        } else if (strcmp(s, "--no-hud") == 0) {
            a->o.hud = false;
        } else if (strcmp(s, "--levels") == 0) {
            if (!need(argc, argv, i, 1)) return 0;
            a->o.levels_dir = argv[++i];
        } else if (strcmp(s, "--save-dir") == 0) {
            if (!need(argc, argv, i, 1)) return 0;
            a->o.save_dir = argv[++i];
        } else if (strcmp(s, "--save") == 0) {
            if (!need(argc, argv, i, 1)) return 0;
            a->o.save_path = argv[++i];
        } else if (strcmp(s, "--record") == 0) {
            if (!need(argc, argv, i, 1)) return 0;
            a->o.record_path = argv[++i];
        } else if (s[0] == '-' && s[1] != '\0') {
            fprintf(stderr, "ntile-play: unknown option '%s' (see --help)\n", s);
            return 0;
        } else {
            size_t l = strlen(s);
            if (l > 4 && strcmp(s + l - 4, ".ntr") == 0 && !a->o.replay_path) { /* a replay given as a file */
                a->o.replay_path = s;
                continue;
            }
            if (a->o.level_path) {
                fprintf(stderr, "ntile-play: more than one level given ('%s' and '%s')\n", a->o.level_path, s);
                return 0;
            }
            a->o.level_path = s;
        }
    }
    if (a->o.level_path && a->o.replay_path) {
        fprintf(stderr, "ntile-play: give a LEVEL or --replay, not both (a replay names its level)\n");
        return 0;
    }
    return 1;
}

int main(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage(stdout);
            return 0;
        }
        if (strcmp(argv[i], "--image-stats") == 0) {
            if (i + 1 >= argc) {
                fprintf(stderr, "ntile-play: --image-stats needs a file\n");
                return EXIT_USAGE;
            }
            return image_stats(argv[i + 1]);
        }
    }
    if (nt_real_size() != (int)sizeof(nt_real)) {
        fprintf(stderr, "ntile-play: built against a library with a different scalar type (NT_DOUBLE mismatch)\n");
        return EXIT_USAGE;
    }
    args a;
    if (!parse_args(argc, argv, &a)) return EXIT_USAGE;
    script sc;
    memset(&sc, 0, sizeof sc);
    if (a.script && !load_script(a.script, &sc)) {
        script_free(&sc);
        return EXIT_USAGE;
    }
    bool fixed = !a.realtime && (a.frames > 0 || a.script);

    char why[1200];
    pg *p = pg_create(&a.o, why, sizeof why);
    if (!p) {
        fprintf(stderr, "ntile-play: %s\n", why);
        script_free(&sc);
        return 1;
    }
    if (SDL_Init(SDL_INIT_VIDEO) != 0) {
        fprintf(stderr,
                "ntile-play: cannot start SDL video: %s\n"
                "ntile-play: without a display, use SDL_VIDEODRIVER=dummy with --frames N --screenshot OUT.bmp,\n"
                "ntile-play: or `make run` for the headless replay of the default level\n",
                SDL_GetError());
        pg_destroy(p);
        script_free(&sc);
        return 1;
    }
    /* Offscreen and dummy drivers have their own framebuffer: do not let SDL load an
     * OpenGL/EGL stack to draw a plain surface (an environment variable still wins). */
    const char *driver = SDL_GetCurrentVideoDriver();
    bool invisible = driver && (strcmp(driver, "offscreen") == 0 || strcmp(driver, "dummy") == 0);
    if (invisible) SDL_SetHintWithPriority(SDL_HINT_FRAMEBUFFER_ACCELERATION, "0", SDL_HINT_DEFAULT);
    const char *asked = getenv("SDL_VIDEODRIVER");
    if (invisible && !(asked && *asked) && a.frames == 0 && a.seconds == 0 && !a.script) {
        /* SDL found no display and fell back to a driver that shows nothing: an
         * interactive session would run unseen for ever. */
        fprintf(stderr,
                "ntile-play: no display found (SDL fell back to its '%s' video driver, which shows nothing)\n"
                "ntile-play: run it in a desktop session (DISPLAY or WAYLAND_DISPLAY set), or headless with\n"
                "ntile-play: SDL_VIDEODRIVER=dummy and --frames N --screenshot OUT.bmp, or `make run` for the headless replay\n",
                driver);
        SDL_Quit();
        pg_destroy(p);
        script_free(&sc);
        return 1;
    }
    char title[512];
    pg_title(p, title, sizeof title);
    SDL_Window *win = SDL_CreateWindow(title, SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, a.w, a.h, SDL_WINDOW_RESIZABLE);
    pg_canvas canvas;
    memset(&canvas, 0, sizeof canvas);
    int rc = 0;
    if (!win) {
        fprintf(stderr, "ntile-play: cannot open a window: %s\n", SDL_GetError());
        rc = 1;
        goto done;
    }
    int ww = a.w, wh = a.h;
    if (!pg_canvas_resize(&canvas, ww, wh)) {
        fprintf(stderr, "ntile-play: out of memory for a %dx%d frame\n", ww, wh);
        rc = 1;
        goto done;
    }
    pg_set_window(p, ww, wh);
    if (a.has_mouse) pg_mouse_move(p, a.mouse_x, a.mouse_y);

    Uint64 freq = SDL_GetPerformanceFrequency(), start = SDL_GetPerformanceCounter(), last = start;
    double fps = 0;
    long frame = 0;
    int quit = 0;
    while (!quit) {
        frame++;
        while (sc.next < sc.n && sc.e[sc.next].frame <= frame) {
            const script_event *se = &sc.e[sc.next++];
            if (se->resize_w > 0) {
                SDL_SetWindowSize(win, se->resize_w, se->resize_h);
                continue;
            }
            SDL_Event ev = se->ev;
            ev.common.timestamp = SDL_GetTicks();
            if (ev.type == SDL_DROPFILE) ev.drop.file = SDL_strdup(se->drop);
            SDL_PushEvent(&ev);
        }
        SDL_Event ev;
        int resized = 0;
        bool idle_timeout = false, idle_msg = false;
        if (!fixed && (pg_idle(p) || !focused)) {
            /* Paused or in the background: nothing moves, so sleep until something
             * happens (a key, the mouse, the window) instead of drawing 60 frames a
             * second; wake at least every half second for messages and --seconds. */
            int ms = 500;
            if (a.seconds > 0) {
                double left = a.seconds - (double)(SDL_GetPerformanceCounter() - start) / (double)freq;
                ms = left <= 0 ? 0 : left * 1000 < ms ? (int)(left * 1000) + 1 : ms;
            }
            bool msg_before = pg_message(p)[0] != 0;
            if (SDL_WaitEventTimeout(&ev, ms)) quit = handle_event(p, &ev, &resized);
            else idle_timeout = true;
            idle_msg = msg_before;
        }
        while (!quit && SDL_PollEvent(&ev)) quit = handle_event(p, &ev, &resized);
        if (quit) break;
        if (resized) {
            int nw, nh;
            SDL_GetWindowSize(win, &nw, &nh);
            if (nw > 0 && nh > 0 && pg_canvas_resize(&canvas, nw, nh)) pg_set_window(p, nw, nh);
        }
        Uint64 now = SDL_GetPerformanceCounter();
        double dt = (double)(now - last) / (double)freq;
        last = now;
        if (dt > 0) fps = fps > 0 ? fps * 0.9 + 0.1 / dt : 1 / dt;
        if (fixed) pg_advance_frame(p);
        else pg_advance(p, focused ? dt : 0); /* the game stands still while the window is in the background */
        /* A sleep that ended without an event changes nothing on screen, unless a
         * message just ran out. */
        if (idle_timeout && !resized && idle_msg == (pg_message(p)[0] != 0) && sc.next >= sc.n) {
            double elapsed0 = (double)(SDL_GetPerformanceCounter() - start) / (double)freq;
            if (a.seconds > 0 && elapsed0 >= a.seconds) break;
            continue;
        }
        char now_title[512];
        pg_title(p, now_title, sizeof now_title);
        if (strcmp(now_title, title) != 0) {
            snprintf(title, sizeof title, "%s", now_title);
            SDL_SetWindowTitle(win, title);
        }
        pg_render(p, &canvas, fps);
        SDL_Surface *ws = SDL_GetWindowSurface(win);
        SDL_Surface *cs = canvas_surface(&canvas);
        if (ws && cs) {
            SDL_BlitSurface(cs, NULL, ws, NULL);
            SDL_UpdateWindowSurface(win);
        }
        SDL_FreeSurface(cs);
        if (a.frames > 0 && frame >= a.frames) break;
        double elapsed = (double)(SDL_GetPerformanceCounter() - start) / (double)freq;
        if (a.seconds > 0 && elapsed >= a.seconds) break;
        if (!fixed) {
            /* About 60 frames a second; the simulation keeps its own fixed ticks. */
            double spent = (double)(SDL_GetPerformanceCounter() - now) / (double)freq;
            if (spent < 1.0 / 60) SDL_Delay((Uint32)((1.0 / 60 - spent) * 1000));
        }
    }
    if (a.frames > 0 || a.seconds > 0) {
        char line[400];
        pg_summary(p, line, sizeof line);
        printf("ntile-play: %s\n", line);
    }
    if (a.screenshot && !save_screenshot(&canvas, a.screenshot)) rc = 1;
    else if (a.screenshot)
        printf("ntile-play: frame %ld (tick %d, video driver %s) saved to %s\n", frame, pg_tick_count(p),
               SDL_GetCurrentVideoDriver() ? SDL_GetCurrentVideoDriver() : "?", a.screenshot);
done:
    pg_finish(p);
    if (pg_message(p)[0]) printf("ntile-play: %s\n", pg_message(p));
    pg_canvas_free(&canvas);
    if (win) SDL_DestroyWindow(win);
    SDL_Quit();
    pg_destroy(p);
    script_free(&sc);
    return rc;
}
