/* The two-phase state, allocated with the plan when effect two_phase is on
 * (a light fluid: density below light_fraction of the heaviest fluid's, a
 * documented choice; and two_phase_model not "single"), never for a
 * single-phase solver. Its table (struct two_phase, one row a member) says
 * what carries from one step into the next, so that saved states
 * (solver/state.c), checkpoints (io/checkpoint.c) and a failed step's
 * rollback keep it and a restored two-phase solver continues bit for bit.
 *
 * Carried (read in a step before that step writes them):
 *   join_weight      ramped from its last value (liquid_pressure_solve); read
 *                    by phases_start's liquid number density first
 *   joined           "joined in the step before" for collision (which runs
 *                    before interface_join) and, as was_joined, join_hold;
 *                    always 0 in the two_step model
 *   heavy_n_initial, have_initial
 *                    the liquid's number density at the first step, the
 *                    reference of gas_liquid_volume 2
 *   heavy_pressure, gas_pressure
 *                    the initial guesses of the liquid and gas CG solves
 *                    (pressure_assemble_system; CHOLMOD ignores them)
 *   gas_top, have_gas_top
 *                    the gas damping layer's top, taken at the first step
 *                    with effect gas_buffer on (gas_buffer.c)
 *   gas_pressure_limit
 *                    derived at allocation from the gravity of that time;
 *                    mps2p_solver_set_gravity does not change it
 *   the last step's counts and gas_pressure_max
 *                    reported by mps2p_solver_get_stat until the next step
 *   heavy_mask       read by viscosity and phases_start before the liquid
 *                    solve rewrites it, but it is !light || join_weight > 0
 *                    at the end of every step (and at allocation): rebuilt
 *                    from join_weight, not saved
 * Not carried: light, gas_rho, improved and the densities come from the
 * scene; triggered, enclosed, was_joined, bubble, flood_queue, heavy_part, gas_part, the
 * surfaces, gas_open, heavy_n, heavy_n_start, gas_n and heavy_rho are
 * written for every particle in a step before they are read. */
#include "core/core.h"
#include "two_phase/two_phase.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define FIELD(member, type, flags)                                                     \
    {#member, offsetof(two_phase, member), type, 1, flags}
#define CARRIED (FIELD_SAVED | FIELD_CHECKPOINTED | FIELD_ROLLED_BACK)
#define ARRAY(member, type, flags) FIELD(member, type, FIELD_PER_PARTICLE | (flags))

/* Datasets, then attributes, of group "two_phase" of a checkpoint, in this
 * order (docs/results-files.md). */
static const field two_phase_rows[] = {
    ARRAY(join_weight, FIELD_DOUBLE, CARRIED),
    ARRAY(joined, FIELD_FLAG, CARRIED),
    ARRAY(heavy_n_initial, FIELD_DOUBLE, CARRIED),
    ARRAY(heavy_pressure, FIELD_DOUBLE, CARRIED),
    ARRAY(gas_pressure, FIELD_DOUBLE, CARRIED),
    /* from the scene: a state fits only a solver with the same light particles */
    ARRAY(light, FIELD_FLAG, FIELD_MATCHED),
    /* rebuilt from light and join_weight (phases_carried_rebuild) */
    ARRAY(heavy_mask, FIELD_FLAG, 0),
    /* written for every particle in a step before they are read */
    ARRAY(triggered, FIELD_FLAG, 0),
    ARRAY(enclosed, FIELD_FLAG, 0),
    ARRAY(was_joined, FIELD_FLAG, 0),
    ARRAY(bubble, FIELD_FLAG, 0),
    ARRAY(flood_queue, FIELD_LONG, 0),
    ARRAY(heavy_part, FIELD_FLAG, 0),
    ARRAY(gas_part, FIELD_FLAG, 0),
    ARRAY(heavy_surface, FIELD_FLAG, 0),
    ARRAY(gas_surface, FIELD_FLAG, 0),
    ARRAY(gas_open, FIELD_FLAG, 0),
    ARRAY(heavy_n, FIELD_DOUBLE, 0),
    ARRAY(heavy_n_start, FIELD_DOUBLE, 0),
    ARRAY(gas_n, FIELD_DOUBLE, 0),
    ARRAY(gas_n_weight, FIELD_DOUBLE, 0),
    ARRAY(heavy_rho, FIELD_DOUBLE, 0),
    /* from the scene (phases_init) */
    ARRAY(gas_rho, FIELD_DOUBLE, 0),

    FIELD(have_initial, FIELD_INT, CARRIED),
    FIELD(gas_pressure_limit, FIELD_DOUBLE, CARRIED),
    FIELD(gas_pressure_max, FIELD_DOUBLE, CARRIED),
    FIELD(triggered_count, FIELD_SIZE, CARRIED),
    FIELD(enclosed_count, FIELD_SIZE, CARRIED),
    FIELD(joined_count, FIELD_SIZE, CARRIED),
    FIELD(heavy_unknowns, FIELD_SIZE, CARRIED),
    FIELD(heavy_iterations, FIELD_SIZE, CARRIED),
    FIELD(gas_unknowns, FIELD_SIZE, CARRIED),
    FIELD(gas_iterations, FIELD_SIZE, CARRIED),
    FIELD(capped_count, FIELD_SIZE, CARRIED | FIELD_OPTIONAL),
    FIELD(bubble_count, FIELD_SIZE, CARRIED | FIELD_OPTIONAL),
    /* absent (0) in older files: the layer's top is taken at the next step */
    FIELD(gas_top, FIELD_DOUBLE, CARRIED | FIELD_OPTIONAL),
    FIELD(have_gas_top, FIELD_INT, CARRIED | FIELD_OPTIONAL),
    FIELD(buffered_count, FIELD_SIZE, CARRIED | FIELD_OPTIONAL),
};

const field_table two_phase_fields = {two_phase_rows,
                                      sizeof two_phase_rows / sizeof two_phase_rows[0]};

two_phase *phases_copy_carried(const mps2p_solver *s, unsigned with)
{
    two_phase *copy = calloc(1, sizeof *copy);
    if (!copy || fields_allocate(&two_phase_fields, copy, s->count, with, 0) != MPS2P_OK) {
        phases_free(copy);
        return NULL;
    }
    fields_copy(&two_phase_fields, copy, s->phases, s->count, with);
    return copy;
}

void phases_save_before_step(mps2p_solver *s)
{
    fields_copy(&two_phase_fields, s->phases->before_step, s->phases, s->count,
                FIELD_ROLLED_BACK);
}

void phases_carried_rebuild(mps2p_solver *s)
{
    two_phase *tp = s->phases;
    for (size_t i = 0; i < s->count; i++)
        tp->heavy_mask[i] = !tp->light[i] || tp->join_weight[i] > 0.0;
}

void phases_put_carried(mps2p_solver *s, const two_phase *from, unsigned with)
{
    fields_copy(&two_phase_fields, s->phases, from, s->count, with);
    phases_carried_rebuild(s);
}

int phases_carried_check(const mps2p_solver *s, char *why, size_t size)
{
    const two_phase *tp = s->phases;
    const size_t n = s->count;
    /* a diverged solver's step is rolled back but its two-phase arrays are
     * not: its pressures may be anything (it never steps again) */
    const int any_pressure = s->diverged;
    for (size_t i = 0; i < n; i++) {
        double w = tp->join_weight[i];
        /* only light particles ever join or get a weight */
        int ok = w >= 0.0 && w <= 1.0 && tp->joined[i] <= 1 &&
                 (tp->light[i] || (w == 0.0 && tp->joined[i] == 0)) &&
                 isfinite(tp->heavy_n_initial[i]) && tp->heavy_n_initial[i] >= 0.0 &&
                 (any_pressure || (isfinite(tp->heavy_pressure[i]) &&
                                   isfinite(tp->gas_pressure[i])));
        if (!ok) {
            snprintf(why, size, "two-phase state of particle %zu is inconsistent (%s, join "
                     "weight %g, joined %d, initial liquid number density %g, liquid pressure "
                     "%g, gas pressure %g)", i, tp->light[i] ? "light" : "not light", w,
                     tp->joined[i], tp->heavy_n_initial[i], tp->heavy_pressure[i],
                     tp->gas_pressure[i]);
            return -1;
        }
    }
    int ok = (tp->have_initial == 0 || tp->have_initial == 1) &&
             isfinite(tp->gas_pressure_limit) && tp->gas_pressure_limit > 0.0 &&
             (any_pressure || isfinite(tp->gas_pressure_max)) && tp->gas_pressure_max >= 0.0 &&
             tp->triggered_count <= n && tp->enclosed_count <= n && tp->joined_count <= n &&
             (tp->have_gas_top == 0 || tp->have_gas_top == 1) && isfinite(tp->gas_top) &&
             tp->capped_count <= n && tp->bubble_count <= n && tp->buffered_count <= n &&
             tp->heavy_unknowns <= n &&
             tp->gas_unknowns <= n;
    if (!ok) {
        snprintf(why, size, "inconsistent two-phase values (have_initial %d, gas pressure limit "
                 "%g Pa, gas pressure max %g Pa, have_gas_top %d, gas top %g m, counts %zu, "
                 "%zu, %zu, %zu, %zu, %zu, unknowns %zu, %zu of %zu particles)",
                 tp->have_initial, tp->gas_pressure_limit, tp->gas_pressure_max,
                 tp->have_gas_top, tp->gas_top, tp->triggered_count, tp->enclosed_count,
                 tp->joined_count, tp->capped_count, tp->bubble_count, tp->buffered_count,
                 tp->heavy_unknowns, tp->gas_unknowns, n);
        return -1;
    }
    return 0;
}

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
        /* out of the run too: a checkpoint's solver has the same light flags
         * as the one that wrote it, and a state the same as its solver's */
        tp->light[i] = kind_is_fluid(s->kind[i]) &&
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
