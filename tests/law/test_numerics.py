"""camcad.numerics against closed forms and against scipy.optimize (an independent implementation)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

from camcad.numerics import bounded_minimum, brent_root

ROOTS = [  # (f, a, b, closed-form root)
    (lambda x: x * x - 2.0, 0.0, 2.0, math.sqrt(2.0)),
    (lambda x: math.cos(x) - x, 0.0, 1.0, None),
    (lambda x: x**3, -1.0, 2.0, 0.0),
    (lambda x: math.exp(x) - 10.0, 0.0, 5.0, math.log(10.0)),
    (lambda x: 1.0 if x > 0.3 else -1.0, 0.0, 1.0, 0.3),          # a step: bisection must get there
    (lambda x: math.tan(x) - 1.0, 0.0, 1.2, math.pi / 4),
]


@pytest.mark.reference("second method", "scipy.optimize.brentq and the closed-form roots")
@pytest.mark.parametrize("f, a, b, exact", ROOTS)
def test_brent_root_against_closed_form_and_scipy(f, a, b, exact):
    x = brent_root(f, a, b, xtol=1e-14)
    reference = brentq(f, a, b, xtol=1e-14, maxiter=1000)
    assert abs(x - reference) <= 1e-12
    if exact is not None:
        assert abs(x - exact) <= 1e-12


@pytest.mark.reference("property", "no sign change: ValueError; a root at an end is returned exactly")
def test_brent_root_needs_a_bracket_and_returns_exact_ends():
    with pytest.raises(ValueError):
        brent_root(lambda x: x * x + 1.0, -1.0, 1.0)
    assert brent_root(lambda x: x - 1.0, 1.0, 3.0) == 1.0


MINIMA = [  # (f, a, b, closed-form minimiser, tolerance on f at the minimum)
    (lambda t: (t - 0.3) ** 2 + 1.0, 0.0, 1.0, 0.3, 1e-12),
    (lambda t: -math.sin(t), 0.0, 3.0, math.pi / 2, 1e-12),
    (lambda t: math.cosh(t - 1.7), -5.0, 5.0, 1.7, 1e-12),
    (lambda t: abs(t - 0.25), 0.0, 1.0, 0.25, 1e-8),                 # a kink: f is linear in the x error
    (lambda t: t**4 - 3 * t, 0.0, 2.0, (3 / 4) ** (1 / 3), 1e-12),
]


@pytest.mark.reference("second method", "scipy.optimize.minimize_scalar (bounded) and the closed-form minima")
@pytest.mark.parametrize("f, a, b, exact, f_tol", MINIMA)
def test_bounded_minimum_against_closed_form_and_scipy(f, a, b, exact, f_tol):
    x, fx = bounded_minimum(f, a, b, xatol=1e-12)
    reference = minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": 1e-12}).x
    # the abscissa of a smooth minimum is known to about sqrt(eps)·|x|; its value far better
    assert abs(x - exact) <= 1e-7 * max(1.0, abs(exact))
    assert abs(x - reference) <= 1e-7 * max(1.0, abs(exact))
    assert fx == pytest.approx(f(exact), abs=f_tol)


@pytest.mark.reference("property", "a minimum at the interval's end is returned inside it; an empty interval is "
                                   "refused")
def test_bounded_minimum_at_the_end_of_the_interval_stays_inside():
    x, _ = bounded_minimum(lambda t: t, 2.0, 3.0)
    assert 2.0 <= x < 2.0 + 1e-6
    with pytest.raises(ValueError):
        bounded_minimum(lambda t: t, 1.0, 1.0)


@pytest.mark.reference("closed form", "random quadratics: minimum and root at c, known exactly")
def test_many_random_quadratics_match_scipy():
    rng = np.random.default_rng(7)
    for _ in range(50):
        c, k = rng.uniform(-3, 3), rng.uniform(0.1, 10)
        a, b = c - rng.uniform(0.1, 4), c + rng.uniform(0.1, 4)
        x, _ = bounded_minimum(lambda t, k=k, c=c: k * (t - c) ** 2, a, b, xatol=1e-12)
        assert abs(x - c) <= 1e-7
        root = brent_root(lambda t, k=k, c=c: k * (t - c), a, b, xtol=1e-14)
        assert abs(root - c) <= 1e-13 * max(1, abs(c))
