#!/usr/bin/env bash
# The README's test command: every test, under AddressSanitizer and
# UndefinedBehaviorSanitizer, then the installed library as an outside
# program sees it (pkg-config, exported symbols) and the Python binding's
# tests against that installed library. Issue 7's reliability checks
# (scripts/test-reliability.sh) run in between. The pytest suite also
# installs the self-contained package into a fresh venv (pip install .,
# test_package.py) and opens results with ParaView and meshio
# (test_paraview.py). Both builds of option petsc are tested: the sanitizer
# builds leave PETSc out (its MPI's allocations would be reported as leaks;
# test_gamg then checks that gamg is refused, and is skipped), the release
# build has it (test_gamg, the binding's tests).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh

echo "== sanitizer build (address, undefined) and tests"
[ -d build-sanitize ] || meson setup build-sanitize -Db_sanitize=address,undefined \
    -Db_lundef=false --buildtype=debugoptimized -Dpetsc=disabled >/dev/null
meson configure build-sanitize -Dpetsc=disabled >/dev/null
ninja --quiet -C build-sanitize
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
log=$(mktemp)
meson test -C build-sanitize --suite fast --suite validation --print-errorlogs \
    --timeout-multiplier 3 | tee "$log"
passed=$(awk '/^Ok:/ {print $2}' "$log")
rm -f "$log"

echo "== reliability: allocation failure, kills, determinism, fuzzing, TSan, ABI (issue 7)"
rlog=$(mktemp)
bash scripts/test-reliability.sh | tee "$rlog"
rpassed=$(grep -oE '^reliability: [0-9]+ passed' "$rlog" | awk '{print $2}')
rm -f "$rlog"

echo "== release build, install, and an outside program"
prefix=$(mktemp -d)
# a developer's build-release gets its own prefix back at the end
if [ -d build-release ]; then
    own_prefix=$(meson introspect build-release --buildoptions | python3 -c \
        'import json, sys; print([o["value"] for o in json.load(sys.stdin) if o["name"] == "prefix"][0])')
    trap 'meson configure build-release --prefix="$own_prefix" >/dev/null' EXIT
else
    meson setup build-release --buildtype=release --prefix="$prefix" -Dpetsc=enabled >/dev/null
fi
meson configure build-release --prefix="$prefix" -Dpetsc=enabled >/dev/null
ninja --quiet -C build-release
meson install -C build-release --quiet >/dev/null
# pressure_solver gamg, with PETSc (the sanitizer build ran it without)
glog=$(mktemp)
meson test -C build-release --print-errorlogs test_gamg | tee "$glog"
gpassed=$(awk '/^Ok:/ {print $2}' "$glog")
rm -f "$glog"
# The two-phase tests are long (about 2 minutes): in the release build, once.
tlog=$(mktemp)
meson test -C build-release --suite two_phase --print-errorlogs | tee "$tlog"
tpassed=$(awk '/^Ok:/ {print $2}' "$tlog")
rm -f "$tlog"
libdir=$(dirname "$(find "$prefix" -name mps2p.pc | head -n1)")
export PKG_CONFIG_PATH="$libdir${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}"
out=$(mktemp -d)
"${CC:-gcc}" -std=c11 -Wall -Wextra -Werror tests/consumer/consumer.c -o "$out/consumer" \
    $(pkg-config --cflags --libs mps2p) -lm -Wl,-rpath,"$(pkg-config --variable=libdir mps2p)"
"$out/consumer"
# mps2p.h needs none of the library's dependencies: none in the .pc file (pkg-config
# resolves Requires.private for --cflags too: PETSc's absent .pc would fail it)
[ -z "$(pkg-config --print-requires-private mps2p)" ] ||
    { echo "mps2p.pc requires privately: $(pkg-config --print-requires-private mps2p)"; exit 1; }

echo "== Python binding, installed, against the installed library"
python3 -m pip install -q --disable-pip-version-check --root-user-action=ignore --no-deps \
    --target "$prefix/python" bindings/python >/dev/null
unset MPS2P_LIBRARY MPS2P_HEADER
pylog=$(mktemp)
PYTHONPATH="$prefix/python" MPS2P_EXAMPLES="$PWD/build-release/examples" \
    python3 -m pytest -q -p no:cacheprovider tests/python | tee "$pylog"
pypassed=$(grep -oE '[0-9]+ passed' "$pylog" | tail -n1 | awk '{print $1}')
rm -f "$pylog"
PYTHONPATH="$prefix/python" "$prefix/python/bin/mps2p" info >"$out/info.txt"
head -n2 "$out/info.txt"
# and from the build tree, as the main job uses it
MPS2P_LIBRARY="$PWD/build-release/lib/libmps2p.so.0" PYTHONPATH=bindings/python \
    python3 -c 'import mps2p; print("build tree:", mps2p.library_path)'

echo "== exported symbols"
so=$(find "$prefix" -name 'libmps2p.so.0' | head -n1)
objdump -p "$so" | grep -q 'SONAME *libmps2p.so.0' || { echo "SONAME is not libmps2p.so.0"; exit 1; }
foreign=$(nm -D --defined-only "$so" | awk '{print $3}' | grep -v '^mps2p_' || true)
if [ -n "$foreign" ]; then
    echo "exported symbols without the mps2p_ prefix:"; echo "$foreign"; exit 1
fi
echo "only mps2p_ symbols exported ($(nm -D --defined-only "$so" | wc -l) of them)"
rm -rf "$prefix" "$out"
# meson's tests, reliability's, pytest's, plus the outside-program and exported-symbol checks
echo "$((passed + rpassed + tpassed + gpassed + pypassed + 2)) passed, 0 failed"
