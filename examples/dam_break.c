/* Water-only dam break (Martin & Moyce's n^2 = 2 column, the paper's case
 * without air) from C: builds the scene, runs it, prints the surge front.
 *
 *   dam_break [l0 [end_time [results.h5]]]
 *
 * Prints t, T = t sqrt(2g/a), Z = z/a and the step count every 0.01 s of
 * simulated time, where z is the front on the floor (mps2p_solver_front: the
 * rightmost water particle lower than 2 l0, plus l0/2) and a = 0.15 m. With a
 * results path, also writes an HDF5 results file (snapshots every 0.1 s, the
 * front as a series) with its XDMF sidecar. The same scene is
 * examples/scenes/dam_break.toml; tests/python/test_c_python.py checks that
 * both paths build the same particles and give the same front. */
#include <mps2p.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define WIDTH 0.15  /* column width a (m) */
#define HEIGHT 0.30 /* column height 2a (m) */
#define TANK 0.60   /* tank width (m) */

static void check(int status, const char *what)
{
    if (status < 0) {
        fprintf(stderr, "%s: %s: %s\n", what, mps2p_status_string(status), mps2p_last_error());
        exit(1);
    }
}

int main(int argc, char **argv)
{
    double l0 = argc > 1 ? atof(argv[1]) : 0.01;
    double end = argc > 2 ? atof(argv[2]) : 0.3;
    const char *results_path = argc > 3 ? argv[3] : NULL;

    mps2p_scene *scene;
    int water;
    check(mps2p_scene_create(l0, &scene), "scene");
    check(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water), "fluid");
    check(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, WIDTH, HEIGHT), "water column");
    check(mps2p_scene_add_tank(scene, 0.0, 0.0, TANK, 0.7, 1), "tank");
    mps2p_solver *solver;
    check(mps2p_solver_create(scene, &solver), "solver");
    mps2p_scene_destroy(scene);

    mps2p_results *results = NULL;
    if (results_path) {
        check(mps2p_results_create(results_path, solver, NULL, &results), "results file");
        check(mps2p_results_write_snapshot(results, solver), "snapshot");
    }
    const double scale = sqrt(2.0 * 9.81 / WIDTH);
    int status = MPS2P_OK;
    printf("# t(s) T Z steps\n");
    for (int k = 1; k * 0.01 <= end + 1e-9 && status == MPS2P_OK; k++) {
        status = mps2p_solver_advance_to(solver, k * 0.01, NULL, NULL);
        if (status < 0) {
            fprintf(stderr, "%s\n", mps2p_solver_last_error(solver));
            break;
        }
        uint64_t steps;
        double t, z;
        check(mps2p_solver_get_step_count(solver, &steps), "steps");
        check(mps2p_solver_get_time(solver, &t), "time");
        check(mps2p_solver_front(solver, water, 2.0 * l0, &z), "front");
        printf("%.3f %.4f %.4f %llu\n", t, t * scale, z / WIDTH, (unsigned long long)steps);
        if (results) {
            check(mps2p_results_append_series(results, "front", t, z), "series");
            if (k % 10 == 0)
                check(mps2p_results_write_snapshot(results, solver), "snapshot");
        }
    }
    check(mps2p_results_close(results), "closing the results file");
    mps2p_solver_destroy(solver);
    return status < 0 ? 1 : 0;
}
