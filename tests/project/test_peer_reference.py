"""The peer comparison's reference (benchmarks/bench_peer.py) without the peer or the network.

The closed form there (pitch curve, roller profile and pressure angle of a centred translating
roller follower on the cycloidal dwell-rise-dwell-return cam, h = 20, Rb = 40, Rr = 10 mm) is
checked against camcad's geometry, against finite differences of its own points, and the
distance kernels it measures errors with are checked on curves whose distances are known.
Nothing here installs or runs the peer.
"""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

from camcad.profile.geometry import CamGeometry
from camcad.profile.summary import profile_report as report
from camcad.profile.synth import ProfileSettings, synthesize

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_peer.py"


@pytest.fixture(scope="module")
def bench():
    # the benchmarks import their shared helpers (benchmarks/timing.py) as top-level modules, as
    # camcad.report.bench.load_benchmark arranges
    import sys

    if str(BENCH.parent) not in sys.path:
        sys.path.insert(0, str(BENCH.parent))
    spec = importlib.util.spec_from_file_location("bench_peer", BENCH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def angles_away_from_breakpoints(count: int, margin_deg: float) -> np.ndarray:
    """θ (rad) on a uniform grid, minus those within ``margin_deg`` of 0, 90, 180, 270, 360°, where the
    jerk jumps and a difference stencil straddling it would lose its order."""
    theta = np.linspace(0.0, 2.0 * math.pi, count, endpoint=False)
    edges = np.radians([0.0, 90.0, 180.0, 270.0, 360.0])
    return theta[np.min(np.abs(theta[:, None] - edges[None, :]), axis=1) > math.radians(margin_deg)]


def test_closed_form_matches_camcad_geometry(bench):
    # Two independent routes to the same curves: the polar closed form in bench_peer (P = r e_r,
    # n = (r e_r + v e_t)/sqrt(r^2 + v^2), X = P - Rr n, phi = atan(v/r)) and camcad's vector form
    # (rotation of the fixed-frame track, normal from T = q' - J q). Measured: < 1e-13 mm, < 1e-15 rad.
    law, follower = bench.camcad_case()
    geometry = CamGeometry(law, follower)
    theta = np.union1d(np.linspace(0.0, 2.0 * math.pi, 20_001), np.radians([90.0, 180.0, 270.0]))
    assert np.max(np.abs(geometry.pitch(theta).points - bench.exact_pitch(theta))) < 1e-9
    assert np.max(np.abs(geometry.profile(theta).points - bench.exact_profile(theta))) < 1e-9
    assert np.max(np.abs(geometry.pressure_angle(theta) - bench.exact_pressure_angle(theta))) < 1e-9
    s = law.kinematics(theta)
    s_ref, v_ref, a_ref = bench.cycloidal_drdr(theta)
    assert np.max(np.abs(s.s - s_ref)) < 1e-9 and np.max(np.abs(s.v - v_ref)) < 1e-9
    assert np.max(np.abs(s.a - a_ref)) < 1e-9


def test_closed_form_profile_is_the_roller_envelope(bench):
    # Without camcad: the profile point X is at distance Rr from the roller centre P, along the
    # pitch curve's normal, i.e. (X - P) . P' = 0 with P' from a fourth-order central difference
    # of generated pitch points (truncation ~ h^4 |P^(5)|/30 ~ 1e-11 mm/rad at h = 1e-3 rad).
    # The pressure angle is the angle between that normal and the radius (the follower's axis
    # seen from the cam): for the polar curve r(theta), tan(phi) = (dr/dtheta)/r, again by differences.
    theta = angles_away_from_breakpoints(1441, 1.0)
    step = 1e-3
    pitch, profile = bench.exact_pitch(theta), bench.exact_profile(theta)
    assert np.max(np.abs(np.hypot(*(profile - pitch).T) - 10.0)) < 1e-12

    def derivative(fn):
        return (fn(theta - 2 * step) - 8 * fn(theta - step) + 8 * fn(theta + step) - fn(theta + 2 * step)) / (12 * step)

    tangent = derivative(bench.exact_pitch)
    cosine = np.einsum("ij,ij->i", profile - pitch, tangent) / (10.0 * np.hypot(*tangent.T))
    assert np.max(np.abs(cosine)) < 1e-9
    # the roller is outside the cam: X lies nearer the centre than P
    assert np.all(np.hypot(*profile.T) < np.hypot(*pitch.T))
    radius_rate = derivative(lambda t: np.hypot(*bench.exact_pitch(t).T))
    phi = np.arctan(radius_rate / np.hypot(*pitch.T))
    assert np.max(np.abs(phi - bench.exact_pressure_angle(theta))) < 1e-9


def test_peak_pressure_angle_against_camcad_and_a_dense_grid(bench):
    # Brent's root of a r - v^2 = 0 (bench) against (1) camcad's grid + bounded-Brent extremum in
    # synthesize, and (2) the largest phi on a 2,000,001-point grid, which lies below the true peak
    # by at most phi''/2 (dtheta/2)^2, a few 1e-12 rad (measured 3.5e-12). The cycloidal return is
    # the rise mirrored in time, so the smallest phi is minus the largest. Measured: camcad within
    # 2e-14 deg.
    peaks = bench.pressure_angle_extremes()
    law, follower = bench.camcad_case()
    figures = report(synthesize(law, follower, ProfileSettings(plots=False, design=False)))
    assert figures["pressure_angle_max_deg"] == pytest.approx(math.degrees(peaks["max"]), abs=1e-9)
    assert figures["pressure_angle_min_deg"] == pytest.approx(math.degrees(peaks["min"]), abs=1e-9)
    assert figures["pressure_angle_max_at_deg"] == pytest.approx(math.degrees(peaks["max_at"]), abs=1e-4)
    grid = np.linspace(0.0, 2.0 * math.pi, 2_000_001)
    phi = bench.exact_pressure_angle(grid)
    assert 0.0 <= peaks["max"] - phi.max() < 1e-11
    assert 0.0 <= phi.min() - peaks["min"] < 1e-11
    assert peaks["min"] == pytest.approx(-peaks["max"], abs=1e-14)
    assert math.degrees(peaks["max"]) == pytest.approx(23.233, abs=1e-3)  # atan(v/r) near mid-rise: v ~ 25.5, r ~ 59.5


def test_curve_distance_on_an_ellipse(bench):
    # Points put at a known distance d along the normal of an ellipse (a = 50, b = 30 mm): while
    # |d| is below the smallest radius of curvature b^2/a = 18 mm, their distance to the curve is |d|.
    a, b = 50.0, 30.0

    def ellipse(t):
        return np.stack((a * np.cos(t), b * np.sin(t)), axis=-1)

    rng = np.random.default_rng(7)
    t0 = rng.uniform(0.0, 2.0 * math.pi, 2000)
    d = rng.uniform(-5.0, 5.0, 2000)
    normal = np.stack((b * np.cos(t0), a * np.sin(t0)), axis=-1)
    normal /= np.hypot(*normal.T)[:, None]
    points = ellipse(t0) + d[:, None] * normal
    assert np.max(np.abs(bench.curve_distance(points, ellipse) - np.abs(d))) < 1e-10
    assert np.max(bench.curve_distance(ellipse(t0), ellipse)) < 1e-12


def test_polyline_deviation_of_a_regular_polygon(bench):
    # A regular N-gon inscribed in a circle of radius R: the Hausdorff distance is the sagitta
    # R (1 - cos(pi/N)) at each chord's midpoint. Rotated by an odd angle so no vertex sits on a sample.
    radius, count = 50.0, 500

    def circle(t):
        return radius * np.stack((np.cos(t), np.sin(t)), axis=-1)

    vertices = circle(0.123 + np.arange(count) * 2.0 * math.pi / count)
    expected = radius * (1.0 - math.cos(math.pi / count))
    assert bench.polyline_deviation(vertices, circle) == pytest.approx(expected, rel=1e-9)


def test_peer_points_turned_into_camcad_frame(bench):
    # The peer (mechanism 1.1.10, cams.py: Motion.get_profile) returns (base + s) e^{i theta_r} with
    # theta_r = -theta for a ccw cam, follower on +x. Turned by +90 deg they must be camcad's points
    # of the same theta: with base = Rb + Rr, the exact pitch curve (follower on +y).
    theta = np.linspace(0.0, 2.0 * math.pi, 997, endpoint=False)
    s, _, _ = bench.cycloidal_drdr(theta)
    peer = (40.0 + 10.0 + s) * np.exp(-1j * theta)
    turned = bench.peer_to_camcad_frame(peer.real, peer.imag)
    assert np.max(np.abs(turned - bench.exact_pitch(theta))) < 1e-12


def test_run_without_the_peer_measures_camcad_and_says_why(bench, monkeypatch):
    # No network here: the peer's environment is refused, and run() must still measure camcad against
    # the closed form and add one row saying the peer is unavailable. Figures checked against the
    # closed form: written points on the exact profile (round-off), the chord polyline within the
    # chord tolerance, the peak pressure angle, and the base radius for the exact peak angle
    # (40 mm by construction, up to min_base_radius's round-up of 2 xtol = 2e-9 mm).
    def refuse(*_args, **_kwargs):
        raise bench.PeerUnavailable("no network in this test")

    monkeypatch.setattr(bench, "peer_python", refuse)
    rows = bench.run(quick=True)
    keys = {"kernel", "method", "setting", "time_s", "error", "error_unit", "status"}
    assert all(keys <= row.keys() for row in rows)
    missing = [row for row in rows if row["status"] != "ok"]
    assert [row["status"] for row in missing] == ["peer unavailable: no network in this test"]
    assert missing[0]["time_s"] is None and missing[0]["error"] is None
    measured = [row for row in rows if row["status"] == "ok"]
    assert measured and all(row["time_s"] > 0.0 for row in measured)
    for row in measured:
        if row["kernel"] == bench.K_PROFILE:
            tol = float(row["setting"].split()[1])
            assert row["error"] < 1e-9 and row["pitch_mm"] < 1e-9
            assert 0.5 * tol < row["polyline_mm"] <= 1.01 * tol
        elif row["kernel"] == bench.K_PRESSURE:
            assert row["error"] < 1e-9
        else:
            assert row["error"] < 1e-8
    assert bench.summary(rows) == ["peer unavailable: no network in this test"]
