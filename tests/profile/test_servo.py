"""Servo (electronic cam) tables: ``camcad profile … --export servo`` (camcad.profile.servo, camcad.report.servo).

References used here (never a re-run of the code under test):
- the cycloidal rise written out: s = h (u − sin 2πu / 2π), s' = (h/β)(1 − cos 2πu), s'' = (2πh/β²) sin 2πu
  (Norton, Cam Design and Manufacturing Handbook 2009, eq. 3.8), per master degree by the chain rule;
- two readers written here from the formats' documentation, not from camcad's writers:
  * CODESYS SoftMotion (V3.5, SM3_Basic), "Read Cam Data from ASCII Table": the file is X/Y values of a cam
    (master, slave), one pair per line, and holds no other information about the cam;
  * TwinCAT 3 NC Camming (TF5050, Tc2_MC2_Camming), MC_MotionFunctionPoint: PointIndex (strictly increasing,
    without gaps, > 0), FunctionType (MC_MotionFunctionType), PointType (MC_MotionPointType; IGNORE not allowed
    first and last), RelIndexNextPoint (usually 1), MasterPos, SlavePos, SlaveVelo, SlaveAcc, SlaveJerk (LREAL);
    MOTIONFUNCTYPE_POLYNOM5_MM: a fifth-order polynomial "motion <-> motion" between two points with the
    given position, velocity and acceleration — evaluated here by its own Hermite construction.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

LIFT, RISE_DEG, SPEED = 12.0, 90.0, 250.0
PHASES = "0:90:rise,90:180:dwell,180:270:return,270:360:dwell"


def cycloid_deg(master_deg):
    """Position (mm) and its derivatives per master degree of the rise 0..90 deg, then the dwell at h."""
    beta = math.radians(RISE_DEG)
    theta = np.radians(np.asarray(master_deg, dtype=float))
    u = np.clip(theta / beta, 0.0, 1.0)
    rising = theta <= beta
    per = math.pi / 180
    s = np.where(rising, LIFT * (u - np.sin(2 * np.pi * u) / (2 * np.pi)), LIFT)
    v = np.where(rising, LIFT / beta * (1 - np.cos(2 * np.pi * u)) * per, 0.0)
    a = np.where(rising, 2 * np.pi * LIFT / beta**2 * np.sin(2 * np.pi * u) * per**2, 0.0)
    return s, v, a


def run_profile(cli, tmp_path, *extra):
    scene = tmp_path / "cam.toml"
    scene.write_text(f"""
name = "cam"
[machine]
rpm = {SPEED}
[law]
standard = "cycloidal"
phases = "{PHASES}"
lift = {LIFT}
[follower]
type = "roller"
base_radius = 40.0
roller_radius = 10.0
""")
    out = tmp_path / "out"
    result = cli("profile", scene, "-o", out, "--no-plots", "--json", "--export", "servo", *extra)
    assert result.code == 0, result.err
    return out, result.json()


def read_csv(path):
    lines = path.read_text().splitlines()
    comments = [line for line in lines if line.startswith("#")]
    body = [line for line in lines if not line.startswith("#")]
    return comments, body[0].split(","), np.array([[float(x) for x in line.split(",")] for line in body[1:]])


@pytest.mark.reference("closed form", "cycloidal rise s = h(u - sin 2 pi u / 2 pi), Norton 2009 eq. 3.8")
def test_servo_table_at_one_degree_equals_the_cycloidal_closed_form(cli, tmp_path):
    out, payload = run_profile(cli, tmp_path)
    comments, names, data = read_csv(out / "servo_table.csv")
    assert names[:4] == ["master_deg", "position_mm", "velocity_mm_per_deg", "accel_mm_per_deg2"]
    assert any("units" in line and "mm/deg^2" in line for line in comments)
    assert np.array_equal(data[:, 0], np.arange(361.0))
    rise = data[:, 0] <= 180.0           # the rise and the dwell after it
    s, v, a = cycloid_deg(data[rise, 0])
    assert np.max(np.abs(data[rise, 1] - s)) <= 1e-9 * LIFT
    assert np.max(np.abs(data[rise, 2] - v)) <= 1e-9 * LIFT
    assert np.max(np.abs(data[rise, 3] - a)) <= 1e-9 * LIFT
    # at the speed: per second = per degree x (6 n deg/s)^k
    w = 6.0 * SPEED
    assert np.allclose(data[:, 5], data[:, 2] * w, rtol=1e-10, atol=1e-12)
    assert np.allclose(data[:, 6], data[:, 3] * w**2, rtol=1e-10, atol=1e-9)
    # the slave's peaks at the speed: 2h/beta, 2 pi h/beta^2, 4 pi^2 h/beta^3 per rad (Norton 2009 sec. 3.8)
    beta, omega = math.radians(RISE_DEG), 2 * math.pi * SPEED / 60
    slave = payload["servo"]["slave"]
    assert slave["velocity_peak_mm_s"] == pytest.approx(2 * LIFT / beta * omega, rel=1e-9)
    assert slave["acceleration_peak_mm_s2"] == pytest.approx(2 * math.pi * LIFT / beta**2 * omega**2, rel=1e-9)
    assert slave["jerk_peak_mm_s3"] == pytest.approx(4 * math.pi**2 * LIFT / beta**3 * omega**3, rel=1e-9)
    assert slave["jerk_infinite"] is False


def read_codesys(path):
    """The CODESYS ASCII cam table as documented: X/Y values, one pair per line (tab or blanks between)."""
    xs, ys = [], []
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        if not line.strip():
            continue
        fields = line.split()
        assert len(fields) == 2, f"line {number}: not an X/Y pair: {line!r}"
        xs.append(float(fields[0]))
        ys.append(float(fields[1]))
    return np.array(xs), np.array(ys)


@pytest.mark.reference("closed form", "CODESYS ASCII table read back by a reader written from its documentation")
def test_codesys_ascii_table_parses_and_holds_the_law(cli, tmp_path):
    out, payload = run_profile(cli, tmp_path, "--servo-format", "codesys", "--servo-step", "0.5")
    x, y = read_codesys(out / "servo_codesys.txt")
    assert len(x) == 721 and x[0] == 0.0 and x[-1] == 360.0
    assert np.allclose(np.diff(x), 0.5, rtol=0, atol=1e-9)          # equidistant master
    s, _, _ = cycloid_deg(x[x <= 180.0])
    assert np.max(np.abs(y[x <= 180.0] - s)) <= 1e-9 * LIFT
    assert (out / "servo_table.csv").is_file()
    assert payload["servo"]["format"] == "codesys"


MOTION_FUNCTION_TYPES = {"MOTIONFUNCTYPE_NOTDEF", "MOTIONFUNCTYPE_POLYNOM1", "MOTIONFUNCTYPE_POLYNOM3",
                         "MOTIONFUNCTYPE_POLYNOM5", "MOTIONFUNCTYPE_POLYNOM5_MM", "MOTIONFUNCTYPE_POLYNOM7_MM"}
POINT_TYPES = {"MOTIONPOINTTYPE_REST", "MOTIONPOINTTYPE_VELOCITY", "MOTIONPOINTTYPE_TURN", "MOTIONPOINTTYPE_MOTION"}
FIELDS = ("PointIndex", "FunctionType", "PointType", "RelIndexNextPoint", "MasterPos", "SlavePos", "SlaveVelo",
          "SlaveAcc", "SlaveJerk")
REAL = r"[+-]?\d+\.\d+(?:E[+-]?\d+)?"        # IEC 61131-3 real literal: digits, point, digits, exponent


def read_twincat(text):
    """ARRAY[1..N] OF MC_MotionFunctionPoint := [(field := value, ...), ...] as TwinCAT documents the struct."""
    head = re.search(r"ARRAY\[1\.\.(\d+)\] OF MC_MotionFunctionPoint\s*:=\s*\[", text)
    assert head, "no ARRAY OF MC_MotionFunctionPoint initialiser"
    count = int(head.group(1))
    points = []
    for body in re.findall(r"\(([^()]*)\)", text[head.end():]):
        pairs = [part.split(":=") for part in body.split(",")]
        names = tuple(p[0].strip() for p in pairs)
        assert names == FIELDS, names
        values = {name: p[1].strip() for name, p in zip(names, pairs)}
        for key in FIELDS[4:]:
            assert re.fullmatch(REAL, values[key]), f"{key} := {values[key]} is not an IEC real literal"
        points.append(values)
    assert len(points) == count
    return points


def quintic(x0, x1, p0, p1):
    """The fifth-order polynomial with position, velocity, acceleration p0 at x0 and p1 at x1 (Hermite)."""
    h = x1 - x0
    (s0, v0, a0), (s1, v1, a1) = p0, p1
    # f(t) = s0 + v0 h t + a0 h^2 t^2/2 + c3 t^3 + c4 t^4 + c5 t^5, t in [0, 1]
    m = np.array([[1, 1, 1], [3, 4, 5], [6, 12, 20]], dtype=float)
    rhs = np.array([s1 - s0 - v0 * h - a0 * h**2 / 2, (v1 - v0 - a0 * h) * h, (a1 - a0) * h**2])
    c3, c4, c5 = np.linalg.solve(m, rhs)
    return lambda x: (s0 + v0 * h * ((x - x0) / h) + a0 * h**2 * ((x - x0) / h) ** 2 / 2 + c3 * ((x - x0) / h) ** 3
                      + c4 * ((x - x0) / h) ** 4 + c5 * ((x - x0) / h) ** 5)


@pytest.mark.reference("closed form", "TwinCAT MC_MotionFunctionPoint list read and interpolated as POLYNOM5_MM")
def test_twincat_motion_function_parses_and_interpolates_the_law(cli, tmp_path):
    out, _ = run_profile(cli, tmp_path, "--servo-format", "twincat")
    points = read_twincat((out / "servo_twincat.st").read_text())
    index = [int(p["PointIndex"]) for p in points]
    assert index == list(range(1, len(points) + 1))                      # > 0, increasing, no gaps
    assert all(p["FunctionType"] in MOTION_FUNCTION_TYPES for p in points)
    assert all(p["PointType"] in POINT_TYPES for p in points)            # IGNORE nowhere, so not first nor last
    assert all(p["RelIndexNextPoint"] == "1" for p in points)
    master = np.array([float(p["MasterPos"]) for p in points])
    state = np.array([[float(p[k]) for k in ("SlavePos", "SlaveVelo", "SlaveAcc")] for p in points])
    # at rest before the rise, a = 0 halfway up (the velocity's peak), moving and accelerating in between
    assert [points[k]["PointType"] for k in (0, 20, 45)] == ["MOTIONPOINTTYPE_REST", "MOTIONPOINTTYPE_MOTION",
                                                            "MOTIONPOINTTYPE_VELOCITY"]
    # between the points the NC interpolates a quintic with the given ends: the law between the samples
    worst = 0.0
    for k in range(180):
        curve = quintic(master[k], master[k + 1], state[k], state[k + 1])
        x = np.linspace(master[k], master[k + 1], 7)
        worst = max(worst, float(np.max(np.abs(curve(x) - cycloid_deg(x)[0]))))
    assert worst <= 1e-9 * LIFT


@pytest.mark.reference("property", "a normalised table runs 0 to 1 over the 18 deg stroke; bad options refused in one "
                                   "line")
def test_normalised_oscillating_table_and_bad_options(cli, tmp_path):
    scene = tmp_path / "osc.toml"
    scene.write_text(f"""
[law]
standard = "poly345"
phases = "{PHASES}"
lift = 10.0
[follower]
type = "oscillating"
base_radius = 40.0
roller_radius = 10.0
pivot = 120.0
arm = 80.0
swing = 18.0
pressure_angle_limit_rise = 60.0
pressure_angle_limit_return = 60.0
""")
    out = tmp_path / "o"
    result = cli("profile", scene, "-o", out, "--no-plots", "--json", "--export", "servo", "--servo-normalise",
                 "--servo-step", "2")
    assert result.code == 0, result.err
    servo = result.json()["servo"]
    assert servo["stroke"] == pytest.approx(18.0) and servo["stroke_unit"] == "deg" and "note" in servo
    _, names, data = read_csv(out / "servo_table.csv")
    assert names[1] == "position_norm" and data[0, 1] == 0.0 and np.max(data[:, 1]) == pytest.approx(1.0)
    assert len(names) == 5                      # no speed: no columns per second
    for args, words in ((("--export", "servo", "--servo-step", "7"), "divide"),
                        (("--export", "servo", "--servo-format", "siemens"), "--servo-format"),
                        (("--export", "servox"), "--export"),
                        (("--servo-step", "2"), "--export servo"),
                        (("--export", "servo", "--servo-rpm", "-5"), "--servo-rpm")):
        bad = cli("profile", scene, "-o", tmp_path / "bad", "--no-plots", *args)
        assert bad.code == 2 and words in bad.err and len(bad.err.strip().splitlines()) == 1


@pytest.mark.reference("property", "a harmonic rise from a dwell jumps in acceleration: infinite jerk at its ends")
def test_acceleration_jumps_are_reported_as_infinite_jerk():
    import camcad
    from camcad.profile.scaled_law import law_breakpoints
    from camcad.profile.servo import slave_peaks

    law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 10.0, "harmonic")
    peaks = slave_peaks(law, law_breakpoints(law), rpm=100.0)
    jump = 10.0 / 2 * (math.pi / (math.pi / 2)) ** 2 * (math.pi / 180) ** 2    # h/2 (pi/beta)^2 per deg^2
    assert [round(at, 6) for at, _ in peaks.jumps_deg] == [0.0, 90.0, 180.0, 270.0]
    assert [size for _, size in peaks.jumps_deg] == pytest.approx([jump, jump, -jump, -jump], rel=1e-9)
    assert peaks.to_dict()["jerk_infinite"] is True
