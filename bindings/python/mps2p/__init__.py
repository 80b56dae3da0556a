"""libmps2p from Python: a thin cffi binding over the C library's public
header. The numerics are all in C; this package converts and checks
arguments, turns status codes into exceptions and returns fields as numpy
arrays (copies). The applications built on it (scene files, `mps2p run`,
the study, the stability checks, pictures, the command) are mps2p.tools.

    import mps2p
    with mps2p.Scene(0.01) as scene:
        water = scene.add_fluid("water", 1000.0, 1e-6)
        scene.add_fluid_box(water, 0, 0, 0.15, 0.3)
        scene.add_tank(0, 0, 0.6, 0.7, open_top=True)
        solver = mps2p.Solver(scene)
    solver.advance_to(0.3)
    xy = solver.positions()            # (n, 2) numpy array, a copy
"""
import sys


def _run_as_command():
    """`python3 -m mps2p[.tools...]`: Python sets argv[0] to "-m" while it
    imports the package, and orig_argv names the module (another package run
    with -m that imports mps2p keeps its ImportError to catch)."""
    argv = getattr(sys, "orig_argv", [])
    if sys.argv[:1] != ["-m"] or "-m" not in argv[:-1]:
        return False
    return argv[argv.index("-m") + 1].split(".")[0] == "mps2p"


try:
    from . import _native  # loads libmps2p
except ImportError as _error:
    # a command: one line and exit status 2, as the `mps2p` command
    if _run_as_command():
        print("mps2p: %s" % _error, file=sys.stderr)
        raise SystemExit(2) from None
    raise
from . import errors, results
from ._core import version as _version
from ._native import header_path, library_path
from .errors import (BufferError_, DivergedError, Error, FileError, InvalidArgumentError,
                     MissingFileError, NotResultsFileError, NullArgumentError,
                     OutOfMemoryError, SceneFileError, SnapWarning, SolveError, StateError,
                     UnknownKeyError)
from .results import Results, ResultsFile, open_results
from .scene import KIND_DUMMY, KIND_FLUID, KIND_OUT, KIND_WALL, Scene, option_info, param_info
from .solver import COUNT_STATS, STAT_KEYS, Solver, State, stat_info

__version__ = _version()


def __getattr__(name):
    """mps2p.example_names, mps2p.example_path and mps2p.examples, as before
    the applications moved to mps2p.tools: imported when first asked for."""
    if name in ("example_names", "example_path", "examples"):
        from .tools import examples
        return examples if name == "examples" else getattr(examples, name)
    raise AttributeError("module 'mps2p' has no attribute %r" % name)


__all__ = [
    "Scene", "Solver", "State", "param_info", "option_info", "stat_info", "STAT_KEYS",
    "COUNT_STATS", "KIND_FLUID", "KIND_WALL", "KIND_DUMMY", "KIND_OUT", "Results", "ResultsFile",
    "open_results", "example_names", "example_path", "Error", "NullArgumentError",
    "InvalidArgumentError", "UnknownKeyError", "OutOfMemoryError", "StateError",
    "BufferError_", "SolveError", "DivergedError", "FileError", "MissingFileError",
    "NotResultsFileError", "SceneFileError",
    "SnapWarning", "errors", "results", "library_path", "header_path", "__version__",
]
