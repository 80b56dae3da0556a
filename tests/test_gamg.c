/* pressure_solver "gamg" (PETSc's CG with algebraic multigrid, option
 * petsc): it agrees with CHOLMOD on the systems test_solvers uses, needs
 * fewer iterations than CG with Jacobi, gives the same bits for any thread
 * count and beside another solver in another thread, continues a
 * checkpoint bit for bit, and a solve that may not converge is
 * MPS2P_ERR_SOLVE with the state as it was. In a build
 * without PETSc: gamg is neither listed nor accepted (MPS2P_ERR_INVALID,
 * naming PETSc), then the test is skipped (77). */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "scenes.h"

static int gamg_listed(void)
{
    size_t options, choices;
    const char *key, *name;
    MUST(mps2p_option_count(&options));
    for (size_t i = 0; i < options; i++) {
        MUST(mps2p_option_info(i, &key, NULL, NULL, &choices));
        if (strcmp(key, "pressure_solver") != 0)
            continue;
        for (size_t c = 0; c < choices; c++) {
            MUST(mps2p_option_choice(i, c, &name));
            if (strcmp(name, "gamg") == 0)
                return 1;
        }
    }
    return 0;
}

/* Pressure after `steps` steps of the 0.2 m tank, and the last step's iterations. */
static double *pressure_after(const char *method, const char *preconditioner, double threads,
                              int steps, size_t *n, double *iterations)
{
    mps2p_scene *scene = tank_scene(0.01, 0.2, 0.2);
    MUST(mps2p_scene_set_option(scene, "pressure_solver", method));
    MUST(mps2p_scene_set_option(scene, "cg_preconditioner", preconditioner));
    MUST(mps2p_scene_set_param(scene, "threads", threads));
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    for (int s = 0; s < steps; s++)
        MUST(mps2p_solver_step(solver));
    MUST(mps2p_solver_particle_count(solver, n));
    double *p = malloc(*n * sizeof *p);
    MUST(mps2p_solver_get_pressure(solver, p, *n));
    MUST(mps2p_solver_get_stat(solver, "ppe_iterations", iterations));
    mps2p_solver_destroy(solver);
    return p;
}

typedef struct job {
    double *pressure;
    size_t n;
    double iterations;
} job;

static void *run_gamg(void *arg)
{
    job *j = arg;
    j->pressure = pressure_after("gamg", "jacobi", 1, 3, &j->n, &j->iterations);
    return NULL;
}

static void *run_cholmod(void *arg)
{
    job *j = arg;
    j->pressure = pressure_after("cholmod", "jacobi", 1, 3, &j->n, &j->iterations);
    return NULL;
}

static int same_bits(const double *a, const double *b, size_t n)
{
    return memcmp(a, b, n * sizeof *a) == 0;
}

int main(void)
{
    if (!gamg_listed()) {
        mps2p_scene *scene;
        MUST(mps2p_scene_create(0.01, &scene));
        int status = mps2p_scene_set_option(scene, "pressure_solver", "gamg");
        CHECK(status == MPS2P_ERR_INVALID, "gamg without PETSc: %s",
              mps2p_status_string(status));
        CHECK(strstr(mps2p_last_error(), "PETSc") != NULL, "message: %s", mps2p_last_error());
        const char *kept;
        MUST(mps2p_scene_get_option(scene, "pressure_solver", &kept));
        CHECK(strcmp(kept, "cg") == 0, "pressure_solver is %s after a refusal", kept);
        mps2p_scene_destroy(scene);
        if (check_failures)
            return check_summary("test_gamg");
        printf("test_gamg: built without PETSc (gamg refused, not listed): skipped\n");
        return 77;
    }

    /* 1. the one-step system of test_solvers: gamg against CHOLMOD */
    size_t n, n_gamg;
    double it_cholmod, it_gamg, it_jacobi;
    double *direct = pressure_after("cholmod", "jacobi", 1, 1, &n, &it_cholmod);
    double *gamg = pressure_after("gamg", "jacobi", 1, 1, &n_gamg, &it_gamg);
    double *jacobi = pressure_after("cg", "jacobi", 1, 1, &n_gamg, &it_jacobi);
    double worst = 0.0, largest = 0.0;
    for (size_t i = 0; i < n; i++) {
        worst = fmax(worst, fabs(direct[i] - gamg[i]));
        largest = fmax(largest, fabs(direct[i]));
    }
    printf("cholmod vs gamg: largest difference %.3g Pa of %.3g Pa; %g gamg iterations, %g "
           "cg (jacobi)\n", worst, largest, it_gamg, it_jacobi);
    CHECK(largest > 0.0, "no pressure at all after a step under gravity");
    CHECK(worst <= 1e-6 * largest, "gamg differs from cholmod by %g Pa", worst);
    CHECK(it_gamg > 0.0 && it_gamg < it_jacobi, "gamg took %g iterations, cg (jacobi) %g",
          it_gamg, it_jacobi);
    free(direct);
    free(gamg);
    free(jacobi);

    /* 2. a closed box filled with water: no free surface, SPD by compressibility only */
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(0.01, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.1, 0.1));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.1, 0.1, 0));
    double *box[2];
    for (int k = 0; k < 2; k++) {
        mps2p_solver *solver;
        MUST(mps2p_scene_set_option(scene, "pressure_solver", k ? "gamg" : "cholmod"));
        MUST(mps2p_solver_create(scene, &solver));
        for (int s = 0; s < 5; s++) {
            int status = mps2p_solver_step(solver);
            CHECK(status == MPS2P_OK, "closed box, %s, step %d: %s", k ? "gamg" : "cholmod", s,
                  mps2p_solver_last_error(solver));
        }
        MUST(mps2p_solver_particle_count(solver, &n));
        box[k] = malloc(n * sizeof *box[k]);
        MUST(mps2p_solver_get_pressure(solver, box[k], n));
        mps2p_solver_destroy(solver);
    }
    worst = largest = 0.0;
    for (size_t i = 0; i < n; i++) {
        worst = fmax(worst, fabs(box[0][i] - box[1][i]));
        largest = fmax(largest, fabs(box[0][i]));
    }
    printf("closed box, 5 steps: cholmod vs gamg largest difference %.3g Pa of %.3g Pa\n", worst,
           largest);
    CHECK(largest > 0.0 && worst <= 1e-6 * largest, "closed box: gamg differs by %g Pa of %g",
          worst, largest);
    free(box[0]);
    free(box[1]);

    /* 3. a gamg solve that may not converge: an error, the state as before */
    mps2p_solver *solver;
    MUST(mps2p_scene_set_option(scene, "pressure_solver", "gamg"));
    MUST(mps2p_scene_set_param(scene, "cg_max_iterations", 1));
    MUST(mps2p_solver_create(scene, &solver));
    MUST(mps2p_solver_particle_count(solver, &n));
    double *before = malloc(5 * n * sizeof *before), *after = malloc(5 * n * sizeof *after);
    MUST(mps2p_solver_get_positions(solver, before, 2 * n));
    MUST(mps2p_solver_get_velocities(solver, before + 2 * n, 2 * n));
    MUST(mps2p_solver_get_pressure(solver, before + 4 * n, n));
    int status = mps2p_solver_step(solver);
    CHECK(status == MPS2P_ERR_SOLVE, "expected MPS2P_ERR_SOLVE, got %s",
          mps2p_status_string(status));
    CHECK(strstr(mps2p_solver_last_error(solver), "gamg did not converge") != NULL,
          "message: %s", mps2p_solver_last_error(solver));
    printf("one iteration allowed: %s\n", mps2p_solver_last_error(solver));
    uint64_t steps;
    double t;
    MUST(mps2p_solver_get_step_count(solver, &steps));
    MUST(mps2p_solver_get_time(solver, &t));
    CHECK(steps == 0 && t == 0.0, "a failed step advanced the solver (%llu steps, t = %g)",
          (unsigned long long)steps, t);
    MUST(mps2p_solver_get_positions(solver, after, 2 * n));
    MUST(mps2p_solver_get_velocities(solver, after + 2 * n, 2 * n));
    MUST(mps2p_solver_get_pressure(solver, after + 4 * n, n));
    CHECK(same_bits(before, after, 5 * n), "a failed gamg step changed the state");
    free(before);
    free(after);
    mps2p_solver_destroy(solver);
    mps2p_scene_destroy(scene);

    /* 4. the same bits for 1 and 2 threads, and beside a CHOLMOD and another
     * gamg solver in other threads */
    size_t n_one, n_two;
    double iterations;
    double *one = pressure_after("gamg", "jacobi", 1, 3, &n_one, &iterations);
    double *two = pressure_after("gamg", "jacobi", 2, 3, &n_two, &iterations);
    CHECK(n_one == n_two && same_bits(one, two, n_one), "gamg: 2 threads differ from 1");
    job jobs[3] = {{0}};
    pthread_t threads[3];
    for (int i = 0; i < 3; i++)
        CHECK(pthread_create(&threads[i], NULL, i == 2 ? run_cholmod : run_gamg, &jobs[i]) == 0,
              "thread %d", i);
    for (int i = 0; i < 3; i++)
        pthread_join(threads[i], NULL);
    for (int i = 0; i < 2; i++)
        CHECK(jobs[i].n == n_one && same_bits(jobs[i].pressure, one, n_one),
              "gamg in thread %d differs from the run alone", i);
    for (int i = 0; i < 3; i++)
        free(jobs[i].pressure);
    free(one);
    free(two);

    /* 5. a checkpoint continues bit for bit: nothing of the solve is carried
     * between steps but the pressure (the initial guess), which is saved */
    char dir[] = "/tmp/mps2p-gamg-XXXXXX", path[64];
    CHECK(mkdtemp(dir) != NULL, "mkdtemp");
    snprintf(path, sizeof path, "%s/gamg.chk", dir);
    scene = dam_break_scene(0.01);
    MUST(mps2p_scene_set_option(scene, "pressure_solver", "gamg"));
    mps2p_solver *run, *restored;
    MUST(mps2p_solver_create(scene, &run));
    mps2p_scene_destroy(scene);
    for (int s = 0; s < 3; s++)
        MUST(mps2p_solver_step(run));
    MUST(mps2p_solver_save_checkpoint(run, path));
    MUST(mps2p_solver_load_checkpoint(path, &restored));
    for (int s = 0; s < 3; s++) {
        MUST(mps2p_solver_step(run));
        MUST(mps2p_solver_step(restored));
    }
    MUST(mps2p_solver_particle_count(run, &n));
    double *a = malloc(3 * n * sizeof *a), *b = malloc(3 * n * sizeof *b);
    MUST(mps2p_solver_get_positions(run, a, 2 * n));
    MUST(mps2p_solver_get_pressure(run, a + 2 * n, n));
    MUST(mps2p_solver_get_positions(restored, b, 2 * n));
    MUST(mps2p_solver_get_pressure(restored, b + 2 * n, n));
    CHECK(same_bits(a, b, 3 * n), "the restored gamg run differs from the one it was saved from");
    free(a);
    free(b);
    mps2p_solver_destroy(run);
    mps2p_solver_destroy(restored);
    unlink(path);
    rmdir(dir);
    return check_summary("test_gamg");
}
