"""Correcting the area balance: one entry point (``correct``) for every mode, the least change solved exactly.

The balance conditions and what each mode moves are described once, in the package docstring
(``camcad.balance``). Here every mode meets the same path: the conditions as rows of C
(``balance.conditions``), the columns a mode may use (``balance.modes``, ``balance.phase``), the least
change δ solving C δ = −C a (or the source's loop, ``balance.iterate``), the user's ``--move`` edits held,
and the balance checked again, exactly, before and after.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from camcad.arrays import unique
from camcad.balance.checking import BalanceReport, check
from camcad.balance.conditions import (
    DEFAULT_MAX_STRETCH,
    DEFAULT_STEP_DEG,
    DEFAULT_TOL,
    METHODS,
    MODES,
    conditions,
    lift_conditions,
    stated_ends,
    valid_tol,
)
from camcad.balance.modes import resample_law, vertex_mode, zero_law_message
from camcad.balance.phase import phase_mode
from camcad.errors import CamcadError
from camcad.law.law import PiecewiseLinearLaw, sample_piecewise_linear
from camcad.law.phases import zero_threshold

# ---------------------------------------------------------------------------------------------
# Correction
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Move:
    """One ``--move`` edit and what became of it; angles in deg, values in the law's units (mm/rad²).

    ``status`` is "honoured" (vertex ``vertex`` was set from ``old_value`` to ``value`` and held while
    the rest was rebalanced) or "refused" (``reason`` says why; nothing was changed for it).
    ``camcad.correct`` returns them in ``Correction.moves``; its example shows one.

    Attributes
    ----------
    theta_deg : float
        The angle asked for, deg.
    value : float
        The value asked for, mm/rad².
    status : str
        "honoured" or "refused".
    reason : str
        Why it was refused ("" when honoured).
    vertex : int, optional
        The vertex moved (its index), None when refused.
    vertex_deg : float, optional
        That vertex's angle, deg.
    old_value : float, optional
        Its value before, mm/rad².
    """

    theta_deg: float
    value: float
    status: str
    reason: str = ""
    vertex: int | None = None
    vertex_deg: float | None = None
    old_value: float | None = None

    @property
    def honoured(self) -> bool:
        return self.status == "honoured"


@dataclass(frozen=True)
class Correction:
    """A corrected law and what it cost. Changes are in the law's units (mm/rad²).

    Attributes
    ----------
    law : PiecewiseLinearLaw
        The corrected law (θ rad, a mm/rad²).
    mode, method : str
        The correction mode and "exact" or "iterate".
    before, after : BalanceReport
        The balance of the law before and after.
    max_change, rms_change : float
        Largest and RMS change of a(θ), the two laws compared as functions of θ, exactly (mm/rad²).
    iterations : int
        Trapezoid integrations of the iterative loop (0 for an exact solve; no unit).
    resampled : bool
        The corrected law has other vertices than the input.
    notes : tuple of str
        What was done and why.
    changed : bool
        False when the law was already balanced and nothing was done.
    moves : tuple of Move
        Each requested edit and what became of it.
    lift_targets : tuple of float
        The rises (mm) the correction kept; empty when the lift was free.
    keep_lift : bool
        The rises were held at their drawn values.
    max_vertex_change : float
        Largest change of one vertex's ordinate (mm/rad²).
    max_shift_deg : float
        Largest shift of a vertex in angle by the phase modes (deg).
    vertices_changed : int
        How many vertices moved (no unit).
    peak : float
        max |a| of the law before (mm/rad²).
    """

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
    changed: bool = True
    moves: tuple[Move, ...] = ()
    lift_targets: tuple[float, ...] = ()
    keep_lift: bool = True
    max_vertex_change: float = 0.0
    max_shift_deg: float = 0.0
    vertices_changed: int = 0
    peak: float = 0.0


def correct(law: PiecewiseLinearLaw, mode: str = "min-change", *, tol: float = DEFAULT_TOL,
            method: str = "exact", step_deg: float = DEFAULT_STEP_DEG, segment_deg: tuple[float, float] | None = None,
            move: tuple[float, float] | None = None, moves=(), fixed: np.ndarray | None = None,
            max_stretch: float = DEFAULT_MAX_STRETCH, max_iterations: int = 2000,
            where: str = "", keep_lift: bool = True) -> Correction:
    """Balance ``law`` with the chosen mode (see the module docstring).

    Parameters
    ----------
    law : PiecewiseLinearLaw
        The law (θ in rad, a in mm/rad²) with its phases.
    mode : str
        One of MODES.
    tol : float
        Closure tolerance, fraction of the rise (also the stopping rule of ``method="iterate"``).
    method : str
        "exact" (solve the linear conditions) or "iterate" (the source's trial-step loop with
        trapezoidal integration at ``step_deg``).
    step_deg : float
        Resampling step (deg) of "iterate" and "extrema-resample".
    segment_deg : (float, float), optional
        (A, B) in deg for mode "segment".
    move : (float, float), optional
        One edit (θ in deg, a in mm/rad²); the same as ``moves=[move]``.
    moves : sequence of (float, float)
        Edits (θ_deg, a in mm/rad²): each sets the vertex nearest θ (of a jump, the one nearer the
        new value) to a and holds it; an edit that cannot be made is refused with its reason
        (``Correction.moves``) and the others still apply.
    fixed : ndarray of bool, optional
        Vertices that must not move (in addition to those on the axis); no unit.
    max_stretch : float
        Largest relative phase stretch of "phase-keypoints" (a fraction of the phase angle).
    max_iterations : int
        Integration budget of "iterate" (the samples converge in under 150; a law the loop cannot balance
        stops there, and earlier when the integrations would exceed 2·10⁷ grid points in all).
    where : str
        The input, for messages.
    keep_lift : bool
        Hold the displacement over every rise at its drawn value (default); False lets it change.

    Returns
    -------
    Correction
        The corrected law and its cost: changes in mm/rad², the balance before and after (mm, mm/rad).

    Examples
    --------
    The law of ``camcad.check``'s example (the return's last lobe 20 % high): the least change balances
    it and keeps the drawn rise of 10 mm:

    >>> import math, tempfile, pathlib
    >>> import camcad
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> rows = [(0, 0), (45, 1), (90, 0), (135, -1), (180, 0), (225, -1), (270, 0), (315, 1.2), (360, 0)]
    >>> _ = (folder / "law.csv").write_text("".join(f"{t},{a}\\n" for t, a in rows))
    >>> loaded = camcad.load_law(folder / "law.csv", lift=10.0)
    >>> fixed = camcad.correct(loaded.law)
    >>> fixed.before.balanced, fixed.after.balanced, round(fixed.after.rise, 9)
    (False, True, 10.0)
    >>> max(abs(r) for r in fixed.after.residuals) < 1e-12
    True
    """
    if mode not in MODES:
        raise CamcadError(f"unknown mode {mode!r}", where or "--mode", f"use one of {', '.join(MODES)}")
    if method not in METHODS:
        raise CamcadError(f"unknown method {method!r}", where or "--method", "use exact or iterate")
    if mode == "segment" and segment_deg is None:
        raise CamcadError("mode segment needs the angle range", where or "--segment", "add --segment A:B (deg)")
    valid_tol(tol)
    if not (math.isfinite(max_stretch) and max_stretch >= 0.0):
        raise CamcadError(f"the largest phase stretch must be a finite fraction >= 0, got {max_stretch:g}",
                          "--max-stretch", "give e.g. 0.05 (5 % of a phase angle)")
    before = check(law, tol)
    peak = float(np.max(np.abs(law.a)))
    notes: list[str] = []
    hold = np.zeros(len(law.x), dtype=bool) if fixed is None else np.asarray(fixed, dtype=bool).copy()
    requested = ([move] if move is not None else []) + list(moves)
    start, outcomes = _apply_moves(law, requested, hold)
    lift_targets = tuple(c.target for c in lift_conditions(law)) if keep_lift else ()
    start = _zero_dwells(start, notes)
    if not any(m.honoured for m in outcomes) and before.balanced and start is law:
        return Correction(law, mode, method, before, before, 0.0, 0.0, 0, notes=(
            "already balanced within the tolerance; nothing changed",), changed=False, moves=tuple(outcomes),
            lift_targets=lift_targets, keep_lift=keep_lift, peak=peak)
    if keep_lift and lift_targets and not any(p.kind == "return" for p in law.phases):
        rises = ", ".join(f"{np.degrees(p.start):.4g}..{np.degrees(p.end):.4g}" for p in law.phases
                          if p.kind == "rise")
        try:  # with too few vertices even a free lift leaves no motion: that is the first thing to say
            free, _ = vertex_mode(start, "min-change", "exact", tol, step_deg, None, hold, 0, where)
            no_motion = not np.any(np.abs(free.a[_drawn(free.x)]) > zero_threshold(law.a))
        except CamcadError:
            no_motion = False
        if no_motion:
            raise CamcadError(zero_law_message(mode, len(law.x), len(conditions(law))), where,
                              "draw each lobe with more vertices")
        raise CamcadError(f"the law has a rise ({rises} deg) but no return, so it cannot come back to its start "
                          "while keeping the rise", where,
                          "give its phases with --phases (a rise and a return), or add --free-lift")
    targets_or_none = lift_targets if keep_lift else None
    if mode in ("phase", "phase-keypoints") and stated_ends(law):
        raise CamcadError(f"mode {mode} stretches motions that end at rest; this law's phases state end positions or "
                          "velocities", where or "--mode", "use --mode min-change, keypoints or extrema")
    if mode in ("phase", "phase-keypoints"):
        if method == "iterate":
            notes.append("phase modes are solved in closed form; --method iterate does not apply")
        corrected, iterations = phase_mode(start, mode, max_stretch, hold, tol, where, notes,
                                            lift_targets=targets_or_none)
        resampled = False
    else:
        resampled = mode == "extrema-resample"
        if resampled:
            start, hold = resample_law(start, step_deg, hold)
        corrected, iterations = vertex_mode(start, mode, method, tol, step_deg, segment_deg, hold,
                                             max_iterations, where, lift_targets=targets_or_none)
    if not np.all(np.isfinite(corrected.a)) or not np.any(np.abs(corrected.a[_drawn(corrected.x)])
                                                          > zero_threshold(law.a)):
        # too few points may move for the conditions: the only law they can balance is a = 0
        raise CamcadError(zero_law_message(mode, len(law.x), len(conditions(law))), where,
                          "draw each lobe with more vertices")
    after = check(corrected, tol)
    max_change, rms_change = difference_norms(law, corrected)
    if not resampled and len(corrected.x) == len(law.x):
        vertex_change = np.abs(corrected.a - law.a)
        shift = np.abs(corrected.x - law.x)
        max_vertex = float(vertex_change.max())
        max_shift = float(np.degrees(shift.max()))
        # a vertex moved by round-off only (the solver's last bits) is not counted as changed
        count = int(np.count_nonzero((vertex_change > ROUND_OFF * peak)
                                     | (shift > ROUND_OFF * 2 * np.pi)))
    else:
        max_vertex, max_shift, count = max_change, 0.0, len(corrected.x)
    return Correction(corrected, mode, method, before, after, max_change, rms_change, iterations,
                      resampled=resampled, notes=tuple(notes), moves=tuple(outcomes), lift_targets=lift_targets,
                      keep_lift=keep_lift, max_vertex_change=max_vertex, max_shift_deg=max_shift,
                      vertices_changed=count, peak=peak)


#: a relative change at or below this is round-off, not a change a designer made (vertices_changed)
ROUND_OFF = 1e-12


def _drawn(x: np.ndarray) -> np.ndarray:
    """Vertices that shape the function: at least one of their segments has a length."""
    length = np.diff(x) > 0
    return np.concatenate(([False], length)) | np.concatenate((length, [False]))


def _apply_moves(law: PiecewiseLinearLaw, requested, hold: np.ndarray) -> tuple[PiecewiseLinearLaw, list[Move]]:
    """Set each requested vertex and hold it (``hold`` is updated); refuse what cannot be set, saying why."""
    a = law.a.copy()
    outcomes: list[Move] = []
    cycle_deg = float(np.degrees(law.cycle))
    dwells = [p for p in law.phases if p.kind == "dwell"]
    taken: dict[int, int] = {}
    for number, (theta_deg, value) in enumerate(requested, start=1):
        theta_deg, value = float(theta_deg), float(value)

        def refuse(reason: str, theta_deg=theta_deg, value=value) -> None:
            outcomes.append(Move(theta_deg, value, "refused", reason))

        if not (np.isfinite(theta_deg) and np.isfinite(value)):
            refuse("the angle and the value must be finite numbers")
            continue
        if not 0.0 <= theta_deg <= cycle_deg:
            refuse(f"{theta_deg:g} deg is outside the cycle 0..{cycle_deg:g} deg")
            continue
        theta = np.radians(theta_deg)
        nearest = int(np.argmin(np.abs(law.x - theta)))
        candidates = np.flatnonzero(law.x == law.x[nearest])
        at_deg = float(np.degrees(law.x[nearest]))
        inside = [p for p in dwells if p.start < law.x[nearest] < p.end]
        if inside:
            refuse(f"the nearest vertex ({at_deg:.6g} deg) is inside the dwell {np.degrees(inside[0].start):.6g}.."
                   f"{np.degrees(inside[0].end):.6g} deg, which stays at zero acceleration")
            continue
        usable = [int(i) for i in candidates if value == 0.0 or not _on_dwell_side(law, int(i), dwells)]
        if not usable:
            refuse(f"the vertex at {at_deg:.6g} deg is the end of a dwell, which stays at zero acceleration")
            continue
        free = [i for i in usable if i not in taken]
        if not free:
            refuse(f"the vertex at {at_deg:.6g} deg is already set by --move #{taken[usable[0]]}")
            continue
        index = min(free, key=lambda i: (abs(law.a[i] - value), i))
        outcomes.append(Move(theta_deg, value, "honoured", vertex=index, vertex_deg=at_deg,
                             old_value=float(law.a[index])))
        a[index] = value
        hold[index] = True
        taken[index] = number
    if not any(m.honoured for m in outcomes):
        return law, outcomes
    return law.with_ordinates(a), outcomes


def _on_dwell_side(law: PiecewiseLinearLaw, index: int, dwells) -> bool:
    """True when vertex ``index`` ends a segment that lies in a dwell (it must stay at zero); the far
    vertex of a jump at a dwell's edge belongs to the motion."""
    x, n = law.x[index], len(law.x)
    return any((x == p.end and index > 0 and law.x[index - 1] < x)
               or (x == p.start and index + 1 < n and law.x[index + 1] > x) for p in dwells)


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
    """(max |Δa|, RMS of Δa over the cycle) between two piecewise-linear laws, exactly.

    Parameters
    ----------
    first, second : PiecewiseLinearLaw
        The two laws (θ in rad, a in mm/rad²) over the same cycle.

    Returns
    -------
    tuple of float
        The largest difference of their accelerations and its root mean square over the cycle, mm/rad².

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.law.law import PiecewiseLinearLaw
    >>> from camcad.law.phases import detect_phases
    >>> x = np.radians([0.0, 45, 90, 135, 180, 225, 270, 315, 360])
    >>> a = np.array([0.0, 1, 0, -1, 0, -1, 0, 1.2, 0])          # the return's last lobe 20 % high, mm/rad²
    >>> law = PiecewiseLinearLaw(x, a, 2 * np.pi, detect_phases(x, a, 2 * np.pi))
    >>> from camcad.balance import difference_norms
    >>> shifted = law.with_ordinates(law.a + 0.5)
    >>> difference_norms(law, shifted)
    (0.5, 0.5)
    """
    if len(first.x) == len(second.x) and np.array_equal(first.x, second.x):
        # the same knots (and the same jumps): Δa is the polyline of the vertex differences
        d = second.a - first.a
        length = np.diff(first.x)
        d0, d1 = d[:-1], d[1:]
        integral = np.sum(length * (d0**2 + d0 * d1 + d1**2) / 3.0)
        total = float(np.sum(length))
        return float(np.max(np.abs(d), initial=0.0)), float(np.sqrt(integral / total)) if total > 0 else 0.0
    breaks = unique(np.concatenate((first.x, second.x)))
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


