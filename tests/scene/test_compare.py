"""``camcad compare``: two laws on one mechanism, side by side (issue 26, item 4).

References: a law against itself (every ratio exactly 1), a law against the same law at half the lift (every
kinematic figure and, the elastic model being linear, every dynamic one in the ratio 2), and the displacement
deviation of two closed-form laws sampled independently here.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import camcad
from camcad.io.law_write import write_law_dxf

PHASES = [("dwell", 60), ("rise", 100), ("dwell", 40), ("return", 100), ("dwell", 60)]

SCENE = """name = "cmp"
[machine]
rpm = [300.0, 450.0]
[law]
standard = "cycloidal"
phases = "0:60:dwell,60:160:rise,160:200:dwell,200:300:return,300:360:dwell"
lift = 20.0
[follower]
type = "roller"
base_radius = 50.0
roller_radius = 12.0
[dynamics]
natural_frequency_hz = 90.0
damping_ratio = 0.05
mass_kg = 2.0
start_pulse_ratio = 0.3
method = "frequency"
samples = 4096
[contact]
cam_modulus = 2.1e5
cam_poisson = 0.3
follower_modulus = 2.1e5
follower_poisson = 0.3
width = 15.0
mass = 2.0
allowable_stress = 900.0
spring_rate = 5.0
preload = 200.0
"""


def _law_file(tmp_path, name, lift=20.0, shape="cycloidal"):
    law = camcad.compose(PHASES, lift, shape)
    theta = np.radians(np.linspace(0.0, 360.0, 7201))
    return write_law_dxf(tmp_path / name, np.degrees(theta), law.kinematics(theta).a)


@pytest.fixture
def scene(tmp_path):
    path = tmp_path / "cmp.toml"
    path.write_text(SCENE)
    return path


@pytest.mark.reference("property", "a law compared with itself: A/B = 1 for every figure")
def test_a_law_compared_with_itself_gives_ratios_of_one(cli, tmp_path, scene):
    law = _law_file(tmp_path, "law.dxf")
    run = cli("compare", law, law, "--scene", scene, "--json", "--no-plots", "-o", tmp_path / "out")
    assert run.code == 0, run.err
    data = run.json()["compare"]
    ratios = [f["A/B"] for f in data["figures"] if f["A/B"] is not None]
    ratios += [h["A/B"] for h in data["harmonics"] if h["A/B"] is not None]
    assert len(ratios) > 40
    assert max(abs(r - 1.0) for r in ratios) <= 1e-12
    names = {f["name"] for f in data["figures"]}
    for wanted in ("peak_accel_rigid", "peak_accel_elastic", "start_accel_rigid", "start_accel_elastic",
                   "start_load", "start_load_pulse", "residual_vibration", "sigma_max", "safety_factor",
                   "displacement_deviation"):
        assert wanted in names, wanted
    assert data["A"]["name"] == "law" and data["figures"][0]["applies"]
    assert next(f for f in data["figures"] if f["name"] == "displacement_deviation")["A"] == 0.0


@pytest.mark.reference("closed form", "cycloidal law: a_max = 2 pi h / beta^2, v_max = 2h/beta; the law at half "
                                      "the lift halves every kinematic and (linear model) every dynamic figure")
def test_half_the_lift_halves_the_figures(tmp_path, scene):
    from camcad.scene.commands.compare import CompareRequest, run_compare

    full, half = _law_file(tmp_path, "full.dxf"), _law_file(tmp_path, "half.dxf", lift=10.0)
    report = run_compare(CompareRequest(full, half, scene))
    comparison = report.comparison
    beta = math.radians(100.0)
    omega = 2 * math.pi * 450.0 / 60.0
    peak = comparison.find("peak_accel_rigid", rpm=450.0)
    assert peak.a == pytest.approx(2 * math.pi * 20.0 / beta**2 * omega**2 * 1e-3, rel=1e-4)
    assert comparison.find("peak_velocity", rpm=450.0).a == pytest.approx(2 * 20.0 / beta * omega * 1e-3, rel=1e-6)
    for name in ("stroke", "peak_accel_rigid", "peak_velocity", "start_accel_rigid", "peak_accel_elastic",
                 "start_accel_elastic", "start_load", "start_load_pulse", "start_deformation", "residual_vibration",
                 "dynamic_error_max"):
        for figure in (f for f in comparison.figures if f.name == name):
            assert figure.ratio == pytest.approx(2.0, rel=1e-9), (name, figure.applies)
    # the contact force is not linear in the law (spring preload): the smaller law has the lower stress
    assert comparison.find("sigma_max", rpm=450.0).ratio > 1.0


@pytest.mark.reference("second method", "the two closed-form laws sampled independently on 20001 points")
def test_the_displacement_deviation_of_two_closed_form_laws(tmp_path, scene):
    from camcad.scene.commands.compare import CompareRequest, run_compare

    a, b = _law_file(tmp_path, "cyc.dxf"), _law_file(tmp_path, "harm.dxf", shape="poly345")
    report = run_compare(CompareRequest(a, b, None, rpm="300"))
    theta = np.radians(np.linspace(0.0, 360.0, 20001))
    s_a = camcad.compose(PHASES, 20.0, "cycloidal").kinematics(theta).s
    s_b = camcad.compose(PHASES, 20.0, "poly345").kinematics(theta).s
    expected = float(np.max(np.abs(s_b - s_a)))
    found = report.comparison.find("displacement_deviation").a
    assert found == pytest.approx(expected, rel=1e-4)
    assert any("no scene" in n for n in report.notes)


@pytest.mark.reference("published", "the batten study's figures (docs/references.md), each with its status: "
                                    "published, reproduced, depends, not reproduced")
def test_published_figures_get_their_status(cli, tmp_path, scene):
    _law_file(tmp_path, "law.dxf"), _law_file(tmp_path, "half.dxf", lift=10.0)
    text = scene.read_text() + """
[compare]
a = "law.dxf"
b = "half.dxf"
[[compare.published]]
name = "stroke"
value = 20.0
unit = "mm"
figure = "stroke"
input = true
[[compare.published]]
name = "accelerations lower"
value = 2.0
figure = "peak_accel_rigid"
law = "A/B"
rpm = 450.0
[[compare.published]]
name = "start load lower"
value = 3.45
figure = "start_load_pulse"
law = "A/B"
depends_on = "the pulse ratio and the natural frequency"
[[compare.published]]
name = "deformations lower (experiment)"
value = [1.5, 1.8]
why_not = "a measured strain, not modelled"
"""
    scene.write_text(text)
    run = cli("compare", "--scene", scene, "--json", "-o", tmp_path / "out")
    assert run.code == 0, run.err
    published = {p["name"]: p for p in run.json()["compare"]["published"]}
    assert published["stroke"]["status"] == "published" and published["stroke"]["camcad"] == pytest.approx(20.0)
    assert published["accelerations lower"]["status"] == "reproduced"
    assert published["start load lower"]["status"] == "depends on chosen inputs"
    assert published["deformations lower (experiment)"]["status"] == "not reproduced"
    assert (tmp_path / "out" / "compare_contact.png").exists() and (tmp_path / "out" / "compare.csv").exists()
    text_run = cli("compare", "--scene", scene, "--no-plots", "-o", tmp_path / "out2")
    assert "published figures beside camcad's" in text_run.out and "depends on chosen inputs" in text_run.out


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("args,expected", [
    (("{law}", "{law}"), "no speed given"),
    (("{law}", "--rpm", "300"), "no law B given"),
    (("{law}", "{law}", "--rpm", "300", "--mechanism", "x"), "--mechanism needs a scene"),
])
def test_what_compare_cannot_do_says_why(cli, tmp_path, args, expected):
    law = _law_file(tmp_path, "law.dxf")
    result = cli("compare", *[a.format(law=law) for a in args], "--no-plots", "-o", tmp_path / "out")
    assert result.code == 2 and expected in result.err and len(result.err.strip().splitlines()) == 1
