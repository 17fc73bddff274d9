"""`camcad drive SCENE`: the camshaft torque and power of the scene's mechanisms on one shaft, the flywheel
for a speed fluctuation, the motor through its gearbox.

Thin: the options become a request, ``camcad.report.drive.drive_command`` computes and writes (torque.csv,
torque.png, drive.json), and the run is printed (text or --json).
"""

from __future__ import annotations

from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.analysis_options import emit
from camcad.cli.common import JsonOpt, NoPlotsOpt, OutOpt, RpmOpt, SceneArg

DeltaOpt = Annotated[str | None, typer.Option(
    "--delta", help='Allowed coefficient of speed fluctuation (n_max - n_min)/n_mean, e.g. 0.0333 or 1/30; '
                    "default the scene's [drive] delta.")]


@app.command()
def drive(scene_file: SceneArg, rpm: RpmOpt = None, delta: DeltaOpt = None, output: OutOpt = None,
          no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Camshaft torque and power, flywheel and motor sizing.

    The torque of every mechanism with a [follower] and a [contact] (inertia, spring, preload, [load]
    process force, friction) and of the shaft they share; the flywheel for a speed fluctuation δ (energy
    method); the motor through the [drive] gearbox against its rated and peak torque. Writes torque.csv,
    torque.png and drive.json; exit 0 ok, 1 a [drive] check failed, 2 bad input."""
    from camcad.report.drive import DriveCommand, drive_command
    from camcad.scene.commands.drive import DriveRequest
    from camcad.scene.sections.drive import parse_fraction

    value = None if delta is None else float(parse_fraction(delta, "--delta", "--delta"))
    emit(drive_command(DriveCommand(DriveRequest(scene_file, rpm, value), output, not no_plots)), as_json)
