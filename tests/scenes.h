/* Small scenes shared by the tests. */
#ifndef MPS2P_TEST_SCENES_H
#define MPS2P_TEST_SCENES_H

#include <mps2p.h>
#include "check.h"

/* The paper's column (0.15 m x 0.30 m) at the left of a 0.6 m open tank. */
static inline mps2p_scene *dam_break_scene(double l0)
{
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(l0, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.15, 0.30));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.6, 0.7, 1));
    return scene;
}

/* A tank of still water, depth x width, open top. */
static inline mps2p_scene *tank_scene(double l0, double width, double depth)
{
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(l0, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, width, depth));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, width, depth + 0.1, 1));
    return scene;
}

/* Two phases: a water column (0.1 m x 0.2 m) at the left of a closed
 * 0.3 m x 0.4 m tank, air beside and above it up to 0.3 m; model NULL
 * keeps the default (two_step_improved, reaction drift). */
static inline mps2p_scene *water_air_column_scene(double l0, const char *model)
{
    mps2p_scene *scene;
    int water, air;
    MUST(mps2p_scene_create(l0, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_add_fluid(scene, "air", 1.2, 1.5e-5, &air));
    if (model)
        MUST(mps2p_scene_set_option(scene, "two_phase_model", model));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.1, 0.2));
    MUST(mps2p_scene_add_fluid_box(scene, air, 0.1, 0.0, 0.3, 0.3));
    MUST(mps2p_scene_add_fluid_box(scene, air, 0.0, 0.2, 0.1, 0.3));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.3, 0.4, 0));
    return scene;
}

/* Two phases: a 4 x 4 air pocket (0.08-0.12 m across, 0.05-0.09 m up) in
 * water up to water_top in a 0.2 m x 0.3 m open tank, l0 = 0.01 m, and air
 * from water_top up to air_top above it (none when air_top <= water_top:
 * the pocket is then all the gas). Water is fluid 0, air AIR_POCKET_AIR. */
#define AIR_POCKET_AIR 1
static inline mps2p_scene *air_pocket_scene(double water_top, double air_top)
{
    mps2p_scene *scene;
    int water, air;
    MUST(mps2p_scene_create(0.01, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_add_fluid(scene, "air", 1.2, 1.5e-5, &air));
    CHECK(air == AIR_POCKET_AIR, "air is fluid %d", air);
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.2, 0.05));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.05, 0.08, 0.09));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.12, 0.05, 0.2, 0.09));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.09, 0.2, water_top));
    MUST(mps2p_scene_add_fluid_box(scene, air, 0.08, 0.05, 0.12, 0.09));
    if (air_top > water_top)
        MUST(mps2p_scene_add_fluid_box(scene, air, 0.0, water_top, 0.2, air_top));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.2, 0.3, 1));
    return scene;
}

/* Spray leaving the domain: the dam break's column (0.1 m x 0.2 m, l0 =
 * 0.01 m) in a 0.4 m x 0.3 m open tank, and three droplets above the tank
 * floor thrown up at 2 m/s through the top of a domain that ends at 0.35 m:
 * droplet a leaves first, b (sqrt 2 l0 from a, within its density radius)
 * 1 l0 behind it, c alone 2 l0 behind a. *first gets a's index; b and c
 * follow it. */
static inline mps2p_scene *spray_scene(size_t *first)
{
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(0.01, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.1, 0.2));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.4, 0.3, 1));
    MUST(mps2p_scene_set_domain(scene, -0.1, -0.1, 0.5, 0.35));
    MUST(mps2p_scene_particle_count(scene, first));
    const double positions[6] = {0.255, 0.265, 0.265, 0.255, 0.155, 0.245};
    const double velocities[6] = {0.0, 2.0, 0.0, 2.0, 0.0, 2.0};
    const int kinds[3] = {MPS2P_KIND_FLUID, MPS2P_KIND_FLUID, MPS2P_KIND_FLUID};
    const int ids[3] = {water, water, water};
    MUST(mps2p_scene_add_particles(scene, 3, positions, velocities, kinds, ids));
    return scene;
}

#endif
