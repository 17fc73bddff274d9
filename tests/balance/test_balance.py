"""Area balance: the linear conditions, the exact least change, the source's modes and loop."""

import numpy as np
import pytest
from conftest import SAMPLES
from scipy.linalg import null_space

from camcad import balance
from camcad.errors import CamcadError
from camcad.law.law import PiecewiseLinearLaw
from camcad.law.phases import detect_phases
from camcad.law.source import load_law

UNBALANCED = ["dxf/fig2_rise_area_too_large.dxf", "dxf/drrd_return_short.dxf", "dxf/constant_accel_jumps.dxf",
              "dxf/r12_polyline_harmonic.dxf", "dxf/spline_law.dxf", "dxf/line_chain_trapezoid.dxf",
              "dxf/drawing_with_axes_grid_text.dxf", "law_table.csv", "law_table_semicolon.txt"]
SOURCE_MODES = ["extrema", "extrema-resample", "keypoints", "phase", "phase-keypoints"]


def _unbalanced_cycloidal(n=181, seed=0):
    from camcad.law.standard import compose

    law = compose([("dwell", 60), ("rise", 120), ("dwell", 60), ("return", 120)], 25.0)
    theta = np.linspace(0, 2 * np.pi, n)
    a = law.kinematics(theta).a
    rng = np.random.default_rng(seed)
    a = a * (1 + 0.05 * rng.standard_normal(n)) * (np.abs(a) > 0)
    return PiecewiseLinearLaw(theta, a, 2 * np.pi, detect_phases(theta, a, 2 * np.pi))


@pytest.mark.reference("second method", "v(theta) and s(theta) of the exact integrator (camcad.law), also inside a "
                                        "segment")
def test_condition_rows_equal_the_exact_integrals_anywhere():
    # C @ a must equal v(θ) and s(θ) of the exact integrator, also for θ inside a segment.
    law = _unbalanced_cycloidal()
    thetas = [0.3, 1.7, np.pi, 4.4, 2 * np.pi]
    conds = tuple(balance.Condition("v", "v", t) for t in thetas) + \
        tuple(balance.Condition("s", "s", t) for t in thetas)
    values = balance.functional_rows(law.x, conds) @ law.a
    kin = law.kinematics(np.array(thetas))
    assert values[:5] == pytest.approx(kin.v, abs=1e-12)
    assert values[5:] == pytest.approx(kin.s, abs=1e-11)


@pytest.mark.reference("second method", "dense trapezoid quadrature of a^2 on 2,000,001 points")
def test_mass_matrix_gives_the_l2_norm_of_the_polyline():
    # ∫ a² dθ of a polyline against dense trapezoid quadrature (independent, converges as h²)
    law = _unbalanced_cycloidal()
    exact = law.a @ (balance.mass_matrix(law.x) @ law.a)
    t = np.linspace(0, 2 * np.pi, 2_000_001)
    dense = np.trapezoid(np.interp(t, law.x, law.a) ** 2, t)
    assert exact == pytest.approx(dense, rel=1e-9)


@pytest.mark.reference("property", "KKT optimality: the change is M-orthogonal to the null space of the conditions "
                                   "(scipy null_space); no random feasible change is smaller")
@pytest.mark.parametrize("keep_lift", [True, False])
def test_min_change_is_the_least_change_and_balances_exactly(keep_lift):
    law = _unbalanced_cycloidal()   # no jumps: every free vertex is an unknown of its own
    result = balance.correct(law, "min-change", keep_lift=keep_lift)
    scale = result.before.rise
    assert np.max(np.abs(result.after.residuals)) <= 1e-9 * scale
    # Optimality (KKT): the change is M-orthogonal to every change that keeps the conditions (the
    # balance conditions and, unless freed, the rise), i.e. to the null space of C on the movable vertices.
    free = balance.modes._free_vertices(law, np.zeros(len(law.x), bool))
    conds = balance.conditions(law) + (balance.lift_conditions(law) if keep_lift else ())
    rows = balance.functional_rows(law.x, conds)[:, free]
    delta = (result.law.a - law.a)[free]
    mass = balance.mass_matrix(law.x).toarray()[np.ix_(free, free)]
    z = null_space(rows)
    assert np.max(np.abs(z.T @ (mass @ delta))) <= 1e-9 * np.linalg.norm(mass @ delta)
    # and it is no larger than the RMS of any random feasible correction
    rng = np.random.default_rng(1)
    for _ in range(5):
        other = delta + z @ rng.standard_normal(z.shape[1]) * 0.1
        assert other @ mass @ other >= delta @ mass @ delta


@pytest.mark.reference("property", "a balanced law is its own least change: every mode's solver returns it unchanged "
                                   "to 1e-12 of the peak")
def test_fixing_a_balanced_law_changes_nothing():
    # a balanced law is its own least change: the fast path says so without solving, and every mode's own solver
    # (reached by holding one vertex at its drawn value, a move that skips the fast path) returns it unchanged to
    # round-off; a mode that moved a balanced law (a bias, a rescaled lobe) fails here
    loaded = load_law(SAMPLES / "dxf" / "balanced_drdr_cycloidal.dxf")
    law = loaded.law
    before = balance.check(law)
    assert before.balanced and np.max(np.abs(before.residuals)) <= 1e-12 * before.rise
    quick = balance.correct(law, "min-change")
    assert not quick.changed and quick.law is law and quick.iterations == 0
    peak = float(np.max(np.abs(law.a)))
    k = int(np.argmax(law.a))
    hold = (float(np.degrees(law.x[k])), float(law.a[k]))
    for mode in balance.MODES:
        result = balance.correct(law, mode, segment_deg=(0, 360), moves=[hold])
        assert result.moves[0].honoured and result.iterations >= 1, mode     # the solver ran
        assert result.after.balanced, mode
        assert result.max_change <= 1e-12 * peak, (mode, result.max_change / peak)
        same = np.interp(law.x, result.law.x, result.law.a)
        assert np.max(np.abs(same - law.a)) <= 1e-12 * peak, mode


@pytest.mark.reference("property", "the least change: no other mode's balanced law has a smaller RMS change")
@pytest.mark.parametrize("name", UNBALANCED)
def test_min_change_balances_every_sample_and_changes_it_least(name):
    loaded = load_law(SAMPLES / name)
    before = balance.check(loaded.law)
    assert not before.balanced
    best = balance.correct(loaded.law, "min-change")
    lift = before.rise
    assert np.max(np.abs(best.after.residuals)) <= 1e-9 * lift
    for mode in SOURCE_MODES:
        other = balance.correct(loaded.law, mode)
        assert other.after.balanced, mode
        assert best.rms_change <= other.rms_change * (1 + 1e-9), mode


@pytest.mark.reference("second method", "residuals measured by the exact integrator, not the loop's own trapezoid")
@pytest.mark.parametrize("name", UNBALANCED[:4])
@pytest.mark.parametrize("mode", ["min-change", "keypoints", "extrema-resample"])
def test_iterative_loop_reaches_the_requested_tolerance(name, mode):
    loaded = load_law(SAMPLES / name)
    tol = 1e-5
    result = balance.correct(loaded.law, mode, method="iterate", step_deg=0.1, tol=tol)
    # measured with the exact integrator, not the loop's own trapezoid
    assert np.max(np.abs(result.after.residuals)) <= tol * result.before.rise
    assert result.iterations > 1


@pytest.mark.reference("property", "points of the rise cannot change the return's own balance: refused, naming "
                                   "min-change")
def test_segment_mode_that_cannot_reach_an_unbalanced_phase_says_so():
    # the return's own areas differ (its decelerating lobe is drawn 5 % high); points of the rise
    # cannot change the return's own balance, only shift the velocity it starts from
    loaded = load_law(SAMPLES / "dxf" / "r12_polyline_harmonic.dxf")
    with pytest.raises(CamcadError, match="segment") as err:
        balance.correct(loaded.law, "segment", segment_deg=(40, 180))
    assert "min-change" in str(err.value)


@pytest.mark.reference("property", "only vertices inside the segment (>= 60 deg) change, and the law balances")
def test_segment_mode_covering_the_motions_balances():
    loaded = load_law(SAMPLES / "dxf" / "fig2_rise_area_too_large.dxf")
    result = balance.correct(loaded.law, "segment", segment_deg=(60, 360))
    assert result.after.balanced
    changed = np.flatnonzero(result.law.a != loaded.law.a)
    assert np.degrees(loaded.law.x[changed]).min() >= 60 - 1e-9


@pytest.mark.reference("property", "a --move vertex keeps exactly the value set, the rest balances")
def test_move_holds_the_users_point():
    loaded = load_law(SAMPLES / "dxf" / "fig2_rise_area_too_large.dxf")
    target_deg, value = 90.0, float(loaded.law.a[np.argmin(np.abs(loaded.law.x - np.radians(90)))] * 0.9)
    result = balance.correct(loaded.law, "min-change", move=(target_deg, value))
    index = int(np.argmin(np.abs(loaded.law.x - np.radians(target_deg))))
    assert result.law.a[index] == value
    assert result.after.balanced


@pytest.mark.reference("property", "phase mode: ordinates unchanged, angles moved, residuals within 1e-9 of the rise")
def test_phase_mode_keeps_the_ordinates_and_moves_the_angles():
    loaded = load_law(SAMPLES / "dxf" / "fig2_rise_area_too_large.dxf")
    result = balance.correct(loaded.law, "phase")
    assert np.array_equal(result.law.a, loaded.law.a)
    assert not np.array_equal(result.law.x, loaded.law.x)
    assert np.max(np.abs(result.after.residuals)) <= 1e-9 * result.before.rise
    assert result.law.x[0] == 0 and result.law.x[-1] == pytest.approx(2 * np.pi)


@pytest.mark.reference("second method", "the change recomputed here by linear interpolation through the extrema, zero "
                                        "outside the lobes")
def test_extrema_mode_moves_the_extrema_and_tapers_to_the_lobe_ends():
    # the change is piecewise linear in θ through its values at the extrema, zero at the vertices just
    # outside each lobe: recomputed here from the groups and the lobes, independently of the basis
    smooth = _unbalanced_cycloidal(seed=0)
    theta = smooth.x
    from camcad.law.standard import compose

    a = compose([("dwell", 60), ("rise", 120), ("dwell", 60), ("return", 120)], 25.0).kinematics(theta).a
    a = np.where((theta > np.radians(60)) & (theta < np.radians(120)), a * 1.05, a)
    law = PiecewiseLinearLaw(theta, a, 2 * np.pi, detect_phases(theta, a, 2 * np.pi))
    result = balance.correct(law, "extrema")
    delta = result.law.a - law.a
    free = balance.modes._free_vertices(law, np.zeros(len(law.x), bool))
    groups = balance.extremum_groups(law.a, free)
    assert len(groups) == 4  # one peak per lobe of a dwell-rise-dwell-return law
    assert result.after.balanced
    inside = np.zeros(len(theta), bool)
    for lobe in balance.lobes(law.a, free):
        inside[lobe] = True
        mine = [g for g in groups if g[0] in lobe]
        anchor_x = [theta[lobe[0] - 1]] + [theta[g[0]] for g in mine] + [theta[lobe[-1] + 1]]
        anchor_d = [0.0] + [delta[g[0]] for g in mine] + [0.0]
        assert delta[lobe] == pytest.approx(np.interp(theta[lobe], anchor_x, anchor_d), abs=1e-12)
    assert np.all(delta[~inside] == 0)
    assert np.max(np.abs(delta)) <= np.max(np.abs(law.a))   # no spike


@pytest.mark.reference("second method", "RMS and max of the difference by dense sampling and every knot of both laws")
def test_difference_norms_against_dense_sampling():
    law = _unbalanced_cycloidal()
    other = balance.correct(law, "extrema-resample").law
    max_change, rms = balance.difference_norms(law, other)
    # dense samples and every knot of both laws (the largest difference of two polylines sits on a knot)
    t = np.unique(np.concatenate((np.linspace(0, 2 * np.pi, 4_000_001), law.x, other.x)))
    diff = other.kinematics(t).a - law.kinematics(t).a
    assert rms == pytest.approx(np.sqrt(np.trapezoid(diff**2, t) / (2 * np.pi)), rel=1e-6)
    assert max_change == pytest.approx(np.abs(diff).max(), rel=1e-6)


@pytest.mark.reference("property", "the least change is linear in a: a law scaled by 1e-6 or 1e6 gives the scaled "
                                   "change")
def test_tiny_and_huge_scales_balance_alike():
    law = _unbalanced_cycloidal()
    base = balance.correct(law, "min-change")
    for factor in (1e-6, 1e6):
        scaled = balance.correct(law.with_ordinates(law.a * factor), "min-change")
        assert scaled.law.a == pytest.approx(base.law.a * factor, rel=1e-9, abs=1e-12 * factor * np.abs(law.a).max())
        assert np.max(np.abs(scaled.after.residuals)) <= 1e-9 * scaled.before.rise


@pytest.mark.reference("closed form", "trapezoid error bounds derived here: |v error| <= sum|dm_k| h^2/8, |s error| "
                                      "adds T h^2 max|a'|/12")
def test_source_check_by_trapezoid_is_within_its_error_bound():
    # The source's check: resample a with step h, trapezoid twice. Bounds derived here:
    # - a grid that holds every knot integrates the polyline's v exactly (a is linear between grid points);
    # - otherwise each knot of slope change Δm_k inside a cell moves the area by at most |Δm_k| h²/8, so
    #   |error of v| ≤ Σ|Δm_k| h²/8 and |error of s| ≤ T Σ|Δm_k| h²/8 + T h² max|a'|/12 (trapezoid on v).
    on_grid = _unbalanced_cycloidal(n=181)              # knots every 2 deg
    for step in (0.4, 0.2, 0.1):
        errors = balance.check_by_trapezoid(on_grid, step_deg=step)["error_vs_exact"]
        assert max(abs(e) for e in errors[:-1]) < 1e-12
    law = _unbalanced_cycloidal(n=203)                   # knots off every grid below
    slopes = np.diff(law.a) / np.diff(law.x)
    kinks = np.sum(np.abs(np.diff(slopes)))
    period = law.cycle
    for step in (0.4, 0.2, 0.1, 0.05):
        h = np.radians(step)
        errors = balance.check_by_trapezoid(law, step_deg=step)["error_vs_exact"]
        assert max(abs(e) for e in errors[:-1]) <= kinks * h**2 / 8
        assert abs(errors[-1]) <= period * kinks * h**2 / 8 + period * h**2 * np.abs(slopes).max() / 12


@pytest.mark.reference("property", "check --trapezoid reports its step and one residual per condition beside the "
                                   "exact ones")
def test_check_cli_reports_the_trapezoid_beside_the_exact(cli):
    result = cli("check", SAMPLES / "law_table.csv", "--trapezoid", "--step", "0.5", "--json")
    assert result.code == 1
    trap = result.json()["trapezoid"]
    assert trap["step_deg"] == 0.5 and len(trap["residuals"]) == len(result.json()["conditions"])
