/* Host-driven walls: a body's rigid motion, or the positions its particles
 * reach at the end of the next step, set between steps. The stage
 * body_motion moves the body's particles and gives them the velocity of that
 * motion at the start of the step, so that the viscous term (no-slip against
 * the wall's velocity), the collision model (approach relative to the wall)
 * and the pressure equation (the number density the moved wall makes) all
 * see the moving wall. A scene whose bodies stay put does not run the stage. */
#include "core/core.h"
#include "coupling/coupling.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int body_moves(const body *b)
{
    return b->target || b->velocity[0] != 0.0 || b->velocity[1] != 0.0 ||
           b->angular_velocity != 0.0;
}

int body_motion_wanted(const mps2p_solver *s)
{
    if (!s->coupling)
        return 0;
    for (int b = 0; b < s->coupling->body_count; b++)
        if (body_moves(&s->coupling->bodies[b]))
            return 1;
    return 0;
}

static void move_rigidly(mps2p_solver *s, body *b, double dt)
{
    double *r = s->state.position, *u = s->state.velocity;
    const double omega = b->angular_velocity, *v = b->velocity;
    /* exact rotation by omega dt about the reference point, which itself
     * moves by v dt */
    const double c = cos(omega * dt), sn = sin(omega * dt);
    for (size_t m = 0; m < b->particles; m++) {
        size_t i = b->member[m];
        double dx = r[2 * i] - b->about[0], dy = r[2 * i + 1] - b->about[1];
        u[2 * i] = v[0] - omega * dy;
        u[2 * i + 1] = v[1] + omega * dx;
        if (omega == 0.0) { /* a translation adds v dt, bitwise 0 when at rest */
            r[2 * i] += dt * v[0];
            r[2 * i + 1] += dt * v[1];
        } else {
            r[2 * i] = b->about[0] + c * dx - sn * dy + dt * v[0];
            r[2 * i + 1] = b->about[1] + sn * dx + c * dy + dt * v[1];
        }
    }
}

/* A body that stops is at rest: its particles' velocities are zero again. */
static void rest(mps2p_solver *s, const body *b)
{
    for (size_t m = 0; m < b->particles; m++) {
        size_t i = b->member[m];
        s->state.velocity[2 * i] = s->state.velocity[2 * i + 1] = 0.0;
    }
}

static void move_to_targets(mps2p_solver *s, body *b, double dt)
{
    double *r = s->state.position, *u = s->state.velocity;
    for (size_t m = 0; m < b->particles; m++) {
        size_t i = b->member[m];
        for (int d = 0; d < 2; d++) {
            u[2 * i + d] = (b->target[2 * m + d] - r[2 * i + d]) / dt;
            r[2 * i + d] = b->target[2 * m + d];
        }
    }
}

int body_motion_apply(mps2p_solver *s, double dt)
{
    for (int k = 0; k < s->coupling->body_count; k++) {
        body *b = &s->coupling->bodies[k];
        if (b->target)
            move_to_targets(s, b, dt);
        else if (body_moves(b))
            move_rigidly(s, b, dt);
    }
    return MPS2P_OK;
}

static int check_solver_body(mps2p_solver *s, int body_id, const char *function)
{
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "%s: solver is NULL", function);
    if (body_id < 0 || body_id >= s->coupling->body_count)
        return fail(s->error, MPS2P_ERR_INVALID, "%s: no body with id %d (the solver has %d)",
                    function, body_id, s->coupling->body_count);
    if (s->diverged)
        return fail(s->error, MPS2P_ERR_STATE, "%s: the solver diverged", function);
    return MPS2P_OK;
}

int mps2p_solver_set_body_motion(mps2p_solver *s, int body_id, const double velocity[2],
                                 double angular_velocity, const double about[2])
{
    error_clear();
    int status = check_solver_body(s, body_id, "mps2p_solver_set_body_motion");
    if (status != MPS2P_OK)
        return status;
    if (!velocity)
        return fail(s->error, MPS2P_ERR_NULL, "mps2p_solver_set_body_motion: velocity is NULL");
    if (angular_velocity != 0.0 && !about)
        return fail(s->error, MPS2P_ERR_NULL,
                    "mps2p_solver_set_body_motion: a rotation needs its centre (about)");
    if (!isfinite(velocity[0]) || !isfinite(velocity[1]) || !isfinite(angular_velocity) ||
        (about && (!isfinite(about[0]) || !isfinite(about[1]))))
        return fail(s->error, MPS2P_ERR_INVALID,
                    "mps2p_solver_set_body_motion: velocity, angular velocity and centre "
                    "must be finite");
    body *b = &s->coupling->bodies[body_id];
    b->velocity[0] = velocity[0];
    b->velocity[1] = velocity[1];
    b->angular_velocity = angular_velocity;
    b->about[0] = about ? about[0] : 0.0;
    b->about[1] = about ? about[1] : 0.0;
    if (!body_moves(b))
        rest(s, b);
    s->plan_stale = 1;
    return MPS2P_OK;
}

int mps2p_solver_set_body_positions(mps2p_solver *s, int body_id, const double *positions,
                                    size_t length)
{
    error_clear();
    int status = check_solver_body(s, body_id, "mps2p_solver_set_body_positions");
    if (status != MPS2P_OK)
        return status;
    body *b = &s->coupling->bodies[body_id];
    if (!positions) { /* clear */
        free(b->target);
        b->target = NULL;
        if (!body_moves(b))
            rest(s, b);
        s->plan_stale = 1;
        return MPS2P_OK;
    }
    if (length != 2 * b->particles)
        return fail(s->error, MPS2P_ERR_BUFFER,
                    "mps2p_solver_set_body_positions: body %d has %zu particles, so %zu "
                    "values are needed, got %zu", body_id, b->particles, 2 * b->particles,
                    length);
    for (size_t k = 0; k < length; k++)
        if (!isfinite(positions[k]))
            return fail(s->error, MPS2P_ERR_INVALID,
                        "mps2p_solver_set_body_positions: position %zu is not finite", k / 2);
    if (!b->target && !(b->target = malloc((length ? length : 1) * sizeof *b->target)))
        return fail(s->error, MPS2P_ERR_NOMEM, "out of memory for %zu body positions",
                    b->particles);
    memcpy(b->target, positions, length * sizeof *positions);
    s->plan_stale = 1;
    return MPS2P_OK;
}

/* After a step that succeeded (a failed one is rolled back and keeps its
 * inputs) with stage body_motion: the rotation centres move on with their
 * bodies, and targets, used by one step, are dropped. */
void body_motion_done(mps2p_solver *s, double dt)
{
    if (!body_motion_wanted(s)) /* nothing moved: about stays bitwise as it is */
        return;
    for (int k = 0; k < s->coupling->body_count; k++) {
        body *b = &s->coupling->bodies[k];
        if (b->target) {
            free(b->target);
            b->target = NULL;
            s->plan_stale = 1;
            if (!body_moves(b))
                rest(s, b);
        } else {
            b->about[0] += dt * b->velocity[0];
            b->about[1] += dt * b->velocity[1];
        }
    }
}
