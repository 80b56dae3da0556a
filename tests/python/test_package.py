"""What a newcomer does (issue 19): a fresh venv, `pip install .` at the
checkout's root, and the package imports and runs with the library and
header it carries; and the thin package (bindings/python) says how to get a
library when it finds none. Needs PyPI (pip fetches meson-python, cffi,
numpy, h5py) and the system's -dev packages (scripts/install-deps.sh)."""
import json
import os
import subprocess
import sys

import pytest

from conftest import ROOT

# nothing of the developer's set-up may leak into the newcomer's shell
CLEAN = ("PYTHONPATH", "PYTHONHOME", "MPS2P_LIBRARY", "MPS2P_HEADER", "PKG_CONFIG_PATH",
         "VIRTUAL_ENV", "PIP_TARGET", "PIP_PREFIX")


def shell(*command, cwd, extra=None, check=True):
    env = {k: v for k, v in os.environ.items() if k not in CLEAN}
    env.update(extra or {})
    done = subprocess.run([str(c) for c in command], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=1200)
    if check:
        assert done.returncode == 0, "%s\n%s\n%s" % (command, done.stdout[-3000:],
                                                      done.stderr[-3000:])
    return done


def make_venv(folder, package):
    shell(sys.executable, "-m", "venv", folder / ".venv", cwd=folder)
    pip = folder / ".venv" / "bin" / "pip"
    shell(pip, "install", "--disable-pip-version-check", "-q", package, cwd=folder)
    return folder / ".venv" / "bin"


@pytest.fixture(scope="module")
def newcomer(tmp_path_factory):
    folder = tmp_path_factory.mktemp("newcomer")
    return folder, make_venv(folder, ROOT)


def test_pip_install_dot_imports_with_the_library_and_header_it_carries(newcomer):
    folder, bin_dir = newcomer
    code = "import mps2p, json; print(json.dumps([mps2p.library_path, mps2p.header_path, " \
           "mps2p.__version__]))"
    library, header, version = json.loads(shell(bin_dir / "python", "-c", code,
                                                cwd=folder).stdout)
    site = str(folder / ".venv")
    assert library.startswith(site) and library.endswith("mps2p/libmps2p.so.0"), library
    assert header.startswith(site) and header.endswith("mps2p/mps2p.h"), header
    assert version.count(".") == 2
    assert ("libmps2p %s" % version) in shell(bin_dir / "mps2p", "--version", cwd=folder).stdout
    assert "usage: mps2p" in shell(bin_dir / "mps2p", "--help", cwd=folder).stdout


def test_the_newcomer_runs_an_example_by_name_and_reads_its_results(newcomer):
    folder, bin_dir = newcomer
    listed = shell(bin_dir / "mps2p", "examples", cwd=folder).stdout
    assert "dam_break" in listed and "hydrostatic" in listed
    run = shell(bin_dir / "mps2p", "run", "dam_break", "--until", "0.02", "--quiet",
                cwd=folder)
    assert "dam_break: ok at t = 0.02 s" in run.stdout
    # the venv has no matplotlib: the run says so instead of failing
    assert run.stderr.strip() == "mps2p: warning: no pictures: matplotlib is not installed " \
                                 "(pip install matplotlib)"
    out = folder / "out" / "dam_break"
    assert sorted(os.listdir(out)) == ["results.h5", "results.xdmf", "series.csv",
                                       "summary.json"]
    code = "import mps2p; r = mps2p.open_results('out/dam_break/results.h5'); " \
           "print(len(r), r.metadata['format'], r.snapshot(-1)['position'].shape)"
    assert shell(bin_dir / "python", "-c", code, cwd=folder).stdout.split() == \
        ["2", "libmps2p", "results", "(1282,", "2)"]


def test_the_thin_package_without_a_library_says_how_to_get_one(tmp_path):
    bin_dir = make_venv(tmp_path, os.path.join(ROOT, "bindings", "python"))
    failed = shell(bin_dir / "python", "-c", "import mps2p", cwd=tmp_path, check=False)
    assert failed.returncode == 1
    last = failed.stderr.strip().splitlines()[-1]
    assert last.startswith("ImportError: libmps2p not found") and "pip install ." in last \
        and "PKG_CONFIG_PATH" in last and "MPS2P_LIBRARY" in last, last
    # the command says the same in one line, without a traceback
    command = shell(bin_dir / "mps2p", "--version", cwd=tmp_path, check=False)
    assert command.returncode == 2
    assert command.stderr.strip().splitlines() == [
        "mps2p: " + last[len("ImportError: "):]], command.stderr
    # MPS2P_LIBRARY alone (a build tree) is enough: its header is found from it
    library = os.path.join(ROOT, "build-release", "lib", "libmps2p.so.0")
    assert os.path.exists(library), "build the library first: ninja -C build-release"
    code = "import mps2p; print(mps2p.header_path)"
    found = shell(bin_dir / "python", "-c", code, cwd=tmp_path,
                  extra={"MPS2P_LIBRARY": library}).stdout.strip()
    assert found == os.path.join(ROOT, "include", "mps2p.h")
