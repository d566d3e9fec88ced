/* Levels: the .ntl parser, the canonical writer, validation of hand-built levels,
 * and building a world from a level.
 *
 * The text is read line by line. A file is: the header line, settings, the tiles
 * block (then optional materials and flags blocks), then objects. That order is
 * enforced so that everything a line depends on (map size, cell size, friction
 * model, the paths and bodies it names) is known when the line is read, and every
 * error can point at the field that is wrong. */
#include <stdio.h>
#include <string.h>
#include "text.h"

/* A level text starts "ntile-level VERSION" (parser and writer). */
#define LEVEL_MAGIC "ntile-level"

/* ---------------------------------------------------------------- tile codes */

char nt_level_tile_char(int tile)
{
    if (tile == NT_TILE_EMPTY) return '.';
    if (tile == NT_TILE_FULL) return '#';
    if (tile > NT_TILE_FULL && tile < NT_TILE_COUNT) return (char)('0' + tile);
    return 0;
}

int nt_level_tile_from_char(char c)
{
    if (c == '.') return NT_TILE_EMPTY;
    if (c == '#') return NT_TILE_FULL;
    int id = c - '0';
    return (id > NT_TILE_FULL && id < NT_TILE_COUNT) ? id : -1;
}

static int material_from_char(char c)
{
    if (c == '.') return 0;
    if (c >= '1' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    return -1;
}

static char material_char(int m) { return m == 0 ? '.' : (char)(m < 10 ? '0' + m : 'a' + m - 10); }

/* ---------------------------------------------------------------- level memory */

static nt_material n_material(void)
{
    nt_material m;
    m.friction = (nt_real)0.05;
    m.bounce = (nt_real)0.3;
    return m;
}

nt_status nt_level_create(int width, int height, nt_real cell_size, nt_level **out)
{
    if (!out) return NT_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (width < 1 || height < 1 || width > NT_MAP_MAX_SIDE || height > NT_MAP_MAX_SIDE) return NT_ERR_OUT_OF_RANGE;
    if (!nt__finite(cell_size)) return NT_ERR_NON_FINITE;
    if (cell_size <= 0) return NT_ERR_INVALID_ARGUMENT;
    if (cell_size < (nt_real)NT_MIN_CELL_SIZE || cell_size > (nt_real)NT_MAX_CELL_SIZE) return NT_ERR_OUT_OF_RANGE;
    nt_level *lv = (nt_level *)nt__alloc(sizeof *lv);
    if (!lv) return NT_ERR_OUT_OF_MEMORY;
    memset(lv, 0, sizeof *lv);
    size_t n = (size_t)width * (size_t)height;
    lv->tiles = (uint8_t *)nt__alloc(n);
    lv->cell_materials = (uint8_t *)nt__alloc(n);
    lv->cell_flags = (uint8_t *)nt__alloc(n);
    if (!lv->tiles || !lv->cell_materials || !lv->cell_flags) {
        nt_level_destroy(lv);
        return NT_ERR_OUT_OF_MEMORY;
    }
    memset(lv->tiles, 0, n);
    memset(lv->cell_materials, 0, n);
    memset(lv->cell_flags, 0, n);
    nt_world_def wd = nt_default_world_def();
    lv->width = width;
    lv->height = height;
    lv->cell_size = cell_size;
    lv->gravity = wd.gravity;
    lv->friction_model = wd.friction_model;
    lv->enable_sleep = wd.enable_sleep;
    lv->seed = 1;
    for (int i = 0; i < NT_MAX_MATERIALS; i++) lv->materials[i] = wd.tile_material;
    lv->body_material = n_material();
    lv->body_linear_drag = 0;
    *out = lv;
    return NT_OK;
}

void nt_level_destroy(nt_level *lv)
{
    if (!lv) return;
    nt__free(lv->tiles);
    nt__free(lv->cell_materials);
    nt__free(lv->cell_flags);
    nt__free(lv->bodies);
    nt__free(lv->regions);
    nt__free(lv->paths);
    nt__free(lv->spawners);
    nt__free(lv);
}

/* Capacities are not stored in nt_level: an array of count items has room for the
 * next power of two (at least 8), which is what nt__grow_array gives. */
static int cap_of(int count)
{
    int c = 8;
    while (c < count) c *= 2;
    return count == 0 ? 0 : c;
}

nt_level_body nt_level_default_body(const nt_level *lv)
{
    nt_level_body b;
    memset(&b, 0, sizeof b);
    b.type = NT_BODY_DYNAMIC;
    b.shape = nt_shape_aabb(6, 6);
    b.mass = 1;
    b.gravity_scale = 1;
    b.linear_drag = lv ? lv->body_linear_drag : 0;
    b.material = lv ? lv->body_material : n_material();
    b.category = 1;
    b.mask = 0xffffffffu;
    b.enable_sleep = true;
    b.is_awake = true;
    b.path = -1;
    b.repeat_x = 1;
    b.repeat_y = 1;
    return b;
}

int nt_level_find_body(const nt_level *lv, const char *name)
{
    if (!lv || !name) return -1;
    for (int i = 0; i < lv->body_count; i++)
        if (strcmp(lv->bodies[i].name, name) == 0) return i;
    return -1;
}

int nt_level_find_region(const nt_level *lv, const char *name)
{
    if (!lv || !name) return -1;
    for (int i = 0; i < lv->region_count; i++)
        if (strcmp(lv->regions[i].name, name) == 0) return i;
    return -1;
}

int nt_level_find_path(const nt_level *lv, const char *name)
{
    if (!lv || !name) return -1;
    for (int i = 0; i < lv->path_count; i++)
        if (strcmp(lv->paths[i].name, name) == 0) return i;
    return -1;
}

static int count_name(const nt_level *lv, const char *name)
{
    int n = 0;
    for (int i = 0; i < lv->body_count; i++) n += strcmp(lv->bodies[i].name, name) == 0;
    for (int i = 0; i < lv->region_count; i++) n += strcmp(lv->regions[i].name, name) == 0;
    for (int i = 0; i < lv->path_count; i++) n += strcmp(lv->paths[i].name, name) == 0;
    for (int i = 0; i < lv->spawner_count; i++) n += strcmp(lv->spawners[i].name, name) == 0;
    return n;
}

static int name_taken(const nt_level *lv, const char *name) { return count_name(lv, name) > 0; }

int nt_level_instance_count(const nt_level *lv)
{
    if (!lv) return 0;
    long long n = 0;
    for (int i = 0; i < lv->body_count; i++)
        if (!lv->bodies[i].is_template) n += (long long)lv->bodies[i].repeat_x * lv->bodies[i].repeat_y;
    return n > NT_LEVEL_MAX_BODIES ? NT_LEVEL_MAX_BODIES : (int)n;
}

/* ---------------------------------------------------------------- checks shared by the parser and the API */

static int fin2(nt_vec2 v) { return nt__finite(v.x) && nt__finite(v.y); }

/* A material under a friction model; NULL when valid, else why not. */
static const char *material_problem(nt_friction_model model, nt_material m)
{
    if (!nt__finite(m.friction) || !nt__finite(m.bounce)) return "non-finite friction or bounce";
    if (m.friction < 0) return "negative friction";
    if (model == NT_FRICTION_N && m.friction > 1) return "friction above 1 (the limit of the N friction model)";
    if (m.bounce < 0 || m.bounce > 1) return "bounce outside 0..1";
    return NULL;
}

/* A shape against the cell size (half-size at most NT_MAX_HALF_CELLS cells); NULL when valid. */
static const char *shape_problem(const nt_level *lv, nt_shape s)
{
    if (s.type != NT_SHAPE_AABB && s.type != NT_SHAPE_CIRCLE) return "unknown shape type";
    if (!fin2(s.half)) return "non-finite size";
    if (s.half.x <= 0 || s.half.y <= 0) return "size must be > 0";
    if (s.type == NT_SHAPE_CIRCLE && s.half.x != s.half.y) return "a circle needs equal halves";
    nt_real cap = lv->cell_size * NT_MAX_HALF_CELLS;
    if (s.half.x > cap || s.half.y > cap) return nt_status_string(NT_ERR_SHAPE_TOO_LARGE);
    return NULL;
}

static long long instances_of(const nt_level_body *b)
{
    return b->is_template ? 0 : (long long)b->repeat_x * b->repeat_y;
}

static long long total_instances(const nt_level *lv)
{
    long long n = 0;
    for (int i = 0; i < lv->body_count; i++) n += instances_of(&lv->bodies[i]);
    return n;
}

/* Within NT_WORLD_REACH_CELLS cells of the map, computed as the world computes it
 * (a world refuses anything farther out). */
static int in_reach(const nt_level *lv, nt_vec2 p)
{
    nt_real m = lv->cell_size * NT_WORLD_REACH_CELLS;
    return p.x >= -m && p.y >= -m && p.x <= (nt_real)lv->width * lv->cell_size + m &&
           p.y <= (nt_real)lv->height * lv->cell_size + m;
}

/* The last instance of a body's repeat grid (the first is its position): between
 * them they hold the grid's extremes on both axes. */
static nt_vec2 last_instance(const nt_level_body *b)
{
    return nt_v2(b->position.x + (nt_real)(b->repeat_x - 1) * b->repeat_step.x,
                 b->position.y + (nt_real)(b->repeat_y - 1) * b->repeat_step.y);
}

/* Every instance of a body within reach. */
static int body_in_reach(const nt_level *lv, const nt_level_body *b)
{
    return in_reach(lv, b->position) && in_reach(lv, last_instance(b));
}

/* A shape at p wholly inside the map, computed as the world computes it. */
static int inside_map(const nt_level *lv, nt_vec2 p, nt_vec2 h)
{
    return p.x - h.x >= 0 && p.y - h.y >= 0 && p.x + h.x <= (nt_real)lv->width * lv->cell_size &&
           p.y + h.y <= (nt_real)lv->height * lv->cell_size;
}

/* A body above half a cell must lie wholly inside the map where the world creates it
 * (nt_body_create refuses it otherwise): every instance; templates are created where
 * their spawner says. */
static int body_fits_map(const nt_level *lv, const nt_level_body *b)
{
    nt_real lim = lv->cell_size * (nt_real)0.5;
    if (b->is_template || (b->shape.half.x <= lim && b->shape.half.y <= lim)) return 1;
    return inside_map(lv, b->position, b->shape.half) && inside_map(lv, last_instance(b), b->shape.half);
}

/* 1 + index of a region: whether it names a switch region of the level. */
static int is_switch(const nt_level *lv, int one_based)
{
    return one_based >= 1 && one_based <= lv->region_count && lv->regions[one_based - 1].kind == NT_REGION_SWITCH;
}

static const char *body_problem(const nt_level *lv, const nt_level_body *b)
{
    const char *p;
    if (!nt__valid_name(b->name)) return "invalid name";
    if (b->type != NT_BODY_STATIC && b->type != NT_BODY_KINEMATIC && b->type != NT_BODY_DYNAMIC) return "unknown type";
    if ((p = shape_problem(lv, b->shape)) != NULL) return p;
    if (!fin2(b->position) || !fin2(b->velocity) || !nt__finite(b->mass) || !nt__finite(b->gravity_scale) ||
        !nt__finite(b->linear_drag) || !nt__finite(b->phase) || !fin2(b->repeat_step))
        return "non-finite number";
    if (b->mass <= 0) return "mass must be > 0";
    if (b->type == NT_BODY_DYNAMIC && !(b->mass >= NT_MIN_MASS && b->mass <= NT_MAX_MASS)) return "mass outside 1e-12 .. 1e12";
    if (b->linear_drag < 0) return "negative drag";
    if (nt__fabs(b->gravity_scale) > (nt_real)NT_MAX_GRAVITY_SCALE) return "gravity scale outside -1e6 .. 1e6";
    if ((p = material_problem(lv->friction_model, b->material)) != NULL) return p;
    if (b->path < -1 || b->path >= lv->path_count) return "unknown path";
    if (b->path >= 0 && b->type != NT_BODY_KINEMATIC) return "only kinematic bodies follow paths";
    if (b->phase < 0 || b->phase >= 1) return "phase outside [0, 1)";
    if (b->score < 0 || b->score > 1000000) return "score outside 0..1000000";
    if (b->score > 0 && !b->is_sensor) return "a body with a score must be a sensor";
    if (b->repeat_x < 1 || b->repeat_y < 1 || b->repeat_x > 10000 || b->repeat_y > 10000) return "repeat outside 1..10000";
    if (b->is_template && (b->repeat_x > 1 || b->repeat_y > 1)) return "a template cannot repeat";
    if (!body_in_reach(lv, b)) return "position more than 64 cells outside the map";
    if (!body_fits_map(lv, b)) return "a body larger than half a cell must lie inside the map";
    if (b->door < NT_DOOR_NONE || b->door > NT_DOOR_TRAP) return "unknown door kind";
    if (b->door != NT_DOOR_NONE && (b->type == NT_BODY_DYNAMIC || b->is_sensor || b->is_template))
        return "a door is a solid static or kinematic body, not a template";
    if ((b->door == NT_DOOR_LOCKED || b->door == NT_DOOR_TRAP) != (b->door_switch != 0)) return "a locked or trap door (only) names its switch";
    if (b->door_switch != 0 && !is_switch(lv, b->door_switch)) return "the door's switch is not a switch region";
    if (b->one_way < NT_ONE_WAY_NONE || b->one_way > NT_ONE_WAY_UP) return "unknown one-way side";
    if (b->one_way != NT_ONE_WAY_NONE && (b->type == NT_BODY_DYNAMIC || b->is_sensor || b->is_template || b->door != NT_DOOR_NONE))
        return "a one-way body is a solid static or kinematic body, not a door or a template";
    return NULL;
}

static const char *path_problem(const nt_level_path *p)
{
    if (!nt__valid_name(p->name)) return "invalid name";
    if (!nt__finite(p->speed) || !fin2(p->center) || !nt__finite(p->radius) || !nt__finite(p->wait))
        return "non-finite number";
    if (p->speed <= 0) return "speed must be > 0";
    if (p->wait < 0) return "negative wait";
    if (p->mode == NT_PATH_ORBIT && p->wait != 0) return "an orbit has no waypoints to wait at";
    if (p->mode == NT_PATH_ORBIT) {
        if (p->radius <= 0) return "radius must be > 0";
        return NULL;
    }
    if (p->mode != NT_PATH_LOOP && p->mode != NT_PATH_PINGPONG) return "unknown path mode";
    if (p->point_count < 2 || p->point_count > NT_LEVEL_MAX_PATH_POINTS) return "needs 2 to 64 points";
    for (int i = 0; i < p->point_count; i++)
        if (!fin2(p->points[i])) return "non-finite point";
    return NULL;
}

static const char *region_problem(const nt_level *lv, const nt_level_region *r)
{
    if (!nt__valid_name(r->name)) return "invalid name";
    if (r->kind < NT_REGION_ZONE || r->kind > NT_REGION_SWITCH) return "unknown kind";
    if (r->needs != 0 && (r->kind != NT_REGION_EXIT || !is_switch(lv, r->needs)))
        return "only an exit needs a switch, and it must be a switch region";
    if (!fin2(r->lo) || !fin2(r->hi)) return "non-finite corner";
    if (!(r->lo.x < r->hi.x) || !(r->lo.y < r->hi.y)) return "empty region (lo must be below hi)";
    if (r->kind == NT_REGION_SCORE && (r->value < 1 || r->value > 1000000)) return "score value outside 1..1000000";
    if (r->kind != NT_REGION_SCORE && r->value != 0) return "only score regions have a value";
    return NULL;
}

static const char *spawner_problem(const nt_level *lv, const nt_level_spawner *s)
{
    if (!nt__valid_name(s->name)) return "invalid name";
    if (s->template_body < 0 || s->template_body >= lv->body_count) return "unknown template body";
    if (!lv->bodies[s->template_body].is_template) return "spawns a body that is not a template";
    if (s->trigger != NT_SPAWN_ACTION && s->trigger != NT_SPAWN_EVERY) return "unknown trigger";
    if (s->trigger == NT_SPAWN_EVERY && (s->every < 1 || s->every > 100000000 || s->start < 1 || s->start > 100000000))
        return "every and start must be in 1..100000000";
    if (s->limit < 1 || s->limit > NT_LEVEL_MAX_BODIES) return "limit outside 1..1000000";
    if (s->attach < -1 || s->attach >= lv->body_count) return "unknown attached body";
    if (s->attach >= 0 && lv->bodies[s->attach].is_template) return "attached to a template";
    if (!fin2(s->offset) || !nt__finite(s->jitter)) return "non-finite number";
    if (s->jitter < 0) return "negative jitter";
    return NULL;
}

/* Append a copy of item to an array of the level (count items, capacity implied). */
static nt_status append(void **arr, int *count, const void *item, size_t size)
{
    int cap = cap_of(*count);
    if (!nt__grow_array(arr, *count, &cap, size)) return NT_ERR_OUT_OF_MEMORY;
    memcpy((char *)*arr + (size_t)*count * size, item, size);
    ++*count;
    return NT_OK;
}

/* The shared checks of nt_level_add_*: what (e.g. "body"), its name and its problem. */
static nt_status add_problem(const nt_level *lv, const char *what, const char *name, const char *problem,
                             nt_text_error *err)
{
    if (problem) {
        /* An invalid name may not even be terminated: it is not quoted back. */
        if (!nt__valid_name(name)) return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "%s: %s", what, problem);
        return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "%s '%s': %s", what, name, problem);
    }
    if (name_taken(lv, name))
        return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "%s '%s': the name is taken by another object", what, name);
    return NT_OK;
}

nt_status nt_level_add_body(nt_level *lv, const nt_level_body *b, int *index, nt_text_error *err)
{
    if (!lv || !b) return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "body: NULL level or body");
    nt_status s = add_problem(lv, "body", b->name, body_problem(lv, b), err);
    if (s != NT_OK) return s;
    if (total_instances(lv) + instances_of(b) > NT_LEVEL_MAX_BODIES)
        return nt__error_plain(err, NT_ERR_LIMIT, "body '%s': the level would hold more than %d bodies", b->name,
                               NT_LEVEL_MAX_BODIES);
    s = append((void **)&lv->bodies, &lv->body_count, b, sizeof *b);
    if (s != NT_OK) return nt__error_plain(err, s, "body '%s': out of memory", b->name);
    if (index) *index = lv->body_count - 1;
    return NT_OK;
}

/* nt_level_add_region, _path and _spawner: the shared checks, the per-kind limit,
 * then the append (index, when wanted, receives the new one's). */
static nt_status add_object(nt_level *lv, const char *what, const char *plural, const char *name,
                            const char *problem, void **arr, int *count, const void *item, size_t size, int *index,
                            nt_text_error *err)
{
    nt_status s = add_problem(lv, what, name, problem, err);
    if (s != NT_OK) return s;
    if (*count >= NT_LEVEL_MAX_OBJECTS)
        return nt__error_plain(err, NT_ERR_LIMIT, "%s '%s': the level already holds %d %s", what, name,
                               NT_LEVEL_MAX_OBJECTS, plural);
    s = append(arr, count, item, size);
    if (s != NT_OK) return nt__error_plain(err, s, "%s '%s': out of memory", what, name);
    if (index) *index = *count - 1;
    return NT_OK;
}

nt_status nt_level_add_region(nt_level *lv, const nt_level_region *r, nt_text_error *err)
{
    if (!lv || !r) return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "region: NULL level or region");
    return add_object(lv, "region", "regions", r->name, region_problem(lv, r), (void **)&lv->regions, &lv->region_count,
                      r, sizeof *r, NULL, err);
}

nt_status nt_level_add_path(nt_level *lv, const nt_level_path *p, int *index, nt_text_error *err)
{
    if (!lv || !p) return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "path: NULL level or path");
    return add_object(lv, "path", "paths", p->name, path_problem(p), (void **)&lv->paths, &lv->path_count, p,
                      sizeof *p, index, err);
}

nt_status nt_level_add_spawner(nt_level *lv, const nt_level_spawner *sp, nt_text_error *err)
{
    if (!lv || !sp) return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "spawner: NULL level or spawner");
    return add_object(lv, "spawner", "spawners", sp->name, spawner_problem(lv, sp), (void **)&lv->spawners,
                      &lv->spawner_count, sp, sizeof *sp, NULL, err);
}

static int compare_names(const void *a, const void *b) { return strcmp(*(const char *const *)a, *(const char *const *)b); }

nt_status nt_level_validate(const nt_level *lv, nt_text_error *err)
{
    if (!lv) return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "level: NULL");
    if (lv->width < 1 || lv->height < 1 || lv->width > NT_MAP_MAX_SIDE || lv->height > NT_MAP_MAX_SIDE)
        return nt__error_plain(err, NT_ERR_OUT_OF_RANGE, "level: size %dx%d outside 1..%d", lv->width, lv->height,
                               NT_MAP_MAX_SIDE);
    if (!nt__finite(lv->cell_size) || lv->cell_size <= 0)
        return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "level: cell size must be finite and > 0");
    if (lv->cell_size < (nt_real)NT_MIN_CELL_SIZE || lv->cell_size > (nt_real)NT_MAX_CELL_SIZE)
        return nt__error_plain(err, NT_ERR_OUT_OF_RANGE, "level: cell size %g outside %g .. %g", (double)lv->cell_size,
                               (double)NT_MIN_CELL_SIZE, (double)NT_MAX_CELL_SIZE);
    if (!lv->tiles || !lv->cell_materials || !lv->cell_flags)
        return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "level: missing cell arrays");
    if (!nt__valid_text(lv->title, NT_LEVEL_TEXT_MAX) || !nt__valid_text(lv->author, NT_LEVEL_TEXT_MAX))
        return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "level: title or author holds '\"', '\\' or a control character");
    if (!fin2(lv->gravity) || !nt__finite(lv->body_linear_drag) || (lv->has_player && !fin2(lv->player)))
        return nt__error_plain(err, NT_ERR_NON_FINITE, "level: non-finite setting");
    if (nt__fabs(lv->gravity.x) > (nt_real)NT_MAX_GRAVITY || nt__fabs(lv->gravity.y) > (nt_real)NT_MAX_GRAVITY)
        return nt__error_plain(err, NT_ERR_OUT_OF_RANGE, "level: gravity beyond %g", (double)NT_MAX_GRAVITY);
    if (lv->friction_model != NT_FRICTION_N && lv->friction_model != NT_FRICTION_COULOMB)
        return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "level: unknown friction model");
    if (lv->has_player && !in_reach(lv, lv->player))
        return nt__error_plain(err, NT_ERR_OUT_OF_RANGE, "level: player spawn more than %d cells outside the map",
                               NT_WORLD_REACH_CELLS);
    if (lv->body_linear_drag < 0) return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "level: negative body drag");
    const char *p;
    for (int i = 0; i < NT_MAX_MATERIALS; i++)
        if ((p = material_problem(lv->friction_model, lv->materials[i])) != NULL)
            return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "level: material %d: %s", i, p);
    if ((p = material_problem(lv->friction_model, lv->body_material)) != NULL)
        return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "level: body material: %s", p);
    size_t n = (size_t)lv->width * (size_t)lv->height;
    for (size_t k = 0; k < n; k++) {
        if (lv->tiles[k] >= NT_TILE_COUNT || lv->cell_materials[k] >= NT_MAX_MATERIALS || (lv->cell_flags[k] & ~NT_CELL_ONE_WAY))
            return nt__error_plain(err, NT_ERR_OUT_OF_RANGE, "level: cell %zu,%zu: tile, material or flags out of range",
                                   k % (size_t)lv->width, k / (size_t)lv->width);
    }
    for (int i = 0; i < lv->path_count; i++)
        if ((p = path_problem(&lv->paths[i])) != NULL)
            return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "level: path '%s': %s", lv->paths[i].name, p);
    for (int i = 0; i < lv->region_count; i++)
        if ((p = region_problem(lv, &lv->regions[i])) != NULL ||
            (p = lv->regions[i].needs > i ? "its switch must come before it" : NULL) != NULL)
            return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "level: region '%s': %s", lv->regions[i].name, p);
    for (int i = 0; i < lv->body_count; i++)
        if ((p = body_problem(lv, &lv->bodies[i])) != NULL)
            return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "level: body '%s': %s", lv->bodies[i].name, p);
    for (int i = 0; i < lv->spawner_count; i++)
        if ((p = spawner_problem(lv, &lv->spawners[i])) != NULL)
            return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "level: spawner '%s': %s", lv->spawners[i].name, p);
    if (total_instances(lv) > NT_LEVEL_MAX_BODIES)
        return nt__error_plain(err, NT_ERR_LIMIT, "level: more than %d bodies", NT_LEVEL_MAX_BODIES);
    /* One namespace for every named object (the writer relies on it): sort the
     * names and compare neighbours. */
    size_t total = (size_t)lv->body_count + (size_t)lv->region_count + (size_t)lv->path_count + (size_t)lv->spawner_count;
    if (total < 2) return NT_OK;
    const char **names = (const char **)nt__alloc(total * sizeof *names);
    if (!names) return nt__error_plain(err, NT_ERR_OUT_OF_MEMORY, "level: out of memory");
    size_t k = 0;
    for (int i = 0; i < lv->body_count; i++) names[k++] = lv->bodies[i].name;
    for (int i = 0; i < lv->region_count; i++) names[k++] = lv->regions[i].name;
    for (int i = 0; i < lv->path_count; i++) names[k++] = lv->paths[i].name;
    for (int i = 0; i < lv->spawner_count; i++) names[k++] = lv->spawners[i].name;
    qsort(names, total, sizeof *names, compare_names);
    nt_status st = NT_OK;
    for (k = 1; k < total && st == NT_OK; k++)
        if (strcmp(names[k - 1], names[k]) == 0)
            st = nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "level: duplicate name '%s'", names[k]);
    nt__free(names);
    return st;
}

/* ---------------------------------------------------------------- the parser */

enum { SEC_SETTINGS = 0, SEC_GRIDS = 1, SEC_OBJECTS = 2 };
enum { GRID_TILES = 0, GRID_MATERIALS = 1, GRID_FLAGS = 2 };

/* Where each setting was given, so a repeat can say where the first one is. */
enum { K_TITLE, K_AUTHOR, K_SIZE, K_CELL, K_GRAVITY, K_MODEL, K_SLEEP, K_SEED, K_BODY_MATERIAL, K_BODY_DRAG, K_PLAYER, K_COUNT };
static const char *const setting_names[K_COUNT] = {"title", "author", "size", "cell", "gravity", "friction-model",
                                                   "sleep", "seed", "body-material", "body-drag", "player"};

/* Name table: the line of each definition, for "duplicate name" messages. Names of
 * all four kinds share one table (open addressing, FNV-1a). */
typedef struct name_slot {
    char text[NT_LEVEL_NAME_MAX];
    int line;
    int used;
} name_slot;

typedef struct parser {
    nt__text t;
    nt_level *lv;
    int section;
    int grid_line[3];
    int key_line[K_COUNT];
    int material_line[NT_MAX_MATERIALS];
    int material_col[NT_MAX_MATERIALS], body_material_col;
    long long instances;
    name_slot *names;
    size_t name_cap, name_count;
} parser;

static uint64_t fnv(const char *s)
{
    uint64_t h = 1469598103934665603ull;
    for (; *s; s++) h = (h ^ (unsigned char)*s) * 1099511628211ull;
    return h;
}

static name_slot *name_lookup(parser *P, const char *name)
{
    if (P->name_cap == 0) return NULL;
    size_t i = (size_t)fnv(name) & (P->name_cap - 1);
    while (P->names[i].used) {
        if (strcmp(P->names[i].text, name) == 0) return &P->names[i];
        i = (i + 1) & (P->name_cap - 1);
    }
    return NULL;
}

static int name_insert(parser *P, const char *name, int line)
{
    if ((P->name_count + 1) * 2 > P->name_cap) {
        size_t cap = P->name_cap ? P->name_cap * 2 : 64;
        name_slot *t = (name_slot *)nt__alloc(cap * sizeof *t);
        if (!t) return 0;
        memset(t, 0, cap * sizeof *t);
        for (size_t k = 0; k < P->name_cap; k++) {
            if (!P->names[k].used) continue;
            size_t i = (size_t)fnv(P->names[k].text) & (cap - 1);
            while (t[i].used) i = (i + 1) & (cap - 1);
            t[i] = P->names[k];
        }
        nt__free(P->names);
        P->names = t;
        P->name_cap = cap;
    }
    size_t i = (size_t)fnv(name) & (P->name_cap - 1);
    while (P->names[i].used) i = (i + 1) & (P->name_cap - 1);
    P->names[i].used = 1;
    P->names[i].line = line;
    strcpy(P->names[i].text, name);
    P->name_count++;
    return 1;
}

/* Read field `i` as a new object name. */
static nt_status new_name(parser *P, int i, const char *what, char *out)
{
    nt__text *t = &P->t;
    nt_status s = nt__field_name(t, &t->f[i], what, out);
    if (s != NT_OK) return s;
    const name_slot *prev = name_lookup(P, out);
    if (prev) return nt__fail_col(t, t->f[i].col, "duplicate name '%s' (first defined at line %d)", out, prev->line);
    if (!name_insert(P, out, t->line)) return NT_ERR_OUT_OF_MEMORY;
    return NT_OK;
}

static nt_status need(parser *P, int i, const char *form)
{
    nt__text *t = &P->t;
    if (i < t->nf) return NT_OK;
    return nt__fail_col(t, nt__text_eol_col(t), "missing fields: expected '%s'", form);
}

static nt_status real_at(parser *P, int i, const char *what, nt_real *out) { return nt__field_real(&P->t, &P->t.f[i], what, out); }

static nt_status positive_at(parser *P, int i, const char *what, nt_real *out)
{
    nt_status s = real_at(P, i, what, out);
    if (s == NT_OK && !(*out > 0)) {
        char q[NT__QUOTE_MAX];
        return nt__fail_col(&P->t, P->t.f[i].col, "%s '%s' must be > 0", what, nt__quote(q, P->t.f[i].s, P->t.f[i].n));
    }
    return s;
}

static nt_status nonneg_at(parser *P, int i, const char *what, nt_real *out)
{
    nt_status s = real_at(P, i, what, out);
    if (s == NT_OK && *out < 0) {
        char q[NT__QUOTE_MAX];
        return nt__fail_col(&P->t, P->t.f[i].col, "%s '%s' must be >= 0", what, nt__quote(q, P->t.f[i].s, P->t.f[i].n));
    }
    return s;
}

static nt_status vec_at(parser *P, int i, const char *what_x, const char *what_y, nt_vec2 *out)
{
    nt_status s = real_at(P, i, what_x, &out->x);
    return s != NT_OK ? s : real_at(P, i + 1, what_y, &out->y);
}

/* A real at field i within [-lim, lim] (lo > 0: also at least lo). */
static nt_status ranged_at(parser *P, int i, const char *what, nt_real lo, nt_real lim, nt_real *out)
{
    nt_status s = real_at(P, i, what, out);
    if (s == NT_OK && (nt__fabs(*out) > lim || (lo > 0 && !(*out >= lo)))) {
        char q[NT__QUOTE_MAX];
        if (lo > 0)
            return nt__fail_col(&P->t, P->t.f[i].col, "%s '%s' is outside %g .. %g", what,
                                nt__quote(q, P->t.f[i].s, P->t.f[i].n), (double)lo, (double)lim);
        return nt__fail_col(&P->t, P->t.f[i].col, "%s '%s' is outside -%g .. %g", what,
                            nt__quote(q, P->t.f[i].s, P->t.f[i].n), (double)lim, (double)lim);
    }
    return s;
}

/* `material` fields friction, bounce at i, i+1, checked against the friction model. */
static nt_status material_at(parser *P, int i, const char *what, nt_material *m)
{
    nt__text *t = &P->t;
    char q[NT__QUOTE_MAX], w[64];
    snprintf(w, sizeof w, "%s friction", what);
    nt_status s = nonneg_at(P, i, w, &m->friction);
    if (s != NT_OK) return s;
    snprintf(w, sizeof w, "%s bounce", what);
    if ((s = nonneg_at(P, i + 1, w, &m->bounce)) != NT_OK) return s;
    if (m->bounce > 1)
        return nt__fail_col(t, t->f[i + 1].col, "%s bounce '%s' is above 1", what, nt__quote(q, t->f[i + 1].s, t->f[i + 1].n));
    return NT_OK;
}

static nt_status check_model_friction(parser *P, nt_material m, int line, int col, const char *what)
{
    if (P->lv->friction_model == NT_FRICTION_N && m.friction > 1)
        return nt__fail(&P->t, line, col, "%s friction %g is above 1, the limit of the N friction model", what,
                        (double)m.friction);
    return NT_OK;
}

static nt_status setting_once(parser *P, int key)
{
    nt__text *t = &P->t;
    if (P->key_line[key])
        return nt__fail_col(t, t->f[0].col, "duplicate '%s' (first at line %d)", setting_names[key], P->key_line[key]);
    P->key_line[key] = t->line;
    return NT_OK;
}

static nt_status parse_setting(parser *P, int key)
{
    nt__text *t = &P->t;
    nt_level *lv = P->lv;
    nt_status s = setting_once(P, key);
    if (s != NT_OK) return s;
    switch (key) {
    case K_TITLE:
    case K_AUTHOR:
        if ((s = nt__expect_fields(t, 2, key == K_TITLE ? "title \"TEXT\"" : "author \"TEXT\"")) != NT_OK) return s;
        return nt__field_string(t, &t->f[1], setting_names[key], key == K_TITLE ? lv->title : lv->author,
                                NT_LEVEL_TEXT_MAX, 0);
    case K_SIZE: {
        if ((s = nt__expect_fields(t, 3, "size WIDTH HEIGHT")) != NT_OK) return s;
        long long w, h;
        if ((s = nt__field_int(t, &t->f[1], "width", 1, NT_MAP_MAX_SIDE, &w)) != NT_OK) return s;
        if ((s = nt__field_int(t, &t->f[2], "height", 1, NT_MAP_MAX_SIDE, &h)) != NT_OK) return s;
        lv->width = (int)w;
        lv->height = (int)h;
        return NT_OK;
    }
    case K_CELL:
        if ((s = nt__expect_fields(t, 2, "cell SIZE")) != NT_OK) return s;
        if ((s = positive_at(P, 1, "cell size", &lv->cell_size)) != NT_OK) return s;
        return ranged_at(P, 1, "cell size", (nt_real)NT_MIN_CELL_SIZE, (nt_real)NT_MAX_CELL_SIZE, &lv->cell_size);
    case K_GRAVITY:
        if ((s = nt__expect_fields(t, 3, "gravity X Y")) != NT_OK) return s;
        if ((s = ranged_at(P, 1, "gravity x", 0, (nt_real)NT_MAX_GRAVITY, &lv->gravity.x)) != NT_OK) return s;
        return ranged_at(P, 2, "gravity y", 0, (nt_real)NT_MAX_GRAVITY, &lv->gravity.y);
    case K_MODEL:
        if ((s = nt__expect_fields(t, 2, "friction-model n|coulomb")) != NT_OK) return s;
        if (nt__field_is(&t->f[1], "n")) lv->friction_model = NT_FRICTION_N;
        else if (nt__field_is(&t->f[1], "coulomb")) lv->friction_model = NT_FRICTION_COULOMB;
        else {
            char q[NT__QUOTE_MAX];
            return nt__fail_col(t, t->f[1].col, "unknown friction model '%s' (expected n or coulomb)",
                                nt__quote(q, t->f[1].s, t->f[1].n));
        }
        return NT_OK;
    case K_SLEEP:
        if ((s = nt__expect_fields(t, 2, "sleep on|off")) != NT_OK) return s;
        if (nt__field_is(&t->f[1], "on")) lv->enable_sleep = true;
        else if (nt__field_is(&t->f[1], "off")) lv->enable_sleep = false;
        else {
            char q[NT__QUOTE_MAX];
            return nt__fail_col(t, t->f[1].col, "expected on or off, got '%s'", nt__quote(q, t->f[1].s, t->f[1].n));
        }
        return NT_OK;
    case K_SEED: {
        if ((s = nt__expect_fields(t, 2, "seed N")) != NT_OK) return s;
        long long v;
        if ((s = nt__field_int(t, &t->f[1], "seed", 0, 0x7fffffffffffffffLL, &v)) != NT_OK) return s;
        lv->seed = (uint64_t)v;
        return NT_OK;
    }
    case K_BODY_MATERIAL:
        if ((s = nt__expect_fields(t, 3, "body-material FRICTION BOUNCE")) != NT_OK) return s;
        P->body_material_col = t->f[1].col;
        return material_at(P, 1, "body-material", &lv->body_material);
    case K_BODY_DRAG:
        if ((s = nt__expect_fields(t, 2, "body-drag D")) != NT_OK) return s;
        return nonneg_at(P, 1, "body drag", &lv->body_linear_drag);
    }
    return NT_OK;
}

static nt_status parse_material(parser *P)
{
    nt__text *t = &P->t;
    nt_status s = nt__expect_fields(t, 4, "material INDEX FRICTION BOUNCE");
    if (s != NT_OK) return s;
    long long i;
    if ((s = nt__field_int(t, &t->f[1], "material index", 0, NT_MAX_MATERIALS - 1, &i)) != NT_OK) return s;
    if (P->material_line[i])
        return nt__fail_col(t, t->f[1].col, "duplicate material %lld (first at line %d)", i, P->material_line[i]);
    P->material_line[i] = t->line;
    P->material_col[i] = t->f[2].col;
    return material_at(P, 2, "material", &P->lv->materials[i]);
}

/* The settings are complete: allocate the grids, fill unset materials, check frictions. */
static nt_status end_settings(parser *P)
{
    nt__text *t = &P->t;
    nt_level *lv = P->lv;
    if (!P->key_line[K_SIZE]) return nt__fail_col(t, t->f[0].col, "'tiles' before 'size' (the map size must come first)");
    for (int i = 1; i < NT_MAX_MATERIALS; i++)
        if (!P->material_line[i]) lv->materials[i] = lv->materials[0];
    for (int i = 0; i < NT_MAX_MATERIALS; i++) {
        if (!P->material_line[i]) continue;
        nt_status s = check_model_friction(P, lv->materials[i], P->material_line[i], P->material_col[i], "material");
        if (s != NT_OK) return s;
    }
    if (P->key_line[K_BODY_MATERIAL]) {
        nt_status s = check_model_friction(P, lv->body_material, P->key_line[K_BODY_MATERIAL], P->body_material_col,
                                           "body-material");
        if (s != NT_OK) return s;
    }
    size_t n = (size_t)lv->width * (size_t)lv->height;
    lv->tiles = (uint8_t *)nt__alloc(n);
    lv->cell_materials = (uint8_t *)nt__alloc(n);
    lv->cell_flags = (uint8_t *)nt__alloc(n);
    if (!lv->tiles || !lv->cell_materials || !lv->cell_flags) return NT_ERR_OUT_OF_MEMORY;
    memset(lv->tiles, 0, n);
    memset(lv->cell_materials, 0, n);
    memset(lv->cell_flags, 0, n);
    return NT_OK;
}

static const char *const grid_names[3] = {"tiles", "materials", "flags"};

/* Read the `height` rows of a grid block. */
static nt_status parse_grid(parser *P, int grid)
{
    nt__text *t = &P->t;
    nt_level *lv = P->lv;
    int W = lv->width, H = lv->height;
    char q[NT__QUOTE_MAX];
    for (int row = 0; row < H;) {
        int r = nt__text_next_line(t);
        if (r < 0) return NT_ERR_PARSE;
        if (r == 0) {
            int line, col;
            nt__text_eof_pos(t, &line, &col);
            return nt__fail(t, line, col, "unexpected end of file: the '%s' block has %d of %d rows", grid_names[grid],
                            row, H);
        }
        size_t i = 0;
        while (i < t->ll && (t->ls[i] == ' ' || t->ls[i] == '\t' || t->ls[i] == '\r')) i++;
        /* Blank and comment lines may sit between rows; a comment there is '#' then a
         * blank (or nothing), so that a row typed without its '|' is not taken for one. */
        if (i == t->ll || (t->ls[i] == '#' && (i + 1 == t->ll || t->ls[i + 1] == ' ' || t->ls[i + 1] == '\t')))
            continue;
        if (t->ls[i] != '|')
            return nt__fail_col(t, (int)i + 1, "expected row %d of %d of the '%s' block ('|', %d codes, '|'), got '%s'",
                                row + 1, H, grid_names[grid], W, nt__quote(q, t->ls + i, t->ll - i));
        size_t first = i + 1;
        uint8_t *dst = (grid == GRID_TILES ? lv->tiles : grid == GRID_MATERIALS ? lv->cell_materials : lv->cell_flags) +
                       (size_t)row * (size_t)W;
        int k = 0;
        for (;; k++) {
            size_t c = first + (size_t)k;
            if (c >= t->ll)
                return nt__fail_col(t, (int)c + 1, "ragged row: the row ends after %d codes without a closing '|' (expected %d)",
                                    k, W);
            char ch = t->ls[c];
            if (ch == '|') {
                if (k != W) return nt__fail_col(t, (int)c + 1, "ragged row: %d codes, expected %d", k, W);
                break;
            }
            if (k == W) return nt__fail_col(t, (int)c + 1, "ragged row: more than %d codes (no '|' after code %d)", W, W);
            int v;
            if (grid == GRID_TILES) {
                v = nt_level_tile_from_char(ch);
                if (v < 0) {
                    if (ch == '0' || ch == '1')
                        return nt__fail_col(t, (int)c + 1, "unknown tile code '%c' (EMPTY is '.', FULL is '#')", ch);
                    return nt__fail_col(t, (int)c + 1,
                                        "unknown tile code '%s' (expected '.', '#' or an N code '2'..'Q', see the legend)",
                                        nt__quote(q, &t->ls[c], 1));
                }
            } else if (grid == GRID_MATERIALS) {
                v = material_from_char(ch);
                if (v < 0)
                    return nt__fail_col(t, (int)c + 1, "unknown material code '%s' (expected '.', 1-9 or a-f)",
                                        nt__quote(q, &t->ls[c], 1));
            } else {
                v = ch == '.' ? 0 : ch == '-' ? (int)NT_CELL_ONE_WAY : -1;
                if (v < 0)
                    return nt__fail_col(t, (int)c + 1, "unknown flag code '%s' (expected '.' or '-' for one-way)",
                                        nt__quote(q, &t->ls[c], 1));
            }
            dst[k] = (uint8_t)v;
        }
        size_t after = first + (size_t)W + 1;
        while (after < t->ll && (t->ls[after] == ' ' || t->ls[after] == '\t' || t->ls[after] == '\r')) after++;
        if (after < t->ll && t->ls[after] != '#')
            return nt__fail_col(t, (int)after + 1, "unexpected text after the row's closing '|'");
        row++;
    }
    return NT_OK;
}

static nt_status parse_player(parser *P)
{
    nt__text *t = &P->t;
    nt_status s = setting_once(P, K_PLAYER);
    if (s != NT_OK) return s;
    if ((s = nt__expect_fields(t, 3, "player X Y")) != NT_OK) return s;
    if ((s = vec_at(P, 1, "player x", "player y", &P->lv->player)) != NT_OK) return s;
    if (!in_reach(P->lv, P->lv->player))
        return nt__fail_col(&P->t, P->t.f[1].col, "player spawn is more than %d cells outside the map", NT_WORLD_REACH_CELLS);
    P->lv->has_player = true;
    return NT_OK;
}

/* The switch region named by field i: *out = 1 + its index. */
static nt_status switch_at(parser *P, int i, int *out)
{
    nt__text *t = &P->t;
    char name[NT_LEVEL_NAME_MAX];
    nt_status s = nt__field_name(t, &t->f[i], "switch name", name);
    if (s != NT_OK) return s;
    int r = nt_level_find_region(P->lv, name);
    if (r < 0) return nt__fail_col(t, t->f[i].col, "unknown switch '%s' (switches must be defined before what they open)", name);
    if (P->lv->regions[r].kind != NT_REGION_SWITCH)
        return nt__fail_col(t, t->f[i].col, "region '%s' is not a switch (region NAME switch X0 Y0 X1 Y1)", name);
    *out = r + 1;
    return NT_OK;
}

static nt_status parse_region(parser *P)
{
    nt__text *t = &P->t;
    nt_level *lv = P->lv;
    static const char form[] = "region NAME zone|exit|score|kill|switch X0 Y0 X1 Y1 [value N] [needs SWITCH]";
    char q[NT__QUOTE_MAX];
    nt_level_region r;
    memset(&r, 0, sizeof r);
    nt_status s = need(P, 6, form);
    if (s != NT_OK) return s;
    if (lv->region_count >= NT_LEVEL_MAX_OBJECTS)
        return nt__fail_col(t, t->f[0].col, "too many regions (at most %d)", NT_LEVEL_MAX_OBJECTS);
    if ((s = new_name(P, 1, "region name", r.name)) != NT_OK) return s;
    static const char *const kinds[5] = {"zone", "exit", "score", "kill", "switch"};
    int kind = -1;
    for (int k = 0; k < 5; k++)
        if (nt__field_is(&t->f[2], kinds[k])) kind = k;
    if (kind < 0)
        return nt__fail_col(t, t->f[2].col, "unknown region kind '%s' (expected zone, exit, score, kill or switch)",
                            nt__quote(q, t->f[2].s, t->f[2].n));
    r.kind = (nt_region_kind)kind;
    if ((s = vec_at(P, 3, "region x0", "region y0", &r.lo)) != NT_OK) return s;
    if ((s = vec_at(P, 5, "region x1", "region y1", &r.hi)) != NT_OK) return s;
    if (!(r.lo.x < r.hi.x)) return nt__fail_col(t, t->f[5].col, "region x1 must be greater than x0");
    if (!(r.lo.y < r.hi.y)) return nt__fail_col(t, t->f[6].col, "region y1 must be greater than y0");
    if (t->nf > 7 && nt__field_is(&t->f[7], "needs")) {
        if (r.kind != NT_REGION_EXIT) return nt__fail_col(t, t->f[7].col, "only exit regions need a switch");
        if ((s = nt__expect_fields(t, 9, form)) != NT_OK) return s;
        if ((s = switch_at(P, 8, &r.needs)) != NT_OK) return s;
    } else if (t->nf > 7) {
        if (!nt__field_is(&t->f[7], "value"))
            return nt__fail_col(t, t->f[7].col, "unexpected field '%s': expected '%s'", nt__quote(q, t->f[7].s, t->f[7].n), form);
        if (r.kind != NT_REGION_SCORE) return nt__fail_col(t, t->f[7].col, "only score regions have a value");
        if ((s = nt__expect_fields(t, 9, form)) != NT_OK) return s;
        long long v;
        if ((s = nt__field_int(t, &t->f[8], "score value", 1, 1000000, &v)) != NT_OK) return s;
        r.value = (int)v;
    } else if (r.kind == NT_REGION_SCORE) {
        return nt__fail_col(t, nt__text_eol_col(t), "a score region needs 'value N'");
    }
    return append((void **)&lv->regions, &lv->region_count, &r, sizeof r);
}

static nt_status parse_path(parser *P)
{
    nt__text *t = &P->t;
    nt_level *lv = P->lv;
    char q[NT__QUOTE_MAX];
    static const char form[] =
        "path NAME loop|pingpong speed S [wait W] points X Y X Y ... | path NAME orbit speed S center X Y radius R";
    nt_level_path p;
    memset(&p, 0, sizeof p);
    nt_status s = need(P, 5, form);
    if (s != NT_OK) return s;
    if (lv->path_count >= NT_LEVEL_MAX_OBJECTS)
        return nt__fail_col(t, t->f[0].col, "too many paths (at most %d)", NT_LEVEL_MAX_OBJECTS);
    if ((s = new_name(P, 1, "path name", p.name)) != NT_OK) return s;
    if (nt__field_is(&t->f[2], "loop")) p.mode = NT_PATH_LOOP;
    else if (nt__field_is(&t->f[2], "pingpong")) p.mode = NT_PATH_PINGPONG;
    else if (nt__field_is(&t->f[2], "orbit")) p.mode = NT_PATH_ORBIT;
    else
        return nt__fail_col(t, t->f[2].col, "unknown path mode '%s' (expected loop, pingpong or orbit)",
                            nt__quote(q, t->f[2].s, t->f[2].n));
    if (!nt__field_is(&t->f[3], "speed"))
        return nt__fail_col(t, t->f[3].col, "expected 'speed', got '%s'", nt__quote(q, t->f[3].s, t->f[3].n));
    if ((s = positive_at(P, 4, "path speed", &p.speed)) != NT_OK) return s;
    if (p.mode == NT_PATH_ORBIT) {
        if ((s = nt__expect_fields(t, 10, "path NAME orbit speed S center X Y radius R")) != NT_OK) return s;
        if (!nt__field_is(&t->f[5], "center"))
            return nt__fail_col(t, t->f[5].col, "expected 'center', got '%s'", nt__quote(q, t->f[5].s, t->f[5].n));
        if ((s = vec_at(P, 6, "center x", "center y", &p.center)) != NT_OK) return s;
        if (!nt__field_is(&t->f[8], "radius"))
            return nt__fail_col(t, t->f[8].col, "expected 'radius', got '%s'", nt__quote(q, t->f[8].s, t->f[8].n));
        if ((s = positive_at(P, 9, "orbit radius", &p.radius)) != NT_OK) return s;
    } else {
        int i = 5;
        if (nt__field_is(&t->f[5], "wait")) {
            if ((s = need(P, 7, form)) != NT_OK) return s;
            if ((s = nonneg_at(P, 6, "wait", &p.wait)) != NT_OK) return s;
            i = 7;
        }
        if ((s = need(P, i + 1, form)) != NT_OK) return s;
        if (!nt__field_is(&t->f[i], "points"))
            return nt__fail_col(t, t->f[i].col, "expected 'points'%s, got '%s'", i == 5 ? " or 'wait'" : "",
                                nt__quote(q, t->f[i].s, t->f[i].n));
        int first = i + 1;
        int nc = t->nf - first;
        if (nc % 2 != 0) return nt__fail_col(t, nt__text_eol_col(t), "points need pairs X Y: the last point has no y");
        if (nc / 2 < 2) return nt__fail_col(t, nt__text_eol_col(t), "a path needs at least 2 points, got %d", nc / 2);
        if (nc / 2 > NT_LEVEL_MAX_PATH_POINTS)
            return nt__fail_col(t, t->f[first + 2 * NT_LEVEL_MAX_PATH_POINTS].col, "a path has at most %d points",
                                NT_LEVEL_MAX_PATH_POINTS);
        for (int k = 0; k < nc / 2; k++)
            if ((s = vec_at(P, first + 2 * k, "point x", "point y", &p.points[k])) != NT_OK) return s;
        p.point_count = nc / 2;
    }
    return append((void **)&lv->paths, &lv->path_count, &p, sizeof p);
}

/* A body name that must already exist; -1 after setting the error. */
static int ref_body(parser *P, int i, const char *what)
{
    nt__text *t = &P->t;
    char q[NT__QUOTE_MAX];
    char name[NT_LEVEL_NAME_MAX];
    if (nt__field_name(t, &t->f[i], what, name) != NT_OK) return -1;
    int b = nt_level_find_body(P->lv, name);
    if (b < 0) {
        nt__fail_col(t, t->f[i].col, "unknown body '%s' (bodies must be defined before they are named)",
                     nt__quote(q, t->f[i].s, t->f[i].n));
        return -1;
    }
    return b;
}

static nt_status size_at(parser *P, int i, const char *what, nt_real *out)
{
    nt__text *t = &P->t;
    char q[NT__QUOTE_MAX];
    nt_status s = positive_at(P, i, what, out);
    if (s != NT_OK) return s;
    nt_real cap = P->lv->cell_size * NT_MAX_HALF_CELLS;
    if (*out > cap)
        return nt__fail_col(t, t->f[i].col, "%s '%s' is larger than the largest half-size, %d cells (%g)", what,
                            nt__quote(q, t->f[i].s, t->f[i].n), NT_MAX_HALF_CELLS, (double)cap);
    return NT_OK;
}

static nt_status parse_body(parser *P)
{
    nt__text *t = &P->t;
    nt_level *lv = P->lv;
    char q[NT__QUOTE_MAX];
    static const char form[] = "body NAME static|kinematic|dynamic box HW HH|circle R at X Y [OPTIONS]";
    nt_level_body b = nt_level_default_body(lv);
    nt_status s = need(P, 3, form);
    if (s != NT_OK) return s;
    if ((s = new_name(P, 1, "body name", b.name)) != NT_OK) return s;
    if (nt__field_is(&t->f[2], "static")) b.type = NT_BODY_STATIC;
    else if (nt__field_is(&t->f[2], "kinematic")) b.type = NT_BODY_KINEMATIC;
    else if (nt__field_is(&t->f[2], "dynamic")) b.type = NT_BODY_DYNAMIC;
    else
        return nt__fail_col(t, t->f[2].col, "unknown body type '%s' (expected static, kinematic or dynamic)",
                            nt__quote(q, t->f[2].s, t->f[2].n));
    if ((s = need(P, 4, form)) != NT_OK) return s;
    int i;
    if (nt__field_is(&t->f[3], "box")) {
        if ((s = need(P, 6, form)) != NT_OK) return s;
        nt_real hw, hh;
        if ((s = size_at(P, 4, "half-width", &hw)) != NT_OK || (s = size_at(P, 5, "half-height", &hh)) != NT_OK) return s;
        b.shape = nt_shape_aabb(hw, hh);
        i = 6;
    } else if (nt__field_is(&t->f[3], "circle")) {
        if ((s = need(P, 5, form)) != NT_OK) return s;
        nt_real r;
        if ((s = size_at(P, 4, "radius", &r)) != NT_OK) return s;
        b.shape = nt_shape_circle(r);
        i = 5;
    } else {
        return nt__fail_col(t, t->f[3].col, "unknown shape '%s' (expected box or circle)", nt__quote(q, t->f[3].s, t->f[3].n));
    }
    if ((s = need(P, i, form)) != NT_OK) return s;
    if (!nt__field_is(&t->f[i], "at"))
        return nt__fail_col(t, t->f[i].col, "expected 'at X Y', got '%s'", nt__quote(q, t->f[i].s, t->f[i].n));
    int at = i;
    if ((s = need(P, i + 2, form)) != NT_OK) return s;
    if ((s = vec_at(P, i + 1, "x", "y", &b.position)) != NT_OK) return s;
    i += 3;
    /* Options, each at most once. */
    static const char *const opts[] = {"vel",   "mass",   "material", "drag",     "gravity-scale", "category",
                                       "mask",  "sensor", "no-sleep", "asleep",   "path",          "phase",
                                       "score", "deadly", "template", "repeat",   "door",          "opened-by",
                                       "closed-by", "one-way"};
    static const int nargs[] = {2, 1, 2, 1, 1, 1, 1, 0, 0, 0, 1, 1, 1, 0, 0, 4, 0, 1, 1, 1};
    enum { O_VEL, O_MASS, O_MATERIAL, O_DRAG, O_GSCALE, O_CATEGORY, O_MASK, O_SENSOR, O_NOSLEEP, O_ASLEEP, O_PATH, O_PHASE,
           O_SCORE, O_DEADLY, O_TEMPLATE, O_REPEAT, O_DOOR, O_OPENED_BY, O_CLOSED_BY, O_ONE_WAY, O_COUNT };
    int seen[O_COUNT] = {0};
    int material_col = 0, repeat_col = 0;
    while (i < t->nf) {
        int o = -1;
        for (int k = 0; k < O_COUNT; k++)
            if (nt__field_is(&t->f[i], opts[k])) o = k;
        if (o < 0)
            return nt__fail_col(t, t->f[i].col,
                                "unknown body option '%s' (expected vel, mass, material, drag, gravity-scale, category, mask, "
                                "sensor, no-sleep, asleep, path, phase, score, deadly, template, repeat, door, "
                                "opened-by, closed-by or one-way)",
                                nt__quote(q, t->f[i].s, t->f[i].n));
        if (seen[o]) return nt__fail_col(t, t->f[i].col, "duplicate body option '%s'", opts[o]);
        seen[o] = t->f[i].col;
        if (i + nargs[o] >= t->nf && nargs[o] > 0)
            return nt__fail_col(t, nt__text_eol_col(t), "option '%s' needs %d value%s", opts[o], nargs[o], nargs[o] > 1 ? "s" : "");
        int a = i + 1;
        switch (o) {
        case O_VEL: s = vec_at(P, a, "velocity x", "velocity y", &b.velocity); break;
        case O_MASS:
            s = positive_at(P, a, "mass", &b.mass);
            if (s == NT_OK && !(b.mass >= NT_MIN_MASS && b.mass <= NT_MAX_MASS))
                s = nt__fail_col(t, t->f[a].col, "mass '%s' is outside 1e-12 .. 1e12", nt__quote(q, t->f[a].s, t->f[a].n));
            break;
        case O_MATERIAL:
            material_col = t->f[a].col;
            s = material_at(P, a, "body", &b.material);
            if (s == NT_OK) s = check_model_friction(P, b.material, t->line, material_col, "body");
            break;
        case O_DRAG: s = nonneg_at(P, a, "drag", &b.linear_drag); break;
        case O_GSCALE: s = ranged_at(P, a, "gravity scale", 0, (nt_real)NT_MAX_GRAVITY_SCALE, &b.gravity_scale); break;
        case O_CATEGORY: s = nt__field_u32(t, &t->f[a], "category", &b.category); break;
        case O_MASK: s = nt__field_u32(t, &t->f[a], "mask", &b.mask); break;
        case O_SENSOR: b.is_sensor = true; break;
        case O_NOSLEEP: b.enable_sleep = false; break;
        case O_ASLEEP: b.is_awake = false; break;
        case O_PATH: {
            char name[NT_LEVEL_NAME_MAX];
            s = nt__field_name(t, &t->f[a], "path name", name);
            if (s != NT_OK) break;
            b.path = nt_level_find_path(lv, name);
            if (b.path < 0)
                s = nt__fail_col(t, t->f[a].col, "unknown path '%s' (paths must be defined before the bodies on them)", name);
            break;
        }
        case O_PHASE:
            s = real_at(P, a, "phase", &b.phase);
            if (s == NT_OK && (b.phase < 0 || b.phase >= 1))
                s = nt__fail_col(t, t->f[a].col, "phase '%s' is outside [0, 1)", nt__quote(q, t->f[a].s, t->f[a].n));
            break;
        case O_SCORE: {
            long long v;
            s = nt__field_int(t, &t->f[a], "score", 1, 1000000, &v);
            b.score = (int)v;
            break;
        }
        case O_DEADLY: b.deadly = true; break;
        case O_TEMPLATE: b.is_template = true; break;
        case O_DOOR:
        case O_OPENED_BY:
        case O_CLOSED_BY:
            if (b.door != NT_DOOR_NONE) {
                s = nt__fail_col(t, t->f[i].col, "a door is one of 'door', 'opened-by SWITCH' or 'closed-by SWITCH'");
                break;
            }
            b.door = o == O_DOOR ? NT_DOOR_PLAIN : o == O_OPENED_BY ? NT_DOOR_LOCKED : NT_DOOR_TRAP;
            if (o != O_DOOR) s = switch_at(P, a, &b.door_switch);
            break;
        case O_ONE_WAY: {
            static const char *const sides[4] = {"right", "down", "left", "up"};
            for (int k = 0; k < 4; k++)
                if (nt__field_is(&t->f[a], sides[k])) b.one_way = (nt_one_way_side)(k + 1);
            if (b.one_way == NT_ONE_WAY_NONE)
                s = nt__fail_col(t, t->f[a].col, "unknown one-way side '%s' (expected right, down, left or up)",
                                 nt__quote(q, t->f[a].s, t->f[a].n));
            break;
        }
        case O_REPEAT: {
            long long nx, ny;
            repeat_col = t->f[i].col;
            if ((s = nt__field_int(t, &t->f[a], "repeat count x", 1, 10000, &nx)) != NT_OK) break;
            if ((s = nt__field_int(t, &t->f[a + 1], "repeat count y", 1, 10000, &ny)) != NT_OK) break;
            s = vec_at(P, a + 2, "repeat step x", "repeat step y", &b.repeat_step);
            b.repeat_x = (int)nx;
            b.repeat_y = (int)ny;
            break;
        }
        }
        if (s != NT_OK) return s;
        i = a + nargs[o];
    }
    if (b.path >= 0 && b.type != NT_BODY_KINEMATIC)
        return nt__fail_col(t, seen[O_PATH], "only kinematic bodies follow paths (this body is %s)",
                            b.type == NT_BODY_STATIC ? "static" : "dynamic");
    if (seen[O_PHASE] && b.path < 0) return nt__fail_col(t, seen[O_PHASE], "'phase' needs 'path'");
    if (b.score > 0 && !b.is_sensor) return nt__fail_col(t, seen[O_SCORE], "a body with a score must be a sensor (add 'sensor')");
    if (b.is_template && (b.repeat_x > 1 || b.repeat_y > 1)) return nt__fail_col(t, repeat_col, "a template cannot repeat");
    if (b.one_way != NT_ONE_WAY_NONE && (b.type == NT_BODY_DYNAMIC || b.is_sensor || b.is_template || b.door != NT_DOOR_NONE))
        return nt__fail_col(t, seen[O_ONE_WAY],
                            "a one-way body is a solid static or kinematic body (not dynamic, a sensor, a template or a door)");
    if (b.door != NT_DOOR_NONE && (b.type == NT_BODY_DYNAMIC || b.is_sensor || b.is_template)) {
        int col = seen[O_DOOR] ? seen[O_DOOR] : seen[O_OPENED_BY] ? seen[O_OPENED_BY] : seen[O_CLOSED_BY];
        return nt__fail_col(t, col, "a door is a solid static or kinematic body (not dynamic, a sensor or a template)");
    }
    if (!in_reach(lv, b.position))
        return nt__fail_col(t, t->f[at + 1].col, "position %g %g is more than %d cells outside the map", (double)b.position.x,
                            (double)b.position.y, NT_WORLD_REACH_CELLS);
    if (!body_in_reach(lv, &b))
        return nt__fail_col(t, repeat_col, "the repeat grid reaches more than %d cells outside the map", NT_WORLD_REACH_CELLS);
    if (!inside_map(lv, b.position, b.shape.half) && !body_fits_map(lv, &b))
        return nt__fail_col(t, t->f[at + 1].col,
                            "a body larger than half a cell must lie inside the map (0 0 .. %g %g): at %g %g it reaches outside",
                            (double)((nt_real)lv->width * lv->cell_size), (double)((nt_real)lv->height * lv->cell_size),
                            (double)b.position.x, (double)b.position.y);
    if (!body_fits_map(lv, &b))
        return nt__fail_col(t, repeat_col, "the repeat grid takes a body larger than half a cell outside the map");
    long long add = instances_of(&b);
    if (P->instances + add > NT_LEVEL_MAX_BODIES)
        return nt__fail_col(t, t->f[1].col, "too many bodies: more than %d in the level", NT_LEVEL_MAX_BODIES);
    P->instances += add;
    return append((void **)&lv->bodies, &lv->body_count, &b, sizeof b);
}

static nt_status parse_spawner(parser *P)
{
    nt__text *t = &P->t;
    nt_level *lv = P->lv;
    char q[NT__QUOTE_MAX];
    static const char form[] = "spawner NAME TEMPLATE action|every N [start T] limit K [attach BODY] [offset DX DY] [jitter J]";
    nt_level_spawner sp;
    memset(&sp, 0, sizeof sp);
    sp.attach = -1;
    sp.trigger = (nt_spawn_trigger)-1;
    nt_status s = need(P, 3, form);
    if (s != NT_OK) return s;
    if (lv->spawner_count >= NT_LEVEL_MAX_OBJECTS)
        return nt__fail_col(t, t->f[0].col, "too many spawners (at most %d)", NT_LEVEL_MAX_OBJECTS);
    if ((s = new_name(P, 1, "spawner name", sp.name)) != NT_OK) return s;
    if ((sp.template_body = ref_body(P, 2, "template body")) < 0) return NT_ERR_PARSE;
    if (!lv->bodies[sp.template_body].is_template)
        return nt__fail_col(t, t->f[2].col, "body '%s' is not a template (add 'template' to its line)",
                            lv->bodies[sp.template_body].name);
    static const char *const opts[] = {"action", "every", "start", "limit", "attach", "offset", "jitter"};
    static const int nargs[] = {0, 1, 1, 1, 1, 2, 1};
    int seen[7] = {0};
    int i = 3;
    while (i < t->nf) {
        int o = -1;
        for (int k = 0; k < 7; k++)
            if (nt__field_is(&t->f[i], opts[k])) o = k;
        if (o < 0)
            return nt__fail_col(t, t->f[i].col,
                                "unknown spawner option '%s' (expected action, every, start, limit, attach, offset or jitter)",
                                nt__quote(q, t->f[i].s, t->f[i].n));
        if (seen[o]) return nt__fail_col(t, t->f[i].col, "duplicate spawner option '%s'", opts[o]);
        seen[o] = t->f[i].col;
        if (nargs[o] > 0 && i + nargs[o] >= t->nf)
            return nt__fail_col(t, nt__text_eol_col(t), "option '%s' needs %d value%s", opts[o], nargs[o], nargs[o] > 1 ? "s" : "");
        int a = i + 1;
        long long v;
        switch (o) {
        case 0:
            if (seen[1]) return nt__fail_col(t, t->f[i].col, "a spawner has one trigger: 'action' or 'every N'");
            sp.trigger = NT_SPAWN_ACTION;
            break;
        case 1:
            if (seen[0]) return nt__fail_col(t, t->f[i].col, "a spawner has one trigger: 'action' or 'every N'");
            sp.trigger = NT_SPAWN_EVERY;
            if ((s = nt__field_int(t, &t->f[a], "every", 1, 100000000, &v)) != NT_OK) return s;
            sp.every = (int)v;
            break;
        case 2:
            if ((s = nt__field_int(t, &t->f[a], "start", 1, 100000000, &v)) != NT_OK) return s;
            sp.start = (int)v;
            break;
        case 3:
            if ((s = nt__field_int(t, &t->f[a], "limit", 1, NT_LEVEL_MAX_BODIES, &v)) != NT_OK) return s;
            sp.limit = (int)v;
            break;
        case 4:
            if ((sp.attach = ref_body(P, a, "attached body")) < 0) return NT_ERR_PARSE;
            if (lv->bodies[sp.attach].is_template)
                return nt__fail_col(t, t->f[a].col, "cannot attach a spawner to a template");
            break;
        case 5:
            if ((s = vec_at(P, a, "offset x", "offset y", &sp.offset)) != NT_OK) return s;
            break;
        case 6:
            if ((s = nonneg_at(P, a, "jitter", &sp.jitter)) != NT_OK) return s;
            break;
        }
        i = a + nargs[o];
    }
    if (!seen[0] && !seen[1]) return nt__fail_col(t, nt__text_eol_col(t), "a spawner needs a trigger: 'action' or 'every N'");
    if (!seen[3]) return nt__fail_col(t, nt__text_eol_col(t), "a spawner needs 'limit K'");
    if (seen[2] && !seen[1]) return nt__fail_col(t, seen[2], "'start' needs 'every N'");
    if (sp.trigger == NT_SPAWN_EVERY && !seen[2]) sp.start = 1;
    return append((void **)&lv->spawners, &lv->spawner_count, &sp, sizeof sp);
}

static int setting_key(const nt__field *f)
{
    for (int k = 0; k < K_COUNT; k++)
        if (k != K_PLAYER && nt__field_is(f, setting_names[k])) return k;
    return -1;
}

static nt_status parse_lines(parser *P)
{
    nt__text *t = &P->t;
    char q[NT__QUOTE_MAX];
    nt_status s = nt__read_header(t, LEVEL_MAGIC, NT_LEVEL_VERSION);
    if (s != NT_OK) return s;
    for (;;) {
        int r = nt__text_next_fields(t);
        if (r < 0) return NT_ERR_PARSE;
        if (r == 0) break;
        const nt__field *w = &t->f[0];
        int key = setting_key(w);
        if (key >= 0 || nt__field_is(w, "material")) {
            if (P->section != SEC_SETTINGS)
                return nt__fail_col(t, w->col, "'%s' must come before the 'tiles' block", nt__quote(q, w->s, w->n));
            s = key >= 0 ? parse_setting(P, key) : parse_material(P);
        } else if (nt__field_is(w, "tiles") || nt__field_is(w, "materials") || nt__field_is(w, "flags")) {
            int grid = nt__field_is(w, "tiles") ? GRID_TILES : nt__field_is(w, "materials") ? GRID_MATERIALS : GRID_FLAGS;
            if (P->grid_line[grid])
                return nt__fail_col(t, w->col, "duplicate '%s' block (first at line %d)", grid_names[grid], P->grid_line[grid]);
            if (grid != GRID_TILES && !P->grid_line[GRID_TILES])
                return nt__fail_col(t, w->col, "the '%s' block must come after the 'tiles' block", grid_names[grid]);
            if (P->section == SEC_OBJECTS)
                return nt__fail_col(t, w->col, "the '%s' block must come before the objects", grid_names[grid]);
            if (t->nf > 1) return nt__fail_col(t, t->f[1].col, "unexpected field after '%s' (rows go on the next lines)", grid_names[grid]);
            if (grid == GRID_TILES && (s = end_settings(P)) != NT_OK) return s;
            P->grid_line[grid] = t->line;
            P->section = SEC_GRIDS;
            s = parse_grid(P, grid);
        } else if (nt__field_is(w, "player") || nt__field_is(w, "region") || nt__field_is(w, "path") ||
                   nt__field_is(w, "body") || nt__field_is(w, "spawner")) {
            if (!P->grid_line[GRID_TILES])
                return nt__fail_col(t, w->col, "'%s' must come after the 'tiles' block", nt__quote(q, w->s, w->n));
            P->section = SEC_OBJECTS;
            if (nt__field_is(w, "player")) s = parse_player(P);
            else if (nt__field_is(w, "region")) s = parse_region(P);
            else if (nt__field_is(w, "path")) s = parse_path(P);
            else if (nt__field_is(w, "body")) s = parse_body(P);
            else s = parse_spawner(P);
        } else if (w->n > 0 && w->s[0] == '|') {
            return nt__fail_col(t, w->col, "a grid row outside a block (more rows than the map height?)");
        } else {
            return nt__fail_col(t, w->col, "unknown keyword '%s'", nt__quote(q, w->s, w->n));
        }
        if (s != NT_OK) return s;
    }
    if (!P->grid_line[GRID_TILES]) {
        int line, col;
        nt__text_eof_pos(t, &line, &col);
        return nt__fail(t, line, col, "unexpected end of file: no 'tiles' block");
    }
    return NT_OK;
}

nt_status nt_level_parse(const char *name, const char *text, size_t length, nt_level **out, nt_text_error *err)
{
    if (out) *out = NULL;
    if (!out || (!text && length > 0)) return nt__error_plain(err, NT_ERR_INVALID_ARGUMENT, "nt_level_parse: NULL argument");
    parser *P = (parser *)nt__alloc(sizeof *P);
    if (!P) return nt__error_plain(err, NT_ERR_OUT_OF_MEMORY, "%s: out of memory", name ? name : "(text)");
    memset(P, 0, sizeof *P);
    nt__text_init(&P->t, name, text, length, err);
    nt_level *lv = (nt_level *)nt__alloc(sizeof *lv);
    nt_status s = NT_ERR_OUT_OF_MEMORY;
    if (lv) {
        memset(lv, 0, sizeof *lv);
        nt_world_def wd = nt_default_world_def();
        lv->cell_size = 24;
        lv->gravity = wd.gravity;
        lv->friction_model = wd.friction_model;
        lv->enable_sleep = wd.enable_sleep;
        lv->seed = 1;
        for (int i = 0; i < NT_MAX_MATERIALS; i++) lv->materials[i] = wd.tile_material;
        lv->body_material = n_material();
        P->lv = lv;
        s = parse_lines(P);
    }
    if (s == NT_ERR_OUT_OF_MEMORY) nt__error_plain(err, s, "%s: out of memory", P->t.name);
    nt__free(P->names);
    nt__free(P);
    if (s != NT_OK) {
        nt_level_destroy(lv);
        return s;
    }
    *out = lv;
    return NT_OK;
}

/* ---------------------------------------------------------------- the writer */

static int same_material(nt_material a, nt_material b) { return memcmp(&a, &b, sizeof a) == 0; }
static int same_real(nt_real a, nt_real b) { return memcmp(&a, &b, sizeof a) == 0; }

static void put_vec(nt__sink *o, nt_vec2 v)
{
    nt__sink_real(o, v.x);
    nt__sink_puts(o, " ");
    nt__sink_real(o, v.y);
}

static void put_grid(nt__sink *o, const nt_level *lv, const uint8_t *cells, int grid)
{
    char *row = (char *)nt__alloc((size_t)lv->width + 3);
    for (int y = 0; y < lv->height; y++) {
        const uint8_t *c = cells + (size_t)y * (size_t)lv->width;
        if (row) {
            row[0] = '|';
            for (int x = 0; x < lv->width; x++)
                row[x + 1] = grid == GRID_TILES ? nt_level_tile_char(c[x]) : grid == GRID_MATERIALS ? material_char(c[x])
                                                                                                   : (c[x] ? '-' : '.');
            row[lv->width + 1] = '|';
            row[lv->width + 2] = '\n';
            nt__sink_put(o, row, (size_t)lv->width + 3);
        } else {
            /* Out of memory for the row buffer: byte by byte, same text. */
            nt__sink_puts(o, "|");
            for (int x = 0; x < lv->width; x++) {
                char ch = grid == GRID_TILES ? nt_level_tile_char(c[x]) : grid == GRID_MATERIALS ? material_char(c[x])
                                                                                                : (c[x] ? '-' : '.');
                nt__sink_put(o, &ch, 1);
            }
            nt__sink_puts(o, "|\n");
        }
    }
    nt__free(row);
}

static int any_nonzero(const uint8_t *a, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (a[i]) return 1;
    return 0;
}

static void put_body(nt__sink *o, const nt_level *lv, const nt_level_body *b)
{
    static const char *const types[3] = {"static", "kinematic", "dynamic"};
    nt__sink_printf(o, "body %s %s ", b->name, types[b->type]);
    if (b->shape.type == NT_SHAPE_CIRCLE) {
        nt__sink_puts(o, "circle ");
        nt__sink_real(o, b->shape.half.x);
    } else {
        nt__sink_puts(o, "box ");
        put_vec(o, b->shape.half);
    }
    nt__sink_puts(o, " at ");
    put_vec(o, b->position);
    nt_level_body d = nt_level_default_body(lv);
    if (!same_real(b->velocity.x, d.velocity.x) || !same_real(b->velocity.y, d.velocity.y)) {
        nt__sink_puts(o, " vel ");
        put_vec(o, b->velocity);
    }
    if (!same_real(b->mass, d.mass)) {
        nt__sink_puts(o, " mass ");
        nt__sink_real(o, b->mass);
    }
    if (!same_material(b->material, d.material)) {
        nt__sink_puts(o, " material ");
        nt__sink_real(o, b->material.friction);
        nt__sink_puts(o, " ");
        nt__sink_real(o, b->material.bounce);
    }
    if (!same_real(b->linear_drag, d.linear_drag)) {
        nt__sink_puts(o, " drag ");
        nt__sink_real(o, b->linear_drag);
    }
    if (!same_real(b->gravity_scale, d.gravity_scale)) {
        nt__sink_puts(o, " gravity-scale ");
        nt__sink_real(o, b->gravity_scale);
    }
    if (b->category != d.category) nt__sink_printf(o, " category 0x%x", (unsigned)b->category);
    if (b->mask != d.mask) nt__sink_printf(o, " mask 0x%x", (unsigned)b->mask);
    if (b->is_sensor) nt__sink_puts(o, " sensor");
    if (!b->enable_sleep) nt__sink_puts(o, " no-sleep");
    if (!b->is_awake) nt__sink_puts(o, " asleep");
    if (b->path >= 0) {
        nt__sink_printf(o, " path %s", lv->paths[b->path].name);
        if (!same_real(b->phase, 0)) {
            nt__sink_puts(o, " phase ");
            nt__sink_real(o, b->phase);
        }
    }
    if (b->score > 0) nt__sink_printf(o, " score %d", b->score);
    if (b->deadly) nt__sink_puts(o, " deadly");
    if (b->is_template) nt__sink_puts(o, " template");
    if (b->repeat_x > 1 || b->repeat_y > 1) {
        nt__sink_printf(o, " repeat %d %d ", b->repeat_x, b->repeat_y);
        put_vec(o, b->repeat_step);
    }
    if (b->door == NT_DOOR_PLAIN) nt__sink_puts(o, " door");
    else if (b->door == NT_DOOR_LOCKED) nt__sink_printf(o, " opened-by %s", lv->regions[b->door_switch - 1].name);
    else if (b->door == NT_DOOR_TRAP) nt__sink_printf(o, " closed-by %s", lv->regions[b->door_switch - 1].name);
    static const char *const sides[5] = {"", "right", "down", "left", "up"};
    if (b->one_way > NT_ONE_WAY_NONE && b->one_way <= NT_ONE_WAY_UP) nt__sink_printf(o, " one-way %s", sides[b->one_way]);
    nt__sink_puts(o, "\n");
}

size_t nt_level_write(const nt_level *lv, char *buf, size_t cap)
{
    nt__sink o;
    nt__sink_init(&o, buf, cap);
    if (!lv) return nt__sink_finish(&o);
    nt__sink_header(&o, LEVEL_MAGIC, NT_LEVEL_VERSION);
    if (lv->title[0]) nt__sink_printf(&o, "title \"%s\"\n", lv->title);
    if (lv->author[0]) nt__sink_printf(&o, "author \"%s\"\n", lv->author);
    nt__sink_printf(&o, "size %d %d\ncell ", lv->width, lv->height);
    nt__sink_real(&o, lv->cell_size);
    nt__sink_puts(&o, "\ngravity ");
    put_vec(&o, lv->gravity);
    nt__sink_printf(&o, "\nfriction-model %s\nsleep %s\nseed %llu\n", lv->friction_model == NT_FRICTION_N ? "n" : "coulomb",
                    lv->enable_sleep ? "on" : "off", (unsigned long long)lv->seed);
    for (int i = 0; i < NT_MAX_MATERIALS; i++) {
        if (i > 0 && same_material(lv->materials[i], lv->materials[0])) continue;
        nt__sink_printf(&o, "material %d ", i);
        nt__sink_real(&o, lv->materials[i].friction);
        nt__sink_puts(&o, " ");
        nt__sink_real(&o, lv->materials[i].bounce);
        nt__sink_puts(&o, "\n");
    }
    nt__sink_puts(&o, "body-material ");
    nt__sink_real(&o, lv->body_material.friction);
    nt__sink_puts(&o, " ");
    nt__sink_real(&o, lv->body_material.bounce);
    nt__sink_puts(&o, "\nbody-drag ");
    nt__sink_real(&o, lv->body_linear_drag);
    nt__sink_puts(&o, "\n\n# tile codes: '.' EMPTY, '#' FULL, other tiles N's code '0' + id (README: The tile set)\ntiles\n");
    size_t n = (size_t)lv->width * (size_t)lv->height;
    put_grid(&o, lv, lv->tiles, GRID_TILES);
    if (any_nonzero(lv->cell_materials, n)) {
        nt__sink_puts(&o, "materials\n");
        put_grid(&o, lv, lv->cell_materials, GRID_MATERIALS);
    }
    if (any_nonzero(lv->cell_flags, n)) {
        nt__sink_puts(&o, "flags\n");
        put_grid(&o, lv, lv->cell_flags, GRID_FLAGS);
    }
    if (lv->has_player || lv->path_count || lv->region_count || lv->body_count || lv->spawner_count) nt__sink_puts(&o, "\n");
    if (lv->has_player) {
        nt__sink_puts(&o, "player ");
        put_vec(&o, lv->player);
        nt__sink_puts(&o, "\n");
    }
    static const char *const modes[3] = {"loop", "pingpong", "orbit"};
    for (int i = 0; i < lv->path_count; i++) {
        const nt_level_path *p = &lv->paths[i];
        nt__sink_printf(&o, "path %s %s speed ", p->name, modes[p->mode]);
        nt__sink_real(&o, p->speed);
        if (p->mode == NT_PATH_ORBIT) {
            nt__sink_puts(&o, " center ");
            put_vec(&o, p->center);
            nt__sink_puts(&o, " radius ");
            nt__sink_real(&o, p->radius);
        } else {
            if (!same_real(p->wait, 0)) {
                nt__sink_puts(&o, " wait ");
                nt__sink_real(&o, p->wait);
            }
            nt__sink_puts(&o, " points");
            for (int k = 0; k < p->point_count; k++) {
                nt__sink_puts(&o, " ");
                put_vec(&o, p->points[k]);
            }
        }
        nt__sink_puts(&o, "\n");
    }
    static const char *const kinds[5] = {"zone", "exit", "score", "kill", "switch"};
    for (int i = 0; i < lv->region_count; i++) {
        const nt_level_region *r = &lv->regions[i];
        nt__sink_printf(&o, "region %s %s ", r->name, kinds[r->kind]);
        put_vec(&o, r->lo);
        nt__sink_puts(&o, " ");
        put_vec(&o, r->hi);
        if (r->kind == NT_REGION_SCORE) nt__sink_printf(&o, " value %d", r->value);
        if (r->needs) nt__sink_printf(&o, " needs %s", lv->regions[r->needs - 1].name);
        nt__sink_puts(&o, "\n");
    }
    for (int i = 0; i < lv->body_count; i++) put_body(&o, lv, &lv->bodies[i]);
    for (int i = 0; i < lv->spawner_count; i++) {
        const nt_level_spawner *s = &lv->spawners[i];
        nt__sink_printf(&o, "spawner %s %s", s->name, lv->bodies[s->template_body].name);
        if (s->trigger == NT_SPAWN_ACTION) nt__sink_puts(&o, " action");
        else nt__sink_printf(&o, " every %d start %d", s->every, s->start);
        nt__sink_printf(&o, " limit %d", s->limit);
        if (s->attach >= 0) nt__sink_printf(&o, " attach %s", lv->bodies[s->attach].name);
        if (!same_real(s->offset.x, 0) || !same_real(s->offset.y, 0)) {
            nt__sink_puts(&o, " offset ");
            put_vec(&o, s->offset);
        }
        if (!same_real(s->jitter, 0)) {
            nt__sink_puts(&o, " jitter ");
            nt__sink_real(&o, s->jitter);
        }
        nt__sink_puts(&o, "\n");
    }
    return nt__sink_finish(&o);
}

/* ---------------------------------------------------------------- level -> world */

nt_body_def nt_level_body_def(const nt_level_body *b, int k)
{
    nt_body_def d = nt_default_body_def();
    if (!b) return d;
    int rx = b->repeat_x > 0 ? b->repeat_x : 1;
    d.type = b->type;
    d.shape = b->shape;
    d.position = nt_v2(b->position.x + (nt_real)(k % rx) * b->repeat_step.x,
                       b->position.y + (nt_real)(k / rx) * b->repeat_step.y);
    d.velocity = b->velocity;
    d.mass = b->mass;
    d.gravity_scale = b->gravity_scale;
    d.linear_drag = b->linear_drag;
    d.material = b->material;
    d.category = b->category;
    d.mask = b->mask;
    d.is_sensor = b->is_sensor;
    d.enable_sleep = b->enable_sleep;
    d.is_awake = b->is_awake;
    return d;
}

nt_status nt_level_create_world(const nt_level *lv, nt_world **out, nt_body_id *ids, size_t id_count)
{
    if (out) *out = NULL;
    if (!lv || !out) return NT_ERR_INVALID_ARGUMENT;
    if (ids && id_count < (size_t)nt_level_instance_count(lv)) return NT_ERR_INVALID_ARGUMENT;
    nt_world_def wd = nt_default_world_def();
    wd.map.width = lv->width;
    wd.map.height = lv->height;
    wd.map.cell_size = lv->cell_size;
    wd.gravity = lv->gravity;
    wd.friction_model = lv->friction_model;
    wd.tile_material = lv->materials[0];
    wd.enable_sleep = lv->enable_sleep;
    /* Speeds in the defaults are for cells of 24 units: scale them with the cell. */
    nt_real scale = lv->cell_size / 24;
    wd.restitution_threshold *= scale;
    wd.hit_event_threshold *= scale;
    wd.sleep_speed *= scale;
    int count = nt_level_instance_count(lv);
    wd.body_capacity = count > 16 ? count : 16;
    nt_world *w = NULL;
    nt_status s = nt_world_create(&wd, &w);
    if (s != NT_OK) return s;
    size_t n = (size_t)lv->width * (size_t)lv->height;
    s = nt_world_set_tiles(w, lv->tiles, n);
    for (int i = 1; s == NT_OK && i < NT_MAX_MATERIALS; i++) s = nt_world_set_material(w, i, lv->materials[i]);
    for (size_t k = 0; s == NT_OK && k < n; k++) {
        int x = (int)(k % (size_t)lv->width), y = (int)(k / (size_t)lv->width);
        if (lv->cell_materials[k]) s = nt_world_set_cell_material(w, x, y, lv->cell_materials[k]);
        if (s == NT_OK && lv->cell_flags[k]) s = nt_world_set_cell_flags(w, x, y, lv->cell_flags[k]);
    }
    size_t next = 0;
    for (int i = 0; s == NT_OK && i < lv->body_count; i++) {
        const nt_level_body *b = &lv->bodies[i];
        if (b->is_template) continue;
        int m = b->repeat_x * b->repeat_y;
        for (int k = 0; s == NT_OK && k < m; k++) {
            nt_body_def d = nt_level_body_def(b, k);
            nt_body_id id;
            s = nt_body_create(w, &d, &id);
            if (s == NT_OK && ids) ids[next] = id;
            next++;
        }
    }
    if (s != NT_OK) {
        nt_world_destroy(w);
        return s;
    }
    *out = w;
    return NT_OK;
}
