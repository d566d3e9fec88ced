/* The tile map: cells, N's edge states, and resolution (freeing an object from
 * every tile it overlaps by the shortest way out of their union). */
#include <string.h>
#include "core_internal.h"

nt_map_def nt_default_map_def(void)
{
    nt_map_def d;
    d.width = 31;
    d.height = 23;
    d.cell_size = 24;
    return d;
}

static const int side_dx[4] = {-1, 1, 0, 0};
static const int side_dy[4] = {0, 0, -1, 1};
static const int side_opposite[4] = {NT_SIDE_RIGHT, NT_SIDE_LEFT, NT_SIDE_BOTTOM, NT_SIDE_TOP};

/* How tile `t` meets side `s`: 0 = not at all, 1 = partly (interval or point), 2 = whole. */
static int cover_kind(int t, int s)
{
    const nt_tile_info *info = &nt__tiles[t];
    nt_real lo = info->cover_lo[s], hi = info->cover_hi[s];
    if (lo > hi) return 0;
    return (lo <= 0 && hi >= 1) ? 2 : 1;
}

/* Cell data for (x, y) computed from the tiles around it. */
static nt__cell compute_cell(const nt_map *map, int x, int y)
{
    nt__cell c;
    c.tile = (uint8_t)nt__map_tile(map, x, y);
    c.edges = 0;
    c.seams = 0;
    c.walls = 0;
    for (int s = 0; s < 4; s++) {
        int nb = nt__map_tile(map, x + side_dx[s], y + side_dy[s]);
        int o = side_opposite[s];
        int mine = cover_kind(c.tile, s), theirs = cover_kind(nb, o);
        nt_edge e;
        if ((mine == 2 && theirs == 2) || (mine == 0 && theirs == 0)) e = NT_EDGE_OFF;
        else if (mine == 2 || theirs == 2) e = NT_EDGE_SOLID;
        else e = NT_EDGE_INTERESTING;
        c.edges |= (uint8_t)(e << (2 * s));
        if (theirs == 2) c.walls |= (uint8_t)(1u << s);
        /* A face is a seam when the neighbour's solid covers all of it. */
        const nt_tile_info *a = &nt__tiles[c.tile], *b = &nt__tiles[nb];
        if (mine && a->cover_lo[s] < a->cover_hi[s] && theirs && b->cover_lo[o] <= a->cover_lo[s] &&
            b->cover_hi[o] >= a->cover_hi[s])
            c.seams |= (uint8_t)(1u << s);
    }
    return c;
}

nt__cell nt__map_cell(const nt_map *map, int x, int y)
{
    if (x < 0 || y < 0 || x >= map->w || y >= map->h) return compute_cell(map, x, y);
    return map->cells[(size_t)y * (size_t)map->w + (size_t)x];
}

static void refresh_open3(nt_map *map, int x, int y)
{
    if (x < 0 || y < 0 || x >= map->w || y >= map->h) return;
    unsigned near = 0;
    for (int j = -1; j <= 1; j++)
        for (int i = -1; i <= 1; i++) {
            int cx = x + i, cy = y + j;
            if (cx < 0 || cy < 0 || cx >= map->w || cy >= map->h ||
                map->cells[(size_t)cy * (size_t)map->w + (size_t)cx].tile != NT_TILE_EMPTY)
                near |= 1u << (3 * (j + 1) + i + 1);
        }
    size_t k = (size_t)y * (size_t)map->w + (size_t)x;
    map->near9[k] = (uint16_t)near;
    if (!near) map->open3[k >> 6] |= (uint64_t)1 << (k & 63);
    else map->open3[k >> 6] &= ~((uint64_t)1 << (k & 63));
}

static void refresh_open3_all(nt_map *map)
{
    for (int y = 0; y < map->h; y++)
        for (int x = 0; x < map->w; x++) refresh_open3(map, x, y);
}

static void count_block_cell(nt_map *map, int x, int y, int tile, int sign)
{
    size_t b = (size_t)(y / NT__BLOCK) * (size_t)map->bw + (size_t)(x / NT__BLOCK);
    if (tile == NT_TILE_EMPTY) map->blk_empty[b] = (uint8_t)(map->blk_empty[b] + sign);
    if (tile != NT_TILE_FULL) map->blk_open[b] = (uint8_t)(map->blk_open[b] + sign);
}

static void count_blocks_all(nt_map *map)
{
    size_t nb = (size_t)map->bw * (size_t)map->bh;
    memset(map->blk_empty, 0, nb);
    memset(map->blk_open, 0, nb);
    for (int y = 0; y < map->h; y++)
        for (int x = 0; x < map->w; x++) count_block_cell(map, x, y, map->cells[(size_t)y * (size_t)map->w + (size_t)x].tile, 1);
}

/* The smallest Chebyshev distance from cell (cx, cy) to a cell of the map within
 * `reach` of it whose block counts a cell of `cnt` (conservative: a block's nearest
 * cell), or -1 when no block within reach has one. */
static int nearest_block(const nt_map *map, const uint8_t *cnt, int cx, int cy, int reach)
{
    int bx0 = cx - reach, by0 = cy - reach, bx1 = cx + reach, by1 = cy + reach;
    if (bx1 < 0 || by1 < 0 || bx0 >= map->w || by0 >= map->h) return -1;
    bx0 = bx0 < 0 ? 0 : bx0 / NT__BLOCK;
    by0 = by0 < 0 ? 0 : by0 / NT__BLOCK;
    bx1 = (bx1 >= map->w ? map->w - 1 : bx1) / NT__BLOCK;
    by1 = (by1 >= map->h ? map->h - 1 : by1) / NT__BLOCK;
    int best = -1;
    for (int by = by0; by <= by1; by++)
        for (int bx = bx0; bx <= bx1; bx++) {
            if (!cnt[(size_t)by * (size_t)map->bw + (size_t)bx]) continue;
            int lx = bx * NT__BLOCK, hx = lx + NT__BLOCK - 1, ly = by * NT__BLOCK, hy = ly + NT__BLOCK - 1;
            int dx = cx < lx ? lx - cx : cx > hx ? cx - hx : 0;
            int dy = cy < ly ? ly - cy : cy > hy ? cy - hy : 0;
            int dd = dx > dy ? dx : dy;
            if (best < 0 || dd < best) best = dd;
        }
    return best;
}

nt_status nt_map_create(const nt_map_def *def, nt_map **out)
{
    if (!out) return NT_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!def) return NT_ERR_INVALID_ARGUMENT;
    if (!nt__finite(def->cell_size)) return NT_ERR_NON_FINITE;
    if (def->cell_size <= 0) return NT_ERR_INVALID_ARGUMENT;
    if (def->cell_size < (nt_real)NT_MIN_CELL_SIZE || def->cell_size > (nt_real)NT_MAX_CELL_SIZE) return NT_ERR_OUT_OF_RANGE;
    if (def->width < 1 || def->height < 1 || def->width > NT_MAP_MAX_SIDE || def->height > NT_MAP_MAX_SIDE)
        return NT_ERR_OUT_OF_RANGE;
    nt_map *m = (nt_map *)nt__alloc(sizeof *m);
    if (!m) return NT_ERR_OUT_OF_MEMORY;
    size_t n = (size_t)def->width * (size_t)def->height;
    m->cells = (nt__cell *)nt__alloc(n * sizeof *m->cells);
    m->open3 = (uint64_t *)nt__alloc(((n + 63) / 64) * sizeof *m->open3);
    m->near9 = (uint16_t *)nt__alloc(n * sizeof *m->near9);
    m->bw = (def->width + NT__BLOCK - 1) / NT__BLOCK;
    m->bh = (def->height + NT__BLOCK - 1) / NT__BLOCK;
    m->blk_empty = (uint8_t *)nt__alloc((size_t)m->bw * (size_t)m->bh);
    m->blk_open = (uint8_t *)nt__alloc((size_t)m->bw * (size_t)m->bh);
    if (!m->cells || !m->open3 || !m->near9 || !m->blk_empty || !m->blk_open) {
        nt_map_destroy(m); /* frees what was allocated (nt__free takes NULL) */
        return NT_ERR_OUT_OF_MEMORY;
    }
    m->w = def->width;
    m->h = def->height;
    m->cell = def->cell_size;
    m->inv_cell = 1 / def->cell_size;
    m->far_w = (nt_real)m->w + 2;
    m->far_h = (nt_real)m->h + 2;
    memset(m->cells, 0, n * sizeof *m->cells);
    for (int y = 0; y < m->h; y++)
        for (int x = 0; x < m->w; x++)
            if (x == 0 || y == 0 || x == m->w - 1 || y == m->h - 1) /* the border's edges */
                m->cells[(size_t)y * (size_t)m->w + (size_t)x] = compute_cell(m, x, y);
    refresh_open3_all(m);
    count_blocks_all(m);
    *out = m;
    return NT_OK;
}

/* Also frees nt_map_create's partial map: it must touch only these arrays. */
void nt_map_destroy(nt_map *map)
{
    if (!map) return;
    nt__free(map->cells);
    nt__free(map->open3);
    nt__free(map->near9);
    nt__free(map->blk_empty);
    nt__free(map->blk_open);
    nt__free(map);
}

int nt_map_get_width(const nt_map *map) { return map ? map->w : 0; }
int nt_map_get_height(const nt_map *map) { return map ? map->h : 0; }
nt_real nt_map_get_cell_size(const nt_map *map) { return map ? map->cell : 0; }

static void refresh(nt_map *map, int x, int y)
{
    if (x < 0 || y < 0 || x >= map->w || y >= map->h) return;
    map->cells[(size_t)y * (size_t)map->w + (size_t)x] = compute_cell(map, x, y);
}

nt_status nt_map_set_tile(nt_map *map, int x, int y, int tile)
{
    if (!map) return NT_ERR_INVALID_ARGUMENT;
    if (x < 0 || y < 0 || x >= map->w || y >= map->h) return NT_ERR_OUT_OF_RANGE;
    if (tile < 0 || tile >= NT_TILE_COUNT) return NT_ERR_OUT_OF_RANGE;
    count_block_cell(map, x, y, map->cells[(size_t)y * (size_t)map->w + (size_t)x].tile, -1);
    count_block_cell(map, x, y, tile, 1);
    map->cells[(size_t)y * (size_t)map->w + (size_t)x].tile = (uint8_t)tile;
    refresh(map, x, y);
    for (int s = 0; s < 4; s++) refresh(map, x + side_dx[s], y + side_dy[s]);
    for (int j = y - 1; j <= y + 1; j++)
        for (int i = x - 1; i <= x + 1; i++) refresh_open3(map, i, j);
    return NT_OK;
}

nt_status nt_map_set_tiles(nt_map *map, const uint8_t *tiles, size_t count)
{
    if (!map || !tiles) return NT_ERR_INVALID_ARGUMENT;
    size_t n = (size_t)map->w * (size_t)map->h;
    if (count != n) return NT_ERR_INVALID_ARGUMENT;
    for (size_t i = 0; i < n; i++)
        if (tiles[i] >= NT_TILE_COUNT) return NT_ERR_OUT_OF_RANGE;
    for (size_t i = 0; i < n; i++) map->cells[i].tile = tiles[i];
    for (int y = 0; y < map->h; y++)
        for (int x = 0; x < map->w; x++) refresh(map, x, y);
    refresh_open3_all(map);
    count_blocks_all(map);
    return NT_OK;
}

int nt_map_get_tile(const nt_map *map, int x, int y)
{
    if (!map) return NT_TILE_FULL;
    return nt__map_tile(map, x, y);
}

nt_edge nt_map_get_edge(const nt_map *map, int x, int y, nt_side side)
{
    if (!map || x < 0 || y < 0 || x >= map->w || y >= map->h || (unsigned)side > 3u) return NT_EDGE_OFF;
    return (nt_edge)((map->cells[(size_t)y * (size_t)map->w + (size_t)x].edges >> (2 * side)) & 3);
}

/* ------------------------------------------------------------------------------
 * Resolution.
 *
 * Work in cell units. An object up to half a cell overlaps at most 2 x 2 cells;
 * larger ones take resolve_big (below), the same plan sized for them. Each overlapped
 * tile gives its exact minimum translation with the seam faces masked (a push
 * through a face that the neighbour covers only enters the neighbour). The answer
 * is the shortest candidate that frees the object from every tile; a candidate no
 * longer than the deepest single-tile overlap is provably optimal. Otherwise the
 * boundary curves within reach are enumerated exactly (enumerate() below); deep
 * spots with no way out within reach fall back to a search over directions and,
 * last, to the nearest empty cell (escape()).
 * ------------------------------------------------------------------------------ */

typedef struct cand {
    nt_real nx, ny, depth; /* push = n * depth, cell units */
    int cx, cy;            /* its cell */
} cand;

#define MAX_CANDS 4

/* The map as the resolution sees it: cells numbered from the cell (ox, oy) of the
 * map, which is the local origin of every position it computes with (cell units).
 * Near that origin float keeps the precision it has near the map's origin, so the
 * answers (pushes, depths) are as exact at the far corner of the largest map as near
 * its origin; only the caller's world position rounds them. The map's own cells are
 * x0 <= x < w, y0 <= y < h here. */
typedef struct mview {
    const nt_map *map;
    int ox, oy;
} mview;

/* The map's own cells in the view: VX0 <= x < VX1, VY0 <= y < VY1. */
#define VX0(v) (-(v)->ox)
#define VY0(v) (-(v)->oy)
#define VX1(v) ((v)->map->w - (v)->ox)
#define VY1(v) ((v)->map->h - (v)->oy)

static inline int vtile(const mview *v, int x, int y) { return nt__map_tile(v->map, x + v->ox, y + v->oy); }
static inline nt__cell vcell(const mview *v, int x, int y) { return nt__map_cell(v->map, x + v->ox, y + v->oy); }

/* The view from the corner of the cell holding pos (world units), and *p: pos in
 * cell units from there. The position in cells is rounded once, as every caller
 * rounds it (casts, queries, the world's cell ranges), so that they all see the
 * object where the resolution does; the subtraction of the corner is exact. What
 * the resolution then computes (depths, pushes, free tests, their rounding
 * allowances) keeps the precision it has near the map's origin. (A position outside
 * the map gives a corner outside it: cells there are border cells all the same.) */
static inline mview local_view(const nt_map *map, nt_vec2 pos, nt_vec2 *p)
{
    mview v;
    nt_real ic = map->inv_cell;
    nt_real gx = pos.x * ic, gy = pos.y * ic;
    v.map = map;
    v.ox = nt__floor_int(gx);
    v.oy = nt__floor_int(gy);
    p->x = gx - (nt_real)v.ox;
    p->y = gy - (nt_real)v.oy;
    return v;
}

/* The object being resolved (cell units): the map as the resolution sees it, its
 * shape and half-size, for the helpers that test it at many places. */
typedef struct probe {
    const mview *map;
    nt_shape shape;
    nt_vec2 h;
} probe;
/* Large objects: distinct push normals kept (see resolve_big). */
#define BIG_CANDS 16

/* Per-tile test in cell units; local coordinates keep float precision. */
static int tile_test(int tile, nt_real lx, nt_real ly, nt_shape shape, nt_vec2 h, unsigned mask, nt_mtv *m)
{
    nt_vec2 c = nt_v2(lx, ly);
    return shape.type == NT_SHAPE_CIRCLE ? nt__collide_map_tile_circle_m(tile, c, h.x, mask, m)
                                         : nt__collide_map_tile_aabb_m(tile, c, h, mask, m);
}

/* Cell range the object's interior can touch. */
static inline void cell_range(nt_vec2 p, nt_vec2 h, int *x0, int *y0, int *x1, int *y1)
{
    *x0 = nt__floor_int(p.x - h.x);
    *x1 = nt__floor_int(p.x + h.x);
    *y0 = nt__floor_int(p.y - h.y);
    *y1 = nt__floor_int(p.y + h.y);
}

/* cell_range for p in [0, 1] x [0, 1] and h in [0, 1/2] (a small object at its local
 * view's origin): p - h then lies in [-1/2, 1] and p + h in [0, 3/2], where
 * nt__floor_int is these comparisons. */
static inline void cell_range_local(nt_vec2 p, nt_vec2 h, int *x0, int *y0, int *x1, int *y1)
{
    nt_real lx = p.x - h.x, ly = p.y - h.y;
    *x0 = (lx >= 1) - (lx < 0);
    *x1 = p.x + h.x >= 1;
    *y0 = (ly >= 1) - (ly < 0);
    *y1 = p.y + h.y >= 1;
}

/* Largest single-tile depth at p (cell units), no masks: 0 when free. */
static nt_real depth_at(const mview *map, nt_vec2 p, nt_shape shape, nt_vec2 h)
{
    int x0, y0, x1, y1;
    cell_range(p, h, &x0, &y0, &x1, &y1);
    nt_real worst = 0;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            int t = vtile(map, x, y);
            if (t == NT_TILE_EMPTY) continue;
            nt_mtv m;
            if (tile_test(t, p.x - (nt_real)x, p.y - (nt_real)y, shape, h, 0, &m) == NT__PUSH && m.depth > worst)
                worst = m.depth;
        }
    return worst;
}

/* What gather finds at the object's place, for best_candidate: the cell range its
 * interior can touch, the masked per-tile candidates, the number of overlapped tiles
 * (`overlapped`), of non-EMPTY tiles in range (`present`), whether every overlapped
 * tile is convex, and lb, the deepest unmasked single-tile depth (no way out of the
 * union is shorter), or -1 when a masked tile overlaps; with use_masks, lb0 is that
 * depth over the tiles without seams (masked_depth adds the others). */
typedef struct gathered {
    int x0, y0, x1, y1;
    cand cs[MAX_CANDS];
    int nc, overlapped, present, all_convex;
    nt_real lb, lb0;
} gathered;

/* Gather the per-tile candidates of the object at p (seams masked when use_masks);
 * returns the number of overlapped tiles. A small object, p in [0, 1] x [0, 1] (the
 * caller's local view, which is in or near the map). */
static int gather(const probe *o, nt_vec2 p, unsigned use_masks, gathered *g)
{
    const mview *map = o->map;
    const nt_shape shape = o->shape;
    const nt_vec2 h = o->h;
    cell_range_local(p, h, &g->x0, &g->y0, &g->x1, &g->y1);
    const int x0 = g->x0, y0 = g->y0, x1 = g->x1, y1 = g->y1;
    const int ox = map->ox, oy = map->oy;
    int overlapped = 0, inside = x0 + ox >= 0 && y0 + oy >= 0 && x1 + ox < map->map->w && y1 + oy < map->map->h;
    const nt__cell *cells = map->map->cells;
    const size_t stride = (size_t)map->map->w;
    g->nc = 0;
    g->all_convex = 1;
    g->present = 0;
    g->lb = 0;
    g->lb0 = 0;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            /* Cells in the map are read directly; border cells are computed. */
            nt__cell cell = inside ? cells[(size_t)(y + oy) * stride + (size_t)(x + ox)] : vcell(map, x, y);
            int t = cell.tile;
            if (t == NT_TILE_EMPTY) continue;
            g->present++;
            nt_mtv m;
            unsigned mask = use_masks ? cell.seams : 0u;
            int r = tile_test(t, p.x - (nt_real)x, p.y - (nt_real)y, shape, h, mask, &m);
            if (r == NT__SEPARATE) continue;
            overlapped++;
            /* A masked tile's own depth is not known here: the bound is then left to
             * masked_depth, computed only if the certificate below fails. */
            if (mask) g->lb = -1;
            else if (r == NT__PUSH && m.depth > g->lb0) g->lb0 = m.depth;
            if (nt__tiles[t].cls == NT_CLASS_CONCAVE) g->all_convex = 0;
            if (r == NT__PUSH && g->nc < MAX_CANDS) {
                cand *c = &g->cs[g->nc++];
                c->nx = m.normal.x;
                c->ny = m.normal.y;
                c->depth = m.depth;
                c->cx = x;
                c->cy = y;
            }
        }
    g->overlapped = overlapped;
    if (g->lb == 0) g->lb = g->lb0;
    return overlapped;
}

/* depth_at(map, p, shape, h) after gather(o, p, 1u, g): the tests of its tiles without
 * seams were depth_at's own; the others are tested again without masks. */
static nt_real masked_depth(const mview *map, nt_vec2 p, nt_shape shape, nt_vec2 h, const gathered *g)
{
    nt_real worst = g->lb0;
    for (int y = g->y0; y <= g->y1; y++)
        for (int x = g->x0; x <= g->x1; x++) {
            nt__cell cell = vcell(map, x, y);
            if (cell.tile == NT_TILE_EMPTY || !cell.seams) continue;
            nt_mtv m;
            if (tile_test(cell.tile, p.x - (nt_real)x, p.y - (nt_real)y, shape, h, 0, &m) == NT__PUSH && m.depth > worst)
                worst = m.depth;
        }
    return worst;
}

/* Residual overlap accepted as "free": rounding of positions, not geometry. */
static inline nt_real free_tolerance(nt_vec2 p)
{
    nt_real mag = nt__max(nt__fabs(p.x), nt__fabs(p.y));
    return (nt_real)16 * NT_REAL_EPS * nt__max((nt_real)1, mag);
}

/* Is some tile overlapped deeper than tol at p? (depth_at(...) > tol, stopping at
 * the first such tile.) gap_shortcut, a constant at each call, adds big_free's
 * concave-gap verdicts: their rounding could settle a borderline case otherwise
 * than tile_test, so the free tests of small objects keep the plain scan. Inline:
 * each caller gets its own loop, with the shortcut compiled in or out. */
static inline int overlaps_beyond(const mview *map, nt_vec2 p, nt_shape shape, nt_vec2 h, nt_real tol, int gap_shortcut)
{
    int x0, y0, x1, y1;
    cell_range(p, h, &x0, &y0, &x1, &y1);
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            int t = vtile(map, x, y);
            if (t == NT_TILE_EMPTY) continue;
            /* A circle's depth in a tile is at least r minus its centre's distance to
             * the solid: for CONCAVE tiles (whose way out is a search) that settles
             * most verdicts. */
            if (gap_shortcut && shape.type == NT_SHAPE_CIRCLE && nt__tiles[t].cls == NT_CLASS_CONCAVE) {
                nt_real gap = nt__concave_gap(t, nt_v2(p.x - (nt_real)x, p.y - (nt_real)y));
                if (gap >= h.x) continue;
                if (h.x - gap > tol) return 1;
            }
            nt_mtv m;
            if (tile_test(t, p.x - (nt_real)x, p.y - (nt_real)y, shape, h, 0, &m) == NT__PUSH && m.depth > tol) return 1;
        }
    return 0;
}

/* depth_at(map, p, shape, h) <= tol (depth_at is at least 0: a negative or NaN tol
 * is never met). */
static int depth_within(const mview *map, nt_vec2 p, nt_shape shape, nt_vec2 h, nt_real tol)
{
    if (!(tol >= 0)) return 0;
    return !overlaps_beyond(map, p, shape, h, tol, 0);
}

static int is_free(const mview *map, nt_vec2 p, nt_shape shape, nt_vec2 h)
{
    return depth_within(map, p, shape, h, free_tolerance(p));
}

/* Free up to rounding only: for searches that converge onto the contact. */
static int is_free_strict(const mview *map, nt_vec2 p, nt_shape shape, nt_vec2 h)
{
    nt_real mag = nt__max((nt_real)1, nt__max(nt__fabs(p.x), nt__fabs(p.y)));
    return depth_within(map, p, shape, h, (nt_real)8 * NT_REAL_EPS * mag);
}

/* is_free's verdict, by the early-out scan with the concave-gap shortcut. */
static int big_free(const mview *map, nt_vec2 p, nt_shape shape, nt_vec2 h)
{
    return !overlaps_beyond(map, p, shape, h, free_tolerance(p), 1);
}

static int probe_free(const probe *o, nt_vec2 p) { return big_free(o->map, p, o->shape, o->h); }

/* The displacement d with d.n1 = depth1 and d.n2 = depth2 (the corner of two
 * push planes). Returns 0 when the planes are (nearly) parallel. */
static int corner(const cand *a, const cand *b, nt_vec2 *d)
{
    nt_real det = a->nx * b->ny - a->ny * b->nx;
    if (nt__fabs(det) < (nt_real)(1e-3)) return 0;
    d->x = (a->depth * b->ny - b->depth * a->ny) / det;
    d->y = (b->depth * a->nx - a->depth * b->nx) / det;
    return 1;
}

static void set_single(nt_resolution *out, const cand *c)
{
    out->push = nt_v2(c->nx * c->depth, c->ny * c->depth);
    out->contact_count = 1;
    out->contacts[0].normal = nt_v2(c->nx, c->ny);
    out->contacts[0].depth = c->depth;
    out->contacts[0].cell_x = c->cx;
    out->contacts[0].cell_y = c->cy;
}

static void set_pair(nt_resolution *out, nt_vec2 d, const cand *a, const cand *b)
{
    out->push = d;
    out->contact_count = 2;
    const cand *cc[2] = {a, b};
    for (int i = 0; i < 2; i++) {
        out->contacts[i].normal = nt_v2(cc[i]->nx, cc[i]->ny);
        out->contacts[i].depth = cc[i]->depth;
        out->contacts[i].cell_x = cc[i]->cx;
        out->contacts[i].cell_y = cc[i]->cy;
    }
}

/* The shortest freeing push among the candidates: a single, shortest first, or a
 * corner of two (which may be shorter than a freeing single that goes a long way
 * round). Nothing shorter than lb, the deepest single-tile overlap, is taken: it
 * could free the object only within the tolerance of the free test. Small objects
 * (big = 0) keep their corners within 1.5 cells; large ones test freeness with the
 * early-out scan (the same verdicts). The scalar parameters, not a probe: the small
 * path's caller is inlined into nt__map_resolve, where a struct cost 0.5 % of the
 * particles scene. */
static int shortest_freeing(const probe *o, nt_vec2 p, const cand *cs, int nc, nt_real lb, int big, nt_resolution *out)
{
    const mview *map = o->map;
    const nt_shape shape = o->shape;
    const nt_vec2 h = o->h;
    nt_real mag = nt__max((nt_real)1, nt__max(nt__fabs(p.x), nt__fabs(p.y)));
    nt_real floor_len = lb - (nt_real)8 * NT_REAL_EPS * mag;
    nt_real max_corner = big ? NT_REAL_MAX : (nt_real)1.5;
    int order[BIG_CANDS];
    for (int i = 0; i < nc; i++) order[i] = i;
    for (int i = 1; i < nc; i++)
        for (int j = i; j > 0 && cs[order[j]].depth < cs[order[j - 1]].depth; j--) {
            int t = order[j];
            order[j] = order[j - 1];
            order[j - 1] = t;
        }
    nt_real best_len = NT_REAL_MAX;
    int found = 0;
    for (int k = 0; k < nc; k++) {
        const cand *c = &cs[order[k]];
        if (c->depth < floor_len) continue;
        nt_vec2 q = nt_v2(p.x + c->nx * c->depth, p.y + c->ny * c->depth);
        if (big ? big_free(map, q, shape, h) : is_free(map, q, shape, h)) {
            set_single(out, c);
            best_len = c->depth;
            found = 1;
            break;
        }
    }
    for (int i = 0; i < nc; i++)
        for (int j = i + 1; j < nc; j++) {
            nt_vec2 d;
            if (!corner(&cs[i], &cs[j], &d)) continue;
            nt_real len = nt__len(d);
            if (len >= best_len || len > max_corner || len < floor_len) continue;
            nt_vec2 q = nt__add(p, d);
            if (big ? big_free(map, q, shape, h) : is_free(map, q, shape, h)) {
                set_pair(out, d, &cs[i], &cs[j]);
                best_len = len;
                found = 1;
            }
        }
    return found;
}

/* Best push from the candidates at p: shortest single or corner that frees the
 * object. Returns 1 and fills out (cell units) on success. */
static int best_candidate(const probe *o, nt_vec2 p, const gathered *g, nt_resolution *out, nt_real *lower)
{
    const mview *map = o->map;
    const nt_shape shape = o->shape;
    const nt_vec2 h = o->h;
    const cand *cs = g->cs;
    const int nc = g->nc, overlapped = g->overlapped, all_convex = g->all_convex, present = g->present;
    nt_real lb = g->lb;
    /* Fast certificate: every overlapped tile pushes the same way and is convex, so
     * the deepest push clears them all (a convex region stays cleared further along
     * an outward normal); it is the answer when no other tile overlaps the object
     * at its new place (tested there, one tile each). A single concave tile is
     * tested at the new place as well. */
    /* With one candidate the tile may be concave: its own push is then tested too. */
    if (nc == overlapped && nc > 0 && (all_convex || nc == 1)) {
        int deepest = 0, same = 1;
        for (int i = 1; i < nc; i++) {
            if (cs[i].nx != cs[0].nx || cs[i].ny != cs[0].ny) same = 0;
            if (cs[i].depth > cs[deepest].depth) deepest = i;
        }
        if (same) {
            nt_vec2 q = nt_v2(p.x + cs[deepest].nx * cs[deepest].depth, p.y + cs[deepest].ny * cs[deepest].depth);
            int c0, d0, c1, d1, clear = 1;
            const int a0 = g->x0, b0 = g->y0, a1 = g->x1, b1 = g->y1;
            cell_range(q, h, &c0, &d0, &c1, &d1);
            /* Every tile in range was overlapped and no new cell comes into range:
             * nothing else to test. */
            int same_range = all_convex && nc == present && c0 >= a0 && d0 >= b0 && c1 <= a1 && d1 <= b1;
            nt_real tol = free_tolerance(q);
            for (int y = d0; y <= d1 && clear && !same_range; y++)
                for (int x = c0; x <= c1; x++) {
                    int t = vtile(map, x, y), known = 0;
                    if (t == NT_TILE_EMPTY) continue;
                    for (int i = 0; i < nc && all_convex; i++) known |= cs[i].cx == x && cs[i].cy == y;
                    if (known) continue;
                    nt_mtv m;
                    if (tile_test(t, q.x - (nt_real)x, q.y - (nt_real)y, shape, h, 0, &m) == NT__PUSH &&
                        m.depth > tol) {
                        clear = 0;
                        break;
                    }
                }
            if (clear) {
                set_single(out, &cs[deepest]);
                *lower = cs[deepest].depth;
                /* The push frees the object, but a push made longer by a seam is not
                 * known to be the shortest way out of the union: across the seam a
                 * neighbour's free pocket may be nearer (a tiny body buried in a FULL
                 * tile beside a slope). Past resting depth the bound is then the
                 * deepest plain (unmasked) overlap, and the caller enumerates the
                 * curves within reach when the push is longer than that. */
                if (lb < 0 && *lower > (nt_real)0.01) {
                    nt_real plain = 0;
                    for (int i = 0; i < nc; i++) {
                        nt_mtv m;
                        int x = cs[i].cx, y = cs[i].cy;
                        if (tile_test(vtile(map, x, y), p.x - (nt_real)x, p.y - (nt_real)y, shape, h, 0, &m) ==
                                NT__PUSH &&
                            m.depth > plain)
                            plain = m.depth;
                    }
                    if (plain < *lower) *lower = plain;
                }
                return 1;
            }
        }
    }
    /* No way out of the union is shorter than the way out of its deepest tile: a
     * candidate below that bound can free the object only within the tolerance of
     * is_free, leaving it slightly inside, so it is not taken. */
    if (lb < 0) lb = masked_depth(map, p, shape, h, g);
    *lower = lb;
    return shortest_freeing(o, p, cs, nc, lb, 0, out);
}

/* ---- exact enumeration ----
 * The nearest free point lies on the boundary of the union of the tiles' Minkowski
 * regions M_k: it is the foot of c on one boundary curve, or where two curves
 * cross. Every curve is a line or a circle; those farther than the best free
 * point known so far cannot hold a nearer one. */

typedef struct feat {
    int circle;          /* 0: line n.p = e (free side n.p >= e); 1: circle (q, rad) */
    int sign;            /* circles: +1 free outside, -1 free inside */
    nt_real nx, ny, e;
    nt_real qx, qy, rad;
    int cx, cy;
} feat;

/* Enough for the curves of every tile within 2 cells of a small object (5 x 5 cells). */
enum { MAX_FEATS = 256 };

typedef struct feats {
    feat f[MAX_FEATS];
    int n;
} feats;

static void add_line(feats *fs, nt_real nx, nt_real ny, nt_real e, int cx, int cy)
{
    if (fs->n >= MAX_FEATS) return;
    feat *f = &fs->f[fs->n++];
    f->circle = 0;
    f->sign = 1;
    f->nx = nx;
    f->ny = ny;
    f->e = e;
    f->qx = f->qy = f->rad = 0;
    f->cx = cx;
    f->cy = cy;
}

static void add_circle(feats *fs, nt_real qx, nt_real qy, nt_real rad, int sign, int cx, int cy)
{
    if (fs->n >= MAX_FEATS || rad <= 0) return;
    feat *f = &fs->f[fs->n++];
    f->circle = 1;
    f->sign = sign;
    f->nx = f->ny = f->e = 0;
    f->qx = qx;
    f->qy = qy;
    f->rad = rad;
    f->cx = cx;
    f->cy = cy;
}

/* The boundary curves of M = tile (+) object, for the tile in cell (X, Y). */
static void tile_features(feats *fs, int t, int X, int Y, nt_shape shape, nt_vec2 h)
{
    const nt_tile_info *ti = &nt__tiles[t];
    const nt__tile_geom *g = &nt__geom[t];
    nt_real fx = (nt_real)X, fy = (nt_real)Y;
    if (shape.type == NT_SHAPE_AABB) {
        add_line(fs, -1, 0, -(fx + ti->bounds_min.x - h.x), X, Y);
        add_line(fs, 1, 0, fx + ti->bounds_max.x + h.x, X, Y);
        add_line(fs, 0, -1, -(fy + ti->bounds_min.y - h.y), X, Y);
        add_line(fs, 0, 1, fy + ti->bounds_max.y + h.y, X, Y);
        if (ti->cls == NT_CLASS_POLYGON) {
            if (g->has_slope) {
                nt_real nx = g->slope[4], ny = g->slope[5];
                nt_real e = g->slope[2] * g->slope[3] + nx * fx + ny * fy + h.x * nt__fabs(nx) + h.y * nt__fabs(ny);
                add_line(fs, nx, ny, e, X, Y);
            }
        } else {
            /* The arc swept by the box corner facing it (convex: free outside; concave:
             * the corner nearest the solid must lie inside the hollow). */
            nt_real qx = fx + ti->arc_center.x + h.x * (nt_real)ti->signx;
            nt_real qy = fy + ti->arc_center.y + h.y * (nt_real)ti->signy;
            add_circle(fs, qx, qy, 1, ti->cls == NT_CLASS_CONVEX ? 1 : -1, X, Y);
        }
        return;
    }
    nt_real r = h.x;
    for (int i = 0; i < g->edge_count; i++) {
        const nt__edge *ed = &g->edges[i];
        add_line(fs, ed->nx, ed->ny, ed->ud * ed->inv + ed->nx * fx + ed->ny * fy + r, X, Y);
    }
    for (int i = 0; i < ti->vertex_count; i++) add_circle(fs, fx + ti->vertices[i].x, fy + ti->vertices[i].y, r, 1, X, Y);
    if (ti->cls == NT_CLASS_CONVEX) add_circle(fs, fx + ti->arc_center.x, fy + ti->arc_center.y, 1 + r, 1, X, Y);
    if (ti->cls == NT_CLASS_CONCAVE) {
        add_circle(fs, fx + ti->arc_center.x, fy + ti->arc_center.y, 1 - r, -1, X, Y);
        add_line(fs, -1, 0, -(fx - r), X, Y);
        add_line(fs, 1, 0, fx + 1 + r, X, Y);
        add_line(fs, 0, -1, -(fy - r), X, Y);
        add_line(fs, 0, 1, fy + 1 + r, X, Y);
    }
}

/* The distance from c to a curve; inline (NT__INLINE): enumerate and big_features
 * measure every curve listed, and the call cost more than this. */
static NT__INLINE nt_real feat_distance(const feat *f, nt_vec2 c)
{
    if (!f->circle) return nt__fabs(f->nx * c.x + f->ny * c.y - f->e);
    nt_real dx = c.x - f->qx, dy = c.y - f->qy;
    return nt__fabs(nt__sqrt(dx * dx + dy * dy) - f->rad);
}

/* The push normal a feature gives at a point on it. */
static nt_vec2 feat_normal(const feat *f, nt_vec2 p)
{
    if (!f->circle) return nt_v2(f->nx, f->ny);
    nt_real dx = p.x - f->qx, dy = p.y - f->qy;
    nt_real d = nt__sqrt(dx * dx + dy * dy);
    if (d <= 0) return nt_v2(0, -1);
    nt_real s = (nt_real)f->sign / d;
    return nt_v2(dx * s, dy * s);
}

static int foot(const feat *f, nt_vec2 c, nt_vec2 *p)
{
    if (!f->circle) {
        nt_real s = f->nx * c.x + f->ny * c.y - f->e;
        *p = nt_v2(c.x - s * f->nx, c.y - s * f->ny);
        return 1;
    }
    nt_real dx = c.x - f->qx, dy = c.y - f->qy;
    nt_real d = nt__sqrt(dx * dx + dy * dy);
    if (d <= 0) return 0;
    *p = nt_v2(f->qx + dx * f->rad / d, f->qy + dy * f->rad / d);
    return 1;
}

/* Up to two crossing points of two curves. */
static int cross(const feat *a, const feat *b, nt_vec2 pts[2])
{
    if (!a->circle && !b->circle) {
        nt_real det = a->nx * b->ny - a->ny * b->nx;
        if (nt__fabs(det) < (nt_real)(1e-6)) return 0;
        pts[0] = nt_v2((a->e * b->ny - b->e * a->ny) / det, (a->nx * b->e - b->nx * a->e) / det);
        return 1;
    }
    if (a->circle && !b->circle) {
        const feat *t = a;
        a = b;
        b = t;
    }
    if (!a->circle) { /* line a, circle b */
        nt_real s = a->nx * b->qx + a->ny * b->qy - a->e;
        if (nt__fabs(s) > b->rad) return 0;
        nt_real fx = b->qx - s * a->nx, fy = b->qy - s * a->ny;
        nt_real hc = nt__sqrt(nt__max(0, b->rad * b->rad - s * s));
        pts[0] = nt_v2(fx - a->ny * hc, fy + a->nx * hc);
        pts[1] = nt_v2(fx + a->ny * hc, fy - a->nx * hc);
        return 2;
    }
    nt_real dx = b->qx - a->qx, dy = b->qy - a->qy;
    nt_real d2 = dx * dx + dy * dy;
    nt_real d = nt__sqrt(d2);
    if (d <= 0 || d > a->rad + b->rad || d < nt__fabs(a->rad - b->rad)) return 0;
    nt_real k = (a->rad * a->rad - b->rad * b->rad + d2) / (2 * d);
    nt_real hh = nt__sqrt(nt__max(0, a->rad * a->rad - k * k));
    nt_real bx = a->qx + dx * k / d, by = a->qy + dy * k / d;
    pts[0] = nt_v2(bx - dy * hh / d, by + dx * hh / d);
    pts[1] = nt_v2(bx + dy * hh / d, by - dx * hh / d);
    return 2;
}

static void set_from_feats(nt_resolution *out, nt_vec2 c, nt_vec2 p, const feat *a, const feat *b)
{
    out->push = nt__sub(p, c);
    out->contact_count = b ? 2 : 1;
    const feat *fs[2] = {a, b};
    for (int i = 0; i < out->contact_count; i++) {
        nt_vec2 n = feat_normal(fs[i], p);
        out->contacts[i].normal = n;
        out->contacts[i].depth = nt__max(0, nt__dot(out->push, n));
        out->contacts[i].cell_x = fs[i]->cx;
        out->contacts[i].cell_y = fs[i]->cy;
    }
}

/* Nearest free point within `reach` of c. Returns 1 and fills out when found. */
static int enumerate(const mview *map, nt_vec2 c, nt_shape shape, nt_vec2 h, nt_real reach, nt_resolution *out)
{
    feats all;
    all.n = 0;
    int x0 = nt__floor_int(c.x - h.x - reach), x1 = nt__floor_int(c.x + h.x + reach);
    int y0 = nt__floor_int(c.y - h.y - reach), y1 = nt__floor_int(c.y + h.y + reach);
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            int t = vtile(map, x, y);
            if (t != NT_TILE_EMPTY) tile_features(&all, t, x, y, shape, h);
        }
    /* Keep the curves that come within reach. */
    int near[MAX_FEATS], nn = 0;
    for (int i = 0; i < all.n; i++)
        if (feat_distance(&all.f[i], c) < reach) near[nn++] = i;
    nt_real best = reach;
    int found = 0;
    for (int i = 0; i < nn; i++) {
        const feat *f = &all.f[near[i]];
        nt_vec2 p;
        if (!foot(f, c, &p)) continue;
        nt_real d = nt__len(nt__sub(p, c));
        if (d < best && is_free(map, p, shape, h)) {
            best = d;
            set_from_feats(out, c, p, f, NULL);
            found = 1;
        }
    }
    for (int i = 0; i < nn; i++)
        for (int j = i + 1; j < nn; j++) {
            const feat *a = &all.f[near[i]], *b = &all.f[near[j]];
            nt_vec2 pts[2];
            int k = cross(a, b, pts);
            for (int m = 0; m < k; m++) {
                nt_real d = nt__len(nt__sub(pts[m], c));
                if (d < best && is_free(map, pts[m], shape, h)) {
                    best = d;
                    set_from_feats(out, c, pts[m], a, b);
                    found = 1;
                }
            }
        }
    return found;
}

/* Last resort for deep positions: the nearest free point found along 64 directions. */
static int search_directions(const mview *map, nt_vec2 p, nt_shape shape, nt_vec2 h, nt_vec2 *d)
{
    enum { DIRS = 64, STEPS = 48 };
    const nt_real reach = (nt_real)1.5;
    nt_real best = NT_REAL_MAX;
    int found = 0;
    for (int k = 0; k < DIRS; k++) {
        nt_real a = (nt_real)k * (nt_real)(6.283185307179586 / DIRS);
        nt_cos_sin cs = nt_compute_cos_sin((double)a);
        nt_real ux = (nt_real)cs.cosine, uy = (nt_real)cs.sine;
        nt_real lo = 0, hi = -1;
        for (int s = 1; s <= STEPS; s++) {
            nt_real t = reach * (nt_real)s / STEPS;
            if (t >= best) break;
            if (is_free(map, nt_v2(p.x + ux * t, p.y + uy * t), shape, h)) {
                hi = t;
                break;
            }
            lo = t;
        }
        if (hi < 0) continue;
        if (!is_free_strict(map, nt_v2(p.x + ux * hi, p.y + uy * hi), shape, h)) lo = hi, hi = hi + reach / STEPS;
        for (int it = 0; it < 32; it++) {
            nt_real mid = (nt_real)0.5 * (lo + hi);
            if (is_free_strict(map, nt_v2(p.x + ux * mid, p.y + uy * mid), shape, h)) hi = mid;
            else lo = mid;
        }
        if (hi < best) {
            best = hi;
            *d = nt_v2(ux * hi, uy * hi);
            found = 1;
        }
    }
    return found;
}

/* Deep in solid, beyond any short way out: clamp into the map and, if still stuck,
 * go to the nearest EMPTY cell's centre. Frees the object; not the shortest way. */
static nt_vec2 escape(const mview *map, nt_vec2 p, nt_shape shape, nt_vec2 h)
{
    nt_vec2 q = nt_v2(nt__clamp(p.x, (nt_real)VX0(map) + h.x, (nt_real)VX1(map) - h.x),
                      nt__clamp(p.y, (nt_real)VY0(map) + h.y, (nt_real)VY1(map) - h.y));
    if (is_free(map, q, shape, h)) return nt__sub(q, p);
    int cx = (int)nt__clamp(nt__floor(q.x), (nt_real)VX0(map), (nt_real)(VX1(map) - 1));
    int cy = (int)nt__clamp(nt__floor(q.y), (nt_real)VY0(map), (nt_real)(VY1(map) - 1));
    nt_real best = NT_REAL_MAX;
    nt_vec2 d = nt_v2(0, 0);
    /* Rings nearer than the nearest block holding an EMPTY cell hold none: start
     * there (none within reach: nothing to find). Each ring walks its perimeter only,
     * in the order of a row-major scan of its square. Worst case: one EMPTY cell 63
     * rings away, about 16,000 cells. */
    int ring0 = nearest_block(map->map, map->map->blk_empty, cx + map->ox, cy + map->oy, 63);
    if (ring0 < 0) return d;
    for (int ring = ring0; ring < 64; ring++) {
        if ((nt_real)ring - 1 > best) break; /* no cell of this ring can be nearer */
        for (int y = cy - ring; y <= cy + ring; y++)
            for (int x = cx - ring; x <= cx + ring; x += (y == cy - ring || y == cy + ring || ring == 0) ? 1 : 2 * ring) {
                if (vtile(map, x, y) != NT_TILE_EMPTY) continue;
                nt_vec2 c = nt_v2((nt_real)x + (nt_real)0.5, (nt_real)y + (nt_real)0.5);
                nt_real dist = nt__len(nt__sub(c, p));
                if (dist < best) {
                    best = dist;
                    d = nt__sub(c, p);
                }
            }
    }
    return d;
}

/* ------------------------------------------------------------------------------
 * Large objects: half-size above half a cell, up to NT_MAX_HALF_CELLS (a box of
 * half 4 covers up to 9 x 9 cells). The same plan as above, sized for it: the
 * candidates are merged by normal (a box on a floor overlaps nine tiles that all
 * push up; only the deepest push along a normal can free the object, since a
 * shorter one leaves that tile overlapped), so the certificate and the corners stay
 * cheap; enumeration keeps only the curves within reach, once each, and none from
 * a seam face (such a face lies inside the neighbour's region, off the union's
 * boundary); freeness tests stop at the first overlapping tile. Costs, in
 * instructions: a 4 x 0.5 box on a floor ~3.4 k (the certificate), a 4 x 4 box
 * in a floor-wall corner ~27 k (enumeration), an r 4 circle 1.5 cells into that
 * corner ~330 k, 9 cells deep in round tiles ~60 M. Small objects never come
 * here: their path above is unchanged, bit for bit.
 * ------------------------------------------------------------------------------ */

enum { BIG_SIDE = 12, BIG_FEATS = 128, BIG_POINTS = 256 };

/* What the overlapped tiles say at p. */
typedef struct big_gather {
    cand cs[BIG_CANDS];  /* one per distinct normal: the deepest push along it */
    int nc, dropped;     /* dropped: distinct normals beyond BIG_CANDS */
    int overlapped, pushes, all_convex;
    nt_real lb;          /* deepest unmasked single-tile depth, -1 when a masked tile overlaps */
    int r4[4];           /* the cell range */
    uint8_t hit[BIG_SIDE * BIG_SIDE]; /* overlapped, relative to r4 (when it fits) */
    int fits;
} big_gather;

static void big_collect(const probe *o, nt_vec2 p, big_gather *g)
{
    cell_range(p, o->h, &g->r4[0], &g->r4[1], &g->r4[2], &g->r4[3]);
    const int x0 = g->r4[0], y0 = g->r4[1], x1 = g->r4[2], y1 = g->r4[3];
    g->nc = g->dropped = g->overlapped = g->pushes = 0;
    g->all_convex = 1;
    g->lb = 0;
    g->fits = x1 - x0 < BIG_SIDE && y1 - y0 < BIG_SIDE;
    if (g->fits) memset(g->hit, 0, sizeof g->hit);
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            nt__cell cell = vcell(o->map, x, y);
            int t = cell.tile;
            if (t == NT_TILE_EMPTY) continue;
            nt_mtv m;
            int r = tile_test(t, p.x - (nt_real)x, p.y - (nt_real)y, o->shape, o->h, cell.seams, &m);
            if (r == NT__SEPARATE) continue;
            g->overlapped++;
            if (g->fits) g->hit[(y - y0) * BIG_SIDE + (x - x0)] = 1;
            if (cell.seams) g->lb = -1;
            else if (r == NT__PUSH && g->lb >= 0 && m.depth > g->lb) g->lb = m.depth;
            if (nt__tiles[t].cls == NT_CLASS_CONCAVE) g->all_convex = 0;
            if (r != NT__PUSH) continue;
            g->pushes++;
            int i = 0;
            while (i < g->nc && (g->cs[i].nx != m.normal.x || g->cs[i].ny != m.normal.y)) i++;
            if (i == g->nc) {
                if (g->nc == BIG_CANDS) {
                    g->dropped++;
                    continue;
                }
                g->nc++;
                g->cs[i].depth = -1;
            }
            if (m.depth > g->cs[i].depth) {
                cand *c = &g->cs[i];
                c->nx = m.normal.x;
                c->ny = m.normal.y;
                c->depth = m.depth;
                c->cx = x;
                c->cy = y;
            }
        }
}

/* Certificate: every overlapped tile is convex (or it is the only one) and pushes
 * along the same normal: the deepest push clears them all; it is the answer when
 * no other tile overlaps at the new place. */
static int big_certificate(const probe *o, nt_vec2 p, const big_gather *g, nt_resolution *out)
{
    if (g->nc != 1 || g->dropped || g->pushes != g->overlapped || !(g->all_convex || g->overlapped == 1)) return 0;
    const cand *c = &g->cs[0];
    nt_vec2 q = nt_v2(p.x + c->nx * c->depth, p.y + c->ny * c->depth);
    int c0, d0, c1, d1;
    cell_range(q, o->h, &c0, &d0, &c1, &d1);
    nt_real tol = free_tolerance(q);
    const int x0 = g->r4[0], y0 = g->r4[1], x1 = g->r4[2], y1 = g->r4[3];
    for (int y = d0; y <= d1; y++)
        for (int x = c0; x <= c1; x++) {
            /* An overlapped convex tile was pushed along its own normal by at least its depth. */
            if (g->all_convex && g->fits && x >= x0 && x <= x1 && y >= y0 && y <= y1 &&
                g->hit[(y - y0) * BIG_SIDE + (x - x0)])
                continue;
            int t = vtile(o->map, x, y);
            if (t == NT_TILE_EMPTY) continue;
            nt_mtv m;
            if (tile_test(t, q.x - (nt_real)x, q.y - (nt_real)y, o->shape, o->h, 0, &m) == NT__PUSH && m.depth > tol)
                return 0;
        }
    set_single(out, c);
    return 1;
}

/* The features of the tiles within reach, each once: BIG_FEATS on the stack, more
 * (deep in a mass of tiles) from the allocator. */
typedef struct big_feats {
    feat *f, *heap;
    int n, cap;
    feat own[BIG_FEATS];
} big_feats;

/* Room for one more feature; 0 when the allocator fails. */
static int big_room(big_feats *all)
{
    if (all->n < all->cap) return 1;
    feat *g = (feat *)nt__alloc((size_t)all->cap * 2 * sizeof *g);
    if (!g) return 0;
    memcpy(g, all->f, (size_t)all->n * sizeof *g);
    nt__free(all->heap);
    all->f = all->heap = g;
    all->cap *= 2;
    return 1;
}

/* The cell side a feature's line lies on, or -1. */
static int line_side(const feat *f, int X, int Y, nt_vec2 off)
{
    nt_real fx = (nt_real)X, fy = (nt_real)Y;
    if (f->circle) return -1;
    if (f->nx == -1 && f->e == -(fx - off.x)) return NT_SIDE_LEFT;
    if (f->nx == 1 && f->e == fx + 1 + off.x) return NT_SIDE_RIGHT;
    if (f->ny == -1 && f->e == -(fy - off.y)) return NT_SIDE_TOP;
    if (f->ny == 1 && f->e == fy + 1 + off.y) return NT_SIDE_BOTTOM;
    return -1;
}

static int same_feat(const feat *a, const feat *b)
{
    return a->circle == b->circle && a->sign == b->sign && a->nx == b->nx && a->ny == b->ny && a->e == b->e &&
           a->qx == b->qx && a->qy == b->qy && a->rad == b->rad;
}

/* Returns 0 when the allocator fails (the caller then looks less far). */
/* A circle's vertex curve is needed only where the union has a corner. A vertex
 * whose two faces on this tile are both seams is no corner of the union: the
 * tiles across them fill it in, and if the union still has a corner there, the
 * tile owning the face along it lists the same vertex (a seam face lies inside the
 * union, so no face along the union's boundary is one). */
static int vertex_hidden(int t, int vi, unsigned seams)
{
    const nt__tile_geom *g = &nt__geom[t];
    nt_vec2 v = nt__tiles[t].vertices[vi];
    int adjacent = 0, hidden = 0;
    for (int i = 0; i < g->edge_count; i++) {
        const nt__edge *e = &g->edges[i];
        int at_start = e->ax == v.x && e->ay == v.y;
        int at_end = e->ax + e->tx * e->len == v.x && e->ay + e->ty * e->len == v.y;
        if (!at_start && !at_end) continue;
        adjacent++;
        hidden += e->side >= 0 && ((seams >> e->side) & 1u);
    }
    return adjacent == 2 && hidden == 2;
}

/* The cells (x-1..x+1, y-1..y+1) of the map all lie in blocks without a cell that is
 * not FULL, and (x, y) is in the map. */
static int solid_around(const nt_map *map, int x, int y)
{
    if (!nt__map_in(map, x, y)) return 0;
    int xa = x > 0 ? x - 1 : 0, xb = x + 1 < map->w ? x + 1 : x;
    int ya = y > 0 ? y - 1 : 0, yb = y + 1 < map->h ? y + 1 : y;
    const uint8_t *b = map->blk_open;
    size_t bw = (size_t)map->bw;
    size_t r0 = (size_t)(ya / NT__BLOCK) * bw, r1 = (size_t)(yb / NT__BLOCK) * bw;
    size_t c0 = (size_t)(xa / NT__BLOCK), c1 = (size_t)(xb / NT__BLOCK);
    return !b[r0 + c0] && !b[r0 + c1] && !b[r1 + c0] && !b[r1 + c1];
}

static int big_features(const probe *o, nt_vec2 c, nt_real reach, big_feats *all)
{
    const nt_shape shape = o->shape;
    const nt_vec2 h = o->h;
    all->n = 0;
    int x0 = nt__floor_int(c.x - h.x - reach), x1 = nt__floor_int(c.x + h.x + reach);
    int y0 = nt__floor_int(c.y - h.y - reach), y1 = nt__floor_int(c.y + h.y + reach);
    /* Box features offset the cell's sides by the half-size; a circle's lines by r. */
    nt_vec2 off = shape.type == NT_SHAPE_CIRCLE ? nt_v2(h.x, h.x) : h;
    /* Cells more than one outside the map, and cells whose 3 x 3 neighbourhood lies in
     * blocks of FULL cells only, are FULL among FULL: every side a seam, every vertex
     * inside solid, no curve. */
    const mview *map = o->map;
    if (x0 < VX0(map) - 1) x0 = VX0(map) - 1;
    if (y0 < VY0(map) - 1) y0 = VY0(map) - 1;
    if (x1 > VX1(map)) x1 = VX1(map);
    if (y1 > VY1(map)) y1 = VY1(map);
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            if (solid_around(map->map, x + map->ox, y + map->oy)) continue;
            nt__cell cell = vcell(map, x, y);
            if (cell.tile == NT_TILE_EMPTY) continue;
            feats one; /* a tile has at most 9 curves */
            one.n = 0;
            tile_features(&one, cell.tile, x, y, shape, h);
            /* tile_features lists a circle's edges, then its vertices. */
            int v0 = shape.type == NT_SHAPE_CIRCLE ? nt__geom[cell.tile].edge_count : one.n;
            int v1 = shape.type == NT_SHAPE_CIRCLE ? v0 + nt__tiles[cell.tile].vertex_count : one.n;
            for (int i = 0; i < one.n; i++) {
                const feat *f = &one.f[i];
                if (feat_distance(f, c) >= reach) continue;
                int side = line_side(f, x, y, off);
                if (side >= 0 && (cell.seams >> side) & 1u) continue;
                if (i >= v0 && i < v1 && cell.seams && vertex_hidden(cell.tile, i - v0, cell.seams)) continue;
                int k = 0;
                while (k < all->n && !same_feat(&all->f[k], f)) k++;
                if (k < all->n) continue;
                if (!big_room(all)) return 0;
                all->f[all->n++] = *f;
            }
        }
    return 1;
}

/* Crossing points waiting for their freeness test, nearest first. */
typedef struct big_point {
    nt_real d;
    nt_vec2 p;
    int a, b; /* feature indices; b = -1 for a foot */
    int seq;  /* order of listing, for ties */
} big_point;

typedef struct big_search {
    const probe *o;
    nt_vec2 c;             /* the object's centre */
    const big_feats *all;  /* the curves the points lie on */
    nt_resolution *out;    /* the nearest free point, when found */
    big_point pt[BIG_POINTS];
    int n;
    nt_real best; /* distance of the nearest free point found */
    int found, seq;
} big_search;

/* Heap order of the waiting points: nearer first, then the one listed first. */
static int point_before(const big_point *a, const big_point *b)
{
    return a->d < b->d || (a->d == b->d && a->seq < b->seq);
}

static void sift_down(big_point *pt, int n, int i)
{
    for (;;) {
        int l = 2 * i + 1, m = i;
        if (l < n && point_before(&pt[l], &pt[m])) m = l;
        if (l + 1 < n && point_before(&pt[l + 1], &pt[m])) m = l + 1;
        if (m == i) return;
        big_point t = pt[i];
        pt[i] = pt[m];
        pt[m] = t;
        i = m;
    }
}

/* Test the waiting points nearest first (a heap: deep inside a mass of tiles
 * hundreds wait and many are not free); the first free one beats the rest. */
static void big_flush(big_search *s)
{
    int n = s->n;
    for (int i = n / 2 - 1; i >= 0; i--) sift_down(s->pt, n, i);
    while (n > 0 && s->pt[0].d < s->best) {
        const big_point *q = &s->pt[0];
        if (probe_free(s->o, q->p)) {
            s->best = q->d;
            s->found = 1;
            set_from_feats(s->out, s->c, q->p, &s->all->f[q->a], q->b >= 0 ? &s->all->f[q->b] : NULL);
            break;
        }
        s->pt[0] = s->pt[--n];
        sift_down(s->pt, n, 0);
    }
    s->n = 0;
}

static void big_point_add(big_search *s, nt_vec2 p, int a, int b)
{
    nt_real d = nt__len(nt__sub(p, s->c));
    if (!(d < s->best)) return;
    if (s->n == BIG_POINTS) big_flush(s);
    if (!(d < s->best)) return;
    big_point *q = &s->pt[s->n++];
    q->seq = s->seq++;
    q->d = d;
    q->p = p;
    q->a = a;
    q->b = b;
}

/* Nearest free point within reach of c (cf. enumerate): the feet first, which bound
 * the crossings worth looking at. */
static int big_enumerate(const probe *o, nt_vec2 c, nt_real reach, nt_resolution *out)
{
    big_feats all;
    all.f = all.own;
    all.heap = NULL;
    all.cap = BIG_FEATS;
    /* Out of memory: look less far (exact within the smaller reach). */
    while (!big_features(o, c, reach, &all)) reach *= (nt_real)0.5;
    big_search s;
    s.o = o;
    s.c = c;
    s.all = &all;
    s.out = out;
    s.n = 0;
    s.best = reach;
    s.found = s.seq = 0;
    for (int i = 0; i < all.n; i++) {
        nt_vec2 p;
        if (foot(&all.f[i], c, &p)) big_point_add(&s, p, i, -1);
    }
    big_flush(&s);
    for (int i = 0; i < all.n; i++) {
        if (feat_distance(&all.f[i], c) >= s.best) continue;
        for (int j = i + 1; j < all.n; j++) {
            if (feat_distance(&all.f[j], c) >= s.best) continue;
            nt_vec2 pts[2];
            int k = cross(&all.f[i], &all.f[j], pts);
            for (int m = 0; m < k; m++) big_point_add(&s, pts[m], i, j);
        }
    }
    big_flush(&s);
    nt__free(all.heap);
    return s.found;
}

/* One axis of the map: the centre clamped so that the object lies inside (the
 * middle when the map is narrower than the object). */
static nt_real clamp_in(nt_real v, nt_real half, int s0, int s1)
{
    nt_real lo = (nt_real)s0 + half, hi = (nt_real)s1 - half;
    return lo > hi ? (nt_real)0.5 * ((nt_real)s0 + (nt_real)s1) : nt__clamp(v, lo, hi);
}

/* Last resort (cf. escape), sized for the object: centres that put it in the middle
 * or at a quarter of a cell, or flush with a cell's side. Returns 0 when none of
 * them within 32 cells is free (no room that way for the object). */
static int big_escape(const probe *o, nt_vec2 p, nt_vec2 *d)
{
    const mview *map = o->map;
    const nt_vec2 h = o->h;
    nt_vec2 q = nt_v2(clamp_in(p.x, h.x, VX0(map), VX1(map)), clamp_in(p.y, h.y, VY0(map), VY1(map)));
    *d = nt__sub(q, p);
    if (probe_free(o, q)) return 1;
    int cx = (int)nt__clamp(nt__floor(q.x), (nt_real)VX0(map), (nt_real)(VX1(map) - 1));
    int cy = (int)nt__clamp(nt__floor(q.y), (nt_real)VY0(map), (nt_real)(VY1(map) - 1));
    const nt_real ox[6] = {(nt_real)0.5, h.x - nt__floor(h.x), 1 - (h.x - nt__floor(h.x)), 0, (nt_real)0.25, (nt_real)0.75};
    const nt_real oy[6] = {(nt_real)0.5, h.y - nt__floor(h.y), 1 - (h.y - nt__floor(h.y)), 0, (nt_real)0.25, (nt_real)0.75};
    nt_real best = NT_REAL_MAX;
    /* A centre in ring r covers cells within ceil(h) + 1 of its own: while that stays
     * short of the nearest block with a cell that is not FULL, the object overlaps
     * FULL cells only, by at least its half-size, and is not free. */
    int hc = (int)nt__floor(nt__max(h.x, h.y)) + 2;
    int nb = nearest_block(map->map, map->map->blk_open, cx + map->ox, cy + map->oy, 31 + hc);
    if (nb < 0) return 0;
    int ring0 = nb - hc > 0 ? nb - hc : 0;
    for (int ring = ring0; ring < 32; ring++) {
        if ((nt_real)ring - 1 > best) break; /* no centre of this ring can be nearer */
        for (int y = cy - ring; y <= cy + ring; y++)
            for (int x = cx - ring; x <= cx + ring; x += (y == cy - ring || y == cy + ring || ring == 0) ? 1 : 2 * ring) {
                for (int i = 0; i < 36; i++) {
                    nt_vec2 c = nt_v2((nt_real)x + ox[i % 6], (nt_real)y + oy[i / 6]);
                    nt_real dist = nt__len(nt__sub(c, p));
                    /* A centre in a FULL cell overlaps it by more than half a cell. */
                    if (dist < best && vtile(map, nt__floor_int(c.x), nt__floor_int(c.y)) != NT_TILE_FULL &&
                        probe_free(o, c)) {
                        best = dist;
                        *d = nt__sub(c, p);
                    }
                }
            }
    }
    return best < NT_REAL_MAX;
}

/* A way out d found by a search rather than from the tiles' surfaces: one contact
 * along it, at the object's own cell. */
static void set_escape(nt_resolution *res, nt_vec2 p, nt_vec2 d)
{
    nt_real l = nt__len(d);
    res->push = d;
    res->contact_count = 1;
    res->contacts[0].normal = l > 0 ? nt__scale(d, 1 / l) : nt_v2(0, -1);
    res->contacts[0].depth = l;
    res->contacts[0].cell_x = nt__floor_int(p.x);
    res->contacts[0].cell_y = nt__floor_int(p.y);
}

/* nt_map_resolve for a large object, in cell units (p, h); res is zeroed. */
NT__NOINLINE static bool resolve_big(const mview *map, nt_vec2 p, nt_shape shape, nt_vec2 h, nt_resolution *res)
{
    const probe obj = {map, shape, h}, *o = &obj;
    const nt_real far_x = (nt_real)1.5 + h.x, far_y = (nt_real)1.5 + h.y;
    nt_vec2 d;
    if (p.x < (nt_real)VX0(map) - far_x || p.y < (nt_real)VY0(map) - far_y || p.x > (nt_real)VX1(map) + far_x ||
        p.y > (nt_real)VY1(map) + far_y) {
        /* Far inside the border: come back into the map first. */
        if (!big_escape(o, p, &d))
            d = nt__sub(nt_v2(clamp_in(p.x, h.x, VX0(map), VX1(map)), clamp_in(p.y, h.y, VY0(map), VY1(map))), p);
    } else {
        big_gather g;
        big_collect(o, p, &g);
        if (g.overlapped == 0) return false;
        if (big_certificate(o, p, &g, res)) return true;
        nt_real lb = g.lb >= 0 ? g.lb : depth_at(map, p, shape, h);
        int found = shortest_freeing(o, p, g.cs, g.nc, lb, 1, res);
        /* Optimal when no longer than the deepest single-tile overlap; otherwise the
         * curves within the candidate's length are enumerated. Without a candidate,
         * the reach starts two cells past the object's size and doubles until the
         * whole map is in it: deep inside a mass of tiles, the answer is still the
         * shortest way out, at a cost that grows with the depth. */
        nt_real len = found ? nt__len(res->push) : 2 * nt__max(h.x, h.y) + 2;
        /* Bounded: 16 cells past the object's size at most (it was the whole map, whose
         * area each doubling walked: seconds a step for large bodies sunk in a porous
         * mass). Deeper than that, big_escape's nearest free centre is the answer. */
        nt_real all = nt__min((nt_real)map->map->w + (nt_real)map->map->h + 4 * nt__max(h.x, h.y) + 4,
                              2 * nt__max(h.x, h.y) + 16);
        /* Every curve comes from a tile side or vertex that is not a seam: within the
         * cells of FULL blocks around p there is none, so the reaches that stay
         * inside them are skipped (they cost their area in cells each, to the whole
         * map, for an object in a solid mass). (Blocks are the map's: map coordinates.) */
        int hc = (int)nt__floor(nt__max(h.x, h.y)) + 3;
        int fx = (int)nt__clamp(nt__floor(p.x) + (nt_real)map->ox, -8, (nt_real)map->map->w + 8);
        int fy = (int)nt__clamp(nt__floor(p.y) + (nt_real)map->oy, -8, (nt_real)map->map->h + 8);
        int near_open = nearest_block(map->map, map->map->blk_open, fx, fy, (int)all + 2 * hc);
        if (!found || len > lb * (nt_real)1.000001 + (nt_real)(1e-6))
            for (;;) {
                nt_resolution e;
                memset(&e, 0, sizeof e);
                int none = near_open < 0 || (nt_real)near_open > len + (nt_real)hc;
                if (!none && big_enumerate(o, p, len, &e)) {
                    *res = e;
                    found = 1;
                }
                if (found || len > all) break;
                len *= 2;
            }
        if (found) return true;
        /* No room for the object within the map: the nearest centre found, or none. */
        if (!big_escape(o, p, &d)) d = nt_v2(0, 0);
    }
    set_escape(res, p, d);
    return true;
}

/* A resolution in the view's cell units back to world units and the map's cells. */
static void to_world(nt_resolution *res, const mview *v, nt_real cell)
{
    res->push = nt__scale(res->push, cell);
    for (int i = 0; i < res->contact_count; i++) {
        res->contacts[i].depth *= cell;
        res->contacts[i].cell_x += v->ox;
        res->contacts[i].cell_y += v->oy;
    }
}

nt_status nt_map_check_shape(const nt_map *map, nt_shape shape)
{
    if (!map) return NT_ERR_INVALID_ARGUMENT;
    if (shape.type != NT_SHAPE_AABB && shape.type != NT_SHAPE_CIRCLE) return NT_ERR_INVALID_ARGUMENT;
    if (!nt__finite(shape.half.x) || !nt__finite(shape.half.y)) return NT_ERR_NON_FINITE;
    if (shape.half.x < 0 || shape.half.y < 0) return NT_ERR_INVALID_ARGUMENT;
    nt_real cap = map->cell * (nt_real)NT_MAX_HALF_CELLS;
    if (shape.half.x > cap || shape.half.y > cap) return NT_ERR_SHAPE_TOO_LARGE;
    return NT_OK;
}

bool nt_map_resolve(const nt_map *map, nt_vec2 pos, nt_shape shape, nt_resolution *out)
{
    nt_resolution scratch;
    nt_resolution *res = out ? out : &scratch;
    /* Refused before any loop, whatever the assert hook answers: a half-size of 1e30
     * let through by a hook that carries on walked cells for a very long time. */
    nt_status st = nt_map_check_shape(map, shape);
    if (st != NT_OK) {
        memset(res, 0, sizeof *res);
        res->status = st;
        return false;
    }
    return nt__map_resolve(map, pos, &shape, res);
}

bool nt__map_resolve(const nt_map *map, nt_vec2 pos, const nt_shape *shape_p, nt_resolution *out)
{
    const nt_shape shape = *shape_p;
    memset(out, 0, sizeof *out);
    nt_real ic = map->inv_cell, cell = map->cell;
    nt_vec2 p;
    const mview view = local_view(map, pos, &p), *vm = &view;
    nt_vec2 h = nt_v2(shape.half.x * ic, shape.half.y * ic);
    /* (A position that is not finite gives a p that is not: its product with ic > 0 is
     * not finite, and neither is its difference from the clamped corner.) */
    if (!nt__finite(p.x) || !nt__finite(p.y)) return false;
    if (h.x > (nt_real)0.5 || h.y > (nt_real)0.5) {
        /* (In a copy: *out stays zero when it fails.) */
        nt_resolution res;
        memset(&res, 0, sizeof res);
        if (!resolve_big(vm, p, shape, h, &res)) return false;
        to_world(&res, vm, cell);
        *out = res;
        return true;
    }

    /* p more than 2 cells outside the view's map, decided on the position in cells:
     * p is its exact difference from the view's origin (to within its rounding up to
     * 1 in a cell just before 0, where neither side is near), and a view far enough
     * for a conversion to round is on the far side either way. (gx < -2 is the view's
     * corner, gx's floor (clamped at -1e9), below -2; far_w is (nt_real)w + 2.) */
    nt_real gx = pos.x * ic, gy = pos.y * ic;
    if (view.ox < -2 || view.oy < -2 || gx > map->far_w || gy > map->far_h) {
        /* Far inside the border: come back into the map first. */
        set_escape(out, p, escape(vm, p, shape, h));
        to_world(out, vm, cell);
        return true;
    }
    /* The answer is built in *out (zero so far). */
    const probe obj = {vm, shape, h};
    gathered g;
    if (gather(&obj, p, 1u, &g) == 0) return false;

    nt_real lower = 0;
    int found = best_candidate(&obj, p, &g, out, &lower);
    /* A freeing push no longer than the deepest single-tile overlap is optimal: no
     * way out of the union can be shorter than the way out of one of its tiles. */
    nt_real len = found ? nt__len(out->push) : (nt_real)0.8;
    if (!found || len > lower * (nt_real)1.000001 + (nt_real)(1e-6)) {
        nt_resolution e;
        memset(&e, 0, sizeof e);
        if (enumerate(vm, p, shape, h, len, &e)) {
            *out = e;
            found = 1;
        }
    }
    if (!found) {
        nt_vec2 e = escape(vm, p, shape, h), d = e;
        /* The sampled search probes centres up to 1.6 cells away, whose shapes cover
         * cells within 4 of p's: when all of those are FULL and the shape is thicker
         * than the free tolerance, it cannot find a way out (skipped: its 3,000 probes
         * were most of a step in a solid mass). (Blocks are the map's: map coordinates.) */
        int fx = (int)nt__clamp(nt__floor(p.x) + (nt_real)vm->ox, -8, (nt_real)map->w + 8);
        int fy = (int)nt__clamp(nt__floor(p.y) + (nt_real)vm->oy, -8, (nt_real)map->h + 8);
        int near_open = nearest_block(map, map->blk_open, fx, fy, 4);
        int hopeless = (near_open < 0 || near_open > 4) &&
                       nt__min(h.x, h.y) > (nt_real)2 * free_tolerance(nt_v2(nt__fabs(p.x) + 2, nt__fabs(p.y) + 2));
        if (hopeless || !search_directions(vm, p, shape, h, &d) || nt__len(e) < nt__len(d)) d = e;
        nt_real l = nt__len(d);
        /* Deeper than the exact search reached: the sampled way out bounds the
         * shortest, which the exact search then finds within that reach. */
        nt_resolution x;
        memset(&x, 0, sizeof x);
        if (l > (nt_real)0.8 && l < (nt_real)2 && enumerate(vm, p, shape, h, l * (nt_real)1.0001 + (nt_real)(1e-6), &x)) {
            *out = x;
        } else {
            set_escape(out, p, d);
        }
    }
    to_world(out, vm, cell);
    return true;
}

/* nt_map_overlap_depth(map, pos, shape) > limit (limit >= 0), without the exact test
 * of a tile a box overlaps too little to matter. The depth is the largest single-tile
 * depth, so the answer is whether some tile's depth times the cell exceeds limit
 * (rounding is monotonic). A box's depth in a tile is at most its overlap with the
 * tile's bounds along either axis: the routines list those pushes as candidates and
 * take the shortest (POLYGON tiles with these very sums; the round ones in a mirrored
 * frame, equal to within a few units in the last place of 1, hence the margin). */
/* The glide test (core_internal.h). Only flat (polygon) tiles: the normal of a curve turns as
 * the object moves along it. Pushing along n by the deepest depth frees the object from
 * every one of those convex tiles, so no way out of their union is needed: the object
 * stays where it is, within the skin, which is what the full resolution followed by
 * the world's skin rule gives up to the width of [lo, hi]. Anything else (a curve, a
 * tile that pushes another way or deeper, a masked overlap, nothing overlapped) gives
 * false and the caller resolves. */
bool nt__map_glides(const nt_map *map, nt_vec2 pos, const nt_shape *shape_p, nt_vec2 n, nt_real lo, nt_real hi,
                    nt_tile_contact *out)
{
    const nt_shape shape = *shape_p;
    nt_real ic = map->inv_cell;
    nt_vec2 p;
    const mview view = local_view(map, pos, &p), *vm = &view;
    nt_vec2 h = nt_v2(shape.half.x * ic, shape.half.y * ic);
    if (!(h.x <= (nt_real)0.5 && h.y <= (nt_real)0.5)) return false;
    int x0, y0, x1, y1;
    /* p lies in [0, 1]^2, at the view's origin, unless the position is beyond the
     * range of cell indices; only there can it be infinite or NaN. */
    if (p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 1 && h.x >= 0 && h.y >= 0) {
        cell_range_local(p, h, &x0, &y0, &x1, &y1);
    } else {
        if (!nt__finite(p.x) || !nt__finite(p.y)) return false;
        cell_range(p, h, &x0, &y0, &x1, &y1);
    }
    lo *= ic;
    hi *= ic;
    const int ox = vm->ox, oy = vm->oy;
    int inside = x0 + ox >= 0 && y0 + oy >= 0 && x1 + ox < map->w && y1 + oy < map->h;
    const nt__cell *cells = map->cells;
    const size_t stride = (size_t)map->w;
    nt_real deepest = -1;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            nt__cell cell = inside ? cells[(size_t)(y + oy) * stride + (size_t)(x + ox)] : vcell(vm, x, y);
            int t = cell.tile;
            if (t == NT_TILE_EMPTY) continue;
            nt_mtv m;
            int r = tile_test(t, p.x - (nt_real)x, p.y - (nt_real)y, shape, h, cell.seams, &m);
            if (r == NT__SEPARATE) continue;
            if (r != NT__PUSH || nt__tiles[t].cls != NT_CLASS_POLYGON || !(nt__dot(m.normal, n) > (nt_real)0.999) ||
                !(m.depth >= lo && m.depth <= hi))
                return false;
            if (m.depth > deepest) {
                deepest = m.depth;
                out->normal = m.normal;
                out->cell_x = x + ox;
                out->cell_y = y + oy;
            }
        }
    if (!(deepest >= 0)) return false;
    out->depth = deepest * map->cell;
    return true;
}

int nt__map_depth_exceeds(const nt_map *map, nt_vec2 pos, const nt_shape *shape_p, nt_real limit)
{
    const nt_shape shape = *shape_p;
    nt_real ic = map->inv_cell;
    if (!nt__finite(pos.x) || !nt__finite(pos.y)) return 0;
    nt_vec2 p;
    const mview view = local_view(map, pos, &p);
    nt_vec2 h = nt_v2(shape.half.x * ic, shape.half.y * ic);
    int x0, y0, x1, y1;
    cell_range(p, h, &x0, &y0, &x1, &y1);
    nt_real round_limit = limit * ic - (nt_real)(1e-5);
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            int t = vtile(&view, x, y);
            if (t == NT_TILE_EMPTY) continue;
            nt_vec2 c = nt_v2(p.x - (nt_real)x, p.y - (nt_real)y);
            if (shape.type == NT_SHAPE_AABB) {
                const nt_tile_info *ti = &nt__tiles[t];
                nt_real b = nt__min(nt__min(c.x + h.x - ti->bounds_min.x, ti->bounds_max.x - (c.x - h.x)),
                                    nt__min(c.y + h.y - ti->bounds_min.y, ti->bounds_max.y - (c.y - h.y)));
                if (ti->cls == NT_CLASS_POLYGON ? b * map->cell <= limit : b <= round_limit) continue;
            }
            nt_mtv m;
            if (tile_test(t, c.x, c.y, shape, h, 0, &m) == NT__PUSH && m.depth * map->cell > limit) return 1;
        }
    return 0;
}

nt_real nt_map_overlap_depth(const nt_map *map, nt_vec2 pos, nt_shape shape)
{
    if (nt_map_check_shape(map, shape) != NT_OK) return 0;
    nt_real ic = map->inv_cell;
    if (!nt__finite(pos.x) || !nt__finite(pos.y)) return 0;
    nt_vec2 p;
    const mview view = local_view(map, pos, &p);
    return depth_at(&view, p, shape, nt_v2(shape.half.x * ic, shape.half.y * ic)) * map->cell;
}
