#!/usr/bin/env bash
# The long fuzzing campaign (issue 20): every libFuzzer target for FUZZ_RUNS
# executions (default 1e7) or FUZZ_SECONDS seconds (default 12 hours),
# whichever comes first, all targets at once (one process each), then the
# inputs that add coverage merged into tests/fuzz/corpus (-merge=1) and each
# crash triaged as in CI (tests/fuzz/run_fuzzer.sh). Also the scene-file
# target (tests/fuzz/fuzz_scenefile.py, atheris) when atheris is installed.
# Needs build-fuzz (scripts/test-reliability.sh sets it up). Run with
#   FUZZ_RUNS=10000000 nice -n 15 bash scripts/fuzz-long.sh
# Each target's last line says its executions; the record of past campaigns
# is in docs/guarantees.md.
set -uo pipefail
cd "$(dirname "$0")/.."
runs=${FUZZ_RUNS:-10000000}
seconds=${FUZZ_SECONDS:-43200}
out=$(mktemp -d)
pids=()
for target in fuzz_scene fuzz_checkpoint fuzz_advance; do
    extra=()
    [ "$target" = fuzz_checkpoint ] && extra=(-max_len=32768)
    FUZZ_RUNS=$runs FUZZ_MERGE=1 bash tests/fuzz/run_fuzzer.sh build-fuzz "$target" "$seconds" \
        "${extra[@]}" >"$out/$target.log" 2>&1 &
    pids+=($!)
done
if python3 -c 'import atheris' 2>/dev/null; then
    FUZZ_MERGE=1 python3 tests/fuzz/fuzz_scenefile.py -runs="$runs" -max_total_time="$seconds" \
        >"$out/fuzz_scenefile.log" 2>&1 &
    pids+=($!)
else
    echo "fuzz_scenefile: atheris is not installed (python3 -m pip install atheris)" \
        >"$out/fuzz_scenefile.log"
fi
status=0
for pid in "${pids[@]}"; do
    wait "$pid" || status=1
done
for log in "$out"/*.log; do
    grep -vE '^ *(#|INFO|MERGE)' "$log" | tail -n 20
done
rm -rf "$out"
exit $status
