/* No global state: two solvers stepping in two threads give bitwise the same
 * results as the same two run one after the other; repeated runs agree. */
#include <pthread.h>
#include <string.h>
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
