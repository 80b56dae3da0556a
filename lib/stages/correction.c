/* Correction: u' = -(dt / rho) <grad p>, u = u* + u', r = r* + dt u', with
 * one of two pressure gradients (option pressure_gradient):
 *   minimum    Koshizuka and Oka: p^_i = min(p_i, min_j p_j) as reference, so
 *              every pair pushes; the paper's form. In still water p_i - p^_i
 *              is about 2 rho g l0, a repulsive background under which a square
 *              lattice is unstable to shearing column against column.
 *   corrected  p_i as reference, times the inverse of the corrective matrix
 *              (Khayyer and Gotoh 2011): exact for a linear field on any
 *              arrangement, so no background; particles with a one-sided
 *              neighbourhood fall back to the uncorrected difference form.
 *              With wall_ghosts = hydrostatic a dry wall takes the ghost value
 *              the PPE gave it (pressure.c), not its p = 0: a dry wall at 0
 *              next to wet fluid pulls the fluid to it, and in still water
 *              turns a slow vortex at each corner where the surface meets a
 *              wall that stands above it. */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"

void pressure_gradient_at(const mps2p_solver *s, size_t i, const double *pressure,
                          const unsigned char *mask, const unsigned char *surface,
                          double gradient[2])
{
    if (s->params.pressure_gradient == GRADIENT_MINIMUM) {
        gradient_masked_at(s, i, pressure, minimum_masked_around(s, i, pressure, mask), mask,
                           gradient);
        return;
    }
    corrected_gradient_at(s, i, pressure, mask,
                          s->params.wall_ghosts == WALL_GHOSTS_HYDROSTATIC ? surface : NULL,
                          gradient);
}

int pressure_correct(mps2p_solver *s, double dt)
{
    const double *pressure = s->state.pressure;
    double *change = s->scratch;
    PARALLEL_FOR(s->params.threads, schedule(static),
    for (size_t i = 0; i < s->count; i++) {
        double *du = &change[2 * i];
        du[0] = du[1] = 0.0;
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        double gradient[2];
        pressure_gradient_at(s, i, pressure, NULL, s->on_surface, gradient);
        du[0] = -dt / s->density[i] * gradient[0];
        du[1] = -dt / s->density[i] * gradient[1];
    });
    correction_apply(s, change, dt);
    return MPS2P_OK;
}

void correction_apply(mps2p_solver *s, const double *change, double dt)
{
    double *position = s->state.position, *velocity = s->state.velocity;
    PARALLEL_FOR(s->params.threads, schedule(static),
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        velocity[2 * i] += change[2 * i];
        velocity[2 * i + 1] += change[2 * i + 1];
        position[2 * i] += dt * change[2 * i];
        position[2 * i + 1] += dt * change[2 * i + 1];
    });
}
