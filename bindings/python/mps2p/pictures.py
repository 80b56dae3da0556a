"""Pictures of a run (matplotlib, drawn from arrays the solver returned):
axes in metres, equal aspect, time in each title, a colour bar or legend."""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

REFERENCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data",
                         "martin_moyce_1952.csv")
PHASE_COLOURS = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"]


def snapshots_picture(path, snapshots, title, fluid_names, by="pressure"):
    """Particles of up to six snapshots: fluid coloured by pressure, or by phase."""
    if not snapshots:
        return
    fig, axes, lo, hi, pad = _panels(snapshots)
    fluid = [snap["kinds"] == 0 for snap in snapshots]
    pmax = max(float(np.percentile(snap["pressure"][f], 99)) if np.any(f) else 0.0
               for snap, f in zip(snapshots, fluid)) or 1.0
    scatter = None
    for ax, snap, is_fluid in zip(axes.flat, snapshots, fluid):
        t, xy, p, ids = snap["time"], snap["positions"], snap["pressure"], snap["fluid_ids"]
        ax.scatter(xy[~is_fluid, 0], xy[~is_fluid, 1], s=1.5, c="0.6", label="walls")
        if by == "pressure":
            scatter = ax.scatter(xy[is_fluid, 0], xy[is_fluid, 1], s=3, c=p[is_fluid],
                                 cmap="viridis", vmin=0, vmax=pmax)
        else:
            for k, name in enumerate(fluid_names):
                mine = is_fluid & (ids == k)
                ax.scatter(xy[mine, 0], xy[mine, 1], s=3, label=name,
                           c=PHASE_COLOURS[k % len(PHASE_COLOURS)])
        ax.set_aspect("equal")
        ax.set_xlim(lo[0] - pad, hi[0] + pad)
        ax.set_ylim(lo[1] - pad, hi[1] + pad)
        ax.set_title("t = %.3f s" % t)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    for ax in axes.flat[len(snapshots):]:
        ax.axis("off")
    if by == "pressure":
        fig.colorbar(scatter, ax=axes, label="pressure (Pa)", shrink=0.9)
    else:
        axes.flat[0].legend(loc="upper right", markerscale=3, fontsize=8)
    fig.suptitle(title)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def _panels(snapshots, width=4.2):
    """A grid of up to three columns framing the walls and the initial fluid
    (spray beyond is cut off): figure, axes, lower and upper corner, pad."""
    count = len(snapshots)
    columns = min(3, count)
    rows = (count + columns - 1) // columns
    xy0 = snapshots[0]["positions"]
    lo, hi = xy0.min(axis=0), xy0.max(axis=0)
    # with a light fluid filling the tank above the liquid, walls far above it
    # (headroom for the air) would only shrink the flow
    fluid = snapshots[0]["kinds"] == 0
    if np.unique(snapshots[0]["fluid_ids"][fluid]).size > 1:
        fluid_top = xy0[fluid, 1].max()
        hi[1] = min(hi[1], fluid_top + 0.1 * (fluid_top - lo[1]))
    pad = 0.03 * (hi - lo).max()
    aspect = (hi[1] - lo[1] + 2 * pad) / (hi[0] - lo[0] + 2 * pad)
    fig, axes = plt.subplots(rows, columns, figsize=(width * columns + 1.2,
                                                     width * aspect * rows + 0.8 * rows),
                             squeeze=False, layout="constrained")
    return fig, axes, lo, hi, pad


def velocity_picture(path, snapshots, title, fluid_names, fluid, stride=1):
    """One fluid's velocity as arrows (as the paper's figure 8 draws the air),
    the other fluids as dots, at each picture snapshot."""
    if not snapshots:
        return
    fig, axes, lo, hi, pad = _panels(snapshots)
    for ax, snap in zip(axes.flat, snapshots):
        xy, uv, kinds, ids = (snap["positions"], snap["velocities"], snap["kinds"],
                              snap["fluid_ids"])
        ax.scatter(xy[kinds != 0, 0], xy[kinds != 0, 1], s=1.5, c="0.6")
        for k, name in enumerate(fluid_names):
            if k != fluid:
                mine = (kinds == 0) & (ids == k)
                ax.scatter(xy[mine, 0], xy[mine, 1], s=3, label=name,
                           c=PHASE_COLOURS[k % len(PHASE_COLOURS)])
        mine = np.flatnonzero((kinds == 0) & (ids == fluid))[::stride]
        speed = np.hypot(uv[mine, 0], uv[mine, 1])
        quiver = ax.quiver(xy[mine, 0], xy[mine, 1], uv[mine, 0], uv[mine, 1], speed,
                           cmap="plasma", scale_units="xy", angles="xy",
                           scale=max(float(np.percentile(speed, 99)), 1e-9) / (0.03 * (hi - lo).max()),
                           width=0.002)
        ax.set_aspect("equal")
        ax.set_xlim(lo[0] - pad, hi[0] + pad)
        ax.set_ylim(lo[1] - pad, hi[1] + pad)
        ax.set_title("t = %.3f s" % snap["time"])
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        fig.colorbar(quiver, ax=ax, label="%s speed (m/s)" % fluid_names[fluid], shrink=0.8)
    for ax in axes.flat[len(snapshots):]:
        ax.axis("off")
    fig.suptitle("%s: %s velocity" % (title, fluid_names[fluid]))
    fig.savefig(path, dpi=100)
    plt.close(fig)


def zoom_picture(path, snap, particle, half_width, title, fluid_names, reason=""):
    """The neighbourhood of one particle (where a run diverged), particles by
    phase with velocity arrows, the particle circled (the paper's figure 3)."""
    xy, uv, kinds, ids = snap["positions"], snap["velocities"], snap["kinds"], snap["fluid_ids"]
    centre = xy[particle]
    near = np.all(np.abs(xy - centre) <= half_width, axis=1)
    fig, ax = plt.subplots(figsize=(6.5, 6), layout="constrained")
    ax.scatter(xy[near & (kinds != 0), 0], xy[near & (kinds != 0), 1], s=25, c="0.6",
               label="walls")
    for k, name in enumerate(fluid_names):
        mine = near & (kinds == 0) & (ids == k)
        colour = PHASE_COLOURS[k % len(PHASE_COLOURS)]
        ax.scatter(xy[mine, 0], xy[mine, 1], s=25, c=colour, label=name)
        ax.quiver(xy[mine, 0], xy[mine, 1], uv[mine, 0], uv[mine, 1], color=colour,
                  angles="xy", width=0.004)
    ax.scatter([centre[0]], [centre[1]], s=250, facecolors="none", edgecolors="red",
               label="particle %d" % particle)
    ax.set_aspect("equal")
    ax.set_xlim(centre[0] - half_width, centre[0] + half_width)
    ax.set_ylim(centre[1] - half_width, centre[1] + half_width)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.legend(loc="upper right", fontsize=8)
    wrapped = reason if len(reason) < 110 else reason[:107] + "..."
    ax.set_title("%s\nlast good state, t = %.4f s\n%s" % (title, snap["time"], wrapped),
                 fontsize=8)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def series_picture(path, names, rows):
    """Each probe against time."""
    data = np.array(rows, dtype=float)
    fig, axes = plt.subplots(len(names), 1, figsize=(7, 2.4 * len(names)), squeeze=False,
                             sharex=True, layout="constrained")
    for k, (ax, name) in enumerate(zip(axes.flat, names)):
        ax.plot(data[:, 0], data[:, 2 + k], "-")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
    axes.flat[-1].set_xlabel("time (s)")
    fig.savefig(path, dpi=100)
    plt.close(fig)


def martin_moyce():
    """{a_inch: (T, Z)} of Martin & Moyce (1952), n^2 = 2."""
    with open(REFERENCE) as f:
        lines = [line.strip() for line in f if line.strip() and not line.startswith("#")]
    assert lines[0] == "a_inch,T,Z", lines[0]
    data = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    return {a: (data[data[:, 0] == a, 1], data[data[:, 0] == a, 2])
            for a in np.unique(data[:, 0])}


def front_picture(path, front, column_width, title, g=9.81):
    """Surge front Z = z/a against T = t sqrt(2g/a), with Martin & Moyce."""
    t, z = front[:, 0], front[:, 1]
    keep = np.isfinite(z)
    T = t[keep] * np.sqrt(2 * g / column_width)
    fig, ax = plt.subplots(figsize=(6, 4.5), layout="constrained")
    ax.plot(T, z[keep] / column_width, "-", label="libmps2p")
    for (a_inch, (ref_T, ref_Z)), marker in zip(sorted(martin_moyce().items(), reverse=True),
                                               "osd^"):
        ax.plot(ref_T, ref_Z, marker, mfc="none", label="Martin & Moyce 1952, a = %g in" % a_inch)
    ax.set_xlabel("T = t sqrt(2g/a)")
    ax.set_ylabel("Z = z/a (surge front)")
    ax.set_xlim(0, min(4.0, T.max() if T.size else 4.0))
    ax.set_title("%s\nsurge front, a = %g m" % (title, column_width))
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(alpha=0.3)
    fig.savefig(path, dpi=120)
    plt.close(fig)
