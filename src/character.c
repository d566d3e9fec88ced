/* The character mover: a body moved by cast-and-slide instead of the world step.
 *
 * A character is a dynamic or kinematic body with a record here (world->chars). While
 * it is one, the world step treats it as kinematic and does not move it: the game
 * calls nt_character_move once a step, which
 *   1. carries it with the body it stands on (a moving platform), by that body's
 *      velocity times dt, cast like any motion;
 *   2. moves it by velocity * dt, cast against the tiles and the bodies that stop it
 *      (static and kinematic bodies; dynamic ones too with collide_dynamic), sliding
 *      along what it meets, up to max_slides times; a wall met on the floor may be a
 *      step it climbs;
 *   3. snaps it down onto the floor when it stood on one and is not moving up;
 * and sets the body's velocity to the displacement over dt, so that the contact solver
 * pushes the dynamic bodies in its way as a kinematic body's would. Every cast starts
 * where the last one ended (resting on a surface counts as free, see character.h).
 */
#include <math.h>
#include "simulation.h"

nt_character_def nt_default_character_def(void)
{
    nt_character_def d;
    memset(&d, 0, sizeof d);
    d.floor_angle = (nt_real)0.87266462599716477; /* 50 degrees: 45 is a floor, 63.4 a wall */
    d.snap_cells = (nt_real)0.5;
    d.step_cells = (nt_real)0.5;
    d.stop_on_slope = true;
    d.constant_speed_on_slopes = false;
    d.slide_on_walls = true;
    d.collide_dynamic = false;
    d.max_slides = 4;
    return d;
}

static int finite2(nt_vec2 v) { return nt__finite(v.x) && nt__finite(v.y); }

static nt_status check_def(const nt_character_def *d)
{
    if (!nt__finite(d->floor_angle) || !nt__finite(d->snap_cells) || !nt__finite(d->step_cells))
        return NT_ERR_NON_FINITE;
    if (d->floor_angle < 0 || d->floor_angle > (nt_real)1.5707963267948966) return NT_ERR_INVALID_ARGUMENT;
    if (d->snap_cells < 0 || d->snap_cells > NT_MAX_HALF_CELLS * 2) return NT_ERR_INVALID_ARGUMENT;
    if (d->step_cells < 0 || d->step_cells > NT_MAX_HALF_CELLS * 2) return NT_ERR_INVALID_ARGUMENT;
    if (d->max_slides < 1 || d->max_slides > 16) return NT_ERR_INVALID_ARGUMENT;
    return NT_OK;
}

static void set_angle(nt__character *c)
{
    double a = (double)c->def.floor_angle;
    nt_cos_sin cs = nt_compute_cos_sin(a);
    c->floor_cos = (nt_real)cs.cosine;
    c->floor_tan = (nt_real)(a < 1.5083775167989393 ? cs.sine / cs.cosine : 16.0); /* tan(86.4 deg) = 16 */
}

/* The character record of a live body, or NULL. */
static nt__character *char_of(const nt_world *w, nt_body_id id)
{
    if (!w || id.world0 != w->tag || id.index1 <= 0 || id.index1 > w->body_hwm) return NULL;
    const nt__body *b = &w->bodies[id.index1 - 1];
    if (!(b->flags & NT__BF_ALIVE) || b->generation != id.generation) return NULL;
    int32_t k = w->cold[id.index1 - 1].character;
    return k >= 0 ? &w->chars[k] : NULL;
}

nt_status nt_character_create(nt_world *w, nt_body_id id, const nt_character_def *def)
{
    NT__CHECK_LOCK(w);
    if (!w || !def) return NT_ERR_INVALID_ARGUMENT;
    if (id.world0 != w->tag || id.index1 <= 0 || id.index1 > w->body_hwm) return NT_ERR_INVALID_ID;
    nt__body *b = &w->bodies[id.index1 - 1];
    if (!(b->flags & NT__BF_ALIVE) || b->generation != id.generation) return NT_ERR_INVALID_ID;
    nt_status s = check_def(def);
    if (s != NT_OK) return s;
    int32_t i = id.index1 - 1;
    if (w->cold[i].character >= 0) {
        nt__character *c = &w->chars[w->cold[i].character];
        c->def = *def; /* new settings, same state */
        c->rep_valid = 0; /* the last move was made with the old ones */
        set_angle(c);
        return NT_OK;
    }
    if (b->type == NT_BODY_STATIC || (b->flags & NT__BF_SENSOR)) return NT_ERR_INVALID_ARGUMENT;
    if (!nt__reserve(&w->chars, w->char_count, &w->char_cap, w->char_count + 1, sizeof *w->chars))
        return NT_ERR_OUT_OF_MEMORY;
    nt__character *c = &w->chars[w->char_count];
    memset(c, 0, sizeof *c);
    c->body = i;
    c->def = *def;
    set_angle(c);
    c->type = b->type;
    c->floor_body = -1;
    w->cold[i].character = w->char_count++;
    /* The world step sees a kinematic body: no gravity, no tiles, infinite mass, never
     * asleep, pushing dynamic bodies; nt_character_move moves it. */
    if (b->type == NT_BODY_DYNAMIC) nt__set_kinematic(w, i, true);
    return NT_OK;
}

nt_status nt_character_destroy(nt_world *w, nt_body_id id)
{
    NT__CHECK_LOCK(w);
    nt__character *c = char_of(w, id);
    if (!c) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    int32_t i = c->body;
    int was_dynamic = c->type == NT_BODY_DYNAMIC;
    nt__character_remove(w, i);
    if (was_dynamic) nt__set_kinematic(w, i, false);
    return NT_OK;
}

bool nt_character_is_valid(const nt_world *w, nt_body_id id) { return char_of(w, id) != NULL; }


nt_status nt_character_drop_through(nt_world *w, nt_body_id id)
{
    NT__CHECK_LOCK(w);
    nt__character *c = char_of(w, id);
    if (!c) return w ? NT_ERR_INVALID_ID : NT_ERR_INVALID_ARGUMENT;
    c->dropping = 1;
    return NT_OK;
}

/* ---------------------------------------------------------------- the move */

typedef struct mover {
    nt_world *w;
    nt__character *c;
    nt__body *b;
    nt_shape shape;
    nt_query_filter filter;
    int32_t skip_body; /* a body the current cast ignores (the platform being ridden), -1 none */
    int shape_ok;      /* the shape is one casts accept (checked once a move) */
    nt__cast_start start; /* the last cast's start overlaps with the tiles (one move: one world, one filter) */
    nt_real cos_floor;
    int on_ground;     /* stood on a floor before the move, or met one during it */
    nt_character_result *r;
} mover;

/* Which bodies stop the character: not itself, not sensors (queries never see them),
 * dynamic ones with collide_dynamic or when under its feet. */
static bool stops_character(nt_body_id id, void *ctx)
{
    const mover *m = (const mover *)ctx;
    int32_t i = id.index1 - 1;
    if (i == m->skip_body) return false;
    /* Both ways, as the world step pairs bodies: the other must take the character too. */
    if (!(m->w->bodies[i].mask & m->b->category)) return false;
    if (nt__character_type(m->w, i) == NT_BODY_DYNAMIC && m->w->cold[i].character < 0 && !m->c->def.collide_dynamic) {
        /* Pushed out of the way, unless wholly below its feet where the move starts:
         * then it is something to stand on (a crate), not to sink into. */
        const nt__body *o = &m->w->bodies[i];
        return o->p.y - o->half.y >= m->b->p.y + m->b->half.y - m->w->cell * (nt_real)NT_CAST_START_TOLERANCE;
    }
    return true;
}

/* Cast from p along d: the fraction travelled (1: nothing met) and the hit. */
static nt_real cast(mover *m, nt_vec2 p, nt_vec2 d, nt_world_shape_hit *hit)
{
    if (d.x == 0 && d.y == 0) {
        memset(hit, 0, sizeof *hit);
        return 1;
    }
    if (!nt__world_cast_shape(m->w, p, &m->shape, d, &m->filter, m->shape_ok, &m->start, hit)) return 1;
    return hit->fraction;
}

enum { SURF_FLOOR = 1, SURF_WALL = 2, SURF_CEILING = 3 };

static int classify(const mover *m, nt_vec2 n)
{
    if (-n.y >= m->cos_floor) return SURF_FLOOR;
    if (n.y >= m->cos_floor) return SURF_CEILING;
    return SURF_WALL;
}

/* Note a surface met (its normal, what it is) in the result. */
static void note(mover *m, int kind, const nt_world_shape_hit *h)
{
    nt_character_result *r = m->r;
    if (kind == SURF_FLOOR) {
        /* The flattest floor met wins. */
        if (!r->on_floor || h->normal.y < r->floor_normal.y) {
            r->floor_normal = h->normal;
            r->floor_body = h->body;
            r->floor_cell_x = h->cell_x;
            r->floor_cell_y = h->cell_y;
        }
        r->on_floor = true;
    } else if (kind == SURF_CEILING) {
        r->on_ceiling = true;
        r->ceiling_normal = h->normal;
    } else {
        r->on_wall = true;
        r->wall_normal = h->normal;
    }
}

/* Remove from v what goes into the surface n (v . n < 0). */
static nt_vec2 slide(nt_vec2 v, nt_vec2 n)
{
    nt_real a = nt__dot(v, n);
    return a < 0 ? nt__sub(v, nt__scale(n, a)) : v;
}

/* What is left of a motion after meeting surface n: slid along it. On a floor, with
 * stop_on_slope the downward part is the floor's to carry (standing still on a slope
 * does not slide it down), and with constant_speed_on_slopes the slid motion keeps the
 * horizontal length it had. (NT__INLINE: two calls a slide, measured cheaper inline.) */
static NT__INLINE nt_vec2 slide_motion(const mover *m, nt_vec2 d, nt_vec2 n, int kind)
{
    if (kind != SURF_FLOOR) return slide(d, n);
    nt_vec2 in = d;
    if (m->c->def.stop_on_slope && in.y > 0) in.y = 0;
    nt_vec2 out = slide(in, n);
    if (m->c->def.constant_speed_on_slopes && out.x != 0 && in.x != 0) {
        nt_real len = nt__len(out);
        if (len > 0) out = nt__scale(out, nt__fabs(in.x) / len);
    }
    return out;
}

/* Move from p along d, sliding, at most max_slides casts. Returns the end. *v is slid
 * along every surface met; *wall_left_over is the motion a wall stopped, (0, 0) when
 * none did (for the step-up). */
static nt_vec2 slide_move(mover *m, nt_vec2 p, nt_vec2 d, nt_vec2 *v, nt_vec2 *wall_left_over)
{
    nt_vec2 prev_n = nt_v2(0, 0);
    int have_prev = 0;
    nt_real tiny = m->w->cell * (nt_real)1e-7;
    *wall_left_over = nt_v2(0, 0);
    for (int k = 0; k < m->c->def.max_slides; k++) {
        if (nt__fabs(d.x) <= tiny && nt__fabs(d.y) <= tiny) break;
        nt_world_shape_hit h;
        nt_real t = cast(m, p, d, &h);
        if (t >= 1) {
            p = nt__add(p, d);
            break;
        }
        p = nt__add(p, nt__scale(d, t));
        m->r->slide_count++;
        if (h.normal.x == 0 && h.normal.y == 0) break; /* started inside: stay */
        int kind = classify(m, h.normal);
        note(m, kind, &h);
        if (kind == SURF_FLOOR) m->on_ground = 1;
        nt_vec2 rest = nt__scale(d, 1 - t);
        if (kind == SURF_WALL && rest.x != 0) *wall_left_over = rest;
        nt_vec2 next = slide_motion(m, rest, h.normal, kind);
        /* On a floor a wall (a steep slope too) is not climbed by running into it: the
         * slide along it may go down, not up; without slide_on_walls it stops. */
        if (kind == SURF_WALL && m->on_ground) {
            if (!m->c->def.slide_on_walls) next = nt_v2(0, 0);
            else if (next.y < 0) next = nt_v2(0, 0);
        }
        *v = kind == SURF_FLOOR && m->c->def.stop_on_slope ? slide_motion(m, *v, h.normal, kind) : slide(*v, h.normal);
        /* Two surfaces in 2D: moving along the second must not go back into the first
         * (a crease); then nothing is left. */
        if (have_prev && nt__dot(next, prev_n) < 0) {
            nt_vec2 along = slide(next, prev_n);
            next = nt__dot(along, h.normal) < -tiny ? nt_v2(0, 0) : along;
        }
        prev_n = h.normal;
        have_prev = 1;
        d = next;
    }
    return p;
}

/* Climb a step: up by the step height, across by the motion a wall stopped, down
 * onto a floor. Returns 1 and the new place when that lands on a floor higher than p
 * by no more than the step height. */
static int step_up(mover *m, nt_vec2 p, nt_vec2 across, nt_vec2 *out)
{
    nt_real height = m->c->def.step_cells * m->w->cell;
    if (height <= 0 || across.x == 0) return 0;
    nt_world_shape_hit h;
    nt_vec2 up = nt_v2(0, -height);
    nt_real t = cast(m, p, up, &h);
    nt_vec2 q = nt__add(p, nt__scale(up, t));
    nt_vec2 a = nt_v2(across.x, 0);
    t = cast(m, q, a, &h);
    if (t <= 0) return 0;
    q = nt__add(q, nt__scale(a, t));
    nt_vec2 down = nt_v2(0, (p.y - q.y) + m->w->cell * (nt_real)1e-3);
    t = cast(m, q, down, &h);
    if (t >= 1 || classify(m, h.normal) != SURF_FLOOR) return 0;
    q = nt__add(q, nt__scale(down, t));
    if (!(q.y < p.y)) return 0; /* no higher: not a step */
    *out = q;
    note(m, SURF_FLOOR, &h);
    return 1;
}

typedef struct overlap_probe {
    mover *m;
    nt_vec2 p;
    nt_vec2 push; /* the deepest overlap's way out */
    nt_real depth;
} overlap_probe;

static bool overlap_visit(const nt_world *w, int32_t i, void *ctx)
{
    overlap_probe *q = (overlap_probe *)ctx;
    if (i == q->m->c->body || !nt__query_sees(w, i, &q->m->filter)) return true;
    const nt__body *o = &w->bodies[i];
    nt_mtv mtv;
    if (o->one_way || !nt_collide_shapes(q->p, q->m->shape, o->p, nt__body_shape(o), &mtv)) return true;
    if (mtv.depth > q->depth) {
        q->depth = mtv.depth;
        q->push = nt__scale(mtv.normal, mtv.depth);
    }
    return true;
}

/* A body that stops the character and overlaps it more than casts allow (a kinematic
 * body moved into it, a body placed on it): out by the shortest way, deepest first, a
 * few times; casts from inside a body go nowhere. */
static nt_vec2 out_of_bodies(mover *m, nt_vec2 p)
{
    const nt_world *w = m->w;
    if (!w->heads || w->grid_bodies == 0) return p; /* no body to visit: nt__grid_visit would find none */
    for (int k = 0; k < 4; k++) {
        overlap_probe q;
        q.m = m;
        q.p = p;
        q.push = nt_v2(0, 0);
        q.depth = w->cell * (nt_real)NT_CAST_START_TOLERANCE;
        nt__grid_visit(w, nt__sub(p, m->shape.half), nt__add(p, m->shape.half), overlap_visit, &q);
        if (q.push.x == 0 && q.push.y == 0) break;
        p = nt__add(p, q.push);
    }
    return p;
}

/* The velocity of the floor met, when it is a body. */
static nt_vec2 floor_velocity(const nt_world *w, const nt_character_result *r)
{
    if (nt_body_id_is_null(r->floor_body)) return nt_v2(0, 0);
    return w->bodies[r->floor_body.index1 - 1].v;
}

typedef struct one_way_probe {
    int32_t self;
    nt_vec2 p;
    nt_shape s;
    int found;
} one_way_probe;

static bool one_way_visit(const nt_world *w, int32_t i, void *ctx)
{
    one_way_probe *q = (one_way_probe *)ctx;
    const nt__body *b = &w->bodies[i];
    if (i == q->self || !b->one_way) return true;
    nt_mtv m;
    q->found = nt_collide_shapes(q->p, q->s, b->p, nt__body_shape(b), &m);
    return !q->found;
}

/* Does the shape at p, grown by a thousandth of a cell, overlap a one-way cell's tile
 * or a one-way body (other than body self)? */
static int touches_one_way(const nt_world *w, int32_t self, nt_vec2 p, nt_shape s)
{
    one_way_probe q;
    q.self = self;
    q.p = p;
    q.s = s;
    q.s.half = nt_v2(s.half.x + w->cell * (nt_real)1e-3, s.half.y + w->cell * (nt_real)1e-3);
    q.found = 0;
    nt__grid_visit(w, nt__sub(p, q.s.half), nt__add(p, q.s.half), one_way_visit, &q);
    if (q.found) return 1;
    if (!w->oneway_count) return 0;
    nt_real ic = w->inv_cell, g = (nt_real)1e-3;
    nt_vec2 c = nt_v2(p.x * ic, p.y * ic), h = nt_v2(s.half.x * ic + g, s.half.y * ic + g);
    s.half = h;
    int x0 = nt__ifloor(c.x - h.x), x1 = nt__ifloor(c.x + h.x), y0 = nt__ifloor(c.y - h.y), y1 = nt__ifloor(c.y + h.y);
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            if ((nt__cell_flags(w, x, y) & NT_CELL_ONE_WAY) &&
                nt_tile_collide_shape(nt__map_tile(w->map, x, y), nt_v2(c.x - (nt_real)x, c.y - (nt_real)y), s, NULL))
                return 1;
    return 0;
}

static int same_bits(nt_real a, nt_real b) { return memcmp(&a, &b, sizeof a) == 0; }
static int same_bits2(nt_vec2 a, nt_vec2 b) { return same_bits(a.x, b.x) && same_bits(a.y, b.y); }

typedef struct near_probe {
    int32_t self;
    uint32_t mask;
    int found;
} near_probe;

static bool near_visit(const nt_world *w, int32_t i, void *ctx)
{
    near_probe *q = (near_probe *)ctx;
    const nt__body *o = &w->bodies[i];
    if (i == q->self || (o->flags & NT__BF_SENSOR) || !(o->category & q->mask)) return true;
    q->found = 1;
    return false;
}

/* Is a body the character's queries could see (not itself, not a sensor, in its
 * mask) within reach of its box at p? */
static int bodies_near(const nt_world *w, const nt__character *c, const nt__body *b, nt_vec2 p, nt_real reach)
{
    if (!b->mask || !w->heads || w->grid_bodies == 0) return 0; /* the move's queries find none either */
    nt_vec2 e = nt_v2(b->half.x + reach, b->half.y + reach);
    near_probe q;
    q.self = c->body;
    q.mask = b->mask;
    q.found = 0;
    nt__grid_visit(w, nt__sub(p, e), nt__add(p, e), near_visit, &q);
    return q.found;
}

/* The last move was a fixed point (see nt__character.rep_valid): the same input
 * (the velocity after the speed limit: the move reads no other), map, mask and state,
 * and no body it could meet, give the same move: its result, and what it wrote. */
NT__NOINLINE static int repeat_last(nt_world *w, nt__character *c, nt__body *b, nt_vec2 velocity, nt_real dt,
                                    nt_character_result *rp)
{
    if (c->rep_epoch != w->map_epoch || !same_bits2(c->rep_velocity, velocity) || !same_bits(c->rep_dt, dt) ||
        c->rep_mask != b->mask || !same_bits2(b->p, c->rep_r.position) || c->dropping ||
        bodies_near(w, c, b, b->p, c->rep_reach))
        return 0;
    *rp = c->rep_r;
    b->v = c->rep_bv;
    b->ntc = 0;
    b->flags &= (uint8_t)~NT__BF_RESTING;
    if (b->gcell >= 0) nt__grid_update(w, c->body);
    w->char_repeats++;
    return 1;
}

/* A move that was a fixed point as far as the character's own state goes: kept when
 * no body it could meet is near either. Its queries for bodies (the casts' start and
 * swept boxes, the way out of bodies) looked no farther from its box than its slides
 * (max_slides casts, none longer than the motion) and `looked` beyond them (the step,
 * the snap), plus rounding (of the casts' boxes to cells and back); the same move made
 * again looks at the same places while it finds no body there. */
NT__NOINLINE static void keep_fixed_point(nt_world *w, nt__character *c, const nt__body *b, nt_vec2 velocity,
                                          nt_real dt, nt_real looked, const nt_character_result *rp)
{
    nt_vec2 p = b->p;
    nt_real reach = (nt__fabs(velocity.x * dt) + nt__fabs(velocity.y * dt)) * (nt_real)c->def.max_slides + looked +
                    w->cell * (nt_real)0.01 + (nt__fabs(p.x) + nt__fabs(p.y)) * (nt_real)1e-5;
    if (bodies_near(w, c, b, p, reach)) return;
    c->rep_valid = 1;
    c->rep_reach = reach;
    c->rep_epoch = w->map_epoch;
    c->rep_mask = b->mask;
    c->rep_velocity = velocity;
    c->rep_dt = dt;
    c->rep_bv = b->v;
    c->rep_r = *rp;
}

nt_status nt_character_move(nt_world *w, nt_body_id id, nt_vec2 velocity, nt_real dt, nt_character_result *out)
{
    NT__CHECK_LOCK(w);
    /* The result is built in place (a copy of a struct just written field by field
     * stalls on store forwarding); *out is zero on every error, which all come first. */
    if (out) memset(out, 0, sizeof *out);
    if (!w || !out) return NT_ERR_INVALID_ARGUMENT;
    nt_character_result *rp = out;
    nt__character *c = char_of(w, id);
    if (!c) return NT_ERR_INVALID_ID;
    if (!finite2(velocity) || !nt__finite(dt)) return NT_ERR_NON_FINITE;
    if (dt <= 0) return NT_ERR_INVALID_ARGUMENT;
    nt__body *b = &w->bodies[c->body];
    /* The speed limit of the world step. */
    nt_real maxd = w->def.max_cells_per_step * w->cell, sp2 = nt__dot(velocity, velocity);
    /* Within the limit (the usual case, no square root: sqrt(sp2) * dt is then finite
     * too, its square being at most maxd^2 <= NT_REAL_MAX), else: a speed or a
     * displacement too large for nt_real, its direction at the limit; or over it. */
    if (sp2 <= NT_REAL_MAX && maxd * maxd <= NT_REAL_MAX && sp2 * dt * dt <= maxd * maxd) {
    } else if (!(sp2 <= NT_REAL_MAX) || !(nt__sqrt(sp2) * dt <= NT_REAL_MAX)) {
        velocity = nt__clamp_overflow(velocity, maxd / dt);
    } else if (!(sp2 * dt * dt <= maxd * maxd)) {
        velocity = nt__scale(velocity, maxd / (nt__sqrt(sp2) * dt));
    }
    if (c->rep_valid) {
        if (repeat_last(w, c, b, velocity, dt, rp)) return NT_OK;
        c->rep_valid = 0;
    }
    mover m;
    m.w = w;
    m.c = c;
    m.b = b;
    m.shape = nt__body_shape(b);
    m.shape_ok = nt__cast_shape_ok(m.shape, w->map->cell);
    m.start.valid = 0;
    /* nt_default_query_filter, field by field (a returned struct copied in stalls on
     * store forwarding). */
    memset(&m.filter, 0, sizeof m.filter);
    m.filter.tiles = true;
    m.filter.mask = b->mask;
    m.filter.ignore_count = 1;
    m.filter.ignore[0] = id;
    m.filter.accept = stops_character;
    m.filter.accept_context = &m;
    m.filter.one_way_off = c->dropping != 0;
    m.skip_body = -1;
    m.cos_floor = c->floor_cos;
    m.r = rp;
    const nt_vec2 p0 = b->p;
    nt_vec2 p = p0;
    /* Inside the tiles (a tile painted over it, a teleport into a wall): out by the
     * shortest way first, as the world step would free a body; casts from inside
     * solid go nowhere. */
    const nt_map *solid = w->solid ? w->solid : w->map;
    int checked = c->free_checked & (c->free_epoch == w->map_epoch) & (c->free_p.x == p.x) & (c->free_p.y == p.y);
    if (!checked && nt_map_overlap_depth(solid, p, m.shape) > w->cell * (nt_real)NT_CAST_START_TOLERANCE) {
        nt_resolution res;
        if (nt_map_resolve(solid, p, m.shape, &res)) p = nt__add(p, res.push);
    }
    p = out_of_bodies(&m, p);
    const int was_on_floor = c->on_floor;
    m.on_ground = was_on_floor;
    /* The velocity of the body stood on (a moving platform), if it still lives. */
    nt_vec2 platform = nt_v2(0, 0);
    int on_body = 0; /* (a fixed point stands on no body) */
    if (was_on_floor && c->floor_body >= 0) {
        on_body = 1;
        const nt__body *fb = &w->bodies[c->floor_body];
        if ((fb->flags & NT__BF_ALIVE) && fb->generation == c->floor_gen) platform = fb->v;
    }
    /* 1. The move, relative to where things are now. */
    nt_vec2 v = velocity, wall;
    const nt_vec2 p_move = p;
    p = slide_move(&m, p, nt__scale(velocity, dt), &v, &wall);
    /* How much farther than the slides (max_slides casts no longer than the motion)
     * the step and the snap may look, from where the slides ended: for a fixed point's
     * bodies_near. */
    nt_real looked = 0;
    /* 2. A step: a wall stopped the move while on a floor. */
    if ((was_on_floor || rp->on_floor) && wall.x != 0) {
        nt_vec2 q;
        looked = 2 * c->def.step_cells * w->cell + nt__fabs(wall.x) + w->cell * (nt_real)1e-3;
        if (step_up(&m, p, wall, &q)) {
            p = q;
            rp->stepped_up = true;
            /* What stopped it was a step, not a wall: the run goes on. */
            if (v.x == 0) v.x = velocity.x;
        }
    }
    /* 3. Snap down onto the floor it stood on, unless moving up; else, still standing,
     * make sure the floor is still known (a move along a floor need not meet it). */
    if (was_on_floor && !rp->on_floor && velocity.y >= 0) {
        nt_world_shape_hit h;
        /* A floor sloping down as steeply as floor_angle falls away by |dx| tan(angle)
         * under a move dx across: a sloped floor is followed down by that much more
         * than the snap distance, at any speed (a flat one only by the snap distance). */
        nt_real snap = nt__max(c->def.snap_cells * w->cell, w->cell * (nt_real)2e-3);
        nt_real across = nt__fabs(p.x - p_move.x);
        nt_real reach = snap + (c->def.snap_cells > 0 ? across * c->floor_tan : 0);
        nt_vec2 down = nt_v2(0, reach);
        looked += reach;
        nt_real t = cast(&m, p, down, &h);
        if (t < 1 && classify(&m, h.normal) == SURF_FLOOR &&
            (t * reach <= snap || t * reach * -h.normal.y <= snap * -h.normal.y + across * nt__fabs(h.normal.x))) {
            p = nt__add(p, nt__scale(down, t));
            note(&m, SURF_FLOOR, &h);
            rp->snapped = t * reach > w->cell * (nt_real)2e-3;
            v = slide_motion(&m, v, h.normal, SURF_FLOOR);
        }
    }
    rp->landed = rp->on_floor && !was_on_floor;
    /* 4. Carried by the platform over this step (it moves by as much in the world step),
     * cast without it; leaving it keeps its velocity. */
    rp->floor_velocity = rp->on_floor ? floor_velocity(w, rp) : nt_v2(0, 0);
    if (platform.x != 0 || platform.y != 0) {
        nt_character_result keep = *rp;
        nt_vec2 ignored = platform;
        m.skip_body = c->floor_body;
        p = slide_move(&m, p, nt__scale(platform, dt), &ignored, &wall);
        m.skip_body = -1;
        *rp = keep; /* what the carry met is not the move's */
        if (!rp->on_floor) v = nt__add(v, platform);
    }
    /* On a floor the floor carries the vertical part: what is left is the run along it
     * (so running up a slope and over its crest does not launch the character, and
     * the next move, not moving up, snaps). */
    if (rp->on_floor) v.y = 0;
    /* Dropping through one-way cells lasts while the character overlaps or rests on one. */
    if (c->dropping && !touches_one_way(w, c->body, p, m.shape)) c->dropping = 0;
    /* Casts that start resting on a surface are made with the shape shrunk by that
     * depth: along a curved surface (a quarter pipe) the slides can sink it a little
     * deeper each time, in float. Past half the resting tolerance it is lifted back
     * out by the shortest way, so that no move ends deeper than that. */
    int met = rp->slide_count || rp->snapped || rp->stepped_up || platform.x != 0 || platform.y != 0, free_end = 1;
    if (met && nt__map_depth_exceeds(solid, p, &m.shape, w->cell * (nt_real)(0.5 * NT_CAST_START_TOLERANCE))) {
        nt_resolution res;
        if (nt_map_resolve(solid, p, m.shape, &res)) p = nt__add(p, res.push);
        free_end = nt_map_overlap_depth(solid, p, m.shape) <= w->cell * (nt_real)NT_CAST_START_TOLERANCE;
    }
    /* A move from a free place that met nothing ends free: the next move need not ask. */
    c->free_checked = (uint8_t)free_end;
    c->free_epoch = w->map_epoch;
    c->free_p = p;
    /* Back to the body: its place and, for the contact solver, the velocity it moved at. */
    b->p = p;
    b->v = nt_v2((p.x - p0.x) / dt, (p.y - p0.y) / dt);
    b->ntc = 0;
    b->flags &= (uint8_t)~NT__BF_RESTING; /* (its tile contacts are gone, see nt_body_set_position) */
    if (b->gcell >= 0) nt__grid_update(w, c->body);
    c->on_floor = rp->on_floor;
    c->floor_body = nt_body_id_is_null(rp->floor_body) || !rp->on_floor ? -1 : rp->floor_body.index1 - 1;
    c->floor_gen = rp->floor_body.generation;
    rp->position = p;
    rp->velocity = v;
    /* A fixed point: it ended where it started, free both times (no way out of the
     * tiles taken), on a floor or not as before, on no body before or after (floor_body
     * and floor_gen then go unread: no platform), not dropping (it stays so), and no
     * body it could meet is near. Then the state the next move reads is the one this
     * move read, and the same input repeats this move while the map, the mask and the
     * bodies near stay. */
    if (p.x == p0.x && p.y == p0.y && same_bits2(p, p0) && checked && free_end && c->on_floor == (uint8_t)was_on_floor &&
        !on_body && c->floor_body < 0 && !m.filter.one_way_off)
        keep_fixed_point(w, c, b, velocity, dt, looked, rp);
    return NT_OK;
}
