"""Running a scene file: snapshots and probe series into one HDF5 file (with
its XDMF sidecar), series.csv, summary.json and pictures."""
import bisect
import json
import math
import os
import sys
import time as clock

import numpy as np

from .. import errors
from .._core import version
from ..progress import Progress
from ..results import Results
from ..scene import KIND_DUMMY, KIND_FLUID, KIND_OUT, KIND_WALL
from .scenefile import check_schedule, lattice_box, load

PICTURE_SNAPSHOTS = 6
# A vertical gap in the fluid at a wave gauge wider than this (in l0) is air:
# what lies above it (spray, a drop falling past) is not the water's top. A
# column on the lattice, or disordered, has gaps of 1-1.5 l0.
GAUGE_GAP = 2.0


class Probes:
    """Evaluates a scene file's probes on a solver; every probe is one C call."""

    def __init__(self, scene_file):
        self.entries = scene_file.probes
        self.fluid_ids = {name: i for i, name in enumerate(scene_file.fluids)}
        self.l0 = scene_file.l0
        self.names = [p["name"] for p in self.entries]

    def sample(self, solver):
        values = []
        fluid_ids = positions = None
        for p in self.entries:
            kind = p["type"]
            if kind == "pressure":
                values.append(solver.probe([p["at"]])[0][0])
            elif kind == "front":
                try:
                    values.append(solver.front(self.fluid_ids[p["fluid"]],
                                               p.get("below", 2 * self.l0)))
                except errors.InvalidArgumentError:
                    values.append(float("nan"))  # no particle of that fluid low enough
            elif kind == "elevation":
                if positions is None:
                    positions, kinds = solver.positions(), solver.kinds()
                    fluid_ids = solver.fluid_ids()
                near = ((kinds == KIND_FLUID) & (fluid_ids == self.fluid_ids[p["fluid"]]) &
                        (np.abs(positions[:, 0] - p["x"]) <= p.get("half_width", self.l0)))
                values.append(water_top(positions[near, 1], self.l0))
            elif kind == "count":
                if fluid_ids is None:
                    fluid_ids = solver.fluid_ids()
                values.append(float(np.count_nonzero(fluid_ids == self.fluid_ids[p["fluid"]])))
            else:
                values.append(solver.stat(p["stat"]))
        return values


def water_top(heights, l0):
    """A wave gauge's reading from the heights of the fluid's particles at
    it: the top of the column that rises from the lowest of them through
    gaps of at most GAUGE_GAP l0, plus half a spacing (the water's top), as
    a wire gauge reads the water that wets it from below; spray above a
    larger gap is not the water's top. nan where there is none (dry)."""
    if len(heights) == 0:
        return float("nan")
    heights = np.sort(heights)
    gaps = np.flatnonzero(np.diff(heights) > GAUGE_GAP * l0)
    top = heights[gaps[0]] if len(gaps) else heights[-1]
    return float(top) + 0.5 * l0


def _schedule(end_time, every):
    if every <= 0:
        return [end_time]
    count = int(np.floor(end_time / every + 1e-9))
    times = [k * every for k in range(1, count + 1)]
    if not times or end_time - times[-1] > 1e-9 * end_time:
        times.append(end_time)
    # the last is the end itself (6 x 0.05 is 0.30000000000000004, past 0.3)
    times[-1] = end_time
    return times


def particle_counts(solver, fluid_names):
    """Particles per fluid in the run, walls, dummies, and (when any) the
    fluid particles that left the domain and are out of the run ("out")."""
    kinds, ids = solver.kinds(), solver.fluid_ids()
    counts = {name: int(np.count_nonzero((kinds == KIND_FLUID) & (ids == k)))
              for k, name in enumerate(fluid_names)}
    counts["wall"] = int(np.count_nonzero(kinds == KIND_WALL))
    counts["dummy"] = int(np.count_nonzero(kinds == KIND_DUMMY))
    out = int(np.count_nonzero(kinds == KIND_OUT))
    if out:
        counts["out"] = out
    return counts


# More particles than this, and the command says so before the run: a scene
# written in centimetres at l0 = 0.01 builds 10,000 times the particles meant.
LONG_RUN_PARTICLES = 1_000_000


def run(scene_path, out_dir, until=None, pictures=True, progress=False, threads=None,
        l0=None):
    """Runs the scene file into out_dir; returns the summary (also written as
    summary.json). A scene that cannot be read or built raises before anything
    is written. A divergence ends the run early with status "diverged": the last
    good state is written as a final snapshot and everything so far is kept.
    threads, when given, replaces the scene's parameter threads (the results do
    not depend on it); l0 the scene's particle spacing."""
    scene_file = load(scene_path)
    if l0 is not None:
        scene_file.l0 = float(l0)
    if threads is not None:
        scene_file.data.setdefault("parameters", {})["threads"] = float(threads)
    end = scene_file.end_time if until is None else float(until)
    if not (end > 0 and math.isfinite(end)):
        raise errors.SceneFileError("%s: the end time must be > 0 and finite, got %r"
                                    % (scene_path, until))
    problem = check_schedule(end, scene_file.snapshot_every, scene_file.series_every)
    if problem:
        key, reason = problem
        if until is not None:  # the file's schedule was fine up to its own end_time
            key = "--until %g with %s" % (end, key)
        raise errors.SceneFileError("%s: %s: %s" % (scene_path, key, reason))
    if pictures and not pictures_available():
        print("mps2p: warning: no pictures: matplotlib is not installed "
              "(pip install matplotlib)", file=sys.stderr)
        pictures = False
    solver = scene_file.make_solver()
    try:
        make_output_folder(out_dir)
        clear_previous_run(out_dir)
    except errors.Error:
        solver.close()
        raise
    probes = Probes(scene_file)
    n = solver.particle_count
    snapshot_times = set(_schedule(end, scene_file.snapshot_every))
    wanted = [t for t in scene_file.picture_times or [] if t <= end]
    if wanted:
        scheduled = snapshot_times | {0.0}
        # the start, always; the end too when --until cut the asked times short
        shortened = len(wanted) < len(scene_file.picture_times)
        picture_times = sorted({_on_schedule(t, scheduled, end)
                                for t in wanted + [0.0] + ([end] if shortened else [])})
        snapshot_times |= set(t for t in picture_times if t > 0)
    else:  # none asked for, or none before a shortened run's end
        candidates = sorted(snapshot_times | {0.0})
        picks = np.unique(np.linspace(0, len(candidates) - 1,
                                      PICTURE_SNAPSHOTS).round().astype(int))
        picture_times = [candidates[k] for k in picks]
    series_every = scene_file.series_every
    series_times = _schedule(end, series_every) if series_every > 0 else []
    events = _merged(snapshot_times, series_times, end)
    pictures_data, rows = [], []
    status, reason, diverged_particle = "ok", "", -1
    if progress is True:  # the command's: what is about to run, before its bar
        counts = particle_counts(solver, scene_file.fluids)
        print("%s: %d particles (%s), l0 = %g m, to t = %g s%s"
              % (scene_file.name, n, ", ".join("%s %d" % kv for kv in counts.items()),
                 scene_file.l0, end,
                 "; over %s: a long run (are the scene's lengths in metres?)"
                 % format(LONG_RUN_PARTICLES, ",") if n > LONG_RUN_PARTICLES else ""),
              file=sys.stderr, flush=True)
    bar = Progress(end, n, progress)
    started = clock.perf_counter()
    scene_text = scene_file.text
    if l0 is not None:  # the file as run: its l0 replaced (the results say l0 too)
        scene_text = "# run with l0 = %r (mps2p run --l0)\n%s" % (scene_file.l0, scene_text)
    with Results(os.path.join(out_dir, "results.h5"), solver, scene_text) as results:
        def sample():
            values = probes.sample(solver)
            rows.append([solver.time, solver.step_count] + values)
            for name, value in zip(probes.names, values):
                if math.isfinite(value):  # no value: a front with no water low enough yet
                    results.append_series(name, solver.time, value)

        def snapshot(force_picture=False):
            results.write_snapshot(solver)
            if pictures and (force_picture or any(abs(solver.time - t) <= 1e-9 * max(1.0, end)
                                                  for t in picture_times)):
                pictures_data.append(snapshot_arrays(solver))

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
                        bar.update(solver)
                if t in snapshot_times:
                    snapshot()
                bar.update(solver)
        except (errors.DivergedError, errors.SolveError) as e:
            status = "diverged" if isinstance(e, errors.DivergedError) else "failed"
            reason = str(e)
            snapshot(force_picture=True)  # the last good state
            diverged_particle = int(solver.stat("diverged_particle"))
        bar.update(solver, final=True)
    wall = clock.perf_counter() - started
    steps = solver.step_count
    stages = solver.stages()
    effects = solver.effects()
    summary = {
        "status": status,
        "reason": reason,
        "time": solver.time,
        "steps": steps,
        "wall_seconds": wall,
        "threads": int(scene_file.threads()),  # a count (the parameter is a double)
        "threads_used": solver.stat("threads"),
        "stage_seconds": {k: v["seconds"] for k, v in stages.items() if v["active"]},
        "stage_calls": {k: v["calls"] for k, v in stages.items() if v["active"]},
        "particles": particle_counts(solver, scene_file.fluids),
        "effects": {k: {"active": a, "reason": r} for k, (a, r) in effects.items()},
        "version": version(),
        "name": scene_file.name,
        "scene": os.path.abspath(scene_path),
        "l0": scene_file.l0,
        "end_time": end,
        "particle_steps_per_second": n * steps / wall if wall > 0 else None,
        "memory_bytes": solver.stat("memory_bytes"),
        "final": solver.stats(),
        "probes": probes.names,
        "diverged_particle": diverged_particle,
        # out of the run, not diverged: up to parameter out_limit's share may leave
        "fluid_out": solver.stat("fluid_out"),
    }
    _write_series(os.path.join(out_dir, "series.csv"), probes.names, rows)
    with open(os.path.join(out_dir, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    if pictures:
        from .pictures import (front_picture, series_picture, snapshots_picture,
                               velocity_picture, zoom_picture)
        title = "%s (libmps2p %s, l0 = %g m)" % (scene_file.name, version(), scene_file.l0)
        snapshots_picture(os.path.join(out_dir, "snapshots.png"), pictures_data, title,
                          scene_file.fluids, by="pressure")
        if len(scene_file.fluids) > 1:
            snapshots_picture(os.path.join(out_dir, "snapshots_phase.png"), pictures_data,
                              title, scene_file.fluids, by="phase")
            densities = [f["density"] for f in scene_file.data["fluid"]]
            for k, name in enumerate(scene_file.fluids):
                if densities[k] < max(densities):
                    velocity_picture(os.path.join(out_dir, "velocity_%s.png" % name),
                                     pictures_data, title, scene_file.fluids, k)
        if diverged_particle >= 0 and pictures_data:
            zoom_picture(os.path.join(out_dir, "divergence.png"), pictures_data[-1],
                         diverged_particle, 10 * scene_file.l0, title, scene_file.fluids,
                         reason)
        if probes.names:
            series_picture(os.path.join(out_dir, "series.png"), scene_file.probes, rows,
                           title)
        tanks = scene_file.data.get("tank", [])
        tank = lattice_box(tanks[0]["box"], scene_file.l0) if tanks else None
        origin, wall = (tank[0], tank[2]) if tank else (0.0, None)
        for p in scene_file.probes:
            if p["type"] == "front" and "compare" in p:
                k = probes.names.index(p["name"])
                data = np.array([[r[0], r[2 + k]] for r in rows])
                front_picture(os.path.join(out_dir, "front.png"), data, p["column_width"],
                              title, origin=origin, wall=wall, spacing=scene_file.l0)
    solver.close()
    return summary


def pictures_available():
    """True when matplotlib can be imported (the pictures need it)."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        return False
    return True


def _cpu_quota():
    """The cores a container's CPU quota allows (cgroup v2 cpu.max or v1
    cfs_quota_us over cfs_period_us, rounded up), or None without one."""
    for path, split in (("/sys/fs/cgroup/cpu.max", lambda text: text.split()),
                        ("/sys/fs/cgroup/cpu/cpu.cfs_quota_us", None)):
        try:
            with open(path) as f:
                text = f.read()
            if split:
                quota, period = split(text)
            else:
                quota = text
                with open("/sys/fs/cgroup/cpu/cpu.cfs_period_us") as f:
                    period = f.read()
            quota, period = int(quota), int(period)
        except (OSError, ValueError):
            continue  # no such file, or "max" / -1: no quota there
        if quota > 0 and period > 0:
            return -(-quota // period)
    return None


def idle_cores(sample=0.3):
    """(idle, cores): how much of the CPUs this process may run on (its
    affinity, at most a container's quota) was idle over `sample` seconds,
    in CPUs, from Linux's /proc/stat (where it cannot be read: all of them).
    The quota caps the count only: what a container's other jobs use of a
    host's idle CPUs is not seen. OpenMP's threads wait for each other by
    spinning: on a machine another job shares, more threads than free cores
    made the main job's runs 4 to 100 times slower (docs/performance.md)."""
    allowed = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else None
    cores = len(allowed) if allowed else (os.cpu_count() or 1)
    cores = max(1, min(cores, _cpu_quota() or cores))

    def times():
        """{cpu: (idle, total)} of the allowed CPUs, in clock ticks"""
        found = {}
        with open("/proc/stat") as f:
            for line in f:
                name, *fields = line.split()
                if not name.startswith("cpu") or name == "cpu":
                    continue
                cpu = int(name[3:])
                if allowed is None or cpu in allowed:
                    # user nice system idle iowait irq softirq steal (guest time
                    # is counted in user and nice already)
                    ticks = [int(v) for v in fields[:8]]
                    found[cpu] = (ticks[3] + ticks[4], sum(ticks))
        return found
    try:
        before = times()
        clock.sleep(sample)
        after = times()
    except (OSError, ValueError, IndexError):
        return float(cores), cores
    idle = 0.0
    for cpu, (idle1, total1) in after.items():
        idle0, total0 = before.get(cpu, (idle1, total1))
        idle += (idle1 - idle0) / (total1 - total0) if total1 > total0 else 1.0
    if not after:
        return float(cores), cores
    return min(float(cores), idle), cores


def auto_threads():
    """(threads, idle, cores): `--threads auto`'s count, the idle cores
    rounded, at least 1 (idle_cores)."""
    idle, cores = idle_cores()
    return max(1, min(cores, round(idle))), idle, cores


def make_output_folder(path):
    """Creates the output folder (and its parents), or raises FileError with
    the reason: a file in the way, no permission, a read-only place."""
    if os.path.exists(path) and not os.path.isdir(path):
        raise errors.FileError("output folder %s: a file of that name is in the way" % path)
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as e:
        raise errors.FileError("output folder %s: cannot create it: %s"
                               % (path, e.strerror or e)) from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise errors.FileError("output folder %s: not writable" % path)


# What a run writes: a run into a folder that holds an earlier run's removes
# these first, so that no earlier picture (a divergence.png, a front.png the
# new scene does not draw) sits beside the new results as if it were theirs.
RUN_FILES = ("summary.json", "series.csv", "results.h5", "results.xdmf", "snapshots.png",
             "snapshots_phase.png", "series.png", "front.png", "divergence.png")


def clear_previous_run(path):
    """Removes the files an earlier run wrote into path (RUN_FILES and the
    velocity_<fluid>.png pictures); nothing else in the folder."""
    names = [n for n in os.listdir(path)
             if n in RUN_FILES or (n.startswith("velocity_") and n.endswith(".png"))]
    for name in names:
        target = os.path.join(path, name)
        if os.path.isfile(target) or os.path.islink(target):
            try:
                os.remove(target)
            except OSError as e:
                raise errors.FileError("output folder %s: cannot remove the earlier run's %s: %s"
                                       % (path, name, e.strerror or e)) from None


def _merged(snapshot_times, series_times, end):
    """The sorted times to stop at: the snapshot times, and the series times
    that are not one of them (0.3 = 6 x 0.05 and 60 x 0.005 differ in the last
    bit: one stop, the snapshot's, not two)."""
    ordered = sorted(snapshot_times)
    tolerance = 1e-9 * max(1.0, end)
    events = set(ordered)
    for t in series_times:
        k = bisect.bisect_left(ordered, t - tolerance)
        if not (k < len(ordered) and ordered[k] <= t + tolerance):
            events.add(t)
    return sorted(events)


def _on_schedule(t, times, end):
    """t, or the scheduled time it stands for (0.15 and 3 x 0.05 are one time)."""
    near = [s for s in times if abs(s - t) <= 1e-9 * max(1.0, end)]
    return near[0] if near else t


def snapshot_arrays(solver):
    """What the pictures draw from one snapshot."""
    return {"time": solver.time, "positions": solver.positions(),
            "velocities": solver.velocities(), "pressure": solver.pressure(),
            "kinds": solver.kinds(), "fluid_ids": solver.fluid_ids()}


def _write_series(path, names, rows):
    with open(path, "w") as f:
        f.write(",".join(["time", "step"] + names) + "\n")
        for row in rows:
            f.write(",".join(["%.9g" % row[0], "%d" % row[1]] + ["%.9g" % v for v in row[2:]])
                    + "\n")
