"""Independent references for ``camcad bench``: what every error in the kernel table is measured against.

None of these uses camcad's code (tests/report/test_bench_floors.py checks the imports); each is a closed form or
another method, named in the ``reference`` column of the rows it serves:

- ``RollerCam``: a translating roller follower (no offset, counter-clockwise cam) on cycloidal and 3-4-5
  motions, in polar closed form (Norton 2009, eq. 3.8 and §3.9; ch. 8 for the profile as the inner envelope
  of the roller); extremes of the pressure angle from d(v/r)/dθ = 0, i.e. a r − v² = 0 (Brent's method),
  and of the radius of curvature by a bounded scalar minimisation to 1e-12 rad;
- ``curve_distance``, ``polyline_deviation``: the distance of points to the exact curve (nearest sample,
  then golden-section search on the parameter) and the Hausdorff distance of a written polyline to it;
- ``sdof_exact``: the periodic response of the single-degree-of-freedom follower on a cycloidal
  dwell-rise-dwell-return law by matrix exponentials per phase (the forcing is the state of a harmonic
  oscillator, so each phase is one 4×4 exponential): exact to round-off;
- ``cycloidal_coefficients``: the Fourier coefficients of the same law in closed form;
- ``simpson_closure``: the balance of a drawn polyline by Simpson's rule per segment (exact for the
  quadratic and cubic integrands there), summed with ``math.fsum``.
"""

from __future__ import annotations

import math

import numpy as np

TWO_PI = 2.0 * math.pi
GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0


# =============================================================================================
# Roller cam in closed form
# =============================================================================================


class RollerCam:
    """Motions ``segments`` [(kind, width deg, shape)] with one ``lift`` (mm), Rb and Rr (mm), no offset.

    Frame (camcad's): follower on +y, the cam turns counter-clockwise, the point of cam angle θ lies at
    r e_r with e_r = (sin θ, cos θ), r = Rb + Rr + s. Shapes: "cycloidal" and "poly345".
    """

    def __init__(self, segments, lift: float, base_radius: float, roller_radius: float) -> None:
        self.segments = [(kind, math.radians(width), shape) for kind, width, shape in segments]
        self.lift, self.rb, self.rr = float(lift), float(base_radius), float(roller_radius)
        starts, level, levels = [], 0.0, []
        position = 0.0
        for kind, width, _ in self.segments:
            starts.append(position)
            levels.append(level)
            position += width
            level += {"rise": self.lift, "return": -self.lift}.get(kind, 0.0)
        self.starts, self.levels = starts, levels

    def motion(self, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """s (mm), v (mm/rad), a (mm/rad²) at θ (rad)."""
        t = np.mod(np.asarray(theta, dtype=float), TWO_PI)
        s, v, a = np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)
        for (kind, width, shape), start, level in zip(self.segments, self.starts, self.levels):
            on = (t >= start) & (t < start + width)
            s[on] = level
            if kind == "dwell":
                continue
            u = (t[on] - start) / width
            h = self.lift if kind == "rise" else -self.lift
            if shape == "cycloidal":
                f0, f1, f2 = u - np.sin(TWO_PI * u) / TWO_PI, 1 - np.cos(TWO_PI * u), TWO_PI * np.sin(TWO_PI * u)
            else:   # 3-4-5: 10u³ − 15u⁴ + 6u⁵
                f0 = 10 * u**3 - 15 * u**4 + 6 * u**5
                f1 = 30 * u**2 - 60 * u**3 + 30 * u**4
                f2 = 60 * u - 180 * u**2 + 120 * u**3
            s[on] += h * f0
            v[on] = h * f1 / width
            a[on] = h * f2 / width**2
        return s, v, a

    def pitch(self, theta) -> np.ndarray:
        theta = np.asarray(theta, dtype=float)
        s, _, _ = self.motion(theta)
        r = self.rb + self.rr + s
        return np.stack((r * np.sin(theta), r * np.cos(theta)), axis=-1)

    def profile(self, theta) -> np.ndarray:
        """X = P − Rr n, n = (r e_r + v e_t)/√(r² + v²), e_t = (−cos θ, sin θ)."""
        theta = np.asarray(theta, dtype=float)
        s, v, _ = self.motion(theta)
        r = self.rb + self.rr + s
        e_r = np.stack((np.sin(theta), np.cos(theta)), axis=-1)
        e_t = np.stack((-np.cos(theta), np.sin(theta)), axis=-1)
        n = (r[:, None] * e_r + v[:, None] * e_t) / np.hypot(r, v)[:, None]
        return r[:, None] * e_r - self.rr * n

    def pressure_angle(self, theta) -> np.ndarray:
        s, v, _ = self.motion(theta)
        return np.arctan2(v, self.rb + self.rr + s)

    def rho_pitch(self, theta) -> np.ndarray:
        """ρ = (r² + v²)^{3/2} / (r² + 2v² − a r) (mm, + convex)."""
        s, v, a = self.motion(theta)
        r = self.rb + self.rr + s
        with np.errstate(divide="ignore"):
            return (r * r + v * v) ** 1.5 / (r * r + 2 * v * v - a * r)

    def extremes(self) -> dict:
        """Largest and smallest pressure angle (rad) and where (rad); the smallest convex pitch radius (mm)."""
        from scipy.optimize import brentq, minimize_scalar

        def slope(t: float) -> float:
            s, v, a = self.motion(np.array([t]))
            return float(a[0] * (self.rb + self.rr + s[0]) - v[0] ** 2)

        grid = np.linspace(0.0, TWO_PI, 72001)
        phi = self.pressure_angle(grid)
        out = {}
        for name, index in (("max", int(np.argmax(phi))), ("min", int(np.argmin(phi)))):
            lo, hi = grid[max(index - 1, 0)], grid[min(index + 1, len(grid) - 1)]
            at = brentq(slope, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps) \
                if slope(lo) * slope(hi) < 0 else grid[index]
            out[name], out[f"{name}_at"] = float(self.pressure_angle(np.array([at]))[0]), float(at)
        rho = self.rho_pitch(grid)
        convex = np.where(rho > 0, rho, np.inf)
        index = int(np.argmin(convex))
        found = minimize_scalar(lambda t: float(self.rho_pitch(np.array([t]))[0]),
                                bounds=(grid[max(index - 1, 0)], grid[min(index + 1, len(grid) - 1)]),
                                method="bounded", options={"xatol": 1e-12})
        out["rho_pitch_min"], out["rho_pitch_min_at"] = float(found.fun), float(found.x)
        return out


def curve_distance(points: np.ndarray, curve, *, samples: int = 1 << 16, iterations: int = 56) -> np.ndarray:
    """Distance (mm) from each point to the closed curve X(t), t ∈ [0, 2π): the nearest of ``samples``
    curve points (by a k-d tree), then a golden-section search of |Q − X(t)|² over t ± 2Δ."""
    from scipy.spatial import cKDTree

    points = np.asarray(points, dtype=float)
    grid = np.linspace(0.0, TWO_PI, samples, endpoint=False)
    step = TWO_PI / samples
    _, nearest = cKDTree(curve(grid)).query(points)
    lo, hi = grid[nearest] - 2.0 * step, grid[nearest] + 2.0 * step

    def squared(t: np.ndarray) -> np.ndarray:
        d = points - curve(t)
        return np.einsum("ij,ij->i", d, d)

    inner, outer = hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo)
    f_inner, f_outer = squared(inner), squared(outer)
    for _ in range(iterations):
        left = f_inner < f_outer
        hi = np.where(left, outer, hi)
        lo = np.where(left, lo, inner)
        kept = np.where(left, f_inner, f_outer)
        inner, outer = (np.where(left, hi - GOLDEN * (hi - lo), outer),
                        np.where(left, inner, lo + GOLDEN * (hi - lo)))
        fresh = squared(np.where(left, inner, outer))
        f_inner, f_outer = np.where(left, fresh, kept), np.where(left, kept, fresh)
    return np.sqrt(np.minimum(np.minimum(f_inner, f_outer), np.minimum(squared(lo), squared(hi))))


def polyline_deviation(vertices: np.ndarray, curve, samples: int = 1 << 15) -> float:
    """Hausdorff distance (mm) between the closed polyline through ``vertices`` and the curve X(t): the
    larger of the distance of ``samples`` curve points to the polyline and of the vertices and the chords'
    quarter, half and three-quarter points to the curve."""
    from scipy.spatial import cKDTree

    vertices = np.asarray(vertices, dtype=float)
    n = len(vertices)
    dense = curve(np.linspace(0.0, TWO_PI, samples, endpoint=False))
    _, near = cKDTree(vertices).query(dense, k=min(3, n))
    near = near.reshape(len(dense), -1)
    best = np.full(len(dense), np.inf)
    for start in np.concatenate((near, (near - 1) % n), axis=1).T:
        a, b = vertices[start], vertices[(start + 1) % n]
        seg = b - a
        t = np.clip(np.einsum("ij,ij->i", dense - a, seg) / np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-300), 0, 1)
        gap = dense - (a + t[:, None] * seg)
        best = np.minimum(best, np.einsum("ij,ij->i", gap, gap))
    following = np.roll(vertices, -1, axis=0)
    chord_points = np.concatenate([vertices + f * (following - vertices) for f in (0.0, 0.25, 0.5, 0.75)])
    return max(float(np.sqrt(best.max())), float(curve_distance(chord_points, curve).max()))


# =============================================================================================
# The single-degree-of-freedom follower on a cycloidal dwell-rise-dwell-return law
# =============================================================================================

#: the law of the dynamics and Fourier rows: (kind, width deg) with cycloidal motions
SDOF_PHASES = (("dwell", 90.0), ("rise", 90.0), ("dwell", 90.0), ("return", 90.0))


def sdof_exact(rpm: float, fn_hz: float, zeta: float, lift: float, phases=SDOF_PHASES,
               grid: int = 256) -> tuple[np.ndarray, np.ndarray, float]:
    """(ÿ (mm/s²) and x = y − s (mm) at θ_j = 2πj/grid, peak rigid acceleration (mm/s²)).

    In θ, x'' + 2ζρ x' + ρ² x = −a(θ), ρ = ωn/ω; on each phase the forcing is 0 (dwell) or ∓(2πh/β²)
    sin(2πu), u = (θ − θ0)/β, so with the state [x, x', sin 2πu, cos 2πu] it is z' = A z with a constant
    A per phase; the cycle map is a product of exponentials and the periodic state solves (I − M) z0 = b.
    """
    from scipy.linalg import expm

    omega = TWO_PI * rpm / 60.0
    ratio = TWO_PI * fn_hz / omega
    k, c = ratio * ratio, 2 * zeta * ratio
    starts, matrices, position = [], [], 0.0
    for kind, width in phases:
        beta = math.radians(width)
        p = TWO_PI / beta
        amplitude = {"rise": 1.0, "return": -1.0, "dwell": 0.0}[kind] * TWO_PI * lift / beta**2
        matrices.append(np.array([[0.0, 1.0, 0.0, 0.0], [-k, -c, -amplitude, 0.0], [0.0, 0.0, 0.0, p],
                                  [0.0, 0.0, -p, 0.0]]))
        starts.append((math.radians(position), beta))
        position += width
    transfers = [expm(a * beta) for a, (_, beta) in zip(matrices, starts)]
    m, b = np.eye(2), np.zeros(2)
    for e in transfers:
        m, b = e[:2, :2] @ m, e[:2, :2] @ b + e[:2, 3]
    state = np.linalg.solve(np.eye(2) - m, b)
    phase_states = []
    for e in transfers:
        phase_states.append(state.copy())
        state = e[:2, :2] @ state + e[:2, 3]
    theta = TWO_PI * np.arange(grid) / grid
    accel, error = np.empty(grid), np.empty(grid)
    for j, th in enumerate(theta):
        i = max(index for index, (start, _) in enumerate(starts) if start <= th + 1e-15)
        z = expm(matrices[i] * (th - starts[i][0])) @ np.array([*phase_states[i], 0.0, 1.0])
        accel[j] = -omega**2 * (k * z[0] + c * z[1])
        error[j] = z[0]
    width = min(math.radians(w) for kind, w in phases if kind != "dwell")
    return accel, error, TWO_PI * lift / width**2 * omega**2


def cycloidal_coefficients(phases, lift: float, harmonics: int) -> np.ndarray:
    """c_k (k = 1..N) of s(θ) = Σ c_k e^{ikθ} + c.c. for cycloidal motions (period 2π, ``phases`` as
    (kind, width deg)): c_k(a) = (h/2π)·4π² e^{−ikθ1}(1 − e^{−ikβ})/(β(4π² − k²β²)), c_k(s) = −c_k(a)/k²
    (valid where kβ is not a whole turn)."""
    w = np.arange(1, harmonics + 1, dtype=float)
    total = np.zeros(harmonics, dtype=complex)
    position = 0.0
    for kind, width in phases:
        if kind != "dwell":
            theta1, beta = math.radians(position), math.radians(width)
            h = lift if kind == "rise" else -lift
            total += h * 4 * math.pi**2 * np.exp(-1j * w * theta1) * (1 - np.exp(-1j * w * beta)) / (
                TWO_PI * beta * (4 * math.pi**2 - w**2 * beta**2))
        position += width
    return -total / w**2


# =============================================================================================
# Balance of a drawn polyline
# =============================================================================================


def simpson_integrals(x: np.ndarray, a: np.ndarray, end: float) -> tuple[float, float]:
    """v(end) and s(end) of the polyline a(θ) from rest: per segment the integrands a(τ) and (end − τ) a(τ)
    are of degree 1 and 2, so the trapezoid and Simpson's rule are exact there; summed with math.fsum."""
    keep = x <= end
    xs, ys = x[keep], a[keep]
    if xs[-1] < end:
        xs = np.append(xs, end)
        ys = np.append(ys, np.interp(end, x, a))
    h = np.diff(xs)
    v = math.fsum((h * (ys[:-1] + ys[1:]) / 2).tolist())
    mid = (xs[:-1] + xs[1:]) / 2
    f0, f1, fm = (end - xs[:-1]) * ys[:-1], (end - xs[1:]) * ys[1:], (end - mid) * (ys[:-1] + ys[1:]) / 2
    return v, math.fsum((h / 6 * (f0 + 4 * fm + f1)).tolist())


def simpson_closure(x: np.ndarray, a: np.ndarray, motion_ends, lift: float) -> float:
    """The largest residual of the balance (v at each motion's end, s at the cycle's end) over the lift."""
    residuals = [simpson_integrals(x, a, end)[0] for end in motion_ends]
    residuals.append(simpson_integrals(x, a, float(x[-1]))[1])
    return max(abs(r) for r in residuals) / lift
