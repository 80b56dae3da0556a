/*
 * libmps2p: gas-liquid two-phase flow with the Moving Particle Semi-implicit
 * (MPS) method, in 2D.
 *
 * The header reads like the method:
 *   1. versions, status codes and error messages;
 *   2. a scene: particle spacing, fluids, particles (boxes, tanks, arrays) and
 *      parameters set by name;
 *   3. a solver built from the scene, stepped or advanced to a time;
 *   4. results: fields copied into caller buffers, and statistics by name;
 *   5. files and probes: HDF5 results files, checkpoints, point probes;
 *   6. effects and costs: which physical effects are on and why, and the
 *      wall time of each stage of the step;
 *   7. coupling: wall bodies and the forces on them, walls a host moves,
 *      windows of time and saved states (docs/embedding.md).
 *
 * Conventions, everywhere:
 *   - every function that can fail returns an int status: MPS2P_OK (0) on
 *     success, a negative MPS2P_ERR_* code on failure; the codes never change;
 *   - on failure, mps2p_last_error() holds a message for the calling thread,
 *     and a non-const call on a handle also keeps it on the handle
 *     (mps2p_scene_last_error, mps2p_solver_last_error: the last failure on
 *     that handle); on success mps2p_last_error() is "";
 *   - MPS2P_STOPPED (1) is not an error: a progress callback stopped a run;
 *   - handles are opaque; destroy functions accept NULL; a function that
 *     makes a handle (mps2p_scene_create, mps2p_solver_create,
 *     mps2p_solver_load_checkpoint, mps2p_results_create) sets it to NULL
 *     when it fails;
 *   - arrays are copied into caller buffers whose length (in elements) is
 *     passed explicitly; vectors are interleaved (x0, y0, x1, y1, ...);
 *   - SI units throughout (m, s, kg/m^3, m^2/s, Pa).
 *
 * Thread safety: there is no global mutable state. Different handles may be
 * used from different threads at the same time; one handle must not be used
 * by two threads at once.
 */
#ifndef MPS2P_H
#define MPS2P_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(MPS2P_BUILDING) && defined(__GNUC__)
#define MPS2P_API __attribute__((visibility("default")))
#else
#define MPS2P_API
#endif

/* ---------------------------------------------------------------------------
 * 1. Versions, status codes, errors
 * ------------------------------------------------------------------------- */

#define MPS2P_VERSION_MAJOR 0
#define MPS2P_VERSION_MINOR 2
#define MPS2P_VERSION_PATCH 0
/* major * 10000 + minor * 100 + patch, as for the header you compiled with */
#define MPS2P_VERSION_NUMBER 200
#define MPS2P_VERSION_STRING "0.2.0"

/* Version of the library actually loaded at run time. */
MPS2P_API unsigned mps2p_version_number(void);
MPS2P_API const char *mps2p_version_string(void);

enum {
    MPS2P_OK = 0,
    MPS2P_STOPPED = 1,            /* not an error: a progress callback asked to stop */
    MPS2P_ERR_NULL = -1,          /* a required pointer argument was NULL */
    MPS2P_ERR_INVALID = -2,       /* an argument is out of range or not finite */
    MPS2P_ERR_UNKNOWN_KEY = -3,   /* no parameter, option or statistic of that name */
    MPS2P_ERR_NOMEM = -4,         /* memory allocation failed */
    MPS2P_ERR_STATE = -5,         /* the call does not fit the handle's state */
    MPS2P_ERR_BUFFER = -6,        /* the caller's buffer is too short */
    MPS2P_ERR_SOLVE = -7,         /* the pressure solve failed (singular, no convergence) */
    MPS2P_ERR_DIVERGED = -8,      /* the run blew up; the last good state is kept */
    MPS2P_ERR_IO = -9             /* a file could not be read or written */
};

/* Name of a status code, e.g. "MPS2P_ERR_INVALID"; never NULL. */
MPS2P_API const char *mps2p_status_string(int status);

/* Message of the calling thread's last call that returns a status: why it
 * failed, or "" when it succeeded. Functions that return no status (the
 * destroy functions, mps2p_*_last_error, mps2p_status_string, the version
 * functions) leave it as it is. Valid until the next such call in this
 * thread. */
MPS2P_API const char *mps2p_last_error(void);

/* ---------------------------------------------------------------------------
 * 2. Scene
 * ------------------------------------------------------------------------- */

typedef struct mps2p_scene mps2p_scene;

/* Particle kinds. Walls carry a pressure; dummy walls only fill the wall's
 * thickness so that wall particles see a full neighbourhood. MPS2P_KIND_OUT
 * is a fluid particle that left the domain during a run (parameter
 * out_limit) and is out of the run from then on, like DualSPHysics's
 * excluded particles: frozen where it left, velocity and pressure 0 (and
 * number density 0), no neighbour of anything, its fluid id kept. Only a
 * solver's particles become OUT: scenes refuse the kind. */
enum {
    MPS2P_KIND_FLUID = 0,
    MPS2P_KIND_WALL = 1,
    MPS2P_KIND_DUMMY = 2,
    MPS2P_KIND_OUT = 3
};

/* A new, empty scene with particle spacing l0 > 0 (metres). */
MPS2P_API int mps2p_scene_create(double l0, mps2p_scene **scene);
MPS2P_API void mps2p_scene_destroy(mps2p_scene *scene);
MPS2P_API const char *mps2p_scene_last_error(const mps2p_scene *scene);

/* Adds a fluid; its id (0, 1, ...) is written to *fluid_id (may be NULL). */
MPS2P_API int mps2p_scene_add_fluid(mps2p_scene *scene, const char *name,
                                    double density, double kinematic_viscosity,
                                    int *fluid_id);
MPS2P_API int mps2p_scene_fluid_count(const mps2p_scene *scene, int *count);
/* *name stays valid while the scene lives. Any output pointer may be NULL. */
MPS2P_API int mps2p_scene_get_fluid(const mps2p_scene *scene, int fluid_id,
                                    const char **name, double *density,
                                    double *kinematic_viscosity);

/* Fills the box [x0,x1] x [y0,y1] with fluid particles on the square lattice
 * of spacing l0, at cell centres x0 + (i + 1/2) l0. A side that is not a
 * whole number of l0 is rounded down to one. Boxes (fluid and wall boxes,
 * a tank's walls, which lie outside its box) may touch but not overlap: a
 * box over one added before is refused (MPS2P_ERR_INVALID, naming both). Coordinates (here and in every
 * function that adds particles) must lie within 1e9 l0 of the origin, where
 * a double still resolves 2.2e-7 l0 (MPS2P_ERR_INVALID beyond: lattice
 * sites would merge). */
MPS2P_API int mps2p_scene_add_fluid_box(mps2p_scene *scene, int fluid_id,
                                        double x0, double y0, double x1, double y1);

/* Fills a box with solid particles on the same lattice. When the solver is
 * created, solid particles with an empty lattice site among their 8 lattice
 * neighbours become MPS2P_KIND_WALL, the others MPS2P_KIND_DUMMY. */
MPS2P_API int mps2p_scene_add_wall_box(mps2p_scene *scene,
                                       double x0, double y0, double x1, double y1);

/* Walls around the inner region [x0,x1] x [y0,y1]: left, right and bottom,
 * and top unless open_top is non-zero. The walls are ceil(max radius / l0)
 * layers thick for the radii set when this is called (set radii first;
 * mps2p_solver_create refuses radii raised past a tank's layers afterwards,
 * MPS2P_ERR_INVALID): the layer facing the inside is MPS2P_KIND_WALL, the
 * layers behind it dummies.
 * Only the walls count against the particle cap and memory_limit. */
MPS2P_API int mps2p_scene_add_tank(mps2p_scene *scene, double x0, double y0,
                                   double x1, double y1, int open_top);

/* Adds count particles from caller arrays: positions (2*count), velocities
 * (2*count, or NULL for rest), kinds (count, MPS2P_KIND_FLUID, _WALL or
 * _DUMMY; MPS2P_KIND_OUT is refused), fluid_ids (count;
 * read only for fluid particles; may be NULL if no particle is fluid). count
 * is checked against the particle cap and memory_limit before the arrays are
 * read. */
MPS2P_API int mps2p_scene_add_particles(mps2p_scene *scene, size_t count,
                                        const double *positions,
                                        const double *velocities,
                                        const int *kinds, const int *fluid_ids);

MPS2P_API int mps2p_scene_particle_count(const mps2p_scene *scene, size_t *count);

/* Numerical parameters, by name. Defaults (those the option "scheme" sets are
 * marked *, with Koshizuka and Oka's value in brackets) and meanings:
 *   re_density              2.1   radius of number density and gradient, in l0
 *   re_laplacian          * 3.1   radius of the Laplacian, in l0 (4.0)
 *   beta                    0.97  free surface when n* < beta n0
 *   gravity_x, gravity_y    0, -9.81 (m/s^2)
 *   dt                      0     fixed time step (s); 0 = adaptive (cfl)
 *   cfl                     0.2   adaptive dt <= cfl l0 / max speed
 *   diffusion_number        0.2   adaptive dt <= diffusion_number l0^2 / nu
 *   gravity_number        * 0.03  adaptive dt <= gravity_number sqrt(l0 / |g|);
 *                                 0 = no such limit (0)
 *   dt_max                  0     largest adaptive dt (s); 0 = cfl l0 / U, U the
 *                                 larger of sqrt(2 |g| H) (H the height of the
 *                                 initial fluid, from its lowest particle to
 *                                 the highest of a fluid not lighter than
 *                                 light_fraction of the heaviest: a gas over
 *                                 a liquid does not count) and its fastest
 *                                 initial speed (1 m/s when both are 0)
 *   collision_distance    * 0.995 too-close distance, in l0; 0 = no collision
 *                                 model (0.5)
 *   collision_time        * 0.03  the collision model gives dt / tau of its
 *                                 impulse a step (at most all), tau =
 *                                 collision_time sqrt(l0 / |g|): its rate does
 *                                 not grow as dt shrinks; 0 = all every step (0)
 *   collision_core        * 0.5   in l0: a pair closer than it (and than
 *                                 collision_distance) after the move loses its
 *                                 whole approach in the step, whatever
 *                                 collision_time (two spray particles meeting
 *                                 head on otherwise overlap); air meeting water
 *                                 keeps the two-phase model's rule (whole inside
 *                                 0.5 l0 in the improved model, never in the
 *                                 conventional one); 0 = none (0.5)
 *   collision_restitution   0.2   restitution of the collision model
 *   shifting              * 0.04  particle shifting: a fluid particle off the free
 *                                 surface moves shifting u_max dt sum_j
 *                                 (rbar_i / r_ij)^2 e_ji a step (u_max the fastest
 *                                 fluid speed), away from close neighbours (single
 *                                 phase); 0 = off (0)
 *   ppe_step_gain         * 0.4   share of this step's compression, n* - n^k,
 *                                 that the ecs and mixed sources answer in the
 *                                 step (against 1: a turning stream's wall-pressure
 *                                 scatter a quarter lower, Buchner's probe noise
 *                                 and the dam break's spray two fifths lower,
 *                                 docs/validation.md); one phase and the single
 *                                 two-phase model: the two-step models' liquid,
 *                                 not shifted, answers in full (1)
 *   ppe_relaxation          0.2   factor on the PPE source term
 *   compressibility         4.5e-10  1/Pa, on the PPE diagonal; keeps a fluid
 *                                 cluster without free surface solvable
 *   clamp_negative_pressure 1     1 = negative pressures set to 0, 0 = kept
 *   cg_tolerance            1e-9  relative residual of the CG pressure solver
 *   cg_max_iterations       0     0 = 10 * unknowns + 100
 *   pressure_limit          0     |p| above it means diverged (Pa);
 *                                 0 = 1000 rho_max max(|g| L, 1 m^2/s^2),
 *                                 L the largest side of the initial particles' box
 *   displacement_limit      1.0   a particle moving farther in one step
 *                                 means diverged, in l0; 0 = no check
 *   out_limit               0.01  share of the fluid particles (of those at
 *                                 the start) that may leave the domain: each
 *                                 becomes MPS2P_KIND_OUT and the run goes on;
 *                                 one more means diverged; 0 = any fluid
 *                                 particle leaving the domain means diverged.
 *                                 Walls and dummies leaving it always do
 *   beta_count              0.85  free_surface "neighbour_count": surface below
 *                                 beta_count N0 neighbours within re_density
 *   smagorinsky_constant    0.1   Cs of effect.turbulence: nu_t = (Cs l0)^2 |S|
 *   neighbour_skin          0.4   extra radius of the neighbour list, in l0
 *   excitation_acceleration 0     A of a shaken tank's horizontal acceleration
 *                                 A sin(2 pi t / T) (m/s^2); effect.excitation
 *   excitation_period       1.0   T (s)
 *   threads                 1     threads of the particle loops (OpenMP builds);
 *                                 0 = OpenMP's default (OMP_NUM_THREADS); per
 *                                 solver; the results are the same bits for any
 *                                 count (docs/performance.md); called from inside
 *                                 the host's own OpenMP parallel region, a solver
 *                                 runs on the calling thread
 *   memory_limit            0     bytes a scene or a solver may take (bytes);
 *                                 0 = the memory the system gives the process:
 *                                 physical memory, or less under RLIMIT_AS,
 *                                 RLIMIT_DATA or a cgroup limit. Checked before
 *                                 allocating, against 44 bytes a particle for a
 *                                 scene (when it grows) and an estimate of a
 *                                 solver (its arrays and the neighbour lists of a
 *                                 filled lattice, about 850 bytes a particle with
 *                                 the defaults; with a team of threads, the
 *                                 lists' or the matrix's part, the larger, up
 *                                 to twice: each thread's run is built apart
 *                                 before it is copied in) at creation and
 *                                 checkpoint loading:
 *                                 MPS2P_ERR_NOMEM beyond it. (With the kernel's
 *                                 overcommit, malloc of too much succeeds and the
 *                                 process is killed later, while writing.)
 * mps2p_param_info() lists them at run time. */
MPS2P_API int mps2p_scene_set_param(mps2p_scene *scene, const char *key, double value);
MPS2P_API int mps2p_scene_get_param(const mps2p_scene *scene, const char *key,
                                    double *value);

/* Choices, by name:
 *   pressure_solver   "cg" (default: preconditioned conjugate gradients to
 *                     cg_tolerance), "cholmod" (sparse direct; slower from a
 *                     few hundred particles on: docs/performance.md), or
 *                     "gamg": PETSc's CG with its algebraic multigrid
 *                     (cg_tolerance, cg_max_iterations), only in a build
 *                     with PETSc (listed by mps2p_option_choice there;
 *                     elsewhere refused, MPS2P_ERR_INVALID); its solves are
 *                     serialised across threads (docs/guarantees.md)
 *   cg_preconditioner "two_level" (default): the diagonal plus a coarse
 *                     correction on aggregates of neighbouring unknowns
 *                     (CHOLMOD factorises the coarse matrix), iterations
 *                     that do not grow with the system (46-56 a step from
 *                     12,678 to 106,592 particles against Jacobi's 350-485;
 *                     docs/performance.md); "jacobi": the diagonal alone;
 *                     "ic0": incomplete Cholesky with the matrix's own
 *                     pattern, about 3.5 times fewer iterations than Jacobi
 *                     at twice the cost of one
 *   scheme            "corrected" (default) or "koshizuka1996": sets
 *                     pressure_gradient, ppe_source, wall_ghosts,
 *                     surface_pressure and the parameters marked * above
 *                     together (docs/validation.md
 *                     measures both); set it first, then change any of them;
 *                     reads "custom" once one differs from both schemes
 *   pressure_gradient "corrected" (default): p_i as reference and the
 *                     corrective matrix, exact for linear fields (Khayyer and
 *                     Gotoh); "minimum" (koshizuka1996): Koshizuka and Oka's
 *                     gradient with p^_i = min of the neighbours' pressures
 *                     as reference (docs/method.md, the paper's form)
 *   ppe_source        "ecs" (default): a (n* - n^k) + |n^k - n0|/n0 (n^k - n0),
 *                     an error-compensating form; "density" (koshizuka1996):
 *                     gamma (n* - n0), gamma = ppe_relaxation; "mixed":
 *                     a (n* - n^k) + gamma (n^k - n0) (all over n0, times
 *                     rho/dt^2; a = ppe_step_gain)
 *   wall_ghosts       "hydrostatic" (default): a dummy wall, or a wall on the
 *                     free surface, takes p_i + rho_i g . r_ij seen from
 *                     particle i, in the PPE and the gradient; "none"
 *                     (koshizuka1996): dummies only fill the number density
 *                     and a dry wall holds p = 0
 *   surface_pressure  "extrapolated" (default): a free-surface fluid particle
 *                     is an unknown, its missing neighbours the linear
 *                     extrapolation of its pressure to 0 half a spacing
 *                     beyond it, where the water's top lies (still water's
 *                     pressure is that of the water's depth); "centre"
 *                     (koshizuka1996): p = 0 at its centre, the pressure of
 *                     a depth l0/2 short (docs/method.md)
 *   ppe_pattern       "distance" (default): the PPE matrix holds the pairs
 *                     within re_laplacian; "neighbour_list": every pair of
 *                     the neighbour list (zeros beyond re_laplacian), a
 *                     pattern that stands while the list and the unknowns
 *                     do, so CHOLMOD reuses its analysis (still water: one
 *                     analysis instead of one a step; docs/performance.md)
 *   effect.gravity, effect.viscosity, effect.collision
 *                     "auto" (default): on when the scene needs it (non-zero
 *                     gravity; a fluid with viscosity > 0; collision_distance
 *                     > 0); "on": required (solver creation fails with
 *                     MPS2P_ERR_INVALID if the scene cannot support it);
 *                     "off": left out. An effect that is off costs nothing:
 *                     its stages are not in the step.
 *   free_surface      "number_density" (default): n* < beta n0 (docs/method.md);
 *                     "neighbour_count": that, or fewer neighbours than
 *                     beta_count N0 (its own stage, neighbour_count)
 *   effect.excitation "auto": on when excitation_acceleration != 0: every
 *                     fluid particle feels -A sin(2 pi t / T) along x (the
 *                     tank's frame; sloshing), a stage after gravity
 *   effect.turbulence "auto" and "off": off; "on": a sub-particle-scale eddy
 *                     viscosity (Smagorinsky, smagorinsky_constant), a
 *                     stage after the viscous one; possible in any scene
 *   effect.two_phase  "auto": on when a fluid is light (density below
 *                     light_fraction of the heaviest) and two_phase_model is
 *                     not "single": the two-step pressure (liquid PPE, then
 *                     gas PPE; docs/two-phase.md, a PROTOTYPE)
 *   effect.interface_reaction  "auto": on with two_phase and
 *                     two_phase_model "two_step_improved"
 *   effect.gas_buffer "auto": on with two_phase, gravity,
 *                     gas_buffer_depth > 0 and gas_buffer_rate > 0: the gas's top boundary, a layer
 *                     under the gas's top at the first step where the gas's
 *                     velocity is damped (gas_buffer_depth, gas_buffer_rate);
 *                     "off": an open top (docs/two-phase.md, rung 6)
 *   two_phase_model   "two_step_improved" (default; docs/method.md 3), "two_step"
 *                     (Koshizuka's conventional model, docs/method.md 2) or
 *                     "single" (one PPE over every fluid, as without air)
 *   interface_reaction what delta_al = 1 does in two_step_improved: "drift",
 *                     the one form left (the bubble drift closure; the
 *                     others' record is in docs/two-phase.md)
 * Two-phase parameters (light_fraction, trigger_speed, sector_scan_walls,
 * join_bubbles, join_enclosed, join_hold, join_ramp_time, bubble_rise_velocity,
 * bubble_relaxation_time, drift_without_gravity,
 * gas_liquid_volume, gas_correction_limit, gas_cg_tolerance,
 * gas_pressure_limit, gas_buffer_depth, gas_buffer_rate): mps2p_param_info,
 * docs/two-phase.md.
 * Water at rest stays still with the default scheme; Koshizuka and Oka's
 * lets a still square lattice shear and rearrange (docs/validation.md). */
MPS2P_API int mps2p_scene_set_option(mps2p_scene *scene, const char *key,
                                     const char *value);
MPS2P_API int mps2p_scene_get_option(const mps2p_scene *scene, const char *key,
                                     const char **value);

/* Particles outside this box count as diverged, except fluid particles up
 * to parameter out_limit's share: those become MPS2P_KIND_OUT. Default: the
 * box around the initial particles, widened by its own width and height on
 * every side. */
MPS2P_API int mps2p_scene_set_domain(mps2p_scene *scene, double xmin, double ymin,
                                     double xmax, double ymax);

/* The index-th numeric parameter (0, 1, ...): its key, a one-line
 * description and its default. MPS2P_ERR_INVALID past the last one. Any
 * output pointer may be NULL. */
MPS2P_API int mps2p_param_info(size_t index, const char **key,
                               const char **description, double *default_value);
/* How many numeric parameters mps2p_param_info lists. */
MPS2P_API int mps2p_param_count(size_t *count);

/* The options (named choices) at run time, index 0 to count - 1: its key, a
 * one-line description, its default choice and how many choices it has;
 * mps2p_option_choice gives the choice-th name (0 to choices - 1). The last
 * option is "scheme". MPS2P_ERR_INVALID past the last one. Any output
 * pointer may be NULL; the strings are static. */
MPS2P_API int mps2p_option_count(size_t *count);
MPS2P_API int mps2p_option_info(size_t index, const char **key, const char **description,
                                const char **default_choice, size_t *choices);
MPS2P_API int mps2p_option_choice(size_t index, size_t choice, const char **name);

/* ---------------------------------------------------------------------------
 * 3. Solver
 * ------------------------------------------------------------------------- */

typedef struct mps2p_solver mps2p_solver;

/* Builds a solver from a copy of the scene (the scene may then be changed or
 * destroyed). Fails on a scene without fluid particles, on particles closer
 * than 0.1 l0 to each other, on radii raised past a tank's wall layers after
 * it was added, and on inconsistent parameters. */
MPS2P_API int mps2p_solver_create(const mps2p_scene *scene, mps2p_solver **solver);
/* From the solver's own progress callback: freed when the run returns
 * (see mps2p_progress_fn). */
MPS2P_API void mps2p_solver_destroy(mps2p_solver *solver);
MPS2P_API const char *mps2p_solver_last_error(const mps2p_solver *solver);

/* One time step. On MPS2P_ERR_DIVERGED or MPS2P_ERR_SOLVE the solver keeps
 * the state from before the step, and the message names the particle,
 * position and time. Once diverged, further steps return MPS2P_ERR_STATE. */
MPS2P_API int mps2p_solver_step(mps2p_solver *solver);

/* Called after each step; return non-zero to stop the run. From inside it,
 * the calls that step the same solver or replace its state
 * (mps2p_solver_step, _advance_to, _advance_window, _restore_state) return
 * MPS2P_ERR_STATE and change nothing; queries, checkpoints, results and the
 * inputs of section 7 (gravity, body motions, forces: they apply from the
 * next step) work. mps2p_solver_destroy of that solver from inside does not
 * free it at once: the run stops after the callback, the solver is freed
 * when mps2p_solver_advance_to returns, and that returns MPS2P_ERR_STATE
 * ("destroyed") - the caller must not use the solver afterwards. Other
 * solvers may be used freely. A C++ exception thrown from the callback
 * (in a GCC or Clang build of the library, which unwinds through it)
 * passes to the caller of mps2p_solver_advance_to and ends the run: the
 * solver keeps the state of the step before the callback and may be stepped
 * again (or, destroyed from inside, is freed). Do not longjmp out of it. */
typedef int (*mps2p_progress_fn)(const mps2p_solver *solver, void *user_data);

/* Steps until the time reaches end_time exactly: each step is the remaining
 * time divided evenly into steps no longer than the chosen dt, so the run
 * lands on end_time without one short step (a short step biases the pressure
 * read there, which scales with 1/dt^2). Every step of such a division is
 * longer than dt / 2. A window shorter than dt / 2 is one step of its
 * length, whose pressure Poisson equation is solved as for a step of dt / 2
 * (a tiny step solved with its own dt would press the whole density error
 * out at once, with a pressure growing as 1/dt^2: a false divergence); its
 * velocity and position corrections are those of its own length. A rest
 * within 1e-12 max(1, |end_time|) s is not stepped; the time is set to
 * end_time. A window that would take more than 1e9 steps at the chosen dt
 * (checked before each step; e.g. a viscosity of 1e20 m^2/s gives dt 1e-24
 * s) is refused with MPS2P_ERR_INVALID, naming the bound that sets dt; the
 * solver keeps the state of its last step. Returns MPS2P_OK, MPS2P_STOPPED
 * when the callback asked to stop, or the error of the failing step.
 * progress may be NULL. */
MPS2P_API int mps2p_solver_advance_to(mps2p_solver *solver, double end_time,
                                      mps2p_progress_fn progress, void *user_data);

/* ---------------------------------------------------------------------------
 * 4. Results
 * ------------------------------------------------------------------------- */

MPS2P_API int mps2p_solver_particle_count(const mps2p_solver *solver, size_t *count);
/* length is the buffer's length in elements: 2 * count for vectors. */
MPS2P_API int mps2p_solver_get_positions(const mps2p_solver *solver, double *out, size_t length);
MPS2P_API int mps2p_solver_get_velocities(const mps2p_solver *solver, double *out, size_t length);
MPS2P_API int mps2p_solver_get_pressure(const mps2p_solver *solver, double *out, size_t length);
MPS2P_API int mps2p_solver_get_number_density(const mps2p_solver *solver, double *out, size_t length);
/* MPS2P_KIND_* per particle. Kinds change during a run: a fluid particle
 * that leaves the domain turns from MPS2P_KIND_FLUID to MPS2P_KIND_OUT
 * (parameter out_limit), at the end of the step that took it out. */
MPS2P_API int mps2p_solver_get_kinds(const mps2p_solver *solver, int *out, size_t length);
/* fluid id per particle (MPS2P_KIND_OUT particles keep theirs); -1 for wall
 * and dummy particles */
MPS2P_API int mps2p_solver_get_fluid_ids(const mps2p_solver *solver, int *out, size_t length);

MPS2P_API int mps2p_solver_get_time(const mps2p_solver *solver, double *time);
MPS2P_API int mps2p_solver_get_step_count(const mps2p_solver *solver, uint64_t *steps);
MPS2P_API int mps2p_solver_get_last_dt(const mps2p_solver *solver, double *dt);

/* Statistics by name, of the current state or the last step ("fluid": the
 * fluid particles in the run, not those of MPS2P_KIND_OUT):
 *   max_speed          largest fluid speed (m/s)
 *   kinetic_energy     sum of m u^2 / 2 over fluid, m = rho l0^2 (J per m depth)
 *   potential_energy   sum of -m g.r over fluid (J per m depth; 0 with effect
 *                      gravity off)
 *   pressure_min, pressure_max   over fluid and wall particles (Pa)
 *   ppe_unknowns       unknowns of the last pressure solve
 *   ppe_iterations     CG iterations of the last solve (0 for cholmod)
 *   ppe_residual       relative residual |Ax - b| / |b| of the last solve
 *   surface_particles  particles flagged free surface in the last step
 *   n0, lambda         reference number density and Laplacian constant
 *   neighbour_builds   times the neighbour list was built so far
 *   ppe_iterations_total  CG iterations of all solves so far
 *   dt_next            the time step the next mps2p_solver_step would take (s)
 *   eddy_viscosity_max largest eddy viscosity of the last step (m^2/s; 0
 *                      unless effect.turbulence is on)
 *   ppe_analyses       CHOLMOD symbolic analyses so far (a pressure matrix with
 *                      the previous one's pattern reuses its analysis; 0 for cg)
 *   memory_bytes       memory the solver holds (arrays, lists, matrix, solver
 *                      workspace; CHOLMOD's last factor, kept for the next
 *                      matrix of the same pattern, included)
 *   diverged_particle  the particle a divergence was found at (its place in the
 *                      kept state is where it started the failed step); -1 when
 *                      the solver has not diverged or the particle is not known
 *   closest_pair       smallest distance from a fluid particle to any other
 *                      particle (l0; computed when asked, from the neighbour list)
 *   fluid_out          fluid particles that left the domain and are out of the
 *                      run (MPS2P_KIND_OUT; parameter out_limit)
 *   threads            threads the particle loops run on: parameter threads,
 *                      or OpenMP's default for 0 (OMP_NUM_THREADS, else the
 *                      cores); 1 in a build without OpenMP or when asked
 *                      inside a host's OpenMP parallel region (where the
 *                      loops run on one thread); as the calling thread sees it
 * With two phases (0 when effect two_phase is off): gas_triggered (light
 *   particles with delta_al = 1 in the last step), gas_enclosed (heavy
 *   particles in all 8 sectors), gas_joined (reacting), gas_pressure_max (Pa,
 *   over light particles moved by the gas), gas_ppe_unknowns,
 *   gas_ppe_iterations, gas_capped (light particles whose correction was
 *   capped at gas_correction_limit), gas_in_liquid (light particles inside the
 *   heavy fluid: more heavy than light neighbours within re_density, or heavy
 *   fluid above and heavy fluid or wall below; computed when asked),
 *   gas_in_bubbles (light particles cut off from the gas's free surface),
 *   gas_buffered (light particles the gas's damping layer slowed, effect
 *   gas_buffer), two_phase_active (1 when the effect is on). */
MPS2P_API int mps2p_solver_get_stat(const mps2p_solver *solver, const char *key,
                                    double *value);

/* The statistics at run time, index 0 to count - 1 (the solver's, then the
 * two phases', in the order `mps2p info` lists them): its
 * key for mps2p_solver_get_stat, a one-line description with its unit, and
 * whether it counts something (*is_count 1: a whole number). MPS2P_ERR_INVALID
 * past the last one. Any output pointer may be NULL; the strings are static. */
MPS2P_API int mps2p_stat_count(size_t *count);
MPS2P_API int mps2p_stat_info(size_t index, const char **key, const char **description,
                              int *is_count);

/* ---------------------------------------------------------------------------
 * 5. Files and probes: HDF5 results (with an XDMF sidecar for ParaView),
 *    checkpoints, point probes and the surge front
 *
 * The file layouts are in docs/results-files.md. Every file error is
 * MPS2P_ERR_IO with a message naming the file and what failed; HDF5's own
 * error printing is switched off for the duration of each call (and the
 * calling thread's setting restored after it). Different handles and files
 * may be used from different threads at once, as everywhere in the library.
 * ------------------------------------------------------------------------- */

typedef struct mps2p_results mps2p_results;

/* Creates (or truncates) the HDF5 results file at path and writes the run's
 * metadata: library version, l0, n0, lambda, domain, every numeric parameter
 * and option by name, the fluids (name, density, kinematic viscosity) and
 * scene_text, the text of the scene file the run came from (may be NULL).
 * Also (re)writes the XDMF sidecar: path with ".h5" replaced by ".xdmf"
 * (".xdmf" appended when path does not end in ".h5"). The file stays open
 * until mps2p_results_close. */
MPS2P_API int mps2p_results_create(const char *path, const mps2p_solver *solver,
                                   const char *scene_text, mps2p_results **results);

/* Appends the solver's current state as the group /snapshots/NNNNNN (000000,
 * 000001, ...): attributes time (s) and step, datasets position and velocity
 * (n x 2), pressure (Pa), number_density, kind and fluid_id (int). Flushes the
 * file, then rewrites the XDMF sidecar atomically. The solver must have the
 * particle count of the one the file was created with (MPS2P_ERR_INVALID). */
MPS2P_API int mps2p_results_write_snapshot(mps2p_results *results,
                                           const mps2p_solver *solver);

/* Appends the row (time, value) to the n x 2 dataset /series/<name>, created
 * on first use. name: 1 to 64 characters among letters, digits, '_', '-' and
 * '.', not starting with '.' (MPS2P_ERR_INVALID otherwise); time and value
 * must be finite. Rows reach the disk at the next snapshot or at close. */
MPS2P_API int mps2p_results_append_series(mps2p_results *results, const char *name,
                                          double time, double value);

/* Flushes and closes the file and frees the handle, whatever the outcome;
 * returns the status of closing (MPS2P_ERR_IO if HDF5 could not). NULL is
 * accepted (MPS2P_OK). */
MPS2P_API int mps2p_results_close(mps2p_results *results);
MPS2P_API const char *mps2p_results_last_error(const mps2p_results *results);

/* Writes everything the next step depends on (state, particle properties,
 * parameters, derived constants, time, step count, last dt, the diverged
 * flag, the neighbour list's reference positions; the wall bodies, their
 * motions and targets, gravity and the accelerations of section 7; with
 * effect two_phase on, the two-phase state that carries into the next step:
 * join weights, joined flags, the liquid's initial number density, the liquid
 * and gas pressures) to path, atomically: it is
 * written to "<path>.tmp", flushed to disk and renamed over path. Format 4:
 * an HDF5 file whose 512-byte user block holds a CRC-64 of the whole file
 * (docs/results-files.md). */
MPS2P_API int mps2p_solver_save_checkpoint(const mps2p_solver *solver, const char *path);

/* Rebuilds a solver from a checkpoint. Stepping it gives bitwise the results
 * the saved solver would have given (same library build). Refuses, with
 * MPS2P_ERR_IO: a missing or unreadable file, anything but a regular file
 * (a FIFO, a directory), a file that is not a libmps2p checkpoint, a
 * damaged one (checksum, length: checked on the raw bytes before HDF5 reads
 * the file), a newer format version, datasets of the wrong shape or type,
 * contents mps2p_solver_create would not give (kinds, fluid ids, parameters
 * out of range, a negative time or number density, particles outside the
 * domain other than MPS2P_KIND_OUT ones, OUT particles that move or carry a
 * pressure, a fluid_out count that is not theirs, n0 or lambda that do not follow from l0, densities that are not
 * their fluid's; the message names the field), a two-phase state missing or
 * out of range where the fluids and parameters make two phases, or present
 * where they make one. Files of format 3 and older (no checksum) load
 * unchecked. An empty path is MPS2P_ERR_INVALID; a solver beyond the file's
 * memory_limit MPS2P_ERR_NOMEM. */
MPS2P_API int mps2p_solver_load_checkpoint(const char *path, mps2p_solver **solver);

/* Samples the particles at count points (points: x0, y0, x1, y1, ...), with
 * the MPS weight w(r) = re / r - 1 (r < re, re the density radius
 * re_density l0), over the particles in the run (not MPS2P_KIND_OUT ones):
 *   pressure[k]   sum of w p over fluid and wall particles / sum of w (Pa);
 *   velocity      sum of w u over fluid particles / sum of w (m/s; 2*count;
 *                 may be NULL);
 *   inside[k]     1 when the summed weight of the fluid particles around the
 *                 point is at least beta n0 / 2 (about half a full
 *                 neighbourhood: within roughly half a spacing of the free
 *                 surface or deeper), else 0 (may be NULL).
 * Points outside the fluid get pressure 0, velocity 0 and inside 0. A point
 * on a particle is dominated by that particle's values. Cost: one pass over the
 * particles plus the neighbours of each point. */
MPS2P_API int mps2p_solver_probe(const mps2p_solver *solver, size_t count,
                                 const double *points, double *pressure,
                                 double *velocity, int *inside);

/* Surge front: the largest x among fluid particles in the run of fluid
 * fluid_id (-1 = any fluid) with y < below_y (INFINITY = no limit), plus l0 / 2 (m).
 * MPS2P_ERR_INVALID if no particle qualifies. */
MPS2P_API int mps2p_solver_front(const mps2p_solver *solver, int fluid_id, double below_y,
                                 double *front_x);

/* ---------------------------------------------------------------------------
 * 6. Effects and what the step costs
 * ------------------------------------------------------------------------- */

/* The physical effects, each on or off for this solver and why: *reason is
 * "inferred: ...", "requested: on; ..." or "requested: off; ..." (then what the
 * scene has that decides it) and stays valid while the solver lives.
 * index runs from 0 to count - 1. Any output pointer may be NULL. */
MPS2P_API int mps2p_solver_effect_count(const mps2p_solver *solver, size_t *count);
MPS2P_API int mps2p_solver_get_effect(const mps2p_solver *solver, size_t index,
                                      const char **name, int *active, const char **reason);

/* The stages of a step, index 0 to count - 1 in the order a step runs them
 * (neighbours, number_density_start, ..., viscosity, ..., advection,
 * collision, number_density, ..., pressure_solve, ..., correction, ...,
 * divergence_check; docs/internals.md lists them): whether each is in this
 * solver's next step, its wall time in seconds and its calls since creation
 * or the last reset. neighbours (index 0) also runs after advection and
 * collision, each run a call. Names stay; an index moves when a stage is
 * added before it, so look stages up by name. Timing costs two clock reads
 * per stage. */
MPS2P_API int mps2p_solver_stage_count(const mps2p_solver *solver, size_t *count);
MPS2P_API int mps2p_solver_get_stage(const mps2p_solver *solver, size_t index,
                                     const char **name, int *active, double *seconds,
                                     uint64_t *calls);
MPS2P_API int mps2p_solver_reset_stage_timings(mps2p_solver *solver);

/* ---------------------------------------------------------------------------
 * 7. Coupling: wall bodies, forces on them, host-driven walls and inputs
 *
 * A body is a named group of wall and dummy particles. Every solid belongs
 * to one: those added by mps2p_scene_add_wall_box, _add_tank and
 * _add_particles to body 0, "walls", which always exists. Functions taking
 * a body name add to the body of that name, creating it (ids 1, 2, ... in
 * order of creation) when there is none. The calling sequence of a coupling
 * adapter, units and discrete forms: docs/embedding.md.
 * ------------------------------------------------------------------------- */

/* Fills a box with solid particles of body name, as mps2p_scene_add_wall_box
 * (walls where they face a free lattice site, dummies behind). */
MPS2P_API int mps2p_scene_add_body_box(mps2p_scene *scene, const char *name,
                                       double x0, double y0, double x1, double y1,
                                       int *body_id);
/* Adds count particles of body name at positions (2*count); kinds are
 * MPS2P_KIND_WALL or MPS2P_KIND_DUMMY. */
MPS2P_API int mps2p_scene_add_body_particles(mps2p_scene *scene, const char *name,
                                             size_t count, const double *positions,
                                             const int *kinds, int *body_id);
/* Moves the solid particles already in the scene whose position lies in
 * [x0,x1] x [y0,y1] into body name (e.g. one wall of a tank).
 * MPS2P_ERR_INVALID when the box holds none. A tank's floor layers run under
 * its side walls: for a side wall alone start the box at the floor's top
 * (y0 = the tank's y0), or it takes the corner's particles and their load. */
MPS2P_API int mps2p_scene_assign_body(mps2p_scene *scene, const char *name,
                                      double x0, double y0, double x1, double y1,
                                      int *body_id);
/* Bodies in the scene, "walls" included (so at least 1). */
MPS2P_API int mps2p_scene_body_count(const mps2p_scene *scene, int *count);

MPS2P_API int mps2p_solver_body_count(const mps2p_solver *solver, int *count);
/* *name stays valid while the solver lives. Any output pointer may be NULL. */
MPS2P_API int mps2p_solver_get_body(const mps2p_solver *solver, int body_id,
                                    const char **name, size_t *particles);
/* body id per particle; -1 for fluid particles. */
MPS2P_API int mps2p_solver_get_body_ids(const mps2p_solver *solver, int *out, size_t length);

/* Force (N per metre of depth) and moment (N m per metre, counter-clockwise
 * positive, about the point about; NULL = the origin) that the fluid's
 * pressure exerts on the body, in the current state:
 *   F = sum_i p_i l0 n_i over the body's wall particles i,
 *   n_i = the unit normal of the wall at i, pointing from the fluid into
 *         the wall: perpendicular to the main axis of sum_j w_ij r_ij r_ij^T
 *         / |r_ij|^2 over the wall particles j around i (any body, within
 *         re_density), oriented by the fluid side s_i = sum_j w_ij (r_i - r_j)
 *         / |r_ij| over fluid neighbours j; where the walls around i form no
 *         clear line (a corner: smaller eigenvalue >= 1/4 of the larger),
 *         n_i = s_i / |s_i|. Wall particles with p_i = 0 or no fluid
 *         neighbour add nothing.
 *   M = sum_i (r_i - about) x p_i l0 n_i.
 * fluid_id >= 0 gives that fluid's part: each p_i l0 n_i times the share of
 * that fluid in sum_j w_ij (the parts add up to fluid_id = -1, all fluids).
 * Pressure only: viscous shear on walls is not included. moment may be NULL. */
MPS2P_API int mps2p_solver_body_force(const mps2p_solver *solver, int body_id, int fluid_id,
                                      double force[2], double *moment, const double about[2]);

/* The same force particle by particle, for a host whose structure deforms:
 * loads[2 i], loads[2 i + 1] = p_i l0 n_i (N/m) for each wall particle i of
 * the body (as mps2p_solver_body_force counts it, fluid_id the same), 0 for
 * every other particle; length at least 2 * particle count. Summed over the
 * body's particles in index order they give mps2p_solver_body_force's F,
 * bit for bit. */
MPS2P_API int mps2p_solver_get_wall_loads(const mps2p_solver *solver, int body_id, int fluid_id,
                                          double *loads, size_t length);

/* Sets the body's rigid motion from the next step on, until changed: its
 * particles move with u = velocity + angular_velocity x (r - about) (rad/s,
 * counter-clockwise positive), positions advanced by the exact rotation and
 * translation each step, velocities set to u so that the fluid's viscosity
 * (no-slip), collisions and pressure see the moving wall. about moves with
 * velocity; it may be NULL when angular_velocity is 0. Zero motion puts the
 * body at rest (velocities 0). Bodies at rest cost nothing: the stage
 * body_motion is in the step only while a body moves. */
MPS2P_API int mps2p_solver_set_body_motion(mps2p_solver *solver, int body_id,
                                           const double velocity[2], double angular_velocity,
                                           const double about[2]);
/* Positions (2 per particle of the body, in particle order; length =
 * 2 * its particles) that the body's particles reach at the end of the next
 * step; during that step their velocity is (target - r) / dt. Used by one
 * step (then the body follows its rigid motion); NULL clears them. */
MPS2P_API int mps2p_solver_set_body_positions(mps2p_solver *solver, int body_id,
                                              const double *positions, size_t length);

/* Gravity from the next step on (m/s^2). The time step bound dt_max stays
 * the one derived at creation. With effect.gravity "on", zero gravity is
 * refused (MPS2P_ERR_INVALID) and the old gravity kept. */
MPS2P_API int mps2p_solver_set_gravity(mps2p_solver *solver, double gx, double gy);
MPS2P_API int mps2p_solver_get_gravity(const mps2p_solver *solver, double gravity[2]);

/* Body forces in the continuum sense, per unit mass, on the fluid (not forces
 * on this section's wall bodies): per-particle accelerations (m/s^2, 2 per
 * particle, length = 2 * particle
 * count; entries of non-fluid particles are ignored) added to the fluid in
 * every step, after gravity, until replaced or cleared with NULL. The stage
 * external_forces is in the step only while they are set. */
MPS2P_API int mps2p_solver_set_body_forces(mps2p_solver *solver, const double *accelerations,
                                           size_t length);

/* One coupling window: mps2p_solver_advance_to(solver, end_time) (equal
 * steps, landing on end_time exactly), with the number of steps that
 * succeeded written to *steps_taken (may be NULL), also when a step fails. */
MPS2P_API int mps2p_solver_advance_window(mps2p_solver *solver, double end_time,
                                          uint64_t *steps_taken);

/* The solver's state in memory, for implicit coupling iterations: take a
 * window, read the forces, put the state back and take it again with
 * corrected inputs. A state holds everything the next step depends on, as a
 * checkpoint does: positions, velocities, pressure (the pressure solve's
 * warm start), number density, free-surface flags, the neighbour list's
 * build positions and count, time, step count, last dt, the diverged flag,
 * the kinds and the count of fluid particles out of the run (MPS2P_KIND_OUT),
 * parameters (gravity included), every body's motion and targets, the
 * accelerations, and with two phases what a checkpoint holds of them.
 * Restoring it gives bitwise the run the solver would have had from that
 * point (inputs included: set new ones after restoring), and
 * clears a divergence that happened since (and puts back in the run the fluid
 * particles that left the domain since). A state fits only a solver with the
 * same particles, kinds (MPS2P_KIND_FLUID and _OUT alike) and bodies (its
 * own, or one created from the same scene): others, and a state of a single-phase solver into a two-phase one
 * or the other way round, are refused with MPS2P_ERR_INVALID and nothing
 * changes. It takes about 9 doubles per particle (4 doubles and 2 bytes more
 * with two phases); one state can be restored many times. */
typedef struct mps2p_state mps2p_state;

MPS2P_API int mps2p_solver_save_state(const mps2p_solver *solver, mps2p_state **state);
/* On MPS2P_ERR_NOMEM for the host's inputs nothing changes; on MPS2P_ERR_NOMEM
 * for the neighbour list the state is restored and the list rebuilt at the
 * next step (the run then differs in rounding from the saved one's). */
MPS2P_API int mps2p_solver_restore_state(mps2p_solver *solver, const mps2p_state *state);
MPS2P_API void mps2p_state_destroy(mps2p_state *state);

#ifdef __cplusplus
}
#endif

#endif /* MPS2P_H */
