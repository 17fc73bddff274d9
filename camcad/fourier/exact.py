"""Exact Fourier coefficients: composite standard laws (piecewise elementary functions) and drawn
laws (piecewise-linear acceleration), by integration by parts over the pieces (see camcad.fourier).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import cast

import numpy as np

from camcad.law import standard
from camcad.law.law import PiecewiseLinearLaw
from camcad.numerics import hurwitz_zeta

EPS = float(np.finfo(float).eps)
#: below this |z| the monomial moments E_m(z) are integrated by Gauss–Legendre, above by recurrence
_SMALL_Z = 8.0
#: derivative orders whose jumps enter the remainder estimate of the composite laws
TAIL_ORDERS = 7
#: elements per block when a (points × harmonics) matrix of exponentials is formed
_BLOCK = 1 << 21



# =============================================================================================
# Exact analysis: piecewise elementary functions (composite standard laws)
# =============================================================================================

@functools.lru_cache(maxsize=64)
def gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes and weights of n-point Gauss–Legendre on [0, 1] (computed once per n; read-only)."""
    nodes, weights = np.polynomial.legendre.leggauss(n)
    nodes, weights = (nodes + 1.0) / 2.0, weights / 2.0
    nodes.flags.writeable = False
    weights.flags.writeable = False
    return nodes, weights


def monomial_moments(z: np.ndarray, degree: int) -> np.ndarray:
    """E_m(z) = ∫_0^1 u^m e^{−izu} du for m = 0..degree, shape (degree+1, len(z)); exact to round-off.

    |z| < 8: 48-point Gauss–Legendre (exact for the polynomial, the exponential's Taylor series is
    below round-off past degree 45). |z| ≥ 8: E_0 = e^{−iz/2} sin(z/2)/(z/2) and upward recurrence
    E_m = (m E_{m−1} − e^{−iz})/(iz), whose error grows by m/|z| ≤ 1 per step for m ≤ 8.

    Parameters
    ----------
    z : ndarray
        The arguments (dimensionless).
    degree : int
        The highest m.

    Returns
    -------
    ndarray
        E_m(z), complex, dimensionless.

    Examples
    --------
    At z = 0, E_m = 1/(m + 1):

    >>> import numpy as np
    >>> from camcad.fourier import monomial_moments
    >>> [round(float(e.real), 12) for e in monomial_moments(np.array([0.0]), 2)[:, 0]]
    [1.0, 0.5, 0.333333333333]
    """
    z = np.asarray(z, dtype=float)
    out = np.empty((degree + 1, len(z)), dtype=complex)
    small = np.abs(z) < _SMALL_Z
    if small.any():
        nodes, weights = gauss_legendre(48)
        kernel = np.exp(-1j * np.outer(nodes, z[small])) * weights[:, None]
        powers = nodes[None, :] ** np.arange(degree + 1)[:, None]
        out[:, small] = powers @ kernel
    big = ~small
    if big.any():
        zb = z[big]
        edge = np.exp(-1j * zb)
        current = np.exp(-0.5j * zb) * np.sinc(zb / (2.0 * np.pi))
        out[0, big] = current
        for m in range(1, degree + 1):
            current = (m * current - edge) / (1j * zb)
            out[m, big] = current
    return out


@dataclass(frozen=True)
class Piece:
    """f(θ) = Σ_m poly[m] t^m + Σ_j amps[j] e^{i rates[j] t} (real part), t = θ − start ∈ [0, length].

    ``composite_pieces`` makes them from a standard law; the example is there.

    Attributes
    ----------
    start, length : float
        Where the piece starts and how long it is, rad.
    poly : ndarray
        The polynomial's coefficients, mm per rad^m.
    rates : ndarray
        The exponentials' rates, per rad.
    amps : ndarray
        Their complex amplitudes, mm.
    """

    start: float
    length: float
    poly: np.ndarray
    rates: np.ndarray = field(default_factory=lambda: np.zeros(0))
    amps: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=complex))

    def derivative(self, order: int) -> Piece:
        if order == 0:
            return self
        poly = np.polynomial.polynomial.polyder(self.poly, order) if len(self.poly) > order else np.zeros(1)
        return Piece(self.start, self.length, poly, self.rates, self.amps * (1j * self.rates) ** order)

    def values(self, t, order: int = 0) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        piece = self.derivative(order)
        out = np.polynomial.polynomial.polyval(t, piece.poly) + 0.0 * t
        if len(piece.amps):
            out = out + np.real(np.exp(1j * np.multiply.outer(t, piece.rates)) @ piece.amps)
        return out

    def derivatives(self, t: float, first: int, count: int) -> np.ndarray:
        """f^(m)(t) for m = first … first + count − 1, at one t (all orders at once)."""
        t = float(t)
        poly = [float(c) for c in self.poly]
        values = [math.fsum(c * math.perm(n, m) * t ** (n - m) for n, c in enumerate(poly) if n >= m and c != 0.0)
                  for m in range(first, first + count)]          # d^m t^n = n!/(n − m)! t^(n − m)
        out = np.array(values)
        if len(self.amps):
            orders = np.arange(first, first + count)
            waves = self.amps * np.exp(1j * self.rates * t)
            out += np.real((1j * self.rates[None, :]) ** orders[:, None] @ waves)
        return out

    def transform(self, w: np.ndarray) -> np.ndarray:
        """∫ over the piece of f(θ) e^{−iwθ} dθ for each w (complex)."""
        w = np.asarray(w, dtype=float)
        length = self.length
        total = np.zeros(len(w), dtype=complex)
        used = np.flatnonzero(self.poly)
        if len(used):
            poly = np.asarray(self.poly[:used[-1] + 1], dtype=float)
            moments = monomial_moments(w * length, len(poly) - 1)
            scale = poly * length ** np.arange(1, len(poly) + 1)
            total += scale @ moments
        if len(self.amps):
            half = (self.rates[:, None] - w[None, :]) * (length / 2.0)
            total += (self.amps * length) @ (np.exp(1j * half) * np.sinc(half / np.pi))
        return total * np.exp(-1j * w * self.start)

    def integral_of_square(self) -> float:
        """∫ f² over the piece, Gauss–Legendre with enough nodes to be exact to round-off."""
        rate = float(np.max(np.abs(self.rates))) if len(self.rates) else 0.0
        n = int(len(self.poly) + 24 + math.ceil(rate * self.length))
        nodes, weights = gauss_legendre(n)
        values = self.values(nodes * self.length)
        return float(self.length * np.sum(weights * values**2))

    def scale(self) -> float:
        """Σ |terms| over the piece: the size against which round-off is measured."""
        poly = np.abs(self.poly) * self.length ** np.arange(1, len(self.poly) + 1)
        return float(poly.sum() + np.abs(self.amps).sum() * self.length)


def shape_terms(shape) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """A standard rise shape as f(u) = Σ p_m u^m + Re Σ c_j e^{iλ_j u}: (p, λ, c), or None if unknown.

    Cycloidal f = u − sin(2πu)/(2π); harmonic f = (1 − cos πu)/2; polynomials as they are. The
    decomposition is checked against ``shape.evaluate`` (orders 0 and 2) before it is trusted.

    Parameters
    ----------
    shape : object
        A shape of ``camcad.law.standard``.

    Returns
    -------
    tuple of ndarray, optional
        p, λ and c (dimensionless: unit lift over unit width), or None.

    Examples
    --------
    >>> from camcad.law.standard import SHAPES
    >>> from camcad.fourier import shape_terms
    >>> p, rates, amps = shape_terms(SHAPES["harmonic"])       # (1 - cos(pi u))/2
    >>> [round(float(x), 12) for x in p], sorted(round(float(r), 12) for r in rates)   # cos as two exponentials
    ([0.5], [-3.14159265359, 3.14159265359])
    """
    two_pi = 2.0 * np.pi
    if isinstance(shape, standard.Cycloidal):
        terms = (np.array([0.0, 1.0]), np.array([two_pi, -two_pi]),
                 np.array([0.5j / two_pi, -0.5j / two_pi]))
    elif isinstance(shape, standard.SimpleHarmonic):
        terms = (np.array([0.5]), np.array([np.pi, -np.pi]), np.array([-0.25, -0.25], dtype=complex))
    elif isinstance(shape, standard.Polynomial):
        terms = (np.asarray(shape.coefficients, dtype=float), np.zeros(0), np.zeros(0, dtype=complex))
    else:
        return None
    piece = Piece(0.0, 1.0, *terms)
    u = np.array([0.0, 0.13, 0.37, 0.5, 0.71, 0.93, 1.0])
    for order in (0, 2):
        expected = np.asarray(shape.evaluate(u, order), dtype=float)
        if np.max(np.abs(piece.values(u, order) - expected)) > 1e-11 * (1.0 + np.max(np.abs(expected))):
            return None
    return terms


def composite_pieces(law) -> list[Piece] | None:
    """The displacement of a standard law (``camcad.compose``) as elementary pieces, or None for an unknown shape.

    Made once per law (a law is immutable and hashable; an unhashable one is decomposed each time).

    Parameters
    ----------
    law : CompositeLaw
        A law made by ``camcad.compose`` (θ in rad, s in mm).

    Returns
    -------
    list of Piece, optional
        One piece per phase (rad, mm), or None.

    Examples
    --------
    >>> import numpy as np
    >>> import camcad
    >>> law = camcad.compose([("dwell", 70), ("rise", 100), ("dwell", 110), ("return", 80)], 25.0)
    >>> from camcad.fourier import composite_pieces
    >>> pieces = composite_pieces(law)
    >>> [round(float(np.degrees(p.length)), 9) for p in pieces]
    [70.0, 100.0, 110.0, 80.0]
    """
    try:
        found = _cached_pieces(law)
    except TypeError:
        return _pieces_or_none(law)
    return None if found is None else list(found)


@functools.lru_cache(maxsize=32)
def _cached_pieces(law) -> tuple[Piece, ...] | None:
    found = _pieces_or_none(law)
    return None if found is None else tuple(found)


def _pieces_or_none(law) -> list[Piece] | None:
    try:
        return _composite_pieces(law)
    except (AttributeError, TypeError, ValueError):  # a composite law of another make: sample it instead
        return None


def _composite_pieces(law) -> list[Piece] | None:
    pieces: list[Piece] = []
    level = 0.0
    position = 0.0
    for segment in law.segments:
        width = segment.end - segment.start
        if abs(segment.start - position) > 1e-12 * law.cycle or width <= 0:
            return None
        position = segment.end
        if segment.kind == "dwell":
            pieces.append(Piece(segment.start, width, np.array([level])))
            continue
        terms = shape_terms(segment.shape)
        if terms is None:
            return None
        poly_u, rates_u, amps = terms
        lift = segment.lift if segment.kind == "rise" else -segment.lift
        poly = lift * poly_u / width ** np.arange(len(poly_u))
        poly[0] += level
        pieces.append(Piece(segment.start, width, poly, rates_u / width, lift * amps))
        level += lift
    if abs(position - law.cycle) > 1e-12 * law.cycle:
        return None
    return pieces


def checked_pieces(law) -> list[Piece] | None:
    """The law's elementary pieces (``composite_pieces``) when they reproduce its s and a, else None; decided
    once per (hashable) law."""
    try:
        found = _checked(law)
    except TypeError:
        pieces = _pieces_or_none(law)
        return pieces if pieces is not None and _pieces_check(law, pieces) else None
    return None if found is None else list(found)


@functools.lru_cache(maxsize=32)
def _checked(law) -> tuple[Piece, ...] | None:
    pieces = composite_pieces(law)
    return tuple(pieces) if pieces is not None and _pieces_check(law, pieces) else None


def _pieces_check(law, pieces: list[Piece]) -> bool:
    """True when the pieces reproduce the law's s and a (guards against a changed law class); one
    evaluation of the law at three points of every piece."""
    fractions = np.array([0.1, 0.5, 0.9])
    kin = law.kinematics(np.concatenate([p.start + p.length * fractions for p in pieces]))
    for index, piece in enumerate(pieces):
        t = piece.length * fractions
        s, a = kin.s[3 * index:3 * index + 3], kin.a[3 * index:3 * index + 3]
        scale = 1.0 + np.max(np.abs(s)) + np.max(np.abs(a))
        if np.max(np.abs(piece.values(t, 0) - s)) > 1e-9 * scale or \
                np.max(np.abs(piece.values(t, 2) - a)) > 1e-9 * scale:
            return False
    return True


def _piece_jumps(pieces: list[Piece], orders: int, shift: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Knot positions and jumps Δf^{(m)} (right − left), m = 0..orders−1, of the (shift)-th derivative."""
    positions = np.array([p.start for p in pieces])
    starts = np.array([p.derivatives(0.0, shift, orders) for p in pieces]).T
    ends = np.array([p.derivatives(p.length, shift, orders) for p in pieces]).T
    return positions, starts - np.roll(ends, 1, axis=1)


def pieces_coefficients(pieces: list[Piece], cycle: float, harmonics: int, order: int, tail_to: int,
                         with_tail: bool = True):
    """(mean, c_k for k = 1..harmonics, Σ_{k>N} A_k²/2 (NaN unless ``with_tail``), round-off bound) of the
    ``order``-th derivative of the pieces."""
    w = np.arange(0, max(harmonics, tail_to) + 1) * (2.0 * np.pi / cycle)     # k = 0 gives the mean
    derived = [p.derivative(order) for p in pieces]
    transformed = cast(np.ndarray, sum(p.transform(w) for p in derived) / cycle)
    mean, coefficients = float(np.real(transformed[0])), transformed[1:]
    tail = math.nan
    if with_tail:
        positions, deltas = _piece_jumps(pieces, TAIL_ORDERS, shift=order)
        tail = _remainder(coefficients, harmonics, positions, deltas, cycle)
    error = 2.0 * 64.0 * EPS * sum(p.scale() for p in derived) / cycle
    return mean, coefficients[:harmonics], tail, error


def _remainder(coefficients: np.ndarray, harmonics: int, positions, deltas, cycle: float) -> float:
    """Σ_{k>N} A_k²/2: exact over the extra coefficients computed, the jump asymptotics beyond them.

    The averaged asymptotic estimate alone is a few per cent off just above N, where the interference of
    the knots has not averaged out over k; summing the exact terms up to several N first makes its
    share negligible.
    """
    extra = coefficients[harmonics:]
    return float(np.sum(2.0 * np.abs(extra[::-1]) ** 2)) + \
        tail_mean_square(positions, deltas, cycle, len(coefficients))


# =============================================================================================
# Exact analysis: piecewise-linear acceleration (drawn laws)
# =============================================================================================

def _polyline_segments(law: PiecewiseLinearLaw):
    """Positive-length segments (start, length, s0, v0, a0, slope), stretched to cover [0, cycle]."""
    x, a = law.x, law.a
    lengths = np.diff(x)
    keep = np.flatnonzero(lengths > 0)
    start = x[keep].copy()
    length = lengths[keep].copy()
    slope = (a[keep + 1] - a[keep]) / length
    a0 = a[keep].copy()
    v0 = law.v_knots[keep].copy()
    s0 = law.s_knots[keep].copy()
    if start[0] > 0:  # the law's kinematics extrapolates its first segment back to 0
        t = -start[0]
        s0[0] = s0[0] + v0[0] * t + a0[0] * t**2 / 2 + slope[0] * t**3 / 6
        v0[0] = v0[0] + a0[0] * t + slope[0] * t**2 / 2
        a0[0] = a0[0] + slope[0] * t
        length[0] -= t
        start[0] = 0.0
    end = start[-1] + length[-1]
    if end < law.cycle:
        length[-1] += law.cycle - end
    return start, length, s0, v0, a0, slope


def _polyline_jumps(law: PiecewiseLinearLaw) -> tuple[np.ndarray, np.ndarray]:
    """Knots and jumps of s, v, a, j (rows 0..3) of a piecewise-linear law; interior s, v are continuous."""
    start, length, s0, v0, a0, slope = _polyline_segments(law)
    L = length[-1]
    s_end = s0[-1] + v0[-1] * L + a0[-1] * L**2 / 2 + slope[-1] * L**3 / 6
    v_end = v0[-1] + a0[-1] * L + slope[-1] * L**2 / 2
    a_left = a0 + slope * length           # a at the end of each segment
    deltas = np.zeros((4, len(start)))
    deltas[2, 1:] = a0[1:] - a_left[:-1]
    deltas[3, 1:] = slope[1:] - slope[:-1]
    deltas[0, 0] = s0[0] - s_end
    deltas[1, 0] = v0[0] - v_end
    deltas[2, 0] = a0[0] - a_left[-1]
    deltas[3, 0] = slope[0] - slope[-1]
    return start, deltas


def uniform_grid_size(positions: np.ndarray, cycle: float, limit: int = 1 << 22) -> int | None:
    """M when every position is a multiple of cycle/M (to 1e-12·cycle), with M ≤ limit; else None.

    Parameters
    ----------
    positions : ndarray
        The knots, rad.
    cycle : float
        T, rad.
    limit : int
        The largest M tried.

    Returns
    -------
    int, optional
        M, or None (a count, no unit).

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from camcad.fourier import uniform_grid_size
    >>> uniform_grid_size(np.radians([0.0, 90.0, 270.0]), 2 * math.pi), uniform_grid_size(np.array([1.0]), 2 * math.pi)
    (4, None)
    """
    if len(positions) < 2:
        return None
    gaps = np.diff(np.sort(positions))
    smallest = float(gaps[gaps > 0].min()) if np.any(gaps > 0) else cycle
    size = int(round(cycle / smallest))  # noqa: RUF046 - round() of a numpy float is a float on numpy < 2
    if size < 1 or size > limit or size > 64 * len(positions):
        return None
    index = positions * size / cycle
    if np.max(np.abs(index - np.rint(index))) * cycle / size > 1e-12 * cycle:
        return None
    return size


def knot_sums(positions: np.ndarray, deltas: np.ndarray, w: np.ndarray, cycle: float) -> np.ndarray:
    """S_m(w) = Σ_j Δ_{m,j} e^{−i w x_j} for each row m: one FFT on uniform knots, else blockwise sums.

    Parameters
    ----------
    positions : ndarray
        The knots x_j, rad.
    deltas : ndarray
        Δ_{m,j}, one row per derivative order m (mm per rad^m).
    w : ndarray
        The frequencies k ω0, per rad.
    cycle : float
        T, rad.

    Returns
    -------
    ndarray
        S_m(w), one row per m, complex (mm per rad^m).

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from camcad.fourier import knot_sums
    >>> sums = knot_sums(np.array([0.0, math.pi]), np.array([[1.0, 1.0]]), np.array([1.0, 2.0]), 2 * math.pi)
    >>> [round(float(abs(x)), 12) for x in sums[0]]                     # 1 + e^{-i k pi}: 0 for odd k, 2 for even
    [0.0, 2.0]
    """
    deltas = np.atleast_2d(deltas)
    size = uniform_grid_size(positions, cycle)
    k = np.rint(w * cycle / (2.0 * np.pi)).astype(np.int64)
    if size is not None and np.allclose(k * (2.0 * np.pi / cycle), w, rtol=1e-15, atol=0):
        grid = np.rint(positions * size / cycle).astype(np.int64) % size
        dense = np.zeros((deltas.shape[0], size))
        for row in range(deltas.shape[0]):
            np.add.at(dense[row], grid, deltas[row])
        transformed = np.fft.fft(dense, axis=1)
        return transformed[:, k % size]
    out = np.zeros((deltas.shape[0], len(w)), dtype=complex)
    block = max(1, _BLOCK // max(1, len(w)))
    for first in range(0, len(positions), block):
        phase = np.exp(-1j * np.outer(positions[first:first + block], w))
        out += deltas[:, first:first + block] @ phase
    return out


def _jump_coefficients(positions, deltas, cycle: float, harmonics: int) -> np.ndarray:
    w = np.arange(1, harmonics + 1) * (2.0 * np.pi / cycle)
    sums = knot_sums(positions, deltas, w, cycle)
    total = np.zeros(harmonics, dtype=complex)
    for m in range(deltas.shape[0]):
        total += sums[m] / (1j * w) ** (m + 1)
    return total / cycle


def polyline_analysis(law: PiecewiseLinearLaw, harmonics: int, tail_to: int):
    """The spectrum of a polyline acceleration law from its jumps (exact), the remainder summed to ``tail_to``."""
    positions, deltas = _polyline_jumps(law)
    cycle = law.cycle
    omega = 2.0 * np.pi / cycle
    if uniform_grid_size(positions, cycle) is None:
        # direct knot sums cost knots × harmonics: keep the remainder's exact part affordable
        tail_to = min(tail_to, max(harmonics, (1 << 25) // max(1, len(positions))))
    extended = _jump_coefficients(positions, deltas, cycle, max(harmonics, tail_to))
    coefficients = extended[:harmonics]
    accel = _jump_coefficients(positions, deltas[2:], cycle, harmonics)
    _start, length, s0, v0, a0, slope = _polyline_segments(law)
    # numpy's pairwise summation: round-off ~ eps·log2(n) of the sum of |terms|
    integral = s0 * length + v0 * length**2 / 2 + a0 * length**3 / 6 + slope * length**4 / 24
    mean = float(np.sum(integral)) / cycle
    nodes, weights = gauss_legendre(4)   # exact for the degree-6 square of a cubic
    t = np.outer(length, nodes)
    s = s0[:, None] + v0[:, None] * t + a0[:, None] * t**2 / 2 + slope[:, None] * t**3 / 6
    mean_square = float(np.sum(length[:, None] * weights[None, :] * s**2)) / cycle - mean**2
    accel_mean = float(np.sum(length * (a0 + slope * length / 2))) / cycle
    # round-off: a few ulps of the sum of |terms| (the largest term is at k = 1)
    scale = [np.sum(np.abs(deltas[m])) / omega ** (m + 1) for m in range(4)]
    error = 2.0 * 8.0 * EPS * sum(scale) / cycle
    accel_error = 2.0 * 8.0 * EPS * (scale[2] + scale[3]) * omega**2 / cycle
    return dict(mean=mean, coefficients=coefficients, accel_mean=accel_mean, accel_coefficients=accel,
                tail=_remainder(extended, harmonics, positions, deltas, cycle), mean_square=mean_square,
                error=error, accel_error=accel_error)


def tail_mean_square(positions: np.ndarray, deltas: np.ndarray, cycle: float, harmonics: int) -> float:
    """Σ_{k>N} A_k²/2 estimated from the jumps: (2/T²) Σ_m (Σ_j Δ_{m,j}²) ζ(2m+2, N+1)/ω0^{2m+2}.

    The cross terms between knots and orders average out over k (they oscillate in k), so this is
    the asymptotic mean of the remainder; jumps at coincident knots are merged first.

    Parameters
    ----------
    positions : ndarray
        The knots, rad.
    deltas : ndarray
        The jumps Δ_{m,j} of s and its derivatives, one row per order m (mm per rad^m).
    cycle : float
        T, rad.
    harmonics : int
        N.

    Returns
    -------
    float
        The remainder's mean square, mm².

    Examples
    --------
    A unit jump of s at 0 (a sawtooth): |c_k| = 1/(2πk), so Σ_{k>N} A_k²/2 = (2/(4π²)) ζ(2, N+1):

    >>> import math
    >>> import numpy as np
    >>> from scipy.special import zeta
    >>> from camcad.fourier import tail_mean_square
    >>> got = tail_mean_square(np.array([0.0]), np.array([[1.0]]), 2 * math.pi, 10)
    >>> round(float(got / (2 / (4 * math.pi ** 2) * zeta(2, 11))), 12)
    1.0
    """
    if len(positions) == 0:
        return 0.0
    order = np.argsort(positions, kind="stable")
    pos = positions[order]
    d = np.atleast_2d(deltas)[:, order]
    group = np.concatenate(([0], np.cumsum(np.diff(pos) > 1e-12 * cycle)))
    merged = np.zeros((d.shape[0], group[-1] + 1))
    for row in range(d.shape[0]):
        np.add.at(merged[row], group, d[row])
    omega = 2.0 * np.pi / cycle
    total = 0.0
    for m in range(merged.shape[0]):
        power = float(np.sum(merged[m] ** 2))
        if power > 0:
            total += power * hurwitz_zeta(2 * m + 2, harmonics + 1) / omega ** (2 * m + 2)
    return 2.0 * total / cycle**2




