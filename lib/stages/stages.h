/* The single-phase stages of a step, a file each, run by the plan as
 * int (*)(mps2p_solver *, double dt) (solver/plan.c), and what they share
 * with the two phases: the MPS operators at a particle (operators.c), the
 * pressure Poisson system (pressure.c), the time step (timestep.c) and
 * where a divergence was found (divergence.c). They read no other part's
 * state: what the two phases change in them comes through the solver's
 * viscosity_mask and collision_share. */
#ifndef MPS2P_STAGES_H
#define MPS2P_STAGES_H

#include "core/core.h"

/* ---- MPS operators at particle i (operators.c) ---- */

/* A dummy, or a wall that is free surface (surface: the PPE's flags), is a
 * hydrostatic ghost under option wall_ghosts = hydrostatic (pressure.c). */
static inline int is_hydrostatic_ghost(const mps2p_solver *s, const unsigned char *surface,
                                       size_t j)
{
    return s->kind[j] == MPS2P_KIND_DUMMY || (s->kind[j] == MPS2P_KIND_WALL && surface[j]);
}
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
/* The gradient with p_i as reference over non-dummy neighbours (those of
 * mask, when given; with ghosts, a wall flagged there takes the ghost value
 * p_i + rho_i g . r_ij), times the inverse of the corrective matrix
 * (d/n0) sum_j w r_ij r_ij^T / |r_ij|^2 over the same neighbours; left
 * uncorrected where that matrix's determinant is below
 * CORRECTIVE_MIN_DETERMINANT (one-sided neighbourhoods). Both sums in one
 * pass over the neighbours. */
#define CORRECTIVE_MIN_DETERMINANT 0.1
void corrected_gradient_at(const mps2p_solver *s, size_t i, const double *pressure,
                           const unsigned char *mask, const unsigned char *ghosts,
                           double out[2]);
/* (2d / (lambda n0)) sum_j (f_j - f_i) w, per component of an interleaved field. */
void laplacian_at(const mps2p_solver *s, size_t i, const double *field, size_t components,
                  double *out);

/* The pressure gradient of option pressure_gradient at fluid particle i over
 * the neighbours of mask (NULL = all), dry walls those flagged in surface
 * (correction.c): the single phase's and the liquid's. */
void pressure_gradient_at(const mps2p_solver *s, size_t i, const double *pressure,
                          const unsigned char *mask, const unsigned char *surface,
                          double gradient[2]);

/* u += du, r += dt du for every fluid particle, du = change (correction.c):
 * the single phase's and the two phases' corrections end with it. */
void correction_apply(mps2p_solver *s, const double *change, double dt);

/* Particle shifting after the single phase's correction, when parameter
 * shifting is above 0 (correction.c). */
int particles_shift(mps2p_solver *s, double dt);

/* ---- the time step (timestep.c) ---- */

double timestep_choose(const mps2p_solver *s);
/* Which bound sets timestep_choose's dt, in words, for messages. */
void timestep_explain(const mps2p_solver *s, char *out, size_t size);

/* ---- the stages, in the order of a step ---- */

int neighbours_refresh(mps2p_solver *s, double dt);      /* neighbour_update.c */
/* n into out (number_density.c); the stages: n^k at the step's start, n* at r* */
void number_density_compute(mps2p_solver *s, double *out);
int number_density_start(mps2p_solver *s, double dt);
int viscosity_apply(mps2p_solver *s, double dt);         /* viscosity.c */
int turbulence_apply(mps2p_solver *s, double dt);        /* turbulence.c */
int gravity_apply(mps2p_solver *s, double dt);           /* gravity.c */
int excitation_apply(mps2p_solver *s, double dt);        /* excitation.c */
int advect(mps2p_solver *s, double dt);                  /* advection.c */
int collision_apply(mps2p_solver *s, double dt);         /* collision.c */
int number_density_star(mps2p_solver *s, double dt);
int neighbour_count_compute(mps2p_solver *s, double dt); /* free_surface.c */
int free_surface_detect(mps2p_solver *s, double dt);     /* free_surface.c */
int pressure_assemble(mps2p_solver *s, double dt);       /* pressure.c */
int pressure_solve(mps2p_solver *s, double dt);          /* pressure.c */
int pressure_correct(mps2p_solver *s, double dt);        /* correction.c */
int divergence_check(mps2p_solver *s, double dt);        /* divergence.c */
/* Remembers where a divergence was found (statistic diverged_particle);
 * returns status. */
int diverged_at(mps2p_solver *s, size_t i, int status);  /* divergence.c */

/* ---- the pressure Poisson system (pressure.c) ---- */

/* One PPE over a subset of the particles (pressure.c), for the two phases'
 * solves: part marks the participants (NULL = the fluid in the run and the
 * walls; masks never hold dummies or particles out of the run), surface
 * the free-surface ones (p = 0, or with surface_diagonal unknowns whose
 * pressure reaches 0 half a spacing out); n_star, n_start and density enter the source
 * (and density the diagonal); pressure holds the warm start on entry and
 * every particle's result on exit (0 for non-participants). */
typedef struct ppe_system {
    const unsigned char *part;
    const unsigned char *surface;
    const double *n_star, *n_start, *density;
    double *pressure;
    double tolerance;           /* CG tolerance; 0 = cg_tolerance */
    int hydrostatic_ghosts;     /* dummies and dry walls as ghosts (option wall_ghosts) */
    int density_source;         /* Koshizuka's source gamma (n* - n0) whatever ppe_source */
    double step_gain;           /* a, the share of n* - n^k the ecs and mixed sources answer */
    int keep_negative;          /* negative pressures kept whatever clamp_negative_pressure */
    double *surface_diagonal;   /* n, workspace: surface_pressure extrapolated; NULL: centre */
    size_t unknowns, iterations;
    double residual;
} ppe_system;
int pressure_assemble_system(mps2p_solver *s, double dt, ppe_system *sys);
/* surface_diagonal for the water's systems: the stage workspace with
 * surface_pressure extrapolated, NULL with centre (pressure.c). */
double *surface_diagonal_of(mps2p_solver *s);
int pressure_solve_system(mps2p_solver *s, ppe_system *sys);

#endif
