#!/usr/bin/env bash
# Installs what building and testing libmps2p needs on Debian bookworm (as root).
set -euo pipefail
packages="gcc g++ gfortran pkg-config ninja-build libgsl-dev libsuitesparse-dev libhdf5-dev binutils python3-pip"
# scripts/test-reliability.sh: clang with libFuzzer and the sanitizer
# runtimes, and libabigail's abidw/abidiff.
packages="$packages clang libclang-rt-14-dev abigail-tools"
missing=""
for p in $packages; do
    dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"
done
if [ -n "$missing" ]; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $missing >/dev/null
fi
# A current Meson from PyPI; cffi and numpy for the Python binding, matplotlib
# for the pictures, pytest and h5py for the binding's tests, hypothesis for
# the scene-file property tests.
python_packages="meson>=1.1 cffi numpy matplotlib pytest h5py hypothesis"
python3 -m pip install -q --disable-pip-version-check $python_packages 2>/dev/null ||
    python3 -m pip install -q --disable-pip-version-check --break-system-packages $python_packages
# atheris, for the scene-file fuzzer (tests/fuzz/fuzz_scenefile.py); where it
# does not install, scripts/test-reliability.sh says so and skips that target.
python3 -c 'import atheris' 2>/dev/null ||
    python3 -m pip install -q --disable-pip-version-check atheris 2>/dev/null ||
    python3 -m pip install -q --disable-pip-version-check --break-system-packages atheris \
        2>/dev/null || echo "install-deps: atheris did not install (scene-file fuzzing skipped)"
