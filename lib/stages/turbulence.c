/* Turbulence: a sub-particle-scale eddy viscosity (Smagorinsky), the
 * eddy-viscosity term of the paper's momentum equation (Gotoh, Shibahara and
 * Sakai's SPS model for MPS):
 *   nu_t,i = (Cs l0)^2 |S_i|,  |S| = sqrt(2 S:S),  S = (grad u + grad u^T) / 2,
 * grad u by the MPS gradient with u_i as reference over fluid and wall
 * neighbours (walls at rest: the no-slip shear counts), then
 *   u* += dt nu_t,i lap u
 * on the velocities the viscosity stage left (operator splitting: the
 * molecular and the eddy part one after the other). */
#include "core/core.h"
#include "stages/stages.h"

#include <math.h>

int turbulence_apply(mps2p_solver *s, double dt)
{
    double *velocity = s->state.velocity;
    double *eddy = s->eddy_viscosity, *change = s->scratch;
    const double length = s->params.smagorinsky_constant * s->l0;
    double largest = 0.0;
    for (size_t i = 0; i < s->count; i++) {
        change[2 * i] = change[2 * i + 1] = 0.0;
        eddy[i] = 0.0;
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        double gu[2], gv[2], component[2];
        /* gradients of the two velocity components, each as a scalar field */
        gradient_at_component(s, i, velocity, 0, gu);
        gradient_at_component(s, i, velocity, 1, gv);
        double sxx = gu[0], syy = gv[1], sxy = 0.5 * (gu[1] + gv[0]);
        double strain = sqrt(2.0 * (sxx * sxx + syy * syy + 2.0 * sxy * sxy));
        eddy[i] = length * length * strain;
        largest = fmax(largest, eddy[i]);
        if (eddy[i] == 0.0)
            continue;
        laplacian_at(s, i, velocity, 2, component);
        change[2 * i] = dt * eddy[i] * component[0];
        change[2 * i + 1] = dt * eddy[i] * component[1];
    }
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        velocity[2 * i] += change[2 * i];
        velocity[2 * i + 1] += change[2 * i + 1];
    }
    s->eddy_viscosity_max = largest;
    return MPS2P_OK;
}
