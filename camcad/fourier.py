"""Fourier analysis and synthesis of motion laws, and resonance filtering (background.md §2, seed 001).

Conventions
-----------
A law is periodic with period T = ``cycle`` (rad); ω0 = 2π/T is the fundamental (per radian of cam
angle). The displacement series is written in the source's form, with amplitudes and *initial phases*:

    s(θ) = mean + Σ_{k≥1} A_k sin(k ω0 θ + φ_k),        A_k ≥ 0 (mm), φ_k ∈ (−π, π].

Internally the complex coefficients c_k = (1/T) ∫_0^T s(θ) e^{−i k ω0 θ} dθ are kept, so that
s = c_0 + 2 Re Σ c_k e^{i k ω0 θ}, A_k = 2|c_k| and φ_k = arg c_k + π/2. The acceleration analog
a = d²s/dθ² (mm/rad²) is analysed the same way with its own coefficients. At a cam speed n (rpm) the
k-th harmonic has the frequency k·n/60 Hz.

Exact coefficients
------------------
* A piecewise-linear acceleration (a drawn law) has a piecewise-cubic s. Integrating by parts on each
  piece and summing, every term cancels except the jumps Δf^{(m)} = f^{(m)}(x⁺) − f^{(m)}(x⁻) of the
  derivatives at the knots x_j (the jump at θ = 0 is s(0⁺) − s(T⁻), the cycle closure):

      ∫_0^T f(θ) e^{−iwθ} dθ = Σ_j e^{−iw x_j} Σ_{m=0}^{3} Δ_j f^{(m)} / (iw)^{m+1},   w = k ω0.

  Exact for every k; on uniformly spaced knots the knot sums are one FFT.
* A composite standard law (``standard.compose``) is, on each phase, a polynomial plus complex
  exponentials in t = θ − θ0. ∫_0^L t^m e^{−iwt} dt = L^{m+1} E_m(wL) with E_m(z) = ∫_0^1 u^m e^{−izu} du
  (Gauss–Legendre, exact to round-off, for |z| < 8; the recurrence E_m = (m E_{m−1} − e^{−iz})/(iz),
  stable for |z| ≥ 8, otherwise), and ∫_0^L e^{iλt} e^{−iwt} dt = L e^{iδ} sin δ/δ, δ = (λ − w)L/2.
* Any other law: FFT of a uniform sampling, doubled until two successive samplings agree on the first
  N amplitudes within the tolerance (the trapezoidal rule; the sample at θ = 0 is the mean of s(0) and
  s(T), the value the Fourier series converges to at a closure jump).

Truncation error (Parseval): (1/T)∫(s − s_N)² dθ = Σ_{k>N} A_k²/2. The sum over the computed
harmonics is exact; beyond them the remainder is estimated from the jump asymptotics
|c_k|² ≈ (1/T²) Σ_m Σ_j |Δ_j f^{(m)}|² / (kω0)^{2m+2} (averaged over k), summed with the Hurwitz zeta.

Sources: PhD abstract on the batten mechanism of the STB loom, Novosibirsk (seed 001; background.md §2:
harmonic patterns, RMS error against the number of harmonics, resonance filtering of the 17th harmonic
and its neighbours, lead-in segments of 14° at 0.1 of the peak acceleration); A. Zygmund,
Trigonometric Series (1959), ch. II (integration by parts, Parseval); W. H. Press et al., Numerical
Recipes, 3rd ed. (2007), §13.9 (Fourier integrals of piecewise polynomials).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from camcad.errors import CamcadError
from camcad.law.law import Kinematics, MotionLaw, Phase, PiecewiseLinearLaw
from camcad.params import parse_speeds, Field, read_table

EPS = float(np.finfo(float).eps)
#: below this |z| the monomial moments E_m(z) are integrated by Gauss–Legendre, above by recurrence
_SMALL_Z = 8.0
#: derivative orders whose jumps enter the remainder estimate of the composite laws
_TAIL_ORDERS = 7
#: elements per block when a (points × harmonics) matrix of exponentials is formed
_BLOCK = 1 << 21


# =============================================================================================
# The series and its spectrum
# =============================================================================================

def amplitudes_of(coefficients: np.ndarray) -> np.ndarray:
    """A_k = 2|c_k| (units of the analysed function)."""
    return 2.0 * np.abs(np.asarray(coefficients))


def initial_phases_of(coefficients: np.ndarray) -> np.ndarray:
    """φ_k = arg c_k + π/2 wrapped to (−π, π] (rad): the sine form s = Σ A_k sin(kω0θ + φ_k)."""
    phase = np.angle(np.asarray(coefficients)) + np.pi / 2.0
    return np.pi - np.mod(np.pi - phase, 2.0 * np.pi)


def coefficients_from(amplitudes, phases_rad) -> np.ndarray:
    """c_k from the sine form: c_k = (A_k/2) e^{i(φ_k − π/2)}."""
    return 0.5 * np.asarray(amplitudes, dtype=float) * np.exp(1j * (np.asarray(phases_rad, dtype=float) - np.pi / 2))


def evaluate_series(mean: float, coefficients: np.ndarray, cycle: float, theta, order: int = 0) -> np.ndarray:
    """d^order/dθ^order of mean + 2 Re Σ_k c_k e^{ikω0θ} at θ (rad); units of s per rad^order."""
    return evaluate_series_orders(mean, coefficients, cycle, theta, (order,))[0]


def evaluate_series_orders(mean: float, coefficients: np.ndarray, cycle: float, theta,
                           orders=(0, 1, 2, 3)) -> list[np.ndarray]:
    """Several derivatives of the series at θ (rad), by Horner's scheme in z = e^{iω0θ}.

    Σ_k c_k z^k = z(c_1 + z(c_2 + … + z c_N)): N complex multiply-adds per point and order, no table
    of exponentials; |z| = 1, so the round-off grows at most like N·eps·Σ|c_k|.
    """
    theta = np.asarray(theta, dtype=float)
    flat = theta.ravel()
    coefficients = np.asarray(coefficients, dtype=complex)
    n = len(coefficients)
    outs = [np.full(flat.shape, mean if order == 0 else 0.0) for order in orders]
    if n and len(flat):
        w = np.arange(1, n + 1) * (2.0 * np.pi / cycle)
        weighted = np.stack([coefficients * (1j * w) ** order for order in orders], axis=1)
        z = np.exp(1j * (2.0 * np.pi / cycle) * flat)[:, None]
        total = np.zeros((len(flat), len(orders)), dtype=complex)
        for k in range(n - 1, -1, -1):
            total *= z
            total += weighted[k]
        values = 2.0 * np.real(total * z)
        for index, out in enumerate(outs):
            out += values[:, index]
    return [out.reshape(theta.shape) for out in outs]


def series_on_grid(mean: float, coefficients: np.ndarray, samples: int, order: int = 0,
                   cycle: float = 2 * np.pi) -> np.ndarray:
    """The series' order-th derivative at θ_j = j T/M, j = 0..M−1, by one inverse FFT (needs N < M/2)."""
    coefficients = np.asarray(coefficients, dtype=complex)
    n = len(coefficients)
    if 2 * n >= samples:
        raise ValueError(f"{samples} samples cannot carry {n} harmonics")
    spectrum = np.zeros(samples // 2 + 1, dtype=complex)
    w = np.arange(1, n + 1) * (2.0 * np.pi / cycle)
    spectrum[1:n + 1] = coefficients * (1j * w) ** order
    spectrum[0] = mean if order == 0 else 0.0
    return np.fft.irfft(spectrum * samples, n=samples)


@dataclass(frozen=True)
class FourierLaw:
    """A motion law given by its harmonics: s = mean + 2 Re Σ_{k=1}^{N} c_k e^{ikω0θ} (mm), ω0 = 2π/cycle.

    Satisfies the ``MotionLaw`` protocol; v, a, j are the exact term-by-term derivatives (mm/rad,
    mm/rad², mm/rad³). Periodic by construction, so it always closes.
    """

    cycle: float
    mean: float
    coefficients: np.ndarray
    phases: tuple[Phase, ...] = ()

    def __post_init__(self) -> None:
        c = np.ascontiguousarray(self.coefficients, dtype=complex)
        c.setflags(write=False)
        object.__setattr__(self, "coefficients", c)

    @classmethod
    def from_amplitudes(cls, amplitudes, phases_rad, mean: float, cycle: float,
                        phases: tuple[Phase, ...] = ()) -> "FourierLaw":
        """From A_k (mm) and initial phases φ_k (rad) of s = mean + Σ A_k sin(kω0θ + φ_k)."""
        return cls(cycle, float(mean), coefficients_from(amplitudes, phases_rad), tuple(phases))

    @property
    def harmonics(self) -> int:
        return len(self.coefficients)

    def kinematics(self, theta) -> Kinematics:
        theta = np.asarray(theta, dtype=float)
        s, v, a, j = evaluate_series_orders(self.mean, self.coefficients, self.cycle, theta)
        return Kinematics(theta=theta, s=s, v=v, a=a, j=j)


@dataclass(frozen=True)
class CorrectedLaw:
    """``base`` plus a finite trigonometric ``correction`` (a FourierLaw): the filtered law.

    Removing harmonics R from the infinite series of ``base`` is exactly base − Σ_{k∈R} (term k),
    so nothing else of the law changes: no truncation, no Gibbs ripple.
    """

    base: Any
    correction: FourierLaw

    @property
    def cycle(self) -> float:
        return self.base.cycle

    @property
    def phases(self) -> tuple[Phase, ...]:
        return tuple(self.base.phases)

    def kinematics(self, theta) -> Kinematics:
        first = self.base.kinematics(theta)
        second = self.correction.kinematics(theta)
        return Kinematics(theta=first.theta, s=first.s + second.s, v=first.v + second.v,
                          a=first.a + second.a, j=first.j + second.j)


@dataclass(frozen=True)
class Spectrum:
    """Harmonics 1..N of the displacement (mm) and of the acceleration analog (mm/rad²) of a law.

    ``tail_mean_square`` is Σ_{k>N} A_k²/2 (mm²): exact for a FourierLaw, the jump-asymptotic estimate
    for the exact methods, the discrete remainder for FFT. ``mean_square`` is (1/T)∫(s − mean)² dθ
    when computed independently of the coefficients (NaN otherwise). ``coefficient_error`` bounds the
    error of each amplitude A_k (mm): round-off for the exact methods, the difference between the two
    finest samplings for FFT.
    """

    cycle: float
    mean: float
    coefficients: np.ndarray
    accel_mean: float
    accel_coefficients: np.ndarray
    tail_mean_square: float
    mean_square: float
    coefficient_error: float
    accel_coefficient_error: float
    method: str
    samples: int = 0
    converged: bool = True

    @property
    def harmonics(self) -> np.ndarray:
        return np.arange(1, len(self.coefficients) + 1)

    @property
    def amplitudes(self) -> np.ndarray:
        return amplitudes_of(self.coefficients)

    @property
    def phases(self) -> np.ndarray:
        return initial_phases_of(self.coefficients)

    @property
    def accel_amplitudes(self) -> np.ndarray:
        return amplitudes_of(self.accel_coefficients)

    @property
    def accel_phases(self) -> np.ndarray:
        return initial_phases_of(self.accel_coefficients)

    def rms_errors(self) -> np.ndarray:
        """RMS error (mm) of the series truncated after n = 0, 1, …, N harmonics (Parseval)."""
        power = self.amplitudes**2 / 2.0
        # tail sums from the top, so small terms are added first
        tails = np.concatenate((np.cumsum(power[::-1])[::-1], [0.0])) + self.tail_mean_square
        return np.sqrt(tails)

    def rms_error(self, n: int) -> float:
        """RMS error (mm) of the series truncated after n harmonics, 0 ≤ n ≤ N."""
        if not 0 <= n <= len(self.coefficients):
            raise ValueError(f"n = {n} outside 0..{len(self.coefficients)}")
        return float(self.rms_errors()[n])

    def least_harmonics(self, tol: float) -> int | None:
        """Least n with RMS error ≤ tol (mm); None when even N harmonics are not enough."""
        ok = np.flatnonzero(self.rms_errors() <= tol)
        return int(ok[0]) if len(ok) else None

    def truncated(self, n: int | None = None, phases: tuple[Phase, ...] = ()) -> FourierLaw:
        """The law synthesised from the mean and the first n harmonics."""
        n = len(self.coefficients) if n is None else n
        return FourierLaw(self.cycle, self.mean, self.coefficients[:n], tuple(phases))

    def table(self) -> list[dict]:
        """Rows {k, amplitude (mm), phase_deg, accel_amplitude (mm/rad²), accel_phase_deg}."""
        return [{"k": int(k), "amplitude": float(amp), "phase_deg": float(np.degrees(ph)),
                 "accel_amplitude": float(aamp), "accel_phase_deg": float(np.degrees(aph))}
                for k, amp, ph, aamp, aph in zip(self.harmonics, self.amplitudes, self.phases,
                                                 self.accel_amplitudes, self.accel_phases)]


# =============================================================================================
# Exact analysis: piecewise elementary functions (composite standard laws)
# =============================================================================================

def _gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes and weights of n-point Gauss–Legendre on [0, 1]."""
    nodes, weights = np.polynomial.legendre.leggauss(n)
    return (nodes + 1.0) / 2.0, weights / 2.0


def monomial_moments(z: np.ndarray, degree: int) -> np.ndarray:
    """E_m(z) = ∫_0^1 u^m e^{−izu} du for m = 0..degree, shape (degree+1, len(z)); exact to round-off.

    |z| < 8: 48-point Gauss–Legendre (exact for the polynomial, the exponential's Taylor series is
    below round-off past degree 45). |z| ≥ 8: E_0 = e^{−iz/2} sin(z/2)/(z/2) and upward recurrence
    E_m = (m E_{m−1} − e^{−iz})/(iz), whose error grows by m/|z| ≤ 1 per step for m ≤ 8.
    """
    z = np.asarray(z, dtype=float)
    out = np.empty((degree + 1, len(z)), dtype=complex)
    small = np.abs(z) < _SMALL_Z
    if small.any():
        nodes, weights = _gauss_legendre(48)
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
    """f(θ) = Σ_m poly[m] t^m + Σ_j amps[j] e^{i rates[j] t} (real part), t = θ − start ∈ [0, length]."""

    start: float
    length: float
    poly: np.ndarray
    rates: np.ndarray = field(default_factory=lambda: np.zeros(0))
    amps: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=complex))

    def derivative(self, order: int) -> "Piece":
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

    def transform(self, w: np.ndarray) -> np.ndarray:
        """∫ over the piece of f(θ) e^{−iwθ} dθ for each w (complex)."""
        w = np.asarray(w, dtype=float)
        length = self.length
        total = np.zeros(len(w), dtype=complex)
        poly = np.trim_zeros(self.poly, "b")
        if len(poly):
            moments = monomial_moments(w * length, len(poly) - 1)
            scale = poly * length ** np.arange(1, len(poly) + 1)
            total += scale @ moments
        for amp, rate in zip(self.amps, self.rates):
            half = (rate - w) * length / 2.0
            total += amp * length * np.exp(1j * half) * np.sinc(half / np.pi)
        return total * np.exp(-1j * w * self.start)

    def integral_of_square(self) -> float:
        """∫ f² over the piece, Gauss–Legendre with enough nodes to be exact to round-off."""
        rate = float(np.max(np.abs(self.rates))) if len(self.rates) else 0.0
        n = int(len(self.poly) + 24 + math.ceil(rate * self.length))
        nodes, weights = _gauss_legendre(n)
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
    """
    from camcad.law import standard

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
    """The displacement of a ``standard.CompositeLaw`` as elementary pieces, or None if a shape is unknown."""
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


def _pieces_check(law, pieces: list[Piece]) -> bool:
    """True when the pieces reproduce the law's s and a (guards against a changed law class)."""
    for piece in pieces:
        t = piece.length * np.array([0.1, 0.5, 0.9])
        kin = law.kinematics(piece.start + t)
        scale = 1.0 + np.max(np.abs(kin.s)) + np.max(np.abs(kin.a))
        if np.max(np.abs(piece.values(t, 0) - kin.s)) > 1e-9 * scale or \
                np.max(np.abs(piece.values(t, 2) - kin.a)) > 1e-9 * scale:
            return False
    return True


def _piece_jumps(pieces: list[Piece], orders: int, shift: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Knot positions and jumps Δf^{(m)} (right − left), m = 0..orders−1, of the (shift)-th derivative."""
    positions = np.array([p.start for p in pieces])
    deltas = np.zeros((orders, len(pieces)))
    for index, piece in enumerate(pieces):
        before = pieces[index - 1]
        for m in range(orders):
            deltas[m, index] = piece.values(0.0, m + shift) - before.values(before.length, m + shift)
    return positions, deltas


def _pieces_coefficients(pieces: list[Piece], cycle: float, harmonics: int, order: int, tail_to: int):
    w = np.arange(1, max(harmonics, tail_to) + 1) * (2.0 * np.pi / cycle)
    derived = [p.derivative(order) for p in pieces]
    coefficients = sum(p.transform(w) for p in derived) / cycle
    mean = float(np.real(sum(p.transform(np.zeros(1))[0] for p in derived))) / cycle
    positions, deltas = _piece_jumps(pieces, _TAIL_ORDERS, shift=order)
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
    """M when every position is a multiple of cycle/M (to 1e-12·cycle), with M ≤ limit; else None."""
    if len(positions) < 2:
        return None
    gaps = np.diff(np.sort(positions))
    smallest = float(gaps[gaps > 0].min()) if np.any(gaps > 0) else cycle
    size = int(round(cycle / smallest))
    if size < 1 or size > limit or size > 64 * len(positions):
        return None
    index = positions * size / cycle
    if np.max(np.abs(index - np.rint(index))) * cycle / size > 1e-12 * cycle:
        return None
    return size


def knot_sums(positions: np.ndarray, deltas: np.ndarray, w: np.ndarray, cycle: float) -> np.ndarray:
    """S_m(w) = Σ_j Δ_{m,j} e^{−i w x_j} for each row m: one FFT on uniform knots, else blockwise sums."""
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


def _polyline_analysis(law: PiecewiseLinearLaw, harmonics: int, tail_to: int):
    positions, deltas = _polyline_jumps(law)
    cycle = law.cycle
    omega = 2.0 * np.pi / cycle
    if uniform_grid_size(positions, cycle) is None:
        # direct knot sums cost knots × harmonics: keep the remainder's exact part affordable
        tail_to = min(tail_to, max(harmonics, (1 << 25) // max(1, len(positions))))
    extended = _jump_coefficients(positions, deltas, cycle, max(harmonics, tail_to))
    coefficients = extended[:harmonics]
    accel = _jump_coefficients(positions, deltas[2:], cycle, harmonics)
    start, length, s0, v0, a0, slope = _polyline_segments(law)
    # numpy's pairwise summation: round-off ~ eps·log2(n) of the sum of |terms|
    integral = s0 * length + v0 * length**2 / 2 + a0 * length**3 / 6 + slope * length**4 / 24
    mean = float(np.sum(integral)) / cycle
    nodes, weights = _gauss_legendre(4)   # exact for the degree-6 square of a cubic
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
    """
    from scipy.special import zeta

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
            total += power * float(zeta(2 * m + 2, harmonics + 1)) / omega ** (2 * m + 2)
    return 2.0 * total / cycle**2


# =============================================================================================
# Analysis entry points
# =============================================================================================

def exact_available(law) -> bool:
    """True when ``analyse`` can integrate the law exactly (drawn polyline, known composite, series)."""
    from camcad.law.standard import CompositeLaw

    if isinstance(law, (PiecewiseLinearLaw, FourierLaw)):
        return True
    if isinstance(law, CorrectedLaw):
        return exact_available(law.base)
    if isinstance(law, CompositeLaw):
        pieces = composite_pieces(law)
        return pieces is not None and _pieces_check(law, pieces)
    return False


def analyse(law: MotionLaw, harmonics: int = 64, *, tol: float = 1e-9, method: str = "auto",
            max_samples: int = 1 << 22, tail_harmonics: int | None = None) -> Spectrum:
    """Amplitudes and initial phases of s (mm) and a (mm/rad²) of a full-cycle law, k = 1..harmonics.

    Parameters
    ----------
    law : any MotionLaw over one cycle (rad).
    harmonics : N, the number of harmonics returned.
    tol : FFT path only — the sampling is doubled until two successive samplings agree on every A_k,
        k ≤ N, within ``tol`` mm (the accuracy knob); ignored by the exact methods.
    method : "auto" (exact when available, else FFT), "exact" or "fft".
    max_samples : the largest FFT sampling tried; ``converged`` is False when it was not enough.
    tail_harmonics : exact methods — coefficients up to this k (default 4N) are computed and summed
        exactly into the remainder Σ_{k>N} A_k²/2; only the part beyond is the asymptotic estimate.
        The knob of the truncation-error accuracy near N.
    """
    if harmonics < 1:
        raise ValueError("harmonics must be at least 1")
    if method not in ("auto", "exact", "fft"):
        raise ValueError(f"method must be auto, exact or fft, not {method!r}")
    if method == "fft" or (method == "auto" and not exact_available(law)):
        return _fft_analysis(law, harmonics, tol, max_samples)
    if not exact_available(law):
        raise ValueError(f"no exact analysis for {type(law).__name__}; use method='fft'")
    return _exact_analysis(law, harmonics, max(harmonics, tail_harmonics or 4 * harmonics))


def _exact_analysis(law, harmonics: int, tail_to: int) -> Spectrum:
    from camcad.law.standard import CompositeLaw

    cycle = law.cycle
    if isinstance(law, FourierLaw):
        c = np.zeros(harmonics, dtype=complex)
        n = min(harmonics, law.harmonics)
        c[:n] = law.coefficients[:n]
        w = np.arange(1, harmonics + 1) * (2.0 * np.pi / cycle)
        beyond = law.coefficients[harmonics:]
        return Spectrum(cycle, law.mean, c, 0.0, -(w**2) * c, float(np.sum(2 * np.abs(beyond) ** 2)),
                        float(np.sum(2 * np.abs(law.coefficients) ** 2)), 0.0, 0.0, "exact")
    if isinstance(law, CorrectedLaw):
        extra = law.correction.harmonics
        wide = max(harmonics, extra)
        base = _exact_analysis(law.base, wide, max(tail_to, wide))
        w = np.arange(1, wide + 1) * (2.0 * np.pi / cycle)
        add = np.zeros(wide, dtype=complex)
        add[:extra] = law.correction.coefficients
        c = base.coefficients + add
        ca = base.accel_coefficients - w**2 * add
        tail = base.tail_mean_square + float(np.sum(2 * np.abs(c[harmonics:]) ** 2))
        return Spectrum(cycle, base.mean + law.correction.mean, c[:harmonics], base.accel_mean, ca[:harmonics],
                        tail, float("nan"), base.coefficient_error, base.accel_coefficient_error, "exact")
    if isinstance(law, PiecewiseLinearLaw):
        r = _polyline_analysis(law, harmonics, tail_to)
        return Spectrum(cycle, r["mean"], r["coefficients"], r["accel_mean"], r["accel_coefficients"],
                        r["tail"], r["mean_square"], r["error"], r["accel_error"], "exact")
    if isinstance(law, CompositeLaw):
        pieces = composite_pieces(law)
        mean, c, tail, error = _pieces_coefficients(pieces, cycle, harmonics, 0, tail_to)
        accel_mean, ca, _, accel_error = _pieces_coefficients(pieces, cycle, harmonics, 2, harmonics)
        raw_square = math.fsum(p.integral_of_square() for p in pieces) / cycle
        return Spectrum(cycle, mean, c, accel_mean, ca, tail, raw_square - mean**2, error, accel_error, "exact")
    raise ValueError(f"no exact analysis for {type(law).__name__}")


def _fft_analysis(law, harmonics: int, tol: float, max_samples: int) -> Spectrum:
    cycle = law.cycle
    samples = max(1024, 1 << int(math.ceil(math.log2(8 * (harmonics + 1)))))
    end = law.kinematics(np.array([cycle]))
    previous = None
    while True:
        theta = np.arange(samples) * (cycle / samples)
        kin = law.kinematics(theta)
        s = np.array(kin.s, dtype=float)
        a = np.array(kin.a, dtype=float)
        # the series converges to the mean of the two sides of a closure jump
        s[0] = 0.5 * (s[0] + end.s[0])
        a[0] = 0.5 * (a[0] + end.a[0])
        cs = np.fft.rfft(s) / samples
        ca = np.fft.rfft(a) / samples
        if previous is not None:
            error = 2.0 * float(np.max(np.abs(cs[1:harmonics + 1] - previous[0][1:harmonics + 1])))
            accel_error = 2.0 * float(np.max(np.abs(ca[1:harmonics + 1] - previous[1][1:harmonics + 1])))
            if error <= tol or 2 * samples > max_samples:
                break
        previous = (cs, ca)
        samples *= 2
    power = 2.0 * np.abs(cs[harmonics + 1:]) ** 2
    power[-1] /= 2.0  # the Nyquist term is real and counted once
    mean = float(np.real(cs[0]))
    mean_square = float(np.mean(s**2)) - mean**2
    return Spectrum(cycle, mean, cs[1:harmonics + 1].copy(), float(np.real(ca[0])), ca[1:harmonics + 1].copy(),
                    float(np.sum(power)), mean_square, error, accel_error, "fft", samples, error <= tol)


def analyse_samples(s: np.ndarray, cycle: float, harmonics: int, a: np.ndarray | None = None) -> Spectrum:
    """Spectrum of uniform samples s_j = s(jT/M), j = 0..M−1 (and of a, if given): one real FFT.

    The trapezoidal rule: exact for harmonics below M/2 of a band-limited law; otherwise aliasing,
    Σ_{j≠0} c_{k+jM}, is the error (estimated from the discarded upper half of the spectrum).
    """
    s = np.asarray(s, dtype=float)
    samples = len(s)
    if 2 * harmonics >= samples:
        raise ValueError(f"{samples} samples cannot resolve {harmonics} harmonics")
    cs = np.fft.rfft(s) / samples
    if a is None:
        w = np.arange(samples // 2 + 1) * (2.0 * np.pi / cycle)
        ca = -(w**2) * cs
    else:
        ca = np.fft.rfft(np.asarray(a, dtype=float)) / samples
    upper = cs[samples // 4:]
    error = 2.0 * float(np.max(np.abs(upper))) if len(upper) else 0.0
    power = 2.0 * np.abs(cs[harmonics + 1:]) ** 2
    power[-1] /= 2.0
    mean = float(np.real(cs[0]))
    return Spectrum(cycle, mean, cs[1:harmonics + 1].copy(), float(np.real(ca[0])), ca[1:harmonics + 1].copy(),
                    float(np.sum(power)), float(np.mean(s**2)) - mean**2, error, float("nan"), "samples", samples)


def max_errors(law: MotionLaw, spectrum: Spectrum, ns, samples: int | None = None) -> np.ndarray:
    """max_θ |s(θ) − s_n(θ)| (mm) for each n in ``ns``, on a uniform grid of ``samples`` points.

    The default grid has at least 64 points per period of the highest harmonic kept, so the sampled
    maximum is within ~0.1 % of the true one for the smooth part of the error.
    """
    ns = np.atleast_1d(np.asarray(ns, dtype=int))
    if samples is None:
        samples = max(1 << 14, 1 << int(math.ceil(math.log2(64 * (int(ns.max()) + 1)))))
    theta = np.arange(samples) * (law.cycle / samples)
    s = law.kinematics(theta).s
    out = []
    for n in ns:
        partial = series_on_grid(spectrum.mean, spectrum.coefficients[:n], samples, 0, law.cycle)
        out.append(float(np.max(np.abs(s - partial))))
    return np.array(out)


#: a least N is trusted only when this many times N harmonics were computed exactly, so the
#: asymptotic estimate of the remainder beyond them is a negligible part of the RMS error
HEADROOM = 8


def least_harmonics(law: MotionLaw, tol: float, *, max_harmonics: int = 1 << 14,
                    start: int = 64) -> tuple[int | None, Spectrum]:
    """Least n whose truncated series has RMS error ≤ tol (mm), and the spectrum it was read from.

    The spectrum is grown until it holds at least HEADROOM·n harmonics (or ``max_harmonics``).
    """
    return _grow_until_found(lambda count: analyse(law, count), tol, start, max_harmonics)


def _grow_until_found(spectrum_of, tol: float, start: int, max_harmonics: int):
    harmonics = max(1, min(start, max_harmonics))
    while True:
        spectrum = spectrum_of(harmonics)
        n = spectrum.least_harmonics(tol)
        if harmonics >= max_harmonics:
            return n, spectrum
        if n is None:
            harmonics = min(4 * harmonics, max_harmonics)
        elif HEADROOM * n > harmonics:
            harmonics = min(HEADROOM * n, max_harmonics)
        else:
            return n, spectrum


# =============================================================================================
# The database of harmonic patterns of the standard laws, and synthesis from it
# =============================================================================================

@dataclass(frozen=True)
class MotionPattern:
    """The normalised harmonic pattern of one motion of a standard shape (unit lift over unit width).

    For a motion of lift h starting at θ0 over the angle β in a cycle T, the velocity analog
    v = (h/β) f'(u) contributes to the Fourier coefficients of v exactly
        c_k(v) = (h/T) e^{−ikω0θ0} Φ(kω0β),     Φ(z) = ∫_0^1 f'(u) e^{−izu} du,
    so c_k(s) = c_k(v)/(ikω0) for a closed cycle (v = 0 on the dwells). Φ is the pattern: one
    function of z = kω0β for every lift, phase angle and cycle. ``moments`` = (∫f du, ∫f² du) give
    the mean and the mean square (Parseval); ``edge_derivatives`` (f^{(m)}(0), f^{(m)}(1), m = 0..6)
    give the asymptotic decay of the pattern, hence the harmonics a requested accuracy needs.
    """

    name: str
    shape: Any
    velocity_piece: Piece
    moments: tuple[float, float]
    edge_derivatives: np.ndarray

    def transform(self, z) -> np.ndarray:
        """Φ(z) = ∫_0^1 f'(u) e^{−izu} du (complex, dimensionless)."""
        return self.velocity_piece.transform(np.atleast_1d(np.asarray(z, dtype=float)))

    def table(self, z) -> list[dict]:
        """|Φ| and arg Φ (deg) at the given z: the printed form of the database."""
        phi = self.transform(z)
        return [{"z": float(zi), "magnitude": float(abs(p)), "phase_deg": float(np.degrees(np.angle(p)))}
                for zi, p in zip(np.atleast_1d(z), phi)]


def motion_pattern(shape, name: str | None = None) -> MotionPattern:
    """The pattern of a rise shape (``standard.SHAPES`` member or any shape ``shape_terms`` knows)."""
    terms = shape_terms(shape)
    if terms is None:
        raise CamcadError(f"no exact harmonic pattern for the shape {getattr(shape, 'name', shape)!r}",
                          "harmonic database", "use cycloidal, harmonic, poly345 or poly4567")
    piece = Piece(0.0, 1.0, *terms)
    nodes, weights = _gauss_legendre(64)
    f = piece.values(nodes)
    moments = (float(np.sum(weights * f)), float(np.sum(weights * f**2)))
    edges = np.array([[piece.values(0.0, m), piece.values(1.0, m)] for m in range(_TAIL_ORDERS)])
    return MotionPattern(name or getattr(shape, "name", "shape"), shape, piece.derivative(1), moments, edges)


def pattern_database() -> dict[str, MotionPattern]:
    """The database: the normalised pattern of every standard shape that has an exact one."""
    from camcad.law.standard import SHAPES

    database = {}
    for name, shape in SHAPES.items():
        if shape_terms(shape) is not None:
            database[name] = motion_pattern(shape, name)
    return database


TACHOGRAMS = ("DRRD", "DRDR")


def tachogram(kind: str, rise_deg: float, return_deg: float, *, far_dwell_deg: float = 0.0,
              start_deg: float = 0.0, cycle_deg: float = 360.0) -> list[tuple[str, float]]:
    """Phase list (kind, width_deg) of the source's tachogram shapes.

    "DRRD": dwell – rise – return – dwell (no dwell at the top); "DRDR": dwell – rise – dwell –
    return (– dwell), the dwell–rise–dwell shape closed by its return. ``start_deg`` is the dwell
    before the rise; the rest of the cycle is the dwell after the return.
    """
    kind = kind.upper()
    if kind not in TACHOGRAMS:
        raise CamcadError(f"unknown tachogram {kind!r}", "tachogram", f"use one of {', '.join(TACHOGRAMS)}")
    far = far_dwell_deg if kind == "DRDR" else 0.0
    if kind == "DRDR" and not far > 0:
        raise CamcadError("a dwell-rise-dwell-return tachogram needs a far dwell > 0 deg", "tachogram",
                          "give far_dwell_deg, or use DRRD")
    rest = cycle_deg - start_deg - rise_deg - far - return_deg
    if min(rise_deg, return_deg) <= 0 or start_deg < 0 or rest < -1e-9 * cycle_deg:
        raise CamcadError(f"phase angles {start_deg:g}+{rise_deg:g}+{far:g}+{return_deg:g} deg do not fit the "
                          f"cycle of {cycle_deg:g} deg", "tachogram", "shorten the phases")
    items = [("dwell", start_deg), ("rise", rise_deg), ("dwell", far), ("return", return_deg),
             ("dwell", max(rest, 0.0))]
    return [(k, w) for k, w in items if w > 1e-12 * cycle_deg]


@dataclass(frozen=True)
class Synthesis:
    """A law synthesised from the database, and how accurate it is.

    ``rms_predicted`` is the Parseval figure the harmonic count was chosen by; ``rms_measured`` and
    ``max_error`` compare the synthesised law with the closed-form composite law by quadrature on
    ``samples`` points (an independent check).
    """

    law: FourierLaw
    exact: Any
    harmonics: int
    tol: float
    rms_predicted: float
    rms_measured: float
    max_error: float
    reached: bool
    samples: int
    spectrum: Spectrum


def pattern_coefficients(phases_deg, lift: float, shape: str = "cycloidal", return_shape: str | None = None,
                         harmonics: int = 64, cycle_deg: float = 360.0,
                         database: dict[str, MotionPattern] | None = None) -> Spectrum:
    """The spectrum of a composite standard cycle built from the database patterns (exact)."""
    database = database or pattern_database()
    for name in (shape, return_shape or shape):
        if name not in database:
            raise CamcadError(f"no pattern {name!r} in the database", "harmonic database",
                              f"known: {', '.join(sorted(database))}")
    cycle = float(np.radians(cycle_deg))
    omega = 2.0 * np.pi / cycle
    w = np.arange(1, harmonics + 1) * omega
    velocity = np.zeros(harmonics, dtype=complex)
    accel = np.zeros(harmonics, dtype=complex)
    level = 0.0
    start = 0.0
    integral = 0.0
    square = 0.0
    positions, jumps = [], []
    for kind, width_deg in phases_deg:
        beta = float(np.radians(width_deg))
        if kind == "dwell":
            integral += level * beta
            square += level**2 * beta
        else:
            pattern = database[shape if kind == "rise" else (return_shape or shape)]
            h = lift if kind == "rise" else -lift
            velocity += h * np.exp(-1j * w * start) * pattern.transform(w * beta)
            m1, m2 = pattern.moments
            integral += beta * (level + h * m1)
            square += beta * (level**2 + 2 * level * h * m1 + h**2 * m2)
            edges = pattern.edge_derivatives
            scale = h / beta ** np.arange(_TAIL_ORDERS)
            scale[0] = 0.0  # s itself is continuous at the ends of a motion
            positions += [start, start + beta]
            jumps += [scale * edges[:, 0], -scale * edges[:, 1]]
            level += h
        start += beta
    if abs(start - cycle) > 1e-9 * cycle or abs(level) > 1e-9 * max(lift, 1.0):
        raise CamcadError("the phases do not make a closed cycle", "harmonic database",
                          "give widths adding up to the cycle and as many returns as rises")
    velocity /= cycle
    coefficients = velocity / (1j * w)
    accel = 1j * w * velocity
    mean = integral / cycle
    deltas = np.array(jumps).T
    tail = tail_mean_square(np.array(positions), deltas, cycle, harmonics)
    return Spectrum(cycle, mean, coefficients, 0.0, accel, tail, square / cycle - mean**2,
                    64 * EPS * lift, 64 * EPS * lift * harmonics**2, "database")


def synthesise_standard(phases_deg, lift: float, tol: float, *, shape: str = "cycloidal",
                        return_shape: str | None = None, cycle_deg: float = 360.0,
                        max_harmonics: int = 1 << 14, samples: int | None = None) -> Synthesis:
    """A FourierLaw for the cycle (kind, width_deg)… of ``shape`` rises and ``return_shape`` returns, with
    RMS error ≤ ``tol`` mm against the closed-form law, using the least number of harmonics that the
    Parseval prediction from the database allows; the accuracy reached is then measured.
    """
    from camcad.law.standard import compose

    if not (np.isfinite(tol) and tol > 0):
        raise CamcadError(f"tolerance {tol!r} mm must be positive", "synthesis", "give e.g. 1e-3 mm")
    exact = compose(list(phases_deg), lift, shape, return_shape, cycle_deg)
    database = pattern_database()
    n, spectrum = _grow_until_found(
        lambda count: pattern_coefficients(phases_deg, lift, shape, return_shape, count, cycle_deg, database),
        tol, 64, max_harmonics)
    if n is None:
        n = len(spectrum.coefficients)
    law = spectrum.truncated(n, exact.phases)
    if samples is None:
        samples = max(1 << 14, 1 << int(math.ceil(math.log2(64 * (n + 1)))))
    theta = np.arange(samples) * (exact.cycle / samples)
    difference = exact.kinematics(theta).s - series_on_grid(law.mean, law.coefficients, samples, 0, exact.cycle)
    measured = float(np.sqrt(np.mean(difference**2)))
    return Synthesis(law, exact, n, tol, spectrum.rms_error(n), measured, float(np.max(np.abs(difference))),
                     measured <= tol, samples, spectrum)


# =============================================================================================
# Resonance filtering
# =============================================================================================

@dataclass(frozen=True)
class ResonanceBand:
    """Harmonics that meet the natural frequency over a speed range.

    k is *resonant* when |k n/60 − fn| ≤ band·fn for some n ∈ [n1, n2] rpm, i.e.
        60 fn (1 − band)/n2 ≤ k ≤ 60 fn (1 + band)/n1     (both ends included, to 1e-9 relative).
    ``removed`` adds ``neighbours`` harmonics on each side. ``gains`` multiply the harmonics: 0 for the
    removed ones, and with ``taper`` > 0 a raised-cosine ramp g = sin²(π d / (2(taper + 1))) over the
    next ``taper`` harmonics at distance d from the removed set.
    """

    fn_hz: float
    rpm: tuple[float, float]
    band: float
    neighbours: int
    taper: int
    k_low: float
    k_high: float
    core: tuple[int, ...]
    removed: tuple[int, ...]
    gains: dict

    @property
    def highest(self) -> int:
        return max(self.gains) if self.gains else 0

    def frequency_band_hz(self) -> tuple[float, float]:
        return self.fn_hz * (1.0 - self.band), self.fn_hz * (1.0 + self.band)


def parse_rpm(value, where: str = "--rpm") -> tuple[float, float]:
    """The speed range (n1, n2) in rpm of a speed or range (see camcad.params.parse_speeds)."""
    speeds = parse_speeds(value, where)
    return min(speeds), max(speeds)


def resonant_harmonics(fn_hz: float, rpm, band: float = 0.05, neighbours: int = 1, taper: int = 0,
                       where: str = "filter") -> ResonanceBand:
    """The resonant harmonics (see ``ResonanceBand``) for natural frequency fn (Hz) over rpm = (n1, n2)."""
    low, high = parse_rpm(rpm, where)
    if not (np.isfinite(fn_hz) and fn_hz > 0):
        raise CamcadError(f"natural frequency {fn_hz!r} Hz must be positive", where, "give fn in Hz, e.g. --fn 160")
    if not (np.isfinite(band) and 0 <= band < 1):
        raise CamcadError(f"band {band!r} must be a fraction in [0, 1)", where,
                          "give the half-width as a fraction of fn, e.g. 0.05 for ±5 %")
    if neighbours < 0 or taper < 0:
        raise CamcadError("neighbours and taper must be >= 0", where, "give whole numbers >= 0")
    k_low = 60.0 * fn_hz * (1.0 - band) / high
    k_high = 60.0 * fn_hz * (1.0 + band) / low
    slack = 1e-9
    first = max(1, int(math.ceil(k_low * (1 - slack))))
    last = int(math.floor(k_high * (1 + slack)))
    core = tuple(range(first, last + 1))
    if len(core) > 100000:
        raise CamcadError(f"the band covers {len(core)} harmonics", where, "narrow the band or the speed range")
    removed = set()
    for k in core:
        removed.update(j for j in range(k - neighbours, k + neighbours + 1) if j >= 1)
    gains = {k: 0.0 for k in removed}
    if taper and removed:
        for d in range(1, taper + 1):
            gain = math.sin(math.pi * d / (2 * (taper + 1))) ** 2
            for j in (min(removed) - d, max(removed) + d):
                if j >= 1 and j not in gains:
                    gains[j] = gain
    return ResonanceBand(float(fn_hz), (low, high), float(band), int(neighbours), int(taper), k_low, k_high,
                         core, tuple(sorted(removed)), dict(sorted(gains.items())))


def motion_starts(phases: tuple[Phase, ...]) -> list[float]:
    """θ (rad) where a rise or return begins after a dwell."""
    starts = []
    for index, phase in enumerate(phases):
        if phase.kind != "dwell" and phases[index - 1].kind == "dwell":
            starts.append(phase.start)
    return starts


def dwell_grid(phases: tuple[Phase, ...], spacing: float) -> np.ndarray:
    """Points (rad) on every dwell, ends included, at most ``spacing`` apart."""
    parts = [np.linspace(p.start, p.end, int(math.ceil(p.width / spacing)) + 1)
             for p in phases if p.kind == "dwell"]
    return np.concatenate(parts) if parts else np.zeros(0)


def _knots_of(law) -> np.ndarray:
    """Angles (rad) where the law's acceleration may jump or kink: knots, phase ends."""
    points = [p.start for p in law.phases] + [p.end for p in law.phases]
    if isinstance(law, PiecewiseLinearLaw):
        points += list(law.x)
    if isinstance(law, CorrectedLaw):
        points += list(_knots_of(law.base))
    return np.unique(np.asarray(points, dtype=float)) if points else np.zeros(0)


def _jumps_and_phase_ends(law) -> np.ndarray:
    """Angles (rad) where a drawn base law's acceleration jumps, and the ends of its phases."""
    points = [p.start for p in law.phases] + [p.end for p in law.phases]
    base = law
    while isinstance(base, CorrectedLaw):
        base = base.base
    if isinstance(base, PiecewiseLinearLaw):
        points += list(base.x[:-1][np.diff(base.x) == 0])
    return np.unique(np.asarray(points, dtype=float)) if points else np.zeros(0)


def _evaluation_grid(law, samples: int) -> np.ndarray:
    """A uniform grid plus the knots approached from both sides, so jumps and extremes at knots are seen."""
    grid = np.arange(samples + 1) * (law.cycle / samples)
    knots = _knots_of(law)
    knots = knots[(knots >= 0) & (knots <= law.cycle)]
    left = np.nextafter(knots, -np.inf)
    return np.unique(np.concatenate((grid, knots, left[left >= 0])))


def start_accelerations(law, window: float, samples: int = 512) -> list[float]:
    """max |a| (mm/rad²) over [θs, θs + window] after each motion start θs."""
    values = []
    for start in motion_starts(tuple(law.phases)):
        theta = start + np.linspace(0.0, window, samples + 1)
        values.append(float(np.max(np.abs(law.kinematics(theta).a))))
    return values


@dataclass(frozen=True)
class FilterResult:
    """A filtered law and the figures the source and SPEC.md ask for (mm, mm/rad², rad)."""

    law: CorrectedLaw
    original: Any
    band: ResonanceBand
    spectrum: Spectrum
    removal: FourierLaw
    compensation: FourierLaw | None
    max_deviation: float
    dwell_deviation: float | None
    removal_bound: float
    lift_original: float
    lift_filtered: float
    peak_accel_original: float
    peak_accel_filtered: float
    peak_accel_removed_only: float
    start_accel_original: float | None
    start_accel_filtered: float | None
    start_window: float
    dwell_tol: float
    dwells_kept: bool
    lambda_used: float | None
    notes: tuple[str, ...]

    @property
    def peak_accel_ratio(self) -> float:
        return self.peak_accel_filtered / self.peak_accel_original

    @property
    def start_accel_ratio(self) -> float | None:
        if self.start_accel_original is None or self.start_accel_original == 0:
            return None
        return self.start_accel_filtered / self.start_accel_original

    def report(self) -> dict:
        """SPEC.md ``spectrum`` filter keys and the further figures."""
        band = self.band
        ratio = self.start_accel_ratio
        comp = None
        if self.compensation is not None:
            amplitudes = self.compensation.coefficients
            used = np.flatnonzero(np.abs(amplitudes) > 0) + 1
            comp = {"harmonics": [int(k) for k in used],
                    "max_amplitude_mm": float(2 * np.max(np.abs(amplitudes))) if len(amplitudes) else 0.0,
                    "mean_shift_mm": float(self.compensation.mean),
                    "regularisation": self.lambda_used,
                    "peak_accel_ratio_without": self.peak_accel_removed_only / self.peak_accel_original}
        return {
            "removed": list(band.removed),
            "attenuated": {str(k): g for k, g in band.gains.items() if g > 0},
            "resonant": list(band.core),
            "k_band": [band.k_low, band.k_high],
            "fn_hz": band.fn_hz, "rpm": list(band.rpm), "band": band.band, "neighbours": band.neighbours,
            "taper": band.taper,
            "max_deviation_mm": self.max_deviation,
            "dwell_deviation_mm": self.dwell_deviation,
            "removed_amplitude_sum_mm": self.removal_bound,
            "dwell_tol_mm": self.dwell_tol,
            "dwells_kept": self.dwells_kept,
            "lift_mm": self.lift_original,
            "lift_change_mm": self.lift_filtered - self.lift_original,
            "peak_accel_ratio": self.peak_accel_ratio,
            "peak_accel_mm_per_rad2": {"original": self.peak_accel_original, "filtered": self.peak_accel_filtered},
            "start_accel": {"window_deg": float(np.degrees(self.start_window)),
                            "original_mm_per_rad2": self.start_accel_original,
                            "filtered_mm_per_rad2": self.start_accel_filtered,
                            "ratio": ratio,
                            "change_percent": None if ratio is None else 100.0 * (ratio - 1.0)},
            "compensation": comp,
            "notes": list(self.notes),
        }


def filter_law(law: MotionLaw, band: ResonanceBand, *, harmonics: int = 64, keep_dwells: bool = True,
               dwell_tol: float | None = None, start_window_deg: float = 7.0,
               compensation_harmonics: int | None = None, samples: int | None = None,
               spectrum: Spectrum | None = None) -> FilterResult:
    """Remove (or taper) the resonant harmonics of ``law``; keep the dwells and the lift within ``dwell_tol``.

    The filtered law is law − Σ_{k} (1 − g_k)·(term k) (``CorrectedLaw``): exact, every other harmonic
    kept. On the dwells it deviates by the removed terms, at most Σ (1 − g_k) A_k. When that exceeds
    ``dwell_tol`` (mm, default 1e-3 × lift) and ``keep_dwells`` is set, a compensation δ made only of
    harmonics outside the removed set (k ≤ ``compensation_harmonics``, default 2·max removed + 8, and a
    constant) is added: the least-squares fit of −(removed terms) on the dwells and at the extremes of s,
    regularised by λ·mean(δ² + δ''²/(k_b ω0)⁴) — the displacement and acceleration it costs (k_b the
    lowest touched harmonic). λ is the largest that meets the tolerance;
    if none does, the smallest deviation reached is reported with its cost. The resonant harmonics
    stay exactly zero either way.

    Parameters
    ----------
    band : from ``resonant_harmonics``.
    harmonics : harmonics analysed (at least the highest one touched).
    start_window_deg : window after each motion start over which max |a| is the start-of-motion load
        (the source saw it over about the first 7°).
    samples : uniform grid for maxima (default ≥ 64 points per period of the highest harmonic, ≥ 2^14).
    """
    cycle = law.cycle
    omega = 2.0 * np.pi / cycle
    notes: list[str] = []
    wide = max(harmonics, band.highest)
    if spectrum is None or len(spectrum.coefficients) < wide:
        spectrum = analyse(law, wide)
    if not spectrum.converged:
        notes.append(f"FFT analysis did not reach its tolerance: coefficient error {spectrum.coefficient_error:.3g} mm")
    removal = np.zeros(band.highest, dtype=complex)
    for k, gain in band.gains.items():
        removal[k - 1] = -(1.0 - gain) * spectrum.coefficients[k - 1]
    removal_law = FourierLaw(cycle, 0.0, removal)
    bound = float(np.sum(2.0 * np.abs(removal)))
    phases = tuple(law.phases)
    if samples is None:
        top = max(band.highest, compensation_harmonics or 0, 2 * band.highest + 8)
        samples = max(1 << 14, 1 << int(math.ceil(math.log2(64 * (top + 1)))))
    grid = _evaluation_grid(law, samples)
    base = law.kinematics(grid)
    lift = float(np.ptp(base.s))
    tol = 1e-3 * lift if dwell_tol is None else float(dwell_tol)
    if dwell_tol is None:
        notes.append(f"dwell tolerance not given: 1e-3 of the lift, {tol:.4g} mm")
    dwells = dwell_grid(phases, cycle / samples)
    extremes = grid[[int(np.argmax(base.s)), int(np.argmin(base.s))]]
    keep_points = np.concatenate((dwells, extremes))

    def deviation_on(points, correction: FourierLaw) -> float:
        if len(points) == 0:
            return 0.0
        return float(np.max(np.abs(evaluate_series(correction.mean, correction.coefficients, cycle, points))))

    plain_dwell = deviation_on(keep_points, removal_law)
    correction = removal_law
    compensation = None
    lam = None
    if not band.removed:
        notes.append("no harmonic falls in the band: nothing removed")
    elif keep_dwells and plain_dwell > tol:
        highest = compensation_harmonics or (2 * max(band.gains) + 8)
        # fit on 16 points per period of the highest harmonic, check on the fine grid
        fit_points = np.concatenate((dwell_grid(phases, cycle / (16 * highest)), extremes))
        compensation, lam, reached = _compensate(removal_law, fit_points, keep_points, band, tol, omega, highest)
        correction = FourierLaw(cycle, compensation.mean, _add_series(removal, compensation.coefficients))
        if not reached:
            notes.append("the dwells and the lift cannot be kept within the tolerance with the harmonics "
                         "outside the band; the smallest deviation reached is reported with its cost")
    filtered = CorrectedLaw(law, FourierLaw(cycle, correction.mean, correction.coefficients, phases))
    delta = correction.kinematics(grid)
    a_filtered = base.a + delta.a
    a_removed = base.a + removal_law.kinematics(grid).a
    peak = float(np.max(np.abs(base.a)))
    dwell_dev = deviation_on(dwells, correction) if len(dwells) else None
    kept_dev = deviation_on(keep_points, correction)
    dwells_kept = kept_dev <= tol * (1 + 1e-9)
    if compensation is not None:
        notes.append(f"plain removal moved the dwells/lift by {plain_dwell:.4g} mm (> {tol:.4g} mm); the compensation "
                     f"brings it to {kept_dev:.4g} mm at peak-acceleration ratio "
                     f"{np.max(np.abs(a_filtered)) / peak:.4f} (removal alone: {np.max(np.abs(a_removed)) / peak:.4f})")
    window = float(np.radians(start_window_deg))
    starts_before = start_accelerations(law, window)
    starts_after = start_accelerations(filtered, window)
    return FilterResult(
        law=filtered, original=law, band=band, spectrum=spectrum, removal=removal_law, compensation=compensation,
        max_deviation=float(np.max(np.abs(delta.s))), dwell_deviation=dwell_dev, removal_bound=bound,
        lift_original=lift, lift_filtered=float(np.ptp(base.s + delta.s)),
        peak_accel_original=peak, peak_accel_filtered=float(np.max(np.abs(a_filtered))),
        peak_accel_removed_only=float(np.max(np.abs(a_removed))),
        start_accel_original=max(starts_before) if starts_before else None,
        start_accel_filtered=max(starts_after) if starts_after else None,
        start_window=window, dwell_tol=tol, dwells_kept=bool(dwells_kept), lambda_used=lam, notes=tuple(notes))


def _add_series(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    out = np.zeros(max(len(first), len(second)), dtype=complex)
    out[:len(first)] += first
    out[:len(second)] += second
    return out


def _compensate(removal: FourierLaw, points: np.ndarray, check_points: np.ndarray, band: ResonanceBand,
                tol: float, omega: float, highest: int) -> tuple[FourierLaw, float, bool]:
    """δ = x0 + 2 Re Σ_{k∈C} x_k e^{ikω0θ}, C = {1..highest} \\ band, minimising
    mean_D (removal + δ)² + λ Σ_k 2|x_k|² (1 + (k/k_b)⁴), k_b the lowest touched harmonic: the mean
    square over the cycle of δ (the displacement change) plus δ''/(k_b ω0)² (the acceleration change,
    weighted to equal the displacement at the band).

    Solved for every λ from one SVD of the prewhitened design matrix on the fit points D; the
    largest λ whose max deviation on ``check_points`` is ≤ tol is used (the least cost), else the
    one with the smallest deviation.
    """
    allowed = [k for k in range(1, highest + 1) if k not in band.gains]
    reference = float(min(band.gains))

    def design_of(theta: np.ndarray) -> np.ndarray:
        columns = [np.ones(len(theta))]
        for k in allowed:
            arg = k * omega * theta
            columns += [2.0 * np.cos(arg), -2.0 * np.sin(arg)]
        return np.column_stack(columns)

    count = len(points)
    target = -evaluate_series(removal.mean, removal.coefficients, removal.cycle, points)
    check_target = -evaluate_series(removal.mean, removal.coefficients, removal.cycle, check_points)
    design = design_of(points) / math.sqrt(count)
    check_design = design_of(check_points)
    penalty = np.concatenate(([0.0], np.repeat([2.0 * (1.0 + (k / reference) ** 4) for k in allowed], 2)))
    # the constant costs nothing; a tiny weight keeps the prewhitening invertible
    penalty[0] = 1e-6 * penalty[1:].min()
    whiten = 1.0 / np.sqrt(penalty)
    u, sigma, vt = np.linalg.svd(design * whiten, full_matrices=False)
    projected = u.T @ (target / math.sqrt(count))
    best = None
    chosen = None
    for lam in sigma[0] ** 2 * np.logspace(2, -16, 109):
        x = whiten * (vt.T @ (sigma / (sigma**2 + lam) * projected))
        deviation = float(np.max(np.abs(check_design @ x - check_target)))
        if best is None or deviation < best[0]:
            best = (deviation, x, lam)
        if deviation <= tol:
            chosen = (deviation, x, lam)
            break
    deviation, x, lam = chosen or best
    coefficients = np.zeros(highest, dtype=complex)
    for index, k in enumerate(allowed):
        coefficients[k - 1] = x[1 + 2 * index] + 1j * x[2 + 2 * index]
    return FourierLaw(removal.cycle, float(x[0]), coefficients), float(lam), chosen is not None


# =============================================================================================
# Polylines of the acceleration: export, lead-in segments
# =============================================================================================

def acceleration_polyline(law: MotionLaw, step_deg: float = 0.1, *, extra_knots=(),
                          phases: tuple[Phase, ...] | None = None, from_rest: bool = True) -> PiecewiseLinearLaw:
    """The law's acceleration as a polyline on a uniform step (deg) plus its knots and phase ends.

    A jump of a (left and right limits differ) becomes two vertices at one θ, as SPEC.md draws it.
    ``from_rest``: start from v = 0, s = 0 at θ = 0, as a drawn law is read back (SPEC.md); otherwise
    the law's own v(0), s(0). Chord error of a smooth a: step²·max|a''|/8 (step in rad).
    """
    if not (np.isfinite(step_deg) and 0 < step_deg <= 30):
        raise CamcadError(f"step {step_deg!r} deg must be in (0, 30]", "polyline", "give e.g. 0.1 deg")
    cycle = law.cycle
    count = max(8, int(math.ceil(cycle / np.radians(step_deg) - 1e-9)))
    grid = np.linspace(0.0, cycle, count + 1)
    breaks = _knots_of(law)
    if len(breaks) > 4 * count:
        # a densely drawn base: keep its jumps and the phase ends, sample the rest on the grid
        breaks = _jumps_and_phase_ends(law)
    knots = np.concatenate((grid, breaks, np.asarray(extra_knots, dtype=float)))
    knots = np.unique(knots[(knots >= 0.0) & (knots <= cycle)])
    right = law.kinematics(knots).a
    left = law.kinematics(np.nextafter(knots, -np.inf).clip(0.0)).a
    left[0] = right[0]
    right[-1] = left[-1]
    scale = max(float(np.max(np.abs(right))), 1e-300)
    jump = np.abs(right - left) > 1e-9 * scale
    repeats = np.where(jump, 2, 1)
    x = np.repeat(knots, repeats)
    a = np.empty(len(x))
    first = np.cumsum(repeats) - repeats
    a[first] = np.where(jump, left, right)
    a[first[jump] + 1] = right[jump]
    start = law.kinematics(np.zeros(1))
    v0, s0 = (0.0, 0.0) if from_rest else (float(start.v[0]), float(start.s[0]))
    return PiecewiseLinearLaw(x, a, cycle, tuple(law.phases if phases is None else phases), v0, s0)


def _right_value(law: PiecewiseLinearLaw, theta: float) -> float:
    return float(law.kinematics(np.array([theta])).a[0])


def _left_value(law: PiecewiseLinearLaw, theta: float) -> float:
    return float(law.kinematics(np.array([max(np.nextafter(theta, -np.inf), 0.0)])).a[0])


@dataclass(frozen=True)
class LeadInResult:
    """Lead-in segments before each motion, rebalanced (mm/rad², rad, mm).

    ``segments``: (start, end, a) of each plateau. ``start_jump_*``: the acceleration jump at the start
    of each motion before, and the largest jump there after (at the start of the lead-in, or at the old
    start). ``max_change``/``rms_change``: what the balance corrector changed elsewhere in the law.
    """

    law: PiecewiseLinearLaw
    unbalanced: PiecewiseLinearLaw
    segments: tuple[tuple[float, float, float], ...]
    angle: float
    fraction: float
    peak_accel: float
    start_jump_original: tuple[float, ...]
    start_jump_new: tuple[float, ...]
    velocity_added: tuple[float, ...]
    lift_original: float
    lift_new: float
    peak_accel_new: float
    max_change: float
    rms_change: float
    scale: float
    balanced: bool
    notes: tuple[str, ...]

    def report(self) -> dict:
        return {
            "angle_deg": float(np.degrees(self.angle)), "fraction": self.fraction,
            "segments": [{"start_deg": float(np.degrees(s)), "end_deg": float(np.degrees(e)),
                          "accel_mm_per_rad2": float(a)} for s, e, a in self.segments],
            "peak_accel_mm_per_rad2": self.peak_accel,
            "start_jump_original_mm_per_rad2": [float(j) for j in self.start_jump_original],
            "start_jump_new_mm_per_rad2": [float(j) for j in self.start_jump_new],
            "start_jump_ratio": [float(n / o) if o > 0 else None
                                 for n, o in zip(self.start_jump_new, self.start_jump_original)],
            "velocity_added_mm_per_rad": [float(v) for v in self.velocity_added],
            "lift_mm": self.lift_original, "lift_change_mm": self.lift_new - self.lift_original,
            "scale": self.scale,
            "peak_accel_ratio": self.peak_accel_new / self.peak_accel if self.peak_accel else None,
            "balance_max_change_mm_per_rad2": self.max_change, "balance_rms_change_mm_per_rad2": self.rms_change,
            "balanced": self.balanced, "notes": list(self.notes),
        }


def add_lead_in(law: MotionLaw, angle_deg: float = 14.0, fraction: float = 0.1, *, step_deg: float = 0.1,
                tol: float | None = None, keep_lift: bool = True, where: str = "lead-in") -> LeadInResult:
    """The source's remedy for the load at the start of motion: before every motion that follows a dwell,
    a plateau of acceleration fraction × max|a| (sign of the motion's first acceleration) over
    ``angle_deg``, so the follower is brought up to the cam at low speed; then the law is rebalanced with
    ``camcad.balance.correct`` (min-change, the plateaus and the dwells held) so it still closes.

    The plateau becomes part of the motion's phase (the dwell before it is shortened). ``tol`` is the
    balance tolerance (fraction of the rise; default the corrector's own). The lead-in adds travel, so
    the balanced law rises further; ``keep_lift`` scales the whole law back to the original lift
    (the balance conditions are linear in a, so the scaled law stays balanced; the plateaus scale too).
    """
    from camcad import balance

    if not (np.isfinite(angle_deg) and angle_deg > 0):
        raise CamcadError(f"lead-in angle {angle_deg!r} deg must be positive", where, "give e.g. 14 (deg)")
    if not (np.isfinite(fraction) and 0 < fraction <= 1):
        raise CamcadError(f"lead-in fraction {fraction!r} must be in (0, 1]", where,
                          "give a fraction of the peak acceleration, e.g. 0.1")
    phases = tuple(law.phases)
    starts = motion_starts(phases)
    if not starts:
        raise CamcadError("the law has no motion that starts after a dwell", where,
                          "give the phases (--phases) so the dwells are known")
    angle = float(np.radians(angle_deg))
    new_phases = list(phases)
    for index, phase in enumerate(phases):
        if phase.kind != "dwell" and phases[index - 1].kind == "dwell":
            dwell = phases[index - 1]
            if not dwell.width > angle * (1 + 1e-9):
                raise CamcadError(f"the dwell before the {phase.kind} at {np.degrees(phase.start):.6g} deg is "
                                  f"{np.degrees(dwell.width):.4g} deg, not longer than the lead-in of "
                                  f"{angle_deg:g} deg",
                                  where, f"use a lead-in shorter than {np.degrees(dwell.width):.4g} deg")
            before = (index - 1) % len(phases)
            new_phases[before] = Phase("dwell", new_phases[before].start, phase.start - angle)
            new_phases[index] = Phase(phase.kind, phase.start - angle, phase.end)
    if any(p.start < 0 for p in new_phases):
        raise CamcadError("a lead-in would start before 0 deg", where,
                          "start the cycle inside the dwell (shift the phases) or shorten the lead-in")
    base = acceleration_polyline(law, step_deg, extra_knots=[s - angle for s in starts])
    peak = float(np.max(np.abs(base.a)))
    xs, as_ = base.x.copy(), base.a.copy()
    segments, jumps_before, jumps_after, velocities = [], [], [], []
    for start in starts:
        phase = next(p for p in phases if p.start == start)
        probe = start + np.linspace(0.0, phase.width / 10.0, 64)
        mean_a = float(np.mean(law.kinematics(probe).a))
        sign = float(np.sign(mean_a)) or (1.0 if phase.kind == "rise" else -1.0)
        level = sign * fraction * peak
        lo = start - angle
        a_left = _left_value(base, lo)
        a_right = _right_value(base, start)
        jumps_before.append(abs(a_right - _left_value(base, start)))
        outside = (xs < lo) | (xs > start)
        inside_grid = np.unique(xs[(xs > lo) & (xs < start)])
        x_new = np.concatenate((xs[outside], [lo, lo], inside_grid, [start, start]))
        a_new = np.concatenate((as_[outside], [a_left, level], np.full(len(inside_grid), level), [level, a_right]))
        order = np.argsort(x_new, kind="stable")
        xs, as_ = x_new[order], a_new[order]
        segments.append((lo, start, level))
        jumps_after.append(max(abs(level - a_left), abs(a_right - level)))
        velocities.append(level * angle)
    unbalanced = PiecewiseLinearLaw(xs, as_, law.cycle, tuple(new_phases))
    held = np.zeros(len(xs), dtype=bool)
    for lo, hi, level in segments:
        held |= (xs >= lo) & (xs <= hi) & (as_ == level)
    kwargs = {} if tol is None else {"tol": tol}
    corrected = balance.correct(unbalanced, "min-change", fixed=held, where=where, **kwargs)
    result = corrected.law
    grid = _evaluation_grid(result, 1 << 14)
    lift_before = float(np.ptp(law.kinematics(_evaluation_grid(law, 1 << 14)).s))
    notes = list(corrected.notes)
    factor = 1.0
    if keep_lift:
        factor = lift_before / float(np.ptp(result.kinematics(grid).s))
        result = result.with_ordinates(result.a * factor)
        segments = [(lo, hi, level * factor) for lo, hi, level in segments]
        jumps_after = [j * factor for j in jumps_after]
        velocities = [v * factor for v in velocities]
        notes.append(f"the whole law scaled by {factor:.6g} to keep the lift of {lift_before:.6g} mm")
    kin = result.kinematics(grid)
    balanced = bool(balance.check(result, corrected.after.tolerance).balanced)
    notes.append(f"lead-in plateaus of {fraction:g} x {peak:.6g} mm/rad^2 over {angle_deg:g} deg before "
                 f"{len(starts)} motion(s); rebalanced with balance.correct (min-change)")
    return LeadInResult(result, unbalanced, tuple(segments), angle, float(fraction), peak, tuple(jumps_before),
                        tuple(jumps_after), tuple(velocities), lift_before, float(np.ptp(kin.s)),
                        float(np.max(np.abs(kin.a))), corrected.max_change, corrected.rms_change, factor,
                        balanced, tuple(notes))


def _closing_harmonic(v0: float, cycle: float, removed, drift_tol: float | None) -> int:
    """The harmonic m of the closing change: drift |v0|/(mω0) ≤ drift_tol, outside and below ``removed``."""
    removed = set(removed)
    wanted = 1 if drift_tol is None or drift_tol <= 0 else \
        max(1, math.ceil(abs(v0) / (2.0 * np.pi / cycle) / drift_tol))
    ceiling = min(removed) if removed else wanted + 1
    below = [k for k in range(1, ceiling) if k not in removed]
    if not below:  # the band starts at k = 1: take the first harmonic above it
        return next(k for k in range(1, max(removed) + 2) if k not in removed)
    return next((k for k in below if k >= wanted), below[-1])


@dataclass(frozen=True)
class ExportedLaw:
    """A law as an acceleration polyline that reads back from a DXF (from rest at s = 0) and closes.

    ``max_change`` (mm/rad²): what the balance corrector changed in the sampled polyline;
    ``max_deviation`` (mm): max |s_polyline − (s_law − s_law(0))|; ``band_amplitudes``: A_k (mm) of the
    polyline at the removed harmonics, computed exactly; ``balanced_with_phases``: the balance check
    of the polyline with the law's own phases (v = 0 at the end of every rise and return).
    """

    law: PiecewiseLinearLaw
    closed: bool
    exact_dwells: bool
    balanced_with_phases: bool
    max_change: float
    max_deviation: float
    band_amplitudes: dict
    notes: tuple[str, ...]

    def report(self) -> dict:
        return {"vertices": len(self.law.x), "closed": self.closed, "exact_dwells": self.exact_dwells,
                "balanced_with_phases": self.balanced_with_phases,
                "balance_max_change_mm_per_rad2": self.max_change, "max_deviation_mm": self.max_deviation,
                "band_amplitudes_mm": {str(k): v for k, v in self.band_amplitudes.items()},
                "notes": list(self.notes)}


def export_polyline(law: MotionLaw, *, step_deg: float = 0.1, tol: float | None = None, removed=(),
                    exact_dwells: bool = False, drift_tol: float | None = None,
                    where: str = "export") -> ExportedLaw:
    """Sample ``law``'s acceleration as a polyline (``acceleration_polyline``) that starts from rest at
    s = 0, as a drawn law is read back, and make it close with ``camcad.balance.correct`` (min-change).

    Default: only the two closure conditions of the whole cycle are imposed, v(T) = 0 and s(T) = 0
    (a filtered law's v(0) is not exactly 0, so starting it from rest leaves a drift), with the least
    change of the form δa = c0 + c1 cos(mω0θ) + c2 sin(mω0θ): the conditions are exact linear
    functionals of the ordinates (``balance.functional_rows``), and this change touches no harmonic
    but 0 and m, so the filtered spectrum is kept. It moves s by about |v(0)|/(mω0) and a by about
    |v(0)|·mω0: m is the lowest harmonic, outside and below the removed ones, that keeps the first
    within ``drift_tol`` (mm; None: m = 1).
    ``exact_dwells``: ``balance.correct`` (min-change) imposes the law's phases instead — a = 0 on the
    dwells and v = 0 at the end of every rise and return — as ``camcad check`` expects of a drawn law
    with its phases; for a filtered law this brings part of the removed harmonics back, which
    ``band_amplitudes`` measures.
    """
    from camcad import balance

    polyline = acceleration_polyline(law, step_deg)
    kwargs = {} if tol is None else {"tol": tol}
    phases = tuple(law.phases)
    notes: list[str] = []
    if exact_dwells:
        corrected = balance.correct(polyline, "min-change", where=where, **kwargs)
        result = corrected.law.with_phases(phases) if phases else corrected.law
        tolerance, max_change = corrected.after.tolerance, corrected.max_change
        notes += list(corrected.notes)
    else:
        harmonic = _closing_harmonic(float(law.kinematics(np.zeros(1)).v[0]), law.cycle, removed, drift_tol)
        conditions = (balance.Condition("v(T)", "v", law.cycle), balance.Condition("s(T)", "s", law.cycle))
        rows = balance.functional_rows(polyline.x, conditions)
        arg = harmonic * (2.0 * np.pi / law.cycle) * polyline.x
        basis = np.column_stack((np.ones(len(arg)), np.cos(arg), np.sin(arg)))
        coefficients = np.linalg.lstsq(rows @ basis, -(rows @ polyline.a), rcond=None)[0]
        change = basis @ coefficients
        result = polyline.with_ordinates(polyline.a + change)
        tolerance = balance.DEFAULT_TOL if tol is None else tol
        max_change = float(np.max(np.abs(change)))
        notes.append(f"closed from rest (the law has v(0) = {law.kinematics(np.zeros(1)).v[0]:.3g} mm/rad) with a "
                     f"change of a of at most {max_change:.3g} mm/rad^2 (constant and harmonic {harmonic})")
    grid = _evaluation_grid(law, 1 << 14)
    s_law = law.kinematics(grid).s - law.kinematics(np.zeros(1)).s[0]
    s_result = result.kinematics(grid).s
    deviation = float(np.max(np.abs(s_result - s_law)))
    band = {}
    if len(removed):
        spectrum = analyse(result, max(removed))
        band = {int(k): float(spectrum.amplitudes[k - 1]) for k in removed}
    ends = result.kinematics(np.array([0.0, law.cycle]))
    limit = tolerance * max(float(np.ptp(s_result)), 1e-300)
    closed = abs(ends.s[1] - ends.s[0]) <= limit and abs(ends.v[1] - ends.v[0]) <= limit
    with_phases = bool(balance.check(result, tolerance).balanced) if phases else bool(closed)
    if not exact_dwells and phases and not with_phases:
        notes.append("the filtered law keeps a small residue on the dwells, so a balance check with the "
                     "original phases reports v != 0 at the ends of the motions; the cycle itself closes")
    return ExportedLaw(result, bool(closed), exact_dwells, with_phases, max_change, deviation, band,
                       tuple(notes))


# =============================================================================================
# The scene's [filter] section, and the pipeline step
# =============================================================================================

FILTER_FIELDS = [
    Field("fn_hz", "float", "Hz", positive=True,
          help="natural frequency of the follower system; omitted: taken from [dynamics]"),
    Field("rpm", "number_or_list", "rpm", positive=True,
          help="speed or [n1, n2] range (or \"n1:n2\"); omitted: taken from [machine]"),
    Field("band", "float", "fraction of fn", default=0.05, minimum=0.0, maximum=0.99,
          help="half-width of the resonance band, e.g. 0.05 for ±5 %"),
    Field("neighbours", "int", "harmonics", default=1, minimum=0, help="harmonics removed on each side"),
    Field("taper", "int", "harmonics", default=0, minimum=0, help="raised-cosine ramp beyond the removed ones"),
    Field("harmonics", "int", "", default=64, minimum=1, maximum=1 << 16, help="harmonics analysed"),
    Field("keep_dwells", "bool", "", default=True, help="compensate so the dwells stay within dwell_tol_mm"),
    Field("dwell_tol_mm", "float", "mm", positive=True, help="default 1e-3 of the lift"),
    Field("lead_in_deg", "float", "deg", positive=True, maximum=180.0, help="lead-in angle, e.g. 14"),
    Field("lead_in_fraction", "float", "of peak acceleration", default=0.1, positive=True, maximum=1.0),
    Field("start_window_deg", "float", "deg", default=7.0, positive=True, maximum=90.0),
    Field("step_deg", "float", "deg", default=0.1, positive=True, maximum=30.0,
          help="vertex step of the filtered polyline"),
    Field("exact_dwells", "bool", "", default=False,
          help="write the filtered law with a = 0 on the dwells (brings part of the band back)"),
    Field("enabled", "bool", "", default=True),
]


@dataclass(frozen=True)
class FilterSettings:
    """Resonance filtering and lead-in settings (Hz, rpm, mm, deg); None = not given."""

    fn_hz: float | None = None
    rpm: tuple[float, float] | None = None
    band: float = 0.05
    neighbours: int = 1
    taper: int = 0
    harmonics: int = 64
    keep_dwells: bool = True
    dwell_tol_mm: float | None = None
    lead_in_deg: float | None = None
    lead_in_fraction: float = 0.1
    start_window_deg: float = 7.0
    step_deg: float = 0.1
    exact_dwells: bool = False
    enabled: bool = True


def parse_filter(table: Any, where: str = "[filter]") -> FilterSettings:
    """A scene's ``[filter]`` table → FilterSettings (unknown keys, types and ranges checked)."""
    if isinstance(table, dict) and isinstance(table.get("rpm"), str):
        table = {**table, "rpm": list(parse_rpm(table["rpm"], f"{where} rpm"))}
    values = read_table(table, FILTER_FIELDS, where)
    rpm = values.pop("rpm")
    if rpm is not None:
        rpm = parse_rpm(rpm, f"{where} rpm")
    return FilterSettings(rpm=rpm, **values)


@dataclass(frozen=True)
class FilterOutcome:
    """The pipeline step: the law to continue with (a closed polyline) and what was done to get it."""

    law: PiecewiseLinearLaw
    filtered: FilterResult | None
    lead_in: LeadInResult | None
    exported: ExportedLaw | None
    band_amplitudes: dict = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    @property
    def passed(self) -> bool:
        """The dwells were kept within their tolerance, the written law closes and a lead-in balanced."""
        return not ((self.filtered is not None and not self.filtered.dwells_kept)
                    or (self.exported is not None and not self.exported.closed)
                    or (self.lead_in is not None and not self.lead_in.balanced))

    def report(self) -> dict:
        out: dict = {"pipeline_notes": list(self.notes)} if self.notes else {}
        if self.filtered is not None:
            out.update(self.filtered.report())
        if self.lead_in is not None:
            out["lead_in"] = self.lead_in.report()
        if self.exported is not None:
            out["export"] = self.exported.report()
        if self.band_amplitudes:
            out["final_band_amplitudes_mm"] = {str(k): v for k, v in self.band_amplitudes.items()}
        return out


def apply_filter(law: MotionLaw, settings: FilterSettings, *, fn_hz: float | None = None,
                 rpm=None, where: str = "[filter]") -> FilterOutcome:
    """Resonance filtering (when a natural frequency and a speed range are known) and lead-in segments
    (when ``lead_in_deg`` is set), in that order; returns the closed polyline law to continue with.

    ``fn_hz``/``rpm`` fill in what ``settings`` leaves out (e.g. from the scene's [dynamics] and [machine]).
    """
    fn = settings.fn_hz if settings.fn_hz is not None else fn_hz
    speeds = settings.rpm if settings.rpm is not None else rpm
    filtered = exported = lead = None
    current = law
    if fn is not None:
        if speeds is None:
            raise CamcadError("resonance filtering needs the speed range", where,
                              "add rpm = [n1, n2] to [filter] or [machine], or pass --rpm N1:N2")
        band = resonant_harmonics(fn, speeds, settings.band, settings.neighbours, settings.taper, where)
        filtered = filter_law(law, band, harmonics=settings.harmonics, keep_dwells=settings.keep_dwells,
                              dwell_tol=settings.dwell_tol_mm, start_window_deg=settings.start_window_deg)
        current = filtered.law
    elif settings.lead_in_deg is None:
        raise CamcadError("nothing to do: no natural frequency and no lead-in", where,
                          "give fn_hz (or a [dynamics] section) and rpm, or lead_in_deg")
    if settings.lead_in_deg is not None:
        lead = add_lead_in(current, settings.lead_in_deg, settings.lead_in_fraction,
                           step_deg=settings.step_deg, where=where)
        final = lead.law
    else:
        exported = export_polyline(current, step_deg=settings.step_deg,
                                   removed=filtered.band.removed if filtered else (),
                                   exact_dwells=settings.exact_dwells,
                                   drift_tol=filtered.dwell_tol / 4 if filtered else None, where=where)
        final = exported.law
    band_after = {}
    notes = []
    if filtered is not None and filtered.band.removed:
        # what the written law carries at the removed harmonics (the lead-in's plateaus and exact dwells
        # put some of it back), against what the original had there
        after = analyse(final, max(filtered.band.removed))
        band_after = {int(k): float(after.amplitudes[k - 1]) for k in filtered.band.removed}
        before = sum(2 * abs(filtered.spectrum.coefficients[k - 1]) for k in filtered.band.removed)
        now = sum(band_after.values())
        if lead is not None and before > 0:
            notes.append(f"the lead-in plateaus (jumps of a) have harmonics of their own: the written law carries "
                         f"{now:.3g} mm summed over the removed harmonics, {100 * now / before:.0f} % of the "
                         f"original's {before:.3g} mm")
    return FilterOutcome(final, filtered, lead, exported, band_after, tuple(notes))
