/* The world simulation's internals: body, contact and world layouts, and the
 * functions world.c, response.c, grid.c, sleep.c, cast.c and character.c share. Not
 * installed. */
#ifndef NT_SIMULATION_H
#define NT_SIMULATION_H

#include <stddef.h>
#include "core_internal.h"
#include "ntile/world.h" /* public: outside the hidden region */

#if defined(__GNUC__)
#pragma GCC visibility push(hidden) /* internal, as above */
#endif

enum {
    NT__BF_SENSOR = 1,     /* is_sensor */
    NT__BF_SLEEP_OK = 2,   /* enable_sleep */
    NT__BF_HITS = 4,       /* enable_hit_events */
    NT__BF_ALIVE = 8,
    NT__BF_MARK = 16,      /* scratch mark within one phase of a step */
    NT__BF_MOVED = 32,     /* scratch: moved by position correction */
    NT__BF_RESTING = 64,   /* rest_p is a fixed point of the tile resolution (see move_dynamic) */
    NT__BF_LARGE = 128     /* above half a cell: grid level >= 1, tiles met over many cells */
};
enum { NT__LIST_ACTIVE = 0, NT__LIST_REST = 1 };
/* nt__body.motion: the velocity solve met the body in its contacts this step and
 * answered its forces then (set from there to the start of its move); the body
 * began the previous step's move with no tile contact (with none now either, it has
 * been in the air for a whole step: its flight is the parabola); from the velocity
 * solve to the move, a time-of-impact shift waits in scratch_r (response.c); the move
 * met a tile surface it had not rested on; the correction after the move must look
 * at the body's pairs (kicked by the solve or fast: in the broad phase too; left
 * closing by the solve: its contacts only; response.c); the move bounced the body
 * off the surface of normal tc[0].n and left it no tile contact (ntc 0; read by the
 * correction after the move only). */
enum {
    NT__MF_SOLVED = 1,
    NT__MF_AIR = 2,
    NT__MF_SHIFT = 4,
    NT__MF_MET = 8,
    NT__MF_KICKED = 16,
    NT__MF_RECHECK = 32,
    NT__MF_BOUNCED = 64,
    NT__MF_HELD = 128 /* at rest, its forces stopped exactly by its tile contacts (move_bodies) */
};
/* Contact flags: which side is a sensor; touching = overlapping or closer than the
 * skin (else a near contact, solved but not reported). */
enum { NT__CF_SENSOR_A = 1, NT__CF_SENSOR_B = 2, NT__CF_SENSOR = 3, NT__CF_TOUCH = 4, NT__CF_GONE = 8 /* parked slot emptied */, NT__CF_BOUNCED = 16,
       NT__CF_IMPACT = 32 /* this step: an elastic pair answered by bounce_pass (response.c) */ };
/* Broad-phase levels: level 0 is N's grid (bodies up to half a cell), level k holds
 * bodies up to 2^(k-1) cells in cells 2^k wide, up to NT_MAX_HALF_CELLS. */
#define NT__LEVELS 4
/* Body pairs closer than this (in cells) are solved, so that resting contacts never
 * come and go; only overlapping ones count as touching (events, sensors). */
#define NT__CONTACT_MARGIN ((nt_real)0.05)

/* A tile surface a body touches; kept between steps for the resting-contact solve. */
typedef struct nt__tile_ct {
    nt_vec2 n;          /* unit normal, out of the tile */
    nt_real depth;      /* at detection, world units */
    nt_real lambda;     /* normal velocity change applied this step */
    int32_t cx, cy;     /* the tile's cell */
    uint8_t material;
    uint8_t solved;     /* friction already applied for this surface this step */
} nt__tile_ct;

/* An awake body of the broad phase, in a compact array sorted by cell each step so
 * that neighbours are met in memory order. */
typedef struct nt__proxy {
    nt_vec2 lo, hi;            /* box grown by everything the exact pair test may allow */
    uint32_t key;              /* y * (grid_w + 1) + x: rows padded by an empty column */
    uint32_t cell;             /* y * grid_w + x */
    int32_t body;
} nt__proxy;

/* Hot per-body state. Cold data (user pointer, creation order) is in nt__body_cold.
 * What the pair search, the contact passes and the move read of most bodies
 * (position, size, velocity, type and flags, the move's marks, generation, awake slot,
 * inverse mass, material, grid cell) comes first, in the first 68 bytes of float
 * builds; the tile contacts, read by them only for bodies resting on tiles, come last. */
typedef struct nt__body {
    nt_vec2 p, half, v;
    int32_t gnext;             /* broad phase: next body in the cell's list */
    uint32_t category, mask;
    uint8_t type, shape, flags, ntc;
    /* (Next to type..ntc: the move tests these eight bytes as one word, plain_body.) */
    uint8_t glist;             /* NT__LIST_* */
    uint8_t level;             /* broad-phase level: 0 up to half a cell, k: up to 2^(k-1) cells (grid.c) */
    uint8_t one_way;           /* is_one_way: contacts only from above (grid.c), casts likewise (cast.c) */
    uint8_t motion;            /* NT__MF_*: how the move of this step integrates (response.c) */
    uint32_t generation;
    int32_t awake_slot;        /* index in world->awake, -1 when not simulated */
    nt_real inv_mass, friction, bounce;
    int32_t gcell;             /* broad phase: list head index (-1 = not in the grid) */
    /* The rest: integration, sleep, the broad phase's list link, tile contacts. */
    int32_t gprev;             /* broad phase: previous body in the cell's list */
    nt_real gravity_scale, drag, sleep_time;
    int32_t sleep_next;        /* circular list of a sleeping group; -1 otherwise; free list when dead */
    uint32_t rest_epoch;       /* map_epoch when rest_p was resolved */
    nt_vec2 rest_p;
    nt__tile_ct tc[2];
} nt__body;
_Static_assert(offsetof(nt__body, motion) == offsetof(nt__body, type) + 7, "type to motion: eight bytes in a row");

typedef struct nt__body_cold {
    void *user_data;
    nt_real mass;
    int32_t cprev, cnext;      /* creation order */
    int32_t park_head;         /* first parked slot naming this body (nt__plink chain), -1: none */
    int32_t character;         /* index in world->chars, -1: not a character */
} nt__body_cold;

/* A character (character.c): a body the game moves with nt_character_move. */
typedef struct nt__character {
    int32_t body;
    uint8_t type;              /* the body's own type (dynamic or kinematic); the step sees kinematic */
    uint8_t on_floor, dropping;
    uint8_t free_checked;      /* free_p was found free of the tiles with the tiles of free_epoch */
    int32_t floor_body;        /* the body stood on at the last move, -1: a tile or none */
    uint32_t free_epoch;
    nt_vec2 free_p;
    nt_real floor_cos;         /* cos(def.floor_angle) */
    nt_real floor_tan;         /* tan(def.floor_angle), at most 16: how far the steepest floor falls per unit across */
    uint32_t floor_gen;
    nt_character_def def;
    /* The last move, kept when it left the character as it found it (a fixed point:
     * standing still, wedged): the same input in the same world is the same move, so
     * nt_character_move answers it from here. rep_valid is cleared by a new def. */
    uint8_t rep_valid;
    uint32_t rep_epoch;        /* map_epoch of that move */
    uint32_t rep_mask;         /* the body's mask then */
    nt_vec2 rep_velocity;      /* its velocity (after the speed limit), bit for bit */
    nt_real rep_dt;
    nt_vec2 rep_bv;            /* the body velocity it set */
    nt_real rep_reach;         /* how far beyond its box its queries for bodies looked */
    nt_character_result rep_r; /* its result (rep_r.position: where it found and left it) */
} nt__character;

/* A parked slot's place in the chains of its two bodies (next[0]: body a's, next[1]: b's). */
typedef struct nt__plink {
    int32_t next[2];
} nt__plink;

/* The velocity solver's copy of a body in a contact (compact, so that the
 * iterations stay in cache however many bodies the world holds). */
typedef struct nt__svel {
    nt_vec2 v;
    nt_real w;                 /* inverse mass as the solver sees it (0: does not move) */
} nt__svel;

/* A solver body's tile contacts as one-sided constraints (see solve_tile_pair, response.c). */
typedef struct nt__stile {
    uint32_t s;                /* its nt__svel, as an offset in nt_reals (solve_tile_blocks) */
    int32_t ntc;               /* its tile contact count (1 or 2) */
    nt_vec2 n[2];
    nt_real lambda[2];
    int32_t body;
} nt__stile;

/* What the pair search finds of a contact (con_new): the fields it sets, half a
 * contact's bytes, since every new contact is written, sorted and read again each step.
 * collide makes the contact from it (the other fields zero). */
typedef struct nt__pair {
    uint64_t key;              /* (a << 32) | b */
    uint32_t gen_a, gen_b;
    nt_vec2 n;                 /* from a towards b */
    nt_real depth;
    uint32_t flags;            /* NT__CF_SENSOR_A, NT__CF_SENSOR_B, NT__CF_TOUCH */
} nt__pair;

/* A body pair whose shapes overlap (or a sensor and a visitor). a < b by slot. */
typedef struct nt__contact {
    uint64_t key;              /* (a << 32) | b */
    uint32_t gen_a, gen_b;
    nt_vec2 n;                 /* from a towards b */
    nt_real depth;
    nt_real ln, lt;            /* accumulated normal / tangent impulses (warm start) */
    nt_real friction, bounce, bias, meff;
    uint32_t flags;
    int32_t sa, sb;            /* the velocity solver's nt__svel of a and b, this step */
} nt__contact;

struct nt_world {
    nt_map *map;               /* every tile */
    nt_map *solid;             /* the tiles minus one-way cells; NULL while no cell is one-way */
    uint8_t *cell_mat, *cell_flags; /* per cell; NULL until first set */
    int oneway_count;
    nt_material materials[NT_MAX_MATERIALS];
    nt_world_def def;
    nt_real cell, inv_cell, prev_dt;
    nt_real floor_cos;         /* cos(def.floor_angle): the tile-contact summary's floor test */

    nt__body *bodies;
    nt__body_cold *cold;
    int32_t *awake;            /* simulated bodies (awake dynamic + kinematic) */
    int32_t *scratch_a;        /* per-body scratch (union-find, lists) */
    nt_real *scratch_r;        /* 2 per body */
    int32_t *sleep_parent;     /* per body: the sleep islands' union-find (nt__sleep_note, sleep.c) */
    nt_real *sleep_tmin;       /* per body: the least rest time of its island while it is a root */
    int body_cap, body_hwm, body_count, awake_count, free_head;
    int32_t first, last;       /* creation order */
    int grid_bodies;           /* bodies in the broad phase */
    int grid_rest;             /* of which in REST lists */
    uint32_t grid_cat, grid_mask; /* union of their categories and masks (never shrinks) */

    int32_t *heads;            /* broad phase: 2 list heads per cell; NULL until needed */
    uint64_t *occupied;        /* bit per list head: the list is not empty (L1-sized, read first) */
    uint32_t *rest_near;       /* per cell: REST-list bodies in the 3 x 3 cells around it */
    nt__proxy *prox, *prox_tmp; /* awake grid bodies sorted by cell, rebuilt each step */
    int prox_cap;
    nt_real pair_margin, pair_dt; /* the pair search's base margin and step (grid.c) */
    uint32_t tag;              /* names the world in its body handles (nt_body_id.world0) */
    uint32_t map_epoch;        /* bumped by every change of tiles, cell flags or cell materials */
    uint32_t force_epoch;      /* bumped when the world's gravity changes (NT__MF_HELD) */
    uint32_t held_epoch;       /* force_epoch at the last move */
    uint32_t *radix;           /* 2 x 8192 counters of the proxies' radix sort */
    int grid_w, grid_h;
    /* Coarser loose-grid levels 1..NT__LEVELS-1 for bodies above half a cell (grid.c):
     * level k has cells 2^k map cells wide, 2 list heads each, all levels in one
     * array from lbase[k]; NULL until the first such body enters the grid. */
    int32_t *lheads;
    uint64_t *loccupied;       /* bit per list head of lheads: the list is not empty */
    int lbase[NT__LEVELS], lw[NT__LEVELS], lh[NT__LEVELS];
    int lcount[NT__LEVELS][2]; /* bodies per level and list */
    int large_count;           /* bodies above half a cell in the grid (all levels >= 1) */
    int one_way_bodies;        /* live bodies with is_one_way (the pair test asks only then) */
    nt__character *chars;      /* characters (character.c) */
    uint64_t char_repeats;     /* character moves answered from the last move (character.c; for the tests) */
    int char_count, char_cap;

    nt__contact *con, *con_tmp, *parked;
    nt__pair *con_new;         /* this step's pairs (nt__grid_find_pairs), in the order found */
    uint64_t *sort_keys;       /* 2 x 2 per new contact: (key, index) records of the radix sort */
    int sort_cap;
    int con_count, con_new_count, parked_count;
    int con_cap, con_new_cap, con_tmp_cap, parked_cap;
    int pairs_over; /* the last pair search stopped at NT_MAX_CONTACTS */
    int locked;     /* > 0 while a draw or query callback runs: mutating calls get NT_ERR_LOCKED */
    /* Parked contacts (both bodies asleep or static) keep their slots until the array
     * is compacted; each body chains the slots that name it (nt__body_cold.park_head),
     * so waking a group costs its own contacts, not every parked one. */
    nt__plink *park_link;      /* per parked slot */
    int32_t *park_pick;        /* per parked slot: scratch of nt__unpark */
    int park_link_cap, park_pick_cap, parked_live;
    int32_t *woken;            /* bodies woken since the last unpark (capacity body_cap) */
    int woken_count, woken_lost; /* lost: more than fit; the next unpark scans every slot */
    int con_dirty;             /* con not sorted by key: only its first con_sorted are */
    int con_sorted;

    nt_contact_begin_event *ev_begin;
    nt_contact_end_event *ev_end;
    nt_hit_event *ev_hit;
    nt_sensor_event *ev_sbegin, *ev_send;
    int n_begin, n_end, n_hit, n_sbegin, n_send;
    int cap_begin, cap_end, cap_hit, cap_sbegin, cap_send;

    int32_t *wake_list;        /* bodies to wake after pair finding (capacity body_cap) */
    uint64_t *move_marks;      /* a bit per awake slot: marked for the correction after the move (nt__mark_move) */
    int marks_span;            /* awake slots the last step may have marked */
    nt__svel *svel;            /* the velocity solver's compact bodies (capacity body_cap) */
    nt__stile *stile;          /* the velocity solver's tile contacts (capacity body_cap) */
    int32_t *level;            /* per body: contacts from the ground, this step's solve; then the
                                * correction after the move's queue (response.c) */
    int32_t *level_q;          /* 3 per body: contact list starts and ends, bodies by level (response.c) */
    int32_t *adj;              /* 2 per contact: the bodies' contact lists */
    int adj_cap;
    int leveled, level_count;  /* level[] held this step's levels (until the move); bodies with one */
    int kicked_count;          /* bodies marked NT__MF_KICKED this step */
    int wake_count;
    nt_world_counters counters;
    int profiling;
    nt_world_profile profile;  /* of the last step, while profiling */
    double pairs_ms;           /* clock when collide had found the pairs (profiling) */
};

/* The skin near the origin: no skin is thinner. */
static inline nt_real nt__skin_base(const nt_world *w) { return w->cell * (nt_real)2.5e-4; }
/* Contacts are left overlapping by this skin, so that a resting contact is found
 * again next step: 2.5e-4 cell, or one unit in the last place of the coordinates
 * where that is more (far from the origin in float: the resolution is exact there,
 * but the position it moves the body to rounds by half a unit per axis, so the skin
 * must exceed 0.71 unit for the body to stay in contact). Constant over each binade,
 * so that a body sliding along a floor does not sink as its x grows. */
static inline nt_real nt__skin(const nt_world *w, nt_vec2 p)
{
    nt_real mag = nt__max(nt__fabs(p.x), nt__fabs(p.y));
    nt_real base = nt__skin_base(w);
    if (mag * NT_REAL_EPS <= base) return base;
    /* The unit in the last place of the binade holding mag: 2^(e - 1) * eps with
     * mag = f * 2^e, f in [0.5, 1), built from mag's exponent field E (e = E - bias
     * + 1) instead of frexp and ldexp, which are library calls (this runs for every
     * body resolved far from the origin). Tiny magnitudes (a tiny cell size) take
     * the calls. */
    nt_real ulp;
#if NT_REAL_IS_DOUBLE
    uint64_t bits;
    memcpy(&bits, &mag, sizeof bits);
    if ((bits >> 52) >= 2047) return nt__max(base, mag); /* not finite: no ilogb(inf) */
    if ((bits >> 52) <= 52) return nt__max(base, (nt_real)ldexp(NT_REAL_EPS, ilogb(mag)));
    bits = ((bits >> 52) - 52) << 52;
#else
    uint32_t bits;
    memcpy(&bits, &mag, sizeof bits);
    if ((bits >> 23) >= 255) return nt__max(base, mag); /* not finite: no ilogb(inf) */
    if ((bits >> 23) <= 23) return nt__max(base, (nt_real)ldexp((double)NT_REAL_EPS, ilogb(mag)));
    bits = ((bits >> 23) - 23) << 23;
#endif
    memcpy(&ulp, &bits, sizeof ulp);
    return nt__max(base, ulp);
}

/* floor() to int without a libm call, for the hot paths; clamped like nt__floor_int. */
static inline int nt__ifloor(nt_real v) { return nt__floor_int(v); }

/* A cell's flags (NT_CELL_ONE_WAY, ...): 0 outside the map or when none were set. */
static inline uint32_t nt__cell_flags(const nt_world *w, int x, int y)
{
    if (!w->cell_flags || x < 0 || y < 0 || x >= w->map->w || y >= w->map->h) return 0;
    return w->cell_flags[(size_t)y * (size_t)w->map->w + (size_t)x];
}

/* sleep.c: the awake list, sleeping groups and parked contacts */
void nt__awake_add(nt_world *w, int32_t i);     /* join the awake list */
void nt__awake_remove(nt_world *w, int32_t i);  /* leave it (no-op when not in it) */
void nt__note_woken(nt_world *w, int32_t i);    /* i woke or died: its parked contacts go back at the next unpark */
void nt__wake(nt_world *w, int32_t i);          /* wake i's sleeping group, restore its contacts */
void nt__wake_group(nt_world *w, int32_t i);    /* the same without restoring contacts */
void nt__wake_all(nt_world *w);                 /* every dynamic body (gravity changed) */
void nt__wake_near_cells(nt_world *w, int x0, int y0, int x1, int y1); /* bodies near changed cells, their tile contacts dropped */
void nt__wake_partners(nt_world *w, int32_t i); /* every body in contact with i (listed or parked) */
void nt__unpark(nt_world *w);                   /* move parked contacts of woken (or dead) bodies back */
void nt__park(nt_world *w, const nt__contact *c); /* set a contact aside (room reserved by the caller) */
void nt__compact_parked(nt_world *w);           /* drop the parked slots emptied by nt__unpark */
void nt__sleep_body(nt_world *w, int32_t i);    /* leave the simulation (caller links the group) */
/* Sleep bookkeeping done in the move's pass over the awake bodies, while each body's
 * record is in cache (nt__sleep_note after its move), for nt__update_sleep: how long
 * each has rested, whether any has rested long enough, and for a step with body
 * contacts (islands) each body's union-find start. */
typedef struct nt__sleep_pass {
    nt_real v2max, dt, limit;
    int on, islands, sleepers;
} nt__sleep_pass;
static inline nt__sleep_pass nt__sleep_pass_of(const nt_world *w, nt_real dt)
{
    nt__sleep_pass s;
    s.v2max = w->def.sleep_speed * w->def.sleep_speed;
    s.dt = dt;
    s.limit = w->def.sleep_time;
    s.on = w->def.enable_sleep;
    s.islands = w->con_count > 0; /* without body contacts every body is an island of its own */
    s.sleepers = 0;
    return s;
}
/* (Called only with s->on.) */
static inline void nt__sleep_note(nt_world *w, nt__sleep_pass *s, nt__body *b, int32_t i)
{
    if (b->type != NT_BODY_DYNAMIC) {
        if (s->islands) w->sleep_parent[i] = -1;
        return;
    }
    if (!(b->flags & NT__BF_SLEEP_OK) || nt__dot(b->v, b->v) > s->v2max) b->sleep_time = 0;
    else b->sleep_time += s->dt;
    if (b->sleep_time >= s->limit) s->sleepers++;
    if (s->islands) {
        w->sleep_parent[i] = i;
        w->sleep_tmin[i] = b->sleep_time;
    }
}
void nt__update_sleep(nt_world *w, const nt__sleep_pass *s); /* the end of a step: groups that rested long enough sleep */

/* The velocity body b enters this step's contact solve with (dt the step): awake
 * dynamic bodies get gravity and drag (response.c), the others keep theirs. The pair
 * search predicts with it whether a gap closes this step, which must be the solve's
 * own answer: the same arithmetic. */
static inline nt_vec2 nt__solve_velocity_g(nt_vec2 gravity, const nt__body *b, nt_real dt)
{
    nt_vec2 v = b->v;
    if (b->type != NT_BODY_DYNAMIC || b->awake_slot < 0) return v;
    v.x += gravity.x * b->gravity_scale * dt;
    v.y += gravity.y * b->gravity_scale * dt;
    if (b->drag > 0) {
        nt_real f = 1 / (1 + b->drag * dt);
        v.x *= f;
        v.y *= f;
    }
    return v;
}
static inline nt_vec2 nt__solve_velocity(const nt_world *w, const nt__body *b, nt_real dt)
{
    return nt__solve_velocity_g(w->def.gravity, b, dt);
}
/* Mark body b for the correction after the move (flag: NT__MF_KICKED, NT__MF_RECHECK
 * or NT__MF_MET) and note its awake slot, so that the correction visits the marked
 * bodies in awake order without reading every body (response.c). Slots do not move
 * from the pair search to the correction: bodies are only woken (appended) then. */
static inline void nt__mark_move(nt_world *w, nt__body *b, unsigned flag)
{
    b->motion |= (uint8_t)flag;
    if (b->awake_slot >= 0) w->move_marks[(uint32_t)b->awake_slot >> 6] |= (uint64_t)1 << (b->awake_slot & 63);
}
static inline bool nt__body_in_grid(const nt__body *b) { return b->mask != 0 && b->category != 0; }
static inline nt_shape nt__body_shape(const nt__body *b)
{
    nt_shape s;
    s.type = (nt_shape_type)b->shape;
    s.half = b->half;
    return s;
}

/* world.c, for characters */
void nt__set_kinematic(nt_world *w, int32_t i, bool kinematic); /* the step's view of a character's type */
void nt__character_remove(nt_world *w, int32_t i); /* the body stops being a character (destroyed) */
nt_body_type nt__character_type(const nt_world *w, int32_t i); /* a body's own type */

/* grid.c */
int nt__grid_level(const nt_world *w, nt_vec2 half); /* the level a body of this size sits in */
nt_status nt__grid_enable(nt_world *w, int level); /* room for bodies of this level (before insert) */
void nt__grid_insert(nt_world *w, int32_t i);
void nt__grid_remove(nt_world *w, int32_t i);
void nt__grid_update(nt_world *w, int32_t i);   /* after the body moved or changed list */
nt_status nt__grid_find_pairs(nt_world *w, nt_real dt); /* fills con_new; may grow it */
typedef bool nt__visit_fn(const nt_world *w, int32_t i, void *ctx);
void nt__grid_visit(const nt_world *w, nt_vec2 lo, nt_vec2 hi, nt__visit_fn *fn, void *ctx);
/* The bodies of the grid whose boxes overlap body i's (i left out), at most cap of
 * them in out; returns how many. */
int nt__grid_overlapping(const nt_world *w, int32_t i, int32_t *out, int cap);
/* A level's list heads (2 per cell: ACTIVE, REST), its size in cells and its cell width. */
void nt__grid_level_view(const nt_world *w, int level, const int32_t **heads, int *gw, int *gh, nt_real *size);
int nt__grid_level_used(const nt_world *w, int level); /* any body in it (level 0: grid enabled) */
bool nt__pair_filter(const nt__body *a, const nt__body *b);
void nt__box_axis(const nt__body *a, const nt__body *b, nt_mtv *m); /* box pair: the axis they met on */

/* response.c */
nt_status nt__step(nt_world *w, nt_real dt);

/* cast.c: a shape a cast accepts (box or circle, half-sizes in (0, NT_MAX_HALF_CELLS
 * cells]); nt_world_cast_shape with the filter by pointer, and shape_known when the
 * caller checked the shape (the character mover, once a move). */
static inline int nt__cast_shape_ok(nt_shape s, nt_real cell)
{
    nt_real cap = cell * (nt_real)NT_MAX_HALF_CELLS;
    if (s.type != NT_SHAPE_AABB && s.type != NT_SHAPE_CIRCLE) return 0;
    if (!nt__finite(s.half.x) || !nt__finite(s.half.y)) return 0;
    if (!(s.half.x > 0 && s.half.y > 0 && s.half.x <= cap && s.half.y <= cap)) return 0;
    return s.type != NT_SHAPE_CIRCLE || s.half.x == s.half.y;
}
/* The tiles' start overlaps of a cast (cell units), for the next cast from the same
 * place in the same world with the same filter (start_tiles in cast.c). valid = 0:
 * none kept. */
#define NT__CAST_START_MAX 8
typedef struct nt__cast_start {
    int valid;
    nt_vec2 p0, half; /* where and what was scanned */
    nt_vec2 pos;      /* p0 in world units (start_push_depth's corner case resolves there) */
    int n;
    struct {
        nt_real depth;
        nt_vec2 n;
        int x, y, tile;
    } e[NT__CAST_START_MAX]; /* the overlaps that count, in scan order */
} nt__cast_start;
/* out must not be NULL; start: NULL, or kept by the caller for one world state and
 * one filter. */
bool nt__world_cast_shape(const nt_world *world, nt_vec2 pos, const nt_shape *shape, nt_vec2 translation,
                          const nt_query_filter *filter, int shape_known, nt__cast_start *start, nt_world_shape_hit *out);

/* world.c: does a query with this filter see body i (sensors, mask, ignore list, callback)? */
bool nt__query_sees(const nt_world *w, int32_t i, const nt_query_filter *f);

/* Bodies a, b (slots ia < ib) at the very same place have no way apart of their own:
 * each pair takes one of the four axis directions by its slots (n from a to b), so that
 * a heap of them created at one point bursts apart rather than stacking along one
 * line; the depth is their overlap along it (grid.c: contacts; response.c: position
 * correction). */
static inline void nt__coincident(const nt__body *a, const nt__body *b, int32_t ia, int32_t ib, nt_vec2 *n,
                                  nt_real *depth)
{
    static const signed char dirs[4][2] = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}};
    uint32_t k = ((uint32_t)ia * 2654435761u ^ (uint32_t)ib * 40503u) >> 7;
    *n = nt_v2((nt_real)dirs[k & 3][0], (nt_real)dirs[k & 3][1]);
    *depth = n->x != 0 ? a->half.x + b->half.x : a->half.y + b->half.y;
}

/* Both bodies of a contact are still the ones it was made for. */
static inline int nt__contact_is_live(const nt_world *w, const nt__contact *c)
{
    const nt__body *a = &w->bodies[(int32_t)(c->key >> 32)], *b = &w->bodies[(int32_t)(c->key & 0xffffffffu)];
    return (a->flags & NT__BF_ALIVE) && (b->flags & NT__BF_ALIVE) && a->generation == c->gen_a &&
           b->generation == c->gen_b;
}

#if defined(__GNUC__)
#pragma GCC visibility pop
#endif

#endif /* NT_SIMULATION_H */
