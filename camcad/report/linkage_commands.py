"""What ``camcad linkage …`` writes: one library run (``camcad.linkage.runners`` or
``camcad.scene.linkage_commands``) and its files in the output folder.

``linkage_command(request, output, plots)`` runs the request's ``run_linkage_*`` function, opens the
``OutputFolder`` (-o, else ``./camcad-out/<name>/``; the command's inputs can never be replaced), writes the
report's files (JSON, CSV, DXF, PNG) and returns a ``CommandRun``: the CLI prints ``run.text()`` or
``run.payload`` and exits with ``run.exit_code``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

from camcad.io.atomic import write_text_atomic
from camcad.io.jsonout import write_json
from camcad.linkage.runners import (
    AtlasRequest,
    FamilyReport,
    FamilyRequest,
    FgenReport,
    FgenRequest,
    LinkageAtlasReport,
    LinkageReport,
    PathReport,
    PathRequest,
    SixbarReport,
    VariatorReport,
    VariatorRequest,
    outputs_line,
    run_linkage_atlas,
    run_linkage_family,
    run_linkage_fgen,
    run_linkage_path,
    run_linkage_variator,
)
from camcad.report.animation import write_animation
from camcad.report.command import CommandRun, open_folder
from camcad.report.linkage import (
    analysis_csv,
    analysis_figure,
    diagram_figure,
    family_figure,
    kinematic_drawing,
    rows_csv,
    settings_figure,
    sixbar_error_figure,
    tune_figure,
    working_figure,
    write_atlas_outputs,
    write_fgen_outputs,
    write_linkage_outputs,
)
from camcad.report.linkage_path import path_files, variator_drawing, variator_figure
from camcad.scene.linkage_commands import (
    AdjustReport,
    AdjustRequest,
    AnalyseReport,
    AnalyseRequest,
    TuneReport,
    TuneRequest,
    run_linkage_adjust,
    run_linkage_analyse,
    run_linkage_tune,
)

#: the files each command may write (checked against the inputs before anything is written)
FGEN_FILES = ("fgen.json", "error.csv", "linkage.dxf", "error.png", "positions.png", "pivots.png")


def _lines(run: CommandRun) -> list[str]:
    return run.report.lines() + outputs_line(run.outputs)


def _run(request):
    """The request's runner."""
    runners = {AtlasRequest: run_linkage_atlas, FgenRequest: run_linkage_fgen, FamilyRequest: run_linkage_family,
               PathRequest: run_linkage_path, VariatorRequest: run_linkage_variator,
               AnalyseRequest: run_linkage_analyse, AdjustRequest: run_linkage_adjust,
               TuneRequest: run_linkage_tune}
    return runners[type(request)](request)


def linkage_command(request, output: Path | None = None, plots: bool = True) -> CommandRun:
    """Run one ``camcad linkage`` command and write its files.

    Parameters
    ----------
    request : AtlasRequest, FgenRequest, PathRequest, FamilyRequest, AnalyseRequest, AdjustRequest or TuneRequest
        What to compute (lengths mm, angles deg).
    output : Path or None
        The output folder; default ``./camcad-out/<name>/``.
    plots : bool
        Write the PNG plots.

    Returns
    -------
    CommandRun
        ``payload`` the JSON (with ``outputs``; lengths mm, angles deg), ``exit_code`` 0 or 1, ``text()`` the
        printed lines.

    Examples
    --------
    >>> import tempfile
    >>> from camcad.linkage.runners import AtlasRequest
    >>> run = linkage_command(AtlasRequest(4, 1), Path(tempfile.mkdtemp()), plots=False)
    >>> run.payload["count"], run.exit_code, sorted(Path(p).name for p in run.outputs)
    (1, 0, ['atlas.csv', 'atlas.dxf', 'atlas.json', 'schemes.dxf'])
    """
    report = _run(request)
    with open_folder(output, report.name, report.inputs) as out:
        written = write_report(report, out, plots)
    payload = report.to_dict()
    payload["outputs"] = [str(p) for p in written]
    return CommandRun(report, written, payload, _lines)


def write_report(report: LinkageReport, out, plots: bool) -> list[Path]:
    """Write a linkage report's files into the OutputFolder ``out``; the JSON is the last path."""
    if isinstance(report, LinkageAtlasReport):
        out.plan([(name,) for name in ("atlas.json", "atlas.csv", "atlas.dxf", "atlas.png", "schemes.dxf",
                                       "schemes.png")])
        return write_atlas_outputs(out.folder, report.atlas, plots)
    if isinstance(report, FgenReport):
        return _write_fgen(report, out, plots)
    # (texts, figures, drawing) of each report type
    writers: dict[type, Callable[[Any, bool], Any]] = {
        FamilyReport: _family_files, AnalyseReport: _analyse_files, AdjustReport: _adjust_files,
        TuneReport: _tune_files, PathReport: path_files, VariatorReport: _variator_files,
        SixbarReport: _sixbar_files}
    texts, figures, drawing = writers[type(report)](report, plots)
    out.plan([(name,) for name in [*texts, *figures, *animation_files(report), f"{report.command}.dxf",
                                   f"{report.command}.json"]])
    return write_linkage_outputs(out.folder, report.command, report.payload, texts, figures, drawing,
                                 _write_animation(report, out.folder))


def animation_files(report: LinkageReport) -> list[str]:
    """The animation files a report asks for (``--animate``): none when it has no frames to draw."""
    return [f"animation.{kind}" for kind in report.animate] if report.animation is not None else []


def _write_animation(report: LinkageReport, folder: Path) -> list[Path]:
    if report.animation is None:
        return []
    moves = (report.payload.get("animation") or {}).get("moves", "")
    files = write_animation(report.animation, folder, report.animate, title=report.animation.name, subtitle=moves)
    report.payload.setdefault("animation", {})["files"] = [p.name for p in files]
    return files


def _write_fgen(report: FgenReport, out, plots: bool) -> list[Path]:
    several = report.method == "all"
    prefixes = [f"{r.method}-" for r in report.results] if several else [""]
    out.plan([(prefix + name,) for prefix in prefixes for name in FGEN_FILES])
    written: list[Path] = []
    for result, payload, prefix in zip(report.results, report.payloads, prefixes):
        written += write_fgen_outputs(out.folder, result, payload, plots=plots, prefix=prefix)
    if not several:
        return written
    outputs = [write_text_atomic(out.path("compare.txt"), report.compare_text + "\n"), out.path("compare.json")]
    report.payload["outputs"] = [str(p) for p in outputs]
    write_json(out.path("compare.json"), report.payload)
    return outputs


def _sixbar_files(report: SixbarReport, plots: bool):
    result, p = report.result, report.payload
    assert result is not None  # a six-bar report carries its result
    t = result.target
    rows = [{"phi_deg": math.degrees(f), "x": float(t.x_of(f)), "psi_target_deg": math.degrees(float(t.psi(f))),
             "error_deg": math.degrees(e)} for f, e in zip(result.phi, result.error)]
    swing = abs(t.dphi)
    figures = {} if not plots else {
        "error.png": lambda: sixbar_error_figure(result, p),
        "diagram.png": lambda: diagram_figure(result.linkage, swing, title=(
            f"six-bar function generator for {t.label}"), ends=(f"x = {t.x0:g}", f"x = {t.x1:g}"))}
    drawing = kinematic_drawing(result.linkage, swing, title=(
        f"camcad linkage fgen --chain sixbar: {t.label} on [{t.x0:g}, {t.x1:g}]",
        f"max error {p['max_error_deg']:.4g} deg, mu min {p['mu_min_deg']:.2f} deg, Q {p['q']['value']:.3g}"))
    return {"error.csv": rows_csv(rows, "structural error of the six-bar over the input range")}, figures, drawing


def _family_files(report: FamilyReport, plots: bool):
    result, members = report.result, report.members
    assert result is not None  # a family report carries its result
    settings = [(f"x = {math.degrees(x):.3f} deg", result.mechanism(k)) for k, x in enumerate(result.settings)]
    arc = (result.centre, result.radius, list(result.settings))
    base = settings[0][1]
    figures = {} if not plots else {
        "family.png": lambda: family_figure(result, members),
        "diagram.png": lambda: diagram_figure(base, report.phi_end, settings, arc,
                                              "the family's mechanism at every setting")}
    drawing = kinematic_drawing(base, report.phi_end, settings, arc, title=(
        f"camcad linkage family: {len(members)} members, Q = {result.q:.3g}",
        (f"OA {result.crank:.4f}  AB {result.coupler:.4f}  CB {result.output_link:.4f} mm; arc F "
         f"({result.centre.real:.4f}, {result.centre.imag:.4f}) R {result.radius:.4f} mm")))
    return {"family.csv": rows_csv(report.payload["rows"])}, figures, drawing


def _analyse_files(report: AnalyseReport, plots: bool):
    command, result = report.command_linkage, report.analysis
    assert command is not None and result is not None  # an analyse report carries both
    texts = {"analysis.csv": analysis_csv(result)}
    figures = {} if not plots else {"analysis.png": lambda: analysis_figure(result, command.mu_min)}
    if report.working is not None:
        theta, kin, unit = report.working
        texts["working.csv"] = rows_csv([{"theta_deg": math.degrees(t), "y": s, "y_1": v, "y_2": a, "y_3": j}
                                         for t, s, v, a, j in zip(theta, kin.s, kin.v, kin.a, kin.j)],
                                        f"the working member y = Pi(psi(theta)) in {unit} and its derivatives per rad "
                                        "of cam angle")
        if plots:
            figures["working.png"] = lambda: working_figure(theta, kin, unit)
    if report.settings_rows:
        texts["settings.csv"] = rows_csv(report.settings_rows, "psi1, psi2: the working member at the follower's "
                                                               "extremes, from its nominal position at psi = 0 (deg)")
        if plots:
            figures["settings.png"] = lambda: settings_figure(report.settings_rows, f"setting ({report.setting_unit})",
                                                              report.element)
    if plots:
        figures["diagram.png"] = lambda: diagram_figure(command.linkage, command.psi_max, report.settings, report.arc,
                                                        f"{command.name}: the linkage in its extreme positions")
    profile = report.profile
    title = (f"camcad linkage analyse: {command.name}, {result.linkage.kind}",
             (f"swing {math.degrees(command.psi_max):.6g} deg, stroke {math.degrees(result.stroke):.6g} deg, "
              f"worst transmission angle {result.worst_mu_deg():.3f} deg"),
             "layers: LINKS psi = 0, EXTREME_POSITIONS psi max, SETTINGS, ADJUSTMENT arc" +
             (", cam PROFILE/PITCH/BASE_CIRCLE" if profile is not None else ""))
    drawing = kinematic_drawing(command.linkage, command.psi_max, report.settings, report.arc, profile,
                                None if profile is None else profile.follower, title)
    return texts, figures, drawing


def _adjust_files(report: AdjustReport, plots: bool):
    command = report.command_linkage
    assert command is not None  # an adjust report carries its linkage
    lk, psi_max = command.linkage, command.psi_max
    if report.table == 2:
        figures = {} if not plots else {
            "diagram.png": lambda: diagram_figure(lk, psi_max, report.settings, report.arc, report.drawing_note)}
        drawing = kinematic_drawing(lk, psi_max, report.settings, report.arc, title=(
            f"camcad linkage adjust: Table 2 task {report.task}", report.element, report.drawing_note))
        return {"adjust.csv": rows_csv(report.rows)}, figures, drawing
    figures = {} if not plots else {
        "adjust.png": lambda: settings_figure([{**r, "setting": r["setting_deg"]} for r in report.rows],
                                              "lock angle (deg)", f"Table 3 task {report.task}: {report.element}"),
        "diagram.png": lambda: diagram_figure(lk, psi_max, report.settings, report.arc,
                                              f"task {report.task}: every setting")}
    drawing = kinematic_drawing(lk, psi_max, report.settings, report.arc, title=(
        f"camcad linkage adjust: Table 3 task {report.task}", report.element, report.drawing_note))
    return {"adjust.csv": rows_csv(report.rows, "u: the regulating variable (task 1: the requested swing)")}, \
        figures, drawing


def _tune_files(report: TuneReport, plots: bool):
    command = report.command_linkage
    assert command is not None  # a tune report carries its linkage
    if report.result is None:     # the settings table
        return {"tune.csv": rows_csv(report.rows, report.table_comment)}, {}, None
    result = report.result
    figures = {} if not plots else {"tune.png": lambda: tune_figure(result, "rad" if report.unit == "deg" else "mm")}
    drawing = None
    if report.settings:
        p = report.payload
        drawing = kinematic_drawing(command.linkage, command.psi_max, report.settings, title=(
            f"camcad linkage tune: psi1 {p['psi1_deg']:g} deg, psi2 {p['psi2_deg']:g} deg", p["element"],
            "SETTINGS: the mechanism at every root, both extremes"))
    return {"tune.csv": rows_csv(report.rows)}, figures, drawing



def _variator_files(report: VariatorReport, plots: bool):
    result = report.result
    assert result is not None  # a variator report carries its result
    v = result.variator
    lines = ["# the output's velocity analog U = w k over the working interval at every setting (dimensionless)",
             "setting_deg,theta_deg,w,k,U"]
    for x in result.settings:
        theta, w, k, u = v.ratios(float(x))
        lines += [f"{math.degrees(math.remainder(float(x), 2 * math.pi)):.9g},{math.degrees(t):.9g},{a:.12g},"
                  f"{b:.12g},{c:.12g}" for t, a, b, c in zip(theta, w, k, u)]
    figures = {"variator.png": lambda: variator_figure(result)} if plots else {}
    return {"variator.csv": "\n".join(lines) + "\n"}, figures, variator_drawing(result)
