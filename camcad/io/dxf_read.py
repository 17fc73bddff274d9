"""Reading a drawing: open any DXF (ASCII, binary, damaged, UTF-8 or UTF-16) and list its drawn pieces.

What a designer's drawing may hold (docs/reading.md says how camcad reads each): the law as one
entity (LWPOLYLINE, POLYLINE with bulges, SPLINE with fit or control points) or as a chain of
pieces of any kind joined end to end (LINE, ARC, ELLIPSE arcs, polylines, splines), and around it
axes, a grid, a frame, text and dimensions. Every curve entity of the model space becomes a
:class:`Piece`; block references are exploded within a budget. Which pieces form the law is
decided by :mod:`camcad.io.chain`; the result is a :class:`Curve`. All coordinates are WCS, in
drawing units.
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
from typing import TYPE_CHECKING

import numpy as np

from camcad.arrays import unique
from camcad.errors import CamcadError
from camcad.io.input_file import decode_text, read_input, utf16_without_bom

if TYPE_CHECKING:
    from ezdxf.document import Drawing as EzdxfDocument

#: entity types that can hold (a piece of) the law
#: the block in which camcad fix keeps the original law (io.law_write.ORIGINAL_BLOCK)
KEPT_ORIGINAL_BLOCK = "CAMCAD_ORIGINAL"
CURVE_TYPES = ("LWPOLYLINE", "POLYLINE", "SPLINE", "LINE", "ARC", "ELLIPSE")
#: block references nest at most this deep
MAX_BLOCK_DEPTH = 16
#: block references expand to at most this many curve pieces in all
MAX_BLOCK_ENTITIES = 10_000
#: block references (each cell of a MINSERT, each nested reference) are placed at most this many times in all
MAX_BLOCK_PLACEMENTS = 100_000
#: default flattening tolerance of splines and arcs, as a fraction of the entity's size
DEFAULT_FLATTEN_FRACTION = 1e-5
#: coordinates beyond this magnitude are damage, not drawing (and overflow any distance computation)
MAX_COORDINATE = 1e100
#: names of $INSUNITS values (the DXF reference's table, the common ones)
UNIT_NAMES = {0: "unitless", 1: "inches", 2: "feet", 3: "miles", 4: "millimetres", 5: "centimetres",
              6: "metres", 7: "kilometres", 8: "microinches", 9: "mils", 10: "yards", 11: "angstroms",
              12: "nanometres", 13: "microns", 14: "decimetres", 15: "decametres", 16: "hectometres",
              17: "gigametres", 18: "astronomical units", 19: "light years", 20: "parsecs"}

#: drawing units a law's lengths are read in and converted from where the law meets the follower (mm):
#: $INSUNITS -> (the unit's short name, mm per unit)
LENGTH_UNITS = {1: ("in", 25.4), 5: ("cm", 10.0)}


@dataclass(frozen=True)
class Piece:
    """One drawn curve entity as a polyline, in the entity's own direction (WCS, drawing units).

    Attributes
    ----------
    points : ndarray, shape (n, 2)
        The entity's vertices (``exact``) or its flattening within ``flatten_tol``.
    kind : str
        DXF type: LINE, ARC, ELLIPSE, LWPOLYLINE, POLYLINE or SPLINE.
    handle : str
        The entity's handle; for an entity inside a block, the handle of the model-space INSERT.
    layer : str
        Its layer.
    index : int
        Position of the entity (or of its INSERT) in model-space order: finds the entity again
        in a file whose handles are not unique.
    exact : bool
        ``points`` are the entity's own vertices, point i = vertex i (LINE: 0 start, 1 end;
        LWPOLYLINE and POLYLINE without bulges), so a new position can be written back into them.
    closed : bool
        The entity is closed (closed polyline or spline, full ellipse or circle-like arc).
    flatten_tol : float
        Largest distance between the entity and ``points`` (0 when exact), drawing units.
    in_block : bool
        The entity comes from a block reference (it cannot be edited in place).
    hidden : bool
        On a layer that is off or frozen.
    breakpoints : ndarray, shape (m, 2)
        The points the author placed: polyline vertices, LINE and arc ends, a spline's fit points
        (or, without them, the spline's points at its distinct knots).
    interpolating : bool
        A spline drawn through its ``breakpoints``: it has fit points, or it is a cubic of three or
        more spans that is C2 at its knots (an interpolating cubic spline, however it was saved).
    virtual : bool
        A piece the drawing implies but does not hold (a vertical jump between plateaus drawn without
        risers): it stands for no entity.
    sources : tuple of (str, int)
        (handle, model-space index) of the entities the piece stands for when it is not one entity of
        its own (the centre line of an outlined stroke stands for the outline's entities); empty: itself.
    layout : str
        The layout the entity is in: "" for the model space, else a paper-space layout's name (then
        ``index`` counts in that layout).
    """

    points: np.ndarray
    kind: str
    handle: str
    layer: str
    index: int = -1
    exact: bool = False
    closed: bool = False
    flatten_tol: float = 0.0
    in_block: bool = False
    hidden: bool = False
    breakpoints: np.ndarray | None = None
    interpolating: bool = False
    virtual: bool = False
    sources: tuple[tuple[str, int], ...] = ()
    layout: str = ""

    @property
    def label(self) -> str:
        return f"{self.kind} {self.handle} on layer {self.layer}"

    @property
    def entities(self) -> tuple[tuple[str, int], ...]:
        """(handle, model-space index) of the entities this piece stands for (none for a virtual piece)."""
        if self.virtual:
            return ()
        return self.sources or ((self.handle, self.index),)

    @property
    def x_range(self) -> float:
        return float(np.ptp(self.points[:, 0])) if len(self.points) else 0.0


@dataclass(frozen=True)
class Curve:
    """The law's curve as read: a polyline in drawing order, and how it maps to the drawn entities.

    This is the contract with the writers (``io.law_write.write_corrected_drawing``):

    - ``points`` (n, 2): the curve in WCS drawing units, point i in drawing order. A curve of one
      entity keeps the entity's own vertex order (it may run right to left); a chain of several
      pieces runs left to right.
    - ``editable`` is True in exactly two cases, and then each point is a vertex of its entity:
      (a) one LWPOLYLINE or POLYLINE without bulges, not from a block: point i is vertex i of the
      entity ``handles[0]`` (``entity_indices[0]`` in model-space order), ``len(points)`` equals
      its vertex count; ``vertex_refs`` is empty. (b) a chain of LINEs only, not from blocks:
      ``vertex_refs[i]`` lists the (handle, "start" | "end") LINE ends that sit at point i (two for
      an inner point, one at the chain's ends). Otherwise the points come from flattening (bulges,
      arcs, splines, ellipses), from a block, or from a chain mixing entity kinds; ``editable`` is
      False and the writer draws a new polyline.
    - ``vertex_refs`` is also filled, with ``editable`` False, for a chain of exact pieces of mixed
      kinds (LINEs and bulge-free polylines): a polyline vertex is referred to as (handle, k), k the
      vertex index (int). A writer that supports it may move those vertices in place.
    - ``handles``: every entity the curve uses, in chain order (duplicates possible for a block);
      ``entity_indices``: their positions in model-space order, which identify them even when the
      file's handles are not unique (use :func:`curve_entities`).
    - ``pieces`` and ``reversed_pieces``: the pieces in chain order and whether each is run against
      its own direction.
    - ``breakpoints``: the points the author placed along the curve, in curve order (see
      :class:`Piece`); ``layers``: the layers the curve's pieces are on.
    - ``layout``: "" when the curve is in the model space, else the paper-space layout it is drawn in
      (the model space held no curves); ``entity_indices`` then count in that layout.
    """

    points: np.ndarray
    kind: str
    handle: str
    layer: str
    editable: bool
    closed: bool = False
    flatten_tol: float = 0.0
    handles: tuple[str, ...] = ()
    vertex_refs: tuple[tuple[tuple[str, str | int], ...], ...] = ()
    hidden: bool = False
    pieces: tuple[Piece, ...] = ()
    reversed_pieces: tuple[bool, ...] = ()
    entity_indices: tuple[int, ...] = ()
    breakpoints: np.ndarray | None = None
    layers: tuple[str, ...] = ()

    @property
    def layout(self) -> str:
        """The layout the curve is drawn in: "" for the model space, else a paper-space layout's name."""
        return self.pieces[0].layout if self.pieces else ""

    @property
    def label(self) -> str:
        if len(self.pieces) <= 1:
            return f"{self.kind} {self.handle} on layer {self.layer}"
        return f"{self.kind} ({handles_text(self.handles)}) on layer{'s' if len(self.layers) > 1 else ''} " \
               f"{', '.join(self.layers)}"

    @property
    def x_range(self) -> float:
        return float(np.ptp(self.points[:, 0])) if len(self.points) else 0.0


@dataclass(frozen=True)
class Drawing:
    """An opened drawing: the ezdxf document, how it was loaded, and what ezdxf had to repair.

    ``insunits`` is the file's own $INSUNITS (None when the file does not state it; ezdxf reports
    its template's value for such files, dxf-interop.md trap 2).
    """

    path: Path
    doc: EzdxfDocument
    binary: bool
    recovered: bool
    notes: tuple[str, ...] = ()
    insunits: int | None = None
    encoding: str = ""


@dataclass(frozen=True)
class PieceSet:
    """Every curve piece of a drawing, what else it holds, and what reading it noted.

    ``layout`` is the layout the pieces come from ("" for the model space; a paper-space layout's
    name when the model space holds no curves); ``elsewhere`` counts the entities of every other
    layout that holds some ({layout name: Counter of entity types}).
    """

    pieces: tuple[Piece, ...]
    entity_counts: Counter = field(default_factory=Counter)
    notes: tuple[str, ...] = ()
    layout: str = ""
    elsewhere: dict = field(default_factory=dict)


def handles_text(handles, limit: int = 6) -> str:
    """A short list of handles: 'LINE 2A, 2B, 2C ... (40 entities)' style, without kinds.

    Examples
    --------
    >>> handles_text(["2A", "2B"])
    '2A, 2B'
    >>> handles_text([str(i) for i in range(10)], limit=3)
    '0, 1, 2 ... 9 (10 entities)'
    """
    unique = list(dict.fromkeys(handles))
    if len(unique) <= limit:
        return ", ".join(unique)
    return f"{', '.join(unique[:limit])} ... {unique[-1]} ({len(unique)} entities)"


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
            messages.append(" ".join(record.getMessage().split())[:200])

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
_BINARY_SENTINEL = b"AutoCAD Binary DXF"


def open_drawing(path: str | Path) -> Drawing:
    """Load a DXF file: ASCII or binary, UTF-8 (with or without BOM) or UTF-16; damaged files
    go through ezdxf's recover.

    Only regular files are read, at most ``input_file.MAX_INPUT_BYTES`` (FIFOs, devices and
    directories are refused at once). Files with R2000 entities but no $ACADVER (ENTITIES-only
    excerpts) get $ACADVER = AC1015 injected before loading, because ezdxf would otherwise read
    them as R12 and silently drop their subclass data (closed flags, widths, spline degree) —
    dxf-interop.md, trap 1. What ezdxf logs about repairs becomes the drawing's notes.

    Parameters
    ----------
    path : str or Path
        The drawing.

    Returns
    -------
    Drawing
        The ezdxf document and how it was read.

    Raises
    ------
    CamcadError
        Not a readable DXF file (one line: what, where, how to fix).
    """
    with ezdxf_messages() as messages:
        drawing = _open_drawing(path)
    if messages:
        drawing = replace(drawing, notes=drawing.notes + tuple(summarise_messages(messages)))
    return drawing


def _open_drawing(path: str | Path) -> Drawing:
    import ezdxf

    path = Path(path)
    where = str(path)
    raw = read_input(path, "a DXF drawing")
    if not raw.strip():
        raise CamcadError("the file is empty", where, "save the drawing again from your CAD program")
    if raw.startswith(_BINARY_SENTINEL):
        try:
            doc = ezdxf.readfile(str(path))  # a regular file, checked above; ezdxf reads binary by name
        except Exception as err:  # noqa: BLE001 - ezdxf raises several types for damaged files
            raise CamcadError(f"damaged binary DXF ({_short(err)})", where,
                              "save the drawing again as ASCII DXF") from None
        return Drawing(path, doc, binary=True, recovered=False, insunits=_stated_units(doc, True))
    if re.match(rb"AC10[0-3][0-9]", raw[:6]) or raw[:6] in (b"AC1.50", b"AC1.40", b"AC2.10", b"AC2.21", b"AC2.22"):
        raise CamcadError("this is a DWG file, not DXF", where, "save it as DXF (ASCII) from your CAD program")
    notes: list[str] = []
    encoding = ""
    if raw.startswith(b"\xef\xbb\xbf") or raw[:2] in (b"\xff\xfe", b"\xfe\xff") or utf16_without_bom(raw):
        text, encoding = decode_text(raw)
        notes.append({"utf-8-sig": "the file starts with a UTF-8 byte-order mark (ignored)"}.get(
            encoding, f"the file is {encoding.upper()} text; read as such"))
        raw = text.encode("utf-8", errors="surrogateescape")
    if not _looks_like_dxf(raw):
        raise CamcadError("not a DXF file (no '0 / SECTION' group found)", where,
                          "give a DXF drawing, or a .csv/.txt table of angle and acceleration")
    if not _ACADVER.search(raw) and _SUBCLASS.search(raw):
        drawing = _recover(_inject_acadver(raw), where,
                           first_note="no $ACADVER in the file but R2000 entities: read as AC1015")
        return replace(drawing, notes=tuple(notes) + drawing.notes, insunits=_raw_units(raw, drawing.doc),
                       encoding=encoding)
    try:
        doc = ezdxf.read(io.StringIO(_decode(raw), newline=None))
    except Exception:  # noqa: BLE001 - fall back to recover for any structural damage
        drawing = _recover(raw, where, first_note="the file is damaged; ezdxf's recover repaired it")
        return replace(drawing, notes=tuple(notes) + drawing.notes, insunits=_raw_units(raw, drawing.doc),
                       encoding=encoding)
    return Drawing(path, doc, binary=False, recovered=False, notes=tuple(notes), insunits=_raw_units(raw, doc),
                   encoding=encoding)


def _stated_units(doc, stated: bool) -> int | None:
    if not stated:
        return None
    try:
        value = doc.header.get("$INSUNITS", None)
        return None if value is None else int(value)
    except Exception:  # noqa: BLE001 - a damaged header states nothing
        return None


def _raw_units(raw: bytes, doc) -> int | None:
    return _stated_units(doc, b"$INSUNITS" in raw)


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
            notes.append(f"auditor: {' '.join(str(message).split())[:200]}")
    return Drawing(Path(where), doc, binary=False, recovered=True, notes=tuple(notes))


def _decode(raw: bytes) -> str:
    # the law's coordinates are ASCII in any code page, so a lossless byte-preserving decode is enough
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


def _short(err: Exception, limit: int = 120) -> str:
    text = " ".join(str(err).split()) or type(err).__name__
    return text if len(text) <= limit else text[: limit - 3] + "..."


def units_note(drawing: Drawing, scaled: bool) -> str:
    """What the drawing's units are and what camcad does with them (one note).

    x is never a length: it is mapped to the cycle (or is degrees with ``--x-deg``). y is the
    acceleration analog in the drawing's length unit per rad²: a drawing in inches or centimetres
    ($INSUNITS 1, 5; ``LENGTH_UNITS``) is read in that unit (in/rad², cm/rad²: ``check`` and ``fix``
    report its figures in it) and converted to mm where the law meets the follower (``profile``); any
    other unit is read as mm/rad² per drawing unit. ``--lift`` scales y to a rise in mm, and the
    units then do not matter.

    Parameters
    ----------
    drawing : Drawing
        The opened drawing.
    scaled : bool
        y is scaled by ``--lift`` (the units then do not matter at all).

    Returns
    -------
    str
        The note.
    """
    code = drawing.insunits
    if code is None:
        stated = "the drawing states no units ($INSUNITS absent)"
    else:
        stated = f"drawing units: {UNIT_NAMES.get(code, 'unknown')} ($INSUNITS {code})"
    if scaled:
        return f"{stated}; not used: x is mapped to the cycle and y is scaled by --lift"
    if code in (None, 0, 4):
        return f"{stated}; y is read as mm/rad² per drawing unit (--lift H scales it to a rise of H mm)"
    if code in LENGTH_UNITS:
        short, factor = LENGTH_UNITS[code]
        return (f"{stated}; y is read as {short}/rad² and the law's lengths are reported in {short} "
                f"(a profile converts them to mm, x {factor:g}; --lift H scales the rise to H mm instead)")
    return (f"{stated}; camcad does not convert them: y is read as mm/rad² per drawing unit "
            "(--lift H scales it to a rise of H mm)")


# ---------------------------------------------------------------------------------------------
# Pieces
# ---------------------------------------------------------------------------------------------

def collect_pieces(drawing: Drawing, *, flatten_tol: float | None = None, layout: str = "") -> PieceSet:
    """Every curve entity of the model space as a :class:`Piece` (block references exploded).

    A block's pieces are computed once per block definition and placed by each reference's
    transformation (nested references compose their matrices; an entity on layer 0 inside a
    block takes the reference's layer, as CAD programs draw it).

    Parameters
    ----------
    drawing : Drawing
        The opened drawing.
    flatten_tol : float, optional
        Largest distance (drawing units) between a SPLINE, ELLIPSE or arc and its flattening;
        default 1e-5 × the entity's size.
    layout : str
        "" for the model space, or a paper-space layout's name. When the model space holds no curve,
        the first paper-space layout (in tab order) that does is read instead, with a note.

    Returns
    -------
    PieceSet
        The pieces in model-space order, the count of every entity type, and notes (entities
        skipped and why, ezdxf's messages).

    Raises
    ------
    CamcadError
        Block references nested deeper than :data:`MAX_BLOCK_DEPTH`, a block that inserts itself,
        references expanding to more than :data:`MAX_BLOCK_ENTITIES` curve pieces or placed more than
        :data:`MAX_BLOCK_PLACEMENTS` times in all (MINSERT cells counted as rows × columns), all counted
        before any reference is expanded; a reference whose transformation is not finite or places a
        vertex out of range.
    """
    counts: Counter = Counter()
    notes: list[str] = []
    pieces: list[Piece] = []
    hidden = _hidden_layers(drawing.doc)
    zero = [0]
    blocks = _BlockCache(drawing, flatten_tol, notes, zero)
    space = drawing.doc.layouts.get(layout) if layout else drawing.doc.modelspace()
    with ezdxf_messages() as messages:
        blocks.check_budget(space)   # every reference counted before any is expanded
        for index, entity in enumerate(space):
            kind = entity.dxftype()
            handle = str(entity.dxf.get("handle", "") or "?")
            if kind == "INSERT":
                counts[kind] += 1
                for piece in blocks.place(entity, handle, index, counts):
                    pieces.append(replace(piece, hidden=piece.layer.upper() in hidden))
                continue
            counts[kind] += 1
            piece = _entity_piece(entity, kind, handle, flatten_tol, notes, zero, index, hidden)
            if piece is not None:
                pieces.append(piece)
        # the original laws that camcad fix kept in its unreferenced block: hidden candidates, found only
        # when asked for (--layer CAMCAD_ORIGINAL or --handle), so nothing the user drew is out of reach
        for block in drawing.doc.blocks:
            if not str(block.name).upper().startswith(KEPT_ORIGINAL_BLOCK):
                continue
            for entity in block:
                kind = entity.dxftype()
                handle = str(entity.dxf.get("handle", "") or "?")
                piece = _entity_piece(entity, kind, handle, flatten_tol, notes, zero, -1, None)
                if piece is not None:
                    pieces.append(replace(piece, hidden=True))
    if zero[0]:
        notes.append(f"{zero[0]} entit{'y' if zero[0] == 1 else 'ies'} of no length (a point, an arc of radius 0) "
                     "ignored")
    notes.extend(summarise_messages(messages))
    if layout:
        pieces = [replace(p, layout=layout) if p.index >= 0 else p for p in pieces]
        return PieceSet(tuple(pieces), counts, tuple(notes), layout)
    if any(p.index >= 0 for p in pieces):
        return PieceSet(tuple(pieces), counts, tuple(notes))
    # the model space holds no curve: the law may be drawn on a sheet
    elsewhere = {"Model": counts} if counts else {}
    found = None
    for name in _paper_layouts(drawing.doc):
        try:
            held = Counter(entity.dxftype() for entity in drawing.doc.layouts.get(name))
        except Exception:  # noqa: BLE001 - a layout ezdxf cannot read holds nothing here
            continue
        if held:
            elsewhere[name] = held
        if found is None and _holds_curves(held):
            sheet = collect_pieces(drawing, flatten_tol=flatten_tol, layout=name)
            if any(p.index >= 0 for p in sheet.pieces):
                found = sheet
    if found is None:
        return PieceSet(tuple(pieces), counts, tuple(notes), "", elsewhere)
    others = [n for n in elsewhere if n not in ("Model", found.layout) and _holds_curves(elsewhere[n])]
    note = (f"the model space holds no curves ({_counter_text(counts)}): the law is read from the paper-space "
            f"layout {found.layout!r}" + (f" (other layouts with curves: {', '.join(map(repr, others[:4]))})"
                                          if others else ""))
    return replace(found, notes=(note,) + found.notes, elsewhere=elsewhere)


def _paper_layouts(doc) -> list[str]:
    """The paper-space layouts' names in tab order."""
    try:
        return [name for name in doc.layouts.names_in_taborder() if name.upper() != "MODEL"]
    except Exception:  # noqa: BLE001 - a damaged layout table: none
        return []


def _holds_curves(counts: Counter) -> bool:
    return any(counts.get(kind) for kind in CURVE_TYPES + ("INSERT",))


def _counter_text(counts: Counter) -> str:
    if not counts:
        return "it is empty"
    return ", ".join(f"{n} {kind}" for kind, n in sorted(counts.items()))


def _entity_piece(entity, kind: str, handle: str, flatten_tol: float | None, notes: list[str],
                  zero: list[int], index: int = -1, hidden: set[str] | None = None) -> Piece | None:
    """The piece of one curve entity (None for other entities, and for a skipped one, noted)."""
    if kind not in CURVE_TYPES:
        return None
    try:
        layer = str(entity.dxf.get("layer", "0"))
    except Exception:  # noqa: BLE001 - very old entity types have no layer attribute
        layer = "0"
    off = hidden is not None and layer.upper() in hidden
    try:
        piece = _piece(entity, kind, handle, layer, flatten_tol, index, off)
    except CamcadError:
        raise
    except Exception as err:  # noqa: BLE001 - a malformed entity is skipped and reported
        notes.append(f"{kind} {handle} on layer {layer} skipped: {_short(err)}")
        return None
    if piece is None:
        return None
    if len(piece.points) < 2:
        if kind in ("LWPOLYLINE", "POLYLINE", "SPLINE"):
            notes.append(f"{kind} {handle} on layer {layer} skipped: it has {len(piece.points)} vertices; "
                         "a law needs at least 3")
        else:
            zero[0] += 1
        return None
    return piece


class _BlockCache:
    """Block definitions as pieces in block coordinates (each computed once), placed by matrices.

    What a reference expands to is counted first (``check_budget``): curve pieces and placements
    (a MINSERT's rows × columns from its header, a nested reference's count times its block's), so a
    32767 × 32767 MINSERT is refused in microseconds instead of being expanded cell by cell.
    """

    def __init__(self, drawing: Drawing, flatten_tol: float | None, notes: list[str], zero: list[int]) -> None:
        self.doc = drawing.doc
        self.where = str(drawing.path)
        self.flatten_tol = flatten_tol
        self.notes = notes
        self.zero = zero
        self.content: dict[str, tuple[list[Piece], list, Counter]] = {}
        self.sizes: dict[str, tuple[int, int]] = {}
        self.subtree_counts: dict[str, Counter] = {}
        self.matrices: dict[int, list[np.ndarray]] = {}

    def _content(self, name: str):
        """(pieces, [(child block name, INSERT entity, cells, child layer, handle)], entity counts) of a block;
        the children's matrices are not computed here (``place`` does, after the budget is checked)."""
        key = name.upper()
        if key not in self.content:
            block = self.doc.blocks.get(name)
            pieces: list[Piece] = []
            children = []
            counts: Counter = Counter()
            for entity in block if block is not None else ():
                kind = entity.dxftype()
                counts[kind] += 1
                if kind == "INSERT":
                    children.append((str(entity.dxf.get("name", "")), entity, _repeat(entity),
                                     str(entity.dxf.get("layer", "0")), str(entity.dxf.get("handle", "") or "?")))
                    continue
                piece = _entity_piece(entity, kind, name, self.flatten_tol, self.notes, self.zero)
                if piece is not None:
                    pieces.append(piece)
            self.content[key] = (pieces, children, counts)
        return self.content[key]

    def check_budget(self, entities) -> None:
        """Count what every reference among ``entities`` (the model space) expands to; refuse past the budgets."""
        pieces = placements = 0
        for entity in entities:
            if entity.dxftype() != "INSERT":
                continue
            handle = str(entity.dxf.get("handle", "") or "?")
            name = str(entity.dxf.get("name", ""))
            cells = _repeat(entity)
            inner_pieces, inner_placements = self._size(name, handle, 1, ())
            pieces += cells * inner_pieces
            placements += cells * (1 + inner_placements)
            what = f"INSERT {handle} of block {name[:40]}" + (f", a MINSERT of {_cells_text(entity)}" if cells > 1
                                                               else "")
            if pieces > MAX_BLOCK_ENTITIES:
                raise CamcadError(f"block references expand to more than {MAX_BLOCK_ENTITIES} curves (at least "
                                  f"{_count_text(pieces)}: {what})", self.where,
                                  "explode the blocks in your CAD program, or copy the law out of them")
            if placements > MAX_BLOCK_PLACEMENTS:
                raise CamcadError(f"block references are placed more than {MAX_BLOCK_PLACEMENTS} times (at least "
                                  f"{_count_text(placements)}: {what})", self.where,
                                  "explode the blocks in your CAD program, or copy the law out of them")

    def _size(self, name: str, handle: str, depth: int, chain: tuple[str, ...]) -> tuple[int, int]:
        """(curve pieces, nested placements) of one reference of block ``name``; counting stops past the budgets."""
        key = name.upper()
        if key in chain:
            raise CamcadError(f"block {name[:40]} inserts itself (INSERT {handle})", self.where,
                              "explode or repair the block in your CAD program")
        if depth > MAX_BLOCK_DEPTH:
            raise CamcadError(f"block references nest more than {MAX_BLOCK_DEPTH} deep (INSERT {handle}, block "
                              f"{name[:40]})", self.where,
                              "explode the nested blocks in your CAD program, or copy the law out of them")
        if key not in self.sizes:
            pieces, children, _ = self._content(name)
            total, placed = len(pieces), 0
            for child, _entity, cells, _, _ in children:
                inner, inner_placed = self._size(child, handle, depth + 1, chain + (key,))
                total += cells * inner
                placed += cells * (1 + inner_placed)
                if total > MAX_BLOCK_ENTITIES or placed > MAX_BLOCK_PLACEMENTS:
                    break
            self.sizes[key] = (total, placed)
        return self.sizes[key]

    def place(self, insert, handle: str, index: int, counts: Counter):
        """The pieces of a model-space reference in WCS (handle and index of the INSERT)."""
        out: list[Piece] = []
        layer = str(insert.dxf.get("layer", "0"))
        stack = [(str(insert.dxf.get("name", "")), m, layer) for m in self._placed(insert, handle)]
        while stack:
            name, m, layer = stack.pop()
            pieces, children, block_counts = self._content(name)
            if self.sizes.get(name.upper(), (1, 0))[0] == 0:   # no curve below: count its entities, place nothing
                counts.update(self._subtree_counts(name))
                continue
            counts.update(block_counts)
            scale = _scale(m)
            for piece in pieces:
                try:
                    points = _transform(piece.points, m)
                    breakpoints = None if piece.breakpoints is None else _transform(piece.breakpoints, m)
                except ValueError as err:
                    raise CamcadError(f"INSERT {handle} (block {name[:40]}) places {piece.kind} at an out-of-range "
                                      f"coordinate ({_short(err, 80).split(';')[0]})", self.where,
                                      "fix the reference's insertion point, scale or rotation in your CAD "
                                      "program") from None
                out.append(replace(piece, points=points, handle=handle, index=index,
                                   exact=False, in_block=True, flatten_tol=piece.flatten_tol * scale,
                                   layer=layer if piece.layer == "0" else piece.layer, breakpoints=breakpoints))
            for child, entity, _, child_layer, child_handle in children:
                inherited = layer if child_layer == "0" else child_layer
                stack.extend((child, local @ m, inherited) for local in self._placed(entity, child_handle))
        return out

    def _subtree_counts(self, name: str) -> Counter:
        """The entity counts of one reference of block ``name``, its nested references' included (counted, not
        placed; the budget has bounded them)."""
        key = name.upper()
        if key not in self.subtree_counts:
            _, children, block_counts = self._content(name)
            total = Counter(block_counts)
            for child, _entity, cells, _, _ in children:
                for kind, count in self._subtree_counts(child).items():
                    total[kind] += cells * count
            self.subtree_counts[key] = total
        return self.subtree_counts[key]

    def _placed(self, insert, handle: str) -> list[np.ndarray]:
        """The matrices of a reference (``_matrices``, computed once per entity), refused with the entity named
        when one is not finite."""
        key = id(insert)
        if key in self.matrices:
            return self.matrices[key]
        matrices = _matrices(insert)
        self.matrices[key] = matrices
        for m in matrices:
            if not np.isfinite(m).all() or np.abs(m).max() > MAX_COORDINATE:
                raise CamcadError(f"INSERT {handle} (block {str(insert.dxf.get('name', ''))[:40]}) has a "
                                  "transformation that is not finite or out of range (its scale, rotation or "
                                  "insertion point)", self.where,
                                  "fix the reference in your CAD program, or explode it") from None
        return matrices


def _cells_text(insert) -> str:
    try:
        return f"{int(insert.dxf.get('row_count', 1))} rows x {int(insert.dxf.get('column_count', 1))} columns"
    except Exception:  # noqa: BLE001
        return "several cells"


def _count_text(count: int) -> str:
    return f"{count:,}" if count < 10**15 else f"{float(count):.3g}"


def _matrices(insert) -> list[np.ndarray]:
    """The 4×4 row-vector matrices placing a block reference (one per cell of a MINSERT; the caller checks the
    cell count against the budget before calling this).

    A MINSERT's cells differ only by their translation, linear in the row and the column: ezdxf places the
    cells (0, 0), (0, 1) and (1, 0) of a 2 × 2 copy, and every other cell is (0, 0) moved by whole steps.
    """
    def matrix(single) -> np.ndarray:
        return np.array([list(single.matrix44().get_row(k)) for k in range(4)], dtype=float)

    try:
        with np.errstate(all="ignore"):
            if _repeat(insert) <= 1:
                return [matrix(insert)]
            rows = max(1, int(insert.dxf.get("row_count", 1)))
            cols = max(1, int(insert.dxf.get("column_count", 1)))
            probe = insert.copy()
            probe.dxf.row_count, probe.dxf.column_count = min(rows, 2), min(cols, 2)
            cells = [matrix(single) for single in probe.multi_insert()]
            base = cells[0]
            step_col = cells[1][3] - base[3] if cols > 1 else np.zeros(4)
            step_row = cells[min(cols, 2)][3] - base[3] if rows > 1 else np.zeros(4)
            out = []
            for r in range(rows):
                for c in range(cols):
                    m = base.copy()
                    m[3] = base[3] + c * step_col + r * step_row
                    out.append(m)
            return out
    except Exception:  # noqa: BLE001 - a reference that cannot be placed draws nothing
        return []


def _transform(points: np.ndarray, m: np.ndarray) -> np.ndarray:
    """2-D points (z = 0) through a 4×4 row-vector matrix, back to 2-D."""
    out = points @ m[:2, :2] + m[3, :2]
    if not (np.isfinite(out).all() and np.abs(out).max() <= MAX_COORDINATE):
        return _checked(out)  # raises, naming the vertex
    return out


def _scale(m: np.ndarray) -> float:
    return float(max(np.hypot(*m[0, :2]), np.hypot(*m[1, :2]), 1e-300))


def _piece(entity, kind: str, handle: str, layer: str, flatten_tol: float | None, index: int = -1,
           hidden: bool = False) -> Piece | None:
    if kind == "LINE":
        start, end = entity.dxf.start, entity.dxf.end
        values = (start.x, start.y, end.x, end.y)
        if not all(math.isfinite(v) and abs(v) <= MAX_COORDINATE for v in values):
            _checked(np.array(values, dtype=float).reshape(2, 2))  # raises, naming the vertex
        ends = np.array(values, dtype=float).reshape(2, 2)
        return Piece(ends, "LINE", handle, layer, index, exact=True, hidden=hidden, breakpoints=ends)
    piece = _other_piece(entity, kind, handle, layer, flatten_tol)
    return None if piece is None else replace(piece, index=index, hidden=hidden)


def _other_piece(entity, kind: str, handle: str, layer: str, flatten_tol: float | None) -> Piece | None:
    if kind == "ARC":
        points = _checked(_arc_points(entity, flatten_tol))
        if len(points) < 2 or float(entity.dxf.radius) <= 0:
            return Piece(points[:1], "ARC", handle, layer)
        span = (float(entity.dxf.end_angle) - float(entity.dxf.start_angle)) % 360.0
        return Piece(points, "ARC", handle, layer, closed=span == 0.0,
                     flatten_tol=_tolerance(points, flatten_tol), breakpoints=points[[0, -1]])
    if kind == "ELLIPSE":
        return _ellipse_piece(entity, handle, layer, flatten_tol)
    if kind == "LWPOLYLINE":
        return _lwpolyline_piece(entity, handle, layer, flatten_tol)
    if kind == "POLYLINE":
        return _polyline_piece(entity, handle, layer, flatten_tol)
    return _spline_piece(entity, handle, layer, flatten_tol)


def _hidden_layers(doc) -> set[str]:
    names = set()
    for layer in doc.layers:
        try:
            off = not layer.is_on() or layer.is_frozen()
            name = layer.dxf.name.upper()
        except Exception:  # noqa: BLE001 - a damaged layer table entry hides nothing
            off = False
        if off:
            names.add(name)
    return names


def _repeat(insert) -> int:
    try:
        return max(1, int(insert.dxf.get("row_count", 1))) * max(1, int(insert.dxf.get("column_count", 1)))
    except Exception:  # noqa: BLE001
        return 1


def _checked(points: np.ndarray) -> np.ndarray:
    """The points, or ValueError naming the first vertex with a NaN, infinite or absurdly large coordinate."""
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    finite = np.isfinite(points).all(axis=1)
    if not finite.all():
        index = int(np.flatnonzero(~finite)[0])
        raise ValueError(f"vertex {index} has a non-finite coordinate ({points[index, 0]:.6g}, "
                         f"{points[index, 1]:.6g}); fix or delete that vertex in your CAD program")
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


def _lwpolyline_piece(entity, handle: str, layer: str, flatten_tol: float | None) -> Piece:
    points = _checked(np.array([[p.x, p.y] for p in entity.vertices_in_wcs()], dtype=float))
    bulges = [b for *_, b in entity.get_points("xyb")]
    closed = bool(entity.closed)
    if any(b for b in bulges[: len(bulges) if closed else len(bulges) - 1]):
        tol = _tolerance(points, flatten_tol)
        return Piece(_flatten_virtual(entity, tol, points), "LWPOLYLINE", handle, layer, closed=closed,
                     flatten_tol=tol, breakpoints=points)
    return Piece(points, "LWPOLYLINE", handle, layer, exact=True, closed=closed, breakpoints=points)


def _polyline_piece(entity, handle: str, layer: str, flatten_tol: float | None) -> Piece | None:
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
    if any(b for b in bulges[: len(bulges) if closed else len(bulges) - 1]):
        tol = _tolerance(points, flatten_tol)
        return Piece(_flatten_virtual(entity, tol, points), "POLYLINE", handle, layer, closed=closed,
                     flatten_tol=tol, breakpoints=points)
    return Piece(points, "POLYLINE", handle, layer, exact=True, closed=closed, breakpoints=points)


def _flatten_virtual(entity, tol: float, vertices: np.ndarray) -> np.ndarray:
    """Exact flattening of a polyline with bulges: its virtual LINEs and ARCs, arcs by sagitta."""
    out: list[np.ndarray] = [vertices[:1]]
    for part in entity.virtual_entities():
        if part.dxftype() == "LINE":
            seg = np.array([[part.dxf.start.x, part.dxf.start.y], [part.dxf.end.x, part.dxf.end.y]])
        else:
            seg = _arc_points(part, tol)
            if len(seg) < 2:
                continue
        if np.hypot(*(seg[-1] - out[-1][-1])) < np.hypot(*(seg[0] - out[-1][-1])):
            seg = seg[::-1]  # virtual ARCs always run counter-clockwise; follow the polyline instead
        out.append(seg[1:])
    return _checked(np.concatenate(out))


def _arc_points(arc, tol: float | None) -> np.ndarray:
    radius = float(arc.dxf.radius)
    if not radius > 0:
        center = arc.dxf.center
        return np.array([[center.x, center.y]], dtype=float)
    if tol is None:
        tol = max(radius * DEFAULT_FLATTEN_FRACTION, 1e-12)
    sagitta = min(tol, radius)
    points = np.array([[p.x, p.y] for p in arc.flattening(sagitta)], dtype=float)
    return points.reshape(-1, 2)


def _ellipse_piece(entity, handle: str, layer: str, flatten_tol: float | None) -> Piece:
    major = entity.dxf.major_axis
    size = 2.0 * math.hypot(major.x, major.y)
    tol = flatten_tol if flatten_tol is not None else max(size * DEFAULT_FLATTEN_FRACTION, 1e-12)
    points = _checked(np.array([[p.x, p.y] for p in entity.flattening(tol)], dtype=float))
    start, end = float(entity.dxf.start_param), float(entity.dxf.end_param)
    closed = math.isclose((end - start) % (2 * math.pi), 0.0, abs_tol=1e-12) or \
        math.isclose(abs(end - start), 2 * math.pi, abs_tol=1e-12)
    return Piece(points, "ELLIPSE", handle, layer, closed=closed, flatten_tol=tol,
                 breakpoints=points[[0, -1]] if len(points) else points)


def _spline_piece(entity, handle: str, layer: str, flatten_tol: float | None) -> Piece:
    control = [tuple(p)[:2] for p in entity.control_points]
    fit = [tuple(p)[:2] for p in entity.fit_points]
    frame_points = _checked(np.array(control or fit, dtype=float))
    tol = _tolerance(frame_points, flatten_tol)
    points = _checked(np.array([[p.x, p.y] for p in entity.flattening(tol)], dtype=float))
    if len(fit) >= 2:
        breakpoints = _checked(np.array(fit, dtype=float))
        interpolating = True
    else:
        breakpoints = _knot_points(entity, points)
        interpolating = is_interpolating_cubic(entity)
    return Piece(points, "SPLINE", handle, layer, closed=bool(entity.closed), flatten_tol=tol,
                 breakpoints=breakpoints, interpolating=interpolating)


#: a cubic spline whose second derivative jumps at no knot by more than this fraction of its largest
#: second derivative is C2 (FreeCAD writes coordinates to 4 decimals, which breaks C2 by up to ~2e-3 of it)
C2_FRACTION = 1e-2


def is_interpolating_cubic(entity) -> bool:
    """The SPLINE (control points and knots) is a cubic of three or more spans whose second derivative
    is continuous at every knot (to ``C2_FRACTION`` of its largest value): the C2 cubic spline through
    its knot points, i.e. an interpolating spline however it was saved (FreeCAD writes its interpolated
    B-splines as control points with knots of multiplicity 3). A designer's chain of Bézier lobes is
    not C2 where the lobes meet; a uniform control-point spline is C2 too, and then its knot points are
    taken as the points it was drawn through.
    """
    try:
        tool = entity.construction_tool()
        if int(tool.degree) != 3 or (hasattr(tool, "is_rational") and tool.is_rational):
            return False
        knots = np.asarray(tool.knots(), dtype=float)
        order = int(tool.order)
        inner = unique(knots[order - 1: len(knots) - order + 1])
        if len(inner) < 4:
            return False
        step = 1e-7 * float(inner[-1] - inner[0])
        second = []
        for t in inner[1:-1]:
            left = np.asarray(tool.derivative(float(t) - step, 2)[2], dtype=float)[:2]
            right = np.asarray(tool.derivative(float(t) + step, 2)[2], dtype=float)[:2]
            second.append((left, right))
        samples = np.linspace(inner[0], inner[-1], 4 * len(inner))
        scale = max(float(np.hypot(*np.asarray(tool.derivative(float(t), 2)[2], dtype=float)[:2]))
                    for t in samples)
        if not scale > 0:
            return False
        return all(float(np.hypot(*(left - right))) <= C2_FRACTION * scale for left, right in second)
    except Exception:  # noqa: BLE001 - a spline ezdxf cannot evaluate is not known to interpolate
        return False


def _knot_points(entity, points: np.ndarray) -> np.ndarray:
    """The spline's points at its distinct knots inside the parameter range (where the pieces of
    the spline meet: the points an interpolating spline was drawn through)."""
    try:
        tool = entity.construction_tool()
        knots = np.asarray(tool.knots(), dtype=float)
        order = int(tool.order)
        inner = unique(knots[order - 1: len(knots) - order + 1])
        return _checked(np.array([[p.x, p.y] for p in (tool.point(float(t)) for t in inner)], dtype=float))
    except Exception:  # noqa: BLE001 - the flattening's ends then stand for the spline's points
        return points[[0, -1]]


def curve_space(doc, curve: Curve):
    """The layout ``curve`` is drawn in, in ``doc``: the model space, or the paper-space layout it was read
    from (``Curve.layout``)."""
    if curve.layout:
        try:
            return doc.layouts.get(curve.layout)
        except Exception:  # noqa: BLE001 - a layout that is gone: the model space
            return doc.modelspace()
    return doc.modelspace()


def curve_entities(doc, curve: Curve) -> list:
    """The entities of ``curve`` in ``doc`` (a fresh load of the same file), in ``curve.handles``
    order; None where an entity cannot be found.

    Found by model-space position (``curve.entity_indices``) and checked against the handle and
    type, so a file whose handles are not unique (ezdxf reassigns duplicates when loading) still
    gives the right entities; a block's pieces give the INSERT.

    Parameters
    ----------
    doc : ezdxf Drawing
        The document, loaded again with :func:`open_drawing`.
    curve : Curve
        The curve read from the same file.

    Returns
    -------
    list
        One entity (or None) per handle of the curve.
    """
    msp = list(curve_space(doc, curve))
    found = []
    for handle, index in zip(curve.handles, curve.entity_indices):
        entity = msp[index] if 0 <= index < len(msp) else None
        if entity is not None and str(entity.dxf.get("handle", "")).upper() != handle.upper():
            entity = None
        if entity is None:
            entity = doc.entitydb.get(handle)
        found.append(entity)
    return found


__all__ = [
    "CURVE_TYPES",
    "LENGTH_UNITS",
    "MAX_BLOCK_DEPTH",
    "MAX_BLOCK_ENTITIES",
    "UNIT_NAMES",
    "Curve",
    "Drawing",
    "Piece",
    "PieceSet",
    "collect_pieces",
    "curve_entities",
    "curve_space",
    "ezdxf_messages",
    "handles_text",
    "is_interpolating_cubic",
    "open_drawing",
    "summarise_messages",
    "units_note",
]
