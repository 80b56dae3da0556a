/* Effect gas_buffer: the gas's top boundary (docs/two-phase.md, rung 6).
 *
 * An open top where a gas particle flung up at an impact flies on until it
 * leaves the tank is no boundary condition. Below the gas's top at the
 * first step (the highest light particle, against gravity), a layer
 * gas_buffer_depth l0 deep damps the velocity of the light particles the gas
 * moves, at a rate growing as the square of the depth into the layer to
 * gas_buffer_rate at its top and above: a damping (sponge) zone, as particle
 * codes use to absorb waves. A particle entering it at speed v stops within
 * the layer when v < gas_buffer_rate depth / 3 (8.3 m/s at the defaults,
 * l0 = 0.01 m) and then sinks back under gravity. Drift bubbles (moved with
 * the liquid) and the liquid are left alone: the layer is the gas's. */
#include "core/core.h"
#include "two_phase/two_phase.h"

#include <math.h>

void gas_buffer_reference(mps2p_solver *s)
{
    two_phase *tp = s->phases;
    double up[2];
    if (!gravity_up(s, up))
        return;
    const double *r = s->state.position;
    double top = -INFINITY;
    for (size_t i = 0; i < s->count; i++)
        if (light_in_run(s, i))
            top = fmax(top, r[2 * i] * up[0] + r[2 * i + 1] * up[1]);
    if (isfinite(top)) {
        tp->gas_top = top;
        tp->have_gas_top = 1;
    }
}

int gas_buffer_apply(mps2p_solver *s, double dt)
{
    two_phase *tp = s->phases;
    double up[2];
    tp->buffered_count = 0;
    if (!tp->have_gas_top || !gravity_up(s, up))
        return MPS2P_OK;
    const double depth = s->params.gas_buffer_depth * s->l0;
    const double bottom = tp->gas_top - depth, rate = s->params.gas_buffer_rate;
    double *r = s->state.position, *u = s->state.velocity;
    size_t damped = 0;
    for (size_t i = 0; i < s->count; i++) {
        if (!light_in_run(s, i) || moves_with_liquid(s, i))
            continue;
        double into = r[2 * i] * up[0] + r[2 * i + 1] * up[1] - bottom;
        if (!(into > 0.0))
            continue;
        double x = fmin(1.0, into / depth);
        /* implicit in the damping, stable at any dt */
        double keep = 1.0 / (1.0 + dt * rate * x * x);
        for (int d = 0; d < 2; d++) {
            double du = (keep - 1.0) * u[2 * i + d];
            u[2 * i + d] += du;
            r[2 * i + d] += dt * du; /* the step moved it with the undamped velocity */
        }
        damped++;
    }
    tp->buffered_count = damped;
    return MPS2P_OK;
}
