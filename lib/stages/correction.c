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

#include <math.h>

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
    PARALLEL_FOR(s->params.threads, UNEQUAL_ROWS,
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
    return s->params.shifting > 0.0 ? particles_shift(s, dt) : MPS2P_OK;
}

/* Particle shifting (parameter shifting, C): a fluid particle off the free
 * surface moves by C u_max dt sum_j (rbar_i / r_ij)^2 e_ji over its
 * neighbours within re_density, u_max the fastest fluid particle's speed,
 * rbar_i their mean distance and e_ji the unit vector from j to i: away from
 * close neighbours, into gaps (Xu, Stansby and Laurence 2009). The fastest speed,
 * not each particle's own (Lind et al. 2012): where a stream turns up a
 * wall the slow particles by the wall are the strained ones (measured: the
 * wall pressure's scatter 0.75 with their own speed, 0.59 with the fastest,
 * 0.81 without; docs/validation.md). Zero inside a regular lattice and at
 * rest, so still water is left alone; a particle under the free surface,
 * whose row above is short of neighbours without being surface itself, is
 * pushed toward the surface while the flow moves (Lind et al. shift only
 * along the surface there: not done). The velocity is not changed. Every
 * shift is taken from the positions before any moves: the same bits for any
 * number of threads. */
int particles_shift(mps2p_solver *s, double dt)
{
    /* the correction moved the particles since the list's last check: a pair
     * it brought within re_density must be in it */
    int status = neighbours_refresh(s, dt);
    if (status != MPS2P_OK)
        return status;
    const double re = s->params.re_density * s->l0;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    double *position = s->state.position, *shift = s->scratch;
    const double *velocity = s->state.velocity;
    double fastest2 = 0.0; /* serial: a maximum in any order is the same bits */
    for (size_t i = 0; i < s->count; i++)
        if (s->kind[i] == MPS2P_KIND_FLUID)
            fastest2 = fmax(fastest2, velocity[2 * i] * velocity[2 * i] +
                                          velocity[2 * i + 1] * velocity[2 * i + 1]);
    const double c = s->params.shifting * sqrt(fastest2) * dt;
    PARALLEL_FOR(s->params.threads, UNEQUAL_ROWS,
    for (size_t i = 0; i < s->count; i++) {
        double *d = &shift[2 * i];
        d[0] = d[1] = 0.0;
        if (s->kind[i] != MPS2P_KIND_FLUID || s->on_surface[i])
            continue;
        double sum_r = 0.0, sum_x = 0.0, sum_y = 0.0;
        int count = 0;
        for (size_t k = nl.start[i]; k < nl.start[i + 1]; k++) {
            size_t j = nl.index[k];
            double dx = position[2 * i] - position[2 * j];
            double dy = position[2 * i + 1] - position[2 * j + 1];
            double r2 = dx * dx + dy * dy;
            if (!(r2 < re * re) || r2 <= 0.0)
                continue;
            double r = sqrt(r2);
            sum_r += r;
            count++;
            sum_x += dx / (r2 * r); /* (1 / r^2) e_ji */
            sum_y += dy / (r2 * r);
        }
        if (count == 0)
            continue;
        double mean = sum_r / count;
        double scale = c * mean * mean;
        d[0] = scale * sum_x;
        d[1] = scale * sum_y;
    });
    PARALLEL_FOR(s->params.threads, schedule(static),
    for (size_t i = 0; i < s->count; i++) {
        position[2 * i] += shift[2 * i];
        position[2 * i + 1] += shift[2 * i + 1];
    });
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
