"""Dynamics and stop-impact analyses of one law over the machine's speeds, with their verdicts: what
`camcad dynamics`, `camcad impact` and the scene pipeline (steps 5, 6 and 8 of docs/INTERFACE.md) share.

The models are in camcad.dynamics.steady, .residual, .multimass and .impact; this module runs them over
the speeds and gathers the figures under the docs/INTERFACE.md ``dynamics`` and ``impact`` keys, and a
``camcad.verdict.Verdict``: every check a figure, a limit and a margin (a figure without a limit is
reported for information), and the warnings a senior engineer would give even where no limit is set.

Units: the law's displacement is in mm (translating follower) or rad (oscillating follower,
``output_unit = "rad"``); every key that carries a length says its unit (``dynamic_error_max_mm`` or
``dynamic_error_max_rad``, see ``camcad.dynamics.model.unit_key``).

Resonance rules (docs/analyses.md):

- the residual vibration after each motion phase is always computed (Duhamel integral, finite at any
  speed: the free vibration after a phase that starts from rest);
- the periodic steady state at a speed is refused only when a harmonic in exact resonance has a
  non-zero amplitude (``ResonanceError``): that speed is reported as unbounded and the check
  "bounded steady state" fails; a resonant harmonic of zero amplitude is dropped (the ζ → 0 limit)
  with a note;
- a harmonic of non-zero amplitude within ``NEAR_RESONANCE`` of the natural frequency is warned about
  with its frequency ratio kn/(60 fn)·(360°/cycle) and speed.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np

from camcad.dynamics.impact import impact_sweep
from camcad.dynamics.model import OUTPUT_UNITS, LoadSum, rpm_to_rad_s, unit_key
from camcad.dynamics.rebound import compare_published, rebound_study
from camcad.dynamics.spectrum import check_closure, law_spectrum
from camcad.dynamics.steady import steady_state, sweep
from camcad.fourier.leadin import add_lead_in
from camcad.verdict import Check, Verdict, Warning

#: a harmonic of non-zero amplitude whose frequency is within this fraction of the natural frequency at
#: some speed is "near resonance" (the ±5 % band the resonance filter removes by default)
NEAR_RESONANCE = 0.05
#: a harmonic whose displacement amplitude is at most this fraction of the lift counts as zero
#: (the sampled spectrum's round-off is ~1e-16 of the lift)
ZERO_AMPLITUDE = 1e-12


@dataclass(frozen=True)
class DynamicsRun:
    """What ``run_dynamics`` found: ``report`` (docs/INTERFACE.md ``dynamics`` keys and more, without the verdict),
    ``verdict``, the ``sweep`` (camcad.dynamics.steady.Sweep), the speeds whose responses are kept for
    plots, the settings, and the residual vibration at every speed (``residuals``: {rpm: [Residual]})."""

    report: dict
    sweep: Any
    keep: tuple[float, ...]
    settings: Any
    verdict: Verdict = field(default_factory=Verdict)
    residuals: dict = field(default_factory=dict)
    lift: float = 0.0
    phases: tuple = ()
    cycle: float = 2.0 * math.pi
    beats: Any = None     # camcad.dynamics.beats.HarmonicBeats when one harmonic is drawn

    def to_dict(self) -> dict:
        """``report`` with ``passed``, ``checks``, ``tightest`` and ``warnings`` of the verdict."""
        return {**self.report, **self.verdict.to_dict()}


def run_dynamics(law, settings, speeds: list[float], *, progress: Callable | None = None,
                 lead_in: tuple[float, float] | None = None, compare=None, compare_name: str = "",
                 applies: str = "") -> DynamicsRun:
    """The elastic follower over ``speeds`` (rpm): docs/INTERFACE.md ``dynamics`` keys, residual vibration at every
    speed, start-of-motion loads, the multi-mass model when the settings have one, and the verdict.

    Parameters
    ----------
    law : MotionLaw
        The law (mm, or rad for ``settings.output_unit == "rad"``); must close over its cycle.
    settings : camcad.scene.sections.dynamics.DynamicsSettings
        The follower, the limits (``allowed_*``) and the solver knobs.
    speeds : list of float
        Cam speeds, rpm (the first one is the docs/INTERFACE.md residual-vibration speed).
    lead_in : (float, float) or None
        (angle deg, fraction of the peak) — compare with lead-in segments before each motion.
    compare : MotionLaw or None
        A second law whose start-of-motion load is compared.
    applies : str
        Added to every check's ``applies`` (e.g. which phase angles were analysed).

    Returns
    -------
    DynamicsRun
    """
    from camcad.dynamics.residual import residual_vibration

    follower = settings.follower
    lift = check_closure(law)
    speeds = [float(s) for s in speeds]
    fastest = max(speeds)
    keep = tuple(sorted({speeds[0], fastest}))
    unit = OUTPUT_UNITS[settings.output_unit]
    # the residual vibration first: it exists at every speed, resonance or not
    residuals = {rpm: residual_vibration(law, follower, rpm) for rpm in speeds}
    result = sweep(law, follower, speeds, method=settings.method, samples=settings.samples, solver=settings.solver,
                   rtol=settings.rtol, keep=keep, progress=progress)
    first = residuals[speeds[0]]
    by_kind = {"rise": 0.0, "return": 0.0}
    for item in first:
        by_kind[item.phase.kind] = max(by_kind[item.phase.kind], item.amplitude)
    worst_residual = max(((item.amplitude, rpm, item) for rpm, items in residuals.items() for item in items),
                         key=lambda entry: entry[0], default=(0.0, speeds[0], None))

    def key(name: str) -> str:
        return unit_key(name, unit.name)

    report: dict[str, Any] = {
        "natural_frequency_hz": follower.natural_frequency_hz, "damping_ratio": follower.damping_ratio,
        "mass_kg": follower.mass_kg, "variable_stiffness": not follower.constant_stiffness,
        "unit": unit.name, "lift": lift, "speeds_rpm": list(result.speeds_rpm),
        "peak_accel_ratio": [_finite_or_none(v) for v in result.peak_accel_ratio],
        key("dynamic_error_max_mm"): [_finite_or_none(v) for v in result.dynamic_error_max],
        f"peak_accel_rigid_{unit.accel_key}": list(result.peak_accel_rigid * unit.si_scale),
        f"peak_accel_elastic_{unit.accel_key}": [_finite_or_none(v * unit.si_scale)
                                                 for v in result.peak_accel_elastic],
        key("residual_vibration_mm"): by_kind,
        "residual_vibration_rpm": speeds[0],
        "residual_vibration_phases": [{"kind": r.phase.kind, "start_deg": math.degrees(r.phase.start),
                                       "end_deg": math.degrees(r.phase.end), key("amplitude_mm"): r.amplitude,
                                       "rpm": r.rpm} for r in first],
        key("residual_vibration_max_mm"): {"value": worst_residual[0], "rpm": worst_residual[1],
                                           "phase": (None if worst_residual[2] is None
                                                     else worst_residual[2].phase.kind)},
        "method": result.method,
        "accuracy": ({"samples": settings.samples} if result.method == "frequency"
                     else {"solver": settings.solver, "rtol": settings.rtol, "samples": settings.samples}),
        "unbounded": [{"rpm": rpm, "harmonic": err.harmonic, key("amplitude_mm"): err.amplitude,
                       "why": err.what} for rpm, err in result.unbounded.items()],
        "notes": sorted({note for notes in result.notes.values() for note in notes}),
    }
    skipped: dict[str, str] = {}
    if fastest in result.unbounded:
        skipped["start_load"] = f"no bounded steady state at {fastest:g} rpm"
    else:
        report["start_load"] = {"rpm": fastest, "phases": start_load_entries(law, follower, fastest, settings)}
        if compare is not None:
            report["compare"] = {"law": compare_name, **_compared(report, compare, follower, fastest, settings, unit)}
        if lead_in is not None:
            angle, fraction = lead_in
            result_lead = add_lead_in(law, angle, fraction, where="lead-in")
            report["lead_in"] = {"angle_deg": angle, "fraction": fraction, "balanced": result_lead.balanced,
                                 **_compared(report, result_lead.law, follower, fastest, settings, unit)}
    if settings.has_multimass and (settings.shaft_stiffness is not None or settings.motor_torque is not None):
        report["multimass"] = _multimass_entry(law, settings, fastest)
    elif settings.has_multimass:
        skipped["multimass"] = "rigid shaft: the multi-mass model reduces to the single-DOF one"
    if skipped:
        report["skipped"] = skipped
    verdict = _dynamics_verdict(law, result, residuals, settings, lift, unit.name, applies)
    return DynamicsRun(report, result, keep, settings, verdict, residuals, lift, tuple(law.phases), float(law.cycle))


def _finite_or_none(value: float):
    value = float(value)
    return value if math.isfinite(value) else None


def _speed_text(speeds) -> str:
    speeds = [float(s) for s in speeds]
    return f"{min(speeds):g} rpm" if min(speeds) == max(speeds) else f"{min(speeds):g}-{max(speeds):g} rpm"


def _worst_text(speeds, at: float) -> str:
    """"at 300 rpm" for one speed, "worst of 280-420 rpm (at 300 rpm)" for several."""
    speeds = [float(s) for s in speeds]
    if min(speeds) == max(speeds):
        return f"at {at:g} rpm"
    return f"worst of {_speed_text(speeds)} (at {at:g} rpm)"


def _dynamics_verdict(law, result, residuals: dict, settings, lift: float, unit: str, applies: str) -> Verdict:
    """Checks (worst speed first named) and warnings of a dynamics run."""
    speeds = list(result.speeds_rpm)
    span = _speed_text(speeds)
    tail = f"; {applies}" if applies else ""
    checks: list[Check] = []
    warnings: list[Warning] = []
    if result.unbounded:
        worst = min(result.unbounded)
        err = result.unbounded[worst]
        checks.append(Check("bounded steady state", float(len(result.unbounded)), 0.0, "speeds",
                            applies=f"{span}{tail}",
                            note=f"no bounded periodic steady state at {', '.join(f'{r:g}' for r in result.unbounded)}"
                                 f" rpm: {err.what}"))
    ratio_value = float(np.max(result.peak_accel_ratio)) if len(speeds) else None
    checks.append(Check("peak acceleration ratio elastic/rigid", ratio_value, settings.allowed_peak_accel_ratio, "",
                        applies=f"{_worst_text(speeds, speeds[int(np.argmax(result.peak_accel_ratio))])}{tail}"))
    error_value = float(np.max(result.dynamic_error_max))
    i_error = int(np.argmax(result.dynamic_error_max))
    checks.append(Check("dynamic error", error_value, settings.allowed_dynamic_error_mm, unit,
                        applies=f"max |y - s| over the cycle, {_worst_text(speeds, speeds[i_error])}{tail}"))
    worst_res = max(((item.amplitude, rpm, item.phase.kind) for rpm, items in residuals.items() for item in items),
                    default=(0.0, speeds[0], "rise"))
    checks.append(Check("residual vibration", worst_res[0], settings.allowed_residual_mm, unit,
                        applies=f"after the {worst_res[2]} started from rest, {_worst_text(speeds, worst_res[1])}"
                                f"{tail}"))
    # warnings: near resonance, dynamic error larger than the lift
    spectrum = law_spectrum(law, min(settings.samples, 1 << 14))
    amplitudes = 2.0 * np.abs(spectrum.coefficients[1:-1])
    orders = spectrum.orders[1:-1]
    nonzero = amplitudes > ZERO_AMPLITUDE * lift
    wn = settings.follower.omega_n
    closest = None
    for rpm in speeds:
        omega = 2.0 * math.pi * rpm / 60.0
        ratios = orders * omega / wn
        candidates = np.flatnonzero(nonzero & (np.abs(ratios - 1.0) <= NEAR_RESONANCE))
        for index in candidates:
            gap = abs(ratios[index] - 1.0)
            if closest is None or gap < closest[0]:
                closest = (gap, rpm, int(index) + 1, float(ratios[index]), float(amplitudes[index]))
    if closest is not None:
        gap, rpm, k, ratio, amplitude = closest
        zeta = settings.follower.damping_ratio
        magnification = 1.0 / math.hypot(1.0 - ratio**2, 2.0 * zeta * ratio) if (ratio != 1.0 or zeta > 0) \
            else math.inf
        warnings.append(Warning(
            f"near resonance: harmonic {k} (amplitude {amplitude:.3g} {unit}) at {rpm:g} rpm has frequency ratio "
            f"{ratio:.4f} to fn {settings.follower.natural_frequency_hz:g} Hz (magnification "
            f"{magnification:.3g} with damping ratio {zeta:.3g})", ratio,
            f"a harmonic of non-zero amplitude within ±{100 * NEAR_RESONANCE:g} % of fn"))
    if math.isfinite(error_value) and error_value > lift:
        warnings.append(Warning(
            f"dynamic error {error_value:.4g} {unit} at {speeds[i_error]:g} rpm is larger than the lift "
            f"{lift:.4g} {unit}: the follower does not follow the law", error_value, "dynamic error > lift"))
    return Verdict(tuple(checks), tuple(warnings))


@dataclass(frozen=True)
class ImpactRun:
    """What ``run_impact`` found: ``report`` (docs/INTERFACE.md ``impact`` keys), the sweep, the stop model, the
    verdict."""

    report: dict
    sweep: Any
    model: Any
    verdict: Verdict = field(default_factory=Verdict)
    law: Any = None
    published: Any = None      # camcad.dynamics.rebound.PublishedImpact or None
    comparisons: tuple = ()    # camcad.dynamics.rebound.Comparison, one per published figure
    study: Any = None          # camcad.dynamics.rebound.ReboundStudy or None

    def to_dict(self) -> dict:
        return {**self.report, **self.verdict.to_dict()}


#: a rebound within this fraction of its limit (or of the preload) is warned about
CLOSE_TO_LIMIT = 0.05


def run_impact(law, model, speeds: list[float], *, progress: Callable | None = None,
               applies: str = "", published=None, study: bool = False) -> ImpactRun:
    """Impact on the limit stop over ``speeds`` (rpm): docs/INTERFACE.md ``impact`` keys, the linearised rebound
    relation, the least phase angle for the allowed amplitude, and the verdict.

    Parameters
    ----------
    law : MotionLaw
        The law; the contact point moves ``model.ratio`` mm per unit of its displacement.
    model : StopModel
        The lever on its stop (camcad.dynamics.impact).
    speeds : list of float
        Cam speeds, rpm.
    applies : str
        Added to every check's ``applies`` (e.g. which phase angles were analysed).
    published : camcad.dynamics.rebound.PublishedImpact, optional
        Published figures: each is listed beside camcad's (``report["published"]``: value, error, role
        "calibrated" or "validates").
    study : bool
        Also run ``camcad.dynamics.rebound.rebound_study`` on the published rebounds (``report["study"]``).

    Returns
    -------
    ImpactRun
        Checks: rebound against the allowed amplitude (mm, worst speed), rebound against the preload (the
        lever stays pressed on its stop, the model's premise), the approach phase angle against the least
        one for the allowed amplitude (deg).
    """
    speeds = [float(s) for s in speeds]
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
    if model.allowed_amplitude_mm is not None:
        report["phase_limit_deg"] = relation.least_phase(model.allowed_amplitude_mm)
        report["phase_limit_linear_deg"] = (model.allowed_amplitude_mm - intercept) / slope
    if model.beam is not None:
        report["lever_beam"] = model.beam.describe()
    comparisons: tuple = ()
    found_study = None
    if published is not None:
        comparisons = tuple(compare_published(law, model, published))
        report["published"] = {"source": published.source, "figures": [row.to_dict() for row in comparisons]}
        if study and len(published.of("rebound_mm", "computed")) >= 2:
            found_study = rebound_study(law, model, published)
            report["study"] = found_study.to_dict()
    verdict = _impact_verdict(result, model, report, applies)
    return ImpactRun(report, result, model, verdict, law, published, comparisons, found_study)


def _impact_verdict(result, model, report: dict, applies: str) -> Verdict:
    speeds = list(result.speeds_rpm)
    tail = f"; {applies}" if applies else ""
    rebounds = result.rebound_mm
    worst = int(np.argmax(rebounds))
    worst_text = _worst_text(speeds, speeds[worst])
    checks = [Check("first rebound", float(rebounds[worst]), model.allowed_amplitude_mm, "mm",
                    applies=f"{worst_text}{tail}"),
              Check("rebound below the preload", float(rebounds[worst]), model.preload_mm, "mm",
                    applies=f"{worst_text}; the lever stays pressed on its stop (the model's premise){tail}")]
    if report["phase_limit_deg"] is not None:
        checks.append(Check(f"approach phase angle ({result.contact.phase.kind})", float(result.phase_deg),
                            float(report["phase_limit_deg"]), "deg", sense="min",
                            applies=f"least angle for the allowed rebound at {result.relation.rpm:g} rpm{tail}"))
    warnings = []
    for check in checks:
        ratio = check.margin_ratio
        if check.limit is not None and ratio is not None and 0.0 <= ratio < CLOSE_TO_LIMIT:
            warnings.append(Warning(f"{check.name} {check.value:.4g} {check.unit} is within "
                                    f"{100 * ratio:.2g} % of its limit {check.limit:.4g} {check.unit}",
                                    check.value, f"margin < {100 * CLOSE_TO_LIMIT:g} % of the limit"))
    return Verdict(tuple(checks), tuple(warnings))


def _one_or_list(values):
    values = [float(v) for v in values]
    return values[0] if len(values) == 1 else values


def start_load_entries(law, follower, rpm: float, settings) -> list[dict]:
    """Start-of-motion load of every motion phase at ``rpm``, with and without the summary pulse."""
    from camcad.dynamics.residual import motion_phases
    from camcad.dynamics.startload import start_loads, start_pulse

    unit = OUTPUT_UNITS[settings.output_unit]
    kwargs = {"method": settings.method, "samples": settings.samples, "solver": settings.solver, "rtol": settings.rtol}
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
    return {"kind": load.phase.kind, "start_deg": math.degrees(load.phase.start), "at_deg": load.at_deg,
            f"peak_link_accel_{unit.accel_key}": load.peak_link_accel * unit.si_scale,
            f"peak_rigid_accel_{unit.accel_key}": load.peak_rigid_accel * unit.si_scale,
            unit.force_key: load.force_n}


def _multimass_entry(law, settings, rpm: float) -> dict:
    """The multi-mass model at ``rpm``: flywheel held at speed (or turned by the motor's characteristic M0(n)),
    elastic or rigid shaft; figures over the last cycle."""
    from camcad.dynamics.multimass import MotorCurve, MultiMassModel, SpeedDrive, simulate

    scale = 1e-3 if settings.output_unit == "mm" else 1.0
    shaft = settings.shaft_stiffness if settings.shaft_stiffness is not None else math.inf
    model = MultiMassModel.from_follower(settings.follower, settings.flywheel_inertia, settings.cam_inertia,
                                         shaft, position_scale=scale)
    motor = settings.motor_torque is not None
    drive: MotorCurve | SpeedDrive = MotorCurve(settings.motor_torque) if motor else SpeedDrive(rpm)
    start_rpm = drive.nominal_rpm
    period = 2.0 * math.pi / rpm_to_rad_s(start_rpm)
    cycles = 8 if motor else 3
    result = simulate(model, law, drive, cycles * period, samples=cycles * 1024 + 1, method=settings.solver,
                      rtol=settings.rtol, where=settings.where)
    last = result.time >= (cycles - 1) * period
    rigid = law.kinematics(result.phi1[last]).a * result.dphi1[last] ** 2
    entry = {"rpm": rpm, "drive": "motor characteristic M0(n)" if motor else "flywheel at constant speed",
             "cycles": cycles, "peak_accel_ratio": float(np.max(np.abs(result.accel_elastic[last])) /
                                                         np.max(np.abs(rigid))),
             unit_key("dynamic_error_max_mm", settings.output_unit):
                 float(np.max(np.abs(result.dynamic_error[last]))),
             "cam_speed_range_rpm": [float(result.cam_speed_rpm[last].min()), float(result.cam_speed_rpm[last].max())]}
    if math.isfinite(shaft):
        entry["shaft_frequency_hz"] = math.sqrt(model.shaft_stiffness / model.cam_inertia) / (2.0 * math.pi)
    if motor:
        speeds = result.cam_speed_rpm[last]
        curve = cast(MotorCurve, drive)
        torque = np.array([curve(w) for w in result.dphi0[last]])
        entry.update({"rpm": float(np.mean(speeds)), "started_at_rpm": start_rpm,
                      "motor_torque_Nm": [float(torque.min()), float(torque.max())],
                      "motor_torque_mean_Nm": float(np.mean(torque)),
                      "speed_fluctuation": float((speeds.max() - speeds.min()) / np.mean(speeds)),
                      "note": "the motor sets the speed: rpm is the mean cam speed over the last of "
                              f"{cycles} cycles from {start_rpm:g} rpm"})
    return entry


def _compared(report: dict, other, follower, rpm: float, settings, unit) -> dict:
    """Start-of-motion loads of another law and this law's load over it, phase by phase (rise, return, ...)."""
    theirs = start_load_entries(other, follower, rpm, settings)
    key = f"peak_link_accel_{unit.accel_key}"
    ours = report["start_load"]["phases"]
    return {"rpm": rpm, "phases": theirs, "reduction": [a[key] / b[key] for a, b in zip(ours, theirs)]}
