"""The area-balance check: areas, closures and the verdict, exact; and the source's trapezoid check.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from camcad.arrays import unique
from camcad.balance.conditions import (
    DEFAULT_STEP_DEG,
    DEFAULT_TOL,
    Condition,
    conditions,
    functional_rows,
    functional_values,
    targets,
    valid_step,
    valid_tol,
)
from camcad.law.law import PiecewiseLinearLaw, integrate_trapezoid
from camcad.law.phases import phases_integrals
from camcad.law.source import rise_displacement

# ---------------------------------------------------------------------------------------------
# Check
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class BalanceReport:
    """The area balance of a law (docs/INTERFACE.md ``check`` keys); areas in mm/rad (∫ a dθ, θ in rad).

    Attributes
    ----------
    areas : dict
        ``rise_accel``, ``rise_decel``, ``return_accel``, ``return_decel``: ∫ a dθ over each part (mm/rad).
    velocity_closure : dict
        ``rise``, ``return``: the velocity at the end of each motion minus its stated value (rest unless the
        phase states a velocity), the largest of each kind (mm/rad; 0 when balanced).
    displacement_closure : float
        s at the end of the cycle minus s at its start (mm; 0 when rise = −return).
    rise, return_ : float
        Displacement over the rises and over the returns (mm).
    balanced : bool
        Every closure within ``tolerance_abs``.
    tolerance : float
        The tolerance as a fraction of the rise (dimensionless).
    tolerance_abs : float
        The tolerance in mm (and mm/rad for velocities): tolerance × rise.
    phases : tuple of dict
        One row per phase: kind, from/to (deg), positive and negative area (mm/rad), v at end (mm/rad),
        displacement (mm).
    residuals : tuple of float
        Each balance condition's residual (mm/rad or mm), in the order of ``condition_names``.
    condition_names : tuple of str
        The conditions, e.g. "velocity at the end of the rise (150 deg)".
    basis : dict or None
        The rule the verdict came from when it is not the balance conditions: a law camcad wrote with
        the "closure" rule (``check_recorded``): its figures, limits and who wrote it.
    """

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
    basis: dict | None = None

    def to_dict(self) -> dict:
        out = {"areas": self.areas, "velocity_closure": self.velocity_closure,
               "displacement_closure": self.displacement_closure, "rise": self.rise,
               "return": self.return_, "balanced": self.balanced, "tolerance": self.tolerance,
               "tolerance_abs": self.tolerance_abs, "phases": list(self.phases),
               "conditions": [{"name": n, "residual": r}
                              for n, r in zip(self.condition_names, self.residuals)]}
        if self.basis is not None:
            out["basis"] = self.basis
        return out


def check(law: PiecewiseLinearLaw, tol: float = DEFAULT_TOL) -> BalanceReport:
    """Areas, closures and verdict of a drawn law: balanced when every closure is within tol × rise.

    Exact: v and s are the piecewise-quadratic and -cubic integrals of the drawn polyline (Dupliak & Kotsiyba 2018,
    eqs. 1–3: the velocity back to zero at the end of every rise and return, rise = −return).

    Parameters
    ----------
    law : PiecewiseLinearLaw
        The law: θ in rad, a in mm/rad² (or rad/rad² for a swing), with its phases.
    tol : float
        Closure tolerance, a fraction of the rise (dimensionless; 1e-5 by default).

    Returns
    -------
    BalanceReport
        Areas (mm/rad), velocity closures (mm/rad), displacement closure (mm), rise and return (mm),
        the verdict and each condition's residual.

    Examples
    --------
    Triangular lobes of base 90° (a table of θ in deg and a), the return's last lobe drawn 20 % high.
    Scaled to a 10 mm rise (k = 80/π² mm/rad² per unit), the return's decelerating area is 0.2·(π/4)·k
    too large, so the velocity at the end of the return is 4/π mm/rad:

    >>> import math, tempfile, pathlib
    >>> import camcad
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> rows = [(0, 0), (45, 1), (90, 0), (135, -1), (180, 0), (225, -1), (270, 0), (315, 1.2), (360, 0)]
    >>> _ = (folder / "law.csv").write_text("".join(f"{t},{a}\\n" for t, a in rows))
    >>> loaded = camcad.load_law(folder / "law.csv", lift=10.0)
    >>> report = camcad.check(loaded.law)
    >>> report.balanced, round(report.rise, 9), round(report.return_, 9)
    (False, 10.0, -9.0)
    >>> round(report.velocity_closure["return"] - 4 / math.pi, 12)
    0.0
    """
    tol = valid_tol(tol)
    x, a = law.x, law.a
    areas = {"rise_accel": 0.0, "rise_decel": 0.0, "return_accel": 0.0, "return_decel": 0.0}
    closure = {"rise": 0.0, "return": 0.0}
    moved = {"rise": 0.0, "return": 0.0}
    phase_rows = []
    integrals = phases_integrals(x, a, [(phase.start, phase.end) for phase in law.phases])
    ends = law.kinematics(np.array([t for phase in law.phases for t in (phase.start, phase.end)]))
    for index, phase in enumerate(law.phases):
        positive, negative = integrals[index]
        s_start, s_end, v_end = ends.s[2 * index], ends.s[2 * index + 1], ends.v[2 * index + 1]
        row = {**phase.as_deg(), "area_positive": positive, "area_negative": negative,
               "v_end": float(v_end), "displacement": float(s_end - s_start)}
        phase_rows.append(row)
        if phase.kind == "rise":
            areas["rise_accel"] += positive
            areas["rise_decel"] += negative
        elif phase.kind == "return":
            areas["return_accel"] += negative
            areas["return_decel"] += positive
        if phase.states_end:
            row["v_stated"] = float(phase.v_end)
            if phase.s_end is not None:
                row["s_end"] = float(s_end)
                row["s_stated"] = float(phase.s_end)
        if phase.kind in closure:
            moved[phase.kind] += row["displacement"]
            # the velocity closure is the end velocity's departure from its stated value (rest by default)
            off = row["v_end"] - phase.v_end
            if abs(off) >= abs(closure[phase.kind]):
                closure[phase.kind] = off
    conds = conditions(law)
    residuals = functional_values(x, a, conds) - targets(conds)
    scale = lift_scale(law)
    limit = tol * scale
    return BalanceReport(areas=areas, velocity_closure=closure,
                         displacement_closure=float(residuals[-1]), rise=moved["rise"],
                         return_=moved["return"], balanced=bool(np.all(np.abs(residuals) <= limit)),
                         tolerance=tol, tolerance_abs=limit, phases=tuple(phase_rows),
                         residuals=tuple(float(r) for r in residuals),
                         condition_names=tuple(c.name for c in conds))


#: uniform samples of the cycle on which the "closure" rule looks for the largest dwell deviation (plus every
#: knot and phase end from both sides): the grid ``camcad spectrum`` judges a written law on
RECORDED_SAMPLES = 1 << 15


def check_recorded(law: PiecewiseLinearLaw, record) -> BalanceReport:
    """The verdict on a law camcad wrote, by the rule it recorded (``camcad.io.law_record``).

    "balance": ``check`` with the recorded tolerance. "closure" (a filtered law, whose dwells keep the
    filter's small residue): s and v close over the cycle within ``record.tol`` × ``record.lift``, and on
    each dwell |s − level| ≤ ``record.dwell_tol`` (the level recorded for it) — the rule and the sampling
    ``camcad spectrum --filter`` judged the written law by. The balance conditions are still computed and
    reported as figures.

    Parameters
    ----------
    law : PiecewiseLinearLaw
        The law as read back, with the recorded phases.
    record : camcad.io.law_record.LawRecord

    Returns
    -------
    BalanceReport
        ``basis`` holds the rule's figures and limits; ``balanced`` is its verdict.
    """
    report = check(law, record.tol)
    if record.basis != "closure":
        return replace(report, basis={"rule": "balance", "written_by": record.writer, "tolerance": record.tol})
    cycle = law.cycle
    points = [np.arange(RECORDED_SAMPLES + 1) * (cycle / RECORDED_SAMPLES), np.asarray(law.x, dtype=float),
              np.array([p.start for p in law.phases] + [p.end for p in law.phases])]
    knots = np.concatenate(points)
    knots = knots[(knots >= 0.0) & (knots <= cycle)]
    grid = unique(np.concatenate((knots, np.nextafter(knots, -np.inf).clip(0.0))))
    kin = law.kinematics(grid)
    s = kin.s - law.kinematics(np.zeros(1)).s[0]
    ends = law.kinematics(np.array([0.0, cycle]))
    closure_s, closure_v = float(ends.s[1] - ends.s[0]), float(ends.v[1] - ends.v[0])
    lift = record.lift if record.lift is not None else lift_scale(law)
    limit = record.tol * lift
    dwells = [p for p in law.phases if p.kind == "dwell"]
    deviation, at = 0.0, None
    if dwells and len(record.dwell_levels) == len(dwells):
        for phase, level in zip(dwells, record.dwell_levels):
            on = (grid >= phase.start) & (grid <= phase.end)
            if on.any():
                local = np.abs(s[on] - level)
                k = int(np.argmax(local))
                if local[k] > deviation:
                    deviation, at = float(local[k]), float(np.degrees(grid[on][k]))
    dwell_tol = record.dwell_tol
    dwell_ok = dwell_tol is None or deviation <= dwell_tol
    balanced = abs(closure_s) <= limit and abs(closure_v) <= limit and dwell_ok
    basis = {"rule": "closure", "written_by": record.writer, "closure_s": closure_s, "closure_v": closure_v,
             "closure_limit": limit, "tolerance": record.tol, "lift": lift, "dwell_deviation": deviation,
             "dwell_deviation_at_deg": at, "dwell_tol": dwell_tol, "balanced": bool(balanced)}
    return replace(report, balanced=bool(balanced), basis=basis)


def trapezoid_residuals(law: PiecewiseLinearLaw, step_deg: float = DEFAULT_STEP_DEG,
                        conds: tuple[Condition, ...] | None = None) -> np.ndarray:
    """The conditions' residuals by the source's method: resample a, integrate twice by the trapezoidal rule.

    a is resampled with ``step_deg`` and integrated twice with the trapezoidal rule (``integrate_trapezoid``); v
    and s are read at each condition's angle (linear between grid points), minus each condition's target. Its
    error against ``camcad.check`` (exact) is O(step²).

    Parameters
    ----------
    law : PiecewiseLinearLaw
        The law (θ in rad, a in mm/rad²) with its phases.
    step_deg : float
        Resampling step (deg).
    conds : tuple of Condition, optional
        Default: the balance conditions of ``law``.

    Returns
    -------
    ndarray
        One residual per condition (mm/rad for velocities, mm for displacements).

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.law.law import PiecewiseLinearLaw
    >>> from camcad.law.phases import detect_phases
    >>> x = np.radians([0.0, 45, 90, 135, 180, 225, 270, 315, 360])
    >>> a = np.array([0.0, 1, 0, -1, 0, -1, 0, 1.2, 0])          # the return's last lobe 20 % high, mm/rad²
    >>> law = PiecewiseLinearLaw(x, a, 2 * np.pi, detect_phases(x, a, 2 * np.pi))
    >>> from camcad.balance import trapezoid_residuals
    >>> [round(float(r), 9) for r in trapezoid_residuals(law, 0.5)]    # v at the ends of rise and return, s(2 pi)
    [0.0, 0.157079633, 0.123370055]
    >>> round(0.2 * np.pi / 4, 9), round(0.2 * np.pi / 4 * np.pi / 4, 9)   # the extra lobe's area, its moment
    (0.157079633, 0.123370055)
    """
    valid_step(step_deg, law.cycle)
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
    """The source's check, by the trapezoid rule at ``step_deg``, beside the exact one.

    Dupliak & Kotsiyba (2018) resample the drawn law at a step and integrate twice with the trapezoidal rule;
    ``camcad check --trapezoid`` reports that check with how far each residual is from the exact value.

    Parameters
    ----------
    law : PiecewiseLinearLaw
        The law (θ in rad, a in mm/rad²) with its phases.
    tol : float
        Closure tolerance, a fraction of the rise (dimensionless).
    step_deg : float
        The resampling step, deg.

    Returns
    -------
    dict
        ``step_deg`` (deg), ``residuals`` (mm/rad for velocities, mm for the displacement), ``balanced`` (the
        verdict at ``tol``) and ``error_vs_exact`` (each residual minus the exact one, same units).

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.law.law import PiecewiseLinearLaw
    >>> from camcad.law.phases import detect_phases
    >>> x = np.radians([0.0, 45, 90, 135, 180, 225, 270, 315, 360])
    >>> a = np.array([0.0, 1, 0, -1, 0, -1, 0, 1.2, 0])          # the return's last lobe 20 % high, mm/rad²
    >>> law = PiecewiseLinearLaw(x, a, 2 * np.pi, detect_phases(x, a, 2 * np.pi))
    >>> from camcad.balance import check_by_trapezoid
    >>> report = check_by_trapezoid(law, step_deg=0.5)
    >>> report["balanced"], max(abs(e) for e in report["error_vs_exact"]) < 1e-12   # the grid holds every knot
    (False, True)
    """
    conds = conditions(law)
    approximate = trapezoid_residuals(law, step_deg, conds)
    exact = functional_rows(law.x, conds) @ law.a - targets(conds)
    limit = tol * lift_scale(law)
    return {"step_deg": step_deg, "residuals": [float(r) for r in approximate],
            "balanced": bool(np.all(np.abs(approximate) <= limit)),
            "error_vs_exact": [float(e) for e in approximate - exact]}


def lift_scale(law: PiecewiseLinearLaw) -> float:
    """The rise displacement (mm), the yardstick of every closure; the range of s if there is no rise or the rise
    is round-off (below 1e-9 of max |a|·T²: a rise with no return, corrected to end where it began, is judged
    against the range of its motion, not against a net rise of 1e-14 mm), and never below that round-off."""
    rise = rise_displacement(law)
    roundoff = 1e-9 * float(np.max(np.abs(law.a), initial=0.0)) * float(law.cycle) ** 2
    if rise > roundoff:
        return rise
    theta = np.linspace(0, law.cycle, 2049)
    return max(float(np.ptp(law.kinematics(theta).s)), roundoff, 1e-300)




