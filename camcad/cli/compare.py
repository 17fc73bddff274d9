"""`camcad compare A B [--scene S]`: two laws on one mechanism, side by side.

Thin: the options become a CompareRequest, ``camcad.report.compare.compare_command`` computes and writes, and
the run is printed (text or --json: ``{"compare": {...}}``). Exit 0 (a comparison has no verdict), 2 bad input.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.analysis_options import UnitOpt, emit
from camcad.cli.common import CycleOpt, JsonOpt, MechanismOpt, NoPlotsOpt, OutOpt, RpmOpt

LawOpt = Annotated[Path | None, typer.Argument(help="A law file (DXF or table); absent: the scene's.")]


@app.command()
def compare(law_a: LawOpt = None, law_b: LawOpt = None,
            scene: Annotated[Path | None, typer.Option(
                "--scene", help="The mechanism both laws run on (its [dynamics], [contact], [follower], "
                                "[compare]).")] = None,
            rpm: RpmOpt = None, mechanism: MechanismOpt = None,
            harmonics: Annotated[int | None, typer.Option(
                "--harmonics", "-N", help="Harmonics listed side by side (default 32).")] = None,
            window: Annotated[float | None, typer.Option(
                "--window", help="Start-of-motion window after each motion starts (deg, default 7).")] = None,
            cycle: CycleOpt = 360.0, unit: UnitOpt = None, output: OutOpt = None, no_plots: NoPlotsOpt = False,
            as_json: JsonOpt = False) -> None:
    """Two laws on one mechanism, side by side: A, B and A/B.

    Peak and start-of-motion acceleration (rigid and elastic), the summary dynamic load at the start, the
    displacement deviation, harmonic tables, residual vibration, contact stress and its safety factor against
    speed; each with the phase and speed it applies to, and the published figures of the scene's [compare]
    beside camcad's."""
    from camcad.report.compare import CompareCommand, compare_command
    from camcad.scene.commands.compare import CompareRequest

    request = CompareRequest(law_a, law_b, scene, rpm, mechanism, harmonics, window, cycle, unit)
    emit(compare_command(CompareCommand(request, output, not no_plots)), as_json)
