"""The Python binding: version, coverage of the header, Scene and Solver,
errors with the C messages, arrays as copies, callbacks, lifetimes."""
import gc
import math
import re

import numpy as np
import pytest

import mps2p
from mps2p._native import ffi, lib


def small_dam_break(**settings):
    scene = mps2p.Scene(0.02, **settings)
    water = scene.add_fluid("water", 1000.0, 1e-6)
    scene.add_fluid_box(water, 0.0, 0.0, 0.16, 0.3)
    scene.add_tank(0.0, 0.0, 0.6, 0.5, open_top=True)
    return scene


def test_version_matches_the_c_library_and_header():
    assert mps2p.__version__ == ffi.string(lib.mps2p_version_string()).decode()
    header = open(mps2p.header_path).read()
    declared = re.search(r'#define MPS2P_VERSION_STRING "([^"]+)"', header).group(1)
    assert mps2p.__version__ == declared


def test_every_header_function_is_exported_and_declared():
    header = open(mps2p.header_path).read()
    names = re.findall(r"MPS2P_API[^;(]*?\b(mps2p_\w+)\s*\(", header)
    assert len(names) > 30
    for name in names:
        assert getattr(lib, name) is not None, name  # resolves the symbol in the .so


def test_scene_and_solver_run_a_dam_break():
    with small_dam_break(pressure_solver="cg") as scene:
        assert scene.fluids == [("water", 1000.0, 1e-6)]
        assert scene.get_option("pressure_solver") == "cg"
        solver = mps2p.Solver(scene)
    n = solver.particle_count
    assert solver.advance_to(0.05) is True
    assert solver.time == pytest.approx(0.05, abs=1e-12)
    assert solver.step_count > 0 and 0 < solver.last_dt <= 0.05
    positions, velocities = solver.positions(), solver.velocities()
    assert positions.shape == (n, 2) and positions.dtype == np.float64
    assert velocities.shape == (n, 2)
    kinds, ids = solver.kinds(), solver.fluid_ids()
    assert kinds.shape == (n,) and ids.shape == (n,)
    fluid = kinds == mps2p.KIND_FLUID
    assert np.all(ids[fluid] == 0) and np.all(ids[~fluid] == -1)
    assert fluid.sum() == 8 * 15
    assert solver.pressure().max() > 0
    assert velocities[fluid, 1].min() < 0  # the column falls
    stats = solver.stats()
    assert set(stats) == set(mps2p.STAT_KEYS)
    assert stats["kinetic_energy"] > 0
    solver.close()


def test_returned_arrays_are_copies():
    with small_dam_break() as scene, mps2p.Solver(scene) as solver:
        first = solver.positions()
        kept = first.copy()
        first[:] = 0.0  # the solver's state is not touched
        assert np.array_equal(solver.positions(), kept)
        solver.step()
        assert np.array_equal(kept, kept.copy())
        assert not np.array_equal(solver.positions(), kept)  # new state, new array
        assert solver.positions() is not solver.positions()


def test_the_library_lists_its_parameters_options_and_statistics():
    count = ffi.new("size_t *")
    assert lib.mps2p_param_count(count) == lib.MPS2P_OK
    assert len(mps2p.param_info()) == count[0] > 30
    options = mps2p.option_info()
    # gamg is listed only by a build with PETSc (meson option petsc)
    assert options["pressure_solver"][:2] in [("cg", ("cholmod", "cg")),
                                              ("cg", ("cholmod", "cg", "gamg"))]
    assert options["scheme"][:2] == ("corrected", ("corrected", "koshizuka1996"))
    with mps2p.Scene(0.01) as scene:
        for key, (default, choices, description) in options.items():
            assert scene.get_option(key) == default and default in choices and description
            for choice in choices:
                scene.set_option(key, choice)
    stats = mps2p.stat_info()
    assert tuple(stats) == mps2p.STAT_KEYS and all(d for d, _ in stats.values())
    assert stats["ppe_unknowns"][1] and not stats["max_speed"][1]
    assert mps2p.COUNT_STATS == {k for k, (_, counts) in stats.items() if counts}


def test_gamg_agrees_with_cholmod_or_is_refused_without_petsc():
    if "gamg" not in mps2p.option_info()["pressure_solver"][1]:
        with mps2p.Scene(0.02) as scene:
            with pytest.raises(mps2p.InvalidArgumentError, match="PETSc"):
                scene.set_option("pressure_solver", "gamg")
        return
    pressure = {}
    for method in ("cholmod", "gamg"):
        with small_dam_break(pressure_solver=method) as scene, mps2p.Solver(scene) as solver:
            for _ in range(3):
                solver.step()
            pressure[method] = solver.pressure()
    largest = np.abs(pressure["cholmod"]).max()
    assert largest > 0
    assert np.abs(pressure["gamg"] - pressure["cholmod"]).max() <= 1e-6 * largest


def test_parameters_default_to_the_c_defaults():
    info = mps2p.param_info()
    assert info["re_density"][0] == 2.1 and info["beta"][0] == 0.97
    with mps2p.Scene(0.01) as scene:
        assert scene.params == {key: default for key, (default, _) in info.items()}
    with mps2p.Scene(0.01, cfl=0.1, re_laplacian=3.1) as scene:
        assert scene.get_param("cfl") == 0.1 and scene.get_param("re_laplacian") == 3.1


@pytest.mark.parametrize("call, error, words", [
    (lambda: mps2p.Scene(-0.01), mps2p.InvalidArgumentError, "got -0.01"),
    (lambda: mps2p.Scene(float("nan")), mps2p.InvalidArgumentError, "l0"),
    (lambda: mps2p.Scene(0.01, cfl=math.inf), mps2p.InvalidArgumentError, "cfl"),
    (lambda: mps2p.Scene(0.01, no_such=1.0), mps2p.UnknownKeyError, "no_such"),
    (lambda: mps2p.Scene(0.01, pressure_solver="lu"), mps2p.InvalidArgumentError, '"lu"'),
    (lambda: mps2p.Scene(0.01).add_fluid("water", -1.0, 1e-6), mps2p.InvalidArgumentError,
     "density"),
    (lambda: mps2p.Scene(0.01).add_fluid_box(3, 0, 0, 1, 1), mps2p.InvalidArgumentError, "3"),
    (lambda: mps2p.Solver(mps2p.Scene(0.01)), mps2p.Error, "fluid"),
])
def test_c_errors_become_exceptions_with_the_c_message(call, error, words):
    with pytest.raises(error) as caught:
        call()
    assert words in str(caught.value)
    assert caught.value.status < 0 and caught.value.status_name.startswith("MPS2P_ERR_")


def test_python_type_errors_before_c():
    with pytest.raises(TypeError):
        mps2p.Scene("0.01")
    with pytest.raises(TypeError):
        mps2p.Scene(True)
    with pytest.raises(ValueError):
        mps2p.Scene(0.01).add_particles(np.zeros((3, 3)), [0, 0, 0])


def test_unknown_statistic():
    with small_dam_break() as scene, mps2p.Solver(scene) as solver:
        with pytest.raises(mps2p.UnknownKeyError, match="nope"):
            solver.stat("nope")


def test_divergence_keeps_the_last_good_state_then_refuses():
    with small_dam_break(pressure_limit=1.0) as scene, mps2p.Solver(scene) as solver:
        with pytest.raises(mps2p.DivergedError) as caught:
            for _ in range(100):
                before = (solver.positions(), solver.time, solver.step_count)
                solver.step()
        assert "diverged" in str(caught.value) and "particle" in str(caught.value)
        assert np.array_equal(solver.positions(), before[0])
        assert (solver.time, solver.step_count) == before[1:]
        with pytest.raises(mps2p.StateError, match="diverged"):
            solver.step()


def test_progress_callback_can_stop_and_exceptions_come_through():
    with small_dam_break() as scene, mps2p.Solver(scene) as solver:
        assert solver.advance_to(1.0, progress=lambda s: s.step_count >= 3) is False
        assert solver.step_count == 3

        def broken(s):
            raise KeyError("from the callback")

        with pytest.raises(KeyError, match="from the callback"):
            solver.advance_to(1.0, progress=broken)
        assert solver.step_count == 4  # the step before the callback ran


class Interrupted(Exception):
    pass


@pytest.mark.parametrize("progress", [None, lambda s: False])
def test_a_signal_stops_advance_to_at_the_next_step(progress):
    """A signal handler's exception (as Ctrl-C's KeyboardInterrupt) comes out
    of advance_to at the next step, with or without a progress callback, and
    the solver goes on from there (before: without a callback only when the
    run ended; with one, lost when it arrived before the callback's try)."""
    import signal

    def interrupt(_signum, _frame):
        raise Interrupted()

    previous = signal.signal(signal.SIGALRM, interrupt)
    try:
        with small_dam_break() as scene, mps2p.Solver(scene) as solver:
            signal.setitimer(signal.ITIMER_REAL, 0.3)
            with pytest.raises(Interrupted):
                solver.advance_to(100.0, progress=progress)  # minutes of steps
            signal.setitimer(signal.ITIMER_REAL, 0.0)
            assert 0.0 < solver.time < 100.0
            steps = solver.step_count
            solver.step()
            assert solver.step_count == steps + 1
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)


def test_advance_to_in_another_thread_runs_without_a_callback():
    """Off the main thread (no signals reach it) advance_to calls into C
    without a Python callback, and gives the same run as on the main thread."""
    import threading
    results = {}
    with small_dam_break() as scene, mps2p.Solver(scene) as there, \
            mps2p.Solver(scene) as here:
        worker = threading.Thread(target=lambda: results.update(done=there.advance_to(0.02)))
        worker.start()
        worker.join()
        assert results["done"] is True
        assert here.advance_to(0.02) is True
        assert np.array_equal(there.positions(), here.positions())


def test_particles_from_arrays_match_a_box():
    l0 = 0.02
    x, y = np.meshgrid((np.arange(8) + 0.5) * l0, (np.arange(15) + 0.5) * l0)
    block = np.column_stack([x.ravel(), y.ravel()])
    with mps2p.Scene(l0) as scene:
        water = scene.add_fluid("water", 1000.0, 1e-6)
        scene.add_particles(block, np.zeros(len(block), dtype=int),
                            np.full(len(block), water), velocities=np.zeros_like(block))
        scene.add_tank(0.0, 0.0, 0.6, 0.5)
        with mps2p.Solver(scene) as from_arrays, small_dam_break() as box_scene, \
                mps2p.Solver(box_scene) as from_box:
            assert from_arrays.particle_count == from_box.particle_count
            from_arrays.advance_to(0.02)
            from_box.advance_to(0.02)
            a, b = from_arrays.positions(), from_box.positions()
            assert np.allclose(np.sort(a, axis=0), np.sort(b, axis=0), atol=1e-12)
    with mps2p.Scene(l0) as scene:
        with pytest.raises(TypeError, match="integers"):
            scene.add_particles(block, np.zeros(len(block)))
        with pytest.raises(ValueError, match="shape"):
            scene.add_particles(block, np.zeros(3, dtype=int))


def test_handles_are_freed_and_closed_handles_refuse():
    scene = small_dam_break()
    solver = mps2p.Solver(scene)
    scene.close()
    scene.close()  # twice is fine
    with pytest.raises(ValueError, match="closed"):
        scene.add_fluid("air", 1.2, 1.5e-5)
    solver.step()  # the solver copied the scene
    solver.close()
    with pytest.raises(ValueError, match="closed"):
        solver.step()
    for _ in range(50):  # garbage collection frees what was not closed
        mps2p.Solver(small_dam_break())
    gc.collect()
