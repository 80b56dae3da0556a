"""The two-phase ladder's measures (docs/two-phase.md, "The ladder"): each rung
a scene in examples/scenes and a number that tells, measured here and
asserted by tests/python/test_two_phase_ladder.py.

    python3 -m mps2p.tools.ladder [rung ...] [--until T]
    python3 -m mps2p.tools.ladder --results out/ikari2003_dam_break_air/results.h5

prints each rung's measures as JSON (rungs: still_water_under_air,
droplet_in_air, droplet_settles, bubble_rise_4x4, bubble_rise_8x8, dam_break_front,
paper_case, gas_thrown_up, droplet_thrown_up, tip_into_wall, void_in_gas), or
with --results rung 4's of a run of the paper's case
(`mps2p run`'s results.h5): water suspended in the air and the widest hole in
the gas, per snapshot."""
import argparse
import copy
import json
import math
import os
import sys

import numpy as np

from .. import errors
from ..scene import KIND_DUMMY, KIND_FLUID, KIND_OUT, KIND_WALL
from . import scenefile

SCENES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenes")
G = 9.81


def scene_path(name):
    return os.path.join(SCENES, name + ".toml")


def _own_copy(sf):
    """sf's tables, every level copied: a variant's change (its [run] values
    too) leaves the loaded scene alone."""
    return copy.deepcopy(sf.data)


def _solver(path, without=None, options=None):
    """The scene's solver; without: a fluid whose boxes are left out (the
    same scene with one phase only)."""
    sf = scenefile.load(path)
    if without is not None:
        data = _own_copy(sf)
        data["fluid_box"] = [b for b in data["fluid_box"] if b["fluid"] != without]
        data["fluid"] = [f for f in data["fluid"] if f["name"] != without]
        sf = scenefile.SceneFile(path, sf.text, data)
    if options:
        data = _own_copy(sf)
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


def outside_tank(sf, positions, fluid, out=None):
    """Fluid particles outside every tank's box of the scene file, and those
    of `out` (kinds == KIND_OUT: they left the domain and are out of the
    run) wherever they stopped (rung 6: none may leave). fluid: the fluid
    particles at the start."""
    inside = np.zeros(len(positions), dtype=bool)
    for tank in sf.data.get("tank", []):
        x0, y0, x1, y1 = tank["box"]
        inside |= ((positions[:, 0] >= x0) & (positions[:, 0] <= x1) &
                   (positions[:, 1] >= y0) & (positions[:, 1] <= y1))
    gone = ~inside if out is None else ~inside | out
    return int((fluid & gone).sum())


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
            water = (kinds == KIND_FLUID) & (fluids == sf.fluids.index("water"))
            air = (kinds == KIND_FLUID) & ~water
            air_ids = np.flatnonzero(air)
            worst_water = worst_air = 0.0
            most_below = most_outside = 0
            steps = int(round(until / sample_every))
            for k in range(1, steps + 1):
                t = k * sample_every
                s.advance_to(t)
                r, v, now = s.positions(), s.velocities(), s.kinds()
                if t > 0.5 - 1e-12:
                    worst_water = max(worst_water, _rms(v, water))
                if air.any():
                    if t > 1.0 - 1e-12:
                        worst_air = max(worst_air, _rms(v, air))
                    # the surface of the water in the run (not a drop frozen out of it)
                    most_below = max(most_below, below_surface(r, water & (now == KIND_FLUID),
                                                               air_ids, sf.l0))
                most_outside = max(most_outside, outside_tank(sf, r, kinds == KIND_FLUID,
                                                              now == KIND_OUT))
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
        water = (kinds == KIND_FLUID) & (fluids == sf.fluids.index("water"))
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
    mean, in l0), the most fluid particles outside the tank at a sample, and
    at the end the statistics gas_in_bubbles (air cut off from the open gas)
    and gas_in_liquid beside the column test."""
    path = path or scene_path(name)
    sf, s = _solver(path)
    with s:
        r0, kinds, fluids = s.positions(), s.kinds(), s.fluid_ids()
        water = (kinds == KIND_FLUID) & (fluids == sf.fluids.index("water"))
        air = (kinds == KIND_FLUID) & ~water
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
            r, now = s.positions(), s.kinds()
            most_outside = max(most_outside, outside_tank(sf, r, kinds == KIND_FLUID,
                                                          now == KIND_OUT))
            inside = below_surface(r, water & (now == KIND_FLUID), bubble, sf.l0)
            in_water.append((round(t, 6), inside))
            if inside == len(bubble) and whole:
                rise = (r[bubble, 1].mean() - y_start) / t
            else:
                whole = False  # the rise is measured until the first particle leaves
            if inside == 0 and all_out_at is None:
                all_out_at = t
        water_rms = _rms(s.velocities(), water)
        _, tops_end = _column_tops(s.positions(), water & (s.kinds() == KIND_FLUID), sf.l0)
        # the surface settled back flat: the columns' tops about their mean, in l0
        level = np.array(list(tops_end.values()))
        surface = float(np.abs(level - level.mean()).max() / sf.l0)
        end = s.time
        # beside the column test: the library's own counts of air cut off from
        # the open gas (enclosed) and inside the liquid (docs/two-phase.md)
        enclosed_at_end = int(s.stat("gas_in_bubbles"))
        in_liquid_at_end = int(s.stat("gas_in_liquid"))
    estimate = 0.5 * math.sqrt(G * radius)
    return {"bubble_particles": int(len(bubble)), "status": status, "end": end,
            "all_out_at": all_out_at, "left_in_water": in_water[-1][1] if in_water else None,
            "rise_speed_while_whole": rise, "rise_estimate": estimate,
            "rise_ratio": None if rise is None else rise / estimate,
            "water_rms_at_end": water_rms, "surface_deviation_at_end": surface,
            "most_outside_tank": most_outside,
            "gas_in_bubbles_at_end": enclosed_at_end, "gas_in_liquid_at_end": in_liquid_at_end,
            "in_water": in_water[::10]}


def gas_thrown_up(speed=3.0, until=0.3, buffer=True, sample_every=0.005, path=None):
    """Rung 6, the gas's top: rung 1's tank with the air particle at the top
    of the gas's middle column thrown up at `speed` m/s (the site left out of
    the air box, the particle added with that velocity); with the gas's
    damping layer (effect gas_buffer) or without it (an open top). Reports
    the highest the thrown particle and any gas particle got above the
    gas's starting top, in l0, the most gas particles above the tank's walls
    or outside its sides (or out of the run), the fluid particles that left
    the domain and are out of the run (statistic fluid_out; parameter
    out_limit), the thrown particle's vertical velocity at the end, and the
    divergence's message if the run diverged."""
    from ..solver import Solver
    path = path or scene_path("still_water_under_air")
    sf = scenefile.load(path)
    l0 = sf.l0
    data = _own_copy(sf)
    air = [b for b in data["fluid_box"] if b["fluid"] == "air"][0]
    x0, y0, x1, y1 = air["box"]
    middle = x0 + l0 * math.floor((x1 - x0) / (2 * l0))
    boxes = [b for b in data["fluid_box"] if b is not air]
    boxes += [{"fluid": "air", "box": [x0, y0, x1, y1 - l0]},
              {"fluid": "air", "box": [x0, y1 - l0, middle, y1]},
              {"fluid": "air", "box": [middle + l0, y1 - l0, x1, y1]}]
    data["fluid_box"] = boxes
    data["options"] = dict(data.get("options", {}),
                           **{"effect.gas_buffer": "auto" if buffer else "off"})
    sf = scenefile.SceneFile(path, sf.text, data)
    start = (middle + 0.5 * l0, y1 - 0.5 * l0)
    with sf.build() as scene:
        scene.add_particles([start], [0], [sf.fluids.index("air")], [[0.0, speed]])
        s = Solver(scene)
    with s:
        ids, kinds = s.fluid_ids(), s.kinds()
        gas = (kinds == KIND_FLUID) & (ids == sf.fluids.index("air"))
        thrown = int(np.argmin(np.hypot(*(s.positions() - start).T)))
        gas_top = float(s.positions()[gas, 1].max())
        tx0, _, tx1, ty1 = sf.data["tank"][0]["box"]
        highest = highest_gas = -math.inf
        most_out = 0
        steps = int(round(until / sample_every))
        diverged = None
        for k in range(1, steps + 1):
            try:
                s.advance_to(k * sample_every)
            except errors.DivergedError as e:
                diverged = str(e)
                break
            r = s.positions()
            highest = max(highest, r[thrown, 1])
            highest_gas = max(highest_gas, r[gas, 1].max())
            # out of the run: it flew out of the domain (the open top)
            out = gas & ((r[:, 1] > ty1) | (r[:, 0] < tx0) | (r[:, 0] > tx1) |
                         (s.kinds() == KIND_OUT))
            most_out = max(most_out, int(out.sum()))
        return {"buffer": bool(buffer), "speed": speed, "until": until, "diverged": diverged,
                "effect_on": s.effects()["gas_buffer"][0],
                "thrown_highest_above_top": (highest - gas_top) / l0,
                "gas_highest_above_top": (highest_gas - gas_top) / l0,
                "tank_top_above_gas_top": (ty1 - gas_top) / l0,
                "most_gas_outside_tank": most_out, "out_of_run": s.stat("fluid_out"),
                "thrown_velocity_at_end": float(s.velocities()[thrown, 1])}


def droplet_settles(gap=2.0, until=0.5, sample_every=0.0025, path=None):
    """Under rung 2 (and under rung 3's stragglers): rung 2's pool under air,
    with a droplet of one particle released at rest `gap` spacings above the
    pool's top row (the air's site there left out). Reports when it touches
    the pool (its centre within one spacing above the highest pool particle
    within 1.5 l0 to either side), against the free fall's time to get
    there. Air squeezed under a single droplet, joined to the liquid's solve
    as the paper's cushion, held droplets over the surface for over half a second
    (docs/two-phase.md, "A droplet held up by the air under it")."""
    from ..solver import Solver
    path = path or scene_path("droplet_in_air")
    sf = scenefile.load(path)
    l0 = sf.l0
    x, y = 0.145, 0.095 + gap * l0  # the pool's top row's centres are at 0.095 m
    sf = _pool_under_air_around(sf, (x - 0.5 * l0, y - 0.5 * l0, x + 0.5 * l0, y + 0.5 * l0))
    water_id = sf.fluids.index("water")
    with sf.build() as scene:
        scene.add_particles([(x, y)], [0], [water_id], [[0.0, 0.0]])
        s = Solver(scene)
    with s:
        r0, kinds, ids = s.positions(), s.kinds(), s.fluid_ids()
        water = (kinds == KIND_FLUID) & (ids == water_id)
        drop = int(np.flatnonzero(water & (r0[:, 1] > y - 0.25 * l0))[0])
        pool = water.copy()
        pool[drop] = False
        touched = None
        for k in range(1, int(round(until / sample_every)) + 1):
            s.advance_to(k * sample_every)
            r = s.positions()
            below = pool & (np.abs(r[:, 0] - r[drop, 0]) < 1.5 * l0)
            if r[drop, 1] - r[below, 1].max() < l0 * (1.0 + 1e-9):
                touched = s.time
                break
    return {"gap": gap, "touched_at": touched,
            "free_fall": math.sqrt(2.0 * (gap - 1.0) * l0 / G)}


def _pool_under_air_around(sf, site, **tables):
    """Scene file sf (rung 2's) with its fluid boxes made a 0.1 m pool under
    air to 0.6 m, 0.3 m wide, the air left out of the box site = (x0, y0,
    x1, y1) (None: no site, the air whole), and any other top-level tables
    replaced by `tables`."""
    data = dict(_own_copy(sf), **copy.deepcopy(tables))
    air = [[0.0, 0.1, 0.3, 0.6]]
    if site is not None:
        x0, y0, x1, y1 = site
        air = [[0.0, 0.1, 0.3, y0], [0.0, y0, x0, y1], [x1, y0, 0.3, y1], [0.0, y1, 0.3, 0.6]]
    data["fluid_box"] = ([{"fluid": "water", "box": [0.0, 0.0, 0.3, 0.1]}] +
                         [{"fluid": "air", "box": box} for box in air])
    return scenefile.SceneFile(sf.path, sf.text, data)


def droplet_thrown_up(speed=4.0, until=0.15, sample_every=0.01, path=None):
    """The wake of a splash in the gas (under rung 4's holes): rung 2's pool
    under 0.5 m of air, in a tank 1.2 m high, with a 3 x 3 water droplet
    0.15 m above the pool thrown up at `speed` m/s. Reports the widest hole
    in the gas (widest_gas_hole, l0) while the droplet is below the gas's
    damping layer (its top under the gas's starting top less
    gas_buffer_depth l0), and when it got there."""
    from ..solver import Solver
    path = path or scene_path("droplet_in_air")
    sf = scenefile.load(path)
    l0 = sf.l0
    site = (0.14, 0.25, 0.17, 0.28)
    sf = _pool_under_air_around(sf, site, tank=[{"box": [0.0, 0.0, 0.3, 1.2], "open_top": True}])
    tank = sf.data["tank"][0]["box"]
    drop = [(site[0] + (i + 0.5) * l0, site[1] + (j + 0.5) * l0)
            for i in range(3) for j in range(3)]
    water_id = sf.fluids.index("water")
    with sf.build() as scene:
        scene.add_particles(drop, [0] * 9, [water_id] * 9, [[0.0, speed]] * 9)
        depth = scene.get_param("gas_buffer_depth")
        s = Solver(scene)
    with s:
        kinds, ids = s.kinds(), s.fluid_ids()
        light = (kinds == KIND_FLUID) & (ids == sf.fluids.index("air"))
        r0 = s.positions()
        droplet = np.flatnonzero((kinds == KIND_FLUID) & (ids == water_id) & (r0[:, 1] > 0.2))
        layer = r0[light, 1].max() - depth * l0
        widest, reached = 1.0, None
        for k in range(1, int(round(until / sample_every)) + 1):
            s.advance_to(k * sample_every)
            r = s.positions()
            if r[droplet, 1].max() + 0.5 * l0 >= layer:
                reached = s.time
                break
            now = s.kinds()  # the gas in the run
            widest = max(widest, widest_gas_hole(r, now, light & (now == KIND_FLUID), tank, l0))
        return {"speed": speed, "droplet_particles": int(len(droplet)),
                "widest_gas_hole": widest, "reached_layer_at": reached}


def void_in_gas(width=4, dt=None, until=0.2, sample_every=0.01, path=None):
    """Under rung 4's holes: a void closing in still air. Rung 2's pool
    under 0.5 m of air with a square hole `width` l0 wide cut out of the air
    0.2 m above the pool (well below the gas's damping layer), at the
    scene's dt or a fixed `dt` (width 0: no void, the still air's own
    holes). Reports the widest hole in the gas (widest_gas_hole, l0) at the
    start and at the last sample (`until`, or the last before a divergence),
    when it first fell to 1.5 l0, the widest at any sample from then on and
    the mean over those samples (hole_after_closing, _mean; width 0: from
    the first sample on), the fastest gas
    particle and the lowest gas pressure over the samples, and the
    divergence message if the run stopped."""
    path = path or scene_path("droplet_in_air")
    sf = scenefile.load(path)
    l0 = sf.l0
    h0, h1 = 0.3 - 0.5 * width * l0, 0.3 + 0.5 * width * l0
    x0, x1 = 0.15 - 0.5 * width * l0, 0.15 + 0.5 * width * l0
    parameters = sf.data.get("parameters", {})
    sf = _pool_under_air_around(sf, (x0, h0, x1, h1) if width > 0 else None,
                                parameters=parameters if dt is None else dict(parameters, dt=dt))
    tank = sf.data["tank"][0]["box"]
    result = {"width": width, "dt": dt, "until": until, "closed_at": None,
              "diverged": None, "fastest_gas": 0.0, "lowest_gas_pressure": 0.0}
    with sf.make_solver() as s:
        light = (s.kinds() == KIND_FLUID) & (s.fluid_ids() == sf.fluids.index("air"))
        result["hole_at_start"] = widest_gas_hole(s.positions(), s.kinds(), light, tank, l0)
        hole = result["hole_at_start"]
        after = []
        try:
            for k in range(1, int(round(until / sample_every)) + 1):
                s.advance_to(k * sample_every)
                hole = widest_gas_hole(s.positions(), s.kinds(), light, tank, l0)
                if hole <= 1.5 and result["closed_at"] is None:
                    result["closed_at"] = round(s.time, 9)
                if result["closed_at"] is not None or width == 0:
                    after.append(hole)
                speed = np.hypot(*s.velocities()[light].T).max()
                result["fastest_gas"] = max(result["fastest_gas"], float(speed))
                result["lowest_gas_pressure"] = min(result["lowest_gas_pressure"],
                                                    float(s.pressure()[light].min()))
        except errors.DivergedError as e:
            result["diverged"] = str(e)
        result["hole_at_end"] = hole
        if after:
            result["hole_after_closing"] = max(after)
            result["hole_after_closing_mean"] = float(np.mean(after))
        result["time"] = s.time
    return result


def tip_into_wall(air=True, speed=2.5, until=0.15, path=None, depth=3, ramp=0.0):
    """Under rung 5's spray: a water slab `depth` l0 deep and 15 l0 long sliding
    at `speed` m/s along the floor into the right wall of a 0.3 m tank, with
    still air around it (air=True) or none. With ramp > 0 the slab starts at
    rest and a uniform push brings it to `speed` over `ramp` seconds (the air
    ahead of it starts with it) instead of starting at `speed`. Reports the
    first contact (the slab's front within l0 of the wall), the fastest upward
    water speed after it (against 2 speed, about a jet's at a wall), the
    highest pressure on a light particle (the liquid solve's when joined) and
    the divergence message if the run stopped; checked after every step."""
    from ..solver import Solver
    path = path or scene_path("still_water_under_air")
    sf = scenefile.load(path)
    l0 = sf.l0
    rows = int(depth)
    if rows != depth or rows < 1:
        raise ValueError("depth is a whole number of spacings, got %r" % (depth,))
    x0, x1, depth = 0.1, 0.25, rows * l0
    data = _own_copy(sf)
    data["fluid_box"] = ([{"fluid": "air", "box": [0.0, depth, 0.3, 0.3]},
                          {"fluid": "air", "box": [0.0, 0.0, x0, depth]},
                          {"fluid": "air", "box": [x1, 0.0, 0.3, depth]}] if air else [])
    if not air:
        data["fluid"] = [f for f in data["fluid"] if f["name"] != "air"]
    data["tank"] = [{"box": [0.0, 0.0, 0.3, 0.6], "open_top": True}]
    sf = scenefile.SceneFile(path, sf.text, data)
    n = int(round((x1 - x0) / l0))
    slab = [(x0 + (i + 0.5) * l0, (j + 0.5) * l0) for i in range(n) for j in range(rows)]
    water_id = sf.fluids.index("water")
    start = 0.0 if ramp > 0.0 else speed
    with sf.build() as scene:
        scene.add_particles(slab, [0] * len(slab), [water_id] * len(slab),
                            [[start, 0.0]] * len(slab))
        s = Solver(scene)
    result = {"air": air, "speed": speed, "contact_at": None, "fastest_up_after": 0.0,
              "highest_light_pressure": 0.0, "diverged": None}
    with s:
        kinds, ids = s.kinds(), s.fluid_ids()
        water = (kinds == KIND_FLUID) & (ids == water_id)
        light = (kinds == KIND_FLUID) & ~water
        push = np.zeros((s.particle_count, 2))
        push[water, 0] = speed / ramp if ramp > 0.0 else 0.0
        pushing = ramp > 0.0
        if pushing:
            s.set_body_forces(push)
        try:
            while s.time < until - 1e-12:
                if pushing and s.time >= ramp - 1e-12:
                    s.set_body_forces(None)
                    pushing = False
                s.advance_to(min(ramp, until) if pushing else until,
                             progress=lambda _: True)  # one step
                r, u = s.positions(), s.velocities()
                if result["contact_at"] is None and r[water, 0].max() >= 0.3 - l0:
                    result["contact_at"] = round(s.time, 6)
                if result["contact_at"] is not None:
                    result["fastest_up_after"] = max(result["fastest_up_after"],
                                                     float(u[water, 1].max()))
                if light.any():
                    result["highest_light_pressure"] = max(result["highest_light_pressure"],
                                                           float(s.pressure()[light].max()))
        except errors.DivergedError as e:
            result["diverged"] = str(e)
        result["time"] = s.time
    return result


def _nearest_distance(points, particles, chunk=2048):
    """Distance from each point to its nearest particle (brute force, in
    chunks: a results snapshot is a few thousand particles)."""
    best = np.full(len(points), np.inf)
    if len(particles) == 0:
        return best
    for k in range(0, len(points), chunk):
        d = points[k:k + chunk, None, :] - particles[None, :, :]
        best[k:k + chunk] = np.sqrt((d ** 2).sum(axis=2).min(axis=1))
    return best


def suspended_water(position, water, l0, radius=2.1):
    """Rung 4's water suspended in the air: water particles with no other
    water particle within `radius` l0 (isolated, as issue 15 counts spray)
    that lie above the top of the water body (the water that is not
    isolated) in their l0-wide column, or in a column without it. A clump
    of two or more held up in the air counts as water body: this sees
    spray, not suspended blobs."""
    r = position[water]
    if len(r) == 0:
        return 0
    d = r[:, None, :] - r[None, :, :]
    d2 = (d ** 2).sum(axis=2)
    np.fill_diagonal(d2, np.inf)
    isolated = d2.min(axis=1) > (radius * l0) ** 2
    columns = np.floor(r[:, 0] / l0).astype(int)
    tops = {}
    for c, y in zip(columns[~isolated], r[~isolated, 1]):
        tops[c] = max(tops.get(c, -math.inf), y)
    return int(sum(1 for c, y in zip(columns[isolated], r[isolated, 1])
                   if y > tops.get(c, -math.inf)))


def _reached_from_top(free):
    """The cells of a boolean (x, y) grid joined to its top row's free cells
    through free cells (4-neighbours)."""
    reached = np.zeros_like(free)
    nx, ny = free.shape
    stack = [(i, ny - 1) for i in range(nx) if free[i, ny - 1]]
    for i, j in stack:
        reached[i, j] = True
    while stack:
        i, j = stack.pop()
        for a, b in ((i + 1, j), (i - 1, j), (i, j + 1), (i, j - 1)):
            if 0 <= a < nx and 0 <= b < ny and free[a, b] and not reached[a, b]:
                reached[a, b] = True
                stack.append((a, b))
    return reached


def widest_gas_hole(position, kind, light, tank, l0):
    """Rung 4's holes in the gas, in l0: the widest empty disc (diameter
    2 d - l0, d the distance from its centre to the nearest particle of any
    kind, each particle taken as l0 wide) centred on a point of an l0/2
    lattice inside the tank's walls that the particles close off from the
    open air above the gas, and whose nearest fluid particle is gas.
    Lattice points within l0 of a particle are struck off first (no hole
    wider than 1 l0 there); a point is closed off when no path through the
    lattice's other points leads above the highest gas particle (a gas
    particle floating above the gas's surface, in its damping layer, closes
    nothing off under it); the rest are measured exactly. A void joined to
    the air above by a channel wider than about 2 l0 is open, not a hole."""
    x0, y0, x1, _ = tank
    h = 0.5 * l0
    gas = position[light]
    if len(gas) == 0:
        return 0.0
    nx = int(math.floor((x1 - x0 - l0) / h)) + 1
    # the top row lies more than l0 above the highest gas particle: the open air
    ny = int(math.floor((gas[:, 1].max() + 1.5 * l0 - y0 - 0.5 * l0) / h)) + 1
    if nx < 1 or ny < 2:
        return 0.0
    free = np.ones((nx, ny), dtype=bool)
    cell = np.round((position - (x0 + 0.5 * l0, y0 + 0.5 * l0)) / h).astype(int)
    for di in range(-2, 3):
        for dj in range(-2, 3):
            if di * di + dj * dj > 4:
                continue
            i, j = cell[:, 0] + di, cell[:, 1] + dj
            keep = (i >= 0) & (i < nx) & (j >= 0) & (j < ny)
            free[i[keep], j[keep]] = False
    closed = free & ~_reached_from_top(free)
    ii, jj = np.nonzero(closed)
    points = np.column_stack((x0 + 0.5 * l0 + h * ii, y0 + 0.5 * l0 + h * jj))
    if len(points) == 0:
        return 1.0  # every lattice point near a particle or open: no hole wider than 1 l0
    fluid = kind == KIND_FLUID
    d_gas = _nearest_distance(points, gas)
    liquid = position[fluid & ~light]
    d_liquid = _nearest_distance(points, liquid)
    in_gas = d_gas <= d_liquid
    if not in_gas.any():
        return 1.0
    solid = (kind == KIND_WALL) | (kind == KIND_DUMMY)  # not fluid out of the run
    d_any = np.minimum(np.minimum(d_gas, d_liquid), _nearest_distance(points, position[solid]))
    return float(max(1.0, (2.0 * d_any[in_gas].max() - l0) / l0))


def paper_case_measures(results_path, water="water", air="air"):
    """Rung 4's measures of a run of the paper's case (`mps2p run`'s
    results.h5, the scene's tank): per snapshot the time, the suspended
    water (count and fraction of the water) and the widest hole in the gas
    (l0)."""
    from ..results import open_results
    from .scenefile import tomllib
    rows = []
    with open_results(results_path) as f:
        names = [name for name, _, _ in f.fluids]
        tank = tomllib.loads(f.scene_text)["tank"][0]["box"]
        l0 = float(f.metadata["l0"])
        for snap in f.snapshots():
            fluid = snap["kind"] == KIND_FLUID  # in the run
            is_water = fluid & (snap["fluid_id"] == names.index(water))
            light = fluid & (snap["fluid_id"] == names.index(air))
            count = suspended_water(snap["position"], is_water, l0)
            rows.append({"time": snap["time"], "suspended_water": count,
                         "suspended_fraction": count / max(1, int(is_water.sum())),
                         "widest_gas_hole": widest_gas_hole(snap["position"], snap["kind"],
                                                            light, tank, l0)})
    return rows


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


def air_leaves(times, counts):
    """Rung 4's air criterion from a gas_in_liquid series: its peak, when,
    and the times from which it stays below a quarter and a tenth of it."""
    times, counts = np.asarray(times), np.asarray(counts)
    k = int(np.argmax(counts))
    peak, at = float(counts[k]), float(times[k])

    def stays_below(fraction):
        above = np.flatnonzero((times > at) & (counts >= fraction * peak))
        if not len(above):
            return float(times[k + 1]) if k + 1 < len(times) else None
        return float(times[above[-1] + 1]) if above[-1] + 1 < len(times) else None

    return {"peak": peak, "peak_at": at, "quarter_from": stays_below(0.25),
            "tenth_from": stays_below(0.1)}


def paper_case(until=10.0, path=None, parameters=None, sample_every=0.005,
               snapshot_every=0.05):
    """Rung 4, the paper's case to `until` (the scene, or `parameters`
    changed): the air criterion (air_leaves, from gas_in_liquid every
    sample_every), the most air in the water after 3 s and at the end, the
    most suspended water from 5 s on and the widest hole in the gas (every
    snapshot_every), the most fluid particles outside the tank, steps."""
    path = path or scene_path("ikari2003_dam_break_air")
    sf = scenefile.load(path)
    if parameters:
        data = _own_copy(sf)
        data["parameters"] = dict(data.get("parameters", {}), **parameters)
        sf = scenefile.SceneFile(path, sf.text, data)
    tank = sf.data["tank"][0]["box"]
    with sf.make_solver() as s:
        kinds, ids = s.kinds(), s.fluid_ids()
        fluid = kinds == KIND_FLUID
        water = fluid & (ids == sf.fluids.index("water"))
        light = fluid & (ids == sf.fluids.index("air"))
        times, counts = [], []
        suspended, holes, outside = [], [], 0
        every = int(round(snapshot_every / sample_every))
        for k in range(1, int(round(until / sample_every)) + 1):
            s.advance_to(k * sample_every)
            times.append(s.time)
            counts.append(s.stat("gas_in_liquid"))
            if k % every == 0:
                r = s.positions()
                if s.time >= 5.0 - 1e-9:
                    suspended.append(suspended_water(r, water, sf.l0) / water.sum())
                now = s.kinds()
                holes.append(widest_gas_hole(r, now, light & (now == KIND_FLUID), tank, sf.l0))
                outside = max(outside, outside_tank(sf, r, fluid, now == KIND_OUT))
        times, counts = np.array(times), np.array(counts)
        result = air_leaves(times, counts)
        result.update(until=until, steps=s.step_count,
                      most_after_3s=float(counts[times >= 3.0 - 1e-9].max())
                      if until >= 3.0 else None,
                      at_end=float(counts[-1]),
                      most_suspended_from_5s=max(suspended) if suspended else None,
                      widest_gas_hole=max(holes), most_outside_tank=outside)
        return result


RUNGS = {
    "still_water_under_air": lambda until: still_water_under_air(until=until or 10.0),
    "droplet_in_air": lambda until: droplet_in_air(),
    "droplet_settles": lambda until: [droplet_settles(gap=g, until=until or 0.5)
                                      for g in (2.0, 3.0, 5.0)],
    "bubble_rise_4x4": lambda until: bubble_rise("bubble_rise_4x4", until=until or 2.0),
    "bubble_rise_8x8": lambda until: bubble_rise("bubble_rise_8x8", until=until or 2.0),
    "dam_break_front": lambda until: dam_break_front(until=until or 0.2),
    "paper_case": lambda until: paper_case(until=until or 10.0),
    "gas_thrown_up": lambda until: [gas_thrown_up(until=until or 0.3, buffer=b)
                                    for b in (True, False)],
    "droplet_thrown_up": lambda until: droplet_thrown_up(until=until or 0.15),
    "tip_into_wall": lambda until: [tip_into_wall(air=a, until=until or 0.15)
                                    for a in (False, True)],
    "void_in_gas": lambda until: [void_in_gas(width=w, dt=dt, until=until or 0.2)
                                  for w, dt in ((4, None), (8, None), (4, 1e-4),
                                                (4, 2e-4), (4, 5e-5))],
}


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m mps2p.tools.ladder",
                                     description="the two-phase ladder's measures")
    parser.add_argument("rungs", nargs="*", help="of %s (default: all)" % ", ".join(RUNGS))
    parser.add_argument("--until", type=float, default=None, help="end time (s)")
    parser.add_argument("--results", metavar="RESULTS_H5",
                        help="rung 4's measures of a run of the paper's case instead "
                             "(suspended water, holes in the gas, per snapshot)")
    args = parser.parse_args(argv)
    if args.results:
        rows = paper_case_measures(args.results)
        late = [r["suspended_fraction"] for r in rows if r["time"] >= 5.0 - 1e-9]
        print(json.dumps({"paper_case": {
            "most_suspended_fraction_from_5s": max(late) if late else None,
            "widest_gas_hole": max(r["widest_gas_hole"] for r in rows), "snapshots": rows}}))
        return 0
    unknown = [name for name in args.rungs if name not in RUNGS]
    if unknown:
        parser.error("unknown rung %s (rungs: %s)" % (", ".join(unknown), ", ".join(RUNGS)))
    for name in args.rungs or list(RUNGS):
        print(json.dumps({name: RUNGS[name](args.until)}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
