/* ntile bench — the scenes (see scene.h). Every scene is built from a fixed seed.
 *
 * World scenes (speed), N's scale (cell 24 units, gravity 320 units/s^2, dt 1/40 s,
 * N's friction model with the world defaults) unless said:
 *   rain       bodies (half circles, half boxes, half-sizes 0.2..0.4 cell) start in
 *              the empty cells of a 256 x 256 map whose ledges use every tile shape,
 *              fall and settle on them (map side grows as sqrt(bodies))
 *   particles  the same scene with every body colliding with tiles only
 *   giants     rain with bodies of mixed sizes, 0.2 to 4 cells across (log-uniform: half
 *              are under a cell), boxes of unequal sides and circles (2,000 bodies,
 *              twice rain's map area per body)
 *   sparse     bodies flying in straight lines (no gravity) through a 256 x 256 map
 *              that is almost empty
 *   pile       a 64-cell-wide container filled with 3000 bodies (Coulomb friction 0.5,
 *              no bounce), sleep off: dense contact
 *   asleep     that pile with sleep on, stepped until every body sleeps, then timed
 *              (200 steps, and on until at least 20 ms of steps are timed)
 * Error scenes (each built so that one error has a known right answer):
 *   slide      boxes and circles sliding without friction along a 220-cell FULL floor,
 *              a HALFd floor and down 22/45/67 degree slopes onto flat floors: ghost bumps
 *              and speed lost at seams
 *   bounce     bodies dropped from 3..9 cells onto a floor, bounce 0.5 (apex heights
 *              e^2n h0) and bounce 1 (energy), no friction
 *   gas        300 bodies in a closed 32 x 32 room, no gravity, bounce 1, no friction:
 *              energy through body-body and wall collisions
 *   incline    Coulomb boxes and circles on 22, 45, 67 degree slopes and their mirrors:
 *              mu below tan: acceleration g (sin - mu cos); mu above: must stay put
 *   flight     bodies thrown through an empty map: the parabola
 *   rest       stacks of boxes and a row of circles on a floor (Coulomb 0.5, no bounce,
 *              sleep off): motion of bodies that should be at rest
 *   tunnel     small bodies fired at 2, 3 and 4 cells per step at each of the 33 solid
 *              tiles from 8 directions (no gravity)
 * Skipping scenes (tiles only, sleep off, 10,000 bodies):
 *   free       bodies drifting (no gravity) through an empty 256 x 256 map: nothing near
 *   touching   bodies resting on floors (a FULL row every other row), each on one
 *              FULL tile
 */
#include "scene.h"
#include "ntile/base.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "bench.h"

const char *const scene_names[] = {"rain",   "particles", "giants", "sparse", "pile", "asleep", "slide",    "bounce", "gas",
                                   "incline", "flight",  "rest",   "tunnel", "free", "touching", NULL};

static const double CELL = 24, GRAVITY = 320, DT = 1.0 / 40;

/* ---------- building blocks ---------- */

static int scene_init(scene *s, const char *name, const char *summary, int w, int h, int nbodies)
{
    memset(s, 0, sizeof *s);
    s->name = name;
    s->summary = summary;
    s->width = w;
    s->height = h;
    s->cell = CELL;
    s->gx = 0;
    s->gy = GRAVITY;
    s->dt = DT;
    s->coulomb = 0;
    s->tile_friction = 0.05; /* ntile's defaults (N's values) */
    s->tile_bounce = 0.3;
    s->restitution_threshold = 24;
    s->sleep = 1;
    s->velocity_iterations = 8;
    s->position_iterations = 4;
    s->substeps = 1;
    s->tiles = calloc((size_t)w * (size_t)h, 1);
    s->bodies = calloc(nbodies > 0 ? (size_t)nbodies : 1, sizeof *s->bodies);
    if (!s->tiles || !s->bodies) {
        scene_free(s);
        return 0;
    }
    return 1;
}

void scene_free(scene *s)
{
    free(s->tiles);
    free(s->bodies);
    s->tiles = NULL;
    s->bodies = NULL;
    s->nbodies = 0;
}

static void set_tile(scene *s, int x, int y, int tile)
{
    if (x >= 0 && y >= 0 && x < s->width && y < s->height) s->tiles[(size_t)y * (size_t)s->width + (size_t)x] = (uint8_t)tile;
}

/* A body with ntile's default material (friction 0.05, bounce 0.3), mass 1. */
static scene_body *add_body(scene *s, int circle, double half, double x, double y, double vx, double vy)
{
    scene_body *b = &s->bodies[s->nbodies++];
    memset(b, 0, sizeof *b);
    b->circle = circle;
    b->hx = b->hy = half;
    b->x = x;
    b->y = y;
    b->vx = vx;
    b->vy = vy;
    b->mass = 1;
    b->friction = 0.05;
    b->bounce = 0.3;
    b->collide_bodies = 1;
    return b;
}

/* ---------- world scenes (the same placements as the first bench world) ---------- */

/* Tiles of the rain map: a full floor row, then ledges of 2..6 cells whose tiles
 * cycle through all 33 solid shapes, about one cell in six solid. */
static void rain_tiles(uint8_t *t, int side, uint64_t *rng)
{
    memset(t, NT_TILE_EMPTY, (size_t)side * (size_t)side);
    for (int x = 0; x < side; x++) t[(size_t)(side - 1) * (size_t)side + (size_t)x] = NT_TILE_FULL;
    int ledges = side * side / 24, next = 1;
    for (int k = 0; k < ledges; k++) {
        int len = 2 + (int)(bench_rng_next(rng) % 5);
        int x0 = (int)(bench_rng_next(rng) % (uint64_t)side);
        int y = 3 + (int)(bench_rng_next(rng) % (uint64_t)(side - 4));
        for (int x = x0; x < x0 + len && x < side; x++) {
            t[(size_t)y * (size_t)side + (size_t)x] = (uint8_t)next;
            next = next % (NT_TILE_COUNT - 1) + 1;
        }
    }
}

/* A few scattered tiles (one cell in 500). */
static void sparse_tiles(uint8_t *t, int side, uint64_t *rng)
{
    memset(t, NT_TILE_EMPTY, (size_t)side * (size_t)side);
    for (int k = 0; k < side * side / 500; k++)
        t[bench_rng_next(rng) % ((uint64_t)side * (uint64_t)side)] = (uint8_t)(1 + bench_rng_next(rng) % 33);
}

typedef enum world_kind { KIND_RAIN, KIND_SPARSE, KIND_PILE } world_kind;

static int make_world_scene(scene *s, const char *name, const char *summary, world_kind kind, int side, int n,
                            int collide)
{
    uint64_t rng = 0x7261696Eull + (uint64_t)n; /* "rain" */
    int w = side, h = kind == KIND_PILE ? n / side + 8 : side;
    if (!scene_init(s, name, summary, w, h, n)) return 0;
    size_t ncells = (size_t)w * (size_t)h;
    uint8_t *used = calloc(ncells, 1);
    if (!used) {
        scene_free(s);
        return 0;
    }
    if (kind == KIND_SPARSE) s->gy = 0;
    if (kind == KIND_PILE) {
        /* A pile that comes to rest: Coulomb friction 0.5, no bounce. (With N's
         * slippery defaults, 0.05 and no static friction, a pile keeps flowing.) */
        s->coulomb = 1;
        s->tile_friction = 0.5;
        s->tile_bounce = 0;
    }
    if (kind == KIND_RAIN) rain_tiles(s->tiles, w, &rng);
    else if (kind == KIND_SPARSE) sparse_tiles(s->tiles, w, &rng);
    if (kind != KIND_PILE) {
        /* Spawn cells: random empty cells with empty cells above and below, one body
         * each. Bodies are then created in reading order of their cells, as a level
         * lists them. */
        for (int i = 0; i < n; i++) {
            int tries = 0;
            for (;;) {
                size_t k = (size_t)(bench_rng_next(&rng) % ncells);
                int y = (int)(k / (size_t)w);
                if (!used[k] && s->tiles[k] == NT_TILE_EMPTY && y >= 1 && y <= h - 2 &&
                    s->tiles[k - (size_t)w] == NT_TILE_EMPTY && s->tiles[k + (size_t)w] == NT_TILE_EMPTY) {
                    used[k] = 1;
                    break;
                }
                if (++tries > 1000) {
                    free(used);
                    scene_free(s);
                    return 0;
                }
            }
        }
    }
    size_t next_cell = 0;
    for (int i = 0; i < n; i++) {
        double half = bench_rng_range(&rng, 0.2, 0.4) * CELL;
        int x, y, circle = i & 1;
        if (kind == KIND_PILE) {
            /* Rows from the bottom, one body per cell, 0.1 cell apart. */
            x = i % w;
            y = h - 1 - i / w;
            half = 0.45 * CELL;
        } else {
            while (!used[next_cell]) next_cell++;
            x = (int)(next_cell % (size_t)w);
            y = (int)(next_cell / (size_t)w);
            next_cell++;
        }
        double px = ((double)x + 0.5 + bench_rng_range(&rng, -0.05, 0.05)) * CELL;
        double py = ((double)y + 0.5 + bench_rng_range(&rng, -0.05, 0.05)) * CELL;
        scene_body *b = add_body(s, circle, half, px, py, 0, 0);
        b->collide_bodies = collide;
        if (kind == KIND_PILE) {
            b->friction = 0.5;
            b->bounce = 0;
        } else if (kind == KIND_SPARSE) {
            double a = bench_rng_range(&rng, 0, 6.283185307179586), sp = bench_rng_range(&rng, 2.5, 8) * CELL;
            b->vx = sp * nt_compute_cos_sin(a).cosine;
            b->vy = sp * nt_compute_cos_sin(a).sine;
        } else {
            b->vx = bench_rng_range(&rng, -2, 2) * CELL;
            b->vy = bench_rng_range(&rng, 0, 2) * CELL;
        }
    }
    free(used);
    return 1;
}

/* Rain with bodies of mixed sizes, 0.2 to 4 cells across: each body takes a random
 * place where its box, grown by a tenth of a cell, covers only empty cells that no
 * body placed before covers (the largest are placed first, where room is easiest to
 * find); bodies are then created in the order they were placed. */
static int make_giants(scene *s, int n)
{
    uint64_t rng = 0x6769616E7473ull + (uint64_t)n; /* "giants" */
    /* Twice rain's area per body: the larger bodies need room to be placed. */
    int side = (int)ceil(256.0 * sqrt(2.0 * (double)n / 10000.0));
    if (!scene_init(s, "giants", "rain with bodies 0.2 to 4 cells across (half under a cell)", side, side, n)) return 0;
    rain_tiles(s->tiles, side, &rng);
    size_t ncells = (size_t)side * (size_t)side;
    uint8_t *used = calloc(ncells, 1);
    double *width = malloc((size_t)n * sizeof *width);
    if (!used || !width) {
        free(used);
        free(width);
        scene_free(s);
        return 0;
    }
    /* Widths log-uniform in [0.2, 4] cells, largest first. */
    for (int i = 0; i < n; i++) width[i] = 0.2 * exp(bench_rng_range(&rng, 0, log(20.0)));
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && width[j] > width[j - 1]; j--) {
            double t = width[j];
            width[j] = width[j - 1];
            width[j - 1] = t;
        }
    for (int i = 0; i < n; i++) {
        int circle = i & 1;
        double hx = 0.5 * width[i], hy = circle ? hx : fmin(2.0, fmax(0.1, hx * bench_rng_range(&rng, 0.5, 2.0)));
        int placed = 0;
        for (int tries = 0; tries < 4000 && !placed; tries++) {
            double x = bench_rng_range(&rng, hx + 0.1, side - hx - 0.1);
            double y = bench_rng_range(&rng, hy + 1.1, side - hy - 1.1);
            int x0 = (int)floor(x - hx - 0.1), x1 = (int)floor(x + hx + 0.1);
            int y0 = (int)floor(y - hy - 0.1), y1 = (int)floor(y + hy + 0.1);
            int ok = 1;
            for (int cy = y0; cy <= y1 && ok; cy++)
                for (int cx = x0; cx <= x1; cx++) {
                    size_t k = (size_t)cy * (size_t)side + (size_t)cx;
                    if (used[k] || s->tiles[k] != NT_TILE_EMPTY) {
                        ok = 0;
                        break;
                    }
                }
            if (!ok) continue;
            for (int cy = y0; cy <= y1; cy++)
                for (int cx = x0; cx <= x1; cx++) used[(size_t)cy * (size_t)side + (size_t)cx] = 1;
            scene_body *b = add_body(s, circle, hx * CELL, x * CELL, y * CELL, bench_rng_range(&rng, -2, 2) * CELL,
                                     bench_rng_range(&rng, 0, 2) * CELL);
            b->hy = hy * CELL;
            placed = 1;
        }
        if (!placed) {
            free(used);
            free(width);
            scene_free(s);
            return 0;
        }
    }
    free(used);
    free(width);
    s->steps = 120;
    return 1;
}

/* ---------- error scenes ---------- */

/* Fill column x with FULL from row y to row y1 inclusive. */
static void fill_down(scene *s, int x, int y, int y1)
{
    for (; y <= y1; y++) set_tile(s, x, y, NT_TILE_FULL);
}

/* Lanes of floors, each 8 rows tall, floors 220 cells long: flat FULL, flat HALFd,
 * then 45, 22 and 67 degree slopes going down to the right onto a lower flat. */
static int make_slide(scene *s)
{
    enum { W = 220, LANE = 8, NLANES = 5, PER_LANE = 8 };
    if (!scene_init(s, "slide", "ghost bumps: sliding along seams and slope-to-flat joins, no friction", W,
                    LANE * NLANES, NLANES * PER_LANE))
        return 0;
    s->tile_friction = 0;
    s->tile_bounce = 0;
    s->sleep = 0;
    s->steps = 200;
    for (int lane = 0; lane < NLANES; lane++) {
        int top = lane * LANE + 3; /* the upper floor row */
        int bottom = lane * LANE + LANE - 1;
        double floor_y = top * CELL; /* upper floor surface */
        double flat_from = -1e30;    /* x from which the floor is flat */
        int join = 12;               /* first slope column */
        if (lane == 0) {
            for (int x = 0; x < W; x++) fill_down(s, x, top, bottom);
        } else if (lane == 1) {
            for (int x = 0; x < W; x++) {
                set_tile(s, x, top, NT_TILE_HALFd);
                fill_down(s, x, top + 1, bottom);
            }
            floor_y = (top + 0.5) * CELL;
        } else {
            /* upper flat, slope cells, lower flat one (45, 22) or two (67) rows down */
            int drop = lane == 4 ? 2 : 1, width = lane == 3 ? 2 : 1;
            for (int x = 0; x < join; x++) fill_down(s, x, top, bottom);
            if (lane == 2) {
                set_tile(s, join, top, NT_TILE_45DEGpn);
            } else if (lane == 3) {
                set_tile(s, join, top, NT_TILE_22DEGpnB);
                set_tile(s, join + 1, top, NT_TILE_22DEGpnS);
            } else {
                set_tile(s, join, top, NT_TILE_67DEGpnS);
                set_tile(s, join, top + 1, NT_TILE_67DEGpnB);
            }
            for (int x = join; x < join + width; x++) fill_down(s, x, top + drop, bottom);
            for (int x = join + width; x < W; x++) fill_down(s, x, top + drop, bottom);
            flat_from = (join + width + 1) * CELL;
        }
        for (int k = 0; k < PER_LANE; k++) {
            int circle = k & 1;
            double half = (k & 2 ? 0.45 : 0.25) * CELL, speed = (k & 4 ? 8 : 3) * CELL;
            double x = (1.5 + (double)k) * CELL;
            scene_body *b = add_body(s, circle, half, x, floor_y - half, speed, 0);
            b->friction = 0;
            b->bounce = 0;
            b->collide_bodies = 0;
            b->role = ROLE_SLIDE;
            /* the flat part starts once the whole body is past the join */
            b->role_a = flat_from > -1e29 ? flat_from + half : flat_from;
            b->role_b = lane <= 1 ? 1 : 0;
        }
    }
    return 1;
}

static int make_bounce(scene *s)
{
    enum { W = 40, H = 12 };
    if (!scene_init(s, "bounce", "bounce heights (bounce 0.5) and energy (bounce 1) on a floor, no friction", W, H,
                    24))
        return 0;
    s->tile_friction = 0;
    s->tile_bounce = 0;
    s->restitution_threshold = 0;
    s->sleep = 0;
    s->steps = 200;
    for (int x = 0; x < W; x++) set_tile(s, x, H - 1, NT_TILE_FULL);
    double floor_y = (H - 1) * CELL;
    for (int k = 0; k < 24; k++) {
        int circle = k & 1, elastic = (k >> 1) & 1;
        double half = 0.3 * CELL, h0 = (3 + 3 * ((k >> 2) % 3)) * CELL;
        double rest_y = floor_y - half;
        scene_body *b = add_body(s, circle, half, (1.5 + 1.5 * k) * CELL, rest_y - h0, 0, 0);
        b->friction = 0;
        b->bounce = elastic ? 1 : 0.5;
        b->collide_bodies = 0;
        b->role = elastic ? ROLE_ENERGY : ROLE_BOUNCE;
        b->role_a = rest_y;
    }
    return 1;
}

static int make_gas(scene *s)
{
    enum { W = 32, N = 300 };
    if (!scene_init(s, "gas", "energy of 300 bodies bouncing (bounce 1) in a closed room, no gravity", W, W, N))
        return 0;
    uint64_t rng = 0x676173ull; /* "gas" */
    s->gy = 0;
    s->tile_friction = 0;
    s->tile_bounce = 1;
    s->restitution_threshold = 0;
    s->sleep = 0;
    s->steps = 200;
    for (int i = 0; i < N; i++) {
        int cx = 1 + 1 + (i % 20) * 3 / 2, cy = 4 + (i / 20) * 3 / 2; /* spread over the room */
        double half = bench_rng_range(&rng, 0.2, 0.35) * CELL;
        double a = bench_rng_range(&rng, 0, 6.283185307179586), sp = bench_rng_range(&rng, 2, 6) * CELL;
        scene_body *b = add_body(s, i & 1, half, (cx + 0.5) * CELL, (cy + 0.5) * CELL, sp * nt_compute_cos_sin(a).cosine, sp * nt_compute_cos_sin(a).sine);
        b->friction = 0;
        b->bounce = 1;
        b->role = ROLE_ENERGY;
        b->role_a = 0;
    }
    return 1;
}

/* One slope lane: tiles of a straight slope going down to the right from cell
 * (x0, y0), `len` slope cells across, FULL below; mirrored in x when `mirror`.
 * kind 0: 45 degrees, 1: 22 (26.57), 2: 67 (63.43). */
static void slope_lane(scene *s, int x0, int y0, int kind, int len, int mirror, int bottom)
{
    for (int i = 0; i < len; i++) {
        int x = x0 + i, tiles[2] = {0, 0}, rows[2] = {0, 0}, n = 0;
        if (kind == 0) {
            tiles[0] = NT_TILE_45DEGpn, rows[0] = y0 + i, n = 1;
        } else if (kind == 1) {
            tiles[0] = i % 2 ? NT_TILE_22DEGpnS : NT_TILE_22DEGpnB, rows[0] = y0 + i / 2, n = 1;
        } else {
            tiles[0] = NT_TILE_67DEGpnS, rows[0] = y0 + 2 * i;
            tiles[1] = NT_TILE_67DEGpnB, rows[1] = y0 + 2 * i + 1, n = 2;
        }
        int mx = mirror ? (2 * x0 + len - 1) - x : x;
        for (int k = 0; k < n; k++) set_tile(s, mx, rows[k], mirror ? tiles[k] + 1 : tiles[k]); /* pn+1 = nn */
        fill_down(s, mx, rows[n - 1] + 1, bottom);
    }
}

static int make_incline(scene *s)
{
    /* kind: 45, 22, 67; horizontal slope length in cells; mu sliding; mu sticking */
    static const int len[3] = {14, 24, 8};
    static const double mu_slide[3] = {0.5, 0.3, 1.0}, mu_stick[3] = {1.3, 0.7, 2.5};
    static const double dx[3] = {1, 2, 1}, dy[3] = {1, 1, 2}; /* slope direction, unnormalised */
    enum { LANE_W = 30, H = 24 };
    if (!scene_init(s, "incline", "Coulomb slopes 22/45/67 and mirrors: sliding acceleration, sticking drift",
                    6 * LANE_W, H, 6 * 4))
        return 0;
    s->coulomb = 1;
    s->tile_friction = 1; /* the pair's friction sqrt(1 * mu^2) is the body's mu */
    s->tile_bounce = 0;
    s->sleep = 0;
    s->warm_steps = 10;
    s->rest_from = 10;
    s->steps = 50;
    for (int lane = 0; lane < 6; lane++) {
        int kind = lane % 3, mirror = lane / 3, x0 = lane * LANE_W + 3, y0 = 2;
        slope_lane(s, x0, y0, kind, len[kind], mirror, H - 1);
        double norm = sqrt(dx[kind] * dx[kind] + dy[kind] * dy[kind]);
        double ux = dx[kind] / norm, uy = dy[kind] / norm; /* down the slope, to the right */
        double nx = uy, ny = -ux;                          /* outward normal */
        double sx = x0 * CELL, sy = y0 * CELL;             /* top of the slope */
        if (mirror) {
            ux = -ux;
            nx = -nx;
            sx = (x0 + len[kind]) * CELL;
        }
        double sin_t = uy, cos_t = fabs(ux);
        for (int k = 0; k < 4; k++) {
            int circle = k & 1, stick = k >> 1;
            double half = 0.3 * CELL, mu = stick ? mu_stick[kind] : mu_slide[kind];
            double along = (1.0 + 2.5 * k) * CELL;
            double support = circle ? half : half * (fabs(nx) + fabs(ny));
            double gap = 0.002 * CELL;
            scene_body *b = add_body(s, circle, half, sx + ux * along + nx * (support + gap),
                                     sy + uy * along + ny * (support + gap), 0, 0);
            b->friction = mu * mu;
            b->bounce = 0;
            b->collide_bodies = 0;
            if (stick) {
                b->role = ROLE_REST;
            } else {
                b->role = ROLE_INCLINE;
                b->role_a = ux;
                b->role_b = uy;
                b->accel = GRAVITY * (sin_t - mu * cos_t);
            }
        }
    }
    return 1;
}

static int make_flight(scene *s)
{
    enum { W = 64, N = 100 };
    if (!scene_init(s, "flight", "free flight through an empty map: the parabola", W, W, N)) return 0;
    uint64_t rng = 0x666C69676874ull; /* "flight" */
    s->sleep = 0;
    s->steps = 40;
    for (int i = 0; i < N; i++) {
        /* one draw per statement: the order of evaluation of arguments is unspecified */
        double half = bench_rng_range(&rng, 0.2, 0.4) * CELL;
        double x = bench_rng_range(&rng, 24, 40) * CELL;
        double y = bench_rng_range(&rng, 24, 40) * CELL;
        double vx = bench_rng_range(&rng, -10, 10) * CELL;
        double vy = bench_rng_range(&rng, -15, 0) * CELL;
        scene_body *b = add_body(s, i & 1, half, x, y, vx, vy);
        b->collide_bodies = 0;
        b->role = ROLE_FLIGHT;
    }
    return 1;
}

static int make_rest(scene *s)
{
    enum { W = 48, H = 16, COLS = 8, TALL = 8, CIRCLES = 16 };
    if (!scene_init(s, "rest", "jitter: 8 stacks of 8 boxes and 16 circles on a floor (Coulomb 0.5, sleep off)", W,
                    H, COLS * TALL + CIRCLES))
        return 0;
    s->coulomb = 1;
    s->tile_friction = 0.5;
    s->tile_bounce = 0;
    s->sleep = 0;
    s->warm_steps = 80;
    s->rest_from = 80;
    s->steps = 200;
    for (int x = 0; x < W; x++) set_tile(s, x, H - 1, NT_TILE_FULL);
    double floor_y = (H - 1) * CELL, half = 0.45 * CELL, gap = 0.01 * CELL;
    for (int c = 0; c < COLS; c++)
        for (int k = 0; k < TALL; k++) {
            scene_body *b = add_body(s, 0, half, (2.5 + 2 * c) * CELL, floor_y - half - k * (2 * half + gap), 0, 0);
            b->friction = 0.5;
            b->bounce = 0;
            b->role = ROLE_REST;
        }
    for (int k = 0; k < CIRCLES; k++) {
        scene_body *b = add_body(s, 1, half, (20.5 + 1.5 * k) * CELL, floor_y - half, 0, 0);
        b->friction = 0.5;
        b->bounce = 0;
        b->role = ROLE_REST;
    }
    return 1;
}

static int make_tunnel(scene *s)
{
    enum { BLOCK = 9, PER_ROW = 6, DIRS = 8, SPEEDS = 3 };
    int rows = (NT_TILE_COUNT - 1 + PER_ROW - 1) / PER_ROW;
    if (!scene_init(s, "tunnel", "bodies fired at 2..4 cells/step at each solid tile from 8 directions", PER_ROW * BLOCK,
                    rows * BLOCK, (NT_TILE_COUNT - 1) * DIRS * SPEEDS))
        return 0;
    s->gy = 0;
    s->sleep = 0;
    s->steps = 40;
    for (int t = 1; t < NT_TILE_COUNT; t++) {
        int bx = ((t - 1) % PER_ROW) * BLOCK + BLOCK / 2, by = ((t - 1) / PER_ROW) * BLOCK + BLOCK / 2;
        set_tile(s, bx, by, t);
        for (int d = 0; d < DIRS; d++)
            for (int v = 0; v < SPEEDS; v++) {
                double a = d * 6.283185307179586 / DIRS + 0.1 * v; /* a little off the axes */
                double cx = (bx + 0.5) * CELL, cy = (by + 0.5) * CELL;
                double speed = (2 + v) * CELL / DT; /* cells per step */
                double half = (v % 2 ? 0.1 : 0.25) * CELL;
                scene_body *b = add_body(s, (d + v) & 1, half, cx + 3.5 * CELL * nt_compute_cos_sin(a).cosine, cy + 3.5 * CELL * nt_compute_cos_sin(a).sine,
                                         -speed * nt_compute_cos_sin(a).cosine, -speed * nt_compute_cos_sin(a).sine);
                b->collide_bodies = 0;
            }
    }
    return 1;
}

/* free: an empty map, slow drift; touching: every body rests on a floor. */
static int make_skip(scene *s, int n, int touching)
{
    int side = (int)ceil(sqrt(2.0 * n)) + 2;
    if (!scene_init(s, touching ? "touching" : "free",
                    touching ? "bodies resting on floors, tiles only" : "bodies drifting through an empty map, tiles only",
                    side, side, n))
        return 0;
    uint64_t rng = 0x736B6970ull; /* "skip" */
    s->sleep = 0;
    s->steps = 120;
    if (!touching) s->gy = 0;
    for (int y = 2; touching && y < side; y += 2)
        for (int x = 0; x < side; x++) set_tile(s, x, y, NT_TILE_FULL);
    int per_row = side - 2;
    for (int i = 0; i < n; i++) {
        int x = 1 + i % per_row, row = i / per_row;
        double half = bench_rng_range(&rng, 0.2, 0.4) * CELL;
        double y = touching ? (2.0 * row + 2) * CELL - half : (row + 0.5) * CELL;
        double vx = touching ? 0 : bench_rng_range(&rng, -0.5, 0.5) * CELL;
        scene_body *b = add_body(s, i & 1, half, (x + 0.5) * CELL, y, vx, 0);
        b->collide_bodies = 0;
        b->bounce = 0;
    }
    return 1;
}

int scene_default_bodies(const char *name)
{
    if (strcmp(name, "pile") == 0 || strcmp(name, "asleep") == 0) return 3000;
    if (strcmp(name, "giants") == 0) return 2000;
    if (strcmp(name, "rain") == 0 || strcmp(name, "particles") == 0 || strcmp(name, "sparse") == 0 ||
        strcmp(name, "free") == 0 || strcmp(name, "touching") == 0)
        return 10000;
    return 0;
}

int scene_make(const char *name, int n, scene *out)
{
    static const char *const rain_summary =
        "bodies falling into a map of ledges of every tile shape, settling (side grows as sqrt(bodies))";
    int nn = n > 0 ? n : scene_default_bodies(name);
    if (strcmp(name, "rain") == 0 || strcmp(name, "particles") == 0) {
        int side = (int)ceil(256.0 * sqrt((double)nn / 10000.0));
        int particles = name[0] == 'p';
        if (!make_world_scene(out, particles ? "particles" : "rain",
                              particles ? "rain with every body colliding with tiles only" : rain_summary, KIND_RAIN,
                              side, nn, !particles))
            return 0;
        out->steps = 120;
        return 1;
    }
    if (strcmp(name, "giants") == 0) return make_giants(out, nn);
    if (strcmp(name, "sparse") == 0) {
        if (!make_world_scene(out, "sparse", "bodies flying straight through an almost empty 256 x 256 map",
                              KIND_SPARSE, 256, nn, 1))
            return 0;
        out->steps = 120;
        return 1;
    }
    if (strcmp(name, "pile") == 0 || strcmp(name, "asleep") == 0) {
        int asleep = name[0] == 'a';
        if (!make_world_scene(out, asleep ? "asleep" : "pile",
                              asleep ? "the pile once every body sleeps"
                                     : "a 64-cell-wide container full of bodies (Coulomb 0.5), sleep off",
                              KIND_PILE, 64, nn, 1))
            return 0;
        out->sleep = asleep;
        out->warm_steps = 40;
        out->until_asleep = asleep ? 4000 : 0;
        out->steps = asleep ? 200 : 60;
        /* An asleep step is a microsecond or so: time at least 20 ms of them. */
        if (asleep) out->min_timed_ms = 20;
        return 1;
    }
    if (strcmp(name, "slide") == 0) return make_slide(out);
    if (strcmp(name, "bounce") == 0) return make_bounce(out);
    if (strcmp(name, "gas") == 0) return make_gas(out);
    if (strcmp(name, "incline") == 0) return make_incline(out);
    if (strcmp(name, "flight") == 0) return make_flight(out);
    if (strcmp(name, "rest") == 0) return make_rest(out);
    if (strcmp(name, "tunnel") == 0) return make_tunnel(out);
    if (strcmp(name, "free") == 0 || strcmp(name, "touching") == 0) return make_skip(out, nn, name[0] == 't');
    return 0;
}
