#!/usr/bin/env bash
# Time per step and memory per particle of the water-only dam break from
# about 13,000 to 1,000,000 particles, for CG (two-level, Jacobi, IC(0)) and
# gamg (a build with PETSc), one l0 per process (so that each l0 has its own peak
# resident memory), then the plot (benchmarks/scale_plot.py).
# docs/performance.md, "Algebraic multigrid (PETSc GAMG)". About 10 minutes
# on the 2-core machine, most of it CG at 1,000,000 particles.
#   bash benchmarks/scale.sh [build-dir [out-dir [l0 ...]]]   (SCALE_PNG: the figure's path;
#   SCALE_SOLVERS: a subset of "two_level gamg ic0 jacobi")
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-release}
out=${2:-out/scale}
shift $(( $# > 2 ? 2 : $# ))
levels=${*:-0.014 0.007 0.0045 0.0025 0.0014}
mkdir -p "$out"
for solver in ${SCALE_SOLVERS:-two_level gamg ic0 jacobi}; do
    kind=cg
    [ "$solver" = gamg ] && kind=gamg
    for l0 in $levels; do
        MPS2P_PRECONDITIONER=$([ "$solver" = gamg ] && echo jacobi || echo "$solver") \
            nice -n 10 "$build/benchmarks/throughput" 5 "$kind" water "$l0" >"$out/$solver-$l0.md"
        grep '^| 0' "$out/$solver-$l0.md"
    done
done
python3 benchmarks/scale_plot.py "$out" "${SCALE_PNG:-docs/performance/scale_gamg.png}"
