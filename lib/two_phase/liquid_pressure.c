/* The liquid's side of the two-step pressure (docs/method.md section 2):
 * stage phases_start (the liquid's own number density n^k) and stage
 * liquid_pressure (the liquid PPE, light particles ignored unless joined). */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"
#include "two_phase/two_phase.h"

#include <math.h>
#include <string.h>

/* Number density as the liquid sees it: light particles count only when
 * they have joined the liquid solve. With all (the step's start), also the
 * number density of all particles (number_density_compute's sums, in the
 * same order: the same bits) from the same pass over the pairs. */
static void heavy_number_density(const mps2p_solver *s, double *out, double *all)
{
    two_phase *tp = s->phases; /* its splits change */
    const double re = s->params.re_density * s->l0;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    const double *position = s->state.position;
    /* each pair's weight once, added to both rows (first_above, pair_block_first) */
    PAIR_BLOCKS(s->params.threads, nl.start, s->count,
                all ? &tp->heavy_start_blocks : &tp->heavy_blocks, first, end,
        for (size_t i = first; i < end; i++) {
            double n = 0.0, n_all = 0.0;
            for (size_t k = nl.start[i]; k < nl.start[i + 1] && nl.index[k] < first; k++) {
                size_t j = nl.index[k];
                if (!tp->heavy_mask[j] && !all)
                    continue;
                double dx = position[2 * j] - position[2 * i];
                double dy = position[2 * j + 1] - position[2 * i + 1];
                double w = kernel_weight_squared(dx * dx + dy * dy, re);
                n_all += w;
                if (tp->heavy_mask[j])
                    n += tp->light[j] ? tp->join_weight[j] * w : w;
            }
            out[i] = n;
            if (all)
                all[i] = n_all;
        }
        for (size_t i = first; i < end; i++) {
            double n = out[i], n_all = all ? all[i] : 0.0;
            /* the rows above in this block take i's term if i is seen */
            const size_t below = all || tp->heavy_mask[i] ? row_end_below(nl, i, end) : 0;
            const size_t inside_all = all ? below : 0;
            const size_t inside = tp->heavy_mask[i] ? below : 0;
            for (size_t k = first_above(nl, i); k < nl.start[i + 1]; k++) {
                size_t j = nl.index[k];
                const int to_j = k < inside;
                if (!tp->heavy_mask[j] && !to_j && !all)
                    continue;
                double dx = position[2 * j] - position[2 * i];
                double dy = position[2 * j + 1] - position[2 * i + 1];
                double w = kernel_weight_squared(dx * dx + dy * dy, re);
                if (all) {
                    n_all += w;
                    if (k < inside_all)
                        all[j] += w;
                }
                if (tp->heavy_mask[j])
                    n += tp->light[j] ? tp->join_weight[j] * w : w;
                if (to_j)
                    out[j] += tp->light[i] ? tp->join_weight[i] * w : w;
            }
            out[i] = n;
            if (all)
                all[i] = n_all;
        }
    );
}

int phases_step_start(mps2p_solver *s, double dt)
{
    (void)dt;
    two_phase *tp = s->phases;
    /* n^k of all particles too (the gas's source), in the same pass: the
     * plan leaves stage number_density_start out with two phases */
    heavy_number_density(s, tp->heavy_n_start,
                         s->params.ppe_source != PPE_SOURCE_DENSITY ? s->number_density_start
                                                                    : NULL);
    if (!tp->have_initial) {
        memcpy(tp->heavy_n_initial, tp->heavy_n_start, s->count * sizeof(double));
        tp->have_initial = 1;
    }
    if (s->effect_active[EFFECT_GAS_BUFFER] && !tp->have_gas_top)
        gas_buffer_reference(s);
    return MPS2P_OK;
}


/* n^k as if this step's join weights had held at its start: the ecs and
 * mixed sources take n* - n^k as this step's compression, and a particle
 * joining (its weight 0 in n^k, 1 in n*) would read as a whole particle's
 * compression of its neighbours, a pressure spike (measured: the 8 x 8
 * bubble diverged in 0.02 s). The change is weighed at r*, not r^k. */
static void start_density_follows_join(mps2p_solver *s, const double *old_weight)
{
    two_phase *tp = s->phases;
    const double re = s->params.re_density * s->l0;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    const double *position = s->state.position;
    for (size_t j = 0; j < s->count; j++) {
        double change = tp->light[j] ? tp->join_weight[j] - old_weight[j] : 0.0;
        if (change == 0.0)
            continue;
        for (size_t k = nl.start[j]; k < nl.start[j + 1]; k++) {
            size_t i = nl.index[k];
            double dx = position[2 * j] - position[2 * i];
            double dy = position[2 * j + 1] - position[2 * i + 1];
            tp->heavy_n_start[i] += change * kernel_weight(sqrt(dx * dx + dy * dy), re);
        }
    }
}

static int liquid_system_solve(mps2p_solver *s, double dt, ppe_system *heavy)
{
    int status = pressure_assemble_system(s, dt, heavy);
    return status == MPS2P_OK ? pressure_solve_system(s, heavy) : status;
}

/* The liquid PPE: light particles ignored unless joined, liquid touching the
 * gas is free surface. Requires number_density (all particles) at r* and the
 * sector scan (and the join, with the interface reaction). */
int liquid_pressure_solve(mps2p_solver *s, double dt)
{
    two_phase *tp = s->phases;
    const double threshold = s->params.beta * s->n0_density;
    /* A joining light particle enters the liquid's number density with a
     * weight ramped over join_ramp_time (0 = at once), and leaves it the
     * same way: it usually joins while overlapping liquid particles, and a
     * sudden full weight is a pressure spike. */
    const double ramp = s->params.join_ramp_time > 0.0 ? dt / s->params.join_ramp_time : 1.0;
    double *old_weight = s->scratch;
    memcpy(old_weight, tp->join_weight, s->count * sizeof *old_weight);
    for (size_t i = 0; i < s->count; i++) {
        if (!tp->light[i])
            continue;
        double target = tp->joined[i] ? 1.0 : 0.0;
        tp->join_weight[i] = target > tp->join_weight[i]
                                 ? fmin(target, tp->join_weight[i] + ramp)
                                 : fmax(target, tp->join_weight[i] - ramp);
    }
    for (size_t i = 0; i < s->count; i++) {
        int joined = tp->light[i] && tp->join_weight[i] > 0.0;
        tp->heavy_mask[i] = !tp->light[i] || joined;
        tp->heavy_part[i] = tp->heavy_mask[i] && kind_carries_pressure(s->kind[i]);
        /* A joined light particle stands for liquid volume in the liquid's
         * incompressibility: its source takes the liquid's density. */
        tp->heavy_rho[i] = tp->light[i] ? tp->heavy_density : s->density[i];
    }
    heavy_number_density(s, tp->heavy_n, NULL);
    start_density_follows_join(s, old_weight);
    size_t surface = 0;
    for (size_t i = 0; i < s->count; i++) {
        tp->heavy_surface[i] = tp->heavy_part[i] && tp->heavy_n[i] < threshold;
        surface += tp->heavy_surface[i];
    }
    s->surface_particles = surface;
    /* the liquid's walls and dummies as hydrostatic ghosts, and its surface's
     * pressure (next to air too), as in one phase */
    ppe_system heavy = {.part = tp->heavy_part,
                        .surface = tp->heavy_surface,
                        .n_star = tp->heavy_n,
                        .n_start = tp->heavy_n_start,
                        .density = tp->heavy_rho,
                        .pressure = tp->heavy_pressure,
                        .hydrostatic_ghosts =
                            s->params.wall_ghosts == WALL_GHOSTS_HYDROSTATIC,
                        /* the step's compression in full: this liquid is not shifted,
                         * and unshifted a lower gain speeds the spray that opens holes
                         * in the gas (docs/two-phase.md) */
                        .step_gain = 1.0,
                        .surface_diagonal = surface_diagonal_of(s)};
    /* With threads, the gas's number density and free surface (which read
     * only what is set above) are prepared beside this solve while the
     * liquid's system (last step's size) is too small to share between
     * threads: about 450 rows in the paper's case (docs/performance.md) */
    int status = MPS2P_OK;
    tp->gas_prepared = 0;
    if (team_size(s->params.threads) > 1 && tp->heavy_unknowns < REDUCTION_BLOCK)
        SIDE_BY_SIDE(s->params.threads, status = liquid_system_solve(s, dt, &heavy),
                     gas_pressure_prepare(s));
    else
        status = liquid_system_solve(s, dt, &heavy);
    if (status != MPS2P_OK)
        tp->gas_prepared = 0; /* a failed step: its next try prepares afresh */
    s->ppe_unknowns = tp->heavy_unknowns = heavy.unknowns;
    s->ppe_iterations = tp->heavy_iterations = heavy.iterations;
    s->ppe_iterations_total += heavy.iterations;
    s->ppe_residual = heavy.residual;
    return status;
}
