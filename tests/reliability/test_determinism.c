/* Determinism: the same scene and parameters give bitwise identical results
 * on repeated runs, in one process and in fresh processes, and whatever
 * OMP_NUM_THREADS says (CHOLMOD links libgomp, and with parameter threads =
 * 0 libmps2p's own particle loops take OMP_NUM_THREADS threads; the test
 * shows the thread count does not reach the results). Runs a small dam break for
 * 60 steps with each pressure solver and compares positions, velocities,
 * pressure, time and step count byte for byte.
 *
 * "test_determinism --dump FILE" writes the runs' results to FILE (used for
 * the fresh processes, started with OMP_NUM_THREADS = 1, 2 and 4). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>
#include "../scenes.h"

#define STEPS 60

typedef struct result {
    size_t n;
    double *data; /* positions, velocities, pressure, time, step count */
    size_t length;
} result;

static result run(const char *pressure_solver)
{
    mps2p_scene *scene = dam_break_scene(0.02);
    MUST(mps2p_scene_set_option(scene, "pressure_solver", pressure_solver));
    MUST(mps2p_scene_set_param(scene, "threads", 0)); /* OpenMP's default */
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    for (int k = 0; k < STEPS; k++)
        MUST(mps2p_solver_step(solver));
    result r;
    MUST(mps2p_solver_particle_count(solver, &r.n));
    r.length = 5 * r.n + 2;
    r.data = malloc(r.length * sizeof *r.data);
    MUST(mps2p_solver_get_positions(solver, r.data, 2 * r.n));
    MUST(mps2p_solver_get_velocities(solver, r.data + 2 * r.n, 2 * r.n));
    MUST(mps2p_solver_get_pressure(solver, r.data + 4 * r.n, r.n));
    uint64_t steps;
    MUST(mps2p_solver_get_time(solver, &r.data[5 * r.n]));
    MUST(mps2p_solver_get_step_count(solver, &steps));
    r.data[5 * r.n + 1] = (double)steps;
    mps2p_solver_destroy(solver);
    return r;
}

static const char *solvers[] = {"cholmod", "cg"};

static int dump(const char *path)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return 1;
    for (int s = 0; s < 2; s++) {
        result r = run(solvers[s]);
        fwrite(&r.length, sizeof r.length, 1, f);
        fwrite(r.data, sizeof *r.data, r.length, f);
        free(r.data);
    }
    return fclose(f) != 0;
}

/* The dump of a fresh process with OMP_NUM_THREADS=threads. */
static result *fresh(const char *self, const char *dir, int threads)
{
    char path[300], value[16];
    snprintf(path, sizeof path, "%s/omp%d.bin", dir, threads);
    snprintf(value, sizeof value, "%d", threads);
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        setenv("OMP_NUM_THREADS", value, 1);
        execl(self, self, "--dump", path, (char *)NULL);
        _exit(127);
    }
    int wstatus = 0;
    waitpid(pid, &wstatus, 0);
    CHECK(WIFEXITED(wstatus) && WEXITSTATUS(wstatus) == 0, "dump with %d threads failed",
          threads);
    result *r = calloc(2, sizeof *r);
    FILE *f = fopen(path, "rb");
    for (int s = 0; f && s < 2; s++) {
        if (fread(&r[s].length, sizeof r[s].length, 1, f) != 1)
            break;
        r[s].data = malloc(r[s].length * sizeof *r[s].data);
        if (fread(r[s].data, sizeof *r[s].data, r[s].length, f) != r[s].length)
            r[s].length = 0;
    }
    if (f)
        fclose(f);
    remove(path);
    return r;
}

static int same(const result *a, const result *b)
{
    return a->length == b->length && a->data && b->data &&
           memcmp(a->data, b->data, a->length * sizeof *a->data) == 0;
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "--dump") == 0)
        return dump(argv[2]);
    char self[4096];
    ssize_t length = readlink("/proc/self/exe", self, sizeof self - 1);
    CHECK(length > 0, "cannot find my own executable");
    self[length > 0 ? length : 0] = '\0';
    char dir[] = "/tmp/mps2p-determinism-XXXXXX";
    CHECK(mkdtemp(dir) != NULL, "mkdtemp failed");

    result first[2], again[2];
    for (int s = 0; s < 2; s++) {
        first[s] = run(solvers[s]);
        again[s] = run(solvers[s]);
        CHECK(same(&first[s], &again[s]), "%s: two runs in one process differ", solvers[s]);
    }
    const int thread_counts[] = {1, 2, 4};
    for (int t = 0; t < 3; t++) {
        result *r = fresh(self, dir, thread_counts[t]);
        for (int s = 0; s < 2; s++) {
            CHECK(same(&first[s], &r[s]), "%s: a fresh process with OMP_NUM_THREADS=%d "
                  "differs from this one", solvers[s], thread_counts[t]);
            free(r[s].data);
        }
        free(r);
    }
    for (int s = 0; s < 2; s++) {
        free(first[s].data);
        free(again[s].data);
    }
    rmdir(dir);
    printf("test_determinism: %d steps, cholmod and cg: bitwise equal across runs and "
           "OMP_NUM_THREADS = 1, 2, 4\n", STEPS);
    return check_summary("test_determinism");
}
