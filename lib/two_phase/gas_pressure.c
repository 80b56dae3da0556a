/* The light fluid's pressure (docs/method.md section 2, step 2): one PPE over the
 * light particles with every other non-dummy particle (liquid, joined light
 * particles, walls) a fixed wall of gas density: it carries a pressure
 * unknown with the gas's density in its source, and it is not moved by the
 * result. Free surface where the number density of all particles is below
 * beta n0 (the top of the air), except at a void inside the gas of the
 * improved model (gas_free_surface). */
#include "numerics/numerics.h"
#include "core/core.h"
#include "stages/stages.h"
#include "two_phase/two_phase.h"

#include <math.h>
#include <string.h>

/* The weight factor of a liquid particle in the gas's number density (below),
 * 0 for any other particle. */
static double liquid_volume(const mps2p_solver *s, size_t j)
{
    const two_phase *tp = s->phases;
    if (s->kind[j] != MPS2P_KIND_FLUID || tp->light[j] || !(tp->heavy_n[j] > 0.0))
        return 0.0;
    /* 1: against n0; 2: against the particle's own initial liquid number
     * density (no spike at the start) */
    const double n0 = s->n0_density;
    double reference = s->params.gas_liquid_volume == 2.0 ? fmin(n0, tp->heavy_n_initial[j]) : n0;
    return fmin(2.0, fmax(1.0, reference / tp->heavy_n[j]));
}

/* Number density for the gas with each liquid particle weighted by the
 * volume it stands for, n0 / n_liquid in [1, 2]: a sparse liquid sheet
 * (n_liquid < n0, common at MPS free surfaces) then does not look like room
 * for gas between its particles. */
static const double *gas_number_density(mps2p_solver *s)
{
    two_phase *tp = s->phases;
    if (s->params.gas_liquid_volume == 0.0 || !tp->improved) /* the paper's conventional */
        return s->number_density;
    const double re = s->params.re_density * s->l0;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    const double *position = s->state.position;
    double *out = tp->gas_n;
    /* each particle's factor once, not once a pair (it divides) */
    double *volume = tp->gas_n_weight;
    PARALLEL_FOR(s->params.threads, schedule(static),
    for (size_t i = 0; i < s->count; i++)
        volume[i] = liquid_volume(s, i);
    );
    /* each pair's weight once, added to both rows (first_above, pair_block_first) */
    PAIR_BLOCKS(s->params.threads, nl.start, s->count, &tp->gas_density_blocks, first, end,
        for (size_t i = first; i < end; i++) {
            double n = 0.0;
            for (size_t k = nl.start[i]; k < nl.start[i + 1] && nl.index[k] < first; k++) {
                size_t j = nl.index[k];
                double dx = position[2 * j] - position[2 * i];
                double dy = position[2 * j + 1] - position[2 * i + 1];
                double w = kernel_weight_squared(dx * dx + dy * dy, re);
                double volume_j = volume[j];
                n += volume_j > 0.0 ? w * volume_j : w;
            }
            out[i] = n;
        }
        for (size_t i = first; i < end; i++) {
            double n = out[i];
            const double volume_i = volume[i];
            const size_t inside = row_end_below(nl, i, end);
            for (size_t k = first_above(nl, i); k < nl.start[i + 1]; k++) {
                size_t j = nl.index[k];
                double dx = position[2 * j] - position[2 * i];
                double dy = position[2 * j + 1] - position[2 * i + 1];
                double w = kernel_weight_squared(dx * dx + dy * dy, re);
                double volume_j = volume[j];
                n += volume_j > 0.0 ? w * volume_j : w;
                if (k < inside)
                    out[j] += volume_i > 0.0 ? w * volume_i : w;
            }
            out[i] = n;
        }
    );
    return tp->gas_n;
}

/* Marks gas_open: light particles the gas moves that reach its damping
 * layer through such particles within re_density (breadth first from the
 * layer), with the layer's bottom and up. Returns 0, marking nothing,
 * without a gas top. */
static int mark_open_gas(mps2p_solver *s, double *layer_bottom, double up[2])
{
    two_phase *tp = s->phases;
    memset(tp->gas_open, 0, s->count);
    if (!s->effect_active[EFFECT_GAS_BUFFER] || !tp->have_gas_top || !gravity_up(s, up))
        return 0;
    const double bottom = tp->gas_top - s->params.gas_buffer_depth * s->l0;
    const double *r = s->state.position;
    for (size_t i = 0; i < s->count; i++)
        tp->gas_open[i] = light_in_run(s, i) && !moves_with_liquid(s, i) &&
                          r[2 * i] * up[0] + r[2 * i + 1] * up[1] >= bottom;
    light_flood(s, tp->gas_open, 1);
    *layer_bottom = bottom;
    return 1;
}

/* A liquid particle within re_density of particle i. */
static int near_liquid(const mps2p_solver *s, size_t i)
{
    const two_phase *tp = s->phases;
    const double re = s->params.re_density * s->l0, re2 = re * re;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    const double *r = s->state.position;
    for (size_t k = nl.start[i]; k < nl.start[i + 1]; k++) {
        size_t j = nl.index[k];
        double dx = r[2 * j] - r[2 * i], dy = r[2 * j + 1] - r[2 * i + 1];
        if (s->kind[j] == MPS2P_KIND_FLUID && !tp->light[j] && dx * dx + dy * dy < re2)
            return 1;
    }
    return 0;
}

/* The gas PPE's free surface: number density below beta n0. In the
 * improved model with a gas top (effect gas_buffer), a light particle of the
 * open gas below the damping layer, with no liquid within re_density and at
 * least VOID_EDGE_MIN n0, is not free surface: the only atmosphere is above
 * the gas, so an empty region inside it (a splash's wake) is a void the gas
 * closes, and its pressure may fall below the atmosphere's there (returns 1:
 * the solve keeps negative pressures). With p = 0 at a void's edge and
 * negative pressures clamped, nothing but gravity drew air into a wake, and
 * the paper's case opened holes of 3-5 l0 (docs/two-phase.md). Liquid
 * neighbours keep the old rule (suction there drew air into the gaps of a
 * splash), and so do bubbles (their low-density particles are their only
 * reference pressure). */
#define VOID_EDGE_MIN 0.5
static int gas_free_surface(mps2p_solver *s, const double *n_gas)
{
    two_phase *tp = s->phases;
    const double threshold = s->params.beta * s->n0_density;
    double bottom = 0.0, up[2] = {0.0, 1.0};
    int voids = tp->improved && mark_open_gas(s, &bottom, up);
    const double *r = s->state.position;
    for (size_t i = 0; i < s->count; i++) {
        tp->gas_part[i] = kind_carries_pressure(s->kind[i]);
        int surface = tp->gas_part[i] && n_gas[i] < threshold;
        if (surface && voids && tp->gas_open[i] &&
            n_gas[i] >= VOID_EDGE_MIN * s->n0_density &&
            r[2 * i] * up[0] + r[2 * i + 1] * up[1] < bottom && !near_liquid(s, i))
            surface = 0;
        tp->gas_surface[i] = (unsigned char)surface;
    }
    return voids;
}

/* The gas PPE's n*: a void's edge (below beta n0, not free surface) counts
 * as at beta n0, so that its source asks for no more than the deficit at
 * beta n0. Its own deficit (up to half of n0) closed the void in
 * one step: a suction growing as 1 / dt^2, which the adaptive dt, shrinking
 * with the speeds it caused, fed until the paper's case diverged at 1.478 s
 * (an air particle at -15.5 kPa, docs/two-phase.md). The void now closes by
 * the flow over several steps. */
static const double *gas_source_density(mps2p_solver *s, const double *n_gas)
{
    two_phase *tp = s->phases;
    const double threshold = s->params.beta * s->n0_density;
    int copied = n_gas == tp->gas_n;
    for (size_t i = 0; i < s->count; i++) {
        if (!tp->gas_part[i] || tp->gas_surface[i] || n_gas[i] >= threshold)
            continue;
        if (!copied) { /* n_gas is the solver's number density: leave it */
            memcpy(tp->gas_n, n_gas, s->count * sizeof *n_gas);
            copied = 1;
        }
        tp->gas_n[i] = threshold;
    }
    return copied ? tp->gas_n : n_gas;
}

void gas_pressure_prepare(mps2p_solver *s)
{
    two_phase *tp = s->phases;
    tp->gas_n_seen = gas_number_density(s);
    tp->gas_voids = gas_free_surface(s, tp->gas_n_seen);
    tp->gas_prepared = 1;
}

int gas_pressure_solve(mps2p_solver *s, double dt)
{
    two_phase *tp = s->phases;
    if (!tp->gas_prepared)
        gas_pressure_prepare(s);
    tp->gas_prepared = 0; /* used once */
    const double *n_gas = tp->gas_n_seen;
    const int voids = tp->gas_voids;
    ppe_system gas = {.part = tp->gas_part,
                      .surface = tp->gas_surface,
                      .n_star = voids ? gas_source_density(s, n_gas) : n_gas,
                      .n_start = s->number_density_start,
                      .density = tp->gas_rho,
                      .pressure = tp->gas_pressure,
                      .tolerance = s->params.gas_cg_tolerance,
                      /* n* is gas_n (liquid-weighted; void edges raised), n^k the plain number
                       * density: their difference (the ecs and mixed sources)
                       * is not the gas's compression */
                      .density_source = 1,
                      .keep_negative = voids};
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
        if (light_in_run(s, i) && !tp->joined[i])
            gas_max = fmax(gas_max, tp->gas_pressure[i]);
    }
    tp->gas_pressure_max = gas_max;
}
