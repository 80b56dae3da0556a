"""Buchner's dam break at H/l0 = 40 with the default scheme (docs/validation.md,
"Impact pressure against Buchner (2002)"; issue 15's bars): P1's series against
the experiment. One run (about 20 s), shared by the tests; the bars the scheme
does not meet yet are strict expected failures, so that meeting one shows."""
import pytest

from conftest import load_validation

validation = load_validation()


@pytest.fixture(scope="module")
def summary():
    _, result = validation.impact("corrected", 40)
    assert result["stopped"] is None, result
    return result


def test_the_noise_at_p1_is_the_step_gains(summary):
    """The noise (the RMS of P1 less its 0.1 t* moving mean, t* = 2-7) under
    0.12 p*: with the source answering 0.4 of the step's compression it reads
    0.091 +- 0.008 over four runs perturbed in cfl (at most 0.103), with the
    whole of it 0.151 +- 0.012 (at least 0.14; docs/validation.md, "Run-to-run
    scatter"). Issue 15's bar, 0.1 at H/l0 = 80, is the long suite's."""
    assert summary["noise_2_7"] < 0.12, summary


@pytest.mark.xfail(strict=True, reason="the load arrives late: 2.77-2.98 against 2.49 "
                   "(docs/validation.md, 'Impact pressure against Buchner')")
def test_the_impact_comes_on_time(summary):
    """P1 first above 0.1 p* within 0.1 t* of the experiment's 2.49."""
    assert summary["impact_t"] == pytest.approx(summary["impact_t_experiment"], abs=0.1)


@pytest.mark.xfail(strict=True, reason="the plateau reads 0.24-0.27 against 0.55 "
                   "(docs/validation.md, 'Impact pressure against Buchner')")
def test_the_plateau_is_the_experiments(summary):
    """P1's mean over t* = 3-5 within 10 % of the experiment's 0.55."""
    assert summary["plateau_3_5"] == pytest.approx(summary["plateau_experiment"], rel=0.1)
