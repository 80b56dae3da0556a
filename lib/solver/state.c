/* The solver's state in memory, for a coupling host's implicit iterations:
 * everything the next step depends on (what a checkpoint holds), saved and
 * put back without a file, so that a window can be taken again with other
 * inputs. The particles' properties, derived constants and bodies' members
 * never change after creation: they are compared, not copied. With two
 * phases, the members of the two-phase state that carry into the next step
 * (two_phase/state.c) are copied too. */
#include "numerics/numerics.h"
#include "core/core.h"
#include "two_phase/two_phase.h"
#include "coupling/coupling.h"
#include "solver/solver.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct mps2p_state {
    /* the saved and matched members of the solver it came from (its table's
     * rows), nothing else allocated */
    mps2p_solver *solver;
    int body_count, *body_of;
    /* the neighbour list's */
    double *built_at;
    unsigned long builds;
    int stale;
    /* the host's inputs: per body velocity, angular velocity, about, and the
     * targets of one step (NULL when none); accelerations (NULL when none) */
    double (*motion)[5];
    double **target;
    double *acceleration;
    /* the carried two-phase members, and light; NULL for a single-phase solver */
    struct two_phase *phases;
};

#define STATE_ROWS (FIELD_SAVED | FIELD_MATCHED)

void mps2p_state_destroy(mps2p_state *st)
{
    if (!st)
        return;
    if (st->solver)
        fields_free(&solver_fields, st->solver);
    free(st->solver);
    free(st->body_of);
    free(st->built_at);
    for (int b = 0; st->target && b < st->body_count; b++)
        free(st->target[b]);
    free(st->target);
    free(st->motion);
    free(st->acceleration);
    phases_free(st->phases);
    free(st);
}

static void *copy_of(const void *from, size_t bytes)
{
    void *to = malloc(bytes ? bytes : 1);
    if (to)
        memcpy(to, from, bytes);
    return to;
}

/* Copies every array; 0 when an allocation failed (the caller frees). */
static int copy_arrays(mps2p_state *st, const mps2p_solver *s)
{
    const size_t n = s->count;
    const struct coupling *c = s->coupling;
    int ok = (st->solver = calloc(1, sizeof *st->solver)) &&
             fields_allocate(&solver_fields, st->solver, n, STATE_ROWS, 0) == MPS2P_OK &&
             (st->body_of = copy_of(c->body_of, n * sizeof *c->body_of)) &&
             (st->built_at = copy_of(s->neighbours.built_at, 2 * n * sizeof(double))) &&
             (st->motion = malloc((size_t)c->body_count * sizeof *st->motion)) &&
             (st->target = calloc((size_t)c->body_count, sizeof *st->target)) &&
             (!c->acceleration ||
              (st->acceleration = copy_of(c->acceleration, 2 * n * sizeof(double)))) &&
             (!s->phases || (st->phases = phases_copy_carried(s, STATE_ROWS)));
    for (int b = 0; ok && b < c->body_count; b++) {
        const body *bd = &c->bodies[b];
        st->motion[b][0] = bd->velocity[0];
        st->motion[b][1] = bd->velocity[1];
        st->motion[b][2] = bd->angular_velocity;
        st->motion[b][3] = bd->about[0];
        st->motion[b][4] = bd->about[1];
        if (bd->target)
            ok = (st->target[b] = copy_of(bd->target, 2 * bd->particles * sizeof(double))) != NULL;
    }
    if (ok)
        fields_copy(&solver_fields, st->solver, s, n, STATE_ROWS);
    return ok;
}

int mps2p_solver_save_state(const mps2p_solver *s, mps2p_state **state)
{
    error_clear();
    if (!state)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_save_state: state output pointer is NULL");
    *state = NULL;
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_save_state: solver is NULL");
    mps2p_state *st = calloc(1, sizeof *st);
    if (st)
        st->body_count = s->coupling->body_count;
    if (!st || !copy_arrays(st, s)) {
        mps2p_state_destroy(st);
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory saving the state of %zu particles",
                    s->count);
    }
    st->builds = s->neighbours.builds;
    st->stale = s->neighbours.stale;
    *state = st;
    return MPS2P_OK;
}

/* The same kinds, a fluid particle in the run and one out of it alike:
 * fluid particles turn MPS2P_KIND_OUT during a run (stages/divergence.c). */
static int same_kinds(const int *a, const int *b, size_t count)
{
    for (size_t i = 0; i < count; i++)
        if (a[i] != b[i] && !(kind_is_fluid(a[i]) && kind_is_fluid(b[i])))
            return 0;
    return 1;
}

/* The same particles, kinds and bodies, and two phases (with the same light
 * particles) or not: a state fits only its own solver (or one built from
 * the same scene). */
static int same_shape(const mps2p_solver *s, const mps2p_state *st)
{
    return fields_equal(&solver_fields, st->solver, s, s->count, FIELD_MATCHED) &&
           same_kinds(st->solver->kind, s->kind, s->count) &&
           st->body_count == s->coupling->body_count &&
           memcmp(st->body_of, s->coupling->body_of, s->count * sizeof *st->body_of) == 0 &&
           !st->phases == !s->phases &&
           (!s->phases ||
            fields_equal(&two_phase_fields, st->phases, s->phases, s->count, FIELD_MATCHED));
}

/* Buffers the solver lacks for the state's targets and accelerations, all
 * allocated before anything changes, so that a failure changes nothing. */
static int reserve_inputs(const mps2p_solver *s, const mps2p_state *st, double **fresh,
                          double **acceleration)
{
    const struct coupling *c = s->coupling;
    int ok = 1;
    for (int b = 0; ok && b < st->body_count; b++)
        if (st->target[b] && !c->bodies[b].target)
            ok = (fresh[b] = malloc(2 * (c->bodies[b].particles ? c->bodies[b].particles : 1) *
                                    sizeof(double))) != NULL;
    if (ok && st->acceleration && !c->acceleration)
        ok = (*acceleration = malloc(2 * s->count * sizeof(double))) != NULL;
    return ok;
}

static void put_inputs(mps2p_solver *s, const mps2p_state *st, double **fresh,
                       double *acceleration)
{
    struct coupling *c = s->coupling;
    for (int b = 0; b < st->body_count; b++) {
        body *bd = &c->bodies[b];
        bd->velocity[0] = st->motion[b][0];
        bd->velocity[1] = st->motion[b][1];
        bd->angular_velocity = st->motion[b][2];
        bd->about[0] = st->motion[b][3];
        bd->about[1] = st->motion[b][4];
        if (!st->target[b]) {
            free(bd->target);
            bd->target = NULL;
            continue;
        }
        if (!bd->target)
            bd->target = fresh[b];
        memcpy(bd->target, st->target[b], 2 * bd->particles * sizeof(double));
    }
    if (!st->acceleration) {
        free(c->acceleration);
        c->acceleration = NULL;
    } else {
        if (!c->acceleration)
            c->acceleration = acceleration;
        memcpy(c->acceleration, st->acceleration, 2 * s->count * sizeof(double));
    }
}

int mps2p_solver_restore_state(mps2p_solver *s, const mps2p_state *st)
{
    error_clear();
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_restore_state: solver is NULL");
    int refused = solver_refuse_if_running(s, "mps2p_solver_restore_state");
    if (refused != MPS2P_OK)
        return refused;
    if (!st)
        return fail(s->error, MPS2P_ERR_NULL, "mps2p_solver_restore_state: state is NULL");
    if (!same_shape(s, st))
        return fail(s->error, MPS2P_ERR_INVALID,
                    "mps2p_solver_restore_state: the state is of another solver (%zu particles, "
                    "%d fluids, %d bodies, %s; this one has %zu, %d, %d, %s, or other kinds, "
                    "bodies or light particles)",
                    st->solver->count, st->solver->fluid_count, st->body_count,
                    st->phases ? "two phases" : "one phase", s->count, s->fluid_count,
                    s->coupling->body_count, s->phases ? "two phases" : "one phase");
    double **fresh = calloc((size_t)st->body_count, sizeof *fresh), *acceleration = NULL;
    if (!fresh || !reserve_inputs(s, st, fresh, &acceleration)) {
        for (int b = 0; fresh && b < st->body_count; b++)
            free(fresh[b]);
        free(fresh);
        free(acceleration);
        return fail(s->error, MPS2P_ERR_NOMEM,
                    "mps2p_solver_restore_state: out of memory for the host's inputs");
    }
    put_inputs(s, st, fresh, acceleration);
    free(fresh);

    const size_t n = s->count;
    /* particles out of the run are in no pair: other kinds, other lists */
    const int kinds_changed = memcmp(s->kind, st->solver->kind, n * sizeof *s->kind) != 0;
    fields_copy(&solver_fields, s, st->solver, n, FIELD_SAVED);
    if (s->phases)
        phases_put_carried(s, st->phases, FIELD_SAVED);

    /* the same pairs as when saved: rebuilt from the build positions unless
     * the list still holds them */
    neighbour_list *nl = &s->neighbours;
    int status = MPS2P_OK;
    if (nl->stale || nl->builds != st->builds || kinds_changed ||
        memcmp(nl->built_at, st->built_at, 2 * n * sizeof(double)) != 0)
        status = neighbours_restore(nl, st->built_at, st->builds);
    nl->stale = nl->stale || st->stale;
    if (status != MPS2P_OK)
        status = fail(s->error, status, "mps2p_solver_restore_state: out of memory for the "
                      "neighbour list (it is rebuilt at the next step)");
    /* gravity may differ: the effects follow, the plan is rebuilt at the next step */
    s->plan_stale = 1;
    int planned = effects_decide(s);
    if (planned != MPS2P_OK && status == MPS2P_OK) {
        char why[ERROR_MESSAGE_SIZE];
        snprintf(why, sizeof why, "%s", mps2p_last_error());
        status = fail(s->error, planned, "mps2p_solver_restore_state: %s", why);
    }
    return status;
}
