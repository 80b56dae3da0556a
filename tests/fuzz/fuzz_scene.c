/* libFuzzer target: the scene-building API driven by arbitrary bytes.
 * The bytes become a spacing and up to 32 calls (fluids, boxes, tanks,
 * particle arrays, parameters, options, domain, queries) with arbitrary
 * doubles including NaN, infinities and huge values; then, for scenes of
 * at most MAX_SOLVER_PARTICLES particles, a solver, two steps, statistics,
 * fields, probes and the front. Every call must return a status; none may
 * crash, leak or trip a sanitizer. A refused call must leave a message.
 *
 * Boxes that would really hold between MAX_BUILD_PARTICLES and a few
 * billion particles are not asked for (they are valid, and slow: the
 * refusal of larger ones, and of the memory, is tested in test_api_errors
 * and tests/reliability/test_alloc_failure). */
#include <mps2p.h>

#include <stdio.h>
#include <stdlib.h>
#include "fuzz_input.h"

#define MAX_BUILD_PARTICLES 20000.0
#define MAX_SOLVER_PARTICLES 800
#define MAX_OPS 32

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void expect_message(int status)
{
    if (status < 0 && mps2p_last_error()[0] == '\0') {
        fprintf(stderr, "status %s without a message\n", mps2p_status_string(status));
        abort();
    }
}

/* Skips valid-but-slow boxes: about n = w h / l0^2 particles, up to above
 * what a scene holds (refused before allocating: cheap, and fuzzed). */
static int too_slow(double l0, double x0, double y0, double x1, double y1)
{
    double n = ((x1 - x0) / l0) * ((y1 - y0) / l0);
    return isfinite(n) && n > MAX_BUILD_PARTICLES && n < 3e9;
}

/* A tank's walls are separate boxes: a billion-particle wall can hide in a
 * tank of any size, so only small tanks (and overflowing ones) are asked. */
static int tank_too_slow(double l0, double x0, double y0, double x1, double y1)
{
    double n = ((x1 - x0) / l0 + 24.0) * ((y1 - y0) / l0 + 24.0);
    return isfinite(n) && n > MAX_BUILD_PARTICLES;
}

static const char *const fluid_names[] = {"water", "air", "", "oil", "water"};
static const char *const option_keys[] = {"pressure_solver", "pressure_gradient",
                                          "ppe_source", "nonsense", ""};
static const char *const option_values[] = {"cholmod", "cg", "minimum", "corrected",
                                            "density", "mixed", "ecs", "lu", ""};
static const char *const stat_keys[] = {
    "max_speed", "kinetic_energy", "potential_energy", "pressure_min", "pressure_max",
    "ppe_unknowns", "ppe_iterations", "ppe_residual", "surface_particles", "n0", "lambda",
    "neighbour_builds", "nonsense"};

static void exercise_solver(mps2p_solver *solver, fuzz_input *in)
{
    for (int k = 0; k < 2; k++) {
        int status = mps2p_solver_step(solver);
        expect_message(status);
        if (status != MPS2P_OK)
            break;
    }
    double value;
    for (size_t k = 0; k < sizeof stat_keys / sizeof stat_keys[0]; k++)
        expect_message(mps2p_solver_get_stat(solver, stat_keys[k], &value));
    size_t n = 0;
    mps2p_solver_particle_count(solver, &n);
    double *vectors = malloc(2 * n * sizeof *vectors);
    int *ints = malloc(n * sizeof *ints);
    if (vectors && ints) {
        size_t length = take_u8(in) % 2 ? 2 * n : n; /* sometimes too short */
        expect_message(mps2p_solver_get_positions(solver, vectors, length));
        expect_message(mps2p_solver_get_velocities(solver, vectors, length));
        expect_message(mps2p_solver_get_pressure(solver, vectors, n));
        expect_message(mps2p_solver_get_number_density(solver, vectors, n));
        expect_message(mps2p_solver_get_kinds(solver, ints, n));
        expect_message(mps2p_solver_get_fluid_ids(solver, ints, n));
    }
    free(vectors);
    free(ints);
    double points[6], pressure[3], velocity[6];
    int inside[3];
    for (int k = 0; k < 6; k++)
        points[k] = take_double(in);
    expect_message(mps2p_solver_probe(solver, 3, points, pressure, velocity, inside));
    double front;
    expect_message(mps2p_solver_front(solver, (int)take_u8(in) % 4 - 1, take_double(in), &front));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = {data, size};
    double l0 = take_double(&in);
    mps2p_scene *scene = NULL;
    int status = mps2p_scene_create(l0, &scene);
    expect_message(status);
    if (status != MPS2P_OK)
        return 0;
    for (int op = 0; op < MAX_OPS && in.left; op++) {
        int id = (int)(take_u8(&in) % 4) - 1;
        double v[4];
        int kind = take_u8(&in) % 10;
        switch (kind) {
        case 0: {
            double density = take_double(&in), viscosity = take_double(&in);
            status = mps2p_scene_add_fluid(scene, fluid_names[take_u8(&in) % 5], density,
                                           viscosity, NULL);
            break;
        }
        case 1:
        case 2:
            for (int k = 0; k < 4; k++)
                v[k] = take_double(&in);
            if (too_slow(l0, v[0], v[1], v[2], v[3]))
                continue;
            status = kind == 1 ? mps2p_scene_add_fluid_box(scene, id, v[0], v[1], v[2], v[3])
                               : mps2p_scene_add_wall_box(scene, v[0], v[1], v[2], v[3]);
            break;
        case 3:
            for (int k = 0; k < 4; k++)
                v[k] = take_double(&in);
            if (tank_too_slow(l0, v[0], v[1], v[2], v[3]))
                continue;
            status = mps2p_scene_add_tank(scene, v[0], v[1], v[2], v[3], take_u8(&in) % 2);
            break;
        case 4: {
            size_t count = take_u8(&in) % 9;
            double positions[16], velocities[16];
            int kinds[8], ids[8];
            for (size_t k = 0; k < count; k++) {
                positions[2 * k] = take_double(&in);
                positions[2 * k + 1] = take_double(&in);
                velocities[2 * k] = take_double(&in);
                velocities[2 * k + 1] = take_double(&in);
                kinds[k] = (int)(take_u8(&in) % 5) - 1;
                ids[k] = (int)(take_u8(&in) % 4) - 1;
            }
            uint8_t nulls = take_u8(&in);
            status = mps2p_scene_add_particles(scene, count, positions,
                                               nulls & 1 ? NULL : velocities, kinds,
                                               nulls & 2 ? NULL : ids);
            break;
        }
        case 5: {
            const char *key = "nonsense";
            mps2p_param_info(take_u8(&in) % 24, &key, NULL, NULL);
            double value = take_double(&in);
            /* an iteration limit of 1e9 with a stalling CG is valid and slow */
            if (key[0] == 'c' && key[1] == 'g' && value > 1e4)
                continue;
            status = mps2p_scene_set_param(scene, key, value);
            break;
        }
        case 6:
            status = mps2p_scene_set_option(scene, option_keys[take_u8(&in) % 5],
                                            option_values[take_u8(&in) % 9]);
            break;
        case 7:
            for (int k = 0; k < 4; k++)
                v[k] = take_double(&in);
            status = mps2p_scene_set_domain(scene, v[0], v[1], v[2], v[3]);
            break;
        case 8: {
            const char *name, *value_text;
            double a, b;
            int count;
            size_t particles;
            expect_message(mps2p_scene_get_fluid(scene, id, &name, &a, &b));
            expect_message(mps2p_scene_fluid_count(scene, &count));
            expect_message(mps2p_scene_particle_count(scene, &particles));
            expect_message(mps2p_scene_get_param(scene, "beta", &a));
            status = mps2p_scene_get_option(scene, option_keys[take_u8(&in) % 5], &value_text);
            break;
        }
        default:
            status = mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, NULL);
            break;
        }
        expect_message(status);
    }
    size_t particles = 0;
    mps2p_scene_particle_count(scene, &particles);
    if (particles <= MAX_SOLVER_PARTICLES) {
        mps2p_solver *solver = NULL;
        status = mps2p_solver_create(scene, &solver);
        expect_message(status);
        if (getenv("MPS2P_FUZZ_VERBOSE"))
            fprintf(stderr, "%zu particles: solver %s\n", particles,
                    status == MPS2P_OK ? "created" : mps2p_last_error());
        if (status == MPS2P_OK)
            exercise_solver(solver, &in);
        mps2p_solver_destroy(solver);
    }
    mps2p_scene_destroy(scene);
    return 0;
}
