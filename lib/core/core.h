/* What every part shares: errors, the state tables, parameters and options,
 * effects, the scene, the solver's struct and the memory limit (errors.c,
 * fields.c, params.c, effects.c, scene.c, memory_limit.c, version.c). */
#ifndef MPS2P_CORE_H
#define MPS2P_CORE_H

#include "numerics/numerics.h"

#include <limits.h>
#include <stdint.h>

#define ERROR_MESSAGE_SIZE 512
/* Most particles a scene or checkpoint may hold: the pressure matrix's
 * indices are int, and the neighbour lists store 4-byte indices with a mark
 * in the low bit during a build (2 j + 1, numerics.h). */
#define MAX_PARTICLES ((size_t)INT_MAX / 2)
_Static_assert(2 * (MAX_PARTICLES - 1) + 1 <= UINT32_MAX,
               "neighbour indices (marked 2 j + 1) must fit 4 bytes");
/* Particle coordinates must lie within this many l0 of the origin: there a
 * double still resolves 2.2e-7 l0, so boxes keep every lattice site (at
 * 1e11 m a 0.02 m lattice lost particles to rounding). */
#define COORDINATE_LIMIT_L0 1e9
/* A step of mps2p_solver_advance_to shorter than this fraction of the chosen
 * dt solves its pressure as one of this fraction (stages/pressure.c,
 * solver/solver.c). */
#define PPE_MIN_STEP_FRACTION 0.5
#define FLUID_NAME_SIZE 64

/* ---- errors (errors.c) ---- */

/* Formats a message into the thread's last error and, if handle_buffer is
 * non-NULL, into the handle's too; returns status. */
int fail(char *handle_buffer, int status, const char *format, ...)
    __attribute__((format(printf, 3, 4)));
/* Empties the thread's last error: every public function that returns a
 * status calls it first, so a success leaves "" (one thread-local store). */
void error_clear(void);

/* A statistic for mps2p_solver_get_stat and mps2p_stat_info (stats.c). */
typedef struct stat_entry {
    const char *name, *description;
    int is_count; /* a whole number of something */
    double (*value)(const mps2p_solver *s);
} stat_entry;

/* ---- the state tables (fields.c) ---- */

/* One row a member of a struct: an array of width values per particle
 * (FIELD_PER_PARTICLE), or width values. The rows say what is allocated,
 * counted, saved, checkpointed and rolled back; adding a member is a row. */
enum field_type {
    FIELD_DOUBLE, FIELD_INT, FIELD_LONG, FIELD_UNSIGNED,
    FIELD_FLAG,   /* unsigned char, 0 or 1 */
    FIELD_SIZE,   /* a size_t value (no arrays); uint64 in a checkpoint */
    FIELD_U64,
    FIELD_PARAMS  /* a struct params */
};
enum field_flags {
    FIELD_PER_PARTICLE = 1 << 0,
    FIELD_SAVED = 1 << 1,        /* in an mps2p_state, put back by restore_state */
    FIELD_MATCHED = 1 << 2,      /* in an mps2p_state, which fits only where it is equal */
    FIELD_CHECKPOINTED = 1 << 3, /* written to and read from checkpoints */
    FIELD_ROLLED_BACK = 1 << 4,  /* put back when a step fails */
    FIELD_ON_DEMAND = 1 << 5,    /* allocated when a stage of the plan needs it */
    FIELD_OPTIONAL = 1 << 6      /* absent from older checkpoints: read as 0 there */
};
typedef struct field {
    const char *name; /* in checkpoints and messages */
    size_t offset;    /* of the member: the array's pointer, or the values */
    unsigned char type, width;
    unsigned short flags;
} field;
typedef struct field_table {
    const field *rows;
    size_t count;
} field_table;

extern const field_table solver_fields; /* struct mps2p_solver's */
size_t field_element_size(const field *f);
/* Bytes of the member's values for count particles. */
size_t field_bytes(const field *f, size_t count);
/* The values: the array a per-particle member points to, else the member. */
void *field_data(const void *object, const field *f);
/* Allocates (zeroed) the row's array where it is not allocated yet. */
int field_allocate(const field *f, void *object, size_t count);
/* The same for the rows with any flag of with (0: every row) and none of
 * without. */
int fields_allocate(const field_table *t, void *object, size_t count, unsigned with,
                    unsigned without);
void fields_free(const field_table *t, void *object);
/* Bytes of the arrays the object holds. */
size_t fields_memory(const field_table *t, const void *object, size_t count);
/* Copies the rows with any flag of with; both hold their arrays. */
void fields_copy(const field_table *t, void *to, const void *from, size_t count,
                 unsigned with);
/* 1 when the rows with any flag of with are equal, scalars compared first. */
int fields_equal(const field_table *t, const void *a, const void *b, size_t count,
                 unsigned with);
/* The row of the member at offset, or NULL. */
const field *field_at(const field_table *t, size_t offset);

/* ---- parameters and options (params.c) ---- */

enum pressure_gradient_kind { GRADIENT_MINIMUM = 0, GRADIENT_CORRECTED = 1 };
enum free_surface_kind { FREE_SURFACE_NUMBER_DENSITY = 0, FREE_SURFACE_NEIGHBOUR_COUNT = 1 };
enum ppe_source_kind { PPE_SOURCE_DENSITY = 0, PPE_SOURCE_MIXED = 1, PPE_SOURCE_ECS = 2 };
/* The PPE matrix's pattern: the pairs within re_laplacian, or every pair of
 * the neighbour list (zeros beyond re_laplacian), which stands as long as
 * the list and the unknowns do, so CHOLMOD's analysis is reused (stages/pressure.c). */
enum ppe_pattern_kind { PPE_PATTERN_DISTANCE = 0, PPE_PATTERN_NEIGHBOUR_LIST = 1 };
/* What dummy walls, and walls with no fluid around them (free surface),
 * stand for in the PPE and the pressure gradient (stages/pressure.c,
 * stages/correction.c). */
enum wall_ghosts_kind {
    WALL_GHOSTS_NONE = 0,       /* Koshizuka and Oka: dummies only fill n, a dry wall p = 0 */
    WALL_GHOSTS_HYDROSTATIC = 1 /* p_j = p_i + rho_i g . r_ij, seen from each particle i */
};
/* The pressure of a free-surface fluid particle (stages/pressure.c). */
enum surface_pressure_kind {
    SURFACE_PRESSURE_CENTRE = 0,      /* Koshizuka and Oka: p = 0 at its centre */
    SURFACE_PRESSURE_EXTRAPOLATED = 1 /* an unknown; p = 0 half a spacing beyond it */
};
/* Two-phase model (effects two_phase and interface_reaction; two_phase/). */
enum two_phase_model_kind {
    TWO_PHASE_IMPROVED = 0, /* two_step_improved: the default */
    TWO_PHASE_TWO_STEP = 1, /* two_step: Koshizuka's conventional model */
    TWO_PHASE_SINGLE = 2    /* single: one PPE over every fluid */
};
/* What delta_al = 1 does (two_phase/interface_reaction.c). The forms that lost
 * (volume, wall, pair, push, continuity) are in docs/two-phase.md's record. */
enum interface_reaction_kind {
    REACTION_DRIFT = 0 /* joins the liquid solve, moves with the liquid plus a rise velocity */
};

/* Physical effects (effects.c); each is switched by option "effect.<name>". */
enum effect_id {
    EFFECT_GRAVITY,
    EFFECT_VISCOSITY,
    EFFECT_COLLISION,
    EFFECT_TWO_PHASE,          /* two-step pressure, liquid and gas (docs/method.md 2) */
    EFFECT_INTERFACE_REACTION, /* gas acting back on the liquid (docs/method.md 3); needs two_phase */
    EFFECT_TURBULENCE,         /* Smagorinsky eddy viscosity; only when requested */
    EFFECT_EXCITATION,         /* horizontal base excitation (a shaken tank) */
    EFFECT_GAS_BUFFER,         /* the gas's top: a damping layer (two_phase/gas_buffer.c) */
    EFFECT_COUNT
};
enum effect_mode { EFFECT_AUTO = 0, EFFECT_ON = 1, EFFECT_OFF = 2 };

typedef struct params {
    double re_density;
    double re_laplacian;
    double beta;
    double gravity[2];
    double dt;
    double cfl;
    double diffusion_number;
    double gravity_number;
    double dt_max;
    double collision_distance;
    double collision_time;
    double collision_restitution;
    double shifting;
    double ppe_step_gain;      /* share of this step's compression the ecs/mixed source answers */
    double collision_core;     /* in l0: inside it a pair's approach goes whole in one step */
    double ppe_relaxation;
    double compressibility;
    double clamp_negative_pressure;
    double cg_tolerance;
    double cg_max_iterations;
    double pressure_limit;
    double displacement_limit;
    double out_limit;          /* share of the fluid that may leave the domain (divergence.c) */
    double neighbour_skin;
    double light_fraction;     /* a fluid is light below this fraction of the heaviest */
    double sector_scan_walls;  /* 1 = walls count as heavy in the 8-sector scan */
    double join_enclosed;      /* 1 = enclosed light particles join as triggered ones */
    double trigger_speed;      /* scan threshold, in sqrt(|g| l0) */
    double join_bubbles;       /* 1 = gas cut off from the gas's free surface joins */
    double gas_pressure_limit; /* Pa; 0 = derived */
    double bubble_rise_velocity; /* m/s, slip of a joined light particle (drift) */
    double bubble_relaxation_time; /* s, of the slip toward the rise velocity (drift) */
    double join_ramp_time;     /* s, ramp of a joining particle's weight; 0 = at once */
    double excitation_acceleration; /* amplitude of the tank's horizontal acceleration */
    double excitation_period;
    double drift_without_gravity;
    double gas_correction_limit; /* cap on a gas particle's correction (two_phase/) */
    double gas_liquid_volume;  /* gas sees liquid particles weighted (0, 1, 2: gas_pressure.c) */
    double gas_cg_tolerance;   /* CG tolerance of the gas solve; 0 = cg_tolerance */
    double join_hold;          /* 1 = a joined particle stays joined while inside the liquid */
    double gas_buffer_depth;   /* l0, the damping layer under the gas's starting top; 0 = none */
    double gas_buffer_rate;    /* 1/s, its damping rate at the top and above */
    double threads;            /* threads of the particle loops; 0 = OpenMP's default */
    int pressure_solver;
    int cg_preconditioner;
    int pressure_gradient;
    int ppe_source;
    int ppe_pattern;
    int wall_ghosts;
    int surface_pressure;
    int free_surface;
    int two_phase_model;
    int interface_reaction;
    int effect_mode[EFFECT_COUNT];
    double smagorinsky_constant;
    double beta_count;
    double memory_limit;       /* bytes a scene or a solver may take; 0 = memory_available */
} params;

void params_set_defaults(params *p);
/* " (did you mean \"x\"?)" into out for the nearest of count names given by
 * name_at, when it is a near miss (a third of the key's letters, at least
 * two, at most); "" otherwise. */
void near_miss(const char *key, const char *(*name_at)(size_t), size_t count, char *out,
               size_t size);
/* Validates and sets; writes a reason into message on failure. */
int params_set(params *p, const char *key, double value, char *message, size_t size);
int params_get(const params *p, const char *key, double *value);
int params_set_option(params *p, const char *key, const char *value,
                      char *message, size_t size);
int params_get_option(const params *p, const char *key, const char **value);
double params_max_radius(const params *p);
/* Key of the index-th numeric parameter (0, 1, ...), NULL past the last:
 * lets the output files list them without touching the caller's last error,
 * as mps2p_param_info would. */
const char *params_key(size_t index);
/* Key of the index-th option (0, 1, ...), NULL past the last: lets the
 * output files list every option without knowing them. */
const char *params_option_key(size_t index);

/* ---- scene (scene.c) ---- */

typedef struct fluid {
    char name[FLUID_NAME_SIZE];
    double density;
    double viscosity;
} fluid;

/* Scene-only kind, classified at solver creation; apart from every
 * MPS2P_KIND_* (3 is MPS2P_KIND_OUT, a solver's only). */
enum { SOLID_FROM_BOX = -2 };

struct mps2p_scene {
    double l0;
    params params;
    /* One allocation per fluid: only the pointer array moves when it grows,
     * so the names mps2p_scene_get_fluid hands out stay valid (issue 20). */
    fluid **fluids;
    int fluid_count, fluid_capacity;
    size_t count, capacity;
    double *position;  /* 2 * count */
    double *velocity;  /* 2 * count */
    int *kind;         /* MPS2P_KIND_* or SOLID_FROM_BOX */
    int *fluid_id;     /* -1 for solids */
    int *body_id;      /* -1 for fluid, 0 = "walls", else a body of body_names */
    char (*body_names)[FLUID_NAME_SIZE]; /* body k's name at k - 1 (coupling/bodies.c) */
    int body_count, body_capacity;       /* bodies besides "walls" */
    int has_domain;
    double domain[4];  /* xmin, ymin, xmax, ymax */
    int tank_layers;   /* the fewest wall layers of a tank added so far; 0: no tank */
    /* every box filled so far (fluid boxes, wall boxes, a tank's walls), as
     * filled (snapped to whole cells): a fluid box may touch another box but
     * not overlap it (scene.c) */
    struct placed_box {
        double x0, y0, x1, y1;
        int fluid;           /* 1: a fluid box */
        size_t first, count; /* its particles */
    } *boxes;
    size_t box_count, box_capacity;
    char error[ERROR_MESSAGE_SIZE];
};

/* MPS2P_ERR_INVALID (message naming what) when x or y lies beyond
 * COORDINATE_LIMIT_L0 l0 of the origin (scene.c; the checkpoint loader too). */
int coordinates_check(double l0, double x, double y, const char *what, char *handle_error);
/* Room for extra more particles in a scene: the particle cap and the memory
 * limit, checked without allocating (scene.c). */
int scene_check_room(mps2p_scene *scene, size_t extra);

/* ---- the solver ---- */

/* A fluid particle, in the run or out of it (MPS2P_KIND_OUT: it left the
 * domain, keeping its fluid id). */
static inline int kind_is_fluid(int kind)
{
    return kind == MPS2P_KIND_FLUID || kind == MPS2P_KIND_OUT;
}
/* Fluid in the run and walls: the particles that carry a pressure. Dummies
 * only fill the number density; OUT particles are in nothing. */
static inline int kind_carries_pressure(int kind)
{
    return kind == MPS2P_KIND_FLUID || kind == MPS2P_KIND_WALL;
}

#define STAGE_COUNT 26   /* rows of the stage table (solver/plan.c) */
#define PLAN_CAPACITY 32 /* the stages of a step, with the neighbour list's updates */
#define EFFECT_REASON_SIZE 160

typedef struct particle_state {
    double *position;  /* 2n */
    double *velocity;  /* 2n */
    double *pressure;  /* n  */
} particle_state;

/* Its members that are per particle or carry from one step into the next
 * are rows of solver_fields too (fields.c): a row says how each is kept. */
struct mps2p_solver {
    double l0;
    params params;
    fluid *fluids;
    int fluid_count;
    size_t count;
    int *kind;
    int *fluid_id;
    double *density;        /* per particle; walls take the heaviest fluid's */
    double *viscosity;      /* per particle; 0 for walls */
    particle_state state;
    /* The rolled-back members as the current step found them (the same
     * members, nothing else allocated): put back when it fails. */
    struct mps2p_solver *before_step;
    double *number_density; /* n* of the last step */
    double *number_density_start; /* n at the start of the last step */
    double *scratch;        /* 2n, stage workspace */
    unsigned char *on_surface;
    neighbour_list neighbours;
    pair_balance density_blocks, viscosity_blocks; /* the pair sums' splits */

    /* derived constants */
    double n0_density, n0_laplacian, lambda;
    double domain[4];
    double dt_max, pressure_limit;
    /* Shortest dt the pressure Poisson equation of the current step may see
     * (stages/pressure.c): 0, or PPE_MIN_STEP_FRACTION of the chosen dt in a step
     * of mps2p_solver_advance_to shorter than that. */
    double ppe_min_dt;

    struct two_phase *phases; /* two_phase/: allocated only when effect two_phase is on */
    /* How the two phases change two single-phase stages, set with their
     * state (NULL without): the neighbours a particle's viscosity sees (all
     * where viscosity_mask is NULL or viscosity_unmasked[i] is set), and the
     * share of a collision's impulse fluid particle i takes from fluid
     * particle j (below 0: they do not collide; NULL: by mass), and where
     * the pair's impulse comes whole this step rather than at the damper's
     * rate (*whole: one of WHOLE_*). */
    const unsigned char *viscosity_mask, *viscosity_unmasked;
    double (*collision_share)(const mps2p_solver *s, size_t i, size_t j, int *whole);
#define WHOLE_NEVER 0   /* the damper's rate at any distance */
#define WHOLE_IN_CORE 1 /* whole closer than collision_core */
#define WHOLE_IN_HALF 2 /* whole closer than half a spacing, whatever collision_core */

    /* pressure solve */
    sparse_matrix matrix;
    double *rhs, *solution;
    int *unknown_of;        /* particle -> unknown index or -1 (the matrix's int rows) */
    linear_solver *linear;

    /* time and statistics */
    double time, last_dt;
    uint64_t steps;
    size_t ppe_unknowns, ppe_iterations, surface_particles;
    uint64_t ppe_iterations_total;
    double ppe_residual;
    int diverged;
    long diverged_particle; /* the particle a divergence was found at; -1 none */
    size_t fluid_out;       /* particles of kind MPS2P_KIND_OUT (stages/divergence.c) */
    /* Inside mps2p_solver_advance_to, whose progress callback may call back
     * into this solver: stepping or restoring it is refused there, and
     * mps2p_solver_destroy only sets destroy_requested (solver/solver.c). */
    int running, destroy_requested;
    char error[ERROR_MESSAGE_SIZE];

    /* turbulence (stages/turbulence.c): allocated only when the effect is on */
    double *eddy_viscosity;
    double eddy_viscosity_max;
    /* free_surface "neighbour_count" (stages/free_surface.c): allocated only then */
    unsigned *neighbour_count;

    /* the step, assembled from the effects the scene needs (solver/plan.c) */
    int effect_active[EFFECT_COUNT];
    char effect_reason[EFFECT_COUNT][EFFECT_REASON_SIZE];
    int plan[PLAN_CAPACITY]; /* rows of the stage table */
    size_t plan_length;
    int plan_stale;          /* an input changed what the plan holds: rebuilt before a step */
    double stage_seconds[STAGE_COUNT];
    uint64_t stage_calls[STAGE_COUNT];

    struct coupling *coupling; /* bodies and host inputs (coupling/) */
};

/* ---- effects (effects.c) ---- */

/* Decides every effect from the scene and the requests (effects.c). */
int effects_decide(mps2p_solver *s);
/* Density of the heaviest light fluid (below light_fraction of the
 * heaviest), 0 when the scene has none; *heaviest gets the heaviest fluid's
 * (effects.c; effect two_phase and the two-phase state share the rule). */
double light_fluid_density(const mps2p_solver *s, double *heaviest);
const char *effect_name(int effect);
/* The gravity the step applies: parameter gravity, or none when effect
 * gravity is off. Everything that reads gravity inside a step (the walls'
 * hydrostatic ghosts, the damper's time scale, the trigger's speed) reads
 * this one, so that a tank with the effect off stays still. */
static inline void gravity_acting(const mps2p_solver *s, double g[2])
{
    const int on = s->effect_active[EFFECT_GRAVITY];
    g[0] = on ? s->params.gravity[0] : 0.0;
    g[1] = on ? s->params.gravity[1] : 0.0;
}
/* ---- memory (memory_limit.c) ---- */

/* Bytes this process can have: physical memory, or less under RLIMIT_AS,
 * RLIMIT_DATA or a cgroup memory limit (read at each call: nothing kept). */
double memory_available(void);
/* Parameter memory_limit, or memory_available() when it is 0. */
double memory_limit_bytes(const params *p);
/* Bytes a scene holds per particle (its five arrays). */
size_t scene_bytes_per_particle(void);
/* Bytes a solver of n particles takes at least: its per-particle arrays
 * and the neighbour lists of a filled lattice (the pressure matrix and the
 * solver's factor come on top). */
double solver_bytes_estimate(const params *p, size_t n);
/* MPS2P_OK when bytes fit memory_limit_bytes(p), else MPS2P_ERR_NOMEM with a
 * message naming what (e.g. "a scene of 9e8 particles") and the limit. */
int memory_check(const params *p, double bytes, const char *what, char *handle_error);

#endif
