/* Statistics by name: one row each (name, description, whether it counts,
 * how it is read), the solver's here and the two phases' in
 * two_phase/stats.c; mps2p_stat_info lists both, in that order. */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"
#include "two_phase/two_phase.h"
#include "solver/solver.h"

#include <math.h>
#include <string.h>

/* Over the fluid particles in the run (not those out of it, MPS2P_KIND_OUT:
 * a droplet that left the domain takes its energy out of the sums); mass per
 * unit depth is rho l0^2. */
static double max_speed(const mps2p_solver *s)
{
    double result = 0.0;
    for (size_t i = 0; i < s->count; i++)
        if (s->kind[i] == MPS2P_KIND_FLUID)
            result = fmax(result, hypot(s->state.velocity[2 * i], s->state.velocity[2 * i + 1]));
    return result;
}

static double kinetic_energy(const mps2p_solver *s)
{
    const double area = s->l0 * s->l0;
    double result = 0.0;
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        const double *u = &s->state.velocity[2 * i];
        double m = s->density[i] * area;
        result += 0.5 * m * (u[0] * u[0] + u[1] * u[1]);
    }
    return result;
}

static double potential_energy(const mps2p_solver *s)
{
    const double area = s->l0 * s->l0;
    double g[2];
    gravity_acting(s, g); /* the energy of the forces the step applies */
    double result = 0.0;
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        const double *r = &s->state.position[2 * i];
        double m = s->density[i] * area;
        result -= m * (g[0] * r[0] + g[1] * r[1]);
    }
    return result;
}

static double pressure_extreme(const mps2p_solver *s, int want_max)
{
    double result = want_max ? -INFINITY : INFINITY;
    for (size_t i = 0; i < s->count; i++) {
        if (!kind_carries_pressure(s->kind[i]))
            continue;
        double p = s->state.pressure[i];
        result = want_max ? fmax(result, p) : fmin(result, p);
    }
    return result;
}

static double pressure_min(const mps2p_solver *s) { return pressure_extreme(s, 0); }
static double pressure_max(const mps2p_solver *s) { return pressure_extreme(s, 1); }
static double ppe_unknowns(const mps2p_solver *s) { return (double)s->ppe_unknowns; }
static double ppe_iterations(const mps2p_solver *s) { return (double)s->ppe_iterations; }
static double ppe_residual(const mps2p_solver *s) { return s->ppe_residual; }
static double surface_particles(const mps2p_solver *s) { return (double)s->surface_particles; }
static double n0(const mps2p_solver *s) { return s->n0_density; }
static double lambda(const mps2p_solver *s) { return s->lambda; }
static double neighbour_builds(const mps2p_solver *s) { return (double)s->neighbours.builds; }
static double ppe_iterations_total(const mps2p_solver *s)
{
    return (double)s->ppe_iterations_total;
}
static double dt_next(const mps2p_solver *s) { return timestep_choose(s); }
static double ppe_analyses(const mps2p_solver *s)
{
    return (double)linear_solver_analyses(s->linear);
}
static double eddy_viscosity_max(const mps2p_solver *s) { return s->eddy_viscosity_max; }
static double memory_bytes(const mps2p_solver *s) { return (double)solver_memory_bytes(s); }
static double fluid_out(const mps2p_solver *s) { return (double)s->fluid_out; }
/* what parameter threads comes to: 0 asks OpenMP's default, which a run's
 * record should name as a count (1 in a build without OpenMP) */
static double threads(const mps2p_solver *s) { return (double)team_size(s->params.threads); }
static double diverged_particle(const mps2p_solver *s)
{
    return s->diverged ? (double)s->diverged_particle : -1.0;
}

/* Closest approach of a fluid particle to any other particle, in l0: MPS
 * keeps particles apart only through pressure and collisions, so a pair far
 * inside l0 is an early sign of a squeeze. From the Verlet list, which holds
 * every pair within its cutoff at the current positions. */
static double closest_pair(const mps2p_solver *s)
{
    if (!s->neighbours.start)
        return INFINITY;
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

#define STAT(name, is_count, description) {#name, description, is_count, name}
static const stat_entry solver_stats[] = {
    STAT(max_speed, 0, "largest speed of the fluid in the run (m/s)"),
    STAT(kinetic_energy, 0,
         "sum of m u^2 / 2 over the fluid in the run, m = rho l0^2 (J per m depth)"),
    STAT(potential_energy, 0, "sum of -m g.r over the fluid in the run (J per m depth; 0 "
                              "with effect gravity off)"),
    STAT(pressure_min, 0, "lowest pressure of the fluid and wall particles (Pa)"),
    STAT(pressure_max, 0, "highest pressure of the fluid and wall particles (Pa)"),
    STAT(ppe_unknowns, 1, "unknowns of the last pressure solve"),
    STAT(ppe_iterations, 1, "CG iterations of the last solve (0 for cholmod)"),
    STAT(ppe_residual, 0, "relative residual |Ax - b| / |b| of the last solve"),
    STAT(surface_particles, 1, "particles flagged free surface in the last step"),
    STAT(n0, 0, "reference number density n0 (of re_density)"),
    STAT(lambda, 0, "Laplacian constant lambda (m^2)"),
    STAT(neighbour_builds, 1, "times the neighbour list was built so far"),
    STAT(ppe_iterations_total, 1, "CG iterations of all solves so far"),
    STAT(dt_next, 0, "the time step the next mps2p_solver_step would take (s)"),
    STAT(ppe_analyses, 1, "CHOLMOD symbolic analyses so far (0 for cg)"),
    STAT(eddy_viscosity_max, 0,
         "largest eddy viscosity of the last step (m^2/s; 0 unless effect.turbulence is on)"),
    STAT(memory_bytes, 1, "memory the solver holds: arrays, lists, matrix, solver workspace"),
    STAT(closest_pair, 0, "smallest distance from a fluid particle to any other particle (l0)"),
    STAT(diverged_particle, 1,
         "the particle a divergence was found at; -1 when none or not known"),
    STAT(fluid_out, 1, "fluid particles that left the domain and are out of the run "
                       "(kind MPS2P_KIND_OUT; parameter out_limit)"),
    STAT(threads, 1, "threads the particle loops run on: parameter threads, or OpenMP's "
                     "default for 0; 1 without OpenMP"),
};
#define SOLVER_STATS (sizeof solver_stats / sizeof solver_stats[0])
#define STAT_COUNT (SOLVER_STATS + two_phase_stat_count)

static const stat_entry *stat_at(size_t index)
{
    if (index < SOLVER_STATS)
        return &solver_stats[index];
    index -= SOLVER_STATS;
    return index < two_phase_stat_count ? &two_phase_stats[index] : NULL;
}

int mps2p_stat_count(size_t *count)
{
    error_clear();
    if (!count)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_stat_count: count is NULL");
    *count = STAT_COUNT;
    return MPS2P_OK;
}

int mps2p_stat_info(size_t index, const char **key, const char **description, int *is_count)
{
    error_clear();
    const stat_entry *e = stat_at(index);
    if (!e)
        return fail(NULL, MPS2P_ERR_INVALID, "statistic index %zu is past the last (%zu)",
                    index, STAT_COUNT - 1);
    if (key)
        *key = e->name;
    if (description)
        *description = e->description;
    if (is_count)
        *is_count = e->is_count;
    return MPS2P_OK;
}

static const char *stat_name_at(size_t index)
{
    return stat_at(index)->name;
}

int mps2p_solver_get_stat(const mps2p_solver *s, const char *key, double *value)
{
    error_clear();
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "%s: solver is NULL", __func__);
    if (!value)
        return fail(NULL, MPS2P_ERR_NULL, "%s: output pointer is NULL", __func__);
    if (!key)
        return fail(NULL, MPS2P_ERR_NULL, "statistic key is NULL");
    for (size_t k = 0; stat_at(k); k++)
        if (strcmp(stat_at(k)->name, key) == 0) {
            *value = stat_at(k)->value(s);
            return MPS2P_OK;
        }
    char hint[96];
    near_miss(key, stat_name_at, STAT_COUNT, hint, sizeof hint);
    return fail(NULL, MPS2P_ERR_UNKNOWN_KEY, "unknown statistic \"%s\"%s", key, hint);
}
