"""The scene's [cyclogram] section (events, operations, bounds and vibration relations) and ``camcad cyclogram``
as one library function (``run_cyclogram``), with the verdict the pipeline's step 9 shares.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from camcad.cyclogram.limits import LinearRelation
from camcad.cyclogram.network import Network, Operation, make_network
from camcad.errors import CamcadError, nearest_name
from camcad.scene.fields import Field, read_table
from camcad.verdict import Check, Verdict, Warning

#: cycle slack below this fraction of the cycle is warned about
CLOSE_TO_LIMIT = 0.05
#: a phase angle within this (relative, of max(1 deg, the bound)) of a bound is on the bound
HELD_TOL_DEG = 1e-9



# --------------------------------------------------------------------------------------------
# The scene's [cyclogram] section
# --------------------------------------------------------------------------------------------

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


# --------------------------------------------------------------------------------------------
# camcad cyclogram
# --------------------------------------------------------------------------------------------

def cyclogram_verdict(found) -> Verdict:
    """The checks of an optimised cyclogram (camcad.scene.phase_angles.CyclogramAngles): feasible; the
    makespan against the cycle; every operation's phase angle against its least admissible one (its
    designer's bound or a phase limit, whichever is larger), active ones noted as holding the makespan;
    a finite upper bound that is active. Warnings: little cycle slack, operations held at a phase limit."""
    result = found.result
    if not result.feasible:
        return Verdict((Check("cyclogram feasible", None, None, passed_override=False, note=result.explanation),), ())
    network = result.network
    checks = [Check("makespan", float(result.makespan_deg), float(network.cycle_deg), "deg",
                    applies=f"p({network.end}) - p({network.start}) within the cycle")]
    active = {(c.label, c.kind) for c in result.active}
    warnings = []
    for op in network.operations:
        angle = float(result.phase_angles_deg[op.label])
        least, source = result.lower_bounds_deg[op.label]
        # the times are sums of bounds and carry their round-off: an angle that close to a bound is on it
        for bound in (float(least), float(op.max_deg)):
            if math.isfinite(bound) and abs(angle - bound) <= HELD_TOL_DEG * max(1.0, abs(bound)):
                angle = bound
        name = f"{op.label} {op.name}".strip()
        what = f"{op.mechanism} {op.phase}" if op.mechanism and op.phase else "operation"
        held = (op.label, "min") in active
        note = "active: holds the makespan" if held else ""
        if least > 0 or op.mechanism:
            checks.append(Check(f"phase angle {name}", angle, float(least), "deg", sense="min",
                                applies=f"{what}; least angle from {source}", note=note))
        if math.isfinite(op.max_deg) and (op.label, "max") in active:
            checks.append(Check(f"phase angle {name} (upper bound)", angle, float(op.max_deg), "deg",
                                applies=f"{what}; bounds_deg", note="active: holds the makespan"))
        if held and source != "bounds_deg":
            warnings.append(Warning(f"{name} ({what}) is held at its least angle {least:.6g} deg by {source}: "
                                    "it sets the makespan", least, "an active phase limit"))
    slack = float(network.cycle_deg - result.makespan_deg)
    if slack < CLOSE_TO_LIMIT * network.cycle_deg:
        warnings.append(Warning(f"the group fills {result.makespan_deg:.6g} of its {network.cycle_deg:g} deg: "
                                f"{slack:.3g} deg to spare", slack, f"cycle slack < {100 * CLOSE_TO_LIMIT:g} %"))
    return Verdict(tuple(checks), tuple(warnings))


@dataclass(frozen=True)
class CyclogramRequest:
    """What ``camcad cyclogram`` can be asked: the scene, the speeds (--rpm text) and samples per phase."""

    scene: Path
    rpm: str | None = None
    samples: int = 2000


def run_cyclogram(request: CyclogramRequest):
    """``camcad cyclogram``: the group's network optimised with every operation's phase limits (the same
    function ``camcad profile`` uses, camcad.scene.phase_angles), as an AnalysisReport (key ``cyclogram``)
    whose ``result`` is the CyclogramAngles.

    Parameters
    ----------
    request : CyclogramRequest

    Returns
    -------
    camcad.scene.analysis.AnalysisReport
    """
    from camcad.scene.analysis import AnalysisReport, require_scene
    from camcad.scene.fields import parse_speeds
    from camcad.scene.file import read_scene
    from camcad.scene.phase_angles import cyclogram_angles

    if isinstance(request.samples, bool) or not isinstance(request.samples, int) or not 16 <= request.samples <= 10**6:
        raise CamcadError(f"--samples {request.samples} is not in 16..1000000", "--samples",
                          "give the cam-angle samples per phase, e.g. 2000")
    path = require_scene(Path(request.scene), "cyclogram")
    scene = read_scene(path)
    if scene.cyclogram is None:
        raise CamcadError("the scene has no [cyclogram] section", str(path),
                          "add [cyclogram] with [[cyclogram.operations]] (from, to, bounds_deg)")
    speeds = parse_speeds(request.rpm, "--rpm") if request.rpm is not None else (
        list(scene.speeds_rpm) if scene.speeds_rpm else None)
    found = cyclogram_angles(scene, speeds, request.samples)
    body = found.report()
    source = {"scene": str(path), "name": scene.name, "title": str(scene.cyclogram.get("name") or scene.name)}
    return AnalysisReport("cyclogram", body, cyclogram_verdict(found), source, found, dict(found.skipped))

