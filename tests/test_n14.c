/* N v1.4 import, on level strings written here: tile order (column by column),
 * the border, every supported object, warnings for the rest, errors with their
 * positions, picking one level of several. */
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

#define COLS 31
#define ROWS 23

/* 713 tile characters, all EMPTY ('0'). */
static void blank_tiles(char t[COLS * ROWS + 1])
{
    memset(t, '0', COLS * ROWS);
    t[COLS * ROWS] = '\0';
}

/* Set playable cell (col, row) to tile id: N stores column by column. */
static void put(char t[], int col, int row, int id) { t[col * ROWS + row] = (char)('0' + id); }

static char g_text[8192];

static const char *level_string(const char *name, const char *tiles, const char *objects)
{
    snprintf(g_text, sizeof g_text, "$%s#someone##%s|%s#", name, tiles, objects);
    return g_text;
}

typedef struct warnings {
    int count;
    char text[16][256];
} warnings;

static void on_warning(const char *message, void *ctx)
{
    warnings *w = ctx;
    if (w->count < 16) snprintf(w->text[w->count], sizeof w->text[0], "%s", message);
    w->count++;
}

static nt_level *import_ok(const char *text, int index, warnings *w)
{
    nt_level *lv = NULL;
    nt_text_error e;
    nt_status s = nt_level_import_n14("t.n", text, strlen(text), index, &lv, NULL, &e, on_warning, w);
    if (s != NT_OK) fprintf(stderr, "unexpected error: %s\n", e.message);
    assert_int_equal(s, NT_OK);
    return lv;
}

static void import_fails(const char *text, const char *message)
{
    nt_level *lv = (nt_level *)&lv;
    nt_text_error e;
    nt_status s = nt_level_import_n14("t.n", text, strlen(text), 0, &lv, NULL, &e, NULL, NULL);
    if (s != NT_ERR_PARSE || strcmp(e.message, message) != 0) fprintf(stderr, "expected: %s\ngot:      %s\n", message, e.message);
    assert_int_equal(s, NT_ERR_PARSE);
    assert_null(lv);
    assert_string_equal(e.message, message);
}

static int tile_at(const nt_level *lv, int x, int y) { return lv->tiles[y * lv->width + x]; }

static void test_tiles_and_border(void **state)
{
    (void)state;
    char t[COLS * ROWS + 1];
    blank_tiles(t);
    put(t, 0, 0, NT_TILE_45DEGpn);
    put(t, 30, 22, NT_TILE_HALFl);
    put(t, 5, 7, NT_TILE_CONVEXpn);
    put(t, 7, 5, NT_TILE_HALFd);
    put(t, 30, 0, NT_TILE_FULL);
    warnings w = {0};
    nt_level *lv = import_ok(level_string("A \"quoted\" name", t, ""), 0, &w);
    assert_int_equal(w.count, 0);
    assert_int_equal(lv->width, 33);
    assert_int_equal(lv->height, 25);
    assert_true(lv->cell_size == 24);
    assert_string_equal(lv->title, "A _quoted_ name");
    assert_string_equal(lv->author, "someone");
    /* Playable (col, row) is map cell (col + 1, row + 1). */
    assert_int_equal(tile_at(lv, 1, 1), NT_TILE_45DEGpn);
    assert_int_equal(tile_at(lv, 31, 23), NT_TILE_HALFl);
    assert_int_equal(tile_at(lv, 6, 8), NT_TILE_CONVEXpn);
    assert_int_equal(tile_at(lv, 8, 6), NT_TILE_HALFd);
    assert_int_equal(tile_at(lv, 31, 1), NT_TILE_FULL);
    int full = 0, empty = 0;
    for (int y = 0; y < 25; y++)
        for (int x = 0; x < 33; x++) {
            int border = x == 0 || y == 0 || x == 32 || y == 24;
            if (border) assert_int_equal(tile_at(lv, x, y), NT_TILE_FULL);
            full += tile_at(lv, x, y) == NT_TILE_FULL;
            empty += tile_at(lv, x, y) == NT_TILE_EMPTY;
        }
    assert_int_equal(full, 2 * 33 + 2 * 23 + 1);
    assert_int_equal(empty, 31 * 23 - 5);
    assert_false(lv->has_player);
    assert_int_equal(nt_level_validate(lv, NULL), NT_OK);
    nt_level_destroy(lv);
}

/* Found by the fuzzer: huge coordinates and directions must be judged, not cast. */
static void test_huge_numbers(void **state)
{
    (void)state;
    char t[COLS * ROWS + 1];
    blank_tiles(t);
    warnings w = {0};
    nt_level *lv = import_ok(level_string("huge", t, "5^60,516!7^300,228,3e9!0^-2.5e27,3e38!12^4e30,1"), 0, &w);
    assert_true(lv->has_player);
    assert_int_equal(lv->body_count, 0); /* the platform, the gold and the pad are all skipped with warnings */
    assert_true(w.count >= 2);
    nt_level_destroy(lv);
}

static void test_objects(void **state)
{
    (void)state;
    char t[COLS * ROWS + 1];
    blank_tiles(t);
    put(t, 7, 8, NT_TILE_FULL); /* map cell (8, 9): behind the diagonal launch pad at (204, 228) */
    const char *objects = "5^60,516!0^108,540!0^132,540!12^30,546!11^588,492,168,156!7^324,228,3!7^300,228,0!"
                          "2^36,576,0,-1!2^204,228,0.707106781186547,-0.707106781186547!2^400,300,0,-1!1^408,264!"
                          "9^60,60,0,1,15,15,0,-1,0!5^100,100!7^36,48,3";
    warnings w = {0};
    const char *text = level_string("objects", t, objects);
    nt_level *lv = import_ok(text, 0, &w);
    assert_true(lv->has_player && lv->player.x == 60 && lv->player.y == 516);
    /* gold: static sensors with a score; the mine: a deadly sensor; the block: dynamic; the locked door;
     * the one-way platform facing right */
    assert_int_equal(lv->body_count, 6);
    const nt_level_body *g = &lv->bodies[nt_level_find_body(lv, "gold2")];
    assert_true(g->type == NT_BODY_STATIC && g->is_sensor && g->score == 1 && !g->deadly);
    assert_true(g->shape.type == NT_SHAPE_CIRCLE && g->shape.half.x == 6 && g->position.x == 132);
    const nt_level_body *m = &lv->bodies[nt_level_find_body(lv, "mine1")];
    assert_true(m->is_sensor && m->deadly && m->score == 0 && m->shape.half.x == 4);
    const nt_level_body *b = &lv->bodies[nt_level_find_body(lv, "block1")];
    assert_true(b->type == NT_BODY_DYNAMIC && b->shape.type == NT_SHAPE_AABB && b->shape.half.x == (nt_real)9.6);
    /* the exit door: a one-cell exit region that needs its switch, a switch region before it */
    int ex = nt_level_find_region(lv, "exit"), sw = nt_level_find_region(lv, "exitswitch");
    assert_true(ex >= 0 && sw >= 0 && sw < ex);
    assert_int_equal(lv->regions[ex].kind, NT_REGION_EXIT);
    assert_int_equal(lv->regions[ex].needs, sw + 1);
    assert_true(lv->regions[ex].lo.x == 576 && lv->regions[ex].lo.y == 480 && lv->regions[ex].hi.x == 600);
    assert_true(lv->regions[sw].kind == NT_REGION_SWITCH && lv->regions[sw].lo.x == 156);
    /* the locked door 9^60,60,0,1,15,15,0,-1,0: its switch around (60, 60), the door a
     * flat box (not upright: 0) through the centre of cell (15 - 1, 15 + 0) */
    const nt_level_body *d = &lv->bodies[nt_level_find_body(lv, "lockeddoor1")];
    int ds = nt_level_find_region(lv, "doorswitch1");
    assert_true(ds >= 0 && lv->regions[ds].kind == NT_REGION_SWITCH && lv->regions[ds].lo.x == 48);
    assert_true(d->type == NT_BODY_STATIC && d->door == NT_DOOR_LOCKED && d->door_switch == ds + 1 && !d->is_sensor);
    assert_true(d->position.x == 14 * 24 + 12 && d->position.y == 15 * 24 + 12);
    assert_true(d->shape.half.x == 12 && d->shape.half.y == 3);
    /* one-way facing up at (324, 228) = cell (13, 9): a one-way HALFu; (36, 48): cell (1, 2) */
    assert_int_equal(tile_at(lv, 13, 9), NT_TILE_HALFu);
    assert_int_equal(lv->cell_flags[9 * 33 + 13], NT_CELL_ONE_WAY);
    assert_int_equal(tile_at(lv, 1, 2), NT_TILE_HALFu);
    assert_int_equal(tile_at(lv, 12, 9), NT_TILE_EMPTY); /* the one facing right is a body over the cell's right half */
    const nt_level_body *ow = &lv->bodies[nt_level_find_body(lv, "oneway1")];
    assert_true(ow->type == NT_BODY_STATIC && ow->one_way == NT_ONE_WAY_RIGHT && !ow->is_sensor);
    assert_true(ow->position.x == 12 * 24 + 18 && ow->position.y == 9 * 24 + 12 && ow->shape.half.x == 6 && ow->shape.half.y == 12);
    /* launch pads: the cell behind gets material 1, which bounces fully */
    assert_int_equal(lv->cell_materials[24 * 33 + 1], 1);  /* floor pad at (36, 576): border cell (1, 24) */
    assert_int_equal(lv->cell_materials[9 * 33 + 8], 1);   /* diagonal pad: behind it, cell (8, 9) */
    assert_true(lv->materials[1].bounce == 1);
    assert_int_equal(w.count, 2);
    /* Warnings name the object's column in the line. */
    char want[2][256];
    const char *at_pad = strstr(text, "2^400");
    const char *at_5 = strstr(text, "5^100");
    snprintf(want[0], 256, "t.n:1:%d: warning: launch pad at 400,300 has no tile behind it; skipped", (int)(at_pad - text) + 1);
    snprintf(want[1], 256, "t.n:1:%d: warning: a second player spawn at 100,100; skipped", (int)(at_5 - text) + 1);
    for (int i = 0; i < 2; i++) assert_string_equal(w.text[i], want[i]);
    assert_int_equal(nt_level_validate(lv, NULL), NT_OK);
    /* The import writes and reads back as any level. */
    size_t n = nt_level_write(lv, NULL, 0);
    char *out = malloc(n + 1);
    nt_level_write(lv, out, n + 1);
    nt_level *back = NULL;
    assert_int_equal(nt_level_parse("out.ntl", out, n, &back, NULL), NT_OK);
    assert_memory_equal(back->tiles, lv->tiles, 33 * 25);
    assert_memory_equal(back->cell_flags, lv->cell_flags, 33 * 25);
    assert_int_equal(back->body_count, 6);
    assert_int_equal(back->bodies[nt_level_find_body(back, "oneway1")].one_way, NT_ONE_WAY_RIGHT);
    assert_int_equal(back->regions[ex].needs, sw + 1);
    assert_int_equal(back->bodies[nt_level_find_body(back, "lockeddoor1")].door, NT_DOOR_LOCKED);
    nt_level_destroy(back);
    free(out);
    nt_level_destroy(lv);
}

/* Objects ntile does not have are named in their warnings; trap and plain doors. */
static void test_object_names_and_doors(void **state)
{
    (void)state;
    char t[COLS * ROWS + 1];
    blank_tiles(t);
    const char *objects = "3^100,100!4^100,100,1!6^100,100,0,0,0,0!8^100,100,1!10^100,100!13^1,1!"
                          "9^84,324,1,0,10,14,1,0,0!9^204,204,0,0,1,14,1,0,0!9^84,324,1,1,5,5,1,0,0!9^84,324,0,1,40,5,1,0,0!"
                          "7^60,420,1!7^84,420,2!7^12,12,0";
    warnings w = {0};
    const char *text = level_string("names", t, objects);
    nt_level *lv = import_ok(text, 0, &w);
    static const char *const want[] = {
        "N object type 3 (gauss turret) is not supported; skipped",
        "N object type 4 (floor guard) is not supported; skipped",
        "N object type 6 (drone) is not supported; skipped",
        "N object type 8 (thwump) is not supported; skipped",
        "N object type 10 (rocket launcher) is not supported; skipped",
        "N object type 13 is not an N object; skipped",
        "door at cell 5,5 is both a trap door and a locked door; skipped",
        "door in cell 40,5 lies outside the level; skipped",
        "one-way platform facing right at 12,12 is not in an empty cell; skipped",
    };
    assert_int_equal(w.count, 9);
    for (int i = 0; i < 9; i++) {
        const char *tail = strstr(w.text[i], ": warning: ");
        if (!tail || strcmp(tail + 11, want[i]) != 0) fail_msg("warning %d: '%s', expected '...: warning: %s'", i, w.text[i], want[i]);
    }
    /* The trap door: upright in cell (10, 14), its switch around (84, 324); the plain door in cell (1, 14). */
    const nt_level_body *trap = &lv->bodies[nt_level_find_body(lv, "trapdoor1")];
    int sw = nt_level_find_region(lv, "doorswitch1");
    assert_true(sw >= 0 && lv->regions[sw].kind == NT_REGION_SWITCH && lv->regions[sw].lo.x == 72 && lv->regions[sw].lo.y == 312);
    assert_true(trap->door == NT_DOOR_TRAP && trap->door_switch == sw + 1);
    assert_true(trap->position.x == 10 * 24 + 12 && trap->position.y == 14 * 24 + 12);
    assert_true(trap->shape.half.x == 3 && trap->shape.half.y == 12);
    const nt_level_body *plain = &lv->bodies[nt_level_find_body(lv, "door1")];
    assert_true(plain->door == NT_DOOR_PLAIN && plain->door_switch == 0 && plain->position.x == 36);
    /* One-way platforms facing down and left: the bottom and the left half of their cells. */
    const nt_level_body *down = &lv->bodies[nt_level_find_body(lv, "oneway1")];
    const nt_level_body *leftw = &lv->bodies[nt_level_find_body(lv, "oneway2")];
    assert_true(down->one_way == NT_ONE_WAY_DOWN && down->position.x == 2 * 24 + 12 && down->position.y == 17 * 24 + 18);
    assert_true(down->shape.half.x == 12 && down->shape.half.y == 6);
    assert_true(leftw->one_way == NT_ONE_WAY_LEFT && leftw->position.x == 3 * 24 + 6 && leftw->position.y == 17 * 24 + 12);
    assert_int_equal(lv->body_count, 4);
    assert_int_equal(lv->region_count, 1);
    assert_int_equal(nt_level_validate(lv, NULL), NT_OK);
    nt_level_destroy(lv);
}

static void test_errors(void **state)
{
    (void)state;
    char t[COLS * ROWS + 1];
    blank_tiles(t);
    import_fails("#x#y##|#", "t.n:1:1: an N level starts with '$' ($NAME#AUTHOR##TILES|OBJECTS#)");
    import_fails("$name", "t.n:1:6: missing '#' after the level name");
    import_fails("$name#me#x", "t.n:1:10: expected '##' before the tiles");
    import_fails("$name#me##000|#", "t.n:1:14: the tiles have 3 characters, expected 713 (31 x 23)");
    char buf[2048];
    snprintf(buf, sizeof buf, "$n#a##%s", t);
    import_fails(buf, "t.n:1:720: missing '|' after the 713 tile characters");
    snprintf(buf, sizeof buf, "$n#a##%s|0^1,2", t);
    import_fails(buf, "t.n:1:726: missing the closing '#' after the objects");
    t[100] = 'z';
    snprintf(buf, sizeof buf, "$n#a##%s|#", t);
    import_fails(buf, "t.n:1:107: unknown N tile character 'z' (expected '0'..'Q')");
    t[100] = '0';
    snprintf(buf, sizeof buf, "$n#a##%s|0^1,2!0^x,2#", t);
    import_fails(buf, "t.n:1:729: object value 'x' is not a number");
    snprintf(buf, sizeof buf, "$n#a##%s|0^1,2!11^1,2#", t);
    import_fails(buf, "t.n:1:727: object type 11 (exit door) needs 4 values, got 2");
    snprintf(buf, sizeof buf, "$n#a##%s|0-1,2#", t);
    import_fails(buf, "t.n:1:721: object '0-1,2' has no '^' (expected TYPE^X,Y,...)");
    snprintf(buf, sizeof buf, "$n#a##%s|q^1,2#", t);
    import_fails(buf, "t.n:1:721: object type 'q' is not an integer");
    import_fails("", "t.n:1:1: no N level in the text");
    import_fails("\n  \n", "t.n:3:1: no N level in the text");
}

static void test_several_levels(void **state)
{
    (void)state;
    char t[COLS * ROWS + 1], text[4 * 1024];
    blank_tiles(t);
    int n = 0;
    for (int i = 0; i < 3; i++) {
        put(t, i, 0, NT_TILE_FULL);
        n += snprintf(text + n, sizeof text - (size_t)n, "$level %d#a##%s|#\n%s", i, t, i == 0 ? "\n" : "");
    }
    nt_level *lv = NULL;
    int count = 0;
    assert_int_equal(nt_level_import_n14("t.n", text, strlen(text), 2, &lv, &count, NULL, NULL, NULL), NT_OK);
    assert_int_equal(count, 3);
    assert_string_equal(lv->title, "level 2");
    assert_int_equal(tile_at(lv, 3, 1), NT_TILE_FULL);
    nt_level_destroy(lv);
    nt_text_error e;
    assert_int_equal(nt_level_import_n14("t.n", text, strlen(text), 5, &lv, &count, &e, NULL, NULL), NT_ERR_PARSE);
    assert_null(lv);
    assert_string_equal(e.message, "t.n:5:1: level 6 asked for, but the text holds 3 levels");
}

static void test_out_of_memory(void **state)
{
    (void)state;
    char t[COLS * ROWS + 1];
    blank_tiles(t);
    const char *text = level_string("oom", t, "5^60,516!0^108,540!0^132,540!12^30,546!11^588,492,168,156!1^408,264");
    int failures = 0;
    for (long budget = 0;; budget++) {
        failalloc_begin(budget);
        nt_level *lv = NULL;
        nt_text_error e;
        nt_status s = nt_level_import_n14("t.n", text, strlen(text), 0, &lv, NULL, &e, NULL, NULL);
        if (s == NT_OK) nt_level_destroy(lv);
        assert_int_equal(failalloc_end(), 0);
        if (s == NT_OK) break;
        failures++;
        assert_int_equal(s, NT_ERR_OUT_OF_MEMORY);
        assert_null(lv);
    }
    assert_true(failures >= 5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tiles_and_border),
        cmocka_unit_test(test_objects),
        cmocka_unit_test(test_huge_numbers),
        cmocka_unit_test(test_object_names_and_doors),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_several_levels),
        cmocka_unit_test(test_out_of_memory),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
