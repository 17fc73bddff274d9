"""`camcad check` and `camcad fix`: parse the options, call ``balance.fixing.check_law`` / ``fix_law``, print."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.common import (
    CycleOpt,
    HandleOpt,
    JsonOpt,
    LawArg,
    LayerOpt,
    LiftOpt,
    OriginOpt,
    PhasesOpt,
    X0Opt,
    XDegOpt,
    Y0Opt,
    load_law_from_options,
    parse_pair,
    print_json,
)

TolOpt = Annotated[float, typer.Option("--tol", help="Closure tolerance, as a fraction of the rise.")]


def _show(report, as_json: bool) -> None:
    if as_json:
        print_json(report.to_dict())
    else:
        print(report.to_text())
    raise typer.Exit(report.exit_code)


@app.command()
def check(law_file: LawArg, layer: LayerOpt = None, handle: HandleOpt = None, cycle: CycleOpt = 360.0,
          lift: LiftOpt = None, phases: PhasesOpt = None, x_deg: XDegOpt = False, y0: Y0Opt = None, x0: X0Opt = None,
          origin: OriginOpt = None, tol: TolOpt = 1e-5,
          plot: Annotated[Path | None, typer.Option("--plot", help="Write a PNG of a, v, s with the areas.")] = None,
          trapezoid: Annotated[bool, typer.Option(
              "--trapezoid",
              help="Also check as Dupliak & Kotsiyba 2018 do: resample with --step, trapezoidal rule.")] = False,
          step: Annotated[float, typer.Option("--step", help="Resampling step of --trapezoid (deg).")] = 0.1,
          follower: Annotated[str | None, typer.Option(
              "--follower", help="The follower of a radius-vector table (r_mm): roller, knife or oscillating.")] = None,
          rr: Annotated[float | None, typer.Option("--rr", help="Roller radius of --follower (mm).")] = None,
          offset: Annotated[float, typer.Option("--offset", help="Offset of a translating --follower (mm).")] = 0.0,
          pivot: Annotated[float | None, typer.Option("--pivot", help="Pivot distance C (mm).")] = None,
          arm: Annotated[float | None, typer.Option("--arm", help="Arm length L (mm).")] = None,
          cw: Annotated[bool, typer.Option("--cw", help="The cam of a radius table turns clockwise.")] = False,
          smoothing: Annotated[float | None, typer.Option(
              "--smoothing", help="A motion table's measurement error (its unit); default: chosen by GCV.")] = None,
          accel_smoothing: Annotated[str, typer.Option(
              "--accel-smoothing", help="A motion table's a re-smoothed by a cubic spline: gcv or none.")] = "gcv",
          as_json: JsonOpt = False) -> None:
    """Check the area balance of an acceleration law (exit 0 balanced, 1 not, 2 bad input); exact integration,
    and with --trapezoid the resample-and-trapezoid check of Dupliak & Kotsiyba 2018 beside it."""
    from camcad.balance.fixing import check_law, check_plot_output
    from camcad.law.motion_table import follower_from_options

    check_plot_output(plot, law_file)   # before anything is read or written
    table_follower = follower_from_options(follower, rr, offset, pivot, arm, cw)
    loaded = load_law_from_options(law_file, layer, handle, cycle, lift, phases, x_deg, y0, x0, origin,
                                   follower=table_follower, smoothing=smoothing, accel_smoothing=accel_smoothing)
    report = check_law(loaded, tol, trapezoid=trapezoid, step_deg=step)
    if plot is not None:
        from camcad.report.balance import plot_balance

        report.plot = str(plot_balance(loaded.law, report.balance, plot, title=law_file.name))
    _show(report, as_json)


@app.command()
def fix(law_file: LawArg,
        output: Annotated[Path | None, typer.Option(
            "-o", "--output", help="Corrected file (default <name>.fixed.dxf).")] = None,
        mode: Annotated[str, typer.Option("--mode", help="min-change | extrema | extrema-resample | keypoints | "
                                                         "segment | phase | phase-keypoints")] = "min-change",
        method: Annotated[str, typer.Option(
            "--method", help="exact (linear solve) or iterate (resample, integrate, move the key points and repeat, as "
                              "Dupliak & Kotsiyba 2018 do).")] = "exact",
        step: Annotated[float, typer.Option(
            "--step", help="Resampling step of iterate and extrema-resample (deg).")] = 0.1,
        segment: Annotated[str | None, typer.Option(
            "--segment", help="A:B, the angle range mode segment may change (deg).")] = None,
        move: Annotated[list[str] | None, typer.Option(
            "--move",
            help="X:Y, set the point at X deg to a = Y (input units) and rebalance the rest; repeat for several "
                 "points.")] = None,
        max_stretch: Annotated[float, typer.Option(
            "--max-stretch", help="Largest phase stretch of phase-keypoints (fraction).")] = 0.05,
        free_lift: Annotated[bool, typer.Option(
            "--free-lift", help="Let the rise change (by default the drawn rise, or --lift, is kept).")] = False,
        force: Annotated[bool, typer.Option(
            "--force", help="Write a copy even when the law is already balanced.")] = False,
        layer: LayerOpt = None, handle: HandleOpt = None, cycle: CycleOpt = 360.0, lift: LiftOpt = None,
        phases: PhasesOpt = None, x_deg: XDegOpt = False, y0: Y0Opt = None, x0: X0Opt = None,
        origin: OriginOpt = None, tol: TolOpt = 1e-5,
        no_plots: Annotated[bool, typer.Option("--no-plots", help="Do not write the PNG beside the output.")] = False,
        as_json: JsonOpt = False) -> None:
    """Correct an unbalanced law with the least change (keeping the drawn rise) and write a corrected copy of
    the drawing; a law already balanced is left alone (exit 0, nothing written)."""
    from camcad.balance.fixing import fix_law, plot_path

    loaded = load_law_from_options(law_file, layer, handle, cycle, lift, phases, x_deg, y0, x0, origin)
    segment_deg = parse_pair(segment, "--segment", "60:180") if segment else None
    moves = [parse_pair(text, "--move", "75:12.5") for text in (move or [])]
    report = fix_law(loaded, mode, output=output, tol=tol, method=method, step_deg=step, segment_deg=segment_deg,
                     moves=moves, max_stretch=max_stretch, free_lift=free_lift, force=force, plot=not no_plots)
    if report.output is not None and not no_plots:
        from camcad.report.balance import plot_balance

        c = report.correction
        report.plot = str(plot_balance(loaded.law, c.before, plot_path(report.output), corrected=c.law,
                                       after=c.after, title=f"{law_file.name}, fix --mode {mode}"))
    _show(report, as_json)
