#define _POSIX_C_SOURCE 200809L /* clock_gettime */
/* Throughput at growing particle counts, two cases:
 *
 *   water      the water-only dam break of PySPH's dam_break_2d geometry (water
 *              column 1 m wide, 2 m high, in a 4 m tank), spacings 0.04 m down
 *              to 0.0045 m (about 107,000 particles);
 *   two_phase  the paper's dam break with air (examples/scenes/
 *              ikari2003_dam_break_air.toml: water 0.15 x 0.3 m at the left
 *              wall of a 0.6 m tank, air up to 0.7 m, tank 0.8 m high, open
 *              top; two_step_improved with the drift reaction, fixed dt 2e-4 s),
 *              spacings 0.02 m down to 0.0025 m. The steps timed are the first
 *              ones (t < 0.01 s), well before the prototype's divergence
 *              (after 0.2 s, docs/two-phase.md).
 *
 * For each: particles, wall time and CPU time per step (after 3 warm-up
 * steps), particle-steps per second (wall), time per simulated second (wall
 * per step / dt), memory per particle, and the fitted growth exponents (of
 * wall and CPU time). Prints Markdown; then, for each l0, the stages that
 * took most of the timed steps' wall time and the process's peak resident
 * memory so far (run one l0 per process for each l0's own peak).
 *
 *   throughput [steps [solver [case] [l0 ...]]]
 *       solver: cholmod (this tool's default; the library's is cg), cg, or gamg (a build
 *       with PETSc); case: water (default) or two_phase. MPS2P_PRECONDITIONER=jacobi, ic0
 *       or two_level sets CG's preconditioner (default: the library's, two_level). */
#include <mps2p.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

static void check(int status, const char *what)
{
    if (status < 0) {
        fprintf(stderr, "%s: %s\n", what, mps2p_last_error());
        exit(1);
    }
}

static double seconds(clockid_t clock)
{
    struct timespec t;
    clock_gettime(clock, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double now(void) { return seconds(CLOCK_MONOTONIC); }

/* this process's CPU time: on a shared machine, wall time includes waiting for
 * a core; CPU time (one thread) mostly does not */
static double cpu_now(void) { return seconds(CLOCK_PROCESS_CPUTIME_ID); }

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
    int first = 3; /* first l0 argument */
    int two_phase = 0;
    if (argc > 3 && (strcmp(argv[3], "water") == 0 || strcmp(argv[3], "two_phase") == 0)) {
        two_phase = strcmp(argv[3], "two_phase") == 0;
        first = 4;
    }
    const double water_levels[] = {0.04, 0.02, 0.01, 0.0066, 0.005, 0.0045};
    const double two_phase_levels[] = {0.02, 0.01, 0.005, 0.0025};
    const double *default_levels = two_phase ? two_phase_levels : water_levels;
    int count = argc > first ? argc - first : (two_phase ? 4 : 6);
    if (count > 16)
        count = 16;
    double levels[16];
    for (int k = 0; k < count; k++)
        levels[k] = argc > first ? atof(argv[first + k]) : default_levels[k];

    double particles[16], per_step[16], cpu_per_step[16], memory[16];
    static char stage_line[16][256];
    if (two_phase)
        printf("Two-phase dam break (water 0.15 m x 0.3 m, air to 0.7 m, 0.6 m tank; "
               "two_step_improved, drift), pressure solver %s, %d steps after 3 warm-up "
               "steps:\n\n", solver_kind, steps);
    else
        printf("Water-only dam break (1 m x 2 m column, 4 m tank), pressure solver %s, "
               "%d steps after 3 warm-up steps:\n\n", solver_kind, steps);
    printf("| l0 (m) | particles | ms per step | CPU ms per step | particle-steps/s | dt (s) | "
           "wall s per simulated s | memory bytes per particle |\n");
    printf("|---|---|---|---|---|---|---|---|\n");
    for (int k = 0; k < count; k++) {
        mps2p_scene *scene;
        int water;
        check(mps2p_scene_create(levels[k], &scene), "scene");
        check(mps2p_scene_set_option(scene, "pressure_solver", solver_kind), "solver kind");
        if (getenv("MPS2P_PRECONDITIONER"))
            check(mps2p_scene_set_option(scene, "cg_preconditioner",
                                         getenv("MPS2P_PRECONDITIONER")),
                  "cg_preconditioner");
        if (getenv("MPS2P_THREADS")) /* parameter threads (docs/performance.md) */
            check(mps2p_scene_set_param(scene, "threads", atof(getenv("MPS2P_THREADS"))),
                  "threads");
        check(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water), "fluid");
        if (two_phase) {
            int air;
            check(mps2p_scene_set_param(scene, "dt", 2.0e-4), "dt");
            check(mps2p_scene_set_option(scene, "two_phase_model", "two_step_improved"),
                  "two_phase_model");
            check(mps2p_scene_set_option(scene, "interface_reaction", "drift"), "reaction");
            check(mps2p_scene_add_fluid(scene, "air", 1.2, 1.5e-5, &air), "air");
            check(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.15, 0.3), "column");
            check(mps2p_scene_add_fluid_box(scene, air, 0.15, 0.0, 0.6, 0.7), "air right");
            check(mps2p_scene_add_fluid_box(scene, air, 0.0, 0.3, 0.15, 0.7), "air above");
            check(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.6, 0.8, 1), "tank");
        } else {
            check(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 1.0, 2.0), "column");
            check(mps2p_scene_add_tank(scene, 0.0, 0.0, 4.0, 2.5, 1), "tank");
        }
        mps2p_solver *solver;
        check(mps2p_solver_create(scene, &solver), "solver");
        mps2p_scene_destroy(scene);
        size_t n;
        check(mps2p_solver_particle_count(solver, &n), "count");
        for (int s = 0; s < 3; s++)
            check(mps2p_solver_step(solver), "warm-up step");
        check(mps2p_solver_reset_stage_timings(solver), "stage timings");
        double iterations_before, iterations_after;
        check(mps2p_solver_get_stat(solver, "ppe_iterations_total", &iterations_before),
              "iterations");
        double start = now(), cpu_start = cpu_now(), dt_sum = 0.0;
        for (int s = 0; s < steps; s++) {
            double dt;
            check(mps2p_solver_step(solver), "step");
            check(mps2p_solver_get_last_dt(solver, &dt), "dt");
            dt_sum += dt;
        }
        double wall = (now() - start) / steps, cpu = (cpu_now() - cpu_start) / steps, dt = dt_sum / steps, bytes, active = 1.0;
        if (two_phase) {
            check(mps2p_solver_get_stat(solver, "two_phase_active", &active), "two_phase_active");
            if (active != 1.0) {
                fprintf(stderr, "l0 = %g: the two-phase model is not active\n", levels[k]);
                exit(1);
            }
        }
        check(mps2p_solver_get_stat(solver, "memory_bytes", &bytes), "memory");
        check(mps2p_solver_get_stat(solver, "ppe_iterations_total", &iterations_after),
              "iterations");
        particles[k] = (double)n;
        per_step[k] = wall;
        cpu_per_step[k] = cpu;
        memory[k] = bytes / (double)n;
        printf("| %g | %zu | %.2f | %.2f | %.3g | %.2e | %.0f | %.0f |\n", levels[k], n,
               1e3 * wall, 1e3 * cpu, (double)n / wall, dt, wall / dt, memory[k]);
        fflush(stdout);
        /* the three slowest stages of the timed steps, as shares of their wall time */
        size_t stages;
        check(mps2p_solver_stage_count(solver, &stages), "stage count");
        const char *top_name[3] = {"", "", ""};
        double top_seconds[3] = {0.0, 0.0, 0.0};
        for (size_t i = 0; i < stages; i++) {
            const char *name;
            double t;
            check(mps2p_solver_get_stage(solver, i, &name, NULL, &t, NULL), "stage");
            for (int r = 0; r < 3; r++) {
                if (t > top_seconds[r]) {
                    for (int q = 2; q > r; q--) {
                        top_seconds[q] = top_seconds[q - 1];
                        top_name[q] = top_name[q - 1];
                    }
                    top_seconds[r] = t;
                    top_name[r] = name;
                    break;
                }
            }
        }
        struct rusage usage;
        getrusage(RUSAGE_SELF, &usage);
        int written = snprintf(stage_line[k], sizeof stage_line[k],
                               "- l0 = %g (%zu particles): peak resident memory %.0f bytes per "
                               "particle; stages",
                               levels[k], n, 1024.0 * (double)usage.ru_maxrss / (double)n);
        for (int r = 0; r < 3 && written > 0 && (size_t)written < sizeof stage_line[k]; r++)
            written += snprintf(stage_line[k] + written, sizeof stage_line[k] - (size_t)written,
                                " %s %.0f %%", top_name[r],
                                100.0 * top_seconds[r] / (wall * steps));
        if (written > 0 && (size_t)written < sizeof stage_line[k])
            snprintf(stage_line[k] + written, sizeof stage_line[k] - (size_t)written,
                     "; %.0f solver iterations a step",
                     (iterations_after - iterations_before) / steps);
        mps2p_solver_destroy(solver);
    }
    if (count >= 2) {
        printf("\nTime per step grows as particles^%.2f (CPU time: particles^%.2f); memory per "
               "particle as particles^%.2f (0 = linear memory).\n",
               slope(particles, per_step, count), slope(particles, cpu_per_step, count),
               slope(particles, memory, count));
    }
    printf("\nSlowest stages (share of the timed steps' wall time) and the process's peak "
           "resident memory:\n\n");
    for (int k = 0; k < count; k++)
        printf("%s\n", stage_line[k]);
    return 0;
}
