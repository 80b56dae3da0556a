/* Hydrostatic tank: water 0.3 m deep at l0 = 0.01 m, walls on both sides and
 * below, run 2 s. The time-averaged pressure near the bottom must be within
 * 5 % of rho g depth, particles must stay put (RMS displacement < 0.1 l0), and
 * nothing may diverge.
 *
 * It runs the still-water scheme of docs/validation.md: the corrected gradient
 * (no repulsive background, so the square lattice does not shear), the
 * error-compensating source, and the collision model acting on every pair
 * closer than 0.995 l0 (it removes approach velocity only, a damper on the
 * odd-even row mode). Koshizuka's standard scheme fails this test; that is
 * measured and explained in the docs. With SCHEME=standard in the environment
 * the test runs the defaults instead, to show it. */
#include <mps2p.h>
#include "check.h"

#include <string.h>

#define L0 0.01
#define DEPTH 0.30
#define WIDTH 0.30
#define RHO 1000.0
#define G 9.81

int main(void)
{
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(L0, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", RHO, 1e-6, &water));
    const char *scheme = getenv("SCHEME");
    if (!scheme || strcmp(scheme, "standard") != 0) {
        MUST(mps2p_scene_set_option(scene, "pressure_gradient", "corrected"));
        MUST(mps2p_scene_set_option(scene, "ppe_source", "ecs"));
        MUST(mps2p_scene_set_param(scene, "collision_distance", 0.995));
    }
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, WIDTH, DEPTH));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, WIDTH, DEPTH + 0.1, 1));
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);

    size_t n;
    MUST(mps2p_solver_particle_count(solver, &n));
    double *initial = malloc(2 * n * sizeof *initial), *r = malloc(2 * n * sizeof *r);
    double *p = malloc(n * sizeof *p);
    int *kind = malloc(n * sizeof *kind);
    MUST(mps2p_solver_get_positions(solver, initial, 2 * n));
    MUST(mps2p_solver_get_kinds(solver, kind, n));

    /* probe: the fluid particles of the lowest row, 0.10 m to 0.20 m from the left wall */
    double sum_p = 0.0, sum_depth = 0.0;
    long samples = 0;
    for (int k = 1; k <= 200; k++) {
        int status = mps2p_solver_advance_to(solver, k * 0.01, NULL, NULL);
        CHECK(status == MPS2P_OK, "advance to %g s: %s", k * 0.01, mps2p_solver_last_error(solver));
        if (status != MPS2P_OK)
            return check_summary("test_hydrostatic");
        if (k <= 100)
            continue; /* average over the second second, after the start-up */
        MUST(mps2p_solver_get_positions(solver, r, 2 * n));
        MUST(mps2p_solver_get_pressure(solver, p, n));
        for (size_t i = 0; i < n; i++) {
            if (kind[i] != MPS2P_KIND_FLUID || r[2 * i + 1] > L0 ||
                r[2 * i] < 0.10 || r[2 * i] > 0.20)
                continue;
            sum_p += p[i];
            sum_depth += DEPTH - r[2 * i + 1];
            samples++;
        }
    }
    double mean_p = sum_p / samples, expected = RHO * G * sum_depth / samples;
    double error = (mean_p - expected) / expected;
    printf("probe near the bottom: mean p = %.1f Pa, rho g depth = %.1f Pa, error %+.2f %%\n",
           mean_p, expected, 100 * error);
    CHECK(samples > 0, "no particle in the probe region");
    CHECK(fabs(error) < 0.05, "pressure error %.2f %% beyond 5 %%", 100 * error);

    MUST(mps2p_solver_get_positions(solver, r, 2 * n));
    double sum2 = 0.0;
    size_t fluid = 0;
    for (size_t i = 0; i < n; i++) {
        if (kind[i] != MPS2P_KIND_FLUID)
            continue;
        double dx = r[2 * i] - initial[2 * i], dy = r[2 * i + 1] - initial[2 * i + 1];
        sum2 += dx * dx + dy * dy;
        fluid++;
    }
    double rms = sqrt(sum2 / fluid) / L0;
    double max_speed;
    MUST(mps2p_solver_get_stat(solver, "max_speed", &max_speed));
    printf("RMS displacement after 2 s: %.4f l0; max speed %.4f m/s\n", rms, max_speed);
    CHECK(rms < 0.1, "RMS displacement %.4f l0 is not below 0.1 l0", rms);

    free(initial);
    free(r);
    free(p);
    free(kind);
    mps2p_solver_destroy(solver);
    return check_summary("test_hydrostatic");
}
