/* The adaptive dt's bound dt_max = cfl l0 / sqrt(2 g H) at the start
 * (docs/method.md, "Time step"): H from the lowest fluid particle to the
 * highest of a heavy fluid. Air over water does not fall, so it leaves H
 * alone (counted, it made the paper's case take 5.4e-4 s steps for its
 * water's 8.2e-4, docs/performance.md); air under water is room the water
 * can fall through, so it counts. gravity_number 0 takes the gravity bound
 * away, so that the first dt is dt_max itself. */
#include <math.h>
#include <mps2p.h>
#include "check.h"

#define L0 0.01
#define CFL 0.2
#define G 9.81

/* Water in [0.2, 0.4] x [water_bottom, water_top] of a 0.6 m x 1.0 m tank,
 * air under it from the floor when water_bottom > 0, air over it up to
 * air_top when air_top > water_top; the first step's dt. */
static double first_dt(double water_bottom, double water_top, double air_top)
{
    mps2p_scene *scene;
    int water, air;
    MUST(mps2p_scene_create(L0, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_add_fluid(scene, "air", 1.2, 1.5e-5, &air));
    MUST(mps2p_scene_set_param(scene, "gravity_number", 0.0));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.2, water_bottom, 0.4, water_top));
    if (water_bottom > 0.0)
        MUST(mps2p_scene_add_fluid_box(scene, air, 0.0, 0.0, 0.6, water_bottom));
    if (air_top > water_top)
        MUST(mps2p_scene_add_fluid_box(scene, air, 0.0, water_top, 0.6, air_top));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.6, 1.0, 1));
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    double dt = 0.0;
    MUST(mps2p_solver_get_stat(solver, "dt_next", &dt));
    mps2p_solver_destroy(solver);
    return dt;
}

static double bound(double height)
{
    return CFL * L0 / sqrt(2.0 * G * height);
}

int main(void)
{
    /* water alone, 0.3 m high: H is its height (centres l0 / 2 in from its
     * ends, plus l0) */
    CHECK_CLOSE(first_dt(0.0, 0.3, 0.0), bound(0.3), 1e-12, "water 0.3 m");
    /* 0.4 m of air over it: the same bound */
    CHECK_CLOSE(first_dt(0.0, 0.3, 0.7), bound(0.3), 1e-12, "water 0.3 m under 0.4 m of air");
    /* the water 0.2 m high over 0.1 m of air: it can fall 0.3 m */
    CHECK_CLOSE(first_dt(0.1, 0.3, 0.0), bound(0.3), 1e-12, "water 0.2 m over 0.1 m of air");
    return check_summary("test_timestep");
}
