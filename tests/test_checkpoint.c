/* Checkpoint and restart: a restored solver continues bitwise as the saved
 * one, for both pressure solvers and with the host's inputs (a moving body,
 * one step's targets, accelerations, changed gravity); version 1 files still
 * load; damaged or foreign files are refused. Format 4 files carry a
 * checksum (issue 20): every change of their bytes is refused before HDF5
 * reads them. Edits "as a crafted file would" are resealed with a fresh
 * checksum (checkpoint_seal.h) to reach the content checks behind it. */
#define _POSIX_C_SOURCE 200809L
#include <hdf5.h>
#include <signal.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "checkpoint_seal.h"
#include "scenes.h"

#define BEFORE 40 /* steps before the checkpoint */
#define AFTER 40  /* steps after it */

typedef struct state {
    size_t n;
    double *position, *velocity, *pressure;
    double time, dt, builds;
    uint64_t steps;
} state;

static state capture(const mps2p_solver *solver)
{
    state s;
    MUST(mps2p_solver_particle_count(solver, &s.n));
    s.position = malloc(2 * s.n * sizeof(double));
    s.velocity = malloc(2 * s.n * sizeof(double));
    s.pressure = malloc(s.n * sizeof(double));
    MUST(mps2p_solver_get_positions(solver, s.position, 2 * s.n));
    MUST(mps2p_solver_get_velocities(solver, s.velocity, 2 * s.n));
    MUST(mps2p_solver_get_pressure(solver, s.pressure, s.n));
    MUST(mps2p_solver_get_time(solver, &s.time));
    MUST(mps2p_solver_get_last_dt(solver, &s.dt));
    MUST(mps2p_solver_get_step_count(solver, &s.steps));
    MUST(mps2p_solver_get_stat(solver, "neighbour_builds", &s.builds));
    return s;
}

static void release(state *s)
{
    free(s->position);
    free(s->velocity);
    free(s->pressure);
}

static void steps(mps2p_solver *solver, int count)
{
    for (int k = 0; k < count; k++)
        MUST(mps2p_solver_step(solver));
}

static void restart_is_bitwise(const char *method, const char *path)
{
    mps2p_scene *scene = dam_break_scene(0.02);
    MUST(mps2p_scene_set_option(scene, "pressure_solver", method));
    mps2p_solver *original, *restored;
    MUST(mps2p_solver_create(scene, &original));
    mps2p_scene_destroy(scene);
    steps(original, BEFORE);
    MUST(mps2p_solver_save_checkpoint(original, path));
    state saved = capture(original);
    steps(original, AFTER);
    state expected = capture(original);

    MUST(mps2p_solver_load_checkpoint(path, &restored));
    state loaded = capture(restored);
    CHECK(loaded.n == saved.n && loaded.steps == saved.steps && loaded.time == saved.time &&
          loaded.dt == saved.dt && loaded.builds == saved.builds,
          "%s: loaded solver differs in counts, time or last dt", method);
    CHECK(!memcmp(loaded.position, saved.position, 2 * saved.n * sizeof(double)),
          "%s: loaded positions differ", method);
    steps(restored, AFTER);
    state got = capture(restored);
    CHECK(got.n == expected.n, "%s: particle counts differ", method);
    CHECK(got.steps == expected.steps, "%s: step counts %llu vs %llu", method,
          (unsigned long long)got.steps, (unsigned long long)expected.steps);
    CHECK(!memcmp(&got.time, &expected.time, sizeof got.time), "%s: time %.17g vs %.17g",
          method, got.time, expected.time);
    CHECK(!memcmp(got.position, expected.position, 2 * got.n * sizeof(double)),
          "%s: positions are not bitwise identical", method);
    CHECK(!memcmp(got.velocity, expected.velocity, 2 * got.n * sizeof(double)),
          "%s: velocities are not bitwise identical", method);
    CHECK(!memcmp(got.pressure, expected.pressure, got.n * sizeof(double)),
          "%s: pressures are not bitwise identical", method);
    CHECK(got.builds == expected.builds && got.builds > saved.builds,
          "%s: neighbour builds %g vs %g (at the checkpoint %g)", method, got.builds,
          expected.builds, saved.builds);
    printf("%s: %llu steps, t = %.6f s, %g neighbour builds: restart is bitwise\n", method,
           (unsigned long long)got.steps, got.time, got.builds);
    release(&saved);
    release(&expected);
    release(&loaded);
    release(&got);
    mps2p_solver_destroy(original);
    mps2p_solver_destroy(restored);
}

/* A dam break against a paddle (body 1) turning about its foot, with
 * accelerations on the fluid and gravity tilted: every input is saved. */
static mps2p_solver *driven_dam_break(int *paddle)
{
    mps2p_scene *scene = dam_break_scene(0.02);
    MUST(mps2p_scene_add_body_box(scene, "paddle", 0.22, 0.0, 0.26, 0.1, paddle));
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    size_t n;
    MUST(mps2p_solver_particle_count(solver, &n));
    double *a = malloc(2 * n * sizeof *a);
    for (size_t i = 0; i < n; i++) {
        a[2 * i] = 0.5 + 1e-3 * (double)(i % 7);
        a[2 * i + 1] = -0.2;
    }
    MUST(mps2p_solver_set_body_forces(solver, a, 2 * n));
    free(a);
    MUST(mps2p_solver_set_gravity(solver, 0.3, -9.7));
    const double still[2] = {0.0, 0.0}, foot[2] = {0.24, 0.0};
    MUST(mps2p_solver_set_body_motion(solver, *paddle, still, 0.8, foot));
    return solver;
}

/* One step's targets for the paddle: where it is, moved 1 mm to the right. */
static void set_paddle_targets(mps2p_solver *solver, int paddle)
{
    size_t n, members;
    MUST(mps2p_solver_particle_count(solver, &n));
    MUST(mps2p_solver_get_body(solver, paddle, NULL, &members));
    double *r = malloc(2 * n * sizeof *r), *target = malloc(2 * members * sizeof *target);
    int *body = malloc(n * sizeof *body);
    MUST(mps2p_solver_get_positions(solver, r, 2 * n));
    MUST(mps2p_solver_get_body_ids(solver, body, n));
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (body[i] == paddle) {
            target[2 * m] = r[2 * i] + 0.001;
            target[2 * m + 1] = r[2 * i + 1];
            m++;
        }
    MUST(mps2p_solver_set_body_positions(solver, paddle, target, 2 * members));
    free(r);
    free(target);
    free(body);
}

static void driven_restart_is_bitwise(const char *path)
{
    int paddle;
    mps2p_solver *original = driven_dam_break(&paddle), *restored;
    steps(original, BEFORE);
    set_paddle_targets(original, paddle);
    MUST(mps2p_solver_save_checkpoint(original, path));
    steps(original, AFTER);
    state expected = capture(original);
    double f_expected[2], m_expected;
    MUST(mps2p_solver_body_force(original, paddle, -1, f_expected, &m_expected, NULL));

    MUST(mps2p_solver_load_checkpoint(path, &restored));
    int bodies = 0;
    const char *name = "";
    size_t members = 0, original_members = 0;
    double g[2];
    MUST(mps2p_solver_body_count(restored, &bodies));
    MUST(mps2p_solver_get_body(restored, bodies - 1, &name, &members));
    MUST(mps2p_solver_get_body(original, paddle, NULL, &original_members));
    MUST(mps2p_solver_get_gravity(restored, g));
    CHECK(bodies == 2 && strcmp(name, "paddle") == 0 && members == original_members,
          "restored bodies: %d, last \"%s\" with %zu particles", bodies, name, members);
    CHECK(g[0] == 0.3 && g[1] == -9.7, "restored gravity (%g, %g)", g[0], g[1]);
    steps(restored, AFTER);
    state got = capture(restored);
    double f_got[2], m_got;
    MUST(mps2p_solver_body_force(restored, paddle, -1, f_got, &m_got, NULL));
    CHECK(got.steps == expected.steps && !memcmp(&got.time, &expected.time, sizeof got.time),
          "driven: steps or time differ");
    CHECK(!memcmp(got.position, expected.position, 2 * got.n * sizeof(double)),
          "driven: positions are not bitwise identical");
    CHECK(!memcmp(got.velocity, expected.velocity, 2 * got.n * sizeof(double)),
          "driven: velocities are not bitwise identical");
    CHECK(!memcmp(got.pressure, expected.pressure, got.n * sizeof(double)),
          "driven: pressures are not bitwise identical");
    CHECK(!memcmp(f_got, f_expected, sizeof f_got) && !memcmp(&m_got, &m_expected, sizeof m_got),
          "driven: paddle force (%.17g, %.17g) vs (%.17g, %.17g)", f_got[0], f_got[1],
          f_expected[0], f_expected[1]);
    printf("driven: %llu steps, t = %.6f s, paddle force (%.3f, %.3f) N/m, moment %.4f N m/m: "
           "restart is bitwise\n", (unsigned long long)got.steps, got.time, f_got[0], f_got[1],
           m_got);
    release(&expected);
    release(&got);
    mps2p_solver_destroy(original);
    mps2p_solver_destroy(restored);
}

static void expect_refused(const char *path, const char *fragment)
{
    mps2p_solver *solver = (mps2p_solver *)&solver; /* must be reset to NULL */
    int status = mps2p_solver_load_checkpoint(path, &solver);
    const char *message = mps2p_last_error();
    printf("refused: %s\n", message);
    CHECK(status == MPS2P_ERR_IO, "%s: got %s", path, mps2p_status_string(status));
    CHECK(solver == NULL, "%s: solver not NULL after a refusal", path);
    CHECK(strstr(message, path) != NULL, "message \"%s\" does not name %s", message, path);
    CHECK(strstr(message, fragment) != NULL, "message \"%s\" lacks \"%s\"", message, fragment);
    mps2p_solver_destroy(solver);
}

static void copy_prefix(const char *from, const char *to, double fraction)
{
    FILE *in = fopen(from, "rb"), *out = fopen(to, "wb");
    CHECK(in && out, "cannot copy %s", from);
    if (!in || !out)
        exit(1);
    fseek(in, 0, SEEK_END);
    long size = ftell(in);
    fseek(in, 0, SEEK_SET);
    long keep = (long)(size * fraction);
    char *bytes = malloc((size_t)size);
    CHECK(fread(bytes, 1, (size_t)size, in) == (size_t)size, "short read of %s", from);
    fwrite(bytes, 1, (size_t)keep, out);
    free(bytes);
    fclose(in);
    fclose(out);
}

/* Edits a saved checkpoint with the HDF5 API, as damage would. */
static void set_format_version(const char *path, int version)
{
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    hid_t attribute = H5Aopen(file, "format_version", H5P_DEFAULT);
    CHECK(H5Awrite(attribute, H5T_NATIVE_INT, &version) >= 0, "cannot edit %s", path);
    H5Aclose(attribute);
    H5Fclose(file);
    reseal_file(path); /* no header (format 3 and older): nothing to reseal */
}

static void shorten_dataset(const char *path, const char *name)
{
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    CHECK(H5Ldelete(file, name, H5P_DEFAULT) >= 0, "cannot delete %s", name);
    hsize_t dims[1] = {3};
    double values[3] = {0.0, 0.0, 0.0};
    hid_t space = H5Screate_simple(1, dims, NULL);
    hid_t dataset = H5Dcreate2(file, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT,
                               H5P_DEFAULT);
    H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values);
    H5Dclose(dataset);
    H5Sclose(space);
    H5Fclose(file);
    reseal_file(path);
}

/* Sets every value of a dataset (converted to its type), as a crafted file would. */
static void fill_dataset(const char *path, const char *name, double value)
{
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    hid_t dataset = H5Dopen2(file, name, H5P_DEFAULT);
    hid_t space = H5Dget_space(dataset);
    hssize_t count = H5Sget_simple_extent_npoints(space);
    double *values = malloc((size_t)(count > 0 ? count : 1) * sizeof *values);
    for (hssize_t i = 0; i < count; i++)
        values[i] = value;
    CHECK(H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values) >= 0,
          "cannot write %s", name);
    free(values);
    H5Sclose(space);
    H5Dclose(dataset);
    H5Fclose(file);
    reseal_file(path);
}

static void delete_link(const char *path, const char *name)
{
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    CHECK(H5Ldelete(file, name, H5P_DEFAULT) >= 0, "cannot delete %s", name);
    H5Fclose(file);
    reseal_file(path);
}

/* A root attribute of count doubles, rewritten (then resealed). */
static void set_root_doubles(const char *path, const char *name, const double *values,
                             int reseal)
{
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    hid_t attribute = H5Aopen(file, name, H5P_DEFAULT);
    CHECK(H5Awrite(attribute, H5T_NATIVE_DOUBLE, values) >= 0, "cannot edit %s", name);
    H5Aclose(attribute);
    H5Fclose(file);
    if (reseal)
        reseal_file(path);
}

static void expect_loads(const char *path)
{
    mps2p_solver *solver = NULL;
    int status = mps2p_solver_load_checkpoint(path, &solver);
    CHECK(status == MPS2P_OK, "%s: %s", path, mps2p_last_error());
    if (status == MPS2P_OK)
        MUST(mps2p_solver_step(solver));
    mps2p_solver_destroy(solver);
}

/* 0 when loading the image is refused with MPS2P_ERR_IO and a message
 * holding fragment (NULL: any), -1 otherwise. */
static int image_refused(const char *path, const unsigned char *p, size_t n,
                         const char *fragment)
{
    write_whole(path, p, n);
    mps2p_solver *solver = NULL;
    int status = mps2p_solver_load_checkpoint(path, &solver);
    int refused = status == MPS2P_ERR_IO && solver == NULL &&
                  (!fragment || strstr(mps2p_last_error(), fragment));
    if (!refused)
        fprintf(stderr, "  not refused as \"%s\": %s: %s\n", fragment ? fragment : "",
                mps2p_status_string(status), mps2p_last_error());
    mps2p_solver_destroy(solver);
    return refused ? 0 : -1;
}

/* Damage (issue 20, defect 7): any change to a format 4 file's bytes is
 * refused before HDF5 parses it. On format 3, byte 4999 set to 0x14 gave a
 * heap-buffer-overflow inside HDF5 (H5Aexists), 6 of 440 random flips of 1
 * to 64 bytes crashed, one made HDF5 allocate 455 GB, and others loaded
 * silently changed values. */
static void damage_is_refused(const char *dir, const char *good)
{
    char path[256];
    snprintf(path, sizeof path, "%s/damaged.chk", dir);
    size_t n = 0;
    unsigned char *original = read_whole(good, &n), *p = malloc(n);
    CHECK(original && p && n > 5000 && seal_has_header(original, n), "%s: %zu bytes", good, n);
    if (!original || !p || n <= 5000) {
        free(original);
        free(p);
        return;
    }
    memcpy(p, original, n);
    CHECK(reseal_bytes(p, n) && memcmp(p, original, n) == 0,
          "the library's checksum is not the documented CRC-64/XZ");
    p[4999] = original[4999] == 0x14 ? 0x15 : 0x14;
    CHECK(image_refused(path, p, n, "damaged: its checksum does not match") == 0, "byte 4999");
    /* 440 random changes of 1 to 64 bytes in a row, anywhere */
    uint64_t seed = 20;
    int refused = 0, tries = 440;
    for (int k = 0; k < tries; k++) {
        memcpy(p, original, n);
        seed = seed * 6364136223846793005u + 1442695040888963407u;
        size_t length = 1 + (size_t)(seed >> 33) % 64;
        seed = seed * 6364136223846793005u + 1442695040888963407u;
        size_t at = (size_t)(seed >> 33) % (n - length + 1);
        for (size_t i = 0; i < length; i++) {
            seed = seed * 6364136223846793005u + 1442695040888963407u;
            p[at + i] ^= (unsigned char)(1 + (seed >> 33) % 255); /* never 0: a change */
        }
        refused += image_refused(path, p, n, NULL) == 0;
    }
    CHECK(refused == tries, "%d of %d damaged files refused", refused, tries);
    printf("damage: %d of %d random changes refused\n", refused, tries);
    /* cut short, or grown */
    const size_t cuts[] = {0, 7, 8, 511, 512, n / 2, n - 1};
    for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; k++)
        CHECK(image_refused(path, original, cuts[k], NULL) == 0, "cut to %zu bytes", cuts[k]);
    unsigned char *longer = malloc(n + 1);
    memcpy(longer, original, n);
    longer[n] = 0;
    CHECK(image_refused(path, longer, n + 1, "appended to") == 0, "one byte appended");
    free(longer);
    /* an edit through HDF5 without a fresh checksum */
    write_whole(path, original, n);
    double minus_one = -1.0;
    set_root_doubles(path, "time", &minus_one, 0);
    expect_refused(path, "damaged");
    remove(path);
    free(original);
    free(p);
}

static void on_alarm(int signal)
{
    (void)signal;
    static const char text[] = "FAIL: loading a FIFO blocked\n";
    if (write(2, text, sizeof text - 1) < 0)
        _exit(2);
    _exit(1);
}

/* A FIFO blocked the loader forever; it and a directory are refused at once. */
static void not_regular_files_refused(const char *dir)
{
    char fifo[256];
    snprintf(fifo, sizeof fifo, "%s/fifo.chk", dir);
    CHECK(mkfifo(fifo, 0600) == 0, "mkfifo %s", fifo);
    signal(SIGALRM, on_alarm);
    alarm(20);
    expect_refused(fifo, "not a regular file (a FIFO)");
    alarm(0);
    remove(fifo);
    expect_refused(dir, "not a regular file (a directory)");
}

/* Saving writes a temporary file and renames it over the path: over a FIFO
 * or a device that put a regular file in its place (as root, saving to
 * /dev/null replaced the system's /dev/null). Such paths are refused; a
 * symbolic link keeps being a link, its target replaced. */
static void saving_over_what_is_not_a_file(const char *dir, const mps2p_solver *solver)
{
    char fifo[256], link[256], target[256];
    struct stat seen;
    snprintf(fifo, sizeof fifo, "%s/save-fifo.chk", dir);
    CHECK(mkfifo(fifo, 0600) == 0, "mkfifo %s", fifo);
    int status = mps2p_solver_save_checkpoint(solver, fifo);
    CHECK(status == MPS2P_ERR_IO && strstr(mps2p_last_error(), "not a regular file (a FIFO)"),
          "saving over a FIFO: %s, %s", mps2p_status_string(status), mps2p_last_error());
    CHECK(lstat(fifo, &seen) == 0 && S_ISFIFO(seen.st_mode), "the FIFO was replaced");
    remove(fifo);
    status = mps2p_solver_save_checkpoint(solver, dir);
    CHECK(status == MPS2P_ERR_IO && strstr(mps2p_last_error(), "a directory"),
          "saving over a directory: %s, %s", mps2p_status_string(status), mps2p_last_error());
    snprintf(target, sizeof target, "%s/save-target.chk", dir);
    snprintf(link, sizeof link, "%s/save-link.chk", dir);
    FILE *f = fopen(target, "w");
    CHECK(f && fputs("old", f) >= 0 && fclose(f) == 0, "cannot write %s", target);
    CHECK(symlink(target, link) == 0, "symlink %s", link);
    MUST(mps2p_solver_save_checkpoint(solver, link));
    CHECK(lstat(link, &seen) == 0 && S_ISLNK(seen.st_mode), "the link was replaced by a file");
    mps2p_solver *loaded = NULL;
    MUST(mps2p_solver_load_checkpoint(target, &loaded));
    mps2p_solver_destroy(loaded);
    remove(target); /* the link now dangles: refused, nothing created */
    status = mps2p_solver_save_checkpoint(solver, link);
    CHECK(status == MPS2P_ERR_IO && strstr(mps2p_last_error(), "symbolic link"),
          "saving through a dangling link: %s, %s", mps2p_status_string(status),
          mps2p_last_error());
    CHECK(lstat(target, &seen) != 0, "saving through a dangling link created its target");
    remove(link);
    /* a folder that is not there: HDF5's reason is passed on (it was "HDF5 gave
     * no reason": a property list closed before the error was read cleared it) */
    snprintf(target, sizeof target, "%s/no-such-folder/x.chk", dir);
    status = mps2p_solver_save_checkpoint(solver, target);
    CHECK(status == MPS2P_ERR_IO && strstr(mps2p_last_error(), "No such file or directory"),
          "saving into a missing folder: %s, %s", mps2p_status_string(status),
          mps2p_last_error());
}

static herr_t copy_attribute(hid_t from, const char *name, const H5A_info_t *info, void *to)
{
    (void)info;
    hid_t a = H5Aopen(from, name, H5P_DEFAULT), type = H5Aget_type(a), space = H5Aget_space(a);
    size_t bytes = H5Tget_size(type) * (size_t)H5Sget_simple_extent_npoints(space);
    void *value = malloc(bytes);
    hid_t b = H5Acreate2(*(hid_t *)to, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    herr_t status = H5Aread(a, type, value) >= 0 && H5Awrite(b, type, value) >= 0 ? 0 : -1;
    free(value);
    H5Aclose(b);
    H5Sclose(space);
    H5Tclose(type);
    H5Aclose(a);
    return status;
}

static herr_t copy_link(hid_t from, const char *name, const H5L_info_t *info, void *to)
{
    (void)info;
    return H5Ocopy(from, name, *(hid_t *)to, name, H5P_DEFAULT, H5P_DEFAULT) >= 0 ? 0 : -1;
}

/* Files of format 3 and older have no checksum header: they still load,
 * unchecked, as before; one claiming format 4 without the header is damaged. */
static void unsealed_files(const char *dir, const char *good)
{
    char path[256];
    snprintf(path, sizeof path, "%s/format3.chk", dir);
    hid_t from = H5Fopen(good, H5F_ACC_RDONLY, H5P_DEFAULT);
    hid_t to = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    CHECK(H5Aiterate2(from, H5_INDEX_NAME, H5_ITER_INC, NULL, copy_attribute, &to) >= 0 &&
          H5Literate(from, H5_INDEX_NAME, H5_ITER_INC, NULL, copy_link, &to) >= 0,
          "cannot copy %s", good);
    H5Fclose(from);
    H5Fclose(to);
    set_format_version(path, 3);
    expect_loads(path);
    set_format_version(path, 4);
    expect_refused(path, "format version 4 has a checksum header, this file has none");
    remove(path);
}

/* Contents mps2p_solver_create would refuse, behind a valid checksum (a
 * crafted file): each refused, naming the field. */
static void bad_contents_refused(const char *dir, const char *good)
{
    char path[256];
    snprintf(path, sizeof path, "%s/contents.chk", dir);
    const double minus_one = -1.0, huge = 1e300;
    copy_prefix(good, path, 1.0);
    set_root_doubles(path, "time", &minus_one, 1);
    expect_refused(path, "attribute time is -1");
    copy_prefix(good, path, 1.0);
    set_root_doubles(path, "l0", &huge, 1);
    expect_refused(path, "l0 = 1e+300");
    copy_prefix(good, path, 1.0);
    fill_dataset(path, "/particles/number_density", -1.0);
    expect_refused(path, "number_density of particle 0 is -1");
    copy_prefix(good, path, 1.0);
    const double small[4] = {0.0, 0.0, 0.05, 0.05}; /* smaller than the particles */
    set_root_doubles(path, "domain", small, 1);
    expect_refused(path, "outside attribute domain");
    copy_prefix(good, path, 1.0);
    fill_dataset(path, "/particles/density", 2000.0);
    expect_refused(path, "density or viscosity of particle 0");
    copy_prefix(good, path, 1.0);
    fill_dataset(path, "/particles/position", 5.0); /* all on one point, outside */
    expect_refused(path, "outside attribute domain");
    copy_prefix(good, path, 1.0);
    /* deleted and written again: HDF5 1.10 cannot rewrite an attribute in
     * dense storage (a group of many attributes) in place */
    hid_t file = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    hid_t group = H5Gopen2(file, "parameters", H5P_DEFAULT);
    hid_t space = H5Screate(H5S_SCALAR);
    H5Adelete(group, "memory_limit");
    hid_t attribute = H5Acreate2(group, "memory_limit", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT,
                                 H5P_DEFAULT);
    const double tiny = 1000.0;
    CHECK(H5Awrite(attribute, H5T_NATIVE_DOUBLE, &tiny) >= 0, "cannot set memory_limit");
    H5Aclose(attribute);
    H5Sclose(space);
    H5Gclose(group);
    H5Fclose(file);
    reseal_file(path);
    mps2p_solver *solver = NULL;
    int status = mps2p_solver_load_checkpoint(path, &solver);
    CHECK(status == MPS2P_ERR_NOMEM && solver == NULL &&
              strstr(mps2p_last_error(), "memory limit of 1e+03 bytes") &&
              strstr(mps2p_last_error(), path),
          "a checkpoint beyond its memory_limit: %s: %s", mps2p_status_string(status),
          mps2p_last_error());
    remove(path);
}

/* Format 3: group two_phase, written by a two-phase solver, must be there,
 * whole and in range exactly when the fluids and parameters make two
 * phases; anything else is refused, never half loaded. (Restarts are
 * bitwise: test_two_phase_restart.) */
static void two_phase_files(const char *dir, const char *single_phase)
{
    char path[256], other[256];
    snprintf(path, sizeof path, "%s/two-phase.chk", dir);
    snprintf(other, sizeof other, "%s/damaged.chk", dir);
    mps2p_scene *scene = water_air_column_scene(0.05, NULL);
    mps2p_solver *solver, *loaded = NULL;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    for (int k = 0; k < 3; k++)
        MUST(mps2p_solver_step(solver));
    MUST(mps2p_solver_save_checkpoint(solver, path));
    mps2p_solver_destroy(solver);
    MUST(mps2p_solver_load_checkpoint(path, &loaded));
    double active = 0.0;
    MUST(mps2p_solver_get_stat(loaded, "two_phase_active", &active));
    CHECK(active == 1.0, "a two-phase checkpoint loaded as one phase");
    MUST(mps2p_solver_step(loaded));
    mps2p_solver_destroy(loaded);

    const struct { const char *edit, *fragment; } damage[] = {
        {"/two_phase", "has no group two_phase"},
        {"/two_phase/join_weight", "dataset join_weight is missing"},
        {"/two_phase/gas_pressure", "dataset gas_pressure is missing"},
    };
    for (size_t k = 0; k < sizeof damage / sizeof damage[0]; k++) {
        copy_prefix(path, other, 1.0);
        delete_link(other, damage[k].edit);
        expect_refused(other, damage[k].fragment);
    }
    copy_prefix(path, other, 1.0);
    delete_link(other, "/two_phase");
    set_format_version(other, 2);
    expect_refused(other, "format version 2 cannot hold");
    copy_prefix(path, other, 1.0);
    shorten_dataset(other, "/two_phase/heavy_pressure");
    expect_refused(other, "dataset heavy_pressure has shape (3)");
    copy_prefix(path, other, 1.0);
    fill_dataset(other, "/two_phase/join_weight", 2.0);
    expect_refused(other, "two-phase state of particle 0 is inconsistent");
    copy_prefix(path, other, 1.0);
    fill_dataset(other, "/two_phase/joined", 1.0); /* liquid particles too */
    expect_refused(other, "is inconsistent (not light");
    copy_prefix(path, other, 1.0);
    fill_dataset(other, "/two_phase/heavy_n_initial", NAN);
    expect_refused(other, "is inconsistent");
    copy_prefix(path, other, 1.0);
    hid_t file = H5Fopen(other, H5F_ACC_RDWR, H5P_DEFAULT);
    CHECK(H5Adelete_by_name(file, "two_phase", "have_initial", H5P_DEFAULT) >= 0,
          "cannot delete have_initial");
    H5Fclose(file);
    reseal_file(other);
    expect_refused(other, "attribute have_initial is missing");

    /* a single-phase solver's file with a two-phase group */
    copy_prefix(single_phase, other, 1.0);
    file = H5Fopen(other, H5F_ACC_RDWR, H5P_DEFAULT);
    hid_t group = H5Gcreate2(file, "two_phase", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    CHECK(group >= 0, "cannot add a group to %s", other);
    H5Gclose(group);
    H5Fclose(file);
    reseal_file(other);
    expect_refused(other, "make a single-phase solver");
    remove(path);
    remove(other);
}

int main(void)
{
    char dir[] = "/tmp/mps2p-checkpoint-XXXXXX";
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    char path[256], other[256], text[256], missing[256], temporary[300];
    snprintf(path, sizeof path, "%s/run.chk", dir);
    snprintf(temporary, sizeof temporary, "%s.tmp", path);

    restart_is_bitwise("cholmod", path);
    CHECK(access(temporary, F_OK) != 0, "the temporary %s was left behind", temporary);
    restart_is_bitwise("cg", path);
    driven_restart_is_bitwise(path);

    /* refusals */
    snprintf(missing, sizeof missing, "%s/no-such-file.chk", dir);
    expect_refused(missing, "cannot open");
    snprintf(text, sizeof text, "%s/text.chk", dir);
    FILE *f = fopen(text, "w");
    fputs("not a checkpoint\n", f);
    fclose(f);
    expect_refused(text, "not an HDF5 file");

    mps2p_scene *scene = dam_break_scene(0.02);
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    snprintf(other, sizeof other, "%s/results.h5", dir);
    mps2p_results *results;
    MUST(mps2p_results_create(other, solver, NULL, &results));
    MUST(mps2p_results_close(results));
    expect_refused(other, "not a libmps2p checkpoint");

    snprintf(other, sizeof other, "%s/newer.chk", dir);
    MUST(mps2p_solver_save_checkpoint(solver, other));
    set_format_version(other, 5);
    expect_refused(other, "format version 5 is newer");

    /* a version 1 file (no bodies, no inputs) loads with every solid in body 0 */
    snprintf(other, sizeof other, "%s/version1.chk", dir);
    MUST(mps2p_solver_save_checkpoint(solver, other));
    hid_t file = H5Fopen(other, H5F_ACC_RDWR, H5P_DEFAULT);
    CHECK(H5Ldelete(file, "bodies", H5P_DEFAULT) >= 0, "cannot delete /bodies");
    H5Fclose(file);
    set_format_version(other, 1); /* and resealed */
    mps2p_solver *old = NULL;
    int old_bodies = 0;
    MUST(mps2p_solver_load_checkpoint(other, &old));
    MUST(mps2p_solver_body_count(old, &old_bodies));
    CHECK(old_bodies == 1, "a version 1 file gave %d bodies", old_bodies);
    MUST(mps2p_solver_step(old));
    mps2p_solver_destroy(old);

    /* a file from before surface_pressure loads with p = 0 held at the free
     * surface's centres, as such files ran: after a step its free-surface
     * fluid (n* < beta n0) is at zero where a file of today's default gives
     * it a pressure (a clamped negative solve elsewhere is 0 in both) */
    char legacy[300], current[300];
    snprintf(legacy, sizeof legacy, "%s/no_surface_pressure.chk", dir);
    MUST(mps2p_solver_save_checkpoint(solver, legacy));
    snprintf(current, sizeof current, "%s/surface_pressure.chk", dir);
    MUST(mps2p_solver_save_checkpoint(solver, current));
    file = H5Fopen(legacy, H5F_ACC_RDWR, H5P_DEFAULT);
    hid_t parameters = H5Gopen2(file, "parameters", H5P_DEFAULT);
    CHECK(H5Adelete(parameters, "surface_pressure") >= 0, "cannot delete surface_pressure");
    H5Gclose(parameters);
    H5Fclose(file);
    reseal_file(legacy);
    size_t zeros[2] = {0, 0}, surface[2] = {0, 0};
    const char *files[2] = {legacy, current};
    for (int k = 0; k < 2; k++) {
        mps2p_solver *loaded = NULL;
        MUST(mps2p_solver_load_checkpoint(files[k], &loaded));
        MUST(mps2p_solver_step(loaded));
        size_t n = 0;
        MUST(mps2p_solver_particle_count(loaded, &n));
        double *p = malloc(n * sizeof *p), *density = malloc(n * sizeof *density);
        int *kinds = malloc(n * sizeof *kinds);
        double n0 = 0.0;
        const double beta = 0.97; /* the scene's, the default */
        MUST(mps2p_solver_get_pressure(loaded, p, n));
        MUST(mps2p_solver_get_number_density(loaded, density, n));
        MUST(mps2p_solver_get_kinds(loaded, kinds, n));
        MUST(mps2p_solver_get_stat(loaded, "n0", &n0));
        for (size_t i = 0; i < n; i++) {
            int at_surface = kinds[i] == MPS2P_KIND_FLUID && density[i] < beta * n0;
            surface[k] += at_surface;
            zeros[k] += at_surface && p[i] == 0.0;
        }
        free(p);
        free(density);
        free(kinds);
        mps2p_solver_destroy(loaded);
    }
    printf("free-surface fluid at p = 0 after a step: %zu of %zu from a file without "
           "surface_pressure, %zu of %zu with\n", zeros[0], surface[0], zeros[1], surface[1]);
    CHECK(surface[0] >= 10 && zeros[0] == surface[0] && zeros[1] < surface[1] / 2,
          "a file without surface_pressure: %zu of %zu free-surface particles at p = 0, %zu of "
          "%zu with it", zeros[0], surface[0], zeros[1], surface[1]);
    remove(legacy);
    remove(current);

    /* version 2 without its bodies */
    set_format_version(other, 2);
    expect_refused(other, "bodies");

    snprintf(other, sizeof other, "%s/shape.chk", dir);
    MUST(mps2p_solver_save_checkpoint(solver, other));
    shorten_dataset(other, "/particles/pressure");
    expect_refused(other, "dataset pressure has shape (3)");

    two_phase_files(dir, path);
    damage_is_refused(dir, path);
    not_regular_files_refused(dir);
    unsealed_files(dir, path);
    bad_contents_refused(dir, path);

    snprintf(other, sizeof other, "%s/half.chk", dir);
    copy_prefix(path, other, 0.5);
    expect_refused(other, "cannot open");

    /* arguments */
    mps2p_solver *none;
    CHECK(mps2p_solver_save_checkpoint(NULL, path) == MPS2P_ERR_NULL, "NULL solver");
    CHECK(mps2p_solver_save_checkpoint(solver, NULL) == MPS2P_ERR_NULL, "NULL path");
    CHECK(mps2p_solver_save_checkpoint(solver, "") == MPS2P_ERR_INVALID, "empty path");
    CHECK(mps2p_solver_load_checkpoint(NULL, &none) == MPS2P_ERR_NULL, "NULL path");
    CHECK(mps2p_solver_load_checkpoint(path, NULL) == MPS2P_ERR_NULL, "NULL output");
    snprintf(other, sizeof other, "%s/no-such-dir/run.chk", dir);
    int status = mps2p_solver_save_checkpoint(solver, other);
    CHECK(status == MPS2P_ERR_IO && strstr(mps2p_last_error(), other),
          "saving into a missing directory: %s, %s", mps2p_status_string(status),
          mps2p_last_error());
    saving_over_what_is_not_a_file(dir, solver);
    mps2p_solver_destroy(solver);

    const char *names[] = {"run.chk", "text.chk", "results.h5", "results.xdmf", "newer.chk",
                           "shape.chk", "half.chk", "version1.chk"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        snprintf(other, sizeof other, "%s/%s", dir, names[i]);
        remove(other);
    }
    CHECK(rmdir(dir) == 0, "%s is not empty: something left a file behind", dir);
    return check_summary("test_checkpoint");
}
