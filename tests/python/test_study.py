"""The quick accuracy-cost study writes its CSV, pictures and conclusions,
with numbers in their plausible ranges."""
import csv

import pytest

from mps2p.tools.study import observed_order, pareto, study


def test_pareto_and_order():
    assert pareto([(1, 5), (2, 3), (3, 4), (0.5, 9)]) == [3, 0, 1]
    assert observed_order([0.02, 0.01, 0.005], [0.4, 0.1, 0.025]) == pytest.approx(2.0)


def fine_and_coarse(rows):
    return {r["l0"] for r in rows if r["variant"] == "default"} == {"0.025", "0.0125"}


def test_quick_study(tmp_path):
    study(str(tmp_path), quick=True, log=None)
    for name in ("study.csv", "study.md", "error_vs_time.png", "error_vs_l0.png",
                 "time_vs_particles.png"):
        assert (tmp_path / name).stat().st_size > 0, name
    rows = list(csv.DictReader(open(tmp_path / "study.csv")))
    assert {r["problem"] for r in rows} == {"dam_break", "still_tank", "two_phase"}
    assert fine_and_coarse(rows)
    for r in rows:
        assert float(r["wall_seconds"]) > 0 and int(r["steps"]) > 0
        solve = ("stage_liquid_pressure", "stage_gas_pressure") if r["problem"] == "two_phase" \
            else ("stage_pressure_solve",)
        assert 0 < sum(float(r[k]) for k in solve) <= float(r["wall_seconds"])
        assert float(r["memory_bytes"]) > 100 * int(r["particles"])
        if r["problem"] in ("dam_break", "two_phase"):
            assert 0.0 < float(r["front_error"]) < 0.3  # MPS leads the experiment by 10-20 %
            if r["reference"] != "finest":
                assert 0.0 < float(r["front_error_vs_finest"]) < 0.3
        else:
            assert float(r["pressure_error"]) < 0.1
    fine = [r for r in rows if r["l0"] == "0.0125" and r["variant"] == "default"]
    coarse = [r for r in rows if r["l0"] == "0.025" and r["variant"] == "default"]
    for f, c in zip(sorted(fine, key=lambda r: r["problem"]),
                    sorted(coarse, key=lambda r: r["problem"])):
        assert int(f["particles"]) > 2 * int(c["particles"])  # walls grow as 1/l0 only
    assert "Halving l0" in (tmp_path / "study.md").read_text()
