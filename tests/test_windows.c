/* Short windows (issue 20, defect 1): mps2p_solver_advance_to and
 * _advance_window to a time much closer than the chosen dt. The PPE source
 * is rho/dt^2 times a density deviation, so a tiny step taken as a full
 * one gave pressures of 1e7 Pa and a false, permanent divergence; such a
 * step now solves its pressure as one of dt/2 (docs/guarantees.md). */
#include <mps2p.h>
#include "check.h"

#include <string.h>

/* The outside tester's scene: a 0.1 m x 0.2 m column at the left wall of an
 * open 0.4 m x 0.3 m tank, l0 0.02 m (dt about 2 ms). */
static mps2p_solver *small_dam_break(void)
{
    mps2p_scene *scene;
    mps2p_solver *solver;
    int water;
    MUST(mps2p_scene_create(0.02, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.1, 0.2));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.4, 0.3, 1));
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    return solver;
}

/* After start full steps, one window of length window (advance_to, or
 * advance_window when use_window), then two full steps: all succeed, the
 * time lands on the window's end, and the pressure stays that of a flow
 * (a 0.2 m column: a few kPa; the limit is 5.5 MPa). */
static int short_window(int start, double window, int use_window, double *pressure_max)
{
    mps2p_solver *solver = small_dam_break();
    for (int k = 0; k < start; k++)
        MUST(mps2p_solver_step(solver));
    double t, end, after;
    MUST(mps2p_solver_get_time(solver, &t));
    end = t + window;
    uint64_t taken = 0;
    int status = use_window ? mps2p_solver_advance_window(solver, end, &taken)
                            : mps2p_solver_advance_to(solver, end, NULL, NULL);
    int ok = status == MPS2P_OK;
    CHECK(ok, "%d steps, then a window of %g s (%s): %s: %s", start, window,
          use_window ? "advance_window" : "advance_to", mps2p_status_string(status),
          mps2p_solver_last_error(solver));
    MUST(mps2p_solver_get_time(solver, &after));
    if (ok) {
        CHECK(after == end, "window end %.17g, time %.17g", end, after);
        /* within 1e-12 max(1, end) of the end there is nothing to step */
        uint64_t expected = end - t > 1e-12 * fmax(1.0, end) ? 1 : 0;
        CHECK(!use_window || taken == expected, "a window of %g s took %llu steps", window,
              (unsigned long long)taken);
        MUST(mps2p_solver_get_stat(solver, "pressure_max", pressure_max));
        CHECK(*pressure_max < 2e4, "%d steps + %g s: pressure_max %g Pa", start, window,
              *pressure_max);
        for (int k = 0; k < 2 && ok; k++) {
            status = mps2p_solver_step(solver);
            ok = status == MPS2P_OK;
            CHECK(ok, "step after the window: %s", mps2p_solver_last_error(solver));
        }
    }
    mps2p_solver_destroy(solver);
    return ok;
}

static void test_short_windows(void)
{
    const double windows[] = {1e-5, 1e-6, 1e-9, 1e-11, 1e-12, 1e-4, 5e-4};
    int failed = 0, runs = 0;
    double worst = 0.0;
    for (size_t w = 0; w < sizeof windows / sizeof windows[0]; w++)
        for (int start = 1; start <= 30; start++) {
            double p = 0.0;
            failed += !short_window(start, windows[w], start % 2, &p);
            worst = p > worst ? p : worst;
            runs++;
        }
    printf("short windows: %d of %d failed, largest pressure after one %g Pa\n", failed, runs,
           worst);
}

/* A step of length h: advance_to(h) from the start, or one mps2p_solver_step
 * of a solver whose fixed dt is h. Positions and pressures, 3 n doubles;
 * *dt_next: the step the solver would choose at the start. */
static double *one_step(double h, int fixed, size_t *n, double *dt_next)
{
    mps2p_scene *scene;
    mps2p_solver *solver;
    int water;
    MUST(mps2p_scene_create(0.02, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water));
    /* the column moving down and right from the start: it presses on the
     * walls in the first step, which a column at rest does not */
    double position[2 * 50], velocity[2 * 50];
    int kind[50], id[50];
    for (int k = 0; k < 50; k++) {
        position[2 * k] = 0.01 + 0.02 * (k % 5);
        position[2 * k + 1] = 0.01 + 0.02 * (k / 5);
        velocity[2 * k] = 0.3;
        velocity[2 * k + 1] = -0.5;
        kind[k] = MPS2P_KIND_FLUID;
        id[k] = water;
    }
    MUST(mps2p_scene_add_particles(scene, 50, position, velocity, kind, id));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.4, 0.3, 1));
    if (fixed)
        MUST(mps2p_scene_set_param(scene, "dt", h));
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    MUST(mps2p_solver_get_stat(solver, "dt_next", dt_next));
    if (fixed)
        MUST(mps2p_solver_step(solver));
    else
        MUST(mps2p_solver_advance_to(solver, h, NULL, NULL));
    MUST(mps2p_solver_particle_count(solver, n));
    double *x = malloc(3 * *n * sizeof *x);
    MUST(mps2p_solver_get_positions(solver, x, 2 * *n));
    MUST(mps2p_solver_get_pressure(solver, x + 2 * *n, *n));
    mps2p_solver_destroy(solver);
    return x;
}

/* A window of dt / 2 or longer is taken as it always was: its one step is
 * the same bits as a fixed-dt step of its length. A shorter one is not
 * (its pressure is solved as for dt / 2), and its pressure is bounded. */
static void test_floor_only_below_half(void)
{
    size_t n;
    double dt, unused;
    free(one_step(1e-3, 0, &n, &dt)); /* the adaptive dt */
    const double fractions[] = {1.0, 0.6, 0.5, 0.1};
    for (size_t k = 0; k < sizeof fractions / sizeof fractions[0]; k++) {
        double h = fractions[k] * dt;
        double *window = one_step(h, 0, &n, &unused);
        double *fixed = one_step(h, 1, &n, &unused);
        int same = memcmp(window, fixed, 3 * n * sizeof *window) == 0;
        if (fractions[k] >= 0.5)
            CHECK(same, "a window of %g dt differs from a fixed step of that length",
                  fractions[k]);
        else
            CHECK(!same, "a window of %g dt is the same bits as a full-pressure step",
                  fractions[k]);
        free(window);
        free(fixed);
    }
}

/* Many tiny windows in a row, then on to 0.3 s: the run goes on and ends
 * near the undisturbed one (front within 2 l0). */
static void test_many_tiny_windows(void)
{
    mps2p_solver *a = small_dam_break(), *b = small_dam_break();
    MUST(mps2p_solver_advance_to(a, 0.3, NULL, NULL));
    MUST(mps2p_solver_advance_to(b, 0.05, NULL, NULL));
    int status = MPS2P_OK;
    for (int k = 1; k <= 1000 && status == MPS2P_OK; k++)
        status = mps2p_solver_advance_window(b, 0.05 + k * 1e-6, NULL);
    CHECK(status == MPS2P_OK, "1000 windows of 1 us: %s", mps2p_solver_last_error(b));
    if (status == MPS2P_OK) {
        status = mps2p_solver_advance_to(b, 0.3, NULL, NULL);
        CHECK(status == MPS2P_OK, "on to 0.3 s: %s", mps2p_solver_last_error(b));
    }
    double fa, fb;
    MUST(mps2p_solver_front(a, -1, INFINITY, &fa));
    MUST(mps2p_solver_front(b, -1, INFINITY, &fb));
    CHECK(fabs(fa - fb) < 0.04, "front at 0.3 s: %g undisturbed, %g after tiny windows", fa, fb);
    mps2p_solver_destroy(a);
    mps2p_solver_destroy(b);
}

int main(void)
{
    test_short_windows();
    test_floor_only_below_half();
    test_many_tiny_windows();
    return check_summary("test_windows");
}
