"""A designed law as a drawing: its acceleration as a polyline that meets every end value the law states.

A drawing holds the acceleration analog as a polyline (docs/INTERFACE.md "Acceleration-law input"). Sampled from a
closed form, a polyline's integrals miss the law's positions and velocities by the chords' error (second
order in the step), so a drawing read back would fail ``camcad check``. ``drawn_polyline`` samples the law
until the chords are within ``tol`` of its largest acceleration (bisecting only where they are not; a jump
of the acceleration at a joint becomes a vertical segment, a double knot), then states at every phase's end
the law's own position and velocity (``Phase.s_end``, ``Phase.v_end``) and balances the polyline with the
least change (``camcad.balance.correct``, mode min-change): the drawing reads back with the law's phases,
ends every phase where the law does (to round-off), and differs from the closed form by the chords and that
change, both reported.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import pairwise

import numpy as np

from camcad.balance.correction import Correction, correct
from camcad.errors import CamcadError
from camcad.law.law import MotionLaw, Phase, PiecewiseLinearLaw

#: bisections of an interval at most; a piece whose chords still miss after this is written as it is
MAX_LEVELS = 14
#: first samples per piece of the law
FIRST_SAMPLES = 16


@dataclass(frozen=True)
class DrawnLaw:
    """The polyline of a designed law and what drawing it cost.

    Attributes
    ----------
    law : PiecewiseLinearLaw
        The balanced polyline (θ rad, a mm/rad²) with the designed law's phases and their stated end values.
    sampled : PiecewiseLinearLaw
        The polyline as sampled, before balancing.
    correction : Correction
        The least change that made the sampled polyline meet every stated value.
    chord_error : float
        Largest distance between the sampled polyline and the closed form's acceleration at the midpoints of
        its chords (mm/rad²).
    peak : float
        Largest |a| of the law (mm/rad²).
    """

    law: PiecewiseLinearLaw
    sampled: PiecewiseLinearLaw
    correction: Correction
    chord_error: float
    peak: float

    def to_dict(self) -> dict:
        """The drawing's figures: vertices, chord error and balancing change (mm/rad² and of the peak)."""
        change = self.correction.max_change
        return {"vertices": len(self.law.x), "chord_error_mm_per_rad2": self.chord_error,
                "balancing_change_mm_per_rad2": change,
                "deviation_of_peak": (self.chord_error + change) / self.peak if self.peak > 0 else 0.0,
                "balanced": bool(self.correction.after.balanced),
                "largest_residual": max((abs(r) for r in self.correction.after.residuals), default=0.0)}


def _breakpoints(law: MotionLaw) -> np.ndarray:
    points = {0.0, float(law.cycle)}
    points.update(float(p.start) for p in law.phases)
    points.update(float(p.end) for p in law.phases)
    inner = getattr(law, "breakpoints", None)
    if inner is not None:
        points.update(float(x) for x in np.asarray(inner()))
    kept: list[float] = []
    for p in sorted(p for p in points if 0.0 <= p <= law.cycle):
        if not kept or p - kept[-1] > 1e-12 * law.cycle:   # phase ends summed in floating point land an ulp apart
            kept.append(p)
    kept[-1] = float(law.cycle)
    return np.array(kept)


def _sample_piece(law: MotionLaw, lo: float, hi: float, tol: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Knots on [lo, hi] where the chords of a stay within ``tol`` at their midpoints (or MAX_LEVELS bisections);
    the acceleration at the ends is the piece's own (its one-sided limits)."""
    width = hi - lo
    u = np.linspace(0.0, 1.0, FIRST_SAMPLES + 1)
    inset = 1e-12 * width   # one-sided values at the ends: a jump at a joint belongs to the pieces it separates

    def accel(points: np.ndarray) -> np.ndarray:
        theta = lo + np.clip(points, 0.0, 1.0) * width
        theta = np.clip(theta, lo + inset, hi - inset)
        return law.kinematics(theta).a

    values = accel(u)
    worst = 0.0
    for _ in range(MAX_LEVELS):
        mid = (u[:-1] + u[1:]) / 2.0
        exact = accel(mid)
        chord = (values[:-1] + values[1:]) / 2.0
        miss = np.abs(exact - chord)
        bad = miss > tol
        if not bad.any():
            worst = float(miss.max()) if len(miss) else 0.0
            break
        u = np.sort(np.concatenate((u, mid[bad])))
        values = accel(u)
    else:
        mid = (u[:-1] + u[1:]) / 2.0
        worst = float(np.max(np.abs(accel(mid) - (values[:-1] + values[1:]) / 2.0)))
    return lo + u * width, values, worst


def drawn_polyline(law: MotionLaw, *, tol: float = 1e-5, balance_tol: float = 1e-9) -> DrawnLaw:
    """The law's acceleration as a polyline that meets every position and velocity the law reaches at its phases' ends.

    Parameters
    ----------
    law : MotionLaw
        A designed law (standard or from segments): θ in rad, s mm, a mm/rad².
    tol : float
        Largest chord error of the sampled acceleration, a fraction of its peak (dimensionless).
    balance_tol : float
        Closure tolerance of the balanced polyline, a fraction of the rise (dimensionless).

    Returns
    -------
    DrawnLaw
        The balanced polyline (θ rad, a mm/rad²) with the law's phases, each stating the law's position (mm)
        and velocity (mm/rad) at its end.

    Examples
    --------
    A cycloidal rise and return: the drawing ends the rise at 20 mm and at rest, to round-off:

    >>> import numpy as np
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> drawn = drawn_polyline(law)
    >>> s, v = (lambda k: (k.s, k.v))(drawn.law.kinematics(np.radians([90.0])))
    >>> round(float(s[0]), 9), abs(float(v[0])) < 1e-9, drawn.correction.after.balanced
    (20.0, True, True)
    """
    if not (np.isfinite(tol) and 0.0 < tol < 1.0):
        raise CamcadError(f"chord tolerance {tol:g} is not a fraction of the peak acceleration in (0, 1)", "--tol",
                          "give e.g. 1e-5")
    points = _breakpoints(law)
    probe = np.linspace(0.0, law.cycle, 4097)
    peak = float(np.max(np.abs(law.kinematics(np.union1d(probe, points)).a)))
    if peak == 0.0:
        raise CamcadError("the law has no acceleration anywhere: there is nothing to draw", "law",
                          "give it a motion")
    start = law.kinematics(np.array([0.0]))
    speed = float(np.max(np.abs(law.kinematics(probe).v)))
    if abs(float(start.v[0])) > 1e-12 * speed:
        raise CamcadError(f"the law moves at {np.radians(float(start.v[0])):.6g} mm/deg at 0 deg, but a drawn "
                          "acceleration law is read from rest at its start", "the drawing of the law",
                          "start the cycle at a dwell or another point of rest (the profile and the table do not "
                          "need it)")
    xs: list[np.ndarray] = []
    as_: list[np.ndarray] = []
    worst = 0.0
    for lo, hi in pairwise(points):
        x, a, miss = _sample_piece(law, float(lo), float(hi), tol * peak)
        worst = max(worst, miss)
        if xs and abs(as_[-1][-1] - a[0]) <= 1e-9 * peak:
            x, a = x[1:], a[1:]          # continuous there: one knot
        xs.append(x)
        as_.append(a)
    x = np.concatenate(xs)
    a = np.concatenate(as_)
    x[0], x[-1] = 0.0, float(law.cycle)
    ends = law.kinematics(np.array([p.end for p in law.phases]))
    speed = float(np.max(np.abs(law.kinematics(probe).v)))
    # a velocity within round-off of rest is rest (the phase ends at rest, as its law says)
    rest = 1e-12 * max(speed, peak * law.cycle)
    lift = float(np.ptp(law.kinematics(probe).s))
    # a position the law states is taken as stated; one computed within round-off of 0 is 0
    positions = [p.s_end if p.s_end is not None else (float(s) if abs(s) > 1e-12 * lift else 0.0)
                 for p, s in zip(law.phases, ends.s)]
    phases = tuple(Phase(p.kind, p.start, p.end, s, float(v) if p.kind != "dwell" and abs(v) > rest else 0.0)
                   for p, s, v in zip(law.phases, positions, ends.v))
    sampled = PiecewiseLinearLaw(x, a, float(law.cycle), phases)
    try:
        fixed = correct(sampled, "min-change", tol=balance_tol, keep_lift=False, where="the drawing of the law")
    except CamcadError as err:
        raise CamcadError(f"the law cannot be drawn as an acceleration polyline that meets its end values ({err.what})",
                          "the drawing of the law", "give its shortest segments more angle") from None
    return DrawnLaw(fixed.law, sampled, fixed, worst, peak)
