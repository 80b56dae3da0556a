/* The run's parameters, options and fluids as HDF5 groups, shared by the
 * results file (metadata) and the checkpoint (which reads them back). */
#include "core/core.h"
#include "io/io.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int h5_write_parameters(h5_context *ctx, hid_t file, const mps2p_solver *s)
{
    hid_t group = H5Gcreate2(file, "parameters", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    int status = 0;
    const char *key;
    for (size_t i = 0; status == 0 && (key = params_key(i)) != NULL; i++) {
        double value = 0.0;
        params_get(&s->params, key, &value);
        status = h5_write_attribute(ctx, group, key, H5T_NATIVE_DOUBLE, 1, &value);
    }
    for (size_t i = 0; status == 0 && (key = params_option_key(i)) != NULL; i++) {
        const char *value = "";
        params_get_option(&s->params, key, &value);
        status = h5_write_attribute_string(ctx, group, key, value);
    }
    H5Gclose(group);
    return status;
}

int h5_write_fluids(h5_context *ctx, hid_t file, const mps2p_solver *s)
{
    size_t count = (size_t)s->fluid_count;
    const char **names = malloc((count ? count : 1) * sizeof *names);
    double *values = malloc(2 * (count ? count : 1) * sizeof *values);
    hid_t group = -1;
    int status = -1;
    if (!names || !values) {
        h5_note_text(ctx, "out of memory");
        goto done;
    }
    for (size_t f = 0; f < count; f++) {
        names[f] = s->fluids[f].name;
        values[f] = s->fluids[f].density;
        values[count + f] = s->fluids[f].viscosity;
    }
    group = H5Gcreate2(file, "fluids", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        goto done;
    }
    hsize_t dims[1] = {count};
    status = h5_write_string_array(ctx, group, "name", count, names);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "density", H5T_NATIVE_DOUBLE, 1, dims, values);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "kinematic_viscosity", H5T_NATIVE_DOUBLE, 1, dims,
                                  values + count);
done:
    if (group >= 0)
        H5Gclose(group);
    free(names);
    free(values);
    return status;
}

int h5_read_parameters(h5_context *ctx, hid_t file, params *out)
{
    hid_t group = H5Gopen2(file, "parameters", H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    params_set_defaults(out);
    char message[ERROR_MESSAGE_SIZE];
    int status = 0;
    const char *key;
    for (size_t i = 0; status == 0 && (key = params_key(i)) != NULL; i++) {
        double value = 0.0;
        /* threads changes no result bit, memory_limit only what is refused,
         * gas_buffer_rate nothing without the layer (off in older files, below);
         * files from before them lack them (their defaults) */
        if ((strcmp(key, "threads") == 0 || strcmp(key, "memory_limit") == 0 ||
             strcmp(key, "gas_buffer_rate") == 0) &&
            H5Aexists(group, key) == 0)
            continue;
        /* files from before the corrected scheme: no gravity limit on dt, the
         * collision impulse in full every step; from before the two-phase
         * ladder: the paper's trigger, no whole bubbles joining; from before
         * particle shifting: none; from before
         * the gas's damping layer: an open top; from before out_limit: any
         * fluid particle leaving the domain diverges; from before
         * collision_core: no core */
        double *before = strcmp(key, "gravity_number") == 0   ? &out->gravity_number
                         : strcmp(key, "collision_time") == 0 ? &out->collision_time
                         : strcmp(key, "trigger_speed") == 0  ? &out->trigger_speed
                         : strcmp(key, "join_bubbles") == 0   ? &out->join_bubbles
                         : strcmp(key, "gas_buffer_depth") == 0 ? &out->gas_buffer_depth
                         : strcmp(key, "out_limit") == 0      ? &out->out_limit
                         : strcmp(key, "shifting") == 0       ? &out->shifting
                         : strcmp(key, "collision_core") == 0 ? &out->collision_core
                                                              : NULL;
        if (before && H5Aexists(group, key) == 0) {
            *before = 0.0;
            continue;
        }
        /* files from before ppe_step_gain answered the step's compression in
         * full (1, whatever the default becomes) */
        if (strcmp(key, "ppe_step_gain") == 0 && H5Aexists(group, key) == 0) {
            out->ppe_step_gain = 1.0;
            continue;
        }
        status = h5_read_attribute(ctx, group, key, H5T_NATIVE_DOUBLE, 1, &value);
        if (status == 0 && params_set(out, key, value, message, sizeof message) != MPS2P_OK) {
            h5_note_text(ctx, "%s", message);
            status = -1;
        }
    }
    for (size_t i = 0; status == 0 && (key = params_option_key(i)) != NULL; i++) {
        char value[64];
        /* the scheme is a name for the other settings, read on their own */
        if (strcmp(key, "scheme") == 0)
            continue;
        /* files from before ppe_pattern or effect.gas_buffer: its default, their
         * only choice then (the layer is off there through gas_buffer_depth 0) */
        if ((strcmp(key, "ppe_pattern") == 0 || strcmp(key, "effect.gas_buffer") == 0) &&
            H5Aexists(group, key) == 0)
            continue;
        /* files from before cg_preconditioner: Jacobi, the only one then (no
         * longer the default) */
        if (strcmp(key, "cg_preconditioner") == 0 && H5Aexists(group, key) == 0) {
            out->cg_preconditioner = CG_PRECONDITIONER_JACOBI;
            continue;
        }
        /* files from before surface_pressure held p = 0 at the centre */
        if (strcmp(key, "surface_pressure") == 0 && H5Aexists(group, key) == 0) {
            out->surface_pressure = SURFACE_PRESSURE_CENTRE;
            continue;
        }
        /* files from before wall_ghosts had none */
        if (strcmp(key, "wall_ghosts") == 0 && H5Aexists(group, key) == 0) {
            out->wall_ghosts = WALL_GHOSTS_NONE;
            continue;
        }
        status = h5_read_attribute_string(ctx, group, key, value, sizeof value);
        if (status == 0 &&
            params_set_option(out, key, value, message, sizeof message) != MPS2P_OK) {
            h5_note_text(ctx, "%s", message);
            status = -1;
        }
    }
    H5Gclose(group);
    return status;
}

int h5_read_fluid_count(h5_context *ctx, hid_t file, int *count)
{
    hid_t group = H5Gopen2(file, "fluids", H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    hsize_t length = 0;
    int status = h5_dataset_length(ctx, group, "density", &length);
    if (status == 0 && (length < 1 || length > 1000000)) {
        h5_note_text(ctx, "the file lists %llu fluids", (unsigned long long)length);
        status = -1;
    }
    if (status == 0)
        *count = (int)length;
    H5Gclose(group);
    return status;
}

int h5_read_fluids(h5_context *ctx, hid_t file, int count, fluid *out)
{
    hid_t group = H5Gopen2(file, "fluids", H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    size_t n = (size_t)count;
    hsize_t dims[1] = {n};
    const size_t width = FLUID_NAME_SIZE + 1; /* a stored name may fill its 64 bytes */
    char *names = malloc(n * width);
    double *values = malloc(2 * n * sizeof *values);
    int status = -1;
    if (!names || !values)
        h5_note_text(ctx, "out of memory");
    else if (h5_read_string_array(ctx, group, "name", n, names, width) == 0 &&
             h5_read_dataset(ctx, group, "density", H5T_NATIVE_DOUBLE, 1, dims, values) == 0 &&
             h5_read_dataset(ctx, group, "kinematic_viscosity", H5T_NATIVE_DOUBLE, 1, dims,
                             values + n) == 0)
        status = 0;
    for (size_t f = 0; status == 0 && f < n; f++) {
        const char *name = names + f * width;
        if (strlen(name) >= FLUID_NAME_SIZE) {
            h5_note_text(ctx, "fluid %zu has a name of %zu characters", f, strlen(name));
            status = -1;
            break;
        }
        memset(&out[f], 0, sizeof out[f]);
        strcpy(out[f].name, name);
        out[f].density = values[f];
        out[f].viscosity = values[n + f];
        if (!out[f].name[0] || !isfinite(out[f].density) || out[f].density <= 0.0 ||
            !isfinite(out[f].viscosity) || out[f].viscosity < 0.0) {
            h5_note_text(ctx, "fluid %zu (\"%s\") has density %g and viscosity %g", f,
                         out[f].name, out[f].density, out[f].viscosity);
            status = -1;
        }
    }
    free(names);
    free(values);
    H5Gclose(group);
    return status;
}
