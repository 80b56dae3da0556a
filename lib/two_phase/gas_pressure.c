/* The light fluid's pressure (docs/method.md section 2, step 2): one PPE over the
 * light particles with every other non-dummy particle (liquid, joined light
 * particles, walls) a fixed wall of gas density: it carries a pressure
 * unknown with the gas's density in its source, and it is not moved by the
 * result. Free surface where the number density of all particles is below
 * beta n0 (the top of the air). */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"
#include "two_phase/two_phase.h"

#include <math.h>

/* Number density for the gas with each liquid particle weighted by the
 * volume it stands for, n0 / n_liquid in [1, 2]: a sparse liquid sheet
 * (n_liquid < n0, common at MPS free surfaces) then does not look like room
 * for gas between its particles. */
static const double *gas_number_density(mps2p_solver *s)
{
    two_phase *tp = s->phases;
    if (s->params.gas_liquid_volume == 0.0 || !tp->improved) /* the paper's conventional */
        return s->number_density;
    const double re = s->params.re_density * s->l0, n0 = s->n0_density;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    const double *position = s->state.position;
    PARALLEL_FOR(s->params.threads, schedule(static),
    for (size_t i = 0; i < s->count; i++) {
        double n = 0.0;
        for (size_t k = nl.start[i]; k < nl.start[i + 1]; k++) {
            size_t j = nl.index[k];
            double dx = position[2 * j] - position[2 * i];
            double dy = position[2 * j + 1] - position[2 * i + 1];
            double w = kernel_weight(sqrt(dx * dx + dy * dy), re);
            if (s->kind[j] == MPS2P_KIND_FLUID && !tp->light[j] && tp->heavy_n[j] > 0.0) {
                /* 1: against n0; 2: against the particle's own initial
                 * liquid number density (no spike at the start) */
                double reference = s->params.gas_liquid_volume == 2.0
                                       ? fmin(n0, tp->heavy_n_initial[j]) : n0;
                w *= fmin(2.0, fmax(1.0, reference / tp->heavy_n[j]));
            }
            n += w;
        }
        tp->gas_n[i] = n;
    });
    return tp->gas_n;
}

int gas_pressure_solve(mps2p_solver *s, double dt)
{
    two_phase *tp = s->phases;
    const double threshold = s->params.beta * s->n0_density;
    const double *n_gas = gas_number_density(s);
    for (size_t i = 0; i < s->count; i++) {
        tp->gas_part[i] = s->kind[i] != MPS2P_KIND_DUMMY;
        tp->gas_surface[i] = tp->gas_part[i] && n_gas[i] < threshold;
    }
    ppe_system gas = {.part = tp->gas_part,
                      .surface = tp->gas_surface,
                      .n_star = n_gas,
                      .n_start = s->number_density_start,
                      .density = tp->gas_rho,
                      .pressure = tp->gas_pressure,
                      .tolerance = s->params.gas_cg_tolerance,
                      /* n* is the liquid-weighted gas_n, n^k the plain number
                       * density: their difference (the ecs and mixed sources)
                       * is not the gas's compression */
                      .density_source = 1};
    int status = pressure_assemble_system(s, dt, &gas);
    if (status == MPS2P_OK)
        status = pressure_solve_system(s, &gas);
    tp->gas_unknowns = gas.unknowns;
    tp->gas_iterations = gas.iterations;
    if (status == MPS2P_OK)
        phases_pressure_combine(s);
    return status;
}

/* After both solves, the state's pressure: the gas's for light particles
 * moved by it, the liquid's for the others. */
void phases_pressure_combine(mps2p_solver *s)
{
    two_phase *tp = s->phases;
    double gas_max = 0.0;
    for (size_t i = 0; i < s->count; i++) {
        int by_gas = tp->light[i] && !moves_with_liquid(s, i);
        s->state.pressure[i] = by_gas ? tp->gas_pressure[i] : tp->heavy_pressure[i];
        if (tp->light[i] && !tp->joined[i])
            gas_max = fmax(gas_max, tp->gas_pressure[i]);
    }
    tp->gas_pressure_max = gas_max;
}
