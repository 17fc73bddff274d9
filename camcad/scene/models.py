"""The pipeline's model steps, loaded only for a scene that has a model: the filter (step 3), the linkage, the
elastic dynamics (5), the stop impact (6), the contact stress (7) and the cyclogram (9).

``camcad.scene.pipeline`` imports this module when a mechanism has one of those sections, so that
``camcad profile`` of a plain cam imports no model (numpy's FFT, scipy's optimisers; tests/project/test_startup.py).
The stand-alone commands (``camcad.scene.commands``) import it directly.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

from camcad.dynamics.runs import run_dynamics, run_impact
from camcad.profile.scaled_law import ScaledLaw
from camcad.scene.analysis_report import rounded_tree
from camcad.scene.contact import contact_step, contact_verdict
from camcad.scene.filtering import filter_step
from camcad.scene.laws import pipeline_angles
from camcad.scene.linkage import linkage_step, prepare, unit_scale
from camcad.scene.phase_angles import CyclogramAngles, cyclogram_angles, cyclogram_verdict
from camcad.scene.polydyne import polydyne_step
from camcad.scene.sections.dynamics import parse_dynamics
from camcad.scene.sections.filter import parse_filter
from camcad.scene.sections.stops import parse_stops, published_of

if TYPE_CHECKING:   # the pipeline imports this module, not the reverse
    from camcad.scene.file import Scene
    from camcad.scene.pipeline import MechanismRun, PipelineOptions

__all__ = ["contact_step_of", "cyclogram_step", "dynamics_step", "filter_step", "impact_step", "linkage_step",
           "model_law", "model_unit", "polydyne_step", "prepare"]


def model_law(run: MechanismRun):
    """The law the models (dynamics, impact) analyse: the working member's behind a [linkage], else the
    mechanism's law (a swing in deg turned into rad)."""
    if run.linkage is not None and run.linkage.law_of == "output" and run.linkage.setting is None:
        # the cam is designed so that the nominal linkage's working member does the [law]: y = Π(ψ(θ)) is that
        # law (to the round trip the linkage report states), in the working member's unit — exact, and cheap for
        # the time path; an adjusted setting moves the member otherwise (Π of that setting, below)
        return ScaledLaw(run.output_law, unit_scale(run.linkage.spec.output_unit))
    if run.linkage is not None:
        return run.linkage.working_law(run.law)
    return ScaledLaw(run.law, math.pi / 180.0) if run.unit == "deg" else run.law


def model_unit(run: MechanismRun) -> str:
    """The unit of ``model_law(run)``'s displacement: mm or rad (the working member's behind a [linkage])."""
    if run.linkage is not None:
        return run.linkage.transfer.unit_out
    return "rad" if run.unit == "deg" else run.unit


def dynamics_step(scene, mech, run, speeds, options, where, limits) -> None:
    """Step 5: the elastic follower (``[dynamics]``) over the speeds, on ``model_law(run)``."""
    settings = replace(parse_dynamics(mech.sections["dynamics"], where, math.degrees(run.law.cycle)),
                       output_unit=model_unit(run))
    lead = None
    if mech.has("filter"):
        filt = parse_filter(mech.sections["filter"], mech.where(scene.path, "filter"))
        if filt.lead_in_deg is not None and "filter" not in run.ran:
            lead = (filt.lead_in_deg, filt.lead_in_fraction)
    extras = options.dynamics_extras
    progress = compare = None
    compare_name = ""
    if extras is not None:
        if extras.lead_in is not None and "filter" not in run.ran:   # a filtered law has its lead-in already
            lead = extras.lead_in
        progress, compare, compare_name = extras.progress, extras.compare, extras.compare_name
    run.dynamics = run_dynamics(model_law(run), settings, speeds, progress=progress, lead_in=lead, compare=compare,
                                compare_name=compare_name, applies=pipeline_angles(scene, mech, run.law).describe())
    run.report["dynamics"] = rounded_tree(run.dynamics.to_dict())


def impact_step(scene, mech, run, speeds, options, where, limits) -> None:
    """Step 6: the stop impact (``[stops]``) over the speeds, on ``model_law(run)``."""
    model = parse_stops(mech.sections["stops"], where)
    run.impact = run_impact(model_law(run), model, speeds, progress=options.impact_progress,
                            applies=pipeline_angles(scene, mech, run.law).describe(),
                            published=published_of(mech.sections["stops"], where), study=options.impact_study)
    run.report["impact"] = rounded_tree(run.impact.to_dict())


def contact_step_of(scene, mech, run, speeds, options, where, limits) -> None:
    """Step 7: Hertz contact stress (``[contact]``) along the profile over the speeds; its least phase angles
    found by root finding (``limits``) or the cyclogram's (``run.contact_least``)."""
    extra = None if run.linkage is None else (lambda theta: run.linkage.load_on(run.law, theta))  # [linkage]
    found = contact_step(scene, mech, run.law, speeds, options.contact_samples, pipeline_angles(scene, mech, run.law),
                         None if limits else dict(run.contact_least or {}), memo=run.memo, extra_load=extra)
    run.contact = found
    run.report["contact"] = rounded_tree({**found.report, **contact_verdict([found], speeds).to_dict()})


# --------------------------------------------------------------------------------------------
# 9 cyclogram
# --------------------------------------------------------------------------------------------

def cyclogram_step(scene: Scene, runs: dict, options: PipelineOptions,
                   angles: CyclogramAngles | None = None) -> tuple[dict, CyclogramAngles]:
    """Optimise the network with the operations' limits (or take ``angles`` decided by a machine of groups,
    ``camcad.scene.machine``); return (report, the CyclogramAngles)."""
    speeds = list(scene.speeds_rpm) if scene.speeds_rpm else None
    # the impact rebound limit of a mechanism with [stops] bounds the phase that approaches its stop
    impacts = {name: run.impact for name, run in runs.items() if run.impact is not None}
    memo = next(iter(runs.values())).memo if runs else None
    found = angles if angles is not None else cyclogram_angles(scene, speeds, options.contact_samples,
                                                               impacts=impacts, memo=memo)
    report = rounded_tree({**found.report(), **cyclogram_verdict(found).to_dict()})
    return report, found


