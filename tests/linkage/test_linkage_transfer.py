"""The linkage as the follower's position function (camcad.linkage.transfer): the chain rule against a
second route, inverse design round trips, the rigid model's energy balance, the load on the follower and
the contact hook, tables with hard rows.
"""

from __future__ import annotations

import math
from itertools import pairwise

import numpy as np
import pytest
from numpy.polynomial import chebyshev as cheb

from camcad.errors import CamcadError
from camcad.law.standard import compose
from camcad.linkage.analysis import Linkage, Loop
from camcad.linkage.transfer import (
    FollowerLaw,
    LinkageTransfer,
    RatioTransfer,
    TableTransfer,
    WorkingLaw,
    follower_generalised_force,
    kinetic_energy,
    linkage_load,
)
from camcad.profile.scaled_law import ScaledLaw

LINKAGE = Linkage((Loop((0.0, 0.0), (100.0, 20.0), 40.0, 120.0, 90.0, 1),), theta0=math.radians(80.0),
                  input_sense=-1)
SWING = math.radians(30.0)
RISE = (math.radians(100.0), math.radians(170.0))


def _follower_law():
    """ψ(θ): a cycloidal rise and return of 30 deg (rad of swing)."""
    law = compose([("dwell", 100.0), ("rise", 70.0), ("dwell", 30.0), ("return", 70.0), ("dwell", 90.0)], 1.0,
                  "cycloidal")
    return ScaledLaw(law, SWING)


def _spectral_derivatives(fn, a: float, b: float, at, n: int = 40):
    """Derivatives 1..3 of fn on [a, b] at ``at`` from its Chebyshev interpolant on n points (a second route)."""
    x = np.cos(np.pi * (np.arange(n) + 0.5) / n)
    coef = cheb.chebfit(x, fn(a + (x + 1) / 2 * (b - a)), n - 1)
    xx = 2 * (np.asarray(at) - a) / (b - a) - 1
    return [cheb.chebval(xx, cheb.chebder(coef, k)) * (2 / (b - a)) ** k for k in (1, 2, 3)]


@pytest.mark.reference("second method", "spectral differentiation of theta -> Pi(psi(theta))")
def test_chain_rule_against_the_composed_function():
    """y'' = Π''ψ'² + Π'ψ'' (and y', y''') equal the derivatives of θ ↦ Π(ψ(θ)) taken by spectral
    differentiation of the composed function on the rise (smooth there): relative 1e-9 for y'' (measured 5e-12)."""
    psi_law = _follower_law()
    transfer = LinkageTransfer(LINKAGE, SWING)
    y = WorkingLaw(psi_law, transfer)
    at = np.linspace(RISE[0] + 0.05, RISE[1] - 0.05, 25)
    kin = y.kinematics(at)
    route = _spectral_derivatives(lambda t: transfer(psi_law.kinematics(t).s), *RISE, at)
    for mine, other, tol in ((kin.v, route[0], 1e-11), (kin.a, route[1], 1e-9), (kin.j, route[2], 1e-8)):
        assert np.max(np.abs(mine - other)) <= tol * np.max(np.abs(mine))


@pytest.mark.reference("property", "the round trip Pi(Pi^-1(y)) gives the law within 1e-9 mm")
def test_inverse_design_then_forward_kinematics_reproduces_the_law_within_1e_9_mm():
    """A working member's law → the follower's law by Π⁻¹ → forward through Π: the law again. For the
    four-bar, y is the angle of an output arm of 150 mm (1e-9 mm is 6.7e-12 rad there); for a table in mm
    (a nonlinear Π), directly in mm."""
    theta = np.linspace(0.0, 2 * np.pi, 20001)
    out_law = compose([("dwell", 90.0), ("rise", 80.0), ("dwell", 40.0), ("return", 80.0), ("dwell", 70.0)],
                      math.radians(14.0), "poly345")
    transfer = LinkageTransfer(LINKAGE, SWING)
    psi_law = FollowerLaw(out_law, transfer, SWING)
    back = WorkingLaw(psi_law, transfer).kinematics(theta)
    target = out_law.kinematics(theta)
    assert np.max(np.abs(back.s - target.s)) * 150.0 <= 1e-9
    assert np.max(np.abs(back.a - target.a)) <= 1e-9 * np.max(np.abs(target.a))
    rows_psi = np.linspace(0.0, 40.0, 41)
    table = TableTransfer(rows_psi, 25.0 * np.sin(rows_psi / 30.0) + 0.2 * rows_psi, "mm", "mm")
    mm_law = compose([("dwell", 90.0), ("rise", 80.0), ("dwell", 40.0), ("return", 80.0), ("dwell", 70.0)], 20.0,
                     "cycloidal")
    psi_mm = FollowerLaw(mm_law, table, 40.0)
    assert np.max(np.abs(WorkingLaw(psi_mm, table).kinematics(theta).s - mm_law.kinematics(theta).s)) <= 1e-9


@pytest.mark.reference("property", "energy balance: the follower's work equals the change of T = J Pi'^2 psi'^2/2, "
                                   "Gauss-Legendre")
def test_rigid_model_energy_balance_with_a_nonlinear_position_function():
    """No damping, rigid: the follower's power (the force along the roller's path from ``linkage_load`` times
    the roller's speed) integrated over the cycle equals the change of T = ½ J Π'² ψ̇² at every panel end
    within 1e-8 of T's peak. The integral is a composite 10-point Gauss–Legendre rule on 1-degree panels
    inside each phase (the integrand is analytic there), vectorised; dropping the Π'Π'' velocity-squared
    term breaks the balance by orders of magnitude (the test has teeth)."""
    psi_law = _follower_law()
    transfer = LinkageTransfer(LINKAGE, SWING)
    inertia, rpm, arm_mm = 1.2, 400.0, 120.0
    omega = 2 * math.pi * rpm / 60.0
    nodes, weights = np.polynomial.legendre.leggauss(10)
    ends = sorted({0.0, 2 * math.pi} | {p.start for p in psi_law.phases} | {p.end for p in psi_law.phases})
    panels = np.concatenate([np.linspace(a, b, max(2, math.ceil(math.degrees(b - a)) + 1))[:-1]
                             for a, b in pairwise(ends)] + [[2 * math.pi]])
    lo, hi = panels[:-1], panels[1:]
    theta = (lo[:, None] + hi[:, None]) / 2 + (hi - lo)[:, None] / 2 * nodes[None, :]
    kin = psi_law.kinematics(theta.ravel())
    _, d1, d2, _ = transfer.derivatives(kin.s)
    psi_dot = kin.v * omega
    with_term = linkage_load(transfer, kin, inertia, 0.0, arm_mm).at(rpm)
    without = follower_generalised_force(inertia, d1, 0 * d2, psi_dot, kin.a * omega ** 2) / (arm_mm * 1e-3)
    t_ends = panels / omega
    k_ends = psi_law.kinematics(panels)
    energy = kinetic_energy(inertia, transfer.derivatives(k_ends.s)[1], k_ends.v * omega)
    for force, expect_ok in ((with_term, True), (without, False)):
        power = (force * psi_dot * arm_mm * 1e-3).reshape(theta.shape)
        work = np.concatenate([[0.0], np.cumsum((power * weights[None, :]).sum(axis=1) * np.diff(t_ends) / 2)])
        error = np.max(np.abs(work - (energy - energy[0])))
        if expect_ok:
            assert error <= 1e-8 * np.max(energy)
        else:
            assert error > 1e-3 * np.max(energy)


@pytest.mark.reference("closed form", "Pi = k psi: M = J k^2 psi'' + k Q, no velocity-squared term")
def test_constant_ratio_is_the_special_case():
    """Π = kψ: M_ψ = J k² ψ̈ + k Q and no velocity-squared term; the ratio and a table of kψ agree."""
    k, inertia = 2.5, 3.0
    assert float(follower_generalised_force(inertia, k, 0.0, 7.0, 11.0, 2.0)) == pytest.approx(inertia * k * k * 11.0
                                                                                                + k * 2.0, rel=1e-15)
    psi = np.linspace(0.0, 12.0, 13)
    table = TableTransfer(psi, k * psi, "mm", "mm")
    at = np.linspace(0.0, 12.0, 101)
    for a, b in zip(table.derivatives(at), RatioTransfer(k).derivatives(at)):
        assert np.max(np.abs(a - b)) <= 1e-12


@pytest.mark.reference("closed form", "a constant load Q through ratio k adds k Q / cos phi to the normal force")
def test_the_contact_hook_adds_the_reduced_load():
    """contact_stress with a LinkageLoad of zero is the contact without it; with a constant load Q through a
    ratio k on a translating follower, the normal force grows by k Q / cos φ."""
    from camcad.contact import ContactParams, contact_stress
    from camcad.law.law import Kinematics
    from camcad.linkage.transfer import LinkageLoad

    theta = np.linspace(0.0, 1.0, 11)
    s = 5 * theta
    v = np.full_like(theta, 5.0)
    a = np.zeros_like(theta)
    phi = np.full_like(theta, 0.3)
    rho = np.full_like(theta, 40.0)
    params = ContactParams(2.1e5, 0.3, 2.1e5, 0.3, 10.0, 0.5, 2000.0, "force", 2.0, 50.0)
    plain = contact_stress(theta, s, v, a, phi, rho, 10.0, 300.0, params)
    zero = contact_stress(theta, s, v, a, phi, rho, 10.0, 300.0, params,
                          linkage_load=LinkageLoad(theta, 0 * theta, 0 * theta))
    assert np.array_equal(plain.normal_force, zero.normal_force)
    kin = Kinematics(theta, s, v, a, 0 * theta)
    load = linkage_load(RatioTransfer(3.0, "mm", "mm"), kin, 0.0, 20.0)
    more = contact_stress(theta, s, v, a, phi, rho, 10.0, 300.0, params, linkage_load=load)
    assert np.max(np.abs(more.normal_force - plain.normal_force - 60.0 / math.cos(0.3))) < 1e-9


@pytest.mark.reference("closed form", "separation at w^2 = F0/|m a/1000 + A|")
def test_separation_speed_with_the_linkage_inertia():
    """F = F0 + ω²(m a/1000 + A): the follower leaves the cam at ω² = F0/|m a/1000 + A| (closed form)."""
    from camcad.contact import ContactParams, separation_speed_rpm
    from camcad.linkage.transfer import LinkageLoad

    theta = np.array([0.0, 1.0])
    a = np.array([-100.0, 50.0])
    params = ContactParams(2.1e5, 0.3, 2.1e5, 0.3, 10.0, 0.5, 2000.0, "force", 0.0, 80.0)
    load = LinkageLoad(theta, np.array([-0.01, 0.0]), np.zeros(2))
    omega = math.sqrt(80.0 / (0.5 * 100.0 / 1000.0 + 0.01))
    assert separation_speed_rpm(theta, 0 * theta, a, params, load) == pytest.approx(omega * 60 / (2 * math.pi),
                                                                                    rel=1e-14)


@pytest.mark.reference("property", "unsorted and duplicated rows accepted, a vertical step and a turning table "
                                   "refused with the dead point")
def test_tables_with_hard_rows():
    # unsorted and duplicated rows are accepted; a vertical step (two y at one psi) is refused
    t = TableTransfer([3.0, 0.0, 1.0, 1.0, 2.0], [6.0, 0.0, 2.0, 2.0, 4.0], "mm", "mm")
    assert float(t(np.array([2.5]))[0]) == pytest.approx(5.0, rel=1e-14)
    with pytest.raises(CamcadError, match="two values of y"):
        TableTransfer([0.0, 1.0, 1.0, 2.0], [0.0, 1.0, 1.5, 2.0], "mm", "mm")
    with pytest.raises(CamcadError, match="starts at"):
        TableTransfer([1.0, 2.0], [0.0, 1.0], "mm", "mm")
    # a table that turns back: the dead point is named
    psi = np.linspace(0.0, 3.0, 31)
    bump = TableTransfer(psi, np.sin(psi), "rad", "rad")
    with pytest.raises(CamcadError, match=r"dead point .* at swing 90"):
        bump.check_monotone(3.0, "x")
    # tiny and huge scales
    for scale in (1e-6, 1e6):
        big = TableTransfer(psi * scale, np.sin(psi / 3) * scale, "mm", "mm")
        y = np.linspace(0.0, float(big(np.array([3.0 * scale]))[0]), 7)
        assert np.max(np.abs(big(big.inverse(y, 3.0 * scale)) - y)) <= 1e-13 * scale
