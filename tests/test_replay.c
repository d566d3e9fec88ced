/* Replays: the .ntr parser (every error path with its exact message and position),
 * the canonical writer (round trip), run-length inputs, hash and trace lines per
 * scalar build. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "failalloc.h"
#include "ntile/ntile.h"

#define HEAD "ntile-replay 1\nlevel l.ntl\nticks 100\n"

static nt_replay *parse_ok(const char *text)
{
    nt_replay *rp = NULL;
    nt_text_error e;
    nt_status s = nt_replay_parse("r.ntr", text, strlen(text), &rp, &e);
    if (s != NT_OK) fprintf(stderr, "unexpected error: %s\n", e.message);
    assert_int_equal(s, NT_OK);
    assert_non_null(rp);
    return rp;
}

static void parse_fails(const char *text, const char *message)
{
    nt_replay *rp = (nt_replay *)&rp;
    nt_text_error e;
    nt_status s = nt_replay_parse("r.ntr", text, strlen(text), &rp, &e);
    if (s != NT_ERR_PARSE || strcmp(e.message, message) != 0)
        fprintf(stderr, "input:\n%s\nexpected: %s\ngot:      %s\n", text, message, e.message);
    assert_int_equal(s, NT_ERR_PARSE);
    assert_null(rp);
    assert_string_equal(e.message, message);
}

static char *write_replay(const nt_replay *rp)
{
    size_t n = nt_replay_write(rp, NULL, 0);
    char *buf = malloc(n + 1);
    assert_non_null(buf);
    assert_int_equal(nt_replay_write(rp, buf, n + 1), n);
    return buf;
}

static void test_parse(void **state)
{
    (void)state;
    nt_replay *rp = parse_ok("ntile-replay 1\n# comment\nname \"my run\"\nlevel ../levels/x.ntl\nseed 42\ndt 0.02\n"
                             "ticks 100\nfriction-model coulomb\ninput 10R 5RJ 3.\ninput 2LUDA\n"
                             "expect complete by 90\nexpect not alive at 0\nexpect inside exit body crate at 50\n"
                             "expect inside exit always\nexpect score >= 3.5 at 100\nexpect bodies <= 7 by 20\n"
                             "expect momentum-drift == 0 always\nexpect no-body-in-solid always\n"
                             "hash float 0 0x0000000000000001\nhash double 5 0xFFFFFFFFFFFFFFFF\nhash float 100 0x0123456789abcdef\n"
                             "trace float 1 00000001 00000002\ntrace float 3 0000000a\ntrace double 1 deadbeef\n");
    assert_string_equal(rp->name, "my run");
    assert_string_equal(rp->level, "../levels/x.ntl");
    assert_true(rp->has_seed && rp->seed == 42);
    assert_true(rp->dt == (nt_real)0.02);
    assert_int_equal(rp->ticks, 100);
    assert_true(rp->has_friction_model && rp->friction_model == NT_FRICTION_COULOMB);
    assert_int_equal(rp->input_count, 4);
    assert_true(rp->inputs[0].count == 10 && rp->inputs[0].keys == NT_INPUT_RIGHT);
    assert_true(rp->inputs[1].keys == (NT_INPUT_RIGHT | NT_INPUT_JUMP));
    assert_true(rp->inputs[2].count == 3 && rp->inputs[2].keys == 0);
    assert_true(rp->inputs[3].keys == (NT_INPUT_LEFT | NT_INPUT_UP | NT_INPUT_DOWN | NT_INPUT_ACTION));
    assert_int_equal(nt_replay_keys_at(rp, 1), NT_INPUT_RIGHT);
    assert_int_equal(nt_replay_keys_at(rp, 10), NT_INPUT_RIGHT);
    assert_int_equal(nt_replay_keys_at(rp, 11), NT_INPUT_RIGHT | NT_INPUT_JUMP);
    assert_int_equal(nt_replay_keys_at(rp, 18), 0);
    assert_int_equal(nt_replay_keys_at(rp, 19), NT_INPUT_LEFT | NT_INPUT_UP | NT_INPUT_DOWN | NT_INPUT_ACTION);
    assert_int_equal(nt_replay_keys_at(rp, 21), 0); /* past the inputs: no keys */
    assert_int_equal(rp->fact_count, 8);
    assert_true(rp->facts[0].kind == NT_FACT_COMPLETE && rp->facts[0].when == NT_WHEN_BY && rp->facts[0].tick == 90);
    assert_true(rp->facts[1].kind == NT_FACT_ALIVE && rp->facts[1].negate && rp->facts[1].when == NT_WHEN_AT);
    assert_string_equal(rp->facts[2].region, "exit");
    assert_string_equal(rp->facts[2].body, "crate");
    assert_true(rp->facts[3].when == NT_WHEN_ALWAYS && rp->facts[3].body[0] == '\0');
    assert_true(rp->facts[4].kind == NT_FACT_SCORE && rp->facts[4].op == NT_OP_GE && rp->facts[4].value == 3.5);
    assert_true(rp->facts[5].op == NT_OP_LE && rp->facts[6].op == NT_OP_EQ);
    assert_int_equal(rp->facts[7].line, 18);
    assert_int_equal(rp->hash_count, 3);
    /* float hashes first, then double */
    assert_true(!rp->hashes[0].is_double && rp->hashes[0].tick == 0 && rp->hashes[0].hash == 1);
    assert_true(!rp->hashes[1].is_double && rp->hashes[1].tick == 100 && rp->hashes[1].hash == 0x0123456789abcdefull);
    assert_true(rp->hashes[2].is_double && rp->hashes[2].hash == 0xffffffffffffffffull && rp->hashes[2].line == 20);
    assert_int_equal(rp->trace_count[0], 3);
    assert_int_equal(rp->trace[0][2], 10);
    assert_int_equal(rp->trace_count[1], 1);
    assert_true(rp->trace[1][0] == 0xdeadbeefu);
    nt_replay_destroy(rp);
    rp = parse_ok("ntile-replay 1\nticks 5\nlevel \"dir with space/l.ntl\"\n");
    assert_string_equal(rp->level, "dir with space/l.ntl");
    assert_true(rp->dt == (nt_real)0.025);
    assert_false(rp->has_seed);
    nt_replay_destroy(rp);
}

static void test_errors(void **state)
{
    (void)state;
    parse_fails("", "r.ntr:1:1: empty file: expected 'ntile-replay 1' on the first line");
    parse_fails("ntile-level 1\n", "r.ntr:1:1: expected 'ntile-replay 1' on the first line");
    parse_fails("ntile-replay 9\n", "r.ntr:1:14: unsupported ntile-replay version 9 (this ntile reads version 1)");
    parse_fails("ntile-replay 1\nticks 10\n", "r.ntr:3:1: unexpected end of file: no 'level' line");
    parse_fails("ntile-replay 1\nlevel x\n", "r.ntr:3:1: unexpected end of file: no 'ticks' line");
    parse_fails("ntile-replay 1\nlevel x", "r.ntr:2:8: unexpected end of file: no 'ticks' line");
    parse_fails("ntile-replay 1\nlevel \"\"\nticks 1\n", "r.ntr:2:7: empty level path");
    /* Found by the fuzzer: a '"' inside a bare path could not be written back. */
    parse_fails("ntile-replay 1\nlevel ../a\"b.ntl\nticks 1\n", "r.ntr:2:11: level path holds a control character, '\\' or '\"'");
    parse_fails("ntile-replay 1\nticks 0\n", "r.ntr:2:7: ticks '0' is out of range 1..100000000");
    parse_fails("ntile-replay 1\nticks 1\nticks 2\n", "r.ntr:3:1: duplicate 'ticks' (first at line 2)");
    parse_fails("ntile-replay 1\ninput 3R\n", "r.ntr:2:1: 'input' before 'ticks' (the tick count must come first)");
    parse_fails(HEAD "dt 0\n", "r.ntr:4:4: dt must lie in 1e-06 .. 1 seconds");
    parse_fails(HEAD "dt nan\n", "r.ntr:4:4: dt 'nan' is not a finite number");
    parse_fails(HEAD "seed x\n", "r.ntr:4:6: seed 'x' is not an integer");
    parse_fails(HEAD "friction-model q\n", "r.ntr:4:16: unknown friction model 'q' (expected n or coulomb)");
    parse_fails(HEAD "speed 3\n", "r.ntr:4:1: unknown keyword 'speed'");
    parse_fails(HEAD "input R10\n", "r.ntr:4:7: input 'R10' must start with a tick count (e.g. 30R, 8RJ, 12.)");
    parse_fails(HEAD "input 10\n", "r.ntr:4:9: input '10' has no keys (letters L R U D J A, or '.' for none)");
    parse_fails(HEAD "input 10RX\n", "r.ntr:4:10: unknown key 'X' (keys are L R U D J A; '.' alone means none)");
    parse_fails(HEAD "input 10R.\n", "r.ntr:4:10: unknown key '.' (keys are L R U D J A; '.' alone means none)");
    parse_fails(HEAD "input 10RJR\n", "r.ntr:4:11: key 'R' repeated in one input");
    parse_fails(HEAD "input 0R\n", "r.ntr:4:7: input tick count '0' is out of range 1..100000000");
    parse_fails(HEAD "input 60R\ninput 30. 11J\n", "r.ntr:5:11: inputs cover 101 ticks, more than the replay's 100");
    parse_fails(HEAD "expect\n", "r.ntr:4:7: missing fact: expected 'expect [not] FACT (at T | by T | always)'");
    parse_fails(HEAD "expect happy at 3\n",
                "r.ntr:4:8: unknown fact 'happy' (expected complete, alive, inside, no-body-in-solid, score, bodies, spawned, "
                "energy-ratio or momentum-drift)");
    parse_fails(HEAD "expect complete\n", "r.ntr:4:16: missing 'at T', 'by T' or 'always'");
    parse_fails(HEAD "expect complete at\n", "r.ntr:4:19: missing tick after 'at'");
    parse_fails(HEAD "expect complete at 101\n", "r.ntr:4:20: tick '101' is out of range 0..100");
    parse_fails(HEAD "expect complete soon\n", "r.ntr:4:17: expected 'at T', 'by T' or 'always', got 'soon'");
    parse_fails(HEAD "expect complete always now\n", "r.ntr:4:24: unexpected field 'now' after the fact");
    parse_fails(HEAD "expect score > 3 at 5\n", "r.ntr:4:14: unknown comparison '>' (expected >=, <= or ==)");
    parse_fails(HEAD "expect score >=\n", "r.ntr:4:16: missing comparison: expected 'score >=|<=|== VALUE'");
    parse_fails(HEAD "expect score >= inf at 3\n", "r.ntr:4:17: value 'inf' is not a finite number");
    parse_fails(HEAD "expect inside\n", "r.ntr:4:14: missing region: expected 'inside REGION [body NAME]'");
    parse_fails(HEAD "expect inside exit body\n", "r.ntr:4:24: missing body name after 'body'");
    parse_fails(HEAD "hash 5 0x0000000000000000\n", "r.ntr:4:26: missing fields: expected 'hash float|double TICK 0xHHHHHHHHHHHHHHHH'");
    parse_fails(HEAD "hash single 5 0x0000000000000000\n", "r.ntr:4:6: expected the scalar build 'float' or 'double', got 'single'");
    parse_fails(HEAD "hash float 5 0x00000000\n", "r.ntr:4:14: hash '0x00000000' must be 0x and 16 hex digits");
    parse_fails(HEAD "hash float 5 0x000000000000000g\n", "r.ntr:4:14: hash '0x000000000000000g' is not a hex number");
    parse_fails(HEAD "hash float 5 0000000000000000\n", "r.ntr:4:14: hash must be written 0x and 16 hex digits");
    parse_fails(HEAD "hash float 5 0x0000000000000000\nhash float 5 0x0000000000000000\n",
                "r.ntr:5:12: float hash ticks must increase (tick 5 after tick 5)");
    parse_fails(HEAD "hash float 101 0x0000000000000000\n", "r.ntr:4:12: hash tick '101' is out of range 0..100");
    parse_fails(HEAD "trace float 2 00000000\n", "r.ntr:4:13: float trace lines must follow on: expected tick 1, got 2");
    parse_fails(HEAD "trace float 1 0000000\n", "r.ntr:4:15: trace value '0000000' must be 8 hex digits");
    parse_fails("ntile-replay 1\nlevel l\nticks 2\ntrace double 1 00000000 00000000 00000000\n",
                "r.ntr:4:34: the trace is longer than the replay's 2 ticks");
}

static void test_roundtrip(void **state)
{
    (void)state;
    const char *text = "ntile-replay 1\nname \"a b\"\nlevel \"x y.ntl\"\nseed 3\ndt 0.0166667\nticks 500\n"
                       "friction-model n\n"
                       "input 1R 2L 3U 4D 5J 6A 7. 8RJ 9LJA 10. 11R 12R 13R 14R 15R 16R 17R 18R\n"
                       "expect not complete by 10\nexpect inside z body b at 3\nexpect energy-ratio <= 0.29327 at 400\n"
                       "expect momentum-drift >= 1e-12 always\nexpect spawned == 30 at 500\n"
                       "hash double 500 0x00000000000000ff\nhash float 1 0x1000000000000000\n"
                       "trace float 1 01 02 03 04 05 06 07 08 09 0a\n";
    /* (the trace line above is invalid: 2-digit values) */
    nt_replay *bad = NULL;
    assert_int_equal(nt_replay_parse("r", text, strlen(text), &bad, NULL), NT_ERR_PARSE);
    char fixed[2048];
    snprintf(fixed, sizeof fixed, "%.*strace float 1 00000001 00000002 00000003 00000004 00000005 00000006 00000007 "
                                  "00000008 00000009\n",
             (int)(strstr(text, "trace") - text), text);
    nt_replay *a = parse_ok(fixed);
    char *t1 = write_replay(a);
    nt_replay *b = parse_ok(t1);
    char *t2 = write_replay(b);
    assert_string_equal(t1, t2);
    assert_int_equal(b->input_count, 18);
    assert_int_equal(b->fact_count, 5);
    assert_true(b->facts[2].value == 0.29327 && b->facts[3].value == 1e-12);
    assert_int_equal(b->trace_count[0], 9);
    assert_true(b->hashes[0].tick == 1 && b->hashes[1].is_double);
    /* The canonical text: 16 inputs a line, 8 trace values a line, hashes float first. */
    assert_non_null(strstr(t1, "input 1R 2L 3U 4D 5J 6A 7. 8RJ 9LJA 10. 11R 12R 13R 14R 15R 16R\ninput 17R 18R\n"));
    assert_non_null(strstr(t1, "hash float 1 0x1000000000000000\n"
                               "trace float 1 00000001 00000002 00000003 00000004 00000005 00000006 00000007 00000008\n"
                               "trace float 9 00000009\nhash double 500 0x00000000000000ff\n"));
    assert_non_null(strstr(t1, "name \"a b\"\nlevel \"x y.ntl\"\nseed 3\ndt 0.0166667\nticks 500\n"));
    free(t1);
    free(t2);
    nt_replay_destroy(a);
    nt_replay_destroy(b);
}

static void test_set_inputs_and_hashes(void **state)
{
    (void)state;
    nt_replay *rp = NULL;
    assert_int_equal(nt_replay_create(0, &rp), NT_ERR_OUT_OF_RANGE);
    assert_int_equal(nt_replay_create(50, &rp), NT_OK);
    nt_text_error e;
    assert_int_equal(nt_replay_set_inputs(rp, "--input", "", 0, &e), NT_OK);
    assert_int_equal(rp->input_count, 0);
    assert_int_equal(nt_replay_set_inputs(rp, "--input", "20R  5RJ\t25.", 12, &e), NT_OK);
    assert_int_equal(rp->input_count, 3);
    assert_int_equal(nt_replay_keys_at(rp, 21), NT_INPUT_RIGHT | NT_INPUT_JUMP);
    /* A bad string leaves the inputs as they were. */
    assert_int_equal(nt_replay_set_inputs(rp, "--input", "20R 31.", 7, &e), NT_ERR_PARSE);
    assert_string_equal(e.message, "--input:1:5: inputs cover 51 ticks, more than the replay's 50");
    assert_int_equal(rp->input_count, 3);
    nt_replay_hash h[2] = {{10, false, 0xabc, 0}, {20, false, 0xdef, 0}};
    uint32_t tr[3] = {1, 2, 3};
    assert_int_equal(nt_replay_set_hashes(rp, 1, h, 2, tr, 3), NT_OK);
    h[0].hash = 0x111;
    assert_int_equal(nt_replay_set_hashes(rp, 0, h, 1, NULL, 0), NT_OK);
    assert_int_equal(rp->hash_count, 3);
    assert_true(!rp->hashes[0].is_double && rp->hashes[0].hash == 0x111);
    assert_true(rp->hashes[1].is_double && rp->hashes[2].is_double && rp->hashes[2].hash == 0xdef);
    assert_int_equal(rp->trace_count[1], 3);
    assert_int_equal(rp->trace_count[0], 0);
    h[1].tick = 5; /* not increasing */
    assert_int_equal(nt_replay_set_hashes(rp, 0, h, 2, NULL, 0), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(rp->hash_count, 3);
    nt_replay_destroy(rp);
}

/* Every allocation of a parse fails in turn: reported, and nothing is left allocated. */
static void test_parse_out_of_memory(void **state)
{
    (void)state;
    static const char text[] = HEAD "input 1R 2L 3J 4A 5. 6R 7L 8J 9A 10. 11R 12L 13J\n"
                                    "expect complete by 9\nexpect score >= 1 at 9\nhash float 5 0x0000000000000001\n"
                                    "trace float 1 00000001 00000002\ntrace double 1 00000001\n";
    int failures = 0;
    for (long budget = 0;; budget++) {
        failalloc_begin(budget);
        nt_replay *rp = NULL;
        nt_text_error e;
        nt_status s = nt_replay_parse("r.ntr", text, sizeof text - 1, &rp, &e);
        if (s == NT_OK) nt_replay_destroy(rp);
        assert_int_equal(failalloc_end(), 0);
        if (s == NT_OK) break;
        failures++;
        if (s != NT_ERR_OUT_OF_MEMORY) fprintf(stderr, "budget %ld: %s\n", budget, e.message);
        assert_int_equal(s, NT_ERR_OUT_OF_MEMORY);
        assert_null(rp);
        assert_string_equal(e.message, "r.ntr: out of memory");
    }
    assert_true(failures >= 5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_roundtrip),
        cmocka_unit_test(test_set_inputs_and_hashes),
        cmocka_unit_test(test_parse_out_of_memory),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
