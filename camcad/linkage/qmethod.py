"""The Q method of function-generator synthesis (Sunkuev 1984, ch. 2 of the abstract).

Sunkuev 1984's statement (ch. 2, the paragraph "Выберем на отрезке [φ0, φm] S узлов интерполирования"
and the formula for Q): choose S interpolation nodes 1..S on the input interval, S being the number
of scheme parameters. A synthesis method that interpolates on r < S nodes fixes r parameters by
finding one fixed pivot, the other S − r (the *free* parameters) being chosen. Of the C(S, r) node
subsets take the K subsets that all contain node 1 and contain each other node exactly once
({1,2,3}, {1,4,5}, … for r = 3: K = (S − 1)/(r − 1)). With the same free parameters, each subset
gives a position of the fixed pivot; Q is the diagonal of the axis-parallel rectangle around the K
positions,

    Q = sqrt((x_max − x_min)² + (y_max − y_min)²),

a function of the free parameters, minimised by nonlinear programming under the limits on the
mechanism. Q = 0 means a mechanism that interpolates on all S nodes. After the minimum, the
pivot is chosen inside the rectangle (Sunkuev 1984: "for example in the middle of the diagonal"), or
searched inside it for the least deviation. One value of Q costs S positions of the mechanism,
one value of a deviation N (Sunkuev 1984's third conclusion of ch. 2).

camcad's four-bar version (Sunkuev 1984's Fig. 5 parametrisation, ch. 4: "при заданных α5, α4 …
определить положение C123 шарнира C"): S = 5 (a, b, c, d up to scale; φ0; ψ0), r = 3, K = 2. The
crank has length a = 1 (this fixes the scale, so Q is measured in crank lengths: camcad's choice;
Sunkuev 1984 leaves the normalisation open) and points along +x at node 1: A_k = e^{i(φ_k − φ_1)}. The
free parameters are the coupler length b and its angle α to the crank at node 1 (Sunkuev 1984's α5):
B_1 = 1 + b e^{iα}. For node k the output link turns by Δψ_k = ψ_k − ψ_1 about the unknown pivot C,
so B_k = C + r_k (B_1 − C), r_k = e^{iΔψ_k}; the coupler length is kept, |B_k − A_k| = b, exactly when

    |C − z_k| = ρ_k,   z_k = (A_k − r_k B_1)/(1 − r_k),   ρ_k = b/|1 − r_k|,

a circle of possible pivots per node k ≥ 2. The subset {1, i, j} gives the pivot C_1ij as an
intersection of circles i and j (0, 1 or 2 points). camcad keeps an intersection only when the
linkage is on the same assembly branch at the subset's nodes, and of the 2^K choices of one
intersection per subset takes the one with the smallest Q whose branch at node 1 is common
(camcad's rule: Sunkuev 1984 does not say how to choose between the two intersections). With no
admissible choice, Q is replaced by a penalty (100 crank lengths plus the gap between the circles).

Limits (``fgen.Limits``) are checked on the mechanism with the pivot at the centre of the rectangle:
transmission angle over the working range (closed form) and the largest link ratio.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass
from itertools import product
from typing import Any

import numpy as np

from camcad.errors import CamcadError
from camcad.linkage.fgen import (
    FunctionGenerator,
    Limits,
    Work,
    from_pivots,
    structural_error,
)
from camcad.linkage.target import Target

PENALTY = 100.0


def node_subsets(count: int, r: int = 3) -> list[tuple[int, ...]]:
    """Sunkuev 1984's K node subsets (1-based): each contains node 1, every other node is in exactly one.

    K = (S − 1)/(r − 1) must be whole.

    Examples
    --------
    >>> node_subsets(5), node_subsets(7)
    ([(1, 2, 3), (1, 4, 5)], [(1, 2, 3), (1, 4, 5), (1, 6, 7)])
    """
    if count < r or (count - 1) % (r - 1):
        raise CamcadError(f"{count} nodes cannot be split into subsets of {r} that share node 1 and hold every "
                          f"other node once ((S-1)/(r-1) = {(count - 1) / (r - 1):g} is not whole)", "--nodes",
                          f"give an odd number of nodes >= {r}, e.g. --nodes 5 (the four-bar has S = 5 parameters)")
    return [(1, *range(2 + (r - 1) * k, 2 + (r - 1) * (k + 1))) for k in range((count - 1) // (r - 1))]


def pivot_circle(a_k: complex, b_1: complex, dpsi_k: float, b: float) -> tuple[complex, float]:
    """Centre z_k and radius ρ_k of the circle of output pivots C that keep the coupler length b when the
    crank end moves to ``a_k`` and the output link turns by Δψ_k (module docstring).

    Examples
    --------
    A parallelogram (crank 1, coupler 3 along +x, output pivot at 3): turning both links by 30°
    keeps C = 3 on the circle.

    >>> r = cmath.exp(1j * math.radians(30))
    >>> z, rho = pivot_circle(r, 1 + 3 + 0j, math.radians(30), 3.0)
    >>> round(abs(3 - z) - rho, 12)
    0.0
    """
    r = cmath.exp(1j * dpsi_k)
    return (a_k - r * b_1) / (1 - r), b / abs(1 - r)


def circle_intersections(z1: complex, r1: float, z2: complex, r2: float) -> tuple[list[complex], float]:
    """Intersections of two circles and, when there are none, the gap between them (0 otherwise).

    Examples
    --------
    >>> pts, gap = circle_intersections(0j, 5.0, 8 + 0j, 5.0)
    >>> sorted((round(p.real, 12), round(p.imag, 12)) for p in pts), gap
    ([(4.0, -3.0), (4.0, 3.0)], 0.0)
    """
    dz = z2 - z1
    dist = abs(dz)
    if dist == 0.0:
        return [], abs(r1 - r2) + 1.0
    if dist > r1 + r2:
        return [], dist - (r1 + r2)
    if dist < abs(r1 - r2):
        return [], abs(r1 - r2) - dist
    along = (r1 * r1 - r2 * r2 + dist * dist) / (2 * dist)
    h = math.sqrt(max(r1 * r1 - along * along, 0.0))
    base = z1 + along * dz / dist
    normal = 1j * dz / dist
    return [base + h * normal, base - h * normal], 0.0


def circles_meet(z1, r1, z2, r2):
    """Where the circles (z1, r1) and (z2, r2) meet, element by element (complex centres, lengths): (meet, base,
    offset, gap) — the two points are base ± offset where ``meet``; ``gap`` is how far apart the circles are where
    they do not meet (0 where they do)."""
    dz = z2 - z1
    dist = np.abs(dz)
    with np.errstate(all="ignore"):
        along = (r1 ** 2 - r2 ** 2 + dist ** 2) / (2 * dist)
        h = np.sqrt(np.maximum(r1 ** 2 - along ** 2, 0.0))
        meet = (dist > 0) & (dist <= r1 + r2) & (dist >= np.abs(r1 - r2))
        base = z1 + along * dz / dist
        offset = h * (1j * dz / dist)
    gap = np.where(meet, 0.0, np.maximum(dist - (r1 + r2), np.abs(r1 - r2) - dist))
    return meet, base, offset, gap


def _cross(u: complex, v: complex) -> float:
    return (u.conjugate() * v).imag


@dataclass
class QState:
    """One value of Q: the free parameters, the K pivots, the rectangle and the centre mechanism."""

    b: float
    alpha: float
    q: float
    feasible: bool
    pivots: list[complex]
    candidates: list[list[complex]]
    circles: list[tuple[complex, float]]
    mechanism: FunctionGenerator | None


class QProblem:
    """The Q objective for one target, node set and limits; counts positions in ``work``."""

    def __init__(self, target: Target, nodes_phi: np.ndarray, limits: Limits, work: Work):
        self.target = target
        self.phi = np.asarray(nodes_phi, dtype=float)
        self.psi = np.asarray(target.psi(self.phi), dtype=float)
        self.count = len(self.phi)
        self.subsets = node_subsets(self.count)
        self.limits = limits
        self.work = work
        self.a_points = [cmath.exp(1j * (p - self.phi[0])) for p in self.phi]
        self._last: tuple[tuple[float, float], QState] | None = None
        self._margins: tuple[QState, list[float]] | None = None

    def state(self, b: float, alpha: float) -> QState:
        """Q and its pivots for free parameters b (crank lengths) and α (rad). S positions (a repeated
        call with the same parameters is answered from memory and not counted again)."""
        if self._last is not None and self._last[0] == (b, alpha):
            return self._last[1]
        st = self._state(b, alpha)
        self._last = ((b, alpha), st)
        return st

    def _state(self, b: float, alpha: float) -> QState:
        self.work.positions += self.count
        self.work.objective_evaluations += 1
        b_1 = self.a_points[0] + b * cmath.exp(1j * alpha)
        circles: list[Any] = [None] + [pivot_circle(self.a_points[k], b_1, self.psi[k] - self.psi[0], b)
                            for k in range(1, self.count)]
        rotations = [cmath.exp(1j * (self.psi[k] - self.psi[0])) for k in range(self.count)]

        def branch(c: complex, k: int) -> int:
            b_k = c + rotations[k] * (b_1 - c)
            return 1 if _cross(self.a_points[k] - c, b_k - c) > 0 else -1

        candidates, gap = [], 0.0
        for subset in self.subsets:
            i, j = subset[1] - 1, subset[2] - 1
            points, g = circle_intersections(*circles[i], *circles[j])
            gap += g
            kept = []
            for c in points:
                signs = {branch(c, k - 1) for k in subset}
                if len(signs) == 1:
                    kept.append(c)
            candidates.append(kept)
        if any(not kept for kept in candidates):
            return QState(b, alpha, PENALTY + gap, False, [], candidates, circles[1:], None)
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
            return QState(b, alpha, PENALTY, False, [], candidates, circles[1:], None)
        xs = [c.real for c in best]
        ys = [c.imag for c in best]
        centre = complex((max(xs) + min(xs)) / 2, (max(ys) + min(ys)) / 2)
        mech = from_pivots(self.a_points[0], b_1, centre, self.phi[0], self.psi[0])
        return QState(b, alpha, best_q, True, best, candidates, circles[1:], mech)

    def penalised_many(self, b: np.ndarray, alpha: np.ndarray) -> np.ndarray:
        """``penalised`` for arrays of free parameters at once (the scan): the same rules vectorised;
        S positions plus the transmission-angle check per point are counted."""
        b = np.asarray(b, dtype=float)
        alpha = np.asarray(alpha, dtype=float)
        m = b.size
        self.work.positions += self.count * m
        self.work.objective_evaluations += m
        a_pts = np.array(self.a_points)
        rot = np.exp(1j * (self.psi - self.psi[0]))
        b_1 = a_pts[0] + b * np.exp(1j * alpha)
        centres = {k: (a_pts[k] - rot[k] * b_1) / (1 - rot[k]) for k in range(1, self.count)}
        radii = {k: b / abs(1 - rot[k]) for k in range(1, self.count)}

        def branch(c, k):
            b_k = c + rot[k] * (b_1 - c)
            return np.sign(((a_pts[k] - c).conj() * (b_k - c)).imag)

        cands, gaps = [], np.zeros(m)
        for subset in self.subsets:
            i, j = subset[1] - 1, subset[2] - 1
            meet, base, offset, gap = circles_meet(centres[i], radii[i], centres[j], radii[j])
            gaps += gap
            pair = []
            for sign in (1.0, -1.0):
                c = base + sign * offset
                ok = meet.copy()
                signs = [branch(c, k - 1) for k in subset]
                ok &= (signs[0] == signs[1]) & (signs[0] == signs[2])
                pair.append((c, ok, signs[0]))
            cands.append(pair)
        best_q = np.full(m, np.inf)
        best_centre = np.zeros(m, dtype=complex)
        for choice in product(*[range(2)] * len(self.subsets)):
            picked = [cands[s][c] for s, c in enumerate(choice)]
            ok = np.logical_and.reduce([p[1] for p in picked])
            ok &= np.logical_and.reduce([p[2] == picked[0][2] for p in picked])
            xs = np.array([p[0].real for p in picked])
            ys = np.array([p[0].imag for p in picked])
            q = np.hypot(xs.max(0) - xs.min(0), ys.max(0) - ys.min(0))
            better = ok & (q < best_q)
            best_q = np.where(better, q, best_q)
            best_centre = np.where(better, (xs.max(0) + xs.min(0)) / 2 + 1j * (ys.max(0) + ys.min(0)) / 2,
                                   best_centre)
        found = np.isfinite(best_q)
        lo, hi = _bounds(self.limits)
        bound = np.maximum(0.0, lo - b) + np.maximum(0.0, b - hi)
        out = np.where(found, 0.0, PENALTY + gaps) + PENALTY_WEIGHT * bound
        # limits of the centre mechanism (a = 1, b, c = |B1 - C|, d = |C|), closed-form transmission angle
        c_len = np.abs(b_1 - best_centre)
        d_len = np.abs(best_centre)
        with np.errstate(all="ignore"):
            links = np.stack([np.ones(m), b, c_len, d_len])
            ratio = math.log(self.limits.ratio_max) - np.log(links.max(0) / links.min(0))
            theta_1 = -np.angle(best_centre)
        start = theta_1 - self.phi[0] + min(0.0, self.target.dphi)
        stop = theta_1 - self.phi[0] + max(0.0, self.target.dphi)
        angles = [start, stop]
        for base_angle in (0.0, math.pi):
            k = np.ceil((start - base_angle) / (2 * math.pi))
            inside = base_angle + 2 * math.pi * k
            angles.append(np.where(inside <= stop, inside, start))
        self.work.positions += 4 * m
        worst = np.full(m, np.inf)
        for theta in angles:
            f2 = 1.0 + d_len ** 2 - 2.0 * d_len * np.cos(theta)
            with np.errstate(all="ignore"):
                cos_mu = (b ** 2 + c_len ** 2 - f2) / (2.0 * b * c_len)
                mu = np.where(np.abs(cos_mu) <= 1.0, np.arccos(np.clip(cos_mu, -1.0, 1.0)), -1.0)
            worst = np.minimum(worst, np.where(mu < 0, -1.0 - math.radians(self.limits.mu_min_deg),
                                               np.minimum(mu, math.pi - mu)))
        mu_margin = worst - math.radians(self.limits.mu_min_deg)
        mu_margin = np.where(worst <= -1.0 - math.radians(self.limits.mu_min_deg) + 1e-12, -1.0, mu_margin)
        limits_pen = PENALTY_WEIGHT * (np.maximum(0.0, -mu_margin) + np.maximum(0.0, -ratio))
        return np.where(found, best_q + limits_pen, 0.0) + out

    def constraints(self, b: float, alpha: float) -> list[float]:
        """Limit margins (≥ 0 when met) of the centre mechanism: transmission angle (rad), link ratio (log)."""
        st = self.state(b, alpha)
        if st.mechanism is None:
            return [-1.0, -1.0]
        if self._margins is not None and self._margins[0] is st:
            return self._margins[1]
        margins = [self.limits.mu_margin(st.mechanism, self.target, self.work),
                   self.limits.ratio_margin(st.mechanism)]
        self._margins = (st, margins)
        return margins


@dataclass
class QResult:
    """The outcome of the Q method: the best state, the mechanism after the last step, how it was found."""

    state: QState
    mechanism: FunctionGenerator
    pick: str
    feasible: bool
    samples: int
    local_runs: list[dict]
    message: str


PENALTY_WEIGHT = 10.0


def penalised(problem: QProblem, b: float, alpha: float) -> float:
    """Q + 10 × (violation of the transmission-angle margin in rad + violation of the log link-ratio
    margin + violation of b's bounds): the exact-penalty objective the local search minimises.

    Examples
    --------
    Within the limits it is Q itself:

    >>> from camcad.linkage.fgen import nodes
    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> p = QProblem(t, nodes(5, t.dphi), Limits(30.0, 10.0), Work())
    >>> penalised(p, 1.3378, 3.5439) == p.state(1.3378, 3.5439).q
    True
    """
    st = problem.state(b, alpha)
    lo, hi = _bounds(problem.limits)
    bound = max(0.0, lo - b) + max(0.0, b - hi)
    if st.mechanism is None:
        return st.q + PENALTY_WEIGHT * bound
    mu, ratio = problem.constraints(b, alpha)
    return st.q + PENALTY_WEIGHT * (max(0.0, -mu) + max(0.0, -ratio) + bound)


def _bounds(limits: Limits) -> tuple[float, float]:
    return 1.0 / limits.ratio_max, limits.ratio_max



def crank_of(log_b: float) -> float:
    """The crank length b from its logarithm, the optimisers' variable; an optimiser's step far out (log b past
    700, where exp overflows) gives the largest finite length, which the link-ratio limit refuses."""
    return math.exp(min(float(log_b), 700.0))

def local_minimum(problem: QProblem, start: tuple[float, float], polish: bool = True) -> tuple[np.ndarray, float]:
    """Minimise the penalised Q from ``start`` = (b, α rad) by Nelder–Mead (log b, α), finish on an active
    limit with SLSQP, then, when K = 2 and Q is nearly zero, by Gauss–Newton on the vector C_145 − C_123
    (whose length is Q), each kept only if it lowers the penalised Q. Returns ((b, α), penalised value).

    Examples
    --------
    >>> from camcad.linkage.fgen import nodes
    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> p = QProblem(t, nodes(5, t.dphi), Limits(30.0, 10.0), Work())
    >>> x, value = local_minimum(p, (1.4, math.radians(214.0)))
    >>> round(value, 7)
    0.0009526
    """
    from scipy.optimize import least_squares, minimize

    def objective(y):
        return penalised(problem, crank_of(y[0]), float(y[1]))

    y0 = np.array([math.log(start[0]), start[1]])
    simplex = np.array([y0, y0 + [0.2, 0.0], y0 + [0.0, 0.3]])
    result = minimize(objective, y0, method="Nelder-Mead",
                      options={"xatol": 1e-10, "fatol": 1e-15, "maxfev": 2000, "initial_simplex": simplex})
    y, value = np.array(result.x, dtype=float), float(result.fun)
    state = problem.state(crank_of(y[0]), float(y[1]))
    near_limit = state.feasible and min(problem.constraints(crank_of(y[0]), float(y[1]))) < 1e-4
    if near_limit and value <= state.q + 1e-12:
        # on a limit the exact penalty converges slowly: finish with SLSQP on Q under the limits
        def margins(z):
            b = crank_of(z[0])
            lo, hi = _bounds(problem.limits)
            return np.array([*problem.constraints(b, float(z[1])), b - lo, hi - b])

        def q_of(z):
            st = problem.state(crank_of(z[0]), float(z[1]))
            return st.q if st.feasible else PENALTY

        fine = minimize(q_of, y, method="SLSQP", constraints=[{"type": "ineq", "fun": margins}],
                        options={"ftol": 1e-16, "maxiter": 200})
        if np.all(np.isfinite(fine.x)) and min(margins(fine.x)) >= -1e-12:
            trial = objective(fine.x)
            if trial < value:
                y, value = np.array(fine.x, dtype=float), trial
        state = problem.state(crank_of(y[0]), float(y[1]))
    if polish and len(problem.subsets) == 2 and state.feasible and state.q < 1e-3 and value == state.q:
        def residual(z):
            st = problem.state(crank_of(z[0]), float(z[1]))
            if not st.feasible:
                return np.array([PENALTY, PENALTY])
            gap = st.pivots[1] - st.pivots[0]
            return np.array([gap.real, gap.imag])

        fine = least_squares(residual, y, xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=100)
        trial = objective(fine.x)
        if trial < value:
            y, value = np.array(fine.x, dtype=float), trial
    return np.array([crank_of(y[0]), y[1]]), value


def grid_minima(values: np.ndarray) -> list[tuple[int, int]]:
    """Cells (i, j) of a scan grid (rows: b, columns: α, α periodic) where the pivots exist (value <
    PENALTY/2) and the value is not above any of the 8 neighbours': the discrete local minima, best first.

    Examples
    --------
    >>> v = np.array([[5.0, 4.0, 6.0, 7.0], [8.0, 7.5, 6.5, 6.2], [7.0, 6.6, 6.3, 1.0]])
    >>> grid_minima(v)
    [(2, 3), (0, 1)]
    """
    padded = np.pad(values, ((1, 1), (0, 0)), constant_values=np.inf)
    padded = np.concatenate([padded[:, -1:], padded, padded[:, :1]], axis=1)
    centre = padded[1:-1, 1:-1]
    is_min = centre < PENALTY / 2
    for di in (-1, 0, 1):
        for dj in (-1, 0, 1):
            if di or dj:
                is_min &= centre <= padded[1 + di:padded.shape[0] - 1 + di, 1 + dj:padded.shape[1] - 1 + dj]
    cells = list(zip(*np.nonzero(is_min)))
    return [(int(i), int(j)) for i, j in sorted(cells, key=lambda c: values[c])]


def q_synthesis(target: Target, nodes_phi, limits: Limits, work: Work, grid: tuple[int, int] = (64, 128),
                seed: int = 0, keep: int = 3, pick: str = "centre",
                starts: list[tuple[float, float]] | None = None) -> QResult:
    """The Q method: minimise Q over the free parameters (b, α) under the limits, then pick the pivot.

    Search (camcad's; Sunkuev 1984 asks for nonlinear programming from a good initial mechanism and
    argues that Q makes one cheap to find): Q is evaluated on a grid of ``grid`` = (n_b, n_α) points —
    log b uniform in [1/ratio_max, ratio_max], α in [0, 360°), the whole grid shifted by a random
    fraction of a cell drawn from ``numpy.random.default_rng(seed)`` — at S positions (plus the
    transmission-angle check) per point. A local minimisation (``local_minimum``) starts from each of
    the ``keep`` best discrete local minima of the grid (``grid_minima``);
    the least penalised Q wins, ties (within 1e-9) going to the least maximum deviation on 41 points.
    ``starts`` (b, α rad) replaces the scan by given starts (single local runs). Last step (seed):
    ``pick='centre'`` the centre of the rectangle, ``'search'`` the pivot of least maximum deviation
    inside it.

    Examples
    --------
    A target made by the crank-rocker a = 1, b = 3, c = 2.25, d = 2.5: Q reaches zero and the pivot gives
    the frame length back.

    >>> from camcad.linkage.fgen import nodes
    >>> from camcad.linkage.fourbar import output_angle
    >>> from camcad.linkage.target import make_target
    >>> f = lambda x: output_angle(1.0, 3.0, 2.25, 2.5, 1.0 + x, 1) - output_angle(1.0, 3.0, 2.25, 2.5, 1.0, 1)
    >>> t = make_target(f, 0.0, 1.0, math.degrees(1.0), math.degrees(f(1.0)), "four-bar")
    >>> r = q_synthesis(t, nodes(5, t.dphi), Limits(30.0, 10.0), Work(), grid=(16, 32), keep=2)
    >>> r.state.q < 1e-10, round(r.mechanism.d, 9)
    (True, 2.5)
    """
    problem = QProblem(target, nodes_phi, limits, work)
    lo, hi = _bounds(limits)
    if starts is None:
        rng = np.random.default_rng(seed)
        shift = rng.uniform(0.0, 1.0, 2)
        n_b, n_a = grid
        log_b = math.log(lo) + (np.arange(n_b) + shift[0]) * (math.log(hi) - math.log(lo)) / n_b
        alpha = (np.arange(n_a) + shift[1]) * 2 * math.pi / n_a
        mesh_b, mesh_a = np.meshgrid(np.exp(log_b), alpha, indexing="ij")
        values = problem.penalised_many(mesh_b.ravel(), mesh_a.ravel()).reshape(mesh_b.shape)
        chosen = [(float(mesh_b[i, j]), float(mesh_a[i, j])) for i, j in grid_minima(values)[:keep]]
        samples = values.size
    else:
        chosen = list(starts)
        samples = 0
    if not chosen:
        raise CamcadError("no four-bar within the link-ratio limit has an output pivot through the nodes of this "
                          "target (the Q method's circles never meet): the function may be beyond a four-bar",
                          "--method q", "loosen --ratio-max, change the ranges, or see the best deviation fit with "
                                        "--method lsq")
    runs = []
    best: tuple[Any, ...] | None = None
    check = np.linspace(0.0, target.dphi, 41)
    for start in chosen:
        x, value = local_minimum(problem, start)
        state = problem.state(float(x[0]), float(x[1]))
        dev = math.inf
        if state.mechanism is not None:
            err = structural_error(state.mechanism, target, check, work)
            dev = float(np.max(np.abs(err))) if np.all(np.isfinite(err)) else math.inf
        runs.append({"start_b": start[0], "start_alpha_deg": math.degrees(start[1]), "b": float(x[0]),
                     "alpha_deg": math.degrees(float(x[1])) % 360.0, "q": state.q, "penalised": value,
                     "max_deviation_deg": math.degrees(dev)})
        key = (value, dev)
        if best is None or key[0] < best[0][0] - 1e-9 or (abs(key[0] - best[0][0]) <= 1e-9 and key[1] < best[0][1]):
            best = (key, x, state)
    assert best is not None  # chosen is not empty
    (value, _), x, state = best
    if state.mechanism is None:
        raise CamcadError("the Q method found no admissible mechanism", "--method q",
                          "loosen --mu-min or --ratio-max")
    feasible = bool(value <= state.q + 1e-12)
    mech = _search_pivot(problem, state) if pick == "search" and state.q > 0 else state.mechanism
    message = "limits met" if feasible else "the best Q found violates a limit (penalty > 0)"
    return QResult(state, mech, pick, feasible, samples, runs, message)


def _search_pivot(problem: QProblem, state: QState, points: int = 41) -> FunctionGenerator:
    """Sunkuev 1984's alternative last step: the pivot inside the Q_min rectangle with the least maximum
    deviation on ``points`` points (Nelder–Mead on the rectangle, N positions per trial)."""
    from scipy.optimize import minimize

    xs = [c.real for c in state.pivots]
    ys = [c.imag for c in state.pivots]
    box = (min(xs), max(xs), min(ys), max(ys))
    b_1 = problem.a_points[0] + state.b * cmath.exp(1j * state.alpha)
    phi = np.linspace(0.0, problem.target.dphi, points)

    def mech_at(u):
        cx = box[0] + (box[1] - box[0]) * min(max(u[0], 0.0), 1.0)
        cy = box[2] + (box[3] - box[2]) * min(max(u[1], 0.0), 1.0)
        return from_pivots(problem.a_points[0], b_1, complex(cx, cy), problem.phi[0], problem.psi[0])

    def deviation(u):
        mech = mech_at(u)
        if problem.limits.mu_margin(mech, problem.target, problem.work) < 0:
            return PENALTY
        err = structural_error(mech, problem.target, phi, problem.work)
        return float(np.max(np.abs(err))) if np.all(np.isfinite(err)) else PENALTY

    result = minimize(deviation, np.array([0.5, 0.5]), method="Nelder-Mead",
                      options={"xatol": 1e-6, "fatol": 1e-12, "maxiter": 400})
    best = mech_at(result.x)
    return best if deviation(result.x) <= deviation(np.array([0.5, 0.5])) else mech_at(np.array([0.5, 0.5]))
