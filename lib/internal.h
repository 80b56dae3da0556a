/* Private data structures shared by the library's stages. */
#ifndef MPS2P_INTERNAL_H
#define MPS2P_INTERNAL_H

#define MPS2P_BUILDING 1
#include "mps2p.h"

#include <stdarg.h>
#include <stddef.h>
#ifdef _OPENMP
#include <omp.h>
#endif

/* Threads of a parallel loop for a `threads` setting (parameter threads:
 * 0 = OpenMP's default). Given to each loop's num_threads clause, never set
 * process-wide, so two solvers can run with different counts side by side. */
static inline int team_size(double threads)
{
#ifdef _OPENMP
    return threads >= 1.0 ? (int)threads : omp_get_max_threads();
#else
    (void)threads;
    return 1;
#endif
}

/* PARALLEL_FOR(threads, clauses, for-statement): the loop over team_size
 * threads with OpenMP's "parallel for" and the given clauses (schedule,
 * reduction, if; no commas). With one thread, or without OpenMP, it is the
 * plain loop: libgomp is never entered, since it exits the process when its
 * own allocations fail (libmps2p returns MPS2P_ERR_NOMEM instead). Each
 * iteration writes only its own outputs, or the clause is an order-free
 * reduction (|, + of integers), so the results do not depend on the team. */
#ifdef _OPENMP
#define OMP_PRAGMA_(...) _Pragma(#__VA_ARGS__)
#define PARALLEL_FOR(threads, clauses, ...)                                      \
    do {                                                                         \
        const int team_ = team_size(threads);                                    \
        if (team_ > 1) {                                                         \
            OMP_PRAGMA_(omp parallel for num_threads(team_) clauses)             \
            __VA_ARGS__                                                          \
        } else {                                                                 \
            __VA_ARGS__                                                          \
        }                                                                        \
    } while (0)
#else
#define PARALLEL_FOR(threads, clauses, ...)                                      \
    do {                                                                         \
        (void)(threads);                                                         \
        __VA_ARGS__                                                              \
    } while (0)
#endif

/* Reductions (sums, maxima) are taken over fixed blocks of this many
 * particles or unknowns, each summed in order, and the block results
 * combined in block order: the same bits for any number of threads. */
#define REDUCTION_BLOCK 1024

#define ERROR_MESSAGE_SIZE 512
/* Particle coordinates must lie within this many l0 of the origin: there a
 * double still resolves 2.2e-7 l0, so boxes keep every lattice site (at
 * 1e11 m a 0.02 m lattice lost particles to rounding). */
#define COORDINATE_LIMIT_L0 1e9
/* A step of mps2p_solver_advance_to shorter than this fraction of the chosen
 * dt solves its pressure as one of this fraction (pressure.c, solver.c). */
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

/* ---- parameters (params.c) ---- */

enum pressure_solver_kind { PRESSURE_SOLVER_CHOLMOD = 0, PRESSURE_SOLVER_CG = 1 };
enum cg_preconditioner_kind { CG_PRECONDITIONER_JACOBI = 0, CG_PRECONDITIONER_IC0 = 1 };
enum pressure_gradient_kind { GRADIENT_MINIMUM = 0, GRADIENT_CORRECTED = 1 };
enum free_surface_kind { FREE_SURFACE_NUMBER_DENSITY = 0, FREE_SURFACE_NEIGHBOUR_COUNT = 1 };
enum ppe_source_kind { PPE_SOURCE_DENSITY = 0, PPE_SOURCE_MIXED = 1, PPE_SOURCE_ECS = 2 };
/* The PPE matrix's pattern: the pairs within re_laplacian, or every pair of
 * the neighbour list (zeros beyond re_laplacian), which stands as long as
 * the list and the unknowns do, so CHOLMOD's analysis is reused (pressure.c). */
enum ppe_pattern_kind { PPE_PATTERN_DISTANCE = 0, PPE_PATTERN_NEIGHBOUR_LIST = 1 };
/* What dummy walls, and walls with no fluid around them (free surface),
 * stand for in the PPE and the pressure gradient (pressure.c, correction.c). */
enum wall_ghosts_kind {
    WALL_GHOSTS_NONE = 0,       /* Koshizuka and Oka: dummies only fill n, a dry wall p = 0 */
    WALL_GHOSTS_HYDROSTATIC = 1 /* p_j = p_i + rho_i g . r_ij, seen from each particle i */
};
/* Two-phase model (effects two_phase and interface_reaction, phases.c). */
enum two_phase_model_kind {
    TWO_PHASE_IMPROVED = 0, /* two_step_improved: the default */
    TWO_PHASE_TWO_STEP = 1, /* two_step: Koshizuka's conventional model */
    TWO_PHASE_SINGLE = 2    /* single: one PPE over every fluid */
};
/* What delta_al = 1 does (interface_reaction.c). */
enum interface_reaction_kind {
    REACTION_VOLUME = 0, /* joins the liquid solve, moved by -grad p_l / rho_eff */
    REACTION_WALL = 1,   /* joins the liquid solve as a moving wall, moved by its gas pressure */
    REACTION_PAIR = 2,   /* momentum-conserving pair reaction of its gas pressure */
    REACTION_PUSH = 3,   /* its gas pressure pushes the liquid, eq. (5) read literally */
    REACTION_DRIFT = 4,  /* joins the liquid solve, moves with the liquid plus a rise velocity */
    REACTION_CONTINUITY = 5 /* gas solve with the liquid's pressure on liquid particles,
                               bounded gas density in liquid, pair reaction when triggered */
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
    double ppe_relaxation;
    double compressibility;
    double clamp_negative_pressure;
    double cg_tolerance;
    double cg_max_iterations;
    double pressure_limit;
    double displacement_limit;
    double neighbour_skin;
    double light_fraction;     /* a fluid is light below this fraction of the heaviest */
    double sector_scan_walls;  /* 1 = walls count as heavy in the 8-sector scan */
    double join_enclosed;      /* 1 = enclosed light particles join as triggered ones */
    double bubble_added_mass;  /* C_m of the volume reaction */
    double gas_pressure_limit; /* Pa; 0 = derived */
    double bubble_rise_velocity; /* m/s, slip of a joined light particle (drift) */
    double bubble_relaxation_time; /* s, of the slip toward the rise velocity (drift) */
    double drift_liquid_gradient;  /* 1 = drift particles corrected by the liquid pressure */
    double join_ramp_time;     /* s, ramp of a joining particle's weight; 0 = at once */
    double excitation_acceleration; /* amplitude of the tank's horizontal acceleration */
    double excitation_period;
    double drift_without_gravity;
    double gas_correction_limit; /* cap on a gas particle's correction (phases.c) */
    double gas_liquid_volume;  /* gas sees liquid particles weighted (0, 1, 2: gas_pressure.c) */
    double gas_cg_tolerance;   /* CG tolerance of the gas solve; 0 = cg_tolerance */
    double join_hold;          /* 1 = a joined particle stays joined while inside the liquid */
    double threads;            /* threads of the particle loops; 0 = OpenMP's default */
    int pressure_solver;
    int cg_preconditioner;
    int pressure_gradient;
    int ppe_source;
    int ppe_pattern;
    int wall_ghosts;
    int free_surface;
    int two_phase_model;
    int interface_reaction;
    int effect_mode[EFFECT_COUNT];
    double smagorinsky_constant;
    double beta_count;
    double memory_limit;       /* bytes a scene or a solver may take; 0 = memory_available */
} params;

void params_set_defaults(params *p);
/* Validates and sets; writes a reason into message on failure. */
int params_set(params *p, const char *key, double value, char *message, size_t size);
int params_get(const params *p, const char *key, double *value);
int params_set_option(params *p, const char *key, const char *value,
                      char *message, size_t size);
int params_get_option(const params *p, const char *key, const char **value);
double params_max_radius(const params *p);
/* Key of the index-th option (0, 1, ...), NULL past the last: lets the
 * output files list every option without knowing them. */
const char *params_option_key(size_t index);

/* ---- scene (scene.c) ---- */

typedef struct fluid {
    char name[FLUID_NAME_SIZE];
    double density;
    double viscosity;
} fluid;

enum { SOLID_FROM_BOX = 3 }; /* scene-only kind, classified at solver creation */

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
    char (*body_names)[FLUID_NAME_SIZE]; /* body k's name at k - 1 (bodies.c) */
    int body_count, body_capacity;       /* bodies besides "walls" */
    int has_domain;
    double domain[4];  /* xmin, ymin, xmax, ymax */
    char error[ERROR_MESSAGE_SIZE];
};

/* MPS2P_ERR_INVALID (message naming what) when x or y lies beyond
 * COORDINATE_LIMIT_L0 l0 of the origin (scene.c; the checkpoint loader too). */
int coordinates_check(double l0, double x, double y, const char *what, char *handle_error);
/* Room for extra more particles in a scene: the particle cap and the memory
 * limit, checked without allocating (scene.c). */
int scene_check_room(mps2p_scene *scene, size_t extra);

/* ---- kernel and reference lattice (kernel.c) ---- */

static inline double kernel_weight(double r, double re)
{
    return (r > 0.0 && r < re) ? re / r - 1.0 : 0.0;
}

/* n0 and lambda of an interior particle of the square lattice of spacing l0. */
void lattice_constants(double l0, double re, double *n0, double *lambda);

/* ---- neighbour list (neighbours.c) ---- */

/* Every pair closer than cutoff = max radius + skin, kept as a compressed
 * row list (both directions, ordered by index); rebuilt when a particle has
 * moved more than skin / 2 since the last build, so each stage can reuse it.
 * At each build a short list is also taken from it: the pairs closer than
 * short_radius + skin (short_radius = re_density l0), in the same order, for
 * the stages that look no further than short_radius (about 20 neighbours
 * instead of 60); see neighbour_rows_within. */
typedef struct neighbour_list {
    double cutoff, skin;
    size_t count;
    size_t *start;       /* count + 1 */
    size_t *index;       /* start[count] entries */
    size_t capacity;
    double short_radius; /* 0 = no short list (it would be the long one) */
    size_t *short_start; /* count + 1, NULL without a short list */
    size_t *short_index; /* short_start[count] entries */
    size_t short_capacity;
    double *built_at;    /* positions at the last build, 2 * count */
    /* cell grid over the domain */
    double origin[2];
    double cell_size;
    size_t cells[2];
    size_t *cell_start;  /* cells + 1 */
    size_t *cell_cursor; /* cells, fill position while sorting */
    size_t *cell_particle;
    size_t *particle_cell;
    unsigned long builds;
    int stale;           /* a rebuild failed half-way: rebuild at the next update */
    double threads;      /* parameter threads (team_size) */
} neighbour_list;

/* short_radius: the radius the short list must serve (re_density l0); 0, or
 * one within skin of cutoff, keeps no short list. */
int neighbours_init(neighbour_list *list, size_t count, double cutoff, double skin,
                    double short_radius, const double domain[4]);
void neighbours_free(neighbour_list *list);
/* Rebuilds both lists when needed; returns MPS2P_OK or MPS2P_ERR_NOMEM (both
 * lists then empty and stale, rebuilt at the next update). */
int neighbours_update(neighbour_list *list, const double *position);
/* Builds the list from the positions of an earlier build (built_at) and sets
 * the build count, so that a restored solver reuses the same pairs and makes
 * the same rebuild decisions as the one it was saved from. built_at must not
 * be list->built_at itself (it is copied there). */
int neighbours_restore(neighbour_list *list, const double *built_at, unsigned long builds);

/* The rows a stage loops over for the pairs closer than radius: the short
 * list when radius is within its radius, else the long one. The short list
 * holds, in the same order, every pair of the long one closer than
 * short_radius + skin at the build, so a stage that skips the pairs at radius
 * or beyond sees the same pairs, in the same order, from either: its sums
 * come out bit for bit the same. */
typedef struct neighbour_rows {
    const size_t *start, *index;
} neighbour_rows;

static inline neighbour_rows neighbour_rows_within(const neighbour_list *list, double radius)
{
    neighbour_rows rows = {list->start, list->index};
    if (list->short_start && radius <= list->short_radius) {
        rows.start = list->short_start;
        rows.index = list->short_index;
    }
    return rows;
}

/* ---- linear solvers (linear_solver.c) ---- */

/* A symmetric matrix in compressed rows, full pattern (both triangles). */
typedef struct sparse_matrix {
    int rows;
    int *row_start;      /* rows + 1; int, as CHOLMOD's int interface wants */
    int *column;
    double *value;
    size_t capacity;     /* of column and value */
    size_t row_capacity; /* of row_start */
} sparse_matrix;

typedef struct linear_solver linear_solver;

/* kind: enum pressure_solver_kind; preconditioner: enum cg_preconditioner_kind
 * (CG only); threads: parameter threads, for CG's loops (team_size). */
int linear_solver_create(int kind, int preconditioner, double threads,
                         linear_solver **solver);
void linear_solver_destroy(linear_solver *solver);
/* Solves A x = b; x holds the initial guess on entry (used by CG). */
/* CHOLMOD symbolic analyses so far (a matrix of the last one's pattern reuses it). */
uint64_t linear_solver_analyses(const linear_solver *solver);
/* Bytes of workspace, CHOLMOD's included. */
size_t linear_solver_memory(const linear_solver *solver);
int linear_solver_solve(linear_solver *solver, const sparse_matrix *a,
                        const double *b, double *x, double tolerance,
                        size_t max_iterations, size_t *iterations,
                        double *residual, char *message, size_t size);

/* ---- the step's stages (stages.c) ---- */

#define STAGE_COUNT 25   /* rows of the stage table (stages.c) */
#define PLAN_CAPACITY 32 /* the stages of a step, with the neighbour list's updates */
#define EFFECT_REASON_SIZE 160

/* ---- two phases (phases.c, interface_reaction.c, gas_pressure.c) ---- */

/* State of the two-step pressure (docs/method.md sections 2-3). Allocated by
 * plan_build only when effect two_phase is on (a scene with a light fluid:
 * density below light_fraction of the heaviest, and two_phase_model not
 * "single"); a single-phase solver never holds one. */
typedef struct two_phase {
    struct two_phase *before_step; /* the carried state at the step's start, for rollback */
    int improved;               /* effect interface_reaction is on */
    double heavy_density;       /* of the heaviest fluid */
    double light_density;       /* of the heaviest light fluid */
    unsigned char *light;       /* per particle: fluid of a light phase */
    unsigned char *triggered;   /* delta_al = 1 in the last step (eq. 15) */
    unsigned char *enclosed;    /* heavy particles in all 8 sectors */
    unsigned char *joined;      /* light particle taking part in the liquid solve */
    unsigned char *was_joined;  /* joined in the step before */
    double *join_weight;        /* weight in the liquid's number density, ramped 0..1 */
    unsigned char *heavy_part;  /* participants of the liquid PPE */
    unsigned char *heavy_mask;  /* neighbours the liquid sees: not light, or joined */
    unsigned char *gas_part;    /* participants of the gas PPE */
    unsigned char *heavy_surface, *gas_surface;
    double *heavy_n, *heavy_n_start; /* number density the liquid sees */
    double *heavy_pressure, *gas_pressure;
    double *gas_dirichlet;      /* liquid pressure on liquid particles (continuity) */
    double *gas_n;              /* number density the gas solve sees */
    double *heavy_n_initial;    /* the liquid's number density at the first step */
    int have_initial;
    double *heavy_rho, *gas_rho;     /* densities of the two PPEs' sources */
    double gas_pressure_limit;
    /* diagnostics of the last step */
    size_t triggered_count, enclosed_count, joined_count, capped_count;
    size_t heavy_unknowns, heavy_iterations, gas_unknowns, gas_iterations;
    double gas_pressure_max;
} two_phase;

/* The share of a collision's impulse between phases (phases_rules.c). */
double phases_collision_share(const mps2p_solver *s, size_t i, size_t j);
/* Allocates s->phases (plan_build, when effect two_phase is on). */
int phases_init(mps2p_solver *s);
void phases_free(struct two_phase *tp);
size_t phases_memory_bytes(const mps2p_solver *s);
/* Stages of a two-phase step, in the order of the plan (stages.c). */
int phases_step_start(mps2p_solver *s, double dt);       /* liquid's own n^k */
int interface_scan(mps2p_solver *s, double dt);          /* interface_reaction.c */
int interface_join(mps2p_solver *s, double dt);          /* interface_reaction.c */
int liquid_pressure_solve(mps2p_solver *s, double dt);   /* phases.c */
/* The gas PPE, then the state's pressure per phase (phases_pressure_combine). */
int gas_pressure_solve(mps2p_solver *s, double dt);      /* gas_pressure.c */
void phases_pressure_combine(mps2p_solver *s);           /* phases.c */
int phases_correct(mps2p_solver *s, double dt);          /* per phase, plus reaction */
void interface_reaction_apply(mps2p_solver *s, double dt, double *change);
int interface_drift_apply(mps2p_solver *s, double dt);
int phases_divergence_check(mps2p_solver *s, double dt);
/* The two-phase statistics (phases_stats.c), after the solver's (stats.c). */
extern const stat_entry two_phase_stats[];
extern const size_t two_phase_stat_count;
size_t gas_in_liquid_count(const mps2p_solver *s);                  /* gas_in_liquid.c */
/* A light particle with more heavy-fluid than light-fluid neighbours within re. */
int more_liquid_than_light_neighbours(const mps2p_solver *s, size_t i);

/* What of s->phases is saved, checkpointed and rolled back, row by row
 * (phases_carry.c says why each member, and why not the others). */
extern const field_table two_phase_fields;
/* A struct two_phase holding only the rows of s->phases with any flag of
 * with, the other arrays NULL; NULL when out of memory. Freed with
 * phases_free. */
two_phase *phases_copy_carried(const mps2p_solver *s, unsigned with);
/* Puts from's rows with any flag of with into s->phases, then rebuilds
 * heavy_mask. */
void phases_put_carried(mps2p_solver *s, const two_phase *from, unsigned with);
/* Into s->phases->before_step at a step's start; put back when it fails. */
void phases_save_before_step(mps2p_solver *s);
/* heavy_mask from light and join_weight, as the last step left it. */
void phases_carried_rebuild(mps2p_solver *s);
/* 0 when the carried members of s->phases are in range (a loaded file's),
 * else -1 with the reason in why. */
int phases_carried_check(const mps2p_solver *s, char *why, size_t size);

/* ---- solver state (solver.c and the stages) ---- */

typedef struct particle_state {
    double *position;  /* 2n */
    double *velocity;  /* 2n */
    double *pressure;  /* n  */
} particle_state;

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

    /* derived constants */
    double n0_density, n0_laplacian, lambda;
    double domain[4];
    double dt_max, pressure_limit;
    /* Shortest dt the pressure Poisson equation of the current step may see
     * (pressure.c): 0, or PPE_MIN_STEP_FRACTION of the chosen dt in a step
     * of mps2p_solver_advance_to shorter than that. */
    double ppe_min_dt;

    struct two_phase *phases; /* allocated only when effect two_phase is on */
    /* How the two phases change two single-phase stages, set with their
     * state (NULL without): the neighbours a particle's viscosity sees (all
     * where viscosity_mask is NULL or viscosity_unmasked[i] is set), and the
     * share of a collision's impulse fluid particle i takes from fluid
     * particle j (below 0: they do not collide; NULL: by mass). */
    const unsigned char *viscosity_mask, *viscosity_unmasked;
    double (*collision_share)(const mps2p_solver *s, size_t i, size_t j);

    /* pressure solve */
    sparse_matrix matrix;
    double *rhs, *solution;
    long *unknown_of;       /* particle -> unknown index or -1 */
    linear_solver *linear;

    /* time and statistics */
    double time, last_dt;
    uint64_t steps;
    size_t ppe_unknowns, ppe_iterations, surface_particles;
    uint64_t ppe_iterations_total;
    double ppe_residual;
    int diverged;
    long diverged_particle; /* the particle a divergence was found at; -1 none */
    /* Inside mps2p_solver_advance_to, whose progress callback may call back
     * into this solver: stepping or restoring it is refused there, and
     * mps2p_solver_destroy only sets destroy_requested (solver.c). */
    int running, destroy_requested;
    char error[ERROR_MESSAGE_SIZE];

    /* turbulence (turbulence.c): allocated only when the effect is on */
    double *eddy_viscosity;
    double eddy_viscosity_max;
    /* free_surface "neighbour_count" (free_surface.c): allocated only then */
    unsigned *neighbour_count;

    /* the step, assembled from the effects the scene needs (stages.c) */
    int effect_active[EFFECT_COUNT];
    char effect_reason[EFFECT_COUNT][EFFECT_REASON_SIZE];
    int plan[PLAN_CAPACITY]; /* rows of the stage table */
    size_t plan_length;
    int plan_stale;          /* an input changed what the plan holds: rebuilt before a step */
    double stage_seconds[STAGE_COUNT];
    uint64_t stage_calls[STAGE_COUNT];

    struct coupling *coupling; /* bodies and host inputs (bodies.c) */
};

/* Decides every effect from the scene and the requests (effects.c). */
int effects_decide(mps2p_solver *s);
/* Density of the heaviest light fluid (below light_fraction of the
 * heaviest), 0 when the scene has none; *heaviest gets the heaviest fluid's
 * (effects.c; effect two_phase and the two-phase state share the rule). */
double light_fluid_density(const mps2p_solver *s, double *heaviest);
const char *effect_name(int effect);
/* Lays out the step's stages for the effects decided (effects_decide) and
 * allocates what only an active stage needs (stages.c). Inputs that change
 * the plan decide the effects and set s->plan_stale instead: the step
 * rebuilds it. */
int plan_build(mps2p_solver *s);
/* Runs one step's stages in order, timing each; stops at the first error. */
int plan_run(mps2p_solver *s, double dt);
/* Bytes the solver holds: its arrays, lists, matrix and solver workspace. */
size_t solver_memory_bytes(const mps2p_solver *s);                  /* memory.c */
/* Bytes this process can have: physical memory, or less under RLIMIT_AS,
 * RLIMIT_DATA or a cgroup memory limit (read at each call: nothing kept). */
double memory_available(void);                                      /* memory.c */
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

/* MPS2P_ERR_STATE with a message naming function when s is inside
 * mps2p_solver_advance_to (called from its progress callback), else
 * MPS2P_OK (solver.c). */
int solver_refuse_if_running(mps2p_solver *s, const char *function);

/* Allocates every per-particle array of a zeroed solver (solver.c); the
 * checkpoint loader fills them instead of a scene. */
int solver_allocate(mps2p_solver *s, size_t n, int fluid_count);
/* Starts the neighbour list (empty) and the pressure solver, once l0, params
 * and domain are set. */
int solver_start(mps2p_solver *s);

/* ---- wall bodies and host inputs (bodies.c, body_motion.c, external_forces.c) ---- */

/* Creates the solver's bodies: all solids in body 0 "walls", or the scene's
 * bodies when scene is non-NULL. Called once the kinds are known. */
int coupling_create(mps2p_solver *s, const mps2p_scene *scene);
void coupling_free(struct coupling *c);
int body_motion_wanted(const mps2p_solver *s);
int external_forces_wanted(const mps2p_solver *s);
int body_motion_apply(mps2p_solver *s, double dt);
int external_forces_apply(mps2p_solver *s, double dt);
/* After a step that succeeded: rotation centres move on, targets dropped. */
void body_motion_done(mps2p_solver *s, double dt);

/* ---- output files ---- */

/* Writes the XDMF sidecar for count snapshots of a results file whose name
 * (relative to the sidecar) is h5_name; atomic (xdmf.c). */
int xdmf_write(const char *xdmf_path, const char *h5_name, size_t count, const double *times,
               const size_t *particles, char *handle_error);

/* ---- MPS operators at particle i (operators.c) ---- */
/* A dummy, or a wall that is free surface (surface: the PPE's flags), is a
 * hydrostatic ghost under option wall_ghosts = hydrostatic (pressure.c). */
static inline int is_hydrostatic_ghost(const mps2p_solver *s, const unsigned char *surface,
                                       size_t j)
{
    return s->kind[j] == MPS2P_KIND_DUMMY || (s->kind[j] == MPS2P_KIND_WALL && surface[j]);
}
/* The gradient with p_i as reference over non-dummy neighbours, where a wall
 * on the free surface takes the ghost value p_i + rho_i g . r_ij. */
void gradient_with_ghosts_at(const mps2p_solver *s, size_t i, const double *pressure,
                             double out[2]);
/* (d / n0) sum_j (f_j - reference) r_ij w / |r_ij|^2 over non-dummy neighbours. */
void gradient_at(const mps2p_solver *s, size_t i, const double *field, double reference,
                 double out[2]);
/* min(f_i, min_j f_j) over non-dummy neighbours within the density radius. */
double minimum_around(const mps2p_solver *s, size_t i, const double *field);
/* gradient_at of component c of an interleaved 2-vector field, f_i as reference. */
void gradient_at_component(const mps2p_solver *s, size_t i, const double *field, int c,
                           double out[2]);
/* The same, over the neighbours j with mask[j] != 0 only (NULL = as above):
 * each phase of a two-phase step sees only its own particles. */
void gradient_masked_at(const mps2p_solver *s, size_t i, const double *field, double reference,
                        const unsigned char *mask, double out[2]);
double minimum_masked_around(const mps2p_solver *s, size_t i, const double *field,
                             const unsigned char *mask);
void laplacian_masked_at(const mps2p_solver *s, size_t i, const double *field,
                         size_t components, const unsigned char *mask, double *out);
/* Inverse of (d/n0) sum_j w r_ij r_ij^T / |r_ij|^2 over fluid and wall
 * neighbours, as (xx, xy, yy); returns 0 when its determinant is below
 * CORRECTIVE_MIN_DETERMINANT (one-sided neighbourhoods), 1 otherwise. */
#define CORRECTIVE_MIN_DETERMINANT 0.1
int corrective_matrix_at(const mps2p_solver *s, size_t i, double inverse[3]);
/* (2d / (lambda n0)) sum_j (f_j - f_i) w, per component of an interleaved field. */
void laplacian_at(const mps2p_solver *s, size_t i, const double *field, size_t components,
                  double *out);

/* ---- stages, in the order of a step ---- */
double timestep_choose(const mps2p_solver *s);                   /* timestep.c */
/* Which bound sets timestep_choose's dt, in words, for messages. */
void timestep_explain(const mps2p_solver *s, char *out, size_t size);
/* mps2p_solver_advance_to refuses a window that would take more steps. */
#define MAX_STEPS_PER_ADVANCE 1e9
/* The stages, each run by the plan as int (*)(mps2p_solver *, double dt). */
int neighbours_refresh(mps2p_solver *s, double dt);               /* neighbour_update.c */
int viscosity_apply(mps2p_solver *s, double dt);                  /* explicit_forces.c */
int gravity_apply(mps2p_solver *s, double dt);                    /* explicit_forces.c */
int excitation_apply(mps2p_solver *s, double dt);                 /* explicit_forces.c */
int turbulence_apply(mps2p_solver *s, double dt);                 /* turbulence.c */
int advect(mps2p_solver *s, double dt);                           /* explicit_forces.c */
int collision_apply(mps2p_solver *s, double dt);                  /* collision.c */
/* n into out (number_density.c); the stages: n^k at the step's start, n* at r* */
void number_density_compute(mps2p_solver *s, double *out);
int number_density_start(mps2p_solver *s, double dt);
int number_density_star(mps2p_solver *s, double dt);
int free_surface_detect(mps2p_solver *s, double dt);              /* free_surface.c */
int neighbour_count_compute(mps2p_solver *s, double dt);          /* free_surface.c */
int pressure_assemble(mps2p_solver *s, double dt);                /* pressure.c */
int pressure_solve(mps2p_solver *s, double dt);                   /* pressure.c */
/* One PPE over a subset of the particles (pressure.c), for the two phases'
 * solves: part marks the participants (NULL = every non-dummy particle),
 * surface the Dirichlet ones; n_star, n_start and density enter the source
 * (and density the diagonal); pressure holds the warm start on entry and
 * every particle's result on exit (0 for non-participants). */
typedef struct ppe_system {
    const unsigned char *part;
    const unsigned char *surface;
    const double *n_star, *n_start, *density;
    double *pressure;
    double tolerance;           /* CG tolerance; 0 = cg_tolerance */
    const double *dirichlet;    /* values of participants that are not unknowns; NULL = 0 */
    double re_in_l0;            /* Laplacian radius of this system; 0 = re_laplacian */
    size_t unknowns, iterations;
    double residual;
} ppe_system;
int pressure_assemble_system(mps2p_solver *s, double dt, ppe_system *sys);
int pressure_solve_system(mps2p_solver *s, ppe_system *sys);
int pressure_correct(mps2p_solver *s, double dt);                 /* correction.c */
int diverged_at(mps2p_solver *s, size_t i, int status);           /* divergence.c */
int divergence_check(mps2p_solver *s, double dt);                 /* divergence.c */

#endif
