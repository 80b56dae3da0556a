"""validation.py's transplant puts another code's water (PySPH's) on this
library's lattice (lattice_from): checked here on water whose answer is known,
without PySPH."""
import numpy as np

from conftest import load_validation


def test_a_lattice_comes_back_as_itself_and_a_jittered_one_nearly():
    v = load_validation()
    l0 = 0.015
    x, y = np.meshgrid((np.arange(10) + 3.5) * l0, (np.arange(8) + 0.5) * l0)
    block = np.column_stack([x.ravel(), y.ravel()])
    velocity = np.tile([1.0, -2.0], (len(block), 1))
    sites, velocities = v.lattice_from(block, velocity, l0, 1.0, 0.5)
    assert len(sites) == len(block)
    assert np.array_equal(np.sort(sites, axis=0), np.sort(block, axis=0))
    assert np.allclose(velocities, [1.0, -2.0], atol=1e-12)
    # particles off the lattice by up to a fifth of a spacing (as SPH's are):
    # the same water to within an edge site, the same velocity
    jittered = block + np.random.default_rng(1).uniform(-0.2, 0.2, block.shape) * l0
    sites, velocities = v.lattice_from(jittered, velocity, l0, 1.0, 0.5)
    assert abs(len(sites) - len(block)) <= 2
    assert np.allclose(velocities, [1.0, -2.0], atol=1e-12)
