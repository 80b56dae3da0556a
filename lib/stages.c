/* The step as a plan of stages, assembled from the active effects, and what
 * each stage costs: wall time and calls, kept per solver. */
#include "internal.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

static int run_neighbours(mps2p_solver *s, double dt)
{
    (void)dt;
    if (neighbours_update(&s->neighbours, s->state.position) != MPS2P_OK)
        return fail(s->error, MPS2P_ERR_NOMEM,
                    "step %llu at t = %.6g s: out of memory for the neighbour list",
                    (unsigned long long)s->steps + 1, s->time);
    return MPS2P_OK;
}

static int run_number_density_start(mps2p_solver *s, double dt)
{
    (void)dt;
    number_density_compute(s, s->number_density_start);
    return MPS2P_OK;
}

static int run_body_motion(mps2p_solver *s, double dt)
{
    body_motion_apply(s, dt);
    return MPS2P_OK;
}

static int run_external_forces(mps2p_solver *s, double dt)
{
    external_forces_apply(s, dt);
    return MPS2P_OK;
}

static int run_viscosity(mps2p_solver *s, double dt)
{
    viscosity_apply(s, dt);
    return MPS2P_OK;
}

static int run_neighbour_count(mps2p_solver *s, double dt)
{
    (void)dt;
    neighbour_count_compute(s);
    return MPS2P_OK;
}

static int counts_neighbours(const mps2p_solver *s)
{
    return s->params.free_surface == FREE_SURFACE_NEIGHBOUR_COUNT &&
           !s->effect_active[EFFECT_TWO_PHASE];
}

static int run_turbulence(mps2p_solver *s, double dt)
{
    turbulence_apply(s, dt);
    return MPS2P_OK;
}

static int run_gravity(mps2p_solver *s, double dt)
{
    gravity_apply(s, dt);
    return MPS2P_OK;
}

static int run_advection(mps2p_solver *s, double dt)
{
    advect(s, dt);
    return MPS2P_OK;
}

static int run_collision(mps2p_solver *s, double dt)
{
    collision_apply(s, dt);
    return MPS2P_OK;
}

static int run_number_density(mps2p_solver *s, double dt)
{
    (void)dt;
    number_density_compute(s, s->number_density);
    return MPS2P_OK;
}

static int run_free_surface(mps2p_solver *s, double dt)
{
    (void)dt;
    free_surface_detect(s);
    return MPS2P_OK;
}

static int run_pressure_assembly(mps2p_solver *s, double dt)
{
    return pressure_assemble(s, dt);
}

static int run_pressure_solve(mps2p_solver *s, double dt)
{
    (void)dt;
    return pressure_solve(s);
}

static int run_correction(mps2p_solver *s, double dt)
{
    pressure_correct(s, dt);
    return MPS2P_OK;
}

static int run_divergence_check(mps2p_solver *s, double dt)
{
    return divergence_check(s, dt);
}

static int run_phases_start(mps2p_solver *s, double dt)
{
    (void)dt;
    phases_step_start(s);
    return MPS2P_OK;
}

static int run_interface_scan(mps2p_solver *s, double dt)
{
    (void)dt;
    interface_scan(s);
    return MPS2P_OK;
}

static int run_interface_join(mps2p_solver *s, double dt)
{
    (void)dt;
    interface_join(s);
    return MPS2P_OK;
}

static int run_liquid_pressure(mps2p_solver *s, double dt)
{
    return liquid_pressure_solve(s, dt);
}

static int run_excitation(mps2p_solver *s, double dt)
{
    excitation_apply(s, dt);
    return MPS2P_OK;
}

static int run_gas_pressure(mps2p_solver *s, double dt)
{
    return gas_pressure_solve(s, dt);
}

static int run_two_phase_correction(mps2p_solver *s, double dt)
{
    phases_correct(s, dt);
    return MPS2P_OK;
}

static int run_interface_drift(mps2p_solver *s, double dt)
{
    interface_drift_apply(s, dt);
    return MPS2P_OK;
}

static int run_gas_divergence_check(mps2p_solver *s, double dt)
{
    return phases_divergence_check(s, dt);
}

static int uses_start_density(const mps2p_solver *s)
{
    return s->params.ppe_source != PPE_SOURCE_DENSITY;
}

/* The single-phase pressure stages give way to the two phases' own. */
static int single_phase(const mps2p_solver *s)
{
    return !s->effect_active[EFFECT_TWO_PHASE];
}

static int drift_reaction(const mps2p_solver *s)
{
    return s->params.interface_reaction == REACTION_DRIFT;
}

typedef struct stage_entry {
    const char *name;
    int effect;                              /* the effect it belongs to, or -1 */
    int (*wanted)(const mps2p_solver *s);    /* extra condition, or NULL */
    int (*run)(mps2p_solver *s, double dt);
} stage_entry;

static const stage_entry stages[STAGE_COUNT] = {
    [STAGE_NEIGHBOURS] = {"neighbours", -1, NULL, run_neighbours},
    [STAGE_NUMBER_DENSITY_START] = {"number_density_start", -1, uses_start_density,
                                    run_number_density_start},
    [STAGE_BODY_MOTION] = {"body_motion", -1, body_motion_wanted, run_body_motion},
    [STAGE_VISCOSITY] = {"viscosity", EFFECT_VISCOSITY, NULL, run_viscosity},
    [STAGE_GRAVITY] = {"gravity", EFFECT_GRAVITY, NULL, run_gravity},
    [STAGE_EXCITATION] = {"excitation", EFFECT_EXCITATION, NULL, run_excitation},
    [STAGE_EXTERNAL_FORCES] = {"external_forces", -1, external_forces_wanted,
                               run_external_forces},
    [STAGE_ADVECTION] = {"advection", -1, NULL, run_advection},
    [STAGE_COLLISION] = {"collision", EFFECT_COLLISION, NULL, run_collision},
    [STAGE_NUMBER_DENSITY] = {"number_density", -1, NULL, run_number_density},
    [STAGE_FREE_SURFACE] = {"free_surface", -1, single_phase, run_free_surface},
    [STAGE_PRESSURE_ASSEMBLY] = {"pressure_assembly", -1, single_phase, run_pressure_assembly},
    [STAGE_PRESSURE_SOLVE] = {"pressure_solve", -1, single_phase, run_pressure_solve},
    [STAGE_CORRECTION] = {"correction", -1, single_phase, run_correction},
    [STAGE_DIVERGENCE_CHECK] = {"divergence_check", -1, NULL, run_divergence_check},
    [STAGE_PHASES_START] = {"phases_start", EFFECT_TWO_PHASE, NULL, run_phases_start},
    [STAGE_INTERFACE_SCAN] = {"interface_scan", EFFECT_TWO_PHASE, NULL, run_interface_scan},
    [STAGE_INTERFACE_JOIN] = {"interface_join", EFFECT_INTERFACE_REACTION, NULL,
                              run_interface_join},
    [STAGE_LIQUID_PRESSURE] = {"liquid_pressure", EFFECT_TWO_PHASE, NULL, run_liquid_pressure},
    [STAGE_GAS_PRESSURE] = {"gas_pressure", EFFECT_TWO_PHASE, NULL, run_gas_pressure},
    [STAGE_TWO_PHASE_CORRECTION] = {"two_phase_correction", EFFECT_TWO_PHASE, NULL,
                                    run_two_phase_correction},
    [STAGE_INTERFACE_DRIFT] = {"interface_drift", EFFECT_INTERFACE_REACTION, drift_reaction,
                               run_interface_drift},
    [STAGE_TURBULENCE] = {"turbulence", EFFECT_TURBULENCE, NULL, run_turbulence},
    [STAGE_NEIGHBOUR_COUNT] = {"neighbour_count", -1, counts_neighbours, run_neighbour_count},
    [STAGE_GAS_DIVERGENCE_CHECK] = {"gas_divergence_check", EFFECT_TWO_PHASE, NULL,
                                    run_gas_divergence_check},
};

/* One MPS step (docs/method.md section 1, fig. 1 of the paper), in order. The
 * neighbour list is brought up to date after each stage that moves particles.
 * Host-moved walls move first, so that viscosity sees their velocity. With
 * two phases (docs/method.md 2-3) the liquid's own n^k is taken at the start, and
 * the free surface, PPE and correction are replaced by the sector scan, the
 * liquid then the gas PPE and a correction per phase; the gas's own check
 * runs before the general one (its message says more about a squeezed gas
 * particle). */
static const int sequence[] = {
    STAGE_NEIGHBOURS,       STAGE_NUMBER_DENSITY_START, STAGE_PHASES_START,
    STAGE_BODY_MOTION,      STAGE_VISCOSITY,            STAGE_TURBULENCE,
    STAGE_GRAVITY,          STAGE_EXCITATION,
    STAGE_EXTERNAL_FORCES,  STAGE_ADVECTION,            STAGE_NEIGHBOURS,
    STAGE_COLLISION,        STAGE_NEIGHBOURS,           STAGE_NUMBER_DENSITY,
    STAGE_NEIGHBOUR_COUNT,  STAGE_FREE_SURFACE,     STAGE_PRESSURE_ASSEMBLY,    STAGE_PRESSURE_SOLVE,
    STAGE_INTERFACE_SCAN,   STAGE_INTERFACE_JOIN,       STAGE_LIQUID_PRESSURE,
    STAGE_GAS_PRESSURE,     STAGE_CORRECTION,           STAGE_TWO_PHASE_CORRECTION,
    STAGE_INTERFACE_DRIFT,  STAGE_GAS_DIVERGENCE_CHECK, STAGE_DIVERGENCE_CHECK,
};
#define SEQUENCE_LENGTH (sizeof sequence / sizeof sequence[0])

static int stage_active(const mps2p_solver *s, int stage)
{
    const stage_entry *e = &stages[stage];
    return (e->effect < 0 || s->effect_active[e->effect]) && (!e->wanted || e->wanted(s));
}

int plan_build(mps2p_solver *s)
{
    int status = effects_decide(s);
    if (status != MPS2P_OK)
        return status;
    s->plan_length = 0;
    for (size_t k = 0; k < SEQUENCE_LENGTH; k++) {
        int stage = sequence[k];
        if (!stage_active(s, stage))
            continue;
        /* nothing moved since the last neighbour update: skip the repeat */
        if (stage == STAGE_NEIGHBOURS && s->plan_length > 0 &&
            s->plan[s->plan_length - 1] == STAGE_NEIGHBOURS)
            continue;
        s->plan[s->plan_length++] = stage;
    }
    for (int stage = 0; stage < STAGE_COUNT; stage++)
        s->stage_active[stage] = stage_active(s, stage);
    /* arrays of stages that are off are never allocated */
    if (s->stage_active[STAGE_NEIGHBOUR_COUNT] && !s->neighbour_count) {
        s->neighbour_count = calloc(s->count, sizeof *s->neighbour_count);
        if (!s->neighbour_count)
            return fail(NULL, MPS2P_ERR_NOMEM, "out of memory for %zu neighbour counts",
                        s->count);
    }
    if (s->stage_active[STAGE_TURBULENCE] && !s->eddy_viscosity) {
        s->eddy_viscosity = calloc(s->count, sizeof *s->eddy_viscosity);
        if (!s->eddy_viscosity)
            return fail(NULL, MPS2P_ERR_NOMEM, "out of memory for %zu eddy viscosities",
                        s->count);
    }
    if (s->stage_active[STAGE_NUMBER_DENSITY_START] && !s->number_density_start) {
        s->number_density_start = calloc(s->count, sizeof *s->number_density_start);
        if (!s->number_density_start)
            return fail(NULL, MPS2P_ERR_NOMEM, "out of memory for %zu number densities",
                        s->count);
    }
    if (s->effect_active[EFFECT_TWO_PHASE] && !s->phases && phases_init(s) != MPS2P_OK)
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory for the two-phase state of %zu "
                    "particles", s->count);
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
    if (active)
        *active = s->stage_active[index];
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
