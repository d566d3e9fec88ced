/* One world step, in this order:
 *
 *  1. collide   find the body pairs that overlap now (broad phase in grid.c), match
 *               them with last step's contacts (warm start, begin/end events, wake
 *               on touch). Every buffer the step needs is grown here, before any
 *               state changes, so a failed step leaves the world as it was.
 *  2. correct   push overlapping bodies apart, split by inverse mass, and free the
 *               pushed bodies from the tiles again.
 *  3. velocity  gravity and drag; resting tile contacts remembered from the last
 *               step (friction model applied once per surface); body contacts by
 *               sequential impulses (restitution, friction, warm start) with the
 *               tile contacts of those bodies as one-sided constraints.
 *  4. move      semi-implicit Euler with the tiles: per body, in sub-steps when it
 *               moves further than its smaller half-size; each sub-step is freed
 *               by nt_map_resolve and answered by the friction model.
 *  5. sleep     groups of touching bodies that rested long enough fall asleep
 *               (sleep.c).
 *
 * Contacts are left overlapping by a tiny skin (2.5e-4 cell plus rounding of the
 * position) so that a resting contact is found again next step without a gap
 * appearing and closing. */
#include <string.h>
#include <time.h>
#include "simulation.h"
#include "pair_internal.h"

#define skin_at nt__skin

static inline nt_vec2 perp(nt_vec2 n) { return nt_v2(-n.y, n.x); }

static inline int32_t key_a(uint64_t k) { return (int32_t)(k >> 32); }
static inline int32_t key_b(uint64_t k) { return (int32_t)(k & 0xffffffffu); }

static inline nt_body_id id_of(const nt_world *w, int32_t i, uint32_t gen)
{
    nt_body_id id;
    id.index1 = i + 1;
    id.world0 = w->tag;
    id.generation = gen;
    return id;
}

/* Inverse mass as the solver sees it: only awake dynamic bodies move. */
static inline nt_real solver_w(const nt__body *b)
{
    return (b->type == NT_BODY_DYNAMIC && b->awake_slot >= 0) ? b->inv_mass : 0;
}

/* Whether both bodies of a contact still exist: between steps a body may have been
 * destroyed. Within a step, after the merge (collide), every contact is this step's
 * and needs no such test. */
static inline int contact_live(const nt_world *w, const nt__contact *c) { return nt__contact_is_live(w, c); }

/* ---------------------------------------------------------------- 1. collide */

/* Milliseconds of a clock, for the profile: C's timespec_get, the monotonic clock
 * where the C library has it (C23), else the calendar clock. */
static double clock_ms(void)
{
    struct timespec ts;
#ifdef TIME_MONOTONIC
    if (!timespec_get(&ts, TIME_MONOTONIC)) return 0;
#else
    if (!timespec_get(&ts, TIME_UTC)) return 0;
#endif
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* A phase's time; 0 if the calendar clock was set back during it. */
static inline double phase_ms(double t0, double t1) { return t1 > t0 ? t1 - t0 : 0; }

/* Stable bottom-up merge sort by key; returns the array holding the result. */
static nt__contact *sort_contacts(nt__contact *a, nt__contact *tmp, int n)
{
    int sorted = 1;
    for (int i = 1; i < n && sorted; i++)
        if (a[i - 1].key > a[i].key) sorted = 0;
    if (sorted) return a;
    nt__contact *src = a, *dst = tmp;
    for (int width = 1; width < n; width *= 2) {
        for (int lo = 0; lo < n; lo += 2 * width) {
            int mid = lo + width < n ? lo + width : n, hi = lo + 2 * width < n ? lo + 2 * width : n;
            int i = lo, j = mid, k = lo;
            while (i < mid && j < hi) dst[k++] = src[j].key < src[i].key ? src[j++] : src[i++];
            while (i < mid) dst[k++] = src[i++];
            while (j < hi) dst[k++] = src[j++];
        }
        nt__contact *t = src;
        src = dst;
        dst = t;
    }
    return src;
}

/* The n records a (distinct; top: all of them or-ed) in increasing order into b, in
 * one counting pass: by their top bits in use into at most 2048 buckets (about one
 * per record), then an insertion sort, which moves records within their buckets
 * only. Returns 0, b unwritten, when the buckets are so uneven that the sort could
 * cost more than a few moves a record (the radix passes then). count: 2049 words. */
static int by_buckets(const uint64_t *a, uint64_t *b, int n, uint64_t top, uint32_t *count)
{
    int nbits = 1, tbits = 0;
    while (nbits < 11 && (uint32_t)n >> nbits) nbits++;
    while (tbits < 64 && top >> tbits) tbits++;
    const int shift = tbits > nbits ? tbits - nbits : 0;
    const uint32_t buckets = 1u << nbits;
    memset(count, 0, (buckets + 1) * sizeof *count);
    for (int i = 0; i < n; i++) count[(a[i] >> shift) + 1]++;
    uint64_t cost = 0;
    for (uint32_t d = 0; d < buckets; d++) {
        cost += (uint64_t)count[d + 1] * count[d + 1];
        count[d + 1] += count[d];
    }
    if (cost > 8 * (uint64_t)n) return 0;
    for (int i = 0; i < n; i++) b[count[a[i] >> shift]++] = a[i];
    for (int i = 1; i < n; i++) {
        uint64_t r = b[i];
        int j = i;
        for (; j > 0 && b[j - 1] > r; j--) b[j] = b[j - 1];
        b[j] = r;
    }
    return 1;
}

/* The order of n pairs by key (n >= 0), as n indices into src: keys are unique, so
 * the order is fully determined, whichever sort finds it. A key's two slots fit in
 * slot_bits each (the bodies' numbers): when they and the index fit in one word, a
 * record is that word, the slots packed into its top 2 * slot_bits bits (the same
 * order as the key) above the index, sorted by buckets (by_buckets) or, when the
 * buckets are uneven, by an LSD radix sort over the key's bits in as few passes of at
 * most 11 bits as cover them (at most three passes up to 2^16 bodies, four up to
 * 2^22).
 * Else a record is (key, index), sorted a byte a pass, skipping the bytes every key
 * shares. keys holds 4n words. */
static const uint32_t *sort_by_key(const nt__pair *src, int n, int slot_bits, uint64_t *keys)
{
    if (n <= 0) return (const uint32_t *)keys; /* keys may still be NULL: not read */
    const int bits = 2 * slot_bits, low = 64 - bits; /* the key's bits; below them, the index's */
    if (bits <= 48 && (uint64_t)(n - 1) >> low == 0) {
        uint64_t *a = keys, *b = keys + (size_t)n, top = 0;
        for (int i = 0; i < n; i++) {
            uint64_t k = src[i].key;
            a[i] = (((k >> 32) << slot_bits | (k & 0xffffffffu)) << low) | (uint32_t)i;
            top |= a[i];
        }
        const uint64_t imask = ((uint64_t)1 << low) - 1u;
        uint32_t *idx = (uint32_t *)(keys + 2 * (size_t)n); /* past both record arrays */
        uint32_t count[2049];
        if (by_buckets(a, b, n, top, count)) {
            for (int i = 0; i < n; i++) idx[i] = (uint32_t)(b[i] & imask);
            return idx;
        }
        const int passes = (bits + 10) / 11, digit = (bits + passes - 1) / passes;
        const uint32_t digits = 1u << digit, mask = digits - 1u;
        for (int shift = low; shift < 64; shift += digit) {
            memset(count, 0, (digits + 1) * sizeof *count);
            for (int i = 0; i < n; i++) count[((a[i] >> shift) & mask) + 1]++;
            for (uint32_t d = 0; d < digits; d++) count[d + 1] += count[d];
            for (int i = 0; i < n; i++) b[count[(a[i] >> shift) & mask]++] = a[i];
            uint64_t *t = a;
            a = b;
            b = t;
        }
        for (int i = 0; i < n; i++) idx[i] = (uint32_t)(a[i] & imask);
        return idx;
    }
    uint64_t *a = keys, *b = keys + 2 * (size_t)n;
    uint64_t all_or = 0, all_and = ~(uint64_t)0;
    for (int i = 0; i < n; i++) {
        a[2 * i] = src[i].key;
        a[2 * i + 1] = (uint64_t)i;
        all_or |= src[i].key;
        all_and &= src[i].key;
    }
    for (int shift = 0; shift < 64; shift += 8) {
        if ((((all_or ^ all_and) >> shift) & 0xffu) == 0) continue; /* same byte everywhere */
        uint32_t count[257] = {0};
        for (int i = 0; i < n; i++) count[((a[2 * i] >> shift) & 0xffu) + 1]++;
        for (int d = 0; d < 256; d++) count[d + 1] += count[d];
        for (int i = 0; i < n; i++) {
            uint32_t k = count[(a[2 * i] >> shift) & 0xffu]++;
            b[2 * k] = a[2 * i];
            b[2 * k + 1] = a[2 * i + 1];
        }
        uint64_t *t = a;
        a = b;
        b = t;
    }
    uint32_t *idx = (uint32_t *)b; /* the other half, no longer needed */
    for (int i = 0; i < n; i++) idx[i] = (uint32_t)a[2 * i + 1];
    return idx;
}

static void end_event(nt_world *w, const nt__contact *c)
{
    int32_t a = key_a(c->key), b = key_b(c->key);
    if (c->flags & NT__CF_SENSOR) {
        nt_sensor_event *e = &w->ev_send[w->n_send++];
        int a_is_sensor = (c->flags & NT__CF_SENSOR_A) != 0;
        e->sensor = a_is_sensor ? id_of(w, a, c->gen_a) : id_of(w, b, c->gen_b);
        e->visitor = a_is_sensor ? id_of(w, b, c->gen_b) : id_of(w, a, c->gen_a);
    } else {
        nt_contact_end_event *e = &w->ev_end[w->n_end++];
        e->a = id_of(w, a, c->gen_a);
        e->b = id_of(w, b, c->gen_b);
    }
}

static void begin_event(nt_world *w, const nt__contact *c)
{
    int32_t a = key_a(c->key), b = key_b(c->key);
    if (c->flags & NT__CF_SENSOR) {
        nt_sensor_event *e = &w->ev_sbegin[w->n_sbegin++];
        int a_is_sensor = (c->flags & NT__CF_SENSOR_A) != 0;
        e->sensor = a_is_sensor ? id_of(w, a, c->gen_a) : id_of(w, b, c->gen_b);
        e->visitor = a_is_sensor ? id_of(w, b, c->gen_b) : id_of(w, a, c->gen_a);
        return;
    }
    nt_contact_begin_event *e = &w->ev_begin[w->n_begin++];
    e->a = id_of(w, a, c->gen_a);
    e->b = id_of(w, b, c->gen_b);
    e->normal = c->n;
    e->depth = c->depth;
    /* Wake on touch: a sleeping body touched by an awake one. */
    for (int s = 0; s < 2; s++) {
        int32_t i = s ? b : a, o = s ? a : b;
        nt__body *bi = &w->bodies[i];
        if (bi->type == NT_BODY_DYNAMIC && bi->awake_slot < 0 && w->bodies[o].awake_slot >= 0 &&
            !(bi->flags & NT__BF_MARK)) {
            bi->flags |= NT__BF_MARK;
            w->wake_list[w->wake_count++] = i;
        }
    }
}

/* A box pair keeps the axis it touched on while that overlap stays shallow, so a
 * resting contact does not flip sideways when the other overlap becomes smaller. */
static void keep_box_axis(const nt_world *w, const nt__contact *o, nt__contact *c)
{
    const nt__body *a = &w->bodies[key_a(c->key)], *b = &w->bodies[key_b(c->key)];
    if (a->shape != NT_SHAPE_AABB || b->shape != NT_SHAPE_AABB || nt__dot(o->n, c->n) > (nt_real)0.5) return;
    if (o->n.x != 0 && o->n.y != 0) return;
    nt_real dx = b->p.x - a->p.x, dy = b->p.y - a->p.y;
    nt_real lim = (nt_real)0.5 * nt__min(nt__min(a->half.x, a->half.y), nt__min(b->half.x, b->half.y));
    if (o->n.x == 0) {
        nt_real oy = a->half.y + b->half.y - nt__fabs(dy);
        if (oy > lim || (dy > 0) != (o->n.y > 0)) return;
        c->n = o->n;
        c->depth = oy;
    } else {
        nt_real ox = a->half.x + b->half.x - nt__fabs(dx);
        if (ox > lim || (dx > 0) != (o->n.x > 0)) return;
        c->n = o->n;
        c->depth = ox;
    }
}

/* The contact a pair of the pair search starts as: its fields, the rest zero. */
static inline void contact_of(nt__contact *c, const nt__pair *p)
{
    memset(c, 0, sizeof *c);
    c->key = p->key;
    c->gen_a = p->gen_a;
    c->gen_b = p->gen_b;
    c->n = p->n;
    c->depth = p->depth;
    c->flags = p->flags;
}

/* con_tmp (just written) becomes con; the old con is the next scratch buffer. */
static void swap_contact_buffers(nt_world *w)
{
    nt__contact *t = w->con;
    int tc = w->con_cap;
    w->con = w->con_tmp;
    w->con_cap = w->con_tmp_cap;
    w->con_tmp = t;
    w->con_tmp_cap = tc;
}

static nt_status collide(nt_world *w, nt_real dt)
{
    if (w->con_dirty) {
        /* Contacts woken since the last step were appended after the sorted ones:
         * sort those few, then merge (not a sort of the whole list, which is most
         * of a big world's contacts every step something wakes). */
        int ns = w->con_sorted, n = w->con_count;
        nt__contact *tail = sort_contacts(w->con + ns, w->con_tmp + ns, n - ns);
        if (tail != w->con + ns) memcpy(w->con + ns, tail, (size_t)(n - ns) * sizeof *tail);
        const nt__contact *a = w->con, *b = w->con + ns;
        nt__contact *out = w->con_tmp;
        int i = 0, j = 0, k = 0, m = n - ns;
        while (i < ns && j < m) out[k++] = b[j].key < a[i].key ? b[j++] : a[i++];
        while (i < ns) out[k++] = a[i++];
        while (j < m) out[k++] = b[j++];
        swap_contact_buffers(w);
        w->con_dirty = 0;
    }
    nt_status s = nt__grid_find_pairs(w, dt);
    if (s != NT_OK) return s;
    if (w->profiling) w->pairs_ms = clock_ms();
    int nn = w->con_new_count, no = w->con_count;
    /* Room for everything this step can produce (the merge keeps con and con_tmp
     * interchangeable, and unparking needs con_count + parked_live). */
    int need = nn + no + w->parked_live;
    bool ok = nt__reserve(&w->con, w->con_count, &w->con_cap, need, sizeof *w->con);
    ok = ok && nt__reserve(&w->con_tmp, 0, &w->con_tmp_cap, need, sizeof *w->con_tmp);
    if (!ok) return NT_ERR_OUT_OF_MEMORY;
    /* Parked slots for this step's parking. Emptied slots make room first once they
     * are a quarter of all (compacting costs every slot: not at every wake); else the
     * arrays grow by half again what they need, so that the wakes after a big group
     * falls asleep do not each grow them. */
    int pneed = w->parked_count + no;
    if (pneed > w->parked_cap && 4 * (w->parked_count - w->parked_live) >= w->parked_count &&
        w->parked_live < w->parked_count) {
        nt__compact_parked(w);
        pneed = w->parked_count + no;
    }
    if (pneed > w->parked_cap) pneed += pneed / 2;
    ok = nt__reserve(&w->parked, w->parked_count, &w->parked_cap, pneed, sizeof *w->parked);
    ok = ok && nt__reserve(&w->park_link, w->parked_count, &w->park_link_cap, pneed, sizeof *w->park_link);
    ok = ok && nt__reserve(&w->park_pick, 0, &w->park_pick_cap, pneed, sizeof *w->park_pick);
    ok = ok && nt__reserve(&w->ev_begin, 0, &w->cap_begin, nn, sizeof *w->ev_begin);
    ok = ok && nt__reserve(&w->ev_end, 0, &w->cap_end, no, sizeof *w->ev_end);
    ok = ok && nt__reserve(&w->ev_sbegin, 0, &w->cap_sbegin, nn, sizeof *w->ev_sbegin);
    ok = ok && nt__reserve(&w->ev_send, 0, &w->cap_send, no, sizeof *w->ev_send);
    ok = ok && nt__reserve(&w->ev_hit, 0, &w->cap_hit, w->awake_count + nn, sizeof *w->ev_hit);
    ok = ok && nt__reserve(&w->sort_keys, 0, &w->sort_cap, 4 * nn, sizeof *w->sort_keys);
    ok = ok && nt__reserve(&w->adj, 0, &w->adj_cap, 2 * need, sizeof *w->adj);
    if (!ok) return NT_ERR_OUT_OF_MEMORY;

    /* Committed: nothing below allocates. */
    w->n_begin = w->n_end = w->n_hit = w->n_sbegin = w->n_send = 0;
    w->wake_count = 0;
    int slot_bits = 1;
    while (slot_bits < 31 && ((uint32_t)w->body_cap - 1u) >> slot_bits) slot_bits++;
    const uint32_t *order = sort_by_key(w->con_new, nn, slot_bits, w->sort_keys);
    nt__contact *old = w->con, *out = w->con_tmp;
    int i = 0, j = 0, k = 0;
    while (i < no || j < nn) {
        if (j >= nn || (i < no && old[i].key < w->con_new[order[j]].key)) {
            const nt__contact *c = &old[i++];
            const nt__body *a = &w->bodies[key_a(c->key)], *b = &w->bodies[key_b(c->key)];
            if (contact_live(w, c) && a->awake_slot < 0 && b->awake_slot < 0)
                nt__park(w, c); /* both asleep or static: keep it aside */
            else if (c->flags & NT__CF_TOUCH)
                end_event(w, c);
        } else if (i >= no || w->con_new[order[j]].key < old[i].key) {
            contact_of(&out[k], &w->con_new[order[j++]]);
            if (out[k].flags & NT__CF_TOUCH) begin_event(w, &out[k]);
            k++;
        } else {
            const nt__contact *o = &old[i++];
            contact_of(&out[k], &w->con_new[order[j++]]);
            nt__contact *c = &out[k++];
            if (o->gen_a == c->gen_a && o->gen_b == c->gen_b) {
                if (c->flags & NT__CF_TOUCH) keep_box_axis(w, o, c);
                /* Warm start only while the normal holds. */
                if (nt__dot(o->n, c->n) > (nt_real)0.95 && !(o->flags & NT__CF_BOUNCED)) {
                    c->ln = o->ln;
                    c->lt = o->lt;
                }
                if ((o->flags & NT__CF_TOUCH) && !(c->flags & NT__CF_TOUCH)) end_event(w, o);
                if (!(o->flags & NT__CF_TOUCH) && (c->flags & NT__CF_TOUCH)) begin_event(w, c);
            } else {
                if (o->flags & NT__CF_TOUCH) end_event(w, o);
                if (c->flags & NT__CF_TOUCH) begin_event(w, c);
            }
        }
    }
    swap_contact_buffers(w); /* the merged list becomes current */
    w->con_count = k;
    for (int q = 0; q < w->wake_count; q++) {
        int32_t b = w->wake_list[q];
        w->bodies[b].flags &= (uint8_t)~NT__BF_MARK;
        nt__wake_group(w, b);
    }
    if (w->wake_count) nt__unpark(w);
    return NT_OK;
}

/* ---------------------------------------------------------------- tiles */

static int oneway_in_range(const nt_world *w, nt_vec2 p, nt_vec2 h)
{
    nt_real ic = w->inv_cell;
    int x0 = nt__ifloor((p.x - h.x) * ic), x1 = nt__ifloor((p.x + h.x) * ic);
    int y0 = nt__ifloor((p.y - h.y) * ic), y1 = nt__ifloor((p.y + h.y) * ic);
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            if (nt__cell_flags(w, x, y) & NT_CELL_ONE_WAY) return 1;
    return 0;
}

/* Deepest overlap (cell units) of the body at p with the one-way tiles alone. */
static nt_real oneway_depth(const nt_world *w, nt_vec2 p, const nt__body *b)
{
    nt_real ic = w->inv_cell;
    nt_vec2 h = nt_v2(b->half.x * ic, b->half.y * ic), c = nt_v2(p.x * ic, p.y * ic);
    int x0 = nt__ifloor(c.x - h.x), x1 = nt__ifloor(c.x + h.x);
    int y0 = nt__ifloor(c.y - h.y), y1 = nt__ifloor(c.y + h.y);
    nt_real worst = 0;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            if (!(nt__cell_flags(w, x, y) & NT_CELL_ONE_WAY)) continue;
            nt_shape s;
            s.type = (nt_shape_type)b->shape;
            s.half = h;
            nt_mtv m;
            if (nt_tile_collide_shape(nt__map_tile(w->map, x, y), nt_v2(c.x - (nt_real)x, c.y - (nt_real)y), s, &m) &&
                m.depth > worst)
                worst = m.depth;
        }
    return worst;
}

/* True when every cell the box can touch is an EMPTY cell of the map: nothing to
 * resolve (the common case for a body in the air, checked without a call). A body
 * is at most half a cell, so it lies within the 3 x 3 cells around its centre's, and
 * each end of its range is that cell or the one next to it: comparisons find which,
 * and the cell's near9 mask says whether those cells are all EMPTY. *cell: the centre's
 * cell (the map's and the grid's), set only when the answer is yes (the body then
 * moves there; otherwise it may end elsewhere). */
static inline int open_air_at(const nt_map *m, nt_real ic, nt_vec2 mwh, nt_vec2 p, nt_vec2 h, int32_t *cell)
{
    nt_real gx = p.x * ic, gy = p.y * ic;
    /* In the map (mwh: its size in cells; border cells covered, NaN refused); there
     * truncation is the floor. */
    if (!(gx >= 0 && gx < mwh.x && gy >= 0 && gy < mwh.y)) return 0;
    int cx = (int)gx, cy = (int)gy;
    int32_t c = (int32_t)cy * m->w + cx;
    unsigned near = m->near9[c];
    if (near) {
        unsigned cols = 2u | ((p.x - h.x) * ic < (nt_real)cx ? 1u : 0u) | ((p.x + h.x) * ic >= (nt_real)(cx + 1) ? 4u : 0u);
        /* The rows as the shifts of the cols mask (1, 8, 64 for rows 0, 1, 2): their
         * product with it is the 3 x 3 mask (cols is below 8: no carries). */
        unsigned rows = 8u | ((p.y - h.y) * ic < (nt_real)cy ? 1u : 0u) | ((p.y + h.y) * ic >= (nt_real)(cy + 1) ? 64u : 0u);
        unsigned covered = cols * rows;
        if (near & covered) return 0;
    }
    *cell = c;
    return 1;
}

static inline int open_air(const nt_world *w, nt_vec2 p, nt_vec2 h)
{
    int32_t cell;
    return open_air_at(w->map, w->inv_cell, nt_v2((nt_real)w->map->w, (nt_real)w->map->h), p, h, &cell);
}

/* True when every cell of the range is an EMPTY cell of the map. */
static int cells_empty(const nt_map *m, int x0, int y0, int x1, int y1)
{
    if (x0 < 0 || y0 < 0 || x1 >= m->w || y1 >= m->h) return 0;
    for (int y = y0; y <= y1; y++) {
        const nt__cell *row = m->cells + (size_t)y * (size_t)m->w;
        for (int x = x0; x <= x1; x++)
            if (row[x].tile != NT_TILE_EMPTY) return 0;
    }
    return 1;
}

/* open_air for a body above half a cell: every cell its box covers is an EMPTY
 * cell of the map. */
NT__NOINLINE static int open_box(const nt_world *w, nt_vec2 p, nt_vec2 h)
{
    nt_real ic = w->inv_cell;
    int x0 = nt__ifloor((p.x - h.x) * ic), x1 = nt__ifloor((p.x + h.x) * ic);
    int y0 = nt__ifloor((p.y - h.y) * ic), y1 = nt__ifloor((p.y + h.y) * ic);
    return cells_empty(w->map, x0, y0, x1, y1);
}

/* The tile resolution of a body that is not in open air (see resolve_body). */
NT__NOINLINE static bool resolve_near(nt_world *w, const nt__body *b, nt_vec2 p_prev, nt_vec2 p, nt_resolution *res)
{
    w->counters.tile_resolutions++;
    nt_shape s = nt__body_shape(b);
    if (!w->oneway_count || !oneway_in_range(w, p, b->half)) return nt__map_resolve(w->map, p, &s, res);
    /* One-way tiles stop a body only from above, and only if it was not inside them. */
    if (oneway_depth(w, p_prev, b) * w->cell <= skin_at(w, p_prev) * 2) {
        if (!nt__map_resolve(w->map, p, &s, res)) return false;
        int ok = 1;
        for (int k = 0; k < res->contact_count; k++)
            if ((nt__cell_flags(w, res->contacts[k].cell_x, res->contacts[k].cell_y) & NT_CELL_ONE_WAY) &&
                !(res->contacts[k].normal.y < 0))
                ok = 0;
        if (ok) return true;
    }
    return nt__map_resolve(w->solid, p, &s, res);
}

/* Free the body at p (it was at p_prev) from the tiles: false when it touches none,
 * else true with the resolution in *res (world units). */
static inline bool resolve_body(nt_world *w, const nt__body *b, nt_vec2 p_prev, nt_vec2 p, nt_resolution *res)
{
    if (!(b->flags & NT__BF_LARGE) ? open_air(w, p, b->half) : open_box(w, p, b->half)) return false;
    return resolve_near(w, b, p_prev, p, res);
}

static inline int cell_material_index(const nt_world *w, int x, int y)
{
    if (!w->cell_mat || x < 0 || y < 0 || x >= w->map->w || y >= w->map->h) return 0;
    return w->cell_mat[(size_t)y * (size_t)w->map->w + (size_t)x];
}

static inline void tile_material(const nt_world *w, const nt__body *b, int mat, nt_real *f, nt_real *e)
{
    const nt_material *m = &w->materials[mat];
    *f = nt__sqrt(b->friction * m->friction);
    *e = nt__max(b->bounce, m->bounce);
}

/* The depth a body is left at in a surface: the skin, but a body thinner than two
 * skins would end wholly inside the surface, so half its thickness then. (Never so for
 * bodies of a normal size.) */
static inline nt_real thin_skin(const nt__body *b, nt_real skin)
{
    nt_real hmin = nt__min(b->half.x, b->half.y);
    return skin * 2 > hmin ? (nt_real)0.5 * hmin : skin;
}

/* Move the body out by the resolution's push, leaving it `skin` deep in each
 * surface (in a corner: in both, so that both stay in contact). */
static void apply_push(const nt_world *w, nt__body *b, const nt_resolution *res)
{
    nt_vec2 p = res->push;
    nt_real skin = thin_skin(b, skin_at(w, b->p));
    if (res->contact_count == 2) {
        /* p' = p - skin * c with c.n1 = c.n2 = 1. Between surfaces facing each other
         * (a pinch: normals more than 120 degrees apart) c is long, and skin * c would
         * sink the body several skins into the tiles along it: for a body above half a
         * cell, which meets such pinches along its long sides, c is cut to length 2,
         * which still leaves it inside both. (Small bodies keep the old rule, so that
         * their recorded replays stay bit for bit the same.) */
        nt_vec2 n1 = res->contacts[0].normal, n2 = res->contacts[1].normal;
        nt_real det = n1.x * n2.y - n1.y * n2.x;
        if (nt__fabs(det) > (nt_real)0.1) {
            nt_vec2 c = nt_v2((n2.y - n1.y) / det, (n1.x - n2.x) / det);
            nt_real c2 = nt__dot(c, c);
            if (c2 > 4 && (b->flags & NT__BF_LARGE)) c = nt__scale(c, 2 / nt__sqrt(c2));
            b->p.x += p.x - skin * c.x;
            b->p.y += p.y - skin * c.y;
            return;
        }
    }
    /* One surface: end exactly `skin` deep, even when that means a hair further in
     * (a graze shallower than the map's tolerance would be lost in a later corner). */
    nt_real len = nt__len(p);
    nt_vec2 n = res->contact_count ? res->contacts[0].normal : (len > 0 ? nt__scale(p, 1 / len) : nt_v2(0, 0));
    b->p.x += p.x - skin * n.x;
    b->p.y += p.y - skin * n.y;
}

/* The depth apply_push leaves a body at in a surface. */
static inline nt_real body_skin(const nt_world *w, const nt__body *b) { return thin_skin(b, skin_at(w, b->p)); }

/* How far from that depth a body may be and still count as held there (an eighth of
 * it): pushing it back to exactly the skin would move it by a rounding of its position
 * every step. */
#define SKIN_BAND (nt_real)0.125

/* True when every surface of the resolution holds the body within the band about the
 * skin's depth: where apply_push would leave it, up to rounding. */
static int skin_deep(const nt_world *w, const nt__body *b, const nt_resolution *res)
{
    nt_real skin = body_skin(w, b), tol = SKIN_BAND * skin;
    if (res->contact_count < 1) return 0;
    for (int k = 0; k < res->contact_count; k++)
        if (!(nt__fabs(res->contacts[k].depth - skin) <= tol)) return 0;
    return 1;
}

/* A remembered tile contact from a resolution's contact c, with normal n (glide's and
 * store_tile_contacts': one way of storing, so that the two cannot differ). */
static inline void set_tile_ct(const nt_world *w, nt__tile_ct *t, nt_vec2 n, const nt_tile_contact *c, int solved)
{
    t->n = n;
    t->depth = c->depth;
    t->lambda = 0;
    t->cx = c->cell_x;
    t->cy = c->cell_y;
    t->material = (uint8_t)cell_material_index(w, t->cx, t->cy);
    t->solved = (uint8_t)solved;
}

/* A body gliding along the flat surface it touched at the end of the last step (every
 * remembered contact along one normal n, not moving into it, no one-way tile in the
 * world): when at p every tile it overlaps holds it along n within the band about the
 * skin, that is the resolution (one contact, no push), found without searching for the
 * way out of the tiles, and stored here as store_tile_contacts(w, b, res, 1) would
 * store it. False: resolve (the body unchanged). */
static int glide(const nt_world *w, nt__body *b, nt_vec2 p)
{
    if (!b->ntc || w->oneway_count || (b->flags & NT__BF_LARGE)) return 0;
    nt_vec2 n = b->tc[0].n;
    if (b->ntc == 2 && !(nt__dot(b->tc[1].n, n) > (nt_real)0.999)) return 0;
    /* (A curve held it: its normal will have turned.) */
    if (nt__tiles[nt__map_tile(w->map, b->tc[0].cx, b->tc[0].cy)].cls != NT_CLASS_POLYGON) return 0;
    if (nt__dot(b->v, n) < 0) return 0;
    nt_real skin = body_skin(w, b), tol = SKIN_BAND * skin;
    nt_shape s = nt__body_shape(b);
    nt_tile_contact c;
    if (!nt__map_glides(w->map, p, &s, n, skin - tol, skin + tol, &c)) return 0;
    /* store_tile_contacts' answer, known here: the contact's tile is POLYGON and its
     * normal within 0.999 of tc[0].n (nt__map_glides' tests: the same products, in
     * the same order), so it keeps tc[0].n, and then tc[1].n when there are two (within
     * 0.999 of tc[0].n: tested above); its answered normal is the last remembered one. */
    set_tile_ct(w, &b->tc[0], b->tc[b->ntc - 1].n, &c, 1);
    b->ntc = 1;
    return 1;
}

/* Remember the surfaces of a resolution. A straight surface seen again keeps the
 * normal it had: where two tiles of one slope meet, the resolution may report a
 * corner's normal tilted by up to a degree or so, and a remembered tilted normal
 * would steer the body off the slope. Round tiles always take the new normal. */
static void store_tile_contacts(const nt_world *w, nt__body *b, const nt_resolution *res, int solved)
{
    nt_vec2 keep[2];
    for (int k = 0; k < res->contact_count; k++) {
        keep[k] = res->contacts[k].normal;
        int t = nt__map_tile(w->map, res->contacts[k].cell_x, res->contacts[k].cell_y);
        if (nt__tiles[t].cls != NT_CLASS_POLYGON) continue;
        for (int j = 0; j < b->ntc; j++)
            if (nt__dot(b->tc[j].n, keep[k]) > (nt_real)0.999) keep[k] = b->tc[j].n;
    }
    b->ntc = (uint8_t)res->contact_count;
    for (int k = 0; k < res->contact_count; k++) set_tile_ct(w, &b->tc[k], keep[k], &res->contacts[k], solved);
}

/* The friction model for one surface the body moves into (a = v.n < 0).
 * `bounce` is the restitution to use (0 for resting contacts). The new velocity is
 * rebuilt from its normal and tangent parts, so a body that sticks gets exactly 0. */
static nt_vec2 respond(nt_friction_model model, nt_vec2 v, nt_vec2 n, nt_real friction, nt_real bounce,
                       nt_real *normal_change)
{
    nt_vec2 t = perp(n);
    nt_real a = nt__dot(v, n), bt = nt__dot(v, t);
    nt_real a2 = -bounce * a, bt2;
    if (model == NT_FRICTION_N) {
        bt2 = (1 - friction) * bt;
    } else {
        nt_real limit = friction * (a2 - a); /* mu * normal velocity change */
        bt2 = nt__fabs(bt) <= limit ? 0 : (bt > 0 ? bt - limit : bt + limit);
    }
    *normal_change = a2 - a;
    return nt_v2(a2 * n.x + bt2 * t.x, a2 * n.y + bt2 * t.y);
}

/* Keep v out of every listed surface. With two surfaces the velocities allowed form
 * a wedge; when both are active the only answer is v = 0 (in 2D). */
static nt_vec2 clamp_surfaces(nt_vec2 v, const nt_vec2 *n, int count)
{
    int active = 0;
    for (int k = 0; k < count; k++) {
        nt_real a = nt__dot(v, n[k]);
        if (a < 0) {
            v = nt__sub(v, nt__scale(n[k], a));
            active |= 1 << k;
        }
    }
    if (count == 2 && (active & 2)) {
        nt_real a = nt__dot(v, n[0]);
        if (a < -(nt_real)(1e-6) * nt__len(v)) v = nt_v2(0, 0);
    }
    return v;
}

/* Resting contacts remembered from the last step: friction applied once, no bounce. */
static void tile_solve(nt_world *w, nt__body *b)
{
    nt_friction_model model = w->def.friction_model;
    for (int k = 0; k < b->ntc; k++) {
        nt__tile_ct *t = &b->tc[k];
        t->solved = 1;
        t->lambda = 0;
        nt_real a = nt__dot(b->v, t->n);
        if (a >= 0) continue;
        /* Straight into the surface (a body resting on it, gravity along its normal):
         * no tangential part for friction to take, no bounce; it stops. */
        if (nt__dot(b->v, perp(t->n)) == 0) {
            b->v = nt_v2(0, 0);
            t->lambda = -a;
            continue;
        }
        nt_real f, e, dn;
        tile_material(w, b, t->material, &f, &e);
        b->v = respond(model, b->v, t->n, f, 0, &dn);
        t->lambda = dn;
    }
    /* Two surfaces: the second answer may have pushed into the first again. */
    if (b->ntc == 2) {
        nt_vec2 n[2] = {b->tc[0].n, b->tc[1].n};
        b->v = clamp_surfaces(b->v, n, 2);
    }
}

/* The surface answered earlier in this step that n is (within 2.6 degrees: the
 * resolution's normal jitters slightly where tiles meet), or NULL. */
static const nt__tile_ct *answered(const nt__body *b, nt_vec2 n)
{
    for (int k = 0; k < b->ntc; k++)
        if (b->tc[k].solved && nt__dot(b->tc[k].n, n) > (nt_real)0.999) return &b->tc[k];
    return NULL;
}

typedef struct hit_rec {
    nt_real speed;
    nt_vec2 n;
    int cx, cy;
} hit_rec;

/* Answer a resolution: for each surface moved into, the friction model (or, for a
 * surface already answered this step, just stop moving into it). */
static void respond_tiles(nt_world *w, nt__body *b, const nt_resolution *res, hit_rec *hit)
{
    for (int k = 0; k < res->contact_count; k++) {
        nt_vec2 n = res->contacts[k].normal;
        const nt__tile_ct *same = answered(b, n);
        if (same) {
            /* Already answered: only stop moving into it, along the answered normal. */
            nt_real a = nt__dot(b->v, same->n);
            if (a < 0) b->v = nt__sub(b->v, nt__scale(same->n, a));
            continue;
        }
        nt_real a = nt__dot(b->v, n);
        if (a >= 0) continue;
        nt__mark_move(w, b, NT__MF_MET);
        nt_real f, e, dn;
        tile_material(w, b, cell_material_index(w, res->contacts[k].cell_x, res->contacts[k].cell_y), &f, &e);
        if (-a < w->def.restitution_threshold) e = 0;
        b->v = respond(w->def.friction_model, b->v, n, f, e, &dn);
        if (-a > hit->speed) {
            hit->speed = -a;
            hit->n = n;
            hit->cx = res->contacts[k].cell_x;
            hit->cy = res->contacts[k].cell_y;
        }
    }
    if (res->contact_count == 2) {
        nt_vec2 n[2] = {res->contacts[0].normal, res->contacts[1].normal};
        b->v = clamp_surfaces(b->v, n, 2);
    }
}

/* ---------------------------------------------------------------- levels */

static inline int32_t other_body(const nt__contact *c, int32_t i)
{
    int32_t a = key_a(c->key);
    return a == i ? key_b(c->key) : a;
}

/* Each body's contacts (live, not sensors) as lists in w->adj: body i's are
 * adj[start[i] .. end[i]) (start = w->level_q, end = w->level_q + body_cap), for the
 * bodies of the contacts only; an entry is the contact's index k, or -1 - k when the
 * pair is not two moving bodies (or there are no levels). Made once a step, after the
 * pairs: the levels walk them, and so does the correction after the move.
 *
 * Levels, on the way (with gravity): how many contacts each body is from the ground
 * (a body touching a tile surface that holds it against gravity, or touching a body
 * that does not move), breadth first over the contacts between moving bodies,
 * speculative ones too (a column falling onto a pile is levelled before it lands); the
 * bodies in that order go to w->level_q + 2 body_cap. In a stack or a pile the lower
 * body of a pair is the one nearer the ground: the velocity solve's last pass
 * (shock_pass) goes up the levels with it not giving way. w->leveled is 0 without
 * gravity (no ground) and when no body touches the ground; bodies not connected to
 * the ground get NT__NO_LEVEL. */
#define NT__NO_LEVEL INT32_MAX
static void build_contact_lists(nt_world *w)
{
    int32_t *start = w->level_q, *end = w->level_q + w->body_cap, *adj = w->adj;
    int32_t *lv = w->level, *order = w->level_q + 2 * w->body_cap;
    nt_vec2 g = w->def.gravity;
    int nc = w->con_count, leveled = g.x != 0 || g.y != 0, nq = 0;
    w->leveled = 0;
    w->level_count = 0;
    for (int k = 0; k < nc; k++) {
        int32_t ia = key_a(w->con[k].key), ib = key_b(w->con[k].key);
        end[ia] = end[ib] = 0;
        start[ia] = start[ib] = -1; /* not placed yet */
        lv[ia] = lv[ib] = NT__NO_LEVEL;
    }
    /* Degrees, and the roots of the levels. */
    for (int k = 0; k < nc; k++) {
        nt__contact *c = &w->con[k];
        if (c->flags & NT__CF_SENSOR) continue;
        int32_t ia = key_a(c->key), ib = key_b(c->key);
        end[ia]++;
        end[ib]++;
        if (!leveled) continue;
        const nt__body *a = &w->bodies[ia], *b = &w->bodies[ib];
        if (!(c->depth > -nt__skin(w, a->p))) continue;
        nt_real wa = solver_w(a), wb = solver_w(b);
        for (int s2 = 0; s2 < 2; s2++) {
            int32_t i = s2 ? ib : ia;
            const nt__body *bi = s2 ? b : a;
            if ((s2 ? wb : wa) <= 0 || lv[i] == 0) continue;
            /* Held up by a body that does not move (its push on i, along n for b and -n
             * for a, against gravity: not one touched from the side), or by a tile. */
            nt_real ng = s2 ? nt__dot(c->n, g) : -nt__dot(c->n, g);
            int root = (s2 ? wa : wb) <= 0 && ng < 0;
            for (int t = 0; t < bi->ntc && !root; t++) root = nt__dot(bi->tc[t].n, g) < 0;
            if (root) {
                lv[i] = 0;
                order[nq++] = i;
            }
        }
    }
    int sum = 0;
    for (int k = 0; k < nc; k++) {
        int32_t ids[2] = {key_a(w->con[k].key), key_b(w->con[k].key)};
        for (int s2 = 0; s2 < 2; s2++) {
            int32_t i = ids[s2];
            if (start[i] >= 0) continue; /* placed already */
            int32_t degree = end[i];
            start[i] = end[i] = sum;
            sum += degree;
        }
    }
    for (int k = 0; k < nc; k++) {
        const nt__contact *c = &w->con[k];
        if (c->flags & NT__CF_SENSOR) continue;
        int32_t ia = key_a(c->key), ib = key_b(c->key);
        int both_move = leveled && solver_w(&w->bodies[ia]) > 0 && solver_w(&w->bodies[ib]) > 0;
        int32_t e = both_move ? k : -1 - k;
        adj[end[ia]++] = e;
        adj[end[ib]++] = e;
    }
    if (nq == 0) return;
    /* Breadth first from the roots, over the contacts between moving bodies. */
    for (int h = 0; h < nq; h++) {
        int32_t i = order[h], l = lv[i] + 1;
        for (int32_t e = start[i]; e < end[i]; e++) {
            if (adj[e] < 0) continue;
            int32_t j = other_body(&w->con[adj[e]], i);
            if (lv[j] != NT__NO_LEVEL) continue;
            lv[j] = l;
            order[nq++] = j;
        }
    }
    w->leveled = 1;
    w->level_count = nq;
}

/* ---------------------------------------------------------------- 2. correct */

/* True when pushing b along dir drives it into a tile surface it rests on. */
static inline int held(const nt__body *b, nt_vec2 dir)
{
    for (int k = 0; k < b->ntc; k++)
        if (nt__dot(b->tc[k].n, dir) < (nt_real)(-0.1)) return 1;
    return 0;
}

/* The bodies a correction moved: their places before it (w->scratch_r) and their
 * list (w->wake_list), for the tile resolution once the pushes are done. */
typedef struct moved_set {
    int32_t *list;
    nt_real *prev;
    int n;
} moved_set;

/* What the correction after the move knows of support (NULL elsewhere): the levels
 * (contacts from the ground, build_contact_lists) of the bodies in contacts, gravity,
 * and how far along it a push must point for support to count (within 60 degrees). */
typedef struct support {
    const int32_t *lv;
    const int32_t *inq; /* >= 0: in a contact, lv valid (correct_after_move) */
    nt_vec2 g;
    nt_real lim;
    int levels; /* the levels count: only for a kicked body's pairs (in the queue's
                 * pairs they pushed piles up bottom first until the visits ran out,
                 * leaving a tenth of a cell at the top: the pile scene settled 0.1) */
} support;

static inline int32_t support_level(const nt_world *w, const support *sp, int32_t i)
{
    return w->bodies[i].awake_slot >= 0 && sp->inq[i] >= 0 ? sp->lv[i] : NT__NO_LEVEL;
}

/* held; after the move (sp given), also a body that bounced off a floor in the move
 * and is pushed down into it: the lower body of a falling pair has no tile contact
 * left then, and pushed into the floor by half the overlap it would be freed from the
 * floor after the pushes, straight back into the upper one. */
static inline int held_by_tile(const nt__body *b, nt_vec2 dir, const support *sp)
{
    return held(b, dir) || (sp && (b->motion & NT__MF_BOUNCED) && nt__dot(dir, sp->g) > sp->lim &&
                            nt__dot(b->tc[0].n, sp->g) < -sp->lim && nt__dot(b->tc[0].n, dir) < (nt_real)(-0.1));
}

/* Push bodies ia and ib apart when they overlap deeper than the skin, by inverse mass.
 * sp: the correction after the move's support rules, or NULL. Returns which moved (1:
 * a, 2: b). */
static NT__INLINE int push_pair(nt_world *w, int32_t ia, int32_t ib, moved_set *ms, const support *sp)
{
    nt__body *a = &w->bodies[ia], *b = &w->bodies[ib];
    nt_real wa = solver_w(a), wb = solver_w(b);
    if (wa + wb <= 0) return 0;
    /* nt_collide_shapes' answer (coincident centres get their own below). */
    nt_mtv m;
    if (!nt__shapes_depth(a->p, a->shape, a->half, b->p, b->shape, b->half, &m)) return 0;
    if (a->p.x == b->p.x && a->p.y == b->p.y) { /* m.normal moves a out of b: -n */
        nt_vec2 n;
        nt__coincident(a, b, ia, ib, &n, &m.depth);
        m.normal = nt_v2(-n.x, -n.y);
    }
    nt_real d = m.depth - skin_at(w, a->p);
    if (d <= 0) return 0;
    /* A body held by a tile surface against this push does not give way: the other
     * one moves the whole distance (tiles are resolved after the pushes). When both
     * are held, the push is split anyway: the tile resolution slides each along its
     * surface (a circle sliding down a slope into one resting in a notch would
     * otherwise creep into it). */
    int ha = wa > 0 && held_by_tile(a, m.normal, sp);
    int hb = wb > 0 && held_by_tile(b, nt_v2(-m.normal.x, -m.normal.y), sp);
    if (ha && !hb) wa = 0;
    if (hb && !ha) wb = 0;
    /* With sp->levels, of two bodies pushed apart along gravity the one nearer the ground does
     * not give way either: a body kicked down by a bounce from above into one resting
     * on others goes back the whole way, instead of pushing that one half the overlap
     * down, where its support pushes it back up into the kicked body (a pair no
     * contact of this step: not tested again). */
    if (sp && sp->levels && wa > 0 && wb > 0) {
        nt_real gn = nt__dot(m.normal, sp->g); /* > 0: a is pushed down */
        int32_t la = support_level(w, sp, ia), lb = support_level(w, sp, ib);
        if (gn > sp->lim && la < lb) wa = 0;
        else if (gn < -sp->lim && lb < la) wb = 0;
    }
    if (wa + wb <= 0) return 0;
    /* Exactly 0 for a body that does not give way (d - d wa / wa can be an ulp, which
     * would count it as moved: a static body then went through the tile resolution). */
    nt_real sa = wb <= 0 ? d : wa <= 0 ? 0 : d * wa / (wa + wb);
    nt_real sb = wa <= 0 ? d : wb <= 0 ? 0 : d - sa;
    int which = 0;
    for (int s = 0; s < 2; s++) {
        int32_t i = s ? ib : ia;
        nt__body *bi = s ? b : a;
        if ((s ? sb : sa) <= 0) continue;
        which |= 1 << s;
        if (!(bi->flags & NT__BF_MOVED)) {
            bi->flags |= NT__BF_MOVED;
            ms->prev[2 * i] = bi->p.x;
            ms->prev[2 * i + 1] = bi->p.y;
            ms->list[ms->n++] = i;
        }
    }
    /* m.normal moves a out of b. */
    a->p.x += m.normal.x * sa;
    a->p.y += m.normal.y * sa;
    b->p.x -= m.normal.x * sb;
    b->p.y -= m.normal.y * sb;
    return which;
}

/* Pushed bodies must not end inside tiles: resolved once, after the pushes (the tile
 * resolution costs far more than a pair push). After the move, their grid cells too. */
static void settle_moved(nt_world *w, moved_set *ms, int after_move)
{
    for (int q = 0; q < ms->n; q++) {
        int32_t i = ms->list[q];
        nt__body *b = &w->bodies[i];
        b->flags &= (uint8_t)~NT__BF_MOVED;
        nt_resolution res;
        nt_vec2 p0 = nt_v2(ms->prev[2 * i], ms->prev[2 * i + 1]);
        if (resolve_body(w, b, p0, b->p, &res)) {
            apply_push(w, b, &res);
            store_tile_contacts(w, b, &res, 0);
        } else {
            b->ntc = 0;
        }
        if (after_move && b->gcell >= 0) nt__grid_update(w, i);
    }
}

/* correct_positions' push of contact c, noted in pushed_at as `when`; 1 when pushed. */
static inline int push_contact(nt_world *w, const nt__contact *c, int32_t *pushed_at, int32_t when, moved_set *ms)
{
    int32_t ia = key_a(c->key), ib = key_b(c->key);
    if ((c->flags & NT__CF_SENSOR) || !push_pair(w, ia, ib, ms, NULL)) return 0;
    pushed_at[ia] = pushed_at[ib] = when;
    return 1;
}

static void correct_positions(nt_world *w)
{
    int iters = w->def.position_iterations;
    if (iters == 0 || w->con_count == 0) return;
    moved_set ms = {w->wake_list, w->scratch_r, 0};
    /* When each body was last pushed, as it * n + k (iteration it, contact k; -1:
     * not yet; below 2^31: at most 64 iterations of fewer than 2^25 contacts, which
     * would take gigabytes): a contact whose bodies have not been pushed since it was
     * last tested gives the same answer again (it depends on their positions only), so
     * later iterations test only the contacts around pushed bodies. */
    const int n = w->con_count;
    const nt__contact *con = w->con;
    int32_t *pushed_at = w->scratch_a;
    for (int k = 0; k < n; k++) pushed_at[key_a(con[k].key)] = pushed_at[key_b(con[k].key)] = -1;
    /* The contacts of this step's pair search (those unparked since come after them)
     * know their depth at the bodies' places: the exact test (push_pair's) finds the
     * same depth or less (of two boxes it takes the lesser axis), so one no deeper than
     * the thinnest skin is not pushed while neither body has moved. */
    const int searched = w->con_dirty ? w->con_sorted : w->con_count;
    const nt_real skin0 = nt__skin_base(w);
    /* The first pass and the later ones as loops of their own: their tests differ. */
    int pushed = 0;
    for (int k = 0; k < n; k++) {
        const nt__contact *c = &con[k];
        int32_t ia = key_a(c->key), ib = key_b(c->key);
        if (k < searched && c->depth <= skin0 && pushed_at[ia] < 0 && pushed_at[ib] < 0) continue;
        pushed |= push_contact(w, c, pushed_at, k, &ms);
    }
    for (int it = 1; it < iters && pushed; it++) {
        pushed = 0;
        for (int k = 0; k < n; k++) {
            const nt__contact *c = &con[k];
            int32_t ia = key_a(c->key), ib = key_b(c->key);
            /* Untouched since the test at (it - 1, k)? */
            int32_t last = (it - 1) * n + k;
            if (pushed_at[ia] < last && pushed_at[ib] < last) continue;
            pushed |= push_contact(w, c, pushed_at, it * n + k, &ms);
        }
    }
    settle_moved(w, &ms, 0);
}

/* After the move, the overlaps the velocity solve could not see: a body that met a
 * tile in the move turned back into one that kept coming (the lower one of a falling
 * pair bounces off a floor), a body moved to its time of impact with a partner that
 * stopped at once (toi_shift), a body the solve kicked farther than its pairs reach,
 * a fast body whose contacts may lie beyond the cells searched (NT__MF_KICKED marks
 * those). Their pairs are pushed apart, those of the bodies pushed then in turn, each
 * body's at most position_iterations times; the pairs that were no contact of this
 * step come from the broad phase around the marked bodies. */
/* Sensors, one-way bodies and characters keep to the contacts' own rules. */
static inline int plain_pair_body(const nt_world *w, int32_t i)
{
    const nt__body *b = &w->bodies[i];
    return !(b->flags & NT__BF_SENSOR) && !b->one_way && !(w->char_count && w->cold[i].character >= 0);
}

/* A queue of bodies in a ring of `cap` slots: the correction after the move's and the
 * bounce pass's (each keeps a body in it at most once, so body_cap slots do). */
typedef struct ring {
    int32_t *slot;
    int cap, head, tail, count;
} ring;

static inline void ring_push(ring *r, int32_t i)
{
    r->slot[r->tail] = i;
    r->tail = (r->tail + 1) % r->cap;
    r->count++;
}

static inline int32_t ring_pop(ring *r)
{
    int32_t i = r->slot[r->head];
    r->head = (r->head + 1) % r->cap;
    r->count--;
    return i;
}

/* The correction's queue; inq[i]: 1 queued, 0 in a contact and not queued, -1 in none. */
static inline void enqueue(ring *q, int32_t *inq, int32_t i)
{
    inq[i] = 1;
    ring_push(q, i);
}

/* The marks the correction after the move reads, off every awake body. */
static void clear_move_marks(nt_world *w)
{
    for (int q = 0; q < w->awake_count; q++)
        w->bodies[w->awake[q]].motion &= (uint8_t)~(NT__MF_KICKED | NT__MF_MET | NT__MF_RECHECK);
}

static void correct_after_move(nt_world *w)
{
    int iters = w->def.position_iterations;
    if (iters == 0) {
        clear_move_marks(w);
        return;
    }
    moved_set ms = {w->wake_list, w->scratch_r, 0};
    int32_t *visits = w->scratch_a, *inq = w->scratch_a + w->body_cap;
    int32_t *start = w->level_q, *end = w->level_q + w->body_cap;
    /* The queue in the level order's room (the levels themselves are read). */
    ring bq = {w->level_q + 2 * w->body_cap, w->body_cap, 0, 0, 0};
    nt_vec2 g = w->def.gravity;
    nt_real g2 = nt__dot(g, g);
    support sup = {w->level, inq, g, (nt_real)0.5 * nt__sqrt(g2), 1}, *sp = g2 > 0 ? &sup : NULL;
    support fl = {w->level, inq, g, sup.lim, 0}, *spq = g2 > 0 ? &fl : NULL;
    /* A body is in the contacts' lists when it is in a contact; mark those first. */
    const int32_t *awake = w->awake;
    for (int q = 0, na = w->awake_count; q < na; q++) {
        int32_t i = awake[q];
        visits[i] = 0;
        inq[i] = -1; /* not in a contact */
    }
    const nt__contact *con = w->con;
    const int32_t *adj = w->adj;
    for (int k = 0, nc = w->con_count; k < nc; k++) inq[key_a(con[k].key)] = inq[key_b(con[k].key)] = 0;
    /* The marked bodies in awake order (nt__mark_move): pairs beyond the contacts from
     * the broad phase first. */
    for (int word = 0; word < (w->awake_count + 63) / 64; word++) {
        uint64_t bits = w->move_marks[word];
        w->move_marks[word] = 0;
        for (; bits; bits &= bits - 1) {
            int32_t i = w->awake[word * 64 + nt__ctz64(bits)];
            nt__body *b = &w->bodies[i];
            if (!(b->motion & (NT__MF_KICKED | NT__MF_MET | NT__MF_RECHECK))) continue;
            int kicked = (b->motion & NT__MF_KICKED) != 0;
            b->motion &= (uint8_t)~(NT__MF_KICKED | NT__MF_MET | NT__MF_RECHECK);
            if (inq[i] == 0) enqueue(&bq, inq, i);
            /* One that met a tile has its pairs among the contacts; the others may not. */
            if (!kicked || !nt__body_in_grid(b) || !plain_pair_body(w, i)) continue;
            /* These pairs are no contacts, which the queue below would come back to: they
             * are pushed here until i does not move (a body kicked among several, each push
             * undoing some of the one before), at most position_iterations times; and
             * once more from a new search when that moved the kicked body itself (pushed
             * out sideways by a body that does not give way, it may now overlap others). */
            for (int pass = 0; pass < 2; pass++) {
                nt_vec2 p0 = b->p;
                int32_t found[32];
                int nf = nt__grid_overlapping(w, i, found, 32), kept = 0;
                for (int f = 0; f < nf; f++) {
                    int32_t j = found[f];
                    if (plain_pair_body(w, j) && nt__pair_filter(b, &w->bodies[j])) found[kept++] = j;
                }
                for (int it = 0; it < iters; it++) {
                    int any = 0;
                    for (int f = 0; f < kept; f++) {
                        int32_t j = found[f];
                        int which = push_pair(w, i < j ? i : j, i < j ? j : i, &ms, sp);
                        any |= which & (i < j ? 1 : 2); /* only moving i can undo another pair */
                        int32_t pj = (which & (i < j ? 2 : 1)) ? j : -1;
                        if (pj >= 0 && w->bodies[pj].awake_slot >= 0 && inq[pj] == 0) enqueue(&bq, inq, pj);
                    }
                    if (!any || kept == 1) break; /* (one pair pushed apart stays apart) */
                }
                if (b->p.x == p0.x && b->p.y == p0.y) break;
            }
        }
    }
    /* Then the contacts of the queued bodies, until none is pushed or each has had
     * its turns. */
    while (bq.count > 0) {
        int32_t i = ring_pop(&bq);
        inq[i] = 0;
        if (visits[i]++ >= iters) continue;
        for (int32_t e = start[i]; e < end[i]; e++) {
            const nt__contact *c = &con[adj[e] < 0 ? -1 - adj[e] : adj[e]];
            int32_t ia = key_a(c->key), ib = key_b(c->key);
            int which = push_pair(w, ia, ib, &ms, spq);
            for (int s = 0; s < 2; s++) {
                int32_t j = s ? ib : ia;
                if (!(which & (1 << s)) || w->bodies[j].awake_slot < 0 || inq[j] != 0 || visits[j] >= iters) continue;
                enqueue(&bq, inq, j);
            }
        }
    }
    settle_moved(w, &ms, 1);
}

/* ---------------------------------------------------------------- 3. velocity */

static void hit_event_bodies(nt_world *w, const nt__contact *c, nt_real speed)
{
    int32_t a = key_a(c->key), b = key_b(c->key);
    if (!((w->bodies[a].flags | w->bodies[b].flags) & NT__BF_HITS)) return;
    nt_hit_event *e = &w->ev_hit[w->n_hit++];
    e->a = id_of(w, a, c->gen_a);
    e->b = id_of(w, b, c->gen_b);
    e->cell_x = e->cell_y = 0;
    e->normal = c->n;
    e->speed = speed;
}

/* A body's tile contacts as one-sided constraints with accumulated impulses
 * (lambda, velocity units), solved exactly: with two surfaces the small
 * complementarity problem is enumerated (both, first, second, none), as Box2D's
 * block solver does for two-point manifolds. */
static inline void solve_tile_single(nt__stile *t, nt_vec2 *v)
{
    nt_real l = nt__max_sel(t->lambda[0] - nt__dot(*v, t->n[0]), 0);
    *v = nt__add(*v, nt__scale(t->n[0], l - t->lambda[0]));
    t->lambda[0] = l;
}

static void solve_tile_pair(nt__stile *t, nt_vec2 *v)
{
    nt_vec2 n1 = t->n[0], n2 = t->n[1];
    /* The velocity without the tiles' impulses. */
    nt_vec2 v0 = nt__sub(*v, nt__add(nt__scale(n1, t->lambda[0]), nt__scale(n2, t->lambda[1])));
    nt_real b1 = nt__dot(v0, n1), b2 = nt__dot(v0, n2), c = nt__dot(n1, n2);
    nt_real x1 = 0, x2 = 0, det = 1 - c * c;
    if (det > (nt_real)(1e-6)) {
        x1 = (-b1 + c * b2) / det;
        x2 = (-b2 + c * b1) / det;
    }
    if (!(det > (nt_real)(1e-6) && x1 >= 0 && x2 >= 0)) {
        x1 = nt__max(-b1, 0);
        x2 = 0;
        if (b2 + c * x1 < 0) {
            x1 = 0;
            x2 = nt__max(-b2, 0);
            if (b1 + c * x2 < 0) {
                /* Parallel surfaces pushing the same way: one answer does for both. */
                x1 = nt__max(-b1, 0);
                x2 = 0;
            }
        }
    }
    t->lambda[0] = x1;
    t->lambda[1] = x2;
    *v = nt__add(v0, nt__add(nt__scale(n1, x1), nt__scale(n2, x2)));
}

/* The solver's tile blocks: those of one contact from the front of w->stile, those of
 * two from its back (body_cap slots, a block per solver body). Each block changes
 * only its own body's velocity, so the order they are solved in within a pass does
 * not change the bits; apart, the single ones run as a tight loop. */
typedef struct tile_blocks {
    nt__stile *st;
    int n1, n2, cap;
} tile_blocks;

/* A solver body by its offset in w->svel counted in nt_reals (the solver's loops then
 * do no multiply for it). A world holds at most NT_MAX_BODIES = 2^30 bodies, so the
 * offsets, below 3 x 2^30, fit in 32 bits. */
static inline nt__svel *svel_at(nt__svel *sv, uint32_t off)
{
    return (nt__svel *)(void *)((char *)sv + (size_t)off * sizeof(nt_real));
}

static inline void solve_tile_blocks(const tile_blocks *tb, nt__svel *sv)
{
    for (int q = 0; q < tb->n1; q++) solve_tile_single(&tb->st[q], &svel_at(sv, tb->st[q].s)->v);
    for (int q = tb->cap - tb->n2; q < tb->cap; q++) solve_tile_pair(&tb->st[q], &svel_at(sv, tb->st[q].s)->v);
}

/* Gravity, drag and tile contacts of a body in the velocity solve, once (NT__MF_SOLVED,
 * cleared after its move). A body's forces depend on nothing another body's do, so
 * answered here, on first sight in the contacts, or in the move for a body in none
 * (move_bodies), they come out as they would in a pass of their own, without the
 * pass over every awake body. */
static inline void solver_forces(nt_world *w, nt__body *b, nt_real dt)
{
    if (b->type != NT_BODY_DYNAMIC || b->awake_slot < 0 || (b->motion & NT__MF_SOLVED)) return;
    b->motion |= NT__MF_SOLVED;
    b->v = nt__solve_velocity(w, b, dt);
    if (b->ntc) tile_solve(w, b);
}

/* The compact solver body of body i, made on first sight (its velocity and the
 * solver's inverse mass copied, its tile contacts too when it moves and has some). */
static inline int32_t solver_body(nt_world *w, int32_t i, int32_t *index, int *nsv, tile_blocks *tb)
{
    if (index[i] >= 0) return index[i];
    const nt__body *b = &w->bodies[i];
    int32_t s = (int32_t)(*nsv)++;
    index[i] = s;
    nt__svel *sv = w->svel;
    sv[s].v = b->v;
    sv[s].w = solver_w(b);
    if (sv[s].w > 0 && b->ntc) {
        nt__stile *t = b->ntc == 1 ? &tb->st[tb->n1++] : &tb->st[tb->cap - ++tb->n2];
        t->s = (uint32_t)s * (uint32_t)(sizeof *sv / sizeof(nt_real));
        t->ntc = b->ntc;
        t->body = i;
        for (int k = 0; k < b->ntc; k++) {
            t->n[k] = b->tc[k].n;
            t->lambda[k] = b->tc[k].lambda;
        }
    }
    return s;
}

/* Time of impact. A speculative contact that closes its gap this step is answered as a
 * collision now (the velocities after it), but the bodies only meet at t = gap /
 * approach speed into the step: up to then each moves with its old velocity, i.e. by
 * (v_before - v_after) t more than v_after dt. Without it a falling body that meets a
 * box stops dead up to v dt above it, and a body pushed by a rolling one keeps that
 * gap. Only for collisions without a bounce: one with a bounce turns back at the gap
 * (it leaves at the speed it should, a gap's distance early). Not for a body resting on another (a touching
 * contact): its velocity change holds the weight too, which is no impact. (Tile
 * contacts are answered before the solve, tile_solve.) Per body in the contacts:
 * scratch_r[2i] the earliest such t (NT_REAL_MAX: none), scratch_r[2i + 1] 1 when
 * resting on a body; NT__MF_SHIFT marks the slots in use (then, from the write-back
 * to the move, the shift itself). */
static inline void toi_note(nt_world *w, int32_t i, int touch, nt_real toi)
{
    nt__body *b = &w->bodies[i];
    nt_real *s = &w->scratch_r[2 * i];
    if (!(b->motion & NT__MF_SHIFT)) {
        b->motion |= NT__MF_SHIFT;
        s[0] = NT_REAL_MAX;
        s[1] = 0;
    }
    if (touch) s[1] = 1;
    if (toi >= 0 && toi < s[0]) s[0] = toi;
}

/* At the write-back of body i's velocity v (the solve's answer): its shift, if any. */
static inline void toi_shift(nt_world *w, int32_t i, nt_vec2 v, nt_real wi)
{
    nt__body *b = &w->bodies[i];
    nt_real *s = &w->scratch_r[2 * i];
    if (!(b->motion & NT__MF_SHIFT)) return;
    if (s[0] == NT_REAL_MAX || s[1] != 0 || wi <= 0) {
        b->motion &= (uint8_t)~NT__MF_SHIFT;
        return;
    }
    nt_real t = s[0];
    s[0] = (b->v.x - v.x) * t;
    s[1] = (b->v.y - v.y) * t;
    /* The shift assumes the partner keeps its old velocity up to the impact too, which
     * one resting on others does not (it stops now): a row of a pile landing on the
     * row beneath ended a fifth of a cell into it. The correction after the move
     * looks at the shifted body's contacts. */
    nt__mark_move(w, b, NT__MF_RECHECK);
    w->kicked_count++;
}

/* After the iterations, which leave a tall stack still closing a little at every
 * level: one pass up the levels in which the body nearer the ground does not give
 * way (shock propagation), so that no pair ends approaching faster than its target. */
static inline void shock_pair(nt__svel *sv, const nt__contact *c, int a_lower)
{
    nt__svel *a = &sv[c->sa], *b = &sv[c->sb];
    nt_real vn = nt__dot(nt__sub(b->v, a->v), c->n);
    if (!(vn < c->bias)) return;
    if (a_lower) {
        if (b->w > 0) b->v = nt__add(b->v, nt__scale(c->n, c->bias - vn));
    } else {
        if (a->w > 0) a->v = nt__sub(a->v, nt__scale(c->n, c->bias - vn));
    }
}

static void shock_pass(nt_world *w)
{
    nt__svel *sv = w->svel;
    const int32_t *lv = w->level, *start = w->level_q, *end = w->level_q + w->body_cap;
    const int32_t *order = w->level_q + 2 * w->body_cap;
    /* The bodies in level order, each against the partners below it. */
    for (int h = 0; h < w->level_count; h++) {
        int32_t i = order[h];
        for (int32_t e = start[i]; e < end[i]; e++) {
            const nt__contact *c = &w->con[w->adj[e] < 0 ? -1 - w->adj[e] : w->adj[e]];
            int32_t j = other_body(c, i);
            if (c->meff <= 0 || !(lv[j] < lv[i])) continue;
            shock_pair(sv, c, key_a(c->key) == j);
        }
    }
}

/* Whether the solve's answer v1 (the velocity was v0) sends a body farther along an
 * axis than its pairs were found for (the pair search reaches each body's own travel
 * plus the base margin): a body kicked by others may then meet one that is no contact
 * of this step (correct_after_move looks for those). */
static inline int kicked_out(const nt_world *w, nt_vec2 v0, nt_vec2 v1, nt_real dt)
{
    nt_real m = w->pair_margin * (nt_real)0.5;
    return (nt__max_sel(v1.x, 0) - nt__max_sel(v0.x, 0)) * dt > m || (nt__max_sel(-v1.x, 0) - nt__max_sel(-v0.x, 0)) * dt > m ||
           (nt__max_sel(v1.y, 0) - nt__max_sel(v0.y, 0)) * dt > m || (nt__max_sel(-v1.y, 0) - nt__max_sel(-v0.y, 0)) * dt > m;
}

/* Perfectly elastic collisions (bounce 1) between bodies not standing on the ground
 * (no level: in flight, or no gravity) are answered before the iterations, one pair
 * at a time, each as the impact of two free bodies: the relative normal velocity vn
 * turns into -vn, which keeps momentum and energy. As restitution targets inside the
 * iterations they did not: a pair whose gap the solve closed (a speculative contact
 * it had not predicted to close) stopped dead, and a target met against a tile
 * surface or a third body took its whole velocity change from the other body
 * (energy from nothing). The gas scene (300 bodies, bounce 1, no gravity) drifted
 * by 1 % in 200 steps so, both ways (summed over the steps: -6.6 % of its energy
 * lost where the solve closed a gap, +5.9 % made against the walls). Bounces below 1, and bodies in piles, keep the targets: the pile
 * answers as one body (what a landing body bounces off), and pairwise impacts
 * through a pile dissipate more, which settles the rain scene sooner (10 % more
 * contacts, 6.5 % more instructions per body-step). */
static inline int elastic_free(const nt_world *w, const nt__contact *c)
{
    return c->bounce >= 1 && w->level[key_a(c->key)] == NT__NO_LEVEL && w->level[key_b(c->key)] == NT__NO_LEVEL;
}

static inline int bounce_contact(nt_world *w, nt__contact *c)
{
    nt__svel *a = &w->svel[c->sa], *b = &w->svel[c->sb];
    nt_real vn = nt__dot(nt__sub(b->v, a->v), c->n);
    /* Closing its gap this step (the bias: zero when touching), above the threshold. */
    if (!(vn < c->bias) || !(vn < -w->def.restitution_threshold)) return 0;
    nt_real dl = -(1 + c->bounce) * vn * c->meff;
    a->v = nt__sub(a->v, nt__scale(c->n, dl * a->w));
    b->v = nt__add(b->v, nt__scale(c->n, dl * b->w));
    c->flags |= NT__CF_BOUNCED;
    return 1;
}

/* The tile surfaces a body touched at the end of the last step, as impacts too, by
 * the move's rule (respond_tiles: the material's bounce and friction, no bounce
 * below the threshold); else the iterations' one-sided tile constraints would stop
 * a body the pass sent back into a wall it had just left. */
static inline void bounce_tiles(const nt_world *w, const nt__body *b, nt__svel *s)
{
    for (int k = 0; k < b->ntc; k++) {
        nt_vec2 n = b->tc[k].n;
        nt_real a = nt__dot(s->v, n), f, e, dn;
        if (!(a < 0)) continue;
        tile_material(w, b, b->tc[k].material, &f, &e);
        if (-a < w->def.restitution_threshold) e = 0;
        s->v = respond(w->def.friction_model, s->v, n, f, e, &dn);
    }
}

/* The bodies whose velocity an impact changed wait in a queue (a ring of body_cap
 * slots, each body in it at most once) to have their surfaces and contacts looked at. */
typedef struct bounce_queue {
    ring r;
    int32_t *state;        /* state per solver body: 2 x turns taken + 1 while queued */
    const int32_t *index;  /* body -> solver body */
    int turns;
} bounce_queue;

static inline void bounce_enqueue(const nt_world *w, bounce_queue *q, int32_t i)
{
    int32_t s = q->index[i];
    if (w->svel[s].w <= 0 || (q->state[s] & 1) || (q->state[s] >> 1) >= q->turns) return;
    q->state[s] |= 1;
    ring_push(&q->r, i);
}

static inline void bounce_pair(nt_world *w, bounce_queue *q, nt__contact *c)
{
    if (!bounce_contact(w, c)) return;
    bounce_enqueue(w, q, key_a(c->key));
    bounce_enqueue(w, q, key_b(c->key));
}

/* The pass: the contacts flagged NT__CF_IMPACT in contact order, then, body by body,
 * the surfaces and contacts of each body an impact changed, until no such pair
 * closes or each body has had velocity_iterations turns (a Newton's cradle passes
 * its impact down the row). What is left closing goes to the iterations. */
static void bounce_pass(nt_world *w, const int32_t *index, int nsv)
{
    const int32_t *start = w->level_q, *end = w->level_q + w->body_cap;
    /* wake_list and the second half of scratch_a are free during the solve. */
    bounce_queue q = {{w->wake_list, w->body_cap, 0, 0, 0}, w->scratch_a + w->body_cap, index,
                      w->def.velocity_iterations};
    memset(q.state, 0, (size_t)nsv * sizeof *q.state);
    for (int k = 0; k < w->con_count; k++) {
        nt__contact *c = &w->con[k];
        if (c->meff > 0 && (c->flags & NT__CF_IMPACT)) bounce_pair(w, &q, c);
    }
    while (q.r.count > 0) {
        int32_t i = ring_pop(&q.r), s = index[i];
        q.state[s] = (q.state[s] & ~1) + 2;
        if (w->bodies[i].ntc) bounce_tiles(w, &w->bodies[i], &w->svel[s]);
        for (int32_t e = start[i]; e < end[i]; e++) {
            nt__contact *c = &w->con[w->adj[e] < 0 ? -1 - w->adj[e] : w->adj[e]];
            if (c->meff > 0 && elastic_free(w, c)) bounce_pair(w, &q, c);
        }
    }
}

/* A body contact as the velocity iterations see it: the fields they use, in a compact
 * array of the contacts with meff > 0 in contact order (in con_tmp, free from the merge
 * of one step's pairs to the next step's: at least con_count contacts' bytes), the
 * solver bodies as svel_at's offsets. */
typedef struct solver_ct {
    uint32_t a, b;
    nt_vec2 n;
    nt_real ln, lt, bias, meff, friction;
} solver_ct;
_Static_assert(sizeof(solver_ct) <= sizeof(nt__contact), "con_tmp holds a solver contact per contact");

/* One contact's normal impulse in an iteration. */
static inline void solve_normal(solver_ct *c, nt__svel *a, nt__svel *b)
{
    nt_real wa = a->w, wb = b->w;
    nt_vec2 n = c->n;
    nt_real vn = nt__dot(nt__sub(b->v, a->v), n);
    nt_real ln = nt__max_sel(c->ln - (vn - c->bias) * c->meff, 0);
    nt_real dl = ln - c->ln;
    c->ln = ln;
    a->v = nt__sub(a->v, nt__scale(n, dl * wa));
    b->v = nt__add(b->v, nt__scale(n, dl * wb));
}

/* The iterations over the body contacts, after the tiles' in each; the friction model's
 * test out of the loop. */
static void solve_contacts(nt_world *w, const tile_blocks *tb, solver_ct *sc, int ns)
{
    nt__svel *sv = w->svel;
    int iters = w->def.velocity_iterations;
    if (w->def.friction_model != NT_FRICTION_COULOMB) {
        for (int it = 0; it < iters; it++) {
            solve_tile_blocks(tb, sv);
            for (int k = 0; k < ns; k++) solve_normal(&sc[k], svel_at(sv, sc[k].a), svel_at(sv, sc[k].b));
        }
        return;
    }
    for (int it = 0; it < iters; it++) {
        solve_tile_blocks(tb, sv);
        for (int k = 0; k < ns; k++) {
            solver_ct *c = &sc[k];
            nt__svel *a = svel_at(sv, c->a), *b = svel_at(sv, c->b);
            solve_normal(c, a, b);
            nt_real wa = a->w, wb = b->w;
            nt_vec2 t = perp(c->n);
            nt_real vt = nt__dot(nt__sub(b->v, a->v), t);
            nt_real lim = c->friction * c->ln;
            nt_real lt = nt__clamp(c->lt - vt * c->meff, -lim, lim);
            nt_real dt_ = lt - c->lt;
            c->lt = lt;
            a->v = nt__sub(a->v, nt__scale(t, dt_ * wa));
            b->v = nt__add(b->v, nt__scale(t, dt_ * wb));
        }
    }
}

/* Kept out of nt__step: inlined there, gcc 12 laid out its loops so that rain's solve
 * phase took 55 ns per body-step instead of 43 (alternated --profile runs). */
NT__NOINLINE static void solve_velocities(nt_world *w, nt_real dt, nt_real dt_ratio)
{
    nt_friction_model model = w->def.friction_model;
    /* Body contacts. Which pairs collide, and hit speeds, come from the velocities
     * before any contact impulse (warm start included) is applied: each body's own
     * forces first (solver_forces), the bodies in no contact get theirs in the move. */
    int any = 0, bounces = 0;
    for (int k = 0; k < w->con_count; k++) {
        nt__contact *c = &w->con[k];
        c->meff = 0;
        if (c->flags & NT__CF_SENSOR) continue;
        nt__body *a = &w->bodies[key_a(c->key)], *b = &w->bodies[key_b(c->key)];
        nt_real wa = solver_w(a), wb = solver_w(b);
        if (wa + wb <= 0) continue;
        any = 1;
        solver_forces(w, a, dt);
        solver_forces(w, b, dt);
        w->scratch_a[key_a(c->key)] = w->scratch_a[key_b(c->key)] = -1;
        c->meff = 1 / (wa + wb);
        c->friction = nt__sqrt(a->friction * b->friction);
        c->bounce = nt__max(a->bounce, b->bounce);
        nt_real vn0 = nt__dot(nt__sub(b->v, a->v), c->n);
        /* Within the skin: resting or overlapping (position correction takes the
         * overlap). Farther apart: a speculative contact, which may close its gap this
         * step and no more; one that closes it is a collision now, so it bounces with
         * the full approach speed; without a bounce the bodies travel the gap first
         * (toi_note, move_dynamic): else they would stop dead at the gap's distance. */
        int touch = c->depth > -nt__skin(w, a->p);
        int hits = touch ? vn0 < 0 : vn0 * dt < c->depth;
        c->bias = touch ? 0 : c->depth / dt;
        /* A bounce is an impact, not a lasting push: its impulse is not carried over as
         * the next step's warm start (which would push the separating bodies apart
         * again: energy from nothing in a gas of bouncing bodies). */
        c->flags &= ~(uint32_t)(NT__CF_BOUNCED | NT__CF_IMPACT);
        /* A touching pair that held last step (its impulse carried over) is resting: of
         * what it closes at, up to what gravity adds along its normal in this step is
         * its weight, not an impact, however long the step (else a box resting on
         * another hops once g dt passes the restitution threshold). */
        nt_real vimp = vn0;
        if (touch && c->ln > 0) {
            nt_real gs = nt__max(a->type == NT_BODY_DYNAMIC ? nt__fabs(a->gravity_scale) : 0,
                                 b->type == NT_BODY_DYNAMIC ? nt__fabs(b->gravity_scale) : 0);
            vimp = nt__min(vn0 + gs * nt__fabs(nt__dot(w->def.gravity, c->n)) * dt, 0);
        }
        if (hits && vimp < -w->def.restitution_threshold) {
            if (elastic_free(w, c)) {
                /* Answered by bounce_pass, before the iterations; the bias keeps the gap. */
                c->flags |= NT__CF_BOUNCED | NT__CF_IMPACT;
                bounces = 1;
            } else {
                c->bias = nt__max(c->bias, -c->bounce * vimp);
                if (c->bounce > 0) c->flags |= NT__CF_BOUNCED;
            }
        }
        nt_real toi = hits && !touch && vn0 < -w->def.restitution_threshold && c->bounce == 0 ? c->depth / vn0 : -1;
        toi_note(w, key_a(c->key), touch, toi);
        toi_note(w, key_b(c->key), touch, toi);
        if (hits && -vn0 >= w->def.hit_event_threshold) hit_event_bodies(w, c, -vn0);
        if (model == NT_FRICTION_N) {
            /* N's rule on the relative velocity, once: lose `friction` of the tangential
             * part. Measured now, applied with the warm start below. */
            c->lt = touch && hits ? -c->friction * nt__dot(nt__sub(b->v, a->v), perp(c->n)) * c->meff : 0;
        }
    }
    /* From here on the solver works on compact copies (nt__svel, w->stile): the
     * iterations touch nothing else, and the results go back to the bodies at the
     * end. Solver bodies are numbered in order of first appearance in the contacts,
     * tile blocks likewise: the same order, the same arithmetic, as on the bodies. */
    int32_t *index = w->scratch_a; /* body -> solver body; -1 (set above): none yet */
    int nsv = 0;
    tile_blocks tb = {w->stile, 0, 0, w->body_cap};
    nt__svel *sv = w->svel;
    solver_ct *sc = (solver_ct *)(void *)w->con_tmp;
    int ns = 0;
    for (int k = 0; k < w->con_count; k++) {
        nt__contact *c = &w->con[k];
        if (c->meff <= 0) continue;
        c->sa = solver_body(w, key_a(c->key), index, &nsv, &tb);
        c->sb = solver_body(w, key_b(c->key), index, &nsv, &tb);
        nt__svel *a = &sv[c->sa], *b = &sv[c->sb];
        nt_real wa = a->w, wb = b->w;
        nt_vec2 n = c->n, t = perp(n);
        if (model == NT_FRICTION_COULOMB) c->lt *= dt_ratio;
        c->ln *= dt_ratio;
        nt_vec2 P = nt_v2(n.x * c->ln + t.x * c->lt, n.y * c->ln + t.y * c->lt);
        a->v = nt__sub(a->v, nt__scale(P, wa));
        b->v = nt__add(b->v, nt__scale(P, wb));
        if (model == NT_FRICTION_N) c->lt = 0; /* N's friction is not carried over */
        solver_ct *q = &sc[ns++];
        q->a = (uint32_t)c->sa * (uint32_t)(sizeof *sv / sizeof(nt_real));
        q->b = (uint32_t)c->sb * (uint32_t)(sizeof *sv / sizeof(nt_real));
        q->n = n;
        q->ln = c->ln;
        q->lt = c->lt;
        q->bias = c->bias;
        q->meff = c->meff;
        q->friction = c->friction;
    }
    if (bounces) bounce_pass(w, index, nsv);
    if (any) {
        /* Tiles first in each iteration (infinite mass, one-sided): they carry the
         * warm-started weight. (bounce_pass changes none of the fields copied above.) */
        solve_contacts(w, &tb, sc, ns);
        /* The tiles, once more after the iterations, then the pass up the stack (which
         * may leave a little velocity into a surface: the move answers it). */
        solve_tile_blocks(&tb, sv);
        if (w->leveled) shock_pass(w);
        /* Pairs the iterations left closing by more than half the base margin over the
         * step (a tall column under a heavy impact): the correction after the move
         * looks at their bodies' contacts. */
        nt_real slack = (nt_real)0.5 * w->pair_margin / dt;
        for (int k = 0, j = 0; k < w->con_count; k++) {
            nt__contact *c = &w->con[k];
            if (c->meff <= 0) continue;
            c->ln = sc[j].ln;
            c->lt = sc[j].lt;
            j++;
            if (!(nt__dot(nt__sub(sv[c->sb].v, sv[c->sa].v), c->n) < c->bias - slack)) continue;
            /* (Only bodies that move: the correction after the move clears the marks of
             * the awake bodies.) */
            if (sv[c->sa].w > 0) nt__mark_move(w, &w->bodies[key_a(c->key)], NT__MF_RECHECK);
            if (sv[c->sb].w > 0) nt__mark_move(w, &w->bodies[key_b(c->key)], NT__MF_RECHECK);
            w->kicked_count++;
        }
    }
    /* Back to the bodies: velocities (of every solver body: one that does not move
     * received zero impulses, which can still turn a -0 into +0, as on the bodies)
     * and tile impulses. */
    for (int k = 0; k < w->con_count; k++) {
        const nt__contact *c = &w->con[k];
        if (c->meff <= 0) continue;
        for (int s2 = 0; s2 < 2; s2++) {
            int32_t i = s2 ? key_b(c->key) : key_a(c->key);
            int32_t q = s2 ? c->sb : c->sa;
            if (index[i] != q) continue; /* written back already */
            index[i] = -1;
            /* A static body keeps its zero velocity whatever the impulses were (they
             * are multiplied by its zero inverse mass: exact zeros, or NaN after an
             * overflow). */
            if (w->bodies[i].type == NT_BODY_STATIC) continue;
            toi_shift(w, i, sv[q].v, sv[q].w);
            if (kicked_out(w, w->bodies[i].v, sv[q].v, dt)) {
                nt__mark_move(w, &w->bodies[i], NT__MF_KICKED);
                w->kicked_count++;
            }
            w->bodies[i].v = sv[q].v;
        }
    }
    for (int q = 0; q < tb.n1; q++) w->bodies[tb.st[q].body].tc[0].lambda = tb.st[q].lambda[0];
    for (int q = tb.cap - tb.n2; q < tb.cap; q++) {
        nt__body *b = &w->bodies[tb.st[q].body];
        b->tc[0].lambda = tb.st[q].lambda[0];
        b->tc[1].lambda = tb.st[q].lambda[1];
    }
}

/* ---------------------------------------------------------------- 4. move */

/* True when every cell the box swept from p to p + d (half-size h) is EMPTY. */
static int sweep_empty(const nt_world *w, nt_vec2 p, nt_vec2 d, nt_vec2 h)
{
    nt_real ic = w->inv_cell;
    nt_real lx = nt__min(p.x, p.x + d.x) - h.x, hx = nt__max(p.x, p.x + d.x) + h.x;
    nt_real ly = nt__min(p.y, p.y + d.y) - h.y, hy = nt__max(p.y, p.y + d.y) + h.y;
    int x0 = nt__ifloor(lx * ic), x1 = nt__ifloor(hx * ic);
    int y0 = nt__ifloor(ly * ic), y1 = nt__ifloor(hy * ic);
    if ((long)(x1 - x0 + 1) * (long)(y1 - y0 + 1) > 48) return 0;
    /* Up to 3 x 3 cells with the corner cell's diagonal neighbour in the map (the usual
     * sweep of a falling body): that cell's near9 mask, whose bits are set for cells
     * outside the map and those not EMPTY, answers for all of them. */
    const nt_map *m = w->map;
    if ((unsigned)(x1 - x0) <= 2u && (unsigned)(y1 - y0) <= 2u && nt__map_in(m, x0 + 1, y0 + 1)) {
        static const unsigned rows[3] = {1u, 9u, 73u}; /* 1, 1 + 8, 1 + 8 + 64 */
        unsigned covered = ((1u << (x1 - x0 + 1)) - 1u) * rows[y1 - y0];
        return !(m->near9[(size_t)(y0 + 1) * (size_t)m->w + (size_t)(x0 + 1)] & covered);
    }
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            if (nt__map_tile(w->map, x, y) != NT_TILE_EMPTY) return 0;
    return 1;
}

/* A flying body that met one surface during a substep of length h (it went from p0
 * by d to b->p, which the resolution res pushes back out; `after` is the time left in the
 * step after this substep, ga its gravity): bounce at the time of impact instead of
 * where the push leaves it. The surface is met at the fraction tau of the substep at
 * which the linear path enters it by the skin; there the velocity (v - ga (after +
 * (1 - tau) h)) is answered by the material (bounce, friction), and the rest of the
 * substep and of the step is flown on the parabola from there. Returns 0, changing
 * nothing, when that is not a plain bounce: a corner, a contact it was not moving
 * into, a bounce too slow to keep (restitution threshold), or a way back that meets
 * the tiles again. */
static int toi_bounce(nt_world *w, nt__body *b, nt_vec2 p0, nt_vec2 d, const nt_resolution *res, nt_vec2 ga, nt_real after,
                      nt_real h, hit_rec *hit)
{
    if (res->contact_count != 1) return 0;
    nt_vec2 n = res->contacts[0].normal;
    nt_real in = -nt__dot(d, n);                         /* how far the substep went into the surface */
    nt_real pen = nt__dot(res->push, n) - skin_at(w, b->p); /* ...of which past the resting skin */
    if (!(in > 0) || !(pen <= in)) return 0;
    if (!(pen > 0)) pen = 0; /* within the skin by rounding (far from the origin): met at the end */
    nt_real tau = 1 - pen / in;
    nt_real left = (1 - tau) * h + after;                /* time from the impact to the end of the step */
    nt_vec2 vc = nt__sub(b->v, nt__scale(ga, left));    /* velocity at the impact */
    nt_real a = nt__dot(vc, n);
    if (!(a < 0) || -a < w->def.restitution_threshold) return 0;
    nt_real f, e, dn;
    tile_material(w, b, cell_material_index(w, res->contacts[0].cell_x, res->contacts[0].cell_y), &f, &e);
    if (e <= 0) return 0;
    nt_vec2 vr = respond(w->def.friction_model, vc, n, f, e, &dn);
    nt_vec2 pc = nt__add(p0, nt__scale(d, tau));
    nt_vec2 q = nt_v2(pc.x + (vr.x + (nt_real)0.5 * ga.x * left) * left, pc.y + (vr.y + (nt_real)0.5 * ga.y * left) * left);
    /* The way back must be free, but for the surface it left, within the skin (a
     * late, slow bounce ends a hair from it: rounding must not decide the path); for a
     * body thinner than two skins, within half its thickness, as apply_push leaves it
     * (else its centre could stay on the far side of the surface). */
    nt_real sk = thin_skin(b, skin_at(w, q));
    nt_resolution again;
    if (resolve_body(w, b, pc, q, &again) &&
        (again.contact_count != 1 || nt__dot(again.contacts[0].normal, n) < (nt_real)0.999 ||
         nt__dot(again.push, again.push) > sk * sk))
        return 0;
    b->p = q;
    b->v = nt__add(vr, nt__scale(ga, left));
    nt__mark_move(w, b, NT__MF_MET);
    if (-a > hit->speed) {
        hit->speed = -a;
        hit->n = n;
        hit->cx = res->contacts[0].cell_x;
        hit->cy = res->contacts[0].cell_y;
    }
    return 1;
}

/* How many substeps a move by disp takes: a step longer than the body's smaller
 * half-size could skip a thin piece of tile, unless every cell it sweeps is EMPTY.
 * (The square root only for steps near that length or longer: most are far shorter.) */
static inline int substep_count(const nt_world *w, const nt__body *b, nt_vec2 disp)
{
    nt_real d2 = nt__dot(disp, disp), hmin = nt__min(b->half.x, b->half.y);
    if (d2 < (nt_real)0.98 * hmin * hmin) return 1;
    nt_real dist = nt__sqrt(d2);
    if (!(dist > hmin) || sweep_empty(w, b->p, disp, b->half)) return 1;
    nt_real q = dist / hmin;
    return q >= 256 ? 256 : (int)q + 1;
}

/* What the move reads of the world for every body, read once per step: a store to a
 * body's nt_real fields may alias the world's, so the compiler would read them again
 * for each body. */
typedef struct move_consts {
    const nt_map *map;
    nt_vec2 mwh;               /* the map's size in cells */
    nt_vec2 g;                 /* gravity */
    nt_real dt, ic, maxd, vmax2;
    nt_real vfree2;            /* vmax2, at most NT_REAL_MAX: speeds up to it are left alone */
    nt_real bend;              /* (1/2) dt^2 */
    nt_real back;              /* move_dynamic's `back` for one substep: dt - dt / 2 */
    int gravity;               /* g is not zero */
    uint32_t map_epoch;
} move_consts;

static move_consts move_consts_of(const nt_world *w, nt_real dt)
{
    move_consts mc;
    mc.map = w->map;
    mc.mwh = nt_v2((nt_real)w->map->w, (nt_real)w->map->h);
    mc.g = w->def.gravity;
    mc.dt = dt;
    mc.ic = w->inv_cell;
    mc.maxd = w->def.max_cells_per_step * w->cell;
    mc.vmax2 = (mc.maxd / dt) * (mc.maxd / dt);
    mc.vfree2 = mc.vmax2 <= NT_REAL_MAX ? mc.vmax2 : NT_REAL_MAX;
    mc.bend = (nt_real)0.5 * dt * dt;
    nt_real h = dt / (nt_real)1;
    mc.back = dt - (nt_real)0.5 * h;
    mc.gravity = mc.g.x != 0 || mc.g.y != 0;
    mc.map_epoch = w->map_epoch;
    return mc;
}

/* The gravity whose exact parabola a body in free flight follows this step (see
 * move_dynamic), or zero. Read before the move updates NT__MF_AIR. */
static inline nt_vec2 flight_gravity(const move_consts *mc, const nt__body *b, int free_ok)
{
    if (!mc->gravity || !(free_ok && !b->ntc && (b->motion & NT__MF_AIR) && !(b->motion & NT__MF_SOLVED) && b->drag == 0))
        return nt_v2(0, 0);
    nt_vec2 ga = nt_v2(mc->g.x * b->gravity_scale, mc->g.y * b->gravity_scale);
    /* Not when the parabola's bend is more than a step may move (huge gravity): the
     * speed limit holds the displacement, and v dt keeps within it. */
    if (!(nt__fabs(ga.x) * mc->bend <= mc->maxd && nt__fabs(ga.y) * mc->bend <= mc->maxd)) ga = nt_v2(0, 0);
    return ga;
}

/* move_dynamic's answer for a body in flight that fly_plain does not take (one held
 * by the speed limit, with drag, above half a cell, resting, or in a contact of the
 * velocity solve): no tile contact at the end of the last step, no time-of-impact
 * shift, one substep (a step shorter than its smaller half-size, or a sweep through
 * EMPTY cells only), and open air where it arrives. The same arithmetic as
 * move_dynamic; returns 0, changing nothing, for any other body. *cell: the grid cell
 * of a body up to half a cell where it arrives, else -1. fly_plain repeats its
 * arithmetic for its bodies: keep the two in step. */
static inline int fly_free(nt_world *w, const move_consts *mc, nt__body *b, int free_ok, int32_t *cell)
{
    if (b->ntc || (b->motion & NT__MF_SHIFT)) return 0;
    const nt_real dt = mc->dt;
    nt_vec2 disp = nt__scale(b->v, dt);
    if (substep_count(w, b, disp) != 1) return 0;
    nt_vec2 ga = flight_gravity(mc, b, free_ok), d = disp;
    if (ga.x != 0 || ga.y != 0) /* one substep (h = dt / 1 = dt), as move_dynamic computes it */
        d = nt_v2((b->v.x - ga.x * mc->back) * dt, (b->v.y - ga.y * mc->back) * dt);
    nt_vec2 q = nt_v2(b->p.x + d.x, b->p.y + d.y);
    *cell = -1;
    if (!(!(b->flags & NT__BF_LARGE) ? open_air_at(mc->map, mc->ic, mc->mwh, q, b->half, cell) : open_box(w, q, b->half))) return 0;
    b->motion = (uint8_t)((b->motion & ~(NT__MF_MET | NT__MF_BOUNCED | NT__MF_SOLVED)) | NT__MF_AIR);
    if (q.x == b->p.x && q.y == b->p.y) {
        b->flags |= NT__BF_RESTING;
        b->rest_p = q;
        b->rest_epoch = mc->map_epoch;
    } else {
        b->flags &= (uint8_t)~NT__BF_RESTING;
        b->p = q;
    }
    return 1;
}

/* The move of a dynamic body that does not fly free (fly_plain, fly_free). Out of
 * line: inlined, it takes the registers of move_bodies' loop, whose bodies mostly
 * fly free. */
NT__NOINLINE static int move_dynamic(nt_world *w, const move_consts *mc, int32_t i, int free_ok)
{
    const nt_real dt = mc->dt;
    nt__body *b = &w->bodies[i];
    nt_vec2 disp = nt__scale(b->v, dt);
    b->motion &= (uint8_t)~(NT__MF_MET | NT__MF_BOUNCED);
    /* The time-of-impact shift (toi_shift), swept with the step's own travel. */
    int shifted = (b->motion & NT__MF_SHIFT) != 0;
    nt_vec2 shift = nt_v2(0, 0);
    if (shifted) {
        b->motion &= (uint8_t)~NT__MF_SHIFT;
        shift = nt_v2(w->scratch_r[2 * i], w->scratch_r[2 * i + 1]);
        disp = nt__add(disp, shift);
    }
    int n = substep_count(w, b, disp);
    nt_real h = dt / (nt_real)n;
    hit_rec hit = {0, {0, 0}, 0, 0};
    b->flags &= (uint8_t)~NT__BF_RESTING;
    /* Free flight (no tile contact at the end of the last two steps, no contact in
     * this step's solve, no drag, not held back by the speed limit) follows the exact
     * parabola: the solve added g dt to v, and over a substep ending at time t1 the
     * exact displacement is (v - g (dt - t1 + h/2)) h. Bodies in contact keep
     * semi-implicit Euler (v dt), which stacks stably, and so does a body that lost its
     * tile contact only in the last step (at a seam, a crest): with v dt it sinks back
     * into the surface it slides along, where the parabola would leave it above it,
     * within the skin, and out of contact. */
    nt_vec2 ga = flight_gravity(mc, b, free_ok);
    b->motion = (uint8_t)((b->motion & ~NT__MF_AIR) | (b->ntc ? 0 : NT__MF_AIR));
    int flying = ga.x != 0 || ga.y != 0;
    for (int s = 0; s < n; s++) {
        nt_vec2 p0 = b->p;
        nt_real back = flying ? dt - ((nt_real)s + (nt_real)0.5) * h : 0;
        /* The displacement itself, not p1 - p0: far from the origin that difference
         * keeps only a few bits of it. */
        nt_vec2 d = nt_v2((b->v.x - ga.x * back) * h, (b->v.y - ga.y * back) * h);
        if (shifted) {
            d.x += shift.x / (nt_real)n;
            d.y += shift.y / (nt_real)n;
        }
        b->p.x += d.x;
        b->p.y += d.y;
        nt_vec2 p1 = b->p;
        nt_resolution res;
        if (n == 1 && !flying && !shifted && glide(w, b, b->p)) {
            /* (glide stored its contact) */
        } else if (!resolve_body(w, b, p0, b->p, &res)) {
            b->ntc = 0;
        } else if (flying && toi_bounce(w, b, p0, d, &res, ga, dt - ((nt_real)s + 1) * h, h, &hit)) {
            b->ntc = 0; /* on its way back, free: the rest of the step is flown */
            break;
        } else {
            /* A body that did not move and sits within the skin of every surface it
             * touches is resting: no push. (Pushing it to exactly the skin moves it by
             * a rounding of its position every step, and it never counts as resting.) */
            if (!(n == 1 && p0.x == p1.x && p0.y == p1.y && skin_deep(w, b, &res))) apply_push(w, b, &res);
            respond_tiles(w, b, &res, &hit);
            store_tile_contacts(w, b, &res, 1);
            flying = 0;
            ga = nt_v2(0, 0);
        }
        if (n == 1 && p0.x == p1.x && p0.y == p1.y && b->p.x == p1.x && b->p.y == p1.y) {
            b->flags |= NT__BF_RESTING;
            b->rest_p = b->p;
            b->rest_epoch = w->map_epoch;
        }
    }
    for (int k = 0; k < b->ntc; k++) b->tc[k].solved = 0;
    /* Met a surface and left it again within the move (a bounce, in one substep or
     * over several): the surface for the correction after the move. */
    if (!b->ntc && (b->motion & NT__MF_MET) && hit.speed > 0) {
        b->motion |= NT__MF_BOUNCED;
        b->tc[0].n = hit.n;
    }
    if (hit.speed > 0 && hit.speed >= w->def.hit_event_threshold && (b->flags & NT__BF_HITS)) {
        nt_hit_event *e = &w->ev_hit[w->n_hit++];
        e->a = id_of(w, i, b->generation);
        e->b = nt_null_body_id();
        e->cell_x = hit.cx;
        e->cell_y = hit.cy;
        e->normal = hit.n;
        e->speed = hit.speed;
    }
    return n;
}

/* A body that does not move, where the last resolution moved it by nothing, with
 * the tiles unchanged since: the resolution would give the same answer again (it
 * depends on the position and the tiles only), so its contacts are kept as they are
 * and it stays where it is. This is what makes bodies resting on tiles cheap. */
static inline int at_rest(const move_consts *mc, const nt__body *b)
{
    return (b->flags & NT__BF_RESTING) && b->v.x == 0 && b->v.y == 0 && !(b->motion & NT__MF_SHIFT) &&
           b->rest_epoch == mc->map_epoch && b->p.x == b->rest_p.x && b->p.y == b->rest_p.y;
}

/* Both components +0 (the bits, not just == 0). */
static inline int plus_zero(nt_vec2 v)
{
    const nt_vec2 z = nt_v2(0, 0);
    return memcmp(&v, &z, sizeof v) == 0;
}

/* A resting body whose remembered tile contacts stopped its gravity (and drag) from a
 * velocity of +0 exactly, to +0 exactly (NT__MF_HELD, set here): the same forces from
 * the same +0 against the same surfaces give the same answer, so as long as it stays
 * at rest and nothing its answer depends on has changed (the step, the world's gravity
 * and materials: held_ok; the body's own gravity scale, drag, velocity and material:
 * their setters clear the mark, and so does sleep), its forces and contacts are not
 * answered again. Only in steps without body contacts (`forces`): with them, each
 * body's forces are answered anew (by the solve for the bodies in contacts, by the move
 * for the others). */
static inline void rest_again(nt__body *b)
{
    b->motion &= (uint8_t)~(NT__MF_MET | NT__MF_BOUNCED | NT__MF_SOLVED);
    for (int c = 0; c < b->ntc; c++) {
        b->tc[c].lambda = 0;
        b->tc[c].solved = 0;
    }
}

/* A body's forces in a step without body contacts: gravity, drag, its tile contacts. */
static inline void body_forces(nt_world *w, const move_consts *mc, nt__body *b)
{
    b->motion &= (uint8_t)~NT__MF_HELD;
    b->v = nt__solve_velocity_g(mc->g, b, mc->dt);
    if (b->ntc) tile_solve(w, b);
}

/* The most common body: dynamic, not resting, up to half a cell (not LARGE), no tile
 * contact, no time-of-impact shift, its forces answered by the move (not
 * NT__MF_SOLVED), no drag (never below 0: its setters). All but the drag are in
 * eight bytes in a row (type to motion), tested as one word. */
static inline int plain_body(const nt__body *b, uint64_t mask, uint64_t want)
{
    uint64_t head;
    memcpy(&head, (const unsigned char *)b + offsetof(nt__body, type), sizeof head);
    return (head & mask) == want && !(b->drag > 0);
}

/* A plain body: its forces (body_forces), then, unless the speed limit holds it,
 * fly_free, in one pass, with what they share computed once: the same arithmetic
 * (keep it in step with body_forces, flight_gravity and fly_free). held: the motion
 * flags its forces keep (body_forces clears NT__MF_HELD), keep: those they and
 * fly_free keep. Returns 1 when it flew free (*cell: the grid cell where it arrived),
 * else 0 with its forces applied and *cell untouched (the move goes on from there). */
static inline int fly_plain(nt_world *w, const move_consts *mc, nt__body *b, unsigned held, unsigned keep, int32_t *cell)
{
    const nt_real dt = mc->dt;
    nt_vec2 ga = nt_v2(mc->g.x * b->gravity_scale, mc->g.y * b->gravity_scale);
    nt_vec2 v = nt_v2(b->v.x + ga.x * dt, b->v.y + ga.y * dt);
    nt_vec2 d = nt__scale(v, dt);
    nt_real d2 = nt__dot(d, d), hmin = nt__min(b->half.x, b->half.y);
    /* Left alone by the speed limit (NaN and overflow are not), in one substep
     * (substep_count). A step shorter than hmin, at most half a cell (not LARGE), is
     * below half the limit (a cell or more per step), whatever the rounding: the
     * limit's test is needed only for longer steps. */
    if (d2 < (nt_real)0.98 * hmin * hmin ||
        (nt__dot(v, v) <= mc->vfree2 && (!(nt__sqrt(d2) > hmin) || sweep_empty(w, b->p, d, b->half)))) {
        /* flight_gravity (its ga: g * gravity_scale, as above), then fly_free. */
        if (mc->gravity && (b->motion & NT__MF_AIR) && nt__fabs(ga.x) * mc->bend <= mc->maxd &&
            nt__fabs(ga.y) * mc->bend <= mc->maxd && (ga.x != 0 || ga.y != 0))
            d = nt_v2((v.x - ga.x * mc->back) * dt, (v.y - ga.y * mc->back) * dt);
        nt_vec2 q = nt_v2(b->p.x + d.x, b->p.y + d.y);
        if (open_air_at(mc->map, mc->ic, mc->mwh, q, b->half, cell)) {
            b->v = v;
            b->motion = (uint8_t)((b->motion & keep) | NT__MF_AIR);
            if (q.x == b->p.x && q.y == b->p.y) {
                b->flags |= NT__BF_RESTING;
                b->rest_p = q;
                b->rest_epoch = mc->map_epoch;
            } else {
                b->p = q;
            }
            return 1;
        }
    }
    b->v = v;
    b->motion &= (uint8_t)held;
    return 0;
}

/* The forces of a body flagged resting, in a step without body contacts: 1 when it
 * rests again (done with this step), else 0 with its forces applied. */
NT__NOINLINE static int rest_forces(nt_world *w, const move_consts *mc, nt__body *b, int held_ok)
{
    int still = at_rest(mc, b) && plus_zero(b->v);
    if (still && held_ok && (b->motion & NT__MF_HELD)) {
        rest_again(b);
        w->counters.bodies_held++;
        return 1;
    }
    body_forces(w, mc, b);
    if (!at_rest(mc, b)) return 0;
    rest_again(b);
    if (still && plus_zero(b->v)) b->motion |= NT__MF_HELD;
    return 1;
}

/* The move. Each body's gravity, drag and resting tile contacts are answered here,
 * just before its move, unless the velocity solve answered them (a body in its
 * contacts: NT__MF_SOLVED); `forces`: there was no body contact to solve, so this is
 * every body, and resting ones may be answered from the step before (rest_forces).
 * Each body's rest time is noted after its move (nt__sleep_note). The most common
 * body (plain_body) is answered by fly_plain when it flies free. */
static void move_bodies(nt_world *w, nt_real dt, int forces, nt__sleep_pass *sleep)
{
    nt__sleep_pass sl = *sleep; /* (a local copy: the loop keeps it in registers) */
    const move_consts mcs = move_consts_of(w, dt), *mc = &mcs;
    const nt_real maxd = mc->maxd, vmax2 = mc->vmax2;
    /* The marks are valid from one step without body contacts to the next. */
    const int held_ok = forces && dt == w->prev_dt && w->force_epoch == w->held_epoch;
    if (forces) w->held_epoch = w->force_epoch;
    else w->force_epoch++;
    /* fly_plain's masks: body_forces clears NT__MF_HELD (in steps without body contacts
     * only: the solve's forces keep it), fly_free the last move's marks. */
    const unsigned held = forces ? (unsigned)~NT__MF_HELD : ~0u, keep = held & (unsigned)~(NT__MF_MET | NT__MF_BOUNCED);
    /* plain_body's test of the eight bytes from type to motion, each byte placed by
     * its field's offset. */
#define AT(f) (offsetof(nt__body, f) - offsetof(nt__body, type))
    uint64_t plain_mask, plain_head;
    uint8_t mask[8] = {0}, head[8] = {0};
    mask[AT(type)] = 0xff;
    head[AT(type)] = NT_BODY_DYNAMIC;
    mask[AT(flags)] = NT__BF_RESTING | NT__BF_LARGE;
    mask[AT(ntc)] = 0xff;
    mask[AT(motion)] = NT__MF_SHIFT | NT__MF_SOLVED;
#undef AT
    memcpy(&plain_mask, mask, sizeof mask);
    memcpy(&plain_head, head, sizeof head);
    /* (The move wakes no body: the awake list stays as it is.) */
    const int32_t *awake = w->awake;
    const int count = w->awake_count;
    /* Sub-steps: one for each awake body, plus move_dynamic's extra ones. */
    int moves = count;
    nt__body *bodies = w->bodies;
    for (int k = 0; k < count; k++) {
        int32_t i = awake[k];
        nt__body *b = &bodies[i];
        int plain = plain_body(b, plain_mask, plain_head);
        if (plain) {
            int32_t cell;
            if (fly_plain(w, mc, b, held, keep, &cell)) {
                if (b->gcell >= 0 && 2 * cell + b->glist != b->gcell) nt__grid_update(w, i);
                if (sl.on) nt__sleep_note(w, &sl, b, i);
                continue;
            }
            /* (Its forces applied, not resting: on to the speed limit.) */
        } else if (b->type == NT_BODY_DYNAMIC) {
            if (forces) {
                if (b->flags & NT__BF_RESTING) {
                    if (rest_forces(w, mc, b, held_ok)) {
                        if (sl.on) nt__sleep_note(w, &sl, b, i);
                        continue; /* (in the same grid cell, at the same place) */
                    }
                } else {
                    body_forces(w, mc, b);
                }
            } else if (!(b->motion & NT__MF_SOLVED)) {
                /* In no contact of the velocity solve: its forces now (solver_forces). */
                b->v = nt__solve_velocity_g(mc->g, b, dt);
                if (b->ntc) tile_solve(w, b);
            }
            if (at_rest(mc, b)) {
                rest_again(b);
                if (sl.on) nt__sleep_note(w, &sl, b, i);
                continue; /* (in the same grid cell, at the same place) */
            }
        }
        nt_real sp2 = nt__dot(b->v, b->v);
        int limited = 1;
        if (!(sp2 <= NT_REAL_MAX)) b->v = nt__clamp_overflow(b->v, maxd / dt);
        else if (sp2 > vmax2) b->v = nt__scale(b->v, maxd / (nt__sqrt(sp2) * dt));
        else limited = 0;
        int32_t cell = -1;
        if (b->type == NT_BODY_KINEMATIC) {
            /* A character was moved by nt_character_move: its velocity, that move's,
             * has served the contacts; it does not carry over to the next step. */
            if (w->char_count && w->cold[i].character >= 0) {
                b->v = nt_v2(0, 0);
            } else {
                b->p.x += b->v.x * dt;
                b->p.y += b->v.y * dt;
            }
        } else if ((plain && !limited) || !fly_free(w, mc, b, !limited, &cell)) {
            /* (A plain body the speed limit leaves alone has had fly_free's answer from
             * fly_plain: no.) */
            moves += move_dynamic(w, mc, i, !limited) - 1;
            if ((b->motion & (NT__MF_MET | NT__MF_SOLVED)) == (NT__MF_MET | NT__MF_SOLVED)) w->kicked_count++;
            b->motion &= (uint8_t)~NT__MF_SOLVED; /* (fly_free and rest_again clear it too) */
        }
        /* Open air told the cell: the grid's list changes only when the cell did. */
        if (b->gcell >= 0 && (cell < 0 || 2 * cell + b->glist != b->gcell)) nt__grid_update(w, i);
        if (sl.on) nt__sleep_note(w, &sl, b, i);
    }
    w->counters.substep_count = moves;
    sleep->sleepers = sl.sleepers;
}

/* ---------------------------------------------------------------- the step */

nt_status nt__step(nt_world *w, nt_real dt)
{
    /* t[0] start, t[1] pairs found (set by collide), then the end of each phase. */
    double t[7] = {0};
    if (w->profiling) t[0] = clock_ms();
    w->pairs_ms = 0;
    w->kicked_count = 0;
    w->counters.tile_resolutions = 0;
    w->counters.bodies_held = 0;
    /* The last step's marks for the correction, off (their slots may have moved). */
    if (w->marks_span > 0) memset(w->move_marks, 0, (size_t)((w->marks_span + 63) / 64) * sizeof *w->move_marks);
    nt_status s = collide(w, dt);
    w->marks_span = w->awake_count; /* (the step only appends to the awake bodies) */
    if (s != NT_OK) {
        clear_move_marks(w); /* the pair search may have marked fast bodies: a failed step leaves no trace */
        return s;
    }
    if (w->profiling) t[2] = clock_ms();
    nt_real ratio = w->prev_dt > 0 ? dt / w->prev_dt : 1;
    w->leveled = 0;
    w->level_count = 0;
    if (w->con_count) build_contact_lists(w);
    correct_positions(w);
    if (w->profiling) t[3] = clock_ms();
    /* Without body contacts the velocity phase is only each body's own forces: they
     * are applied in the move's pass. */
    int forces = w->con_count == 0;
    if (!forces) solve_velocities(w, dt, ratio);
    if (w->profiling) t[4] = clock_ms();
    nt__sleep_pass sl = nt__sleep_pass_of(w, dt);
    move_bodies(w, dt, forces, &sl);
    /* A body that met a tile in the move, after the velocity solve, may have turned
     * back into a body that kept coming (the lower one of a falling pair bounces off
     * a floor): the pairs around such bodies are corrected once more. */
    if (w->kicked_count) correct_after_move(w);
    if (w->profiling) t[5] = clock_ms();
    nt__update_sleep(w, &sl);
    if (w->profiling) {
        t[6] = clock_ms();
        t[1] = w->pairs_ms;
        nt_world_profile *p = &w->profile;
        p->pairs = phase_ms(t[0], t[1]);
        p->contacts = phase_ms(t[1], t[2]);
        p->correct = phase_ms(t[2], t[3]);
        p->solve = phase_ms(t[3], t[4]);
        p->move = phase_ms(t[4], t[5]);
        p->sleep = phase_ms(t[5], t[6]);
        p->step = p->pairs + p->contacts + p->correct + p->solve + p->move + p->sleep;
    }
    w->prev_dt = dt;
    w->counters.body_count = w->body_count;
    w->counters.awake_count = w->awake_count;
    w->counters.contact_count = w->con_count;
    return NT_OK;
}
