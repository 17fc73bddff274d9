"""Reading a drawing: open any DXF (ASCII, binary, damaged) through ezdxf and list its candidate curves.

What a designer's drawing may hold (see ../shared/dxf-interop.md for the traps): the law as an
LWPOLYLINE, a 2D POLYLINE (bulges are arcs, flattened exactly), a chain of LINEs (and ARCs)
joined end to end, or a SPLINE (flattened to a stated tolerance); and around it axes, a grid,
text and dimensions. Block references are exploded. All coordinates are WCS, drawing units.
"""

from __future__ import annotations

import io
import logging
import math
import re
from collections import Counter
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from camcad.errors import CamcadError

CURVE_TYPES = ("LWPOLYLINE", "POLYLINE", "SPLINE", "LINE", "ARC")
MAX_BLOCK_DEPTH = 16
#: default flattening tolerance of splines and arcs, as a fraction of the entity's size
DEFAULT_FLATTEN_FRACTION = 1e-5
#: default end-to-end join tolerance of LINE/ARC chains, as a fraction of the drawing's size
DEFAULT_JOIN_FRACTION = 1e-6


@dataclass(frozen=True)
class Curve:
    """One candidate curve of a drawing, as a polyline in drawing order (WCS, drawing units).

    ``editable`` means each point is one of the entity's own vertices (LWPOLYLINE or POLYLINE
    without bulges, LINE chain), so a corrected law can be written back vertex for vertex;
    otherwise the points come from flattening (bulges, SPLINE, ARCs) within ``flatten_tol``.
    ``vertex_refs`` (LINE chains only): for each point, the (handle, "start"|"end") LINE ends at it.
    """

    points: np.ndarray
    kind: str
    handle: str
    layer: str
    editable: bool
    closed: bool = False
    flatten_tol: float = 0.0
    handles: tuple[str, ...] = ()
    vertex_refs: tuple[tuple[tuple[str, str], ...], ...] = ()
    hidden: bool = False  # on a layer that is off or frozen (as camcad's kept originals are)

    @property
    def label(self) -> str:
        return f"{self.kind} {self.handle} on layer {self.layer}"

    @property
    def x_range(self) -> float:
        return float(np.ptp(self.points[:, 0])) if len(self.points) else 0.0


@dataclass(frozen=True)
class Drawing:
    """An opened drawing: the ezdxf document, how it was loaded, and what ezdxf had to repair."""

    path: Path
    doc: object
    binary: bool
    recovered: bool
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class CurveSet:
    curves: tuple[Curve, ...]
    entity_counts: Counter = field(default_factory=Counter)
    notes: tuple[str, ...] = ()


# ---------------------------------------------------------------------------------------------
# Opening
# ---------------------------------------------------------------------------------------------

@contextmanager
def ezdxf_messages():
    """Collect what ezdxf logs while reading (repairs of a damaged file) instead of printing it.

    Yields a list that fills with the messages; the logger is restored afterwards.
    """
    messages: list[str] = []

    class _Collect(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            messages.append(" ".join(record.getMessage().split()))

    logger = logging.getLogger("ezdxf")
    handler = _Collect(level=logging.WARNING)
    propagate = logger.propagate
    logger.addHandler(handler)
    logger.propagate = False
    try:
        yield messages
    finally:
        logger.removeHandler(handler)
        logger.propagate = propagate


def summarise_messages(messages: list[str], limit: int = 3) -> list[str]:
    """ezdxf's repair messages as notes: the first few, then a count."""
    notes = [f"ezdxf: {m}" for m in messages[:limit]]
    if len(messages) > limit:
        notes.append(f"ezdxf: ... and {len(messages) - limit} more repair messages")
    return notes

_ACADVER = re.compile(rb"\$ACADVER")
_SUBCLASS = re.compile(rb"(?m)^\s*100\s*\r?\n\s*AcDb")


def open_drawing(path: str | Path) -> Drawing:
    """Load a DXF file with ezdxf: ASCII or binary; a damaged file goes through ezdxf's recover.

    Files with R2000 entities but no $ACADVER (ENTITIES-only excerpts) get $ACADVER = AC1015
    injected before loading, because ezdxf would otherwise read them as R12 and silently drop
    their subclass data (closed flags, widths, spline degree) — dxf-interop.md, trap 1.
    What ezdxf logs about repairs becomes the drawing's notes.
    """
    with ezdxf_messages() as messages:
        drawing = _open_drawing(path)
    if messages:
        drawing = replace(drawing, notes=drawing.notes + tuple(summarise_messages(messages)))
    return drawing


def _open_drawing(path: str | Path) -> Drawing:
    import ezdxf
    from ezdxf.lldxf.validator import dwg_version, is_binary_dxf_file

    path = Path(path)
    where = str(path)
    if not path.exists():
        raise CamcadError("file not found", where, "check the path")
    if path.is_dir():
        raise CamcadError("is a directory, not a DXF file", where, "give the drawing's file name")
    raw = path.read_bytes()
    if not raw.strip():
        raise CamcadError("the file is empty", where, "save the drawing again from your CAD program")
    if is_binary_dxf_file(str(path)):
        try:
            doc = ezdxf.readfile(str(path))
        except Exception as err:  # noqa: BLE001 - ezdxf raises several types for damaged files
            raise CamcadError(f"damaged binary DXF ({_short(err)})", where,
                              "save the drawing again as ASCII DXF") from None
        return Drawing(path, doc, binary=True, recovered=False)
    if dwg_version(str(path)) is not None:
        raise CamcadError("this is a DWG file, not DXF", where,
                          "save it as DXF (ASCII) from your CAD program")
    if not _looks_like_dxf(raw):
        raise CamcadError("not a DXF file (no '0 / SECTION' group found)", where,
                          "give a DXF drawing, or a .csv/.txt table of angle and acceleration")
    if not _ACADVER.search(raw) and _SUBCLASS.search(raw):
        return _recover(_inject_acadver(raw), where,
                        first_note="no $ACADVER in the file but R2000 entities: read as AC1015")
    try:
        doc = ezdxf.read(io.StringIO(_decode(raw), newline=None))
    except Exception:  # noqa: BLE001 - fall back to recover for any structural damage
        return _recover(raw, where, first_note="the file is damaged; ezdxf's recover repaired it")
    return Drawing(path, doc, binary=False, recovered=False)


def _recover(raw: bytes, where: str, first_note: str) -> Drawing:
    from ezdxf import recover

    try:
        doc, auditor = recover.read(io.BytesIO(raw))
    except Exception as err:  # noqa: BLE001
        raise CamcadError(f"damaged DXF that ezdxf cannot repair ({_short(err)})", where,
                          "open and save it again in your CAD program, or export the law as a table") from None
    notes = [first_note]
    fixes = getattr(auditor, "fixes", [])
    errors = getattr(auditor, "errors", [])
    if fixes or errors:
        notes.append(f"auditor: {len(fixes)} fixes, {len(errors)} unfixed errors")
        for entry in list(fixes)[:5] + list(errors)[:5]:
            message = getattr(entry, "message", str(entry))
            notes.append(f"auditor: {' '.join(str(message).split())}")
    return Drawing(Path(where), doc, binary=False, recovered=True, notes=tuple(notes))


def _decode(raw: bytes) -> str:
    # ezdxf detects the code page from the header when reading a file; the law's coordinates
    # are ASCII in any code page, so a lossless byte-preserving decode is enough here.
    return raw.decode("utf-8", errors="surrogateescape")


def _looks_like_dxf(raw: bytes) -> bool:
    from ezdxf.lldxf.validator import is_dxf_stream

    try:
        return is_dxf_stream(io.StringIO(_decode(raw[:1_000_000]), newline=None))
    except Exception:  # noqa: BLE001
        return False


def _inject_acadver(raw: bytes) -> bytes:
    newline = b"\r\n" if b"\r\n" in raw[:4096] else b"\n"
    header = newline.join([b"0", b"SECTION", b"2", b"HEADER", b"9", b"$ACADVER", b"1", b"AC1015",
                           b"0", b"ENDSEC", b""])
    match = re.search(rb"(?m)^\s*0\s*\r?\n\s*SECTION\s*\r?\n\s*2\s*\r?\n\s*HEADER", raw)
    if match:  # a HEADER without $ACADVER: add the variable into it
        end = raw.index(b"HEADER", match.start()) + len(b"HEADER")
        return raw[:end] + newline + b"9" + newline + b"$ACADVER" + newline + b"1" + newline + b"AC1015" + raw[end:]
    first = re.search(rb"(?m)^\s*0\s*\r?\n\s*SECTION", raw)
    at = first.start() if first else 0
    return raw[:at] + header + raw[at:]


def _short(err: Exception) -> str:
    text = " ".join(str(err).split()) or type(err).__name__
    return text[:160]


# ---------------------------------------------------------------------------------------------
# Curves
# ---------------------------------------------------------------------------------------------

def collect_curves(drawing: Drawing, *, flatten_tol: float | None = None,
                   join_tol: float | None = None) -> CurveSet:
    """Every open or closed curve of the model space (blocks exploded), as polylines.

    flatten_tol: largest distance (drawing units) between a SPLINE/arc and its flattening;
        default 1e-5 × the entity's size.
    join_tol: distance (drawing units) within which LINE/ARC ends are joined into a chain;
        default 1e-6 × the size of all LINE/ARC geometry.
    """
    counts: Counter = Counter()
    notes: list[str] = []
    curves: list[Curve] = []
    pieces: list[tuple[str, str, str, np.ndarray]] = []  # (kind, handle, layer, points) of LINE/ARC
    with ezdxf_messages() as messages:
        _gather(drawing, counts, notes, curves, pieces, flatten_tol)
    notes.extend(summarise_messages(messages))
    with ezdxf_messages() as messages:
        curves.extend(_chains(pieces, join_tol))
    notes.extend(summarise_messages(messages))
    hidden = _hidden_layers(drawing.doc)
    curves = [replace(c, hidden=c.layer.upper() in hidden) for c in curves]
    return CurveSet(tuple(curves), counts, tuple(notes))


def _hidden_layers(doc) -> set[str]:
    names = set()
    for layer in doc.layers:
        try:
            if not layer.is_on() or layer.is_frozen():
                names.add(layer.dxf.name.upper())
        except Exception:  # noqa: BLE001 - a damaged layer table entry hides nothing
            continue
    return names


def _gather(drawing, counts, notes, curves, pieces, flatten_tol) -> None:
    for entity, handle in _model_entities(drawing.doc):
        kind = entity.dxftype()
        counts[kind] += 1
        if kind not in CURVE_TYPES:
            continue
        try:
            layer = str(entity.dxf.get("layer", "0"))
        except Exception:  # noqa: BLE001 - very old entity types have no layer attribute
            layer = "0"
        try:
            if kind == "LWPOLYLINE":
                curves.append(_lwpolyline_curve(entity, handle, layer, flatten_tol))
            elif kind == "POLYLINE":
                curve = _polyline_curve(entity, handle, layer, flatten_tol)
                if curve is not None:
                    curves.append(curve)
            elif kind == "SPLINE":
                curves.append(_spline_curve(entity, handle, layer, flatten_tol))
            elif kind == "LINE":
                start, end = entity.dxf.start, entity.dxf.end
                ends = _checked(np.array([[start.x, start.y], [end.x, end.y]]))
                pieces.append(("LINE", handle, layer, ends))
            elif kind == "ARC":
                pieces.append(("ARC", handle, layer, _checked(_arc_points(entity, flatten_tol))))
        except CamcadError:
            raise
        except Exception as err:  # noqa: BLE001 - a malformed entity is skipped and reported
            notes.append(f"{kind} {handle} on layer {layer} skipped: {_short(err)}")


def _model_entities(doc):
    """(entity, handle) for every model-space entity; INSERTs are exploded (handle of the INSERT)."""
    def walk(entity, handle, depth):
        if entity.dxftype() == "INSERT":
            if depth >= MAX_BLOCK_DEPTH:
                return
            try:
                children = list(entity.virtual_entities())
            except Exception:  # noqa: BLE001 - a broken block reference holds no usable curve
                return
            for child in children:
                yield from walk(child, handle, depth + 1)
        else:
            yield entity, handle

    for entity in doc.modelspace():
        handle = str(entity.dxf.get("handle", "") or "?")
        yield from walk(entity, handle, 0)


#: coordinates beyond this magnitude are damage, not drawing (and overflow any distance computation)
MAX_COORDINATE = 1e100


def _checked(points: np.ndarray) -> np.ndarray:
    """The points, or ValueError naming the first vertex with a NaN, infinite or absurdly large coordinate."""
    finite = np.isfinite(points).all(axis=1)
    if not finite.all():
        index = int(np.flatnonzero(~finite)[0])
        raise ValueError(f"vertex {index} has a non-finite coordinate ({points[index, 0]}, {points[index, 1]}); "
                         "fix or delete that vertex in your CAD program")
    huge = (np.abs(points) > MAX_COORDINATE).any(axis=1)
    if huge.any():
        index = int(np.flatnonzero(huge)[0])
        raise ValueError(f"vertex {index} has an out-of-range coordinate ({points[index, 0]:.3g}, "
                         f"{points[index, 1]:.3g}); fix or delete that vertex in your CAD program")
    return points


def _size(points: np.ndarray) -> float:
    if len(points) == 0:
        return 0.0
    span = np.ptp(points, axis=0)
    return float(math.hypot(span[0], span[1]))


def _tolerance(points: np.ndarray, flatten_tol: float | None) -> float:
    if flatten_tol is not None:
        return flatten_tol
    return max(_size(points) * DEFAULT_FLATTEN_FRACTION, 1e-12)


def _lwpolyline_curve(entity, handle: str, layer: str, flatten_tol: float | None) -> Curve:
    points = np.array([[p.x, p.y] for p in entity.vertices_in_wcs()], dtype=float).reshape(-1, 2)
    points = _checked(points)
    bulges = [b for *_, b in entity.get_points("xyb")]
    closed = bool(entity.closed)
    if any(b for b in bulges):
        tol = _tolerance(points, flatten_tol)
        return Curve(_flatten_virtual(entity, tol, points), "LWPOLYLINE", handle, layer,
                     editable=False, closed=closed, flatten_tol=tol, handles=(handle,))
    return Curve(points, "LWPOLYLINE", handle, layer, editable=True, closed=closed, handles=(handle,))


def _polyline_curve(entity, handle: str, layer: str, flatten_tol: float | None) -> Curve | None:
    if not (entity.is_2d_polyline or entity.is_3d_polyline):
        return None  # polyface and polygon meshes are surfaces, not curves
    if entity.is_2d_polyline:
        points = np.array([[p.x, p.y] for p in entity.points_in_wcs()], dtype=float).reshape(-1, 2)
    else:
        xyz = np.array([[p.x, p.y, p.z] for p in entity.points()], dtype=float).reshape(-1, 3)
        if len(xyz) and np.ptp(xyz[:, 2]) > 1e-9 * max(_size(xyz[:, :2]), 1.0):
            raise ValueError("a 3D polyline whose z varies is not a law drawn in the plane")
        points = xyz[:, :2]
    points = _checked(points)
    closed = bool(entity.is_closed)
    bulges = [v.dxf.get("bulge", 0.0) for v in entity.vertices]
    if any(b for b in bulges):
        tol = _tolerance(points, flatten_tol)
        return Curve(_flatten_virtual(entity, tol, points), "POLYLINE", handle, layer,
                     editable=False, closed=closed, flatten_tol=tol, handles=(handle,))
    return Curve(points, "POLYLINE", handle, layer, editable=True, closed=closed, handles=(handle,))


def _flatten_virtual(entity, tol: float, vertices: np.ndarray) -> np.ndarray:
    """Exact flattening of a polyline with bulges: its virtual LINEs and ARCs, arcs by sagitta."""
    out: list[np.ndarray] = [vertices[:1]]
    for part in entity.virtual_entities():
        if part.dxftype() == "LINE":
            seg = np.array([[part.dxf.start.x, part.dxf.start.y], [part.dxf.end.x, part.dxf.end.y]])
        else:
            seg = _arc_points(part, tol)
        if np.hypot(*(seg[-1] - out[-1][-1])) < np.hypot(*(seg[0] - out[-1][-1])):
            seg = seg[::-1]  # virtual ARCs always run counter-clockwise; follow the polyline instead
        out.append(seg[1:])
    return np.concatenate(out)


def _arc_points(arc, tol: float | None) -> np.ndarray:
    radius = float(arc.dxf.radius)
    if tol is None:
        tol = max(radius * DEFAULT_FLATTEN_FRACTION, 1e-12)
    sagitta = min(tol, radius) if radius > 0 else tol
    points = np.array([[p.x, p.y] for p in arc.flattening(sagitta)], dtype=float)
    return points.reshape(-1, 2)


def _spline_curve(entity, handle: str, layer: str, flatten_tol: float | None) -> Curve:
    frame = [tuple(p)[:2] for p in entity.control_points] or [tuple(p)[:2] for p in entity.fit_points]
    frame_points = np.array(frame, dtype=float).reshape(-1, 2)
    _checked(frame_points)
    tol = _tolerance(frame_points, flatten_tol)
    points = np.array([[p.x, p.y] for p in entity.flattening(tol)], dtype=float).reshape(-1, 2)
    return Curve(_checked(points), "SPLINE", handle, layer, editable=False,
                 closed=bool(entity.closed), flatten_tol=tol, handles=(handle,))


def _chains(pieces: list[tuple[str, str, str, np.ndarray]], join_tol: float | None) -> list[Curve]:
    """Join LINE/ARC pieces of the same layer end to end into chains (a node of degree > 2 ends a chain)."""
    from scipy.cluster.hierarchy import DisjointSet
    from scipy.spatial import cKDTree

    if not pieces:
        return []
    ends = np.array([[p[3][0], p[3][-1]] for p in pieces]).reshape(-1, 2)  # 2 ends per piece
    if join_tol is None:
        join_tol = max(_size(ends) * DEFAULT_JOIN_FRACTION, 1e-12)
    layers = [p[2] for p in pieces]
    nodes = DisjointSet(range(len(ends)))
    for i, j in cKDTree(ends).query_pairs(join_tol):
        if layers[i // 2] == layers[j // 2]:
            nodes.merge(i, j)
    node_of = np.array([nodes.__getitem__(i) for i in range(len(ends))])
    incident: dict[int, list[int]] = {}
    for end_index, node in enumerate(node_of):
        incident.setdefault(int(node), []).append(end_index)
    used = np.zeros(len(pieces), dtype=bool)
    curves: list[Curve] = []

    def follow(start_end: int) -> list[int]:
        """End indices (piece*2 + side) of the chain leaving through start_end's piece."""
        sequence = []
        end_index = start_end
        while True:
            piece = end_index // 2
            if used[piece]:
                break
            used[piece] = True
            sequence.append(end_index)
            other = end_index ^ 1
            node = int(node_of[other])
            nxt = [e for e in incident[node] if e != other]
            if len(incident[node]) != 2 or not nxt or used[nxt[0] // 2]:
                break
            end_index = nxt[0]
        return sequence

    starts = [e for e in range(len(ends)) if len(incident[int(node_of[e])]) != 2]
    for start in starts + list(range(len(ends))):
        if used[start // 2]:
            continue
        sequence = follow(start)
        closed = len(sequence) > 1 and node_of[sequence[0]] == node_of[sequence[-1] ^ 1]
        points: list[np.ndarray] = []
        refs: list[list[tuple[str, str]]] = []
        editable = True
        handles = []
        for end_index in sequence:
            kind, handle, layer, pts = pieces[end_index // 2]
            handles.append(handle)
            forward = end_index % 2 == 0
            pts = pts if forward else pts[::-1]
            if kind == "LINE":
                first, last = ("start", "end") if forward else ("end", "start")
                if not points:
                    points.append(pts[:1])
                    refs.append([(handle, first)])
                else:
                    refs[-1].append((handle, first))
                points.append(pts[1:])
                refs.append([(handle, last)])
            else:
                editable = False
                if not points:
                    points.append(pts[:1])
                    refs.append([])
                points.append(pts[1:])
                refs.extend([] for _ in range(len(pts) - 1))
        layer = pieces[sequence[0] // 2][2]
        kind = "LINE chain" if editable else "LINE/ARC chain"
        curves.append(Curve(np.concatenate(points), kind, handles[0], layer, editable=editable,
                            closed=bool(closed), flatten_tol=0.0 if editable else (join_tol or 0.0),
                            handles=tuple(handles),
                            vertex_refs=tuple(tuple(r) for r in refs) if editable else ()))
    return curves
