"""`camcad sweep`: explore a design space — a scene's keys over ranges, lists and distributions.

Every design runs the scene's models (only those the scene has, checks only: no files) on a local pool of
processes or a Dask cluster; the rows stream to Parquet chunks under -o (``--resume`` completes an interrupted
sweep); then the feasible region, the Pareto front, the best design as a scene (run through ``camcad
profile``) and report.json with counts, timings and throughput. Exit 0 when a feasible design was found, 1
when none was, 2 for bad input, 3 when a design hit an internal error (its row says which), 130 when stopped.
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
    no_best: Annotated[bool, typer.Option("--no-best", help="Do not run the best design through camcad profile.")]
    = False,
    no_plots: NoPlotsOpt = False,
    as_json: JsonOpt = False,
    stop_after_chunks: Annotated[int | None, typer.Option("--stop-after-chunks", hidden=True)] = None,
) -> None:
    """Explore a design space: every design of the --vary grid (and draws) through the scene's checks, on a
    local pool or a Dask cluster; Parquet results, feasible region, Pareto front, best design. Exit 0 if a
    feasible design was found, 1 if none."""
    from camcad.errors import CamcadError
    from camcad.io.output_folder import OutputFolder, safe_name
    from camcad.sweep import analysis, store
    from camcad.sweep.engine import make_engine
    from camcad.sweep.run import load_scene_tables, prepare_sweep, run_sweep, sized

    store.require_pyarrow()
    tables, name, base_dir, inputs = load_scene_tables(scene)
    plan = prepare_sweep(tables, name, base_dir, list(vary or []), samples, seed)
    space = _space(plan)
    names = list(plan.first_row) + ["min_margin_ratio"]
    objectives = ([analysis.parse_objective(text, names) for text in objective] if objective
                  else analysis.default_objectives(plan.keys))
    plot_axes = None
    if plot is not None:
        parts = [p.strip() for p in plot.split(",")]
        if len(parts) != 2:
            raise CamcadError(f"{plot[:60]!r} is not KEY_X,KEY_Y", "--plot", "give two varied keys, e.g. "
                              "--plot law.phases.rise,follower.base_radius")
        plot_axes = analysis.region_axes(space, (parts[0], parts[1]))
    stem = Path(name).stem if scene is not None else "default"
    folder = output if output is not None else Path("camcad-out") / f"{safe_name(stem)}-sweep"
    with OutputFolder(folder, inputs) as out:
        out.plan(OUTPUT_FILES, folders=OUTPUT_FOLDERS)  # a clash with an input is refused before any work
        if resume and chunk is None:
            found = store.read_manifest(out.folder)
            if found is not None:
                chunk = int(found["chunk_designs"])
        with make_engine(workers, scheduler, connect_timeout) as engine:
            plan = sized(plan, engine.workers, chunk)
            show = not as_json
            progress, close = _progress_bar(show, plan.designs)
            try:
                stats = run_sweep(plan, out.folder, engine, resume=resume, progress=progress,
                                  stop_after_chunks=stop_after_chunks, out=out)
            except KeyboardInterrupt:
                close()
                typer.echo(f"camcad: error: interrupted; the chunks written are kept: rerun with --resume to "
                           f"complete the sweep in {out.folder}", err=True)
                raise typer.Exit(130) from None
            finally:
                close()
        if stats.stopped:
            typer.echo(f"camcad: error: stopped after {stats.chunks_computed} chunks (--stop-after-chunks); "
                       f"rerun with --resume to complete the sweep in {out.folder}", err=True)
            raise typer.Exit(130)
        from camcad.report.sweep import sweep_outputs

        found = sweep_outputs(out.folder, plan, tables, base_dir, objectives, plot_axes, plots=not no_plots,
                              run_best=not no_best, out=out)
        report = {"scene": str(scene) if scene is not None else name, "vary": list(plan.task.vary),
                  "samples": plan.task.samples, "seed": plan.task.seed, "designs": plan.designs, **found,
                  "results": str(out.path(store.RESULTS)), "manifest": str(out.path(store.MANIFEST))}
        report = _write_reports(out, report, {"chunks": plan.chunks, "chunk_designs": plan.chunk_designs,
                                              "throughput": stats.as_dict()})
    if as_json:
        print_json(report)
    else:
        _print(report)
    counts = report["counts"]
    if counts["internal_errors"]:
        first = counts["errors"]["internal error"][0]["error"] if counts["errors"]["internal error"] else ""
        typer.echo(f"camcad: internal error in {counts['internal_errors']} designs (first: {first[:120]}) - please "
                   "report it; their rows say which", err=True)
        raise typer.Exit(3)
    raise typer.Exit(0 if counts["feasible"] else 1)


#: every file the sweep writes into its folder, and the folders it fills
OUTPUT_FILES = ("sweep.json", "report.json", "throughput.json", "best.toml", "region.png", "pareto.png", "pareto.csv")
OUTPUT_FOLDERS = ("results", "best")


def _write_reports(out, report: dict, run: dict) -> dict:
    """report.json (what the sweep found: the same bytes for the same sweep) and throughput.json (how this run
    went: chunking, engine, timings); returns both merged, the --json payload."""
    from camcad.io.jsonout import write_json

    run_path, report_path = out.path("throughput.json"), out.path("report.json")
    report["outputs"] = [*report["outputs"], str(run_path), str(report_path)]
    write_json(run_path, run)
    write_json(report_path, report)
    return {**report, **run}


def _space(plan):
    from camcad.sweep.evaluate import prepared

    return prepared(plan.task).space


def _progress_bar(enabled: bool, total: int):
    """A rich progress bar on stderr (designs, rate, ETA) as (callback, close); no-ops when not shown."""
    import sys

    if not enabled or not sys.stderr.isatty():
        return None, lambda: None
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    from camcad.cli.common import console

    bar = Progress(TextColumn("camcad sweep"), BarColumn(), MofNCompleteColumn(), TextColumn("{task.fields[rate]}"),
                   TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn(), console=console(stderr=True),
                   transient=True)
    task = bar.add_task("sweep", total=total, rate="")
    bar.start()

    def update(done: int, _total: int, computed: int, seconds: float) -> None:
        rate = f"{computed / seconds:.3g} designs/s" if seconds > 0 and computed else ""
        bar.update(task, completed=done, rate=rate)

    return update, bar.stop


def _print(report: dict) -> None:
    counts, speed = report["counts"], report["throughput"]
    print(f"camcad sweep: {counts['designs']} designs, {counts['feasible']} feasible, {counts['infeasible']} "
          f"infeasible, {counts['bad_input']} refused (bad input), {counts['internal_errors']} internal errors")
    if counts.get("grid_points") is not None:
        print(f"  grid points feasible in every draw: {counts['grid_points_feasible_in_every_draw']} of "
              f"{counts['grid_points']}")
    for check, count in list(counts["failed_by"].items())[:6]:
        print(f"  failed {check}: {count}")
    for kind in ("bad input", "internal error"):
        for item in counts["errors"].get(kind, [])[:2]:
            print(f"  {kind} ({item['designs']} designs): {item['error'][:150]}")
    if speed["designs_computed"]:
        rate = speed["designs_per_s"] or 0.0
        per_cpu = speed["designs_per_cpu_s"] or 0.0
        print(f"  computed {speed['designs_computed']} designs in {speed['wall_s']:.3g} s on {speed['workers']} "
              f"{speed['engine']} workers: {rate:.3g} designs/s ({rate / max(speed['workers'], 1):.3g} per worker); "
              f"{per_cpu:.3g} designs per CPU-second")
    if speed["chunks_on_disk_before"]:
        print(f"  resumed: {speed['chunks_on_disk_before']} of {speed['chunks']} chunks were on disk")
    best = report.get("best")
    if best:
        values = ", ".join(f"{k} = {v}" for k, v in best["values"].items())
        print(f"  best ({', '.join(report['objectives'])}): design {best['design']}: {values}; governing "
              f"{best['governing']}")
        if "profile" in best:
            print(f"  best design through camcad profile: {'passed' if best['profile']['passed'] else 'FAILED'} "
                  f"-> {best['profile']['folder']}")
    else:
        print("  no feasible design")
    count = report["pareto"]["designs"]
    print(f"  Pareto front: {count} design{'' if count == 1 else 's'}")
    print("written: " + ", ".join(report["outputs"]))
