"""Results as ParaView and meshio open them: Debian's ParaView (pvbatch)
through the Xdmf3 readers ParaView suggests, the legacy XDMF reader, and
meshio's XDMF time-series reader (issue 19). scripts/install-deps.sh
installs paraview, xvfb and meshio."""
import json
import os
import shutil
import subprocess

import numpy as np
import pytest

from mps2p import open_results
from mps2p.tools.run import run

from conftest import HERE, SCENES

LOAD = os.path.join(HERE, "tools", "paraview_load.py")
PARTICLES = 1282  # the dam break at l0 = 0.01 m, walls included


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    out = tmp_path_factory.mktemp("dam_break")
    run(os.path.join(SCENES, "dam_break.toml"), str(out), until=0.1, pictures=False)
    return out


def pvbatch(path, cwd, picture=None):
    assert shutil.which("pvbatch"), "pvbatch not found: apt-get install paraview " \
        "python3-paraview (scripts/install-deps.sh)"
    command = ["pvbatch", LOAD, str(path)] + ([str(picture)] if picture else [])
    if picture:  # Debian's ParaView renders through X: a virtual one
        assert shutil.which("xvfb-run"), "xvfb-run not found: apt-get install xvfb xauth"
        command = ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24"] + command
    # ParaView's embedded Python takes its home from the python3 first on PATH:
    # Debian's, not a venv's or pyenv's (their numpy would crash the renderer)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    env["PATH"] = "/usr/bin:/bin:" + env.get("PATH", "")
    done = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=300,
                          env=env)
    lines = [line for line in done.stdout.splitlines() if line.startswith("PARAVIEW ")]
    # ParaView's stack traces are long lists of addresses: keep the words
    said = "\n".join(line for line in done.stderr.splitlines() if "0x" not in line)
    assert done.returncode == 0 and lines, done.stdout[-2000:] + said[-3000:]
    return json.loads(lines[-1][len("PARAVIEW "):])


def check_readers(seen):
    for reader in ("Xdmf3ReaderS", "Xdmf3ReaderT", "XDMFReader"):
        got = seen[reader]
        assert got["point_arrays"] == ["fluid_id", "kind", "number_density", "pressure",
                                       "velocity"], reader
        assert len(got["steps"]) == 3, reader
        for step in got["steps"]:
            # every particle a point and a cell: Points and Surface show them
            assert step["points"] == PARTICLES and step["cells"] == PARTICLES, (reader, step)
        assert got["pressure_range"][1] > 100.0, reader  # the water's weight, read from .h5
    assert seen["Xdmf3ReaderS"]["times"] == pytest.approx([0.0, 0.05, 0.1], abs=1e-12)


def test_paraview_xdmf3_readers_load_particles_as_cells(results, tmp_path):
    # from another folder, by a relative path, as a user in their shell would
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    check_readers(pvbatch(os.path.relpath(results / "results.xdmf", elsewhere), elsewhere))
    # from the results folder itself, as ./results.xdmf
    check_readers(pvbatch("./results.xdmf", results))


def test_a_moved_copy_still_opens(results, tmp_path):
    moved = tmp_path / "moved"
    moved.mkdir()
    for name in ("results.h5", "results.xdmf"):
        shutil.copy(results / name, moved / name)
    check_readers(pvbatch(moved / "results.xdmf", tmp_path))


def test_paraview_renders_the_points(results, tmp_path):
    picture = tmp_path / "paraview.png"
    pvbatch(results / "results.xdmf", tmp_path, picture=picture)
    import matplotlib.image
    image = matplotlib.image.imread(picture)[:, :, :3]
    coloured = np.ptp(image, axis=2) > 0.2  # neither the white background nor grey text
    assert coloured.sum() > 0.5 * PARTICLES, coloured.sum()


def test_meshio_reads_the_time_series(results):
    import meshio  # installed by scripts/install-deps.sh
    with meshio.xdmf.TimeSeriesReader(str(results / "results.xdmf")) as reader:
        points, cells = reader.read_points_cells()
        assert points.shape == (PARTICLES, 2)
        assert [(c.type, c.data.shape) for c in cells] == [("vertex", (PARTICLES, 1))]
        assert np.array_equal(cells[0].data[:, 0], np.arange(PARTICLES))
        with open_results(results / "results.h5") as written:
            assert reader.num_steps == len(written) == 3
            assert np.array_equal(points, written.snapshot(0)["position"])
            for k in range(reader.num_steps):
                t, point_data, _ = reader.read_data(k)
                snapshot = written.snapshot(k)
                assert t == pytest.approx(snapshot["time"], abs=1e-12)
                for name in ("velocity", "pressure", "kind", "fluid_id"):
                    assert np.array_equal(point_data[name], snapshot[name]), (k, name)
    # and the cloud converts to other formats (meshio needs (n, 1) vertex cells)
    mesh = meshio.Mesh(points, cells, point_data=point_data)
    mesh.write(str(results / "last.vtu"))
    assert meshio.read(str(results / "last.vtu")).points.shape[0] == PARTICLES
