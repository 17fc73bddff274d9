"""``camcad drive``: the torque plots (Figures), torque.csv and the text.

- ``plot_drive``: at the governing speed, the camshaft torque of every mechanism (or, for one mechanism, its
  shares: inertia, spring, loads, linkage, friction) and the shaft's total with its peak, RMS and mean; the
  power; the shaft's energy over the turn with the swing ΔE and the speed fluctuation it gives.
- ``plot_drive_speeds``: peak, RMS and mean torque and the inertia δ needs, against speed.
- ``write_torque_csv``: ``theta_deg,torque_Nm,power_W,…`` at the governing speed (the report's ``rpm``), and
  ``torque_speeds.csv`` with one column per speed; the header line first, no comment lines.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from camcad.io.atomic import write_text_atomic
from camcad.report.command import finish, open_folder
from camcad.report.figure import COLOURS, new_figure, save_figure
from camcad.report.text import fmt, table, verdict_lines
from camcad.scene.commands.drive import DriveRequest, run_drive
from camcad.scene.commands.source import require_scene
from camcad.scene.file import read_scene

#: the step (deg) of torque.csv and of the plotted curves
CSV_STEP_DEG = 0.5
_SHARES = (("inertia", "inertia  m a ω²", "#1f77b4"), ("spring", "spring  k s + F0", "#2ca02c"),
           ("load", "process and external loads", "#9467bd"), ("linkage", "working member (linkage)", "#8c564b"),
           ("friction", "friction (guide, pair)", "#d62728"))


def _grid() -> np.ndarray:
    return np.radians(np.arange(0.0, 360.0 + 1e-9, CSV_STEP_DEG))


def _shade_motion(ax, result) -> None:
    """Each mechanism's rises and returns as a light band at the top of the axes (one mechanism) or none."""
    if len(result.mechanisms) != 1:
        return
    for phase in result.mechanisms[0].law.phases:
        if phase.kind in ("rise", "return"):
            ax.axvspan(math.degrees(phase.start), math.degrees(phase.end), color=COLOURS[phase.kind], zorder=0)


def plot_drive(report, *, title: str = ""):
    """Torque, power and energy over one turn at the governing speed (module docstring).

    Parameters
    ----------
    report : camcad.scene.analysis_report.AnalysisReport
        ``camcad.scene.commands.drive.run_drive``'s report.

    Returns
    -------
    matplotlib.figure.Figure
    """
    result = report.result
    rpm = result.governing_rpm
    theta = _grid()
    deg = np.degrees(theta)
    parts = result.components(theta, rpm)
    total = sum(c.total for c in parts.values())
    figures = result.figures[rpm]
    omega = 2.0 * math.pi * rpm / 60.0
    fig, (ax_t, ax_p, ax_e) = new_figure(10.0, 9.5, rows=3, sharex=True,
                                         gridspec_kw={"height_ratios": [2.2, 1.0, 1.3]})
    for ax in (ax_t, ax_p, ax_e):
        _shade_motion(ax, result)
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.grid(color="0.9")
    if len(parts) == 1:
        (only,) = parts.values()
        for key, label, colour in _SHARES:
            values = getattr(only, key)
            if np.any(np.abs(values) > 1e-12 * max(1.0, figures.peak)):
                ax_t.plot(deg, values, color=colour, lw=1.0, label=label)
    else:
        for name, comp in parts.items():
            ax_t.plot(deg, comp.total, lw=1.0, label=name)
    ax_t.plot(deg, total, color="black", lw=2.0, label="camshaft" if len(parts) > 1 else "total")
    if result.elastic.get(rpm) is not None:
        e_theta, e_torque = result.elastic[rpm]
        ax_t.plot(np.degrees(e_theta), e_torque, color=COLOURS["elastic"], lw=1.0, ls="--",
                  label="camshaft, elastic model" if len(parts) > 1 else "total, elastic model")
    ax_t.plot(math.degrees(figures.peak_at), np.interp(figures.peak_at, theta, total), "o", color=COLOURS["limit"])
    ax_t.annotate(f"peak {figures.peak:.4g} N·m at {math.degrees(figures.peak_at):.1f}°",
                  (math.degrees(figures.peak_at), float(np.interp(figures.peak_at, theta, total))),
                  textcoords="offset points", xytext=(8, 4), fontsize=8)
    ax_t.axhline(figures.mean, color="black", lw=0.8, ls=":", label=f"mean {figures.mean:.4g} N·m")
    ax_t.axhline(figures.rms, color="0.4", lw=0.8, ls="-.", label=f"RMS {figures.rms:.4g} N·m")
    ax_t.set_ylabel("camshaft torque T, N·m")
    ax_t.legend(fontsize=8, loc="best", ncol=2)
    scale, unit = (1000.0, "kW") if figures.peak * omega >= 2000.0 else (1.0, "W")
    ax_p.plot(deg, total * omega / scale, color="black", lw=1.2)
    ax_p.axhline(figures.mean * omega / scale, color="black", lw=0.8, ls=":",
                 label=(f"mean {figures.mean * omega / scale:.4g} {unit}, "
                        f"peak {figures.peak * omega / scale:.4g} {unit}"))
    ax_p.set_ylabel(f"power P = T ω, {unit}")
    ax_p.legend(fontsize=8, loc="best")
    energy = result.energy[rpm]
    ax_e.plot(np.degrees(energy.theta), energy.energy, color=COLOURS["law"], lw=1.2)
    low, high = energy.energy_min, energy.energy_min + energy.delta_energy
    for value, at in ((high, energy.max_at), (low, energy.min_at)):
        ax_e.axhline(value, color="0.6", lw=0.6, ls="--")
        ax_e.plot(math.degrees(at), value, "o", color=COLOURS["law"], ms=4)
    ax_e.annotate("", xy=(352.0, high), xytext=(352.0, low), arrowprops={"arrowstyle": "<->", "color": "0.3"})
    ax_e.text(348.0, 0.5 * (low + high), f"ΔE {energy.delta_energy:.4g} J", ha="right", va="center", fontsize=8)
    flywheel = report.body["flywheel"]
    delta = flywheel.get("speed_fluctuation")
    text = f"energy swing ΔE = {energy.delta_energy:.4g} J"
    if flywheel.get("delta") is not None:
        text += (f"; δ = {flywheel['delta']:.4g} needs J = {flywheel['inertia_required_per_speed_kg_m2'][str(rpm)]:.4g}"
                 " kg·m² here")
    if delta is not None and result.inertia_present > 0 and (result.spec.motor == "induction"
                                                             or flywheel.get("delta") is not None):
        text += f"; with {result.inertia_present:.4g} kg·m²: δ = {energy.delta_with(result.inertia_present):.3g}"
    ax_e.set_title(text, fontsize=8, loc="left")
    ax_e.set_ylabel("shaft energy E(θ), J")
    ax_e.set_xlabel("cam angle θ, deg" + (" (rises shaded green, returns red)" if len(result.mechanisms) == 1 else ""))
    ax_e.set_xlim(0.0, 360.0)
    ax_e.set_xticks(np.arange(0, 361, 30))
    names = ", ".join(m.name for m in result.mechanisms)
    ax_t.set_title(f"{title or report.source.get('name', '')}: camshaft torque at {rpm:g} rpm "
                   f"(the largest peak of the speeds)\n{names}; T > 0: the shaft drives, T < 0: it is driven back",
                   fontsize=9)
    return fig


def plot_drive_speeds(report, *, title: str = ""):
    """Peak, RMS and mean camshaft torque against speed and, with δ, the inertia it needs at each speed."""
    result = report.result
    speeds = np.array(result.speeds)
    flywheel = report.body["flywheel"]
    rows = 2 if flywheel.get("delta") is not None else 1
    fig, axes = new_figure(8.5, 3.2 * rows + 0.8, rows=rows, sharex=True)
    axes = np.atleast_1d(axes)
    ax = axes[0]
    for key, label, style in (("peak", "peak |T|", "o-"), ("rms", "RMS", "s-"), ("mean", "mean", "^-")):
        ax.plot(speeds, [getattr(result.figures[n], key) for n in result.speeds], style, ms=3, label=label)
    ax.set_ylabel("camshaft torque, N·m")
    ax.legend(fontsize=8)
    ax.grid(color="0.9")
    if rows == 2:
        need = flywheel["inertia_required_per_speed_kg_m2"]
        axes[1].plot(speeds, [need[str(n)] for n in result.speeds], "o-", ms=3, color=COLOURS["law"],
                     label=f"needed for δ = {flywheel['delta']:.4g}")
        axes[1].axhline(result.inertia_present, color=COLOURS["limit"], ls="--",
                        label=f"present {result.inertia_present:.4g} kg·m²")
        axes[1].set_ylabel("inertia on the camshaft, kg·m²")
        axes[1].legend(fontsize=8)
        axes[1].grid(color="0.9")
    axes[-1].set_xlabel("camshaft speed n, rpm")
    axes[0].set_title(title or f"{report.source.get('name', '')}: camshaft torque against speed", fontsize=10)
    return fig


def torque_table(report) -> tuple[list[str], np.ndarray]:
    """(column names, rows) of torque.csv at the governing speed: θ (deg), the shaft's torque (N·m) and power
    (W), each mechanism's torque (a group) or the shares (one mechanism), the elastic torque, the energy (J)."""
    result = report.result
    rpm = result.governing_rpm
    theta = _grid()
    parts = result.components(theta, rpm)
    total = sum(c.total for c in parts.values())
    omega = 2.0 * math.pi * rpm / 60.0
    columns = {"theta_deg": np.degrees(theta), "torque_Nm": total, "power_W": total * omega}
    if len(parts) > 1:
        for name, comp in parts.items():
            columns[f"{name}_Nm"] = comp.total
    for key, _, _ in _SHARES:
        columns[f"{key}_Nm"] = sum(getattr(c, key) for c in parts.values())
    if result.elastic.get(rpm) is not None:
        e_theta, e_torque = result.elastic[rpm]
        columns["torque_elastic_Nm"] = np.interp(theta, e_theta, e_torque, period=2.0 * math.pi)
    energy = result.energy[rpm]
    columns["energy_J"] = np.interp(theta, energy.theta, energy.energy, period=2.0 * math.pi)
    names = list(columns)
    return names, np.column_stack([np.asarray(columns[n], dtype=float) for n in names])


def _csv(names, data, header: list[str]) -> str:
    lines = [f"# {line}" for line in header] + [",".join(names)]
    lines.extend(",".join(f"{value:.12g}" for value in row) for row in data)
    return "\n".join(lines) + "\n"


def write_torque_csv(report, folder) -> list[Path]:
    """torque.csv (and torque_speeds.csv with several speeds) into the OutputFolder ``folder``: the header line
    first (docs/INTERFACE.md: ``theta_deg,torque_Nm,…``; units in the names), no comment lines — the speed is the
    report's ``rpm``."""
    result = report.result
    names, data = torque_table(report)
    written = [write_text_atomic(folder.path("torque.csv"), _csv(names, data, []))]
    if len(result.speeds) > 1:
        theta = _grid()
        columns = {"theta_deg": np.degrees(theta)}
        for rpm in result.speeds:
            columns[f"torque_{rpm:g}rpm_Nm"] = result.shaft_torque(theta, rpm)
        data = np.column_stack(list(columns.values()))
        written.append(write_text_atomic(folder.path("torque_speeds.csv"), _csv(list(columns), data, [])))
    return written


def drive_lines(run) -> list[str]:
    """The text ``camcad drive`` prints: the figures per speed and per mechanism, the flywheel, the motor, the
    notes and the verdict (tightest margin first)."""
    report = run.report
    body = report.body
    lines = [f"{report.source['name']} ({report.source['scene']}): camshaft torque and drive",
             f"phase angles: {report.source['phase_angles']}"]
    rows = [[fmt(r["rpm"]), fmt(r["torque_peak_Nm"]), fmt(r["torque_peak_at_deg"]), fmt(r["torque_rms_Nm"]),
             fmt(r["torque_mean_Nm"]), fmt(r["power_peak_W"]), fmt(r["power_mean_W"]), fmt(r["energy_swing_J"])]
            for r in body["speeds"]]
    lines += table(["rpm", "peak N·m", "at deg", "RMS N·m", "mean N·m", "peak W", "mean W", "ΔE J"], rows,
                   title="camshaft (all mechanisms on one shaft):")
    if len(body["mechanisms"]) > 1:
        rpm = body["rpm"]
        rows = []
        for name, item in body["mechanisms"].items():
            r = next(x for x in item["per_speed"] if x["rpm"] == rpm)
            rows.append([name, fmt(r["torque_peak_Nm"]), fmt(r["torque_peak_at_deg"]), fmt(r["torque_rms_Nm"]),
                         fmt(r["torque_mean_Nm"])])
        lines += table(["mechanism", "peak N·m", "at deg", "RMS N·m", "mean N·m"], rows, title=f"at {rpm:g} rpm:")
    flywheel = body["flywheel"]
    if flywheel.get("delta") is not None:
        parts = flywheel["inertia_parts_kg_m2"]
        others = flywheel["inertia_present_kg_m2"] - parts["flywheel"]
        given = f" (the scene's: {fmt(parts['flywheel'])} kg·m²)" if report.result.spec.flywheel_inertia else ""
        lines.append(f"flywheel: δ = {fmt(flywheel['delta'])} needs {fmt(flywheel['inertia_required_kg_m2'])} kg·m² "
                     f"on the camshaft (at {fmt(flywheel['inertia_required_rpm'])} rpm); the cams, shaft and motor "
                     f"give {fmt(others)} kg·m², so the flywheel needs {fmt(flywheel['flywheel_required_kg_m2'])} "
                     f"kg·m²{given}")
    if (flywheel.get("speed_fluctuation") is not None and flywheel["inertia_present_kg_m2"] > 0
            and (body["motor"]["regime"] == "induction" or flywheel.get("delta") is not None)):
        lines.append(f"speed fluctuation with {fmt(flywheel['inertia_present_kg_m2'])} kg·m²: δ = "
                     f"{fmt(flywheel['speed_fluctuation'])} (at {fmt(flywheel['speed_fluctuation_rpm'])} rpm)")
    motor = body["motor"]
    if report.result.spec.given:
        lines.append(f"motor ({motor['regime']}, gear ratio {fmt(motor['gear_ratio'])}, efficiency "
                     f"{fmt(motor['gear_efficiency'])}): {fmt(motor['speed_rpm'])} rpm, RMS "
                     f"{fmt(motor['torque_rms_Nm'])} N·m, peak {fmt(motor['torque_peak_Nm'])} N·m"
                     + (f", run-up {fmt(motor['run_up']['torque_Nm'])} N·m" if "run_up" in motor else ""))
    if "elastic" in body:
        e = body["elastic"]
        lines.append(f"elastic model ({', '.join(e['mechanisms'])}): peak {fmt(e['torque_peak_Nm'])} N·m at "
                     f"{fmt(e['rpm'])} rpm, RMS {fmt(e['torque_rms_Nm'])} N·m")
    for name, item in body["mechanisms"].items():
        for note in item["notes"]:
            lines.append(f"  {name}: {note}")
    for name, reason in report.skipped.items():
        lines.append(f"  skipped {name}: {reason}")
    lines += verdict_lines(report.verdict, details=True)
    return lines + [f"written: {p}" for p in run.outputs]


@dataclass(frozen=True)
class DriveCommand:
    """``camcad drive``: the request (camcad.scene.commands.drive.DriveRequest) and what to write."""

    request: DriveRequest
    output: Path | None = None
    plots: bool = True


def drive_command(command: DriveCommand):
    """Run ``camcad drive``: compute (camcad.scene.commands.drive.run_drive), write torque.csv, the plots and drive.json
    into the output folder (the scene and its files are never replaced). Returns a CommandRun."""
    path = require_scene(command.request.scene, "drive")
    scene = read_scene(path)
    with open_folder(command.output, path.stem, scene.input_files()) as out:
        report = run_drive(command.request)
        written = write_torque_csv(report, out)
        if command.plots:
            written.append(save_figure(plot_drive(report), out.path("torque.png")))
            if len(report.result.speeds) > 1:
                written.append(save_figure(plot_drive_speeds(report), out.path("torque_speed.png")))
        return finish(report, out, written, "drive.json", drive_lines)
