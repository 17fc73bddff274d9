"""One adjustable four-bar reproducing a family of position functions ψ = F⁽ʲ⁾(φ), j = 1 … p (Sunkuev 1984, ch. 4).

Sunkuev 1984 (ch. 4, "В общем случае требуется воспроизвести заданное семейство зависимостей ψ = F⁽ʲ⁾(φ)" and
the six-bar paragraph "Через точки C(1), C(2), C(3) проведем окружность") solves it in two stages:

1. *Stage 1 — Q over the members' pivot sets.* With the free parameters given (here: the coupler length b,
   shared, and each member's coupler angle α⁽ʲ⁾ at its node 1 — Sunkuev 1984's α4 and α5⁽ʲ⁾), the Q method of
   ch. 2 gives for member j the pivots C₁₂₃⁽ʲ⁾, C₁₄₅⁽ʲ⁾, … of the output link from its S nodes
   (``camcad.linkage.qmethod``: the circles |C − z_k| = b/|1 − r_k|); Q⁽ʲ⁾ is the diagonal of their
   rectangle, C⁽ʲ⁾ its centre. The objective is Q = Σ_j Q⁽ʲ⁾ (Sunkuev 1984's sum for the six-bar and the guiding
   four-bar of ch. 5) plus, camcad's addition, the spread max c⁽ʲ⁾ − min c⁽ʲ⁾ of the output link lengths
   c⁽ʲ⁾ = |B₁⁽ʲ⁾ − C⁽ʲ⁾|: one mechanism has one output link.
2. *Stage 2 — the circle through the members' pivots.* The pivots C⁽ʲ⁾ lie on the arc of the adjustable
   link: its centre F and radius R (the circumcircle for p = 3, the least-squares circle for p > 3), and
   the settings x⁽ʲ⁾ = arg(C⁽ʲ⁾ − F), the lock angles of the adjustable link FC.

Sunkuev 1984's four-bar text takes Q over the union of all members' pivots (a fixed pivot C and another
adjustable element, Fig. 5, which the OCR does not show); camcad follows the two-stage form Sunkuev 1984 uses
for the six-bar (Fig. 6) and the guiding four-bar (Fig. 10): the output pivot on an arc. The members share
the input (crank O–A of length ``crank`` at the angle φ0 + φ) and the output link's length; each member's
output angle is measured from its own start (ψ⁽ʲ⁾(φ₁) is free).

Search: the free parameters are scanned (log b × α on a grid, every member at once, vectorised), the best
b rows start a least-squares solve of the residual vector (C₁₄₅⁽ʲ⁾ − C₁₂₃⁽ʲ⁾, …, c⁽ʲ⁾ − c⁽¹⁾) whose zero is
Q = 0 with one output link — exact for a family that one adjustable four-bar generates.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Callable
from dataclasses import dataclass
from itertools import product
from typing import Any, cast

import numpy as np

from camcad.errors import CamcadError
from camcad.linkage.analysis import Linkage, Loop
from camcad.linkage.qmethod import circle_intersections, node_subsets, pivot_circle


@dataclass(frozen=True)
class Member:
    """One member of the family: ψ(φ) (rad → rad) on [φ_start, φ_end] (rad, the common input scale)."""

    function: Callable[[float], float]
    phi_start: float
    phi_end: float
    label: str = ""


def member_nodes(member: Member, count: int, spacing: str = "chebyshev") -> np.ndarray:
    """``count`` nodes φ (rad) on the member's interval: Chebyshev points with both ends, or uniform.

    Examples
    --------
    >>> [round(math.degrees(p), 6) for p in member_nodes(Member(np.sin, 0.0, math.pi / 2), 3)]
    [0.0, 45.0, 90.0]
    """
    k = np.arange(count)
    if spacing == "uniform" or count < 3:
        u = k / (count - 1)
    else:
        u = 0.5 * (1 - np.cos(np.pi * k / (count - 1)))
    return member.phi_start + (member.phi_end - member.phi_start) * u


@dataclass
class MemberState:
    """Stage 1 for one member at (b, α): its pivots, Q, centre C, output link c, branch (None: no pivots)."""

    pivots: list
    q: float
    centre: complex | None
    c: float
    branch: int


def member_state(a_points: np.ndarray, psi: np.ndarray, b: float, alpha: float, subsets) -> MemberState:
    """The Q method for one member: crank ends ``a_points`` (complex, crank units), output angles ``psi``
    (rad) at the nodes, coupler b and its absolute angle α at node 1 (module docstring).

    Examples
    --------
    A four-bar's own nodes give one pivot (Q = 0) at its output pivot:

    >>> loop = Loop((0.0, 0.0), (2.5, 0.4), 1.0, 3.0, 2.25, 1)
    >>> phi = np.linspace(0.3, 1.3, 5)
    >>> a_pts = np.exp(1j * phi); beta = loop.output(phi)
    >>> _, b_pts = loop.joints(phi[0])
    >>> st = member_state(a_pts, beta, 3.0, cmath.phase(complex(b_pts) - a_pts[0]), node_subsets(5))
    >>> st.q < 1e-12, round(st.centre.real, 9), round(st.centre.imag, 9)
    (True, 2.5, 0.4)
    """
    b_1 = a_points[0] + b * cmath.exp(1j * alpha)
    count = len(a_points)
    circles = [None] + [pivot_circle(a_points[k], b_1, psi[k] - psi[0], b) for k in range(1, count)]
    rotations = [cmath.exp(1j * (psi[k] - psi[0])) for k in range(count)]

    def branch(c: complex, k: int) -> int:
        b_k = c + rotations[k] * (b_1 - c)
        u, v = a_points[k] - c, b_k - c
        return 1 if (u.conjugate() * v).imag > 0 else -1

    candidates = []
    for subset in subsets:
        i, j = subset[1] - 1, subset[2] - 1
        points, _ = circle_intersections(*circles[i], *circles[j])
        kept = [c for c in points if len({branch(c, k - 1) for k in subset}) == 1]
        if not kept:
            return MemberState([], math.inf, None, math.nan, 0)
        candidates.append(kept)
    best, best_q = None, math.inf
    for choice in product(*candidates):
        if len({branch(c, 0) for c in choice}) != 1:
            continue
        xs = [c.real for c in choice]
        ys = [c.imag for c in choice]
        q = math.hypot(max(xs) - min(xs), max(ys) - min(ys))
        if q < best_q:
            best, best_q = list(choice), q
    if best is None:
        return MemberState([], math.inf, None, math.nan, 0)
    xs = [c.real for c in best]
    ys = [c.imag for c in best]
    centre = complex((max(xs) + min(xs)) / 2, (max(ys) + min(ys)) / 2)
    return MemberState(best, best_q, centre, abs(b_1 - centre), branch(centre, 0))


@dataclass(frozen=True)
class FamilyResult:
    """The adjustable four-bar reproducing the family (lengths mm, angles rad).

    ``crank`` OA, ``coupler`` b, ``output_link`` c; ``centre`` F and ``radius`` R of the adjustable link's
    arc; ``settings`` x⁽ʲ⁾; ``pivots`` C⁽ʲ⁾ (stage 1, complex mm); ``q`` the stage-1 objective Σ Q⁽ʲ⁾ + c
    spread (crank lengths); ``q_members`` Q⁽ʲ⁾; ``circle_residual`` max | |C⁽ʲ⁾ − F| − R | (mm);
    ``max_error`` each member's largest structural error (rad) with the final mechanism; ``mu_min`` each
    member's worst transmission angle (rad); ``branch_ok`` each member closes and keeps its branch.
    """

    crank: float
    coupler: float
    output_link: float
    phi0: float
    centre: complex
    radius: float
    settings: np.ndarray
    pivots: list
    q: float
    q_members: list
    c_members: list
    circle_residual: float
    max_error: list
    mu_min: list
    branch_ok: list
    branches: list
    alphas: list
    evaluations: int

    def mechanism(self, j: int) -> Linkage:
        """The four-bar of member j (its pivot on the arc at setting x⁽ʲ⁾), input angle φ0 + φ with θ0 = φ0."""
        c = self.centre + self.radius * cmath.exp(1j * self.settings[j])
        loop = Loop((0.0, 0.0), (c.real, c.imag), self.crank, self.coupler, self.output_link, self.branches[j])
        return Linkage((loop,), self.phi0, 1)


def fit_circle(points: list[complex]) -> tuple[complex, float, float]:
    """Centre, radius and largest radial residual of the circle through ``points`` (complex mm): the
    circumcircle of three points, a least-squares circle (algebraic start, geometric finish) of more.

    Examples
    --------
    >>> centre, r, res = fit_circle([3 + 0j, 0 + 3j, -3 + 0j])
    >>> round(abs(centre), 12), round(r, 12), res < 1e-12
    (0.0, 3.0, True)
    """
    from scipy.optimize import least_squares

    z = np.array(points, dtype=complex)
    if len(z) < 3:
        raise CamcadError(f"a circle needs three pivots, the family has {len(z)} members", "family",
                          "give three or more members")
    a = np.column_stack([2 * z.real, 2 * z.imag, np.ones(len(z))])
    rhs = np.abs(z) ** 2
    (cx, cy, _), *_ = np.linalg.lstsq(a, rhs, rcond=None)
    centre = complex(cx, cy)
    if len(z) > 3:
        fit = least_squares(lambda p: np.abs(z - complex(p[0], p[1])) - np.mean(np.abs(z - complex(p[0], p[1]))),
                            np.array([cx, cy]), xtol=1e-15, ftol=1e-15, gtol=1e-15)
        centre = complex(*fit.x)
    elif abs(np.linalg.det(a)) < 1e-12 * np.max(np.abs(a)) ** 3:
        raise CamcadError("the members' pivots are on a line: no circle through them", "family",
                          "the adjustable element is then a slot, which camcad's family synthesis does not fit")
    r = float(np.mean(np.abs(z - centre)))
    return centre, r, float(np.max(np.abs(np.abs(z - centre) - r)))


def synthesize_family(members: list[Member], nodes: int = 5, crank: float = 1.0, phi0: float = 0.0,
                      spacing: str = "chebyshev", grid: tuple[int, int] = (48, 96), ratio_max: float = 10.0,
                      keep: int = 8, mu_min: float = 0.0) -> FamilyResult:
    """Two-stage synthesis of the adjustable four-bar for a family (module docstring).

    Parameters
    ----------
    members : list of Member
        The family ψ⁽ʲ⁾(φ), rad, on their intervals (≥ 3 members).
    nodes : int
        S nodes per member (odd; subsets {1,2,3}, {1,4,5}, …).
    crank : float
        Crank length OA (mm); the result is scaled to it.
    phi0 : float
        The crank's angle at φ = 0 (rad).
    spacing : str
        "chebyshev" or "uniform" nodes.
    grid : tuple of int
        Scan points in log b and in α.
    ratio_max : float
        b is scanned in [1/ratio_max, ratio_max] crank lengths.
    keep : int
        Best scan rows refined by least squares.
    mu_min : float
        Transmission-angle limit (rad), a constraint of the search: a member's centre mechanism below it is
        excluded from the scan and penalised (10 × the violation, rad) in the least-squares refinement.

    Returns
    -------
    FamilyResult
    """
    from scipy.optimize import least_squares, minimize_scalar

    if len(members) < 3:
        raise CamcadError(f"a family needs at least three members, got {len(members)}", "family",
                          "give three or more position functions (--member)")
    subsets = node_subsets(nodes)
    data = []
    for m in members:
        phi = member_nodes(m, nodes, spacing)
        psi = np.asarray([float(m.function(p)) for p in phi], dtype=float)
        if not np.all(np.isfinite(psi)):
            raise CamcadError(f"member {m.label or ''} is not defined at every node", "family",
                              "check the member's function on its interval")
        data.append((np.exp(1j * (phi0 + phi)), psi))
    evaluations = 0

    lo = 1.0 / ratio_max
    spans = [(phi0 + m.phi_start, phi0 + m.phi_end) for m in members]

    def worst_mu(st: MemberState, b: float, j: int) -> float:
        centre = st.centre
        assert centre is not None     # its callers pass members with pivots only
        loop = Loop((0.0, 0.0), (centre.real, centre.imag), 1.0, b, st.c)
        worst = loop.worst_transmission(*spans[j])
        return worst if math.isfinite(worst) else -1.0

    def admissible(st: MemberState, b: float, j: int | None = None) -> MemberState:
        """A degenerate four-bar (an output link or frame shorter than 1/ratio_max cranks, or links
        beyond the ratio) is no mechanism: B₁ on O with C = O makes Q = 0 for any family. With ``j``, a
        member's centre mechanism below the transmission-angle limit is excluded too."""
        if st.centre is None:
            return st
        links = (1.0, b, st.c, abs(st.centre))
        if min(links) < lo or max(links) / min(links) > ratio_max:
            return MemberState([], math.inf, None, math.nan, 0)
        if j is not None and mu_min > 0 and worst_mu(st, b, j) < mu_min:
            return MemberState([], math.inf, None, math.nan, 0)
        return st

    def states(b, alphas):
        nonlocal evaluations
        evaluations += len(data)
        return [admissible(member_state(a, psi, b, al, subsets), b) for (a, psi), al in zip(data, alphas)]

    def objective(sts):
        if any(s.centre is None for s in sts):
            return math.inf
        cs = [s.c for s in sts]
        return sum(s.q for s in sts) + (max(cs) - min(cs))

    log_b = np.linspace(math.log(1 / ratio_max), math.log(ratio_max), grid[0])
    alpha = np.linspace(0.0, 2 * math.pi, grid[1], endpoint=False)
    rows = []
    step = alpha[1] - alpha[0]
    for lb in log_b:
        b = math.exp(lb)
        best_alphas, ok = [], True
        for j, (a_pts, psi) in enumerate(data):
            evaluations += len(alpha)
            q = np.array([admissible(member_state(a_pts, psi, b, al, subsets), b, j).q for al in alpha])
            if not np.any(np.isfinite(q)):
                ok = False
                break
            # the landscape of Q in α is sharp: refine the best cell by a bounded one-dimensional search
            start = float(alpha[int(np.argmin(q))])

            def q_of(al, a_pts=a_pts, psi=psi, b=b, j=j):
                nonlocal evaluations
                evaluations += 1
                return min(admissible(member_state(a_pts, psi, b, al, subsets), b, j).q, 1e3)

            fine = minimize_scalar(q_of, bounds=(start - step, start + step), method="bounded",
                                   options={"xatol": 1e-10})
            best_alphas.append(float(fine.x) if fine.fun <= q_of(start) else start)
        if ok:
            rows.append((objective(states(b, best_alphas)), b, best_alphas))
    rows = [r for r in rows if math.isfinite(r[0])]
    if not rows:
        raise CamcadError("no coupler length gives output pivots for every member (the Q method's circles never "
                          "meet)", "family", "check the members: they may be beyond one adjustable four-bar")
    rows.sort(key=lambda r: r[0])
    best: tuple[Any, ...] | None = None
    for _, b, alphas in rows[:keep]:
        def residual(p):
            sts = states(math.exp(p[0]), p[1:])
            if any(s.centre is None for s in sts):
                return np.full(sum(2 * (len(subsets) - 1) for _ in sts) + len(sts) - 1
                               + (len(sts) if mu_min > 0 else 0), 10.0)
            out = []
            for s in sts:
                for c in s.pivots[1:]:
                    out += [(c - s.pivots[0]).real, (c - s.pivots[0]).imag]
            out += [s.c - sts[0].c for s in sts[1:]]
            if mu_min > 0:     # the limit as an exact penalty (rad): 0 inside it
                out += [10.0 * max(0.0, mu_min - worst_mu(s, math.exp(p[0]), j)) for j, s in enumerate(sts)]
            return np.array(out)

        fit = least_squares(residual, np.r_[math.log(b), alphas], xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=400)
        sts = states(math.exp(fit.x[0]), fit.x[1:])
        value = objective(sts)
        if best is None or value < best[0]:
            best = (value, fit.x, sts)
    value, x, sts = cast(tuple[Any, ...], best)
    if not math.isfinite(value):
        raise CamcadError("the family synthesis found no admissible mechanism", "family",
                          "change the members or the number of nodes")
    scale = crank
    b = math.exp(x[0])
    pivots = [s.centre * scale for s in sts]
    c_len = float(np.mean([s.c for s in sts])) * scale
    centre, r, residual_circle = fit_circle(pivots)
    settings = np.array([cmath.phase(p - centre) for p in pivots])
    result = FamilyResult(crank, b * scale, c_len, phi0, centre, r, settings, pivots, value,
                          [s.q for s in sts], [s.c * scale for s in sts], residual_circle, [], [], [],
                          [s.branch for s in sts], list(x[1:]), evaluations)
    errors, mus, oks, branches = [], [], [], []
    for j, m in enumerate(members):
        lk = _member_linkage(result, j, data[j][0][0] * scale)
        branches.append(lk.loops[0].branch)
        phi = np.linspace(m.phi_start, m.phi_end, 401)
        beta = lk.loops[0].output(phi0 + phi)
        target = np.array([float(m.function(p)) for p in phi])
        # the output angle may jump by 2π where A crosses the frame line beyond C: compare turns mod 2π
        err = np.remainder((beta - beta[0]) - (target - target[0]) + np.pi, 2 * np.pi) - np.pi
        errors.append(float(np.max(np.abs(err))) if np.all(np.isfinite(err)) else math.inf)
        loop = lk.loops[0]
        mus.append(loop.worst_transmission(phi0 + m.phi_start, phi0 + m.phi_end))
        deads = [t for t in loop.dead_points() if _inside(t, phi0 + m.phi_start, phi0 + m.phi_end)]
        oks.append(bool(np.all(np.isfinite(beta)) and not deads))
    from dataclasses import replace

    return replace(result, max_error=errors, mu_min=mus, branch_ok=oks, branches=branches)


def _member_linkage(result: FamilyResult, j: int, a_1: complex) -> Linkage:
    """Member j's four-bar on the branch that puts B at B₁⁽ʲ⁾ at node 1."""
    c = result.centre + result.radius * cmath.exp(1j * result.settings[j])
    loop = Loop((0.0, 0.0), (c.real, c.imag), result.crank, result.coupler, result.output_link, 1)
    b_1 = a_1 + result.coupler * cmath.exp(1j * result.alphas[j])
    theta_1 = cmath.phase(a_1)
    return Linkage((loop.with_branch_through(theta_1, b_1),), result.phi0, 1)


def _inside(angle: float, start: float, end: float) -> bool:
    lo, hi = min(start, end), max(start, end)
    k = math.ceil((lo - angle) / (2 * math.pi))
    return angle + 2 * math.pi * k < hi and angle + 2 * math.pi * k > lo
