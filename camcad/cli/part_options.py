"""The options of `camcad profile` that make the part: --export and what the part needs (docs/part.md)."""

from __future__ import annotations

from typing import Annotated, Any

import typer

ExportOpt = Annotated[str | None, typer.Option(
    "--export", help="Also write the part's files: a comma list of points (profile_points.csv), cutter "
                     "(cutter_path.csv), gcode (profile.nc), step (cam.step), stl (cam.stl), servo "
                     "(servo_table.csv, an electronic cam table).")]
ServoStepOpt = Annotated[float, typer.Option("--servo-step", help="Master step of the servo table (deg).")]
ServoFormatOpt = Annotated[str, typer.Option("--servo-format", help="Servo table format: csv, codesys or twincat.")]
ServoRpmOpt = Annotated[float | None, typer.Option(
    "--servo-rpm", help="Master speed for the servo figures per second (rpm; default the scene's highest).")]
ServoNormaliseOpt = Annotated[bool, typer.Option(
    "--servo-normalise", help="Servo slave as a fraction of its stroke.")]
PolydyneOpt = Annotated[float | None, typer.Option(
    "--polydyne", help="Design the cam for the scene's elastic follower at this speed (rpm): a polydyne cam.")]
UnitsOpt = Annotated[str | None, typer.Option(
    "--units", help="Length unit of every written file: mm (default) or in (every length / 25.4, DXF $INSUNITS 1, "
                    "G20); the options stay in mm.")]
StepDegOpt = Annotated[str | None, typer.Option(
    "--step-deg", help="Step of profile_points.csv and cutter_path.csv (deg, default 1), or 'chord': the "
                       "profile's chord nodes within --tol-mm.")]
CutterRadiusOpt = Annotated[float | None, typer.Option(
    "--cutter-radius", help="Radius of the cutter or grinding wheel (mm), for cutter and gcode.")]
CompOpt = Annotated[str | None, typer.Option(
    "--comp", help="camcad (default): the program follows the cutter centre; machine: the flank, with G41.")]
FeedOpt = Annotated[float | None, typer.Option("--feed", help="Feed rate of the contour program (mm/min).")]
DepthOpt = Annotated[float | None, typer.Option(
    "--depth", help="Depth of cut (mm; a groove's depth); default: the thickness.")]
ThicknessOpt = Annotated[float | None, typer.Option("--thickness", help="Plate thickness of the solid (mm).")]
BoreOpt = Annotated[float | None, typer.Option("--bore", help="Bore diameter of the solid (mm).")]
KeywayOpt = Annotated[str | None, typer.Option(
    "--keyway", help="Keyway W,H (mm): width, and depth beyond the bore, on the cam's +y axis.")]
PlateOpt = Annotated[float | None, typer.Option("--plate", help="A groove cam's plate diameter (mm).")]


def export_options(*, export: str | None, units: str | None, step_deg: str | None, cutter_radius: float | None,
                   comp: str | None, feed: float | None, depth: float | None, thickness: float | None,
                   bore: float | None, keyway: str | None, plate: float | None) -> dict[str, Any] | None:
    """The options given, as ``camcad.scene.sections.export.ExportSettings`` field values (None: none given)."""
    from camcad.errors import CamcadError
    from camcad.scene.sections.export import COMPENSATION, UNITS, parse_keyway, parse_kinds, parse_step

    given: dict[str, Any] = {}
    if export is not None:
        kinds = tuple(kind for kind in parse_kinds(export) if kind != "servo")   # servo: camcad.profile.servo
        if kinds:
            given["kinds"] = kinds
    if units is not None:
        if units not in UNITS:
            raise CamcadError(f"unit {units!r} is unknown", "--units", "use mm or in")
        given["units"] = units
    if comp is not None:
        if comp not in COMPENSATION:
            raise CamcadError(f"cutter compensation {comp!r} is unknown", "--comp", "use camcad or machine")
        given["comp"] = comp
    if step_deg is not None:
        given["step_deg"] = parse_step(step_deg)
    if keyway is not None:
        given["keyway"] = parse_keyway(keyway)
    for name, value, option in (("cutter_radius", cutter_radius, "--cutter-radius"), ("feed", feed, "--feed"),
                                ("depth", depth, "--depth"), ("thickness", thickness, "--thickness"),
                                ("bore", bore, "--bore"), ("plate", plate, "--plate")):
        if value is None:
            continue
        if not (value > 0.0 and value < 1e9):
            raise CamcadError(f"{option} {value:g} must be a positive, finite number", option,
                              f"give {option} in {'mm/min' if name == 'feed' else 'mm'}")
        given[name] = float(value)
    return given or None
