"""Settings for given extreme positions of the working member (Sunkuev 1984, ch. 6).

Sunkuev 1984 (ch. 6, "В период остановки непроворачивающегося механизма регулируются координаты ψ1 и ψ2"):
for a mechanism with two setting parameters x₁, x₂ and the extreme positions ψ₁ = ψ₁(x₁, x₂),
ψ₂ = ψ₂(x₁, x₂), the given ψ₁, ψ₂ turn the two equations into x₂ = f₁(x₁) and x₂ = f₂(x₁), and

    F(x₁) = f₁(x₁) − f₂(x₁) = 0                                                (Sunkuev 1984, eq. 2)

is one transcendental equation in one unknown; x₂ follows from either f. Sunkuev 1984 solves it "by one of
the fast numerical methods" using the mechanism's kinematic properties.

camcad's mechanism with two settings: x₁ is the adjustable element of ``camcad.linkage.adjust`` (a pivot
or joint on an arc or slot), x₂ the angle at which the input link is clamped to the follower's arm (a link
locked at angles). Then f_k is closed form: the working member at its k-th extreme position fixes the
output link; the loop closure solved backwards (the input joint A on the circles (P, a) and (B, b); the
assembly branch kept) gives the input link's angle θ, and x₂ = θ − θ₀(x₁) − s_in ψ_k. F is sampled on
a grid of x₁, every sign change (not a jump of 2π) is bracketed and refined by Brent's method, and every
root is reported — the equation may have several, each a different mechanism setting for the same
extreme positions.

Settings tables (Sunkuev 1984's buttonhole-machine tables of "the buttonhole's parameters and the
corresponding settings", ch. 6) list the roots over a grid of requested (ψ₁, swing).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camcad.errors import CamcadError
from camcad.linkage.adjust import Adjustment, adjusted, base_setting
from camcad.linkage.analysis import Linkage, analyse
from camcad.linkage.qmethod import circle_intersections


def loop_inputs(loop, beta: float) -> list[float]:
    """Absolute input angles θ (rad) at which ``loop`` (on its branch) has the absolute output angle β:
    A on the circles (P, a) and (B, b), B = Q + c e^{iβ}; kept when the forward solution gives β back.

    Examples
    --------
    >>> from camcad.linkage.analysis import Loop
    >>> loop = Loop((0.0, 0.0), (100.0, 20.0), 40.0, 120.0, 90.0, 1)
    >>> beta = float(loop.output(1.2))
    >>> sorted(round(t, 12) for t in loop_inputs(loop, beta))      # a crank-rocker meets β twice per turn
    [-2.651298685708, 1.2]
    """
    p, q = complex(*loop.p), complex(*loop.q)
    b_pt = q + loop.c * complex(math.cos(beta), math.sin(beta))
    points, _ = circle_intersections(p, loop.a, b_pt, loop.b)
    out = []
    for a_pt in points:
        theta = math.atan2((a_pt - p).imag, (a_pt - p).real)
        back = float(loop.output(theta))
        if np.isfinite(back) and abs(math.remainder(back - beta, 2 * math.pi)) < 1e-9:
            out.append(theta)
    return out


def chain_inputs(linkage: Linkage, working: float) -> list[float]:
    """Input angles θ₁ (rad) of loop 1 at which the working member stands at the absolute angle ``working``.

    Examples
    --------
    >>> from camcad.linkage.analysis import Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 20.0), 40.0, 120.0, 90.0, 1),), theta0=1.2)
    >>> sorted(round(t, 12) for t in chain_inputs(lk, float(lk.working_angle(0.0))))
    [-2.651298685708, 1.2]
    """
    betas = [working - linkage.output_offset]
    for k in range(len(linkage.loops) - 1, -1, -1):
        thetas = [t for beta in betas for t in loop_inputs(linkage.loops[k], beta)]
        betas = [t - linkage.couplings[k - 1] for t in thetas] if k > 0 else thetas
    return betas


@dataclass(frozen=True)
class TuneRoot:
    """One solution: settings x₁ (rad or mm), x₂ (rad), the extreme positions reached (rad, as ``adjust``),
    the round-trip error (rad), the worst transmission angle (rad) and the branch check over the swing."""

    x1: float
    x2: float
    psi1: float
    psi2: float
    error: float
    mu_min: float
    branch_continuous: bool


@dataclass(frozen=True)
class TuneResult:
    """Every root of F(x₁) = 0 for the requested ψ₁, ψ₂ (rad) and the sampled F (for the plot)."""

    psi1: float
    psi2: float
    roots: list
    x1_grid: np.ndarray
    f_grid: np.ndarray
    adjustment: Adjustment


def _x2_candidates(linkage: Linkage, adj: Adjustment, x1: float, target_working: float, at_psi: float) -> list[float]:
    lk = adjusted(linkage, adj, x1)
    return [math.remainder(t - lk.theta0 - lk.input_sense * at_psi, 2 * math.pi)
            for t in chain_inputs(lk, target_working)]


def tuned(linkage: Linkage, adj: Adjustment, x1: float, x2: float) -> Linkage:
    """The linkage at settings x₁ (the element ``adj``) and x₂ (the input link's clamp angle), rad."""
    return adjusted(adjusted(linkage, adj, x1), Adjustment("link_angle"), x2)


def extreme_positions(linkage: Linkage, tuned_linkage: Linkage, psi_max: float) -> tuple[float, float]:
    """(ψ₁, ψ₂) of ``tuned_linkage`` from the nominal ``linkage``'s working angle at ψ = 0 (rad)."""
    ref = float(linkage.working_angle(np.array([0.0]))[0])
    w = tuned_linkage.working_angle(np.array([0.0, psi_max]))
    s = linkage.output_sense
    return s * math.remainder(float(w[0]) - ref, 2 * math.pi), s * math.remainder(float(w[1]) - ref, 2 * math.pi)


def solve_settings(linkage: Linkage, adj: Adjustment, psi_max: float, psi1: float, psi2: float,
                   x1_range: tuple[float, float] | None = None, points: int = 721) -> TuneResult:
    """All settings (x₁, x₂) giving the extreme positions ψ₁, ψ₂ (rad, module docstring).

    Parameters
    ----------
    linkage : Linkage
        The nominal mechanism.
    adj : Adjustment
        The element of x₁ (not ``link_angle``: x₂ is the input link's clamp angle).
    psi_max : float
        The follower's swing, rad.
    psi1, psi2 : float
        The requested extreme positions, rad, from the nominal working angle at ψ = 0.
    x1_range : tuple or None
        The interval of x₁ searched (rad, mm for a slot); default ±90° (±the radius) around the nominal.
    points : int
        Samples of F over the interval.

    Returns
    -------
    TuneResult

    Examples
    --------
    The nominal mechanism's own extremes are found at its own settings:

    >>> from camcad.linkage.analysis import Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 20.0), 40.0, 120.0, 90.0, 1),), theta0=1.4, input_sense=-1)
    >>> adj = Adjustment("pivot", "C", "arc", 100 + 5j)
    >>> psi1, psi2 = extreme_positions(lk, lk, 0.5)
    >>> r = solve_settings(lk, adj, 0.5, psi1, psi2)
    >>> any(abs(t.x1 - base_setting(lk, adj)) < 1e-9 and abs(t.x2) < 1e-9 for t in r.roots)
    True
    """
    from scipy.optimize import brentq

    if adj.element == "link_angle":
        raise CamcadError("x1 must be a pivot or joint: x2 is already the input link's clamp angle", "tune",
                          "adjust a pivot (C) or a joint (A, B) for x1")
    x_b = base_setting(linkage, adj)
    if x1_range is None:
        half = 0.5 * min(loop.c for loop in linkage.loops)
        x1_range = (x_b - math.pi / 2, x_b + math.pi / 2) if adj.path == "arc" else (-half, half)
    ref = float(linkage.working_angle(np.array([0.0]))[0])
    s = linkage.output_sense
    targets = (ref + s * psi1, ref + s * psi2)

    def branches(x1):
        first = _x2_candidates(linkage, adj, x1, targets[0], 0.0)
        second = _x2_candidates(linkage, adj, x1, targets[1], psi_max)
        return first, second

    grid = np.linspace(x1_range[0], x1_range[1], points)
    # F per pair of candidate branches; with one admissible candidate each (the usual case) one curve
    values = np.full((points, 4), np.nan)
    for i, x1 in enumerate(grid):
        first, second = branches(float(x1))
        for p, f1 in enumerate(first[:2]):
            for q, f2 in enumerate(second[:2]):
                values[i, 2 * p + q] = math.remainder(f1 - f2, 2 * math.pi)

    def f_of(x1, column):
        first, second = branches(float(x1))
        p, q = divmod(column, 2)
        if p >= len(first) or q >= len(second):
            return math.nan
        return math.remainder(first[p] - second[q], 2 * math.pi)

    roots: list[TuneRoot] = []
    seen: list[tuple[float, float]] = []
    for column in range(4):
        col = values[:, column]
        for i in range(points - 1):
            v0, v1 = col[i], col[i + 1]
            if not (np.isfinite(v0) and np.isfinite(v1)) or abs(v1 - v0) > math.pi:
                continue
            if v0 == 0.0 or v0 * v1 < 0.0:
                if v0 == 0.0:
                    x1 = float(grid[i])
                else:
                    try:
                        x1 = float(brentq(lambda x, c=column: f_of(x, c), grid[i], grid[i + 1], xtol=1e-15,
                                          rtol=4 * np.finfo(float).eps))
                    except ValueError:
                        continue
                first = branches(x1)[0]
                p = column // 2
                if p >= len(first):
                    continue
                x2 = first[p]
                if any(abs(x1 - a) < 1e-9 and abs(math.remainder(x2 - b, 2 * math.pi)) < 1e-9 for a, b in seen):
                    continue
                seen.append((x1, x2))
                lk = tuned(linkage, adj, x1, x2)
                got1, got2 = extreme_positions(linkage, lk, psi_max)
                res = analyse(lk, psi_max, 181)
                mu = min(res.mu_min) if res.closes else math.nan
                roots.append(TuneRoot(x1, x2, got1, got2, max(abs(got1 - psi1), abs(got2 - psi2)), mu,
                                      res.branch_continuous))
    roots.sort(key=lambda r: r.x1)
    f_grid = values[:, 0]
    return TuneResult(psi1, psi2, roots, grid, f_grid, adj)


def settings_table(linkage: Linkage, adj: Adjustment, psi_max: float, psi1_values, swing_values,
                   x1_range: tuple[float, float] | None = None, points: int = 361) -> list[dict]:
    """The settings for every requested (ψ₁, swing) pair (rad): one row per root (deg, mm), with the
    round-trip error and the checks — Sunkuev 1984's settings tables.

    Examples
    --------
    >>> from camcad.linkage.analysis import Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (100.0, 20.0), 40.0, 120.0, 90.0, 1),), theta0=1.4, input_sense=-1)
    >>> rows = settings_table(lk, Adjustment("pivot", "C", "arc", 100 + 5j), 0.5, [0.0], [0.26])
    >>> len(rows) >= 1 and all(r["error_deg"] < 1e-8 for r in rows if r["x1"] is not None)
    True
    """
    rows = []
    unit = "deg" if adj.path == "arc" else "mm"
    for p1 in np.atleast_1d(psi1_values):
        for sw in np.atleast_1d(swing_values):
            found = solve_settings(linkage, adj, psi_max, float(p1), float(p1 + sw), x1_range, points)
            base = {"psi1_deg": math.degrees(p1), "swing_deg": math.degrees(sw), "psi2_deg": math.degrees(p1 + sw)}
            if not found.roots:
                rows.append({**base, "root": 0, "x1": None, "x1_unit": unit, "x2_deg": None, "error_deg": None,
                             "mu_min_deg": None, "branch_continuous": None})
            for k, r in enumerate(found.roots, start=1):
                rows.append({**base, "root": k, "x1": math.degrees(r.x1) if unit == "deg" else r.x1, "x1_unit": unit,
                             "x2_deg": math.degrees(r.x2), "error_deg": math.degrees(r.error),
                             "mu_min_deg": math.degrees(r.mu_min) if np.isfinite(r.mu_min) else None,
                             "branch_continuous": r.branch_continuous})
    return rows

