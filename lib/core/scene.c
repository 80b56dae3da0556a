/* Building a scene: spacing, fluids, particles and parameters. */
#include "core/core.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


#define CHECK_SCENE(scene)                                                      \
    do {                                                                        \
        if (!(scene))                                                           \
            return fail(NULL, MPS2P_ERR_NULL, "%s: scene is NULL", __func__);   \
    } while (0)

int mps2p_scene_create(double l0, mps2p_scene **scene)
{
    error_clear();
    if (!scene)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_scene_create: scene output pointer is NULL");
    *scene = NULL;
    if (!isfinite(l0) || l0 <= 0.0)
        return fail(NULL, MPS2P_ERR_INVALID, "spacing l0 must be > 0 and finite, got %g", l0);
    mps2p_scene *s = calloc(1, sizeof *s);
    if (!s)
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory creating a scene");
    s->l0 = l0;
    params_set_defaults(&s->params);
    *scene = s;
    return MPS2P_OK;
}

void mps2p_scene_destroy(mps2p_scene *scene)
{
    if (!scene)
        return;
    for (int f = 0; f < scene->fluid_count; f++)
        free(scene->fluids[f]);
    free(scene->fluids);
    free(scene->position);
    free(scene->velocity);
    free(scene->kind);
    free(scene->fluid_id);
    free(scene->body_id);
    free(scene->body_names);
    free(scene->boxes);
    free(scene);
}

const char *mps2p_scene_last_error(const mps2p_scene *scene)
{
    return scene ? scene->error : "scene is NULL";
}

int mps2p_scene_add_fluid(mps2p_scene *scene, const char *name, double density,
                          double kinematic_viscosity, int *fluid_id)
{
    error_clear();
    CHECK_SCENE(scene);
    if (!name)
        return fail(scene->error, MPS2P_ERR_NULL, "fluid name is NULL");
    if (name[0] == '\0' || strlen(name) >= FLUID_NAME_SIZE)
        return fail(scene->error, MPS2P_ERR_INVALID,
                    "fluid name must have 1 to %d characters", FLUID_NAME_SIZE - 1);
    if (!isfinite(density) || density <= 0.0)
        return fail(scene->error, MPS2P_ERR_INVALID,
                    "density of fluid \"%s\" must be > 0 and finite, got %g", name, density);
    if (!isfinite(kinematic_viscosity) || kinematic_viscosity < 0.0)
        return fail(scene->error, MPS2P_ERR_INVALID,
                    "kinematic viscosity of fluid \"%s\" must be >= 0 and finite, got %g",
                    name, kinematic_viscosity);
    for (int i = 0; i < scene->fluid_count; i++)
        if (strcmp(scene->fluids[i]->name, name) == 0)
            return fail(scene->error, MPS2P_ERR_INVALID, "fluid \"%s\" already exists", name);
    if (scene->fluid_count == scene->fluid_capacity) {
        int capacity = scene->fluid_capacity ? 2 * scene->fluid_capacity : 4;
        fluid **grown = realloc(scene->fluids, (size_t)capacity * sizeof *grown);
        if (!grown)
            return fail(scene->error, MPS2P_ERR_NOMEM, "out of memory adding a fluid");
        scene->fluids = grown;
        scene->fluid_capacity = capacity;
    }
    fluid *f = calloc(1, sizeof *f);
    if (!f)
        return fail(scene->error, MPS2P_ERR_NOMEM, "out of memory adding a fluid");
    scene->fluids[scene->fluid_count] = f;
    strcpy(f->name, name);
    f->density = density;
    f->viscosity = kinematic_viscosity;
    if (fluid_id)
        *fluid_id = scene->fluid_count;
    scene->fluid_count++;
    return MPS2P_OK;
}

int mps2p_scene_fluid_count(const mps2p_scene *scene, int *count)
{
    error_clear();
    CHECK_SCENE(scene);
    if (!count)
        return fail(NULL, MPS2P_ERR_NULL, "count output pointer is NULL");
    *count = scene->fluid_count;
    return MPS2P_OK;
}

int mps2p_scene_get_fluid(const mps2p_scene *scene, int fluid_id, const char **name,
                          double *density, double *kinematic_viscosity)
{
    error_clear();
    CHECK_SCENE(scene);
    if (fluid_id < 0 || fluid_id >= scene->fluid_count)
        return fail(NULL, MPS2P_ERR_INVALID, "no fluid with id %d (the scene has %d)",
                    fluid_id, scene->fluid_count);
    const fluid *f = scene->fluids[fluid_id];
    if (name)
        *name = f->name;
    if (density)
        *density = f->density;
    if (kinematic_viscosity)
        *kinematic_viscosity = f->viscosity;
    return MPS2P_OK;
}

int coordinates_check(double l0, double x, double y, const char *what, char *handle_error)
{
    const double limit = COORDINATE_LIMIT_L0 * l0;
    if (fabs(x) <= limit && fabs(y) <= limit)
        return MPS2P_OK;
    return fail(handle_error, MPS2P_ERR_INVALID,
                "%s at (%g, %g) is beyond %g l0 = %g m of the origin: a double there "
                "resolves less than 2.2e-7 l0 (lattice sites would merge); move the "
                "origin near the scene", what, x, y, COORDINATE_LIMIT_L0, limit);
}

int scene_check_room(mps2p_scene *scene, size_t extra)
{
    if (extra > MAX_PARTICLES || scene->count > MAX_PARTICLES - extra)
        return fail(scene->error, MPS2P_ERR_INVALID,
                    "a scene holds at most %zu particles; adding %zu to %zu is too many",
                    MAX_PARTICLES, extra, scene->count);
    size_t needed = scene->count + extra;
    if (needed <= scene->capacity)
        return MPS2P_OK;
    char what[64];
    snprintf(what, sizeof what, "a scene of %zu particles", needed);
    return memory_check(&scene->params, (double)needed * (double)scene_bytes_per_particle(),
                        what, scene->error);
}

/* Makes room for extra particles; all arrays grow together. */
static int reserve(mps2p_scene *scene, size_t extra)
{
    int status = scene_check_room(scene, extra);
    if (status != MPS2P_OK)
        return status;
    size_t needed = scene->count + extra;
    if (needed <= scene->capacity)
        return MPS2P_OK;
    const double per_particle = (double)scene_bytes_per_particle();
    size_t capacity = scene->capacity ? scene->capacity : 256;
    while (capacity < needed)
        capacity *= 2;
    /* doubling past the limit: exactly what is needed instead */
    if ((double)capacity * per_particle > memory_limit_bytes(&scene->params))
        capacity = needed;
    double *position = realloc(scene->position, 2 * capacity * sizeof *position);
    if (position)
        scene->position = position;
    double *velocity = realloc(scene->velocity, 2 * capacity * sizeof *velocity);
    if (velocity)
        scene->velocity = velocity;
    int *kind = realloc(scene->kind, capacity * sizeof *kind);
    if (kind)
        scene->kind = kind;
    int *fluid_id = realloc(scene->fluid_id, capacity * sizeof *fluid_id);
    if (fluid_id)
        scene->fluid_id = fluid_id;
    int *body_id = realloc(scene->body_id, capacity * sizeof *body_id);
    if (body_id)
        scene->body_id = body_id;
    if (!position || !velocity || !kind || !fluid_id || !body_id)
        return fail(scene->error, MPS2P_ERR_NOMEM,
                    "out of memory growing the scene to %zu particles", needed);
    scene->capacity = capacity;
    return MPS2P_OK;
}

static void append(mps2p_scene *scene, double x, double y, double u, double v,
                   int kind, int fluid_id)
{
    size_t i = scene->count++;
    scene->position[2 * i] = x;
    scene->position[2 * i + 1] = y;
    scene->velocity[2 * i] = u;
    scene->velocity[2 * i + 1] = v;
    scene->kind[i] = kind;
    scene->fluid_id[i] = fluid_id;
    scene->body_id[i] = kind == MPS2P_KIND_FLUID ? -1 : 0; /* solids join "walls" */
}

/* A box's lattice: nx x ny cells of l0 (each count at most MAX_PARTICLES;
 * their product is add_box's to check: a tank's inside holds none). */
static int box_cells(mps2p_scene *scene, double x0, double y0, double x1, double y1,
                     size_t *nx, size_t *ny)
{
    if (!isfinite(x0) || !isfinite(y0) || !isfinite(x1) || !isfinite(y1))
        return fail(scene->error, MPS2P_ERR_INVALID,
                    "box corners must be finite, got (%g, %g) to (%g, %g)", x0, y0, x1, y1);
    if (x1 <= x0 || y1 <= y0)
        return fail(scene->error, MPS2P_ERR_INVALID,
                    "box must have x1 > x0 and y1 > y0, got (%g, %g) to (%g, %g)",
                    x0, y0, x1, y1);
    int status = coordinates_check(scene->l0, x0, y0, "box corner", scene->error);
    if (status == MPS2P_OK)
        status = coordinates_check(scene->l0, x1, y1, "box corner", scene->error);
    if (status != MPS2P_OK)
        return status;
    /* A small tolerance so that 0.3 / 0.01 counts as 30 cells, not 29. */
    double cx = floor((x1 - x0) / scene->l0 + 1e-6);
    double cy = floor((y1 - y0) / scene->l0 + 1e-6);
    if (cx < 1.0 || cy < 1.0)
        return fail(scene->error, MPS2P_ERR_INVALID,
                    "box (%g, %g) to (%g, %g) is narrower than the spacing l0 = %g",
                    x0, y0, x1, y1, scene->l0);
    if (cx > (double)MAX_PARTICLES || cy > (double)MAX_PARTICLES)
        return fail(scene->error, MPS2P_ERR_INVALID,
                    "box (%g, %g) to (%g, %g) is %.3g x %.3g spacings, more than a scene can "
                    "hold in a row (%zu)", x0, y0, x1, y1, cx, cy, MAX_PARTICLES);
    *nx = (size_t)cx;
    *ny = (size_t)cy;
    return MPS2P_OK;
}

static int check_box(mps2p_scene *scene, double x0, double y0, double x1, double y1,
                     size_t *nx, size_t *ny)
{
    int status = box_cells(scene, x0, y0, x1, y1, nx, ny);
    if (status == MPS2P_OK && (double)*nx * (double)*ny > (double)MAX_PARTICLES)
        return fail(scene->error, MPS2P_ERR_INVALID,
                    "box would hold %.3g particles, more than a scene can hold (%zu)",
                    (double)*nx * (double)*ny, MAX_PARTICLES);
    return status;
}

/* A box over another puts particles inside each other: on the same lattice
 * two in one place (refused at the solver's creation, naming two particle
 * numbers), half a spacing off a pair the first pressure solve answers with
 * a spike (the run diverged at its first step, "pressure beyond the limit",
 * saying nothing of the cause). Boxes may touch; a tank's walls lie outside
 * its box. Particles added as arrays are not boxes and are not checked here
 * (the solver refuses two in one place). */
static int check_overlap(mps2p_scene *scene, int fluid, double x0, double y0, double x1,
                         double y1)
{
    const double touch = 1e-6 * scene->l0;
    for (size_t k = 0; k < scene->box_count; k++) {
        const struct placed_box *b = &scene->boxes[k];
        double w = fmin(x1, b->x1) - fmax(x0, b->x0), h = fmin(y1, b->y1) - fmax(y0, b->y0);
        if (w > touch && h > touch)
            return fail(scene->error, MPS2P_ERR_INVALID,
                        "%s box [%g, %g, %g, %g] overlaps particles %zu to %zu, a %s box "
                        "[%g, %g, %g, %g] added before: boxes may touch, not overlap (their "
                        "particles would lie inside each other)",
                        fluid ? "the fluid" : "the solid", x0, y0, x1, y1, b->first,
                        b->first + b->count - 1, b->fluid ? "fluid" : "solid", b->x0, b->y0,
                        b->x1, b->y1);
    }
    return MPS2P_OK;
}

static int add_box(mps2p_scene *scene, int kind, int fluid_id,
                   double x0, double y0, double x1, double y1)
{
    size_t nx = 0, ny = 0;
    int status = check_box(scene, x0, y0, x1, y1, &nx, &ny);
    if (status != MPS2P_OK)
        return status;
    const int fluid = kind == MPS2P_KIND_FLUID;
    /* as filled: whole cells from the lower-left corner */
    x1 = x0 + (double)nx * scene->l0;
    y1 = y0 + (double)ny * scene->l0;
    status = check_overlap(scene, fluid, x0, y0, x1, y1);
    if (status != MPS2P_OK)
        return status;
    if (scene->box_count == scene->box_capacity) {
        size_t capacity = scene->box_capacity ? 2 * scene->box_capacity : 8;
        struct placed_box *grown = realloc(scene->boxes, capacity * sizeof *grown);
        if (!grown)
            return fail(scene->error, MPS2P_ERR_NOMEM, "out of memory for the scene's boxes");
        scene->boxes = grown;
        scene->box_capacity = capacity;
    }
    status = reserve(scene, nx * ny);
    if (status != MPS2P_OK)
        return status;
    scene->boxes[scene->box_count++] =
        (struct placed_box){x0, y0, x1, y1, fluid, scene->count, nx * ny};
    for (size_t j = 0; j < ny; j++)
        for (size_t i = 0; i < nx; i++)
            append(scene, x0 + (i + 0.5) * scene->l0, y0 + (j + 0.5) * scene->l0,
                   0.0, 0.0, kind, fluid_id);
    return MPS2P_OK;
}

int mps2p_scene_add_fluid_box(mps2p_scene *scene, int fluid_id,
                              double x0, double y0, double x1, double y1)
{
    error_clear();
    CHECK_SCENE(scene);
    if (fluid_id < 0 || fluid_id >= scene->fluid_count)
        return fail(scene->error, MPS2P_ERR_INVALID,
                    "no fluid with id %d (the scene has %d; add fluids first)",
                    fluid_id, scene->fluid_count);
    return add_box(scene, MPS2P_KIND_FLUID, fluid_id, x0, y0, x1, y1);
}

int mps2p_scene_add_wall_box(mps2p_scene *scene, double x0, double y0, double x1, double y1)
{
    error_clear();
    CHECK_SCENE(scene);
    return add_box(scene, SOLID_FROM_BOX, -1, x0, y0, x1, y1);
}

int mps2p_scene_add_tank(mps2p_scene *scene, double x0, double y0, double x1, double y1,
                         int open_top)
{
    error_clear();
    CHECK_SCENE(scene);
    size_t nx = 0, ny = 0;
    /* only the walls count against the particle cap: the inside stays empty */
    int status = box_cells(scene, x0, y0, x1, y1, &nx, &ny);
    if (status != MPS2P_OK)
        return status;
    const int layers = (int)ceil(params_max_radius(&scene->params) - 1e-9);
    double t = layers * scene->l0;
    /* Snap the inner box to whole cells so that walls and fluid share a lattice. */
    x1 = x0 + nx * scene->l0;
    y1 = y0 + ny * scene->l0;
    double top = open_top ? y1 : y1 + t;
    size_t before = scene->count, boxes_before = scene->box_count;
    status = add_box(scene, MPS2P_KIND_DUMMY, -1, x0 - t, y0 - t, x0, top);
    if (status == MPS2P_OK)
        status = add_box(scene, MPS2P_KIND_DUMMY, -1, x1, y0 - t, x1 + t, top);
    if (status == MPS2P_OK)
        status = add_box(scene, MPS2P_KIND_DUMMY, -1, x0, y0 - t, x1, y0);
    if (status == MPS2P_OK && !open_top)
        status = add_box(scene, MPS2P_KIND_DUMMY, -1, x0, y1, x1, y1 + t);
    if (status != MPS2P_OK) {
        scene->count = before; /* all or nothing */
        scene->box_count = boxes_before;
        return status;
    }
    /* The tank knows its inside: only the layer facing it carries pressure.
     * (Its outer faces must not: as free-surface walls they would pin p = 0
     * within the Laplacian radius of the inner wall layer.) */
    const double margin = 1.5 * scene->l0;
    for (size_t i = before; i < scene->count; i++) {
        double x = scene->position[2 * i], y = scene->position[2 * i + 1];
        int inner = x > x0 - margin && x < x1 + margin && y > y0 - margin &&
                    (open_top || y < y1 + margin);
        if (inner)
            scene->kind[i] = MPS2P_KIND_WALL;
    }
    /* the solver checks the radii against the thinnest tank's walls */
    if (scene->tank_layers == 0 || layers < scene->tank_layers)
        scene->tank_layers = layers;
    return MPS2P_OK;
}

int mps2p_scene_add_particles(mps2p_scene *scene, size_t count, const double *positions,
                              const double *velocities, const int *kinds,
                              const int *fluid_ids)
{
    error_clear();
    CHECK_SCENE(scene);
    if (count == 0)
        return MPS2P_OK;
    if (!positions || !kinds)
        return fail(scene->error, MPS2P_ERR_NULL, "positions and kinds must not be NULL");
    /* before reading the arrays: count may be absurd */
    int status = scene_check_room(scene, count);
    if (status != MPS2P_OK)
        return status;
    for (size_t i = 0; i < count; i++) {
        if (!isfinite(positions[2 * i]) || !isfinite(positions[2 * i + 1]))
            return fail(scene->error, MPS2P_ERR_INVALID,
                        "particle %zu: position is not finite (%g, %g)", i,
                        positions[2 * i], positions[2 * i + 1]);
        char what[48];
        snprintf(what, sizeof what, "particle %zu", i);
        if (coordinates_check(scene->l0, positions[2 * i], positions[2 * i + 1], what,
                              scene->error) != MPS2P_OK)
            return MPS2P_ERR_INVALID;
        if (velocities && (!isfinite(velocities[2 * i]) || !isfinite(velocities[2 * i + 1])))
            return fail(scene->error, MPS2P_ERR_INVALID,
                        "particle %zu: velocity is not finite (%g, %g)", i,
                        velocities[2 * i], velocities[2 * i + 1]);
        if (kinds[i] != MPS2P_KIND_FLUID && kinds[i] != MPS2P_KIND_WALL &&
            kinds[i] != MPS2P_KIND_DUMMY)
            return fail(scene->error, MPS2P_ERR_INVALID,
                        "particle %zu: kind %d is not MPS2P_KIND_FLUID, _WALL or _DUMMY%s",
                        i, kinds[i],
                        kinds[i] == MPS2P_KIND_OUT ? " (MPS2P_KIND_OUT is a solver's fluid "
                                                     "particle that left the domain, never a "
                                                     "scene's)" : "");
        if (kinds[i] == MPS2P_KIND_FLUID) {
            if (!fluid_ids)
                return fail(scene->error, MPS2P_ERR_NULL,
                            "particle %zu is fluid but fluid_ids is NULL", i);
            if (fluid_ids[i] < 0 || fluid_ids[i] >= scene->fluid_count)
                return fail(scene->error, MPS2P_ERR_INVALID,
                            "particle %zu: no fluid with id %d (the scene has %d)", i,
                            fluid_ids[i], scene->fluid_count);
        }
    }
    status = reserve(scene, count);
    if (status != MPS2P_OK)
        return status;
    for (size_t i = 0; i < count; i++) {
        int is_fluid = kinds[i] == MPS2P_KIND_FLUID;
        append(scene, positions[2 * i], positions[2 * i + 1],
               is_fluid && velocities ? velocities[2 * i] : 0.0,
               is_fluid && velocities ? velocities[2 * i + 1] : 0.0,
               kinds[i], is_fluid ? fluid_ids[i] : -1);
    }
    return MPS2P_OK;
}

int mps2p_scene_particle_count(const mps2p_scene *scene, size_t *count)
{
    error_clear();
    CHECK_SCENE(scene);
    if (!count)
        return fail(NULL, MPS2P_ERR_NULL, "count output pointer is NULL");
    *count = scene->count;
    return MPS2P_OK;
}

int mps2p_scene_set_param(mps2p_scene *scene, const char *key, double value)
{
    error_clear();
    CHECK_SCENE(scene);
    if (!key)
        return fail(scene->error, MPS2P_ERR_NULL, "parameter key is NULL");
    char message[ERROR_MESSAGE_SIZE];
    int status = params_set(&scene->params, key, value, message, sizeof message);
    if (status != MPS2P_OK)
        return fail(scene->error, status, "%s", message);
    return MPS2P_OK;
}

int mps2p_scene_get_param(const mps2p_scene *scene, const char *key, double *value)
{
    error_clear();
    CHECK_SCENE(scene);
    if (!key || !value)
        return fail(NULL, MPS2P_ERR_NULL, "parameter key or value pointer is NULL");
    if (params_get(&scene->params, key, value) != MPS2P_OK)
        return fail(NULL, MPS2P_ERR_UNKNOWN_KEY, "unknown parameter \"%s\"", key);
    return MPS2P_OK;
}

int mps2p_scene_set_option(mps2p_scene *scene, const char *key, const char *value)
{
    error_clear();
    CHECK_SCENE(scene);
    if (!key || !value)
        return fail(scene->error, MPS2P_ERR_NULL, "option key or value is NULL");
    char message[ERROR_MESSAGE_SIZE];
    int status = params_set_option(&scene->params, key, value, message, sizeof message);
    if (status != MPS2P_OK)
        return fail(scene->error, status, "%s", message);
    return MPS2P_OK;
}

int mps2p_scene_get_option(const mps2p_scene *scene, const char *key, const char **value)
{
    error_clear();
    CHECK_SCENE(scene);
    if (!key || !value)
        return fail(NULL, MPS2P_ERR_NULL, "option key or value pointer is NULL");
    if (params_get_option(&scene->params, key, value) != MPS2P_OK)
        return fail(NULL, MPS2P_ERR_UNKNOWN_KEY, "unknown option \"%s\"", key);
    return MPS2P_OK;
}

int mps2p_scene_set_domain(mps2p_scene *scene, double xmin, double ymin, double xmax,
                           double ymax)
{
    error_clear();
    CHECK_SCENE(scene);
    if (!isfinite(xmin) || !isfinite(ymin) || !isfinite(xmax) || !isfinite(ymax) ||
        xmax <= xmin || ymax <= ymin || !isfinite(xmax - xmin) || !isfinite(ymax - ymin))
        return fail(scene->error, MPS2P_ERR_INVALID,
                    "domain must be finite, of finite width and height, with xmax > xmin and "
                    "ymax > ymin, got "
                    "(%g, %g) to (%g, %g)", xmin, ymin, xmax, ymax);
    scene->has_domain = 1;
    scene->domain[0] = xmin;
    scene->domain[1] = ymin;
    scene->domain[2] = xmax;
    scene->domain[3] = ymax;
    return MPS2P_OK;
}
