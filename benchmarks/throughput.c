#define _POSIX_C_SOURCE 200809L /* clock_gettime */
/* Throughput at growing particle counts: the water-only dam break of
 * PySPH's dam_break_2d geometry (water column 1 m wide, 2 m high, in a 4 m
 * tank), at spacings from 0.04 m down. For each: particles, wall time per
 * step (after a few warm-up steps), particle-steps per second, time per
 * simulated second (wall per step / dt), memory per particle, and the
 * fitted growth exponents. Prints Markdown.
 *
 *   throughput [steps [solver [l0 ...]]]     solver: cholmod (default) or cg */
#include <mps2p.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static void check(int status, const char *what)
{
    if (status < 0) {
        fprintf(stderr, "%s: %s\n", what, mps2p_last_error());
        exit(1);
    }
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* least-squares slope of log y against log x */
static double slope(const double *x, const double *y, int n)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int k = 0; k < n; k++) {
        double lx = log(x[k]), ly = log(y[k]);
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

int main(int argc, char **argv)
{
    int steps = argc > 1 ? atoi(argv[1]) : 20;
    const char *solver_kind = argc > 2 ? argv[2] : "cholmod";
    double default_levels[] = {0.04, 0.02, 0.01, 0.0066, 0.005};
    int count = argc > 3 ? argc - 3 : 5;
    double levels[16];
    for (int k = 0; k < count && k < 16; k++)
        levels[k] = argc > 3 ? atof(argv[3 + k]) : default_levels[k];

    double particles[16], per_step[16], memory[16];
    printf("Water-only dam break (1 m x 2 m column, 4 m tank), pressure solver %s, "
           "%d steps after 3 warm-up steps:\n\n", solver_kind, steps);
    printf("| l0 (m) | particles | ms per step | particle-steps/s | dt (s) | "
           "wall s per simulated s | memory bytes per particle |\n");
    printf("|---|---|---|---|---|---|---|\n");
    for (int k = 0; k < count; k++) {
        mps2p_scene *scene;
        int water;
        check(mps2p_scene_create(levels[k], &scene), "scene");
        check(mps2p_scene_set_option(scene, "pressure_solver", solver_kind), "solver kind");
        if (getenv("MPS2P_THREADS")) /* parameter threads (docs/performance.md) */
            check(mps2p_scene_set_param(scene, "threads", atof(getenv("MPS2P_THREADS"))),
                  "threads");
        check(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water), "fluid");
        check(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 1.0, 2.0), "column");
        check(mps2p_scene_add_tank(scene, 0.0, 0.0, 4.0, 2.5, 1), "tank");
        mps2p_solver *solver;
        check(mps2p_solver_create(scene, &solver), "solver");
        mps2p_scene_destroy(scene);
        size_t n;
        check(mps2p_solver_particle_count(solver, &n), "count");
        for (int s = 0; s < 3; s++)
            check(mps2p_solver_step(solver), "warm-up step");
        double start = now(), dt_sum = 0.0;
        for (int s = 0; s < steps; s++) {
            double dt;
            check(mps2p_solver_step(solver), "step");
            check(mps2p_solver_get_last_dt(solver, &dt), "dt");
            dt_sum += dt;
        }
        double wall = (now() - start) / steps, dt = dt_sum / steps, bytes;
        check(mps2p_solver_get_stat(solver, "memory_bytes", &bytes), "memory");
        particles[k] = (double)n;
        per_step[k] = wall;
        memory[k] = bytes / (double)n;
        printf("| %g | %zu | %.2f | %.3g | %.2e | %.0f | %.0f |\n", levels[k], n, 1e3 * wall,
               (double)n / wall, dt, wall / dt, memory[k]);
        fflush(stdout);
        mps2p_solver_destroy(solver);
    }
    if (count >= 2) {
        printf("\nTime per step grows as particles^%.2f; memory per particle as "
               "particles^%.2f (0 = linear memory).\n", slope(particles, per_step, count),
               slope(particles, memory, count));
    }
    return 0;
}
