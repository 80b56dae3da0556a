/* Stage advection: r* = r + dt u* on fluid particles; the neighbour list is
 * brought up to date after it. */
#include "core/core.h"
#include "stages/stages.h"

int advect(mps2p_solver *s, double dt)
{
    double *position = s->state.position;
    const double *velocity = s->state.velocity;
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        position[2 * i] += dt * velocity[2 * i];
        position[2 * i + 1] += dt * velocity[2 * i + 1];
    }
    return MPS2P_OK;
}
