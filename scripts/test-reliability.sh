#!/usr/bin/env bash
# Issue 7's checks, for CI (after scripts/install-deps.sh): allocation
# failure, kills during checkpointing and determinism (plain build), the
# API contract and the fuzzers' inputs under clang's AddressSanitizer and
# UndefinedBehaviorSanitizer, the threads test under ThreadSanitizer, each
# libFuzzer target (and the atheris scene-file target) for a bounded time,
# the ABI guard, and the scene-file
# property tests. Under 10 minutes on 2 cores. What each check promises is in
# docs/guarantees.md. FUZZ_SECONDS (default 60) sets each fuzzer's time.
set -euo pipefail
cd "$(dirname "$0")/.."
fuzz_seconds=${FUZZ_SECONDS:-60}
passed=0 failed=0
log=$(mktemp)
count() { # adds meson test's Ok/Fail counts from $log
    local ok fail
    ok=$(awk '/^Ok:/ {print $2}' "$log"); fail=$(awk '/^Fail:/ {print $2}' "$log")
    passed=$((passed + ${ok:-0})); failed=$((failed + ${fail:-0}))
}
check() { # one named check: a command that passes or fails
    local name=$1; shift
    if "$@"; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAILED: $name"; fi
}
clang_cc=clang
command -v clang >/dev/null || clang_cc=clang-14

echo "== plain build: allocation failure (LD_PRELOAD), SIGKILL during checkpoints, determinism"
[ -d build-rel ] || meson setup build-rel --buildtype=debugoptimized >/dev/null
ninja --quiet -C build-rel
meson test -C build-rel --suite reliability --print-errorlogs | tee "$log" || true
count

echo "== clang AddressSanitizer + UndefinedBehaviorSanitizer: API errors, files, fuzz inputs"
# Without PETSc, as the other sanitizer builds (scripts/test.sh).
[ -d build-fuzz ] || CC=$clang_cc meson setup build-fuzz -Db_sanitize=address,undefined \
    -Db_lundef=false -Dc_args=-fsanitize=fuzzer-no-link --buildtype=debugoptimized \
    -Dpetsc=disabled >/dev/null
meson configure build-fuzz -Dpetsc=disabled >/dev/null
ninja --quiet -C build-fuzz
export ASAN_OPTIONS="detect_leaks=1:suppressions=$PWD/tests/sanitizers/asan.supp"
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizers/lsan.supp"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
meson test -C build-fuzz --print-errorlogs --timeout-multiplier 3 test_api_errors \
    test_checkpoint test_windows test_reentry test_limits fuzz_scene_replay \
    fuzz_checkpoint_replay fuzz_advance_replay | tee "$log" || true
count

echo "== ThreadSanitizer: two solvers and two files in two threads"
# Without OpenMP: libgomp is not built with TSan, whose reports on its
# barriers would be false (docs/guarantees.md).
# Without PETSc too: its gamg solves are serialised by a lock of libmps2p's
# (lib/numerics/gamg_solver.c), and OpenMPI is not built for TSan.
[ -d build-tsan ] || meson setup build-tsan -Db_sanitize=thread -Db_lundef=false \
    -Dopenmp=disabled -Dpetsc=disabled --buildtype=debugoptimized >/dev/null
meson configure build-tsan -Dopenmp=disabled -Dpetsc=disabled >/dev/null
ninja --quiet -C build-tsan tests/test_threads tests/reliability/test_determinism
TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" \
    meson test -C build-tsan --no-rebuild --print-errorlogs --timeout-multiplier 5 \
    test_threads test_determinism | tee "$log" || true
count

echo "== libFuzzer, ${fuzz_seconds} s per target"
check fuzz_scene bash tests/fuzz/run_fuzzer.sh build-fuzz fuzz_scene "$fuzz_seconds"
check fuzz_checkpoint bash tests/fuzz/run_fuzzer.sh build-fuzz fuzz_checkpoint \
    "$fuzz_seconds" -max_len=32768
check fuzz_advance bash tests/fuzz/run_fuzzer.sh build-fuzz fuzz_advance "$fuzz_seconds"
# Scene files through mps2p run's code path (Python, atheris), against build-rel's library.
if python3 -c 'import atheris' 2>/dev/null; then
    scenefile_fuzz() {
        local log
        log=$(mktemp)
        MPS2P_LIBRARY="$PWD/build-rel/lib/libmps2p.so.0" python3 tests/fuzz/fuzz_scenefile.py \
            -max_total_time="$fuzz_seconds" -timeout=20 -rss_limit_mb=2048 >"$log" 2>&1
        local status=$?
        local runs
        runs=$(grep -oE '^Done [0-9]+ runs' "$log" | awk '{print $2}')
        [ "$status" -eq 0 ] || tail -n 30 "$log"
        echo "fuzz fuzz_scenefile: ${runs:-0} executions in $fuzz_seconds s, exit $status"
        rm -f "$log"
        [ "$status" -eq 0 ] && [ -n "$runs" ]
    }
    check fuzz_scenefile scenefile_fuzz
else
    echo "fuzz_scenefile: atheris is not installed (scripts/install-deps.sh installs it): skipped"
fi

echo "== ABI against abi/libmps2p.so.0.abi"
check abi bash abi/check.sh

echo "== scene files: hypothesis"
set +e
MPS2P_LIBRARY="$PWD/build-rel/lib/libmps2p.so.0" PYTHONPATH=bindings/python \
    python3 -m pytest -q -p no:cacheprovider tests/python/test_scenefile_fuzz.py | tee "$log"
set -e
pyok=$(grep -oE '[0-9]+ passed' "$log" | tail -n1 | awk '{print $1}' || true)
pyfail=$(grep -oE '[0-9]+ (failed|error)' "$log" | awk '{s += $1} END {print s + 0}' || true)
passed=$((passed + ${pyok:-0})); failed=$((failed + ${pyfail:-0}))
[ -n "${pyok:-}" ] || { failed=$((failed + 1)); echo "FAILED: pytest did not run"; }
rm -f "$log"

echo "reliability: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
