"""Checkpoints written by earlier versions of the library (the fuzz corpus's
seeds, format 4, from before trigger_speed and join_bubbles existed) still
load, with the behaviour of their time for what they lack, and continue."""
import os

import pytest

import mps2p

from conftest import ROOT

SEEDS = os.path.join(ROOT, "tests", "fuzz", "corpus", "checkpoint")


@pytest.mark.parametrize("name", ["cholmod-start.chk", "cholmod-5-steps.chk", "cg-3-steps.chk",
                                  "two-phase-3-steps.chk"])
def test_an_older_checkpoint_loads_and_continues(name):
    with mps2p.Solver.load_checkpoint(os.path.join(SEEDS, name)) as solver:
        start, steps = solver.time, solver.step_count
        solver.advance_to(start + 0.001)
        assert solver.time == pytest.approx(start + 0.001, abs=1e-12)
        assert solver.step_count > steps
