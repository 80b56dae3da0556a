"""Every C status code as a Python exception carrying the C message."""


class Error(Exception):
    """A libmps2p call failed. `status` is the C code (negative), `status_name`
    its name (e.g. "MPS2P_ERR_INVALID"), str(error) the library's message."""

    def __init__(self, message, status=None, status_name=None):
        super().__init__(message)
        self.status = status
        self.status_name = status_name


class NullArgumentError(Error, ValueError):
    """MPS2P_ERR_NULL: a required argument was missing."""


class InvalidArgumentError(Error, ValueError):
    """MPS2P_ERR_INVALID: an argument out of range or not finite."""


class UnknownKeyError(Error, LookupError):
    """MPS2P_ERR_UNKNOWN_KEY: no parameter, option or statistic of that name."""


class OutOfMemoryError(Error, MemoryError):
    """MPS2P_ERR_NOMEM."""


class StateError(Error, RuntimeError):
    """MPS2P_ERR_STATE: the call does not fit the handle's state (e.g. after divergence)."""


class BufferError_(Error):
    """MPS2P_ERR_BUFFER: a buffer was too short (a binding bug if it happens)."""


class SolveError(Error, RuntimeError):
    """MPS2P_ERR_SOLVE: the pressure solve failed; the solver keeps its last state."""


class DivergedError(Error, RuntimeError):
    """MPS2P_ERR_DIVERGED: the run blew up; the solver keeps its last good state."""


class FileError(Error, OSError):
    """MPS2P_ERR_IO: a file could not be read or written."""

    def __init__(self, message, status=None, status_name=None):
        Error.__init__(self, message, status, status_name)

    def __str__(self):
        return self.args[0]


class MissingFileError(FileError, FileNotFoundError):
    """A file to read is not there: a FileError that is also what open()
    raises for a missing file."""


class NotResultsFileError(FileError, ValueError):
    """An HDF5 file that is not a results file (a checkpoint, another
    program's): a FileError that is also the ValueError it used to be."""


class SceneFileError(Error, ValueError):
    """A scene file is wrong: the message names the file, the key and the reason."""


class SnapWarning(UserWarning):
    """A box is not on the l0 lattice. From Scene: a side that is not a whole
    number of l0 is filled with whole l0 x l0 cells, so the box holds less than
    asked (rounded down). From a scene file: a corner off the lattice from the
    origin is moved down onto it (the box may grow at its lower corner)."""


BY_STATUS = {
    -1: NullArgumentError,
    -2: InvalidArgumentError,
    -3: UnknownKeyError,
    -4: OutOfMemoryError,
    -5: StateError,
    -6: BufferError_,
    -7: SolveError,
    -8: DivergedError,
    -9: FileError,
}
