/* The two phases' statistics (mps2p_solver_get_stat), 0 when effect
 * two_phase is off: the last step's counts of the sector scan, the join and
 * the gas solve. */
#include "core/core.h"
#include "two_phase/two_phase.h"

#define COUNT(name, member)                                                            \
    static double name(const mps2p_solver *s)                                          \
    {                                                                                  \
        return s->phases ? (double)s->phases->member : 0.0;                            \
    }
COUNT(gas_triggered, triggered_count)
COUNT(gas_enclosed, enclosed_count)
COUNT(gas_joined, joined_count)
COUNT(gas_capped, capped_count)
COUNT(gas_in_bubbles, bubble_count)
COUNT(gas_buffered, buffered_count)
COUNT(gas_ppe_unknowns, gas_unknowns)
COUNT(gas_ppe_iterations, gas_iterations)

static double gas_pressure_max(const mps2p_solver *s)
{
    return s->phases ? s->phases->gas_pressure_max : 0.0;
}

static double gas_in_liquid(const mps2p_solver *s)
{
    return (double)gas_in_liquid_count(s);
}

static double two_phase_active(const mps2p_solver *s)
{
    return s->effect_active[EFFECT_TWO_PHASE];
}

#define STAT(name, is_count, description) {#name, description, is_count, name}
const stat_entry two_phase_stats[] = {
    STAT(gas_triggered, 1, "light particles with delta_al = 1 in the last step"),
    STAT(gas_enclosed, 1, "light particles with heavy ones in all 8 sectors in the last step"),
    STAT(gas_joined, 1, "light particles reacting on the liquid in the last step"),
    STAT(gas_in_bubbles, 1,
         "light particles cut off from the gas's free surface (enclosed bubbles) in the last step"),
    STAT(gas_in_liquid, 1,
         "light particles inside the heavy fluid: more heavy than light neighbours within "
         "re_density, or heavy fluid above and heavy fluid or wall below (computed when asked)"),
    STAT(gas_capped, 1,
         "light particles whose correction was capped at gas_correction_limit in the last step"),
    STAT(gas_buffered, 1,
         "light particles the gas's damping layer (effect gas_buffer) slowed in the last step"),
    STAT(gas_pressure_max, 0, "highest gas pressure of the light particles moved by the gas (Pa)"),
    STAT(gas_ppe_unknowns, 1, "unknowns of the last gas pressure solve"),
    STAT(gas_ppe_iterations, 1, "CG iterations of the last gas pressure solve"),
    STAT(two_phase_active, 1, "1 when effect two_phase is on"),
};
const size_t two_phase_stat_count = sizeof two_phase_stats / sizeof two_phase_stats[0];
