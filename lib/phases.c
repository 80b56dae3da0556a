/* Two phases of very different density (docs/method.md sections 2-3), the
 * stages of effect two_phase: the liquid's own number density, the liquid
 * PPE, the state's pressure per phase, the correction per phase and the
 * gas's divergence check.
 *
 * Classification (a documented choice): a fluid is light when its density is
 * below light_fraction (0.1) of the heaviest fluid's; the others are heavy.
 * With no light fluid, or two_phase_model "single", the effect is off: none
 * of these stages is in the plan and s->phases is never allocated. */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

size_t phases_memory_bytes(const mps2p_solver *s)
{
    const two_phase *tp = s->phases;
    if (!tp)
        return 0;
    return sizeof *tp + fields_memory(&two_phase_fields, tp, s->count) +
           sizeof *tp->before_step + fields_memory(&two_phase_fields, tp->before_step, s->count);
}

void phases_free(two_phase *tp)
{
    if (!tp)
        return;
    fields_free(&two_phase_fields, tp);
    phases_free(tp->before_step);
    free(tp);
}

int phases_init(mps2p_solver *s)
{
    double heaviest = 0.0, light_density = light_fluid_density(s, &heaviest);
    const double threshold = s->params.light_fraction * heaviest;

    const size_t n = s->count;
    two_phase *tp = calloc(1, sizeof *tp);
    if (!tp || fields_allocate(&two_phase_fields, tp, n, 0, 0) != MPS2P_OK) {
        phases_free(tp);
        return MPS2P_ERR_NOMEM;
    }
    /* effects are decided before the plan allocates this state */
    tp->improved = s->effect_active[EFFECT_INTERFACE_REACTION];
    tp->heavy_density = heaviest;
    tp->light_density = light_density;
    for (size_t i = 0; i < n; i++) {
        tp->light[i] = s->kind[i] == MPS2P_KIND_FLUID &&
                       s->fluids[s->fluid_id[i]].density < threshold;
        tp->heavy_mask[i] = !tp->light[i];
        tp->gas_rho[i] = light_density; /* heavy particles: walls of gas density */
    }
    double g = hypot(s->params.gravity[0], s->params.gravity[1]);
    double extent = fmax(s->domain[2] - s->domain[0], s->domain[3] - s->domain[1]) / 3.0;
    tp->gas_pressure_limit = s->params.gas_pressure_limit > 0.0
                                 ? s->params.gas_pressure_limit
                                 : 1000.0 * light_density * fmax(g * extent, 1.0);
    s->phases = tp;
    /* a failed step puts the carried state back, as it does the particles */
    tp->before_step = phases_copy_carried(s, FIELD_ROLLED_BACK);
    if (!tp->before_step) {
        s->phases = NULL;
        phases_free(tp);
        return MPS2P_ERR_NOMEM;
    }
    /* the liquid's viscosity ignores the gas (docs/method.md section 2); the
     * gas sees the liquid as moving walls */
    s->viscosity_mask = tp->heavy_mask;
    s->viscosity_unmasked = tp->light;
    s->collision_share = phases_collision_share;
    return MPS2P_OK;
}

/* Number density as the liquid sees it: light particles count only when
 * they have joined the liquid solve. */
static void heavy_number_density(const mps2p_solver *s, double *out)
{
    const two_phase *tp = s->phases;
    const double re = s->params.re_density * s->l0;
    const neighbour_rows nl = neighbour_rows_within(&s->neighbours, re);
    const double *position = s->state.position;
    for (size_t i = 0; i < s->count; i++) {
        double n = 0.0;
        for (size_t k = nl.start[i]; k < nl.start[i + 1]; k++) {
            size_t j = nl.index[k];
            if (!tp->heavy_mask[j])
                continue;
            double dx = position[2 * j] - position[2 * i];
            double dy = position[2 * j + 1] - position[2 * i + 1];
            double w = kernel_weight(sqrt(dx * dx + dy * dy), re);
            n += tp->light[j] ? tp->join_weight[j] * w : w;
        }
        out[i] = n;
    }
}

int phases_step_start(mps2p_solver *s, double dt)
{
    (void)dt;
    two_phase *tp = s->phases;
    heavy_number_density(s, tp->heavy_n_start);
    if (!tp->have_initial) {
        memcpy(tp->heavy_n_initial, tp->heavy_n_start, s->count * sizeof(double));
        tp->have_initial = 1;
    }
    return MPS2P_OK;
}

/* A light particle moved by the liquid's pressure: volume, or drift with
 * drift_liquid_gradient, for as long as it has a weight in the liquid. */
static int moves_with_liquid(const mps2p_solver *s, size_t i)
{
    const two_phase *tp = s->phases;
    int kind = s->params.interface_reaction;
    return tp->light[i] && tp->join_weight[i] > 0.0 &&
           (kind == REACTION_VOLUME ||
            (kind == REACTION_DRIFT && s->params.drift_liquid_gradient != 0.0));
}

static int joins_liquid_solve(const mps2p_solver *s, size_t i)
{
    const two_phase *tp = s->phases;
    return tp->joined[i] && (s->params.interface_reaction == REACTION_VOLUME ||
                             s->params.interface_reaction == REACTION_WALL ||
                             s->params.interface_reaction == REACTION_DRIFT);
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
    for (size_t i = 0; i < s->count; i++) {
        if (!tp->light[i])
            continue;
        double target = joins_liquid_solve(s, i) ? 1.0 : 0.0;
        tp->join_weight[i] = target > tp->join_weight[i]
                                 ? fmin(target, tp->join_weight[i] + ramp)
                                 : fmax(target, tp->join_weight[i] - ramp);
    }
    for (size_t i = 0; i < s->count; i++) {
        int joined = tp->light[i] && tp->join_weight[i] > 0.0;
        tp->heavy_mask[i] = !tp->light[i] || joined;
        tp->heavy_part[i] = tp->heavy_mask[i] && s->kind[i] != MPS2P_KIND_DUMMY;
        /* A joined light particle stands for liquid volume in the liquid's
         * incompressibility: its source takes the liquid's density. */
        tp->heavy_rho[i] = tp->light[i] ? tp->heavy_density : s->density[i];
    }
    heavy_number_density(s, tp->heavy_n);
    size_t surface = 0;
    for (size_t i = 0; i < s->count; i++) {
        tp->heavy_surface[i] = tp->heavy_part[i] && tp->heavy_n[i] < threshold;
        surface += tp->heavy_surface[i];
    }
    s->surface_particles = surface;
    ppe_system heavy = {tp->heavy_part, tp->heavy_surface, tp->heavy_n, tp->heavy_n_start,
                        tp->heavy_rho, tp->heavy_pressure, 0.0, NULL, 0.0, 0, 0, 0.0};
    int status = pressure_assemble_system(s, dt, &heavy);
    if (status == MPS2P_OK)
        status = pressure_solve_system(s, &heavy);
    s->ppe_unknowns = tp->heavy_unknowns = heavy.unknowns;
    s->ppe_iterations = tp->heavy_iterations = heavy.iterations;
    s->ppe_iterations_total += heavy.iterations;
    s->ppe_residual = heavy.residual;
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

/* Correction per phase, Koshizuka and Oka's gradient over the particles each
 * phase sees:
 *   liquid: the liquid pressure over liquid, walls (and joined light ones);
 *   light particle moved by the gas: gas pressure over every particle, rho_a;
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
            gradient_masked_at(s, i, tp->heavy_pressure,
                               minimum_masked_around(s, i, tp->heavy_pressure, tp->heavy_part),
                               tp->heavy_part, gradient);
        } else if (moves_with_liquid(s, i)) {
            gradient_masked_at(s, i, tp->heavy_pressure,
                               minimum_masked_around(s, i, tp->heavy_pressure, tp->heavy_part),
                               tp->heavy_part, gradient);
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

/* The gas's own failure (docs/method.md section 2): a gas particle squeezed by
 * the liquid reaches a gas pressure far above any hydrostatic or dynamic
 * value. Reported with its place and how enclosed it was. */
int phases_divergence_check(mps2p_solver *s, double dt)
{
    const two_phase *tp = s->phases;
    const double jump = s->params.displacement_limit * s->l0;
    const double *before = s->before_step->state.position;
    for (size_t i = 0; i < s->count; i++) {
        if (!tp->light[i])
            continue;
        double moved = hypot(s->state.position[2 * i] - before[2 * i],
                             s->state.position[2 * i + 1] - before[2 * i + 1]);
        if (jump > 0.0 && moved > jump)
            return diverged_at(s, i, fail(s->error, MPS2P_ERR_DIVERGED,
                        "diverged at step %llu, t = %.6g s: gas particle %zu (%s) jumped %g l0 "
                        "in one step, to (%g, %g) (limit %g l0); gas pressure %g Pa, liquid "
                        "pressure %g Pa, n/n0 = %.3f, %s, %s, %s",
                        (unsigned long long)s->steps + 1, s->time + dt, i,
                        s->fluids[s->fluid_id[i]].name, moved / s->l0, s->state.position[2 * i],
                        s->state.position[2 * i + 1],
                        s->params.displacement_limit, tp->gas_pressure[i],
                        tp->heavy_pressure[i], s->number_density[i] / s->n0_density,
                        tp->enclosed[i] ? "enclosed by liquid" : "not enclosed",
                        tp->triggered[i] ? "triggered" : "not triggered",
                        tp->joined[i] ? "joined the liquid solve" : "gas"));
        if (!(fabs(tp->gas_pressure[i]) > tp->gas_pressure_limit))
            continue;
        return diverged_at(s, i, fail(s->error, MPS2P_ERR_DIVERGED,
                    "diverged at step %llu, t = %.6g s: gas particle %zu (%s) at (%g, %g) "
                    "has gas pressure %g Pa, beyond the limit %g Pa (n/n0 = %.3f, %s, %s): "
                    "the liquid is closing in on it",
                    (unsigned long long)s->steps + 1, s->time + dt, i,
                    s->fluids[s->fluid_id[i]].name, s->state.position[2 * i],
                    s->state.position[2 * i + 1], tp->gas_pressure[i], tp->gas_pressure_limit,
                    s->number_density[i] / s->n0_density,
                    tp->enclosed[i] ? "enclosed by liquid" : "not enclosed",
                    tp->triggered[i] ? "triggered" : "not triggered"));
    }
    return MPS2P_OK;
}
