/* The solver's life: creation from a scene, the step as a plan of stages
 * from one ordered table (plan.c), rollback, advancing to a time (solver.c);
 * saved states (state.c), results, statistics and probes (results.c,
 * stats.c, probes.c, memory.c), coupling windows (window.c). Offers the
 * checkpoint loader (io/) the two calls its solver is built with. */
#ifndef MPS2P_SOLVER_H
#define MPS2P_SOLVER_H

#include "core/core.h"

/* mps2p_solver_advance_to refuses a window that would take more steps. */
#define MAX_STEPS_PER_ADVANCE 1e9

/* MPS2P_ERR_STATE with a message naming function when s is inside
 * mps2p_solver_advance_to (called from its progress callback), else
 * MPS2P_OK (solver.c). */
int solver_refuse_if_running(mps2p_solver *s, const char *function);

/* Allocates every per-particle array of a zeroed solver (solver.c); the
 * checkpoint loader fills them instead of a scene. */
int solver_allocate(mps2p_solver *s, size_t n, int fluid_count);
/* Starts the neighbour list (empty) and the pressure solver, decides the
 * effects and builds the plan, once l0, params and domain are set. */
int solver_start(mps2p_solver *s);

/* Lays out the step's stages for the effects decided (effects_decide) and
 * allocates what only an active stage needs (plan.c). Inputs that change
 * the plan decide the effects and set s->plan_stale instead: the step
 * rebuilds it. */
int plan_build(mps2p_solver *s);
/* Runs one step's stages in order, timing each; stops at the first error. */
int plan_run(mps2p_solver *s, double dt);
/* Bytes the solver holds: its arrays, lists, matrix and solver workspace. */
size_t solver_memory_bytes(const mps2p_solver *s);                  /* memory.c */

#endif
