"""Floors: the least work each camcad kernel does, written again with numpy alone (and LAPACK's banded solve).

A floor computes the same figures as the camcad kernel it stands beside, from the same input, by the
shortest numpy route its author could write; ``camcad bench`` times both in one run and checks that the
floor reproduces camcad's figures. Nothing here imports camcad (tests/report/test_bench_floors.py checks it), so
a floor is a second implementation, not camcad's code timed twice.

- ``profile_floor``: a translating roller follower without offset on a cam of cycloidal and 3-4-5 motions
  and dwells: chords within a tolerance (profile and pitch curve), extremes of the pressure angle per phase
  and of the radius of curvature, the law's table.
- ``min_change_floor``: the least change ∫δa² dθ of a drawn acceleration polyline that closes the velocity
  at the end of each motion phase and the displacement over the cycle and keeps the rise (a tridiagonal
  Gram matrix, LAPACK ``gtsv`` through ``scipy.linalg.solve_banded``).
- ``sweep_floor``: the periodic response of the single-degree-of-freedom elastic follower at many speeds,
  one broadcast over the speeds of the harmonics of the sampled displacement.
- ``fourier_floor``: harmonics of s and a of a sampled law by one real FFT each.
- ``table_floor``: a numeric two-column table by ``numpy.loadtxt``.
"""

from __future__ import annotations

import math
from itertools import pairwise

import numpy as np

TWO_PI = 2.0 * math.pi

# =============================================================================================
# The law: cycloidal and 3-4-5 motions between dwells, in closed form
# =============================================================================================


def _shape(name: str, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """f, f', f'', f''' of a normalised rise on u ∈ [0, 1]."""
    if name == "cycloidal":
        w = TWO_PI * u
        sin, cos = np.sin(w), np.cos(w)
        return u - sin / TWO_PI, 1.0 - cos, TWO_PI * sin, TWO_PI**2 * cos
    if name == "poly345":
        u2 = u * u
        return (u2 * u * (10.0 + u * (-15.0 + 6.0 * u)), u2 * (30.0 + u * (-60.0 + 30.0 * u)),
                u * (60.0 + u * (-180.0 + 120.0 * u)), 60.0 + u * (-360.0 + 360.0 * u))
    raise ValueError(f"no closed form here for {name!r}")


class Law:
    """s, v, a, j (mm, per rad) of a cycle of motions and dwells; ``segments`` are (kind, width deg, shape)
    with kind "rise", "return" or "dwell" and one lift for every motion."""

    def __init__(self, segments, lift: float) -> None:
        widths = np.radians([w for _, w, _ in segments])
        self.starts = np.concatenate(([0.0], np.cumsum(widths)[:-1]))
        self.widths = widths
        self.kinds = [k for k, _, _ in segments]
        self.shapes = [s for _, _, s in segments]
        self.lift = float(lift)
        levels, level = [], 0.0
        for kind in self.kinds:
            levels.append(level)
            level += {"rise": lift, "return": -lift}.get(kind, 0.0)
        self.levels = np.array(levels)
        self.breaks = np.concatenate((self.starts, [TWO_PI]))

    def __call__(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        t = np.mod(theta, TWO_PI)
        index = np.clip(np.searchsorted(self.starts, t, side="right") - 1, 0, len(self.starts) - 1)
        s = self.levels[index].astype(float)
        v, a, j = np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)
        for k, kind in enumerate(self.kinds):
            if kind == "dwell":
                continue
            on = index == k
            beta = self.widths[k]
            h = self.lift if kind == "rise" else -self.lift
            f0, f1, f2, f3 = _shape(self.shapes[k], (t[on] - self.starts[k]) / beta)
            s[on] += h * f0
            v[on] = h * f1 / beta
            a[on] = h * f2 / beta**2
            j[on] = h * f3 / beta**3
        return s, v, a, j


# =============================================================================================
# Profile: translating roller, no offset, cam turning counter-clockwise (follower on +y)
# =============================================================================================


def _pitch(law: Law, prime: float, theta: np.ndarray):
    """Roller centre P = r e_r (r = Rp + s, e_r = (sin θ, cos θ)), its unit normal n, speed |P'|, signed
    radius of curvature ρ (+ convex), pressure angle φ = atan(v/r)."""
    s, v, a, _ = law(theta)
    r = prime + s
    sin, cos = np.sin(theta), np.cos(theta)
    speed = np.hypot(r, v)
    point = np.stack((r * sin, r * cos), axis=-1)
    # n = (r e_r + v e_t)/|P'|, e_t = (−cos θ, sin θ)
    normal = np.stack((r * sin - v * cos, r * cos + v * sin), axis=-1) / speed[:, None]
    with np.errstate(divide="ignore"):
        rho = speed**3 / (r * r + 2.0 * v * v - a * r)
    return point, normal, speed, rho, np.arctan2(v, r)


def _curves(law: Law, prime: float, roller: float, theta: np.ndarray):
    """Profile and pitch curve at θ: points (2, N, 2), speeds (2, N), radii (2, N)."""
    point, normal, speed, rho, _ = _pitch(law, prime, theta)
    profile = point - roller * normal
    with np.errstate(divide="ignore", invalid="ignore"):
        stretch = np.abs(1.0 - roller / rho)
    return np.stack((profile, point)), np.stack((speed * stretch, speed)), np.stack((rho - roller, rho))


def _segment_distance(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    d = b - a
    t = np.clip(np.einsum("...k,...k->...", points - a, d) / np.maximum(np.einsum("...k,...k->...", d, d),
                                                                         1e-300), 0.0, 1.0)
    gap = points - (a + t[..., None] * d)
    return np.sqrt(np.einsum("...k,...k->...", gap, gap))


def _place(cum: np.ndarray, grid: np.ndarray, breaks: np.ndarray) -> np.ndarray:
    """Nodes that share the predicted chord count evenly between consecutive breaks."""
    at = np.interp(breaks, grid, cum)
    nodes = [breaks[:1]]
    for (c0, c1), (t0, t1) in zip(pairwise(at), pairwise(breaks)):
        count = max(1, math.ceil(c1 - c0))
        nodes.append(np.interp(np.linspace(c0, c1, count + 1)[1:], cum, grid) if c1 > c0
                     else np.linspace(t0, t1, count + 1)[1:])
    out = np.concatenate(nodes)
    out[-1] = breaks[-1]
    return out


def _chords(law: Law, prime: float, roller: float, tol: float, breaks: np.ndarray) -> list[np.ndarray]:
    """Nodes (rad) of the profile's and the pitch curve's chords within ``tol`` (sagitta c²/(8ρ) ≤ tol)."""
    pilot = np.unique(np.concatenate((np.linspace(0.0, TWO_PI, 2049), breaks)))
    _, speed, rho = _curves(law, prime, roller, pilot)
    density = speed / np.sqrt(8.0 * np.maximum(np.abs(rho), tol / 8.0) * 0.8 * tol)
    density = np.where(np.isfinite(density), density, 0.0)
    cum = np.concatenate((np.zeros((2, 1)), np.cumsum(np.diff(pilot) * (density[:, 1:] + density[:, :-1]) / 2,
                                                      axis=1)), axis=1)
    nodes = [_place(cum[c], pilot, breaks) for c in range(2)]
    for _ in range(60):
        sizes = [len(n) for n in nodes]
        frac = np.arange(1, 8) / 8.0
        inner = [(n[:-1, None] + np.diff(n)[:, None] * frac).ravel() for n in nodes]
        theta = np.concatenate(nodes + inner)
        points, _, _ = _curves(law, prime, roller, theta)
        bad_any = False
        offset = sum(sizes)
        for c, n in enumerate(nodes):
            start = sum(sizes[:c])
            ends = points[c, start:start + len(n)]
            chunk = points[c, offset:offset + 7 * (len(n) - 1)].reshape(len(n) - 1, 7, 2)
            offset += 7 * (len(n) - 1)
            deviation = _segment_distance(chunk, ends[:-1, None], ends[1:, None]).max(axis=1)
            bad = deviation > 0.97 * tol
            if bad.any():
                bad_any = True
                nodes[c] = np.sort(np.concatenate((n, (n[:-1][bad] + n[1:][bad]) / 2.0)))
        if not bad_any:
            return nodes
    raise RuntimeError("the chords did not meet the tolerance")


def _zoom(function, lo: np.ndarray, hi: np.ndarray, levels: int = 3, samples: int = 17):
    """Largest value of each row's function on [lo, hi] by zooming grids, all rows per evaluation:
    ``function(theta (rows, m)) -> values (rows, m)``. Returns (value, at)."""
    rows = np.arange(len(lo))
    best = np.full(len(lo), -np.inf)
    at = lo.copy()
    for _ in range(levels):
        grid = lo[:, None] + (hi - lo)[:, None] * np.linspace(0.0, 1.0, samples)
        values = function(grid)
        k = np.argmax(values, axis=1)
        better = values[rows, k] > best
        best = np.where(better, values[rows, k], best)
        at = np.where(better, grid[rows, k], at)
        step = (hi - lo) / (samples - 1)
        lo, hi = np.maximum(at - step, lo), np.minimum(at + step, hi)
    # the function at the vertex of the parabola through the best point and its neighbours
    h = (hi - lo) / 2.0
    values = function(np.stack((at - h, at, at + h), axis=1))
    curvature = values[:, 0] - 2.0 * values[:, 1] + values[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        shift = np.where(curvature < 0.0, 0.5 * h * (values[:, 0] - values[:, 2]) / curvature, 0.0)
    shift = np.where(np.isfinite(shift) & (np.abs(shift) <= h), shift, 0.0)
    there = function((at + shift)[:, None])[:, 0]
    better = there > best
    return np.where(better, there, best), np.where(better, at + shift, at)


def profile_floor(segments, lift: float, base_radius: float, roller_radius: float, tol: float = 1e-3,
                  step_deg: float = 0.1, table_step_deg: float = 0.5) -> dict:
    """The figures of a roller cam's synthesis (module docstring), numpy only.

    Returns a dict: ``profile`` and ``pitch`` (N, 2) chord nodes (mm, the cam's frame), ``phi_max``,
    ``phi_min`` (rad) with ``phi_max_at``, ``phi_min_at`` (rad), ``rho_pitch_min`` and ``rho_profile_min``
    (smallest convex radii, mm), ``rho_pitch_min_at`` (rad), ``table`` (θ, s, v, a, j, φ, ρ at the table
    step) and ``closure_gap`` (mm).
    """
    law = Law(segments, lift)
    prime = base_radius + roller_radius
    breaks = law.breaks
    grid = np.unique(np.concatenate((np.linspace(0.0, TWO_PI, round(360.0 / step_deg) + 1), breaks)))
    _, _, _, rho, phi = _pitch(law, prime, grid)
    convex = np.where(rho > 0.0, rho, np.inf)
    picks = np.array([np.argmax(phi), np.argmin(phi), np.argmin(convex)])
    lo = grid[np.maximum(picks - 1, 0)]
    hi = grid[np.minimum(picks + 1, len(grid) - 1)]
    signs = np.array([1.0, -1.0])

    def objective(theta: np.ndarray) -> np.ndarray:
        shape = theta.shape
        _, _, _, r, p = _pitch(law, prime, theta.ravel())
        r, p = r.reshape(shape), p.reshape(shape)
        out = np.empty(shape)
        out[:2] = signs[:, None] * p[:2]
        out[2] = -np.where(r[2] > 0.0, r[2], np.inf)
        return out

    value, at = _zoom(objective, lo, hi)
    profile_nodes, pitch_nodes = _chords(law, prime, roller_radius, tol, breaks)
    ends, _, _ = _curves(law, prime, roller_radius, np.concatenate((profile_nodes, pitch_nodes)))
    table_theta = np.linspace(0.0, TWO_PI, round(360.0 / table_step_deg) + 1)
    s, v, a, j = law(table_theta)
    _, _, _, table_rho, table_phi = _pitch(law, prime, table_theta)
    profile = ends[0, :len(profile_nodes)]
    return {"profile": profile, "pitch": ends[1, len(profile_nodes):], "phi_max": float(value[0]),
            "phi_max_at": float(at[0]), "phi_min": float(-value[1]), "phi_min_at": float(at[1]),
            "rho_pitch_min": float(-value[2]), "rho_pitch_min_at": float(at[2]),
            "rho_profile_min": float(-value[2] - roller_radius),
            "table": (table_theta, s, v, a, j, table_phi, table_rho),
            "closure_gap": float(np.hypot(*(profile[-1] - profile[0])))}


# =============================================================================================
# Min-change balancing of a drawn acceleration polyline
# =============================================================================================


def _weights(x: np.ndarray, end: float, quantity: str) -> np.ndarray:
    """w with Σ w_k a_k = v(end) ("v") or s(end) ("s") for the polyline a through the knots x from rest."""
    n = len(x)
    w = np.zeros(n)
    k = int(np.searchsorted(x, end, side="right")) - 1        # the segment that holds end
    length = np.diff(x[: k + 1])
    if quantity == "v":
        half = length / 2.0
        w[:k] += half
        w[1:k + 1] += half
    else:
        d = end - x[:k]
        w[:k] += length * (d / 2.0 - length / 6.0)
        w[1:k + 1] += length * (d / 2.0 - length / 3.0)
    if k < n - 1 and x[k] < end:                              # the part of segment k before end
        part, seg = end - x[k], x[k + 1] - x[k]
        t = part / seg
        first, second = (part / 2.0, part / 2.0) if quantity == "v" else (part * part / 3.0, part * part / 6.0)
        w[k] += first + second * (1.0 - t)
        w[k + 1] += second * t
    return w


def phase_areas(x: np.ndarray, a: np.ndarray, bounds) -> np.ndarray:
    """(∫ max(a, 0), ∫ min(a, 0)) over each (start, end) of ``bounds`` whose ends are knots of x, shape
    (phases, 2); each segment is split where a crosses zero."""
    length = np.diff(x)
    a0, a1 = a[:-1], a[1:]
    crossing = a0 * a1 < 0
    cut = np.where(crossing, length * a0 / np.where(crossing, a0 - a1, 1.0), length)
    left = np.where(crossing, cut * a0 / 2.0, length * (a0 + a1) / 2.0)
    right = np.where(crossing, (length - cut) * a1 / 2.0, 0.0)
    out = np.empty((len(bounds), 2))
    for row, (start, end) in enumerate(bounds):
        i, j = np.searchsorted(x, [start, end])
        pieces = np.concatenate((left[i:j], right[i:j]))
        out[row] = pieces[pieces > 0].sum(), pieces[pieces < 0].sum()
    return out


def min_change_floor(x: np.ndarray, a: np.ndarray, motions, dwells, rises, phases=()) -> dict:
    """The least-∫δa² change of the drawn law (x rad, a mm/rad²) that brings v back to 0 at the end of each
    motion (``motions``: end angles, rad), s(cycle) to 0, and keeps s over each rise (``rises``: (start,
    end), rad); vertices on the axis (|a| ≤ 1e-6 max|a|) or inside a dwell (``dwells``: (start, end)) stay,
    the two vertices of a jump move together.

    Returns a dict: ``a`` (the corrected ordinates), ``residuals`` (the conditions after, mm/rad and mm),
    ``rms_change`` (mm/rad², the RMS of δa over the cycle, exact for the polylines), and ``areas_before``,
    ``areas_after`` of each of ``phases`` ((start, end), rad; see ``phase_areas``).
    """
    from scipy.linalg import solve_banded

    cycle = float(x[-1])
    rows = [_weights(x, end, "v") for end in motions] + [_weights(x, cycle, "s")]
    rows += [_weights(x, end, "s") - _weights(x, start, "s") for start, end in rises]
    C = np.array(rows)
    goal = np.zeros(len(rows))
    goal[len(motions) + 1:] = C[len(motions) + 1:] @ a
    free = np.abs(a) > 1e-6 * np.max(np.abs(a))
    for start, end in dwells:
        free &= ~((x > start) & (x < end))
    node = np.concatenate(([0], np.cumsum(np.diff(x) != 0)))       # a jump's two vertices: one node
    idx = np.flatnonzero(free)
    nodes, column = np.unique(node[idx], return_inverse=True)
    k = len(nodes)
    # Gram matrix BᵀMB of the node columns: M is the polyline's tridiagonal mass matrix
    length = np.diff(x)
    diag_m = np.zeros(len(x))
    diag_m[:-1] += length / 3.0
    diag_m[1:] += length / 3.0
    diag = np.zeros(k)
    np.add.at(diag, column, diag_m[idx])
    upper = np.zeros(k)            # G[c, c+1]
    nxt = idx[:-1] + 1
    linked = (nxt == idx[1:]) & (column[1:] == column[:-1] + 1)
    np.add.at(upper, column[:-1][linked], length[idx[:-1][linked]] / 6.0)
    A = np.zeros((len(rows), k))
    np.add.at(A.T, column, C[:, idx].T)
    band = np.zeros((3, k))
    band[0, 1:] = upper[:-1]
    band[1] = diag
    band[2, :-1] = upper[:-1]
    g_inv_at = solve_banded((1, 1), band, A.T)
    y = np.linalg.solve(A @ g_inv_at, goal - C @ a)
    delta = np.zeros(len(x))
    delta[idx] = (g_inv_at @ y)[column]
    fixed = a + delta
    # RMS of δa over the cycle: ∫ of the square of the linear δ on each segment
    d0, d1 = delta[:-1], delta[1:]
    rms = math.sqrt(float(np.sum(length * (d0 * d0 + d0 * d1 + d1 * d1) / 3.0)) / cycle)
    # each phase's end velocity and displacement, before and after
    ends = np.array([t for pair in phases for t in pair])
    return {"a": fixed, "residuals": C @ fixed - goal, "rms_change": rms, "max_change": float(np.max(np.abs(delta))),
            "residuals_before": C @ a - goal, "areas_before": phase_areas(x, a, phases),
            "areas_after": phase_areas(x, fixed, phases), "phase_motion_before": motion_at(x, a, ends),
            "phase_motion_after": motion_at(x, fixed, ends)}


def motion_at(x: np.ndarray, a: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """(v, s) at each θ of the polyline a from rest at x[0], shape (2, len(θ)): one cumulative integration at
    the knots, then the cut segment (v = v_k + a_k τ + Δa τ²/(2L), s = s_k + v_k τ + a_k τ²/2 + Δa τ³/(6L))."""
    length = np.diff(x)
    a0, a1 = a[:-1], a[1:]
    v = np.concatenate(([0.0], np.cumsum(length * (a0 + a1) / 2.0)))
    s = np.concatenate(([0.0], np.cumsum(length * v[:-1] + length**2 * (2.0 * a0 + a1) / 6.0)))
    k = np.clip(np.searchsorted(x, theta, side="right") - 1, 0, len(x) - 2)
    tau, seg = theta - x[k], length[k]
    slope = np.divide(a[k + 1] - a[k], seg, out=np.zeros_like(seg), where=seg > 0)
    return np.stack((v[k] + a[k] * tau + slope * tau**2 / 2.0,
                     s[k] + v[k] * tau + a[k] * tau**2 / 2.0 + slope * tau**3 / 6.0))


# =============================================================================================
# Elastic follower over a speed range: one broadcast over the speeds
# =============================================================================================


def sweep_floor(s: np.ndarray, a: np.ndarray, cycle: float, fn_hz: float, zeta: float, speeds_rpm,
                chunk: int = 32) -> dict:
    """Periodic response of ẍ + 2ζωn ẋ + ωn² x = −ω² a(θ) at each speed from the samples s, a (mm, mm/rad²)
    of one cycle: X_k = Ω_k² S_k/(ωn² − Ω_k² + 2iζωnΩ_k), Ω_k = kνω. Returns per speed ``peak_ratio``
    (max|ÿ|/max|s̈|) and ``error_max`` (max|x|, mm), and ``accel`` (speeds, N) of ÿ (mm/s²)."""
    n = len(s)
    coefficients = np.fft.rfft(s) / n
    orders = TWO_PI / cycle * np.arange(len(coefficients))
    wn = TWO_PI * fn_hz
    speeds = np.asarray(speeds_rpm, dtype=float)
    omega = TWO_PI * speeds / 60.0
    peak_rigid = np.max(np.abs(a)) * omega**2
    accel = np.empty((len(speeds), n))
    error = np.empty(len(speeds))
    for first in range(0, len(speeds), chunk):
        big = orders[None, :] * omega[first:first + chunk, None]
        x_k = big**2 * coefficients / (wn**2 - big**2 + 2j * zeta * wn * big)
        x_k[:, -1] = 0.0
        y_k = -big**2 * (coefficients + x_k)
        y_k[:, -1] = 0.0
        accel[first:first + chunk] = np.fft.irfft(y_k * n, n, axis=1)
        error[first:first + chunk] = np.max(np.abs(np.fft.irfft(x_k * n, n, axis=1)), axis=1)
    return {"peak_ratio": np.max(np.abs(accel), axis=1) / peak_rigid, "error_max": error, "accel": accel}


# =============================================================================================
# Fourier coefficients and tables
# =============================================================================================


def fourier_floor(s: np.ndarray, a: np.ndarray, harmonics: int) -> dict:
    """A_k = 2|c_k| (k = 1..N) of the samples s (mm) and a (mm/rad²) of one cycle, by ``numpy.fft.rfft``;
    ``mean`` the constant term of s."""
    n = len(s)
    cs, ca = np.fft.rfft(s) / n, np.fft.rfft(a) / n
    return {"amplitudes": 2.0 * np.abs(cs[1:harmonics + 1]), "accel_amplitudes": 2.0 * np.abs(ca[1:harmonics + 1]),
            "coefficients": cs[1:harmonics + 1], "mean": float(cs[0].real)}


def table_floor(path) -> np.ndarray:
    """The rows of a comma-separated numeric table with one header line, by ``numpy.loadtxt`` (rows, columns)."""
    return np.loadtxt(path, delimiter=",", skiprows=1, comments="#", ndmin=2)
