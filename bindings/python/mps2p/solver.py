"""Solver: built from a scene, stepped, queried. Fields come back as numpy
arrays that are COPIES: each call copies the solver's current state into a
new array that the caller owns; stepping never changes an array already
returned, and changing the array never changes the solver."""
import threading

import numpy as np

from . import errors
from ._core import Owned, check, encode, encode_path, index, real, real_array
from ._native import ffi, lib



def stat_info():
    """{key: (description, is_count)} for every statistic, in the C
    library's order (mps2p_stat_info)."""
    count = ffi.new("size_t *")
    check(lib.mps2p_stat_count(count))
    key, description, is_count = ffi.new("char **"), ffi.new("char **"), ffi.new("int *")
    info = {}
    for i in range(count[0]):
        check(lib.mps2p_stat_info(i, key, description, is_count))
        info[ffi.string(key[0]).decode()] = (ffi.string(description[0]).decode(),
                                             bool(is_count[0]))
    return info


_STATS = stat_info()
# The statistics' keys, and those that count something (returned as int).
STAT_KEYS = tuple(_STATS)
COUNT_STATS = frozenset(key for key, (_, is_count) in _STATS.items() if is_count)


class State(Owned):
    """A solver state saved in memory by Solver.save_state() (wraps
    mps2p_state); freed when collected or closed."""

    _what = "state"

    def __init__(self, handle):
        self._own(handle, lib.mps2p_state_destroy)


def _never(_solver):
    return False


class Solver(Owned):
    """Wraps mps2p_solver. Solver(scene) copies the scene: the scene may be
    changed or closed afterwards. Free it with close(), a `with` block, or
    garbage collection. Solver.load_checkpoint(path) restores one from a file.

    While advance_to runs, its progress callback may read the solver (time,
    fields, statistics) but not change it: step, advance_to, close and the
    other calls that change the state raise StateError there."""

    _what = "solver"
    _busy = False

    def __init__(self, scene):
        from .scene import Scene
        if not isinstance(scene, Scene):
            raise TypeError("Solver(scene) needs an mps2p.Scene, got %s" % type(scene).__name__)
        handle = ffi.new("mps2p_solver **")
        check(lib.mps2p_solver_create(scene.handle, handle))
        self._own(handle[0], lib.mps2p_solver_destroy)

    @classmethod
    def _adopt(cls, handle):
        solver = cls.__new__(cls)
        solver._own(handle, lib.mps2p_solver_destroy)
        return solver

    def _changing(self, what):
        """The handle, for a call that changes the solver; refused while a
        progress callback of advance_to runs (the C loop holds the state)."""
        if self._busy:
            raise errors.StateError(
                "solver is running advance_to: %s from its progress callback is refused "
                "(return a true value from the callback to stop the run)" % what,
                lib.MPS2P_ERR_STATE, "MPS2P_ERR_STATE")
        return self.handle

    def close(self):
        """Frees the C solver now; later use raises ValueError. Refused
        (StateError) from inside a progress callback of advance_to."""
        if self._handle is not None:
            self._changing("close()")
        super().close()

    # -- running ------------------------------------------------------------
    def step(self):
        """One time step. Raises DivergedError or SolveError (the solver keeps
        the state from before the step)."""
        check(lib.mps2p_solver_step(self._changing("step()")))

    def advance_to(self, end_time, progress=None):
        """Steps until `end_time` (s) exactly (the C library divides the
        remaining time evenly into steps no longer than the chosen dt).

        progress: None; a callable `progress(solver)` called after each step,
        whose true return value stops the run; or True for a progress bar on
        stderr (tqdm when installed, `pip install tqdm`; else a plain line).
        Returns True when end_time was reached, False when progress stopped
        it. An exception raised by progress stops the run and is re-raised
        here; DivergedError and SolveError as in step()."""
        end = real(end_time, "end time")
        handle = self._changing("advance_to()")
        if progress is None or progress is False:
            if threading.current_thread() is not threading.main_thread():
                # signals reach the main thread only; a callback here would
                # only take the interpreter lock back after every step
                return check(lib.mps2p_solver_advance_to(handle, end, ffi.NULL, ffi.NULL)) \
                    == lib.MPS2P_OK
            # a callback all the same: Python runs its signal handlers only
            # while Python code runs, so Ctrl-C (KeyboardInterrupt) stops the
            # run at the next step instead of after it
            return self._advance_with(end, _never)
        if progress is True:
            from .progress import bar_for
            with bar_for(self, end) as bar:
                return self._advance_with(end, bar.update)
        if not callable(progress):
            raise TypeError("progress must be a callable, True or None, got %r" % (progress,))
        return self._advance_with(end, progress)

    def _advance_with(self, end, progress):
        failure = []

        def stop_on(_type, value, _traceback):
            # an exception the callback did not catch itself: a signal's
            # (KeyboardInterrupt) can arrive before its try block is entered
            failure.append(value)
            return 1

        @ffi.callback("int(const mps2p_solver *, void *)", onerror=stop_on)
        def callback(_solver, _user):
            try:
                return 1 if progress(self) else 0
            except BaseException as e:  # noqa: B902 - re-raised below
                failure.append(e)
                return 1

        try:
            self._busy = True  # inside: an interrupt here must not leave it set
            status = lib.mps2p_solver_advance_to(self.handle, end, callback, ffi.NULL)
        finally:
            self._busy = False
        if failure:
            raise failure[0]
        return check(status) == lib.MPS2P_OK

    # -- state ----------------------------------------------------------------
    @property
    def particle_count(self):
        """Particles in the solver (fluid, wall and dummy), int."""
        count = ffi.new("size_t *")
        check(lib.mps2p_solver_particle_count(self.handle, count))
        return int(count[0])

    @property
    def time(self):
        """Simulated time reached (s)."""
        value = ffi.new("double *")
        check(lib.mps2p_solver_get_time(self.handle, value))
        return value[0]

    @property
    def step_count(self):
        """Steps taken since the start (int; a restored checkpoint keeps its count)."""
        value = ffi.new("uint64_t *")
        check(lib.mps2p_solver_get_step_count(self.handle, value))
        return int(value[0])

    @property
    def last_dt(self):
        """Length of the last step (s); 0 before the first."""
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
        """(n, 2) float64 positions (m), a copy."""
        return self._field(lib.mps2p_solver_get_positions, np.float64, 2)

    def velocities(self):
        """(n, 2) float64 velocities (m/s), a copy."""
        return self._field(lib.mps2p_solver_get_velocities, np.float64, 2)

    def pressure(self):
        """(n,) float64 pressure (Pa), a copy."""
        return self._field(lib.mps2p_solver_get_pressure, np.float64, 1)

    def number_density(self):
        """(n,) float64 particle number density of the last step, a copy."""
        return self._field(lib.mps2p_solver_get_number_density, np.float64, 1)

    def kinds(self):
        """(n,) int32 of KIND_FLUID, KIND_WALL, KIND_DUMMY and KIND_OUT (fluid
        that left the domain, out of the run: kinds change from KIND_FLUID to
        KIND_OUT during a run), a copy."""
        return self._field(lib.mps2p_solver_get_kinds, np.intc, 1)

    def fluid_ids(self):
        """(n,) int32, the fluid id of each particle (KIND_OUT ones keep
        theirs), -1 for walls; a copy."""
        return self._field(lib.mps2p_solver_get_fluid_ids, np.intc, 1)

    def stat(self, key):
        """The statistic `key` (STAT_KEYS; meanings and units: stat_info()):
        an int for counts (COUNT_STATS), else a float.
        UnknownKeyError for an unknown key."""
        value = ffi.new("double *")
        check(lib.mps2p_solver_get_stat(self.handle, encode(key, "statistic name"), value))
        return int(value[0]) if key in COUNT_STATS else value[0]

    def stats(self):
        """{name: value} of every statistic, as stat() gives them."""
        return {key: self.stat(key) for key in STAT_KEYS}

    # -- effects and costs -------------------------------------------------
    def effects(self):
        """{name: (active, reason)} of every physical effect, in the library's
        order; reason starts with "inferred: ", "requested: on; " or
        "requested: off; ", then what the scene has that decides it."""
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
        """Sets every stage's seconds and calls back to 0."""
        check(lib.mps2p_solver_reset_stage_timings(self._changing("reset_stage_timings()")))

    # -- coupling: bodies, forces, host inputs, windows ----------------------
    def bodies(self):
        """[(name, particles)] by body id (0 is "walls")."""
        count = ffi.new("int *")
        check(lib.mps2p_solver_body_count(self.handle, count))
        name, particles = ffi.new("char **"), ffi.new("size_t *")
        result = []
        for body in range(count[0]):
            check(lib.mps2p_solver_get_body(self.handle, body, name, particles))
            result.append((ffi.string(name[0]).decode(), int(particles[0])))
        return result

    def body_ids(self):
        """(n,) int32: the body of each particle, -1 for fluid; a copy."""
        return self._field(lib.mps2p_solver_get_body_ids, np.intc, 1)

    def body_force(self, body_id, fluid_id=-1, about=(0.0, 0.0)):
        """(force (2,) N/m, moment N m/m about `about`) that the fluid's pressure
        exerts on the body; fluid_id >= 0 gives that fluid's part."""
        force, moment = ffi.new("double[2]"), ffi.new("double *")
        point = ffi.new("double[2]", _pair(about, "about"))
        check(lib.mps2p_solver_body_force(self.handle, index(body_id, "body_id"),
                                          index(fluid_id, "fluid_id"), force, moment, point))
        return np.array([force[0], force[1]]), moment[0]

    def wall_loads(self, body_id, fluid_id=-1):
        """(n, 2) float64: p_i l0 n_i (N/m) on each wall particle of the body,
        the terms of body_force's force (their sum over the body, in index
        order, is it exactly); 0 for every other particle."""
        body_id, fluid_id = index(body_id, "body_id"), index(fluid_id, "fluid_id")
        return self._field(lambda handle, out, size: lib.mps2p_solver_get_wall_loads(
            handle, body_id, fluid_id, out, size), np.float64, 2)

    def set_body_motion(self, body_id, velocity=(0.0, 0.0), angular_velocity=0.0,
                        about=(0.0, 0.0)):
        """Rigid motion of the body from the next step on (m/s, rad/s about `about`)."""
        v = ffi.new("double[2]", _pair(velocity, "velocity"))
        point = ffi.new("double[2]", _pair(about, "about"))
        check(lib.mps2p_solver_set_body_motion(self._changing("set_body_motion()"),
                                               index(body_id, "body_id"), v,
                                               real(angular_velocity, "angular velocity"),
                                               point))

    def set_body_positions(self, body_id, positions):
        """Positions (m, 2) in metres that the body's m particles reach at the
        end of the next step; None clears them."""
        handle = self._changing("set_body_positions()")
        body_id = index(body_id, "body_id")
        if positions is None:
            check(lib.mps2p_solver_set_body_positions(handle, body_id, ffi.NULL, 0))
            return
        positions = real_array(positions, (-1, 2), "positions")
        check(lib.mps2p_solver_set_body_positions(handle, body_id,
                                                  ffi.from_buffer("double[]", positions),
                                                  positions.size))

    @property
    def gravity(self):
        """(gx, gy) in m/s^2; assign a pair to change it from the next step on."""
        g = ffi.new("double[2]")
        check(lib.mps2p_solver_get_gravity(self.handle, g))
        return (g[0], g[1])

    @gravity.setter
    def gravity(self, value):
        gx, gy = _pair(value, "gravity")
        check(lib.mps2p_solver_set_gravity(self._changing("setting gravity"), gx, gy))

    def set_body_forces(self, accelerations):
        """Per-particle accelerations (n, 2) m/s^2, n = particle_count, added to
        the fluid every step; None clears them."""
        handle = self._changing("set_body_forces()")
        if accelerations is None:
            check(lib.mps2p_solver_set_body_forces(handle, ffi.NULL, 0))
            return
        accelerations = real_array(accelerations, (self.particle_count, 2), "accelerations")
        check(lib.mps2p_solver_set_body_forces(handle,
                                               ffi.from_buffer("double[]", accelerations),
                                               accelerations.size))

    def save_state(self):
        """Everything the next step depends on, in memory (for implicit coupling
        iterations): restore_state(state) returns the solver to it bitwise."""
        handle = ffi.new("mps2p_state **")
        check(lib.mps2p_solver_save_state(self.handle, handle))
        return State(handle[0])

    def restore_state(self, state):
        """Puts the solver back to a State from save_state() of this solver
        (or one built from the same scene): positions, time, step count and
        everything else the next step reads; clears a divergence since."""
        if not isinstance(state, State):
            raise TypeError("restore_state needs a State from save_state(), got %s"
                            % type(state).__name__)
        check(lib.mps2p_solver_restore_state(self._changing("restore_state()"), state.handle))

    def advance_window(self, end_time):
        """One coupling window to end_time exactly; returns the steps it took."""
        steps = ffi.new("uint64_t *")
        check(lib.mps2p_solver_advance_window(self._changing("advance_window()"),
                                              real(end_time, "end time"), steps))
        return int(steps[0])

    # -- probes and checkpoints -------------------------------------------
    def probe(self, points):
        """Pressure and velocity at arbitrary points, MPS-weighted from the
        particles around each: returns (pressure (m,), velocity (m, 2), inside (m,)
        bool). Points outside the fluid get 0 and inside False."""
        points = np.asarray(points)
        if points.ndim == 1:
            points = points.reshape(1, -1)
        points = real_array(points, (-1, 2), "points")
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
        fluid_id -1) lower than `below` (m), plus l0/2. InvalidArgumentError
        when none is that low (a scene file's front probe records nan)."""
        x = ffi.new("double *")
        check(lib.mps2p_solver_front(self.handle, index(fluid_id, "fluid_id"),
                                     real(below if below is not None else float("inf"), "below"), x))
        return x[0]

    def save_checkpoint(self, path):
        """Writes everything the next step depends on to `path` (str or
        os.PathLike; written aside and renamed, so a crash never leaves half a
        checkpoint)."""
        check(lib.mps2p_solver_save_checkpoint(self.handle, encode_path(path)))

    @staticmethod
    def load_checkpoint(path):
        """A solver restored from a checkpoint file; it continues bitwise as
        the saved one would."""
        handle = ffi.new("mps2p_solver **")
        check(lib.mps2p_solver_load_checkpoint(encode_path(path), handle))
        return Solver._adopt(handle[0])


def _pair(value, what):
    try:
        x, y = value
    except (TypeError, ValueError):
        raise TypeError("%s must be a pair (x, y), got %r" % (what, value)) from None
    return [real(x, what), real(y, what)]


__all__ = ["Solver", "State", "stat_info", "STAT_KEYS", "COUNT_STATS", "errors"]
