/* Running a replay: step the game with the recorded inputs, check every fact at the
 * ticks it names, hash every tick, and compare with the recorded hashes and trace.
 * Facts are the main checks of a replay; hashes catch any change at all, and the
 * per-tick trace says at which tick the run first differs. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "internal.h"

typedef struct fact_run {
    bool settled; /* by: became true; always/at: already failed or checked */
    int region;   /* NT_FACT_INSIDE */
    bool bad;     /* could not be evaluated (unknown region or body) */
} fact_run;

typedef struct runner {
    const nt_replay *rp;
    nt_game *g;
    nt_run_report *rep;
    fact_run *fr;
    nt_map *solid;    /* the level's tiles without one-way cells */
    nt_body_id *ids;  /* scratch: live bodies */
    int ids_cap;
    double ke0, p0x, p0y, pscale;
} runner;

static void vmessage(nt_run_report *rep, bool hash, const char *fmt, va_list ap)
{
    if (rep->message_count >= NT_RUN_MAX_MESSAGES) return;
    rep->message_is_hash[rep->message_count] = hash;
    vsnprintf(rep->messages[rep->message_count++], sizeof rep->messages[0], fmt, ap);
}

static void message(nt_run_report *rep, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void message(nt_run_report *rep, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vmessage(rep, false, fmt, ap);
    va_end(ap);
}

static void hash_message(nt_run_report *rep, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void hash_message(nt_run_report *rep, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vmessage(rep, true, fmt, ap);
    va_end(ap);
}

static void fail(nt_run_report *rep)
{
    rep->failure_count++;
    rep->fact_failures++;
}

static void hash_fail(nt_run_report *rep)
{
    rep->failure_count++;
    rep->hash_failures++;
}

/* The fact as written in the replay, for messages. */
static void fact_text(const nt_replay_fact *f, char *buf, size_t cap)
{
    static const char *const kinds[] = {"complete", "alive", "inside", "no-body-in-solid", "score",
                                        "bodies", "spawned", "energy-ratio", "momentum-drift"};
    static const char *const ops[] = {">=", "<=", "=="};
    int n = snprintf(buf, cap, "expect %s%s", f->negate ? "not " : "", kinds[f->kind]);
    if (f->kind == NT_FACT_INSIDE) n += snprintf(buf + n, cap - (size_t)n, " %s%s%s", f->region, f->body[0] ? " body " : "", f->body);
    else if (f->kind >= NT_FACT_SCORE) n += snprintf(buf + n, cap - (size_t)n, " %s %.9g", ops[f->op], f->value);
    if (f->when == NT_WHEN_ALWAYS) snprintf(buf + n, cap - (size_t)n, " always");
    else snprintf(buf + n, cap - (size_t)n, " %s %d", f->when == NT_WHEN_AT ? "at" : "by", f->tick);
}

static int live_bodies(runner *R)
{
    int n = nt_game_get_bodies(R->g, NULL, 0);
    if (n > R->ids_cap) {
        nt_body_id *p = realloc(R->ids, (size_t)n * sizeof *p);
        if (!p) return -1;
        R->ids = p;
        R->ids_cap = n;
    }
    return nt_game_get_bodies(R->g, R->ids, R->ids_cap);
}

/* Kinetic energy and momentum of the dynamic bodies. */
static void mechanics(runner *R, double *ke, double *px, double *py, double *scale)
{
    nt_world *w = nt_game_get_world(R->g);
    int n = live_bodies(R);
    *ke = *px = *py = *scale = 0;
    for (int i = 0; i < n; i++) {
        if (nt_body_get_type(w, R->ids[i]) != NT_BODY_DYNAMIC) continue;
        double m = (double)nt_body_get_mass(w, R->ids[i]);
        nt_vec2 v = nt_body_get_velocity(w, R->ids[i]);
        double vx = (double)v.x, vy = (double)v.y;
        *ke += 0.5 * m * (vx * vx + vy * vy);
        *px += m * vx;
        *py += m * vy;
        *scale += m * sqrt(vx * vx + vy * vy);
    }
}

/* Evaluate a fact now. Returns 1 true, 0 false, -1 cannot be evaluated; `why`
 * describes the value seen. */
static int fact_now(runner *R, const nt_replay_fact *f, fact_run *fr, char *why, size_t cap)
{
    nt_game_state st = nt_game_get_state(R->g);
    nt_world *w = nt_game_get_world(R->g);
    int truth = 0;
    double value = 0;
    switch (f->kind) {
    case NT_FACT_COMPLETE:
        truth = st.complete;
        snprintf(why, cap, "%s", st.complete ? "complete" : "not complete");
        break;
    case NT_FACT_ALIVE:
        truth = st.alive;
        snprintf(why, cap, "%s", !st.has_player ? "the level has no player" : st.alive ? "alive" : "dead");
        break;
    case NT_FACT_INSIDE: {
        nt_body_id id = f->body[0] ? nt_game_find_body(R->g, f->body) : nt_game_get_player(R->g);
        if (nt_body_id_is_null(id)) {
            truth = 0;
            snprintf(why, cap, "%s is gone", f->body[0] ? f->body : "the player");
        } else {
            truth = nt_game_body_in_region(R->g, id, fr->region);
            nt_vec2 p = nt_body_get_position(w, id);
            snprintf(why, cap, "%s at %.6g, %.6g", f->body[0] ? f->body : "the player", (double)p.x, (double)p.y);
        }
        break;
    }
    case NT_FACT_NO_BODY_IN_SOLID: {
        int n = live_bodies(R);
        if (n < 0) return -1;
        nt_real limit = R->g->cell * (nt_real)1e-3;
        truth = 1;
        snprintf(why, cap, "no body inside solid");
        for (int i = 0; i < n; i++) {
            if (nt_body_get_type(w, R->ids[i]) != NT_BODY_DYNAMIC) continue;
            nt_vec2 p = nt_body_get_position(w, R->ids[i]);
            nt_real d = nt_map_overlap_depth(R->solid, p, nt_body_get_shape(w, R->ids[i]));
            if (d > limit) {
                const game_body *b = nt__game_record(R->g, R->ids[i]);
                const char *name = b && b->source == GB_PLAYER ? "the player"
                                   : b && b->level_body >= 0  ? R->g->level->bodies[b->level_body].name
                                                              : "a body";
                snprintf(why, cap, "%s at %.6g, %.6g is %.3g cells inside solid", name, (double)p.x, (double)p.y,
                         (double)(d / R->g->cell));
                truth = 0;
                break;
            }
        }
        break;
    }
    case NT_FACT_SCORE: value = st.score; snprintf(why, cap, "score is %d", st.score); break;
    case NT_FACT_BODIES: value = nt_world_get_body_count(w); snprintf(why, cap, "%d bodies", nt_world_get_body_count(w)); break;
    case NT_FACT_SPAWNED: value = st.spawned; snprintf(why, cap, "%d spawned", st.spawned); break;
    case NT_FACT_ENERGY_RATIO: {
        double ke, px, py, sc;
        mechanics(R, &ke, &px, &py, &sc);
        if (R->ke0 <= 0) {
            snprintf(why, cap, "the kinetic energy at tick 0 is zero");
            return -1;
        }
        value = ke / R->ke0;
        snprintf(why, cap, "energy ratio is %.9g", value);
        break;
    }
    case NT_FACT_MOMENTUM_DRIFT: {
        double ke, px, py, sc;
        mechanics(R, &ke, &px, &py, &sc);
        double dx = px - R->p0x, dy = py - R->p0y, d = sqrt(dx * dx + dy * dy);
        value = R->pscale > 0 ? d / R->pscale : (d > 0 ? INFINITY : 0);
        snprintf(why, cap, "momentum drift is %.9g (momentum %.9g, %.9g; at tick 0 %.9g, %.9g)", value, px, py, R->p0x, R->p0y);
        break;
    }
    }
    if (f->kind >= NT_FACT_SCORE) {
        truth = f->op == NT_OP_GE ? value >= f->value : f->op == NT_OP_LE ? value <= f->value : value == f->value;
    }
    return f->negate ? !truth : truth;
}

static void check_facts(runner *R, int tick)
{
    const nt_replay *rp = R->rp;
    char why[200], text[160];
    for (int i = 0; i < rp->fact_count; i++) {
        const nt_replay_fact *f = &rp->facts[i];
        fact_run *fr = &R->fr[i];
        if (fr->bad || fr->settled) continue;
        if (f->when == NT_WHEN_AT && tick != f->tick) continue;
        if (f->when == NT_WHEN_BY && tick > f->tick) continue;
        int v = fact_now(R, f, fr, why, sizeof why);
        fact_text(f, text, sizeof text);
        if (v < 0) {
            fr->bad = true;
            fail(R->rep);
            message(R->rep, "line %d: %s: cannot be checked at tick %d: %s", f->line, text, tick, why);
            continue;
        }
        if (f->when == NT_WHEN_BY) {
            if (v) fr->settled = true;
            else if (tick == f->tick) {
                fr->settled = true;
                fail(R->rep);
                message(R->rep, "line %d: %s: never true in ticks 0..%d (at tick %d: %s)", f->line, text, f->tick, tick, why);
            }
        } else if (!v) {
            fr->settled = true;
            fail(R->rep);
            message(R->rep, "line %d: %s: false at tick %d (%s)", f->line, text, tick, why);
        } else if (f->when == NT_WHEN_AT) {
            fr->settled = true;
        }
    }
}

/* Resolve names; facts that name unknown things fail before the run. */
static void prepare_facts(runner *R)
{
    const nt_replay *rp = R->rp;
    const nt_level *lv = R->g->level;
    char text[160];
    for (int i = 0; i < rp->fact_count; i++) {
        const nt_replay_fact *f = &rp->facts[i];
        fact_run *fr = &R->fr[i];
        fr->region = -1;
        if (f->kind != NT_FACT_INSIDE) continue;
        fact_text(f, text, sizeof text);
        fr->region = nt_level_find_region(lv, f->region);
        if (fr->region < 0) {
            fr->bad = true;
            fail(R->rep);
            message(R->rep, "line %d: %s: the level has no region '%s'", f->line, text, f->region);
        } else if (f->body[0] && nt_level_find_body(lv, f->body) < 0) {
            fr->bad = true;
            fail(R->rep);
            message(R->rep, "line %d: %s: the level has no body '%s'", f->line, text, f->body);
        } else if (!f->body[0] && !lv->has_player) {
            fr->bad = true;
            fail(R->rep);
            message(R->rep, "line %d: %s: the level has no player", f->line, text);
        }
    }
}

static nt_status make_solid_map(const nt_level *lv, nt_map **out)
{
    nt_map_def md;
    md.width = lv->width;
    md.height = lv->height;
    md.cell_size = lv->cell_size;
    nt_status s = nt_map_create(&md, out);
    if (s != NT_OK) return s;
    size_t n = (size_t)lv->width * (size_t)lv->height;
    uint8_t *t = malloc(n);
    if (!t) {
        nt_map_destroy(*out);
        *out = NULL;
        return NT_ERR_OUT_OF_MEMORY;
    }
    /* One-way cells let bodies through from below: they are not solid for this check. */
    for (size_t k = 0; k < n; k++) t[k] = (lv->cell_flags[k] & NT_CELL_ONE_WAY) ? NT_TILE_EMPTY : lv->tiles[k];
    s = nt_map_set_tiles(*out, t, n);
    free(t);
    return s;
}

/* Compare with the hashes and the trace recorded for this scalar build (float and
 * double builds compute different bits; each checks its own). */
static void check_hashes(runner *R)
{
    const nt_replay *rp = R->rp;
    nt_run_report *rep = R->rep;
    const int b = NT_REAL_IS_DOUBLE;
    const uint32_t *trace = rp->trace[b];
    int trace_count = rp->trace_count[b];
    int first_trace = -1;
    for (int t = 1; t <= trace_count && t <= rep->ticks; t++) {
        if (nt_trace_fold(rep->hashes[t]) != trace[t - 1]) {
            first_trace = t;
            break;
        }
    }
    int last_good = -1, first_bad = -1;
    for (int i = 0; i < rp->hash_count; i++) {
        const nt_replay_hash *h = &rp->hashes[i];
        if (h->is_double != (b == 1) || h->tick > rep->ticks) continue;
        if (rep->hashes[h->tick] == h->hash) {
            if (first_bad < 0) last_good = h->tick;
            continue;
        }
        if (first_bad < 0) first_bad = h->tick;
        hash_fail(rep);
        hash_message(rep, "line %d: %s hash at tick %d: expected 0x%016llx, got 0x%016llx", h->line, b ? "double" : "float",
                     h->tick, (unsigned long long)h->hash, (unsigned long long)rep->hashes[h->tick]);
    }
    if (first_trace > 0) {
        rep->first_divergence = first_trace;
        if (first_bad < 0) hash_fail(rep); /* the trace alone disagrees */
        hash_message(rep, "first tick that diverges: %d (trace: expected %08lx, got %08lx)", first_trace,
                     (unsigned long)trace[first_trace - 1], (unsigned long)nt_trace_fold(rep->hashes[first_trace]));
    } else if (first_bad >= 0) {
        rep->first_divergence = first_bad;
        if (trace_count >= first_bad) {
            /* The trace matches up to the checkpoint: only the 64-bit value differs. */
            hash_message(rep, "first tick that diverges: %d", first_bad);
        } else {
            int lo = last_good > trace_count ? last_good : trace_count;
            hash_message(rep, "diverges after tick %d and by tick %d; no trace covers it (record one with --record-hashes)",
                         lo, first_bad);
        }
    }
}

nt_status nt_run_replay(const nt_replay *rp, const nt_level *lv, nt_run_report *rep)
{
    if (!rep) return NT_ERR_INVALID_ARGUMENT;
    memset(rep, 0, sizeof *rep);
    rep->first_divergence = -1;
    if (!rp || !lv) return NT_ERR_INVALID_ARGUMENT;
    nt_game_def gd = nt_default_game_def();
    gd.override_seed = rp->has_seed;
    gd.seed = rp->seed;
    gd.override_friction_model = rp->has_friction_model;
    gd.friction_model = rp->friction_model;
    runner R;
    memset(&R, 0, sizeof R);
    R.rp = rp;
    R.rep = rep;
    nt_status s = nt_game_create(lv, &gd, &R.g);
    if (s != NT_OK) return s;
    rep->hashes = malloc(((size_t)rp->ticks + 1) * sizeof *rep->hashes);
    R.fr = rp->fact_count ? calloc((size_t)rp->fact_count, sizeof *R.fr) : NULL;
    if (!rep->hashes || (rp->fact_count && !R.fr)) s = NT_ERR_OUT_OF_MEMORY;
    for (int i = 0; s == NT_OK && i < rp->fact_count; i++)
        if (rp->facts[i].kind == NT_FACT_NO_BODY_IN_SOLID && !R.solid) s = make_solid_map(lv, &R.solid);
    if (s == NT_OK) {
        prepare_facts(&R);
        double ke, px, py, sc;
        mechanics(&R, &ke, &px, &py, &sc);
        R.ke0 = ke;
        R.p0x = px;
        R.p0y = py;
        R.pscale = sc;
        rep->hashes[0] = nt_game_hash(R.g);
        check_facts(&R, 0);
        int k = 0, left = rp->input_count > 0 ? rp->inputs[0].count : 0;
        for (int t = 1; t <= rp->ticks && s == NT_OK; t++) {
            while (k < rp->input_count && left == 0) {
                k++;
                left = k < rp->input_count ? rp->inputs[k].count : 0;
            }
            uint32_t keys = k < rp->input_count ? rp->inputs[k].keys : 0;
            if (left > 0) left--;
            s = nt_game_step(R.g, keys, rp->dt);
            if (s != NT_OK) break;
            rep->hashes[t] = nt_game_hash(R.g);
            rep->ticks = t;
            check_facts(&R, t);
        }
    }
    if (s == NT_OK) {
        check_hashes(&R);
        rep->final_state = nt_game_get_state(R.g);
        rep->passed = rep->failure_count == 0;
    } else {
        free(rep->hashes);
        rep->hashes = NULL;
    }
    nt_map_destroy(R.solid);
    free(R.fr);
    free(R.ids);
    nt_game_destroy(R.g);
    return s;
}

void nt_run_report_free(nt_run_report *rep)
{
    if (!rep) return;
    free(rep->hashes);
    rep->hashes = NULL;
}
