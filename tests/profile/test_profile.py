"""Profile synthesis: geometry against independent numerical methods, checks, design helper, CLI."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest
import shapely

from camcad.errors import CamcadError
from camcad.law.law import PiecewiseLinearLaw
from camcad.law.standard import compose
from camcad.profile.design import min_base_radius
from camcad.profile.followers import Follower
from camcad.profile.geometry import CamGeometry, rotate
from camcad.profile.scaled_law import swing_law
from camcad.profile.summary import profile_report as report
from camcad.profile.synth import ProfileSettings, synthesize
from camcad.scene.sections.follower import FOLLOWER_FIELDS, parse_follower

LAW = compose([("rise", 120), ("dwell", 60), ("return", 120), ("dwell", 60)], 25.0, "cycloidal", "poly345")
FAST = ProfileSettings(design=False, plots=False, analysis_step_deg=0.5)

FOLLOWERS = {
    "roller e=0": Follower("roller", 50.0, 10.0, 0.0),
    "roller e>0": Follower("roller", 50.0, 10.0, 12.0),
    "roller e<0": Follower("roller", 50.0, 10.0, -12.0),
    "roller e>0 cw": Follower("roller", 50.0, 10.0, 12.0, cw=True),
    "knife": Follower("knife", 45.0, 0.0, 5.0),
    "flat": Follower("flat", 50.0),
    "oscillating": Follower("oscillating", 40.0, 10.0, pivot=120.0, arm=100.0),
    "oscillating cw": Follower("oscillating", 40.0, 10.0, pivot=120.0, arm=100.0, cw=True),
}


def law_for(follower: Follower):
    return swing_law(LAW, arm_mm=follower.arm) if follower.kind == "oscillating" else LAW


def sample_angles() -> np.ndarray:
    """θ away from the law's breakpoints (0, 120, 180, 300°) by more than the difference stencils,
    which must not straddle a jump of the jerk."""
    theta = np.radians(np.arange(2.5, 360.0, 5.0))
    edges = np.radians([0.0, 120.0, 180.0, 300.0, 360.0])
    return theta[np.min(np.abs(theta[:, None] - edges[None, :]), axis=1) > np.radians(1.0)]


def derivative(points_at, theta: np.ndarray, h: float) -> np.ndarray:
    """Fourth-order central difference of generated points: (P(−2h) − 8P(−h) + 8P(h) − P(2h)) / 12h."""
    return (points_at(theta - 2 * h) - 8 * points_at(theta - h) + 8 * points_at(theta + h)
            - points_at(theta + 2 * h)) / (12 * h)


def circumradius(points_at, theta: np.ndarray, h: float, sigma: float) -> np.ndarray:
    """Signed radius of the circle through P(θ − h), P(θ), P(θ + h), extrapolated to h → 0.

    R = |a||b||c| / (2 |(P1 − P0) × (P2 − P1)|); its sign is the turn of the triple, negated for a
    clockwise-traversed curve (σ = +1) so that convex is positive. The triple is symmetric in h,
    so R(h) = ρ + c h² + O(h⁴) and Richardson's (4R(h/2) − R(h))/3 removes the h² term."""
    def radius(step):
        p0, p1, p2 = points_at(theta - step), points_at(theta), points_at(theta + step)
        a, b = p1 - p0, p2 - p1
        c = p2 - p0
        turn = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        return -sigma * np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1) * np.linalg.norm(c, axis=1) / (2 * turn)

    return (4 * radius(h / 2) - radius(h)) / 3


@pytest.mark.reference("second method", "circumradii of triples of generated points, and the normal from differences "
                                        "of generated points")
@pytest.mark.parametrize("key", list(FOLLOWERS))
def test_pressure_angle_and_curvature_match_numerical_methods(key):
    follower = FOLLOWERS[key]
    cam = CamGeometry(law_for(follower), follower)
    theta = sample_angles()
    sigma = follower.sigma

    # radius of curvature: closed form against circumradii of triples of generated points
    for curve in (cam.profile, cam.pitch):
        rho = curve(theta).rho
        numeric = circumradius(lambda t, curve=curve: curve(t).points, theta, 2e-3, sigma)
        assert np.max(np.abs(numeric - rho) / np.abs(rho)) < 1e-6, curve.__name__

    # pressure angle: the profile's normal comes from differences of its generated points (turned
    # back into the fixed frame); the follower's path direction w from the generated roller centre:
    # (0, 1) for a translating follower, perpendicular to the arm pivot→centre for an oscillating one.
    # |φ| is the angle between the normal line and w: |φ| = atan2(|w·t|, |w × t|), t the unit tangent.
    tangent = rotate(derivative(lambda t: cam.profile(t).points, theta, 1e-3), sigma * theta)
    tangent /= np.linalg.norm(tangent, axis=1)[:, None]
    if follower.kind == "oscillating":
        centre = rotate(cam.pitch(theta).points, sigma * theta)
        arm = centre - np.array([follower.pivot, 0.0])
        w = np.stack((-arm[:, 1], arm[:, 0]), axis=1) / np.linalg.norm(arm, axis=1)[:, None]
    else:
        w = np.tile([0.0, 1.0], (len(theta), 1))
    along = np.abs(w[:, 0] * tangent[:, 0] + w[:, 1] * tangent[:, 1])
    across = np.abs(w[:, 0] * tangent[:, 1] - w[:, 1] * tangent[:, 0])
    numeric_phi = np.arctan2(along, across)
    analytic = np.abs(cam.pressure_angle(theta))
    if follower.kind == "flat":
        assert np.max(numeric_phi) < 1e-9   # the face stays normal to its axis
        assert np.all(analytic == 0.0)
    else:
        assert np.max(np.abs(numeric_phi - analytic)) < 1e-6 * np.max(analytic)
        moving = analytic > np.radians(1.0)
        assert np.max(np.abs(numeric_phi - analytic)[moving] / analytic[moving]) < 1e-6


@pytest.mark.reference("closed form", "phi = atan((v - e)/(d + s)), d = sqrt(Rp^2 - e^2); Norton's rho for the offset "
                                      "roller")
@pytest.mark.parametrize("offset", [0.0, 12.0, -12.0])
def test_translating_roller_matches_the_textbook_formulas(offset):
    # docs/INTERFACE.md: φ = atan((v − e)/(d + s)), d = √(Rp² − e²) for the CCW cam; Norton's
    # ρ = ((d+s)² + (v−e)²)^{3/2} / ((d+s)² + (v−e)(2v−e) − a(d+s)) (derived for the offset roller).
    follower = Follower("roller", 50.0, 10.0, offset)
    cam = CamGeometry(LAW, follower)
    theta = np.linspace(0.0, 2 * math.pi, 721)
    kin = LAW.kinematics(theta)
    d = math.sqrt(60.0**2 - offset**2)
    phi = np.arctan((kin.v - offset) / (d + kin.s))
    y = d + kin.s
    rho = ((y**2 + (kin.v - offset) ** 2) ** 1.5) / (y**2 + (kin.v - offset) * (2 * kin.v - offset) - kin.a * y)
    assert np.allclose(cam.pressure_angle(theta), phi, rtol=0, atol=1e-13)
    assert np.allclose(cam.pitch(theta).rho, rho, rtol=1e-12)


@pytest.mark.reference("property", "the CW cam with offset e is the CCW cam with offset -e mirrored in the y axis")
def test_clockwise_cam_is_the_mirror_image():
    # Turning the cam the other way mirrors the mechanism: the CW profile with offset e is the CCW
    # profile with offset −e reflected in the y axis, point for point.
    theta = np.linspace(0.0, 2 * math.pi, 361)
    cw = CamGeometry(LAW, Follower("roller", 50.0, 10.0, 7.0, cw=True)).profile(theta).points
    ccw = CamGeometry(LAW, Follower("roller", 50.0, 10.0, -7.0)).profile(theta).points
    assert np.allclose(cw, ccw * np.array([-1.0, 1.0]), atol=1e-12)


@pytest.mark.reference("closed form", "phi = atan((L(1 + psi') - C cos g)/(C sin g)), g0 by the law of cosines")
def test_oscillating_pressure_angle_formula():
    # Derived in geometry.py: φ = atan((L(1 + ψ') − C cos γ)/(C sin γ)), γ = γ0 + ψ, CCW; γ0 by the
    # law of cosines (Rb + Rr)² = C² + L² − 2CL cos γ0.
    follower = FOLLOWERS["oscillating"]
    law = law_for(follower)
    cam = CamGeometry(law, follower)
    theta = np.linspace(0.0, 2 * math.pi, 361)
    kin = law.kinematics(theta)
    c, arm = 120.0, 100.0
    gamma = math.acos((c**2 + arm**2 - 50.0**2) / (2 * c * arm)) + kin.s
    phi = np.arctan((arm * (1 + kin.v) - c * np.cos(gamma)) / (c * np.sin(gamma)))
    assert np.allclose(cam.pressure_angle(theta), phi, rtol=0, atol=1e-13)


def roller_clearance(cam: CamGeometry, polygon_points: np.ndarray, theta: np.ndarray, second=False) -> np.ndarray:
    """Distance from the roller centre to the cam polygon at each θ, the centre taken in the cam's
    frame — an envelope check independent of the offset-curve formula."""
    ring = shapely.LinearRing(polygon_points)
    centres = cam.pitch(theta, second=second).points
    return shapely.distance(shapely.points(centres), ring)


@pytest.mark.reference("second method", "the roller's distance from the written polygon at every angle (shapely), "
                                        "within the chord tolerance")
@pytest.mark.parametrize("follower", [Follower("roller", 50.0, 10.0, 8.0, groove=True, pair_distance=150.0),
                                      Follower("oscillating", 40.0, 10.0, pivot=120.0, arm=100.0,
                                               pair_angle_deg=60.0)])
def test_rollers_touch_but_never_cut_their_cams(follower):
    # The roller (radius Rr) rolling round the written polygon stays at distance Rr from it at every θ,
    # to within the chord tolerance, for the cam, the groove's outer flank and the counter-cam.
    result = synthesize(law_for(follower), follower, FAST)
    cam = result.geometry
    theta = np.linspace(0.0, 2 * math.pi, 721)
    tol = FAST.tol_mm
    for curve, second in ((result.profile, False), (result.counter, True)):
        gap = roller_clearance(cam, curve.polyline.points, theta, second) - follower.roller_radius
        assert np.max(np.abs(gap)) <= tol
    if follower.groove:
        gap = roller_clearance(cam, result.outer.polyline.points, theta) - follower.roller_radius
        assert np.max(np.abs(gap)) <= tol
    assert result.passed and not result.undercut
    counter = report(result)["counter_cam"]
    assert counter["closed"] and counter["simple"]


@pytest.mark.reference("closed form", "hand geometry: a second roller D below comes within Rr of the axis for 50 <= D "
                                      "<= 95")
@pytest.mark.parametrize("distance", [60.0, 65.0, 85.0])
def test_pair_whose_second_roller_crosses_the_shaft_is_refused(distance):
    # Rb 50, Rr 10, lift 25: the first roller centre runs from 60 to 85 mm above the axis, so a second
    # roller D below it comes within Rr of the axis for 50 <= D <= 95 (hand geometry, no offset).
    follower = Follower("roller", 50.0, 10.0, pair_distance=distance)
    with pytest.raises(CamcadError) as caught:
        synthesize(law_for(follower), follower, FAST)
    assert "pair_distance" in caught.value.where and "cam centre" in caught.value.what


def pitch_radius_min_numeric(cam: CamGeometry) -> float:
    """Smallest convex radius of the pitch curve from circumradii of generated points (dense)."""
    theta = np.linspace(0.0, 2 * math.pi, 72001)
    rho = circumradius(lambda t: cam.pitch(t).points, theta, 1e-3, cam.sigma)
    return float(np.min(rho[rho > 0]))


@pytest.mark.reference("closed form", "the pitch curve's smallest convex radius rho_min: Rr = rho_min/1.01 passes, "
                                      "rho_min/0.99 is flagged")
def test_undercut_threshold_at_one_percent():
    # A steep rise on a small pitch circle: the pitch curve (which depends on Rp = Rb + Rr only) has a
    # smallest convex radius ρ_min. Rr = ρ_min/1.01 must pass; Rr = ρ_min/0.99 must be flagged.
    steep = compose([("rise", 60), ("dwell", 120), ("return", 60), ("dwell", 120)], 20.0, "poly345")
    rp = 40.0
    probe = CamGeometry(steep, Follower("roller", rp - 1.0, 1.0))
    rho_min = pitch_radius_min_numeric(probe)
    assert rho_min < rp   # the rise makes the pitch curve sharper than its base circle
    ok = synthesize(steep, Follower("roller", rp - rho_min / 1.01, rho_min / 1.01), FAST)
    assert not ok.undercut and ok.profile.simple
    assert ok.rho_pitch_min.value == pytest.approx(rho_min, rel=1e-6)
    bad = synthesize(steep, Follower("roller", rp - rho_min / 0.99, rho_min / 0.99), FAST)
    assert bad.undercut and "convex pitch radius" in bad.undercut_reasons[0]
    assert not bad.passed


@pytest.mark.reference("second method", "shapely finds the offset ring not simple")
def test_case_built_to_undercut_is_flagged_and_loops():
    # 25 mm in 40° on Rp = 35 mm with Rr = 15 mm: the convex pitch radius falls far below Rr, the
    # offset curve crosses itself, and shapely sees a polygon that is not simple.
    law = compose([("rise", 40), ("dwell", 140), ("return", 40), ("dwell", 140)], 25.0, "cycloidal")
    result = synthesize(law, Follower("roller", 20.0, 15.0), FAST)
    assert result.undercut
    assert result.rho_pitch_min.value < 15.0
    assert not result.profile.simple
    assert any("not simple" in reason for reason in result.undercut_reasons)


@pytest.mark.reference("closed form", "flat face: rho = Rb + s + a < 0 is a cusp")
def test_flat_face_cusp_is_flagged():
    # ρ = Rb + s + a < 0 where the deceleration is large on a small base circle.
    law = compose([("rise", 60), ("dwell", 120), ("return", 60), ("dwell", 120)], 25.0, "cycloidal")
    kin = law.kinematics(np.linspace(0.0, 2 * math.pi, 100001))
    rb = 0.5 * float(-np.min(kin.s + kin.a))  # half of what the face needs
    result = synthesize(law, Follower("flat", rb), FAST)
    assert result.undercut and not result.profile.simple


@pytest.mark.reference("closed form", "d_min = max over theta of |v - e|/tan(limit) - s, Rb = sqrt(d_min^2 + e^2) - Rr")
@pytest.mark.parametrize("offset, cw, reversible", [(0.0, False, False), (8.0, False, False),
                                                     (-8.0, False, True), (8.0, True, False)])
def test_smallest_base_radius_equals_the_per_angle_closed_form(offset, cw, reversible):
    # For a translating roller |φ| ≤ limit ⇔ d ≥ |v − σe|/tan(limit) − s at every θ, so
    # d_min = max over θ of that (dense grid), Rb = √(d_min² + e²) − Rr.
    follower = Follower("roller", 50.0, 10.0, offset, cw=cw, reversible=reversible,
                        pressure_angle_limit_rise_deg=30.0, pressure_angle_limit_return_deg=40.0)
    design = min_base_radius(LAW, follower)
    theta = np.linspace(0.0, 2 * math.pi, 400001)
    kin = LAW.kinematics(theta)
    limit = np.where(kin.v < 0, math.radians(40.0), math.radians(30.0))
    if reversible:
        limit = np.full_like(theta, math.radians(30.0))
    sigma = -1.0 if cw else 1.0
    d_min = np.max(np.abs(kin.v - sigma * offset) / np.tan(limit) - kin.s)
    expected = math.hypot(d_min, offset) - 10.0
    assert design.rb_pressure_angle == pytest.approx(expected, rel=1e-7)
    # and the cam built on it sits on its limit: the worst margin is zero (to the solver's tolerance)
    result = synthesize(LAW, follower.with_base_radius(design.rb_pressure_angle), FAST)
    assert result.pressure_angle.passed
    assert abs(result.pressure_angle.worst_margin.value) < 1e-8


@pytest.mark.reference("property", "the designed Rb gives the smallest convex radius exactly at the 30 mm limit; a "
                                   "smaller Rb fails")
def test_smallest_base_radius_for_a_curvature_limit():
    # With ρ_min = 30 mm the design's Rb makes the smallest convex profile radius exactly 30 mm.
    steep = compose([("rise", 60), ("dwell", 120), ("return", 60), ("dwell", 120)], 20.0, "poly345")
    follower = Follower("roller", 40.0, 8.0, rho_min=30.0, pressure_angle_limit_rise_deg=None,
                        pressure_angle_limit_return_deg=None)
    design = min_base_radius(steep, follower)
    assert design.limited_by == "curvature"
    result = synthesize(steep, follower.with_base_radius(design.rb_min), FAST)
    assert result.profile.rho_convex_min.value == pytest.approx(30.0, rel=1e-7)
    assert result.curvature_passed
    smaller = synthesize(steep, follower.with_base_radius(design.rb_min - 0.01), FAST)
    assert not smaller.curvature_passed


@pytest.mark.reference("property", "the designed Rb sits on the pressure-angle limit (margin < 1e-7); below it fails")
def test_oscillating_design_sits_on_the_limit():
    follower = Follower("oscillating", 40.0, 10.0, pivot=120.0, arm=100.0)
    law = law_for(follower)
    design = min_base_radius(law, follower)
    assert design.rb_min is not None and 10.0 < design.rb_min < 40.0
    on_limit = synthesize(law, follower.with_base_radius(design.rb_pressure_angle), FAST)
    assert on_limit.pressure_angle.passed and abs(on_limit.pressure_angle.worst_margin.value) < 1e-7
    below = synthesize(law, follower.with_base_radius(design.rb_pressure_angle - 0.05), FAST)
    assert not below.pressure_angle.passed


@pytest.mark.reference("property", "a limit between the rise's and the return's peaks fails exactly the phase with "
                                   "the higher peak")
def test_pressure_angle_limits_per_phase_and_reversible():
    # On Rb = 25 mm the default law peaks at different |φ| on the rise (cycloidal) and on the return
    # (3-4-5). A limit halfway between the two peaks fails exactly the phase with the higher peak;
    # a reversible cam applies its rise limit to the return as well.
    follower = Follower("roller", 25.0, 10.0, pressure_angle_limit_rise_deg=40.0,
                        pressure_angle_limit_return_deg=40.0)
    result = synthesize(LAW, follower, FAST)
    rise, back = result.pressure_angle.rise_max.value, result.pressure_angle.return_max.value
    assert result.pressure_angle.passed and abs(rise - back) > math.radians(0.5)
    middle = math.degrees(rise + back) / 2
    strict_return = replace(follower, pressure_angle_limit_return_deg=middle)
    strict_rise = replace(follower, pressure_angle_limit_rise_deg=middle)
    assert synthesize(LAW, strict_return, FAST).pressure_angle.passed is bool(back < rise)
    assert synthesize(LAW, strict_rise, FAST).pressure_angle.passed is bool(rise < back)
    # reversible: only the rise limit is given, and the higher of the two peaks must respect it
    reversible = replace(follower, pressure_angle_limit_rise_deg=middle, pressure_angle_limit_return_deg=None,
                         reversible=True)
    assert not synthesize(LAW, reversible, FAST).pressure_angle.passed
    not_reversible = replace(reversible, reversible=False)
    assert synthesize(LAW, not_reversible, FAST).pressure_angle.passed is bool(rise < back)


@pytest.mark.reference("closed form", "a return 10 % short leaves s(360) = 0.1 h: the profile opens by that along the "
                                      "axis")
def test_unbalanced_drawn_law_does_not_close():
    # A drawn acceleration whose return is 10 % short: s(360°) = 0.1·h, so the pitch curve and the
    # profile (translating, e = 0) open by exactly that amount along the follower axis.
    beta = math.pi / 2
    h = 20.0
    peak = 4 * h / beta**2   # constant acceleration rise: ±peak over each half
    x = np.array([0, 0, 0.5, 0.5, 1, 1, 2, 2, 2.5, 2.5, 3, 3, 4]) * beta
    a = np.array([0, peak, peak, -peak, -peak, 0, 0, -0.9 * peak, -0.9 * peak, 0.9 * peak, 0.9 * peak, 0, 0])
    law = PiecewiseLinearLaw(x, a, 2 * math.pi)
    drift = float(law.kinematics(np.array([2 * math.pi])).s[0])
    assert drift == pytest.approx(0.1 * h, rel=1e-12)
    result = synthesize(law, Follower("roller", 50.0, 10.0), FAST)
    assert not result.profile.closed
    assert result.profile.closure_gap == pytest.approx(drift, rel=1e-12)
    assert not result.passed and any("does not close" in note for note in result.notes)


@pytest.mark.reference("property", "a balanced polyline law closes (gap < 1e-12) within the chord tolerance")
def test_balanced_drawn_law_closes_and_meets_the_tolerance():
    # Constant-acceleration rise and return drawn as a polyline (jumps of a at the knots).
    beta, h = math.pi / 2, 20.0
    peak = 4 * h / beta**2
    x = np.array([0, 0, 0.5, 0.5, 1, 1, 2, 2, 2.5, 2.5, 3, 3, 4]) * beta
    a = np.array([0, peak, peak, -peak, -peak, 0, 0, -peak, -peak, peak, peak, 0, 0])
    law = PiecewiseLinearLaw(x, a, 2 * math.pi)
    result = synthesize(law, Follower("roller", 40.0, 10.0), FAST)
    assert result.profile.closed and result.profile.closure_gap < 1e-12
    # the chords' own check stays within the tolerance; the DXF tests measure it independently
    assert result.profile.polyline.max_deviation <= FAST.tol_mm


@pytest.mark.reference("property", "a 180 deg law makes a two-lobe cam unchanged by a half turn (shapely distance)")
def test_two_lobe_cam_is_symmetric():
    # A law over 180° makes a cam with two lobes: the profile is unchanged by a half turn.
    law = compose([("rise", 60), ("dwell", 30), ("return", 60), ("dwell", 30)], 10.0, "cycloidal", cycle_deg=180.0)
    result = synthesize(law, Follower("roller", 40.0, 8.0), FAST)
    assert result.geometry.lobes == 2 and result.profile.closed and result.profile.simple
    points = result.profile.polyline.points
    turned = -points   # rotation by 180°
    ring = shapely.LinearRing(points)
    assert np.max(shapely.distance(shapely.points(turned), ring)) < FAST.tol_mm


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_law_cycle_must_divide_a_turn():
    law = compose([("rise", 100), ("return", 100), ("dwell", 50)], 10.0, cycle_deg=250.0)
    with pytest.raises(CamcadError, match="does not divide"):
        synthesize(law, Follower("roller", 40.0, 8.0), FAST)


@pytest.mark.reference("closed form", "oscillating follower: Rb + Rr = sqrt(C^2 + L^2 - 2CL cos g0)")
def test_parse_follower_table():
    follower = parse_follower({"type": "roller", "base_radius": 40, "roller_radius": 8, "offset": 5,
                               "pressure_angle_limit_rise": 28, "reversible": True, "cw": True}, "s.toml [follower]")
    assert (follower.base_radius, follower.roller_radius, follower.offset) == (40.0, 8.0, 5.0)
    assert follower.pressure_angle_limit_rise_deg == 28.0 and follower.reversible and follower.cw
    # oscillating with initial_angle: Rb + Rr = √(C² + L² − 2CL cos γ0) (law of cosines)
    osc = parse_follower({"type": "oscillating", "roller_radius": 10, "pivot": 120, "arm": 100,
                          "initial_angle": 25}, "w")
    assert osc.base_radius + 10 == pytest.approx(
        math.sqrt(120**2 + 100**2 - 2 * 120 * 100 * math.cos(math.radians(25))))
    assert {field.name for field in FOLLOWER_FIELDS} >= {
        "type", "base_radius", "roller_radius", "offset", "pivot", "arm", "initial_angle",
        "pressure_angle_limit_rise", "pressure_angle_limit_return", "reversible", "cw"}


@pytest.mark.reference("closed form", "tan phi = (v - e)/(sqrt(Rp^2 - e^2) + s) reaches the 30 deg limit at the sized "
                                      "base radius")
@pytest.mark.parametrize("table", [
    {"type": "oscillating", "roller_radius": 10, "pivot": 120, "arm": 100, "pressure_angle_limit_rise": 30,
     "pressure_angle_limit_return": 40},
    {"type": "roller", "roller_radius": 3, "offset": 12, "pressure_angle_limit_rise": 30,
     "pressure_angle_limit_return": 30},
])
def test_auto_base_radius_for_every_follower(table):
    # An oscillating follower, and an offset larger than 1 mm + Rr, once refused while the base radius was
    # unknown. The sized base radius is the one min_base_radius gives for the same follower with any valid
    # base radius; for the offset roller, the largest |phi| at that radius from the closed form
    # tan phi = (v - e)/(sqrt(Rp^2 - e^2) + s) (CCW cam, no other source) equals the 30 deg limit.
    from camcad.scene.follower import follower_for_law

    sized, law, _, notes = follower_for_law({**table, "auto_base_radius": True}, "s.toml [follower]", LAW)
    given = parse_follower({**table, "base_radius": 70.0}, "s.toml [follower]")
    assert sized.base_radius == pytest.approx(min_base_radius(law, given).rb_min, rel=1e-12)
    assert "smallest that meets the limits" in notes[0]
    if table["type"] == "roller":
        k = LAW.kinematics(np.linspace(0.0, 2 * math.pi, 200001))
        rp, e = sized.base_radius + 3.0, 12.0
        phi = np.degrees(np.arctan(np.abs(k.v - e) / (math.sqrt(rp**2 - e**2) + k.s)))
        assert phi.max() == pytest.approx(30.0, abs=1e-6)


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("table, message", [
    ({"type": "roller", "base_radius": 40, "roler_radius": 8}, "did you mean 'roller_radius'"),
    ({"type": "roller", "base_radius": 40}, "roller_radius"),
    ({"type": "oscillating", "base_radius": 40, "roller_radius": 8, "pivot": 100}, "pivot' and 'arm'"),
    ({"type": "oscillating", "base_radius": 40, "roller_radius": 8, "pivot": 100, "arm": 90,
      "initial_angle": 20}, "not both"),
    ({"type": "roller", "base_radius": 40, "roller_radius": 8, "offset": 60}, "offset"),
    ({"type": "flat", "base_radius": 40, "pivot": 100}, "oscillating"),
    ({"type": "oscillating", "base_radius": 5, "roller_radius": 2, "pivot": 100, "arm": 50}, "cannot reach"),
])
def test_parse_follower_errors(table, message):
    with pytest.raises(CamcadError, match=message):
        parse_follower(table, "scene.toml [follower]")


@pytest.mark.reference("closed form", "law.csv: s at 60 deg of the cycloidal rise is h/2; the files written as "
                                      "documented")
def test_cli_default_run_in_a_fresh_directory(cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    run = cli("profile")
    assert run.code == 0, run.err
    out = tmp_path / "camcad-out" / "default"
    names = {p.name for p in out.iterdir()}
    # by default one summary page; --plots all draws every plot
    assert names == {"profile.dxf", "law.csv", "report.json", "summary.png"}
    every = cli("profile", "--plots", "all", "-o", tmp_path / "all")
    assert every.code == 0, every.err
    assert {p.name for p in (tmp_path / "all").iterdir()} == names | {
        "kinematics.png", "pressure_angle.png", "curvature.png", "profile.png", "hodograph.png"}
    assert not [n for n in names if n.endswith(".tmp")]
    data = json.loads((out / "report.json").read_text())
    for key in ("pressure_angle_max_deg", "pressure_angle_max_at_deg", "pressure_angle_min_deg",
                "pressure_angle_min_at_deg", "rho_pitch_min_mm", "rho_profile_min_mm", "undercut", "closed",
                "closure_gap_mm", "profile_points", "outputs"):
        assert key in data
    assert data["closed"] and not data["undercut"] and data["passed"]
    assert len(data["outputs"]) == len(names)
    # law.csv holds the law: s at 60° of the cycloidal rise is h/2 − 0 (u = 1/2: f = 1/2)
    rows = (out / "law.csv").read_text().splitlines()
    header = rows[0].split(",")
    row = dict(zip(header, rows[121].split(",")))
    assert float(row["theta_deg"]) == 60.0
    assert float(row["s_mm"]) == pytest.approx(12.5, rel=1e-11)


@pytest.mark.reference("property", "a base radius too small fails the pressure angle (exit 1); --auto-rb passes")
def test_cli_json_failures_and_errors(cli, tmp_path):
    good = cli("profile", "--json", "--no-plots", "-o", tmp_path / "a", "--arcs")
    assert good.code == 0
    payload = good.json()
    assert payload["profile_representation"] == "arcs" and payload["passed"]
    too_small = cli("profile", "--no-plots", "--rb", "10", "-o", tmp_path / "b", "--json")
    assert too_small.code == 1 and not too_small.json()["pressure_angle"]["passed"]
    auto = cli("profile", "--no-plots", "--auto-rb", "-o", tmp_path / "c", "--json")
    assert auto.code == 0
    assert auto.json()["follower"]["base_radius_mm"] == pytest.approx(
        auto.json()["design"]["rb_min_mm"], rel=1e-6)
    bad = cli("profile", "--rb", "-5", "--no-plots", "-o", tmp_path / "d")
    assert bad.code == 2 and bad.err.startswith("camcad: error:") and len(bad.err.strip().splitlines()) == 1
    assert cli("profile", "--r12", "--spline", "-o", tmp_path / "e").code == 2
    assert cli("profile", "--follower", "oscillating", "-o", tmp_path / "f").code == 2
    osc = cli("profile", "--follower", "oscillating", "--pivot", "120", "--arm", "100", "--rb", "40",
              "--swing", "15", "--no-plots", "-o", tmp_path / "g", "--json")
    assert osc.code == 0 and osc.json()["swing_deg"] == pytest.approx(15.0, rel=1e-9)


@pytest.mark.reference("second method", "shapely's is_simple and is_valid on random star-shaped and broken rings")
def test_the_star_shaped_shortcut_never_calls_a_self_intersecting_ring_simple():
    # synth._is_simple skips shapely for rings that turn once about the cam axis; shapely (an
    # independent implementation) must find every such ring simple and valid, also when the axis is
    # off-centre or a vertex is thrown far out of place
    import shapely

    from camcad.profile.synth import _is_simple, _star_shaped

    rng = np.random.default_rng(7)
    star_count = 0
    for _ in range(2000):
        n = int(rng.integers(3, 60))
        theta = np.sort(rng.uniform(0.0, 2.0 * np.pi, n))[:: 1 if rng.random() < 0.5 else -1]
        radius = rng.uniform(0.5, 2.0, n)
        shift = rng.normal(0.0, 0.6, 2) * (rng.random() < 0.5)
        points = np.c_[radius * np.cos(theta), radius * np.sin(theta)] + shift
        if rng.random() < 0.3:
            points[rng.integers(0, n)] = rng.normal(0.0, 2.0, 2)
        ring = shapely.LinearRing(points)
        truth = bool(ring.is_simple and shapely.Polygon(ring).is_valid)
        if _star_shaped(points):
            star_count += 1
            assert truth
        assert _is_simple(points) == (truth and len(points) >= 4)
    assert 500 < star_count < 1900   # both branches are exercised
