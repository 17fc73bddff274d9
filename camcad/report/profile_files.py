"""Writing a synthesised profile: profile.dxf, law.csv, report.json and the plots."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import cast

import numpy as np

from camcad.io.atomic import write_text_atomic
from camcad.io.dxf_write import Drawing, DxfCircle, DxfLine, DxfPath, DxfSpline, DxfText, scaled_drawing, write_dxf
from camcad.io.jsonout import write_json
from camcad.io.output_folder import OutputFolder
from camcad.profile.scaled_law import describe_law, describe_phases
from camcad.profile.summary import profile_report as report
from camcad.profile.summary import stroke
from camcad.profile.synth import CurveResult, ProfileResult, ProfileSettings
from camcad.report.profile import save_profile_plots

#: mm per inch
INCH_MM = 25.4
LAYERS = ("PROFILE", "PITCH", "BASE_CIRCLE", "CENTER", "ROLLER", "TEXT")


def _path(layer: str, curve: CurveResult, prefer_arcs: bool = True) -> DxfPath:
    if prefer_arcs and curve.arcs is not None:
        return DxfPath(layer, curve.arcs.vertices, curve.closed, curve.arcs.bulges)
    return DxfPath(layer, curve.polyline.points, curve.closed)


def drawing_texts(result: ProfileResult, units: str = "mm") -> list[str]:
    """The TEXT layer's lines (ASCII): law, phases, follower (Rb, Rr, e), lift or swing, key figures; the
    drawing's length unit (``units``: "mm" or "in"; the figures of the text stay in mm)."""
    f = result.follower
    pa = result.pressure_angle
    if f.kind == "oscillating":
        size = f"swing {math.degrees(stroke(result)):.6g} deg"
    else:
        size = f"lift {stroke(result):.6g} mm"
    lines = [
        f"camcad profile: {result.name}",
        f"law: {describe_law(result.law)}",
        f"phases (deg): {describe_phases(result.law)}",
        f"follower: {f.describe()}",
        f"{size} (the follower's stroke)",
        (f"pressure angle max {math.degrees(pa.maximum.value):.3f} deg at {math.degrees(pa.maximum.at):.3f} deg, "
         f"min {math.degrees(pa.minimum.value):.3f} deg at {math.degrees(pa.minimum.at):.3f} deg"),
        (f"units mm, cam turns {'CW' if f.cw else 'CCW'}, chord tolerance {result.settings.tol_mm:g} mm"
         if units == "mm" else f"units inch (the figures above in mm), cam turns {'CW' if f.cw else 'CCW'}, "
                               f"chord tolerance {result.settings.tol_mm / 25.4:.3g} in"),
    ]
    return lines


def build_drawing(result: ProfileResult, units: str = "mm") -> Drawing:
    """The profile drawing: layers PROFILE, PITCH, BASE_CIRCLE, CENTER, ROLLER, TEXT (+ optional); lengths in
    ``units`` ("mm", or "in": every length / 25.4)."""
    f = result.follower
    geometry = result.geometry
    paths = [_path("PROFILE", result.profile), _path("PITCH", result.pitch, prefer_arcs=False)]
    splines = []
    if result.profile.spline is not None:
        s = result.profile.spline
        splines.append(DxfSpline("PROFILE_SPLINE", s.control_points, s.knots, s.degree))
    if result.outer is not None:
        paths.append(_path("GROOVE_OUTER", result.outer))
    if result.counter is not None:
        paths.append(_path("COUNTER_PROFILE", result.counter))
        paths.append(_path("COUNTER_PITCH", cast(CurveResult, result.counter_pitch), prefer_arcs=False))
    extent = max(float(np.max(np.hypot(*p.points.T))) for p in paths)
    cross = max(5.0, 0.15 * f.base_radius)
    circles = [DxfCircle("BASE_CIRCLE", (0.0, 0.0), f.base_radius)]
    lines = [DxfLine("CENTER", (-cross, 0.0), (cross, 0.0)), DxfLine("CENTER", (0.0, -cross), (0.0, cross))]
    zero = np.array([0.0])
    centre = geometry.pitch(zero).centre[0]  # θ = 0: the cam and fixed frames coincide
    if f.kind == "flat":
        kin = geometry.kinematics(zero)
        height = f.base_radius + float(kin.s[0])
        left, right = cast(tuple[float, float], result.face_extent)  # a flat face has its extent
        margin = 0.1 * (right - left) + 2.0
        lines.append(DxfLine("ROLLER", (f.offset + left - margin, height), (f.offset + right + margin, height)))
        lines.append(DxfLine("ROLLER", (f.offset, height), (f.offset, height + 0.5 * f.base_radius)))
    else:
        if f.roller_radius > 0.0:
            circles.append(DxfCircle("ROLLER", (float(centre[0]), float(centre[1])), f.roller_radius))
        else:  # knife edge: draw the blade along its axis
            lines.append(DxfLine("ROLLER", (float(centre[0]), float(centre[1])),
                                 (float(centre[0]), float(centre[1]) + 0.3 * f.base_radius)))
        if f.kind == "oscillating":
            pivot, arm = cast(float, f.pivot), cast(float, f.arm)
            lines.append(DxfLine("ROLLER", (pivot, 0.0), (float(centre[0]), float(centre[1]))))
            circles.append(DxfCircle("ROLLER", (pivot, 0.0), max(1.0, 0.04 * arm)))
        if f.has_pair:
            second = geometry.pitch(zero, second=True).centre[0]
            if f.roller_radius > 0.0:
                circles.append(DxfCircle("ROLLER", (float(second[0]), float(second[1])), f.roller_radius))
            if f.kind == "oscillating":
                lines.append(DxfLine("ROLLER", (cast(float, f.pivot), 0.0), (float(second[0]), float(second[1]))))
    height = max(2.5, round(extent / 40.0, 1))
    top = -extent - 3.0 * height
    texts = [DxfText("TEXT", line, (-extent, top - 1.6 * height * k), height)
             for k, line in enumerate(drawing_texts(result, units))]
    drawing = Drawing(tuple(paths), tuple(splines), tuple(circles), tuple(lines), tuple(texts), LAYERS)
    return scaled_drawing(drawing, 1.0 / INCH_MM) if units == "in" else drawing


_NAN_FIELD = re.compile(r"(?<![^,\n])nan(?![^,\n])")


def law_csv_text(result: ProfileResult, units: str = "mm") -> str:
    """law.csv: θ, s, v, a, j, pressure angle (and its limit), radii of curvature; one row per step; lengths
    in ``units`` ("mm" or "in")."""
    t = result.table
    k = 1.0 / INCH_MM if units == "in" else 1.0
    swing = result.follower.kind == "oscillating"
    unit = "rad" if swing else units
    ks = 1.0 if swing else k
    header = ["theta_deg", f"s_{unit}", f"v_{unit}_per_rad", f"a_{unit}_per_rad2", f"j_{unit}_per_rad3",
              "pressure_angle_deg", "pressure_angle_limit_deg", f"rho_pitch_{units}", f"rho_profile_{units}"]
    columns = [np.degrees(t.theta), t.s * ks, t.v * ks, t.a * ks, t.j * ks, np.degrees(t.pressure_angle),
               np.degrees(t.limit), t.rho_pitch * k, t.rho_profile * k]
    # one %-format per row (a format per value took 23.5 ms for the default 721-row table, this 4.6 ms); NaN is written
    # as an empty field, infinities as inf and -inf
    row_format = ",".join(["%.15g"] * len(columns))
    rows = "\n".join(row_format % row for row in zip(*(c.tolist() for c in columns)))
    rows = _NAN_FIELD.sub("", rows)
    return ",".join(header) + "\n" + rows + ("\n" if rows else "")


def write_outputs(result: ProfileResult, out: OutputFolder | str | Path, settings: ProfileSettings | None = None,
                  extra: dict | None = None, *, sub: tuple[str, ...] = (), report_json: bool = True,
                  inputs: tuple[Path, ...] = (), plots: tuple[str, ...] | None = None,
                  units: str = "mm") -> list[Path]:
    """Write a synthesised cam's files: profile.dxf, law.csv, the plots and report.json.

    profile.dxf has the layers PROFILE, PITCH, BASE_CIRCLE, CENTER, ROLLER and TEXT (mm, DXF R2000 or
    R12); law.csv has one row per ``csv_step_deg`` with θ (deg), s, v, a, j (mm or rad of swing, per
    rad of cam angle), the pressure angle and its limit (deg) and the radii of curvature (mm). Every
    file is written atomically into an ``OutputFolder``, which never replaces an input.

    Parameters
    ----------
    result : ProfileResult
        The synthesised profile.
    out : OutputFolder or path
        Where to write (a path is opened as an ``OutputFolder`` guarding ``inputs``).
    settings : ProfileSettings, optional
        DXF flavour and plots; ``result.settings`` by default.
    extra : dict, optional
        Keys merged into report.json.
    sub : tuple of str
        A subfolder of ``out`` (a mechanism of a group scene).
    report_json : bool
        Write report.json (a scene writes one report for all its mechanisms instead).
    inputs : tuple of Path
        Files the run read: an output that would replace one of them is refused (when ``out`` is a path).
    plots : tuple of str, optional
        Names of ``camcad.report.profile.PLOTS`` to draw ("all" for every one); by default the summary
        page when ``settings.plots`` is true, none otherwise.
    units : str
        Length unit of profile.dxf and law.csv: "mm" (default) or "in" (every length / 25.4, $INSUNITS 1).

    Returns
    -------
    list of Path
        The written files (no unit; their contents are in mm and deg as above).

    Examples
    --------
    >>> import csv, tempfile, pathlib
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> result = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0),
    ...                            camcad.ProfileSettings(plots=False, design=False, csv_step_deg=1.0))
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> [path.name for path in camcad.write_outputs(result, folder)]
    ['profile.dxf', 'law.csv', 'report.json']
    >>> rows = list(csv.DictReader(open(folder / "law.csv")))
    >>> len(rows), rows[45]["theta_deg"], rows[45]["s_mm"]     # half the rise at half the rise angle
    (361, '45', '10')
    """
    if not isinstance(out, OutputFolder):
        with OutputFolder(out, inputs) as folder:
            return write_outputs(result, folder, settings, extra, sub=sub, report_json=report_json, plots=plots,
                                 units=units)
    settings = settings or result.settings
    if plots is None:
        plots = ("summary",) if settings.plots else ()
    written = [write_dxf(out.path(*sub, "profile.dxf"), build_drawing(result, units),
                         "R12" if settings.r12 else "R2000", units),
               write_text_atomic(out.path(*sub, "law.csv"), law_csv_text(result, units))]
    if plots:
        written.extend(save_profile_plots(result, out.path(*sub) if sub else out.folder, plots))
    if report_json:
        report_path = out.path(*sub, "report.json")
        written.append(report_path)
        payload = report(result)
        payload["outputs"] = [str(p) for p in written]
        if extra:
            payload.update(extra)
        write_json(report_path, payload)
    return written
