"""Issue 20's binding checks: values C cannot hold are refused, never
wrapped or truncated; paths are paths; a solver is not closed or re-entered
from inside its own progress callback."""
import os

import numpy as np
import pytest

import mps2p


def dam_break(l0=0.02):
    scene = mps2p.Scene(l0)
    water = scene.add_fluid("water", 1000.0, 1e-6)
    scene.add_fluid_box(water, 0.0, 0.0, 0.16, 0.3)
    scene.add_tank(0.0, 0.0, 0.6, 0.5)
    return scene


# -- issue 20: conversions the binding used to make silently ------------------

def lattice(n=4, l0=0.02):
    x, y = np.meshgrid((np.arange(n) + 0.5) * l0, (np.arange(n) + 0.5) * l0)
    return np.column_stack([x.ravel(), y.ravel()])


@pytest.mark.parametrize("kinds, words", [
    (np.array([2 ** 32, 2 ** 32 + 1] * 8, dtype=np.int64), r"kinds\[0\] = 4294967296 is out of range"),
    (np.array([0] * 15 + [-2 ** 40], dtype=np.int64), r"kinds\[15\] = -1099511627776"),
])
def test_kinds_out_of_c_int_range_are_refused(kinds, words):
    with mps2p.Scene(0.02) as scene:
        scene.add_fluid("water", 1000.0, 1e-6)
        with pytest.raises(ValueError, match=words):
            scene.add_particles(lattice(), kinds, np.zeros(16, dtype=int))
        assert scene.particle_count == 0


def test_fluid_ids_out_of_c_int_range_are_refused():
    with mps2p.Scene(0.02) as scene:
        scene.add_fluid("water", 1000.0, 1e-6)
        with pytest.raises(ValueError, match=r"fluid_ids\[0\] = 4294967296"):
            scene.add_particles(lattice(), np.zeros(16, dtype=int),
                                np.full(16, 2 ** 32, dtype=np.int64))
        with pytest.raises(ValueError, match="fluid_id = 4294967296 is out of range"):
            scene.add_fluid_box(2 ** 32, 0, 0, 0.1, 0.1)


@pytest.mark.parametrize("fluid_id, error", [(1.9, TypeError), ("0", TypeError),
                                             (True, TypeError), (None, TypeError)])
def test_a_fluid_id_must_be_an_int(fluid_id, error):
    with mps2p.Scene(0.02) as scene:
        scene.add_fluid("water", 1000.0, 1e-6)
        with pytest.raises(error, match="fluid_id must be an int"):
            scene.add_fluid_box(fluid_id, 0, 0, 0.1, 0.1)
        assert scene.particle_count == 0
        scene.add_fluid_box(np.int64(0), 0, 0, 0.1, 0.1)  # numpy integers are integers
        assert scene.particle_count == 25


def test_checkpoint_paths_are_paths(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with dam_break() as scene, mps2p.Solver(scene) as solver:
        solver.save_checkpoint(b"x.ck")
        assert sorted(os.listdir(tmp_path)) == ["x.ck"]  # not "b'x.ck'"
        with mps2p.Solver.load_checkpoint(b"x.ck") as restored:
            assert restored.particle_count == solver.particle_count
        for bad in (None, 3, ["x.ck"]):
            with pytest.raises(TypeError, match="path must be a str or os.PathLike"):
                mps2p.Solver.load_checkpoint(bad)
            with pytest.raises(TypeError, match="path"):
                solver.save_checkpoint(bad)
        with pytest.raises(ValueError, match="empty"):
            solver.save_checkpoint("")
    assert not os.path.exists(tmp_path / "None")


def test_body_forces_must_have_the_particles_shape():
    with dam_break() as scene, mps2p.Solver(scene) as solver:
        n = solver.particle_count
        with pytest.raises(ValueError, match=r"accelerations must have shape \(%d, 2\)" % n):
            solver.set_body_forces(np.zeros((2, n)))  # the right count, the wrong shape
        with pytest.raises(ValueError, match="shape"):
            solver.set_body_forces(np.zeros(2 * n))
        with pytest.raises(TypeError, match="real numbers"):
            solver.set_body_forces(np.full((n, 2), "1"))
        solver.set_body_forces(np.zeros((n, 2)))
        solver.set_body_forces(None)


@pytest.mark.parametrize("scene", [None, "scene", 0.01])
def test_solver_needs_a_scene(scene):
    with pytest.raises(TypeError, match="Solver\\(scene\\) needs an mps2p.Scene"):
        mps2p.Solver(scene)


def test_close_from_the_progress_callback_is_refused():
    with dam_break() as scene, mps2p.Solver(scene) as solver:
        caught = []

        def close_it(s):
            try:
                s.close()
            except mps2p.StateError as e:
                caught.append(str(e))
            return s.step_count >= 2

        assert solver.advance_to(1.0, progress=close_it) is False
        assert caught and "close() from its progress callback is refused" in caught[0]
        solver.step()  # still a working solver
        with pytest.raises(mps2p.StateError, match="close"):
            solver.advance_to(1.0, progress=lambda s: s.close())
        assert solver.step_count == 4
    with pytest.raises(ValueError, match="closed"):  # closing after the run is fine
        solver.step()


def test_nested_runs_from_the_progress_callback_are_refused():
    with dam_break() as scene, mps2p.Solver(scene) as solver:
        for call in (lambda s: s.advance_to(0.5), lambda s: s.step(),
                     lambda s: s.advance_window(0.5), lambda s: s.restore_state(s.save_state()),
                     lambda s: setattr(s, "gravity", (0.0, -1.0))):
            with pytest.raises(mps2p.StateError, match="progress callback is refused"):
                solver.advance_to(1.0, progress=call)
        # reading is what a callback is for
        seen = []
        solver.advance_to(0.02, progress=lambda s: seen.append((s.time, s.positions().shape)))
        assert seen and seen[-1][0] == pytest.approx(0.02, abs=1e-12)


def test_a_setting_of_the_wrong_kind_says_which_kind_it_is():
    with pytest.raises(mps2p.UnknownKeyError, match="cfl is a numeric parameter: give it a "
                       "number, not the string '0.3'"):
        mps2p.Scene(0.01, cfl="0.3")
    with pytest.raises(mps2p.UnknownKeyError, match="pressure_solver is an option: .*cg"):
        mps2p.Scene(0.01, pressure_solver=1)
    with pytest.raises(mps2p.UnknownKeyError, match='did you mean "cfl"'):
        mps2p.Scene(0.01, cfll=0.3)
