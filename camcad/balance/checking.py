"""The area-balance check: areas, closures and the verdict, exact; and the source's trapezoid check.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from camcad.balance.conditions import (
    DEFAULT_STEP_DEG,
    DEFAULT_TOL,
    Condition,
    conditions,
    functional_rows,
)
from camcad.errors import CamcadError
from camcad.law.law import PiecewiseLinearLaw, integrate_trapezoid
from camcad.law.phases import phase_integrals

# ---------------------------------------------------------------------------------------------
# Check
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class BalanceReport:
    """The area balance of a law (SPEC.md ``check`` keys); areas in mm/rad (∫ a dθ, θ in rad)."""

    areas: dict
    velocity_closure: dict
    displacement_closure: float
    rise: float
    return_: float
    balanced: bool
    tolerance: float
    tolerance_abs: float
    phases: tuple[dict, ...]
    residuals: tuple[float, ...]
    condition_names: tuple[str, ...]

    def to_dict(self) -> dict:
        return {"areas": self.areas, "velocity_closure": self.velocity_closure,
                "displacement_closure": self.displacement_closure, "rise": self.rise,
                "return": self.return_, "balanced": self.balanced, "tolerance": self.tolerance,
                "tolerance_abs": self.tolerance_abs, "phases": list(self.phases),
                "conditions": [{"name": n, "residual": r}
                               for n, r in zip(self.condition_names, self.residuals)]}


def check(law: PiecewiseLinearLaw, tol: float = DEFAULT_TOL) -> BalanceReport:
    """Areas, closures and verdict. Balanced when every closure is within tol × rise (mm, mm/rad).

    Exact: v and s are the piecewise-quadratic and -cubic integrals of the drawn polyline.
    """
    x, a = law.x, law.a
    areas = {"rise_accel": 0.0, "rise_decel": 0.0, "return_accel": 0.0, "return_decel": 0.0}
    closure = {"rise": 0.0, "return": 0.0}
    moved = {"rise": 0.0, "return": 0.0}
    phase_rows = []
    for phase in law.phases:
        positive, negative = phase_integrals(x, a, phase.start, phase.end)
        kin = law.kinematics(np.array([phase.start, phase.end]))
        row = {**phase.as_deg(), "area_positive": positive, "area_negative": negative,
               "v_end": float(kin.v[1]), "displacement": float(kin.s[1] - kin.s[0])}
        phase_rows.append(row)
        if phase.kind == "rise":
            areas["rise_accel"] += positive
            areas["rise_decel"] += negative
        elif phase.kind == "return":
            areas["return_accel"] += negative
            areas["return_decel"] += positive
        if phase.kind in closure:
            moved[phase.kind] += row["displacement"]
            if abs(row["v_end"]) >= abs(closure[phase.kind]):
                closure[phase.kind] = row["v_end"]
    conds = conditions(law)
    residuals = functional_rows(x, conds) @ a
    scale = _scale(law)
    limit = tol * scale
    return BalanceReport(areas=areas, velocity_closure=closure,
                         displacement_closure=float(residuals[-1]), rise=moved["rise"],
                         return_=moved["return"], balanced=bool(np.all(np.abs(residuals) <= limit)),
                         tolerance=tol, tolerance_abs=limit, phases=tuple(phase_rows),
                         residuals=tuple(float(r) for r in residuals),
                         condition_names=tuple(c.name for c in conds))


def trapezoid_residuals(law: PiecewiseLinearLaw, step_deg: float = DEFAULT_STEP_DEG,
                        conds: tuple[Condition, ...] | None = None) -> np.ndarray:
    """The conditions' residuals by the source's method: resample a with ``step_deg``, integrate twice with
    the trapezoidal rule (``integrate_trapezoid``), read v and s at each condition's angle (linear between
    grid points), minus each condition's target. Its error against ``check`` (exact) is O(step²).

    Parameters
    ----------
    law : PiecewiseLinearLaw
    step_deg : float
        Resampling step (deg).
    conds : tuple of Condition, optional
        Default: the balance conditions of ``law``.

    Returns
    -------
    ndarray
        One residual per condition (mm/rad for velocities, mm for displacements).
    """
    conds = conditions(law) if conds is None else conds
    grid, _, v, s = integrate_trapezoid(law.x, law.a, np.radians(step_deg))
    values = []
    for cond in conds:
        value = float(np.interp(cond.theta, grid, v if cond.quantity == "v" else s))
        if cond.quantity == "rise":
            value -= float(np.interp(cond.start, grid, s))
        values.append(value - cond.target)
    return np.array(values)


def check_by_trapezoid(law: PiecewiseLinearLaw, tol: float = DEFAULT_TOL,
                       step_deg: float = DEFAULT_STEP_DEG) -> dict:
    """The source's check (trapezoid at ``step_deg``) beside the exact one: its residuals, its verdict and
    how far each residual is from the exact value (mm/rad for velocities, mm for the displacement)."""
    if not (np.isfinite(step_deg) and step_deg > 0):
        raise CamcadError(f"step {step_deg!r} deg must be positive", "--step", "give e.g. --step 0.1")
    conds = conditions(law)
    approximate = trapezoid_residuals(law, step_deg, conds)
    exact = functional_rows(law.x, conds) @ law.a
    limit = tol * _scale(law)
    return {"step_deg": step_deg, "residuals": [float(r) for r in approximate],
            "balanced": bool(np.all(np.abs(approximate) <= limit)),
            "error_vs_exact": [float(e) for e in approximate - exact]}


def _scale(law: PiecewiseLinearLaw) -> float:
    """The rise displacement (mm), the yardstick of every closure; max |s| if there is no rise."""
    from camcad.law.source import rise_displacement

    rise = rise_displacement(law)
    if rise > 0:
        return rise
    theta = np.linspace(0, law.cycle, 2049)
    return max(float(np.ptp(law.kinematics(theta).s)), 1e-300)




