"""Running a scene file: snapshots and probe series into one HDF5 file (with
its XDMF sidecar), series.csv, summary.json and pictures."""
import json
import os
import time as clock

import numpy as np

from . import errors
from ._core import version
from .results import Results
from .scenefile import load
from .solver import Solver

PICTURE_SNAPSHOTS = 6


class Probes:
    """Evaluates a scene file's probes on a solver; every probe is one C call."""

    def __init__(self, scene_file, scene):
        self.entries = scene_file.probes
        self.fluid_ids = {name: i for i, name in enumerate(scene_file.fluids)}
        self.l0 = scene_file.l0
        self.names = [p["name"] for p in self.entries]

    def sample(self, solver):
        values = []
        fluid_ids = None
        for p in self.entries:
            kind = p["type"]
            if kind == "pressure":
                values.append(solver.probe([p["at"]])[0][0])
            elif kind == "front":
                try:
                    values.append(solver.front(self.fluid_ids[p["fluid"]], p.get("below", 2 * self.l0)))
                except errors.InvalidArgumentError:
                    values.append(float("nan"))  # no particle of that fluid low enough
            elif kind == "count":
                if fluid_ids is None:
                    fluid_ids = solver.fluid_ids()
                values.append(float(np.count_nonzero(fluid_ids == self.fluid_ids[p["fluid"]])))
            else:
                values.append(solver.stat(p["stat"]))
        return values


def _schedule(end_time, every):
    if every <= 0:
        return [end_time]
    count = int(np.floor(end_time / every + 1e-9))
    times = [k * every for k in range(1, count + 1)]
    if not times or end_time - times[-1] > 1e-9 * end_time:
        times.append(end_time)
    return times


def run(scene_path, out_dir, end_time=None, pictures=True, log=print):
    """Runs the scene file into out_dir; returns the summary (also written as
    summary.json). A divergence ends the run early with status "diverged";
    what was written until then stays."""
    scene_file = load(scene_path)
    end = scene_file.end_time if end_time is None else float(end_time)
    os.makedirs(out_dir, exist_ok=True)
    with scene_file.build() as scene:
        solver = Solver(scene)
        probes = Probes(scene_file, scene)
    n = solver.particle_count
    snapshot_times = set(_schedule(end, scene_file.snapshot_every))
    series_every = scene_file.series_every
    events = sorted(snapshot_times | set(_schedule(end, series_every) if series_every > 0 else []))
    candidates = sorted(snapshot_times | {0.0})
    picks = np.unique(np.linspace(0, len(candidates) - 1, PICTURE_SNAPSHOTS).round().astype(int))
    picture_times = [candidates[k] for k in picks]
    pictures_data, rows = [], []
    status, message = "completed", ""
    started = clock.perf_counter()
    with Results(os.path.join(out_dir, "results.h5"), solver, scene_file.text) as results:
        def sample():
            values = probes.sample(solver)
            rows.append([solver.time, solver.step_count] + values)
            for name, value in zip(probes.names, values):
                results.append_series(name, solver.time, value)

        def snapshot():
            results.write_snapshot(solver)
            if pictures and any(abs(solver.time - t) <= 1e-9 * max(1.0, end)
                                for t in picture_times):
                pictures_data.append((solver.time, solver.positions(), solver.pressure(),
                                      solver.kinds()))

        sample()
        snapshot()
        try:
            for t in events:
                if series_every > 0:
                    solver.advance_to(t)
                    sample()
                else:
                    while solver.time < t - 1e-12 * max(1.0, t):
                        solver.advance_to(t, progress=lambda s: True)  # one step
                        sample()
                if t in snapshot_times:
                    snapshot()
                    if log:
                        log("t = %.4f s, %d steps" % (solver.time, solver.step_count))
        except (errors.DivergedError, errors.SolveError) as e:
            status = "diverged" if isinstance(e, errors.DivergedError) else "solve failed"
            message = str(e)
            if log:
                log("stopped: " + message)
    wall = clock.perf_counter() - started
    steps = solver.step_count
    summary = {
        "library_version": version(), "scene": os.path.abspath(scene_path),
        "name": scene_file.name, "l0": scene_file.l0, "particles": n,
        "fluids": scene_file.fluids, "end_time": end, "time_reached": solver.time,
        "steps": steps, "status": status, "message": message, "wall_time_s": wall,
        "particle_steps_per_s": n * steps / wall if wall > 0 else None,
        "final": solver.stats(), "probes": probes.names,
    }
    _write_series(os.path.join(out_dir, "series.csv"), probes.names, rows)
    with open(os.path.join(out_dir, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    if pictures:
        from .pictures import snapshots_picture, series_picture
        snapshots_picture(os.path.join(out_dir, "snapshots.png"), pictures_data, scene_file.name)
        if probes.names:
            series_picture(os.path.join(out_dir, "series.png"), probes.names, rows)
    solver.close()
    return summary


def _write_series(path, names, rows):
    with open(path, "w") as f:
        f.write(",".join(["time", "step"] + names) + "\n")
        for row in rows:
            f.write(",".join(["%.9g" % row[0], "%d" % row[1]] + ["%.9g" % v for v in row[2:]])
                    + "\n")
