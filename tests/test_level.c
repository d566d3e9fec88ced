/* Levels: the .ntl parser (every error path with its exact message and position),
 * the canonical writer (load -> save -> load gives the same level and the same
 * text, for hand-written, random and shipped levels), failed loads under
 * allocation failure (nothing left allocated), and level -> world. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "failalloc.h"
#include "ntile/ntile.h"

#define R(x) ((nt_real)(x))

/* A small valid level: 3 x 2 cells, a FULL floor. */
#define HEAD "ntile-level 1\nsize 3 2\n"
#define GRID "tiles\n|#.#|\n|###|\n"

static nt_level *parse_ok(const char *text)
{
    nt_level *lv = NULL;
    nt_text_error e;
    nt_status s = nt_level_parse("t.ntl", text, strlen(text), &lv, &e);
    if (s != NT_OK) fprintf(stderr, "unexpected error: %s\n", e.message);
    assert_int_equal(s, NT_OK);
    assert_non_null(lv);
    return lv;
}

/* The text must fail with exactly this message (which names its position). */
static void parse_fails(const char *text, const char *message)
{
    nt_level *lv = (nt_level *)&lv; /* must be reset to NULL */
    nt_text_error e;
    nt_status s = nt_level_parse("t.ntl", text, strlen(text), &lv, &e);
    if (s != NT_ERR_PARSE || strcmp(e.message, message) != 0)
        fprintf(stderr, "input:\n%s\nexpected: %s\ngot:      %s (%s)\n", text, message, e.message, nt_status_string(s));
    assert_int_equal(s, NT_ERR_PARSE);
    assert_null(lv);
    assert_string_equal(e.message, message);
    /* line and column agree with the message */
    char prefix[64];
    snprintf(prefix, sizeof prefix, "t.ntl:%d:%d: ", e.line, e.column);
    assert_true(strncmp(e.message, prefix, strlen(prefix)) == 0);
}

static char *write_level(const nt_level *lv)
{
    size_t n = nt_level_write(lv, NULL, 0);
    char *buf = malloc(n + 1);
    assert_non_null(buf);
    assert_int_equal(nt_level_write(lv, buf, n + 1), n);
    assert_int_equal(strlen(buf), n);
    return buf;
}

/* ---------------------------------------------------------------- parsing */

static void test_parse_minimal_and_defaults(void **state)
{
    (void)state;
    nt_level *lv = parse_ok(HEAD GRID);
    nt_world_def wd = nt_default_world_def();
    assert_int_equal(lv->width, 3);
    assert_int_equal(lv->height, 2);
    assert_true(lv->cell_size == 24);
    assert_true(lv->gravity.x == wd.gravity.x && lv->gravity.y == wd.gravity.y);
    assert_int_equal(lv->friction_model, NT_FRICTION_N);
    assert_true(lv->materials[0].friction == wd.tile_material.friction);
    assert_true(lv->materials[5].bounce == wd.tile_material.bounce);
    const uint8_t want[6] = {1, 0, 1, 1, 1, 1};
    assert_memory_equal(lv->tiles, want, 6);
    assert_false(lv->has_player);
    assert_int_equal(lv->body_count, 0);
    nt_level_destroy(lv);
}

static void test_parse_everything(void **state)
{
    (void)state;
    const char *text = "ntile-level 1\n"
                       "# a comment line\n"
                       "title \"Test level\"   # trailing comment\n"
                       "author \"me\"\n"
                       "size 4 3\n"
                       "cell 16\n"
                       "gravity 0 -10.5\n"
                       "friction-model coulomb\n"
                       "sleep off\n"
                       "seed 99\n"
                       "material 0 0.5 0.25\n"
                       "material 3 2 1\n"
                       "body-material 0.7 0.1\n"
                       "body-drag 0.5\n"
                       "tiles\n"
                       "|.2>Q|\n"
                       "\n"
                       "# comments between rows\n"
                       "|#..P|  # row comment\n"
                       "|####|\n"
                       "materials\n"
                       "|...f|\n"
                       "|.3..|\n"
                       "|a..9|\n"
                       "flags\n"
                       "|....|\n"
                       "|...-|\n"
                       "|....|\n"
                       "player 8 8\n"
                       "path p1 loop speed 10 wait 0.5 points 0 0 10 0 10 10\n"
                       "path p2 orbit speed 5 center 30 20 radius 4\n"
                       "region r1 score 0 0 16 16 value 7\n"
                       "region r2 exit 1 2 3 4\n"
                       "body b1 dynamic circle 3 at 5 6 vel 1 -2 mass 2.5 material 1.5 0.5 drag 0.25 gravity-scale -1 "
                       "category 0x4 mask 12 no-sleep asleep\n"
                       "body k1 kinematic box 8 2 at 1 1 path p1 phase 0.25\n"
                       "body s1 static circle 2 at 9 9 sensor score 3 deadly\n"
                       "body t1 dynamic box 1 1 at 0 0 template\n"
                       "body g1 dynamic box 1 2 at 20 4 repeat 3 2 4 5\n"
                       "spawner sp1 t1 every 10 start 5 limit 4 attach k1 offset 0 3 jitter 2\n"
                       "spawner sp2 t1 action limit 1\n";
    nt_level *lv = parse_ok(text);
    assert_string_equal(lv->title, "Test level");
    assert_string_equal(lv->author, "me");
    assert_true(lv->cell_size == 16);
    assert_true(lv->gravity.y == R(-10.5));
    assert_int_equal(lv->friction_model, NT_FRICTION_COULOMB);
    assert_false(lv->enable_sleep);
    assert_true(lv->seed == 99);
    assert_true(lv->materials[0].friction == R(0.5) && lv->materials[0].bounce == R(0.25));
    assert_true(lv->materials[3].friction == 2 && lv->materials[3].bounce == 1);
    assert_true(lv->materials[4].friction == R(0.5)); /* unset: material 0 */
    assert_true(lv->body_material.friction == R(0.7));
    assert_true(lv->body_linear_drag == R(0.5));
    const uint8_t tiles[12] = {0, 2, 14, 33, 1, 0, 0, 32, 1, 1, 1, 1};
    assert_memory_equal(lv->tiles, tiles, 12);
    const uint8_t mats[12] = {0, 0, 0, 15, 0, 3, 0, 0, 10, 0, 0, 9};
    assert_memory_equal(lv->cell_materials, mats, 12);
    assert_int_equal(lv->cell_flags[7], NT_CELL_ONE_WAY);
    assert_int_equal(lv->cell_flags[6], 0);
    assert_true(lv->has_player && lv->player.x == 8);
    assert_int_equal(lv->path_count, 2);
    assert_int_equal(lv->paths[0].mode, NT_PATH_LOOP);
    assert_int_equal(lv->paths[0].point_count, 3);
    assert_true(lv->paths[0].wait == R(0.5) && lv->paths[0].points[2].y == 10);
    assert_int_equal(lv->paths[1].mode, NT_PATH_ORBIT);
    assert_true(lv->paths[1].radius == 4 && lv->paths[1].center.x == 30);
    assert_int_equal(lv->region_count, 2);
    assert_int_equal(lv->regions[0].kind, NT_REGION_SCORE);
    assert_int_equal(lv->regions[0].value, 7);
    assert_int_equal(lv->regions[1].kind, NT_REGION_EXIT);
    assert_int_equal(lv->body_count, 5);
    const nt_level_body *b = &lv->bodies[0];
    assert_int_equal(b->type, NT_BODY_DYNAMIC);
    assert_int_equal(b->shape.type, NT_SHAPE_CIRCLE);
    assert_true(b->shape.half.x == 3 && b->velocity.y == -2 && b->mass == R(2.5));
    assert_true(b->material.friction == R(1.5) && b->linear_drag == R(0.25) && b->gravity_scale == -1);
    assert_true(b->category == 4 && b->mask == 12 && !b->enable_sleep && !b->is_awake && b->path == -1);
    b = &lv->bodies[1];
    assert_true(b->path == 0 && b->phase == R(0.25) && b->type == NT_BODY_KINEMATIC);
    assert_true(b->material.friction == R(0.7)); /* body-material default */
    b = &lv->bodies[2];
    assert_true(b->is_sensor && b->score == 3 && b->deadly);
    assert_true(lv->bodies[3].is_template);
    assert_true(lv->bodies[4].repeat_x == 3 && lv->bodies[4].repeat_y == 2 && lv->bodies[4].repeat_step.y == 5);
    assert_int_equal(nt_level_instance_count(lv), 3 + 6);
    assert_int_equal(lv->spawner_count, 2);
    const nt_level_spawner *sp = &lv->spawners[0];
    assert_true(sp->template_body == 3 && sp->trigger == NT_SPAWN_EVERY && sp->every == 10 && sp->start == 5);
    assert_true(sp->limit == 4 && sp->attach == 1 && sp->offset.y == 3 && sp->jitter == 2);
    assert_true(lv->spawners[1].trigger == NT_SPAWN_ACTION && lv->spawners[1].attach == -1);
    assert_int_equal(nt_level_find_body(lv, "s1"), 2);
    assert_int_equal(nt_level_find_region(lv, "r2"), 1);
    assert_int_equal(nt_level_find_path(lv, "p2"), 1);
    assert_int_equal(nt_level_find_body(lv, "nope"), -1);
    assert_int_equal(nt_level_validate(lv, NULL), NT_OK);
    nt_level_destroy(lv);
}

static void test_line_endings_and_final_newline(void **state)
{
    (void)state;
    nt_level *a = parse_ok("ntile-level 1\r\nsize 3 2\r\ntiles\r\n|#.#|\r\n|###|\r\n");
    nt_level *b = parse_ok("ntile-level 1\nsize 3 2\ntiles\n|#.#|\n|###|"); /* no final newline */
    assert_memory_equal(a->tiles, b->tiles, 6);
    nt_level_destroy(a);
    nt_level_destroy(b);
}

/* ---------------------------------------------------------------- errors */

static void test_header_errors(void **state)
{
    (void)state;
    parse_fails("", "t.ntl:1:1: empty file: expected 'ntile-level 1' on the first line");
    parse_fails("\n" HEAD GRID, "t.ntl:1:1: expected 'ntile-level 1' on the first line");
    parse_fails("  ntile-map 1\n", "t.ntl:1:3: expected 'ntile-level 1' on the first line");
    parse_fails("ntile-level 2\n", "t.ntl:1:13: unsupported ntile-level version 2 (this ntile reads version 1)");
    parse_fails("ntile-level\n", "t.ntl:1:12: missing fields: expected 'ntile-level VERSION'");
    parse_fails("ntile-level one\n", "t.ntl:1:13: version 'one' is not an integer");
    parse_fails("ntile-level 1 x\n", "t.ntl:1:15: unexpected field: expected 'ntile-level VERSION'");
}

static void test_setting_errors(void **state)
{
    (void)state;
    parse_fails("ntile-level 1\nsize 0 2\n", "t.ntl:2:6: width '0' is out of range 1..4096");
    parse_fails("ntile-level 1\nsize 3 4097\n", "t.ntl:2:8: height '4097' is out of range 1..4096");
    parse_fails("ntile-level 1\nsize 3.5 2\n", "t.ntl:2:6: width '3.5' is not an integer");
    parse_fails("ntile-level 1\nsize 99999999999999999999 2\n",
                "t.ntl:2:6: width '99999999999999999999' is out of range 1..4096");
    parse_fails("ntile-level 1\nsize 3\n", "t.ntl:2:7: missing fields: expected 'size WIDTH HEIGHT'");
    parse_fails(HEAD "size 3 2\n", "t.ntl:3:1: duplicate 'size' (first at line 2)");
    parse_fails(HEAD "cell 0\n", "t.ntl:3:6: cell size '0' must be > 0");
    parse_fails(HEAD "cell -24\n", "t.ntl:3:6: cell size '-24' must be > 0");
    parse_fails(HEAD "cell nan\n", "t.ntl:3:6: cell size 'nan' is not a finite number");
    parse_fails(HEAD "gravity 0 inf\n", "t.ntl:3:11: gravity y 'inf' is not a finite number");
    parse_fails(HEAD "gravity 0 -Infinity\n", "t.ntl:3:11: gravity y '-Infinity' is not a finite number");
    parse_fails(HEAD "gravity 1e999 0\n", "t.ntl:3:9: gravity x '1e999' is not a finite number");
    parse_fails(HEAD "gravity 0x10 0\n", "t.ntl:3:9: gravity x '0x10' is not a number");
    parse_fails(HEAD "gravity 1.5.2 0\n", "t.ntl:3:9: gravity x '1.5.2' is not a number");
    parse_fails(HEAD "gravity 1e 0\n", "t.ntl:3:9: gravity x '1e' is not a number");
#if !NT_REAL_IS_DOUBLE
    parse_fails(HEAD "gravity 1e300 0\n", "t.ntl:3:9: gravity x '1e300' is too large for float");
#endif
    parse_fails(HEAD "friction-model box2d\n", "t.ntl:3:16: unknown friction model 'box2d' (expected n or coulomb)");
    parse_fails(HEAD "sleep maybe\n", "t.ntl:3:7: expected on or off, got 'maybe'");
    parse_fails(HEAD "seed -1\n", "t.ntl:3:6: seed '-1' is out of range 0..9223372036854775807");
    parse_fails(HEAD "material 16 0 0\n", "t.ntl:3:10: material index '16' is out of range 0..15");
    parse_fails(HEAD "material 1 -0.5 0\n", "t.ntl:3:12: material friction '-0.5' must be >= 0");
    parse_fails(HEAD "material 1 0.5 1.5\n", "t.ntl:3:16: material bounce '1.5' is above 1");
    parse_fails(HEAD "material 1 0 0\nmaterial 1 0 0\n", "t.ntl:4:10: duplicate material 1 (first at line 3)");
    /* The friction limit of N's model is checked when the settings are complete,
     * so the model may come after the material. */
    parse_fails(HEAD "material 2 1.5 0\n" GRID,
                "t.ntl:3:12: material friction 1.5 is above 1, the limit of the N friction model");
    nt_level_destroy(parse_ok(HEAD "material 2 1.5 0\nfriction-model coulomb\n" GRID));
    parse_fails(HEAD "body-material 2 0\n" GRID,
                "t.ntl:3:15: body-material friction 2 is above 1, the limit of the N friction model");
    parse_fails(HEAD "body-drag -1\n", "t.ntl:3:11: body drag '-1' must be >= 0");
    parse_fails(HEAD "title Level\n", "t.ntl:3:7: title must be a quoted string, got 'Level'");
    parse_fails(HEAD "title \"a \\ b\"\n", "t.ntl:3:10: title holds a control character, '\\' or '\"'");
    parse_fails(HEAD "title \"unterminated\n", "t.ntl:3:7: unterminated string (no closing '\"' on this line)");
    parse_fails(HEAD "title \"a\"b\n", "t.ntl:3:10: text right after a closing quote");
    parse_fails(HEAD "gravity 0 1\nwind 3\n", "t.ntl:4:1: unknown keyword 'wind'");
    parse_fails(HEAD GRID "gravity 0 1\n", "t.ntl:6:1: 'gravity' must come before the 'tiles' block");
    parse_fails("ntile-level 1\ntiles\n", "t.ntl:2:1: 'tiles' before 'size' (the map size must come first)");
}

static void test_grid_errors(void **state)
{
    (void)state;
    parse_fails(HEAD "tiles\n|#z#|\n|###|\n",
                "t.ntl:4:3: unknown tile code 'z' (expected '.', '#' or an N code '2'..'Q', see the legend)");
    parse_fails(HEAD "tiles\n|#0#|\n|###|\n", "t.ntl:4:3: unknown tile code '0' (EMPTY is '.', FULL is '#')");
    parse_fails(HEAD "tiles\n|#.|\n|###|\n", "t.ntl:4:4: ragged row: 2 codes, expected 3");
    parse_fails(HEAD "tiles\n|#.##|\n|###|\n", "t.ntl:4:5: ragged row: more than 3 codes (no '|' after code 3)");
    parse_fails(HEAD "tiles\n|#.#\n|###|\n",
                "t.ntl:4:5: ragged row: the row ends after 3 codes without a closing '|' (expected 3)");
    parse_fails(HEAD "tiles\n  #.#\n", "t.ntl:4:3: expected row 1 of 2 of the 'tiles' block ('|', 3 codes, '|'), got '#.#'");
    parse_fails(HEAD "tiles\n# a comment\n#\n..#\n", "t.ntl:6:1: expected row 1 of 2 of the 'tiles' block ('|', 3 codes, '|'), got '..#'");
    parse_fails(HEAD "tiles\n|#.#| x\n", "t.ntl:4:7: unexpected text after the row's closing '|'");
    parse_fails(HEAD "tiles\n|#.#|\n", "t.ntl:5:1: unexpected end of file: the 'tiles' block has 1 of 2 rows");
    parse_fails(HEAD "tiles\n|#.#|", "t.ntl:4:6: unexpected end of file: the 'tiles' block has 1 of 2 rows");
    parse_fails(HEAD, "t.ntl:3:1: unexpected end of file: no 'tiles' block");
    parse_fails(HEAD "tiles x\n", "t.ntl:3:7: unexpected field after 'tiles' (rows go on the next lines)");
    parse_fails(HEAD GRID "|###|\n", "t.ntl:6:1: a grid row outside a block (more rows than the map height?)");
    parse_fails(HEAD GRID "tiles\n", "t.ntl:6:1: duplicate 'tiles' block (first at line 3)");
    parse_fails(HEAD "materials\n", "t.ntl:3:1: the 'materials' block must come after the 'tiles' block");
    parse_fails(HEAD GRID "materials\n|.1g|\n", "t.ntl:7:4: unknown material code 'g' (expected '.', 1-9 or a-f)");
    parse_fails(HEAD GRID "flags\n|.-x|\n", "t.ntl:7:4: unknown flag code 'x' (expected '.' or '-' for one-way)");
    parse_fails(HEAD GRID "player 1 1\nflags\n", "t.ntl:7:1: the 'flags' block must come before the objects");
    parse_fails(HEAD "tiles\n|#\t#|\n", "t.ntl:4:3: unknown tile code '\\x09' (expected '.', '#' or an N code '2'..'Q', see the legend)");
    /* A NUL byte anywhere is an error at its position. */
    const char nul[] = "ntile-level 1\nsize 3 2\ntiles\n|#.\0|\n|###|\n";
    nt_level *lv = NULL;
    nt_text_error e;
    assert_int_equal(nt_level_parse("t.ntl", nul, sizeof nul - 1, &lv, &e), NT_ERR_PARSE);
    assert_null(lv);
    assert_string_equal(e.message, "t.ntl:4:4: NUL byte in the text");
}

static void test_object_errors(void **state)
{
    (void)state;
    parse_fails("ntile-level 1\nsize 3 2\nplayer 1 1\n", "t.ntl:3:1: 'player' must come after the 'tiles' block");
    parse_fails(HEAD GRID "player 1 1\nplayer 2 2\n", "t.ntl:7:1: duplicate 'player' (first at line 6)");
    parse_fails(HEAD GRID "player 1\n", "t.ntl:6:9: missing fields: expected 'player X Y'");
    parse_fails(HEAD GRID "region r lava 0 0 1 1\n",
                "t.ntl:6:10: unknown region kind 'lava' (expected zone, exit, score, kill or switch)");
    parse_fails(HEAD GRID "region r zone 0 0 0 1\n", "t.ntl:6:19: region x1 must be greater than x0");
    parse_fails(HEAD GRID "region r zone 0 5 1 1\n", "t.ntl:6:21: region y1 must be greater than y0");
    parse_fails(HEAD GRID "region r score 0 0 1 1\n", "t.ntl:6:23: a score region needs 'value N'");
    parse_fails(HEAD GRID "region r exit 0 0 1 1 value 3\n", "t.ntl:6:23: only score regions have a value");
    parse_fails(HEAD GRID "region r score 0 0 1 1 value 0\n", "t.ntl:6:30: score value '0' is out of range 1..1000000");
    parse_fails(HEAD GRID "region r zone 0 0 1\n",
                "t.ntl:6:20: missing fields: expected 'region NAME zone|exit|score|kill|switch X0 Y0 X1 Y1 [value N] [needs SWITCH]'");
    parse_fails(HEAD GRID "region 9r zone 0 0 1 1\n",
                "t.ntl:6:8: region name '9r' is not a valid name (a letter or '_', then letters, digits, '_', '-' or "
                "'.'; at most 31 characters)");
    parse_fails(HEAD GRID "region abcdefghijklmnopqrstuvwxyz012345 zone 0 0 1 1\n",
                "t.ntl:6:8: region name 'abcdefghijklmnopqrstuvwxyz012345' is not a valid name (a letter or '_', then "
                "letters, digits, '_', '-' or '.'; at most 31 characters)");
    parse_fails(HEAD GRID "path p zigzag speed 1 points 0 0 1 1\n",
                "t.ntl:6:8: unknown path mode 'zigzag' (expected loop, pingpong or orbit)");
    parse_fails(HEAD GRID "path p loop speed 0 points 0 0 1 1\n", "t.ntl:6:19: path speed '0' must be > 0");
    parse_fails(HEAD GRID "path p loop speed 1 points 0 0\n", "t.ntl:6:31: a path needs at least 2 points, got 1");
    parse_fails(HEAD GRID "path p loop speed 1 points 0 0 1\n",
                "t.ntl:6:33: points need pairs X Y: the last point has no y");
    parse_fails(HEAD GRID "path p loop speed 1 wait -1 points 0 0 1 1\n", "t.ntl:6:26: wait '-1' must be >= 0");
    parse_fails(HEAD GRID "path p loop speed 1 via 0 0 1 1\n", "t.ntl:6:21: expected 'points' or 'wait', got 'via'");
    parse_fails(HEAD GRID "path p orbit speed 1 center 0 0 radius 0\n", "t.ntl:6:40: orbit radius '0' must be > 0");
    parse_fails(HEAD GRID "path p orbit speed 1 centre 0 0 radius 1\n", "t.ntl:6:22: expected 'center', got 'centre'");
}

static void test_body_errors(void **state)
{
    (void)state;
    parse_fails(HEAD GRID "body b flying circle 1 at 0 0\n",
                "t.ntl:6:8: unknown body type 'flying' (expected static, kinematic or dynamic)");
    parse_fails(HEAD GRID "body b dynamic triangle 1 at 0 0\n",
                "t.ntl:6:16: unknown shape 'triangle' (expected box or circle)");
    /* Half-sizes up to NT_MAX_HALF_CELLS (4) cells of 24: 96 is the largest. */
    parse_fails(HEAD GRID "body b dynamic circle 96.001 at 0 0\n",
                "t.ntl:6:23: radius '96.001' is larger than the largest half-size, 4 cells (96)");
    parse_fails(HEAD GRID "body b dynamic box 6 97 at 0 0\n",
                "t.ntl:6:22: half-height '97' is larger than the largest half-size, 4 cells (96)");
    parse_fails(HEAD GRID "body b static box 1e9 6 at 0 0\n",
                "t.ntl:6:19: half-width '1e9' is larger than the largest half-size, 4 cells (96)");
    parse_fails("ntile-level 1\nsize 3 2\ncell 1\n" GRID "body b dynamic circle 4.5 at 0 0\n",
                "t.ntl:7:23: radius '4.5' is larger than the largest half-size, 4 cells (4)");
    parse_fails(HEAD GRID "body b dynamic box nan 6 at 0 0\n", "t.ntl:6:20: half-width 'nan' is not a finite number");
    parse_fails(HEAD GRID "body b dynamic box 6 0 at 0 0\n", "t.ntl:6:22: half-height '0' must be > 0");
    parse_fails(HEAD GRID "body b dynamic box -48 6 at 0 0\n", "t.ntl:6:20: half-width '-48' must be > 0");
    /* A world refuses bodies more than NT_WORLD_REACH_CELLS (64) cells outside the map. */
    parse_fails(HEAD GRID "body b dynamic circle 5 at -1600 0\n",
                "t.ntl:6:28: position -1600 0 is more than 64 cells outside the map");
    parse_fails(HEAD GRID "body b static circle 5 at 10 10 repeat 100 1 24 0\n",
                "t.ntl:6:33: the repeat grid reaches more than 64 cells outside the map");
    parse_fails(HEAD GRID "player 1e9 1\n", "t.ntl:6:8: player spawn is more than 64 cells outside the map");
    parse_fails(HEAD GRID "body b dynamic circle 0 at 0 0\n", "t.ntl:6:23: radius '0' must be > 0");
    parse_fails(HEAD GRID "body b dynamic circle 1 0 0\n", "t.ntl:6:25: expected 'at X Y', got '0'");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0\n",
                "t.ntl:6:29: missing fields: expected 'body NAME static|kinematic|dynamic box HW HH|circle R at X Y [OPTIONS]'");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 nan\n", "t.ntl:6:30: y 'nan' is not a finite number");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 0 spin 3\n",
                "t.ntl:6:32: unknown body option 'spin' (expected vel, mass, material, drag, gravity-scale, category, mask, "
                "sensor, no-sleep, asleep, path, phase, score, deadly, template, repeat, door, opened-by, closed-by or one-way)");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 0 mass 1 mass 2\n", "t.ntl:6:39: duplicate body option 'mass'");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 0 mass 0\n", "t.ntl:6:37: mass '0' must be > 0");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 0 mass 1e-40\n", "t.ntl:6:37: mass '1e-40' is outside 1e-12 .. 1e12");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 0 mass 2e12\n", "t.ntl:6:37: mass '2e12' is outside 1e-12 .. 1e12");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 0 vel 1\n", "t.ntl:6:37: option 'vel' needs 2 values");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 0 material 2 0\n",
                "t.ntl:6:41: body friction 2 is above 1, the limit of the N friction model");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 0 mask 0x100000000\n",
                "t.ntl:6:37: mask '0x100000000' is out of range (32 bits)");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 0 path p\n",
                "t.ntl:6:37: unknown path 'p' (paths must be defined before the bodies on them)");
    parse_fails(HEAD GRID "path p loop speed 1 points 0 0 1 1\nbody b dynamic circle 1 at 0 0 path p\n",
                "t.ntl:7:32: only kinematic bodies follow paths (this body is dynamic)");
    parse_fails(HEAD GRID "body b kinematic circle 1 at 0 0 phase 0.5\n", "t.ntl:6:34: 'phase' needs 'path'");
    parse_fails(HEAD GRID "path p loop speed 1 points 0 0 1 1\nbody b kinematic circle 1 at 0 0 path p phase 1\n",
                "t.ntl:7:47: phase '1' is outside [0, 1)");
    parse_fails(HEAD GRID "body b static circle 1 at 0 0 score 5\n",
                "t.ntl:6:31: a body with a score must be a sensor (add 'sensor')");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 0 template repeat 2 2 1 1\n", "t.ntl:6:41: a template cannot repeat");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 0 repeat 2 0 1 1\n", "t.ntl:6:41: repeat count y '0' is out of range 1..10000");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 0 repeat 1000 1000 1 1\nbody c dynamic circle 1 at 0 0 repeat 2 1 1 1\n",
                "t.ntl:7:6: too many bodies: more than 1000000 in the level");
    parse_fails(HEAD GRID "body b dynamic circle 1 at 0 0\nregion b zone 0 0 1 1\n",
                "t.ntl:7:8: duplicate name 'b' (first defined at line 6)");
    parse_fails(HEAD GRID "path b loop speed 1 points 0 0 1 1\nbody b dynamic circle 1 at 0 0\n",
                "t.ntl:7:6: duplicate name 'b' (first defined at line 6)");
}

static void test_spawner_errors(void **state)
{
    (void)state;
#define T "body t dynamic circle 1 at 0 0 template\nbody k kinematic box 2 2 at 0 0\n"
    parse_fails(HEAD GRID T "spawner s u action limit 1\n",
                "t.ntl:8:11: unknown body 'u' (bodies must be defined before they are named)");
    parse_fails(HEAD GRID T "spawner s k action limit 1\n",
                "t.ntl:8:11: body 'k' is not a template (add 'template' to its line)");
    parse_fails(HEAD GRID T "spawner s t limit 1\n", "t.ntl:8:20: a spawner needs a trigger: 'action' or 'every N'");
    parse_fails(HEAD GRID T "spawner s t action\n", "t.ntl:8:19: a spawner needs 'limit K'");
    parse_fails(HEAD GRID T "spawner s t action every 3 limit 1\n",
                "t.ntl:8:20: a spawner has one trigger: 'action' or 'every N'");
    parse_fails(HEAD GRID T "spawner s t action start 3 limit 1\n", "t.ntl:8:20: 'start' needs 'every N'");
    parse_fails(HEAD GRID T "spawner s t every 0 limit 1\n", "t.ntl:8:19: every '0' is out of range 1..100000000");
    parse_fails(HEAD GRID T "spawner s t action limit 1 attach t\n", "t.ntl:8:35: cannot attach a spawner to a template");
    parse_fails(HEAD GRID T "spawner s t action limit 1 jitter -2\n", "t.ntl:8:35: jitter '-2' must be >= 0");
    parse_fails(HEAD GRID T "spawner s t action limit 1 speed 3\n",
                "t.ntl:8:28: unknown spawner option 'speed' (expected action, every, start, limit, attach, offset or jitter)");
    parse_fails(HEAD GRID T "spawner s t action limit 1 limit 2\n", "t.ntl:8:28: duplicate spawner option 'limit'");
    parse_fails(HEAD GRID T "spawner s t action limit\n", "t.ntl:8:25: option 'limit' needs 1 value");
    parse_fails(HEAD GRID T "spawner t t action limit 1\n", "t.ntl:8:9: duplicate name 't' (first defined at line 6)");
#undef T
}

/* ---------------------------------------------------------------- allocation failures */

static const char rich[] = "ntile-level 1\ntitle \"x\"\nsize 5 3\nmaterial 2 0.1 0.9\n"
                           "tiles\n|#.2.#|\n|#...#|\n|#####|\nmaterials\n|.....|\n|.....|\n|.2.2.|\n"
                           "flags\n|.-...|\n|.....|\n|.....|\nplayer 30 30\n"
                           "path p loop speed 3 points 0 0 10 0\nregion r exit 0 0 10 10\n"
                           "body a dynamic circle 3 at 40 30\nbody b dynamic box 2 2 at 50 30 repeat 3 2 4 4\n"
                           "body c kinematic box 4 4 at 0 0 path p\nbody t dynamic circle 2 at 0 0 template\n"
                           "spawner s t every 5 limit 3 attach c\n";

/* Every allocation of a parse fails in turn: the parse reports it and leaves no
 * memory behind. */
static void test_parse_out_of_memory(void **state)
{
    (void)state;
    int failures = 0;
    for (long budget = 0;; budget++) {
        failalloc_begin(budget);
        nt_level *lv = NULL;
        nt_text_error e;
        nt_status s = nt_level_parse("t.ntl", rich, sizeof rich - 1, &lv, &e);
        if (s == NT_OK) nt_level_destroy(lv);
        assert_int_equal(failalloc_end(), 0);
        if (s == NT_OK) break;
        failures++;
        assert_int_equal(s, NT_ERR_OUT_OF_MEMORY);
        assert_null(lv);
        assert_string_equal(e.message, "t.ntl: out of memory");
    }
    assert_true(failures >= 8); /* parser, level, cell arrays, names, bodies, ... */
}

/* ---------------------------------------------------------------- the writer */

static void roundtrip_text(const char *text)
{
    nt_level *a = parse_ok(text);
    char *t1 = write_level(a);
    nt_level *b = parse_ok(t1);
    char *t2 = write_level(b);
    assert_string_equal(t1, t2);
    /* The data is the same, bit for bit, where it matters. */
    assert_int_equal(a->width, b->width);
    assert_int_equal(a->height, b->height);
    size_t n = (size_t)a->width * (size_t)a->height;
    assert_memory_equal(a->tiles, b->tiles, n);
    assert_memory_equal(a->cell_materials, b->cell_materials, n);
    assert_memory_equal(a->cell_flags, b->cell_flags, n);
    assert_memory_equal(a->materials, b->materials, sizeof a->materials);
    assert_int_equal(a->body_count, b->body_count);
    for (int i = 0; i < a->body_count; i++) {
        const nt_level_body *x = &a->bodies[i], *y = &b->bodies[i];
        assert_string_equal(x->name, y->name);
        assert_memory_equal(&x->position, &y->position, sizeof x->position);
        assert_memory_equal(&x->velocity, &y->velocity, sizeof x->velocity);
        assert_memory_equal(&x->shape.half, &y->shape.half, sizeof x->shape.half);
        assert_memory_equal(&x->material, &y->material, sizeof x->material);
        assert_true(x->mass == y->mass && x->linear_drag == y->linear_drag && x->gravity_scale == y->gravity_scale);
        assert_true(x->type == y->type && x->shape.type == y->shape.type && x->category == y->category && x->mask == y->mask);
        assert_true(x->is_sensor == y->is_sensor && x->enable_sleep == y->enable_sleep && x->is_awake == y->is_awake &&
                    x->path == y->path);
        assert_true(x->phase == y->phase && x->score == y->score && x->deadly == y->deadly && x->is_template == y->is_template);
        assert_true(x->repeat_x == y->repeat_x && x->repeat_y == y->repeat_y);
    }
    assert_int_equal(a->region_count, b->region_count);
    assert_int_equal(a->path_count, b->path_count);
    assert_int_equal(a->spawner_count, b->spawner_count);
    for (int i = 0; i < a->path_count; i++) assert_memory_equal(a->paths[i].points, b->paths[i].points, sizeof a->paths[i].points);
    for (int i = 0; i < a->spawner_count; i++) {
        assert_int_equal(a->spawners[i].template_body, b->spawners[i].template_body);
        assert_int_equal(a->spawners[i].attach, b->spawners[i].attach);
        assert_int_equal(a->spawners[i].start, b->spawners[i].start);
    }
    free(t1);
    free(t2);
    nt_level_destroy(a);
    nt_level_destroy(b);
}

/* Bodies larger than a cell (issue 18): a 1 x 2-cell crate, a 4-cell-wide platform
 * and a circle 8 cells across (the cap) parse as written and round-trip. */
static const char large[] = "ntile-level 1\nsize 12 9\n"
                            "tiles\n|############|\n|#..........#|\n|#..........#|\n|#..........#|\n"
                            "|#..........#|\n|#..........#|\n|#..........#|\n|#..........#|\n|############|\n"
                            "body crate dynamic box 12 24 at 60 72\n"
                            "body platform kinematic box 48 6 at 180 60\n"
                            "body boulder static circle 96 at 150 108\n"
                            "body wall static box 96 0.5 at 144 130\n"
                            "body ghost dynamic box 96 96 at -500 0 template\n";

static void test_large_bodies(void **state)
{
    (void)state;
    nt_level *lv = parse_ok(large);
    assert_int_equal(lv->body_count, 5);
    const nt_level_body *b = lv->bodies;
    assert_int_equal(b[0].shape.type, NT_SHAPE_AABB);
    assert_true(b[0].shape.half.x == 12 && b[0].shape.half.y == 24); /* 1 x 2 cells */
    assert_true(b[1].shape.half.x == 48 && b[1].shape.half.y == 6);  /* 4 cells wide */
    assert_int_equal(b[2].shape.type, NT_SHAPE_CIRCLE);
    assert_true(b[2].shape.half.x == 96 && b[2].shape.half.y == 96);
    assert_true(b[3].shape.half.x == (nt_real)NT_MAX_HALF_CELLS * lv->cell_size);
    assert_int_equal(nt_level_validate(lv, NULL), NT_OK);
    char *t = write_level(lv);
    assert_non_null(strstr(t, "\nbody crate dynamic box 12 24 at 60 72\n"));
    assert_non_null(strstr(t, "\nbody platform kinematic box 48 6 at 180 60\n"));
    assert_non_null(strstr(t, "\nbody boulder static circle 96 at 150 108\n"));
    free(t);
    /* A world takes them as they are (the template is not created). */
    nt_world *w = NULL;
    nt_body_id ids[4];
    assert_int_equal(nt_level_create_world(lv, &w, ids, 4), NT_OK);
    assert_int_equal(nt_world_get_body_count(w), 4);
    assert_true(nt_body_get_shape(w, ids[0]).half.y == 24 && nt_body_get_shape(w, ids[2]).half.x == 96);
    nt_world_destroy(w);
    nt_level_destroy(lv);
    roundtrip_text(large);
    /* The cap scales with the cell size. */
    lv = parse_ok("ntile-level 1\nsize 8 2\ncell 0.5\ntiles\n|........|\n|........|\nbody b dynamic box 2 0.5 at 2 0.5\n");
    assert_true(lv->bodies[0].shape.half.x == 2);
    nt_level_destroy(lv);
    parse_fails("ntile-level 1\nsize 8 2\ncell 0.5\ntiles\n|........|\n|........|\nbody b dynamic box 2.01 0.5 at 2 0.5\n",
                "t.ntl:7:20: half-width '2.01' is larger than the largest half-size, 4 cells (2)");
    /* A body above half a cell lies wholly inside the map (the world's rule), every
     * instance of a repeat; smaller ones may reach outside as before. The map: 72 x 48. */
    parse_fails(HEAD GRID "body b dynamic box 13 6 at 12.9 10\n",
                "t.ntl:6:28: a body larger than half a cell must lie inside the map (0 0 .. 72 48): at 12.9 10 it reaches "
                "outside");
    parse_fails(HEAD GRID "body b static circle 24.5 at 36 24\n",
                "t.ntl:6:30: a body larger than half a cell must lie inside the map (0 0 .. 72 48): at 36 24 it reaches "
                "outside");
    parse_fails(HEAD GRID "body b static box 13 6 at 13 6 repeat 3 1 24 0\n",
                "t.ntl:6:32: the repeat grid takes a body larger than half a cell outside the map");
    lv = parse_ok(HEAD GRID "body b static box 13 6 at 13 6 repeat 2 2 46 36\nbody c dynamic box 12 12 at -5 -5\n");
    nt_level_destroy(lv);
    lv = parse_ok(HEAD GRID);
    nt_level_body nb = nt_level_default_body(lv);
    strcpy(nb.name, "big");
    nb.shape = nt_shape_aabb(36, 24);
    nb.position = nt_v2(36, 24); /* exactly the map */
    assert_int_equal(nt_level_add_body(lv, &nb, NULL, NULL), NT_OK);
    strcpy(nb.name, "out");
    nb.position = nt_v2(36, R(24.5));
    nt_text_error e;
    assert_int_equal(nt_level_add_body(lv, &nb, NULL, &e), NT_ERR_INVALID_ARGUMENT);
    assert_string_equal(e.message, "body 'out': a body larger than half a cell must lie inside the map");
    nb.is_template = true; /* created where its spawner says */
    assert_int_equal(nt_level_add_body(lv, &nb, NULL, NULL), NT_OK);
    nt_level_destroy(lv);
}

/* Switches, exits that need them, and doors: what parses, what writes back, what fails. */
static void test_switches_and_doors(void **state)
{
    (void)state;
    static const char text[] = HEAD GRID "region sw switch 0 0 10 10\nregion sw2 switch 20 0 30 10\n"
                                         "region out exit 40 0 50 10 needs sw2\n"
                                         "body a static box 2 10 at 12 12 opened-by sw\n"
                                         "body b kinematic box 2 10 at 30 12 closed-by sw2\n"
                                         "body c static box 2 10 at 50 12 door\n"
                                         "body d static box 6 12 at 60 12 one-way right\nbody e kinematic box 6 12 at 60 12 one-way up\n";
    nt_level *lv = parse_ok(text);
    assert_int_equal(lv->regions[0].kind, NT_REGION_SWITCH);
    assert_int_equal(lv->regions[2].kind, NT_REGION_EXIT);
    assert_int_equal(lv->regions[2].needs, 2);
    assert_int_equal(lv->regions[0].needs, 0);
    assert_true(lv->bodies[0].door == NT_DOOR_LOCKED && lv->bodies[0].door_switch == 1);
    assert_true(lv->bodies[1].door == NT_DOOR_TRAP && lv->bodies[1].door_switch == 2);
    assert_true(lv->bodies[2].door == NT_DOOR_PLAIN && lv->bodies[2].door_switch == 0);
    assert_true(lv->bodies[3].one_way == NT_ONE_WAY_RIGHT && lv->bodies[4].one_way == NT_ONE_WAY_UP);
    assert_true(lv->bodies[0].one_way == NT_ONE_WAY_NONE);
    char *out = write_level(lv);
    if (!strstr(out, "region sw switch 0 0 10 10\n") || !strstr(out, "region out exit 40 0 50 10 needs sw2\n") ||
        !strstr(out, " opened-by sw\n") || !strstr(out, " closed-by sw2\n") || !strstr(out, " door\n") ||
        !strstr(out, " one-way right\n") || !strstr(out, " one-way up\n"))
        fail_msg("canonical text:\n%s", out);
    free(out);
    nt_level_destroy(lv);
    roundtrip_text(text);

    parse_fails(HEAD GRID "region r zone 0 0 1 1 needs sw\n", "t.ntl:6:23: only exit regions need a switch");
    parse_fails(HEAD GRID "region r exit 0 0 1 1 needs sw\n",
                "t.ntl:6:29: unknown switch 'sw' (switches must be defined before what they open)");
    parse_fails(HEAD GRID "region z zone 0 0 1 1\nregion r exit 0 0 1 1 needs z\n",
                "t.ntl:7:29: region 'z' is not a switch (region NAME switch X0 Y0 X1 Y1)");
    parse_fails(HEAD GRID "region sw switch 0 0 1 1\nregion r exit 0 0 1 1 needs sw x\n",
                "t.ntl:7:32: unexpected field: expected 'region NAME zone|exit|score|kill|switch X0 Y0 X1 Y1 [value N] [needs SWITCH]'");
    parse_fails(HEAD GRID "body d static box 2 2 at 5 5 opened-by nothing\n",
                "t.ntl:6:40: unknown switch 'nothing' (switches must be defined before what they open)");
    parse_fails(HEAD GRID "region sw switch 0 0 1 1\nbody d dynamic box 2 2 at 5 5 closed-by sw\n",
                "t.ntl:7:31: a door is a solid static or kinematic body (not dynamic, a sensor or a template)");
    parse_fails(HEAD GRID "body d static box 2 2 at 5 5 sensor door\n",
                "t.ntl:6:37: a door is a solid static or kinematic body (not dynamic, a sensor or a template)");
    parse_fails(HEAD GRID "region sw switch 0 0 1 1\nbody d static box 2 2 at 5 5 door opened-by sw\n",
                "t.ntl:7:35: a door is one of 'door', 'opened-by SWITCH' or 'closed-by SWITCH'");

    parse_fails(HEAD GRID "body d static box 2 2 at 5 5 one-way sideways\n",
                "t.ntl:6:38: unknown one-way side 'sideways' (expected right, down, left or up)");
    parse_fails(HEAD GRID "body d dynamic box 2 2 at 5 5 one-way up\n",
                "t.ntl:6:31: a one-way body is a solid static or kinematic body (not dynamic, a sensor, a template or a door)");
    parse_fails(HEAD GRID "body d static box 2 2 at 5 5 door one-way up\n",
                "t.ntl:6:35: a one-way body is a solid static or kinematic body (not dynamic, a sensor, a template or a door)");

    /* The API checks the same. */
    lv = parse_ok(HEAD GRID "region sw switch 0 0 1 1\nregion r exit 0 0 1 1\nbody d static box 2 2 at 5 5\n");
    nt_text_error e;
    lv->regions[1].needs = 2; /* itself: not a switch */
    assert_int_equal(nt_level_validate(lv, &e), NT_ERR_INVALID_ARGUMENT);
    lv->regions[1].needs = 1;
    assert_int_equal(nt_level_validate(lv, NULL), NT_OK);
    lv->bodies[0].door = NT_DOOR_LOCKED; /* without its switch */
    assert_int_equal(nt_level_validate(lv, NULL), NT_ERR_INVALID_ARGUMENT);
    lv->bodies[0].door_switch = 1;
    assert_int_equal(nt_level_validate(lv, NULL), NT_OK);
    lv->bodies[0].door_switch = 2; /* the exit is no switch */
    assert_int_equal(nt_level_validate(lv, NULL), NT_ERR_INVALID_ARGUMENT);
    nt_level_destroy(lv);
}

static void test_roundtrip_hand_written(void **state)
{
    (void)state;
    roundtrip_text(HEAD GRID);
    roundtrip_text(rich);
    roundtrip_text("ntile-level 1\nsize 2 1\ncell 0.1\ngravity -0 1e-7\nfriction-model coulomb\nmaterial 0 3.5 0\n"
                   "tiles\n|.Q|\npath o orbit speed 0.3 center 0.05 0.05 radius 0.01\n"
                   "body k kinematic circle 0.0333 at 0 0 path o phase 0.999\n"
                   "body s static box 0.05 0.01 at 1e-3 -6.25 sensor deadly score 2 category 0 mask 0\n");
}

/* The canonical text of a known level, exactly. */
static void test_canonical_text(void **state)
{
    (void)state;
    nt_level *lv = parse_ok("ntile-level 1 # hi\nsize 2 1\ntitle \"T\"\nmaterial 1 0.5 0.5\ntiles\n|#.|\nmaterials\n|.1|\n"
                            "body b dynamic circle 2 at 1.5 2 vel 0 0 mass 1\n");
    char *t = write_level(lv);
    assert_string_equal(t, "ntile-level 1\ntitle \"T\"\nsize 2 1\ncell 24\ngravity 0 320\nfriction-model n\nsleep on\nseed 1\n"
                           "material 0 0.05 0.3\nmaterial 1 0.5 0.5\nbody-material 0.05 0.3\nbody-drag 0\n\n"
                           "# tile codes: '.' EMPTY, '#' FULL, other tiles N's code '0' + id (README: The tile set)\n"
                           "tiles\n|#.|\nmaterials\n|.1|\n\nbody b dynamic circle 2 at 1.5 2\n");
    /* A buffer too small gets a NUL-terminated prefix and the full length. */
    char small[10];
    assert_int_equal(nt_level_write(lv, small, sizeof small), strlen(t));
    assert_string_equal(small, "ntile-lev");
    free(t);
    nt_level_destroy(lv);
}

static uint32_t g_rng = 12345;
static uint32_t rnd(void)
{
    g_rng = g_rng * 1664525u + 1013904223u;
    return g_rng >> 8;
}
static nt_real rreal(double lo, double hi) { return (nt_real)(lo + (hi - lo) * (double)rnd() / 16777216.0); }

/* A body above half a cell lies wholly inside the W x H map: shrunk to fit if need
 * be, placed at random inside it, not repeated. */
static void fit_inside(nt_level_body *b, nt_real W, nt_real H)
{
    nt_vec2 h = b->shape.half;
    if (h.x > W / 2) h.x = W / 2;
    if (h.y > H / 2) h.y = H / 2;
    if (b->shape.type == NT_SHAPE_CIRCLE) h.x = h.y = h.x < h.y ? h.x : h.y;
    b->shape.half = h;
    nt_vec2 p = nt_v2(h.x + rreal(0, 1) * (W - 2 * h.x), h.y + rreal(0, 1) * (H - 2 * h.y));
    if (p.x - h.x < 0 || p.x + h.x > W) p.x = W / 2; /* rounding: the middle always fits */
    if (p.y - h.y < 0 || p.y + h.y > H) p.y = H / 2;
    b->position = p;
    b->repeat_x = b->repeat_y = 1;
}

/* Random levels built through the API: write -> parse -> write gives the same text. */
static void test_roundtrip_random(void **state)
{
    (void)state;
    for (int iter = 0; iter < 60; iter++) {
        nt_level *lv = NULL;
        int w = 1 + (int)(rnd() % 40), h = 1 + (int)(rnd() % 30);
        assert_int_equal(nt_level_create(w, h, rreal(0.5, 64), &lv), NT_OK);
        lv->gravity = nt_v2(rreal(-500, 500), rreal(-500, 500));
        lv->friction_model = rnd() % 2 ? NT_FRICTION_N : NT_FRICTION_COULOMB;
        lv->seed = rnd();
        for (int i = 0; i < NT_MAX_MATERIALS; i++)
            if (rnd() % 3 == 0) lv->materials[i] = (nt_material){rreal(0, 1), rreal(0, 1)};
        for (int k = 0; k < w * h; k++) {
            lv->tiles[k] = (uint8_t)(rnd() % NT_TILE_COUNT);
            lv->cell_materials[k] = (uint8_t)(rnd() % 4 == 0 ? rnd() % NT_MAX_MATERIALS : 0);
            lv->cell_flags[k] = (uint8_t)(rnd() % 9 == 0 ? NT_CELL_ONE_WAY : 0);
        }
        lv->has_player = rnd() % 2;
        /* Anywhere within the reach of a world: up to 30 cells outside the map. */
        nt_real cs = lv->cell_size;
        lv->player = nt_v2(rreal(-30, w + 30) * cs, rreal(-30, h + 30) * cs);
        nt_level_path p;
        memset(&p, 0, sizeof p);
        snprintf(p.name, sizeof p.name, "path_%d", iter);
        p.mode = (nt_path_mode)(rnd() % 3);
        p.speed = rreal(0.01, 100);
        p.wait = p.mode == NT_PATH_ORBIT ? 0 : rreal(0, 2);
        p.point_count = 2 + (int)(rnd() % 5);
        for (int k = 0; k < p.point_count; k++) p.points[k] = nt_v2(rreal(-99, 99), rreal(-99, 99));
        p.center = nt_v2(rreal(-99, 99), rreal(-99, 99));
        p.radius = rreal(0.1, 50);
        if (p.mode == NT_PATH_ORBIT) p.point_count = 0;
        assert_int_equal(nt_level_add_path(lv, &p, NULL, NULL), NT_OK);
        int nb = (int)(rnd() % 6);
        for (int i = 0; i < nb; i++) {
            nt_level_body b = nt_level_default_body(lv);
            snprintf(b.name, sizeof b.name, "b%d.x-%d", i, iter);
            b.type = (nt_body_type)(rnd() % 3);
            nt_real r = rreal(0.001, NT_MAX_HALF_CELLS) * lv->cell_size;
            b.shape = rnd() % 2 ? nt_shape_circle(r) : nt_shape_aabb(r, rreal(0.001, NT_MAX_HALF_CELLS) * lv->cell_size);
            b.position = nt_v2(rreal(-30, w + 30) * cs, rreal(-30, h + 30) * cs);
            b.velocity = nt_v2(rreal(-10, 10), 0);
            b.mass = rreal(0.01, 9);
            b.material = (nt_material){rreal(0, 1), rreal(0, 1)};
            b.category = rnd();
            b.is_sensor = rnd() % 2;
            b.score = b.is_sensor && rnd() % 2 ? (int)(1 + rnd() % 9) : 0;
            b.deadly = rnd() % 2;
            if (b.type == NT_BODY_KINEMATIC && rnd() % 2) {
                b.path = 0;
                b.phase = rreal(0, 0.999);
            }
            b.is_template = rnd() % 4 == 0;
            if (!b.is_template && rnd() % 3 == 0) {
                b.repeat_x = 1 + (int)(rnd() % 4);
                b.repeat_y = 1 + (int)(rnd() % 4);
                b.repeat_step = nt_v2(rreal(0, 3) * cs, rreal(-3, 3) * cs);
            }
            if (!b.is_template && (b.shape.half.x > cs / 2 || b.shape.half.y > cs / 2))
                fit_inside(&b, (nt_real)w * cs, (nt_real)h * cs);
            assert_int_equal(nt_level_add_body(lv, &b, NULL, NULL), NT_OK);
            if (b.is_template) {
                nt_level_spawner s;
                memset(&s, 0, sizeof s);
                snprintf(s.name, sizeof s.name, "s%d", i);
                s.template_body = lv->body_count - 1;
                s.trigger = rnd() % 2 ? NT_SPAWN_ACTION : NT_SPAWN_EVERY;
                s.every = 1 + (int)(rnd() % 50);
                s.start = 1 + (int)(rnd() % 50);
                s.limit = 1 + (int)(rnd() % 50);
                s.attach = -1;
                s.jitter = rreal(0, 3);
                assert_int_equal(nt_level_add_spawner(lv, &s, NULL), NT_OK);
            }
        }
        nt_level_region rg;
        memset(&rg, 0, sizeof rg);
        strcpy(rg.name, "zone");
        rg.kind = NT_REGION_SCORE;
        rg.value = 5;
        rg.lo = nt_v2(rreal(-9, 0), rreal(-9, 0));
        rg.hi = nt_v2(rreal(1, 9), rreal(1, 9));
        assert_int_equal(nt_level_add_region(lv, &rg, NULL), NT_OK);
        assert_int_equal(nt_level_validate(lv, NULL), NT_OK);
        char *t = write_level(lv);
        roundtrip_text(t);
        /* The parsed level equals the one built by hand. */
        nt_level *back = parse_ok(t);
        assert_memory_equal(back->tiles, lv->tiles, (size_t)(w * h));
        assert_memory_equal(&back->gravity, &lv->gravity, sizeof lv->gravity);
        assert_memory_equal(back->materials, lv->materials, sizeof lv->materials);
        assert_memory_equal(&back->paths[0].speed, &lv->paths[0].speed, sizeof(nt_real));
        assert_int_equal(back->body_count, lv->body_count);
        for (int i = 0; i < lv->body_count; i++) {
            assert_memory_equal(&back->bodies[i].position, &lv->bodies[i].position, sizeof(nt_vec2));
            assert_memory_equal(&back->bodies[i].shape, &lv->bodies[i].shape, sizeof(nt_shape));
            assert_memory_equal(&back->bodies[i].phase, &lv->bodies[i].phase, sizeof(nt_real));
        }
        nt_level_destroy(back);
        free(t);
        nt_level_destroy(lv);
    }
}

/* The shipped levels round-trip too (make test runs from the source tree). */
static void test_roundtrip_shipped_levels(void **state)
{
    (void)state;
    static const char *const names[] = {"tour", "ninja", "pachinko", "lab", "slopes", "stress"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char path[256];
        snprintf(path, sizeof path, "levels/%s.ntl", names[i]);
        FILE *f = fopen(path, "rb");
        if (!f) fail_msg("cannot open %s (run the tests from the source tree)", path);
        static char buf[1 << 20];
        size_t n = fread(buf, 1, sizeof buf - 1, f);
        fclose(f);
        buf[n] = '\0';
        roundtrip_text(buf);
    }
}

/* ---------------------------------------------------------------- API checks */

static void test_api_validation(void **state)
{
    (void)state;
    nt_level *lv = NULL;
    assert_int_equal(nt_level_create(0, 3, 24, &lv), NT_ERR_OUT_OF_RANGE);
    assert_null(lv);
    assert_int_equal(nt_level_create(3, 3, R(NAN), &lv), NT_ERR_NON_FINITE);
    assert_int_equal(nt_level_create(3, 3, 0, &lv), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(nt_level_create(3, 3, 24, &lv), NT_OK);
    nt_level_body b = nt_level_default_body(lv);
    strcpy(b.name, "a");
    b.shape = nt_shape_circle(R(96.5)); /* above NT_MAX_HALF_CELLS (4) cells of 24 */
    nt_text_error ae;
    assert_int_equal(nt_level_add_body(lv, &b, NULL, &ae), NT_ERR_INVALID_ARGUMENT);
    assert_string_equal(ae.message, "body 'a': shape larger than the largest half-size (4 cells)");
    assert_int_equal(lv->body_count, 0);
    assert_int_equal(nt_level_add_body(lv, &b, NULL, NULL), NT_ERR_INVALID_ARGUMENT); /* no report asked for */
    b.shape = nt_shape_aabb(12, 97);
    assert_int_equal(nt_level_add_body(lv, &b, NULL, &ae), NT_ERR_INVALID_ARGUMENT);
    assert_string_equal(ae.message, "body 'a': shape larger than the largest half-size (4 cells)");
    b.shape = nt_shape_aabb(R(NAN), 12);
    assert_int_equal(nt_level_add_body(lv, &b, NULL, &ae), NT_ERR_INVALID_ARGUMENT);
    b.shape = nt_shape_aabb(0, 12);
    assert_int_equal(nt_level_add_body(lv, &b, NULL, &ae), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(lv->body_count, 0);
    b.shape = nt_shape_circle(36); /* above half a cell, wholly inside the 72 x 72 map */
    b.position = nt_v2(36, 36);
    int index = -1;
    assert_int_equal(nt_level_add_body(lv, &b, &index, &ae), NT_OK);
    assert_int_equal(index, 0);
    assert_int_equal(nt_level_add_body(lv, &b, NULL, &ae), NT_ERR_INVALID_ARGUMENT); /* duplicate name */
    assert_string_equal(ae.message, "body 'a': the name is taken by another object");
    assert_int_equal(ae.line, 0);
    strcpy(b.name, "bad name");
    assert_int_equal(nt_level_add_body(lv, &b, NULL, &ae), NT_ERR_INVALID_ARGUMENT);
    assert_string_equal(ae.message, "body: invalid name");
    memset(b.name, 'x', sizeof b.name); /* not even terminated: never quoted back */
    assert_int_equal(nt_level_add_body(lv, &b, NULL, &ae), NT_ERR_INVALID_ARGUMENT);
    assert_string_equal(ae.message, "body: invalid name");
    assert_int_equal(nt_level_add_body(NULL, &b, NULL, &ae), NT_ERR_INVALID_ARGUMENT);
    assert_int_equal(lv->body_count, 1);
    nt_level_region r;
    memset(&r, 0, sizeof r);
    strcpy(r.name, "a");
    r.hi = nt_v2(1, 1);
    assert_int_equal(nt_level_add_region(lv, &r, &ae), NT_ERR_INVALID_ARGUMENT); /* name taken by the body */
    assert_string_equal(ae.message, "region 'a': the name is taken by another object");
    strcpy(r.name, "r");
    assert_int_equal(nt_level_add_region(lv, &r, &ae), NT_OK);
    nt_level_path pa;
    memset(&pa, 0, sizeof pa);
    strcpy(pa.name, "p");
    pa.point_count = 1; /* a path needs at least two points */
    assert_int_equal(nt_level_add_path(lv, &pa, NULL, &ae), NT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(ae.message, "path 'p': "));
    assert_int_equal(lv->path_count, 0);
    nt_level_spawner sp;
    memset(&sp, 0, sizeof sp);
    strcpy(sp.name, "s");
    sp.template_body = 7;
    assert_int_equal(nt_level_add_spawner(lv, &sp, &ae), NT_ERR_INVALID_ARGUMENT);
    assert_string_equal(ae.message, "spawner 's': unknown template body");
    assert_int_equal(lv->spawner_count, 0);
    lv->tiles[4] = 40;
    nt_text_error e;
    assert_int_equal(nt_level_validate(lv, &e), NT_ERR_OUT_OF_RANGE);
    assert_string_equal(e.message, "level: cell 1,1: tile, material or flags out of range");
    lv->tiles[4] = 1;
    lv->bodies[0].mass = 0;
    assert_int_equal(nt_level_validate(lv, &e), NT_ERR_INVALID_ARGUMENT);
    assert_string_equal(e.message, "level: body 'a': mass must be > 0");
    lv->bodies[0].mass = 1;
    assert_int_equal(nt_level_validate(lv, &e), NT_OK);
    memset(lv->title, 'T', sizeof lv->title); /* unterminated, by hand: rejected, nothing past it read */
    assert_int_equal(nt_level_validate(lv, &e), NT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(e.message, "title or author"));
    lv->title[0] = '\0';
    strcpy(lv->regions[0].name, "a"); /* by hand, past the checks of nt_level_add_region */
    assert_int_equal(nt_level_validate(lv, &e), NT_ERR_INVALID_ARGUMENT);
    assert_string_equal(e.message, "level: duplicate name 'a'");
    nt_level_destroy(lv);
    assert_int_equal(nt_level_tile_from_char('.'), 0);
    assert_int_equal(nt_level_tile_from_char('#'), 1);
    for (int t = 0; t < NT_TILE_COUNT; t++) assert_int_equal(nt_level_tile_from_char(nt_level_tile_char(t)), t);
    assert_int_equal(nt_level_tile_char(34), 0);
    assert_int_equal(nt_level_tile_from_char('R'), -1);
}

static void test_create_world(void **state)
{
    (void)state;
    nt_level *lv = parse_ok(rich);
    int n = nt_level_instance_count(lv);
    assert_int_equal(n, 1 + 6 + 1); /* a, b x 6, c; the template is not created */
    nt_body_id ids[8];
    nt_world *w = NULL;
    assert_int_equal(nt_level_create_world(lv, &w, ids, 7), NT_ERR_INVALID_ARGUMENT);
    assert_null(w);
    assert_int_equal(nt_level_create_world(lv, &w, ids, 8), NT_OK);
    assert_int_equal(nt_world_get_body_count(w), 8);
    assert_int_equal(nt_world_get_tile(w, 2, 0), NT_TILE_45DEGpn);
    assert_int_equal(nt_world_get_tile(w, 1, 1), NT_TILE_EMPTY);
    assert_int_equal(nt_world_get_cell_material(w, 3, 2), 2);
    assert_true(nt_world_get_material(w, 2).bounce == R(0.9));
    assert_int_equal(nt_world_get_cell_flags(w, 1, 0), NT_CELL_ONE_WAY);
    /* Repeats go row by row: b at (50,30), (54,30), (58,30), (50,34), ... */
    nt_vec2 p = nt_body_get_position(w, ids[1 + 4]);
    assert_true(p.x == 54 && p.y == 34);
    assert_int_equal(nt_body_get_type(w, ids[7]), NT_BODY_KINEMATIC);
    assert_true(nt_body_get_shape(w, ids[0]).half.x == 3);
    nt_world_destroy(w);
    nt_level_destroy(lv);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse_minimal_and_defaults),
        cmocka_unit_test(test_parse_everything),
        cmocka_unit_test(test_line_endings_and_final_newline),
        cmocka_unit_test(test_header_errors),
        cmocka_unit_test(test_setting_errors),
        cmocka_unit_test(test_grid_errors),
        cmocka_unit_test(test_object_errors),
        cmocka_unit_test(test_switches_and_doors),
        cmocka_unit_test(test_body_errors),
        cmocka_unit_test(test_spawner_errors),
        cmocka_unit_test(test_parse_out_of_memory),
        cmocka_unit_test(test_large_bodies),
        cmocka_unit_test(test_roundtrip_hand_written),
        cmocka_unit_test(test_canonical_text),
        cmocka_unit_test(test_roundtrip_random),
        cmocka_unit_test(test_roundtrip_shipped_levels),
        cmocka_unit_test(test_api_validation),
        cmocka_unit_test(test_create_world),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
