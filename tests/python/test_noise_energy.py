"""The dam break's particle-scale kinetic energy (docs/validation.md, "Dam
break against Martin & Moyce"): examples/validation.py's noise_energy on
made-up particles, where the answer is known."""

import numpy as np
import pytest

from conftest import load_validation

validation = load_validation()

L0 = 0.01


def lattice(n=30):
    xs = L0 * np.arange(n)
    return np.array(np.meshgrid(xs, xs, indexing="ij")).reshape(2, -1).T


def test_a_uniform_flow_has_no_noise():
    xy = lattice()
    uv = np.tile([1.5, -0.3], (len(xy), 1))
    assert validation.noise_energy(xy, uv, L0) == pytest.approx(0.0, abs=1e-20)


def test_one_moving_particle_among_resting_ones():
    """One particle at speed v among particles at rest, with 12 neighbours
    within 2.1 l0 on the lattice (13 in its mean with itself): its own
    deviation is v (1 - 1/13), each neighbour's v/13 (its mean also has 13
    members, the moving one among them)."""
    xy = lattice(30)  # 900 particles: the sum runs in blocks of 256 rows
    uv = np.zeros_like(xy)
    centre = 20 * 30 + 15  # a row of the third block
    uv[centre] = [2.0, 0.0]
    expected = 0.5 * (2.0 * (1 - 1 / 13)) ** 2 + 12 * 0.5 * (2.0 / 13) ** 2
    assert validation.noise_energy(xy, uv, L0) == pytest.approx(expected, rel=1e-12)
