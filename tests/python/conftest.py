"""The binding's tests run against whichever libmps2p the package finds:
MPS2P_LIBRARY (a build tree) or the installed one (pkg-config); see
scripts/test.sh."""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "bindings", "python"))
SCENES = os.path.join(ROOT, "examples", "scenes")
