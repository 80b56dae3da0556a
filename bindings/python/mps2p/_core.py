"""Turning C status codes into exceptions, and small conversions."""
import math

from . import errors
from ._native import ffi, lib


def check(status):
    """Raises the exception for a negative status; returns the status otherwise
    (0, or MPS2P_STOPPED)."""
    if status >= 0:
        return status
    message = ffi.string(lib.mps2p_last_error()).decode("utf-8", "replace")
    name = ffi.string(lib.mps2p_status_string(status)).decode()
    raise errors.BY_STATUS.get(status, errors.Error)(message or name, status, name)


def encode(text, what):
    if not isinstance(text, str):
        raise TypeError("%s must be a str, got %s" % (what, type(text).__name__))
    return text.encode("utf-8")


def real(value, what):
    """A float from a Python number; bools and strings are refused (the C side
    checks finiteness and range)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        try:
            import numpy
            if isinstance(value, numpy.floating) or isinstance(value, numpy.integer):
                return float(value)
        except ImportError:
            pass
        raise TypeError("%s must be a number, got %r" % (what, value))
    return float(value)


class Owned:
    """Owns one C handle, freed by close(), a `with` block, or garbage
    collection (ffi.gc with the C destroy function); a closed object refuses
    use with ValueError, and closing twice is fine."""

    _what = "handle"

    def _own(self, handle, destroy):
        self._handle = ffi.gc(handle, destroy)

    @property
    def handle(self):
        if self._handle is None:
            raise ValueError("the %s is closed" % self._what)
        return self._handle

    def close(self):
        if self._handle is not None:
            ffi.release(self._handle)
            self._handle = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def version():
    return ffi.string(lib.mps2p_version_string()).decode()


__all__ = ["check", "encode", "real", "version", "math"]
