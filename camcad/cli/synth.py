"""`camcad synth`: a law of a given tachogram from the harmonic database.

Thin: the options become a SynthRequest, ``camcad.report.synth.synth_command`` computes and writes (synth.dxf,
synth.csv with the law's phases, harmonics.csv, patterns.csv, plots), and the run is printed (text or --json).
Exit 0 when the written law meets its limits, 1 when not, 2 bad input.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.analysis_options import emit
from camcad.cli.common import CycleOpt, JsonOpt, NoPlotsOpt, OutOpt, PhasesOpt


@app.command()
def synth(lift: Annotated[float | None, typer.Option(
              "--lift", help="Lift (mm), or swing (rad or deg with --unit).")] = None,
          tachogram: Annotated[str | None, typer.Option(
              "--tachogram", help="DRTD (dwell-rise-return-dwell), DRDTD (dwell-rise-dwell-return-dwell), "
                                  "RT (rise-return) or RDTD; or give --phases.")] = None,
          rise: Annotated[float | None, typer.Option("--rise", help="Rise angle (deg).")] = None,
          back: Annotated[float | None, typer.Option("--return", help="Return angle (deg).")] = None,
          start: Annotated[float, typer.Option("--start", help="Dwell before the rise (deg).")] = 0.0,
          far_dwell: Annotated[float, typer.Option("--far-dwell", help="Dwell at the top (deg).")] = 0.0,
          phases: PhasesOpt = None, cycle: CycleOpt = 360.0,
          unit: Annotated[str, typer.Option("--unit", help="Unit of the lift: mm, rad or deg.")] = "mm",
          shape: Annotated[str, typer.Option(
              "--shape", help="Shape of the rises: a standard law, or drawn (--shape-from's rise).")] = "cycloidal",
          return_shape: Annotated[str | None, typer.Option(
              "--return-shape", help="Shape of the returns (default: --shape).")] = None,
          shape_from: Annotated[Path | None, typer.Option(
              "--shape-from", help="A drawn law whose rise and return join the database.")] = None,
          tol: Annotated[float | None, typer.Option(
              "--tol", help="RMS error wanted (law unit; default 1e-3 of the lift): the least N meeting it.")] = None,
          harmonics: Annotated[int | None, typer.Option("--harmonics", "-N", help="N instead of --tol.")] = None,
          dwell_tol: Annotated[float | None, typer.Option(
              "--dwell-tol", help="Dwell deviation limit of the written law (default 1e-3 of the lift).")] = None,
          step: Annotated[float, typer.Option("--step", help="Vertex step of the written polyline (deg).")] = 0.1,
          r12: Annotated[bool, typer.Option("--r12", help="Write synth.dxf as DXF R12.")] = False,
          output: OutOpt = None, no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Synthesise a law of a given tachogram from the harmonic database.

    Amplitude and phase patterns of every standard shape (and of a drawn law's own motions), the number of
    harmonics for the RMS error wanted, the law written as synth.dxf and synth.csv with its phases; exit 1 when
    the written law misses its RMS, dwell or closure limit."""
    from camcad.report.synth import SynthCommand, synth_command
    from camcad.scene.commands.synth import SynthRequest

    request = SynthRequest(lift, tachogram, phases, rise, back, start, far_dwell, cycle, unit, shape, return_shape,
                           shape_from, tol, harmonics, dwell_tol, step)
    emit(synth_command(SynthCommand(request, output, not no_plots, r12)), as_json)
