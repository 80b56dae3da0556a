#!/usr/bin/env bash
# The README's main job: the paper's dam break (water only until the
# two-phase model lands), run through the Python binding and the mps2p
# command, into out/dam_break: results.h5 (+ .xdmf for ParaView), series.csv,
# summary.json, snapshots.png, series.png and front.png (against Martin & Moyce).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
[ -d build-release ] || meson setup build-release --buildtype=release >/dev/null
ninja --quiet -C build-release
export MPS2P_LIBRARY="$PWD/build-release/lib/libmps2p.so.0"
export PYTHONPATH="$PWD/bindings/python${PYTHONPATH:+:$PYTHONPATH}"
out=out/dam_break
python3 -m mps2p run examples/scenes/dam_break.toml --out "$out"
