"""Solver: built from a scene, stepped, queried. Fields come back as numpy
arrays that are COPIES: each call copies the solver's current state into a
new array that the caller owns; stepping never changes an array already
returned, and changing the array never changes the solver."""
import numpy as np

from . import errors
from ._core import Owned, check, encode, real
from ._native import ffi, lib

STAT_KEYS = ("max_speed", "kinetic_energy", "potential_energy", "pressure_min",
             "pressure_max", "ppe_unknowns", "ppe_iterations", "ppe_residual",
             "surface_particles", "n0", "lambda", "neighbour_builds", "ppe_iterations_total",
             "dt_next", "ppe_analyses", "eddy_viscosity_max", "memory_bytes", "closest_pair", "diverged_particle",
             # two phases (0 when effect two_phase is off)
             "gas_triggered", "gas_enclosed", "gas_joined", "gas_in_liquid", "gas_capped",
             "gas_pressure_max",
             "gas_ppe_unknowns", "gas_ppe_iterations", "two_phase_active")


class State(Owned):
    """A solver state saved in memory (wraps mps2p_state); freed when collected
    or closed."""

    _what = "state"

    def __init__(self, handle):
        self._own(handle, lib.mps2p_state_destroy)


class Solver(Owned):
    """Wraps mps2p_solver. Solver(scene) copies the scene: the scene may be
    changed or closed afterwards. Free it with close(), a `with` block, or
    garbage collection."""

    _what = "solver"

    def __init__(self, scene=None, _handle=None):
        if _handle is not None:
            self._own(_handle, lib.mps2p_solver_destroy)
            return
        handle = ffi.new("mps2p_solver **")
        check(lib.mps2p_solver_create(scene.handle, handle))
        self._own(handle[0], lib.mps2p_solver_destroy)

    # -- running ------------------------------------------------------------
    def step(self):
        """One time step. Raises DivergedError or SolveError (the solver keeps
        the state from before the step)."""
        check(lib.mps2p_solver_step(self.handle))

    def advance_to(self, end_time, progress=None):
        """Steps until `end_time` exactly. `progress(solver)` is called after
        each step; a true return value stops the run. Returns True when
        end_time was reached, False when progress stopped it. An exception
        raised by progress stops the run and is re-raised here."""
        if progress is None:
            return check(lib.mps2p_solver_advance_to(self.handle, real(end_time, "end time"),
                                                     ffi.NULL, ffi.NULL)) == lib.MPS2P_OK
        failure = []

        @ffi.callback("int(const mps2p_solver *, void *)")
        def callback(_solver, _user):
            try:
                return 1 if progress(self) else 0
            except BaseException as e:  # noqa: B902 - re-raised below
                failure.append(e)
                return 1

        status = lib.mps2p_solver_advance_to(self.handle, real(end_time, "end time"),
                                             callback, ffi.NULL)
        if failure:
            raise failure[0]
        return check(status) == lib.MPS2P_OK

    # -- state ----------------------------------------------------------------
    @property
    def particle_count(self):
        count = ffi.new("size_t *")
        check(lib.mps2p_solver_particle_count(self.handle, count))
        return count[0]

    @property
    def time(self):
        value = ffi.new("double *")
        check(lib.mps2p_solver_get_time(self.handle, value))
        return value[0]

    @property
    def step_count(self):
        value = ffi.new("uint64_t *")
        check(lib.mps2p_solver_get_step_count(self.handle, value))
        return int(value[0])

    @property
    def last_dt(self):
        value = ffi.new("double *")
        check(lib.mps2p_solver_get_last_dt(self.handle, value))
        return value[0]

    def _field(self, getter, dtype, columns):
        n = self.particle_count
        out = np.empty((n, columns) if columns > 1 else (n,), dtype=dtype)
        ctype = "double[]" if dtype == np.float64 else "int[]"
        check(getter(self.handle, ffi.from_buffer(ctype, out, require_writable=True), out.size))
        return out

    def positions(self):
        """(n, 2) float64, a copy."""
        return self._field(lib.mps2p_solver_get_positions, np.float64, 2)

    def velocities(self):
        """(n, 2) float64, a copy."""
        return self._field(lib.mps2p_solver_get_velocities, np.float64, 2)

    def pressure(self):
        """(n,) float64 in Pa, a copy."""
        return self._field(lib.mps2p_solver_get_pressure, np.float64, 1)

    def number_density(self):
        """(n,) float64, a copy."""
        return self._field(lib.mps2p_solver_get_number_density, np.float64, 1)

    def kinds(self):
        """(n,) int32 of KIND_FLUID, KIND_WALL, KIND_DUMMY, a copy."""
        return self._field(lib.mps2p_solver_get_kinds, np.intc, 1)

    def fluid_ids(self):
        """(n,) int32, the fluid id of each particle, -1 for walls; a copy."""
        return self._field(lib.mps2p_solver_get_fluid_ids, np.intc, 1)

    def stat(self, key):
        value = ffi.new("double *")
        check(lib.mps2p_solver_get_stat(self.handle, encode(key, "statistic name"), value))
        return value[0]

    def stats(self):
        """{name: value} of every statistic."""
        return {key: self.stat(key) for key in STAT_KEYS}

    # -- effects and costs -------------------------------------------------
    def effects(self):
        """{name: (active, reason)} of every physical effect, in the library's
        order; reason starts with "inferred:" or "requested:"."""
        count = ffi.new("size_t *")
        check(lib.mps2p_solver_effect_count(self.handle, count))
        name, active, reason = ffi.new("char **"), ffi.new("int *"), ffi.new("char **")
        result = {}
        for i in range(count[0]):
            check(lib.mps2p_solver_get_effect(self.handle, i, name, active, reason))
            result[ffi.string(name[0]).decode()] = (bool(active[0]),
                                                    ffi.string(reason[0]).decode())
        return result

    def stages(self):
        """{name: {"active", "seconds", "calls"}} for the stages of a step, in
        order: wall time and calls since creation or reset_stage_timings()."""
        count = ffi.new("size_t *")
        check(lib.mps2p_solver_stage_count(self.handle, count))
        name, active = ffi.new("char **"), ffi.new("int *")
        seconds, calls = ffi.new("double *"), ffi.new("uint64_t *")
        result = {}
        for i in range(count[0]):
            check(lib.mps2p_solver_get_stage(self.handle, i, name, active, seconds, calls))
            result[ffi.string(name[0]).decode()] = {
                "active": bool(active[0]), "seconds": seconds[0], "calls": int(calls[0])}
        return result

    def reset_stage_timings(self):
        check(lib.mps2p_solver_reset_stage_timings(self.handle))

    # -- coupling: bodies, forces, host inputs, windows ----------------------
    def bodies(self):
        """[(name, particles)] by body id (0 is "walls")."""
        count = ffi.new("int *")
        check(lib.mps2p_solver_body_count(self.handle, count))
        name, particles = ffi.new("char **"), ffi.new("size_t *")
        result = []
        for body in range(count[0]):
            check(lib.mps2p_solver_get_body(self.handle, body, name, particles))
            result.append((ffi.string(name[0]).decode(), particles[0]))
        return result

    def body_ids(self):
        """(n,) int32: the body of each particle, -1 for fluid; a copy."""
        return self._field(lib.mps2p_solver_get_body_ids, np.intc, 1)

    def body_force(self, body_id, fluid_id=-1, about=(0.0, 0.0)):
        """(force (2,) N/m, moment N m/m about `about`) that the fluid's pressure
        exerts on the body; fluid_id >= 0 gives that fluid's part."""
        force, moment = ffi.new("double[2]"), ffi.new("double *")
        point = ffi.new("double[2]", [real(about[0], "about"), real(about[1], "about")])
        check(lib.mps2p_solver_body_force(self.handle, int(body_id), int(fluid_id), force,
                                          moment, point))
        return np.array([force[0], force[1]]), moment[0]

    def set_body_motion(self, body_id, velocity=(0.0, 0.0), angular_velocity=0.0,
                        about=(0.0, 0.0)):
        """Rigid motion of the body from the next step on (m/s, rad/s about `about`)."""
        v = ffi.new("double[2]", [real(velocity[0], "velocity"), real(velocity[1], "velocity")])
        point = ffi.new("double[2]", [real(about[0], "about"), real(about[1], "about")])
        check(lib.mps2p_solver_set_body_motion(self.handle, int(body_id), v,
                                               real(angular_velocity, "angular velocity"),
                                               point))

    def set_body_positions(self, body_id, positions):
        """Positions (m, 2) the body's particles reach at the end of the next step;
        None clears them."""
        if positions is None:
            check(lib.mps2p_solver_set_body_positions(self.handle, int(body_id), ffi.NULL, 0))
            return
        positions = np.ascontiguousarray(positions, dtype=np.float64)
        check(lib.mps2p_solver_set_body_positions(self.handle, int(body_id),
                                                  ffi.from_buffer("double[]", positions),
                                                  positions.size))

    @property
    def gravity(self):
        g = ffi.new("double[2]")
        check(lib.mps2p_solver_get_gravity(self.handle, g))
        return (g[0], g[1])

    @gravity.setter
    def gravity(self, value):
        check(lib.mps2p_solver_set_gravity(self.handle, real(value[0], "gravity"),
                                           real(value[1], "gravity")))

    def set_body_forces(self, accelerations):
        """Per-particle accelerations (n, 2) added to the fluid every step; None clears."""
        if accelerations is None:
            check(lib.mps2p_solver_set_body_forces(self.handle, ffi.NULL, 0))
            return
        accelerations = np.ascontiguousarray(accelerations, dtype=np.float64)
        check(lib.mps2p_solver_set_body_forces(self.handle,
                                               ffi.from_buffer("double[]", accelerations),
                                               accelerations.size))

    def save_state(self):
        """Everything the next step depends on, in memory (for implicit coupling
        iterations): restore_state(state) returns the solver to it bitwise."""
        handle = ffi.new("mps2p_state **")
        check(lib.mps2p_solver_save_state(self.handle, handle))
        return State(handle[0])

    def restore_state(self, state):
        check(lib.mps2p_solver_restore_state(self.handle, state.handle))

    def advance_window(self, end_time):
        """One coupling window to end_time exactly; returns the steps it took."""
        steps = ffi.new("uint64_t *")
        check(lib.mps2p_solver_advance_window(self.handle, real(end_time, "end time"), steps))
        return int(steps[0])

    # -- probes and checkpoints -------------------------------------------
    def probe(self, points):
        """Pressure and velocity at arbitrary points, MPS-weighted from the
        particles around each: returns (pressure (m,), velocity (m, 2), inside (m,)
        bool). Points outside the fluid get 0 and inside False."""
        points = np.ascontiguousarray(points, dtype=np.float64)
        if points.ndim == 1:
            points = points.reshape(1, -1)
        if points.ndim != 2 or points.shape[1] != 2:
            raise ValueError("points must have shape (m, 2), got %s" % (points.shape,))
        m = points.shape[0]
        pressure = np.empty(m)
        velocity = np.empty((m, 2))
        inside = np.empty(m, dtype=np.intc)
        check(lib.mps2p_solver_probe(self.handle, m, ffi.from_buffer("double[]", points),
                                     ffi.from_buffer("double[]", pressure, require_writable=True),
                                     ffi.from_buffer("double[]", velocity, require_writable=True),
                                     ffi.from_buffer("int[]", inside, require_writable=True)))
        return pressure, velocity, inside.astype(bool)

    def front(self, fluid_id=-1, below=None):
        """Surge front: the largest x of the fluid's particles (any fluid for
        fluid_id -1) lower than `below` (m), plus l0/2."""
        x = ffi.new("double *")
        check(lib.mps2p_solver_front(self.handle, int(fluid_id),
                                     real(below if below is not None else float("inf"), "below"), x))
        return x[0]

    def save_checkpoint(self, path):
        """Writes everything the next step depends on (atomically)."""
        check(lib.mps2p_solver_save_checkpoint(self.handle, encode(str(path), "path")))

    @staticmethod
    def load_checkpoint(path):
        """A solver restored from a checkpoint; it continues bitwise as the saved one would."""
        handle = ffi.new("mps2p_solver **")
        check(lib.mps2p_solver_load_checkpoint(encode(str(path), "path"), handle))
        return Solver(_handle=handle[0])


__all__ = ["Solver", "STAT_KEYS", "errors"]
