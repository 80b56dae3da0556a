"""The public Python API (issue 19): documented, no private arguments,
counts as int, the results reader, the progress bar, box snapping."""
import inspect
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import mps2p
from mps2p import results as results_module

from conftest import PACKAGE_DIR

PUBLIC_CLASSES = [mps2p.Scene, mps2p.Solver, mps2p.State, mps2p.Results, mps2p.ResultsFile]
PUBLIC_FUNCTIONS = [mps2p.param_info, mps2p.open_results, mps2p.example_names,
                    mps2p.example_path]


def public_members(cls):
    for name, member in inspect.getmembers(cls):
        if name.startswith("_"):
            continue
        if inspect.isfunction(member) or isinstance(member, (property, staticmethod,
                                                             classmethod)):
            yield name, member
        elif inspect.ismethod(member):
            yield name, member


def test_every_public_method_has_a_docstring():
    missing = []
    for cls in PUBLIC_CLASSES:
        if not (cls.__doc__ or "").strip():
            missing.append(cls.__name__)
        for name, member in public_members(cls):
            doc = inspect.getdoc(getattr(cls, name)) if not isinstance(member, property) \
                else member.__doc__
            if not (doc or "").strip():
                missing.append("%s.%s" % (cls.__name__, name))
    for function in PUBLIC_FUNCTIONS:
        if not (function.__doc__ or "").strip():
            missing.append(function.__name__)
    assert not missing, "no docstring: %s" % ", ".join(missing)
    # the ones issue 19 named, explicitly
    for name in ("add_fluid_box", "add_tank", "add_wall_box", "set_domain", "set_param",
                 "get_param", "set_option", "get_option"):
        assert inspect.getdoc(getattr(mps2p.Scene, name))
    for name in ("stat", "restore_state"):
        assert inspect.getdoc(getattr(mps2p.Solver, name))
    for name in ("time", "step_count", "last_dt"):
        assert getattr(mps2p.Solver, name).__doc__


def test_no_private_arguments_in_signatures():
    for cls in PUBLIC_CLASSES:
        signatures = [("%s()" % cls.__name__, inspect.signature(cls))]
        for name, _ in public_members(cls):
            member = getattr(cls, name)
            if callable(member):
                signatures.append(("%s.%s" % (cls.__name__, name), inspect.signature(member)))
        for label, signature in signatures:
            private = [p for p in signature.parameters if p.startswith("_")]
            assert not private, "%s has private arguments %s" % (label, private)
    assert list(inspect.signature(mps2p.Solver).parameters) == ["scene"]


def test_results_module_comes_with_the_package():
    code = "import mps2p; print(mps2p.results.Results.__name__, mps2p.open_results.__name__)"
    env = dict(os.environ, PYTHONPATH=PACKAGE_DIR + os.pathsep + os.environ.get("PYTHONPATH",
                                                                                  ""))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["Results", "open_results"]


def dam_break(l0=0.02):
    scene = mps2p.Scene(l0)
    water = scene.add_fluid("water", 1000.0, 1e-6)
    scene.add_fluid_box(water, 0.0, 0.0, 0.16, 0.3)
    scene.add_tank(0.0, 0.0, 0.6, 0.5)
    return scene


def test_counts_are_ints_and_measures_floats():
    with dam_break() as scene, mps2p.Solver(scene) as solver:
        solver.advance_to(0.02)
        stats = solver.stats()
        for key in mps2p.COUNT_STATS:
            assert type(stats[key]) is int, key
        assert stats["ppe_unknowns"] > 0 and stats["neighbour_builds"] >= 1
        assert stats["diverged_particle"] == -1
        for key in set(mps2p.STAT_KEYS) - mps2p.COUNT_STATS:
            assert type(stats[key]) is float, key
        assert type(solver.particle_count) is int and type(scene.particle_count) is int
        assert all(type(count) is int for _, count in solver.bodies())


def test_open_results_gives_numpy_arrays_and_str_metadata(tmp_path):
    path = tmp_path / "run.h5"
    with dam_break() as scene, mps2p.Solver(scene) as solver, \
            mps2p.Results(path, solver, scene_text="# the scene") as out:
        out.write_snapshot(solver)
        expected = []
        for t in (0.01, 0.02):
            solver.advance_to(t)
            out.write_snapshot(solver)
            out.append_series("kinetic_energy", solver.time, solver.stat("kinetic_energy"))
            expected.append((solver.time, solver.step_count, solver.positions(),
                             solver.kinds()))
    with mps2p.open_results(path) as r:
        assert r.metadata["format"] == "libmps2p results"
        assert r.metadata["library_version"] == mps2p.__version__
        assert type(r.metadata["particle_count"]) is int
        assert r.metadata["l0"] == 0.02
        assert r.parameters["pressure_solver"] == "cg" and r.parameters["beta"] == 0.97
        assert r.fluids == [("water", 1000.0, 1e-6)]
        assert r.scene_text == "# the scene"
        assert len(r) == 3 and r.times.tolist() == [0.0] + [e[0] for e in expected]
        assert r.steps.dtype == np.int64 and r.steps[-1] == expected[-1][1]
        last = r.snapshot(-1)
        assert isinstance(last["position"], np.ndarray) and last["kind"].dtype == np.int32
        assert np.array_equal(last["position"], expected[-1][2])
        assert np.array_equal(last["kind"], expected[-1][3])
        assert type(last["step"]) is int and last["time"] == expected[-1][0]
        assert [s["time"] for s in r.snapshots()] == r.times.tolist()
        assert r.series["kinetic_energy"].shape == (2, 2)
    with pytest.raises(TypeError, match="path"):
        mps2p.open_results(None)


def test_open_results_says_what_is_wrong_with_the_file(tmp_path):
    with pytest.raises(mps2p.FileError, match='"%s": no such file' % (tmp_path / "none.h5")):
        mps2p.open_results(tmp_path / "none.h5")
    with pytest.raises(mps2p.FileError, match="is a directory"):
        mps2p.open_results(tmp_path)
    xdmf = tmp_path / "results.xdmf"
    xdmf.write_text("<Xdmf/>")
    with pytest.raises(mps2p.FileError, match="not an HDF5 file.*open results.h5"):
        mps2p.open_results(xdmf)
    with pytest.raises(FileNotFoundError):  # as h5py's was
        mps2p.open_results(tmp_path / "none.h5")


def test_open_results_refuses_a_checkpoint(tmp_path):
    with dam_break() as scene, mps2p.Solver(scene) as solver:
        solver.save_checkpoint(tmp_path / "c.chk")
    with pytest.raises(ValueError, match="not a libmps2p results file"):
        mps2p.open_results(tmp_path / "c.chk")
    # a file error, as every other file open_results refuses
    with pytest.raises(mps2p.FileError, match="not a libmps2p results file"):
        mps2p.open_results(tmp_path / "c.chk")
    assert results_module.SNAPSHOT_FIELDS[0] == "position"


def test_progress_true_draws_a_tqdm_bar(capfd):
    import tqdm  # noqa: F401 - installed by scripts/install-deps.sh; the bar is tqdm's
    with dam_break() as scene, mps2p.Solver(scene) as solver:
        assert solver.advance_to(0.02, progress=True) is True
        assert solver.time == pytest.approx(0.02, abs=1e-12)
    err = capfd.readouterr().err
    assert "100%" in err and "0.02/0.02 s" in err and "steps" in err


def test_progress_must_be_callable_or_true():
    with dam_break() as scene, mps2p.Solver(scene) as solver:
        with pytest.raises(TypeError, match="progress"):
            solver.advance_to(0.01, progress="yes")


def test_a_box_that_is_not_whole_l0_warns_and_says_what_it_holds():
    with mps2p.Scene(0.02) as scene:
        water = scene.add_fluid("water", 1000.0, 1e-6)
        with pytest.warns(mps2p.SnapWarning, match=r"width 0.15 m is 7.5 l0 .*to 7 l0 = 0.14 m"):
            scene.add_fluid_box(water, 0.0, 0.0, 0.15, 0.3)
        assert scene.particle_count == 7 * 15  # the C library's rounding, as the warning says
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # whole numbers of l0: no warning
            scene.add_fluid_box(water, 0.2, 0.0, 0.3, 0.3)
            with mps2p.Scene(0.01) as fine:
                fine.add_fluid_box(fine.add_fluid("w", 1000.0, 1e-6), 0.0, 0.0, 0.15, 0.3)
        with pytest.warns(mps2p.SnapWarning, match="tank"):
            scene.add_tank(0.0, 0.0, 0.61, 0.5)
    assert "rounded down" in mps2p.Scene.__doc__
