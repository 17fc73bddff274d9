"""`camcad profile`: synthesise a cam profile and write profile.dxf, law.csv, report.json, plots.

With no argument it runs the built-in default design (camcad/profile/defaults.py); with a
LAW (.dxf, .csv, .txt) it reads the drawn acceleration law; with a SCENE.toml it hands over
to the scene pipeline. Exit 1 when a design check fails (pressure angle over its limit,
undercut, curvature limit, profile not closed).
"""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from camcad.errors import CamcadError
from camcad.cli import app
from camcad.cli.common import JsonOpt, NoPlotsOpt

LAW_SUFFIXES = (".dxf", ".csv", ".txt")


def _standard_law(phases: str | None, lift: float | None, rise_law: str | None, return_law: str | None,
                  cycle_deg: float):
    """The built-in law (defaults.py), with any of its phases, lift and shapes replaced by the options."""
    import math

    from camcad.law.phases import parse_phases
    from camcad.law.standard import compose, shape_named
    from camcad.profile import defaults

    if phases:
        widths = [(p.kind, math.degrees(p.end - p.start)) for p in parse_phases(phases, cycle_deg)]
    elif abs(cycle_deg - 360.0) > 1e-9:
        raise CamcadError("--cycle needs --phases for the built-in law", "--cycle", "give --phases too")
    else:
        widths = list(defaults.DEFAULT_PHASES_DEG)
    lift = defaults.DEFAULT_LIFT_MM if lift is None else lift
    if not lift > 0.0:
        raise CamcadError(f"lift must be positive, got {lift:g} mm", "--lift", "give --lift in mm")
    shapes = []
    for option, name in (("--rise-law", rise_law or defaults.DEFAULT_RISE_SHAPE),
                         ("--return-law", return_law or defaults.DEFAULT_RETURN_SHAPE)):
        try:
            shapes.append(shape_named(name))
        except KeyError as err:
            raise CamcadError(str(err.args[0]), option, "pick one of the names listed") from None
    try:
        return compose(widths, lift, shapes[0], shapes[1], cycle_deg=cycle_deg)
    except ValueError as err:
        raise CamcadError(str(err), "--phases", "give as many returns as rises") from None


def _drawn_law(path: Path, layer, handle, cycle_deg, lift, phases):
    from camcad.law.source import load_law

    loaded = load_law(path, layer=layer, handle=handle, cycle_deg=cycle_deg, lift=lift, phases=phases)
    return loaded.law, list(loaded.notes), loaded.source


def _summary(payload: dict) -> None:
    def fmt(x, digits=4):
        return "-" if x is None else f"{x:.{digits}g}"

    pa = payload["pressure_angle"]
    lines = [
        f"camcad profile: {payload['name']}  ({payload['law']})",
        f"  follower       {payload['follower']['type']}, Rb {fmt(payload['follower']['base_radius_mm'])} mm",
        (f"  pressure angle max {fmt(payload['pressure_angle_max_deg'])} deg at "
         f"{fmt(payload['pressure_angle_max_at_deg'])} deg, min {fmt(payload['pressure_angle_min_deg'])} deg at "
         f"{fmt(payload['pressure_angle_min_at_deg'])} deg (limits rise {fmt(pa['limit_rise_deg'])}, "
         f"return {fmt(pa['limit_return_deg'])}): {'ok' if pa['passed'] else 'OVER THE LIMIT'}"),
        (f"  curvature      pitch min {fmt(payload['rho_pitch_min_mm'])} mm, profile min "
         f"{fmt(payload['rho_profile_min_mm'])} mm: {'ok' if payload['curvature']['passed'] else 'BELOW THE LIMIT'}"),
        f"  undercut       {'YES: ' + '; '.join(payload['undercut_reasons']) if payload['undercut'] else 'no'}",
        (f"  closed         {'yes' if payload['closed'] else 'NO'} (gap {payload['closure_gap_mm']:.3g} mm), "
         f"{payload['profile_points']} points ({payload['profile_representation']}), deviation "
         f"{payload['max_deviation_mm']:.3g} <= {payload['chord_tolerance_mm']:g} mm"),
    ]
    design = payload.get("design")
    if design and design.get("rb_min_mm") is not None:
        lines.append(f"  smallest Rb    {design['rb_min_mm']:.6g} mm (limited by {design['limited_by']})")
    for note in payload.get("notes", []):
        lines.append(f"  note           {note}")
    outputs = payload["outputs"]
    if outputs:
        folder = Path(outputs[0]).parent
        lines.append(f"  wrote          {folder}/: {', '.join(Path(p).name for p in outputs)}")
    lines.append("  verdict        " + ("all checks passed" if payload["passed"] else
                                         "FAILED: " + ", ".join(k for k, ok in payload["checks"].items() if not ok)))
    typer.echo("\n".join(lines))


@app.command()
def profile(
    target: Optional[Path] = typer.Argument(
        None, help="SCENE.toml, or a drawn law LAW.dxf / LAW.csv / LAW.txt; none: the built-in default design."),
    output: Optional[Path] = typer.Option(None, "-o", "--output", help="Output folder (default ./camcad-out/<name>/)."),
    rb: Optional[float] = typer.Option(None, "--rb", help="Base-circle radius Rb of the profile (mm)."),
    auto_rb: bool = typer.Option(False, "--auto-rb", help="Use the smallest Rb that meets the limits."),
    rr: Optional[float] = typer.Option(None, "--rr", help="Roller radius Rr (mm); 0 = knife edge."),
    offset: float = typer.Option(0.0, "--offset", help="Offset e of a translating follower's axis (mm)."),
    follower: str = typer.Option("roller", "--follower", help="roller, knife, flat or oscillating."),
    pivot: Optional[float] = typer.Option(None, "--pivot", help="Pivot distance C, oscillating follower (mm)."),
    arm: Optional[float] = typer.Option(None, "--arm", help="Arm length L, oscillating follower (mm)."),
    swing: Optional[float] = typer.Option(
        None, "--swing", help="Total swing of an oscillating follower (deg); without it the lift is the roller's arc."),
    lift: Optional[float] = typer.Option(None, "--lift", help="Scale the law so the rise is this many mm."),
    cycle: float = typer.Option(360.0, "--cycle", help="Cam angle the law spans (deg)."),
    phases: Optional[str] = typer.Option(None, "--phases", help='Phases, e.g. "0:120:rise,120:180:dwell,...".'),
    layer: Optional[str] = typer.Option(None, "--layer", help="DXF layer holding the law."),
    handle: Optional[str] = typer.Option(None, "--handle", help="DXF handle of the law's curve."),
    rise_law: Optional[str] = typer.Option(
        None, "--rise-law", help="Built-in law: rise shape (cycloidal, harmonic, poly345, poly4567, "
                                 "modified_trapezoid, modified_sine, constant_acceleration, scca:b:c:d)."),
    return_law: Optional[str] = typer.Option(None, "--return-law", help="Built-in law: return shape."),
    cw: bool = typer.Option(False, "--cw", help="The cam turns clockwise."),
    reversible: bool = typer.Option(False, "--reversible", help="The cam runs both ways."),
    pa_rise: Optional[float] = typer.Option(None, "--pa-rise", help="Pressure-angle limit on the rise (deg; 0 = none)."),
    pa_return: Optional[float] = typer.Option(
        None, "--pa-return", help="Pressure-angle limit on the return (deg; 0 = none)."),
    rho_min: Optional[float] = typer.Option(None, "--rho-min", help="Smallest convex radius of the profile (mm)."),
    groove: bool = typer.Option(False, "--groove", help="Also write the outer flank of a groove cam."),
    pair_distance: Optional[float] = typer.Option(
        None, "--pair-distance", help="Conjugate cam for a second roller this far below the first (mm)."),
    pair_angle: Optional[float] = typer.Option(
        None, "--pair-angle", help="Conjugate cam for a second arm at this angle (oscillating, deg)."),
    tol_mm: float = typer.Option(0.001, "--tol-mm", help="Chord tolerance of the written curves (mm)."),
    r12: bool = typer.Option(False, "--r12", help="Write DXF R12 instead of R2000."),
    spline: bool = typer.Option(False, "--spline", help="Also write a closed control-point SPLINE."),
    arcs: bool = typer.Option(False, "--arcs", help="Write the profile as lines and tangent arcs (for CNC)."),
    no_plots: NoPlotsOpt = False,
    as_json: JsonOpt = False,
) -> None:
    """Synthesise a cam profile; write profile.dxf, law.csv, report.json and plots. Exit 1 if a check fails."""
    from camcad.scene.pipeline import PipelineOptions
    from camcad.profile.followers import Follower
    from camcad.profile.summary import report
    from camcad.profile.synth import ProfileSettings, synthesize
    from camcad.profile import defaults
    from camcad.profile.design import min_base_radius
    from camcad.profile.scaled_law import swing_law
    from camcad.report.profile_files import write_outputs
    from camcad.cli.common import print_json

    notes: list[str] = []
    if target is not None and target.suffix.lower() == ".toml":
        _scene(target, PipelineOptions(output=output, tol_mm=tol_mm, arcs=arcs, spline=spline, r12=r12,
                                       plots=not no_plots), as_json)
        return

    if target is None:
        name = defaults.DEFAULT_NAME
        law = _standard_law(phases, lift, rise_law, return_law, cycle)
        default_rb, default_rr = defaults.DEFAULT_BASE_RADIUS_MM, defaults.DEFAULT_ROLLER_RADIUS_MM
    else:
        if not target.exists():
            raise CamcadError("file not found", str(target), "check the path")
        if target.suffix.lower() not in LAW_SUFFIXES:
            raise CamcadError(f"cannot tell what '{target.suffix}' holds", str(target),
                              "give a scene (.toml) or a law (.dxf, .csv, .txt)")
        if rise_law or return_law:
            raise CamcadError("--rise-law/--return-law choose the built-in law", str(target),
                              "drop them when you give a law file")
        name = target.stem
        law, law_notes, _ = _drawn_law(target, layer, handle, cycle, lift, phases)
        notes.extend(law_notes)
        default_rb, default_rr = None, None

    kind = follower.strip().lower()
    if kind not in ("roller", "knife", "flat", "oscillating"):
        raise CamcadError(f"follower type '{follower}' is unknown", "--follower", "use roller, knife, flat or oscillating")
    if kind in ("flat", "knife"):
        if rr not in (None, 0.0):
            raise CamcadError(f"a {kind} follower has no roller", "--rr", "drop --rr")
        rr = 0.0
    elif rr is None:
        if default_rr is None:
            raise CamcadError(f"the roller radius of the {kind} follower is not given", "--rr",
                              "give --rr in mm (0 for a knife edge)")
        rr = default_rr
    if rb is None and not auto_rb:
        if default_rb is None:
            raise CamcadError("the base-circle radius is not given", "--rb", "give --rb in mm, or --auto-rb")
        rb = default_rb
    if kind == "oscillating":
        if pivot is None or arm is None:
            raise CamcadError("an oscillating follower needs its pivot distance and arm length", "--follower",
                              "give --pivot C and --arm L in mm")
        law = swing_law(law, arm_mm=arm, swing_deg=swing)
        if swing is None:
            notes.append("oscillating follower: the lift is the arc of the roller centre, swing = lift / L")
    elif swing is not None:
        raise CamcadError("--swing is for an oscillating follower", "--swing", "drop it or use --follower oscillating")

    def limit(value: float | None, default: float) -> float | None:
        if value is None:
            return default
        return None if value == 0.0 else value

    spec = Follower(
        kind=kind, base_radius=rb if rb is not None else 1.0, roller_radius=rr, offset=offset,
        pivot=pivot, arm=arm, cw=cw,
        pressure_angle_limit_rise_deg=limit(pa_rise, defaults.PRESSURE_ANGLE_LIMIT_RISE_DEG),
        pressure_angle_limit_return_deg=limit(pa_return, defaults.PRESSURE_ANGLE_LIMIT_RETURN_DEG),
        reversible=reversible, groove=groove, pair_distance=pair_distance, pair_angle_deg=pair_angle,
        rho_min=rho_min)
    if auto_rb:
        if rb is not None:
            raise CamcadError("--rb and --auto-rb both choose the base radius", "--auto-rb", "give only one")
        design = min_base_radius(law, spec)
        if design.rb_min is None:
            raise CamcadError("no base radius meets the limits: " + "; ".join(design.notes), "--auto-rb",
                              "relax --pa-rise/--pa-return/--rho-min or change the follower")
        spec = spec.with_base_radius(design.rb_min)
        notes.append(f"base radius chosen by --auto-rb: {design.rb_min:.9g} mm ({design.limited_by})")
    spec.validate("follower options")

    settings = ProfileSettings(tol_mm=tol_mm, arcs=arcs, spline=spline, r12=r12, plots=not no_plots, name=name)
    result = synthesize(law, spec, settings, name=name)
    outdir = output if output is not None else Path("camcad-out") / name
    extra = {"notes": list(result.notes) + notes} if notes else None
    written = write_outputs(result, outdir, settings, extra=extra)
    payload = report(result)
    payload["outputs"] = [str(p) for p in written]
    if extra:
        payload.update(extra)
    if as_json:
        print_json(payload)
    else:
        _summary(payload)
    if not result.passed:
        raise typer.Exit(1)


def _scene(path: Path, options, as_json: bool) -> None:
    """The scene pipeline with a progress line on stderr; exit 1 when any check of any model fails."""
    from camcad.report.scene import run_scene
    from camcad.cli.common import console, print_json

    if as_json:
        result = run_scene(path, options)
        print_json(result.report)
    else:
        with console(stderr=True).status("scene") as status:
            result = run_scene(path, options, progress=lambda text: status.update(f"camcad: {text}"))
        _scene_summary(result.report)
    if not result.passed:
        raise typer.Exit(1)


def _scene_summary(report: dict) -> None:
    from rich.markup import escape
    from rich.table import Table

    from camcad.cli.common import console

    out = console()
    out.print(escape(f"{report['name']} ({report['scene']})" + (f": {report['description']}"
                                                                 if report.get("description") else "")))
    mechanisms = report.get("mechanisms") or {report["name"]: report}
    table = Table(title="models run per mechanism")
    for column in ("mechanism", "ran", "pressure angle max/min deg", "rho min mm", "checks"):
        table.add_column(column)
    for name, mech in mechanisms.items():
        pa = (f"{mech['pressure_angle_max_deg']:.2f} / {mech['pressure_angle_min_deg']:.2f}"
              if mech.get("pressure_angle_max_deg") is not None else "-")
        rho = f"{mech['rho_profile_min_mm']:.3f}" if mech.get("rho_profile_min_mm") is not None else "-"
        checks = ", ".join(f"{k} {'ok' if ok else 'FAILED'}" for k, ok in mech["checks_by_model"].items())
        table.add_row(escape(name), ", ".join(mech["models_run"]), pa, rho, checks)
    out.print(table)
    for name, mech in mechanisms.items():
        for key, why in mech["skipped"].items():
            out.print(escape(f"  {name}: {key} skipped ({why})"))
        limits = mech.get("phase_limits") or {}
        for label, sources in limits.items():
            parts = ", ".join(f"{k} {v:.3f}" for k, v in sources.items() if k != "least_deg" and v is not None)
            if sources.get("least_deg") is not None:
                out.print(escape(f"  {name}: least {label} angle {sources['least_deg']:.3f} deg ({parts})"))
    if "cyclogram" in report:
        cyc = report["cyclogram"]
        if cyc["feasible"]:
            out.print(f"cyclogram: makespan {cyc['makespan_deg']:.3f} deg, critical path "
                      f"{' -> '.join(cyc['critical_path'])}, active bounds {', '.join(cyc['active_bounds'])}")
            for name, text in cyc.get("phases", {}).items():
                out.print(escape(f"  {name}: phases {text}"))
        else:
            out.print(escape(f"cyclogram infeasible: {cyc.get('explanation', '')}"))
    elif report.get("mechanisms") and "cyclogram" in report.get("skipped", {}):
        out.print(escape(f"  cyclogram skipped ({report['skipped']['cyclogram']})"))
    out.print(escape(f"wrote {len(report['outputs'])} files; report: {report['outputs'][-1]}"))
    out.print("all checks passed" if report["passed"] else "FAILED: a check did not pass (see report.json)")
