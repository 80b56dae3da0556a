/* Stage two_phase_correction: the correction per phase, and within it the
 * reaction of the forms pair, push and continuity (interface_reaction.c). */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"
#include "two_phase/two_phase.h"

#include <math.h>

/* A light particle moved by the liquid's pressure: volume, or drift with
 * drift_liquid_gradient, for as long as it has a weight in the liquid. */
int moves_with_liquid(const mps2p_solver *s, size_t i)
{
    const two_phase *tp = s->phases;
    int kind = s->params.interface_reaction;
    return tp->light[i] && tp->join_weight[i] > 0.0 &&
           (kind == REACTION_VOLUME ||
            (kind == REACTION_DRIFT && s->params.drift_liquid_gradient != 0.0));
}

/* Continuity: a gas particle's inertia, blended by the liquid fraction f of
 * its fluid neighbours within re (kernel-weighted) between the gas's own
 * density (f = 0) and the added-mass density rho_eff (f = 1, a small bubble
 * in the liquid: it then rises with (rho_l - rho_a)/(rho_a + C_m rho_l) g in
 * hydrostatic liquid). Bounds the acceleration that the liquid's pressure,
 * now seen by the gas, can give a gas particle among liquid ones. */
static double continuity_density(const mps2p_solver *s, size_t i, double rho_eff)
{
    const two_phase *tp = s->phases;
    const double re = s->params.re_density * s->l0, re2 = re * re;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    const double *r = s->state.position;
    double heavy = 0.0, all = 0.0;
    for (size_t k = nl.start[i]; k < nl.start[i + 1]; k++) {
        size_t j = nl.index[k];
        if (s->kind[j] != MPS2P_KIND_FLUID)
            continue;
        double dx = r[2 * j] - r[2 * i], dy = r[2 * j + 1] - r[2 * i + 1];
        double d2 = dx * dx + dy * dy;
        if (d2 >= re2 || d2 <= 0.0)
            continue;
        double w = kernel_weight(sqrt(d2), re);
        all += w;
        if (!tp->light[j])
            heavy += w;
    }
    double f = all > 0.0 ? heavy / all : 0.0;
    return tp->light_density + f * (rho_eff - tp->light_density);
}

/* Correction per phase, over the particles each phase sees:
 *   liquid: the liquid pressure over liquid, walls (and joined light ones),
 *     with the single phase's gradient (option pressure_gradient; its dry
 *     walls and dummies as ghosts with wall_ghosts): a liquid under air is
 *     as quiet as one alone (docs/two-phase.md, the ladder's first rung);
 *   light particle moved by the gas: Koshizuka and Oka's gradient of the gas
 *     pressure over every particle, rho_a;
 *   light particle joined by the volume reaction: the liquid pressure over
 *   the liquid's particles, divided by the added-mass density
 *   rho_eff = (rho_a + C_m rho_l) / (1 + C_m). That is the exact acceleration
 *   of a small bubble in a liquid of pressure field p: (rho_a + C_m rho_l)
 *   dv/dt = (1 + C_m)(-grad p) + (rho_a + C_m rho_l) g; in hydrostatic liquid
 *   it rises with (rho_l - rho_a) / (rho_a + C_m rho_l) g (C_m = 1: a 2D
 *   cylinder; 0.5: a sphere). */
int phases_correct(mps2p_solver *s, double dt)
{
    two_phase *tp = s->phases;
    double *position = s->state.position, *velocity = s->state.velocity;
    double *change = s->scratch;
    const double cm = s->params.bubble_added_mass;
    const double rho_eff = (tp->light_density + cm * tp->heavy_density) / (1.0 + cm);
    /* the improved model's guard; the conventional model is the paper's */
    const double cap = tp->improved ? s->params.gas_correction_limit * s->l0 / dt : 0.0;
    size_t capped = 0;
    for (size_t i = 0; i < s->count; i++) {
        double *du = &change[2 * i];
        du[0] = du[1] = 0.0;
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        double gradient[2], rho = s->density[i];
        if (!tp->light[i]) {
            pressure_gradient_at(s, i, tp->heavy_pressure, tp->heavy_part, tp->heavy_surface,
                                 gradient);
        } else if (moves_with_liquid(s, i)) {
            pressure_gradient_at(s, i, tp->heavy_pressure, tp->heavy_part, tp->heavy_surface,
                                 gradient);
            /* drift: moved as liquid, then the slip below */
            rho = s->params.interface_reaction == REACTION_VOLUME ? rho_eff : tp->heavy_density;
        } else {
            gradient_masked_at(s, i, tp->gas_pressure,
                               minimum_masked_around(s, i, tp->gas_pressure, tp->gas_part),
                               tp->gas_part, gradient);
            if (s->params.interface_reaction == REACTION_CONTINUITY)
                rho = continuity_density(s, i, rho_eff);
        }
        du[0] = -dt / rho * gradient[0];
        du[1] = -dt / rho * gradient[1];
        if (tp->light[i] && !moves_with_liquid(s, i) && cap > 0.0) {
            double size = hypot(du[0], du[1]);
            if (size > cap) {
                du[0] *= cap / size;
                du[1] *= cap / size;
                capped++;
            }
        }
    }
    tp->capped_count = capped;
    if (tp->improved) /* pair, push and continuity act inside the correction */
        interface_reaction_apply(s, dt, change);
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        velocity[2 * i] += change[2 * i];
        velocity[2 * i + 1] += change[2 * i + 1];
        position[2 * i] += dt * change[2 * i];
        position[2 * i + 1] += dt * change[2 * i + 1];
    }
    return MPS2P_OK;
}
