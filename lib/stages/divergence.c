/* Divergence detection after a step: non-finite values, particles leaving
 * the domain, pressure spikes and jumps of more than displacement_limit. */
#include "core/core.h"
#include "stages/stages.h"

#include <math.h>

static const char *describe(const mps2p_solver *s, size_t i)
{
    if (s->kind[i] == MPS2P_KIND_FLUID)
        return s->fluids[s->fluid_id[i]].name;
    return s->kind[i] == MPS2P_KIND_WALL ? "wall" : "dummy wall";
}

/* Remembers where a divergence was found (statistic diverged_particle). */
int diverged_at(mps2p_solver *s, size_t i, int status)
{
    s->diverged_particle = (long)i;
    return status;
}

int divergence_check(mps2p_solver *s, double dt)
{
    const double *r = s->state.position, *u = s->state.velocity, *p = s->state.pressure;
    const double *before = s->before_step->state.position;
    const double jump = s->params.displacement_limit * s->l0;
    const double t = s->time + dt;
    const unsigned long long step = (unsigned long long)s->steps + 1;
    for (size_t i = 0; i < s->count; i++) {
        const double x = r[2 * i], y = r[2 * i + 1];
        if (!isfinite(x) || !isfinite(y) || !isfinite(u[2 * i]) || !isfinite(u[2 * i + 1]) ||
            !isfinite(p[i]))
            return diverged_at(s, i, fail(s->error, MPS2P_ERR_DIVERGED,
                        "diverged at step %llu, t = %.6g s: particle %zu (%s) has a "
                        "non-finite value (position (%g, %g), velocity (%g, %g), p = %g)",
                        step, t, i, describe(s, i), x, y, u[2 * i], u[2 * i + 1], p[i]));
        if (x < s->domain[0] || x > s->domain[2] || y < s->domain[1] || y > s->domain[3])
            return diverged_at(s, i, fail(s->error, MPS2P_ERR_DIVERGED,
                        "diverged at step %llu, t = %.6g s: particle %zu (%s) left the "
                        "domain [%g, %g] x [%g, %g] at (%g, %g), speed %g m/s",
                        step, t, i, describe(s, i), s->domain[0], s->domain[2],
                        s->domain[1], s->domain[3], x, y, hypot(u[2 * i], u[2 * i + 1])));
        if (fabs(p[i]) > s->pressure_limit)
            return diverged_at(s, i, fail(s->error, MPS2P_ERR_DIVERGED,
                        "diverged at step %llu, t = %.6g s: particle %zu (%s) at (%g, %g) "
                        "has pressure %g Pa, beyond the limit %g Pa",
                        step, t, i, describe(s, i), x, y, p[i], s->pressure_limit));
        double moved = hypot(x - before[2 * i], y - before[2 * i + 1]);
        if (jump > 0.0 && moved > jump)
            return diverged_at(s, i, fail(s->error, MPS2P_ERR_DIVERGED,
                        "diverged at step %llu, t = %.6g s: particle %zu (%s) jumped %g l0 "
                        "in one step, to (%g, %g) (limit %g l0)",
                        step, t, i, describe(s, i), moved / s->l0, x, y,
                        s->params.displacement_limit));
    }
    return MPS2P_OK;
}
