"""Step 10 of the scene pipeline: the outputs of a scene, written into one output folder as a unit.

Per mechanism (a subfolder named by ``safe_name`` for a group scene): profile.dxf, law.csv and the
plots of the models it ran; for the whole scene one report.json. The folder is an ``OutputFolder``: no
output replaces a file the scene reads, names cannot leave the folder, and a concurrent run into the
same folder waits for this one.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np

from camcad.io.jsonout import write_json
from camcad.io.law_write import write_law_csv
from camcad.io.output_folder import OutputFolder, safe_name
from camcad.scene.pipeline import MechanismRun, PipelineOptions, SceneResult, analyse_scene

#: cam-angle samples of law.csv for a mechanism without a profile
LAW_SAMPLES = 721


def default_folder(scene_name: str) -> Path:
    """./camcad-out/<scene name made safe>/."""
    return Path("camcad-out") / safe_name(scene_name)


def write_scene(result: SceneResult, options: PipelineOptions = PipelineOptions(),
                progress: Callable[[str], None] | None = None) -> SceneResult:
    """Write every output of ``result`` into ``options.output`` (default ``default_folder``); the report
    gains ``outputs`` (all files) and, per mechanism, its own ``outputs``. Returns ``result``."""
    say = progress or (lambda _text: None)
    folder = options.output if options.output is not None else default_folder(result.scene.name)
    outputs: list[Path] = []
    with OutputFolder(folder, result.scene.input_files()) as out:
        for name, run in result.runs.items():
            sub = (name,) if result.group else ()
            say(f"{name}: writing")
            written = _write_mechanism(run, out, sub, options)
            target = result.report["mechanisms"][name] if result.group else result.report
            target["outputs"] = [str(p) for p in written]
            outputs.extend(written)
        if options.plots and result.report.get("cyclogram"):
            from camcad.report.cyclogram import scene_cyclogram_figures
            from camcad.report.figure import save_figure

            for name, fig in scene_cyclogram_figures(result.scene, result.report["cyclogram"]):
                outputs.append(save_figure(fig, out.path(name)))
        report_path = out.path("report.json")
        outputs.append(report_path)
        result.report["outputs"] = [str(p) for p in outputs]
        write_json(report_path, result.report)
    return result


def run_scene(path: str | Path, options: PipelineOptions = PipelineOptions(),
              progress: Callable[[str], None] | None = None) -> SceneResult:
    """The whole pipeline on a scene file: ``analyse_scene`` then ``write_scene``."""
    return write_scene(analyse_scene(path, options, progress), options, progress)


def _write_mechanism(run: MechanismRun, out: OutputFolder, sub: tuple[str, ...],
                     options: PipelineOptions) -> list[Path]:
    written: list[Path] = []
    if run.profile is not None:
        from camcad.report.profile_files import write_outputs

        written.extend(write_outputs(run.profile, out, sub=sub, report_json=False))
    else:
        theta = np.linspace(0.0, run.law.cycle, LAW_SAMPLES)
        written.append(write_law_csv(out.path(*sub, "law.csv"), run.law.kinematics(theta)))
    if options.plots:
        from camcad.report.figure import save_figure

        figures = []
        if run.dynamics is not None:
            from camcad.report.dynamics import plot_acceleration_cycle, plot_speed_sweep

            responses = [run.dynamics.sweep.responses[s] for s in run.dynamics.keep if s in run.dynamics.sweep.responses]
            if responses:
                figures.append(("dynamics_cycle.png", plot_acceleration_cycle(
                    responses, run.dynamics.phases, unit=run.dynamics.settings.output_unit,
                    title=f"{run.name}: rigid vs elastic acceleration", verdict=run.dynamics.verdict)))
            if len(run.dynamics.sweep.speeds_rpm) > 1:
                figures.append(("dynamics_speed.png", plot_speed_sweep(run.dynamics, title=f"{run.name}: against speed",
                                                                       verdict=run.dynamics.verdict)))
        if run.impact is not None:
            from camcad.report.dynamics import plot_impact_response, plot_rebound

            figures.append(("impact_rebound.png", plot_rebound(run.impact.sweep, run.impact.model,
                                                               verdict=run.impact.verdict,
                                                               title=f"{run.name}: impact on the stop")))
            figures.append(("impact_response.png", plot_impact_response(
                [i for i in run.impact.sweep.impacts if len(i.time)], run.impact.model)))
        if run.contact is not None:
            from camcad.report.contact import plot_contact_stress, plot_safety_versus_speed

            figures.append(("contact.png", plot_contact_stress(run.contact, title=run.name)))
            if len(run.contact.sweep.rpm) > 1:
                figures.append(("contact_speed.png", plot_safety_versus_speed(
                    run.contact.sweep, title=f"{run.name}: contact stress against speed")))
        written.extend(save_figure(fig, out.path(*sub, name)) for name, fig in figures)
    return written
