"""The transforming six-bar of an impulse variator (Sunkuev 1984, ch. 4, Fig. 7).

An impulse (pulse) variator turns a crank's rotation into an oscillation whose forward strokes a one-way clutch
adds up; its mean speed ratio is regulated. Sunkuev 1984's mechanism: two four-bars in series, O A B C and C B D E
("Регулируемый шестизвенник состоит из двух последовательно соединенных четырехзвенников OA(j)B(j)C(j) и
C(j)B(j)D(j)E"): crank OA, coupler AB, rocker CB pivoted at C; the rocker CB is the input of the second loop,
whose coupler BD drives the output ED pivoted at the fixed E. The regulation moves C on an arc about O, so the
first loop turns rigidly about O and its transmission ratio w(φ) = dβ/dφ keeps its shape ("не изменяется
зависимость w(j) от φ") while the second loop's ratio k = dψ/dβ changes; the output's velocity analog is
U = w·k. Over the working interval φ_p of the crank U should be constant while its mean U_cp = ψ_p/φ_p is
regulated over [U_cp⁽⁰⁾, U_cp⁽ᵐ⁾]; the non-uniformity is δ = (U_max − U_min)/U_cp and the requirement
max_j δ⁽ʲ⁾ <= [δ].

Synthesis in Sunkuev 1984's two stages:

1. the first four-bar (crank a = 1; coupler, rocker, |OC|, the interval's start) for the least non-uniformity
   δ_w of w over the working interval (Nelder–Mead from a grid of starts; the crank must turn fully, the
   transmission angle over the turn >= μ_min);
2. the second four-bar (coupler BD, output ED, the pivot E) and the settings x⁽ʲ⁾ (the angle of C about O) for
   min max_j δ⁽ʲ⁾ with U_cp⁽ʲ⁾ equal to the p requested values spread over the range (SLSQP in epigraph form; the
   transmission angle of the second loop over the working interval >= μ_min; its loop must close over the whole
   turn), from a grid of starts.

U is computed with the exact derivatives of ``camcad.linkage.analysis.Loop`` on 61 points of the interval.
Lengths are in crank lengths during the synthesis and scaled to ``crank`` mm in the result.
"""

from __future__ import annotations

import cmath
import math
from dataclasses import dataclass, field

import numpy as np

from camcad.errors import CamcadError
from camcad.linkage.analysis import Loop

SAMPLES = 61


@dataclass(frozen=True)
class Variator:
    """The transforming six-bar (lengths mm, angles rad): crank ``a`` about O = (0, 0), coupler ``b``, rocker ``c``
    about C = R e^{ix} (R = ``radius``), coupler BD ``e``, output ED ``f`` about ``pivot_e``; the working interval
    starts at the crank angle ``start`` + x and lasts ``interval``; ``branch1``, ``branch2`` the loops' branches."""

    a: float
    b: float
    c: float
    radius: float
    e: float
    f: float
    pivot_e: complex
    start: float
    interval: float
    branch1: int = 1
    branch2: int = 1

    def loops(self, x: float) -> tuple[Loop, Loop]:
        c_pt = self.radius * cmath.exp(1j * x)
        first = Loop((0.0, 0.0), (c_pt.real, c_pt.imag), self.a, self.b, self.c, self.branch1)
        second = Loop((c_pt.real, c_pt.imag), (self.pivot_e.real, self.pivot_e.imag), self.c, self.e, self.f,
                      self.branch2)
        return first, second

    def ratios(self, x: float, theta=None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(θ, w, k, U) over the working interval at setting x (θ absolute crank angles, rad; w = dβ/dθ,
        k = dψ/dβ, U = w·k, dimensionless)."""
        if theta is None:
            theta = x + self.start + np.linspace(0.0, self.interval, SAMPLES)
        first, second = self.loops(x)
        beta, w, *_ = first.derivatives(theta, order=1)
        _, k, *_ = second.derivatives(beta, order=1)
        return theta, w, k, w * k

    def figures(self, x: float) -> dict:
        """δ, U_cp, the output's turn over the interval and the worst transmission angles (deg) at setting x."""
        theta, w, _, u = self.ratios(x)
        first, second = self.loops(x)
        beta = first.output(theta)
        psi = second.output(beta)
        turn = float(np.remainder(psi[-1] - psi[0] + math.pi, 2 * math.pi) - math.pi)
        mean = turn / self.interval
        mu1 = first.worst_transmission(0.0, 2 * math.pi)
        mu2 = float(np.nanmin(np.minimum(second.transmission(beta), math.pi - second.transmission(beta))))
        return {"setting_deg": math.degrees(math.remainder(x, 2 * math.pi)), "u_mean": mean,
                "delta": float((u.max() - u.min()) / abs(mean)),
                "delta_w": float((w.max() - w.min()) / abs(np.mean(w))), "output_turn_deg": math.degrees(turn),
                "mu_min_first_deg": math.degrees(mu1), "mu_min_second_deg": math.degrees(mu2)}


@dataclass
class VariatorResult:
    """The synthesised variator, its settings (rad), each setting's figures, the work done."""

    variator: Variator
    settings: np.ndarray
    targets: np.ndarray
    rows: list[dict]
    delta_w: float
    evaluations: int
    notes: list[str] = field(default_factory=list)

    @property
    def delta_max(self) -> float:
        return max(r["delta"] for r in self.rows)


def _stage1(interval: float, mu_min: float, ratio_max: float, grid: int = 4):
    """The first four-bar (a = 1) of least δ_w over the working interval: (b, c, R, start, branch, δ_w)."""
    from scipy.optimize import minimize

    def value(y, branch):
        b, c, r = np.exp(y[:3])
        links = (1.0, b, c, r)
        if max(links) / min(links) > ratio_max:
            return 10.0 + math.log(max(links) / min(links))
        loop = Loop((0.0, 0.0), (r, 0.0), 1.0, b, c, branch)
        worst = loop.worst_transmission(0.0, 2 * math.pi)
        if not math.isfinite(worst):
            return 10.0
        theta = y[3] + np.linspace(0.0, interval, SAMPLES)
        _, w, *_ = loop.derivatives(theta, order=1)
        if not np.all(np.isfinite(w)) or abs(np.mean(w)) < 1e-3:
            return 10.0
        return float((w.max() - w.min()) / abs(np.mean(w))) + 10.0 * max(0.0, mu_min - worst)

    best = None
    count = 0
    for b0 in np.linspace(math.log(2.0), math.log(6.0), grid):
        for c0 in np.linspace(math.log(1.5), math.log(5.0), grid):
            for r0 in np.linspace(math.log(2.0), math.log(6.0), grid):
                for s0 in np.linspace(0.0, 2 * math.pi, grid, endpoint=False):
                    for branch in (1, -1):
                        y0 = np.array([b0, c0, r0, s0])
                        if value(y0, branch) >= 10.0:
                            continue
                        res = minimize(value, y0, args=(branch,), method="Nelder-Mead",
                                       options={"xatol": 1e-8, "fatol": 1e-12, "maxfev": 600})
                        count += res.nfev
                        if best is None or res.fun < best[0]:
                            best = (res.fun, res.x, branch)
    if best is None:
        raise CamcadError("no crank-rocker with a full turn meets the limits", "linkage variator",
                          "loosen --mu-min or --ratio-max")
    fun, y, branch = best
    b, c, r = np.exp(y[:3])
    return float(b), float(c), float(r), float(y[3]), branch, float(fun), count


def synthesise_variator(u_range: tuple[float, float], interval_deg: float = 180.0, settings: int = 3,
                        crank: float = 20.0, mu_min_deg: float = 30.0, ratio_max: float = 10.0,
                        starts: int = 24, seed: int = 0) -> VariatorResult:
    """The transforming six-bar of an impulse variator for mean ratios U_cp over ``u_range`` (module docstring).

    Parameters
    ----------
    u_range : tuple of float
        U_cp⁽⁰⁾, U_cp⁽ᵐ⁾: the mean velocity analog of the output over the working interval at the first and the
        last setting (dimensionless, rad of output per rad of crank; non-zero, one sign).
    interval_deg : float
        The working interval φ_p of the crank, deg.
    settings : int
        p, the settings (U_cp spread evenly over the range).
    crank : float
        Crank length OA of the result, mm.
    mu_min_deg : float
        Transmission-angle limit, deg.
    ratio_max : float
        Largest link-length ratio (dimensionless).
    starts : int
        Random starts of stage 2.
    seed : int
        Their seed.

    Returns
    -------
    VariatorResult
        The variator (mm), the settings (rad) and per setting δ, U_cp and the worst transmission angles (deg).

    Examples
    --------
    The mean ratios are met exactly at every setting; the transmission angles stay at or above their limit of
    30° (the first four-bar's optimum lies on it, to round-off):

    >>> r = synthesise_variator((0.05, 0.15), 180.0, 3, starts=6)
    >>> [round(row["u_mean"], 9) for row in r.rows]
    [0.05, 0.1, 0.15]
    >>> all(min(row["mu_min_first_deg"], row["mu_min_second_deg"]) >= 30.0 - 1e-9 for row in r.rows)
    True
    """
    from scipy.optimize import minimize

    lo, hi = u_range
    if not (lo and hi) or lo * hi < 0 or lo == hi or not (math.isfinite(lo) and math.isfinite(hi)):
        raise CamcadError(f"the mean ratios {lo:g}:{hi:g} must be non-zero, of one sign and different", "--u-mean",
                          "give --u-mean A:B, e.g. 0.05:0.15")
    if not 10.0 <= interval_deg <= 300.0:
        raise CamcadError(f"working interval {interval_deg:g} deg is out of range", "--interval",
                          "give 10 to 300 deg")
    if not 2 <= settings <= 12:
        raise CamcadError(f"{settings} settings is out of range", "--settings", "give 2 to 12")
    interval = math.radians(interval_deg)
    mu_min = math.radians(mu_min_deg)
    b, c, r, start, branch1, delta_w, count = _stage1(interval, mu_min, ratio_max)
    targets = np.linspace(lo, hi, settings)

    def variator(z, branch2) -> Variator:
        e, f = math.exp(float(np.clip(z[0], -50.0, 50.0))), math.exp(float(np.clip(z[1], -50.0, 50.0)))
        return Variator(1.0, b, c, r, e, f, complex(z[2], z[3]), start, interval, branch1, branch2)

    def per_setting(z, branch2):
        v = variator(z, branch2)
        out = []
        for x in z[4:4 + settings]:
            theta, _, _, u = v.ratios(float(x))
            first, second = v.loops(float(x))
            beta = first.output(theta)
            psi = second.output(beta)
            if not (np.all(np.isfinite(u)) and np.all(np.isfinite(psi))):
                out.append(None)
                continue
            turn = float(np.remainder(psi[-1] - psi[0] + math.pi, 2 * math.pi) - math.pi)
            cos_mu = (second.b ** 2 + second.c ** 2 - np.abs(np.exp(1j * beta) * second.a + complex(*second.p)
                                                           - complex(*second.q)) ** 2) / (2 * second.b * second.c)
            out.append((u, turn / interval, cos_mu))
        return out

    def constraints(z, branch2):
        vals = per_setting(z, branch2)
        ineq, eq = [], []
        bound = math.cos(mu_min)
        for j, item in enumerate(vals):
            if item is None:
                ineq += [-1.0] * (2 * SAMPLES + 2 * SAMPLES)
                eq.append(1.0)
                continue
            u, mean, cos_mu = item
            ineq += list(z[-1] * abs(mean) - (u - mean)) + list(z[-1] * abs(mean) + (u - mean))
            ineq += list(bound - cos_mu) + list(bound + cos_mu)
            eq.append((mean - targets[j]) / abs(targets[-1]))
        logs = np.array([0.0, math.log(b), math.log(c), math.log(r), float(np.clip(z[0], -50.0, 50.0)),
                         float(np.clip(z[1], -50.0, 50.0))])
        ineq += [math.log(ratio_max) - (logs[i] - logs[j]) for i in range(6) for j in range(6) if i != j]
        return np.array(ineq), np.array(eq)

    rng = np.random.default_rng(seed)
    best = None
    c_pt = r + 0j
    for _ in range(starts):
        branch2 = int(rng.choice([1, -1]))
        e0, f0 = rng.uniform(1.5, 5.0), rng.uniform(1.0, 4.0)
        pivot = c_pt + complex(*rng.uniform(-1, 1, 2)) * (c + e0)
        z0 = np.concatenate([[math.log(e0), math.log(f0), pivot.real, pivot.imag],
                             rng.uniform(-0.3, 0.3) + np.linspace(0.0, rng.uniform(0.2, 0.8), settings), [0.5]])
        try:
            res = minimize(lambda z: z[-1], z0, jac=lambda z: np.eye(len(z))[-1], method="SLSQP",
                           constraints=[{"type": "ineq", "fun": lambda z, s=branch2: constraints(z, s)[0]},
                                        {"type": "eq", "fun": lambda z, s=branch2: constraints(z, s)[1]}],
                           options={"maxiter": 200, "ftol": 1e-12})
        except (ValueError, OverflowError, ZeroDivisionError):
            continue
        count += res.nfev * settings
        ineq, eq = constraints(res.x, branch2)
        ok = bool(np.all(np.isfinite(res.x)) and ineq.min() >= -1e-7 and np.max(np.abs(eq)) <= 1e-7)
        if ok and (best is None or res.x[-1] < best[0]):
            best = (res.x[-1], res.x, branch2)
    if best is None:
        raise CamcadError("no second four-bar gives these mean ratios within the limits", "linkage variator",
                          "narrow --u-mean, lengthen --interval, or loosen --mu-min")
    _, z, branch2 = best
    unit = variator(z, branch2)
    scale = crank
    v = Variator(scale, unit.b * scale, unit.c * scale, unit.radius * scale, unit.e * scale, unit.f * scale,
                 unit.pivot_e * scale, start, interval, branch1, branch2)
    xs = np.array(z[4:4 + settings])
    rows = [v.figures(float(x)) for x in xs]
    return VariatorResult(v, xs, targets, rows, delta_w, count,
                          [f"stage 1 (the first four-bar alone): δ_w = {delta_w:.4g} over the working interval"])
