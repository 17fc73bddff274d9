"""Step 10 of the scene pipeline: the outputs of a scene, written into one output folder as a unit.

Per mechanism (a subfolder named by ``safe_name`` for a group scene): profile.dxf, law.csv and the
plots asked for; for the whole scene one report.json. The folder is an ``OutputFolder``: no output
replaces a file the scene reads, names cannot leave the folder, and a concurrent run into the same
folder waits for this one.

Plots: by default one summary page per mechanism (``summary.png``: the profile, the law, the pressure
angle and the curvature with their limits, and the verdict with every margin); ``plots=("all",)`` adds
every plot of the profile and of the models the mechanism ran (dynamics, impact, contact). The pages are
drawn in this process, one after the other, every mechanism's summary into the same figure
(``camcad.report.profile.SummaryPage``): a group pays once for the page's axes and ticks and for
matplotlib's first page (its fonts), where parallel processes each paid for both and for their start
(the loom group's six pages: 2.3 s of CPU in two processes, 1.2 s in one).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from camcad.io.jsonout import write_json
from camcad.io.law_write import write_law_csv
from camcad.io.output_folder import OutputFolder, distinct_names, safe_name
from camcad.profile.servo import ServoExport
from camcad.report.animation import write_animation
from camcad.report.design_report import write_design_report
from camcad.report.figure import save_figure
from camcad.report.part_files import scene_part_files, write_part_files
from camcad.report.profile import PLOTS, SummaryPage, save_profile_plots
from camcad.report.profile_files import write_outputs
from camcad.report.scene_toml import scene_toml
from camcad.report.servo import servo_files, write_servo
from camcad.scene.animation import mechanism_frames
from camcad.scene.file import Scene
from camcad.scene.pipeline import MechanismRun, PipelineOptions, SceneResult, analyse_scene

#: cam-angle samples of law.csv for a mechanism without a profile
LAW_SAMPLES = 721
#: plot names that belong to the models a mechanism ran (drawn with "all" or when named)
MODEL_PLOTS = ("dynamics", "impact", "contact")


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
    if result.group:   # each mechanism's own subfolder: "lift 1" and "lift_1" would share one
        distinct_names(result.runs, "mechanisms", str(result.scene.path))
    parts = scene_part_files(result, options.export)   # a part that cannot be made is refused before any write
    servos: dict[str, ServoExport | None] = {name: options.servo if options.servo is not None else (
        ServoExport().validated() if parts[name].servo else None) for name in result.runs}
    cyclogram_plots = bool(options.plots and (result.report.get("cyclogram") or {}).get("feasible"))
    with OutputFolder(folder, [(p, "an input of the scene") for p in result.scene.input_files()]) as out:
        # every file of the run, checked as a set before any is written
        planned = [(name, (name,) if result.group else (), file) for name, run in result.runs.items()
                   for file in _data_files(run) + (MECHANISM_PLOT_FILES if options.plots else ())
                   + tuple(parts[name].files) + servo_files(servos[name])]
        planned += [(CYCLOGRAM_JOB, (), file) for file in (CYCLOGRAM_PLOT_FILES if cyclogram_plots else ())]
        planned += [(name, (name,) if result.group else (), f"animation.{kind}") for name, run in result.runs.items()
                    if run.profile is not None for kind in options.animate]
        planned += [("", (), file) for file in ("report.json", *(f"report.{kind}" for kind in options.report))]
        out.plan([(*sub, file) for _, sub, file in planned],
                 [f"{file} of {name}" if name else file for name, _, file in planned])
        written: dict[str, list[Path]] = {}
        animations: dict[str, str] = {}
        jobs = []
        pages = [out.path(f"report.{kind}") for kind in options.report]   # refused before anything is written
        for name, run in result.runs.items():
            sub = (name,) if result.group else ()
            say(f"{name}: writing")
            written[name] = _write_data(run, out, sub, options, parts[name].units)
            written[name] += write_part_files(parts[name], out, sub)
            target = result.report["mechanisms"][name] if result.group else result.report
            if parts[name].report:
                target["export"] = parts[name].report
            # ---- --export servo, or servo in the [export] kinds (camcad.report.servo)
            servo = servos[name]
            if servo is not None:
                files, target["servo"] = write_servo(run, out, sub, servo, result.scene.speeds_rpm)
                written[name].extend(files)
            # ---- --animate (camcad.report.animation)
            if options.animate:
                written[name] += _write_animation(run, out, sub, options, target, animations)
            # ----
            if options.plots:
                jobs.append((name, run, out.path(*sub) if sub else out.folder, tuple(options.plots), target))
        if cyclogram_plots:
            jobs.append((CYCLOGRAM_JOB, result.scene, out.folder, (), result.report["cyclogram"]))
        drawn: list[Path] = []
        if jobs:
            say("plots")
            for name, paths in _draw_all(jobs):
                (drawn if name == CYCLOGRAM_JOB else written[name]).extend(paths)
        for name, paths in written.items():
            target = result.report["mechanisms"][name] if result.group else result.report
            target["outputs"] = [str(p) for p in paths]
            outputs.extend(paths)
        outputs.extend(drawn)
        report_path = out.path("report.json")
        outputs.append(report_path)
        result.report["outputs"] = [str(p) for p in outputs + pages]
        write_json(report_path, result.report)
        if pages:   # --report (camcad.report.design_report): from report.json as written
            say("report")
            scene = result.scene
            scene_text = (scene.path.read_text(encoding="utf-8") if scene.from_file and scene.path.is_file() else
                          scene_toml(scene.raw, "the scene camcad built from the command's options"))
            write_design_report(report_path, pages[0], pdf_path=pages[1] if len(pages) > 1 else None,
                                command=options.command, scene_text=scene_text, animations=animations)
    return result


def _write_animation(run: MechanismRun, out: OutputFolder, sub: tuple[str, ...], options: PipelineOptions,
                     target: dict, animations: dict[str, str]) -> list[Path]:
    """The mechanism's animation files (``options.animate``); its page is kept in ``animations`` for the report."""
    if run.profile is None:
        target.setdefault("skipped", {})["animation"] = "no profile to animate (no [follower])"
        return []
    for kind in options.animate:
        out.path(*sub, f"animation.{kind}")
    frames = mechanism_frames(run, options.animate_step_deg)
    folder = out.path(*sub) if sub else out.folder
    law = "; ".join(note.removeprefix("law: ") for note in (target.get("law") or {}).get("notes", [])[:1])
    files = write_animation(frames, folder, options.animate, title=run.name,
                            subtitle=run.profile.follower.describe() + (f"; {law}" if law else ""))
    target["animation"] = {"files": [p.name for p in files], "frames": frames.count,
                           "step_deg": 360.0 / frames.count}
    html_file = folder / "animation.html"
    if html_file in files:
        animations[run.name] = html_file.read_text(encoding="utf-8")
    return files


def run_scene(source: str | Path | Scene, options: PipelineOptions = PipelineOptions(),
              progress: Callable[[str], None] | None = None) -> SceneResult:
    """Run the whole scene pipeline and write its outputs: ``analyse_scene`` then ``write_scene``.

    The outputs go into one ``OutputFolder`` (``options.output``, default ``camcad-out/<scene name>/``):
    per mechanism profile.dxf (mm), law.csv (deg, mm) and the plots asked for; one report.json. No
    output replaces a file the scene reads.

    Parameters
    ----------
    source : str, Path or Scene
        The scene file, or a ``Scene`` built from a command's options.
    options : PipelineOptions
        Where to write (``output``), the chord tolerance ``tol_mm`` (mm), arcs, spline, R12, the plots
        to draw (``plots``: names, "all", or () for none) and ``contact_samples`` (a count).
    progress : callable, optional
        Called with a short text (no unit) as each step starts.

    Returns
    -------
    SceneResult
        As ``analyse_scene`` (docs/INTERFACE.md keys: deg, mm, rpm, N, MPa); ``report["outputs"]`` lists the
        files written.

    Raises
    ------
    CamcadError
        Bad input anywhere in the scene, or an output that would replace an input.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import camcad
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "cam.toml").write_text('''
    ... name = "cam"
    ... [law]
    ... standard = "cycloidal"
    ... phases = "0:90:rise,90:180:dwell,180:270:return,270:360:dwell"
    ... lift = 20.0
    ... [follower]
    ... type = "roller"
    ... base_radius = 40.0
    ... roller_radius = 10.0
    ... ''')
    >>> from camcad.scene.pipeline import PipelineOptions
    >>> result = camcad.run_scene(folder / "cam.toml", PipelineOptions(output=folder / "out", plots=()))
    >>> sorted(path.name for path in (folder / "out").iterdir())
    ['law.csv', 'profile.dxf', 'report.json']
    """
    return write_scene(analyse_scene(source, options, progress), options, progress)


def _data_files(run: MechanismRun) -> tuple[str, ...]:
    """The data files ``_write_data`` writes for a mechanism."""
    return ("profile.dxf", "law.csv") if run.profile is not None else ("law.csv",)


def _write_data(run: MechanismRun, out: OutputFolder, sub: tuple[str, ...], options: PipelineOptions,
                units: str = "mm") -> list[Path]:
    """profile.dxf and law.csv (or law.csv alone for a mechanism without a profile), lengths in ``units``."""
    if run.profile is not None:
        return write_outputs(run.profile, out, sub=sub, report_json=False, plots=(), units=units)
    theta = np.linspace(0.0, run.law.cycle, LAW_SAMPLES)
    return [write_law_csv(out.path(*sub, "law.csv"), run.law.kinematics(theta))]


def mechanism_plots(run: MechanismRun, folder: Path, plots: tuple[str, ...], report: dict,
                    page=None) -> list[Path]:
    """Draw and save the plots of one mechanism named in ``plots`` into ``folder`` (the profile's through
    ``camcad.report.profile``, the models' when named or with "all"); the summary into ``page`` when given
    (a ``camcad.report.profile.SummaryPage`` shared by the mechanisms of a run)."""
    every = "all" in plots
    written: list[Path] = []
    if run.profile is not None:
        wanted = tuple(name for name in PLOTS if every or name in plots)
        written.extend(save_profile_plots(run.profile, folder, wanted, report, page=page))
    figures = []
    if run.dynamics is not None and (every or "dynamics" in plots):
        from camcad.report.dynamics import plot_acceleration_cycle, plot_speed_sweep

        responses = [run.dynamics.sweep.responses[s] for s in run.dynamics.keep if s in run.dynamics.sweep.responses]
        if responses:
            figures.append(("dynamics_cycle.png", plot_acceleration_cycle(
                responses, run.dynamics.phases, unit=run.dynamics.settings.output_unit,
                title=f"{run.name}: rigid vs elastic acceleration", verdict=run.dynamics.verdict)))
        if len(run.dynamics.sweep.speeds_rpm) > 1:
            figures.append(("dynamics_speed.png", plot_speed_sweep(run.dynamics, title=f"{run.name}: against speed",
                                                                   verdict=run.dynamics.verdict)))
    if run.impact is not None and (every or "impact" in plots):
        from camcad.report.dynamics import plot_impact_response, plot_rebound

        figures.append(("impact_rebound.png", plot_rebound(run.impact.sweep, run.impact.model,
                                                           verdict=run.impact.verdict,
                                                           title=f"{run.name}: impact on the stop")))
        figures.append(("impact_response.png", plot_impact_response(
            [i for i in run.impact.sweep.impacts if len(i.time)], run.impact.model)))
        from camcad.report.dynamics import published_figures

        figures.extend(published_figures(run.impact, run.name))   # with [stops.published]
    if run.contact is not None and (every or "contact" in plots):
        from camcad.report.contact import plot_contact_stress, plot_safety_versus_speed

        figures.append(("contact.png", plot_contact_stress(run.contact, title=run.name)))
        if len(run.contact.sweep.rpm) > 1:
            figures.append(("contact_speed.png", plot_safety_versus_speed(
                run.contact.sweep, title=f"{run.name}: contact stress against speed")))
    written.extend(save_figure(fig, folder / name) for name, fig in figures)
    return written


#: every file a mechanism's plots may write (``mechanism_plots``), and the cyclogram's: each is checked
#: against the run's inputs before any plot is drawn
MECHANISM_PLOT_FILES = ("summary.png", "kinematics.png", "pressure_angle.png", "curvature.png", "profile.png",
                        "hodograph.png", "dynamics_cycle.png", "dynamics_speed.png", "impact_rebound.png",
                        "impact_response.png", "impact_published.png", "impact_analogs.png", "contact.png",
                        "contact_speed.png")
CYCLOGRAM_PLOT_FILES = ("cyclogram.png", "network.png")
#: the name of the job that draws the scene's cyclogram (Gantt chart and network) beside the mechanisms'
CYCLOGRAM_JOB = "[cyclogram]"


def _draw_all(jobs: list) -> list[tuple[str, list[Path]]]:
    """Every mechanism's plots and the cyclogram's, in this process, the summaries into one shared page
    (module docstring)."""
    page: SummaryPage | None = None
    drawn = []
    for name, run, folder, plots, report in jobs:
        if name == CYCLOGRAM_JOB:          # run is the scene, report its cyclogram object
            from camcad.report.cyclogram import scene_cyclogram_figures

            figures = scene_cyclogram_figures(run, report)
            drawn.append((name, [save_figure(fig, folder / file) for file, fig in figures]))
            continue
        if page is None and run.profile is not None and ("summary" in plots or "all" in plots):
            page = SummaryPage()
        drawn.append((name, mechanism_plots(run, folder, plots, report, page)))
    return drawn
