"""``camcad contact`` as one library function (``run_contact``): every mechanism's Hertz stress along its profile
at the phase angles ``camcad profile`` ends with, each check a figure, a limit and a margin.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

from camcad.errors import CamcadError
from camcad.scene.analysis_report import AnalysisReport
from camcad.scene.commands.source import require_scene
from camcad.scene.contact import contact_verdict
from camcad.scene.fields import parse_speeds
from camcad.scene.file import read_scene
from camcad.scene.pipeline import PipelineOptions, analyse_scene


@dataclass(frozen=True)
class ContactRequest:
    """What ``camcad contact`` can be asked: the scene, one mechanism (default all), the speeds (--rpm text),
    samples per phase, and the phase angles ("auto": the cyclogram's when the scene has one)."""

    scene: Path
    mechanism: str | None = None
    rpm: str | None = None
    samples: int = 2000
    phase_angles: str = "auto"


def run_contact(request: ContactRequest):
    """``camcad contact``: Hertz stress along each mechanism's profile over the speeds, as an AnalysisReport
    (key ``contact``) whose ``result`` is the list of MechanismContact.

    Each mechanism is analysed as ``camcad profile`` analyses it: the pipeline's contact step on its machine
    (the [filter]ed law, the working member's inertia and load behind a [linkage], the law's unit).

    The phase angles are those ``camcad profile SCENE`` ends with: the optimised cyclogram's when the scene
    has a [cyclogram] (``phase_angles`` "auto" or "cyclogram"), else the law's own; each mechanism's report
    says which (``phase_angles``).

    Parameters
    ----------
    request : ContactRequest

    Returns
    -------
    camcad.scene.analysis_report.AnalysisReport
    """
    if isinstance(request.samples, bool) or not isinstance(request.samples, int) or not 16 <= request.samples <= 10**6:
        raise CamcadError(f"--samples {request.samples} is not in 16..1000000", "--samples",
                          "give the cam-angle samples per phase, e.g. 2000")
    path = require_scene(Path(request.scene), "contact")
    scene = read_scene(path)
    if not scene.mechanisms:
        raise CamcadError("the scene has no mechanism", str(path), "add [law], [follower] and [contact]")
    group = [scene.mechanism(request.mechanism)] if request.mechanism is not None else list(scene.mechanisms)
    speeds = parse_speeds(request.rpm, "--rpm") if request.rpm is not None else (
        list(scene.speeds_rpm) if scene.speeds_rpm else None)
    if speeds is None:
        raise CamcadError("no speed given", f"{path} [machine]", "add [machine] rpm = ... or pass --rpm")
    if request.phase_angles not in ("auto", "law", "cyclogram"):
        raise CamcadError(f"--phase-angles {request.phase_angles!r} is not one of auto, law, cyclogram",
                          "--phase-angles", "use law (the law's own) or cyclogram (the optimised cyclogram's)")
    with_contact = [m for m in group if m.has("contact")]
    skipped = {m.name: "no [contact] section" for m in group if not m.has("contact")}
    if not with_contact:
        raise CamcadError("no mechanism has a [contact] section", str(path),
                          "add [contact] (materials, loads, allowable stress) to a mechanism")
    scene = replace(scene, speeds_rpm=tuple(speeds))
    options = PipelineOptions(plots=(), contact_samples=request.samples, models=("contact",),
                              mechanisms=tuple(m.name for m in with_contact),
                              use_cyclogram=request.phase_angles != "law")
    if request.phase_angles == "cyclogram" and (scene.cyclogram is None or not with_contact[0].prefix):
        raise CamcadError("the scene has no [cyclogram]", str(path), "use --phase-angles law, or add a [cyclogram]")
    result = analyse_scene(scene, options)
    cyclogram = result.report.get("cyclogram")
    if cyclogram is not None and not cyclogram["feasible"]:
        raise CamcadError(f"the scene's cyclogram is infeasible, so it has no phase angles "
                          f"({cyclogram.get('explanation', '')})", f"{path} [cyclogram]",
                          "run camcad cyclogram to see the conflict, or use --phase-angles law")
    results = [result.runs[m.name].contact for m in with_contact]
    verdict = contact_verdict(results, speeds)
    reports = {item.name: item.report for item in results}
    worst = max(results, key=lambda item: item.report["sigma_max_MPa"])
    body = {key: worst.report[key] for key in ("sigma_max_MPa", "at_deg", "safety_factor", "phase_limit_deg", "rpm")}
    body.update(separation=any(r["separation"] for r in reports.values()), mechanism=worst.name,
                speeds_rpm=list(speeds), mechanisms=reports,
                phase_angles={item.name: item.angles.to_dict() for item in results})
    source = {"scene": str(path), "name": scene.name,
              "phase_angles": ("the cyclogram's (as camcad profile uses them)" if cyclogram is not None
                               else "the laws' own")}
    return AnalysisReport("contact", body, verdict, source, results, skipped)
