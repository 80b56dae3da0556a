/* Checkpoint and restart: everything the next step depends on, in one HDF5
 * file, so that a restored solver continues bitwise as the saved one would.
 * Derived values (n0, lambda, dt_max, pressure_limit, domain) are stored,
 * not recomputed: dt_max and pressure_limit come from the initial state,
 * which a checkpoint no longer has. Layout in docs/results-files.md. */
#define _POSIX_C_SOURCE 200809L
#include "numerics/numerics.h"
#include "core/core.h"
#include "two_phase/two_phase.h"
#include "coupling/coupling.h"
#include "solver/solver.h"
#include "io/io.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CHECKPOINT_FORMAT "libmps2p checkpoint"
/* 2 added the wall bodies and the host's inputs (group "bodies", body_id and
 * acceleration in "particles"); version 1 files load with every solid in
 * body 0 and no inputs, as they were written. 3 added group "two_phase",
 * written by a two-phase solver only; versions 1 and 2 were never written by
 * one (refused then), so a file of theirs that makes one is refused. */
#define CHECKPOINT_FORMAT_VERSION 4
/* 4: the same contents after a checksum header, the HDF5 user block
 * (checkpoint_seal.c), checked before HDF5 reads a byte. Files without it
 * (format 3 and older) are read unchecked, as before; a file without it
 * claiming format 4 or later is refused. */
#define LAST_UNSEALED_VERSION 3

static hid_t h5_type(const field *f)
{
    switch (f->type) {
    case FIELD_DOUBLE: return H5T_NATIVE_DOUBLE;
    case FIELD_INT: return H5T_NATIVE_INT;
    case FIELD_FLAG: return H5T_NATIVE_UCHAR;
    default: return H5T_NATIVE_UINT64; /* FIELD_SIZE, FIELD_U64 */
    }
}

/* The checkpointed rows of a state table: the per-particle ones as datasets
 * of location (arrays set), or the others as its attributes, in table order.
 * size_t values are stored as uint64. */
static int write_fields(h5_context *ctx, hid_t location, const field_table *t,
                        const void *object, size_t count, int arrays)
{
    for (size_t k = 0; k < t->count; k++) {
        const field *f = &t->rows[k];
        if (!(f->flags & FIELD_CHECKPOINTED) || !(f->flags & FIELD_PER_PARTICLE) != !arrays)
            continue;
        const void *data = field_data(object, f);
        uint64_t wide[4];
        if (f->type == FIELD_SIZE) {
            for (size_t i = 0; i < f->width; i++)
                wide[i] = ((const size_t *)data)[i];
            data = wide;
        }
        hsize_t dims[2] = {count, f->width};
        int status = arrays ? h5_write_dataset(ctx, location, f->name, h5_type(f),
                                               f->width > 1 ? 2 : 1, dims, data)
                            : h5_write_attribute(ctx, location, f->name, h5_type(f), f->width,
                                                 data);
        if (status != 0)
            return -1;
    }
    return 0;
}

/* The reverse of write_fields; a FIELD_OPTIONAL attribute that is absent
 * (a file written before it was added) stays 0. */
static int read_fields(h5_context *ctx, hid_t location, const field_table *t, void *object,
                       size_t count, int arrays)
{
    for (size_t k = 0; k < t->count; k++) {
        const field *f = &t->rows[k];
        if (!(f->flags & FIELD_CHECKPOINTED) || !(f->flags & FIELD_PER_PARTICLE) != !arrays)
            continue;
        if (f->flags & FIELD_OPTIONAL) {
            htri_t present = H5Aexists(location, f->name);
            if (present < 0) {
                h5_note(ctx);
                return -1;
            }
            if (!present)
                continue;
        }
        void *data = field_data(object, f);
        uint64_t wide[4] = {0, 0, 0, 0};
        hsize_t dims[2] = {count, f->width};
        int status = arrays ? h5_read_dataset(ctx, location, f->name, h5_type(f),
                                              f->width > 1 ? 2 : 1, dims, data)
                            : h5_read_attribute(ctx, location, f->name, h5_type(f), f->width,
                                                f->type == FIELD_SIZE ? wide : data);
        if (status != 0)
            return -1;
        for (size_t i = 0; !arrays && f->type == FIELD_SIZE && i < f->width; i++)
            ((size_t *)data)[i] = (size_t)wide[i];
    }
    return 0;
}

static int write_root(h5_context *ctx, hid_t file, const mps2p_solver *s)
{
    int version = CHECKPOINT_FORMAT_VERSION;
    int status = h5_write_attribute_string(ctx, file, "format", CHECKPOINT_FORMAT);
    if (status == 0)
        status = h5_write_attribute(ctx, file, "format_version", H5T_NATIVE_INT, 1, &version);
    if (status == 0)
        status = h5_write_attribute_string(ctx, file, "library_version", mps2p_version_string());
    if (status == 0)
        status = write_fields(ctx, file, &solver_fields, s, s->count, 0);
    return status;
}

static int write_particles(h5_context *ctx, hid_t file, const mps2p_solver *s)
{
    hid_t group = H5Gcreate2(file, "particles", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    int status = write_fields(ctx, group, &solver_fields, s, s->count, 1);
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

/* The bodies and the host's inputs: names and motions per body, body ids
 * and targets (when set) per particle, in group "bodies"; the fluid's
 * accelerations (when set) as the root dataset "acceleration". */
static int write_bodies(h5_context *ctx, hid_t file, const mps2p_solver *s)
{
    const struct coupling *c = s->coupling;
    const size_t bodies = (size_t)c->body_count, n = s->count;
    const char **names = malloc(bodies * sizeof *names);
    double *motion = malloc(5 * bodies * sizeof *motion);
    int *has_target = malloc(bodies * sizeof *has_target);
    double *target = NULL;
    int status = -1, targets = 0;
    hid_t group = -1;
    if (!names || !motion || !has_target) {
        h5_note_text(ctx, "out of memory");
        goto done;
    }
    for (size_t b = 0; b < bodies; b++) {
        const body *bd = &c->bodies[b];
        names[b] = bd->name;
        motion[2 * b] = bd->velocity[0];
        motion[2 * b + 1] = bd->velocity[1];
        motion[2 * bodies + b] = bd->angular_velocity;
        motion[3 * bodies + 2 * b] = bd->about[0];
        motion[3 * bodies + 2 * b + 1] = bd->about[1];
        has_target[b] = bd->target != NULL;
        targets |= has_target[b];
    }
    if (targets && !(target = calloc(2 * n, sizeof *target))) {
        h5_note_text(ctx, "out of memory");
        goto done;
    }
    for (size_t b = 0; targets && b < bodies; b++)
        for (size_t m = 0; has_target[b] && m < c->bodies[b].particles; m++) {
            size_t i = c->bodies[b].member[m];
            target[2 * i] = c->bodies[b].target[2 * m];
            target[2 * i + 1] = c->bodies[b].target[2 * m + 1];
        }
    group = H5Gcreate2(file, "bodies", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        goto done;
    }
    hsize_t per_body[2] = {bodies, 2}, per_particle[2] = {n, 2};
    status = h5_write_string_array(ctx, group, "name", bodies, names);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "velocity", H5T_NATIVE_DOUBLE, 2, per_body,
                                  motion);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "angular_velocity", H5T_NATIVE_DOUBLE, 1,
                                  per_body, motion + 2 * bodies);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "about", H5T_NATIVE_DOUBLE, 2, per_body,
                                  motion + 3 * bodies);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "has_target", H5T_NATIVE_INT, 1, per_body,
                                  has_target);
    if (status == 0 && targets)
        status = h5_write_dataset(ctx, group, "target", H5T_NATIVE_DOUBLE, 2, per_particle,
                                  target);
    if (status == 0)
        status = h5_write_dataset(ctx, group, "body_id", H5T_NATIVE_INT, 1, per_particle,
                                  c->body_of);
    if (status == 0 && c->acceleration)
        status = h5_write_dataset(ctx, file, "acceleration", H5T_NATIVE_DOUBLE, 2,
                                  per_particle, c->acceleration);
done:
    if (group >= 0)
        H5Gclose(group);
    free(names);
    free(motion);
    free(has_target);
    free(target);
    return status;
}

/* Group "two_phase": what of the two-phase state carries into the next step
 * (two_phase/state.c), one dataset per array, the scalars as attributes. */
static int write_two_phase(h5_context *ctx, hid_t file, const mps2p_solver *s)
{
    hid_t group = H5Gcreate2(file, "two_phase", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    int status = write_fields(ctx, group, &two_phase_fields, s->phases, s->count, 1);
    if (status == 0)
        status = write_fields(ctx, group, &two_phase_fields, s->phases, s->count, 0);
    H5Gclose(group);
    return status;
}

int mps2p_solver_save_checkpoint(const mps2p_solver *s, const char *path)
{
    error_clear();
    if (!s)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_save_checkpoint: solver is NULL");
    if (!path)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_save_checkpoint: path is NULL");
    if (!path[0])
        return fail(NULL, MPS2P_ERR_INVALID, "mps2p_solver_save_checkpoint: path is empty");
    char reason[256] = "", *target;
    int refused = file_replace_target(path, &target, reason, sizeof reason);
    if (refused != MPS2P_OK)
        return fail(NULL, refused, "checkpoint \"%s\": %s", path, reason);
    char *temporary = path_join_suffix(target, strlen(target), ".tmp");
    if (!temporary) {
        free(target);
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory saving checkpoint \"%s\"", path);
    }

    h5_guard guard;
    h5_context ctx;
    h5_enter(&guard);
    h5_context_init(&ctx, "checkpoint", path);
    int status = MPS2P_OK;
    hid_t create = H5Pcreate(H5P_FILE_CREATE), file = -1;
    if (create >= 0 && H5Pset_userblock(create, CHECKPOINT_HEADER_SIZE) >= 0)
        file = H5Fcreate(temporary, H5F_ACC_TRUNC, create, H5P_DEFAULT);
    /* HDF5's reason first: every call (H5Pclose too) clears its error stack */
    if (file < 0)
        h5_note(&ctx);
    if (create >= 0)
        H5Pclose(create);
    if (file < 0) {
        status = h5_fail(&ctx, NULL, "cannot create the temporary file \"%s\"", temporary);
    } else {
        int written = write_root(&ctx, file, s) == 0 && h5_write_parameters(&ctx, file, s) == 0 &&
                      h5_write_fluids(&ctx, file, s) == 0 &&
                      write_particles(&ctx, file, s) == 0 && write_neighbours(&ctx, file, s) == 0 &&
                      write_bodies(&ctx, file, s) == 0 &&
                      (!s->phases || write_two_phase(&ctx, file, s) == 0);
        if (!written)
            status = h5_fail(&ctx, NULL, "cannot write \"%s\"", temporary);
        if (H5Fclose(file) < 0 && status == MPS2P_OK) {
            h5_note(&ctx);
            status = h5_fail(&ctx, NULL, "cannot close \"%s\"", temporary);
        }
    }
    h5_leave(&guard);
    if (status == MPS2P_OK && checkpoint_seal(temporary, reason, sizeof reason) != 0)
        status = fail(NULL, MPS2P_ERR_IO, "checkpoint \"%s\": cannot write the checksum into "
                      "\"%s\": %s", path, temporary, reason);
    if (status == MPS2P_OK && file_replace(temporary, target, reason, sizeof reason) != 0)
        status = fail(NULL, MPS2P_ERR_IO, "checkpoint \"%s\": cannot move \"%s\" over it: %s",
                      path, temporary, reason);
    if (status != MPS2P_OK)
        remove(temporary);
    free(temporary);
    free(target);
    return status;
}

/* ---- loading ---- */

static int read_header(h5_context *ctx, hid_t file, int sealed, int *file_version)
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
    if (!sealed && version > LAST_UNSEALED_VERSION) {
        h5_note_text(ctx, "damaged: format version %d has a checksum header, this file has "
                     "none", version);
        return -1;
    }
    *file_version = version;
    return 0;
}

static int read_root(h5_context *ctx, hid_t file, mps2p_solver *s)
{
    if (read_fields(ctx, file, &solver_fields, s, 0, 0) != 0)
        return -1;
    const uint64_t particles = s->count, unknowns = s->ppe_unknowns,
                   surface = s->surface_particles;
    /* each value in the range mps2p_solver_create would give it; the first
     * one out of range is named */
    const struct { const char *name; int ok; double value; } checks[] = {
        {"l0", isfinite(s->l0) && s->l0 > 0.0, s->l0},
        {"time", isfinite(s->time) && s->time >= 0.0, s->time},
        {"last_dt", isfinite(s->last_dt) && s->last_dt >= 0.0, s->last_dt},
        {"n0_density", isfinite(s->n0_density) && s->n0_density > 0.0, s->n0_density},
        {"n0_laplacian", isfinite(s->n0_laplacian) && s->n0_laplacian > 0.0, s->n0_laplacian},
        {"lambda", isfinite(s->lambda) && s->lambda > 0.0, s->lambda},
        {"dt_max", isfinite(s->dt_max) && s->dt_max > 0.0, s->dt_max},
        {"pressure_limit", isfinite(s->pressure_limit) && s->pressure_limit > 0.0,
         s->pressure_limit},
        {"ppe_residual", isfinite(s->ppe_residual) && s->ppe_residual >= 0.0, s->ppe_residual},
        {"diverged", s->diverged == 0 || s->diverged == 1, s->diverged},
        {"particle_count", particles > 0 && particles <= MAX_PARTICLES, (double)particles},
        {"ppe_unknowns", unknowns <= particles, (double)unknowns},
        {"surface_particles", surface <= particles, (double)surface},
    };
    for (size_t k = 0; k < sizeof checks / sizeof checks[0]; k++)
        if (!checks[k].ok) {
            h5_note_text(ctx, "attribute %s is %g, out of range", checks[k].name,
                         checks[k].value);
            return -1;
        }
    int sane = 1;
    for (int d = 0; d < 4; d++)
        sane = sane && isfinite(s->domain[d]);
    sane = sane && s->domain[2] > s->domain[0] && s->domain[3] > s->domain[1] &&
           isfinite(s->domain[2] - s->domain[0]) && isfinite(s->domain[3] - s->domain[1]);
    if (!sane) {
        h5_note_text(ctx, "attribute domain [%g, %g] x [%g, %g] is not a box of finite width "
                     "and height", s->domain[0], s->domain[2], s->domain[1], s->domain[3]);
        return -1;
    }
    return 0;
}

static int read_particles(h5_context *ctx, hid_t file, mps2p_solver *s)
{
    hid_t group = H5Gopen2(file, "particles", H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    int status = read_fields(ctx, group, &solver_fields, s, s->count, 1);
    H5Gclose(group);
    return status;
}

/* n0 and lambda follow from l0 and the radii (as mps2p_solver_create
 * computes them); a stored l0 they do not fit (1e300, say) is refused.
 * Relative 1e-9: another build may round the sums differently. */
static int check_lattice(h5_context *ctx, const mps2p_solver *s)
{
    double n0_density, n0_laplacian, lambda, unused;
    lattice_constants(s->l0, s->params.re_density, &n0_density, &unused);
    lattice_constants(s->l0, s->params.re_laplacian, &n0_laplacian, &lambda);
    const struct { const char *name; double stored, expected; } values[] = {
        {"n0_density", s->n0_density, n0_density},
        {"n0_laplacian", s->n0_laplacian, n0_laplacian},
        {"lambda", s->lambda, lambda},
    };
    for (size_t k = 0; k < 3; k++) {
        double stored = values[k].stored, expected = values[k].expected;
        if (!(isfinite(expected) && fabs(stored - expected) <= 1e-9 * fabs(expected))) {
            h5_note_text(ctx, "attribute %s is %.17g, but l0 = %g and the radii give %.17g "
                         "(l0 or %s damaged)", values[k].name, stored, s->l0, expected,
                         values[k].name);
            return -1;
        }
    }
    return 0;
}

/* The fluids as mps2p_scene_add_fluid accepts them: names unique too. */
static int check_fluids(h5_context *ctx, const mps2p_solver *s)
{
    for (int f = 0; f < s->fluid_count; f++)
        for (int g = 0; g < f; g++)
            if (strcmp(s->fluids[f].name, s->fluids[g].name) == 0) {
                h5_note_text(ctx, "fluids %d and %d are both named \"%s\"", g, f,
                             s->fluids[f].name);
                return -1;
            }
    return 0;
}

/* Values the stages index with or divide by must be in range, and every
 * particle as mps2p_solver_create would have it: inside the domain, with
 * its fluid's density and viscosity (walls: the heaviest fluid's, and 0);
 * or as a run leaves fluid that went out of it (MPS2P_KIND_OUT, counted by
 * fluid_out): outside the domain, at rest, no pressure, its fluid id kept. */
static int check_particles(h5_context *ctx, const mps2p_solver *s)
{
    double heaviest = 0.0;
    size_t fluid_particles = 0, out = 0;
    for (int f = 0; f < s->fluid_count; f++)
        heaviest = fmax(heaviest, s->fluids[f].density);
    for (size_t i = 0; i < s->count; i++) {
        int kind = s->kind[i], id = s->fluid_id[i];
        int fluid = kind_is_fluid(kind), is_out = kind == MPS2P_KIND_OUT;
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
        fluid_particles += fluid;
        out += is_out;
        const double x = s->state.position[2 * i], y = s->state.position[2 * i + 1];
        const double *d = s->domain;
        if (fabs(x) > COORDINATE_LIMIT_L0 * s->l0 || fabs(y) > COORDINATE_LIMIT_L0 * s->l0) {
            h5_note_text(ctx, "particle %zu at (%g, %g) is beyond %g l0 of the origin (a "
                         "scene refuses such coordinates)", i, x, y, COORDINATE_LIMIT_L0);
            return -1;
        }
        int outside = x < d[0] || x > d[2] || y < d[1] || y > d[3];
        if (outside != is_out) {
            h5_note_text(ctx, "particle %zu (kind %d) at (%g, %g) is %s attribute domain [%g, "
                         "%g] x [%g, %g]", i, kind, x, y, outside ? "outside" : "out of the "
                         "run (kind MPS2P_KIND_OUT) but inside", d[0], d[2], d[1], d[3]);
            return -1;
        }
        if (is_out && (s->state.velocity[2 * i] != 0.0 || s->state.velocity[2 * i + 1] != 0.0 ||
                       s->state.pressure[i] != 0.0)) {
            h5_note_text(ctx, "particle %zu is out of the run (kind MPS2P_KIND_OUT) but has "
                         "velocity (%g, %g) and pressure %g, not 0", i,
                         s->state.velocity[2 * i], s->state.velocity[2 * i + 1],
                         s->state.pressure[i]);
            return -1;
        }
        const double density = fluid ? s->fluids[id].density : heaviest;
        const double viscosity = fluid ? s->fluids[id].viscosity : 0.0;
        if (s->density[i] != density || s->viscosity[i] != viscosity) {
            h5_note_text(ctx, "particles/density or viscosity of particle %zu (%g, %g) is not "
                         "its %s's (%g, %g)", i, s->density[i], s->viscosity[i],
                         fluid ? "fluid" : "wall, the heaviest fluid", density, viscosity);
            return -1;
        }
        if (s->number_density[i] < 0.0) {
            h5_note_text(ctx, "particles/number_density of particle %zu is %g, below 0", i,
                         s->number_density[i]);
            return -1;
        }
    }
    if (fluid_particles == 0) {
        h5_note_text(ctx, "it holds no fluid particle");
        return -1;
    }
    if (s->fluid_out != out) {
        h5_note_text(ctx, "attribute fluid_out is %zu, but %zu particles are of kind "
                     "MPS2P_KIND_OUT", s->fluid_out, out);
        return -1;
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

/* Reads group "bodies" and the accelerations (format 2) into s->coupling,
 * checking every id, name and value the stages rely on. */
static int read_bodies(h5_context *ctx, hid_t file, mps2p_solver *s)
{
    const size_t n = s->count, width = FLUID_NAME_SIZE + 1;
    hid_t group = H5Gopen2(file, "bodies", H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    hsize_t length = 0, per_particle[2] = {n, 2};
    int status = h5_dataset_length(ctx, group, "angular_velocity", &length);
    if (status == 0 && (length < 1 || length > (1u << 20) + 1)) {
        h5_note_text(ctx, "%llu bodies (1 to %d allowed)", (unsigned long long)length,
                     (1 << 20) + 1);
        status = -1;
    }
    const size_t bodies = status == 0 ? (size_t)length : 1;
    hsize_t per_body[2] = {bodies, 2};
    char *names = malloc(bodies * width);
    char(*rest)[FLUID_NAME_SIZE] = malloc(bodies * sizeof *rest);
    double *motion = malloc(5 * bodies * sizeof *motion), *target = NULL;
    int *has_target = malloc(bodies * sizeof *has_target);
    int *body_id = malloc(n * sizeof *body_id), targets = 0;
    if (status == 0 && (!names || !rest || !motion || !has_target || !body_id)) {
        h5_note_text(ctx, "out of memory");
        status = -1;
    }
    if (status == 0)
        status = h5_read_string_array(ctx, group, "name", bodies, names, width);
    if (status == 0)
        status = h5_read_dataset(ctx, group, "velocity", H5T_NATIVE_DOUBLE, 2, per_body, motion);
    if (status == 0)
        status = h5_read_dataset(ctx, group, "angular_velocity", H5T_NATIVE_DOUBLE, 1, per_body,
                                 motion + 2 * bodies);
    if (status == 0)
        status = h5_read_dataset(ctx, group, "about", H5T_NATIVE_DOUBLE, 2, per_body,
                                 motion + 3 * bodies);
    if (status == 0)
        status = h5_read_dataset(ctx, group, "has_target", H5T_NATIVE_INT, 1, per_body,
                                 has_target);
    if (status == 0)
        status = h5_read_dataset(ctx, group, "body_id", H5T_NATIVE_INT, 1, per_particle, body_id);
    for (size_t b = 0; status == 0 && b < bodies; b++) {
        const char *name = names + b * width;
        int ok = strlen(name) > 0 && strlen(name) < FLUID_NAME_SIZE &&
                 (b > 0 || strcmp(name, "walls") == 0) &&
                 (has_target[b] == 0 || has_target[b] == 1);
        for (size_t k = 0; k < 5 && ok; k++)
            ok = isfinite(motion[k < 2 ? 2 * b + k : k == 2 ? 2 * bodies + b
                                                  : 3 * bodies + 2 * b + (k - 3)]);
        if (!ok) {
            h5_note_text(ctx, "body %zu (\"%s\") is inconsistent", b, name);
            status = -1;
        } else if (b > 0) {
            strcpy(rest[b - 1], name);
        }
        targets |= status == 0 && has_target[b];
    }
    for (size_t i = 0; status == 0 && i < n; i++) {
        int fluid = kind_is_fluid(s->kind[i]), id = body_id[i];
        if (fluid ? id != -1 : id < 0 || (size_t)id >= bodies) {
            h5_note_text(ctx, "particle %zu of kind %d has body id %d (%zu bodies)", i,
                         s->kind[i], id, bodies);
            status = -1;
        }
    }
    if (status == 0 && targets) {
        if (!(target = malloc(2 * n * sizeof *target))) {
            h5_note_text(ctx, "out of memory");
            status = -1;
        } else {
            status = h5_read_dataset(ctx, group, "target", H5T_NATIVE_DOUBLE, 2, per_particle,
                                     target);
        }
    }
    if (status == 0 && coupling_build(s, (int)bodies, rest, body_id) != MPS2P_OK) {
        h5_note_text(ctx, "out of memory for %zu bodies", bodies);
        status = -1;
    }
    for (size_t b = 0; status == 0 && b < bodies; b++) {
        body *bd = &s->coupling->bodies[b];
        bd->velocity[0] = motion[2 * b];
        bd->velocity[1] = motion[2 * b + 1];
        bd->angular_velocity = motion[2 * bodies + b];
        bd->about[0] = motion[3 * bodies + 2 * b];
        bd->about[1] = motion[3 * bodies + 2 * b + 1];
        if (!has_target[b])
            continue;
        if (!(bd->target = malloc((bd->particles ? 2 * bd->particles : 1) * sizeof *bd->target))) {
            h5_note_text(ctx, "out of memory");
            status = -1;
        }
        for (size_t m = 0; status == 0 && m < bd->particles; m++) {
            size_t i = bd->member[m];
            bd->target[2 * m] = target[2 * i];
            bd->target[2 * m + 1] = target[2 * i + 1];
            if (!isfinite(bd->target[2 * m]) || !isfinite(bd->target[2 * m + 1])) {
                h5_note_text(ctx, "target of particle %zu is not finite", i);
                status = -1;
            }
        }
    }
    H5Gclose(group);
    htri_t has_acceleration = status == 0 ? H5Lexists(file, "acceleration", H5P_DEFAULT) : 0;
    if (has_acceleration < 0) {
        h5_note(ctx);
        status = -1;
    } else if (has_acceleration > 0) {
        double *a = malloc(2 * n * sizeof *a);
        if (!a) {
            h5_note_text(ctx, "out of memory");
            status = -1;
        } else {
            s->coupling->acceleration = a;
            status = h5_read_dataset(ctx, file, "acceleration", H5T_NATIVE_DOUBLE, 2,
                                     per_particle, a);
        }
        for (size_t k = 0; status == 0 && k < 2 * n; k++)
            if (!isfinite(a[k])) {
                h5_note_text(ctx, "acceleration of particle %zu is not finite", k / 2);
                status = -1;
            }
    }
    free(names);
    free(rest);
    free(motion);
    free(has_target);
    free(body_id);
    free(target);
    return status;
}

/* Reads group "two_phase" into the loaded solver's s->phases, allocated by
 * its plan from the fluids and parameters: a file has the group exactly
 * when they make a two-phase solver. */
static int read_two_phase(h5_context *ctx, hid_t file, mps2p_solver *s, int version)
{
    htri_t has_group = H5Lexists(file, "two_phase", H5P_DEFAULT);
    if (has_group < 0) {
        h5_note(ctx);
        return -1;
    }
    if (has_group > 0 && !s->phases) {
        h5_note_text(ctx, "it holds a two-phase state (group two_phase), but its fluids and "
                     "parameters make a single-phase solver");
        return -1;
    }
    if (!s->phases)
        return 0;
    if (has_group == 0) {
        if (version < 3)
            h5_note_text(ctx, "its fluids and parameters make a two-phase solver (effect "
                         "two_phase on), which format version %d cannot hold", version);
        else
            h5_note_text(ctx, "its fluids and parameters make a two-phase solver (effect "
                         "two_phase on), but it has no group two_phase");
        return -1;
    }
    hid_t group = H5Gopen2(file, "two_phase", H5P_DEFAULT);
    if (group < 0) {
        h5_note(ctx);
        return -1;
    }
    int status = read_fields(ctx, group, &two_phase_fields, s->phases, s->count, 1);
    if (status == 0)
        status = read_fields(ctx, group, &two_phase_fields, s->phases, s->count, 0);
    H5Gclose(group);
    char why[ERROR_MESSAGE_SIZE];
    if (status == 0 && phases_carried_check(s, why, sizeof why) != 0) {
        h5_note_text(ctx, "%s", why);
        status = -1;
    }
    if (status == 0)
        phases_carried_rebuild(s);
    return status;
}

/* Reads the open file into a new solver; MPS2P_ERR_IO (detail noted) or
 * MPS2P_ERR_NOMEM on failure, with *out left NULL. */
static int load(h5_context *ctx, hid_t file, int sealed, mps2p_solver **out)
{
    mps2p_solver *s = calloc(1, sizeof *s);
    if (!s)
        return fail(NULL, MPS2P_ERR_NOMEM, "out of memory loading a checkpoint");
    s->diverged_particle = -1; /* not saved */
    int version = 0, status = MPS2P_ERR_IO;
    double *built_at = NULL;
    uint64_t builds = 0;
    if (read_header(ctx, file, sealed, &version) != 0 || read_root(ctx, file, s) != 0 ||
        h5_read_parameters(ctx, file, &s->params) != 0)
        goto done;
    const size_t count = s->count;
    const int fluids = s->fluid_count;
    int file_fluids = 0;
    if (h5_read_fluid_count(ctx, file, &file_fluids) != 0)
        goto done;
    if (file_fluids != fluids) {
        h5_note_text(ctx, "fluid_count says %d fluids, the fluids group holds %d", fluids,
                     file_fluids);
        goto done;
    }
    char what[ERROR_MESSAGE_SIZE / 2];
    snprintf(what, sizeof what, "checkpoint \"%s\": its solver of %zu particles", ctx->path,
             count);
    status = memory_check(&s->params, solver_bytes_estimate(&s->params, count), what, NULL);
    if (status != MPS2P_OK)
        goto done;
    status = solver_allocate(s, count, fluids);
    built_at = malloc(2 * count * sizeof *built_at);
    if (status != MPS2P_OK || !built_at) {
        status = fail(NULL, MPS2P_ERR_NOMEM, "out of memory loading a checkpoint of %zu "
                      "particles", count);
        goto done;
    }
    status = MPS2P_ERR_IO;
    if (check_lattice(ctx, s) != 0 || h5_read_fluids(ctx, file, fluids, s->fluids) != 0 ||
        check_fluids(ctx, s) != 0 || read_particles(ctx, file, s) != 0 ||
        check_particles(ctx, s) != 0 || read_neighbours(ctx, file, s, built_at, &builds) != 0 ||
        (version >= 2 && read_bodies(ctx, file, s) != 0))
        goto done;
    status = solver_start(s);
    if (status == MPS2P_OK && neighbours_restore(&s->neighbours, built_at,
                                                 (unsigned long)builds) != MPS2P_OK)
        status = fail(NULL, MPS2P_ERR_NOMEM, "out of memory for the neighbour list");
    /* after solver_start: its plan allocated s->phases if the file makes two phases */
    if (status == MPS2P_OK && read_two_phase(ctx, file, s, version) != 0)
        status = MPS2P_ERR_IO;
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
    error_clear();
    if (!solver)
        return fail(NULL, MPS2P_ERR_NULL,
                    "mps2p_solver_load_checkpoint: solver output pointer is NULL");
    *solver = NULL;
    if (!path)
        return fail(NULL, MPS2P_ERR_NULL, "mps2p_solver_load_checkpoint: path is NULL");

    if (!path[0])
        return fail(NULL, MPS2P_ERR_INVALID, "mps2p_solver_load_checkpoint: path is empty");

    /* the raw bytes first: HDF5 must not parse a damaged file, nor open a FIFO */
    struct stat checked;
    char reason[256] = "";
    int sealed = checkpoint_verify(path, &checked, reason, sizeof reason);
    if (sealed < 0)
        return fail(NULL, MPS2P_ERR_IO, "checkpoint \"%s\": cannot open: %s", path, reason);
    h5_guard guard;
    h5_context ctx;
    h5_enter(&guard);
    h5_context_init(&ctx, "checkpoint", path);
    int status;
    int *fd = NULL;
    hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file < 0) {
        h5_note(&ctx);
        status = h5_fail(&ctx, NULL, "cannot open");
    } else if (H5Fget_vfd_handle(file, H5P_DEFAULT, (void **)&fd) < 0 || !fd ||
               checkpoint_same_file(*fd, &checked) != 0) {
        h5_note_text(&ctx, "it changed between its check and its reading");
        status = h5_fail(&ctx, NULL, "cannot load");
        H5Fclose(file);
    } else {
        status = load(&ctx, file, sealed == CHECKPOINT_SEALED, solver);
        if (status == MPS2P_ERR_IO)
            status = h5_fail(&ctx, NULL, "cannot load");
        H5Fclose(file);
    }
    h5_leave(&guard);
    return status;
}
