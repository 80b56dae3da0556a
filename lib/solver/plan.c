/* The step as a plan of stages: one ordered table of every stage, laid out
 * for the effects that are on, and what each stage costs (wall time and
 * calls, kept per solver). */
#include "core/core.h"
#include "stages/stages.h"
#include "two_phase/two_phase.h"
#include "coupling/coupling.h"
#include "solver/solver.h"

#include <string.h>
#include <time.h>

/* With two phases, phases_start computes n^k with the liquid's own. */
static int uses_start_density(const mps2p_solver *s)
{
    return s->params.ppe_source != PPE_SOURCE_DENSITY && !s->effect_active[EFFECT_TWO_PHASE];
}

/* The single-phase pressure stages give way to the two phases' own. */
static int single_phase(const mps2p_solver *s)
{
    return !s->effect_active[EFFECT_TWO_PHASE];
}

static int counts_neighbours(const mps2p_solver *s)
{
    return s->params.free_surface == FREE_SURFACE_NEIGHBOUR_COUNT && single_phase(s);
}

typedef struct stage {
    const char *name;
    int effect;                           /* the effect it belongs to, or -1 */
    int (*wanted)(const mps2p_solver *s); /* a further condition, or NULL */
    int (*run)(mps2p_solver *s, double dt);
    int moves;    /* it moves particles: the neighbour list is brought up to date after it */
    size_t needs; /* the on-demand array it uses (offsetof mps2p_solver), or 0 (l0: none) */
} stage;

#define NEEDS(member) offsetof(mps2p_solver, member)

/* One MPS step (docs/method.md section 1, fig. 1 of the paper), in order;
 * mps2p_solver_get_stage's index is the row. Host-moved walls move first,
 * so that viscosity sees their velocity. With two phases (docs/method.md
 * 2-3) the liquid's own n^k is taken at the start (with all particles'), and the free surface,
 * PPE and correction give way to the sector scan, the liquid then the gas
 * PPE and a correction per phase, then the gas's damping layer at its top
 * (before the checks: it is the boundary, not a repair); the gas's own check runs before the
 * general one (its message says more about a squeezed gas particle). */
static const stage stages[] = {
    {"neighbours", -1, NULL, neighbours_refresh, 0, 0},
    {"number_density_start", -1, uses_start_density, number_density_start, 0,
     NEEDS(number_density_start)},
    {"phases_start", EFFECT_TWO_PHASE, NULL, phases_step_start, 0, NEEDS(number_density_start)},
    {"body_motion", -1, body_motion_wanted, body_motion_apply, 0, 0},
    {"viscosity", EFFECT_VISCOSITY, NULL, viscosity_apply, 0, 0},
    {"turbulence", EFFECT_TURBULENCE, NULL, turbulence_apply, 0, NEEDS(eddy_viscosity)},
    {"gravity", EFFECT_GRAVITY, NULL, gravity_apply, 0, 0},
    {"excitation", EFFECT_EXCITATION, NULL, excitation_apply, 0, 0},
    {"external_forces", -1, external_forces_wanted, external_forces_apply, 0, 0},
    {"advection", -1, NULL, advect, 1, 0},
    {"collision", EFFECT_COLLISION, NULL, collision_apply, 1, 0},
    {"number_density", -1, NULL, number_density_star, 0, 0},
    {"neighbour_count", -1, counts_neighbours, neighbour_count_compute, 0,
     NEEDS(neighbour_count)},
    {"free_surface", -1, single_phase, free_surface_detect, 0, 0},
    {"pressure_assembly", -1, single_phase, pressure_assemble, 0, 0},
    {"pressure_solve", -1, single_phase, pressure_solve, 0, 0},
    {"interface_scan", EFFECT_TWO_PHASE, NULL, interface_scan, 0, 0},
    {"interface_join", EFFECT_INTERFACE_REACTION, NULL, interface_join, 0, 0},
    {"liquid_pressure", EFFECT_TWO_PHASE, NULL, liquid_pressure_solve, 0, 0},
    {"gas_pressure", EFFECT_TWO_PHASE, NULL, gas_pressure_solve, 0, 0},
    {"correction", -1, single_phase, pressure_correct, 0, 0},
    {"two_phase_correction", EFFECT_TWO_PHASE, NULL, phases_correct, 0, 0},
    {"interface_drift", EFFECT_INTERFACE_REACTION, NULL, interface_drift_apply, 0, 0},
    {"gas_buffer", EFFECT_GAS_BUFFER, NULL, gas_buffer_apply, 0, 0},
    {"gas_divergence_check", EFFECT_TWO_PHASE, NULL, phases_divergence_check, 0, 0},
    {"divergence_check", -1, NULL, divergence_check, 0, 0},
};
_Static_assert(sizeof stages / sizeof stages[0] == STAGE_COUNT, "STAGE_COUNT is the table's");
#define NEIGHBOURS 0 /* the row of the neighbour list's update */

static int stage_active(const mps2p_solver *s, size_t k)
{
    const stage *e = &stages[k];
    return (e->effect < 0 || s->effect_active[e->effect]) && (!e->wanted || e->wanted(s));
}

int plan_build(mps2p_solver *s)
{
    s->plan_length = 0;
    for (size_t k = 0; k < STAGE_COUNT; k++) {
        if (!stage_active(s, k))
            continue;
        s->plan[s->plan_length++] = (int)k;
        if (stages[k].moves)
            s->plan[s->plan_length++] = NEIGHBOURS;
        /* arrays of stages that are off are never allocated */
        const field *f = field_at(&solver_fields, stages[k].needs);
        if (f && (f->flags & FIELD_ON_DEMAND) && field_allocate(f, s, s->count) != MPS2P_OK)
            return fail(s->error, MPS2P_ERR_NOMEM, "out of memory for %zu values of %s",
                        s->count, f->name);
    }
    if (s->effect_active[EFFECT_TWO_PHASE] && !s->phases && phases_init(s) != MPS2P_OK)
        return fail(s->error, MPS2P_ERR_NOMEM, "out of memory for the two-phase state of %zu "
                    "particles", s->count);
    s->plan_stale = 0;
    return MPS2P_OK;
}

static double seconds_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int plan_run(mps2p_solver *s, double dt)
{
    double before = seconds_now();
    for (size_t k = 0; k < s->plan_length; k++) {
        int stage = s->plan[k];
        int status = stages[stage].run(s, dt);
        double after = seconds_now();
        s->stage_seconds[stage] += after - before;
        s->stage_calls[stage]++;
        before = after;
        if (status != MPS2P_OK)
            return status;
    }
    return MPS2P_OK;
}

int mps2p_solver_stage_count(const mps2p_solver *s, size_t *count)
{
    error_clear();
    if (!s || !count)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_stage_count: %s is NULL",
                    s ? "count" : "solver");
    *count = STAGE_COUNT;
    return MPS2P_OK;
}

int mps2p_solver_get_stage(const mps2p_solver *s, size_t index, const char **name,
                           int *active, double *seconds, uint64_t *calls)
{
    error_clear();
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_get_stage: solver is NULL");
    if (index >= STAGE_COUNT)
        return fail(NULL, MPS2P_ERR_INVALID, "stage index %zu is past the last (%d)", index,
                    STAGE_COUNT - 1);
    if (name)
        *name = stages[index].name;
    if (active) /* as the next step's plan will be, stale or not */
        *active = stage_active(s, index);
    if (seconds)
        *seconds = s->stage_seconds[index];
    if (calls)
        *calls = s->stage_calls[index];
    return MPS2P_OK;
}

int mps2p_solver_reset_stage_timings(mps2p_solver *s)
{
    error_clear();
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_reset_stage_timings: solver is NULL");
    memset(s->stage_seconds, 0, sizeof s->stage_seconds);
    memset(s->stage_calls, 0, sizeof s->stage_calls);
    return MPS2P_OK;
}
