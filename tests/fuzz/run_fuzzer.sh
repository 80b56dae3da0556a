#!/usr/bin/env bash
# Runs one libFuzzer target for a bounded time and triages what it finds.
#   tests/fuzz/run_fuzzer.sh BUILD_DIR TARGET SECONDS [libFuzzer flags...]
# The corpus starts from tests/fuzz/corpus/<name> (copied to a scratch
# directory: the repository keeps only the small seed corpus). libFuzzer
# runs in fork mode and goes on after a crash; each crash input is then
# replayed alone and classified:
#   - its sanitizer report reaches libhdf5 before any libmps2p frame: an
#     HDF5 1.10.8 bug on a corrupt file (see tests/fuzz/hdf5-crashes), listed;
#   - otherwise (a libmps2p frame first, a report with no HDF5 frame, or a
#     replay that takes over 120 s): a libmps2p bug (or a harness that asks
#     for a valid but huge scene): the script fails, and the input belongs in
#     tests/fuzz/regressions/<name> with the fix;
#   - a crash, leak, out-of-memory or timeout that does not happen again
#     when replayed alone is listed, not failed: libmps2p keeps no state
#     between calls, HDF5 (caches, free lists) does.
# Prints "fuzz <target>: N executions in S s, H HDF5-internal crashes, B bugs".
# FUZZ_RUNS=N stops after N executions (else SECONDS alone bounds the run);
# FUZZ_MERGE=1 merges the inputs that add coverage into tests/fuzz/corpus
# (libFuzzer -merge=1: the corpus stays minimal); scripts/fuzz-long.sh.
set -uo pipefail
build=$1 target=$2 seconds=$3
shift 3
here=$(cd "$(dirname "$0")" && pwd)
name=${target#fuzz_}
binary="$build/tests/fuzz/$target"
replay="$build/tests/fuzz/${target}_replay"
work=$(mktemp -d)
mkdir -p "$work/corpus" "$work/artifacts"
cp "$here/corpus/$name"/* "$work/corpus/"
export ASAN_OPTIONS="allocator_may_return_null=1:detect_leaks=1:suppressions=$here/../sanitizers/asan.supp"
export LSAN_OPTIONS="suppressions=$here/../sanitizers/lsan.supp"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
log="$work/fuzz.log"
runs=()
[ -n "${FUZZ_RUNS:-}" ] && runs=("-runs=$FUZZ_RUNS")
"$binary" -fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 \
    -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -malloc_limit_mb=1000000 \
    -artifact_prefix="$work/artifacts/" "${runs[@]}" "$@" "$work/corpus" >"$log" 2>&1
if [ "${FUZZ_MERGE:-0}" = 1 ]; then
    "$binary" -merge=1 -timeout=20 -rss_limit_mb=2048 -malloc_limit_mb=1000000 "$@" \
        "$here/corpus/$name" "$work/corpus" >"$work/merge.log" 2>&1 ||
        { echo "fuzz $target: merging the corpus failed"; tail -n 5 "$work/merge.log"; }
fi
executions=$(grep -oE '^#[0-9]+' "$log" | tail -n1 | tr -d '#')
hdf5=0 bugs=0 other=0
for input in "$work/artifacts"/*; do
    [ -e "$input" ] || continue
    report=$(timeout 120 "$replay" "$input" 2>&1)
    status=$?
    first=$(printf '%s\n' "$report" | grep -E '^ *#[0-9]+ ' | grep -oE 'libhdf5|/lib/[a-z0-9_]+\.c|libmps2p' | head -n1)
    kind=$(basename "$input" | cut -d- -f1)
    if [ "$status" -eq 124 ]; then
        bugs=$((bugs + 1))
        echo "  BUG $kind $(basename "$input"): its replay alone takes over 120 s (copy it to $here/regressions/$name/)"
    elif [ "$status" -eq 0 ]; then
        other=$((other + 1)) # a crash, leak or out-of-memory only in the long-running process
        echo "  $kind $(basename "$input"): not reproducible alone (HDF5 keeps state between files)"
    elif [ "$first" = libhdf5 ]; then
        hdf5=$((hdf5 + 1))
        echo "  $kind $(basename "$input"): inside HDF5: $(printf '%s\n' "$report" | grep -E 'SUMMARY' | head -n1)"
    else
        bugs=$((bugs + 1))
        keep="$here/regressions/$name/$(basename "$input")"
        echo "  BUG $kind $(basename "$input") (copy it to $keep):"
        printf '%s\n' "$report" | grep -E 'ERROR|runtime error|SUMMARY|^ *#[0-9] ' | head -n 12
    fi
done
if [ -z "${executions:-}" ]; then
    echo "fuzz $target: did not run"; tail -n 20 "$log"; rm -rf "$work"; exit 1
fi
echo "fuzz $target: $executions executions in $seconds s, $hdf5 HDF5-internal crashes," \
     "$other not reproducible alone, $bugs libmps2p bugs"
rm -rf "$work"
[ "$bugs" -eq 0 ]
