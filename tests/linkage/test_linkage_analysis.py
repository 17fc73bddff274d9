"""Linkage analysis (camcad.linkage.analysis): exact Π, Π', Π'', Π''' against an independent route, special
positions in closed form, branch continuity, the six-bar, hard cases.

The independent route: the loop closure solved numerically (scipy fsolve on the two real equations, not
camcad's closed form) at Chebyshev points of the swing, then differentiated spectrally (numpy's Chebyshev
series). Its accuracy is that of the solve amplified by differentiation: ≈ 1e-12 for Π', 1e-10 for Π'',
1e-8 for Π''' relative with 24 points (measured on this linkage; the tolerances below leave a margin).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.polynomial import chebyshev as cheb
from scipy.optimize import fsolve

from camcad.errors import CamcadError
from camcad.linkage.analysis import Linkage, Loop, analyse, compose

LOOP = Loop((0.0, 0.0), (100.0, 20.0), 40.0, 120.0, 90.0, 1)
PSI_MAX = math.radians(30.0)


def _solve_loop(loop: Loop, theta: float, guess: tuple[float, float]) -> tuple[float, float]:
    """(λ, β) closing a e^{iθ} + b e^{iλ} − c e^{iβ} − (Q − P) = 0 by fsolve from ``guess``."""
    qp = complex(*loop.q) - complex(*loop.p)

    def equations(v):
        z = loop.a * np.exp(1j * theta) + loop.b * np.exp(1j * v[0]) - loop.c * np.exp(1j * v[1]) - qp
        return [z.real, z.imag]

    lam, beta = fsolve(equations, guess, xtol=1e-15, full_output=False)
    return float(lam), float(beta)


def _spectral(values_of, psi_max: float, n: int = 24):
    """Chebyshev interpolant of ψ ↦ value on [0, ψ_max] and a function giving its k-th derivative."""
    x = np.cos(np.pi * (np.arange(n) + 0.5) / n)
    psi = (x + 1) / 2 * psi_max
    coef = cheb.chebfit(x, values_of(psi), n - 1)

    def derivative(k, at):
        return cheb.chebval(2 * np.asarray(at) / psi_max - 1, cheb.chebder(coef, k) if k else coef) * (2 / psi_max) ** k

    return derivative


def _fsolve_output(linkage: Linkage, psi: np.ndarray) -> np.ndarray:
    """β_last at swings ψ by fsolve through every loop (continuation from camcad's ψ = 0 configuration)."""
    out = []
    order = np.argsort(psi)
    guesses = []
    for _loop, (_theta, d) in zip(linkage.loops, linkage.angles(0.0)):
        guesses.append((float(d[4]), float(d[0])))
    values = {}
    for i in order:
        theta = linkage.theta0 + linkage.input_sense * psi[i]
        for k, loop in enumerate(linkage.loops):
            lam, beta = _solve_loop(loop, theta, guesses[k])
            guesses[k] = (lam, beta)
            if k < len(linkage.couplings):
                theta = beta + linkage.couplings[k]
        values[i] = beta
    out = np.array([values[i] for i in range(len(psi))])
    return out


@pytest.mark.reference("second method", "scipy fsolve of the loop closure and spectral differentiation of its solution")
@pytest.mark.parametrize("sense", [1, -1])
def test_fourbar_derivatives_against_fsolve_and_spectral_differentiation(sense):
    lk = Linkage((LOOP,), theta0=math.radians(80.0), input_sense=sense)
    spectral = _spectral(lambda p: _fsolve_output(lk, p), PSI_MAX)
    at = np.linspace(0.03, PSI_MAX - 0.03, 9)
    mine = lk.absolute_derivatives(at)
    for k, tol in ((0, 1e-13), (1, 1e-11), (2, 1e-9), (3, 1e-7)):
        scale = np.max(np.abs(mine[k])) if k else 1.0
        assert np.max(np.abs(spectral(k, at) - mine[k])) <= tol * scale, k


@pytest.mark.reference("second method", "scipy fsolve of the six-bar's loops and spectral differentiation")
def test_sixbar_derivatives_against_fsolve_and_spectral_differentiation():
    second = Loop((100.0, 20.0), (180.0, -30.0), 50.0, 110.0, 70.0, -1)
    lk = Linkage((LOOP, second), theta0=math.radians(80.0), input_sense=-1, couplings=(math.radians(150.0),))
    res = analyse(lk, PSI_MAX)
    assert res.closes and res.branch_continuous
    spectral = _spectral(lambda p: _fsolve_output(lk, p), PSI_MAX)
    at = np.linspace(0.03, PSI_MAX - 0.03, 9)
    mine = lk.absolute_derivatives(at)
    for k, tol in ((0, 1e-13), (1, 1e-11), (2, 1e-9), (3, 1e-7)):
        scale = np.max(np.abs(mine[k])) if k else 1.0
        assert np.max(np.abs(spectral(k, at) - mine[k])) <= tol * scale, k


@pytest.mark.reference("closed form", "derivatives of exp(sin x) written out")
def test_faa_di_bruno_against_a_closed_form():
    # exp(sin x): f' = cos x e^s, f'' = (cos² − sin) e^s, f''' = (cos³ − 3 sin cos − cos) e^s
    x = 0.37
    s, c = math.sin(x), math.cos(x)
    d = compose((s, c, -s, -c), (math.exp(s),) * 4)
    e = math.exp(s)
    assert d[1] == pytest.approx(c * e, rel=1e-15)
    assert d[2] == pytest.approx((c * c - s) * e, rel=1e-14)
    assert d[3] == pytest.approx((c ** 3 - 3 * s * c - c) * e, rel=1e-14)


@pytest.mark.reference("closed form", "a parallelogram's output follows its input: Pi = psi, Pi' = 1")
def test_parallelogram_position_function_is_the_identity():
    lk = Linkage((Loop((0.0, 0.0), (300.0, 0.0), 80.0, 300.0, 80.0, -1),), theta0=1.0, input_sense=1)
    psi = np.linspace(0.0, 0.8, 11)
    pi, d1, d2, d3 = lk.position(psi)
    assert np.max(np.abs(pi - psi)) < 1e-13
    assert np.max(np.abs(d1 - 1)) < 1e-12 and np.max(np.abs(d2)) < 1e-12 and np.max(np.abs(d3)) < 1e-11


@pytest.mark.reference("closed form", "the diagonal reaches b + c = 2.5 at cos theta = (1 + 9 - 6.25)/6")
def test_dead_point_in_closed_form_and_branch_broken():
    # crank 1 at P, frame 3: the diagonal reaches b + c = 2.5 at cos θ = (1 + 9 − 6.25)/6
    loop = Loop((0.0, 0.0), (3.0, 0.0), 1.0, 1.5, 1.0, 1)
    expected = math.acos((1 + 9 - 6.25) / 6)
    assert min(abs(t - expected) for t in loop.dead_points()) < 1e-15
    # at the dead point the transmission angle is 0 or 180 (b, c aligned): independent check from the diagonal
    f = abs(complex(math.cos(expected), math.sin(expected)) - 3)
    assert f == pytest.approx(2.5, rel=1e-14)
    # a swing that reaches it from inside the working range
    lk = Linkage((loop,), theta0=expected - 0.3, input_sense=1)
    res = analyse(lk, 0.5)
    assert not res.branch_continuous
    assert any(abs(x - 0.3) < 1e-9 for x in res.dead_points)


@pytest.mark.reference("closed form", "Pi' = 0 where |PB| = a + b, B on the circles (P, a + b) and (Q, c)")
def test_limit_position_is_where_input_and_coupler_align():
    # a crank-rocker turned through its output's limit position: Π' = 0 where |PB| = a + b
    loop = Loop((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 2.5, 1)
    # the extended position: B on the circles (P, a + b) and (Q, c), B below the frame line on this branch
    bx = (16 - 6.25 + 9) / 6
    theta_ext = math.atan2(-math.sqrt(16 - bx * bx), bx)
    lk = Linkage((loop,), theta0=theta_ext - 0.3, input_sense=1)
    res = analyse(lk, 0.6)
    assert len(res.limit_positions) == 1 and not res.monotone
    psi = res.limit_positions[0]
    j = lk.joints(np.array([psi]))
    pb = abs(complex(np.asarray(j["B"])[0]) - complex(*loop.p))
    assert pb == pytest.approx(loop.a + loop.b, rel=1e-12)
    assert psi == pytest.approx(0.3, abs=1e-12)


@pytest.mark.reference("second method", "the transmission angle sampled densely")
def test_worst_transmission_angle_matches_the_sampled_one():
    lk = Linkage((LOOP,), theta0=math.radians(80.0), input_sense=-1)
    res = analyse(lk, PSI_MAX, points=20001)
    sampled = float(np.min(np.minimum(res.mu[0], np.pi - res.mu[0])))
    assert res.mu_min[0] == pytest.approx(sampled, abs=1e-7)


@pytest.mark.reference("closed form", "the coupler's midpoint is (A + B)/2")
def test_coupler_point_path():
    lk = Linkage((LOOP,), theta0=math.radians(80.0), coupler_point=(0, 60.0, 0.0))
    j = lk.joints(np.linspace(0, 0.4, 5))
    assert np.max(np.abs(j["P"] - (j["A"] + j["B"]) / 2)) < 1e-12


@pytest.mark.reference("property", "scaling every length leaves the position function unchanged to 1e-12")
@pytest.mark.parametrize("scale", [1e-3, 1e4])
def test_tiny_and_huge_scales_give_the_same_position_function(scale):
    lk = Linkage((LOOP,), theta0=math.radians(80.0))
    big = Linkage((Loop((0.0, 0.0), (100.0 * scale, 20.0 * scale), 40.0 * scale, 120.0 * scale, 90.0 * scale, 1),),
                  theta0=math.radians(80.0))
    psi = np.linspace(0, PSI_MAX, 7)
    for a, b in zip(lk.position(psi), big.position(psi)):
        assert np.max(np.abs(a - b)) <= 1e-12 * max(1.0, float(np.max(np.abs(a))))


@pytest.mark.reference("property", "a linkage that cannot close is reported so; bad input refused")
def test_a_linkage_that_does_not_close():
    lk = Linkage((Loop((0.0, 0.0), (300.0, 0.0), 40.0, 100.0, 90.0, 1),), theta0=0.0)
    res = analyse(lk, 0.3)
    assert not res.closes and not res.branch_continuous
    with pytest.raises(CamcadError):
        analyse(lk, 0.0)


@pytest.mark.reference("property", "the modules' docstring examples run and print what they say")
def test_docstring_examples_of_part_two_run():
    import doctest
    import importlib

    for name in ("analysis", "transfer", "adjust", "family", "tune"):
        module = importlib.import_module(f"camcad.linkage.{name}")
        failed, _ = doctest.testmod(module, optionflags=doctest.ELLIPSIS)
        assert failed == 0, name
