"""The phase modes of the correction (Dupliak & Kotsiyba 2018 options f and g): stretch phase parts in angle.
"""

from __future__ import annotations

import numpy as np

from camcad.balance.checking import check
from camcad.balance.conditions import DEFAULT_STEP_DEG, conditions, functional_rows, lift_conditions, targets
from camcad.balance.modes import vertex_mode
from camcad.errors import CamcadError
from camcad.law.law import Phase, PiecewiseLinearLaw
from camcad.law.phases import phase_integrals, sign_runs

# --- phase modes ----------------------------------------------------------------------------------

def phase_mode(law, mode, max_stretch, hold, tol, where, notes, lift_targets=None):
    """Stretch phase parts in angle (closed form), the next dwell taking up the change.

    The ordinates stay, so stretching a part by f scales its area (velocity change) by f and its
    displacement by f². Each motion's decelerating part is stretched until the motion ends at rest;
    with ``lift_targets`` (mm, one per rise) each rise is then stretched as a whole by
    g = √(h / s_rise), which keeps its end velocity zero and brings its displacement to h; the last
    return is stretched the same way until the follower is back at its start. A part whose end lies
    inside a segment changes that segment's shape a little when stretched, so each stretch is
    repeated until it is exact (a few times at most); phase-keypoints stretches once, within its limit.
    """
    limit = max_stretch if mode == "phase-keypoints" else None
    repeats = 1 if limit is not None else 30
    current = PiecewiseLinearLaw(law.x.copy(), law.a, law.cycle, tuple(law.phases))
    motion = [i for i, p in enumerate(law.phases) if p.kind in ("rise", "return")]
    rise_number = 0

    def clipped(factor: float) -> float:
        return float(np.clip(factor, 1 / (1 + limit), 1 + limit)) if limit is not None else factor

    for index in motion:
        for _ in range(repeats):
            phase = current.phases[index]
            runs = [r for r in sign_runs(current.x, current.a)
                    if r[0] != 0 and r[2] > phase.start and r[1] < phase.end]
            if not runs:
                break
            closing_start = max(runs[-1][1], phase.start)
            v_start = float(current.kinematics(np.array([closing_start])).v[0])
            pos, neg = phase_integrals(current.x, current.a, closing_start, phase.end)
            closing_area = pos + neg
            if closing_area == 0 or -v_start / closing_area <= 0:
                raise CamcadError(f"mode {mode} cannot balance the {phase.kind} at {np.degrees(phase.end):.6g} deg "
                                  "by stretching its decelerating part (the areas have the wrong signs)", where,
                                  "use --mode min-change")
            factor = clipped(-v_start / closing_area)
            if abs(factor - 1.0) <= 1e-15:
                break
            current = _stretch(current, closing_start, phase.end, factor, where, mode)
        if lift_targets is not None and current.phases[index].kind == "rise":
            target = lift_targets[rise_number]
            rise_number += 1
            for _ in range(repeats):
                phase = current.phases[index]
                s = current.kinematics(np.array([phase.start, phase.end])).s
                moved = float(s[1] - s[0])
                if not (moved != 0 and target / moved > 0):
                    raise CamcadError(f"mode {mode} cannot bring the rise at {np.degrees(phase.start):.6g} deg to "
                                      f"{target:.6g} mm by stretching it (it moves {moved:.3g} mm)", where,
                                      "add --free-lift, or use --mode min-change")
                factor = clipped(float(np.sqrt(target / moved)))
                if abs(factor - 1.0) <= 1e-15:
                    break
                current = _stretch(current, phase.start, phase.end, factor, where, mode)
    returns = [i for i, p in enumerate(current.phases) if p.kind == "return"]
    if returns:
        for _ in range(repeats):
            last = current.phases[returns[-1]]
            s = current.kinematics(np.array([last.start, last.end, current.cycle])).s
            moved_back = s[1] - s[0]
            others = s[2] - moved_back
            if not moved_back < 0 < others:
                break
            # the ordinates stay, so stretching the angle by f scales v by f and s by f²
            factor = clipped(float(np.sqrt(-others / moved_back)))
            if abs(factor - 1.0) <= 1e-15:
                break
            current = _stretch(current, last.start, last.end, factor, where, mode)
    notes.append("phase angles changed: " + ", ".join(
        f"{p.kind} {np.degrees(p.start):.4g}..{np.degrees(p.end):.4g} deg" for p in current.phases))
    if mode == "phase-keypoints":
        conds = conditions(current) + (lift_conditions(current, lift_targets) if lift_targets is not None else ())
        residual = np.abs(functional_rows(current.x, conds) @ current.a - targets(conds))
        if np.any(residual > 1e-12 * check(current, tol).tolerance_abs / tol):
            # vertex order is unchanged by a stretch, so the held vertices are the same indices
            current, _ = vertex_mode(current, "keypoints", "exact", tol, DEFAULT_STEP_DEG, None,
                                      hold, 0, where, lift_targets=lift_targets)
    return current, 1


def _stretch(law: PiecewiseLinearLaw, start: float, end: float, factor: float, where: str, mode: str):
    """Stretch [start, end] by ``factor``; a dwell takes up the change.

    The dwell after ``end`` absorbs it (the part keeps its start); when the cycle has no dwell
    after it, the dwell before ``start`` does (the part keeps its end).
    """
    delta = (factor - 1.0) * (end - start)
    phases = list(law.phases)
    after = [p for p in phases if p.kind == "dwell" and p.start >= end - 1e-12]
    before = [p for p in phases if p.kind == "dwell" and p.end <= start + 1e-12]
    if after:
        dwell = after[0]
        old = [0.0, start, end, dwell.start, dwell.end, law.cycle]
        new = [0.0, start, end + delta, dwell.start + delta, dwell.end, law.cycle]
    elif before:
        dwell = before[-1]
        old = [0.0, dwell.start, dwell.end, start, end, law.cycle]
        new = [0.0, dwell.start, dwell.end - delta, start - delta, end, law.cycle]
    else:
        raise CamcadError(f"mode {mode} needs a dwell to take up the stretch of "
                          f"{np.degrees(start):.6g}..{np.degrees(end):.6g} deg", where, "use --mode min-change")
    if delta >= dwell.width:
        raise CamcadError(f"mode {mode} would need {np.degrees(delta):.4g} deg more, but the dwell at "
                          f"{np.degrees(dwell.start):.6g} deg is only {np.degrees(dwell.width):.4g} deg", where,
                          "use --mode min-change or phase-keypoints")
    old_arr, keep = np.unique(np.array(old), return_index=True)
    new_arr = np.array(new)[keep]

    def warp(t):
        return np.interp(t, old_arr, new_arr)

    x_new = warp(law.x)
    new_phases = tuple(Phase(p.kind, float(warp(p.start)), float(warp(p.end))) for p in phases
                       if warp(p.end) > warp(p.start))
    return PiecewiseLinearLaw(x_new, law.a, law.cycle, new_phases)




