"""The README's quick starts are the programs the tests run: the Python one
is tests/python/quickstart.py, the C one tests/consumer/consumer.c (built
and run by scripts/test.sh); the internals live in docs/internals.md."""
import os
import re
import subprocess
import sys

from conftest import HERE, PACKAGE_DIR, ROOT


def readme():
    with open(os.path.join(ROOT, "README.md")) as f:
        return f.read()


def test_the_python_quick_start_is_the_program_run_here():
    with open(os.path.join(HERE, "quickstart.py")) as f:
        program = f.read()
    assert "```python\n" + program + "```" in readme()
    assert len(program.strip().splitlines()) <= 10
    env = dict(os.environ, PYTHONPATH=PACKAGE_DIR + os.pathsep + os.environ.get("PYTHONPATH",
                                                                                  ""))
    done = subprocess.run([sys.executable, os.path.join(HERE, "quickstart.py")],
                          capture_output=True, text=True, env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    front, particles = done.stdout.splitlines()
    match = re.fullmatch(r"front at x = (\d\.\d{3}) m after (\d+) steps", front)
    # on its way: not yet at the right wall (0.6 m), which it reaches at about 0.27 s
    assert match and 0.3 < float(match.group(1)) < 0.58 and int(match.group(2)) > 100, front
    assert particles.startswith("(1282, 2) particles, walls too; max speed "), particles
    assert "0.2/0.2 s" in done.stderr  # the progress bar reached the end


def test_the_c_quick_start_is_the_consumer_the_tests_build():
    with open(os.path.join(ROOT, "tests", "consumer", "consumer.c")) as f:
        program = f.read()
    assert "```c\n" + program + "```" in readme()


def test_the_readme_starts_with_the_quick_start_and_leaves_internals_to_docs():
    text = readme()
    order = [text.index(h) for h in ("## The two commands", "bash scripts/main-job.sh",
                                     "bash scripts/test.sh", "## Python quick start",
                                     "## C quick start")]
    assert order == sorted(order)
    assert "| stage | file |" not in text and "## Guarantees" not in text
    with open(os.path.join(ROOT, "docs", "internals.md")) as f:
        internals = f.read()
    assert "| stage | file |" in internals and "## Guarantees" in internals
    assert "docs/internals.md" in text
