"""Pictures of a run (matplotlib, drawn from arrays the solver returned):
axes in metres with units, equal aspect, the time in each panel's title, a
title that fits the figure, a colour bar or legend, and each fluid told
apart from the others in every snapshot."""
import os
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from ..scene import KIND_DUMMY, KIND_WALL  # noqa: E402

REFERENCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data",
                         "martin_moyce_1952.csv")
PHASE_COLOURS = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"]
# Pressure colour maps by fluid id: the heaviest fluid first, so that water
# and air never share a colour scale.
PRESSURE_MAPS = ["viridis", "autumn", "cool", "spring", "winter"]
# Units of the solver's statistics (include/mps2p.h), for probe axes.
STAT_UNITS = {
    "max_speed": "m/s", "kinetic_energy": "J/m", "potential_energy": "J/m",
    "pressure_min": "Pa", "pressure_max": "Pa", "ppe_residual": "relative",
    "n0": "dimensionless", "lambda": "m^2", "dt_next": "s", "eddy_viscosity_max": "m^2/s",
    "memory_bytes": "bytes", "closest_pair": "l0", "gas_pressure_max": "Pa",
    "two_phase_active": "0 or 1", "ppe_unknowns": "unknowns", "gas_ppe_unknowns": "unknowns",
    "ppe_iterations": "iterations", "ppe_iterations_total": "iterations",
    "gas_ppe_iterations": "iterations", "neighbour_builds": "builds",
    "ppe_analyses": "analyses", "diverged_particle": "index", "fluid_out": "particles",
}
TITLE_SIZE = 11


def fit_title(text, width_inches, fontsize=TITLE_SIZE):
    """The text wrapped to lines that fit width_inches at fontsize points
    (an average glyph is about 0.55 em wide)."""
    columns = max(24, int(width_inches * 72 / (0.55 * fontsize)))
    return "\n".join(textwrap.fill(line, columns) for line in text.split("\n"))


def _suptitle(fig, text):
    fig.suptitle(fit_title(text, fig.get_figwidth() * 0.95), fontsize=TITLE_SIZE)


def _frame(ax, lo, hi, pad, t):
    ax.set_aspect("equal")
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_title("t = %.3f s" % t, fontsize=10)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def _solid(kinds):
    """Walls and dummies; not fluid that left the domain (KIND_OUT), which is
    not drawn: out of the run, it is outside the domain."""
    return (kinds == KIND_WALL) | (kinds == KIND_DUMMY)


def _walls(ax, xy, kinds):
    solid = _solid(kinds)
    return ax.scatter(xy[solid, 0], xy[solid, 1], s=1.5, c="0.6", label="walls")


def snapshots_picture(path, snapshots, title, fluid_names, by="pressure"):
    """Particles of the picture snapshots: each fluid coloured by its
    pressure on its own colour scale (by="pressure"), or each fluid in its
    own colour (by="phase"). Walls grey."""
    if not snapshots:
        return
    fig, axes, lo, hi, pad = _panels(snapshots)
    count = len(fluid_names)
    scales = []  # per fluid: upper pressure bound of its colour scale
    for k in range(count):
        highs = [float(np.percentile(s["pressure"][(s["kinds"] == 0) & (s["fluid_ids"] == k)],
                                     99))
                 for s in snapshots if np.any((s["kinds"] == 0) & (s["fluid_ids"] == k))]
        scales.append(max(highs) if highs and max(highs) > 0 else 1.0)
    mappables = [None] * count
    for ax, snap in zip(axes.flat, snapshots):
        xy, p, kinds, ids = snap["positions"], snap["pressure"], snap["kinds"], snap["fluid_ids"]
        _walls(ax, xy, kinds)
        for k, name in enumerate(fluid_names):
            mine = (kinds == 0) & (ids == k)
            # the first (heaviest in the examples) fluid as dots, the others as rings
            marker = "o" if k == 0 else "$\\circ$"
            if by == "pressure":
                mappables[k] = ax.scatter(xy[mine, 0], xy[mine, 1], s=4 if k == 0 else 9,
                                          c=p[mine], cmap=PRESSURE_MAPS[k % len(PRESSURE_MAPS)],
                                          vmin=0, vmax=scales[k], marker=marker,
                                          linewidths=0, label=name)
            else:
                ax.scatter(xy[mine, 0], xy[mine, 1], s=4, label=name,
                           c=PHASE_COLOURS[k % len(PHASE_COLOURS)])
        _frame(ax, lo, hi, pad, snap["time"])
    for ax in axes.flat[len(snapshots):]:
        ax.axis("off")
    if by == "pressure":
        for k, name in enumerate(fluid_names):
            if mappables[k] is not None:
                fig.colorbar(mappables[k], ax=axes, shrink=0.9 if count == 1 else 0.6,
                             label="%s pressure (Pa)" % name)
        if count > 1:
            axes.flat[0].legend(loc="upper right", markerscale=2.5, fontsize=8)
    else:
        axes.flat[0].legend(loc="upper right", markerscale=3, fontsize=8)
    _suptitle(fig, title + (": pressure" if by == "pressure" else ": fluids"))
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
    fig, axes = plt.subplots(rows, columns, figsize=(width * columns + 1.6,
                                                     width * aspect * rows + 0.8 * rows + 0.4),
                             squeeze=False, layout="constrained")
    return fig, axes, lo, hi, pad


def velocity_picture(path, snapshots, title, fluid_names, fluid, stride=1):
    """One fluid's velocity as arrows (as the paper's figure 8 draws the air),
    the other fluids as dots, at each picture snapshot."""
    if not snapshots:
        return
    fig, axes, lo, hi, pad = _panels(snapshots)

    def speeds(snap):
        mine = np.flatnonzero((snap["kinds"] == 0) & (snap["fluid_ids"] == fluid))[::stride]
        return np.hypot(snap["velocities"][mine, 0], snap["velocities"][mine, 1])

    # each panel on its own scale, but none below a hundredth of the largest:
    # a fluid at rest (t = 0) shows no arrows rather than its rounding noise
    tops = [float(np.percentile(v, 99)) if v.size else 0.0 for v in map(speeds, snapshots)]
    floor = max(0.01 * max(tops), 1e-9)
    for ax, snap, panel_top in zip(axes.flat, snapshots, tops):
        xy, uv, kinds, ids = (snap["positions"], snap["velocities"], snap["kinds"],
                              snap["fluid_ids"])
        _walls(ax, xy, kinds)
        for k, name in enumerate(fluid_names):
            if k != fluid:
                mine = (kinds == 0) & (ids == k)
                ax.scatter(xy[mine, 0], xy[mine, 1], s=3, label=name,
                           c=PHASE_COLOURS[k % len(PHASE_COLOURS)])
        mine = np.flatnonzero((kinds == 0) & (ids == fluid))[::stride]
        speed = np.hypot(uv[mine, 0], uv[mine, 1])
        top = max(panel_top, floor)
        quiver = ax.quiver(xy[mine, 0], xy[mine, 1], uv[mine, 0], uv[mine, 1], speed,
                           cmap="plasma", scale_units="xy", angles="xy",
                           scale=top / (0.03 * (hi - lo).max()), width=0.002,
                           clim=(0.0, top), label="%s velocity" % fluid_names[fluid])
        _frame(ax, lo, hi, pad, snap["time"])
        fig.colorbar(quiver, ax=ax, label="%s speed (m/s)" % fluid_names[fluid], shrink=0.8)
    axes.flat[0].legend(loc="upper right", markerscale=3, fontsize=8)
    for ax in axes.flat[len(snapshots):]:
        ax.axis("off")
    _suptitle(fig, "%s: %s velocity" % (title, fluid_names[fluid]))
    fig.savefig(path, dpi=100)
    plt.close(fig)


def zoom_picture(path, snap, particle, half_width, title, fluid_names, reason=""):
    """The neighbourhood of one particle (where a run diverged), particles by
    phase with velocity arrows, the particle circled (the paper's figure 3)."""
    xy, uv, kinds, ids = snap["positions"], snap["velocities"], snap["kinds"], snap["fluid_ids"]
    centre = xy[particle]
    near = np.all(np.abs(xy - centre) <= half_width, axis=1)
    fig, ax = plt.subplots(figsize=(6.5, 6.5), layout="constrained")
    ax.scatter(xy[near & _solid(kinds), 0], xy[near & _solid(kinds), 1], s=25, c="0.6",
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
    ax.set_title(fit_title("%s\nlast good state, t = %.4f s\n%s" % (title, snap["time"], reason),
                           6.3, 8), fontsize=8)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def probe_label(probe):
    """The y axis of a probe: what it measures and its unit."""
    kind = probe["type"]
    if kind == "pressure":
        return "%s\npressure at (%g, %g) m (Pa)" % (probe["name"], probe["at"][0],
                                                     probe["at"][1])
    if kind == "front":
        return "%s\nsurge front x (m)" % probe["name"]
    if kind == "elevation":
        return "%s\nsurface at x = %g m (m)" % (probe["name"], probe["x"])
    if kind == "count":
        return "%s\n%s particles" % (probe["name"], probe["fluid"])
    what = "%s (%s)" % (probe["stat"], STAT_UNITS.get(probe["stat"], "particles"))
    return what if probe["name"] == probe["stat"] else "%s\n%s" % (probe["name"], what)


def series_picture(path, probes, rows, title):
    """Each probe against time, one panel each, labelled with its unit."""
    data = np.array(rows, dtype=float)
    fig, axes = plt.subplots(len(probes), 1, figsize=(7.5, 2.3 * len(probes) + 0.7),
                             squeeze=False, sharex=True, layout="constrained")
    for k, (ax, probe) in enumerate(zip(axes.flat, probes)):
        ax.plot(data[:, 0], data[:, 2 + k], "-", lw=1.2)
        ax.set_ylabel(probe_label(probe), fontsize=9)
        ax.grid(alpha=0.3)
    axes.flat[-1].set_xlabel("time t (s)")
    _suptitle(fig, title + ": probes")
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


def _front_curve(front, column_width, origin, Z_wall, g, spacing):
    t, x = front[:, 0], front[:, 1]
    keep = np.isfinite(x)
    T = t[keep] * np.sqrt(2 * g / column_width)
    Z = (x[keep] - origin) / column_width
    if Z_wall is not None:
        # the water touches the wall with its front within a spacing of it (a
        # gap of a fraction of l0 stays): the first such sample ends the curve
        margin = spacing / column_width if spacing else 0.02
        reached = np.flatnonzero(Z >= Z_wall - margin)
        if reached.size:
            T, Z = T[:reached[0] + 1], Z[:reached[0] + 1]
    return T, Z


def front_picture(path, front, column_width, title, origin=0.0, wall=None, g=9.81,
                  label="libmps2p", others=(), spacing=None):
    """Surge front Z = (x - origin)/a against T = t sqrt(2g/a), with Martin &
    Moyce (1952) and the opposite wall at x = `wall` (m) as a line; the
    curve stops where the front reaches the wall (beyond, Z means nothing).
    others: (label, front) pairs drawn beside it (another run's front);
    spacing: l0, within which of the wall the front counts as arrived."""
    Z_wall = (wall - origin) / column_width if wall is not None else None
    T, Z = _front_curve(front, column_width, origin, Z_wall, g, spacing)
    fig, ax = plt.subplots(figsize=(6.5, 4.8), layout="constrained")
    ax.plot(T, Z, "-", lw=1.6, label=label)
    for other_label, other in others:
        other_T, other_Z = _front_curve(other, column_width, origin, Z_wall, g, spacing)
        ax.plot(other_T, other_Z, "--", lw=1.4, label=other_label)
    for (a_inch, (ref_T, ref_Z)), marker in zip(sorted(martin_moyce().items(), reverse=True),
                                               "osd^"):
        ax.plot(ref_T, ref_Z, marker, mfc="none", label="Martin & Moyce 1952, a = %g in"
                % a_inch)
    top = max(float(Z.max()) if Z.size else 1.0, Z_wall or 0.0)
    if Z_wall is not None:
        ax.axhline(Z_wall, color="0.3", lw=1.0, ls="--",
                   label="opposite wall, Z = %.3g" % Z_wall)
    T_end = float(T.max()) if T.size else 4.0
    ax.set_xlim(0, max(1.0, min(4.0, T_end + 0.3)))
    ax.set_ylim(min(0.8, float(Z.min()) - 0.1) if Z.size else 0.8, 1.1 * top)
    ax.set_xlabel("T = t sqrt(2g/a) (dimensionless time; t in s, a = %g m)" % column_width)
    ax.set_ylabel("Z = z/a (surge front, dimensionless)")
    ax.set_title(fit_title("%s\nsurge front against Martin & Moyce (1952), column width a = "
                           "%g m" % (title, column_width), 6.2), fontsize=TITLE_SIZE - 1)
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(alpha=0.3)
    fig.savefig(path, dpi=120)
    plt.close(fig)
