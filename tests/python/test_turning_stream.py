"""A stream turning up a wall without gravity (docs/validation.md, "A stream
turning up a wall"), the rung under Buchner's impact pressure: the
free-streamline reference itself, and the default scheme's known deficit
(a slab 1.5 m long here; 2 m in examples/validation.py)."""
import math

import pytest

from conftest import load_validation

validation = load_validation()


def test_free_streamline_reference():
    """p = 1 at the corner, falling monotonically; at y = h the wall speed q
    solves pi/4 = artanh q + arctan q (q = 0.3913...); the profile's integral
    over the wall is the momentum flux rho U^2 h (2 in units of rho U^2 / 2
    and h: the integral of (1 - q^2) dy/dq = (8/pi) / (1 + q^2))."""
    theory = validation.turning_theory
    assert theory(1e-9, 1.0) == pytest.approx(1.0, abs=1e-6)
    heights = [0.01 * k for k in range(1, 2001)]
    values = [theory(y, 1.0) for y in heights]
    assert all(a > b for a, b in zip(values, values[1:]))
    q = 0.3913
    assert math.atanh(q) + math.atan(q) == pytest.approx(math.pi / 4, abs=1e-3)
    assert theory(1.0, 1.0) == pytest.approx(1 - q * q, abs=2e-3)
    integral = 0.01 * (0.5 * (1.0 + values[0]) + sum(values[:-1]))  # trapezoid from 0
    tail = 8 / math.pi * math.atan(1.0) - 8 / math.pi * math.atan(
        math.sqrt(1 - values[-1]))  # the rest, beyond y = 20 h, in closed form
    assert integral + tail == pytest.approx(2.0, rel=5e-3)


@pytest.mark.xfail(strict=True, reason="the default's collision damper at 0.995 l0 carries a "
                   "fifth to a quarter of the force (docs/validation.md, 'A stream turning up a wall')")
def test_default_scheme_carries_the_momentum_flux_as_pressure():
    """The wall's pressure force within 15 % of the stream's momentum flux
    rho U^2 h, as the free-streamline theory (and Buchner's plateau) needs.
    The default measures 0.82-0.87 on the 2 m slab and 0.74 on this one
    (2026-12-03; 0.67-0.71 with p = 0 at the free-surface centres); with the
    damper at 0.95 l0, 1.02, but still water then fails (docs/validation.md)."""
    _, summary, _ = validation.turning_stream("default", {}, length=1.5, end=1.0)
    assert summary["force"] == pytest.approx(1.0, abs=0.15), summary
