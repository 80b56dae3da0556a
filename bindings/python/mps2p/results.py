"""Results files (HDF5 + XDMF sidecar), written by the C library so C and
Python users get the same files; see docs/results-files.md for the layout."""
from ._core import check, encode, real
from ._native import ffi, lib


class Results:
    """Wraps mps2p_results: Results(path, solver, scene_text=None) creates
    the file and writes the run's metadata. Close it (or use `with`)."""

    def __init__(self, path, solver, scene_text=None):
        handle = ffi.new("mps2p_results **")
        text = encode(scene_text, "scene text") if scene_text is not None else ffi.NULL
        check(lib.mps2p_results_create(encode(str(path), "path"), solver.handle, text, handle))
        self._handle = handle[0]
        self.path = str(path)

    def write_snapshot(self, solver):
        check(lib.mps2p_results_write_snapshot(self._open(), solver.handle))

    def append_series(self, name, time, value):
        check(lib.mps2p_results_append_series(self._open(), encode(name, "series name"),
                                              real(time, "time"), real(value, "value")))

    def _open(self):
        if self._handle is None:
            raise ValueError("the results file %s is closed" % self.path)
        return self._handle

    def close(self):
        if self._handle is not None:
            handle, self._handle = self._handle, None
            check(lib.mps2p_results_close(handle))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        if getattr(self, "_handle", None) is not None:
            lib.mps2p_results_close(self._handle)
            self._handle = None
