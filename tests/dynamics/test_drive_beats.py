"""The driving torque M0 in scenes and one harmonic's beats with the free vibration (issue 26, item 5)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import SAMPLES
from scipy.integrate import solve_ivp

import camcad
from camcad.dynamics.beats import harmonic_beats
from camcad.dynamics.model import ElasticFollower, rpm_to_rad_s
from camcad.dynamics.multimass import MotorCurve

LAW = camcad.compose([("dwell", 100), ("rise", 64), ("return", 64), ("dwell", 132)], 0.421, "harmonic")


@pytest.mark.reference("closed form", "linear interpolation of the table and its zero crossing")
def test_a_motor_characteristic_interpolates_and_finds_its_no_load_speed():
    motor = MotorCurve(((0.0, 900.0), (400.0, 700.0), (425.0, 0.0)))
    assert motor.nominal_rpm == pytest.approx(425.0)
    assert motor(rpm_to_rad_s(200.0)) == pytest.approx(800.0)
    assert motor(rpm_to_rad_s(430.0)) == pytest.approx(-140.0)   # beyond the table: along the last segment
    with pytest.raises(ValueError):
        MotorCurve(((0.0, 1.0),))


@pytest.mark.reference("second method", "scipy solve_ivp (DOP853, rtol 1e-11) of the same equation")
@pytest.mark.parametrize("rpm,zeta", [(400.0, 0.02), (390.0, 0.002), (250.0, 0.1)])
def test_the_harmonic_response_from_rest_is_the_ode_solution(rpm, zeta):
    follower = ElasticFollower(113.0, zeta)
    beats = harmonic_beats(LAW, follower, rpm, 17, cycles=3, samples_per_cycle=512)
    wn, big = follower.omega_n, 17 * rpm_to_rad_s(rpm)
    amplitude, phase = beats.amplitude, math.radians(beats.phase_deg)

    def rhs(t, u):
        s = amplitude * math.sin(big * t + phase)
        ds = amplitude * big * math.cos(big * t + phase)
        return [u[1], 2 * zeta * wn * (ds - u[1]) + wn**2 * (s - u[0])]

    t = np.radians(beats.theta_deg) / rpm_to_rad_s(rpm)
    solved = solve_ivp(rhs, (0.0, t[-1]), [0.0, 0.0], t_eval=t, method="DOP853", rtol=1e-11, atol=1e-15)
    assert np.max(np.abs(solved.y[0] - beats.y)) <= 1e-8 * np.max(np.abs(beats.y))
    wd = wn * math.sqrt(1 - zeta**2)
    assert beats.beat_period_s == pytest.approx(2 * math.pi / abs(big - wd), rel=1e-12)
    # the harmonic itself: A_k and phi_k of camcad spectrum
    spectrum = camcad.fourier.analyse(LAW, 17)
    assert beats.amplitude == pytest.approx(float(spectrum.amplitudes[16]), rel=1e-12)


@pytest.mark.reference("property", "a motor characteristic that falls steeply at 420 rpm holds the machine there")
def test_a_scene_drives_the_multimass_model_with_its_motor(cli, tmp_path):
    text = (SAMPLES / "scenes" / "batten.toml").read_text()
    text = text.replace('solver = "DOP853"', 'solver = "DOP853"\ndrive = "motor"\n'
                        'motor_torque = [[0.0, 20000.0], [419.0, 2000.0], [421.0, -2000.0]]\nharmonic_plot = 17')
    scene = tmp_path / "motor.toml"
    scene.write_text(text)
    run = cli("dynamics", scene, "--rpm", "420", "-o", tmp_path / "out", "--json")
    assert run.code == 0, run.err
    data = run.json()["dynamics"]
    multimass = data["multimass"]
    assert multimass["drive"] == "motor characteristic M0(n)"
    assert multimass["rpm"] == pytest.approx(420.0, abs=1.0)
    assert data["harmonic"]["k"] == 17 and (tmp_path / "out" / "harmonic_17.png").exists()


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("extra,expected", [
    ('drive = "motor"', "needs the motor's characteristic"),
    ('motor_torque = [[0.0, 1.0], [400.0, 0.0]]', 'drive is "speed"'),
    ('drive = "motor"\nmotor_torque = [[400.0, 1.0], [100.0, 0.0]]', "increase"),
])
def test_a_bad_drive_is_refused(cli, tmp_path, extra, expected):
    text = (SAMPLES / "scenes" / "batten.toml").read_text().replace('solver = "DOP853"',
                                                                     f'solver = "DOP853"\n{extra}')
    scene = tmp_path / "bad.toml"
    scene.write_text(text)
    result = cli("dynamics", scene, "--rpm", "420", "-o", tmp_path / "out", "--no-plots")
    assert result.code == 2 and expected in result.err
