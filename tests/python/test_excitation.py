"""Effect excitation (a shaken tank): the fluid feels -A sin(2 pi t / T) along
x, and nothing when A = 0."""
import math

import numpy as np
import pytest

import mps2p


def blob(**settings):
    scene = mps2p.Scene(0.01, gravity_y=0.0, dt=1e-4, **settings)
    water = scene.add_fluid("water", 1000.0, 0.0)
    scene.add_fluid_box(water, 0.0, 0.0, 0.1, 0.1)
    return scene


def test_free_blob_follows_the_forcing():
    """No walls, no gravity: the blob's mean velocity is the integral of the
    forcing, -A T / (2 pi) (1 - cos(2 pi t / T)); internal pressure forces
    nearly cancel in the mean."""
    amplitude, period, t = 2.0, 0.2, 0.1
    with blob(excitation_acceleration=amplitude, excitation_period=period) as scene:
        solver = mps2p.Solver(scene)
    with solver:
        assert solver.effects()["excitation"][0]
        solver.advance_to(t)
        mean = solver.velocities().mean(axis=0)
    omega = 2 * math.pi / period
    expected = -amplitude / omega * (1 - math.cos(omega * t))
    assert mean[0] == pytest.approx(expected, rel=0.01)
    assert abs(mean[1]) < 1e-3 * abs(expected)


def test_off_without_amplitude():
    with blob() as scene:
        solver = mps2p.Solver(scene)
    with solver:
        assert not solver.effects()["excitation"][0]
        assert not solver.stages()["excitation"]["active"]
        solver.advance_to(0.01)
        assert np.abs(solver.velocities()).max() < 1e-9


def test_switching_it_on_without_amplitude_is_refused():
    with blob() as scene:
        scene.set_option("effect.excitation", "on")
        with pytest.raises(mps2p.InvalidArgumentError, match="excitation_acceleration is 0"):
            mps2p.Solver(scene)
