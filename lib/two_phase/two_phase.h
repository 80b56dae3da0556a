/* The two phases (docs/method.md sections 2-3), behind effect two_phase:
 * their state and its table (state.c), their stages (liquid_pressure.c,
 * interface_reaction.c, gas_pressure.c, correction.c, divergence.c), their
 * statistics (stats.c) and what they change in two single-phase stages
 * (collision_rule.c; the viscosity mask is set in state.c). The interface
 * reaction (option interface_reaction) lives here only. */
#ifndef MPS2P_TWO_PHASE_H
#define MPS2P_TWO_PHASE_H

#include "stages/stages.h"

#include <math.h>

/* State of the two-step pressure. Allocated by the plan only when effect
 * two_phase is on; a single-phase solver never holds one. */
typedef struct two_phase {
    struct two_phase *before_step; /* the carried state at the step's start, for rollback */
    int improved;               /* effect interface_reaction is on */
    double heavy_density;       /* of the heaviest fluid */
    double light_density;       /* of the heaviest light fluid */
    unsigned char *light;       /* per particle: fluid of a light phase (in the run or
                                 * out of it: see light_in_run) */
    unsigned char *triggered;   /* delta_al = 1 in the last step (eq. 15) */
    unsigned char *enclosed;    /* heavy particles in all 8 sectors */
    unsigned char *joined;      /* light particle taking part in the liquid solve */
    unsigned char *was_joined;  /* joined in the step before */
    unsigned char *bubble;      /* light, cut off from the gas's free surface */
    long *flood_queue;          /* light_flood's queue */
    double *join_weight;        /* weight in the liquid's number density, ramped 0..1 */
    unsigned char *heavy_part;  /* participants of the liquid PPE */
    unsigned char *heavy_mask;  /* neighbours the liquid sees: not light, or joined */
    unsigned char *gas_part;    /* participants of the gas PPE */
    unsigned char *heavy_surface, *gas_surface;
    unsigned char *gas_open;    /* light, moved by the gas, joined through gas to its top */
    double *heavy_n, *heavy_n_start; /* number density the liquid sees */
    double *heavy_pressure, *gas_pressure;
    double *gas_n;              /* number density the gas solve sees */
    double *gas_n_weight;       /* each particle's weight in it (liquid_volume, or 0) */
    double *heavy_n_initial;    /* the liquid's number density at the first step */
    int have_initial;
    double *heavy_rho, *gas_rho;     /* densities of the two PPEs' sources */
    double gas_pressure_limit;
    double gas_top;             /* height of the highest light particle at the first step */
    int have_gas_top;
    /* diagnostics of the last step */
    size_t triggered_count, enclosed_count, joined_count, capped_count, bubble_count;
    size_t buffered_count;      /* light particles the gas buffer damped */
    size_t heavy_unknowns, heavy_iterations, gas_unknowns, gas_iterations;
    double gas_pressure_max;
    /* the gas PPE's number density and free surface, prepared beside the
     * liquid's solve (gas_pressure_prepare) for this step's gas solve */
    int gas_prepared, gas_voids;
    const double *gas_n_seen;
    /* the enclosed bubbles, marked beside the sector scan on two threads
     * (interface_scan) for this step's join */
    int bubbles_marked;
    size_t bubbles_ahead;
    /* the pair sums' splits (numerics.h: pair_balance) */
    pair_balance heavy_start_blocks, heavy_blocks, gas_density_blocks;
} two_phase;


/* ---- for the solver and checkpoints ---- */

/* Allocates s->phases (the plan, when effect two_phase is on) and sets the
 * solver's viscosity_mask and collision_share. */
int phases_init(mps2p_solver *s);
void phases_free(struct two_phase *tp);
size_t phases_memory_bytes(const mps2p_solver *s);
/* What of s->phases is saved, checkpointed and rolled back, row by row
 * (state.c says why each member, and why not the others). */
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
/* The statistics (stats.c), listed after the solver's. */
extern const stat_entry two_phase_stats[];
extern const size_t two_phase_stat_count;

/* The stages, in the order of a step. */
int phases_step_start(mps2p_solver *s, double dt);     /* liquid_pressure.c: its n^k */
int interface_scan(mps2p_solver *s, double dt);        /* interface_reaction.c */
int interface_join(mps2p_solver *s, double dt);        /* interface_reaction.c */
int liquid_pressure_solve(mps2p_solver *s, double dt); /* liquid_pressure.c */
/* The gas PPE, then the state's pressure per phase (phases_pressure_combine). */
int gas_pressure_solve(mps2p_solver *s, double dt);    /* gas_pressure.c */
/* The gas solve's number density and free surface, before its matrix: run
 * by the liquid's solve beside its own on two threads, else by the gas's. */
void gas_pressure_prepare(mps2p_solver *s);
int phases_correct(mps2p_solver *s, double dt);        /* correction.c: per phase */
/* The gas's damping layer (effect gas_buffer): its top taken at the first
 * step's start (from phases_step_start), then the damping after the drift. */
void gas_buffer_reference(mps2p_solver *s);           /* gas_buffer.c */
int gas_buffer_apply(mps2p_solver *s, double dt);      /* gas_buffer.c */
int interface_drift_apply(mps2p_solver *s, double dt); /* interface_reaction.c */
int phases_divergence_check(mps2p_solver *s, double dt); /* divergence.c */

/* ---- within the part ---- */

/* A light particle in the run: light stays set for one that left the
 * domain (MPS2P_KIND_OUT, stages/divergence.c), which is in no loop of the
 * gas, no count and no solve. As a neighbour no stage sees it (the
 * neighbour list leaves it out). */
static inline int light_in_run(const mps2p_solver *s, size_t i)
{
    return s->phases->light[i] && s->kind[i] == MPS2P_KIND_FLUID;
}

/* The share of a collision's impulse between phases (collision_rule.c). */
double phases_collision_share(const mps2p_solver *s, size_t i, size_t j, int *whole);
void phases_pressure_combine(mps2p_solver *s);         /* gas_pressure.c */
/* A light particle moved by the liquid's pressure (correction.c). */
int moves_with_liquid(const mps2p_solver *s, size_t i);
/* Marks the light particles joined through light neighbours within
 * re_density to one marked in reached (the seeds), passing through none
 * moved by the liquid when skip_with_liquid (light_flood.c). */
void light_flood(mps2p_solver *s, unsigned char *reached, int skip_with_liquid);
size_t gas_in_liquid_count(const mps2p_solver *s);     /* gas_in_liquid.c */
/* A light particle with more heavy-fluid than light-fluid neighbours within re. */
int more_liquid_than_light_neighbours(const mps2p_solver *s, size_t i);
/* "Up", against the gravity the step applies (gravity_acting): returns 1 with
 * up = -g / |g|, or 0 with up = (0, 1) when there is none (zero, or effect
 * gravity off). */
static inline int gravity_up(const mps2p_solver *s, double up[2])
{
    double g[2];
    gravity_acting(s, g);
    double size = hypot(g[0], g[1]);
    int have = size > 0.0;
    up[0] = have ? -g[0] / size : 0.0;
    up[1] = have ? -g[1] / size : 1.0;
    return have;
}

#endif
