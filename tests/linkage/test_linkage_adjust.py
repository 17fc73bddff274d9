"""Adjustable mechanisms (Sunkuev 1984 ch. 3, 4, 6): Table 3 task 1, a fitted task, Table 2's crank
characteristics, the family of position functions, and tuning for given extreme positions."""

from __future__ import annotations

import cmath
import math

import numpy as np
import pytest

from camcad.errors import CamcadError
from camcad.linkage.adjust import (
    Adjustment,
    adjusted,
    base_setting,
    characteristics,
    check_requirements,
    crank_extremes,
    fit_task,
    solve_task1,
)
from camcad.linkage.analysis import Linkage, Loop
from camcad.linkage.family import Member, synthesize_family
from camcad.linkage.tune import extreme_positions, settings_table, solve_settings, tuned

LINKAGE = Linkage((Loop((0.0, 0.0), (100.0, 20.0), 40.0, 120.0, 90.0, 1),), theta0=math.radians(80.0),
                  input_sense=-1)
SWING = math.radians(30.0)


@pytest.mark.reference("property", "Sunkuev 1984 Table 3 task 1: one extreme fixed within 1e-9 rad at 41 settings, "
                                   "the swing monotone over 10-20 deg")
@pytest.mark.parametrize("keep", ["psi1", "psi2"])
def test_table3_task1_keeps_one_extreme_and_covers_the_swings(keep):
    """ψ₁ (or ψ₂) stays within 1e-9 rad over the whole adjustment range — checked on 41 settings spread
    over it, not only the listed ones — and the swing runs monotonically over the requested 10…20 deg."""
    result = solve_task1(LINKAGE, SWING, (math.radians(10.0), math.radians(20.0)), count=5, keep=keep)
    swings = [r.swing for r in result.rows]
    assert np.max(np.abs(np.array(swings) - np.radians([10.0, 12.5, 15.0, 17.5, 20.0]))) < 1e-12
    assert result.monotone
    dense = np.linspace(result.settings.min(), result.settings.max(), 41)
    rows = [characteristics(LINKAGE, result.adjustment, float(x), SWING, points=31) for x in dense]
    fixed = np.array([getattr(r, keep) for r in rows])
    assert np.max(np.abs(fixed - fixed[0])) <= 1e-9
    moving = np.array([r.swing for r in rows])
    assert np.all(np.diff(moving) > 0) or np.all(np.diff(moving) < 0)
    assert all(r.branch_continuous for r in rows)
    # the arc is task 1's by construction: radius = the coupler
    assert result.radius == pytest.approx(120.0, rel=1e-12)


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_task1_out_of_reach_names_the_range():
    with pytest.raises(CamcadError, match="swing runs"):
        solve_task1(LINKAGE, SWING, (math.radians(10.0), math.radians(60.0)), count=3, mu_min=math.radians(30.0))


@pytest.mark.reference("closed form", "the swing relation of a known arc, approached to 0.05 deg by the fit")
def test_fitted_task6_approaches_a_swing_relation_an_arc_can_give():
    """Task 6 (the swing a given function of the setting): the swing relation of a known arc at settings
    x(u) = x₀ + (x₁ − x₀)u on u ∈ [0, 1] is approached to 0.05 deg by the local fit started from task 1's
    arc (a short fit: the problem is ill-conditioned, many arcs give nearly the same relation)."""
    arc = Adjustment("joint", "A", "arc", complex(60.0, -40.0))
    x0 = base_setting(LINKAGE, arc)
    x1 = x0 + math.radians(8.0)

    def swing_of(u):
        return characteristics(LINKAGE, arc, x0 + (x1 - x0) * u, SWING, points=31).swing

    result = fit_task(LINKAGE, SWING, 6, (0.0, 1.0), {"swing": swing_of}, count=5, starts=1, max_evaluations=40,
                      ring_starts=0)
    assert math.degrees(result.deviation["swing"]) < 0.05
    assert result.monotone and all(r.branch_continuous for r in result.rows)


@pytest.mark.reference("second method", "the crank's extremes from a sampled full turn")
def test_crank_extremes_against_a_sampled_full_turn():
    loop = Loop((0.0, 0.0), (3.0, 0.5), 1.0, 3.0, 2.5, 1)
    ext = crank_extremes(loop)
    theta = np.linspace(-math.pi, math.pi, 200001)
    beta = np.unwrap(loop.output(theta))
    sampled = sorted(float(v) % (2 * math.pi) for v in (np.max(beta), np.min(beta)))
    found = sorted(b % (2 * math.pi) for _, b in ext)
    assert found == pytest.approx(sampled, abs=1e-8)


@pytest.mark.reference("property", "requirements met and unmet on hand-made rows; bad ones refused")
def test_requirement_checks():
    rows = [{"psi1_deg": 0.0, "psi2_deg": 10.0, "swing_deg": 10.0}, {"psi1_deg": 1e-12, "psi2_deg": 9.0,
                                                                      "swing_deg": 9.0}]
    assert check_requirements(rows, 1)["passed"]
    rows[1]["psi1_deg"] = 0.1
    assert not check_requirements(rows, 1)["passed"]
    with pytest.raises(CamcadError):
        check_requirements(rows, 9)


def _family_members(centre, radius, settings, phi0, span):
    members = []
    for x in settings:
        c = centre + radius * cmath.exp(1j * x)
        loop = Loop((0.0, 0.0), (c.real, c.imag), 40.0, 120.0, 90.0, 1)
        members.append(Member(lambda p, loop=loop: float(loop.output(phi0 + p)), 0.0, span))
    return members


@pytest.mark.reference("closed form", "three members made by a known four-bar (F = (100, 10) mm, R = 15 mm): F, R and "
                                      "the settings within 1e-7")
def test_family_generated_by_one_adjustable_fourbar_is_recovered():
    """Three members made by one four-bar whose output pivot sits on an arc (F = (100, 10) mm, R = 15 mm, at
    200, 240, 280 deg): stage 1 reaches Q < 1e-9, stage 2 gives F, R and the settings within 1e-7."""
    centre, radius, settings = complex(100.0, 10.0), 15.0, np.radians([200.0, 240.0, 280.0])
    phi0 = math.radians(60.0)
    members = _family_members(centre, radius, settings, phi0, math.radians(60.0))
    result = synthesize_family(members, crank=40.0, phi0=phi0, grid=(24, 48))
    assert result.q < 1e-9
    assert abs(result.centre - centre) < 1e-7
    assert result.radius == pytest.approx(radius, abs=1e-7)
    assert np.max(np.abs(np.remainder(result.settings - settings + math.pi, 2 * math.pi) - math.pi)) < 1e-7
    assert result.coupler == pytest.approx(120.0, abs=1e-7) and result.output_link == pytest.approx(90.0, abs=1e-7)
    assert max(result.max_error) < 1e-9 and all(result.branch_ok)


@pytest.mark.reference("property", "settings -> analysis gives the requested psi1, psi2 within 1e-10 rad for every "
                                   "root")
def test_tuning_round_trip_and_every_root():
    """Settings → analysis → the requested ψ₁, ψ₂ within 1e-10 rad, for every root; the nominal
    mechanism's own extremes are found at its own settings."""
    arc = Adjustment("pivot", "C", "arc", complex(100.0, 5.0))
    psi1, psi2 = math.radians(-2.0), math.radians(12.0)
    result = solve_settings(LINKAGE, arc, SWING, psi1, psi2, points=361)
    assert len(result.roots) >= 2
    for root in result.roots:
        got = extreme_positions(LINKAGE, tuned(LINKAGE, arc, root.x1, root.x2), SWING)
        assert abs(got[0] - psi1) <= 1e-10 and abs(got[1] - psi2) <= 1e-10
    own = extreme_positions(LINKAGE, LINKAGE, SWING)
    nominal = solve_settings(LINKAGE, arc, SWING, *own, points=361)
    assert any(abs(r.x1 - base_setting(LINKAGE, arc)) < 1e-9 and abs(r.x2) < 1e-9 for r in nominal.roots)


@pytest.mark.reference("property", "every pair of settings listed, each within 1e-8 deg of its target")
def test_settings_table_rows():
    arc = Adjustment("pivot", "C", "arc", complex(100.0, 5.0))
    rows = settings_table(LINKAGE, arc, SWING, np.radians([0.0, 2.0]), np.radians([12.0, 15.0]), points=181)
    pairs = sorted({(round(r["psi1_deg"], 9), round(r["swing_deg"], 9)) for r in rows})
    assert pairs == [(0.0, 12.0), (0.0, 15.0), (2.0, 12.0), (2.0, 15.0)]
    assert all(r["error_deg"] is None or r["error_deg"] < 1e-8 for r in rows)


@pytest.mark.reference("property", "at its nominal setting an adjusted element gives the nominal position function to "
                                   "1e-12")
def test_adjusted_elements_keep_the_nominal_geometry_at_their_nominal_setting():
    psi = np.linspace(0.0, SWING, 7)
    for adj in (Adjustment("pivot", "C", "arc", complex(90.0, 20.0)), Adjustment("joint", "A", "arc", 10 + 5j),
                Adjustment("joint", "B", "arc", complex(60.0, 60.0)), Adjustment("joint", "A", "slot", None, 0.4),
                Adjustment("link_angle")):
        again = adjusted(LINKAGE, adj, base_setting(LINKAGE, adj))
        assert np.max(np.abs(again.working_angle(psi) - LINKAGE.working_angle(psi))) < 1e-12, adj
