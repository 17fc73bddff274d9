"""`camcad edit`: the graphical point editor of a drawn acceleration law (window, browser, or a script)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.common import (
    CycleOpt,
    HandleOpt,
    JsonOpt,
    LayerOpt,
    LiftOpt,
    PhasesOpt,
    ReturnStandardOpt,
    SourceArg,
    StandardOpt,
    XDegOpt,
    console,
    print_json,
    resolve_source,
)


@app.command()
def edit(law_file: SourceArg = None,
         web: Annotated[bool, typer.Option(
             "--web", help="Open the editor in a browser (served on 127.0.0.1 only).")] = False,
         port: Annotated[int, typer.Option("--port", help="Port of the browser editor (0: a free one).")] = 0,
         no_browser: Annotated[bool, typer.Option(
             "--no-browser", help="Print the URL, do not open a browser.")] = False,
         output: Annotated[Path | None, typer.Option(
             "-o", "--output",
             help="Where to save (.dxf drawing, .csv table, .json script); default <name>.edited.dxf.")] = None,
         script: Annotated[Path | None, typer.Option(
             "--script", help="Replay this JSON list of operations headless, then save.")] = None,
         tol: Annotated[float, typer.Option("--tol", help="Closure tolerance, as a fraction of the rise.")] = 1e-5,
         step: Annotated[float, typer.Option("--step", help="Sampling step of a --standard law (deg).")] = 0.5,
         standard: StandardOpt = None, return_standard: ReturnStandardOpt = None,
         layer: LayerOpt = None, handle: HandleOpt = None, cycle: CycleOpt = 360.0, lift: LiftOpt = None,
         phases: PhasesOpt = None, x_deg: XDegOpt = False, as_json: JsonOpt = False) -> None:
    """Edit a drawn acceleration law by hand: drag points, lobes and phase boundaries, watch the areas
    balance and the profile close, preview and accept fix's corrections, save the drawing as fix does.
    With --script, replay the edits headless (exit 0 when the final law is balanced, 1 when not)."""
    from camcad.edit.app import make_session, run_editor

    if web and script is None:
        from camcad.edit.web import require_tornado

        require_tornado()
    source = resolve_source(law_file, standard, return_standard, phases, lift, layer, handle, cycle, x_deg, None)
    input_path = law_file if law_file is not None and source.loaded is not None and \
        law_file.suffix.lower() != ".toml" else None
    session = make_session(source.loaded if source.loaded is not None else source.law, name=source.name,
                           input_path=input_path if input_path is not None else
                           (source.loaded.path if source.loaded is not None else None),
                           tol=tol, notes=source.notes, step_deg=step)
    outcome = run_editor(session, script=script, output=output, web=web, port=port, open_browser=not no_browser,
                         announce=lambda text: typer.echo(text, err=as_json),
                         inputs=source.scene.input_files() if source.scene is not None else ())
    payload = outcome.payload
    if as_json:
        print_json(payload)
    else:
        out = console()
        verdict = "the profile closes" if payload["balanced"] else \
            f"the profile does not close (gap {payload['displacement_closure']:.3g} mm)"
        out.print(f"{payload['operations']} operations applied; {verdict}; max change {payload['max_change']:.4g}, "
                  f"RMS change {payload['rms_change']:.4g} (input y units)")
        for path in payload["outputs"]:
            out.print(f"written: {path}")
    raise typer.Exit(0 if outcome.balanced else 1)
