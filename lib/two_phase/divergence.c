/* Stage gas_divergence_check. */
#include "core/core.h"
#include "stages/stages.h"
#include "two_phase/two_phase.h"

#include <math.h>

/* The gas's own failure (docs/method.md section 2): a gas particle squeezed by
 * the liquid reaches a gas pressure far above any hydrostatic or dynamic
 * value. Reported with its place and how enclosed it was. */
int phases_divergence_check(mps2p_solver *s, double dt)
{
    const two_phase *tp = s->phases;
    const double jump = s->params.displacement_limit * s->l0;
    const double *before = s->before_step->state.position;
    for (size_t i = 0; i < s->count; i++) {
        if (!light_in_run(s, i))
            continue;
        double moved = hypot(s->state.position[2 * i] - before[2 * i],
                             s->state.position[2 * i + 1] - before[2 * i + 1]);
        if (jump > 0.0 && moved > jump)
            return diverged_at(s, i, fail(s->error, MPS2P_ERR_DIVERGED,
                        "diverged at step %llu, t = %.6g s: gas particle %zu (%s) jumped %g l0 "
                        "in one step, to (%g, %g) (limit %g l0); gas pressure %g Pa, liquid "
                        "pressure %g Pa, n/n0 = %.3f, %s, %s, %s",
                        (unsigned long long)s->steps + 1, s->time + dt, i,
                        s->fluids[s->fluid_id[i]].name, moved / s->l0, s->state.position[2 * i],
                        s->state.position[2 * i + 1],
                        s->params.displacement_limit, tp->gas_pressure[i],
                        tp->heavy_pressure[i], s->number_density[i] / s->n0_density,
                        tp->enclosed[i] ? "enclosed by liquid" : "not enclosed",
                        tp->triggered[i] ? "triggered" : "not triggered",
                        tp->joined[i] ? "joined the liquid solve" : "gas"));
        if (!(fabs(tp->gas_pressure[i]) > tp->gas_pressure_limit))
            continue;
        return diverged_at(s, i, fail(s->error, MPS2P_ERR_DIVERGED,
                    "diverged at step %llu, t = %.6g s: gas particle %zu (%s) at (%g, %g) "
                    "has gas pressure %g Pa, beyond the limit %g Pa (n/n0 = %.3f, %s, %s): "
                    "the liquid is closing in on it",
                    (unsigned long long)s->steps + 1, s->time + dt, i,
                    s->fluids[s->fluid_id[i]].name, s->state.position[2 * i],
                    s->state.position[2 * i + 1], tp->gas_pressure[i], tp->gas_pressure_limit,
                    s->number_density[i] / s->n0_density,
                    tp->enclosed[i] ? "enclosed by liquid" : "not enclosed",
                    tp->triggered[i] ? "triggered" : "not triggered"));
    }
    return MPS2P_OK;
}
