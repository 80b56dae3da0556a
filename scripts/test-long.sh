#!/usr/bin/env bash
# The long suite (not part of scripts/test.sh; about an hour on 2 cores):
# 10 s of still water in the 0.3 m and 0.2 m tanks against issue 15's bars
# (meson suite "long"), then examples/validation.py's full runs (still water
# for both schemes, the dam break at four spacings, Buchner's impact pressure
# at H/l0 = 40 and 80, the stream turning up a wall, Buchner's stream alone)
# into out/validation, whose numbers docs/validation.md quotes, and the two-phase ladder's 10 s rung (MPS2P_LONG=1). The full
# accuracy-cost study is `mps2p study` (docs/accuracy-cost.md).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
[ -d build-release ] || meson setup build-release --buildtype=release >/dev/null
ninja --quiet -C build-release
meson test -C build-release --suite long --print-errorlogs
export MPS2P_LIBRARY="$PWD/build-release/lib/libmps2p.so.0"
export PYTHONPATH="$PWD/bindings/python${PYTHONPATH:+:$PYTHONPATH}"
python3 examples/validation.py all --out out/validation
# the two-phase ladder's tests (docs/two-phase.md), rung 1 for 10 s
MPS2P_LONG=1 MPS2P_HEADER="$PWD/include/mps2p.h" python3 -m pytest -q -p no:cacheprovider \
    tests/python/test_two_phase_ladder.py
