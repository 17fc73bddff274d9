"""`camcad linkage`: structural atlas of (adjustable) chains and four-bar function-generator synthesis
(seed 002, Sunkuev 1984, chapters 1–2)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, cast

import numpy as np
import typer

from camcad.cli import app
from camcad.cli.common import JsonOpt, NoPlotsOpt, OutOpt, output_dir, print_json
from camcad.errors import CamcadError

linkage_app = typer.Typer(no_args_is_help=True, help="Linkages after the cam (Sunkuev 1984): atlas of adjustable "
                                                    "chains, function-generator synthesis (Q method).")
app.add_typer(linkage_app, name="linkage")


def _atlas_summary(payload: dict, seconds: float) -> None:
    lines = []
    if payload["kind"] == "adjustable":
        lines.append(f"camcad linkage atlas: adjustable chains n'={payload['links']}, W'={payload['dof']}, "
                     f"m={payload['adjustable']} (from {payload['base_chains']} ordinary chains with "
                     f"n={payload['base_links']}, W={payload['base_dof']}; {payload['colourings']} colourings)")
    else:
        lines.append(f"camcad linkage atlas: ordinary chains n={payload['links']}, W={payload['dof']}, "
                     f"p={payload['pairs']} pairs")
    lines.append(f"  count          {payload['count']}  (enumerated in {seconds:.2f} s)")
    if "published_count" in payload:
        same = "matches" if payload["published_count"] == payload["count"] else "DIFFERS from"
        lines.append(f"  published      {payload['published_count']} ({same} the count)")
    if "seed_count" in payload:
        same = "reproduced" if payload["seed_count"] == payload["count"] else "NOT reproduced"
        lines.append(f"  Sunkuev Table 1 {payload['seed_count']} ({same})")
    if payload.get("counts"):
        c = payload["counts"]
        lines.append(f"  weaker rules   no condition {c['unconditional']}, contracted chain simple "
                     f"{c['contracted_simple']}, rule {c['rule']}")
    if payload.get("by_assortment"):
        lines.append("  by assortment  " + ", ".join(f"{k}: {v}" for k, v in payload["by_assortment"].items()))
    if payload.get("discrepancy"):
        lines.append(f"  discrepancy    {payload['discrepancy']}")
    lines.append(f"  rule           {payload['rule']}")
    outputs = payload.get("outputs", [])
    if outputs:
        lines.append(f"  wrote          {Path(outputs[0]).parent}/: {', '.join(Path(p).name for p in outputs)}")
    typer.echo("\n".join(lines))


@linkage_app.command()
def atlas(
    links: Annotated[int, typer.Option("--links", help="Number of links n (frame counted); with --adjustable, n'.")],
    dof: Annotated[int, typer.Option("--dof", help="Mobility W; with --adjustable, W' of the adjustable chain.")] = 1,
    adjustable: Annotated[int | None, typer.Option(
        "--adjustable", help="m locked pairs: enumerate adjustable chains (Sunkuev 1984, Table 1).")] = None,
    output: OutOpt = None,
    no_plots: NoPlotsOpt = False,
    as_json: JsonOpt = False,
) -> None:
    """Enumerate planar chains with revolute pairs (or adjustable chains) up to isomorphism; draw the atlas."""
    from camcad.linkage.atlas import atlas as build_atlas
    from camcad.report.linkage import write_atlas_outputs

    report = build_atlas(links, dof, adjustable)
    name = f"atlas-n{links}-w{dof}" + (f"-m{adjustable}" if adjustable else "")
    write_atlas_outputs(output_dir(output, name), report, plots=not no_plots)
    if as_json:
        print_json(report.payload)
    else:
        _atlas_summary(report.payload, report.seconds)


def _fgen_table(reports: list[dict]) -> str:
    head = (f"{'method':<10} {'max error':>11} {'RMS error':>11} {'mu min':>8} {'positions':>10}  "
            f"{'a (OA)':>9} {'b (AB)':>9} {'c (CB)':>9} {'d (OC)':>9}  checks")
    rows = [head, "-" * len(head)]
    for r in reports:
        links = r["links"]
        failed = [k for k, c in r["checks"].items() if not c["passed"]]
        rows.append(f"{r['method']:<10} {r['max_error_deg']:>9.4g}° {r['rms_error_deg']:>9.4g}° "
                    f"{r['mu_min_deg']:>7.2f}° {r['position_evaluations']:>10d}  "
                    f"{links['a']:>9.3f} {links['b']:>9.3f} {links['c']:>9.3f} {links['d']:>9.3f}  "
                    + ("ok" if not failed else "FAILED: " + ", ".join(failed)))
    return "\n".join(rows)


def _fgen_summary(payload: dict) -> None:
    head = (f"camcad linkage fgen: {payload['function']} on [{payload['x'][0]:g}, {payload['x'][1]:g}], input "
            f"{payload['input_range_deg']:g} deg, output {payload['output_range_deg']:g} deg, method "
            f"{payload['method']}")
    lines = [head, _fgen_table([payload])]
    lines.append(f"  offsets        phi0 {payload['offsets_deg']['phi0']:.4f} deg, psi0 "
                 f"{payload['offsets_deg']['psi0']:.4f} deg, branch {payload['branch']:+d}, "
                 f"{payload['grashof']['class']}")
    lines.append("  nodes (deg)    " + ", ".join(f"{v:.4f}" for v in payload["nodes_deg"][:12])
                 + (" ..." if len(payload["nodes_deg"]) > 12 else ""))
    lines.append("  positions      " + ", ".join(f"{k} {v}" for k, v in payload["position_breakdown"].items())
                 + f" (+ {payload['verification_positions']} to check the result)")
    if "q" in payload:
        q = payload["q"]
        lines.append(f"  Q              {q['value']:.4e} {q['unit']}; subsets {q['subsets']}; pivot: {q['pick']}")
    if "minimax" in payload:
        m = payload["minimax"]
        lines.append(f"  equal ripple   level {m['level_deg']:.5g} deg at {len(m['references_deg'])} points, spread "
                     f"{100 * m['ripple_spread']:.3g} % ({m['message']})")
    for name, c in payload["checks"].items():
        lines.append(f"  check {name:<15} value {c['value']:.5g}, limit {c['limit']:.5g}, margin {c['margin']:+.4g}: "
                     + ("ok" if c["passed"] else "FAILED"))
    for note in payload.get("notes", []):
        lines.append(f"  note           {note}")
    outputs = payload.get("outputs", [])
    if outputs:
        lines.append(f"  wrote          {Path(outputs[0]).parent}/: {', '.join(Path(p).name for p in outputs)}")
    typer.echo("\n".join(lines))


@linkage_app.command()
def fgen(
    function: Annotated[str | None, typer.Option("--function", help='y = f(x), e.g. "log10(x)" (x, pi, e, '
                                                     '+-*/^, sin cos tan exp log log10 sqrt ...).')] = None,
    table: Annotated[Path | None, typer.Option("--table", help="Two-column table x, y (.csv/.txt) instead of "
                                                  "--function.")] = None,
    x: Annotated[str | None, typer.Option("--x", help="Interval X0:X1 of x (default with --table: the "
                                             "table's range).")] = None,
    input_range: Annotated[float | None, typer.Option("--input-range", help="Turn of the input link (deg, "
                                                         "signed).")] = None,
    output_range: Annotated[float | None, typer.Option("--output-range", help="Turn of the output link (deg, "
                                                          "signed).")] = None,
    method: Annotated[str, typer.Option("--method", help="q (Sunkuev 1984's), precision, lsq, minimax, or all "
                                        "(compare the four).")] = "q",
    nodes: Annotated[int | None, typer.Option("--nodes", help="q: S nodes (odd, default 5); precision: 3; "
                                                 "lsq: N points (default 41).")] = None,
    spacing: Annotated[str, typer.Option("--spacing", help="Nodes: chebyshev or uniform.")] = "chebyshev",
    mu_min: Annotated[float, typer.Option("--mu-min", help="Smallest transmission angle (deg).")] = 30.0,
    ratio_max: Annotated[float, typer.Option("--ratio-max", help="Largest link-length ratio.")] = 10.0,
    frame: Annotated[float, typer.Option("--frame", help="Frame length OC of the result (mm).")] = 100.0,
    phi0: Annotated[float | None, typer.Option("--phi0", help="precision: input offset (deg); default "
                                                  "scanned.")] = None,
    psi0: Annotated[float | None, typer.Option("--psi0", help="precision: output offset (deg).")] = None,
    pick: Annotated[str, typer.Option("--pick", help="q, the last step of Sunkuev 1984's method: centre of the Q "
                                                     "rectangle, or "
                                      "search it for the least deviation.")] = "centre",
    seed: Annotated[int, typer.Option("--seed", help="q: random-number seed that shifts the scan grid.")] = 0,
    max_error: Annotated[float | None, typer.Option("--max-error", help="Also check the largest error "
                                                       "(deg).")] = None,
    output: OutOpt = None,
    no_plots: NoPlotsOpt = False,
    as_json: JsonOpt = False,
) -> None:
    """Synthesise a four-bar function generator y = f(x); exit 1 when a check (transmission angle, link ratio,
    branch, --max-error) fails (--method all compares and exits 0)."""
    from camcad.cli.common import parse_pair
    from camcad.linkage.expr import parse_expression
    from camcad.linkage.fgen import Limits
    from camcad.linkage.synthesis import METHODS, FgenOptions, report, synthesize
    from camcad.linkage.target import make_target, target_from_table
    from camcad.report.linkage import write_fgen_outputs

    if (function is None) == (table is None):
        raise CamcadError("give the function either as --function or as --table", "command line",
                          'e.g. --function "log10(x)" --x 1:2')
    for option, value in (("--input-range", input_range), ("--output-range", output_range)):
        if value is None:
            raise CamcadError("missing", option, f"give {option} DEG (the link's turn over the interval)")
    assert input_range is not None and output_range is not None  # refused above when missing
    methods = list(METHODS) if method == "all" else [method]
    if method != "all" and method not in METHODS:
        raise CamcadError(f"unknown method {method!r}", "--method", f"use one of {', '.join(METHODS)} or all")
    x0: float | None
    x1: float | None
    if function is not None:
        if x is None:
            raise CamcadError("missing", "--x", "give the interval of x, e.g. --x 1:2")
        x0, x1 = parse_pair(x, "--x", "1:2")
        expression = parse_expression(function)
        target = make_target(expression, x0, x1, input_range, output_range, function, expression.derivative)
    else:
        assert table is not None  # exactly one of --function and --table
        if table.exists() and table.is_dir():
            raise CamcadError("is a folder", str(table), "give a .csv/.txt table of x, y")
        x0, x1 = parse_pair(x, "--x", "1:2") if x is not None else (None, None)
        target = target_from_table(table, x0, x1, input_range, output_range)
    limits = Limits(mu_min, ratio_max)
    results = []
    for name in methods:
        opts = FgenOptions(method=name, nodes=nodes if method != "all" or name in ("q",) else None,
                           spacing=spacing, limits=limits, frame_mm=frame,
                           phi0_deg=phi0 if name == "precision" else None,
                           psi0_deg=psi0 if name == "precision" else None, seed=seed, pick=pick,
                           max_error_deg=max_error)
        results.append(synthesize(target, opts))
    folder = output_dir(output, f"fgen-{method}")
    if table is not None:
        prefixes = [f"{m}-" for m in methods] if method == "all" else [""]
        names = {f"{p}{n}" for p in prefixes for n in ("fgen.json", "error.csv", "linkage.dxf", "error.png",
                                                       "positions.png", "pivots.png")}
        names |= {"compare.txt", "compare.json"}
        if table.resolve().parent == folder.resolve() and table.name in names:
            raise CamcadError(f"the output {table.name} would overwrite the input table", str(table),
                              "choose another folder with -o or rename the table")
    payloads = []
    for result in results:
        payload = report(result)
        write_fgen_outputs(folder, result, payload, plots=not no_plots,
                           prefix=f"{result.method}-" if method == "all" else "")
        payloads.append(payload)
    if method == "all":
        from camcad.io.atomic import write_text_atomic
        from camcad.io.jsonout import write_json

        text = _fgen_table(payloads)
        summary = {"method": "all", "function": target.label, "x": [target.x0, target.x1],
                   "input_range_deg": target.input_range_deg, "output_range_deg": target.output_range_deg,
                   "table": [{k: p[k] for k in ("method", "max_error_deg", "rms_error_deg", "mu_min_deg",
                                                "position_evaluations", "links", "passed")} for p in payloads],
                   "results": payloads}
        outputs = [write_text_atomic(folder / "compare.txt", text + "\n"), folder / "compare.json"]
        summary["outputs"] = [str(p) for p in outputs]
        write_json(folder / "compare.json", summary)
        if as_json:
            print_json(summary)
        else:
            typer.echo(f"camcad linkage fgen: {target.label} on [{target.x0:g}, {target.x1:g}], input "
                       f"{target.input_range_deg:g} deg, output {target.output_range_deg:g} deg, limits mu >= "
                       f"{mu_min:g} deg, ratio <= {ratio_max:g}")
            typer.echo(text)
            for p in payloads:
                for note in p.get("notes", []):
                    typer.echo(f"  note ({p['method']}): {note}")
            typer.echo(f"  wrote          {folder}/")
        raise typer.Exit(0)
    payload = payloads[0]
    if as_json:
        print_json(payload)
    else:
        _fgen_summary(payload)
    raise typer.Exit(0 if payload["passed"] else 1)


# --------------------------------------------------------------------------------------------
# Part II: the linkage after the follower — analyse, adjust, family, tune
# --------------------------------------------------------------------------------------------

SceneOptArg = Annotated[Path | None, typer.Argument(help="A scene (.toml) with a [linkage]; or give the linkage "
                                                         "by options.", show_default=False)]
MechOpt = Annotated[str | None, typer.Option("--mechanism", help="The mechanism of a group scene.")]
PivotOpt = Annotated[str, typer.Option("--pivot", help="Input pivot O = the follower's pivot, X,Y (mm).")]
OutPivotOpt = Annotated[str | None, typer.Option("--output-pivot", help="Output pivot C, X,Y (mm).")]
LinksOpt = Annotated[str | None, typer.Option("--links", help="Input link OA, coupler AB, output link CB: A,B,C (mm).")]
InputAngleOpt = Annotated[float | None, typer.Option("--input-angle", help="Input link's angle at psi = 0 (deg).")]
SwingOpt = Annotated[float | None, typer.Option("--swing", help="The follower's swing psi_max (deg).")]
SenseOpt = Annotated[int, typer.Option("--sense", help="+1: the input link turns CCW as psi grows; -1: CW (as "
                                                        "camcad's oscillating follower).")]
BranchOpt = Annotated[int, typer.Option("--branch", help="Assembly branch +1 or -1.")]
OutPivot2Opt = Annotated[str | None, typer.Option("--output-pivot-2", help="Six-bar: second output pivot F, X,Y.")]
Links2Opt = Annotated[str | None, typer.Option("--links-2", help="Six-bar: CD, DE, FE (mm).")]
Coupling2Opt = Annotated[float, typer.Option("--coupling-2", help="Six-bar: angle from CB to CD (deg).")]
Branch2Opt = Annotated[int, typer.Option("--branch-2", help="Six-bar: branch of the second loop.")]
CouplerOpt = Annotated[str | None, typer.Option("--coupler-point", help="Coupler point U,V (mm along AB, left of AB).")]
MuOpt = Annotated[float, typer.Option("--mu-min", help="Transmission-angle limit (deg).")]


def _xy(text: str | None, option: str):
    from camcad.cli.common import parse_pair

    if text is None:
        return None
    return list(parse_pair(text.replace(",", ":"), option, "120,35"))


def _triple(text: str | None, option: str):
    if text is None:
        return None
    parts = text.replace(":", ",").split(",")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise CamcadError(f"{text!r} is not three numbers", option, f"write {option} 40,120,90") from None
    if len(values) != 3:
        raise CamcadError(f"{text!r} is not three numbers", option, f"write {option} 40,120,90")
    return values


def _command_linkage(scene: Path | None, mechanism: str | None, pivot: str, output_pivot, links, input_angle, swing,
                     sense: int, branch: int, output_pivot_2, links_2, coupling_2: float, branch_2: int, coupler_point,
                     mu_min: float):
    from camcad.scene.linkage import from_options, from_scene

    if scene is not None:
        given = [o for o, v in (("--output-pivot", output_pivot), ("--links", links), ("--input-angle", input_angle),
                                ("--swing", swing), ("--links-2", links_2)) if v is not None]
        if given:
            raise CamcadError(f"{given[0]} describes the linkage, which the scene already does", given[0],
                              "give the scene or the linkage options, not both")
        if scene.is_dir() or scene.suffix.lower() != ".toml":
            raise CamcadError("not a scene file", str(scene), "give a .toml scene with a [linkage]")
        return from_scene(scene, mechanism)
    if links is None or output_pivot is None or input_angle is None:
        missing = next(o for o, v in (("--links", links), ("--output-pivot", output_pivot),
                                      ("--input-angle", input_angle)) if v is None)
        raise CamcadError("missing", missing, "give a scene, or --links A,B,C --output-pivot X,Y --input-angle DEG "
                                              "--swing DEG")
    a, b, c = _triple(links, "--links")
    values = {"type": "sixbar" if links_2 is not None else "fourbar", "input_pivot": _xy(pivot, "--pivot"),
              "output_pivot": _xy(output_pivot, "--output-pivot"), "input_link": a, "coupler": b, "output_link": c,
              "input_angle": input_angle, "branch": branch, "coupler_point": _xy(coupler_point, "--coupler-point"),
              "mu_min": mu_min}
    if links_2 is not None:
        d2, e2, f2 = _triple(links_2, "--links-2")
        values.update({"output_pivot_2": _xy(output_pivot_2, "--output-pivot-2"), "input_link_2": d2,
                       "coupler_2": e2, "output_link_2": f2, "coupling_2": coupling_2, "branch_2": branch_2})
    if sense not in (1, -1):
        raise CamcadError(f"--sense must be +1 or -1, got {sense}", "--sense", "write --sense 1 or --sense -1")
    return from_options(values, swing, sense, "command line")


def _element(command, element: str | None, joint: str, path: str, centre: str | None, direction: float):
    """The adjustable element: the options', else the scene's [linkage.adjust]; None if neither."""
    from camcad.linkage.adjust import Adjustment

    if element is None:
        context = command.context
        if context is not None and context.spec.adjust is not None:
            from camcad.scene.linkage import adjustment_of

            return adjustment_of(context.spec.adjust), context.spec.adjust
        return None, None
    if element not in ("pivot", "joint", "link_angle"):
        raise CamcadError(f"unknown element {element!r}", "--element", "use pivot, joint or link_angle")
    joints = {"pivot": ("C", "F"), "joint": ("A", "B", "E"), "link_angle": ("",)}[element]
    if element != "link_angle" and joint.upper() not in joints:
        raise CamcadError(f"joint {joint!r} cannot be a {element}", "--joint", f"use {' or '.join(joints)}")
    xy = _xy(centre, "--centre")
    if element != "link_angle" and path == "arc" and xy is None:
        raise CamcadError("an arc needs its centre", "--centre", "give --centre X,Y (mm)")
    return Adjustment(element, joint.upper() if element != "link_angle" else "", path,
                      None if xy is None else complex(*xy), math.radians(direction)), None


def _numbers(text: str | None, option: str) -> list[float] | None:
    if text is None:
        return None
    try:
        return [float(p) for p in text.replace(";", ",").split(",") if p.strip()]
    except ValueError:
        raise CamcadError(f"{text!r} is not a list of numbers", option, f"write {option} 10,20,30") from None


def _finish(payload: dict, summary: list[str], as_json: bool, passed: bool) -> None:
    if as_json:
        print_json(payload)
    else:
        outputs = payload.get("outputs", [])
        if outputs:
            summary.append(f"  wrote          {Path(outputs[0]).parent}/: {', '.join(Path(p).name for p in outputs)}")
        typer.echo("\n".join(summary))
    raise typer.Exit(0 if passed else 1)


@linkage_app.command()
def analyse(
    scene: SceneOptArg = None,
    mechanism: MechOpt = None,
    pivot: PivotOpt = "0,0",
    output_pivot: OutPivotOpt = None,
    links: LinksOpt = None,
    input_angle: InputAngleOpt = None,
    swing: SwingOpt = None,
    sense: SenseOpt = 1,
    branch: BranchOpt = 1,
    output_pivot_2: OutPivot2Opt = None,
    links_2: Links2Opt = None,
    coupling_2: Coupling2Opt = 0.0,
    branch_2: Branch2Opt = 1,
    coupler_point: CouplerOpt = None,
    mu_min: MuOpt = 30.0,
    points: Annotated[int, typer.Option("--points", help="Samples over the swing.")] = 721,
    cam: Annotated[bool, typer.Option("--cam/--no-cam", help="Scene: draw the cam profile on the same sheet.")] = True,
    output: OutOpt = None,
    no_plots: NoPlotsOpt = False,
    as_json: JsonOpt = False,
) -> None:
    """Analyse the linkage after the follower: exact Pi, Pi', Pi'', Pi''', transmission angles, dead points,
    branch, coupler path; exit 1 when a check fails."""
    from camcad.linkage.analysis import analyse as run_analysis
    from camcad.report.linkage import (
        analysis_csv,
        analysis_figure,
        diagram_figure,
        kinematic_drawing,
        rows_csv,
        settings_figure,
        working_figure,
        write_linkage_outputs,
    )

    if points < 11 or points > 200001:
        raise CamcadError(f"--points {points} is out of range", "--points", "give 11 to 200001")
    command = _command_linkage(scene, mechanism, pivot, output_pivot, links, input_angle, swing, sense, branch,
                               output_pivot_2, links_2, coupling_2, branch_2, coupler_point, mu_min)
    result = run_analysis(command.linkage, command.psi_max, points)
    payload = {"command": "linkage analyse", "name": command.name, "linkage": result.report(command.mu_min)}
    texts = {"analysis.csv": analysis_csv(result)}
    figures = {} if no_plots else {"analysis.png": lambda: analysis_figure(result, command.mu_min)}
    settings, arc, profile, follower = [], None, None, None
    if command.context is not None:
        from camcad.scene.linkage import working_report

        ctx = command.context
        payload["law_of"] = ctx.law_of
        payload["working_member"] = working_report(ctx, command.follower_law, command.output_law)
        theta = np.linspace(0.0, command.follower_law.cycle, 1441)
        kin = ctx.working_law(command.follower_law).kinematics(theta)
        texts["working.csv"] = rows_csv([{"theta_deg": math.degrees(t), "y": s, "y_1": v, "y_2": a, "y_3": j}
                                         for t, s, v, a, j in zip(theta, kin.s, kin.v, kin.a, kin.j)],
                                        f"the working member y = Pi(psi(theta)) in {ctx.transfer.unit_out} and its "
                                        "derivatives per rad of cam angle")
        if not no_plots:
            figures["working.png"] = lambda: working_figure(theta, kin, ctx.transfer.unit_out)
        if ctx.spec.adjust is not None:
            from camcad.linkage.adjust import adjusted, characteristics, radius
            from camcad.scene.linkage import adjustment_of, setting_value

            adj = adjustment_of(ctx.spec.adjust)
            rows = []
            for value in ctx.spec.adjust.settings:
                x = setting_value(ctx.spec.adjust, value)
                ch = characteristics(command.linkage, adj, x, command.psi_max)
                rows.append({"setting": value, **{k: v for k, v in ch.as_dict(adj.unit).items()
                                                  if not k.startswith("setting")}})
                settings.append((f"{value:g} {'mm' if adj.unit == 'mm' else 'deg'}", adjusted(command.linkage, adj, x)))
            payload["settings"] = {"element": adj.describe(), "rows": rows}
            texts["settings.csv"] = rows_csv(rows, "psi1, psi2: the working member at the follower's extremes, "
                                                   "from its nominal position at psi = 0 (deg)")
            if adj.element != "link_angle" and adj.path == "arc":
                arc = (adj.centre, radius(command.linkage, adj),
                       [setting_value(ctx.spec.adjust, v) for v in ctx.spec.adjust.settings])
            if not no_plots:
                unit = "deg" if adj.unit == "rad" else "mm"
                figures["settings.png"] = lambda: settings_figure(rows, f"setting ({unit})", adj.describe())
        if cam:
            from camcad.profile.followers import FOLLOWER_KINDS  # noqa: F401 - the profile package
            from camcad.scene.linkage import cam_profile

            profile = cam_profile(command)
            follower = profile.follower
    if not no_plots:
        figures["diagram.png"] = lambda: diagram_figure(command.linkage, command.psi_max, settings, arc,
                                                        f"{command.name}: the linkage in its extreme positions")
    title = (f"camcad linkage analyse: {command.name}, {result.linkage.kind}",
             (f"swing {math.degrees(command.psi_max):.6g} deg, stroke {math.degrees(result.stroke):.6g} deg, "
              f"worst transmission angle {result.worst_mu_deg():.3f} deg"),
             "layers: LINKS psi = 0, EXTREME_POSITIONS psi max, SETTINGS, ADJUSTMENT arc" +
             (", cam PROFILE/PITCH/BASE_CIRCLE" if profile is not None else ""))
    drawing = kinematic_drawing(command.linkage, command.psi_max, settings, arc, profile, follower, title)
    folder = output_dir(output, f"linkage-{command.name}")
    _refuse_inputs(command, folder)
    write_linkage_outputs(folder, "analysis", payload, texts, figures, drawing)
    passed = bool(payload["linkage"]["passed"])
    rep = payload["linkage"]
    summary = [(f"camcad linkage analyse: {command.name}, {rep['type']}, swing {rep['swing_deg']:.6g} deg -> stroke "
                f"{rep['stroke_deg']:.6g} deg ({rep['output_direction']})"),
               (f"  Pi'            {rep['pi_prime_range'][0]:.6g} .. {rep['pi_prime_range'][1]:.6g} rad/rad; "
                f"|Pi''| <= {rep['pi_second_abs_max']:.4g}, |Pi'''| <= {rep['pi_third_abs_max']:.4g}"),
               f"  mu min         {', '.join(f'{m:.3f}' for m in rep['mu_min_deg'])} deg (limit {command.mu_min:g})",
               (f"  dead points    {rep['dead_points_swing_deg'] or 'none'}; limit positions "
                f"{rep['limit_positions_swing_deg'] or 'none'} (swing deg)"),
               (f"  branch         {'continuous' if rep['branch_continuous'] else 'NOT continuous'}; "
                f"{'monotone' if rep['monotone'] else 'NOT monotone'}")]
    if "working_member" in payload:
        w = payload["working_member"]
        line = f"  working member stroke {w['stroke']:.6g} {w['unit']}, |y''| <= {w['acceleration_analog_max']:.5g}"
        if "round_trip_max" in w:
            line += f"; law_of = output round trip {w['round_trip_max']:.3g} {w['round_trip_unit']}"
        summary.append(line)
    for row in payload.get("settings", {}).get("rows", []):
        summary.append(f"  setting {row['setting']:<8g} psi1 {row['psi1_deg']:+.5f}, psi2 {row['psi2_deg']:+.5f}, "
                       f"swing {row['swing_deg']:.5f}, mu min {row['mu_min_deg']:.2f} deg"
                       + ("" if row["branch_continuous"] else ", BRANCH BROKEN"))
    for name, check in rep["checks"].items():
        summary.append(f"  check {name:<20} " + ("ok" if check["passed"] else "FAILED"))
    _finish(payload, summary, as_json, passed)


def _refuse_inputs(command, folder: Path) -> None:
    """Outputs never replace an input (the scene, its law or table files): every file these commands may write
    is checked by the shared guard (resolved path, device and inode) before any is written."""
    from camcad.io.output_folder import check_outputs

    if command.scene is None:
        return
    names = [f"{stem}.{suffix}" for stem in ("analysis", "adjust", "tune") for suffix in ("json", "csv", "dxf", "png")]
    names += ["working.csv", "settings.csv", "working.png", "settings.png", "diagram.png"]
    inputs = [(path, "an input of the scene") for path in command.scene.input_files()]
    check_outputs([folder / name for name in names], inputs)


def _functions(options: dict) -> dict:
    """Expressions of the regulating variable x (deg values) → callables rad → rad."""
    from camcad.linkage.expr import parse_expression

    out = {}
    for key, (option, text) in options.items():
        if text is None:
            continue
        try:
            expr = parse_expression(text)
        except CamcadError as err:
            raise CamcadError(err.what, option, err.fix) from None
        out[key] = _in_radians(expr, key == "psi2_of_psi1")
    return out


def _in_radians(expr, argument_in_deg: bool = False):
    """A callable rad → rad of an expression giving deg (of x in deg when ``argument_in_deg``, else of x)."""
    if argument_in_deg:
        return lambda u: math.radians(float(expr(math.degrees(u))))
    return lambda u: math.radians(float(expr(u)))


@linkage_app.command()
def adjust(
    scene: SceneOptArg = None,
    mechanism: MechOpt = None,
    task: Annotated[int | None, typer.Option("--task", help="Regulation task of Sunkuev 1984's Table 3 (1-6) or, with "
                                                            "--table 2, Table 2 (1-17, checked).")] = None,
    table: Annotated[int, typer.Option("--table", help="3: rocker input (the cam case, synthesis); 2: crank input "
                                                       "(the element's settings checked).")] = 3,
    swing_range: Annotated[str | None, typer.Option("--swing-range", help="Task 1: swings A:B (deg) to cover.")] = None,
    keep: Annotated[str, typer.Option("--keep", help="Task 1: keep psi1 or psi2 constant.")] = "psi1",
    count: Annotated[int, typer.Option("--count", help="Settings listed.")] = 7,
    u_range: Annotated[str | None, typer.Option("--x", help="Tasks 2-6: range U0:U1 of the regulating variable x.")]
    = None,
    psi1: Annotated[str | None, typer.Option("--psi1", help="Tasks 3, 5: psi1 (deg) as a function of x.")] = None,
    psi2: Annotated[str | None, typer.Option("--psi2", help="Tasks 4, 5: psi2 (deg) as a function of x.")] = None,
    swing_fn: Annotated[str | None, typer.Option("--swing-function", help="Task 6: the swing (deg) as a function "
                                                                          "of x.")] = None,
    psi2_of_psi1: Annotated[str | None, typer.Option("--psi2-of-psi1", help="Task 2: psi2 (deg) as a function of "
                                                                            "x = psi1 (deg).")] = None,
    pivot: PivotOpt = "0,0",
    output_pivot: OutPivotOpt = None,
    links: LinksOpt = None,
    input_angle: InputAngleOpt = None,
    swing: SwingOpt = None,
    sense: SenseOpt = 1,
    branch: BranchOpt = 1,
    output_pivot_2: OutPivot2Opt = None,
    links_2: Links2Opt = None,
    coupling_2: Coupling2Opt = 0.0,
    branch_2: Branch2Opt = 1,
    mu_min: MuOpt = 30.0,
    element: Annotated[str | None, typer.Option("--element", help="--table 2: pivot, joint or link_angle.")] = None,
    joint: Annotated[str, typer.Option("--joint", help="--table 2: the element's joint (C, F, A, B, E).")] = "C",
    path: Annotated[str, typer.Option("--path", help="--table 2: arc or slot.")] = "arc",
    centre: Annotated[str | None, typer.Option("--centre", help="--table 2: arc centre X,Y (mm).")] = None,
    direction: Annotated[float, typer.Option("--direction", help="--table 2: slot direction (deg).")] = 0.0,
    settings: Annotated[str | None, typer.Option("--settings", help="--table 2: settings (deg or mm).")] = None,
    output: OutOpt = None,
    no_plots: NoPlotsOpt = False,
    as_json: JsonOpt = False,
) -> None:
    """Synthesise an adjustable mechanism for a regulation task (Sunkuev 1984, Table 3; Table 2 checked); exit 1 when
    the result fails a check."""
    from camcad.cli.common import parse_pair
    from camcad.linkage import adjust as adj_mod
    from camcad.report.linkage import (
        diagram_figure,
        kinematic_drawing,
        rows_csv,
        settings_figure,
        write_linkage_outputs,
    )

    if table not in (2, 3):
        raise CamcadError(f"--table {table}: Sunkuev 1984's regulation tables are 2 and 3", "--table", "use 2 or 3")
    if task is None:
        raise CamcadError("missing", "--task", "give the regulation task, e.g. --task 1")
    if not 2 <= count <= 201:
        raise CamcadError(f"--count {count} is out of range", "--count", "give 2 to 201")
    command = _command_linkage(scene, mechanism, pivot, output_pivot, links, input_angle, swing, sense, branch,
                               output_pivot_2, links_2, coupling_2, branch_2, None, mu_min)
    lk, psi_max = command.linkage, command.psi_max
    payload: dict = {"command": "linkage adjust", "name": command.name, "table": table, "task": task}
    if table == 2:
        adj, spec = _element(command, element, joint, path, centre, direction)
        values = _numbers(settings, "--settings") or (list(spec.settings) if spec is not None else None)
        if adj is None or not values:
            raise CamcadError("Table 2 checks an adjustable element's settings", "--element",
                              "give --element, --joint, --centre and --settings (or a scene with [linkage.adjust])")
        rows = []
        for v in values:
            x = math.radians(v) if adj.unit == "rad" else v
            ch = adj_mod.crank_characteristics(lk, adj, x)
            if not ch:
                raise CamcadError(f"at setting {v:g} the input link cannot turn fully (not a crank)", "--table 2",
                                  "Table 2 is for a rotating input; the cam's rocker input is Table 3")
            rows.append({"setting": v, **ch})
        verdict = adj_mod.check_requirements(rows, task, 2)
        payload.update({"element": adj.describe(), "rows": rows, "requirements": verdict,
                        "passed": bool(verdict["passed"])})
        folder = output_dir(output, f"adjust-{command.name}")
        _refuse_inputs(command, folder)
        write_linkage_outputs(folder, "adjust", payload, {"adjust.csv": rows_csv(rows)})
        summary = [f"camcad linkage adjust: Table 2 task {task}, {adj.describe()}"]
        summary += [f"  setting {r['setting']:<8g} phi1 {r['phi1_deg']:.4f} psi1 {r['psi1_deg']:.4f} phi2 "
                    f"{r['phi2_deg']:.4f} psi2 {r['psi2_deg']:.4f} deg" for r in rows]
        summary += [f"  requirement {k}: {v['need']} " + ("ok" if v["passed"] else "NOT met")
                    for k, v in verdict.items() if isinstance(v, dict)]
        _finish(payload, summary, as_json, bool(verdict["passed"]))
    if task == 1:
        if swing_range is None:
            raise CamcadError("missing", "--swing-range", "give the swings to cover, e.g. --swing-range 18:30 (deg)")
        lo, hi = parse_pair(swing_range, "--swing-range", "18:30")
        if not (lo > 0 and hi > lo):
            raise CamcadError(f"--swing-range {swing_range} must be 0 < A < B (deg)", "--swing-range",
                              "e.g. --swing-range 18:30")
        result = adj_mod.solve_task1(lk, psi_max, (math.radians(lo), math.radians(hi)), count, keep)
    elif task in (2, 3, 4, 5, 6):
        if u_range is None:
            raise CamcadError("missing", "--x", "give the regulating variable's range, e.g. --x 0:10")
        u0, u1 = parse_pair(u_range, "--x", "0:10")
        if u1 == u0:
            raise CamcadError("--x has no width", "--x", "give U0:U1 with U1 != U0")
        needed = {2: {"psi2_of_psi1": ("--psi2-of-psi1", psi2_of_psi1)}, 3: {"psi1": ("--psi1", psi1)},
                  4: {"psi2": ("--psi2", psi2)}, 5: {"psi1": ("--psi1", psi1), "psi2": ("--psi2", psi2)},
                  6: {"swing": ("--swing-function", swing_fn)}}[task]
        for option, text in needed.values():
            if text is None:
                raise CamcadError("missing", option, f"task {task} needs {option} EXPR (deg, a function of x)")
        functions = _functions(needed)
        if task == 2:
            u0, u1 = math.radians(u0), math.radians(u1)
        result = adj_mod.fit_task(lk, psi_max, task, (u0, u1), functions, count=max(count, 11))
    else:
        raise CamcadError(f"Table 3 has no task {task}", "--task", "tasks are 1 to 6")
    rows = [{"u": float(u), **r.as_dict(result.adjustment.unit)} for u, r in zip(result.u, result.rows)]
    if task == 1:
        for row in rows:
            row["u"] = row["swing_deg"]
    swapped = task == 1 and keep == "psi2"   # task 1 with the second extreme kept: the columns trade roles
    check_rows = [{**r, "psi1_deg": r["psi2_deg"], "psi2_deg": r["psi1_deg"]} for r in rows] if swapped else rows
    verdict = adj_mod.check_requirements(check_rows, task, 3)
    if swapped:
        verdict = {{"psi1": "psi2", "psi2": "psi1"}.get(k, k): v for k, v in verdict.items()}
    checks_ok = all(r["branch_continuous"] and r["mu_min_deg"] >= mu_min for r in rows)
    adj = result.adjustment
    arc_centre = cast(complex, adj.centre)  # every task of Table 3 moves joint A on an arc
    payload.update({"element": adj.describe(), "arc_centre_mm": [arc_centre.real, arc_centre.imag],
                    "arc_radius_mm": result.radius, "rows": rows, "deviation_deg": {k: math.degrees(v) for k, v in
                                                                                   result.deviation.items()},
                    "monotone": result.monotone, "requirements": verdict, "notes": list(result.notes),
                    "passed": bool(verdict["passed"] and checks_ok and result.monotone)})
    settings_links = [(f"x = {r['setting_deg']:.3f} deg", adj_mod.adjusted(lk, adj, math.radians(r["setting_deg"])))
                      for r in rows]
    arc = (adj.centre, result.radius, [math.radians(r["setting_deg"]) for r in rows])
    figures = {} if no_plots else {
        "adjust.png": lambda: settings_figure([{**r, "setting": r["setting_deg"]} for r in rows], "lock angle (deg)",
                                              f"Table 3 task {task}: {adj.describe()}"),
        "diagram.png": lambda: diagram_figure(lk, psi_max, settings_links, arc, f"task {task}: every setting")}
    drawing = kinematic_drawing(lk, psi_max, settings_links, arc, title=(
        f"camcad linkage adjust: Table 3 task {task}", adj.describe(),
        f"arc radius {result.radius:.4f} mm, lock angles {rows[0]['setting_deg']:.3f} .. "
        f"{rows[-1]['setting_deg']:.3f} deg"))
    folder = output_dir(output, f"adjust-{command.name}")
    _refuse_inputs(command, folder)
    write_linkage_outputs(folder, "adjust", payload, {"adjust.csv": rows_csv(rows, "u: the regulating variable "
                                                                                   "(task 1: the requested swing)")},
                          figures, drawing)
    summary = [f"camcad linkage adjust: Table 3 task {task}, {adj.describe()}, radius {result.radius:.4f} mm"]
    summary += [f"  x {r['u']:<10.5g} lock {r['setting_deg']:9.4f} deg  psi1 {r['psi1_deg']:+.9f}  psi2 "
                f"{r['psi2_deg']:+.6f}  swing {r['swing_deg']:.6f}  mu {r['mu_min_deg']:.2f}" for r in rows]
    summary.append("  deviation      " + ", ".join(f"{k} {v:.3g} deg" for k, v in payload["deviation_deg"].items()))
    summary += [f"  requirement {k}: {v['need']} " + ("ok" if v["passed"] else "NOT met")
                for k, v in verdict.items() if isinstance(v, dict)]
    _finish(payload, summary, as_json, payload["passed"])


@linkage_app.command()
def family(
    member: Annotated[list[str] | None, typer.Option("--member", help="A member psi(x) (deg) of the input angle x "
                                                                       "(deg); repeat for each member.")] = None,
    table: Annotated[Path | None, typer.Option("--table", help="Members as a table: x (deg), then one column per "
                                                               "member (deg).")] = None,
    phi: Annotated[str | None, typer.Option("--phi", help="Input interval A:B (deg) of every member.")] = None,
    nodes: Annotated[int, typer.Option("--nodes", help="S nodes per member (odd).")] = 5,
    crank: Annotated[float, typer.Option("--crank", help="Crank length OA (mm).")] = 40.0,
    phi0: Annotated[float, typer.Option("--phi0", help="The crank's angle at x = 0 (deg).")] = 0.0,
    spacing: Annotated[str, typer.Option("--spacing", help="chebyshev or uniform nodes.")] = "chebyshev",
    ratio_max: Annotated[float, typer.Option("--ratio-max", help="Largest link ratio.")] = 10.0,
    mu_min: MuOpt = 30.0,
    output: OutOpt = None,
    no_plots: NoPlotsOpt = False,
    as_json: JsonOpt = False,
) -> None:
    """One adjustable four-bar for a family of position functions (Sunkuev 1984, ch. 4: Q, then the circle through
    the pivots); exit 1 when a member fails its checks."""
    from camcad.cli.common import parse_pair
    from camcad.linkage.family import Member, synthesize_family
    from camcad.report.linkage import (
        diagram_figure,
        family_figure,
        kinematic_drawing,
        rows_csv,
        write_linkage_outputs,
    )

    if (not member) == (table is None):
        raise CamcadError("give the members either as --member (repeated) or as --table", "command line",
                          'e.g. --member "0.5*x" --member "0.6*x" --member "0.7*x" --phi 0:60')
    if phi is None:
        raise CamcadError("missing", "--phi", "give the input interval, e.g. --phi 0:60 (deg)")
    a, b = parse_pair(phi, "--phi", "0:60")
    if b <= a:
        raise CamcadError(f"--phi {phi}: the interval must grow", "--phi", "write --phi A:B with B > A")
    if spacing not in ("chebyshev", "uniform"):
        raise CamcadError(f"unknown spacing {spacing!r}", "--spacing", "use chebyshev or uniform")
    if not crank > 0 or not ratio_max > 1:
        raise CamcadError("--crank must be > 0 and --ratio-max > 1", "--crank", "give positive values")
    members = []
    if member:
        from camcad.linkage.expr import parse_expression

        for k, text in enumerate(member, start=1):
            try:
                expr = parse_expression(text)
            except CamcadError as err:
                raise CamcadError(err.what, f"--member {k}", err.fix) from None
            members.append(Member(_in_radians(expr, True), math.radians(a), math.radians(b), text))
    else:
        assert table is not None  # exactly one of --member and --table
        members = _table_members(table, a, b)
    result = synthesize_family(members, nodes, crank, math.radians(phi0), spacing, ratio_max=ratio_max)
    rows = [{"member": m.label or str(k + 1), "setting_deg": math.degrees(x), "pivot_x_mm": p.real,
             "pivot_y_mm": p.imag, "q_member": q, "output_link_mm": c, "max_error_deg": math.degrees(e),
             "mu_min_deg": math.degrees(mu), "branch_ok": ok}
            for k, (m, x, p, q, c, e, mu, ok) in enumerate(zip(members, result.settings, result.pivots,
                                                               result.q_members, result.c_members, result.max_error,
                                                               result.mu_min, result.branch_ok))]
    passed = all(r["branch_ok"] and r["mu_min_deg"] >= mu_min for r in rows)
    payload = {"command": "linkage family", "members": len(members), "nodes": nodes, "crank_mm": result.crank,
               "coupler_mm": result.coupler, "output_link_mm": result.output_link, "phi0_deg": phi0,
               "q": result.q, "q_unit": "crank lengths (sum of the members' Q plus the output-link spread)",
               "arc_centre_mm": [result.centre.real, result.centre.imag], "arc_radius_mm": result.radius,
               "circle_residual_mm": result.circle_residual, "settings_deg": [math.degrees(x) for x in result.settings],
               "rows": rows, "position_evaluations": result.evaluations, "passed": passed}
    settings_links = [(f"x = {math.degrees(x):.3f} deg", result.mechanism(k)) for k, x in enumerate(result.settings)]
    arc = (result.centre, result.radius, list(result.settings))
    base = settings_links[0][1]
    swing = math.radians(b)
    figures = {} if no_plots else {"family.png": lambda: family_figure(result, members),
                                   "diagram.png": lambda: diagram_figure(base, swing, settings_links, arc,
                                                                         "the family's mechanism at every setting")}
    drawing = kinematic_drawing(base, swing, settings_links, arc, title=(
        f"camcad linkage family: {len(members)} members, Q = {result.q:.3g}",
        (f"OA {result.crank:.4f}  AB {result.coupler:.4f}  CB {result.output_link:.4f} mm; arc F "
         f"({result.centre.real:.4f}, {result.centre.imag:.4f}) R {result.radius:.4f} mm")))
    folder = output_dir(output, "family")
    write_linkage_outputs(folder, "family", payload, {"family.csv": rows_csv(rows)}, figures, drawing)
    summary = [f"camcad linkage family: {len(members)} members on [{a:g}, {b:g}] deg, {nodes} nodes each",
               (f"  stage 1        Q = {result.q:.4g} crank lengths; OA {result.crank:.6g}, AB {result.coupler:.6g}, "
                f"CB {result.output_link:.6g} mm"),
               (f"  stage 2        arc centre F ({result.centre.real:.6f}, {result.centre.imag:.6f}) mm, radius "
                f"{result.radius:.6f} mm (residual {result.circle_residual:.3g} mm)")]
    summary += [f"  member {r['member']:<14} setting {r['setting_deg']:10.5f} deg, max error {r['max_error_deg']:.3g} "
                f"deg, mu min {r['mu_min_deg']:.2f} deg" + ("" if r["branch_ok"] else ", BRANCH BROKEN") for r in rows]
    _finish(payload, summary, as_json, passed)


def _table_members(path: Path, a: float, b: float) -> list:
    """Members from a table: x (deg) then one column per member (deg), a not-a-knot cubic spline each."""
    from scipy.interpolate import CubicSpline

    from camcad.io.input_file import decode_text, read_input
    from camcad.linkage.family import Member

    text, _ = decode_text(read_input(path, "a table of x and member columns (.csv/.txt)"))
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        content = line.split("#", 1)[0].strip()
        if not content:
            continue
        cells = [c for c in content.replace(";", ",").replace("\t", ",").split(",")]
        try:
            rows.append([float(c) for c in cells])
        except ValueError:
            if rows:
                raise CamcadError(f"line {number} is not numbers", str(path), "fix or delete that line") from None
    if len(rows) < 4 or len({len(r) for r in rows}) != 1 or len(rows[0]) < 4:
        raise CamcadError("the table needs at least 4 rows of x and 3 or more member columns", str(path),
                          "write x, psi1, psi2, psi3 per line (deg)")
    data = np.array(rows, dtype=float)
    order = np.argsort(data[:, 0])
    data = data[order]
    if np.any(np.diff(data[:, 0]) <= 0):
        raise CamcadError("x repeats in the table", str(path), "give each x once")
    if a < data[0, 0] - 1e-12 or b > data[-1, 0] + 1e-12:
        raise CamcadError(f"--phi {a:g}:{b:g} is outside the table's x range", str(path), "narrow --phi")
    members = []
    for k in range(1, data.shape[1]):
        spline = CubicSpline(np.radians(data[:, 0]), np.radians(data[:, k]))
        members.append(Member(spline, math.radians(a), math.radians(b), f"column {k}"))
    return members


@linkage_app.command()
def tune(
    scene: SceneOptArg = None,
    mechanism: MechOpt = None,
    psi1: Annotated[float | None, typer.Option("--psi1", help="Requested first extreme position (deg).")] = None,
    psi2: Annotated[float | None, typer.Option("--psi2", help="Requested second extreme position (deg).")] = None,
    grid: Annotated[str | None, typer.Option("--grid", help="Settings table: PSI1_A:PSI1_B:N,SWING_A:SWING_B:M "
                                                            "(deg).")] = None,
    x1_range: Annotated[str | None, typer.Option("--range", help="Interval A:B of x1 searched (deg, mm for a "
                                                                 "slot).")] = None,
    points: Annotated[int, typer.Option("--points", help="Samples of F(x1).")] = 721,
    element: Annotated[str | None, typer.Option("--element", help="x1's element: pivot or joint (default: the "
                                                                  "scene's [linkage.adjust]).")] = None,
    joint: Annotated[str, typer.Option("--joint", help="The element's joint (C, F, A, B, E).")] = "C",
    path: Annotated[str, typer.Option("--path", help="arc or slot.")] = "arc",
    centre: Annotated[str | None, typer.Option("--centre", help="Arc centre X,Y (mm).")] = None,
    direction: Annotated[float, typer.Option("--direction", help="Slot direction (deg).")] = 0.0,
    pivot: PivotOpt = "0,0",
    output_pivot: OutPivotOpt = None,
    links: LinksOpt = None,
    input_angle: InputAngleOpt = None,
    swing: SwingOpt = None,
    sense: SenseOpt = 1,
    branch: BranchOpt = 1,
    output_pivot_2: OutPivot2Opt = None,
    links_2: Links2Opt = None,
    coupling_2: Coupling2Opt = 0.0,
    branch_2: Branch2Opt = 1,
    mu_min: MuOpt = 30.0,
    output: OutOpt = None,
    no_plots: NoPlotsOpt = False,
    as_json: JsonOpt = False,
) -> None:
    """Settings (x1 on the adjustable element, x2 the input link's clamp angle) for given extreme positions,
    every root of F(x1) = 0 (Sunkuev 1984, ch. 6); exit 1 when none is found."""
    from camcad.cli.common import parse_pair
    from camcad.linkage.tune import settings_table, solve_settings, tuned
    from camcad.report.linkage import (
        kinematic_drawing,
        rows_csv,
        tune_figure,
        write_linkage_outputs,
    )

    if not 11 <= points <= 100001:
        raise CamcadError(f"--points {points} is out of range", "--points", "give 11 to 100001")
    command = _command_linkage(scene, mechanism, pivot, output_pivot, links, input_angle, swing, sense, branch,
                               output_pivot_2, links_2, coupling_2, branch_2, None, mu_min)
    adj, _ = _element(command, element, joint, path, centre, direction)
    if adj is None:
        raise CamcadError("no adjustable element for x1", "--element",
                          "give --element pivot --joint C --centre X,Y (or a scene with [linkage.adjust])")
    if adj.element == "link_angle":
        raise CamcadError("x2 is the input link's clamp angle: x1 must be a pivot or joint", "--element",
                          "use --element pivot or joint")
    lk, psi_max = command.linkage, command.psi_max
    rng = None
    if x1_range is not None:
        lo, hi = parse_pair(x1_range, "--range", "30:150")
        rng = (math.radians(lo), math.radians(hi)) if adj.unit == "rad" else (lo, hi)
    unit = "deg" if adj.unit == "rad" else "mm"
    payload: dict = {"command": "linkage tune", "name": command.name, "element": adj.describe(), "x1_unit": unit}
    folder = output_dir(output, f"tune-{command.name}")
    _refuse_inputs(command, folder)
    if grid is not None:
        if psi1 is not None or psi2 is not None:
            raise CamcadError("--grid and --psi1/--psi2 both ask for settings", "--grid", "give one of them")
        first, second = _grid_axes(grid)
        rows = settings_table(lk, adj, psi_max, np.radians(first), np.radians(second), rng, min(points, 361))
        payload.update({"rows": rows, "passed": all(r["x1"] is not None for r in rows)})
        write_linkage_outputs(folder, "tune", payload, {"tune.csv": rows_csv(
            rows, "settings table: every root x1 (lock angle or slot position) and x2 (clamp angle) per psi1, swing")})
        summary = [f"camcad linkage tune: settings table, {adj.describe()}"]
        summary += [f"  psi1 {r['psi1_deg']:+8.3f} swing {r['swing_deg']:8.3f} deg -> " +
                    (f"root {r['root']}: x1 {r['x1']:.6f} {unit}, x2 {r['x2_deg']:.6f} deg (error {r['error_deg']:.2g})"
                     if r["x1"] is not None else "no setting") for r in rows]
        _finish(payload, summary, as_json, payload["passed"])
    if psi1 is None or psi2 is None:
        raise CamcadError("missing", "--psi1" if psi1 is None else "--psi2",
                          "give --psi1 DEG --psi2 DEG (or --grid for a settings table)")
    result = solve_settings(lk, adj, psi_max, math.radians(psi1), math.radians(psi2), rng, points)
    rows = [{"root": k, "x1": math.degrees(r.x1) if unit == "deg" else r.x1, "x2_deg": math.degrees(r.x2),
             "psi1_deg": math.degrees(r.psi1), "psi2_deg": math.degrees(r.psi2), "error_deg": math.degrees(r.error),
             "mu_min_deg": math.degrees(r.mu_min) if np.isfinite(r.mu_min) else None,
             "branch_continuous": r.branch_continuous} for k, r in enumerate(result.roots, start=1)]
    payload.update({"psi1_deg": psi1, "psi2_deg": psi2, "roots": rows, "passed": bool(rows)})
    figures = {} if no_plots else {"tune.png": lambda: tune_figure(result, adj.unit)}
    drawing = None
    if rows:
        settings_links = [(f"root {k + 1}", tuned(lk, adj, r.x1, r.x2)) for k, r in enumerate(result.roots)]
        drawing = kinematic_drawing(lk, psi_max, settings_links, title=(
            f"camcad linkage tune: psi1 {psi1:g} deg, psi2 {psi2:g} deg", adj.describe(),
            "SETTINGS: the mechanism at every root, both extremes"))
    write_linkage_outputs(folder, "tune", payload, {"tune.csv": rows_csv(rows)}, figures, drawing)
    summary = [(f"camcad linkage tune: psi1 {psi1:g} deg, psi2 {psi2:g} deg; x1 on {adj.describe()}, x2 the input "
                "link's clamp angle")]
    summary += [f"  root {r['root']}: x1 {r['x1']:.9f} {unit}, x2 {r['x2_deg']:.9f} deg; round trip error "
                f"{r['error_deg']:.2g} deg, mu min {r['mu_min_deg'] or float('nan'):.2f} deg" +
                ("" if r["branch_continuous"] else ", BRANCH BROKEN") for r in rows] or [
        "  no setting gives these extreme positions"]
    _finish(payload, summary, as_json, bool(rows))


def _grid_axes(text: str) -> tuple[list[float], list[float]]:
    parts = text.split(",")
    if len(parts) != 2:
        raise CamcadError(f"{text!r} is not two ranges", "--grid", "write --grid -2:2:3,10:20:3")
    axes = []
    for part in parts:
        bits = part.split(":")
        try:
            if len(bits) == 1:
                axes.append([float(bits[0])])
                continue
            start, stop, n = float(bits[0]), float(bits[1]), int(bits[2])
        except (ValueError, IndexError):
            raise CamcadError(f"{part!r} is not A:B:N", "--grid", "write --grid -2:2:3,10:20:3") from None
        if not 1 <= n <= 50:
            raise CamcadError(f"{n} values is out of range", "--grid", "give 1 to 50 values per axis")
        axes.append(list(np.linspace(start, stop, n)))
    return axes[0], axes[1]
