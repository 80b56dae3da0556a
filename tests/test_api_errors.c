/* API misuse: every bad call returns its code and a message, none crashes. */
#define _DEFAULT_SOURCE
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>
#include "scenes.h"

#define EXPECT(call, code, fragment)                                                \
    do {                                                                            \
        int expect_status_ = (call);                                                \
        CHECK(expect_status_ == (code), "%s returned %s, expected %s", #call,       \
              mps2p_status_string(expect_status_), mps2p_status_string(code));      \
        CHECK(strstr(mps2p_last_error(), (fragment)) != NULL,                       \
              "%s: message \"%s\" lacks \"%s\"", #call, mps2p_last_error(), fragment); \
    } while (0)

/* A fluid's name from mps2p_scene_get_fluid stays valid while the scene
 * lives (issue 20: adding fluids realloc'ed the array under it, a
 * heap-use-after-free). */
static void test_fluid_names_stay_valid(void)
{
    mps2p_scene *scene;
    const char *first = NULL, *fifth = NULL;
    char name[16];
    MUST(mps2p_scene_create(0.01, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, NULL));
    MUST(mps2p_scene_get_fluid(scene, 0, &first, NULL, NULL));
    for (int f = 1; f < 40; f++) {
        snprintf(name, sizeof name, "fluid-%d", f);
        MUST(mps2p_scene_add_fluid(scene, name, 1000 - f, 1e-6, NULL));
        if (f == 4)
            MUST(mps2p_scene_get_fluid(scene, 4, &fifth, NULL, NULL));
    }
    CHECK(strcmp(first, "water") == 0, "first fluid's name reads \"%.15s\"", first);
    CHECK(strcmp(fifth, "fluid-4") == 0, "fifth fluid's name reads \"%.15s\"", fifth);
    mps2p_scene_destroy(scene);
}

static size_t particles_of(const mps2p_scene *scene)
{
    size_t count = 0;
    MUST(mps2p_scene_particle_count(scene, &count));
    return count;
}

/* Far from the origin a 0.1 m x 0.2 m box at l0 0.02 m lost particles to
 * rounding (50 at the origin, 45 at x = 1e11 m, 36 at 1e12 m); coordinates
 * beyond 1e9 l0 are refused, and within it every site is kept. */
static void test_far_from_the_origin(void)
{
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(0.02, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, &water));
    const double at[] = {0.0, 1e5, 1e7, 1.9e7};
    for (size_t k = 0; k < sizeof at / sizeof at[0]; k++) {
        size_t before = particles_of(scene);
        MUST(mps2p_scene_add_fluid_box(scene, water, at[k], 0.0, at[k] + 0.1, 0.2));
        CHECK(particles_of(scene) - before == 50, "a box at x = %g holds %zu particles", at[k],
              particles_of(scene) - before);
    }
    size_t before = particles_of(scene);
    EXPECT(mps2p_scene_add_fluid_box(scene, water, 1e11, 0, 1e11 + 0.1, 0.2), MPS2P_ERR_INVALID,
           "beyond 1e+09 l0");
    EXPECT(mps2p_scene_add_wall_box(scene, -1e12, 0, -1e12 + 0.1, 0.2), MPS2P_ERR_INVALID,
           "beyond");
    EXPECT(mps2p_scene_add_tank(scene, 1e11, 0, 1e11 + 0.4, 0.3, 1), MPS2P_ERR_INVALID, "beyond");
    double position[2] = {0.0, 3e7};
    int kind = MPS2P_KIND_FLUID;
    EXPECT(mps2p_scene_add_particles(scene, 1, position, NULL, &kind, &water), MPS2P_ERR_INVALID,
           "particle 0 at (0, 3e+07) is beyond");
    CHECK(particles_of(scene) == before, "refused calls added %zu particles",
          particles_of(scene) - before);
    mps2p_scene_destroy(scene);
}

/* A tank counts its walls against the particle cap, not its inside: a 1 m
 * tank at l0 3e-5 m (1.1e9 inner sites, 5e5 wall particles) was refused. */
static void test_tank_counts_its_walls(void)
{
    mps2p_scene *scene;
    MUST(mps2p_scene_create(3e-5, &scene));
    int status = mps2p_scene_add_tank(scene, 0, 0, 1, 1, 1);
    CHECK(status == MPS2P_OK, "a 1 m tank at l0 3e-5: %s: %s", mps2p_status_string(status),
          mps2p_last_error());
    size_t walls = particles_of(scene);
    CHECK(walls > 3 * 33333 * 4 && walls < 1000000, "the tank has %zu wall particles", walls);
    mps2p_scene_destroy(scene);
}

/* A tank's walls are as thick as the radii when it was added: radii raised
 * afterwards are refused at the solver's creation (they were taken without a
 * word and the run went on with walls too thin for its sums). */
static void test_radii_raised_after_a_tank(void)
{
    mps2p_scene *scene = dam_break_scene(0.02);
    mps2p_solver *solver = NULL;
    MUST(mps2p_scene_set_param(scene, "re_laplacian", 6.0));
    EXPECT(mps2p_solver_create(scene, &solver), MPS2P_ERR_INVALID,
           "a tank's walls are 4 layers thick");
    CHECK(solver == NULL, "a solver made with walls too thin");
    CHECK(strstr(mps2p_last_error(), "now need 6") != NULL, "%s", mps2p_last_error());
    /* lowered: the walls are thicker than needed, which is fine */
    MUST(mps2p_scene_set_param(scene, "re_laplacian", 2.1));
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_solver_destroy(solver);
    mps2p_scene_destroy(scene);
    /* set first, the tank is built for them */
    mps2p_scene *thick;
    int water;
    MUST(mps2p_scene_create(0.02, &thick));
    MUST(mps2p_scene_set_param(thick, "re_laplacian", 6.0));
    MUST(mps2p_scene_add_fluid(thick, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_add_fluid_box(thick, water, 0.0, 0.0, 0.16, 0.3));
    MUST(mps2p_scene_add_tank(thick, 0.0, 0.0, 0.6, 0.7, 1));
    MUST(mps2p_solver_create(thick, &solver));
    mps2p_solver_destroy(solver);
    mps2p_scene_destroy(thick);
}

/* count is checked against the cap before the arrays are read: here the
 * arrays hold one particle and end at an unreadable page. */
static void test_count_checked_before_reading(void)
{
    long page = sysconf(_SC_PAGESIZE);
    unsigned char *region = mmap(NULL, 2 * (size_t)page, PROT_READ | PROT_WRITE,
                                 MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    CHECK(region != MAP_FAILED, "mmap");
    if (region == MAP_FAILED)
        return;
    mprotect(region + page, (size_t)page, PROT_NONE);
    double *position = (double *)(region + page) - 2;
    int *kind = (int *)(region + page / 2) - 1;
    position[0] = position[1] = 0.0;
    *kind = MPS2P_KIND_WALL;
    mps2p_scene *scene;
    MUST(mps2p_scene_create(0.01, &scene));
    const size_t absurd = (size_t)1 << 40;
    EXPECT(mps2p_scene_add_particles(scene, absurd, position, NULL, kind, NULL),
           MPS2P_ERR_INVALID, "at most");
    int id;
    EXPECT(mps2p_scene_add_body_particles(scene, "gate", absurd, position, kind, &id),
           MPS2P_ERR_INVALID, "at most");
    CHECK(particles_of(scene) == 0, "refused calls added particles");
    MUST(mps2p_scene_add_particles(scene, 1, position, NULL, kind, NULL));
    mps2p_scene_destroy(scene);
    munmap(region, 2 * (size_t)page);
}

/* mps2p_last_error() is "" after a success (it kept the last failure's
 * message); the handle keeps its last failure; destroy leaves it alone. */
static void test_last_error_cleared_on_success(void)
{
    mps2p_scene *scene = tank_scene(0.02, 0.2, 0.1);
    mps2p_solver *solver, *loaded;
    double value;
    CHECK(mps2p_scene_set_param(scene, "beta", 7.0) == MPS2P_ERR_INVALID, "beta 7");
    CHECK(mps2p_last_error()[0] != '\0', "a failure leaves a message");
    MUST(mps2p_scene_set_param(scene, "beta", 0.97));
    CHECK(mps2p_last_error()[0] == '\0', "after set_param succeeded: \"%s\"",
          mps2p_last_error());
    CHECK(strstr(mps2p_scene_last_error(scene), "beta") != NULL, "the handle keeps its failure");
    MUST(mps2p_solver_create(scene, &solver));
    CHECK(mps2p_solver_get_stat(solver, "nonsense", &value) == MPS2P_ERR_UNKNOWN_KEY, "stat");
    MUST(mps2p_solver_get_stat(solver, "max_speed", &value));
    CHECK(mps2p_last_error()[0] == '\0', "after get_stat: \"%s\"", mps2p_last_error());
    CHECK(mps2p_param_info(100000, NULL, NULL, NULL) == MPS2P_ERR_INVALID, "index");
    MUST(mps2p_solver_step(solver));
    CHECK(mps2p_last_error()[0] == '\0', "after step: \"%s\"", mps2p_last_error());
    CHECK(mps2p_solver_load_checkpoint("/nonexistent/x.chk", &loaded) == MPS2P_ERR_IO, "load");
    MUST(mps2p_solver_advance_to(solver, 0.01, NULL, NULL));
    CHECK(mps2p_last_error()[0] == '\0', "after advance_to: \"%s\"", mps2p_last_error());
    /* saving, loading and a results file list the parameters: their listing
     * must not leave its end-of-list failure behind */
    char directory[] = "/tmp/mps2p_last_error_XXXXXX", path[64];
    CHECK(mkdtemp(directory) != NULL, "mkdtemp");
    snprintf(path, sizeof path, "%s/run.chk", directory);
    MUST(mps2p_solver_save_checkpoint(solver, path));
    CHECK(mps2p_last_error()[0] == '\0', "after save_checkpoint: \"%s\"", mps2p_last_error());
    MUST(mps2p_solver_load_checkpoint(path, &loaded));
    CHECK(mps2p_last_error()[0] == '\0', "after load_checkpoint: \"%s\"", mps2p_last_error());
    mps2p_solver_destroy(loaded);
    unlink(path);
    snprintf(path, sizeof path, "%s/run.h5", directory);
    mps2p_results *results;
    MUST(mps2p_results_create(path, solver, NULL, &results));
    CHECK(mps2p_last_error()[0] == '\0', "after results_create: \"%s\"", mps2p_last_error());
    MUST(mps2p_results_close(results));
    unlink(path);
    snprintf(path, sizeof path, "%s/run.xdmf", directory);
    unlink(path);
    rmdir(directory);
    CHECK(mps2p_scene_fluid_count(scene, NULL) == MPS2P_ERR_NULL, "fluid_count");
    mps2p_scene_destroy(scene);
    CHECK(mps2p_last_error()[0] != '\0', "destroy cleared the message");
    mps2p_solver_destroy(solver);
    /* an empty path is an invalid argument for saving and loading alike */
    EXPECT(mps2p_solver_load_checkpoint("", &loaded), MPS2P_ERR_INVALID, "path is empty");
}

/* A spacing or gravity at the ends of a double's range gives derived
 * constants (lambda, n0, dt_max) that are nan or 0: creation refuses it
 * rather than make a solver whose every step fails and whose checkpoint its
 * loader refuses. */
static void test_spacing_beyond_a_double(void)
{
    const double spacings[] = {1e300, 1e-300, 1e100};
    for (size_t k = 0; k < sizeof spacings / sizeof spacings[0]; k++) {
        double l0 = spacings[k];
        mps2p_scene *scene;
        mps2p_solver *solver = NULL;
        int water;
        MUST(mps2p_scene_create(l0, &scene));
        MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water));
        MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 5 * l0, 5 * l0));
        if (l0 == 1e100) /* a finite lambda, but dt_max underflows */
            MUST(mps2p_scene_set_param(scene, "gravity_y", -1e300));
        EXPECT(mps2p_solver_create(scene, &solver), MPS2P_ERR_INVALID, "not a finite positive");
        CHECK(solver == NULL, "a refused creation returned a solver");
        mps2p_scene_destroy(scene);
    }
}

/* A step at the end of a double's range makes the PPE source overflow:
 * the step fails naming that, not "residual nan", and keeps its state. */
static void test_step_beyond_a_double(void)
{
    mps2p_scene *scene = tank_scene(0.02, 0.2, 0.1);
    mps2p_solver *solver;
    MUST(mps2p_scene_set_param(scene, "dt", 1e-300));
    MUST(mps2p_solver_create(scene, &solver));
    EXPECT(mps2p_solver_step(solver), MPS2P_ERR_SOLVE, "too large to solve");
    double time = -1.0;
    MUST(mps2p_solver_get_time(solver, &time));
    CHECK(time == 0.0, "the failed step moved time to %g", time);
    mps2p_solver_destroy(solver);
    mps2p_scene_destroy(scene);
    /* a density whose source is finite but whose square overflows in CG's norms */
    int heavy;
    MUST(mps2p_scene_create(0.02, &scene));
    MUST(mps2p_scene_add_fluid(scene, "heavy", 1e296, 1e-6, &heavy));
    MUST(mps2p_scene_add_fluid_box(scene, heavy, 0.0, 0.0, 0.1, 0.1));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.2, 0.2, 1));
    MUST(mps2p_solver_create(scene, &solver));
    EXPECT(mps2p_solver_step(solver), MPS2P_ERR_SOLVE, "too large to solve");
    mps2p_solver_destroy(solver);
    mps2p_scene_destroy(scene);
}

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
    CHECK(strstr(mps2p_last_error(), "did you mean") == NULL, "a far miss gets no suggestion: %s",
          mps2p_last_error());
    /* a near miss names the key meant */
    EXPECT(mps2p_scene_set_param(scene, "cfll", 1.0), MPS2P_ERR_UNKNOWN_KEY,
           "unknown parameter \"cfll\" (did you mean \"cfl\"?)");
    EXPECT(mps2p_scene_set_param(scene, "collision_distanse", 1.0), MPS2P_ERR_UNKNOWN_KEY,
           "(did you mean \"collision_distance\"?)");
    /* no near miss: a name holding the key, or sharing its first word */
    EXPECT(mps2p_scene_set_option(scene, "solver", "cg"), MPS2P_ERR_UNKNOWN_KEY,
           "(did you mean \"pressure_solver\"?)");
    EXPECT(mps2p_scene_set_param(scene, "excitation_amplitude", 1.0), MPS2P_ERR_UNKNOWN_KEY,
           "(did you mean \"excitation_acceleration\"?)");
    /* keys are lower case; a key in capitals is a near miss */
    EXPECT(mps2p_scene_set_param(scene, "CFL", 0.2), MPS2P_ERR_UNKNOWN_KEY,
           "unknown parameter \"CFL\" (did you mean \"cfl\"?)");
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
    kinds[1] = MPS2P_KIND_OUT; /* a solver's only: fluid that left the domain */
    EXPECT(mps2p_scene_add_particles(scene, 2, position, NULL, kinds, ids), MPS2P_ERR_INVALID,
           "kind 3 is not MPS2P_KIND_FLUID, _WALL or _DUMMY (MPS2P_KIND_OUT");
    EXPECT(mps2p_scene_add_body_particles(scene, "lid", 1, position, kinds + 1, NULL),
           MPS2P_ERR_INVALID, "got kind 3 (MPS2P_KIND_OUT");
    kinds[1] = 9;
    EXPECT(mps2p_scene_add_particles(scene, 2, position, NULL, kinds, NULL), MPS2P_ERR_NULL,
           "fluid_ids is NULL");
    MUST(mps2p_scene_particle_count(scene, &count));
    CHECK(count == 0, "refused calls added %zu particles", count);

    /* empty scene, then overlapping boxes */
    EXPECT(mps2p_solver_create(scene, &solver), MPS2P_ERR_STATE, "no fluid particles");
    CHECK(solver == NULL, "no solver on failure");
    MUST(mps2p_scene_add_fluid_box(scene, water, 0, 0, 0.1, 0.1));
    EXPECT(mps2p_scene_add_fluid_box(scene, water, 0.05, 0.05, 0.15, 0.15), MPS2P_ERR_INVALID,
           "overlaps particles 0 to 99, a fluid box [0, 0, 0.1, 0.1] added before");
    /* half a spacing off: no two particles in one place, and the run used to
     * diverge at its first step ("pressure beyond the limit") */
    EXPECT(mps2p_scene_add_fluid_box(scene, water, 0.095, 0.005, 0.195, 0.105),
           MPS2P_ERR_INVALID, "boxes may touch, not overlap");
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.1, 0.0, 0.2, 0.1)); /* touching */
    MUST(mps2p_scene_particle_count(scene, &count));
    CHECK(count == 200, "refused boxes added particles: %zu", count);
    /* a tank whose wall runs through a fluid box: refused whole */
    EXPECT(mps2p_scene_add_tank(scene, 0.05, 0.0, 0.3, 0.3, 1), MPS2P_ERR_INVALID,
           "the solid box");
    MUST(mps2p_scene_particle_count(scene, &count));
    CHECK(count == 200, "a refused tank added particles: %zu", count);
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.3, 0.3, 1));
    /* a wall box reaching into the tank's floor, which lies outside its box */
    EXPECT(mps2p_scene_add_wall_box(scene, 0.25, -0.02, 0.3, 0.05), MPS2P_ERR_INVALID,
           "the solid box [0.25, -0.02, 0.3, 0.05] overlaps particles");
    MUST(mps2p_scene_add_wall_box(scene, 0.25, 0.0, 0.3, 0.05)); /* on the floor */
    mps2p_scene_destroy(scene);

    /* a working solver, and bad queries on it */
    scene = tank_scene(0.02, 0.2, 0.1);
    MUST(mps2p_solver_create(scene, &solver));
    MUST(mps2p_solver_particle_count(solver, &count));
    double small[4];
    EXPECT(mps2p_solver_get_positions(solver, small, 4), MPS2P_ERR_BUFFER, "buffer holds 4");
    EXPECT(mps2p_solver_get_pressure(solver, NULL, count), MPS2P_ERR_NULL, "output pointer");
    EXPECT(mps2p_solver_get_stat(solver, "nonsense", &value), MPS2P_ERR_UNKNOWN_KEY, "nonsense");
    EXPECT(mps2p_solver_get_stat(solver, "max_sped", &value), MPS2P_ERR_UNKNOWN_KEY,
           "unknown statistic \"max_sped\" (did you mean \"max_speed\"?)");
    EXPECT(mps2p_solver_advance_to(solver, NAN, NULL, NULL), MPS2P_ERR_INVALID, "end time");
    MUST(mps2p_solver_step(solver));
    EXPECT(mps2p_solver_advance_to(solver, -1.0, NULL, NULL), MPS2P_ERR_INVALID,
           "not before the current time");
    int solver_kinds[4];
    EXPECT(mps2p_solver_get_kinds(solver, solver_kinds, 4), MPS2P_ERR_BUFFER, "kinds");

    /* issue 7's audit: every remaining entry point, NULLs and absurd values */
    int ints[2];
    uint64_t steps;
    const char *text;
    EXPECT(mps2p_solver_get_time(solver, NULL), MPS2P_ERR_NULL, "output pointer");
    EXPECT(mps2p_solver_get_step_count(NULL, &steps), MPS2P_ERR_NULL, "solver is NULL");
    EXPECT(mps2p_solver_get_last_dt(solver, NULL), MPS2P_ERR_NULL, "output pointer");
    EXPECT(mps2p_solver_particle_count(solver, NULL), MPS2P_ERR_NULL, "output pointer");
    EXPECT(mps2p_solver_get_velocities(solver, small, 4), MPS2P_ERR_BUFFER, "velocities");
    EXPECT(mps2p_solver_get_number_density(solver, small, 1), MPS2P_ERR_BUFFER, "number");
    EXPECT(mps2p_solver_get_fluid_ids(solver, ints, 2), MPS2P_ERR_BUFFER, "fluid ids");
    EXPECT(mps2p_solver_get_stat(solver, NULL, &value), MPS2P_ERR_NULL, "key is NULL");
    EXPECT(mps2p_solver_advance_to(solver, INFINITY, NULL, NULL), MPS2P_ERR_INVALID, "finite");
    double points[2] = {NAN, 0.0}, probe_p;
    EXPECT(mps2p_solver_probe(solver, 1, points, &probe_p, NULL, NULL), MPS2P_ERR_INVALID,
           "not finite");
    EXPECT(mps2p_solver_probe(solver, 1, NULL, &probe_p, NULL, NULL), MPS2P_ERR_NULL, "points");
    EXPECT(mps2p_solver_probe(NULL, 1, points, &probe_p, NULL, NULL), MPS2P_ERR_NULL, "NULL");
    EXPECT(mps2p_solver_front(solver, 5, INFINITY, &value), MPS2P_ERR_INVALID, "");
    EXPECT(mps2p_solver_front(solver, -1, INFINITY, NULL), MPS2P_ERR_NULL, "");
    EXPECT(mps2p_solver_save_checkpoint(NULL, "x.chk"), MPS2P_ERR_NULL, "solver is NULL");
    EXPECT(mps2p_solver_save_checkpoint(solver, NULL), MPS2P_ERR_NULL, "path is NULL");
    EXPECT(mps2p_solver_save_checkpoint(solver, ""), MPS2P_ERR_INVALID, "path is empty");
    EXPECT(mps2p_solver_save_checkpoint(solver, "/nonexistent-dir/x.chk"), MPS2P_ERR_IO,
           "nonexistent-dir");
    mps2p_solver *loaded = NULL;
    EXPECT(mps2p_solver_load_checkpoint(NULL, &loaded), MPS2P_ERR_NULL, "path is NULL");
    EXPECT(mps2p_solver_load_checkpoint("x.chk", NULL), MPS2P_ERR_NULL, "output pointer");
    mps2p_results *results = NULL;
    EXPECT(mps2p_results_create(NULL, solver, NULL, &results), MPS2P_ERR_NULL, "path is NULL");
    EXPECT(mps2p_results_create("r.h5", NULL, NULL, &results), MPS2P_ERR_NULL, "solver is NULL");
    EXPECT(mps2p_results_create("r.h5", solver, NULL, NULL), MPS2P_ERR_NULL, "output pointer");
    EXPECT(mps2p_results_create("", solver, NULL, &results), MPS2P_ERR_INVALID, "empty");
    EXPECT(mps2p_results_write_snapshot(NULL, solver), MPS2P_ERR_NULL, "results is NULL");
    EXPECT(mps2p_results_append_series(NULL, "a", 0, 0), MPS2P_ERR_NULL, "NULL");
    CHECK(mps2p_results_close(NULL) == MPS2P_OK, "closing NULL is OK");
    CHECK(strcmp(mps2p_results_last_error(NULL), "") != 0, "a NULL handle has a message");
    CHECK(strcmp(mps2p_solver_last_error(NULL), "") != 0, "a NULL solver has a message");
    CHECK(strcmp(mps2p_scene_last_error(NULL), "") != 0, "a NULL scene has a message");
    mps2p_solver_destroy(solver);
    mps2p_scene_destroy(scene);

    /* scene entry points */
    EXPECT(mps2p_scene_create(INFINITY, &scene), MPS2P_ERR_INVALID, "finite");
    MUST(mps2p_scene_create(0.01, &scene));
    int fluids = -1;
    EXPECT(mps2p_scene_fluid_count(scene, NULL), MPS2P_ERR_NULL, "NULL");
    EXPECT(mps2p_scene_fluid_count(NULL, &fluids), MPS2P_ERR_NULL, "scene is NULL");
    EXPECT(mps2p_scene_get_fluid(scene, 0, &text, NULL, NULL), MPS2P_ERR_INVALID, "no fluid");
    EXPECT(mps2p_scene_set_param(scene, NULL, 1.0), MPS2P_ERR_NULL, "key is NULL");
    EXPECT(mps2p_scene_set_param(scene, "cfl", INFINITY), MPS2P_ERR_INVALID, "finite");
    EXPECT(mps2p_scene_set_param(scene, "re_density", 1e300), MPS2P_ERR_INVALID, "must be in");
    EXPECT(mps2p_scene_get_param(scene, "beta", NULL), MPS2P_ERR_NULL, "NULL");
    EXPECT(mps2p_scene_set_option(scene, NULL, "cg"), MPS2P_ERR_NULL, "NULL");
    EXPECT(mps2p_scene_set_option(scene, "pressure_solver", NULL), MPS2P_ERR_NULL, "NULL");
    EXPECT(mps2p_scene_set_option(scene, "nonsense", "cg"), MPS2P_ERR_UNKNOWN_KEY, "nonsense");
    EXPECT(mps2p_scene_set_option(scene, "pressure_solvr", "cg"), MPS2P_ERR_UNKNOWN_KEY,
           "(did you mean \"pressure_solver\"?)");
    EXPECT(mps2p_scene_set_option(scene, "shceme", "corrected"), MPS2P_ERR_UNKNOWN_KEY,
           "(did you mean \"scheme\"?)");
    EXPECT(mps2p_scene_get_option(scene, "nonsense", &text), MPS2P_ERR_UNKNOWN_KEY, "nonsense");
    EXPECT(mps2p_scene_get_option(scene, "pressure_solver", NULL), MPS2P_ERR_NULL, "NULL");
    EXPECT(mps2p_param_info(100000, &text, NULL, NULL), MPS2P_ERR_INVALID, "past the last");
    size_t listed = 0;
    EXPECT(mps2p_param_count(NULL), MPS2P_ERR_NULL, "NULL");
    EXPECT(mps2p_option_count(NULL), MPS2P_ERR_NULL, "NULL");
    EXPECT(mps2p_stat_count(NULL), MPS2P_ERR_NULL, "NULL");
    MUST(mps2p_option_count(&listed));
    EXPECT(mps2p_option_info(listed, &text, NULL, NULL, NULL), MPS2P_ERR_INVALID,
           "past the last");
    EXPECT(mps2p_option_choice(0, 1000, &text), MPS2P_ERR_INVALID, "choices");
    MUST(mps2p_stat_count(&listed));
    EXPECT(mps2p_stat_info(listed, &text, NULL, NULL), MPS2P_ERR_INVALID, "past the last");
    EXPECT(mps2p_scene_add_wall_box(NULL, 0, 0, 1, 1), MPS2P_ERR_NULL, "scene is NULL");
    EXPECT(mps2p_scene_add_wall_box(scene, 0, 0, NAN, 1), MPS2P_ERR_INVALID, "finite");
    EXPECT(mps2p_scene_add_tank(scene, 0, 0, 1e300, 1e300, 1), MPS2P_ERR_INVALID, "");
    EXPECT(mps2p_scene_add_tank(scene, -INFINITY, 0, 1, 1, 0), MPS2P_ERR_INVALID, "finite");
    EXPECT(mps2p_scene_add_particles(scene, 1, NULL, NULL, kinds, ids), MPS2P_ERR_NULL, "NULL");
    CHECK(mps2p_scene_add_particles(scene, 0, NULL, NULL, NULL, NULL) == MPS2P_OK,
          "adding no particles is OK");
    /* a domain whose width overflows (regression: fuzz_scene) */
    EXPECT(mps2p_scene_set_domain(scene, -1e308, 0, 1e308, 1), MPS2P_ERR_INVALID,
           "finite width");
    EXPECT(mps2p_scene_set_domain(scene, 0, 0, 1, NAN), MPS2P_ERR_INVALID, "finite");
    /* spacing larger than the domain: the particles fall outside it */
    MUST(mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, &water));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0, 0, 0.1, 0.1));
    MUST(mps2p_scene_set_domain(scene, 0, 0, 0.004, 0.004));
    EXPECT(mps2p_solver_create(scene, &solver), MPS2P_ERR_INVALID, "outside the domain");
    mps2p_scene_destroy(scene);
    /* particles so far apart that the default domain overflows (regression) */
    MUST(mps2p_scene_create(0.01, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, &water));
    double far[4] = {-1e308, 0.0, 1e308, 0.0};
    int far_kinds[2] = {MPS2P_KIND_FLUID, MPS2P_KIND_FLUID}, far_ids[2] = {0, 0};
    /* (now refused before: coordinates beyond 1e9 l0, issue 20) */
    EXPECT(mps2p_scene_add_particles(scene, 2, far, NULL, far_kinds, far_ids),
           MPS2P_ERR_INVALID, "beyond 1e+09 l0");
    mps2p_scene_destroy(scene);

    test_fluid_names_stay_valid();
    test_far_from_the_origin();
    test_tank_counts_its_walls();
    test_radii_raised_after_a_tank();
    test_count_checked_before_reading();
    test_last_error_cleared_on_success();
    test_spacing_beyond_a_double();
    test_step_beyond_a_double();
    return check_summary("test_api_errors");
}
