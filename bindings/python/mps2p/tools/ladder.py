"""The two-phase ladder's measures (docs/two-phase.md, "The ladder"): each rung
a scene in examples/scenes and a number that tells, measured here and
asserted by tests/python/test_two_phase_ladder.py.

    python3 -m mps2p.tools.ladder [rung ...] [--until T]

prints each rung's measures as JSON (rungs: still_water_under_air,
droplet_in_air, bubble_rise_4x4, bubble_rise_8x8, dam_break_front)."""
import argparse
import json
import math
import os
import sys

import numpy as np

from .. import errors
from . import scenefile

SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenes")
G = 9.81


def scene_path(name):
    return os.path.join(SCENES, name + ".toml")


def _solver(path, without=None, options=None):
    """The scene's solver; without: a fluid whose boxes are left out (the
    same scene with one phase only)."""
    sf = scenefile.load(path)
    if without is not None:
        data = dict(sf.data)
        data["fluid_box"] = [b for b in data["fluid_box"] if b["fluid"] != without]
        data["fluid"] = [f for f in data["fluid"] if f["name"] != without]
        sf = scenefile.SceneFile(path, sf.text, data)
    if options:
        data = dict(sf.data)
        data["options"] = dict(data.get("options", {}), **options)
        sf = scenefile.SceneFile(path, sf.text, data)
    return sf, sf.make_solver()


def _column_tops(positions, liquid, l0):
    """The highest liquid particle of each l0-wide column."""
    columns = np.floor(positions[:, 0] / l0).astype(int)
    tops = {}
    for c, y in zip(columns[liquid], positions[liquid, 1]):
        if y > tops.get(c, -math.inf):
            tops[c] = y
    return columns, tops


def below_surface(positions, liquid, which, l0):
    """How many of the particles `which` (indices) lie more than l0/2 below
    the top liquid particle of their column: under the water surface."""
    columns, tops = _column_tops(positions, liquid, l0)
    return sum(1 for i in which if positions[i, 1] < tops.get(columns[i], -math.inf) - 0.5 * l0)


def outside_tank(sf, positions, fluid):
    """Fluid particles outside every tank's box of the scene file (rung 6:
    none may leave)."""
    inside = np.zeros(len(positions), dtype=bool)
    for tank in sf.data.get("tank", []):
        x0, y0, x1, y1 = tank["box"]
        inside |= ((positions[:, 0] >= x0) & (positions[:, 0] <= x1) &
                   (positions[:, 1] >= y0) & (positions[:, 1] <= y1))
    return int((fluid & ~inside).sum())


def _rms(v, mask):
    return float(math.sqrt((v[mask] ** 2).sum(axis=1).mean())) if mask.any() else 0.0


def still_water_under_air(until=10.0, sample_every=0.01, path=None):
    """Rung 1: the worst RMS water speed after 0.5 s with air above and
    without it (the same scene, air boxes left out), the worst RMS air
    speed after 1 s, the most air particles below the water surface at any
    sample, and the most fluid particles outside the tank."""
    path = path or scene_path("still_water_under_air")
    result = {"until": until}
    for label, without in (("with_air", None), ("without_air", "air")):
        sf, s = _solver(path, without=without)
        with s:
            kinds, fluids = s.kinds(), s.fluid_ids()
            water = (kinds == 0) & (fluids == sf.fluids.index("water"))
            air = (kinds == 0) & ~water
            air_ids = np.flatnonzero(air)
            worst_water = worst_air = 0.0
            most_below = most_outside = 0
            steps = int(round(until / sample_every))
            for k in range(1, steps + 1):
                t = k * sample_every
                s.advance_to(t)
                r, v = s.positions(), s.velocities()
                if t > 0.5 - 1e-12:
                    worst_water = max(worst_water, _rms(v, water))
                if air.any():
                    if t > 1.0 - 1e-12:
                        worst_air = max(worst_air, _rms(v, air))
                    most_below = max(most_below, below_surface(r, water, air_ids, sf.l0))
                most_outside = max(most_outside, outside_tank(sf, r, kinds == 0))
            result[label] = {"worst_water_rms": worst_water, "steps": s.step_count,
                             "most_outside_tank": most_outside}
            if air.any():
                result[label].update(worst_air_rms=worst_air, most_air_below_surface=most_below)
    result["water_rms_ratio"] = (result["with_air"]["worst_water_rms"] /
                                 result["without_air"]["worst_water_rms"])
    return result


def droplet_in_air(path=None, sample_every=0.005):
    """Rung 2: the droplet's mean height sampled until it is within 0.02 m
    (plus its half height) of the pool, and the acceleration of a parabola
    fitted to its fall, against g."""
    path = path or scene_path("droplet_in_air")
    sf, s = _solver(path)
    with s:
        r0, kinds, fluids = s.positions(), s.kinds(), s.fluid_ids()
        water = (kinds == 0) & (fluids == sf.fluids.index("water"))
        pool_top = r0[water & (r0[:, 1] < 0.2), 1].max() + 0.5 * sf.l0
        drop = np.flatnonzero(water & (r0[:, 1] > pool_top + 0.1))
        y0 = r0[drop, 1].mean()
        half = 0.5 * (r0[drop, 1].max() - r0[drop, 1].min()) + 0.5 * sf.l0
        times, fallen = [], []
        t = 0.0
        while t < sf.end_time:
            t += sample_every
            s.advance_to(t)
            y = s.positions()[drop, 1].mean()
            if y - half < pool_top + 0.02:
                break
            times.append(t)
            fallen.append(y0 - y)
    a = 2.0 * np.polyfit(np.array(times), np.array(fallen), 2)[0]
    return {"droplet_particles": int(len(drop)), "fitted_acceleration": float(a),
            "relative_error": float(a / G - 1.0), "fitted_until": float(times[-1])}


def bubble_rise(name, until=2.0, sample_every=0.01, path=None):
    """Rung 3: the bubble's particles (air below the water surface at the
    start) in the water over time, when the last one left, their mean rise
    speed until the first of them left the water, against 0.5 sqrt(g R) (R the
    equivalent radius), the water's RMS speed at the end and how flat the
    surface is then (the largest distance of a column's top from their
    mean, in l0), and the most fluid particles outside the tank at a sample."""
    path = path or scene_path(name)
    sf, s = _solver(path)
    with s:
        r0, kinds, fluids = s.positions(), s.kinds(), s.fluid_ids()
        water = (kinds == 0) & (fluids == sf.fluids.index("water"))
        air = (kinds == 0) & ~water
        air_ids = np.flatnonzero(air)
        columns, tops = _column_tops(r0, water, sf.l0)
        bubble = np.array([i for i in air_ids
                           if r0[i, 1] < tops.get(columns[i], -math.inf) - 0.5 * sf.l0])
        y_start = r0[bubble, 1].mean()
        radius = math.sqrt(len(bubble) * sf.l0 ** 2 / math.pi)
        in_water, all_out_at, rise, most_outside = [], None, None, 0
        whole = True
        status = "ran"
        steps = int(round(until / sample_every))
        for k in range(1, steps + 1):
            t = k * sample_every
            try:
                s.advance_to(t)
            except errors.Error as e:
                status = "failed at t = %.3f s: %s" % (t, str(e)[:300])
                break
            r = s.positions()
            most_outside = max(most_outside, outside_tank(sf, r, kinds == 0))
            inside = below_surface(r, water, bubble, sf.l0)
            in_water.append((round(t, 6), inside))
            if inside == len(bubble) and whole:
                rise = (r[bubble, 1].mean() - y_start) / t
            else:
                whole = False  # the rise is measured until the first particle leaves
            if inside == 0 and all_out_at is None:
                all_out_at = t
        water_rms = _rms(s.velocities(), water)
        _, tops_end = _column_tops(s.positions(), water, sf.l0)
        # the surface settled back flat: the columns' tops about their mean, in l0
        level = np.array(list(tops_end.values()))
        surface = float(np.abs(level - level.mean()).max() / sf.l0)
        end = s.time
    estimate = 0.5 * math.sqrt(G * radius)
    return {"bubble_particles": int(len(bubble)), "status": status, "end": end,
            "all_out_at": all_out_at, "left_in_water": in_water[-1][1] if in_water else None,
            "rise_speed_while_whole": rise, "rise_estimate": estimate,
            "rise_ratio": None if rise is None else rise / estimate,
            "water_rms_at_end": water_rms, "surface_deviation_at_end": surface,
            "most_outside_tank": most_outside,
            "in_water": in_water[::10]}


def dam_break_front(until=0.2, sample_every=0.05, path=None):
    """Rung 4's front: the water front on the floor (probe "front" of the
    paper's scene: below 0.02 m) every sample_every until `until`, with air
    and for the same scene without it (same dt, solver and tolerances), and
    the largest lag of the front with air behind the one without (m)."""
    path = path or scene_path("ikari2003_dam_break_air")
    result = {"until": until}
    for label, without in (("with_air", None), ("without_air", "air")):
        sf, s = _solver(path, without=without)
        probe = next(p for p in sf.probes if p["name"] == "front")
        fronts = []
        with s:
            water = sf.fluids.index(probe["fluid"])
            for k in range(1, int(round(until / sample_every)) + 1):
                t = k * sample_every
                s.advance_to(t)
                fronts.append((round(t, 6), s.front(water, below=probe["below"])))
        result[label] = fronts
    result["largest_lag"] = max(b[1] - a[1] for a, b in
                                zip(result["with_air"], result["without_air"]))
    return result


RUNGS = {
    "still_water_under_air": lambda until: still_water_under_air(until=until or 10.0),
    "droplet_in_air": lambda until: droplet_in_air(),
    "bubble_rise_4x4": lambda until: bubble_rise("bubble_rise_4x4", until=until or 2.0),
    "bubble_rise_8x8": lambda until: bubble_rise("bubble_rise_8x8", until=until or 2.0),
    "dam_break_front": lambda until: dam_break_front(until=until or 0.2),
}


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m mps2p.tools.ladder",
                                     description="the two-phase ladder's measures")
    parser.add_argument("rungs", nargs="*", help="of %s (default: all)" % ", ".join(RUNGS))
    parser.add_argument("--until", type=float, default=None, help="end time (s)")
    args = parser.parse_args(argv)
    unknown = [name for name in args.rungs if name not in RUNGS]
    if unknown:
        parser.error("unknown rung %s (rungs: %s)" % (", ".join(unknown), ", ".join(RUNGS)))
    for name in args.rungs or list(RUNGS):
        print(json.dumps({name: RUNGS[name](args.until)}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
