/* The player controller, in the spirit of N's ninja: a circle that runs with ground
 * acceleration and skid, steers in the air, jumps higher while the button is held
 * (gravity is scaled down while it rises), slides down walls it presses into and
 * jumps off them.
 *
 * The player's own material has no friction and no bounce: the controller is its
 * friction. It reads the engine's tile-contact summary of the last step (floor
 * normal, walls) and, for floors made of bodies (a moving platform, a crate), a
 * small overlap query under its feet: the summary covers tiles only. */
#include <math.h>
#include "internal.h"

/* Move v toward target by at most step. */
static nt_real approach(nt_real v, nt_real target, nt_real step)
{
    if (v < target) return v + step < target ? v + step : target;
    if (v > target) return v - step > target ? v - step : target;
    return v;
}

typedef struct probe {
    nt_body_id self;
    nt_body_id found;
    nt_real self_y;
    const nt_world *world;
} probe;

static bool probe_fn(nt_body_id id, void *ctx)
{
    probe *p = ctx;
    if (nt_body_id_equals(id, p->self)) return true;
    /* Only bodies below the player's centre carry it. */
    if (nt_body_get_position(p->world, id).y <= p->self_y) return true;
    p->found = id;
    return false;
}

/* A body under the player's feet (null when none). */
static nt_body_id body_floor(const nt_game *g, nt_body_id self, nt_vec2 pos, nt_real r)
{
    probe p;
    p.self = self;
    p.found = nt_null_body_id();
    p.self_y = pos.y;
    p.world = g->world;
    nt_vec2 lo = nt_v2(pos.x - r * (nt_real)0.6, pos.y + r * (nt_real)0.5);
    nt_vec2 hi = nt_v2(pos.x + r * (nt_real)0.6, pos.y + r + g->cell * (nt_real)0.02);
    nt_world_overlap_aabb(g->world, lo, hi, nt_default_query_filter(), probe_fn, &p);
    return p.found;
}

void nt__player_sense(nt_game *g)
{
    nt_world *w = g->world;
    nt_body_id id = g->bodies[g->player_record].id;
    player_state *ps = &g->ps;
    nt_body_tile_contacts *tc = &ps->tc;
    if (nt_body_get_tile_contacts(w, id, tc) != NT_OK) {
        tc->count = 0;
        tc->on_floor = tc->wall_left = tc->wall_right = false;
    }
    ps->normal = tc->floor_normal;
    ps->on_floor = tc->on_floor;
    ps->ground = body_floor(g, id, nt_body_get_position(w, id), g->def.player.radius * g->cell);
    ps->ground_v = nt_body_id_is_null(ps->ground) ? nt_v2(0, 0) : nt_body_get_velocity(w, ps->ground);
    if (!nt_body_id_is_null(ps->ground)) {
        if (!ps->on_floor) ps->normal = nt_v2(0, -1);
        ps->on_floor = true;
    }
    ps->wall_left = tc->wall_left;
    ps->wall_right = tc->wall_right;
    if (ps->on_floor) ps->since_floor = 0;
    else if (ps->since_floor < 1000000) ps->since_floor++;
    if (tc->wall_left || tc->wall_right) {
        ps->since_wall = 0;
        ps->wall_away = tc->wall_left ? 1 : -1;
    } else if (ps->since_wall < 1000000) {
        ps->since_wall++;
    }
}

void nt__player_control(nt_game *g, uint32_t keys, nt_real dt)
{
    const nt_player_def *pd = &g->def.player;
    nt_world *w = g->world;
    nt_body_id id = g->bodies[g->player_record].id;
    const nt_real c = g->cell;
    uint32_t pressed = keys & ~g->prev_keys;
    int dir = ((keys & NT_INPUT_RIGHT) ? 1 : 0) - ((keys & NT_INPUT_LEFT) ? 1 : 0);
    nt_vec2 v = nt_body_get_velocity(w, id);
    nt_vec2 grav = nt_world_get_gravity(w);
    player_state *ps = &g->ps;
    const nt_body_tile_contacts *tc = &ps->tc;
    bool ground = ps->on_floor;
    nt_vec2 n = ps->normal;
    /* The player's speed is taken relative to the carrier's velocity of the last step
     * and given back relative to its velocity for the coming step (paths set theirs
     * before the controller runs), so that the rider keeps up without a tick of lag. */
    nt_vec2 ground_v = nt_body_is_valid(w, ps->ground) ? nt_body_get_velocity(w, ps->ground) : nt_v2(0, 0);
    nt_vec2 ground_was = ps->ground_v;

    /* N's ninja lands softly: the bounce of ordinary tiles is taken back, but tiles
     * bouncier than the threshold (launch pads) keep it. */
    for (int i = 0; i < tc->count; i++) {
        const nt_tile_contact *k = &tc->contacts[i];
        nt_material m = nt_world_get_material(w, nt_world_get_cell_material(w, k->cell_x, k->cell_y));
        nt_real away = v.x * k->normal.x + v.y * k->normal.y;
        if (m.bounce <= pd->bouncy_threshold && away > 0) {
            v.x -= away * k->normal.x;
            v.y -= away * k->normal.y;
        }
    }

    if (ground) {
        /* Along the floor, relative to what carries the player. */
        nt_vec2 t = nt_v2(-n.y, n.x);
        nt_vec2 rel = nt_v2(v.x - ground_was.x, v.y - ground_was.y);
        nt_real s = rel.x * t.x + rel.y * t.y;
        nt_real vn = rel.x * n.x + rel.y * n.y;
        nt_real target = (nt_real)dir * pd->run_speed * c;
        if (dir == 0) s = approach(s, 0, pd->ground_decel * c * dt);
        else if (s * (nt_real)dir < 0) s = approach(s, target, pd->skid_decel * c * dt);
        else if (s * (nt_real)dir < pd->run_speed * c) s = approach(s, target, pd->ground_accel * c * dt);
        else s = approach(s, target, pd->ground_decel * c * dt);
        /* The step adds gravity's pull along the slope: take it off in advance so
         * that the player stands still on a slope when no key is held. */
        s -= (grav.x * t.x + grav.y * t.y) * dt;
        v = nt_v2(ground_v.x + s * t.x + vn * n.x, ground_v.y + s * t.y + vn * n.y);
        ps->jumping = false;
    } else {
        if (dir != 0) {
            if (v.x * (nt_real)dir < pd->run_speed * c)
                v.x = approach(v.x, (nt_real)dir * pd->run_speed * c, pd->air_accel * c * dt);
        } else {
            v.x = approach(v.x, 0, pd->air_decel * c * dt);
        }
        bool into_wall = (dir < 0 && tc->wall_left) || (dir > 0 && tc->wall_right);
        nt_real slide = pd->wall_slide_speed * c - grav.y * dt;
        if (into_wall && v.y > slide) v.y = slide;
    }

    int grace = (int)(pd->grace_time / dt + (nt_real)0.5);
    if (pressed & NT_INPUT_JUMP) {
        if (ps->since_floor <= grace) {
            v.y = -pd->jump_speed * c + (ground_v.y < 0 ? ground_v.y : 0);
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
    if (v.y > pd->max_fall_speed * c) v.y = pd->max_fall_speed * c;
    nt_body_set_gravity_scale(w, id, ps->jumping ? pd->jump_gravity_scale : 1);
    nt_body_set_velocity(w, id, v);
}
