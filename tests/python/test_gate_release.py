"""examples/validation.py's gate case (docs/validation.md, "A gate in the
scene does not make that lag"): the gate holds the column until it is lifted."""

from conftest import load_validation

validation = load_validation()


def test_a_gate_barely_lifted_holds_the_column():
    # to Martin & Moyce's first points (T = 0.83-0.85, t = 0.074 s): lifted at
    # 0.01 m/s the gate's edge is under a millimetre off the floor, and the
    # front stays at the column's face (Z = 1.05 with its half spacing), 18-20 %
    # behind the experiment; released at once it runs ahead of it
    held = validation.gate_release(0.01, l0=0.015, end_T=0.9)
    free = validation.gate_release(0.0, l0=0.015, end_T=0.9)
    assert len(held["errors"]) == len(free["errors"]) == 2
    assert all(e < -0.1 for e in held["errors"]), held
    assert all(e > 0.0 for e in free["errors"]), free
