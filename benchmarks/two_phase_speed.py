"""What the paper's water-air case costs (issue 18): wall and CPU seconds per
simulated second, steps, the gas solve's share and iterations, and what the
run computed (air in the water, the front; gas_iterations_sampled: the mean of
the gas CG's iterations in the last step of every 0.01 s), for variants of the scene's
settings, run one after the other in one process.

    python3 benchmarks/two_phase_speed.py [--until T] [--scene FILE] [VARIANT ...]

A VARIANT is key=value pairs joined by commas, parameters or options of the
scene ("threads=2", "dt=0,cg_preconditioner=ic0"); "" is the scene as it is
(the default: that alone). Prints one JSON line per variant. docs/performance.md
has the measurements and the commands."""
import argparse
import json
import os
import time

from mps2p.tools import scenefile

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "examples", "scenes", "ikari2003_dam_break_air.toml")


def settings(variant):
    parameters, options = {}, {}
    for pair in filter(None, variant.split(",")):
        key, _, value = pair.partition("=")
        try:
            parameters[key] = float(value)
        except ValueError:
            options[key] = value
    return parameters, options


def measure(scene, until, variant):
    parameters, options = settings(variant)
    sf = scenefile.load(scene)
    sf.data.setdefault("parameters", {}).update(parameters)
    sf.data.setdefault("options", {}).update(options)
    solver = sf.make_solver()
    with solver:
        wall, cpu = time.perf_counter(), time.process_time()
        iterations = []
        while solver.time < until - 1e-12:
            solver.advance_to(min(until, solver.time + 0.01))
            iterations.append(solver.stat("gas_ppe_iterations"))
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        stages = solver.stages()
        total = sum(stage["seconds"] for stage in stages.values()) or 1.0
        water = sf.fluids.index("water")
        return {"variant": variant, "until": until, "steps": solver.step_count,
                "wall_s_per_simulated_s": wall / until, "cpu_s_per_simulated_s": cpu / until,
                "gas_solve_share": stages["gas_pressure"]["seconds"] / total,
                "gas_iterations_sampled": sum(iterations) / max(1, len(iterations)),
                "gas_in_liquid": solver.stat("gas_in_liquid"),
                "front": solver.front(water, 0.05)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("variants", nargs="*", default=[""])
    parser.add_argument("--until", type=float, default=0.2, help="simulated time (s)")
    parser.add_argument("--scene", default=SCENE)
    args = parser.parse_args()
    for variant in args.variants:
        print(json.dumps(measure(args.scene, args.until, variant)), flush=True)


if __name__ == "__main__":
    main()
