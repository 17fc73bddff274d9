"""`camcad dynamics LAW|SCENE` (elastic follower over a speed range) and `camcad impact LAW|SCENE`
(limit-stop impact and rebound).

Thin: the options become a request, ``camcad.report.dynamics.dynamics_command`` / ``impact_command``
computes and writes, and the run is printed (text or --json). Exit 0 when every check passed, 1 when one
failed, 2 bad input.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.analysis_options import PhaseAnglesOpt, UnitOpt, emit, progress
from camcad.cli.common import (
    CycleOpt,
    HandleOpt,
    JsonOpt,
    LayerOpt,
    LiftOpt,
    MechanismOpt,
    NoPlotsOpt,
    OutOpt,
    PhasesOpt,
    ReturnStandardOpt,
    RpmOpt,
    SourceArg,
    StandardOpt,
    XDegOpt,
)

ZetaOpt = Annotated[float | None, typer.Option("--zeta", help="Damping ratio ζ (0 <= ζ < 1).")]


@app.command()
def dynamics(source: SourceArg = None,
             fn: Annotated[float | None, typer.Option(
                 "--fn", help="Natural frequency of the follower system (Hz).")] = None,
             zeta: ZetaOpt = None,
             psi: Annotated[float | None, typer.Option(
                 "--psi", help="Dissipation coefficient ψ (= 4πζ) instead of --zeta.")] = None,
             mass: Annotated[float | None, typer.Option(
                 "--mass", help="Reduced follower mass (kg), for forces.")] = None,
             rpm: RpmOpt = None,
             method: Annotated[str | None, typer.Option(
                 "--method", help="frequency | time | auto (frequency for constant stiffness).")] = None,
             solver: Annotated[str | None, typer.Option(
                 "--solver", help="solve_ivp method of the time path: RK45, DOP853, Radau, LSODA, ...")] = None,
             rtol: Annotated[float | None, typer.Option("--rtol", help="Relative tolerance of the time path.")] = None,
             samples: Annotated[int | None, typer.Option(
                 "--samples", help="Samples per cycle (frequency path: the accuracy knob).")] = None,
             start_pulse: Annotated[float | None, typer.Option(
                 "--start-pulse", help="Summary load at the start of motion, × the phase's peak acceleration.")] = None,
             compare: Annotated[Path | None, typer.Option(
                 "--compare",
                 help="A second law (e.g. a filtered one) whose start-of-motion load is compared.")] = None,
             lead_in: Annotated[str | None, typer.Option(
                 "--lead-in",
                 help="Compare with lead-in segments DEG[:FRACTION] before each motion (default fraction 0.1), e.g. "
                      "14:0.1; a scene's [filter] lead-in is used when present.")] = None,
             max_ratio: Annotated[float | None, typer.Option(
                 "--max-ratio", help="Allowed peak acceleration ratio elastic/rigid.")] = None,
             max_error: Annotated[float | None, typer.Option(
                 "--max-error", help="Allowed dynamic error (law unit: mm, or rad).")] = None,
             max_residual: Annotated[float | None, typer.Option(
                 "--max-residual", help="Allowed residual vibration (law unit).")] = None,
             harmonic: Annotated[int | None, typer.Option(
                 "--harmonic", help="Draw harmonic K of s and a and its beats with the free vibration.")] = None,
             unit: UnitOpt = None, phase_angles: PhaseAnglesOpt = "auto",
             standard: StandardOpt = None, return_standard: ReturnStandardOpt = None, phases: PhasesOpt = None,
             lift: LiftOpt = None, layer: LayerOpt = None, handle: HandleOpt = None, cycle: CycleOpt = 360.0,
             x_deg: XDegOpt = False, mechanism: MechanismOpt = None, output: OutOpt = None,
             no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Elastic follower over a speed range: rigid vs elastic acceleration.

    Dynamic error, residual vibration (always reported, also at resonance), start-of-motion loads; exit 1
    when a given limit is exceeded or a speed has no bounded steady state."""
    from camcad.report.dynamics import DynamicsCommand, dynamics_command
    from camcad.scene.commands.dynamics import DynamicsRequest
    from camcad.scene.commands.source import LawRequest

    law = LawRequest(source, standard, return_standard, phases, lift, layer, handle, cycle, x_deg, mechanism, unit,
                     phase_angles, rpm)
    request = DynamicsRequest(law, fn, zeta, psi, mass, method, solver, rtol, samples, start_pulse, compare, lead_in,
                              max_ratio, max_error, max_residual, harmonic)
    callback, close = progress(not as_json, "dynamics")
    try:
        run = dynamics_command(DynamicsCommand(request, output, not no_plots), callback)
    finally:
        close()
    emit(run, as_json)


@app.command()
def impact(source: SourceArg = None, rpm: RpmOpt = None,
           mass: Annotated[float | None, typer.Option(
               "--mass", help="Reduced mass of the lever at the contact point (kg).")] = None,
           f_free: Annotated[float | None, typer.Option(
               "--f-free", help="Natural frequency without the stop (Hz).")] = None,
           f_stop: Annotated[float | None, typer.Option("--f-stop", help="Natural frequency on the stop (Hz).")] = None,
           restitution: Annotated[float | None, typer.Option(
               "--restitution", help="Coefficient of restitution k (5/9 for steel).")] = None,
           zeta: ZetaOpt = None,
           preload: Annotated[float | None, typer.Option(
               "--preload", help="Preload of the stop (mm at the contact point).")] = None,
           stop: Annotated[str | None, typer.Option(
               "--stop", help="upper (end of rise) or lower (end of return).")] = None,
           ratio: Annotated[float | None, typer.Option(
               "--ratio", help="Contact-point displacement per unit of the law's.")] = None,
           allowed: Annotated[float | None, typer.Option("--allowed", help="Allowed rebound amplitude (mm).")] = None,
           phase_angles: PhaseAnglesOpt = "auto",
           standard: StandardOpt = None, return_standard: ReturnStandardOpt = None, phases: PhasesOpt = None,
           lift: LiftOpt = None, layer: LayerOpt = None, handle: HandleOpt = None, cycle: CycleOpt = 360.0,
           x_deg: XDegOpt = False, mechanism: MechanismOpt = None, output: OutOpt = None,
           no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Impact on a limit stop: force and first rebound against speed.

    And the least phase angle for an allowed amplitude (exit 1 when the rebound exceeds it or the preload)."""
    from camcad.report.dynamics import DynamicsCommand, impact_command
    from camcad.scene.commands.impact import ImpactRequest
    from camcad.scene.commands.source import LawRequest

    law = LawRequest(source, standard, return_standard, phases, lift, layer, handle, cycle, x_deg, mechanism, None,
                     phase_angles, rpm)
    request = ImpactRequest(law, mass, f_free, f_stop, restitution, zeta, preload, stop, ratio, allowed)
    callback, close = progress(not as_json, "impact")
    try:
        run = impact_command(DynamicsCommand(request, output, not no_plots), callback)
    finally:
        close()
    emit(run, as_json)
