"""The record camcad writes with every law: its phase angles and the rule it was judged by.

A law written as a polyline (``filtered.dxf``, a fixed drawing, ``synth`` output) or as a table
(``filtered.csv``, ``law.csv``) loses what the command that wrote it knew: where the phases are, and by
which rule it passed. Read back, a filtered law's phases would be detected again from its acceleration —
and a law whose dwells carry the filter's small residue is cut elsewhere (a "rise" from 0°). So every law
camcad writes carries a ``LawRecord``:

- in a DXF: XDATA of the application ``CAMCAD`` on the law's polyline (group 1000 strings, the JSON of
  the record in pieces of at most 250 characters). Other readers ignore XDATA (LibreCAD, Inkscape,
  LibreOffice, AutoCAD keep it untouched); it exists in R12 as in R2000 and later;
- in a table: one comment line ``# camcad-law: {json}`` before the rows (a comment to every other reader).

Reading the law back (``camcad.load_law``) restores the phases with a note, unless ``--phases`` is given;
``camcad check`` judges it by the rule recorded (``basis``): "balance" (v = 0 at the end of every rise and
return, s closes: ``camcad check``'s own rule) or "closure" (a filtered law: s and v close over the cycle
within ``closure_tol`` × lift, and s stays within ``dwell_tol`` of each dwell's level — what
``camcad spectrum --filter`` judged it by).

The record also holds the vertex count and a CRC-32 of the written vertices (DXF) so a curve edited after
camcad wrote it is noticed (the phases are still restored, with a note saying so).
"""

from __future__ import annotations

import json
import math
import zlib
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

#: XDATA application name of the record
APPID = "CAMCAD"
#: the comment that opens the record line of a table
TABLE_TAG = "camcad-law:"
#: the record's format version
VERSION = 1
BASES = ("balance", "closure")
_CHUNK = 250


@dataclass(frozen=True)
class LawRecord:
    """What camcad writes with a law so it reads back as it was meant.

    Parameters
    ----------
    phases : str
        The phase angles, "0:100:dwell,100:164:rise,..." (deg of cam angle).
    cycle_deg : float
        The cycle the phases cover (deg).
    writer : str
        The command that wrote the law, e.g. "camcad spectrum --filter".
    unit : str
        Unit of the law's displacement: "mm", "rad" or "deg" (of swing).
    basis : str
        The rule the law is judged by: "balance" or "closure" (module docstring).
    tol : float
        Closure tolerance, a fraction of the lift (dimensionless).
    dwell_tol : float or None
        "closure": the largest |s − level| allowed on a dwell, mm (or rad/deg of swing: ``unit``).
    dwell_levels : tuple of float
        "closure": s of each dwell, mm (or rad/deg of swing), in the order of the dwells in ``phases``.
    lift : float or None
        The lift the tolerances refer to, mm (or rad/deg of swing).
    vertices : int or None
        The number of vertices written (DXF).
    digest : str or None
        CRC-32 (hex) of the written vertices as float64 (DXF), see ``vertex_digest``.
    extra : dict
        Further facts of the writer (free-form, JSON types).

    Examples
    --------
    >>> record = LawRecord("0:90:rise,90:180:dwell,180:270:return,270:360:dwell", 360.0, "camcad synth")
    >>> LawRecord.from_json(record.to_json()) == record
    True
    >>> table_line(record)[:15]
    '# camcad-law: {'
    """

    phases: str
    cycle_deg: float
    writer: str
    unit: str = "mm"
    basis: str = "balance"
    tol: float = 1e-5
    dwell_tol: float | None = None
    dwell_levels: tuple[float, ...] = ()
    lift: float | None = None
    vertices: int | None = None
    digest: str | None = None
    extra: dict = field(default_factory=dict)

    def to_json(self) -> str:
        data = {"version": VERSION, **asdict(self)}
        data["dwell_levels"] = [float(v) for v in self.dwell_levels]
        return json.dumps({k: v for k, v in data.items() if v not in (None, {}, [])}, sort_keys=True,
                          separators=(",", ":"), allow_nan=False)

    @classmethod
    def from_json(cls, text: str) -> LawRecord:
        """The record of its JSON; ValueError when the text is not a record camcad can read."""
        data = json.loads(text)
        if not isinstance(data, dict) or not isinstance(data.get("phases"), str):
            raise ValueError("not a camcad law record")
        version = data.pop("version", VERSION)
        if not isinstance(version, int) or version > VERSION:
            raise ValueError(f"record version {version!r} is newer than this camcad reads ({VERSION})")
        known = set(cls.__dataclass_fields__)
        values: dict[str, Any] = {k: v for k, v in data.items() if k in known}
        if values.get("basis", "balance") not in BASES:
            raise ValueError(f"unknown basis {values.get('basis')!r}")
        cycle = values.get("cycle_deg")
        if not isinstance(cycle, (int, float)) or not (math.isfinite(cycle) and 0 < cycle <= 360):
            raise ValueError("the record's cycle is not an angle in (0, 360]")
        values["cycle_deg"] = float(cycle)
        values["dwell_levels"] = tuple(float(v) for v in values.get("dwell_levels", ()))
        values.setdefault("writer", "camcad")
        return cls(**values)

    @classmethod
    def for_law(cls, law, writer: str, **fields) -> LawRecord:
        """The record of a law (anything with ``phases`` in rad and ``cycle`` in rad) written by ``writer``;
        further fields (unit, basis, tol, ...) as keywords."""
        return cls(phases_text(law.phases), math.degrees(law.cycle), writer, **fields)

    def describe(self) -> str:
        """One line: who wrote the law and the rule it is judged by."""
        if self.basis == "closure":
            rule = (f"closure of s and v within {self.tol:g} of the lift, dwells within "
                    f"{self.dwell_tol or 0.0:.4g} {self.unit} of their levels")
        else:
            rule = f"balance (v = 0 at the end of every motion, s closes) within {self.tol:g} of the lift"
        return f"written by {self.writer}; judged by {rule}"


def phases_text(phases) -> str:
    """"0:90:rise,90:180:dwell,..." (deg, 12 significant digits) of phases with ``start``, ``end`` (rad) and
    ``kind``; a phase that states where it ends (``s_end`` mm, ``v_end`` mm/rad: a stop, a blend into a
    velocity) adds them as ``:s_end[:v_end]`` (mm, mm/deg), the form ``--phases`` reads.

    Examples
    --------
    >>> from types import SimpleNamespace as P
    >>> phases_text([P(kind="rise", start=0.0, end=math.pi / 2), P(kind="dwell", start=math.pi / 2, end=math.pi)])
    '0:90:rise,90:180:dwell'
    >>> phases_text([P(kind="rise", start=0.0, end=math.pi / 3, s_end=12.0, v_end=math.degrees(0.3))])
    '0:60:rise:12:0.3'
    """
    items = []
    for p in phases:
        item = f"{math.degrees(p.start):.12g}:{math.degrees(p.end):.12g}:{p.kind}"
        s_end, v_end = getattr(p, "s_end", None), float(getattr(p, "v_end", 0.0))
        if s_end is not None or v_end != 0.0:
            item += f":{'-' if s_end is None else _exact(s_end)}"    # repr: the shortest exact text
            if v_end != 0.0:
                item += f":{_exact(math.radians(v_end))}"
        items.append(item)
    return ",".join(items)


def _exact(value: float) -> str:
    """The shortest text that reads back as ``value`` exactly ("12", "0.3", "1e-05")."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def rows_text(rows) -> str:
    """``phases_text`` of phases given as rows (kind, start_deg, end_deg, s_end_mm or None, v_end_mm_per_deg).

    Examples
    --------
    >>> rows_text([("rise", 0.0, 60.0, 12.0, 0.3), ("dwell", 60.0, 360.0, None, 0.0)])
    '0:60:rise:12:0.3,60:360:dwell'
    """
    items = []
    for kind, start, end, s_end, v_end in rows:
        item = f"{float(start):.12g}:{float(end):.12g}:{kind}"
        if s_end is not None or v_end:
            item += f":{'-' if s_end is None else _exact(s_end)}"
            if v_end:
                item += f":{_exact(v_end)}"
        items.append(item)
    return ",".join(items)


def vertex_digest(points: np.ndarray) -> str:
    """CRC-32 (8 hex digits) of the points (n, 2) as float64 in C order: the same for the same vertices.

    Examples
    --------
    >>> vertex_digest(np.array([[0.0, 1.0], [2.0, 3.0]])) == vertex_digest(np.array([[0, 1], [2, 3]]))
    True
    """
    data = np.ascontiguousarray(np.asarray(points, dtype=np.float64)).tobytes()
    return f"{zlib.crc32(data) & 0xFFFFFFFF:08x}"


def table_line(record: LawRecord) -> str:
    """The comment line of a table that holds ``record``."""
    return f"# {TABLE_TAG} {record.to_json()}"


def record_of_comment(comment: str) -> LawRecord | None:
    """The record of a table's comment line (without its ``#``), None when it is another comment;
    ValueError when it is a record camcad cannot read."""
    text = comment.strip()
    if not text.startswith(TABLE_TAG):
        return None
    return LawRecord.from_json(text[len(TABLE_TAG):].strip())


def attach_to_entity(doc, entity, record: LawRecord) -> None:
    """Store ``record`` as XDATA (application ``CAMCAD``) on ``entity`` of ``doc`` (the APPID is
    registered when missing); a record already there is replaced."""
    if APPID not in doc.appids:
        doc.appids.new(APPID)
    text = record.to_json()
    tags = [(1000, text[i:i + _CHUNK]) for i in range(0, len(text), _CHUNK)]
    entity.set_xdata(APPID, tags)


def record_of_entity(entity) -> LawRecord | None:
    """The record stored on an entity, None when it has none; ValueError when it cannot be read."""
    try:
        if not entity.has_xdata(APPID):
            return None
        tags = entity.get_xdata(APPID)
    except (AttributeError, LookupError):
        return None
    text = "".join(str(value) for code, value in tags if code == 1000)
    return LawRecord.from_json(text)


__all__ = ["APPID", "BASES", "TABLE_TAG", "LawRecord", "attach_to_entity", "phases_text", "record_of_comment",
           "record_of_entity", "table_line", "vertex_digest"]
