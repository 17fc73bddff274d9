"""Harmonic-database synthesis of a law of a given tachogram (the batten study's method, as a command).

The PhD abstract on the batten mechanism of the STB loom (Novosibirsk) analysed many laws — tables of
profiles and laws made of analytic pieces — into Fourier series, found that the amplitudes and initial phases
of the harmonics follow patterns, built a database of them, and synthesised laws of a given tachogram
(dwell–rise–return–dwell, dwell–rise–dwell, ...) from it, with the number of harmonics set by the RMS error
wanted. Here the database holds, for every rise shape, its pattern

    Φ(z) = ∫_0^1 f'(u) e^{−izu} du,

one complex function of z = kω0β for every lift, phase angle and cycle (``camcad.fourier.patterns``): a motion
of lift h starting at θ0 over β contributes (h/T) e^{−ikω0θ0} Φ(kω0β) to the k-th coefficient of the
velocity analog, so the coefficients of s are c_k = Σ (h/T) e^{−ikω0θ0} Φ(kω0β)/(ikω0), and A_k = 2|c_k|,
φ_k = arg c_k + π/2 are the amplitudes and initial phases. Patterns: exact for the cycloidal, harmonic and
polynomial shapes (``MotionPattern``); by Gauss–Legendre quadrature on the smooth pieces of every other
standard shape (Norton's SCCA family) and of a drawn law's own rises and returns (``NumericPattern``: f' is
piecewise quadratic on a drawn law's knots, each piece subdivided so z·Δu ≤ 2, 16 nodes: exact to round-off).

The RMS error of the series truncated after N harmonics is exact by Parseval,
RMS² = (1/T)∫(s − mean)² dθ − Σ_{k≤N} A_k²/2, with the variance from each shape's moments ∫f du and ∫f² du;
the least N whose RMS error meets the tolerance is taken, and the synthesised law is then measured against
the closed-form composite law (``camcad.compose``, with the drawn shapes as they are) on 2^15 points.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from camcad.errors import CamcadError
from camcad.fourier.patterns import MotionPattern, motion_pattern
from camcad.fourier.series import FourierLaw, Spectrum, series_on_grid
from camcad.law.law import MotionLaw, Phase
from camcad.law.standard import SHAPES, compose, shape_named

#: tachogram names and the phases they stand for (D dwell, R rise, T return)
TACHOGRAM_KINDS = {
    "DRTD": "dwell - rise - return - dwell (no dwell at the top)",
    "DRDTD": "dwell - rise - dwell - return - dwell",
    "RT": "rise - return, no dwell",
    "RDTD": "rise - dwell - return - dwell",
}
#: the patterns' tabulated z for the database file
DATABASE_Z = np.arange(0.0, 80.0001, 0.5)
#: Gauss–Legendre nodes per sub-interval of a numeric pattern, and the largest z·Δu of a sub-interval
_NODES = 16
_PHASE_STEP = 2.0
#: the most harmonics the synthesis takes
MAX_HARMONICS = 4096


@dataclass(frozen=True)
class DrawnShape:
    """A rise shape read off a drawn law's motion: f(u) = (s(θ0 + uβ) − s(θ0))/Δs, u ∈ [0, 1] (a return read
    the same way rises from 0 to 1). ``law`` is the drawn law (rad), ``phase`` its motion."""

    law: Any
    phase: Phase
    name: str = "drawn"

    @property
    def _delta(self) -> float:
        ends = self.law.kinematics(np.array([self.phase.start, self.phase.end])).s
        return float(ends[1] - ends[0])

    def evaluate(self, u, order: int) -> np.ndarray:
        u = np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
        beta = self.phase.width
        theta = self.phase.start + u * beta
        kin = self.law.kinematics(theta)
        delta = self._delta
        if order == 0:
            return (kin.s - float(self.law.kinematics(np.array([self.phase.start])).s[0])) / delta
        return {1: kin.v * beta, 2: kin.a * beta**2, 3: kin.j * beta**3}[order] / delta

    def breakpoints(self) -> tuple[float, ...]:
        knots = np.asarray(getattr(self.law, "x", ()), dtype=float)
        inside = knots[(knots > self.phase.start) & (knots < self.phase.end)]
        return tuple(np.unique((inside - self.phase.start) / self.phase.width).tolist())


@dataclass(frozen=True)
class NumericPattern:
    """The pattern Φ(z) of a shape without closed-form terms, by Gauss–Legendre on its smooth pieces
    (module docstring); the same interface as ``MotionPattern`` (``transform``, ``moments``, ``table``)."""

    name: str
    shape: Any
    breakpoints: tuple[float, ...]
    moments: tuple[float, float]

    def _nodes(self, z_max: float) -> tuple[np.ndarray, np.ndarray]:
        edges = np.unique(np.concatenate(([0.0, 1.0], np.asarray(self.breakpoints, dtype=float))))
        base, weights = np.polynomial.legendre.leggauss(_NODES)
        nodes, wts = [], []
        for lo, hi in itertools.pairwise(edges):
            count = max(1, math.ceil((hi - lo) * max(z_max, 1.0) / _PHASE_STEP))
            cuts = np.linspace(lo, hi, count + 1)
            half = np.diff(cuts) / 2.0
            mid = (cuts[:-1] + cuts[1:]) / 2.0
            nodes.append((mid[:, None] + half[:, None] * base[None, :]).ravel())
            wts.append((half[:, None] * weights[None, :]).ravel())
        return np.concatenate(nodes), np.concatenate(wts)

    def transform(self, z) -> np.ndarray:
        """Φ(z) = ∫_0^1 f'(u) e^{−izu} du (complex)."""
        z = np.atleast_1d(np.asarray(z, dtype=float))
        nodes, weights = self._nodes(float(np.max(np.abs(z))) if len(z) else 1.0)
        slope = np.asarray(self.shape.evaluate(nodes, 1), dtype=float) * weights
        out = np.empty(len(z), dtype=complex)
        block = max(1, (1 << 22) // max(len(nodes), 1))
        for start in range(0, len(z), block):
            part = z[start:start + block]
            out[start:start + block] = np.exp(-1j * np.multiply.outer(part, nodes)) @ slope
        return out

    def table(self, z) -> list[dict]:
        phi = self.transform(z)
        return [{"z": float(zi), "magnitude": float(abs(p)), "phase_deg": float(np.degrees(np.angle(p)))}
                for zi, p in zip(np.atleast_1d(z), phi)]


def numeric_pattern(shape, name: str | None = None) -> NumericPattern:
    """The quadrature pattern of any rise shape (its breakpoints from ``shape.breakpoints()`` when it has them)."""
    breaks = tuple(shape.breakpoints()) if hasattr(shape, "breakpoints") else ()
    edges = np.unique(np.concatenate(([0.0, 1.0], np.asarray(breaks, dtype=float))))
    base, weights = np.polynomial.legendre.leggauss(24)
    first = second = 0.0
    for lo, hi in itertools.pairwise(edges):
        half = (hi - lo) / 2.0
        u = (lo + hi) / 2.0 + half * base
        f = np.asarray(shape.evaluate(u, 0), dtype=float)
        first += float(np.sum(half * weights * f))
        second += float(np.sum(half * weights * f * f))
    return NumericPattern(str(name or getattr(shape, "name", "shape")), shape, breaks, (first, second))


def shape_pattern(shape, name: str | None = None):
    """The database pattern of a shape: exact (``MotionPattern``) when the shape has closed-form terms,
    else by quadrature (``NumericPattern``)."""
    try:
        return motion_pattern(shape, name)
    except CamcadError:
        return numeric_pattern(shape, name)


def full_database(extra: dict | None = None) -> dict:
    """The pattern of every standard shape camcad has (``camcad.law.standard.SHAPES``), and ``extra`` shapes
    (e.g. a drawn law's rise and return) by name."""
    database = {name: shape_pattern(shape, name) for name, shape in SHAPES.items()}
    for name, shape in (extra or {}).items():
        database[name] = shape_pattern(shape, name)
    return database


def drawn_shapes(law: MotionLaw, label: str = "drawn") -> dict:
    """The rise and return shapes of a drawn law (its first rise and first return), by name
    "<label>_rise" and "<label>_return"."""
    found = {}
    for kind in ("rise", "return"):
        phase = next((p for p in law.phases if p.kind == kind), None)
        if phase is not None:
            found[f"{label}_{kind}"] = DrawnShape(law, phase, f"{label}_{kind}")
    if not found:
        raise CamcadError("the drawn law has no rise or return to take a shape from", label,
                          "give a law with its phases (--phases)")
    return found


def tachogram_phases(kind: str, rise_deg: float, return_deg: float, *, start_deg: float = 0.0,
                     far_dwell_deg: float = 0.0, cycle_deg: float = 360.0) -> list[tuple[str, float]]:
    """The phases (kind, width deg) of a tachogram (``TACHOGRAM_KINDS``).

    ``start_deg`` is the dwell before the rise, ``far_dwell_deg`` the dwell at the top; the rest of the cycle
    is the dwell after the return.

    Parameters
    ----------
    kind : str
        "DRTD", "DRDTD", "RT" or "RDTD" (D dwell, R rise, T return).
    rise_deg, return_deg : float
        The rise and return angles, deg.
    start_deg : float
        The dwell before the rise, deg (tachograms that start with a dwell).
    far_dwell_deg : float
        The dwell at the top, deg (DRDTD, RDTD).
    cycle_deg : float
        The cycle, deg.

    Returns
    -------
    list of (str, float)
        (kind, width in deg) of each phase, adding up to the cycle.

    Examples
    --------
    >>> tachogram_phases("DRTD", 64.0, 64.0, start_deg=100.0)
    [('dwell', 100.0), ('rise', 64.0), ('return', 64.0), ('dwell', 132.0)]
    >>> tachogram_phases("RT", 180.0, 180.0)
    [('rise', 180.0), ('return', 180.0)]
    """
    kind = kind.upper()
    if kind not in TACHOGRAM_KINDS:
        raise CamcadError(f"unknown tachogram {kind!r}", "--tachogram",
                          "use " + "; ".join(f"{k} ({v})" for k, v in TACHOGRAM_KINDS.items()))
    start = start_deg if kind.startswith("D") else 0.0
    far = far_dwell_deg if "DT" in kind[1:] else 0.0
    if "DT" in kind[1:] and not far > 0:
        raise CamcadError(f"a {TACHOGRAM_KINDS[kind]} tachogram needs a dwell at the top", "--far-dwell",
                          "give --far-dwell DEG > 0")
    rest = cycle_deg - start - rise_deg - far - return_deg
    if min(rise_deg, return_deg) <= 0 or start < 0 or rest < -1e-9 * cycle_deg:
        raise CamcadError(f"phase angles {start:g} + {rise_deg:g} + {far:g} + {return_deg:g} deg do not fit the "
                          f"cycle of {cycle_deg:g} deg", "--tachogram", "shorten the phases")
    if kind == "RT" and rest > 1e-9 * cycle_deg:
        raise CamcadError(f"a rise-return tachogram fills the cycle: {rise_deg:g} + {return_deg:g} is not "
                          f"{cycle_deg:g} deg", "--tachogram", "use DRTD for a dwell after the return")
    items = [("dwell", start), ("rise", rise_deg), ("dwell", far), ("return", return_deg), ("dwell", max(rest, 0.0))]
    return [(k, w) for k, w in items if w > 1e-12 * cycle_deg]


def database_spectrum(phases_deg, lift: float, rise, back, harmonics: int, cycle_deg: float = 360.0) -> Spectrum:
    """The spectrum of s of the cycle (kind, width deg)… with rises of pattern ``rise`` and returns of pattern
    ``back`` (each a MotionPattern or NumericPattern) and lift ``lift``; its ``tail_mean_square`` is the exact
    remainder variance − Σ_{k≤N} A_k²/2 (module docstring)."""
    cycle = math.radians(cycle_deg)
    omega = 2.0 * math.pi / cycle
    w = np.arange(1, harmonics + 1) * omega
    velocity = np.zeros(harmonics, dtype=complex)
    level = start = integral = square = 0.0
    for kind, width_deg in phases_deg:
        beta = math.radians(width_deg)
        if kind == "dwell":
            integral += level * beta
            square += level**2 * beta
        else:
            pattern = rise if kind == "rise" else back
            h = lift if kind == "rise" else -lift
            velocity += h * np.exp(-1j * w * start) * pattern.transform(w * beta)
            m1, m2 = pattern.moments
            integral += beta * (level + h * m1)
            square += beta * (level**2 + 2 * level * h * m1 + h**2 * m2)
            level += h
        start += beta
    if abs(start - cycle) > 1e-9 * cycle or abs(level) > 1e-9 * max(abs(lift), 1.0):
        raise CamcadError("the phases do not make a closed cycle", "synthesis",
                          "give widths adding up to the cycle and as many returns as rises")
    velocity /= cycle
    coefficients = velocity / (1j * w)
    mean = integral / cycle
    variance = square / cycle - mean**2
    power = float(np.sum(2.0 * np.abs(coefficients) ** 2))
    floor = 64.0 * np.finfo(float).eps * max(variance, 1e-300)
    return Spectrum(cycle, mean, coefficients, 0.0, 1j * w * velocity, max(variance - power, floor), variance,
                    64 * np.finfo(float).eps * abs(lift), 64 * np.finfo(float).eps * abs(lift) * harmonics**2,
                    "database")


@dataclass(frozen=True)
class DatabaseSynthesis:
    """A law synthesised from the database and how accurate it is.

    ``law``: the truncated series (FourierLaw, with the tachogram's phases); ``exact``: the closed-form
    composite law; ``spectrum``: the database spectrum the count was chosen from (``harmonics_listed``
    harmonics); ``harmonics``: N; ``rms_predicted``: Parseval's RMS error after N; ``rms_measured`` and
    ``max_error``: against ``exact`` on ``samples`` points; ``reached``: ``rms_measured`` ≤ ``tol``.
    """

    law: FourierLaw
    exact: Any
    spectrum: Spectrum
    harmonics: int
    tol: float | None
    rms_predicted: float
    rms_measured: float
    max_error: float
    reached: bool
    samples: int
    phases_deg: tuple
    shapes: tuple[str, str]


def synthesise_tachogram(phases_deg, lift: float, rise, back, *, rise_shape, return_shape,
                         tol: float | None = None, harmonics: int | None = None, cycle_deg: float = 360.0,
                         samples: int = 1 << 15, names: tuple[str, str] = ("rise", "return")) -> DatabaseSynthesis:
    """The law of the tachogram ``phases_deg`` from the database (module docstring).

    Parameters
    ----------
    phases_deg : list of (str, float)
        (kind, width deg) adding up to the cycle, as many returns as rises.
    lift : float
        Lift of every rise and return (mm, or rad/deg of swing).
    rise, back : MotionPattern or NumericPattern
        The database patterns of the rises and of the returns.
    rise_shape, return_shape : RiseShape
        The same shapes, for the closed-form law the result is measured against.
    tol : float, optional
        The RMS error wanted (the lift's unit): the least N that meets it by Parseval.
    harmonics : int, optional
        N itself instead of ``tol``.
    cycle_deg : float
        The cycle (deg).
    samples : int
        Points of the independent measurement against the closed form.
    names : (str, str)
        The shapes' names, for the report.

    Returns
    -------
    DatabaseSynthesis
        The series (s in the lift's unit: mm, or rad/deg of swing), N, and its RMS and largest error in the
        same unit.

    Examples
    --------
    A dwell–rise–return–dwell of cycloidal motions, 64° each, to 1e-3 of its 0.421 lift:

    >>> import camcad
    >>> phases = tachogram_phases("DRTD", 64, 64, start_deg=100)
    >>> database = full_database()
    >>> shape = camcad.law.standard.SHAPES["cycloidal"]
    >>> found = synthesise_tachogram(phases, 0.421, database["cycloidal"], database["cycloidal"],
    ...                              rise_shape=shape, return_shape=shape, tol=0.421e-3)
    >>> found.harmonics, found.reached
    (13, True)
    """
    if (tol is None) == (harmonics is None):
        raise CamcadError("give the RMS error wanted or the number of harmonics (one of them)", "synthesis",
                          "pass --tol RMS or --harmonics N")
    if tol is not None and not (math.isfinite(tol) and tol > 0):
        raise CamcadError(f"RMS error {tol!r} must be positive", "--tol", "give e.g. 0.001 of the lift")
    if harmonics is not None and not 1 <= harmonics <= MAX_HARMONICS:
        raise CamcadError(f"{harmonics} harmonics is not in 1..{MAX_HARMONICS}", "--harmonics", "give e.g. 32")
    count = harmonics if harmonics is not None else 64
    found: int | None = None
    while True:
        spectrum = database_spectrum(phases_deg, lift, rise, back, count, cycle_deg)
        if harmonics is not None or tol is None:
            found = count
            break
        found = spectrum.least_harmonics(tol)
        if found is not None or count >= MAX_HARMONICS:
            break
        count = min(4 * count, MAX_HARMONICS)
    reached_count = found is not None
    n = found if found is not None else count
    phases = _phase_tuple(phases_deg)
    law = spectrum.truncated(n, phases)
    exact = compose(list(phases_deg), lift, rise_shape, return_shape, cycle_deg)
    cycle = exact.cycle
    theta = np.arange(samples) * (cycle / samples)
    difference = exact.kinematics(theta).s - series_on_grid(law.mean, law.coefficients, samples, 0, cycle)
    measured = float(np.sqrt(np.mean(difference**2)))
    return DatabaseSynthesis(law, exact, spectrum, n, tol, spectrum.rms_error(n), measured,
                             float(np.max(np.abs(difference))),
                             reached_count and (tol is None or measured <= tol * (1 + 1e-6)), samples,
                             tuple(phases_deg), names)


def _phase_tuple(phases_deg) -> tuple[Phase, ...]:
    out, start = [], 0.0
    for kind, width in phases_deg:
        end = start + math.radians(width)
        out.append(Phase(kind, start, end))
        start = end
    return tuple(out)


def named_shape(name: str, drawn: dict | None = None):
    """A rise shape by name: a standard one (``shape_named``, e.g. "cycloidal" or "scca:b:c:d") or a drawn
    one of ``drawn``."""
    if drawn and name in drawn:
        return drawn[name]
    try:
        return shape_named(name)
    except KeyError as err:
        known = sorted(SHAPES) + sorted(drawn or {})
        raise CamcadError(str(err.args[0]), "--shape", f"use one of {', '.join(known)}") from None


__all__ = ["DATABASE_Z", "TACHOGRAM_KINDS", "DatabaseSynthesis", "DrawnShape", "MotionPattern", "NumericPattern",
           "database_spectrum", "drawn_shapes", "full_database", "named_shape", "numeric_pattern", "shape_pattern",
           "synthesise_tachogram", "tachogram_phases"]
