"""One adjustable six-bar for a family of position functions ψ = F⁽ʲ⁾(φ), j = 1 … p (Sunkuev 1984, ch. 4, Fig. 6).

Sunkuev 1984 (ch. 4, "В регулируемом шестизвеннике (рис. 6) искомыми являются параметры схемы a1 … a10 и
дискретные значения x1⁽ʲ⁾"): with the free parameters given, the algorithm of ch. 2 for the six-bar gives, for
each member j, the positions C₁ᵢ⁽ʲ⁾ of the adjustable joint from its node subsets; Q⁽ʲ⁾ is the diagonal of their
rectangle; stage 1 minimises Q = Σ_j Q⁽ʲ⁾; the centres C⁽ʲ⁾ of the rectangles are the joint's positions at the
settings; stage 2 draws the circle through C⁽¹⁾ … C⁽³⁾: its centre is the fixed pivot of the adjusting link, and
the settings x1⁽ʲ⁾ follow.

camcad's reading (the OCR does not show Fig. 6): the chain is ``camcad.linkage.sixbar``'s (two four-bars in
series) and the adjustable joint is the output pivot F of loop 2, moved along an arc about a fixed pivot G between
settings (Sunkuev's C). The members share loop 1, the lever, the coupler DE and the output rocker FE; each member
has its own coupler angle α2⁽ʲ⁾ at node 1 (its output offset ψ0⁽ʲ⁾ is free, as in "φ = k⁽ʲ⁾ψ + φ0⁽ʲ⁾ with φ0⁽ʲ⁾
sought"). F⁽ʲ⁾ is found from three-node subsets as in ``sixbar`` (S nodes per member, odd, >= 5). The rocker
length g⁽ʲ⁾ = |E₁⁽ʲ⁾ − F⁽ʲ⁾| the Q construction gives differs between members unless the family is right, so
the objective is Σ_j Q⁽ʲ⁾ plus camcad's addition, the spread max g⁽ʲ⁾ − min g⁽ʲ⁾ (one mechanism has one rocker;
``camcad.linkage.family`` does the same for the four-bar), plus the limits' penalties of each member. Search: a
seeded random scan, Levenberg–Marquardt on the residuals (F differences of every member and g⁽ʲ⁾ − g⁽¹⁾: zero for a
family one adjustable six-bar generates), Nelder–Mead on the objective. The members must share the input range.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares, minimize

from camcad.errors import CamcadError
from camcad.linkage.analysis import Linkage, Loop
from camcad.linkage.family import fit_circle
from camcad.linkage.fgen import Limits, Work, nodes
from camcad.linkage.sixbar import (
    KAPPA,
    RATIO_BOX,
    SixbarOptions,
    SixbarProblem,
    SixbarQ,
    SixbarResult,
    check,
)
from camcad.linkage.target import Target


@dataclass
class SixbarFamilyResult:
    """The adjustable six-bar: one ``SixbarResult`` per member (its setting's linkage, mm), the arc of F (centre G,
    radius, mm), the settings (rad, angle of GF), Σ Q, the spread of the rocker lengths, the work done."""

    members: list[SixbarResult]
    arc_centre: complex
    arc_radius: float
    arc_residual: float
    settings: list[float]
    q_sum: float
    g_spread: float
    work: Work
    notes: list[str] = field(default_factory=list)

    @property
    def max_error_deg(self) -> float:
        return max(m.max_error_deg for m in self.members)

    @property
    def mu_min_deg(self) -> float:
        return min(m.mu_min_deg for m in self.members)


class FamilyProblem:
    """Σ Q⁽ʲ⁾ + spread of g⁽ʲ⁾ + penalties for the shared parameters and the members' α2⁽ʲ⁾ (module docstring)."""

    def __init__(self, targets: list[Target], count: int, spacing: str, limits: Limits, work: Work):
        self.problems = [SixbarProblem(t, nodes(count, t.dphi, spacing), limits, work)
                         for t in targets]
        self.p = len(targets)

    def _split(self, y: np.ndarray, j: int) -> np.ndarray:
        return np.column_stack([y[:, :5], y[:, 5 + j]])

    def parts(self, y: np.ndarray, branch_1: int) -> list[dict]:
        y = np.atleast_2d(y)
        return [prob.evaluate(self._split(y, j), branch_1) for j, prob in enumerate(self.problems)]

    def objective(self, y: np.ndarray, branch_1: int) -> np.ndarray:
        outs = self.parts(y, branch_1)
        total = np.sum([o["objective"] for o in outs], axis=0)
        g = np.array([o["g"] for o in outs])
        found = np.logical_and.reduce([o["found"] for o in outs])
        return total + np.where(found, g.max(0) - g.min(0), 0.0)

    def residuals(self, y: np.ndarray, branch_1: int) -> np.ndarray:
        outs = self.parts(y, branch_1)
        cols = []
        for o in outs:
            diff = o["pivots"][:, 1:] - o["pivots"][:, :1]
            cols += [diff.real, diff.imag, 3.0 * np.maximum(0.0, -np.column_stack([o["mu1"], o["mu2"]]))]
        g = np.array([o["g"] for o in outs])
        cols.append((g[1:] - g[:1]).T)
        res = np.column_stack(cols)
        found = np.logical_and.reduce([o["found"] for o in outs])
        return np.where(found[:, None], res, 100.0)


def synthesize_sixbar_family(targets: list[Target], count: int = 5, options: SixbarOptions | None = None,
                             starts: int = 40, scan: int = 20000) -> SixbarFamilyResult:
    """Synthesise one adjustable six-bar (the output pivot F on an arc) for the family ``targets`` by Sunkuev
    1984's two stages (module docstring): stage 1 Σ Q⁽ʲ⁾ (+ the rocker-length spread), stage 2 the circle through
    F⁽¹⁾ … F⁽ᵖ⁾.

    Parameters
    ----------
    targets : list of Target
        Three or more members sharing the input range (deg).
    count : int
        S nodes per member (odd, >= 5).
    options : SixbarOptions, optional
        Spacing, limits, frame OC (mm), seed (``nodes`` is ``count``).
    starts, scan : int
        Levenberg–Marquardt runs per branch of loop 1 from the best of ``scan`` random points.

    Returns
    -------
    SixbarFamilyResult
        Each member's six-bar (mm) with its error (deg) and transmission angles, the arc (mm), the settings (rad).

    Examples
    --------
    >>> from camcad.linkage.target import make_target
    >>> fam = [make_target(lambda x, k=k: k * x, 0.0, 60.0, 60.0, 60.0 * k, f"{k}x") for k in (0.5, 0.55, 0.6)]
    >>> r = synthesize_sixbar_family(fam, starts=5, scan=2000)
    >>> len(r.members), len(r.settings)
    (3, 3)
    """
    options = options or SixbarOptions()
    if len(targets) < 3:
        raise CamcadError(f"a family needs three or more members, got {len(targets)}", "family",
                          "give three or more members")
    if len({round(t.input_range_deg, 9) for t in targets}) != 1:
        raise CamcadError("the members' input ranges differ", "family", "give every member the same input range")
    if count < 5 or count % 2 == 0:
        raise CamcadError(f"{count} nodes per member: need an odd number >= 5", "--nodes", "give --nodes 5 (or 7, 9)")
    work = Work()
    fam = FamilyProblem(targets, count, options.spacing, options.limits, work)
    rng = np.random.default_rng(options.seed)
    lo, hi = (math.log(v) for v in RATIO_BOX)
    n = 5 + fam.p
    found = []
    for branch_1 in (1, -1):
        y = np.column_stack([rng.uniform(lo, hi, (scan, 3)), rng.uniform(0, 2 * math.pi, scan),
                             rng.uniform(lo, hi, scan), rng.uniform(0, 2 * math.pi, (scan, fam.p))])
        obj = fam.objective(y, branch_1)
        for k in np.argsort(obj)[:starts]:
            def fun(v, br=branch_1):
                return fam.residuals(v[None, :], br)[0]

            def jac(v, br=branch_1):
                pts = v[None, :] + 1e-7 * np.vstack([np.zeros(n), np.eye(n)])
                r = fam.residuals(pts, br)
                return (r[1:] - r[0]).T / 1e-7

            res = least_squares(fun, y[k], jac=jac, method="trf", xtol=1e-14, ftol=1e-14, gtol=1e-14, max_nfev=40)
            fy = float(fam.objective(res.x[None, :], branch_1)[0])
            found.append((fy, res.x, branch_1) if fy < obj[k] else (float(obj[k]), y[k], branch_1))
    found.sort(key=lambda s: s[0])
    _, y0, branch_1 = found[0]
    nm = minimize(lambda v: float(fam.objective(v[None, :], branch_1)[0]), y0, method="Nelder-Mead",
                  options={"maxfev": 2000, "xatol": 1e-12, "fatol": 1e-15, "adaptive": True})
    y_best = nm.x if nm.fun <= fam.objective(y0[None, :], branch_1)[0] else y0
    outs = fam.parts(y_best[None, :], branch_1)
    if not all(bool(o["found"][0]) for o in outs):
        raise CamcadError("the six-bar family search found no parameter set where every member's subsets give a "
                          "pivot F", "family", "try another --seed or members closer to each other")
    g = [float(o["g"][0]) for o in outs]
    centres = [complex(o["centre"][0]) for o in outs]
    q_sum = float(sum(o["q"][0] for o in outs))
    # stage 2: the circle through the members' pivots F (loop 2's frame, CD = 1 along the lever at node 1)
    g_loc, radius_loc, residual_loc = fit_circle(centres)
    b1, c1, d1 = (math.exp(v) for v in y_best[:3])
    th0, f_len = float(y_best[3]), math.exp(y_best[4])
    g_mean = float(np.mean(g))
    lengths1 = (1.0, b1, c1, d1)
    lengths2 = (1.0, f_len, g_mean, *[abs(c) for c in centres], radius_loc)
    s = math.sqrt(min(lengths1) * max(lengths1) / (min(lengths2) * max(lengths2)))
    k = options.frame_mm / d1
    loop1 = Loop((0.0, 0.0), (k * d1, 0.0), k, k * b1, k * c1, branch_1)
    phi_1 = fam.problems[0].phi[0]
    chi_1 = float(Loop((0.0, 0.0), (d1, 0.0), 1.0, b1, c1, branch_1).output(th0 + phi_1))
    turn = complex(math.cos(chi_1 + KAPPA), math.sin(chi_1 + KAPPA))
    c_abs = complex(d1, 0.0)

    def absolute(z: complex) -> complex:
        return k * (c_abs + s * z * turn)

    members = []
    settings = []
    arc_centre = absolute(g_loc)
    sense = 1 if targets[0].dphi > 0 else -1
    for j, (t, prob, out) in enumerate(zip(targets, fam.problems, outs)):
        al2 = float(y_best[5 + j])
        e_1 = 1.0 + f_len * complex(math.cos(al2), math.sin(al2))
        f_abs = absolute(centres[j])
        loop2 = Loop((k * d1, 0.0), (f_abs.real, f_abs.imag), k * s, k * s * f_len, k * s * g_mean, 1)
        loop2 = loop2.with_branch_through(chi_1 + KAPPA, absolute(e_1))
        lk = Linkage((loop1, loop2), theta0=th0, input_sense=sense, couplings=(KAPPA,))
        beta2_1 = float(loop2.output(chi_1 + KAPPA))
        st = SixbarQ(np.concatenate([y_best[:5], [al2]]), branch_1, float(out["q"][0]), True,
                     list(out["pivots"][0]), centres[j], float(out["objective"][0]),
                     {"mu_loop1_rad": float(out["mu1"][0]), "mu_loop2_rad": float(out["mu2"][0]),
                      "ratio_log": float(out["ratio"][0])})
        opts = SixbarOptions(nodes=count, spacing=options.spacing, limits=options.limits, frame_mm=options.frame_mm,
                             max_error_deg=options.max_error_deg, seed=options.seed)
        result = SixbarResult(t, opts, lk, beta2_1 - float(prob.psi[0]), prob.phi, st, work)
        check(result)
        members.append(result)
        settings.append(math.atan2((f_abs - arc_centre).imag, (f_abs - arc_centre).real))
    return SixbarFamilyResult(members, arc_centre, k * s * radius_loc, k * s * residual_loc, settings, q_sum,
                              k * s * (max(g) - min(g)), work,
                              [f"the rocker FE is the members' mean {k * s * g_mean:.6g} mm (spread "
                               f"{k * s * (max(g) - min(g)):.3g} mm in stage 1)"])
