/* Checkpoint and restart: everything the next step depends on, in one HDF5
 * file, so that a restored solver continues bitwise as the saved one would.
 * Derived values (n0, lambda, dt_max, pressure_limit, domain) are stored,
 * not recomputed: dt_max and pressure_limit come from the initial state,
 * which a checkpoint no longer has. Layout in docs/results-files.md. */
#include "hdf5_io.h"
#include "files.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CHECKPOINT_FORMAT "libmps2p checkpoint"
#define CHECKPOINT_FORMAT_VERSION 1
/* as in scene.c: the pressure matrix uses int indices */
#define MAX_PARTICLES ((size_t)INT_MAX / 2)

/* Scalars of the solver, as root attributes: name, type, address. */
typedef struct scalar_field {
    const char *name;
    int is_integer; /* uint64 when set, else double */
    size_t offset;
} scalar_field;

#define DOUBLE_FIELD(name) {#name, 0, offsetof(mps2p_solver, name)}
static const scalar_field doubles[] = {
    DOUBLE_FIELD(l0),           DOUBLE_FIELD(time),         DOUBLE_FIELD(last_dt),
    DOUBLE_FIELD(n0_density),   DOUBLE_FIELD(n0_laplacian), DOUBLE_FIELD(lambda),
    DOUBLE_FIELD(dt_max),       DOUBLE_FIELD(pressure_limit), DOUBLE_FIELD(ppe_residual),
};
#define DOUBLE_COUNT (sizeof doubles / sizeof doubles[0])

/* Counters kept as size_t or uint64_t in the solver, uint64 in the file. */
static int write_counters(h5_context *ctx, hid_t file, const mps2p_solver *s)
{
    const struct { const char *name; uint64_t value; } counters[] = {
        {"particle_count", s->count},
        {"steps", s->steps},
        {"ppe_unknowns", s->ppe_unknowns},
        {"ppe_iterations", s->ppe_iterations},
        {"surface_particles", s->surface_particles},
    };
    for (size_t i = 0; i < sizeof counters / sizeof counters[0]; i++)
        if (h5_write_attribute(ctx, file, counters[i].name, H5T_NATIVE_UINT64, 1,
                               &counters[i].value) != 0)
            return -1;
    return 0;
}

static int write_root(h5_context *ctx, hid_t file, const mps2p_solver *s)
{
    int version = CHECKPOINT_FORMAT_VERSION, fluids = s->fluid_count, diverged = s->diverged;
    int status = h5_write_attribute_string(ctx, file, "format", CHECKPOINT_FORMAT);
    if (status == 0)
        status = h5_write_attribute(ctx, file, "format_version", H5T_NATIVE_INT, 1, &version);
    if (status == 0)
        status = h5_write_attribute_string(ctx, file, "library_version", mps2p_version_string());
    for (size_t i = 0; status == 0 && i < DOUBLE_COUNT; i++)
        status = h5_write_attribute(ctx, file, doubles[i].name, H5T_NATIVE_DOUBLE, 1,
                                    (const char *)s + doubles[i].offset);
    if (status == 0)
        status = h5_write_attribute(ctx, file, "domain", H5T_NATIVE_DOUBLE, 4, s->domain);
    if (status == 0)
        status = h5_write_attribute(ctx, file, "fluid_count", H5T_NATIVE_INT, 1, &fluids);
    if (status == 0)
        status = h5_write_attribute(ctx, file, "diverged", H5T_NATIVE_INT, 1, &diverged);
    if (status == 0)
        status = write_counters(ctx, file, s);
    return status;
}

static int write_particles(h5_context *ctx, hid_t file, const mps2p_solver *s)
{
    hid_t group = H5Gcreate2(file, "particles", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    hsize_t vectors[2] = {s->count, 2}, scalars[1] = {s->count};
    int status = h5_write_dataset(ctx, group, "position", H5T_NATIVE_DOUBLE, 2, vectors,
                                  s->state.position);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "velocity", H5T_NATIVE_DOUBLE, 2, vectors,
                                  s->state.velocity);
    const struct { const char *name; const double *data; } fields[] = {
        {"pressure", s->state.pressure},   {"number_density", s->number_density},
        {"density", s->density},           {"viscosity", s->viscosity},
    };
    for (size_t i = 0; status == 0 && i < sizeof fields / sizeof fields[0]; i++)
        status = h5_write_dataset(ctx, group, fields[i].name, H5T_NATIVE_DOUBLE, 1, scalars,
                                  fields[i].data);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "kind", H5T_NATIVE_INT, 1, scalars, s->kind);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "fluid_id", H5T_NATIVE_INT, 1, scalars,
                                  s->fluid_id);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "on_surface", H5T_NATIVE_UCHAR, 1, scalars,
                                  s->on_surface);
    H5Gclose(group);
    return status;
}

static int write_neighbours(h5_context *ctx, hid_t file, const mps2p_solver *s)
{
    hid_t group = H5Gcreate2(file, "neighbours", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    uint64_t builds = s->neighbours.builds;
    hsize_t dims[2] = {s->count, 2};
    int status = h5_write_attribute(ctx, group, "builds", H5T_NATIVE_UINT64, 1, &builds);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "built_at", H5T_NATIVE_DOUBLE, 2, dims,
                                  s->neighbours.built_at);
    H5Gclose(group);
    return status;
}

int mps2p_solver_save_checkpoint(const mps2p_solver *s, const char *path)
{
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_save_checkpoint: solver is NULL");
    if (!path)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_save_checkpoint: path is NULL");
    if (!path[0])
        return fail(NULL, MPS2P_ERR_INVALID, "mps2p_solver_save_checkpoint: path is empty");
    char *temporary = path_join_suffix(path, strlen(path), ".tmp");
    if (!temporary)
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory saving checkpoint \"%s\"", path);

    h5_guard guard;
    h5_context ctx;
    h5_enter(&guard);
    h5_context_init(&ctx, "checkpoint", path);
    int status = MPS2P_OK;
    hid_t file = H5Fcreate(temporary, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (file < 0) {
        h5_note(&ctx);
        status = h5_fail(&ctx, NULL, "cannot create the temporary file \"%s\"", temporary);
    } else {
        int written = write_root(&ctx, file, s) == 0 && h5_write_parameters(&ctx, file, s) == 0 &&
                      h5_write_fluids(&ctx, file, s) == 0 &&
                      write_particles(&ctx, file, s) == 0 && write_neighbours(&ctx, file, s) == 0;
        if (!written)
            status = h5_fail(&ctx, NULL, "cannot write \"%s\"", temporary);
        if (H5Fclose(file) < 0 && status == MPS2P_OK) {
            h5_note(&ctx);
            status = h5_fail(&ctx, NULL, "cannot close \"%s\"", temporary);
        }
    }
    h5_leave(&guard);
    char reason[256] = "";
    if (status == MPS2P_OK && file_replace(temporary, path, reason, sizeof reason) != 0)
        status = fail(NULL, MPS2P_ERR_IO, "checkpoint \"%s\": cannot move \"%s\" over it: %s",
                      path, temporary, reason);
    if (status != MPS2P_OK)
        remove(temporary);
    free(temporary);
    return status;
}

/* ---- loading ---- */

static int read_header(h5_context *ctx, hid_t file)
{
    char format[64];
    int version = 0;
    htri_t has_format = H5Aexists(file, "format");
    if (has_format <= 0) {
        h5_note_text(ctx, "not a libmps2p checkpoint (no format attribute)");
        return -1;
    }
    if (h5_read_attribute_string(ctx, file, "format", format, sizeof format) != 0)
        return -1;
    if (strcmp(format, CHECKPOINT_FORMAT) != 0) {
        h5_note_text(ctx, "not a libmps2p checkpoint (format \"%s\")", format);
        return -1;
    }
    if (h5_read_attribute(ctx, file, "format_version", H5T_NATIVE_INT, 1, &version) != 0)
        return -1;
    if (version > CHECKPOINT_FORMAT_VERSION || version < 1) {
        h5_note_text(ctx, "format version %d %s (this library, %s, reads version %d)", version,
                     version > CHECKPOINT_FORMAT_VERSION ? "is newer than this library reads"
                                                        : "is not valid",
                     mps2p_version_string(), CHECKPOINT_FORMAT_VERSION);
        return -1;
    }
    return 0;
}

static int read_root(h5_context *ctx, hid_t file, mps2p_solver *s, size_t *count,
                     int *fluids)
{
    for (size_t i = 0; i < DOUBLE_COUNT; i++)
        if (h5_read_attribute(ctx, file, doubles[i].name, H5T_NATIVE_DOUBLE, 1,
                              (char *)s + doubles[i].offset) != 0)
            return -1;
    uint64_t particles = 0, steps = 0, unknowns = 0, iterations = 0, surface = 0;
    if (h5_read_attribute(ctx, file, "domain", H5T_NATIVE_DOUBLE, 4, s->domain) != 0 ||
        h5_read_attribute(ctx, file, "fluid_count", H5T_NATIVE_INT, 1, fluids) != 0 ||
        h5_read_attribute(ctx, file, "diverged", H5T_NATIVE_INT, 1, &s->diverged) != 0 ||
        h5_read_attribute(ctx, file, "particle_count", H5T_NATIVE_UINT64, 1, &particles) != 0 ||
        h5_read_attribute(ctx, file, "steps", H5T_NATIVE_UINT64, 1, &steps) != 0 ||
        h5_read_attribute(ctx, file, "ppe_unknowns", H5T_NATIVE_UINT64, 1, &unknowns) != 0 ||
        h5_read_attribute(ctx, file, "ppe_iterations", H5T_NATIVE_UINT64, 1, &iterations) != 0 ||
        h5_read_attribute(ctx, file, "surface_particles", H5T_NATIVE_UINT64, 1, &surface) != 0)
        return -1;
    int sane = isfinite(s->l0) && s->l0 > 0.0 && isfinite(s->time) && isfinite(s->last_dt) &&
               s->last_dt >= 0.0 && s->n0_density > 0.0 && s->n0_laplacian > 0.0 &&
               s->lambda > 0.0 && isfinite(s->dt_max) && s->dt_max > 0.0 &&
               s->pressure_limit > 0.0 && (s->diverged == 0 || s->diverged == 1) &&
               particles > 0 && particles <= MAX_PARTICLES && unknowns <= particles &&
               surface <= particles;
    for (int d = 0; d < 4; d++)
        sane = sane && isfinite(s->domain[d]);
    sane = sane && s->domain[2] > s->domain[0] && s->domain[3] > s->domain[1] &&
           isfinite(s->domain[2] - s->domain[0]) && isfinite(s->domain[3] - s->domain[1]);
    if (!sane) {
        h5_note_text(ctx, "inconsistent run values (l0 %g, time %g, last dt %g, dt_max %g, "
                     "%llu particles, domain [%g, %g] x [%g, %g])", s->l0, s->time, s->last_dt,
                     s->dt_max, (unsigned long long)particles, s->domain[0], s->domain[2],
                     s->domain[1], s->domain[3]);
        return -1;
    }
    *count = (size_t)particles;
    s->steps = steps;
    s->ppe_unknowns = (size_t)unknowns;
    s->ppe_iterations = (size_t)iterations;
    s->surface_particles = (size_t)surface;
    return 0;
}

static int read_particles(h5_context *ctx, hid_t file, mps2p_solver *s)
{
    hid_t group = H5Gopen2(file, "particles", H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    hsize_t vectors[2] = {s->count, 2}, scalars[1] = {s->count};
    const struct { const char *name; double *data; } fields[] = {
        {"pressure", s->state.pressure}, {"number_density", s->number_density},
        {"density", s->density},         {"viscosity", s->viscosity},
    };
    int status = h5_read_dataset(ctx, group, "position", H5T_NATIVE_DOUBLE, 2, vectors,
                                 s->state.position);
    if (status == 0)
        status = h5_read_dataset(ctx, group, "velocity", H5T_NATIVE_DOUBLE, 2, vectors,
                                 s->state.velocity);
    for (size_t i = 0; status == 0 && i < sizeof fields / sizeof fields[0]; i++)
        status = h5_read_dataset(ctx, group, fields[i].name, H5T_NATIVE_DOUBLE, 1, scalars,
                                 fields[i].data);
    if (status == 0)
        status = h5_read_dataset(ctx, group, "kind", H5T_NATIVE_INT, 1, scalars, s->kind);
    if (status == 0)
        status = h5_read_dataset(ctx, group, "fluid_id", H5T_NATIVE_INT, 1, scalars,
                                 s->fluid_id);
    if (status == 0)
        status = h5_read_dataset(ctx, group, "on_surface", H5T_NATIVE_UCHAR, 1, scalars,
                                 s->on_surface);
    H5Gclose(group);
    return status;
}

/* Values the stages index with or divide by must be in range. */
static int check_particles(h5_context *ctx, const mps2p_solver *s)
{
    for (size_t i = 0; i < s->count; i++) {
        int kind = s->kind[i], id = s->fluid_id[i];
        int fluid = kind == MPS2P_KIND_FLUID;
        int ok = (fluid || kind == MPS2P_KIND_WALL || kind == MPS2P_KIND_DUMMY) &&
                 (fluid ? id >= 0 && id < s->fluid_count : id == -1) &&
                 isfinite(s->state.position[2 * i]) && isfinite(s->state.position[2 * i + 1]) &&
                 isfinite(s->state.velocity[2 * i]) && isfinite(s->state.velocity[2 * i + 1]) &&
                 isfinite(s->state.pressure[i]) && isfinite(s->number_density[i]) &&
                 isfinite(s->density[i]) && s->density[i] > 0.0 &&
                 isfinite(s->viscosity[i]) && s->viscosity[i] >= 0.0 && s->on_surface[i] <= 1;
        if (!ok) {
            h5_note_text(ctx, "particle %zu is inconsistent (kind %d, fluid id %d, position "
                         "(%g, %g), density %g)", i, kind, id, s->state.position[2 * i],
                         s->state.position[2 * i + 1], s->density[i]);
            return -1;
        }
    }
    return 0;
}

static int read_neighbours(h5_context *ctx, hid_t file, const mps2p_solver *s,
                           double *built_at, uint64_t *builds)
{
    hid_t group = H5Gopen2(file, "neighbours", H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    hsize_t dims[2] = {s->count, 2};
    int status = h5_read_attribute(ctx, group, "builds", H5T_NATIVE_UINT64, 1, builds);
    if (status == 0 && *builds < 1) {
        h5_note_text(ctx, "the neighbour list was never built");
        status = -1;
    }
    if (status == 0)
        status = h5_read_dataset(ctx, group, "built_at", H5T_NATIVE_DOUBLE, 2, dims, built_at);
    for (size_t i = 0; status == 0 && i < 2 * s->count; i++)
        if (!isfinite(built_at[i])) {
            h5_note_text(ctx, "neighbour reference position %zu is not finite", i / 2);
            status = -1;
        }
    H5Gclose(group);
    return status;
}

/* Reads the open file into a new solver; MPS2P_ERR_IO (detail noted) or
 * MPS2P_ERR_NOMEM on failure, with *out left NULL. */
static int load(h5_context *ctx, hid_t file, mps2p_solver **out)
{
    mps2p_solver *s = calloc(1, sizeof *s);
    if (!s)
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory loading a checkpoint");
    size_t count = 0;
    int fluids = 0, status = MPS2P_ERR_IO;
    double *built_at = NULL;
    uint64_t builds = 0;
    if (read_header(ctx, file) != 0 || read_root(ctx, file, s, &count, &fluids) != 0 ||
        h5_read_parameters(ctx, file, &s->params) != 0)
        goto done;
    int file_fluids = 0;
    if (h5_read_fluid_count(ctx, file, &file_fluids) != 0)
        goto done;
    if (file_fluids != fluids) {
        h5_note_text(ctx, "fluid_count says %d fluids, the fluids group holds %d", fluids,
                     file_fluids);
        goto done;
    }
    status = solver_allocate(s, count, fluids);
    built_at = malloc(2 * count * sizeof *built_at);
    if (status != MPS2P_OK || !built_at) {
        status = fail(NULL, MPS2P_ERR_NOMEM, "out of memory loading a checkpoint of %zu "
                      "particles", count);
        goto done;
    }
    status = MPS2P_ERR_IO;
    if (h5_read_fluids(ctx, file, fluids, s->fluids) != 0 || read_particles(ctx, file, s) != 0 ||
        check_particles(ctx, s) != 0 || read_neighbours(ctx, file, s, built_at, &builds) != 0)
        goto done;
    status = solver_start(s);
    if (status == MPS2P_OK && neighbours_restore(&s->neighbours, built_at,
                                                 (unsigned long)builds) != MPS2P_OK)
        status = fail(NULL, MPS2P_ERR_NOMEM, "out of memory for the neighbour list");
    if (status == MPS2P_OK) {
        memcpy(s->saved.position, s->state.position, 2 * count * sizeof(double));
        memcpy(s->saved.velocity, s->state.velocity, 2 * count * sizeof(double));
        memcpy(s->saved.pressure, s->state.pressure, count * sizeof(double));
    }
done:
    free(built_at);
    if (status != MPS2P_OK) {
        mps2p_solver_destroy(s);
        return status;
    }
    *out = s;
    return MPS2P_OK;
}

int mps2p_solver_load_checkpoint(const char *path, mps2p_solver **solver)
{
    if (!solver)
        return fail(NULL, MPS2P_ERR_NULL,
                    "mps2p_solver_load_checkpoint: solver output pointer is NULL");
    *solver = NULL;
    if (!path)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_load_checkpoint: path is NULL");

    h5_guard guard;
    h5_context ctx;
    h5_enter(&guard);
    h5_context_init(&ctx, "checkpoint", path);
    int status;
    hid_t file = -1;
    htri_t is_hdf5 = H5Fis_hdf5(path);
    if (is_hdf5 <= 0) {
        if (is_hdf5 < 0)
            h5_note(&ctx);
        else
            h5_note_text(&ctx, "not an HDF5 file");
        status = h5_fail(&ctx, NULL, "cannot open");
    } else if ((file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT)) < 0) {
        h5_note(&ctx);
        status = h5_fail(&ctx, NULL, "cannot open");
    } else {
        status = load(&ctx, file, solver);
        if (status == MPS2P_ERR_IO)
            status = h5_fail(&ctx, NULL, "cannot load");
        H5Fclose(file);
    }
    h5_leave(&guard);
    return status;
}
