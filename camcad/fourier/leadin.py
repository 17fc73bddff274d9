"""Lead-in segments before each motion (the batten study: 14° at 0.1 of the peak acceleration), rebalanced.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from camcad import balance
from camcad.arrays import unique
from camcad.errors import CamcadError
from camcad.fourier.export import acceleration_polyline, left_value, right_value
from camcad.fourier.filter import evaluation_grid, motion_starts
from camcad.law.law import MotionLaw, Phase, PiecewiseLinearLaw


@dataclass(frozen=True)
class LeadInResult:
    """Lead-in segments before each motion, rebalanced (mm/rad², rad, mm); ``add_lead_in`` returns it.

    Attributes
    ----------
    law : PiecewiseLinearLaw
        The law with its lead-ins, balanced (rad, mm/rad²).
    unbalanced : PiecewiseLinearLaw
        The same before balancing.
    segments : tuple of (float, float, float)
        (start rad, end rad, a mm/rad²) of each plateau.
    angle : float
        The lead-in's angle, rad.
    fraction : float
        Its plateau as a fraction of the peak |a| (dimensionless).
    peak_accel : float
        The original's peak |a|, mm/rad².
    start_jump_original : tuple of float
        The acceleration jump at the start of each motion before, mm/rad².
    start_jump_new : tuple of float
        The largest jump there after (at the start of the lead-in, or at the old start), mm/rad².
    velocity_added : tuple of float
        The velocity each lead-in brings the follower to, mm/rad.
    lift_original, lift_new : float
        The lifts, mm.
    peak_accel_new : float
        The new peak |a|, mm/rad².
    max_change, rms_change : float
        What the balance corrector changed elsewhere in the law, mm/rad².
    scale : float
        The factor that brought the lift back (dimensionless).
    balanced : bool
        Whether the result balances.
    notes : tuple of str
        What was done, in words.
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
    """The batten study's remedy for the load at the start of motion: lead-in plateaus of acceleration, rebalanced.

    Before every motion that follows a dwell, a plateau of acceleration fraction × max|a| (sign of the motion's
    first acceleration) over ``angle_deg``, so the follower is brought up to the cam at low speed; then the law
    is rebalanced with ``camcad.correct`` (min-change, the plateaus and the dwells held) so it still closes. The
    dwells are set to rest (a = 0): a filtered law's residue on them would keep the follower moving after its
    last motion, and the law would not close over the cycle.

    The plateau becomes part of the motion's phase (the dwell before it is shortened). The lead-in adds travel,
    so the balanced law rises further; ``keep_lift`` scales the whole law back to the original lift (the
    balance conditions are linear in a, so the scaled law stays balanced; the plateaus scale too).

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, s in mm).
    angle_deg : float
        The lead-in's angle, deg (the batten study: 14).
    fraction : float
        The plateau over the peak |a| (a fraction; the batten study: 0.1).
    step_deg : float
        The polyline's step, deg.
    tol : float, optional
        The balance tolerance, a fraction of the rise (default the corrector's own).
    keep_lift : bool
        Scale back to the original lift.
    where : str
        Named in errors.

    Returns
    -------
    LeadInResult
        The law with its lead-ins (rad, mm/rad²), the plateaus, the jumps before and after (mm/rad²).

    Examples
    --------
    The plateau of 0.1 of the peak over 14 deg: the follower leaves it at v = 0.1 peak × 14 deg (rad), times the
    scale that brings the lift back:

    >>> import numpy as np
    >>> import camcad
    >>> law = camcad.compose([("dwell", 70), ("rise", 100), ("dwell", 110), ("return", 80)], 25.0)
    >>> import math
    >>> from camcad.fourier import add_lead_in
    >>> result = add_lead_in(law)
    >>> start, end, a = result.segments[0]
    >>> round(math.degrees(start), 6), round(math.degrees(end), 6), result.balanced
    (56.0, 70.0, True)
    >>> round(result.velocity_added[0] / (0.1 * result.peak_accel * math.radians(14.0) * result.scale), 9)
    1.0
    >>> round(result.lift_new, 9)                               # scaled back to the 25 mm lift
    25.0
    """
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
        a_left = left_value(base, lo)
        a_right = right_value(base, start)
        jumps_before.append(abs(a_right - left_value(base, start)))
        outside = (xs < lo) | (xs > start)
        inside_grid = unique(xs[(xs > lo) & (xs < start)])
        x_new = np.concatenate((xs[outside], [lo, lo], inside_grid, [start, start]))
        a_new = np.concatenate((as_[outside], [a_left, level], np.full(len(inside_grid), level), [level, a_right]))
        order = np.argsort(x_new, kind="stable")
        xs, as_ = x_new[order], a_new[order]
        segments.append((lo, start, level))
        jumps_after.append(max(abs(level - a_left), abs(a_right - level)))
        velocities.append(level * angle)
    # the dwells at rest: a filtered law's residue on them would leave the follower moving after its last
    # motion (v(T) != 0, a law that does not close), so a = 0 there, held
    held = np.zeros(len(xs), dtype=bool)
    for phase in new_phases:
        if phase.kind == "dwell":
            inside = (xs > phase.start) & (xs < phase.end)
            edges = np.flatnonzero((xs == phase.start) | (xs == phase.end))
            as_[inside] = 0.0
            held |= inside
            for index in edges.tolist():   # the dwell's side of a boundary vertex (of a jump, next to the dwell)
                neighbour = index + 1 if xs[index] == phase.start else index - 1
                if 0 <= neighbour < len(xs) and phase.start <= xs[neighbour] <= phase.end:
                    as_[index] = 0.0
                    held[index] = True
    unbalanced = PiecewiseLinearLaw(xs, as_, law.cycle, tuple(new_phases))
    for lo, hi, level in segments:
        held |= (xs >= lo) & (xs <= hi) & (as_ == level)
    kwargs: dict[str, Any] = {} if tol is None else {"tol": tol}
    corrected = balance.correct(unbalanced, "min-change", fixed=held, where=where, **kwargs)
    result = corrected.law
    grid = evaluation_grid(result, 1 << 14)
    lift_before = float(np.ptp(law.kinematics(evaluation_grid(law, 1 << 14)).s))
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



