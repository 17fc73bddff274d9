"""Writing drawings as DXF that every CAD program opens (docs/part.md lists the readers checked).

The writer takes plain geometry (``Drawing``: polylines with optional bulges, control-point
splines, circles, lines, text) so it does not depend on how the geometry was made. Rules it
follows, each learned from real readers:

- ASCII DXF only (binary is unreadable for GDAL < 3.12, LibreOffice, Inkscape, dxfgrabber);
- R2000 by default (LWPOLYLINE, SPLINE), R12 on request (2D POLYLINE; R12 has no SPLINE);
- ``$INSUNITS = 4`` (mm) in R2000 — R12 cannot store it; ``ezdxf.new()`` would say metres;
- ``$EXTMIN/$EXTMAX`` set from the content with ezdxf's fast bounding boxes (``_set_extents``):
  LibreOffice collapses a drawing whose extents keep ezdxf's ±1e20 default;
- SPLINEs with control points and knots, never fit points only (GDAL, Inkscape, LibreCAD and
  LibreOffice lose or misdraw those);
- text reduced to ASCII (no reader decodes non-ASCII right in every DXF version);
- the file is written atomically, and byte for byte the same for the same content: ezdxf stamps
  every save with the time and a random GUID ($TDCREATE, $TDUPDATE, $VERSIONGUID, $FINGERPRINTGUID
  and its own metadata); ``save_document`` writes a fixed creation stamp instead (the time given by
  ``SOURCE_DATE_EPOCH``, else 2000-01-01 00:00 UTC) or, for a copy of a user's drawing, the
  input's own values (``HeaderKeep``).
"""

from __future__ import annotations

import logging
import math
import os
import re
import unicodedata
from contextlib import contextmanager
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

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


#: $INSUNITS of the length units camcad writes (the DXF reference's table)
INSUNITS = {"mm": 4, "in": 1}


def scaled_drawing(drawing: Drawing, factor: float) -> Drawing:
    """``drawing`` with every length (coordinates, radii, text heights) multiplied by ``factor``: 1/25.4 turns
    a drawing in mm into one in inches."""
    from dataclasses import replace

    def xy(point) -> tuple[float, float]:
        return (float(point[0]) * factor, float(point[1]) * factor)

    return replace(
        drawing,
        paths=tuple(replace(p, points=np.asarray(p.points, dtype=float) * factor) for p in drawing.paths),
        splines=tuple(replace(s, control_points=np.asarray(s.control_points, dtype=float) * factor)
                      for s in drawing.splines),
        circles=tuple(replace(c, centre=xy(c.centre), radius=float(c.radius) * factor) for c in drawing.circles),
        lines=tuple(replace(line, start=xy(line.start), end=xy(line.end)) for line in drawing.lines),
        texts=tuple(replace(t, insert=xy(t.insert), height=float(t.height) * factor) for t in drawing.texts))


def build_document(drawing: Drawing, version: str = "R2000", units: str = "mm"):
    """An ezdxf document holding ``drawing`` (its lengths in ``units``, "mm" or "in"; save_document sets the
    extents when it is written)."""

    if version not in DXF_VERSIONS:
        raise CamcadError(f"DXF version {version!r} is not supported", "dxf writer", "use R2000 or R12")
    r12 = version == "R12"
    if r12 and drawing.splines:
        raise CamcadError("DXF R12 has no SPLINE entity", "--r12 --spline", "drop --spline or --r12")
    # $INSUNITS 4 = mm (1 = inch), $MEASUREMENT metric (imperial); of ezdxf's standard resources only the
    # linetypes the layers use (ezdxf's full set of text and dimension styles would be 60 % of the file and of
    # its writing time)
    doc = new_document(DXF_VERSIONS[version], setup=False, units=INSUNITS[units])
    _add_linetypes(doc, sorted(set(LAYER_LINETYPES.values())))
    used = list(drawing.layers)
    item: Any
    for item in (*drawing.paths, *drawing.splines, *drawing.circles, *drawing.lines, *drawing.texts):
        if item.layer not in used:
            used.append(item.layer)
    attribs: dict[str, Any]
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
    return doc


def _add_linetypes(doc, names: list[str]) -> None:
    """ezdxf's standard definitions of the linetypes ``names`` (those it knows), added to ``doc`` as
    ``ezdxf.new(setup=True)`` adds them (ISO-scaled in a metric drawing)."""
    from ezdxf.tools.standards import ISO_LTYPE_FACTOR, linetypes

    factor = ISO_LTYPE_FACTOR if doc.header.get("$MEASUREMENT", 1) else 1.0
    for name, description, pattern in linetypes(scale=factor):
        if name in names and name not in doc.linetypes:
            doc.linetypes.new(name, dxfattribs={"description": description, "pattern": pattern})


def write_dxf(path: str | Path, drawing: Drawing, version: str = "R2000", units: str = "mm") -> Path:
    """Write ``drawing`` as an ASCII DXF file (atomically, byte-deterministic); return the path.

    Parameters
    ----------
    path : str or Path
        The file to write.
    drawing : Drawing
        The geometry (mm).
    version : str
        "R2000" (default) or "R12".
    units : str
        The unit of the drawing's lengths, "mm" or "in" ($INSUNITS 4 or 1 in R2000; R12 cannot say it).

    Returns
    -------
    Path
        ``path``.
    """
    doc = build_document(drawing, version, units)
    return save_document(doc, path)


# ---------------------------------------------------------------------------------------------
# Deterministic, faithful saving
# ---------------------------------------------------------------------------------------------

#: the environment variable of reproducible builds: seconds since 1970-01-01 UTC
STAMP_VARIABLE = "SOURCE_DATE_EPOCH"
#: the creation stamp of camcad's own drawings when SOURCE_DATE_EPOCH is not set
FIXED_STAMP = datetime(2000, 1, 1, tzinfo=UTC)
#: header variables a saved copy recomputes instead of keeping the input's value
RECOMPUTED = ("$ACADVER", "$EXTMIN", "$EXTMAX", "$HANDSEED", "$DWGCODEPAGE")
#: header variables that hold a time or an identity of the save (ezdxf sets them anew every time)
STAMPED = ("$TDCREATE", "$TDUCREATE", "$TDUPDATE", "$TDUUPDATE", "$VERSIONGUID", "$FINGERPRINTGUID")
NULL_GUID = "{00000000-0000-0000-0000-000000000000}"


def creation_stamp() -> datetime:
    """The time stamped into camcad's own drawings: ``SOURCE_DATE_EPOCH`` if set (and valid), else 2000-01-01.

    Returns
    -------
    datetime
        A time in UTC.

    Examples
    --------
    >>> import os
    >>> os.environ.pop("SOURCE_DATE_EPOCH", None) and None
    >>> creation_stamp().isoformat()
    '2000-01-01T00:00:00+00:00'
    """
    text = os.environ.get(STAMP_VARIABLE, "").strip()
    if text.isdigit():
        try:
            return datetime.fromtimestamp(int(text), tz=UTC)
        except (OverflowError, OSError, ValueError):
            pass
    return FIXED_STAMP


@contextmanager
def _fixed_ezdxf_stamps():
    """ezdxf writes constant metadata (no time, no random GUID) inside this block; logging kept quiet."""
    import ezdxf

    options = ezdxf.options
    previous = options.write_fixed_meta_data_for_testing
    quiet = logging.getLogger("ezdxf")
    level = quiet.level
    options.write_fixed_meta_data_for_testing = True
    quiet.setLevel(logging.ERROR)  # e.g. "$INSUNITS are not exported for DXF R12": nothing to report
    try:
        yield
    finally:
        options.write_fixed_meta_data_for_testing = previous
        quiet.setLevel(level)


def new_document(version: str = "R2000", **kwargs):
    """``ezdxf.new`` without its random GUIDs and time stamps (see ``save_document``).

    Parameters
    ----------
    version : str
        DXF version as ezdxf names it ("R12", "R2000", "AC1015", ...).
    **kwargs
        Passed to ``ezdxf.new`` (``setup``, ``units``).

    Returns
    -------
    ezdxf.document.Drawing
    """
    import ezdxf

    with _fixed_ezdxf_stamps():
        return ezdxf.new(version, **kwargs)


@dataclass(frozen=True)
class HeaderKeep:
    """The header variables of an input drawing, to be written back into a copy of it.

    ``names`` are the variables the input file holds (in its order); ``values`` their values as
    ezdxf read them (ezdxf ``HeaderVar`` objects). A copy keeps every one of them, also those ezdxf
    would drop because they do not belong to the DXF version it writes, except ``RECOMPUTED``.
    """

    names: tuple[str, ...]
    values: dict


_HEADER_SECTION = re.compile(rb"(?s)0\s*\r?\n\s*SECTION\s*\r?\n\s*2\s*\r?\n\s*HEADER\s*\r?\n"
                             rb"(.*?)\n\s*0\s*\r?\n\s*ENDSEC")


def header_snapshot(doc, raw: bytes | None) -> HeaderKeep:
    """The header variables of the DXF file ``raw`` as it holds them, for ``save_document`` to keep.

    The values are read from the file's bytes, not from the loaded document: ezdxf stamps a loaded
    document with the current time ($TDCREATE) and new GUIDs before anyone sees it.

    Parameters
    ----------
    doc : ezdxf.document.Drawing
        The document ezdxf loaded from ``raw`` (for its encoding; binary files: its header).
    raw : bytes or None
        The file's bytes (ASCII DXF); None for a binary file (then ezdxf's values are taken).

    Returns
    -------
    HeaderKeep
    """
    if raw is None:
        hdrvars = doc.header.hdrvars
        names = tuple(name for name in hdrvars if name not in STAMPED)
        return HeaderKeep(names, {name: hdrvars[name] for name in names})
    match = _HEADER_SECTION.search(raw)
    if match is None:
        return HeaderKeep((), {})
    import io

    from ezdxf.lldxf.tagger import ascii_tags_loader, tag_compiler
    from ezdxf.lldxf.tags import Tags
    from ezdxf.sections.header import HeaderSection

    text = match.group(1).decode(doc.encoding if doc.dxfversion < "AC1021" else "utf-8", errors="replace")
    try:
        tags = Tags([*tag_compiler(iter([*_section_start(), *ascii_tags_loader(io.StringIO(text, newline=None))]))])
        hdrvars = HeaderSection.load(tags).hdrvars
    except Exception:  # noqa: BLE001 - a header ezdxf cannot parse again: keep what the document holds
        hdrvars = {name: var for name, var in doc.header.hdrvars.items() if name not in STAMPED}
    return HeaderKeep(tuple(hdrvars), dict(hdrvars))


def _section_start():
    from ezdxf.lldxf.types import DXFTag

    return DXFTag(0, "SECTION"), DXFTag(2, "HEADER")


def dxf_text(doc, keep: HeaderKeep | None = None) -> str:
    """The ASCII DXF of ``doc``, the same text every time for the same document.

    - ``keep`` given (a copy of a user's drawing): every header variable of the input is written
      with the input's value — its creation and update times and GUIDs included — except
      $ACADVER (the version ezdxf writes), $HANDSEED (the next free handle), $DWGCODEPAGE (the
      encoding written) and $EXTMIN/$EXTMAX, recomputed from the model space;
    - otherwise (camcad's own drawing): times from ``creation_stamp()``, null GUIDs, extents
      recomputed.

    Parameters
    ----------
    doc : ezdxf.document.Drawing
    keep : HeaderKeep, optional

    Returns
    -------
    str
        The DXF text with ``\n`` line ends.
    """
    import io

    from ezdxf.lldxf.const import DXF12
    from ezdxf.lldxf.tagwriter import TagWriter
    from ezdxf.tools.juliandate import juliandate

    with _fixed_ezdxf_stamps():
        doc.commit_pending_changes()
        doc.update_all()
    header = doc.header
    if keep is not None:
        for name in keep.names:
            if name not in RECOMPUTED:
                header.hdrvars[name] = keep.values[name]
    missing = [name for name in STAMPED if keep is None or name not in keep.names]
    stamp = juliandate(creation_stamp().replace(tzinfo=None))
    for name in missing:
        if name in header.hdrvars or name in ("$TDCREATE", "$TDUPDATE", "$VERSIONGUID", "$FINGERPRINTGUID"):
            header[name] = NULL_GUID if name.endswith("GUID") else stamp
    _set_extents(doc, own=keep is None)
    version = doc.dxfversion
    handles = bool(header.get("$HANDLING", 0)) if version == DXF12 else True
    stream = io.StringIO()
    writer = TagWriter(stream, write_handles=handles, dxfversion=version)
    extra = () if keep is None else keep.names
    # the header goes out through _export_header; every other section as ezdxf writes it
    header.export_dxf = lambda tagwriter: _export_header(header, tagwriter, extra)
    try:
        doc.export_sections(writer)
    finally:
        del header.export_dxf  # back to the class's method
    return stream.getvalue()


def save_document(doc, path: str | Path, *, keep: HeaderKeep | None = None, crlf: bool = False) -> Path:
    """Write ``doc`` as ASCII DXF to ``path``: atomically, in its own encoding, byte-deterministic.

    Parameters
    ----------
    doc : ezdxf.document.Drawing
    path : str or Path
    keep : HeaderKeep, optional
        The input's header to keep (a copy of a user's drawing); see ``dxf_text``.
    crlf : bool
        Write CR LF line ends (as the input had) instead of LF.

    Returns
    -------
    Path
        ``path``.
    """
    text = dxf_text(doc, keep)
    if crlf:
        text = text.replace("\n", "\r\n")
    data = text.encode(doc.output_encoding, errors="dxfreplace")
    return write_atomic(path, lambda tmp: tmp.write_bytes(data))


def _set_extents(doc, own: bool = True) -> None:
    """$EXTMIN/$EXTMAX from what the model space draws (ezdxf keeps ±1e20 where it does not know them).

    Geometry is bounded by ezdxf's fast bounding boxes. In camcad's own drawings (``own``) the entities
    camcad writes are bounded from their own numbers instead (``_own_box``: vertices widened by each
    arc's sagitta, circles, lines, spline control points; TEXT and MTEXT by their insert point, height
    and character count, ``_text_box``), because ezdxf's bounding boxes convert every polyline to a
    path and its text bounds load and parse a TrueType font (25 ms and 68 ms against 2 ms for the
    default profile); the extents only tell a CAD program where to zoom on opening, and a box that is a
    little generous does no harm. A copy of a user's drawing is bounded by ezdxf throughout.
    """
    msp = doc.modelspace()
    corners: list = []
    others = []
    for entity in msp:
        text = entity.dxftype() in ("TEXT", "MTEXT")
        pair = (_text_box(entity) if text else _own_box(entity)) if own else None
        if pair is not None:
            corners.extend(pair)
        elif not (own and text):
            others.append(entity)
    if not others:
        if corners:
            low = np.min(np.asarray(corners, dtype=float), axis=0)
            high = np.max(np.asarray(corners, dtype=float), axis=0)
            _store_extents(doc, msp, tuple(low), tuple(high))
        return
    from ezdxf import bbox

    try:
        box = bbox.extents(others, fast=True)
    except Exception:  # noqa: BLE001 - an entity ezdxf cannot bound (an invalid leader) is left out
        box = bbox.BoundingBox()
        for entity in others:
            try:
                box.extend(bbox.extents([entity], fast=True))
            except Exception:  # noqa: BLE001
                continue
    if corners:
        box.extend(corners)
    if box.has_data:
        _store_extents(doc, msp, tuple(box.extmin), tuple(box.extmax))


def _store_extents(doc, msp, low: tuple, high: tuple) -> None:
    if all(math.isfinite(float(v)) for v in (*low, *high)):
        low = tuple(float(v) for v in low)
        high = tuple(float(v) for v in high)
        doc.header["$EXTMIN"] = low
        doc.header["$EXTMAX"] = high
        if doc.dxfversion > "AC1009":  # R12 layouts have no such attributes
            msp.dxf.extmin, msp.dxf.extmax = low, high


def _own_box(entity) -> list[tuple[float, float, float]] | None:
    """Two corners bounding an entity of the kinds camcad writes (None for any other kind).

    A polyline's arcs (bulge b over a chord c) stray at most their sagitta |b|·c/2 from the chord, so the
    vertices' box widened by the largest sagitta holds the curve; a spline lies in its control points'
    convex hull."""
    kind = entity.dxftype()
    if kind == "LWPOLYLINE":   # ezdxf holds the vertices as rows x, y, start width, end width, bulge
        rows = np.asarray(entity.lwpoints.values, dtype=float).reshape(-1, 5)
        xy, bulge = rows[:, :2], rows[:, 4]
    elif kind == "POLYLINE" and not entity.is_3d_polyline and not entity.is_poly_face_mesh \
            and not entity.is_polygon_mesh:
        rows = np.asarray([(v.dxf.location.x, v.dxf.location.y, v.dxf.bulge) for v in entity.vertices],
                          dtype=float).reshape(-1, 3)
        xy, bulge = rows[:, :2], rows[:, 2]
    elif kind == "CIRCLE":
        (x, y, z), r = entity.dxf.center, float(entity.dxf.radius)
        return [(x - r, y - r, z), (x + r, y + r, z)]
    elif kind == "LINE":
        return [tuple(entity.dxf.start), tuple(entity.dxf.end)]
    elif kind == "SPLINE":
        xy = np.asarray(entity.control_points, dtype=float).reshape(-1, 3)[:, :2]
        bulge = np.zeros(len(xy))
    else:
        return None
    if len(xy) == 0:
        return []
    chord = np.hypot(*(np.roll(xy, -1, axis=0) - xy).T)     # each vertex to the next (the last to the first)
    reach = float(np.max(np.abs(bulge) * chord / 2.0))
    low, high = xy.min(axis=0) - reach, xy.max(axis=0) + reach
    return [(float(low[0]), float(low[1]), 0.0), (float(high[0]), float(high[1]), 0.0)]


#: width of a character as a fraction of the text height (generous: most CAD fonts are narrower)
CHAR_WIDTH = 1.0


def _text_box(entity) -> list[tuple[float, float, float]] | None:
    """Two corners bounding a TEXT or MTEXT: its run of characters from the insert point when it is
    horizontal and left-aligned, else a square of that length around the insert point."""
    try:
        x, y, z = (float(v) for v in entity.dxf.insert)
        if entity.dxftype() == "MTEXT":
            height = float(entity.dxf.get("char_height", 2.5))
            lines = entity.text.replace("\\P", "\n").splitlines() or [""]
            length = max(len(line) for line in lines) * height * CHAR_WIDTH
            depth = len(lines) * height * 1.7
            plain = entity.dxf.get("attachment_point", 1) == 1 and not entity.dxf.get("rotation", 0.0)
            if plain:
                return [(x, y - depth, z), (x + length, y, z)]
        else:
            height = float(entity.dxf.get("height", 2.5))
            length = len(entity.dxf.get("text", "")) * height * CHAR_WIDTH * float(entity.dxf.get("width", 1.0))
            plain = (not entity.dxf.get("rotation", 0.0) and not entity.dxf.get("halign", 0)
                     and not entity.dxf.get("valign", 0))
            if plain:
                return [(x, y - 0.3 * height, z), (x + length, y + height, z)]
    except (TypeError, ValueError, AttributeError):
        return None
    reach = max(length, height)
    if not all(math.isfinite(v) for v in (x, y, z, reach)):
        return None
    return [(x - reach, y - reach, z), (x + reach, y + reach, z)]


def _export_header(header, tagwriter, extra: tuple[str, ...]) -> None:
    """ezdxf's header export, plus the input's variables ezdxf does not write for this version."""
    from ezdxf.sections.header import HeaderVar, header_vars_by_priority
    from ezdxf.sections.headervars import HEADER_VAR_MAP, version_specific_group_code

    version = tagwriter.dxfversion
    tagwriter.write_str("  0\nSECTION\n  2\nHEADER\n")
    saved = header["$ACADVER"]
    header["$ACADVER"] = version
    written = set()
    for name, value in header_vars_by_priority(header.hdrvars, version):
        if name == "$HANDSEED" and not tagwriter.write_handles and name not in extra:
            continue
        if value.value is None:
            continue
        code = version_specific_group_code(name, version)
        if code != value.code:
            value = HeaderVar((code, value.value))
        tagwriter.write_tag2(9, name)
        tagwriter.write_str(str(value))
        written.add(name)
        if name == "$LASTSAVEDBY":
            header.custom_vars.write(tagwriter)
    for name in extra:
        value = header.hdrvars.get(name)
        if name in written or value is None or value.value is None:
            continue
        if name in HEADER_VAR_MAP and not _fits(HEADER_VAR_MAP[name], version) and name in RECOMPUTED:
            continue
        tagwriter.write_tag2(9, name)
        tagwriter.write_str(str(value))
    header["$ACADVER"] = saved
    tagwriter.write_str("  0\nENDSEC\n")


def _fits(vardef, version: str) -> bool:
    return vardef.mindxf <= version <= vardef.maxdxf
