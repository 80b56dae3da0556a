"""Runs the reference cases of scripts/compare-bitwise.sh with whichever mps2p
package and library the environment gives (PYTHONPATH, MPS2P_LIBRARY) and
writes each case's positions, velocities and pressures as raw float64 bytes
into OUT/<case>.<field>, with the step count, for a byte-for-byte comparison
of two builds.

    python3 scripts/bitwise_runs.py OUT SCENE_FILE
"""
import os
import sys

import mps2p

try:  # the scene files' module moved with the applications (issue 16)
    from mps2p.tools.scenefile import load
except ImportError:
    from mps2p.scenefile import load


def dam_break(scheme):
    with mps2p.Scene(0.01) as scene:
        if scheme:
            scene.set_option("scheme", scheme)
        water = scene.add_fluid("water", 1000.0, 1e-6)
        scene.add_fluid_box(water, 0.0, 0.0, 0.15, 0.3)
        scene.add_tank(0.0, 0.0, 0.6, 0.7, open_top=True)
        return mps2p.Solver(scene)


def main(out, scene_file):
    os.makedirs(out, exist_ok=True)
    cases = [("dam_break", lambda: dam_break(None), 0.3),
             ("dam_break_koshizuka1996", lambda: dam_break("koshizuka1996"), 0.3),
             ("ikari2003_air", lambda: load(scene_file).make_solver(), 0.05)]
    for name, make, end in cases:
        solver = make()
        solver.advance_to(end)
        for field in ("positions", "velocities", "pressure"):
            with open(os.path.join(out, "%s.%s" % (name, field)), "wb") as f:
                f.write(getattr(solver, field)().tobytes())
        with open(os.path.join(out, name + ".steps"), "w") as f:
            f.write("%d\n" % solver.step_count)
        print("%s: %d particles, %d steps to t = %g s" % (name, solver.particle_count,
                                                          solver.step_count, solver.time))
        solver.close()


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
