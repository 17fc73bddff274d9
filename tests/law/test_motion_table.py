"""Laws from tables of the motion (issue 26, item 1): displacement, swing and radius-vector tables.

The references are closed forms written here: the cycloidal dwell–rise–dwell–return law
s = h(u − sin 2πu/2π), its peak acceleration 2πh/β², and the cam profile of a roller follower built from
it by hand (the roller centre's path turned into the cam's frame, offset by the roller radius along the
normal, sampled at whole degrees of polar angle by interpolating a 0.005° sampling of the profile).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import camcad
from camcad.errors import CamcadError
from camcad.law.motion_table import ProfileFollower

H = 20.0                  # mm
BETA = math.pi / 2        # rad: 90 deg rise and return
PEAK = 2 * math.pi * H / BETA**2


def _cycloid(u):
    u = np.clip(u, 0.0, 1.0)
    return u - np.sin(2 * np.pi * u) / (2 * np.pi)


def _cycloid_rate(u):
    return np.where((u > 0) & (u < 1), 1 - np.cos(2 * np.pi * u), 0.0)


def law_s(phi, lift=H):
    """Dwell 0–90, rise 90–180, dwell 180–270, return 270–360 (cycloidal), s in the lift's unit."""
    d = np.degrees(phi) % 360.0
    return lift * (_cycloid((d - 90) / 90) - _cycloid((d - 270) / 90))


def law_v(phi, lift=H):
    d = np.degrees(phi) % 360.0
    return lift / BETA * (_cycloid_rate((d - 90) / 90) - _cycloid_rate((d - 270) / 90))


def _profile_table(centre, centre_rate, rr, noise, seed, sigma=1.0):
    """r at whole degrees of polar angle of the profile touched by a roller whose centre (fixed frame) is
    ``centre(phi)`` with derivative ``centre_rate(phi)``; the cam turns by sigma*phi."""
    phi = np.radians(np.arange(0.0, 360.0, 0.005))
    q, dq = centre(phi), centre_rate(phi)
    turned = dq - sigma * np.column_stack((-q[:, 1], q[:, 0]))
    c, s = np.cos(-sigma * phi), np.sin(-sigma * phi)

    def rotate(v):
        return np.column_stack((c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]))

    pitch, tangent = rotate(q), rotate(turned)
    normal = np.column_stack((tangent[:, 1], -tangent[:, 0])) / np.hypot(tangent[:, 0], tangent[:, 1])[:, None]
    normal = np.where(np.sum(normal * pitch, axis=1)[:, None] > 0, normal, -normal)
    profile = pitch - rr * normal
    alpha = np.degrees(np.unwrap(np.arctan2(profile[:, 1], profile[:, 0])))
    radius = np.hypot(profile[:, 0], profile[:, 1])
    order = np.argsort(alpha)
    alpha, radius = alpha[order], radius[order]
    grid = np.arange(0.0, 360.0, 1.0)
    r = np.interp((grid - alpha[0]) % 360.0 + alpha[0], alpha, radius)
    return grid, r + np.random.default_rng(seed).uniform(-noise, noise, len(grid))


def translating_table(rb, rr, e, noise=1e-3, seed=0):
    d = math.sqrt((rb + rr) ** 2 - e**2)
    return _profile_table(lambda p: np.column_stack((np.full_like(p, e), d + law_s(p))),
                          lambda p: np.column_stack((np.zeros_like(p), law_v(p))), rr, noise, seed)


def oscillating_table(rb, rr, pivot, arm, swing, noise=1e-3, seed=0):
    gamma0 = math.acos((pivot**2 + arm**2 - (rb + rr) ** 2) / (2 * pivot * arm))

    def centre(p):
        g = gamma0 + law_s(p, swing)
        return np.column_stack((pivot - arm * np.cos(g), arm * np.sin(g)))

    def rate(p):
        g = gamma0 + law_s(p, swing)
        w = law_v(p, swing)
        return np.column_stack((arm * w * np.sin(g), arm * w * np.cos(g)))

    return _profile_table(centre, rate, rr, noise, seed)


def _write(path, header, theta, values):
    path.write_text(header + "\n" + "".join(f"{t:.10g},{v:.10f}\n" for t, v in zip(theta, values)))
    return path


def _errors(loaded, lift=H):
    fine = np.radians(np.linspace(0.0, 360.0, 7201))
    kin = loaded.law.kinematics(fine)
    return float(np.max(np.abs(kin.s - law_s(fine, lift)))), float(np.max(np.abs(kin.a))) / (2 * math.pi * lift
                                                                                             / BETA**2) - 1


@pytest.mark.reference("closed form", "cycloidal law s = h(u - sin 2pi u / 2pi), a_max = 2 pi h / beta^2; "
                                      "the roller's profile built here from the law and the follower geometry")
@pytest.mark.parametrize("offset", [0.0, 12.0])
def test_a_radius_table_of_a_known_cam_gives_its_law(tmp_path, offset):
    theta, r = translating_table(40.0, 10.0, offset, seed=int(offset))
    path = _write(tmp_path / "cam.csv", "theta_deg,r_mm", theta, r)
    loaded = camcad.load_law(path, follower=ProfileFollower("translating", 10.0, offset))
    ds, da = _errors(loaded)
    assert ds <= 2e-3 and abs(da) <= 0.02, (ds, da)
    assert loaded.motion.kind == "radius" and loaded.unit == "mm"
    assert camcad.check(loaded.law).balanced


@pytest.mark.reference("closed form", "cycloidal swing law; the oscillating roller's profile built here")
def test_a_radius_table_through_an_oscillating_roller_gives_the_swing(tmp_path):
    swing = 0.35
    theta, r = oscillating_table(55.0, 25.0, 160.0, 120.0, swing, seed=5)
    path = _write(tmp_path / "cam.csv", "theta_deg,r_mm", theta, r)
    loaded = camcad.load_law(path, follower=ProfileFollower("oscillating", 25.0, pivot=160.0, arm=120.0))
    ds, da = _errors(loaded, swing)
    # 2e-3 mm at the roller, i.e. 2e-3/L rad of swing
    assert ds <= 2e-3 / 120.0 and abs(da) <= 0.02, (ds, da)
    assert loaded.unit == "rad" and loaded.motion.figures["kind"] == "radius"


@pytest.mark.reference("closed form", "cycloidal law s = h(u - sin 2pi u / 2pi), a_max = 2 pi h / beta^2")
@pytest.mark.parametrize("closing,jitter", [(False, False), (True, False), (False, True)])
def test_a_displacement_table_gives_the_law(tmp_path, closing, jitter):
    rng = np.random.default_rng(11)
    theta = np.arange(0.0, 361.0 if closing else 360.0, 1.0)
    if jitter:   # unequal steps
        theta[1:-1] += rng.uniform(-0.3, 0.3, len(theta) - 2)
    s = law_s(np.radians(theta)) + rng.uniform(-1e-3, 1e-3, len(theta))
    loaded = camcad.load_law(_write(tmp_path / "s.csv", "theta_deg,s_mm", theta, s))
    ds, da = _errors(loaded)
    assert ds <= 2e-3 and abs(da) <= 0.02, (ds, da)
    kinds = [(p.kind, round(math.degrees(p.start))) for p in loaded.law.phases]
    assert kinds == [("dwell", 0), ("rise", 90), ("dwell", 180), ("return", 270)]
    figures = loaded.motion.report()
    assert figures["row_at_cycle_end"] is closing and figures["equal_steps"] is (not jitter)
    # the fit's residual is the noise: uniform on ±1e-3 has RMS 1e-3/sqrt(3)
    assert figures["smoothing"]["residual_rms_mm"] == pytest.approx(1e-3 / math.sqrt(3), rel=0.25)


@pytest.mark.reference("closed form", "cycloidal swing in deg: peak 2 pi h / beta^2 in deg/rad^2")
def test_a_swing_table_in_degrees_keeps_its_unit(tmp_path):
    theta = np.arange(0.0, 360.0, 2.0)
    psi = law_s(np.radians(theta), 24.0)
    loaded = camcad.load_law(_write(tmp_path / "psi.csv", "theta_deg,psi_deg", theta, psi))
    assert loaded.unit == "deg"
    ds, da = _errors(loaded, 24.0)
    assert ds <= 2e-3 and abs(da) <= 0.005


@pytest.mark.reference("property", "a quintic spline through noisy rows oscillates in s''; the cubic "
                                   "re-smoothing removes part of it (the batten study's observation)")
def test_the_second_smoothing_removes_the_oscillation_of_a_nearly_interpolating_quintic(tmp_path):
    theta = np.arange(0.0, 360.0, 1.0)
    s = law_s(np.radians(theta)) + np.random.default_rng(2).uniform(-1e-3, 1e-3, len(theta))
    path = _write(tmp_path / "s.csv", "theta_deg,s_mm", theta, s)
    stiff = camcad.load_law(path, smoothing=1e-5)       # a stated error far below the noise: near interpolation
    removed = stiff.motion.report()["accel_smoothing"]["oscillation_removed_percent_of_peak"]
    assert removed > 1.0
    plain = camcad.load_law(path, smoothing=1e-5, accel_smoothing="none")
    assert plain.motion.report()["accel_smoothing"] is None
    # the re-smoothed law is closer to the closed-form acceleration than the raw second derivative
    fine = np.radians(np.linspace(0.0, 360.0, 7201))
    exact = 2 * math.pi * H / BETA**2 * np.sin(2 * np.pi * np.clip((np.degrees(fine) - 90) / 90, 0, 1))
    rise = (np.degrees(fine) > 92) & (np.degrees(fine) < 178)
    err_smooth = np.sqrt(np.mean((stiff.law.kinematics(fine).a - exact)[rise] ** 2))
    err_raw = np.sqrt(np.mean((plain.law.kinematics(fine).a - exact)[rise] ** 2))
    assert err_smooth < err_raw


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("text,expected", [
    ("theta_deg,torque_Nm\n0,1\n90,2\n", "the header names the columns 'theta_deg', 'torque_Nm'"),
    ("time_s,a\n0,1\n90,2\n", "the header names the columns 'time_s', 'a'"),
    ("theta_deg,psi\n0,1\n90,2\n", "does not say its unit"),
    ("theta_deg,s_mm,r_mm\n0,1,1\n90,2,2\n", "names 2 kinds of law"),
])
def test_a_header_camcad_does_not_know_is_refused(cli, tmp_path, text, expected):
    path = tmp_path / "t.csv"
    path.write_text(text)
    result = cli("check", path)
    assert result.code == 2 and expected in result.err and len(result.err.strip().splitlines()) == 1


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_tables_that_cannot_be_a_motion_are_refused_with_one_line(tmp_path):
    theta = np.arange(0.0, 360.0, 1.0)
    s = law_s(np.radians(theta))
    cases = {
        "open.csv": ("theta_deg,s_mm", theta, s + 0.5 * (theta > 300)),        # jumps before the seam: no closure
        "gap.csv": ("theta_deg,s_mm", theta[(theta < 100) | (theta > 140)], s[(theta < 100) | (theta > 140)]),
        "moving.csv": ("theta_deg,s_mm", theta, law_s(np.radians(theta + 120.0))),   # starts mid-motion
        "radius.csv": ("theta_deg,r_mm", theta, 50.0 + s),                        # no follower given
    }
    expected = {"open.csv": "does not close", "gap.csv": "no rows between 99 and 141 deg",
                "moving.csv": "not at rest at 0 deg", "radius.csv": "needs its follower"}
    for name, (header, t, values) in cases.items():
        with pytest.raises(CamcadError) as err:
            camcad.load_law(_write(tmp_path / name, header, t, values))
        assert expected[name] in str(err.value), name
    with pytest.raises(CamcadError, match="subtract"):
        camcad.load_law(tmp_path / "moving.csv")


@pytest.mark.reference("closed form", "cycloidal law; the table given through the command line")
def test_check_takes_a_radius_table_with_its_follower(cli, tmp_path):
    theta, r = translating_table(40.0, 10.0, 0.0, seed=3)
    path = _write(tmp_path / "cam.csv", "theta_deg,r_mm", theta, r)
    result = cli("check", path, "--follower", "roller", "--rr", "10", "--json")
    assert result.code == 0, result.err
    data = result.json()
    assert data["balanced"] and data["rise"] == pytest.approx(H, abs=2e-3)
    refused = cli("check", path)
    assert refused.code == 2 and "needs its follower" in refused.err


@pytest.mark.reference("closed form", "cycloidal law from a displacement table named in a scene")
def test_a_scene_reads_a_radius_table_through_its_follower(cli, tmp_path):
    theta, r = translating_table(40.0, 10.0, 5.0, seed=4)
    _write(tmp_path / "cam.csv", "theta_deg,r_mm", theta, r)
    (tmp_path / "cam.toml").write_text('name = "cam"\n[law]\nfile = "cam.csv"\n[follower]\ntype = "roller"\n'
                                       'base_radius = 40.0\nroller_radius = 10.0\noffset = 5.0\n')
    result = cli("profile", tmp_path / "cam.toml", "--no-plots", "-o", tmp_path / "out", "--json")
    assert result.code == 0, result.err
    data = result.json()
    # the profile rebuilt from the law read off the table: its pressure-angle maximum is the closed form's
    law = camcad.compose([("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)], H)
    exact = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0, offset=5.0))
    assert data["pressure_angle_max_deg"] == pytest.approx(math.degrees(exact.pressure_angle.maximum.value),
                                                           abs=0.05)
