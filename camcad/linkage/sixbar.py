"""Six-bar function generator of two four-bars in series, synthesised by the Q method (Sunkuev 1984, ch. 2).

The chain is camcad's six-bar (``camcad.linkage.analysis``): loop 1 O-A-B-C (input crank OA = a, coupler
AB = b, rocker CB = c, frame OC = d) and loop 2 C-D-E-F whose input link CD = e is rigid with CB (the
ternary lever B-C-D, angle κ from CB to CD), coupler DE = f, output link FE = g, frame CF = h. The input
crank stands at θ = θ0 + φ, the output link at β2 = ψ0 + ψ, for the target ψ(φ) of
``camcad.linkage.target``.

The Q method for this chain (Sunkuev 1984, ch. 2: "the set of positions of the fixed pivot found from node
subsets; Q the diagonal of its bounding box; minimise Q, then take the centre") as camcad states it:

- scheme parameters S = 9: loop 1's three ratios b/a, c/a, d/a and its offset θ0 (4), loop 2's three
  ratios and its input offset relative to CF (4), the output offset ψ0 (1). The intermediate angle of the
  lever, χ(φ) = β1(θ0 + φ), is the output of loop 1 and the input of loop 2.
- the last fixed pivot F is the pivot found by interpolation on r = 3 nodes (the four-bar construction of
  ``camcad.linkage.qmethod`` applied to loop 2 with the crank angles χ_k − χ_1 instead of φ_k − φ_1), so
  there are 9 − 3 = 6 free parameters: log b/a, log c/a, log d/a, θ0 of loop 1 (a = 1) and, for loop 2
  with e = 1 and CD along the lever at node 1, log f/e and the coupler's angle α2 to CD at node 1.
- the K = (S − 1)/2 subsets {1,2,3}, {1,4,5}, {1,6,7}, {1,8,9} (``qmethod.node_subsets``) give K positions
  of F; Q is the diagonal of their axis-parallel rectangle, in units of e (loop 2's crank).
- Q is minimised over the six free parameters under the limits (transmission angles of both loops over
  the working range, the largest link ratio of the whole chain) by a seeded random scan (vectorised) and
  Nelder–Mead from the best scan points, the limits entering as penalties of weight ``PENALTY_WEIGHT``
  (camcad's choice of nonlinear-programming method; Sunkuev 1984 names none). The transmission angle of
  loop 2 is taken over the range of χ at the nodes and the two ends in the search; the verdict uses the
  dense grid.
- F is put at the centre of the rectangle (Sunkuev 1984: "for example, in the middle of its diagonal").

The ratios of loop 2 fix the function, not its size: camcad scales loop 2 by s = sqrt(min1 max1 / (min2
max2)) (min, max the shortest and longest link of each loop), which makes the chain's link ratio
max(R1, R2), the least any scale gives. κ does not change the function either (loop 2 turns about C with
the lever); camcad lays the chain out with κ = 180° (D opposite B on a straight lever through C). The
result is scaled to the frame OC asked for.

Source: B. S. Sunkuev, *Optimisation synthesis of adjustable linkages of light-industry machines*, doctoral
abstract, 1984, ch. 2 (the Q objective) and ch. 4 (the six-bar of two four-bars in series).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from itertools import product

import numpy as np
from scipy.optimize import least_squares, minimize

from camcad.errors import CamcadError
from camcad.linkage.analysis import Linkage, Loop
from camcad.linkage.fgen import CHECK_POINTS, DEAD_POINT, Limits, Work, nodes, wrap
from camcad.linkage.fourbar import output_angle
from camcad.linkage.qmethod import circles_meet, node_subsets
from camcad.linkage.target import Target

#: Q of a parameter set whose circles do not meet (crank lengths of loop 2, plus the gap)
PENALTY = 100.0
#: weight of a limit's violation (rad of transmission angle, log of the link ratio) added to Q
PENALTY_WEIGHT = 10.0
#: the free parameters' scan box: link ratios (log-uniform), angles (uniform over a turn)
RATIO_BOX = (0.3, 6.0)
#: κ, the angle from CB to CD on the lever (rad): a straight lever with D opposite B
KAPPA = math.pi
#: the least number of nodes: S = 9 scheme parameters
MIN_NODES = 9


@dataclass
class SixbarOptions:
    """How to synthesise: S nodes (odd, >= 9), spacing, limits, frame OC (mm), accuracy (deg), search size."""

    nodes: int = MIN_NODES
    spacing: str = "chebyshev"
    limits: Limits = field(default_factory=Limits)
    frame_mm: float = 100.0
    max_error_deg: float | None = None
    seed: int = 0
    scan: int = 12000         # random points per branch of loop 1
    starts: int = 40          # Levenberg-Marquardt runs per branch of loop 1 from the best scan points
    keep: int = 6             # pattern searches from the best of those


@dataclass
class SixbarQ:
    """One value of Q: free parameters, F positions (loop-2 frame), rectangle centre, branch, margins."""

    x: np.ndarray
    branch_1: int
    q: float
    feasible: bool
    pivots: list[complex]
    centre: complex
    objective: float
    margins: dict[str, float]


@dataclass
class SixbarResult:
    """A synthesised six-bar: the ``analysis.Linkage`` (mm), ψ0 (rad), its check and the Q details."""

    target: Target
    options: SixbarOptions
    linkage: Linkage
    psi0: float
    nodes_phi: np.ndarray
    q: SixbarQ
    work: Work
    phi: np.ndarray = field(repr=False, default_factory=lambda: np.array([]))
    error: np.ndarray = field(repr=False, default_factory=lambda: np.array([]))
    max_error_deg: float = float("nan")
    rms_error_deg: float = float("nan")
    mu_deg: tuple[float, float] = (float("nan"), float("nan"))
    branch_continuous: bool = False
    verification_positions: int = 0
    runs: int = 0

    @property
    def links(self) -> tuple[float, ...]:
        """a, b, c, d, e, f, g, h (mm)."""
        l1, l2 = self.linkage.loops
        return l1.a, l1.b, l1.c, l1.d, l2.a, l2.b, l2.c, l2.d

    @property
    def mu_min_deg(self) -> float:
        return min(self.mu_deg)

    @property
    def ratio(self) -> float:
        return max(self.links) / min(self.links)

    @property
    def admissible(self) -> bool:
        lim = self.options.limits
        return bool(self.mu_min_deg >= lim.mu_min_deg and self.ratio <= lim.ratio_max and self.branch_continuous)


def _cos_mu_extremes(a, b, c, d, lo, hi):
    """cos μ at the input angles (relative to the frame) where |cos μ| can be largest over [lo, hi]
    (ends, θ ≡ 0, θ ≡ π; ``fourbar.worst_transmission_angle``), for arrays of loops; shape (4, m)."""
    angles = [lo, hi]
    for base in (0.0, math.pi):
        k = np.ceil((lo - base) / (2 * math.pi))
        inside = base + 2 * math.pi * k
        angles.append(np.where(inside <= hi, inside, lo))
    theta = np.stack(angles)
    f2 = a * a + d * d - 2.0 * a * d * np.cos(theta)
    with np.errstate(all="ignore"):
        return (b * b + c * c - f2) / (2.0 * b * c)


def _mu_margin(cos_mu, mu_min_deg: float):
    """Worst min(μ, π − μ) − μ_min (rad) from ``_cos_mu_extremes``; −1 − μ_min where the loop opens."""
    bad = ~np.all(np.abs(cos_mu) <= 1.0, axis=0)
    worst = np.arccos(np.clip(np.max(np.abs(cos_mu), axis=0), 0.0, 1.0))
    margin = worst - math.radians(mu_min_deg)
    return np.where(bad, -1.0 - math.radians(mu_min_deg), margin)


class SixbarProblem:
    """The Q objective of the six-bar for one target, node set and limits (module docstring)."""

    def __init__(self, target: Target, nodes_phi: np.ndarray, limits: Limits, work: Work):
        self.target = target
        self.phi = np.asarray(nodes_phi, dtype=float)
        self.count = len(self.phi)
        self.subsets = node_subsets(self.count)
        self.psi = np.asarray(target.psi(self.phi), dtype=float)
        self.rot = np.exp(1j * (self.psi - self.psi[0]))
        # the nodes and the two ends of the working range
        self.phi_all = np.concatenate([self.phi, [0.0, target.dphi]])
        self.limits = limits
        self.work = work

    def evaluate(self, x: np.ndarray, branch_1: int) -> dict[str, np.ndarray]:
        """Q (penalised) for an (m, 6) array of free parameters on loop-1 branch ``branch_1``; counts S + 2
        positions of loop 1 and S of loop 2 per point."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        m = x.shape[0]
        self.work.positions += (2 * self.count + 2) * m
        self.work.objective_evaluations += m
        b1, c1, d1 = np.exp(x[:, 0]), np.exp(x[:, 1]), np.exp(x[:, 2])
        th0, b2, al2 = x[:, 3], np.exp(x[:, 4]), x[:, 5]
        col = (slice(None), None)
        chi_all = output_angle(1.0, b1[col], c1[col], d1[col], th0[col] + self.phi_all[None, :], branch_1)
        closed = np.all(np.isfinite(chi_all), axis=1)
        chi_all = np.where(np.isfinite(chi_all), chi_all, 0.0)
        chi = chi_all[:, :self.count]
        # loop 2 in its frame: C at the origin, CD = 1 along +x at node 1, D_k = e^{i(χ_k - χ_1)}
        d_pts = np.exp(1j * (chi - chi[:, :1]))
        e_1 = d_pts[:, 0] + b2 * np.exp(1j * al2)
        centres = {k: (d_pts[:, k] - self.rot[k] * e_1) / (1 - self.rot[k]) for k in range(1, self.count)}
        radii = {k: b2 / abs(1 - self.rot[k]) for k in range(1, self.count)}

        def side(f_pt, k):
            e_k = f_pt + self.rot[k] * (e_1 - f_pt)
            return np.sign(((d_pts[:, k] - f_pt).conj() * (e_k - f_pt)).imag)

        cands, gaps = [], np.zeros(m)
        for subset in self.subsets:
            i, j = subset[1] - 1, subset[2] - 1
            meet, base, offset, gap = circles_meet(centres[i], radii[i], centres[j], radii[j])
            gaps += gap
            pair = []
            for sign in (1.0, -1.0):
                f_pt = np.where(meet, base + sign * offset, 0.0)
                signs = [side(f_pt, k - 1) for k in subset]
                ok = meet & (signs[0] == signs[1]) & (signs[0] == signs[2]) & (signs[0] != 0)
                pair.append((f_pt, ok, signs[0]))
            cands.append(pair)
        best_q = np.full(m, np.inf)
        best_centre = np.zeros(m, dtype=complex)
        best_pick = np.zeros((m, len(self.subsets)), dtype=complex)
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
            best_pick = np.where(better[:, None], np.stack([p[0] for p in picked], axis=1), best_pick)
        found = np.isfinite(best_q) & closed
        # limits of the centre mechanism
        lo1 = th0 + min(0.0, self.target.dphi)
        hi1 = th0 + max(0.0, self.target.dphi)
        mu1 = _mu_margin(_cos_mu_extremes(1.0, b1, c1, d1, lo1, hi1), self.limits.mu_min_deg)
        g = np.abs(e_1 - best_centre)
        h_len = np.abs(best_centre)
        eps2 = np.angle(best_centre)
        rel = chi_all - chi[:, :1] - eps2[:, None]          # loop 2's input angle relative to CF
        mu2 = _mu_margin(_cos_mu_extremes(1.0, b2, g, h_len, rel.min(1), rel.max(1)), self.limits.mu_min_deg)
        with np.errstate(all="ignore"):
            r1 = np.maximum.reduce([np.ones(m), b1, c1, d1]) / np.minimum.reduce([np.ones(m), b1, c1, d1])
            r2 = np.maximum.reduce([np.ones(m), b2, g, h_len]) / np.minimum.reduce([np.ones(m), b2, g, h_len])
            ratio = math.log(self.limits.ratio_max) - np.log(np.maximum(r1, r2))
        ratio = np.where(np.isfinite(ratio), ratio, -10.0)
        pen = PENALTY_WEIGHT * (np.maximum(0.0, -mu1) + np.maximum(0.0, -mu2) + np.maximum(0.0, -ratio))
        objective = np.where(found, best_q + pen, PENALTY + gaps + (~closed) * PENALTY)
        return {"objective": objective, "q": best_q, "found": found, "centre": best_centre, "pivots": best_pick,
                "mu1": mu1, "mu2": mu2, "ratio": ratio, "g": g}

    def state(self, x: np.ndarray, branch_1: int) -> SixbarQ:
        """``evaluate`` for one parameter vector, as a ``SixbarQ``."""
        out = self.evaluate(np.asarray(x)[None, :], branch_1)
        found = bool(out["found"][0])
        margins = {"mu_loop1_rad": float(out["mu1"][0]), "mu_loop2_rad": float(out["mu2"][0]),
                   "ratio_log": float(out["ratio"][0])}
        return SixbarQ(np.asarray(x, dtype=float), branch_1, float(out["q"][0]) if found else float("inf"), found,
                       list(out["pivots"][0]) if found else [], complex(out["centre"][0]),
                       float(out["objective"][0]), margins)


def pattern_search(problem: SixbarProblem, x: np.ndarray, branch_1: int, rng: np.random.Generator,
                   step: float = 0.3, iterations: int = 2500, tol: float = 1e-10) -> tuple[np.ndarray, np.ndarray]:
    """Local minima of the penalised Q from the rows of ``x`` (one start each, all on ``branch_1``): a
    pattern search run for every start at once (one vectorised call per iteration): the ± coordinate
    steps and 12 random directions of the current step length; a success doubles the step, a failure
    halves it; it ends when every step is below ``tol``."""
    x = np.array(x, dtype=float)
    k, n = x.shape
    f = problem.evaluate(x, branch_1)["objective"]
    steps = np.full(k, step)
    eye = np.vstack([np.eye(n), -np.eye(n)])
    for _ in range(iterations):
        live = steps > tol
        if not live.any():
            break
        rand = rng.normal(size=(12, n))
        dirs = np.vstack([eye, rand / np.linalg.norm(rand, axis=1, keepdims=True)])
        trial = x[:, None, :] + steps[:, None, None] * dirs[None, :, :]
        ft = problem.evaluate(trial.reshape(-1, n), branch_1)["objective"].reshape(k, -1)
        pick = np.argmin(ft, axis=1)
        fbest = ft[np.arange(k), pick]
        better = live & (fbest < f)
        x = np.where(better[:, None], trial[np.arange(k), pick], x)
        f = np.where(better, fbest, f)
        steps = np.where(better, np.minimum(2 * steps, 1.0), np.where(live, steps / 2, steps))
    return x, f


def residuals(problem: SixbarProblem, x: np.ndarray, branch_1: int) -> np.ndarray:
    """For an (m, 6) array of free parameters: the differences F_j − F_1 (real and imaginary parts) between
    the pivots of subset j and of subset 1 (all zero exactly when Q = 0) and the limits' violations times
    sqrt(``PENALTY_WEIGHT``); ``PENALTY`` where a subset gives no pivot. Shape (m, 2(K − 1) + 3)."""
    out = problem.evaluate(x, branch_1)
    piv = out["pivots"]
    diff = piv[:, 1:] - piv[:, :1]
    viol = math.sqrt(PENALTY_WEIGHT) * np.maximum(0.0, -np.column_stack([out["mu1"], out["mu2"], out["ratio"]]))
    res = np.column_stack([diff.real, diff.imag, viol])
    return np.where(out["found"][:, None], res, PENALTY)


def close_nodes(problem: SixbarProblem, x0: np.ndarray, branch_1: int, evaluations: int = 30) -> np.ndarray:
    """Drive the K pivots of F together from ``x0`` by Levenberg–Marquardt on ``residuals`` (6 equations in
    the 6 free parameters: a six-bar that interpolates on all S nodes when they meet), the Jacobian by
    forward differences in one vectorised call; at most ``evaluations`` residual evaluations."""
    n = len(x0)
    step = 1e-7

    def fun(y):
        return residuals(problem, y[None, :], branch_1)[0]

    def jac(y):
        pts = y[None, :] + step * np.vstack([np.zeros(n), np.eye(n)])
        r = residuals(problem, pts, branch_1)
        return (r[1:] - r[0]).T / step

    res = least_squares(fun, x0, jac=jac, method="trf", xtol=1e-14, ftol=1e-14, gtol=1e-14,
                        max_nfev=evaluations)
    return res.x


def search(problem: SixbarProblem, options: SixbarOptions) -> tuple[SixbarQ, int]:
    """Minimise the penalised Q: a random scan of ``options.scan`` points per branch of loop 1; from the best
    ``options.starts`` of each branch the pivots driven together (``close_nodes``); a pattern search on Q
    from the ``options.keep`` best of those (``pattern_search``) and Nelder–Mead from the best. Returns the
    best state and the number of local runs."""
    rng = np.random.default_rng(options.seed)
    lo, hi = (math.log(v) for v in RATIO_BOX)
    found = []
    runs = 0
    for branch_1 in (1, -1):
        x = np.column_stack([rng.uniform(lo, hi, options.scan), rng.uniform(lo, hi, options.scan),
                             rng.uniform(lo, hi, options.scan), rng.uniform(0, 2 * math.pi, options.scan),
                             rng.uniform(lo, hi, options.scan), rng.uniform(0, 2 * math.pi, options.scan)])
        obj = problem.evaluate(x, branch_1)["objective"]
        for k in np.argsort(obj)[:options.starts]:
            runs += 1
            y = close_nodes(problem, x[k], branch_1)
            fy = float(problem.evaluate(y[None, :], branch_1)["objective"][0])
            found.append((fy, y, branch_1) if fy < obj[k] else (float(obj[k]), x[k], branch_1))
    found.sort(key=lambda s: s[0])
    best = found[:options.keep]
    polished = []
    for branch_1 in (1, -1):
        group = [xv for _, xv, br in best if br == branch_1]
        if group:
            runs += len(group)
            xs, fs = pattern_search(problem, np.array(group), branch_1, rng)
            polished += [(float(fv), xv, branch_1) for fv, xv in zip(fs, xs)]
    polished.sort(key=lambda s: s[0])
    _, x0, branch_1 = polished[0]

    def fun(y, br=branch_1):
        return float(problem.evaluate(y[None, :], br)["objective"][0])

    res = minimize(fun, x0, method="Nelder-Mead",
                   options={"maxfev": 1500, "xatol": 1e-12, "fatol": 1e-15, "adaptive": True})
    st = problem.state(res.x if res.fun <= fun(x0) else x0, branch_1)
    return st, runs + 1


def build(problem: SixbarProblem, st: SixbarQ, frame_mm: float) -> tuple[Linkage, float]:
    """The six-bar (``analysis.Linkage``, mm, OC = ``frame_mm``) of a Q state with F at the rectangle's centre,
    and ψ0 (rad) that makes node 1 exact."""
    b1, c1, d1 = (math.exp(v) for v in st.x[:3])
    th0, b2, al2 = float(st.x[3]), math.exp(st.x[4]), float(st.x[5])
    loop1 = Loop((0.0, 0.0), (d1, 0.0), 1.0, b1, c1, st.branch_1)
    chi_1 = float(loop1.output(th0 + problem.phi[0]))
    e_1 = 1.0 + b2 * complex(math.cos(al2), math.sin(al2))
    f_loc = st.centre
    g, h = abs(e_1 - f_loc), abs(f_loc)
    l1 = (1.0, b1, c1, d1)
    l2 = (1.0, b2, g, h)
    s = math.sqrt(min(l1) * max(l1) / (min(l2) * max(l2)))
    k = frame_mm / d1
    turn = complex(math.cos(chi_1 + KAPPA), math.sin(chi_1 + KAPPA))   # loop 2's frame in absolute axes
    c_abs = complex(d1, 0.0)
    f_abs = c_abs + s * f_loc * turn
    e_abs = c_abs + s * e_1 * turn
    loop2 = Loop((k * d1, 0.0), (k * f_abs.real, k * f_abs.imag), k * s, k * s * b2, k * s * g, 1)
    loop2 = loop2.with_branch_through(chi_1 + KAPPA, k * e_abs)
    loop1 = Loop((0.0, 0.0), (k * d1, 0.0), k, k * b1, k * c1, st.branch_1)
    sense = 1 if problem.target.dphi > 0 else -1
    linkage = Linkage((loop1, loop2), theta0=th0, input_sense=sense, couplings=(KAPPA,))
    beta2_1 = float(loop2.output(chi_1 + KAPPA))
    return linkage, beta2_1 - float(problem.psi[0])


def output(linkage: Linkage, phi) -> np.ndarray:
    """β2 (rad), the output link's absolute angle, at input coordinates φ (rad, signed as the target's)."""
    loop1, loop2 = linkage.loops
    theta = linkage.theta0 + np.asarray(phi, dtype=float)
    return np.asarray(loop2.output(np.asarray(loop1.output(theta)) + linkage.couplings[0]))


def check(result: SixbarResult, points: int = CHECK_POINTS) -> None:
    """Fill the dense-grid check of ``result``: structural error, transmission angle of each loop over its
    input range (closed form over the grid's range), branch continuity (no NaN, no dead point, no step of
    an output angle above 1.5 max|β'| h)."""
    lk, t = result.linkage, result.target
    loop1, loop2 = lk.loops
    phi = np.linspace(0.0, t.dphi, points)
    theta1 = lk.theta0 + phi
    chi, d_chi = loop1.derivatives(theta1, order=1)[:2]
    theta2 = np.asarray(chi) + lk.couplings[0]
    beta2, d_beta2 = loop2.derivatives(theta2, order=1)[:2]
    err = wrap(beta2 - result.psi0 - t.psi(phi))
    result.verification_positions = 2 * points
    h = abs(phi[1] - phi[0])
    finite = bool(np.all(np.isfinite(err)) and np.all(np.isfinite(d_chi)) and np.all(np.isfinite(d_beta2)))
    mu1 = loop1.worst_transmission(float(theta1.min()), float(theta1.max()))
    mu2 = loop2.worst_transmission(float(np.nanmin(theta2)), float(np.nanmax(theta2))) if finite else float("nan")
    continuous = finite and all(math.isfinite(v) and v > DEAD_POINT for v in (mu1, mu2))
    if continuous:
        for ang, der in ((chi, d_chi), (beta2, d_beta2 * d_chi)):
            steps = np.abs(wrap(np.diff(ang)))
            continuous &= bool(steps.max() <= 1.5 * np.max(np.abs(der)) * h + 1e-15)
    result.phi, result.error = phi, err
    result.max_error_deg = math.degrees(float(np.max(np.abs(err)))) if finite else float("inf")
    result.rms_error_deg = (math.degrees(float(np.sqrt(np.trapezoid(err ** 2, phi) / (phi[-1] - phi[0]))))
                            if finite else float("inf"))
    result.mu_deg = (math.degrees(mu1), math.degrees(mu2))
    result.branch_continuous = bool(continuous)


def check_options(options: SixbarOptions) -> None:
    """Refuse what the six-bar Q method cannot do (one line, exit 2)."""
    if options.nodes < MIN_NODES:
        raise CamcadError(f"the six-bar Q method needs S >= {MIN_NODES} nodes (the six-bar has S = 9 scheme "
                          f"parameters), got {options.nodes}", "--nodes", "give --nodes 9 (or 11, 13, ...)")
    node_subsets(options.nodes)
    if options.spacing not in ("chebyshev", "uniform"):
        raise CamcadError(f"unknown spacing {options.spacing!r}", "--spacing", "use chebyshev or uniform")
    if not (options.frame_mm > 0 and math.isfinite(options.frame_mm)):
        raise CamcadError(f"--frame {options.frame_mm:g} mm must be positive", "--frame", "give the frame length in mm")


def synthesize_sixbar(target: Target, options: SixbarOptions | None = None) -> SixbarResult:
    """Synthesise a six-bar function generator (two four-bars in series) for ``target`` by Sunkuev 1984's
    Q method: the last pivot F from node subsets, Q the diagonal of their rectangle, minimised under the
    transmission-angle and link-ratio limits, F at the centre (module docstring).

    Parameters
    ----------
    target : Target
        ψ(φ) (``camcad.linkage.target.make_target``; ranges in deg).
    options : SixbarOptions, optional
        S nodes (odd, >= 9), spacing, limits (deg, ratio), frame OC (mm), seed and search size.

    Returns
    -------
    SixbarResult
        The linkage (mm, ``analysis.Linkage`` of two loops), ψ0 (rad), the max and RMS structural error (deg),
        the worst transmission angle of each loop (deg), the Q state and the position count.

    References
    ----------
    B. S. Sunkuev, doctoral abstract, 1984, ch. 2 (the Q objective) and ch. 4 (two four-bars in series).

    Examples
    --------
    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> r = synthesize_sixbar(t, SixbarOptions(scan=2000, keep=2))
    >>> len(r.linkage.loops), round(r.linkage.loops[0].d, 6), r.max_error_deg < 0.9
    (2, 100.0, True)
    """
    options = options or SixbarOptions()
    check_options(options)
    work = Work()
    node_phi = nodes(options.nodes, target.dphi, options.spacing)
    problem = SixbarProblem(target, node_phi, options.limits, work)
    st, runs = search(problem, options)
    if not st.feasible:
        raise CamcadError(f"the six-bar Q search found no parameter set whose {len(problem.subsets)} node subsets "
                          "all give a pivot F", "--chain sixbar",
                          "try another --seed, fewer --nodes, or a smaller --input-range/--output-range")
    linkage, psi0 = build(problem, st, options.frame_mm)
    result = SixbarResult(target, options, linkage, psi0, node_phi, st, work, runs=runs)
    check(result)
    return result


def error_tolerance(options: SixbarOptions, target: Target) -> float:
    """The largest structural error (deg) the verdict allows: ``max_error_deg``, else 1 % of |output range|
    (as ``fgen``)."""
    if options.max_error_deg is not None:
        return float(options.max_error_deg)
    return 0.01 * abs(target.output_range_deg)


def _check(value: float, limit: float, margin: float, passed: bool, why: str) -> dict:
    out = {"value": value, "limit": limit, "margin": margin, "passed": passed, "why": why}
    if passed and abs(margin) <= 1e-6 * abs(limit):
        out["note"] = "at its limit (the optimisation holds it there): no reserve"
    return out


def report(result: SixbarResult) -> dict:
    """The JSON of a six-bar synthesis: ``fgen``'s keys (``links`` are loop 1's a, b, c, d) plus ``chain``,
    ``links_2`` (e = CD, f = DE, g = FE, h = CF, mm), ``mu_loop_deg``, ``pivots`` and ``analyse_options``
    (the options of ``camcad linkage analyse`` that rebuild the chain).

    Examples
    --------
    >>> from camcad.linkage.target import make_target
    >>> t = make_target(np.log10, 1.0, 2.0, 60.0, 90.0, "log10(x)")
    >>> out = report(synthesize_sixbar(t, SixbarOptions(scan=2000, keep=2)))
    >>> out["chain"], sorted(out["links_2"]), len(out["nodes_deg"])
    ('sixbar', ['e', 'f', 'g', 'h'], 9)
    """
    lk, t, o = result.linkage, result.target, result.options
    loop1, loop2 = lk.loops
    a, b, c, d, e, f, g, h = result.links
    tolerance = error_tolerance(o, t)
    lim = o.limits
    ratio = result.ratio
    mu = result.mu_min_deg
    checks = {
        "transmission_angle": _check(mu, lim.mu_min_deg, mu - lim.mu_min_deg, bool(mu >= lim.mu_min_deg),
                                     "smallest min(mu, 180 - mu) of both loops over their input ranges (deg), closed "
                                     "form"),
        "link_ratio": _check(ratio, lim.ratio_max, lim.ratio_max - ratio, bool(ratio <= lim.ratio_max),
                             "longest / shortest of the 8 links"),
        "branch": {"value": float(result.branch_continuous), "limit": 1.0,
                   "margin": float(result.branch_continuous) - 1.0, "passed": result.branch_continuous, "why":
                   f"1 when both loops close on {len(result.phi)} grid points, no dead point, no output step above "
                         "1.5 max|dbeta/dtheta| h: no jump to the other assembly branch"},
        "max_error": _check(result.max_error_deg, tolerance, tolerance - result.max_error_deg,
                            bool(result.max_error_deg <= tolerance),
                            "largest |structural error| (deg) against " + (
                                "--max-error" if o.max_error_deg is not None else
                                "1 % of the output range (the default; set --max-error)")),
    }
    node_err = wrap(output(lk, result.nodes_phi) - result.psi0 - t.psi(result.nodes_phi))
    err_deg = np.degrees(result.error)
    ext = [0] + [k for k in range(1, len(err_deg) - 1)
                 if (err_deg[k] - err_deg[k - 1]) * (err_deg[k + 1] - err_deg[k]) < 0] + [len(err_deg) - 1]
    st = result.q
    xs = [p.real for p in st.pivots]
    ys = [p.imag for p in st.pivots]
    joints = lk.joints(0.0)
    return {
        "method": "q",
        "chain": "sixbar",
        "function": t.label,
        "x": [t.x0, t.x1],
        "input_range_deg": t.input_range_deg,
        "output_range_deg": t.output_range_deg,
        "links": {"a": a, "b": b, "c": c, "d": d},
        "links_2": {"e": e, "f": f, "g": g, "h": h},
        "link_names": {"a": "input crank OA", "b": "coupler AB", "c": "lever arm CB", "d": "frame OC",
                       "e": "lever arm CD", "f": "coupler DE", "g": "output rocker FE", "h": "frame CF"},
        "pivots": {name: [float(complex(joints[name]).real), float(complex(joints[name]).imag)]
                   for name in ("O", "C", "F")},
        "coupling_2_deg": math.degrees(lk.couplings[0]),
        "offsets_deg": {"phi0": math.degrees(lk.theta0) % 360.0, "psi0": math.degrees(result.psi0) % 360.0},
        "branch": loop1.branch,
        "branch_2": loop2.branch,
        "max_error_deg": result.max_error_deg,
        "rms_error_deg": result.rms_error_deg,
        "mu_min_deg": mu,
        "mu_loop_deg": list(result.mu_deg),
        "link_ratio": ratio,
        "position_evaluations": result.work.positions,
        "position_breakdown": {"q": result.work.positions},
        "objective_evaluations": result.work.objective_evaluations,
        "verification_positions": result.verification_positions,
        "nodes_deg": [math.degrees(v) for v in result.nodes_phi],
        "node_errors_deg": [float(v) for v in np.degrees(node_err)],
        "nodes_x": [float(v) for v in t.x_of(result.nodes_phi)],
        "spacing": o.spacing,
        "constrained": True,
        "admissible": result.admissible,
        "max_error_tolerance_deg": tolerance,
        "error_extrema": [{"phi_deg": math.degrees(float(result.phi[k])), "error_deg": float(err_deg[k])}
                          for k in ext],
        "q": {"value": st.q, "unit": "lengths of loop 2's input arm CD (e = 1 during the search)",
              "nodes": len(result.nodes_phi), "subsets": node_subsets(len(result.nodes_phi)),
              "free_parameters": {"b_over_a": math.exp(st.x[0]), "c_over_a": math.exp(st.x[1]),
                                  "d_over_a": math.exp(st.x[2]), "theta0_deg": math.degrees(st.x[3]) % 360.0,
                                  "f_over_e": math.exp(st.x[4]), "alpha2_deg": math.degrees(st.x[5]) % 360.0},
              "pivots_F": [[p.real, p.imag] for p in st.pivots],
              "rectangle": {"x": [min(xs), max(xs)], "y": [min(ys), max(ys)]},
              "pick": "centre", "limits_met": bool(min(st.margins.values()) >= 0), "scan_points": 2 * o.scan,
              "pivot_closing_runs": 2 * o.starts,
              "local_runs": result.runs},
        "analyse_options": {
            "pivot": "0,0", "output_pivot": f"{d:.6g},0", "links": f"{a:.6g},{b:.6g},{c:.6g}",
            "input_angle": math.degrees(lk.theta0), "sense": lk.input_sense, "branch": loop1.branch,
            "output_pivot_2": f"{loop2.q[0]:.6g},{loop2.q[1]:.6g}", "links_2": f"{e:.6g},{f:.6g},{g:.6g}",
            "coupling_2": math.degrees(lk.couplings[0]), "branch_2": loop2.branch},
        "checks": checks,
        "passed": all(ch["passed"] for ch in checks.values()),
        "notes": [f"six-bar Q method: S = {len(result.nodes_phi)} nodes, the last pivot F from "
                  f"{len(st.pivots)} subsets, 6 free parameters (camcad's formulation, docs/linkage.md)"],
    }
