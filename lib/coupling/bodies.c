/* Wall bodies: named groups of wall and dummy particles, in the scene and in
 * the solver, and the force and moment the fluid's pressure exerts on them. */
#include "numerics/numerics.h"
#include "core/core.h"
#include "coupling/coupling.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define WALLS_NAME "walls"

/* ---- scene ---- */

static int check_name(mps2p_scene *scene, const char *name)
{
    if (!name)
        return fail(scene->error, MPS2P_ERR_NULL, "body name is NULL");
    if (name[0] == '\0' || strlen(name) >= FLUID_NAME_SIZE)
        return fail(scene->error, MPS2P_ERR_INVALID, "body name must have 1 to %d characters",
                    FLUID_NAME_SIZE - 1);
    return MPS2P_OK;
}

/* The id of the body called name, or the id a new one would get (its name is
 * stored only by commit_body, once its particles are in: all or nothing). */
static int find_body(const mps2p_scene *scene, const char *name)
{
    if (strcmp(name, WALLS_NAME) == 0)
        return 0;
    for (int k = 0; k < scene->body_count; k++)
        if (strcmp(scene->body_names[k], name) == 0)
            return k + 1;
    return scene->body_count + 1;
}

static int reserve_name(mps2p_scene *scene)
{
    if (scene->body_count < scene->body_capacity)
        return MPS2P_OK;
    if (scene->body_count >= 1 << 20)
        return fail(scene->error, MPS2P_ERR_INVALID, "a scene holds at most %d bodies",
                    1 << 20);
    int capacity = scene->body_capacity ? 2 * scene->body_capacity : 4;
    char(*grown)[FLUID_NAME_SIZE] =
        realloc(scene->body_names, (size_t)capacity * sizeof *grown);
    if (!grown)
        return fail(scene->error, MPS2P_ERR_NOMEM, "out of memory adding a body");
    scene->body_names = grown;
    scene->body_capacity = capacity;
    return MPS2P_OK;
}

static void commit_body(mps2p_scene *scene, int id, const char *name, int *body_id)
{
    if (id == scene->body_count + 1) {
        strcpy(scene->body_names[scene->body_count], name);
        scene->body_count++;
    }
    if (body_id)
        *body_id = id;
}

int mps2p_scene_add_body_box(mps2p_scene *scene, const char *name, double x0, double y0,
                             double x1, double y1, int *body_id)
{
    error_clear();
    if (!scene)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_scene_add_body_box: scene is NULL");
    int status = check_name(scene, name);
    if (status == MPS2P_OK)
        status = reserve_name(scene);
    if (status != MPS2P_OK)
        return status;
    int id = find_body(scene, name);
    size_t before = scene->count;
    status = mps2p_scene_add_wall_box(scene, x0, y0, x1, y1);
    if (status != MPS2P_OK)
        return status;
    for (size_t i = before; i < scene->count; i++)
        scene->body_id[i] = id;
    commit_body(scene, id, name, body_id);
    return MPS2P_OK;
}

int mps2p_scene_add_body_particles(mps2p_scene *scene, const char *name, size_t count,
                                   const double *positions, const int *kinds, int *body_id)
{
    error_clear();
    if (!scene)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_scene_add_body_particles: scene is NULL");
    int status = check_name(scene, name);
    if (status == MPS2P_OK)
        status = reserve_name(scene);
    if (status != MPS2P_OK)
        return status;
    if (count > 0 && !kinds)
        return fail(scene->error, MPS2P_ERR_NULL, "kinds must not be NULL");
    status = scene_check_room(scene, count); /* before reading the arrays */
    if (status != MPS2P_OK)
        return status;
    for (size_t i = 0; i < count; i++)
        if (kinds[i] != MPS2P_KIND_WALL && kinds[i] != MPS2P_KIND_DUMMY)
            return fail(scene->error, MPS2P_ERR_INVALID,
                        "particle %zu: a body holds MPS2P_KIND_WALL and _DUMMY particles, "
                        "got kind %d%s", i, kinds[i],
                        kinds[i] == MPS2P_KIND_OUT ? " (MPS2P_KIND_OUT: a solver's fluid that "
                                                     "left the domain, never a scene's)" : "");
    int id = find_body(scene, name);
    size_t before = scene->count;
    status = mps2p_scene_add_particles(scene, count, positions, NULL, kinds, NULL);
    if (status != MPS2P_OK)
        return status;
    for (size_t i = before; i < scene->count; i++)
        scene->body_id[i] = id;
    commit_body(scene, id, name, body_id);
    return MPS2P_OK;
}

int mps2p_scene_assign_body(mps2p_scene *scene, const char *name, double x0, double y0,
                            double x1, double y1, int *body_id)
{
    error_clear();
    if (!scene)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_scene_assign_body: scene is NULL");
    int status = check_name(scene, name);
    if (status == MPS2P_OK)
        status = reserve_name(scene);
    if (status != MPS2P_OK)
        return status;
    if (!isfinite(x0) || !isfinite(y0) || !isfinite(x1) || !isfinite(y1) || x1 <= x0 ||
        y1 <= y0)
        return fail(scene->error, MPS2P_ERR_INVALID,
                    "box must be finite with x1 > x0 and y1 > y0, got (%g, %g) to (%g, %g)",
                    x0, y0, x1, y1);
    int id = find_body(scene, name);
    size_t moved = 0;
    for (size_t i = 0; i < scene->count; i++) {
        double x = scene->position[2 * i], y = scene->position[2 * i + 1];
        if (scene->kind[i] != MPS2P_KIND_FLUID && x >= x0 && x <= x1 && y >= y0 && y <= y1) {
            scene->body_id[i] = id;
            moved++;
        }
    }
    if (moved == 0)
        return fail(scene->error, MPS2P_ERR_INVALID,
                    "no solid particle in the box (%g, %g) to (%g, %g) for body \"%s\"", x0,
                    y0, x1, y1, name);
    commit_body(scene, id, name, body_id);
    return MPS2P_OK;
}

int mps2p_scene_body_count(const mps2p_scene *scene, int *count)
{
    error_clear();
    if (!scene || !count)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_scene_body_count: %s is NULL",
                    scene ? "count" : "scene");
    *count = scene->body_count + 1;
    return MPS2P_OK;
}

/* ---- solver ---- */

void coupling_free(struct coupling *c)
{
    if (!c)
        return;
    for (int b = 0; c->bodies && b < c->body_count; b++) { /* bodies NULL: calloc failed */
        free(c->bodies[b].member);
        free(c->bodies[b].target);
    }
    free(c->bodies);
    free(c->body_of);
    free(c->acceleration);
    free(c);
}

int coupling_build(mps2p_solver *s, int count, char (*names)[FLUID_NAME_SIZE],
                   const int *body_of)
{
    struct coupling *c = calloc(1, sizeof *c);
    if (c) {
        c->body_count = count;
        c->bodies = calloc((size_t)count, sizeof *c->bodies);
        c->body_of = malloc((s->count ? s->count : 1) * sizeof *c->body_of);
    }
    if (!c || !c->bodies || !c->body_of) {
        coupling_free(c);
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory for %d bodies", count);
    }
    for (size_t i = 0; i < s->count; i++) {
        int id = kind_is_fluid(s->kind[i]) ? -1 : body_of ? body_of[i] : 0;
        c->body_of[i] = id;
        if (id >= 0)
            c->bodies[id].particles++;
    }
    int status = MPS2P_OK;
    for (int b = 0; b < count; b++) {
        body *bd = &c->bodies[b];
        strcpy(bd->name, b == 0 ? WALLS_NAME : names[b - 1]);
        bd->member = malloc((bd->particles ? bd->particles : 1) * sizeof *bd->member);
        if (!bd->member)
            status = MPS2P_ERR_NOMEM;
        bd->particles = 0;
    }
    if (status != MPS2P_OK) {
        coupling_free(c);
        return fail(NULL, status, "out of memory for %d bodies", count);
    }
    for (size_t i = 0; i < s->count; i++)
        if (c->body_of[i] >= 0) {
            body *bd = &c->bodies[c->body_of[i]];
            bd->member[bd->particles++] = i;
        }
    coupling_free(s->coupling);
    s->coupling = c;
    return MPS2P_OK;
}

int coupling_create(mps2p_solver *s, const mps2p_scene *scene)
{
    if (!scene)
        return coupling_build(s, 1, NULL, NULL);
    return coupling_build(s, scene->body_count + 1, scene->body_names, scene->body_id);
}

static int check_body(const mps2p_solver *s, int body_id, const char *function)
{
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "%s: solver is NULL", function);
    if (body_id < 0 || body_id >= s->coupling->body_count)
        return fail(NULL, MPS2P_ERR_INVALID, "%s: no body with id %d (the solver has %d)",
                    function, body_id, s->coupling->body_count);
    return MPS2P_OK;
}

int mps2p_solver_body_count(const mps2p_solver *s, int *count)
{
    error_clear();
    if (!s || !count)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_body_count: %s is NULL",
                    s ? "count" : "solver");
    *count = s->coupling->body_count;
    return MPS2P_OK;
}

int mps2p_solver_get_body(const mps2p_solver *s, int body_id, const char **name,
                          size_t *particles)
{
    error_clear();
    int status = check_body(s, body_id, "mps2p_solver_get_body");
    if (status != MPS2P_OK)
        return status;
    if (name)
        *name = s->coupling->bodies[body_id].name;
    if (particles)
        *particles = s->coupling->bodies[body_id].particles;
    return MPS2P_OK;
}

int mps2p_solver_get_body_ids(const mps2p_solver *s, int *out, size_t length)
{
    error_clear();
    if (!s || !out)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_get_body_ids: %s is NULL",
                    s ? "output pointer" : "solver");
    if (length < s->count)
        return fail(NULL, MPS2P_ERR_BUFFER,
                    "body ids: buffer holds %zu elements, %zu needed", length, s->count);
    memcpy(out, s->coupling->body_of, s->count * sizeof *out);
    return MPS2P_OK;
}

/* The unit normal of wall particle i: the wall's own direction, perpendicular
 * to the line of the wall particles around it, of any body (the main axis of
 * sum_j w r_ij r_ij^T / |r_ij|^2 over them, w the density kernel), turned to
 * point from the fluid into the wall. Where that line is not clear (a
 * corner, a lone particle), the fluid's side alone: the unit vector of
 * sum_j w (r_i - r_j) / |r_ij| over fluid neighbours. (The fluid's side alone
 * tilts the normal of a wall's lowest particle by 13 degrees at a tank's
 * floor; the line of one body's particles alone sees a straight wall where
 * two bodies meet in a corner, and the forces of still water on a tank's
 * bodies then do not cancel.) */
static int wall_normal(const mps2p_solver *s, size_t i, const double fluid_side[2],
                       double n[2])
{
    const double re = s->params.re_density * s->l0;
    const double *r = s->state.position;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    double xx = 0.0, xy = 0.0, yy = 0.0;
    for (size_t k = nl.start[i]; k < nl.start[i + 1]; k++) {
        size_t j = nl.index[k];
        if (s->kind[j] != MPS2P_KIND_WALL)
            continue;
        double dx = r[2 * j] - r[2 * i], dy = r[2 * j + 1] - r[2 * i + 1];
        double d2 = dx * dx + dy * dy, w = kernel_weight(sqrt(d2), re);
        if (w == 0.0)
            continue;
        xx += w * dx * dx / d2;
        xy += w * dx * dy / d2;
        yy += w * dy * dy / d2;
    }
    /* eigenvalues of [[xx, xy], [xy, yy]]: a line when the smaller is under a
     * quarter of the larger */
    double mean = 0.5 * (xx + yy), spread = hypot(0.5 * (xx - yy), xy);
    double large = mean + spread, small = mean - spread;
    double length = hypot(fluid_side[0], fluid_side[1]);
    if (length == 0.0)
        return 0;
    if (large > 0.0 && small < 0.25 * large) {
        /* tangent = eigenvector of the larger eigenvalue; normal perpendicular */
        double tx = xy, ty = large - xx;
        if (hypot(tx, ty) == 0.0) {
            tx = large - yy;
            ty = xy;
        }
        double t = hypot(tx, ty);
        n[0] = -ty / t;
        n[1] = tx / t;
        if (n[0] * fluid_side[0] + n[1] * fluid_side[1] < 0.0) {
            n[0] = -n[0];
            n[1] = -n[1];
        }
        return 1;
    }
    n[0] = fluid_side[0] / length;
    n[1] = fluid_side[1] / length;
    return 1;
}

/* Force on wall particle i: p_i l0 n_i, times the share of fluid_id's weight
 * in sum_j w_ij over fluid neighbours j; 0 (none) for a dummy, a wall at p =
 * 0 or one without fluid neighbours. */
static int wall_force(const mps2p_solver *s, size_t i, int fluid_id, double f[2])
{
    if (s->kind[i] != MPS2P_KIND_WALL || s->state.pressure[i] == 0.0)
        return 0;
    const double re = s->params.re_density * s->l0;
    const double *r = s->state.position;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    double side[2] = {0.0, 0.0}, weight = 0.0, mine = 0.0;
    for (size_t k = nl.start[i]; k < nl.start[i + 1]; k++) {
        size_t j = nl.index[k];
        if (s->kind[j] != MPS2P_KIND_FLUID)
            continue;
        double dx = r[2 * i] - r[2 * j], dy = r[2 * i + 1] - r[2 * j + 1];
        double d = sqrt(dx * dx + dy * dy), w = kernel_weight(d, re);
        if (w == 0.0)
            continue;
        side[0] += w * dx / d;
        side[1] += w * dy / d;
        weight += w;
        if (fluid_id < 0 || s->fluid_id[j] == fluid_id)
            mine += w;
    }
    double n[2];
    if (weight == 0.0 || !wall_normal(s, i, side, n))
        return 0;
    double magnitude = s->state.pressure[i] * s->l0 * (mine / weight);
    f[0] = magnitude * n[0];
    f[1] = magnitude * n[1];
    return 1;
}

/* The fluid id of the force calls: -1 (all) or a fluid of the solver. */
static int check_fluid_of_force(const mps2p_solver *s, int fluid_id, const char *function)
{
    if (fluid_id < -1 || fluid_id >= s->fluid_count)
        return fail(NULL, MPS2P_ERR_INVALID, "%s: no fluid with id %d (the solver has %d; -1 = all)",
                    function, fluid_id, s->fluid_count);
    return MPS2P_OK;
}

int mps2p_solver_get_wall_loads(const mps2p_solver *s, int body_id, int fluid_id, double *loads,
                                size_t length)
{
    error_clear();
    int status = check_body(s, body_id, "mps2p_solver_get_wall_loads");
    if (status == MPS2P_OK && !loads)
        status = fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_get_wall_loads: loads is NULL");
    if (status == MPS2P_OK)
        status = check_fluid_of_force(s, fluid_id, "mps2p_solver_get_wall_loads");
    if (status == MPS2P_OK && length < 2 * s->count)
        status = fail(NULL, MPS2P_ERR_BUFFER,
                      "wall loads: buffer holds %zu elements, %zu needed (2 per particle)",
                      length, 2 * s->count);
    if (status != MPS2P_OK)
        return status;
    memset(loads, 0, 2 * s->count * sizeof *loads);
    /* the terms mps2p_solver_body_force sums, in its order */
    const body *b = &s->coupling->bodies[body_id];
    for (size_t m = 0; m < b->particles; m++) {
        size_t i = b->member[m];
        double f[2];
        if (!wall_force(s, i, fluid_id, f))
            continue;
        loads[2 * i] = f[0];
        loads[2 * i + 1] = f[1];
    }
    return MPS2P_OK;
}

int mps2p_solver_body_force(const mps2p_solver *s, int body_id, int fluid_id, double force[2],
                            double *moment, const double about[2])
{
    error_clear();
    int status = check_body(s, body_id, "mps2p_solver_body_force");
    if (status != MPS2P_OK)
        return status;
    if (!force)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_body_force: force output is NULL");
    status = check_fluid_of_force(s, fluid_id, "mps2p_solver_body_force");
    if (status != MPS2P_OK)
        return status;
    if (about && (!isfinite(about[0]) || !isfinite(about[1])))
        return fail(NULL, MPS2P_ERR_INVALID,
                    "mps2p_solver_body_force: moment point (%g, %g) is not finite", about[0],
                    about[1]);
    const double centre[2] = {about ? about[0] : 0.0, about ? about[1] : 0.0};
    const body *b = &s->coupling->bodies[body_id];
    double total[2] = {0.0, 0.0}, torque = 0.0;
    for (size_t m = 0; m < b->particles; m++) {
        size_t i = b->member[m];
        double f[2];
        if (!wall_force(s, i, fluid_id, f))
            continue;
        total[0] += f[0];
        total[1] += f[1];
        torque += (s->state.position[2 * i] - centre[0]) * f[1] -
                  (s->state.position[2 * i + 1] - centre[1]) * f[0];
    }
    force[0] = total[0];
    force[1] = total[1];
    if (moment)
        *moment = torque;
    return MPS2P_OK;
}
