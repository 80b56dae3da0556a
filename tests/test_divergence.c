/* A run that blows up says so, where and when, and keeps its last good state.
 * Fluid leaving the domain ends it beyond out_limit's share (a whole block
 * falling out at the default, any particle at 0); walls leaving it always. */
#include <string.h>
#include "scenes.h"

/* Steps until a step fails (at most max); its status. */
static int step_until_failure(mps2p_solver *solver, int max)
{
    int status = MPS2P_OK;
    for (int k = 0; k < max && status == MPS2P_OK; k++)
        status = mps2p_solver_step(solver);
    return status;
}

static size_t count_out(const mps2p_solver *solver)
{
    size_t n, out = 0;
    MUST(mps2p_solver_particle_count(solver, &n));
    int *kinds = malloc(n * sizeof *kinds);
    MUST(mps2p_solver_get_kinds(solver, kinds, n));
    for (size_t i = 0; i < n; i++)
        out += kinds[i] == MPS2P_KIND_OUT;
    free(kinds);
    return out;
}

/* out_limit 0: the first droplet of the spray to cross the domain's top ends
 * the run, as before out_limit; nothing is taken out of the run. */
static void no_fluid_may_leave(void)
{
    size_t a;
    mps2p_scene *scene = spray_scene(&a);
    MUST(mps2p_scene_set_param(scene, "out_limit", 0.0));
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    int status = step_until_failure(solver, 400);
    const char *message = mps2p_solver_last_error(solver);
    printf("message: %s\n", message);
    CHECK(status == MPS2P_ERR_DIVERGED, "out_limit 0: got %s", mps2p_status_string(status));
    CHECK(strstr(message, "particle") && strstr(message, "(water) left the domain") &&
              strstr(message, "out_limit 0"),
          "out_limit 0: message: %s", message);
    double particle, out;
    MUST(mps2p_solver_get_stat(solver, "diverged_particle", &particle));
    MUST(mps2p_solver_get_stat(solver, "fluid_out", &out));
    CHECK(particle == (double)a, "diverged at particle %g, the first droplet is %zu", particle, a);
    CHECK(out == 0.0 && count_out(solver) == 0, "out_limit 0 took %g (%zu) out of the run",
          out, count_out(solver));
    mps2p_solver_destroy(solver);
}

/* A wall body driven out of the domain diverges whatever out_limit. */
static void walls_may_not_leave(void)
{
    mps2p_scene *scene = tank_scene(0.01, 0.1, 0.1);
    int lid;
    MUST(mps2p_scene_add_body_box(scene, "lid", 0.02, 0.15, 0.08, 0.17, &lid));
    MUST(mps2p_scene_set_domain(scene, -0.1, -0.1, 0.2, 0.2));
    MUST(mps2p_scene_set_param(scene, "out_limit", 1.0));
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    const double up[2] = {0.0, 1.0};
    MUST(mps2p_solver_set_body_motion(solver, lid, up, 0.0, NULL));
    int status = step_until_failure(solver, 400);
    const char *message = mps2p_solver_last_error(solver);
    printf("message: %s\n", message);
    CHECK(status == MPS2P_ERR_DIVERGED && strstr(message, "(wall of body \"lid\") left the domain"),
          "a lid leaving the domain: %s: %s", mps2p_status_string(status), message);
    mps2p_solver_destroy(solver);
}

int main(void)
{
    /* 1. a block of water falling out of a tight domain: its bottom row of 10
     * leaves at once, more than out_limit's 1 % of 100 */
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
    CHECK(strstr(message, "with 10 leaving this step and 0 out before") &&
              strstr(message, "out_limit 0.01 of the 100 fluid particles"),
          "message does not say that out_limit was reached: %s", message);
    CHECK(count_out(solver) == 0, "the failed step left %zu particles out of the run",
          count_out(solver));
    double t_after;
    MUST(mps2p_solver_get_positions(solver, after, 2 * n));
    MUST(mps2p_solver_get_time(solver, &t_after));
    CHECK(memcmp(before, after, 2 * n * sizeof *before) == 0,
          "positions changed by the failed step");
    CHECK(t_after == t_before, "time moved from %g to %g", t_before, t_after);
    status = mps2p_solver_step(solver);
    CHECK(status == MPS2P_ERR_STATE, "stepping a diverged solver gave %s",
          mps2p_status_string(status));
    /* the same step and the kept state's time as the failure said */
    uint64_t steps = 0;
    MUST(mps2p_solver_get_step_count(solver, &steps));
    char said[160];
    snprintf(said, sizeof said, "diverged in step %llu, from its last good state at t = %.6g s",
             (unsigned long long)steps + 1, t_before);
    CHECK(strstr(mps2p_solver_last_error(solver), said), "message: %s (expected \"%s\")",
          mps2p_solver_last_error(solver), said);
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

    /* 3. out_limit 0, and walls */
    no_fluid_may_leave();
    walls_may_not_leave();
    return check_summary("test_divergence");
}
