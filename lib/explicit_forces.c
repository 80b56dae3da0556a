/* Explicit part of the step: u* = u + dt (nu lap u + g), r* = r + dt u*.
 * Walls and dummies have zero velocity in the Laplacian: no-slip. */
#include "internal.h"

void explicit_forces(mps2p_solver *s, double dt)
{
    double *position = s->state.position, *velocity = s->state.velocity;
    double *acceleration = s->scratch;
    for (size_t i = 0; i < s->count; i++) {
        double *a = &acceleration[2 * i];
        a[0] = a[1] = 0.0;
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        if (s->viscosity[i] > 0.0) {
            laplacian_at(s, i, velocity, 2, a);
            a[0] *= s->viscosity[i];
            a[1] *= s->viscosity[i];
        }
        a[0] += s->params.gravity[0];
        a[1] += s->params.gravity[1];
    }
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        velocity[2 * i] += dt * acceleration[2 * i];
        velocity[2 * i + 1] += dt * acceleration[2 * i + 1];
        position[2 * i] += dt * velocity[2 * i];
        position[2 * i + 1] += dt * velocity[2 * i + 1];
    }
}
