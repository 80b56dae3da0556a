"""libmps2p from Python: a thin cffi binding over the C library's public
header. The numerics are all in C; this package converts and checks
arguments, turns status codes into exceptions and returns fields as numpy
arrays (copies).

    import mps2p
    with mps2p.Scene(0.01) as scene:
        water = scene.add_fluid("water", 1000.0, 1e-6)
        scene.add_fluid_box(water, 0, 0, 0.15, 0.3)
        scene.add_tank(0, 0, 0.6, 0.7, open_top=True)
        solver = mps2p.Solver(scene)
    solver.advance_to(0.3)
    xy = solver.positions()            # (n, 2) numpy array, a copy
"""
from . import errors, examples, results
from ._core import version as _version
from ._native import header_path, library_path
from .errors import (BufferError_, DivergedError, Error, FileError, InvalidArgumentError,
                     NullArgumentError, OutOfMemoryError, SceneFileError, SnapWarning,
                     SolveError, StateError, UnknownKeyError)
from .examples import example_names, example_path
from .results import Results, ResultsFile, open_results
from .scene import KIND_DUMMY, KIND_FLUID, KIND_WALL, Scene, option_info, param_info
from .solver import COUNT_STATS, STAT_KEYS, Solver, State, stat_info

__version__ = _version()

__all__ = [
    "Scene", "Solver", "State", "param_info", "option_info", "stat_info", "STAT_KEYS", "COUNT_STATS", "KIND_FLUID",
    "KIND_WALL", "KIND_DUMMY", "Results", "ResultsFile", "open_results", "example_names",
    "example_path", "Error", "NullArgumentError", "InvalidArgumentError", "UnknownKeyError",
    "OutOfMemoryError", "StateError", "BufferError_", "SolveError", "DivergedError",
    "FileError", "SceneFileError", "SnapWarning", "errors", "examples", "results",
    "library_path", "header_path", "__version__",
]
