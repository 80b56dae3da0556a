"""The impact-pressure statistics of docs/validation.md ("Impact pressure
against Buchner"), which read libmps2p's and PySPH's series alike:
examples/validation.py's impact_summary on series whose answers are known; and
its Buchner scene with air (`validation.py buchner_air`), built and run briefly."""

import numpy as np
import pytest

from conftest import load_validation

validation = load_validation()


def experiment_sampled(every=0.01):
    """Buchner's P1 series, interpolated every `every` t* from 1.5 to 7."""
    ref = validation.buchner_reference()["P1"]
    t = np.arange(1.5, 7.0 + every / 2, every)
    return np.column_stack([t, np.interp(t, ref[:, 0], ref[:, 1])])


def test_the_experiment_against_itself():
    s = validation.impact_summary("experiment", 0, experiment_sampled())
    assert s["rms_difference_2_7"] == pytest.approx(0.0, abs=1e-12)
    # the interpolated series crosses 0.1 between the experiment's last point
    # below it and its first above (0.019 t* apart there)
    assert abs(s["impact_t"] - s["impact_t_experiment"]) <= 0.02
    # the plateau of the interpolated series against the mean of the points in t* = 3-5
    assert s["plateau_3_5"] == pytest.approx(s["plateau_experiment"], abs=0.01)
    assert s["peak"] == pytest.approx(s["peak_experiment"], abs=0.02)
    # the experiment's own series is smooth over 0.1 t*: little noise
    assert s["noise_2_7"] < 0.03


def test_noise_reads_added_white_noise():
    arr = experiment_sampled()
    rng = np.random.default_rng(7)
    noisy = arr.copy()
    noisy[:, 1] += rng.normal(0.0, 0.2, len(arr))
    s = validation.impact_summary("noisy", 0, noisy)
    # white noise less its 10-sample moving mean keeps sqrt(1 - 1/10) of its RMS
    assert s["noise_2_7"] == pytest.approx(0.2 * np.sqrt(0.9), rel=0.1)
    assert s["rms_difference_2_7"] == pytest.approx(0.2, rel=0.1)


def test_a_late_series_is_late():
    arr = experiment_sampled()
    late = np.column_stack([arr[:, 0], np.interp(arr[:, 0] - 0.3, arr[:, 0], arr[:, 1])])
    on_time = validation.impact_summary("on time", 0, arr)
    s = validation.impact_summary("late", 0, late)
    assert s["impact_t"] - on_time["impact_t"] == pytest.approx(0.3, abs=0.011)
    assert s["rms_difference_2_7"] > 0.1


def test_scatter_row_reads_the_worst_run_of_each_statistic():
    """The scatter table's row (docs/validation.md, "Run-to-run scatter"):
    mean +- standard deviation, and in brackets the worst run: the largest
    error, spray, energy, impact time and noise, the smallest plateau and
    force."""
    s = validation.spread
    summary = {"settings": {"shifting": 0},
               "dam": {"front_error_max": s([0.16, 0.18]),
                       "isolated_max_fraction": s([0.02, 0.04]),
                       "energy_excess_max": s([0.0, 0.001])},
               "buchner_40": {"impact_t": s([2.7, 2.9]), "plateau_3_5": s([0.2, 0.3]),
                              "noise_2_7": s([0.1, 0.2])},
               "turning_force": s([0.7, 0.9])}
    assert summary["dam"]["isolated_max_fraction"]["std"] == pytest.approx(0.01)
    cells = [c.strip() for c in validation.scatter_row(summary).split("|")[1:-1]]
    assert cells == ['{"shifting": 0}', "17.0 +- 1.0 (18.0) %", "3.0 +- 1.0 (4.0) %",
                     "0.05 +- 0.05 (0.10) %", "2.80 +- 0.10 (2.90)", "0.25 +- 0.05 (0.20)",
                     "0.150 +- 0.050 (0.200)", "0.80 +- 0.10 (0.70)"]


def test_buchner_with_air_fills_the_tank_around_the_column():
    """`validation.py buchner_air`'s scene: air up to 2H around the column
    (H/l0 = 10, a few steps): the particles add up, and the run goes on."""
    _, water = validation.impact("corrected", 10, end_star=0.2)
    _, with_air = validation.impact("corrected", 10, end_star=0.2, air=True)
    # the column is 2H x H in a tank 5.3 H long at this spacing; the air fills
    # 5.3 H x 2H less the column: 4.3 times the column's particles
    added = with_air["particles"] - water["particles"]
    column = 20 * 10
    assert 4.2 * column < added < 4.4 * column
    assert water["stopped"] is None and with_air["stopped"] is None
    assert with_air["end_t"] == pytest.approx(0.2)
