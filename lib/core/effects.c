/* Physical effects: which a scene needs, which the user asked for, and why
 * each is on or off. An effect that is off has its stages left out of the
 * step (solver/plan.c), so it costs nothing. Adding an effect: a row here, its
 * option in params.c, and its stages in solver/plan.c. */
#include "core/core.h"

#include <math.h>
#include <stdio.h>

double light_fluid_density(const mps2p_solver *s, double *heaviest)
{
    double heavy = 0.0, light = 0.0;
    for (int f = 0; f < s->fluid_count; f++)
        heavy = fmax(heavy, s->fluids[f].density);
    const double threshold = s->params.light_fraction * heavy;
    for (int f = 0; f < s->fluid_count; f++)
        if (s->fluids[f].density < threshold)
            light = fmax(light, s->fluids[f].density);
    *heaviest = heavy;
    return light;
}

/* 1 when the scene gives the effect something to act on; says why either way. */
typedef int (*needed_fn)(const mps2p_solver *s, char *why, size_t size);

static int gravity_needed(const mps2p_solver *s, char *why, size_t size)
{
    const double *g = s->params.gravity;
    int needed = g[0] != 0.0 || g[1] != 0.0;
    snprintf(why, size, "gravity is (%g, %g) m/s^2", g[0], g[1]);
    return needed;
}

static int viscosity_needed(const mps2p_solver *s, char *why, size_t size)
{
    int viscous = 0;
    for (int f = 0; f < s->fluid_count; f++)
        viscous += s->fluids[f].viscosity > 0.0;
    snprintf(why, size, "%d of %d fluids have viscosity > 0", viscous, s->fluid_count);
    return viscous > 0;
}

static int collision_needed(const mps2p_solver *s, char *why, size_t size)
{
    snprintf(why, size, "collision_distance is %g l0", s->params.collision_distance);
    return s->params.collision_distance > 0.0;
}

/* A light fluid (density below light_fraction of the heaviest) calls for the
 * two-step pressure; two_phase_model "single" solves one PPE over every fluid
 * instead, so the effect cannot be on then. */
static int two_phase_needed(const mps2p_solver *s, char *why, size_t size)
{
    double heaviest = 0.0, light = light_fluid_density(s, &heaviest);
    if (s->params.two_phase_model == TWO_PHASE_SINGLE) {
        snprintf(why, size, "two_phase_model is \"single\" (one PPE over every fluid)");
        return 0;
    }
    if (light > 0.0)
        snprintf(why, size, "a fluid of %g kg/m^3 is below light_fraction %g of the heaviest "
                 "(%g kg/m^3)", light, s->params.light_fraction, heaviest);
    else
        snprintf(why, size, "no fluid is below light_fraction %g of the heaviest (%g kg/m^3)",
                 s->params.light_fraction, heaviest);
    return light > 0.0;
}

/* The gas acting back on the liquid (docs/method.md 3): the improved model only.
 * Decided after two_phase (effects are decided in table order). */
static int interface_reaction_needed(const mps2p_solver *s, char *why, size_t size)
{
    if (!s->effect_active[EFFECT_TWO_PHASE]) {
        snprintf(why, size, "effect two_phase is off");
        return 0;
    }
    if (s->params.two_phase_model != TWO_PHASE_IMPROVED) {
        snprintf(why, size, "two_phase_model is \"two_step\" (the conventional model: the gas "
                 "never pushes the liquid)");
        return 0;
    }
    const char *form = "?";
    params_get_option(&s->params, "interface_reaction", &form);
    snprintf(why, size, "two_phase_model is \"two_step_improved\", reaction \"%s\"", form);
    return 1;
}

/* Nothing in a scene calls for a turbulence model: it is the user's choice,
 * possible in any scene with fluid. */
static int turbulence_needed(const mps2p_solver *s, char *why, size_t size)
{
    snprintf(why, size, "eddy viscosity (Smagorinsky, Cs = %g) only when asked for",
             s->params.smagorinsky_constant);
    return 0;
}

/* A shaken tank: in the tank's frame the fluid feels minus its acceleration. */
static int excitation_needed(const mps2p_solver *s, char *why, size_t size)
{
    snprintf(why, size, "excitation_acceleration is %g m/s^2 (period %g s)",
             s->params.excitation_acceleration, s->params.excitation_period);
    return s->params.excitation_acceleration != 0.0;
}

/* The gas's top boundary: a layer under the gas's starting top where the
 * gas's velocity is damped, so that gas flung up at an impact stops and
 * falls back instead of leaving the tank (docs/two-phase.md, rung 6). "Up"
 * is against gravity. Decided after gravity and two_phase. */
static int gas_buffer_needed(const mps2p_solver *s, char *why, size_t size)
{
    if (!s->effect_active[EFFECT_TWO_PHASE]) {
        snprintf(why, size, "effect two_phase is off");
        return 0;
    }
    if (!s->effect_active[EFFECT_GRAVITY]) {
        snprintf(why, size, "effect gravity is off (the layer lies against gravity)");
        return 0;
    }
    snprintf(why, size, "gas_buffer_depth is %g l0, gas_buffer_rate %g 1/s",
             s->params.gas_buffer_depth, s->params.gas_buffer_rate);
    return s->params.gas_buffer_depth > 0.0 && s->params.gas_buffer_rate > 0.0;
}

static int always_possible(const mps2p_solver *s)
{
    (void)s;
    return 1;
}

typedef struct effect_entry {
    const char *name; /* its option is "effect.<name>" */
    needed_fn needed;
    int (*possible)(const mps2p_solver *s); /* may be switched on though not needed */
} effect_entry;

static const effect_entry effects[EFFECT_COUNT] = {
    [EFFECT_GRAVITY] = {"gravity", gravity_needed, NULL},
    [EFFECT_VISCOSITY] = {"viscosity", viscosity_needed, NULL},
    [EFFECT_COLLISION] = {"collision", collision_needed, NULL},
    [EFFECT_TWO_PHASE] = {"two_phase", two_phase_needed, NULL},
    [EFFECT_INTERFACE_REACTION] = {"interface_reaction", interface_reaction_needed, NULL},
    [EFFECT_TURBULENCE] = {"turbulence", turbulence_needed, always_possible},
    [EFFECT_EXCITATION] = {"excitation", excitation_needed, NULL},
    [EFFECT_GAS_BUFFER] = {"gas_buffer", gas_buffer_needed, NULL},
};

const char *effect_name(int effect)
{
    return effects[effect].name;
}

int effects_decide(mps2p_solver *s)
{
    for (int e = 0; e < EFFECT_COUNT; e++) {
        char why[EFFECT_REASON_SIZE - 32];
        int needed = effects[e].needed(s, why, sizeof why);
        int mode = s->params.effect_mode[e];
        int possible = needed || (effects[e].possible && effects[e].possible(s));
        if (mode == EFFECT_ON && !possible)
            return fail(NULL, MPS2P_ERR_INVALID,
                        "effect %s is switched on, but the scene cannot support it: %s",
                        effects[e].name, why);
        s->effect_active[e] = mode == EFFECT_AUTO ? needed : mode == EFFECT_ON;
        snprintf(s->effect_reason[e], sizeof s->effect_reason[e], "%s%s",
                 mode == EFFECT_AUTO ? "inferred: "
                 : mode == EFFECT_ON ? "requested: on; "
                                     : "requested: off; ",
                 why);
    }
    return MPS2P_OK;
}

int mps2p_solver_effect_count(const mps2p_solver *s, size_t *count)
{
    error_clear();
    if (!s || !count)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_effect_count: %s is NULL",
                    s ? "count" : "solver");
    *count = EFFECT_COUNT;
    return MPS2P_OK;
}

int mps2p_solver_get_effect(const mps2p_solver *s, size_t index, const char **name,
                            int *active, const char **reason)
{
    error_clear();
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_get_effect: solver is NULL");
    if (index >= EFFECT_COUNT)
        return fail(NULL, MPS2P_ERR_INVALID, "effect index %zu is past the last (%d)", index,
                    EFFECT_COUNT - 1);
    if (name)
        *name = effects[index].name;
    if (active)
        *active = s->effect_active[index];
    if (reason)
        *reason = s->effect_reason[index];
    return MPS2P_OK;
}
