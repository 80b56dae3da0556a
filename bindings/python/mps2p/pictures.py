"""Pictures of a run (matplotlib, drawn from arrays the solver returned)."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def snapshots_picture(path, snapshots, title):
    """Particles of up to six snapshots, fluid coloured by pressure."""
    if not snapshots:
        return
    count = len(snapshots)
    columns = min(3, count)
    rows = (count + columns - 1) // columns
    _, xy0, _, kind0 = snapshots[0]
    # The view: the walls and the initial fluid; spray beyond is cut off.
    lo, hi = xy0.min(axis=0), xy0.max(axis=0)
    pad = 0.03 * (hi - lo).max()
    aspect = (hi[1] - lo[1] + 2 * pad) / (hi[0] - lo[0] + 2 * pad)
    width = 4.2
    fig, axes = plt.subplots(rows, columns, figsize=(width * columns + 1.2,
                                                     width * aspect * rows + 0.8 * rows),
                             squeeze=False, layout="constrained")
    pmax = max(float(np.percentile(p[k == 0], 99)) if np.any(k == 0) else 0.0
               for _, _, p, k in snapshots) or 1.0
    for ax, (t, xy, p, kind) in zip(axes.flat, snapshots):
        solid = kind != 0
        ax.scatter(xy[solid, 0], xy[solid, 1], s=1.5, c="0.6")
        sc = ax.scatter(xy[~solid, 0], xy[~solid, 1], s=3, c=p[~solid], cmap="viridis",
                        vmin=0, vmax=pmax)
        ax.set_aspect("equal")
        ax.set_xlim(lo[0] - pad, hi[0] + pad)
        ax.set_ylim(lo[1] - pad, hi[1] + pad)
        ax.set_title("t = %.3f s" % t)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    for ax in axes.flat[count:]:
        ax.axis("off")
    fig.colorbar(sc, ax=axes, label="pressure (Pa)", shrink=0.9)
    fig.suptitle(title)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def series_picture(path, names, rows):
    """Each probe against time."""
    data = np.array(rows, dtype=float)
    fig, axes = plt.subplots(len(names), 1, figsize=(7, 2.4 * len(names)), squeeze=False,
                             sharex=True)
    for k, (ax, name) in enumerate(zip(axes.flat, names)):
        ax.plot(data[:, 0], data[:, 2 + k], "-")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
    axes.flat[-1].set_xlabel("time (s)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
