#!/usr/bin/env bash
# Installs what building and testing libmps2p needs on Debian bookworm (as root).
set -euo pipefail
packages="gcc pkg-config ninja-build libgsl-dev libsuitesparse-dev libhdf5-dev binutils python3-pip"
missing=""
for p in $packages; do
    dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"
done
if [ -n "$missing" ]; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $missing >/dev/null
fi
# A current Meson from PyPI; cffi and numpy for the Python binding, matplotlib
# for the pictures, pytest and h5py for the binding's tests.
python_packages="meson>=1.1 cffi numpy matplotlib pytest h5py"
python3 -m pip install -q --disable-pip-version-check $python_packages 2>/dev/null ||
    python3 -m pip install -q --disable-pip-version-check --break-system-packages $python_packages
