"""Particle shifting (parameter shifting, docs/method.md step 7): after the
correction each fluid particle off the free surface moves by
shifting u_max dt sum_j (rbar_i / r_ij)^2 e_ji over its neighbours within
re_density, u_max the fastest fluid particle's speed. Checked against that
formula, from a run without it."""
import numpy as np
import pytest

import mps2p

L0, DT = 0.01, 1e-3


def one_step(shifting, offset, row=5):
    """A 20 x 10 block of water moving right at 0.5 m/s without gravity in a
    closed box, the particle in the block's middle column and the given row
    moved `offset` l0 toward its right neighbour; positions, velocities and
    kinds after one step, and that particle's index."""
    with mps2p.Scene(L0) as scene:
        scene.set(gravity_y=0.0, dt=DT, shifting=shifting)
        water = scene.add_fluid("water", 1000.0, 1e-6)
        xs = L0 * (np.arange(20) + 0.5) + 0.1
        ys = L0 * (np.arange(10) + 0.5)
        grid = np.array(np.meshgrid(xs, ys, indexing="ij")).reshape(2, -1).T
        middle = int(np.argmin(np.hypot(grid[:, 0] - xs[10], grid[:, 1] - ys[row])))
        grid[middle, 0] += offset * L0
        velocity = np.zeros_like(grid)
        velocity[:, 0] = 0.5
        scene.add_particles(grid, np.full(len(grid), mps2p.KIND_FLUID, dtype=np.intc),
                            np.full(len(grid), water, dtype=np.intc), velocity)
        scene.add_tank(0.0, 0.0, 0.5, 0.2, open_top=False)
        solver = mps2p.Solver(scene)
    with solver:
        solver.advance_to(DT)
        assert solver.step_count == 1
        return solver.positions(), solver.velocities(), solver.kinds(), middle


def expected_shift(positions, velocities, fluid, i, shifting):
    r = positions[i] - positions  # from each neighbour j to i
    distance = np.hypot(r[:, 0], r[:, 1])
    near = (distance > 0) & (distance < 2.1 * L0)
    mean = distance[near].mean()
    terms = r[near] / distance[near, None] ** 3  # e_ji / r^2
    fastest = np.hypot(velocities[fluid, 0], velocities[fluid, 1]).max()
    return shifting * fastest * DT * mean ** 2 * terms.sum(axis=0)


def test_the_shift_is_the_formula_and_moves_a_crowded_particle_away():
    plain, velocity, kinds, middle = one_step(0.0, 0.3)
    shifted, _, _, _ = one_step(0.04, 0.3)
    fluid = kinds == mps2p.KIND_FLUID
    want = expected_shift(plain, velocity, fluid, middle, 0.04)
    got = shifted[middle] - plain[middle]
    assert want[0] < -1e-7  # away from the right neighbour it was pushed to
    assert got == pytest.approx(want, rel=1e-9, abs=1e-15)
    # only fluid moves, and nothing else changed in the step
    assert np.array_equal(shifted[~fluid], plain[~fluid])


def test_a_regular_lattice_is_not_shifted():
    plain, _, kinds, middle = one_step(0.0, 0.0)
    shifted, _, _, _ = one_step(0.04, 0.0)
    # inside a regular block every neighbour has its opposite: no shift
    assert np.allclose(shifted[middle], plain[middle], rtol=0, atol=1e-15)


def test_the_free_surface_is_not_shifted():
    # the block's top row is free surface: a crowded particle there stays
    plain, _, _, top = one_step(0.0, 0.3, row=9)
    shifted, _, _, _ = one_step(0.04, 0.3, row=9)
    assert np.array_equal(shifted[top], plain[top])
    # while the same particle one row down is shifted
    plain, _, _, below = one_step(0.0, 0.3, row=8)
    shifted, _, _, _ = one_step(0.04, 0.3, row=8)
    assert not np.array_equal(shifted[below], plain[below])


def test_the_schemes_set_it():
    with mps2p.Scene(L0) as scene:
        assert scene.get_param("shifting") == 0.04
        scene.set_option("scheme", "koshizuka1996")
        assert scene.get_param("shifting") == 0.0
        scene.set_option("scheme", "corrected")
        scene.set(shifting=0.1)
        assert scene.get_option("scheme") == "custom"
