/* Particle number density n_i = sum_j w(|r_ij|) with the density radius,
 * for the stages number_density_start (n^k, for the mixed and ecs PPE
 * sources) and number_density (n* at r*). */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"

#include <math.h>
#include <string.h>

/* The density weight of the pair (i, j): the same bits from either row. */
static inline double pair_weight(const double *position, size_t i, size_t j, double re)
{
    double dx = position[2 * j] - position[2 * i];
    double dy = position[2 * j + 1] - position[2 * i + 1];
    return kernel_weight_squared(dx * dx + dy * dy, re);
}

void number_density_compute(mps2p_solver *s, double *out)
{
    const double re = s->params.re_density * s->l0;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    const double *position = s->state.position;
    /* each pair's weight once, added to both rows (first_above, pair_block_first) */
    PAIR_BLOCKS(s->params.threads, nl.start, s->count, &s->density_blocks, first, end,
        for (size_t i = first; i < end; i++) {
            double n = 0.0;
            for (size_t k = nl.start[i]; k < nl.start[i + 1] && nl.index[k] < first; k++)
                n += pair_weight(position, i, nl.index[k], re);
            out[i] = n;
        }
        for (size_t i = first; i < end; i++) {
            double n = out[i];
            const size_t inside = row_end_below(nl, i, end);
            size_t k = first_above(nl, i);
            for (; k < inside; k++) {
                size_t j = nl.index[k];
                double w = pair_weight(position, i, j, re);
                n += w;
                out[j] += w;
            }
            for (; k < nl.start[i + 1]; k++)
                n += pair_weight(position, i, nl.index[k], re);
            out[i] = n;
        }
    );
}

int number_density_start(mps2p_solver *s, double dt)
{
    (void)dt;
    number_density_compute(s, s->number_density_start);
    return MPS2P_OK;
}

int number_density_star(mps2p_solver *s, double dt)
{
    (void)dt;
    number_density_compute(s, s->number_density);
    return MPS2P_OK;
}
