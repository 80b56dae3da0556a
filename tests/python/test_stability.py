"""The hard-case checker (mps2p.tools.stability) on a case that is known to be
stable, and each check shown able to fail."""
import os

import pytest

from mps2p.tools import stability

from conftest import SCENES

DAM_BREAK = os.path.join(SCENES, "dam_break.toml")


def run(**kwargs):
    return stability.check_run(DAM_BREAK, until=0.3, l0=0.02, **kwargs)


def test_water_only_dam_break_passes_every_check():
    report = run()
    assert report["status"] == "ok", report["violations"]
    assert report["time"] == pytest.approx(0.3)
    assert report["particles"] == {"water": 105}
    # kinetic energy stays near the potential energy released (MPS's initial
    # lattice transient puts it slightly above early on)
    assert 0.5 < report["energy_ratio_max"] < 1.5
    assert 0.25 < report["closest_min"] < 1.0
    assert report["series"][-1]["kinetic_energy_water"] > 0


def test_energy_check_can_fail(monkeypatch):
    monkeypatch.setattr(stability, "MARGIN", -0.5)
    report = run()
    assert report["status"] == "unstable"
    assert "energy" in report["violations"]


def test_spacing_check_can_fail(monkeypatch):
    monkeypatch.setattr(stability, "CLOSEST", 0.9)
    monkeypatch.setattr(stability, "CLOSEST_STEPS", 3)
    report = run()
    assert "spacing" in report["violations"]


def test_divergence_is_reported_with_its_reason():
    # a displacement limit no moving particle can meet
    report = run(parameters={"displacement_limit": 1e-6})
    assert report["status"] == "diverged"
    assert "jumped" in report["reason"]
    assert report["steps"] == 0
