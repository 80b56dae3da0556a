/* HDF5 inside libmps2p: the entry-point guard, error messages naming the
 * file, and typed read/write helpers.
 *
 * HDF5 prints its error stack to stderr by default, from whichever library
 * calls it. The switch is per thread in a thread-safe HDF5 build (Debian's
 * libhdf5 1.10 "serial" is built thread-safe: error stacks live in
 * thread-local storage and a global recursive lock serialises the API), and
 * process-wide otherwise. So every public call that uses HDF5 saves the
 * calling thread's handler, switches it off, and puts it back on the way out:
 * the application's own HDF5 use (h5py, say) keeps its settings. If the HDF5
 * loaded at run time is not thread-safe, a static mutex serialises all of
 * libmps2p's HDF5 calls; that mutex is synchronisation, not solver state. */
#include "core/core.h"
#include "io/io.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static pthread_once_t probe_once = PTHREAD_ONCE_INIT;
static int hdf5_is_thread_safe; /* written once, under probe_once */
static pthread_mutex_t hdf5_mutex = PTHREAD_MUTEX_INITIALIZER;

static void probe_thread_safety(void)
{
    hbool_t safe = 0;
    hdf5_is_thread_safe = H5is_library_threadsafe(&safe) >= 0 && safe;
}

void h5_enter(h5_guard *g)
{
    memset(g, 0, sizeof *g);
    pthread_once(&probe_once, probe_thread_safety);
    if (!hdf5_is_thread_safe) {
        pthread_mutex_lock(&hdf5_mutex);
        g->locked = 1;
    }
    unsigned is_v2 = 1;
    if (H5Eauto_is_v2(H5E_DEFAULT, &is_v2) < 0)
        is_v2 = 1;
    g->saved_v2 = is_v2 != 0;
#ifndef H5_NO_DEPRECATED_SYMBOLS
    if (!g->saved_v2) {
        H5Eget_auto1(&g->func1, &g->data);
        H5Eset_auto1(NULL, NULL);
        return;
    }
#endif
    H5Eget_auto2(H5E_DEFAULT, &g->func2, &g->data);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}

void h5_leave(h5_guard *g)
{
#ifndef H5_NO_DEPRECATED_SYMBOLS
    if (!g->saved_v2)
        H5Eset_auto1(g->func1, g->data);
    else
#endif
        H5Eset_auto2(H5E_DEFAULT, g->func2, g->data);
    if (g->locked)
        pthread_mutex_unlock(&hdf5_mutex);
}

void h5_context_init(h5_context *ctx, const char *role, const char *path)
{
    ctx->role = role;
    ctx->path = path;
    ctx->detail[0] = '\0';
}

/* HDF5's file driver says "unable to open file: name = '...', errno = 2,
 * error message = 'No such file or directory', flags = ..., o_flags = ...":
 * the message names the file already, so keep what failed and the system's
 * reason ("unable to open file: No such file or directory"). 0 when the text
 * is not of that form. */
static int system_reason(const char *desc, char *out, size_t size)
{
    const char *name = strstr(desc, ": name = ");
    const char *reason = strstr(desc, "error message = '");
    if (!name || !reason)
        return 0;
    reason += strlen("error message = '");
    const char *end = strchr(reason, '\'');
    if (!end)
        return 0;
    snprintf(out, size, "%.*s: %.*s", (int)(name - desc), desc, (int)(end - reason), reason);
    return 1;
}

/* The walk starts at the innermost record: the most specific reason. */
static herr_t take_innermost(unsigned n, const H5E_error2_t *error, void *data)
{
    h5_context *ctx = data;
    if (n == 0 && error->desc && error->desc[0]) {
        if (!system_reason(error->desc, ctx->detail, sizeof ctx->detail))
            snprintf(ctx->detail, sizeof ctx->detail, "%s", error->desc);
    }
    else if (n == 0 && error->func_name)
        snprintf(ctx->detail, sizeof ctx->detail, "HDF5 error in %s", error->func_name);
    return 0;
}

void h5_note(h5_context *ctx)
{
    if (ctx->detail[0])
        return;
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, take_innermost, ctx);
    if (!ctx->detail[0])
        snprintf(ctx->detail, sizeof ctx->detail, "HDF5 gave no reason");
}

void h5_note_text(h5_context *ctx, const char *format, ...)
{
    if (ctx->detail[0])
        return;
    va_list args;
    va_start(args, format);
    vsnprintf(ctx->detail, sizeof ctx->detail, format, args);
    va_end(args);
}

int h5_fail(h5_context *ctx, char *handle_error, const char *format, ...)
{
    char what[ERROR_MESSAGE_SIZE];
    va_list args;
    va_start(args, format);
    vsnprintf(what, sizeof what, format, args);
    va_end(args);
    if (ctx->detail[0])
        return fail(handle_error, MPS2P_ERR_IO, "%s \"%s\": %s: %s", ctx->role, ctx->path, what,
                    ctx->detail);
    return fail(handle_error, MPS2P_ERR_IO, "%s \"%s\": %s", ctx->role, ctx->path, what);
}

/* A fixed-length, NUL-terminated UTF-8 string type of size bytes. */
static hid_t string_type(size_t size)
{
    hid_t type = H5Tcopy(H5T_C_S1);
    if (type < 0)
        return -1;
    if (H5Tset_size(type, size > 0 ? size : 1) < 0 || H5Tset_strpad(type, H5T_STR_NULLTERM) < 0 ||
        H5Tset_cset(type, H5T_CSET_UTF8) < 0) {
        H5Tclose(type);
        return -1;
    }
    return type;
}

static hid_t make_space(size_t count)
{
    if (count == 1)
        return H5Screate(H5S_SCALAR);
    hsize_t dims[1] = {count};
    return H5Screate_simple(1, dims, NULL);
}

int h5_write_attribute(h5_context *ctx, hid_t object, const char *name, hid_t type,
                       size_t count, const void *value)
{
    hid_t space = make_space(count), attribute = -1;
    int ok = space >= 0 &&
             (attribute = H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT)) >= 0 &&
             H5Awrite(attribute, type, value) >= 0;
    if (!ok)
        h5_note(ctx);
    if (attribute >= 0)
        H5Aclose(attribute);
    if (space >= 0)
        H5Sclose(space);
    return ok ? 0 : -1;
}

int h5_write_attribute_string(h5_context *ctx, hid_t object, const char *name,
                              const char *value)
{
    hid_t type = string_type(strlen(value) + 1);
    if (type < 0) {
        h5_note(ctx);
        return -1;
    }
    int status = h5_write_attribute(ctx, object, name, type, 1, value);
    H5Tclose(type);
    return status;
}

int h5_write_dataset(h5_context *ctx, hid_t location, const char *name, hid_t type, int rank,
                     const hsize_t *dims, const void *data)
{
    hid_t space = H5Screate_simple(rank, dims, NULL), dataset = -1;
    int ok = space >= 0 &&
             (dataset = H5Dcreate2(location, name, type, space, H5P_DEFAULT, H5P_DEFAULT,
                                   H5P_DEFAULT)) >= 0;
    /* An empty dataset has nothing to write (and data may be NULL). */
    if (ok && H5Sget_simple_extent_npoints(space) > 0)
        ok = H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) >= 0;
    if (!ok)
        h5_note(ctx);
    if (dataset >= 0)
        H5Dclose(dataset);
    if (space >= 0)
        H5Sclose(space);
    return ok ? 0 : -1;
}

int h5_write_string_dataset(h5_context *ctx, hid_t location, const char *name,
                            const char *text)
{
    hid_t type = string_type(strlen(text) + 1), space = -1, dataset = -1;
    int ok = type >= 0 && (space = H5Screate(H5S_SCALAR)) >= 0 &&
             (dataset = H5Dcreate2(location, name, type, space, H5P_DEFAULT, H5P_DEFAULT,
                                   H5P_DEFAULT)) >= 0 &&
             H5Dwrite(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, text) >= 0;
    if (!ok)
        h5_note(ctx);
    if (dataset >= 0)
        H5Dclose(dataset);
    if (space >= 0)
        H5Sclose(space);
    if (type >= 0)
        H5Tclose(type);
    return ok ? 0 : -1;
}

int h5_write_string_array(h5_context *ctx, hid_t location, const char *name, size_t count,
                          const char *const *strings)
{
    size_t width = 1;
    for (size_t i = 0; i < count; i++)
        if (strlen(strings[i]) + 1 > width)
            width = strlen(strings[i]) + 1;
    char *packed = calloc(count > 0 ? count : 1, width);
    if (!packed) {
        h5_note_text(ctx, "out of memory");
        return -1;
    }
    for (size_t i = 0; i < count; i++)
        memcpy(packed + i * width, strings[i], strlen(strings[i]));
    hid_t type = string_type(width);
    hsize_t dims[1] = {count};
    int status = -1;
    if (type < 0)
        h5_note(ctx);
    else
        status = h5_write_dataset(ctx, location, name, type, 1, dims, packed);
    if (type >= 0)
        H5Tclose(type);
    free(packed);
    return status;
}

/* ---- readers ---- */

static int same_class(h5_context *ctx, const char *what, const char *name, hid_t stored,
                      hid_t memory_type)
{
    H5T_class_t have = H5Tget_class(stored), want = H5Tget_class(memory_type);
    if (have == want)
        return 0;
    h5_note_text(ctx, "%s %s holds %s values, expected %s", what, name,
                 have == H5T_INTEGER ? "integer" : have == H5T_FLOAT ? "floating-point"
                 : have == H5T_STRING ? "string" : "other",
                 want == H5T_INTEGER ? "integer" : want == H5T_FLOAT ? "floating-point"
                 : "string");
    return -1;
}

/* Compares a dataspace with the expected shape; count 1 also accepts a scalar. */
static int check_shape(h5_context *ctx, const char *what, const char *name, hid_t space,
                       int rank, const hsize_t *dims)
{
    int have_rank = H5Sget_simple_extent_ndims(space);
    hsize_t have[H5S_MAX_RANK] = {0};
    if (have_rank < 0 || have_rank > H5S_MAX_RANK) {
        h5_note(ctx);
        return -1;
    }
    H5Sget_simple_extent_dims(space, have, NULL);
    if (have_rank == 0 && rank == 1 && dims[0] == 1)
        return 0;
    int same = have_rank == rank;
    for (int d = 0; same && d < rank; d++)
        same = have[d] == dims[d];
    if (same)
        return 0;
    char got[96] = "", want[96] = "";
    for (int d = 0; d < have_rank && d < 4; d++)
        snprintf(got + strlen(got), sizeof got - strlen(got), "%s%llu", d ? " x " : "",
                 (unsigned long long)have[d]);
    for (int d = 0; d < rank; d++)
        snprintf(want + strlen(want), sizeof want - strlen(want), "%s%llu", d ? " x " : "",
                 (unsigned long long)dims[d]);
    h5_note_text(ctx, "%s %s has shape (%s), expected (%s)", what, name,
                 have_rank ? got : "scalar", want);
    return -1;
}

static int attribute_exists(h5_context *ctx, hid_t object, const char *name)
{
    htri_t exists = H5Aexists(object, name);
    if (exists < 0) {
        h5_note(ctx);
        return 0;
    }
    if (!exists)
        h5_note_text(ctx, "attribute %s is missing", name);
    return exists > 0;
}

int h5_read_attribute(h5_context *ctx, hid_t object, const char *name, hid_t memory_type,
                      size_t count, void *value)
{
    if (!attribute_exists(ctx, object, name))
        return -1;
    hid_t attribute = H5Aopen(object, name, H5P_DEFAULT), space = -1, type = -1;
    hsize_t dims[1] = {count};
    int ok = attribute >= 0 && (space = H5Aget_space(attribute)) >= 0 &&
             (type = H5Aget_type(attribute)) >= 0;
    if (!ok)
        h5_note(ctx);
    ok = ok && same_class(ctx, "attribute", name, type, memory_type) == 0 &&
         check_shape(ctx, "attribute", name, space, 1, dims) == 0;
    if (ok && H5Aread(attribute, memory_type, value) < 0) {
        h5_note(ctx);
        ok = 0;
    }
    if (type >= 0)
        H5Tclose(type);
    if (space >= 0)
        H5Sclose(space);
    if (attribute >= 0)
        H5Aclose(attribute);
    return ok ? 0 : -1;
}

int h5_read_attribute_string(h5_context *ctx, hid_t object, const char *name, char *out,
                             size_t size)
{
    if (!attribute_exists(ctx, object, name))
        return -1;
    hid_t attribute = H5Aopen(object, name, H5P_DEFAULT), type = -1, memory = -1;
    int ok = attribute >= 0 && (type = H5Aget_type(attribute)) >= 0;
    if (!ok)
        h5_note(ctx);
    if (ok && (H5Tget_class(type) != H5T_STRING || H5Tis_variable_str(type) != 0)) {
        h5_note_text(ctx, "attribute %s is not a fixed-length string", name);
        ok = 0;
    }
    size_t length = ok ? H5Tget_size(type) : 0;
    if (ok && length + 1 > size) {
        h5_note_text(ctx, "attribute %s is %zu bytes long, more than %zu", name, length,
                     size - 1);
        ok = 0;
    }
    if (ok && ((memory = string_type(length)) < 0 || H5Aread(attribute, memory, out) < 0)) {
        h5_note(ctx);
        ok = 0;
    }
    if (ok)
        out[length] = '\0';
    if (memory >= 0)
        H5Tclose(memory);
    if (type >= 0)
        H5Tclose(type);
    if (attribute >= 0)
        H5Aclose(attribute);
    return ok ? 0 : -1;
}

static hid_t open_dataset(h5_context *ctx, hid_t location, const char *name)
{
    htri_t exists = H5Lexists(location, name, H5P_DEFAULT);
    if (exists <= 0) {
        if (exists < 0)
            h5_note(ctx);
        else
            h5_note_text(ctx, "dataset %s is missing", name);
        return -1;
    }
    hid_t dataset = H5Dopen2(location, name, H5P_DEFAULT);
    if (dataset < 0)
        h5_note(ctx);
    return dataset;
}

int h5_read_dataset(h5_context *ctx, hid_t location, const char *name, hid_t memory_type,
                    int rank, const hsize_t *dims, void *data)
{
    hid_t dataset = open_dataset(ctx, location, name), space = -1, type = -1;
    if (dataset < 0)
        return -1;
    int ok = (space = H5Dget_space(dataset)) >= 0 && (type = H5Dget_type(dataset)) >= 0;
    if (!ok)
        h5_note(ctx);
    ok = ok && same_class(ctx, "dataset", name, type, memory_type) == 0 &&
         check_shape(ctx, "dataset", name, space, rank, dims) == 0;
    if (ok && H5Sget_simple_extent_npoints(space) > 0 &&
        H5Dread(dataset, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0) {
        h5_note(ctx);
        ok = 0;
    }
    if (type >= 0)
        H5Tclose(type);
    if (space >= 0)
        H5Sclose(space);
    H5Dclose(dataset);
    return ok ? 0 : -1;
}

int h5_dataset_length(h5_context *ctx, hid_t location, const char *name, hsize_t *length)
{
    hid_t dataset = open_dataset(ctx, location, name), space = -1;
    if (dataset < 0)
        return -1;
    int ok = (space = H5Dget_space(dataset)) >= 0;
    if (!ok)
        h5_note(ctx);
    if (ok && H5Sget_simple_extent_ndims(space) != 1) {
        h5_note_text(ctx, "dataset %s is not one-dimensional", name);
        ok = 0;
    }
    if (ok)
        H5Sget_simple_extent_dims(space, length, NULL);
    if (space >= 0)
        H5Sclose(space);
    H5Dclose(dataset);
    return ok ? 0 : -1;
}

int h5_read_string_array(h5_context *ctx, hid_t location, const char *name, size_t count,
                         char *out, size_t width)
{
    hid_t dataset = open_dataset(ctx, location, name), space = -1, type = -1, memory = -1;
    if (dataset < 0)
        return -1;
    hsize_t dims[1] = {count};
    int ok = (space = H5Dget_space(dataset)) >= 0 && (type = H5Dget_type(dataset)) >= 0;
    if (!ok)
        h5_note(ctx);
    ok = ok && check_shape(ctx, "dataset", name, space, 1, dims) == 0;
    if (ok && (H5Tget_class(type) != H5T_STRING || H5Tis_variable_str(type) != 0)) {
        h5_note_text(ctx, "dataset %s does not hold fixed-length strings", name);
        ok = 0;
    }
    size_t stored = ok ? H5Tget_size(type) : 0;
    if (ok && stored + 1 > width) {
        h5_note_text(ctx, "dataset %s holds strings of %zu bytes, more than %zu", name, stored,
                     width - 1);
        ok = 0;
    }
    char *packed = ok ? calloc(count > 0 ? count : 1, stored) : NULL;
    if (ok && !packed) {
        h5_note_text(ctx, "out of memory");
        ok = 0;
    }
    if (ok && count > 0 &&
        ((memory = string_type(stored)) < 0 ||
         H5Dread(dataset, memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, packed) < 0)) {
        h5_note(ctx);
        ok = 0;
    }
    for (size_t i = 0; ok && i < count; i++) {
        memcpy(out + i * width, packed + i * stored, stored);
        out[i * width + stored] = '\0';
    }
    free(packed);
    if (memory >= 0)
        H5Tclose(memory);
    if (type >= 0)
        H5Tclose(type);
    if (space >= 0)
        H5Sclose(space);
    H5Dclose(dataset);
    return ok ? 0 : -1;
}
