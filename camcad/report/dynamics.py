"""``camcad dynamics`` and ``camcad impact``: plots (Figures), files and text.

Dynamics: rigid against elastic acceleration over the cycle and the dynamic error (in the law's thousandth:
µm, or mrad for a law in rad — one unit per panel), and against speed the peak ratio and the residual
vibration with their limits. Impact: the first rebound against speed with the allowed amplitude and the
preload, the impact force against speed, the rebound against the approach phase angle with the least
angle, and the lever's response after the impact.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, cast

import numpy as np

from camcad.dynamics.model import OUTPUT_UNITS, unit_key
from camcad.report.command import finish, open_folder
from camcad.report.command import write_figures as write_planned
from camcad.report.figure import COLOURS, new_figure, save_figure
from camcad.report.stop import analogs_window, plot_analogs, plot_published, published_lines
from camcad.report.text import common_applies, fmt, header_lines, output_lines, table, verdict_lines
from camcad.scene.commands.dynamics import run_dynamics_report
from camcad.scene.commands.impact import run_impact_report
from camcad.scene.commands.source import resolve_source
from camcad.verdict import note_line

if TYPE_CHECKING:
    from camcad.scene.commands.dynamics import DynamicsRequest
    from camcad.scene.commands.impact import ImpactRequest

_PHASE_COLOURS = {"rise": "#e8f0fb", "return": "#fbeee8"}


def _shade_phases(ax, phases) -> None:
    for phase in phases:
        if phase.kind in _PHASE_COLOURS:
            ax.axvspan(np.degrees(phase.start), np.degrees(phase.end), color=_PHASE_COLOURS[phase.kind], zorder=0)


def _check(verdict, name: str):
    for check in (verdict.checks if verdict is not None else ()):
        if check.name == name:
            return check
    return None


def _warnings_footer(fig, verdict) -> None:
    """The verdict's warnings (at most three) in red under the plot: what a reader must not miss."""
    warnings = list(verdict.warnings) if verdict is not None else []
    if warnings:
        text = "\n".join(f"WARNING: {w.what}" for w in warnings[:3])
        fig.text(0.01, 0.005, text, fontsize=7.5, color=COLOURS["fail"], ha="left", va="bottom", wrap=True)
        fig.get_layout_engine().set(rect=(0, 0.03 + 0.025 * min(len(warnings), 3),
                                          1, 1 - 0.03 - 0.025 * min(len(warnings), 3)))


def _limit_label(check, scale: float = 1.0, unit: str = "") -> str:
    unit = f" {unit}" if unit else ""
    return (f"limit {check.limit * scale:.4g}{unit}: worst {check.value * scale:.4g}{unit}, "
            f"margin {check.margin * scale:.4g}{unit}")


def plot_acceleration_cycle(responses, phases, *, title: str = "", unit: str = "mm", verdict=None):
    """Rigid and elastic acceleration over the cycle at each response's speed (m/s², or rad/s² for a law in
    rad), and the dynamic error below in the law's thousandth (µm or mrad), legend included.

    Parameters
    ----------
    responses : list of camcad.dynamics.steady.Response
    phases : tuple of Phase
        Shaded (rises blue, returns red).
    unit : str
        The law's unit (mm or rad).
    verdict : Verdict or None
        Its "dynamic error" and "peak acceleration ratio elastic/rigid" limits are drawn.

    Returns
    -------
    matplotlib.figure.Figure
    """
    u = OUTPUT_UNITS[unit]
    fig, (top, bottom) = new_figure(9.5, 7, rows=2, sharex=True, gridspec_kw={"height_ratios": (2, 1)})
    for ax in (top, bottom):
        _shade_phases(ax, phases)
    first = responses[0]
    deg = np.degrees(first.theta)
    top.plot(deg, first.accel_rigid * u.si_scale, color="black", lw=1.2, label=f"rigid, {first.rpm:g} rpm")
    for response in responses:
        line, = top.plot(np.degrees(response.theta), response.accel_elastic * u.si_scale, lw=1.0,
                         label=f"elastic, {response.rpm:g} rpm (peak ×{response.peak_accel_ratio:.3g} of rigid)")
        if response is not first:
            top.plot(np.degrees(response.theta), response.accel_rigid * u.si_scale, color=line.get_color(), lw=0.6,
                     ls=":", label=f"rigid, {response.rpm:g} rpm")
        bottom.plot(np.degrees(response.theta), response.dynamic_error * 1e3, color=line.get_color(), lw=1.0,
                    label=f"{response.rpm:g} rpm: max {response.dynamic_error_max * 1e3:.4g} {u.fine_label}")
    ratio = _check(verdict, "peak acceleration ratio elastic/rigid")
    if ratio is not None and ratio.limit is not None:
        fastest = max(responses, key=lambda r: r.rpm)
        allowed = ratio.limit * fastest.peak_accel_rigid * u.si_scale
        for sign in (-1, 1):
            top.axhline(sign * allowed, color=COLOURS["limit"], ls="--", lw=0.8,
                        label=(f"{ratio.limit:g} × rigid peak at {fastest.rpm:g} rpm; worst ratio over the speeds "
                               f"{ratio.value:.4g}, margin {ratio.margin:.3g}" if sign > 0 else None))
    error = _check(verdict, "dynamic error")
    if error is not None and error.limit is not None:
        for sign in (-1, 1):
            bottom.axhline(sign * error.limit * 1e3, color=COLOURS["limit"], ls="--", lw=0.8,
                           label=f"dynamic error {_limit_label(error, 1e3, u.fine_label)}" if sign > 0 else None)
    top.set_ylabel(f"acceleration, {u.accel_label}")
    top.set_title(title or "Rigid vs elastic follower acceleration", fontsize=10)
    top.legend(fontsize=7.5, loc="upper right")
    top.grid(alpha=0.3)
    bottom.set_xlabel("cam angle θ, deg (rises shaded blue, returns red)")
    bottom.set_ylabel(f"dynamic error y − s, {u.fine_label}")
    bottom.legend(fontsize=7.5, loc="upper right")
    bottom.grid(alpha=0.3)
    bottom.set_xlim(0, np.degrees(first.theta[-1] + first.theta[1] - first.theta[0]))
    _warnings_footer(fig, verdict)
    return fig


def plot_speed_sweep(run, *, title: str = "", verdict=None):
    """Against speed (rpm): peak rigid and elastic acceleration, their ratio with its limit, and the residual
    vibration after each motion with its limit; the speeds where a harmonic k meets fn (k·n/60 = fn, for the
    cycle of 360 deg) are marked, and speeds without a bounded steady state are flagged.

    Parameters
    ----------
    run : camcad.dynamics.runs.DynamicsRun

    Returns
    -------
    matplotlib.figure.Figure
    """
    sweep, settings = run.sweep, run.settings
    u = OUTPUT_UNITS[settings.output_unit]
    fig, (top, middle, bottom) = new_figure(9, 9, rows=3, sharex=True)
    speeds = sweep.speeds_rpm
    marker = "o" if len(speeds) <= 30 else None
    finite = np.isfinite(sweep.peak_accel_elastic)
    top.plot(speeds, sweep.peak_accel_rigid * u.si_scale, color="black", marker=marker, ms=3, label="rigid")
    top.plot(speeds[finite], sweep.peak_accel_elastic[finite] * u.si_scale, color="tab:red", marker=marker, ms=3,
             label="elastic")
    top.set_ylabel(f"peak acceleration, {u.accel_label}")
    top.set_title(title or f"Peak acceleration against speed ({sweep.method} path)", fontsize=10)
    middle.plot(speeds[finite], sweep.peak_accel_ratio[finite], color="tab:blue", marker=marker, ms=3,
                label="elastic / rigid")
    middle.axhline(1.0, color="grey", lw=0.8)
    ratio = _check(verdict, "peak acceleration ratio elastic/rigid")
    if ratio is not None and ratio.limit is not None:
        middle.axhline(ratio.limit, color=COLOURS["limit"], ls="--", lw=0.9, label=f"ratio {_limit_label(ratio)}")
    if finite.any():
        i = int(np.argmax(np.where(finite, sweep.peak_accel_ratio, -np.inf)))
        middle.annotate(f"×{sweep.peak_accel_ratio[i]:.3g} at {speeds[i]:g} rpm",
                        (speeds[i], sweep.peak_accel_ratio[i]), textcoords="offset points", xytext=(5, -12), fontsize=8)
    middle.set_ylabel("elastic / rigid")
    for kind, colour, style in (("rise", "tab:blue", "-"), ("return", "tab:orange", "--")):
        values = [max((r.amplitude for r in run.residuals[float(s)] if r.phase.kind == kind), default=np.nan)
                  for s in speeds]
        bottom.plot(speeds, np.array(values) * 1e3, color=colour, ls=style, marker=marker, ms=3,
                    label=f"after the {kind} (from rest)")
    residual = _check(verdict, "residual vibration")
    if residual is not None and residual.limit is not None:
        bottom.axhline(residual.limit * 1e3, color=COLOURS["limit"], ls="--", lw=0.9,
                       label=f"residual {_limit_label(residual, 1e3, u.fine_label)}")
    bottom.set_ylabel(f"residual vibration, {u.fine_label}")
    bottom.set_xlabel("speed n, rpm")
    fn = settings.follower.natural_frequency_hz
    low, high = float(np.min(speeds)), float(np.max(speeds))
    per_turn = 2.0 * np.pi / run.cycle        # harmonic orders per turn of the cam
    ks = [k for k in range(1, 2000) if low <= 60.0 * fn / (k * per_turn) <= high]
    for index, k in enumerate(ks[:40]):
        n = 60.0 * fn / (k * per_turn)
        for ax in (top, middle, bottom):
            ax.axvline(n, color="0.6", lw=0.7, ls=":", zorder=0,
                       label=("k·n/60 = fn: harmonic k in resonance" if (index == 0 and ax is middle) else None))
        if len(ks) <= 20:
            top.text(n, 1.0, f"k={k}", transform=top.get_xaxis_transform(), fontsize=7, color="0.4", ha="center",
                     va="bottom")
    for rpm in sweep.unbounded:
        for ax in (top, middle, bottom):
            ax.axvline(rpm, color=COLOURS["fail"], lw=1.2,
                       label=("no bounded steady state" if ax is middle and rpm == min(sweep.unbounded) else None))
    for ax in (top, middle, bottom):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7.5, loc="best")
    bottom.text(0.99, 0.04, f"fn = {fn:g} Hz, damping ratio {settings.follower.damping_ratio:.3g}", ha="right",
                va="bottom", fontsize=8, transform=bottom.transAxes)
    _warnings_footer(fig, verdict)
    return fig


def dynamics_figures(report) -> list[tuple[str, object]]:
    """(file name, Figure) of a dynamics report: the cycle at the first and fastest speeds (those with a
    bounded steady state) and, with several speeds, the sweep."""
    run = report.result
    unit = run.settings.output_unit
    name = report.source.get("name", "")
    figures = []
    responses = [run.sweep.responses[s] for s in run.keep if s in run.sweep.responses]
    if responses:
        figures.append(("dynamics_cycle.png", plot_acceleration_cycle(
            responses, run.phases, unit=unit, title=f"{name}: rigid vs elastic acceleration", verdict=report.verdict)))
    if len(run.sweep.speeds_rpm) > 1:
        figures.append(("dynamics_speed.png", plot_speed_sweep(run, title=f"{name}: against speed",
                                                               verdict=report.verdict)))
    if run.beats is not None:
        figures.append((f"harmonic_{run.beats.k}.png", plot_harmonic_beats(run.beats, run.phases, unit=unit,
                                                                           title=name)))
    return figures


def plot_harmonic_beats(beats, phases=(), *, unit: str = "mm", title: str = ""):
    """The k-th harmonic of s (top) and of a (bottom) over the cycles drawn, with the follower's response to it
    from rest: its beats with the free vibration (the batten study's Figs. 8–9). The motions of the law are
    shaded in every cycle."""
    fig, (top, bottom) = new_figure(11, 7, rows=2, sharex=True)
    top.plot(beats.theta_deg, beats.s, color=COLOURS["original"], lw=1.0, label=f"harmonic {beats.k} of s")
    top.plot(beats.theta_deg, beats.y, color=COLOURS["elastic"], lw=1.0, label="follower, from rest")
    bottom.plot(beats.theta_deg, beats.a, color=COLOURS["original"], lw=1.0, label=f"harmonic {beats.k} of a")
    bottom.plot(beats.theta_deg, beats.y_accel, color=COLOURS["elastic"], lw=1.0, label="follower, from rest")
    span = float(beats.theta_deg[-1])
    cycle = 360.0 if not phases else math.degrees(phases[-1].end)
    for start in np.arange(0.0, span, cycle):
        for phase in phases:
            if phase.kind != "dwell":
                for ax in (top, bottom):
                    ax.axvspan(start + math.degrees(phase.start), start + math.degrees(phase.end),
                               color=COLOURS[phase.kind], alpha=0.35, lw=0, zorder=0)
    if math.isfinite(beats.beat_deg):
        text = f"beat period {beats.beat_period_s:.3g} s = {beats.beat_deg:.4g} deg of cam angle"
        if beats.decay_s < 0.5 * beats.beat_period_s:
            text += (f"; the free vibration decays in {beats.decay_s:.2g} s, before a beat: the response settles at "
                     f"{beats.steady_amplitude / max(beats.amplitude, 1e-300):.3g} x the harmonic")
    else:
        text = "exactly tuned: no beats, the response grows"
    top.set_title(f"{title}: harmonic {beats.k} at {beats.rpm:g} rpm ({beats.forced_hz:.4g} Hz) against the free "
                  f"vibration ({beats.free_hz:.4g} Hz)\n{text}", fontsize=9)
    top.set_ylabel(f"s, {unit}")
    bottom.set_ylabel(f"a, {unit}/s²")
    bottom.set_xlabel("cam angle θ (deg, from the start); shaded: the motions")
    for ax in (top, bottom):
        ax.grid(color="0.9")
        ax.legend(fontsize=8, loc="upper left")
    return fig


def plot_rebound(sweep, model, *, title: str = "", verdict=None):
    """Three panels: the first rebound against speed (mm) with the allowed amplitude and the preload, the
    impact force against speed (N), and the rebound against the approach phase angle at the fastest speed
    with the least admissible angle. Every curve has a legend; limits and margins are written on them.

    Parameters
    ----------
    sweep : camcad.dynamics.impact.ImpactSweep
    model : camcad.dynamics.impact.StopModel

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (left, middle, right) = new_figure(14, 4.6, cols=3)
    speeds = sweep.speeds_rpm
    left.plot(speeds, sweep.rebound_mm, "o-", color="tab:red", ms=3, label="first rebound")
    allowed = _check(verdict, "first rebound")
    if allowed is not None and allowed.limit is not None:
        left.axhline(allowed.limit, color=COLOURS["limit"], ls="--", lw=0.9,
                     label=f"allowed: {_limit_label(allowed, 1.0, 'mm')}")
    preload = _check(verdict, "rebound below the preload")
    if preload is not None:
        left.axhline(preload.limit, color="0.4", ls=":", lw=0.9,
                     label=f"preload {preload.limit:g} mm (lever stays on its stop): margin {preload.margin:.3g} mm")
    left.set_xlabel("speed n, rpm")
    left.set_ylabel("first rebound amplitude, mm")
    left.set_ylim(bottom=0)
    left.set_title("rebound against speed", fontsize=10)
    middle.plot(speeds, sweep.force_n, "s-", color="tab:blue", ms=3, label="impact force F = S/τ")
    middle.set_xlabel("speed n, rpm")
    middle.set_ylabel("impact force F, N")
    middle.set_ylim(bottom=0)
    middle.set_title(f"force against speed (τ = {model.pulse_s * 1e3:.3g} ms)", fontsize=10)
    relation = sweep.relation
    t0 = relation.phase_deg
    t = np.linspace(0.6 * t0, 1.6 * t0, 200)
    right.plot(t, relation(t), color="tab:red", label=f"A(t) = A0·t0/t at {relation.rpm:g} rpm")
    slope, intercept = relation.tangent
    right.plot(t, slope * t + intercept, color="grey", ls="--", label=f"tangent a = {slope:.4g}·t + {intercept:.4g}")
    right.plot([t0], [relation.amplitude_mm], "ko", ms=4,
               label=f"this law: {t0:.4g} deg, {relation.amplitude_mm:.4g} mm")
    angle = _check(verdict, f"approach phase angle ({sweep.contact.phase.kind})")
    if model.allowed_amplitude_mm:
        right.axhline(model.allowed_amplitude_mm, color=COLOURS["limit"], ls=":", lw=0.9,
                      label=f"allowed {model.allowed_amplitude_mm:g} mm")
        limit = relation.least_phase(model.allowed_amplitude_mm)
        text = f"least phase angle {limit:.4g} deg"
        if angle is not None:
            text += f" (margin {angle.margin:.3g} deg)"
        right.axvline(limit, color=COLOURS["ok"] if (angle is None or angle.passed) else COLOURS["fail"], lw=0.9,
                      label=text)
    right.set_xlabel(f"phase angle of the approach ({sweep.contact.phase.kind}), deg")
    right.set_ylabel("rebound amplitude, mm")
    right.set_title("rebound against the phase angle", fontsize=10)
    for ax in (left, middle, right):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7.5, loc="best")
    fig.suptitle(title or "Impact on the stop", fontsize=11)
    return fig


def plot_impact_response(impacts, stop, *, title: str = ""):
    """Displacement of the contact point after the impact (mm, towards the stop > 0) at each kept speed, the
    pulse 2τ shaded, the preload and the allowed rebound drawn."""
    fig, ax = new_figure(8.5, 4.6)
    for impact in impacts:
        if len(impact.time) == 0:
            continue
        ax.plot(impact.time * 1e3, impact.q_mm, lw=1.0, label=f"{impact.rpm:g} rpm, rebound {impact.rebound_mm:.4g} mm")
        ax.plot(impact.rebound_at_s * 1e3, -impact.rebound_mm, "k.", ms=5)
    ax.axvspan(0.0, 2.0 * stop.pulse_s * 1e3, color="#eeeeee", zorder=0, label="impact pulse 2τ")
    ax.axhline(-stop.preload_mm, color="0.4", ls=":", lw=0.8, label=f"− preload {stop.preload_mm:g} mm")
    if stop.allowed_amplitude_mm:
        ax.axhline(-stop.allowed_amplitude_mm, color=COLOURS["limit"], ls="--", lw=0.8,
                   label=f"− allowed rebound {stop.allowed_amplitude_mm:g} mm")
    ax.axhline(0.0, color="grey", lw=0.6)
    ax.set_xlabel("time after contact, ms")
    ax.set_ylabel("q, mm (towards the stop > 0)")
    ax.set_title(title or f"Response after the impact (on the stop, {stop.f_stop_hz:.0f} Hz)", fontsize=10)
    ax.legend(fontsize=7.5)
    ax.grid(alpha=0.3)
    return fig


def impact_figures(report) -> list[tuple[str, object]]:
    run = report.result
    name = report.source.get("name", "")
    figures = [("impact_rebound.png", plot_rebound(run.sweep, run.model, verdict=report.verdict,
                                                   title=f"{name}: impact on the {run.model.stop} stop")),
               ("impact_response.png", plot_impact_response([i for i in run.sweep.impacts if len(i.time)], run.model,
                                                            title=f"{name}: response after the impact"))]
    return figures + published_figures(run, name)


def published_figures(run, name: str = "") -> list[tuple[str, object]]:
    """With published figures (``run.comparisons``): the rebound and force against speed with the published
    points (``impact_published.png``) and the analogs with the lever's elasticity at the published speeds
    (``impact_analogs.png``, the source's Fig. 4)."""
    if not run.comparisons:
        return []

    speeds = sorted({c.figure.rpm for c in run.comparisons if c.figure.rpm is not None
                     and min(run.sweep.speeds_rpm) <= c.figure.rpm <= max(run.sweep.speeds_rpm)})
    figures = [("impact_published.png", plot_published(run, title=f"{name}: impact on the {run.model.stop} stop"))]
    if speeds:
        figures.append(("impact_analogs.png", plot_analogs(
            run.law, run.model.f_free_hz, run.model.damping_ratio, speeds, window=analogs_window(run),
            contact_deg=math.degrees(run.sweep.contact.theta),
            title=f"{name}: analogs with the lever's elasticity ({run.model.f_free_hz:.4g} Hz, ζ "
                  f"{run.model.damping_ratio:.3g}) at {', '.join(f'{s:g}' for s in speeds)} rpm "
                  "(the source's Fig. 4)")))
    return figures


# --------------------------------------------------------------------------------------------
# Files, text and the commands
# --------------------------------------------------------------------------------------------

def write_figures(figures, out, sub: tuple[str, ...] = ()) -> list[Path]:
    return [save_figure(fig, out.path(*sub, name)) for name, fig in figures]


def dynamics_lines(run) -> list[str]:
    report = run.report
    d = report.body
    u = OUTPUT_UNITS[d["unit"]]
    unit = d["unit"]

    lines = header_lines(report)
    lines.append(f"fn = {fmt(d['natural_frequency_hz'])} Hz, damping ratio {fmt(d['damping_ratio'])}"
                 f"{' (variable stiffness)' if d['variable_stiffness'] else ''}, {d['method']} path")
    speeds = d["speeds_rpm"]
    step = max(1, len(speeds) // 15)
    rows = []
    for i in sorted(set(range(0, len(speeds), step)) | {len(speeds) - 1}):
        rows.append([fmt(speeds[i]), fmt(d["peak_accel_rigid_" + u.accel_key][i]),
                     fmt(d["peak_accel_elastic_" + u.accel_key][i]), fmt(d["peak_accel_ratio"][i]),
                     fmt(d[unit_key("dynamic_error_max_mm", unit)][i])])
    lines += table(["speed rpm", f"peak rigid {u.accel_label}", f"peak elastic {u.accel_label}", "elastic/rigid",
                    f"dynamic error {unit}"], rows)
    res = d[unit_key("residual_vibration_mm", unit)]
    lines.append(f"residual vibration at {fmt(d['residual_vibration_rpm'])} rpm: after the rise {fmt(res['rise'])} "
                 f"{unit}, after the return {fmt(res['return'])} {unit}")
    for entry in d["unbounded"]:
        lines.append(f"no bounded steady state at {fmt(entry['rpm'])} rpm: {entry['why']}")
    for entry in d.get("start_load", {}).get("phases", []):
        force = f", {fmt(entry[u.force_key])} {u.force_label}" if entry[u.force_key] is not None else ""
        line = (f"start of the {entry['kind']} at {fmt(entry['start_deg'])} deg ({fmt(d['start_load']['rpm'])} rpm): "
                f"link load {fmt(entry['peak_link_accel_' + u.accel_key])} {u.accel_label}{force} at "
                f"{fmt(entry['at_deg'])} deg")
        if "with_pulse" in entry:
            line += f"; with the summary pulse ×{fmt(entry['with_pulse']['increase'])}"
        lines.append(line)
    if "compare" in d:
        lines.append("start-of-motion load, this law / compared law: "
                     + ", ".join(fmt(r) for r in d["compare"]["reduction"]))
    if "lead_in" in d:
        lead = d["lead_in"]
        lines.append(f"lead-in {fmt(lead['angle_deg'])} deg at {fmt(lead['fraction'])} of the peak: start-of-motion "
                     "load reduced " + ", ".join(f"{fmt(r)}x" for r in lead["reduction"])
                     + f" ({fmt(lead['rpm'])} rpm)")
    if "multimass" in d:
        mm = d["multimass"]
        lines.append(f"multi-mass model at {fmt(mm['rpm'])} rpm: elastic/rigid {fmt(mm['peak_accel_ratio'])}, dynamic "
                     f"error {fmt(mm[unit_key('dynamic_error_max_mm', unit)])} {unit}, cam speed "
                     f"{fmt(mm['cam_speed_range_rpm'][0])}…{fmt(mm['cam_speed_range_rpm'][1])} rpm")
        if "motor_torque_mean_Nm" in mm:
            lines.append(f"  driven by the motor's characteristic M0(n): mean torque {fmt(mm['motor_torque_mean_Nm'])} "
                         f"N·m, speed fluctuation {fmt(100 * mm['speed_fluctuation'])} % (from "
                         f"{fmt(mm['started_at_rpm'])} rpm)")
    for note in d.get("notes", []):
        lines.append(note_line(note))
    lines += verdict_lines(report.verdict, common_applies(report))
    return lines + output_lines(run.outputs)


def impact_lines(run) -> list[str]:
    report = run.report
    d = report.body
    sweep = report.result.sweep
    lines = header_lines(report)
    lines.append(f"c = {fmt(d['reduced_stiffness_N_per_m'], 5)} N/m, m = {fmt(d['mass_kg'])} kg, f free "
                 f"{fmt(d['f_free_hz'])} Hz, on the stop {fmt(d['f_stop_hz'])} Hz, τ = {fmt(d['pulse_s'] * 1e3)} ms")
    lines.append(f"contact at {fmt(d['contact_at_deg'], 6)} deg ({d['stop']} stop, preload {fmt(d['preload_mm'])} mm, "
                 f"approach phase {fmt(d['approach_phase_deg'])} deg)")
    step = max(1, len(sweep.impacts) // 15)
    rows = []
    for i in sorted(set(range(0, len(sweep.impacts), step)) | {len(sweep.impacts) - 1}):
        item = sweep.impacts[i]
        rows.append([fmt(item.rpm), fmt(item.approach_velocity_mm_s), fmt(item.impulse_ns), fmt(item.force_n),
                     fmt(item.rebound_mm)])
    lines += table(["speed rpm", "v0 mm/s", "impulse N·s", "force N", "rebound mm"], rows)
    lin = d["linear"]
    lines.append(f"linearised at {fmt(lin['at_deg'])} deg, {fmt(lin['at_rpm'])} rpm: "
                 f"a = {fmt(lin['slope_mm_per_deg'])}·t + {fmt(lin['intercept_mm'])} (mm, t deg)")
    if d["phase_limit_deg"] is not None:
        lines.append(f"least phase angle for {fmt(d['allowed_amplitude_mm'])} mm: {fmt(d['phase_limit_deg'], 6)} deg "
                     f"(linearised {fmt(d['phase_limit_linear_deg'], 6)} deg)")
    beam = d.get("lever_beam")
    if beam:
        lines.append(f"on the stop: {beam['scheme']}; E {fmt(beam['youngs_modulus_MPa'])} MPa, J "
                     f"{fmt(beam['second_moment_mm4'])} mm4, a {fmt(beam['arm_a_mm'])} mm, "
                     f"b {fmt(beam['arm_b_mm'])} mm, stop at {fmt(beam['stop_arm_mm'], 6)} mm from the pivot: "
                     f"c free {fmt(beam['free_stiffness_N_per_m'])} N/m, on the stop "
                     f"{fmt(beam['stop_stiffness_N_per_m'])} N/m")

    lines += published_lines(report.result)
    lines += verdict_lines(report.verdict, common_applies(report))
    return lines + output_lines(run.outputs)


@dataclass(frozen=True)
class DynamicsCommand:
    """``camcad dynamics`` or ``camcad impact``: the request (camcad.scene.commands.dynamics.DynamicsRequest or
    camcad.scene.commands.impact.ImpactRequest) and what to write."""

    request: DynamicsRequest | ImpactRequest
    output: Path | None = None
    plots: bool = True


def dynamics_command(command: DynamicsCommand, progress=None):
    """Run ``camcad dynamics``: resolve the law, compute (camcad.scene.commands.dynamics.run_dynamics_report), write the
    plots and dynamics.json (the inputs are never replaced). Returns a CommandRun."""
    request = cast("DynamicsRequest", command.request)  # camcad dynamics asks with a DynamicsRequest
    require = () if request.fn is not None else (
        ("dynamics", "add [dynamics] with natural_frequency_hz and damping_ratio, or pass --fn and --zeta"),)
    src = resolve_source(request.law, command="dynamics", require=require)
    inputs = list(src.inputs) + ([request.compare] if request.compare is not None else [])
    with open_folder(command.output, src.name, inputs) as out:
        report = run_dynamics_report(request, src, progress)
        written = write_planned(out, dynamics_figures(report) if command.plots else [], "dynamics.json")
        return finish(report, out, written, "dynamics.json", dynamics_lines)


def impact_command(command: DynamicsCommand, progress=None):
    """Run ``camcad impact``: resolve the law, compute (camcad.scene.commands.impact.run_impact_report), write the plots
    and impact.json. Returns a CommandRun."""
    request = cast("ImpactRequest", command.request)  # camcad impact asks with an ImpactRequest
    src = resolve_source(request.law, command="impact", require=(
        ("stops", "add [stops] with the lever, the stop stiffness, restitution, damping and preload"),))
    with open_folder(command.output, src.name, src.inputs) as out:
        report = run_impact_report(request, src, progress)
        written = write_planned(out, impact_figures(report) if command.plots else [], "impact.json")
        return finish(report, out, written, "impact.json", impact_lines)
