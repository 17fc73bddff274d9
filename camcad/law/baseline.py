"""Where a drawn law's zero is: the zero axis (baseline) and the origin, found in the drawing.

A designer places the acceleration graph anywhere on the sheet (Inkscape even writes page
coordinates: the axis lands at y = page height minus its SVG position), so y = 0 of the file is
rarely the law's zero. The rules (docs/reading.md):

1. **An axis line.** A horizontal straight line (LINE, or a polyline; several collinear pieces
   count as one) that spans the law's x-extent (within 1 % of it at each end) and lies within the
   curve's height is a zero-axis candidate. Of several, the one agreeing with the dwell level
   wins; without a dwell, the one nearest the curve's mean height (a balanced law's mean is its
   zero), and the note says so.
2. **The dwell level.** Runs of the author's points (polyline vertices, spline fit or knot
   points) at one height, at least 1 % of the law's width long, are flat stretches. The level
   of the flat stretches at the curve's ends (the near dwell) is the dwell level, provided the
   curve rises above it and falls below it by at least 5 % of its height (a constant-acceleration
   plateau at the top or bottom is no dwell); without flat ends, the longest such interior level.
3. **Both, or either.** An axis that agrees with the dwell level (within 1 % of the curve's
   height) is used; a lone axis or a lone dwell level is used and named. When the dwells sit
   within 1 % of the curve's height of the file's own y = 0 and there is no axis, y = 0 is kept.
   When nothing is evident, y = 0 and a note says how to override.
4. ``--y0`` / ``--x0`` (or ``--origin X,Y``, scene keys ``y0``, ``x0``) override.

Warnings: flat stretches drawn near but not at the zero (largest deviation and where), and a
spline (or arc) that leaves the zero between the author's points of a dwell (an interpolating
spline overshoots there: draw the dwells as lines or use a polyline).
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass

import numpy as np

from camcad.io.chain import is_straight
from camcad.io.dxf_read import Curve, Piece, handles_text

#: an axis must reach within this fraction of the law's width of each end of the law
AXIS_REACH_FRACTION = 0.01
#: a flat stretch is at least this fraction of the law's width long
DWELL_MIN_FRACTION = 0.01
#: the curve must rise above and fall below a dwell level by this fraction of its height
TWO_SIDED_FRACTION = 0.05
#: an axis and a dwell level agree within this fraction of the curve's height
AGREE_FRACTION = 0.01
#: a flat stretch within this fraction of the curve's height of the zero is a dwell drawn off zero
NEAR_ZERO_FRACTION = 0.05
#: deviations below this fraction of the curve's height are the drawing's rounding
NOISE_FRACTION = 1e-6
#: a curve leaving the zero between dwell points by more than this fraction of its height is warned of
OVERSHOOT_FRACTION = 1e-3
#: ... unless it reaches this fraction of the law's peak: then it is a lobe drawn between them
LOBE_FRACTION = 0.5
#: an interpolating spline (fit points, or a C2 cubic through its knot points) leaving the zero between its
#: own points there by more than this fraction of the curve's height overshoots, whatever the amount: two
#: consecutive points the designer put on the zero mean a dwell, and no lobe can be drawn between them
INTERPOLATING_NOISE_FRACTION = 1e-5


@dataclass(frozen=True)
class Baseline:
    """The law's zero axis and origin in drawing coordinates, and how they were found.

    Attributes
    ----------
    y0 : float
        Drawing y of zero acceleration.
    x0 : float or None
        Drawing x of θ = 0 when given; None: the curve's left end.
    source : str
        "given", "axis", "axis+dwell", "dwell", "origin" (y = 0 kept) or "none".
    notes : tuple of str
        What was found and used (and the warnings, prefixed "warning: ").
    axis_pieces : tuple of int
        Indices of the pieces forming the axis used.
    drawn_dwells : tuple of (float, float)
        Drawing x-ranges (drawing units) between an interpolating spline's own points at the zero that
        the spline leaves: the dwells the designer drew, which the phases take.
    drawn_zeros : tuple of float
        Drawing x (drawing units) of an interpolating spline's own points at the zero: where the
        designer put the lobes' ends.
    """

    y0: float
    x0: float | None
    source: str
    notes: tuple[str, ...]
    axis_pieces: tuple[int, ...] = ()
    drawn_dwells: tuple[tuple[float, float], ...] = ()
    drawn_zeros: tuple[float, ...] = ()


@dataclass(frozen=True)
class _Run:
    level: float
    x_start: float
    x_end: float
    first: int   # index of the first breakpoint of the run (x order)
    last: int

    @property
    def length(self) -> float:
        return self.x_end - self.x_start


def flat_runs(points: np.ndarray, min_length: float, tol: float) -> list[_Run]:
    """Maximal runs of consecutive points (x order) at one height (within ``tol``) that are at
    least ``min_length`` long in x.

    Parameters
    ----------
    points : ndarray, shape (n, 2)
        Points in x order.
    min_length : float
        Shortest run, drawing units of x.
    tol : float
        Largest height difference within a run, drawing units of y.

    Returns
    -------
    list of _Run

    Examples
    --------
    >>> pts = np.array([[0, 5], [10, 5], [20, 5], [25, 9], [30, 5], [31, 5]], dtype=float)
    >>> [(r.level, r.x_start, r.x_end) for r in flat_runs(pts, 5.0, 1e-9)]
    [(5.0, 0.0, 20.0)]
    """
    runs: list[_Run] = []
    n = len(points)
    start = 0
    while start < n:
        end = start
        while end + 1 < n and abs(points[end + 1, 1] - points[start, 1]) <= tol:
            end += 1
        if end > start and points[end, 0] - points[start, 0] >= min_length:
            runs.append(_Run(float(points[start:end + 1, 1].mean()), float(points[start, 0]), float(points[end, 0]),
                             start, end))
        start = end + 1
    return runs


def _x_order(points: np.ndarray) -> np.ndarray:
    return points[::-1] if len(points) > 1 and points[-1, 0] < points[0, 0] else points


def _horizontal_runs(pieces: tuple[Piece, ...], candidates: list[int],
                     tol: float) -> list[tuple[float, float, float, list[int]]]:
    """Horizontal straight pieces merged into collinear runs: (level, x_min, x_max, piece indices)."""
    lines = []
    for i in candidates:
        pts = pieces[i].points
        if np.ptp(pts[:, 1]) <= tol and np.ptp(pts[:, 0]) > 0 and is_straight(pts):
            lines.append((float(pts[:, 1].mean()), float(pts[:, 0].min()), float(pts[:, 0].max()), i))
    lines.sort()
    runs: list[list] = []
    levels: list[float] = []   # each run's level; lines come by level, so runs are made in order of level
    for level, x_lo, x_hi, i in lines:
        # only runs within tol of this level can take the line: from the first of them on (10,000 horizontal
        # lines at as many levels took 5e7 comparisons when every run was tried)
        for run in runs[bisect.bisect_left(levels, level - tol):]:
            if abs(run[0] - level) <= tol and x_lo <= run[2] + tol and x_hi >= run[1] - tol:
                run[1], run[2] = min(run[1], x_lo), max(run[2], x_hi)
                run[3].append(i)
                break
        else:
            runs.append([level, x_lo, x_hi, [i]])
            levels.append(level)
    return [(r[0], r[1], r[2], r[3]) for r in runs]


def find_baseline(curve: Curve, pieces: tuple[Piece, ...], law_pieces: set[int], *, y0: float | None = None,
                  x0: float | None = None, join_tol: float = 0.0) -> Baseline:
    """The zero axis and origin of a drawn law (the rules are in the module docstring).

    Parameters
    ----------
    curve : Curve
        The law's curve (drawing units).
    pieces : tuple of Piece
        Every piece of the drawing (axis lines are looked for among those not in the law).
    law_pieces : set of int
        Indices (into ``pieces``) of the law's own pieces.
    y0, x0 : float, optional
        Given zero axis and origin (drawing units); they override what is found.
    join_tol : float
        The drawing's join tolerance (drawing units): pieces this close in height are collinear.

    Returns
    -------
    Baseline

    Examples
    --------
    A law drawn around y = 100 with a near and a far dwell, no axis line: the dwell level is the zero.

    >>> from camcad.io.dxf_read import Curve
    >>> pts = np.array([[0, 100], [90, 100], [135, 120], [180, 80], [225, 100], [270, 100],
    ...                 [315, 80], [360, 100]], dtype=float)
    >>> line = Curve(pts, "LWPOLYLINE", "2F", "0", editable=True, breakpoints=pts)
    >>> base = find_baseline(line, (), set())
    >>> base.y0, base.source
    (100.0, 'dwell')
    """
    pts = _x_order(np.asarray(curve.points, dtype=float))
    breakpoints = _x_order(np.asarray(curve.breakpoints if curve.breakpoints is not None else curve.points,
                                      dtype=float))
    xa, xb = float(pts[0, 0]), float(pts[-1, 0])
    span = max(xb - xa, 1e-300)
    y_low, y_high = float(pts[:, 1].min()), float(pts[:, 1].max())
    height = max(y_high - y_low, 1e-300)
    level_tol = max(join_tol, NOISE_FRACTION * height)
    notes: list[str] = []

    # dwell level: flat runs of the author's points
    runs = flat_runs(breakpoints, DWELL_MIN_FRACTION * span, level_tol)
    two_sided = [r for r in runs if y_high - r.level >= TWO_SIDED_FRACTION * height
                 and r.level - y_low >= TWO_SIDED_FRACTION * height]
    ends = [r for r in two_sided if r.first == 0 or r.last == len(breakpoints) - 1]
    dwell, dwell_how = None, ""
    if ends:
        if len(ends) == 2 and abs(ends[0].level - ends[1].level) <= AGREE_FRACTION * height:
            dwell = ends[0].level
            dwell_how = (f"the flat stretches at both ends (x {ends[0].x_start:.6g}..{ends[0].x_end:.6g} and "
                         f"{ends[1].x_start:.6g}..{ends[1].x_end:.6g})")
        else:
            longest = max(ends, key=lambda r: r.length)
            dwell, dwell_how = longest.level, f"the flat stretch at x {longest.x_start:.6g}..{longest.x_end:.6g}"
    elif two_sided:
        by_level: dict[int, float] = {}
        for r in two_sided:
            by_level[round(r.level / (AGREE_FRACTION * height))] = by_level.get(
                round(r.level / (AGREE_FRACTION * height)), 0.0) + r.length
        key = max(by_level, key=by_level.get)  # type: ignore[arg-type]  # typeshed: dict.get may give None
        longest = max((r for r in two_sided if round(r.level / (AGREE_FRACTION * height)) == key),
                      key=lambda r: r.length)
        dwell, dwell_how = longest.level, f"the flat stretch at x {longest.x_start:.6g}..{longest.x_end:.6g}"

    # axis lines: horizontal straight pieces spanning the law, within its height
    others = [i for i in range(len(pieces)) if i not in law_pieces and not pieces[i].hidden]
    reach = AXIS_REACH_FRACTION * span
    axes = [run for run in _horizontal_runs(pieces, others, max(join_tol, 1e-9 * height))
            if run[1] <= xa + reach and run[2] >= xb - reach
            and y_low - level_tol <= run[0] <= y_high + level_tol]
    axis, axis_how = None, ""
    if axes:
        if dwell is not None:
            near = min(axes, key=lambda run: abs(run[0] - dwell))
            if abs(near[0] - dwell) <= AGREE_FRACTION * height:
                axis, axis_how = near, "agreeing with the dwell level"
        if axis is None:
            if len(axes) == 1:
                axis, axis_how = axes[0], "the only horizontal line spanning the law"
            else:
                mean = _mean_height(pts)
                axis = min(axes, key=lambda run: abs(run[0] - mean))
                axis_how = f"of {len(axes)} horizontal lines spanning the law, the one nearest the curve's " \
                           f"mean height {mean:.6g}"

    source = "none"
    axis_pieces: tuple[int, ...] = ()
    if y0 is not None:
        value, source = float(y0), "given"
        notes.append(f"zero axis: y = {value:.9g} as given")
    elif axis is not None:
        value = axis[0]
        axis_pieces = tuple(axis[3])
        names = handles_text([f"{pieces[i].kind} {pieces[i].handle}" for i in axis[3]], 3)
        source = "axis+dwell" if axis_how.startswith("agreeing") else "axis"
        notes.append(f"zero axis: y = {value:.9g}, {names} (x {axis[1]:.6g}..{axis[2]:.6g}), {axis_how}; "
                     "--y0 overrides")
    elif dwell is not None and abs(dwell) <= AGREE_FRACTION * height:
        value, source = 0.0, "origin"
        notes.append("zero axis: y = 0 of the drawing (the dwells lie within 1 % of the curve's height of it)")
    elif dwell is not None:
        value, source = dwell, "dwell"
        notes.append(f"zero axis: y = {value:.9g}, the dwell level ({dwell_how}); no axis line spans the law; "
                     "--y0 overrides")
    else:
        value = 0.0
        notes.append("zero axis: none found (no horizontal line spans the law, no flat stretch at its ends): "
                     "y = 0 of the drawing is zero acceleration; pass --y0 Y to set it")
    if x0 is not None:
        notes.append(f"origin: x = {float(x0):.9g} as given (theta = 0 there)")
    if source in ("axis", "given") and dwell is not None and abs(dwell - value) > NEAR_ZERO_FRACTION * height:
        notes.append(f"warning: {dwell_how} lie{'' if 'stretches' in dwell_how else 's'} at y = {dwell:.6g}, "
                     f"{abs(dwell - value) / height:.0%} of the curve's height off the zero axis y = {value:.6g}; "
                     f"if that is a dwell, pass --y0 {dwell:.9g}")
    warnings, drawn_dwells = _dwell_warnings(curve, pts, runs, value, height, span, level_tol)
    notes.extend(warnings)
    zeros = tuple(sorted(float(bx) for piece in curve.pieces if piece.interpolating and piece.breakpoints is not None
                         for bx, by in piece.breakpoints if abs(by - value) <= level_tol))
    return Baseline(value, None if x0 is None else float(x0), source, tuple(notes), axis_pieces, drawn_dwells,
                    zeros)


def _overshoot(points: np.ndarray, breakpoints: np.ndarray, y0: float, level_tol: float,
               min_length: float) -> tuple[float, float, float, float] | None:
    """The largest departure from y0 of a piece between consecutive author's points lying at y0
    (a run of three or more such points, or two with the piece crossing y0 between them):
    (departure, x where, run start x, run end x), or None."""
    at_zero = np.abs(breakpoints[:, 1] - y0) <= level_tol
    worst = None
    i, n = 0, len(breakpoints)
    while i < n:
        if not at_zero[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and at_zero[j + 1]:
            j += 1
        x_lo, x_hi = breakpoints[i, 0], breakpoints[j, 0]
        inside = (points[:, 0] > x_lo) & (points[:, 0] < x_hi)
        if j > i and x_hi - x_lo >= min_length and inside.any():
            dev = points[inside, 1] - y0
            crosses = dev.max() > level_tol and dev.min() < -level_tol
            k = int(np.argmax(np.abs(dev)))
            size = float(abs(dev[k]))
            if (j - i >= 2 or crosses) and size > level_tol and (worst is None or size > worst[0]):
                worst = (size, float(points[inside][k, 0]), float(x_lo), float(x_hi))
        i = j + 1
    return worst


def _mean_height(pts: np.ndarray) -> float:
    """The curve's mean y over its x-range (trapezoids; vertical segments carry no weight)."""
    dx = np.diff(pts[:, 0])
    total = float(dx.sum())
    if total <= 0:
        return float(pts[:, 1].mean())
    return float(np.sum(dx * (pts[1:, 1] + pts[:-1, 1]) / 2) / total)


def _dwell_warnings(curve: Curve, pts: np.ndarray, runs: list[_Run], y0: float, height: float,
                    span: float, at_zero_tol: float) -> tuple[list[str], tuple[tuple[float, float], ...]]:
    """Warnings about dwells: flat stretches near but not at y0, and flattened pieces leaving y0
    between the author's dwell points; and the drawn dwells of interpolating splines that overshoot."""
    warnings: list[str] = []
    # flat stretches drawn near, but not at, the zero
    off = [(abs(r.level - y0), r) for r in runs
           if NOISE_FRACTION * height < abs(r.level - y0) <= NEAR_ZERO_FRACTION * height]
    if off:
        deviation, run = max(off, key=lambda t: t[0])
        side = "above" if run.level > y0 else "below"
        warnings.append(f"warning: {len(off)} dwell{'s are' if len(off) > 1 else ' is'} not at zero: the largest "
                        f"deviation is {deviation:.4g} {side} the zero axis ({deviation / height:.2%} of the curve's "
                        f"height) at x {run.x_start:.6g}..{run.x_end:.6g}; move the dwell onto the axis "
                        "(or set the zero with --y0)")
    # a flattened piece (spline, arc) leaving the zero between the author's dwell points on it
    level_tol = OVERSHOOT_FRACTION * height
    peak = float(np.max(np.abs(pts[:, 1] - y0))) or 1.0
    worst = None
    drawn: list[tuple[float, float]] = []
    for piece in curve.pieces:
        if piece.exact or piece.breakpoints is None:
            continue
        if piece.interpolating:
            found_all = interpolating_overshoots(_x_order(piece.points), _x_order(piece.breakpoints), y0,
                                                 at_zero_tol, INTERPOLATING_NOISE_FRACTION * height,
                                                 DWELL_MIN_FRACTION * span)
            drawn.extend((x_lo, x_hi) for _, _, x_lo, x_hi in found_all)
            found = max(found_all, default=None)
        else:
            found = _overshoot(_x_order(piece.points), _x_order(piece.breakpoints), y0, level_tol,
                               DWELL_MIN_FRACTION * span)
            if found is not None and found[0] >= LOBE_FRACTION * peak:
                found = None
        if found is not None and (worst is None or found[0] > worst[0]):
            worst = found + (piece,)
    if worst is not None:
        size, at, x_lo, x_hi, piece = worst
        what = "spline" if piece.kind == "SPLINE" else "curve"
        where = f"at x {x_lo:.6g}..{x_hi:.6g}" if len(drawn) <= 1 else \
            f"at x {x_lo:.6g}..{x_hi:.6g} (and {len(drawn) - 1} more)"
        then = "; the phases take the drawn dwell points" if drawn else ""
        warnings.append(f"warning: {piece.kind} {piece.handle} leaves the zero between the dwell points "
                        f"{where} by up to {size:.4g} ({size / peak:.1%} of the peak) at x "
                        f"{at:.6g}: your {what} overshoots through the dwell points{then}; draw the dwells as lines "
                        "or use a polyline")
    return warnings, tuple(sorted(drawn))


def interpolating_overshoots(points: np.ndarray, breakpoints: np.ndarray, y0: float, at_zero_tol: float,
                             noise: float, min_length: float) -> list[tuple[float, float, float, float]]:
    """Every run of two or more consecutive points of an interpolating spline at y0 (within
    ``at_zero_tol``, at least ``min_length`` long in x) that the spline leaves by more than ``noise``
    between them: (largest departure, x where, run start x, run end x), drawing units.

    Examples
    --------
    >>> pts = np.array([[0, 0], [5, -0.3], [10, 0], [15, 0.1], [20, 0], [25, 4], [30, 0]], dtype=float)
    >>> bps = np.array([[0, 0], [10, 0], [20, 0], [25, 4], [30, 0]], dtype=float)
    >>> interpolating_overshoots(pts, bps, 0.0, 1e-9, 1e-6, 1.0)
    [(0.3, 5.0, 0.0, 20.0)]
    """
    at_zero = np.abs(breakpoints[:, 1] - y0) <= at_zero_tol
    found = []
    i, n = 0, len(breakpoints)
    while i < n:
        if not at_zero[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and at_zero[j + 1]:
            j += 1
        x_lo, x_hi = float(breakpoints[i, 0]), float(breakpoints[j, 0])
        inside = (points[:, 0] > x_lo) & (points[:, 0] < x_hi)
        if j > i and x_hi - x_lo >= min_length and inside.any():
            dev = np.abs(points[inside, 1] - y0)
            k = int(np.argmax(dev))
            if dev[k] > noise:
                found.append((float(dev[k]), float(points[inside][k, 0]), x_lo, x_hi))
        i = j + 1
    return found


__all__ = ["Baseline", "find_baseline", "flat_runs", "interpolating_overshoots"]
