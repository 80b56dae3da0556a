"""The collision model's core (parameter collision_core; docs/validation.md,
"Spray meeting spray"): two water particles alone in the air, closer than
half a spacing and meeting head on, the simplest case of the spray that
stopped a newcomer's weir scene at l0 = 0.0025 m."""
import numpy as np
import pytest

import mps2p


def meeting_pair(core, steps=20):
    """Two water particles 0.4 l0 apart meeting at 2 m/s (l0 = 2.5 mm, dt
    1e-4 s: the damper gives a fifth of its impulse a step): their distance
    after `steps` steps, in l0, or the error that stopped the run."""
    l0 = 0.0025
    with mps2p.Scene(l0) as scene:
        water = scene.add_fluid("water", 1000.0, 1e-6)
        scene.add_particles(np.array([[0.0, 0.5], [0.4 * l0, 0.5]]), np.array([0, 0]),
                            np.array([water, water]), np.array([[1.0, 0.0], [-1.0, 0.0]]))
        scene.set_domain(-0.1, -0.5, 0.1, 1.0)
        scene.set_param("collision_core", core)
        scene.set_param("dt", 1e-4)
        solver = mps2p.Solver(scene)
    with solver:
        try:
            for _ in range(steps):
                solver.step()
        except mps2p.DivergedError as e:
            return str(e)
        x = solver.positions()
        return float(np.hypot(*(x[1] - x[0]))) / l0


def test_a_pair_inside_the_core_loses_its_whole_approach():
    """With the core (the default scheme's 0.5 l0) the pair's approach goes
    in one step and it parts (restitution 0.2); without it the damper's
    fifth a step lets the pair overlap, its number density passes beta n0 and
    the pressure solve asks 3e8 Pa of it: the run stops."""
    assert mps2p.Scene(0.01).get_param("collision_core") == 0.5
    parted = meeting_pair(0.5)
    assert isinstance(parted, float) and parted > 0.4, parted
    stopped = meeting_pair(0.0)
    assert isinstance(stopped, str) and "pressure" in stopped, stopped
