"""A law as an acceleration polyline that reads back from a DXF and closes (export of filtered laws).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from camcad import balance
from camcad.arrays import unique
from camcad.errors import CamcadError
from camcad.fourier.analysis import analyse
from camcad.fourier.filter import evaluation_grid, jumps_and_phase_ends, knots_of
from camcad.law.law import MotionLaw, Phase, PiecewiseLinearLaw

# =============================================================================================
# Polylines of the acceleration: export, lead-in segments
# =============================================================================================

def acceleration_polyline(law: MotionLaw, step_deg: float = 0.1, *, extra_knots=(),
                          phases: tuple[Phase, ...] | None = None, from_rest: bool = True) -> PiecewiseLinearLaw:
    """The law's acceleration as a polyline on a uniform step (deg) plus its knots and phase ends.

    A jump of a (left and right limits differ) becomes two vertices at one θ, as docs/INTERFACE.md draws it.
    ``from_rest``: start from v = 0, s = 0 at θ = 0, as a drawn law is read back (docs/INTERFACE.md); otherwise
    the law's own v(0), s(0). Chord error of a smooth a: step²·max|a''|/8 (step in rad).

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, a in mm/rad²).
    step_deg : float
        The step, deg.
    extra_knots : sequence of float
        More knots, rad.
    phases : tuple of Phase, optional
        Phases to give the polyline (rad); default the law's.
    from_rest : bool
        Start from v = 0, s = 0.

    Returns
    -------
    PiecewiseLinearLaw
        The polyline: knots in rad, a in mm/rad².

    Examples
    --------
    >>> import numpy as np
    >>> import camcad
    >>> law = camcad.compose([("rise", 180), ("return", 180)], 20.0, "harmonic")       # s = 10 - 10 cos(theta), mm
    >>> from camcad.fourier import acceleration_polyline
    >>> polyline = acceleration_polyline(law, 1.0, from_rest=False)
    >>> h, error = np.radians(1.0), float(polyline.kinematics(np.array([np.pi])).s[0]) - 20.0
    >>> len(polyline.x), bool(abs(error) <= np.pi ** 2 / 2 * h ** 2 * 10.0 / 8)   # chord error h² max|a''|/8
    (361, True)
    """
    if not (np.isfinite(step_deg) and 0 < step_deg <= 30):
        raise CamcadError(f"step {step_deg!r} deg must be in (0, 30]", "polyline", "give e.g. 0.1 deg")
    cycle = law.cycle
    count = max(8, math.ceil(cycle / np.radians(step_deg) - 1e-9))
    grid = np.linspace(0.0, cycle, count + 1)
    breaks = knots_of(law)
    if len(breaks) > 4 * count:
        # a densely drawn base: keep its jumps and the phase ends, sample the rest on the grid
        breaks = jumps_and_phase_ends(law)
    knots = np.concatenate((grid, breaks, np.asarray(extra_knots, dtype=float)))
    knots = unique(knots[(knots >= 0.0) & (knots <= cycle)])
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


def right_value(law: PiecewiseLinearLaw, theta: float) -> float:
    """The acceleration (mm/rad²) just right of ``theta`` (rad)."""
    return float(law.kinematics(np.array([theta])).a[0])


def left_value(law: PiecewiseLinearLaw, theta: float) -> float:
    """The acceleration (mm/rad²) just left of ``theta`` (rad); at 0 the value at 0."""
    return float(law.kinematics(np.array([max(np.nextafter(theta, -np.inf), 0.0)])).a[0])




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

    ``export_polyline`` returns it; the example is there.

    Attributes
    ----------
    law : PiecewiseLinearLaw
        The polyline (rad, mm/rad²).
    closed : bool
        Whether s and v close over the cycle.
    exact_dwells : bool
        Whether the dwells were made exact (a = 0).
    balanced_with_phases : bool
        The balance check of the polyline with the law's own phases (v = 0 at the end of every rise and
        return).
    max_change : float
        What the balance corrector changed in the sampled polyline, mm/rad².
    max_deviation : float
        max |s_polyline − (s_law − s_law(0))|, mm.
    band_amplitudes : dict
        {k: A_k, mm} of the polyline at the removed harmonics, computed exactly.
    notes : tuple of str
        What was done, in words.
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
    """A law's acceleration as a polyline that starts from rest at s = 0, as a drawn law is read back, made to close.

    The polyline is ``acceleration_polyline``'s; it is made to close with ``camcad.correct`` (min-change).
    Default: only the two closure conditions of the whole cycle are imposed, v(T) = 0 and s(T) = 0
    (a filtered law's v(0) is not exactly 0, so starting it from rest leaves a drift), with the least
    change of the form δa = c0 + c1 cos(mω0θ) + c2 sin(mω0θ): the conditions are exact linear
    functionals of the ordinates (``camcad.balance.functional_rows``), and this change touches no harmonic
    but 0 and m, so the filtered spectrum is kept. It moves s by about |v(0)|/(mω0) and a by about
    |v(0)|·mω0: m is the lowest harmonic, outside and below the removed ones, that keeps the first
    within ``drift_tol``.
    ``exact_dwells``: ``camcad.correct`` (min-change) imposes the law's phases instead — a = 0 on the
    dwells and v = 0 at the end of every rise and return — as ``camcad check`` expects of a drawn law
    with its phases; for a filtered law this brings part of the removed harmonics back, which
    ``band_amplitudes`` measures.

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, s in mm).
    step_deg : float
        The polyline's step, deg.
    tol : float, optional
        The balance tolerance, a fraction of the rise.
    removed : sequence of int
        The harmonics removed (their amplitudes in the polyline are reported).
    exact_dwells : bool
        Impose the law's phases instead of the cycle's closure alone.
    drift_tol : float, optional
        The drift allowed, mm (None: m = 1).
    where : str
        Named in errors.

    Returns
    -------
    ExportedLaw
        The closed polyline (rad, mm/rad²), what closing it changed (mm/rad²) and moved (mm).

    Examples
    --------
    >>> import numpy as np
    >>> import camcad
    >>> law = camcad.compose([("dwell", 70), ("rise", 100), ("dwell", 110), ("return", 80)], 25.0)
    >>> from camcad.fourier import export_polyline
    >>> exported = export_polyline(law, step_deg=0.5)
    >>> exported.closed, exported.max_deviation < 0.01          # mm, 0.04 % of the 25 mm lift: the chords at 0.5 deg
    (True, True)
    """
    polyline = acceleration_polyline(law, step_deg)
    kwargs: dict[str, Any] = {} if tol is None else {"tol": tol}
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
    grid = evaluation_grid(law, 1 << 14)
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




