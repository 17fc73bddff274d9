"""From a file to a law: pick the curve, map it to the cycle, scale it, find its phases.

Conventions (SPEC.md "Acceleration-law input"):
- x is cam angle. A drawing's x-extent maps to one cycle [0, cycle_deg] unless ``x_deg`` says x is
  already degrees; a table's first column is always degrees.
- y is the acceleration analog; ``lift`` scales it so the rise equals ``lift`` mm, otherwise it is
  taken literally in mm/rad².
- A vertical segment is a jump of acceleration; duplicated vertices are ignored; a curve drawn
  right-to-left is accepted. The law starts from rest at s = 0 at θ = 0.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from camcad.errors import CamcadError
from camcad.io.dxf_read import Curve, CurveSet, Drawing, collect_curves, open_drawing
from camcad.io.table_read import TABLE_SUFFIXES, Table, read_table
from camcad.law.law import Phase, PiecewiseLinearLaw
from camcad.law.phases import detect_phases, parse_phases

#: relative tolerance (of the curve's x-range) below which x steps count as vertical or equal
X_TOLERANCE = 1e-9
#: two candidate curves whose x-ranges agree within this fraction are ambiguous
AMBIGUITY_FRACTION = 1e-6


@dataclass(frozen=True)
class VertexMap:
    """How the points of the drawn curve (drawing order) map onto the law's vertices.

    Point i of the curve corresponds to law vertex ``lo[i]`` when ``hi[i] == lo[i]``; a middle
    vertex of a vertical run lies at fraction ``weight[i]`` between law vertices ``lo[i]`` and ``hi[i]``.
    """

    lo: np.ndarray
    hi: np.ndarray
    weight: np.ndarray

    def ordinates(self, law_values: np.ndarray) -> np.ndarray:
        return law_values[self.lo] + self.weight * (law_values[self.hi] - law_values[self.lo])


@dataclass(frozen=True)
class LoadedLaw:
    """A law read from a file, with everything needed to report on it and write it back.

    a_law = y_input × ``y_scale``;  θ = (x − x_min)/(x_max − x_min) × cycle  (x in drawing units).
    """

    law: PiecewiseLinearLaw
    path: Path
    source: str
    notes: tuple[str, ...]
    y_scale: float
    x_min: float
    x_max: float
    phases_given: bool
    vertex_map: VertexMap
    curve: Curve | None = None
    drawing: Drawing | None = None
    table: Table | None = None
    candidates: int = 1
    extra: dict = field(default_factory=dict)

    def theta_to_x(self, theta: np.ndarray) -> np.ndarray:
        return self.x_min + np.asarray(theta) / self.law.cycle * (self.x_max - self.x_min)

    def a_to_y(self, a: np.ndarray) -> np.ndarray:
        return np.asarray(a) / self.y_scale


def load_law(path: str | Path, *, layer: str | None = None, handle: str | None = None,
             cycle_deg: float = 360.0, lift: float | None = None, phases: str | tuple[Phase, ...] | None = None,
             x_deg: bool = False, flatten_tol: float | None = None, join_tol: float | None = None) -> LoadedLaw:
    """Read the acceleration law of a DXF drawing or a table file (see the module docstring).

    Parameters
    ----------
    layer, handle : pick the curve (DXF); otherwise the curve spanning the largest x-range.
    cycle_deg : the working angle the curve spans (deg).
    lift : scale the law so its rise equals ``lift`` mm; None keeps y literally (mm/rad²).
    phases : "0:90:rise,90:180:dwell,..." (deg) or Phase tuple; None detects them.
    x_deg : the drawing's x is already the cam angle in degrees (it must span [0, cycle_deg]).
    flatten_tol, join_tol : SPLINE/arc flattening and LINE-chain joining tolerances (drawing units).
    """
    path = Path(path)
    if not np.isfinite(cycle_deg) or not 0 < cycle_deg <= 360.0:
        raise CamcadError(f"cycle {cycle_deg:g} deg is not in (0, 360]", "--cycle", "give the working angle in degrees")
    if lift is not None and not (np.isfinite(lift) and lift > 0):
        raise CamcadError(f"lift {lift:g} mm must be positive", "--lift", "give the rise in mm")
    if _is_table(path):
        return _from_table(path, cycle_deg, lift, phases)
    drawing = open_drawing(path)
    curve_set = collect_curves(drawing, flatten_tol=flatten_tol, join_tol=join_tol)
    curve, choice_note, candidates = select_curve(curve_set, str(path), layer=layer, handle=handle)
    notes = list(drawing.notes) + list(curve_set.notes) + [choice_note]
    if not curve.editable:
        notes.append(f"{curve.kind} {curve.handle} flattened to {len(curve.points)} points "
                     f"(tolerance {curve.flatten_tol:.3g} drawing units)")
    return _build(path, curve.points, cycle_deg, lift, phases, x_deg, notes,
                  where=f"{path}, {curve.label}", curve=curve, drawing=drawing, candidates=candidates)


def _is_table(path: Path) -> bool:
    if path.suffix.lower() in TABLE_SUFFIXES:
        return True
    if path.suffix.lower() == ".dxf" or not path.exists() or path.is_dir():
        return False
    head = path.read_bytes()[:2048]
    return b"SECTION" not in head and b"AutoCAD Binary DXF" not in head


def _from_table(path: Path, cycle_deg: float, lift: float | None, phases) -> LoadedLaw:
    table = read_table(path)
    theta, accel = table.theta_deg, table.accel
    notes = list(table.notes)
    where = str(path)
    if len(theta) < 3:
        raise CamcadError(f"the table has {len(theta)} rows; a law needs at least 3", where,
                          "give the acceleration over the whole cycle")
    tol = 1e-6 * cycle_deg
    if abs(theta[0]) > tol:
        raise CamcadError(f"the table starts at {theta[0]:g} deg, not 0", where,
                          "start the table at 0 deg (shift the angles), or use --cycle")
    steps = np.diff(theta)
    typical = float(np.median(steps[steps > 0])) if np.any(steps > 0) else 0.0
    gap = cycle_deg - theta[-1]
    if gap < -tol:
        raise CamcadError(f"the table runs to {theta[-1]:g} deg, past the cycle of {cycle_deg:g}", where,
                          f"end the table at {cycle_deg:g} deg or pass --cycle {theta[-1]:g}")
    points = np.column_stack((theta, accel))
    if gap > tol:
        if gap <= 1.5 * typical:
            points = np.vstack((points, [cycle_deg, accel[0]]))
            notes.append(f"the table ends at {theta[-1]:g} deg; closed periodically with a({cycle_deg:g}) = a(0)")
        else:
            raise CamcadError(f"the table covers 0..{theta[-1]:g} deg, not the cycle 0..{cycle_deg:g}", where,
                              f"add rows up to {cycle_deg:g} deg, or pass --cycle {theta[-1]:g}")
    loaded = _build(path, points, cycle_deg, lift, phases, True, notes, where=where)
    return replace(loaded, table=table, source=f"table {path.name}, {len(theta)} rows")


def select_curve(curve_set: CurveSet, where: str, layer: str | None = None,
                 handle: str | None = None) -> tuple[Curve, str, int]:
    """The curve holding the law: by handle, else the largest x-range among law-like curves (of a layer)."""
    curves = list(curve_set.curves)
    if handle is not None:
        wanted = handle.strip().upper()
        match = [c for c in curves if wanted in (h.upper() for h in c.handles)]
        if not match:
            raise CamcadError(f"no curve with handle {handle}", where,
                              f"curve handles here: {_handles_text(curves)}")
        curve = match[0]
        problem = law_problem(curve)
        if problem:
            raise CamcadError(problem, f"{where}, {curve.label}", _problem_fix(problem))
        return curve, f"law: {curve.label}, chosen by --handle", 1
    if layer is not None:
        on_layer = [c for c in curves if c.layer.upper() == layer.upper()]
        if not on_layer:
            layers = sorted({c.layer for c in curves})
            raise CamcadError(f"no curve on layer {layer}", where,
                              f"layers with curves: {', '.join(layers) or 'none'}")
        curves = on_layer
    else:
        # curves on layers that are off or frozen (camcad's kept originals among them) are not
        # candidates unless asked for by --layer or --handle
        visible = [c for c in curves if not c.hidden]
        if visible:
            curves = visible
    if not curves:
        skipped = [n for n in curve_set.notes if " skipped: " in n]
        why = f" ({skipped[0]})" if skipped else ""
        raise CamcadError(f"no curve found{why}", where,
                          f"the drawing holds {_counts_text(curve_set)}; draw the law as a polyline, "
                          "a chain of lines or a spline")
    lawlike = [c for c in curves if not law_problem(c)]
    open_curves = sorted((c for c in curves if not c.closed and not _straight(c.points)),
                         key=lambda c: c.x_range, reverse=True)
    if not lawlike:
        best = open_curves[0] if open_curves else max(curves, key=lambda c: c.x_range)
        problem = law_problem(best)
        raise CamcadError(f"no curve here can be a law; the largest, {best.label}: {problem}", where,
                          _problem_fix(problem))
    lawlike.sort(key=lambda c: (c.x_range, len(c.points)), reverse=True)
    chosen = lawlike[0]
    # a larger open curve that is not a function of x is more likely the intended, mis-drawn law
    if open_curves and open_curves[0].x_range > chosen.x_range * (1 + AMBIGUITY_FRACTION) \
            and open_curves[0] is not chosen:
        bigger = open_curves[0]
        problem = law_problem(bigger)
        raise CamcadError(f"the widest curve, {bigger.label}, cannot be a law: {problem}", where,
                          f"{_problem_fix(problem)}, or pick another curve with --handle {chosen.handle}")
    rivals = [c for c in lawlike[1:] if abs(c.x_range - chosen.x_range) <= AMBIGUITY_FRACTION * chosen.x_range]
    if rivals:
        names = ", ".join(c.handle for c in [chosen] + rivals)
        scope = f"layer {layer}" if layer else "the drawing"
        raise CamcadError(f"{scope} holds {len(rivals) + 1} curves spanning the same x-range (handles {names})",
                          where, "pick one with --handle" + ("" if layer else " or --layer"))
    how = "the only law-like curve" if len(lawlike) == 1 else \
        f"the curve spanning the largest x-range of {len(lawlike)} candidates"
    return chosen, f"law: {chosen.label}, {how}", len(lawlike)


def law_problem(curve: Curve) -> str:
    """Why a curve cannot be a law (empty string when it can)."""
    points = curve.points
    if curve.closed:
        return "it is closed"
    if len(points) < 3:
        return f"it has {len(points)} vertices; a law needs at least 3"
    distinct = _dedupe_mask(points)
    if int(distinct.sum()) < 3:
        return f"it has {int(distinct.sum())} distinct vertices; a law needs at least 3"
    x = points[:, 0]
    span = np.ptp(x)
    if span <= 0:
        return "it has no extent in x (it is vertical)"
    direction = 1.0 if x[-1] >= x[0] else -1.0
    steps = np.diff(x) * direction
    back = np.flatnonzero(steps < -X_TOLERANCE * span)
    if len(back):
        i = int(back[0]) + 1
        if direction < 0:
            return f"it goes back in x at vertex {i} (x {x[i]:.6g} after {x[i - 1]:.6g}, drawn right to left)"
        return f"it goes back in x at vertex {i} (x {x[i]:.6g} after {x[i - 1]:.6g})"
    if _straight(points):
        return "it is a straight line (an axis or a grid line, not a law)"
    return ""


def _problem_fix(problem: str) -> str:
    if "goes back" in problem:
        return "move that vertex so x never decreases along the curve (a vertical segment is a jump)"
    if "vertices" in problem:
        return "draw the law with at least 3 vertices"
    if "closed" in problem:
        return "draw the law as an open curve from the start to the end of the cycle"
    return "pick the law with --handle or --layer"


def _straight(points: np.ndarray) -> bool:
    if len(points) < 3:
        return True
    d = points - points[0]
    chord = points[-1] - points[0]
    norm = np.hypot(*chord)
    if norm == 0:
        return False
    deviation = np.abs(d[:, 0] * chord[1] - d[:, 1] * chord[0]) / norm
    return bool(deviation.max() <= 1e-9 * max(norm, np.ptp(points[:, 1])))


def _dedupe_mask(points: np.ndarray) -> np.ndarray:
    span = max(np.ptp(points[:, 0]), 1e-300)
    yspan = max(np.ptp(points[:, 1]), 1e-300)
    keep = np.ones(len(points), dtype=bool)
    keep[1:] = (np.abs(np.diff(points[:, 0])) > X_TOLERANCE * span) | \
               (np.abs(np.diff(points[:, 1])) > 1e-12 * yspan)
    return keep


def _handles_text(curves: list[Curve]) -> str:
    text = ", ".join(f"{c.handle} ({c.kind}, layer {c.layer})" for c in curves[:8])
    return text + (" ..." if len(curves) > 8 else "") if text else "none"


def _counts_text(curve_set: CurveSet) -> str:
    if not curve_set.entity_counts:
        return "no entities"
    return ", ".join(f"{n} {kind}" for kind, n in sorted(curve_set.entity_counts.items()))


def _build(path: Path, points: np.ndarray, cycle_deg: float, lift: float | None, phases, x_deg: bool,
           notes: list[str], where: str, curve: Curve | None = None, drawing: Drawing | None = None,
           candidates: int = 1) -> LoadedLaw:
    points = np.asarray(points, dtype=float)
    if not np.isfinite(points).all():
        index = int(np.flatnonzero(~np.isfinite(points).all(axis=1))[0])
        raise CamcadError(f"vertex {index} has a non-finite coordinate", where, "fix or delete that vertex")
    order = np.arange(len(points))
    if len(points) >= 2 and points[-1, 0] < points[0, 0]:
        order = order[::-1]
        notes.append("the curve is drawn right to left; read left to right")
    pts = points[order]
    x, y = pts[:, 0].copy(), pts[:, 1].copy()
    span = float(np.ptp(x))
    if span <= 0:
        raise CamcadError("the curve has no extent in x", where, "draw the law along the angle axis")
    back = np.flatnonzero(np.diff(x) < -X_TOLERANCE * span)
    if len(back):
        i = int(order[back[0] + 1])
        raise CamcadError(f"vertex {i} goes back in x (x {points[i, 0]:.6g})", where,
                          "move that vertex so x never decreases along the curve (a vertical segment is a jump)")
    # snap x steps below the tolerance: they are vertical segments drawn a hair off
    x = np.maximum.accumulate(x)
    small = np.diff(x) <= X_TOLERANCE * span
    x[1:][small] = x[:-1][small]
    keep, lo, hi, weight = _vertex_structure(x, y)
    dropped = len(x) - int(keep.sum())
    if dropped:
        notes.append(f"{dropped} duplicated or redundant vertices ignored")
    kept = np.flatnonzero(keep)
    if len(kept) < 3:
        raise CamcadError(f"the curve has {len(kept)} distinct vertices; a law needs at least 3", where,
                          "draw the law with at least 3 vertices")
    new_index = np.cumsum(keep) - 1
    # map back to drawing order
    lo_law = np.empty(len(points), dtype=int)
    hi_law = np.empty(len(points), dtype=int)
    w_law = np.empty(len(points))
    lo_law[order] = new_index[lo]
    hi_law[order] = new_index[hi]
    w_law[order] = weight
    xk, yk = x[kept], y[kept]
    x_min, x_max = float(xk[0]), float(xk[-1])
    cycle = float(np.radians(cycle_deg))
    if x_deg:
        tol = 1e-6 * cycle_deg
        if abs(x_min) > tol or abs(x_max - cycle_deg) > tol:
            raise CamcadError(f"the curve covers x {x_min:g}..{x_max:g} deg, not the cycle 0..{cycle_deg:g}", where,
                              f"extend the curve to the whole cycle, or pass --cycle {x_max - x_min:g}")
        x_min, x_max = 0.0, float(cycle_deg)
    theta = (xk - x_min) / (x_max - x_min) * cycle
    theta[0], theta[-1] = 0.0, cycle
    if isinstance(phases, str):
        phase_tuple = parse_phases(phases, cycle_deg)
    elif phases:
        phase_tuple = tuple(phases)
    else:
        phase_tuple = detect_phases(theta, yk, cycle, where)
    law = PiecewiseLinearLaw(theta, yk, cycle, phase_tuple)
    y_scale = 1.0
    if lift is not None:
        rise = rise_displacement(law)
        if not rise > 0:
            raise CamcadError(f"the drawn law has no positive rise ({rise:.4g}), so it cannot be scaled to a lift",
                              where, "check the sign of the acceleration, or give --phases")
        y_scale = lift / rise
        law = law.with_ordinates(yk * y_scale)
        notes.append(f"y scaled by {y_scale:.6g} so the rise is {lift:g} mm")
    source = f"{where}, {len(kept)} vertices, x {x_min:g}..{x_max:g} -> 0..{cycle_deg:g} deg"
    return LoadedLaw(law=law, path=path, source=source, notes=tuple(notes), y_scale=y_scale,
                     x_min=x_min, x_max=x_max, phases_given=bool(phases),
                     vertex_map=VertexMap(lo_law, hi_law, w_law), curve=curve, drawing=drawing,
                     candidates=candidates)


def _vertex_structure(x: np.ndarray, y: np.ndarray):
    """Which points become law vertices, and how each point maps onto them.

    Consecutive duplicates are dropped (mapped onto the kept twin); in a run of three or more
    points at the same x only the first and last matter to a(θ): the middle ones are dropped and
    mapped by their fraction along the vertical segment.
    """
    n = len(x)
    yspan = max(float(np.ptp(y)), 1e-300)
    keep = np.ones(n, dtype=bool)
    lo = np.arange(n)
    hi = np.arange(n)
    weight = np.zeros(n)
    # a point alone at its x is kept as it is; only runs of equal x need a look (a drawn law may
    # have a million vertices and a handful of jumps)
    repeated = np.flatnonzero(x[1:] == x[:-1])
    run_starts = repeated[np.concatenate(([True], np.diff(repeated) > 1))] if len(repeated) else repeated
    for start in run_starts:
        end = start
        while end + 1 < n and x[end + 1] == x[start]:
            end += 1
        run = np.arange(start, end + 1)
        # inside a run at one x: drop exact duplicates of the previous point
        last_kept = start
        for i in run[1:]:
            if abs(y[i] - y[last_kept]) <= 1e-12 * yspan:
                keep[i] = False
                lo[i] = hi[i] = last_kept
            else:
                last_kept = i
        kept_run = run[keep[run]]
        if len(kept_run) >= 3:
            first, last = kept_run[0], kept_run[-1]
            for i in kept_run[1:-1]:
                keep[i] = False
                lo[i], hi[i] = first, last
                weight[i] = (y[i] - y[first]) / (y[last] - y[first]) if y[last] != y[first] else 0.0
            for i in run:
                if not keep[i] and lo[i] == hi[i] and not keep[lo[i]]:
                    lo[i] = hi[i] = first if abs(y[i] - y[first]) <= abs(y[i] - y[last]) else last
    return keep, lo, hi, weight


def rise_displacement(law: PiecewiseLinearLaw) -> float:
    """Sum of s(end) − s(start) over the rise phases (mm), exact."""
    total = 0.0
    for phase in law.phases:
        if phase.kind == "rise":
            s = law.kinematics(np.array([phase.start, phase.end])).s
            total += float(s[1] - s[0])
    return total


__all__ = ["LoadedLaw", "VertexMap", "load_law", "select_curve", "law_problem", "rise_displacement"]
