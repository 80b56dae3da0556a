#!/usr/bin/env bash
# ABI guard (issue 7): builds libmps2p (release, with debug info) in
# build-abi and compares its ABI with the stored abi/libmps2p.so.0.abi, the
# ABI of the released libmps2p.so.0, using libabigail's abidiff. Only types
# of the public header (include/) count: the handles are opaque, so their
# definitions in lib/ may change freely.
#   - additions (new functions, new enumerators at the end...) pass;
#   - anything abidiff calls incompatible (exit status bit 8,
#     ABIDIFF_ABI_INCOMPATIBLE_CHANGE), a removed function or variable, or a
#     changed one (parameter or return types, sizes) fails.
# abi/check.sh --update rewrites the stored file: only together with a
# SONAME bump (docs/guarantees.md).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${ABI_BUILD_DIR:-build-abi}
[ -d "$build" ] || meson setup "$build" --buildtype=release -Dc_args=-g >/dev/null
ninja --quiet -C "$build" lib/libmps2p.so.0.1.0 2>/dev/null || ninja --quiet -C "$build"
so=$(ls "$build"/lib/libmps2p.so.0.*.* | head -n1)
current=$(mktemp)
abidw --headers-dir include --no-corpus-path "$so" >"$current"
if [ "${1:-}" = --update ]; then
    cp "$current" abi/libmps2p.so.0.abi
    rm -f "$current"
    echo "abi: stored the ABI of $so"
    exit 0
fi
report=$(mktemp)
set +e
abidiff --headers-dir1 include --headers-dir2 include abi/libmps2p.so.0.abi "$current" >"$report" 2>&1
status=$?
set -e
removed=$(grep -oE '[0-9]+ Removed' "$report" | awk '{s += $1} END {print s + 0}' || true)
changed=$(grep -oE '[0-9]+ Changed' "$report" | awk '{s += $1} END {print s + 0}' || true)
added=$(grep -oE '[0-9]+ Added' "$report" | awk '{s += $1} END {print s + 0}' || true)
fail=0
if (( status & 1 )) || (( status & 2 )); then
    echo "abi: abidiff could not compare (exit status $status)"; fail=1
elif (( status & 8 )); then
    echo "abi: incompatible change (ABIDIFF_ABI_INCOMPATIBLE_CHANGE)"; fail=1
elif (( removed > 0 || changed > 0 )); then
    echo "abi: $removed removed, $changed changed functions or variables"; fail=1
fi
if (( fail )); then
    cat "$report"
    echo "abi: FAILED: a deliberate break must bump the SONAME (docs/guarantees.md)"
else
    echo "abi: compatible with abi/libmps2p.so.0.abi ($added added, 0 removed, 0 changed)"
fi
rm -f "$current" "$report"
exit "$fail"
