"""The phase angles of a group scene's optimised cyclogram: one function for the pipeline and every command.

``camcad profile SCENE`` optimises the [cyclogram] with each operation's phase-angle limits (contact stress,
pressure angle, the vibration relation, the impact rebound of a mechanism with [stops]) and regenerates every
mechanism with the optimal angles. ``cyclogram_angles`` does exactly that part, so ``camcad contact``,
``dynamics``, ``impact``, ``spectrum`` and ``cyclogram`` analyse the same phase angles as ``camcad profile``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from camcad.errors import CamcadError


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
        """The SPEC.md ``cyclogram`` keys (and more), with the retimed phases as text."""
        from camcad.cyclogram.retime import format_phases

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


def impact_phase_limit(scene, mech, speeds, law=None):
    """(ImpactRun, stop phase kind) of a mechanism with [stops] on its analysis law (the pipeline's step 6),
    or (None, None) without [stops] or speeds."""
    if not mech.has("stops") or not speeds:
        return None, None
    from camcad.dynamics.runs import run_impact
    from camcad.scene.file import mechanism_law
    from camcad.scene.filter import filter_step
    from camcad.scene.stops import parse_stops

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
    from camcad.cyclogram.lp import optimise
    from camcad.scene.mechanism import retimed_phases

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
    from camcad.cyclogram.limits import PhaseLimit
    from camcad.scene.cyclogram import parse_cyclogram
    from camcad.scene.mechanism import cyclogram_limits

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
