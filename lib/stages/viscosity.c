/* Stage viscosity: u* += dt nu lap u (walls and dummies at rest: no-slip),
 * evaluated from the velocities at the start of the step. */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"

#include <string.h>

/* The rows viscosity_apply computes: fluid with a viscosity. */
static int viscous(const mps2p_solver *s, size_t i)
{
    return s->kind[i] == MPS2P_KIND_FLUID && s->viscosity[i] > 0.0;
}

/* Only the neighbours of the mask, if another part sets one (the two
 * phases: the liquid ignores the gas). */
static const unsigned char *row_mask(const mps2p_solver *s, size_t i)
{
    return s->viscosity_mask && !s->viscosity_unmasked[i] ? s->viscosity_mask : NULL;
}

/* Whether row i takes the term of neighbour j. */
static int takes_term(const mps2p_solver *s, size_t i, size_t j)
{
    const unsigned char *mask = row_mask(s, i);
    return viscous(s, i) && (!mask || mask[j]);
}

/* The MPS Laplacian of the velocity of each viscous row (laplacian_masked_at's
 * sums), times its viscosity, with each pair's weight computed once, from
 * the row of its lower index, and its term added to both rows, in blocks of
 * rows on the threads (first_above and pair_block_first in numerics.h: the
 * same bits as row by row). */
static void laplacians_pairwise(mps2p_solver *s, const double *velocity, double *acceleration)
{
    const double re = s->params.re_laplacian * s->l0;
    const neighbour_list *nl = &s->neighbours;
    const neighbour_rows rows = {nl->start, nl->index};
    const double *position = s->state.position;
    const double factor = 2.0 * 2 / (s->lambda * s->n0_laplacian);
    /* row i's position, velocity and sums in locals: the stores into the
     * sums could be into the positions or velocities, as far as the
     * compiler knows, and it would load them again at every pair */
    PAIR_BLOCKS(s->params.threads, nl->start, s->count, &s->viscosity_blocks, first, end,
        for (size_t i = first; i < end; i++) {
            const double xi = position[2 * i], yi = position[2 * i + 1];
            const double ui = velocity[2 * i], vi = velocity[2 * i + 1];
            double a0 = 0.0, a1 = 0.0;
            for (size_t k = nl->start[i]; k < nl->start[i + 1] && nl->index[k] < first; k++) {
                size_t j = nl->index[k];
                if (!takes_term(s, i, j))
                    continue;
                double dx = position[2 * j] - xi;
                double dy = position[2 * j + 1] - yi;
                double w = kernel_weight_squared(dx * dx + dy * dy, re);
                if (w == 0.0)
                    continue;
                a0 += (velocity[2 * j] - ui) * w;
                a1 += (velocity[2 * j + 1] - vi) * w;
            }
            acceleration[2 * i] = a0;
            acceleration[2 * i + 1] = a1;
        }
        for (size_t i = first; i < end; i++) {
            const int row_i = viscous(s, i);
            const unsigned char *mask_i = row_mask(s, i);
            const size_t inside = row_end_below(rows, i, end);
            const double xi = position[2 * i], yi = position[2 * i + 1];
            const double ui = velocity[2 * i], vi = velocity[2 * i + 1];
            double a0 = acceleration[2 * i], a1 = acceleration[2 * i + 1];
            for (size_t k = first_above(rows, i); k < nl->start[i + 1]; k++) {
                size_t j = nl->index[k];
                int to_i = row_i && (!mask_i || mask_i[j]);
                int to_j = k < inside && takes_term(s, j, i);
                if (!to_i && !to_j)
                    continue;
                double dx = position[2 * j] - xi;
                double dy = position[2 * j + 1] - yi;
                double w = kernel_weight_squared(dx * dx + dy * dy, re);
                if (w == 0.0)
                    continue;
                const double uj = velocity[2 * j], vj = velocity[2 * j + 1];
                if (to_i) {
                    a0 += (uj - ui) * w;
                    a1 += (vj - vi) * w;
                }
                if (to_j) {
                    acceleration[2 * j] += (ui - uj) * w;
                    acceleration[2 * j + 1] += (vi - vj) * w;
                }
            }
            if (row_i) {
                a0 *= factor;
                a1 *= factor;
                a0 *= s->viscosity[i];
                a1 *= s->viscosity[i];
            }
            acceleration[2 * i] = a0;
            acceleration[2 * i + 1] = a1;
        }
    );
}

int viscosity_apply(mps2p_solver *s, double dt)
{
    double *velocity = s->state.velocity;
    double *acceleration = s->scratch;
    laplacians_pairwise(s, velocity, acceleration);
    PARALLEL_FOR(s->params.threads, schedule(static),
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        velocity[2 * i] += dt * acceleration[2 * i];
        velocity[2 * i + 1] += dt * acceleration[2 * i + 1];
    });
    return MPS2P_OK;
}
