"""The scene's ``[linkage]`` section (with ``[linkage.adjust]``): the linkage between the follower and the
working member, and what the pipeline does with it.

``[linkage]`` describes the chain after the follower (lengths in mm in the cam's frame: origin at the cam
centre, the oscillating follower's pivot at (pivot, 0); angles in deg, counter-clockwise):

- ``type = "fourbar"``: the input link of length ``input_link`` is clamped to the follower's arm
  (``input_offset``, deg from the arm, or ``input_angle``, its absolute angle with the roller on the base
  circle), a ``coupler`` joins it to the ``output_link`` pivoted at ``output_pivot`` = [x, y]; the output link
  is the working member. ``branch`` = ±1 picks the assembly (``camcad.linkage.fourbar``).
- ``type = "sixbar"``: a second four-bar in series whose input link ``input_link_2`` is rigid with the first
  output link (``coupling_2`` deg from it), ``coupler_2``, ``output_link_2`` pivoted at ``output_pivot_2``,
  ``branch_2``; its output link is the working member.
- ``type = "table"``: Π as a table of (ψ, y) rows (``file`` = a .csv/.txt file, or ``table`` = [[ψ, y], …]),
  ψ in ``input_unit``, y in ``output_unit``.
- ``type = "ratio"``: Π = ``ratio`` · ψ (the constant ratio of camcad's [stops]).

``output_unit`` is also the unit of the [law] when ``[law] law_of = "output"`` (the law then describes the
working member, and the cam is designed for ψ = Π⁻¹(y)). ``mu_min`` is the transmission-angle limit (deg).
``output_inertia`` (kg·m², or kg for a sliding member) and ``output_load`` (N·m or N, resisting its motion,
within ``output_load_range_deg``) are the working member's, reduced to the follower and the contact through
Π' (``camcad.linkage.transfer``).

``[linkage.adjust]``: one adjustable element (``camcad.linkage.adjust``) and its ``settings``; the pipeline
runs every setting and reports each and the governing one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from camcad.errors import CamcadError, excerpt
from camcad.io.table_read import read_table as read_rows
from camcad.scene.fields import Field, read_table

TYPES = ("fourbar", "sixbar", "table", "ratio")
UNITS = ("deg", "rad", "mm")
DIRECTIONS = ("auto", "ccw", "cw")
#: the default transmission-angle limit (deg), as ``camcad linkage fgen --mu-min``
MU_MIN_DEG = 30.0

LINKAGE_FIELDS: list[Field] = [
    Field("type", "str", required=True, choices=TYPES, help="(fourbar, sixbar, table or ratio)"),
    Field("output_pivot", "list", "mm", help="[x, y] of the output link's frame pivot C (cam frame)"),
    Field("input_link", "float", "mm", positive=True, help="input link OA, clamped to the follower's arm"),
    Field("coupler", "float", "mm", positive=True, help="coupler AB"),
    Field("output_link", "float", "mm", positive=True, help="output link CB (the working member for a four-bar)"),
    Field("input_offset", "float", "deg", help="angle from the follower's arm to the input link (CCW)"),
    Field("input_angle", "float", "deg", help="absolute angle of the input link on the base circle "
                                              "(instead of input_offset)"),
    Field("branch", "int", default=1, minimum=-1, maximum=1, help="assembly branch +1 or -1"),
    Field("output_pivot_2", "list", "mm", help="six-bar: [x, y] of the second output pivot F"),
    Field("input_link_2", "float", "mm", positive=True, help="six-bar: CD, rigid with the first output link"),
    Field("coupling_2", "float", "deg", default=0.0, help="six-bar: angle from CB to CD"),
    Field("coupler_2", "float", "mm", positive=True, help="six-bar: coupler DE"),
    Field("output_link_2", "float", "mm", positive=True, help="six-bar: output link FE (the working member)"),
    Field("branch_2", "int", default=1, minimum=-1, maximum=1, help="six-bar: branch of the second loop"),
    Field("coupler_point", "list", "mm", help="[u, v]: a point of the (first) coupler, u along AB, v to its left"),
    Field("file", "str", help="table: a .csv/.txt file of psi, y rows"),
    Field("table", "list", help="table: [[psi, y], ...] rows"),
    Field("input_unit", "str", default="deg", choices=UNITS, help="table: unit of psi (deg/rad swing, mm lift)"),
    Field("output_unit", "str", choices=UNITS, help="unit of y in the table, the ratio and a law_of = output law "
                                                    "(default deg for a turning member, mm for a ratio)"),
    Field("ratio", "float", positive=True, help="ratio: y per unit of psi"),
    Field("output_direction", "str", default="auto", choices=DIRECTIONS,
          help="four/six-bar: the working member's positive sense (auto: the one it turns on the rise)"),
    Field("mu_min", "float", "deg", default=MU_MIN_DEG, minimum=0.0, maximum=90.0,
          help="transmission-angle limit"),
    Field("output_inertia", "float", "kg m^2 (kg)", minimum=0.0, help="the working member's J (mass if it slides)"),
    Field("output_load", "float", "N m (N)", help="load on the working member, resisting its motion"),
    Field("output_load_range_deg", "list", "deg", help="[start, end] cam angles of output_load (all if not given)"),
    Field("adjust", "table", help="the [linkage.adjust] table"),
]

ADJUST_FIELDS: list[Field] = [
    Field("element", "str", required=True, choices=("pivot", "joint", "link_angle"),
          help="a frame pivot on an arc or slot, a joint on its lever, or the input link locked at angles"),
    Field("joint", "str", default="", help="pivot: C (or F of a six-bar); joint: A (input lever), B or E (output "
                                           "lever)"),
    Field("path", "str", default="arc", choices=("arc", "slot"), help="the pivot's or joint's path"),
    Field("centre", "list", "mm", help="[x, y]: the arc's centre with the follower on the base circle"),
    Field("direction", "float", "deg", default=0.0, help="slot: its direction"),
    Field("settings", "list", "deg (mm for a slot)", required=True,
          help="lock angles of the arc's radius, slot positions, or added link angles"),
]


#: the most settings an adjustable linkage may list: each is a whole analysis over the cycle (0.17 s of CPU
#: for the batten sample; 25 of them took 6.8 s), so 20 stay within seconds
MAX_ADJUST_SETTINGS = 20


@dataclass(frozen=True)
class AdjustSpec:
    where: str
    element: str
    joint: str
    path: str
    centre: tuple[float, float] | None
    direction_deg: float
    settings: tuple[float, ...]


@dataclass(frozen=True)
class LinkageSpec:
    """What ``[linkage]`` asks for (validated; lengths mm, angles deg)."""

    where: str
    type: str
    values: dict
    rows: tuple | None = None          # table rows (psi, y) as read
    adjust: AdjustSpec | None = None

    @property
    def output_unit(self) -> str:
        unit = self.values["output_unit"]
        if unit is not None:
            return unit
        return "mm" if self.type == "ratio" else "deg"


def _point(value, key: str, where: str) -> tuple[float, float]:
    if (not isinstance(value, list) or len(value) != 2
            or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) for v in value)):
        raise CamcadError(f"'{key}' must be [x, y] in mm, got {excerpt(value)}", where, f"write {key} = [120.0, 35.0]")
    return float(value[0]), float(value[1])


def parse_linkage(table: Any, where: str, base_dir: Path) -> LinkageSpec:
    """A scene's ``[linkage]`` table (and its ``[linkage.adjust]``) → LinkageSpec; every mistake is one line.

    Parameters
    ----------
    table : dict
        The raw TOML table.
    where : str
        "scene.toml [linkage]" for messages.
    base_dir : Path
        Folder of the scene (a table ``file`` is relative to it).

    Returns
    -------
    LinkageSpec
    """
    values = read_table(table, LINKAGE_FIELDS, where)
    kind = values["type"]
    needed = {"fourbar": ("output_pivot", "input_link", "coupler", "output_link"),
              "sixbar": ("output_pivot", "input_link", "coupler", "output_link", "output_pivot_2", "input_link_2",
                         "coupler_2", "output_link_2"),
              "table": (), "ratio": ("ratio",)}[kind]
    for key in needed:
        if values[key] is None:
            raise CamcadError(f"missing value '{key}' for a {kind} linkage", where, f"add {key} = ...")
    if kind in ("fourbar", "sixbar"):
        for key in ("output_pivot", "output_pivot_2", "coupler_point"):
            if values[key] is not None:
                values[key] = _point(values[key], key, where)
        if values["input_offset"] is not None and values["input_angle"] is not None:
            raise CamcadError("input_offset and input_angle both place the input link", where, "give only one")
        if values["input_offset"] is None and values["input_angle"] is None:
            raise CamcadError("the input link has no angle", where,
                              "add input_offset = ... (deg from the follower's arm) or input_angle = ... (deg)")
        for key in ("branch", "branch_2"):
            if values[key] == 0:
                raise CamcadError(f"'{key}' must be +1 or -1, got 0", where, f"write {key} = 1 or {key} = -1")
        if values["output_unit"] == "mm":
            raise CamcadError("a four-bar or six-bar turns its working member: output_unit mm does not apply",
                              where, 'use output_unit = "deg" or "rad"')
    else:
        extra = [k for k in ("output_pivot", "input_link", "coupler", "output_link", "output_pivot_2",
                             "input_link_2", "coupler_2", "output_link_2", "coupler_point", "input_offset",
                             "input_angle") if values[k] is not None]
        if extra:
            raise CamcadError(f"'{extra[0]}' belongs to a four-bar or six-bar, this linkage is a {kind}", where,
                              f"drop {extra[0]} or set type = \"fourbar\"")
    if kind == "fourbar":
        extra = [k for k in ("output_pivot_2", "input_link_2", "coupler_2", "output_link_2")
                 if values[k] is not None]
        if extra:
            raise CamcadError(f"'{extra[0]}' belongs to a six-bar", where, 'drop it or set type = "sixbar"')
    rows = None
    if kind == "table":
        rows = _table_rows(values, where, base_dir)
    elif values["file"] is not None or values["table"] is not None:
        raise CamcadError("'file' and 'table' give a tabulated position function", where,
                          'drop them or set type = "table"')
    if kind != "ratio" and values["ratio"] is not None:
        raise CamcadError("'ratio' is for type = \"ratio\"", where, "drop ratio or set type = \"ratio\"")
    load_range = values["output_load_range_deg"]
    if load_range is not None:
        if (len(load_range) != 2 or any(isinstance(x, bool) or not isinstance(x, (int, float)) for x in load_range)):
            raise CamcadError(f"'output_load_range_deg' must be [start, end] in deg, got {excerpt(load_range)}",
                              where, "write output_load_range_deg = [90.0, 180.0]")
        values["output_load_range_deg"] = (float(load_range[0]), float(load_range[1]))
    adjust = None
    if values["adjust"] is not None:
        adjust = parse_adjust(values["adjust"], where.replace("[linkage]", "[linkage.adjust]")
                              if "[linkage]" in where else where + " adjust", kind)
    return LinkageSpec(where, kind, values, rows, adjust)


def _table_rows(values: dict, where: str, base_dir: Path) -> tuple:
    if (values["file"] is None) == (values["table"] is None):
        raise CamcadError("a table linkage needs its rows as 'file' or as 'table'", where,
                          'write file = "pi.csv" (two columns psi, y) or table = [[0, 0], [10, 5], ...]')
    if values["file"] is not None:
        path = (base_dir / values["file"]).resolve()
        if not path.is_file():
            raise CamcadError(f"table file {excerpt(values['file'])} not found", where,
                              "give the path relative to the scene file")
        found = read_rows(path)
        return tuple(zip(found.theta_deg.tolist(), found.accel.tolist()))
    rows = []
    for i, row in enumerate(values["table"]):
        if (not isinstance(row, list) or len(row) != 2
                or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) for v in row)):
            raise CamcadError(f"table row {i + 1} is {excerpt(row)}, not [psi, y]", f"{where} table",
                              "write table = [[0.0, 0.0], [5.0, 2.1], ...]")
        rows.append((float(row[0]), float(row[1])))
    return tuple(rows)


def parse_adjust(table: Any, where: str, kind: str) -> AdjustSpec:
    """``[linkage.adjust]`` → AdjustSpec (deg, mm); the joint must exist in the linkage ``kind``."""
    values = read_table(table, ADJUST_FIELDS, where)
    element, joint = values["element"], values["joint"].upper()
    if kind in ("table", "ratio"):
        raise CamcadError(f"a {kind} position function has no links to adjust", where,
                          "describe the linkage as a fourbar or sixbar")
    allowed = {"pivot": ("C", "F") if kind == "sixbar" else ("C",),
               "joint": ("A", "B", "E") if kind == "sixbar" else ("A", "B"),
               "link_angle": ("",)}[element]
    if joint not in allowed:
        raise CamcadError(f"joint {excerpt(values['joint'])} cannot be a {element} of a {kind}", where,
                          f"use joint = {' or '.join(repr(j) for j in allowed)}" if allowed != ("",)
                          else "drop joint (the input link is locked at the settings' angles)")
    centre = None
    if element != "link_angle":
        if values["path"] == "arc":
            if values["centre"] is None:
                raise CamcadError("an arc needs its centre", where, "add centre = [x, y] (mm)")
            centre = _point(values["centre"], "centre", where)
        elif values["centre"] is not None:
            raise CamcadError("a slot has no centre", where, "drop centre, give direction (deg)")
    settings = values["settings"]
    if (not settings or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)
                            for v in settings)):
        raise CamcadError(f"'settings' must be a list of numbers, got {excerpt(settings)}", where,
                          "write settings = [40.0, 50.0, 60.0]")
    if len(settings) > MAX_ADJUST_SETTINGS:   # each setting is a whole linkage analysis
        raise CamcadError(f"{len(settings)} settings are too many (at most {MAX_ADJUST_SETTINGS})", where,
                          "list the settings the machine is adjusted to, e.g. settings = [40.0, 50.0, 60.0]")
    return AdjustSpec(where, element, joint, values["path"] if element != "link_angle" else "angle", centre,
                      values["direction"], tuple(float(v) for v in settings))


