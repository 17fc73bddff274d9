"""Periodic smoothing splines: the quintic spline of a tabulated motion and the cubic re-smoothing of its
second derivative (the batten study's method, with the smoothing chosen by generalised cross-validation).

A cam's motion is periodic, so the splines are periodic B-splines of odd degree k = 2q − 1 on the cycle T,
with a knot at every table angle (at most ``MAX_KNOTS``; a longer table gets every m-th angle as a knot).
The fit minimises

    Σ w_i (y_i − f(θ_i))² + λ ∫_0^T (f^(q)(θ))² dθ

— for a knot at every angle this is exactly the periodic smoothing spline of degree 2q − 1 (q = 3: quintic,
the penalty on the third derivative; q = 2: cubic, on the second). The B-spline basis and its derivatives
are scipy.interpolate's (``BSpline.design_matrix``, ``BSpline.derivative``); the penalty is integrated
exactly by Gauss–Legendre on each knot interval.

The smoothing λ is chosen by generalised cross-validation (Craven & Wahba 1979): the minimum of
GCV(λ) = n·RSS(λ)/(n − tr H(λ))², H the hat matrix. With A = DᵀWD and the generalised
eigen-decomposition Ω V = A V diag(d), VᵀAV = I (scipy.linalg.eigh), the columns of D V are
W-orthonormal, so for every λ

    tr H = Σ 1/(1 + λd_j),   RSS = yᵀWy − Σ z_j² + Σ (λd_j/(1 + λd_j))² z_j²,   z = Vᵀ DᵀWy,

one O(m³) decomposition and O(m) per trial λ. A stated measurement error σ replaces GCV by the
discrepancy rule RSS(λ) = (n − tr H)·σ².

Sources: P. Craven, G. Wahba, "Smoothing noisy data with spline functions", Numer. Math. 31 (1979)
377–403 (GCV); C. H. Reinsch, "Smoothing by spline functions", Numer. Math. 10 (1967) 177–183 (the
penalised fit and the discrepancy rule); P. H. C. Eilers, B. D. Marx, "Flexible smoothing with B-splines
and penalties", Statist. Sci. 11 (1996) 89–121 (fewer knots than data); PhD abstract on the batten
mechanism of the STB loom, Novosibirsk (quintic splines of the radius-vectors, the second derivative
smoothed again by a cubic spline).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camcad.errors import CamcadError
from camcad.numerics import bounded_minimum, brent_root

#: the most knots of one periodic spline (a longer table gets every m-th angle as a knot)
MAX_KNOTS = 720
#: log10 range searched for λ around the scale of the penalty's eigenvalues
_SEARCH_DECADES = 6.0


@dataclass(frozen=True)
class PeriodicSpline:
    """A periodic B-spline of degree ``degree`` and period ``period`` (rad): f(θ) = Σ c_j B_j(θ mod T).

    ``knots`` are the m distinct knots in [knots[0], knots[0] + period); ``coefficients`` the m periodic
    coefficients. Call it with θ (rad) and the derivative order ``nu``.
    """

    knots: np.ndarray
    coefficients: np.ndarray
    degree: int
    period: float

    def _bspline(self):
        from scipy.interpolate import BSpline  # scipy costs start-up time: loaded when a table is smoothed

        t = extended_knots(self.knots, self.period, self.degree)
        c = np.concatenate((self.coefficients, self.coefficients[:self.degree]))
        return BSpline(t, c, self.degree)

    def __call__(self, theta, nu: int = 0) -> np.ndarray:
        theta = np.asarray(theta, dtype=float)
        start = float(self.knots[0])
        inside = start + np.mod(theta - start, self.period)
        spline = self._bspline()
        return spline.derivative(nu)(inside) if nu else spline(inside)


@dataclass(frozen=True)
class SmoothingFit:
    """A periodic smoothing spline fitted to a table, and how it was chosen.

    ``spline``: the fit; ``lam``: λ (units of y² per unit of the penalty); ``method``: "gcv",
    "stated" (σ given) or "interpolation"; ``rss``: Σ w (y − f)²; ``dof``: tr H; ``sigma``: the
    estimated (or stated) measurement error √(RSS/(n − tr H)); ``residual_rms`` and ``residual_max``:
    of y − f at the table's angles; ``knots_every``: 1 when every angle is a knot; ``ramp`` and
    ``ramp_error``: the coefficient of the unpenalised ramp column and its standard error (when asked).
    """

    spline: PeriodicSpline
    lam: float
    method: str
    rss: float
    dof: float
    n: int
    sigma: float
    residual_rms: float
    residual_max: float
    knots_every: int
    ramp: float | None = None
    ramp_error: float | None = None


def extended_knots(knots: np.ndarray, period: float, degree: int) -> np.ndarray:
    """The full knot vector of the periodic spline: ``degree`` knots before and ``degree`` + 1 after the
    m knots of one period, repeated with the period."""
    m = len(knots)
    index = np.arange(-degree, m + degree + 1)
    return knots[np.mod(index, m)] + period * np.floor_divide(index, m)


def design(theta: np.ndarray, knots: np.ndarray, period: float, degree: int, nu: int = 0) -> np.ndarray:
    """The periodic design matrix (n, m): column j is the j-th periodic basis function (its ``nu``-th
    derivative) at ``theta`` (rad)."""
    from scipy.interpolate import BSpline

    t = extended_knots(knots, period, degree)
    m = len(knots)
    start = float(knots[0])
    inside = start + np.mod(np.asarray(theta, dtype=float) - start, period)
    if nu == 0:
        full = BSpline.design_matrix(inside, t, degree).toarray()
    else:
        basis = BSpline(t, np.eye(m + degree), degree).derivative(nu)
        full = basis(inside)
    folded = full[:, :m].copy()
    folded[:, :degree] += full[:, m:m + degree]
    return folded


def penalty(knots: np.ndarray, period: float, degree: int) -> np.ndarray:
    """Ω_ij = ∫ B_i^(q) B_j^(q) dθ over one period, q = (degree + 1)/2 (exact: Gauss–Legendre on each
    knot interval with enough points for the polynomial product)."""
    q = (degree + 1) // 2
    points = degree - q + 1
    nodes, weights = np.polynomial.legendre.leggauss(points)
    edges = np.append(knots, knots[0] + period)
    lo, hi = edges[:-1], edges[1:]
    half = (hi - lo) / 2.0
    x = ((lo + hi) / 2.0)[:, None] + half[:, None] * nodes[None, :]
    w = half[:, None] * weights[None, :]
    derivative = design(x.ravel(), knots, period, degree, q)
    return derivative.T @ (derivative * w.ravel()[:, None])


def fit_periodic(theta: np.ndarray, y: np.ndarray, period: float, *, degree: int = 5,
                 sigma: float | None = None, lam: float | None = None, weights: np.ndarray | None = None,
                 ramp: np.ndarray | None = None, where: str = "table") -> SmoothingFit:
    """The periodic smoothing spline of degree ``degree`` (odd) through (θ, y), θ in rad over ``period``.

    Parameters
    ----------
    theta : ndarray
        Angles (rad), any order; an angle may repeat (modulo the period) when ``ramp`` tells the rows apart.
    y : ndarray
        Values (any unit).
    period : float
        The period T (rad).
    degree : int
        5 (quintic, the penalty on the third derivative) or 3 (cubic, on the second).
    sigma : float, optional
        The stated measurement error of y (its unit): λ from RSS = (n − tr H)σ²; None: GCV.
    lam : float, optional
        λ itself (overrides ``sigma`` and GCV; 0 interpolates).
    weights : ndarray, optional
        w_i (default 1).
    ramp : ndarray, optional
        A further, unpenalised column r_i (e.g. θ_i/T, 1 for a row at the cycle's end): the fit is then
        f(θ) + J·r and ``SmoothingFit.ramp`` is J with its standard error — how far the table is from
        closing. The returned ``spline`` is the periodic part f.
    where : str
        For messages.

    Returns
    -------
    SmoothingFit

    Examples
    --------
    A sine sampled every 10° with no noise is reproduced: GCV picks almost no smoothing.

    >>> import numpy as np
    >>> theta = np.radians(np.arange(0.0, 360.0, 10.0))
    >>> fit = fit_periodic(theta, np.sin(theta), 2 * np.pi)
    >>> bool(abs(fit.spline(np.array([0.3]))[0] - np.sin(0.3)) < 1e-6)
    True
    """
    if degree not in (3, 5):
        raise ValueError("degree must be 3 or 5")
    theta = np.mod(np.asarray(theta, dtype=float), period)
    y = np.asarray(y, dtype=float)
    order = np.argsort(theta, kind="stable")
    theta, y = theta[order], y[order]
    w = np.ones(len(y)) if weights is None else np.asarray(weights, dtype=float)[order]
    extra = None if ramp is None else np.asarray(ramp, dtype=float)[order]
    n = len(theta)
    if n < degree + 3:
        raise CamcadError(f"{n} rows are too few for a spline of degree {degree}", where,
                          f"give at least {degree + 3} rows over the cycle")
    distinct = np.concatenate(([True], np.diff(theta) > 1e-12 * period))
    if not distinct.all() and extra is None:
        raise CamcadError("two rows have the same angle", where, "delete or average the repeated rows")
    angles = theta[distinct]
    every = max(1, math.ceil(len(angles) / MAX_KNOTS))
    knots = angles[::every].copy()
    m = len(knots)
    d = design(theta, knots, period, degree)
    omega = penalty(knots, period, degree)
    if extra is not None:
        d = np.column_stack((d, extra))
        omega = np.pad(omega, ((0, 1), (0, 1)))
    a = d.T @ (d * w[:, None])
    b = d.T @ (w * y)
    scale = float(np.trace(a)) / a.shape[0]
    import scipy.linalg  # start-up cost: loaded when a table is smoothed

    try:
        # Vᵀ A V = I, Vᵀ Ω V = diag(d): the columns of D V are W-orthonormal (module docstring)
        d_eig, v = scipy.linalg.eigh((omega + omega.T) / 2.0, a + 1e-13 * scale * np.eye(a.shape[0]))
    except np.linalg.LinAlgError:
        raise CamcadError("the table's angles do not determine a spline", where,
                          "give rows spread over the whole cycle") from None
    d_eig = np.clip(d_eig, 0.0, None)
    z = v.T @ b
    total = float(np.sum(w * y * y))
    outside = max(total - float(np.sum(z * z)), 0.0)

    def rss_dof(lam_value: float) -> tuple[float, float]:
        shrink = 1.0 / (1.0 + lam_value * d_eig)
        return outside + float(np.sum(((1.0 - shrink) * z) ** 2)), float(np.sum(shrink))

    positive = d_eig[d_eig > 1e-12 * max(float(d_eig.max()), 1e-300)]
    lo = math.log10(1.0 / float(positive.max())) - _SEARCH_DECADES / 2 if len(positive) else -12.0
    hi = math.log10(1.0 / float(positive.min())) + _SEARCH_DECADES / 2 if len(positive) else 12.0
    if lam is not None:
        method, chosen = ("interpolation" if lam == 0 else "stated"), float(lam)
    elif sigma is not None:
        if not (math.isfinite(sigma) and sigma > 0):
            raise CamcadError(f"measurement error {sigma!r} must be positive", where, "give e.g. 0.001 (mm)")
        method = "stated"

        def excess(log_lam: float) -> float:
            rss, dof = rss_dof(10.0 ** log_lam)
            return rss - max(n - dof, 1e-300) * sigma**2

        if excess(hi) < 0:
            raise CamcadError(f"the stated measurement error {sigma:g} is larger than the table's whole scatter "
                              "about its smoothest fit", where, "give a smaller error, or let camcad choose (GCV)")
        chosen = 10.0 ** lo if excess(lo) > 0 else 10.0 ** brent_root(excess, lo, hi, xtol=1e-6)
    else:
        method = "gcv"

        def gcv(log_lam: float) -> float:
            rss, dof = rss_dof(10.0 ** log_lam)
            return n * rss / max(n - dof, 1e-9) ** 2

        grid = np.linspace(lo, hi, 121)
        values = np.array([gcv(g) for g in grid])
        best = int(np.argmin(values))
        left, right = grid[max(best - 1, 0)], grid[min(best + 1, len(grid) - 1)]
        log_best = bounded_minimum(gcv, float(left), float(right), xatol=1e-4)[0] if right > left else grid[best]
        chosen = 10.0 ** log_best
    shrink = 1.0 / (1.0 + chosen * d_eig)
    coefficients = v @ (shrink * z)
    fitted = d @ coefficients
    residual = y - fitted
    rss, dof = rss_dof(chosen)
    sigma_hat = float(sigma) if method == "stated" and sigma is not None else \
        math.sqrt(max(rss, 0.0) / max(n - dof, 1.0))
    ramp_value = ramp_error = None
    if extra is not None:
        ramp_value = float(coefficients[m])
        # Cov(c) = σ² V diag(shrink²) Vᵀ for the W-orthonormal columns D V (module docstring)
        ramp_error = sigma_hat * math.sqrt(float(np.sum((v[m] * shrink) ** 2)))
    return SmoothingFit(PeriodicSpline(knots, coefficients[:m], degree, float(period)), chosen, method, rss, dof,
                        n, sigma_hat, float(np.sqrt(np.mean(residual**2))), float(np.max(np.abs(residual))), every,
                        ramp_value, ramp_error)


__all__ = ["MAX_KNOTS", "PeriodicSpline", "SmoothingFit", "design", "extended_knots", "fit_periodic", "penalty"]
