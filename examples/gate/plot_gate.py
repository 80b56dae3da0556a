"""theta(t) and the moments on the gate from examples/gate's CSV.

    python3 examples/gate/plot_gate.py gate.csv [gate.png]
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "gate.csv"
    out = sys.argv[2] if len(sys.argv) > 2 else path.rsplit(".", 1)[0] + ".png"
    with open(path, newline="") as f:
        rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
    t = [r["t"] for r in rows]
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 6), layout="constrained")
    top.plot(t, [r["theta"] for r in rows], color="tab:blue")
    top.set_ylabel("theta (rad), from hanging")
    top.set_title("Hinged gate in a dam break")
    top.grid(alpha=0.3)
    bottom.plot(t, [r["moment_fluid"] for r in rows], label="water's pressure", color="tab:cyan",
                linewidth=0.8)
    bottom.plot(t, [r["moment_gravity"] for r in rows], label="gate's weight", color="tab:red")
    bottom.set_xlabel("t (s)")
    bottom.set_ylabel("moment about the hinge (N m/m)")
    bottom.legend()
    bottom.grid(alpha=0.3)
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()
