"""One harmonic of a law and the follower's response to it from rest: the beats of the batten study's Figs. 8–9.

The PhD abstract on the batten mechanism of the STB loom (Novosibirsk) plots the 17th harmonic of its
displacement and acceleration laws and reads beats in them where the working member moves — the forced
frequency of that harmonic is close to the free frequency of the driven chain. Here the k-th harmonic of s,
s_k(t) = A_k sin(Ω t + φ_k) with Ω = k ω0 ω (ω0 = 2π/cycle, ω the cam speed in rad/s), drives the elastic
follower of ``camcad dynamics`` (constant stiffness, ζ) from rest:

    ÿ + 2ζωn ẏ + ωn² y = 2ζωn ṡ_k + ωn² s_k,     y(0) = ẏ(0) = 0,

solved in closed form: the steady part Y sin(Ωt + φ_k + δ) with Y e^{iδ} = A_k (ωn² + 2iζωnΩ)/(ωn² − Ω² + 2iζωnΩ),
plus the free vibration e^{−ζωn t}(C1 cos ωd t + C2 sin ωd t) that cancels it at t = 0. Their sum beats with
the period 2π/|Ω − ωd|. Units: the law's (mm or rad), s; accelerations in the law's unit per s².
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camcad.dynamics.model import ElasticFollower, rpm_to_rad_s
from camcad.errors import CamcadError
from camcad.fourier.analysis import analyse
from camcad.law.law import MotionLaw

#: the most cycles drawn (one and a half beat periods when they fit)
MAX_CYCLES = 12


@dataclass(frozen=True)
class HarmonicBeats:
    """The k-th harmonic of a law at a speed, and the follower's response to it from rest.

    ``theta_deg``: cam angle (deg, over ``cycles`` cycles); ``s``, ``a``: the harmonic's displacement (law unit)
    and acceleration (law unit/s²); ``y``, ``y_accel``: the follower's; ``amplitude`` A_k, ``phase_deg`` φ_k;
    ``forced_hz`` Ω/2π, ``free_hz`` ωd/2π, ``beat_period_s`` 2π/|Ω − ωd| (inf at exact tuning), ``beat_deg`` the
    same in cam degrees; ``steady_amplitude`` Y; ``decay_s`` 1/(ζωn), the time the free vibration takes to
    fall to 1/e (beats show only while it lasts).
    """

    k: int
    rpm: float
    theta_deg: np.ndarray
    s: np.ndarray
    a: np.ndarray
    y: np.ndarray
    y_accel: np.ndarray
    amplitude: float
    phase_deg: float
    forced_hz: float
    free_hz: float
    beat_period_s: float
    beat_deg: float
    steady_amplitude: float
    decay_s: float = math.inf


def harmonic_beats(law: MotionLaw, follower: ElasticFollower, rpm: float, k: int, *, cycles: int | None = None,
                   samples_per_cycle: int | None = None) -> HarmonicBeats:
    """The k-th harmonic of ``law`` at ``rpm`` and the follower's response to it from rest (module docstring).

    Parameters
    ----------
    law : MotionLaw
        The law (mm, or rad of swing).
    follower : ElasticFollower
        Natural frequency and damping ratio (constant stiffness).
    rpm : float
        Cam speed, rpm.
    k : int
        The harmonic (1, 2, ...).
    cycles : int, optional
        Cycles drawn; default: one and a half beat periods, 3 to 12 cycles.
    samples_per_cycle : int, optional
        Samples per cycle; default: 65536 samples in all, at least 1024 per cycle.

    Returns
    -------
    HarmonicBeats
        Cam angle in deg; s and y in the law's unit (mm or rad), a in the law's unit per s²; frequencies Hz,
        beat period s.

    Examples
    --------
    The 17th harmonic of a law at 400 rpm against a follower of 113 Hz: forced 113.3 Hz, beats about every
    2.8 s.

    >>> import camcad
    >>> from camcad.dynamics.model import ElasticFollower
    >>> law = camcad.compose([("dwell", 100), ("rise", 64), ("return", 64), ("dwell", 132)], 0.421, "harmonic")
    >>> found = harmonic_beats(law, ElasticFollower(113.0, 0.02), 400.0, 17)
    >>> round(found.forced_hz, 3), round(found.beat_period_s, 2)
    (113.333, 2.81)
    """
    if k < 1:
        raise CamcadError(f"harmonic {k} must be 1 or more", "--harmonic", "give e.g. 17")
    spectrum = analyse(law, k)
    amplitude = float(spectrum.amplitudes[k - 1])
    phase = float(spectrum.phases[k - 1])
    omega = rpm_to_rad_s(rpm)
    big = k * (2.0 * math.pi / law.cycle) * omega
    wn, zeta = follower.omega_n, follower.damping_ratio
    wd = wn * math.sqrt(max(1.0 - zeta**2, 0.0))
    response = amplitude * (wn**2 + 2j * zeta * wn * big) / (wn**2 - big**2 + 2j * zeta * wn * big)
    steady, delta = abs(response), math.atan2(response.imag, response.real)
    period = law.cycle / omega
    gap = abs(big - wd)
    beat = 2.0 * math.pi / gap if gap > 0 else math.inf
    if cycles is None:
        cycles = int(min(MAX_CYCLES, max(3, math.ceil(1.5 * beat / period)))) if math.isfinite(beat) else 3
    if samples_per_cycle is None:
        samples_per_cycle = max(1024, (1 << 16) // cycles)
    t = np.arange(cycles * samples_per_cycle + 1) * (period / samples_per_cycle)
    argument = big * t + phase
    s = amplitude * np.sin(argument)
    ds = amplitude * big * np.cos(argument)
    a = -amplitude * big**2 * np.sin(argument)
    y_p = steady * np.sin(argument + delta)
    dy_p = steady * big * np.cos(argument + delta)
    c1 = -steady * math.sin(phase + delta)
    c2 = (zeta * wn * c1 - steady * big * math.cos(phase + delta)) / wd
    decay = np.exp(-zeta * wn * t)
    y_h = decay * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))
    dy_h = decay * ((-zeta * wn * c1 + wd * c2) * np.cos(wd * t) + (-zeta * wn * c2 - wd * c1) * np.sin(wd * t))
    y = y_p + y_h
    dy = dy_p + dy_h
    y_accel = 2.0 * zeta * wn * (ds - dy) + wn**2 * (s - y)
    return HarmonicBeats(k, float(rpm), np.degrees(omega * t), s, a, y, y_accel, amplitude, math.degrees(phase),
                         big / (2.0 * math.pi), wd / (2.0 * math.pi), beat, math.degrees(omega * beat)
                         if math.isfinite(beat) else math.inf, steady,
                         1.0 / (zeta * wn) if zeta > 0 else math.inf)


__all__ = ["HarmonicBeats", "harmonic_beats"]
