"""Turning C status codes into exceptions, and checked conversions of
arguments: a value C cannot hold exactly is refused, never wrapped or
truncated."""
import os

import numpy as np

from . import errors
from ._native import ffi, lib

INT_MIN, INT_MAX = -2 ** 31, 2 ** 31 - 1


def check(status):
    """Raises the exception for a negative status; returns the status otherwise
    (0, or MPS2P_STOPPED)."""
    if status >= 0:
        return status
    message = ffi.string(lib.mps2p_last_error()).decode("utf-8", "replace")
    name = ffi.string(lib.mps2p_status_string(status)).decode()
    raise errors.BY_STATUS.get(status, errors.Error)(message or name, status, name)


def encode(text, what):
    """UTF-8 bytes of a str for a C string; NUL would cut it short, so it is refused."""
    if not isinstance(text, str):
        raise TypeError("%s must be a str, got %s" % (what, type(text).__name__))
    if "\0" in text:
        raise ValueError("%s must not contain NUL characters" % what)
    return text.encode("utf-8")


def encode_path(path, what="path"):
    """A file path (str, bytes or os.PathLike) as the bytes the OS uses."""
    if not isinstance(path, (str, bytes, os.PathLike)):
        raise TypeError("%s must be a str or os.PathLike, got %s" % (what, type(path).__name__))
    raw = os.fsencode(path)
    if not raw:
        raise ValueError("%s must not be empty" % what)
    if b"\0" in raw:
        raise ValueError("%s must not contain NUL characters" % what)
    return raw


def real(value, what):
    """A float from a Python or numpy number; bools and strings are refused
    (the C side checks finiteness and range)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer,
                                                                     np.floating)):
        raise TypeError("%s must be a number, got %r" % (what, value))
    try:
        return float(value)
    except OverflowError:
        raise ValueError("%s = %r does not fit a C double" % (what, value)) from None


def index(value, what):
    """A C int from a Python or numpy integer: 1.9, "0", True and values
    outside the C int range are refused."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise TypeError("%s must be an int, got %r" % (what, value))
    value = int(value)
    if not INT_MIN <= value <= INT_MAX:
        raise ValueError("%s = %d is out of range for a C int" % (what, value))
    return value


def int_array(values, n, what):
    """A (n,) C int array from integers; out-of-range values are refused."""
    array = np.asarray(values)
    if array.shape != (n,):
        raise ValueError("%s must have shape (%d,), got %s" % (what, n, array.shape))
    if array.size and not (np.issubdtype(array.dtype, np.integer)
                           and array.dtype != np.bool_):
        raise TypeError("%s must hold integers, got %s" % (what, array.dtype))
    if array.size and (array.min() < INT_MIN or array.max() > INT_MAX):
        bad = int(np.flatnonzero((array < INT_MIN) | (array > INT_MAX))[0])
        raise ValueError("%s[%d] = %d is out of range for a C int" % (what, bad, array[bad]))
    return np.ascontiguousarray(array, dtype=np.intc)


def real_array(values, shape, what):
    """A C double array of exactly `shape` (-1 for any length) from real numbers."""
    array = np.asarray(values)
    if array.size and not (np.issubdtype(array.dtype, np.integer)
                           or np.issubdtype(array.dtype, np.floating)) \
            or array.dtype == np.bool_:
        raise TypeError("%s must hold real numbers, got %s" % (what, array.dtype))
    if array.ndim != len(shape) or any(want not in (-1, got)
                                       for want, got in zip(shape, array.shape)):
        wanted = "(%s)" % ", ".join("n" if s == -1 else str(s) for s in shape)
        if len(shape) == 1:
            wanted = wanted[:-1] + ",)"
        raise ValueError("%s must have shape %s, got %s" % (what, wanted, array.shape))
    return np.ascontiguousarray(array, dtype=np.float64)


class Owned:
    """Owns one C handle, freed by close(), a `with` block, or garbage
    collection (ffi.gc with the C destroy function); a closed object refuses
    use with ValueError, and closing twice is fine."""

    _what = "handle"
    _handle = None

    def _own(self, handle, destroy):
        self._handle = ffi.gc(handle, destroy)

    @property
    def handle(self):
        """The C handle (a cffi pointer), for calls into `mps2p._native.lib`."""
        if self._handle is None:
            raise ValueError("the %s is closed" % self._what)
        return self._handle

    @property
    def closed(self):
        """True once close() was called."""
        return self._handle is None

    def close(self):
        """Frees the C handle now; later use raises ValueError."""
        if self._handle is not None:
            ffi.release(self._handle)
            self._handle = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def version():
    """The loaded library's version string (mps2p_version_string())."""
    return ffi.string(lib.mps2p_version_string()).decode()


__all__ = ["check", "encode", "encode_path", "real", "index", "int_array", "real_array",
           "version"]
