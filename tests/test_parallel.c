/* The particle loops in parallel (OpenMP, parameter threads): the same short
 * dam break with 1, 2 and 3 threads, and twice with 2, gives bitwise the same
 * positions, velocities and pressure; so do a CG solve of more than one
 * reduction block, a water column collapsing under air (two phases: its
 * scan, number densities, correction per phase and both CG solves) and an
 * air bubble in water (its flood fill beside the scan), and a failed solve
 * there reports on the calling thread. Bad thread counts are refused. Without OpenMP every count
 * runs on one thread, and the test holds trivially. */
#include <string.h>
#include "scenes.h"

typedef struct result {
    size_t n;
    double *state; /* positions (2n), velocities (2n), pressure (n) */
    double ppe_unknowns, gas_ppe_unknowns; /* of the last step (0 without gas) */
} result;

static result run(mps2p_scene *scene, double threads, int steps)
{
    result out = {0, NULL, 0.0, 0.0};
    mps2p_solver *solver;
    MUST(mps2p_scene_set_param(scene, "threads", threads));
    MUST(mps2p_solver_create(scene, &solver));
    for (int k = 0; k < steps; k++)
        MUST(mps2p_solver_step(solver));
    MUST(mps2p_solver_particle_count(solver, &out.n));
    MUST(mps2p_solver_get_stat(solver, "ppe_unknowns", &out.ppe_unknowns));
    MUST(mps2p_solver_get_stat(solver, "gas_ppe_unknowns", &out.gas_ppe_unknowns));
    double used;
    MUST(mps2p_solver_get_stat(solver, "threads", &used));
#ifdef LIBRARY_HAS_OPENMP
    CHECK(used == threads, "statistic threads %g with parameter threads %g", used, threads);
#else
    CHECK(used == 1.0, "statistic threads %g without OpenMP", used);
#endif
    out.state = malloc(5 * out.n * sizeof *out.state);
    if (!out.state) {
        fprintf(stderr, "test_parallel: out of memory\n");
        exit(1);
    }
    MUST(mps2p_solver_get_positions(solver, out.state, 2 * out.n));
    MUST(mps2p_solver_get_velocities(solver, out.state + 2 * out.n, 2 * out.n));
    MUST(mps2p_solver_get_pressure(solver, out.state + 4 * out.n, out.n));
    mps2p_solver_destroy(solver);
    return out;
}

static int same(result a, result b)
{
    return a.n == b.n && memcmp(a.state, b.state, 5 * a.n * sizeof *a.state) == 0;
}

/* Runs scene with 1, 2, 2 again and 3 threads; all must agree bit for bit.
 * Returns the one-thread run's unknowns (liquid, gas) in last_unknowns. */
static double last_unknowns[2];
static void compare_counts(mps2p_scene *scene, int steps, const char *what)
{
    result one = run(scene, 1, steps), two = run(scene, 2, steps);
    last_unknowns[0] = one.ppe_unknowns;
    last_unknowns[1] = one.gas_ppe_unknowns;
    result again = run(scene, 2, steps), three = run(scene, 3, steps);
    CHECK(same(one, two), "%s: 2 threads differ from 1", what);
    CHECK(same(two, again), "%s: two runs with 2 threads differ", what);
    CHECK(same(one, three), "%s: 3 threads differ from 1", what);
    free(one.state);
    free(two.state);
    free(again.state);
    free(three.state);
}

int main(void)
{
    /* the paper's dam break, CHOLMOD: the particle loops and the assembly */
    mps2p_scene *scene = dam_break_scene(0.01);
    MUST(mps2p_scene_set_option(scene, "pressure_solver", "cholmod"));
    compare_counts(scene, 60, "dam break (cholmod)");
    /* a CG solve over more than one block of REDUCTION_BLOCK unknowns, and the
     * assembly in runs of rows, one a thread (smaller systems are one run) */
    mps2p_scene *column;
    int water;
    MUST(mps2p_scene_create(0.02, &column));
    MUST(mps2p_scene_add_fluid(column, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_add_fluid_box(column, water, 0.0, 0.0, 1.0, 2.0));
    MUST(mps2p_scene_add_tank(column, 0.0, 0.0, 4.0, 3.0, 1));
    MUST(mps2p_scene_set_option(column, "pressure_solver", "cg"));
    MUST(mps2p_scene_set_option(column, "cg_preconditioner", "jacobi"));
    compare_counts(column, 4, "1 m x 2 m column (cg with Jacobi, about 5000 unknowns)");
    MUST(mps2p_scene_set_option(column, "cg_preconditioner", "two_level"));
    compare_counts(column, 4, "1 m x 2 m column (cg with the two-level preconditioner)");
    /* IC(0)'s triangular solves on the team's first thread (cg_iterations) */
    MUST(mps2p_scene_set_option(column, "cg_preconditioner", "ic0"));
    compare_counts(column, 4, "1 m x 2 m column (cg with IC(0))");
    mps2p_scene_destroy(column);

    /* two phases: the sector scan, the number densities each phase sees, the
     * correction per phase and both CG solves */
    mps2p_scene *air_column;
    int air;
    MUST(mps2p_scene_create(0.02, &air_column));
    MUST(mps2p_scene_add_fluid(air_column, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_add_fluid(air_column, "air", 1.2, 1.5e-5, &air));
    MUST(mps2p_scene_add_fluid_box(air_column, water, 0.0, 0.0, 0.16, 0.3));
    MUST(mps2p_scene_add_fluid_box(air_column, air, 0.16, 0.0, 0.6, 0.7));
    MUST(mps2p_scene_add_fluid_box(air_column, air, 0.0, 0.3, 0.16, 0.7));
    MUST(mps2p_scene_add_tank(air_column, 0.0, 0.0, 0.6, 1.0, 1));
    MUST(mps2p_scene_set_option(air_column, "pressure_solver", "cg"));
    MUST(mps2p_scene_set_param(air_column, "dt", 1e-3));
    compare_counts(air_column, 60, "water column under air (two phases, cg)");
    /* a liquid solve that fails while the gas is prepared beside it: its
     * message is the calling thread's (SIDE_BY_SIDE runs it there) */
    MUST(mps2p_scene_set_param(air_column, "threads", 2));
    MUST(mps2p_scene_set_param(air_column, "cg_max_iterations", 1));
    for (int k = 0; k < 20; k++) {
        mps2p_solver *failing;
        MUST(mps2p_solver_create(air_column, &failing));
        int status = MPS2P_OK;
        for (int step = 0; step < 20 && status == MPS2P_OK; step++)
            status = mps2p_solver_step(failing);
        CHECK(status == MPS2P_ERR_SOLVE, "cg_max_iterations 1: status %d, not a failed solve",
              status);
        CHECK(strstr(mps2p_last_error(), "pressure solve failed") != NULL &&
                  strcmp(mps2p_last_error(), mps2p_solver_last_error(failing)) == 0,
              "a failed solve on two threads: the caller's message is \"%s\", the solver's "
              "\"%s\"", mps2p_last_error(), mps2p_solver_last_error(failing));
        mps2p_solver_destroy(failing);
    }
    MUST(mps2p_scene_set_param(air_column, "cg_max_iterations", 0));
    MUST(mps2p_scene_set_param(air_column, "threads", 1));
    /* both paths with threads: the liquid's system in one run (under
     * REDUCTION_BLOCK = 1024 unknowns), solved beside the gas's preparation
     * (SIDE_BY_SIDE), the gas's, with its mask of participants, in runs */
    CHECK(last_unknowns[0] > 0 && last_unknowns[0] < 1024, "liquid unknowns %g, not under 1024",
          last_unknowns[0]);
    CHECK(last_unknowns[1] >= 1024, "gas unknowns %g, under 1024: the runs untested",
          last_unknowns[1]);
    mps2p_scene_destroy(air_column);

    /* an air bubble held in water: its flood fill runs beside the sector
     * scan on two threads (interface_scan); at the end of the steps
     * compared it is still a bubble (cut off from the air above) */
    mps2p_scene *bubble = air_pocket_scene(0.15, 0.25);
    MUST(mps2p_scene_set_option(bubble, "pressure_solver", "cg"));
    MUST(mps2p_scene_set_param(bubble, "dt", 1e-3));
    compare_counts(bubble, 40, "an air bubble in water (two phases, its flood fill)");
    mps2p_solver *held;
    double in_bubbles;
    MUST(mps2p_scene_set_param(bubble, "threads", 2));
    MUST(mps2p_solver_create(bubble, &held));
    for (int step = 0; step < 40; step++)
        MUST(mps2p_solver_step(held));
    MUST(mps2p_solver_get_stat(held, "gas_in_bubbles", &in_bubbles));
    CHECK(in_bubbles >= 8.0, "gas in bubbles after 40 steps: %g of the 16, the path untested",
          in_bubbles);
    mps2p_solver_destroy(held);
    mps2p_scene_destroy(bubble);

    /* 0 = OpenMP's default; whole numbers in [0, 1024] only */
    CHECK(mps2p_scene_set_param(scene, "threads", 0) == MPS2P_OK, "threads 0 refused");
    mps2p_solver *every_core;
    double used;
    MUST(mps2p_solver_create(scene, &every_core));
    MUST(mps2p_solver_get_stat(every_core, "threads", &used));
    CHECK(used >= 1.0 && used == (double)(int)used, "threads 0: statistic threads %g", used);
    mps2p_solver_destroy(every_core);
    CHECK(mps2p_scene_set_param(scene, "threads", -1) == MPS2P_ERR_INVALID, "threads -1 taken");
    CHECK(mps2p_scene_set_param(scene, "threads", 1.5) == MPS2P_ERR_INVALID,
          "threads 1.5 taken");
    CHECK(mps2p_scene_set_param(scene, "threads", 1e9) == MPS2P_ERR_INVALID, "threads 1e9 taken");
    mps2p_scene_destroy(scene);
    return check_summary("test_parallel");
}
