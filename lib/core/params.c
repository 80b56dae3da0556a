/* The numeric parameters: names, defaults, documentation and valid ranges. */
#include "numerics/numerics.h"
#include "core/core.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

typedef struct param_entry {
    const char *key;
    size_t offset;
    double default_value;
    double min, max;   /* inclusive valid range */
    const char *description;
} param_entry;

#define FIELD(name) offsetof(params, name)
#define BIG 1e300

static const param_entry table[] = {
    {"re_density", FIELD(re_density), 2.1, 1.0, 10.0,
     "radius of number density and gradient, in l0"},
    {"re_laplacian", FIELD(re_laplacian), 3.1, 1.0, 10.0,
     "radius of the Laplacian, in l0"},
    {"beta", FIELD(beta), 0.97, 0.0, 1.0,
     "free surface when the number density is below beta n0"},
    {"gravity_x", FIELD(gravity[0]), 0.0, -BIG, BIG, "gravity, x (m/s^2)"},
    {"gravity_y", FIELD(gravity[1]), -9.81, -BIG, BIG, "gravity, y (m/s^2)"},
    {"dt", FIELD(dt), 0.0, 0.0, BIG, "fixed time step (s); 0 = adaptive"},
    {"cfl", FIELD(cfl), 0.2, 1e-6, 1.0, "adaptive dt <= cfl l0 / max speed"},
    {"diffusion_number", FIELD(diffusion_number), 0.2, 1e-6, 0.5,
     "adaptive dt <= diffusion_number l0^2 / nu"},
    {"gravity_number", FIELD(gravity_number), 0.03, 0.0, 1.0,
     "adaptive dt <= gravity_number sqrt(l0 / |g|); 0 = no such limit"},
    {"dt_max", FIELD(dt_max), 0.0, 0.0, BIG,
     "largest adaptive dt (s); 0 = cfl l0 / max(sqrt(2 |g| H), the fastest initial fluid speed), "
     "H the initial fluid height"},
    {"collision_distance", FIELD(collision_distance), 0.995, 0.0, 1.0,
     "too-close distance of the collision model, in l0; 0 = off"},
    {"collision_time", FIELD(collision_time), 0.03, 0.0, 1e6,
     "the collision model gives dt / tau of its impulse a step (at most all), tau = "
     "collision_time sqrt(l0 / |g|); 0, or no gravity, = all of it every step"},
    {"collision_core", FIELD(collision_core), 0.5, 0.0, 1.0,
     "in l0: a pair closer than it (and than collision_distance) after the move loses its "
     "whole approach in the step, whatever collision_time (Koshizuka and Oka's collision "
     "distance; air meeting water keeps its own rules); 0 = none"},
    {"collision_restitution", FIELD(collision_restitution), 0.2, 0.0, 1.0,
     "restitution coefficient of the collision model"},
    {"shifting", FIELD(shifting), 0.04, 0.0, 1.0,
     "particle shifting: a fluid particle off the free surface moves shifting u_max dt "
     "sum_j (rbar_i / r_ij)^2 e_ji a step (u_max the fastest fluid speed), away from close "
     "neighbours (single phase); 0 = off"},
    {"ppe_step_gain", FIELD(ppe_step_gain), 0.4, 0.01, 1.0,
     "share of this step's own compression, n* - n^k, that the ecs and mixed PPE sources "
     "answer in the step (the rest stays in the density error their other term answers); "
     "one phase and the single two-phase model: the two-step models' liquid, not shifted, "
     "answers in full"},
    {"ppe_relaxation", FIELD(ppe_relaxation), 0.2, 1e-6, 1.0,
     "relaxation factor on the PPE source term"},
    {"compressibility", FIELD(compressibility), 4.5e-10, 0.0, 1.0,
     "compressibility on the PPE diagonal (1/Pa)"},
    {"clamp_negative_pressure", FIELD(clamp_negative_pressure), 1.0, 0.0, 1.0,
     "1 = negative pressures set to 0, 0 = kept"},
    {"cg_tolerance", FIELD(cg_tolerance), 1e-9, 1e-16, 1e-1,
     "relative residual of the CG pressure solver"},
    {"cg_max_iterations", FIELD(cg_max_iterations), 0.0, 0.0, 1e9,
     "CG iteration limit; 0 = 10 unknowns + 100"},
    {"pressure_limit", FIELD(pressure_limit), 0.0, 0.0, BIG,
     "|p| above it means diverged (Pa); 0 = 1000 rho_max max(|g| L, 1 m^2/s^2)"},
    {"displacement_limit", FIELD(displacement_limit), 1.0, 0.0, BIG,
     "a particle moving farther in one step means diverged, in l0; 0 = no check"},
    /* spray thrown over a wall must not end a run (DualSPHysics's excluded
     * particles); walls and dummies leaving the domain always diverge */
    {"out_limit", FIELD(out_limit), 0.01, 0.0, 1.0,
     "share of the fluid particles (of those at the start) that may leave the domain and "
     "go out of the run (kind MPS2P_KIND_OUT) before the run counts as diverged; 0 = any "
     "fluid particle leaving it means diverged"},
    {"beta_count", FIELD(beta_count), 0.85, 0.0, 1.0,
     "free_surface \"neighbour_count\": surface below beta_count N0 neighbours"},
    {"smagorinsky_constant", FIELD(smagorinsky_constant), 0.1, 0.0, 1.0,
     "Cs of the turbulence effect's eddy viscosity (Cs l0)^2 |S|"},
    {"neighbour_skin", FIELD(neighbour_skin), 0.4, 0.0, 5.0,
     "extra radius of the neighbour list, in l0"},
    {"excitation_acceleration", FIELD(excitation_acceleration), 0.0, -BIG, BIG,
     "amplitude A of the tank's horizontal acceleration A sin(2 pi t / T), m/s^2 (effect "
     "excitation)"},
    {"excitation_period", FIELD(excitation_period), 1.0, 1e-9, BIG,
     "period T of the tank's horizontal oscillation, s (effect excitation)"},
    /* 1 by default: a library embedded in a host program starts no threads
     * unasked, and on a busy machine more threads than free cores are slower
     * (docs/performance.md) */
    {"threads", FIELD(threads), 1.0, 0.0, 1024.0,
     "threads of the particle loops (OpenMP); 0 = OpenMP's default (OMP_NUM_THREADS); "
     "the same result bits for any count"},
    /* two phases (docs/two-phase.md): read only when effect two_phase is on */
    {"light_fraction", FIELD(light_fraction), 0.1, 1e-9, 1.0,
     "a fluid lighter than this fraction of the heaviest is light (two-phase)"},
    {"sector_scan_walls", FIELD(sector_scan_walls), 1.0, 0.0, 1.0,
     "1 = wall particles count as heavy (velocity 0) in the 8-sector scan"},
    {"trigger_speed", FIELD(trigger_speed), 1.0, 0.0, 100.0,
     "the 8-sector scan triggers when opposite sectors close faster than trigger_speed "
     "sqrt(|g| l0) (gravity's size, so 0 without gravity); 0 = the paper's u_a < u_{a+4}"},
    {"join_bubbles", FIELD(join_bubbles), 1.0, 0.0, 1.0,
     "1 = light particles cut off from the gas's free surface (no path through light "
     "neighbours within re_density: an enclosed bubble) react as triggered ones"},
    {"join_enclosed", FIELD(join_enclosed), 1.0, 0.0, 1.0,
     "1 = light particles with heavy ones in all 8 sectors react as triggered ones"},
    {"bubble_rise_velocity", FIELD(bubble_rise_velocity), 0.2, 0.0, 100.0,
     "rise velocity of a joined light particle relative to the liquid, against gravity, m/s "
     "(drift; none without gravity)"},
    {"bubble_relaxation_time", FIELD(bubble_relaxation_time), 0.02, 1e-9, 1e6,
     "relaxation time of a joined light particle's slip toward the rise velocity, s (drift)"},
    {"join_ramp_time", FIELD(join_ramp_time), 0.0, 0.0, 1e6,
     "time over which a joining light particle's weight in the liquid number density ramps "
     "0 to 1, s"},
    {"gas_liquid_volume", FIELD(gas_liquid_volume), 2.0, 0.0, 2.0,
     "gas's number density: a liquid particle weighs 1 (0), n0 / n_liquid (1) or its initial "
     "n_liquid / n_liquid (2), in [1, 2] (two_step_improved)"},
    {"gas_cg_tolerance", FIELD(gas_cg_tolerance), 0.0, 0.0, 1e-1,
     "relative residual of the gas CG solve; 0 = cg_tolerance"},
    {"join_hold", FIELD(join_hold), 1.0, 0.0, 1.0,
     "1 = a joined light particle stays joined while more heavy than light neighbours"},
    {"drift_without_gravity", FIELD(drift_without_gravity), 1.0, 0.0, 1.0,
     "1 = a drift bubble does not feel gravity (its weight and buoyancy are in the rise "
     "velocity), 0 = it does"},
    {"gas_correction_limit", FIELD(gas_correction_limit), 0.2, 0.0, BIG,
     "largest velocity change the gas pressure gives a light particle in one step, in l0 / dt "
     "(two_step_improved); 0 = none"},
    /* the gas's top boundary (docs/two-phase.md, the ladder's rung 6) */
    {"gas_buffer_depth", FIELD(gas_buffer_depth), 5.0, 0.0, 1e6,
     "depth of the gas's damping layer under the gas's top at the first step, in l0 (effect "
     "gas_buffer); 0 = none, an open top"},
    {"gas_buffer_rate", FIELD(gas_buffer_rate), 500.0, 0.0, 1e12,
     "damping rate of a gas particle's velocity at the damping layer's top and above, 1/s; "
     "it grows as the square of the depth into the layer; 0 = no layer"},
    {"gas_pressure_limit", FIELD(gas_pressure_limit), 0.0, 0.0, BIG,
     "|gas pressure| above it means diverged (Pa); 0 = 1000 rho_light max(|g| L, 1 m^2/s^2)"},
    /* checked before allocating: with overcommit, malloc of too much succeeds and the
     * kernel kills the process later, while the pages are written (issue 20) */
    {"memory_limit", FIELD(memory_limit), 0.0, 0.0, BIG,
     "bytes a scene or a solver may take (checked when it grows or is created); 0 = the "
     "memory the system gives the process (physical, rlimit, cgroup)"},
};

#define TABLE_SIZE (sizeof table / sizeof table[0])

/* The named schemes (option "scheme"): each sets the pressure gradient, the
 * PPE source and its gain on the step's compression, the walls' ghosts, the
 * free surface's pressure, the Laplacian radius, the collision distance,
 * time and core, the gravity limit on dt and particle shifting together.
 * The first is the default; docs/validation.md measures both and says why
 * the default is what it is. */
typedef struct scheme_entry {
    const char *name;
    int pressure_gradient, ppe_source, wall_ghosts, surface_pressure;
    double re_laplacian, collision_distance, collision_time, gravity_number, shifting;
    double ppe_step_gain, collision_core;
} scheme_entry;

static const scheme_entry schemes[] = {
    /* Khayyer and Gotoh's corrected gradient and error-compensating source,
     * dummies and dry walls as hydrostatic ghosts, collision as a damper of
     * every approaching pair closer than the lattice spacing at a rate that
     * does not grow as dt shrinks and whole inside half a spacing, a gravity
     * limit on dt; the source answers 0.4 of each step's compression, which
     * takes two fifths off the spray and the impact's pressure noise
     * (docs/validation.md) */
    {"corrected", GRADIENT_CORRECTED, PPE_SOURCE_ECS, WALL_GHOSTS_HYDROSTATIC,
     SURFACE_PRESSURE_EXTRAPOLATED, 3.1, 0.995, 0.03, 0.03, 0.04, 0.4, 0.5},
    /* Koshizuka and Oka (1996), as docs/method.md restates it: the paper's
     * scheme (its density source has no step term; its collision is whole) */
    {"koshizuka1996", GRADIENT_MINIMUM, PPE_SOURCE_DENSITY, WALL_GHOSTS_NONE,
     SURFACE_PRESSURE_CENTRE, 4.0, 0.5, 0.0, 0.0, 0.0, 1.0, 0.5},
};
#define SCHEME_COUNT (sizeof schemes / sizeof schemes[0])

static void scheme_apply(params *p, const scheme_entry *e)
{
    p->pressure_gradient = e->pressure_gradient;
    p->ppe_source = e->ppe_source;
    p->wall_ghosts = e->wall_ghosts;
    p->surface_pressure = e->surface_pressure;
    p->re_laplacian = e->re_laplacian;
    p->collision_distance = e->collision_distance;
    p->collision_time = e->collision_time;
    p->gravity_number = e->gravity_number;
    p->shifting = e->shifting;
    p->ppe_step_gain = e->ppe_step_gain;
    p->collision_core = e->collision_core;
}

/* The scheme the settings are, or NULL when one of them was changed. */
static const scheme_entry *scheme_of(const params *p)
{
    for (size_t i = 0; i < SCHEME_COUNT; i++) {
        const scheme_entry *e = &schemes[i];
        if (p->pressure_gradient == e->pressure_gradient && p->ppe_source == e->ppe_source &&
            p->wall_ghosts == e->wall_ghosts && p->surface_pressure == e->surface_pressure &&
            p->re_laplacian == e->re_laplacian &&
            p->collision_distance == e->collision_distance &&
            p->collision_time == e->collision_time && p->gravity_number == e->gravity_number &&
            p->shifting == e->shifting && p->ppe_step_gain == e->ppe_step_gain &&
            p->collision_core == e->collision_core)
            return e;
    }
    return NULL;
}

static const param_entry *find(const char *key)
{
    for (size_t i = 0; i < TABLE_SIZE; i++)
        if (strcmp(table[i].key, key) == 0)
            return &table[i];
    return NULL;
}

/* Edit distance (insertions, deletions, substitutions) of two short keys;
 * longer keys than KEY_MAX count as far from everything. */
#define KEY_MAX 64
/* not tolower: the keys are ASCII, and a locale must not change the match */
static char ascii_lower(char c) { return c >= 'A' && c <= 'Z' ? (char)(c - 'A' + 'a') : c; }

static size_t edit_distance(const char *a, const char *b)
{
    size_t n = strlen(a), m = strlen(b);
    if (n >= KEY_MAX || m >= KEY_MAX)
        return (size_t)-1;
    size_t row[KEY_MAX + 1];
    for (size_t j = 0; j <= m; j++)
        row[j] = j;
    for (size_t i = 1; i <= n; i++) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= m; j++) {
            size_t above = row[j];
            /* ASCII case does not count: "CFL" is a slip for "cfl" */
            size_t best = diagonal + (ascii_lower(a[i - 1]) != ascii_lower(b[j - 1]));
            if (above + 1 < best)
                best = above + 1;
            if (row[j - 1] + 1 < best)
                best = row[j - 1] + 1;
            row[j] = best;
            diagonal = above;
        }
    }
    return row[m];
}

void near_miss(const char *key, const char *(*name_at)(size_t), size_t count, char *out,
               size_t size)
{
    const char *nearest = NULL;
    size_t best = (size_t)-1;
    for (size_t i = 0; i < count; i++) {
        size_t d = edit_distance(key, name_at(i));
        if (d < best) {
            best = d;
            nearest = name_at(i);
        }
    }
    size_t allowed = strlen(key) / 3 > 2 ? strlen(key) / 3 : 2;
    if (nearest && best <= allowed) {
        snprintf(out, size, " (did you mean \"%s\"?)", nearest);
        return;
    }
    /* no near miss: a name that holds the key ("solver" in "pressure_solver"),
     * else one that starts with the key's first word ("excitation_amplitude":
     * "excitation_acceleration") */
    const size_t length = strlen(key);
    const char *underscore = strchr(key, '_');
    const size_t word = underscore ? (size_t)(underscore - key) : 0;
    const char *holds = NULL, *shares = NULL;
    for (size_t i = 0; i < count && length >= 4; i++) {
        const char *name = name_at(i);
        if (!holds && strstr(name, key))
            holds = name;
        if (!shares && word >= 4 && strncmp(name, key, word + 1) == 0)
            shares = name;
    }
    if (holds || shares)
        snprintf(out, size, " (did you mean \"%s\"?)", holds ? holds : shares);
    else if (size > 0)
        out[0] = '\0';
}

static const char *param_name_at(size_t i) { return table[i].key; }

static double *slot(params *p, const param_entry *e)
{
    return (double *)((char *)p + e->offset);
}

void params_set_defaults(params *p)
{
    for (size_t i = 0; i < TABLE_SIZE; i++)
        *slot(p, &table[i]) = table[i].default_value;
    p->pressure_solver = PRESSURE_SOLVER_CG;
    p->cg_preconditioner = CG_PRECONDITIONER_TWO_LEVEL;
    p->ppe_pattern = PPE_PATTERN_DISTANCE;
    scheme_apply(p, &schemes[0]);
    p->free_surface = FREE_SURFACE_NUMBER_DENSITY;
    p->two_phase_model = TWO_PHASE_IMPROVED;
    /* the one form left: the ladder's (docs/two-phase.md) */
    p->interface_reaction = REACTION_DRIFT;
    for (int e = 0; e < EFFECT_COUNT; e++)
        p->effect_mode[e] = EFFECT_AUTO;
}

int params_set(params *p, const char *key, double value, char *message, size_t size)
{
    const param_entry *e = find(key);
    if (!e) {
        char hint[KEY_MAX + 32];
        near_miss(key, param_name_at, TABLE_SIZE, hint, sizeof hint);
        snprintf(message, size, "unknown parameter \"%s\"%s", key, hint);
        return MPS2P_ERR_UNKNOWN_KEY;
    }
    if (!isfinite(value)) {
        snprintf(message, size, "parameter %s must be finite, got %g", key, value);
        return MPS2P_ERR_INVALID;
    }
    if (value < e->min || value > e->max) {
        snprintf(message, size, "parameter %s must be in [%g, %g], got %g",
                 key, e->min, e->max, value);
        return MPS2P_ERR_INVALID;
    }
    if ((strcmp(key, "cg_max_iterations") == 0 || strcmp(key, "threads") == 0) &&
        value != floor(value)) {
        snprintf(message, size, "parameter %s must be a whole number, got %g", key, value);
        return MPS2P_ERR_INVALID;
    }
    static const char *const switches[] = {"clamp_negative_pressure", "sector_scan_walls",
                                           "join_enclosed", "join_hold",
                                           "join_bubbles"};
    for (size_t i = 0; i < sizeof switches / sizeof switches[0]; i++) {
        if (strcmp(key, switches[i]) == 0 && value != 0.0 && value != 1.0) {
            snprintf(message, size, "parameter %s must be 0 or 1, got %g", key, value);
            return MPS2P_ERR_INVALID;
        }
    }
    if (strcmp(key, "gas_liquid_volume") == 0 && value != 0.0 && value != 1.0 && value != 2.0) {
        snprintf(message, size, "parameter %s must be 0, 1 or 2, got %g", key, value);
        return MPS2P_ERR_INVALID;
    }
    *slot(p, e) = value;
    return MPS2P_OK;
}

int params_get(const params *p, const char *key, double *value)
{
    const param_entry *e = find(key);
    if (!e)
        return MPS2P_ERR_UNKNOWN_KEY;
    *value = *slot((params *)p, e);
    return MPS2P_OK;
}

/* The named choices: each maps a few names onto an int field of params
 * (the index of the name is the stored value; the default is the first,
 * except interface_reaction and those a scheme sets, set in
 * params_set_defaults). "scheme" is not one of them: it sets several. */
typedef struct option_entry {
    const char *key;
    size_t offset;
    const char *names[7]; /* NULL-terminated */
    const char *description;
} option_entry;

#define EFFECT_CHOICES "auto: on when the scene needs it; on: required; off: left out"
/* "gamg" keeps its index in every build (checkpoints name it; a build
 * without PETSc refuses it by name and does not list it, see choice_count). */
#ifdef MPS2P_HAVE_PETSC
#define PRESSURE_SOLVER_DESCRIPTION                                                        \
    "the pressure solver: sparse direct (cholmod), preconditioned conjugate gradients "   \
    "(cg), or CG with PETSc's algebraic multigrid (gamg)"
#else
#define PRESSURE_SOLVER_DESCRIPTION                                                        \
    "the pressure solver: sparse direct (cholmod) or preconditioned conjugate gradients "  \
    "(cg); gamg (PETSc's algebraic multigrid) is not in this build (meson option petsc)"
#endif
static const option_entry options[] = {
    {"pressure_solver", offsetof(params, pressure_solver), {"cholmod", "cg", "gamg", NULL},
     PRESSURE_SOLVER_DESCRIPTION},
    {"cg_preconditioner", offsetof(params, cg_preconditioner), {"jacobi", "ic0", "two_level", NULL},
     "CG's preconditioner: the diagonal (jacobi), incomplete Cholesky (ic0), or the diagonal "
     "plus a coarse correction on aggregates of neighbouring unknowns (two_level)"},
    {"pressure_gradient", offsetof(params, pressure_gradient), {"minimum", "corrected", NULL},
     "corrected: p_i as reference and the corrective matrix; minimum: Koshizuka and Oka's, "
     "the least pressure around as reference"},
    {"ppe_source", offsetof(params, ppe_source), {"density", "mixed", "ecs", NULL},
     "the PPE's source: error-compensating (ecs), gamma (n* - n0) (density), or mixed"},
    {"ppe_pattern", offsetof(params, ppe_pattern), {"distance", "neighbour_list", NULL},
     "the PPE matrix's pattern: pairs within re_laplacian, or every pair of the neighbour "
     "list (CHOLMOD's analysis reused while the list stands)"},
    {"wall_ghosts", offsetof(params, wall_ghosts), {"none", "hydrostatic", NULL},
     "dummies and dry walls as hydrostatic ghosts p_i + rho_i g . r_ij, or not"},
    {"surface_pressure", offsetof(params, surface_pressure), {"centre", "extrapolated", NULL},
     "a free-surface fluid particle's pressure: 0 at its centre, or an unknown whose "
     "pressure reaches 0 half a spacing beyond it (the water's top)"},
    {"free_surface", offsetof(params, free_surface), {"number_density", "neighbour_count", NULL},
     "free surface where n* < beta n0, or also where a particle has few neighbours"},
    {"two_phase_model", offsetof(params, two_phase_model),
     {"two_step_improved", "two_step", "single", NULL},
     "two phases: the improved model, Koshizuka's conventional two-step model, or one PPE "
     "over every fluid"},
    {"interface_reaction", offsetof(params, interface_reaction),
     {"drift", NULL},
     "what delta_al = 1 does in two_step_improved: the bubble drift closure, the one form "
     "left (docs/two-phase.md has the others' record)"},
#define EFFECT_OPTION(key, effect)                                                         \
    {key, offsetof(params, effect_mode) + (effect) * sizeof(int), {"auto", "on", "off", NULL}, \
     EFFECT_CHOICES}
    EFFECT_OPTION("effect.gravity", EFFECT_GRAVITY),
    EFFECT_OPTION("effect.excitation", EFFECT_EXCITATION),
    EFFECT_OPTION("effect.viscosity", EFFECT_VISCOSITY),
    EFFECT_OPTION("effect.collision", EFFECT_COLLISION),
    EFFECT_OPTION("effect.two_phase", EFFECT_TWO_PHASE),
    EFFECT_OPTION("effect.interface_reaction", EFFECT_INTERFACE_REACTION),
    EFFECT_OPTION("effect.turbulence", EFFECT_TURBULENCE),
    EFFECT_OPTION("effect.gas_buffer", EFFECT_GAS_BUFFER),
#undef EFFECT_OPTION
};

#define OPTION_COUNT (sizeof options / sizeof options[0])

static const option_entry *find_option(const char *key)
{
    for (size_t i = 0; i < OPTION_COUNT; i++)
        if (strcmp(options[i].key, key) == 0)
            return &options[i];
    return NULL;
}

static size_t choice_count(size_t index);

static int scheme_set(params *p, const char *value, char *message, size_t size)
{
    for (size_t i = 0; i < SCHEME_COUNT; i++) {
        if (strcmp(value, schemes[i].name) == 0) {
            scheme_apply(p, &schemes[i]);
            return MPS2P_OK;
        }
    }
    char choices[128] = "";
    for (size_t i = 0; i < SCHEME_COUNT; i++) {
        size_t used = strlen(choices);
        snprintf(choices + used, sizeof choices - used, "%s\"%s\"", i ? ", " : "",
                 schemes[i].name);
    }
    snprintf(message, size, "option scheme must be one of %s, got \"%s\"", choices, value);
    return MPS2P_ERR_INVALID;
}

int params_set_option(params *p, const char *key, const char *value,
                      char *message, size_t size)
{
    if (strcmp(key, "scheme") == 0)
        return scheme_set(p, value, message, size);
    const option_entry *e = find_option(key);
    if (!e) {
        char hint[KEY_MAX + 32];
        near_miss(key, params_option_key, OPTION_COUNT + 1, hint, sizeof hint);
        snprintf(message, size, "unknown option \"%s\"%s", key, hint);
        return MPS2P_ERR_UNKNOWN_KEY;
    }
    if (e->offset == offsetof(params, pressure_solver) && strcmp(value, "gamg") == 0 &&
        !linear_solver_have_gamg()) {
        snprintf(message, size, "option pressure_solver \"gamg\" needs PETSc: this libmps2p "
                                "was built without it (meson option petsc)");
        return MPS2P_ERR_INVALID;
    }
    for (int i = 0; e->names[i]; i++) {
        if (strcmp(value, e->names[i]) == 0) {
            *(int *)((char *)p + e->offset) = i;
            return MPS2P_OK;
        }
    }
    char choices[128] = "";
    const size_t listed = choice_count((size_t)(e - options));
    for (size_t i = 0; i < listed; i++) {
        size_t used = strlen(choices);
        snprintf(choices + used, sizeof choices - used, "%s\"%s\"", i ? ", " : "", e->names[i]);
    }
    snprintf(message, size, "option %s must be one of %s, got \"%s\"", key, choices, value);
    return MPS2P_ERR_INVALID;
}

int params_get_option(const params *p, const char *key, const char **value)
{
    if (strcmp(key, "scheme") == 0) {
        const scheme_entry *e = scheme_of(p);
        *value = e ? e->name : "custom";
        return MPS2P_OK;
    }
    const option_entry *e = find_option(key);
    if (!e)
        return MPS2P_ERR_UNKNOWN_KEY;
    *value = e->names[*(const int *)((const char *)p + e->offset)];
    return MPS2P_OK;
}

const char *params_key(size_t index)
{
    return index < TABLE_SIZE ? table[index].key : NULL;
}

const char *params_option_key(size_t index)
{
    if (index < OPTION_COUNT)
        return options[index].key;
    return index == OPTION_COUNT ? "scheme" : NULL;
}

double params_max_radius(const params *p)
{
    return fmax(p->re_density, p->re_laplacian);
}

int mps2p_param_info(size_t index, const char **key, const char **description,
                     double *default_value)
{
    error_clear();
    if (index >= TABLE_SIZE)
        return fail(NULL, MPS2P_ERR_INVALID, "parameter index %zu is past the last (%zu)",
                    index, TABLE_SIZE - 1);
    if (key)
        *key = table[index].key;
    if (description)
        *description = table[index].description;
    if (default_value)
        *default_value = table[index].default_value;
    return MPS2P_OK;
}

int mps2p_param_count(size_t *count)
{
    error_clear();
    if (!count)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_param_count: count is NULL");
    *count = TABLE_SIZE;
    return MPS2P_OK;
}

/* The options, then "scheme" (it sets several of the others). */
#define SCHEME_DESCRIPTION                                                                 \
    "sets pressure_gradient, ppe_source, ppe_step_gain, wall_ghosts, surface_pressure, "   \
    "re_laplacian, collision_distance, collision_time, collision_core, gravity_number "    \
    "and shifting together (docs/validation.md); reads custom once one of them differs"

int mps2p_option_count(size_t *count)
{
    error_clear();
    if (!count)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_option_count: count is NULL");
    *count = OPTION_COUNT + 1;
    return MPS2P_OK;
}

static size_t choice_count(size_t index)
{
    if (index == OPTION_COUNT)
        return SCHEME_COUNT;
    size_t n = 0;
    while (options[index].names[n])
        n++;
    if (options[index].offset == offsetof(params, pressure_solver) && !linear_solver_have_gamg())
        n--; /* gamg, the last: not in this build */
    return n;
}

int mps2p_option_info(size_t index, const char **key, const char **description,
                      const char **default_choice, size_t *choices)
{
    error_clear();
    if (index > OPTION_COUNT)
        return fail(NULL, MPS2P_ERR_INVALID, "option index %zu is past the last (%zu)", index,
                    (size_t)OPTION_COUNT);
    const char *name = params_option_key(index);
    if (key)
        *key = name;
    if (description)
        *description = index == OPTION_COUNT ? SCHEME_DESCRIPTION : options[index].description;
    if (default_choice) {
        params defaults;
        params_set_defaults(&defaults);
        params_get_option(&defaults, name, default_choice);
    }
    if (choices)
        *choices = choice_count(index);
    return MPS2P_OK;
}

int mps2p_option_choice(size_t index, size_t choice, const char **name)
{
    error_clear();
    if (index > OPTION_COUNT)
        return fail(NULL, MPS2P_ERR_INVALID, "option index %zu is past the last (%zu)", index,
                    (size_t)OPTION_COUNT);
    if (choice >= choice_count(index))
        return fail(NULL, MPS2P_ERR_INVALID, "option %s has %zu choices, not %zu",
                    params_option_key(index), choice_count(index), choice + 1);
    if (name)
        *name = index == OPTION_COUNT ? schemes[choice].name : options[index].names[choice];
    return MPS2P_OK;
}
