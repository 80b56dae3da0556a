"""Results files, checkpoints and probes through the binding: the same C code
C users call, checked from Python with h5py."""
import h5py
import numpy as np
import pytest

import mps2p
from mps2p.results import Results


def dam_break(**settings):
    scene = mps2p.Scene(0.02, **settings)
    water = scene.add_fluid("water", 1000.0, 1e-6)
    scene.add_fluid_box(water, 0.0, 0.0, 0.16, 0.3)
    scene.add_tank(0.0, 0.0, 0.6, 0.5)
    with scene:
        return mps2p.Solver(scene)


def test_results_file_holds_what_the_solver_returned(tmp_path):
    path = tmp_path / "run.h5"
    with dam_break() as solver, Results(path, solver, scene_text="# a scene") as results:
        expected = []
        for t in (0.01, 0.02):
            solver.advance_to(t)
            results.write_snapshot(solver)
            results.append_series("kinetic_energy", solver.time, solver.stat("kinetic_energy"))
            expected.append((solver.time, solver.positions(), solver.pressure(), solver.kinds()))
    with h5py.File(path, "r") as f:
        assert f.attrs["library_version"].decode() == mps2p.__version__
        assert f["scene_text"][()].decode() == "# a scene"
        assert f["parameters"].attrs["re_density"] == 2.1
        assert sorted(f["snapshots"]) == ["000000", "000001"]
        for name, (t, xy, p, kind) in zip(sorted(f["snapshots"]), expected):
            group = f["snapshots"][name]
            assert group.attrs["time"] == t
            assert np.array_equal(group["position"][()], xy)
            assert np.array_equal(group["pressure"][()], p)
            assert np.array_equal(group["kind"][()], kind)
        series = f["series"]["kinetic_energy"][()]
        assert series.shape == (2, 2) and series[1, 0] == expected[1][0]
    assert "snapshot_000001" in (tmp_path / "run.xdmf").read_text()


def test_results_file_errors_name_the_path(tmp_path):
    with dam_break() as solver:
        missing = tmp_path / "no" / "such" / "dir" / "run.h5"
        with pytest.raises(mps2p.FileError, match=str(missing)):
            Results(missing, solver)
        with Results(tmp_path / "ok.h5", solver) as results:
            with pytest.raises(mps2p.InvalidArgumentError, match="name"):
                results.append_series("bad name!", 0.0, 1.0)


def test_damaged_results_files_are_file_errors(tmp_path):
    # an audit (session 24): a missing group was a KeyError, a fluid name that
    # is not UTF-8 (the C library takes bytes) a UnicodeDecodeError, and
    # Results(path, None) an AttributeError
    with pytest.raises(TypeError, match="mps2p.Solver"):
        Results(tmp_path / "none.h5", None)
    path = tmp_path / "run.h5"
    with dam_break() as solver, Results(path, solver) as results:
        results.write_snapshot(solver)
        results.write_snapshot(solver)
    with h5py.File(path, "a") as f:
        del f["snapshots"]["000001"]["pressure"]
        f["fluids"]["name"][0] = b"w\xffter"
    with mps2p.open_results(path) as read:
        assert read.fluids[0][0] == "w\udcffter"  # kept, as Python keeps such file names
        assert read.snapshot(0)["pressure"].shape == (read.metadata["particle_count"],)
        with pytest.raises(mps2p.FileError, match="damaged: snapshot 000001: pressure missing"):
            read.snapshot(1)
    with h5py.File(path, "a") as f:
        del f["snapshots"]
    with pytest.raises(mps2p.FileError, match="damaged: snapshots missing"):
        mps2p.open_results(path)


def test_checkpoint_restart_is_bitwise(tmp_path):
    for method in ("cholmod", "cg"):
        with dam_break(pressure_solver=method) as solver:
            for _ in range(20):
                solver.step()
            solver.save_checkpoint(tmp_path / "c.h5")
            for _ in range(20):
                solver.step()
            with mps2p.Solver.load_checkpoint(tmp_path / "c.h5") as restored:
                assert restored.step_count == 20
                for _ in range(20):
                    restored.step()
                assert restored.time == solver.time and restored.step_count == 40
                for field in ("positions", "velocities", "pressure"):
                    a, b = getattr(solver, field)(), getattr(restored, field)()
                    assert a.tobytes() == b.tobytes(), (method, field)
    with pytest.raises(mps2p.FileError, match="nothing.h5"):
        mps2p.Solver.load_checkpoint(tmp_path / "nothing.h5")


def test_probes_and_front():
    with dam_break() as solver:
        assert solver.front(0, below=0.04) == pytest.approx(0.16, abs=1e-12)
        solver.advance_to(0.05)
        pressure, velocity, inside = solver.probe([[0.05, 0.03], [0.4, 0.4]])
        assert inside.tolist() == [True, False]
        assert pressure[0] > 0 and pressure[1] == 0 and np.all(velocity[1] == 0)
        assert velocity.shape == (2, 2)
        with pytest.raises(ValueError, match="shape"):
            solver.probe(np.zeros((2, 3)))
