/* Stage gravity: u* += dt g on fluid particles. */
#include "core/core.h"
#include "stages/stages.h"

int gravity_apply(mps2p_solver *s, double dt)
{
    double *velocity = s->state.velocity;
    const double gx = dt * s->params.gravity[0], gy = dt * s->params.gravity[1];
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        velocity[2 * i] += gx;
        velocity[2 * i + 1] += gy;
    }
    return MPS2P_OK;
}
