"""`camcad contact SCENE` (Hertz stress along the profile, against speed, phase-angle limits) and
`camcad cyclogram SCENE` (the group's network optimised by LP, with the limits as lower bounds).

Thin: the options become a request, ``camcad.report.contact.contact_command`` /
``camcad.report.cyclogram.cyclogram_command`` computes and writes, and the run is printed (text or --json).
"""

from __future__ import annotations

from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.analysis_options import PhaseAnglesOpt, emit
from camcad.cli.common import (
    JsonOpt,
    MechanismOpt,
    NoPlotsOpt,
    OutOpt,
    RpmOpt,
    SceneArg,
)

SamplesOpt = Annotated[int, typer.Option("--samples", help="Cam-angle samples per phase for the stress maximum.")]


@app.command()
def contact(scene_file: SceneArg, mechanism: MechanismOpt = None, rpm: RpmOpt = None, output: OutOpt = None,
            no_plots: NoPlotsOpt = False, samples: SamplesOpt = 2000, phase_angles: PhaseAnglesOpt = "auto",
            as_json: JsonOpt = False) -> None:
    """Hertz contact stress along the profile, safety factor, phase limits.

    The safety factor against speed, separation and the least phase angle of each rise and return, at the
    phase angles camcad profile uses (the cyclogram's in a group scene); exit 0 ok, 1 stress over [σ_H] or
    separation, 2 bad input."""
    from camcad.report.contact import ContactCommand, contact_command
    from camcad.scene.commands.contact import ContactRequest

    request = ContactRequest(scene_file, mechanism, rpm, samples, phase_angles)
    emit(contact_command(ContactCommand(request, output, not no_plots)), as_json)


@app.command()
def cyclogram(scene_file: SceneArg, rpm: RpmOpt = None, output: OutOpt = None, no_plots: NoPlotsOpt = False,
              samples: SamplesOpt = 2000, as_json: JsonOpt = False) -> None:
    """Optimise a group's cyclogram: least makespan under the phase limits.

    By LP under the operations' bounds and their phase-angle limits (vibration, contact stress, pressure
    angle, impact rebound); exit 1 when the network is infeasible."""
    from camcad.report.cyclogram import CyclogramCommand, cyclogram_command
    from camcad.scene.commands.cyclogram import CyclogramRequest

    run = cyclogram_command(CyclogramCommand(CyclogramRequest(scene_file, rpm, samples), output, not no_plots))
    if as_json and not run.report.body["feasible"]:
        import sys

        print(f"camcad: {run.report.body['explanation']}", file=sys.stderr)
    emit(run, as_json)
