/* Results file: three snapshots and two series, read back with the HDF5 C
 * API and compared with what the solver returned; the XDMF sidecar names
 * the snapshots; errors are refused with messages, and HDF5 prints nothing. */
#define _POSIX_C_SOURCE 200809L
#include <hdf5.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>
#include "scenes.h"

#define SNAPSHOTS 3
static const char scene_text[] = "# dam break\nspacing 0.02\nfluid water 1000 1e-6\n";

typedef struct expected {
    size_t n;
    double time;
    uint64_t step;
    double *position, *velocity, *pressure, *number_density;
    int *kind, *fluid_id;
} expected;

static expected capture(const mps2p_solver *solver)
{
    expected e;
    MUST(mps2p_solver_particle_count(solver, &e.n));
    MUST(mps2p_solver_get_time(solver, &e.time));
    MUST(mps2p_solver_get_step_count(solver, &e.step));
    e.position = malloc(2 * e.n * sizeof(double));
    e.velocity = malloc(2 * e.n * sizeof(double));
    e.pressure = malloc(e.n * sizeof(double));
    e.number_density = malloc(e.n * sizeof(double));
    e.kind = malloc(e.n * sizeof(int));
    e.fluid_id = malloc(e.n * sizeof(int));
    MUST(mps2p_solver_get_positions(solver, e.position, 2 * e.n));
    MUST(mps2p_solver_get_velocities(solver, e.velocity, 2 * e.n));
    MUST(mps2p_solver_get_pressure(solver, e.pressure, e.n));
    MUST(mps2p_solver_get_number_density(solver, e.number_density, e.n));
    MUST(mps2p_solver_get_kinds(solver, e.kind, e.n));
    MUST(mps2p_solver_get_fluid_ids(solver, e.fluid_id, e.n));
    return e;
}

static void release(expected *e)
{
    free(e->position);
    free(e->velocity);
    free(e->pressure);
    free(e->number_density);
    free(e->kind);
    free(e->fluid_id);
}

/* Reads a dataset after checking its shape; returns 0 on success. */
static int read_dataset(hid_t file, const char *name, hid_t type, int rank, hsize_t d0,
                        hsize_t d1, void *out)
{
    hid_t dataset = H5Dopen2(file, name, H5P_DEFAULT);
    CHECK(dataset >= 0, "dataset %s is missing", name);
    if (dataset < 0)
        return -1;
    hid_t space = H5Dget_space(dataset);
    hsize_t dims[2] = {0, 0};
    int got_rank = H5Sget_simple_extent_ndims(space);
    H5Sget_simple_extent_dims(space, dims, NULL);
    int ok = got_rank == rank && dims[0] == d0 && (rank == 1 || dims[1] == d1);
    CHECK(ok, "%s has rank %d, %llu x %llu; expected rank %d, %llu x %llu", name, got_rank,
          (unsigned long long)dims[0], (unsigned long long)dims[1], rank,
          (unsigned long long)d0, (unsigned long long)d1);
    if (ok)
        ok = H5Dread(dataset, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) >= 0;
    H5Sclose(space);
    H5Dclose(dataset);
    return ok ? 0 : -1;
}

static void read_attribute(hid_t object, const char *name, hid_t type, void *out)
{
    hid_t attribute = H5Aopen(object, name, H5P_DEFAULT);
    CHECK(attribute >= 0 && H5Aread(attribute, type, out) >= 0, "attribute %s", name);
    if (attribute >= 0)
        H5Aclose(attribute);
}

static void read_string_attribute(hid_t object, const char *name, char *out, size_t size)
{
    hid_t attribute = H5Aopen(object, name, H5P_DEFAULT);
    hid_t type = H5Aget_type(attribute);
    size_t length = H5Tget_size(type);
    CHECK(length < size, "attribute %s is %zu bytes", name, length);
    memset(out, 0, size);
    if (length < size)
        H5Aread(attribute, type, out);
    H5Tclose(type);
    H5Aclose(attribute);
}

static void check_snapshot(hid_t file, int index, const expected *e)
{
    char group_name[64], name[96];
    snprintf(group_name, sizeof group_name, "/snapshots/%06d", index);
    hid_t group = H5Gopen2(file, group_name, H5P_DEFAULT);
    CHECK(group >= 0, "group %s is missing", group_name);
    if (group < 0)
        return;
    double time = -1.0;
    uint64_t step = 0;
    read_attribute(group, "time", H5T_NATIVE_DOUBLE, &time);
    read_attribute(group, "step", H5T_NATIVE_UINT64, &step);
    CHECK(time == e->time && step == e->step, "%s: time %g step %llu, expected %g and %llu",
          group_name, time, (unsigned long long)step, e->time, (unsigned long long)e->step);
    H5Gclose(group);

    size_t n = e->n;
    double *doubles = malloc(2 * n * sizeof *doubles);
    int *ints = malloc(n * sizeof *ints);
    const struct { const char *name; const double *want; int vector; } fields[] = {
        {"position", e->position, 1}, {"velocity", e->velocity, 1},
        {"pressure", e->pressure, 0}, {"number_density", e->number_density, 0},
    };
    for (size_t f = 0; f < 4; f++) {
        snprintf(name, sizeof name, "%s/%s", group_name, fields[f].name);
        if (read_dataset(file, name, H5T_NATIVE_DOUBLE, fields[f].vector ? 2 : 1, n, 2,
                         doubles) == 0)
            CHECK(!memcmp(doubles, fields[f].want, (fields[f].vector ? 2 : 1) * n * sizeof(double)),
                  "%s differs from the solver's", name);
    }
    snprintf(name, sizeof name, "%s/kind", group_name);
    if (read_dataset(file, name, H5T_NATIVE_INT, 1, n, 0, ints) == 0)
        CHECK(!memcmp(ints, e->kind, n * sizeof(int)), "%s differs", name);
    snprintf(name, sizeof name, "%s/fluid_id", group_name);
    if (read_dataset(file, name, H5T_NATIVE_INT, 1, n, 0, ints) == 0)
        CHECK(!memcmp(ints, e->fluid_id, n * sizeof(int)), "%s differs", name);
    free(doubles);
    free(ints);
}

static void check_file(const char *path, const expected *snapshots)
{
    hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    CHECK(file >= 0, "cannot reopen %s", path);
    if (file < 0)
        return;
    char text[256];
    read_string_attribute(file, "format", text, sizeof text);
    CHECK(!strcmp(text, "libmps2p results"), "format \"%s\"", text);
    read_string_attribute(file, "library_version", text, sizeof text);
    CHECK(!strcmp(text, mps2p_version_string()), "library_version \"%s\"", text);
    double l0 = 0.0, beta = 0.0, density = 0.0;
    read_attribute(file, "l0", H5T_NATIVE_DOUBLE, &l0);
    CHECK(l0 == 0.02, "l0 %g", l0);

    /* the XDMF topology's connectivity: particle i is vertex i */
    size_t n = snapshots[0].n;
    int *vertices = malloc(n * sizeof *vertices);
    if (vertices && read_dataset(file, "vertices", H5T_NATIVE_INT, 2, n, 1, vertices) == 0) {
        size_t wrong = 0;
        while (wrong < n && vertices[wrong] == (int)wrong)
            wrong++;
        CHECK(wrong == n, "vertices[%zu] = %d", wrong, wrong < n ? vertices[wrong] : 0);
    }
    free(vertices);

    hid_t parameters = H5Gopen2(file, "parameters", H5P_DEFAULT);
    CHECK(parameters >= 0, "no /parameters");
    const char *key;
    double default_value;
    for (size_t i = 0; mps2p_param_info(i, &key, NULL, &default_value) == MPS2P_OK; i++) {
        double value = NAN;
        read_attribute(parameters, key, H5T_NATIVE_DOUBLE, &value);
        CHECK(value == default_value || !strcmp(key, "beta"), "parameter %s: %g, default %g",
              key, value, default_value);
    }
    read_attribute(parameters, "beta", H5T_NATIVE_DOUBLE, &beta);
    CHECK(beta == 0.95, "beta %g, set to 0.95", beta);
    read_string_attribute(parameters, "pressure_solver", text, sizeof text);
    CHECK(!strcmp(text, "cg"), "pressure_solver \"%s\", the default cg", text);
    H5Gclose(parameters);

    char names[2][64];
    hid_t string = H5Tcopy(H5T_C_S1);
    H5Tset_size(string, 64);
    H5Tset_cset(string, H5T_CSET_UTF8); /* HDF5 converts no character sets */
    hid_t dataset = H5Dopen2(file, "/fluids/name", H5P_DEFAULT);
    CHECK(dataset >= 0 && H5Dread(dataset, string, H5S_ALL, H5S_ALL, H5P_DEFAULT, names) >= 0,
          "/fluids/name");
    CHECK(!strcmp(names[0], "water") && !strcmp(names[1], "air"), "fluids \"%s\", \"%s\"",
          names[0], names[1]);
    H5Dclose(dataset);
    double densities[2];
    if (read_dataset(file, "/fluids/density", H5T_NATIVE_DOUBLE, 1, 2, 0, densities) == 0)
        density = densities[1];
    CHECK(density == 1.2, "air density %g", density);

    char stored_scene[sizeof scene_text + 8];
    hid_t scene_type = H5Tcopy(H5T_C_S1);
    H5Tset_size(scene_type, sizeof stored_scene);
    H5Tset_cset(scene_type, H5T_CSET_UTF8);
    memset(stored_scene, 0, sizeof stored_scene);
    dataset = H5Dopen2(file, "/scene_text", H5P_DEFAULT);
    CHECK(dataset >= 0 &&
              H5Dread(dataset, scene_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, stored_scene) >= 0,
          "/scene_text");
    CHECK(!strcmp(stored_scene, scene_text), "scene text \"%s\"", stored_scene);
    H5Dclose(dataset);
    H5Tclose(scene_type);
    H5Tclose(string);

    for (int k = 0; k < SNAPSHOTS; k++)
        check_snapshot(file, k, &snapshots[k]);
    hsize_t count = 0;
    hid_t group = H5Gopen2(file, "/snapshots", H5P_DEFAULT);
    H5Gget_num_objs(group, &count);
    CHECK(count == SNAPSHOTS, "%llu snapshots", (unsigned long long)count);
    H5Gclose(group);

    double front[5][2], energy[3][2];
    if (read_dataset(file, "/series/front", H5T_NATIVE_DOUBLE, 2, 5, 2, front) == 0)
        for (int k = 0; k < 5; k++)
            CHECK(front[k][0] == 0.1 * k && front[k][1] == 0.15 + 0.01 * k,
                  "front row %d: (%g, %g)", k, front[k][0], front[k][1]);
    if (read_dataset(file, "/series/energy.kinetic-J", H5T_NATIVE_DOUBLE, 2, 3, 2, energy) == 0)
        CHECK(energy[2][0] == 2.0 && energy[2][1] == 20.0, "energy row 2: (%g, %g)",
              energy[2][0], energy[2][1]);
    H5Fclose(file);
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = calloc((size_t)size + 1, 1);
    if (fread(text, 1, (size_t)size, f) != (size_t)size)
        text[0] = '\0';
    fclose(f);
    return text;
}

static void check_sidecar(const char *xdmf, const expected *snapshots)
{
    char *text = slurp(xdmf);
    CHECK(text != NULL, "no sidecar %s", xdmf);
    if (!text)
        return;
    char needle[128];
    for (int k = 0; k < SNAPSHOTS; k++) {
        snprintf(needle, sizeof needle, "run.h5:/snapshots/%06d/position", k);
        CHECK(strstr(text, needle) != NULL, "sidecar lacks %s", needle);
        snprintf(needle, sizeof needle, "<Time Value=\"%.17g\"/>", snapshots[k].time);
        CHECK(strstr(text, needle) != NULL, "sidecar lacks %s", needle);
    }
    snprintf(needle, sizeof needle, "/snapshots/%06d/", SNAPSHOTS);
    CHECK(strstr(text, needle) == NULL, "sidecar names a snapshot that was not written");
    CHECK(strstr(text, "CollectionType=\"Temporal\"") && strstr(text, "Polyvertex") &&
              strstr(text, "Name=\"velocity\"") && strstr(text, "Name=\"pressure\"") &&
              strstr(text, "Name=\"kind\"") && strstr(text, "Name=\"fluid_id\""),
          "sidecar lacks the collection, topology or attributes");
    /* the Xdmf3 readers and meshio make cells only from the connectivity */
    snprintf(needle, sizeof needle, "NumberOfElements=\"%zu\" NodesPerElement=\"1\">",
             snapshots[0].n);
    CHECK(strstr(text, needle) != NULL, "sidecar lacks %s", needle);
    snprintf(needle, sizeof needle, "<DataItem Dimensions=\"%zu 1\" NumberType=\"Int\" "
             "Precision=\"4\" Format=\"HDF\">run.h5:/vertices</DataItem>", snapshots[0].n);
    CHECK(strstr(text, needle) != NULL, "sidecar lacks the topology's %s", needle);
    free(text);
}

int main(void)
{
    char dir[] = "/tmp/mps2p-results-XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    char path[256], xdmf[256], name[300];
    snprintf(path, sizeof path, "%s/run.h5", dir);
    snprintf(xdmf, sizeof xdmf, "%s/run.xdmf", dir);

    mps2p_scene *scene = dam_break_scene(0.02);
    MUST(mps2p_scene_add_fluid(scene, "air", 1.2, 1.5e-5, NULL));
    MUST(mps2p_scene_set_param(scene, "beta", 0.95));
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));

    /* The caller's HDF5 error printing is kept as it was. */
    H5E_auto2_t before_func, after_func;
    void *before_data, *after_data;
    H5Eget_auto2(H5E_DEFAULT, &before_func, &before_data);

    mps2p_results *results;
    MUST(mps2p_results_create(path, solver, scene_text, &results));
    expected snapshots[SNAPSHOTS];
    for (int k = 0; k < SNAPSHOTS; k++) {
        if (k > 0)
            for (int s = 0; s < 10; s++)
                MUST(mps2p_solver_step(solver));
        MUST(mps2p_results_write_snapshot(results, solver));
        snapshots[k] = capture(solver);
    }
    for (int k = 0; k < 5; k++)
        MUST(mps2p_results_append_series(results, "front", 0.1 * k, 0.15 + 0.01 * k));
    for (int k = 0; k < 3; k++)
        MUST(mps2p_results_append_series(results, "energy.kinetic-J", k, 10.0 * k));

    /* errors on a live handle */
    const char *bad_names[] = {"", "a/b", ".hidden", "with space", "tab\t", "é"};
    for (size_t i = 0; i < sizeof bad_names / sizeof bad_names[0]; i++) {
        int status = mps2p_results_append_series(results, bad_names[i], 0.0, 1.0);
        CHECK(status == MPS2P_ERR_INVALID, "series name \"%s\": %s", bad_names[i],
              mps2p_status_string(status));
    }
    CHECK(strstr(mps2p_results_last_error(results), "series name") != NULL,
          "handle message: %s", mps2p_results_last_error(results));
    CHECK(mps2p_results_append_series(results, "front", NAN, 1.0) == MPS2P_ERR_INVALID, "NaN");
    CHECK(mps2p_results_append_series(results, NULL, 0.0, 1.0) == MPS2P_ERR_NULL, "NULL name");
    CHECK(mps2p_results_append_series(NULL, "x", 0.0, 1.0) == MPS2P_ERR_NULL, "NULL results");
    CHECK(mps2p_results_write_snapshot(results, NULL) == MPS2P_ERR_NULL, "NULL solver");
    CHECK(mps2p_results_write_snapshot(NULL, solver) == MPS2P_ERR_NULL, "NULL results");
    mps2p_solver *smaller;
    mps2p_scene *small_scene = tank_scene(0.02, 0.1, 0.1);
    MUST(mps2p_solver_create(small_scene, &smaller));
    CHECK(mps2p_results_write_snapshot(results, smaller) == MPS2P_ERR_INVALID &&
              strstr(mps2p_last_error(), "particles"),
          "a solver of another size: %s", mps2p_last_error());
    mps2p_solver_destroy(smaller);
    mps2p_scene_destroy(small_scene);
    MUST(mps2p_results_close(results));

    check_file(path, snapshots);
    check_sidecar(xdmf, snapshots);
    snprintf(name, sizeof name, "%s.tmp", xdmf);
    CHECK(access(name, F_OK) != 0, "the sidecar's temporary file was left behind");

    /* creation errors; HDF5 must print nothing meanwhile */
    fflush(stderr);
    snprintf(name, sizeof name, "%s/stderr.txt", dir);
    int saved_stderr = dup(2);
    FILE *capture_file = fopen(name, "w");
    CHECK(capture_file != NULL && dup2(fileno(capture_file), 2) == 2, "cannot capture stderr");
    char missing[300];
    snprintf(missing, sizeof missing, "%s/no-such-dir/run.h5", dir);
    results = (mps2p_results *)&results;
    int status = mps2p_results_create(missing, solver, NULL, &results);
    char message[512];
    snprintf(message, sizeof message, "%s", mps2p_last_error());
    int null_path = mps2p_results_create(NULL, solver, NULL, &results);
    int null_solver = mps2p_results_create(path, NULL, NULL, &results);
    int null_output = mps2p_results_create(path, solver, NULL, NULL);
    fflush(stderr);
    dup2(saved_stderr, 2);
    close(saved_stderr);
    fclose(capture_file);
    char *printed = slurp(name);
    CHECK(printed && printed[0] == '\0', "the library printed: %s", printed ? printed : "?");
    free(printed);
    printf("missing directory: %s\n", message);
    CHECK(status == MPS2P_ERR_IO, "missing directory: %s", mps2p_status_string(status));
    CHECK(strstr(message, missing) != NULL, "message \"%s\" does not name the path", message);
    /* the system's reason, without HDF5's driver flags */
    CHECK(strstr(message, "No such file or directory") && !strstr(message, "o_flags"),
          "message \"%s\" does not give the reason plainly", message);
    CHECK(results == NULL, "handle not NULL after a failure");
    CHECK(null_path == MPS2P_ERR_NULL && null_solver == MPS2P_ERR_NULL &&
              null_output == MPS2P_ERR_NULL, "NULL arguments: %d %d %d", null_path,
          null_solver, null_output);
    CHECK(mps2p_results_close(NULL) == MPS2P_OK, "closing NULL");
    H5Eget_auto2(H5E_DEFAULT, &after_func, &after_data);
    CHECK(after_func == before_func && after_data == before_data,
          "the caller's HDF5 error handler was not restored");

    for (int k = 0; k < SNAPSHOTS; k++)
        release(&snapshots[k]);
    mps2p_solver_destroy(solver);
    mps2p_scene_destroy(scene);
    remove(path);
    remove(xdmf);
    remove(name);
    CHECK(rmdir(dir) == 0, "%s is not empty: something left a file behind", dir);
    return check_summary("test_results_file");
}
