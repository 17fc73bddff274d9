"""Writing laws: an acceleration polyline DXF and CSV tables; and a corrected copy of the user's drawing.

All outputs are written atomically (temp file + rename). DXF files are ASCII (binary DXF is
unreadable for several CAD readers, dxf-interop.md trap 5) with extents set (trap 2).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from camcad.errors import CamcadError
from camcad.io.atomic import write_atomic, write_text_atomic
from camcad.io.dxf_write import lwpolyline_from_array, set_lwpolyline_rows

ORIGINAL_LAYER = "CAMCAD_ORIGINAL"


def write_law_dxf(path: str | Path, theta_deg: np.ndarray, accel: np.ndarray, *, layer: str = "ACCEL",
                  r12: bool = False, title: str = "") -> Path:
    """An acceleration law as a polyline: x = cam angle (deg), y = acceleration analog (mm/rad²).

    Besides the law (LWPOLYLINE, or POLYLINE for R12) on ``layer``, the file holds the θ axis on
    layer AXES and a title on layer TEXT, so it reads back through ``camcad check`` unchanged.
    The drawing is unitless ($INSUNITS 0): neither axis is a length.
    """
    import ezdxf
    from ezdxf import appsettings

    theta_deg = np.asarray(theta_deg, dtype=float)
    accel = np.asarray(accel, dtype=float)
    if theta_deg.shape != accel.shape or theta_deg.ndim != 1 or len(theta_deg) < 2:
        raise ValueError("theta_deg and accel must be 1-D arrays of equal length >= 2")
    doc = ezdxf.new("R12" if r12 else "R2000")
    if not r12:  # R12 has no $INSUNITS
        doc.units = 0
    for name, color in ((layer, 1), ("AXES", 8), ("TEXT", 7)):
        if name not in doc.layers:
            doc.layers.add(name, color=color)
    msp = doc.modelspace()
    if r12:
        msp.add_polyline2d([(float(t), float(a)) for t, a in zip(theta_deg, accel)], dxfattribs={"layer": layer})
    else:
        lwpolyline_from_array(msp, np.column_stack((theta_deg, accel)), dxfattribs={"layer": layer})
    msp.add_line((float(theta_deg[0]), 0.0), (float(theta_deg[-1]), 0.0), dxfattribs={"layer": "AXES"})
    height = max(float(np.ptp(accel)), 1e-9) * 0.04
    # plain ASCII without '^' (a caret starts a control code in DXF text)
    label = title or "acceleration analog a (mm/rad/rad) vs cam angle (deg)"
    msp.add_text(label.encode("ascii", "replace").decode(), dxfattribs={"layer": "TEXT", "height": height}) \
        .set_placement((float(theta_deg[0]), float(np.max(accel)) + 2 * height))
    appsettings.update_extents(doc)
    return write_atomic(path, lambda tmp: doc.saveas(tmp, fmt="asc"))


def write_law_csv(path: str | Path, kinematics, extra: dict[str, np.ndarray] | None = None) -> Path:
    """θ (deg), s (mm), v (mm/rad), a (mm/rad²), j (mm/rad³) and any extra columns, one row per sample."""
    columns = {"theta_deg": np.degrees(kinematics.theta), "s_mm": kinematics.s, "v_mm_per_rad": kinematics.v,
               "a_mm_per_rad2": kinematics.a, "j_mm_per_rad3": kinematics.j}
    columns.update(extra or {})
    names = list(columns)
    data = np.column_stack([np.asarray(columns[n], dtype=float) for n in names])
    lines = [",".join(names)]
    lines.extend(",".join(f"{value:.12g}" for value in row) for row in data)
    return write_text_atomic(path, "\n".join(lines) + "\n")


def write_corrected_drawing(loaded, law, out: str | Path, *, resampled: bool = False) -> tuple[Path, list[str]]:
    """A copy of the user's drawing with the law's curve replaced by ``law`` (same layer).

    Every other entity, layer, block and header variable is kept. The original curve is kept on
    layer CAMCAD_ORIGINAL (switched off). An LWPOLYLINE, POLYLINE or LINE chain keeps its entity
    type, handle and vertex count (vertices move); a curve that was flattened (SPLINE, bulges,
    arcs, a block) or a resampled law is written as a new polyline on the curve's layer.
    Coordinates go back to drawing units: x = x_min + θ/cycle·(x_max − x_min), y = a / y_scale.
    """
    from camcad.io.dxf_read import open_drawing

    out = Path(out)
    if loaded.curve is None:
        raise ValueError("the law was not read from a drawing")
    source = open_drawing(loaded.path)  # a fresh copy: the loaded document stays as read
    doc = source.doc
    notes: list[str] = []
    if source.binary:
        notes.append("the input is binary DXF; the corrected copy is written as ASCII DXF")
    if ORIGINAL_LAYER not in doc.layers:
        doc.layers.add(ORIGINAL_LAYER, color=8)
    doc.layers.get(ORIGINAL_LAYER).off()
    curve = loaded.curve
    entities = [doc.entitydb.get(h) for h in curve.handles]
    in_block = any(e is None or e.dxftype() == "INSERT" for e in entities)
    x_new, y_new = _drawing_coordinates(loaded, law)
    if curve.editable and not resampled and not in_block and len(law.x) == int(loaded.vertex_map.lo.max()) + 1:
        xs = loaded.vertex_map.ordinates(x_new)
        ys = loaded.vertex_map.ordinates(y_new)
        msp = doc.modelspace()
        for entity in entities:
            keep = entity.copy()
            keep.dxf.layer = ORIGINAL_LAYER
            msp.add_entity(keep)
        _move_vertices(curve, entities, xs, ys)
        notes.append(f"{curve.label}: {len(xs)} vertices moved in place; the original is kept on layer "
                     f"{ORIGINAL_LAYER} (off)")
    else:
        layer = curve.layer
        for entity in entities:
            if entity is not None and entity.dxftype() != "INSERT":
                entity.dxf.layer = ORIGINAL_LAYER
        points = list(zip(x_new.tolist(), y_new.tolist()))
        msp = doc.modelspace()
        if doc.dxfversion <= "AC1009":
            msp.add_polyline2d(points, dxfattribs={"layer": layer})
        else:
            lwpolyline_from_array(msp, np.column_stack((x_new, y_new)), dxfattribs={"layer": layer})
        why = "resampled" if resampled else f"{curve.kind} cannot take the corrected vertices in place"
        notes.append(f"the corrected law is a new polyline of {len(points)} vertices on layer {layer} ({why}); "
                     f"the original is on layer {ORIGINAL_LAYER} (off)")
    try:
        write_atomic(out, lambda tmp: doc.saveas(tmp, fmt="asc"))
    except OSError as err:
        raise CamcadError(f"cannot write the corrected drawing ({err.strerror})", str(out),
                          "choose another output with -o") from None
    return out, notes


def write_corrected(loaded, law, out: str | Path, *, resampled: bool = False) -> tuple[Path, list[str]]:
    """Save a corrected law the way ``camcad fix`` does, by the output's suffix and the input's kind.

    - a law read from a drawing, saved as ``.dxf``: a corrected copy of the drawing
      (``write_corrected_drawing``: every other entity kept, the original on CAMCAD_ORIGINAL);
    - any law saved as ``.dxf`` otherwise: an acceleration polyline (``write_law_dxf``);
    - anything else: a two-column table (θ in deg, a in the input's y units) in the input table's
      dialect (delimiter, decimal comma) when the law came from a table, else comma-separated.

    Returns the written path and notes saying what was written.
    """
    from camcad.io.table_read import write_table

    out = Path(out)
    if loaded.curve is not None and out.suffix.lower() == ".dxf":
        return write_corrected_drawing(loaded, law, out, resampled=resampled)
    theta_deg = loaded.theta_to_x(law.x) if loaded.curve is not None else np.degrees(law.x)
    accel = loaded.a_to_y(law.a)
    if out.suffix.lower() == ".dxf":
        return write_law_dxf(out, theta_deg, accel), ["the corrected law is written as an acceleration polyline"]
    table = loaded.table
    delimiter = table.delimiter if table is not None else ","
    decimal_comma = table.decimal_comma if table is not None else False
    write_atomic(out, lambda tmp: write_table(tmp, theta_deg, accel, delimiter, decimal_comma))
    return out, [f"the corrected law is written as a table of {len(theta_deg)} rows"]


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


def _move_vertices(curve, entities, xs: np.ndarray, ys: np.ndarray) -> None:
    entity = entities[0]
    kind = entity.dxftype()
    if kind == "LWPOLYLINE":
        ocs = entity.ocs()
        old = entity.get_points("xyseb")
        new = []
        for (x, y, *rest), wx, wy in zip(old, xs, ys):
            p = ocs.from_wcs((wx, wy, 0.0)) if ocs.transform else (wx, wy, 0.0)
            new.append((p[0], p[1], *rest))
        set_lwpolyline_rows(entity, new)
    elif kind == "POLYLINE":
        ocs = entity.ocs() if entity.is_2d_polyline else None
        for vertex, wx, wy in zip(entity.vertices, xs, ys):
            z = vertex.dxf.location.z
            if ocs is not None and ocs.transform:
                p = ocs.from_wcs((wx, wy, 0.0))
                vertex.dxf.location = (p[0], p[1], p[2])
            else:
                vertex.dxf.location = (wx, wy, z)
    else:  # LINE chain: every LINE end that sits on a chain point moves with it
        by_handle = {e.dxf.handle: e for e in entities}
        for refs, wx, wy in zip(curve.vertex_refs, xs, ys):
            for handle, end in refs:
                line = by_handle[handle]
                old = getattr(line.dxf, end)
                setattr(line.dxf, end, (wx, wy, old.z))
