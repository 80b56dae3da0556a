"""Scene files: the shipped scenes load and run; wrong files are refused
with the file, the key and the reason."""
import glob
import json
import os
import textwrap
import warnings
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import mps2p
from mps2p.tools import scenefile
from mps2p.tools.run import run

from conftest import SCENES

GOOD = """
[run]
l0 = 0.02
end_time = 0.02
[[fluid]]
name = "water"
density = 1000.0
viscosity = 1e-6
[[fluid_box]]
fluid = "water"
box = [0.0, 0.0, 0.16, 0.3]
[[tank]]
box = [0.0, 0.0, 0.6, 0.5]
"""


def write(tmp_path, text, name="scene.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return str(path)


def test_a_good_scene_builds(tmp_path):
    loaded = scenefile.load(write(tmp_path, GOOD))
    with loaded.build() as scene:
        assert scene.particle_count > 8 * 15
        assert scene.fluids == [("water", 1000.0, 1e-6)]


@pytest.mark.parametrize("change, key, reason", [
    (("[run]", "[run]\nspeed = 3"), "run.speed", "unknown key"),
    (("[[tank]]", "[[tanks]]"), "tanks", "unknown table"),
    (("l0 = 0.02", "l0 = \"small\""), "run.l0", "finite number"),
    (("l0 = 0.02", "l0 = -0.02"), "run.l0", "> 0"),
    (("l0 = 0.02\n", ""), "run.l0", "missing"),
    (("box = [0.0, 0.0, 0.16, 0.3]", "box = [0.16, 0.0, 0.0, 0.3]"), "fluid_box[0].box",
     "x1 > x0"),
    (("box = [0.0, 0.0, 0.16, 0.3]", "box = [0.0, 0.0, 0.16]"), "fluid_box[0].box",
     "4 numbers"),
    (("fluid = \"water\"", "fluid = \"oil\""), "fluid_box[0].fluid", "no fluid named 'oil'"),
    (("density = 1000.0", "density = -5.0"), "fluid[0]", "density"),
    (("[[tank]]", "[parameters]\ncfl = 5.0\n[[tank]]"), "parameters.cfl", "cfl"),
    (("end_time = 0.02", "end_tme = 0.02"), "run.end_tme", "unknown key, did you mean end_time?"),
    (("[[tank]]", "[[tnk]]"), "tnk", "unknown table, did you mean tank?"),
    (("[[tank]]", "[parameters]\nwarp = 1.0\n[[tank]]"), "parameters.warp", "warp"),
    (("[[tank]]", "[options]\npressure_solver = 3\n[[tank]]"), "options.pressure_solver",
     "string"),
    (("[[tank]]", "[options]\ncfl = 0.3\n[[tank]]"), "options.cfl",
     "cfl is a parameter: put it under [parameters]"),
    (("[[tank]]", "[parameters]\npressure_solver = \"cg\"\n[[tank]]"),
     "parameters.pressure_solver", "pressure_solver is an option: put it under [options]"),
    (("[[tank]]", "[[probe]]\nname = \"p\"\ntype = \"temperature\"\n[[tank]]"),
     "probe[0].type", "must be one of"),
    (("[[tank]]", "[[probe]]\nname = \"p\"\ntype = \"pressure\"\n[[tank]]"), "probe[0]",
     "needs ['at']"),
    (("[[tank]]", "[[probe]]\nname = \"p\"\ntype = \"stat\"\nstat = \"heat\"\n[[tank]]"),
     "probe[0].stat", "must be one of"),
    (("[[tank]]", "[[particles]]\nfile = \"missing.npz\"\n[[tank]]"), "particles[0].file",
     "no such file"),
])
def test_wrong_files_name_the_file_key_and_reason(tmp_path, change, key, reason):
    assert change[0] in GOOD
    path = write(tmp_path, GOOD.replace(change[0], change[1], 1))
    with pytest.raises(mps2p.SceneFileError) as caught:
        scenefile.load(path).build()
    message = str(caught.value)
    assert message.startswith(path + ": ") and key in message and reason in message, message


@pytest.mark.parametrize("change, named", [
    # a fluid box reaching into the tank's wall, two fluid boxes over each other
    # (the library refuses a box over an earlier one: boxes may touch), and the
    # same half a spacing off, where no two particles share a place (the run
    # diverged at its first step)
    (("box = [0.0, 0.0, 0.16, 0.3]", "box = [0.4, 0.0, 0.7, 0.2]"),
     "tank[0] overlaps fluid_box[0]: the solid box"),
    (("[[tank]]", "[[fluid_box]]\nfluid = \"water\"\nbox = [0.1, 0.1, 0.2, 0.2]\n[[tank]]"),
     "fluid_box[1] overlaps fluid_box[0]: the fluid box"),
    (("[[tank]]", "[[fluid_box]]\nfluid = \"water\"\nbox = [0.105, 0.105, 0.205, 0.205]\n"
                  "[[tank]]"),
     "fluid_box[1] overlaps fluid_box[0]: the fluid box"),
])
def test_overlapping_items_are_named(tmp_path, change, named):
    assert change[0] in GOOD
    path = write(tmp_path, GOOD.replace(change[0], change[1], 1))
    with pytest.raises(mps2p.SceneFileError) as caught:
        scenefile.load(path).make_solver()
    assert str(caught.value).startswith(path + ": " + named), str(caught.value)


@pytest.mark.parametrize("box, warned", [
    ("[1.0, 0.0, 1.2, 0.2]", True),   # beside the tank
    ("[0.0, 0.6, 0.16, 0.8]", False),  # over its open top: falls in
    ("[0.0, 0.0, 0.16, 0.3]", False),
])
def test_a_fluid_box_outside_every_tank_is_warned_of(tmp_path, box, warned):
    path = write(tmp_path, GOOD.replace("box = [0.0, 0.0, 0.16, 0.3]", "box = " + box, 1))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scenefile.load(path).build().close()
    outside = [str(w.message) for w in caught if "outside every tank" in str(w.message)]
    assert len(outside) == int(warned), outside
    if warned:
        assert outside[0].startswith(path + ": fluid_box[0]: ")


@pytest.mark.parametrize("wall, warned", [
    ("[0.3, 0.0, 0.4, 0.05]", True),   # a weir inside the tank: nothing under the box
    ("[1.0, 0.0, 1.2, 0.05]", False),  # a shelf under the box beside the tank
])
def test_a_wall_box_under_a_fluid_box_outside_the_tanks_may_hold_it(tmp_path, wall, warned):
    text = GOOD.replace("box = [0.0, 0.0, 0.16, 0.3]", "box = [1.0, 0.05, 1.2, 0.2]", 1)
    path = write(tmp_path, text + "\n[[wall_box]]\nbox = " + wall + "\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scenefile.load(path).build().close()
    outside = [str(w.message) for w in caught if "outside every tank" in str(w.message)]
    assert len(outside) == int(warned), outside


def test_a_parameter_that_is_not_finite(tmp_path):
    """nan is a float to TOML: the message says a finite number is wanted."""
    text = GOOD.replace("[[tank]]", "[parameters]\ncfl = nan\n[[tank]]", 1)
    with pytest.raises(mps2p.SceneFileError) as caught:
        scenefile.load(write(tmp_path, text))
    assert "parameters.cfl: must be a finite number, got nan" in str(caught.value)


def test_every_problem_at_once(tmp_path):
    """A file with three mistakes in its structure names all three, one line
    each, and not yet its value's mistake (end_time); once the structure is
    sound, every mistake in its values."""
    text = GOOD.replace("l0 = 0.02", "l0 = 0.02\nsped = 1").replace(
        "end_time = 0.02", "end_time = -1").replace(
        "density = 1000.0", "density = \"heavy\"").replace(
        "box = [0.0, 0.0, 0.6, 0.5]", "box = [0.0, 0.0, 0.6]")
    with pytest.raises(mps2p.SceneFileError) as caught:
        scenefile.load(write(tmp_path, text))
    lines = str(caught.value).splitlines()
    assert len(lines) == 3, lines
    assert any("run.sped: unknown key" in line for line in lines)
    assert any("fluid[0].density: must be a finite number" in line for line in lines)
    assert any("tank[0].box: must be 4 numbers" in line for line in lines)
    text = GOOD.replace("end_time = 0.02", "end_time = -1").replace(
        'fluid = "water"', 'fluid = "oil"')
    with pytest.raises(mps2p.SceneFileError) as caught:
        scenefile.load(write(tmp_path, text))
    lines = str(caught.value).splitlines()
    assert len(lines) == 2, lines
    assert "run.end_time: must be > 0" in lines[0] and "fluid_box[0].fluid" in lines[1]


def test_not_toml_and_missing_file(tmp_path):
    with pytest.raises(mps2p.SceneFileError, match="not valid TOML"):
        scenefile.load(write(tmp_path, "[run\nl0 = 1"))
    with pytest.raises(mps2p.SceneFileError, match="cannot read"):
        scenefile.load(str(tmp_path / "nowhere.toml"))


def test_files_that_are_not_regular_are_refused(tmp_path):
    # a FIFO blocked the reading forever, /dev/zero filled memory (an audit,
    # session 24): refused at once, an alarm fails the test if it blocks
    import signal

    def blocked(signum, frame):
        raise AssertionError("reading blocked")

    fifo = tmp_path / "fifo.toml"
    os.mkfifo(fifo)
    previous = signal.signal(signal.SIGALRM, blocked)
    signal.alarm(20)
    try:
        with pytest.raises(mps2p.SceneFileError, match="a FIFO, not a regular file"):
            scenefile.load(str(fifo))
        with pytest.raises(mps2p.SceneFileError, match="a device, not a regular file"):
            scenefile.load("/dev/zero")
        with pytest.raises(mps2p.SceneFileError, match="a directory, not a regular file"):
            scenefile.load(str(tmp_path))
        particles = tmp_path / "fifo.npz"
        os.mkfifo(particles)
        text = GOOD.replace("[[fluid_box]]\nfluid = \"water\"\nbox = [0.0, 0.0, 0.16, 0.3]\n",
                            "[[particles]]\nfile = \"fifo.npz\"\n")
        with pytest.raises(mps2p.SceneFileError, match="fifo.npz is a FIFO, not a regular file"):
            scenefile.load(write(tmp_path, text)).build()
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    big = tmp_path / "big.toml"
    with open(big, "wb") as f:
        f.write(b"#" * (scenefile.MOST_SCENE_BYTES + 1))
    with pytest.raises(mps2p.SceneFileError, match="not a scene file"):
        scenefile.load(str(big))


def test_particles_from_an_npz_file(tmp_path):
    l0 = 0.02
    x, y = np.meshgrid((np.arange(8) + 0.5) * l0, (np.arange(15) + 0.5) * l0)
    np.savez(tmp_path / "column.npz", positions=np.column_stack([x.ravel(), y.ravel()]),
             kinds=np.zeros(x.size, dtype=np.int32), fluid_ids=np.zeros(x.size, dtype=np.int32))
    text = GOOD.replace("[[fluid_box]]\nfluid = \"water\"\nbox = [0.0, 0.0, 0.16, 0.3]\n",
                        "[[particles]]\nfile = \"column.npz\"\n")
    from_file = scenefile.load(write(tmp_path, text)).build()
    from_box = scenefile.load(write(tmp_path, GOOD, "box.toml")).build()
    assert from_file.particle_count == from_box.particle_count
    import h5py
    with h5py.File(tmp_path / "column.h5", "w") as f:
        with np.load(tmp_path / "column.npz") as arrays:
            for key in arrays.files:
                f[key] = arrays[key]
    from_h5 = scenefile.load(write(tmp_path, text.replace("column.npz", "column.h5"),
                                   "h5.toml")).build()
    assert from_h5.particle_count == from_box.particle_count
    (tmp_path / "broken.h5").write_bytes(b"not an HDF5 file")
    with pytest.raises(mps2p.SceneFileError, match="cannot read"):
        scenefile.load(write(tmp_path, text.replace("column.npz", "broken.h5"),
                             "broken.toml")).build()
    np.savez(tmp_path / "bad.npz", positions=np.zeros((2, 2)), colours=np.zeros(2))
    with pytest.raises(mps2p.SceneFileError, match="unknown arrays"):
        scenefile.load(write(tmp_path, text.replace("column.npz", "bad.npz"))).build()


SHIPPED = sorted(glob.glob(os.path.join(SCENES, "*.toml")))


def test_scenes_are_shipped():
    names = {os.path.basename(p) for p in SHIPPED}
    assert {"dam_break.toml", "hydrostatic.toml"} <= names


@pytest.mark.parametrize("path", SHIPPED, ids=os.path.basename)
def test_every_shipped_scene_runs(tmp_path, path):
    summary = run(path, str(tmp_path), until=0.02, pictures=True)
    assert summary["status"] == "ok", summary["reason"]
    assert summary["time"] == pytest.approx(0.02, abs=1e-12)
    for name in ("results.h5", "results.xdmf", "series.csv", "summary.json", "snapshots.png"):
        assert (tmp_path / name).exists(), name
    header = (tmp_path / "series.csv").read_text().splitlines()[0].split(",")
    assert header == ["time", "step"] + summary["probes"]
    written = json.loads((tmp_path / "summary.json").read_text())
    for key in ("status", "reason", "time", "steps", "wall_seconds", "stage_seconds",
                "particles", "effects", "version"):
        assert key in written, key
    assert written["steps"] == summary["steps"] > 0
    assert written["version"] == mps2p.__version__
    # the pressure stage: the single-phase solve, or the liquid's with two phases
    pressure_stage = "liquid_pressure" if written["effects"]["two_phase"]["active"] \
        else "pressure_solve"
    assert written["stage_seconds"][pressure_stage] > 0
    assert written["particles"]["water"] > 0 and written["particles"]["wall"] > 0
    assert written["effects"]["gravity"]["active"] is True
    ET.parse(tmp_path / "results.xdmf")  # the sidecar is well-formed XML


def test_a_bad_scene_writes_nothing(tmp_path):
    path = write(tmp_path, GOOD.replace("[[tank]]", "[effects]\nviscosity = \"on\"\n[[tank]]")
                 .replace("viscosity = 1e-6", "viscosity = 0.0"))
    out = tmp_path / "out"
    with pytest.raises(mps2p.SceneFileError, match="effect viscosity is switched on.*cannot"):
        run(path, str(out))
    assert not out.exists()


def test_effects_table_switches_effects(tmp_path):
    path = write(tmp_path, GOOD.replace("[[tank]]", "[effects]\ncollision = \"off\"\n[[tank]]"))
    summary = run(path, str(tmp_path / "out"), pictures=False)
    assert summary["effects"]["collision"] == {
        "active": False, "reason": "requested: off; collision_distance is 0.995 l0"}
    assert "collision" not in summary["stage_seconds"]


@pytest.mark.parametrize("text, words", [
    # a parameter written outside [parameters]
    ("gravity_y = -9.81\n" + GOOD, "gravity_y: gravity_y is one of the library's parameters: "
                                   "put it under [parameters]"),
    ("pressure_solver = \"cg\"\n" + GOOD, "put it under [options]"),
    # a probe type misspelt
    (GOOD + "[[probe]]\nname = \"p\"\ntype = \"presure\"\nat = [0.1, 0.01]\n",
     "did you mean pressure?"),
])
def test_misplaced_settings_and_misspelt_probe_types_say_what_is_meant(tmp_path, text, words):
    path = write(tmp_path, text)
    with pytest.raises(mps2p.SceneFileError) as caught:
        scenefile.load(path)
    assert words in str(caught.value), str(caught.value)


@pytest.mark.parametrize("at, warned", [
    ("[0.31, 0.02]", "inside wall_box[0]"),          # inside the obstacle
    ("[0.7, 0.02]", "outside every tank"),           # beyond the right wall (x1 = 0.6)
    ("[0.29, 0.02]", None),                          # in front of the obstacle's face
])
def test_pressure_probes_out_of_the_fluid_are_warned_of(tmp_path, at, warned):
    text = GOOD + ("[[wall_box]]\nbox = [0.3, 0.0, 0.34, 0.06]\n"
                   "[[probe]]\nname = \"p\"\ntype = \"pressure\"\nat = %s\n" % at)
    path = write(tmp_path, text)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scenefile.load(path).build().close()
    said = [str(w.message) for w in caught if "probe[0]" in str(w.message)]
    if warned:
        assert len(said) == 1 and warned in said[0], said
    else:
        assert not said, said


@pytest.mark.parametrize("l0", [0.02, 0.015, 0.0125])
@pytest.mark.parametrize("path", SHIPPED, ids=os.path.basename)
def test_every_shipped_scene_builds_on_one_lattice_at_other_spacings(path, l0):
    """At a spacing that does not divide its geometry (`--l0`, check_run's
    l0), a shipped scene still builds, and every particle sits at the centre
    of a cell of one l0 lattice from the origin: boxes that touch in the file
    touch on it. Each box filled from its own corner put drop_into_pool.toml's
    drop box into the tank's wall at 0.015 m (refused), and at 0.02 m
    bubble_rise_4x4.toml's bubble half a spacing off the water around it."""
    sf = scenefile.load(path)
    sf.l0 = l0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", mps2p.SnapWarning)
        with sf.make_solver() as solver:
            cells = solver.positions() / l0 - 0.5
    assert np.abs(cells - np.round(cells)).max() < 1e-6


def test_a_box_off_the_lattice_is_moved_onto_it_and_said(tmp_path):
    text = GOOD.replace("[[tank]]", "[[fluid_box]]\nfluid = \"water\"\n"
                        "box = [0.2, 0.05, 0.31, 0.1]\n[[tank]]", 1)
    path = write(tmp_path, text)
    with pytest.warns(mps2p.SnapWarning) as caught:
        scenefile.load(path).build().close()
    said = [str(w.message) for w in caught]
    assert said == [path + ": fluid_box[1]: [0.2, 0.05, 0.31, 0.1] moved onto the lattice of "
                    "l0 = 0.02 m: [0.2, 0.04, 0.3, 0.1]"], said
    narrow = write(tmp_path, text.replace("[0.2, 0.05, 0.31, 0.1]", "[0.21, 0.05, 0.215, 0.1]"),
                   "narrow.toml")
    with pytest.raises(mps2p.SceneFileError, match=r"fluid_box\[1\]: .* is narrower than "
                                                   r"l0 = 0.02 m on the lattice"):
        scenefile.load(narrow).build()
    low = write(tmp_path, text.replace("[0.2, 0.05, 0.31, 0.1]", "[0.2, 0.05, 0.3, 0.055]"),
                "low.toml")
    with pytest.raises(mps2p.SceneFileError, match=r"fluid_box\[1\]: .* is lower than "):
        scenefile.load(low).build()


def test_a_changed_run_table_is_what_is_built(tmp_path):
    """docs/python.md: a script may change sf.data before make_solver(); the
    [run] values too (they were copied at load, and a changed l0 did nothing)."""
    sf = scenefile.load(write(tmp_path, GOOD))
    sf.data["run"]["l0"] = 0.04
    assert sf.l0 == 0.04
    with sf.make_solver() as solver:
        water = sum(1 for k in solver.kinds() if k == mps2p.KIND_FLUID)
    assert water == 4 * 7  # [0, 0.16] x [0, 0.3] on the 0.04 m lattice
    sf.end_time = 0.5
    assert sf.data["run"]["end_time"] == 0.5
