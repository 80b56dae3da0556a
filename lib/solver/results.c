/* Results: fields copied into caller buffers. */
#include "core/core.h"
#include "solver/solver.h"

#include <string.h>

#define CHECK_OUTPUT(s, out)                                                         \
    do {                                                                             \
        if (!(s))                                                                    \
            return fail(NULL, MPS2P_ERR_NULL, "%s: solver is NULL", __func__);        \
        if (!(out))                                                                  \
            return fail(NULL, MPS2P_ERR_NULL, "%s: output pointer is NULL", __func__); \
    } while (0)

static int check_length(const char *what, size_t length, size_t needed)
{
    if (length < needed)
        return fail(NULL, MPS2P_ERR_BUFFER, "%s: buffer holds %zu elements, %zu needed", what,
                    length, needed);
    return MPS2P_OK;
}

int mps2p_solver_particle_count(const mps2p_solver *s, size_t *count)
{
    error_clear();
    CHECK_OUTPUT(s, count);
    *count = s->count;
    return MPS2P_OK;
}

static int copy_doubles(const char *what, const double *from, size_t n, double *out,
                        size_t length)
{
    int status = check_length(what, length, n);
    if (status == MPS2P_OK)
        memcpy(out, from, n * sizeof *out);
    return status;
}

int mps2p_solver_get_positions(const mps2p_solver *s, double *out, size_t length)
{
    error_clear();
    CHECK_OUTPUT(s, out);
    return copy_doubles("positions", s->state.position, 2 * s->count, out, length);
}

int mps2p_solver_get_velocities(const mps2p_solver *s, double *out, size_t length)
{
    error_clear();
    CHECK_OUTPUT(s, out);
    return copy_doubles("velocities", s->state.velocity, 2 * s->count, out, length);
}

int mps2p_solver_get_pressure(const mps2p_solver *s, double *out, size_t length)
{
    error_clear();
    CHECK_OUTPUT(s, out);
    return copy_doubles("pressure", s->state.pressure, s->count, out, length);
}

int mps2p_solver_get_number_density(const mps2p_solver *s, double *out, size_t length)
{
    error_clear();
    CHECK_OUTPUT(s, out);
    return copy_doubles("number density", s->number_density, s->count, out, length);
}

int mps2p_solver_get_kinds(const mps2p_solver *s, int *out, size_t length)
{
    error_clear();
    CHECK_OUTPUT(s, out);
    int status = check_length("kinds", length, s->count);
    if (status == MPS2P_OK)
        memcpy(out, s->kind, s->count * sizeof *out);
    return status;
}

int mps2p_solver_get_fluid_ids(const mps2p_solver *s, int *out, size_t length)
{
    error_clear();
    CHECK_OUTPUT(s, out);
    int status = check_length("fluid ids", length, s->count);
    if (status == MPS2P_OK)
        memcpy(out, s->fluid_id, s->count * sizeof *out);
    return status;
}

int mps2p_solver_get_time(const mps2p_solver *s, double *time)
{
    error_clear();
    CHECK_OUTPUT(s, time);
    *time = s->time;
    return MPS2P_OK;
}

int mps2p_solver_get_step_count(const mps2p_solver *s, uint64_t *steps)
{
    error_clear();
    CHECK_OUTPUT(s, steps);
    *steps = s->steps;
    return MPS2P_OK;
}

int mps2p_solver_get_last_dt(const mps2p_solver *s, double *dt)
{
    error_clear();
    CHECK_OUTPUT(s, dt);
    *dt = s->last_dt;
    return MPS2P_OK;
}
