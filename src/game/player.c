/* The player controller, in the spirit of N's ninja, on the engine's character mover
 * (character.h): a circle that runs with ground acceleration and skid, steers in the
 * air, jumps higher while the button is held (gravity is scaled down while it rises),
 * slides down walls it presses into, jumps off them, and drops through one-way floors
 * (down + jump).
 *
 * The controller keeps its own velocity, relative to what the player stands on: the
 * mover carries it with a moving platform and gives the platform's velocity back when
 * it leaves. Gravity is the world's, applied here (the world step does not move a
 * character). Running along a floor keeps a run speed of its own, so that a slope
 * does not eat it; the mover keeps the player on the floor (snap, stop on slope). */
#include <math.h>
#include <string.h>
#include "internal.h"

/* Move v toward target by at most step. */
static nt_real approach(nt_real v, nt_real target, nt_real step)
{
    if (v < target) return v + step < target ? v + step : target;
    if (v > target) return v - step > target ? v - step : target;
    return v;
}

static nt_vec2 add(nt_vec2 a, nt_vec2 b) { return nt_v2(a.x + b.x, a.y + b.y); }

/* The filter of the player's own probes: everything but itself. */
static nt_query_filter self_filter(nt_body_id self)
{
    nt_query_filter f = nt_default_query_filter();
    f.ignore_count = 1;
    f.ignore[0] = self;
    return f;
}

/* A wall within a hundredth of a cell on side dir (-1 left, +1 right)? Walls are the
 * surfaces the mover calls walls: steeper than its floor angle. */
static bool wall_at(const nt_game *g, nt_body_id id, nt_vec2 pos, int dir)
{
    nt_world_shape_hit h;
    nt_vec2 d = nt_v2((nt_real)dir * g->cell * (nt_real)0.01, 0);
    if (!nt_world_cast_shape(g->world, pos, nt_body_get_shape(g->world, id), d, self_filter(id), &h)) return false;
    nt_real c = (nt_real)nt_compute_cos_sin((double)g->def.player.mover.floor_angle).cosine;
    return h.normal.x * (nt_real)dir < 0 && -h.normal.y < c && h.normal.y < c;
}

void nt__player_sense(nt_game *g)
{
    nt_world *w = g->world;
    nt_body_id id = g->bodies[g->player_record].id;
    player_state *ps = &g->ps;
    nt_vec2 pos = nt_body_get_position(w, id);
    ps->on_floor = ps->move.on_floor;
    ps->wall_left = wall_at(g, id, pos, -1);
    ps->wall_right = wall_at(g, id, pos, 1);
    if (ps->on_floor) ps->since_floor = 0;
    else if (ps->since_floor < 1000000) ps->since_floor++;
    if (ps->wall_left || ps->wall_right) {
        ps->since_wall = 0;
        ps->wall_away = ps->wall_left ? 1 : -1;
    } else if (ps->since_wall < 1000000) {
        ps->since_wall++;
    }
    /* Readers of the body (nt_body_get_velocity) see the player's velocity in the
     * world's frame; a velocity set there by the game's user replaces the
     * controller's at the next tick (nt__player_control compares). */
    ps->shown = add(ps->vel, ps->on_floor ? ps->move.floor_velocity : nt_v2(0, 0));
    /* Only when it differs (setting one wakes what the player touches; the step sets a
     * character's to zero, so a player at rest on a still floor is left alone, and
     * one that moves keeps what it touches awake anyway, as any moving kinematic body). */
    nt_vec2 now = nt_body_get_velocity(w, id);
    if (memcmp(&now, &ps->shown, sizeof now) != 0) nt_body_set_velocity(w, id, ps->shown);
}

/* The tile bounce behind a surface the move met (normal n), by a short cast back into it. */
static nt_real tile_bounce(const nt_game *g, nt_body_id id, nt_vec2 n)
{
    nt_world_shape_hit h;
    nt_query_filter f = self_filter(id);
    nt_vec2 d = nt_v2(-n.x * g->cell * (nt_real)0.01, -n.y * g->cell * (nt_real)0.01);
    f.mask = 0; /* tiles only */
    nt_vec2 pos = nt_body_get_position(g->world, id);
    if (!nt_world_cast_shape(g->world, pos, nt_body_get_shape(g->world, id), d, f, &h) || !nt_body_id_is_null(h.body))
        return 0;
    return nt_world_get_material(g->world, nt_world_get_cell_material(g->world, h.cell_x, h.cell_y)).bounce;
}

/* N's ninja lands softly, but tiles bouncier than the threshold (launch pads) throw it
 * back: the part of the velocity `in` that went into a surface the move met (a floor
 * when landing, a wall or a ceiling) comes back times the tile's bounce. */
static nt_vec2 launch(const nt_game *g, nt_body_id id, nt_vec2 in, nt_vec2 out, const nt_character_result *r, bool ground)
{
    const nt_vec2 normals[3] = {r->floor_normal, r->wall_normal, r->ceiling_normal};
    const bool met[3] = {r->on_floor && !ground, r->on_wall, r->on_ceiling}; /* a floor: when landing on it */
    /* The world's restitution threshold (the level's world scales it with the cell):
     * slower impacts, a player standing on a pad included, do not bounce. */
    nt_real slow = nt_default_world_def().restitution_threshold * g->cell / 24;
    for (int k = 0; k < 3; k++) {
        nt_vec2 n = normals[k];
        nt_real into = -(in.x * n.x + in.y * n.y);
        if (!met[k] || into <= slow) continue;
        nt_real e = tile_bounce(g, id, n);
        if (e <= g->def.player.bouncy_threshold) continue;
        nt_real now = out.x * n.x + out.y * n.y;
        out = nt_v2(out.x + (e * into - now) * n.x, out.y + (e * into - now) * n.y);
    }
    return out;
}

void nt__player_control(nt_game *g, uint32_t keys, nt_real dt)
{
    const nt_player_def *pd = &g->def.player;
    nt_world *w = g->world;
    nt_body_id id = g->bodies[g->player_record].id;
    const nt_real c = g->cell;
    player_state *ps = &g->ps;
    if (g->dead) keys = 0; /* a dead player is not steered: it falls and comes to rest */
    uint32_t pressed = keys & ~g->prev_keys;
    int dir = ((keys & NT_INPUT_RIGHT) ? 1 : 0) - ((keys & NT_INPUT_LEFT) ? 1 : 0);
    nt_vec2 grav = nt_world_get_gravity(w);
    bool ground = ps->on_floor;

    /* A velocity set on the body from outside since the last tick wins. */
    nt_vec2 bv = nt_body_get_velocity(w, id);
    if (memcmp(&bv, &ps->shown, sizeof bv) != 0) {
        ps->vel = nt_v2(bv.x - (ground ? ps->move.floor_velocity.x : 0), bv.y - (ground ? ps->move.floor_velocity.y : 0));
        ps->run = ps->vel.x;
    }
    nt_vec2 v = ps->vel;

    if (ground) {
        /* Along the floor at the run speed, which a slope does not change. */
        nt_real s = ps->run;
        nt_real target = (nt_real)dir * pd->run_speed * c;
        if (dir == 0) s = approach(s, 0, pd->ground_decel * c * dt);
        else if (s * (nt_real)dir < 0) s = approach(s, target, pd->skid_decel * c * dt);
        else if (s * (nt_real)dir < pd->run_speed * c) s = approach(s, target, pd->ground_accel * c * dt);
        else s = approach(s, target, pd->ground_decel * c * dt);
        v = nt_v2(s, 0);
        ps->jumping = false;
    } else {
        if (dir != 0) {
            if (v.x * (nt_real)dir < pd->run_speed * c)
                v.x = approach(v.x, (nt_real)dir * pd->run_speed * c, pd->air_accel * c * dt);
        } else {
            v.x = approach(v.x, 0, pd->air_decel * c * dt);
        }
    }

    int grace = (int)(pd->grace_time / dt + (nt_real)0.5);
    if (pressed & NT_INPUT_JUMP) {
        if (ground && (keys & NT_INPUT_DOWN)) {
            /* Down + jump: through the one-way floor underfoot (nothing on a solid one). */
            nt_character_drop_through(w, id);
        } else if (ps->since_floor <= grace) {
            v.y = -pd->jump_speed * c;
            ps->jumping = true;
            ps->since_floor = 1000000;
        } else if (ps->since_wall <= grace) {
            v.x = (nt_real)ps->wall_away * pd->wall_jump_speed_x * c;
            v.y = -pd->wall_jump_speed_y * c;
            ps->jumping = true;
            ps->since_wall = 1000000;
        }
    }
    if (ps->jumping && (!(keys & NT_INPUT_JUMP) || v.y >= 0)) ps->jumping = false;
    /* Gravity, scaled while a held jump rises (variable height). */
    nt_real gs = ps->jumping ? pd->jump_gravity_scale : 1;
    v = nt_v2(v.x + grav.x * gs * dt, v.y + grav.y * gs * dt);
    bool into_wall = (dir < 0 && ps->wall_left) || (dir > 0 && ps->wall_right);
    if (!ground && into_wall && v.y > pd->wall_slide_speed * c) v.y = pd->wall_slide_speed * c;
    if (v.y > pd->max_fall_speed * c) v.y = pd->max_fall_speed * c;

    nt_character_result r;
    if (nt_character_move(w, id, v, dt, &r) != NT_OK) return; /* cannot fail on the game's own player */
    nt_vec2 out = launch(g, id, v, r.velocity, &r, ground);
    /* Thrown off the floor by a launch pad: in the air from now on. */
    if (r.on_floor && (out.x != r.velocity.x || out.y != r.velocity.y) &&
        out.x * r.floor_normal.x + out.y * r.floor_normal.y > 0)
        r.on_floor = false;
    /* The run goes on along floors, up and down slopes, unless a wall stopped it. */
    if (r.on_floor && ground && !r.stepped_up && r.on_wall && r.wall_normal.x * v.x < 0) ps->run = 0;
    else if (r.on_floor && ground) ps->run = v.x;
    else ps->run = out.x;
    ps->vel = out;
    ps->move = r;
}

typedef struct touch_probe {
    nt_body_id self;
    nt_vec2 pos;
    nt_shape shape; /* the player's, grown by the margin */
    nt_body_id *out;
    int n, cap;
    const nt_world *world;
} touch_probe;

static bool touch_fn(nt_body_id id, void *ctx)
{
    touch_probe *t = ctx;
    if (nt_body_id_equals(id, t->self) || nt_body_get_type(t->world, id) == NT_BODY_DYNAMIC) return true;
    if (!nt_collide_shapes(t->pos, t->shape, nt_body_get_position(t->world, id), nt_body_get_shape(t->world, id), NULL))
        return true;
    if (t->n < t->cap) t->out[t->n] = id;
    t->n++;
    return true;
}

int nt__player_touches(const nt_game *g, nt_body_id *out, int cap)
{
    const nt_world *w = g->world;
    nt_body_id id = g->bodies[g->player_record].id;
    touch_probe t;
    t.self = id;
    t.pos = nt_body_get_position(w, id);
    t.shape = nt_body_get_shape(w, id);
    nt_real m = g->cell * (nt_real)0.01;
    t.shape.half = nt_v2(t.shape.half.x + m, t.shape.half.y + m);
    t.out = out;
    t.n = 0;
    t.cap = cap;
    t.world = w;
    nt_vec2 lo = nt_v2(t.pos.x - t.shape.half.x, t.pos.y - t.shape.half.y);
    nt_vec2 hi = nt_v2(t.pos.x + t.shape.half.x, t.pos.y + t.shape.half.y);
    nt_world_overlap_aabb(w, lo, hi, nt_default_query_filter(), touch_fn, &t);
    return t.n;
}
