"""Re-entry from a progress callback (issue 20): closing the solver inside
its own advance_to callback segfaulted (a use-after-free in the C library),
and a nested advance_to returned at the nested time. Each case runs in a
child process, so that a crash fails the test instead of ending pytest."""
import os
import subprocess
import sys
import textwrap

SETUP = """
import mps2p
scene = mps2p.Scene(0.02)
water = scene.add_fluid("water", 1000.0, 1e-6)
scene.add_fluid_box(water, 0.0, 0.0, 0.1, 0.2)
scene.add_tank(0.0, 0.0, 0.4, 0.3, open_top=True)
solver = mps2p.Solver(scene)
"""


def run_child(code):
    return subprocess.run([sys.executable, "-c", textwrap.dedent(SETUP + code)],
                          capture_output=True, text=True, timeout=120, env=os.environ.copy())


def test_close_inside_progress_does_not_crash():
    child = run_child("""
calls = []
def close_it(s):
    calls.append(s.time)
    s.close()
try:
    solver.advance_to(0.05, progress=close_it)
    print("returned normally")
except Exception as e:  # the C library's refusal, or the binding's
    print("raised", type(e).__name__)
print("callbacks", len(calls))
""")
    assert child.returncode == 0, child.stderr[-2000:]
    assert "raised" in child.stdout, child.stdout
    assert "callbacks 1" in child.stdout, child.stdout


def test_nested_advance_inside_progress_is_refused():
    child = run_child("""
inner = []
def nested(s):
    if not inner:
        try:
            s.advance_to(0.2)
            inner.append("ran")
        except mps2p.Error as e:
            inner.append(e.status_name)
    return False
solver.advance_to(0.05, progress=nested)
print("inner", inner[0])
print("time %.17g" % solver.time)
""")
    assert child.returncode == 0, child.stderr[-2000:]
    assert "inner MPS2P_ERR_STATE" in child.stdout, child.stdout
    assert "time 0.050000000000000003" in child.stdout, child.stdout
