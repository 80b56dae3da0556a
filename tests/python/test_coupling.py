"""Coupling through the binding: bodies, the force on a wall, host-driven
motion, gravity changes and windows (the numbers are the C library's; these
check the binding carries them)."""
import numpy as np
import pytest

import mps2p


def tank_with_piston():
    scene = mps2p.Scene(0.02, pressure_solver="cg")
    water = scene.add_fluid("water", 1000.0, 1e-6)
    scene.add_fluid_box(water, 0.0, 0.0, 0.4, 0.2)
    scene.add_tank(0.0, 0.0, 0.4, 0.3)
    piston = scene.assign_body("right_wall", 0.4, -0.1, 0.6, 0.4)
    assert scene.body_count == 2
    return scene, piston


def test_bodies_force_motion_gravity_windows():
    scene, piston = tank_with_piston()
    with scene, mps2p.Solver(scene) as solver:
        names = [name for name, _ in solver.bodies()]
        assert names == ["walls", "right_wall"]
        ids = solver.body_ids()
        assert ids.shape == (solver.particle_count,)
        assert np.count_nonzero(ids == piston) == solver.bodies()[piston][1] > 0
        steps = solver.advance_window(0.1)
        assert steps > 0 and solver.time == pytest.approx(0.1, abs=1e-12)
        force, moment = solver.body_force(piston)
        assert force[0] > 0  # the water pushes the right wall outwards
        water_part, _ = solver.body_force(piston, fluid_id=0)
        assert np.allclose(water_part, force)
        # the same force particle by particle (a deforming structure's loads)
        loads = solver.wall_loads(piston)
        assert loads.shape == (solver.particle_count, 2)
        assert not loads[ids != piston].any() and loads[ids == piston].any()
        total = np.zeros(2)
        for row in loads[ids == piston]:  # in index order, as body_force sums
            total += row
        assert (total == force).all()
        with pytest.raises(mps2p.InvalidArgumentError):
            solver.wall_loads(piston, fluid_id=3)
        before = solver.positions()[ids == piston]
        solver.set_body_motion(piston, velocity=(-0.05, 0.0))
        solver.advance_window(0.12)
        moved = solver.positions()[ids == piston]
        assert np.allclose(moved[:, 0] - before[:, 0], -0.05 * 0.02, atol=1e-12)
        solver.gravity = (1.0, -9.81)
        assert solver.gravity == (1.0, -9.81)
        solver.set_body_forces(np.zeros((solver.particle_count, 2)))
        solver.set_body_forces(None)
        with pytest.raises(mps2p.InvalidArgumentError):
            solver.body_force(7)


def test_state_save_restore_is_bitwise():
    scene, piston = tank_with_piston()
    with scene, mps2p.Solver(scene) as solver:
        solver.advance_window(0.05)
        state = solver.save_state()
        solver.set_body_motion(piston, velocity=(-0.05, 0.0))
        solver.advance_window(0.08)
        first = (solver.positions(), solver.pressure(), solver.time, solver.step_count)
        solver.restore_state(state)
        assert solver.time == pytest.approx(0.05, abs=1e-15)
        solver.set_body_motion(piston, velocity=(-0.05, 0.0))
        solver.advance_window(0.08)
        assert solver.positions().tobytes() == first[0].tobytes()
        assert solver.pressure().tobytes() == first[1].tobytes()
        assert (solver.time, solver.step_count) == first[2:]
        state.close()
        with pytest.raises(ValueError, match="closed"):
            solver.restore_state(state)
