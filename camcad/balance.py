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
from camcad.law.law import Phase, PiecewiseLinearLaw, integrate_trapezoid, sample_piecewise_linear, uniform_grid
from camcad.law.phases import phase_integrals, sign_runs, zero_threshold

MODES = ("min-change", "extrema", "extrema-resample", "keypoints", "segment", "phase", "phase-keypoints")
METHODS = ("exact", "iterate")
DEFAULT_TOL = 1e-5       # of the rise displacement
DEFAULT_STEP_DEG = 0.1   # the source's resampling step
DEFAULT_MAX_STRETCH = 0.05


# ---------------------------------------------------------------------------------------------
# Conditions
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Condition:
    """One balance condition: ``quantity`` ("v" or "s") must be zero at ``theta`` (rad)."""

    name: str
    quantity: str
    theta: float
    phase_index: int | None = None


def conditions(law: PiecewiseLinearLaw) -> tuple[Condition, ...]:
    """v = 0 at the end of every rise and return; s(cycle) = s(0) at the end of the cycle."""
    found = []
    for index, phase in enumerate(law.phases):
        if phase.kind in ("rise", "return"):
            found.append(Condition(f"velocity at the end of the {phase.kind} "
                                   f"({np.degrees(phase.end):.6g} deg)", "v", phase.end, index))
    found.append(Condition("displacement closure (rise = -return)", "s", law.cycle))
    return tuple(found)


def functional_rows(x: np.ndarray, conds: tuple[Condition, ...]) -> np.ndarray:
    """Matrix C: row i gives v(θ_i) or s(θ_i) as Σ_k C_ik a_k for the polyline on knots x, exactly.

    On a segment of length L starting at x_k with D = θc − x_k (for the part before θc):
        ∫ a dθ            → a_k L/2,            a_{k+1} L/2
        ∫ (θc − τ) a dτ   → a_k L(D/2 − L/6),   a_{k+1} L(D/2 − L/3)
    A segment cut by θc is treated as a shorter segment whose end value interpolates a_k, a_{k+1}.
    """
    n = len(x)
    rows = np.zeros((len(conds), n))
    lengths = np.diff(x)
    for row, cond in zip(rows, conds):
        tc = cond.theta
        full = np.flatnonzero(x[1:] <= tc)  # segments entirely before tc
        length = lengths[full]
        if cond.quantity == "v":
            np.add.at(row, full, length / 2.0)
            np.add.at(row, full + 1, length / 2.0)
        else:
            d = tc - x[full]
            np.add.at(row, full, length * (d / 2.0 - length / 6.0))
            np.add.at(row, full + 1, length * (d / 2.0 - length / 3.0))
        k = int(np.searchsorted(x, tc, side="right")) - 1
        if 0 <= k < n - 1 and x[k] < tc < x[k + 1]:
            seg = x[k + 1] - x[k]
            part = tc - x[k]
            t = part / seg
            if cond.quantity == "v":
                w_start, w_end = part / 2.0, part / 2.0
            else:
                w_start, w_end = part * (part / 2.0 - part / 6.0), part * (part / 2.0 - part / 3.0)
            row[k] += w_start + w_end * (1.0 - t)
            row[k + 1] += w_end * t
    return rows


def mass_matrix(x: np.ndarray):
    """Sparse M with ∫ (Σ δ_k φ_k)² dθ = δᵀ M δ for the hat functions φ_k of the knots x (rad)."""
    from scipy import sparse

    length = np.diff(x)
    n = len(x)
    diag = np.zeros(n)
    diag[:-1] += length / 3.0
    diag[1:] += length / 3.0
    off = length / 6.0
    return sparse.diags([off, diag, off], [-1, 0, 1], format="csc")


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
    """The balance conditions' residuals by the source's method: resample a with ``step_deg``, integrate
    twice with the trapezoidal rule (``integrate_trapezoid``), read v and s at each condition's angle
    (linear between grid points). Its error against ``check`` (exact) is O(step²); see the benchmark."""
    conds = conditions(law) if conds is None else conds
    grid, _, v, s = integrate_trapezoid(law.x, law.a, np.radians(step_deg))
    return np.array([np.interp(cond.theta, grid, v if cond.quantity == "v" else s) for cond in conds])


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


def _free_vertices(law: PiecewiseLinearLaw, hold: np.ndarray) -> np.ndarray:
    """Vertices a correction may move: off the axis, outside dwells, not held."""
    eps = zero_threshold(law.a)
    free = (np.abs(law.a) > eps) & ~hold
    for phase in law.phases:
        if phase.kind == "dwell":
            free &= ~((law.x > phase.start) & (law.x < phase.end))
    return free


def _resample(law: PiecewiseLinearLaw, step_deg: float, hold: np.ndarray):
    """The law resampled at a uniform step; jumps keep both their vertices so they stay vertical."""
    if not (np.isfinite(step_deg) and step_deg > 0):
        raise CamcadError(f"step {step_deg!r} deg must be positive", "--step", "give e.g. --step 0.1")
    grid = uniform_grid(0.0, law.cycle, np.radians(step_deg))
    jumps = law.x[:-1][np.diff(law.x) == 0]
    boundaries = np.array([p.start for p in law.phases] + [p.end for p in law.phases])
    held = law.x[hold]
    knots = np.unique(np.concatenate((grid, jumps, boundaries, held)))
    x_parts, a_parts = [], []
    for t in knots:
        at = np.flatnonzero(law.x == t)
        if len(at) > 1:  # a jump: left and right values
            x_parts.extend([t, t])
            a_parts.extend([law.a[at[0]], law.a[at[-1]]])
        else:
            x_parts.append(t)
            a_parts.append(sample_piecewise_linear(law.x, law.a, np.array([t]))[0])
    x_new = np.array(x_parts)
    new_hold = np.isin(x_new, held)
    return PiecewiseLinearLaw(x_new, np.array(a_parts), law.cycle, law.phases), new_hold


# --- vertex modes -------------------------------------------------------------------------------

def _basis(law: PiecewiseLinearLaw, mode: str, free: np.ndarray, segment_deg, where: str):
    """Columns B of allowed changes δ = B p, and whether to measure p with the mass matrix."""
    from scipy import sparse

    n = len(law.x)
    if mode in ("min-change", "keypoints"):
        idx = np.flatnonzero(free)
        return sparse.csc_matrix((np.ones(len(idx)), (idx, np.arange(len(idx)))), shape=(n, len(idx))), \
            mode == "min-change", idx
    if mode == "segment":
        lo, hi = np.radians(min(segment_deg)), np.radians(max(segment_deg))
        idx = np.flatnonzero(free & (law.x >= lo) & (law.x <= hi))
        if len(idx) == 0:
            raise CamcadError(f"the segment {segment_deg[0]:g}:{segment_deg[1]:g} deg holds no vertex off the axis",
                              where or "--segment", "widen the segment or use --mode min-change")
        return sparse.csc_matrix((np.ones(len(idx)), (idx, np.arange(len(idx)))), shape=(n, len(idx))), True, idx
    groups = extremum_groups(law.a, free) if mode == "extrema" else lobe_groups(law.a, free)
    rows, cols, vals = [], [], []
    for col, group in enumerate(groups):
        rows.extend(group)
        cols.extend([col] * len(group))
        # extrema move by a common amount; a lobe scales, so every point moves in proportion
        vals.extend([1.0] * len(group) if mode == "extrema" else list(law.a[group]))
    return sparse.csc_matrix((vals, (rows, cols)), shape=(n, len(groups))), True, \
        np.unique(np.concatenate(groups)) if groups else np.array([], dtype=int)


def lobes(a: np.ndarray, free: np.ndarray) -> list[np.ndarray]:
    """Runs of consecutive free vertices with the same sign of a."""
    result = []
    current: list[int] = []
    sign = 0
    for i in range(len(a)):
        s = int(np.sign(a[i])) if free[i] else 0
        if s != 0 and s == sign:
            current.append(i)
        else:
            if current:
                result.append(np.array(current))
            current = [i] if s != 0 else []
            sign = s
    if current:
        result.append(np.array(current))
    return result


def lobe_groups(a: np.ndarray, free: np.ndarray) -> list[np.ndarray]:
    return lobes(a, free)


def extremum_groups(a: np.ndarray, free: np.ndarray) -> list[np.ndarray]:
    """The local maxima of positive lobes and minima of negative lobes; equal neighbours form one group."""
    groups = []
    for lobe in lobes(a, free):
        values = np.abs(a[lobe])
        scale = values.max()
        # plateaus of equal values (within round-off) are one point for this purpose
        runs = []
        start = 0
        for i in range(1, len(lobe) + 1):
            if i == len(lobe) or abs(values[i] - values[start]) > 1e-9 * scale:
                runs.append((start, i))
                start = i
        for r, (r0, r1) in enumerate(runs):
            here = values[r0]
            left = values[runs[r - 1][0]] if r > 0 else -np.inf
            right = values[runs[r + 1][0]] if r + 1 < len(runs) else -np.inf
            if here >= left and here >= right:
                groups.append(lobe[r0:r1])
    return groups


def _vertex_mode(law, mode, method, tol, step_deg, segment_deg, hold, max_iterations, where):
    free = _free_vertices(law, hold)
    basis, use_mass, touched = _basis(law, mode, free, segment_deg, where)
    conds = conditions(law)
    rows = functional_rows(law.x, conds)
    if basis.shape[1] == 0:
        raise CamcadError(f"mode {mode} finds no point it may move", where,
                          "use --mode min-change")
    if method == "exact":
        delta = _least_change(law, rows, basis, use_mass, conds, mode, where)
        return law.with_ordinates(law.a + delta), 1
    return _iterate(law, mode, conds, basis, touched, tol, step_deg, max_iterations, where)


def _least_change(law, rows, basis, use_mass, conds, mode, where) -> np.ndarray:
    """δ = B p with the least pᵀGp such that C(a + δ) = 0; G = BᵀMB (function norm) or I."""
    from scipy.sparse.linalg import splu

    residual = rows @ law.a
    A = np.asarray((basis.T @ rows.T).T)  # C B, m × k
    if use_mass:
        gram = (basis.T @ mass_matrix(law.x) @ basis).tocsc()
        solve = splu(gram).solve
        g_inv_at = solve(np.ascontiguousarray(A.T))
    else:
        g_inv_at = A.T.copy()
    schur = A @ g_inv_at
    scale = _scale(law)
    p = -g_inv_at @ np.linalg.lstsq(schur, residual, rcond=1e-12)[0]
    delta = np.asarray(basis @ p).ravel()
    remaining = rows @ (law.a + delta)
    if np.any(np.abs(remaining) > 1e-8 * scale):
        _explain_unreachable(A, residual, conds, mode, where)
    return delta


def _explain_unreachable(A, residual, conds, mode, where):
    scale_rows = np.abs(A).max(axis=1)
    dead = [c.name for c, s, r in zip(conds, scale_rows, residual) if s <= 1e-12 * max(scale_rows.max(), 1e-300)
            and abs(r) > 0]
    if dead:
        what = f"mode {mode} cannot change the {dead[0]}: none of the points it may move acts on it"
    else:
        what = (f"mode {mode} has {np.linalg.matrix_rank(A)} independent ways to change the law "
                f"for {len(conds)} balance conditions")
    fix = "use --mode min-change or keypoints (they move every point off the axis)"
    if mode == "segment":
        fix = "widen --segment to cover every phase that is out of balance, or use --mode min-change"
    raise CamcadError(what, where, fix)


def _iterate(law, mode, conds, basis, touched, tol, step_deg, max_iterations, where):
    """The source's loop: trapezoid integration at step_deg, trial steps on one knob per condition.

    Knob of the velocity condition of a phase: the movable points of that phase's closing part
    (its last lobe), scaled — "raise the maxima and lower the minima, or the reverse". Knob of
    the displacement condition: every movable point of the last return, scaled. Each knob is
    searched with expanding trial steps until the residual changes sign, then by halving, and the
    conditions are swept in turn until all agree within the tolerance.
    """
    limit = tol * _scale(law)
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
            def f(t: float, i=i, knob=knob) -> float:
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
    else:
        returns = [p for p in law.phases if p.kind == "return"]
        phase = returns[-1] if returns else law.phases[-1]
        mask = allowed & (x >= phase.start) & (x <= phase.end)
    if not mask.any():
        raise CamcadError(f"mode {mode} finds no point to move for the {cond.name}", where,
                          "use --mode min-change")
    return mask.astype(float)


# --- phase modes ----------------------------------------------------------------------------------

def _phase_mode(law, mode, max_stretch, hold, tol, where, notes):
    """Stretch phase parts in angle (closed form), the next dwell taking up the change."""
    x = law.x.copy()
    phases = list(law.phases)
    limit = max_stretch if mode == "phase-keypoints" else None
    current = PiecewiseLinearLaw(x, law.a, law.cycle, tuple(phases))
    motion = [i for i, p in enumerate(phases) if p.kind in ("rise", "return")]
    for index in motion:
        phase = current.phases[index]
        runs = [r for r in sign_runs(current.x, current.a) if r[0] != 0 and r[2] > phase.start and r[1] < phase.end]
        if not runs:
            continue
        closing_start = max(runs[-1][1], phase.start)
        v_start = float(current.kinematics(np.array([closing_start])).v[0])
        pos, neg = phase_integrals(current.x, current.a, closing_start, phase.end)
        closing_area = pos + neg
        if closing_area == 0 or -v_start / closing_area <= 0:
            raise CamcadError(f"mode {mode} cannot balance the {phase.kind} at {np.degrees(phase.end):.6g} deg by "
                              "stretching its decelerating part (the areas have the wrong signs)", where,
                              "use --mode min-change")
        factor = -v_start / closing_area
        if limit is not None:
            factor = float(np.clip(factor, 1 / (1 + limit), 1 + limit))
        current = _stretch(current, closing_start, phase.end, factor, where, mode)
    returns = [i for i, p in enumerate(current.phases) if p.kind == "return"]
    if returns:
        last = current.phases[returns[-1]]
        s = current.kinematics(np.array([last.start, last.end, current.cycle])).s
        moved_back = s[1] - s[0]
        others = s[2] - moved_back
        if moved_back < 0 < others:
            # the ordinates stay, so stretching the angle by f scales v by f and s by f²
            factor = float(np.sqrt(-others / moved_back))
            if limit is not None:
                factor = float(np.clip(factor, 1 / (1 + limit), 1 + limit))
            current = _stretch(current, last.start, last.end, factor, where, mode)
    notes.append("phase angles changed: " + ", ".join(
        f"{p.kind} {np.degrees(p.start):.4g}..{np.degrees(p.end):.4g} deg" for p in current.phases))
    if mode == "phase-keypoints":
        shifted_hold = hold  # vertex order is unchanged by a stretch
        if not check(current, tol).balanced:
            current, _ = _vertex_mode(current, "keypoints", "exact", tol, DEFAULT_STEP_DEG, None,
                                      shifted_hold, 0, where)
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
