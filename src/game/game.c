/* The game: a world built from a level, the level's objects, one tick at a time. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"

/* ---------------------------------------------------------------- random source */

void nt_rng_seed(nt_rng *rng, uint64_t seed) { rng->state = seed; }

uint32_t nt_rng_next(nt_rng *rng)
{
    /* splitmix64: a full-period 64-bit sequence, good enough for gameplay. */
    uint64_t z = (rng->state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (uint32_t)(z >> 32);
}

nt_real nt_rng_range(nt_rng *rng, nt_real lo, nt_real hi)
{
    /* 24 bits: the fraction is exact in float, so both builds see the same value. */
    nt_real f = (nt_real)(nt_rng_next(rng) >> 8) * (nt_real)(1.0 / 16777216.0);
    return lo + (hi - lo) * f;
}

/* ---------------------------------------------------------------- paths */

static double seg_len(nt_vec2 a, nt_vec2 b)
{
    double dx = (double)b.x - (double)a.x, dy = (double)b.y - (double)a.y;
    return sqrt(dx * dx + dy * dy);
}

nt_vec2 nt_path_position(const nt_level_path *p, double time, double phase)
{
    if (!p) return nt_v2(0, 0);
    if (p->mode == NT_PATH_ORBIT) {
        const double two_pi = 6.283185307179586;
        double a = two_pi * phase + time * (double)p->speed / (double)p->radius;
        nt_cos_sin cs = nt_compute_cos_sin(a); /* ntile's own: the same bits everywhere */
        return nt_v2((nt_real)((double)p->center.x + (double)p->radius * cs.cosine),
                     (nt_real)((double)p->center.y + (double)p->radius * cs.sine));
    }
    int n = p->point_count;
    if (n < 2) return n == 1 ? p->points[0] : nt_v2(0, 0);
    /* The tour as a loop of legs: LOOP p0..pn-1 and back to p0; PINGPONG p0..pn-1..p1
     * and back to p0. Each leg starts with `wait` seconds at its first point. */
    int legs = p->mode == NT_PATH_LOOP ? n : 2 * (n - 1);
    double wait = (double)p->wait, speed = (double)p->speed, cycle = 0;
    for (int k = 0; k < legs; k++) {
        int a = k < n ? k : 2 * (n - 1) - k, b = k + 1 < n ? k + 1 : 2 * (n - 1) - (k + 1);
        if (p->mode == NT_PATH_LOOP) a = k, b = (k + 1) % n;
        cycle += wait + seg_len(p->points[a], p->points[b]) / speed;
    }
    if (cycle <= 0) return p->points[0];
    double u = fmod(time + phase * cycle, cycle);
    for (int k = 0; k < legs; k++) {
        int a = k < n ? k : 2 * (n - 1) - k, b = k + 1 < n ? k + 1 : 2 * (n - 1) - (k + 1);
        if (p->mode == NT_PATH_LOOP) a = k, b = (k + 1) % n;
        nt_vec2 pa = p->points[a], pb = p->points[b];
        if (u < wait) return pa;
        u -= wait;
        double travel = seg_len(pa, pb) / speed;
        if (u <= travel || k == legs - 1) {
            double f = travel > 0 ? u / travel : 1;
            if (f > 1) f = 1;
            return nt_v2((nt_real)((double)pa.x + f * ((double)pb.x - (double)pa.x)),
                         (nt_real)((double)pa.y + f * ((double)pb.y - (double)pa.y)));
        }
        u -= travel;
    }
    return p->points[0];
}

/* ---------------------------------------------------------------- body records */

game_body *nt__game_record(const nt_game *g, nt_body_id id)
{
    if (id.index1 <= 0 || id.index1 > g->slot_cap) return NULL;
    int r = g->slot_record[id.index1 - 1];
    if (r < 0) return NULL;
    game_body *b = &g->bodies[r];
    return (b->alive && nt_body_id_equals(b->id, id)) ? b : NULL;
}

static nt_status add_record(nt_game *g, nt_body_id id, int source, int level_body)
{
    if (g->body_count == g->body_cap) {
        int cap = g->body_cap ? g->body_cap * 2 : 64;
        game_body *nb = nt_alloc((size_t)cap * sizeof *nb);
        if (!nb) return NT_ERR_OUT_OF_MEMORY;
        if (g->body_count) memcpy(nb, g->bodies, (size_t)g->body_count * sizeof *nb);
        nt_free(g->bodies);
        g->bodies = nb;
        g->body_cap = cap;
    }
    if (id.index1 > g->slot_cap) {
        int cap = g->slot_cap ? g->slot_cap : 64;
        while (cap < id.index1) cap *= 2;
        int *ns = nt_alloc((size_t)cap * sizeof *ns);
        if (!ns) return NT_ERR_OUT_OF_MEMORY;
        if (g->slot_cap) memcpy(ns, g->slot_record, (size_t)g->slot_cap * sizeof *ns);
        for (int i = g->slot_cap; i < cap; i++) ns[i] = -1;
        nt_free(g->slot_record);
        g->slot_record = ns;
        g->slot_cap = cap;
    }
    game_body *b = &g->bodies[g->body_count];
    b->id = id;
    b->source = source;
    b->level_body = level_body;
    b->alive = true;
    g->slot_record[id.index1 - 1] = g->body_count;
    g->body_count++;
    return NT_OK;
}

static void remove_body(nt_game *g, game_body *b)
{
    if (!b->alive) return;
    nt_body_destroy(g->world, b->id);
    g->slot_record[b->id.index1 - 1] = -1;
    b->alive = false;
}

static void set_one_way_bodies(nt_game *g);

/* ---------------------------------------------------------------- create / destroy */

nt_player_def nt_default_player_def(void)
{
    nt_player_def d;
    d.radius = (nt_real)(10.0 / 24.0);
    d.mass = 1;
    d.run_speed = (nt_real)6.25;
    d.ground_accel = 25;
    d.ground_decel = (nt_real)37.5;
    d.skid_decel = 50;
    d.air_accel = (nt_real)12.5;
    d.air_decel = 2;
    d.jump_speed = (nt_real)5.6;
    d.jump_gravity_scale = (nt_real)(1.0 / 3.0);
    d.wall_slide_speed = (nt_real)2.5;
    d.wall_jump_speed_x = (nt_real)4.5;
    d.wall_jump_speed_y = 5;
    d.max_fall_speed = 16;
    d.grace_time = (nt_real)0.1;
    d.bouncy_threshold = (nt_real)0.5;
    d.mover = nt_default_character_def();
    return d;
}

nt_game_def nt_default_game_def(void)
{
    nt_game_def d;
    memset(&d, 0, sizeof d);
    d.player = nt_default_player_def();
    return d;
}

void nt_game_destroy(nt_game *g)
{
    if (!g) return;
    nt_world_destroy(g->world);
    nt_free(g->bodies);
    nt_free(g->slot_record);
    nt_free(g->saved_spawn_counts);
    nt_free(g->saved_path_vel);
    nt_free(g->touched);
    free(g->level_first);
    free(g->spawn_counts);
    free(g->switch_on);
    free(g);
}

static int player_def_ok(const nt_player_def *p)
{
    const nt_real v[] = {p->radius, p->mass, p->run_speed, p->ground_accel, p->ground_decel, p->skid_decel,
                         p->air_accel, p->air_decel, p->jump_speed, p->jump_gravity_scale, p->wall_slide_speed,
                         p->wall_jump_speed_x, p->wall_jump_speed_y, p->max_fall_speed, p->grace_time,
                         p->bouncy_threshold};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
        if (!isfinite(v[i]) || v[i] < 0) return 0;
    /* The mover's settings, as nt_character_create checks them (a def not made by
     * nt_default_player_def() must not fail later, at creation, without a reason). */
    const nt_character_def *m = &p->mover;
    if (!isfinite(m->floor_angle) || !isfinite(m->snap_cells) || !isfinite(m->step_cells) || m->floor_angle < 0 ||
        m->floor_angle > (nt_real)1.5707963267948966 || m->snap_cells < 0 || m->snap_cells > 2 * NT_MAX_HALF_CELLS ||
        m->step_cells < 0 || m->step_cells > 2 * NT_MAX_HALF_CELLS || m->max_slides < 1 || m->max_slides > 16)
        return 0;
    /* The player stays within half a cell though bodies may be larger (game.h). */
    return p->radius > 0 && p->radius <= (nt_real)0.5 && p->mass > 0;
}

nt_status nt_game_create(const nt_level *lv, const nt_game_def *def, nt_game **out)
{
    if (out) *out = NULL;
    if (!lv || !out) return NT_ERR_INVALID_ARGUMENT;
    nt_game_def d = def ? *def : nt_default_game_def();
    if (!player_def_ok(&d.player)) return NT_ERR_INVALID_ARGUMENT;
    if (d.override_friction_model && d.friction_model != NT_FRICTION_N && d.friction_model != NT_FRICTION_COULOMB)
        return NT_ERR_INVALID_ARGUMENT;
    nt_status s = nt_level_validate(lv, NULL);
    if (s != NT_OK) return s;
    nt_game *g = calloc(1, sizeof *g);
    if (!g) return NT_ERR_OUT_OF_MEMORY;
    g->level = lv;
    g->def = d;
    g->cell = lv->cell_size;
    g->player_record = -1;
    g->complete_tick = -1;
    g->death_tick = -1;
    g->ps.since_floor = g->ps.since_wall = 1000000; /* no jump before touching anything */
    nt_rng_seed(&g->rng, d.override_seed ? d.seed : lv->seed);
    int n = nt_level_instance_count(lv);
    nt_body_id *ids = n > 0 ? malloc((size_t)n * sizeof *ids) : NULL;
    g->level_first = lv->body_count > 0 ? malloc((size_t)lv->body_count * sizeof *g->level_first) : NULL;
    g->spawn_counts = lv->spawner_count > 0 ? calloc((size_t)lv->spawner_count, sizeof *g->spawn_counts) : NULL;
    if ((n > 0 && !ids) || (lv->body_count > 0 && !g->level_first) || (lv->spawner_count > 0 && !g->spawn_counts)) {
        free(ids);
        nt_game_destroy(g);
        return NT_ERR_OUT_OF_MEMORY;
    }
    /* A friction-model override needs the level's materials to suit it too. */
    const nt_level *use = lv;
    nt_level copy;
    if (d.override_friction_model && d.friction_model != lv->friction_model) {
        copy = *lv;
        copy.friction_model = d.friction_model;
        if ((s = nt_level_validate(&copy, NULL)) != NT_OK) {
            free(ids);
            nt_game_destroy(g);
            return s;
        }
        use = &copy;
    }
    s = nt_level_create_world(use, &g->world, ids, (size_t)n);
    /* Records for the level's bodies, in creation order. */
    int k = 0;
    for (int i = 0; s == NT_OK && i < lv->body_count; i++) {
        const nt_level_body *b = &lv->bodies[i];
        g->level_first[i] = -1;
        if (b->is_template) continue;
        g->level_first[i] = g->body_count;
        int m = b->repeat_x * b->repeat_y;
        for (int j = 0; s == NT_OK && j < m; j++, k++) {
            s = add_record(g, ids[k], GB_LEVEL, i);
            /* Bodies on paths start where their path puts them at time 0. */
            if (s == NT_OK && b->path >= 0)
                s = nt_body_set_position(g->world, ids[k], nt_path_position(&lv->paths[b->path], 0, (double)b->phase));
        }
    }
    free(ids);
    if (s == NT_OK && lv->has_player) {
        nt_body_def pd = nt_default_body_def();
        pd.type = NT_BODY_DYNAMIC;
        pd.shape = nt_shape_circle(d.player.radius * g->cell);
        pd.position = lv->player;
        pd.mass = d.player.mass;
        pd.material.friction = 0; /* the controller is the player's friction */
        pd.material.bounce = 0;
        pd.enable_sleep = false;
        nt_body_id pid;
        s = nt_body_create(g->world, &pd, &pid);
        /* The mover moves it (character.h); the world step pushes what it walks into. */
        if (s == NT_OK && (s = nt_character_create(g->world, pid, &d.player.mover)) != NT_OK) nt_body_destroy(g->world, pid);
        if (s == NT_OK) {
            g->player_record = g->body_count;
            s = add_record(g, pid, GB_PLAYER, -1);
        }
    }
    for (int i = 0; i < lv->region_count; i++) {
        if (lv->regions[i].kind == NT_REGION_SCORE || lv->regions[i].kind == NT_REGION_KILL) g->has_score_or_kill = true;
        if (lv->regions[i].kind == NT_REGION_SWITCH && !g->switch_on && s == NT_OK) {
            g->switch_on = calloc((size_t)lv->region_count, sizeof *g->switch_on);
            if (!g->switch_on) s = NT_ERR_OUT_OF_MEMORY;
        }
    }
    for (int i = 0; i < lv->body_count; i++) g->has_one_way |= lv->bodies[i].one_way != NT_ONE_WAY_NONE;
    /* Trap doors start open: they collide with nothing until their switch is on. */
    for (int i = 0; s == NT_OK && i < g->body_count; i++) {
        const game_body *b = &g->bodies[i];
        if (b->source == GB_LEVEL && lv->bodies[b->level_body].door == NT_DOOR_TRAP) s = nt_body_set_filter(g->world, b->id, 0, 0);
    }
    if (s != NT_OK) {
        nt_game_destroy(g);
        return s;
    }
    if (g->player_record >= 0) {
        nt__player_sense(g);
        set_one_way_bodies(g);
    }
    *out = g;
    return NT_OK;
}

/* ---------------------------------------------------------------- accessors */

nt_world *nt_game_get_world(const nt_game *g) { return g ? g->world : NULL; }
const nt_level *nt_game_get_level(const nt_game *g) { return g ? g->level : NULL; }

nt_body_id nt_game_get_player(const nt_game *g)
{
    if (!g || g->player_record < 0) return nt_null_body_id();
    return g->bodies[g->player_record].id;
}

nt_game_state nt_game_get_state(const nt_game *g)
{
    nt_game_state s;
    memset(&s, 0, sizeof s);
    s.complete_tick = -1;
    s.death_tick = -1;
    if (!g) return s;
    s.tick = g->tick;
    s.score = g->score;
    s.complete = g->complete;
    s.complete_tick = g->complete_tick;
    s.has_player = g->player_record >= 0;
    s.alive = s.has_player && !g->dead;
    s.death_tick = g->death_tick;
    s.spawned = g->spawned;
    s.on_floor = g->ps.on_floor;
    s.wall_left = g->ps.wall_left;
    s.wall_right = g->ps.wall_right;
    return s;
}

nt_body_id nt_game_find_body(const nt_game *g, const char *name)
{
    if (!g) return nt_null_body_id();
    int i = nt_level_find_body(g->level, name);
    if (i < 0 || g->level_first[i] < 0) return nt_null_body_id();
    const game_body *b = &g->bodies[g->level_first[i]];
    return b->alive ? b->id : nt_null_body_id();
}

int nt_game_get_bodies(const nt_game *g, nt_body_id *out, int cap)
{
    if (!g) return 0;
    int n = 0;
    for (int i = 0; i < g->body_count; i++) {
        if (!g->bodies[i].alive) continue;
        if (out && n < cap) out[n] = g->bodies[i].id;
        n++;
    }
    return n;
}

/* ---------------------------------------------------------------- changes */

nt_status nt_game_add_body(nt_game *g, const nt_body_def *def, nt_body_id *out)
{
    if (out) *out = nt_null_body_id();
    if (!g || !def) return NT_ERR_INVALID_ARGUMENT;
    nt_body_id id;
    nt_status s = nt_body_create(g->world, def, &id);
    if (s != NT_OK) return s;
    s = add_record(g, id, GB_ADDED, -1);
    if (s != NT_OK) {
        nt_body_destroy(g->world, id);
        return s;
    }
    if (out) *out = id;
    return NT_OK;
}

nt_status nt_game_remove_body(nt_game *g, nt_body_id id)
{
    if (!g) return NT_ERR_INVALID_ARGUMENT;
    game_body *b = nt__game_record(g, id);
    if (!b || !nt_body_is_valid(g->world, id)) return NT_ERR_INVALID_ID;
    /* The controller drives the player's body every tick: it stays. */
    if (b->source == GB_PLAYER) return NT_ERR_INVALID_ARGUMENT;
    remove_body(g, b);
    return NT_OK;
}

nt_status nt_game_set_tile(nt_game *g, int x, int y, int tile)
{
    if (!g) return NT_ERR_INVALID_ARGUMENT;
    return nt_world_set_tile(g->world, x, y, tile);
}

bool nt_game_switch_is_on(const nt_game *g, int region)
{
    return g && g->switch_on && region >= 0 && region < g->level->region_count && g->switch_on[region];
}

static bool point_in_region(const nt_level_region *r, nt_vec2 p)
{
    return p.x >= r->lo.x && p.x <= r->hi.x && p.y >= r->lo.y && p.y <= r->hi.y;
}

bool nt_game_body_in_region(const nt_game *g, nt_body_id id, int region)
{
    if (!g || region < 0 || region >= g->level->region_count || !nt_body_is_valid(g->world, id)) return false;
    return point_in_region(&g->level->regions[region], nt_body_get_position(g->world, id));
}

/* ---------------------------------------------------------------- hash */

static uint64_t mix(uint64_t h, uint64_t v)
{
    /* FNV-1a over the 8 bytes of v, least significant first (independent of endianness). */
    for (int i = 0; i < 8; i++) h = (h ^ ((v >> (8 * i)) & 0xffu)) * 1099511628211ull;
    return h;
}

/* The bits of a real, as an integer (the same on either byte order). */
static uint64_t real_bits(nt_real x)
{
#if NT_REAL_IS_DOUBLE
    uint64_t u;
#else
    uint32_t u;
#endif
    memcpy(&u, &x, sizeof u);
    return u;
}

uint64_t nt_game_hash(const nt_game *g)
{
    uint64_t h = 1469598103934665603ull;
    if (!g) return h;
    h = mix(h, nt_world_hash(g->world));
    h = mix(h, (uint64_t)(uint32_t)g->tick);
    h = mix(h, (uint64_t)(uint32_t)g->score);
    h = mix(h, (uint64_t)g->complete | (uint64_t)g->dead << 1 | (uint64_t)g->ps.jumping << 2);
    h = mix(h, (uint64_t)(uint32_t)g->complete_tick);
    h = mix(h, (uint64_t)(uint32_t)g->death_tick);
    h = mix(h, (uint64_t)(uint32_t)g->spawned);
    h = mix(h, (uint64_t)(uint32_t)g->ps.since_floor);
    h = mix(h, (uint64_t)(uint32_t)g->ps.since_wall);
    h = mix(h, (uint64_t)(uint32_t)g->ps.wall_away);
    h = mix(h, (uint64_t)g->prev_keys);
    if (g->player_record >= 0) { /* the controller's own velocity: not in the world */
        h = mix(h, real_bits(g->ps.vel.x));
        h = mix(h, real_bits(g->ps.vel.y));
        h = mix(h, real_bits(g->ps.run));
        h = mix(h, (uint64_t)g->ps.on_floor);
    }
    h = mix(h, g->rng.state);
    for (int i = 0; i < g->level->spawner_count; i++) h = mix(h, (uint64_t)(uint32_t)g->spawn_counts[i]);
    if (g->switch_on) /* only levels with switches: the hashes of the others stay as they were */
        for (int i = 0; i < g->level->region_count; i++) h = mix(h, (uint64_t)g->switch_on[i]);
    return h;
}

/* ---------------------------------------------------------------- one tick */

static void move_path_bodies(nt_game *g, nt_real dt, int save)
{
    const nt_level *lv = g->level;
    int n = 0;
    double t1 = g->time + (double)dt;
    for (int i = 0; i < g->body_count; i++) {
        game_body *b = &g->bodies[i];
        if (!b->alive || b->level_body < 0) continue;
        const nt_level_body *lb = &lv->bodies[b->level_body];
        if (lb->path < 0 || b->source != GB_LEVEL) continue;
        /* Aim at where the path is at the end of the tick: no drift, however long it runs. */
        nt_vec2 target = nt_path_position(&lv->paths[lb->path], t1, (double)lb->phase);
        nt_vec2 p = nt_body_get_position(g->world, b->id);
        if (save) g->saved_path_vel[n++] = nt_body_get_velocity(g->world, b->id);
        nt_body_set_velocity(g->world, b->id, nt_v2((target.x - p.x) / dt, (target.y - p.y) / dt));
    }
}

/* The path bodies' velocities back as move_path_bodies found them. */
static void restore_path_bodies(nt_game *g)
{
    const nt_level *lv = g->level;
    int n = 0;
    for (int i = 0; i < g->body_count; i++) {
        game_body *b = &g->bodies[i];
        if (!b->alive || b->level_body < 0) continue;
        const nt_level_body *lb = &lv->bodies[b->level_body];
        if (lb->path < 0 || b->source != GB_LEVEL) continue;
        nt_body_set_velocity(g->world, b->id, g->saved_path_vel[n++]);
    }
}

static int path_body_count(const nt_game *g)
{
    int n = 0;
    for (int i = 0; i < g->body_count; i++) {
        const game_body *b = &g->bodies[i];
        if (b->alive && b->level_body >= 0 && b->source == GB_LEVEL && g->level->bodies[b->level_body].path >= 0) n++;
    }
    return n;
}

static nt_status spawn(nt_game *g, int si)
{
    const nt_level *lv = g->level;
    const nt_level_spawner *sp = &lv->spawners[si];
    const nt_level_body *tb = &lv->bodies[sp->template_body];
    nt_body_def d = nt_level_body_def(tb, 0);
    nt_vec2 at = tb->position;
    if (sp->attach >= 0) {
        int r = g->level_first[sp->attach];
        if (r < 0 || !g->bodies[r].alive) return NT_OK; /* nothing to spawn from */
        at = nt_body_get_position(g->world, g->bodies[r].id);
    }
    d.position = nt_v2(at.x + sp->offset.x, at.y + sp->offset.y);
    if (sp->jitter > 0) d.velocity.x += nt_rng_range(&g->rng, -sp->jitter, sp->jitter);
    nt_body_id id;
    nt_status s = nt_body_create(g->world, &d, &id);
    if (s != NT_OK) return s;
    s = add_record(g, id, GB_SPAWNED, sp->template_body);
    if (s != NT_OK) {
        nt_body_destroy(g->world, id);
        return s;
    }
    g->spawn_counts[si]++;
    g->spawned++;
    return NT_OK;
}

static nt_status run_spawners(nt_game *g, uint32_t pressed)
{
    const nt_level *lv = g->level;
    for (int i = 0; i < lv->spawner_count; i++) {
        const nt_level_spawner *sp = &lv->spawners[i];
        if (g->spawn_counts[i] >= sp->limit) continue;
        bool fire = sp->trigger == NT_SPAWN_ACTION ? (pressed & NT_INPUT_ACTION) != 0
                                                   : g->tick >= sp->start && (g->tick - sp->start) % sp->every == 0;
        if (!fire) continue;
        nt_status s = spawn(g, i);
        if (s != NT_OK) return s;
    }
    return NT_OK;
}

static const nt_level_body *level_body_of(const nt_game *g, const game_body *b)
{
    return b && b->level_body >= 0 ? &g->level->bodies[b->level_body] : NULL;
}

static void kill_player(nt_game *g)
{
    if (g->dead || g->complete) return;
    g->dead = true;
    g->death_tick = g->tick;
}

/* Touches between the player and gold or deadly bodies. Events are copied out first:
 * removing a body invalidates the event arrays. */
static void apply_events(nt_game *g)
{
    if (g->player_record < 0) return;
    nt_body_id pid = g->bodies[g->player_record].id;
    nt_sensor_events se = nt_world_get_sensor_events(g->world);
    nt_contact_events ce = nt_world_get_contact_events(g->world);
    nt_body_id near[16];
    int nn = g->dead ? 0 : nt__player_touches(g, near, 16);
    if (nn > 16) nn = 16; /* the rest on the next ticks (gold goes as it is taken) */
    int n = nn;
    for (int i = 0; i < se.begin_count; i++) n += nt_body_id_equals(se.begin_events[i].visitor, pid);
    for (int i = 0; i < ce.begin_count; i++)
        n += nt_body_id_equals(ce.begin_events[i].a, pid) || nt_body_id_equals(ce.begin_events[i].b, pid);
    if (n == 0) return;
    if (n > g->touched_cap) return; /* cannot happen: reserved before the step */
    nt_body_id *touched = g->touched;
    int m = 0;
    for (int i = 0; i < nn; i++) touched[m++] = near[i];
    for (int i = 0; i < se.begin_count; i++)
        if (nt_body_id_equals(se.begin_events[i].visitor, pid)) touched[m++] = se.begin_events[i].sensor;
    for (int i = 0; i < ce.begin_count; i++) {
        if (nt_body_id_equals(ce.begin_events[i].a, pid)) touched[m++] = ce.begin_events[i].b;
        else if (nt_body_id_equals(ce.begin_events[i].b, pid)) touched[m++] = ce.begin_events[i].a;
    }
    for (int i = 0; i < m; i++) {
        game_body *b = nt__game_record(g, touched[i]);
        const nt_level_body *lb = level_body_of(g, b);
        if (!lb) continue;
        if (lb->door == NT_DOOR_PLAIN && !g->dead) {
            remove_body(g, b); /* a plain door opens at the player's touch */
            continue;
        }
        if (lb->deadly && !g->dead) kill_player(g);
        if (lb->score > 0 && !g->dead) {
            g->score += lb->score;
            remove_body(g, b);
        }
    }
}

/* Switch r goes on: its locked doors go away, its trap doors become solid (no
 * allocation: nothing here can fail). */
static void turn_switch_on(nt_game *g, int r)
{
    g->switch_on[r] = true;
    for (int i = 0; i < g->body_count; i++) {
        game_body *b = &g->bodies[i];
        const nt_level_body *lb = level_body_of(g, b);
        if (!b->alive || b->source != GB_LEVEL || !lb || lb->door_switch != r + 1) continue;
        if (lb->door == NT_DOOR_LOCKED) remove_body(g, b);
        else if (lb->door == NT_DOOR_TRAP) nt_body_set_filter(g->world, b->id, lb->category, lb->mask);
    }
}

static void apply_regions(nt_game *g)
{
    const nt_level *lv = g->level;
    if (lv->region_count == 0) return;
    if (g->player_record >= 0 && !g->dead && !g->complete) {
        nt_vec2 p = nt_body_get_position(g->world, g->bodies[g->player_record].id);
        for (int r = 0; r < lv->region_count; r++) {
            const nt_level_region *rg = &lv->regions[r];
            if (!point_in_region(rg, p)) continue;
            if (rg->kind == NT_REGION_SWITCH && !g->switch_on[r]) {
                turn_switch_on(g, r);
            } else if (rg->kind == NT_REGION_EXIT && !g->complete && (rg->needs == 0 || g->switch_on[rg->needs - 1])) {
                g->complete = true;
                g->complete_tick = g->tick;
            } else if (rg->kind == NT_REGION_KILL) {
                kill_player(g);
            }
        }
    }
    if (!g->has_score_or_kill) return;
    for (int i = 0; i < g->body_count; i++) {
        game_body *b = &g->bodies[i];
        if (!b->alive || b->source == GB_PLAYER) continue;
        if (nt_body_get_type(g->world, b->id) != NT_BODY_DYNAMIC) continue;
        nt_vec2 p = nt_body_get_position(g->world, b->id);
        for (int r = 0; r < lv->region_count && b->alive; r++) {
            const nt_level_region *rg = &lv->regions[r];
            if ((rg->kind != NT_REGION_SCORE && rg->kind != NT_REGION_KILL) || !point_in_region(rg, p)) continue;
            if (rg->kind == NT_REGION_SCORE) g->score += rg->value;
            remove_body(g, b);
        }
    }
}

/* One-way bodies of the game layer (nt_level_body.one_way): solid (the level's filter)
 * while the player lies wholly on the side they face, within a twentieth of a cell;
 * colliding with nothing otherwise, so that the player passes from the other sides. */
static void set_one_way_bodies(nt_game *g)
{
    if (!g->has_one_way) return;
    nt_world *w = g->world;
    nt_body_id pid = g->bodies[g->player_record].id;
    nt_vec2 p = nt_body_get_position(w, pid);
    nt_real r = nt_body_get_shape(w, pid).half.x, tol = g->cell / 20;
    for (int i = 0; i < g->body_count; i++) {
        game_body *b = &g->bodies[i];
        const nt_level_body *lb = level_body_of(g, b);
        if (!b->alive || b->source != GB_LEVEL || !lb || lb->one_way == NT_ONE_WAY_NONE) continue;
        nt_vec2 c = nt_body_get_position(w, b->id), h = nt_body_get_shape(w, b->id).half;
        bool outside = lb->one_way == NT_ONE_WAY_RIGHT  ? p.x - r >= c.x + h.x - tol
                       : lb->one_way == NT_ONE_WAY_LEFT ? p.x + r <= c.x - h.x + tol
                       : lb->one_way == NT_ONE_WAY_DOWN ? p.y - r >= c.y + h.y - tol
                                                        : p.y + r <= c.y - h.y + tol;
        uint32_t cat = outside ? lb->category : 0, mask = outside ? lb->mask : 0;
        if (nt_body_get_category(w, b->id) != cat || nt_body_get_mask(w, b->id) != mask) nt_body_set_filter(w, b->id, cat, mask);
    }
}

/* Everything a step of the game may allocate outside the world, before it changes
 * anything: the undo buffers and room for every touch of the player (a contact and a
 * sensor begin per body of the world, this tick's spawns included, and 16 near ones). */
static nt_status reserve_step(nt_game *g)
{
    int ns = g->level->spawner_count;
    if (ns > 0 && !g->saved_spawn_counts) {
        g->saved_spawn_counts = nt_alloc((size_t)ns * sizeof *g->saved_spawn_counts);
        if (!g->saved_spawn_counts) return NT_ERR_OUT_OF_MEMORY;
    }
    int np = path_body_count(g);
    if (np > g->path_cap) {
        nt_vec2 *v = nt_alloc((size_t)np * sizeof *v);
        if (!v) return NT_ERR_OUT_OF_MEMORY;
        nt_free(g->saved_path_vel);
        g->saved_path_vel = v;
        g->path_cap = np;
    }
    int nt = 2 * (nt_world_get_body_count(g->world) + ns) + 16;
    if (nt > g->touched_cap) {
        int cap = nt + nt / 2;
        nt_body_id *t = nt_alloc((size_t)cap * sizeof *t);
        if (!t) return NT_ERR_OUT_OF_MEMORY;
        nt_free(g->touched);
        g->touched = t;
        g->touched_cap = cap;
    }
    return NT_OK;
}

nt_status nt_game_step(nt_game *g, uint32_t keys, nt_real dt)
{
    if (!g) return NT_ERR_INVALID_ARGUMENT;
    if (!isfinite(dt)) return NT_ERR_NON_FINITE;
    if (dt <= 0) return NT_ERR_INVALID_ARGUMENT;
    if (dt < (nt_real)NT_MIN_DT || dt > (nt_real)NT_MAX_DT) return NT_ERR_OUT_OF_RANGE;
    nt_status s = reserve_step(g);
    if (s != NT_OK) return s;
    /* What the tick changes before the world step, kept to undo it if the step fails. */
    const int tick0 = g->tick, spawned0 = g->spawned, count0 = g->body_count;
    const nt_rng rng0 = g->rng;
    const player_state ps0 = g->ps;
    nt_vec2 pp0 = nt_v2(0, 0), pv0 = nt_v2(0, 0);
    nt_body_id pid = g->player_record >= 0 ? g->bodies[g->player_record].id : nt_null_body_id();
    if (g->player_record >= 0) {
        pp0 = nt_body_get_position(g->world, pid);
        pv0 = nt_body_get_velocity(g->world, pid);
    }
    if (g->level->spawner_count > 0)
        memcpy(g->saved_spawn_counts, g->spawn_counts, (size_t)g->level->spawner_count * sizeof *g->spawn_counts);
    uint32_t pressed = keys & ~g->prev_keys;
    g->tick++;
    move_path_bodies(g, dt, 1);
    s = run_spawners(g, pressed);
    if (s == NT_OK) {
        if (g->player_record >= 0) nt__player_control(g, keys, dt);
        s = nt_world_step(g->world, dt);
    }
    if (s != NT_OK) {
        /* Undo, newest first: spawned bodies, the player's move, the paths, counters. */
        while (g->body_count > count0) remove_body(g, &g->bodies[--g->body_count]);
        if (g->player_record >= 0) {
            nt_body_set_position(g->world, pid, pp0);
            nt_body_set_velocity(g->world, pid, pv0);
        }
        g->ps = ps0;
        restore_path_bodies(g);
        if (g->level->spawner_count > 0)
            memcpy(g->spawn_counts, g->saved_spawn_counts, (size_t)g->level->spawner_count * sizeof *g->spawn_counts);
        g->rng = rng0;
        g->spawned = spawned0;
        g->tick = tick0;
        return s;
    }
    g->time += (double)dt;
    g->prev_keys = keys;
    apply_events(g);
    apply_regions(g);
    if (g->player_record >= 0) {
        nt__player_sense(g);
        set_one_way_bodies(g); /* for the next tick, from where the player ended this one */
    }
    return NT_OK;
}
