/* Embedding ntile: a small headless platformer built on the character mover. A level
 * built in code (a plateau with a 45-degree ramp down, a half-tile step, a lift going
 * up and down, a one-way platform, a pit), a 1 x 2-cell player and a script that plays
 * it at 60 Hz. Build against an installed ntile with
 *
 *   cc -std=c11 embed.c $(pkg-config --cflags --libs ntile) -o embed
 *
 * It prints a line per part of the script as it is done, then its verdict, either
 * "platformer: reached the goal at tick N, y Y, on_floor 1, snapped S, stepped up U"
 * (exit 0) or "platformer: gave up at tick N before ..." (exit 1). `make check-install`
 * builds it against a staged install and checks that line: on the floor (top y = 336)
 * the player's centre is at y = 312. Same output in float and double builds.
 */
#include <stdbool.h>
#include <stdio.h>
#include <ntile/ntile.h>

#define CELL 24 /* world units per cell */
enum { W = 44, H = 16, FLOOR = 14, MAX_TICKS = 1500 };
static const nt_real RUN = 150, JUMP = 400, GRAVITY = 900; /* units/s, units/s^2 */

/* The lift rests 1 s at the bottom, rises 2 s, rests 1 s at the top, comes down 2 s:
 * its velocity is a function of the tick, so the game sets it before every step. */
enum { LIFT_PERIOD = 360 };
static const nt_real LIFT_SPEED = 54; /* 4.5 cells in 2 s */
static nt_real lift_velocity(int tick)
{
    int t = tick % LIFT_PERIOD;
    return t < 60 ? 0 : t < 180 ? -LIFT_SPEED : t < 240 ? 0 : LIFT_SPEED;
}

/* The script: keys held (run right, jump, down to drop) until a condition holds. It
 * knows the lift's timetable, as a player watching it would. */
enum { UNTIL_X, UNTIL_LIFT_DOWN, UNTIL_LIFT_UP, UNTIL_LANDED };
static const struct {
    const char *what;
    bool run, jump, drop;
    int until;
    double x_cells; /* for UNTIL_X: the player's centre reaches this */
} script[] = {
    {"down the ramp and up the step", 1, 0, 0, UNTIL_X, 17.25},
    {"waited for the lift", 0, 0, 0, UNTIL_LIFT_DOWN, 0},
    {"stepped onto the lift", 1, 0, 0, UNTIL_X, 19},
    {"rode it up", 0, 0, 0, UNTIL_LIFT_UP, 0},
    {"jumped to the one-way platform", 1, 1, 0, UNTIL_LANDED, 0},
    {"dropped through it", 0, 0, 1, UNTIL_LANDED, 0},
    {"ran to the pit", 1, 0, 0, UNTIL_X, 29.5},
    {"jumped over it", 1, 1, 0, UNTIL_LANDED, 0},
    {"ran to the goal", 1, 0, 0, UNTIL_X, 40},
};
enum { STEPS = sizeof script / sizeof script[0] };

static void build_level(nt_world *w)
{
    for (int x = 0; x < W; x++)
        if (x < 31 || x > 33) /* the pit: cells 31-33 */
            for (int y = FLOOR; y < H; y++) nt_world_set_tile(w, x, y, NT_TILE_FULL);
    for (int x = 0; x < 6; x++) /* the plateau, 3 cells high */
        for (int y = FLOOR - 3; y < FLOOR; y++) nt_world_set_tile(w, x, y, NT_TILE_FULL);
    for (int k = 0; k < 3; k++) { /* the ramp down from it: 45-degree tiles, full below */
        nt_world_set_tile(w, 6 + k, FLOOR - 3 + k, NT_TILE_45DEGpn);
        for (int y = FLOOR - 2 + k; y < FLOOR; y++) nt_world_set_tile(w, 6 + k, y, NT_TILE_FULL);
    }
    for (int x = 13; x < 18; x++) nt_world_set_tile(w, x, FLOOR - 1, NT_TILE_HALFd); /* the step */
    for (int x = 22; x < 28; x++) { /* the one-way platform: its top at row 9 */
        nt_world_set_tile(w, x, 9, NT_TILE_HALFu);
        nt_world_set_cell_flags(w, x, 9, NT_CELL_ONE_WAY);
    }
}

int main(void)
{
    if (nt_real_size() != (int)sizeof(nt_real)) {
        fprintf(stderr, "embed: compiled with a different NT_DOUBLE setting than libntile\n");
        return 1;
    }
    nt_world_def wd = nt_default_world_def();
    wd.map.width = W;
    wd.map.height = H;
    wd.map.cell_size = CELL;
    wd.gravity = nt_v2(0, GRAVITY); /* for dynamic bodies; the player falls by the script's own */
    nt_world *world;
    nt_status st = nt_world_create(&wd, &world);
    if (st != NT_OK) {
        fprintf(stderr, "embed: nt_world_create: %s\n", nt_status_string(st));
        return 1;
    }
    build_level(world);

    /* The lift: a kinematic 2 x 0.5-cell body; at the bottom its top is the step's top. */
    nt_body_def bd = nt_default_body_def();
    bd.type = NT_BODY_KINEMATIC;
    bd.shape = nt_shape_aabb(CELL, CELL / 4);
    bd.position = nt_v2(19 * CELL, (FLOOR - 0.25) * CELL);
    nt_body_id lift, player;
    if ((st = nt_body_create(world, &bd, &lift)) != NT_OK) goto fail;
    /* The player: a 1 x 2-cell body on the plateau, made a character with the defaults
     * (50-degree floors, half-cell step-up and floor snap, stop on slopes). */
    bd = nt_default_body_def();
    bd.shape = nt_shape_aabb(CELL / 2, CELL);
    bd.position = nt_v2(2.5 * CELL, (FLOOR - 4) * CELL - 1);
    if ((st = nt_body_create(world, &bd, &player)) != NT_OK) goto fail;
    nt_character_def cd = nt_default_character_def();
    if ((st = nt_character_create(world, player, &cd)) != NT_OK) goto fail;

    const nt_real dt = (nt_real)1 / 60;
    nt_vec2 v = nt_v2(0, 0);     /* the player's velocity, kept from move to move */
    nt_character_result r = {0}; /* the last move's, for on_floor */
    int step = 0, tick, snaps = 0, steps_up = 0;
    for (tick = 1; tick <= MAX_TICKS && step < STEPS; tick++) {
        /* The game's rules, not the engine's: run speed, gravity, jump, drop. */
        v.x = script[step].run ? RUN : 0;
        v.y += GRAVITY * dt;
        if (script[step].jump && r.on_floor) v.y = -JUMP;
        if (script[step].drop) nt_character_drop_through(world, player);
        nt_body_set_velocity(world, lift, nt_v2(0, lift_velocity(tick)));
        /* Move first (it rides the lift by the lift's velocity), then step the world
         * (which moves the lift by as much, and never the character). */
        if ((st = nt_character_move(world, player, v, dt, &r)) != NT_OK) goto fail;
        v = r.velocity; /* slid along what it met: no vertical part on a floor */
        snaps += r.snapped;       /* kept on the ramp going down */
        steps_up += r.stepped_up; /* onto the step without a jump */
        if ((st = nt_world_step(world, dt)) != NT_OK) goto fail;

        int t = tick % LIFT_PERIOD;
        bool done = script[step].until == UNTIL_X ? r.position.x >= script[step].x_cells * CELL
                  : script[step].until == UNTIL_LIFT_DOWN ? t < 60
                  : script[step].until == UNTIL_LIFT_UP ? t >= 180 && t < 240
                  : r.landed;
        if (done) {
            printf("tick %4d  x %6.1f y %6.1f  %s%s\n", tick, r.position.x, r.position.y, script[step].what,
                   r.on_floor ? "" : " (in the air)");
            step++;
        }
    }
    tick--;
    bool ok = step == STEPS && r.on_floor;
    if (ok)
        printf("platformer: reached the goal at tick %d, y %.2f, on_floor %d, snapped %d, stepped up %d\n", tick,
               r.position.y, r.on_floor, snaps, steps_up);
    else
        printf("platformer: gave up at tick %d before \"%s\", x %.1f y %.1f, on_floor %d\n", tick,
               step < STEPS ? script[step].what : "the end", r.position.x, r.position.y, r.on_floor);
    nt_world_destroy(world);
    return ok ? 0 : 1;
fail:
    fprintf(stderr, "embed: %s\n", nt_status_string(st));
    nt_world_destroy(world);
    return 1;
}
