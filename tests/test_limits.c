/* Bounds on memory and time (issue 20, defect 4): a scene asking for more
 * memory than it may have is refused before anything is allocated (it grew
 * for a minute until the kernel killed the process), and a window that
 * would take more than 1e9 steps is refused (a viscosity of 1e20 m^2/s gave
 * dt = 8e-25 s and a run that never ended). */
#include <mps2p.h>
#include "check.h"

#include <string.h>
#include <time.h>
#include <unistd.h>

static double cpu_seconds(void)
{
    return (double)clock() / CLOCKS_PER_SEC;
}

/* Parameter memory_limit: a box, a solver and a scene growth beyond it are
 * MPS2P_ERR_NOMEM with a message naming the limit, at once, and change
 * nothing. */
static void test_memory_limit(void)
{
    mps2p_scene *scene;
    int water;
    double limit;
    MUST(mps2p_scene_create(0.001, &scene));
    MUST(mps2p_scene_get_param(scene, "memory_limit", &limit));
    CHECK(limit == 0.0, "memory_limit defaults to 0 (derived), got %g", limit);
    MUST(mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, &water));
    MUST(mps2p_scene_set_param(scene, "memory_limit", 1e9));
    double start = cpu_seconds();
    int status = mps2p_scene_add_fluid_box(scene, water, 0, 0, 30, 30); /* 9e8 particles */
    CHECK(status == MPS2P_ERR_NOMEM, "9e8 particles under a 1 GB limit: %s",
          mps2p_status_string(status));
    CHECK(strstr(mps2p_last_error(), "memory_limit") != NULL, "message: %s",
          mps2p_last_error());
    CHECK(cpu_seconds() - start < 1.0, "the refusal took %g s", cpu_seconds() - start);
    size_t count = 1;
    MUST(mps2p_scene_particle_count(scene, &count));
    CHECK(count == 0, "a refused box added %zu particles", count);
    /* 1e6 particles: a 44 MB scene fits 500 MB, their solver (about 800 bytes
     * each) does not */
    MUST(mps2p_scene_set_param(scene, "memory_limit", 5e8));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0, 0, 1, 1));
    mps2p_solver *solver = NULL;
    status = mps2p_solver_create(scene, &solver);
    CHECK(status == MPS2P_ERR_NOMEM && solver == NULL, "a solver of 1e6 particles under 1 GB: %s",
          mps2p_status_string(status));
    CHECK(strstr(mps2p_last_error(), "a solver of 1000000 particles") != NULL, "message: %s",
          mps2p_last_error());
    mps2p_scene_destroy(scene);
    /* out of range */
    MUST(mps2p_scene_create(0.01, &scene));
    CHECK(mps2p_scene_set_param(scene, "memory_limit", -1.0) == MPS2P_ERR_INVALID, "negative");
    CHECK(mps2p_scene_set_param(scene, "memory_limit", INFINITY) == MPS2P_ERR_INVALID, "inf");
    mps2p_scene_destroy(scene);
}

/* The bytes a refusal names for a solver of this scene with `threads`. */
static double refused_bytes(mps2p_scene *scene, double threads)
{
    MUST(mps2p_scene_set_param(scene, "threads", threads));
    MUST(mps2p_scene_set_param(scene, "memory_limit", 1.0));
    mps2p_solver *solver = NULL;
    CHECK(mps2p_solver_create(scene, &solver) == MPS2P_ERR_NOMEM && !solver,
          "a solver under a limit of 1 byte");
    double bytes = 0.0;
    const char *take = strstr(mps2p_last_error(), "would take ");
    CHECK(take && sscanf(take, "would take %lg", &bytes) == 1, "message: %s", mps2p_last_error());
    return bytes;
}

/* With a team, each thread's run of the neighbour list or of the matrix is
 * built apart and copied in: the estimate counts that room (a solver near
 * the limit is refused with a message, not killed while it builds). */
static void test_estimate_counts_the_team(void)
{
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(0.01, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, &water));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0, 0, 1, 1));
    double one = refused_bytes(scene, 1), four = refused_bytes(scene, 4);
#ifdef LIBRARY_HAS_OPENMP
    CHECK(four > 1.2 * one && four < 2.0 * one, "estimate %g bytes with 4 threads, %g with 1",
          four, one);
    /* a limit between the two: one thread runs, four are refused */
    MUST(mps2p_scene_set_param(scene, "memory_limit", 0.5 * (one + four)));
    mps2p_solver *solver = NULL;
    MUST(mps2p_scene_set_param(scene, "threads", 1));
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_solver_destroy(solver);
    solver = NULL;
    MUST(mps2p_scene_set_param(scene, "threads", 4));
    CHECK(mps2p_solver_create(scene, &solver) == MPS2P_ERR_NOMEM && !solver,
          "4 threads over the limit");
#else
    CHECK(four == one, "without OpenMP one thread runs: %g against %g bytes", four, one);
#endif
    mps2p_scene_destroy(scene);
}

/* The default (memory_limit 0) is the memory the system gives the process:
 * a box of 1.5 times the machine's memory is refused at once, without an
 * allocation, whatever the machine (beyond a billion particles it is the
 * particle cap). */
static void test_default_limit(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    double machine = (double)pages * (double)page;
    double particles = 1.5 * machine / 44.0; /* a scene holds 44 bytes a particle */
    double side = sqrt(particles) * 0.001;
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(0.001, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000, 1e-6, &water));
    double start = cpu_seconds();
    int status = mps2p_scene_add_fluid_box(scene, water, 0, 0, side, side);
    CHECK(status == MPS2P_ERR_NOMEM || status == MPS2P_ERR_INVALID,
          "%.3g particles on a machine of %.3g bytes: %s", particles, machine,
          mps2p_status_string(status));
    CHECK(cpu_seconds() - start < 1.0, "the refusal took %g s", cpu_seconds() - start);
    printf("default limit: %.3g particles refused (%s)\n", particles, mps2p_last_error());
    mps2p_scene_destroy(scene);
}

/* A viscosity of 1e20 m^2/s: dt is 8e-25 s; advancing 1 s is refused at
 * once, naming the viscosity; one step still works. */
static void test_too_many_steps(void)
{
    mps2p_scene *scene;
    mps2p_solver *solver;
    int goo;
    MUST(mps2p_scene_create(0.02, &scene));
    MUST(mps2p_scene_add_fluid(scene, "goo", 1000, 1e20, &goo));
    MUST(mps2p_scene_add_fluid_box(scene, goo, 0, 0, 0.1, 0.2));
    MUST(mps2p_scene_add_tank(scene, 0, 0, 0.4, 0.3, 1));
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    double start = cpu_seconds();
    int status = mps2p_solver_advance_to(solver, 1.0, NULL, NULL);
    CHECK(status == MPS2P_ERR_INVALID, "advance_to(1 s) at dt 8e-25 s: %s",
          mps2p_status_string(status));
    CHECK(strstr(mps2p_last_error(), "nu = 1e+20") != NULL, "message: %s", mps2p_last_error());
    uint64_t taken = 1;
    status = mps2p_solver_advance_window(solver, 1.0, &taken);
    CHECK(status == MPS2P_ERR_INVALID && taken == 0, "advance_window: %s, %llu steps",
          mps2p_status_string(status), (unsigned long long)taken);
    CHECK(cpu_seconds() - start < 5.0, "the refusals took %g s", cpu_seconds() - start);
    MUST(mps2p_solver_step(solver));
    double t, dt;
    MUST(mps2p_solver_get_time(solver, &t));
    MUST(mps2p_solver_get_stat(solver, "dt_next", &dt));
    /* a window of a few steps goes on */
    MUST(mps2p_solver_advance_to(solver, t + 10 * dt, NULL, NULL));
    mps2p_solver_destroy(solver);
}

int main(void)
{
    test_memory_limit();
    test_default_limit();
    test_estimate_counts_the_team();
    test_too_many_steps();
    return check_summary("test_limits");
}
