"""Loads libmps2p with cffi (ABI mode) and declares its public header.

The declarations are read from the `mps2p.h` paired with the library, so the
binding follows the header it is paired with and cannot drift from it by hand.

Where the library is looked for, in order:
  1. MPS2P_LIBRARY (a path), for a build tree or an unusual install;
  2. beside this module: the self-contained package (`pip install .` at the
     checkout's root) carries libmps2p.so.0 and mps2p.h in mps2p/;
  3. pkg-config's libdir for `mps2p` (a `meson install`ed library);
  4. the dynamic loader's search path (libmps2p.so.0).
The header: MPS2P_HEADER, else the one that belongs to the library found
(beside it; its prefix's include/; for a library in a Meson build tree, that
tree's source include/), else pkg-config's includedir, else this checkout's
include/ when the package runs from a checkout.
"""
import json
import os
import re
import shutil
import subprocess

import cffi

SONAME = "libmps2p.so.0"
HEADER = "mps2p.h"
_HERE = os.path.dirname(os.path.abspath(__file__))
_CHECKOUT_HEADER = os.path.normpath(os.path.join(_HERE, "..", "..", "..", "include", HEADER))
HOW_TO_INSTALL = (
    "install the self-contained package from the checkout's root (pip install .), "
    "or `meson install` the library and put the folder of its mps2p.pc (lib/pkgconfig, or "
    "lib/<multiarch>/pkgconfig on Debian) on PKG_CONFIG_PATH, "
    "or set MPS2P_LIBRARY to the library (and MPS2P_HEADER to its mps2p.h when it is "
    "not beside it, in its prefix's include/ or in a build tree's checkout; "
    "docs/python.md)")


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
    """The library's path, or its soname for the loader to search."""
    path = os.environ.get("MPS2P_LIBRARY")
    if path:
        if not os.path.exists(path):
            raise ImportError("MPS2P_LIBRARY=%s: no such file" % path)
        # a path, not a bare name, which the loader would look for elsewhere
        return os.path.abspath(path)
    bundled = os.path.join(_HERE, SONAME)
    if os.path.exists(bundled):
        return bundled
    libdir = _pkg_config("libdir")
    if libdir and os.path.exists(os.path.join(libdir, SONAME)):
        return os.path.join(libdir, SONAME)
    return SONAME


def _headers_beside(library_path):
    """Where the header of this library would be: beside it, in its prefix
    (lib/ or lib/<triplet>/ next to include/), or, in a Meson build tree, in
    the source tree the build was made from."""
    if os.sep not in library_path:
        return []
    folder = os.path.dirname(os.path.realpath(library_path))
    candidates = [os.path.join(folder, HEADER)]
    for up in (os.pardir, os.path.join(os.pardir, os.pardir)):
        candidates.append(os.path.normpath(os.path.join(folder, up, "include", HEADER)))
    probe = folder
    for _ in range(4):
        info = os.path.join(probe, "meson-info", "meson-info.json")
        if os.path.exists(info):
            try:
                with open(info) as f:
                    source = json.load(f)["directories"]["source"]
                candidates.append(os.path.join(source, "include", HEADER))
            except (OSError, ValueError, KeyError, TypeError):
                pass
            break
        probe = os.path.dirname(probe)
    return candidates


def find_header(library_path):
    path = os.environ.get("MPS2P_HEADER")
    if path:
        if not os.path.exists(path):
            raise ImportError("MPS2P_HEADER=%s: no such file" % path)
        return path
    candidates = _headers_beside(library_path)
    includedir = _pkg_config("includedir")
    if includedir:
        candidates.append(os.path.join(includedir, HEADER))
    candidates.append(_CHECKOUT_HEADER)
    for candidate in candidates:
        if os.path.exists(candidate):
            return candidate
    if os.sep not in library_path:  # find_library's last resort: the loader's search
        raise ImportError("libmps2p not found (not in the package, MPS2P_LIBRARY not set, "
                          "pkg-config does not know mps2p; the system's loader may know %s, "
                          "but its header mps2p.h is nowhere): %s" % (library_path,
                                                                       HOW_TO_INSTALL))
    raise ImportError("libmps2p's header mps2p.h not found (not beside %s, not through "
                      "pkg-config, not in a checkout): %s" % (library_path, HOW_TO_INSTALL))


def load():
    """(ffi, lib, library_path, header_path)."""
    library_path = find_library()
    header_path = find_header(library_path)
    with open(header_path) as f:
        header = f.read()
    ffi = cffi.FFI()
    ffi.cdef(cdef_from_header(header))
    try:
        lib = ffi.dlopen(library_path)
    except OSError as e:
        raise ImportError("cannot load %s: %s; %s" % (library_path, e, HOW_TO_INSTALL)) from e
    major, minor, _ = header_version(header)
    loaded = lib.mps2p_version_number()
    if loaded // 10000 != major or (loaded // 100) % 100 < minor:
        raise ImportError("%s is version %s but %s declares %d.%d: they do not belong together"
                          % (library_path, ffi.string(lib.mps2p_version_string()).decode(),
                             header_path, major, minor))
    return ffi, lib, library_path, header_path


ffi, lib, library_path, header_path = load()
