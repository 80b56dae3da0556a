/* Correction: u' = -(dt / rho) <grad p>, u = u* + u', r = r* + dt u', with
 * Koshizuka and Oka's gradient: p^_i = min(p_i, min_j p_j) as reference, which
 * keeps the pair forces repulsive. */
#include "internal.h"

void pressure_correct(mps2p_solver *s, double dt)
{
    double *position = s->state.position, *velocity = s->state.velocity;
    const double *pressure = s->state.pressure;
    double *change = s->scratch;
    for (size_t i = 0; i < s->count; i++) {
        double *du = &change[2 * i];
        du[0] = du[1] = 0.0;
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        double gradient[2];
        gradient_at(s, i, pressure, minimum_around(s, i, pressure), gradient);
        du[0] = -dt / s->density[i] * gradient[0];
        du[1] = -dt / s->density[i] * gradient[1];
    }
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        velocity[2 * i] += change[2 * i];
        velocity[2 * i + 1] += change[2 * i + 1];
        position[2 * i] += dt * change[2 * i];
        position[2 * i + 1] += dt * change[2 * i + 1];
    }
}
