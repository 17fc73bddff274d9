"""The scene's [contact] section (materials, loads and the allowable stress) and ``camcad contact`` as one
library function (``run_contact``): every mechanism's Hertz stress along its profile at the phase angles
``camcad profile`` ends with, each check a figure, a limit and a margin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from camcad.contact import ContactParams
from camcad.errors import CamcadError
from camcad.scene.fields import Field, read_table
from camcad.verdict import Check, Verdict, Warning

#: a safety factor [σ_H]/σ_max below 1 + this (and a margin below this fraction of a limit) is warned about
CLOSE_TO_LIMIT = 0.05
#: a phase angle within this (relative, of max(1 deg, the limit)) of its least angle is at that angle
HELD_TOL_DEG = 1e-9


# --------------------------------------------------------------------------------------------
# Contact data from a scene ([contact] section)
# --------------------------------------------------------------------------------------------

CLOSURES = ("force", "form")

CONTACT_FIELDS: list[Field] = [
    Field("cam_modulus", unit="MPa", required=True, positive=True,
          help="(Young's modulus of the cam, e.g. 2.1e5 for steel)"),
    Field("cam_poisson", required=True, minimum=0.0, maximum=0.5,
          help="(Poisson's ratio of the cam, e.g. 0.3)"),
    Field("follower_modulus", unit="MPa", required=True, positive=True,
          help="(Young's modulus of the roller or flat face)"),
    Field("follower_poisson", required=True, minimum=0.0, maximum=0.5,
          help="(Poisson's ratio of the roller or flat face)"),
    Field("width", unit="mm", required=True, positive=True,
          help="(contact width L: the narrower of cam and roller)"),
    Field("mass", unit="kg", required=True, minimum=0.0,
          help="(follower mass reduced to the contact point)"),
    Field("allowable_stress", unit="MPa", required=True, positive=True,
          help="(allowable contact stress [sigma_H])"),
    Field("closure", "str", default="force", choices=CLOSURES,
          help="force: a spring keeps the follower on the cam; form: a groove or conjugate cam"),
    Field("spring_rate", unit="N/mm", minimum=0.0, help="(spring rate, needed for closure = force)"),
    Field("preload", unit="N", help="(spring force at the lowest follower position)"),
    Field("load", unit="N", help="(external or technological load on the follower, N)"),
    Field("load_range_deg", "list", unit="deg",
          help="([start, end] cam angles where the load acts; all the cycle if not given)"),
    Field("friction", minimum=0.0, help="(friction coefficient in the follower guide)"),
    Field("roller_radius", unit="mm", positive=True,
          help="(only when the [follower] section does not give it)"),
]





def parse_contact(table: Any, where: str) -> ContactParams:
    """A scene's ``[contact]`` section → ContactParams (unknown keys, missing values, wrong types
    and units give a one-line CamcadError naming ``where``)."""
    values = read_table(table, CONTACT_FIELDS, where)
    assumed: list[str] = []
    if values["closure"] == "force":
        for name, unit in (("spring_rate", "N/mm"), ("preload", "N")):
            if values[name] is None:
                raise CamcadError(f"missing value '{name}' ({unit}) for a force-closed follower", where,
                                  f"add {name} = ... or set closure = \"form\" for a groove cam")
        if values["spring_rate"] == 0.0 and values["preload"] <= 0.0:
            raise CamcadError("a force-closed follower needs a spring: spring_rate and preload are 0",
                              where, "give the spring's rate and preload, or closure = \"form\"")
    for name, unit in (("spring_rate", "N/mm"), ("preload", "N"), ("load", "N"), ("friction", "")):
        if values[name] is None:
            values[name] = 0.0
            if name in ("load", "friction") or values["closure"] == "force":
                assumed.append(f"{name} = 0{(' ' + unit) if unit else ''} (not given)")
    load_range = values["load_range_deg"]
    if load_range is not None:
        if (len(load_range) != 2 or any(isinstance(x, bool) or not isinstance(x, (int, float))
                                         for x in load_range)):
            raise CamcadError(f"'load_range_deg' must be [start, end] in deg, got {load_range!r}",
                              where, "write load_range_deg = [90.0, 180.0]")
        load_range = (float(load_range[0]), float(load_range[1]))
    return ContactParams(
        cam_modulus=values["cam_modulus"], cam_poisson=values["cam_poisson"],
        follower_modulus=values["follower_modulus"], follower_poisson=values["follower_poisson"],
        width=values["width"], mass=values["mass"], allowable_stress=values["allowable_stress"],
        closure=values["closure"], spring_rate=values["spring_rate"], preload=values["preload"],
        load=values["load"], load_range_deg=load_range, friction=values["friction"],
        roller_radius=values["roller_radius"], assumed=tuple(assumed))


# --------------------------------------------------------------------------------------------
# camcad contact
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class ContactRequest:
    """What ``camcad contact`` can be asked: the scene, one mechanism (default all), the speeds (--rpm text),
    samples per phase, and the phase angles ("auto": the cyclogram's when the scene has one)."""

    scene: Path
    mechanism: str | None = None
    rpm: str | None = None
    samples: int = 2000
    phase_angles: str = "auto"


@dataclass(frozen=True)
class MechanismContact:
    """One mechanism's contact analysis: its report (SPEC.md ``contact`` keys), the result at the worst
    speed and the speed sweep (for the plots), the phase angles analysed and the least ones."""

    name: str
    report: dict
    at_worst: Any
    sweep: Any
    angles: Any
    least: dict          # {phase label: (least angle deg, source, binding)}


def _least_from_cyclogram(found, mech_name: str) -> dict:
    """{phase label: (least angle deg, source)} of the mechanism's operations in an optimised cyclogram."""
    least = {}
    for op in found.operations_of(mech_name):
        if op.phase is None or op.phase == "dwell":
            continue
        label = op.phase if op.occurrence == 1 else f"{op.phase}_{op.occurrence}"
        for limit in found.limits.get(op.label, ()):
            if limit.source.startswith("contact"):
                least[label] = (limit.angle_deg, "contact stress", bool(limit.binding))
    return least


def contact_of_mechanism(scene, mech, speeds: list[float], samples: int, phase_angles: str = "auto",
                         found=None) -> MechanismContact:
    """The contact analysis of one mechanism on the law ``camcad profile`` analyses: its [law] at the
    cyclogram's phase angles (unless ``phase_angles`` is "law"; ``found``: the CyclogramAngles already
    computed), after its [filter] step."""
    from camcad.scene.analysis import (
        LawRequest,
        PhaseAngles,
        law_unit,
        scene_phase_angles,
    )
    from camcad.scene.file import mechanism_law
    from camcad.scene.filter import filter_step
    from camcad.scene.mechanism import law_with_phases

    base = mechanism_law(scene, mech).law
    request = LawRequest(phase_angles=phase_angles, samples=samples)
    if found is not None and phase_angles != "law" and found.phases.get(mech.name) is not None:
        angles = PhaseAngles("cyclogram", tuple(tuple(p) for p in found.phases[mech.name]), found.held_note(mech.name))
    elif found is not None and phase_angles != "law":
        angles = PhaseAngles.of_law(base, note="no operation of the cyclogram moves this mechanism")
    else:
        angles, found = scene_phase_angles(scene, mech, base, request, speeds)
    law = base
    if angles.source == "cyclogram":
        law = law_with_phases(base, list(angles.phases_deg), mech.where(scene.path, "law"))
    unit, _ = law_unit(scene, mech, None, law)
    step = filter_step(scene, mech, law, speeds, unit)
    least = _least_from_cyclogram(found, mech.name) if angles.source == "cyclogram" else None
    result = contact_step(scene, mech, step.law, speeds, samples, angles, least)
    if step.report is not None:
        result.report["notes"].append("the scene's [filter] was applied first, as camcad profile does")
    return result


def contact_step(scene, mech, law, speeds: list[float], samples: int, angles=None,
                 least: dict | None = None, memo=None, extra_load=None) -> MechanismContact:
    """Contact stress of one mechanism's ``law`` (the pipeline's step 7 and ``camcad contact``): the SPEC.md
    ``contact`` keys, the least normal force over the speeds, and the least phase angles — computed by root
    finding when ``least`` is None, else ``least`` ({label: (deg, source, binding)}, e.g. the cyclogram's)."""
    from camcad.scene.analysis import PhaseAngles
    from camcad.scene.mechanism import contact_params, mechanism_contact

    angles = angles if angles is not None else PhaseAngles.of_law(law)
    report, at_worst, sweep = mechanism_contact(scene, mech, speeds, samples, law=law, with_limits=least is None,
                                                memo=memo, extra_load=extra_load)
    if least is None:
        # mechanism_contact searches down to a tenth of the phase: a limit there does not bind
        widths = {}
        counts: dict[str, int] = {}
        for phase in law.phases:
            if phase.kind != "dwell":
                counts[phase.kind] = counts.get(phase.kind, 0) + 1
                key = phase.kind if counts[phase.kind] == 1 else f"{phase.kind}_{counts[phase.kind]}"
                widths[key] = math.degrees(phase.width)
        least = {label: (deg, "contact stress", abs(deg - 0.1 * widths.get(label, 0.0)) > 1e-9 * max(1.0, deg))
                 for label, deg in report["phase_limit_deg"].items() if deg is not None}
    else:
        report["phase_limit_deg"] = {label: value[0] for label, value in least.items()}
    report["phase_angles"] = angles.to_dict()
    params = contact_params(scene, mech)
    if params.closure == "force":
        report["normal_force_min_all_speeds_N"] = _min_force(scene, mech, law, speeds, samples, params)
    return MechanismContact(mech.name, report, at_worst, sweep, angles, least)


def _min_force(scene, mech, law, speeds, samples, params) -> dict | None:
    """The smallest normal force (N) over the speeds and where: the force-closed follower's hold on the cam."""
    from camcad.contact import contact_stress
    from camcad.scene.mechanism import contact_geometry, phase_grid, phases_deg

    geometry = contact_geometry(law, mech.sections.get("follower", {}), mech.where(scene.path, "follower"),
                                phase_grid(phases_deg(law), samples))
    worst = None
    for rpm in speeds:
        result = contact_stress(*geometry.arrays()[:7], rpm, params, geometry.rho_back)
        if worst is None or result.min_force < worst["value"]:
            worst = {"value": result.min_force, "at_deg": math.degrees(result.min_force_at), "rpm": float(rpm)}
    return worst


def contact_verdict(found: list[MechanismContact], speeds) -> Verdict:
    """Per mechanism: stress against [σ_H], the force-closed follower's least normal force against 0, and each
    motion's phase angle against the least one contact stress allows; warnings near the limits."""
    span = f"{min(speeds):g} rpm" if min(speeds) == max(speeds) else f"{min(speeds):g}-{max(speeds):g} rpm"
    checks: list[Check] = []
    warnings: list[Warning] = []
    for item in found:
        r, angles = item.report, item.angles
        whose = angles.describe()
        checks.append(Check(f"{item.name}: contact stress", r["sigma_max_MPa"], r["allowable_MPa"], "MPa",
                            applies=f"at {r['at_deg']:.4g} deg, {r['rpm']:g} rpm (worst of {span}); {whose}"))
        force = r.get("normal_force_min_all_speeds_N")
        if force is not None:
            checks.append(Check(f"{item.name}: normal force (spring holds the follower)", force["value"], 0.0, "N",
                                sense="min", applies=f"least at {force['at_deg']:.4g} deg, {force['rpm']:g} rpm; "
                                                     f"{whose}"))
        counts: dict[str, int] = {}
        for start, end, kind in angles.phases_deg:
            if kind == "dwell":
                continue
            counts[kind] = counts.get(kind, 0) + 1
            label = kind if counts[kind] == 1 else f"{kind}_{counts[kind]}"
            if label not in item.least:
                continue
            least, source, binding = item.least[label]
            width = float(end) - float(start)
            note = "" if binding else f"[sigma_H] is met down to {least:.4g} deg, where the search stopped: not binding"
            if abs(width - least) <= HELD_TOL_DEG * max(1.0, least):
                # the cyclogram's event times carry round-off: a phase held at its least angle is
                # at it, not 1e-14 deg under it
                width = least
                if angles.source == "cyclogram" and binding:
                    note = "held at its limit by the cyclogram"
            checks.append(Check(f"{item.name}: {label} phase angle", width, least, "deg", sense="min",
                                applies=f"least angle for [sigma_H] ({source}) over {span}; {whose}", note=note))
        safety = r["safety_factor"]
        if safety is not None and math.isfinite(safety) and safety < 1.0 + CLOSE_TO_LIMIT:
            warnings.append(Warning(f"{item.name}: safety factor {safety:.4g} is within "
                                    f"{100 * abs(safety - 1.0):.2g} % of 1 ({r['sigma_max_MPa']:.4g} MPa against "
                                    f"{r['allowable_MPa']:g} MPa)", safety, f"safety factor < {1 + CLOSE_TO_LIMIT:g}"))
        sep = r.get("versus_speed", {}).get("separation_rpm")
        if sep is not None and not r["separation"] and sep < (1.0 + CLOSE_TO_LIMIT) * max(speeds):
            warnings.append(Warning(f"{item.name}: the follower leaves the cam from {sep:.4g} rpm, within "
                                    f"{100 * (sep / max(speeds) - 1):.2g} % of the top speed {max(speeds):g} rpm",
                                    sep, "separation speed < 1.05 x the top speed"))
    return Verdict(tuple(checks), tuple(warnings))


def run_contact(request: ContactRequest):
    """``camcad contact``: Hertz stress along each mechanism's profile over the speeds, as an AnalysisReport
    (key ``contact``) whose ``result`` is the list of MechanismContact.

    The phase angles are those ``camcad profile SCENE`` ends with: the optimised cyclogram's when the scene
    has a [cyclogram] (``phase_angles`` "auto" or "cyclogram"), else the law's own; each mechanism's report
    says which (``phase_angles``).

    Parameters
    ----------
    request : ContactRequest

    Returns
    -------
    camcad.scene.analysis.AnalysisReport
    """
    from camcad.scene.analysis import AnalysisReport, require_scene
    from camcad.scene.fields import parse_speeds
    from camcad.scene.file import read_scene

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
    found = None
    if request.phase_angles != "law" and scene.cyclogram is not None and with_contact[0].prefix:
        from camcad.scene.phase_angles import cyclogram_angles

        found = cyclogram_angles(scene, speeds, request.samples)
        if not found.result.feasible:
            raise CamcadError(f"the scene's cyclogram is infeasible, so it has no phase angles "
                              f"({found.result.explanation})", f"{path} [cyclogram]",
                              "run camcad cyclogram to see the conflict, or use --phase-angles law")
    elif request.phase_angles == "cyclogram":
        raise CamcadError("the scene has no [cyclogram]", str(path), "use --phase-angles law, or add a [cyclogram]")
    results = [contact_of_mechanism(scene, mech, speeds, request.samples, request.phase_angles, found)
               for mech in with_contact]
    verdict = contact_verdict(results, speeds)
    reports = {item.name: item.report for item in results}
    worst = max(results, key=lambda item: item.report["sigma_max_MPa"])
    body = {key: worst.report[key] for key in ("sigma_max_MPa", "at_deg", "safety_factor", "phase_limit_deg", "rpm")}
    body.update(separation=any(r["separation"] for r in reports.values()), mechanism=worst.name,
                speeds_rpm=list(speeds), mechanisms=reports,
                phase_angles={item.name: item.angles.to_dict() for item in results})
    source = {"scene": str(path), "name": scene.name,
              "phase_angles": ("the cyclogram's (as camcad profile uses them)" if found is not None
                               else "the laws' own")}
    return AnalysisReport("contact", body, verdict, source, results, skipped)

