"""Minimax (Chebyshev, equal-ripple) four-bar function generator by a Remez exchange.

The best uniform approximation by a family with S parameters is characterised (under the Haar
condition, which holds locally for the four-bar's position function) by S + 1 points where the
error takes its maximum magnitude with alternating signs (Chebyshev's equioscillation theorem; for
linkages: Levitsky, Sarkisyan, Akhiezer; Freudenstein 1959). The exchange:

1. on S + 1 reference points φ_j solve the S + 1 equations Δψ(φ_j; p) = (−1)^j E for the S = 5
   parameters p (a = 1; log b, log c, log d, φ0, ψ0) and the level E (``scipy.optimize.least_squares``
   on the square system);
2. find the local extrema of Δψ on a dense grid (2001 points), refine each by a bounded scalar search,
   keep an alternating sequence, reduce it to S + 1 points by dropping the smallest (keeping
   alternation), and make these the new references;
3. stop when the references no longer move and max|Δψ| equals |E| to 1e-9 relative.

Every solve of step 1 costs S + 1 positions per evaluation, every sweep of step 2 the grid plus the
refinements; all are counted.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from camcad.linkage.deviation import parameter_bounds
from camcad.linkage.fgen import (
    FunctionGenerator,
    Limits,
    Work,
    limit_margins,
    nodes,
    pack,
    structural_error,
    unpack,
)
from camcad.linkage.target import Target

GRID = 2001


@dataclass
class MinimaxResult:
    """The equal-ripple mechanism (a = 1), its level |E| (deg), the S + 1 references and the errors there."""

    mechanism: FunctionGenerator
    level_deg: float                   # |E|
    references_deg: list[float]        # the S + 1 reference points φ_j
    extrema_deg: list[float]           # error at the references, deg
    ripple_spread: float               # (max − min)/max of |error| at the references
    iterations: int
    converged: bool
    message: str


def _extrema(fg: FunctionGenerator, target: Target, work: Work) -> tuple[np.ndarray, np.ndarray]:
    """Refined local extrema (φ, error) of the structural error, ends included."""
    from scipy.optimize import minimize_scalar

    phi = np.linspace(0.0, target.dphi, GRID)
    err = structural_error(fg, target, phi, work)
    if not np.all(np.isfinite(err)):
        return np.array([]), np.array([])
    idx = [0]
    for k in range(1, GRID - 1):
        if (err[k] - err[k - 1]) * (err[k + 1] - err[k]) < 0:
            idx.append(k)
    idx.append(GRID - 1)
    xs, es = [], []
    for k in idx:
        if k in (0, GRID - 1):
            xs.append(phi[k])
            es.append(err[k])
            continue
        sign = 1.0 if err[k] > 0 else -1.0
        lo, hi = sorted((phi[k - 1], phi[k + 1]))
        res = minimize_scalar(lambda t, s=sign: -s * float(structural_error(fg, target, t, work)),
                              bounds=(lo, hi), method="bounded", options={"xatol": 1e-13})
        xs.append(res.x)
        es.append(-sign * res.fun)
    return np.array(xs), np.array(es)


def _alternating(xs: np.ndarray, es: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Reduce extrema to an alternating sequence of ``count`` points (or fewer if there are fewer)."""
    seq: list[tuple[Any, Any]] = []
    for x, e in zip(xs, es):
        if seq and np.sign(seq[-1][1]) == np.sign(e):
            if abs(e) > abs(seq[-1][1]):
                seq[-1] = (x, e)
        else:
            seq.append((x, e))
    while len(seq) > count:
        mags = [abs(e) for _, e in seq]
        k = int(np.argmin(mags))
        if k == 0 or k == len(seq) - 1:
            seq.pop(k)
            continue
        # drop the smallest and merge its two neighbours (same sign) into the larger one
        left, right = seq[k - 1], seq[k + 1]
        keep = left if abs(left[1]) >= abs(right[1]) else right
        seq[k - 1:k + 2] = [keep]
    return np.array([x for x, _ in seq]), np.array([e for _, e in seq])


def minimax_synthesis(target: Target, start: FunctionGenerator, work: Work, max_iterations: int = 40
                      ) -> MinimaxResult:
    """Equal-ripple four-bar from ``start`` by the Remez exchange (module docstring).

    Returns the mechanism with a = 1.

    Examples
    --------
    A target made by a four-bar is reproduced exactly: the level is zero.

    >>> import math
    >>> from camcad.linkage.fourbar import output_angle
    >>> from camcad.linkage.target import make_target
    >>> f = lambda x: output_angle(1.0, 3.0, 2.25, 2.5, 1.0 + x, 1) - output_angle(1.0, 3.0, 2.25, 2.5, 1.0, 1)
    >>> t = make_target(f, 0.0, 1.0, math.degrees(1.0), math.degrees(f(1.0)), "four-bar")
    >>> start = FunctionGenerator(1.0, 3.0, 2.25, 2.5, 1.0, output_angle(1.0, 3.0, 2.25, 2.5, 1.0, 1), 1)
    >>> minimax_synthesis(t, start, Work()).level_deg < 1e-9
    True
    """
    from scipy.optimize import least_squares

    count = 6
    branch = start.branch
    xs, es = _extrema(start, target, work)
    refs, _ = _alternating(xs, es, count)
    if len(refs) < count:
        j = np.arange(count)
        refs = target.dphi * (1 - np.cos(j * np.pi / (count - 1))) / 2
    x = pack(start)
    err0 = structural_error(start, target, refs, work)
    level = float(np.mean(np.abs(err0))) * (1.0 if err0[0] >= 0 else -1.0)
    fg = start
    message, converged, iteration = "iteration limit", False, 0
    if len(es) and float(np.max(np.abs(es))) < 1e-13:
        max_iterations = 0                   # the start reproduces the target: nothing to equalise
        message, converged = "the start reproduces the target (zero error)", True
    for iteration in range(1, max_iterations + 1):  # noqa: B007 - the count is reported after the loop
        signs = (-1.0) ** np.arange(count)

        def equations(y, refs=refs, signs=signs):
            work.objective_evaluations += 1
            trial = unpack(y[:5], branch)
            err = structural_error(trial, target, refs, work)
            return np.where(np.isfinite(err), err, math.pi) - signs * y[5]

        sol = least_squares(equations, np.append(x, level), method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15,
                            max_nfev=600)
        x, level = sol.x[:5], float(sol.x[5])
        fg = unpack(x, branch)
        xs, es = _extrema(fg, target, work)
        if len(xs) == 0:
            message = "the linkage does not close over the whole range"
            break
        new_refs, _ = _alternating(xs, es, count)
        peak = float(np.max(np.abs(es)))
        if len(new_refs) < count:
            message = f"the error has only {len(new_refs)} alternating extrema"
            break
        moved = float(np.max(np.abs(new_refs - refs)))
        refs = new_refs
        if peak <= abs(level) * (1 + 1e-9) + 1e-15 or moved < 1e-12:
            converged = True
            message = "equal ripple reached"
            break
    final = structural_error(fg, target, refs, work)
    mags = np.abs(final)
    spread = float((mags.max() - mags.min()) / mags.max()) if mags.size and mags.max() > 0 else 0.0
    return MinimaxResult(fg, math.degrees(abs(level)), [math.degrees(v) for v in refs],
                         [math.degrees(v) for v in final], spread, iteration, converged, message)


@dataclass
class ConstrainedMinimax:
    """The least maximum error under the limits: the mechanism (a = 1), its level (deg), the points the last
    round was solved on, the rounds, how many starts were tried and which one won."""

    mechanism: FunctionGenerator
    level_deg: float                   # the largest |error| on the dense check of the winner
    points: int                        # points of the last round's discrete problem
    rounds: int
    starts: int
    start: str                         # the name of the winning start
    admissible: bool
    message: str
    runs: list[dict]


def _epigraph(target: Target, limits: Limits, work: Work, branch: int, phi: np.ndarray, x0: np.ndarray,
              level0: float):
    """min E over (p, E) subject to |Δψ(φ_k; p)| <= E on ``phi`` and the limits (SLSQP)."""
    from scipy.optimize import minimize

    def error(y):
        err = structural_error(unpack(y[:5], branch), target, phi, work)
        return np.where(np.isfinite(err), err, math.pi)

    def constraints(y):
        work.objective_evaluations += 1
        err = error(y)
        return np.concatenate([y[5] - err, y[5] + err, limit_margins(unpack(y[:5], branch), target, limits, work)])

    gradient = np.zeros(6)
    gradient[5] = 1.0
    return minimize(lambda y: y[5], np.append(x0, level0), jac=lambda y: gradient, method="SLSQP",
                    bounds=[*parameter_bounds(limits), (0.0, None)],
                    constraints=[{"type": "ineq", "fun": constraints}], options={"maxiter": 400, "ftol": 1e-15})


def constrained_minimax(target: Target, starts: list[tuple[str, FunctionGenerator]], limits: Limits, work: Work,
                        points: int = 81, rounds: int = 8) -> ConstrainedMinimax:
    """The four-bar of least maximum structural error under the limits (transmission angle, link ratio).

    The minimax problem is solved in its epigraph form: minimise E over the five scheme parameters and E
    subject to −E <= Δψ(φ_k) <= E on a set of points and the limits as smooth constraints
    (``fgen.limit_margins``), by SLSQP. The points start as ``points`` Chebyshev points of the range; after
    each round the error is checked on the 2001-point grid with its local extrema refined, the extrema are
    added to the points (an exchange as in Remez's method, but the points are kept: with a limit active the
    optimum has fewer than S + 1 equal extrema), and the round is repeated until the checked maximum is
    within 1e-7 of E. Each start (an admissible mechanism from another method, with a name) is run; the
    admissible result of least checked maximum wins. Positions are counted in ``work``.

    Returns the mechanism with a = 1.

    Examples
    --------
    Started on the four-bar that generates the target, the level is zero:

    >>> from camcad.linkage.fourbar import output_angle
    >>> from camcad.linkage.target import make_target
    >>> f = lambda x: output_angle(1.0, 3.0, 2.25, 2.5, 1.0 + x, 1) - output_angle(1.0, 3.0, 2.25, 2.5, 1.0, 1)
    >>> t = make_target(f, 0.0, 1.0, math.degrees(1.0), math.degrees(f(1.0)), "four-bar")
    >>> start = FunctionGenerator(1.0, 3.0, 2.25, 2.5, 1.0, output_angle(1.0, 3.0, 2.25, 2.5, 1.0, 1), 1)
    >>> r = constrained_minimax(t, [("self", start)], Limits(30.0, 10.0), Work())
    >>> r.level_deg < 1e-8, r.admissible
    (True, True)
    """
    best: ConstrainedMinimax | None = None
    runs = []
    base = nodes(points, target.dphi, "chebyshev")
    base = np.concatenate([[0.0], base, [target.dphi]])
    for name, start in starts:
        branch = start.branch
        x = pack(start)
        phi = base.copy()
        err0 = structural_error(start, target, phi, work)
        level = float(np.max(np.abs(err0))) if np.all(np.isfinite(err0)) else math.pi
        checked, fg, message, done = math.inf, start, "round limit", 0
        for done in range(1, rounds + 1):  # noqa: B007 - the count is reported after the loop
            sol = _epigraph(target, limits, work, branch, phi, x, level)
            trial = unpack(sol.x[:5], branch)
            if not np.all(np.isfinite(sol.x)) or float(limit_margins(trial, target, limits, inside=0.0).min()) < 0:
                message = f"SLSQP left the limits ({sol.message})"
                break
            x, level, fg = sol.x[:5], float(sol.x[5]), trial
            xs, es = _extrema(fg, target, work)
            if len(es) == 0:
                message = "the linkage does not close over the whole range"
                break
            checked = float(np.max(np.abs(es)))
            if checked <= level * (1 + 1e-7) + 1e-15:
                message = "the maximum on the check grid equals the level"
                break
            phi = np.union1d(phi, xs)
        admissible = bool(math.isfinite(checked) and limit_margins(fg, target, limits, inside=0.0).min() >= 0)
        runs.append({"start": name, "max_error_deg": math.degrees(checked), "rounds": done, "points": len(phi),
                     "admissible": admissible, "message": message})
        if admissible and (best is None or math.degrees(checked) < best.level_deg):
            best = ConstrainedMinimax(fg, math.degrees(checked), len(phi), done, len(starts), name, True, message,
                                      runs)
    if best is None:
        first = starts[0][1]
        return ConstrainedMinimax(first, math.inf, 0, 0, len(starts), starts[0][0], False,
                                  "no start ended inside the limits", runs)
    best.runs = runs
    return best
