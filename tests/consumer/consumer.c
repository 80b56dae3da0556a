/* An outside program: built against the installed header and library with
 * pkg-config, it runs the water-only dam break to t = 0.2 s. */
#include <mps2p.h>

#include <stdio.h>

int main(void)
{
    mps2p_scene *scene;
    mps2p_solver *solver;
    int water;
    if (mps2p_scene_create(0.01, &scene) || mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, &water) ||
        mps2p_scene_add_fluid_box(scene, water, 0, 0, 0.15, 0.3) ||
        mps2p_scene_add_tank(scene, 0, 0, 0.6, 0.7, 1) || mps2p_solver_create(scene, &solver)) {
        fprintf(stderr, "setup failed: %s\n", mps2p_last_error());
        return 1;
    }
    mps2p_scene_destroy(scene);
    if (mps2p_solver_advance_to(solver, 0.2, NULL, NULL) != MPS2P_OK) {
        fprintf(stderr, "run failed: %s\n", mps2p_solver_last_error(solver));
        return 1;
    }
    double max_speed;
    uint64_t steps;
    mps2p_solver_get_stat(solver, "max_speed", &max_speed);
    mps2p_solver_get_step_count(solver, &steps);
    printf("consumer: libmps2p %s, dam break to 0.2 s in %llu steps, max speed %.2f m/s\n",
           mps2p_version_string(), (unsigned long long)steps, max_speed);
    mps2p_solver_destroy(solver);
    return max_speed > 1.0 ? 0 : 1;
}
