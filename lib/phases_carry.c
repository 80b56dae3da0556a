/* What of the two-phase state carries from one step into the next, so that
 * mps2p_solver_save_state (state.c) and checkpoints (checkpoint.c) can save
 * it and a restored two-phase solver continues bit for bit.
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
 * scene; triggered, enclosed, was_joined, heavy_part, gas_part, the
 * surfaces, heavy_n, heavy_n_start, gas_n, gas_dirichlet and heavy_rho are
 * written for every particle in a step before they are read. */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CARRIED(member, is_double) {#member, is_double, offsetof(two_phase, member)}
const phases_array phases_carried[PHASES_CARRIED_ARRAYS] = {
    CARRIED(join_weight, 1),    CARRIED(joined, 0),       CARRIED(heavy_n_initial, 1),
    CARRIED(heavy_pressure, 1), CARRIED(gas_pressure, 1),
};

void *phases_array_data(const two_phase *tp, const phases_array *a)
{
    void *data;
    memcpy(&data, (const char *)tp + a->offset, sizeof data);
    return data;
}

size_t phases_array_bytes(const phases_array *a, size_t count)
{
    return count * (a->is_double ? sizeof(double) : 1);
}

static void copy_scalars(two_phase *to, const two_phase *from)
{
    to->have_initial = from->have_initial;
    to->gas_pressure_limit = from->gas_pressure_limit;
    to->triggered_count = from->triggered_count;
    to->enclosed_count = from->enclosed_count;
    to->joined_count = from->joined_count;
    to->capped_count = from->capped_count; /* not in checkpoints: 0 after a load */
    to->heavy_unknowns = from->heavy_unknowns;
    to->heavy_iterations = from->heavy_iterations;
    to->gas_unknowns = from->gas_unknowns;
    to->gas_iterations = from->gas_iterations;
    to->gas_pressure_max = from->gas_pressure_max;
}

two_phase *phases_copy_carried(const mps2p_solver *s)
{
    const two_phase *tp = s->phases;
    const size_t n = s->count;
    two_phase *copy = calloc(1, sizeof *copy);
    if (!copy)
        return NULL;
    /* light too: a state fits only a solver with the same light particles */
    int ok = (copy->light = malloc(n ? n : 1)) != NULL;
    if (ok)
        memcpy(copy->light, tp->light, n);
    for (size_t k = 0; ok && k < PHASES_CARRIED_ARRAYS; k++) {
        const phases_array *a = &phases_carried[k];
        size_t bytes = phases_array_bytes(a, n);
        void *data = malloc(bytes ? bytes : 1);
        ok = data != NULL;
        if (ok)
            memcpy(data, phases_array_data(tp, a), bytes);
        memcpy((char *)copy + a->offset, &data, sizeof data);
    }
    if (!ok) {
        phases_free(copy);
        return NULL;
    }
    copy_scalars(copy, tp);
    return copy;
}

void phases_save_before_step(mps2p_solver *s)
{
    two_phase *tp = s->phases, *to = tp->before_step;
    for (size_t k = 0; k < PHASES_CARRIED_ARRAYS; k++) {
        const phases_array *a = &phases_carried[k];
        memcpy(phases_array_data(to, a), phases_array_data(tp, a),
               phases_array_bytes(a, s->count));
    }
    copy_scalars(to, tp);
}

void phases_carried_rebuild(mps2p_solver *s)
{
    two_phase *tp = s->phases;
    for (size_t i = 0; i < s->count; i++)
        tp->heavy_mask[i] = !tp->light[i] || tp->join_weight[i] > 0.0;
}

void phases_put_carried(mps2p_solver *s, const two_phase *from)
{
    two_phase *tp = s->phases;
    for (size_t k = 0; k < PHASES_CARRIED_ARRAYS; k++) {
        const phases_array *a = &phases_carried[k];
        memcpy(phases_array_data(tp, a), phases_array_data(from, a),
               phases_array_bytes(a, s->count));
    }
    copy_scalars(tp, from);
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
             tp->heavy_unknowns <= n && tp->gas_unknowns <= n;
    if (!ok) {
        snprintf(why, size, "inconsistent two-phase values (have_initial %d, gas pressure limit "
                 "%g Pa, gas pressure max %g Pa, counts %zu, %zu, %zu, unknowns %zu, %zu of "
                 "%zu particles)", tp->have_initial, tp->gas_pressure_limit,
                 tp->gas_pressure_max, tp->triggered_count, tp->enclosed_count,
                 tp->joined_count, tp->heavy_unknowns, tp->gas_unknowns, n);
        return -1;
    }
    return 0;
}
