/* Replays: the .ntr parser and canonical writer. `ticks` must come before the
 * lines that depend on it (input, expect, hash, trace) so that every tick number
 * and input total is checked where it is written. */
#include <stdio.h>
#include <string.h>
#include "ntile/replay.h"
#include "text.h"

/* A replay text starts "ntile-replay VERSION" (parser and writer). */
#define REPLAY_MAGIC "ntile-replay"

static const char key_letters[] = "LRUDJA";

nt_status nt_replay_create(int ticks, nt_replay **out)
{
    if (!out) return NT_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (ticks < 1 || ticks > NT_REPLAY_MAX_TICKS) return NT_ERR_OUT_OF_RANGE;
    nt_replay *rp = (nt_replay *)nt__alloc(sizeof *rp);
    if (!rp) return NT_ERR_OUT_OF_MEMORY;
    memset(rp, 0, sizeof *rp);
    rp->dt = (nt_real)0.025;
    rp->ticks = ticks;
    *out = rp;
    return NT_OK;
}

void nt_replay_destroy(nt_replay *rp)
{
    if (!rp) return;
    nt__free(rp->inputs);
    nt__free(rp->facts);
    nt__free(rp->hashes);
    nt__free(rp->trace[0]);
    nt__free(rp->trace[1]);
    nt__free(rp);
}

uint32_t nt_replay_keys_at(const nt_replay *rp, int tick)
{
    if (!rp || tick < 1) return 0;
    long long at = 0;
    for (int i = 0; i < rp->input_count; i++) {
        at += rp->inputs[i].count;
        if (tick <= at) return rp->inputs[i].keys;
    }
    return 0;
}

typedef struct rparser {
    nt__text t;
    nt_replay *rp;
    int input_cap, fact_cap, hash_cap, trace_cap[2];
    int last_tick[2]; /* last hash tick per build, -1 */
    long long input_total;
    int line_of[6]; /* name, level, seed, dt, ticks, friction-model */
} rparser;

/* One input token COUNT KEYS at field f; appended to the replay. */
static nt_status input_token(nt__text *t, const nt__field *f, nt_replay *rp, int *cap, long long *total, int limit_ticks)
{
    char q[NT__QUOTE_MAX];
    size_t d = 0;
    while (d < f->n && f->s[d] >= '0' && f->s[d] <= '9') d++;
    if (d == 0)
        return nt__fail_col(t, f->col, "input '%s' must start with a tick count (e.g. 30R, 8RJ, 12.)",
                            nt__quote(q, f->s, f->n));
    if (d == f->n)
        return nt__fail_col(t, f->col + (int)d, "input '%s' has no keys (letters L R U D J A, or '.' for none)",
                            nt__quote(q, f->s, f->n));
    nt__field cf = {f->s, d, f->col};
    long long count;
    nt_status s = nt__field_int(t, &cf, "input tick count", 1, NT_REPLAY_MAX_TICKS, &count);
    if (s != NT_OK) return s;
    uint32_t keys = 0;
    if (f->n - d == 1 && f->s[d] == '.') {
        keys = 0;
    } else {
        for (size_t i = d; i < f->n; i++) {
            const char *k = strchr(key_letters, f->s[i]);
            if (!k || f->s[i] == '\0')
                return nt__fail_col(t, f->col + (int)i, "unknown key '%s' (keys are L R U D J A; '.' alone means none)",
                                    nt__quote(q, f->s + i, 1));
            uint32_t bit = 1u << (k - key_letters);
            if (keys & bit) return nt__fail_col(t, f->col + (int)i, "key '%c' repeated in one input", f->s[i]);
            keys |= bit;
        }
    }
    if (*total + count > limit_ticks)
        return nt__fail_col(t, f->col, "inputs cover %lld ticks, more than the replay's %d", *total + count, limit_ticks);
    if (!nt__grow_array((void **)&rp->inputs, rp->input_count, cap, sizeof *rp->inputs)) return NT_ERR_OUT_OF_MEMORY;
    rp->inputs[rp->input_count].count = (int)count;
    rp->inputs[rp->input_count].keys = keys;
    rp->input_count++;
    *total += count;
    return NT_OK;
}

static nt_status tick_at(rparser *P, int i, const char *what, int *out)
{
    long long v;
    nt_status s = nt__field_int(&P->t, &P->t.f[i], what, 0, P->rp->ticks, &v);
    if (s == NT_OK) *out = (int)v;
    return s;
}

static nt_status parse_expect(rparser *P)
{
    nt__text *t = &P->t;
    nt_replay *rp = P->rp;
    char q[NT__QUOTE_MAX];
    static const char form[] = "expect [not] FACT (at T | by T | always)";
    nt_replay_fact f;
    memset(&f, 0, sizeof f);
    f.line = t->line;
    int i = 1;
    if (i < t->nf && nt__field_is(&t->f[i], "not")) {
        f.negate = true;
        i++;
    }
    if (i >= t->nf) return nt__fail_col(t, nt__text_eol_col(t), "missing fact: expected '%s'", form);
    static const char *const kinds[] = {"complete", "alive", "inside", "no-body-in-solid", "score",
                                        "bodies", "spawned", "energy-ratio", "momentum-drift"};
    int kind = -1;
    for (int k = 0; k < 9; k++)
        if (nt__field_is(&t->f[i], kinds[k])) kind = k;
    if (kind < 0)
        return nt__fail_col(t, t->f[i].col,
                            "unknown fact '%s' (expected complete, alive, inside, no-body-in-solid, score, bodies, spawned, "
                            "energy-ratio or momentum-drift)",
                            nt__quote(q, t->f[i].s, t->f[i].n));
    f.kind = (nt_fact_kind)kind;
    i++;
    nt_status s;
    if (f.kind == NT_FACT_INSIDE) {
        if (i >= t->nf) return nt__fail_col(t, nt__text_eol_col(t), "missing region: expected 'inside REGION [body NAME]'");
        if ((s = nt__field_name(t, &t->f[i], "region", f.region)) != NT_OK) return s;
        i++;
        if (i < t->nf && nt__field_is(&t->f[i], "body")) {
            if (i + 1 >= t->nf) return nt__fail_col(t, nt__text_eol_col(t), "missing body name after 'body'");
            if ((s = nt__field_name(t, &t->f[i + 1], "body", f.body)) != NT_OK) return s;
            i += 2;
        }
    } else if (f.kind >= NT_FACT_SCORE) {
        if (i + 1 >= t->nf) return nt__fail_col(t, nt__text_eol_col(t), "missing comparison: expected '%s >=|<=|== VALUE'", kinds[kind]);
        if (nt__field_is(&t->f[i], ">=")) f.op = NT_OP_GE;
        else if (nt__field_is(&t->f[i], "<=")) f.op = NT_OP_LE;
        else if (nt__field_is(&t->f[i], "==")) f.op = NT_OP_EQ;
        else return nt__fail_col(t, t->f[i].col, "unknown comparison '%s' (expected >=, <= or ==)", nt__quote(q, t->f[i].s, t->f[i].n));
        if ((s = nt__field_double(t, &t->f[i + 1], "value", &f.value)) != NT_OK) return s;
        i += 2;
    }
    if (i >= t->nf) return nt__fail_col(t, nt__text_eol_col(t), "missing 'at T', 'by T' or 'always'");
    if (nt__field_is(&t->f[i], "always")) {
        f.when = NT_WHEN_ALWAYS;
        f.tick = rp->ticks;
        i++;
    } else if (nt__field_is(&t->f[i], "at") || nt__field_is(&t->f[i], "by")) {
        f.when = nt__field_is(&t->f[i], "at") ? NT_WHEN_AT : NT_WHEN_BY;
        if (i + 1 >= t->nf) return nt__fail_col(t, nt__text_eol_col(t), "missing tick after '%s'", f.when == NT_WHEN_AT ? "at" : "by");
        if ((s = tick_at(P, i + 1, "tick", &f.tick)) != NT_OK) return s;
        i += 2;
    } else {
        return nt__fail_col(t, t->f[i].col, "expected 'at T', 'by T' or 'always', got '%s'", nt__quote(q, t->f[i].s, t->f[i].n));
    }
    if (i < t->nf) return nt__fail_col(t, t->f[i].col, "unexpected field '%s' after the fact", nt__quote(q, t->f[i].s, t->f[i].n));
    if (!nt__grow_array((void **)&rp->facts, rp->fact_count, &P->fact_cap, sizeof f)) return NT_ERR_OUT_OF_MEMORY;
    rp->facts[rp->fact_count++] = f;
    return NT_OK;
}

/* `float` or `double` at field i; -1 after the error. */
static int scalar_at(nt__text *t, int i)
{
    char q[NT__QUOTE_MAX];
    if (nt__field_is(&t->f[i], "float")) return 0;
    if (nt__field_is(&t->f[i], "double")) return 1;
    nt__fail_col(t, t->f[i].col, "expected the scalar build 'float' or 'double', got '%s'", nt__quote(q, t->f[i].s, t->f[i].n));
    return -1;
}

static nt_status parse_hash(rparser *P)
{
    nt__text *t = &P->t;
    nt_replay *rp = P->rp;
    nt_status s = nt__expect_fields(t, 4, "hash float|double TICK 0xHHHHHHHHHHHHHHHH");
    if (s != NT_OK) return s;
    nt_replay_hash h;
    h.line = t->line;
    int b = scalar_at(t, 1);
    if (b < 0) return NT_ERR_PARSE;
    h.is_double = b == 1;
    if ((s = tick_at(P, 2, "hash tick", &h.tick)) != NT_OK) return s;
    if (h.tick <= P->last_tick[b])
        return nt__fail_col(t, t->f[2].col, "%s hash ticks must increase (tick %d after tick %d)", b ? "double" : "float",
                            h.tick, P->last_tick[b]);
    if ((s = nt__field_hex(t, &t->f[3], "hash", 16, &h.hash)) != NT_OK) return s;
    if (t->f[3].n != 18) return nt__fail_col(t, t->f[3].col, "hash must be written 0x and 16 hex digits");
    if (!nt__grow_array((void **)&rp->hashes, rp->hash_count, &P->hash_cap, sizeof h)) return NT_ERR_OUT_OF_MEMORY;
    /* Keep float hashes before double ones (the writer's order). */
    int at = rp->hash_count;
    if (!h.is_double)
        while (at > 0 && rp->hashes[at - 1].is_double) at--;
    memmove(&rp->hashes[at + 1], &rp->hashes[at], (size_t)(rp->hash_count - at) * sizeof h);
    rp->hashes[at] = h;
    rp->hash_count++;
    P->last_tick[b] = h.tick;
    return NT_OK;
}

static nt_status parse_trace(rparser *P)
{
    nt__text *t = &P->t;
    nt_replay *rp = P->rp;
    if (t->nf < 4) return nt__fail_col(t, nt__text_eol_col(t), "missing fields: expected 'trace float|double FIRST_TICK HHHHHHHH ...'");
    int b = scalar_at(t, 1);
    if (b < 0) return NT_ERR_PARSE;
    long long first;
    nt_status s = nt__field_int(&P->t, &t->f[2], "trace tick", 1, rp->ticks, &first);
    if (s != NT_OK) return s;
    if (first != rp->trace_count[b] + 1)
        return nt__fail_col(t, t->f[2].col, "%s trace lines must follow on: expected tick %d, got %lld", b ? "double" : "float",
                            rp->trace_count[b] + 1, first);
    if (rp->trace_count[b] + (t->nf - 3) > rp->ticks)
        return nt__fail_col(t, t->f[3 + (rp->ticks - rp->trace_count[b])].col, "the trace is longer than the replay's %d ticks",
                            rp->ticks);
    for (int i = 3; i < t->nf; i++) {
        uint64_t v;
        if ((s = nt__field_hex(t, &t->f[i], "trace value", 8, &v)) != NT_OK) return s;
        if (t->f[i].n != 8) return nt__fail_col(t, t->f[i].col, "trace values are 8 hex digits without 0x");
        if (!nt__grow_array((void **)&rp->trace[b], rp->trace_count[b], &P->trace_cap[b], sizeof *rp->trace[b]))
            return NT_ERR_OUT_OF_MEMORY;
        rp->trace[b][rp->trace_count[b]++] = (uint32_t)v;
    }
    return NT_OK;
}

enum { RK_NAME, RK_LEVEL, RK_SEED, RK_DT, RK_TICKS, RK_MODEL, RK_COUNT };
static const char *const rkeys[RK_COUNT] = {"name", "level", "seed", "dt", "ticks", "friction-model"};

static nt_status parse_rlines(rparser *P)
{
    nt__text *t = &P->t;
    nt_replay *rp = P->rp;
    char q[NT__QUOTE_MAX];
    nt_status s = nt__read_header(t, REPLAY_MAGIC, NT_REPLAY_VERSION);
    if (s != NT_OK) return s;
    for (;;) {
        int r = nt__text_next_fields(t);
        if (r < 0) return NT_ERR_PARSE;
        if (r == 0) break;
        const nt__field *w = &t->f[0];
        int key = -1;
        for (int k = 0; k < RK_COUNT; k++)
            if (nt__field_is(w, rkeys[k])) key = k;
        if (key >= 0) {
            if (P->line_of[key]) return nt__fail_col(t, w->col, "duplicate '%s' (first at line %d)", rkeys[key], P->line_of[key]);
            P->line_of[key] = t->line;
            switch (key) {
            case RK_NAME:
                if ((s = nt__expect_fields(t, 2, "name NAME")) != NT_OK) return s;
                s = nt__field_string(t, &t->f[1], "replay name", rp->name, sizeof rp->name, 1);
                break;
            case RK_LEVEL:
                if ((s = nt__expect_fields(t, 2, "level PATH")) != NT_OK) return s;
                s = nt__field_string(t, &t->f[1], "level path", rp->level, sizeof rp->level, 1);
                if (s == NT_OK && rp->level[0] == '\0') s = nt__fail_col(t, t->f[1].col, "empty level path");
                break;
            case RK_SEED: {
                if ((s = nt__expect_fields(t, 2, "seed N")) != NT_OK) return s;
                long long v;
                s = nt__field_int(t, &t->f[1], "seed", 0, 0x7fffffffffffffffLL, &v);
                rp->seed = (uint64_t)v;
                rp->has_seed = true;
                break;
            }
            case RK_DT:
                if ((s = nt__expect_fields(t, 2, "dt SECONDS")) != NT_OK) return s;
                s = nt__field_real(t, &t->f[1], "dt", &rp->dt);
                if (s == NT_OK && !(rp->dt >= (nt_real)NT_MIN_DT && rp->dt <= (nt_real)NT_MAX_DT))
                    s = nt__fail_col(t, t->f[1].col, "dt must lie in %g .. %g seconds", (double)NT_MIN_DT, (double)NT_MAX_DT);
                break;
            case RK_TICKS: {
                if ((s = nt__expect_fields(t, 2, "ticks N")) != NT_OK) return s;
                long long v;
                s = nt__field_int(t, &t->f[1], "ticks", 1, NT_REPLAY_MAX_TICKS, &v);
                rp->ticks = (int)v;
                break;
            }
            case RK_MODEL:
                if ((s = nt__expect_fields(t, 2, "friction-model n|coulomb")) != NT_OK) return s;
                if (nt__field_is(&t->f[1], "n")) rp->friction_model = NT_FRICTION_N;
                else if (nt__field_is(&t->f[1], "coulomb")) rp->friction_model = NT_FRICTION_COULOMB;
                else
                    return nt__fail_col(t, t->f[1].col, "unknown friction model '%s' (expected n or coulomb)",
                                        nt__quote(q, t->f[1].s, t->f[1].n));
                rp->has_friction_model = true;
                break;
            }
        } else if (nt__field_is(w, "input") || nt__field_is(w, "expect") || nt__field_is(w, "hash") ||
                   nt__field_is(w, "trace")) {
            if (!P->line_of[RK_TICKS])
                return nt__fail_col(t, w->col, "'%s' before 'ticks' (the tick count must come first)", nt__quote(q, w->s, w->n));
            if (nt__field_is(w, "input")) {
                for (int i = 1; i < t->nf && s == NT_OK; i++)
                    s = input_token(t, &t->f[i], rp, &P->input_cap, &P->input_total, rp->ticks);
            } else if (nt__field_is(w, "expect")) {
                s = parse_expect(P);
            } else if (nt__field_is(w, "hash")) {
                s = parse_hash(P);
            } else {
                s = parse_trace(P);
            }
        } else {
            return nt__fail_col(t, w->col, "unknown keyword '%s'", nt__quote(q, w->s, w->n));
        }
        if (s != NT_OK) return s;
    }
    int line, col;
    nt__text_eof_pos(t, &line, &col);
    if (!P->line_of[RK_LEVEL]) return nt__fail(t, line, col, "unexpected end of file: no 'level' line");
    if (!P->line_of[RK_TICKS]) return nt__fail(t, line, col, "unexpected end of file: no 'ticks' line");
    return NT_OK;
}

nt_status nt_replay_parse(const char *name, const char *text, size_t length, nt_replay **out, nt_text_error *err)
{
    if (out) *out = NULL;
    if (!out || (!text && length > 0)) return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "nt_replay_parse: NULL argument");
    rparser *P = (rparser *)nt__alloc(sizeof *P);
    nt_replay *rp = NULL;
    nt_status s = NT_ERR_OUT_OF_MEMORY;
    if (P) {
        memset(P, 0, sizeof *P);
        nt__text_init(&P->t, name, text, length, err);
        if (nt_replay_create(1, &rp) == NT_OK) {
            P->rp = rp;
            P->last_tick[0] = P->last_tick[1] = -1;
            s = parse_rlines(P);
        }
    }
    if (s == NT_ERR_OUT_OF_MEMORY) nt__error_plain(err, s, "%s: out of memory", name ? name : "(text)");
    nt__free(P);
    if (s != NT_OK) {
        nt_replay_destroy(rp);
        return s;
    }
    *out = rp;
    return NT_OK;
}

nt_status nt_replay_set_inputs(nt_replay *rp, const char *name, const char *text, size_t length, nt_text_error *err)
{
    if (!rp || (!text && length > 0)) return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "nt_replay_set_inputs: NULL argument");
    nt__text *t = (nt__text *)nt__alloc(sizeof *t);
    if (!t) return nt__error_plain(err, NT_ERR_OUT_OF_MEMORY, "out of memory");
    nt__text_init(t, name, text, length, err);
    nt_replay tmp;
    memset(&tmp, 0, sizeof tmp);
    int cap = 0;
    long long total = 0;
    nt_status s = NT_OK;
    int r;
    while (s == NT_OK && (r = nt__text_next_fields(t)) != 0) {
        if (r < 0) {
            s = NT_ERR_PARSE;
            break;
        }
        for (int i = 0; i < t->nf && s == NT_OK; i++) s = input_token(t, &t->f[i], &tmp, &cap, &total, rp->ticks);
    }
    nt__free(t);
    if (s != NT_OK) {
        nt__free(tmp.inputs);
        return s;
    }
    nt__free(rp->inputs);
    rp->inputs = tmp.inputs;
    rp->input_count = tmp.input_count;
    return NT_OK;
}

nt_status nt_replay_set_hashes(nt_replay *rp, int is_double, const nt_replay_hash *hashes, int hash_count,
                               const uint32_t *trace, int trace_count)
{
    if (!rp || (is_double != 0 && is_double != 1) || hash_count < 0 || trace_count < 0 || (hash_count && !hashes) ||
        (trace_count && !trace) || trace_count > rp->ticks)
        return NT_ERR_INVALID_ARGUMENT;
    for (int i = 0; i < hash_count; i++)
        if (hashes[i].tick < 0 || hashes[i].tick > rp->ticks || (i > 0 && hashes[i].tick <= hashes[i - 1].tick))
            return NT_ERR_INVALID_ARGUMENT;
    int keep = 0;
    for (int i = 0; i < rp->hash_count; i++) keep += rp->hashes[i].is_double != (is_double == 1);
    int total = keep + hash_count;
    nt_replay_hash *h = total ? (nt_replay_hash *)nt__alloc((size_t)total * sizeof *h) : NULL;
    uint32_t *tr = trace_count ? (uint32_t *)nt__alloc((size_t)trace_count * sizeof *tr) : NULL;
    if ((total && !h) || (trace_count && !tr)) {
        nt__free(h);
        nt__free(tr);
        return NT_ERR_OUT_OF_MEMORY;
    }
    /* Float hashes first, then double ones. */
    int n = 0;
    for (int b = 0; b < 2; b++) {
        if (b == is_double) {
            for (int i = 0; i < hash_count; i++) {
                h[n] = hashes[i];
                h[n].is_double = b == 1;
                h[n++].line = 0;
            }
        } else {
            for (int i = 0; i < rp->hash_count; i++)
                if (rp->hashes[i].is_double == (b == 1)) h[n++] = rp->hashes[i];
        }
    }
    if (trace_count) memcpy(tr, trace, (size_t)trace_count * sizeof *tr);
    nt__free(rp->hashes);
    nt__free(rp->trace[is_double]);
    rp->hashes = h;
    rp->hash_count = total;
    rp->trace[is_double] = tr;
    rp->trace_count[is_double] = trace_count;
    return NT_OK;
}

/* ---------------------------------------------------------------- the writer */

static int needs_quotes(const char *s)
{
    if (!*s) return 1;
    for (; *s; s++)
        if (*s == ' ' || *s == '\t' || *s == '#' || *s == '"') return 1;
    return 0;
}

static void put_word(nt__sink *o, const char *s)
{
    if (needs_quotes(s)) nt__sink_printf(o, "\"%s\"", s);
    else nt__sink_puts(o, s);
}

size_t nt_replay_write(const nt_replay *rp, char *buf, size_t cap)
{
    nt__sink o;
    nt__sink_init(&o, buf, cap);
    if (!rp) return nt__sink_finish(&o);
    nt__sink_header(&o, REPLAY_MAGIC, NT_REPLAY_VERSION);
    if (rp->name[0]) {
        nt__sink_puts(&o, "name ");
        put_word(&o, rp->name);
        nt__sink_puts(&o, "\n");
    }
    nt__sink_puts(&o, "level ");
    put_word(&o, rp->level);
    nt__sink_puts(&o, "\n");
    if (rp->has_seed) nt__sink_printf(&o, "seed %llu\n", (unsigned long long)rp->seed);
    nt__sink_puts(&o, "dt ");
    nt__sink_real(&o, rp->dt);
    nt__sink_printf(&o, "\nticks %d\n", rp->ticks);
    if (rp->has_friction_model)
        nt__sink_printf(&o, "friction-model %s\n", rp->friction_model == NT_FRICTION_N ? "n" : "coulomb");
    for (int i = 0; i < rp->input_count; i++) {
        nt__sink_puts(&o, i % 16 == 0 ? "input " : " ");
        nt__sink_printf(&o, "%d", rp->inputs[i].count);
        if (rp->inputs[i].keys == 0) nt__sink_puts(&o, ".");
        for (int k = 0; k < 6; k++)
            if (rp->inputs[i].keys & (1u << k)) nt__sink_put(&o, &key_letters[k], 1);
        if (i % 16 == 15 || i == rp->input_count - 1) nt__sink_puts(&o, "\n");
    }
    static const char *const kinds[] = {"complete", "alive", "inside", "no-body-in-solid", "score",
                                        "bodies", "spawned", "energy-ratio", "momentum-drift"};
    static const char *const ops[] = {">=", "<=", "=="};
    for (int i = 0; i < rp->fact_count; i++) {
        const nt_replay_fact *f = &rp->facts[i];
        nt__sink_printf(&o, "expect %s%s", f->negate ? "not " : "", kinds[f->kind]);
        if (f->kind == NT_FACT_INSIDE) {
            nt__sink_printf(&o, " %s", f->region);
            if (f->body[0]) nt__sink_printf(&o, " body %s", f->body);
        } else if (f->kind >= NT_FACT_SCORE) {
            nt__sink_printf(&o, " %s ", ops[f->op]);
            nt__sink_double(&o, f->value);
        }
        if (f->when == NT_WHEN_ALWAYS) nt__sink_puts(&o, " always\n");
        else nt__sink_printf(&o, " %s %d\n", f->when == NT_WHEN_AT ? "at" : "by", f->tick);
    }
    for (int b = 0; b < 2; b++) {
        const char *scalar = b ? "double" : "float";
        for (int i = 0; i < rp->hash_count; i++)
            if (rp->hashes[i].is_double == (b == 1))
                nt__sink_printf(&o, "hash %s %d 0x%016llx\n", scalar, rp->hashes[i].tick,
                                (unsigned long long)rp->hashes[i].hash);
        for (int i = 0; i < rp->trace_count[b]; i++) {
            if (i % 8 == 0) nt__sink_printf(&o, "trace %s %d", scalar, i + 1);
            nt__sink_printf(&o, " %08lx", (unsigned long)rp->trace[b][i]);
            if (i % 8 == 7 || i == rp->trace_count[b] - 1) nt__sink_puts(&o, "\n");
        }
    }
    return nt__sink_finish(&o);
}
