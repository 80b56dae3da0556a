/* What a coupling host feeds into a solver between steps: wall bodies and
 * their motion, per-particle accelerations. Private to the files that use it. */
#ifndef MPS2P_COUPLING_H
#define MPS2P_COUPLING_H

#include "internal.h"

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

#endif
