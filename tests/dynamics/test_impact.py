"""Stop impact: lever stiffness, impulse and restitution, the Duhamel closed form, rebound against speed
and phase angle — against closed forms, numerical integration and the source's published figures."""

from __future__ import annotations

import math
import tomllib
from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from camcad.dynamics import impact
from camcad.dynamics.impact import StopModel
from camcad.errors import CamcadError
from camcad.law.standard import compose
from camcad.scene.sections import stops as scene_stops

SAMPLES = Path(__file__).resolve().parents[2] / "samples"
SHUTTLE = SAMPLES / "scenes" / "shuttle_lift.toml"
K_STEEL = 5.0 / 9.0


def shuttle_law(rise_deg: float = 35.0, lift: float = 11.12):
    return compose([("dwell", 100), ("rise", rise_deg), ("dwell", 180 - rise_deg), ("return", 35), ("dwell", 45)],
                   lift, "cycloidal")


def shuttle_stop() -> StopModel:
    scene = tomllib.loads(SHUTTLE.read_text())
    return scene_stops.parse_stops(scene["stops"], "shuttle_lift.toml [stops]")


# ------------------------------------------------------------------------------------ formulas

@pytest.mark.reference("second method", "Maxwell-Mohr unit-load integral of the overhanging beam's moments")
def test_lever_stiffness_equals_the_unit_load_integral():
    # Independent route (Maxwell–Mohr): beam on supports a apart, overhang b, load F at the tip.
    # Moment in the overhang M = F x (x from the tip), in the span M = F b s/a (s from the far support);
    # tip deflection δ = ∫ M m dx / EJ with the unit-load moment m = M/F.
    e_mpa, j_mm4, a, b = 2.1e5, 62.94, 50.0, 100.0
    overhang, _ = quad(lambda x: x * x, 0.0, b)
    span, _ = quad(lambda s: (b * s / a) ** 2, 0.0, a)
    compliance_mm_per_n = (overhang + span) / (e_mpa * j_mm4)
    assert impact.lever_stiffness(e_mpa, j_mm4, a, b) == pytest.approx(1e3 / compliance_mm_per_n, rel=1e-12)


@pytest.mark.reference("published", "Podgorny et al. 2018, Obrabotka Metallov 20(1) 44-54: 297 Hz without the stop, "
                                    "768 Hz on it (computed values)")
def test_sample_lever_has_the_published_frequencies():
    stop = shuttle_stop()
    # the source: 297 Hz computed without the stop, 768 Hz on the stop (Podgorny et al. 2018)
    assert stop.f_free_hz == pytest.approx(297.0, abs=0.05)
    assert stop.f_stop_hz == pytest.approx(768.0, abs=0.1)
    assert stop.pulse_s == pytest.approx(1.0 / (2.0 * stop.f_stop_hz), rel=1e-15)
    assert stop.mass_kg == pytest.approx(1.708e-4 / 0.150**2, rel=1e-12)  # J_A / l²


@pytest.mark.reference("closed form", "a triangle rising to F over tau and falling over tau carries F tau = S = J_A "
                                      "w0 (1 + k)/l")
def test_impulse_of_the_triangular_pulse_is_s():
    # The triangle rises to F over τ and falls over τ: ∫Q dt = F τ = S.
    stop = shuttle_stop()
    v0 = 0.3
    s = impact.impact_impulse(stop.mass_kg, v0, K_STEEL)
    force = impact.impact_force(s, stop.pulse_s)
    area, _ = quad(lambda t: float(impact.triangular_pulse(t, force, stop.pulse_s)), 0.0, 2 * stop.pulse_s,
                   points=[stop.pulse_s])
    assert area == pytest.approx(s, rel=1e-12)
    # S = J_A ω0 (1 + k)/l, the source's form, with ω0 = v0/l
    j_a, length = 1.708e-4, 0.150
    assert s == pytest.approx(j_a * (v0 / length) * (1 + K_STEEL) / length, rel=1e-12)


@pytest.mark.reference("second method", "a free mass struck by the pulse integrated by solve_ivp leaves at -k v0")
def test_restitution_of_the_contact_model():
    # The contact model: a free mass meeting the stop at v0 receives the pulse −Q(t) of impulse S = m v0 (1+k).
    # Its velocity after the pulse must be −k v0 (integrated numerically, independent of the closed form).
    stop = shuttle_stop()
    v0 = 0.25
    force = impact.impact_force(impact.impact_impulse(stop.mass_kg, v0, K_STEEL), stop.pulse_s)
    tau = stop.pulse_s

    def rhs(t, y):
        return [y[1], -float(impact.triangular_pulse(t, force, tau)) / stop.mass_kg]

    sol = solve_ivp(rhs, (0, 2 * tau), [0.0, v0], method="DOP853", rtol=1e-13, atol=1e-16, first_step=tau / 100)
    assert sol.y[1, -1] == pytest.approx(-K_STEEL * v0, rel=1e-10)


# ------------------------------------------------------------------------------------ Duhamel closed form

@pytest.mark.reference("second method", "solve_ivp with restarts at the pulse's kinks")
@pytest.mark.parametrize("zeta, q0, v0", [(0.0, 0.0, 0.3), (0.05, 0.0, 0.3), (0.2, 1e-4, -0.1), (0.6, 0.0, 0.0)])
def test_triangular_pulse_closed_form_matches_solve_ivp(zeta, q0, v0):
    omega, mass, force, tau = 2 * math.pi * 768.0, 0.0076, -4.2, 1 / (2 * 768.0)
    t = np.linspace(0.0, 6 * tau, 601)
    q, qd = impact.triangular_pulse_response(t, omega=omega, damping_ratio=zeta, mass=mass, peak_force=force,
                                             rise_time=tau, q0=q0, v0=v0)

    def rhs(time, y):
        load = float(impact.triangular_pulse(time, force, tau))
        return [y[1], load / mass - 2 * zeta * omega * y[1] - omega**2 * y[0]]

    # march with restarts at the pulse's kinks (0, τ, 2τ), dense output per piece
    edges = [0.0, tau, 2 * tau, t[-1]]
    pieces, y = [], np.array([q0, v0])
    for lo, hi in pairwise(edges):
        sol = solve_ivp(rhs, (lo, hi), y, method="DOP853", rtol=1e-13, atol=1e-18, dense_output=True)
        pieces.append(sol.sol)
        y = sol.y[:, -1]
    index = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, 2)
    marched = np.array([pieces[i](time) for i, time in zip(index, t)])
    q_num, qd_num = marched[:, 0], marched[:, 1]
    scale = np.max(np.abs(q_num))
    assert np.max(np.abs(q - q_num)) < 1e-8 * scale
    assert np.max(np.abs(qd - qd_num)) < 1e-8 * np.max(np.abs(qd_num))


@pytest.mark.reference("property", "momentum: m (q'(2 tau) - v0) = the impulses of the pulse, damper and spring")
def test_momentum_balance_of_the_closed_form():
    # m (q̇(2τ) − v0) = ∫₀^{2τ} (Q − 2nm q̇ − m ω² q) dt: the impulses of the pulse, damper and spring.
    omega, mass, tau, zeta, v0 = 2 * math.pi * 768.0, 0.0076, 1 / (2 * 768.0), 0.05, 0.3
    force = -impact.impact_force(impact.impact_impulse(mass, v0, K_STEEL), tau)

    def state(time):
        q, qd = impact.triangular_pulse_response(np.array([time]), omega=omega, damping_ratio=zeta, mass=mass,
                                                 peak_force=force, rise_time=tau, v0=v0)
        return float(q[0]), float(qd[0])

    def net_force(time):
        q, qd = state(time)
        return float(impact.triangular_pulse(time, force, tau)) - 2 * zeta * omega * mass * qd - mass * omega**2 * q

    total, _ = quad(net_force, 0.0, 2 * tau, points=[tau], epsabs=0, epsrel=1e-12, limit=200)
    assert mass * (state(2 * tau)[1] - v0) == pytest.approx(total, rel=1e-10)


@pytest.mark.reference("second method", "the minimum of q over a dense sampling")
def test_first_rebound_is_the_minimum_of_a_dense_sampling():
    stop = shuttle_stop()
    v0 = 0.25
    rebound, at = impact.first_rebound(stop, v0)
    t = np.linspace(0.0, 2 * stop.pulse_s + 1 / stop.f_stop_hz, 400_001)
    q, _ = impact.response_after_impact(stop, v0, t)
    assert rebound == pytest.approx(-q.min(), rel=1e-9)
    assert rebound >= -q.min()
    assert at == pytest.approx(t[np.argmin(q)], abs=2 * (t[1] - t[0]))


# ------------------------------------------------------------------------------------ approach, speed, phase angle

@pytest.mark.reference("closed form", "contact where s = h - preload (upper stop) or s = preload (lower stop)")
def test_contact_point_is_where_the_law_reaches_lift_minus_preload():
    law = shuttle_law()
    upper = impact.find_contact(law, "upper", 0.25)
    assert float(law.kinematics(np.array([upper.theta])).s[0]) == pytest.approx(11.12 - 0.25, abs=1e-12)
    assert upper.phase.kind == "rise" and upper.velocity_analog > 0
    lower = impact.find_contact(law, "lower", 0.25)
    assert float(law.kinematics(np.array([lower.theta])).s[0]) == pytest.approx(0.25, abs=1e-12)
    assert lower.phase.kind == "return" and lower.velocity_analog < 0
    with pytest.raises(CamcadError, match="preload"):
        impact.find_contact(law, "upper", 20.0)


@pytest.mark.reference("property", "force and rebound are linear in v0 = |v(theta_c)| w, and w is proportional to n")
def test_impact_force_and_rebound_are_proportional_to_speed():
    law, stop = shuttle_law(), shuttle_stop()
    sweep = impact.impact_sweep(law, stop, [280.0, 320.0, 370.0, 420.0])
    force, rebound = sweep.force_n, sweep.rebound_mm
    # everything is linear in the approach velocity v0 = |v(θc)| ω, and ω ∝ n
    assert force[3] / force[0] == pytest.approx(420 / 280, rel=1e-12)
    assert rebound[3] / rebound[0] == pytest.approx(420 / 280, rel=1e-9)
    # the published 4.137 → 6.2 N and 0.07 → 0.105 mm follow the same ratio; camcad's own figures against them
    # are test_sample_is_calibrated_at_280_rpm_and_validated_at_the_other_speeds's


#: published first-rebound amplitudes (Podgorny et al. 2018, Podgorny et al. 2018), mm, and force at 280/420 rpm, N
PUBLISHED_REBOUND = {280.0: 0.070, 320.0: 0.078, 370.0: 0.092, 420.0: 0.105}
PUBLISHED_FORCE = {280.0: 4.137, 420.0: 6.2}


@pytest.mark.reference("published", "Podgorny et al. 2018, Obrabotka Metallov 20(1) 44-54: rebounds 0.078/0.092/0.105 "
                                    "mm at 320/370/420 rpm and 6.2 N at 420 rpm (the 280 rpm figures are calibrated)")
def test_sample_is_calibrated_at_280_rpm_and_validated_at_the_other_speeds():
    # CALIBRATED: the sample's lever dimensions, stop stiffness, damping and reduced mass were chosen so that the
    # model gives the published 4.137 N and 0.070 mm at 280 rpm — agreement there is by construction, not a
    # result. VALIDATED: the model's force and rebound are proportional to the speed (everything is linear in
    # v0 ∝ n), so its predictions elsewhere are A(n) = A(280)·n/280; the published rebounds are not exactly
    # proportional. Deviations of the model from the published figures (stated in the sample's header):
    #   320 rpm: 0.0800 vs 0.078 mm (+2.6 %); 370 rpm: 0.0925 vs 0.092 (+0.5 %); 420 rpm: 0.105 vs 0.105 (0.0 %);
    #   force at 420 rpm: 6.206 vs 6.2 N (+0.1 %).
    law, stop = shuttle_law(), shuttle_stop()
    speeds = sorted(PUBLISHED_REBOUND)
    sweep = impact.impact_sweep(law, stop, speeds)
    assert sweep.force_n[0] == pytest.approx(PUBLISHED_FORCE[280.0], abs=0.001)       # calibrated
    assert sweep.rebound_mm[0] == pytest.approx(PUBLISHED_REBOUND[280.0], abs=0.0005)  # calibrated
    deviations = {}
    for n, model in zip(speeds, sweep.rebound_mm):
        assert model == pytest.approx(sweep.rebound_mm[0] * n / 280.0, rel=1e-9)   # proportional: the model's law
        deviations[n] = model / PUBLISHED_REBOUND[n] - 1.0
    assert deviations[320.0] == pytest.approx(0.026, abs=0.002)
    assert deviations[370.0] == pytest.approx(0.005, abs=0.002)
    assert deviations[420.0] == pytest.approx(0.000, abs=0.002)
    assert sweep.force_n[-1] / PUBLISHED_FORCE[420.0] - 1.0 == pytest.approx(0.001, abs=0.001)
    # it stays pressed on the stop: the rebound is below the preload
    assert not any(item.leaves_stop for item in sweep.impacts)


@pytest.mark.reference("second method", "the rise stretched and the impact recomputed from scratch, against A(t) = A0 "
                                        "t0/t")
def test_rebound_against_phase_angle_by_recomputing_the_law():
    # Second method for A(t) = A0 t0/t: stretch the rise and recompute the impact from scratch.
    stop = shuttle_stop()
    nominal = impact.impact_sweep(shuttle_law(35.0), stop, [420.0])
    relation = nominal.relation
    for t in (28.0, 42.0):
        stretched = impact.impact_at(shuttle_law(t), stop, 420.0)
        assert stretched.rebound_mm == pytest.approx(float(relation(t)), rel=1e-9)


@pytest.mark.reference("closed form", "tangent of A0 t0/t: slope -A0/t0, intercept 2 A0; A0 t0/t = 0.1 mm at t = "
                                      "36.75 deg; brentq")
def test_linearised_relation_and_least_phase_angle():
    relation = impact.ReboundRelation(amplitude_mm=0.105, phase_deg=35.0, rpm=420.0)
    slope, intercept = relation.tangent
    # tangent of A0 t0/t at t0: slope −A0/t0, intercept 2A0. With the source's A0 = 0.105 mm at 420 rpm
    # this gives −0.0030 and 0.210; the published a = −0.003 t + 0.208 has the slope and t0 = 0.104/0.003 ≈ 35°.
    assert slope == pytest.approx(-0.003, rel=1e-12)
    assert intercept == pytest.approx(0.208, rel=0.01)
    # the exact least phase angle solves A(t) = allowed (checked by root finding on the relation)
    from scipy.optimize import brentq

    limit = relation.least_phase(0.1)
    assert limit == pytest.approx(brentq(lambda t: float(relation(t)) - 0.1, 20.0, 60.0, xtol=1e-14), abs=1e-10)
    # closed form: A0 t0/t = 0.1 mm at t = 0.105 · 35 / 0.1 = 36.75 deg (the published line's 36 deg is what
    # camcad's cyclogram finds from it: tests/cyclogram/test_cyclogram.py)
    assert limit == pytest.approx(0.105 * 35.0 / 0.1, abs=1e-9)
    lo_slope, _lo_intercept = relation.fit(30.0, 40.0)
    assert lo_slope == pytest.approx(slope, rel=0.05)


# ------------------------------------------------------------------------------------ scene section and CLI

@pytest.mark.reference("property", "[stops] parsed in its alternatives; conflicting and bad keys refused with the "
                                   "reason")
def test_parse_stops_alternatives_and_errors():
    direct = scene_stops.parse_stops({"stiffness_N_per_m": 2.6e4, "mass_kg": 0.0076, "stop_stiffness_N_per_m": 1.5e5,
                                 "restitution": 0.5, "damping_ratio": 0.05, "preload_mm": 0.25}, "w")
    assert direct.stiffness_n_per_m == 2.6e4 and direct.mass_kg == 0.0076 and direct.stop == "upper"
    base = {"mass_kg": 0.0076, "stop_stiffness_N_per_m": 1.5e5, "restitution": 0.5, "damping_ratio": 0.05,
            "preload_mm": 0.25}
    with pytest.raises(CamcadError, match="given twice"):
        scene_stops.parse_stops({**base, "stiffness_N_per_m": 1e4, "youngs_modulus_MPa": 2e5, "second_moment_mm4": 1.0,
                            "arm_a_mm": 1.0, "arm_b_mm": 1.0}, "w")
    with pytest.raises(CamcadError, match="missing value 'second_moment_mm4'"):
        scene_stops.parse_stops({**base, "youngs_modulus_MPa": 2e5}, "w")
    with pytest.raises(CamcadError, match="did you mean 'restitution'"):
        scene_stops.parse_stops({**base, "stiffness_N_per_m": 1e4, "restitusion": 0.5}, "w")
    without = dict(base)
    del without["restitution"]
    with pytest.raises(CamcadError, match="restitution"):
        scene_stops.parse_stops({**without, "stiffness_N_per_m": 1e4}, "w")


@pytest.mark.reference("closed form", "the least phase angle t = t0 A0/[a] from the 420 rpm rebound; the 0.1 mm limit "
                                      "of Podgorny et al. 2018, Obrabotka Metallov 20(1) 44-54")
def test_cli_impact_scene_json(cli, tmp_path):
    result = cli("impact", SHUTTLE, "--json", "-o", tmp_path)
    # at the nominal 35 deg the rebound passes the published 0.1 mm limit above 400 rpm: the check fails
    assert result.code == 1, result.err
    d = result.json()["impact"]
    assert d["checks"]["first rebound"]["passed"] is False and d["checks"]["rebound below the preload"]["passed"]
    for key in ("reduced_stiffness_N_per_m", "f_free_hz", "f_stop_hz", "impulse_Ns", "pulse_s", "force_N",
                "rebound_mm", "phase_limit_deg", "passed"):
        assert key in d
    assert d["speeds_rpm"][0] == 280.0 and d["speeds_rpm"][-1] == 420.0 and len(d["rebound_mm"]) == 15
    # the exact relation A(t) = A0 t0/t at the fastest speed: t = t0 A0/[a], with A0 the 420 rpm rebound
    assert d["phase_limit_deg"] == pytest.approx(35.0 * d["rebound_mm"][-1] / 0.1, rel=1e-9)
    assert (tmp_path / "impact_rebound.png").stat().st_size > 10_000
    assert (tmp_path / "impact_response.png").exists()
    relaxed = cli("impact", SHUTTLE, "--json", "--no-plots", "-o", tmp_path, "--allowed", "0.11", "--rpm", "300")
    assert relaxed.code == 0
    assert isinstance(relaxed.json()["impact"]["rebound_mm"], float)  # one speed: a number, not a list


@pytest.mark.reference("published", "Podgorny et al. 2018, Obrabotka Metallov 20(1) 44-54: 4.137 N at 280 rpm (the "
                                    "figure the options are calibrated to); bad options in one line")
def test_cli_impact_law_options(cli, tmp_path):
    result = cli("impact", "--standard", "cycloidal", "--phases",
                 "0:100:dwell,100:135:rise,135:280:dwell,280:315:return,315:360:dwell", "--lift", "11.12",
                 "--rpm", "280:420", "--mass", "0.0075911", "--f-free", "297", "--f-stop", "768",
                 "--restitution", str(K_STEEL), "--zeta", "0.05", "--preload", "0.25", "--json", "--no-plots",
                 "-o", tmp_path)
    assert result.code == 0, result.err
    d = result.json()["impact"]
    assert d["force_N"][0] == pytest.approx(4.137, abs=0.002)
    bad = cli("impact", "--standard", "cycloidal", "--phases", "0:180:rise,180:360:return", "--lift", "10",
              "--rpm", "300", "--mass", "0.01", "--f-free", "800", "--f-stop", "300", "--restitution", "0.5",
              "--zeta", "0.05", "--preload", "0.25")
    assert bad.code == 2 and "f_free < f_stop" in bad.err and len(bad.err.strip().splitlines()) == 1
