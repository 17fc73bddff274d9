"""The source's own correction loop: resample, trapezoid integration, trial steps per condition.
"""

from __future__ import annotations

import numpy as np

from camcad.balance.checking import lift_scale, trapezoid_residuals
from camcad.balance.conditions import Condition, valid_step
from camcad.errors import CamcadError
from camcad.law.phases import sign_runs

#: grid points the loop may integrate in all (integrations × points per integration): a few seconds
WORK_BUDGET = 20_000_000


def iterate_moves(law, mode, conds, basis, touched, tol, step_deg, max_iterations, where):
    """The source's loop: trapezoid integration at step_deg, trial steps on one knob per condition.

    Knob of the velocity condition of a phase: the movable points of that phase's closing part
    (its last lobe), scaled — "raise the maxima and lower the minima, or the reverse". Knob of
    the displacement condition: every movable point of the last return, scaled. Knob of a lift
    condition (the rise kept): every movable point of that rise, scaled. Each knob is
    searched with expanding trial steps until the residual changes sign, then by halving, and the
    conditions are swept in turn until all agree within the tolerance.
    """
    limit = tol * lift_scale(law)
    valid_step(step_deg, law.cycle)
    points = law.cycle / np.radians(step_deg) + len(law.x)
    max_iterations = int(min(max_iterations, max(100, WORK_BUDGET // points)))
    moved = np.zeros(len(law.x), dtype=bool)
    moved[touched] = True
    if mode in ("min-change", "keypoints", "segment"):
        allowed = moved
    else:
        allowed = np.asarray(abs(basis).sum(axis=1)).ravel() > 0
    knobs = [_knob(law, cond, allowed, where, mode) for cond in conds]
    a = law.a.copy()

    def residuals(values: np.ndarray) -> np.ndarray:
        return trapezoid_residuals(law.with_ordinates(values), step_deg, conds)

    evaluations = 0
    for _sweep in range(200):
        r = residuals(a)
        evaluations += 1
        if np.all(np.abs(r) <= limit):
            return law.with_ordinates(a), evaluations
        for i, knob in enumerate(knobs):
            def f(t: float, i=i, knob=knob, a=a) -> float:
                return residuals(a * (1.0 + t * knob))[i]
            r0 = f(0.0)
            evaluations += 1
            if abs(r0) <= limit / 4:
                continue
            t_lo, r_lo = 0.0, r0
            trial = 0.01
            r_try = f(trial)
            evaluations += 1
            if np.sign(r_try) == np.sign(r0):
                # no crossing within the first trial step: go the way the residual shrinks, doubling
                if abs(r_try) >= abs(r0):
                    trial = -trial
                    r_try = f(trial)
                    evaluations += 1
                while np.sign(r_try) == np.sign(r_lo) and evaluations < max_iterations:
                    t_lo, r_lo = trial, r_try
                    trial *= 2.0
                    if abs(trial) > 1e6:
                        raise CamcadError(f"the iterative loop cannot balance the {conds[i].name} with mode {mode}",
                                          where, "use --method exact")
                    r_try = f(trial)
                    evaluations += 1
            t_hi = trial
            mid = t_lo
            while evaluations < max_iterations:
                mid = 0.5 * (t_lo + t_hi)
                r_mid = f(mid)
                evaluations += 1
                if abs(r_mid) <= limit / 4 or abs(t_hi - t_lo) < 1e-15:
                    break
                if np.sign(r_mid) == np.sign(r_lo):
                    t_lo, r_lo = mid, r_mid
                else:
                    t_hi = mid
            a = a * (1.0 + mid * knob)
        if evaluations >= max_iterations:
            break
    raise CamcadError(f"the iterative loop did not converge in {evaluations} integrations", where,
                      "use --method exact, or a larger --tol")


def _knob(law, cond: Condition, allowed: np.ndarray, where: str, mode: str) -> np.ndarray:
    x = law.x
    if cond.quantity == "v":
        phase = law.phases[cond.phase_index]
        runs = [r for r in sign_runs(x, law.a) if r[0] != 0 and r[2] > phase.start and r[1] < phase.end]
        closing_start = max(runs[-1][1], phase.start) if runs else phase.start
        mask = allowed & (x >= closing_start) & (x <= phase.end)
        if not mask.any():
            mask = allowed & (x >= phase.start) & (x <= phase.end)
    elif cond.quantity == "rise":  # the whole rise scales: its closing velocity stays zero
        phase = law.phases[cond.phase_index]
        mask = allowed & (x >= phase.start) & (x <= phase.end)
    else:
        returns = [p for p in law.phases if p.kind == "return"]
        phase = returns[-1] if returns else law.phases[-1]
        mask = allowed & (x >= phase.start) & (x <= phase.end)
    if not mask.any():
        raise CamcadError(f"mode {mode} finds no point to move for the {cond.name}", where,
                          "use --mode min-change")
    return mask.astype(float)




