"""Two-phase hard cases (issue 9; docs/two-phase.md, "Hard cases"): scenes in
examples/scenes run with the checks of mps2p.tools.stability after every step.

By default (CI): the conventional model's documented failure on the drop into
a pool (detected at the impact, with its place), the improved model on the
same scene to its end with every check, and on the wet bed and the sloshing
tank at l0 = 0.015 m.

With MPS2P_HARD_CASES=1 (scripts/test-hard-cases.sh): issue 9's acceptance
tests. The improved model on the other hard cases to their end time with every
check, the paper's case to 3 s with the entrained air below a quarter of its
peak, the paper's case at l0 = 0.005 m to 1 s, and Buchner's dam break with
air. They do not all pass yet: docs/two-phase.md has what each does and why.
And one of water alone: a newcomer's weir scene at l0 = 0.0025 m, whose
spray once stopped it (docs/validation.md, "Spray meeting spray")."""
import os

import pytest

from mps2p.tools.stability import check_run, gas_in_liquid_peak_and_last

from conftest import SCENES, load_validation

ACCEPTANCE = os.environ.get("MPS2P_HARD_CASES") == "1"
acceptance = pytest.mark.skipif(not ACCEPTANCE, reason="issue 9 acceptance run: "
                                "MPS2P_HARD_CASES=1 (scripts/test-hard-cases.sh)")

CONVENTIONAL = {"two_phase_model": "two_step"}
IMPROVED = {"two_phase_model": "two_step_improved"}


def scene(name):
    return os.path.join(SCENES, name + ".toml")


def test_conventional_model_diverges_where_the_drop_traps_air():
    """The drop (free fall from 0.15 m) reaches the pool at 0.175 s; the air
    between them is squeezed. The conventional model with Koshizuka and Oka's
    free surface (p = 0 at the surface particles' centres) cannot hold it:
    detected, stopped, the place and the squeezed gas particle named. When is
    chaotic (0.175 s with cg_tolerance 1e-9, 0.314 s with the scene's 1e-6
    before the sparse product's summation order changed, 0.71 s after, 0.39 s
    on 2026-12-03): only "not before the drop is near the pool, and within
    1 s" is asserted, and that nothing was wrong before then (on the way it
    may also push a gas particle through a wall: a failure of the same model,
    after the impact). With the default surface_pressure (extrapolated) the
    same model ran this drop to 2 s, its trapped air (16 at the peak) all out
    (2026-12-03; docs/two-phase.md)."""
    report = check_run(scene("drop_into_pool"), until=1.0,
                       options={**CONVENTIONAL, "surface_pressure": "centre"})
    assert report["status"] == "diverged"
    assert 0.15 < report["time"] < 1.0
    assert "gas particle" in report["reason"]
    assert "divergence" in report["violations"]
    for what, message in report["violations"].items():
        assert float(message.split(" s:")[0].split("t = ")[1]) > 0.15, (what, message)


def test_drop_into_pool_passes_every_check():
    """The improved model through the drop's impact and 0.5 s past the
    scene's end (1.5 s) with every check of mps2p.tools.stability (energy,
    inside the tank, counts, spacing); the air trapped under the drop is
    counted, and none of it is left in the water at 1.5 s. The trapped air
    leaves between 1.0 and 1.25 s: at 1 s six runs perturbed in their solver
    (preconditioner, tolerances) still had 0-11 of peaks of 20-30, so a bar
    at 1 s (it was below a quarter of the peak) sat in the tail's scatter; at
    1.5 s all six had 0 (docs/two-phase.md)."""
    report = check_run(scene("drop_into_pool"), until=1.5, options=IMPROVED)
    assert report["status"] == "ok", (report["reason"], report["violations"])
    peak, last = gas_in_liquid_peak_and_last(report)
    assert peak > 0  # air is trapped under the drop, and counted
    assert last == 0, "air in the water: peak %d, at 1.5 s %d" % (peak, last)


@pytest.mark.parametrize("name", ["wet_bed_air", "sloshing_air"])
def test_hard_case_passes_every_check_at_a_modest_resolution(name):
    """The column onto a wet bed (to 1.5 s) and the shaken tank (to 4 s,
    4.4 periods), both with air, at l0 = 0.015 m (CI's time; the acceptance
    run below has the scenes' 0.01 m): every check of mps2p.tools.stability
    to the end, gas above the tank's walls counted as gone. Both held by the
    gas's damping layer at its top (docs/two-phase.md, rungs 5 and 6)."""
    report = check_run(scene(name), l0=0.015, options=IMPROVED)
    assert report["status"] == "ok", (report["reason"], report["violations"])
    assert report["time"] == pytest.approx(report["end_time"])


@acceptance
@pytest.mark.parametrize("name", ["ikari2003_dam_break_air", "wet_bed_air", "sloshing_air"])
def test_improved_model_is_stable(name):
    report = check_run(scene(name), options=IMPROVED)
    assert report["status"] == "ok", (report["reason"], report["violations"])


@acceptance
def test_entrained_air_leaves_the_water():
    report = check_run(scene("ikari2003_dam_break_air"), until=3.0, options=IMPROVED)
    assert report["status"] == "ok", (report["reason"], report["violations"])
    peak, last = gas_in_liquid_peak_and_last(report)
    assert last < 0.25 * peak, "air in the water: peak %d, at 3 s %d" % (peak, last)


@acceptance
def test_finer_paper_case_is_stable():
    report = check_run(scene("ikari2003_dam_break_air"), until=1.0, l0=0.005, options=IMPROVED)
    assert report["status"] == "ok", (report["reason"], report["violations"])


@acceptance
@pytest.mark.xfail(strict=True, reason="measured (docs/two-phase.md, \"Buchner's plunge with "
                   "air\"): at H/l0 = 40 every run stops at t* = 5.9-6.1, where the run-up "
                   "plunges back and traps a cavity of air against the wall (gas pressure "
                   "over its limit)")
def test_buchner_with_air_runs_through_the_plunge():
    """Buchner's dam break (H = 0.6 m) with air around the column, the case of
    `examples/validation.py buchner_air` at its first cfl, to t* = 7 (about
    two minutes)."""
    _, summary = load_validation().impact("corrected", 40, settings={"cfl": 0.2}, air=True)
    assert summary["stopped"] is None, summary["stopped"]


@acceptance
def test_weir_beach_passes_every_check_at_a_fine_spacing():
    """Water alone over a weir onto a stepped beach, 12,000 water particles,
    to 0.8 s (about 5 minutes): every check; two spray particles meeting
    head on stopped it at 0.58 s before the collision core (energy ratio at
    most 1.036, closest pair 0.49 l0 with it, 2026-12-05)."""
    report = check_run(scene("weir_beach"), until=0.8, l0=0.0025)
    assert report["status"] == "ok", (report["reason"], report["violations"])
