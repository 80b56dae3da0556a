#!/usr/bin/env python3
"""Side by side with PySPH: its dam_break_2d example against libmps2p on the same
problem, wall time and surge front against Martin & Moyce (1952).

The problem: PySPH's `pysph run dam_break_2d` (a water column 1 m wide and 2 m high at
the left wall of a 4 m x 4 m tank, spacing dx = 0.03 m) to --tf (0.5 s), one thread;
libmps2p's examples/scenes/pysph_dam_break_2d.toml (l0 = 0.03 m, the same column and
tank) to the same time through the `mps2p` command. Each code runs as its own process,
as a user runs it (PySPH's example ends with its own plot, `mps2p run` with its
pictures). Three times per run: the process's wall time, start to exit (interpreter
start, set-up, stepping, output, plots); its CPU time (user + system; both codes run one
thread, so this is what a busy machine disturbs least); and each code's own timer around
its time loop (PySPH's "Run took", libmps2p's summary.json wall_seconds; output writing
included). One untimed warm-up run of each first (PySPH compiles its kernels on its
first run and caches them), then --reps timed repetitions interleaved (PySPH, libmps2p,
PySPH, libmps2p, ...) so that a change of the machine's load hits both; medians are
reported, and the median of each repetition's own libmps2p / PySPH ratio.

The surge front, the same way for both codes: the largest x of the fluid particles
within 2.25 spacings of the floor (y < 0.0675 m: the two lowest rows of either
lattice), read from PySPH's output files (pysph.solver.utils.iter_output) and from
libmps2p's front probe; Z = 1 + (x(t) - x(0)) / a, a = 1 m (the front's advance from
the column's initial edge, so that neither lattice's offset from the wall counts),
against T = t sqrt(2 g / a), interpolated linearly between outputs at Martin & Moyce's
T (both of their series, every point with T <= the run's end). Error: mean and max of
|Z - Z_ref| / Z_ref over those points.

    python3 benchmarks/pysph_compare.py [--reps 3] [--tf 0.5] [--out out/pysph_compare]
        [--pysph-python /path/to/python-with-pysph] [--library build-release/lib/libmps2p.so.0]

Prints a Markdown table and writes runs.csv (one row per run), summary.csv (the
medians) and fronts.csv (Z at Martin & Moyce's T) into --out. With --variants, libmps2p
alone: the scene with each of VARIANTS' settings, one run each without pictures
(variants.csv): what the shipped settings were chosen from. A benchmark, not a test: without PySPH it says so and exits 0.
"""
import argparse
import csv
import json
import os
import platform
import re
import resource
import shutil
import statistics
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SCENE = os.path.join(ROOT, "examples", "scenes", "pysph_dam_break_2d.toml")
FAST_SCENE = os.path.join(ROOT, "examples", "scenes", "pysph_dam_break_2d_fast.toml")
REFERENCE = os.path.join(ROOT, "data", "martin_moyce_1952.csv")
G = 9.81
COLUMN = 1.0        # a, the column's width (m)
SPACING = 0.03      # PySPH's dx and libmps2p's l0 (m)
NEAR_FLOOR = 2.25 * SPACING
KEYS = ("wall_seconds", "cpu_seconds", "solver_seconds")

# Runs in PySPH's interpreter: the front from every output file, as JSON.
PYSPH_READER = r"""
import json, sys
from pysph.solver.utils import get_files, iter_output, load
files = get_files(sys.argv[1])
below = float(sys.argv[2])
rows = []
for solver_data, fluid in iter_output(files, "fluid"):
    x, y = fluid.get("x", "y")
    near = y < below
    rows.append([float(solver_data["t"]), float(x[near].max()) if near.any() else float("nan"),
                 int(solver_data.get("count", -1))])
data = load(files[-1])
arrays = data["arrays"]
print(json.dumps({"rows": rows, "files": len(files),
                  "counts": {k: int(v.get_number_of_particles()) for k, v in arrays.items()},
                  "dt": float(data["solver_data"].get("dt", float("nan")))}))
"""


PYSPH_WITHOUT_PLOT = r"""
import sys
from pysph.examples.dam_break_2d import DamBreak2D
sys.argv = ["dam_break_2d"] + sys.argv[1:]
DamBreak2D().run()   # what `pysph run dam_break_2d` does, less its post_process plot
"""


def martin_moyce(t_end):
    """Martin & Moyce's points (T, Z, a_inch) with T <= T at t_end."""
    with open(REFERENCE) as f:
        lines = [line.strip() for line in f if line.strip() and not line.startswith("#")]
    assert lines[0] == "a_inch,T,Z", lines[0]
    data = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    T_end = t_end * np.sqrt(2 * G / COLUMN)
    keep = data[:, 1] <= T_end + 1e-12
    return data[keep, 1], data[keep, 2], data[keep, 0]


def front_errors(t, x, t_end):
    """Mean and max relative error of Z = 1 + (x - x(0))/a against Martin & Moyce."""
    order = np.argsort(t)
    t, x = np.asarray(t)[order], np.asarray(x)[order]
    ok = np.isfinite(x)
    t, x = t[ok], x[ok]
    T = t * np.sqrt(2 * G / COLUMN)
    Z = 1.0 + (x - x[0]) / COLUMN
    T_ref, Z_ref, _ = martin_moyce(min(t_end, t[-1]))
    Z_at = np.interp(T_ref, T, Z)
    err = np.abs(Z_at - Z_ref) / Z_ref
    if err.size == 0:  # a run ending before Martin & Moyce's first point (T = 0.83)
        return float("nan"), float("nan"), 0, Z_at, T_ref, Z_ref
    return float(err.mean()), float(err.max()), len(err), Z_at, T_ref, Z_ref


def timed(command, env):
    """Runs command; returns the process, its wall time and its CPU time (user + system,
    the child's own: both codes run one thread, so this is the part a busy machine
    disturbs least)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    proc = subprocess.run(command, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return proc, wall, cpu


def pysph_version(python):
    probe = subprocess.run([python, "-c", "import pysph; print(pysph.__version__)"],
                           capture_output=True, text=True)
    return probe.stdout.strip() if probe.returncode == 0 else None


def run_pysph(python, tf, out_dir, env, plot=True):
    shutil.rmtree(out_dir, ignore_errors=True)
    options = ["--no-openmp", "--tf", repr(tf), "-d", out_dir]
    command = ([python, "-m", "pysph.tools.cli", "run", "dam_break_2d"] if plot
               else [python, "-c", PYSPH_WITHOUT_PLOT]) + options
    proc, wall, cpu = timed(command, env)
    if proc.returncode != 0:
        sys.exit("pysph_compare: PySPH failed (%s):\n%s" % (" ".join(command),
                                                          proc.stdout[-3000:] + proc.stderr[-3000:]))
    read = subprocess.run([python, "-c", PYSPH_READER, out_dir, repr(NEAR_FLOOR)],
                          capture_output=True, text=True, env=env)
    if read.returncode != 0:
        sys.exit("pysph_compare: reading PySPH's output failed:\n" + read.stderr[-3000:])
    info = json.loads(read.stdout)
    rows = np.array(info["rows"])
    took = re.search(r"Run took: ([0-9.eE+-]+) secs", proc.stdout)
    mean, worst, points, _, _, _ = front_errors(rows[:, 0], rows[:, 1], tf)
    return {"code": "PySPH", "wall_seconds": wall, "cpu_seconds": cpu,
            "solver_seconds": float(took.group(1)) if took else float("nan"), "steps": int(rows[-1, 2]),
            "fluid": info["counts"].get("fluid", 0),
            "other": sum(v for k, v in info["counts"].items() if k != "fluid"),
            "end_time": float(rows[-1, 0]), "outputs": info["files"],
            "front_mean_error": mean, "front_max_error": worst, "points": points,
            "series": rows[:, :2].tolist()}


class RunEnded(Exception):
    """libmps2p's run stopped before the end (a detected divergence)."""

    def __init__(self, steps, reason):
        super().__init__(reason)
        self.steps, self.reason = steps, reason


def run_mps2p(library, scene, tf, out_dir, env, pictures=True):
    shutil.rmtree(out_dir, ignore_errors=True)
    env = dict(env, MPS2P_LIBRARY=library,
               PYTHONPATH=os.pathsep.join(filter(None, [os.path.join(ROOT, "bindings", "python"),
                                                        env.get("PYTHONPATH")])))
    command = [sys.executable, "-m", "mps2p", "run", scene, "--out", out_dir, "--until", repr(tf),
               "--quiet"] + ([] if pictures else ["--no-pictures"])
    proc, wall, cpu = timed(command, env)
    summary_path = os.path.join(out_dir, "summary.json")
    if proc.returncode != 0 and os.path.exists(summary_path):
        with open(summary_path) as f:
            summary = json.load(f)
        raise RunEnded(summary["steps"], "%s at t = %.4g s: %s" % (
            summary["status"], summary["time"], summary["reason"]))
    if proc.returncode != 0:
        sys.exit("pysph_compare: libmps2p failed (%s):\n%s" % (" ".join(command),
                                                             proc.stdout[-3000:] + proc.stderr[-3000:]))
    with open(os.path.join(out_dir, "summary.json")) as f:
        summary = json.load(f)
    if summary["status"] != "ok":
        sys.exit("pysph_compare: libmps2p run ended %s: %s" % (summary["status"], summary["reason"]))
    series = np.genfromtxt(os.path.join(out_dir, "series.csv"), delimiter=",", names=True)
    mean, worst, points, _, _, _ = front_errors(series["time"], series["front"], tf)
    particles = summary["particles"]
    return {"code": "libmps2p", "wall_seconds": wall, "cpu_seconds": cpu,
            "solver_seconds": summary["wall_seconds"], "steps": summary["steps"],
            "fluid": particles["water"], "other": particles["wall"] + particles["dummy"],
            "end_time": summary["time"], "outputs": None, "version": summary["version"],
            "front_mean_error": mean, "front_max_error": worst, "points": points,
            "series": np.column_stack([series["time"], series["front"]]).tolist()}


# --variants: libmps2p alone, the shipped scene with settings changed (name: parameters
# and options, by the C library's names), one run each
VARIANTS = [
    ("defaults, CG", {"collision_distance": 0.5}),
    ("defaults, CHOLMOD", {"collision_distance": 0.5, "pressure_solver": "cholmod"}),
    ("collision_distance 0.995, CG (shipped)", {}),
    ("collision_distance 0.995, CHOLMOD", {"pressure_solver": "cholmod"}),
    ("+ ppe_source ecs", {"ppe_source": "ecs"}),
    ("+ ppe_source ecs, pressure_gradient corrected (still-water scheme)",
     {"ppe_source": "ecs", "pressure_gradient": "corrected"}),
    ("pressure_gradient corrected alone", {"collision_distance": 0.5,
                                           "pressure_gradient": "corrected"}),
    ("collision_distance 0.995, cfl 0.4", {"cfl": 0.4}),
    ("collision_distance 0.995, re_laplacian 2.1", {"re_laplacian": 2.1}),
    ("collision_distance 0.995, cfl 0.4, re_laplacian 2.1", {"cfl": 0.4, "re_laplacian": 2.1}),
    ("+ cg_tolerance 1e-6 (pysph_dam_break_2d_fast.toml, CG's two-level default)",
     {"cfl": 0.4, "re_laplacian": 2.1, "cg_tolerance": 1e-6}),
    ("+ cg_preconditioner ic0 (the fast scene until 2026-12-02)",
     {"cfl": 0.4, "re_laplacian": 2.1, "cg_tolerance": 1e-6, "cg_preconditioner": "ic0"}),
    ("collision_distance 0.995, cg_preconditioner ic0", {"cg_preconditioner": "ic0"}),
]


def scene_with(text, settings):
    """The scene file's text with [parameters] (numbers) and [options] (strings) set."""
    lines = text.split("\n")
    for key, value in settings.items():
        table = "[options]" if isinstance(value, str) else "[parameters]"
        entry = "%s = %s" % (key, '"%s"' % value if isinstance(value, str) else repr(value))
        lines = [line for line in lines if not re.match(r"\s*%s\s*=" % re.escape(key), line)]
        if table not in lines:
            lines[lines.index("[options]"):lines.index("[options]")] = [table, ""]
        lines.insert(lines.index(table) + 1, entry)
    return "\n".join(lines)


def run_variants(args, env):
    with open(args.scene) as f:
        text = f.read()
    print("| settings | steps | front error mean / max | solver loop s | process CPU s |")
    print("|---|---|---|---|---|")
    rows = []
    for label, settings in VARIANTS:
        folder = os.path.join(args.out, "variant_%d" % len(rows))
        os.makedirs(folder, exist_ok=True)
        scene = os.path.join(folder, "scene.toml")
        with open(scene, "w") as f:
            f.write(scene_with(text, settings))
        try:
            r = run_mps2p(args.library, scene, args.tf, os.path.join(folder, "run"), env,
                          pictures=False)
        except RunEnded as e:
            print("| %s | (%s) | %s | | |" % (label, e.steps, e.reason), flush=True)
            rows.append({"settings": label, "status": e.reason})
            continue
        print("| %s | %d | %.1f %% / %.1f %% | %.2f | %.2f |" % (
            label, r["steps"], 100 * r["front_mean_error"], 100 * r["front_max_error"],
            r["solver_seconds"], r["cpu_seconds"]), flush=True)
        rows.append(dict(settings=label, status="ok", **{k: r[k] for k in (
            "steps", "front_mean_error", "front_max_error", "solver_seconds", "cpu_seconds")}))
    with open(os.path.join(args.out, "variants.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=["settings", "status", "steps", "front_mean_error",
                                               "front_max_error", "solver_seconds",
                                               "cpu_seconds"])
        writer.writeheader()
        writer.writerows(rows)
    return 0




def scene_label(scene):
    return os.path.splitext(os.path.basename(scene))[0]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--reps", type=int, default=3, help="timed repetitions of each code")
    parser.add_argument("--tf", type=float, default=0.5, help="simulated time (s)")
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "pysph_compare"))
    parser.add_argument("--pysph-python", default=os.environ.get("PYSPH_PYTHON", sys.executable),
                        help="a Python interpreter with PySPH installed (default: $PYSPH_PYTHON "
                             "or this one)")
    parser.add_argument("--scene", action="append",
                        help="libmps2p's scene file, repeatable (default: %s and %s)" % (
                            os.path.relpath(SCENE, ROOT), os.path.relpath(FAST_SCENE, ROOT)))
    parser.add_argument("--variants", action="store_true",
                        help="libmps2p alone: the first scene with the settings of VARIANTS, one "
                             "run each, no pictures (variants.csv)")
    parser.add_argument("--library", default=os.environ.get(
        "MPS2P_LIBRARY", os.path.join(ROOT, "build-release", "lib", "libmps2p.so.0")))
    args = parser.parse_args()
    scenes = args.scene or [SCENE, FAST_SCENE]
    args.scene = scenes[0]

    env = dict(os.environ, OMP_NUM_THREADS="1")
    if args.variants:
        os.makedirs(args.out, exist_ok=True)
        return run_variants(args, env)
    version = pysph_version(args.pysph_python)
    if version is None:
        print("pysph_compare: skipped: PySPH is not importable from %s (pip install pysph, or "
              "--pysph-python /path/to/a/python/with/pysph)" % args.pysph_python)
        return 0
    if not os.path.exists(args.library):
        print("pysph_compare: skipped: no libmps2p at %s (meson setup build-release "
              "--buildtype=release && ninja -C build-release, or --library)" % args.library)
        return 0
    os.makedirs(args.out, exist_ok=True)
    # name: (run, the PySPH row it is measured against); PySPH's rows stand for themselves
    codes = {"PySPH": (lambda d: run_pysph(args.pysph_python, args.tf, d, env), None),
             "PySPH, no plot": (lambda d: run_pysph(args.pysph_python, args.tf, d, env,
                                                     plot=False), None)}
    for scene in scenes:
        label = "libmps2p " + scene_label(scene)
        codes[label] = ((lambda d, scene=scene: run_mps2p(args.library, scene, args.tf, d, env)),
                        "PySPH")
        codes[label + ", no pictures"] = (
            (lambda d, scene=scene: run_mps2p(args.library, scene, args.tf, d, env,
                                              pictures=False)), "PySPH, no plot")

    folders = {name: re.sub(r"[^A-Za-z0-9_]+", "_", name) for name in codes}
    for name, (run, _) in codes.items():
        print("warm-up: %s" % name, file=sys.stderr, flush=True)
        run(os.path.join(args.out, "%s_warmup" % folders[name]))
    runs = []
    for rep in range(args.reps):
        for name, (run, _) in codes.items():
            result = run(os.path.join(args.out, "%s_%d" % (folders[name], rep)))
            result.update(code=name, rep=rep)
            runs.append(result)
            print("rep %d %s: %.2f s wall, %.2f s CPU, %.2f s loop, front error mean %.1f %% "
                  "max %.1f %%" % (rep, name, result["wall_seconds"], result["cpu_seconds"],
                                   result["solver_seconds"], 100 * result["front_mean_error"],
                                   100 * result["front_max_error"]), file=sys.stderr, flush=True)

    fields = ["code", "rep", "wall_seconds", "cpu_seconds", "solver_seconds", "steps", "fluid",
              "other", "end_time", "front_mean_error", "front_max_error", "points"]
    with open(os.path.join(args.out, "runs.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(runs)

    medians = {}
    for name in codes:
        mine = [r for r in runs if r["code"] == name]
        medians[name] = dict(mine[-1], version=mine[-1].get("version", version))
        for key in KEYS:
            values = [r[key] for r in mine]
            medians[name][key] = statistics.median(values)
            medians[name][key + "_range"] = (min(values), max(values))
    # each repetition's own ratio against its partner run of the same repetition
    by_rep = {(r["code"], r["rep"]): r for r in runs}
    pairs = {}
    for name, (_, partner) in codes.items():
        if partner:
            pairs[name] = {key: statistics.median(
                [by_rep[(name, k)][key] / by_rep[(partner, k)][key] for k in range(args.reps)])
                for key in KEYS}
    with open(os.path.join(args.out, "summary.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["code", "version", "fluid_particles", "other_particles", "steps",
                         "wall_median_s", "wall_min_s", "wall_max_s", "cpu_median_s",
                         "cpu_min_s", "cpu_max_s", "solver_median_s", "solver_min_s",
                         "solver_max_s", "front_mean_error", "front_max_error", "points",
                         "against", "wall_ratio", "cpu_ratio", "solver_ratio"])
        for name, m in medians.items():
            partner = codes[name][1]
            writer.writerow([name, m["version"], m["fluid"], m["other"], m["steps"]]
                            + ["%.3f" % v for key in KEYS
                               for v in (m[key],) + m[key + "_range"]]
                            + ["%.4f" % m["front_mean_error"], "%.4f" % m["front_max_error"],
                               m["points"], partner or ""]
                            + (["%.3f" % pairs[name][key] for key in KEYS] if partner
                               else ["", "", ""]))
    # the fronts at the reference points, for the record
    with open(os.path.join(args.out, "fronts.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        T_ref, Z_ref, a_inch = martin_moyce(args.tf)
        columns = {}
        for name, m in medians.items():
            s = np.array(m["series"])
            columns[name] = front_errors(s[:, 0], s[:, 1], args.tf)[3]
        writer.writerow(["a_inch", "T", "Z_martin_moyce"] + ["Z_" + n for n in columns])
        for k in range(len(T_ref)):
            writer.writerow([a_inch[k], T_ref[k], Z_ref[k]] + ["%.4f" % columns[n][k]
                                                              for n in columns])

    any_lib = next(m for n, m in medians.items() if codes[n][1])
    print("PySPH %s (dam_break_2d, --no-openmp) and libmps2p %s, OMP_NUM_THREADS=1, to t = %g s, "
          "%d interleaved repetitions after one warm-up each; Python %s.\n"
          % (version, any_lib["version"], args.tf, args.reps, platform.python_version()))
    print("| code | fluid particles | wall/boundary particles | steps | process wall s | "
          "process CPU s | solver loop s | front error mean | front error max |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, m in medians.items():
        print("| %s | %d | %d | %d | %s | %s | %s | %.1f %% | %.1f %% |" % (
            name, m["fluid"], m["other"], m["steps"],
            *["%.2f (%.2f-%.2f)" % ((m[key],) + m[key + "_range"]) for key in KEYS],
            100 * m["front_mean_error"], 100 * m["front_max_error"]))
    print("\nlibmps2p / PySPH, the median of each repetition's own ratio:\n")
    print("| libmps2p | against | steps | process wall | process CPU | solver loop | "
          "front error no worse (mean, max) | bar met (loop, and process like for like) |")
    print("|---|---|---|---|---|---|---|---|")
    for name, ratio in pairs.items():
        partner = codes[name][1]
        lib, ref = medians[name], medians[partner]
        front_ok = (lib["front_mean_error"] <= ref["front_mean_error"]
                    and lib["front_max_error"] <= ref["front_max_error"])
        like_for_like = partner == "PySPH, no plot"
        met = front_ok and ratio["solver_seconds"] <= 0.2 and (
            not like_for_like or (ratio["wall_seconds"] <= 0.2 and ratio["cpu_seconds"] <= 0.2))
        print("| %s | %s | %.3f | %.3f | %.3f | %.3f | %s | %s |" % (
            name, partner, lib["steps"] / ref["steps"], ratio["wall_seconds"],
            ratio["cpu_seconds"], ratio["solver_seconds"], "yes" if front_ok else "no",
            ("yes" if met else "no") if like_for_like else "(pictures: see text)"))
    print("\nSeconds: median (min-max) of the repetitions. Process: the command, start to exit; "
          "solver loop: each code's own timer around its time loop (PySPH's \"Run took\", "
          "libmps2p's summary.json wall_seconds), output writing included. \"PySPH\" is "
          "`pysph run dam_break_2d`, which ends with its example's plot (x_vs_t.png); \"PySPH, "
          "no plot\" runs the same application without it; libmps2p's rows are `mps2p run`, "
          "with its three pictures and with --no-pictures. The issue's bar: libmps2p / PySPH "
          "<= 0.2 at equal or better front error, here read as the solver loop and the "
          "processes without plots both <= 0.2 and both front errors (mean and max) no worse. "
          "Front error over the %d Martin & Moyce points with T <= %.2f."
          % (any_lib["points"], args.tf * np.sqrt(2 * G / COLUMN)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
