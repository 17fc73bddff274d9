"""Phases of a cycle (rise, far dwell, return, near dwell) detected from a drawn acceleration law.

How a drawn law shows its phases:
- a dwell is a stretch of zero acceleration of positive length at either end of the cycle, or
  between two lobes of the *same* sign (− 0 − is a far dwell, + 0 + a near dwell); a zero stretch
  between lobes of opposite signs (+ 0 −) is the constant-velocity part of a motion; dwells can
  also be stated by the caller (the drawn dwell points of an interpolating spline that overshoots);
- between dwells the follower moves; the motion holds a rise and a return when its velocity
  (integrated from rest at the start of the motion) changes sign and then reaches at least half of
  the motion's peak speed — a smaller excursion is the drawing's imbalance, not a phase;
- where a rise and a return meet with no dwell, their boundary is the drawn vertex between their
  lobes: the rise's decelerating lobe and the return's accelerating lobe have one sign, and the
  designer draws the boundary where the acceleration touches zero between them (or crosses it by a
  hair, at most ``CROSS_FRACTION`` of the motion's peak). That is where the designer's lobes meet
  whether or not the law is balanced; the velocity changes sign there only when the law is balanced.
  When the acceleration does not reach zero between the lobes (a harmonic or a constant-acceleration
  law drawn with no dwell), the boundary is where the velocity changes sign, and a note says so and
  how to state the phases (``--phases``); a note also says which of several zeros was taken;
- a motion whose velocity first grows positive is a rise, negative a return.
Within a rise, the accelerating part is where a > 0 and the decelerating part where a < 0; within
a return the reverse.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import pairwise

import numpy as np

from camcad.arrays import unique
from camcad.errors import CamcadError
from camcad.law.law import Phase, PiecewiseLinearLaw, sample_piecewise_linear
from camcad.numerics import brent_root

#: |a| at or below this fraction of max|a| counts as zero acceleration
ZERO_FRACTION = 1e-6
#: a velocity excursion must reach this fraction of the motion's peak speed to be a phase of its own
SPLIT_FRACTION = 0.5
#: between the lobes of a rise and a return with no dwell, a local extreme within this fraction of the
#: motion's peak |a| of the zero touches it (a vertex snapped a hair off the axis, a rounded join of an
#: outlined stroke: w = 1/40 of the peak lowers a sharp junction by 0.5 % of it)
TOUCH_FRACTION = 0.02
#: vertices this fraction of the peak above the lowest of a junction count as its bottom (its middle is taken)
LEVEL_FRACTION = 1e-3
#: ... and the acceleration may cross the zero there by at most this fraction of the peak (a vertex drawn a
#: hair past the axis); a larger excursion is a lobe of its own
CROSS_FRACTION = 0.05
#: the drawn vertex and the velocity's sign change are said to differ when they are this fraction of the cycle
#: apart (0.036 deg of 360): closer, the law is as good as balanced there and nothing needs saying
NOTE_FRACTION = 1e-4


def zero_threshold(a: np.ndarray) -> float:
    peak = float(np.max(np.abs(a))) if len(a) else 0.0
    return ZERO_FRACTION * peak


def sign_runs(x: np.ndarray, a: np.ndarray) -> list[tuple[int, float, float]]:
    """Maximal runs of constant sign (+1, −1, 0) of a piecewise-linear a, as (sign, start, end) in x.

    Zero crossings inside a segment split it exactly (linear interpolation); zero-length
    segments (jumps) carry no run of their own. Vectorised over the segments (a drawn law may
    have a million vertices).
    """
    x = np.asarray(x, dtype=float)
    a = np.asarray(a, dtype=float)
    if len(x) < 2:
        return []
    eps = zero_threshold(a)
    x0, x1, a0, a1 = x[:-1], x[1:], a[:-1], a[1:]
    s0 = np.where(np.abs(a0) <= eps, 0, np.sign(a0)).astype(int)
    s1 = np.where(np.abs(a1) <= eps, 0, np.sign(a1)).astype(int)
    crosses = (s0 * s1) < 0
    with np.errstate(divide="ignore", invalid="ignore"):
        crossing = np.where(crosses, x0 + (x1 - x0) * a0 / (a0 - a1), x1)
    # each segment gives a first piece and, when a crosses zero inside it, a second one;
    # a lobe starting or ending at a vertex on the axis takes the sign of its other end
    first_sign = np.where(crosses | (s0 == s1), s0, s0 + s1)
    signs = np.column_stack((first_sign, s1)).ravel()
    starts = np.column_stack((x0, crossing)).ravel()
    ends = np.column_stack((crossing, x1)).ravel()
    piece = np.column_stack((x1 > x0, crosses & (x1 > x0))).ravel() & (ends > starts)
    signs, starts, ends = signs[piece], starts[piece], ends[piece]
    if len(signs) == 0:
        return []
    # consecutive pieces are contiguous in x, so a run is a maximal block of equal signs
    first = np.flatnonzero(np.concatenate(([True], signs[1:] != signs[:-1])))
    last = np.concatenate((first[1:] - 1, [len(signs) - 1]))
    return [(int(sg), float(st), float(en)) for sg, st, en in zip(signs[first], starts[first], ends[last])]


@dataclass(frozen=True)
class PhaseReading:
    """The phases detected in a law and what was decided to find them.

    Attributes
    ----------
    phases : tuple of Phase
        The phases, start and end in rad.
    notes : tuple of str
        Decisions a designer should know (the rule used for a boundary with no dwell, dwells taken from
        the drawn dwell points), angles in deg.
    """

    phases: tuple[Phase, ...]
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class _Cut:
    """A boundary between a rise and a return with no dwell: where it was put and by which rule."""

    before: str
    after: str
    at: float               # rad, the boundary used
    velocity_at: float      # rad, where the velocity changes sign
    rule: str               # "vertex" (the drawn vertex), "velocity" (no zero between the lobes), "wavering"
    zeros: tuple[float, ...] = ()   # rad, every place the acceleration reaches zero between the lobes
    crosses: bool = False   # the drawn vertex lies past the zero (a crossing), not on it


def detect_phases(x: np.ndarray, a: np.ndarray, cycle: float, where: str = "") -> tuple[Phase, ...]:
    """Rise, return and dwell phases of the piecewise-linear law (x rad, a mm/rad²) over [0, cycle]
    (the rules are in the module docstring; :func:`read_phases` also says how they were found)."""
    return read_phases(x, a, cycle, where).phases


def read_phases(x: np.ndarray, a: np.ndarray, cycle: float, where: str = "",
                dwells: tuple[tuple[float, float], ...] = (), zeros: tuple[float, ...] = ()) -> PhaseReading:
    """The phases of the piecewise-linear law (x rad, a mm/rad²) over [0, cycle], with notes.

    ``dwells`` (rad) are stretches the caller knows to be dwells (an interpolating spline's drawn dwell
    points): they are dwells whatever the acceleration does there. ``zeros`` (rad) are points the designer
    put on the zero (an interpolating spline's points at the zero): between a rise and a return with no
    dwell, such a point is the boundary, wherever the spline through it turns.
    """
    x = np.asarray(x, dtype=float)
    a = np.asarray(a, dtype=float)
    runs = sign_runs(x, a)
    if not any(sign for sign, _, _ in runs):
        raise CamcadError("the acceleration is zero everywhere: there is no motion", where,
                          "pick the curve that holds the law (--layer/--handle)")
    intervals = []
    motion_from = None      # where the motion that the current run belongs to started
    for index, (sign, start, end) in enumerate(runs):
        if sign != 0:
            if motion_from is None:
                motion_from = start
            continue
        before = next((runs[i][0] for i in range(index - 1, -1, -1) if runs[i][0]), None)
        after = next((runs[i][0] for i in range(index + 1, len(runs)) if runs[i][0]), None)
        is_dwell = before is None or after is None or before == after
        if not is_dwell and motion_from is not None:
            # between lobes of opposite signs: a constant velocity, unless the follower is at rest there (an
            # intermediate stop: + - 0 + - is a rise, a stop and a second rise)
            is_dwell = _at_rest(x, a, motion_from, start)
        if is_dwell:
            intervals.append((start, end))
            motion_from = None
    x_first, x_last = float(runs[0][1]), float(runs[-1][2])
    intervals.extend((max(float(s), x_first), min(float(e), x_last)) for s, e in dwells
                     if min(float(e), x_last) > max(float(s), x_first))
    dwell_spans = _union(intervals)
    phases: list[Phase] = []
    cuts: list[_Cut] = []
    cursor = x_first
    eps = zero_threshold(a)
    for start, end in dwell_spans + [(x_last, x_last)]:
        if start > cursor:
            if _max_abs(x, a, cursor, start) > eps:
                motion, motion_cuts = _split_motion(x, a, cursor, start, zeros)
                phases.extend(motion)
                cuts.extend(motion_cuts)
            else:
                phases.append(Phase("dwell", cursor, start))
        if end > start:
            phases.append(Phase("dwell", start, end))
        cursor = max(cursor, end)
    merged = _merge_dwells(phases)
    forced = [(s, e) for s, e in dwells if e > s]
    return PhaseReading(merged, tuple(_cut_notes(cuts, merged, cycle)) + _dwell_notes(forced))


def _max_abs(x: np.ndarray, a: np.ndarray, start: float, end: float) -> float:
    _xs, as_ = restrict(x, a, start, end)
    return float(np.max(np.abs(as_))) if len(as_) else 0.0


def _union(intervals: list[tuple[float, float]]) -> list[tuple[float, float]]:
    out: list[list[float]] = []
    for s, e in sorted(intervals):
        if out and s <= out[-1][1]:
            out[-1][1] = max(out[-1][1], e)
        else:
            out.append([s, e])
    return [(s, e) for s, e in out]


#: a zero stretch between lobes of opposite signs is a stop (a dwell) when the velocity there is at most this
#: fraction of the motion's peak speed before it
REST_FRACTION = 0.05


def _at_rest(x: np.ndarray, a: np.ndarray, start: float, end: float) -> bool:
    """The follower is at rest at ``end``: the velocity integrated from rest at ``start`` is at most
    ``REST_FRACTION`` of its peak over [start, end] (a drawn stop carries the drawing's imbalance)."""
    if not end > start:
        return True
    law = _motion_law(x, a, start, end)
    inner = x[(x > start) & (x < end)] - start
    fraction = np.linspace(0.0, 1.0, 9)
    grid = unique(np.concatenate(([0.0, end - start], inner)))
    fine = unique(np.append(grid[:-1, None] + np.diff(grid)[:, None] * fraction[None, :-1], grid[-1]))
    v = law.kinematics(fine).v
    peak = float(np.max(np.abs(v)))
    return peak == 0.0 or abs(float(v[-1])) <= REST_FRACTION * peak


def _merge_dwells(phases: list[Phase]) -> tuple[Phase, ...]:
    merged: list[Phase] = []
    for phase in phases:
        if merged and merged[-1].kind == phase.kind == "dwell":
            merged[-1] = Phase("dwell", merged[-1].start, phase.end)
        else:
            merged.append(phase)
    return tuple(merged)


def _deg(value: float) -> str:
    text = f"{np.degrees(value):.6f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def phases_text(phases: tuple[Phase, ...]) -> str:
    """The phases as ``--phases`` takes them: "0:90:rise,90:180:dwell,..." (deg).

    Examples
    --------
    >>> import math
    >>> phases_text((Phase("rise", 0.0, math.pi), Phase("return", math.pi, 2 * math.pi)))
    '0:180:rise,180:360:return'
    """
    return ",".join(f"{_deg(p.start)}:{_deg(p.end)}:{p.kind}" for p in phases)


def _cut_notes(cuts: list[_Cut], phases: tuple[Phase, ...], cycle: float) -> list[str]:
    notes = []
    stated = f'--phases "{phases_text(phases)}"'
    tol = NOTE_FRACTION * cycle
    for cut in cuts:
        pair = f"the {cut.before} and the {cut.after} meet with no dwell"
        if cut.rule in ("velocity", "wavering"):
            how = "does not reach zero" if cut.rule == "velocity" else "wavers about the zero (no single vertex)"
            notes.append(f"{pair} and the drawn acceleration {how} between their lobes: the boundary "
                         f"is taken where the velocity changes sign, at {_deg(cut.at)} deg; if the lobes meet "
                         f"elsewhere, state the phases, e.g. {stated}")
            continue
        touch = "crosses" if cut.crosses else "touches"
        if len(cut.zeros) > 1:
            others = ", ".join(_deg(z) for z in cut.zeros)
            notes.append(f"{pair}; the drawn acceleration reaches zero at {len(cut.zeros)} places between their "
                         f"lobes ({others} deg): the boundary is taken at {_deg(cut.at)} deg, the one nearest where "
                         f"the velocity changes sign ({_deg(cut.velocity_at)} deg); if the lobes meet elsewhere, "
                         f"state the phases, e.g. {stated}")
        elif abs(cut.at - cut.velocity_at) > tol:
            notes.append(f"{pair}: the boundary is taken at {_deg(cut.at)} deg, the drawn vertex where the "
                         f"acceleration {touch} zero between their lobes, not where the velocity changes sign "
                         f"({_deg(cut.velocity_at)} deg: the {cut.before} is not balanced); --phases overrides")
    return notes


def _dwell_notes(forced: list[tuple[float, float]]) -> tuple[str, ...]:
    if not forced:
        return ()
    spans = ", ".join(f"{_deg(s)}..{_deg(e)}" for s, e in forced)
    return (f"dwell{'s' if len(forced) > 1 else ''} at {spans} deg taken from the spline's drawn dwell points "
            "(the spline interpolates them but leaves the zero between them); --phases overrides",)


def _split_motion(x: np.ndarray, a: np.ndarray, start: float, end: float,
                  drawn: tuple[float, ...] = ()) -> tuple[list[Phase], list[_Cut]]:
    """Cut one motion (between dwells) into rises and returns (see the module docstring): how many,
    by the sign changes of the velocity; where, at the drawn vertex between the lobes."""
    law = _motion_law(x, a, start, end)
    grid = unique(np.concatenate(([start, end], x[(x > start) & (x < end)])))
    # velocity is quadratic on each segment: a few interior samples catch every sign change
    fraction = np.linspace(0.0, 1.0, 9)
    fine = unique(np.append(grid[:-1, None] + np.diff(grid)[:, None] * fraction[None, :-1], grid[-1]))
    v = law.kinematics(fine - start).v
    peak = float(np.max(np.abs(v)))
    first_sign = _first_lobe_sign(law)
    if peak == 0.0:
        return [Phase("rise" if first_sign > 0 else "return", start, end)], []
    significant = np.abs(v) >= SPLIT_FRACTION * peak
    cuts = [start]
    velocity_cuts = []
    current = first_sign
    sign_of_v = np.sign(v)
    # only the first sample of each stretch of one sign can start a new phase: later samples of the
    # same stretch see a shorter part of the same excursion
    changes = np.flatnonzero(sign_of_v[1:] != sign_of_v[:-1]) + 1
    for i in changes:
        if sign_of_v[i] == -current and significant[i:].any():
            # the velocity changed sign; it is a phase only if it then grows to a significant speed
            # with the new sign before changing back
            ahead = v[i:]
            back = np.flatnonzero(np.sign(ahead) == current)
            stretch = ahead[: back[0]] if len(back) else ahead
            if np.any(np.abs(stretch) >= SPLIT_FRACTION * peak):
                lo, hi = fine[i - 1], fine[i]
                root = brent_root(lambda t: float(law.kinematics(np.array([t - start])).v[0]), lo, hi,
                                  xtol=1e-15, rtol=4 * np.finfo(float).eps) if v[i - 1] != 0 else lo
                velocity_cuts.append((root, current))
                current = -current
    xs, as_ = restrict(x, a, start, end)
    a_peak = float(np.max(np.abs(as_)))
    records: list[_Cut] = []
    for root, before in velocity_cuts:
        # the lobes on both sides of the boundary have the sign opposite to the motion before it
        zeros, crosses, wavering = _drawn_vertices(xs, as_, root, -before, a_peak, drawn)
        pair = ("rise", "return") if before > 0 else ("return", "rise")
        if zeros:
            at = min(zeros, key=lambda z: abs(z - root))
            records.append(_Cut(*pair, at, root, "vertex", tuple(zeros), crosses[zeros.index(at)]))
        else:
            at = root
            records.append(_Cut(*pair, at, root, "wavering" if wavering else "velocity"))
        cuts.append(max(at, cuts[-1]))
    cuts.append(end)
    kinds = []
    sign = first_sign
    for _ in range(len(cuts) - 1):
        kinds.append("rise" if sign > 0 else "return")
        sign = -sign
    return [Phase(kind, c0, c1) for kind, c0, c1 in zip(kinds, cuts[:-1], cuts[1:]) if c1 > c0], records


def _drawn_vertices(xs: np.ndarray, as_: np.ndarray, root: float, sign: int, peak: float,
                    drawn: tuple[float, ...] = ()) -> tuple[list[float], list[bool], bool]:
    """Where the drawn acceleration touches or crosses zero between two lobes of sign ``sign`` around
    ``root`` (the velocity's sign change): the drawn vertices (rad), and whether each crosses zero.

    The stretch looked at runs from ``root`` both ways while sign·a stays above −CROSS_FRACTION·peak
    (past the zero only by a hair); in it, each connected run of vertices within TOUCH_FRACTION·peak of
    the zero (or past it) that has a lobe (sign·a above TOUCH_FRACTION·peak) on both sides gives its
    vertex nearest the other side (the middle of several equal ones). Points the designer put on the zero
    (``drawn``) inside the stretch, with a lobe on both sides, are taken instead. The last value says the
    acceleration wavers about the zero there (no vertex).
    """
    f = sign * as_
    n = len(xs)
    if n < 3 or peak <= 0:
        return [], [], False
    touch, cross = TOUCH_FRACTION * peak, -CROSS_FRACTION * peak
    k = int(np.clip(np.searchsorted(xs, root, side="right") - 1, 0, n - 2))
    allowed = f > cross
    left = k if allowed[k] else k + 1
    right = k + 1 if allowed[k + 1] else k
    blocked_left = np.flatnonzero(~allowed[:left])
    left = int(blocked_left[-1]) + 1 if len(blocked_left) else 0
    blocked_right = np.flatnonzero(~allowed[right + 1:])
    right = right + int(blocked_right[0]) if len(blocked_right) else n - 1
    if right - left < 2:
        return [], [], False
    window = np.arange(left, right + 1)
    near = f[window] <= touch
    lobe = f[window] > touch
    zeros, crosses = [], []
    lobe_x = xs[window][lobe]
    placed = [float(t) for t in drawn if len(lobe_x) and lobe_x[0] < t < lobe_x[-1]]
    if placed:
        return placed, [False] * len(placed), False
    wavering = False
    quiet = f[window] <= -cross           # within CROSS_FRACTION of the zero, either side
    starts = np.flatnonzero(near & np.concatenate(([True], ~near[:-1])))
    for s in starts:
        e = s
        while e + 1 < len(window) and near[e + 1]:
            e += 1
        # a lobe on both sides, inside the motion (not its ends)
        if not (lobe[:s].any() and lobe[e + 1:].any()):
            continue
        # a touch or a hair's crossing leaves the zero at once; an acceleration that wavers about the zero
        # (three or more crossings in the quiet stretch round it: a dwell drawn not quite at zero, a
        # filtered law) shows no vertex
        q0, q1 = s, e
        while q0 > 0 and quiet[q0 - 1]:
            q0 -= 1
        while q1 + 1 < len(window) and quiet[q1 + 1]:
            q1 += 1
        stretch = as_[window[q0:q1 + 1]]
        signs = np.sign(stretch[np.abs(stretch) > ZERO_FRACTION * peak])
        if np.count_nonzero(signs[1:] != signs[:-1]) >= 3:
            wavering = True
            continue
        idx = window[s:e + 1]
        low = f[idx].min()
        # the middle of the lowest vertices (within 1e-3 of the peak): the vertex itself when it is drawn
        # sharp, the middle of a rounded junction
        at = idx[f[idx] <= low + LEVEL_FRACTION * peak]
        zeros.append(float((xs[at[0]] + xs[at[-1]]) / 2))
        crosses.append(bool(low < -touch))
    return zeros, crosses, wavering and not zeros


def _first_lobe_sign(law: PiecewiseLinearLaw) -> int:
    """The sign of the motion's first lobe (a motion starting with positive acceleration is a rise)."""
    runs = [sign for sign, _, _ in sign_runs(law.x, law.a) if sign]
    return runs[0] if runs else 1


def _motion_law(x: np.ndarray, a: np.ndarray, start: float, end: float) -> PiecewiseLinearLaw:
    """The law restricted to [start, end], shifted to start at 0 from rest."""
    inner = (x > start) & (x < end)
    xs = np.concatenate(([start], x[inner], [end]))
    a_start = sample_piecewise_linear(x, a, np.array([start]))[0]
    a_end = _left_value(x, a, end)
    as_ = np.concatenate(([a_start], a[inner], [a_end]))
    return PiecewiseLinearLaw(xs - start, as_, cycle=end - start)


def _left_value(x: np.ndarray, a: np.ndarray, t: float) -> float:
    """a(t−): the value arriving at t from the left (the left side of a jump)."""
    index = np.searchsorted(x, t, side="left")
    if index < len(x) and x[index] == t:
        return float(a[index])

    return float(sample_piecewise_linear(x, a, np.array([t]))[0])


def parse_phases(text: str, cycle_deg: float, where: str = "--phases") -> tuple[Phase, ...]:
    """Phases from a text such as "0:90:rise,90:180:dwell,..." (deg), covering [0, cycle] without gaps.

    Parameters
    ----------
    text : str
        Comma-separated ``start:end:kind[:s_end[:v_end]]`` items, start and end in deg, kind "rise",
        "return" or "dwell"; each phase starts where the previous ends, the first at 0, the last ends at
        the cycle. ``s_end`` states the displacement at the phase's end (mm from s(0) = 0: a rise to an
        intermediate stop), ``v_end`` the velocity there (mm/deg; rest when left out).
    cycle_deg : float
        The cycle the phases must cover, deg.
    where : str
        What to name in an error message: the option or scene key the text came from.

    Returns
    -------
    tuple of Phase
        The phases, with ``start`` and ``end`` in **rad** (the library's inside unit;
        ``Phase.as_deg()`` gives deg), ``s_end`` in mm and ``v_end`` in mm/rad.

    Raises
    ------
    CamcadError
        A malformed item, an unknown kind, a phase that ends before it starts, a gap or an overlap,
        or phases that do not cover the cycle.

    Examples
    --------
    >>> import math
    >>> import camcad
    >>> phases = camcad.parse_phases("0:90:rise,90:180:dwell,180:270:return,270:360:dwell", 360.0)
    >>> [(p.kind, math.degrees(p.start), math.degrees(p.end)) for p in phases][:2]
    [('rise', 0.0, 90.0), ('dwell', 90.0, 180.0)]
    >>> phases[0].as_deg()
    {'kind': 'rise', 'start_deg': 0.0, 'end_deg': 90.0}
    >>> camcad.parse_phases("0:90:rise,100:360:return", 360.0)
    Traceback (most recent call last):
    ...
    camcad.errors.CamcadError: --phases: gap or overlap between phases at 90 and 100 deg; make each phase start where the previous ends
    """  # noqa: E501 - a doctest's expected output is one line
    phases = []
    items = [item.strip() for item in text.split(",") if item.strip()]
    if not items:
        raise CamcadError("no phases given", where, 'write e.g. "0:90:rise,90:180:dwell,180:270:return,270:360:dwell"')
    for item in items:
        parts = item.split(":")
        if len(parts) not in (3, 4, 5):
            raise CamcadError(f"phase {item!r} is not start:end:kind[:s_end[:v_end]]", where,
                              'write e.g. "0:90:rise,90:180:dwell,180:270:return,270:360:dwell"')
        try:
            start, end = float(parts[0]), float(parts[1])
        except ValueError:
            raise CamcadError(f"phase {item!r}: start and end must be numbers (deg)", where,
                              'write e.g. "0:90:rise"') from None
        kind = parts[2].strip().lower()
        if kind not in ("rise", "return", "dwell"):
            raise CamcadError(f"phase {item!r}: kind must be rise, return or dwell", where, "fix the kind")
        if not end > start:
            raise CamcadError(f"phase {item!r} ends before it starts", where, "give start < end")
        stated: list[float | None] = []
        for text, unit in zip(parts[3:], ("mm", "mm/deg")):
            if text.strip() == "-" and unit == "mm":     # the position not stated, only the velocity
                stated.append(None)
                continue
            try:
                value = float(text)
            except ValueError:
                raise CamcadError(f"phase {item!r}: the stated end value {text!r} is not a number ({unit})", where,
                                  'write e.g. "0:60:rise:12" (a stop at 12 mm) or "0:60:rise:12:0.3" (then 0.3 mm/deg)'
                                  ) from None
            if not np.isfinite(value):
                raise CamcadError(f"phase {item!r}: the stated end value {text!r} is not finite", where,
                                  "give a finite number")
            stated.append(value)
        s_end = stated[0] if stated else None
        v_end = float(np.degrees(stated[1])) if len(stated) > 1 and stated[1] is not None else 0.0  # mm/deg -> mm/rad
        if kind == "dwell" and v_end != 0.0:
            raise CamcadError(f"phase {item!r}: a dwell rests, it cannot end at {stated[1]:g} mm/deg", where,
                              "drop the velocity of the dwell")
        phases.append(Phase(kind, float(np.radians(start)), float(np.radians(end)), s_end, v_end))
    tol = 1e-9 * max(cycle_deg, 1.0)
    if abs(np.degrees(phases[0].start)) > tol or abs(np.degrees(phases[-1].end) - cycle_deg) > tol:
        raise CamcadError(f"phases cover {np.degrees(phases[0].start):g}..{np.degrees(phases[-1].end):g} deg, "
                          f"not the cycle 0..{cycle_deg:g}", where, "make the first start 0 and the last end the cycle")
    for before, after in pairwise(phases):
        if abs(np.degrees(after.start - before.end)) > tol:
            raise CamcadError(f"gap or overlap between phases at {np.degrees(before.end):g} and "
                              f"{np.degrees(after.start):g} deg", where,
                              "make each phase start where the previous ends")
    return tuple(phases)


def phase_integrals(x: np.ndarray, a: np.ndarray, start: float, end: float) -> tuple[float, float]:
    """(∫ max(a, 0), ∫ min(a, 0)) over [start, end], exact for piecewise-linear a (θ in rad).

    A segment whose ends have opposite signs is cut at its zero crossing, so each piece has one
    sign and its trapezoid area is exact.
    """
    xs, as_ = restrict(x, a, start, end)
    length = np.diff(xs)
    a0, a1 = as_[:-1], as_[1:]
    crossing = a0 * a1 < 0
    cut = np.divide(length * a0, a0 - a1, out=np.zeros_like(length), where=crossing)
    first = np.where(crossing, cut * a0 / 2.0, length * (a0 + a1) / 2.0)
    second = np.where(crossing, (length - cut) * a1 / 2.0, 0.0)
    pieces = np.concatenate((first, second))
    return float(pieces[pieces > 0].sum()), float(pieces[pieces < 0].sum())


def phases_integrals(x: np.ndarray, a: np.ndarray, bounds) -> list[tuple[float, float]]:
    """``phase_integrals`` of every (start, end) in ``bounds`` in one pass over the polyline: the phase ends
    are inserted as knots (right value at a start, left value at an end, as ``restrict`` takes them), every
    segment is split at its zero crossing, and each phase sums its own run of pieces."""
    bounds = [(float(lo), float(hi)) for lo, hi in bounds]
    if len(x) < 2 or not bounds or any(lo < x[0] or hi > x[-1] or hi < lo for lo, hi in bounds):
        return [phase_integrals(x, a, lo, hi) for lo, hi in bounds]

    ends = np.array(sorted({v for pair in bounds for v in pair}))
    found = np.minimum(np.searchsorted(x, ends), len(x) - 1)
    fresh = ends[x[found] != ends]            # inside a segment: one knot, the polyline's value there
    if len(fresh):
        at = np.searchsorted(x, fresh)
        values = sample_piecewise_linear(x, a, fresh)
        x, a = np.insert(x, at, fresh), np.insert(a, at, values)
    length = np.diff(x)
    a0, a1 = a[:-1], a[1:]
    crossing = a0 * a1 < 0
    cut = np.divide(length * a0, a0 - a1, out=np.zeros_like(length), where=crossing)
    first = np.where(crossing, cut * a0 / 2.0, length * (a0 + a1) / 2.0)
    second = np.where(crossing, (length - cut) * a1 / 2.0, 0.0)
    out = []
    for lo, hi in bounds:
        # the segments between the last knot at lo and the first knot at hi (a jump's zero-length
        # segment at either end adds nothing)
        i = int(np.searchsorted(x, lo, side="left"))
        j = int(np.searchsorted(x, hi, side="left"))
        pieces = np.concatenate((first[i:j], second[i:j]))
        out.append((float(pieces[pieces > 0].sum()), float(pieces[pieces < 0].sum())))
    return out


def restrict(x: np.ndarray, a: np.ndarray, start: float, end: float) -> tuple[np.ndarray, np.ndarray]:
    """The polyline cut to [start, end], with interpolated end points (right value at a start jump)."""
    inner = (x > start) & (x < end)
    xs = np.concatenate(([start], x[inner], [end]))
    a_start = sample_piecewise_linear(x, a, np.array([start]))[0]
    as_ = np.concatenate(([a_start], a[inner], [_left_value(x, a, end)]))
    return xs, as_

