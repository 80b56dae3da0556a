"""The validation page's figures (docs/validation.md): still water, the dam
break against Martin & Moyce (1952), the impact pressure against Buchner
(2002), a stream turning up a wall against free-streamline theory, and
Buchner's stream alone turning up the wall, for the default scheme and
Koshizuka and Oka's (scheme koshizuka1996).

    python3 examples/validation.py still|dam|shift|buchner|turning|stream|all [--quick] [--fine]
        [--pysph-python PY] [--out DIR]
    python3 examples/validation.py scatter [--settings JSON] [--quick] [--out DIR]
    python3 examples/validation.py buchner_air [--quick] [--out DIR]
    python3 examples/validation.py gate [--quick] [--out DIR]
    python3 examples/validation.py transplant --pysph-python PY [--quick] [--out DIR]
    python3 examples/validation.py sensors [--quick] [--fine] [--out DIR]
    python3 examples/validation.py tables [--out DIR]   # the JSONs as Markdown

Each case writes CSV series, a JSON summary and PNG pictures into DIR
(default out/validation). --quick runs shorter versions (still water 2 s,
Buchner at H/l0 = 40 only); --fine adds Buchner at H/l0 = 160; --pysph-python adds
PySPH's own Buchner example (its EDAC scheme, H/dx = 40) to the impact figure and table,
and PySPH's EDAC on Buchner's stream alone (at the stream's spacing and half of it).
scatter runs the violent cases again perturbed in cfl or dt (the default
scheme, or it with --settings changed) and adds their statistics' mean,
standard deviation and range to scatter.json. buchner_air runs Buchner's case
at H/l0 = 40 with air around the column (the paper's improved two-phase model)
and without, over the scatter's cfl values; gate releases the dam break's column
by a gate lifted at several speeds; sensors reads Buchner's P1 as other
particle codes read it (lower on the wall, or averaged down it) beside our
reading at the sensor. Reference data: data/ (cited in
data/README.md).
"""
import argparse
import csv
import json
import math
import os
import sys

import numpy as np

import mps2p

G = 9.81
RHO = 1000.0
SCHEMES = ("corrected", "koshizuka1996")
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "data")


def isolated_count(xy, spacing, radius=2.1):
    """Particles with no other particle within radius * spacing (a cell grid)."""
    reach = radius * spacing
    cells = {}
    keys = np.floor(xy / reach).astype(np.int64)
    for i, (cx, cy) in enumerate(map(tuple, keys)):
        cells.setdefault((cx, cy), []).append(i)
    alone = 0
    for i, (cx, cy) in enumerate(map(tuple, keys)):
        near = False
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for j in cells.get((cx + dx, cy + dy), ()):
                    if j != i and np.sum((xy[j] - xy[i]) ** 2) <= reach * reach:
                        near = True
                        break
                if near:
                    break
            if near:
                break
        alone += not near
    return alone


def noise_energy(xy, uv, spacing, radius=2.1):
    """Kinetic energy per unit mass of each particle's velocity about the mean
    of its neighbourhood (itself and every particle within radius * spacing),
    summed: the particle-scale part of the motion, what a scheme's noise is."""
    reach2 = (radius * spacing) ** 2
    total = 0.0
    for start in range(0, len(xy), 256):  # blocks of rows: memory stays small
        d2 = ((xy[start:start + 256, None, :] - xy[None, :, :]) ** 2).sum(-1)
        near = d2 <= reach2
        mean = near @ uv / near.sum(1)[:, None]
        total += 0.5 * ((uv[start:start + 256] - mean) ** 2).sum()
    return total


def write_csv(path, header, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)


# ---- still water -------------------------------------------------------------

def still_water(depth, scheme, end, l0=0.01):
    with mps2p.Scene(l0, scheme=scheme) as scene:
        water = scene.add_fluid("water", RHO, 1e-6)
        scene.add_fluid_box(water, 0.0, 0.0, depth + 1e-9, depth + 1e-9)
        scene.add_tank(0.0, 0.0, depth, depth + 0.1, open_top=True)
        # the pressure's zero: the water's top, half a spacing above the
        # free-surface row's centres (extrapolated), or those centres (centre)
        top_offset = 0.5 * l0 if scene.get_option("surface_pressure") == "extrapolated" else 0.0
        solver = mps2p.Solver(scene)
    fluid = solver.kinds() == mps2p.KIND_FLUID
    r0 = solver.positions()[fluid]
    bottom_row = r0[:, 1] < r0[:, 1].min() + 0.5 * l0
    expected = RHO * G * (r0[:, 1].max() - r0[:, 1].min() + top_offset)
    rows = []
    for k in range(1, int(round(end / 0.01)) + 1):
        t = 0.01 * k
        try:
            solver.advance_to(t)
        except mps2p.Error as e:
            rows.append((t, math.nan, math.nan, math.nan, math.nan))
            print("  %s, %.2f m: %s" % (scheme, depth, e))
            break
        u = solver.velocities()[fluid]
        r = solver.positions()[fluid]
        p = solver.pressure()[fluid][bottom_row]
        rows.append((t, math.sqrt((u ** 2).sum(1).mean()),
                     math.sqrt(((r - r0) ** 2).sum(1).mean()) / l0, p.mean(), p.std() / p.mean()))
    a = np.array(rows)
    after = a[a[:, 0] > 0.5]
    late = a[a[:, 0] >= 1.0]
    summary = {"depth": depth, "scheme": scheme, "end": float(a[-1, 0]),
               "rms_speed_max_after_0.5": float(np.nanmax(after[:, 1])) if len(after) else None,
               "rms_speed_bar": 0.005 * math.sqrt(G * depth),
               "displacement_end_l0": float(a[-1, 2]),
               "bottom_pressure_error": float(np.mean(late[:, 3]) / expected - 1) if len(late) else None,
               "bottom_spread_max": float(np.nanmax(late[:, 4])) if len(late) else None,
               "steps": solver.step_count}
    return rows, summary


def run_still(out, quick):
    end = 2.0 if quick else 10.0
    summaries, series = [], {}
    for depth in (0.3, 0.2):
        for scheme in SCHEMES:
            print("still water %.1f m, %s, %g s" % (depth, scheme, end))
            rows, s = still_water(depth, scheme, end)
            write_csv(os.path.join(out, "still_%g_%s.csv" % (depth, scheme)),
                      ["t", "rms_speed", "rms_displacement_l0", "bottom_pressure", "bottom_spread"],
                      rows)
            series[(depth, scheme)] = np.array(rows)
            summaries.append(s)
            print("  " + json.dumps(s))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    for (depth, scheme), a in series.items():
        style = "-" if scheme == "corrected" else "--"
        ax[0].semilogy(a[:, 0], a[:, 1], style, label="%s, %.1f m" % (scheme, depth))
        ax[1].semilogy(a[:, 0], np.maximum(a[:, 2], 1e-4), style, label="%s, %.1f m" % (scheme, depth))
    for depth in (0.3, 0.2):
        ax[0].axhline(0.005 * math.sqrt(G * depth), color="grey", lw=0.8, ls=":")
    ax[0].set_title("Still water: RMS speed of the water\n(dotted: 0.005 sqrt(g H) for each depth)")
    ax[0].set_xlabel("t (s)")
    ax[0].set_ylabel("RMS speed (m/s)")
    ax[1].axhline(0.1, color="grey", lw=0.8, ls=":")
    ax[1].set_title("RMS displacement from the start\n(dotted: 0.1 l0)")
    ax[1].set_xlabel("t (s)")
    ax[1].set_ylabel("RMS displacement (l0)")
    for a_ in ax:
        a_.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "still_water.png"), dpi=110)
    return summaries


# ---- dam break ---------------------------------------------------------------

def martin_moyce():
    rows = []
    with open(os.path.join(DATA, "martin_moyce_1952.csv")) as f:
        for line in f:
            if line[0].isdigit():
                a, T, Z = map(float, line.split(","))
                rows.append((a, T, Z))
    return np.array(rows)


def dam_break(scheme, l0=0.01, end=1.0, a=0.15, every=0.005, cfl=0.2, settings=None):
    with mps2p.Scene(l0, scheme=scheme, cfl=cfl) as scene:
        scene.set(**(settings or {}))
        water = scene.add_fluid("water", RHO, 1e-6)
        scene.add_fluid_box(water, 0.0, 0.0, a + 1e-9, 2 * a + 1e-9)
        scene.add_tank(0.0, 0.0, 0.6, 0.7, open_top=True)
        solver = mps2p.Solver(scene)
    fluid = solver.kinds() == mps2p.KIND_FLUID
    y = solver.positions()[fluid, 1]
    available = float(RHO * l0 * l0 * G * (y - y.min()).sum())
    potential0 = solver.stat("potential_energy")
    worst = [0.0, 0.0]

    def energy(s):
        excess = (s.stat("kinetic_energy") - (potential0 - s.stat("potential_energy"))) / available
        if excess > worst[0]:
            worst[:] = [excess, s.time]
        return False

    rows = []
    mass = RHO * l0 * l0
    for k in range(1, int(round(end / every)) + 1):
        solver.advance_to(k * every, progress=energy)
        xy, uv = solver.positions()[fluid], solver.velocities()[fluid]
        released = potential0 - solver.stat("potential_energy")
        rows.append((k * every, solver.front(water, below=0.02), isolated_count(xy, l0),
                     (solver.stat("kinetic_energy") - released) / available,
                     mass * noise_energy(xy, uv, l0) / available))
    arr = np.array(rows)
    T = arr[:, 0] * math.sqrt(2 * G / a)
    Z = arr[:, 1] / a
    points = []
    for series, Tm, Zm in martin_moyce():
        if Tm <= 2.5:
            Zs = float(np.interp(Tm, T, Z))
            points.append({"series_in": series, "T": Tm, "Z_mm": Zm, "Z": Zs, "error": Zs / Zm - 1})
    n = int(fluid.sum())
    summary = {"scheme": scheme, "l0": l0, "cfl": cfl, "front": points,
               "front_error_max": max(abs(p["error"]) for p in points),
               "isolated_max_fraction": float(arr[:, 2].max() / n),
               "isolated_max_at": float(arr[int(np.argmax(arr[:, 2])), 0]),
               "energy_excess_max": worst[0],
               # before the front reaches the right wall (first contact at T = 3.05;
               # T <= 2.8 also lies inside the cfl 0.1 and 0.05 runs at l0 = 0.005 m,
               # which end at T = 2.86): the
               # collapse and run-out alone, where an inviscid flow loses nothing
               "energy_balance_before_wall": float(arr[T <= 2.8, 3][-1]),
               "energy_balance_end": float(arr[-1, 3]),
               "noise_energy_max": float(arr[:, 4].max()),
               "noise_energy_max_before_wall": float(arr[T <= 2.8, 4].max()),
               "steps": solver.step_count, "water_particles": n}
    return rows, summary


def run_dam(out, quick):
    summaries, series, water = [], {}, {}
    # spacings that divide the 0.15 m column exactly; the front depends on dt as
    # much as on l0, hence the cfl sweep
    runs = [(s, 0.01, 0.2) for s in SCHEMES] + [("corrected", 0.015, 0.2)]
    if not quick:
        runs += [("corrected", 0.0075, 0.2), ("corrected", 0.005, 0.2),
                 ("corrected", 0.01, 0.1), ("corrected", 0.01, 0.05),
                 ("corrected", 0.005, 0.1), ("corrected", 0.005, 0.05)]
    for scheme, l0, cfl in runs:
        print("dam break, %s, l0 = %g m, cfl %g" % (scheme, l0, cfl))
        # the fine runs at cfl 0.2 to 1 s too (their spray), the finer cfl sweeps
        # to 0.25 s (T = 2.86, before the wall): the front is all they are for
        end = 1.0 if l0 >= 0.01 or cfl == 0.2 else 0.25
        rows, s = dam_break(scheme, l0, end, cfl=cfl)
        write_csv(os.path.join(out, "dam_%s_%g_cfl%g.csv" % (scheme, l0, cfl)),
                  ["t", "front", "isolated", "energy_balance", "noise_energy"], rows)
        series[(scheme, l0, cfl)] = np.array(rows)
        water[(scheme, l0, cfl)] = s["water_particles"]
        summaries.append(s)
        print("  front error max %.1f %%, isolated max %.1f %% at %.2f s, energy excess %.4f %%, "
              "balance before the wall %+.2f %%, at the end %+.2f %%, noise energy max %.2f %%"
              % (100 * s["front_error_max"], 100 * s["isolated_max_fraction"],
                 s["isolated_max_at"], 100 * s["energy_excess_max"],
                 100 * s["energy_balance_before_wall"], 100 * s["energy_balance_end"],
                 100 * s["noise_energy_max"]))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 3, figsize=(18, 4.5))
    mm = martin_moyce()
    for series_in, marker in ((2.25, "o"), (1.125, "s")):
        m = mm[(mm[:, 0] == series_in) & (mm[:, 1] <= 3.5)]
        ax[0].plot(m[:, 1], m[:, 2], "k" + marker, mfc="none",
                   label="Martin & Moyce, a = %g in" % series_in)
    a = 0.15
    for (scheme, l0, cfl), arr in series.items():
        if cfl != 0.2 and l0 != 0.01:
            continue
        T = arr[:, 0] * math.sqrt(2 * G / a)
        keep = T <= 3.5
        ax[0].plot(T[keep], arr[keep, 1] / a, label="%s, l0 = %g m, cfl %g" % (scheme, l0, cfl))
    ax[0].axhline(0.6 / a, color="grey", lw=0.8, ls=":")
    ax[0].set_xlabel("T = t sqrt(2 g / a)")
    ax[0].set_ylabel("Z = front / a")
    ax[0].set_title("Surge front (dotted: the right wall)")
    ax[0].legend(fontsize=8)
    for (scheme, l0, cfl), arr in series.items():
        if arr[-1, 0] > 0.5 and (l0 == 0.01 or cfl == 0.2):
            ax[1].plot(arr[:, 0], 100 * arr[:, 2] / water[(scheme, l0, cfl)],
                       label="%s, l0 = %g m, cfl %g" % (scheme, l0, cfl))
    ax[1].axhline(2.0, color="grey", lw=0.8, ls=":")
    ax[1].set_xlabel("t (s)")
    ax[1].set_ylabel("isolated particles (% of the water)")
    ax[1].set_title("No other water particle within 2.1 l0\n(dotted: 2 %)")
    ax[1].legend(fontsize=8)
    for (scheme, l0, cfl), arr in series.items():
        if l0 == 0.01 and cfl == 0.2:
            line, = ax[2].plot(arr[:, 0], 100 * arr[:, 3], label="%s: kinetic - released" % scheme)
            ax[2].plot(arr[:, 0], 100 * arr[:, 4], ls="--", color=line.get_color(),
                       label="%s: particle-scale (noise)" % scheme)
    ax[2].axvline(2.8 / math.sqrt(2 * G / a), color="grey", lw=0.8, ls=":")
    ax[2].set_xlabel("t (s)")
    ax[2].set_ylabel("% of the potential energy available")
    ax[2].set_title("Kinetic energy less the potential energy released, and its\n"
                    "particle-scale part (l0 = 0.01 m; dotted: T = 2.8, before the wall)")
    ax[2].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "dam_break.png"), dpi=110)
    return summaries


# ---- the front's lead as a time offset -----------------------------------------

def front_offset(scheme, l0, a=0.15, end_T=9.5, every_T=0.02):
    """The column in a tank 16 a long (no wall before Martin & Moyce's last
    point, Z = 14), its front Z(T) every every_T; then the one shift dT of the
    experiment's clock that fits Z_sim(T - dT) to their points best (least
    squares of the relative error), the error left, and the front's speed."""
    with mps2p.Scene(l0, scheme=scheme) as scene:
        water = scene.add_fluid("water", RHO, 1e-6)
        scene.add_fluid_box(water, 0.0, 0.0, a + 1e-9, 2 * a + 1e-9)
        scene.add_tank(0.0, 0.0, 16 * a + 1e-9, 2 * a + 0.2 + 1e-9, open_top=True)
        solver = mps2p.Solver(scene)
    scale = math.sqrt(a / (2 * G))
    T = np.arange(1, int(round(end_T / every_T)) + 1) * every_T
    Z = []
    for t in T:
        solver.advance_to(t * scale)
        Z.append(solver.front(water, below=0.02) / a)
    Z = np.array(Z)
    mm = martin_moyce()

    def errors(shift, chosen):
        return np.interp(mm[chosen, 1] - shift, T, Z) / mm[chosen, 2] - 1

    summary = {"scheme": scheme, "l0": l0, "steps": solver.step_count}
    shifts = np.arange(0.0, 0.6, 0.005)
    for name, chosen in (("early", mm[:, 1] <= 2.5), ("all", mm[:, 1] <= end_T)):
        rms = [float(np.sqrt(np.mean(errors(d, chosen) ** 2))) for d in shifts]
        best = float(shifts[int(np.argmin(rms))])
        unshifted, shifted = errors(0.0, chosen), errors(best, chosen)
        summary[name] = {"points": int(chosen.sum()), "max_unshifted": float(np.abs(unshifted).max()),
                         "shift": best, "rms_shifted": min(rms),
                         "max_shifted": float(np.abs(shifted).max())}
    for lo, hi in ((1.5, 2.5), (5.0, 9.0)):
        sim = (T >= lo) & (T <= hi)
        exp = (mm[:, 1] >= lo) & (mm[:, 1] <= hi)
        summary["speed_%g_%g" % (lo, hi)] = [float(np.polyfit(T[sim], Z[sim], 1)[0]),
                                             float(np.polyfit(mm[exp, 1], mm[exp, 2], 1)[0])]
    return summary


def gate_release(speed, l0=0.01, a=0.15, thickness=1, end_T=2.5, every_T=0.02):
    """The column released by a gate lifted at `speed` (m/s; 0: no gate, an
    instant release), a body `thickness` spacings thick against the column's
    right face: its front's relative error at Martin & Moyce's points with
    T <= end_T."""
    with mps2p.Scene(l0) as scene:
        water = scene.add_fluid("water", RHO, 1e-6)
        scene.add_fluid_box(water, 0.0, 0.0, a + 1e-9, 2 * a + 1e-9)
        scene.add_tank(0.0, 0.0, 0.6 + 1e-9, 0.7 + 1e-9, open_top=True)
        if speed > 0:
            gate = scene.add_body_box("gate", a + 1e-9, 0.0, a + thickness * l0 + 1e-9,
                                      2 * a + 0.05 + 1e-9)
        scene.set_domain(-0.2, -0.2, 0.8, 3.0)  # room for the gate above the tank
        solver = mps2p.Solver(scene)
    if speed > 0:
        solver.set_body_motion(gate, (0.0, speed))
    scale = math.sqrt(a / (2 * G))
    T = np.arange(1, int(round(end_T / every_T)) + 1) * every_T
    Z = []
    for t in T:
        solver.advance_to(t * scale)
        if speed > 0 and solver.time * speed > 2 * a + 0.1:  # clear of the water: stop it
            solver.set_body_motion(gate, (0.0, 0.0))
        Z.append(solver.front(water, below=0.02) / a)
    mm = martin_moyce()
    chosen = mm[:, 1] <= end_T
    errors = np.interp(mm[chosen, 1], T, np.array(Z)) / mm[chosen, 2] - 1
    return {"speed": speed, "l0": l0, "thickness": thickness, "T": mm[chosen, 1].tolist(),
            "errors": errors.tolist(), "max": float(np.abs(errors).max())}


def run_gate(out, quick):
    summaries = []
    for speed in (0.0, 0.3, 1.5, 3.0, 6.0) if not quick else (0.0, 3.0):
        s = gate_release(speed)
        print("gate lifted at %g m/s: %s" % (speed, json.dumps(s)))
        summaries.append(s)
    return summaries


def run_shift(out, quick):
    runs = [("corrected", 0.01)] + ([] if quick else [("corrected", 0.015), ("corrected", 0.005),
                                                      ("koshizuka1996", 0.01)])
    summaries = []
    for scheme, l0 in runs:
        s = front_offset(scheme, l0)
        print("front offset, %s, l0 = %g m: %s" % (scheme, l0, json.dumps(s)))
        summaries.append(s)
    return summaries


# ---- impact pressure (Buchner 2002) ------------------------------------------

def buchner_reference():
    out = {"P1": [], "P2": []}
    with open(os.path.join(DATA, "buchner_2002_dam_break_pressure.csv")) as f:
        for line in f:
            if line.startswith("P"):
                sensor, t, p = line.strip().split(",")
                out[sensor].append((float(t), float(p)))
    return {k: np.array(sorted(v)) for k, v in out.items()}


# Air around Buchner's column: the paper's improved two-phase model as its
# scene (examples/scenes/ikari2003_dam_break_air.toml) sets it, up to 2H.
AIR_SETTINGS = {"pressure_solver": "cg", "cg_preconditioner": "two_level",
                "two_phase_model": "two_step_improved", "interface_reaction": "drift",
                "gas_cg_tolerance": 1e-4}


def impact(scheme, per_height, H=0.6, end_star=7.0, every_star=0.01, settings=None, air=False,
           readings=()):
    """Buchner's dam break: column H high, 2H wide, tank 5.366 H long (to a
    whole number of spacings: 5.35 H at H/l0 = 40, 5.3625 H at 80). The
    sensors sit on the right wall at y = 0.16 m and 0.584 m; the probes read
    them half a spacing inside the water, as the probes average. With air,
    the tank holds air up to 2H around the column (AIR_SETTINGS). readings:
    lists of heights, each read as the mean of the probes there, added to
    each row after P1 and P2 (the sensors read as others read them)."""
    l0 = H / per_height
    # 5.366 H, to a whole number of spacings (tanks are built on the lattice)
    length = math.floor(5.366 * per_height) * l0
    with mps2p.Scene(l0, scheme=scheme) as scene:
        scene.set(**dict(AIR_SETTINGS if air else {}, **(settings or {})))
        water = scene.add_fluid("water", RHO, 1e-6)
        scene.add_fluid_box(water, 0.0, 0.0, 2 * H + 1e-9, H + 1e-9)
        if air:
            gas = scene.add_fluid("air", 1.2, 1.5e-5)
            scene.add_fluid_box(gas, 2 * H + 1e-9, 0.0, length + 1e-9, 2 * H + 1e-9)
            scene.add_fluid_box(gas, 0.0, H + 1e-9, 2 * H + 1e-9, 2 * H + 1e-9)
        scene.add_tank(0.0, 0.0, length + 1e-9, 3 * H + 1e-9, open_top=True)
        solver = mps2p.Solver(scene)
    scale_t, scale_p = math.sqrt(H / G), RHO * G * H
    points = [[length - 0.5 * l0, y] for y in [0.16, 0.584] + [y for r in readings for y in r]]
    rows, stopped = [], None
    for k in range(1, int(round(end_star / every_star)) + 1):
        try:
            solver.advance_to(k * every_star * scale_t)
        except mps2p.Error as e:
            print("  %s: %s" % (scheme, e))
            stopped = str(e)
            break
        p = solver.probe(points)[0] / scale_p
        at, extra = 2, []
        for heights in readings:
            extra.append(float(np.mean(p[at:at + len(heights)])))
            at += len(heights)
        rows.append((k * every_star, p[0], p[1], *extra))
    summary = impact_summary(scheme, per_height, np.array(rows))
    summary.update({"particles": solver.particle_count, "steps": solver.step_count,
                    "end_t": rows[-1][0] if rows else 0.0, "stopped": stopped})
    return rows, summary


def impact_summary(scheme, per_height, arr):
    """The statistics of a P1 series (rows of t*, P1, ...) against the
    experiment's: the first time above 0.1, the peak, the plateau over
    t* = 3-5, the RMS difference over t* = 2-7 and the noise (the RMS of the
    series less its 0.1 t* moving mean), for the runs of both codes alike."""
    ref = buchner_reference()["P1"]
    t, p1 = arr[:, 0], arr[:, 1]
    every_star = float(np.median(np.diff(t)))
    window = max(1, int(round(0.1 / every_star)))
    smooth = np.convolve(p1, np.ones(window) / window, mode="same")
    span = (t >= 2.0) & (t <= 7.0)
    above = np.flatnonzero(p1 > 0.1)
    ref_above = np.flatnonzero(ref[:, 1] > 0.1)
    inside = span & (t >= ref[0, 0]) & (t <= ref[-1, 0])
    summary = {"scheme": scheme, "H_over_l0": per_height,
               "impact_t": float(t[above[0]]) if len(above) else None,
               "impact_t_experiment": float(ref[ref_above[0], 0]),
               "peak": float(p1.max()), "peak_experiment": float(ref[:, 1].max()),
               "plateau_3_5": float(p1[(t >= 3) & (t <= 5)].mean()),
               "plateau_experiment": float(ref[(ref[:, 0] >= 3) & (ref[:, 0] <= 5), 1].mean()),
               "rms_difference_2_7": float(np.sqrt(np.mean(
                   (p1[inside] - np.interp(t[inside], ref[:, 0], ref[:, 1])) ** 2))),
               "noise_2_7": float(np.sqrt(np.mean((p1 - smooth)[span] ** 2)))}
    return summary


# Runs in PySPH's interpreter: P1 and P2 from every output file of its
# db_2d_buchner example (H = 1 there), read as its own post-processing reads
# its probe (Shepard interpolation over fluid and wall particles), at the
# sensors' heights and half a spacing inside the wall's face, as ours.
PYSPH_PROBE = r"""
import json, sys
import numpy as np
from pysph.solver.utils import get_files, iter_output, load
from pysph.tools.interpolator import Interpolator
files = get_files(sys.argv[1])
dx, heights = float(sys.argv[2]), [float(v) for v in sys.argv[3:]]
first = load(files[0])["arrays"]
bx, by = first["boundary"].get("x", "y")
fx = first["fluid"].get("x")
# the right wall's inner layer (its particles above the floor's layers, H = 1) less half a spacing
face = bx[(by > 0.5) & (bx > fx.max())].min() - 0.5 * dx
x = np.full(len(heights), face - 0.5 * dx)
rows, interp = [], None
for solver_data, fluid, boundary in iter_output(files, "fluid", "boundary"):
    if interp is None:
        interp = Interpolator([fluid, boundary], x=x, y=np.array(heights), method="shepard")
    else:
        interp.update_particle_arrays([fluid, boundary])
    rows.append([float(solver_data["t"])] + [float(v) for v in interp.interpolate("p")])
print(json.dumps({"rows": rows,
                  "particles": int(sum(a.get_number_of_particles() for a in (fluid, boundary)))}))
"""


# PySPH's db_2d_buchner example sets its particles' mass and smoothing
# length from its module's default spacing (dx = 0.03, H = 1) whatever --dx
# asks: at --dx 0.025 its water starts at a summation density of 1440, not
# 1000 (PySPH 1.0b2). Run as the example, with both set from the spacing
# asked: m = rho dx^2, h = hdx dx (its option, 1.3).
PYSPH_BUCHNER = r"""
import sys
from pysph.examples.dam_break import db_2d_buchner as example
class Consistent(example.DamBreak2DBuchner):
    def create_particles(self):
        arrays = super().create_particles()
        for pa in arrays:
            pa.m[:] = self.dx ** 2 * example.ro
            pa.h[:] = self.hdx * self.dx
        return arrays
sys.argv = ["db_2d_buchner"] + sys.argv[1:]
Consistent().run()
"""


def pysph_impact(out, python, per_height=40):
    """PySPH's own Buchner example (pysph.examples.dam_break.db_2d_buchner,
    H = 1 m, column 2H, tank 5.366 H, 4 wall layers; its EDAC scheme, the one
    of its schemes that runs this case to the end at H/dx = 40: its WCSPH and
    Adami-Hu-Adams schemes diverge before the impact) at H/dx = per_height,
    written every 0.01 t*; P1 and P2 read by PYSPH_PROBE. Its output files
    (about 300 MB at H/dx = 40) are deleted once read."""
    import shutil
    import subprocess
    H = 1.0  # the example's column height, fixed there
    dx = H / per_height
    # its dt: 0.125 h / c0, h = 1.3 dx, c0 = 10 sqrt(2 g H)
    dt = 0.125 * 1.3 * dx / (10.0 * math.sqrt(2 * G * H))
    pfreq = max(1, int(round(0.01 * math.sqrt(H / G) / dt)))
    work = os.path.join(out, "pysph_buchner_%d" % per_height)
    # the example ends with its own plot: without matplotlib it fails after the run
    try:
        needs = subprocess.run([python, "-c", "import pysph, matplotlib"], capture_output=True,
                               text=True)
        problem = needs.returncode and (needs.stderr.strip().splitlines() or
                                        ["exit status %d" % needs.returncode])[-1]
    except OSError as e:
        problem = str(e)
    if problem:
        sys.exit("validation.py: --pysph-python %s needs PySPH and matplotlib (its example "
                 "plots at the end): %s" % (python, problem))
    shutil.rmtree(work, ignore_errors=True)
    subprocess.run([python, "-c", PYSPH_BUCHNER, "--scheme", "edac",
                    "--dx", repr(dx), "--pfreq", str(pfreq), "-d", work],
                   check=True, stdout=subprocess.DEVNULL)
    probe = subprocess.run([python, "-c", PYSPH_PROBE, work, repr(dx), repr(0.16 / 0.6 * H),
                            repr(0.584 / 0.6 * H)], check=True, capture_output=True, text=True)
    read = json.loads(probe.stdout)
    for name in os.listdir(work):
        if name.endswith((".npz", ".hdf5")):
            os.remove(os.path.join(work, name))
    scale_t, scale_p = math.sqrt(G / H), RHO * G * H
    rows = [(t * scale_t, p1 / scale_p, p2 / scale_p) for t, p1, p2 in read["rows"]]
    rows = [r for r in rows if r[0] <= 7.0 + 1e-9]
    summary = impact_summary("PySPH edac", per_height, np.array(rows))
    summary.update({"particles": read["particles"], "steps": None})
    return rows, summary


def run_buchner(out, quick, fine=False, pysph_python=None):
    summaries, series = [], {}
    runs = [(s, 40) for s in SCHEMES] + ([] if quick else [("corrected", 80)])
    if fine:  # 58,504 particles, about 45 minutes on one core
        runs += ([("corrected", 80)] if quick else []) + [("corrected", 160)]
    for scheme, per_height in runs:
        print("impact pressure, %s, H/l0 = %d" % (scheme, per_height))
        rows, s = impact(scheme, per_height)
        write_csv(os.path.join(out, "buchner_%s_%d.csv" % (scheme, per_height)),
                  ["t_star", "p1_star", "p2_star"], rows)
        series[(scheme, per_height)] = np.array(rows)
        summaries.append(s)
        print("  " + json.dumps(s))
    if pysph_python:  # about 11 minutes on one core
        print("impact pressure, PySPH's db_2d_buchner (edac), H/dx = 40")
        rows, s = pysph_impact(out, pysph_python)
        write_csv(os.path.join(out, "buchner_pysph_edac_40.csv"),
                  ["t_star", "p1_star", "p2_star"], rows)
        series[("PySPH edac", 40)] = np.array(rows)
        summaries.append(s)
        print("  " + json.dumps(s))
    plot_buchner(out, series)
    return summaries


# Runs in PySPH's interpreter: the water of PySPH's run (its output folder)
# at its last output, as JSON (x, y, u, v; H = 1 there).
PYSPH_STATE = r"""
import json, sys
from pysph.solver.utils import get_files, load
fluid = load(get_files(sys.argv[1])[-1])["arrays"]["fluid"]
print(json.dumps({k: fluid.get(k).tolist() for k in ("x", "y", "u", "v")}))
"""

TRANSPLANT_AT = 2.4  # t*: PySPH's front meets the wall


def lattice_from(xy, uv, l0, length, height, hdx=1.3):
    """Water given as any particles (PySPH's) put on this library's lattice: a
    site is water where their volume fraction, sum l0^2 W(r, hdx l0) with
    PySPH's quintic spline, is at least a half; its velocity the mean of
    theirs within 1.5 l0, weighted 1 - r / (1.5 l0)."""
    h = hdx * l0
    bins = {}
    for k, (x, y) in enumerate(xy):
        bins.setdefault((int(x // l0), int(y // l0)), []).append(k)
    sites, velocities = [], []
    for i in range(int(round(length / l0))):
        for j in range(int(round(height / l0))):
            near = [k for a in range(-4, 5) for b in range(-4, 5) for k in bins.get((i + a, j + b), ())]
            if not near:
                continue
            near = np.array(near)
            x, y = (i + 0.5) * l0, (j + 0.5) * l0
            r = np.hypot(xy[near, 0] - x, xy[near, 1] - y)
            q = r / h
            w = (np.clip(3 - q, 0, None) ** 5 - 6 * np.clip(2 - q, 0, None) ** 5 +
                 15 * np.clip(1 - q, 0, None) ** 5) * 7.0 / (478.0 * math.pi * h * h)
            if (w * l0 * l0).sum() < 0.5:
                continue
            weight = np.clip(1.0 - r / (1.5 * l0), 0.0, None)
            sites.append((x, y))
            velocities.append((weight[:, None] * uv[near]).sum(0) / weight.sum())
    return np.array(sites), np.array(velocities)


def impact_from(xy, uv, start_star, settings=None, per_height=40, H=0.6, end_star=4.5):
    """Buchner's case (as impact()) from a given water state at t* = start_star;
    P1 and the pressure 0.1 m up the wall every 0.01 t*."""
    l0 = H / per_height
    length = math.floor(5.366 * per_height) * l0
    with mps2p.Scene(l0, scheme="corrected") as scene:
        scene.set(**(settings or {}))
        water = scene.add_fluid("water", RHO, 1e-6)
        n = len(xy)
        scene.add_particles(np.ascontiguousarray(xy), np.full(n, mps2p.KIND_FLUID, dtype=np.intc),
                            np.full(n, water, dtype=np.intc), np.ascontiguousarray(uv))
        scene.add_tank(0.0, 0.0, length + 1e-9, 3 * H + 1e-9, open_top=True)
        solver = mps2p.Solver(scene)
    scale_t, scale_p = math.sqrt(H / G), RHO * G * H
    points = [[length - 0.5 * l0, 0.16], [length - 0.5 * l0, 0.1]]
    rows, k = [], 1
    while start_star + k * 0.01 <= end_star + 1e-9:
        solver.advance_to(k * 0.01 * scale_t)
        rows.append((start_star + k * 0.01,) + tuple(solver.probe(points)[0] / scale_p))
        k += 1
    return np.array(rows)


def windows(rows, edges=(3.0, 3.5, 4.0, 4.5)):
    """Means of P1 and of the pressure 0.1 m up over each half unit of t*."""
    out = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        inside = (rows[:, 0] >= lo) & (rows[:, 0] < hi)
        out.append([float(rows[inside, 1].mean()), float(rows[inside, 2].mean())])
    return out


def run_transplant(out, quick, pysph_python=None):
    """Where Buchner's missing load is (docs/validation.md, "The same arriving
    flow in our scheme"): PySPH's corrected run (PYSPH_BUCHNER, H/dx = 40) to
    t* = 2.4, its water put on our lattice (lattice_from) and continued by
    our scheme, as shipped and with the damper at 0.9 l0; as a control, our
    own run's state at t* = 2.4 put on the lattice the same way; each over
    three runs perturbed in cfl. Needs --pysph-python (about 5 minutes)."""
    import shutil
    import subprocess
    if not pysph_python:
        sys.exit("validation.py transplant: needs --pysph-python PY, a Python with PySPH")
    H, per_height = 0.6, 40
    l0 = H / per_height
    length = math.floor(5.366 * per_height) * l0
    work = os.path.join(out, "pysph_buchner_to_%g" % TRANSPLANT_AT)
    shutil.rmtree(work, ignore_errors=True)
    dx = 1.0 / per_height  # H = 1 in PySPH's example
    try:
        subprocess.run([pysph_python, "-c", PYSPH_BUCHNER, "--scheme", "edac", "--dx", repr(dx),
                        "--tf", repr(TRANSPLANT_AT / math.sqrt(G)), "--pfreq", "1000000000",
                        "-d", work], check=True, stdout=subprocess.DEVNULL)
        state = json.loads(subprocess.run([pysph_python, "-c", PYSPH_STATE, work], check=True,
                                          capture_output=True, text=True).stdout)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    # its walls' inner layers at x = 0 and 5.375, y = 0: faces half a spacing in,
    # 5.35 H apart, our tank's 214 l0 at H = 0.6 m
    scale = H / 1.0
    xy = np.column_stack([(np.array(state["x"]) - 0.5 * dx) * scale,
                          (np.array(state["y"]) - 0.5 * dx) * scale])
    uv = np.column_stack([state["u"], state["v"]]) * math.sqrt(scale)
    theirs = lattice_from(xy, uv, l0, length, 3 * H)
    # ours to the same t*, put on the lattice the same way
    with mps2p.Scene(l0, scheme="corrected") as scene:
        water = scene.add_fluid("water", RHO, 1e-6)
        scene.add_fluid_box(water, 0.0, 0.0, 2 * H + 1e-9, H + 1e-9)
        scene.add_tank(0.0, 0.0, length + 1e-9, 3 * H + 1e-9, open_top=True)
        solver = mps2p.Solver(scene)
    solver.advance_to(TRANSPLANT_AT * math.sqrt(H / G))
    fluid = solver.kinds() == mps2p.KIND_FLUID
    ours = lattice_from(solver.positions()[fluid], solver.velocities()[fluid], l0, length, 3 * H)
    runs = [("PySPH's state", theirs, {}), ("PySPH's state, collision_distance 0.9", theirs,
                                             {"collision_distance": 0.9}),
            ("our state", ours, {})]
    # each a chaotic sample: three runs perturbed in cfl, their mean and spread
    summary = []
    for label, (sites, velocities), settings in runs[:1] if quick else runs:
        print("transplant: %s" % label)
        samples = np.array([windows(impact_from(sites, velocities, TRANSPLANT_AT,
                                                dict(settings, cfl=cfl)))
                            for cfl in SCATTER_CFL[:1 if quick else 3]])
        summary.append({"label": label, "sites": len(sites), "settings": settings,
                        "cfl": list(SCATTER_CFL[:len(samples)]),
                        "windows_t_star": [3.0, 3.5, 4.0, 4.5],
                        "P1_mean": samples[:, :, 0].mean(0).tolist(),
                        "P1_std": samples[:, :, 0].std(0).tolist(),
                        "at_0.1m_mean": samples[:, :, 1].mean(0).tolist()})
        print("  " + json.dumps(summary[-1]))
    return summary


# Buchner's P1 as the particle codes compared with read it: ours at the
# sensor (0.16 m); PySPH's and SPHinXsys's examples at 0.2 H; TrixiParticles'
# setups after Adami, Hu and Adams (2012), who follow Greco et al.: the
# numerical sensor's top at the experiment's sensor centre, the mean of 10
# points down 0.009 m (an earlier version) or 0.09 m (its Marrone et al. 2011
# setup). Each reading: (label, heights averaged).
SENSOR_READINGS = (
    ("at the sensor, 0.16 m (ours)", [0.16]),
    ("at 0.2 H = 0.12 m (PySPH, SPHinXsys)", [0.12]),
    ("mean of 0.151-0.16 m (TrixiParticles, 0.009 m sensor)", list(np.linspace(0.151, 0.16, 10))),
    ("mean of 0.07-0.16 m (TrixiParticles, 0.09 m sensor)", list(np.linspace(0.07, 0.16, 10))),
)


def run_sensors(out, quick, fine=False):
    """Buchner's P1 read as SENSOR_READINGS, the default scheme at H/l0 = 40
    over the scatter's first four cfl values and at 80 over its first two
    (--quick: 40 over two; --fine: and one run at 160, about 40 minutes more):
    each reading's impact time, plateau and noise, per run and as mean and
    standard deviation."""
    runs = [(40, cfl) for cfl in SCATTER_CFL[:2 if quick else 4]]
    runs += [] if quick else [(80, cfl) for cfl in SCATTER_CFL[:2]]
    runs += [(160, SCATTER_CFL[0])] if fine else []
    per_run = []
    for per_height, cfl in runs:
        print("impact pressure read as others read it, H/l0 = %d, cfl %g" % (per_height, cfl))
        rows, _ = impact("corrected", per_height, settings={"cfl": cfl},
                         readings=[heights for _, heights in SENSOR_READINGS])
        arr = np.array(rows)
        write_csv(os.path.join(out, "sensors_%d_cfl%g.csv" % (per_height, cfl)),
                  ["t_star", "p1_star", "p2_star"] + ["reading_%d" % k for k in
                                                      range(len(SENSOR_READINGS))], rows)
        for k, (label, _) in enumerate(SENSOR_READINGS):
            s = impact_summary("corrected", per_height, arr[:, [0, 3 + k]])
            s.update({"reading": label, "cfl": cfl})
            per_run.append(s)
            print("  %s: first > 0.1 at %s, plateau %.3f, noise %.3f"
                  % (label, s["impact_t"], s["plateau_3_5"], s["noise_2_7"]))
    summary = []
    for per_height in sorted({h for h, _ in runs}):
        for label, _ in SENSOR_READINGS:
            mine = [r for r in per_run if r["H_over_l0"] == per_height and r["reading"] == label]
            entry = {"H_over_l0": per_height, "reading": label, "runs": len(mine)}
            for key in ("impact_t", "plateau_3_5", "noise_2_7"):
                values = [r[key] for r in mine if r[key] is not None]
                entry[key] = [float(np.mean(values)), float(np.std(values)),
                              float(min(values)), float(max(values))] if values else None
            summary.append(entry)
    return {"runs": per_run, "summary": summary}


def run_buchner_air(out, quick):
    """Buchner's case at H/l0 = 40 with air around the column and without, at
    the scatter's cfl values (four; two with --quick): does the air the
    experiment had move the impact, the plateau or the noise?"""
    summaries, series = [], {}
    for cfl in SCATTER_CFL[:2 if quick else 4]:
        for air in (False, True):
            label = "%s, cfl %g" % ("with air" if air else "water only", cfl)
            print("impact pressure, H/l0 = 40, %s" % label)
            rows, s = impact("corrected", 40, settings={"cfl": cfl}, air=air)
            write_csv(os.path.join(out, "buchner_%s_cfl%g.csv" % ("air" if air else "water", cfl)),
                      ["t_star", "p1_star", "p2_star"], rows)
            series[(label, 40)] = np.array(rows)
            s.update({"air": air, "cfl": cfl})
            summaries.append(s)
            print("  " + json.dumps(s))
    plot_buchner_air(out, series)
    return summaries


def plot_buchner_air(out, series):
    """buchner_air.png: P1 of the runs with air and without, each run thin,
    each set's 0.1 t* moving mean averaged over its runs bold, against the
    experiment's."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ref = buchner_reference()["P1"]
    fig, ax = plt.subplots(figsize=(10, 4.5))
    grid = np.arange(1, 701) * 0.01
    for air, colour in ((False, "tab:blue"), (True, "tab:orange")):
        means = []
        for (label, _), arr in series.items():
            if label.startswith("with air") != air:
                continue
            ax.plot(arr[:, 0], arr[:, 1], lw=0.3, color=colour, alpha=0.35)
            # the moving mean where its whole window lies inside the run
            kernel = np.ones(10) / 10
            mean = np.convolve(arr[:, 1], kernel, mode="valid")
            at = np.convolve(arr[:, 0], kernel, mode="valid")
            means.append(np.interp(grid, at, mean, left=np.nan, right=np.nan))
        if means:  # their mean where every run of the set has one (NaN elsewhere)
            ax.plot(grid, np.mean(np.array(means), axis=0), lw=2, color=colour,
                    label="%s: %d runs over cfl (thin), their 0.1 t* moving mean (bold)"
                    % ("with air" if air else "water only", len(means)))
    ax.plot(ref[:, 0], ref[:, 1], "ko", ms=3, label="Buchner (2002)")
    ax.set_xlim(1.5, 7.0)
    ax.set_ylim(-0.1, 1.6)
    ax.set_xlabel("t sqrt(g / H)")
    ax.set_ylabel("P1: p / (rho g H)")
    ax.set_title("Buchner's case at H/l0 = 40, with air around the column and without")
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "buchner_air.png"), dpi=110)


def plot_buchner(out, series):
    """buchner.png: the series {(scheme, H/l0): rows of t*, P1, P2} against
    the experiment's."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ref = buchner_reference()
    fig, ax = plt.subplots(2, 1, figsize=(10, 7), sharex=True)
    for k, sensor in enumerate(("P1", "P2")):
        for (scheme, per_height), arr in series.items():
            if scheme.startswith("PySPH"):  # its noise hides the rest: its 0.1 t* mean drawn over it
                mean = np.convolve(arr[:, 1 + k], np.ones(10) / 10, mode="same")
                ax[k].plot(arr[:, 0], arr[:, 1 + k], lw=0.4, color="0.8", zorder=1)
                ax[k].plot(arr[:, 0], mean, "--", lw=1.2, color="0.3", zorder=3,
                           label="%s, H/dx = %d (grey; dashed: its 0.1 t* moving mean)"
                           % (scheme, per_height))
                continue
            ax[k].plot(arr[:, 0], arr[:, 1 + k], lw=0.7, zorder=2,
                       label="%s, H/l0 = %d" % (scheme, per_height))
        ax[k].plot(ref[sensor][:, 0], ref[sensor][:, 1], "ko", ms=3, label="Buchner (2002)")
        ax[k].set_ylabel("%s: p / (rho g H)" % sensor)
        ax[k].set_ylim(-0.1, 1.6)
        ax[k].legend(fontsize=8, loc="upper left")
    ax[0].set_title("Impact pressure on the right wall (P1 at y = 0.16 m, P2 at 0.584 m)")
    ax[1].set_xlabel("t sqrt(g / H)")
    ax[1].set_xlim(1.5, 7.0)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "buchner.png"), dpi=110)


def turning_theory(y, h):
    """Wall pressure over rho U^2 / 2 at height y where a stream of depth h
    along a floor turns up a wall, without gravity: the free-streamline
    solution (the symmetric half of a jet 2h wide meeting a plate), on the
    wall y = (4h/pi)(artanh q + arctan q), q the speed over U, and
    p = rho (U^2 - q^2 U^2) / 2. Its integral over the wall is rho U^2 h."""
    lo, hi = 0.0, 1.0
    for _ in range(100):  # bisection: y(q) rises monotonically from 0 to infinity
        q = 0.5 * (lo + hi)
        if 4 * h / math.pi * (math.atanh(q) + math.atan(q)) < y:
            lo = q
        else:
            hi = q
    q = 0.5 * (lo + hi)
    return 1.0 - q * q


TURNING_HEIGHTS = (0.25, 0.5, 1.0, 1.5, 2.0, 3.0)  # over the stream's depth


def turning_stream(label, settings, l0=0.01, h=0.1, U=1.0, length=2.0, end=1.25, every=0.005,
                   picture_at=0.9, heights=TURNING_HEIGHTS):
    """A slab of water h deep and `length` long moving at U along the floor,
    without gravity, into the right wall 0.1 m ahead of it: wall pressure
    (probes half a spacing inside the water, as Buchner's) averaged from the
    time the turn has formed (2 h / U after contact) to `end`, against
    turning_theory; the wall's force from probes every l0 up to 6 h, over
    rho U^2 h; the sheet's speed and fluid per height between 4 and 6 h."""
    x0, gap = 0.1, 0.1
    wall = x0 + length + gap
    with mps2p.Scene(l0) as scene:
        scene.set(**{"gravity_y": 0.0, "dt": 5e-4, **settings})
        water = scene.add_fluid("water", RHO, 1e-6)
        xs = x0 + l0 * (np.arange(int(round(length / l0))) + 0.5)
        ys = l0 * (np.arange(int(round(h / l0))) + 0.5)
        grid = np.array(np.meshgrid(xs, ys, indexing="ij")).reshape(2, -1).T
        velocity = np.zeros_like(grid)
        velocity[:, 0] = U
        scene.add_particles(grid, np.full(len(grid), mps2p.KIND_FLUID, dtype=np.intc),
                            np.full(len(grid), water, dtype=np.intc), velocity)
        scene.add_tank(0.0, 0.0, wall + 1e-9, U * end + 1.0, open_top=True)
        solver = mps2p.Solver(scene)
    probes = [[wall - 0.5 * l0, f * h] for f in heights]
    column = [[wall - 0.5 * l0, l0 * (k + 0.5)] for k in range(int(round(6 * h / l0)))]
    stagnation = 0.5 * RHO * U * U
    fluid = solver.kinds() == mps2p.KIND_FLUID
    start = gap / U + 2 * h / U
    rows, force, sheet, picture = [], [], [], None
    for k in range(1, int(round(end / every)) + 1):
        solver.advance_to(k * every)
        rows.append([solver.time] + list(solver.probe(probes)[0] / stagnation))
        if picture is None and solver.time >= picture_at - 1e-9:
            picture = (solver.time, solver.positions() - [wall, 0.0],
                       solver.pressure() / stagnation, solver.kinds())
        if solver.time < start:
            continue
        force.append(solver.probe(column)[0].sum() * l0 / (RHO * U * U * h))
        r, u = solver.positions()[fluid], solver.velocities()[fluid]
        band = (r[:, 1] > 4 * h) & (r[:, 1] < 6 * h)
        if band.any():
            sheet.append((u[band, 1].mean() / U, band.sum() * l0 * l0 / (2 * h) / h))
    arr = np.array(rows)
    steady = arr[:, 0] >= start
    sheet = np.array(sheet)
    return arr, {"label": label, "settings": settings, "l0": l0, "h": h, "U": U,
                 "window": [start, float(arr[-1, 0])], "heights_over_h": list(heights),
                 "p_mean": [float(v) for v in arr[steady, 1:].mean(axis=0)],
                 "p_std": [float(v) for v in arr[steady, 1:].std(axis=0)],
                 "p_theory": [turning_theory(f * h, h) for f in heights],
                 "force": float(np.mean(force)),
                 "sheet_speed": float(sheet[:, 0].mean()), "sheet_fluid": float(sheet[:, 1].mean()),
                 "steps": solver.step_count}, picture


def run_turning(out, quick):
    runs = [("corrected", {}), ("koshizuka1996", {"scheme": "koshizuka1996"}),
            ("corrected, collision 0.95 l0", {"collision_distance": 0.95})]
    if quick:
        runs = runs[:1]
    summaries = []
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 1 + len(runs), figsize=(6 + 3.2 * len(runs), 5.5),
                             gridspec_kw={"width_ratios": [2] + [1] * len(runs)})
    axes = np.atleast_1d(axes)
    ax = axes[0]
    fine = np.linspace(0.02, 4.0, 200)
    ax.plot([turning_theory(f, 1.0) for f in fine], fine, "k-", label="free-streamline theory")
    for n, (label, settings) in enumerate(runs):
        print("turning stream, %s" % label)
        rows, s, picture = turning_stream(label, settings)
        slug = label.replace(", ", "_").replace(" ", "_").replace(".", "")
        write_csv(os.path.join(out, "turning_%s.csv" % slug),
                  ["t"] + ["p_%gh" % f for f in TURNING_HEIGHTS], rows)
        summaries.append(s)
        offset = 0.04 * (n - 1)  # the bars side by side
        ax.errorbar(s["p_mean"], np.array(TURNING_HEIGHTS) + offset, xerr=s["p_std"], fmt="o-",
                    capsize=2, lw=1, label="%s (force %.2f rho U^2 h)" % (label, s["force"]))
        t, r, p, kind = picture
        fluid = kind == mps2p.KIND_FLUID
        shown = axes[1 + n].scatter(r[fluid, 0], r[fluid, 1], c=p[fluid], s=4, cmap="viridis",
                                    vmin=0.0, vmax=1.5)
        solid = (kind == mps2p.KIND_WALL) | (kind == mps2p.KIND_DUMMY)  # not fluid out of the run
        axes[1 + n].scatter(r[solid, 0], r[solid, 1], c="0.6", s=1)
        axes[1 + n].set_xlim(-0.45, 0.04)
        axes[1 + n].set_ylim(-0.04, 0.9)
        axes[1 + n].set_aspect("equal")
        axes[1 + n].set_title("%s, t = %.2f s" % (label, t), fontsize=8)
        print("  " + json.dumps(s))
    ax.set_xlabel("wall pressure / (rho U^2 / 2), mean and standard deviation")
    ax.set_ylabel("height on the wall / stream depth h")
    ax.set_xlim(-0.1, 1.9)
    ax.set_title("A stream turning up a wall (no gravity, h = 10 l0)")
    ax.legend(fontsize=7)
    fig.colorbar(shown, ax=axes[1:], label="p / (rho U^2 / 2)", shrink=0.8)
    fig.savefig(os.path.join(out, "turning.png"), dpi=110)
    return summaries


# Buchner's stream where it meets the wall at t* = 4 (Ritter's solution 2.02 m
# from the gate: 0.0896 m deep at 2.98 m/s), with gravity, at H/l0 = 40; P1 at
# 0.16 m is 1.78 of its depth. 2.02 m of slab puts the wall on the lattice.
STREAM = {"l0": 0.015, "h": 0.0896, "U": 2.98, "length": 2.02, "end": 0.75, "every": 0.0025,
          "picture_at": 0.5, "heights": (0.25, 0.5, 1.0, 0.16 / 0.0896, 2.0, 3.0)}


# Runs in PySPH's interpreter: Buchner's stream alone (STREAM) in PySPH's EDAC
# scheme as its db_2d_buchner example sets it (quintic spline, h = 1.3 dx,
# c0 ten times sqrt(2 g H) at H = 0.6 m, dt = 0.125 h / c0, pressure clamped at
# 0), 4 wall layers, written every `every` s; then the wall's pressure read as
# PYSPH_PROBE reads Buchner's (Shepard over fluid and walls, half a spacing
# inside the wall's face) at the heights and up a column every dx to 6 h.
PYSPH_STREAM = r"""
import json, math, sys
import numpy as np
from pysph.base.kernels import QuinticSpline
from pysph.base.utils import get_particle_array
from pysph.solver.application import Application
from pysph.solver.utils import get_files, iter_output
from pysph.sph.wc.edac import EDACScheme
from pysph.tools.interpolator import Interpolator
c = json.loads(sys.argv[1])
dx, h, U, length, end, every = c["dx"], c["h"], c["U"], c["length"], c["end"], c["every"]
x0 = gap = 0.1
wall, rho, g, hdx, layers = x0 + length + gap, 1000.0, 9.81, 1.3, 4
c0 = 10.0 * math.sqrt(2 * g * 0.6)
class Stream(Application):
    def create_scheme(self):
        return EDACScheme(fluids=["fluid"], solids=["boundary"], dim=2, c0=c0, nu=0.0,
                          rho0=rho, h=hdx * dx, pb=0.0, gy=-g, eps=0.0, clamp_p=True)
    def configure_scheme(self):
        times = [k * every for k in range(1, int(round(end / every)) + 1)]
        self.scheme.configure_solver(kernel=QuinticSpline(dim=2), dt=0.125 * hdx * dx / c0,
                                     tf=end, output_at_times=times, pfreq=10 ** 9)
    def create_particles(self):
        xf, yf = np.meshgrid(x0 + dx * (np.arange(int(round(length / dx))) + 0.5),
                             dx * (np.arange(int(round(h / dx))) + 0.5), indexing="ij")
        side = dx * (np.arange(int(round((U * end + 1.0) / dx))) + 0.5)
        floor = -layers * dx + dx * (np.arange(int(round(wall / dx)) + 2 * layers) + 0.5)
        xs = np.concatenate([np.concatenate([np.full(len(side), -(j + 0.5) * dx),
                                             np.full(len(side), wall + (j + 0.5) * dx), floor])
                             for j in range(layers)])
        ys = np.concatenate([np.concatenate([side, side, np.full(len(floor), -(j + 0.5) * dx)])
                             for j in range(layers)])
        m = rho * dx * dx
        fluid = get_particle_array(name="fluid", x=xf.ravel(), y=yf.ravel(), h=hdx * dx, m=m,
                                   rho=rho)
        boundary = get_particle_array(name="boundary", x=xs, y=ys, h=hdx * dx, m=m, rho=rho)
        self.scheme.setup_properties([fluid, boundary])
        fluid.u[:] = U
        return [fluid, boundary]
Stream().run(["-d", c["work"]])
heights = [f * h for f in c["heights"]] + [dx * (k + 0.5) for k in range(int(round(6 * h / dx)))]
x = np.full(len(heights), wall - 0.5 * dx)
rows, interp = [], None
for solver_data, fluid, boundary in iter_output(get_files(c["work"]), "fluid", "boundary"):
    if interp is None:
        interp = Interpolator([fluid, boundary], x=x, y=np.array(heights), method="shepard")
    else:
        interp.update_particle_arrays([fluid, boundary])
    rows.append([float(solver_data["t"])] + [float(v) for v in interp.interpolate("p")])
print(json.dumps({"rows": rows}))
"""


def pysph_stream(out, python, l0):
    """Buchner's stream alone in PySPH (PYSPH_STREAM) at spacing l0: its wall
    pressure's statistics as turning_stream gives ours. Output files deleted."""
    import shutil
    import subprocess
    work = os.path.join(out, "pysph_stream_%g" % l0)
    shutil.rmtree(work, ignore_errors=True)
    config = dict(STREAM, dx=l0, work=work)
    config.pop("l0")
    config.pop("picture_at")
    try:
        done = subprocess.run([python, "-c", PYSPH_STREAM, json.dumps(config)],
                              capture_output=True, text=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    if done.returncode != 0:
        sys.exit("validation.py: PySPH's stream with --pysph-python %s failed:\n%s"
                 % (python, done.stderr.strip()[-2000:]))
    rows = np.array(json.loads(done.stdout.strip().splitlines()[-1])["rows"])
    h, U = STREAM["h"], STREAM["U"]
    heights = STREAM["heights"]
    steady = rows[:, 0] >= 0.1 / U + 2 * h / U  # as turning_stream's window
    p = rows[steady, 1:1 + len(heights)] / (0.5 * RHO * U * U)
    force = rows[steady, 1 + len(heights):].sum(axis=1) * l0 / (RHO * U * U * h)
    return {"label": "PySPH edac, dx %g m" % l0, "l0": l0, "h": h, "U": U,
            "heights_over_h": list(heights), "p_mean": [float(v) for v in p.mean(axis=0)],
            "p_std": [float(v) for v in p.std(axis=0)],
            "p_theory": [turning_theory(f * h, h) for f in heights],
            "force": float(force.mean())}


def run_stream(out, quick, pysph_python=None):
    """Buchner's plateau on its own: a uniform stream as deep and fast as
    Ritter's at the wall, with gravity, turning up the wall; P1's reading
    over rho g H (H = 0.6 m) beside Buchner's plateau (0.55) and the
    gravity-free theory's; with pysph_python, PySPH's EDAC on the same stream
    at this spacing and half of it (about 5 minutes more)."""
    if pysph_python:  # before our runs, not after them
        import subprocess
        needs = subprocess.run([pysph_python, "-c", "import pysph"], capture_output=True,
                               text=True)
        if needs.returncode:
            sys.exit("validation.py: --pysph-python %s has no PySPH: %s"
                     % (pysph_python, (needs.stderr.strip().splitlines() or ["?"])[-1]))
    # the turn is chaotic (the readings' standard deviation is most of their
    # mean): three runs a scheme, perturbed in dt
    runs = [("corrected", {}), ("koshizuka1996", {"scheme": "koshizuka1996"})]
    steps = (2e-4, 2.5e-4, 3.2e-4)
    if quick:
        runs, steps = runs[:1], steps[1:2]
    summaries = []
    stagnation_over_rho_g_H = 0.5 * STREAM["U"] ** 2 / (G * 0.6)
    for (scheme, settings), dt in ((r, dt) for r in runs for dt in steps):
        label = "%s, dt %g s" % (scheme, dt)
        print("Buchner's stream turning, %s" % label)
        _, s, _ = turning_stream(label, {"gravity_y": -G, "dt": dt, **settings}, **STREAM)
        s["P1_over_rho_g_H"] = s["p_mean"][3] * stagnation_over_rho_g_H
        s["P1_theory_over_rho_g_H"] = s["p_theory"][3] * stagnation_over_rho_g_H
        summaries.append(s)
        print("  " + json.dumps(s))
    for l0 in ((STREAM["l0"], STREAM["l0"] / 2) if pysph_python else ()):
        print("Buchner's stream turning, PySPH edac, dx %g m" % l0)
        s = pysph_stream(out, pysph_python, l0)
        s["P1_over_rho_g_H"] = s["p_mean"][3] * stagnation_over_rho_g_H
        s["P1_theory_over_rho_g_H"] = s["p_theory"][3] * stagnation_over_rho_g_H
        summaries.append(s)
        print("  " + json.dumps(s))
    return summaries


# The chaotic statistics' scatter: each run of a violent flow is one sample of
# a chaotic process (a change of cfl alone moves the spray's peak from 2.2 to 3.8 %),
# so a bar is judged over runs perturbed in cfl (dt for the turn).
SCATTER_CFL = (0.2, 0.17, 0.23, 0.15, 0.25, 0.19)
SCATTER_DT = (5e-4, 4e-4, 6e-4, 4.5e-4)


def spread(values):
    a = np.array(values, dtype=float)
    return {"mean": float(a.mean()), "std": float(a.std()), "min": float(a.min()),
            "max": float(a.max()), "runs": [float(v) for v in a]}


def run_scatter(out, quick, settings=None):
    """The default scheme (with `settings` changed) over perturbed runs: the
    dam break at l0 = 0.01 m (six cfl values: front, spray, energy), Buchner's
    case at H/l0 = 40 (four: impact, plateau, noise) and the stream turning
    up a wall (four dt values: wall force); mean, standard deviation, range."""
    settings = settings or {}
    dams, impacts, turns = [], [], []
    for cfl in SCATTER_CFL[:3 if quick else 6]:
        print("scatter: dam break, cfl %g, %s" % (cfl, json.dumps(settings)))
        _, s = dam_break("corrected", 0.01, 1.0, cfl=cfl, settings=settings)
        dams.append(s)
    for cfl in SCATTER_CFL[:2 if quick else 4]:
        print("scatter: Buchner H/l0 = 40, cfl %g" % cfl)
        _, s = impact("corrected", 40, settings=dict(settings, cfl=cfl))
        impacts.append(s)
    for dt in SCATTER_DT[:2 if quick else 4]:
        print("scatter: turning stream, dt %g" % dt)
        _, s, _ = turning_stream("dt %g" % dt, dict(settings, dt=dt))
        turns.append(s)
    summary = {
        "settings": settings,
        "dam": {"cfl": [d["cfl"] for d in dams],
                "front_error_max": spread([d["front_error_max"] for d in dams]),
                "isolated_max_fraction": spread([d["isolated_max_fraction"] for d in dams]),
                "energy_excess_max": spread([d["energy_excess_max"] for d in dams]),
                "energy_balance_before_wall": spread(
                    [d["energy_balance_before_wall"] for d in dams])},
        "buchner_40": {"impact_t": spread([d["impact_t"] if d["impact_t"] is not None
                                           else math.nan for d in impacts]),
                       "plateau_3_5": spread([d["plateau_3_5"] for d in impacts]),
                       "noise_2_7": spread([d["noise_2_7"] for d in impacts])},
        "turning_force": spread([t["force"] for t in turns])}
    print("  " + json.dumps(summary))
    return summary


def scatter_row(r):
    """One row of the scatter table: mean +- standard deviation (worst)."""
    def f(x, scale=1.0, digits=1, worst="max"):
        return "%.*f +- %.*f (%.*f)" % (digits, scale * x["mean"], digits, scale * x["std"],
                                        digits, scale * x[worst])
    d, b = r["dam"], r["buchner_40"]
    return "| %s | %s %% | %s %% | %s %% | %s | %s | %s | %s |" % (
        json.dumps(r["settings"]) if r["settings"] else "the default scheme",
        f(d["front_error_max"], 100), f(d["isolated_max_fraction"], 100),
        f(d["energy_excess_max"], 100, 2), f(b["impact_t"], digits=2),
        f(b["plateau_3_5"], digits=2, worst="min"), f(b["noise_2_7"], digits=3),
        f(r["turning_force"], digits=2, worst="min"))


def tables(out):
    """The JSON summaries as docs/validation.md's Markdown tables."""
    def load(name):
        with open(os.path.join(out, name + ".json")) as f:
            return json.load(f)
    lines = []
    if os.path.exists(os.path.join(out, "still.json")):
        lines += ["", "| tank | scheme | RMS speed after 0.5 s, max (bar) | RMS displacement at "
                  "the end (bar 0.1 l0) | bottom pressure vs rho g h' (bar 1 %; h' to the water's top, "
                  "or the top row's centres with koshizuka1996) | bottom row's "
                  "spread, max (bar 5 %) |", "|---|---|---|---|---|---|"]
        for r in load("still"):
            lines.append("| %.1f m, %g s | %s | %.2g m/s (%.2g) | %.3f l0 | %+.3f %% | %.3f %% |" % (
                r["depth"], r["end"], r["scheme"], r["rms_speed_max_after_0.5"], r["rms_speed_bar"],
                r["displacement_end_l0"], 100 * r["bottom_pressure_error"],
                100 * r["bottom_spread_max"]))
    if os.path.exists(os.path.join(out, "dam.json")):
        lines += ["", "| scheme, l0, cfl | " + " | ".join(
            "T = %.3f (%s in)" % (p["T"], ("%g" % p["series_in"])) for p in load("dam")[0]["front"])
            + " | max | isolated, max | energy above the released, max | energy balance before "
            "the wall, at the end | noise energy, max before the wall, overall |",
            "|---|" + "---|" * (len(load("dam")[0]["front"]) + 5)]
        lines.append("| Martin & Moyce Z | " + " | ".join("%.3f" % p["Z_mm"] for p in load("dam")[0]["front"])
                     + " | | | | | |")
        for r in load("dam"):
            lines.append("| %s, %g m, %g | " % (r["scheme"], r["l0"], r["cfl"]) + " | ".join(
                "%.3f (%+.1f %%)" % (p["Z"], 100 * p["error"]) for p in r["front"]) +
                " | %.1f %% | %.1f %% (%.2f s) | %.3f %% | %+.1f %%, %+.1f %% | %.2f %%, %.2f %% |" % (
                    100 * r["front_error_max"], 100 * r["isolated_max_fraction"],
                    r["isolated_max_at"], 100 * r["energy_excess_max"],
                    100 * r["energy_balance_before_wall"], 100 * r["energy_balance_end"],
                    100 * r["noise_energy_max_before_wall"], 100 * r["noise_energy_max"]))
    if os.path.exists(os.path.join(out, "buchner.json")):
        lines += ["", "| scheme, H/l0 | particles | first P1 > 0.1 (exp. %.2f) | peak | plateau "
                  "t* 3-5 (exp. %.2f) | RMS difference t* 2-7 | noise t* 2-7 (bar 0.1 at 80) |"
                  % (load("buchner")[0]["impact_t_experiment"], load("buchner")[0]["plateau_experiment"]),
                  "|---|---|---|---|---|---|---|"]
        for r in load("buchner"):
            lines.append("| %s, %d | %d | %s | %.2f | %.2f | %.2f | %.2f |" % (
                r["scheme"], r["H_over_l0"], r["particles"],
                "%.2f" % r["impact_t"] if r["impact_t"] is not None else "never",
                r["peak"], r["plateau_3_5"], r["rms_difference_2_7"], r["noise_2_7"]))
    if os.path.exists(os.path.join(out, "turning.json")):
        turning = load("turning")
        lines += ["", "| scheme | " + " | ".join("y = %gh" % f for f in turning[0]["heights_over_h"])
                  + " | wall force / rho U^2 h | sheet speed / U (4-6 h) | sheet's fluid / h |",
                  "|---|" + "---|" * (len(turning[0]["heights_over_h"]) + 3),
                  "| free-streamline theory | " + " | ".join("%.2f" % v for v in turning[0]["p_theory"])
                  + " | 1 | 1 | 1 |"]
        for r in turning:
            lines.append("| %s | " % r["label"] + " | ".join(
                "%.2f (%.2f)" % (m, d) for m, d in zip(r["p_mean"], r["p_std"])) +
                " | %.2f | %.2f | %.2f |" % (r["force"], r["sheet_speed"], r["sheet_fluid"]))
    if os.path.exists(os.path.join(out, "stream.json")):
        stream = load("stream")
        lines += ["", "| scheme | " + " | ".join("y = %.2gh" % f for f in stream[0]["heights_over_h"])
                  + " | wall force / rho U^2 h | P1 / (rho g H) (Buchner 0.55) |",
                  "|---|" + "---|" * (len(stream[0]["heights_over_h"]) + 2),
                  "| free-streamline theory, no gravity | " + " | ".join(
                      "%.2f" % v for v in stream[0]["p_theory"]) + " | 1 | %.2f |"
                  % stream[0]["P1_theory_over_rho_g_H"]]
        for r in stream:
            lines.append("| %s | " % r["label"] + " | ".join(
                "%.2f (%.2f)" % (m, d) for m, d in zip(r["p_mean"], r["p_std"])) +
                " | %.2f | %.2f |" % (r["force"], r["P1_over_rho_g_H"]))
    if os.path.exists(os.path.join(out, "scatter.json")):
        lines += ["", "| settings | dam break: front error, max over T <= 2.5 | isolated, max to "
                  "1 s (bar 2 %) | energy above the released, max (bar 2 %) | Buchner H/l0 = "
                  "40: first P1 > 0.1 (exp. 2.49) | plateau t* 3-5 (exp. 0.55) | noise t* 2-7 | "
                  "turning force / rho U^2 h (theory 1) |", "|---|---|---|---|---|---|---|---|"]
        lines += [scatter_row(r) for r in load("scatter")]
    print("\n".join(lines[1:]))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("case", choices=("still", "dam", "shift", "buchner", "turning", "stream", "all",
                                         "scatter", "buchner_air", "gate", "transplant",
                                         "sensors", "tables"),
                        help="a case, all six, or scatter (the violent cases' statistics "
                             "over perturbed runs; not in all), buchner_air (Buchner's case "
                             "with air and without; not in all), gate (the dam break released by a lifted "
                             "gate; not in all), transplant (PySPH's Buchner flow at t* = 2.4 "
                             "continued by this scheme; needs --pysph-python; not in all), "
                             "sensors (Buchner's P1 read as other particle codes read it; not "
                             "in all), or "
                             "tables: the JSON "
                             "summaries in --out as Markdown (the shift and buchner_air "
                             "cases' tables are written by hand)")
    parser.add_argument("--quick", action="store_true", help="shorter runs (see the module help)")
    parser.add_argument("--fine", action="store_true",
                        help="buchner, sensors: also H/l0 = 160 (about 45 minutes more)")
    parser.add_argument("--pysph-python", metavar="PY",
                        help="buchner: also PySPH's own Buchner example at H/dx = 40 (edac), run "
                             "with this Python, which has PySPH (about 11 minutes more); stream: "
                             "PySPH's edac on the same stream (about 5 minutes more)")
    parser.add_argument("--settings", metavar="JSON", default="{}",
                        help="scatter: parameters and options changed from the default scheme, "
                             "as a JSON object (a run's summary is added to scatter.json's list)")
    parser.add_argument("--out", default=os.path.join("out", "validation"),
                        help="folder for the CSV, JSON and PNG files")
    args = parser.parse_args(argv)
    if args.case == "tables":
        tables(args.out)
        return 0
    os.makedirs(args.out, exist_ok=True)
    cases = (("still", "dam", "shift", "buchner", "turning", "stream") if args.case == "all"
             else (args.case,))
    runners = {"still": run_still, "dam": run_dam, "shift": run_shift,
               "buchner": lambda out, quick: run_buchner(out, quick, args.fine, args.pysph_python),
               "turning": run_turning,
               "stream": lambda out, quick: run_stream(out, quick, args.pysph_python),
               "buchner_air": run_buchner_air,
               "transplant": lambda out, quick: run_transplant(out, quick, args.pysph_python),
               "gate": run_gate,
               "sensors": lambda out, quick: run_sensors(out, quick, args.fine)}
    if args.case == "scatter":
        summary = run_scatter(args.out, args.quick, json.loads(args.settings))
        path = os.path.join(args.out, "scatter.json")
        earlier = []
        if os.path.exists(path):
            with open(path) as f:
                earlier = [r for r in json.load(f) if r["settings"] != summary["settings"]]
        with open(path, "w") as f:
            json.dump(earlier + [summary], f, indent=1)
        return 0
    for case in cases:
        summary = runners[case](args.out, args.quick)
        with open(os.path.join(args.out, case + ".json"), "w") as f:
            json.dump(summary, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
