"""Options and output shared by the analysis commands (spectrum, dynamics, impact, contact, cyclogram)."""

from __future__ import annotations

from typing import Annotated

import typer

UnitOpt = Annotated[str | None, typer.Option(
    "--unit", help="Unit of the law's displacement: mm (translating follower), rad or deg (oscillating); "
                   "default mm for a law file, from the scene for a scene.")]
PhaseAnglesOpt = Annotated[str, typer.Option(
    "--phase-angles", help="Which phase angles to analyse in a scene with a [cyclogram]: cyclogram (the optimised "
                           "ones, as camcad profile uses them; the default, auto) or law (the law's own).")]


def emit(run, as_json: bool) -> None:
    """Print a CommandRun (one JSON object with --json, else its text) and exit with its code (0 passed, 1 not)."""
    from camcad.cli.common import console, print_json

    if as_json:
        print_json(run.payload)
    else:
        out = console()
        for line in run.text():
            out.print(line, soft_wrap=True)
    raise typer.Exit(run.exit_code)


def progress(enabled: bool, label: str):
    """(callback(done, total), close): a progress bar on stderr that learns its total from the callback;
    (None, no-op) when disabled (e.g. with --json)."""
    if not enabled:
        return None, lambda: None
    shown: list = []        # the bar, made at the first report of more than one step (rich.progress only then)

    def callback(done: int, total: int) -> None:
        if not shown:
            if total <= 1:
                return
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

            from camcad.cli.common import console

            bar = Progress(TextColumn(label), BarColumn(), MofNCompleteColumn(), TimeRemainingColumn(),
                           console=console(stderr=True), transient=True)
            shown.append((bar, bar.add_task(label, total=None)))
            bar.start()
        bar, task = shown[0]
        bar.update(task, completed=done, total=total)

    return callback, lambda: shown[0][0].stop() if shown else None
