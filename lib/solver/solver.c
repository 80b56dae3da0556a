/* The solver: built from a scene, stepped through the stages of one MPS step. */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"
#include "two_phase/two_phase.h"
#include "coupling/coupling.h"
#include "solver/solver.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CLOSEST_ALLOWED 0.1 /* initial particles closer than this (in l0) are an error */

static void solver_free(mps2p_solver *s)
{
    free(s->fluids);
    fields_free(&solver_fields, s);
    if (s->before_step)
        fields_free(&solver_fields, s->before_step);
    free(s->before_step);
    neighbours_free(&s->neighbours);
    free(s->matrix.row_start);
    free(s->matrix.column);
    free(s->matrix.value);
    linear_solver_destroy(s->linear);
    coupling_free(s->coupling);
    phases_free(s->phases);
    free(s);
}

void mps2p_solver_destroy(mps2p_solver *s)
{
    if (!s)
        return;
    /* From the solver's own progress callback: its run still uses it, so it
     * is freed when mps2p_solver_advance_to returns (issue 20). */
    if (s->running) {
        s->destroy_requested = 1;
        return;
    }
    solver_free(s);
}

int solver_refuse_if_running(mps2p_solver *s, const char *function)
{
    if (!s->running)
        return MPS2P_OK;
    return fail(s->error, MPS2P_ERR_STATE,
                "%s: the solver is inside mps2p_solver_advance_to (this is its progress "
                "callback); return non-zero from the callback to stop the run first",
                function);
}

const char *mps2p_solver_last_error(const mps2p_solver *s)
{
    return s ? s->error : "solver is NULL";
}

typedef struct lattice_key {
    long x, y;
    size_t particle;
} lattice_key;

static int compare_keys(const void *a, const void *b)
{
    const lattice_key *p = a, *q = b;
    if (p->y != q->y)
        return (p->y > q->y) - (p->y < q->y);
    return (p->x > q->x) - (p->x < q->x);
}

/* A lattice coordinate, clamped far inside long's range so that the +-1
 * of the neighbour search cannot overflow (lround of a value out of range
 * is unspecified; such particles are absurdly far apart anyway). */
static long lattice_index(double offset)
{
    return lround(fmax(-1e15, fmin(1e15, offset)));
}

/* Solid particles from wall boxes become walls when one of their 8 lattice
 * neighbours is not solid (they face fluid or open space), dummies otherwise. */
static int classify_solids(mps2p_solver *s, const mps2p_scene *scene)
{
    size_t solids = 0, first = 0;
    for (size_t i = 0; i < s->count; i++)
        if (scene->kind[i] != MPS2P_KIND_FLUID && solids++ == 0)
            first = i;
    if (solids == 0)
        return MPS2P_OK;
    lattice_key *keys = malloc(solids * sizeof *keys);
    if (!keys)
        return MPS2P_ERR_NOMEM;
    /* Keys relative to one solid particle, so box lattices land on integers. */
    const double x0 = scene->position[2 * first], y0 = scene->position[2 * first + 1];
    size_t m = 0;
    for (size_t i = 0; i < s->count; i++) {
        if (scene->kind[i] == MPS2P_KIND_FLUID)
            continue;
        keys[m].x = lattice_index((scene->position[2 * i] - x0) / s->l0);
        keys[m].y = lattice_index((scene->position[2 * i + 1] - y0) / s->l0);
        keys[m].particle = i;
        m++;
    }
    qsort(keys, solids, sizeof *keys, compare_keys);
    for (size_t k = 0; k < solids; k++) {
        size_t i = keys[k].particle;
        if (scene->kind[i] != SOLID_FROM_BOX)
            continue;
        int exposed = 0;
        for (int dy = -1; dy <= 1 && !exposed; dy++) {
            for (int dx = -1; dx <= 1 && !exposed; dx++) {
                if (dx == 0 && dy == 0)
                    continue;
                lattice_key probe = {keys[k].x + dx, keys[k].y + dy, 0};
                if (!bsearch(&probe, keys, solids, sizeof *keys, compare_keys))
                    exposed = 1;
            }
        }
        s->kind[i] = exposed ? MPS2P_KIND_WALL : MPS2P_KIND_DUMMY;
    }
    free(keys);
    return MPS2P_OK;
}

static void default_domain(const mps2p_scene *scene, double domain[4])
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (size_t i = 0; i < scene->count; i++)
        for (int d = 0; d < 2; d++) {
            lo[d] = fmin(lo[d], scene->position[2 * i + d]);
            hi[d] = fmax(hi[d], scene->position[2 * i + d]);
        }
    for (int d = 0; d < 2; d++) {
        double extent = fmax(hi[d] - lo[d], scene->l0);
        domain[d] = lo[d] - extent;
        domain[d + 2] = hi[d] + extent;
    }
}

/* Derived time-step and divergence bounds; see the header for the formulas.
 * The free-fall height is from the lowest fluid particle to the highest of a
 * heavy fluid (not below light_fraction of the heaviest density): a liquid
 * falls through the air under it, but air over a liquid does not fall, and
 * counted it made the paper's case take 5.4e-4 s steps where its water's
 * 0.3 m gives 8.2e-4 (docs/performance.md). One fluid: its height. */
static void derive_bounds(mps2p_solver *s)
{
    double lo = INFINITY, max_speed = 0.0, rho_max = 0.0;
    double box_lo[2] = {INFINITY, INFINITY}, box_hi[2] = {-INFINITY, -INFINITY};
    for (size_t i = 0; i < s->count; i++) {
        for (int d = 0; d < 2; d++) {
            box_lo[d] = fmin(box_lo[d], s->state.position[2 * i + d]);
            box_hi[d] = fmax(box_hi[d], s->state.position[2 * i + d]);
        }
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        lo = fmin(lo, s->state.position[2 * i + 1]);
        max_speed = fmax(max_speed, hypot(s->state.velocity[2 * i], s->state.velocity[2 * i + 1]));
        rho_max = fmax(rho_max, s->density[i]);
    }
    double heavy_top = -INFINITY;
    for (size_t i = 0; i < s->count; i++)
        if (s->kind[i] == MPS2P_KIND_FLUID && s->density[i] >= s->params.light_fraction * rho_max)
            heavy_top = fmax(heavy_top, s->state.position[2 * i + 1]);
    double g = hypot(s->params.gravity[0], s->params.gravity[1]);
    double fluid_height = heavy_top - lo + s->l0;
    double reference_speed = fmax(sqrt(2.0 * g * fluid_height), max_speed);
    if (reference_speed == 0.0)
        reference_speed = 1.0; /* nothing moves and nothing pulls: any scale will do */
    s->dt_max = s->params.dt_max > 0.0 ? s->params.dt_max
                                       : s->params.cfl * s->l0 / reference_speed;
    double extent = fmax(box_hi[0] - box_lo[0], box_hi[1] - box_lo[1]) + s->l0;
    s->pressure_limit = s->params.pressure_limit > 0.0
                            ? s->params.pressure_limit
                            : 1000.0 * rho_max * fmax(g * extent, 1.0);
}

static int check_spacing(const mps2p_solver *s)
{
    const neighbour_list *nl = &s->neighbours;
    const double closest = CLOSEST_ALLOWED * s->l0;
    for (size_t i = 0; i < s->count; i++) {
        for (size_t k = nl->start[i]; k < nl->start[i + 1]; k++) {
            size_t j = nl->index[k];
            double d = hypot(s->state.position[2 * j] - s->state.position[2 * i],
                             s->state.position[2 * j + 1] - s->state.position[2 * i + 1]);
            if (j > i && d < closest)
                return fail(NULL, MPS2P_ERR_INVALID,
                            "particles %zu and %zu are %g l0 apart at (%g, %g), closer than "
                            "%g l0 (overlapping boxes?)",
                            i, j, d / s->l0, s->state.position[2 * i],
                            s->state.position[2 * i + 1], CLOSEST_ALLOWED);
        }
    }
    return MPS2P_OK;
}

int solver_allocate(mps2p_solver *s, size_t n, int fluid_count)
{
    s->count = n;
    s->fluid_count = fluid_count;
    s->fluids = malloc((size_t)fluid_count * sizeof *s->fluids);
    s->before_step = calloc(1, sizeof *s->before_step);
    if (!s->fluids || !s->before_step ||
        fields_allocate(&solver_fields, s, n, 0, FIELD_ON_DEMAND) != MPS2P_OK ||
        fields_allocate(&solver_fields, s->before_step, n, FIELD_ROLLED_BACK, 0) != MPS2P_OK)
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory creating a solver for %zu particles", n);
    return MPS2P_OK;
}

int solver_start(mps2p_solver *s)
{
    if (!s->coupling) { /* a checkpoint's solver: every solid in body 0 */
        int status = coupling_create(s, NULL);
        if (status != MPS2P_OK)
            return status;
    }
    double cutoff = (params_max_radius(&s->params) + s->params.neighbour_skin) * s->l0;
    /* the short list serves the stages within the density radius */
    if (neighbours_init(&s->neighbours, s->count, cutoff, s->params.neighbour_skin * s->l0,
                        s->params.re_density * s->l0, s->domain) != MPS2P_OK)
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory for the neighbour list");
    s->neighbours.threads = s->params.threads;
    /* fluid out of the run (stages/divergence.c) is nobody's neighbour */
    s->neighbours.skip = s->kind;
    s->neighbours.skip_value = MPS2P_KIND_OUT;
    char message[ERROR_MESSAGE_SIZE];
    int status = linear_solver_create(s->params.pressure_solver, s->params.cg_preconditioner,
                                      s->params.threads, &s->linear, message, sizeof message);
    if (status != MPS2P_OK)
        return fail(NULL, status, "%s", message);
    status = effects_decide(s);
    return status == MPS2P_OK ? plan_build(s) : status;
}

static int build(mps2p_solver *s, const mps2p_scene *scene)
{
    const size_t n = scene->count;
    s->l0 = scene->l0;
    s->params = scene->params;
    int status = solver_allocate(s, n, scene->fluid_count);
    if (status != MPS2P_OK)
        return status;
    for (int f = 0; f < scene->fluid_count; f++)
        s->fluids[f] = *scene->fluids[f];
    memcpy(s->state.position, scene->position, 2 * n * sizeof *s->state.position);
    memcpy(s->state.velocity, scene->velocity, 2 * n * sizeof *s->state.velocity);
    memcpy(s->kind, scene->kind, n * sizeof *s->kind);
    memcpy(s->fluid_id, scene->fluid_id, n * sizeof *s->fluid_id);
    if (classify_solids(s, scene) != MPS2P_OK)
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory classifying wall particles");

    double heaviest = 0.0;
    for (int f = 0; f < s->fluid_count; f++)
        heaviest = fmax(heaviest, s->fluids[f].density);
    for (size_t i = 0; i < n; i++) {
        int fluid = s->kind[i] == MPS2P_KIND_FLUID;
        s->density[i] = fluid ? s->fluids[s->fluid_id[i]].density : heaviest;
        s->viscosity[i] = fluid ? s->fluids[s->fluid_id[i]].viscosity : 0.0;
    }

    double unused;
    lattice_constants(s->l0, s->params.re_density, &s->n0_density, &unused);
    lattice_constants(s->l0, s->params.re_laplacian, &s->n0_laplacian, &s->lambda);
    if (scene->has_domain)
        memcpy(s->domain, scene->domain, sizeof s->domain);
    else
        default_domain(scene, s->domain);
    if (!isfinite(s->domain[2] - s->domain[0]) || !isfinite(s->domain[3] - s->domain[1]))
        return fail(NULL, MPS2P_ERR_INVALID,
                    "the domain [%g, %g] x [%g, %g] is too large: its width or height is not "
                    "a finite number", s->domain[0], s->domain[2], s->domain[1], s->domain[3]);
    derive_bounds(s);
    /* an l0 or gravity at the ends of a double's range (l0 = 1e300: lambda
     * overflows to nan; 1e-300: it underflows to 0) gives constants no step
     * can use, and a checkpoint its loader refuses */
    const struct { const char *name; double value; } derived[] = {
        {"n0 (number density)", s->n0_density}, {"n0 (Laplacian)", s->n0_laplacian},
        {"lambda", s->lambda}, {"dt_max", s->dt_max}, {"pressure_limit", s->pressure_limit}};
    for (size_t k = 0; k < sizeof derived / sizeof derived[0]; k++)
        if (!(isfinite(derived[k].value) && derived[k].value > 0.0))
            return fail(NULL, MPS2P_ERR_INVALID,
                        "l0 = %g m, gravity (%g, %g) m/s^2 and the heaviest fluid's density "
                        "%g kg/m^3 give %s = %g, not a finite positive number: the spacing, "
                        "gravity or density is beyond what the solver can compute with",
                        s->l0, s->params.gravity[0], s->params.gravity[1], heaviest,
                        derived[k].name, derived[k].value);

    status = coupling_create(s, scene);
    if (status == MPS2P_OK)
        status = solver_start(s);
    if (status != MPS2P_OK)
        return status;
    if (neighbours_update(&s->neighbours, s->state.position) != MPS2P_OK)
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory for the neighbour list");
    number_density_compute(s, s->number_density);
    return MPS2P_OK;
}

int mps2p_solver_create(const mps2p_scene *scene, mps2p_solver **solver)
{
    error_clear();
    if (!solver)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_create: solver output pointer is NULL");
    *solver = NULL;
    if (!scene)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_create: scene is NULL");
    size_t fluid_particles = 0;
    for (size_t i = 0; i < scene->count; i++)
        fluid_particles += scene->kind[i] == MPS2P_KIND_FLUID;
    if (fluid_particles == 0)
        return fail(NULL, MPS2P_ERR_STATE,
                    "scene has no fluid particles (%zu particles in all): add a fluid box "
                    "or fluid particles first", scene->count);
    if (scene->has_domain) {
        for (size_t i = 0; i < scene->count; i++) {
            double x = scene->position[2 * i], y = scene->position[2 * i + 1];
            if (x < scene->domain[0] || x > scene->domain[2] || y < scene->domain[1] ||
                y > scene->domain[3])
                return fail(NULL, MPS2P_ERR_INVALID,
                            "particle %zu at (%g, %g) is outside the domain [%g, %g] x [%g, %g]",
                            i, x, y, scene->domain[0], scene->domain[2], scene->domain[1],
                            scene->domain[3]);
        }
    }
    /* a tank's walls are as thick as the radii were when it was added: radii
     * raised after it would reach past its dummies, and the run would go on
     * with a wall too thin for its sums, unsaid */
    const double radius = params_max_radius(&scene->params);
    if (scene->tank_layers > 0 && (int)ceil(radius - 1e-9) > scene->tank_layers)
        return fail(NULL, MPS2P_ERR_INVALID,
                    "a tank's walls are %d layers thick, for the radii set when it was added; "
                    "re_density %g and re_laplacian %g l0 now need %d: set the radii (or the "
                    "scheme) before mps2p_scene_add_tank",
                    scene->tank_layers, scene->params.re_density, scene->params.re_laplacian,
                    (int)ceil(radius - 1e-9));
    char what[64];
    snprintf(what, sizeof what, "a solver of %zu particles", scene->count);
    int status = memory_check(&scene->params, solver_bytes_estimate(&scene->params, scene->count),
                              what, NULL);
    if (status != MPS2P_OK)
        return status;
    mps2p_solver *s = calloc(1, sizeof *s);
    if (!s)
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory creating a solver");
    s->diverged_particle = -1;
    status = build(s, scene);
    if (status == MPS2P_OK)
        status = check_spacing(s);
    if (status != MPS2P_OK) {
        mps2p_solver_destroy(s);
        return status;
    }
    *solver = s;
    return MPS2P_OK;
}

static void save_state(mps2p_solver *s)
{
    fields_copy(&solver_fields, s->before_step, s, s->count, FIELD_ROLLED_BACK);
    if (s->phases)
        phases_save_before_step(s);
}

static void restore_state(mps2p_solver *s)
{
    fields_copy(&solver_fields, s, s->before_step, s->count, FIELD_ROLLED_BACK);
    if (s->phases)
        phases_put_carried(s, s->phases->before_step, FIELD_ROLLED_BACK);
}

/* One step of length dt: the plan of stages (plan.c), rolled back on
 * failure. ppe_min_dt: the shortest dt its pressure solve may see (0 = dt). */
static int step_with(mps2p_solver *s, double dt, double ppe_min_dt)
{
    if (s->diverged)
        return fail(s->error, MPS2P_ERR_STATE,
                    "the solver diverged in step %llu, from its last good state at t = %.6g s, "
                    "which it keeps; it cannot step further",
                    (unsigned long long)s->steps + 1, s->time);
    if (s->plan_stale) {
        int status = plan_build(s);
        if (status != MPS2P_OK)
            return status;
    }
    save_state(s);
    s->ppe_min_dt = ppe_min_dt;
    int status = plan_run(s, dt);
    s->ppe_min_dt = 0.0;
    if (status == MPS2P_ERR_DIVERGED)
        s->diverged = 1;
    if (status != MPS2P_OK) {
        restore_state(s);
        return status;
    }
    s->time += dt;
    s->last_dt = dt;
    s->steps++;
    body_motion_done(s, dt);
    return MPS2P_OK;
}

int mps2p_solver_step(mps2p_solver *s)
{
    error_clear();
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_step: solver is NULL");
    int status = solver_refuse_if_running(s, "mps2p_solver_step");
    if (status != MPS2P_OK)
        return status;
    return step_with(s, timestep_choose(s), 0.0);
}

/* The end of a run that a progress callback left by a C++ exception: with
 * -fexceptions (lib/meson.build) the unwinding runs this cleanup, so the
 * solver is not left "running" (every later call refused, destroy freeing
 * nothing), and a destroy asked for before the throw is done. NULL: the run
 * returned. */
static void end_unwound_run(mps2p_solver **run)
{
    mps2p_solver *s = *run;
    if (!s)
        return;
    s->running = 0;
    if (s->destroy_requested)
        solver_free(s);
}

#if defined(__GNUC__)
#define ENDS_AN_UNWOUND_RUN __attribute__((cleanup(end_unwound_run)))
#else
#define ENDS_AN_UNWOUND_RUN
#endif

/* The steps of mps2p_solver_advance_to, with s->running set. */
static int advance(mps2p_solver *s, double end_time, mps2p_progress_fn progress,
                   void *user_data)
{
    const double tolerance = 1e-12 * fmax(1.0, fabs(end_time));
    while (end_time - s->time > tolerance) {
        double dt = timestep_choose(s);
        double remaining = end_time - s->time;
        /* Equal steps to the end rather than full ones and a short last one:
         * the pressure scales with 1/dt^2 times the density error, so a short
         * last step would bias the pressure read at end_time. */
        double steps_left = ceil(remaining / dt * (1.0 - 1e-9));
        if (!(steps_left <= MAX_STEPS_PER_ADVANCE)) {
            /* a viscosity of 1e20 m^2/s gives dt = 1e-24 s: it would never end */
            char why[160];
            timestep_explain(s, why, sizeof why);
            return fail(s->error, MPS2P_ERR_INVALID,
                        "advancing %g s to t = %.9g s at dt = %g s would take %.3g steps, "
                        "more than %g; the step is set by %s", remaining, end_time, dt,
                        steps_left, MAX_STEPS_PER_ADVANCE, why);
        }
        int last = steps_left <= 1.0;
        /* Every step of an even division is longer than dt / 2; only a window
         * shorter than that ends in a shorter one, whose pressure solve then
         * sees dt / 2 (PPE_MIN_STEP_FRACTION; pressure.c says why). */
        double ppe_min_dt = last && remaining < PPE_MIN_STEP_FRACTION * dt
                                ? PPE_MIN_STEP_FRACTION * dt : 0.0;
        dt = last ? remaining : remaining / steps_left;
        int status = step_with(s, dt, ppe_min_dt);
        if (status != MPS2P_OK)
            return status;
        if (last)
            s->time = end_time; /* land exactly, without rounding drift */
        if (progress && (progress(s, user_data) || s->destroy_requested))
            return MPS2P_STOPPED;
    }
    /* A rest within the tolerance (rounding, or a window of 1e-12 s) is not
     * a step; the time still lands on end_time, as promised. */
    s->time = end_time;
    return MPS2P_OK;
}

int mps2p_solver_advance_to(mps2p_solver *s, double end_time, mps2p_progress_fn progress,
                            void *user_data)
{
    error_clear();
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_advance_to: solver is NULL");
    int status = solver_refuse_if_running(s, "mps2p_solver_advance_to");
    if (status != MPS2P_OK)
        return status;
    if (!isfinite(end_time) || end_time < s->time)
        return fail(s->error, MPS2P_ERR_INVALID,
                    "end time must be finite and not before the current time %.9g s, got %g",
                    s->time, end_time);
    s->running = 1;
    mps2p_solver *unwinding ENDS_AN_UNWOUND_RUN = s;
    status = advance(s, end_time, progress, user_data);
    unwinding = NULL;
    s->running = 0;
    if (s->destroy_requested) {
        solver_free(s);
        return fail(NULL, MPS2P_ERR_STATE,
                    "mps2p_solver_advance_to: the progress callback destroyed the solver; the "
                    "run stopped after that callback, and the solver is freed now");
    }
    if (status >= 0)
        error_clear(); /* a failure inside the callback is not this call's */
    return status;
}
