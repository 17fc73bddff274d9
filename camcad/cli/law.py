"""`camcad law`: design a motion (segments or standard shapes) and write it as a drawing, a table and plots.

Thin: the options become a ``camcad.report.law.LawRequest``, ``run_law`` designs, draws and writes, and the run
is printed (text or --json). ``--list`` prints the VDI 2143 catalogue.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.common import JsonOpt, MechanismOpt, NoPlotsOpt, OutOpt


@app.command()
def law(scene_file: Annotated[Path | None, typer.Argument(
            help="SCENE.toml whose [law] to draw; none: the law the options give.", show_default=False)] = None,
        segments: Annotated[str | None, typer.Option(
            "--segments", help='Segments "start:end:shape[:to_mm][:v_end=..][:lambda=..],..." (deg, mm, mm/deg).'
        )] = None,
        rise_law: Annotated[str | None, typer.Option(
            "--rise-law", help="Standard law: rise shape (cycloidal, inclined_sine, poly5, modified_sine:0.4, ...)."
        )] = None,
        return_law: Annotated[str | None, typer.Option("--return-law", help="Standard law: return shape.")] = None,
        phases: Annotated[str | None, typer.Option(
            "--phases", help='Standard law: "0:120:rise,120:180:dwell,...".')] = None,
        lift: Annotated[float | None, typer.Option("--lift", help="Standard law: the lift of every rise (mm).")] = None,
        cycle: Annotated[float | None, typer.Option("--cycle", help="Working angle the law spans (deg; 360).")] = None,
        mechanism: MechanismOpt = None, output: OutOpt = None,
        tol: Annotated[float, typer.Option(
            "--tol", help="Chord tolerance of the drawn acceleration, a fraction of its peak.")] = 1e-5,
        step: Annotated[float, typer.Option("--step", help="Step of the table law.csv (deg).")] = 0.5,
        r12: Annotated[bool, typer.Option("--r12", help="Write DXF R12 instead of R2000.")] = False,
        list_: Annotated[bool, typer.Option("--list", help="Print the VDI 2143 catalogue and exit.")] = False,
        no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Design a motion from segments or standard shapes; write law.dxf, law.csv, law.png, law.json.

    The drawing holds the acceleration (balanced to the law's positions and velocities), the axes and the phase
    marks, and keeps the phases, so camcad check reads it back with them and camcad edit opens it."""
    from camcad.cli.analysis_options import emit
    from camcad.cli.common import print_json

    if list_:
        from camcad.law.vdi import catalogue_table
        from camcad.report.law import catalogue_lines

        if as_json:
            print_json({"catalogue": catalogue_table()})
        else:
            print("\n".join(catalogue_lines()))
        raise typer.Exit(0)
    from camcad.report.law import LawRequest, run_law

    request = LawRequest(scene_file, mechanism, segments, rise_law, return_law, phases, lift, cycle, output,
                         not no_plots, tol, step, r12)
    emit(run_law(request), as_json)
