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
        folder = out.path(*sub) if sub else out.folder
        if run.dynamics is not None:
            from camcad.report.dynamics import dynamics_plots

            written.extend(dynamics_plots(run.dynamics, run.law, folder, run.name))
        if run.impact is not None:
            from camcad.report.dynamics import impact_plots

            written.extend(impact_plots(run.impact, folder, run.name))
        if run.contact is not None:
            from camcad.report.cyclogram import plot_contact_stress, plot_safety_versus_speed

            at_worst, sweep = run.contact
            written.append(plot_contact_stress(at_worst, out.path(*sub, "contact.png"), title=run.name))
            if len(sweep.rpm) > 1:
                written.append(plot_safety_versus_speed(sweep, out.path(*sub, "contact_speed.png"),
                                                        title=f"{run.name}: contact safety factor"))
    return written
