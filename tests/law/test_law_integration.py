"""Exact and trapezoidal integration of a drawn (piecewise-linear) acceleration law."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from camcad.law.law import PiecewiseLinearLaw, integrate_exact, integrate_trapezoid
from camcad.law.standard import compose


@pytest.mark.reference("closed form", "v and s of a two-segment polyline with a jump, integrated by hand (trapezoid "
                                      "and Simpson-exact sums)")
def test_exact_integrator_reproduces_hand_computed_sums():
    # Law: a rises 0 -> 2 on [0, 1], jumps to -1 at x = 1, rises -1 -> 1 on [1, 3] (rad).
    # By hand (v = ∫a, s = ∫v, from rest at 0):
    #   segment 1: v(1) = 1·(0 + 2)/2 = 1,        s(1) = 1²·(2·0 + 2)/6 = 1/3
    #   jump:      nothing changes
    #   segment 3: v(3) = 1 + 2·(−1 + 1)/2 = 1,  s(3) = 1/3 + 1·2 + 2²·(2·(−1) + 1)/6 = 5/3
    #   at θ = 2:  a = 0, v = 1 − 1 + 1/2 = 1/2,  s = 1/3 + 1 − 1/2 + 1/6 = 1
    x = np.array([0.0, 1.0, 1.0, 3.0])
    a = np.array([0.0, 2.0, -1.0, 1.0])
    v, s = integrate_exact(x, a)
    assert v == pytest.approx([0.0, 1.0, 1.0, 1.0], abs=1e-12)
    assert s == pytest.approx([0.0, 1 / 3, 1 / 3, 5 / 3], abs=1e-12)
    law = PiecewiseLinearLaw(x, a, cycle=3.0)
    kin = law.kinematics(np.array([2.0, 0.5]))
    # at θ = 0.5: a = 1, v = 0.5²·2/2 = 0.25, s = 2·0.5³/6 = 1/24
    assert kin.a == pytest.approx([0.0, 1.0], abs=1e-12)
    assert kin.v == pytest.approx([0.5, 0.25], abs=1e-12)
    assert kin.s == pytest.approx([1.0, 1 / 24], abs=1e-12)
    assert kin.j == pytest.approx([1.0, 2.0], abs=1e-12)


@pytest.mark.reference("second method", "scipy.integrate.quad of the interpolated acceleration (v) and of v (s)")
@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.floats(0.01, 1.0), st.floats(-50, 50)), min_size=2, max_size=30))
def test_exact_integration_matches_high_order_quadrature(segments):
    # Independent route: scipy's adaptive quadrature of the interpolated a (v) and of v (s).
    from scipy.integrate import quad

    lengths, values = zip(*segments)
    x = np.concatenate(([0.0], np.cumsum(lengths)))
    a = np.concatenate(([values[0]], values))
    law = PiecewiseLinearLaw(x, a, cycle=float(x[-1]))
    end = float(x[-1])
    v_ref = quad(lambda t: float(np.interp(t, x, a)), 0, end, points=x[1:-1], limit=200)[0]
    s_ref = quad(lambda t: (end - t) * float(np.interp(t, x, a)), 0, end, points=x[1:-1], limit=200)[0]
    kin = law.kinematics(np.array([end]))
    scale = max(1.0, np.abs(a).max() * end**2)
    assert kin.v[0] == pytest.approx(v_ref, abs=1e-9 * scale)
    assert kin.s[0] == pytest.approx(s_ref, abs=1e-9 * scale)


def _drawn_cycloidal(n_vertices: int):
    """A cycloidal dwell–rise–dwell–return law (lift 1) drawn through n uniformly spaced vertices.

    n − 1 is not a multiple of 4, so the vertices miss the phase boundaries: the drawing does not
    balance by symmetry, as a designer's hand-placed vertices would not.
    """
    law = compose([("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)], 1.0)
    theta = np.linspace(0.0, 2 * np.pi, n_vertices)
    return law, PiecewiseLinearLaw(theta, law.kinematics(theta).a, 2 * np.pi, law.phases)


@pytest.mark.reference("property", "linear interpolation of a smooth a: closure error O(h^2), observed order in (1.8, "
                                   "2.2)")
def test_closure_errors_of_a_drawn_cycloidal_law_converge_at_second_order():
    # Linear interpolation of a smooth a has error O(h²); its integrals inherit O(h²).
    from camcad.balance.checking import check

    errors = []
    sizes = [103, 203, 403, 803]
    for n in sizes:
        _, drawn = _drawn_cycloidal(n)
        report = check(drawn)
        errors.append(max(abs(report.velocity_closure["rise"]), abs(report.displacement_closure),
                          abs(report.rise - 1.0)))
    h = 2 * np.pi / (np.array(sizes) - 1)
    order = np.polyfit(np.log(h), np.log(errors), 1)[0]
    assert 1.8 < order < 2.2, (order, errors)


@pytest.mark.reference("property", "trapezoid rule: error O(h^2) in the step, exact for v on the drawn knots (a "
                                   "linear between them)")
def test_trapezoid_error_is_second_order_in_the_step_and_exact_on_the_knots():
    _law, drawn = _drawn_cycloidal(203)
    exact_end = drawn.kinematics(np.array([2 * np.pi])).s[0]
    errs = []
    steps = np.radians([0.4, 0.2, 0.1, 0.05])
    for step in steps:
        _grid, _, _v, s = integrate_trapezoid(drawn.x, drawn.a, step)
        errs.append(abs(s[-1] - exact_end))
    order = np.polyfit(np.log(steps), np.log(errs), 1)[0]
    assert 1.7 < order < 2.3, (order, errs)
    # on the drawn knots themselves the trapezoid is exact for v (a is linear between them)
    v_exact, _ = integrate_exact(drawn.x, drawn.a)
    dx = np.diff(drawn.x)
    v_trap = np.concatenate(([0.0], np.cumsum(dx * (drawn.a[:-1] + drawn.a[1:]) / 2)))
    assert np.max(np.abs(v_trap - v_exact)) < 1e-12


@pytest.mark.reference("closed form", "a = 1 from rest: s = theta^2/2 at the cycle end; the state one cycle later is "
                                      "the same")
def test_law_is_periodic_and_keeps_the_cycle_end():
    x = np.array([0.0, 1.0, 2.0])
    law = PiecewiseLinearLaw(x, np.array([1.0, 1.0, 1.0]), cycle=2.0)
    kin = law.kinematics(np.array([0.5, 2.5, 2.0]))
    assert kin.s[0] == pytest.approx(kin.s[1])      # one cycle later: same state (wrapped)
    assert kin.s[2] == pytest.approx(2.0)           # s(T) itself is kept (s = θ²/2 at θ = 2)


@pytest.mark.reference("property", "the integrals are linear in a: laws scaled by 1e-6 and 1e6 give scaled v and s to "
                                   "round-off")
def test_scale_invariance_tiny_and_huge_ordinates():
    # the integrals are linear in a: 1e-6 and 1e6 scaled laws give scaled closures to round-off
    _, drawn = _drawn_cycloidal(203)
    base = drawn.kinematics(np.array([np.pi, 2 * np.pi]))
    for factor in (1e-6, 1e6):
        scaled = drawn.with_ordinates(drawn.a * factor).kinematics(np.array([np.pi, 2 * np.pi]))
        # round-off is relative to the size of the terms summed (the lift), not to the closure itself
        lift = np.ptp(drawn.kinematics(np.linspace(0, 2 * np.pi, 721)).s)
        assert scaled.s == pytest.approx(base.s * factor, abs=1e-12 * lift * factor)
        assert scaled.v == pytest.approx(base.v * factor, abs=1e-12 * lift * factor)
