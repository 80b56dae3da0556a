"""The binding's tests run against whichever mps2p package Python finds (an
installed one, as scripts/test.sh does), else this checkout's
bindings/python; the package finds libmps2p through MPS2P_LIBRARY (a build
tree) or pkg-config (an installed library)."""
import importlib.util
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
SCENES = os.path.join(ROOT, "examples", "scenes")
if importlib.util.find_spec("mps2p") is None:
    sys.path.insert(0, os.path.join(ROOT, "bindings", "python"))
PACKAGE_DIR = os.path.dirname(os.path.dirname(importlib.util.find_spec("mps2p").origin))


def load_validation():
    """examples/validation.py as a module (it is a script, not a package)."""
    spec = importlib.util.spec_from_file_location(
        "validation", os.path.join(ROOT, "examples", "validation.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
