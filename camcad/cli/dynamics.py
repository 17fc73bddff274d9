"""`camcad dynamics LAW|SCENE` (elastic follower over a speed range) and `camcad impact LAW|SCENE`
(limit-stop impact and rebound)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Callable, Optional

import typer

from camcad.cli import app
from camcad.cli.common import (CycleOpt, HandleOpt, JsonOpt, LayerOpt, LiftOpt, MechanismOpt, NoPlotsOpt, OutOpt,
                     PhasesOpt, ReturnStandardOpt, RpmOpt, SourceArg, StandardOpt, XDegOpt, console,
                     finish, output_dir, progress_bar)

ZetaOpt = Annotated[Optional[float], typer.Option("--zeta", help="Damping ratio ζ.")]


# --------------------------------------------------------------------------------------------
# shared plumbing
# --------------------------------------------------------------------------------------------

def _load_source(source, standard, return_standard, phases, lift, layer, handle, cycle, x_deg, rpm, mechanism):
    """The law and the speeds the command runs at (--rpm, else the scene's [machine] rpm)."""
    from camcad.errors import CamcadError
    from camcad.cli.common import resolve_source

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


# --------------------------------------------------------------------------------------------
# camcad dynamics
# --------------------------------------------------------------------------------------------

def _dynamics_settings(src, fn: float | None, zeta: float | None, psi: float | None, mass: float | None,
                       method: str | None, solver: str | None, rtol: float | None, samples: int | None,
                       start_pulse: float | None, max_ratio, max_error, max_residual):
    """The [dynamics] section of the scene, with the command-line options on top."""
    import math
    from dataclasses import replace

    from camcad.scene.dynamics import DynamicsSettings, parse_dynamics
    from camcad.dynamics.model import ElasticFollower, damping_ratio_from_psi
    from camcad.errors import CamcadError

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


def _lead_in_request(option: str | None, src) -> tuple[float, float] | None:
    """(angle deg, fraction) from --lead-in DEG[:FRACTION], else from the scene's [filter] lead-in, else None."""
    from camcad.errors import CamcadError

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
        from camcad.scene.filter import parse_filter

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
    import math

    from camcad.dynamics.runs import run_dynamics
    from camcad.report.dynamics import dynamics_plots

    src = _load_source(source, standard, return_standard, phases, lift, layer, handle, cycle, x_deg, rpm, mechanism)
    settings = _dynamics_settings(src, fn, zeta, psi, mass, method, solver, rtol, samples, start_pulse,
                                  max_ratio, max_error, max_residual)
    other = None
    if compare is not None:
        from camcad.cli.common import load_law_from_options

        other = load_law_from_options(compare, None, None, math.degrees(src.law.cycle), None, None).law
    run = _run_with_progress(not as_json, len(src.speed_list), "dynamics", lambda callback: run_dynamics(
        src.law, settings, src.speed_list, progress=callback, lead_in=_lead_in_request(lead_in, src),
        compare=other, compare_name=str(compare)))
    report = run.report
    out_dir = output_dir(output, src.name)
    outputs = [] if no_plots else dynamics_plots(run, src.law, out_dir, src.name)
    report_path = out_dir / "dynamics.json"
    outputs.append(report_path)
    report["outputs"] = [str(p) for p in outputs]
    payload = {"source": src.where, "notes": src.notes, "dynamics": report}
    finish(payload, report_path, as_json, _print_dynamics, report["passed"])


def _print_dynamics(payload: dict) -> None:
    from rich.table import Table

    from camcad.dynamics.model import OUTPUT_UNITS

    out = console()
    d = payload["dynamics"]
    u = OUTPUT_UNITS[d["unit"]]
    unit = d["unit"]
    out.print(f"{payload['source']}: fn = {d['natural_frequency_hz']:.4g} Hz, ζ = {d['damping_ratio']:.4g}"
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
        verdict = "ok" if check["passed"] else "exceeded"
        out.print(f"{name}: {check['value']:.4g} (allowed {check['allowed']:g}) {verdict}")
    out.print("outputs: " + ", ".join(d["outputs"]))


# --------------------------------------------------------------------------------------------
# camcad impact
# --------------------------------------------------------------------------------------------

def _stop_model(src, mass, f_free, f_stop, restitution, zeta, preload, stop, ratio, allowed):
    import math
    from dataclasses import replace

    from camcad.dynamics.impact import StopModel
    from camcad.scene.stops import parse_stops
    from camcad.errors import CamcadError

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
    from camcad.dynamics.runs import run_impact
    from camcad.report.dynamics import impact_plots

    src = _load_source(source, standard, return_standard, phases, lift, layer, handle, cycle, x_deg, rpm, mechanism)
    model = _stop_model(src, mass, f_free, f_stop, restitution, zeta, preload, stop, ratio, allowed)
    run = _run_with_progress(not as_json, len(src.speed_list), "impact", lambda callback: run_impact(
        src.law, model, src.speed_list, progress=callback))
    report, result, passed = run.report, run.sweep, run.report["passed"]
    out_dir = output_dir(output, src.name)
    outputs = [] if no_plots else impact_plots(run, out_dir, src.name)
    report_path = out_dir / "impact.json"
    outputs.append(report_path)
    report["outputs"] = [str(p) for p in outputs]
    payload = {"source": src.where, "notes": src.notes, "impact": report}
    finish(payload, report_path, as_json, lambda p: _print_impact(p, result), passed)


def _print_impact(payload: dict, result) -> None:
    from rich.table import Table

    out = console()
    d = payload["impact"]
    out.print(f"{payload['source']}: c = {d['reduced_stiffness_N_per_m']:.5g} N/m, m = {d['mass_kg']:.4g} kg, "
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
        verdict = "ok" if d["passed"] else "exceeded"
        out.print(f"allowed {d['allowed_amplitude_mm']:g} mm {verdict}; least phase angle {d['phase_limit_deg']:.3f} deg "
                  f"(linearised {d['phase_limit_linear_deg']:.3f} deg)")
    if d["leaves_stop"]:
        out.print("the rebound exceeds the preload: the lever leaves the stop, the linear model is rough there")
    out.print("outputs: " + ", ".join(d["outputs"]))
