/* Sleeping groups: the awake list, waking a group (and the bodies near changed tiles,
 * or every body), putting bodies to sleep at the end of a step (groups joined by their
 * contacts that rested long enough), and the contacts parked while both their bodies
 * sleep, which go back to the contact list when one wakes. Used by the step
 * (response.c) and the world's edits (world.c); calls only the broad phase (grid.c). */
#include <stdlib.h>
#include <string.h>
#include "simulation.h"

static inline int32_t key_a(uint64_t k) { return (int32_t)(k >> 32); }
static inline int32_t key_b(uint64_t k) { return (int32_t)(k & 0xffffffffu); }

/* ---------------------------------------------------------------- sleeping groups */

void nt__awake_add(nt_world *w, int32_t i)
{
    w->bodies[i].awake_slot = w->awake_count;
    w->awake[w->awake_count++] = i;
}

void nt__awake_remove(nt_world *w, int32_t i)
{
    int32_t slot = w->bodies[i].awake_slot;
    if (slot < 0) return;
    int32_t last = w->awake[--w->awake_count];
    w->awake[slot] = last;
    w->bodies[last].awake_slot = slot;
    w->bodies[i].awake_slot = -1;
}

/* Record body i (woken, or destroyed) for the next nt__unpark, which walks its chain. */
void nt__note_woken(nt_world *w, int32_t i)
{
    if (w->woken_count < w->body_cap) w->woken[w->woken_count++] = i;
    else w->woken_lost = 1; /* the next unpark scans every slot */
}

void nt__wake_group(nt_world *w, int32_t i)
{
    nt__body *b = &w->bodies[i];
    if (!(b->flags & NT__BF_ALIVE) || b->type != NT_BODY_DYNAMIC || b->awake_slot >= 0) return;
    int32_t j = i;
    do {
        nt__body *bj = &w->bodies[j];
        int32_t next = bj->sleep_next;
        bj->sleep_next = -1;
        bj->sleep_time = 0;
        nt__awake_add(w, j);
        nt__note_woken(w, j);
        if (bj->gcell >= 0) {
            bj->glist = NT__LIST_ACTIVE;
            nt__grid_update(w, j);
        }
        j = next;
    } while (j >= 0 && j != i);
}

void nt__sleep_body(nt_world *w, int32_t i)
{
    nt__body *b = &w->bodies[i];
    nt__awake_remove(w, i);
    b->v = nt_v2(0, 0);
    b->motion &= (uint8_t)~NT__MF_HELD; /* the world may change while it sleeps */
    b->sleep_time = 0;
    if (b->gcell >= 0) {
        b->glist = NT__LIST_REST;
        nt__grid_update(w, i);
    }
}

static int contact_live_awake(const nt_world *w, const nt__contact *c)
{
    int32_t a = (int32_t)(c->key >> 32), b = (int32_t)(c->key & 0xffffffffu);
    const nt__body *ba = &w->bodies[a], *bb = &w->bodies[b];
    if (!(ba->flags & NT__BF_ALIVE) || !(bb->flags & NT__BF_ALIVE) || ba->generation != c->gen_a ||
        bb->generation != c->gen_b)
        return 1; /* dead: must go back to produce its end event */
    return ba->awake_slot >= 0 || bb->awake_slot >= 0;
}

/* Chain parked slot k into the lists of its two bodies. */
static void park_link(nt_world *w, int k)
{
    const nt__contact *c = &w->parked[k];
    int32_t a = (int32_t)(c->key >> 32), b = (int32_t)(c->key & 0xffffffffu);
    w->park_link[k].next[0] = w->cold[a].park_head;
    w->cold[a].park_head = k;
    w->park_link[k].next[1] = w->cold[b].park_head;
    w->cold[b].park_head = k;
}

void nt__park(nt_world *w, const nt__contact *c)
{
    /* Room is reserved by the caller: parked_cap and park_link_cap > parked_count. */
    int k = w->parked_count++;
    w->parked[k] = *c;
    w->parked_live++;
    park_link(w, k);
}

/* Parked slot k goes back to the contact list; its slot stays, emptied. */
static void unpark_slot(nt_world *w, int k)
{
    /* Room is guaranteed: con_cap >= con_count + parked_live. */
    if (!w->con_dirty) w->con_sorted = w->con_count; /* the sorted part ends here */
    w->con[w->con_count++] = w->parked[k];
    w->con_dirty = 1;
    w->parked[k].flags |= NT__CF_GONE;
    w->parked_live--;
}

static int cmp_slot(const void *a, const void *b)
{
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return (x > y) - (x < y);
}

/* Drop the emptied slots (keeping the order of the others) and chain the rest anew. */
void nt__compact_parked(nt_world *w)
{
    for (int k = 0; k < w->parked_count; k++) {
        const nt__contact *c = &w->parked[k];
        w->cold[(int32_t)(c->key >> 32)].park_head = -1;
        w->cold[(int32_t)(c->key & 0xffffffffu)].park_head = -1;
    }
    int n = 0;
    for (int k = 0; k < w->parked_count; k++)
        if (!(w->parked[k].flags & NT__CF_GONE)) w->parked[n++] = w->parked[k];
    w->parked_count = w->parked_live = n;
    for (int k = 0; k < n; k++) park_link(w, k);
}

/* Every parked contact with a body awake (or dead) goes back to the contact list.
 * Only the chains of the bodies woken since the last call are walked: a parked
 * contact's bodies were both asleep or static when it was parked, only
 * nt__wake_group wakes a sleeping body (and records it), and a destroyed body is
 * recorded by nt_body_destroy. Every caller of nt__wake_group unparks right after, so
 * the record never holds a body twice (else: woken_lost, and every slot is scanned). */
void nt__unpark(nt_world *w)
{
    if (w->woken_lost) {
        for (int k = 0; k < w->parked_count; k++)
            if (!(w->parked[k].flags & NT__CF_GONE) && contact_live_awake(w, &w->parked[k])) unpark_slot(w, k);
    } else {
        /* The slots to move back, picked from the chains, go back in slot order: the
         * contacts are used in list order until the next step sorts them, so the
         * order must not depend on which chain reached a slot first. */
        int n = 0;
        for (int q = 0; q < w->woken_count; q++) {
            int32_t j = w->woken[q];
            int32_t *link = &w->cold[j].park_head;
            while (*link >= 0) {
                int k = *link;
                nt__contact *c = &w->parked[k];
                int32_t *next = &w->park_link[k].next[(int32_t)(c->key >> 32) == j ? 0 : 1];
                if (!(c->flags & NT__CF_GONE) && !contact_live_awake(w, c)) {
                    link = next; /* stays parked (cannot happen: j is awake or dead) */
                    continue;
                }
                if (!(c->flags & NT__CF_GONE)) {
                    c->flags |= NT__CF_GONE; /* picked; unpark_slot sets it again */
                    w->park_pick[n++] = k;
                }
                *link = *next; /* out of j's chain */
            }
        }
        if (n > 1) qsort(w->park_pick, (size_t)n, sizeof *w->park_pick, cmp_slot);
        for (int q = 0; q < n; q++) {
            w->parked[w->park_pick[q]].flags &= ~(uint32_t)NT__CF_GONE;
            unpark_slot(w, w->park_pick[q]);
        }
    }
    w->woken_count = 0;
    w->woken_lost = 0;
    /* Emptied slots are dropped once they are the majority: amortised O(1) a contact. */
    if (w->parked_count - w->parked_live > w->parked_live && w->parked_count > 64) nt__compact_parked(w);
}

void nt__wake(nt_world *w, int32_t i)
{
    nt__wake_group(w, i);
    nt__unpark(w);
}

void nt__wake_all(nt_world *w)
{
    for (int32_t i = 0; i < w->body_hwm; i++)
        if ((w->bodies[i].flags & NT__BF_ALIVE) && w->bodies[i].type == NT_BODY_DYNAMIC) nt__wake_group(w, i);
    nt__unpark(w);
}

/* Wake the bodies whose box, grown by a cell, meets cells x0..x1, y0..y1, and drop their
 * remembered contacts with those cells (the surface may be gone). */
void nt__wake_near_cells(nt_world *w, int x0, int y0, int x1, int y1)
{
    nt_real c = w->cell;
    nt_real lx = (nt_real)(x0 - 1) * c, ly = (nt_real)(y0 - 1) * c;
    nt_real hx = (nt_real)(x1 + 2) * c, hy = (nt_real)(y1 + 2) * c;
    for (int32_t i = 0; i < w->body_hwm; i++) {
        nt__body *b = &w->bodies[i];
        if (!(b->flags & NT__BF_ALIVE) || b->type != NT_BODY_DYNAMIC) continue;
        if (b->p.x + b->half.x < lx || b->p.x - b->half.x > hx || b->p.y + b->half.y < ly ||
            b->p.y - b->half.y > hy)
            continue;
        nt__wake_group(w, i);
        b->ntc = 0;
    }
    nt__unpark(w);
}

/* Wake the other body of contact c, which names body i. */
static void wake_other(nt_world *w, const nt__contact *c, int32_t i)
{
    int32_t a = (int32_t)(c->key >> 32), b = (int32_t)(c->key & 0xffffffffu);
    if (a == i) nt__wake_group(w, b);
    else if (b == i) nt__wake_group(w, a);
}

/* Wake every body in contact with body i: its listed contacts, then its parked ones
 * through its chain, in slot order (the order a scan of every slot would wake them
 * in, so the awake order does not depend on the chain's). */
void nt__wake_partners(nt_world *w, int32_t i)
{
    for (int k = 0; k < w->con_count; k++) wake_other(w, &w->con[k], i);
    int n = 0;
    for (int32_t k = w->cold[i].park_head; k >= 0;) {
        const nt__contact *c = &w->parked[k];
        if (!(c->flags & NT__CF_GONE)) w->park_pick[n++] = k; /* room: a slot appears once */
        k = w->park_link[k].next[(int32_t)(c->key >> 32) == i ? 0 : 1];
    }
    if (n > 1) qsort(w->park_pick, (size_t)n, sizeof *w->park_pick, cmp_slot);
    for (int q = 0; q < n; q++) wake_other(w, &w->parked[w->park_pick[q]], i);
}

/* ---------------------------------------------------------------- falling asleep */

/* The union-find of nt__update_sleep: parent per body (-1: an awake body that is not
 * dynamic, never joined), and per root the least sleep_time of its set's awake bodies
 * (NT_REAL_MAX for the sleeping ones), kept by the unions so that no later pass reads
 * the bodies' records again. */
static int32_t uf_find(int32_t *parent, int32_t i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

static void uf_union(int32_t *parent, nt_real *tmin, int32_t a, int32_t b)
{
    a = uf_find(parent, a);
    b = uf_find(parent, b);
    if (a == b) return;
    /* The smaller index becomes the root: the result does not depend on the order. */
    if (a > b) {
        int32_t t = a;
        a = b;
        b = t;
    }
    parent[b] = a;
    if (tmin[b] < tmin[a]) tmin[a] = tmin[b];
}

/* Make an asleep body's whole group one union-find set (first time it is seen). */
static void uf_add_sleeping(nt_world *w, int32_t *parent, nt_real *tmin, int32_t i)
{
    nt__body *b = &w->bodies[i];
    if (b->flags & NT__BF_MARK) return;
    int32_t j = i;
    do {
        w->bodies[j].flags |= NT__BF_MARK;
        parent[j] = j;
        tmin[j] = NT_REAL_MAX;
        j = w->bodies[j].sleep_next;
    } while (j >= 0 && j != i);
    j = i;
    do {
        uf_union(parent, tmin, i, j);
        j = w->bodies[j].sleep_next;
    } while (j >= 0 && j != i);
}

/* Clear the marks of body i's group if it has them, adding it to the sleepers if its
 * set sleeps. */
static int take_marked_group(nt_world *w, int32_t *parent, const nt_real *tmin, int32_t *list, int n, int32_t i)
{
    if (!(w->bodies[i].flags & NT__BF_MARK)) return n;
    int sleeps = tmin[uf_find(parent, i)] >= w->def.sleep_time;
    int32_t j = i;
    do {
        w->bodies[j].flags &= (uint8_t)~NT__BF_MARK;
        if (sleeps) list[n++] = j;
        j = w->bodies[j].sleep_next;
    } while (j >= 0 && j != i);
    return n;
}

/* The body records (156 bytes in float builds, a cache miss each in a big world) are
 * not read again here for the rest times: the move noted them (nt__sleep_note). With
 * sleepers, one pass over the contacts reads the records; the later passes read
 * sleep_parent and sleep_tmin (8 bytes a body) and only the sleepers' records. */
void nt__update_sleep(nt_world *w, const nt__sleep_pass *s)
{
    /* Each awake body's rest time is up to date (nt__sleep_note, in the move). */
    if (!s->on || s->sleepers == 0) return;
    int32_t *parent = w->sleep_parent, *seen = w->scratch_a;
    nt_real *tmin = w->sleep_tmin;
    int32_t *list = w->wake_list;
    int n = 0;
    if (!s->islands) {
        /* Every body an island of its own: the sleepers, gathered before sleeping
         * (which reorders the awake array). */
        for (int k = 0; k < w->awake_count; k++) {
            int32_t i = w->awake[k];
            const nt__body *b = &w->bodies[i];
            if (b->type == NT_BODY_DYNAMIC && b->sleep_time >= s->limit) list[n++] = i;
        }
        for (int q = 0; q < n; q++) {
            nt__sleep_body(w, list[q]);
            w->bodies[list[q]].sleep_next = list[q];
        }
        return;
    }
    /* Islands: bodies joined by contacts (through sleeping groups they rest on too).
     * The bodies not awake that contacts name go to `seen`, in the contacts' order,
     * for the sleeping groups below (ns counts them all: above body_cap, `seen`
     * overflowed and the contacts are scanned again instead). */
    int ns = 0;
    for (int k = 0; k < w->con_count; k++) {
        const nt__contact *c = &w->con[k];
        int32_t ia = key_a(c->key), ib = key_b(c->key);
        nt__body *a = &w->bodies[ia], *b = &w->bodies[ib];
        if (a->awake_slot < 0 && ns++ < w->body_cap) seen[ns - 1] = ia;
        if (b->awake_slot < 0 && ns++ < w->body_cap) seen[ns - 1] = ib;
        if (c->flags & NT__CF_SENSOR) continue; /* (within the step every contact is live) */
        /* A moving kinematic body keeps what it touches awake (an awake dynamic body:
         * its set's least sleep_time too). */
        if (a->type == NT_BODY_KINEMATIC && (a->v.x != 0 || a->v.y != 0)) {
            b->sleep_time = 0;
            if (b->type == NT_BODY_DYNAMIC && b->awake_slot >= 0) tmin[uf_find(parent, ib)] = 0;
        }
        if (b->type == NT_BODY_KINEMATIC && (b->v.x != 0 || b->v.y != 0)) {
            a->sleep_time = 0;
            if (a->type == NT_BODY_DYNAMIC && a->awake_slot >= 0) tmin[uf_find(parent, ia)] = 0;
        }
        if (a->type != NT_BODY_DYNAMIC || b->type != NT_BODY_DYNAMIC) continue;
        if (a->awake_slot < 0) uf_add_sleeping(w, parent, tmin, ia);
        if (b->awake_slot < 0) uf_add_sleeping(w, parent, tmin, ib);
        uf_union(parent, tmin, ia, ib);
    }
    /* The awake sleepers, in the awake array's order (their sleep_time is final). */
    n = 0;
    for (int k = 0; k < w->awake_count; k++) {
        int32_t i = w->awake[k];
        if (parent[i] >= 0 && tmin[uf_find(parent, i)] >= w->def.sleep_time) list[n++] = i;
    }
    /* Sleeping groups reached through contacts join the new group, in the order the
     * contacts name them (only bodies not awake are marked). */
    if (ns <= w->body_cap) {
        for (int q = 0; q < ns; q++) n = take_marked_group(w, parent, tmin, list, n, seen[q]);
    } else {
        for (int k = 0; k < w->con_count; k++) {
            n = take_marked_group(w, parent, tmin, list, n, key_a(w->con[k].key));
            n = take_marked_group(w, parent, tmin, list, n, key_b(w->con[k].key));
        }
    }
    /* Each set's circular list, from its first sleeper on (head: `seen` is done). */
    int32_t *head = seen;
    for (int q = 0; q < n; q++) head[uf_find(parent, list[q])] = -1;
    for (int q = 0; q < n; q++) {
        int32_t i = list[q];
        int32_t r = uf_find(parent, i);
        nt__body *b = &w->bodies[i];
        if (b->awake_slot >= 0) nt__sleep_body(w, i);
        if (head[r] < 0) {
            head[r] = i;
            b->sleep_next = i;
        } else {
            b->sleep_next = w->bodies[head[r]].sleep_next;
            w->bodies[head[r]].sleep_next = i;
        }
    }
}

