"""Polydyne cams (camcad.dynamics.polydyne, ``[dynamics] polydyne_rpm``, ``camcad profile … --polydyne RPM``).

References used here (never a re-run of the code under test):
- the single-DOF follower m ÿ + b (ẏ − ṡ) + c (y − s) = 0 (camcad's elastic follower, docs/analyses.md) integrated
  by scipy's solve_ivp (DOP853) from rest at the start of the rise, the cam's motion s(θ) taken from the polydyne
  law camcad builds; the residual vibration read off the integrated motion over the dwell after the rise;
- the closed form of the undamped polydyne cam, s = y + (ω/ωn)² y'' (Stoddart 1953), with the 5-6-7-8-9
  polynomial written out here;
- the classes of the laws by hand: cycloidal and 3-4-5 have a jerk that jumps against a dwell (C²), 4-5-6-7 a
  fourth derivative that jumps (C³), 5-6-7-8-9 a fifth (C⁴).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import camcad
from camcad.dynamics.polydyne import PolydyneLaw, law_class, polydyne_law
from camcad.errors import CamcadError

LIFT, RISE_DEG, DWELL_END = 20.0, 100.0, 180.0
FN, RPM = 35.0, 300.0


def wanted_law(shape: str = "poly56789"):
    return camcad.compose([("rise", RISE_DEG), ("dwell", DWELL_END - RISE_DEG), ("return", 100.0),
                           ("dwell", 360.0 - DWELL_END - 100.0)], LIFT, shape)


def integrate_rise_and_dwell(cam, zeta: float, rpm: float):
    """The follower's motion (mm) over the rise from rest and the dwell after it, by solve_ivp in time."""
    omega, wn = 2 * math.pi * rpm / 60, 2 * math.pi * FN

    def rhs(t, z):
        k = cam.kinematics(np.array([omega * t]))
        return [z[1], -2 * zeta * wn * (z[1] - k.v[0] * omega) - wn**2 * (z[0] - k.s[0])]

    start = cam.kinematics(np.array([0.0]))
    t_rise = math.radians(RISE_DEG) / omega
    t_end = math.radians(DWELL_END) / omega
    rise = solve_ivp(rhs, (0.0, t_rise), [start.s[0], 0.0], method="DOP853", rtol=1e-12, atol=1e-13)
    times = np.linspace(t_rise, t_end, 4001)
    dwell = solve_ivp(rhs, (t_rise, t_end), rise.y[:, -1], method="DOP853", rtol=1e-12, atol=1e-13, t_eval=times)
    return times, dwell.y[0]


@pytest.mark.reference("second method", "SDOF follower integrated by solve_ivp; residual read over the dwell")
@pytest.mark.parametrize("zeta", [0.0, 0.05])
@pytest.mark.parametrize("shape", ["poly56789", "poly4567"])
def test_polydyne_residual_at_the_design_speed_is_below_1e_6_of_the_lift(zeta, shape):
    law = wanted_law(shape)
    follower = camcad.ElasticFollower(FN, zeta)
    cam, _ = polydyne_law(law, follower, RPM)
    times, y = integrate_rise_and_dwell(cam, zeta, RPM)
    omega = 2 * math.pi * RPM / 60
    # after the cam's own tail (a few lags 2 zeta w/wn), the follower should sit at the lift
    settled = times * omega >= math.radians(RISE_DEG + 10.0)
    after = float(np.max(np.abs(y[settled] - LIFT)))
    _times0, y0 = integrate_rise_and_dwell(law, zeta, RPM)          # the same law without compensation
    before = float(np.max(np.abs(y0[settled] - LIFT)))
    assert after < 1e-6 * LIFT
    assert before > 1e-3 * LIFT
    # camcad's own report of the residual agrees with the integration
    from camcad.dynamics.polydyne import residual_about

    reported_before = residual_about(law, law, follower, RPM)[0].amplitude
    assert reported_before == pytest.approx(before, rel=1e-4) if zeta == 0.0 else reported_before > before
    assert residual_about(cam, law, follower, RPM)[0].amplitude < 1e-9 * LIFT


@pytest.mark.reference("second method", "off-design speeds: the polydyne cam's residual by solve_ivp")
def test_residual_at_other_speeds_matches_the_integration():
    from camcad.dynamics.polydyne import residual_about

    law, follower = wanted_law(), camcad.ElasticFollower(FN, 0.0)
    cam, _ = polydyne_law(law, follower, RPM)
    for rpm in (270.0, 330.0):
        _times, y = integrate_rise_and_dwell(cam, 0.0, rpm)
        measured = float(np.max(np.abs(y - LIFT)))       # undamped: the free vibration's amplitude
        assert residual_about(cam, law, follower, rpm)[0].amplitude == pytest.approx(measured, rel=1e-5)
        assert measured > 1e-3 * LIFT


@pytest.mark.reference("closed form", "undamped polydyne s = y + (w/wn)^2 y'' with 5-6-7-8-9 written out")
def test_undamped_polydyne_is_y_plus_k_y_second_derivative():
    law = wanted_law()
    cam = PolydyneLaw(law, camcad.ElasticFollower(FN, 0.0), RPM)
    k = (RPM / 60.0 / FN) ** 2
    beta = math.radians(RISE_DEG)
    theta = np.linspace(0.0, beta, 301)
    u = theta / beta
    y = LIFT * (126 * u**5 - 420 * u**6 + 540 * u**7 - 315 * u**8 + 70 * u**9)
    y2 = LIFT / beta**2 * (2520 * u**3 - 12600 * u**4 + 22680 * u**5 - 17640 * u**6 + 5040 * u**7)
    assert np.allclose(cam.kinematics(theta).s, y + k * y2, rtol=0, atol=1e-12 * LIFT)


@pytest.mark.reference("closed form", "classes by hand: cycloidal C2, 4-5-6-7 C3, 5-6-7-8-9 C4")
def test_law_classes_and_the_refusal_of_a_velocity_jump():
    from camcad.dynamics.polydyne import _breakpoints

    for shape, expected in (("cycloidal", 2), ("poly345", 2), ("poly4567", 3), ("poly56789", 4)):
        law = wanted_law(shape)
        assert law_class(law, _breakpoints(law))[0] == expected, shape
    with pytest.raises(CamcadError, match="velocity would jump"):
        polydyne_law(wanted_law("cycloidal"), camcad.ElasticFollower(FN, 0.05), RPM)
    _, notes = polydyne_law(wanted_law("poly4567"), camcad.ElasticFollower(FN, 0.05), RPM)
    assert any("acceleration jumps" in note for note in notes)


def scene_text(shape="poly56789", extra=""):
    return f"""
name = "poly"
[machine]
rpm = "250:350:50"
[law]
standard = "{shape}"
phases = "0:100:rise,100:180:dwell,180:280:return,280:360:dwell"
lift = {LIFT}
[follower]
type = "roller"
base_radius = 50.0
roller_radius = 12.0
[dynamics]
natural_frequency_hz = {FN}
damping_ratio = 0.05
{extra}
"""


@pytest.mark.reference("property", "the residual after polydyne design is below 1e-6 of the lift, before it above "
                                   "1e-3; the option over the key")
def test_profile_polydyne_from_the_scene_and_the_option(cli, tmp_path):
    scene = tmp_path / "poly.toml"
    scene.write_text(scene_text(extra="polydyne_rpm = 300"))
    result = cli("profile", scene, "-o", tmp_path / "a", "--no-plots", "--json")
    assert result.code == 0, result.err
    report = result.json()
    poly = report["polydyne"]
    assert "polydyne" in report["models_run"]
    assert poly["residual_after_mm"]["rise"] < 1e-6 * LIFT < 1e-3 * LIFT < poly["residual_before_mm"]["rise"]
    assert [row["rpm"] for row in poly["per_speed"]] == [250.0, 300.0, 350.0]
    # the option overrides the key; the written law is the cam's (not the wanted law)
    scene.write_text(scene_text())
    result = cli("profile", scene, "-o", tmp_path / "b", "--no-plots", "--json", "--polydyne", "300")
    assert result.json()["polydyne"]["design_rpm"] == 300.0
    rows = np.loadtxt(tmp_path / "b" / "law.csv", delimiter=",", skiprows=1)
    at = np.argmin(np.abs(rows[:, 0] - 50.0))
    assert abs(rows[at, 1] - 10.0) > 1e-3        # the cam (y + K y'' + ...) is not the wanted law (10 mm at 50 deg)


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_polydyne_bad_input_is_one_line_exit_2(cli, tmp_path):
    scene = tmp_path / "poly.toml"
    for text, words in ((scene_text("cycloidal", "polydyne_rpm = 300"), "velocity would jump"),
                        (scene_text(extra="polydyne_rpm = -3"), "polydyne_rpm"),
                        (scene_text(extra='polydyne_rpm = 300\nstiffness_variation = [[0, 1.0], [90, 1.2]]'),
                         "constant stiffness")):
        scene.write_text(text)
        result = cli("profile", scene, "-o", tmp_path / "out", "--no-plots")
        assert result.code == 2 and words in result.err and len(result.err.strip().splitlines()) == 1
    law_only = tmp_path / "law.csv"
    law_only.write_text("0,0\n90,1\n180,-1\n270,0\n")
    result = cli("profile", law_only, "--rb", "40", "--rr", "10", "--polydyne", "300", "-o", tmp_path / "o2")
    assert result.code == 2 and "elastic follower" in result.err
