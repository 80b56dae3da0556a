"""The dam break's surge front against Martin & Moyce (1952).

    python3 examples/plot_dam_break.py OUT_DIR

reads OUT_DIR/series.csv (from `mps2p run examples/scenes/dam_break.toml`,
its `front` probe) or else OUT_DIR/front.txt (from the C example
examples/dam_break.c), writes OUT_DIR/front.png and prints the front's error
against the a = 2.25 in series."""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
REFERENCE = os.path.join(HERE, "..", "data", "martin_moyce_1952.csv")


A = 0.15  # column width (m)
G = 9.81


def simulated_front(out):
    """Columns: t, T, Z."""
    series = os.path.join(out, "series.csv")
    if os.path.exists(series):
        d = np.genfromtxt(series, delimiter=",", names=True)
        t, z = d["time"], d["front"]
        keep = np.isfinite(z)
        return np.column_stack([t[keep], t[keep] * np.sqrt(2 * G / A), z[keep] / A])
    return np.loadtxt(os.path.join(out, "front.txt"), comments="#")


def plot_front(out):
    sim = simulated_front(out)
    rows = [line.split(",") for line in open(REFERENCE)
            if line.strip() and not line.startswith("#") and not line.startswith("a_inch")]
    ref = {name: np.array([float(r[k]) for r in rows])
           for k, name in enumerate(("a_inch", "T", "Z"))}
    fig, ax = plt.subplots(figsize=(6, 4.5))
    ax.plot(sim[:, 1], sim[:, 2], "-", label="libmps2p, water only, l0 = 0.01 m")
    for a_inch, marker in ((2.25, "o"), (1.125, "s")):
        sel = ref["a_inch"] == a_inch
        ax.plot(ref["T"][sel], ref["Z"][sel], marker, mfc="none",
                label=f"Martin & Moyce 1952, a = {a_inch} in")
    ax.axhline(4.0, color="gray", lw=0.8, ls=":", label="right wall (Z = 4)")
    ax.set_xlim(0, max(3.6, sim[-1, 1] if sim[-1, 1] < 4 else 3.6))
    ax.set_ylim(0.8, 4.5)
    ax.set_xlabel("T = t sqrt(2g/a)")
    ax.set_ylabel("Z = z/a (surge front)")
    ax.set_title("Dam break surge front, a = 0.15 m")
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "front.png"), dpi=120)
    plt.close(fig)
    sel = (ref["a_inch"] == 2.25) & (ref["T"] >= 1.0) & (ref["T"] <= 2.5)
    for T, Z in zip(ref["T"][sel], ref["Z"][sel]):
        z_sim = np.interp(T, sim[:, 1], sim[:, 2])
        print(f"T = {T:.3f}: Z = {z_sim:.3f} (Martin & Moyce {Z:.3f}, {100 * (z_sim - Z) / Z:+.1f} %)")


if __name__ == "__main__":
    out_dir = sys.argv[1] if len(sys.argv) > 1 else "out/dam_break"
    plot_front(out_dir)
    print(f"front picture written to {out_dir}/front.png")
