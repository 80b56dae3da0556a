/* API misuse: every bad call returns its code and a message, none crashes. */
#include <string.h>
#include "scenes.h"

#define EXPECT(call, code, fragment)                                                \
    do {                                                                            \
        int expect_status_ = (call);                                                \
        CHECK(expect_status_ == (code), "%s returned %s, expected %s", #call,       \
              mps2p_status_string(expect_status_), mps2p_status_string(code));      \
        CHECK(strstr(mps2p_last_error(), (fragment)) != NULL,                       \
              "%s: message \"%s\" lacks \"%s\"", #call, mps2p_last_error(), fragment); \
    } while (0)

int main(void)
{
    mps2p_scene *scene = NULL;
    mps2p_solver *solver = NULL;
    double value;
    size_t count;

    /* versions */
    CHECK(mps2p_version_number() == MPS2P_VERSION_NUMBER, "run-time and header versions differ");
    CHECK(strcmp(mps2p_version_string(), MPS2P_VERSION_STRING) == 0, "version strings differ");
    CHECK(strcmp(mps2p_status_string(MPS2P_ERR_DIVERGED), "MPS2P_ERR_DIVERGED") == 0, "name");
    CHECK(strcmp(mps2p_status_string(12345), "MPS2P_ERR_UNRECOGNISED_STATUS") == 0, "unknown");

    /* spacing */
    EXPECT(mps2p_scene_create(-0.01, &scene), MPS2P_ERR_INVALID, "spacing l0 must be > 0");
    CHECK(scene == NULL, "no scene on failure");
    EXPECT(mps2p_scene_create(0.0, &scene), MPS2P_ERR_INVALID, "got 0");
    EXPECT(mps2p_scene_create(NAN, &scene), MPS2P_ERR_INVALID, "finite");
    EXPECT(mps2p_scene_create(0.01, NULL), MPS2P_ERR_NULL, "NULL");

    /* NULL handles */
    EXPECT(mps2p_scene_add_fluid(NULL, "water", 1000, 1e-6, NULL), MPS2P_ERR_NULL, "scene is NULL");
    EXPECT(mps2p_scene_set_param(NULL, "beta", 0.9), MPS2P_ERR_NULL, "scene is NULL");
    EXPECT(mps2p_solver_create(NULL, &solver), MPS2P_ERR_NULL, "scene is NULL");
    EXPECT(mps2p_solver_step(NULL), MPS2P_ERR_NULL, "solver is NULL");
    EXPECT(mps2p_solver_advance_to(NULL, 1.0, NULL, NULL), MPS2P_ERR_NULL, "solver is NULL");
    EXPECT(mps2p_solver_get_positions(NULL, &value, 1), MPS2P_ERR_NULL, "solver is NULL");
    mps2p_scene_destroy(NULL);
    mps2p_solver_destroy(NULL);

    MUST(mps2p_scene_create(0.01, &scene));
    /* fluids */
    EXPECT(mps2p_scene_add_fluid(scene, "water", -1000, 1e-6, NULL), MPS2P_ERR_INVALID,
           "density of fluid \"water\" must be > 0");
    CHECK(strstr(mps2p_scene_last_error(scene), "density") != NULL, "handle keeps the message");
    EXPECT(mps2p_scene_add_fluid(scene, "water", 1000, NAN, NULL), MPS2P_ERR_INVALID, "viscosity");
    EXPECT(mps2p_scene_add_fluid(scene, "", 1000, 0, NULL), MPS2P_ERR_INVALID, "name");
    EXPECT(mps2p_scene_add_fluid(scene, NULL, 1000, 0, NULL), MPS2P_ERR_NULL, "name is NULL");
    int water;
    MUST(mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, &water));
    EXPECT(mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, NULL), MPS2P_ERR_INVALID,
           "already exists");

    /* parameters */
    EXPECT(mps2p_scene_set_param(scene, "beta", NAN), MPS2P_ERR_INVALID, "finite");
    EXPECT(mps2p_scene_set_param(scene, "beta", 1.5), MPS2P_ERR_INVALID, "beta must be in");
    EXPECT(mps2p_scene_set_param(scene, "dt", -1e-3), MPS2P_ERR_INVALID, "dt must be in");
    EXPECT(mps2p_scene_set_param(scene, "no_such", 1.0), MPS2P_ERR_UNKNOWN_KEY, "no_such");
    EXPECT(mps2p_scene_get_param(scene, "no_such", &value), MPS2P_ERR_UNKNOWN_KEY, "no_such");
    EXPECT(mps2p_scene_set_option(scene, "pressure_solver", "lu"), MPS2P_ERR_INVALID, "\"lu\"");
    MUST(mps2p_scene_get_param(scene, "beta", &value));
    CHECK(value == 0.97, "beta keeps its default after a refused set, got %g", value);
    const char *key;
    double default_value;
    size_t params = 0;
    while (mps2p_param_info(params, &key, NULL, &default_value) == MPS2P_OK) {
        MUST(mps2p_scene_get_param(scene, key, &value));
        CHECK(value == default_value, "%s: scene holds %g, default is %g", key, value,
              default_value);
        params++;
    }
    CHECK(params >= 19, "only %zu parameters listed", params);

    /* geometry */
    EXPECT(mps2p_scene_add_fluid_box(scene, 7, 0, 0, 1, 1), MPS2P_ERR_INVALID, "no fluid with id 7");
    EXPECT(mps2p_scene_add_fluid_box(scene, water, 0, 0, -1, 1), MPS2P_ERR_INVALID, "x1 > x0");
    EXPECT(mps2p_scene_add_fluid_box(scene, water, 0, 0, 0.001, 1), MPS2P_ERR_INVALID, "narrower");
    EXPECT(mps2p_scene_add_fluid_box(scene, water, 0, 0, INFINITY, 1), MPS2P_ERR_INVALID, "finite");
    EXPECT(mps2p_scene_add_fluid_box(scene, water, 0, 0, 1e4, 1e4), MPS2P_ERR_INVALID,
           "more than a scene can hold");
    EXPECT(mps2p_scene_set_domain(scene, 1, 0, 0, 1), MPS2P_ERR_INVALID, "xmax > xmin");
    double position[4] = {0.0, 0.0, NAN, 0.0};
    int kinds[2] = {MPS2P_KIND_FLUID, MPS2P_KIND_FLUID}, ids[2] = {0, 0};
    EXPECT(mps2p_scene_add_particles(scene, 2, position, NULL, kinds, ids), MPS2P_ERR_INVALID,
           "particle 1: position is not finite");
    kinds[1] = 9;
    position[2] = 0.5;
    EXPECT(mps2p_scene_add_particles(scene, 2, position, NULL, kinds, ids), MPS2P_ERR_INVALID,
           "kind 9");
    EXPECT(mps2p_scene_add_particles(scene, 2, position, NULL, kinds, NULL), MPS2P_ERR_NULL,
           "fluid_ids is NULL");
    MUST(mps2p_scene_particle_count(scene, &count));
    CHECK(count == 0, "refused calls added %zu particles", count);

    /* empty scene, then overlapping boxes */
    EXPECT(mps2p_solver_create(scene, &solver), MPS2P_ERR_STATE, "no fluid particles");
    CHECK(solver == NULL, "no solver on failure");
    MUST(mps2p_scene_add_fluid_box(scene, water, 0, 0, 0.1, 0.1));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.05, 0.05, 0.15, 0.15));
    EXPECT(mps2p_solver_create(scene, &solver), MPS2P_ERR_INVALID, "closer than 0.1 l0");
    mps2p_scene_destroy(scene);

    /* a working solver, and bad queries on it */
    scene = tank_scene(0.02, 0.2, 0.1);
    MUST(mps2p_solver_create(scene, &solver));
    MUST(mps2p_solver_particle_count(solver, &count));
    double small[4];
    EXPECT(mps2p_solver_get_positions(solver, small, 4), MPS2P_ERR_BUFFER, "buffer holds 4");
    EXPECT(mps2p_solver_get_pressure(solver, NULL, count), MPS2P_ERR_NULL, "output pointer");
    EXPECT(mps2p_solver_get_stat(solver, "nonsense", &value), MPS2P_ERR_UNKNOWN_KEY, "nonsense");
    EXPECT(mps2p_solver_advance_to(solver, NAN, NULL, NULL), MPS2P_ERR_INVALID, "end time");
    MUST(mps2p_solver_step(solver));
    EXPECT(mps2p_solver_advance_to(solver, -1.0, NULL, NULL), MPS2P_ERR_INVALID,
           "not before the current time");
    int solver_kinds[4];
    EXPECT(mps2p_solver_get_kinds(solver, solver_kinds, 4), MPS2P_ERR_BUFFER, "kinds");
    mps2p_solver_destroy(solver);
    mps2p_scene_destroy(scene);
    return check_summary("test_api_errors");
}
