/* The state in memory, as a coupling host's implicit iterations use it: save,
 * take a window with inputs A, restore, take it again with A: bitwise the
 * same; with inputs B: different; a restore after a divergence gives a
 * solver that steps again; a state of another solver is refused. */
#include <string.h>
#include "scenes.h"

#define L0 0.02

/* The dam break against a gate (body 1) hinged at its top. */
static mps2p_solver *gate_dam_break(int *gate)
{
    mps2p_scene *scene = dam_break_scene(L0);
    MUST(mps2p_scene_add_body_box(scene, "gate", 0.30, 0.02, 0.34, 0.20, gate));
    mps2p_solver *solver;
    MUST(mps2p_solver_create(scene, &solver));
    mps2p_scene_destroy(scene);
    return solver;
}

static const double HINGE[2] = {0.32, 0.20};

typedef struct inputs {
    double omega, gx, gy;
} inputs;

typedef struct window {
    size_t n;
    double *values; /* positions, velocities, pressure */
    double time, force[2], moment;
    uint64_t steps, taken;
} window;

static window take_window(mps2p_solver *solver, int gate, inputs in, double end)
{
    const double still[2] = {0.0, 0.0};
    MUST(mps2p_solver_set_body_motion(solver, gate, still, in.omega, HINGE));
    MUST(mps2p_solver_set_gravity(solver, in.gx, in.gy));
    window w;
    MUST(mps2p_solver_advance_window(solver, end, &w.taken));
    MUST(mps2p_solver_particle_count(solver, &w.n));
    w.values = malloc(5 * w.n * sizeof *w.values);
    MUST(mps2p_solver_get_positions(solver, w.values, 2 * w.n));
    MUST(mps2p_solver_get_velocities(solver, w.values + 2 * w.n, 2 * w.n));
    MUST(mps2p_solver_get_pressure(solver, w.values + 4 * w.n, w.n));
    MUST(mps2p_solver_get_time(solver, &w.time));
    MUST(mps2p_solver_get_step_count(solver, &w.steps));
    MUST(mps2p_solver_body_force(solver, gate, -1, w.force, &w.moment, HINGE));
    return w;
}

static int same_window(const window *a, const window *b)
{
    return a->n == b->n && a->steps == b->steps && a->taken == b->taken &&
           !memcmp(a->values, b->values, 5 * a->n * sizeof *a->values) &&
           !memcmp(&a->time, &b->time, sizeof a->time) &&
           !memcmp(a->force, b->force, sizeof a->force) &&
           !memcmp(&a->moment, &b->moment, sizeof a->moment);
}

static void test_iterations(void)
{
    int gate;
    mps2p_solver *solver = gate_dam_break(&gate);
    MUST(mps2p_solver_advance_to(solver, 0.15, NULL, NULL)); /* the water reaches the gate */
    mps2p_state *state = NULL;
    MUST(mps2p_solver_save_state(solver, &state));
    const inputs a = {0.5, 0.0, -9.81}, b = {-0.5, 0.2, -9.81};
    window first = take_window(solver, gate, a, 0.2);
    MUST(mps2p_solver_restore_state(solver, state));
    double time;
    MUST(mps2p_solver_get_time(solver, &time));
    CHECK(time == 0.15, "restored time %.17g", time);
    window again = take_window(solver, gate, a, 0.2);
    CHECK(same_window(&first, &again), "inputs A twice: the windows differ");
    MUST(mps2p_solver_restore_state(solver, state));
    window other = take_window(solver, gate, b, 0.2);
    CHECK(!same_window(&first, &other), "inputs B gave the window of inputs A");
    printf("window 0.15-0.2 s, %llu steps: gate moment about the hinge %.4f N m/m with A, "
           "%.4f again after restore (bitwise %s), %.4f with B\n",
           (unsigned long long)first.taken, first.moment, again.moment,
           same_window(&first, &again) ? "equal" : "DIFFERENT", other.moment);

    free(first.values);
    free(again.values);
    free(other.values);
    mps2p_state_destroy(state);
    mps2p_solver_destroy(solver);
}

/* A restore after a divergence gives a solver that steps again. */
static void test_divergence_undone(void)
{
    int gate;
    mps2p_solver *solver = gate_dam_break(&gate);
    MUST(mps2p_solver_advance_to(solver, 0.05, NULL, NULL));
    mps2p_state *state;
    MUST(mps2p_solver_save_state(solver, &state));
    size_t n;
    MUST(mps2p_solver_particle_count(solver, &n));
    double *shove = malloc(2 * n * sizeof *shove);
    for (size_t i = 0; i < 2 * n; i++)
        shove[i] = i % 2 ? 0.0 : 1e7;
    MUST(mps2p_solver_set_body_forces(solver, shove, 2 * n));
    free(shove);
    int status = mps2p_solver_step(solver);
    CHECK(status == MPS2P_ERR_DIVERGED, "a 1e7 m/s^2 shove gave %s", mps2p_status_string(status));
    CHECK(mps2p_solver_step(solver) == MPS2P_ERR_STATE, "a diverged solver stepped");
    MUST(mps2p_solver_restore_state(solver, state));
    status = mps2p_solver_advance_to(solver, 0.1, NULL, NULL);
    CHECK(status == MPS2P_OK, "after restoring, the solver does not step: %s",
          mps2p_solver_last_error(solver));
    mps2p_state_destroy(state);
    mps2p_solver_destroy(solver);
}

static void test_arguments(void)
{
    int gate;
    mps2p_solver *solver = gate_dam_break(&gate), *plain, *walled;
    mps2p_scene *scene = dam_break_scene(L0);
    MUST(mps2p_solver_create(scene, &plain));
    /* the same particles, the gate's in body 0: same count, other bodies */
    MUST(mps2p_scene_add_wall_box(scene, 0.30, 0.02, 0.34, 0.20));
    MUST(mps2p_solver_create(scene, &walled));
    mps2p_scene_destroy(scene);
    mps2p_state *state = (mps2p_state *)&state, *mine;
    CHECK(mps2p_solver_save_state(NULL, &state) == MPS2P_ERR_NULL && state == NULL,
          "NULL solver");
    CHECK(mps2p_solver_save_state(solver, NULL) == MPS2P_ERR_NULL, "NULL output");
    CHECK(mps2p_solver_restore_state(NULL, state) == MPS2P_ERR_NULL, "NULL solver");
    CHECK(mps2p_solver_restore_state(solver, NULL) == MPS2P_ERR_NULL, "NULL state");
    MUST(mps2p_solver_save_state(solver, &mine));
    CHECK(mps2p_solver_restore_state(plain, mine) == MPS2P_ERR_INVALID,
          "a state of a solver with other particles was accepted");
    printf("refused: %s\n", mps2p_solver_last_error(plain));
    CHECK(mps2p_solver_restore_state(walled, mine) == MPS2P_ERR_INVALID,
          "a state of a solver with other bodies was accepted");
    double time = -1.0;
    MUST(mps2p_solver_get_time(walled, &time));
    CHECK(time == 0.0, "a refused restore changed the time to %g", time);
    mps2p_state_destroy(mine);
    mps2p_state_destroy(NULL);
    mps2p_solver_destroy(solver);
    mps2p_solver_destroy(plain);
    mps2p_solver_destroy(walled);
}

int main(void)
{
    test_iterations();
    test_divergence_undone();
    test_arguments();
    return check_summary("test_state");
}
