"""The pipeline's contact step (step 7): one mechanism's Hertz stress along its profile over the speeds, its
least phase angles, and the verdict (each check a figure, a limit and a margin, at the phase angles analysed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from camcad.contact import contact_stress
from camcad.scene.analysis_report import PhaseAngles
from camcad.scene.laws import phases_deg
from camcad.scene.mechanism import contact_geometry, contact_params, mechanism_contact, phase_grid
from camcad.verdict import Check, Verdict, Warning

#: a safety factor [σ_H]/σ_max below 1 + this (and a margin below this fraction of a limit) is warned about
CLOSE_TO_LIMIT = 0.05
#: a phase angle within this (relative, of max(1 deg, the limit)) of its least angle is at that angle
HELD_TOL_DEG = 1e-9


@dataclass(frozen=True)
class MechanismContact:
    """One mechanism's contact analysis: its report (docs/INTERFACE.md ``contact`` keys), the result at the worst
    speed and the speed sweep (for the plots), the phase angles analysed and the least ones."""

    name: str
    report: dict
    at_worst: Any
    sweep: Any
    angles: Any
    least: dict          # {phase label: (least angle deg, source, binding)}


def contact_step(scene, mech, law, speeds: list[float], samples: int, angles=None,
                 least: dict | None = None, memo=None, extra_load=None) -> MechanismContact:
    """Contact stress of one mechanism's ``law`` (the pipeline's step 7 and ``camcad contact``): the docs/INTERFACE.md
    ``contact`` keys, the least normal force over the speeds, and the least phase angles — computed by root
    finding when ``least`` is None, else ``least`` ({label: (deg, source, binding)}, e.g. the cyclogram's)."""
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
                                                     f"{whose}", scale=float(r.get("normal_force_max_N", 0.0))))
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


