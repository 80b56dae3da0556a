"""Hard-case stability checks (issue 9): run a scene file step by step and
check, after every step, what a stable run must keep true.

    no divergence     the solver never reports diverged or failed;
    no NaN            positions and velocities finite;
    inside the tank   every fluid particle inside its tank's walls (x between
                      the side walls' first layers, y above the floor's; open
                      tops may spill liquid, but gas above the walls' top has
                      left: the gas's top is a boundary, effect gas_buffer; a
                      gas particle out of the run, KIND_OUT, has left the
                      domain and so the tank);
    energy            kinetic energy <= potential energy released + work done
                      by the excitation + MARGIN x (the potential energy
                      available at the start + the largest work done); a
                      particle out of the run keeps the potential energy of
                      where it stopped (the library's sums leave it out);
    counts            particles per fluid unchanged (those out of the run
                      included: they keep their fluid);
    spacing           no fluid particle closer than CLOSEST l0 to another
                      particle for more than CLOSEST_STEPS steps in a row.

The margins are documented in docs/two-phase.md; they are properties of a
stable run, not fitted to one. `check_run` returns a report (a dict) with the
first violation of each check, the fluid particles that left the domain and
are out of the run ("fluid_out"; parameter out_limit lets up to its share
of the fluid leave before the run diverges) and the time series the docs
draw from.
"""
import math

import numpy as np

from .. import errors
from ..scene import KIND_FLUID, KIND_OUT
from .scenefile import load

MARGIN = 0.05
CLOSEST = 0.25
CLOSEST_STEPS = 10


def _masses(solver, scene_file):
    densities = [f["density"] for f in scene_file.data.get("fluid", [])]
    ids = solver.fluid_ids()
    kinds = solver.kinds()
    fluid = kinds == KIND_FLUID
    mass = np.zeros(len(ids))
    mass[fluid] = np.array(densities)[ids[fluid]] * scene_file.l0 ** 2
    return mass, fluid, ids


def _light(scene_file, ids, fluid):
    """Per particle: of a light fluid (below light_fraction of the heaviest,
    as the library decides)."""
    densities = np.array([f["density"] for f in scene_file.data.get("fluid", [])])
    threshold = _parameter(scene_file, "light_fraction", 0.1) * densities.max()
    light = np.zeros(len(ids), dtype=bool)
    light[fluid] = densities[ids[fluid]] < threshold
    return light


def _tank_of(scene_file, xy):
    """Per fluid particle, the index of the tank whose box holds it at the
    start (-1: none)."""
    tanks = scene_file.data.get("tank", [])
    owner = np.full(len(xy), -1)
    for k, t in enumerate(tanks):
        x0, y0, x1, y1 = t["box"]
        inside = (xy[:, 0] >= x0) & (xy[:, 0] <= x1) & (xy[:, 1] >= y0) & (xy[:, 1] <= y1)
        owner[(owner < 0) & inside] = k
    return owner, tanks


def check_run(scene_path, until=None, l0=None, options=None, parameters=None,
              sample_every=0.01, progress=None):
    """Runs the scene to `until` (its end_time by default), optionally at
    another spacing `l0` and with `options`/`parameters` overriding the file's,
    checking after every step. Returns the report."""
    scene_file = load(scene_path)
    if l0 is not None:
        scene_file.l0 = float(l0)
    for table, extra in (("options", options), ("parameters", parameters)):
        if extra:
            scene_file.data.setdefault(table, {}).update(extra)
    end = scene_file.end_time if until is None else float(until)
    solver = scene_file.make_solver()
    try:
        return _check(solver, scene_file, end, sample_every, progress)
    finally:
        solver.close()


def _check(solver, scene_file, end, sample_every, progress):
    mass, fluid, ids = _masses(solver, scene_file)
    l0 = scene_file.l0
    xy = solver.positions()
    owner, tanks = _tank_of(scene_file, xy)
    light = _light(scene_file, ids, fluid)
    counts0 = np.bincount(ids[fluid], minlength=len(scene_file.fluids))
    g = np.array(solver.gravity)
    g_size = float(np.hypot(*g))
    up = -g / g_size if g_size > 0 else np.array([0.0, 1.0])
    height = xy @ up
    available = float(np.sum(mass[fluid] * g_size * (height[fluid] - height[fluid].min())))
    potential0 = solver.stat("potential_energy")
    amplitude = _parameter(scene_file, "excitation_acceleration", 0.0)
    period = _parameter(scene_file, "excitation_period", 1.0)
    report = {"status": "ok", "reason": "", "end_time": end, "time": 0.0, "steps": 0,
              "violations": {}, "energy_ratio_max": 0.0, "closest_min": math.inf,
              "closest_streak_max": 0, "fluid_out": 0, "series": []}
    work, work_max, streak = 0.0, 0.0, 0
    next_sample = 0.0

    def violate(check, message):
        report["violations"].setdefault(check, "t = %.4f s: %s" % (solver.time, message))

    while solver.time < end - 1e-12 * max(1.0, end):
        t_start = solver.time
        before = xy
        try:
            solver.advance_to(end, progress=lambda _: True)  # one step, landing on end
        except (errors.DivergedError, errors.SolveError) as e:
            report["status"] = "diverged" if isinstance(e, errors.DivergedError) else "failed"
            report["reason"] = str(e)
            violate("divergence", str(e))
            break
        xy = solver.positions()
        uv = solver.velocities()
        if not (np.isfinite(xy).all() and np.isfinite(uv).all()):
            violate("nan", "non-finite position or velocity")
            break
        gone = solver.kinds() == KIND_OUT  # left the domain, out of the run
        # excitation: the fluid is pushed by -A sin(2 pi t / T) along x over the step
        if amplitude:
            force = -amplitude * math.sin(2.0 * math.pi * t_start / period)
            work += float(np.sum(mass[fluid] * force * (xy[fluid, 0] - before[fluid, 0])))
            work_max = max(work_max, abs(work))
        for k, t in enumerate(tanks):
            # the walls' first layer stands half a spacing outside the box
            x0, y0, x1, y1 = t["box"]
            x0, y0, x1, y1 = x0 - 0.5 * l0, y0 - 0.5 * l0, x1 + 0.5 * l0, y1 + 0.5 * l0
            mine = fluid & (owner == k)
            out = mine & ((xy[:, 0] < x0) | (xy[:, 0] > x1) | (xy[:, 1] < y0) |
                          (light & ((xy[:, 1] > y1) | gone)))
            if out.any():
                i = int(np.flatnonzero(out)[0])
                violate("inside", "particle %d (fluid %s) left tank %d at (%.4f, %.4f)%s" % (
                    i, scene_file.fluids[ids[i]], k, xy[i, 0], xy[i, 1],
                    " and the domain: out of the run" if gone[i] else ""))
        kinetic = solver.stat("kinetic_energy")
        # the potential energy of the particles out of the run, where they stopped
        potential_out = float(np.sum(mass[gone] * g_size * (xy[gone] @ up)))
        released = potential0 - solver.stat("potential_energy") - potential_out
        allowance = released + work + MARGIN * (available + work_max)
        scale = max(released + work, MARGIN * (available + work_max), 1e-300)
        report["energy_ratio_max"] = max(report["energy_ratio_max"], kinetic / scale)
        if kinetic > allowance:
            violate("energy", "kinetic energy %.4g J/m above released %.4g + work %.4g + "
                    "margin %.4g" % (kinetic, released, work,
                                     MARGIN * (available + work_max)))
        closest = solver.stat("closest_pair")
        report["closest_min"] = min(report["closest_min"], closest)
        streak = streak + 1 if closest < CLOSEST else 0
        report["closest_streak_max"] = max(report["closest_streak_max"], streak)
        if streak > CLOSEST_STEPS:
            violate("spacing", "closest pair %.3f l0 for %d steps" % (closest, streak))
        if solver.time >= next_sample - 1e-12:
            report["series"].append(_sample(solver, scene_file, mass, fluid, ids, kinetic,
                                            released, work, closest))
            report["fluid_out"] = report["series"][-1]["fluid_out"]
            next_sample += sample_every
            if progress:
                progress(report["series"][-1])
    counts = np.bincount(solver.fluid_ids()[fluid], minlength=len(scene_file.fluids))
    if not np.array_equal(counts, counts0):
        violate("counts", "particles per fluid %s, at the start %s" % (
            counts.tolist(), counts0.tolist()))
    report["time"] = solver.time
    report["steps"] = solver.step_count
    report["particles"] = dict(zip(scene_file.fluids, counts0.tolist()))
    gone = solver.kinds() == KIND_OUT
    xy = solver.positions()
    potential_out = float(np.sum(mass[gone] * g_size * (xy[gone] @ up)))
    report["series"].append(_sample(solver, scene_file, mass, fluid, ids,
                                    solver.stat("kinetic_energy"),
                                    potential0 - solver.stat("potential_energy") - potential_out,
                                    work, solver.stat("closest_pair")))
    report["fluid_out"] = report["series"][-1]["fluid_out"]
    if report["violations"] and report["status"] == "ok":
        report["status"] = "unstable"
    return report


def _sample(solver, scene_file, mass, fluid, ids, kinetic, released, work, closest):
    row = {"time": solver.time, "kinetic_energy": kinetic, "released": released,
           "work": work, "closest_pair": closest, "max_speed": solver.stat("max_speed"),
           "fluid_out": solver.stat("fluid_out")}
    speed2 = (solver.velocities() ** 2).sum(axis=1)
    for k, name in enumerate(scene_file.fluids):
        mine = fluid & (ids == k)
        row["kinetic_energy_" + name] = float(0.5 * np.sum(mass[mine] * speed2[mine]))
    if solver.stat("two_phase_active"):
        for key in ("gas_in_liquid", "gas_triggered", "gas_enclosed", "gas_joined",
                    "gas_in_bubbles", "gas_pressure_max", "gas_capped"):
            row[key] = solver.stat(key)
    return row


def _parameter(scene_file, key, default):
    return float(scene_file.data.get("parameters", {}).get(key, default))


def gas_in_liquid_peak_and_last(report):
    """(peak, last) of the light particles inside the liquid over the run."""
    values = [row.get("gas_in_liquid", 0.0) for row in report["series"]]
    return (max(values), values[-1]) if values else (0.0, 0.0)
