"""``camcad cyclogram`` as one library function (``run_cyclogram``): the group's network optimised with every
operation's phase limits — the same step ``camcad profile`` runs (camcad.scene.phase_angles).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import cast

from camcad.errors import CamcadError
from camcad.scene.analysis_report import AnalysisReport
from camcad.scene.commands.source import require_scene
from camcad.scene.fields import parse_speeds
from camcad.scene.file import read_scene
from camcad.scene.phase_angles import CyclogramAngles, cyclogram_angles, cyclogram_verdict
from camcad.scene.pipeline import PipelineOptions, analyse_scene


@dataclass(frozen=True)
class CyclogramRequest:
    """What ``camcad cyclogram`` can be asked: the scene, the speeds (--rpm text) and samples per phase."""

    scene: Path
    rpm: str | None = None
    samples: int = 2000


def run_cyclogram(request: CyclogramRequest):
    """``camcad cyclogram``: the group's network optimised with every operation's phase limits (the same
    function ``camcad profile`` uses, camcad.scene.phase_angles), as an AnalysisReport (key ``cyclogram``)
    whose ``result`` is the CyclogramAngles.

    Parameters
    ----------
    request : CyclogramRequest

    Returns
    -------
    camcad.scene.analysis_report.AnalysisReport
    """
    if isinstance(request.samples, bool) or not isinstance(request.samples, int) or not 16 <= request.samples <= 10**6:
        raise CamcadError(f"--samples {request.samples} is not in 16..1000000", "--samples",
                          "give the cam-angle samples per phase, e.g. 2000")
    path = require_scene(Path(request.scene), "cyclogram")
    scene = read_scene(path)
    if scene.cyclogram is None:
        raise CamcadError("the scene has no [cyclogram] section", str(path),
                          "add [cyclogram] with [[cyclogram.operations]] (from, to, bounds_deg)")
    speeds = parse_speeds(request.rpm, "--rpm") if request.rpm is not None else (
        list(scene.speeds_rpm) if scene.speeds_rpm else None)
    if scene.mechanisms:
        # the same step 9 camcad profile runs: each operation's limits from its mechanism's machine
        if speeds is not None:
            scene = replace(scene, speeds_rpm=tuple(speeds))
        result = analyse_scene(scene, PipelineOptions(plots=(), contact_samples=request.samples, models=(),
                                                      mechanisms=()))
        found = cast(CyclogramAngles, result.cyclogram)    # the scene has a [cyclogram], so step 9 ran
    else:
        found = cyclogram_angles(scene, speeds, request.samples)
    body = found.report()
    title = (scene.cyclogram or {}).get("name") or scene.name
    source = {"scene": str(path), "name": scene.name, "title": str(title)}
    return AnalysisReport("cyclogram", body, cyclogram_verdict(found), source, found, dict(found.skipped))

