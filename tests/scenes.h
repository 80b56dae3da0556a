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

#endif
