"""`camcad dynamics LAW|SCENE` (elastic follower over a speed range) and `camcad impact LAW|SCENE`
(limit-stop impact and rebound)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Callable, Optional

import typer

from . import app
from .common import (CycleOpt, HandleOpt, JsonOpt, LayerOpt, LiftOpt, MechanismOpt, NoPlotsOpt, OutOpt,
                     PhasesOpt, ReturnStandardOpt, RpmOpt, SourceArg, StandardOpt, XDegOpt, output_dir,
                     print_json, progress_bar)

ZetaOpt = Annotated[Optional[float], typer.Option("--zeta", help="Damping ratio ζ.")]


# --------------------------------------------------------------------------------------------
# shared plumbing
# --------------------------------------------------------------------------------------------

def _load_source(source, standard, return_standard, phases, lift, layer, handle, cycle, x_deg, rpm, mechanism):
    """The law and the speeds the command runs at (--rpm, else the scene's [machine] rpm)."""
    from ..errors import CamcadError
    from .common import resolve_source

    src = resolve_source(source, standard, return_standard, phases, lift, layer, handle, cycle, x_deg, mechanism)
    speeds = src.speeds(rpm)
    if speeds is None:
        where = f"{src.where} [machine]" if src.scene is not None else "command line"
        raise CamcadError("no speed given", where, "add [machine] rpm = ... to the scene or pass --rpm N1:N2[:STEP]")
    src.speed_list = speeds
    return src


def _run_with_progress(enabled: bool, total: int, label: str, work: Callable[[Any], Any]):
    callback, close = progress_bar(enabled, total, label)
    try:
        return work(callback)
    finally:
        close()


def _one_or_list(values):
    values = [float(v) for v in values]
    return values[0] if len(values) == 1 else values


# --------------------------------------------------------------------------------------------
# camcad dynamics
# --------------------------------------------------------------------------------------------

def _dynamics_settings(src, fn: float | None, zeta: float | None, psi: float | None, mass: float | None,
                       method: str | None, solver: str | None, rtol: float | None, samples: int | None,
                       start_pulse: float | None, max_ratio, max_error, max_residual):
    """The [dynamics] section of the scene, with the command-line options on top."""
    import math
    from dataclasses import replace

    from ..dynamics.sdof import DynamicsSettings, ElasticFollower, damping_ratio_from_psi, parse_dynamics
    from ..errors import CamcadError

    if src.section("dynamics") is not None:
        settings = parse_dynamics(src.section("dynamics"), src.section_where("dynamics"),
                                  math.degrees(src.law.cycle))
    elif src.scene is not None and fn is None:
        raise CamcadError("the scene has no [dynamics] section", src.where,
                          "add [dynamics] with natural_frequency_hz and damping_ratio, or pass --fn and --zeta")
    else:
        if fn is None:
            raise CamcadError("no natural frequency given", "command line", "pass --fn HZ (and --zeta Z)")
        if zeta is None and psi is None:
            raise CamcadError("no damping given", "command line", "pass --zeta Z (or --psi, the dissipation coefficient)")
        settings = DynamicsSettings(ElasticFollower(fn, 0.0))
    follower = settings.follower
    if zeta is not None and psi is not None:
        raise CamcadError("both --zeta and --psi given", "command line", "give one of them")
    damping = zeta if zeta is not None else (damping_ratio_from_psi(psi) if psi is not None else follower.damping_ratio)
    if not 0.0 <= damping < 1.0:
        raise CamcadError(f"damping ratio {damping:g} is not in [0, 1)", "--zeta", "give 0 <= zeta < 1")
    if fn is not None and not fn > 0:
        raise CamcadError(f"natural frequency {fn:g} Hz must be positive", "--fn", "give fn > 0")
    follower = ElasticFollower(fn if fn is not None else follower.natural_frequency_hz, damping,
                               mass if mass is not None else follower.mass_kg, follower.stiffness)
    overrides = {"follower": follower}
    for key, value in (("method", method), ("solver", solver), ("rtol", rtol), ("samples", samples),
                       ("start_pulse_ratio", start_pulse), ("allowed_peak_accel_ratio", max_ratio),
                       ("allowed_dynamic_error_mm", max_error), ("allowed_residual_mm", max_residual)):
        if value is not None:
            overrides[key] = value
    settings = replace(settings, **overrides)
    if settings.samples % 2 or settings.samples < 64:
        raise CamcadError(f"--samples {settings.samples} must be an even number >= 64", "--samples", "give e.g. 4096")
    if settings.method == "frequency" and not follower.constant_stiffness:
        raise CamcadError("the frequency-domain path needs a constant stiffness", src.where,
                          "use --method time (or auto) with a stiffness_variation")
    return settings


def _start_load_entries(law, follower, rpm: float, settings) -> list[dict]:
    """Start-of-motion load of every motion phase at ``rpm``, with and without the summary pulse."""
    from ..dynamics.sdof import OUTPUT_UNITS, LoadSum, motion_phases, start_loads, start_pulse, steady_state

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

    from ..dynamics.multimass import MultiMassModel, SpeedDrive, simulate
    from ..dynamics.sdof import rpm_to_rad_s

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


def _lead_in_request(option: str | None, src) -> tuple[float, float] | None:
    """(angle deg, fraction) from --lead-in DEG[:FRACTION], else from the scene's [filter] lead-in, else None."""
    from ..errors import CamcadError

    if option is not None:
        parts = option.split(":")
        try:
            if len(parts) not in (1, 2):
                raise ValueError
            angle = float(parts[0])
            fraction = float(parts[1]) if len(parts) == 2 else 0.1
        except ValueError:
            raise CamcadError(f"--lead-in {option!r} is not DEG or DEG:FRACTION", "--lead-in",
                              "write --lead-in 14 or --lead-in 14:0.1") from None
        return angle, fraction
    table = src.section("filter")
    if isinstance(table, dict) and "lead_in_deg" in table:
        from ..fourier import parse_filter

        settings = parse_filter(table, src.section_where("filter"))
        return settings.lead_in_deg, settings.lead_in_fraction
    return None


@app.command()
def dynamics(source: SourceArg = None,
             fn: Annotated[Optional[float], typer.Option("--fn", help="Natural frequency of the follower system (Hz).")] = None,
             zeta: ZetaOpt = None,
             psi: Annotated[Optional[float], typer.Option("--psi", help="Dissipation coefficient ψ (= 4πζ) instead of --zeta.")] = None,
             mass: Annotated[Optional[float], typer.Option("--mass", help="Reduced follower mass (kg), for forces.")] = None,
             rpm: RpmOpt = None,
             method: Annotated[Optional[str], typer.Option("--method", help="frequency | time | auto (frequency for constant stiffness).")] = None,
             solver: Annotated[Optional[str], typer.Option("--solver", help="solve_ivp method of the time path: RK45, DOP853, Radau, LSODA, ...")] = None,
             rtol: Annotated[Optional[float], typer.Option("--rtol", help="Relative tolerance of the time path.")] = None,
             samples: Annotated[Optional[int], typer.Option("--samples", help="Samples per cycle (frequency path: the accuracy knob).")] = None,
             start_pulse: Annotated[Optional[float], typer.Option("--start-pulse", help="Summary load at the start of motion, × the phase's peak acceleration.")] = None,
             compare: Annotated[Optional[Path], typer.Option("--compare", help="A second law (e.g. a filtered one) whose start-of-motion load is compared.")] = None,
             lead_in: Annotated[Optional[str], typer.Option("--lead-in", help="Compare with lead-in segments DEG[:FRACTION] before each motion (default fraction 0.1), e.g. 14:0.1; a scene's [filter] lead-in is used when present.")] = None,
             max_ratio: Annotated[Optional[float], typer.Option("--max-ratio", help="Allowed peak acceleration ratio elastic/rigid.")] = None,
             max_error: Annotated[Optional[float], typer.Option("--max-error", help="Allowed dynamic error (mm).")] = None,
             max_residual: Annotated[Optional[float], typer.Option("--max-residual", help="Allowed residual vibration (mm).")] = None,
             standard: StandardOpt = None, return_standard: ReturnStandardOpt = None, phases: PhasesOpt = None,
             lift: LiftOpt = None, layer: LayerOpt = None, handle: HandleOpt = None, cycle: CycleOpt = 360.0,
             x_deg: XDegOpt = False, mechanism: MechanismOpt = None, output: OutOpt = None,
             no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Elastic follower over a speed range: rigid vs elastic acceleration, dynamic error, residual vibration
    (exit 1 when a given limit is exceeded)."""
    import json
    import math

    import numpy as np

    from ..dynamics.sdof import OUTPUT_UNITS, residual_vibration, sweep
    from ..io.atomic import write_text_atomic
    from .common import to_jsonable

    src = _load_source(source, standard, return_standard, phases, lift, layer, handle, cycle, x_deg, rpm, mechanism)
    settings = _dynamics_settings(src, fn, zeta, psi, mass, method, solver, rtol, samples, start_pulse,
                                  max_ratio, max_error, max_residual)
    follower = settings.follower
    law = src.law
    speeds = src.speed_list
    fastest = max(speeds)
    keep = sorted({speeds[0], fastest})
    result = _run_with_progress(not as_json, len(speeds), "dynamics", lambda callback: sweep(
        law, follower, speeds, method=settings.method, samples=settings.samples, solver=settings.solver,
        rtol=settings.rtol, keep=keep, progress=callback))
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
        from .common import load_law_from_options

        other = load_law_from_options(compare, None, None, math.degrees(law.cycle), None, None).law
        report["compare"] = {"law": str(compare), **_compared(report, other, follower, fastest, settings, unit)}
    lead = _lead_in_request(lead_in, src)
    if lead is not None:
        from ..fourier import add_lead_in

        angle, fraction = lead
        result_lead = add_lead_in(law, angle, fraction, where="--lead-in")
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
    out_dir = output_dir(output, src.name)
    outputs = []
    if not no_plots:
        from ..plots.dynamics import plot_acceleration_cycle, plot_speed_sweep

        responses = [result.responses[s] for s in keep]
        outputs.append(plot_acceleration_cycle(responses, law.phases, out_dir / "dynamics_cycle.png",
                                               f"{src.name}: rigid vs elastic acceleration", unit.name))
        if len(speeds) > 1:
            outputs.append(plot_speed_sweep(result, out_dir / "dynamics_speed.png", follower.natural_frequency_hz,
                                            f"{src.name}: peak acceleration against speed", unit.name))
    report_path = out_dir / "dynamics.json"
    outputs.append(report_path)
    report["outputs"] = [str(p) for p in outputs]
    payload = {"source": src.where, "notes": src.notes, "dynamics": report}
    write_text_atomic(report_path, json.dumps(to_jsonable(payload), indent=2))
    if as_json:
        print_json(payload)
    else:
        _print_dynamics(payload)
    raise typer.Exit(0 if report["passed"] else 1)


def _print_dynamics(payload: dict) -> None:
    from rich.table import Table

    from ..dynamics.sdof import OUTPUT_UNITS

    out = console()
    d = payload["dynamics"]
    u = OUTPUT_UNITS[d["unit"]]
    unit = d["unit"]
    out.print(f"[bold]{payload['source']}[/]: fn = {d['natural_frequency_hz']:.4g} Hz, ζ = {d['damping_ratio']:.4g}"
              f"{' (variable stiffness)' if d['variable_stiffness'] else ''}, {d['method']} path")
    table = Table("speed, rpm", f"peak rigid, {u.accel_label}", f"peak elastic, {u.accel_label}", "elastic/rigid",
                  f"dynamic error, {unit}")
    speeds = d["speeds_rpm"]
    step = max(1, len(speeds) // 15)
    rows = sorted(set(range(0, len(speeds), step)) | {len(speeds) - 1})
    for i in rows:
        table.add_row(f"{speeds[i]:g}", f"{d['peak_accel_rigid_' + u.accel_key][i]:.4g}",
                      f"{d['peak_accel_elastic_' + u.accel_key][i]:.4g}",
                      f"{d['peak_accel_ratio'][i]:.4f}", f"{d['dynamic_error_max_mm'][i]:.4g}")
    out.print(table)
    res = d["residual_vibration_mm"]
    out.print(f"residual vibration at {speeds[0]:g} rpm: rise {res['rise']:.4g} {unit}, return {res['return']:.4g} {unit}")
    for entry in d["start_load"]["phases"]:
        force = f", {entry[u.force_key]:.4g} {u.force_label}" if entry[u.force_key] is not None else ""
        line = (f"start of {entry['kind']} at {entry['start_deg']:g} deg ({d['start_load']['rpm']:g} rpm): link load "
                f"{entry['peak_link_accel_' + u.accel_key]:.4g} {u.accel_label}{force} at {entry['at_deg']:.2f} deg")
        if "with_pulse" in entry:
            line += f"; with the summary pulse ×{entry['with_pulse']['increase']:.3f}"
        out.print(line)
    if "compare" in d:
        out.print("start-of-motion load, this law / compared law: "
                  + ", ".join(f"{r:.3f}" for r in d["compare"]["reduction"]))
    if "lead_in" in d:
        lead = d["lead_in"]
        out.print(f"lead-in {lead['angle_deg']:g} deg at {lead['fraction']:g} of the peak: start-of-motion load "
                  "reduced " + ", ".join(f"{r:.3f}x" for r in lead["reduction"]) + f" ({lead['rpm']:g} rpm)")
    if "multimass" in d:
        mm = d["multimass"]
        out.print(f"multi-mass model at {mm['rpm']:g} rpm: elastic/rigid {mm['peak_accel_ratio']:.4f}, dynamic error "
                  f"{mm['dynamic_error_max_mm']:.4g} {unit}, cam speed {mm['cam_speed_range_rpm'][0]:.2f}…"
                  f"{mm['cam_speed_range_rpm'][1]:.2f} rpm")
    for name, check in d["checks"].items():
        verdict = "[green]ok[/]" if check["passed"] else "[red]exceeded[/]"
        out.print(f"{name}: {check['value']:.4g} (allowed {check['allowed']:g}) {verdict}")
    out.print("outputs: " + ", ".join(d["outputs"]))


# --------------------------------------------------------------------------------------------
# camcad impact
# --------------------------------------------------------------------------------------------

def _stop_model(src, mass, f_free, f_stop, restitution, zeta, preload, stop, ratio, allowed):
    import math
    from dataclasses import replace

    from ..dynamics.impact import StopModel, parse_stops
    from ..errors import CamcadError

    if src.scene is not None:
        if src.section("stops") is None:
            raise CamcadError("the scene has no [stops] section", src.where,
                              "add [stops] with the lever, the stop stiffness, restitution, damping and preload")
        model = parse_stops(src.section("stops"), src.section_where("stops"))
        if any(v is not None for v in (mass, f_free, f_stop, restitution, zeta, stop, ratio)):
            raise CamcadError("lever options given with a scene", "command line",
                              "change the scene's [stops] instead (only --preload, --allowed and --rpm override it)")
    else:
        needed = {"--mass": mass, "--f-free": f_free, "--f-stop": f_stop, "--restitution": restitution,
                  "--zeta": zeta, "--preload": preload}
        missing = [name for name, value in needed.items() if value is None]
        if missing:
            raise CamcadError(f"missing {', '.join(missing)}", "command line",
                              "give the lever's reduced mass, its frequencies free and on the stop, restitution, "
                              "damping and preload (or use a scene with [stops])")
        if not (mass > 0 and f_free > 0 and f_stop > f_free):
            raise CamcadError("need mass > 0 and 0 < f_free < f_stop", "--mass/--f-free/--f-stop", "fix the values")
        if not (0 <= restitution <= 1 and 0 <= zeta < 1):
            raise CamcadError("need 0 <= restitution <= 1 and 0 <= zeta < 1", "--restitution/--zeta", "fix the values")
        c = mass * (2.0 * math.pi * f_free)**2
        model = StopModel(mass, c, mass * (2.0 * math.pi * f_stop)**2 - c, restitution, zeta, preload,
                          stop or "upper", ratio or 1.0, allowed)
    if preload is not None:
        if not preload > 0:
            raise CamcadError(f"preload {preload:g} mm must be positive", "--preload", "give a preload > 0")
        model = replace(model, preload_mm=preload)
    if allowed is not None:
        if not allowed > 0:
            raise CamcadError(f"allowed amplitude {allowed:g} mm must be positive", "--allowed", "give a value > 0")
        model = replace(model, allowed_amplitude_mm=allowed)
    return model


@app.command()
def impact(source: SourceArg = None, rpm: RpmOpt = None,
           mass: Annotated[Optional[float], typer.Option("--mass", help="Reduced mass of the lever at the contact point (kg).")] = None,
           f_free: Annotated[Optional[float], typer.Option("--f-free", help="Natural frequency without the stop (Hz).")] = None,
           f_stop: Annotated[Optional[float], typer.Option("--f-stop", help="Natural frequency on the stop (Hz).")] = None,
           restitution: Annotated[Optional[float], typer.Option("--restitution", help="Coefficient of restitution k (5/9 for steel).")] = None,
           zeta: ZetaOpt = None,
           preload: Annotated[Optional[float], typer.Option("--preload", help="Preload of the stop (mm at the contact point).")] = None,
           stop: Annotated[Optional[str], typer.Option("--stop", help="upper (end of rise) or lower (end of return).")] = None,
           ratio: Annotated[Optional[float], typer.Option("--ratio", help="Contact-point displacement per unit of the law's.")] = None,
           allowed: Annotated[Optional[float], typer.Option("--allowed", help="Allowed rebound amplitude (mm).")] = None,
           standard: StandardOpt = None, return_standard: ReturnStandardOpt = None, phases: PhasesOpt = None,
           lift: LiftOpt = None, layer: LayerOpt = None, handle: HandleOpt = None, cycle: CycleOpt = 360.0,
           x_deg: XDegOpt = False, mechanism: MechanismOpt = None, output: OutOpt = None,
           no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Impact on a limit stop: force and first rebound against speed, least phase angle for an allowed
    amplitude (exit 1 when the rebound exceeds it)."""
    import json

    from ..dynamics.impact import impact_sweep
    from ..io.atomic import write_text_atomic
    from .common import to_jsonable

    src = _load_source(source, standard, return_standard, phases, lift, layer, handle, cycle, x_deg, rpm, mechanism)
    model = _stop_model(src, mass, f_free, f_stop, restitution, zeta, preload, stop, ratio, allowed)
    speeds = src.speed_list
    keep = sorted({speeds[0], max(speeds)})
    result = _run_with_progress(not as_json, len(speeds), "impact", lambda callback: impact_sweep(
        src.law, model, speeds, keep=keep, progress=callback))
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
    out_dir = output_dir(output, src.name)
    outputs = []
    if not no_plots:
        from ..plots.dynamics import plot_impact_response, plot_rebound

        outputs.append(plot_rebound(result, out_dir / "impact_rebound.png", model.allowed_amplitude_mm,
                                    f"{src.name}: rebound and impact force against speed"))
        outputs.append(plot_impact_response([i for i in result.impacts if len(i.time)], model,
                                            out_dir / "impact_response.png"))
    report_path = out_dir / "impact.json"
    outputs.append(report_path)
    report["outputs"] = [str(p) for p in outputs]
    payload = {"source": src.where, "notes": src.notes, "impact": report}
    write_text_atomic(report_path, json.dumps(to_jsonable(payload), indent=2))
    if as_json:
        print_json(payload)
    else:
        _print_impact(payload, result)
    raise typer.Exit(0 if passed else 1)


def _print_impact(payload: dict, result) -> None:
    from rich.table import Table

    out = console()
    d = payload["impact"]
    out.print(f"[bold]{payload['source']}[/]: c = {d['reduced_stiffness_N_per_m']:.5g} N/m, m = {d['mass_kg']:.4g} kg, "
              f"f free {d['f_free_hz']:.4g} Hz, on the stop {d['f_stop_hz']:.4g} Hz, τ = {d['pulse_s'] * 1e3:.4g} ms")
    out.print(f"contact at {d['contact_at_deg']:.3f} deg ({d['stop']} stop, preload {d['preload_mm']:g} mm, "
              f"approach phase {d['approach_phase_deg']:g} deg)")
    table = Table("speed, rpm", "v0, mm/s", "impulse, N·s", "force, N", "rebound, mm")
    step = max(1, len(result.impacts) // 15)
    rows = sorted(set(range(0, len(result.impacts), step)) | {len(result.impacts) - 1})
    for i in rows:
        item = result.impacts[i]
        table.add_row(f"{item.rpm:g}", f"{item.approach_velocity_mm_s:.4g}", f"{item.impulse_ns:.4g}",
                      f"{item.force_n:.4g}", f"{item.rebound_mm:.4g}")
    out.print(table)
    lin = d["linear"]
    out.print(f"linearised at {lin['at_deg']:g} deg, {lin['at_rpm']:g} rpm: a = {lin['slope_mm_per_deg']:.4g}·t + "
              f"{lin['intercept_mm']:.4g} (mm, t deg)")
    if d["allowed_amplitude_mm"] is not None:
        verdict = "[green]ok[/]" if d["passed"] else "[red]exceeded[/]"
        out.print(f"allowed {d['allowed_amplitude_mm']:g} mm {verdict}; least phase angle {d['phase_limit_deg']:.3f} deg "
                  f"(linearised {d['phase_limit_linear_deg']:.3f} deg)")
    if d["leaves_stop"]:
        out.print("[yellow]the rebound exceeds the preload: the lever leaves the stop, the linear model is rough there[/]")
    out.print("outputs: " + ", ".join(d["outputs"]))
