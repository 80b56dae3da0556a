/* A run that blows up says so, where and when, and keeps its last good state. */
#include <string.h>
#include "scenes.h"

int main(void)
{
    /* 1. a block of water falling out of a tight domain */
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(0.01, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 0.0, &water));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.1, 0.1));
    MUST(mps2p_scene_set_domain(scene, -0.01, -0.02, 0.11, 0.11));
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    size_t n;
    MUST(mps2p_solver_particle_count(solver, &n));
    double *before = malloc(2 * n * sizeof *before), *after = malloc(2 * n * sizeof *after);
    int status = MPS2P_OK;
    double t_before = 0.0;
    for (int k = 0; k < 10000 && status == MPS2P_OK; k++) {
        MUST(mps2p_solver_get_positions(solver, before, 2 * n));
        MUST(mps2p_solver_get_time(solver, &t_before));
        status = mps2p_solver_step(solver);
    }
    const char *message = mps2p_solver_last_error(solver);
    printf("message: %s\n", message);
    CHECK(status == MPS2P_ERR_DIVERGED, "got %s", mps2p_status_string(status));
    CHECK(strstr(message, "left the domain") && strstr(message, "particle") &&
              strstr(message, "water") && strstr(message, "t = "),
          "message does not say what, where and when: %s", message);
    double t_after;
    MUST(mps2p_solver_get_positions(solver, after, 2 * n));
    MUST(mps2p_solver_get_time(solver, &t_after));
    CHECK(memcmp(before, after, 2 * n * sizeof *before) == 0,
          "positions changed by the failed step");
    CHECK(t_after == t_before, "time moved from %g to %g", t_before, t_after);
    status = mps2p_solver_step(solver);
    CHECK(status == MPS2P_ERR_STATE, "stepping a diverged solver gave %s",
          mps2p_status_string(status));
    CHECK(strstr(mps2p_solver_last_error(solver), "diverged at t = "), "message: %s",
          mps2p_solver_last_error(solver));
    mps2p_solver_destroy(solver);
    free(before);
    free(after);

    /* 2. a pressure spike beyond the bound */
    scene = tank_scene(0.01, 0.1, 0.1);
    MUST(mps2p_scene_set_param(scene, "pressure_limit", 50.0));
    MUST(mps2p_solver_create(scene, &solver));
    status = mps2p_solver_advance_to(solver, 0.1, NULL, NULL);
    CHECK(status == MPS2P_ERR_DIVERGED, "got %s", mps2p_status_string(status));
    CHECK(strstr(mps2p_solver_last_error(solver), "beyond the limit 50 Pa"), "message: %s",
          mps2p_solver_last_error(solver));
    mps2p_solver_destroy(solver);
    mps2p_scene_destroy(scene);
    return check_summary("test_divergence");
}
