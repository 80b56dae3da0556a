/* Effects and stages: a scene pays only for what it needs, an effect can be
 * switched on or off explicitly, impossible requests are refused, and
 * inferred and requested effects give bitwise the same run. */
#include <mps2p.h>
#include "check.h"
#include "scenes.h"

#include <string.h>

static int stage_index(const mps2p_solver *solver, const char *wanted)
{
    size_t count;
    MUST(mps2p_solver_stage_count(solver, &count));
    for (size_t i = 0; i < count; i++) {
        const char *name;
        MUST(mps2p_solver_get_stage(solver, i, &name, NULL, NULL, NULL));
        if (strcmp(name, wanted) == 0)
            return (int)i;
    }
    return -1;
}

static uint64_t stage_calls(const mps2p_solver *solver, const char *name, int *active)
{
    int index = stage_index(solver, name);
    CHECK(index >= 0, "no stage %s", name);
    uint64_t calls = 0;
    if (index >= 0)
        MUST(mps2p_solver_get_stage(solver, (size_t)index, NULL, active, NULL, &calls));
    return calls;
}

static int effect_active(const mps2p_solver *solver, const char *wanted, const char **reason)
{
    size_t count;
    MUST(mps2p_solver_effect_count(solver, &count));
    for (size_t i = 0; i < count; i++) {
        const char *name;
        int active;
        MUST(mps2p_solver_get_effect(solver, i, &name, &active, reason));
        if (strcmp(name, wanted) == 0)
            return active;
    }
    CHECK(0, "no effect %s", wanted);
    return -1;
}

static mps2p_solver *make(mps2p_scene *scene)
{
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    return solver;
}

static void run_steps(mps2p_solver *solver, int steps)
{
    for (int k = 0; k < steps; k++)
        MUST(mps2p_solver_step(solver));
}

static mps2p_scene *inviscid_dam_break(void)
{
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(0.02, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 0.0, &water));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.16, 0.3));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.6, 0.5, 1));
    return scene;
}

/* What the scene needs is on, the rest is off and never called. */
static void test_inferred_effects(void)
{
    mps2p_solver *viscous = make(dam_break_scene(0.02));
    mps2p_solver *inviscid = make(inviscid_dam_break());
    run_steps(viscous, 10);
    run_steps(inviscid, 10);
    const char *reason;
    CHECK(effect_active(viscous, "viscosity", &reason) == 1, "viscous fluid, viscosity off");
    CHECK(strstr(reason, "inferred") && strstr(reason, "1 of 1"), "reason: %s", reason);
    CHECK(effect_active(inviscid, "viscosity", &reason) == 0, "inviscid fluid, viscosity on");
    CHECK(strstr(reason, "inferred") && strstr(reason, "0 of 1"), "reason: %s", reason);
    CHECK(effect_active(inviscid, "gravity", NULL) == 1, "gravity should be on");
    int active;
    CHECK(stage_calls(viscous, "viscosity", &active) == 10 && active, "viscosity calls");
    CHECK(stage_calls(inviscid, "viscosity", &active) == 0 && !active,
          "an inviscid scene called the viscosity stage");
    CHECK(stage_calls(inviscid, "pressure_solve", NULL) == 10, "pressure_solve calls");
    /* the default error-compensating source needs the start-of-step number
     * density; Koshizuka and Oka's density source does not (below) */
    CHECK(stage_calls(inviscid, "number_density_start", &active) == 10 && active,
          "number_density_start did not run with the ecs source");
    uint64_t calls;
    double seconds;
    int index = stage_index(inviscid, "pressure_solve");
    MUST(mps2p_solver_get_stage(inviscid, (size_t)index, NULL, NULL, &seconds, &calls));
    CHECK(seconds > 0.0, "pressure_solve took %g s", seconds);
    MUST(mps2p_solver_reset_stage_timings(inviscid));
    CHECK(stage_calls(inviscid, "pressure_solve", NULL) == 0, "reset left calls");
    mps2p_solver_destroy(viscous);
    mps2p_solver_destroy(inviscid);
}

/* Arrays of stages that are off are not allocated: the start-of-step number
 * density (8 bytes a particle) exists only for the mixed and ecs sources. */
static void test_memory_follows_stages(void)
{
    mps2p_scene *with = dam_break_scene(0.02), *without = dam_break_scene(0.02);
    MUST(mps2p_scene_set_option(with, "ppe_source", "ecs"));
    MUST(mps2p_scene_set_option(without, "ppe_source", "density"));
    mps2p_solver *ecs = make(with), *density = make(without);
    double bytes_ecs, bytes_density;
    size_t n;
    MUST(mps2p_solver_get_stat(ecs, "memory_bytes", &bytes_ecs));
    MUST(mps2p_solver_get_stat(density, "memory_bytes", &bytes_density));
    MUST(mps2p_solver_particle_count(ecs, &n));
    CHECK(bytes_ecs - bytes_density == 8.0 * (double)n,
          "memory %g (ecs) - %g (density) should be 8 bytes x %zu particles", bytes_ecs,
          bytes_density, n);
    CHECK(bytes_density > 100.0 * (double)n, "memory %g bytes for %zu particles", bytes_density,
          n);
    run_steps(ecs, 3);
    run_steps(density, 3);
    CHECK(stage_calls(ecs, "number_density_start", NULL) == 3, "ecs needs the start density");
    int active;
    CHECK(stage_calls(density, "number_density_start", &active) == 0 && !active,
          "number_density_start ran with the density source");
    mps2p_solver_destroy(ecs);
    mps2p_solver_destroy(density);
}

/* Switching an effect off explicitly: no viscous pass, and the run equals
 * the inviscid fluid's bit for bit; no collision: Koshizuka and Oka's dam
 * break still runs (the corrected scheme needs the collision model as its
 * damper: docs/validation.md). */
static void test_switched_off(void)
{
    mps2p_scene *scene = dam_break_scene(0.02);
    MUST(mps2p_scene_set_option(scene, "effect.viscosity", "off"));
    mps2p_solver *off = make(scene);
    mps2p_scene *inviscid_scene;
    int water;
    MUST(mps2p_scene_create(0.02, &inviscid_scene));
    MUST(mps2p_scene_add_fluid(inviscid_scene, "water", 1000.0, 0.0, &water));
    MUST(mps2p_scene_add_fluid_box(inviscid_scene, water, 0.0, 0.0, 0.15, 0.30));
    MUST(mps2p_scene_add_tank(inviscid_scene, 0.0, 0.0, 0.6, 0.7, 1));
    mps2p_solver *inviscid = make(inviscid_scene);
    const char *reason;
    CHECK(effect_active(off, "viscosity", &reason) == 0, "viscosity switched off but on");
    CHECK(strstr(reason, "requested: off; ") == reason && strstr(reason, "1 of 1"), "reason: %s",
          reason);
    MUST(mps2p_solver_advance_to(off, 0.1, NULL, NULL));
    MUST(mps2p_solver_advance_to(inviscid, 0.1, NULL, NULL));
    CHECK(stage_calls(off, "viscosity", NULL) == 0, "viscosity ran while off");
    size_t n;
    MUST(mps2p_solver_particle_count(off, &n));
    double *a = malloc(2 * n * sizeof *a), *b = malloc(2 * n * sizeof *b);
    MUST(mps2p_solver_get_positions(off, a, 2 * n));
    MUST(mps2p_solver_get_positions(inviscid, b, 2 * n));
    CHECK(memcmp(a, b, 2 * n * sizeof *a) == 0,
          "viscosity off differs from an inviscid fluid");
    free(a);
    free(b);
    mps2p_solver_destroy(off);
    mps2p_solver_destroy(inviscid);

    scene = dam_break_scene(0.02);
    MUST(mps2p_scene_set_option(scene, "scheme", "koshizuka1996"));
    MUST(mps2p_scene_set_option(scene, "effect.collision", "off"));
    mps2p_solver *no_collision = make(scene);
    int status = mps2p_solver_advance_to(no_collision, 0.5, NULL, NULL);
    CHECK(status == MPS2P_OK, "dam break without collision: %s",
          mps2p_solver_last_error(no_collision));
    CHECK(stage_calls(no_collision, "collision", NULL) == 0, "collision ran while off");
    mps2p_solver_destroy(no_collision);
}

/* A still tank without gravity and without viscosity stays exactly still. */
static void test_quiescent_without_viscosity(void)
{
    mps2p_scene *scene = tank_scene(0.02, 0.2, 0.1);
    MUST(mps2p_scene_set_param(scene, "gravity_y", 0.0));
    MUST(mps2p_scene_set_option(scene, "effect.viscosity", "off"));
    mps2p_solver *solver = make(scene);
    CHECK(effect_active(solver, "gravity", NULL) == 0, "zero gravity but gravity on");
    MUST(mps2p_solver_advance_to(solver, 0.5, NULL, NULL));
    double speed;
    MUST(mps2p_solver_get_stat(solver, "max_speed", &speed));
    CHECK(speed == 0.0, "a tank without forces moves at %g m/s", speed);
    CHECK(stage_calls(solver, "gravity", NULL) == 0, "gravity ran with zero gravity");
    mps2p_solver_destroy(solver);

    /* gravity switched off, its parameter left at -9.81: nothing may read it
     * (the walls' hydrostatic ghosts pushed a resting column at 0.02 m/s
     * after one step, growing) */
    scene = tank_scene(0.02, 0.2, 0.1);
    MUST(mps2p_scene_set_option(scene, "effect.gravity", "off"));
    solver = make(scene);
    MUST(mps2p_solver_advance_to(solver, 0.5, NULL, NULL));
    double energy;
    MUST(mps2p_solver_get_stat(solver, "max_speed", &speed));
    MUST(mps2p_solver_get_stat(solver, "potential_energy", &energy));
    CHECK(speed == 0.0, "with effect gravity off a still tank moves at %g m/s", speed);
    CHECK(energy == 0.0, "with effect gravity off the potential energy is %g", energy);
    mps2p_solver_destroy(solver);
}

/* A bubble joined to the liquid rises by buoyancy, so not without gravity:
 * an air pocket in still water with effect gravity off stays put (it rose
 * along +y at the drift's 0.2 m/s, "up" taken from the parameter). */
static void test_no_rise_without_gravity(void)
{
    mps2p_scene *scene = air_pocket_scene(0.2, 0.2);
    const int air = AIR_POCKET_AIR;
    MUST(mps2p_scene_set_option(scene, "effect.gravity", "off"));
    mps2p_solver *solver = make(scene);
    MUST(mps2p_solver_advance_to(solver, 0.05, NULL, NULL));
    size_t n;
    MUST(mps2p_solver_particle_count(solver, &n));
    double *velocity = malloc(2 * n * sizeof *velocity);
    int *ids = malloc(n * sizeof *ids), *kinds = malloc(n * sizeof *kinds);
    CHECK(velocity && ids && kinds, "out of memory");
    MUST(mps2p_solver_get_velocities(solver, velocity, 2 * n));
    MUST(mps2p_solver_get_fluid_ids(solver, ids, n));
    MUST(mps2p_solver_get_kinds(solver, kinds, n));
    double fastest = 0.0, joined;
    for (size_t i = 0; i < n; i++)
        if (kinds[i] == MPS2P_KIND_FLUID && ids[i] == air)
            fastest = fmax(fastest, fabs(velocity[2 * i + 1]));
    MUST(mps2p_solver_get_stat(solver, "gas_joined", &joined));
    CHECK(joined > 0, "the pocket did not join the liquid: the test tests nothing");
    CHECK(fastest < 0.01, "without gravity an air pocket moves at %g m/s vertically", fastest);
    free(velocity);
    free(ids);
    free(kinds);
    mps2p_solver_destroy(solver);
}

/* Requests the scene cannot support are refused, naming the effect and why. */
static void test_impossible_requests(void)
{
    struct {
        const char *option, *param;
        double value;
        const char *words;
    } cases[] = {
        {"effect.viscosity", NULL, 0.0, "viscosity"},
        {"effect.gravity", "gravity_y", 0.0, "gravity"},
        {"effect.collision", "collision_distance", 0.0, "collision"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        mps2p_scene *scene = inviscid_dam_break();
        MUST(mps2p_scene_set_option(scene, cases[k].option, "on"));
        if (cases[k].param)
            MUST(mps2p_scene_set_param(scene, cases[k].param, cases[k].value));
        mps2p_solver *solver = NULL;
        int status = mps2p_solver_create(scene, &solver);
        CHECK(status == MPS2P_ERR_INVALID && !solver, "%s on: status %d", cases[k].option,
              status);
        CHECK(strstr(mps2p_last_error(), cases[k].words) &&
                  strstr(mps2p_last_error(), "cannot support"),
              "message: %s", mps2p_last_error());
        mps2p_scene_destroy(scene);
    }
    mps2p_scene *scene = inviscid_dam_break();
    CHECK(mps2p_scene_set_option(scene, "effect.gravity", "maybe") == MPS2P_ERR_INVALID,
          "effect mode \"maybe\" accepted");
    CHECK(strstr(mps2p_last_error(), "\"auto\", \"on\", \"off\""), "message: %s",
          mps2p_last_error());
    mps2p_scene_destroy(scene);
}

/* Water and air (docs/two-phase.md) in a small tank: the air fluid's density
 * is a parameter so that the same particles can be one heavy phase. */
static mps2p_scene *water_air_scene(double air_density, const char *model)
{
    mps2p_scene *scene;
    int water, air;
    MUST(mps2p_scene_create(0.02, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_add_fluid(scene, "air", air_density, 1.5e-5, &air));
    if (model)
        MUST(mps2p_scene_set_option(scene, "two_phase_model", model));
    MUST(mps2p_scene_set_option(scene, "pressure_solver", "cg"));
    MUST(mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.1, 0.2));
    MUST(mps2p_scene_add_fluid_box(scene, air, 0.1, 0.0, 0.3, 0.3));
    MUST(mps2p_scene_add_fluid_box(scene, air, 0.0, 0.2, 0.1, 0.3));
    MUST(mps2p_scene_add_tank(scene, 0.0, 0.0, 0.3, 0.4, 1));
    return scene;
}

/* Two phases are effects: inferred from a light fluid, their stages replace
 * the single-phase pressure stages, their arrays exist only when on, and
 * impossible requests are refused. */
static void test_two_phase_effects(void)
{
    const char *reason = NULL;
    int active = 0;
    /* water only: off, no two-phase stage, no two-phase memory */
    mps2p_solver *water = make(dam_break_scene(0.02));
    CHECK(effect_active(water, "two_phase", &reason) == 0, "water only, two_phase on");
    CHECK(reason && strstr(reason, "light_fraction"), "reason: %s", reason);
    CHECK(effect_active(water, "interface_reaction", NULL) == 0, "water only, reaction on");
    CHECK(effect_active(water, "gas_buffer", NULL) == 0, "water only, gas_buffer on");
    run_steps(water, 2);
    CHECK(stage_calls(water, "liquid_pressure", &active) == 0 && !active, "liquid_pressure ran");
    CHECK(stage_calls(water, "pressure_solve", &active) == 2 && active, "pressure_solve");
    double value = -1.0;
    MUST(mps2p_solver_get_stat(water, "two_phase_active", &value));
    CHECK(value == 0.0, "two_phase_active %g for water only", value);
    MUST(mps2p_solver_get_stat(water, "gas_triggered", &value));
    CHECK(value == 0.0, "gas_triggered %g for water only", value);
    mps2p_solver_destroy(water);

    /* water and air: the improved model's stages, not the single-phase ones */
    mps2p_solver *improved = make(water_air_scene(1.2, NULL));
    CHECK(effect_active(improved, "two_phase", &reason) == 1, "air, two_phase off");
    CHECK(reason && strstr(reason, "inferred"), "reason: %s", reason);
    CHECK(effect_active(improved, "interface_reaction", NULL) == 1, "improved, reaction off");
    run_steps(improved, 3);
    const char *on[] = {"phases_start", "interface_scan", "interface_join", "liquid_pressure",
                        "gas_pressure", "two_phase_correction", "interface_drift",
                        "gas_buffer", "gas_divergence_check"};
    for (size_t k = 0; k < sizeof on / sizeof on[0]; k++)
        CHECK(stage_calls(improved, on[k], &active) == 3 && active, "%s not run", on[k]);
    const char *off[] = {"free_surface", "pressure_assembly", "pressure_solve", "correction"};
    for (size_t k = 0; k < sizeof off / sizeof off[0]; k++)
        CHECK(stage_calls(improved, off[k], &active) == 0 && !active, "%s ran", off[k]);
    MUST(mps2p_solver_get_stat(improved, "gas_ppe_unknowns", &value));
    CHECK(value > 0.0, "no gas unknowns");
    /* its state is saved with the two-phase members that carry over (bit for
     * bit: test_two_phase_restart) */
    mps2p_state *state = NULL;
    MUST(mps2p_solver_save_state(improved, &state));
    MUST(mps2p_solver_restore_state(improved, state));
    mps2p_state_destroy(state);
    mps2p_solver_destroy(improved);

    /* the gas's damping layer: off on request, or with no depth; without
     * gravity it cannot be on (there is no top) */
    mps2p_scene *open_top = water_air_scene(1.2, NULL);
    MUST(mps2p_scene_set_option(open_top, "effect.gas_buffer", "off"));
    mps2p_solver *unbuffered = make(open_top);
    CHECK(effect_active(unbuffered, "gas_buffer", &reason) == 0, "gas_buffer off, but on");
    run_steps(unbuffered, 1);
    CHECK(stage_calls(unbuffered, "gas_buffer", &active) == 0 && !active, "gas_buffer ran");
    mps2p_solver_destroy(unbuffered);
    mps2p_scene *no_depth = water_air_scene(1.2, NULL);
    MUST(mps2p_scene_set_param(no_depth, "gas_buffer_depth", 0.0));
    mps2p_solver *shallow = make(no_depth);
    CHECK(effect_active(shallow, "gas_buffer", &reason) == 0, "gas_buffer_depth 0, but on");
    CHECK(reason && strstr(reason, "gas_buffer_depth is 0"), "reason: %s", reason);
    mps2p_solver_destroy(shallow);
    mps2p_scene *weightless = water_air_scene(1.2, NULL);
    MUST(mps2p_scene_set_param(weightless, "gravity_y", 0.0));
    MUST(mps2p_scene_set_option(weightless, "effect.gas_buffer", "on"));
    mps2p_solver *weightless_solver = NULL;
    CHECK(mps2p_solver_create(weightless, &weightless_solver) == MPS2P_ERR_INVALID &&
              !weightless_solver,
          "gas_buffer on without gravity accepted");
    CHECK(strstr(mps2p_last_error(), "gas_buffer") != NULL, "message: %s", mps2p_last_error());
    mps2p_scene_destroy(weightless);

    /* the conventional model: two phases, no reaction */
    mps2p_solver *two_step = make(water_air_scene(1.2, "two_step"));
    CHECK(effect_active(two_step, "two_phase", NULL) == 1, "two_step, two_phase off");
    CHECK(effect_active(two_step, "interface_reaction", &reason) == 0, "two_step, reaction on");
    CHECK(reason && strstr(reason, "two_step"), "reason: %s", reason);
    mps2p_solver_destroy(two_step);

    /* memory: "single" holds exactly what the same particles as one heavy
     * phase hold; the two-phase arrays come only with the effect */
    mps2p_solver *single = make(water_air_scene(1.2, "single"));
    mps2p_solver *heavy = make(water_air_scene(500.0, NULL));
    mps2p_solver *two = make(water_air_scene(1.2, NULL));
    CHECK(effect_active(single, "two_phase", &reason) == 0, "single, two_phase on");
    CHECK(reason && strstr(reason, "single"), "reason: %s", reason);
    double bytes_single, bytes_heavy, bytes_two;
    size_t n;
    MUST(mps2p_solver_particle_count(two, &n));
    MUST(mps2p_solver_get_stat(single, "memory_bytes", &bytes_single));
    MUST(mps2p_solver_get_stat(heavy, "memory_bytes", &bytes_heavy));
    MUST(mps2p_solver_get_stat(two, "memory_bytes", &bytes_two));
    CHECK(bytes_single == bytes_heavy, "memory %g (single) != %g (one heavy phase)",
          bytes_single, bytes_heavy);
    CHECK(bytes_two - bytes_single >= (9.0 + 11.0 * 8.0) * (double)n,
          "two-phase memory %g - %g is less than its arrays for %zu particles", bytes_two,
          bytes_single, n);
    mps2p_solver_destroy(single);
    mps2p_solver_destroy(heavy);
    mps2p_solver_destroy(two);

    /* impossible requests, with the reason */
    struct {
        mps2p_scene *scene;
        const char *option, *words;
    } refused[] = {
        {dam_break_scene(0.02), "effect.two_phase", "light_fraction"},
        {water_air_scene(1.2, "single"), "effect.two_phase", "single"},
        {water_air_scene(1.2, "two_step"), "effect.interface_reaction", "two_step"},
        {dam_break_scene(0.02), "effect.interface_reaction", "two_phase is off"},
    };
    for (size_t k = 0; k < sizeof refused / sizeof refused[0]; k++) {
        MUST(mps2p_scene_set_option(refused[k].scene, refused[k].option, "on"));
        mps2p_solver *solver = NULL;
        int status = mps2p_solver_create(refused[k].scene, &solver);
        CHECK(status == MPS2P_ERR_INVALID && !solver, "%s on: status %d", refused[k].option,
              status);
        CHECK(strstr(mps2p_last_error(), refused[k].words) &&
                  strstr(mps2p_last_error(), "cannot support"),
              "message: %s", mps2p_last_error());
        mps2p_scene_destroy(refused[k].scene);
    }
}

/* Every effect inferred and every effect requested give the same bits. */
static void test_inferred_equals_requested(void)
{
    mps2p_scene *requested_scene = dam_break_scene(0.02);
    MUST(mps2p_scene_set_option(requested_scene, "effect.gravity", "on"));
    MUST(mps2p_scene_set_option(requested_scene, "effect.viscosity", "on"));
    MUST(mps2p_scene_set_option(requested_scene, "effect.collision", "on"));
    mps2p_solver *inferred = make(dam_break_scene(0.02)), *requested = make(requested_scene);
    MUST(mps2p_solver_advance_to(inferred, 0.1, NULL, NULL));
    MUST(mps2p_solver_advance_to(requested, 0.1, NULL, NULL));
    size_t n;
    MUST(mps2p_solver_particle_count(inferred, &n));
    double *a = malloc(2 * n * sizeof *a), *b = malloc(2 * n * sizeof *b);
    MUST(mps2p_solver_get_positions(inferred, a, 2 * n));
    MUST(mps2p_solver_get_positions(requested, b, 2 * n));
    CHECK(memcmp(a, b, 2 * n * sizeof *a) == 0, "inferred and requested effects differ");
    MUST(mps2p_solver_get_velocities(inferred, a, 2 * n));
    MUST(mps2p_solver_get_velocities(requested, b, 2 * n));
    CHECK(memcmp(a, b, 2 * n * sizeof *a) == 0, "inferred and requested velocities differ");
    free(a);
    free(b);
    mps2p_solver_destroy(inferred);
    mps2p_solver_destroy(requested);
}

/* A free block of water moving uniformly, no gravity: no shear, so the
 * eddy viscosity is exactly zero and turbulence on gives the bits of off. */
static mps2p_scene *sliding_block(const char *turbulence)
{
    mps2p_scene *scene;
    int water;
    MUST(mps2p_scene_create(0.02, &scene));
    MUST(mps2p_scene_add_fluid(scene, "water", 1000.0, 1e-6, &water));
    MUST(mps2p_scene_set_param(scene, "gravity_y", 0.0));
    MUST(mps2p_scene_set_option(scene, "effect.turbulence", turbulence));
    double positions[2 * 100], velocities[2 * 100];
    int kinds[100], ids[100];
    for (int k = 0; k < 100; k++) {
        positions[2 * k] = 0.02 * (k % 10 + 0.5);
        positions[2 * k + 1] = 0.02 * (k / 10 + 0.5);
        velocities[2 * k] = 0.1;
        velocities[2 * k + 1] = -0.05;
        kinds[k] = MPS2P_KIND_FLUID;
        ids[k] = water;
    }
    MUST(mps2p_scene_add_particles(scene, 100, positions, velocities, kinds, ids));
    return scene;
}

/* Turbulence is off unless asked for; on, it runs, costs its array, acts
 * on shear only. */
static void test_turbulence(void)
{
    mps2p_solver *off = make(dam_break_scene(0.02));
    const char *reason;
    CHECK(effect_active(off, "turbulence", &reason) == 0, "turbulence on by default");
    CHECK(strstr(reason, "inferred") && strstr(reason, "only when asked"), "reason: %s", reason);
    mps2p_scene *scene = dam_break_scene(0.02);
    MUST(mps2p_scene_set_option(scene, "effect.turbulence", "on"));
    mps2p_solver *on = make(scene);
    CHECK(effect_active(on, "turbulence", &reason) == 1 && strstr(reason, "requested"),
          "turbulence switched on: %s", reason);
    double bytes_on, bytes_off, eddy;
    size_t n;
    MUST(mps2p_solver_particle_count(on, &n));
    MUST(mps2p_solver_get_stat(on, "memory_bytes", &bytes_on));
    MUST(mps2p_solver_get_stat(off, "memory_bytes", &bytes_off));
    CHECK(bytes_on - bytes_off == 8.0 * (double)n, "turbulence memory %g - %g for %zu particles",
          bytes_on, bytes_off, n);
    MUST(mps2p_solver_advance_to(on, 0.2, NULL, NULL));
    MUST(mps2p_solver_advance_to(off, 0.2, NULL, NULL));
    MUST(mps2p_solver_get_stat(on, "eddy_viscosity_max", &eddy));
    uint64_t steps;
    MUST(mps2p_solver_get_step_count(on, &steps));
    CHECK(stage_calls(on, "turbulence", NULL) == steps, "turbulence stage calls");
    CHECK(stage_calls(off, "turbulence", NULL) == 0, "turbulence ran while off");
    /* (Cs l0)^2 |S| with |S| of order the collapse's shear, u/l0 ~ 100 /s */
    CHECK(eddy > 1e-7 && eddy < 1e-3, "eddy viscosity %g m^2/s in a dam break", eddy);
    mps2p_solver_destroy(on);
    mps2p_solver_destroy(off);

    mps2p_solver *still_on = make(sliding_block("on")), *still_off = make(sliding_block("off"));
    MUST(mps2p_solver_advance_to(still_on, 0.05, NULL, NULL));
    MUST(mps2p_solver_advance_to(still_off, 0.05, NULL, NULL));
    MUST(mps2p_solver_get_stat(still_on, "eddy_viscosity_max", &eddy));
    CHECK(eddy == 0.0, "uniform motion has eddy viscosity %g", eddy);
    double a[200], b[200];
    MUST(mps2p_solver_get_velocities(still_on, a, 200));
    MUST(mps2p_solver_get_velocities(still_off, b, 200));
    CHECK(memcmp(a, b, sizeof a) == 0, "turbulence changed a shear-free flow");
    mps2p_solver_destroy(still_on);
    mps2p_solver_destroy(still_off);
}

/* The neighbour-count free-surface variant: its own stage, only when chosen;
 * it flags every particle the number density flags, and maybe more. */
static void test_free_surface_variants(void)
{
    mps2p_scene *scene = dam_break_scene(0.02);
    MUST(mps2p_scene_set_option(scene, "free_surface", "neighbour_count"));
    mps2p_solver *counted = make(scene), *plain = make(dam_break_scene(0.02));
    double bytes_counted, bytes_plain;
    size_t n;
    MUST(mps2p_solver_particle_count(plain, &n));
    MUST(mps2p_solver_get_stat(counted, "memory_bytes", &bytes_counted));
    MUST(mps2p_solver_get_stat(plain, "memory_bytes", &bytes_plain));
    CHECK(bytes_counted - bytes_plain == 4.0 * (double)n, "count memory %g - %g",
          bytes_counted, bytes_plain);
    int active;
    MUST(mps2p_solver_step(counted));
    MUST(mps2p_solver_step(plain));
    CHECK(stage_calls(counted, "neighbour_count", &active) == 1 && active,
          "neighbour_count stage with the variant");
    CHECK(stage_calls(plain, "neighbour_count", &active) == 0 && !active,
          "neighbour_count stage without the variant");
    double with_count, without;
    MUST(mps2p_solver_get_stat(counted, "surface_particles", &with_count));
    MUST(mps2p_solver_get_stat(plain, "surface_particles", &without));
    CHECK(with_count >= without && without > 0, "surface particles %g (count) vs %g", with_count,
          without);
    mps2p_solver_destroy(counted);
    mps2p_solver_destroy(plain);
}

int main(void)
{
    test_inferred_effects();
    test_memory_follows_stages();
    test_switched_off();
    test_quiescent_without_viscosity();
    test_no_rise_without_gravity();
    test_impossible_requests();
    test_inferred_equals_requested();
    test_two_phase_effects();
    test_turbulence();
    test_free_surface_variants();
    return check_summary("test_effects");
}
