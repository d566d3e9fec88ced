/* The world: lifecycle, bodies, tiles and materials, events, queries, debug drawing
 * and the state hash. The step itself is in response.c, the broad phase in grid.c,
 * sleeping groups and parked contacts in sleep.c. */
#include <stdio.h>
#include <stdlib.h>
#include <stdatomic.h>
#include <string.h>
#include "simulation.h"

/* ---------------------------------------------------------------- helpers */

static int finite2(nt_vec2 v) { return nt__finite(v.x) && nt__finite(v.y); }

static nt_status check_material(const nt_world_def *def, nt_material m)
{
    if (!nt__finite(m.friction) || !nt__finite(m.bounce)) return NT_ERR_NON_FINITE;
    if (m.friction < 0 || m.bounce < 0 || m.bounce > 1) return NT_ERR_INVALID_ARGUMENT;
    if (def->friction_model == NT_FRICTION_N && m.friction > 1) return NT_ERR_INVALID_ARGUMENT;
    return NT_OK;
}

/* The body behind a handle, or NULL. */
static nt__body *get_body(const nt_world *w, nt_body_id id)
{
    if (!w || id.world0 != w->tag || id.index1 <= 0 || id.index1 > w->body_hwm) return NULL;
    nt__body *b = &w->bodies[id.index1 - 1];
    if (!(b->flags & NT__BF_ALIVE) || b->generation != id.generation) return NULL;
    return b;
}

static nt_body_id make_id(const nt_world *w, int32_t i)
{
    nt_body_id id;
    id.index1 = i + 1;
    id.world0 = w->tag;
    id.generation = w->bodies[i].generation;
    return id;
}

/* ---------------------------------------------------------------- world */

nt_world_def nt_default_world_def(void)
{
    nt_world_def d;
    memset(&d, 0, sizeof d);
    d.map = nt_default_map_def();
    d.gravity = nt_v2(0, 320);
    d.friction_model = NT_FRICTION_N;
    d.tile_material.friction = (nt_real)0.05;
    d.tile_material.bounce = (nt_real)0.3;
    d.restitution_threshold = 24;
    d.hit_event_threshold = 24;
    d.enable_sleep = true;
    d.sleep_speed = 6;
    d.sleep_time = (nt_real)0.5;
    d.max_cells_per_step = 4;
    d.floor_angle = (nt_real)0.87266462599716477; /* 50 degrees */
    d.velocity_iterations = 8;
    d.position_iterations = 4;
    d.body_capacity = 64;
    d.user_data = NULL;
    return d;
}

/* Gravity within NT_MAX_GRAVITY per part (finite checked first). */
static int gravity_in_range(nt_vec2 g)
{
    return nt__fabs(g.x) <= (nt_real)NT_MAX_GRAVITY && nt__fabs(g.y) <= (nt_real)NT_MAX_GRAVITY;
}

static int gravity_scale_in_range(nt_real s) { return nt__fabs(s) <= (nt_real)NT_MAX_GRAVITY_SCALE; }

static nt_status check_world_def(const nt_world_def *d)
{
    if (!finite2(d->gravity) || !nt__finite(d->restitution_threshold) || !nt__finite(d->hit_event_threshold) ||
        !nt__finite(d->sleep_speed) || !nt__finite(d->sleep_time) || !nt__finite(d->max_cells_per_step) ||
        !nt__finite(d->floor_angle))
        return NT_ERR_NON_FINITE;
    if (d->floor_angle < 0 || d->floor_angle > (nt_real)1.5707963267948966) return NT_ERR_INVALID_ARGUMENT;
    if (d->friction_model != NT_FRICTION_N && d->friction_model != NT_FRICTION_COULOMB) return NT_ERR_INVALID_ARGUMENT;
    nt_status s = check_material(d, d->tile_material);
    if (s != NT_OK) return s;
    if (d->restitution_threshold < 0 || d->hit_event_threshold < 0 || d->sleep_speed < 0 || d->sleep_time < 0)
        return NT_ERR_INVALID_ARGUMENT;
    if (!gravity_in_range(d->gravity)) return NT_ERR_OUT_OF_RANGE;
    if (d->max_cells_per_step < 1 || d->max_cells_per_step > 16) return NT_ERR_OUT_OF_RANGE;
    if (d->velocity_iterations < 1 || d->velocity_iterations > 64) return NT_ERR_OUT_OF_RANGE;
    if (d->position_iterations < 0 || d->position_iterations > 64) return NT_ERR_OUT_OF_RANGE;
    if (d->body_capacity < 0) return NT_ERR_INVALID_ARGUMENT;
    return NT_OK;
}

/* Grow every per-body array to `cap` slots. All or nothing. */
static nt_status reserve_bodies(nt_world *w, int cap)
{
    if (cap <= w->body_cap) return NT_OK;
    size_t n = (size_t)cap;
    nt__body *b = (nt__body *)nt__alloc(n * sizeof *b);
    nt__body_cold *c = (nt__body_cold *)nt__alloc(n * sizeof *c);
    int32_t *aw = (int32_t *)nt__alloc(n * sizeof *aw);
    int32_t *sa = (int32_t *)nt__alloc(2 * n * sizeof *sa);
    nt_real *sr = (nt_real *)nt__alloc(2 * n * sizeof *sr);
    int32_t *wl = (int32_t *)nt__alloc(n * sizeof *wl);
    int32_t *wk = (int32_t *)nt__alloc(n * sizeof *wk);
    nt__svel *sv = (nt__svel *)nt__alloc(n * sizeof *sv);
    nt__stile *st = (nt__stile *)nt__alloc(n * sizeof *st);
    int32_t *lv = (int32_t *)nt__alloc(n * sizeof *lv);
    int32_t *lq = (int32_t *)nt__alloc(3 * n * sizeof *lq);
    uint64_t *mm = (uint64_t *)nt__alloc((n / 64 + 1) * sizeof *mm);
    int32_t *up = (int32_t *)nt__alloc(n * sizeof *up);
    nt_real *ut = (nt_real *)nt__alloc(n * sizeof *ut);
    if (!b || !c || !aw || !sa || !sr || !wl || !wk || !sv || !st || !lv || !lq || !mm || !up || !ut) {
        nt__free(up);
        nt__free(ut);
        nt__free(mm);
        nt__free(lv);
        nt__free(lq);
        nt__free(wk);
        nt__free(sv);
        nt__free(st);
        nt__free(b);
        nt__free(c);
        nt__free(aw);
        nt__free(sa);
        nt__free(sr);
        nt__free(wl);
        return NT_ERR_OUT_OF_MEMORY;
    }
    if (w->body_hwm > 0) {
        memcpy(b, w->bodies, (size_t)w->body_hwm * sizeof *b);
        memcpy(c, w->cold, (size_t)w->body_hwm * sizeof *c);
    }
    if (w->awake_count > 0) memcpy(aw, w->awake, (size_t)w->awake_count * sizeof *aw);
    if (w->woken_count > 0) memcpy(wk, w->woken, (size_t)w->woken_count * sizeof *wk);
    nt__free(w->bodies);
    nt__free(w->cold);
    nt__free(w->awake);
    nt__free(w->scratch_a);
    nt__free(w->scratch_r);
    nt__free(w->wake_list);
    nt__free(w->woken);
    nt__free(w->svel);
    nt__free(w->stile);
    nt__free(w->level);
    nt__free(w->level_q);
    nt__free(w->move_marks);
    nt__free(w->sleep_parent);
    nt__free(w->sleep_tmin);
    w->sleep_parent = up;
    w->sleep_tmin = ut;
    memset(mm, 0, (n / 64 + 1) * sizeof *mm);
    w->move_marks = mm;
    w->level = lv;
    w->level_q = lq;
    w->woken = wk;
    w->svel = sv;
    w->stile = st;
    w->bodies = b;
    w->cold = c;
    w->awake = aw;
    w->scratch_a = sa;
    w->scratch_r = sr;
    w->wake_list = wl;
    w->body_cap = cap;
    return NT_OK;
}

/* The tag a new world puts in its body handles: never 0 (the null handle's), and
 * different for each of 2^32 - 1 worlds made one after another (an atomic counter, so
 * worlds made on several threads at once get different tags too). The handle has no
 * padding: three 32-bit fields. */
static uint32_t next_world_tag(void)
{
    static atomic_uint_least32_t made;
    uint_least32_t n = atomic_fetch_add(&made, 1u);
    return (uint32_t)(n % 0xffffffffu + 1u);
}

nt_status nt_world_create(const nt_world_def *def, nt_world **out)
{
    if (!out) return NT_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!def) return NT_ERR_INVALID_ARGUMENT;
    nt_status s = check_world_def(def);
    if (s != NT_OK) return s;
    nt_world *w = (nt_world *)nt__alloc(sizeof *w);
    if (!w) return NT_ERR_OUT_OF_MEMORY;
    memset(w, 0, sizeof *w);
    s = nt_map_create(&def->map, &w->map);
    if (s != NT_OK) {
        nt__free(w);
        return s;
    }
    w->def = *def;
    w->tag = next_world_tag();
    w->floor_cos = (nt_real)nt_compute_cos_sin((double)def->floor_angle).cosine;
    w->cell = w->map->cell;
    w->inv_cell = w->map->inv_cell;
    for (int i = 0; i < NT_MAX_MATERIALS; i++) w->materials[i] = def->tile_material;
    w->free_head = -1;
    w->first = w->last = -1;
    w->grid_w = w->map->w;
    w->grid_h = w->map->h;
    int cap = def->body_capacity > 0 ? def->body_capacity : 16;
    if (reserve_bodies(w, cap) != NT_OK) {
        nt_world_destroy(w);
        return NT_ERR_OUT_OF_MEMORY;
    }
    *out = w;
    return NT_OK;
}

void nt_world_destroy(nt_world *w)
{
    if (!w || w->locked) return; /* from inside its own callback: refused (nothing to report it to) */
    nt_map_destroy(w->map);
    nt_map_destroy(w->solid);
    nt__free(w->cell_mat);
    nt__free(w->cell_flags);
    nt__free(w->bodies);
    nt__free(w->cold);
    nt__free(w->awake);
    nt__free(w->scratch_a);
    nt__free(w->scratch_r);
    nt__free(w->wake_list);
    nt__free(w->svel);
    nt__free(w->stile);
    nt__free(w->level);
    nt__free(w->level_q);
    nt__free(w->move_marks);
    nt__free(w->sleep_parent);
    nt__free(w->sleep_tmin);
    nt__free(w->adj);
    nt__free(w->heads);
    nt__free(w->occupied);
    nt__free(w->rest_near);
    nt__free(w->lheads);
    nt__free(w->loccupied);
    nt__free(w->chars);
    nt__free(w->sort_keys);
    nt__free(w->prox);
    nt__free(w->prox_tmp);
    nt__free(w->radix);
    nt__free(w->con);
    nt__free(w->con_new);
    nt__free(w->con_tmp);
    nt__free(w->parked);
    nt__free(w->park_link);
    nt__free(w->park_pick);
    nt__free(w->woken);
    nt__free(w->ev_begin);
    nt__free(w->ev_end);
    nt__free(w->ev_hit);
    nt__free(w->ev_sbegin);
    nt__free(w->ev_send);
    nt__free(w);
}

nt_status nt_world_step(nt_world *w, nt_real dt)
{
    NT__CHECK_LOCK(w);
    if (!w) return NT_ERR_INVALID_ARGUMENT;
    if (!nt__finite(dt)) return NT_ERR_NON_FINITE;
    if (dt <= 0) return NT_ERR_INVALID_ARGUMENT;
    if (dt < (nt_real)NT_MIN_DT || dt > (nt_real)NT_MAX_DT) return NT_ERR_OUT_OF_RANGE;
    return nt__step(w, dt);
}

const nt_map *nt_world_get_map(const nt_world *w) { return w ? w->map : NULL; }
int nt_world_get_body_count(const nt_world *w) { return w ? w->body_count : 0; }
int nt_world_get_awake_count(const nt_world *w) { return w ? w->awake_count : 0; }
void *nt_world_get_user_data(const nt_world *w) { return w ? w->def.user_data : NULL; }

nt_world_counters nt_world_get_counters(const nt_world *w)
{
    nt_world_counters c;
    memset(&c, 0, sizeof c);
    if (w) c = w->counters;
    return c;
}

void nt_world_enable_profile(nt_world *w, bool enable)
{
    if (w && w->locked) return;
    if (!w) return;
    w->profiling = enable;
    memset(&w->profile, 0, sizeof w->profile);
}

nt_world_profile nt_world_get_profile(const nt_world *w)
{
    nt_world_profile p;
    memset(&p, 0, sizeof p);
    return w ? w->profile : p;
}

nt_vec2 nt_world_get_gravity(const nt_world *w) { return w ? w->def.gravity : nt_v2(0, 0); }

nt_status nt_world_set_gravity(nt_world *w, nt_vec2 g)
{
    NT__CHECK_LOCK(w);
    if (!w) return NT_ERR_INVALID_ARGUMENT;
    if (!finite2(g)) return NT_ERR_NON_FINITE;
    if (!gravity_in_range(g)) return NT_ERR_OUT_OF_RANGE;
    w->def.gravity = g;
    w->force_epoch++; /* resting bodies' forces are answered again (NT__MF_HELD) */
    nt__wake_all(w);
    return NT_OK;
}

nt_status nt_world_set_iterations(nt_world *w, int velocity_iterations, int position_iterations)
{
    NT__CHECK_LOCK(w);
    if (!w) return NT_ERR_INVALID_ARGUMENT;
    if (velocity_iterations < 1 || velocity_iterations > 64 || position_iterations < 0 || position_iterations > 64)
        return NT_ERR_OUT_OF_RANGE;
    w->def.velocity_iterations = velocity_iterations;
    w->def.position_iterations = position_iterations;
    return NT_OK;
}

void nt_world_get_iterations(const nt_world *w, int *velocity_iterations, int *position_iterations)
{
    if (velocity_iterations) *velocity_iterations = w ? w->def.velocity_iterations : 0;
    if (position_iterations) *position_iterations = w ? w->def.position_iterations : 0;
}

/* ---------------------------------------------------------------- tiles and cells */

int nt_world_get_tile(const nt_world *w, int x, int y) { return w ? nt_map_get_tile(w->map, x, y) : NT_TILE_FULL; }

nt_status nt_world_set_tile(nt_world *w, int x, int y, int tile)
{
    NT__CHECK_LOCK(w);
    if (!w) return NT_ERR_INVALID_ARGUMENT;
    nt_status s = nt_map_set_tile(w->map, x, y, tile);
    if (s != NT_OK) return s;
    w->map_epoch++;
    if (w->solid) {
        int t = (nt__cell_flags(w, x, y) & NT_CELL_ONE_WAY) ? NT_TILE_EMPTY : tile;
        nt_map_set_tile(w->solid, x, y, t);
    }
    nt__wake_near_cells(w, x, y, x, y);
    return NT_OK;
}

nt_status nt_world_set_tiles(nt_world *w, const uint8_t *tiles, size_t count)
{
    NT__CHECK_LOCK(w);
    if (!w || !tiles) return NT_ERR_INVALID_ARGUMENT;
    size_t n = (size_t)w->map->w * (size_t)w->map->h;
    uint8_t *tmp = NULL;
    if (w->solid && count == n) {
        tmp = (uint8_t *)nt__alloc(n);
        if (!tmp) return NT_ERR_OUT_OF_MEMORY;
        for (size_t k = 0; k < n; k++) tmp[k] = (w->cell_flags[k] & NT_CELL_ONE_WAY) ? NT_TILE_EMPTY : tiles[k];
    }
    nt_status s = nt_map_set_tiles(w->map, tiles, count);
    if (s != NT_OK) {
        nt__free(tmp);
        return s;
    }
    w->map_epoch++;
    if (tmp) {
        nt_map_set_tiles(w->solid, tmp, n);
        nt__free(tmp);
    }
    for (int32_t i = 0; i < w->body_hwm; i++) w->bodies[i].ntc = 0;
    nt__wake_all(w);
    return NT_OK;
}

nt_status nt_world_set_material(nt_world *w, int index, nt_material m)
{
    NT__CHECK_LOCK(w);
    if (!w) return NT_ERR_INVALID_ARGUMENT;
    if (index < 0 || index >= NT_MAX_MATERIALS) return NT_ERR_OUT_OF_RANGE;
    nt_status s = check_material(&w->def, m);
    if (s != NT_OK) return s;
    w->materials[index] = m;
    w->force_epoch++; /* resting bodies' friction is answered again (NT__MF_HELD) */
    return NT_OK;
}

nt_material nt_world_get_material(const nt_world *w, int index)
{
    nt_material m = {0, 0};
    if (!w || index < 0 || index >= NT_MAX_MATERIALS) return m;
    return w->materials[index];
}

static int in_map(const nt_world *w, int x, int y) { return x >= 0 && y >= 0 && x < w->map->w && y < w->map->h; }

nt_status nt_world_set_cell_material(nt_world *w, int x, int y, int index)
{
    NT__CHECK_LOCK(w);
    if (!w) return NT_ERR_INVALID_ARGUMENT;
    if (!in_map(w, x, y) || index < 0 || index >= NT_MAX_MATERIALS) return NT_ERR_OUT_OF_RANGE;
    size_t n = (size_t)w->map->w * (size_t)w->map->h;
    if (!w->cell_mat) {
        if (index == 0) return NT_OK;
        w->cell_mat = (uint8_t *)nt__alloc(n);
        if (!w->cell_mat) return NT_ERR_OUT_OF_MEMORY;
        memset(w->cell_mat, 0, n);
    }
    w->cell_mat[(size_t)y * (size_t)w->map->w + (size_t)x] = (uint8_t)index;
    w->map_epoch++;
    return NT_OK;
}

int nt_world_get_cell_material(const nt_world *w, int x, int y)
{
    if (!w || !w->cell_mat || !in_map(w, x, y)) return 0;
    return w->cell_mat[(size_t)y * (size_t)w->map->w + (size_t)x];
}

nt_status nt_world_set_cell_flags(nt_world *w, int x, int y, uint32_t flags)
{
    NT__CHECK_LOCK(w);
    if (!w) return NT_ERR_INVALID_ARGUMENT;
    if (!in_map(w, x, y)) return NT_ERR_OUT_OF_RANGE;
    if (flags & ~NT_CELL_ONE_WAY) return NT_ERR_INVALID_ARGUMENT;
    size_t n = (size_t)w->map->w * (size_t)w->map->h;
    size_t k = (size_t)y * (size_t)w->map->w + (size_t)x;
    if (!w->cell_flags) {
        if (flags == 0) return NT_OK;
        uint8_t *f = (uint8_t *)nt__alloc(n);
        if (!f) return NT_ERR_OUT_OF_MEMORY;
        memset(f, 0, n);
        w->cell_flags = f;
    }
    if ((flags & NT_CELL_ONE_WAY) && !w->solid) {
        /* The map without one-way tiles: built on the first one-way cell. */
        nt_map_def md;
        md.width = w->map->w;
        md.height = w->map->h;
        md.cell_size = w->map->cell;
        nt_map *solid = NULL;
        nt_status s = nt_map_create(&md, &solid);
        if (s != NT_OK) return s;
        uint8_t *tmp = (uint8_t *)nt__alloc(n);
        if (!tmp) {
            nt_map_destroy(solid);
            return NT_ERR_OUT_OF_MEMORY;
        }
        for (size_t i = 0; i < n; i++) tmp[i] = (w->cell_flags[i] & NT_CELL_ONE_WAY) ? 0 : w->map->cells[i].tile;
        nt_map_set_tiles(solid, tmp, n);
        nt__free(tmp);
        w->solid = solid;
    }
    uint8_t old = w->cell_flags[k];
    w->cell_flags[k] = (uint8_t)flags;
    w->map_epoch++;
    if ((old ^ flags) & NT_CELL_ONE_WAY) {
        w->oneway_count += (flags & NT_CELL_ONE_WAY) ? 1 : -1;
        nt_map_set_tile(w->solid, x, y, (flags & NT_CELL_ONE_WAY) ? NT_TILE_EMPTY : w->map->cells[k].tile);
        nt__wake_near_cells(w, x, y, x, y);
    }
    return NT_OK;
}

uint32_t nt_world_get_cell_flags(const nt_world *w, int x, int y) { return w ? nt__cell_flags(w, x, y) : 0; }

/* ---------------------------------------------------------------- bodies */

nt_body_def nt_default_body_def(void)
{
    nt_body_def d;
    memset(&d, 0, sizeof d);
    d.type = NT_BODY_DYNAMIC;
    d.shape = nt_shape_aabb(6, 6);
    d.position = nt_v2(0, 0);
    d.velocity = nt_v2(0, 0);
    d.mass = 1;
    d.gravity_scale = 1;
    d.linear_drag = 0;
    d.material.friction = (nt_real)0.05;
    d.material.bounce = (nt_real)0.3;
    d.category = 1;
    d.mask = 0xffffffffu;
    d.is_sensor = false;
    d.enable_sleep = true;
    d.is_awake = true;
    d.enable_hit_events = true;
    d.user_data = NULL;
    return d;
}

static nt_status check_shape(const nt_world *w, nt_shape s)
{
    if (!finite2(s.half)) return NT_ERR_NON_FINITE;
    if (s.type != NT_SHAPE_AABB && s.type != NT_SHAPE_CIRCLE) return NT_ERR_INVALID_ARGUMENT;
    if (s.half.x <= 0 || s.half.y <= 0) return NT_ERR_INVALID_ARGUMENT;
    if (s.type == NT_SHAPE_CIRCLE && s.half.x != s.half.y) return NT_ERR_INVALID_ARGUMENT;
    nt_real cap = w->cell * (nt_real)NT_MAX_HALF_CELLS;
    if (s.half.x > cap || s.half.y > cap) return NT_ERR_SHAPE_TOO_LARGE;
    return NT_OK;
}

/* A body above half a cell must lie wholly inside the map where it is placed: the
 * resolution brings a small body back from beyond the border, but a large one
 * reaching over the edge would be placed where the map cannot describe it. */
static int fits_placement(const nt_world *w, nt_vec2 p, nt_vec2 half)
{
    nt_real lim = w->cell * (nt_real)0.5;
    if (half.x <= lim && half.y <= lim) return 1;
    return p.x - half.x >= 0 && p.y - half.y >= 0 && p.x + half.x <= (nt_real)w->map->w * w->cell &&
           p.y + half.y <= (nt_real)w->map->h * w->cell;
}

/* Positions must lie within NT_WORLD_REACH_CELLS cells of the map: beyond that the
 * resolution cannot bring a body back (and far enough out, float positions stop
 * resolving a cell at all). */
static int in_reach(const nt_world *w, nt_vec2 p)
{
    nt_real m = w->cell * NT_WORLD_REACH_CELLS;
    return p.x >= -m && p.y >= -m && p.x <= (nt_real)w->map->w * w->cell + m &&
           p.y <= (nt_real)w->map->h * w->cell + m;
}

static nt_status check_body_def(const nt_world *w, const nt_body_def *d)
{
    if (d->type != NT_BODY_STATIC && d->type != NT_BODY_KINEMATIC && d->type != NT_BODY_DYNAMIC)
        return NT_ERR_INVALID_ARGUMENT;
    if (!finite2(d->position) || !finite2(d->velocity) || !nt__finite(d->mass) || !nt__finite(d->gravity_scale) ||
        !nt__finite(d->linear_drag))
        return NT_ERR_NON_FINITE;
    nt_status s = check_shape(w, d->shape);
    if (s != NT_OK) return s;
    s = check_material(&w->def, d->material);
    if (s != NT_OK) return s;
    if (!in_reach(w, d->position) || !fits_placement(w, d->position, d->shape.half)) return NT_ERR_OUT_OF_RANGE;
    if (d->type == NT_BODY_DYNAMIC && d->mass <= 0) return NT_ERR_INVALID_ARGUMENT;
    /* A denormal mass's inverse overflows the solver's products (positions turned NaN,
     * found by the world fuzzer): masses are kept within a range whose inverses are
     * well scaled in float. */
    if (d->type == NT_BODY_DYNAMIC && !(d->mass >= NT_MIN_MASS && d->mass <= NT_MAX_MASS)) return NT_ERR_OUT_OF_RANGE;
    if (d->linear_drag < 0) return NT_ERR_INVALID_ARGUMENT;
    if (!gravity_scale_in_range(d->gravity_scale)) return NT_ERR_OUT_OF_RANGE;
    return NT_OK;
}

nt_status nt_body_create(nt_world *w, const nt_body_def *def, nt_body_id *out)
{
    if (out) *out = nt_null_body_id();
    if (!w || !def || !out) return NT_ERR_INVALID_ARGUMENT;
    NT__CHECK_LOCK(w);
    nt_status s = check_body_def(w, def);
    if (s != NT_OK) return s;
    if (w->body_count >= NT_MAX_BODIES) return NT_ERR_LIMIT;
    int in_grid = def->mask != 0 && def->category != 0;
    if (in_grid) {
        s = nt__grid_enable(w, nt__grid_level(w, def->shape.half));
        if (s != NT_OK) return s;
    }
    int32_t i;
    if (w->free_head >= 0) {
        i = w->free_head;
    } else {
        if (w->body_hwm == w->body_cap) {
            long long cap = (long long)w->body_cap * 2;
            if (cap > 0x7fffffff) cap = 0x7fffffff;
            s = reserve_bodies(w, (int)cap);
            if (s != NT_OK) return s;
        }
        i = w->body_hwm;
    }
    /* Committed: nothing below can fail. */
    nt__body *b = &w->bodies[i];
    uint32_t gen;
    if (i == w->free_head) {
        gen = b->generation;
        w->free_head = b->sleep_next;
    } else {
        gen = 1;
        w->body_hwm++;
    }
    memset(b, 0, sizeof *b);
    b->generation = gen;
    b->p = def->position;
    b->v = def->type == NT_BODY_STATIC ? nt_v2(0, 0) : def->velocity;
    b->half = def->shape.half;
    b->shape = (uint8_t)def->shape.type;
    b->type = (uint8_t)def->type;
    b->inv_mass = def->type == NT_BODY_DYNAMIC ? 1 / def->mass : 0;
    b->gravity_scale = def->gravity_scale;
    b->drag = def->linear_drag;
    b->friction = def->material.friction;
    b->bounce = def->material.bounce;
    b->category = def->category;
    b->mask = def->mask;
    b->flags = NT__BF_ALIVE | (def->is_sensor ? NT__BF_SENSOR : 0) | (def->enable_sleep ? NT__BF_SLEEP_OK : 0) |
               (def->enable_hit_events ? NT__BF_HITS : 0) |
               (def->shape.half.x > w->cell * (nt_real)0.5 || def->shape.half.y > w->cell * (nt_real)0.5 ? NT__BF_LARGE : 0);
    b->awake_slot = -1;
    b->sleep_next = -1;
    b->one_way = def->is_one_way ? 1 : 0;
    b->motion = NT__MF_AIR; /* created touching no tile: in the air since before its first step */
    w->one_way_bodies += b->one_way;
    b->gcell = -1;
    b->gnext = b->gprev = -1;
    nt__body_cold *c = &w->cold[i];
    c->user_data = def->user_data;
    c->mass = def->type == NT_BODY_DYNAMIC ? def->mass : 0;
    c->cprev = w->last;
    c->cnext = -1;
    c->park_head = -1;
    c->character = -1;
    if (w->last >= 0) w->cold[w->last].cnext = i;
    else w->first = i;
    w->last = i;
    w->body_count++;
    if (def->type == NT_BODY_KINEMATIC || (def->type == NT_BODY_DYNAMIC && def->is_awake)) nt__awake_add(w, i);
    else if (def->type == NT_BODY_DYNAMIC) b->sleep_next = i, b->v = nt_v2(0, 0);
    if (in_grid) {
        b->glist = b->awake_slot >= 0 ? NT__LIST_ACTIVE : NT__LIST_REST;
        nt__grid_insert(w, i);
    }
    *out = make_id(w, i);
    return NT_OK;
}

nt_status nt_body_destroy(nt_world *w, nt_body_id id)
{
    NT__CHECK_LOCK(w);
    nt__body *b = get_body(w, id);
    if (!b) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    int32_t i = id.index1 - 1;
    /* Bodies resting on this one must not float: wake its group and its partners. */
    if (b->type == NT_BODY_DYNAMIC && b->awake_slot < 0) nt__wake_group(w, i);
    nt__wake_partners(w, i);
    nt__awake_remove(w, i);
    nt__character_remove(w, i);
    w->one_way_bodies -= b->one_way;
    if (b->gcell >= 0) nt__grid_remove(w, i);
    b->flags = 0;
    b->generation++;
    b->sleep_next = w->free_head;
    w->free_head = i;
    nt__body_cold *c = &w->cold[i];
    if (c->cprev >= 0) w->cold[c->cprev].cnext = c->cnext;
    else w->first = c->cnext;
    if (c->cnext >= 0) w->cold[c->cnext].cprev = c->cprev;
    else w->last = c->cprev;
    w->body_count--;
    /* Its parked contacts go back to give end events: its chain is walked. */
    nt__note_woken(w, i);
    nt__unpark(w);
    return NT_OK;
}

bool nt_body_is_valid(const nt_world *w, nt_body_id id) { return get_body(w, id) != NULL; }

nt_body_type nt_body_get_type(const nt_world *w, nt_body_id id)
{
    const nt__body *b = get_body(w, id);
    return b ? nt__character_type(w, id.index1 - 1) : NT_BODY_STATIC;
}

/* The world owns the character records (character.c fills them): a destroyed body
 * stops being one, and a body's own type is the one it was created as. */
void nt__character_remove(nt_world *w, int32_t i)
{
    int32_t k = w->cold[i].character;
    if (k < 0) return;
    w->cold[i].character = -1;
    w->chars[k] = w->chars[--w->char_count];
    if (k < w->char_count) w->cold[w->chars[k].body].character = k;
}

nt_body_type nt__character_type(const nt_world *w, int32_t i)
{
    int32_t k = w->cold[i].character;
    return k >= 0 ? (nt_body_type)w->chars[k].type : (nt_body_type)w->bodies[i].type;
}

void nt__set_kinematic(nt_world *w, int32_t i, bool kinematic)
{
    nt__body *b = &w->bodies[i];
    if (kinematic) {
        /* Awake for good (kinematic bodies never sleep), its contacts back in play. */
        if (b->awake_slot < 0) nt__wake(w, i);
        b->type = NT_BODY_KINEMATIC;
    } else {
        b->type = NT_BODY_DYNAMIC;
        b->sleep_time = 0;
    }
    b->v = nt_v2(0, 0);
    b->motion &= (uint8_t)~NT__MF_HELD;
}

nt_shape nt_body_get_shape(const nt_world *w, nt_body_id id)
{
    const nt__body *b = get_body(w, id);
    return b ? nt__body_shape(b) : nt_shape_aabb(0, 0);
}

nt_real nt_body_get_mass(const nt_world *w, nt_body_id id)
{
    return get_body(w, id) ? w->cold[id.index1 - 1].mass : 0;
}

nt_vec2 nt_body_get_position(const nt_world *w, nt_body_id id)
{
    const nt__body *b = get_body(w, id);
    return b ? b->p : nt_v2(0, 0);
}

nt_status nt_body_set_position(nt_world *w, nt_body_id id, nt_vec2 p)
{
    NT__CHECK_LOCK(w);
    nt__body *b = get_body(w, id);
    if (!b) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    if (!finite2(p)) return NT_ERR_NON_FINITE;
    if (!in_reach(w, p) || !fits_placement(w, p, b->half)) return NT_ERR_OUT_OF_RANGE;
    int32_t i = id.index1 - 1;
    b->p = p;
    b->ntc = 0;
    /* Its remembered contacts are gone: it is not resting where it rested (even when
     * put back at the same place), so the next step resolves it. */
    b->flags &= (uint8_t)~NT__BF_RESTING;
    b->motion &= (uint8_t)~NT__MF_HELD;
    if (b->gcell >= 0) nt__grid_update(w, i);
    if (b->type == NT_BODY_STATIC) nt__wake_partners(w, i);
    nt__wake(w, i);
    return NT_OK;
}

nt_vec2 nt_body_get_velocity(const nt_world *w, nt_body_id id)
{
    const nt__body *b = get_body(w, id);
    return b ? b->v : nt_v2(0, 0);
}

nt_status nt_body_set_velocity(nt_world *w, nt_body_id id, nt_vec2 v)
{
    NT__CHECK_LOCK(w);
    nt__body *b = get_body(w, id);
    if (!b) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    if (!finite2(v)) return NT_ERR_NON_FINITE;
    if (b->type == NT_BODY_STATIC) return NT_ERR_INVALID_ARGUMENT;
    int32_t i = id.index1 - 1;
    b->v = v;
    b->motion &= (uint8_t)~NT__MF_HELD; /* its forces start from another velocity */
    if (b->type == NT_BODY_KINEMATIC) nt__wake_partners(w, i);
    nt__wake(w, i);
    return NT_OK;
}

nt_status nt_body_apply_impulse(nt_world *w, nt_body_id id, nt_vec2 impulse)
{
    NT__CHECK_LOCK(w);
    nt__body *b = get_body(w, id);
    if (!b) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    if (!finite2(impulse)) return NT_ERR_NON_FINITE;
    if (b->type != NT_BODY_DYNAMIC) return NT_ERR_INVALID_ARGUMENT;
    nt_vec2 v = nt_v2(b->v.x + impulse.x * b->inv_mass, b->v.y + impulse.y * b->inv_mass);
    if (!finite2(v)) return NT_ERR_NON_FINITE;
    b->v = v;
    b->motion &= (uint8_t)~NT__MF_HELD;
    nt__wake(w, id.index1 - 1);
    return NT_OK;
}

nt_material nt_body_get_material(const nt_world *w, nt_body_id id)
{
    nt_material m = {0, 0};
    const nt__body *b = get_body(w, id);
    if (b) m.friction = b->friction, m.bounce = b->bounce;
    return m;
}

nt_status nt_body_set_material(nt_world *w, nt_body_id id, nt_material m)
{
    NT__CHECK_LOCK(w);
    nt__body *b = get_body(w, id);
    if (!b) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    nt_status s = check_material(&w->def, m);
    if (s != NT_OK) return s;
    b->friction = m.friction;
    b->bounce = m.bounce;
    b->motion &= (uint8_t)~NT__MF_HELD;
    return NT_OK;
}

nt_status nt_body_set_gravity_scale(nt_world *w, nt_body_id id, nt_real scale)
{
    NT__CHECK_LOCK(w);
    nt__body *b = get_body(w, id);
    if (!b) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    if (!nt__finite(scale)) return NT_ERR_NON_FINITE;
    if (!gravity_scale_in_range(scale)) return NT_ERR_OUT_OF_RANGE;
    b->gravity_scale = scale;
    b->motion &= (uint8_t)~NT__MF_HELD;
    nt__wake(w, id.index1 - 1);
    return NT_OK;
}

nt_status nt_body_set_linear_drag(nt_world *w, nt_body_id id, nt_real drag)
{
    NT__CHECK_LOCK(w);
    nt__body *b = get_body(w, id);
    if (!b) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    if (!nt__finite(drag)) return NT_ERR_NON_FINITE;
    if (drag < 0) return NT_ERR_INVALID_ARGUMENT;
    b->drag = drag;
    b->motion &= (uint8_t)~NT__MF_HELD;
    return NT_OK;
}

nt_status nt_body_set_filter(nt_world *w, nt_body_id id, uint32_t category, uint32_t mask)
{
    NT__CHECK_LOCK(w);
    nt__body *b = get_body(w, id);
    if (!b) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    int32_t i = id.index1 - 1;
    int was = b->gcell >= 0, will = category != 0 && mask != 0;
    if (will) {
        nt_status s = nt__grid_enable(w, nt__grid_level(w, b->half));
        if (s != NT_OK) return s;
    }
    b->category = category;
    b->mask = mask;
    w->grid_cat |= will ? category : 0u;
    w->grid_mask |= will ? mask : 0u;
    if (was && !will) nt__grid_remove(w, i);
    if (!was && will) {
        b->glist = b->awake_slot >= 0 ? NT__LIST_ACTIVE : NT__LIST_REST;
        nt__grid_insert(w, i);
    }
    nt__wake_partners(w, i);
    nt__wake(w, i);
    return NT_OK;
}

uint32_t nt_body_get_category(const nt_world *w, nt_body_id id)
{
    const nt__body *b = get_body(w, id);
    return b ? b->category : 0;
}

uint32_t nt_body_get_mask(const nt_world *w, nt_body_id id)
{
    const nt__body *b = get_body(w, id);
    return b ? b->mask : 0;
}

bool nt_body_is_awake(const nt_world *w, nt_body_id id)
{
    const nt__body *b = get_body(w, id);
    return b && b->awake_slot >= 0;
}

nt_status nt_body_set_awake(nt_world *w, nt_body_id id, bool awake)
{
    NT__CHECK_LOCK(w);
    nt__body *b = get_body(w, id);
    if (!b) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    int32_t i = id.index1 - 1;
    if (b->type != NT_BODY_DYNAMIC) return NT_OK;
    if (awake) {
        nt__wake(w, i);
    } else if (b->awake_slot >= 0) {
        nt__sleep_body(w, i);
        b->sleep_next = i; /* a group of its own */
    }
    return NT_OK;
}

nt_status nt_body_enable_sleep(nt_world *w, nt_body_id id, bool enable)
{
    NT__CHECK_LOCK(w);
    nt__body *b = get_body(w, id);
    if (!b) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    if (enable) {
        b->flags |= NT__BF_SLEEP_OK;
    } else {
        b->flags &= (uint8_t)~NT__BF_SLEEP_OK;
        nt__wake(w, id.index1 - 1);
    }
    return NT_OK;
}

void *nt_body_get_user_data(const nt_world *w, nt_body_id id)
{
    return get_body(w, id) ? w->cold[id.index1 - 1].user_data : NULL;
}

nt_status nt_body_set_user_data(nt_world *w, nt_body_id id, void *user_data)
{
    NT__CHECK_LOCK(w);
    if (!get_body(w, id)) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    w->cold[id.index1 - 1].user_data = user_data;
    return NT_OK;
}

nt_status nt_body_get_tile_contacts(const nt_world *w, nt_body_id id, nt_body_tile_contacts *out)
{
    if (!out) return NT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    const nt__body *b = get_body(w, id);
    if (!b) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    out->count = b->ntc;
    for (int k = 0; k < b->ntc; k++) {
        const nt__tile_ct *t = &b->tc[k];
        out->contacts[k].normal = t->n;
        out->contacts[k].depth = t->depth;
        out->contacts[k].cell_x = t->cx;
        out->contacts[k].cell_y = t->cy;
        if (t->n.y <= -w->floor_cos) {
            /* The flattest floor wins. */
            if (!out->on_floor || t->n.y < out->floor_normal.y) out->floor_normal = t->n;
            out->on_floor = true;
        } else if (t->n.y >= w->floor_cos) {
            out->on_ceiling = true;
        } else if (t->n.x > 0) {
            out->wall_left = true;
        } else {
            out->wall_right = true;
        }
    }
    return NT_OK;
}

/* Add contact c to the list of body i when it touches (see nt_body_get_contacts). */
static void list_contact(const nt_world *w, const nt__contact *c, int32_t i, nt_body_contact *out, int capacity, int *n)
{
    if (!(c->flags & NT__CF_TOUCH) || (c->flags & (NT__CF_SENSOR | NT__CF_GONE)) || !nt__contact_is_live(w, c)) return;
    int32_t a = (int32_t)(c->key >> 32), b = (int32_t)(c->key & 0xffffffffu);
    if (a != i && b != i) return;
    nt_body_contact e;
    e.other = make_id(w, a == i ? b : a);
    e.normal = a == i ? nt_v2(-c->n.x, -c->n.y) : c->n; /* c->n points from a to b */
    e.depth = c->depth;
    /* Keep the first `capacity` by the other body's slot (contacts come sorted by
     * (a, b), not by the other): insert, dropping the last when full. */
    int k = *n < capacity ? *n : capacity;
    (*n)++;
    if (k == capacity && (k == 0 || out[k - 1].other.index1 < e.other.index1)) return;
    if (k == capacity) k--;
    for (; k > 0 && out[k - 1].other.index1 > e.other.index1; k--) out[k] = out[k - 1];
    out[k] = e;
}

nt_status nt_body_get_contacts(const nt_world *w, nt_body_id id, nt_body_contact *out, int capacity, int *count)
{
    if (count) *count = 0;
    if (!count || capacity < 0 || (capacity > 0 && !out)) return NT_ERR_INVALID_ARGUMENT;
    const nt__body *b = get_body(w, id);
    if (!b) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    int32_t i = id.index1 - 1, n = 0;
    for (int k = 0; k < w->con_count; k++) list_contact(w, &w->con[k], i, out, capacity, &n);
    for (int32_t k = w->cold[i].park_head; k >= 0;) {
        const nt__contact *c = &w->parked[k];
        list_contact(w, c, i, out, capacity, &n);
        k = w->park_link[k].next[(int32_t)(c->key >> 32) == i ? 0 : 1];
    }
    *count = n;
    return NT_OK;
}

/* ---------------------------------------------------------------- events */

nt_contact_events nt_world_get_contact_events(const nt_world *w)
{
    nt_contact_events e;
    memset(&e, 0, sizeof e);
    if (!w) return e;
    e.begin_events = w->ev_begin;
    e.begin_count = w->n_begin;
    e.end_events = w->ev_end;
    e.end_count = w->n_end;
    e.hit_events = w->ev_hit;
    e.hit_count = w->n_hit;
    return e;
}

nt_sensor_events nt_world_get_sensor_events(const nt_world *w)
{
    nt_sensor_events e;
    memset(&e, 0, sizeof e);
    if (!w) return e;
    e.begin_events = w->ev_sbegin;
    e.begin_count = w->n_sbegin;
    e.end_events = w->ev_send;
    e.end_count = w->n_send;
    return e;
}

/* ---------------------------------------------------------------- hash */

static uint64_t fnv_real(uint64_t h, nt_real x)
{
    unsigned char bytes[sizeof(nt_real)];
    memcpy(bytes, &x, sizeof x);
    for (size_t k = 0; k < sizeof bytes; k++) {
        h ^= bytes[k];
        h *= 1099511628211ull;
    }
    return h;
}

uint64_t nt_world_hash(const nt_world *w)
{
    uint64_t h = 14695981039346656037ull;
    if (!w) return h;
    for (int32_t i = w->first; i >= 0; i = w->cold[i].cnext) {
        const nt__body *b = &w->bodies[i];
        h = fnv_real(h, b->p.x);
        h = fnv_real(h, b->p.y);
        h = fnv_real(h, b->v.x);
        h = fnv_real(h, b->v.y);
    }
    return h;
}

/* ---------------------------------------------------------------- queries */

nt_query_filter nt_default_query_filter(void)
{
    nt_query_filter f;
    memset(&f, 0, sizeof f);
    f.mask = 0xffffffffu;
    f.tiles = true;
    return f;
}

/* The filter's mask, ignore list and callback, in that order (cheapest first). */
bool nt__query_sees(const nt_world *w, int32_t i, const nt_query_filter *f)
{
    const nt__body *b = &w->bodies[i];
    if ((b->flags & NT__BF_SENSOR) || (b->category & f->mask) == 0) return false;
    int n = f->ignore_count < NT_QUERY_IGNORE_MAX ? f->ignore_count : NT_QUERY_IGNORE_MAX;
    if (n <= 0 && !f->accept) return true;
    nt_body_id id = make_id(w, i);
    for (int k = 0; k < n; k++)
        if (nt_body_id_equals(id, f->ignore[k])) return false;
    return !f->accept || f->accept(id, f->accept_context);
}

/* Segment p0 + t d (t in [0, 1]) entering a body's interior: first t and normal. */
static int ray_body(const nt__body *b, nt_vec2 p0, nt_vec2 d, nt_real *t_out, nt_vec2 *n_out)
{
    nt_vec2 m = nt__sub(p0, b->p);
    if (b->shape == NT_SHAPE_CIRCLE) {
        nt_real r = b->half.x;
        nt_real c = nt__dot(m, m) - r * r;
        if (c < 0) {
            *t_out = 0;
            *n_out = nt_v2(0, 0);
            return 1;
        }
        nt_real a = nt__dot(d, d);
        if (a <= 0) return 0;
        nt_real bb = nt__dot(m, d);
        if (bb >= 0) return 0; /* moving away (or tangent from the surface) */
        nt_real disc = bb * bb - a * c;
        if (disc <= 0) return 0; /* misses or grazes */
        nt_real t = (-bb - nt__sqrt(disc)) / a;
        if (t < 0) t = 0;
        if (t > 1) return 0;
        nt_vec2 q = nt__add(m, nt__scale(d, t));
        nt_real len = nt__len(q);
        *t_out = t;
        *n_out = len > 0 ? nt__scale(q, 1 / len) : nt_v2(0, 0);
        return 1;
    }
    /* Slabs: the segment is inside the open box for t in (tenter, texit). */
    nt_real tenter = -NT_REAL_MAX, texit = NT_REAL_MAX;
    int axis = -1;
    nt_real comp[2] = {m.x, m.y}, dir[2] = {d.x, d.y}, half[2] = {b->half.x, b->half.y};
    for (int k = 0; k < 2; k++) {
        if (dir[k] == 0) {
            if (comp[k] <= -half[k] || comp[k] >= half[k]) return 0;
            continue;
        }
        nt_real inv = 1 / dir[k];
        nt_real t1 = (-half[k] - comp[k]) * inv, t2 = (half[k] - comp[k]) * inv;
        if (t1 > t2) {
            nt_real tt = t1;
            t1 = t2;
            t2 = tt;
        }
        if (t1 > tenter) {
            tenter = t1;
            axis = k;
        }
        if (t2 < texit) texit = t2;
    }
    if (!(tenter < texit) || texit <= 0) return 0;
    if (tenter < 0) {
        *t_out = 0;
        *n_out = nt_v2(0, 0);
        return 1;
    }
    if (tenter > 1) return 0;
    *t_out = tenter;
    *n_out = axis == 0 ? nt_v2(d.x > 0 ? (nt_real)(-1) : (nt_real)1, 0) : nt_v2(0, d.y > 0 ? (nt_real)(-1) : (nt_real)1);
    return 1;
}

/* One level of the broad-phase grid, as the ray walk sees it. */
typedef struct ray_level {
    const int32_t *heads;
    int gw, gh;
    nt_real size;
} ray_level;

static void cell_clamped(const ray_level *L, int x, int y, int *cx, int *cy)
{
    *cx = x < 0 ? 0 : (x >= L->gw ? L->gw - 1 : x);
    *cy = y < 0 ? 0 : (y >= L->gh ? L->gh - 1 : y);
}

/* Test the bodies of one grid cell against the segment p0 + t d. */
static void ray_cell(const nt_world *w, const ray_level *L, int32_t cell, nt_vec2 p0, nt_vec2 d,
                     nt_query_filter filter, nt_world_ray_hit *best)
{
    for (int list = 0; list < 2; list++)
        for (int32_t j = L->heads[2 * cell + list]; j >= 0; j = w->bodies[j].gnext) {
            const nt__body *b = &w->bodies[j];
            if (!nt__query_sees(w, j, &filter)) continue;
            nt_real t;
            nt_vec2 n;
            if (ray_body(b, p0, d, &t, &n) && t < best->fraction) {
                best->fraction = t;
                best->body = make_id(w, j);
                best->normal = n;
                best->point = nt__add(p0, nt__scale(d, t));
                best->cell_x = best->cell_y = 0;
            }
        }
}

/* Walk the cells of a grid level that the segment crosses from t0 to t1 (Amanatides
 * & Woo), testing the bodies of the 3 x 3 cells around each: a body reaches 1.5 of
 * its level's cells from its cell. */
static void ray_walk(const nt_world *w, const ray_level *L, nt_vec2 p0, nt_vec2 d, nt_real t0, nt_real t1,
                     nt_query_filter filter, nt_world_ray_hit *best)
{
    nt_real ic = 1 / L->size, size = L->size;
    nt_vec2 a = nt__add(p0, nt__scale(d, t0)), e = nt__add(p0, nt__scale(d, t1));
    int cx = nt__floor_int(a.x * ic), cy = nt__floor_int(a.y * ic);
    int ex = nt__floor_int(e.x * ic), ey = nt__floor_int(e.y * ic);
    int sx = d.x > 0 ? 1 : (d.x < 0 ? -1 : 0), sy = d.y > 0 ? 1 : (d.y < 0 ? -1 : 0);
    nt_real tdx = sx ? size / nt__fabs(d.x) : NT_REAL_MAX, tdy = sy ? size / nt__fabs(d.y) : NT_REAL_MAX;
    nt_real tx = sx ? (((nt_real)cx + (sx > 0)) * size - p0.x) / d.x : NT_REAL_MAX;
    nt_real ty = sy ? (((nt_real)cy + (sy > 0)) * size - p0.y) / d.y : NT_REAL_MAX;
    nt_real len = nt__len(d);
    nt_real reach = len > 0 ? (nt_real)2 * size / len : NT_REAL_MAX;
    nt_real t_cell = t0;
    long guard = labs((long)ex - cx) + labs((long)ey - cy) + 2;
    for (long step = 0; step <= guard; step++) {
        if (t_cell > t1 || t_cell > best->fraction + reach) break;
        for (int oy = -1; oy <= 1; oy++)
            for (int ox = -1; ox <= 1; ox++) {
                int gx, gy;
                cell_clamped(L, cx + ox, cy + oy, &gx, &gy);
                ray_cell(w, L, gy * L->gw + gx, p0, d, filter, best);
            }
        if (cx == ex && cy == ey) break;
        if (tx < ty) {
            t_cell = tx;
            tx += tdx;
            cx += sx;
        } else {
            t_cell = ty;
            ty += tdy;
            cy += sy;
        }
    }
}

/* The bodies of one grid level against the segment: the walk over the part of the
 * segment within 2 of the level's cells of the map (Liang-Barsky: a far-away segment
 * must not cost a walk through empty space), and the edge cells' lists, where bodies
 * outside the map live, when part of the segment lies beyond that. */
static void ray_level_bodies(const nt_world *w, int level, nt_vec2 p0, nt_vec2 d, nt_query_filter filter,
                             nt_world_ray_hit *best)
{
    ray_level L;
    nt__grid_level_view(w, level, &L.heads, &L.gw, &L.gh, &L.size);
    nt_real t0 = 0, t1 = 1;
    nt_real lo[2] = {-2 * L.size, -2 * L.size};
    nt_real hi[2] = {((nt_real)L.gw + 2) * L.size, ((nt_real)L.gh + 2) * L.size};
    nt_real o[2] = {p0.x, p0.y}, dd[2] = {d.x, d.y};
    for (int k = 0; k < 2 && t0 <= t1; k++) {
        if (dd[k] == 0) {
            if (o[k] < lo[k] || o[k] > hi[k]) t1 = -1;
            continue;
        }
        nt_real ta = (lo[k] - o[k]) / dd[k], tb = (hi[k] - o[k]) / dd[k];
        if (ta > tb) {
            nt_real t = ta;
            ta = tb;
            tb = t;
        }
        if (ta > t0) t0 = ta;
        if (tb < t1) t1 = tb;
    }
    if (t0 <= t1) ray_walk(w, &L, p0, d, t0, t1, filter, best);
    if (t0 > 0 || t1 < 1) {
        for (int gy = 0; gy < L.gh; gy++)
            for (int gx = 0; gx < L.gw; gx++) {
                if (gy != 0 && gy != L.gh - 1 && gx != 0 && gx != L.gw - 1) continue;
                ray_cell(w, &L, gy * L.gw + gx, p0, d, filter, best);
            }
    }
}

bool nt_world_raycast(const nt_world *w, nt_vec2 p0, nt_vec2 p1, nt_query_filter filter, nt_world_ray_hit *out)
{
    nt_world_ray_hit best;
    memset(&best, 0, sizeof best);
    best.fraction = 2;
    if (out) memset(out, 0, sizeof *out);
    if (!w || !finite2(p0) || !finite2(p1)) return false;
    if (filter.tiles) {
        nt_ray_hit h;
        if (nt_map_raycast(w->map, p0, p1, &h)) {
            best.fraction = h.fraction;
            best.point = h.point;
            best.normal = h.normal;
            best.cell_x = h.cell_x;
            best.cell_y = h.cell_y;
        }
    }
    if (w->heads && w->grid_bodies > 0 && filter.mask != 0) {
        nt_vec2 d = nt__sub(p1, p0);
        NT__LOCK(w); /* the filter's accept callback */
        for (int lv = 0; lv < NT__LEVELS; lv++)
            if (nt__grid_level_used(w, lv)) ray_level_bodies(w, lv, p0, d, filter, &best);
        NT__UNLOCK(w);
    }
    if (best.fraction > 1) return false;
    if (out) *out = best;
    return true;
}

typedef struct point_ctx {
    nt_vec2 lo, hi;
    nt_query_filter filter;
    nt_query_fn *fn;
    void *user;
    int count, stop, point;
} point_ctx;

static bool overlap_visit(const nt_world *w, int32_t i, void *vctx)
{
    point_ctx *q = (point_ctx *)vctx;
    const nt__body *b = &w->bodies[i];
    if (!nt__query_sees(w, i, &q->filter)) return true;
    int hit;
    if (q->point) {
        nt_real dx = q->lo.x - b->p.x, dy = q->lo.y - b->p.y;
        hit = b->shape == NT_SHAPE_CIRCLE ? dx * dx + dy * dy < b->half.x * b->half.x
                                          : nt__fabs(dx) < b->half.x && nt__fabs(dy) < b->half.y;
    } else if (b->shape == NT_SHAPE_CIRCLE) {
        nt_real cx = nt__clamp(b->p.x, q->lo.x, q->hi.x), cy = nt__clamp(b->p.y, q->lo.y, q->hi.y);
        nt_real dx = b->p.x - cx, dy = b->p.y - cy;
        hit = dx * dx + dy * dy < b->half.x * b->half.x;
    } else {
        hit = b->p.x - b->half.x < q->hi.x && b->p.x + b->half.x > q->lo.x && b->p.y - b->half.y < q->hi.y &&
              b->p.y + b->half.y > q->lo.y;
    }
    if (!hit) return true;
    q->count++;
    if (q->fn && !q->fn(make_id(w, i), q->user)) {
        q->stop = 1;
        return false;
    }
    return true;
}

int nt_world_query_point(const nt_world *w, nt_vec2 p, nt_query_filter filter, nt_query_fn *fn, void *context)
{
    if (!w || !finite2(p) || !w->heads) return 0;
    point_ctx q;
    memset(&q, 0, sizeof q);
    q.lo = q.hi = p;
    q.filter = filter;
    q.fn = fn;
    q.user = context;
    q.point = 1;
    NT__LOCK(w);
    nt__grid_visit(w, p, p, overlap_visit, &q);
    NT__UNLOCK(w);
    return q.count;
}

int nt_world_overlap_aabb(const nt_world *w, nt_vec2 lo, nt_vec2 hi, nt_query_filter filter, nt_query_fn *fn,
                          void *context)
{
    if (!w || !finite2(lo) || !finite2(hi) || lo.x > hi.x || lo.y > hi.y || !w->heads) return 0;
    point_ctx q;
    memset(&q, 0, sizeof q);
    q.lo = lo;
    q.hi = hi;
    q.filter = filter;
    q.fn = fn;
    q.user = context;
    NT__LOCK(w);
    nt__grid_visit(w, lo, hi, overlap_visit, &q);
    NT__UNLOCK(w);
    return q.count;
}

/* ---------------------------------------------------------------- debug draw */

nt_debug_draw nt_default_debug_draw(void)
{
    nt_debug_draw d;
    memset(&d, 0, sizeof d);
    d.draw_tiles = true;
    d.draw_bodies = true;
    d.projection_scale = 1;
    return d;
}

static void draw_tile(const nt_debug_draw *dd, int t, nt_real ox, nt_real oy, nt_real s)
{
    const nt_tile_info *info = &nt__tiles[t];
    nt_vec2 pts[4 + 9];
    int n = 0;
    for (int k = 0; k < info->vertex_count; k++)
        pts[n++] = nt_v2(ox + info->vertices[k].x * s, oy + info->vertices[k].y * s);
    if (info->cls == NT_CLASS_CONVEX || info->cls == NT_CLASS_CONCAVE) {
        /* The arc runs from the last straight corner back to the first. */
        nt_vec2 c = info->arc_center;
        nt_vec2 u0 = nt__sub(info->vertices[info->vertex_count - 1], c), u1 = nt__sub(info->vertices[0], c);
        for (int k = 1; k < 9; k++) {
            nt_real f = (nt_real)k / 9;
            nt_vec2 u = nt__add(nt__scale(u0, 1 - f), nt__scale(u1, f));
            nt_real len = nt__len(u);
            if (len > 0) u = nt__scale(u, 1 / len);
            pts[n++] = nt_v2(ox + (c.x + u.x) * s, oy + (c.y + u.y) * s);
        }
    }
    dd->draw_polygon(pts, n, info->cls == NT_CLASS_POLYGON ? 0x9fa8b3u : 0xb3a89fu, dd->context);
}

/* An arrow when the callback exists, else a segment. */
static void draw_vector(const nt_debug_draw *dd, nt_vec2 p, nt_vec2 v, uint32_t color)
{
    nt_vec2 q = nt__add(p, v);
    if (dd->draw_arrow) dd->draw_arrow(p, q, color, dd->context);
    else if (dd->draw_segment) dd->draw_segment(p, q, color, dd->context);
}

/* The occupied cells of the coarser grid levels (bodies above half a cell), each
 * level a shade lighter than the one below. */
static void draw_coarse_cells(const nt_world *w, const nt_debug_draw *dd)
{
    static const uint32_t shade[NT__LEVELS] = {0x404080u, 0x5050a0u, 0x6060c0u, 0x7070e0u};
    for (int lv = 1; lv < NT__LEVELS; lv++) {
        if (!nt__grid_level_used(w, lv)) continue;
        const int32_t *heads;
        int gw, gh;
        nt_real size;
        nt__grid_level_view(w, lv, &heads, &gw, &gh, &size);
        for (int y = 0; y < gh; y++)
            for (int x = 0; x < gw; x++) {
                int32_t cell = y * gw + x;
                if (heads[2 * cell] < 0 && heads[2 * cell + 1] < 0) continue;
                nt_real ox = (nt_real)x * size, oy = (nt_real)y * size;
                if (dd->use_bounds && (ox > dd->bounds_hi.x || oy > dd->bounds_hi.y || ox + size < dd->bounds_lo.x ||
                                       oy + size < dd->bounds_lo.y))
                    continue;
                nt_vec2 q[4] = {nt_v2(ox, oy), nt_v2(ox, oy + size), nt_v2(ox + size, oy + size), nt_v2(ox + size, oy)};
                dd->draw_polygon(q, 4, shade[lv], dd->context);
            }
    }
}

static void draw_world(const nt_world *w, const nt_debug_draw *dd);

bool nt_world_is_locked(const nt_world *w) { return w && w->locked > 0; }

void nt_world_draw(const nt_world *w, const nt_debug_draw *dd)
{
    if (!w || !dd) return;
    NT__LOCK(w);
    draw_world(w, dd);
    NT__UNLOCK(w);
}

static void draw_world(const nt_world *w, const nt_debug_draw *dd)
{
    nt_real s = w->cell, ic = w->inv_cell;
    int x0 = 0, y0 = 0, x1 = w->map->w - 1, y1 = w->map->h - 1;
    nt_vec2 lo = dd->bounds_lo, hi = dd->bounds_hi;
    if (dd->use_bounds) {
        int bx0 = nt__floor_int(lo.x * ic), by0 = nt__floor_int(lo.y * ic);
        int bx1 = nt__floor_int(hi.x * ic), by1 = nt__floor_int(hi.y * ic);
        if (bx0 > x0) x0 = bx0;
        if (by0 > y0) y0 = by0;
        if (bx1 < x1) x1 = bx1;
        if (by1 < y1) y1 = by1;
    }
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            nt_real ox = (nt_real)x * s, oy = (nt_real)y * s;
            int t = nt__map_tile(w->map, x, y);
            if (dd->draw_tiles && dd->draw_polygon && t != NT_TILE_EMPTY) draw_tile(dd, t, ox, oy, s);
            if (dd->draw_edges && dd->draw_segment) {
                for (int side = 0; side < 4; side++) {
                    nt_edge e = nt_map_get_edge(w->map, x, y, (nt_side)side);
                    if (e == NT_EDGE_OFF) continue;
                    nt_vec2 a, b;
                    switch (side) {
                    case NT_SIDE_LEFT: a = nt_v2(ox, oy), b = nt_v2(ox, oy + s); break;
                    case NT_SIDE_RIGHT: a = nt_v2(ox + s, oy), b = nt_v2(ox + s, oy + s); break;
                    case NT_SIDE_TOP: a = nt_v2(ox, oy), b = nt_v2(ox + s, oy); break;
                    default: a = nt_v2(ox, oy + s), b = nt_v2(ox + s, oy + s); break;
                    }
                    dd->draw_segment(a, b, e == NT_EDGE_SOLID ? 0xe04040u : 0xe0e040u, dd->context);
                }
            }
            if (dd->draw_grid && dd->draw_polygon && w->heads) {
                int32_t cell = y * w->grid_w + x;
                if (w->heads[2 * cell] >= 0 || w->heads[2 * cell + 1] >= 0) {
                    nt_vec2 q[4] = {nt_v2(ox, oy), nt_v2(ox, oy + s), nt_v2(ox + s, oy + s), nt_v2(ox + s, oy)};
                    dd->draw_polygon(q, 4, 0x404080u, dd->context);
                }
            }
        }
    if (dd->draw_grid && dd->draw_polygon) draw_coarse_cells(w, dd);
    for (int32_t i = w->first; i >= 0; i = w->cold[i].cnext) {
        const nt__body *b = &w->bodies[i];
        if (dd->use_bounds && (b->p.x + b->half.x < lo.x || b->p.x - b->half.x > hi.x ||
                               b->p.y + b->half.y < lo.y || b->p.y - b->half.y > hi.y))
            continue;
        if (dd->draw_bodies) {
            uint32_t color = b->type == NT_BODY_STATIC ? 0x80e680u
                             : b->type == NT_BODY_KINEMATIC ? 0x8080e6u
                             : b->awake_slot >= 0 ? 0xe6b34du
                                                  : 0x808080u;
            if (b->flags & NT__BF_SENSOR) color = 0xe680e6u;
            if (b->shape == NT_SHAPE_CIRCLE) {
                if (dd->draw_circle) dd->draw_circle(b->p, b->half.x, color, dd->context);
            } else if (dd->draw_box) {
                dd->draw_box(nt__sub(b->p, b->half), nt__add(b->p, b->half), color, dd->context);
            }
        }
        if (dd->draw_velocities && b->type != NT_BODY_STATIC)
            draw_vector(dd, b->p, nt__scale(b->v, (nt_real)0.1), 0x40c0c0u);
        if (dd->draw_velocity_split && b->ntc > 0 && b->type == NT_BODY_DYNAMIC) {
            /* Against the first surface: the part into/out of it and the part along it. */
            nt_vec2 n = b->tc[0].n;
            nt_vec2 vn = nt__scale(n, nt__dot(b->v, n)), vt = nt__sub(b->v, vn);
            draw_vector(dd, b->p, nt__scale(vn, (nt_real)0.1), 0xe04040u);
            draw_vector(dd, b->p, nt__scale(vt, (nt_real)0.1), 0x40e040u);
        }
        for (int k = 0; k < b->ntc; k++) {
            if (dd->draw_tile_contacts) draw_vector(dd, b->p, nt__scale(b->tc[k].n, s * (nt_real)0.5), 0xe08040u);
            if (dd->draw_projections)
                draw_vector(dd, b->p, nt__scale(b->tc[k].n, b->tc[k].depth * dd->projection_scale), 0xffe040u);
        }
    }
    if (dd->draw_contacts || dd->draw_projections)
        for (int k = 0; k < w->con_count; k++) {
            const nt__contact *c = &w->con[k];
            if (!nt__contact_is_live(w, c)) continue;
            const nt__body *a = &w->bodies[c->key >> 32], *b = &w->bodies[c->key & 0xffffffffu];
            nt_vec2 mid = nt__scale(nt__add(a->p, b->p), (nt_real)0.5);
            if (dd->use_bounds && (mid.x < lo.x || mid.x > hi.x || mid.y < lo.y || mid.y > hi.y)) continue;
            if (dd->draw_contacts) draw_vector(dd, mid, nt__scale(c->n, s * (nt_real)0.3), 0xffffffu);
            if (dd->draw_projections && c->depth > 0)
                draw_vector(dd, mid, nt__scale(c->n, c->depth * dd->projection_scale), 0xffe040u);
        }
    for (int k = 0; k < dd->ray_count && dd->rays; k++) {
        const nt_debug_ray *r = &dd->rays[k];
        nt_vec2 end = r->hit ? r->result.point : r->p1;
        if (dd->draw_segment) dd->draw_segment(r->p0, end, r->hit ? 0xff6060u : 0x60ff60u, dd->context);
        if (r->hit) {
            if (dd->draw_point) dd->draw_point(r->result.point, 0xff6060u, dd->context);
            draw_vector(dd, r->result.point, nt__scale(r->result.normal, s * (nt_real)0.5), 0xff6060u);
        }
    }
    if (dd->draw_stats && dd->draw_text) {
        char line[160];
        snprintf(line, sizeof line, "bodies %d  awake %d  contacts %d  moves %d  pair tests %d", w->body_count,
                 w->awake_count, w->counters.contact_count, w->counters.substep_count, w->counters.pair_tests);
        dd->draw_text(dd->use_bounds ? lo : nt_v2(0, 0), line, 0xffffffu, dd->context);
    }
}
