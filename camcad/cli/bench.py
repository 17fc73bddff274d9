"""`camcad bench`: speed against error of camcad's kernels, from the package (camcad.bench)."""

from __future__ import annotations

from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.common import JsonOpt, NoPlotsOpt, OutOpt, console, print_json


@app.command()
def bench(quick: Annotated[bool, typer.Option("--quick", help="Fewer settings and repeats (under a minute).")] = False,
          only: Annotated[str | None, typer.Option(
              "--only", help="Comma-separated benchmark names: kernels, sweeps, startup (installed with camcad), "
                             "a source checkout's benchmarks/ (balance, profile, …), or all.")] = None,
          output: OutOpt = None, no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Time and error of every kernel against its numpy floor and a fair peer.

    CPU time in one run, each error against an independent reference named in every row; sweeps' designs per
    second per core and whole commands against their import floors too. Writes bench.md, bench.json and
    bench.png."""
    import contextlib
    from pathlib import Path

    from camcad.report.bench import BenchRequest, run_bench

    names = None if only is None else tuple(n.strip() for n in only.split(",") if n.strip())
    request = BenchRequest(quick, names, output, not no_plots)
    status = console(stderr=True).status("benchmarks") if not as_json else contextlib.nullcontext()
    with status as bar:
        report = run_bench(request, None if bar is None else bar.update)
    if as_json:
        print_json(report.to_dict())
        raise typer.Exit(report.exit_code)
    typer.echo(report.markdown())
    typer.echo("written: " + ", ".join(str(Path(p)) for p in report.outputs))
    raise typer.Exit(report.exit_code)
