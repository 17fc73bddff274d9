"""The pipeline's cyclogram step (step 9): the phase angles of a group scene's optimised cyclogram, and its verdict.

``camcad profile SCENE`` optimises the [cyclogram] with each operation's phase-angle limits (contact stress,
pressure angle, the vibration relation, the impact rebound of a mechanism with [stops]) and regenerates every
mechanism with the optimal angles. ``cyclogram_angles`` does exactly that part, so ``camcad contact``,
``dynamics``, ``impact``, ``spectrum`` and ``cyclogram`` analyse the same phase angles as ``camcad profile``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from camcad.cyclogram.limits import PhaseLimit
from camcad.cyclogram.lp import optimise
from camcad.cyclogram.retime import format_phases
from camcad.dynamics.runs import run_impact
from camcad.errors import CamcadError
from camcad.scene.filtering import filter_step
from camcad.scene.laws import mechanism_law
from camcad.scene.mechanism import cyclogram_limits, retimed_phases
from camcad.scene.sections.cyclogram import parse_cyclogram
from camcad.scene.sections.stops import parse_stops
from camcad.verdict import Check, Verdict, Warning

#: cycle slack below this fraction of the cycle is warned about
CLOSE_TO_LIMIT = 0.05
#: a phase angle within this (relative, of max(1 deg, the bound)) of a bound is on the bound
HELD_TOL_DEG = 1e-9

# --------------------------------------------------------------------------------------------
# camcad cyclogram
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class CyclogramAngles:
    """An optimised cyclogram and what it does to the mechanisms.

    ``result``: camcad.cyclogram.CyclogramResult; ``network``; ``limits``: {operation label: [PhaseLimit]};
    ``skipped``: limits not computed and why; ``phases``: {mechanism: [(start_deg, end_deg, kind)]}, the
    retimed phases; ``speeds``: the speeds (rpm) the limits were computed at.
    """

    result: Any
    network: Any
    limits: dict
    skipped: dict
    phases: dict
    speeds: list | None = None
    impacts: dict = field(default_factory=dict)

    def report(self) -> dict:
        """The docs/INTERFACE.md ``cyclogram`` keys (and more), with the retimed phases as text."""
        out = self.result.report()
        out["skipped"] = dict(self.skipped)
        out["speeds_rpm"] = None if self.speeds is None else list(self.speeds)
        out["phase_limits"] = {label: [{"deg": limit.angle_deg, "source": limit.source, "value": limit.value,
                                        "limit": limit.limit, "binding": limit.binding, "note": limit.note}
                                       for limit in found] for label, found in self.limits.items()}
        if self.result.feasible:
            out["phases"] = {name: format_phases(phases) for name, phases in self.phases.items()}
        return out

    def operations_of(self, mechanism: str) -> list:
        return [op for op in self.network.operations if op.mechanism == mechanism]

    def held_note(self, mechanism: str) -> str:
        """Which of the mechanism's operations the cyclogram holds at a limit (an active lower bound)."""
        if not self.result.feasible:
            return ""
        active = {(c.label, c.kind): c for c in self.result.active}
        held = []
        for op in self.operations_of(mechanism):
            bound = active.get((op.label, "min"))
            if bound is not None:
                held.append(f"the {op.phase or op.label} at its least angle {bound.bound:.6g} deg ({bound.source})")
        return ("the cyclogram holds " + "; ".join(held)) if held else ""

    def contact_least(self, mechanism: str) -> dict:
        """{phase label: (least angle deg, "contact stress", binding)} of the mechanism's operations whose
        least angle comes from contact stress."""
        least = {}
        for op in self.operations_of(mechanism):
            if op.phase is None or op.phase == "dwell":
                continue
            label = op.phase if op.occurrence == 1 else f"{op.phase}_{op.occurrence}"
            for limit in self.limits.get(op.label, ()):
                if limit.source.startswith("contact"):
                    least[label] = (limit.angle_deg, "contact stress", bool(limit.binding))
        return least


def impact_phase_limit(scene, mech, speeds, law=None):
    """(ImpactRun, stop phase kind) of a mechanism with [stops] on its analysis law (the pipeline's step 6),
    or (None, None) without [stops] or speeds."""
    if not mech.has("stops") or not speeds:
        return None, None
    if law is None:
        law = mechanism_law(scene, mech).law
        step = filter_step(scene, mech, law, speeds)
        law = step.law
    model = parse_stops(mech.sections["stops"], mech.where(scene.path, "stops"))
    run = run_impact(law, model, list(speeds))
    return run, ("rise" if model.stop == "upper" else "return")


def cyclogram_angles(scene, speeds, samples: int, impacts: dict | None = None, memo=None) -> CyclogramAngles:
    """Optimise the scene's [cyclogram] with every operation's phase-angle limits and retime the mechanisms.

    Parameters
    ----------
    scene : camcad.scene.file.Scene
        A scene with a [cyclogram].
    speeds : list of float or None
        Speeds (rpm) for the contact-stress and impact limits; None skips them (said in ``skipped``).
    samples : int
        Cam-angle samples per phase for the contact-stress maxima.
    impacts : dict or None
        {mechanism: ImpactRun} already computed (the pipeline's step 6); None computes them for every
        mechanism with [stops].
    memo : camcad.scene.mechanism.LimitMemo, optional
        Least phase angles already solved in this run (the pipeline's), reused where they apply.

    Returns
    -------
    CyclogramAngles
    """
    network, limits, skipped, found_impacts = group_limits(scene, speeds, samples, impacts, memo)
    # the least makespan; the operations off its critical path keep the largest smallest margin
    result = optimise(network, limits, strict=False, where=f"{scene.path} [cyclogram]", schedule="leximin")
    phases = retimed_phases(scene, result) if result.feasible else {}
    return CyclogramAngles(result, network, limits, skipped, phases, None if speeds is None else list(speeds),
                           found_impacts)


def group_limits(scene, speeds, samples: int, impacts: dict | None = None, memo=None):
    """The scene's [cyclogram] network and every operation's phase-angle limits (contact stress, pressure
    angle, the vibration relation, the impact rebound of a mechanism with [stops]), not yet optimised: what
    ``cyclogram_angles`` optimises for one group and ``camcad.scene.machine`` for a machine of groups.

    Returns (network, limits {label: [PhaseLimit]}, skipped {what: why}, impacts {mechanism: ImpactRun}).
    """
    if scene.cyclogram is None:
        raise CamcadError("the scene has no [cyclogram] section", str(scene.path),
                          "add [cyclogram] with [[cyclogram.operations]] (from, to, bounds_deg)")
    where = f"{scene.path} [cyclogram]"
    network = parse_cyclogram(scene.cyclogram, where, [m.name for m in scene.mechanisms if m.prefix])
    limits, skipped = cyclogram_limits(scene, network, speeds, samples, memo=memo)
    by_name = {m.name: m for m in scene.mechanisms}
    found_impacts = dict(impacts or {})
    for op in network.operations:
        if op.mechanism is None or op.phase is None or op.mechanism not in by_name:
            continue
        mech = by_name[op.mechanism]
        if not mech.has("stops"):
            continue
        if op.mechanism not in found_impacts:
            if impacts is not None or not speeds:
                if not speeds:
                    skipped[f"impact limit {op.label}"] = "no [machine] rpm"
                continue
            found_impacts[op.mechanism] = impact_phase_limit(scene, mech, speeds)[0]
        run = found_impacts[op.mechanism]
        if run is None:
            continue
        stop_phase = "rise" if run.model.stop == "upper" else "return"
        angle = run.report.get("phase_limit_deg")
        if angle is not None and op.phase == stop_phase:
            allowed = run.model.allowed_amplitude_mm
            limits.setdefault(op.label, []).append(PhaseLimit(
                angle_deg=float(angle), source="impact rebound", value=allowed, limit=allowed, binding=True,
                note=f"rebound at the stop of {op.mechanism} within {allowed:g} mm"))
    return network, limits, skipped, found_impacts


def cyclogram_verdict(found) -> Verdict:
    """The checks of an optimised cyclogram (camcad.scene.phase_angles.CyclogramAngles): feasible; the
    makespan against the cycle; every operation's phase angle against its least admissible one (its
    designer's bound or a phase limit, whichever is larger), active ones noted as holding the makespan;
    a finite upper bound that is active. Warnings: little cycle slack, operations held at a phase limit."""
    result = found.result
    if not result.feasible:
        return Verdict((Check("cyclogram feasible", None, None, passed_override=False, note=result.explanation),), ())
    network = result.network
    checks = [Check("makespan", float(result.makespan_deg), float(network.cycle_deg), "deg",
                    applies=f"p({network.end}) - p({network.start}) within the cycle")]
    active = {(c.label, c.kind) for c in result.active}
    warnings = []
    for op in network.operations:
        angle = float(result.phase_angles_deg[op.label])
        least, source = result.lower_bounds_deg[op.label]
        # the times are sums of bounds and carry their round-off: an angle that close to a bound is on it
        for bound in (float(least), float(op.max_deg)):
            if math.isfinite(bound) and abs(angle - bound) <= HELD_TOL_DEG * max(1.0, abs(bound)):
                angle = bound
        name = f"{op.label} {op.name}".strip()
        what = f"{op.mechanism} {op.phase}" if op.mechanism and op.phase else "operation"
        held = (op.label, "min") in active
        note = "active: holds the makespan" if held else ""
        if least > 0 or op.mechanism:
            checks.append(Check(f"phase angle {name}", angle, float(least), "deg", sense="min",
                                applies=f"{what}; least angle from {source}", note=note))
        if math.isfinite(op.max_deg) and (op.label, "max") in active:
            checks.append(Check(f"phase angle {name} (upper bound)", angle, float(op.max_deg), "deg",
                                applies=f"{what}; bounds_deg", note="active: holds the makespan"))
        if held and source != "bounds_deg":
            warnings.append(Warning(f"{name} ({what}) is held at its least angle {least:.6g} deg by {source}: "
                                    "it sets the makespan", least, "an active phase limit"))
    slack = float(network.cycle_deg - result.makespan_deg)
    if slack < CLOSE_TO_LIMIT * network.cycle_deg:
        warnings.append(Warning(f"the group fills {result.makespan_deg:.6g} of its {network.cycle_deg:g} deg: "
                                f"{slack:.3g} deg to spare", slack, f"cycle slack < {100 * CLOSE_TO_LIMIT:g} %"))
    return Verdict(tuple(checks), tuple(warnings))
