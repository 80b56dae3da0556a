"""The mps2p command, as a user runs it."""
import json
import os
import subprocess
import sys

from conftest import PACKAGE_DIR, SCENES


def mps2p(*args, cwd=None):
    env = dict(os.environ)
    env["PYTHONPATH"] = PACKAGE_DIR + os.pathsep + env.get("PYTHONPATH", "")
    return subprocess.run([sys.executable, "-m", "mps2p", *args], capture_output=True,
                          text=True, env=env, cwd=cwd)


def test_info_lists_version_and_parameters():
    result = mps2p("info")
    assert result.returncode == 0, result.stderr
    assert "libmps2p 0." in result.stdout and "re_laplacian" in result.stdout


def test_check_prints_the_scene():
    result = mps2p("check", os.path.join(SCENES, "dam_break.toml"))
    assert result.returncode == 0, result.stderr
    described = json.loads(result.stdout)
    assert described["particles"] == {"water": 450, "wall": 202, "dummy": 630}
    assert described["effects"]["viscosity"]["active"] is True
    assert 0 < described["dt_first_step"] < 0.01


def test_run_writes_results(tmp_path):
    result = mps2p("run", os.path.join(SCENES, "dam_break.toml"), "--out", str(tmp_path),
                   "--until", "0.01", "--no-pictures", "--quiet")
    assert result.returncode == 0, result.stderr
    assert " ok at t = 0.01 s" in result.stdout
    assert (tmp_path / "results.h5").exists() and not (tmp_path / "snapshots.png").exists()


def test_info_with_a_scene_describes_it_without_running():
    result = mps2p("info", os.path.join(SCENES, "hydrostatic.toml"))
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["end_time"] == 2.0


def test_a_diverging_run_exits_1_and_keeps_its_files(tmp_path):
    scene = tmp_path / "blows_up.toml"
    text = open(os.path.join(SCENES, "dam_break.toml")).read()
    scene.write_text(text.replace("[options]", "[parameters]\npressure_limit = 1.0\n\n[options]"))
    result = mps2p("run", str(scene), "--out", str(tmp_path / "out"), "--quiet", "--no-pictures")
    assert result.returncode == 1
    assert "diverged" in result.stderr and "particle" in result.stderr
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["status"] == "diverged" and "particle" in summary["reason"]
    assert (tmp_path / "out" / "results.h5").exists()


def test_a_bad_scene_is_one_clear_line_and_exit_2(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[run]\nl0 = 0.01\n")
    result = mps2p("check", str(bad))
    assert result.returncode == 2
    assert result.stderr.strip() == "mps2p: %s: run.end_time: missing" % bad
