"""Loads libmps2p with cffi (ABI mode) and declares its public header.

The declarations are read from the installed `mps2p.h` itself, so the binding
follows the header it is paired with and cannot drift from it by hand.

Where the library and header are looked for, in order:
  1. MPS2P_LIBRARY / MPS2P_HEADER (paths), for a build tree or an unusual install;
  2. pkg-config's libdir and includedir for `mps2p`;
  3. the system's search path (libmps2p.so.0) and, for the header, this source
     tree's include/ when the package runs from a checkout.
"""
import os
import re
import shutil
import subprocess

import cffi

SONAME = "libmps2p.so.0"
_HERE = os.path.dirname(os.path.abspath(__file__))
_CHECKOUT_HEADER = os.path.normpath(os.path.join(_HERE, "..", "..", "..", "include", "mps2p.h"))


def cdef_from_header(text):
    """The header's declarations as cffi cdef source: no comments, no
    preprocessor lines, no C++ guards, no visibility macro."""
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    text = re.sub(r"#ifdef __cplusplus.*?#endif", " ", text, flags=re.S)
    lines = [line for line in text.splitlines() if not line.lstrip().startswith("#")]
    return re.sub(r"\bMPS2P_API\b", " ", "\n".join(lines))


def header_version(text):
    """(major, minor, patch) from the header's version macros."""
    parts = []
    for name in ("MAJOR", "MINOR", "PATCH"):
        match = re.search(r"#define\s+MPS2P_VERSION_%s\s+(\d+)" % name, text)
        if not match:
            raise ImportError("mps2p.h has no MPS2P_VERSION_%s" % name)
        parts.append(int(match.group(1)))
    return tuple(parts)


def _pkg_config(variable):
    if not shutil.which("pkg-config"):
        return None
    try:
        result = subprocess.run(["pkg-config", "--variable=" + variable, "mps2p"],
                                capture_output=True, text=True, check=True)
    except (OSError, subprocess.CalledProcessError):
        return None
    return result.stdout.strip() or None


def find_library():
    path = os.environ.get("MPS2P_LIBRARY")
    if path:
        if not os.path.exists(path):
            raise ImportError("MPS2P_LIBRARY=%s: no such file" % path)
        return path
    libdir = _pkg_config("libdir")
    if libdir and os.path.exists(os.path.join(libdir, SONAME)):
        return os.path.join(libdir, SONAME)
    return SONAME  # the dynamic loader's search path


def find_header():
    path = os.environ.get("MPS2P_HEADER")
    if path:
        if not os.path.exists(path):
            raise ImportError("MPS2P_HEADER=%s: no such file" % path)
        return path
    includedir = _pkg_config("includedir")
    if includedir and os.path.exists(os.path.join(includedir, "mps2p.h")):
        return os.path.join(includedir, "mps2p.h")
    if os.path.exists(_CHECKOUT_HEADER):
        return _CHECKOUT_HEADER
    raise ImportError("mps2p.h not found: install libmps2p (pkg-config mps2p) "
                      "or set MPS2P_HEADER")


def load():
    """(ffi, lib, library_path, header_path)."""
    header_path = find_header()
    with open(header_path) as f:
        header = f.read()
    ffi = cffi.FFI()
    ffi.cdef(cdef_from_header(header))
    library_path = find_library()
    try:
        lib = ffi.dlopen(library_path)
    except OSError as e:
        raise ImportError("cannot load %s: %s (set MPS2P_LIBRARY to the library's path)"
                          % (library_path, e)) from e
    major, minor, _ = header_version(header)
    loaded = lib.mps2p_version_number()
    if loaded // 10000 != major or (loaded // 100) % 100 < minor:
        raise ImportError("%s is version %s but %s declares %d.%d: they do not belong together"
                          % (library_path, ffi.string(lib.mps2p_version_string()).decode(),
                             header_path, major, minor))
    return ffi, lib, library_path, header_path


ffi, lib, library_path, header_path = load()
