/* Host inputs on the fluid between steps: gravity (sloshing tanks, a moving
 * frame) and per-particle accelerations. The stage external_forces adds
 * u* += dt a_i to fluid particles, after gravity; it is in the step only
 * while accelerations are set. */
#include "core/core.h"
#include "coupling/coupling.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int external_forces_wanted(const mps2p_solver *s)
{
    return s->coupling && s->coupling->acceleration;
}

int external_forces_apply(mps2p_solver *s, double dt)
{
    double *u = s->state.velocity;
    const double *a = s->coupling->acceleration;
    for (size_t i = 0; i < s->count; i++) {
        if (s->kind[i] != MPS2P_KIND_FLUID)
            continue;
        u[2 * i] += dt * a[2 * i];
        u[2 * i + 1] += dt * a[2 * i + 1];
    }
    return MPS2P_OK;
}

int mps2p_solver_set_gravity(mps2p_solver *s, double gx, double gy)
{
    error_clear();
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_set_gravity: solver is NULL");
    if (!isfinite(gx) || !isfinite(gy))
        return fail(s->error, MPS2P_ERR_INVALID,
                    "mps2p_solver_set_gravity: gravity must be finite, got (%g, %g)", gx, gy);
    const double before[2] = {s->params.gravity[0], s->params.gravity[1]};
    s->params.gravity[0] = gx;
    s->params.gravity[1] = gy;
    /* effect.gravity "auto" follows; "on" refuses zero gravity, as at creation */
    int status = effects_decide(s);
    if (status != MPS2P_OK) {
        s->params.gravity[0] = before[0];
        s->params.gravity[1] = before[1];
        char why[ERROR_MESSAGE_SIZE];
        snprintf(why, sizeof why, "%s", mps2p_last_error());
        effects_decide(s);
        return fail(s->error, status, "mps2p_solver_set_gravity: %s", why);
    }
    s->plan_stale = 1;
    return MPS2P_OK;
}

int mps2p_solver_get_gravity(const mps2p_solver *s, double gravity[2])
{
    error_clear();
    if (!s || !gravity)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_get_gravity: %s is NULL",
                    s ? "gravity output" : "solver");
    gravity[0] = s->params.gravity[0];
    gravity[1] = s->params.gravity[1];
    return MPS2P_OK;
}

int mps2p_solver_set_body_forces(mps2p_solver *s, const double *accelerations, size_t length)
{
    error_clear();
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_set_body_forces: solver is NULL");
    struct coupling *c = s->coupling;
    if (!accelerations) {
        free(c->acceleration);
        c->acceleration = NULL;
        s->plan_stale = 1;
        return MPS2P_OK;
    }
    if (length != 2 * s->count)
        return fail(s->error, MPS2P_ERR_BUFFER,
                    "mps2p_solver_set_body_forces: %zu values needed (2 per particle), got %zu",
                    2 * s->count, length);
    for (size_t k = 0; k < length; k++)
        if (!isfinite(accelerations[k]))
            return fail(s->error, MPS2P_ERR_INVALID,
                        "mps2p_solver_set_body_forces: acceleration of particle %zu is not "
                        "finite", k / 2);
    if (!c->acceleration && !(c->acceleration = malloc(length * sizeof *c->acceleration)))
        return fail(s->error, MPS2P_ERR_NOMEM, "out of memory for %zu accelerations", s->count);
    memcpy(c->acceleration, accelerations, length * sizeof *accelerations);
    s->plan_stale = 1;
    return MPS2P_OK;
}
