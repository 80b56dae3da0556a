/* Time step: fixed, or adaptive under the CFL, viscous diffusion and gravity
 * limits. The gravity limit dt <= gravity_number sqrt(l0 / |g|) is the
 * corrected scheme's: water at rest loses its lattice above about 0.04
 * sqrt(l0 / |g|) (measured at l0 = 0.01 and 0.02 m, docs/validation.md),
 * whatever the speeds, which are near 0 there. */
#include "core/core.h"
#include "stages/stages.h"

#include <math.h>
#include <stdio.h>

double timestep_choose(const mps2p_solver *s)
{
    if (s->params.dt > 0.0)
        return s->params.dt;
    double dt = s->dt_max;
    double max_speed2 = 0.0, max_viscosity = 0.0;
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        const double *u = &s->state.velocity[2 * i];
        max_speed2 = fmax(max_speed2, u[0] * u[0] + u[1] * u[1]);
        max_viscosity = fmax(max_viscosity, s->viscosity[i]);
    }
    if (max_speed2 > 0.0)
        dt = fmin(dt, s->params.cfl * s->l0 / sqrt(max_speed2));
    if (!s->effect_active[EFFECT_VISCOSITY])
        max_viscosity = 0.0;
    if (s->effect_active[EFFECT_TURBULENCE]) /* the eddy viscosity of the last step */
        max_viscosity += s->eddy_viscosity_max;
    if (max_viscosity > 0.0)
        dt = fmin(dt, s->params.diffusion_number * s->l0 * s->l0 / max_viscosity);
    const double g = hypot(s->params.gravity[0], s->params.gravity[1]);
    if (s->params.gravity_number > 0.0 && g > 0.0 && s->effect_active[EFFECT_GRAVITY])
        dt = fmin(dt, s->params.gravity_number * sqrt(s->l0 / g));
    return dt;
}

void timestep_explain(const mps2p_solver *s, char *out, size_t size)
{
    if (s->params.dt > 0.0) {
        snprintf(out, size, "the fixed dt (parameter dt)");
        return;
    }
    double max_speed2 = 0.0, max_viscosity = 0.0;
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        const double *u = &s->state.velocity[2 * i];
        max_speed2 = fmax(max_speed2, u[0] * u[0] + u[1] * u[1]);
        if (s->effect_active[EFFECT_VISCOSITY])
            max_viscosity = fmax(max_viscosity, s->viscosity[i]);
    }
    if (s->effect_active[EFFECT_TURBULENCE])
        max_viscosity += s->eddy_viscosity_max;
    double cfl = max_speed2 > 0.0 ? s->params.cfl * s->l0 / sqrt(max_speed2) : INFINITY;
    double diffusion = max_viscosity > 0.0
                           ? s->params.diffusion_number * s->l0 * s->l0 / max_viscosity
                           : INFINITY;
    if (diffusion <= cfl && diffusion <= s->dt_max)
        snprintf(out, size, "viscous diffusion: diffusion_number l0^2 / nu with nu = %g m^2/s",
                 max_viscosity);
    else if (cfl <= s->dt_max)
        snprintf(out, size, "the CFL limit: cfl l0 / max speed with max speed %g m/s",
                 sqrt(max_speed2));
    else
        snprintf(out, size, "dt_max");
}
