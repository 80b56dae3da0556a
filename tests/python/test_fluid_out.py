"""Fluid that leaves the domain goes out of the run (parameter out_limit, kind
KIND_OUT): seen from Python, in results files, by `mps2p run` and by the
stability checks."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import mps2p
from mps2p.tools import scenefile, stability

from conftest import PACKAGE_DIR

DROPLETS = [[0.255, 0.265], [0.265, 0.255], [0.155, 0.245]]


def spray(out_limit=0.05):
    """The C tests' spray: a water column in an open tank, three droplets
    thrown up through the top of a domain that ends at 0.35 m."""
    scene = mps2p.Scene(0.01)
    water = scene.add_fluid("water", 1000.0, 1e-6)
    scene.add_fluid_box(water, 0.0, 0.0, 0.1, 0.2)
    scene.add_tank(0.0, 0.0, 0.4, 0.3, open_top=True)
    scene.set_domain(-0.1, -0.1, 0.5, 0.35)
    scene.set_param("out_limit", out_limit)
    first = scene.particle_count
    scene.add_particles(DROPLETS, [mps2p.KIND_FLUID] * 3, [water] * 3, [[0.0, 2.0]] * 3)
    return scene, list(range(first, first + 3))


def test_droplets_show_kind_out_and_the_count(tmp_path):
    assert mps2p.KIND_OUT == 3
    scene, droplets = spray()
    with scene, mps2p.Solver(scene) as solver:
        path = str(tmp_path / "spray.h5")
        with mps2p.Results(path, solver) as results:
            solver.advance_to(0.08)
            results.write_snapshot(solver)
        kinds = solver.kinds()
        assert solver.stat("fluid_out") == 3
        assert np.flatnonzero(kinds == mps2p.KIND_OUT).tolist() == droplets
        assert (solver.fluid_ids()[droplets] == 0).all()  # still water
        assert (solver.velocities()[droplets] == 0).all() and (solver.pressure()[droplets] == 0).all()
        frozen = solver.positions()[droplets]
        assert (frozen[:, 1] > 0.35).all()
        solver.advance_to(0.1)
        assert np.array_equal(solver.positions()[droplets], frozen)
    with mps2p.open_results(path) as f:
        last = list(f.snapshots())[-1]
        assert np.flatnonzero(last["kind"] == 3).tolist() == droplets


def test_out_limit_zero_diverges_and_scenes_refuse_kind_out():
    scene, droplets = spray(out_limit=0.0)
    with scene, mps2p.Solver(scene) as solver:
        with pytest.raises(mps2p.DivergedError, match="left the domain"):
            solver.advance_to(0.1)
        assert solver.stat("fluid_out") == 0 and (solver.kinds() != mps2p.KIND_OUT).all()
        assert solver.stat("diverged_particle") == droplets[0]
    with mps2p.Scene(0.01) as scene:
        scene.add_fluid("water", 1000.0, 0.0)
        with pytest.raises(mps2p.InvalidArgumentError, match="MPS2P_KIND_OUT"):
            scene.add_particles([[0.0, 0.0]], [mps2p.KIND_OUT], [0])
        with pytest.raises(mps2p.InvalidArgumentError, match="MPS2P_KIND_OUT"):
            scene.add_body_particles("lid", [[0.0, 0.0]], [mps2p.KIND_OUT])


def scene_file(folder, air=False, extra=""):
    """A scene file: a small open tank of water (with air above it with
    air=True, the gas's damping layer off) and, from `extra`, more."""
    text = """[run]
name = "out"
l0 = 0.02
end_time = 0.45
snapshot_every = 0.15

[parameters]
out_limit = 0.05  # 3 of the 61 (1 %% of them would be none)

[effects]
gas_buffer = "off"

[[fluid]]
name = "water"
density = 1000.0
viscosity = 1e-6
%s
[[fluid_box]]
fluid = "water"
box = [0.0, 0.0, 0.2, 0.12]
%s
[[tank]]
box = [0.0, 0.0, 0.2, 0.3]
open_top = true
%s""" % ("" if not air else """
[[fluid]]
name = "air"
density = 1.2
viscosity = 1.5e-5
""", "" if not air else """
[[fluid_box]]
fluid = "air"
box = [0.0, 0.12, 0.2, 0.26]
""", extra)
    path = os.path.join(folder, "out_%s.toml" % ("air" if air else "water"))
    with open(path, "w") as f:
        f.write(text)
    return path


def falling_scene(folder):
    """A drop of water beside the tank, outside it, falling through the
    bottom of the default domain (the particles' box widened by its size) in
    about 0.36 s."""
    np.savez(os.path.join(folder, "drop.npz"), positions=[[0.35, 0.17]], kinds=[0],
             fluid_ids=[0])
    return scene_file(folder, extra='\n[[particles]]\nfile = "drop.npz"\n')


def test_run_says_how_many_left(tmp_path):
    path = falling_scene(str(tmp_path))
    env = dict(os.environ)
    env["PYTHONPATH"] = PACKAGE_DIR + os.pathsep + env.get("PYTHONPATH", "")
    result = subprocess.run([sys.executable, "-m", "mps2p", "run", path, "--out",
                             str(tmp_path / "out"), "--no-pictures", "--quiet"],
                            capture_output=True, text=True, env=env)
    assert result.returncode == 0, result.stderr
    assert "1 fluid particle left the domain and is out of the run" in result.stdout
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["status"] == "ok" and summary["fluid_out"] == 1
    assert summary["particles"]["out"] == 1 and summary["particles"]["water"] == 60


def test_stability_counts_particles_out(tmp_path):
    """The drop leaves no tank (it was in none) and falls freely: every check
    passes, and the report counts it out."""
    report = stability.check_run(falling_scene(str(tmp_path)))
    assert report["status"] == "ok", report["violations"]
    assert report["fluid_out"] == 1 and report["series"][-1]["fluid_out"] == 1
    assert report["particles"] == {"water": 61}


def test_stability_takes_gas_out_of_the_run_as_gone(tmp_path):
    """An air particle thrown up from the top of the gas out of a domain that
    ends between the walls' top layer and the tank's top (where the position
    check alone would not see it outside the tank) has left the tank."""
    sf = scenefile.load(scene_file(str(tmp_path), air=True))
    with sf.build() as scene:
        scene.add_particles([[0.11, 0.27]], [mps2p.KIND_FLUID], [sf.fluids.index("air")],
                            [[0.0, 3.0]])
        scene.set_domain(-0.2, -0.2, 0.4, 0.291)
        solver = mps2p.Solver(scene)
    with solver:
        report = stability._check(solver, sf, 0.03, 0.01, None)
    assert report["fluid_out"] == 1, report
    assert "out of the run" in report["violations"].get("inside", ""), report["violations"]


def test_tools_tell_fluid_out_of_the_run_from_walls(tmp_path):
    """Pictures draw walls and dummies as walls, not fluid out of the run;
    the ladder counts fluid out of the run as outside the tank wherever it
    stopped."""
    from mps2p.tools import ladder, pictures
    kinds = np.array([mps2p.KIND_FLUID, mps2p.KIND_WALL, mps2p.KIND_DUMMY, mps2p.KIND_OUT])
    assert pictures._solid(kinds).tolist() == [False, True, True, False]
    sf = scenefile.load(scene_file(str(tmp_path)))
    inside = np.array([[0.1, 0.1], [0.1, 0.1]])  # both in the tank's box
    fluid = np.array([True, True])
    assert ladder.outside_tank(sf, inside, fluid) == 0
    assert ladder.outside_tank(sf, inside, fluid, np.array([False, True])) == 1


def test_two_phases_restart_bitwise_after_gas_left(tmp_path):
    """A gas particle out of the run stays light (its fluid's) in a solver
    loaded from a checkpoint and after a state restore: both continue bit
    for bit."""
    sf = scenefile.load(scene_file(str(tmp_path), air=True))
    with sf.build() as scene:
        scene.add_particles([[0.11, 0.27]], [mps2p.KIND_FLUID], [sf.fluids.index("air")],
                            [[0.0, 3.0]])
        scene.set_domain(-0.2, -0.2, 0.4, 0.291)
        solver = mps2p.Solver(scene)

    def run_on(s, steps):
        for _ in range(steps):
            s.step()
        return [s.positions(), s.velocities(), s.pressure(), s.kinds(),
                np.array([s.time, s.stat("fluid_out"), s.stat("gas_ppe_unknowns")])]

    with solver:
        start = solver.save_state()
        while solver.stat("fluid_out") == 0 and solver.step_count < 50:
            solver.step()
        assert solver.stat("fluid_out") == 1 and solver.stat("two_phase_active") == 1
        path = str(tmp_path / "gas_out.chk")
        solver.save_checkpoint(path)
        left = solver.save_state()
        left_at = solver.step_count
        expected = run_on(solver, 30)
        with mps2p.Solver.load_checkpoint(path) as loaded:
            got = run_on(loaded, 30)
            assert all(np.array_equal(a, b) for a, b in zip(expected, got))
            # the same light particles: the state of the solver that wrote the file fits
            loaded.restore_state(left)
            got = run_on(loaded, 30)
        assert all(np.array_equal(a, b) for a, b in zip(expected, got))
        solver.restore_state(start)
        assert solver.stat("fluid_out") == 0
        again = run_on(solver, left_at + 30)
        assert all(np.array_equal(a, b) for a, b in zip(expected, again))
