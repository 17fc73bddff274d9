"""Standard rise shapes: peak coefficients, the SCCA family, consistency of the derivatives."""

from __future__ import annotations

import math
from itertools import pairwise

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.optimize import minimize_scalar

from camcad.law import standard
from camcad.law.standard import SCCA, compose, peak_coefficients, scca, shape_named

PI = math.pi

# Closed forms derived by hand (or published), independent of the code's own formulas:
# cycloidal  f' = 1 − cos 2πu → 2 at u = 1/2; f'' = 2π sin 2πu → 2π; f''' = 4π² cos 2πu → 4π².
# harmonic   f' = (π/2) sin πu → π/2; f'' = (π²/2) cos πu → π²/2 at the ends; f''' → π³/2 at u = 1/2.
# 3-4-5      f' = 30u²(1−u)² → 30/16 = 15/8; f'' = 60u − 180u² + 120u³, zero of f''' at
#            u = 1/2 − √3/6 gives 10/√3; f''' = 60 − 360u + 360u² → 60 at the ends.
# 4-5-6-7    f' = 140u³(1−u)³ → 140/64 = 35/16; f'' = 420u²(1−u)²(1−2u); with w = u − 1/2 its
#            extremum is at w² = 1/20: 420·2·(1/√20)(1/5)² = 84√5/25; f''' = 420(1/4 − w²)(10w² − 1/2),
#            largest magnitude at w = 0: 420/8 = 105/2.
# constant acceleration: f'' = ±4 (f = 2u² on the first half), f' → 2 at u = 1/2, f''' = 0 on each piece.
CLOSED_FORMS = {
    "cycloidal": (2.0, 2 * PI, 4 * PI**2),
    "harmonic": (PI / 2, PI**2 / 2, PI**3 / 2),
    "poly345": (15 / 8, 10 / math.sqrt(3), 60.0),
    "poly4567": (35 / 16, 84 * math.sqrt(5) / 25, 105 / 2),
    "constant_acceleration": (2.0, 4.0, 0.0),
}

# Norton (2009) table 3-2, 4 to 5 significant figures as published.
NORTON_TABLE = {
    "modified_trapezoid": (2.0000, 4.8881, 61.426),
    "modified_sine": (1.7596, 5.5280, 69.466),
}


def numeric_peak(shape, order: int) -> float:
    """sup |f^(order)| on [0, 1]: a 20 001-point grid plus a bounded Brent search around the best
    point, and the pieces' edges (SCCA breakpoints) approached from both sides."""
    u = np.linspace(0.0, 1.0, 20001)
    extra = []
    for b in getattr(shape, "breakpoints", lambda: ())():
        extra += [b - 1e-15, b, b + 1e-15]
    u = np.union1d(u, np.clip(extra, 0.0, 1.0))
    values = np.abs(shape.evaluate(u, order))
    k = int(np.argmax(values))
    best = float(values[k])
    lo, hi = u[max(k - 1, 0)], u[min(k + 1, len(u) - 1)]
    res = minimize_scalar(lambda x: -abs(float(shape.evaluate(np.array([x]), order)[0])), bounds=(lo, hi),
                          method="bounded", options={"xatol": 1e-14})
    return max(best, -float(res.fun))


@pytest.mark.reference("second method", "the peaks of each shape's f', f'', f''' found numerically on a dense grid")
@pytest.mark.parametrize("name", sorted(standard.SHAPES))
def test_peak_coefficients_are_the_true_peaks(name):
    # Every shape's closed-form Cv, Ca, Cj equal the peaks of its own f', f'', f''' found numerically.
    shape = shape_named(name)
    peaks = peak_coefficients(shape)
    for order, closed in ((1, peaks.cv), (2, peaks.ca), (3, peaks.cj)):
        assert numeric_peak(shape, order) == pytest.approx(closed, rel=1e-9, abs=1e-12)


@pytest.mark.reference("closed form", "Cv, Ca, Cj derived by hand for each standard shape (Norton 2009 ch. 3)")
@pytest.mark.parametrize("name", sorted(CLOSED_FORMS))
def test_peak_coefficients_equal_hand_derived_closed_forms(name):
    peaks = peak_coefficients(shape_named(name))
    cv, ca, cj = CLOSED_FORMS[name]
    assert peaks.cv == pytest.approx(cv, rel=1e-9)
    assert peaks.ca == pytest.approx(ca, rel=1e-9)
    assert peaks.cj == pytest.approx(cj, rel=1e-9, abs=1e-12)


@pytest.mark.reference("published", "Norton 2009, Cam Design and Manufacturing Handbook, table of Cv, Ca, Cj (4-5 "
                                    "significant figures)")
@pytest.mark.parametrize("name", sorted(NORTON_TABLE))
def test_modified_laws_match_nortons_table(name):
    # Published to 4–5 significant figures, so compared at 5e-5 relative.
    peaks = peak_coefficients(shape_named(name))
    for ours, published in zip((peaks.cv, peaks.ca, peaks.cj), NORTON_TABLE[name]):
        assert ours == pytest.approx(published, rel=5e-5)


@pytest.mark.reference("closed form", "which shapes' f'' jumps against a dwell (harmonic, constant acceleration) or "
                                      "mid-rise")
def test_acceleration_jumps_flag():
    # f'' jumps against a dwell (harmonic, constant acceleration: b = 0) or mid-rise (d = 0).
    jumps = {name: peak_coefficients(shape).acceleration_jumps for name, shape in standard.SHAPES.items()}
    assert jumps == {"cycloidal": False, "harmonic": True, "poly345": False, "poly4567": False, "poly56789": False,
                     "modified_trapezoid": False, "modified_sine": False, "constant_acceleration": True}


@pytest.mark.reference("closed form", "Norton's SCCA family: b = d = 1/2 is the cycloid, d = 1 the simple harmonic")
@pytest.mark.parametrize("members", [((0.5, 0.0, 0.5), standard.Cycloidal()),
                                     ((0.0, 0.0, 1.0), standard.SimpleHarmonic())])
def test_scca_members_equal_the_named_laws(members):
    # Norton: b = d = 1/2 is cycloidal, d = 1 is simple harmonic (every order, every u).
    factors, named = members
    u = np.linspace(0.0, 1.0, 1001)
    member = SCCA(*factors)
    for order in range(4):
        assert np.allclose(member.evaluate(u, order), named.evaluate(u, order), rtol=0, atol=1e-12)


@pytest.mark.reference("second method", "Cauchy's formula f(x) = int_0^x (x - u) f''(u) du by scipy quad, piece by "
                                        "piece")
@settings(max_examples=80, deadline=None)
@given(st.one_of(st.just(0.0), st.floats(1e-6, 1.0)), st.floats(0.0, 1.0))
def test_scca_integrates_to_a_unit_rise(b, fraction):
    # Independent of the closed-form antiderivatives: with f(0) = f'(0) = 0, Cauchy's formula
    # f(x) = ∫_0^x (x − u) f''(u) du and f'(x) = ∫_0^x f''(u) du, integrated numerically (quad,
    # piece by piece), must give f'(1) = 0, f'(1/2) = Cv and f(1) = 1; that fixes Ca (eq. 3.28).
    d = fraction * (1.0 - b)
    d = 0.0 if d < 1e-6 else d
    shape = SCCA(b, 1.0 - b - d, d)
    edges = [0.0, *shape.breakpoints(), 1.0]

    def integral(weight, upper):
        def integrand(u):
            return weight(u) * float(shape.evaluate(np.array([u]), 2)[0])
        return sum(quad(integrand, lo, min(hi, upper), epsabs=1e-14, epsrel=1e-13)[0]
                   for lo, hi in pairwise(edges) if lo < upper)

    assert integral(lambda u: 1.0, 1.0) == pytest.approx(0.0, abs=1e-11)
    assert integral(lambda u: 1.0, 0.5) == pytest.approx(shape.peaks().cv, rel=1e-10)
    assert integral(lambda u: 1.0 - u, 1.0) == pytest.approx(1.0, rel=1e-10)
    ends = shape.evaluate(np.array([0.0, 0.5, 1.0]), 0)
    assert np.allclose(ends, [0.0, 0.5, 1.0], atol=1e-13)


@pytest.mark.reference("second method", "central differences of f^(k) against f^(k+1), to 1e-6")
@pytest.mark.parametrize("name", sorted(standard.SHAPES))
def test_derivative_orders_are_consistent(name):
    # Central differences of f^(k) reproduce f^(k+1) (away from the pieces' edges), to 1e-6.
    shape = shape_named(name)
    u = np.linspace(0.013, 0.987, 97)
    edges = np.array(getattr(shape, "breakpoints", lambda: ())())
    if edges.size:
        u = u[np.min(np.abs(u[:, None] - edges[None, :]), axis=1) > 1e-3]
    h = 1e-5
    for order in range(3):
        difference = (shape.evaluate(u + h, order) - shape.evaluate(u - h, order)) / (2 * h)
        exact = shape.evaluate(u, order + 1)
        scale = max(1.0, float(np.max(np.abs(exact))))
        assert np.max(np.abs(difference - exact)) <= 1e-6 * scale


@pytest.mark.reference("closed form", "peak acceleration Ca h / beta^2; s and v back to 0 at every phase end")
def test_compose_with_modified_sine_closes_and_peaks():
    # A dwell-rise-dwell-return cycle: s returns to 0, v is 0 at every phase end, and the peak
    # acceleration is Ca h / β² (β = 90° for both moving phases).
    law = compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0, "modified_sine")
    theta = np.linspace(0.0, 2 * PI, 36001)
    kin = law.kinematics(theta)
    assert kin.s[-1] == pytest.approx(0.0, abs=1e-12)
    ends = law.kinematics(np.radians([0.0, 90.0, 180.0, 270.0, 360.0]))
    assert np.allclose(ends.v, 0.0, atol=1e-12)
    beta = PI / 2
    assert np.max(kin.a) == pytest.approx(standard.MODIFIED_SINE.ca * 20.0 / beta**2, rel=1e-6)


@pytest.mark.reference("property", "a shape named by its parameters b:c:d; bad names refused with the reason")
def test_scca_by_name_and_bad_names():
    shape = shape_named("scca:0.2:0.3:0.5")
    assert (shape.b, shape.c, shape.d) == (0.2, 0.3, 0.5)
    assert shape.name == "scca:0.2:0.3:0.5"
    with pytest.raises(KeyError, match="b \\+ c \\+ d"):
        shape_named("scca:0.2:0.3:0.6")
    with pytest.raises(KeyError, match="known"):
        shape_named("cycloid")
    with pytest.raises(ValueError):
        scca(-0.1, 0.6, 0.5)
    with pytest.raises(ValueError, match="too small"):
        scca(1e-12, 0.5, 0.5 - 1e-12)


@pytest.mark.reference("closed form", "the modified trapezoid's pieces meet at u = 1/8, 3/8, 1/2, 5/8, 7/8")
def test_composite_breakpoints_include_the_inner_pieces():
    # modified trapezoid over [0°, 120°]: its pieces meet at u = 1/8, 3/8, 1/2, 5/8, 7/8.
    law = compose([("rise", 120), ("dwell", 60), ("return", 120), ("dwell", 60)], 10.0, "modified_trapezoid")
    points = np.degrees(law.breakpoints())
    for expected in (15.0, 45.0, 60.0, 75.0, 105.0, 120.0, 180.0, 195.0, 300.0, 360.0):
        assert np.min(np.abs(points - expected)) < 1e-9
    assert law.describe().startswith("rise modified_trapezoid 0-120, dwell 120-180")


@pytest.mark.reference("closed form", "harmonic rise: a jumps to pi^2 h/(2 beta^2) (infinite jerk), cycloid's jerk "
                                      "peak 4 pi^2")
def test_laws_with_acceleration_jumps_have_an_infinite_peak_jerk():
    # the acceleration of a simple harmonic rise jumps from 0 (dwell) to π²h/(2β²): its jerk has a Dirac there
    harmonic = peak_coefficients(standard.SHAPES["harmonic"])
    assert harmonic.jerk == float("inf") and harmonic.to_dict()["cj"] is None
    assert harmonic.to_dict()["jerk_infinite"] and harmonic.to_dict()["cj_smooth"] == pytest.approx(math.pi**3 / 2)
    # the cycloidal rise starts and ends at a = 0: finite jerk 4π² (its closed form)
    cycloidal = peak_coefficients(standard.SHAPES["cycloidal"])
    assert cycloidal.jerk == pytest.approx(4 * math.pi**2, rel=1e-12) and cycloidal.to_dict()["cj"] is not None


@pytest.mark.reference("second method", "the array route kinematics(theta) against the scalar fast path, angle by "
                                        "angle")
def test_the_scalar_acceleration_equals_the_array_one_at_every_angle():
    # acceleration_at (the ODE right-hand side's fast path) against kinematics(...).a, composed and drawn
    # laws, angles inside and outside the cycle, at segment starts and at a jump
    from camcad.law.law import PiecewiseLinearLaw

    law = compose([("dwell", 40), ("rise", 70), ("dwell", 60), ("return", 70), ("dwell", 120)], 30.0, "poly345")
    starts = np.radians([0.0, 40.0, 110.0, 170.0, 240.0, 360.0])
    theta = np.concatenate((np.random.default_rng(1).uniform(-1.0, 8.0, 500), starts))
    assert [law.acceleration_at(t) for t in theta] == list(law.kinematics(theta).a)
    # s and v for the multi-mass model's right-hand side, and the wrapping of one angle
    kin = law.kinematics(theta)
    assert [law.motion_at(t) for t in theta] == list(zip(kin.s, kin.v))
    from camcad.law.law import wrap, wrap_angle

    assert [wrap_angle(float(t), law.cycle) for t in theta] == list(wrap(theta, law.cycle))
    x = np.sort(np.concatenate((np.linspace(0, 2 * math.pi, 50), [1.0, 1.0])))
    a = np.sin(3 * x)
    a[np.flatnonzero(x == 1.0)[1]] += 2.0                 # a jump of acceleration at x = 1
    drawn = PiecewiseLinearLaw(x, a, 2 * math.pi)
    np.testing.assert_allclose([drawn.acceleration_at(t) for t in theta], drawn.kinematics(theta).a,
                               rtol=0, atol=1e-14)
    assert drawn.acceleration_at(1.0) == drawn.kinematics(np.array([1.0])).a[0]   # the right-hand value
