#!/usr/bin/env bash
# The README's main job: the paper's water-air dam break (docs/method.md
# section 4, examples/scenes/ikari2003_dam_break_air.toml, the improved
# two-phase model) to 3 s, through the Python binding and the mps2p command,
# into out/ikari2003_dam_break_air: results.h5 (+ .xdmf for ParaView),
# series.csv, summary.json, snapshots.png (pressure), snapshots_phase.png
# (water and air), velocity_air.png (the air's velocity arrows), series.png,
# front.png (against Martin & Moyce) and front_vs_water_only.png (the same
# column without air, run into out/dam_break, beside it). About 55 s on 2 cores
# once the dependencies are installed and the library built.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
[ -d build-release ] || meson setup build-release --buildtype=release >/dev/null
ninja --quiet -C build-release
export MPS2P_LIBRARY="$PWD/build-release/lib/libmps2p.so.0"
export PYTHONPATH="$PWD/bindings/python${PYTHONPATH:+:$PYTHONPATH}"
out=out/ikari2003_dam_break_air
# the cores idle as each run starts (--threads auto) unless MPS2P_THREADS says
# otherwise: on a machine other jobs share, more threads than free cores were
# 4-100 times slower; the results are the same bits for any thread count
threads=${MPS2P_THREADS:-auto}
python3 -m mps2p run examples/scenes/dam_break.toml --out out/dam_break --threads "$threads"
python3 -m mps2p run examples/scenes/ikari2003_dam_break_air.toml --out "$out" --threads "$threads"
python3 examples/compare_fronts.py "$out" out/dam_break "$out/front_vs_water_only.png"
