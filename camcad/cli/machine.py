"""`camcad machine MACHINE.toml`: a machine of groups on one main shaft, its cyclogram and every group's profiles.

Thin: the options become a request, ``camcad.report.machine.run_machine`` computes and writes, and the run is
printed (text or --json).
"""

from __future__ import annotations

from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.common import JsonOpt, NoPlotsOpt, OutOpt

MachineArg = Annotated[str, typer.Argument(
    help="Machine scene (TOML): [machine], [groups.NAME] (a group scene or inline), [network].",
    show_default=False)]
ObjectiveOpt = Annotated[str | None, typer.Option(
    "--objective", help="least_cycle (the shortest machine cycle) or limiting (the longest limiting operation "
                        "within the cycle); default: the scene's.")]
SamplesOpt = Annotated[int, typer.Option("--samples", help="Cam-angle samples per phase for the stress maximum.")]


@app.command()
def machine(scene_file: MachineArg, objective: ObjectiveOpt = None, output: OutOpt = None,
            no_plots: NoPlotsOpt = False, samples: SamplesOpt = 2000, as_json: JsonOpt = False) -> None:
    """Optimise a machine of groups: least cycle or the longest limiting operation.

    Every group's phase limits, the machine's network by longest paths, the slack off the critical path spread
    by the max-min rule, and every group's profiles at the machine's phase angles; exit 1 when infeasible or a
    check fails."""
    from pathlib import Path

    from camcad.cli.common import console, print_json
    from camcad.report.machine import MachineRequest, run_machine

    report = run_machine(MachineRequest(Path(scene_file), objective, output, not no_plots, samples))
    if as_json:
        print_json(report.to_dict())
    else:
        out = console()
        for line in report.lines():
            out.print(line, soft_wrap=True)
    raise typer.Exit(report.exit_code)
