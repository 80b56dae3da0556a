"""The Python benchmarks run (their quick versions: nothing timed is asserted,
issue 18): benchmarks/two_phase_speed.py measures two variants of the paper's
case for a few steps and reports what it computed."""
import json
import os
import subprocess
import sys

from conftest import ROOT


def test_two_phase_speed_runs_and_reports():
    script = os.path.join(ROOT, "benchmarks", "two_phase_speed.py")
    out = subprocess.run([sys.executable, script, "--until", "0.002", "dt=2e-4", "threads=2"],
                         check=True, capture_output=True, text=True, env=os.environ).stdout
    rows = [json.loads(line) for line in out.splitlines()]
    assert [row["variant"] for row in rows] == ["dt=2e-4", "threads=2"]
    for row in rows:
        assert row["steps"] > 0 and row["wall_s_per_simulated_s"] > 0, row
        assert 0 < row["gas_solve_share"] < 1 and row["gas_iterations_sampled"] > 0, row
        assert 0.15 <= row["front"] < 0.2, row  # the column has only begun to move
    assert rows[0]["steps"] == 10  # dt 2e-4 s
