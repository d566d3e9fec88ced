/* Narrow phase: exact minimum translation vectors.
 *
 * For an object A (centre c) and a solid region T, the object is free exactly when
 * c lies outside the interior of M = T (+) A (Minkowski sum). The minimum translation
 * is the distance from c to the free set F = complement of int(M). Every routine
 * below writes F as a union of simple pieces (half-planes, discs, outsides of
 * discs restricted to a sector), so the distance to F is the smallest distance to a
 * piece: exact, not an approximation. The derivations are in the comments.
 *
 * Round tiles are solved in their canonical `pn` orientation: the object's centre
 * is mirrored into it (boxes and circles are symmetric) and the normal mirrored back.
 */
#include "core.h"

#define SIDE_BIT(s) (1u << (s))

typedef struct best {
    nt_real depth;
    nt_real nx, ny;
    int found;
} best;

static inline void best_init(best *b)
{
    b->depth = NT_REAL_MAX;
    b->nx = 0;
    b->ny = 0;
    b->found = 0;
}

/* Keeps the first of equal candidates: callers list them in a fixed order. */
static inline void consider(best *b, nt_real depth, nt_real nx, nt_real ny)
{
    if (depth < b->depth) {
        b->depth = depth;
        b->nx = nx;
        b->ny = ny;
        b->found = 1;
    }
}

static inline int finish(const best *b, int sx_flip, int sy_flip, nt_mtv *out)
{
    if (!b->found) return NT__MASKED;
    out->normal.x = sx_flip ? -b->nx : b->nx;
    out->normal.y = sy_flip ? -b->ny : b->ny;
    out->depth = b->depth;
    return NT__PUSH;
}

/* ---------- box vs convex polygon: separating axes ----------
 * M's face normals are the box's (x, y) and the polygon's; the polygon's axis-aligned
 * faces are covered by its bounds, so the candidates are four axis pushes and the
 * slope's normal. */
static int aabb_polygon(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out)
{
    const nt_tile_info *t = &nt__tiles[tile];
    const nt__tile_geom *g = &nt__geom[tile];
    nt_real dl = c.x + h.x - t->bounds_min.x; /* move -x */
    nt_real dr = t->bounds_max.x - (c.x - h.x); /* move +x */
    nt_real du = c.y + h.y - t->bounds_min.y; /* move -y */
    nt_real dd = t->bounds_max.y - (c.y - h.y); /* move +y */
    if (dl <= 0 || dr <= 0 || du <= 0 || dd <= 0) return NT__SEPARATE;
    best b;
    best_init(&b);
    if (g->has_slope) {
        /* Decide with the integer normal (exact at touching), measure with the unit one. */
        nt_real ux = g->slope[0], uy = g->slope[1];
        nt_real ds = g->slope[2] - (ux * c.x + uy * c.y) + h.x * nt__fabs(ux) + h.y * nt__fabs(uy);
        if (ds <= 0) return NT__SEPARATE;
        consider(&b, ds * g->slope[3], g->slope[4], g->slope[5]);
    }
    if (!(mask & SIDE_BIT(NT_SIDE_TOP))) consider(&b, du, 0, -1);
    if (!(mask & SIDE_BIT(NT_SIDE_BOTTOM))) consider(&b, dd, 0, 1);
    if (!(mask & SIDE_BIT(NT_SIDE_LEFT))) consider(&b, dl, -1, 0);
    if (!(mask & SIDE_BIT(NT_SIDE_RIGHT))) consider(&b, dr, 1, 0);
    return finish(&b, 0, 0, out);
}

/* ---------- circle vs convex polygon ----------
 * Centre inside: leave through the nearest face (distance + r). Centre outside: the
 * nearest point p of the polygon; push along c - p by r - |c - p|. */
static int circle_polygon(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    const nt__tile_geom *g = &nt__geom[tile];
    nt_real s[4]; /* signed distance to each edge's line; the sign is exact */
    nt_real smax = -NT_REAL_MAX;
    for (int i = 0; i < g->edge_count; i++) {
        const nt__edge *e = &g->edges[i];
        s[i] = (e->ux * c.x + e->uy * c.y - e->ud) * e->inv;
        if (s[i] > smax) smax = s[i];
    }
    if (smax >= r) return NT__SEPARATE;
    best b;
    best_init(&b);
    if (smax < 0 || (smax == 0 && r > 0)) {
        for (int i = 0; i < g->edge_count; i++) {
            const nt__edge *e = &g->edges[i];
            if (e->side >= 0 && (mask & SIDE_BIT(e->side))) continue;
            consider(&b, r - s[i], e->nx, e->ny);
        }
        return finish(&b, 0, 0, out);
    }
    if (smax == 0) return NT__SEPARATE; /* a point on the boundary */
    /* Outside: nearest point among the faces the centre sees. */
    nt_real best_d2 = NT_REAL_MAX, vx = 0, vy = 0;
    int face = -1;
    for (int i = 0; i < g->edge_count; i++) {
        if (s[i] <= 0) continue;
        const nt__edge *e = &g->edges[i];
        nt_real u = (c.x - e->ax) * e->tx + (c.y - e->ay) * e->ty;
        if (u > 0 && u < e->len) {
            nt_real d2 = s[i] * s[i];
            if (d2 < best_d2) {
                best_d2 = d2;
                face = i;
            }
        } else {
            nt_real px = u <= 0 ? e->ax : e->ax + e->tx * e->len;
            nt_real py = u <= 0 ? e->ay : e->ay + e->ty * e->len;
            nt_real dx = c.x - px, dy = c.y - py, d2 = dx * dx + dy * dy;
            if (d2 < best_d2) {
                best_d2 = d2;
                face = -1;
                vx = dx;
                vy = dy;
            }
        }
    }
    if (face >= 0) {
        const nt__edge *e = &g->edges[face];
        if (e->side >= 0 && (mask & SIDE_BIT(e->side))) return NT__MASKED;
        consider(&b, r - s[face], e->nx, e->ny);
        return finish(&b, 0, 0, out);
    }
    nt_real dist = nt__sqrt(best_d2);
    if (dist >= r) return NT__SEPARATE;
    consider(&b, r - dist, vx / dist, vy / dist);
    return finish(&b, 0, 0, out);
}

/* Canonical frame of a round tile: its `pn` orientation. */
typedef struct canon {
    nt_real x, y;
    int fx, fy;           /* mirrored in x / y */
    unsigned mleft, mbottom; /* the canonical left / bottom face is masked */
} canon;

static inline canon to_canon(int tile, nt_vec2 c, unsigned mask)
{
    const nt_tile_info *t = &nt__tiles[tile];
    canon k;
    k.fx = t->signx < 0;
    k.fy = t->signy > 0;
    k.x = k.fx ? 1 - c.x : c.x;
    k.y = k.fy ? 1 - c.y : c.y;
    k.mleft = mask & SIDE_BIT(k.fx ? NT_SIDE_RIGHT : NT_SIDE_LEFT);
    k.mbottom = mask & SIDE_BIT(k.fy ? NT_SIDE_TOP : NT_SIDE_BOTTOM);
    return k;
}

/* ---------- box vs CONVEX (quarter disc, centre o = (0,1), radius 1) ----------
 * M is convex: the box's four faces swept over the tile's extremes, and the arc
 * of radius 1 around o' = o + (hw, -hh), whose normals span the (+x, -y) quadrant.
 * The arc constrains only when c - o' points into that quadrant. */
static int aabb_convex(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out)
{
    canon k = to_canon(tile, c, mask);
    nt_real dl = k.x + h.x, dr = 1 + h.x - k.x;
    nt_real du = k.y + h.y, dd = 1 + h.y - k.y;
    if (dl <= 0 || dr <= 0 || du <= 0 || dd <= 0) return NT__SEPARATE;
    best b;
    best_init(&b);
    nt_real vx = k.x - h.x, vy = k.y - (1 - h.y);
    if (vx > 0 && vy < 0) {
        nt_real d2 = vx * vx + vy * vy;
        if (d2 >= 1) return NT__SEPARATE;
        nt_real dist = nt__sqrt(d2);
        consider(&b, 1 - dist, vx / dist, vy / dist);
    }
    consider(&b, du, 0, -1);
    if (!k.mbottom) consider(&b, dd, 0, 1);
    if (!k.mleft) consider(&b, dl, -1, 0);
    consider(&b, dr, 1, 0);
    return finish(&b, k.fx, k.fy, out);
}

/* ---------- circle vs CONVEX ----------
 * Convex tile: nearest-point logic, with the arc's Voronoi region being the quadrant
 * x >= 0, y <= 1 seen from o. */
static int circle_convex(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    canon k = to_canon(tile, c, mask);
    nt_real x = k.x, y = k.y;
    best b;
    best_init(&b);
    if (x >= 0 && y <= 1) {
        nt_real vx = x, vy = y - 1;
        nt_real d2 = vx * vx + vy * vy;
        nt_real dist = nt__sqrt(d2);
        if (d2 <= 1) {
            /* Centre in the closed quarter disc. */
            int interior = x > 0 && y < 1 && d2 < 1;
            if (!interior && r == 0) return NT__SEPARATE;
            if (dist > 0) consider(&b, 1 - dist + r, vx / dist, vy / dist);
            if (!k.mbottom) consider(&b, 1 - y + r, 0, 1);
            if (!k.mleft) consider(&b, x + r, -1, 0);
            return finish(&b, k.fx, k.fy, out);
        }
        nt_real gap = dist - 1;
        if (gap >= r) return NT__SEPARATE;
        consider(&b, r - gap, vx / dist, vy / dist);
        return finish(&b, k.fx, k.fy, out);
    }
    nt_real px, py; /* nearest point when it is a corner */
    if (x < 0 && y <= 1) {
        if (y >= 0) {
            if (-x >= r) return NT__SEPARATE;
            if (k.mleft) return NT__MASKED;
            consider(&b, r + x, -1, 0);
            return finish(&b, k.fx, k.fy, out);
        }
        px = 0;
        py = 0;
    } else if (x >= 0 && y > 1) {
        if (x <= 1) {
            if (y - 1 >= r) return NT__SEPARATE;
            if (k.mbottom) return NT__MASKED;
            consider(&b, r - (y - 1), 0, 1);
            return finish(&b, k.fx, k.fy, out);
        }
        px = 1;
        py = 1;
    } else {
        px = 0;
        py = 1;
    }
    nt_real vx = x - px, vy = y - py;
    nt_real dist = nt__sqrt(vx * vx + vy * vy);
    if (dist >= r) return NT__SEPARATE;
    consider(&b, r - dist, vx / dist, vy / dist);
    return finish(&b, k.fx, k.fy, out);
}

/* ---------- box vs CONCAVE (cell minus the disc of radius 1 around o = (1,0)) ----------
 * A box is free iff it leaves the cell's span on some side, or its corner nearest
 * the solid, p = (left, bottom), lies in the disc: the part of the box inside the
 * cell is then inside the disc, because p is that part's farthest point from o.
 * So F = {p.x >= 1} u {right <= 0} u {top >= 1} u {p.y <= 0} u {|p - o| <= 1}. */
static int aabb_concave(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out)
{
    canon k = to_canon(tile, c, mask);
    nt_real px = k.x - h.x, py = k.y + h.y;
    nt_real dr = 1 - px;         /* move +x until the left side clears x = 1 */
    nt_real dl = k.x + h.x;      /* move -x until the right side clears x = 0 */
    nt_real dd = 1 + h.y - k.y;  /* move +y until the top clears y = 1 */
    nt_real du = py;             /* move -y until the bottom clears y = 0 */
    if (dr <= 0 || dl <= 0 || dd <= 0 || du <= 0) return NT__SEPARATE;
    nt_real ox = 1 - px, oy = 0 - py;
    nt_real d2 = ox * ox + oy * oy;
    if (d2 <= 1) return NT__SEPARATE;
    nt_real dist = nt__sqrt(d2);
    best b;
    best_init(&b);
    consider(&b, dist - 1, ox / dist, oy / dist);
    consider(&b, du, 0, -1);
    if (!k.mbottom) consider(&b, dd, 0, 1);
    if (!k.mleft) consider(&b, dl, -1, 0);
    consider(&b, dr, 1, 0);
    return finish(&b, k.fx, k.fy, out);
}

/* Push toward the point v + r * unit(c - v) on the circle of radius r around v. */
static inline void consider_vertex(best *b, nt_real x, nt_real y, nt_real vx, nt_real vy, nt_real r)
{
    nt_real dx = x - vx, dy = y - vy;
    nt_real d = nt__sqrt(dx * dx + dy * dy);
    if (d <= 0) return; /* the neighbouring pieces give the same depth */
    if (d < r) consider(b, r - d, dx / d, dy / d);
    else consider(b, d - r, -dx / d, -dy / d);
}

/* ---------- circle vs CONCAVE ----------
 * The boundary of M is made of the offsets of T's features: the left and bottom
 * faces (lines x = -r, y = 1 + r), the concave arc (circle of radius 1 - r around
 * o, free inside), and circles of radius r around the corner (0,1) and the two
 * cusps (0,0) and (1,1). The free set is the union of the half-planes x <= -r,
 * y >= 1 + r, y <= -r, x >= 1 + r, the disc |c - o| <= 1 - r, and the parts of the
 * vertex circles' outsides inside each vertex's normal cone (cusp (0,0): y <= 0;
 * cusp (1,1): x >= 1; corner (0,1): x <= 0 and y >= 1). A vertex candidate whose
 * nearest circle point falls outside its cone is dominated by a neighbouring piece,
 * whose end point it would be. */
static int circle_concave(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    canon k = to_canon(tile, c, mask);
    nt_real x = k.x, y = k.y;
    nt_real ox = x - 1, oy = y;
    nt_real d2o = ox * ox + oy * oy;
    nt_real dist_o = nt__sqrt(d2o);
    /* Exact overlap test: the distance from c to T. */
    int in_cell = x >= 0 && x <= 1 && y >= 0 && y <= 1;
    if (in_cell && d2o >= 1) {
        int interior = x > 0 && x < 1 && y > 0 && y < 1 && d2o > 1;
        if (!interior && r == 0) return NT__SEPARATE;
    } else {
        nt_real ly = nt__clamp(y, 0, 1), bx = nt__clamp(x, 0, 1);
        nt_real g2 = x * x + (y - ly) * (y - ly);                   /* left face */
        nt_real gb = (x - bx) * (x - bx) + (y - 1) * (y - 1);      /* bottom face */
        if (gb < g2) g2 = gb;
        nt_real gap = nt__sqrt(g2);
        if (x <= 1 && y >= 0) gap = nt__min(gap, nt__fabs(dist_o - 1)); /* the arc */
        if (gap >= r) return NT__SEPARATE;
    }
    best b;
    best_init(&b);
    if (dist_o > 0) consider(&b, dist_o - (1 - r), -ox / dist_o, -oy / dist_o);
    consider(&b, y + r, 0, -1);
    if (!k.mbottom) consider(&b, 1 + r - y, 0, 1);
    if (!k.mleft) consider(&b, x + r, -1, 0);
    consider(&b, 1 + r - x, 1, 0);
    if (y <= 0) consider_vertex(&b, x, y, 0, 0, r);
    if (x >= 1) consider_vertex(&b, x, y, 1, 1, r);
    if (x <= 0 && y >= 1) consider_vertex(&b, x, y, 0, 1, r);
    return finish(&b, k.fx, k.fy, out);
}

int nt__collide_tile_aabb_m(int tile, nt_vec2 c, nt_vec2 h, unsigned mask, nt_mtv *out)
{
    if (tile <= NT_TILE_EMPTY || tile >= NT_TILE_COUNT) return NT__SEPARATE;
    switch (nt__tiles[tile].cls) {
    case NT_CLASS_POLYGON: return aabb_polygon(tile, c, h, mask, out);
    case NT_CLASS_CONVEX: return aabb_convex(tile, c, h, mask, out);
    case NT_CLASS_CONCAVE: return aabb_concave(tile, c, h, mask, out);
    default: return NT__SEPARATE;
    }
}

int nt__collide_tile_circle_m(int tile, nt_vec2 c, nt_real r, unsigned mask, nt_mtv *out)
{
    if (tile <= NT_TILE_EMPTY || tile >= NT_TILE_COUNT) return NT__SEPARATE;
    switch (nt__tiles[tile].cls) {
    case NT_CLASS_POLYGON: return circle_polygon(tile, c, r, mask, out);
    case NT_CLASS_CONVEX: return circle_convex(tile, c, r, mask, out);
    case NT_CLASS_CONCAVE: return circle_concave(tile, c, r, mask, out);
    default: return NT__SEPARATE;
    }
}

bool nt_collide_tile_aabb(int tile, nt_vec2 center, nt_vec2 half, nt_mtv *out)
{
    nt_mtv m;
    if (nt__collide_tile_aabb_m(tile, center, half, 0, &m) != NT__PUSH) return false;
    if (out) *out = m;
    return true;
}

bool nt_collide_tile_circle(int tile, nt_vec2 center, nt_real radius, nt_mtv *out)
{
    nt_mtv m;
    if (nt__collide_tile_circle_m(tile, center, radius, 0, &m) != NT__PUSH) return false;
    if (out) *out = m;
    return true;
}

bool nt_collide_tile_shape(int tile, nt_vec2 center, nt_shape shape, nt_mtv *out)
{
    return shape.type == NT_SHAPE_CIRCLE ? nt_collide_tile_circle(tile, center, shape.half.x, out)
                                         : nt_collide_tile_aabb(tile, center, shape.half, out);
}

/* ---------- object pairs ---------- */

bool nt_collide_aabbs(nt_vec2 ca, nt_vec2 ha, nt_vec2 cb, nt_vec2 hb, nt_mtv *out)
{
    nt_real dx = cb.x - ca.x, dy = cb.y - ca.y;
    nt_real ox = ha.x + hb.x - nt__fabs(dx);
    nt_real oy = ha.y + hb.y - nt__fabs(dy);
    if (ox <= 0 || oy <= 0) return false;
    if (out) {
        if (oy <= ox || (dx == 0 && dy == 0)) {
            out->normal = nt_v2(0, dy > 0 ? R(-1) : (dy < 0 ? R(1) : R(-1)));
            out->depth = oy;
        } else {
            out->normal = nt_v2(dx > 0 ? R(-1) : R(1), 0);
            out->depth = ox;
        }
    }
    return true;
}

bool nt_collide_circles(nt_vec2 ca, nt_real ra, nt_vec2 cb, nt_real rb, nt_mtv *out)
{
    nt_real dx = ca.x - cb.x, dy = ca.y - cb.y;
    nt_real rs = ra + rb;
    nt_real d2 = dx * dx + dy * dy;
    if (d2 >= rs * rs) return false;
    nt_real d = nt__sqrt(d2);
    if (d >= rs) return false;
    if (out) {
        if (d > 0) out->normal = nt_v2(dx / d, dy / d);
        else out->normal = nt_v2(0, -1);
        out->depth = rs - d;
    }
    return true;
}

/* Minimum translation of a circle (centre cc, radius r) out of a box (centre cb,
 * half-size hb). Coincident centres push the circle along -y. */
static bool circle_out_of_box(nt_vec2 cc, nt_real r, nt_vec2 cb, nt_vec2 hb, nt_mtv *m)
{
    nt_real dx = cc.x - cb.x, dy = cc.y - cb.y;
    nt_real qx = nt__clamp(dx, -hb.x, hb.x), qy = nt__clamp(dy, -hb.y, hb.y);
    nt_real vx = dx - qx, vy = dy - qy;
    nt_real d2 = vx * vx + vy * vy;
    if (d2 > 0) {
        nt_real d = nt__sqrt(d2);
        if (d >= r) return false;
        m->normal = nt_v2(vx / d, vy / d);
        m->depth = r - d;
        return true;
    }
    /* Centre inside the closed box: leave through the nearest face. */
    nt_real ox = hb.x - nt__fabs(dx) + r, oy = hb.y - nt__fabs(dy) + r;
    if (ox <= 0 || oy <= 0) return false;
    if (oy <= ox || (dx == 0 && dy == 0)) {
        m->normal = nt_v2(0, dy > 0 ? R(1) : R(-1));
        m->depth = oy;
    } else {
        m->normal = nt_v2(dx < 0 ? R(-1) : R(1), 0);
        m->depth = ox;
    }
    return true;
}

bool nt_collide_aabb_circle(nt_vec2 ca, nt_vec2 ha, nt_vec2 cb, nt_real rb, nt_mtv *out)
{
    nt_mtv m;
    if (!circle_out_of_box(cb, rb, ca, ha, &m)) return false;
    if (out) {
        /* The box leaves the opposite way; coincident centres still push it along -y. */
        if (ca.x == cb.x && ca.y == cb.y) out->normal = nt_v2(0, -1);
        else out->normal = nt_v2(-m.normal.x, -m.normal.y);
        out->depth = m.depth;
    }
    return true;
}

bool nt_collide_shapes(nt_vec2 pa, nt_shape a, nt_vec2 pb, nt_shape b, nt_mtv *out)
{
    if (a.type == NT_SHAPE_AABB && b.type == NT_SHAPE_AABB) return nt_collide_aabbs(pa, a.half, pb, b.half, out);
    if (a.type == NT_SHAPE_CIRCLE && b.type == NT_SHAPE_CIRCLE)
        return nt_collide_circles(pa, a.half.x, pb, b.half.x, out);
    if (a.type == NT_SHAPE_AABB) return nt_collide_aabb_circle(pa, a.half, pb, b.half.x, out);
    nt_mtv m;
    if (!circle_out_of_box(pa, a.half.x, pb, b.half, &m)) return false;
    if (out) *out = m;
    return true;
}
