"""The plot and fits of benchmarks/scale.sh: reads OUT/{two_level,gamg,ic0,jacobi}-L0.md
(benchmarks/throughput's output, one l0 each), prints a Markdown table and
the fitted exponents, and draws time per step and memory per particle
against particles, log-log, with issue 18's bounds (N^1.2, 1 KiB).
    python3 benchmarks/scale_plot.py OUT PNG"""
import glob
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

LABELS = {"two_level": "cg, two_level", "gamg": "gamg (PETSc CG + GAMG)", "ic0": "cg, ic0",
          "jacobi": "cg, jacobi"}


def read(out, solver):
    rows = []
    for path in glob.glob(os.path.join(out, f"{solver}-*.md")):
        text = open(path).read()
        row = re.search(r"^\| ([0-9.]+) \| (\d+) \| ([0-9.]+) \| ([0-9.]+) \|.*\| (\d+) \|$",
                        text, re.M)
        rss = re.search(r"peak resident memory (\d+) bytes per particle; stages (.*)$", text,
                        re.M)
        if row and rss:
            rows.append({"l0": float(row.group(1)), "n": int(row.group(2)),
                         "ms": float(row.group(3)), "cpu_ms": float(row.group(4)),
                         "bytes": int(row.group(5)), "rss": int(rss.group(1)),
                         "stages": rss.group(2)})
    return sorted(rows, key=lambda r: r["n"])


def slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    return (sum((a - mx) * (b - my) for a, b in zip(lx, ly)) /
            sum((a - mx) ** 2 for a in lx))


def main():
    out, png = sys.argv[1], sys.argv[2]
    data = {s: read(out, s) for s in LABELS}
    print("| solver | l0 (m) | particles | ms per step | CPU ms per step | memory_bytes per "
          "particle | peak RSS per particle | slowest stages |")
    print("|---|---|---|---|---|---|---|---|")
    for s, rows in data.items():
        for r in rows:
            print(f"| {s} | {r['l0']:g} | {r['n']:,} | {r['ms']:.0f} | {r['cpu_ms']:.0f} | "
                  f"{r['bytes']} | {r['rss']} | {r['stages']} |")
    print()
    fig, (ax_t, ax_m) = plt.subplots(1, 2, figsize=(11, 4.5))
    for s, rows in data.items():
        if len(rows) < 2:
            continue
        n = [r["n"] for r in rows]
        wall, cpu = slope(n, [r["ms"] for r in rows]), slope(n, [r["cpu_ms"] for r in rows])
        print(f"{s}: time per step ~ N^{wall:.2f} (CPU N^{cpu:.2f}), {n[0]:,} to {n[-1]:,} "
              f"particles")
        line, = ax_t.loglog(n, [r["cpu_ms"] / 1e3 for r in rows], "o-",
                            label=f"{LABELS[s]}: CPU N^{cpu:.2f}")
        ax_t.loglog(n, [r["ms"] / 1e3 for r in rows], "x:", color=line.get_color())
        ax_m.semilogx(n, [r["bytes"] for r in rows], "o-", color=line.get_color(),
                      label=f"{LABELS[s]}: memory_bytes")
        ax_m.semilogx(n, [r["rss"] for r in rows], "x:", color=line.get_color(),
                      label=f"{LABELS[s]}: peak RSS")
    gamg = data["gamg"]
    if gamg:
        n0, t0 = gamg[0]["n"], gamg[0]["cpu_ms"] / 1e3
        ns = [n0, gamg[-1]["n"]]
        ax_t.loglog(ns, [t0 * (x / n0) ** 1.2 for x in ns], "k--", lw=1,
                    label="N^1.2 from gamg's first point (issue 18's bound)")
    ax_t.set_xlabel("particles N")
    ax_t.set_ylabel("seconds per step (o CPU, x wall)")
    ax_t.set_title("Water-only dam break: time per step")
    ax_t.grid(True, which="both", alpha=0.3)
    ax_t.legend(fontsize=7)
    ax_m.axhline(1024, color="k", ls="--", lw=1, label="1 KiB per particle (issue 18)")
    ax_m.set_ylim(0, 4000)
    ax_m.set_xlabel("particles N")
    ax_m.set_ylabel("bytes per particle")
    ax_m.set_title("Memory per particle (o memory_bytes, x peak RSS)")
    ax_m.grid(True, which="both", alpha=0.3)
    ax_m.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print(f"\nwrote {png}")


if __name__ == "__main__":
    main()
