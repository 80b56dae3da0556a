"""The C path and the Python path are the same library: the dam break built
in C (examples/dam_break.c) and from examples/scenes/dam_break.toml has the
same particles and the same surge front."""
import filecmp
import os
import subprocess

import h5py
import numpy as np

from mps2p.tools import scenefile
from mps2p.tools.pictures import REFERENCE

from conftest import ROOT, SCENES


def c_example():
    """The built C example: MPS2P_EXAMPLES or build-release/examples."""
    folder = os.environ.get("MPS2P_EXAMPLES", os.path.join(ROOT, "build-release", "examples"))
    path = os.path.join(folder, "dam_break")
    assert os.path.exists(path), "build the C example first (%s), or set MPS2P_EXAMPLES" % path
    return path


def test_same_particles_and_front_from_c_and_python(tmp_path):
    l0, end = 0.02, 0.3
    out = subprocess.run([c_example(), str(l0), str(end), str(tmp_path / "c.h5")],
                         capture_output=True, text=True, check=True).stdout
    c_rows = np.array([[float(v) for v in line.split()] for line in out.splitlines()
                       if not line.startswith("#")])
    text = open(os.path.join(SCENES, "dam_break.toml")).read().replace("l0 = 0.01", "l0 = 0.02")
    path = tmp_path / "dam_break.toml"
    path.write_text(text)
    with scenefile.load(str(path)).make_solver() as solver:
        with h5py.File(tmp_path / "c.h5", "r") as f:
            c_start = f["snapshots/000000/position"][()]
            c_kind = f["snapshots/000000/kind"][()]
        assert np.array_equal(solver.positions(), c_start)
        assert np.array_equal(solver.kinds(), c_kind)
        fronts = []
        for t, _, _, steps in c_rows:
            solver.advance_to(t)
            fronts.append(solver.front(0, 2 * l0) / 0.15)
            assert solver.step_count == steps
    assert np.array_equal(np.round(fronts, 4), c_rows[:, 2])  # the C example prints 4 digits
    assert c_rows[-1, 2] > 3.0  # it did run: the front is near the right wall


def test_packaged_reference_is_the_repository_one():
    assert filecmp.cmp(REFERENCE, os.path.join(ROOT, "data", "martin_moyce_1952.csv"),
                       shallow=False)
