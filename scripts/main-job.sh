#!/usr/bin/env bash
# The README's main job: the paper's dam break (water only until the
# two-phase model lands), with the front and pictures, into out/dam_break.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
[ -d build-release ] || meson setup build-release --buildtype=release >/dev/null
ninja --quiet -C build-release
out=out/dam_break
mkdir -p "$out"
./build-release/examples/dam_break 0.01 0.6 "$out" | tee "$out/front.txt"
python3 examples/plot_dam_break.py "$out"
