"""Dynamics and stop-impact analyses of one law, as reports: what `camcad dynamics`, `camcad impact` and
the scene pipeline (steps 5, 6 and 8 of SPEC.md) share.

The models are in camcad.dynamics.sdof, .multimass and .impact; this module runs them over the machine's
speeds and gathers the figures under the SPEC.md ``dynamics`` and ``impact`` keys (plus a ``passed`` flag
against the limits the settings give).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np


@dataclass(frozen=True)
class DynamicsRun:
    report: dict
    sweep: Any
    keep: tuple[float, ...]
    settings: Any


def run_dynamics(law, settings, speeds: list[float], *, progress: Callable | None = None,
                 lead_in: tuple[float, float] | None = None, compare=None, compare_name: str = "") -> DynamicsRun:
    """The elastic follower over ``speeds`` (rpm): SPEC.md ``dynamics`` keys, start-of-motion loads, the
    multi-mass model when the settings have one, the limit checks and ``passed``.

    lead_in: (angle deg, fraction) — compare with lead-in segments before each motion (camcad.fourier).
    compare: a second law whose start-of-motion load is compared.
    """
    from camcad.dynamics.model import OUTPUT_UNITS
    from camcad.dynamics.residual import residual_vibration
    from camcad.dynamics.steady import sweep

    follower = settings.follower
    fastest = max(speeds)
    keep = tuple(sorted({speeds[0], fastest}))
    result = sweep(law, follower, speeds, method=settings.method, samples=settings.samples, solver=settings.solver,
                   rtol=settings.rtol, keep=keep, progress=progress)
    unit = OUTPUT_UNITS[settings.output_unit]
    residuals = residual_vibration(law, follower, speeds[0])
    by_kind = {"rise": 0.0, "return": 0.0}
    for item in residuals:
        by_kind[item.phase.kind] = max(by_kind[item.phase.kind], item.amplitude)
    report: dict[str, Any] = {
        "natural_frequency_hz": follower.natural_frequency_hz, "damping_ratio": follower.damping_ratio,
        "mass_kg": follower.mass_kg, "variable_stiffness": not follower.constant_stiffness,
        "unit": unit.name, "speeds_rpm": list(result.speeds_rpm), "peak_accel_ratio": list(result.peak_accel_ratio),
        "dynamic_error_max_mm": list(result.dynamic_error_max),
        f"peak_accel_rigid_{unit.accel_key}": list(result.peak_accel_rigid * unit.si_scale),
        f"peak_accel_elastic_{unit.accel_key}": list(result.peak_accel_elastic * unit.si_scale),
        "residual_vibration_mm": by_kind,
        "residual_vibration_phases": [{"kind": r.phase.kind, "start_deg": math.degrees(r.phase.start),
                                       "end_deg": math.degrees(r.phase.end), "amplitude_mm": r.amplitude,
                                       "rpm": r.rpm} for r in residuals],
        "method": result.method,
        "accuracy": ({"samples": settings.samples} if result.method == "frequency"
                     else {"solver": settings.solver, "rtol": settings.rtol, "samples": settings.samples}),
        "start_load": {"rpm": fastest, "phases": _start_load_entries(law, follower, fastest, settings)},
    }
    if compare is not None:
        report["compare"] = {"law": compare_name, **_compared(report, compare, follower, fastest, settings, unit)}
    if lead_in is not None:
        from camcad.fourier.leadin import add_lead_in

        angle, fraction = lead_in
        result_lead = add_lead_in(law, angle, fraction, where="lead-in")
        report["lead_in"] = {"angle_deg": angle, "fraction": fraction, "balanced": result_lead.balanced,
                             **_compared(report, result_lead.law, follower, fastest, settings, unit)}
    if settings.has_multimass and settings.shaft_stiffness is not None:
        report["multimass"] = _multimass_entry(law, settings, fastest)
    elif settings.has_multimass:
        report["skipped"] = {"multimass": "rigid shaft: the multi-mass model reduces to the single-DOF one"}
    checks = {}
    for key, value, allowed in (
            ("peak_accel_ratio", float(np.max(result.peak_accel_ratio)), settings.allowed_peak_accel_ratio),
            ("dynamic_error_max_mm", float(np.max(result.dynamic_error_max)), settings.allowed_dynamic_error_mm),
            ("residual_vibration_mm", max(by_kind.values()), settings.allowed_residual_mm)):
        if allowed is not None:
            checks[key] = {"value": value, "allowed": allowed, "passed": value <= allowed}
    report["checks"] = checks
    report["passed"] = all(check["passed"] for check in checks.values())
    return DynamicsRun(report, result, keep, settings)


@dataclass(frozen=True)
class ImpactRun:
    report: dict
    sweep: Any
    model: Any


def run_impact(law, model, speeds: list[float], *, progress: Callable | None = None) -> ImpactRun:
    """Impact on the limit stop over ``speeds`` (rpm): SPEC.md ``impact`` keys, the linearised rebound
    relation, the least phase angle for the allowed amplitude and ``passed``."""
    from camcad.dynamics.impact import impact_sweep

    keep = sorted({speeds[0], max(speeds)})
    result = impact_sweep(law, model, speeds, keep=keep, progress=progress)
    relation = result.relation
    slope, intercept = relation.tangent
    rebounds = result.rebound_mm
    report: dict[str, Any] = {
        "reduced_stiffness_N_per_m": model.stiffness_n_per_m, "stop_stiffness_N_per_m": model.stop_stiffness_n_per_m,
        "mass_kg": model.mass_kg, "f_free_hz": model.f_free_hz, "f_stop_hz": model.f_stop_hz,
        "restitution": model.restitution, "damping_ratio": model.damping_ratio, "preload_mm": model.preload_mm,
        "stop": model.stop, "contact_at_deg": result.impacts[0].contact_deg, "approach_phase_deg": result.phase_deg,
        "pulse_s": model.pulse_s, "speeds_rpm": list(result.speeds_rpm),
        "approach_velocity_mm_s": _one_or_list(i.approach_velocity_mm_s for i in result.impacts),
        "impulse_Ns": _one_or_list(i.impulse_ns for i in result.impacts),
        "force_N": _one_or_list(result.force_n), "rebound_mm": _one_or_list(rebounds),
        "leaves_stop": any(i.leaves_stop for i in result.impacts),
        "linear": {"slope_mm_per_deg": slope, "intercept_mm": intercept, "at_deg": relation.phase_deg,
                   "at_rpm": relation.rpm},
        "allowed_amplitude_mm": model.allowed_amplitude_mm,
        "phase_limit_deg": None, "phase_limit_linear_deg": None,
    }
    passed = True
    if model.allowed_amplitude_mm is not None:
        report["phase_limit_deg"] = relation.least_phase(model.allowed_amplitude_mm)
        report["phase_limit_linear_deg"] = (model.allowed_amplitude_mm - intercept) / slope
        passed = bool(max(rebounds) <= model.allowed_amplitude_mm)
    report["passed"] = passed
    return ImpactRun(report, result, model)


def _one_or_list(values):
    values = [float(v) for v in values]
    return values[0] if len(values) == 1 else values


def _start_load_entries(law, follower, rpm: float, settings) -> list[dict]:
    """Start-of-motion load of every motion phase at ``rpm``, with and without the summary pulse."""
    from camcad.dynamics.model import OUTPUT_UNITS, LoadSum
    from camcad.dynamics.residual import motion_phases
    from camcad.dynamics.startload import start_loads, start_pulse
    from camcad.dynamics.steady import steady_state

    unit = OUTPUT_UNITS[settings.output_unit]
    kwargs = dict(method=settings.method, samples=settings.samples, solver=settings.solver, rtol=settings.rtol)
    plain = start_loads(steady_state(law, follower, rpm, **kwargs), law, follower, unit.si_scale)
    pulsed = None
    if settings.start_pulse_ratio:
        pulses = LoadSum(tuple(start_pulse(law, follower, rpm, p, settings.start_pulse_ratio)
                               for p in motion_phases(law)))
        pulsed = start_loads(steady_state(law, follower, rpm, external=pulses, **kwargs), law, follower,
                             unit.si_scale)
    entries = []
    for i, load in enumerate(plain):
        entry = _start_load_dict(load, unit)
        if pulsed is not None:
            entry["with_pulse"] = _start_load_dict(pulsed[i], unit)
            entry["with_pulse"]["pulse_ratio"] = settings.start_pulse_ratio
            entry["with_pulse"]["increase"] = pulsed[i].peak_link_accel / load.peak_link_accel
        entries.append(entry)
    return entries


def _start_load_dict(load, unit) -> dict:
    import math

    return {"kind": load.phase.kind, "start_deg": math.degrees(load.phase.start), "at_deg": load.at_deg,
            f"peak_link_accel_{unit.accel_key}": load.peak_link_accel * unit.si_scale,
            f"peak_rigid_accel_{unit.accel_key}": load.peak_rigid_accel * unit.si_scale,
            unit.force_key: load.force_n}


def _multimass_entry(law, settings, rpm: float) -> dict:
    """The multi-mass model at ``rpm``: flywheel held at speed, elastic shaft; figures over the third cycle."""
    import math

    import numpy as np

    from camcad.dynamics.multimass import MultiMassModel, SpeedDrive, simulate
    from camcad.dynamics.model import rpm_to_rad_s

    scale = 1e-3 if settings.output_unit == "mm" else 1.0
    model = MultiMassModel.from_follower(settings.follower, settings.flywheel_inertia, settings.cam_inertia,
                                         settings.shaft_stiffness, position_scale=scale)
    period = 2.0 * math.pi / rpm_to_rad_s(rpm)
    result = simulate(model, law, SpeedDrive(rpm), 3.0 * period, samples=3 * 1024 + 1, method=settings.solver,
                      rtol=settings.rtol)
    last = result.time >= 2.0 * period
    rigid = law.kinematics(result.phi1[last]).a * rpm_to_rad_s(rpm)**2
    return {"rpm": rpm, "drive": "flywheel at constant speed", "cycles": 3,
            "shaft_frequency_hz": math.sqrt(model.shaft_stiffness / model.cam_inertia) / (2.0 * math.pi),
            "peak_accel_ratio": float(np.max(np.abs(result.accel_elastic[last])) / np.max(np.abs(rigid))),
            "dynamic_error_max_mm": float(np.max(np.abs(result.dynamic_error[last]))),
            "cam_speed_range_rpm": [float(result.cam_speed_rpm[last].min()), float(result.cam_speed_rpm[last].max())]}


def _compared(report: dict, other, follower, rpm: float, settings, unit) -> dict:
    """Start-of-motion loads of another law and this law's load over it, phase by phase (rise, return, ...)."""
    theirs = _start_load_entries(other, follower, rpm, settings)
    key = f"peak_link_accel_{unit.accel_key}"
    ours = report["start_load"]["phases"]
    return {"rpm": rpm, "phases": theirs, "reduction": [a[key] / b[key] for a, b in zip(ours, theirs)]}
