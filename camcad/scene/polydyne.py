"""The pipeline's polydyne step (loaded with ``camcad.scene.models``): with ``[dynamics] polydyne_rpm`` (or
``camcad profile … --polydyne RPM``) the cam is designed for the elastic follower (``camcad.dynamics.polydyne``):
the law becomes the wanted motion of the driven mass, and the cam's motion the compensated one; the report says
the law's class, what it implies for the cam, and the residual vibration before and after at the design speed and
at every speed of the scene.
"""

from __future__ import annotations

import math
from typing import Any

from camcad.dynamics.polydyne import polydyne_law, residual_about
from camcad.errors import CamcadError
from camcad.scene.analysis_report import rounded_tree
from camcad.scene.sections.dynamics import parse_dynamics


def polydyne_step(scene, mech, run, speeds, rpm: float) -> None:
    """Replace ``run.law`` by the polydyne cam for ``rpm`` and put the ``polydyne`` object in ``run.report``."""
    where = mech.where(scene.path, "dynamics")
    if not mech.has("dynamics"):
        raise CamcadError("a polydyne cam needs the elastic follower", mech.where(scene.path, "law"),
                          "add [dynamics] with natural_frequency_hz and damping_ratio (docs/drive.md)")
    if run.linkage is not None:
        raise CamcadError("a polydyne cam behind a [linkage] is not covered (the working member's chain would need "
                          "the compensation through the position function)", where, "drop polydyne_rpm")
    settings = parse_dynamics(mech.sections["dynamics"], where, math.degrees(run.law.cycle))
    if not settings.follower.constant_stiffness:
        raise CamcadError("a polydyne cam needs a constant stiffness (the compensation K y'' holds for one c)",
                          where, "drop stiffness_variation or polydyne_rpm")
    wanted = run.law
    cam, notes = polydyne_law(wanted, settings.follower, rpm)
    before = residual_about(wanted, wanted, settings.follower, rpm)
    after = residual_about(cam, wanted, settings.follower, rpm)
    unit = settings.output_unit
    per_speed: list[dict[str, Any]] = []
    for n in sorted(set(speeds or ()) | {float(rpm)}):
        b = residual_about(wanted, wanted, settings.follower, n)
        a = residual_about(cam, wanted, settings.follower, n)
        per_speed.append({"rpm": n, f"before_{unit}": max(r.amplitude for r in b),
                          f"after_{unit}": max(r.amplitude for r in a)})
    run.law = cam
    run.report["polydyne"] = rounded_tree({
        "design_rpm": float(rpm), "ratio_K_rad2": cam.ratio, "lag_rad": cam.lag,
        "natural_frequency_hz": settings.follower.natural_frequency_hz,
        "damping_ratio": settings.follower.damping_ratio, "unit": unit,
        f"residual_before_{unit}": {r.phase.kind: r.amplitude for r in before},
        f"residual_after_{unit}": {r.phase.kind: r.amplitude for r in after},
        "per_speed": per_speed, "notes": notes,
        "dynamics_note": "the [dynamics] step analyses the polydyne cam: its dynamic error is the follower's "
                         "deviation from the cam's motion, by design K y'' mid-stroke; the residual vibration here "
                         "is about the wanted law"})
    run.ran.append("polydyne")
