"""What to make of a designed cam besides profile.dxf: the scene's [export] section and the profile options.

``--export points,cutter,gcode,step,stl`` (or ``kinds = "points,gcode"`` in [export]) asks for
profile_points.csv, cutter_path.csv, profile.nc, cam.step and cam.stl beside profile.dxf (docs/part.md).
The lengths a run writes are in ``units`` ("mm" or "in"): every file that carries lengths (profile.dxf and
its $INSUNITS, law.csv, the tables, the program, the solids); the options themselves are in mm, as every
length camcad takes. A quantity the part needs and the scene does not give is asked for (exit 2), never
filled in: the cutter radius for a cutter path or a program, the feed for a program, the thickness for a
solid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any

from camcad.errors import CamcadError, nearest_name
from camcad.scene.fields import MAX_MAGNITUDE, Field, read_table

#: what ``--export`` makes, and the file each writes (a conjugate pair's counter-cam adds counter_cam.*)
EXPORT_FILES = {"points": "profile_points.csv", "cutter": "cutter_path.csv", "gcode": "profile.nc",
                "step": "cam.step", "stl": "cam.stl", "servo": "servo_table.csv"}
EXPORT_KINDS = tuple(EXPORT_FILES)
UNITS = ("mm", "in")
COMPENSATION = ("camcad", "machine")

EXPORT_FIELDS: list[Field] = [
    Field("kinds", "str", help='what to write: a comma list of points, cutter, gcode, step, stl, servo'),
    Field("units", "str", choices=UNITS, default="mm", help="the written files' length unit"),
    Field("step_deg", "str", default="1",
          help='step of the points tables (deg, a number), or "chord" for the chord nodes'),
    Field("cutter_radius", "float", "mm", positive=True, help="cutter (or grinding wheel) radius"),
    Field("comp", "str", choices=COMPENSATION, default="camcad",
          help="camcad: the program follows the cutter centre; machine: the flank, with G41"),
    Field("feed", "float", "mm/min", positive=True, help="feed rate of the contour program"),
    Field("depth", "float", "mm", positive=True, help="depth of cut (and a groove's depth); the thickness when absent"),
    Field("thickness", "float", "mm", positive=True, help="plate thickness of the solid"),
    Field("bore", "float", "mm", positive=True, help="bore diameter"),
    Field("keyway", "str", help='keyway "W,H" or [W, H] (mm): width and depth beyond the bore'),
    Field("plate", "float", "mm", positive=True, help="a groove cam's plate diameter"),
]


@dataclass(frozen=True)
class ExportSettings:
    """What to write besides profile.dxf, and the part's data (lengths in mm, feed in mm/min).

    Parameters
    ----------
    kinds : tuple of str
        Any of ``EXPORT_KINDS``.
    units : str
        "mm" or "in": the length unit of every written file.
    step_deg : float or None
        Step of the points tables, deg; None: the profile's chord nodes (within its chord tolerance).
    cutter_radius : float, optional
        R, mm.
    comp : str
        "camcad" or "machine" (G41 on the nominal flank).
    feed : float, optional
        Feed rate, mm/min.
    depth : float, optional
        Depth of cut, mm (a groove's depth); None: the thickness.
    thickness : float, optional
        Plate thickness, mm.
    bore : float, optional
        Bore diameter, mm.
    keyway : (float, float), optional
        Keyway width and depth beyond the bore, mm.
    plate : float, optional
        A groove cam's plate diameter, mm.

    Examples
    --------
    >>> from camcad.scene.sections.export import ExportSettings
    >>> ExportSettings(kinds=("gcode",), cutter_radius=5.0, feed=300.0, thickness=12.0).cut_depth
    12.0
    """

    kinds: tuple[str, ...] = ()
    units: str = "mm"
    step_deg: float | None = 1.0
    cutter_radius: float | None = None
    comp: str = "camcad"
    feed: float | None = None
    depth: float | None = None
    thickness: float | None = None
    bore: float | None = None
    keyway: tuple[float, float] | None = None
    plate: float | None = None

    @property
    def cut_depth(self) -> float | None:
        return self.depth if self.depth is not None else self.thickness

    def validate(self, where: str = "--export") -> ExportSettings:
        """Raise CamcadError for a kind asked for without what it needs; return self."""
        wanted = set(self.kinds)
        if wanted & {"cutter", "gcode"} and self.cutter_radius is None:
            raise CamcadError(f"{'a cutter path' if 'cutter' in wanted else 'a contour program'} needs the cutter's "
                              "radius", where, "give --cutter-radius R (mm)")
        if "gcode" in wanted:
            if self.feed is None:
                raise CamcadError("a contour program needs a feed rate", where,
                                  "give --feed F (mm/min; written in in/min with --units in)")
            if self.cut_depth is None:
                raise CamcadError("a contour program needs the depth of cut", where,
                                  "give --depth D (mm), or --thickness T to cut through the plate")
        if wanted & {"step", "stl"} and self.thickness is None:
            raise CamcadError("a solid needs the plate's thickness", where, "give --thickness T (mm)")
        if self.keyway is not None and self.bore is None:
            raise CamcadError("a keyway needs a bore", "--keyway", "give --bore D (mm) too")
        return self


def parse_kinds(text: str, where: str = "--export") -> tuple[str, ...]:
    """``"points,gcode"`` → ("points", "gcode"): known kinds, each once, in the order given."""
    kinds: list[str] = []
    for name in (part.strip().lower() for part in str(text).split(",")):
        if not name:
            continue
        if name not in EXPORT_KINDS:
            raise CamcadError(f"unknown export {name!r}", where,
                              nearest_name(name, list(EXPORT_KINDS)).replace("valid keys", "exports"))
        if name not in kinds:
            kinds.append(name)
    if not kinds:
        raise CamcadError("no export named", where, f"give a comma list of {', '.join(EXPORT_KINDS)}")
    return tuple(kinds)


def parse_step(value: Any, where: str = "--step-deg") -> float | None:
    """A points table's step: a number of degrees dividing the turn (0 < step ≤ 10), or "chord" (None)."""
    text = str(value).strip().lower()
    if text == "chord":
        return None
    try:
        step = float(text)
    except ValueError:
        raise CamcadError(f"step {value!r} is not a number of degrees or 'chord'", where,
                          "give e.g. --step-deg 1, or --step-deg chord") from None
    if not (math.isfinite(step) and 0.0 < step <= 10.0):
        raise CamcadError(f"step {step:g} deg is out of range", where, "give a step between 0 and 10 deg")
    count = round(360.0 / step)
    if abs(count * step - 360.0) > 1e-9 * 360.0:
        raise CamcadError(f"a step of {step:g} deg does not divide the turn", where,
                          "give a step that divides 360 deg (e.g. 1, 0.5, 0.25)")
    return step


def parse_keyway(value: Any, where: str = "--keyway") -> tuple[float, float]:
    """``"W,H"`` (mm) → (W, H), both positive and finite."""
    parts = str(value).split(",")
    try:
        width, depth = (float(p) for p in parts)
    except ValueError:
        raise CamcadError(f"keyway {value!r} is not W,H", where, "give width and depth in mm, e.g. --keyway 6,2.8") \
            from None
    if not all(math.isfinite(v) and 0.0 < v <= MAX_MAGNITUDE for v in (width, depth)):
        raise CamcadError(f"keyway {value!r}: width and depth must be positive", where,
                          "give width and depth in mm, e.g. --keyway 6,2.8")
    return width, depth


def parse_export(table: Any, where: str) -> ExportSettings:
    """The scene's [export] table → ``ExportSettings`` (not yet validated against the kinds)."""
    if isinstance(table, dict):   # step_deg = 0.5 and keyway = [6, 2.8] are as good as their text
        table = dict(table)
        if isinstance(table.get("step_deg"), (int, float)) and not isinstance(table.get("step_deg"), bool):
            table["step_deg"] = repr(table["step_deg"])
        keyway = table.get("keyway")
        if isinstance(keyway, list) and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in keyway):
            table["keyway"] = ",".join(repr(v) for v in keyway)
    values = read_table(table, EXPORT_FIELDS, where)
    return ExportSettings(
        kinds=parse_kinds(values["kinds"], f"{where} kinds") if values["kinds"] is not None else (),
        units=values["units"], step_deg=parse_step(values["step_deg"], f"{where} step_deg"),
        cutter_radius=values["cutter_radius"], comp=values["comp"], feed=values["feed"], depth=values["depth"],
        thickness=values["thickness"], bore=values["bore"],
        keyway=parse_keyway(values["keyway"], f"{where} keyway") if values["keyway"] is not None else None,
        plate=values["plate"])


def merged(scene: ExportSettings | None, given: ExportSettings | None, given_fields: frozenset[str]) -> ExportSettings:
    """The scene's [export] with the options given on the command line (``given_fields``) put over it."""
    base = scene or ExportSettings()
    if given is None:
        return base
    return replace(base, **{f.name: getattr(given, f.name) for f in fields(ExportSettings) if f.name in given_fields})
