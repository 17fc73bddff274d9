"""`camcad linkage`: structural atlas of (adjustable) chains and four-bar function-generator synthesis
(seed 002, Sunkuev 1984, chapters 1–2)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from camcad.errors import CamcadError
from camcad.cli import app
from camcad.cli.common import JsonOpt, NoPlotsOpt, OutOpt, output_dir, print_json

linkage_app = typer.Typer(no_args_is_help=True, help="Linkages after the cam (seed 002): atlas of adjustable chains, "
                                                    "function-generator synthesis (Q method).")
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
        lines.append(f"  seed Table 1   {payload['seed_count']} ({same})")
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
        "--adjustable", help="m locked pairs: enumerate adjustable chains (seed Table 1).")] = None,
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
                 f"{payload['offsets_deg']['psi0']:.4f} deg, branch {payload['branch']:+d}, {payload['grashof']['class']}")
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
    method: Annotated[str, typer.Option("--method", help="q (the seed's), precision, lsq, minimax, or all "
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
    pick: Annotated[str, typer.Option("--pick", help="q, the seed's last step: centre of the Q rectangle, or "
                                      "search it for the least deviation.")] = "centre",
    seed: Annotated[int, typer.Option("--seed", help="q: random shift of the scan grid.")] = 0,
    max_error: Annotated[float | None, typer.Option("--max-error", help="Also check the largest error "
                                                       "(deg).")] = None,
    output: OutOpt = None,
    no_plots: NoPlotsOpt = False,
    as_json: JsonOpt = False,
) -> None:
    """Synthesise a four-bar function generator y = f(x); exit 1 when a check (transmission angle, link ratio,
    branch, --max-error) fails (--method all compares and exits 0)."""
    from camcad.linkage.expr import parse_expression
    from camcad.linkage.fgen import Limits
    from camcad.linkage.synthesis import METHODS, FgenOptions, report, synthesize
    from camcad.linkage.target import make_target, target_from_table
    from camcad.report.linkage import write_fgen_outputs
    from camcad.cli.common import parse_pair

    if (function is None) == (table is None):
        raise CamcadError("give the function either as --function or as --table", "command line",
                          'e.g. --function "log10(x)" --x 1:2')
    for option, value in (("--input-range", input_range), ("--output-range", output_range)):
        if value is None:
            raise CamcadError("missing", option, f"give {option} DEG (the link's turn over the interval)")
    methods = list(METHODS) if method == "all" else [method]
    if method != "all" and method not in METHODS:
        raise CamcadError(f"unknown method {method!r}", "--method", f"use one of {', '.join(METHODS)} or all")
    if function is not None:
        if x is None:
            raise CamcadError("missing", "--x", "give the interval of x, e.g. --x 1:2")
        x0, x1 = parse_pair(x, "--x", "1:2")
        expression = parse_expression(function)
        target = make_target(expression, x0, x1, input_range, output_range, function, expression.derivative)
    else:
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
