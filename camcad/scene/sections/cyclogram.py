"""The scene's ``[cyclogram]`` section: events, operations, their bounds and vibration relations."""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any

from camcad.cyclogram.limits import LinearRelation
from camcad.cyclogram.network import Network, Operation, make_network
from camcad.errors import CamcadError, nearest_name
from camcad.scene.fields import Field, read_table

CYCLOGRAM_FIELDS: list[Field] = [
    Field("operations", "list", required=True,
          help="([[cyclogram.operations]] tables with from, to, bounds_deg)"),
    Field("events", "list", help="(event names in order; optional)"),
    Field("start", "str", help="(first event; default: the only event without predecessors)"),
    Field("end", "str", help="(last event; default: the only event without successors)"),
    Field("cycle_deg", unit="deg", default=360.0, positive=True,
          help="(the group must fit in this angle of the cycle)"),
    Field("start_deg", unit="deg", default=0.0, minimum=0.0, maximum=360.0,
          help="(where the first event sits on the machine's cycle)"),
    Field("name", "str", default="", help="(name of the group)"),
]

OPERATION_FIELDS: list[Field] = [
    Field("from", "str", required=True, help="(the event the operation starts at)"),
    Field("to", "str", required=True, help="(the event it ends at)"),
    Field("bounds_deg", "list", unit="deg", required=True,
          help="([min, max] phase angle in deg; max may be inf)"),
    Field("name", "str", default=""),
    Field("mechanism", "str", help="(the mechanism doing the operation)"),
    Field("phase", "str", choices=("rise", "return", "dwell"),
          help="(which phase of the mechanism's law the operation is)"),
    Field("occurrence", "int", default=1, minimum=1, help="(1 for the first such phase, 2, ...)"),
    Field("amplitude_limit_mm", unit="mm", positive=True,
          help="(allowed vibration amplitude of the working member)"),
    Field("amplitude_slope_mm_per_deg", unit="mm/deg",
          help="(amplitude = slope * t + intercept, e.g. -0.003)"),
    Field("amplitude_intercept_mm", unit="mm", help="(e.g. 0.208)"),
]


def _event_name(value: Any, key: str, where: str) -> str:
    if isinstance(value, bool) or not isinstance(value, (str, int)):
        raise CamcadError(f"'{key}' must be an event name or number, got {value!r}", where,
                          f'write {key} = "3" or {key} = 3')
    return str(value)


def parse_cyclogram(table: Any, where: str, mechanisms: Iterable[str] | None = None) -> Network:
    """A scene's ``[cyclogram]`` section → validated Network.

    Keys: ``operations`` (array of tables: ``from``, ``to``, ``bounds_deg = [min, max]`` deg,
    optional ``name``, ``mechanism``, ``phase``, ``occurrence``, and a vibration limit
    ``amplitude_limit_mm`` with the linear relation ``amplitude_slope_mm_per_deg``,
    ``amplitude_intercept_mm``), optional ``events``, ``start``, ``end``, ``cycle_deg`` (360),
    ``start_deg`` (0), ``name``. Event names may be numbers. ``mechanisms``: the scene's mechanism
    names, to check the operations' ``mechanism``. Errors are one-line CamcadErrors naming ``where``.
    """
    if isinstance(table, dict):
        table = dict(table)
        for key in ("start", "end"):
            if key in table:
                table[key] = _event_name(table[key], key, where)
        if isinstance(table.get("events"), list):
            table["events"] = [_event_name(e, "events", where) for e in table["events"]]
    values = read_table(table, CYCLOGRAM_FIELDS, where)
    known = list(mechanisms) if mechanisms is not None else None
    operations = []
    for k, raw in enumerate(values["operations"], start=1):
        here = f"{where} operations[{k}]"
        if isinstance(raw, dict):
            raw = dict(raw)
            for key in ("from", "to"):
                if key in raw:
                    raw[key] = _event_name(raw[key], key, here)
        op = read_table(raw, OPERATION_FIELDS, here)
        here = f"{where} operation {op['from']}->{op['to']}"
        bounds = op["bounds_deg"]
        if (len(bounds) != 2 or any(isinstance(b, bool) or not isinstance(b, (int, float)) for b in bounds)
                or math.isnan(bounds[0]) or math.isnan(bounds[1])):
            raise CamcadError(f"'bounds_deg' must be [min, max] in deg, got {bounds!r}", here,
                              "write bounds_deg = [20.0, 60.0] (max may be inf)")
        low, high = float(bounds[0]), float(bounds[1])
        if not math.isfinite(low) or low < 0:
            raise CamcadError(f"lower bound {low:g} deg must be a finite number >= 0", here,
                              "write bounds_deg = [min, max] with 0 <= min")
        if high < low:
            raise CamcadError(f"bounds_deg [{low:g}, {high:g}] has min > max", here, "swap or correct them")
        if known is not None and op["mechanism"] is not None and op["mechanism"] not in known:
            fix = (nearest_name(op["mechanism"], known).replace("valid keys", "mechanisms") if known
                   else f"add [mechanisms.{op['mechanism']}] to the scene, or drop 'mechanism'")
            raise CamcadError(f"unknown mechanism {op['mechanism']!r}", here, fix)
        if op["phase"] is not None and op["mechanism"] is None:
            raise CamcadError("'phase' needs a 'mechanism'", here, "name the mechanism whose law it is")
        relation = None
        vib = (op["amplitude_limit_mm"], op["amplitude_slope_mm_per_deg"], op["amplitude_intercept_mm"])
        if any(v is not None for v in vib):
            if any(v is None for v in vib):
                raise CamcadError("a vibration limit needs amplitude_limit_mm, amplitude_slope_mm_per_deg "
                                  "and amplitude_intercept_mm", here, "give all three, or none")
            if not vib[1] < 0:
                raise CamcadError(f"amplitude_slope_mm_per_deg {vib[1]:g} must be negative (the amplitude "
                                  "falls as the operation gets longer)", here, "give a negative slope")
            relation = LinearRelation(vib[1], vib[2])
        operations.append(Operation(op["from"], op["to"], low, high, op["mechanism"], op["name"],
                                    op["phase"], op["occurrence"], relation, op["amplitude_limit_mm"]))
    return make_network(operations, values["events"], values["start"], values["end"],
                        values["cycle_deg"], values["start_deg"], where)


