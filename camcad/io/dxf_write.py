"""Writing drawings as DXF that every CAD program opens (see ../shared/dxf-interop.md).

The writer takes plain geometry (``Drawing``: polylines with optional bulges, control-point
splines, circles, lines, text) so it does not depend on how the geometry was made. Rules it
follows, each learned from real readers:

- ASCII DXF only (binary is unreadable for GDAL < 3.12, LibreOffice, Inkscape, dxfgrabber);
- R2000 by default (LWPOLYLINE, SPLINE), R12 on request (2D POLYLINE; R12 has no SPLINE);
- ``$INSUNITS = 4`` (mm) in R2000 — R12 cannot store it; ``ezdxf.new()`` would say metres;
- ``$EXTMIN/$EXTMAX`` set from the content with ``ezdxf.appsettings.update_extents``:
  LibreOffice collapses a drawing whose extents keep ezdxf's ±1e20 default;
- SPLINEs with control points and knots, never fit points only (GDAL, Inkscape, LibreCAD and
  LibreOffice lose or misdraw those);
- text reduced to ASCII (no reader decodes non-ASCII right in every DXF version);
- the file is written atomically.
"""

from __future__ import annotations

import logging
import unicodedata
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from camcad.errors import CamcadError
from camcad.io.atomic import write_atomic

DXF_VERSIONS = {"R12": "R12", "R2000": "R2000"}

# ACI colours per layer; unknown layers are white/black (7)
LAYER_COLOURS = {"PROFILE": 7, "PITCH": 3, "BASE_CIRCLE": 5, "CENTER": 1, "ROLLER": 2, "TEXT": 7,
                 "PROFILE_SPLINE": 6, "GROOVE_OUTER": 7, "COUNTER_PROFILE": 4, "COUNTER_PITCH": 3}
LAYER_LINETYPES = {"PITCH": "DASHED", "CENTER": "CENTER", "COUNTER_PITCH": "DASHED"}


@dataclass(frozen=True)
class DxfPath:
    """A 2D polyline on ``layer``: points (N, 2) mm; bulges (N,) per vertex (to the next one) or None."""

    layer: str
    points: np.ndarray
    closed: bool
    bulges: np.ndarray | None = None


@dataclass(frozen=True)
class DxfSpline:
    """A B-spline by control points (N, 2) mm and its full knot vector (N + degree + 1)."""

    layer: str
    control_points: np.ndarray
    knots: np.ndarray
    degree: int = 3


@dataclass(frozen=True)
class DxfCircle:
    layer: str
    centre: tuple[float, float]
    radius: float


@dataclass(frozen=True)
class DxfLine:
    layer: str
    start: tuple[float, float]
    end: tuple[float, float]


@dataclass(frozen=True)
class DxfText:
    layer: str
    text: str
    insert: tuple[float, float]
    height: float = 2.5


@dataclass(frozen=True)
class Drawing:
    """Everything to put in model space."""

    paths: tuple[DxfPath, ...] = ()
    splines: tuple[DxfSpline, ...] = ()
    circles: tuple[DxfCircle, ...] = ()
    lines: tuple[DxfLine, ...] = ()
    texts: tuple[DxfText, ...] = ()
    layers: tuple[str, ...] = field(default=())


_REPLACEMENTS = {"°": " deg", "±": "+/-", "–": "-", "—": "-", "×": "x", "²": "2", "³": "3",
                 "ψ": "psi", "θ": "theta", "φ": "phi", "ρ": "rho", "σ": "sigma", "Ø": "D", "µ": "u",
                 "·": "*", "≤": "<=", "≥": ">="}


def ascii_text(text: str) -> str:
    """``text`` reduced to printable ASCII: known symbols spelled out, accents dropped, rest '?'."""
    for symbol, spelled in _REPLACEMENTS.items():
        text = text.replace(symbol, spelled)
    text = unicodedata.normalize("NFKD", text)
    text = "".join(ch for ch in text if not unicodedata.combining(ch))
    text = text.encode("ascii", "replace").decode("ascii")
    return "".join(ch if 32 <= ord(ch) < 127 else " " for ch in text)


def lwpolyline_from_array(msp, points: np.ndarray, bulges: np.ndarray | None = None, *, closed: bool = False,
                          dxfattribs: dict | None = None):
    """Add an LWPOLYLINE of the (N, 2) ``points`` (mm, OCS) with optional per-vertex ``bulges`` to ``msp``.

    ezdxf 1.4 appends the vertices of ``add_lwpolyline`` and ``set_points`` one at a time, copying the
    whole packed array on every append: O(N²), 45 s for 100 000 vertices and hours for a drawn law of
    a million. Here the packed array is set in one step (O(N)); see ``set_lwpolyline_rows``.
    """
    entity = msp.add_lwpolyline([], close=closed, dxfattribs=dxfattribs or {})
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    zeros = np.zeros(len(points))
    set_lwpolyline_rows(entity, np.column_stack((points, zeros, zeros,
                                                 zeros if bulges is None else np.asarray(bulges, dtype=float))))
    return entity


def set_lwpolyline_rows(entity, rows) -> None:
    """Replace the vertices of an LWPOLYLINE by ``rows`` (N, 5): x, y (OCS), start width, end width, bulge.

    One assignment of ezdxf's packed vertex array (the layout of ``get_points("xyseb")``), linear in N.
    """
    entity.lwpoints.set(np.asarray(rows, dtype=float).reshape(-1, 5))


def build_document(drawing: Drawing, version: str = "R2000"):
    """An ezdxf document holding ``drawing`` (units mm, extents set)."""
    import ezdxf
    import ezdxf.appsettings

    if version not in DXF_VERSIONS:
        raise CamcadError(f"DXF version {version!r} is not supported", "dxf writer", "use R2000 or R12")
    r12 = version == "R12"
    if r12 and drawing.splines:
        raise CamcadError("DXF R12 has no SPLINE entity", "--r12 --spline", "drop --spline or --r12")
    if r12:
        # ezdxf.new() always assigns $INSUNITS and logs that R12 cannot store it; nothing to report
        quiet = logging.getLogger("ezdxf")
        level = quiet.level
        quiet.setLevel(logging.ERROR)
        try:
            doc = ezdxf.new(DXF_VERSIONS[version], setup=True, units=4)
        finally:
            quiet.setLevel(level)
    else:
        doc = ezdxf.new(DXF_VERSIONS[version], setup=True, units=4)  # $INSUNITS 4 = mm, $MEASUREMENT metric
    used = list(drawing.layers)
    for item in (*drawing.paths, *drawing.splines, *drawing.circles, *drawing.lines, *drawing.texts):
        if item.layer not in used:
            used.append(item.layer)
    for name in used:
        attribs = {"color": LAYER_COLOURS.get(name, 7)}
        linetype = LAYER_LINETYPES.get(name)
        if linetype and linetype in doc.linetypes:
            attribs["linetype"] = linetype
        doc.layers.add(name, **attribs)
    msp = doc.modelspace()
    for path in drawing.paths:
        points = np.asarray(path.points, dtype=float)
        bulges = np.zeros(len(points)) if path.bulges is None else np.asarray(path.bulges, dtype=float)
        attribs = {"layer": path.layer}
        if r12:
            rows = [(float(x), float(y), float(b)) for (x, y), b in zip(points, bulges)]
            msp.add_polyline2d(rows, format="xyb", close=path.closed, dxfattribs=attribs)
        else:
            lwpolyline_from_array(msp, points, bulges, closed=path.closed, dxfattribs=attribs)
    for spline in drawing.splines:
        control = [(float(x), float(y), 0.0) for x, y in np.asarray(spline.control_points, dtype=float)]
        msp.add_open_spline(control, degree=spline.degree,
                            knots=[float(k) for k in np.asarray(spline.knots, dtype=float)],
                            dxfattribs={"layer": spline.layer})
    for circle in drawing.circles:
        msp.add_circle((float(circle.centre[0]), float(circle.centre[1])), float(circle.radius),
                       dxfattribs={"layer": circle.layer})
    for line in drawing.lines:
        msp.add_line((float(line.start[0]), float(line.start[1])), (float(line.end[0]), float(line.end[1])),
                     dxfattribs={"layer": line.layer})
    for text in drawing.texts:
        entity = msp.add_text(ascii_text(text.text), height=float(text.height),
                              dxfattribs={"layer": text.layer})
        entity.set_placement((float(text.insert[0]), float(text.insert[1])))
    ezdxf.appsettings.update_extents(doc)
    return doc


def write_dxf(path: str | Path, drawing: Drawing, version: str = "R2000") -> Path:
    """Write ``drawing`` as an ASCII DXF file (atomically); return the path."""
    doc = build_document(drawing, version)
    return write_atomic(path, lambda tmp: doc.saveas(tmp, fmt="asc"))
