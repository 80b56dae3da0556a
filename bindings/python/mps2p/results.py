"""Results files (HDF5 + XDMF sidecar): written by the C library, so C and
Python users get the same files, and read back with open_results(). The
layout is in docs/results-files.md."""
import os

import numpy as np

from ._core import check, encode, encode_path, real
from .errors import FileError, MissingFileError, NotResultsFileError
from ._native import ffi, lib


class Results:
    """Writes a results file (wraps mps2p_results): Results(path, solver,
    scene_text=None) creates `path` (and its .xdmf sidecar) and writes the
    run's metadata. Close it, or use `with`; open_results(path) reads it."""

    def __init__(self, path, solver, scene_text=None):
        from .solver import Solver
        if not isinstance(solver, Solver):
            raise TypeError("Results: solver must be an mps2p.Solver, got %s"
                            % type(solver).__name__)
        handle = ffi.new("mps2p_results **")
        text = encode(scene_text, "scene text") if scene_text is not None else ffi.NULL
        c_path = encode_path(path)
        check(lib.mps2p_results_create(c_path, solver.handle, text, handle))
        self._handle = handle[0]
        self.path = os.fsdecode(c_path)

    def write_snapshot(self, solver):
        """Appends the solver's current state as /snapshots/NNNNNN (flushed to
        disk) and rewrites the XDMF sidecar to name it."""
        check(lib.mps2p_results_write_snapshot(self._open(), solver.handle))

    def append_series(self, name, time, value):
        """Appends the row (time s, value) to the series /series/<name>
        (1 to 64 letters, digits, '_', '-', '.')."""
        check(lib.mps2p_results_append_series(self._open(), encode(name, "series name"),
                                              real(time, "time"), real(value, "value")))

    def _open(self):
        if self._handle is None:
            raise ValueError("the results file %s is closed" % self.path)
        return self._handle

    def close(self):
        """Flushes and closes the file; closing twice is fine."""
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


SNAPSHOT_FIELDS = ("position", "velocity", "pressure", "number_density", "kind", "fluid_id")


def _text(value):
    """HDF5 strings come back from h5py as bytes (UTF-8 in these files; the C
    library takes names as bytes, so others are kept as surrogate escapes,
    as Python keeps file names)."""
    if isinstance(value, bytes):
        return value.decode("utf-8", "surrogateescape")
    if isinstance(value, np.ndarray) and value.dtype.kind in "SO":
        return [_text(v) for v in value.tolist()]
    return value


def _value(value):
    """An attribute as plain Python: str, int, float, or a numpy array."""
    value = _text(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value)
    if isinstance(value, np.ndarray) and value.shape == ():
        return _value(value[()])
    return value


def _open_hdf5(h5py, path):
    """h5py.File(path, "r"), with HDF5's messages turned into a FileError
    that names the file and says what to open instead."""
    if not os.path.exists(path):
        raise MissingFileError('results file "%s": no such file' % path)
    if os.path.isdir(path):
        raise FileError('results file "%s" is a directory (a run\'s results are its '
                        'results.h5)' % path)
    try:
        if not h5py.is_hdf5(path):
            hint = (" (the .xdmf only describes results.h5 for ParaView: open results.h5)"
                    if path.endswith(".xdmf") else "")
            raise FileError('results file "%s" is not an HDF5 file%s' % (path, hint))
        return h5py.File(path, "r")
    except FileError:
        raise
    except OSError as e:
        raise FileError('results file "%s": cannot read it: %s' % (path, e)) from e


class ResultsFile:
    """A results file opened for reading (open_results(path)); metadata as
    str, int and float, fields as numpy arrays. Close it, or use `with`.

    metadata     {format, format_version, library_version, l0, n0, lambda,
                 domain, particle_count}
    parameters   {name: float} for numeric parameters, {name: str} for options
    fluids       [(name, density kg/m^3, kinematic viscosity m^2/s)] by fluid id
    scene_text   the scene file's text, or None
    times        (snapshots,) float64 snapshot times (s); steps likewise, int64
    series       {name: (rows, 2) float64 of (time s, value)}
    snapshot(k)  {"time", "step", "position", "velocity", "pressure",
                 "number_density", "kind", "fluid_id"} of snapshot k (negative
                 k counts from the end)"""

    def __init__(self, path):
        import h5py
        path = os.fsdecode(encode_path(path))
        self.path = path
        self._file = _open_hdf5(h5py, path)
        try:
            self._read_metadata()
        except KeyError as e:  # an attribute or dataset the format has is missing
            self._file.close()
            raise FileError('results file "%s" is damaged: %s' % (path, e)) from e
        except Exception:
            self._file.close()
            raise

    def _read_metadata(self):
        f = self._file
        if _text(f.attrs.get("format")) != "libmps2p results":
            raise NotResultsFileError("%s is not a libmps2p results file (format %r)"
                             % (self.path, _text(f.attrs.get("format"))))
        lacking = [g for g in ("parameters", "fluids", "snapshots", "series") if g not in f]
        if lacking:
            raise FileError('results file "%s" is damaged: %s missing'
                            % (self.path, ", ".join(lacking)))
        self.metadata = {key: _value(f.attrs[key]) for key in f.attrs}
        self.parameters = {key: _value(value) for key, value in f["parameters"].attrs.items()}
        fluids = f["fluids"]
        self.fluids = [(name, float(density), float(viscosity)) for name, density, viscosity in
                       zip(_text(fluids["name"][()]), fluids["density"][()],
                           fluids["kinematic_viscosity"][()])]
        self.scene_text = _text(f["scene_text"][()]) if "scene_text" in f else None
        self._names = sorted(f["snapshots"])
        groups = [f["snapshots"][name] for name in self._names]
        self.times = np.array([g.attrs["time"] for g in groups], dtype=np.float64)
        self.steps = np.array([g.attrs["step"] for g in groups], dtype=np.int64)
        self.series = {name: np.array(data[()], dtype=np.float64)
                       for name, data in f["series"].items()}

    def __len__(self):
        return len(self._names)

    def snapshot(self, k):
        """Snapshot k's time (float), step (int) and fields (numpy arrays)."""
        name = self._names[k]
        group = self._file["snapshots"][name]
        lacking = [a for a in ("time", "step") if a not in group.attrs] + \
                  [field for field in SNAPSHOT_FIELDS if field not in group]
        if lacking:
            raise FileError('results file "%s" is damaged: snapshot %s: %s missing'
                            % (self.path, name, ", ".join(lacking)))
        out = {"time": float(group.attrs["time"]), "step": int(group.attrs["step"])}
        for field in SNAPSHOT_FIELDS:
            out[field] = np.array(group[field][()])
        return out

    def snapshots(self):
        """Every snapshot in order, as snapshot(k) gives them."""
        for k in range(len(self)):
            yield self.snapshot(k)

    def close(self):
        """Closes the file; closing twice is fine."""
        self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def open_results(path):
    """Opens a results file written by Results or `mps2p run` (results.h5)
    for reading: a ResultsFile with str metadata and numpy arrays. Needs
    h5py. mps2p.NotResultsFileError (a FileError and a ValueError) for an
    HDF5 file that is not a results file, mps2p.FileError (an OSError) for a missing file (mps2p.MissingFileError,
    also a FileNotFoundError), one that is not HDF5, one that is damaged (a
    group or attribute of the format missing; snapshot(k) likewise) or one
    that cannot be read."""
    return ResultsFile(path)


__all__ = ["Results", "ResultsFile", "open_results", "SNAPSHOT_FIELDS"]
