/* The conventional model (two_step, docs/method.md section 2) leaves the water
 * alone: the liquid PPE, viscosity and collisions ignore the air, so until
 * the air diverges the water is bit for bit the water-only run of the same
 * tank (docs/two-phase.md). Guards the two-phase stages' masks. */
#include <string.h>
#include <mps2p.h>
#include "check.h"

#define WATER_PARTICLES 450 /* 0.15 m x 0.30 m at l0 = 0.01, added first */

static mps2p_solver *make(int with_air)
{
    mps2p_scene *scene;
    int water, air;
    MUST(mps2p_scene_create(0.01, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_add_fluid(scene, "air", 1.2, 1.5e-5, &air));
    MUST(mps2p_scene_set_option(scene, "two_phase_model", "two_step"));
    MUST(mps2p_scene_set_option(scene, "pressure_solver", "cg"));
    MUST(mps2p_scene_set_param(scene, "dt", 2e-4));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.15, 0.30));
    if (with_air) {
        MUST(mps2p_scene_add_fluid_box(scene, air, 0.15, 0.0, 0.6, 0.7));
        MUST(mps2p_scene_add_fluid_box(scene, air, 0.0, 0.3, 0.15, 0.7));
    }
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.6, 0.8, 1));
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    return solver;
}

int main(void)
{
    mps2p_solver *with_air = make(1), *water_only = make(0);
    double active = 0.0;
    MUST(mps2p_solver_get_stat(with_air, "two_phase_active", &active));
    CHECK(active == 1.0, "air was not classified as a light fluid");
    /* 0.15 s: before any squeeze (the first ones came at 0.21-0.31 s) */
    MUST(mps2p_solver_advance_to(water_only, 0.15, NULL, NULL));
    MUST(mps2p_solver_advance_to(with_air, 0.15, NULL, NULL));
    size_t n_air, n_water;
    MUST(mps2p_solver_particle_count(with_air, &n_air));
    MUST(mps2p_solver_particle_count(water_only, &n_water));
    double *a = malloc(2 * n_air * sizeof *a), *b = malloc(2 * n_water * sizeof *b);
    MUST(mps2p_solver_get_positions(with_air, a, 2 * n_air));
    MUST(mps2p_solver_get_positions(water_only, b, 2 * n_water));
    CHECK(memcmp(a, b, 2 * WATER_PARTICLES * sizeof *a) == 0, "water positions differ");
    MUST(mps2p_solver_get_velocities(with_air, a, 2 * n_air));
    MUST(mps2p_solver_get_velocities(water_only, b, 2 * n_water));
    CHECK(memcmp(a, b, 2 * WATER_PARTICLES * sizeof *a) == 0, "water velocities differ");
    MUST(mps2p_solver_get_pressure(with_air, a, n_air));
    MUST(mps2p_solver_get_pressure(water_only, b, n_water));
    CHECK(memcmp(a, b, WATER_PARTICLES * sizeof *a) == 0, "water pressures differ");
    free(a);
    free(b);
    mps2p_solver_destroy(with_air);
    mps2p_solver_destroy(water_only);
    return check_summary("test_two_phase_water");
}
