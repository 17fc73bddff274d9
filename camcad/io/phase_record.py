"""The phases of a law kept in the drawing camcad writes: a record on the law's curve that other readers ignore.

A law's phases (their kinds and angles, and the position and velocity each states at its end) cannot be read
back from the acceleration alone: a blend from one motion into another, or a stop, leaves no mark on a(θ)
that detection could take for a phase boundary. camcad writes them as XDATA of the law's polyline under the
application name ``CAMCAD`` (DXF group codes 1000: one string per phase), which AutoCAD, LibreCAD, QCAD and
ezdxf keep and ignore; ``camcad.law.source.load_law`` reads them back when the user gives no phases.

Each string: ``phase KIND START_DEG END_DEG S_END_MM V_END_MM_PER_DEG`` (``-`` for a value not stated),
after a first string ``camcad phases 1 CYCLE_DEG``.
"""

from __future__ import annotations

import math
from itertools import pairwise

APPID = "CAMCAD"
HEADER = "camcad phases 1"


def phase_record_tags(rows, cycle_deg: float) -> list[tuple[int, str]]:
    """The XDATA tags of the phases ``rows``: (kind, start_deg, end_deg, s_end_mm or None, v_end_mm_per_deg)."""
    tags = [(1000, f"{HEADER} {cycle_deg:.17g}")]
    for kind, start, end, s_end, v_end in rows:
        s_text = "-" if s_end is None else f"{s_end:.17g}"
        tags.append((1000, f"phase {kind} {start:.17g} {end:.17g} {s_text} {v_end:.17g}"))
    return tags


def write_phase_record(doc, entity, rows, cycle_deg: float) -> None:
    """Attach the phases to ``entity`` (the law's polyline) as XDATA of the application ``CAMCAD``."""
    if APPID not in doc.appids:
        doc.appids.add(APPID)
    entity.set_xdata(APPID, phase_record_tags(rows, cycle_deg))


def read_phase_record(entity) -> tuple[float, list[tuple]] | None:
    """(cycle_deg, rows) from an entity's ``CAMCAD`` XDATA, or None when it has none or it is not a phase record.

    A record that is damaged (a row that does not parse, angles that do not increase) is treated as absent:
    the phases are then detected from the law, as for any drawing."""
    try:
        if not entity.has_xdata(APPID):
            return None
        tags = entity.get_xdata(APPID)
    except (AttributeError, KeyError, TypeError, ValueError):   # no XDATA on this type, or a damaged record
        return None
    texts = [str(value) for code, value in tags if code == 1000]
    if not texts or not texts[0].startswith(HEADER):
        return None
    try:
        cycle = float(texts[0][len(HEADER):])
        rows = []
        for text in texts[1:]:
            parts = text.split()
            if len(parts) != 6 or parts[0] != "phase" or parts[1] not in ("rise", "return", "dwell"):
                return None
            start, end = float(parts[2]), float(parts[3])
            s_end = None if parts[4] == "-" else float(parts[4])
            v_end = float(parts[5])
            if not all(math.isfinite(x) for x in (start, end, v_end, 0.0 if s_end is None else s_end)):
                return None
            rows.append((parts[1], start, end, s_end, v_end))
    except ValueError:
        return None
    if not rows or not math.isfinite(cycle) or not 0.0 < cycle <= 360.0:
        return None
    for (_, s0, e0, _, _), (_, s1, _, _, _) in pairwise(rows):
        if not (e0 > s0 and abs(s1 - e0) <= 1e-9 * cycle):
            return None
    if not rows[-1][2] > rows[-1][1]:
        return None
    if abs(rows[0][1]) > 1e-9 * cycle or abs(rows[-1][2] - cycle) > 1e-9 * cycle:
        return None
    return cycle, rows
