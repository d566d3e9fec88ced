/* Broad phase: N's loose grid, with coarser levels for bodies above half a cell.
 *
 * Level 0 is N's grid: every body up to half a cell with a non-zero category and mask
 * sits in the map cell holding its centre (clamped to the map), in one of two
 * intrusive lists per cell: ACTIVE (awake dynamic and kinematic bodies) and REST
 * (static and sleeping ones). Such a body can only touch level-0 bodies of its own
 * cell and the 8 around it. Pairs are found from the awake side only: each ACTIVE
 * body tests the later ACTIVE bodies of its own cell, the ACTIVE lists of 4 of its 8
 * neighbours (a half neighbourhood, so each pair is met once) and the REST lists of
 * all 9 cells. Sleeping and static bodies cost nothing here.
 *
 * Level k >= 1 holds the bodies whose larger half-size is above 2^(k-2) cells and at
 * most 2^(k-1) (k = 3: up to NT_MAX_HALF_CELLS), in cells 2^k map cells wide, the
 * same way (the cell of the centre, clamped; ACTIVE and REST lists). A pair across
 * levels is found once, by the awake side: an awake body tests both lists of lower
 * levels, the REST lists and the later (by slot) ACTIVE bodies of its own level, and
 * the REST lists of higher levels, each over the cells whose bodies can come within
 * the largest contact margin. A world with no body above half a cell never looks at
 * the coarser levels (one comparison a step).
 *
 * b->gcell is the index of the list head the body is linked in: 2 * cell + list, in
 * w->heads for level 0 and in w->lheads (cells of every coarser level, one after
 * the other) above. */
#include <string.h>
#include "simulation.h"
#include "pair_internal.h"

_Static_assert((1 << (NT__LEVELS - 2)) == NT_MAX_HALF_CELLS, "the coarsest level must hold the largest body");

int nt__grid_level(const nt_world *w, nt_vec2 half)
{
    nt_real m = nt__max(half.x, half.y), lim = w->cell * (nt_real)0.5;
    int k = 0;
    while (m > lim && k < NT__LEVELS - 1) {
        lim *= 2;
        k++;
    }
    return k;
}

/* The coarser levels' list heads, all at once (they are small: a quarter of level
 * 0's cells and less). */
static nt_status enable_levels(nt_world *w)
{
    if (w->lheads) return NT_OK;
    int n = 0;
    for (int k = 1; k < NT__LEVELS; k++) {
        int s = 1 << k;
        w->lw[k] = (w->grid_w + s - 1) / s;
        w->lh[k] = (w->grid_h + s - 1) / s;
        w->lbase[k] = n;
        n += w->lw[k] * w->lh[k];
    }
    size_t words = (2 * (size_t)n + 63) / 64;
    int32_t *h = (int32_t *)nt__alloc(2 * (size_t)n * sizeof *h);
    uint64_t *occ = (uint64_t *)nt__alloc(words * sizeof *occ);
    if (!h || !occ) {
        nt__free(h);
        nt__free(occ);
        return NT_ERR_OUT_OF_MEMORY;
    }
    memset(h, 0xff, 2 * (size_t)n * sizeof *h); /* -1 everywhere */
    memset(occ, 0, words * sizeof *occ);
    w->lheads = h;
    w->loccupied = occ;
    return NT_OK;
}

nt_status nt__grid_enable(nt_world *w, int level)
{
    if (level > 0) {
        nt_status s = enable_levels(w);
        if (s != NT_OK) return s;
    }
    if (w->heads) return NT_OK;
    size_t n = 2 * (size_t)w->grid_w * (size_t)w->grid_h;
    int32_t *h = (int32_t *)nt__alloc(n * sizeof *h);
    uint64_t *occ = (uint64_t *)nt__alloc(((n + 63) / 64) * sizeof *occ);
    uint32_t *near = (uint32_t *)nt__alloc(n / 2 * sizeof *near);
    if (!h || !occ || !near) {
        nt__free(h);
        nt__free(occ);
        nt__free(near);
        return NT_ERR_OUT_OF_MEMORY;
    }
    memset(h, 0xff, n * sizeof *h); /* -1 everywhere */
    memset(occ, 0, ((n + 63) / 64) * sizeof *occ);
    memset(near, 0, n / 2 * sizeof *near);
    w->heads = h;
    w->occupied = occ;
    w->rest_near = near;
    return NT_OK;
}

static inline int32_t cell_of(const nt_world *w, nt_vec2 p)
{
    int x = nt__ifloor(p.x * w->inv_cell), y = nt__ifloor(p.y * w->inv_cell);
    if (x < 0) x = 0;
    if (x >= w->grid_w) x = w->grid_w - 1;
    if (y < 0) y = 0;
    if (y >= w->grid_h) y = w->grid_h - 1;
    return (int32_t)y * w->grid_w + x;
}

/* A REST body entering (+1) or leaving (-1) a cell: the 3 x 3 cells around it count
 * it, so the pair search asks one counter instead of nine lists. */
static void rest_count(nt_world *w, int32_t cell, int delta)
{
    int cx = cell % w->grid_w, cy = cell / w->grid_w;
    for (int y = cy - 1; y <= cy + 1; y++) {
        if (y < 0 || y >= w->grid_h) continue;
        for (int x = cx - 1; x <= cx + 1; x++) {
            if (x < 0 || x >= w->grid_w) continue;
            uint32_t *c = &w->rest_near[y * w->grid_w + x];
            *c = (uint32_t)((int64_t)*c + delta);
        }
    }
}

static inline void link(nt_world *w, int32_t i, int32_t head)
{
    nt__body *b = &w->bodies[i];
    int32_t first = w->heads[head];
    w->grid_rest += head & 1;
    b->gcell = head;
    b->gprev = -1;
    b->gnext = first;
    if (first >= 0) w->bodies[first].gprev = i;
    w->heads[head] = i;
    w->occupied[(uint32_t)head >> 6] |= (uint64_t)1 << (head & 63);
    if (head & 1) rest_count(w, head >> 1, 1);
}

static inline void unlink(nt_world *w, int32_t i)
{
    nt__body *b = &w->bodies[i];
    w->grid_rest -= b->gcell & 1;
    if (b->gcell & 1) rest_count(w, b->gcell >> 1, -1);
    if (b->gprev >= 0) w->bodies[b->gprev].gnext = b->gnext;
    else {
        w->heads[b->gcell] = b->gnext;
        if (b->gnext < 0) w->occupied[(uint32_t)b->gcell >> 6] &= ~((uint64_t)1 << (b->gcell & 63));
    }
    if (b->gnext >= 0) w->bodies[b->gnext].gprev = b->gprev;
    b->gnext = b->gprev = -1;
}

/* The coarser level's cell of a centre (clamped to the level's grid). */
static inline int32_t level_cell(const nt_world *w, int k, nt_vec2 p)
{
    nt_real ic = w->inv_cell / (nt_real)(1 << k);
    int x = nt__ifloor(p.x * ic), y = nt__ifloor(p.y * ic);
    if (x < 0) x = 0;
    if (x >= w->lw[k]) x = w->lw[k] - 1;
    if (y < 0) y = 0;
    if (y >= w->lh[k]) y = w->lh[k] - 1;
    return w->lbase[k] + (int32_t)y * w->lw[k] + x;
}

static void link_large(nt_world *w, int32_t i, int32_t head)
{
    nt__body *b = &w->bodies[i];
    int32_t first = w->lheads[head];
    b->gcell = head;
    b->gprev = -1;
    b->gnext = first;
    if (first >= 0) w->bodies[first].gprev = i;
    w->lheads[head] = i;
    w->loccupied[(uint32_t)head >> 6] |= (uint64_t)1 << (head & 63);
    w->lcount[b->level][head & 1]++;
}

static void unlink_large(nt_world *w, int32_t i)
{
    nt__body *b = &w->bodies[i];
    w->lcount[b->level][b->gcell & 1]--;
    if (b->gprev >= 0) w->bodies[b->gprev].gnext = b->gnext;
    else {
        w->lheads[b->gcell] = b->gnext;
        if (b->gnext < 0) w->loccupied[(uint32_t)b->gcell >> 6] &= ~((uint64_t)1 << (b->gcell & 63));
    }
    if (b->gnext >= 0) w->bodies[b->gnext].gprev = b->gprev;
    b->gnext = b->gprev = -1;
}

void nt__grid_insert(nt_world *w, int32_t i)
{
    nt__body *b = &w->bodies[i];
    b->level = (uint8_t)nt__grid_level(w, b->half);
    NT_ASSERT(!b->level == !(b->flags & NT__BF_LARGE));
    if (b->level) {
        link_large(w, i, 2 * level_cell(w, b->level, b->p) + b->glist);
        w->large_count++;
    } else {
        link(w, i, 2 * cell_of(w, b->p) + b->glist);
    }
    w->grid_bodies++;
    w->grid_cat |= b->category;
    w->grid_mask |= b->mask;
}

void nt__grid_remove(nt_world *w, int32_t i)
{
    nt__body *b = &w->bodies[i];
    if (b->level) {
        unlink_large(w, i);
        w->large_count--;
    } else {
        unlink(w, i);
    }
    b->gcell = -1;
    w->grid_bodies--;
}

NT__NOINLINE static void update_large(nt_world *w, int32_t i)
{
    nt__body *b = &w->bodies[i];
    int32_t head = 2 * level_cell(w, b->level, b->p) + b->glist;
    if (head == b->gcell) return;
    unlink_large(w, i);
    link_large(w, i, head);
}

/* Out of line: the common case (the same list) then needs no registers saved. */
NT__NOINLINE static void relink(nt_world *w, int32_t i, int32_t head)
{
    unlink(w, i);
    link(w, i, head);
}

void nt__grid_update(nt_world *w, int32_t i)
{
    nt__body *b = &w->bodies[i];
    if (b->flags & NT__BF_LARGE) {
        update_large(w, i);
        return;
    }
    int32_t head = 2 * cell_of(w, b->p) + b->glist;
    if (head != b->gcell) relink(w, i, head);
}

/* Two boxes overlap on both axes; the least overlap is not always the axis they met
 * on (a box sinking onto a neighbour's corner would be pushed sideways). Take the
 * axis whose overlap began last, judged by the relative velocity, unless that
 * overlap is already deep. */
void nt__box_axis(const nt__body *a, const nt__body *b, nt_mtv *m)
{
    nt__box_pair q = nt__box_overlaps(a->p, a->half, b->p, b->half);
    nt_real dx = q.dx, dy = q.dy, ox = q.ox, oy = q.oy;
    nt_real vx = b->v.x - a->v.x, vy = b->v.y - a->v.y;
    /* Time since the overlap began along each axis (infinite when not approaching). */
    int ax = vx * dx < 0, ay = vy * dy < 0;
    nt_real lim = (nt_real)0.5 * nt__min(nt__min(a->half.x, a->half.y), nt__min(b->half.x, b->half.y));
    int use_y;
    if (ax && ay) use_y = oy * nt__fabs(vx) < ox * nt__fabs(vy); /* oy/|vy| < ox/|vx| */
    else if (ay) use_y = 1;
    else if (ax) use_y = 0;
    else return;
    if ((use_y ? oy : ox) > lim) return;
    if (use_y) {
        m->normal = nt_v2(0, dy > 0 ? (nt_real)(-1) : (nt_real)1);
        m->depth = oy;
    } else {
        m->normal = nt_v2(dx > 0 ? (nt_real)(-1) : (nt_real)1, 0);
        m->depth = ox;
    }
}

/* Inline in the pair search, which calls it for every pair whose boxes are near. */
static inline bool pair_filter(const nt__body *a, const nt__body *b)
{
    if (!(a->category & b->mask) || !(b->category & a->mask)) return false;
    int sa = a->flags & NT__BF_SENSOR, sb = b->flags & NT__BF_SENSOR;
    if (sa && sb) return false;
    if (sa || sb) return true;
    return a->type == NT_BODY_DYNAMIC || b->type == NT_BODY_DYNAMIC;
}

bool nt__pair_filter(const nt__body *a, const nt__body *b) { return pair_filter(a, b); }

/* Depth (> 0: overlap, < 0: gap) and unit normal from a towards b of two shapes whose
 * boxes are within `margin`. Returns 0 when the gap is at least `margin`. Gaps are
 * measured along an axis or between closest points, never over-estimated. The
 * general form: pair_depth's answer for the cases it leaves here (centres that
 * coincide, a circle's centre in a box, circles not finite). The arithmetic is
 * nt_collide_shapes' (pair_internal.h). */
NT__NOINLINE static int pair_depth_any(const nt__body *a, const nt__body *b, int32_t ia, int32_t ib, nt_real margin,
                                       nt_vec2 *n, nt_real *depth)
{
    nt_mtv m;
    if (nt__shapes_depth(a->p, a->shape, a->half, b->p, b->shape, b->half, &m)) {
        if (a->p.x == b->p.x && a->p.y == b->p.y) {
            nt__coincident(a, b, ia, ib, n, depth);
            return 1;
        }
        if (a->shape == NT_SHAPE_AABB && b->shape == NT_SHAPE_AABB) nt__box_axis(a, b, &m);
        *n = nt_v2(-m.normal.x, -m.normal.y);
        *depth = m.depth;
        return 1;
    }
    /* Apart: the gap, its normal from a towards b. */
    if (a->shape == NT_SHAPE_AABB && b->shape == NT_SHAPE_AABB) {
        nt__aabbs_depth(a->p, a->half, b->p, b->half, 1, &m);
    } else if (a->shape == NT_SHAPE_CIRCLE && b->shape == NT_SHAPE_CIRCLE) {
        if (nt__circles_depth(a->p, a->half.x, b->p, b->half.x, 1, &m) < 0) return 0; /* no direction */
    } else {
        const nt__body *box = a->shape == NT_SHAPE_AABB ? a : b, *cir = a->shape == NT_SHAPE_AABB ? b : a;
        nt__box_point q = nt__box_nearest(cir->p, box->p, box->half);
        if (q.d2 <= 0) return 0; /* d2 = 0: no direction (a NaN d2 is measured: NaN depth) */
        nt__circle_box_out(&q, cir->half.x, box == a ? (nt_real)1 : (nt_real)(-1), 1, &m);
    }
    *n = m.normal;
    if (m.depth <= -margin) return 0;
    *depth = m.depth;
    return 1;
}

/* pair_depth_any's answer, with one square root for the overlap test and the gap and
 * no call for a box pair and for a circle whose centre is outside the other box or
 * apart from the other circle's. */
static inline int pair_depth(const nt__body *a, const nt__body *b, int32_t ia, int32_t ib, nt_real margin, nt_vec2 *n,
                             nt_real *depth)
{
    nt_mtv m;
    if (a->shape == NT_SHAPE_AABB && b->shape == NT_SHAPE_AABB) {
        if (nt__aabbs_depth(a->p, a->half, b->p, b->half, 1, &m)) {
            if (a->p.x == b->p.x && a->p.y == b->p.y) {
                nt__coincident(a, b, ia, ib, n, depth);
                return 1;
            }
            nt__box_axis(a, b, &m);
            *n = nt_v2(-m.normal.x, -m.normal.y);
            *depth = m.depth;
            return 1;
        }
        *n = m.normal;
    } else if (a->shape == NT_SHAPE_CIRCLE && b->shape == NT_SHAPE_CIRCLE) {
        int hit = nt__circles_depth(a->p, a->half.x, b->p, b->half.x, 1, &m);
        if (hit < 0) return pair_depth_any(a, b, ia, ib, margin, n, depth);
        if (hit) { /* m moves a out of b */
            *n = nt_v2(-m.normal.x, -m.normal.y);
            *depth = m.depth;
            return 1;
        }
        *n = m.normal;
    } else {
        const nt__body *box = a->shape == NT_SHAPE_AABB ? a : b, *cir = a->shape == NT_SHAPE_AABB ? b : a;
        nt__box_point q = nt__box_nearest(cir->p, box->p, box->half);
        if (!(q.d2 > 0)) return pair_depth_any(a, b, ia, ib, margin, n, depth);
        /* Overlapping or not, the normal from a towards b. */
        int hit = nt__circle_box_out(&q, cir->half.x, box == a ? (nt_real)1 : (nt_real)(-1), 1, &m);
        *n = m.normal;
        if (hit) {
            *depth = m.depth;
            return 1;
        }
    }
    if (m.depth <= -margin) return 0;
    *depth = m.depth;
    return 1;
}

/* How far a and b can close a gap along an axis this step when either of them is
 * stopped: what each travels towards the other (d = b's centre - a's along the axis,
 * va, vb: their velocities along it), at least their closing speed. Two bodies falling
 * together close at 0, yet when this step's solve stops the lower one, the upper one
 * drives into it unless their pair is a contact. Centres level on the axis: 0 (the
 * gap of two shapes apart is then measured across it; the same whichever body is a).
 * Branch-free: s is the sign of d. */
static inline nt_real axis_reach(nt_real d, nt_real va, nt_real vb)
{
    nt_real s = (nt_real)((d > 0) - (d < 0));
    return nt__max_sel(s * va, 0) + nt__max_sel(-s * vb, 0);
}

/* How close a pair must be to become a contact along an axis: the base margin plus the
 * reach (speculative contacts: a fast pair is solved before it overlaps, instead of
 * being found already deep inside each other). At most one cell: only neighbouring
 * cells are searched. */
static inline nt_real axis_margin(const nt_world *w, nt_real d, nt_real va, nt_real vb)
{
    nt_real m = w->pair_margin + axis_reach(d, va, vb) * w->pair_dt;
    return m < w->cell ? m : w->cell;
}

/* Boxes of a and b (centres pa, pb, half-sizes ha, hb) within the margins. */
static inline int boxes_near(const nt_world *w, nt_vec2 pa, nt_vec2 ha, nt_vec2 va, nt_vec2 pb, nt_vec2 hb, nt_vec2 vb)
{
    nt_real dx = pb.x - pa.x, dy = pb.y - pa.y;
    return nt__fabs(dx) < ha.x + hb.x + axis_margin(w, dx, va.x, vb.x) &&
           nt__fabs(dy) < ha.y + hb.y + axis_margin(w, dy, va.y, vb.y);
}

/* A pair with a one-way platform is a contact only when the other body is above it
 * (the normal from the platform points up, within 60 degrees) and not sunk into it
 * deeper than the contact margin: a body passing up through it, or sideways, is let
 * through. n points from a to b. */
NT__NOINLINE static int one_way_holds(const nt_world *w, const nt__body *a, const nt__body *b, nt_vec2 n, nt_real depth)
{
    if (depth > w->pair_margin) return 0;
    if (a->one_way && !(n.y <= (nt_real)(-0.5))) return 0;
    if (b->one_way && !(n.y >= (nt_real)0.5)) return 0;
    return 1;
}

/* A character and the dynamic body it stood on at its last move (a crate): the mover
 * holds it up and carries it along; a contact would squeeze the body between an
 * infinitely heavy character and what holds it up. */
NT__NOINLINE static int stands_on(const nt_world *w, int32_t i, int32_t j)
{
    for (int s = 0; s < 2; s++) {
        int32_t c = s ? j : i, o = s ? i : j;
        int32_t k = w->cold[c].character;
        if (k >= 0 && w->chars[k].on_floor && w->chars[k].floor_body == o && w->bodies[o].type == NT_BODY_DYNAMIC &&
            w->bodies[o].generation == w->chars[k].floor_gen)
            return 1;
    }
    return 0;
}

/* Test one candidate pair; append its nt__pair to con_new when the shapes overlap or
 * nearly touch. */
static inline int test_pair(nt_world *w, int32_t i, int32_t j)
{
    const nt__body *bi = &w->bodies[i], *bj = &w->bodies[j];
    if (!boxes_near(w, bi->p, bi->half, bi->v, bj->p, bj->half, bj->v)) return 1;
    /* The gap that makes a contact: the base margin plus the reach along both axes (the
     * gap's normal has the signs of the centres' offset, so the sum bounds the reach
     * along it). */
    nt_real dx = bj->p.x - bi->p.x, dy = bj->p.y - bi->p.y;
    nt_real margin = w->pair_margin + w->pair_dt * (axis_reach(dx, bi->v.x, bj->v.x) + axis_reach(dy, bi->v.y, bj->v.y));
    if (margin > w->cell) margin = w->cell;
    if (!pair_filter(bi, bj)) return 1;
    if (w->char_count && stands_on(w, i, j)) return 1;
    int32_t a = i < j ? i : j, b = i < j ? j : i;
    const nt__body *ba = &w->bodies[a], *bb = &w->bodies[b];
    int sensor = (ba->flags | bb->flags) & NT__BF_SENSOR;
    nt_vec2 n;
    nt_real depth;
    /* Sensors only care about real overlap. */
    if (!pair_depth(ba, bb, a, b, sensor ? 0 : margin, &n, &depth) || (sensor && depth <= 0)) return 1;
    if (w->one_way_bodies && !sensor && (ba->one_way | bb->one_way) && !one_way_holds(w, ba, bb, n, depth)) return 1;
    if (w->con_new_count >= NT_MAX_CONTACTS) { /* bodies piled on each other beyond simulation */
        w->pairs_over = 1;
        return 0;
    }
    if (w->con_new_count == w->con_new_cap) {
        nt__pair *p = (nt__pair *)nt__grow(w->con_new, w->con_new_count, &w->con_new_cap, w->con_new_count + 1,
                                           sizeof *p);
        if (!p) return 0;
        w->con_new = p;
    }
    nt__pair *c = &w->con_new[w->con_new_count++];
    c->key = ((uint64_t)(uint32_t)a << 32) | (uint32_t)b;
    c->gen_a = ba->generation;
    c->gen_b = bb->generation;
    c->n = n;
    c->depth = depth;
    /* Touching: overlapping (sensors) or within the skin, or closing the gap during
     * this step at the speed they approach: a collision happens now, so its begin
     * event (and the wake-up of a sleeping partner) is not a step late. */
    int touch = depth > (sensor ? 0 : -nt__skin(w, ba->p));
    if (!touch && !sensor) {
        /* With the velocities the solve starts from (this step's gravity included),
         * so that a gap the solve closes is a touch here too: else a sleeping body
         * would not be woken, and would stop the other one like a wall. */
        nt_vec2 va = nt__solve_velocity(w, ba, w->pair_dt), vb = nt__solve_velocity(w, bb, w->pair_dt);
        nt_real vn = (vb.x - va.x) * n.x + (vb.y - va.y) * n.y;
        touch = vn * w->pair_dt < depth;
    }
    c->flags = ((ba->flags & NT__BF_SENSOR) ? NT__CF_SENSOR_A : 0u) | ((bb->flags & NT__BF_SENSOR) ? NT__CF_SENSOR_B : 0u) |
               (touch ? NT__CF_TOUCH : 0u);
    return 1;
}

/* What every proxy of a step needs of the world, read once (stores to the proxies
 * could alias the world's fields and make the compiler read them again). */
typedef struct proxy_step {
    nt_real half_margin, dt, cell, inv_cell, slack;
} proxy_step;

static proxy_step proxy_step_of(const nt_world *w)
{
    proxy_step c;
    c.half_margin = (nt_real)0.5 * w->pair_margin;
    c.dt = w->pair_dt;
    c.cell = w->cell;
    c.inv_cell = w->inv_cell;
    c.slack = (nt_real)(1e-3) * w->cell;
    return c;
}

/* Awake bodies as proxies sorted by cell. Keys number the cells row by row with one
 * empty column after each row, so the neighbours of a cell are key + 1 and key +
 * stride - 1 .. key + stride + 1 with no test for the map's edges (a key in the
 * padding column holds no proxy).
 *
 * A proxy's box is its body's box grown by half the base margin plus its own reach
 * this step (|v| dt per axis, at most a cell), and a little for rounding: two
 * proxies whose boxes are apart cannot pass boxes_near (the exact test, made again
 * on the bodies), whose margin is at most a cell and at most the base margin plus
 * (|va| + |vb|) dt per axis. */
static inline void fill_proxy(nt_world *w, const proxy_step *c, nt__proxy *q, int32_t i, uint32_t cellix, uint32_t key,
                              uint32_t cx, uint32_t cy)
{
    const nt_real half_margin = c->half_margin, dt = c->dt, cell = c->cell, inv_cell = c->inv_cell;
    nt__body *b = &w->bodies[i];
    const nt_vec2 p = b->p, h = b->half, v = b->v;
    /* Rounding allowance: a thousandth of a cell, plus a few ulps of the position. */
    nt_real slack = c->slack + (nt__fabs(p.x) + nt__fabs(p.y)) * ((nt_real)16 * NT_REAL_EPS);
    nt_real ex = h.x + slack + nt__min(half_margin + nt__fabs(v.x) * dt, cell);
    nt_real ey = h.y + slack + nt__min(half_margin + nt__fabs(v.y) * dt, cell);
    q->lo = nt_v2(p.x - ex, p.y - ey);
    q->hi = nt_v2(p.x + ex, p.y + ey);
    q->cell = cellix;
    q->key = key;
    q->body = i;
    /* The searches here meet the bodies of the neighbouring cells only. A pair of
     * cells two or more apart along an axis can still be a contact when their
     * proxies overlap: along x, (f_i + ex_i) + ((1 - f_j) + ex_j) > 3 cells (f: a
     * centre's place in its cell, 0..1), so one of the two reaches beyond 1.5
     * cells from its cell's far side. Such a body looks for what it overlaps
     * after the move instead (correct_after_move, response.c). */
    nt_real fx = p.x * inv_cell - (nt_real)cx, fy = p.y * inv_cell - (nt_real)cy;
    nt_real rx = nt__max(fx, 1 - fx) + ex * inv_cell, ry = nt__max(fy, 1 - fy) + ey * inv_cell;
    if (rx > (nt_real)1.5 || ry > (nt_real)1.5) {
        nt__mark_move(w, b, NT__MF_KICKED);
        w->kicked_count++;
    }
}

/* The proxies in key order: a stable radix sort (two passes of half the key's bits
 * each, at most 13: keys < 2^25) of the awake order, so the result is deterministic.
 * Digits no wider than the grid needs keep the scatter's write streams few (256 for
 * a 256 x 256 grid), which matters once the proxies outgrow the cache. The bodies
 * are read in the awake order, mostly their order in memory: walking the ACTIVE
 * lists instead gives the cell order with no sort (30 fewer instructions per
 * body-step on rain) but reads the bodies out of order, which made the pair search
 * 25 % slower with 100,000 bodies and no faster with 10,000. */
static nt_status proxies_sorted(nt_world *w, int *count)
{
    if (!w->radix) {
        w->radix = (uint32_t *)nt__alloc(2 * 8192 * sizeof *w->radix);
        if (!w->radix) return NT_ERR_OUT_OF_MEMORY;
    }
    uint32_t *c0 = w->radix, *c1 = w->radix + 8192;
    const uint32_t gw = (uint32_t)w->grid_w, stride = gw + 1u;
    unsigned bits = 2;
    while (bits < 26 && (stride * (uint32_t)w->grid_h - 1u) >> bits) bits++;
    const unsigned lo = (bits + 1) / 2;
    const uint32_t lo_mask = (1u << lo) - 1u, digits = 1u << lo; /* lo >= bits - lo */
    /* Only the digits in use: a small world's step does not pay for clearing 64 KiB. */
    memset(c0, 0, digits * sizeof *c0);
    memset(c1, 0, digits * sizeof *c1);
    nt__proxy *src = w->prox_tmp;
    const proxy_step c = proxy_step_of(w);
    int n = 0;
    for (int k = 0; k < w->awake_count; k++) {
        int32_t i = w->awake[k];
        const nt__body *b = &w->bodies[i];
        if (b->gcell < 0 || (b->flags & NT__BF_LARGE)) continue; /* coarser levels: large_pairs */
        nt__proxy *q = &src[n++];
        uint32_t cellix = (uint32_t)b->gcell >> 1, cy = cellix / gw;
        fill_proxy(w, &c, q, i, cellix, cellix + cy, cellix - cy * gw, cy);
        c0[q->key & lo_mask]++;
        c1[q->key >> lo]++;
    }
    uint32_t s0 = 0, s1 = 0;
    for (uint32_t d = 0; d < digits; d++) {
        uint32_t t0 = c0[d], t1 = c1[d];
        c0[d] = s0;
        c1[d] = s1;
        s0 += t0;
        s1 += t1;
    }
    nt__proxy *mid = w->prox;
    for (int k = 0; k < n; k++) mid[c0[src[k].key & lo_mask]++] = src[k];
    for (int k = 0; k < n; k++) src[c1[mid[k].key >> lo]++] = mid[k];
    *count = n;
    return NT_OK;
}

/* Sentinels after the last proxy: one ends the scans, the pair search's prefetches
 * read PREFETCH_AHEAD more. */
#define PREFETCH_AHEAD 8
#define PROXY_PAD (1 + PREFETCH_AHEAD)

/* The proxies, sorted by key, into w->prox_tmp. */
static nt_status build_proxies(nt_world *w, int *count)
{
    /* Room for the sentinels after the last proxy. */
    if (w->awake_count + PROXY_PAD > w->prox_cap) {
        int cap = w->prox_cap, cap2 = w->prox_cap;
        nt__proxy *a = (nt__proxy *)nt__grow(w->prox, 0, &cap, w->awake_count + PROXY_PAD, sizeof *a);
        if (!a) return NT_ERR_OUT_OF_MEMORY;
        w->prox = a;
        nt__proxy *b = (nt__proxy *)nt__grow(w->prox_tmp, 0, &cap2, w->awake_count + PROXY_PAD, sizeof *b);
        if (!b) return NT_ERR_OUT_OF_MEMORY;
        w->prox_tmp = b;
        w->prox_cap = cap < cap2 ? cap : cap2;
    }
    nt_status s = proxies_sorted(w, count);
    if (s != NT_OK) return s;
    /* A key above every cell's ends the searches' scans; the bodies the search
     * prefetches ahead of the last proxies are body 0's. */
    for (int k = *count; k < *count + PROXY_PAD; k++) {
        w->prox_tmp[k].key = UINT32_MAX;
        w->prox_tmp[k].body = 0;
    }
    return NT_OK;
}

/* Proxy boxes first, then the full test on the bodies. b is a later proxy of a's
 * cell or of the cell to its right: b's left edge against a's right one first, the
 * test that fails most there. */
static inline int test_proxies(nt_world *w, const nt__proxy *a, const nt__proxy *b)
{
    if (!(b->lo.x < a->hi.x && a->lo.x < b->hi.x && a->lo.y < b->hi.y && b->lo.y < a->hi.y)) return 1;
    return test_pair(w, a->body, b->body);
}

/* The same for b in the row below a's: b's top edge against a's bottom first, the
 * test that fails most there (b's bottom is nearly always below a's top). */
static inline int test_proxies_below(nt_world *w, const nt__proxy *a, const nt__proxy *b)
{
    if (!(b->lo.y < a->hi.y && a->lo.x < b->hi.x && b->lo.x < a->hi.x && a->lo.y < b->hi.y)) return 1;
    return test_pair(w, a->body, b->body);
}

/* One level of the grid as the searches see it: its list heads (2 per cell), its
 * size in cells and the width of a cell. */
typedef struct level_view {
    const int32_t *heads;
    int w, h;
    nt_real size;
} level_view;

static level_view view_of(const nt_world *w, int k)
{
    level_view v;
    if (k == 0) {
        v.heads = w->heads;
        v.w = w->grid_w;
        v.h = w->grid_h;
        v.size = w->cell;
    } else {
        v.heads = w->lheads + 2 * (size_t)w->lbase[k];
        v.w = w->lw[k];
        v.h = w->lh[k];
        v.size = w->cell * (nt_real)(1 << k);
    }
    return v;
}

/* The cells of a level whose bodies' centres may lie in lo..hi: bodies outside the
 * map live in its edge cells, so the range is clamped into the grid (a range wholly
 * outside becomes the edge row or column). */
static void view_range(const level_view *v, nt_vec2 lo, nt_vec2 hi, int r[4])
{
    nt_real ic = 1 / v->size;
    int x0 = nt__ifloor(lo.x * ic), y0 = nt__ifloor(lo.y * ic);
    int x1 = nt__ifloor(hi.x * ic), y1 = nt__ifloor(hi.y * ic);
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    if (x1 >= v->w) x1 = v->w - 1;
    if (y1 >= v->h) y1 = v->h - 1;
    if (x0 > x1) x0 = x1 = x0 >= v->w ? v->w - 1 : 0;
    if (y0 > y1) y0 = y1 = y0 >= v->h ? v->h - 1 : 0;
    r[0] = x0;
    r[1] = y0;
    r[2] = x1;
    r[3] = y1;
}

/* Pairs with a body above half a cell (see the top of the file). An awake body tests
 * the lists of level lv over the cells whose bodies can come within the largest
 * contact margin (one cell) of it: their centres lie within its half-size, the
 * level's largest half-size and a cell. */
/* Test body i against the bodies of the lists of cells x0..x1 in rows y0..y1 of a
 * level (r), reading its bitmap of non-empty lists a word at a time: occ and heads
 * are indexed by 2 * (base + cell) + list. `want` keeps the wanted lists' bits
 * (ACTIVE: even bits, REST: odd bits); ACTIVE bodies of the body's own level are
 * met only when their slot is after i (the other one meets the rest). */
static int scan_lists(nt_world *w, int32_t i, const uint64_t *occ, const int32_t *heads, uint32_t base, int gw,
                      const int r[4], uint64_t want, int own_level, int *tests)
{
    for (int y = r[1]; y <= r[3]; y++) {
        uint32_t b0 = 2 * (base + (uint32_t)(y * gw + r[0])), b1 = 2 * (base + (uint32_t)(y * gw + r[2])) + 1;
        for (uint32_t wd = b0 >> 6; wd <= b1 >> 6; wd++) {
            uint64_t bits = occ[wd] & want;
            if (wd == b0 >> 6) bits &= ~(uint64_t)0 << (b0 & 63);
            if (wd == b1 >> 6) bits &= ~(uint64_t)0 >> (63 - (b1 & 63));
            while (bits) {
                uint32_t head = wd * 64 + (uint32_t)nt__ctz64(bits);
                bits &= bits - 1;
                int skip_before = own_level && !(head & 1);
                for (int32_t j = heads[head]; j >= 0; j = w->bodies[j].gnext) {
                    if (skip_before && j <= i) continue; /* met from j's side */
                    (*tests)++;
                    if (!test_pair(w, i, j)) return 0;
                }
            }
        }
    }
    return 1;
}

static int large_pairs_of(nt_world *w, int32_t i, int *tests)
{
    const uint64_t ACTIVE = 0x5555555555555555ull, REST = ~ACTIVE;
    const nt__body *b = &w->bodies[i];
    const int own = b->level;
    for (int lv = own ? 0 : 1; lv < NT__LEVELS; lv++) {
        /* Which lists: both below, REST and later ACTIVE ones at its own level, REST above. */
        uint64_t want = lv <= own ? ACTIVE | REST : REST;
        if (lv > 0) {
            if (!w->lcount[lv][NT__LIST_ACTIVE]) want &= REST;
            if (!w->lcount[lv][NT__LIST_REST]) want &= ACTIVE;
            if (!want) continue;
        }
        level_view v = view_of(w, lv);
        nt_real ex = b->half.x + (nt_real)0.5 * v.size + w->cell, ey = b->half.y + (nt_real)0.5 * v.size + w->cell;
        int r[4];
        view_range(&v, nt_v2(b->p.x - ex, b->p.y - ey), nt_v2(b->p.x + ex, b->p.y + ey), r);
        int ok = lv ? scan_lists(w, i, w->loccupied, w->lheads, (uint32_t)w->lbase[lv], v.w, r, want, lv == own, tests)
                    : scan_lists(w, i, w->occupied, w->heads, 0, v.w, r, want, 0, tests);
        if (!ok) return 0;
    }
    return 1;
}

/* Every pair with a body above half a cell, in awake order: the awake large bodies
 * against everything they can reach, and the awake small ones against the large
 * resting ones. */
NT__NOINLINE static int large_pairs(nt_world *w, int *tests)
{
    int rest_above = 0;
    for (int lv = 1; lv < NT__LEVELS; lv++) rest_above += w->lcount[lv][NT__LIST_REST];
    for (int k = 0; k < w->awake_count; k++) {
        int32_t i = w->awake[k];
        const nt__body *b = &w->bodies[i];
        if (b->gcell < 0 || (!b->level && !rest_above)) continue;
        if (!large_pairs_of(w, i, tests)) return 0;
    }
    return 1;
}

static nt_status find_pairs(nt_world *w, nt_real dt);

/* Failures of the pair search: out of memory, or over NT_MAX_CONTACTS. */
nt_status nt__grid_find_pairs(nt_world *w, nt_real dt)
{
    nt_status s = find_pairs(w, dt);
    if (s == NT_ERR_OUT_OF_MEMORY && w->pairs_over) s = NT_ERR_LIMIT;
    return s;
}

static nt_status find_pairs(nt_world *w, nt_real dt)
{
    w->pair_margin = w->cell * NT__CONTACT_MARGIN;
    w->pair_dt = dt;
    w->con_new_count = 0;
    w->counters.pair_tests = 0;
    w->pairs_over = 0;
    if (!w->heads || w->grid_bodies < 2) return NT_OK;
    /* Skip everything when no awake body can collide with any body of the grid. */
    int possible = 0;
    for (int k = 0; k < w->awake_count && !possible; k++) {
        const nt__body *b = &w->bodies[w->awake[k]];
        if (b->gcell >= 0 && (b->category & w->grid_mask) && (b->mask & w->grid_cat)) possible = 1;
    }
    if (!possible) return NT_OK;
    int n, tests = 0;
    if (w->large_count && !large_pairs(w, &tests)) return NT_ERR_OUT_OF_MEMORY;
    nt_status st = build_proxies(w, &n);
    if (st != NT_OK) return st;
    const nt__proxy *P = w->prox_tmp; /* sorted */
    const uint32_t gw = (uint32_t)w->grid_w, gh = (uint32_t)w->grid_h, stride = gw + 1u;
    /* Awake pairs: each proxy meets the later ones of its own cell and of the cell to
     * its right (the next keys), and those of the three cells below it, found by a
     * cursor that only moves forward (keys grow, so does the row-below range). The
     * sentinel's key ends every scan. */
    int below = 0;
    for (int i = 0; i < n; i++) {
        uint32_t key = P[i].key;
        /* test_pair reads the bodies in cell order, not memory order: the records of
         * the proxies some way ahead in this row and in the row below are asked for
         * early (with 100,000 bodies, a quarter less time in test_pair). */
        NT__PREFETCH(&w->bodies[P[i + PREFETCH_AHEAD].body]);
        NT__PREFETCH(&w->bodies[P[below + PREFETCH_AHEAD].body]);
        for (int j = i + 1; P[j].key <= key + 1u; j++, tests++)
            if (!test_proxies(w, &P[i], &P[j])) return NT_ERR_OUT_OF_MEMORY;
        uint32_t lo = key + stride - 1u, hi = key + stride + 1u;
        while (P[below].key < lo) below++;
        for (int k = below; P[k].key <= hi; k++, tests++)
            if (!test_proxies_below(w, &P[i], &P[k])) return NT_ERR_OUT_OF_MEMORY;
    }
    /* Awake against resting (static and sleeping) bodies: the REST lists of the 9 cells. */
    if (w->grid_rest > 0) {
        const uint64_t REST_BITS = 0xaaaaaaaaaaaaaaaaull;
        for (int i = 0; i < n; i++) {
            if (!w->rest_near[P[i].cell]) continue;
            uint32_t cx = P[i].cell % gw, cy = P[i].cell / gw;
            uint32_t x0 = cx > 0 ? cx - 1 : 0, x1 = cx + 1 < gw ? cx + 1 : cx;
            uint32_t y0 = cy > 0 ? cy - 1 : 0, y1 = cy + 1 < gh ? cy + 1 : cy;
            /* A row's REST lists (odd bits) from the bitmap, a word at a time. */
            for (uint32_t y = y0; y <= y1; y++) {
                uint32_t b0 = 2 * (y * gw + x0) + 1, b1 = 2 * (y * gw + x1) + 1;
                for (uint32_t wd = b0 >> 6; wd <= b1 >> 6; wd++) {
                    uint64_t bits = w->occupied[wd] & REST_BITS;
                    if (wd == b0 >> 6) bits &= ~(uint64_t)0 << (b0 & 63);
                    if (wd == b1 >> 6) bits &= ~(uint64_t)0 >> (63 - (b1 & 63));
                    while (bits) {
                        uint32_t head = wd * 64 + (uint32_t)nt__ctz64(bits);
                        bits &= bits - 1;
                        for (int32_t j = w->heads[head]; j >= 0; j = w->bodies[j].gnext, tests++)
                            if (!test_pair(w, P[i].body, j)) return NT_ERR_OUT_OF_MEMORY;
                    }
                }
            }
        }
    }
    w->counters.pair_tests = tests;
    return NT_OK;
}

/* The bodies of one list whose boxes overlap body b's (slot i left out), into out. */
static inline int take_overlapping(const nt_world *w, int32_t head_body, int32_t i, const nt__body *b, int32_t *out,
                                   int n, int cap)
{
    for (int32_t j = head_body; j >= 0; j = w->bodies[j].gnext) {
        const nt__body *o = &w->bodies[j];
        if (j == i || nt__fabs(o->p.x - b->p.x) >= o->half.x + b->half.x || nt__fabs(o->p.y - b->p.y) >= o->half.y + b->half.y)
            continue;
        if (n < cap) out[n++] = j;
    }
    return n;
}

int nt__grid_overlapping(const nt_world *w, int32_t i, int32_t *out, int cap)
{
    const nt__body *b = &w->bodies[i];
    int n = 0;
    if (!w->heads) return 0;
    /* Level 0 by its cells and bitmap of non-empty lists; the coarser levels when in use.
     * A body reaches half its level's cell beyond its cell. */
    for (int lv = 0; lv < NT__LEVELS; lv++) {
        if (lv > 0 && (!w->large_count || !w->lheads || !(w->lcount[lv][0] | w->lcount[lv][1]))) continue;
        level_view v = view_of(w, lv);
        nt_real m = v.size * (nt_real)0.5;
        int r[4];
        view_range(&v, nt_v2(b->p.x - b->half.x - m, b->p.y - b->half.y - m),
                   nt_v2(b->p.x + b->half.x + m, b->p.y + b->half.y + m), r);
        for (int y = r[1]; y <= r[3]; y++)
            for (int x = r[0]; x <= r[2]; x++) {
                int32_t head = 2 * (y * v.w + x);
                /* Level 0: both lists' bits at once (head is even: the same word). */
                if (lv == 0 && !((w->occupied[(uint32_t)head >> 6] >> (head & 63)) & 3u)) continue;
                n = take_overlapping(w, v.heads[head], i, b, out, n, cap);
                n = take_overlapping(w, v.heads[head + 1], i, b, out, n, cap);
            }
    }
    return n;
}

void nt__grid_visit(const nt_world *w, nt_vec2 lo, nt_vec2 hi, nt__visit_fn *fn, void *ctx)
{
    if (!w->heads) return;
    for (int lv = 0; lv < NT__LEVELS; lv++) {
        if (lv > 0 && (!w->lheads || !(w->lcount[lv][0] | w->lcount[lv][1]))) continue;
        /* A body reaches half its level's cell beyond its cell. */
        level_view v = view_of(w, lv);
        nt_real m = v.size * (nt_real)0.5;
        int r[4];
        view_range(&v, nt_v2(lo.x - m, lo.y - m), nt_v2(hi.x + m, hi.y + m), r);
        for (int y = r[1]; y <= r[3]; y++)
            for (int x = r[0]; x <= r[2]; x++)
                for (int list = 0; list < 2; list++)
                    for (int32_t j = v.heads[2 * (y * v.w + x) + list]; j >= 0; j = w->bodies[j].gnext)
                        if (!fn(w, j, ctx)) return;
    }
}

void nt__grid_level_view(const nt_world *w, int level, const int32_t **heads, int *gw, int *gh, nt_real *size)
{
    level_view v = view_of(w, level);
    *heads = v.heads;
    *gw = v.w;
    *gh = v.h;
    *size = v.size;
}

int nt__grid_level_used(const nt_world *w, int level)
{
    if (level == 0) return w->heads != NULL;
    return w->lheads && (w->lcount[level][0] | w->lcount[level][1]);
}
