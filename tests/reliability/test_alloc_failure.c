/* Allocation failure: with libfailmalloc.so preloaded (see failmalloc.c),
 * the n-th malloc/calloc/realloc inside a short run fails, for n = 1, 2, ...
 * up to the number of allocations the run makes. The run builds a scene,
 * creates a solver, steps it, writes a results file, a checkpoint, probes,
 * and loads the checkpoint back. Every call must return MPS2P_OK or
 * MPS2P_ERR_NOMEM (MPS2P_ERR_IO for a file call: HDF5 reports its own
 * allocation failures as I/O errors), never crash; a failed scene call adds
 * no particles; a failed save leaves no temporary file; and once disarmed
 * every handle still works: the solver steps on and lands bitwise where an
 * undisturbed solver with as many successful steps lands, the checkpoint
 * loads, everything is destroyed. Meson runs it with MALLOC_PERTURB_ set, so
 * that memory used after free or before being written holds garbage.
 *
 * Then the one allocation a caller can make absurdly large: a box of a
 * billion particles under an address-space limit must give MPS2P_ERR_NOMEM.
 *
 * MPS2P_FAIL_MALLOC_AT set in the environment runs that one n only (to
 * reproduce a failure); otherwise the program sets it for each n itself. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>
#include "../scenes.h"

static void (*arm)(void);
static long (*disarm)(void);
static int (*failed)(void);

#define STEPS 3
#define AFTER 2 /* steps taken once disarmed */

static char results_path[512], checkpoint_path[512], temporary_path[600];
static double *reference[STEPS + AFTER + 1];
static size_t reference_n;

typedef struct outcome {
    long allocations;
    int problems;
} outcome;

static int allowed(int status, int io)
{
    return status == MPS2P_OK || status == MPS2P_ERR_NOMEM || (io && status == MPS2P_ERR_IO);
}

#define EXPECT_ALLOWED(call, io)                                                        \
    do {                                                                                \
        int expect_ = (call);                                                           \
        if (!allowed(expect_, io) || (expect_ != MPS2P_OK && !failed()) ||              \
            (expect_ != MPS2P_OK && mps2p_last_error()[0] == '\0')) {                   \
            fprintf(stderr, "FAIL n=%ld: %s returned %s (allocation failed: %s): %s\n",  \
                    n, #call, mps2p_status_string(expect_), failed() ? "yes" : "no",    \
                    mps2p_last_error());                                                \
            out.problems++;                                                             \
        }                                                                               \
        status = expect_;                                                               \
    } while (0)

static int same_positions(mps2p_solver *solver, const double *expected)
{
    size_t n = 0;
    mps2p_solver_particle_count(solver, &n);
    if (n != reference_n)
        return 0;
    double *now = malloc(2 * n * sizeof *now);
    mps2p_solver_get_positions(solver, now, 2 * n);
    int same = memcmp(now, expected, 2 * n * sizeof *now) == 0;
    free(now);
    return same;
}

/* One run with the n-th allocation failing (n = 0: none fails). */
static outcome run(long n)
{
    outcome out = {0, 0};
    char text[32];
    snprintf(text, sizeof text, "%ld", n);
    setenv("MPS2P_FAIL_MALLOC_AT", text, 1);
    remove(checkpoint_path);
    mps2p_scene *scene = NULL;
    mps2p_solver *solver = NULL, *loaded = NULL;
    mps2p_results *results = NULL;
    int status, water = 0, ok_steps = 0, saved = 0, save_failed = 0;
    size_t before = 0, after = 0;
    double points[4] = {0.05, 0.01, 0.05, 0.2}, probe_p[2];

    arm();
    EXPECT_ALLOWED(mps2p_scene_create(0.01, &scene), 0);
    if (status == MPS2P_OK) {
        EXPECT_ALLOWED(mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, &water), 0);
        int building = status == MPS2P_OK;
        if (building) {
            mps2p_scene_particle_count(scene, &before);
            EXPECT_ALLOWED(mps2p_scene_add_fluid_box(scene, water, 0, 0, 0.1, 0.05), 0);
            mps2p_scene_particle_count(scene, &after);
            if (status != MPS2P_OK && after != before) {
                fprintf(stderr, "FAIL n=%ld: failed fluid box added %zu particles\n", n,
                        after - before);
                out.problems++;
            }
            building = status == MPS2P_OK;
        }
        if (building) {
            mps2p_scene_particle_count(scene, &before);
            EXPECT_ALLOWED(mps2p_scene_add_tank(scene, 0, 0, 0.1, 0.1, 1), 0);
            mps2p_scene_particle_count(scene, &after);
            if (status != MPS2P_OK && after != before) {
                fprintf(stderr, "FAIL n=%ld: failed tank added %zu particles\n", n,
                        after - before);
                out.problems++;
            }
            building = status == MPS2P_OK;
        }
        if (building)
            EXPECT_ALLOWED(mps2p_solver_create(scene, &solver), 0);
    }
    if (solver) {
        for (int k = 0; k < STEPS; k++) {
            EXPECT_ALLOWED(mps2p_solver_step(solver), 0);
            ok_steps += status == MPS2P_OK;
        }
        EXPECT_ALLOWED(mps2p_results_create(results_path, solver, "scene", &results), 1);
        if (status == MPS2P_OK) {
            EXPECT_ALLOWED(mps2p_results_write_snapshot(results, solver), 1);
            EXPECT_ALLOWED(mps2p_results_append_series(results, "front", 0.0, 1.0), 1);
            EXPECT_ALLOWED(mps2p_results_append_series(results, "front", 0.1, 2.0), 1);
            EXPECT_ALLOWED(mps2p_results_write_snapshot(results, solver), 1);
            EXPECT_ALLOWED(mps2p_results_close(results), 1);
            results = NULL;
        }
        EXPECT_ALLOWED(mps2p_solver_save_checkpoint(solver, checkpoint_path), 1);
        saved = status == MPS2P_OK;
        save_failed = !saved;
        EXPECT_ALLOWED(mps2p_solver_probe(solver, 2, points, probe_p, NULL, NULL), 0);
        if (saved) {
            EXPECT_ALLOWED(mps2p_solver_load_checkpoint(checkpoint_path, &loaded), 1);
            mps2p_solver_destroy(loaded);
            loaded = NULL;
        }
    }
    out.allocations = disarm();

    /* Disarmed: every handle must still work. */
    if (save_failed && access(temporary_path, F_OK) == 0) {
        fprintf(stderr, "FAIL n=%ld: a failed save left %s behind\n", n, temporary_path);
        out.problems++;
    }
    if (solver) {
        for (int k = 0; k < AFTER; k++) {
            int s = mps2p_solver_step(solver);
            if (s != MPS2P_OK) {
                fprintf(stderr, "FAIL n=%ld: disarmed step returned %s: %s\n", n,
                        mps2p_status_string(s), mps2p_last_error());
                out.problems++;
                break;
            }
        }
        if (reference[0] && !same_positions(solver, reference[ok_steps + AFTER])) {
            fprintf(stderr, "FAIL n=%ld: after %d good steps and %d more, positions differ "
                    "from an undisturbed run\n", n, ok_steps, AFTER);
            out.problems++;
        }
        if (saved) {
            int s = mps2p_solver_load_checkpoint(checkpoint_path, &loaded);
            if (s == MPS2P_OK)
                s = mps2p_solver_step(loaded);
            if (s != MPS2P_OK) {
                fprintf(stderr, "FAIL n=%ld: checkpoint saved under pressure does not load "
                        "and step: %s\n", n, mps2p_last_error());
                out.problems++;
            }
            mps2p_solver_destroy(loaded);
        }
    }
    if (scene) { /* a scene that refused a call is still a working scene */
        size_t count;
        if (mps2p_scene_particle_count(scene, &count) != MPS2P_OK ||
            mps2p_scene_add_wall_box(scene, 1.0, 1.0, 1.05, 1.05) != MPS2P_OK) {
            fprintf(stderr, "FAIL n=%ld: scene unusable after the failure: %s\n", n,
                    mps2p_last_error());
            out.problems++;
        }
    }
    mps2p_solver_destroy(solver);
    mps2p_scene_destroy(scene);
    return out;
}

static void make_reference(void)
{
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(0.01, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, &water));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0, 0, 0.1, 0.05));
    MUST(mps2p_scene_add_tank(scene, 0, 0, 0.1, 0.1, 1));
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    MUST(mps2p_solver_particle_count(solver, &reference_n));
    for (int k = 0; k <= STEPS + AFTER; k++) {
        if (k > 0)
            MUST(mps2p_solver_step(solver));
        reference[k] = malloc(2 * reference_n * sizeof(double));
        MUST(mps2p_solver_get_positions(solver, reference[k], 2 * reference_n));
    }
    mps2p_solver_destroy(solver);
    mps2p_scene_destroy(scene);
}

/* A box of a billion particles in 1 GiB more address space than we use. */
static void billion_particles(void)
{
    struct rlimit limit;
    FILE *status = fopen("/proc/self/status", "r");
    long vm_kb = 0;
    char line[256];
    while (status && fgets(line, sizeof line, status))
        if (sscanf(line, "VmSize: %ld kB", &vm_kb) == 1)
            break;
    if (status)
        fclose(status);
    CHECK(vm_kb > 0, "no VmSize in /proc/self/status");
    limit.rlim_cur = limit.rlim_max = (rlim_t)vm_kb * 1024 + (1ul << 30);
    CHECK(setrlimit(RLIMIT_AS, &limit) == 0, "setrlimit failed");
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(0.001, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, &water));
    int s = mps2p_scene_add_fluid_box(scene, water, 0, 0, 31.6, 31.6); /* 9.99e8 */
    CHECK(s == MPS2P_ERR_NOMEM, "a billion particles: %s (%s)", mps2p_status_string(s),
          mps2p_last_error());
    size_t count = 1;
    MUST(mps2p_scene_particle_count(scene, &count));
    CHECK(count == 0, "refused box left %zu particles", count);
    /* still usable */
    MUST(mps2p_scene_add_fluid_box(scene, water, 0, 0, 0.02, 0.02));
    mps2p_scene_destroy(scene);
    printf("test_alloc_failure: a billion particles: %s (%s)\n", mps2p_status_string(s),
           mps2p_last_error());
}

int main(void)
{
    /* the POSIX way to turn dlsym's void * into a function pointer */
    *(void **)&arm = dlsym(RTLD_DEFAULT, "failmalloc_arm");
    *(void **)&disarm = dlsym(RTLD_DEFAULT, "failmalloc_disarm");
    *(void **)&failed = dlsym(RTLD_DEFAULT, "failmalloc_failed");
    if (!arm || !disarm || !failed) {
        fprintf(stderr, "test_alloc_failure: run with LD_PRELOAD=libfailmalloc.so\n");
        return 77; /* skipped */
    }
    char dir[] = "/tmp/mps2p-nomem-XXXXXX";
    MUST(mkdtemp(dir) ? MPS2P_OK : MPS2P_ERR_IO);
    snprintf(results_path, sizeof results_path, "%s/run.h5", dir);
    snprintf(checkpoint_path, sizeof checkpoint_path, "%s/run.chk", dir);
    snprintf(temporary_path, sizeof temporary_path, "%s.tmp", checkpoint_path);

    const char *only = getenv("MPS2P_FAIL_MALLOC_AT");
    make_reference();
    outcome clean = run(0); /* also warms HDF5 and the thread-locals up */
    CHECK(clean.problems == 0, "the run fails with no allocation failing");
    long total = clean.allocations, first = 1, last = total, problems = 0, failures = 0;
    if (only && atol(only) > 0)
        first = last = atol(only);
    for (long n = first; n <= last; n++) {
        outcome o = run(n);
        problems += o.problems;
        failures += o.problems > 0;
        if (failures >= 20) {
            fprintf(stderr, "stopping after 20 failing n\n");
            break;
        }
    }
    CHECK(problems == 0, "%ld problem(s) in %ld failing runs", problems, failures);
    printf("test_alloc_failure: %ld allocations per run, runs with allocation n = %ld..%ld "
           "failing: %ld with problems\n", total, first, last, failures);
    billion_particles();
    for (int k = 0; k <= STEPS + AFTER; k++)
        free(reference[k]);
    char command[600];
    snprintf(command, sizeof command, "rm -rf '%s'", dir);
    if (system(command) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    return check_summary("test_alloc_failure");
}
