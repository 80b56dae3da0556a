/* What a coupling host feeds into a solver between steps: wall bodies, their
 * motion and the forces on them (bodies.c, body_motion.c), gravity and
 * per-particle accelerations (external_forces.c); the stages body_motion
 * and external_forces. A setter decides the effects it changes and marks the
 * plan stale: the next step rebuilds it. */
#ifndef MPS2P_COUPLING_H
#define MPS2P_COUPLING_H

#include "core/core.h"

typedef struct body {
    char name[FLUID_NAME_SIZE];
    size_t particles;   /* members, in particle order */
    size_t *member;
    /* rigid motion, kept until changed: u = velocity + omega x (r - about);
     * about moves with velocity */
    double velocity[2], angular_velocity, about[2];
    double *target;     /* 2 * particles: positions at the end of the next step, or NULL */
} body;

struct coupling {
    int body_count;
    body *bodies;
    int *body_of;          /* per particle: body id, -1 for fluid */
    double *acceleration;  /* 2n host accelerations of the fluid, or NULL */
};

/* Creates the solver's bodies from a body id per solid particle (body_of,
 * read only for solids; NULL = all in body 0) and the names of bodies 1 to
 * count - 1 (names[k - 1]; body 0 is "walls"). The ids must be in range:
 * callers validate them (the scene by construction, a checkpoint on load). */
int coupling_build(mps2p_solver *s, int count, char (*names)[FLUID_NAME_SIZE],
                   const int *body_of);

/* 1 when the body moves in the next step (a non-zero motion or targets). */
int body_moves(const body *b);

/* Creates the solver's bodies: all solids in body 0 "walls", or the scene's
 * bodies when scene is non-NULL. Called once the kinds are known. */
int coupling_create(mps2p_solver *s, const mps2p_scene *scene);
void coupling_free(struct coupling *c);
/* The stages, and when they are in the step. */
int body_motion_wanted(const mps2p_solver *s);
int body_motion_apply(mps2p_solver *s, double dt);
int external_forces_wanted(const mps2p_solver *s);
int external_forces_apply(mps2p_solver *s, double dt);
/* After a step that succeeded: rotation centres move on, targets dropped. */
void body_motion_done(mps2p_solver *s, double dt);

#endif
