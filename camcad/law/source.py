"""From a file to a law: pick the curve, find its zero axis, map it to the cycle, scale it, find its phases.

Conventions (docs/INTERFACE.md "Acceleration-law input", docs/reading.md):
- The law's curve is the widest chain of drawn pieces that is a function of x (``io.chain``);
  its zero axis and origin are found in the drawing (``law.baseline``) unless ``y0``/``x0`` say.
- x is cam angle. The curve's x-extent maps to one cycle [0, cycle_deg] (from ``x0`` when given)
  unless ``x_deg`` says x is already degrees (θ = x − x0); a table's first column is always degrees.
- y is the acceleration analog: a = (y − y0) × scale; ``lift`` scales it so the rise equals
  ``lift`` mm, otherwise the scale is 1 (mm/rad² per drawing unit). Drawing units are reported,
  never converted.
- A curve that holds a rise without a return (or a return without a rise), ending at rest, is a
  drawing of part of a cycle; unless the cycle is stated (``cycle_deg``, ``x_deg`` or ``phases``)
  it is refused with the options that state it, never silently stretched to 360°.
- A vertical segment is a jump of acceleration; duplicated vertices are ignored; a curve drawn
  right-to-left is accepted. The law starts from rest at s = 0 at θ = 0.
- A table names its kind in its header (``camcad.io.table_read``): an acceleration is read as drawn; a
  displacement, a swing, or a cam profile's radius-vectors (through the ``follower`` given) become a law
  by the batten study's smoothing (``camcad.law.motion_table``).
- A law camcad wrote carries its record (``camcad.io.law_record``): its phases are restored from it (with
  a note) unless ``phases`` is given, and ``camcad check`` judges it by the rule recorded.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from camcad.arrays import unique
from camcad.errors import CamcadError
from camcad.io.chain import find_law
from camcad.io.dxf_read import (
    LENGTH_UNITS,
    Curve,
    Drawing,
    collect_pieces,
    curve_entities,
    handles_text,
    open_drawing,
    units_note,
)
from camcad.io.input_file import is_regular_file, read_input
from camcad.io.law_record import LawRecord, record_of_entity, vertex_digest
from camcad.io.table_read import TABLE_SUFFIXES, Table, read_table
from camcad.law.baseline import Baseline, find_baseline
from camcad.law.law import Phase, PiecewiseLinearLaw
from camcad.law.motion_table import MotionTableLaw, ProfileFollower, motion_law, radius_to_motion
from camcad.law.phases import parse_phases, read_phases

#: the largest lift camcad takes (mm, or deg of swing): larger is a typing mistake
MAX_LIFT = 1e6
#: relative tolerance (of the curve's x-range) below which x steps count as vertical or equal
X_TOLERANCE = 1e-9
#: a rise (or return) whose end velocity is within this fraction of its peak velocity ends at rest
PART_CYCLE_REST_FRACTION = 0.05


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

    a_law = (y_input − ``y0``) × ``y_scale``;  θ = (x − x_min)/(x_max − x_min) × cycle  (x in drawing
    units; ``x_min`` is the drawing x of θ = 0, ``x_max`` that of θ = cycle). ``theta_to_x`` and
    ``a_to_y`` map back to drawing coordinates exactly (the writers use them). Returned by
    ``load_law``; users read it rather than build it.

    Attributes
    ----------
    law : PiecewiseLinearLaw
        The law: knots ``law.x`` in rad of cam angle, ordinates ``law.a`` in mm/rad² (with ``lift``
        given; otherwise drawing units of y per rad²), its ``phases`` (rad) and ``cycle`` (rad).
    path : Path
        The file it was read from.
    source : str
        One line saying which curve (or table) it is, its vertex count and x range.
    notes : tuple of str
        Every decision taken while reading (curve chosen, axis found, scaling), in words.
    y_scale : float
        The factor from drawing y to the law's a: mm/rad² per drawing unit (1.0 without ``lift``).
    x_min, x_max : float
        Drawing x (drawing units) of θ = 0 and of θ = cycle.
    phases_given : bool
        The phases were given (``phases``) rather than detected.
    vertex_map : VertexMap
        How each drawn point maps onto the law's vertices (duplicates and vertical runs folded).
    curve : Curve or None
        The drawn curve (DXF input), None for a table.
    drawing : Drawing or None
        The opened drawing (DXF input), None for a table.
    table : Table or None
        The table read (table input), None for a drawing.
    candidates : int
        How many curves could have been the law (the widest one is taken unless picked).
    extra : dict
        Further facts for the report (free-form keys, no unit).
    y0 : float
        Drawing y of a = 0 (drawing units), found in the drawing unless given.
    baseline : Baseline or None
        The zero axis and origin found in the drawing, with how they were found.
    length_unit : str
        The unit of the law's lengths: "mm", or the drawing's "in" or "cm" ($INSUNITS 1, 5) when no ``lift``
        scales it; ``law.a`` is then in that unit per rad² (``mm_per_unit`` converts it).
    mm_per_unit : float
        mm per ``length_unit`` (1.0, 25.4 or 10.0).
    record : LawRecord or None
        camcad's record in the file (a law camcad wrote): its phases, unit and the rule it was judged by.
    phases_from_record : bool
        The phases were restored from ``record``.
    motion : MotionTableLaw or None
        A motion table's smoothing (fit residual, oscillation removed, balance change), None otherwise.
    unit : str or None
        Unit of the law's displacement when the file says it (a swing table: "deg" or "rad"; a record);
        None: mm unless the command is told otherwise.
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
    y0: float = 0.0
    baseline: Baseline | None = None
    length_unit: str = "mm"
    mm_per_unit: float = 1.0
    record: LawRecord | None = None
    phases_from_record: bool = False
    motion: MotionTableLaw | None = None
    unit: str | None = None

    @property
    def x0(self) -> float:
        """Drawing x of θ = 0 (the origin's x)."""
        return self.x_min

    def theta_to_x(self, theta: np.ndarray) -> np.ndarray:
        """Drawing x of cam angles θ (rad)."""
        return self.x_min + np.asarray(theta) / self.law.cycle * (self.x_max - self.x_min)

    def a_to_y(self, a: np.ndarray) -> np.ndarray:
        """Drawing y of accelerations a (mm/rad²): a / y_scale + y0."""
        return np.asarray(a) / self.y_scale + self.y0


def load_law(path: str | Path, *, layer: str | None = None, handle: str | None = None,
             cycle_deg: float | None = None, lift: float | None = None,
             phases: str | tuple[Phase, ...] | None = None, x_deg: bool = False,
             flatten_tol: float | None = None, join_tol: float | None = None,
             y0: float | None = None, x0: float | None = None, follower: ProfileFollower | None = None,
             smoothing: float | None = None, accel_smoothing: str | float = "gcv") -> LoadedLaw:
    """Read the acceleration law of a DXF drawing or a table file (see the module docstring).

    Parameters
    ----------
    path : str or Path
        A DXF drawing, or a .csv/.txt table of θ (deg) and a.
    layer, handle : str, optional
        Pick the curve (DXF): only pieces on ``layer``; the chain through the entity ``handle``.
    cycle_deg : float, optional
        The working angle the curve spans (deg); None: 360, and a curve that is not a whole
        cycle (a rise without a return) is refused rather than stretched.
    lift : float, optional
        Scale the law so its rise equals ``lift`` mm; None keeps y (mm/rad² per drawing unit).
    phases : str or tuple of Phase, optional
        "0:90:rise,90:180:dwell,..." (deg) or Phase tuple; None detects them.
    x_deg : bool
        The drawing's x is the cam angle in degrees from the origin (θ = x − x0).
    flatten_tol, join_tol : float, optional
        SPLINE/arc flattening and end-to-end joining tolerances (drawing units).
    y0, x0 : float, optional
        The zero axis (drawing y of a = 0) and the origin's x (θ = 0); found in the drawing when None.
    follower : ProfileFollower, optional
        The follower of a radius-vector table (``theta_deg,r_mm``); such a table is refused without it.
    smoothing : float, optional
        A motion table's measurement error (its unit): the quintic spline's smoothing for it; None: chosen
        by generalised cross-validation.
    accel_smoothing : str or float
        A motion table's second derivative smoothed again by a cubic spline: "gcv", "none", or the stated
        error of a (unit per rad²).

    Returns
    -------
    LoadedLaw
        The law (θ in rad, a in mm/rad² — or drawing units of y per rad² without ``lift``) and how
        it maps to the file; ``notes`` say every decision taken.

    Raises
    ------
    CamcadError
        Bad input: one line saying what, where and how to fix.

    See Also
    --------
    camcad.check : the area balance of the law read.

    References
    ----------
    O. M. Dupliak, R. I. Kotsiyba, "Methods for optimization of the cam mechanisms modeling",
    Khmelnytsky National University (2018): the acceleration analog drawn in CAD and
    read from DXF. camcad's reading rules are in ``docs/reading.md``.

    Examples
    --------
    A table of θ (deg) and a: a triangular lobe up and one down for the rise (0–180°), the mirror
    image for the return. By hand, a lobe of height A and base π/2 rad followed by its negative gives
    the rise s = Aπ²/8, so the scale to a 10 mm lift is 80/π² mm/rad² per unit of the table's a:

    >>> import math, tempfile, pathlib
    >>> import camcad
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> rows = [(0, 0), (45, 1), (90, 0), (135, -1), (180, 0), (225, -1), (270, 0), (315, 1), (360, 0)]
    >>> _ = (folder / "law.csv").write_text("".join(f"{t},{a}\\n" for t, a in rows))
    >>> loaded = camcad.load_law(folder / "law.csv", lift=10.0)
    >>> round(loaded.y_scale * math.pi**2, 9)
    80.0
    >>> [(p.kind, math.degrees(p.start), math.degrees(p.end)) for p in loaded.law.phases]
    [('rise', 0.0, 180.0), ('return', 180.0, 360.0)]
    >>> loaded.notes
    ('y scaled by 8.10569 so the rise is 10 mm',)
    """
    path = Path(path)
    cycle_stated = cycle_deg is not None
    cycle_deg = 360.0 if cycle_deg is None else float(cycle_deg)
    if not np.isfinite(cycle_deg) or not 0 < cycle_deg <= 360.0:
        raise CamcadError(f"cycle {cycle_deg:g} deg is not in (0, 360]", "--cycle", "give the working angle in degrees")
    if lift is not None and not (np.isfinite(lift) and 0 < lift <= MAX_LIFT):
        raise CamcadError(f"lift {lift:g} mm must be positive and at most {MAX_LIFT:g}", "--lift",
                          "give the rise in mm")
    for name, value in (("--y0", y0), ("--x0", x0)):
        if value is not None and not (np.isfinite(value) and abs(value) < 1e100):
            raise CamcadError(f"{name} {value:g} is not a finite coordinate", name, "give the drawing coordinate")
    if path.suffix.lower() == ".toml":
        raise CamcadError("this is a scene file, not a drawn law", str(path),
                          "give a drawing (.dxf) or a table (.csv, .txt); a scene runs with camcad profile SCENE")
    if _is_table(path):
        return _from_table(path, cycle_deg, lift, phases, y0, x0, follower, smoothing, accel_smoothing)
    drawing = open_drawing(path)
    piece_set = collect_pieces(drawing, flatten_tol=flatten_tol)
    chain = find_law(piece_set, str(path), layer=layer, handle=handle, join_tol=join_tol)
    curve = chain.curve
    used = set(chain.used)
    baseline = find_baseline(curve, chain.graph.pieces, used, y0=y0, x0=x0, join_tol=chain.graph.join_tol)
    notes = list(drawing.notes) + list(piece_set.notes) + list(chain.notes)
    left_out = [chain.graph.pieces[i] for i in chain.left_out]
    if left_out:
        notes.append(f"left out as axis or grid lines: {len(left_out)} straight piece"
                     f"{'s' if len(left_out) > 1 else ''} ({_pieces_text(left_out)})")
    notes.extend(baseline.notes)
    notes.append(units_note(drawing, scaled=lift is not None))
    x_tol = chain.graph.join_tol if len(curve.pieces) > 1 else 0.0
    record = _drawing_record(drawing, curve, notes)
    if record is not None and not cycle_stated and phases is None:
        cycle_deg, cycle_stated = record.cycle_deg, True    # the law camcad wrote covers the cycle it recorded
    try:
        return _build(path, curve.points, cycle_deg, lift, phases, x_deg, notes, where=f"{path}, {curve.label}",
                      curve=curve, drawing=drawing, candidates=chain.candidates, y0=baseline.y0, x0=baseline.x0,
                      x_tol=x_tol, cycle_stated=cycle_stated, baseline=baseline, record=record)
    except CamcadError as err:
        if not chain.gap_fix:
            raise
        # the law read is only part of the drawn one: the gap is the likelier cause than what went wrong
        raise CamcadError(err.what, err.where, chain.gap_fix) from None


def _pieces_text(pieces) -> str:
    kinds = sorted({p.kind for p in pieces})
    return f"{'/'.join(kinds)} {handles_text([p.handle for p in pieces], 4)}"


def _is_table(path: Path) -> bool:
    """A table by its suffix; a file of another suffix by its content (no DXF section marker).
    Only a regular file is looked into (a FIFO would block); anything else goes to the DXF
    reader, which refuses it with one clear line."""
    if path.suffix.lower() in TABLE_SUFFIXES:
        return True
    if path.suffix.lower() == ".dxf" or not is_regular_file(path):
        return False
    head = read_input(path)[:4096]
    if head[:2] in (b"\xff\xfe", b"\xfe\xff") or b"\x00" in head[:64]:
        head = head.replace(b"\x00", b"")
    return b"SECTION" not in head and b"AutoCAD Binary DXF" not in head


def _drawing_record(drawing: Drawing, curve: Curve, notes: list[str]) -> LawRecord | None:
    """camcad's record on the law's entities (the first one that has it), with a note when the curve
    differs from the one camcad wrote; None when there is none (or it cannot be read: a note says so)."""
    for entity in curve_entities(drawing.doc, curve):
        if entity is None:
            continue
        try:
            record = record_of_entity(entity)
        except ValueError as err:
            notes.append(f"camcad's record on {entity.dxftype()} {entity.dxf.get('handle', '?')} cannot be "
                         f"read ({err}); ignored")
            return None
        if record is None:
            continue
        if record.vertices is not None and (record.vertices != len(curve.points) or (
                record.digest is not None and record.digest != vertex_digest(curve.points))):
            notes.append(f"the curve was changed after {record.writer} wrote it ({len(curve.points)} vertices, "
                         f"{record.vertices} written): its recorded phases are still used; check them or give "
                         "--phases")
        return record
    return None


def _record_phases(record: LawRecord | None, phases, cycle_deg: float, notes: list[str], where: str):
    """(phases to use, taken from the record?) — the given phases first, then the record's."""
    if record is None:
        return phases, False
    if phases:
        notes.append(f"the phases recorded by {record.writer} ({record.phases}) are overridden by the phases given")
        return phases, False
    if abs(record.cycle_deg - cycle_deg) > 1e-9 * cycle_deg:
        notes.append(f"the phases recorded by {record.writer} are for a cycle of {record.cycle_deg:g} deg, not "
                     f"{cycle_deg:g}: ignored, the phases are detected")
        return phases, False
    try:
        restored = parse_phases(record.phases, cycle_deg, where=f"{where} (camcad's record)")
    except CamcadError as err:
        notes.append(f"the phases recorded by {record.writer} cannot be used ({err.what}): the phases are detected")
        return phases, False
    notes.append(f"phases restored from camcad's record in the file ({record.writer}): {record.phases}")
    return restored, True


def _from_table(path: Path, cycle_deg: float, lift: float | None, phases, y0: float | None = None,
                x0: float | None = None, follower: ProfileFollower | None = None, smoothing: float | None = None,
                accel_smoothing: str | float = "gcv") -> LoadedLaw:
    table = read_table(path)
    if table.kind != "acceleration":
        return _from_motion_table(path, table, cycle_deg, lift, phases, follower, smoothing, accel_smoothing)
    theta, accel = table.theta_deg, table.accel
    notes = list(table.notes)
    where = str(path)
    if x0 is not None:
        notes.append("--x0 applies to drawings; a table's angles are degrees from 0, taken as they are")
    if y0 is not None:
        accel = accel - y0
        notes.append(f"accelerations taken relative to {y0:g} (--y0)")
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
    if y0 is not None:
        points[:, 1] += y0  # _build takes the zero off again, so a_to_y gives the table's own values back
    loaded = _build(path, points, cycle_deg, lift, phases, True, notes, where=where, x0=0.0, cycle_stated=True,
                    y0=float(y0 or 0.0), record=table.record)
    return replace(loaded, table=table, source=f"table {path.name}, {len(theta)} rows")


def _from_motion_table(path: Path, table: Table, cycle_deg: float, lift: float | None, phases,
                       follower: ProfileFollower | None, smoothing: float | None,
                       accel_smoothing: str | float) -> LoadedLaw:
    """A displacement, swing or radius-vector table → the smoothed, balanced law (camcad.law.motion_table)."""
    where = str(path)
    notes = list(table.notes)
    theta, values = table.theta_deg, table.values
    unit = {"displacement": "mm", "swing_deg": "deg", "swing_rad": "rad", "radius": "mm"}[table.kind]
    if table.kind == "radius":
        if follower is None:
            raise CamcadError("a table of radius-vectors (r_mm) needs its follower to become a motion", where,
                              "name the follower: in a scene's [follower], or --follower roller|oscillating --rr R "
                              "[--offset E] [--pivot C --arm L]")
        theta, values, figures = radius_to_motion(theta, values, follower, cycle_deg, where=where)
        unit = figures["unit"]
        notes.append(f"radius-vectors turned into the motion of the {follower.describe()} (profile base radius "
                     f"{figures['base_radius_mm']:.6g} mm); the motion is in {unit}")
    stated = parse_phases(phases, cycle_deg) if isinstance(phases, str) else (tuple(phases) if phases else None)
    record_phases, from_record = _record_phases(table.record, stated, cycle_deg, notes, where)
    motion = motion_law(theta, values, cycle_deg, unit=unit, kind=table.kind, sigma=smoothing,
                        accel_smoothing=accel_smoothing, phases=record_phases, where=where)
    notes.extend(motion.notes)
    points = np.column_stack((np.degrees(motion.x), motion.a))
    loaded = _build(path, points, cycle_deg, lift, motion.phases, True, notes, where=where, x0=0.0,
                    cycle_stated=True)
    return replace(loaded, table=table, source=f"table {path.name}, {len(table.theta_deg)} rows of {table.kind}",
                   motion=motion, unit=unit, record=table.record, phases_from_record=from_record,
                   phases_given=stated is not None)


def _build(path: Path, points: np.ndarray, cycle_deg: float, lift: float | None, phases, x_deg: bool,
           notes: list[str], where: str, curve: Curve | None = None, drawing: Drawing | None = None,
           candidates: int = 1, y0: float = 0.0, x0: float | None = None, x_tol: float = 0.0,
           cycle_stated: bool = True, baseline: Baseline | None = None, record: LawRecord | None = None
           ) -> LoadedLaw:
    """The law of a curve's points (drawing order): a = (y − y0)·scale, θ from x (see the module docstring)."""
    points = np.asarray(points, dtype=float)
    if not np.isfinite(points).all():
        index = int(np.flatnonzero(~np.isfinite(points).all(axis=1))[0])
        raise CamcadError(f"vertex {index} has a non-finite coordinate", where, "fix or delete that vertex")
    order = np.arange(len(points))
    if len(points) >= 2 and points[-1, 0] < points[0, 0]:
        order = order[::-1]
        notes.append("the curve is drawn right to left; read left to right")
    pts = points[order]
    x, y = pts[:, 0].copy(), pts[:, 1] - y0
    span = float(np.ptp(x))
    if span <= 0:
        raise CamcadError("the curve has no extent in x", where, "draw the law along the angle axis")
    tol = max(X_TOLERANCE * span, x_tol)
    back = np.flatnonzero(np.diff(x) < -tol)
    if len(back):
        i = int(order[back[0] + 1])
        raise CamcadError(f"vertex {i} goes back in x (x {points[i, 0]:.6g})", where,
                          "move that vertex so x never decreases along the curve (a vertical segment is a jump)")
    # snap x steps below the tolerance: they are vertical segments drawn a hair off
    x = np.maximum.accumulate(x)
    small = np.diff(x) <= tol
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
    x_start, x_end = float(xk[0]), float(xk[-1])
    cycle = float(np.radians(cycle_deg))
    origin = x_start if x0 is None else float(x0)
    edge = max(1e-6 * cycle_deg, tol) if x_deg else max(X_TOLERANCE * span, tol)
    if x0 is not None and abs(x_start - origin) > edge:
        side = "right" if x_start > origin else "left"
        raise CamcadError(f"the curve starts at x {x_start:.6g}, {side} of the origin x0 = {origin:.6g}", where,
                          f"draw the law from the origin, or pass --x0 {x_start:.9g}")
    if x_deg:
        if abs(x_end - origin - cycle_deg) > edge:
            raise CamcadError(f"the curve covers {x_start - origin:g}..{x_end - origin:g} deg from the origin "
                              f"x = {origin:g}, not the cycle 0..{cycle_deg:g}", where,
                              f"extend the curve to the whole cycle, or pass --cycle {x_end - origin:g}")
        x_min, x_max = origin, origin + float(cycle_deg)
        if origin != 0.0:
            notes.append(f"x is degrees from the origin x = {origin:.9g} (theta = x - {origin:.9g})")
    else:
        x_min, x_max = origin, x_end
    theta = (xk - x_min) / (x_max - x_min) * cycle
    theta[0], theta[-1] = 0.0, cycle
    given = bool(phases)
    if isinstance(phases, str):
        phases = parse_phases(phases, cycle_deg)
    phases, from_record = _record_phases(record, phases, cycle_deg, notes, where)
    if isinstance(phases, str):
        phase_tuple = parse_phases(phases, cycle_deg)
    elif phases:
        phase_tuple = tuple(phases)
    else:
        dwells, zeros = _drawn_dwells(baseline, x_min, x_max, cycle)
        reading = read_phases(theta, yk, cycle, where, dwells=dwells, zeros=zeros)
        phase_tuple = reading.phases
        notes.extend(reading.notes)
    law = PiecewiseLinearLaw(theta, yk, cycle, phase_tuple)
    if not phases and not cycle_stated and not x_deg:
        _refuse_part_of_a_cycle(law, x_start, x_end, origin, where)
    y_scale = 1.0
    if lift is not None:
        rise = rise_displacement(law)
        if not rise > 0:
            raise CamcadError(f"the drawn law has no positive rise ({rise:.4g}), so it cannot be scaled to a lift",
                              where, "check the sign of the acceleration, or give --phases")
        y_scale = lift / rise
        law = law.with_ordinates(yk * y_scale)
        notes.append(f"y scaled by {y_scale:.6g} so the rise is {lift:g} mm")
    if not x_deg and curve is not None:
        stated = "" if cycle_stated else " (the default: pass --cycle DEG if the curve spans another working angle)"
        notes.append(f"x {x_min:.6g}..{x_max:.6g} is taken as one cycle of {cycle_deg:g} deg{stated}")
    source = f"{where}, {len(kept)} vertices, x {x_min:g}..{x_max:g} -> 0..{cycle_deg:g} deg"
    unit, per_unit = "mm", 1.0
    if lift is None and drawing is not None and drawing.insunits in LENGTH_UNITS:
        unit, per_unit = LENGTH_UNITS[drawing.insunits]
    return LoadedLaw(law=law, path=path, source=source, notes=tuple(notes), y_scale=y_scale,
                     x_min=x_min, x_max=x_max, phases_given=given,
                     vertex_map=VertexMap(lo_law, hi_law, w_law), curve=curve, drawing=drawing,
                     candidates=candidates, y0=float(y0), baseline=baseline, length_unit=unit,
                     mm_per_unit=per_unit, record=record, phases_from_record=from_record,
                     unit=record.unit if record is not None else None)


def _drawn_dwells(baseline: Baseline | None, x_min: float, x_max: float,
                  cycle: float) -> tuple[tuple[tuple[float, float], ...], tuple[float, ...]]:
    """The drawn dwells and the points on the zero of an interpolating spline (drawing x, from the baseline)
    as cam angles (rad)."""
    if baseline is None:
        return (), ()
    scale = cycle / (x_max - x_min)
    dwells = []
    for lo, hi in baseline.drawn_dwells:
        t0, t1 = max((lo - x_min) * scale, 0.0), min((hi - x_min) * scale, cycle)
        if t1 > t0:
            dwells.append((t0, t1))
    zeros = tuple((x - x_min) * scale for x in baseline.drawn_zeros if x_min < x < x_max)
    return tuple(dwells), zeros


def _refuse_part_of_a_cycle(law: PiecewiseLinearLaw, x_start: float, x_end: float, origin: float,
                            where: str) -> None:
    """A motion from rest to rest with a rise and no return (or the reverse) is a drawing of part of a
    cycle (a rise alone, x 0..120): refuse to stretch it over the cycle. A curve that does not end at
    rest is left to the balance check, which reports its open velocity."""
    kinds = {p.kind for p in law.phases}
    if ("rise" in kinds) == ("return" in kinds):
        return
    theta = np.linspace(0.0, law.cycle, 2049)
    v = law.kinematics(unique(np.concatenate((theta, law.x)))).v
    if abs(v[-1]) > PART_CYCLE_REST_FRACTION * float(np.max(np.abs(v))):
        return
    has, lacks = ("rise", "return") if "rise" in kinds else ("return", "rise")
    width = x_end - origin
    raise CamcadError(f"the curve covers x {x_start:.6g}..{x_end:.6g} and holds a {has} but no {lacks}, "
                      "so it is not a whole cycle", where,
                      f"if x is degrees pass --x-deg --cycle {width:.6g}; if it is the whole cycle pass --cycle 360")


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


__all__ = ["LoadedLaw", "VertexMap", "load_law", "rise_displacement"]
