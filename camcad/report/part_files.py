"""The part's files beside profile.dxf: profile_points.csv, cutter_path.csv, profile.nc, cam.step, cam.stl.

``part_files`` makes every file's bytes first (so that a cutter that cannot follow the profile, or a
solid that does not fit, is refused before anything is written); ``write_part_files`` writes them
atomically into the mechanism's ``OutputFolder``. A conjugate pair's counter-cam has its own program
and solids (counter_profile.nc, counter_cam.step, counter_cam.stl); a groove cam's outer flank is in the
tables and the program beside the profile. Lengths are in the ``units`` asked for (mm or in), said in
every file: the tables' column names (``x_mm`` / ``x_in``) and header, the program's G21 / G20, the
STEP file's unit, the STL header. The same design gives the same bytes.

Tables: ``#`` comment lines (what the table is, units, follower, turning sense, zero reference), then one
row per cam angle. Program: the common subset of ISO 6983 / RS-274 (G0, G1, G2, G3 with I/J, G17,
G20/G21, G40/G41, G90, G94, F, M30), comments in parentheses, no spindle or coolant codes.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from camcad.errors import CamcadError
from camcad.io.atomic import write_atomic
from camcad.io.output_folder import OutputFolder
from camcad.profile.synth import ProfileResult
from camcad.profile.toolpath import (
    ContourProgram,
    Move,
    contour_program,
    cutter_paths,
    flanks,
    part_ready,
    polar,
    table_angles,
    turn_sense,
)
from camcad.report.solid import mesh, part_shape, step_bytes, stl_bytes, volume
from camcad.scene.pipeline import SceneResult
from camcad.scene.sections.export import EXPORT_FILES, ExportSettings, parse_export

INCH_MM = 25.4
#: decimals of a program's coordinates: 0.0001 mm, 0.00001 in
DECIMALS = {"mm": 4, "in": 5}


@dataclass
class PartFiles:
    """The bytes of each part file (name → bytes), what the report says of them (mm) and the length unit of
    every file the mechanism writes ("mm" or "in")."""

    files: dict[str, bytes] = field(default_factory=dict)
    report: dict = field(default_factory=dict)
    units: str = "mm"
    servo: bool = False     # the [export] kinds ask for the servo table (camcad.report.servo writes it)


def _scale(units: str) -> float:
    return 1.0 / INCH_MM if units == "in" else 1.0


def _number(value: float) -> str:
    text = f"{value:.15g}"
    return "0" if text == "-0" else text


def _rows(columns: list[np.ndarray]) -> str:
    return "".join(",".join(_number(v) for v in row) + "\n" for row in zip(*(c.tolist() for c in columns)))


def _frame_lines(result: ProfileResult, units: str) -> list[str]:
    f = result.follower
    where = ("the follower's axis is the line x = e" if f.kind != "oscillating"
             else f"the follower's pivot is at x = {f.pivot:g} mm, y = 0")
    return [
        f"# follower: {f.describe()}",
        f"# frame: the cam's own, origin at the cam centre, x and y as in profile.dxf; at cam angle 0 it is the "
        f"machine frame ({where}, the follower on the +y side)",
        f"# the cam turns {turn_sense(result)}; theta_deg is the cam angle at which the follower touches the row's "
        "point",
        f"# units: lengths in {units}, angles in deg; polar_deg from +x, counter-clockwise",
    ]


def points_text(result: ProfileResult, settings: ExportSettings) -> str:
    """profile_points.csv: per cam angle, each flank's point (x, y, polar radius and angle) and its unit
    normal toward the follower, and the pitch curve (roller centre) where there is one."""
    u = settings.units
    k = _scale(u)
    theta = table_angles(result, settings.step_deg)
    header = ["theta_deg"]
    columns: list[np.ndarray] = [np.degrees(theta)]
    for flank in flanks(result):
        p = flank.contour(theta).points
        r, angle = polar(p)
        n = flank.normal(theta)
        key = flank.key
        header += [f"{key}x_{u}", f"{key}y_{u}", f"{key}r_{u}", f"{key}polar_deg", f"{key}nx", f"{key}ny"]
        columns += [p[:, 0] * k, p[:, 1] * k, r * k, angle, n[:, 0], n[:, 1]]
    if result.follower.kind != "flat":
        pitches = [("pitch_", result.geometry.pitch(theta).points)]
        if result.follower.has_pair:
            pitches.append(("counter_pitch_", result.geometry.pitch(theta, second=True).points))
        for key, p in pitches:
            r, angle = polar(p)
            header += [f"{key}x_{u}", f"{key}y_{u}", f"{key}r_{u}", f"{key}polar_deg"]
            columns += [p[:, 0] * k, p[:, 1] * k, r * k, angle]
    spacing = (f"every {settings.step_deg:g} deg of cam angle" if settings.step_deg is not None
               else f"at the chord nodes of the written curves (within {result.settings.tol_mm:g} mm)")
    names = ", ".join(f.name for f in flanks(result))
    lines = [f"# camcad profile_points.csv: {result.name}: {names}"
             + (" and the pitch curve" if result.follower.kind != "flat" else ""),
             *_frame_lines(result, u),
             "# nx, ny: unit normal of the flank at the point, out of the cam's material toward the follower",
             f"# rows: {spacing}; {len(theta)} rows"]
    return "\n".join(lines) + "\n" + ",".join(header) + "\n" + _rows(columns)


def cutter_text(result: ProfileResult, settings: ExportSettings) -> str:
    """cutter_path.csv: per cam angle, the centre of the cutter on each flank and the unit normal from the
    flank toward it (the centre = the flank's point + R · normal)."""
    u = settings.units
    k = _scale(u)
    radius = float(settings.cutter_radius or 0.0)
    theta = table_angles(result, settings.step_deg)
    paths = cutter_paths(result, radius, theta)
    header = ["theta_deg"]
    columns: list[np.ndarray] = [np.degrees(theta)]
    sides = []
    for path in paths:
        key = path.flank.key
        header += [f"{key}x_{u}", f"{key}y_{u}", f"{key}nx", f"{key}ny"]
        columns += [path.points[:, 0] * k, path.points[:, 1] * k, path.normals[:, 0], path.normals[:, 1]]
        sides.append(f"{path.flank.name}: {path.flank.side} contour")
    spacing = (f"every {settings.step_deg:g} deg of cam angle" if settings.step_deg is not None
               else f"at the chord nodes of the written curves (within {result.settings.tol_mm:g} mm)")
    lines = [f"# camcad cutter_path.csv: {result.name}: the centre of a cutter of radius {radius * k:.6g} {u} "
             f"({'; '.join(sides)})",
             "# exact offset of each flank along its normal: centre = flank point + R * (nx, ny)",
             *_frame_lines(result, u),
             "# nx, ny: unit normal of the flank, out of the cam's material toward the cutter",
             f"# rows: {spacing}; {len(theta)} rows"]
    return "\n".join(lines) + "\n" + ",".join(header) + "\n" + _rows(columns)


# --------------------------------------------------------------------------------------------
# the contour program
# --------------------------------------------------------------------------------------------

def _fmt(value: float, units: str) -> str:
    digits = DECIMALS[units]
    text = f"{value * _scale(units):.{digits}f}"
    return text[1:] if text.startswith("-") and float(text) == 0.0 else text


def _comment(text: str) -> str:
    clean = "".join(ch if 32 <= ord(ch) < 127 and ch not in "()" else " " for ch in text.replace("°", " deg"))
    return f"({clean.strip()})"


def gcode_text(result: ProfileResult, program: ContourProgram, settings: ExportSettings, filename: str) -> str:
    """The contour program as text: a comment header, the passes, the retract and M30."""
    u = settings.units
    k = _scale(u)
    feed = float(settings.feed or 0.0) * k
    radius = program.cutter_radius
    part = "counter-cam" if program.part == "counter_cam" else "cam"
    what = "; ".join(p.label for p in program.passes)
    comp = ("the cutter centre, offset by camcad, --comp camcad: no G41/G42" if program.comp == "camcad" else
            f"the flank itself, --comp machine: G41 on the lead-in line, the control offsets by its own tool "
            f"radius; the leads are made for {radius * k:.6g} {u}")
    arcs = sum(p.arcs for p in program.passes)
    lines_count = sum(p.lines for p in program.passes)
    deviation = max(p.max_deviation for p in program.passes)
    header = [
        "%",
        _comment(f"camcad {filename}: {result.name}, the {part}"),
        _comment(f"passes: {what}"),
        _comment(f"follower: {result.follower.describe()}"),
        _comment(f"units: {'inch G20' if u == 'in' else 'mm G21'}; absolute G90; XY plane G17; feed per minute G94"),
        _comment("origin: X0 Y0 the cam centre, X and Y as in profile.dxf at cam angle 0; Z0 the top of the stock"),
        _comment(f"tool: cutter radius {radius * k:.6g} {u}; path: {comp}"),
        _comment(f"climb milling: the material on the right of the travel; start at cam angle "
                 f"{program.start_deg:.6g} deg, on tangent lead-in and lead-out arcs"),
        _comment(f"feed {feed:.6g} {u}/min; depth {program.depth * k:.6g} {u} in one pass; clearance Z "
                 f"{program.clearance * k:.6g} {u}"),
        _comment(f"contour: {arcs} arcs and {lines_count} lines of a biarc fit within {program.tol_mm * k:.3g} {u} "
                 f"of the exact path, largest deviation found {deviation * k:.3g} {u}"),
        _comment("no spindle, coolant or tool-change codes: add those of your machine"),
        f"G17 {'G20' if u == 'in' else 'G21'} G90 G94 G40",
        f"G0 Z{_fmt(program.clearance, u)}",
    ]
    body: list[str] = []
    feed_set = False
    x = y = None
    for p in program.passes:
        for move in p.moves:
            if move.note:
                body.append(_comment(move.note))
            words, feed_set, x, y = _move_words(move, u, feed, feed_set, x, y)
            if words:
                body.append(words)
    footer = [f"G0 Z{_fmt(program.clearance, u)}", "M30", "%"]
    return "\n".join(header + body + footer) + "\n"


def _move_words(move: Move, u: str, feed: float, feed_set: bool, x, y):
    """One block's words; the current X, Y (text) kept so that unchanged axes are left out."""
    words = []
    if move.comp == "left":
        words.append("G41")
    elif move.comp == "right":
        words.append("G42")
    elif move.comp == "off":
        words.append("G40")
    code = {"rapid": "G0", "line": "G1"}.get(move.kind) or ("G3" if move.ccw else "G2")
    words.insert(0, code)
    start = (x, y)
    if move.end is not None:
        nx, ny = _fmt(move.end[0], u), _fmt(move.end[1], u)
        if nx != x or move.kind == "arc":
            words.append(f"X{nx}")
        if ny != y or move.kind == "arc":
            words.append(f"Y{ny}")
        x, y = nx, ny
    if move.z is not None:
        words.append(f"Z{_fmt(move.z, u)}")
    if move.kind == "arc" and move.centre is not None:
        sx, sy = float(start[0]) / _scale(u), float(start[1]) / _scale(u)
        words.append(f"I{_fmt(move.centre[0] - sx, u)}")
        words.append(f"J{_fmt(move.centre[1] - sy, u)}")
    if move.kind != "rapid" and not feed_set:
        words.append(f"F{feed:.6g}")
        feed_set = True
    if len(words) == 1 and move.kind != "arc":
        return "", feed_set, x, y      # a move to where the tool is
    return " ".join(words), feed_set, x, y


# --------------------------------------------------------------------------------------------
# all the part's files
# --------------------------------------------------------------------------------------------

def _units_note(settings: ExportSettings) -> str:
    return "lengths in inches (every length / 25.4)" if settings.units == "in" else "lengths in mm"


def part_files(result: ProfileResult, settings: ExportSettings) -> PartFiles:
    """Every part file ``settings.kinds`` asks for, as bytes, and the report's ``export`` object (mm).

    Parameters
    ----------
    result : ProfileResult
        The synthesised cam.
    settings : ExportSettings
        What to make and the part's data (mm, mm/min); validated here.

    Returns
    -------
    PartFiles
        ``files``: file name → bytes (the same design gives the same bytes); ``report``: the figures of each
        (cutter radius, arcs and lines, deviations in mm, solid volumes in mm³) and notes.

    Raises
    ------
    CamcadError
        A kind without what it needs, a profile that undercuts or does not close, a cutter that cannot
        follow a flank (with the cam angle), a solid that does not fit, or the kernel missing.

    Examples
    --------
    >>> import camcad
    >>> from camcad.report.part_files import part_files
    >>> from camcad.scene.sections.export import ExportSettings
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> result = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0),
    ...                            camcad.ProfileSettings(plots=False, design=False, tol_mm=0.01))
    >>> made = part_files(result, ExportSettings(kinds=("points", "gcode"), cutter_radius=5.0, feed=400.0,
    ...                                          depth=8.0))
    >>> sorted(made.files)
    ['profile.nc', 'profile_points.csv']
    >>> lines = made.files["profile_points.csv"].decode().splitlines()
    >>> next(line for line in lines if not line.startswith("#")).split(",")[:5]
    ['theta_deg', 'x_mm', 'y_mm', 'r_mm', 'polar_deg']
    """
    settings = settings.validate()
    made = PartFiles(units=settings.units)
    kinds = settings.kinds
    report: dict = {"units": settings.units, "kinds": list(kinds), "notes": [_units_note(settings)]}
    if "points" in kinds:
        made.files[EXPORT_FILES["points"]] = points_text(result, settings).encode("ascii")
    if "cutter" in kinds:
        made.files[EXPORT_FILES["cutter"]] = cutter_text(result, settings).encode("ascii")
        report["cutter_radius_mm"] = settings.cutter_radius
    parts = ["cam"] + (["counter_cam"] if result.follower.has_pair else [])
    if "gcode" in kinds:
        programs = {}
        for part in parts:
            name = "profile.nc" if part == "cam" else "counter_profile.nc"
            program = contour_program(result, part, float(settings.cutter_radius or 0.0),
                                      float(settings.cut_depth or 0.0), settings.comp)
            made.files[name] = gcode_text(result, program, settings, name).encode("ascii")
            programs[name] = {"comp": program.comp, "start_deg": program.start_deg,
                              "passes": [p.label for p in program.passes],
                              "arcs": sum(p.arcs for p in program.passes),
                              "lines": sum(p.lines for p in program.passes),
                              "max_deviation_mm": max(p.max_deviation for p in program.passes),
                              "tolerance_mm": program.tol_mm, "feed_mm_per_min": settings.feed,
                              "depth_mm": program.depth}
        report["programs"] = programs
        report["cutter_radius_mm"] = settings.cutter_radius
    if "step" in kinds or "stl" in kinds:
        part_ready(result, "step" if "step" in kinds else "stl")
        solids = {}
        for part in parts:
            shape = part_shape(result, part, float(settings.thickness or 0.0), settings.bore, settings.keyway,
                               settings.plate, settings.cut_depth if result.follower.groove else None)
            label = f"{result.name} {'counter-cam' if part == 'counter_cam' else 'cam'}"
            figures = {"volume_mm3": volume(shape.shape), "thickness_mm": shape.thickness, "bore_mm": shape.bore,
                       "keyway_mm": list(shape.keyway) if shape.keyway else None, "plate_mm": shape.plate,
                       "groove_depth_mm": shape.groove_depth, "outline_deviation_mm": shape.max_deviation}
            if "step" in kinds:
                made.files[f"{part}.step"] = step_bytes(shape, label, settings.units)
            if "stl" in kinds:
                vertices, faces = mesh(shape, result.settings.tol_mm)
                made.files[f"{part}.stl"] = stl_bytes(vertices, faces, label, settings.units)
                figures["stl_triangles"] = len(faces)
            solids[part] = figures
            report["notes"].extend(f"{part}: {note}" for note in shape.notes)
        report["solids"] = solids
    report["files"] = list(made.files)
    made.report = report
    return made


def write_part_files(made: PartFiles, out: OutputFolder, sub: tuple[str, ...] = ()) -> list[Path]:
    """Write the files of ``part_files`` into the output folder (atomically; never over an input)."""
    written = []
    for name, data in made.files.items():
        def write(tmp: Path, data: bytes = data) -> None:
            tmp.write_bytes(data)

        written.append(write_atomic(out.path(*sub, name), write))
    return written



def scene_part_files(result: SceneResult, given: dict | None) -> dict[str, PartFiles]:
    """Each mechanism's part files (``part_files``), from its [export] section with the command line's
    options ``given`` (``ExportSettings`` field names → values) put over it; made before anything is written,
    so that a part that cannot be made is refused with nothing written (exit 2)."""
    out = {}
    for name, run in result.runs.items():
        mech = result.scene.mechanism(name)
        where = mech.where(result.scene.path, "export")
        settings = parse_export(mech.sections["export"], where) if mech.has("export") else ExportSettings()
        if given:
            settings = replace(settings, **given)
        servo = "servo" in settings.kinds
        settings = replace(settings, kinds=tuple(k for k in settings.kinds if k != "servo"))
        if run.profile is None:
            if settings.kinds:
                raise CamcadError("there is no profile to make a part of", where, "add [follower] to the mechanism")
            out[name] = PartFiles(units=settings.units, servo=servo)
            continue
        out[name] = replace(part_files(run.profile, settings), servo=servo)
    return out
