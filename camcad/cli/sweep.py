"""`camcad sweep`: explore a design space — a scene's keys over ranges, lists and distributions.

Thin: the options become a ``camcad.report.sweep_command.SweepRequest``, ``run_sweep`` computes and writes,
and the report is printed (text or --json). Every design runs the scene's models (only those the scene has,
checks only: no files) on a local pool of processes or a Dask cluster; the rows stream to Parquet chunks under
-o (``--resume`` completes an interrupted sweep); then the feasible region, the Pareto front, the best design
as a scene (run through ``camcad profile``) and report.json with counts, timings and throughput. Exit 0 when a
feasible design was found, 1 when none was, 2 for bad input, 3 when a design hit an internal error (its row
says which), 130 when stopped.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.common import JsonOpt, NoPlotsOpt, print_json

VaryOpt = Annotated[list[str], typer.Option(
    "--vary", help="KEY=SPEC, repeatable. KEY: a scene key (follower.base_radius, law.standard, machine.rpm, "
                   "contact.width, law.phases.rise for a phase angle; mechanisms.NAME.follower.base_radius in a "
                   "group). SPEC: a range A:B:STEP, a list a,b,c, or normal(mu,sigma) / uniform(a,b) with --samples.",
    show_default=False)]


@app.command()
def sweep(
    scene: Annotated[Path | None, typer.Argument(
        help="Scene file (TOML); none: the built-in default design.", show_default=False)] = None,
    vary: VaryOpt = None,  # type: ignore[assignment]
    samples: Annotated[int | None, typer.Option(
        "--samples", help="Draws of the distribution keys per grid point (Monte-Carlo).")] = None,
    seed: Annotated[int, typer.Option(
        "--seed", help="Random-number seed of the draws (the same seed, the same draws).")] = 0,
    objective: Annotated[list[str] | None, typer.Option(
        "--objective", help="min:COLUMN or max:COLUMN, repeatable, in order of priority: a varied key, "
                            "min_margin_ratio, or a check's figure (\"pressure angle, rise.margin\"). Default: "
                            "min of the first varied key (a base radius first), then max:min_margin_ratio.",
        show_default=False)] = None,
    scheduler: Annotated[str | None, typer.Option(
        "--scheduler", help="Run on a Dask cluster: tcp://HOST:PORT of its scheduler, or its scheduler file.",
        show_default=False)] = None,
    workers: Annotated[int | None, typer.Option(
        "--workers", help="Processes of the local pool (default: every core; 1 runs in this process).",
        show_default=False)] = None,
    chunk: Annotated[int | None, typer.Option(
        "--chunk", help="Designs per task (default: about 0.5 s of work, at least 4 tasks per worker).",
        show_default=False)] = None,
    output: Annotated[Path | None, typer.Option(
        "-o", "--output", help="Output folder (default ./camcad-out/<scene>-sweep/).", show_default=False)] = None,
    resume: Annotated[bool, typer.Option("--resume", help="Complete the sweep already in the output folder.")] = False,
    plot: Annotated[str | None, typer.Option(
        "--plot", help="KEY_X,KEY_Y: the keys on the axes of the feasible-region plot (default: the first two "
                       "numeric keys).", show_default=False)] = None,
    connect_timeout: Annotated[float, typer.Option(
        "--connect-timeout", help="Seconds to wait for the Dask scheduler and its first worker.")] = 10.0,
    no_best: Annotated[bool, typer.Option("--no-best", help="Do not run the best design through camcad profile.")
                       ] = False,
    no_plots: NoPlotsOpt = False,
    as_json: JsonOpt = False,
    stop_after_chunks: Annotated[int | None, typer.Option("--stop-after-chunks", hidden=True)] = None,
) -> None:
    """Explore a design space: every design of the --vary grid (and draws) through the scene's checks, on a
    local pool or a Dask cluster; Parquet results, feasible region, Pareto front, best design. Exit 0 if a
    feasible design was found, 1 if none."""
    from camcad.report.sweep_command import SweepRequest, run_sweep

    progress, close = _progress_bar(not as_json)
    request = SweepRequest(scene=scene, vary=tuple(vary or ()), samples=samples, seed=seed,
                           objectives=tuple(objective or ()), scheduler=scheduler, workers=workers, chunk=chunk,
                           output=output, resume=resume, plot=plot, connect_timeout=connect_timeout,
                           run_best=not no_best, plots=not no_plots, stop_after_chunks=stop_after_chunks,
                           progress=progress)
    try:
        report = run_sweep(request)
    finally:
        close()
    if report.stopped is None and as_json:
        print_json(report.to_dict())
    elif report.stopped is None:
        print("\n".join(report.lines()))
    for line in report.errors():
        typer.echo(f"camcad: {line}", err=True)
    raise typer.Exit(report.exit_code)


def _progress_bar(enabled: bool):
    """A rich progress bar on stderr (designs, rate, ETA) as (callback, close), made at the first report (its
    total from it) and closed when every design is done; no-ops when not shown."""
    import sys

    if not enabled or not sys.stderr.isatty():
        return None, lambda: None
    shown: list = []

    def close() -> None:
        while shown:
            shown.pop()[0].stop()

    def update(done: int, total: int, computed: int, seconds: float) -> None:
        if not shown:
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeElapsedColumn,
                TimeRemainingColumn,
            )

            from camcad.cli.common import console

            bar = Progress(TextColumn("camcad sweep"), BarColumn(), MofNCompleteColumn(),
                           TextColumn("{task.fields[rate]}"), TimeElapsedColumn(), TextColumn("ETA"),
                           TimeRemainingColumn(), console=console(stderr=True), transient=True)
            shown.append((bar, bar.add_task("sweep", total=total, rate="")))
            bar.start()
        rate = f"{computed / seconds:.3g} designs/s" if seconds > 0 and computed else ""
        shown[0][0].update(shown[0][1], completed=done, rate=rate)
        if done >= total:
            close()

    return update, close
