"""Fourier analysis entry points: exact where the law allows it, FFT otherwise; truncation errors.
"""

from __future__ import annotations

import math
from typing import cast

import numpy as np

from camcad.fourier.exact import Piece, checked_pieces, pieces_coefficients, polyline_analysis
from camcad.fourier.series import CorrectedLaw, FourierLaw, Spectrum, series_on_grid
from camcad.law.law import MotionLaw, PiecewiseLinearLaw
from camcad.law.standard import CompositeLaw

# =============================================================================================
# Analysis entry points
# =============================================================================================

def exact_available(law) -> bool:
    """True when ``camcad.analyse`` can integrate the law exactly (drawn polyline, known composite, series).

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad).

    Returns
    -------
    bool
        Whether the exact method applies (no unit).

    Examples
    --------
    >>> import numpy as np
    >>> import camcad
    >>> law = camcad.compose([("rise", 180), ("return", 180)], 20.0, "harmonic")       # s = 10 - 10 cos(theta), mm
    >>> from camcad.fourier import exact_available
    >>> exact_available(law)
    True
    """
    if isinstance(law, (PiecewiseLinearLaw, FourierLaw)):
        return True
    if isinstance(law, CorrectedLaw):
        return exact_available(law.base)
    if isinstance(law, CompositeLaw):
        return checked_pieces(law) is not None
    return False


def analyse(law: MotionLaw, harmonics: int = 64, *, tol: float = 1e-9, method: str = "auto",
            max_samples: int = 1 << 22, tail_harmonics: int | None = None) -> Spectrum:
    """Amplitudes and initial phases of the harmonics of a law's displacement and acceleration.

    The series is written in the source's form s(θ) = mean + Σ A_k sin(k ω0 θ + φ_k), ω0 = 2π/cycle,
    with A_k = 2|c_k| and φ_k = arg c_k + π/2 from c_k = (1/T) ∫ s e^{−ikω0θ} dθ; the acceleration analog
    a = d²s/dθ² is analysed the same way. Exact where the law allows it: a drawn (piecewise-linear)
    acceleration integrated by parts over its knots, a composite standard law integrated piece by
    piece; any other law by FFT of a sampling doubled until it converges. At n rpm the k-th harmonic
    has the frequency k·n/60 Hz.

    Parameters
    ----------
    law : MotionLaw
        A law over one cycle: θ in rad, s in mm (or rad of swing), a in mm/rad².
    harmonics : int
        N, the number of harmonics returned (k = 1..N).
    tol : float
        FFT path only: the sampling is doubled until two successive samplings agree on every A_k,
        k ≤ N, within ``tol`` mm (the accuracy knob); ignored by the exact methods.
    method : str
        "auto" (exact when available, else FFT), "exact" or "fft".
    max_samples : int
        The largest FFT sampling tried (a count); ``converged`` is False when it was not enough.
    tail_harmonics : int, optional
        Exact methods: coefficients up to this k (default 4N) are computed and summed exactly into the
        remainder Σ_{k>N} A_k²/2; only the part beyond is the asymptotic estimate. The knob of the
        truncation-error accuracy near N.

    Returns
    -------
    Spectrum
        ``mean`` (mm), ``amplitudes`` A_k (mm), ``phases`` φ_k (rad), ``accel_amplitudes`` (mm/rad²),
        ``accel_phases`` (rad), ``rms_error(n)`` the RMS error of the series truncated after n
        harmonics (mm, by Parseval), ``coefficient_error`` (mm), ``method``, ``converged``.

    Raises
    ------
    ValueError
        ``harmonics`` < 1, an unknown method, or "exact" for a law that has no exact analysis.

    References
    ----------
    Harmonic analysis of cam motion laws, RMS error against the number of harmonics kept, resonance
    filtering: PhD abstract on the batten mechanism of the STB loom, Novosibirsk (the batten study; see
    ``docs/analyses.md``).

    Examples
    --------
    The full-cycle harmonic law s = h(1 − cos θ)/2 is one sine: mean h/2, A_1 = h/2, φ_1 = −90°, nothing
    else; the RMS error of the mean alone is A_1/√2:

    >>> import math
    >>> import camcad
    >>> law = camcad.compose([("rise", 180), ("return", 180)], 20.0, "harmonic")
    >>> spectrum = camcad.analyse(law, 8)
    >>> spectrum.method, round(spectrum.mean, 12), round(float(spectrum.amplitudes[0]), 12)
    ('exact', 10.0, 10.0)
    >>> round(math.degrees(spectrum.phases[0]), 9), float(spectrum.amplitudes[1:].max()) < 1e-12
    (-90.0, True)
    >>> round(spectrum.rms_error(0) * math.sqrt(2.0), 12), spectrum.rms_error(1) < 1e-12
    (10.0, True)

    The exact and the FFT paths agree on a cycloidal cycle:

    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> exact, fft = camcad.analyse(law, 32), camcad.analyse(law, 32, method="fft")
    >>> exact.method, fft.method, float(abs(exact.amplitudes - fft.amplitudes).max()) < 1e-9
    ('exact', 'fft', True)
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
        r = polyline_analysis(law, harmonics, tail_to)
        return Spectrum(cycle, r["mean"], r["coefficients"], r["accel_mean"], r["accel_coefficients"],
                        r["tail"], r["mean_square"], r["error"], r["accel_error"], "exact")
    if isinstance(law, CompositeLaw):
        pieces = cast(list[Piece], checked_pieces(law))  # exact_available: every shape is known
        mean, c, tail, error = pieces_coefficients(pieces, cycle, harmonics, 0, tail_to)
        accel_mean, ca, _, accel_error = pieces_coefficients(pieces, cycle, harmonics, 2, harmonics, with_tail=False)
        raw_square = math.fsum(p.integral_of_square() for p in pieces) / cycle
        return Spectrum(cycle, mean, c, accel_mean, ca, tail, raw_square - mean**2, error, accel_error, "exact")
    raise ValueError(f"no exact analysis for {type(law).__name__}")


def _fft_analysis(law, harmonics: int, tol: float, max_samples: int) -> Spectrum:
    cycle = law.cycle
    samples = max(1024, 1 << math.ceil(math.log2(8 * (harmonics + 1))))
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

    Parameters
    ----------
    s : ndarray
        The samples, mm.
    cycle : float
        T, rad.
    harmonics : int
        N (below M/2).
    a : ndarray, optional
        The acceleration samples, mm/rad².

    Returns
    -------
    Spectrum
        Harmonics 1..N (mm, mm/rad²).

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from camcad.fourier import analyse_samples
    >>> theta = 2 * math.pi * np.arange(64) / 64
    >>> spectrum = analyse_samples(10 - 10 * np.cos(theta), 2 * math.pi, 4)
    >>> round(spectrum.mean, 12), [round(float(x), 12) for x in spectrum.amplitudes]
    (10.0, [10.0, 0.0, 0.0, 0.0])
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

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, s in mm).
    spectrum : Spectrum
        Its spectrum (``camcad.analyse``).
    ns : sequence of int
        The truncations.
    samples : int, optional
        The grid's size.

    Returns
    -------
    ndarray
        One maximum per n, mm.

    Examples
    --------
    >>> import numpy as np
    >>> import camcad
    >>> law = camcad.compose([("rise", 180), ("return", 180)], 20.0, "harmonic")       # s = 10 - 10 cos(theta), mm
    >>> from camcad.fourier import max_errors
    >>> [round(float(e), 9) for e in max_errors(law, camcad.analyse(law, 4), [0, 1])]    # |10 cos|, then nothing
    [10.0, 0.0]
    """
    ns = np.atleast_1d(np.asarray(ns, dtype=int))
    if samples is None:
        samples = max(1 << 14, 1 << math.ceil(math.log2(64 * (int(ns.max()) + 1))))
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

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, s in mm).
    tol : float
        The RMS error allowed, mm.
    max_harmonics : int
        At most this many harmonics.
    start : int
        The first spectrum's size.

    Returns
    -------
    tuple
        n (None when ``max_harmonics`` do not reach ``tol``) and the Spectrum (mm).

    Examples
    --------
    One harmonic is s = 10 − 10 cos θ exactly:

    >>> import numpy as np
    >>> import camcad
    >>> law = camcad.compose([("rise", 180), ("return", 180)], 20.0, "harmonic")       # s = 10 - 10 cos(theta), mm
    >>> from camcad.fourier import least_harmonics
    >>> least_harmonics(law, 1e-6)[0]
    1
    """
    return grow_until_found(lambda count: analyse(law, count), tol, start, max_harmonics)


def grow_until_found(spectrum_of, tol: float, start: int, max_harmonics: int):
    """(least harmonics meeting ``tol``, spectrum): ``spectrum_of(N)`` at a growing N until N has headroom."""
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




