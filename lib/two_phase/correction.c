/* Stage two_phase_correction: the correction per phase. */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"
#include "two_phase/two_phase.h"

#include <math.h>

/* A light particle moved by the liquid's pressure: a drift bubble, for as
 * long as it has a weight in the liquid. */
int moves_with_liquid(const mps2p_solver *s, size_t i)
{
    const two_phase *tp = s->phases;
    return tp->light[i] && tp->join_weight[i] > 0.0;
}

/* Correction per phase, over the particles each phase sees:
 *   liquid: the liquid pressure over liquid, walls (and joined light ones),
 *     with the single phase's gradient (option pressure_gradient; its dry
 *     walls and dummies as ghosts with wall_ghosts): a liquid under air is
 *     as quiet as one alone (docs/two-phase.md, the ladder's first rung);
 *   drift bubble (a joined light particle): as the liquid, with the
 *     liquid's density, then the slip of stage interface_drift (its dry-wall
 *     ghosts take its own density, rho_a, where the liquid's PPE gave its
 *     row rho_l: inconsistent, but the consistent choice made the 8 x 8
 *     bubble diverge at 0.18 s; docs/two-phase.md); moved by
 *     its own gas pressure instead (rho_a), it is pushed about by the gas
 *     and does not rise (the ladder's third rung);
 *   light particle moved by the gas: Koshizuka and Oka's gradient of the gas
 *     pressure over every particle, rho_a, its change capped at
 *     gas_correction_limit in the improved model. */
int phases_correct(mps2p_solver *s, double dt)
{
    two_phase *tp = s->phases;
    double *change = s->scratch;
    /* the improved model's guard; the conventional model is the paper's */
    const double cap = tp->improved ? s->params.gas_correction_limit * s->l0 / dt : 0.0;
    /* 0 where the square is not finite: then hypot decides every time */
    const double cap2_within = isfinite(cap * cap) ? cap * cap * (1.0 - 1e-12) : 0.0;
    size_t capped = 0;
    PARALLEL_FOR(s->params.threads, UNEQUAL_ROWS reduction(+ : capped),
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
            rho = tp->heavy_density; /* moved as liquid, then the drift's slip */
        } else {
            gradient_masked_at(s, i, tp->gas_pressure,
                               minimum_masked_around(s, i, tp->gas_pressure, tp->gas_part),
                               tp->gas_part, gradient);
        }
        du[0] = -dt / rho * gradient[0];
        du[1] = -dt / rho * gradient[1];
        /* hypot (slow) only near or past the cap: below the squared bound the
         * change is surely within it */
        if (tp->light[i] && !moves_with_liquid(s, i) && cap > 0.0 &&
            !(du[0] * du[0] + du[1] * du[1] <= cap2_within)) {
            double size = hypot(du[0], du[1]);
            if (size > cap) {
                du[0] *= cap / size;
                du[1] *= cap / size;
                capped++;
            }
        }
    });
    tp->capped_count = capped;
    correction_apply(s, change, dt);
    return MPS2P_OK;
}
