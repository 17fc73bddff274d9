"""Area balance of a drawn acceleration law: the check, and every way of correcting it.

The conditions (Dupliak & Kotsiyba 2018, seed 003, eqs. 1–3; θ in rad, the law starts from rest
at s = 0): the velocity is zero at the end of every rise and every return (the accelerating and
decelerating areas of each phase balance), and the displacement comes back to its start at the
end of the cycle (rise = −return, the profile closes). With v(0) = s(0) = 0,

    v(θc) = ∫₀^θc a dθ,        s(θc) = ∫₀^θc (θc − τ) a(τ) dτ,

both *linear* in the ordinates a_i of the drawn polyline. So every condition is a row of a small
matrix C (one row per condition, one column per vertex), computed exactly from the piecewise-linear
shape functions, and a correction δ that restores balance solves C δ = −C a.

Correction modes (SPEC.md; the source's list (a)–(g)):
- ``min-change``: the δ of least ∫ δa(θ)² dθ — the smallest change of the drawn curve as a function —
  over all vertices that are off the axis, solved exactly with the polyline's mass matrix M
  (δ = −M⁻¹Cᵀ (C M⁻¹ Cᵀ)⁻¹ C a); vertices on the axis (dwells, phase boundaries) stay put.
- ``extrema``: only the local maximum and minimum points move, equal neighbours together (b).
- ``extrema-resample``: the curve is resampled with the step and each lobe is scaled as a whole so its
  extremum takes the new value, every point recomputed from it (c).
- ``keypoints``: every vertex off the axis moves, least sum of squared vertex changes (d).
- ``segment``: only the vertices in a chosen angle range move (e).
- ``phase``: the decelerating part of each phase and then the whole last return are stretched in
  angle with the ordinates kept (closed form: a stretch f scales an area by f and a displacement
  by f²); a neighbouring dwell takes up the change (f).
- ``phase-keypoints``: a phase stretch limited to ``max_stretch``, then key points for the rest (g).
- ``move``: the user's point is set where they put it and held; the mode rebalances the rest (a).
Each vertex mode can also run the source's own loop, ``method="iterate"``: resample with ``step_deg``,
integrate with the trapezoidal rule, raise or lower the points by trial steps until the areas agree
within the tolerance.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from camcad.errors import CamcadError
from camcad.law.law import PiecewiseLinearLaw, sample_piecewise_linear
from camcad.law.phases import zero_threshold
from camcad.balance.checking import BalanceReport, check
from camcad.balance.conditions import DEFAULT_MAX_STRETCH, DEFAULT_STEP_DEG, DEFAULT_TOL, METHODS, MODES, conditions
from camcad.balance.modes import _resample, _vertex_mode
from camcad.balance.phase import _phase_mode


# ---------------------------------------------------------------------------------------------
# Correction
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Correction:
    """A corrected law and what it cost. Changes are in the law's units (mm/rad²)."""

    law: PiecewiseLinearLaw
    mode: str
    method: str
    before: BalanceReport
    after: BalanceReport
    max_change: float
    rms_change: float
    iterations: int
    resampled: bool = False
    notes: tuple[str, ...] = field(default_factory=tuple)


def correct(law: PiecewiseLinearLaw, mode: str = "min-change", *, tol: float = DEFAULT_TOL,
            method: str = "exact", step_deg: float = DEFAULT_STEP_DEG, segment_deg: tuple[float, float] | None = None,
            move: tuple[float, float] | None = None, fixed: np.ndarray | None = None,
            max_stretch: float = DEFAULT_MAX_STRETCH, max_iterations: int = 20000,
            where: str = "") -> Correction:
    """Balance ``law`` with the chosen mode (see the module docstring).

    Parameters
    ----------
    mode : one of MODES.
    tol : closure tolerance, fraction of the rise (also the stopping rule of ``method="iterate"``).
    method : "exact" (solve the linear conditions) or "iterate" (the source's trial-step loop with
        trapezoidal integration at ``step_deg``).
    segment_deg : (A, B) in deg for mode "segment".
    move : (θ_deg, a) — set the vertex nearest θ to a (law units, mm/rad²) and hold it.
    fixed : boolean mask of vertices that must not move (in addition to those on the axis).
    max_stretch : largest relative phase stretch of "phase-keypoints".
    """
    if mode not in MODES:
        raise CamcadError(f"unknown mode {mode!r}", where or "--mode", f"use one of {', '.join(MODES)}")
    if method not in METHODS:
        raise CamcadError(f"unknown method {method!r}", where or "--method", "use exact or iterate")
    if mode == "segment" and segment_deg is None:
        raise CamcadError("mode segment needs the angle range", where or "--segment", "add --segment A:B (deg)")
    if not (np.isfinite(tol) and tol > 0):
        raise CamcadError(f"tolerance {tol!r} must be a positive number", "--tol", "give e.g. --tol 1e-5")
    before = check(law, tol)
    notes: list[str] = []
    hold = np.zeros(len(law.x), dtype=bool) if fixed is None else np.asarray(fixed, dtype=bool).copy()
    start = law
    if move is not None:
        start, index = _apply_move(law, move, where)
        hold[index] = True
        notes.append(f"vertex {index} moved to a = {move[1]:g} at {np.degrees(law.x[index]):.6g} deg and held")
    start = _zero_dwells(start, notes)
    if move is None and before.balanced and start is law:
        return Correction(law, mode, method, before, before, 0.0, 0.0, 0,
                          notes=("already balanced within the tolerance; nothing changed",))
    if mode in ("phase", "phase-keypoints"):
        if method == "iterate":
            notes.append("phase modes are solved in closed form; --method iterate does not apply")
        corrected, iterations = _phase_mode(start, mode, max_stretch, hold, tol, where, notes)
        resampled = False
    else:
        resampled = mode == "extrema-resample"
        if resampled:
            start, hold = _resample(start, step_deg, hold)
        corrected, iterations = _vertex_mode(start, mode, method, tol, step_deg, segment_deg, hold,
                                             max_iterations, where)
    if not np.any(np.abs(corrected.a) > zero_threshold(law.a)):
        # too few points may move for the conditions: the only law they can balance is a = 0
        raise CamcadError(f"mode {mode} can balance this law only by removing all its motion (every acceleration "
                          f"goes to zero): the {len(law.x)}-vertex law has too few points it may move for its "
                          f"{len(conditions(law))} balance conditions", where,
                          "draw the law with more vertices on each lobe")
    after = check(corrected, tol)
    max_change, rms_change = difference_norms(law, corrected)
    return Correction(corrected, mode, method, before, after, max_change, rms_change, iterations,
                      resampled=resampled, notes=tuple(notes))


def _apply_move(law: PiecewiseLinearLaw, move: tuple[float, float], where: str):
    theta_deg, value = move
    if not (np.isfinite(theta_deg) and np.isfinite(value)):
        raise CamcadError("--move needs finite numbers", where or "--move", "write --move ANGLE_DEG:ACCEL")
    theta = np.radians(theta_deg)
    if not 0 <= theta <= law.cycle:
        raise CamcadError(f"--move angle {theta_deg:g} deg is outside the cycle", where or "--move",
                          f"give an angle in 0..{np.degrees(law.cycle):g}")
    index = int(np.argmin(np.abs(law.x - theta)))
    a = law.a.copy()
    a[index] = value
    return law.with_ordinates(a), index


def _zero_dwells(law: PiecewiseLinearLaw, notes: list[str]) -> PiecewiseLinearLaw:
    """Vertices strictly inside a dwell must have zero acceleration; set them (only given phases can differ)."""
    a = law.a.copy()
    inside = np.zeros(len(a), dtype=bool)
    for phase in law.phases:
        if phase.kind == "dwell":
            inside |= (law.x > phase.start) & (law.x < phase.end)
    eps = zero_threshold(law.a)
    wrong = inside & (np.abs(a) > eps)
    if not wrong.any():
        return law
    a[wrong] = 0.0
    notes.append(f"{int(wrong.sum())} vertices inside dwells set to zero acceleration")
    return law.with_ordinates(a)




# ---------------------------------------------------------------------------------------------
# Measuring a change
# ---------------------------------------------------------------------------------------------

def difference_norms(first: PiecewiseLinearLaw, second: PiecewiseLinearLaw) -> tuple[float, float]:
    """(max |Δa|, RMS of Δa over the cycle) between two piecewise-linear laws, exact (mm/rad²)."""
    breaks = np.unique(np.concatenate((first.x, second.x)))
    left = breaks[:-1]
    right = breaks[1:]
    length = right - left
    keep = length > 0
    left, right, length = left[keep], right[keep], length[keep]
    d0 = _right_value(first, left) - _right_value(second, left)
    d1 = _left_values(first, right) - _left_values(second, right)
    integral = np.sum(length * (d0**2 + d0 * d1 + d1**2) / 3.0)
    max_change = float(np.max(np.abs(np.concatenate((d0, d1))))) if len(d0) else 0.0
    total = float(np.sum(length))
    return max_change, float(np.sqrt(integral / total)) if total > 0 else 0.0


def _right_value(law: PiecewiseLinearLaw, t: np.ndarray) -> np.ndarray:
    return sample_piecewise_linear(law.x, law.a, t)


def _left_values(law: PiecewiseLinearLaw, t: np.ndarray) -> np.ndarray:
    index = np.clip(np.searchsorted(law.x, t, side="left") - 1, 0, len(law.x) - 2)
    x0, x1 = law.x[index], law.x[index + 1]
    length = x1 - x0
    frac = np.divide(t - x0, length, out=np.ones_like(t), where=length > 0)
    return law.a[index] + frac * (law.a[index + 1] - law.a[index])


