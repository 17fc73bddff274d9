"""Synthesis by minimising a deviation over N points: least squares, and the maximum deviation.

Both vary all S = 5 scheme parameters (a = 1; log b, log c, log d, φ0, ψ0; the branch of the start is
kept) and evaluate the structural error at N points of the working range: one value of the objective
costs N positions. Limits are an exact penalty, 10 × (violation of the transmission-angle margin in
rad + violation of the log link-ratio margin), in the same units as the objective.

- ``least_squares_synthesis``: minimises Σ Δψ(φ_k)² by ``scipy.optimize.least_squares`` (trust-region
  reflective, forward-difference Jacobian: 5 extra objective values per Jacobian).
- ``max_deviation_synthesis``: minimises max_k |Δψ(φ_k)| by Nelder–Mead; the "deviation function"
  Sunkuev 1984 compares Q with (ch. 2, conclusions 2–3).
"""

from __future__ import annotations

import math

import numpy as np

from camcad.linkage.fgen import (
    INSIDE,
    FunctionGenerator,
    Limits,
    Work,
    limit_margins,
    pack,
    structural_error,
    unpack,
)
from camcad.linkage.target import Target

PENALTY_WEIGHT = 10.0


def _penalty(fg: FunctionGenerator, target: Target, limits: Limits, work: Work) -> float:
    mu = limits.mu_margin(fg, target, work)
    ratio = limits.ratio_margin(fg)
    return PENALTY_WEIGHT * (max(0.0, -mu) + max(0.0, -ratio))


def least_squares_synthesis(target: Target, start: FunctionGenerator, limits: Limits, work: Work,
                            points: int = 41, phi=None) -> FunctionGenerator:
    """Least-squares four-bar over ``points`` uniform points (or the given ``phi``, rad), from ``start``
    (module docstring).

    Returns the mechanism with a = 1 (scale it with ``FunctionGenerator.scaled``).

    Examples
    --------
    Started on the four-bar that made the target, it stays there (zero residual):

    >>> from camcad.linkage.fourbar import output_angle
    >>> from camcad.linkage.target import make_target
    >>> f = lambda x: output_angle(1.0, 3.0, 2.25, 2.5, 1.0 + x, 1) - output_angle(1.0, 3.0, 2.25, 2.5, 1.0, 1)
    >>> t = make_target(f, 0.0, 1.0, math.degrees(1.0), math.degrees(f(1.0)), "four-bar")
    >>> start = FunctionGenerator(1.0, 3.0, 2.25, 2.5, 1.0, output_angle(1.0, 3.0, 2.25, 2.5, 1.0, 1), 1)
    >>> fg = least_squares_synthesis(t, start, Limits(), Work())
    >>> [round(v, 9) for v in fg.links()]
    [1.0, 3.0, 2.25, 2.5]
    """
    from scipy.optimize import least_squares

    phi = np.linspace(0.0, target.dphi, points) if phi is None else np.asarray(phi, dtype=float)
    branch = start.branch

    def residuals(x):
        work.objective_evaluations += 1
        fg = unpack(x, branch)
        err = structural_error(fg, target, phi, work)
        err = np.where(np.isfinite(err), err, math.pi)
        pen = _penalty(fg, target, limits, work)
        return np.append(err, pen)

    x0 = pack(start)
    result = least_squares(residuals, x0, method="trf", x_scale="jac", xtol=1e-12, ftol=1e-14, gtol=1e-14,
                           max_nfev=400)
    fg = unpack(result.x, branch)
    if limit_margins(fg, target, limits, work).min() < 0:
        # the exact penalty stops a hair outside an active limit: finish with the limits as constraints
        fg = constrained_least_squares(target, fg, limits, work, phi)
    return fg


def parameter_bounds(limits: Limits) -> list[tuple[float | None, float | None]]:
    """Bounds of the ``pack`` parameters for the constrained optimisers: each log link ratio within
    ± (log R_max + 1) (the link-ratio limit itself is a constraint; the bounds keep SLSQP's trial steps from
    overflowing), the offsets free."""
    span = math.log(limits.ratio_max) + 1.0
    return [(-span, span)] * 3 + [(None, None)] * 2


def constrained_least_squares(target: Target, start: FunctionGenerator, limits: Limits, work: Work,
                              phi) -> FunctionGenerator:
    """Σ Δψ(φ_k)² minimised by SLSQP with the limits as constraints (``fgen.limit_margins``) from ``start``;
    ``start`` itself when SLSQP ends outside the limits.

    Examples
    --------
    >>> from camcad.linkage.fourbar import output_angle
    >>> from camcad.linkage.target import make_target
    >>> f = lambda x: output_angle(1.0, 3.0, 2.25, 2.5, 1.0 + x, 1) - output_angle(1.0, 3.0, 2.25, 2.5, 1.0, 1)
    >>> t = make_target(f, 0.0, 1.0, math.degrees(1.0), math.degrees(f(1.0)), "four-bar")
    >>> start = FunctionGenerator(1.0, 3.0, 2.25, 2.5, 1.0, output_angle(1.0, 3.0, 2.25, 2.5, 1.0, 1), 1)
    >>> fg = constrained_least_squares(t, start, Limits(), Work(), np.linspace(0, 1, 21))
    >>> [round(v, 6) for v in fg.links()]
    [1.0, 3.0, 2.25, 2.5]
    """
    from scipy.optimize import minimize

    branch = start.branch
    phi = np.asarray(phi, dtype=float)
    scale = 1.0 / max(len(phi), 1)

    def objective(x):
        work.objective_evaluations += 1
        err = structural_error(unpack(x, branch), target, phi, work)
        return float(np.sum(np.where(np.isfinite(err), err, math.pi) ** 2)) * scale

    result = minimize(objective, pack(start), method="SLSQP", bounds=parameter_bounds(limits),
                      constraints=[{"type": "ineq",
                                    "fun": lambda x: limit_margins(unpack(x, branch), target, limits, work)}],
                      options={"maxiter": 400, "ftol": 1e-18})
    fg = unpack(result.x, branch)
    return fg if np.all(np.isfinite(result.x)) and limit_margins(fg, target, limits).min() >= -INSIDE else start


def max_deviation_synthesis(target: Target, start: FunctionGenerator, limits: Limits, work: Work,
                            points: int = 41, max_evaluations: int = 4000) -> FunctionGenerator:
    """Minimise the maximum structural error over ``points`` uniform points by Nelder–Mead from ``start``
    (a = 1 in the result; N positions per value of the objective).

    Examples
    --------
    >>> from camcad.linkage.fourbar import output_angle
    >>> from camcad.linkage.target import make_target
    >>> f = lambda x: output_angle(1.0, 3.0, 2.25, 2.5, 1.0 + x, 1) - output_angle(1.0, 3.0, 2.25, 2.5, 1.0, 1)
    >>> t = make_target(f, 0.0, 1.0, math.degrees(1.0), math.degrees(f(1.0)), "four-bar")
    >>> start = FunctionGenerator(1.0, 3.0, 2.25, 2.5, 1.0, output_angle(1.0, 3.0, 2.25, 2.5, 1.0, 1), 1)
    >>> w = Work()
    >>> fg = max_deviation_synthesis(t, start, Limits(), w, max_evaluations=50)
    >>> [round(v, 6) for v in fg.links()], w.positions % 41 <= 4 * w.objective_evaluations
    ([1.0, 3.0, 2.25, 2.5], True)
    """
    from scipy.optimize import minimize

    phi = np.linspace(0.0, target.dphi, points)
    branch = start.branch

    def objective(x):
        work.objective_evaluations += 1
        fg = unpack(x, branch)
        err = structural_error(fg, target, phi, work)
        worst = float(np.max(np.abs(err))) if np.all(np.isfinite(err)) else math.pi
        return worst + _penalty(fg, target, limits, work)

    x0 = pack(start)
    simplex = np.array([x0] + [x0 + step for step in np.diag([0.1, 0.1, 0.1, 0.05, 0.05])])
    result = minimize(objective, x0, method="Nelder-Mead",
                      options={"xatol": 1e-10, "fatol": 1e-14, "maxfev": max_evaluations,
                               "initial_simplex": simplex})
    return unpack(result.x, branch)
