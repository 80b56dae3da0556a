/* Stage viscosity: u* += dt nu lap u (walls and dummies at rest: no-slip),
 * evaluated from the velocities at the start of the step. */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"


int viscosity_apply(mps2p_solver *s, double dt)
{
    double *velocity = s->state.velocity;
    double *acceleration = s->scratch;
    /* Each particle writes only its own entries: any split among threads
     * gives the same bits (so do the other particle loops). */
    PARALLEL_FOR(s->params.threads, schedule(static),
    for (size_t i = 0; i < s->count; i++) {
        double *a = &acceleration[2 * i];
        a[0] = a[1] = 0.0;
        if (s->kind[i] != MPS2P_KIND_FLUID || s->viscosity[i] <= 0.0)
            continue;
        /* only the neighbours of the mask, if another part sets one (the
         * two phases: the liquid ignores the gas) */
        const unsigned char *mask =
            s->viscosity_mask && !s->viscosity_unmasked[i] ? s->viscosity_mask : NULL;
        laplacian_masked_at(s, i, velocity, 2, mask, a);
        a[0] *= s->viscosity[i];
        a[1] *= s->viscosity[i];
    });
    PARALLEL_FOR(s->params.threads, schedule(static),
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        velocity[2 * i] += dt * acceleration[2 * i];
        velocity[2 * i + 1] += dt * acceleration[2 * i + 1];
    });
    return MPS2P_OK;
}
