"""The `mps2p` command.

    mps2p run SCENE [--until T] [--l0 L] [--out DIR] [--threads N|auto] [--no-pictures]
              [--quiet]
    mps2p examples            # the example scenes shipped in the package
    mps2p info [SCENE [--l0 L]]  # without a scene: library version, path, parameters,
                                 # options, statistics; with one: particles, fluids,
                                 # effects, dt, without running (at --l0 if given)
    mps2p check SCENE [--l0 L]   # read, check and build the scene; print it as JSON
    mps2p study [--quick] [--out DIR]   # the accuracy-cost study
    mps2p stability SCENE [--until T] [--l0 L] [--model M] [--out FILE.json]
                              # run with the hard-case checks after every step
    mps2p --version

SCENE is a scene file (TOML) or the name of an example scene (`mps2p examples`).
Exit status: 0 done, 1 the run diverged or its pressure solve failed (stability: or
a check failed), 2 bad input (one line on stderr per problem, nothing written), 130
interrupted.
"""
import argparse
import json
import math
import os
import sys
import warnings

from .. import errors

SCENE_HELP = "a scene file (.toml, docs/scene-files.md) or an example's name (mps2p examples)"


def _time(text):
    """argparse type: a finite time > 0 in seconds."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError("not a number: %r" % text) from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError("must be > 0 and finite, got %r" % text)
    return value


def _threads(text):
    """argparse type: a thread count, 0 (OpenMP's default: every core) to 1024,
    or "auto" (the cores idle when the run starts: run.idle_cores)."""
    if text == "auto":
        return text
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError("not a whole number: %r" % text) from None
    if not 0 <= value <= 1024:
        raise argparse.ArgumentTypeError("must be 0 to 1024, got %r" % text)
    return value


def parser():
    """The command's argument parser (every argument has its help)."""
    top = argparse.ArgumentParser(
        prog="mps2p", description="libmps2p: MPS particle runs from scene files",
        epilog="exit status: 0 done, 1 the run diverged or its solve failed, 2 bad input")
    top.add_argument("--version", action=_VersionAction,
                     help="print the versions of the package and the library, and exit")
    commands = top.add_subparsers(dest="command", required=True, metavar="COMMAND")
    run_parser = commands.add_parser(
        "run", help="run a scene: results.h5 (+ .xdmf for ParaView), series.csv, "
                    "summary.json, pictures")
    run_parser.add_argument("scene", metavar="SCENE", help=SCENE_HELP)
    run_parser.add_argument("--out", metavar="DIR", default=None,
                            help="output folder (default out/<the scene's name>)")
    run_parser.add_argument("--until", metavar="T", type=_time, default=None,
                            help="stop at this time (s) instead of the scene's end_time")
    run_parser.add_argument("--l0", metavar="L", type=_time, default=None,
                            help="another particle spacing (m) than the scene's (its boxes "
                                 "are put on the new lattice: docs/scene-files.md)")
    run_parser.add_argument("--threads", metavar="N|auto", type=_threads, default=None,
                            help="threads of the particle loops (parameter threads; 0 = "
                                 "every core; auto = the cores idle as the run starts, "
                                 "since more threads than free cores are many times "
                                 "slower): the same results bit for bit, faster on a "
                                 "machine with free cores (default: the scene's, else the "
                                 "environment variable MPS2P_THREADS, else 1)")
    run_parser.add_argument("--no-pictures", action="store_true",
                            help="write no PNG pictures (faster; no matplotlib needed)")
    run_parser.add_argument("--quiet", action="store_true", help="no progress bar")
    commands.add_parser("examples", help="list the example scenes shipped in the package")
    info_parser = commands.add_parser(
        "info", help="the library (version, paths, parameters), or a scene without running it")
    info_parser.add_argument("scene", metavar="SCENE", nargs="?",
                             help=SCENE_HELP + "; without it, the library")
    check_parser = commands.add_parser("check", help="check a scene and build it; print it "
                                                     "as JSON")
    check_parser.add_argument("scene", metavar="SCENE", help=SCENE_HELP)
    for command in (info_parser, check_parser):  # what a run at --l0 would build
        command.add_argument("--l0", metavar="L", type=_time, default=None,
                             help="another particle spacing (m) than the scene's")
    study_parser = commands.add_parser("study", help="the accuracy-cost study "
                                                     "(docs/accuracy-cost.md)")
    study_parser.add_argument("--quick", action="store_true",
                              help="two spacings and few variants (minutes, for CI)")
    study_parser.add_argument("--out", metavar="DIR", default="out/study",
                              help="output folder (default out/study)")
    stability_parser = commands.add_parser(
        "stability", help="run a scene with the hard-case checks after every step")
    stability_parser.add_argument("scene", metavar="SCENE", help=SCENE_HELP)
    stability_parser.add_argument("--until", metavar="T", type=_time, default=None,
                                  help="stop at this time (s) instead of the scene's end_time")
    stability_parser.add_argument("--l0", metavar="L", type=_time, default=None,
                                  help="another particle spacing (m)")
    stability_parser.add_argument("--model", metavar="M", default=None,
                                  help="two_phase_model: two_step or two_step_improved")
    stability_parser.add_argument("--out", metavar="FILE", default=None,
                                  help="write the report (JSON) to this file")
    return top


class _VersionAction(argparse.Action):
    """--version: one unwrapped line (argparse's own action wraps it)."""

    def __init__(self, option_strings, dest, help=None):
        super().__init__(option_strings, dest, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        print(_version_line())
        parser.exit()


def _version_line():
    import mps2p
    try:
        from importlib.metadata import PackageNotFoundError, version
        package = version("mps2p")
    except (ImportError, PackageNotFoundError):
        package = "(not installed: from %s)" % mps2p.__path__[0]
    return "mps2p %s, libmps2p %s at %s" % (package, mps2p.__version__, mps2p.library_path)


def _show_warning(message, category, filename, lineno, file=None, line=None):
    print("mps2p: warning: %s" % message, file=sys.stderr)


def main(argv=None):
    """The command; returns its exit status."""
    try:
        try:
            status = _main(argv)
        except SystemExit as e:  # argparse's --help, --version and usage errors
            status = e.code
        sys.stdout.flush()  # here, not at exit, where a closed pipe could not be caught
        return status
    except BrokenPipeError:
        # the reader stopped reading (mps2p info | head): stop quietly, and
        # keep Python from failing again on the closed stdout at exit
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141


def _main(argv):
    args = parser().parse_args(argv)
    warnings.showwarning = _show_warning
    if getattr(args, "scene", None):
        from .examples import resolve_scene
        try:
            resolved = resolve_scene(args.scene)
        except KeyError as e:
            print("mps2p: %s" % e.args[0], file=sys.stderr)
            return 2
        if resolved != args.scene and args.scene.endswith(".toml"):
            # a file name that is not here: say which scene runs instead
            print("mps2p: %s: no such file here; the example scene of that name" % args.scene,
                  file=sys.stderr)
        args.scene = resolved
    try:
        if args.command == "run":
            return _run(args)
        if args.command == "check":
            return _check(args)
        if args.command == "examples":
            return _examples()
        if args.command == "study":
            from .study import study
            study(args.out, quick=args.quick)
            print("study written to %s (study.csv, study.md, *.png)" % args.out)
            return 0
        if args.command == "stability":
            return _stability(args)
        return _info(args)
    except errors.Error as e:
        for line in str(e).splitlines() or [""]:  # a scene file's problems, one a line
            print("mps2p: %s" % line, file=sys.stderr)
        return 2
    except BrokenPipeError:
        raise  # main's
    except OSError as e:  # a file the command writes itself
        print("mps2p: %s%s" % (e.strerror or e, ": %s" % e.filename if e.filename else ""),
              file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("mps2p: interrupted", file=sys.stderr)
        return 130


def _examples():
    from .examples import SCENES, example_names, example_path
    from .scenefile import load
    for name in example_names():
        scene_file = load(example_path(name))
        print("%-26s %s" % (name, scene_file.data["run"].get("description", "")))
    print("\nrun one with: mps2p run NAME (e.g. mps2p run dam_break); the files are in %s"
          % SCENES)
    return 0


def _run(args):
    from .run import auto_threads, run
    from .scenefile import load
    out = args.out or "out/%s" % load(args.scene).name
    if args.threads == "auto":
        args.threads, idle, cores = auto_threads()
        print("mps2p: --threads auto: %d (%.1f of %d cores idle)" % (args.threads, idle, cores),
              file=sys.stderr)
    summary = run(args.scene, out, until=args.until, pictures=not args.no_pictures,
                  progress=not args.quiet, threads=args.threads, l0=args.l0)
    print("%s: %s at t = %.4g s after %d steps, %.3g particle-steps/s; results in %s"
          % (summary["name"], summary["status"], summary["time"], summary["steps"],
             summary["particle_steps_per_second"] or 0, out))
    if summary["fluid_out"]:
        print("%s: %s" % (summary["name"], _left_the_domain(summary["fluid_out"])))
    if summary["status"] != "ok":
        print("mps2p: %s" % summary["reason"], file=sys.stderr)
        return 1
    return 0


def _left_the_domain(count):
    return "%d fluid particle%s left the domain and %s out of the run (parameter out_limit)" % (
        count, "" if count == 1 else "s", "is" if count == 1 else "are")


def _stability(args):
    from .stability import check_run, gas_in_liquid_peak_and_last
    options = {"two_phase_model": args.model} if args.model else None

    def show(row):
        print("t = %.3f s  kinetic %.4g J/m  closest %.3f l0  gas in liquid %s"
              % (row["time"], row["kinetic_energy"], row["closest_pair"],
                 row.get("gas_in_liquid", "-")), flush=True)

    if args.out:  # before the run, not after it: its folder made, or the error now
        from .run import make_output_folder
        if os.path.isdir(args.out):
            raise errors.FileError("--out %s: a folder; the report is a file" % args.out)
        make_output_folder(os.path.dirname(os.path.abspath(args.out)))
    report = check_run(args.scene, until=args.until, l0=args.l0, options=options,
                       sample_every=0.05, progress=show)
    peak, last = gas_in_liquid_peak_and_last(report)
    print("%s: %s at t = %.4g s after %d steps; energy ratio max %.3f; closest pair %.3f l0; "
          "gas in liquid peak %d, last %d" % (args.scene, report["status"], report["time"],
                                              report["steps"], report["energy_ratio_max"],
                                              report["closest_min"], peak, last))
    if report["fluid_out"]:
        print("  %s" % _left_the_domain(report["fluid_out"]))
    for check, message in report["violations"].items():
        print("  %s: %s" % (check, message))
    if args.out:
        with open(args.out, "w") as f:
            json.dump(report, f, indent=1)
    return 0 if report["status"] == "ok" else 1


def _describe(path, l0=None):
    from .run import particle_counts
    from .scenefile import load
    scene_file = load(path)
    if l0 is not None:
        scene_file.l0 = l0
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
    print(json.dumps(_describe(args.scene, args.l0), indent=2))
    return 0


def _info(args):
    if args.scene:
        return _check(args)
    if args.l0 is not None:
        raise errors.SceneFileError("info: --l0 needs a scene (mps2p info SCENE --l0 L)")
    import mps2p
    print("libmps2p %s" % mps2p.__version__)
    print("library: %s" % mps2p.library_path)
    print("header:  %s" % mps2p.header_path)
    print("parameters (default, meaning):")
    for key, (default, description) in mps2p.param_info().items():
        print("  %-24s %-10g %s" % (key, default, description))
    print("options (default; choices: meaning):")
    for key, (default, choices, description) in mps2p.option_info().items():
        print("  %-26s %-17s %s: %s" % (key, default, " | ".join(choices), description))
    print("statistics (meaning):")
    for key, (description, _) in mps2p.stat_info().items():
        print("  %-24s %s" % (key, description))
    return 0


if __name__ == "__main__":
    sys.exit(main())
