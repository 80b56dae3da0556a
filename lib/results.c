/* Results: fields copied into caller buffers, and statistics by name. */
#include "internal.h"

#include <math.h>
#include <string.h>

#define CHECK_OUTPUT(s, out)                                                         \
    do {                                                                             \
        if (!(s))                                                                    \
            return fail(NULL, MPS2P_ERR_NULL, "%s: solver is NULL", __func__);        \
        if (!(out))                                                                  \
            return fail(NULL, MPS2P_ERR_NULL, "%s: output pointer is NULL", __func__); \
    } while (0)

static int check_length(const char *what, size_t length, size_t needed)
{
    if (length < needed)
        return fail(NULL, MPS2P_ERR_BUFFER, "%s: buffer holds %zu elements, %zu needed", what,
                    length, needed);
    return MPS2P_OK;
}

int mps2p_solver_particle_count(const mps2p_solver *s, size_t *count)
{
    error_clear();
    CHECK_OUTPUT(s, count);
    *count = s->count;
    return MPS2P_OK;
}

static int copy_doubles(const char *what, const double *from, size_t n, double *out,
                        size_t length)
{
    int status = check_length(what, length, n);
    if (status == MPS2P_OK)
        memcpy(out, from, n * sizeof *out);
    return status;
}

int mps2p_solver_get_positions(const mps2p_solver *s, double *out, size_t length)
{
    error_clear();
    CHECK_OUTPUT(s, out);
    return copy_doubles("positions", s->state.position, 2 * s->count, out, length);
}

int mps2p_solver_get_velocities(const mps2p_solver *s, double *out, size_t length)
{
    error_clear();
    CHECK_OUTPUT(s, out);
    return copy_doubles("velocities", s->state.velocity, 2 * s->count, out, length);
}

int mps2p_solver_get_pressure(const mps2p_solver *s, double *out, size_t length)
{
    error_clear();
    CHECK_OUTPUT(s, out);
    return copy_doubles("pressure", s->state.pressure, s->count, out, length);
}

int mps2p_solver_get_number_density(const mps2p_solver *s, double *out, size_t length)
{
    error_clear();
    CHECK_OUTPUT(s, out);
    return copy_doubles("number density", s->number_density, s->count, out, length);
}

int mps2p_solver_get_kinds(const mps2p_solver *s, int *out, size_t length)
{
    error_clear();
    CHECK_OUTPUT(s, out);
    int status = check_length("kinds", length, s->count);
    if (status == MPS2P_OK)
        memcpy(out, s->kind, s->count * sizeof *out);
    return status;
}

int mps2p_solver_get_fluid_ids(const mps2p_solver *s, int *out, size_t length)
{
    error_clear();
    CHECK_OUTPUT(s, out);
    int status = check_length("fluid ids", length, s->count);
    if (status == MPS2P_OK)
        memcpy(out, s->fluid_id, s->count * sizeof *out);
    return status;
}

int mps2p_solver_get_time(const mps2p_solver *s, double *time)
{
    error_clear();
    CHECK_OUTPUT(s, time);
    *time = s->time;
    return MPS2P_OK;
}

int mps2p_solver_get_step_count(const mps2p_solver *s, uint64_t *steps)
{
    error_clear();
    CHECK_OUTPUT(s, steps);
    *steps = s->steps;
    return MPS2P_OK;
}

int mps2p_solver_get_last_dt(const mps2p_solver *s, double *dt)
{
    error_clear();
    CHECK_OUTPUT(s, dt);
    *dt = s->last_dt;
    return MPS2P_OK;
}

/* Sums over fluid particles; mass per unit depth is rho l0^2. */
static double fluid_sum(const mps2p_solver *s, const char *key)
{
    const double area = s->l0 * s->l0;
    double result = 0.0;
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        const double *u = &s->state.velocity[2 * i], *r = &s->state.position[2 * i];
        double m = s->density[i] * area;
        if (strcmp(key, "max_speed") == 0)
            result = fmax(result, hypot(u[0], u[1]));
        else if (strcmp(key, "kinetic_energy") == 0)
            result += 0.5 * m * (u[0] * u[0] + u[1] * u[1]);
        else
            result -= m * (s->params.gravity[0] * r[0] + s->params.gravity[1] * r[1]);
    }
    return result;
}

static double pressure_extreme(const mps2p_solver *s, int want_max)
{
    double result = want_max ? -INFINITY : INFINITY;
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] == MPS2P_KIND_DUMMY)
            continue;
        double p = s->state.pressure[i];
        result = want_max ? fmax(result, p) : fmin(result, p);
    }
    return result;
}

/* Closest approach of a fluid particle to any other particle, in l0: MPS
 * keeps particles apart only through pressure and collisions, so a pair far
 * inside l0 is an early sign of a squeeze. From the Verlet list, which holds
 * every pair within its cutoff at the current positions. */
static double closest_pair(const mps2p_solver *s)
{
    const neighbour_rows rows = neighbour_rows_within(&s->neighbours, s->l0);
    const double *r = s->state.position;
    double closest = INFINITY;
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        for (size_t k = rows.start[i]; k < rows.start[i + 1]; k++) {
            size_t j = rows.index[k];
            double dx = r[2 * j] - r[2 * i], dy = r[2 * j + 1] - r[2 * i + 1];
            closest = fmin(closest, dx * dx + dy * dy);
        }
    }
    return sqrt(closest) / s->l0;
}

int mps2p_solver_get_stat(const mps2p_solver *s, const char *key, double *value)
{
    error_clear();
    CHECK_OUTPUT(s, value);
    if (!key)
        return fail(NULL, MPS2P_ERR_NULL, "statistic key is NULL");
    if (!strcmp(key, "max_speed") || !strcmp(key, "kinetic_energy") ||
        !strcmp(key, "potential_energy"))
        *value = fluid_sum(s, key);
    else if (!strcmp(key, "pressure_min"))
        *value = pressure_extreme(s, 0);
    else if (!strcmp(key, "pressure_max"))
        *value = pressure_extreme(s, 1);
    else if (!strcmp(key, "ppe_unknowns"))
        *value = (double)s->ppe_unknowns;
    else if (!strcmp(key, "ppe_iterations"))
        *value = (double)s->ppe_iterations;
    else if (!strcmp(key, "ppe_residual"))
        *value = s->ppe_residual;
    else if (!strcmp(key, "surface_particles"))
        *value = (double)s->surface_particles;
    else if (!strcmp(key, "n0"))
        *value = s->n0_density;
    else if (!strcmp(key, "lambda"))
        *value = s->lambda;
    else if (!strcmp(key, "neighbour_builds"))
        *value = (double)s->neighbours.builds;
    else if (!strcmp(key, "ppe_iterations_total"))
        *value = (double)s->ppe_iterations_total;
    else if (!strcmp(key, "ppe_analyses"))
        *value = (double)linear_solver_analyses(s->linear);
    else if (!strcmp(key, "eddy_viscosity_max"))
        *value = s->eddy_viscosity_max;
    else if (!strcmp(key, "dt_next"))
        *value = timestep_choose(s);
    else if (!strcmp(key, "diverged_particle"))
        *value = s->diverged ? (double)s->diverged_particle : -1.0;
    else if (!strcmp(key, "closest_pair"))
        *value = s->neighbours.start ? closest_pair(s) : INFINITY;
    else if (!strcmp(key, "memory_bytes"))
        *value = (double)solver_memory_bytes(s);
    else if (phases_get_stat(s, key, value) == MPS2P_OK)
        return MPS2P_OK;
    else
        return fail(NULL, MPS2P_ERR_UNKNOWN_KEY, "unknown statistic \"%s\"", key);
    return MPS2P_OK;
}
