/* Still water (issue 15's first validation): water DEPTH deep in a tank as
 * wide, l0 = 0.01 m, walls on both sides and below standing 0.1 m above the
 * water, the default scheme, run for DURATION seconds:
 *   - RMS speed of the water below 0.005 sqrt(g H) at every sample (0.01 s)
 *     after 0.5 s;
 *   - RMS displacement below 0.1 l0 at the end;
 *   - mean pressure over the bottom row of water, over the samples from 1 s
 *     on, within 1 % of rho g h', h' the depth from the bottom row's centres
 *     to the water's top, half a spacing above the free-surface row's centres
 *     (the default, surface_pressure extrapolated), or to those centres
 *     (surface_pressure centre: p = 0 there; docs/embedding.md);
 *   - the bottom row's pressure standard deviation (over the row) below 5 %
 *     of its mean, at every sample from 1 s on.
 * Arguments: DEPTH (m) and DURATION (s); CI runs 2 s of the 0.3 m and 0.2 m
 * tanks, the long suite 10 s of each (docs/validation.md). SCHEME in the
 * environment names another scheme (koshizuka1996 fails, as measured). */
#include <mps2p.h>
#include "check.h"

#include <string.h>

#define L0 0.01
#define RHO 1000.0
#define G 9.81

int main(int argc, char **argv)
{
    const double depth = argc > 1 ? atof(argv[1]) : 0.3;
    const double duration = argc > 2 ? atof(argv[2]) : 2.0;
    const double width = depth;
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(L0, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", RHO, 1e-6, &water));
    const char *scheme = getenv("SCHEME");
    if (scheme)
        MUST(mps2p_scene_set_option(scene, "scheme", scheme));
    const char *surface = "";
    MUST(mps2p_scene_get_option(scene, "surface_pressure", &surface));
    /* a hair more than a whole number of l0, so the box is not snapped a row short */
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, width + 1e-9, depth + 1e-9));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, width, depth + 0.1, 1));
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);

    size_t n;
    MUST(mps2p_solver_particle_count(solver, &n));
    double *initial = malloc(2 * n * sizeof *initial), *r = malloc(2 * n * sizeof *r);
    double *u = malloc(2 * n * sizeof *u), *p = malloc(n * sizeof *p);
    int *kind = malloc(n * sizeof *kind);
    MUST(mps2p_solver_get_positions(solver, initial, 2 * n));
    MUST(mps2p_solver_get_kinds(solver, kind, n));
    double top = -1.0, bottom = 1.0;
    size_t fluid = 0;
    for (size_t i = 0; i < n; i++) {
        if (kind[i] != MPS2P_KIND_FLUID)
            continue;
        top = fmax(top, initial[2 * i + 1]);
        bottom = fmin(bottom, initial[2 * i + 1]);
        fluid++;
    }
    const double top_offset = strcmp(surface, "extrapolated") == 0 ? 0.5 * L0 : 0.0;
    const double expected = RHO * G * (top - bottom + top_offset);
    const double speed_bar = 0.005 * sqrt(G * depth);

    double worst_speed = 0.0, worst_speed_at = 0.0, worst_spread = 0.0, sum_p = 0.0;
    long samples = 0;
    const int steps = (int)lround(duration / 0.01);
    for (int k = 1; k <= steps; k++) {
        const double t = k * 0.01;
        int status = mps2p_solver_advance_to(solver, t, NULL, NULL);
        CHECK(status == MPS2P_OK, "advance to %g s: %s", t, mps2p_solver_last_error(solver));
        if (status != MPS2P_OK)
            return check_summary("test_hydrostatic");
        if (t <= 0.5 + 1e-9)
            continue;
        MUST(mps2p_solver_get_velocities(solver, u, 2 * n));
        double sum_u2 = 0.0;
        for (size_t i = 0; i < n; i++)
            if (kind[i] == MPS2P_KIND_FLUID)
                sum_u2 += u[2 * i] * u[2 * i] + u[2 * i + 1] * u[2 * i + 1];
        double rms_speed = sqrt(sum_u2 / fluid);
        if (rms_speed > worst_speed) {
            worst_speed = rms_speed;
            worst_speed_at = t;
        }
        if (t < 1.0 - 1e-9)
            continue;
        MUST(mps2p_solver_get_pressure(solver, p, n));
        double row_sum = 0.0, row_sum2 = 0.0;
        size_t row = 0;
        for (size_t i = 0; i < n; i++) {
            if (kind[i] != MPS2P_KIND_FLUID || initial[2 * i + 1] > bottom + 0.5 * L0)
                continue;
            row_sum += p[i];
            row_sum2 += p[i] * p[i];
            row++;
        }
        double mean = row_sum / row;
        double spread = sqrt(fmax(0.0, row_sum2 / row - mean * mean)) / mean;
        worst_spread = fmax(worst_spread, spread);
        sum_p += mean;
        samples++;
    }
    MUST(mps2p_solver_get_positions(solver, r, 2 * n));
    double sum2 = 0.0;
    for (size_t i = 0; i < n; i++) {
        if (kind[i] != MPS2P_KIND_FLUID)
            continue;
        double dx = r[2 * i] - initial[2 * i], dy = r[2 * i + 1] - initial[2 * i + 1];
        sum2 += dx * dx + dy * dy;
    }
    const double displacement = sqrt(sum2 / fluid) / L0;
    const double mean_p = samples ? sum_p / samples : 0.0;
    const double error = (mean_p - expected) / expected;
    printf("still water %.2f m deep, %.1f s: RMS speed after 0.5 s at most %.3g m/s (at %.2f s; "
           "bar %.3g), RMS displacement %.4f l0 (bar 0.1), bottom pressure %.1f Pa against "
           "rho g h' = %.1f Pa (%+.3f %%; bar 1 %%), its spread over the row at most %.3f %% "
           "(bar 5 %%)\n",
           depth, duration, worst_speed, worst_speed_at, speed_bar, displacement, mean_p,
           expected, 100 * error, 100 * worst_spread);
    CHECK(worst_speed < speed_bar, "RMS speed %.3g m/s at %.2f s, not below %.3g", worst_speed,
          worst_speed_at, speed_bar);
    CHECK(displacement < 0.1, "RMS displacement %.4f l0 is not below 0.1 l0", displacement);
    CHECK(samples > 0 && fabs(error) < 0.01, "bottom pressure error %.3f %% beyond 1 %%",
          100 * error);
    CHECK(worst_spread < 0.05, "bottom row spread %.2f %% beyond 5 %%", 100 * worst_spread);

    free(initial);
    free(r);
    free(u);
    free(p);
    free(kind);
    mps2p_solver_destroy(solver);
    return check_summary("test_hydrostatic");
}
