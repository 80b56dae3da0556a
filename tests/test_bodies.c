/* Wall bodies: the force of still water on a tank's right wall.
 *
 * The hydrostatic tank of test_hydrostatic.c (water 0.3 m deep and wide,
 * l0 = 0.01 m, the still-water scheme) with its right wall above the floor
 * made a body of its own. Over the second second, the time-averaged
 * horizontal force on it must match rho g h^2 / 2 per metre of depth
 * (441.5 N/m), the vertical force must be small, and the moment about the
 * wall's foot must match rho g h^3 / 6.
 *
 * The tolerance: MPS puts p = 0 on the free-surface particles, whose centres
 * are l0/2 below the water's top (the box's edge y = h): the pressure is that
 * of a depth h' = h - l0/2 (test_hydrostatic's -1.6 % at the bottom is the
 * same shift). So the force is rho g h'^2 / 2, first order in l0: -l0/h
 * (-3.3 %) against rho g h^2 / 2. Measured (l0 = 0.01 m): Fx = 426.89 N/m,
 * -3.30 % against rho g h^2/2, +0.01 % against rho g h'^2/2; the moment
 * +0.05 % against rho g h'^3/6; Fy = -3.03 N/m (0.7 % of Fx): the normal of
 * the wall's lowest particle, fitted to the wall particles around it, leans
 * 6 degrees towards the floor's particle diagonally below. Asserted: within
 * 0.5 % of rho g h'^2 / 2 and 1 % of rho g h'^3 / 6 (the remaining error,
 * with room for noise); within l0/h + 0.5 % of rho g h^2 / 2; |Fy| < 1 %. Also checked: the body bookkeeping,
 * per-phase forces adding up, and argument validation. */
#include <mps2p.h>
#include "check.h"

#include <string.h>

#define L0 0.01
#define DEPTH 0.30
#define WIDTH 0.30
#define RHO 1000.0
#define G 9.81

static mps2p_scene *tank_with_right_wall_body(int *wall)
{
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(L0, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", RHO, 1e-6, &water));
    MUST(mps2p_scene_set_option(scene, "pressure_gradient", "corrected"));
    MUST(mps2p_scene_set_option(scene, "ppe_source", "ecs"));
    MUST(mps2p_scene_set_param(scene, "collision_distance", 0.995));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, WIDTH, DEPTH));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, WIDTH, DEPTH + 0.1, 1));
    /* the wall above the floor: its face is the segment x = 0.3, 0 <= y <= top */
    MUST(mps2p_scene_assign_body(scene, "right wall", WIDTH, 0.0, WIDTH + 0.1, 1.0, wall));
    return scene;
}

static void test_validation(void)
{
    mps2p_scene *scene = NULL;
    CHECK(mps2p_scene_add_body_box(NULL, "b", 0, 0, 1, 1, NULL) == MPS2P_ERR_NULL, "NULL scene");
    MUST(mps2p_scene_create(L0, &scene));
    CHECK(mps2p_scene_add_body_box(scene, NULL, 0, 0, 1, 1, NULL) == MPS2P_ERR_NULL, "NULL name");
    CHECK(mps2p_scene_add_body_box(scene, "", 0, 0, 1, 1, NULL) == MPS2P_ERR_INVALID, "empty");
    CHECK(mps2p_scene_add_body_box(scene, "b", 0, 0, NAN, 1, NULL) == MPS2P_ERR_INVALID, "NaN");
    CHECK(mps2p_scene_assign_body(scene, "b", 0, 0, 1, 1, NULL) == MPS2P_ERR_INVALID,
          "assign with no solid in the box");
    int kinds[2] = {MPS2P_KIND_WALL, MPS2P_KIND_FLUID};
    double positions[4] = {0, 0, 0.01, 0};
    CHECK(mps2p_scene_add_body_particles(scene, "b", 2, positions, kinds, NULL) ==
              MPS2P_ERR_INVALID, "fluid in a body");
    int count = 0;
    MUST(mps2p_scene_body_count(scene, &count));
    CHECK(count == 1, "failed calls created a body: %d bodies", count);
    int id = -1;
    MUST(mps2p_scene_add_body_box(scene, "gate", 0.5, 0.0, 0.53, 0.2, &id));
    CHECK(id == 1, "first body id %d", id);
    MUST(mps2p_scene_add_body_box(scene, "gate", 0.53, 0.0, 0.56, 0.2, &id));
    CHECK(id == 1, "same name, same body: %d", id);
    MUST(mps2p_scene_add_body_box(scene, "walls", 0.6, 0.0, 0.63, 0.2, &id));
    CHECK(id == 0, "\"walls\" is body 0: %d", id);
    MUST(mps2p_scene_body_count(scene, &count));
    CHECK(count == 2, "%d bodies", count);
    mps2p_scene_destroy(scene);
}

static void test_hydrostatic_force(void)
{
    int wall = -1;
    mps2p_scene *scene = tank_with_right_wall_body(&wall);
    const char *surface = "";
    MUST(mps2p_scene_get_option(scene, "surface_pressure", &surface));
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);

    int bodies = 0;
    const char *name = NULL;
    size_t particles = 0;
    MUST(mps2p_solver_body_count(solver, &bodies));
    MUST(mps2p_solver_get_body(solver, wall, &name, &particles));
    CHECK(bodies == 2 && wall == 1, "bodies %d, wall id %d", bodies, wall);
    CHECK(particles == 4 * 40, "right wall has %zu particles (4 layers x 40 rows)", particles);
    double force[2], moment;
    const double foot[2] = {WIDTH, 0.0};
    CHECK(mps2p_solver_body_force(solver, 2, -1, force, NULL, NULL) == MPS2P_ERR_INVALID,
          "body id past the last");
    CHECK(mps2p_solver_body_force(solver, wall, 1, force, NULL, NULL) == MPS2P_ERR_INVALID,
          "fluid id past the last");
    CHECK(mps2p_solver_body_force(solver, wall, -1, NULL, NULL, NULL) == MPS2P_ERR_NULL,
          "NULL force");

    double sum_fx = 0.0, sum_fy = 0.0, sum_m = 0.0, max_phase_gap = 0.0;
    int samples = 0;
    for (int k = 1; k <= 200; k++) {
        int status = mps2p_solver_advance_to(solver, k * 0.01, NULL, NULL);
        CHECK(status == MPS2P_OK, "advance: %s", mps2p_solver_last_error(solver));
        if (status != MPS2P_OK)
            break;
        if (k <= 100)
            continue;
        double water[2];
        MUST(mps2p_solver_body_force(solver, wall, -1, force, &moment, foot));
        MUST(mps2p_solver_body_force(solver, wall, 0, water, NULL, NULL));
        max_phase_gap = fmax(max_phase_gap, fabs(water[0] - force[0]));
        sum_fx += force[0];
        sum_fy += force[1];
        sum_m += moment;
        samples++;
    }
    /* the water's depth as the pressure sees it: its top, DEPTH (the default,
     * surface_pressure extrapolated), or the free-surface row's centres,
     * l0/2 lower (centre: docs/embedding.md) */
    const int extrapolated = strcmp(surface, "extrapolated") == 0;
    const double expected = RHO * G * DEPTH * DEPTH / 2.0;
    const double h = extrapolated ? DEPTH : DEPTH - L0 / 2.0;
    const double shifted = RHO * G * h * h / 2.0;
    /* the water pushes the wall to the right, clockwise about its foot */
    const double shifted_moment = -RHO * G * h * h * h / 6.0;
    double fx = sum_fx / samples, fy = sum_fy / samples, m = sum_m / samples;
    printf("right wall (surface_pressure %s), mean over 1-2 s (%d samples): Fx = %.2f N/m; "
           "rho g h^2/2 = %.2f N/m (%+.2f %%); rho g h'^2/2 = %.2f N/m (%+.2f %%), h' = %.4f m; "
           "Fy = %.3f N/m; M = %.3f N m/m vs -rho g h'^3/6 = %.3f (%+.2f %%)\n",
           surface, samples, fx, expected, 100 * (fx - expected) / expected, shifted,
           100 * (fx - shifted) / shifted, h, fy, m, shifted_moment,
           100 * (m - shifted_moment) / shifted_moment);
    CHECK(fabs(fx - shifted) < 0.005 * shifted, "horizontal force vs rho g h'^2/2");
    CHECK(fabs(fx - expected) < ((extrapolated ? 0.0 : L0 / DEPTH) + 0.005) * expected,
          "horizontal force vs rho g h^2/2");
    CHECK(fabs(fy) < 0.01 * expected, "vertical force %.3f N/m on a vertical wall", fy);
    CHECK(fabs(m - shifted_moment) < 0.01 * fabs(shifted_moment), "moment");
    CHECK(max_phase_gap == 0.0, "water's share differs from all fluids by %g", max_phase_gap);
    mps2p_solver_destroy(solver);
}

int main(void)
{
    test_validation();
    test_hydrostatic_force();
    return check_summary("test_bodies");
}
