"""The balance conditions of a drawn law as linear functionals of its ordinates (Dupliak & Kotsiyba 2018, eqs. 1–3).

v = 0 at the end of every rise and return, s(cycle) = s(0); each is a row of C with C a = residuals,
computed exactly from the piecewise-linear shape functions; M is the polyline's mass matrix.
A correction may add the *lift conditions*: the displacement over each rise, s(end) − s(start),
keeps the value it had as drawn — linear in the ordinates too, with a non-zero target.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camcad.errors import CamcadError
from camcad.law.law import PiecewiseLinearLaw

MODES = ("min-change", "extrema", "extrema-resample", "keypoints", "segment", "phase", "phase-keypoints")
METHODS = ("exact", "iterate")
DEFAULT_TOL = 1e-5       # of the rise displacement


def valid_tol(tol: float) -> float:
    """The closure tolerance, a fraction of the rise: finite, positive and below 1 (else a CamcadError)."""
    if not (math.isfinite(tol) and 0.0 < tol < 1.0):
        raise CamcadError(f"tolerance {tol:g} is not a fraction of the rise in (0, 1)", "--tol",
                          "give e.g. --tol 1e-5 (the default)")
    return float(tol)


#: the most points a resampling step may make over the cycle
MAX_STEP_POINTS = 5_000_000


def valid_step(step_deg: float, cycle: float = 2.0 * math.pi) -> float:
    """The source's resampling step (deg): finite, positive, and not so fine that the cycle (rad) holds more
    than ``MAX_STEP_POINTS`` points (else a CamcadError)."""
    if not (math.isfinite(step_deg) and step_deg > 0):
        raise CamcadError(f"step {step_deg!r} deg must be positive", "--step", "give e.g. --step 0.1")
    if cycle / math.radians(step_deg) > MAX_STEP_POINTS:
        raise CamcadError(f"step {step_deg:g} deg makes more than {MAX_STEP_POINTS:,} points over the cycle",
                          "--step", "give a coarser step, e.g. --step 0.1")
    return float(step_deg)


DEFAULT_STEP_DEG = 0.1   # the source's resampling step
DEFAULT_MAX_STRETCH = 0.05
QUANTITIES = ("v", "s", "rise")


# ---------------------------------------------------------------------------------------------
# Conditions
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Condition:
    """One linear condition on the law's ordinates: ``quantity`` at ``theta`` (rad) equals ``target``.

    ``quantity`` is "v" (velocity, mm/rad), "s" (displacement, mm, from s(0) = 0) or "rise"
    (s(theta) − s(start), mm: the displacement over a phase). The balance conditions have target 0;
    a lift condition has the drawn rise as its target.

    Parameters
    ----------
    name : str
        How the condition is named in reports.
    quantity : str
        "v", "s" or "rise".
    theta : float
        Where it holds, rad.
    phase_index : int, optional
        The phase it belongs to (its index in ``law.phases``), or None.
    start : float
        For "rise": where the phase starts, rad.
    target : float
        The value required, mm/rad for "v", mm for "s" and "rise".

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.law.law import PiecewiseLinearLaw
    >>> from camcad.law.phases import detect_phases
    >>> x = np.radians([0.0, 45, 90, 135, 180, 225, 270, 315, 360])
    >>> a = np.array([0.0, 1, 0, -1, 0, -1, 0, 1.2, 0])          # the return's last lobe 20 % high, mm/rad²
    >>> law = PiecewiseLinearLaw(x, a, 2 * np.pi, detect_phases(x, a, 2 * np.pi))
    >>> from camcad.balance import Condition, functional_rows
    >>> end_of_return = Condition("v at the end of the return", "v", 2 * np.pi)
    >>> row = functional_rows(law.x, (end_of_return,))
    >>> round(float((row @ law.a)[0]), 9), round(0.2 * np.pi / 4, 9)   # the extra lobe's area: 0.2 x (pi/2)/2
    (0.157079633, 0.157079633)
    """

    name: str
    quantity: str
    theta: float
    phase_index: int | None = None
    start: float = 0.0
    target: float = 0.0

    @property
    def is_lift(self) -> bool:
        return self.quantity == "rise"


def conditions(law: PiecewiseLinearLaw) -> tuple[Condition, ...]:
    """The balance conditions: every motion ends at its stated velocity (rest), stated positions are met, s closes.

    The velocity at the end of every rise and return comes back to its stated value (rest unless the phase
    states one), the displacement reaches every stated position, and s(cycle) = s(0).
    A phase that states where it ends (``Phase.s_end``, mm from s(0) = 0; a rise to an intermediate stop)
    adds a displacement condition there; one that blends into the next motion (``Phase.v_end`` ≠ 0, mm/rad)
    has that velocity as its target instead of rest. Without stated values these are the source's
    conditions (Dupliak & Kotsiyba 2018, eqs. 1–3).

    Parameters
    ----------
    law : PiecewiseLinearLaw
        The law with its phases (rad).

    Returns
    -------
    tuple of Condition
        One velocity condition per motion phase, in order (mm/rad), then one displacement condition per stated
        position (before the cycle's end, mm), then the displacement closure (always last, mm).

    Examples
    --------
    A rise to an intermediate stop at 4 mm: the stated position is a condition of its own.

    >>> import numpy as np
    >>> from camcad.law.law import Phase, PiecewiseLinearLaw
    >>> x = np.radians([0.0, 45.0, 90.0, 180.0, 360.0])
    >>> law = PiecewiseLinearLaw(x, np.array([0.0, 1.0, -1.0, 0.0, 0.0]), 2 * np.pi,
    ...                          (Phase("rise", 0.0, np.pi / 2, s_end=4.0), Phase("return", np.pi / 2, 2 * np.pi)))
    >>> [(c.quantity, round(float(np.degrees(c.theta)), 6), c.target) for c in conditions(law)]
    [('v', 90.0, 0.0), ('v', 360.0, 0.0), ('s', 90.0, 4.0), ('s', 360.0, 0.0)]
    """
    found = []
    for index, phase in enumerate(law.phases):
        if phase.kind in ("rise", "return"):
            name = f"velocity at the end of the {phase.kind} ({np.degrees(phase.end):.6g} deg)"
            if phase.v_end != 0.0:
                name += f" = {np.radians(phase.v_end):.6g} mm/deg"
            found.append(Condition(name, "v", phase.end, index, target=float(phase.v_end)))
    closing = law.cycle - 1e-12 * law.cycle
    for index, phase in enumerate(law.phases):
        if phase.s_end is not None and phase.end < closing:
            found.append(Condition(f"displacement at the end of the {phase.kind} ({np.degrees(phase.end):.6g} deg) "
                                   f"= {phase.s_end:.6g} mm", "s", phase.end, index, target=float(phase.s_end)))
    found.append(Condition("displacement closure (rise = -return)", "s", law.cycle))
    return tuple(found)


def stated_ends(law) -> bool:
    """True when a phase of ``law`` states an end position or a velocity other than rest."""
    return any(phase.states_end for phase in law.phases)


def lift_conditions(law: PiecewiseLinearLaw, targets: tuple[float, ...] | None = None) -> tuple[Condition, ...]:
    """The lift conditions: the displacement over each rise phase equals its drawn value.

    A rise whose start and end positions are both stated is held by those instead (``conditions``).

    Parameters
    ----------
    law : PiecewiseLinearLaw
        The law whose rise phases (rad) give the rows.
    targets : tuple of float, optional
        The displacement (mm) each rise must keep, one per rise phase in order; by default the
        law's own (exact), so the conditions hold for ``law`` itself.

    Returns
    -------
    tuple of Condition
        One "rise" condition per rise phase (its target in mm).

    Examples
    --------
    >>> import numpy as np
    >>> from camcad.law.law import Phase, PiecewiseLinearLaw
    >>> x = np.radians([0.0, 90.0, 180.0, 270.0, 360.0])
    >>> law = PiecewiseLinearLaw(x, np.array([0.0, 1.0, -1.0, 1.0, 0.0]), 2 * np.pi,
    ...                          (Phase("rise", 0.0, np.pi), Phase("return", np.pi, 2 * np.pi)))
    >>> [round(c.target, 6) for c in lift_conditions(law)]   # s(pi) = pi^2/24 + pi^2/8 + pi^2/24 = 5 pi^2 / 24
    [2.056168]
    """
    rises = [(index, phase) for index, phase in enumerate(law.phases) if phase.kind == "rise"
             and not _position_stated(law, index)]
    if targets is None:
        ends = law.kinematics(np.array([[p.start, p.end] for _, p in rises]).reshape(-1)).s.reshape(-1, 2) \
            if rises else np.zeros((0, 2))
        targets = tuple(float(e - s) for s, e in ends)
    if len(targets) != len(rises):
        raise ValueError(f"{len(targets)} lift targets for {len(rises)} rise phases")
    return tuple(Condition(f"rise {np.degrees(p.start):.6g}..{np.degrees(p.end):.6g} deg of {h:.6g} mm",
                           "rise", p.end, index, start=p.start, target=float(h))
                 for (index, p), h in zip(rises, targets))


def _position_stated(law: PiecewiseLinearLaw, index: int) -> bool:
    """The phase's displacement is fixed by stated positions: its end is stated and so is its start (the cycle's
    start at 0 mm, or the previous phase's stated end)."""
    phase = law.phases[index]
    if phase.s_end is None:
        return False
    for before in reversed(law.phases[:index]):
        if before.s_end is not None:
            return True
        if before.kind != "dwell":      # a motion of unstated end: the start is not fixed
            return False
    return True                          # only dwells before it: it starts at s(0) = 0


def targets(conds: tuple[Condition, ...]) -> np.ndarray:
    """The right-hand sides of ``conds`` (C a = targets), as an array."""
    return np.array([c.target for c in conds], dtype=float)


def functional_rows(x: np.ndarray, conds: tuple[Condition, ...]) -> np.ndarray:
    """Matrix C: row i gives v(θ_i), s(θ_i) or s(θ_i) − s(start_i) as Σ_k C_ik a_k, exactly.

    On a segment of length L starting at x_k with D = θc − x_k (for the part before θc):
        ∫ a dθ            → a_k L/2,            a_{k+1} L/2
        ∫ (θc − τ) a dτ   → a_k L(D/2 − L/6),   a_{k+1} L(D/2 − L/3)
    A segment cut by θc is treated as a shorter segment whose end value interpolates a_k, a_{k+1}.

    Parameters
    ----------
    x : ndarray
        Knots (rad), non-decreasing (a repeated knot is a jump).
    conds : tuple of Condition
        The conditions, one row each.

    Returns
    -------
    ndarray, shape (len(conds), len(x))
        C, in rad for a velocity row (v in mm/rad from a in mm/rad²) and rad² for a displacement row.

    Examples
    --------
    A constant a = 1 mm/rad² from rest: v(2) = 2 mm/rad and s(2) = 2 mm.

    >>> import numpy as np
    >>> from camcad.balance import Condition, functional_rows
    >>> rows = functional_rows(np.array([0.0, 2.0]), (Condition("v", "v", 2.0), Condition("s", "s", 2.0)))
    >>> (rows @ np.array([1.0, 1.0])).tolist()
    [2.0, 2.0]
    """
    x = np.asarray(x, dtype=float)
    rows = np.zeros((len(conds), len(x)))
    for row, cond in zip(rows, conds):
        if cond.quantity not in QUANTITIES:
            raise ValueError(f"unknown quantity {cond.quantity!r}")
        if cond.quantity == "rise":
            row += _row(x, "s", cond.theta) - _row(x, "s", cond.start)
        else:
            row += _row(x, cond.quantity, cond.theta)
    return rows


def functional_values(x: np.ndarray, a: np.ndarray, conds: tuple[Condition, ...]) -> np.ndarray:
    """C a (``functional_rows(x, conds) @ a``) without forming C: the same shape-function weights, each
    condition summed over the segments before its angle."""
    x = np.asarray(x, dtype=float)
    a = np.asarray(a, dtype=float)
    out = np.empty(len(conds))
    for i, cond in enumerate(conds):
        if cond.quantity not in QUANTITIES:
            raise ValueError(f"unknown quantity {cond.quantity!r}")
        if cond.quantity == "rise":
            out[i] = _value(x, a, "s", cond.theta) - _value(x, a, "s", cond.start)
        else:
            out[i] = _value(x, a, cond.quantity, cond.theta)
    return out


def _value(x: np.ndarray, a: np.ndarray, quantity: str, tc: float) -> float:
    full = int(np.searchsorted(x[1:], tc, side="right"))
    length = x[1:full + 1] - x[:full]
    a0, a1 = a[:full], a[1:full + 1]
    if quantity == "v":
        total = float(np.dot(length, a0 + a1)) / 2.0
    else:
        d = tc - x[:full]
        total = float(np.dot(length * (d / 2.0 - length / 6.0), a0) + np.dot(length * (d / 2.0 - length / 3.0), a1))
    n = len(x)
    k = int(np.searchsorted(x, tc, side="right")) - 1
    if 0 <= k < n - 1 and x[k] < tc < x[k + 1]:
        seg = x[k + 1] - x[k]
        part = tc - x[k]
        t = part / seg
        if quantity == "v":
            w_start, w_end = part / 2.0, part / 2.0
        else:
            w_start, w_end = part * (part / 2.0 - part / 6.0), part * (part / 2.0 - part / 3.0)
        total += (w_start + w_end * (1.0 - t)) * a[k] + w_end * t * a[k + 1]
    return total


def _row(x: np.ndarray, quantity: str, tc: float) -> np.ndarray:
    n = len(x)
    row = np.zeros(n)
    # the segments entirely before tc are the first ``full`` ones (x is non-decreasing)
    full = int(np.searchsorted(x[1:], tc, side="right"))
    length = x[1:full + 1] - x[:full]
    if quantity == "v":
        half = length / 2.0
        row[:full] += half
        row[1:full + 1] += half
    else:
        d = tc - x[:full]
        row[:full] += length * (d / 2.0 - length / 6.0)
        row[1:full + 1] += length * (d / 2.0 - length / 3.0)
    k = int(np.searchsorted(x, tc, side="right")) - 1
    if 0 <= k < n - 1 and x[k] < tc < x[k + 1]:
        seg = x[k + 1] - x[k]
        part = tc - x[k]
        t = part / seg
        if quantity == "v":
            w_start, w_end = part / 2.0, part / 2.0
        else:
            w_start, w_end = part * (part / 2.0 - part / 6.0), part * (part / 2.0 - part / 3.0)
        row[k] += w_start + w_end * (1.0 - t)
        row[k + 1] += w_end * t
    return row


def mass_diagonals(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(diagonal, off-diagonal) of the polyline's mass matrix ``mass_matrix(x)``: M_kk = (L_{k−1} + L_k)/3,
    M_k,k+1 = L_k/6 (L_k the segment lengths, rad); numpy only."""
    length = np.diff(x)
    diag = np.zeros(len(x))
    diag[:-1] += length / 3.0
    diag[1:] += length / 3.0
    return diag, length / 6.0


def mass_matrix(x: np.ndarray):
    """Sparse M with ∫ (Σ δ_k φ_k)² dθ = δᵀ M δ for the hat functions φ_k of the knots x (rad).

    Parameters
    ----------
    x : ndarray
        Knots (rad), non-decreasing.

    Returns
    -------
    scipy.sparse.csc_matrix
        Tridiagonal, (len(x), len(x)), in rad; a vertex both of whose segments have zero length has a
        zero row (its ordinate does not change the function).

    Examples
    --------
    A constant δ = 1 over 2 rad: ∫ δ² dθ = 2.

    >>> import numpy as np
    >>> from camcad.balance import mass_matrix
    >>> ones = np.ones(3)
    >>> float(ones @ (mass_matrix(np.array([0.0, 1.0, 2.0])) @ ones))
    2.0
    """
    from scipy import sparse

    diag, off = mass_diagonals(x)
    return sparse.diags([off, diag, off], [-1, 0, 1], format="csc")
