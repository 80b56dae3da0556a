// A hinged gate in the path of a dam break, from C++17: the host integrates
// the gate's angle with one rigid-body ODE (GSL's gsl_odeiv2 driver, rk8pd)
// and drives the wall body through libmps2p, window by window.
//
//   gate [l0 [end_time [out.csv [iterations [min_theta]]]]]
//
// The gate: a steel plate (GATE_THICKNESS x GATE_LENGTH, MASS = 47.1 kg per
// metre of depth) hanging from a hinge at its top, the lower end one lattice
// row above the floor; in the fluid, three lattice columns thick. theta is its angle from hanging straight down,
// counter-clockwise positive (the water pushes it that way, towards +x):
//
//   I theta'' = M_fluid + M_gravity - c theta',
//   I = m L^2 / 3 (a plate about its end), M_gravity = -m g (L/2) sin theta,
//
// M_fluid the moment of the water's pressure about the hinge
// (mps2p_solver_body_force). Each coupling window of WINDOW seconds:
//   1. the ODE is integrated over the window with M_fluid going linearly
//      from its value at the start to the one predicted at the end (at first
//      held constant);
//   2. the body turns about the hinge at the window's mean angular velocity
//      (theta_end - theta_start) / WINDOW, so that its geometric angle is
//      theta_end when the window ends;
//   3. with iterations > 1, the solver's state is saved before the window
//      and restored after it, and steps 1-2 repeat with the end moment just
//      measured (implicit coupling by fixed-point iteration).
// Writes t, theta, theta', M_fluid, M_gravity per window as CSV. With
// min_theta, exits 1 unless the largest |theta| reaches it.
#include <mps2p.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>

namespace {

constexpr double G = 9.81;
constexpr double COLUMN_WIDTH = 0.15, COLUMN_HEIGHT = 0.30, TANK = 0.60;
constexpr double GATE_X = 0.25;          // left face of the gate (m)
constexpr double GATE_LENGTH = 0.20;     // hinge to lower end (m)
constexpr double GATE_THICKNESS = 0.03;  // of the steel plate, for its mass
constexpr double MASS = 7850.0 * GATE_THICKNESS * GATE_LENGTH;  // steel, kg per m depth
constexpr double DAMPING = 0.5;          // c, N m s per rad per m depth
constexpr double WINDOW = 0.005;         // coupling window (s)

// Turns a libmps2p status into an exception that says what failed.
void check(int status, const char *what)
{
    if (status < 0)
        throw std::runtime_error(std::string(what) + ": " + mps2p_status_string(status) + ": " +
                                 mps2p_last_error());
}

struct SceneDeleter {
    void operator()(mps2p_scene *s) const { mps2p_scene_destroy(s); }
};
struct SolverDeleter {
    void operator()(mps2p_solver *s) const { mps2p_solver_destroy(s); }
};
struct StateDeleter {
    void operator()(mps2p_state *s) const { mps2p_state_destroy(s); }
};
struct DriverDeleter {
    void operator()(gsl_odeiv2_driver *d) const { gsl_odeiv2_driver_free(d); }
};
using Scene = std::unique_ptr<mps2p_scene, SceneDeleter>;
using Solver = std::unique_ptr<mps2p_solver, SolverDeleter>;
using State = std::unique_ptr<mps2p_state, StateDeleter>;

// The gate's equation of motion, y = (theta, theta'), with the fluid's moment
// interpolated linearly over the window [t0, t0 + WINDOW].
struct Gate {
    double inertia = MASS * GATE_LENGTH * GATE_LENGTH / 3.0;
    double t0 = 0.0, moment_start = 0.0, moment_end = 0.0;

    double fluid_moment(double t) const
    {
        double s = (t - t0) / WINDOW;
        return moment_start + s * (moment_end - moment_start);
    }
    static double gravity_moment(double theta) { return -MASS * G * 0.5 * GATE_LENGTH * std::sin(theta); }

    static int rhs(double t, const double y[], double dydt[], void *params)
    {
        const Gate *gate = static_cast<const Gate *>(params);
        dydt[0] = y[1];
        dydt[1] = (gate->fluid_moment(t) + gravity_moment(y[0]) - DAMPING * y[1]) / gate->inertia;
        return GSL_SUCCESS;
    }
};

Solver build(double l0, int *gate_id, double hinge[2])
{
    mps2p_scene *raw = nullptr;
    check(mps2p_scene_create(l0, &raw), "scene");
    Scene scene(raw);
    int water = 0;
    check(mps2p_scene_add_fluid(raw, "water", 1000.0, 1e-6, &water), "fluid");
    check(mps2p_scene_add_fluid_box(raw, water, 0.0, 0.0, COLUMN_WIDTH, COLUMN_HEIGHT), "column");
    check(mps2p_scene_add_tank(raw, 0.0, 0.0, TANK, 0.7, 1), "tank");
    // the plate, three lattice columns thick (walls on the faces, dummies
    // inside) whatever l0, one lattice row above the floor
    const double bottom = l0, top = bottom + GATE_LENGTH, thickness = 3.0 * l0;
    check(mps2p_scene_add_body_box(raw, "gate", GATE_X, bottom, GATE_X + thickness, top,
                                   gate_id), "gate");
    hinge[0] = GATE_X + 0.5 * thickness;
    hinge[1] = top;
    mps2p_solver *solver = nullptr;
    check(mps2p_solver_create(raw, &solver), "solver");
    return Solver(solver);
}

}  // namespace

int main(int argc, char **argv)
{
    const double l0 = argc > 1 ? std::atof(argv[1]) : 0.01;
    const double end_time = argc > 2 ? std::atof(argv[2]) : 0.6;
    const char *csv_path = argc > 3 ? argv[3] : "gate.csv";
    const int iterations = argc > 4 ? std::atoi(argv[4]) : 1;
    const double min_theta = argc > 5 ? std::atof(argv[5]) : -1.0;
    if (!(l0 > 0.0) || !(end_time > 0.0) || iterations < 1) {
        std::fprintf(stderr, "usage: gate [l0 > 0 [end_time > 0 [out.csv [iterations >= 1 "
                             "[min_theta]]]]]\n");
        return 2;
    }
    gsl_set_error_handler_off();  // GSL errors come back as statuses
    try {
        int gate_id = 0;
        double hinge[2];
        Solver solver = build(l0, &gate_id, hinge);
        FILE *csv = std::fopen(csv_path, "w");
        if (!csv)
            throw std::runtime_error(std::string("cannot write ") + csv_path);
        std::unique_ptr<FILE, int (*)(FILE *)> csv_file(csv, std::fclose);
        std::fprintf(csv, "t,theta,omega,moment_fluid,moment_gravity\n");

        Gate gate;
        gsl_odeiv2_system system{Gate::rhs, nullptr, 2, &gate};
        std::unique_ptr<gsl_odeiv2_driver, DriverDeleter> driver(
            gsl_odeiv2_driver_alloc_y_new(&system, gsl_odeiv2_step_rk8pd, 1e-5, 1e-10, 1e-10));
        if (!driver)
            throw std::runtime_error("out of memory for the ODE driver");

        double y[2] = {0.0, 0.0}, force[2], moment = 0.0, time = 0.0, largest = 0.0;
        uint64_t steps = 0;
        const double zero[2] = {0.0, 0.0};
        check(mps2p_solver_body_force(solver.get(), gate_id, -1, force, &moment, hinge), "moment");
        std::fprintf(csv, "%.6f,%.8f,%.8f,%.6f,%.6f\n", time, y[0], y[1], moment,
                     Gate::gravity_moment(y[0]));
        while (time < end_time - 1e-12) {
            const double t1 = std::fmin(time + WINDOW, end_time);
            State saved;
            if (iterations > 1) {
                mps2p_state *raw = nullptr;
                check(mps2p_solver_save_state(solver.get(), &raw), "save state");
                saved.reset(raw);
            }
            gate.t0 = time;
            gate.moment_start = gate.moment_end = moment;  // held at first
            double y_end[2] = {y[0], y[1]}, moment_end = moment;
            for (int k = 0; k < iterations; k++) {
                if (k > 0)
                    check(mps2p_solver_restore_state(solver.get(), saved.get()), "restore");
                y_end[0] = y[0];
                y_end[1] = y[1];
                double t = time;
                gsl_odeiv2_driver_reset(driver.get());
                if (gsl_odeiv2_driver_apply(driver.get(), &t, t1, y_end) != GSL_SUCCESS)
                    throw std::runtime_error("the gate's ODE failed");
                const double omega = (y_end[0] - y[0]) / (t1 - time);
                check(mps2p_solver_set_body_motion(solver.get(), gate_id, zero, omega, hinge),
                      "gate motion");
                uint64_t taken = 0;
                check(mps2p_solver_advance_window(solver.get(), t1, &taken), "window");
                steps += taken;
                check(mps2p_solver_body_force(solver.get(), gate_id, -1, force, &moment_end,
                                              hinge), "moment");
                gate.moment_end = moment_end;
            }
            y[0] = y_end[0];
            y[1] = y_end[1];
            moment = moment_end;
            time = t1;
            largest = std::fmax(largest, std::fabs(y[0]));
            std::fprintf(csv, "%.6f,%.8f,%.8f,%.6f,%.6f\n", time, y[0], y[1], moment,
                         Gate::gravity_moment(y[0]));
        }
        std::printf("gate: t = %.3f s, %llu steps (iterations %d), theta = %.4f rad, "
                    "largest |theta| = %.4f rad, M_fluid = %.3f N m/m; CSV in %s\n",
                    time, static_cast<unsigned long long>(steps), iterations, y[0], largest,
                    moment, csv_path);
        if (min_theta >= 0.0 && largest < min_theta) {
            std::fprintf(stderr, "gate: the gate moved %.4f rad, less than %.4f\n", largest,
                         min_theta);
            return 1;
        }
    } catch (const std::exception &e) {
        std::fprintf(stderr, "gate: %s\n", e.what());
        return 1;
    }
    return 0;
}
