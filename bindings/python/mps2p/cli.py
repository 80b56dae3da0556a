"""The `mps2p` command.

    mps2p run SCENE.toml [--out DIR] [--end-time T] [--no-pictures] [--quiet]
    mps2p check SCENE.toml       # read, check and build the scene, print its size
    mps2p info                   # library version and path, parameters and defaults
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
    run_parser.add_argument("--end-time", type=float, default=None,
                            help="stop at this time instead of the scene's end_time")
    run_parser.add_argument("--no-pictures", action="store_true")
    run_parser.add_argument("--quiet", action="store_true")
    check_parser = commands.add_parser("check", help="check a scene file and build it")
    check_parser.add_argument("scene")
    commands.add_parser("info", help="library version, path and parameters")
    args = parser.parse_args(argv)
    try:
        if args.command == "run":
            return _run(args)
        if args.command == "check":
            return _check(args)
        return _info()
    except errors.Error as e:
        print("mps2p: %s" % e, file=sys.stderr)
        return 2


def _run(args):
    from .run import run
    from .scenefile import load
    out = args.out or "out/%s" % load(args.scene).name
    summary = run(args.scene, out, end_time=args.end_time, pictures=not args.no_pictures,
                  log=None if args.quiet else print)
    print("%s: %s at t = %.4g s after %d steps, %.3g particle-steps/s; results in %s"
          % (summary["name"], summary["status"], summary["time_reached"], summary["steps"],
             summary["particle_steps_per_s"] or 0, out))
    return 0 if summary["status"] == "completed" else 1


def _check(args):
    from .scenefile import load
    scene_file = load(args.scene)
    with scene_file.build() as scene:
        print(json.dumps({"scene": args.scene, "name": scene_file.name, "l0": scene_file.l0,
                          "particles": scene.particle_count, "fluids": scene.fluids,
                          "end_time": scene_file.end_time,
                          "probes": [p["name"] for p in scene_file.probes]}, indent=2))
    return 0


def _info():
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
