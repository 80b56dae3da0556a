/* libFuzzer target: sequences of mps2p_solver_advance_to, _advance_window,
 * _step and state save/restore with window lengths of every size, tiny ones
 * included (issue 20: a window of 1e-9 s diverged falsely), and progress
 * callbacks that stop the run or call back into the solver. The bytes pick
 * a small dam break's numerics (pressure solver, source, gradient, fixed or
 * adaptive dt) and up to 24 operations. Checked after every call:
 *   - a status is OK, STOPPED or an error with a message; an invalid end
 *     time (NaN, before now) is MPS2P_ERR_INVALID and changes nothing;
 *   - an advance that succeeds lands on its end time exactly, and
 *     advance_window's step count is the solver's;
 *   - time never goes back, but through restore_state;
 *   - calls back into the solver from its callback are MPS2P_ERR_STATE;
 *   - with the default numerics, no divergence before 0.3 s: the small dam
 *     break never diverges with full steps, so one after short windows is
 *     a false one.
 * Windows that would take more than MAX_STEPS steps are not asked for
 * (valid, and slow). */
#include <mps2p.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "fuzz_input.h"

#define MAX_OPS 24
#define MAX_STEPS 50.0       /* steps one call may take */
#define MAX_TOTAL_STEPS 150  /* steps one input may take */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void bug(const char *what, int status)
{
    fprintf(stderr, "fuzz_advance: %s (%s: \"%s\")\n", what, mps2p_status_string(status),
            mps2p_last_error());
    abort();
}

static void expect_message(int status)
{
    if (status < 0 && mps2p_last_error()[0] == '\0')
        bug("an error without a message", status);
}

static mps2p_solver *make_solver(uint8_t variant, double fixed_dt)
{
    static const char *const solvers[] = {"cholmod", "cg"};
    static const char *const sources[] = {"density", "mixed", "ecs"};
    static const char *const gradients[] = {"minimum", "corrected"};
    mps2p_scene *scene;
    mps2p_solver *solver = NULL;
    int water;
    if (mps2p_scene_create(0.05, &scene) != MPS2P_OK)
        bug("scene", -1);
    int status = mps2p_scene_add_fluid(scene, "water", 1000.0, variant & 0x40 ? 1e-2 : 1e-6,
                                       &water);
    if (!status)
        status = mps2p_scene_add_fluid_box(scene, water, 0.0, 0.0, 0.1, 0.2);
    if (!status)
        status = mps2p_scene_add_tank(scene, 0.0, 0.0, 0.3, 0.3, 1);
    if (!status)
        status = mps2p_scene_set_option(scene, "pressure_solver", solvers[variant & 1]);
    if (!status)
        status = mps2p_scene_set_option(scene, "ppe_source", sources[(variant >> 1) % 3]);
    if (!status)
        status = mps2p_scene_set_option(scene, "pressure_gradient", gradients[(variant >> 3) & 1]);
    if (!status)
        status = mps2p_scene_set_param(scene, "dt", fixed_dt);
    if (!status)
        status = mps2p_solver_create(scene, &solver);
    if (status)
        bug("a valid scene refused", status);
    mps2p_scene_destroy(scene);
    return solver;
}

/* A window length: a table of awkward values, multiples of the next dt, or
 * raw bits (NaN, infinities, negatives, denormals). */
static double take_window(fuzz_input *in, double dt)
{
    static const double absolute[] = {0.0, 5e-324, 1e-300, 1e-15, 1e-12, 1.5e-12, 1e-11,
                                      1e-9, 1e-6, 1e-5, 1e-4, 1e-3, 0.01, -1e-9, -1.0};
    static const double of_dt[] = {0.001, 0.01, 0.1, 0.3, 0.49, 0.4999999, 0.5, 0.5000001,
                                   0.51, 0.9, 0.999999999, 1.0, 1.0 + 1e-10, 1.0000001, 1.01,
                                   1.5, 1.999, 2.0, 2.5, 7.3, 33.0};
    uint8_t how = take_u8(in);
    switch (how % 4) {
    case 0:
        return absolute[take_u8(in) % (sizeof absolute / sizeof absolute[0])];
    case 1:
        return dt * of_dt[take_u8(in) % (sizeof of_dt / sizeof of_dt[0])];
    case 2:
        return dt * take_u16(in) / 4096.0;
    default:
        return take_double(in);
    }
}

typedef struct callback_data {
    int mode, calls, stop_after;
    int inner; /* status of the call made from inside */
    mps2p_state *state;
} callback_data;

static int progress(const mps2p_solver *solver, void *user)
{
    callback_data *cb = user;
    mps2p_solver *s = (mps2p_solver *)solver;
    cb->calls++;
    if (cb->mode == 1 && cb->calls == 1) { /* re-entry: each must be refused */
        int refused = mps2p_solver_step(s) == MPS2P_ERR_STATE &&
                      mps2p_solver_advance_to(s, 1.0, NULL, NULL) == MPS2P_ERR_STATE &&
                      mps2p_solver_advance_window(s, 1.0, NULL) == MPS2P_ERR_STATE &&
                      (!cb->state ||
                       mps2p_solver_restore_state(s, cb->state) == MPS2P_ERR_STATE);
        cb->inner = refused ? MPS2P_ERR_STATE : MPS2P_OK;
    }
    return cb->calls >= cb->stop_after;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = {data, size};
    uint8_t variant = take_u8(&in);
    static const double fixed[] = {1e-3, 2e-3, 3.7e-4, 1e-5};
    double fixed_dt = variant & 0x80 ? fixed[(variant >> 4) & 3] : 0.0;
    /* the reference numerics (the defaults when this was written): adaptive dt,
     * cholmod, density source, minimum gradient, water */
    const int default_numerics = !(variant & 0xC9) && (variant >> 1) % 3 == 0;
    mps2p_solver *solver = make_solver(variant, fixed_dt);
    mps2p_state *state = NULL;
    double time = 0.0, saved_time = 0.0;
    uint64_t steps_total = 0;
    int diverged = 0;
    for (int op = 0; op < MAX_OPS && in.left && steps_total < MAX_TOTAL_STEPS; op++) {
        uint8_t code = take_u8(&in) % 8;
        double dt = 0.0, now = 0.0;
        mps2p_solver_get_stat(solver, "dt_next", &dt);
        mps2p_solver_get_time(solver, &now);
        if (now < time)
            bug("time went back", MPS2P_OK);
        time = now;
        uint64_t before = 0, after = 0, taken = 0;
        mps2p_solver_get_step_count(solver, &before);
        int status = MPS2P_OK, advanced = 0;
        double end = now;
        if (code <= 2 || code == 5 || code == 6) {
            double w = take_window(&in, dt);
            end = now + w;
            double steps = (end - now) / dt;
            /* valid and slow; beyond 2e9 steps advance_to refuses at once */
            if (isfinite(end) && end > now && steps > MAX_STEPS && steps < 2e9)
                continue;
            advanced = 1;
        }
        callback_data cb = {0, 0, 1 << 30, MPS2P_OK, state};
        switch (code) {
        case 0:
            status = mps2p_solver_advance_to(solver, end, NULL, NULL);
            break;
        case 1:
            status = mps2p_solver_advance_window(solver, end, &taken);
            break;
        case 2:
            status = mps2p_solver_step(solver);
            advanced = 0;
            break;
        case 3:
            mps2p_state_destroy(state);
            state = NULL;
            status = mps2p_solver_save_state(solver, &state);
            saved_time = now;
            break;
        case 4:
            if (!state)
                continue;
            status = mps2p_solver_restore_state(solver, state);
            if (status == MPS2P_OK) {
                diverged = 0;
                time = saved_time;
            }
            break;
        case 5: /* a callback that stops after a few steps */
            cb.stop_after = 1 + take_u8(&in) % 4;
            status = mps2p_solver_advance_to(solver, end, progress, &cb);
            break;
        case 6: /* a callback that calls back in */
            cb.mode = 1;
            status = mps2p_solver_advance_to(solver, end, progress, &cb);
            if (cb.calls > 0 && cb.inner != MPS2P_ERR_STATE)
                bug("a call from the progress callback was not refused", cb.inner);
            break;
        default: {
            double g = -9.81 + (int8_t)take_u8(&in) / 16.0;
            status = mps2p_solver_set_gravity(solver, 0.0, g);
            break;
        }
        }
        expect_message(status);
        mps2p_solver_get_step_count(solver, &after);
        mps2p_solver_get_time(solver, &now);
        if (code != 4)
            steps_total += after - before;
        if (code == 1 && taken != after - before)
            bug("advance_window's step count is not the solver's", status);
        if (advanced && !(isfinite(end) && end >= time)) {
            if (status != MPS2P_ERR_INVALID || after != before)
                bug("a bad end time was not refused, or changed the solver", status);
        } else if (advanced && (end - time) / dt >= 2e9) {
            if (status != MPS2P_ERR_INVALID || after != before)
                bug("a window of more than 1e9 steps was not refused at once", status);
        } else if (advanced && status == MPS2P_OK && now != end) {
            bug("an advance that succeeded did not land on its end time", status);
        }
        if (diverged && code != 4 && after != before)
            bug("a diverged solver stepped", status);
        if (status == MPS2P_ERR_DIVERGED)
            diverged = 1;
        if (status == MPS2P_ERR_DIVERGED && default_numerics && now < 0.3)
            bug("a false divergence after short windows", status);
    }
    mps2p_state_destroy(state);
    mps2p_solver_destroy(solver);
    return 0;
}
