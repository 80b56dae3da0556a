/* No global state: two solvers stepping in two threads give bitwise the same
 * results as the same two run one after the other; repeated runs agree; two
 * threads writing results files and checkpoints at once do not interfere. */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <string.h>
#include <unistd.h>
#include "scenes.h"

typedef struct job {
    mps2p_scene *scene;
    int steps;
    double *positions;
    double *pressure;
    size_t n;
    int status;
} job;

static void *run(void *arg)
{
    job *j = arg;
    mps2p_solver *solver;
    j->status = mps2p_solver_create(j->scene, &solver);
    if (j->status != MPS2P_OK)
        return NULL;
    for (int k = 0; k < j->steps && j->status == MPS2P_OK; k++)
        j->status = mps2p_solver_step(solver);
    mps2p_solver_particle_count(solver, &j->n);
    j->positions = malloc(2 * j->n * sizeof *j->positions);
    j->pressure = malloc(j->n * sizeof *j->pressure);
    mps2p_solver_get_positions(solver, j->positions, 2 * j->n);
    mps2p_solver_get_pressure(solver, j->pressure, j->n);
    mps2p_solver_destroy(solver);
    return NULL;
}

static int same(const job *a, const job *b)
{
    return a->n == b->n && !memcmp(a->positions, b->positions, 2 * a->n * sizeof(double)) &&
           !memcmp(a->pressure, b->pressure, a->n * sizeof(double));
}

/* Each thread: a results file with snapshots and a series, a checkpoint,
 * and a restored solver that must equal the saved one. */
typedef struct file_job {
    mps2p_scene *scene;
    char results[256], checkpoint[256];
    int status, same;
    char message[512];
} file_job;

static void *write_files(void *arg)
{
    file_job *j = arg;
    mps2p_solver *solver = NULL, *restored = NULL;
    mps2p_results *results = NULL;
    int status = mps2p_solver_create(j->scene, &solver);
    if (status == MPS2P_OK)
        status = mps2p_results_create(j->results, solver, "threads", &results);
    for (int k = 0; k < 20 && status == MPS2P_OK; k++) {
        status = mps2p_solver_step(solver);
        if (status == MPS2P_OK && k % 5 == 0)
            status = mps2p_results_write_snapshot(results, solver);
        if (status == MPS2P_OK)
            status = mps2p_results_append_series(results, "step", (double)k, (double)k);
    }
    if (status == MPS2P_OK)
        status = mps2p_solver_save_checkpoint(solver, j->checkpoint);
    if (status == MPS2P_OK)
        status = mps2p_solver_load_checkpoint(j->checkpoint, &restored);
    if (status != MPS2P_OK)
        snprintf(j->message, sizeof j->message, "%s", mps2p_last_error());
    int closed = mps2p_results_close(results);
    j->status = status != MPS2P_OK ? status : closed;
    if (status == MPS2P_OK) {
        size_t n;
        mps2p_solver_particle_count(solver, &n);
        double *a = malloc(2 * n * sizeof *a), *b = malloc(2 * n * sizeof *b);
        mps2p_solver_get_positions(solver, a, 2 * n);
        mps2p_solver_get_positions(restored, b, 2 * n);
        j->same = !memcmp(a, b, 2 * n * sizeof *a);
        free(a);
        free(b);
    }
    mps2p_solver_destroy(solver);
    mps2p_solver_destroy(restored);
    return NULL;
}

static void files_in_two_threads(mps2p_scene *a, mps2p_scene *b)
{
    char dir[] = "/tmp/mps2p-threads-XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(0, "mkdtemp failed");
        return;
    }
    file_job jobs[2] = {{a, "", "", 0, 0, ""}, {b, "", "", 0, 0, ""}};
    pthread_t threads[2];
    for (int i = 0; i < 2; i++) {
        snprintf(jobs[i].results, sizeof jobs[i].results, "%s/run%d.h5", dir, i);
        snprintf(jobs[i].checkpoint, sizeof jobs[i].checkpoint, "%s/run%d.chk", dir, i);
        CHECK(pthread_create(&threads[i], NULL, write_files, &jobs[i]) == 0, "thread %d", i);
    }
    for (int i = 0; i < 2; i++)
        pthread_join(threads[i], NULL);
    for (int i = 0; i < 2; i++) {
        CHECK(jobs[i].status == MPS2P_OK, "file thread %d: %s: %s", i,
              mps2p_status_string(jobs[i].status), jobs[i].message);
        CHECK(jobs[i].same, "file thread %d: restored positions differ", i);
        char xdmf[256];
        snprintf(xdmf, sizeof xdmf, "%s/run%d.xdmf", dir, i);
        remove(jobs[i].results);
        remove(jobs[i].checkpoint);
        remove(xdmf);
    }
    CHECK(rmdir(dir) == 0, "%s is not empty", dir);
}

int main(void)
{
    mps2p_scene *dam = dam_break_scene(0.01), *tank = tank_scene(0.01, 0.2, 0.15);
    MUST(mps2p_scene_set_option(tank, "pressure_solver", "cg"));
    job serial[2] = {{dam, 150, 0, 0, 0, 0}, {tank, 150, 0, 0, 0, 0}};
    job parallel[2] = {{dam, 150, 0, 0, 0, 0}, {tank, 150, 0, 0, 0, 0}};
    job again = {dam, 150, 0, 0, 0, 0};

    run(&serial[0]);
    run(&serial[1]);
    pthread_t threads[2];
    for (int i = 0; i < 2; i++)
        CHECK(pthread_create(&threads[i], NULL, run, &parallel[i]) == 0, "thread %d", i);
    for (int i = 0; i < 2; i++)
        pthread_join(threads[i], NULL);
    run(&again);

    for (int i = 0; i < 2; i++) {
        CHECK(serial[i].status == MPS2P_OK && parallel[i].status == MPS2P_OK,
              "run %d failed: %s / %s", i, mps2p_status_string(serial[i].status),
              mps2p_status_string(parallel[i].status));
        CHECK(same(&serial[i], &parallel[i]), "run %d differs between threads and serial", i);
    }
    CHECK(same(&serial[0], &again), "the same run twice gave different results");
    files_in_two_threads(dam, tank);
    for (int i = 0; i < 2; i++) {
        free(serial[i].positions);
        free(serial[i].pressure);
        free(parallel[i].positions);
        free(parallel[i].pressure);
    }
    free(again.positions);
    free(again.pressure);
    mps2p_scene_destroy(dam);
    mps2p_scene_destroy(tank);
    return check_summary("test_threads");
}
