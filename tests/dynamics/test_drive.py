"""Camshaft torque and power, flywheel and motor (``camcad drive``, ``camcad.dynamics.torque``/``flywheel``).

References used here (never a re-run of the code under test):
- the rigid follower's power balance T = (m ω² s'' + k s + F0 + Q) s' (SI, s' = ds/dθ; Norton, Cam Design and
  Manufacturing Handbook 2009, ch. 10), with the cycloidal and harmonic laws written out in this file;
- the guide's friction through the force triangle with docs/INTERFACE.md's pressure angle φ = atan((v − e)/(d + s));
- a flat face's sliding speed ω (Rb + s) (the contact sits at x = v on the face at height Rb + s);
- a roller's rim speed by the instantaneous-centre argument, ω |L_p − Rr|, L_p the pitch point's speed in the
  cam's frame by finite differences of the rotated closed-form point;
- the speed fluctuation of a shaft with inertia J and a constant driving torque by scipy's solve_ivp in time;
- the working member of a linkage designed with law_of = "output": its torque J ω² y'' y' with y the batten's
  harmonic law written out here;
- peaks by a dense grid refined with scipy's bounded Brent search, means and RMS by scipy's quad.
"""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq, minimize_scalar

from camcad.errors import CamcadError
from camcad.scene.commands.drive import DriveRequest, run_drive

CONTACT = """
[contact]
cam_modulus = 2.1e5
cam_poisson = 0.3
follower_modulus = 2.1e5
follower_poisson = 0.3
width = 12.0
allowable_stress = 3000.0
"""

RISE, DWELL_END, RETURN_END = 100.0, 160.0, 260.0
LIFT = 25.0


def scene(tmp_path, body: str, name: str = "cam") -> object:
    path = tmp_path / f"{name}.toml"
    path.write_text(body)
    return path


def roller_scene(tmp_path, *, rpm="300", mass=1.5, spring=8.0, preload=150.0, extra="", follower_extra="",
                 contact_extra="", shape="cycloidal", kind="roller"):
    radius = "" if kind == "flat" else "roller_radius = 12.0\n"
    return scene(tmp_path, f"""
[machine]
rpm = {rpm}
[law]
standard = "{shape}"
phases = "0:{RISE:g}:rise,{RISE:g}:{DWELL_END:g}:dwell,{DWELL_END:g}:{RETURN_END:g}:return,{RETURN_END:g}:360:dwell"
lift = {LIFT}
[follower]
type = "{kind}"
base_radius = 50.0
{radius}pressure_angle_limit_rise = 60.0
pressure_angle_limit_return = 60.0
{follower_extra}
{CONTACT}
mass = {mass}
spring_rate = {spring}
preload = {preload}
{contact_extra}
{extra}
""")


def cycloid(theta):
    """s, s', s'' (mm, mm/rad, mm/rad²) of the test law, written out (Norton eq. 3.8)."""
    theta = np.mod(np.asarray(theta, dtype=float), 2 * math.pi)
    s, v, a = (np.zeros_like(theta) for _ in range(3))
    for start, end, sign in ((0.0, RISE, 1.0), (DWELL_END, RETURN_END, -1.0)):
        beta = math.radians(end - start)
        u = (theta - math.radians(start)) / beta
        inside = (u >= 0) & (u <= 1)
        base = 0.0 if sign > 0 else LIFT
        s = np.where(inside, base + sign * LIFT * (u - np.sin(2 * np.pi * u) / (2 * np.pi)), s)
        v = np.where(inside, sign * LIFT / beta * (1 - np.cos(2 * np.pi * u)), v)
        a = np.where(inside, sign * 2 * np.pi * LIFT / beta**2 * np.sin(2 * np.pi * u), a)
    s = np.where((theta > math.radians(RISE)) & (theta < math.radians(DWELL_END)), LIFT, s)
    return s, v, a


def reference_figures(torque, breakpoints_deg):
    """max |T| (dense grid, then Brent) and the RMS and mean (quad between the breakpoints)."""
    grid = np.linspace(0, 2 * math.pi, 72001)
    values = np.abs(torque(grid))
    k = int(np.argmax(values))
    found = minimize_scalar(lambda t: -abs(float(torque(np.array([t]))[0])),
                            bounds=(grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]), method="bounded",
                            options={"xatol": 1e-12})
    peak = max(values[k], -found.fun)
    edges = np.radians(np.array(sorted(set([0.0, 360.0] + list(breakpoints_deg)))))
    square = sum(quad(lambda t: float(torque(np.array([t]))[0]) ** 2, lo, hi, epsabs=0, epsrel=1e-13, limit=200)[0]
                 for lo, hi in itertools.pairwise(edges))
    mean = sum(quad(lambda t: float(torque(np.array([t]))[0]), lo, hi, epsabs=1e-14, epsrel=1e-13, limit=200)[0]
               for lo, hi in itertools.pairwise(edges))
    return peak, math.sqrt(square / (2 * math.pi)), mean / (2 * math.pi)


# --------------------------------------------------------------------------------------------
# Must show: the rigid translating roller against T = (m ω² s'' + k s + F0) s'
# --------------------------------------------------------------------------------------------

@pytest.mark.reference("closed form", "T = (m w^2 s'' + k s + F0) s' (SI), Norton 2009 ch. 10; cycloid written out")
def test_rigid_roller_peak_and_rms_equal_the_closed_form_at_several_speeds(tmp_path):
    m, k, f0 = 1.5, 8.0, 150.0
    path = roller_scene(tmp_path, rpm='"120:720:300"', mass=m, spring=k, preload=f0)
    report = run_drive(DriveRequest(path))
    rows = {r["rpm"]: r for r in report.body["speeds"]}
    assert sorted(rows) == [120.0, 420.0, 720.0]
    for rpm, row in rows.items():
        omega = 2 * math.pi * rpm / 60

        def torque(theta, omega=omega):
            s, v, a = cycloid(theta)
            # SI: s, s', s'' in m, k in N/m
            return (m * omega**2 * a * 1e-3 + k * 1e3 * s * 1e-3 + f0) * v * 1e-3

        peak, rms, mean = reference_figures(torque, [RISE, DWELL_END, RETURN_END])
        assert row["torque_peak_Nm"] == pytest.approx(peak, rel=1e-6)
        assert row["torque_rms_Nm"] == pytest.approx(rms, rel=1e-6)
        assert abs(row["torque_mean_Nm"] - mean) <= 1e-9 * peak      # a conservative follower: mean 0
        assert row["power_peak_W"] == pytest.approx(peak * omega, rel=1e-6)
        assert row["power_mean_W"] == pytest.approx(row["torque_mean_Nm"] * omega, abs=1e-9 * peak * omega)


@pytest.mark.reference("property", "P = T omega at every row of torque.csv; the first columns named by "
                                   "docs/INTERFACE.md")
def test_torque_csv_power_is_torque_times_omega(tmp_path, cli):
    path = roller_scene(tmp_path, rpm="450")
    out = tmp_path / "out"
    result = cli("drive", path, "-o", out, "--json")
    assert result.code == 0, result.err
    payload = result.json()
    assert {"torque_peak_Nm", "torque_rms_Nm", "torque_mean_Nm", "power_peak_W", "power_mean_W"} <= set(
        payload["drive"])
    lines = (out / "torque.csv").read_text().splitlines()
    names = lines[0].split(",")                  # the header first: no comment lines
    assert names[:3] == ["theta_deg", "torque_Nm", "power_W"]
    data = np.array([[float(x) for x in line.split(",")] for line in lines[1:]])
    omega = 2 * math.pi * 450 / 60
    assert np.allclose(data[:, 2], data[:, 1] * omega, rtol=1e-10, atol=1e-9)
    assert data[0, 0] == 0.0 and data[-1, 0] == 360.0
    # the shares add up to the total
    shares = [names.index(f"{key}_Nm") for key in ("inertia", "spring", "load", "linkage", "friction")]
    assert np.allclose(data[:, shares].sum(axis=1), data[:, 1], atol=1e-9)
    assert (out / "torque.png").is_file() and (out / "drive.json").is_file()


@pytest.mark.reference("closed form", "mean torque = work of the process force per turn / 2 pi = F h / (2 pi)")
def test_process_force_over_the_rise_does_work_f_times_lift(tmp_path):
    force = 400.0
    path = roller_scene(tmp_path, extra=f"[load]\nforce = {force}\nphase = \"rise\"\n")
    report = run_drive(DriveRequest(path))
    work = force * LIFT * 1e-3
    assert report.body["torque_mean_Nm"] == pytest.approx(work / (2 * math.pi), rel=1e-10)
    assert report.body["power_mean_W"] == pytest.approx(work / (2 * math.pi) * 2 * math.pi * 300 / 60, rel=1e-10)


@pytest.mark.reference("closed form", "a table load equal to the constant force gives the same torque everywhere")
def test_load_table_step_equals_constant_force_over_its_range(tmp_path):
    constant = run_drive(DriveRequest(roller_scene(
        tmp_path, extra="[load]\nforce = 250.0\nrange_deg = [20.0, 200.0]\n")))
    (tmp_path / "b").mkdir()
    table = run_drive(DriveRequest(roller_scene(
        tmp_path / "b", extra='[load]\ntable = [[0.0, 0.0], [20.0, 250.0], [200.0, 0.0]]\ninterpolation = "step"\n')))
    theta = np.radians(np.arange(0.0, 360.0, 0.37))
    a = constant.result.shaft_torque(theta, 300.0)
    b = table.result.shaft_torque(theta, 300.0)
    assert np.allclose(a, b, rtol=0, atol=1e-12)
    assert table.body["torque_mean_Nm"] == pytest.approx(constant.body["torque_mean_Nm"], rel=1e-9)


@pytest.mark.reference("second method", "force triangle with guide friction and docs/INTERFACE.md's "
                                        "phi = atan((v - e)/(d + s))")
def test_guide_friction_of_an_offset_roller_follows_the_force_triangle(tmp_path):
    e, mu, m, k, f0, rpm = 8.0, 0.15, 1.5, 8.0, 150.0, 300.0
    path = roller_scene(tmp_path, rpm=str(rpm), follower_extra=f"offset = {e}", contact_extra=f"friction = {mu}")
    report = run_drive(DriveRequest(path))
    omega = 2 * math.pi * rpm / 60
    d = math.sqrt((50.0 + 12.0) ** 2 - e**2)

    def torque(theta):
        s, v, a = cycloid(theta)
        force = m * a * omega**2 / 1000 + k * s + f0
        phi = np.arctan((v - e) / (d + s))
        sense = np.sign(v) * np.sign(force)
        normal = force / (np.cos(phi) - mu * np.abs(np.sin(phi)) * sense)
        return normal * np.cos(phi) * v / 1000

    theta = np.radians(np.arange(0.0, 360.0, 0.1))
    assert np.allclose(report.result.shaft_torque(theta, rpm), torque(theta), rtol=1e-10, atol=1e-12)
    _peak, rms, mean = reference_figures(torque, [RISE, DWELL_END, RETURN_END])
    assert report.body["torque_rms_Nm"] == pytest.approx(rms, rel=1e-6)
    assert mean > 0 and report.body["torque_mean_Nm"] == pytest.approx(mean, rel=1e-6)   # friction dissipates


@pytest.mark.reference("closed form", "flat face: sliding speed w (Rb + s), T = (F s' + mu_c F (Rb + s))/1000")
def test_pair_friction_of_a_flat_face_slides_at_rb_plus_s(tmp_path):
    mu, m, k, f0, rpm = 0.08, 1.5, 8.0, 150.0, 250.0
    path = roller_scene(tmp_path, rpm=str(rpm), kind="flat", extra=f"[load]\npair_friction = {mu}\n")
    report = run_drive(DriveRequest(path))
    omega = 2 * math.pi * rpm / 60

    def torque(theta):
        s, v, a = cycloid(theta)
        force = m * a * omega**2 / 1000 + k * s + f0
        return (force * v + mu * np.abs(force) * (50.0 + s)) / 1000

    theta = np.radians(np.arange(0.0, 360.0, 0.1))
    assert np.allclose(report.result.shaft_torque(theta, rpm), torque(theta), rtol=1e-10, atol=1e-12)


@pytest.mark.reference("second method", "instantaneous centre: rim speed w |L_p - Rr|, L_p by finite differences")
@pytest.mark.parametrize("cw", [False, True])
def test_roller_rim_speed_by_the_instantaneous_centre(cw):
    import camcad
    from camcad.dynamics.torque import contact_slip
    from camcad.profile.geometry import CamGeometry

    law = camcad.compose([("rise", 100), ("dwell", 60), ("return", 100), ("dwell", 100)], 25.0)
    rb, rr, e = 30.0, 12.0, 6.0        # a small cam: concave flanks on the rise
    cam = CamGeometry(law, camcad.Follower("roller", base_radius=rb, roller_radius=rr, offset=e, cw=cw))
    theta = np.radians(np.arange(0.5, 360.0, 1.3))
    sigma = -1.0 if cw else 1.0
    d = math.sqrt((rb + rr) ** 2 - e**2)

    def pitch_in_cam_frame(t):
        s = law.kinematics(np.atleast_1d(t)).s
        x, y = np.full_like(s, e), d + s
        c, si = np.cos(-sigma * t), np.sin(-sigma * t)
        return np.stack((c * x - si * y, si * x + c * y), axis=-1)

    h = 1e-6
    speed = np.linalg.norm((pitch_in_cam_frame(theta + h) - pitch_in_cam_frame(theta - h)) / (2 * h), axis=-1)
    assert np.allclose(contact_slip(cam, theta), np.abs(speed - rr), rtol=1e-7, atol=1e-7)


@pytest.mark.reference("closed form", "oscillating roller, mass at the roller: T = (m a w^2 + k s + F0) s', s = L psi")
def test_oscillating_follower_torque_by_the_swing(tmp_path):
    m, k, f0, rpm, arm, swing = 0.6, 3.0, 80.0, 300.0, 110.0, 20.0
    path = roller_scene(tmp_path, rpm=str(rpm), mass=m, spring=k, preload=f0, kind="oscillating",
                        follower_extra=f"pivot = 150.0\narm = {arm}\nswing = {swing}")
    report = run_drive(DriveRequest(path))
    omega = 2 * math.pi * rpm / 60
    scale = math.radians(swing) / LIFT        # psi per mm of the law

    def torque(theta):
        s, v, a = (x * scale * arm for x in cycloid(theta))      # the roller's arc, mm
        return (m * a * omega**2 / 1000 + k * s + f0) * v / 1000

    theta = np.radians(np.arange(0.0, 360.0, 0.1))
    assert np.allclose(report.result.shaft_torque(theta, rpm), torque(theta), rtol=1e-9, atol=1e-12)


@pytest.mark.reference("closed form", "batten designed with law_of = output: working member's share J w^2 y'' y'")
def test_linkage_working_member_torque_is_its_own_power(tmp_path):
    from conftest import SAMPLES

    report = run_drive(DriveRequest(SAMPLES / "scenes" / "batten_linkage.toml", rpm="400"))
    (item,) = report.result.mechanisms
    theta = np.radians(np.arange(0.0, 360.0, 0.25))
    share = item.drive.components(theta, 400.0).linkage
    # the batten's law: harmonic rise 100..164 deg and return 164..228 deg of 24.12 deg (the scene's [law])
    lift = math.radians(24.12)
    y1, y2 = np.zeros_like(theta), np.zeros_like(theta)
    for start, end, sign in ((100.0, 164.0, 1.0), (164.0, 228.0, -1.0)):
        beta = math.radians(end - start)
        u = (theta - math.radians(start)) / beta
        inside = (u >= 0) & (u < 1)
        y1 = np.where(inside, sign * lift / 2 * math.pi / beta * np.sin(math.pi * u), y1)
        y2 = np.where(inside, sign * lift / 2 * (math.pi / beta) ** 2 * np.cos(math.pi * u), y2)
    omega = 2 * math.pi * 400 / 60
    expected = 1.2 * omega**2 * y2 * y1
    assert np.max(np.abs(share - expected)) <= 1e-7 * np.max(np.abs(expected))


@pytest.mark.reference("closed form", "form closure (groove), no spring: T = m w^2 s'' s' of both signs")
def test_groove_cam_torque_changes_sign_with_the_inertia_force(tmp_path):
    m, rpm = 2.0, 500.0
    path = roller_scene(tmp_path, rpm=str(rpm), mass=m, spring=0.0, preload=0.0, contact_extra='closure = "form"',
                        follower_extra="groove = true")
    report = run_drive(DriveRequest(path))
    omega = 2 * math.pi * rpm / 60
    theta = np.radians(np.arange(0.0, 360.0, 0.1))
    _s, v, a = cycloid(theta)
    expected = m * omega**2 * a * v * 1e-6
    got = report.result.shaft_torque(theta, rpm)
    assert np.allclose(got, expected, rtol=1e-10, atol=1e-12)
    assert got.min() < 0 < got.max()
    assert not any("spring holds" in c for c in report.verdict.to_dict()["checks"])   # form-closed: no such check


@pytest.mark.reference("property", "friction only dissipates: the friction share is >= 0 at every angle, both flanks")
def test_pair_friction_on_both_flanks_of_a_groove_only_dissipates(tmp_path):
    path = roller_scene(tmp_path, rpm="500", mass=2.0, spring=0.0, preload=0.0, contact_extra='closure = "form"\n'
                        "friction = 0.1", follower_extra="groove = true", extra="[load]\npair_friction = 0.01\n")
    report = run_drive(DriveRequest(path))
    theta = np.radians(np.arange(0.0, 360.0, 0.1))
    (parts,) = report.result.components(theta, 500.0).values()
    assert np.all(parts.friction >= -1e-12)
    assert np.any(parts.axial_force < 0) and np.any(parts.axial_force > 0)
    assert report.body["torque_mean_Nm"] > 0


@pytest.mark.reference("closed form", "gravity: a vertical follower's weight m g acts like a preload")
def test_gravity_of_a_vertical_follower_is_a_preload(tmp_path):
    with_weight = run_drive(DriveRequest(roller_scene(tmp_path, preload=150.0, extra="[load]\ngravity_up_deg = 90\n")))
    (tmp_path / "b").mkdir()
    as_preload = run_drive(DriveRequest(roller_scene(tmp_path / "b", preload=150.0 + 1.5 * 9.80665)))
    theta = np.radians(np.arange(0.0, 360.0, 0.5))
    assert np.allclose(with_weight.result.shaft_torque(theta, 300.0), as_preload.result.shaft_torque(theta, 300.0),
                       rtol=1e-12, atol=1e-12)


# --------------------------------------------------------------------------------------------
# The flywheel and the motor
# --------------------------------------------------------------------------------------------

@pytest.mark.reference("second method", "J dw/dt = T_m - T(theta) integrated in time by solve_ivp")
def test_speed_fluctuation_with_a_flywheel_matches_time_integration(tmp_path):
    m, k, f0, rpm, inertia = 1.5, 8.0, 150.0, 300.0, 0.4
    path = roller_scene(tmp_path, rpm=str(rpm), mass=m, spring=k, preload=f0,
                        extra=f'[drive]\nmotor = "induction"\nflywheel_inertia = {inertia}\ndelta = "1/100"\n')
    report = run_drive(DriveRequest(path))
    omega_n = 2 * math.pi * rpm / 60

    def load(theta):       # the torque at the nominal speed (the energy method's premise)
        s, v, a = cycloid(theta)
        return (m * omega_n**2 * a * 1e-3 + k * s + f0) * v * 1e-3

    def rhs(t, y):
        return [y[1], -float(load(np.array([y[0]]))[0]) / inertia]   # T_m = 0: a conservative follower

    def one_turn(start_speed):
        hit = lambda t, y: y[0] - 2 * math.pi  # noqa: E731
        hit.terminal = True
        result = solve_ivp(rhs, (0.0, 10.0), [0.0, start_speed], rtol=1e-12, atol=1e-12, max_step=2e-4,
                           events=hit)
        return result.y[1]

    def mean_speed_error(start_speed):
        speeds = one_turn(start_speed)
        return 0.5 * (speeds.max() + speeds.min()) - omega_n

    start = brentq(mean_speed_error, 0.9 * omega_n, 1.1 * omega_n, xtol=1e-12)
    speeds = one_turn(start)
    delta = (speeds.max() - speeds.min()) / omega_n
    assert 0.003 < delta < 0.03
    assert report.body["flywheel"]["speed_fluctuation"] == pytest.approx(delta, rel=1e-5)
    # the inertia for delta = 1/100 holds it to 1/100 (delta scales as 1/J)
    need = report.body["flywheel"]["inertia_required_kg_m2"]
    assert need == pytest.approx(inertia * report.body["flywheel"]["speed_fluctuation"] / 0.01, rel=1e-9)
    check = report.verdict.to_dict()["checks"]["speed fluctuation (energy method)"]
    assert check["passed"] == (report.body["flywheel"]["speed_fluctuation"] <= 0.01)


@pytest.mark.reference("closed form", "motor torque T/(i eta) driving, T eta/i driven; RMS of T/i for eta = 1")
def test_servo_motor_through_a_gearbox(tmp_path):
    path = roller_scene(tmp_path, rpm="300", extra="[drive]\ngear_ratio = 5.0\nmotor_rated_torque = 1.0\n"
                                                   "motor_peak_torque = 4.0\nmotor_max_speed = 3000.0\n")
    report = run_drive(DriveRequest(path))
    motor = report.body["motor"]
    assert motor["speed_rpm"] == pytest.approx(1500.0)
    assert motor["torque_rms_Nm"] == pytest.approx(report.body["torque_rms_Nm"] / 5.0, rel=1e-9)
    assert motor["torque_peak_Nm"] == pytest.approx(report.body["torque_peak_Nm"] / 5.0, rel=1e-9)
    checks = report.verdict.to_dict()["checks"]
    assert checks["motor torque, RMS against rated"]["margin"] == pytest.approx(1.0 - motor["torque_rms_Nm"])
    assert checks["motor speed"]["passed"]


@pytest.mark.reference("property", "a motor over its rated RMS torque fails the check: exit 1, FAILED printed")
def test_servo_motor_over_its_rating_fails_with_exit_1(tmp_path, cli):
    path = roller_scene(tmp_path, rpm="600", extra="[drive]\nmotor_rated_torque = 0.5\nmotor_peak_torque = 0.6\n")
    result = cli("drive", path, "-o", tmp_path / "out", "--no-plots")
    assert result.code == 1
    assert "motor torque, RMS against rated" in result.out and "FAILED" in result.out


@pytest.mark.reference("closed form", "energy method: J = dE/(delta w^2) for T = T_m + A sin(theta)")
def test_energy_swing_of_a_sine_torque():
    from camcad.dynamics.flywheel import energy_fluctuation

    found = energy_fluctuation(lambda t: 3.0 + 5.0 * np.sin(2 * t + 0.3), [], 400.0)
    assert found.delta_energy == pytest.approx(5.0, rel=1e-12)       # 2 A / 2 for sin(2 theta)
    assert found.inertia_for(0.02) == pytest.approx(5.0 / (0.02 * (2 * math.pi * 400 / 60) ** 2), rel=1e-12)


# --------------------------------------------------------------------------------------------
# The loom group (docs/drive.md) and the elastic torque
# --------------------------------------------------------------------------------------------

@pytest.mark.reference("property", "the shaft's torque is the sum of its mechanisms'; loads doing no net work: mean 0")
def test_loom_group_shaft_is_the_sum_of_its_mechanisms(tmp_path):
    from conftest import SAMPLES

    report = run_drive(DriveRequest(SAMPLES / "scenes" / "loom_group1.toml", rpm="420", delta=1 / 30))
    theta = np.radians(np.arange(0.0, 360.0, 0.5))
    parts = report.result.components(theta, 420.0)
    assert set(parts) == {"weft_returner", "shuttle_lift", "shuttle_spring_opener", "returner_spring_opener"}
    assert np.allclose(sum(p.total for p in parts.values()), report.result.shaft_torque(theta, 420.0), atol=1e-12)
    assert report.body["torque_mean_Nm"] == 0.0
    # the retimed laws (the cyclogram's phase angles) drive the shaft: the shuttle lift rises 55..91 deg
    lift = next(m for m in report.result.mechanisms if m.name == "shuttle_lift")
    rise = next(p for p in lift.law.phases if p.kind == "rise")
    assert math.degrees(rise.start) == pytest.approx(55.0) and math.degrees(rise.end) == pytest.approx(91.0)
    flywheel = report.body["flywheel"]
    omega = 2 * math.pi * 420 / 60
    assert flywheel["inertia_required_kg_m2"] == pytest.approx(report.body["energy_swing_J"] * 30 / omega**2, rel=1e-9)


@pytest.mark.reference("second method", "SDOF follower integrated by solve_ivp to its periodic state: m y'' s'")
def test_elastic_torque_of_a_single_dof_follower(tmp_path):
    fn, zeta, m, rpm = 60.0, 0.05, 1.5, 400.0
    path = roller_scene(tmp_path, rpm=str(rpm), mass=m, spring=0.0, preload=0.0, contact_extra='closure = "form"',
                        extra=f"[dynamics]\nnatural_frequency_hz = {fn}\ndamping_ratio = {zeta}\nmass_kg = {m}\n")
    report = run_drive(DriveRequest(path))
    omega, wn = 2 * math.pi * rpm / 60, 2 * math.pi * fn

    def rhs(t, z):       # m y'' + b (y' - s') + c (y - s) = 0, in time
        s, v, _ = cycloid(np.array([omega * t]))
        return [z[1], -2 * zeta * wn * (z[1] - v[0] * omega * 1e-3) - wn**2 * (z[0] - s[0] * 1e-3)]

    period = 2 * math.pi / omega
    state = [0.0, 0.0]
    for _ in range(6):        # damping ratio 0.05 at 60 Hz: the start-up dies within a few turns
        state = solve_ivp(rhs, (0, period), state, rtol=1e-10, atol=1e-13, method="DOP853").y[:, -1]
    times = np.linspace(0, period, 4001)[:-1]
    sol = solve_ivp(rhs, (0, period), state, rtol=1e-10, atol=1e-13, method="DOP853", t_eval=times)
    accel = np.array([rhs(t, z)[1] for t, z in zip(sol.t, sol.y.T)])
    v = cycloid(omega * times)[1] * 1e-3
    torque = m * accel * v               # the elastic link's force m y'' through the cam's s'
    elastic = report.body["elastic"]
    assert elastic["torque_peak_Nm"] == pytest.approx(np.max(np.abs(torque)), rel=2e-3)
    assert elastic["torque_rms_Nm"] == pytest.approx(np.sqrt(np.mean(torque**2)), rel=1e-3)
    assert elastic["torque_mean_Nm"] > 0       # the chain's damping dissipates


# --------------------------------------------------------------------------------------------
# Bad input: one line, exit 2
# --------------------------------------------------------------------------------------------

@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize(("extra", "words"), [
    ("[drive]\ndelta = 2.0\n", "delta"),
    ('[drive]\ndelta = "1/0"\n', "delta"),
    ("[drive]\ngear_ratio = -3\n", "gear_ratio"),
    ("[drive]\nmotor = \"diesel\"\n", "motor"),
    ("[drive]\nmotor_rated_torque = 5\nmotor_peak_torque = 2\n", "peak"),
    ("[load]\nforce = 10\nphase = \"rise_3\"\n", "rise_3"),
    ("[load]\ntable = [[90, 1], [10, 2]]\n", "increase"),
    ("[load]\nforce = 10\ntable = [[0, 1]]\n", "both"),
    ("[load]\nphase = \"rise\"\n", "force"),
    ("[load]\nfoo = 1\n", "foo"),
])
def test_bad_sections_are_one_line_exit_2(tmp_path, cli, extra, words):
    path = roller_scene(tmp_path, extra=extra)
    result = cli("drive", path, "-o", tmp_path / "out", "--no-plots")
    assert result.code == 2, result.out + result.err
    lines = result.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("camcad: error:") and words in lines[0]
    assert not (tmp_path / "out" / "drive.json").exists()


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_no_speed_no_contact_and_bad_delta_option(tmp_path, cli):
    path = roller_scene(tmp_path)
    assert cli("drive", path, "--delta", "1.5", "-o", tmp_path / "o1").code == 2
    assert cli("drive", path, "--delta", "x/3", "-o", tmp_path / "o2").code == 2
    text = path.read_text().replace("rpm = 300\n", "")
    no_speed = tmp_path / "nospeed.toml"
    no_speed.write_text(text)
    result = cli("drive", no_speed, "-o", tmp_path / "o3")
    assert result.code == 2 and "no speed" in result.err
    bare = tmp_path / "bare.toml"
    bare.write_text(text.split("[contact]")[0].replace("[machine]", "[machine]\nrpm = 100"))
    result = cli("drive", bare, "-o", tmp_path / "o4")
    assert result.code == 2 and "[contact]" in result.err
    with pytest.raises(CamcadError):
        run_drive(DriveRequest(tmp_path / "missing.toml"))


@pytest.mark.reference("property", "drive --json: one object, its assumptions (friction = 0) in the notes")
def test_drive_json_is_one_object_and_says_what_it_assumed(tmp_path, cli):
    path = roller_scene(tmp_path)
    result = cli("drive", path, "-o", tmp_path / "out", "--json", "--no-plots")
    payload = json.loads(result.out)
    mech = payload["drive"]["mechanisms"]["cam"]
    assert any("friction = 0" in note for note in mech["notes"])
    assert payload["drive"]["motor"]["regime"] == "servo"
    assert payload["outputs"][-1].endswith("drive.json")


# --------------------------------------------------------------------------------------------
# docs/drive.md stays true
# --------------------------------------------------------------------------------------------

def _doc() -> str:
    from conftest import ROOT

    return (ROOT / "docs" / "drive.md").read_text()


def _same(line: str) -> str:
    return " ".join(line.split())


@pytest.mark.reference("property", "docs/drive.md quotes what camcad prints (the documentation kept true; the "
                                   "figures' references are the tests above)")
def test_drive_doc_loom_excerpt_is_what_camcad_prints(tmp_path, cli):
    from conftest import SAMPLES

    block = _doc().split("prints (excerpt)")[1].split("```")[1]
    result = cli("drive", SAMPLES / "scenes" / "loom_group1.toml", "--delta", "1/30", "-o", tmp_path / "o",
                 "--no-plots")
    assert result.code == 0, result.err
    printed = {_same(line) for line in result.out.splitlines()}
    for line in block.strip().splitlines():
        assert _same(line) in printed, line


@pytest.mark.reference("property", "docs/drive.md's figures are what camcad finds (the documentation kept true); the "
                                   "polydyne residual after design < 1e-12")
def test_drive_doc_press_feed_and_polydyne_figures_are_what_camcad_finds(tmp_path, cli):
    from conftest import ROOT

    doc = _doc()
    result = cli("drive", ROOT / "docs" / "examples" / "press_feed.toml", "-o", tmp_path / "a", "--no-plots")
    assert result.code == 0, result.err
    for figure in ("20.86", "8.377", "2.164", "0.8685", "2.196", "2.469"):
        assert figure in doc and figure in result.out, figure
    result = cli("profile", ROOT / "docs" / "examples" / "polydyne.toml", "-o", tmp_path / "b", "--no-plots", "--json")
    rows = {row["rpm"]: row for row in result.json()["polydyne"]["per_speed"]}
    table = [line.split("|")[1:4] for line in doc.split("| rpm | residual before")[1].split("\n\n")[0].splitlines()[2:]]
    assert len(table) == len(rows) == 5
    for rpm, before, after in table:
        row = rows[float(rpm)]
        assert float(f"{row['before_mm']:.4g}") == float(before)
        if "e" in after:
            assert row["after_mm"] < 1e-12
        else:
            assert float(f"{row['after_mm']:.4g}") == float(after)
