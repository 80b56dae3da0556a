#define _POSIX_C_SOURCE 200809L /* clock_gettime */
/* What each effect costs: the water-only dam break (l0 = 0.01 m, to 0.3 s)
 * with every effect as the scene infers it, then with one effect switched
 * off at a time. Prints, as Markdown: time per step per stage, total, memory,
 * and the cost of each effect as the difference of the runs; and what timing
 * the stages costs (two clock reads per stage).
 *
 *   effects [l0 [end_time [repeats [water|air]]]]
 *
 * "air" runs the paper's case instead (examples/scenes/ikari2003_dam_break_air
 * .toml: water and air, the two-phase prototype, dt 2e-4 s, CG), and its
 * variants switch off viscosity, collision and the interface reaction, and
 * switch turbulence on.
 *
 * The fastest of `repeats` runs is reported (a shared machine is noisy). */
#include <mps2p.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_STAGES 32

typedef struct run_result {
    double total, per_stage[MAX_STAGES], memory;
    double diverged_at; /* the time of the last good state when it diverged, else -1 */
    uint64_t steps, calls[MAX_STAGES];
    int active[MAX_STAGES];
} run_result;

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

static int with_air = 0;

static mps2p_scene *paper_scene(double l0)
{
    mps2p_scene *scene;
    int water, air;
    check(mps2p_scene_create(l0, &scene), "scene");
    check(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water), "fluid");
    check(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.15, 0.3), "column");
    if (getenv("MPS2P_THREADS")) /* parameter threads (docs/performance.md) */
        check(mps2p_scene_set_param(scene, "threads", atof(getenv("MPS2P_THREADS"))), "threads");
    if (with_air) {
        check(mps2p_scene_add_fluid(scene, "air", 1.2, 1.5e-5, &air), "air");
        check(mps2p_scene_add_fluid_box(scene, air, 0.15, 0.0, 0.6, 0.7), "air right");
        check(mps2p_scene_add_fluid_box(scene, air, 0.0, 0.3, 0.15, 0.7), "air above");
        check(mps2p_scene_set_param(scene, "dt", 2e-4), "dt");
        check(mps2p_scene_set_option(scene, "pressure_solver", "cg"), "solver");
        check(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.6, 0.8, 1), "tank");
    } else {
        check(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.6, 0.7, 1), "tank");
    }
    return scene;
}

/* "name" switches effect.name off; "+name" switches it on. */
static run_result run(double l0, double end, const char *off)
{
    mps2p_scene *scene = paper_scene(l0);
    if (off) {
        char key[64];
        snprintf(key, sizeof key, "effect.%s", off[0] == '+' ? off + 1 : off);
        check(mps2p_scene_set_option(scene, key, off[0] == '+' ? "on" : "off"), key);
    }
    mps2p_solver *solver;
    check(mps2p_solver_create(scene, &solver), "solver");
    mps2p_scene_destroy(scene);
    run_result r = {0};
    r.diverged_at = -1.0;
    double start = now();
    int status = mps2p_solver_advance_to(solver, end, NULL, NULL);
    r.total = now() - start;
    /* a variant can diverge (the corrected scheme needs the collision model):
     * its table column says so, timed over the steps it made */
    if (status == MPS2P_ERR_DIVERGED) {
        fprintf(stderr, "%s: %s\n", off ? off : "all inferred", mps2p_last_error());
        check(mps2p_solver_get_time(solver, &r.diverged_at), "time");
    } else {
        check(status, "run");
    }
    check(mps2p_solver_get_step_count(solver, &r.steps), "steps");
    check(mps2p_solver_get_stat(solver, "memory_bytes", &r.memory), "memory");
    size_t stages;
    check(mps2p_solver_stage_count(solver, &stages), "stages");
    for (size_t k = 0; k < stages && k < MAX_STAGES; k++)
        check(mps2p_solver_get_stage(solver, k, NULL, &r.active[k], &r.per_stage[k],
                                     &r.calls[k]), "stage");
    mps2p_solver_destroy(solver);
    return r;
}

static run_result fastest(double l0, double end, const char *off, int repeats)
{
    run_result best = run(l0, end, off);
    for (int k = 1; k < repeats; k++) {
        run_result r = run(l0, end, off);
        if (r.total < best.total)
            best = r;
    }
    return best;
}

int main(int argc, char **argv)
{
    double l0 = argc > 1 ? atof(argv[1]) : 0.01;
    double end = argc > 2 ? atof(argv[2]) : 0.3;
    int repeats = argc > 3 ? atoi(argv[3]) : 3;
    with_air = argc > 4 && strcmp(argv[4], "air") == 0;
    const char *water_effects[] = {NULL, "viscosity", "collision", "gravity"};
    const char *water_labels[] = {"all inferred", "viscosity off", "collision off",
                                  "gravity off"};
    const char *air_effects[] = {NULL, "viscosity", "collision", "interface_reaction",
                                 "+turbulence"};
    const char *air_labels[] = {"all inferred", "viscosity off", "collision off",
                                "interface_reaction off", "turbulence on"};
    const char **effects = with_air ? air_effects : water_effects;
    const char **labels = with_air ? air_labels : water_labels;
    const int variants = with_air ? 5 : 4;
    run_result results[5];
    for (int e = 0; e < variants; e++)
        results[e] = fastest(l0, end, effects[e], repeats);

    /* stage names, from a throw-away solver */
    mps2p_scene *scene = paper_scene(l0);
    mps2p_solver *solver;
    check(mps2p_solver_create(scene, &solver), "solver");
    mps2p_scene_destroy(scene);
    size_t stages;
    check(mps2p_solver_stage_count(solver, &stages), "stages");

    printf("%s, l0 = %g m, to t = %g s, fastest of %d runs, microseconds per step:\n\n"
           "| stage |", with_air ? "The paper's dam break with air (two-phase prototype)"
                                  : "Water-only dam break", l0, end, repeats);
    for (int e = 0; e < variants; e++)
        printf(" %s |", labels[e]);
    printf("\n|---|");
    for (int e = 0; e < variants; e++)
        printf("---|");
    printf("\n");
    for (size_t k = 0; k < stages; k++) {
        const char *name;
        check(mps2p_solver_get_stage(solver, k, &name, NULL, NULL, NULL), "stage");
        int any = 0;
        for (int e = 0; e < variants; e++)
            any |= results[e].active[k];
        if (!any)
            continue; /* a stage no variant runs */
        printf("| %s |", name);
        for (int e = 0; e < variants; e++) {
            const run_result *r = &results[e];
            if (r->active[k])
                printf(" %.1f |", 1e6 * r->per_stage[k] / (double)r->steps);
            else
                printf(" off |");
        }
        printf("\n");
    }
    printf("| reached |");
    for (int e = 0; e < variants; e++)
        if (results[e].diverged_at >= 0.0)
            printf(" diverged at %.4g s |", results[e].diverged_at);
        else
            printf(" %g s |", end);
    printf("\n| **total per step** |");
    for (int e = 0; e < variants; e++)
        printf(" **%.1f** |", 1e6 * results[e].total / (double)results[e].steps);
    printf("\n| steps |");
    for (int e = 0; e < variants; e++)
        printf(" %llu |", (unsigned long long)results[e].steps);
    printf("\n| solver memory (bytes) |");
    for (int e = 0; e < variants; e++)
        printf(" %.0f |", results[e].memory);
    printf("\n\nCost of each effect per step: its own stage in the all-inferred run, and the "
           "whole step with it minus without it\n(the second also holds what the effect does "
           "to the flow: without gravity nothing moves, so nothing needs solving).\n\n"
           "| effect | own stage (us/step) | share of the step | step with minus without "
           "(us) |\n|---|---|---|---|\n");
    double with = 1e6 * results[0].total / (double)results[0].steps;
    for (int e = 1; e < variants; e++) {
        const char *effect = effects[e][0] == '+' ? effects[e] + 1 : effects[e];
        double own = 0.0;
        for (size_t k = 0; k < stages; k++) {
            const char *name;
            check(mps2p_solver_get_stage(solver, k, &name, NULL, NULL, NULL), "stage");
            int on_run = effects[e][0] == '+' ? e : 0; /* where the effect is on */
            if (strcmp(name, effect) == 0 ||
                (strcmp(effect, "interface_reaction") == 0 &&
                 (strcmp(name, "interface_join") == 0 || strcmp(name, "interface_drift") == 0)))
                own += 1e6 * results[on_run].per_stage[k] / (double)results[on_run].steps;
        }
        double other = 1e6 * results[e].total / (double)results[e].steps;
        double on = effects[e][0] == '+' ? other : with, off = effects[e][0] == '+' ? with : other;
        printf("| %s | %.1f | %.1f %% | %.1f%s |\n", effect, own, 100.0 * own / on, on - off,
               results[e].diverged_at < 0.0 ? ""
               : effects[e][0] == '+'       ? " (with it the run diverged)"
                                            : " (without it the run diverged)");
    }

    /* what the stage timers cost: two clock reads per stage per step */
    const int reads = 1000000;
    double start = now(), sink = 0.0;
    for (int k = 0; k < reads; k++)
        sink += now();
    double per_read = (now() - start) / reads;
    size_t active = 0;
    for (size_t k = 0; k < stages; k++)
        active += results[0].active[k] != 0;
    double per_step = 1e6 * results[0].total / (double)results[0].steps;
    printf("\nTiming overhead: one clock read takes %.0f ns; a step makes about %zu "
           "(one per stage run, plus one), %.2f us, %.3f %% of a %.0f us step.%s\n",
           1e9 * per_read, active + 3, 1e6 * per_read * (double)(active + 3),
           100.0 * per_read * (double)(active + 3) * 1e6 / per_step, per_step,
           sink < 0 ? " " : "");
    mps2p_solver_destroy(solver);
    return 0;
}
