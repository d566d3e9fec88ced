/* The overlap and gap of two objects' shapes (boxes and circles): the arithmetic of
 * the public pair routines (narrow.c), of the pair search (grid.c, pair_depth: a
 * contact's depth, > 0 overlap, < 0 gap) and of the position correction (response.c,
 * push_pair), in one place so that their answers cannot drift apart. Inline: the hot
 * callers make no call, and a constant `gap` leaves out what a caller does not need:
 * gap = 0 the gap of shapes apart, gap = 1 the exit before the square root (a gap
 * needs the root). Not installed. */
#ifndef NT_PAIR_INTERNAL_H
#define NT_PAIR_INTERNAL_H

#include "core_internal.h"

/* Two boxes (centres ca, cb, half-sizes ha, hb): the offset d = cb - ca and the
 * overlaps along x and y (both > 0: overlapping). */
typedef struct nt__box_pair {
    nt_real dx, dy, ox, oy;
} nt__box_pair;

static NT__INLINE nt__box_pair nt__box_overlaps(nt_vec2 ca, nt_vec2 ha, nt_vec2 cb, nt_vec2 hb)
{
    nt__box_pair q;
    q.dx = cb.x - ca.x;
    q.dy = cb.y - ca.y;
    q.ox = ha.x + hb.x - nt__fabs(q.dx);
    q.oy = ha.y + hb.y - nt__fabs(q.dy);
    return q;
}

/* nt_collide_aabbs. Overlapping: returns 1, m the push of a out of b, along the axis
 * of least overlap (y on ties and for coincident centres). Apart: returns 0; with gap,
 * m->depth is minus the gap along the axis where it is larger (it bounds the
 * distance from below) and m->normal points from a towards b along that axis. */
static NT__INLINE int nt__aabbs_depth(nt_vec2 ca, nt_vec2 ha, nt_vec2 cb, nt_vec2 hb, int gap, nt_mtv *m)
{
    nt__box_pair q = nt__box_overlaps(ca, ha, cb, hb);
    nt_real dx = q.dx, dy = q.dy, ox = q.ox, oy = q.oy;
    if (ox <= 0 || oy <= 0) {
        if (!gap) return 0;
        if (ox < oy) {
            m->normal = nt_v2(dx > 0 ? (nt_real)1 : (nt_real)(-1), 0);
            m->depth = ox;
        } else {
            m->normal = nt_v2(0, dy > 0 ? (nt_real)1 : (nt_real)(-1));
            m->depth = oy;
        }
        return 0;
    }
    if (oy <= ox || (dx == 0 && dy == 0)) {
        m->normal = nt_v2(0, dy > 0 ? (nt_real)(-1) : (dy < 0 ? (nt_real)1 : (nt_real)(-1)));
        m->depth = oy;
    } else {
        m->normal = nt_v2(dx > 0 ? (nt_real)(-1) : (nt_real)1, 0);
        m->depth = ox;
    }
    return 1;
}

/* nt_collide_circles (centres ca, cb, radii ra, rb). Overlapping: returns 1, m the
 * push of a out of b (coincident centres: along -y). Apart: returns 0; with gap,
 * m->depth is minus the gap and m->normal points from a towards b. With gap, an
 * offset whose |ca - cb|^2 is not > 0 (coincident centres, an underflow, NaN) gives
 * no direction: returns -1, m unset. The normals
 * are the quotients of ca - cb and of cb - ca as written, so that zeros keep their
 * signs. */
static NT__INLINE int nt__circles_depth(nt_vec2 ca, nt_real ra, nt_vec2 cb, nt_real rb, int gap, nt_mtv *m)
{
    nt_real dx = ca.x - cb.x, dy = ca.y - cb.y;
    nt_real rs = ra + rb;
    nt_real d2 = dx * dx + dy * dy;
    if (gap && !(d2 > 0)) return -1;
    int far = d2 >= rs * rs;
    if (far && !gap) return 0; /* apart, known without the root */
    nt_real d = nt__sqrt(d2);
    if (far || d >= rs) {
        if (!gap) return 0;
        m->normal = nt_v2((cb.x - ca.x) / d, (cb.y - ca.y) / d);
        m->depth = rs - d;
        return 0;
    }
    /* With gap, d > 0 is known. */
    if (gap || d > 0) m->normal = nt_v2(dx / d, dy / d);
    else m->normal = nt_v2(0, -1);
    m->depth = rs - d;
    return 1;
}

/* A circle's centre cc and a box (centre cb, half-size hb): the centre's offset d from
 * the box's, and its offset v from the box's nearest point (0 inside the closed box),
 * with |v|^2. */
typedef struct nt__box_point {
    nt_real dx, dy, vx, vy, d2;
} nt__box_point;

static NT__INLINE nt__box_point nt__box_nearest(nt_vec2 cc, nt_vec2 cb, nt_vec2 hb)
{
    nt__box_point q;
    q.dx = cc.x - cb.x;
    q.dy = cc.y - cb.y;
    q.vx = q.dx - nt__clamp(q.dx, -hb.x, hb.x);
    q.vy = q.dy - nt__clamp(q.dy, -hb.y, hb.y);
    q.d2 = q.vx * q.vx + q.vy * q.vy;
    return q;
}

/* The centre outside the box (q->d2 > 0), circle of radius r: m->depth = r - |v| (> 0:
 * overlapping, returns 1; otherwise minus the gap, returns 0) and m->normal = s v / |v|
 * (s = 1: the way the circle leaves the box; -1: the way the box leaves the circle).
 * Without gap, m is set only when overlapping. */
static NT__INLINE int nt__circle_box_out(const nt__box_point *q, nt_real r, nt_real s, int gap, nt_mtv *m)
{
    nt_real d = nt__sqrt(q->d2);
    int hit = !(d >= r);
    if (!hit && !gap) return 0;
    m->normal = nt_v2(s * q->vx / d, s * q->vy / d);
    m->depth = r - d;
    return hit;
}

/* The centre inside the closed box (q->d2 = 0, or NaN): the circle leaves
 * through the nearest face, along -y for coincident centres. */
static NT__INLINE int nt__circle_box_in(const nt__box_point *q, nt_real r, nt_vec2 hb, nt_mtv *m)
{
    nt_real dx = q->dx, dy = q->dy;
    nt_real ox = hb.x - nt__fabs(dx) + r, oy = hb.y - nt__fabs(dy) + r;
    if (ox <= 0 || oy <= 0) return 0;
    if (oy <= ox || (dx == 0 && dy == 0)) {
        m->normal = nt_v2(0, dy > 0 ? (nt_real)1 : (nt_real)(-1));
        m->depth = oy;
    } else {
        m->normal = nt_v2(dx < 0 ? (nt_real)(-1) : (nt_real)1, 0);
        m->depth = ox;
    }
    return 1;
}

/* Minimum translation of a circle (centre cc, radius r) out of a box (centre cb,
 * half-size hb): returns 1 and sets m when they overlap. */
static NT__INLINE int nt__circle_box_depth(nt_vec2 cc, nt_real r, nt_vec2 cb, nt_vec2 hb, nt_mtv *m)
{
    nt__box_point q = nt__box_nearest(cc, cb, hb);
    if (q.d2 > 0) return nt__circle_box_out(&q, r, 1, 0, m);
    return nt__circle_box_in(&q, r, hb, m);
}

/* nt_collide_aabb_circle: box a, circle b. */
static NT__INLINE int nt__aabb_circle_depth(nt_vec2 ca, nt_vec2 ha, nt_vec2 cb, nt_real rb, nt_mtv *m)
{
    if (!nt__circle_box_depth(cb, rb, ca, ha, m)) return 0;
    /* The box leaves the opposite way; coincident centres still push it along -y. */
    if (ca.x == cb.x && ca.y == cb.y) m->normal = nt_v2(0, -1);
    else m->normal = nt_v2(-m->normal.x, -m->normal.y);
    return 1;
}

/* nt_collide_shapes, the shapes by type and half-size: returns 1 and sets m (the push
 * of a out of b) when they overlap. */
static NT__INLINE int nt__shapes_depth(nt_vec2 pa, int ta, nt_vec2 ha, nt_vec2 pb, int tb, nt_vec2 hb, nt_mtv *m)
{
    if (ta == NT_SHAPE_AABB && tb == NT_SHAPE_AABB) return nt__aabbs_depth(pa, ha, pb, hb, 0, m);
    if (ta == NT_SHAPE_CIRCLE && tb == NT_SHAPE_CIRCLE) return nt__circles_depth(pa, ha.x, pb, hb.x, 0, m);
    if (ta == NT_SHAPE_AABB) return nt__aabb_circle_depth(pa, ha, pb, hb.x, m);
    return nt__circle_box_depth(pa, ha.x, pb, hb, m);
}

#endif /* NT_PAIR_INTERNAL_H */
