"""The lever on its stop as a beam, the published impact figures beside camcad's, and the rebound's speed study.

Independent references: a finite-element beam written here (Euler–Bernoulli, Hermite cubic elements: exact
for point loads at nodes) for the lever's stiffness free and on three supports; the closed form c + k_c for a
stop at the reduced mass; scipy's solve_ivp on the one-mass model against the closed-form triangular pulse
(and a hand-worked impulse for the half-sine); the published figures of Podgorny et al. (2018) for the
shuttle lift (which of them the sample is calibrated to is asserted, the others validate).
"""

from __future__ import annotations

import math
from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest

from camcad.dynamics.impact import LeverBeam, StopModel, first_rebound, impact_at, lever_stiffness, overhang_influence
from camcad.dynamics.rebound import (
    PublishedFigure,
    PublishedImpact,
    implied_preload,
    pulse_force,
    pulse_rebound,
    rebound_study,
)
from camcad.errors import CamcadError
from camcad.scene.file import read_scene
from camcad.scene.laws import mechanism_law
from camcad.scene.sections.published import parse_published
from camcad.scene.sections.stops import parse_stops

ROOT = Path(__file__).resolve().parents[2]
SHUTTLE = ROOT / "samples" / "scenes" / "shuttle_lift.toml"
#: Podgorny et al. (2018): first rebound (mm) against speed (rpm), computed; force (N); frequencies (Hz)
PUBLISHED_REBOUND = {177.0: 0.022, 280.0: 0.07, 320.0: 0.078, 370.0: 0.092, 420.0: 0.105}


def fe_stiffness(e_mpa, j_mm4, nodes_mm, supports_mm, load_at_mm, springs=None):
    """N/m at ``load_at_mm`` of a beam on rigid (or spring) supports: Hermite cubic elements between the nodes."""
    nodes = sorted(set(nodes_mm))
    index = {x: k for k, x in enumerate(nodes)}
    n = 2 * len(nodes)
    stiff = np.zeros((n, n))
    ej = e_mpa * j_mm4
    for x0, x1 in pairwise(nodes):
        h = x1 - x0
        k = ej / h**3 * np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                                  [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]])
        dofs = [2 * index[x0], 2 * index[x0] + 1, 2 * index[x1], 2 * index[x1] + 1]
        stiff[np.ix_(dofs, dofs)] += k
    for x, k_s in (springs or {}).items():
        stiff[2 * index[x], 2 * index[x]] += k_s * 1e-3    # N/m -> N/mm
    fixed = [2 * index[x] for x in supports_mm]
    free = [d for d in range(n) if d not in fixed]
    load = np.zeros(n)
    load[2 * index[load_at_mm]] = 1.0
    w = np.linalg.solve(stiff[np.ix_(free, free)], load[free])
    deflection = w[free.index(2 * index[load_at_mm])]     # mm per N
    return 1e3 / deflection


@pytest.mark.reference("second method", "Euler-Bernoulli finite elements (Hermite cubics) written here")
@pytest.mark.parametrize("a, b, arm", [(50.0, 100.0, 101.03), (50.0, 100.0, 130.0), (40.0, 60.0, 55.0),
                                       (80.0, 30.0, 95.0), (50.0, 100.0, 170.0)])
def test_lever_beam_stiffness_free_and_on_the_stop_equals_finite_elements(a, b, arm):
    e, j = 2.1e5, 62.94
    beam = LeverBeam(e, j, a, b, arm)
    nodes = [0.0, a, a + b, arm]
    free = fe_stiffness(e, j, nodes, [0.0, a], a + b)
    on = fe_stiffness(e, j, nodes, [0.0, a, arm], a + b)
    assert beam.free_stiffness_n_per_m == pytest.approx(free, rel=1e-9)
    assert beam.stop_stiffness_n_per_m == pytest.approx(on, rel=1e-9)
    # an elastic stop: the contact stiffness in series at the support
    soft = LeverBeam(e, j, a, b, arm, contact_stiffness_n_per_m=2e5)
    assert soft.stop_stiffness_n_per_m == pytest.approx(fe_stiffness(e, j, nodes, [0.0, a], a + b, {arm: 2e5}),
                                                        rel=1e-9)
    # Maxwell: the influence coefficients are symmetric
    assert overhang_influence(a, 20.0, 70.0) == overhang_influence(a, 70.0, 20.0)


@pytest.mark.reference("closed form", "stop at the reduced mass: c_on = c + k_c (the stop in parallel)")
def test_stop_at_the_mass_is_the_parallel_model():
    c = lever_stiffness(2.1e5, 62.94, 50.0, 100.0)
    beam = LeverBeam(2.1e5, 62.94, 50.0, 100.0, 150.0, contact_stiffness_n_per_m=150300.0)
    assert beam.stop_stiffness_n_per_m == pytest.approx(c + 150300.0, rel=1e-12)
    assert math.isinf(LeverBeam(2.1e5, 62.94, 50.0, 100.0, 150.0).stop_stiffness_n_per_m)


def shuttle():
    scene = read_scene(SHUTTLE)
    mech = scene.mechanisms[0]
    stops = mech.sections["stops"]
    return mechanism_law(scene, mech).law, parse_stops(stops, "shuttle"), parse_published(stops["published"], "pub")


@pytest.mark.reference("published", "Podgorny et al. 2018: 297/768 Hz computed (calibrated), 268/700 Hz measured")
def test_sample_frequencies_from_the_beam_and_their_roles():
    _, stop, published = shuttle()
    assert stop.beam is not None and stop.beam.stop_arm_mm == pytest.approx(101.03)
    # CALIBRATED: J and the stop's place were chosen for the source's computed 297 and 768 Hz
    assert stop.f_free_hz == pytest.approx(297.0, rel=1e-4)
    assert stop.f_stop_hz == pytest.approx(768.0, rel=1e-4)
    roles = {f.key: f.calibrated for f in published.figures}
    assert roles["f_free_hz"] and roles["f_stop_hz"] and roles["rebound_mm@280"] and roles["force_N@280"]
    # the measured frequencies are not fitted: camcad is 10.8 % and 9.7 % above them, as the source's model is
    assert not roles["f_free_hz (measured)"] and not roles["f_stop_hz (measured)"]
    assert stop.f_free_hz / 268.0 - 1 == pytest.approx(0.108, abs=0.001)
    assert stop.f_stop_hz / 700.0 - 1 == pytest.approx(0.097, abs=0.001)


@pytest.mark.reference("second method", "solve_ivp (DOP853) on the one-mass model vs the closed-form triangle")
@pytest.mark.parametrize("zeta, v0", [(0.0, 0.2), (0.05, 0.228), (0.3, 0.5)])
def test_numerical_pulse_response_equals_the_closed_form_triangle(zeta, v0):
    stop = StopModel(mass_kg=0.0076, stiffness_n_per_m=2.6e4, stop_stiffness_n_per_m=1.5e5, restitution=5 / 9,
                     damping_ratio=zeta, preload_mm=0.25)
    assert pulse_rebound(stop, v0) == pytest.approx(first_rebound(stop, v0)[0] * 1e3, rel=1e-6)


@pytest.mark.reference("closed form", "the impulse of each pulse shape: integral of Q dt = S")
@pytest.mark.parametrize("shape", ["triangle", "half_sine"])
def test_pulse_shapes_carry_the_impulse(shape):
    t = np.linspace(0.0, 2e-3, 200_001)
    force = pulse_force(shape, t, 0.0027, 1.3e-3)
    assert np.trapezoid(force, t) == pytest.approx(0.0027, rel=1e-8)
    with pytest.raises(CamcadError, match="unknown pulse shape"):
        pulse_force("square", t, 1.0, 1.0)


@pytest.mark.reference("property", "the implied preload reproduces the target rebound in the same model")
def test_implied_preload_reproduces_the_rebound():
    law, stop, _ = shuttle()
    preload = implied_preload(law, stop, 177.0, 0.022)
    assert preload is not None and 0.05 < preload < 0.15
    from dataclasses import replace

    assert impact_at(law, replace(stop, preload_mm=preload), 177.0).rebound_mm == pytest.approx(0.022, rel=1e-9)
    assert implied_preload(law, stop, 280.0, 0.07) == pytest.approx(0.25, rel=1e-3)   # the calibration
    assert implied_preload(law, stop, 177.0, 50.0) is None                          # no preload reaches it


@pytest.mark.reference("published", "Podgorny et al. 2018: rebounds 0.022/0.07/0.078/0.092/0.105 mm at 177-420 rpm")
def test_shuttle_lift_impact_report_lists_the_five_published_rebounds_with_errors(cli, tmp_path):
    done = cli("impact", SHUTTLE, "--json", "-o", tmp_path)
    payload = done.json()["impact"]
    rows = [r for r in payload["published"]["figures"] if r["quantity"] == "rebound_mm" and r["kind"] == "computed"]
    assert [r["rpm"] for r in rows] == [177.0, 280.0, 320.0, 370.0, 420.0]
    for row in rows:
        assert row["published"] == PUBLISHED_REBOUND[row["rpm"]]
        assert row["error"] == pytest.approx(row["camcad"] - row["published"], abs=1e-9)
        assert row["error_percent"] == pytest.approx(100 * row["error"] / row["published"], rel=1e-6)
        assert row["role"] == ("calibrated" if row["rpm"] == 280.0 else "validates")
    errors = {r["rpm"]: r["error_percent"] for r in rows}
    # validated: within 3 % at 320-420 rpm; the 177 rpm point is twice camcad's (the study says why)
    assert abs(errors[320.0]) < 3 and abs(errors[370.0]) < 1 and abs(errors[420.0]) < 0.1
    assert errors[177.0] == pytest.approx(101.1, abs=0.5)
    # the text lists them too, one row per figure with its error and role
    text = cli("impact", SHUTTLE, "-o", tmp_path / "text", "--no-plots").out
    for rpm in ("177", "280", "320", "370", "420"):
        assert any(line.startswith("rebound_mm") and f" {rpm} " in line for line in text.splitlines())
    assert "the outlying point needs other inputs" in text
    assert (tmp_path / "impact_published.png").stat().st_size > 0
    assert (tmp_path / "impact_analogs.png").stat().st_size > 0


@pytest.mark.reference("published", "the five published rebounds against every one-calibration variant")
def test_no_one_calibration_variant_reproduces_the_177_rpm_point():
    law, stop, published = shuttle()
    study = rebound_study(law, stop, published)
    assert study.calibration_rpm == 280.0
    k177 = study.speeds_rpm.index(177.0)
    for variant in study.variants:
        assert variant.values_mm[study.speeds_rpm.index(280.0)] == pytest.approx(0.07, rel=1e-9)   # calibrated
        assert variant.errors[k177] > 0.5, variant.name      # every one misses 177 rpm by more than 50 %
    # the published points per rpm: 177 rpm is half of the others, which agree within 2.5 %
    per = dict(zip(study.speeds_rpm, study.per_rpm_mm))
    assert per[177.0] / per[280.0] == pytest.approx(0.497, abs=0.001)
    assert max(abs(per[n] / per[280.0] - 1) for n in (320.0, 370.0, 420.0)) < 0.026
    assert study.implied_preload_mm[177.0] == pytest.approx(0.0845, abs=0.001)


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_published_and_beam_errors():
    with pytest.raises(CamcadError, match="not \\[rpm, value\\]"):
        parse_published({"rebound_mm": [[177, -1.0]]}, "w")
    with pytest.raises(CamcadError, match="calibrated names 'rebound_mm@300'"):
        parse_published({"rebound_mm": [[280, 0.07]], "calibrated": ["rebound_mm@300"]}, "w")
    base = {"youngs_modulus_MPa": 2.1e5, "second_moment_mm4": 62.94, "arm_a_mm": 50.0, "arm_b_mm": 100.0,
            "mass_kg": 0.0076, "restitution": 0.5, "damping_ratio": 0.05, "preload_mm": 0.25}
    with pytest.raises(CamcadError, match="not beyond the drive"):
        parse_stops({**base, "stop_arm_mm": 40.0}, "w")
    with pytest.raises(CamcadError, match="holds it still"):
        parse_stops({**base, "stop_arm_mm": 150.0}, "w")
    with pytest.raises(CamcadError, match="missing the stop"):
        parse_stops(base, "w")
    lever_only = {k: v for k, v in base.items() if k not in ("youngs_modulus_MPa", "second_moment_mm4", "arm_a_mm",
                                                              "arm_b_mm")}
    with pytest.raises(CamcadError, match="needs the lever as a beam"):
        parse_stops({**lever_only, "stiffness_N_per_m": 2.6e4, "stop_arm_mm": 100.0}, "w")
    # the override: the stop's stiffness alone, in parallel (the earlier model)
    parallel = parse_stops({**base, "stop_stiffness_N_per_m": 1.5e5}, "w")
    assert parallel.beam is None and parallel.stop_stiffness_n_per_m == 1.5e5
    with pytest.raises(CamcadError, match="two or more published rebounds"):
        law, stop, _ = shuttle()
        rebound_study(law, stop, PublishedImpact((PublishedFigure("rebound_mm", 0.07, 280.0),)))
