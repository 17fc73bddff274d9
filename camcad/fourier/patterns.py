"""The database of harmonic patterns of the standard laws, and synthesis of tachograms from it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, cast

import numpy as np

from camcad.errors import CamcadError
from camcad.fourier.analysis import grow_until_found
from camcad.fourier.exact import EPS, TAIL_ORDERS, Piece, gauss_legendre, shape_terms, tail_mean_square
from camcad.fourier.series import FourierLaw, Spectrum, series_on_grid
from camcad.law.standard import SHAPES, compose

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
    function of z = kω0β for every lift, phase angle and cycle. ``motion_pattern`` makes one; the example is
    there.

    Attributes
    ----------
    name : str
        The shape's name.
    shape : object
        The shape (``camcad.law.standard``).
    velocity_piece : Piece
        f'(u) as elementary pieces (dimensionless).
    moments : tuple of float
        (∫f du, ∫f² du), dimensionless: the mean and the mean square (Parseval).
    edge_derivatives : ndarray
        f^{(m)}(0), f^{(m)}(1), m = 0..6 (dimensionless): the asymptotic decay of the pattern, hence the
        harmonics a requested accuracy needs.
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
    """The pattern of a rise shape (a ``camcad.law.standard.SHAPES`` member or any shape ``shape_terms`` knows).

    Parameters
    ----------
    shape : object
        The shape (a member of ``camcad.law.standard.SHAPES``).
    name : str, optional
        The pattern's name (default the shape's).

    Returns
    -------
    MotionPattern
        Φ(z) and its moments (dimensionless).

    Examples
    --------
    The cycloid: ∫f du = 1/2 and Φ(0) = ∫f' du = 1.

    >>> from camcad.law.standard import SHAPES
    >>> from camcad.fourier import motion_pattern
    >>> pattern = motion_pattern(SHAPES["cycloidal"])
    >>> round(pattern.moments[0], 12), round(float(abs(pattern.transform(0.0)[0])), 12)
    (0.5, 1.0)
    """
    terms = shape_terms(shape)
    if terms is None:
        raise CamcadError(f"no exact harmonic pattern for the shape {getattr(shape, 'name', shape)!r}",
                          "harmonic database", "use cycloidal, harmonic, poly345 or poly4567")
    piece = Piece(0.0, 1.0, *terms)
    nodes, weights = gauss_legendre(64)
    f = piece.values(nodes)
    moments = (float(np.sum(weights * f)), float(np.sum(weights * f**2)))
    edges = np.array([[piece.values(0.0, m), piece.values(1.0, m)] for m in range(TAIL_ORDERS)])
    return MotionPattern(cast(str, name or getattr(shape, "name", "shape")), shape, piece.derivative(1), moments, edges)


def pattern_database() -> dict[str, MotionPattern]:
    """The database: the normalised pattern of every standard shape that has an exact one.

    Returns
    -------
    dict
        {shape name: MotionPattern}; the patterns are dimensionless (unit lift over unit width).

    Examples
    --------
    >>> from camcad.fourier import pattern_database
    >>> sorted(pattern_database())[:3]
    ['cycloidal', 'harmonic', 'poly345']
    """
    database = {}
    for name, shape in SHAPES.items():
        if shape_terms(shape) is not None:
            database[name] = motion_pattern(shape, name)
    return database


TACHOGRAMS = ("DRRD", "DRDR")


def tachogram(kind: str, rise_deg: float, return_deg: float, *, far_dwell_deg: float = 0.0,
              start_deg: float = 0.0, cycle_deg: float = 360.0) -> list[tuple[str, float]]:
    """Phase list (kind, width_deg) of the batten study's tachogram shapes.

    "DRRD": dwell – rise – return – dwell (no dwell at the top); "DRDR": dwell – rise – dwell –
    return (– dwell), the dwell–rise–dwell shape closed by its return. ``start_deg`` is the dwell
    before the rise; the rest of the cycle is the dwell after the return.

    Parameters
    ----------
    kind : str
        "DRRD" or "DRDR".
    rise_deg, return_deg : float
        The rise's and the return's angles, deg.
    far_dwell_deg : float
        The dwell at the top (DRDR), deg.
    start_deg : float
        The dwell before the rise, deg.
    cycle_deg : float
        The cycle, deg.

    Returns
    -------
    list of (str, float)
        (kind, width deg) of each phase.

    Examples
    --------
    >>> from camcad.fourier import tachogram
    >>> tachogram("DRDR", 100.0, 80.0, far_dwell_deg=110.0, start_deg=70.0)
    [('dwell', 70.0), ('rise', 100.0), ('dwell', 110.0), ('return', 80.0)]
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
    """A law synthesised from the database, and how accurate it is (``synthesise_standard`` returns it).

    Attributes
    ----------
    law : FourierLaw
        The synthesised law (rad, mm).
    exact : MotionLaw
        The closed-form composite law it approximates.
    harmonics : int
        N, the harmonics used.
    tol : float
        The RMS error asked for, mm.
    rms_predicted : float
        The Parseval figure N was chosen by, mm.
    rms_measured : float
        The RMS of synthesised − exact by quadrature on ``samples`` points (an independent check), mm.
    max_error : float
        The largest |synthesised − exact| there, mm.
    reached : bool
        Whether the measured RMS meets ``tol``.
    samples : int
        The quadrature's points.
    spectrum : Spectrum
        The database spectrum (mm).
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
    """The spectrum of a composite standard cycle built from the database patterns (exact).

    Parameters
    ----------
    phases_deg : sequence of (str, float)
        (kind, width deg) of each phase.
    lift : float
        h, mm.
    shape : str
        The rises' shape.
    return_shape : str, optional
        The returns' shape (default ``shape``).
    harmonics : int
        N.
    cycle_deg : float
        The cycle, deg.
    database : dict, optional
        {shape: MotionPattern} (default ``pattern_database()``).

    Returns
    -------
    Spectrum
        Harmonics 1..N (mm).

    Examples
    --------
    The same spectrum as the direct analysis of the composite law:

    >>> import numpy as np
    >>> import camcad
    >>> from camcad.fourier import pattern_coefficients
    >>> phases = [("dwell", 70.0), ("rise", 100.0), ("dwell", 110.0), ("return", 80.0)]
    >>> spectrum = pattern_coefficients(phases, 25.0, harmonics=16)
    >>> direct = camcad.analyse(camcad.compose(phases, 25.0), 16)
    >>> bool(np.max(np.abs(spectrum.coefficients - direct.coefficients)) < 1e-12)
    True
    """
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
            scale = h / beta ** np.arange(TAIL_ORDERS)
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
    """A FourierLaw for a cycle of standard rises and returns, with the least harmonics that meet an RMS error.

    The cycle is (kind, width_deg)… of ``shape`` rises and ``return_shape`` returns; its RMS error against the
    closed-form law is at most ``tol``, with the least number of harmonics that the Parseval prediction from the
    database allows; the accuracy reached is then measured.

    Parameters
    ----------
    phases_deg : sequence of (str, float)
        (kind, width deg) of each phase.
    lift : float
        h, mm.
    tol : float
        The RMS error allowed, mm.
    shape : str
        The rises' shape.
    return_shape : str, optional
        The returns' shape (default ``shape``).
    cycle_deg : float
        The cycle, deg.
    max_harmonics : int
        At most this many.
    samples : int, optional
        The check's quadrature points.

    Returns
    -------
    Synthesis
        The law (rad, mm), its harmonic count, the predicted and measured RMS errors (mm).

    Examples
    --------
    >>> from camcad.fourier import synthesise_standard
    >>> synthesis = synthesise_standard([("dwell", 70), ("rise", 100), ("dwell", 110), ("return", 80)], 25.0, 1e-3)
    >>> synthesis.reached, synthesis.rms_measured <= 1e-3
    (True, True)
    """
    if not (np.isfinite(tol) and tol > 0):
        raise CamcadError(f"tolerance {tol!r} mm must be positive", "synthesis", "give e.g. 1e-3 mm")
    exact = compose(list(phases_deg), lift, shape, return_shape, cycle_deg)
    database = pattern_database()
    n, spectrum = grow_until_found(
        lambda count: pattern_coefficients(phases_deg, lift, shape, return_shape, count, cycle_deg, database),
        tol, 64, max_harmonics)
    if n is None:
        n = len(spectrum.coefficients)
    law = spectrum.truncated(n, exact.phases)
    if samples is None:
        samples = max(1 << 14, 1 << math.ceil(math.log2(64 * (n + 1))))
    theta = np.arange(samples) * (exact.cycle / samples)
    difference = exact.kinematics(theta).s - series_on_grid(law.mean, law.coefficients, samples, 0, exact.cycle)
    measured = float(np.sqrt(np.mean(difference**2)))
    return Synthesis(law, exact, n, tol, spectrum.rms_error(n), measured, float(np.max(np.abs(difference))),
                     measured <= tol, samples, spectrum)




