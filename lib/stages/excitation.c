/* Stage excitation (a shaken tank). */
#include "core/core.h"
#include "stages/stages.h"

#include <math.h>

/* Base excitation: the tank accelerates by A sin(2 pi t / T) along x, so in
 * its frame every fluid particle feels -A sin(2 pi t / T); t is the step's
 * start, as for every explicit force. */
int excitation_apply(mps2p_solver *s, double dt)
{
    double *velocity = s->state.velocity;
    const double omega = 2.0 * 3.14159265358979323846 / s->params.excitation_period;
    const double ax = -s->params.excitation_acceleration * sin(omega * s->time);
    for (size_t i = 0; i < s->count; i++)
        if (s->kind[i] == MPS2P_KIND_FLUID)
            velocity[2 * i] += dt * ax;
    return MPS2P_OK;
}
