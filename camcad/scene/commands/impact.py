"""``camcad impact`` as one library function (``run_impact_report``): the lever's impact on its stop and the
first rebound over a speed range, on the law ``camcad profile`` analyses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

from camcad.dynamics.impact import StopModel
from camcad.dynamics.runs import run_impact
from camcad.errors import CamcadError
from camcad.scene.analysis_report import AnalysisReport
from camcad.scene.commands.source import AnalysisSource, resolve_source
from camcad.scene.fields import Field, read_table
from camcad.scene.sections.stops import STOPS_FIELDS, parse_stops


@dataclass(frozen=True)
class ImpactRequest:
    """Everything ``camcad impact`` can be asked: the lever (law files only; a scene's [stops] gives it),
    and --preload and --allowed, which override a scene's."""

    law: Any
    mass: float | None = None
    f_free: float | None = None
    f_stop: float | None = None
    restitution: float | None = None
    zeta: float | None = None
    preload: float | None = None
    stop: str | None = None
    ratio: float | None = None
    allowed: float | None = None


def _option(value, option: str, field: Field):
    return None if value is None else read_table({field.name: value}, [field], option)[field.name]


def stop_model(request: ImpactRequest, src: AnalysisSource) -> StopModel:
    """The scene's [stops] (with --preload and --allowed on top), or the lever given by the options
    (each checked as the [stops] key it stands for: one line naming the option)."""
    by_name = {f.name: f for f in STOPS_FIELDS}
    preload = _option(request.preload, "--preload", by_name["preload_mm"])
    allowed = _option(request.allowed, "--allowed", by_name["allowed_amplitude_mm"])
    if src.scene is not None:
        if src.section("stops") is None:
            raise CamcadError("the scene has no [stops] section", src.section_where("stops"),
                              "add [stops] with the lever, the stop stiffness, restitution, damping and preload")
        model = parse_stops(src.section("stops"), src.section_where("stops"))
        lever = {"--mass": request.mass, "--f-free": request.f_free, "--f-stop": request.f_stop,
                 "--restitution": request.restitution, "--zeta": request.zeta, "--stop": request.stop,
                 "--ratio": request.ratio}
        given = [name for name, value in lever.items() if value is not None]
        if given:
            raise CamcadError(f"{given[0]} given with a scene", given[0],
                              "change the scene's [stops] instead (only --preload, --allowed and --rpm override it)")
    else:
        needed = {"--mass": request.mass, "--f-free": request.f_free, "--f-stop": request.f_stop,
                  "--restitution": request.restitution, "--zeta": request.zeta, "--preload": request.preload}
        missing = [name for name, value in needed.items() if value is None]
        if missing:
            raise CamcadError(f"missing {', '.join(missing)}", "command line",
                              "give the lever's reduced mass, its frequencies free and on the stop, restitution, "
                              "damping and preload (or use a scene with [stops])")
        mass = _option(request.mass, "--mass", by_name["mass_kg"])
        f_free = _option(request.f_free, "--f-free", Field("f_free", "float", "Hz", positive=True))
        f_stop = _option(request.f_stop, "--f-stop", Field("f_stop", "float", "Hz", positive=True))
        restitution = _option(request.restitution, "--restitution", by_name["restitution"])
        zeta = _option(request.zeta, "--zeta", by_name["damping_ratio"])
        stop = _option(request.stop, "--stop", by_name["stop"]) or "upper"
        ratio = _option(request.ratio, "--ratio", by_name["ratio"]) or 1.0
        if not f_stop > f_free:
            raise CamcadError(f"f_free {f_free:g} Hz must be below f_stop {f_stop:g} Hz (need f_free < f_stop: the "
                              "stop adds stiffness)", "--f-free/--f-stop",
                              "give the frequency on the stop above the free one")
        c = mass * (2.0 * math.pi * f_free)**2
        model = StopModel(mass, c, mass * (2.0 * math.pi * f_stop)**2 - c, restitution, zeta, preload, stop, ratio,
                          allowed)
    if preload is not None:
        model = replace(model, preload_mm=preload)
    if allowed is not None:
        model = replace(model, allowed_amplitude_mm=allowed)
    return model


def run_impact_report(request: ImpactRequest, source: AnalysisSource | None = None, progress=None):
    """``camcad impact``: the lever's impact on its stop over the speeds, as an AnalysisReport (key
    ``impact``) whose ``result`` is the camcad.dynamics.runs.ImpactRun.

    A scene's mechanism is analysed as ``camcad profile`` analyses it (the pipeline's impact step on its
    machine: the [filter]ed law, the working member behind a [linkage], the cyclogram's phase angles), with
    --preload and --allowed written into its [stops]; a law file with the lever given by the options.

    Parameters
    ----------
    request : ImpactRequest
    source : AnalysisSource or None
        The law already resolved (default: ``resolve_source(request.law)``).
    progress : callable or None
        ``progress(done, total)`` after each speed.

    Returns
    -------
    camcad.scene.analysis_report.AnalysisReport
    """
    src = source if source is not None else resolve_source(request.law, command="impact")
    speeds = src.require_speeds("impact")
    model = stop_model(request, src)
    if src.scene is not None:
        given = {key: value for key, value in (("preload_mm", model.preload_mm),
                                                ("allowed_amplitude_mm", model.allowed_amplitude_mm))
                 if value is not None}
        src = src.with_overrides("stops", given)
        run = src.machine(("impact",), impact_progress=progress, impact_study=True).impact
        if run is None:
            raise CamcadError("the impact did not run", src.where, "give the scene a [machine] rpm or pass --rpm")
    else:
        applies = src.angles.describe() if src.angles is not None else ""
        run = run_impact(src.law, model, speeds, progress=progress, applies=applies)
    return AnalysisReport("impact", run.report, run.verdict, src.summary(), run)
