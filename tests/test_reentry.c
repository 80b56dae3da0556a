/* Re-entry (issue 20, defect 3): the progress callback of
 * mps2p_solver_advance_to calling back into its own solver. Stepping or
 * restoring it there is refused with MPS2P_ERR_STATE; destroying it there
 * frees it only when the run has returned (it was a use-after-free in
 * timestep_choose); the inputs (gravity, ...) may be set between steps. */
#include <mps2p.h>
#include "check.h"

#include <string.h>

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

typedef struct nested {
    int calls;
    int step, advance, window, restore, gravity; /* statuses from inside */
    char message[512];
    mps2p_state *state;
} nested;

/* Calls everything that must be refused from inside, once; the callback's
 * solver is its own, so the const is cast away as a host would. */
static int call_back_in(const mps2p_solver *solver, void *data)
{
    nested *n = data;
    mps2p_solver *s = (mps2p_solver *)solver;
    if (n->calls++ > 0)
        return 0;
    n->step = mps2p_solver_step(s);
    snprintf(n->message, sizeof n->message, "%s", mps2p_last_error());
    n->advance = mps2p_solver_advance_to(s, 0.2, NULL, NULL);
    uint64_t taken = 99;
    n->window = mps2p_solver_advance_window(s, 0.2, &taken);
    if (taken != 0)
        n->window = 99;
    n->restore = mps2p_solver_restore_state(s, n->state);
    n->gravity = mps2p_solver_set_gravity(s, 0.0, -9.81);
    return 0;
}

static void test_nested_calls_refused(void)
{
    mps2p_solver *solver = small_dam_break();
    nested n = {0};
    MUST(mps2p_solver_save_state(solver, &n.state));
    int status = mps2p_solver_advance_to(solver, 0.02, call_back_in, &n);
    double t;
    uint64_t steps;
    MUST(mps2p_solver_get_time(solver, &t));
    MUST(mps2p_solver_get_step_count(solver, &steps));
    CHECK(status == MPS2P_OK, "outer run: %s", mps2p_status_string(status));
    CHECK(t == 0.02, "the outer run ends at 0.02 s, not at the nested time: %.17g", t);
    CHECK(n.calls == (int)steps, "%d callbacks for %llu steps", n.calls,
          (unsigned long long)steps);
    CHECK(n.step == MPS2P_ERR_STATE, "step from the callback: %s",
          mps2p_status_string(n.step));
    CHECK(strstr(n.message, "progress callback") != NULL, "message: \"%s\"", n.message);
    CHECK(n.advance == MPS2P_ERR_STATE, "advance_to from the callback: %s",
          mps2p_status_string(n.advance));
    CHECK(n.window == MPS2P_ERR_STATE, "advance_window from the callback: %d", n.window);
    CHECK(n.restore == MPS2P_ERR_STATE, "restore_state from the callback: %s",
          mps2p_status_string(n.restore));
    CHECK(n.gravity == MPS2P_OK, "set_gravity between steps: %s",
          mps2p_status_string(n.gravity));
    /* after the run everything works again */
    MUST(mps2p_solver_step(solver));
    MUST(mps2p_solver_restore_state(solver, n.state));
    MUST(mps2p_solver_advance_window(solver, 0.01, NULL));
    mps2p_state_destroy(n.state);
    mps2p_solver_destroy(solver);
}

static int destroy_it(const mps2p_solver *solver, void *data)
{
    int *calls = data;
    ++*calls;
    mps2p_solver_destroy((mps2p_solver *)solver);
    return 0; /* "go on": the run stops anyway, its solver is gone */
}

/* Destroying the solver from its callback: the run stops after that
 * callback, the solver is freed when advance_to returns (ASan and LSan see
 * neither a use after free nor a leak), and the call says so. */
static void test_destroy_from_callback(void)
{
    mps2p_solver *solver = small_dam_break();
    int calls = 0;
    int status = mps2p_solver_advance_to(solver, 0.05, destroy_it, &calls);
    CHECK(status == MPS2P_ERR_STATE, "advance_to after its callback destroyed the solver: %s",
          mps2p_status_string(status));
    CHECK(strstr(mps2p_last_error(), "destroyed") != NULL, "message: \"%s\"",
          mps2p_last_error());
    CHECK(calls == 1, "%d callbacks after the destroy", calls);
}

/* Another solver may be run from a callback: the guard is per handle. */
static int run_other(const mps2p_solver *solver, void *data)
{
    (void)solver;
    mps2p_solver *other = data;
    double t;
    mps2p_solver_get_time(other, &t);
    return mps2p_solver_advance_to(other, t + 1e-3, NULL, NULL) != MPS2P_OK;
}

static void test_other_solver_from_callback(void)
{
    mps2p_solver *a = small_dam_break(), *b = small_dam_break();
    MUST(mps2p_solver_advance_to(a, 0.01, run_other, b));
    uint64_t steps;
    double t;
    MUST(mps2p_solver_get_step_count(a, &steps));
    MUST(mps2p_solver_get_time(b, &t));
    CHECK(fabs(t - 1e-3 * (double)steps) < 1e-12, "the other solver is at %g s after %llu "
          "callbacks", t, (unsigned long long)steps);
    mps2p_solver_destroy(a);
    mps2p_solver_destroy(b);
}

int main(void)
{
    test_nested_calls_refused();
    test_destroy_from_callback();
    test_other_solver_from_callback();
    return check_summary("test_reentry");
}
