"""`camcad bench`: speed against error for every numerical kernel, from the benchmarks in benchmarks/."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.common import JsonOpt, NoPlotsOpt, OutOpt, console, output_dir, print_json


@app.command()
def bench(quick: Annotated[bool, typer.Option("--quick", help="Fewer settings and repeats (under a minute).")] = False,
          only: Annotated[str | None, typer.Option(
              "--only", help="Comma-separated benchmark names, e.g. balance,profile.")] = None,
          output: OutOpt = None, no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Time and error of every kernel (method, setting, median time, error against a reference); writes
    bench.md, bench.json and bench.png."""
    import contextlib
    import io

    from camcad.errors import CamcadError
    from camcad.io.atomic import write_text_atomic
    from camcad.io.jsonout import write_json
    from camcad.report.bench import find_benchmarks, load_benchmark, markdown_table, plot_speed_error

    found = find_benchmarks()
    if only:
        wanted = [name.strip() for name in only.split(",") if name.strip()]
        unknown = [name for name in wanted if name not in found]
        if unknown:
            raise CamcadError(f"no benchmark named {unknown[0]!r}", "--only", f"choose from {', '.join(found)}")
        found = {name: found[name] for name in wanted}
    rows: list[dict] = []
    status = console(stderr=True).status("benchmarks") if not as_json else contextlib.nullcontext()
    with status as bar:
        for name, path in found.items():
            if bar is not None:
                bar.update(f"camcad bench: {name}{' (quick)' if quick else ''}")
            module = load_benchmark(name, path)
            with contextlib.redirect_stdout(io.StringIO()):  # the benchmarks' own printing is for their CLI
                for row in module.run(quick):
                    rows.append({"benchmark": name, **row})
    out_dir = output_dir(output, "bench")
    outputs = [write_text_atomic(out_dir / "bench.md", markdown_table(rows, quick)),
               write_json(out_dir / "bench.json", rows)]
    if not no_plots:
        outputs.append(plot_speed_error(rows, out_dir / "bench.png"))
    payload = {"quick": quick, "rows": rows, "outputs": [str(p) for p in outputs]}
    if as_json:
        print_json(payload)
        return
    typer.echo(markdown_table(rows, quick))
    typer.echo("written: " + ", ".join(str(Path(p)) for p in outputs))
