"""The `mps2p` command.

    mps2p run SCENE.toml [--until T] [--out DIR] [--no-pictures] [--quiet]
    mps2p info [SCENE.toml]   # without a scene: library version, path, parameters;
                              # with one: particles, fluids, effects, dt, without running
    mps2p check SCENE.toml    # read, check and build the scene; print it as JSON
    mps2p study [--quick] [--out DIR]   # the accuracy-cost study
    mps2p stability SCENE.toml [--until T] [--l0 L] [--model M] [--out FILE.json]
                              # run with the hard-case checks after every step

Exit status: 0 done, 1 the run diverged or its pressure solve failed (stability: or
a check failed), 2 bad input.
"""
import argparse
import json
import sys

from . import errors


def main(argv=None):
    parser = argparse.ArgumentParser(prog="mps2p", description="libmps2p: MPS particle runs")
    commands = parser.add_subparsers(dest="command", required=True)
    run_parser = commands.add_parser("run", help="run a scene file")
    run_parser.add_argument("scene")
    run_parser.add_argument("--out", default=None, help="output folder (default out/<name>)")
    run_parser.add_argument("--until", type=float, default=None,
                            help="stop at this time (s) instead of the scene's end_time")
    run_parser.add_argument("--no-pictures", action="store_true")
    run_parser.add_argument("--quiet", action="store_true", help="no progress bar")
    info_parser = commands.add_parser("info", help="the library, or a scene without running it")
    info_parser.add_argument("scene", nargs="?")
    check_parser = commands.add_parser("check", help="check a scene file and build it")
    check_parser.add_argument("scene")
    study_parser = commands.add_parser("study", help="the accuracy-cost study")
    study_parser.add_argument("--quick", action="store_true",
                              help="two spacings and few variants (for CI)")
    study_parser.add_argument("--out", default="out/study")
    stability_parser = commands.add_parser(
        "stability", help="run a scene with the hard-case checks after every step")
    stability_parser.add_argument("scene")
    stability_parser.add_argument("--until", type=float, default=None)
    stability_parser.add_argument("--l0", type=float, default=None,
                                  help="another particle spacing (m)")
    stability_parser.add_argument("--model", default=None,
                                  help="two_phase_model: two_step or two_step_improved")
    stability_parser.add_argument("--out", default=None, help="write the report (JSON) here")
    args = parser.parse_args(argv)
    try:
        if args.command == "run":
            return _run(args)
        if args.command == "check":
            return _check(args)
        if args.command == "study":
            from .study import study
            study(args.out, quick=args.quick)
            print("study written to %s (study.csv, study.md, *.png)" % args.out)
            return 0
        if args.command == "stability":
            return _stability(args)
        return _info(args)
    except errors.Error as e:
        print("mps2p: %s" % e, file=sys.stderr)
        return 2


def _run(args):
    from .run import run
    from .scenefile import load
    out = args.out or "out/%s" % load(args.scene).name
    summary = run(args.scene, out, until=args.until, pictures=not args.no_pictures,
                  progress=not args.quiet)
    print("%s: %s at t = %.4g s after %d steps, %.3g particle-steps/s; results in %s"
          % (summary["name"], summary["status"], summary["time"], summary["steps"],
             summary["particle_steps_per_second"] or 0, out))
    if summary["status"] != "ok":
        print("mps2p: %s" % summary["reason"], file=sys.stderr)
        return 1
    return 0


def _stability(args):
    from .stability import check_run, gas_in_liquid_peak_and_last
    options = {"two_phase_model": args.model} if args.model else None

    def show(row):
        print("t = %.3f s  kinetic %.4g J/m  closest %.3f l0  gas in liquid %s"
              % (row["time"], row["kinetic_energy"], row["closest_pair"],
                 row.get("gas_in_liquid", "-")), flush=True)

    report = check_run(args.scene, until=args.until, l0=args.l0, options=options,
                       sample_every=0.05, progress=show)
    peak, last = gas_in_liquid_peak_and_last(report)
    print("%s: %s at t = %.4g s after %d steps; energy ratio max %.3f; closest pair %.3f l0; "
          "gas in liquid peak %d, last %d" % (args.scene, report["status"], report["time"],
                                              report["steps"], report["energy_ratio_max"],
                                              report["closest_min"], peak, last))
    for check, message in report["violations"].items():
        print("  %s: %s" % (check, message))
    if args.out:
        with open(args.out, "w") as f:
            json.dump(report, f, indent=1)
    return 0 if report["status"] == "ok" else 1


def _describe(path):
    from .run import particle_counts
    from .scenefile import load
    scene_file = load(path)
    with scene_file.make_solver() as solver:
        return {
            "scene": path, "name": scene_file.name, "l0": scene_file.l0,
            "end_time": scene_file.end_time,
            "particles": particle_counts(solver, scene_file.fluids),
            "fluids": [{"name": f["name"], "density": f["density"],
                        "viscosity": f["viscosity"]} for f in scene_file.data.get("fluid", [])],
            "effects": {k: {"active": a, "reason": r} for k, (a, r) in solver.effects().items()},
            "stages": [k for k, v in solver.stages().items() if v["active"]],
            "dt_first_step": solver.stat("dt_next"),
            "probes": [p["name"] for p in scene_file.probes],
        }


def _check(args):
    print(json.dumps(_describe(args.scene), indent=2))
    return 0


def _info(args):
    if args.scene:
        return _check(args)
    import mps2p
    print("libmps2p %s" % mps2p.__version__)
    print("library: %s" % mps2p.library_path)
    print("header:  %s" % mps2p.header_path)
    print("parameters (default, meaning):")
    for key, (default, description) in mps2p.param_info().items():
        print("  %-24s %-10g %s" % (key, default, description))
    return 0


if __name__ == "__main__":
    sys.exit(main())
