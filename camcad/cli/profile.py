"""`camcad profile`: synthesise a cam profile; write profile.dxf, law.csv, report.json and plots.

With no argument it runs the built-in default design (camcad/profile/defaults.py); with a LAW (.dxf,
.csv, .txt) it reads the drawn acceleration law; with a SCENE.toml it runs the scene. The options of a
law or of the default design are turned into the scene they describe (``_scene_tables``: [law] and
[follower]), so every run goes through the one pipeline and its report means the same everywhere.
Exit 1 when a check fails (pressure angle over its limit, undercut, curvature limit, profile not
closed, or any model of the scene).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import typer

from camcad.cli import app
from camcad.cli.common import (
    JsonOpt,
    NoPlotsOpt,
    OriginOpt,
    X0Opt,
    XDegOpt,
    Y0Opt,
    echo,
    option_given,
    parse_origin,
    print_json,
    progress_line,
)
from camcad.cli.part_options import (
    BoreOpt,
    CompOpt,
    CutterRadiusOpt,
    DepthOpt,
    ExportOpt,
    FeedOpt,
    KeywayOpt,
    PlateOpt,
    PolydyneOpt,
    ServoFormatOpt,
    ServoNormaliseOpt,
    ServoRpmOpt,
    ServoStepOpt,
    StepDegOpt,
    ThicknessOpt,
    UnitsOpt,
    export_options,
)
from camcad.cli.report_options import (
    AnimateFormatOpt,
    AnimateOpt,
    AnimateStepOpt,
    ReportOpt,
    ReportPdfOpt,
    handover_options,
)
from camcad.errors import CamcadError
from camcad.profile import defaults

if TYPE_CHECKING:
    from camcad.scene.file import Scene

LAW_SUFFIXES = (".dxf", ".csv", ".txt", ".tsv", ".dat", ".tab")
FOLLOWER_KINDS = ("roller", "knife", "flat", "oscillating")


@app.command()
def profile(
    target: Path | None = typer.Argument(
        None, help="SCENE.toml, or a drawn law LAW.dxf / LAW.csv / LAW.txt; none: the built-in default design.",
        show_default=False),
    output: Path | None = typer.Option(None, "-o", "--output", help="Output folder (default ./camcad-out/<name>/)."),
    rb: float | None = typer.Option(None, "--rb", help="Base-circle radius Rb of the profile (mm)."),
    auto_rb: bool = typer.Option(False, "--auto-rb", help="Use the smallest Rb that meets the limits."),
    rr: float | None = typer.Option(None, "--rr", help="Roller radius Rr (mm); 0 = knife edge."),
    offset: float = typer.Option(0.0, "--offset", help="Offset e of a translating follower's axis (mm)."),
    follower: str = typer.Option("roller", "--follower", help="roller, knife, flat or oscillating."),
    pivot: float | None = typer.Option(None, "--pivot", help="Pivot distance C, oscillating follower (mm)."),
    arm: float | None = typer.Option(None, "--arm", help="Arm length L, oscillating follower (mm)."),
    swing: float | None = typer.Option(
        None, "--swing", help="Total swing of an oscillating follower (deg); without it the lift is the roller's arc."),
    lift: float | None = typer.Option(None, "--lift", help="Scale the law so the rise is this many mm."),
    cycle: float = typer.Option(360.0, "--cycle", help="Cam angle the law spans (deg)."),
    phases: str | None = typer.Option(None, "--phases", help='Phases, e.g. "0:120:rise,120:180:dwell,...".'),
    layer: str | None = typer.Option(None, "--layer", help="DXF layer holding the law."),
    handle: str | None = typer.Option(None, "--handle", help="DXF handle of the law's curve."),
    y0: Y0Opt = None,
    x0: X0Opt = None,
    origin: OriginOpt = None,
    x_deg: XDegOpt = False,
    rise_law: str | None = typer.Option(
        None, "--rise-law", help="Built-in law: rise shape (cycloidal, harmonic, poly345, poly4567, poly56789, "
                                 "modified_trapezoid, modified_sine, constant_acceleration, scca:b:c:d; the VDI 2143 "
                                 "inclined_sine, poly5, poly7, modified_sine:lambda, ...)."),
    segments: str | None = typer.Option(
        None, "--segments", help='The law as segments "start:end:shape[:to_mm][:v_end=..],..." (docs/laws.md).'),
    return_law: str | None = typer.Option(None, "--return-law", help="Built-in law: return shape."),
    cw: bool = typer.Option(False, "--cw", help="The cam turns clockwise."),
    reversible: bool = typer.Option(False, "--reversible", help="The cam runs both ways."),
    pa_rise: float | None = typer.Option(None, "--pa-rise", help="Pressure-angle limit on the rise (deg; 0 = none)."),
    pa_return: float | None = typer.Option(
        None, "--pa-return", help="Pressure-angle limit on the return (deg; 0 = none)."),
    rho_min: float | None = typer.Option(None, "--rho-min", help="Smallest convex radius of the profile (mm)."),
    groove: bool = typer.Option(False, "--groove", help="Also write the outer flank of a groove cam."),
    pair_distance: float | None = typer.Option(
        None, "--pair-distance", help="Conjugate cam for a second roller this far below the first (mm)."),
    pair_angle: float | None = typer.Option(
        None, "--pair-angle", help="Conjugate cam for a second arm at this angle (oscillating, deg)."),
    tol_mm: float = typer.Option(0.001, "--tol-mm", help="Chord tolerance of the written curves (mm)."),
    r12: bool = typer.Option(False, "--r12", help="Write DXF R12 instead of R2000."),
    spline: bool = typer.Option(False, "--spline", help="Also write a closed control-point SPLINE."),
    arcs: bool = typer.Option(False, "--arcs", help="Write the profile as lines and tangent arcs (for CNC)."),
    plots: str | None = typer.Option(
        None, "--plots", help="Plots to draw: summary (the default: one page per mechanism), all, or a list of "
                              "summary, kinematics, pressure_angle, curvature, profile, hodograph, dynamics, impact, "
                              "contact."),
    no_plots: NoPlotsOpt = False,
    export: ExportOpt = None, units: UnitsOpt = None, step_deg: StepDegOpt = None,
    cutter_radius: CutterRadiusOpt = None,
    comp: CompOpt = None, feed: FeedOpt = None, depth: DepthOpt = None, thickness: ThicknessOpt = None,
    bore: BoreOpt = None, keyway: KeywayOpt = None, plate: PlateOpt = None,
    servo_step: ServoStepOpt = 1.0, servo_format: ServoFormatOpt = "csv", servo_rpm: ServoRpmOpt = None,
    servo_normalise: ServoNormaliseOpt = False, polydyne: PolydyneOpt = None,
    animate: AnimateOpt = False, animate_format: AnimateFormatOpt = None, animate_step: AnimateStepOpt = None,
    report: ReportOpt = False, report_pdf: ReportPdfOpt = False,
    as_json: JsonOpt = False,
) -> None:
    """Synthesise a cam profile; write profile.dxf, law.csv, report.json and plots. Exit 1 if a check fails."""
    from camcad.profile.servo import servo_export
    from camcad.report.scene import run_scene
    from camcad.scene.file import scene_from_dict
    from camcad.scene.pipeline import PipelineOptions

    part = export_options(export=export, units=units, step_deg=step_deg, cutter_radius=cutter_radius, comp=comp,
                          feed=feed, depth=depth, thickness=thickness, bore=bore, keyway=keyway, plate=plate)
    options = PipelineOptions(output=output, tol_mm=tol_mm, arcs=arcs, spline=spline, r12=r12,
                              plots=_plot_names(plots, no_plots), export=part,
                              servo=servo_export(export, servo_step, servo_format, servo_normalise, servo_rpm),
                              polydyne_rpm=polydyne,
                              **handover_options(animate=animate, animate_format=animate_format,
                                                 animate_step=animate_step, report=report, report_pdf=report_pdf))
    if target is not None and target.suffix.lower() == ".toml":
        given = [name for name, value in (("--rb", rb), ("--rr", rr), ("--lift", lift), ("--phases", phases),
                                          ("--layer", layer), ("--handle", handle), ("--rise-law", rise_law),
                                          ("--segments", segments))
                 if value is not None]
        if given:
            raise CamcadError(f"{', '.join(given)} describe a law or a follower; a scene holds its own", str(target),
                              "change the scene's [law] and [follower] sections instead")
        source: Path | Scene = target
    else:
        _name, tables = _scene_tables(target, rb=rb, auto_rb=auto_rb, rr=rr, offset=offset, kind=follower,
                                     pivot=pivot, arm=arm, swing=swing, lift=lift, cycle=cycle, phases=phases,
                                     layer=layer, handle=handle, y0=y0, x0=x0, origin=origin, x_deg=x_deg,
                                     rise_law=rise_law, return_law=return_law, segments=segments, cw=cw,
                                     reversible=reversible, pa_rise=pa_rise, pa_return=pa_return, rho_min=rho_min,
                                     groove=groove, pair_distance=pair_distance, pair_angle=pair_angle)
        source = scene_from_dict(tables, Path("command line"), from_file=False)
    if as_json:
        result = run_scene(source, options)
        print_json(result.report)
    else:
        with progress_line() as say:
            result = run_scene(source, options, progress=lambda text: say(f"camcad: {text}"))
        _print_report(result.report)
    if not result.passed:
        raise typer.Exit(1)


PLOT_NAMES = ("summary", "kinematics", "pressure_angle", "curvature", "profile", "hodograph", "dynamics", "impact",
              "contact", "all")


def _plot_names(plots: str | None, no_plots: bool) -> tuple[str, ...]:
    if no_plots:
        if plots is not None:
            raise CamcadError("--plots and --no-plots contradict each other", "--plots", "give only one")
        return ()
    if plots is None:
        return ("summary",)
    names = tuple(name.strip() for name in plots.split(",") if name.strip())
    for name in names:
        if name not in PLOT_NAMES:
            from camcad.errors import nearest_name

            raise CamcadError(f"unknown plot {name!r}", "--plots",
                              nearest_name(name, list(PLOT_NAMES)).replace("valid keys", "plots"))
    return names


def _scene_tables(target: Path | None, *, rb, auto_rb, rr, offset, kind, pivot, arm, swing, lift, cycle, phases,
                  layer, handle, y0, x0, origin, x_deg, rise_law, return_law, cw, reversible, pa_rise, pa_return,
                  segments=None,
                  rho_min, groove, pair_distance, pair_angle) -> tuple[str, dict]:
    """The scene (TOML tables) the options describe: its name and {name, law, follower}."""
    kind = kind.strip().lower()
    if kind not in FOLLOWER_KINDS:
        raise CamcadError(f"follower type {kind!r} is unknown", "--follower", "use roller, knife, flat or oscillating")
    if target is None:
        for option, value in (("--y0", y0), ("--x0", x0), ("--origin", origin), ("--layer", layer),
                              ("--handle", handle)):
            if value is not None:
                raise CamcadError(f"{option} locates a law in a drawing; the built-in law has none", option,
                                  "give a law file, or drop the option")
        name = defaults.DEFAULT_NAME
        if abs(cycle - 360.0) > 1e-9 and phases is None and segments is None:
            raise CamcadError("--cycle needs --phases for the built-in law", "--cycle", "give --phases too")
        from camcad.scene.default import default_tables

        law = default_tables()["law"]
        law.update({"cycle": cycle, **{key: value for key, value in (
            ("standard", rise_law), ("return_standard", return_law), ("phases", phases), ("lift", lift))
            if value is not None}})
        if segments is not None:
            from camcad.law.segments import parse_segments, spec_tables

            given = [o for o, v in (("--rise-law", rise_law), ("--return-law", return_law), ("--phases", phases),
                                    ("--lift", lift)) if v is not None]
            if given:
                raise CamcadError(f"--segments give the whole law; {', '.join(given)} describe a standard one",
                                  "--segments", "give one or the other")
            law = {"cycle": cycle, "segments": spec_tables(parse_segments(segments))}
        if rb is None and not auto_rb:
            rb = defaults.DEFAULT_BASE_RADIUS_MM
        if rr is None and kind in ("roller", "oscillating"):
            rr = defaults.DEFAULT_ROLLER_RADIUS_MM
    else:
        if not target.exists():
            raise CamcadError("file not found", str(target), "check the path")
        if target.is_dir():
            raise CamcadError("is a folder, not a law or a scene", str(target), "give a .dxf, .csv, .txt or .toml file")
        if target.suffix.lower() not in LAW_SUFFIXES:
            raise CamcadError(f"cannot tell what '{target.suffix}' holds", str(target),
                              "give a scene (.toml) or a law (.dxf, .csv, .txt)")
        if rise_law or return_law or segments:
            raise CamcadError("--rise-law/--return-law/--segments give the built-in law", str(target),
                              "drop them when you give a law file")
        name = target.stem
        if origin is not None:
            x0, y0 = parse_origin(origin, x0, y0)
        law = {"file": str(target.resolve())}
        if cycle != 360.0 or option_given("cycle"):   # a cycle not stated is found from the drawing
            law["cycle"] = cycle
        law.update({k: v for k, v in (("lift", lift), ("phases", phases), ("layer", layer), ("handle", handle),
                                      ("y0", y0), ("x0", x0)) if v is not None})
        if x_deg:
            law["x_deg"] = True
        missing = []
        if rb is None and not auto_rb:
            missing.append("--rb (base radius, mm; or --auto-rb)")
        if rr is None and kind in ("roller", "oscillating"):
            missing.append("--rr (roller radius, mm; 0 for a knife edge)")
        if kind == "oscillating":
            missing += [f"{opt} ({what}, mm)" for opt, what, value in (("--pivot", "pivot distance", pivot),
                                                                      ("--arm", "arm length", arm)) if value is None]
        if missing:
            raise CamcadError(f"the follower is not fully given: missing {', '.join(missing)}", str(target),
                              "give them, e.g. --rb 50 --rr 10")
    if rb is not None and auto_rb:
        raise CamcadError("--rb and --auto-rb both choose the base radius", "--auto-rb", "give only one")
    if kind in ("flat", "knife") and rr not in (None, 0.0):
        raise CamcadError(f"a {kind} follower has no roller", "--rr", "drop --rr")
    if kind == "roller" and rr == 0.0:
        kind = "knife"
    if swing is not None and kind != "oscillating":
        raise CamcadError("--swing is for an oscillating follower", "--swing", "drop it or use --follower oscillating")
    follower: dict = {"type": kind, "offset": offset, "cw": cw, "reversible": reversible, "groove": groove,
                      "pressure_angle_limit_rise": (defaults.PRESSURE_ANGLE_LIMIT_RISE_DEG if pa_rise is None
                                                    else pa_rise),
                      "pressure_angle_limit_return": (defaults.PRESSURE_ANGLE_LIMIT_RETURN_DEG if pa_return is None
                                                      else pa_return)}
    for key, value in (("base_radius", rb), ("roller_radius", rr if kind in ("roller", "oscillating") else None),
                       ("pivot", pivot), ("arm", arm), ("swing", swing), ("rho_min", rho_min),
                       ("pair_distance", pair_distance), ("pair_angle", pair_angle)):
        if value is not None:
            follower[key] = value
    if auto_rb:
        follower["auto_base_radius"] = True
    if kind != "oscillating":
        for option, value in (("--pivot", pivot), ("--arm", arm), ("--pair-angle", pair_angle)):
            if value is not None:
                raise CamcadError(f"{option} is for an oscillating follower", option,
                                  "drop it or use --follower oscillating")
    return name, {"name": name, "law": law, "follower": follower}


# ------------------------------------------------------------------------------------------------
# printing
# ------------------------------------------------------------------------------------------------

def _fmt(x, digits: int = 4) -> str:
    if x is None:
        return "-"
    if isinstance(x, float) and not math.isfinite(x):
        return str(x)
    return f"{x:.{digits}g}"


class _Plain:
    """print() with rich's ``print`` name, so the report printers stay readable."""

    @staticmethod
    def print(text: str = "") -> None:
        echo(text)


def _print_report(report: dict) -> None:
    out = _Plain()
    title = f"{report['name']}" + (f" ({report['scene']})" if report.get("scene") not in (None, "command line") else "")
    if report.get("description"):
        title += f": {report['description']}"
    out.print(title)
    mechanisms = report.get("mechanisms")
    if mechanisms:
        warnings = _print_group(out, report)
    else:
        warnings = _print_mechanism(out, report, "  ", show_skipped=report.get("scene") != "command line")
    if report.get("outputs"):
        folder = Path(report["outputs"][-1]).parent
        out.print(f"wrote {len(report['outputs'])} files into {folder}/")
    plural = "s" if warnings > 1 else ""
    noted = f"; {warnings} warning{plural} (WARN above) to weigh before signing" if warnings else ""
    out.print(("verdict: all checks passed" if report["passed"] else "verdict: FAILED (see the checks above)") + noted)


def _print_mechanism(out, mech: dict, indent: str, show_skipped: bool = True) -> int:
    """Print one mechanism's lines; return how many WARN lines were printed."""
    follower = mech.get("follower") or {}
    law = mech.get("law") or {}
    if isinstance(law, dict):
        for k, note in enumerate(law.get("notes", [])):
            label = "warning" if note.startswith("warning: ") else ("law" if k == 0 else "")
            text = note.removeprefix("warning: ").removeprefix("law: ")
            out.print(f"{indent}{label:<10} {text}")
    if follower:
        out.print(f"{indent}follower   {follower.get('type')}, Rb {_fmt(follower.get('base_radius_mm'))} mm"
                  + (f", Rr {_fmt(follower.get('roller_radius_mm'))} mm" if follower.get("roller_radius_mm") else ""))
    if mech.get("phase_angles"):
        out.print(f"{indent}phases     {mech.get('phases', '')} ({mech['phase_angles']})")
    if mech.get("retimed_by_cyclogram"):
        out.print(f"{indent}retimed    by the cyclogram: {mech['retimed_by_cyclogram']}")
    if "profile_points" in mech:
        out.print(f"{indent}profile    {mech['profile_points']} points ({mech['profile_representation']}), "
                  f"deviation {_fmt(mech['max_deviation_mm'], 3)} <= {mech['chord_tolerance_mm']:g} mm")
    part = mech.get("export") or {}
    if part.get("files"):
        out.print(f"{indent}part       {', '.join(part['files'])} (lengths in {part['units']})")
        for name, figures in (part.get("programs") or {}).items():
            out.print(f"{indent}           {name}: {figures['arcs']} arcs, {figures['lines']} lines within "
                      f"{figures['tolerance_mm']:g} mm of the exact path, start at {figures['start_deg']:.6g} deg")
        for name, figures in (part.get("solids") or {}).items():
            out.print(f"{indent}           {name}: volume {figures['volume_mm3']:.6g} mm3")
        for note in part.get("notes", [])[1:]:
            out.print(f"{indent}note       {note}")
    design = mech.get("design") or {}
    if design.get("rb_min_mm") is not None:
        out.print(f"{indent}smallest Rb {_up(design['rb_min_mm'], 6, significant=True)} mm (limited by "
                  f"{design['limited_by']})")
    from camcad.report.verdict_text import verdict_lines

    lines = verdict_lines(mech)
    if lines:
        out.print(f"{indent}checks, tightest margin first:")
    for status, text in lines:
        out.print(f"{indent}  {dict(ok='ok  ', fail='FAIL', warn='WARN')[status]} {text}")
    for label, sources in (mech.get("phase_limits") or {}).items():
        least = sources.get("least_deg")
        if least is None:
            continue
        # what binds (report.json's phase_limits has every source's angle)
        # rounded up, so that the printed angle, given back as a phase angle, still passes (report.json: exact)
        binding = ", ".join(f"{k} {_up(v)} deg" for k, v in sources.items() if k != "least_deg" and v == least)
        out.print(f"{indent}least {label} angle {_up(least)} deg (bound by {binding})")
    for note in mech.get("phase_limit_notes") or []:
        out.print(f"{indent}note       {note}")
    for key, why in (mech.get("skipped") or {}).items() if show_skipped else ():
        out.print(f"{indent}skipped    {key}: {why}")
    for note in mech.get("notes", []):
        out.print(f"{indent}note       {note}")
    return sum(status == "warn" for status, _ in lines)


def _print_group(out, report: dict) -> int:
    """Print every mechanism and the cyclogram; return how many WARN lines were printed."""
    warnings = 0
    for name, mech in report["mechanisms"].items():
        out.print(f"{name}:")
        warnings += _print_mechanism(out, mech, "  ")
    cyclogram = report.get("cyclogram")
    if cyclogram:
        if cyclogram.get("feasible"):
            out.print(f"cyclogram: makespan {cyclogram['makespan_deg']:.4f} deg, critical path "
                      f"{' -> '.join(cyclogram['critical_path'])}, "
                      f"active bounds {', '.join(cyclogram['active_bounds'])}")
            for name, text in cyclogram.get("phases", {}).items():
                out.print(f"  {name}: phases {text}")
        else:
            out.print(f"cyclogram infeasible: {cyclogram.get('explanation', '')}")
    elif "cyclogram" in report.get("skipped", {}):
        out.print(f"cyclogram skipped ({report['skipped']['cyclogram']})")
    return warnings


def _up(value: float, digits: int = 4, significant: bool = False) -> str:
    """``value`` printed with ``digits`` decimals (or significant digits), rounded up: a least angle or smallest
    radius read off the screen and given back must not fall below the exact one."""
    import math

    if not math.isfinite(value) or value == 0.0:
        return f"{value:.{digits}f}" if not significant else f"{value:.{digits}g}"
    decimals = digits if not significant else digits - 1 - math.floor(math.log10(abs(value)))
    step = 10.0 ** -decimals
    shown = math.ceil(value / step - 1e-9) * step
    return f"{shown:.{max(decimals, 0)}f}" if not significant else f"{shown:.{digits}g}"
