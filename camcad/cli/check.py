"""`camcad check` and `camcad fix`: the area balance of a drawn law, and its correction."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Optional

import typer

from camcad.cli import app
from camcad.cli.common import (CycleOpt, HandleOpt, JsonOpt, LawArg, LayerOpt, LiftOpt, OriginOpt, PhasesOpt, X0Opt,
                               XDegOpt, Y0Opt, console, load_law_from_options, parse_pair, print_json)

TolOpt = Annotated[float, typer.Option("--tol", help="Closure tolerance, as a fraction of the rise.")]


@app.command()
def check(law_file: LawArg, layer: LayerOpt = None, handle: HandleOpt = None, cycle: CycleOpt = 360.0,
          lift: LiftOpt = None, phases: PhasesOpt = None, x_deg: XDegOpt = False, y0: Y0Opt = None, x0: X0Opt = None,
          origin: OriginOpt = None, tol: TolOpt = 1e-5,
          plot: Annotated[Optional[Path], typer.Option("--plot", help="Write a PNG of a, v, s with the areas.")] = None,
          trapezoid: Annotated[bool, typer.Option("--trapezoid", help="Also check by the source's method: resample with --step, trapezoidal rule.")] = False,
          step: Annotated[float, typer.Option("--step", help="Resampling step of --trapezoid (deg).")] = 0.1,
          as_json: JsonOpt = False) -> None:
    """Check the area balance of an acceleration law (exit 0 balanced, 1 not, 2 bad input); exact integration,
    and with --trapezoid the source's resample-and-trapezoid check beside it."""
    from camcad.balance.checking import check as balance_check
    from camcad.balance.checking import check_by_trapezoid

    loaded = load_law_from_options(law_file, layer, handle, cycle, lift, phases, x_deg, y0, x0, origin)
    report = balance_check(loaded.law, tol)
    payload = {"source": loaded.source, "notes": list(loaded.notes), **report.to_dict()}
    if trapezoid:
        payload["trapezoid"] = check_by_trapezoid(loaded.law, tol, step)
    if plot is not None:
        from camcad.report.balance import plot_balance

        payload["plot"] = str(plot_balance(loaded.law, report, plot, title=law_file.name))
    if as_json:
        print_json(payload)
    else:
        _print_report(payload, loaded)
    raise typer.Exit(0 if report.balanced else 1)


@app.command()
def fix(law_file: LawArg,
        output: Annotated[Optional[Path], typer.Option("-o", "--output", help="Corrected file (default <name>.fixed.dxf).")] = None,
        mode: Annotated[str, typer.Option("--mode", help="min-change | extrema | extrema-resample | keypoints | "
                                                         "segment | phase | phase-keypoints")] = "min-change",
        method: Annotated[str, typer.Option("--method", help="exact (linear solve) or iterate (the source's loop).")] = "exact",
        step: Annotated[float, typer.Option("--step", help="Resampling step of iterate and extrema-resample (deg).")] = 0.1,
        segment: Annotated[Optional[str], typer.Option("--segment", help="A:B, the angle range mode segment may change (deg).")] = None,
        move: Annotated[Optional[str], typer.Option("--move", help="X:Y, set the point at X deg to a = Y (input units) and rebalance the rest.")] = None,
        max_stretch: Annotated[float, typer.Option("--max-stretch", help="Largest phase stretch of phase-keypoints (fraction).")] = 0.05,
        layer: LayerOpt = None, handle: HandleOpt = None, cycle: CycleOpt = 360.0, lift: LiftOpt = None,
        phases: PhasesOpt = None, x_deg: XDegOpt = False, y0: Y0Opt = None, x0: X0Opt = None,
        origin: OriginOpt = None, tol: TolOpt = 1e-5,
        no_plots: Annotated[bool, typer.Option("--no-plots", help="Do not write the PNG beside the output.")] = False,
        as_json: JsonOpt = False) -> None:
    """Correct an unbalanced law with the smallest change and write a corrected copy of the drawing."""
    from camcad.balance.correction import correct
    from camcad.errors import CamcadError

    loaded = load_law_from_options(law_file, layer, handle, cycle, lift, phases, x_deg, y0, x0, origin)
    segment_deg = parse_pair(segment, "--segment", "60:180") if segment else None
    move_pair = parse_pair(move, "--move", "75:12.5") if move else None
    if move_pair is not None:
        move_pair = (move_pair[0], move_pair[1] * loaded.y_scale)  # input units -> law units
    out = output or law_file.with_name(law_file.stem + ".fixed" + (law_file.suffix if loaded.curve is None
                                                                    else ".dxf"))
    if out.resolve() == law_file.resolve():
        raise CamcadError("the output would overwrite the input", str(out), "give another name with -o")
    result = correct(loaded.law, mode, tol=tol, method=method, step_deg=step, segment_deg=segment_deg,
                     move=move_pair, max_stretch=max_stretch, where=str(law_file))
    from camcad.io.law_write import write_corrected

    written, notes = write_corrected(loaded, result.law, out, resampled=result.resampled)
    payload = {
        "source": loaded.source, "notes": list(loaded.notes) + list(result.notes) + notes,
        **result.before.to_dict(),
        "mode": mode, "method": method, "output": str(written),
        "max_change": result.max_change / loaded.y_scale, "rms_change": result.rms_change / loaded.y_scale,
        "iterations": result.iterations, "resampled": result.resampled,
        "after": result.after.to_dict(),
    }
    if not no_plots:
        from camcad.report.balance import plot_balance

        payload["plot"] = str(plot_balance(loaded.law, result.before, written.with_suffix(".png"),
                                           corrected=result.law, after=result.after,
                                           title=f"{law_file.name}, fix --mode {mode}"))
    if as_json:
        print_json(payload)
    else:
        _print_report(payload, loaded, fixed=True)
    raise typer.Exit(0 if result.after.balanced else 1)


def _print_report(payload: dict, loaded, fixed: bool = False) -> None:
    from rich.table import Table

    out = console()
    out.print(f"{payload['source']}")
    for note in payload["notes"]:
        out.print(f"  note: {note}")
    phase_table = Table(title="phases", show_lines=False)
    for column in ("phase", "from (deg)", "to (deg)", "area + (mm/rad)", "area - (mm/rad)", "v at end (mm/rad)",
                   "displacement (mm)"):
        phase_table.add_column(column, justify="right")
    for row in payload["phases"]:
        phase_table.add_row(row["kind"], f"{row['start_deg']:.4f}", f"{row['end_deg']:.4f}",
                            f"{row['area_positive']:.6g}", f"{row['area_negative']:.6g}", f"{row['v_end']:.3e}",
                            f"{row['displacement']:.6g}")
    out.print(phase_table)
    closures = Table(title="balance conditions" + (" (before -> after)" if fixed else ""))
    closures.add_column("condition")
    closures.add_column("residual", justify="right")
    if fixed:
        closures.add_column("after", justify="right")
    after = payload.get("after", {}).get("conditions", [])
    for i, cond in enumerate(payload["conditions"]):
        cells = [cond["name"], f"{cond['residual']:.3e}"]
        if fixed:
            cells.append(f"{after[i]['residual']:.3e}" if i < len(after) else "")
        closures.add_row(*cells)
    out.print(closures)
    out.print(f"rise {payload['rise']:.6g} mm, return {payload['return']:.6g} mm, tolerance {payload['tolerance_abs']:.3g} "
              f"(= {payload['tolerance']:g} x rise)")
    if "trapezoid" in payload:
        trap = payload["trapezoid"]
        out.print(f"source's method (trapezoid, step {trap['step_deg']:g} deg): residuals "
                  + ", ".join(f"{r:.3e}" for r in trap["residuals"])
                  + f"; differs from exact by up to {max(abs(e) for e in trap['error_vs_exact']):.2e}; "
                  + ("balanced" if trap["balanced"] else "not balanced"))
    if fixed:
        verdict = "balanced" if payload["after"]["balanced"] else "STILL NOT balanced"
        out.print(f"mode {payload['mode']} ({payload['method']}): max change {payload['max_change']:.4g}, "
                  f"RMS change {payload['rms_change']:.4g} (input y units); {verdict}")
        out.print(f"written: {payload['output']}" + (f", plot {payload['plot']}" if payload.get("plot") else ""))
    else:
        verdict = "balanced" if payload["balanced"] else "NOT balanced: run camcad fix"
        out.print(verdict)
        if payload.get("plot"):
            out.print(f"plot: {payload['plot']}")
