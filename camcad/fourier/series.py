"""The Fourier series of a motion law and its spectrum: amplitudes, initial phases, evaluation.

Conventions (the batten study; see camcad.fourier): s(θ) = mean + Σ A_k sin(k ω0 θ + φ_k), ω0 = 2π/cycle;
c_k = (1/T) ∫ s e^{−ikω0θ} dθ, A_k = 2|c_k|, φ_k = arg c_k + π/2.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from camcad.law.law import Kinematics, Phase

# =============================================================================================
# The series and its spectrum
# =============================================================================================

def amplitudes_of(coefficients: np.ndarray) -> np.ndarray:
    """A_k = 2|c_k| (units of the analysed function).

    Parameters
    ----------
    coefficients : ndarray
        c_k, complex, in the function's units (mm for s).

    Returns
    -------
    ndarray
        A_k, same units (mm for s).

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.fourier import amplitudes_of
    >>> amplitudes_of(np.array([3 + 4j, -5.0])).tolist()
    [10.0, 10.0]
    """
    return 2.0 * np.abs(np.asarray(coefficients))


def initial_phases_of(coefficients: np.ndarray) -> np.ndarray:
    """φ_k = arg c_k + π/2 wrapped to (−π, π] (rad): the sine form s = Σ A_k sin(kω0θ + φ_k).

    Parameters
    ----------
    coefficients : ndarray
        c_k, complex, mm.

    Returns
    -------
    ndarray
        φ_k, rad.

    Examples
    --------
    −10 cos θ = 10 sin(θ − π/2): c_1 = −5, φ_1 = −π/2.

    >>> import math
    >>> import numpy as np
    >>> from camcad.fourier import initial_phases_of
    >>> round(float(initial_phases_of(np.array([-5.0 + 0j]))[0]) / math.pi, 12)
    -0.5
    """
    phase = np.angle(np.asarray(coefficients)) + np.pi / 2.0
    return np.pi - np.mod(np.pi - phase, 2.0 * np.pi)


def coefficients_from(amplitudes, phases_rad) -> np.ndarray:
    """c_k from the sine form: c_k = (A_k/2) e^{i(φ_k − π/2)}.

    Parameters
    ----------
    amplitudes : array_like
        A_k, mm.
    phases_rad : array_like
        φ_k, rad.

    Returns
    -------
    ndarray
        c_k, complex, mm.

    Examples
    --------
    sin θ (A = 1, φ = 0) is c_1 = −i/2:

    >>> from camcad.fourier import coefficients_from
    >>> c = coefficients_from([1.0], [0.0])
    >>> round(float(c[0].real), 12), round(float(c[0].imag), 12)
    (0.0, -0.5)
    """
    return 0.5 * np.asarray(amplitudes, dtype=float) * np.exp(1j * (np.asarray(phases_rad, dtype=float) - np.pi / 2))


def evaluate_series(mean: float, coefficients: np.ndarray, cycle: float, theta, order: int = 0) -> np.ndarray:
    """d^order/dθ^order of mean + 2 Re Σ_k c_k e^{ikω0θ} at θ (rad); units of s per rad^order.

    Parameters
    ----------
    mean : float
        The mean, mm.
    coefficients : ndarray
        c_1 … c_N, complex, mm.
    cycle : float
        T, rad.
    theta : array_like
        The angles, rad.
    order : int
        The derivative's order.

    Returns
    -------
    ndarray
        The values, mm per rad^order.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from camcad.fourier import evaluate_series
    >>> [round(float(x), 12) for x in evaluate_series(10.0, np.array([-5.0 + 0j]), 2 * math.pi, [0.0, math.pi], 2)]
    [10.0, -10.0]
    """
    return evaluate_series_orders(mean, coefficients, cycle, theta, (order,))[0]


def evaluate_series_orders(mean: float, coefficients: np.ndarray, cycle: float, theta,
                           orders=(0, 1, 2, 3)) -> list[np.ndarray]:
    """Several derivatives of the series at θ (rad), by Horner's scheme in z = e^{iω0θ}.

    Σ_k c_k z^k = z^{k_1}(c_{k_1} + z^{k_2−k_1}(c_{k_2} + … + z^{k_m−k_{m−1}} c_{k_m})) over the m
    non-zero terms k_1 < … < k_m: m complex multiply-adds per point and order, and an exponential
    table only for each distinct gap k_{i+1} − k_i > 1 (a filter's removal is a few harmonics high
    up in a long, mostly zero, coefficient vector); |z| = 1, so the round-off grows at most like
    m·eps·Σ|c_k|.

    Parameters
    ----------
    mean : float
        The mean, mm.
    coefficients : ndarray
        c_1 … c_N, complex, mm.
    cycle : float
        T, rad.
    theta : array_like
        The angles, rad.
    orders : sequence of int
        The derivatives' orders.

    Returns
    -------
    list of ndarray
        One array per order, mm per rad^order.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from camcad.fourier import evaluate_series_orders
    >>> s, v = evaluate_series_orders(10.0, np.array([-5.0 + 0j]), 2 * math.pi, [math.pi / 2], (0, 1))
    >>> round(float(s[0]), 12), round(float(v[0]), 12)             # 10 - 10 cos, its slope 10 sin
    (10.0, 10.0)
    """
    theta = np.asarray(theta, dtype=float)
    flat = theta.ravel()
    coefficients = np.asarray(coefficients, dtype=complex)
    terms = np.flatnonzero(coefficients)                     # indices k − 1 of the non-zero terms
    outs = [np.full(flat.shape, mean if order == 0 else 0.0) for order in orders]
    if len(terms) and len(flat):
        omega0 = 2.0 * np.pi / cycle
        w = (terms + 1) * omega0
        weighted = np.stack([coefficients[terms] * (1j * w) ** order for order in orders], axis=1)
        powers: dict[int, np.ndarray] = {}

        def z_to(gap: int) -> np.ndarray:
            """z^gap = e^{i gap ω0 θ} at every point, one table per distinct gap."""
            if gap not in powers:
                powers[gap] = np.exp(1j * (gap * omega0) * flat)[:, None]
            return powers[gap]

        total = np.zeros((len(flat), len(orders)), dtype=complex)
        total += weighted[-1]
        for index in range(len(terms) - 2, -1, -1):
            total *= z_to(int(terms[index + 1] - terms[index]))
            total += weighted[index]
        values = 2.0 * np.real(total * z_to(int(terms[0]) + 1))
        for index, out in enumerate(outs):
            out += values[:, index]
    return [out.reshape(theta.shape) for out in outs]


def series_on_grid(mean: float, coefficients: np.ndarray, samples: int, order: int = 0,
                   cycle: float = 2 * np.pi) -> np.ndarray:
    """The series' order-th derivative at θ_j = j T/M, j = 0..M−1, by one inverse FFT (needs N < M/2).

    Parameters
    ----------
    mean : float
        The mean, mm.
    coefficients : ndarray
        c_1 … c_N, complex, mm.
    samples : int
        M.
    order : int
        The derivative's order.
    cycle : float
        T, rad.

    Returns
    -------
    ndarray
        The values at the M points, mm per rad^order.

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.fourier import series_on_grid
    >>> [round(float(x), 12) for x in series_on_grid(10.0, np.array([-5.0 + 0j]), 4)]   # at 0, 90, 180, 270 deg
    [0.0, 10.0, 20.0, 10.0]
    """
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

    Parameters
    ----------
    cycle : float
        T, rad.
    mean : float
        The mean displacement, mm.
    coefficients : ndarray
        c_1 … c_N, complex, mm.
    phases : tuple of Phase
        The phases it is said to have (rad).

    Examples
    --------
    s = 10 − 10 cos θ is mean 10 and c_1 = −5 (mm):

    >>> import math
    >>> import numpy as np
    >>> from camcad.fourier import FourierLaw
    >>> law = FourierLaw(2 * math.pi, 10.0, np.array([-5.0 + 0j]))
    >>> kin = law.kinematics(np.array([math.pi]))
    >>> round(float(kin.s[0]), 12), round(float(kin.a[0]), 12)          # s(pi) = 20 mm, a(pi) = -10 mm/rad²
    (20.0, -10.0)
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
                        phases: tuple[Phase, ...] = ()) -> FourierLaw:
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

    Parameters
    ----------
    base : MotionLaw
        The law (θ in rad, s in mm).
    correction : FourierLaw
        What is added to it (mm), over the same cycle.

    Examples
    --------
    Taking the first harmonic out of s = 10 − 10 cos θ leaves its mean, 10 mm:

    >>> import numpy as np
    >>> import camcad
    >>> law = camcad.compose([("rise", 180), ("return", 180)], 20.0, "harmonic")       # s = 10 - 10 cos(theta), mm
    >>> from camcad.fourier import CorrectedLaw, FourierLaw
    >>> flat = CorrectedLaw(law, FourierLaw(law.cycle, 0.0, np.array([5.0 + 0j])))
    >>> [round(float(s), 9) for s in flat.kinematics(np.radians([0.0, 90.0, 180.0])).s]
    [10.0, 10.0, 10.0]
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

    ``camcad.analyse`` returns it; the example is there.

    Attributes
    ----------
    cycle : float
        T, rad.
    mean : float
        The mean displacement, mm.
    coefficients : ndarray
        c_1 … c_N of s, complex, mm (``amplitudes`` A_k = 2|c_k|, ``phases`` φ_k in rad).
    accel_mean : float
        The mean of a, mm/rad².
    accel_coefficients : ndarray
        c_k of a, mm/rad².
    tail_mean_square : float
        Σ_{k>N} A_k²/2, mm²: exact for a FourierLaw, the jump-asymptotic estimate for the exact methods,
        the discrete remainder for FFT.
    mean_square : float
        (1/T)∫(s − mean)² dθ when computed independently of the coefficients (NaN otherwise), mm².
    coefficient_error : float
        A bound on the error of each amplitude A_k, mm: round-off for the exact methods, the difference
        between the two finest samplings for FFT.
    accel_coefficient_error : float
        The same for a, mm/rad².
    method : str
        "exact" or "fft".
    samples : int
        The FFT's samples (0 for exact).
    converged : bool
        Whether the FFT met its tolerance.
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



