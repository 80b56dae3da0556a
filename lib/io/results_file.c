/* HDF5 results file: run metadata, snapshots of the particles, time series,
 * and the XDMF sidecar that lets ParaView open the snapshots. Layout in
 * docs/results-files.md. */
#include "core/core.h"
#include "io/io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define RESULTS_FORMAT "libmps2p results"
#define RESULTS_FORMAT_VERSION 1
#define SERIES_NAME_MAX 64
#define SERIES_CHUNK_ROWS 256

struct mps2p_results {
    hid_t file;
    char *path, *xdmf_path;
    size_t particle_count;
    size_t snapshots, capacity; /* snapshots written, and room in the arrays */
    double *times;
    size_t *particles;
    char error[ERROR_MESSAGE_SIZE];
};

const char *mps2p_results_last_error(const mps2p_results *r)
{
    return r ? r->error : "results handle is NULL";
}

static void free_handle(mps2p_results *r)
{
    free(r->path);
    free(r->xdmf_path);
    free(r->times);
    free(r->particles);
    free(r);
}

/* "<path without .h5>.xdmf" */
static char *sidecar_path(const char *path)
{
    size_t length = strlen(path);
    if (length > 3 && strcmp(path + length - 3, ".h5") == 0)
        length -= 3;
    return path_join_suffix(path, length, ".xdmf");
}

static int make_group(h5_context *ctx, hid_t file, const char *name)
{
    hid_t group = H5Gcreate2(file, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    H5Gclose(group);
    return 0;
}

/* /vertices (n, 1) = 0, 1, ..., n-1: the particles as the one-node cells of
 * the XDMF Polyvertex topology. ParaView's Xdmf3 readers and meshio make cells only
 * from a topology's connectivity array; without one they show no cells. */
static int write_vertices(h5_context *ctx, hid_t file, size_t count)
{
    int *index = malloc((count ? count : 1) * sizeof *index);
    if (!index) {
        h5_note_text(ctx, "out of memory for %zu vertex indices", count);
        return -1;
    }
    for (size_t i = 0; i < count; i++)
        index[i] = (int)i;
    hsize_t dims[2] = {count, 1};
    int status = h5_write_dataset(ctx, file, "vertices", H5T_NATIVE_INT, 2, dims, index);
    free(index);
    return status;
}

static int write_metadata(h5_context *ctx, hid_t file, const mps2p_solver *s,
                          const char *scene_text)
{
    int version = RESULTS_FORMAT_VERSION;
    uint64_t particles = s->count;
    int status = h5_write_attribute_string(ctx, file, "format", RESULTS_FORMAT);
    if (status == 0)
        status = h5_write_attribute(ctx, file, "format_version", H5T_NATIVE_INT, 1, &version);
    if (status == 0)
        status = h5_write_attribute_string(ctx, file, "library_version", mps2p_version_string());
    if (status == 0)
        status = h5_write_attribute(ctx, file, "l0", H5T_NATIVE_DOUBLE, 1, &s->l0);
    if (status == 0)
        status = h5_write_attribute(ctx, file, "n0", H5T_NATIVE_DOUBLE, 1, &s->n0_density);
    if (status == 0)
        status = h5_write_attribute(ctx, file, "lambda", H5T_NATIVE_DOUBLE, 1, &s->lambda);
    if (status == 0)
        status = h5_write_attribute(ctx, file, "domain", H5T_NATIVE_DOUBLE, 4, s->domain);
    if (status == 0)
        status = h5_write_attribute(ctx, file, "particle_count", H5T_NATIVE_UINT64, 1,
                                    &particles);
    if (status == 0)
        status = h5_write_parameters(ctx, file, s);
    if (status == 0)
        status = h5_write_fluids(ctx, file, s);
    if (status == 0 && scene_text)
        status = h5_write_string_dataset(ctx, file, "scene_text", scene_text);
    if (status == 0)
        status = write_vertices(ctx, file, s->count);
    if (status == 0)
        status = make_group(ctx, file, "snapshots");
    if (status == 0)
        status = make_group(ctx, file, "series");
    return status;
}

int mps2p_results_create(const char *path, const mps2p_solver *solver, const char *scene_text,
                         mps2p_results **results)
{
    error_clear();
    if (!results)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_results_create: results output pointer is NULL");
    *results = NULL;
    if (!path)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_results_create: path is NULL");
    if (!solver)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_results_create: solver is NULL");
    if (!path[0])
        return fail(NULL, MPS2P_ERR_INVALID, "mps2p_results_create: path is empty");
    mps2p_results *r = calloc(1, sizeof *r);
    if (r) {
        r->file = -1;
        r->path = path_join_suffix(path, strlen(path), "");
        r->xdmf_path = sidecar_path(path);
    }
    if (!r || !r->path || !r->xdmf_path) {
        if (r)
            free_handle(r);
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory creating results file \"%s\"", path);
    }
    r->particle_count = solver->count;

    h5_guard guard;
    h5_context ctx;
    h5_enter(&guard);
    h5_context_init(&ctx, "results file", path);
    int status = MPS2P_OK;
    r->file = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (r->file < 0) {
        h5_note(&ctx);
        status = h5_fail(&ctx, NULL, "cannot create the file");
    } else if (write_metadata(&ctx, r->file, solver, scene_text) != 0) {
        status = h5_fail(&ctx, NULL, "cannot write the run's metadata");
    } else if (H5Fflush(r->file, H5F_SCOPE_GLOBAL) < 0) {
        h5_note(&ctx);
        status = h5_fail(&ctx, NULL, "cannot flush the metadata");
    }
    /* An empty sidecar replaces any stale one from an earlier run. */
    if (status == MPS2P_OK)
        status = xdmf_write(r->xdmf_path, path_basename(r->path), 0, NULL, NULL, NULL);
    if (status != MPS2P_OK && r->file >= 0)
        H5Fclose(r->file);
    h5_leave(&guard);
    if (status != MPS2P_OK) {
        free_handle(r);
        return status;
    }
    *results = r;
    return MPS2P_OK;
}

static int write_snapshot_group(h5_context *ctx, hid_t group, const mps2p_solver *s)
{
    hsize_t vectors[2] = {s->count, 2}, scalars[1] = {s->count};
    uint64_t step = s->steps;
    int status = h5_write_attribute(ctx, group, "time", H5T_NATIVE_DOUBLE, 1, &s->time);
    if (status == 0)
        status = h5_write_attribute(ctx, group, "step", H5T_NATIVE_UINT64, 1, &step);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "position", H5T_NATIVE_DOUBLE, 2, vectors,
                                  s->state.position);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "velocity", H5T_NATIVE_DOUBLE, 2, vectors,
                                  s->state.velocity);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "pressure", H5T_NATIVE_DOUBLE, 1, scalars,
                                  s->state.pressure);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "number_density", H5T_NATIVE_DOUBLE, 1, scalars,
                                  s->number_density);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "kind", H5T_NATIVE_INT, 1, scalars, s->kind);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "fluid_id", H5T_NATIVE_INT, 1, scalars,
                                  s->fluid_id);
    return status;
}

/* Room for one more snapshot in the sidecar's lists. */
static int reserve_snapshot(mps2p_results *r)
{
    if (r->snapshots < r->capacity)
        return MPS2P_OK;
    size_t capacity = r->capacity ? 2 * r->capacity : 16;
    double *times = realloc(r->times, capacity * sizeof *times);
    if (times)
        r->times = times;
    size_t *particles = realloc(r->particles, capacity * sizeof *particles);
    if (particles)
        r->particles = particles;
    if (!times || !particles)
        return fail(r->error, MPS2P_ERR_NOMEM, "out of memory recording snapshot %zu",
                    r->snapshots);
    r->capacity = capacity;
    return MPS2P_OK;
}

int mps2p_results_write_snapshot(mps2p_results *r, const mps2p_solver *solver)
{
    error_clear();
    if (!r)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_results_write_snapshot: results is NULL");
    if (!solver)
        return fail(r->error, MPS2P_ERR_NULL, "mps2p_results_write_snapshot: solver is NULL");
    if (solver->count != r->particle_count)
        return fail(r->error, MPS2P_ERR_INVALID,
                    "results file \"%s\" holds %zu particles per snapshot, the solver has %zu",
                    r->path, r->particle_count, solver->count);
    int status = reserve_snapshot(r);
    if (status != MPS2P_OK)
        return status;
    char name[40];
    snprintf(name, sizeof name, "/snapshots/%06zu", r->snapshots);

    h5_guard guard;
    h5_context ctx;
    h5_enter(&guard);
    h5_context_init(&ctx, "results file", r->path);
    hid_t group = H5Gcreate2(r->file, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (group < 0) {
        h5_note(&ctx);
        status = h5_fail(&ctx, r->error, "cannot create group %s", name);
    } else {
        if (write_snapshot_group(&ctx, group, solver) != 0)
            status = h5_fail(&ctx, r->error, "cannot write snapshot %s", name);
        H5Gclose(group);
        if (status != MPS2P_OK) /* so that the next attempt can use the name */
            H5Ldelete(r->file, name, H5P_DEFAULT);
    }
    if (status == MPS2P_OK && H5Fflush(r->file, H5F_SCOPE_GLOBAL) < 0) {
        h5_note(&ctx);
        status = h5_fail(&ctx, r->error, "cannot flush snapshot %s", name);
    }
    h5_leave(&guard);
    if (status != MPS2P_OK)
        return status;
    r->times[r->snapshots] = solver->time;
    r->particles[r->snapshots] = solver->count;
    r->snapshots++;
    return xdmf_write(r->xdmf_path, path_basename(r->path), r->snapshots, r->times,
                      r->particles, r->error);
}

static int check_series_name(const char *name)
{
    size_t length = strlen(name);
    if (length == 0 || length > SERIES_NAME_MAX || name[0] == '.')
        return 0;
    for (size_t i = 0; i < length; i++) {
        char c = name[i];
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                 c == '_' || c == '-' || c == '.';
        if (!ok)
            return 0;
    }
    return 1;
}

/* Opens /series/<name>, creating an empty extendible n x 2 dataset first. */
static hid_t open_series(h5_context *ctx, hid_t file, const char *path)
{
    htri_t exists = H5Lexists(file, path, H5P_DEFAULT);
    if (exists < 0) {
        h5_note(ctx);
        return -1;
    }
    if (exists) {
        hid_t dataset = H5Dopen2(file, path, H5P_DEFAULT);
        if (dataset < 0)
            h5_note(ctx);
        return dataset;
    }
    hsize_t dims[2] = {0, 2}, max[2] = {H5S_UNLIMITED, 2}, chunk[2] = {SERIES_CHUNK_ROWS, 2};
    hid_t space = H5Screate_simple(2, dims, max), plist = -1, dataset = -1;
    if (space >= 0 && (plist = H5Pcreate(H5P_DATASET_CREATE)) >= 0 &&
        H5Pset_chunk(plist, 2, chunk) >= 0)
        dataset = H5Dcreate2(file, path, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, plist,
                             H5P_DEFAULT);
    if (dataset < 0)
        h5_note(ctx);
    if (plist >= 0)
        H5Pclose(plist);
    if (space >= 0)
        H5Sclose(space);
    return dataset;
}

static int append_row(h5_context *ctx, hid_t dataset, const char *path, const double row[2])
{
    hid_t space = H5Dget_space(dataset), memory = -1;
    hsize_t dims[2] = {0, 0};
    int ok = space >= 0;
    if (!ok)
        h5_note(ctx);
    if (ok && (H5Sget_simple_extent_ndims(space) != 2 ||
               H5Sget_simple_extent_dims(space, dims, NULL) < 0 || dims[1] != 2)) {
        h5_note_text(ctx, "%s is not an n x 2 dataset", path);
        ok = 0;
    }
    if (space >= 0)
        H5Sclose(space);
    space = -1;
    hsize_t grown[2] = {dims[0] + 1, 2}, start[2] = {dims[0], 0}, one[2] = {1, 2};
    ok = ok && H5Dset_extent(dataset, grown) >= 0 && (space = H5Dget_space(dataset)) >= 0 &&
         H5Sselect_hyperslab(space, H5S_SELECT_SET, start, NULL, one, NULL) >= 0 &&
         (memory = H5Screate_simple(2, one, NULL)) >= 0 &&
         H5Dwrite(dataset, H5T_NATIVE_DOUBLE, memory, space, H5P_DEFAULT, row) >= 0;
    if (!ok)
        h5_note(ctx);
    if (memory >= 0)
        H5Sclose(memory);
    if (space >= 0)
        H5Sclose(space);
    return ok ? 0 : -1;
}

int mps2p_results_append_series(mps2p_results *r, const char *name, double time, double value)
{
    error_clear();
    if (!r)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_results_append_series: results is NULL");
    if (!name)
        return fail(r->error, MPS2P_ERR_NULL, "mps2p_results_append_series: name is NULL");
    if (!check_series_name(name))
        return fail(r->error, MPS2P_ERR_INVALID,
                    "series name \"%.80s\" must have 1 to %d characters among letters, digits, "
                    "'_', '-' and '.', and not start with '.'", name, SERIES_NAME_MAX);
    if (!isfinite(time) || !isfinite(value))
        return fail(r->error, MPS2P_ERR_INVALID,
                    "series %s: time and value must be finite, got (%g, %g)", name, time, value);
    char path[SERIES_NAME_MAX + 16];
    snprintf(path, sizeof path, "/series/%s", name);
    const double row[2] = {time, value};

    h5_guard guard;
    h5_context ctx;
    h5_enter(&guard);
    h5_context_init(&ctx, "results file", r->path);
    int status = MPS2P_OK;
    hid_t dataset = open_series(&ctx, r->file, path);
    if (dataset < 0)
        status = h5_fail(&ctx, r->error, "cannot open or create series %s", path);
    else if (append_row(&ctx, dataset, path, row) != 0)
        status = h5_fail(&ctx, r->error, "cannot append to series %s", path);
    if (dataset >= 0)
        H5Dclose(dataset);
    h5_leave(&guard);
    return status;
}

int mps2p_results_close(mps2p_results *r)
{
    error_clear();
    if (!r)
        return MPS2P_OK;
    h5_guard guard;
    h5_context ctx;
    h5_enter(&guard);
    h5_context_init(&ctx, "results file", r->path);
    int status = MPS2P_OK;
    if (H5Fflush(r->file, H5F_SCOPE_GLOBAL) < 0) {
        h5_note(&ctx);
        status = h5_fail(&ctx, NULL, "cannot flush on closing");
    }
    if (H5Fclose(r->file) < 0 && status == MPS2P_OK) {
        h5_note(&ctx);
        status = h5_fail(&ctx, NULL, "cannot close");
    }
    h5_leave(&guard);
    free_handle(r);
    return status;
}
