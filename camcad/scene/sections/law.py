"""The ``[law]`` section of a scene: a standard law, or a drawn law from a DXF or table file.

Keys (angles deg, lengths mm):
    standard         shape of the rises (cycloidal, harmonic, poly345, ...), with ``phases`` and ``lift``
    return_standard  shape of the returns (default: the same as ``standard``)
    phases           "0:90:dwell,90:180:rise,..." — required for a standard law; overrides detection for a file
    lift             rise in mm (deg of swing for an oscillating follower); scales a drawn law when given
    file             a DXF drawing or a .csv/.txt table, relative to the scene file
    layer, handle, cycle, x_deg   choose and map the drawn curve (as the CLI options)
    y0, x0           the drawing's zero axis (y of zero acceleration) and the x of the cycle's start,
                     overriding what camcad finds (as --y0, --x0)
    fix              balance a drawn law first with this mode (min-change, ...); "none" only checks it
    tol              balance tolerance (fraction of the rise)
    law_of           "follower" (default), or "output": the law is the working member's after the [linkage],
                     and the cam is designed for psi = Pi^-1(y) (camcad.scene.linkage)
    segments         [[law.segments]] tables: a law designed from segments (camcad.law.segments), each with
                     to_deg, shape, to_mm and optional v_end, a_end, j_end ("match" or a number per deg) and
                     lambda; the first starts at 0 deg and 0 mm, the last ends at ``cycle``
    smoothing_error  a motion table's measurement error (its unit): the quintic spline's smoothing; absent:
                     generalised cross-validation (camcad.law.motion_table)
    accel_smoothing  "gcv" (default) or "none": the cubic re-smoothing of a motion table's second derivative;
    accel_smoothing_error  its stated error instead (unit per rad^2)
A table of radius-vectors (``theta_deg,r_mm``) becomes a motion through the scene's [follower].
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from camcad.balance.conditions import DEFAULT_TOL, MODES
from camcad.errors import CamcadError, excerpt
from camcad.law.segments import SegmentSpec, shape_names, solve_segments
from camcad.law.standard import shape_named
from camcad.law.standard import shape_names as standard_shape_names
from camcad.scene.fields import Field, read_table

#: the keys of one [[law.segments]] table whose value is "match" or a number (read apart from ``read_table``)
END_VALUE_KEYS = {"v_end": "mm/deg", "a_end": "mm/deg^2", "j_end": "mm/deg^3"}
#: the keys of one [[law.segments]] table (docs/SCENE.md lists them)
SEGMENT_FIELDS = [
    Field("to_deg", "float", "deg", required=True, help="(the cam angle where the segment ends)"),
    Field("shape", "str", required=True,
          help="(dwell, constant_velocity, or a VDI 2143 catalogue law: "
               + ", ".join(n for n in shape_names() if n not in ("dwell", "constant_velocity")) + ")"),
    Field("to_mm", "float", "mm", help="(the position at the segment's end; a dwell keeps its start)"),
    Field("v_end", "match|float", "mm/deg", help='("match": the next segment\'s start velocity; default: that where '
                                                 "the next segment sets it, else rest)"),
    Field("a_end", "match|float", "mm/deg^2", help="(poly5, poly7: the acceleration at the end)"),
    Field("j_end", "match|float", "mm/deg^3", help="(poly7: the jerk at the end)"),
    Field("lambda", "float", help="(the inflection point of inclined_sine, modified_sine, modified_trapezoid, "
                                  "constant_acceleration, harmonic_combination: a fraction 0..1 of the segment)"),
]


def _shape_names() -> tuple[str, ...]:
    return standard_shape_names()


def law_fields() -> list[Field]:
    """The keys of ``[law]`` (the shapes listed are camcad's standard laws)."""
    shapes = _shape_names()
    return [
        Field("standard", "str", help=f"(a standard shape: {', '.join(shapes)})"),
        Field("return_standard", "str", help="(the returns' shape; default: standard)"),
        Field("phases", "str", help='"0:90:dwell,90:180:rise,180:270:dwell,270:360:return" (deg)'),
        Field("lift", "float", "mm, or deg of swing", positive=True),
        Field("file", "str", help="(a DXF drawing or a .csv table of the acceleration)"),
        Field("layer", "str"),
        Field("handle", "str"),
        Field("y0", "float", "drawing units", help="(drawing y of zero acceleration; found when absent)"),
        Field("x0", "float", "drawing units", help="(drawing x of the cycle's start; the curve's start when absent)"),
        Field("cycle", "float", "deg", default=360.0, positive=True, maximum=360.0),
        Field("x_deg", "bool", default=False),
        Field("fix", "str", choices=MODES + ("none",), default="none"),
        Field("tol", "float", default=DEFAULT_TOL, positive=True),
        Field("law_of", "str", choices=("follower", "output"), default="follower",
              help="(what the law describes: the follower, or the working member after the [linkage])"),
        Field("segments", "list", help="(a law designed from [[law.segments]] tables: see [law.segments])"),
        Field("smoothing_error", "float", "the table's unit", positive=True,
              help="(a motion table's measurement error; absent: smoothing by generalised cross-validation)"),
        Field("accel_smoothing", "str", choices=("gcv", "none"), default="gcv",
              help="(a motion table's second derivative smoothed again by a cubic spline, or not)"),
        Field("accel_smoothing_error", "float", "the table's unit per rad^2", positive=True,
              help="(the stated error of the second derivative, instead of gcv)"),
    ]


@dataclass(frozen=True)
class LawSpec:
    """What the ``[law]`` section asks for (validated)."""

    where: str
    standard: str | None = None
    return_standard: str | None = None
    phases: str | None = None
    lift: float | None = None
    file: Path | None = None
    layer: str | None = None
    handle: str | None = None
    y0: float | None = None
    x0: float | None = None
    cycle: float = 360.0
    cycle_stated: bool = True
    x_deg: bool = False
    fix: str = "none"
    tol: float = 1e-5
    law_of: str = "follower"
    segments: tuple[SegmentSpec, ...] | None = None
    smoothing_error: float | None = None
    accel_smoothing: str | float = "gcv"


def parse_segments_table(items, where: str) -> tuple[SegmentSpec, ...]:
    """The [[law.segments]] tables as ``SegmentSpec`` (angles deg, positions mm, end values per deg)."""
    if not isinstance(items, list) or not items:
        raise CamcadError("segments must be a list of [[law.segments]] tables", where,
                          'write [[law.segments]] with to_deg = 60 and shape = "dwell", one table per segment')
    specs = []
    for number, item in enumerate(items, start=1):
        here = f"{where} segment {number}"
        if not isinstance(item, dict):
            raise CamcadError(f"segment {number} is {excerpt(item)}, not a table", where,
                              "write each segment as a [[law.segments]] table")
        ends: dict[str, float | str] = {}
        for key, unit in END_VALUE_KEYS.items():
            if key in item:
                raw = item[key]
                if raw == "match":
                    ends[key] = "match"
                elif isinstance(raw, (int, float)) and not isinstance(raw, bool) and math.isfinite(raw):
                    ends[key] = float(raw)
                else:
                    raise CamcadError(f"'{key}' must be \"match\" or a number in {unit}, got {excerpt(raw)}", here,
                                      f'write {key} = "match" or {key} = 0.25')
        plain = {k: v for k, v in item.items() if k not in END_VALUE_KEYS}
        values = read_table(plain, [f for f in SEGMENT_FIELDS if f.name not in END_VALUE_KEYS], here)
        specs.append(SegmentSpec(values["to_deg"], values["shape"], values["to_mm"], ends.get("v_end"),
                                 ends.get("a_end"), ends.get("j_end"), values["lambda"]))
    return tuple(specs)


def parse_law(table: dict, where: str, base_dir: Path) -> LawSpec:
    values = read_table(table, law_fields(), where)
    if values["segments"] is not None:
        others = [key for key in ("standard", "return_standard", "phases", "lift", "file") if values[key] is not None]
        if others:
            raise CamcadError(f"the law has segments and {', '.join(others)}", where,
                              "keep the segments (they give shape, angles and positions), or drop them")
        if values["fix"] != "none":
            raise CamcadError("a law designed from segments meets its end values by construction; fix balances a "
                              "drawn law", where, 'drop fix (or set fix = "none")')
        specs = parse_segments_table(values["segments"], f"{where} segments")
        solve_segments(specs, values["cycle"], f"{where} segments")    # refuse a bad law while reading the scene
        return LawSpec(where=where, cycle=values["cycle"], cycle_stated="cycle" in table, fix=values["fix"],
                       tol=values["tol"], law_of=values["law_of"], segments=specs)
    if values["standard"] is None and values["file"] is None:
        raise CamcadError("the law has no source", where,
                          'add standard = "cycloidal" (with phases and lift), file = "accel.dxf", or '
                          "[[law.segments]]")
    if values["standard"] is not None and values["file"] is not None:
        raise CamcadError("the law has both 'standard' and 'file'", where, "keep one of them")
    for key in ("standard", "return_standard"):
        if values[key] is not None:
            try:
                shape_named(values[key])
            except KeyError as err:
                raise CamcadError(str(err.args[0]), f"{where} {key}", "pick one of the names listed") from None
    if values["standard"] is not None:
        for key in ("phases", "lift"):
            if values[key] is None:
                raise CamcadError(f"missing value '{key}' for a standard law", where,
                                  'add phases = "0:90:dwell,90:180:rise,180:270:dwell,270:360:return" and lift = 25.0'
                                  if key == "phases" else "add lift = 25.0 (mm)")
    file = None
    if values["file"] is not None:
        if "\x00" in values["file"] or not values["file"].strip():
            raise CamcadError(f"law file name {excerpt(values['file'])} is not a file name", where,
                              'write file = "accel.dxf" (relative to the scene file)')
        file = _as_shown((base_dir / values["file"]).resolve())
        if not file.exists():
            raise CamcadError(f"law file {excerpt(values['file'])} not found", where,
                              "give the path relative to the scene file")
    return LawSpec(where=where, standard=values["standard"], return_standard=values["return_standard"],
                   phases=values["phases"], lift=values["lift"], file=file, layer=values["layer"],
                   handle=values["handle"], y0=values["y0"], x0=values["x0"], cycle=values["cycle"],
                   cycle_stated="cycle" in table, x_deg=values["x_deg"], fix=values["fix"], tol=values["tol"],
                   law_of=values["law_of"], smoothing_error=values["smoothing_error"],
                   accel_smoothing=(values["accel_smoothing_error"] if values["accel_smoothing_error"] is not None
                                    else values["accel_smoothing"]))


def _as_shown(path: Path) -> Path:
    """``path`` relative to the working folder when it lies inside it (what the user typed, in messages
    and reports), else absolute."""
    try:
        return path.relative_to(Path.cwd())
    except ValueError:
        return path

