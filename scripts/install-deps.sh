#!/usr/bin/env bash
# Installs what building and testing libmps2p needs on Debian bookworm (as root).
set -euo pipefail
packages="gcc g++ gfortran pkg-config ninja-build libgsl-dev libsuitesparse-dev libhdf5-dev binutils python3-pip python3-venv"
# scripts/test-reliability.sh: clang with libFuzzer and the sanitizer
# runtimes, and libabigail's abidw/abidiff.
packages="$packages clang libclang-rt-14-dev abigail-tools"
# tests/python/test_paraview.py: Debian's ParaView (pvbatch, the Xdmf3
# readers) and a virtual X server for its renderer, without recommends
# (212 packages, about a minute to install).
viewer="paraview python3-paraview xvfb xauth"
# pressure_solver gamg (meson option petsc): PETSc and the MPI headers its
# own headers include, without recommends (about 75 packages, half a minute).
viewer="$viewer libpetsc-real-dev mpi-default-dev"
missing=""
for p in $packages; do
    dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"
done
missing_viewer=""
for p in $viewer; do
    dpkg -s "$p" >/dev/null 2>&1 || missing_viewer="$missing_viewer $p"
done
if [ -n "$missing$missing_viewer" ]; then
    apt-get update -qq
fi
if [ -n "$missing" ]; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $missing >/dev/null
fi
if [ -n "$missing_viewer" ]; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
        $missing_viewer >/dev/null
fi
# A current Meson from PyPI; cffi, numpy and h5py for the Python binding,
# matplotlib for the pictures, tqdm for its progress bar, pytest for the
# binding's tests, hypothesis for the scene-file property tests, meshio for
# reading the results as another program does.
python_packages="meson>=1.1 cffi numpy h5py matplotlib tqdm pytest hypothesis meshio"
python3 -m pip install -q --disable-pip-version-check $python_packages 2>/dev/null ||
    python3 -m pip install -q --disable-pip-version-check --break-system-packages $python_packages
# atheris, for the scene-file fuzzer (tests/fuzz/fuzz_scenefile.py); where it
# does not install, scripts/test-reliability.sh says so and skips that target.
python3 -c 'import atheris' 2>/dev/null ||
    python3 -m pip install -q --disable-pip-version-check atheris 2>/dev/null ||
    python3 -m pip install -q --disable-pip-version-check --break-system-packages atheris \
        2>/dev/null || echo "install-deps: atheris did not install (scene-file fuzzing skipped)"
