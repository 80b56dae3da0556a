"""The accuracy-cost study: what accuracy costs in time.

Sweeps the knobs that trade accuracy for time on two reference problems and
records, for every run, wall time (total and per stage), particle-steps per
second, memory and the errors against references:

- dam break (Martin & Moyce 1952, column a = 0.15 m, 2a high, 0.6 m tank):
  mean |error| of the surge front Z = z/a against both of their series for
  1 <= T <= 2.5 (front_error: 5 points), and against the finest run at T = 1.0,
  1.1, ..., 2.5 (front_error_vs_finest, the convergence measure: the
  experiment's own gate-opening delay keeps every MPS run 10-20 % ahead of it);
- still tank (water 0.3 m deep, 0.3 m wide, the default scheme, 2 s): error of
  the pressure at a probe 0.05 m above the bottom, averaged over the second
  second, against rho g h, and the pressure noise there (standard deviation
  over that second / rho g h);
- two-phase dam break (the paper's case: the same column with air around it,
  the improved two-step model with the drift reaction, fixed dt 2e-4 s, to
  T = 2.3, t = 0.2 s, before the front reaches the far wall): the water's
  front against the finest run at T = 1.0, ..., 2.3 (front_error_vs_finest),
  and, for the record, against Martin & Moyce (front_error: 5 points).

Knobs: particle spacing l0 (spacings that divide every box of the three scenes,
so none is snapped short), CFL number, pressure solver (CHOLMOD, CG at two
tolerances, CG with the IC(0) preconditioner), the Laplacian radius, and the
scheme itself (Koshizuka and Oka's, scheme koshizuka1996, against the default).
`quick` runs the same code on two spacings and fewer variants (none for the
still tank and the two-phase case), small enough for CI.

Output in the folder: study.csv (one row per run), error_vs_time.png (with the
Pareto front), error_vs_l0.png (with the observed order), time_vs_particles.png
(log axes, fitted exponent), and study.md (the numbers in plain words).
"""
import csv
import os
import time as clock

import numpy as np

from ..scene import Scene
from ..solver import Solver
from .pictures import martin_moyce

G = 9.81
COLUMN = 0.15
# a hair past a whole number of spacings: the boxes' edges fall on the lattice
EDGE = 1e-9
# the paper's case at a fixed dt, as the study measured it (the scene itself now takes
# adaptive dt; docs/two-phase.md)
TWO_PHASE = {"dt": 2e-4, "pressure_solver": "cg", "cg_tolerance": 1e-6,
             "gas_cg_tolerance": 1e-4, "two_phase_model": "two_step_improved",
             "interface_reaction": "drift"}
TWO_PHASE_END_T = 2.3


def _dam_break(l0, settings):
    scene = Scene(l0, **settings)
    water = scene.add_fluid("water", 1000.0, 1e-6)
    scene.add_fluid_box(water, 0.0, 0.0, COLUMN + EDGE, 2 * COLUMN + EDGE)
    scene.add_tank(0.0, 0.0, 0.6, 0.7)
    with scene:
        solver = Solver(scene)
    return _follow_front(solver, water, l0, 2.5)


def _two_phase_dam_break(l0, settings):
    merged = dict(TWO_PHASE)
    merged.update(settings)
    scene = Scene(l0, **merged)
    water = scene.add_fluid("water", 1000.0, 1e-6)
    air = scene.add_fluid("air", 1.2, 1.5e-5)
    scene.add_fluid_box(water, 0.0, 0.0, COLUMN + EDGE, 2 * COLUMN + EDGE)
    scene.add_fluid_box(air, COLUMN, 0.0, 0.6 + EDGE, 0.7 + EDGE)
    scene.add_fluid_box(air, 0.0, 2 * COLUMN, COLUMN + EDGE, 0.7 + EDGE)
    scene.add_tank(0.0, 0.0, 0.6, 1.2)
    with scene:
        solver = Solver(scene)
    return _follow_front(solver, water, l0, TWO_PHASE_END_T)


def _follow_front(solver, water, l0, T_end):
    """Steps through T = 1.0, 1.1, ..., T_end and Martin & Moyce's points (both
    series) in [1, T_end], taking the water's front Z = z/a at each: front_error
    is the mean error against Martin & Moyce, _fronts the front on the T grid
    (compared with the finest run's there)."""
    reference = sorted((T, Z) for T_ref, Z_ref in martin_moyce().values()
                       for T, Z in zip(T_ref, Z_ref) if 1.0 <= T <= T_end)
    grid = [round(1.0 + 0.1 * k, 10) for k in range(int(round((T_end - 1.0) / 0.1)) + 1)]
    scale = np.sqrt(2 * G / COLUMN)
    front_at = {}
    started = clock.perf_counter()
    for T in sorted(set(grid) | {T for T, _ in reference}):
        solver.advance_to(T / scale)
        front_at[T] = solver.front(water, 2 * l0) / COLUMN
    wall = clock.perf_counter() - started
    errors = [abs(front_at[T] - Z) / Z for T, Z in reference]
    return solver, wall, {"front_error": float(np.mean(errors)),
                          "_fronts": [front_at[T] for T in grid]}


def _still_tank(l0, settings, depth=0.3, duration=2.0):
    scene = Scene(l0, **settings)
    water = scene.add_fluid("water", 1000.0, 1e-6)
    scene.add_fluid_box(water, 0.0, 0.0, depth + EDGE, depth + EDGE)
    scene.add_tank(0.0, 0.0, depth, depth + 0.05)
    with scene:
        solver = Solver(scene)
    probe = [0.5 * depth, depth / 6]
    expected = 1000.0 * G * (depth - probe[1])
    samples = []
    started = clock.perf_counter()
    for k in range(1, 101):
        solver.advance_to(k * duration / 100)
        if k > 50:
            samples.append(solver.probe([probe])[0][0])
    wall = clock.perf_counter() - started
    samples = np.array(samples)
    return solver, wall, {"pressure_error": float(abs(samples.mean() - expected) / expected),
                          "pressure_noise": float(samples.std() / expected)}


PROBLEMS = {"dam_break": _dam_break, "still_tank": _still_tank,
            "two_phase": _two_phase_dam_break}
FRONT_PROBLEMS = ("dam_break", "two_phase")


def plan(quick):
    """(problem, l0, settings, label) for every run."""
    runs = []
    for problem in PROBLEMS:
        levels = [0.025, 0.0125] if quick else [0.025, 0.0125, 0.00625, 0.003125]
        if problem != "dam_break" and not quick:
            # 2 s of a 14400-particle tank, or 1000 steps of 71,000 particles with
            # two pressure solves each, is past this study's budget
            levels = levels[:3]
        for l0 in levels:
            runs.append((problem, l0, {}, "default"))
        base = levels[-1] if quick else 0.0125
        if problem == "two_phase":
            # dt is fixed (TWO_PHASE) and both solves are CG already
            variants = [] if quick else [
                ("cg ic0", {"cg_preconditioner": "ic0"}),
                ("re_laplacian 2.1", {"re_laplacian": 2.1}),
                ("koshizuka1996", {"scheme": "koshizuka1996"})]
        else:
            variants = [("cfl 0.1", {"cfl": 0.1}), ("cfl 0.4", {"cfl": 0.4}),
                        ("cholmod", {"pressure_solver": "cholmod"}),
                        ("koshizuka1996", {"scheme": "koshizuka1996"})]
        if not quick and problem != "two_phase":
            variants += [("cg 1e-6", {"pressure_solver": "cg", "cg_tolerance": 1e-6}),
                         ("cg ic0 1e-6", {"pressure_solver": "cg", "cg_tolerance": 1e-6,
                                          "cg_preconditioner": "ic0"}),
                         ("re_laplacian 4.0", {"re_laplacian": 4.0}),
                         ("re_laplacian 2.1", {"re_laplacian": 2.1}),
                         ("re_laplacian 2.1, cg ic0 1e-6",
                          {"re_laplacian": 2.1, "pressure_solver": "cg", "cg_tolerance": 1e-6,
                           "cg_preconditioner": "ic0"})]
        if quick and problem == "still_tank":
            continue  # 2 s of still water per run: the quick study keeps the spacings only
        for label, settings in variants:
            runs.append((problem, base, settings, label))
    return runs


def run_one(problem, l0, settings):
    solver, wall, errors = PROBLEMS[problem](l0, settings)
    with solver:
        n, steps = solver.particle_count, solver.step_count
        row = {"problem": problem, "l0": l0, "particles": n, "steps": steps,
               "wall_seconds": wall, "particle_steps_per_second": n * steps / wall,
               "memory_bytes": solver.stat("memory_bytes")}
        for name, stage in solver.stages().items():
            if stage["active"]:
                row["stage_" + name] = stage["seconds"]
    row.update(errors)
    return row


def study(out_dir, quick=False, log=print):
    os.makedirs(out_dir, exist_ok=True)
    rows = []
    for problem, l0, settings, label in plan(quick):
        row = {"variant": label}
        row.update(run_one(problem, l0, settings))
        rows.append(row)
        if log:
            log("%-10s l0 = %-7g %-17s %6.2f s  %s" % (
                problem, l0, label, row["wall_seconds"],
                "front error %.1f %%" % (100 * row["front_error"]) if "front_error" in row
                else "pressure error %.2f %%, noise %.1f %%" % (
                    100 * row["pressure_error"], 100 * row["pressure_noise"])))
    _compare_with_finest(rows)
    _write_csv(os.path.join(out_dir, "study.csv"), rows)
    conclusions = _pictures_and_conclusions(out_dir, rows)
    with open(os.path.join(out_dir, "study.md"), "w") as f:
        f.write(conclusions)
    return rows


def _compare_with_finest(rows):
    """front_error_vs_finest for every run of a front problem but its finest default one."""
    for problem in FRONT_PROBLEMS:
        mine = [r for r in rows if r["problem"] == problem]
        if not mine:
            continue
        finest = min((r for r in mine if r["variant"] == "default"), key=lambda r: r["l0"])
        reference = np.array(finest["_fronts"])
        for r in mine:
            if r is not finest:
                r["front_error_vs_finest"] = float(np.mean(
                    np.abs(np.array(r["_fronts"]) - reference) / reference))
        finest["reference"] = "finest"


def _write_csv(path, rows):
    keys = []
    for row in rows:
        keys += [k for k in row if k not in keys and not k.startswith("_")]
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)


def _error_of(row):
    """The convergence measure: against the finest run (the dam breaks; None for
    the finest itself) or against rho g h (still tank)."""
    if row["problem"] in FRONT_PROBLEMS:
        return row.get("front_error_vs_finest")
    return row["pressure_error"]


def pareto(points):
    """Indices of the points no other point beats in both time and error."""
    order = sorted(range(len(points)), key=lambda k: (points[k][0], points[k][1]))
    front, best = [], float("inf")
    for k in order:
        if points[k][1] < best:
            front.append(k)
            best = points[k][1]
    return front


def observed_order(l0s, errors):
    """Slope of log(error) against log(l0) (least squares)."""
    return float(np.polyfit(np.log(l0s), np.log(errors), 1)[0])


def _pictures_and_conclusions(out_dir, rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    lines = ["# Accuracy-cost study\n"]
    problems = [p for p in PROBLEMS if any(r["problem"] == p for r in rows)]
    fig1, axes1 = plt.subplots(1, len(problems), figsize=(5.5 * len(problems), 4.2),
                               layout="constrained", squeeze=False)
    fig2, axes2 = plt.subplots(1, len(problems), figsize=(5.5 * len(problems), 4.2),
                               layout="constrained", squeeze=False)
    fig3, ax3 = plt.subplots(figsize=(6, 4.2), layout="constrained")
    for (ax1, ax2), problem in zip(zip(axes1[0], axes2[0]), problems):
        mine = [r for r in rows if r["problem"] == problem and _error_of(r) is not None]
        points = [(r["wall_seconds"], _error_of(r)) for r in mine]
        for r, (t, e) in zip(mine, points):
            ax1.loglog(t, 100 * e, "o")
            ax1.annotate("%s, l0 %g" % (r["variant"], r["l0"]), (t, 100 * e), fontsize=7)
        front = pareto(points)
        ax1.loglog([points[k][0] for k in front], [100 * points[k][1] for k in front], "k--",
                   label="Pareto front")
        what = ("front error against the finest run (%)" if problem in FRONT_PROBLEMS
                else "pressure error (%)")
        ax1.set_xlabel("wall time (s)")
        ax1.set_ylabel(what)
        ax1.set_title(problem)
        ax1.legend(fontsize=8)
        levels = sorted((r for r in mine if r["variant"] == "default"), key=lambda r: -r["l0"])
        l0s = np.array([r["l0"] for r in levels])
        errs = np.array([_error_of(r) for r in levels])
        times = np.array([r["wall_seconds"] for r in levels])
        ax2.loglog(l0s, 100 * errs, "o-")
        ax2.set_xlabel("l0 (m)")
        ax2.set_ylabel(what)
        lines.append("## %s\n" % problem)
        if problem in FRONT_PROBLEMS:
            lines.append("Front against Martin & Moyce (mean over 1 <= T <= %g): %s." % (
                2.5 if problem == "dam_break" else TWO_PHASE_END_T, ", ".join(
                "%.1f %% at l0 %g" % (100 * r["front_error"], r["l0"])
                for r in sorted((r for r in rows if r["problem"] == problem
                                 and r["variant"] == "default"), key=lambda r: -r["l0"]))))
            lines.append("The errors below are against the finest run (l0 %g)." % min(
                r["l0"] for r in rows if r["problem"] == problem))
        if len(levels) >= 2 and np.all(errs > 0):
            order = observed_order(l0s, errs)
            ax2.set_title("%s: observed order %.2f" % (problem, order))
            lines.append("Observed order of the error in l0: %.2f (levels %s)." % (
                order, ", ".join("%g" % v for v in l0s)))
            for a, b in zip(levels, levels[1:]):
                lines.append(
                    "Halving l0 from %g to %g m costs %.1f times the wall time and changes the "
                    "error from %.2f %% to %.2f %%." % (
                        a["l0"], b["l0"], b["wall_seconds"] / a["wall_seconds"],
                        100 * _error_of(a), 100 * _error_of(b)))
        ax3.loglog([r["particles"] for r in levels], times, "o-", label=problem)
        if len(levels) >= 2:
            exponent = float(np.polyfit(np.log([r["particles"] for r in levels]),
                                        np.log(times), 1)[0])
            lines.append("Wall time grows as particles^%.2f over these levels (the number of "
                         "steps grows too, as 1/l0)." % exponent)
        on_front = ", ".join("%s at l0 %g" % (mine[k]["variant"], mine[k]["l0"]) for k in front)
        lines.append("Runs on the Pareto front (no other run is both faster and more "
                     "accurate): %s.\n" % on_front)
    ax3.set_xlabel("particles")
    ax3.set_ylabel("wall time (s)")
    ax3.legend()
    fig1.savefig(os.path.join(out_dir, "error_vs_time.png"), dpi=100)
    fig2.savefig(os.path.join(out_dir, "error_vs_l0.png"), dpi=100)
    fig3.savefig(os.path.join(out_dir, "time_vs_particles.png"), dpi=100)
    for fig in (fig1, fig2, fig3):
        plt.close(fig)
    return "\n".join(lines) + "\n"
