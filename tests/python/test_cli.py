"""The mps2p command, as a user runs it."""
import json
import math
import os
import subprocess
import sys

import mps2p as mps2p_package
import numpy as np
import pytest

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


def test_a_run_at_another_spacing(tmp_path):
    """--l0 runs the scene at another particle spacing: the water column of
    dam_break.toml (0.15 m x 0.3 m) on the 0.02 m lattice is 7 x 15."""
    result = mps2p("run", "dam_break", "--l0", "0.02", "--out", str(tmp_path), "--until",
                   "0.01", "--no-pictures", "--quiet")
    assert result.returncode == 0, result.stderr
    assert "moved onto the lattice of l0 = 0.02 m" in result.stderr
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["particles"]["water"] == 7 * 15
    assert summary["l0"] == 0.02
    with mps2p_package.open_results(str(tmp_path / "results.h5")) as results:
        assert results.metadata["l0"] == 0.02
        assert results.scene_text.startswith("# run with l0 = 0.02 (mps2p run --l0)\n")


def test_info_says_what_another_spacing_builds():
    result = mps2p("info", "dam_break", "--l0", "0.005")
    assert result.returncode == 0, result.stderr
    described = json.loads(result.stdout)
    assert described["l0"] == 0.005 and described["particles"]["water"] == 30 * 60
    result = mps2p("info", "--l0", "0.005")
    assert result.returncode == 2 and "--l0 needs a scene" in result.stderr


def test_stability_makes_the_folder_of_its_report_before_running(tmp_path):
    report = tmp_path / "not" / "yet" / "report.json"
    result = mps2p("stability", "dam_break", "--until", "0.01", "--out", str(report))
    assert result.returncode == 0, result.stderr
    assert json.loads(report.read_text())["status"] == "ok"
    (tmp_path / "a_file").write_text("")
    result = mps2p("stability", "dam_break", "--until", "0.01", "--out",
                   str(tmp_path / "a_file" / "report.json"))
    assert result.returncode == 2 and "a file of that name is in the way" in result.stderr
    assert "t = " not in result.stdout  # refused before the run
    result = mps2p("stability", "dam_break", "--until", "0.01", "--out", str(tmp_path))
    assert result.returncode == 2 and "a folder; the report is a file" in result.stderr
    assert "t = " not in result.stdout


def test_threads_auto_takes_the_idle_cores(tmp_path):
    result = mps2p("run", "dam_break", "--threads", "auto", "--out", str(tmp_path),
                   "--until", "0.01", "--no-pictures", "--quiet")
    assert result.returncode == 0, result.stderr
    said = [line for line in result.stderr.splitlines() if "--threads auto: " in line]
    assert len(said) == 1 and " cores idle)" in said[0], result.stderr
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["threads"] == float(said[0].split("auto: ")[1].split()[0])
    assert 1 <= summary["threads"] <= (os.cpu_count() or 1)


def test_threads_give_the_same_results(tmp_path):
    # the paper's water-air case briefly: its two pressure solves run side by side
    # on two threads (docs/performance.md), the results the same bits
    runs = {}
    for threads in ("1", "2"):
        out = tmp_path / threads
        result = mps2p("run", "ikari2003_dam_break_air", "--out", str(out), "--until", "0.02",
                       "--threads", threads, "--no-pictures", "--quiet")
        assert result.returncode == 0, result.stderr
        summary = json.loads((out / "summary.json").read_text())
        assert summary["threads"] == float(threads)
        # what the library ran on (2 in an OpenMP build, which CI's is)
        assert summary["threads_used"] == summary["final"]["threads"] >= 1
        if threads == "1":
            assert summary["threads_used"] == 1
        with mps2p_package.open_results(str(out / "results.h5")) as results:
            assert results.parameters["threads"] == float(threads)
            last = results.snapshot(-1)
        runs[threads] = [last[field].tobytes() for field in ("position", "velocity", "pressure")]
    assert runs["1"] == runs["2"]


def test_the_environment_gives_the_thread_count_a_scene_leaves_open(tmp_path):
    env = dict(os.environ, MPS2P_THREADS="2",
               PYTHONPATH=PACKAGE_DIR + os.pathsep + os.environ.get("PYTHONPATH", ""))
    command = [sys.executable, "-m", "mps2p", "run", "dam_break", "--until", "0.01",
               "--no-pictures", "--quiet"]
    result = subprocess.run(command + ["--out", str(tmp_path / "env")], capture_output=True,
                            text=True, env=env)
    assert result.returncode == 0, result.stderr
    assert json.loads((tmp_path / "env" / "summary.json").read_text())["threads"] == 2.0
    # --threads wins over the environment
    result = subprocess.run(command + ["--out", str(tmp_path / "flag"), "--threads", "1"],
                            capture_output=True, text=True, env=env)
    assert json.loads((tmp_path / "flag" / "summary.json").read_text())["threads"] == 1.0
    env["MPS2P_THREADS"] = "auto"  # the idle cores, as --threads auto
    result = subprocess.run(command + ["--out", str(tmp_path / "auto")], capture_output=True,
                            text=True, env=env)
    assert result.returncode == 0, result.stderr
    assert 1 <= json.loads((tmp_path / "auto" / "summary.json").read_text())["threads"] <= \
        (os.cpu_count() or 1)
    env["MPS2P_THREADS"] = "two"
    result = subprocess.run(command + ["--out", str(tmp_path / "bad")], capture_output=True,
                            text=True, env=env)
    assert result.returncode == 2 and "MPS2P_THREADS" in result.stderr and \
        "Traceback" not in result.stderr


@pytest.mark.parametrize("threads", ["-1", "1.5", "many", "2000"])
def test_a_bad_thread_count_is_bad_input(threads):
    result = mps2p("run", "dam_break", "--threads", threads)
    assert result.returncode == 2 and "--threads" in result.stderr and "Traceback" not in \
        result.stderr


def test_series_times_are_each_sampled_once(tmp_path):
    # snapshots every 0.05 s, series every 0.005 s: 0.15 = 3 x 0.05 and 30 x 0.005
    # differ in the last bit, and were sampled twice
    result = mps2p("run", os.path.join(SCENES, "dam_break.toml"), "--out", str(tmp_path),
                   "--until", "0.31", "--no-pictures", "--quiet")
    assert result.returncode == 0, result.stderr
    times = np.loadtxt(tmp_path / "series.csv", delimiter=",", skiprows=1, usecols=0)
    assert np.all(np.diff(times) > 1e-6), times[np.flatnonzero(np.diff(times) <= 1e-6)]
    assert len(times) == 1 + 62  # t = 0, then 0.005 ... 0.31 (the end one of them)


def test_a_run_ends_at_its_end_time(tmp_path):
    # 6 x 0.05 is 0.30000000000000004: the run used to stop one ulp past 0.3
    result = mps2p("run", os.path.join(SCENES, "dam_break.toml"), "--out", str(tmp_path),
                   "--until", "0.3", "--no-pictures", "--quiet")
    assert result.returncode == 0, result.stderr
    assert json.loads((tmp_path / "summary.json").read_text())["time"] == 0.3


def test_a_front_with_no_water_low_enough_yet_is_no_value_not_an_error(tmp_path):
    # a block falling from 0.3 m: its front probe has no particle below 0.02 m
    # at first (nan in series.csv, no row in results.h5), and the run goes on
    scene = tmp_path / "drop.toml"
    scene.write_text(dam_break_text().replace("box = [0.0, 0.0, 0.15, 0.3]",
                                              "box = [0.0, 0.3, 0.1, 0.4]"))
    result = mps2p("run", str(scene), "--out", str(tmp_path / "o"), "--until", "0.3",
                   "--no-pictures", "--quiet")
    assert result.returncode == 0, result.stderr
    csv = np.genfromtxt(tmp_path / "o" / "series.csv", delimiter=",", names=True)
    assert np.isnan(csv["front"][0]) and np.isfinite(csv["front"][-1])
    import mps2p as package
    with package.open_results(str(tmp_path / "o" / "results.h5")) as r:
        front = r.series["front"]
    assert len(front) == np.isfinite(csv["front"]).sum() < len(csv)


def test_info_with_a_scene_describes_it_without_running():
    result = mps2p("info", os.path.join(SCENES, "hydrostatic.toml"))
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["end_time"] == 2.0


def test_a_diverging_run_exits_1_and_keeps_its_files(tmp_path):
    scene = tmp_path / "blows_up.toml"
    text = open(os.path.join(SCENES, "dam_break.toml")).read()
    assert "[parameters]" not in text and "[run]" in text
    scene.write_text(text.replace("[run]", "[parameters]\npressure_limit = 1.0\n\n[run]"))
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


def test_every_problem_of_a_bad_scene_is_its_own_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[run]\nl0 = 0.01\nspeed = 2\n")
    result = mps2p("check", str(bad))
    assert result.returncode == 2
    assert result.stderr.splitlines() == [
        "mps2p: %s: run.speed: unknown key (known: description, end_time, l0, name, "
        "picture_times, series_every, snapshot_every)" % bad,
        "mps2p: %s: run.end_time: missing" % bad]


# -- issue 19: examples by name, --version, help --------------------------------

def test_examples_are_listed_and_run_by_name(tmp_path):
    listed = mps2p("examples")
    assert listed.returncode == 0, listed.stderr
    names = [line.split()[0] for line in listed.stdout.splitlines() if line.strip()][:-1]
    assert "dam_break" in names and "hydrostatic" in names
    assert sorted(names) == sorted(f[:-5] for f in os.listdir(SCENES) if f.endswith(".toml"))
    assert "water column 0.15 m x 0.3 m" in listed.stdout
    # by name, from a folder that holds no scene files
    result = mps2p("run", "dam_break", "--until", "0.01", "--out", str(tmp_path / "o"),
                   "--no-pictures", "--quiet", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "o" / "results.h5").exists()
    described = json.loads(mps2p("check", "hydrostatic", cwd=tmp_path).stdout)
    assert described["name"] == "hydrostatic"
    unknown = mps2p("run", "no_such_scene", cwd=tmp_path)
    assert unknown.returncode == 2 and unknown.stderr.count("\n") == 1
    # a misspelt example is named as neither a file nor an example, with the examples
    assert unknown.stderr.startswith("mps2p: no_such_scene: neither a scene file nor an "
                                     "example scene (examples: ")
    assert "dam_break" in unknown.stderr and "mps2p examples" in unknown.stderr
    near = mps2p("run", "dambreak", cwd=tmp_path)
    assert near.returncode == 2 and "; did you mean dam_break?" in near.stderr, near.stderr
    absent = mps2p("run", "no_such_scene.toml", cwd=tmp_path)
    assert absent.returncode == 2 and absent.stderr.startswith(
        "mps2p: no_such_scene.toml: no such file, and not an example scene"), absent.stderr
    missing = mps2p("run", os.path.join("no_folder", "scene.toml"), cwd=tmp_path)
    assert missing.returncode == 2 and "scene.toml" in missing.stderr
    # a file name that is not here but is an example's: run, and said so
    named = mps2p("check", "hydrostatic.toml", cwd=tmp_path)
    assert named.returncode == 0 and json.loads(named.stdout)["name"] == "hydrostatic"
    assert "hydrostatic.toml: no such file here; the example scene of that name" in named.stderr


def test_a_closed_pipe_ends_the_command_quietly():
    env = dict(os.environ)
    env["PYTHONPATH"] = PACKAGE_DIR + os.pathsep + env.get("PYTHONPATH", "")
    env.pop("PYTHONUNBUFFERED", None)  # short output then waits in Python's buffer
    # true reads nothing and exits long before Python has started: every write fails,
    # whether the output is long (info) or short and buffered (examples, --version)
    for command in ("info", "examples", "--version", "check dam_break"):
        result = subprocess.run("%s -m mps2p %s | true" % (sys.executable, command),
                                shell=True, capture_output=True, text=True, env=env)
        assert result.stderr == "", (command, result.stderr)
    first = subprocess.run("%s -m mps2p info | head -n 1" % sys.executable, shell=True,
                           capture_output=True, text=True, env=env)
    assert first.stdout.startswith("libmps2p ") and first.stderr == "", first


@pytest.mark.parametrize("module", ["mps2p", "mps2p.tools.ladder"])
def test_python_m_without_a_library_is_one_line_and_exit_2(module):
    env = dict(os.environ, MPS2P_LIBRARY=os.path.join(os.sep, "nonexistent", "libmps2p.so.0"))
    env["PYTHONPATH"] = PACKAGE_DIR + os.pathsep + env.get("PYTHONPATH", "")
    result = subprocess.run([sys.executable, "-m", module, "run", "dam_break"],
                            capture_output=True, text=True, env=env)
    expect_bad_input(result, "MPS2P_LIBRARY", "nonexistent")


def test_version():
    result = mps2p("--version")
    assert result.returncode == 0, result.stderr
    import mps2p as package
    assert result.stdout.startswith("mps2p ") and "libmps2p %s" % package.__version__ in \
        result.stdout and result.stdout.count("\n") == 1


def test_every_argument_has_help():
    import argparse

    from mps2p.tools.cli import parser
    top = parser()
    subcommands = [a for a in top._actions if isinstance(a, argparse._SubParsersAction)][0]
    helped = {c.dest: c.help for c in subcommands._choices_actions}
    assert set(helped) == set(subcommands.choices) and all(helped.values()), helped
    for name, sub in [("mps2p", top)] + list(subcommands.choices.items()):
        for action in sub._actions:
            if isinstance(action, argparse._SubParsersAction):
                continue
            assert action.help and action.help.strip(), "%s %s has no help" % (
                name, action.option_strings or action.dest)


# -- issue 20: one line on stderr, exit 2, nothing written ------------------------

def dam_break_text():
    return open(os.path.join(SCENES, "dam_break.toml")).read()


def expect_bad_input(result, *words):
    assert result.returncode == 2, (result.returncode, result.stderr)
    assert result.stderr.count("\n") == 1 and result.stderr.startswith("mps2p: "), result.stderr
    assert "Traceback" not in result.stderr
    for word in words:
        assert word in result.stderr, (word, result.stderr)


@pytest.mark.parametrize("name, words", [
    ('"../../x"', "run.name"), ('""', "run.name"), ('"."', "run.name"),
    ('"a/b"', "run.name"), ('"%s"' % ("n" * 5000), "5000 characters"),
])
def test_a_run_name_must_be_one_safe_folder_name(tmp_path, name, words):
    scene = tmp_path / "work" / "scene.toml"
    scene.parent.mkdir()
    scene.write_text(dam_break_text().replace('name = "dam_break"', "name = %s" % name))
    result = mps2p("run", str(scene), "--until", "0.01", "--no-pictures", "--quiet",
                   cwd=scene.parent)
    expect_bad_input(result, words)
    assert sorted(os.listdir(tmp_path)) == ["work"]
    assert os.listdir(scene.parent) == ["scene.toml"]  # no out/ at all


def test_a_deeply_nested_array_is_bad_input(tmp_path):
    scene = tmp_path / "deep.toml"
    scene.write_text(dam_break_text() + "\n[parameters]\nx = " + "[" * 2000 + "]" * 2000 + "\n")
    expect_bad_input(mps2p("check", str(scene)), "nested too deep")
    expect_bad_input(mps2p("run", str(scene), "--out", str(tmp_path / "o")), "nested")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("arrays, words", [
    ({"positions": np.zeros((4, 3)), "kinds": np.zeros(4, dtype=int)}, "shape (n, 2)"),
    ({"positions": np.zeros((4, 2)), "kinds": np.zeros(5, dtype=int)}, "kinds must have shape"),
    ({"positions": np.zeros((4, 2)), "kinds": np.zeros(4)}, "kinds must hold integers"),
    ({"positions": np.zeros((4, 2)), "kinds": np.zeros(4, dtype=int),
      "fluid_ids": np.full(4, 2 ** 32)}, "out of range for a C int"),
    ({"positions": np.full((4, 2), "a"), "kinds": np.zeros(4, dtype=int)}, "real numbers"),
    # fluid particles without their fluid (the C library's message named no file)
    ({"positions": np.zeros((4, 2)), "kinds": np.zeros(4, dtype=int)}, "no array 'fluid_ids'"),
])
def test_particle_files_of_the_wrong_shape_or_kind_are_bad_input(tmp_path, arrays, words):
    np.savez(tmp_path / "p.npz", **arrays)
    scene = tmp_path / "p.toml"
    scene.write_text(dam_break_text() + '\n[[particles]]\nfile = "p.npz"\n')
    expect_bad_input(mps2p("run", str(scene), "--out", str(tmp_path / "o"), "--quiet"),
                     "particles[0]", words)
    assert not (tmp_path / "o").exists()


def test_an_output_folder_that_cannot_be_made_is_bad_input(tmp_path):
    scene = os.path.join(SCENES, "dam_break.toml")
    in_the_way = tmp_path / "a_file"
    in_the_way.write_text("")
    for out, words in ((in_the_way, "a file of that name is in the way"),
                       (in_the_way / "sub", "Not a directory"),
                       ("/proc/mps2p-out", "cannot create it")):
        expect_bad_input(mps2p("run", scene, "--out", str(out), "--until", "0.01", "--quiet"),
                         "output folder", words)
    assert os.listdir(tmp_path) == ["a_file"] and in_the_way.read_text() == ""


@pytest.mark.parametrize("key", ["series_every", "snapshot_every"])
def test_a_schedule_too_fine_to_keep_is_refused(tmp_path, key):
    text = dam_break_text()
    text = text.replace("series_every = 0.005", "") .replace("snapshot_every = 0.05", "")
    scene = tmp_path / "fine.toml"
    scene.write_text(text.replace("[run]\n", "[run]\n%s = 1e-300\n" % key))
    expect_bad_input(mps2p("run", str(scene), "--out", str(tmp_path / "o")), "run." + key,
                     "1e-300")
    assert not (tmp_path / "o").exists()


def test_an_until_too_long_for_the_schedule_names_until():
    result = mps2p("run", "dam_break", "--until", "1e9")
    expect_bad_input(result, "--until 1e+09 with run.snapshot_every", "snapshots")


@pytest.mark.parametrize("until", ["inf", "nan", "-1", "soon"])
def test_a_bad_until_is_bad_input(until):
    result = mps2p("run", "dam_break", "--until", until)
    assert result.returncode == 2 and "--until" in result.stderr and "Traceback" not in \
        result.stderr


def test_progress_off_a_terminal_is_a_line_a_tenth(tmp_path):
    # stderr is a pipe here, as in a log file or CI: a line at each tenth of the
    # run and at its end, not one per snapshot (30 here)
    text = open(os.path.join(SCENES, "dam_break.toml")).read()
    text = text.replace("snapshot_every = 0.05", "snapshot_every = 0.01")
    scene = tmp_path / "often.toml"
    scene.write_text(text)
    result = mps2p("run", str(scene), "--out", str(tmp_path / "out"), "--until", "0.3",
                   "--no-pictures")
    assert result.returncode == 0, result.stderr
    lines = [line for line in result.stderr.splitlines() if "particle-steps/s, ETA" in line]
    assert 2 <= len(lines) <= 11, result.stderr
    assert "t = 0.3 / 0.3 s" in lines[-1]
    # what is about to run, first: its particles, spacing and end
    assert result.stderr.splitlines()[0] == ("dam_break: 1282 particles (water 450, wall 202, "
                                             "dummy 630), l0 = 0.01 m, to t = 0.3 s")
    reached = [float(line.split("t = ")[1].split(" /")[0]) for line in lines]
    assert reached == sorted(set(reached))


def test_a_run_into_an_earlier_runs_folder_leaves_none_of_its_files(tmp_path):
    # an earlier run's divergence.png or front.png beside new results would read
    # as theirs; the folder's other files are the user's and stay
    out = tmp_path / "out"
    out.mkdir()
    stale = ["divergence.png", "front.png", "velocity_air.png", "series.csv", "summary.json"]
    for name in stale + ["notes.txt"]:
        (out / name).write_text("earlier")
    result = mps2p("run", "dam_break", "--until", "0.01", "--out", str(out), "--no-pictures",
                   "--quiet")
    assert result.returncode == 0, result.stderr
    left = sorted(os.listdir(out))
    assert left == ["notes.txt", "results.h5", "results.xdmf", "series.csv", "summary.json"]
    assert (out / "summary.json").read_text() != "earlier"


def test_a_wave_gauge_reads_the_waters_top(tmp_path):
    # the dam break's column (0.15 m x 0.3 m, l0 0.01): at x = 0.05 the gauge reads
    # the column's height at the start and less as it collapses; beyond the
    # front (x = 0.5) there is no water yet: no value (nan, no row in results.h5)
    text = open(os.path.join(SCENES, "dam_break.toml")).read()
    text += ('\n[[probe]]\nname = "gauge"\ntype = "elevation"\nfluid = "water"\nx = 0.05\n'
             '\n[[probe]]\nname = "dry"\ntype = "elevation"\nfluid = "water"\nx = 0.5\n'
             'half_width = 0.005\n')
    scene = tmp_path / "gauged.toml"
    scene.write_text(text)
    out = tmp_path / "out"
    result = mps2p("run", str(scene), "--until", "0.15", "--out", str(out), "--no-pictures",
                   "--quiet")
    assert result.returncode == 0, result.stderr
    import csv
    with open(out / "series.csv") as f:
        rows = list(csv.DictReader(f))
    gauge = [float(r["gauge"]) for r in rows]
    assert gauge[0] == pytest.approx(0.3, abs=1e-9)
    assert 0.1 < gauge[-1] < 0.28
    assert all(r["dry"] in ("nan", "") for r in rows)
    with mps2p_package.open_results(str(out / "results.h5")) as results:
        assert results.series["gauge"].shape[0] == len(rows)
        assert "dry" not in results.series or results.series["dry"].shape[0] == 0


def test_a_wave_gauge_is_not_read_off_spray():
    """A drop passing above the water (a gap of more than 2 l0) is not the
    water's top; the column's own gaps (up to 2 l0) are water."""
    from mps2p.tools.run import water_top
    l0 = 0.01
    column = [0.005 + l0 * k for k in range(10)]  # water up to 0.1 m
    assert water_top(column, l0) == pytest.approx(0.1)
    assert water_top(column + [0.5, 0.51], l0) == pytest.approx(0.1)
    assert water_top(column + [column[-1] + 1.9 * l0], l0) == pytest.approx(0.119)
    assert math.isnan(water_top([], l0))


def test_elevation_probes_are_checked(tmp_path):
    text = open(os.path.join(SCENES, "dam_break.toml")).read()
    text += ('\n[[probe]]\nname = "gauge"\ntype = "elevation"\nfluid = "water"\n'
             'half_width = -1\n')
    scene = tmp_path / "bad.toml"
    scene.write_text(text)
    result = mps2p("check", str(scene))
    assert result.returncode == 2 and "needs ['x']" in result.stderr and \
        "half_width: must be > 0" in result.stderr, result.stderr


def test_a_run_of_over_a_million_particles_says_so_first(tmp_path, monkeypatch, capsys):
    """A scene written in centimetres at l0 = 0.01 builds 10,000 times the
    particles meant: the command says so before the run (the bound lowered
    here, not a million particles built)."""
    from mps2p.tools import run as run_module
    monkeypatch.setattr(run_module, "LONG_RUN_PARTICLES", 1000)
    run_module.run(os.path.join(SCENES, "dam_break.toml"), str(tmp_path), until=0.001,
                   pictures=False, progress=True)
    first = capsys.readouterr().err.splitlines()[0]
    assert first.startswith("dam_break: 1282 particles") and \
        "over 1,000: a long run (are the scene's lengths in metres?)" in first, first
