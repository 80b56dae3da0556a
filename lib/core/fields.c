/* The state tables: what a struct holds per particle and what it carries
 * from one step into the next, one row a member. The rows drive allocation,
 * freeing, memory accounting, saved states, rollback and checkpoints; this
 * file holds the code that reads them, and the solver's own table. */
#include "core/core.h"

#include <stdlib.h>
#include <string.h>

#define FIELD(name, member, type, width, flags)                                        \
    {name, offsetof(mps2p_solver, member), type, width, flags}
#define PARTICLES FIELD_PER_PARTICLE

/* The solver's. Root attributes and datasets of group "particles" of a
 * checkpoint, in this order (docs/results-files.md). */
static const field solver_rows[] = {
    FIELD("l0", l0, FIELD_DOUBLE, 1, FIELD_CHECKPOINTED),
    FIELD("time", time, FIELD_DOUBLE, 1, FIELD_SAVED | FIELD_CHECKPOINTED),
    FIELD("last_dt", last_dt, FIELD_DOUBLE, 1, FIELD_SAVED | FIELD_CHECKPOINTED),
    /* derived at creation from the initial state, which a checkpoint no
     * longer has: stored, not recomputed */
    FIELD("n0_density", n0_density, FIELD_DOUBLE, 1, FIELD_CHECKPOINTED),
    FIELD("n0_laplacian", n0_laplacian, FIELD_DOUBLE, 1, FIELD_CHECKPOINTED),
    FIELD("lambda", lambda, FIELD_DOUBLE, 1, FIELD_CHECKPOINTED),
    FIELD("dt_max", dt_max, FIELD_DOUBLE, 1, FIELD_CHECKPOINTED),
    FIELD("pressure_limit", pressure_limit, FIELD_DOUBLE, 1, FIELD_CHECKPOINTED),
    FIELD("ppe_residual", ppe_residual, FIELD_DOUBLE, 1, FIELD_SAVED | FIELD_CHECKPOINTED),
    FIELD("domain", domain, FIELD_DOUBLE, 4, FIELD_CHECKPOINTED),
    FIELD("fluid_count", fluid_count, FIELD_INT, 1, FIELD_MATCHED | FIELD_CHECKPOINTED),
    FIELD("diverged", diverged, FIELD_INT, 1, FIELD_SAVED | FIELD_CHECKPOINTED),
    FIELD("particle_count", count, FIELD_SIZE, 1, FIELD_MATCHED | FIELD_CHECKPOINTED),
    FIELD("steps", steps, FIELD_U64, 1, FIELD_SAVED | FIELD_CHECKPOINTED),
    FIELD("ppe_unknowns", ppe_unknowns, FIELD_SIZE, 1, FIELD_SAVED | FIELD_CHECKPOINTED),
    FIELD("ppe_iterations", ppe_iterations, FIELD_SIZE, 1, FIELD_SAVED | FIELD_CHECKPOINTED),
    FIELD("surface_particles", surface_particles, FIELD_SIZE, 1,
          FIELD_SAVED | FIELD_CHECKPOINTED),
    FIELD("ppe_iterations_total", ppe_iterations_total, FIELD_U64, 1,
          FIELD_SAVED | FIELD_CHECKPOINTED | FIELD_OPTIONAL),
    /* absent (0) in files from before kind MPS2P_KIND_OUT, which have none */
    FIELD("fluid_out", fluid_out, FIELD_SIZE, 1,
          FIELD_SAVED | FIELD_CHECKPOINTED | FIELD_OPTIONAL),
    /* gravity changes between windows; a checkpoint has group "parameters" */
    FIELD("params", params, FIELD_PARAMS, 1, FIELD_SAVED),

    FIELD("position", state.position, FIELD_DOUBLE, 2,
          PARTICLES | FIELD_SAVED | FIELD_CHECKPOINTED | FIELD_ROLLED_BACK),
    FIELD("velocity", state.velocity, FIELD_DOUBLE, 2,
          PARTICLES | FIELD_SAVED | FIELD_CHECKPOINTED | FIELD_ROLLED_BACK),
    FIELD("pressure", state.pressure, FIELD_DOUBLE, 1,
          PARTICLES | FIELD_SAVED | FIELD_CHECKPOINTED | FIELD_ROLLED_BACK),
    FIELD("number_density", number_density, FIELD_DOUBLE, 1,
          PARTICLES | FIELD_SAVED | FIELD_CHECKPOINTED),
    FIELD("density", density, FIELD_DOUBLE, 1, PARTICLES | FIELD_CHECKPOINTED),
    FIELD("viscosity", viscosity, FIELD_DOUBLE, 1, PARTICLES | FIELD_CHECKPOINTED),
    /* fluid particles turn MPS2P_KIND_OUT in a run: saved, and matched by
     * solver/state.c with FLUID and OUT alike; a step marks them only once it
     * has passed every check, so never rolled back */
    FIELD("kind", kind, FIELD_INT, 1, PARTICLES | FIELD_SAVED | FIELD_CHECKPOINTED),
    FIELD("fluid_id", fluid_id, FIELD_INT, 1, PARTICLES | FIELD_CHECKPOINTED),
    FIELD("on_surface", on_surface, FIELD_FLAG, 1,
          PARTICLES | FIELD_SAVED | FIELD_CHECKPOINTED),
    /* written by a step before it reads them */
    FIELD("scratch", scratch, FIELD_DOUBLE, 2, PARTICLES),
    FIELD("rhs", rhs, FIELD_DOUBLE, 1, PARTICLES),
    FIELD("solution", solution, FIELD_DOUBLE, 1, PARTICLES),
    FIELD("unknown_of", unknown_of, FIELD_INT, 1, PARTICLES),
    /* only for the stages that need them (solver/plan.c) */
    FIELD("number_density_start", number_density_start, FIELD_DOUBLE, 1,
          PARTICLES | FIELD_ON_DEMAND),
    FIELD("eddy_viscosity", eddy_viscosity, FIELD_DOUBLE, 1, PARTICLES | FIELD_ON_DEMAND),
    FIELD("neighbour_count", neighbour_count, FIELD_UNSIGNED, 1, PARTICLES | FIELD_ON_DEMAND),
};

const field_table solver_fields = {solver_rows, sizeof solver_rows / sizeof solver_rows[0]};

size_t field_element_size(const field *f)
{
    switch (f->type) {
    case FIELD_DOUBLE: return sizeof(double);
    case FIELD_INT: return sizeof(int);
    case FIELD_LONG: return sizeof(long);
    case FIELD_UNSIGNED: return sizeof(unsigned);
    case FIELD_FLAG: return sizeof(unsigned char);
    case FIELD_SIZE: return sizeof(size_t);
    case FIELD_U64: return sizeof(uint64_t);
    default: return sizeof(params);
    }
}

size_t field_bytes(const field *f, size_t count)
{
    return field_element_size(f) * f->width * (f->flags & FIELD_PER_PARTICLE ? count : 1);
}

/* An array's pointer, through memcpy: the members are double *, int *...,
 * not void *. */
static void set_array(void *object, const field *f, void *data)
{
    memcpy((char *)object + f->offset, &data, sizeof data);
}

void *field_data(const void *object, const field *f)
{
    const char *at = (const char *)object + f->offset;
    if (!(f->flags & FIELD_PER_PARTICLE))
        return (void *)at;
    void *data;
    memcpy(&data, at, sizeof data);
    return data;
}

static int wanted(const field *f, unsigned with, unsigned without)
{
    return (!with || (f->flags & with)) && !(f->flags & without);
}

int field_allocate(const field *f, void *object, size_t count)
{
    if (!(f->flags & FIELD_PER_PARTICLE) || field_data(object, f))
        return MPS2P_OK;
    void *data = calloc(count ? count : 1, field_bytes(f, 1));
    if (!data)
        return MPS2P_ERR_NOMEM;
    set_array(object, f, data);
    return MPS2P_OK;
}

int fields_allocate(const field_table *t, void *object, size_t count, unsigned with,
                    unsigned without)
{
    for (size_t k = 0; k < t->count; k++)
        if (wanted(&t->rows[k], with, without) &&
            field_allocate(&t->rows[k], object, count) != MPS2P_OK)
            return MPS2P_ERR_NOMEM;
    return MPS2P_OK;
}

void fields_free(const field_table *t, void *object)
{
    for (size_t k = 0; k < t->count; k++)
        if (t->rows[k].flags & FIELD_PER_PARTICLE) {
            free(field_data(object, &t->rows[k]));
            set_array(object, &t->rows[k], NULL);
        }
}

size_t fields_memory(const field_table *t, const void *object, size_t count)
{
    size_t bytes = 0;
    for (size_t k = 0; k < t->count; k++) {
        const field *f = &t->rows[k];
        if ((f->flags & FIELD_PER_PARTICLE) && field_data(object, f))
            bytes += field_bytes(f, count);
    }
    return bytes;
}

void fields_copy(const field_table *t, void *to, const void *from, size_t count, unsigned with)
{
    for (size_t k = 0; k < t->count; k++) {
        const field *f = &t->rows[k];
        if (f->flags & with)
            memcpy(field_data(to, f), field_data(from, f), field_bytes(f, count));
    }
}

int fields_equal(const field_table *t, const void *a, const void *b, size_t count,
                 unsigned with)
{
    /* the scalars first: a particle count that differs ends the comparison
     * before the arrays are read */
    for (int arrays = 0; arrays < 2; arrays++)
        for (size_t k = 0; k < t->count; k++) {
            const field *f = &t->rows[k];
            if ((f->flags & with) && !(f->flags & FIELD_PER_PARTICLE) == !arrays &&
                memcmp(field_data(a, f), field_data(b, f), field_bytes(f, count)) != 0)
                return 0;
        }
    return 1;
}

const field *field_at(const field_table *t, size_t offset)
{
    for (size_t k = 0; k < t->count; k++)
        if (t->rows[k].offset == offset)
            return &t->rows[k];
    return NULL;
}
