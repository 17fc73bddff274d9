"""Writing laws: an acceleration polyline DXF and CSV tables; and a corrected copy of the user's drawing.

All outputs are written atomically and byte-deterministically (``dxf_write.save_document``). DXF
files are ASCII (binary DXF is unreadable for several CAD readers, dxf-interop.md trap 5) with
extents set (trap 2).

A corrected copy of a drawing (``write_corrected_drawing``) is the input as faithfully as ezdxf can
write it: every entity, layer, block and header variable kept, the same DXF version where ezdxf
writes it (R12, R2000 and later; R13/R14 come out as R2000, older than R12 as R12, and the notes
say so), the same line ends (CR LF stays CR LF), the input's creation and update stamps and GUIDs.
The original law is kept in an unreferenced block, CAMCAD_ORIGINAL: LibreCAD, Inkscape and
LibreOffice do not draw a block that is not inserted (they do draw a layer that is switched off,
and Inkscape draws a frozen one too), so a render shows one law, and nothing the user drew is lost.
"""

from __future__ import annotations

import math
import re
from dataclasses import replace
from pathlib import Path

import numpy as np

from camcad.errors import CamcadError
from camcad.io.atomic import write_atomic, write_text_atomic
from camcad.io.dxf_read import curve_space, open_drawing
from camcad.io.dxf_write import (
    HeaderKeep,
    header_snapshot,
    lwpolyline_from_array,
    new_document,
    save_document,
    set_lwpolyline_rows,
)
from camcad.io.law_record import LawRecord, attach_to_entity, rows_text, table_line, vertex_digest
from camcad.io.table_read import write_table

ORIGINAL_LAYER = "CAMCAD_ORIGINAL"
ORIGINAL_BLOCK = "CAMCAD_ORIGINAL"
#: what ezdxf writes instead of a DXF version it cannot write
WRITTEN_AS = {"AC1012": "AC1015", "AC1014": "AC1015", "AC1002": "AC1009", "AC1003": "AC1009",
              "AC1004": "AC1009", "AC1006": "AC1009"}
RELEASES = {"AC1002": "R2.5", "AC1003": "R2.6", "AC1004": "R9", "AC1006": "R10", "AC1009": "R12",
            "AC1012": "R13", "AC1014": "R14", "AC1015": "R2000", "AC1018": "R2004", "AC1021": "R2007",
            "AC1024": "R2010", "AC1027": "R2013", "AC1032": "R2018"}
_ACADVER = re.compile(rb"\$ACADVER\s*\r?\n\s*1\s*\r?\n\s*(AC\d{4})")


def write_law_dxf(path: str | Path, theta_deg: np.ndarray, accel: np.ndarray, *, layer: str = "ACCEL",
                  r12: bool = False, title: str = "", record: LawRecord | None = None) -> Path:
    """An acceleration law as a polyline: x = cam angle (deg), y = acceleration analog (mm/rad²).

    Besides the law (LWPOLYLINE, or POLYLINE for R12) on ``layer``, the file holds the θ axis on
    layer AXES and a title on layer TEXT, so it reads back through ``camcad check`` unchanged.
    The drawing is unitless ($INSUNITS 0): neither axis is a length. The same input gives the same
    bytes (``dxf_write.save_document``).

    Parameters
    ----------
    path : str or Path
        The DXF file to write.
    theta_deg : ndarray
        Cam angle of each vertex (deg), non-decreasing.
    accel : ndarray
        Acceleration analog of each vertex (mm/rad²).
    layer : str
        Layer of the law.
    r12 : bool
        Write DXF R12 (POLYLINE) instead of R2000 (LWPOLYLINE).
    title : str
        Text above the law (ASCII).
    record : LawRecord, optional
        camcad's record of the law (its phases and the rule it was judged by), stored as XDATA on the
        polyline with the vertex count and digest (``camcad.io.law_record``).

    Returns
    -------
    Path
        ``path``.
    """
    theta_deg = np.asarray(theta_deg, dtype=float)
    accel = np.asarray(accel, dtype=float)
    if theta_deg.shape != accel.shape or theta_deg.ndim != 1 or len(theta_deg) < 2:
        raise ValueError("theta_deg and accel must be 1-D arrays of equal length >= 2")
    doc = new_document("R12" if r12 else "R2000")
    if not r12:  # R12 has no $INSUNITS
        doc.units = 0
    for name, color in ((layer, 1), ("AXES", 8), ("TEXT", 7)):
        if name not in doc.layers:
            doc.layers.add(name, color=color)
    msp = doc.modelspace()
    if r12:
        entity = msp.add_polyline2d([(float(t), float(a)) for t, a in zip(theta_deg, accel)],
                                    dxfattribs={"layer": layer})
    else:
        entity = lwpolyline_from_array(msp, np.column_stack((theta_deg, accel)), dxfattribs={"layer": layer})
    if record is not None:
        points = np.column_stack((theta_deg, accel))
        attach_to_entity(doc, entity, replace(record, vertices=len(points), digest=vertex_digest(points)))
    msp.add_line((float(theta_deg[0]), 0.0), (float(theta_deg[-1]), 0.0), dxfattribs={"layer": "AXES"})
    height = max(float(np.ptp(accel)), 1e-9) * 0.04
    # plain ASCII without '^' (a caret starts a control code in DXF text)
    label = title or "acceleration analog a (mm/rad/rad) vs cam angle (deg)"
    msp.add_text(label.encode("ascii", "replace").decode(), dxfattribs={"layer": "TEXT", "height": height}) \
        .set_placement((float(theta_deg[0]), float(np.max(accel)) + 2 * height))
    return save_document(doc, path)


#: layers of a designed law's drawing, as a CAD user reads them (colour numbers of the ACI)
LAW_LAYERS = {"ACCELERATION": 5, "AXES": 8, "PHASE_MARKS": 3, "TEXT": 7}


def write_law_drawing(path: str | Path, theta_deg: np.ndarray, accel: np.ndarray, *, cycle_deg: float,
                      phases: list[tuple], labels: list[str] | None = None, title: str = "",
                      r12: bool = False, writer: str = "camcad law") -> Path:
    """A designed law as a drawing: its acceleration, the axes and the phase marks, with the phases kept.

    Layers: ACCELERATION (the law: x = cam angle in deg, y = acceleration analog in mm/rad², taken literally
    when read back), AXES (the θ axis, the a axis at θ = 0 and a tick every 30° or twelfth of the cycle),
    PHASE_MARKS (a vertical line at every phase boundary and each phase's label above the law), TEXT (the
    title and the axes' captions). The phases, with the position and velocity each states at its end, are
    kept in camcad's record on the law's polyline (``camcad.io.law_record``), so ``camcad check`` reads the drawing
    back with them. ASCII DXF, unitless ($INSUNITS 0: neither axis is a length), byte-deterministic.

    Parameters
    ----------
    path : str or Path
        The DXF file to write.
    theta_deg : ndarray
        Cam angle of each vertex (deg), non-decreasing from 0 to ``cycle_deg`` (a repeated angle is a jump).
    accel : ndarray
        Acceleration analog at each vertex (mm/rad²).
    cycle_deg : float
        The cycle (deg).
    phases : list of tuple
        (kind, start_deg, end_deg, s_end_mm or None, v_end_mm_per_deg) per phase.
    labels : list of str, optional
        A label per phase (default: its kind); written above the law between the phase's marks.
    title : str
        Text above the drawing (ASCII).
    r12 : bool
        DXF R12 (POLYLINE) instead of R2000 (LWPOLYLINE).
    writer : str
        The command named in the record as the law's writer.

    Returns
    -------
    Path
        ``path``.
    """
    theta_deg = np.asarray(theta_deg, dtype=float)
    accel = np.asarray(accel, dtype=float)
    if theta_deg.shape != accel.shape or theta_deg.ndim != 1 or len(theta_deg) < 2:
        raise ValueError("theta_deg and accel must be 1-D arrays of equal length >= 2")
    doc = new_document("R12" if r12 else "R2000")
    if not r12:
        doc.units = 0
    for name, color in LAW_LAYERS.items():
        if name not in doc.layers:
            doc.layers.add(name, color=color)
    msp = doc.modelspace()
    if r12:
        curve = msp.add_polyline2d([(float(t), float(a)) for t, a in zip(theta_deg, accel)],
                                   dxfattribs={"layer": "ACCELERATION"})
    else:
        curve = lwpolyline_from_array(msp, np.column_stack((theta_deg, accel)), dxfattribs={"layer": "ACCELERATION"})
    record = LawRecord(rows_text(phases), float(cycle_deg), writer, vertices=len(theta_deg),
                       digest=vertex_digest(np.column_stack((theta_deg, accel))))
    attach_to_entity(doc, curve, record)
    low, high = float(min(accel.min(), 0.0)), float(max(accel.max(), 0.0))
    span = max(high - low, 1e-9)
    height = 0.03 * max(span, cycle_deg / 4.0)
    text_height = min(height, 0.025 * cycle_deg)
    # the axes: θ along a = 0, a along θ = 0, ticks
    msp.add_line((0.0, 0.0), (float(cycle_deg), 0.0), dxfattribs={"layer": "AXES"})
    msp.add_line((0.0, low - 0.05 * span), (0.0, high + 0.05 * span), dxfattribs={"layer": "AXES"})
    step = 30.0 if cycle_deg >= 120.0 else cycle_deg / 12.0
    tick = 0.02 * span
    for k in range(1, math.floor(cycle_deg / step + 1e-9) + 1):
        x = k * step
        msp.add_line((x, -tick), (x, tick), dxfattribs={"layer": "AXES"})
        _text(msp, f"{x:g}", (x - 0.4 * text_height, low - 0.05 * span - 1.5 * text_height), 0.6 * text_height,
              "AXES")
    # ticks and values on the a axis at round steps
    a_step = _round_step(span / 4.0)
    for k in range(math.ceil(low / a_step), math.floor(high / a_step) + 1):
        if k == 0:
            continue
        y = k * a_step
        msp.add_line((-0.01 * cycle_deg, y), (0.01 * cycle_deg, y), dxfattribs={"layer": "AXES"})
        _text(msp, f"{y:g}", (-0.06 * cycle_deg, y - 0.3 * text_height), 0.6 * text_height, "AXES")
    # the phase marks and labels
    top = high + 0.08 * span
    for index, (kind, start, _, s_end, v_end) in enumerate(phases):
        if index > 0:
            msp.add_line((float(start), low - 0.05 * span), (float(start), top), dxfattribs={"layer": "PHASE_MARKS"})
        label = labels[index] if labels else kind
        _text(msp, label, (float(start) + 0.3 * text_height, top + 0.3 * text_height), 0.55 * text_height,
              "PHASE_MARKS")
        ends = f"to {s_end:.4g} mm" if s_end is not None else ""
        if v_end:
            ends += f", {v_end:.4g} mm/deg"
        if ends and kind != "dwell":
            _text(msp, ends, (float(start) + 0.3 * text_height, top + 1.2 * text_height), 0.45 * text_height,
                  "PHASE_MARKS")
    _text(msp, title or "acceleration analog a (mm/rad^2) against cam angle (deg)",
          (0.0, top + 3.0 * text_height), text_height, "TEXT")
    _text(msp, "cam angle (deg)", (float(cycle_deg) * 0.45, low - 0.05 * span - 3.2 * text_height),
          0.7 * text_height, "TEXT")
    _text(msp, "a (mm/rad^2)", (0.5 * text_height, high + 0.05 * span), 0.7 * text_height, "TEXT")
    return save_document(doc, path)


def _round_step(raw: float) -> float:
    """1, 2 or 5 times a power of ten, at least ``raw`` (> 0)."""
    power = 10.0 ** math.floor(math.log10(raw))
    return next(m * power for m in (1.0, 2.0, 5.0, 10.0) if m * power >= raw)


def _text(msp, text: str, at: tuple[float, float], height: float, layer: str) -> None:
    label = text.encode("ascii", "replace").decode().replace("^", "")   # a caret starts a control code in DXF text
    msp.add_text(label, dxfattribs={"layer": layer, "height": height}).set_placement((float(at[0]), float(at[1])))


def write_law_csv(path: str | Path, kinematics, extra: dict[str, np.ndarray] | None = None, *,
                  record: LawRecord | None = None, unit: str = "mm") -> Path:
    """θ (deg), s, v (per rad), a (per rad²), j (per rad³) and any extra columns, one row per sample.

    Parameters
    ----------
    path : str or Path
    kinematics : camcad.law.law.Kinematics
    extra : dict of str to ndarray, optional
        Further columns, one value per sample.
    record : LawRecord, optional
        camcad's record of the law, written as the comment line before the header
        (``camcad.io.law_record``); read back, the table keeps its phases.
    unit : str
        Unit of s ("mm", or "rad"/"deg" of swing): the columns are named s_<unit>, v_<unit>_per_rad,
        a_<unit>_per_rad2, j_<unit>_per_rad3.

    Returns
    -------
    Path
        ``path`` (12 significant digits, ``\\n`` line ends: the same bytes for the same numbers).
    """
    columns = {"theta_deg": np.degrees(kinematics.theta), f"s_{unit}": kinematics.s,
               f"v_{unit}_per_rad": kinematics.v, f"a_{unit}_per_rad2": kinematics.a,
               f"j_{unit}_per_rad3": kinematics.j}
    columns.update(extra or {})
    names = list(columns)
    data = np.column_stack([np.asarray(columns[n], dtype=float) for n in names])
    lines = [table_line(record)] if record is not None else []
    lines.append(",".join(names))
    lines.extend(",".join(f"{value:.12g}" for value in row) for row in data)
    return write_text_atomic(path, "\n".join(lines) + "\n")


def write_corrected_drawing(loaded, law, out: str | Path, *, resampled: bool = False,
                            record: LawRecord | None = None) -> tuple[Path, list[str]]:
    """A copy of the user's drawing with the law's curve replaced by ``law`` (same layer).

    Every other entity, layer, block and header variable is kept (see the module docstring for the
    version, line ends and stamps). The original curve goes into the block CAMCAD_ORIGINAL (not
    inserted, so not drawn; its entities on the frozen layer CAMCAD_ORIGINAL). An LWPOLYLINE,
    POLYLINE or LINE chain keeps its entity type, handle and vertex count (vertices move); a curve
    that was flattened (SPLINE, bulges, arcs), one inside a block reference, or a resampled law is
    written as a new polyline on the curve's layer, and the original entity itself moves into the
    block. Coordinates go back to drawing units through ``loaded.theta_to_x`` and ``loaded.a_to_y``;
    a vertex the correction did not move keeps its drawn coordinates bit for bit.

    Parameters
    ----------
    loaded : camcad.law.source.LoadedLaw
        The law as read (its curve, vertex map and mapping to drawing units).
    law : PiecewiseLinearLaw
        The corrected law (θ rad, a mm/rad²).
    out : str or Path
        The DXF file to write.
    resampled : bool
        The corrected law has other vertices than the drawn one.
    record : LawRecord, optional
        camcad's record of the corrected law, stored as XDATA on its polyline (the first entity of a
        chain) with the vertex count and digest of the curve as written.

    Returns
    -------
    (Path, list of str)
        The written path and notes saying what was written and what could not be kept.
    """
    out = Path(out)
    if loaded.curve is None:
        raise ValueError("the law was not read from a drawing")
    raw = Path(loaded.path).read_bytes()
    source = open_drawing(loaded.path)  # a fresh copy: the loaded document stays as read
    doc = source.doc
    keep = header_snapshot(doc, None if source.binary else raw)
    notes = _fidelity_notes(raw, source, doc, bool(keep.names))
    if doc.dxfversion <= "AC1009":   # an R12 copy holds what R12 can hold, and says what it could not
        keep, dropped = r12_header(keep)
        if dropped:
            notes.append(f"{len(dropped)} header variable{'s' if len(dropped) > 1 else ''} of DXF R2000 or later "
                         f"that an R12 file cannot hold (group codes R12 does not know) not carried: "
                         f"{', '.join(dropped[:8])}{' ...' if len(dropped) > 8 else ''}")
    block = _original_block(doc)
    curve = loaded.curve
    entities, unique = _curve_entities(doc, curve)
    in_block = not unique or any(e.dxftype() == "INSERT" for e in entities)
    x_new, y_new = _drawing_coordinates(loaded, law)
    msp = curve_space(doc, curve)   # the model space, or the paper-space layout the law was drawn in
    if curve.editable and not resampled and not in_block and len(law.x) == int(loaded.vertex_map.lo.max()) + 1:
        xs = loaded.vertex_map.ordinates(x_new)
        ys = loaded.vertex_map.ordinates(y_new)
        for entity in entities:
            kept = entity.copy()
            kept.dxf.layer = ORIGINAL_LAYER
            block.add_entity(kept)
        moved = _move_vertices(curve, entities, xs, ys)
        if record is not None and entities:
            attach_to_entity(doc, entities[0], replace(record, vertices=len(xs),
                                                       digest=vertex_digest(np.column_stack((xs, ys)))))
        notes.insert(0, f"{curve.label}: {moved} of {len(xs)} vertices moved in place; the original is kept in "
                        f"block {block.name} (not inserted, so not drawn)")
    else:
        layer = curve.layer
        extra = 0
        for entity in entities:
            if entity is None:
                continue
            if entity.dxftype() == "INSERT":
                extra += _keep_insert(doc, entity, curve, block)
            else:
                msp.move_to_layout(entity, block)
                entity.dxf.layer = ORIGINAL_LAYER
        points = np.column_stack((x_new, y_new))
        if doc.dxfversion <= "AC1009":
            written = msp.add_polyline2d([(float(x), float(y)) for x, y in points], dxfattribs={"layer": layer})
        else:
            written = lwpolyline_from_array(msp, points, dxfattribs={"layer": layer})
        if record is not None:
            attach_to_entity(doc, written, replace(record, vertices=len(points), digest=vertex_digest(points)))
        why = "resampled" if resampled else (
            f"{curve.kind} cannot take the corrected vertices in place" if not in_block else
            f"{curve.kind} inside a block reference" if unique else f"{curve.kind} whose handles are not unique")
        text = (f"the corrected law is a new polyline of {len(points)} vertices on layer {layer} ({why}); the "
                f"original {curve.label} is kept in block {block.name} (not inserted, so not drawn)")
        if extra:
            text += f"; the other {extra} entities of its block reference are drawn as copies in model space"
        notes.insert(0, text)
    notes.extend(_writable(doc))
    crlf = _crlf(raw) and not source.binary
    try:
        save_document(doc, out, keep=keep, crlf=crlf)
    except CamcadError:
        raise
    except Exception as err:  # noqa: BLE001 - ezdxf refuses to write some entities it read
        count = sum(1 for _ in doc.modelspace())
        fixes = _audit(doc)
        lost = count - sum(1 for _ in doc.modelspace())
        if not fixes:
            raise CamcadError(f"ezdxf cannot write this drawing ({' '.join(str(err).split())[:100]})", str(out),
                              "write the corrected law as a table instead: -o law.csv") from None
        save_document(doc, out, keep=keep, crlf=crlf)
        notes.append(f"ezdxf could not write the drawing as read ({' '.join(str(err).split())[:80]}); its audit "
                     f"made {len(fixes)} repairs" + (f" and removed {lost} model-space entities" if lost else "")
                     + ": " + "; ".join(fixes[:2]) + (" ..." if len(fixes) > 2 else ""))
    return out, notes


def write_corrected(loaded, law, out: str | Path, *, resampled: bool = False,
                    record: LawRecord | None = None) -> tuple[Path, list[str]]:
    """Save a corrected law the way ``camcad fix`` does, by the output's suffix and the input's kind.

    - a law read from a drawing, saved as ``.dxf``: a corrected copy of the drawing
      (``write_corrected_drawing``: every other entity kept, the original in block CAMCAD_ORIGINAL);
    - any law saved as ``.dxf`` otherwise: an acceleration polyline (``write_law_dxf``);
    - anything else: a two-column table (θ in deg, a in the input's y units) in the input table's
      dialect (delimiter, decimal comma) when the law came from a table, else comma-separated.

    Parameters
    ----------
    loaded : camcad.law.source.LoadedLaw
        The law as read (``camcad.load_law``): its file, curve and mapping to the input's units.
    law : PiecewiseLinearLaw
        The corrected law (θ in rad, a in mm/rad²).
    out : str or Path
        The file to write (.dxf, or a table); written atomically, never over the input.
    resampled : bool
        The corrected law has other vertices than the drawn one.
    record : LawRecord, optional
        camcad's record of the law (its phases and the rule it was judged by), kept in the file
        (``camcad.io.law_record``) so it reads back with these phases.

    Returns
    -------
    (Path, list of str)
        The written path and notes saying what was written (θ in deg, a in the input's y units; no
        unit of its own).

    Examples
    --------
    The corrected law of ``camcad.correct``'s example, saved as a table in the input's dialect: θ in deg
    and a in the table's own units, which read back as the balanced law:

    >>> import math, tempfile, pathlib
    >>> import camcad
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> rows = [(0, 0), (45, 1), (90, 0), (135, -1), (180, 0), (225, -1), (270, 0), (315, 1.2), (360, 0)]
    >>> _ = (folder / "law.csv").write_text("".join(f"{t},{a}\\n" for t, a in rows))
    >>> loaded = camcad.load_law(folder / "law.csv", lift=10.0)
    >>> fixed = camcad.correct(loaded.law)
    >>> path, notes = camcad.write_corrected(loaded, fixed.law, folder / "law.fixed.csv")
    >>> notes
    ['the corrected law is written as a table of 9 rows']
    >>> camcad.check(camcad.load_law(path, lift=10.0).law).balanced
    True
    """
    out = Path(out)
    if loaded.curve is not None and out.suffix.lower() == ".dxf":
        return write_corrected_drawing(loaded, law, out, resampled=resampled, record=record)
    theta_deg = np.degrees(law.x)
    if out.suffix.lower() == ".dxf":
        accel = loaded.a_to_y(law.a)
        return (write_law_dxf(out, theta_deg, accel, record=record),
                ["the corrected law is written as an acceleration polyline"])
    table = loaded.table
    delimiter = table.delimiter if table is not None else ","
    decimal_comma = table.decimal_comma if table is not None else False
    notes = [f"the corrected law is written as a table of {len(theta_deg)} rows"]
    if loaded.curve is not None:
        # a table's first column is cam degrees (never the drawing's x) and its a is measured from the zero:
        # the drawing's y less its zero axis, in the drawing's units, so check reads back the same law
        accel = np.asarray(law.a) / loaded.y_scale
        cycle = float(np.degrees(law.cycle))
        again = [f"--cycle {cycle:.9g}"] if abs(cycle - 360.0) > 1e-9 else []
        if loaded.y_scale != 1.0:
            again.append(f"--lift {rise_of(law):.9g}")
        notes.append(f"theta_deg is the cam angle 0..{cycle:.9g} deg (the drawing's x {loaded.x_min:.6g}.."
                     f"{loaded.x_max:.6g}) and accel the drawing's y above its zero axis y = {loaded.y0:.9g}, in "
                     "drawing units" + (f"; read it back with {' '.join(again)}" if again else ""))
    else:
        accel = loaded.a_to_y(law.a)
    write_atomic(out, lambda tmp: write_table(tmp, theta_deg, accel, delimiter, decimal_comma, record=record))
    return out, notes


def rise_of(law) -> float:
    """Sum of s(end) − s(start) over the law's rise phases (mm), exact: the lift that reads a table of the
    law back at the same scale."""
    total = 0.0
    for phase in law.phases:
        if phase.kind == "rise":
            s = law.kinematics(np.array([phase.start, phase.end])).s
            total += float(s[1] - s[0])
    return total


# --- fidelity ----------------------------------------------------------------------------------------

def r12_code(code: int) -> bool:
    """True when DXF R12 knows the group code ``code`` (0–99 values, 210–239 extrusion, 999 comments,
    1000–1071 extended data); R13 and later added 100–209, 240–998 (the 290 booleans, the 370 lineweights,
    the 390 handles, …).

    Examples
    --------
    >>> [r12_code(c) for c in (1, 10, 70, 210, 290, 370, 390, 1040)]
    [True, True, True, True, False, False, False, True]
    """
    return 0 <= code < 100 or 210 <= code < 240 or code == 999 or 1000 <= code <= 1071


def r12_header(keep: HeaderKeep) -> tuple[HeaderKeep, list[str]]:
    """The header variables of ``keep`` an R12 file can hold (every value's group code known to R12:
    ``r12_code``), and the names of the others."""
    names: list[str] = []
    dropped: list[str] = []
    for name in keep.names:
        code = getattr(keep.values.get(name), "code", 0)
        (names if isinstance(code, int) and r12_code(code) else dropped).append(name)
    return HeaderKeep(tuple(names), {name: keep.values[name] for name in names}), dropped


def _crlf(raw: bytes) -> bool:
    first = raw.find(b"\n")
    return first > 0 and raw[first - 1:first] == b"\r"


def input_version(raw: bytes) -> str | None:
    """The $ACADVER a DXF file's bytes declare (e.g. "AC1014"), or None.

    Examples
    --------
    >>> input_version(b"  0\\nSECTION\\n  2\\nHEADER\\n  9\\n$ACADVER\\n  1\\nAC1014\\n")
    'AC1014'
    """
    match = _ACADVER.search(raw[:65536])
    return match.group(1).decode("ascii") if match else None


def _fidelity_notes(raw: bytes, source, doc, has_header: bool) -> list[str]:
    """What the copy cannot keep of the input, and why."""
    notes = []
    if source.binary:
        notes.append("the input is binary DXF; the copy is ASCII DXF (several CAD readers cannot read binary)")
    declared = None if source.binary else input_version(raw)
    written = doc.dxfversion
    if declared is None and not source.binary:
        notes.append(f"the input has no $ACADVER (no or an incomplete HEADER); the copy is a complete "
                     f"{RELEASES.get(written, written)} drawing with the header, tables and objects ezdxf writes")
    elif declared is not None and declared != written:
        notes.append(f"the input is DXF {RELEASES.get(declared, declared)} ({declared}); the copy is "
                     f"{RELEASES.get(written, written)} ({written}): ezdxf writes R12 and R2000 or later only")
    if source.recovered and declared is not None:
        notes.append("the input was damaged and repaired on reading (see the notes above); the copy holds the "
                     "repaired drawing")
    if has_header:
        notes.append("header variables kept from the input, except $EXTMIN/$EXTMAX (recomputed from the drawing) "
                     "and $HANDSEED (the next free handle)")
    return notes


def _writable(doc) -> list[str]:
    """Rewrite, without changing their shape, entities ezdxf reads but refuses to write; say which.

    An ELLIPSE whose axis ratio exceeds 1 (its "minor" axis is the longer one) is the same ellipse
    with the axes swapped and the parameters shifted by a quarter turn.
    """
    swapped = []
    for entity in list(doc.entitydb.values()):
        if entity.dxftype() == "ELLIPSE" and entity.is_alive and abs(float(entity.dxf.ratio)) > 1.0 + 1e-9:
            entity.swap_axis()
            swapped.append(str(entity.dxf.get("handle", "?")))
    notes = []
    if swapped:
        listed = ", ".join(swapped[:4]) + (" ..." if len(swapped) > 4 else "")
        notes.append(f"{len(swapped)} ELLIPSEs (handles {listed}) have an axis ratio above 1, which ezdxf does not "
                     "write: written with their axes swapped (the same ellipses)")
    # a LEADER needs at least two vertices: ezdxf skips one with fewer (LibreCAD writes such leaders); nothing
    # of it can be drawn, but say so, since the copy then lacks an entity of the input
    empty = [str(e.dxf.get("handle", "?")) for e in doc.modelspace() if e.dxftype() == "LEADER"
             and len(getattr(e, "vertices", ())) < 2]
    if empty:
        listed = ", ".join(empty[:4]) + (" ..." if len(empty) > 4 else "")
        notes.append(f"{len(empty)} LEADER entities (handles {listed}) have fewer than two vertices: ezdxf does not "
                     "write such an (invalid, invisible) leader, so the copy lacks it")
    return notes


def _audit(doc) -> list[str]:
    auditor = doc.audit()
    return [" ".join(str(getattr(entry, "message", entry)).split()) for entry in auditor.fixes]


def _curve_entities(doc, curve) -> tuple[list, bool]:
    """The model-space entities the curve was read from, and whether each handle named exactly one.

    Handles are looked up among the model-space entities (as the reader found them), not in ezdxf's
    handle table: a damaged file may give the same handle to several entities (the table then holds
    only one of them, maybe a BLOCK). Among several candidates, those of the curve's entity kind whose
    ends lie on the curve are taken.
    """
    wanted = list(dict.fromkeys(curve.handles or (curve.handle,)))
    found: dict[str, list] = {h: [] for h in wanted}
    for entity in curve_space(doc, curve):
        handle = str(entity.dxf.get("handle", "") or "?")
        if handle in found:
            found[handle].append(entity)
    kinds = {"LWPOLYLINE": ("LWPOLYLINE",), "POLYLINE": ("POLYLINE",), "SPLINE": ("SPLINE",),
             "LINE chain": ("LINE",), "LINE/ARC chain": ("LINE", "ARC")}.get(curve.kind, ())
    entities, unique = [], True
    for handle in wanted:
        candidates = found[handle]
        if len(candidates) > 1:
            typed = [e for e in candidates if e.dxftype() in kinds or e.dxftype() == "INSERT"]
            candidates = [e for e in typed if _lies_on(e, curve)] or typed
        if len(candidates) != 1:
            unique = False
        entities.extend(candidates)
    return entities, unique


def _plot_style_normal(doc) -> None:
    """The plot style "Normal" every new layer refers to (ezdxf looks it up): a damaged drawing may have lost it
    from its ACAD_PLOTSTYLENAME dictionary; a placeholder is put back, as a new drawing has."""
    styles = doc.plotstyles
    if "Normal" not in styles:
        styles["Normal"] = doc.objects.add_placeholder(owner=styles.dxf.handle)


def _original_block(doc):
    """A new block definition (never inserted) for the original curve, and its frozen layer."""
    if ORIGINAL_LAYER not in doc.layers:
        _plot_style_normal(doc)
        doc.layers.add(ORIGINAL_LAYER, color=8)
    layer = doc.layers.get(ORIGINAL_LAYER)
    layer.off()
    layer.freeze()
    name, number = ORIGINAL_BLOCK, 2
    while name in doc.blocks:
        name, number = f"{ORIGINAL_BLOCK}_{number}", number + 1
    return doc.blocks.new(name)


def _keep_insert(doc, insert, curve, block) -> int:
    """A law inside a block reference: the reference moves into ``block``; every entity it draws that is
    not part of the law is drawn again as a copy in model space. Returns how many were copied."""
    msp = curve_space(doc, curve)
    pieces = list(insert.virtual_entities())
    msp.move_to_layout(insert, block)
    copied = 0
    for piece in pieces:
        if _lies_on(piece, curve):
            continue
        msp.add_entity(piece)
        copied += 1
    return copied


def _lies_on(entity, curve) -> bool:
    """True when ``entity`` is a curve piece whose start, middle and end lie on the curve's polyline."""
    if entity.dxftype() not in ("LWPOLYLINE", "POLYLINE", "SPLINE", "LINE", "ARC") or \
            str(entity.dxf.get("layer", "0")) != curve.layer:
        return False
    from ezdxf import path as ezpath

    try:
        shape = ezpath.make_path(entity)
        points = np.array([[p.x, p.y] for p in shape.flattening(1e-3 * max(curve.x_range, 1e-9))])
    except Exception:  # noqa: BLE001 - anything ezdxf cannot trace is not the law
        return False
    if len(points) == 0:
        return False
    probes = points[[0, len(points) // 2, -1]]
    size = float(np.hypot(*np.ptp(curve.points, axis=0))) or 1.0
    return bool(np.all(_distance_to_polyline(probes, curve.points) <= 1e-6 * size + curve.flatten_tol * 2))


def _distance_to_polyline(probes: np.ndarray, polyline: np.ndarray) -> np.ndarray:
    start, end = polyline[:-1], polyline[1:]
    seg = end - start
    length2 = np.maximum((seg ** 2).sum(axis=1), 1e-300)
    result = []
    for p in probes:
        t = np.clip(((p - start) * seg).sum(axis=1) / length2, 0.0, 1.0)
        nearest = start + t[:, None] * seg
        result.append(float(np.sqrt(((nearest - p) ** 2).sum(axis=1)).min()))
    return np.array(result)


# --- coordinates -------------------------------------------------------------------------------------

def _drawing_coordinates(loaded, law) -> tuple[np.ndarray, np.ndarray]:
    """Drawing x, y of each law vertex; a vertex the correction did not move keeps its drawn coordinates
    bit for bit (no round trip through the angle mapping)."""
    x_new = loaded.theta_to_x(law.x)
    y_new = loaded.a_to_y(law.a)
    if len(law.x) != len(loaded.law.x):
        return x_new, y_new
    vmap = loaded.vertex_map
    exact = vmap.lo == vmap.hi
    first_point = np.full(len(law.x), -1)
    for point in np.flatnonzero(exact)[::-1]:
        first_point[vmap.lo[point]] = point
    has_point = first_point >= 0
    same_x = has_point.copy()
    same_x[has_point] = law.x[has_point] == loaded.law.x[has_point]
    same_y = has_point.copy()
    same_y[has_point] = law.a[has_point] == loaded.law.a[has_point]
    x_new[same_x] = loaded.curve.points[first_point[same_x], 0]
    y_new[same_y] = loaded.curve.points[first_point[same_y], 1]
    return x_new, y_new


def _move_vertices(curve, entities, xs: np.ndarray, ys: np.ndarray) -> int:
    """Write the points (xs, ys) (WCS) into the curve's own entities; return how many points changed.

    A single LWPOLYLINE or POLYLINE takes point i as its vertex i. A chain (``curve.vertex_refs``)
    names, for each point, the entity ends or vertices at it: (handle, "start"|"end") of a LINE, or
    (handle, k) for vertex k of an LWPOLYLINE or POLYLINE piece.
    """
    moved = int(np.count_nonzero((xs != curve.points[:, 0]) | (ys != curve.points[:, 1])))
    by_handle = {e.dxf.handle: e for e in entities}
    if curve.vertex_refs:
        targets: dict[str, dict[int, tuple[float, float]]] = {}
        for refs, wx, wy in zip(curve.vertex_refs, xs, ys):
            for handle, where in refs:
                entity = by_handle[handle]
                if where in ("start", "end"):
                    old = getattr(entity.dxf, where)
                    setattr(entity.dxf, where, (float(wx), float(wy), old.z))
                else:
                    targets.setdefault(handle, {})[int(where)] = (float(wx), float(wy))
        for handle, vertices in targets.items():
            _set_polyline_vertices(by_handle[handle], vertices)
        return moved
    _set_polyline_vertices(entities[0], dict(enumerate(zip(xs.tolist(), ys.tolist()))))
    return moved


def _set_polyline_vertices(entity, vertices: dict[int, tuple[float, float]]) -> None:
    """Set vertex k of an LWPOLYLINE or POLYLINE to the WCS point vertices[k] (OCS handled)."""
    kind = entity.dxftype()
    if kind == "LWPOLYLINE":
        ocs = entity.ocs()
        rows = np.array(entity.get_points("xyseb"), dtype=float).reshape(-1, 5)
        for k, (wx, wy) in vertices.items():
            p = ocs.from_wcs((wx, wy, 0.0)) if ocs.transform else (wx, wy, 0.0)
            rows[k, 0], rows[k, 1] = p[0], p[1]
        set_lwpolyline_rows(entity, rows)
    elif kind == "POLYLINE":
        ocs = entity.ocs() if entity.is_2d_polyline else None
        vertex_list = list(entity.vertices)
        for k, (wx, wy) in vertices.items():
            vertex = vertex_list[k]
            z = vertex.dxf.location.z
            if ocs is not None and ocs.transform:
                p = ocs.from_wcs((wx, wy, 0.0))
                vertex.dxf.location = (p[0], p[1], p[2])
            else:
                vertex.dxf.location = (wx, wy, z)
    else:
        raise ValueError(f"cannot move the vertices of a {kind}")
