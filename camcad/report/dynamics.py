"""Plots of the elastic follower and the stop impact (PNG, Agg): rigid vs elastic acceleration over the
cycle and against speed, rebound against speed, the response after an impact."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from camcad.dynamics.model import OUTPUT_UNITS
from camcad.io.atomic import write_atomic
from camcad.report.figure import pyplot
from camcad.dynamics.runs import DynamicsRun, ImpactRun


def _save(fig, path: Path) -> Path:
    plt = pyplot()
    written = write_atomic(path, lambda tmp: fig.savefig(tmp, format="png", dpi=120))
    plt.close(fig)
    return written


def _shade_phases(ax, phases) -> None:
    colours = {"rise": "#e8f0fb", "return": "#fbeee8"}
    for phase in phases:
        if phase.kind in colours:
            ax.axvspan(np.degrees(phase.start), np.degrees(phase.end), color=colours[phase.kind], zorder=0,
                       label=None)


def plot_acceleration_cycle(responses, phases, path: Path, title: str = "", unit: str = "mm") -> Path:
    """Rigid and elastic acceleration (m/s², or rad/s² for a rad output) over the cycle at each response's
    speed; the dynamic error below (µm or mrad)."""
    plt = pyplot()
    u = OUTPUT_UNITS[unit]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True, height_ratios=(2, 1))
    for ax in (top, bottom):
        _shade_phases(ax, phases)
    first = responses[0]
    deg = np.degrees(first.theta)
    top.plot(deg, first.accel_rigid * u.si_scale, color="black", lw=1.2, label=f"rigid, {first.rpm:g} rpm")
    for response in responses:
        line, = top.plot(np.degrees(response.theta), response.accel_elastic * u.si_scale, lw=1.0,
                         label=f"elastic, {response.rpm:g} rpm (×{response.peak_accel_ratio:.2f})")
        if response is not first:
            top.plot(np.degrees(response.theta), response.accel_rigid * u.si_scale, color=line.get_color(), lw=0.6,
                     ls=":")
        bottom.plot(np.degrees(response.theta), response.dynamic_error * 1e3, color=line.get_color(), lw=1.0,
                    label=f"{response.rpm:g} rpm, max {response.dynamic_error_max:.4g} {u.name}")
    top.set_ylabel(f"acceleration, {u.accel_label}")
    top.set_title(title or "Rigid vs elastic follower acceleration (rises blue, returns red)")
    top.legend(fontsize=8, loc="upper right")
    top.grid(alpha=0.3)
    bottom.set_xlabel("cam angle θ, deg")
    bottom.set_ylabel(f"dynamic error y − s, {u.fine_label}")
    bottom.legend(fontsize=8, loc="upper right")
    bottom.grid(alpha=0.3)
    bottom.set_xlim(0, np.degrees(first.theta[-1] + first.theta[1] - first.theta[0]))
    fig.tight_layout()
    return _save(fig, path)


def plot_speed_sweep(sweep, path: Path, natural_frequency_hz: float | None = None, title: str = "",
                     unit: str = "mm") -> Path:
    """Peak rigid and elastic acceleration (m/s² or rad/s²) and their ratio against speed (rpm)."""
    plt = pyplot()
    u = OUTPUT_UNITS[unit]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    speeds = sweep.speeds_rpm
    marker = "o" if len(speeds) <= 30 else None
    top.plot(speeds, sweep.peak_accel_rigid * u.si_scale, color="black", marker=marker, ms=3, label="rigid")
    top.plot(speeds, sweep.peak_accel_elastic * u.si_scale, color="tab:red", marker=marker, ms=3, label="elastic")
    top.set_ylabel(f"peak acceleration, {u.accel_label}")
    top.legend()
    top.grid(alpha=0.3)
    top.set_title(title or f"Peak acceleration against speed ({sweep.method} path)")
    bottom.plot(speeds, sweep.peak_accel_ratio, color="tab:blue", marker=marker, ms=3)
    i = int(np.argmax(sweep.peak_accel_ratio))
    bottom.annotate(f"×{sweep.peak_accel_ratio[i]:.2f} at {speeds[i]:g} rpm", (speeds[i], sweep.peak_accel_ratio[i]),
                    textcoords="offset points", xytext=(5, -12), fontsize=8)
    bottom.axhline(1.0, color="grey", lw=0.8)
    bottom.set_xlabel("speed, rpm")
    bottom.set_ylabel("elastic / rigid")
    bottom.grid(alpha=0.3)
    if natural_frequency_hz:
        bottom.text(0.99, 0.04, f"fn = {natural_frequency_hz:g} Hz", transform=bottom.transAxes, ha="right",
                    va="bottom", fontsize=8)
    fig.tight_layout()
    return _save(fig, path)


def plot_rebound(sweep, path: Path, allowed_mm: float | None = None, title: str = "") -> Path:
    """First rebound amplitude (mm) and impact force (N) against speed; the rebound against the phase angle."""
    plt = pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    speeds = sweep.speeds_rpm
    left.plot(speeds, sweep.rebound_mm, "o-", color="tab:red", ms=3, label="rebound")
    left.set_xlabel("speed, rpm")
    left.set_ylabel("first rebound amplitude, mm", color="tab:red")
    if allowed_mm:
        left.axhline(allowed_mm, color="tab:red", ls="--", lw=0.8, label=f"allowed {allowed_mm:g} mm")
    left.grid(alpha=0.3)
    twin = left.twinx()
    twin.plot(speeds, sweep.force_n, "--", color="tab:blue", lw=1.0)
    twin.set_ylabel("impact force F, N", color="tab:blue")
    left.set_title(title or "Rebound and impact force against speed")
    relation = sweep.relation
    t0 = relation.phase_deg
    t = np.linspace(0.6 * t0, 1.6 * t0, 200)
    right.plot(t, relation(t), color="tab:red", label=f"A(t) = A0·t0/t at {relation.rpm:g} rpm")
    slope, intercept = relation.tangent
    right.plot(t, slope * t + intercept, color="grey", ls="--", label=f"a = {slope:.4g}·t + {intercept:.4g}")
    right.plot([t0], [relation.amplitude_mm], "ko", ms=4)
    if allowed_mm:
        right.axhline(allowed_mm, color="tab:red", ls=":", lw=0.8)
        limit = relation.least_phase(allowed_mm)
        right.axvline(limit, color="tab:green", lw=0.8, label=f"least phase angle {limit:.2f} deg")
    right.set_xlabel("phase angle of the approach, deg")
    right.set_ylabel("rebound amplitude, mm")
    right.legend(fontsize=8)
    right.grid(alpha=0.3)
    fig.tight_layout()
    return _save(fig, path)


def plot_impact_response(impacts, stop, path: Path, title: str = "") -> Path:
    """Displacement of the contact point after the impact (mm, positive towards the stop) at each speed."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for impact in impacts:
        if len(impact.time) == 0:
            continue
        ax.plot(impact.time * 1e3, impact.q_mm, lw=1.0, label=f"{impact.rpm:g} rpm, rebound {impact.rebound_mm:.4g} mm")
        ax.plot(impact.rebound_at_s * 1e3, -impact.rebound_mm, "k.", ms=5)
    ax.axvspan(0.0, 2.0 * stop.pulse_s * 1e3, color="#eeeeee", zorder=0, label="impact pulse 2τ")
    ax.axhline(-stop.preload_mm, color="tab:red", ls="--", lw=0.8, label=f"preload {stop.preload_mm:g} mm")
    ax.axhline(0.0, color="grey", lw=0.6)
    ax.set_xlabel("time after contact, ms")
    ax.set_ylabel("q, mm (towards the stop > 0)")
    ax.set_title(title or f"Response after the impact (on the stop, {stop.f_stop_hz:.0f} Hz)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    return _save(fig, path)


def dynamics_plots(run: DynamicsRun, law, out_dir: Path, name: str) -> list[Path]:
    """Rigid vs elastic acceleration over the cycle, and the peak ratio against speed (several speeds)."""
    from camcad.dynamics.model import OUTPUT_UNITS

    unit = OUTPUT_UNITS[run.settings.output_unit]
    responses = [run.sweep.responses[s] for s in run.keep]
    outputs = [plot_acceleration_cycle(responses, law.phases, out_dir / "dynamics_cycle.png",
                                       f"{name}: rigid vs elastic acceleration", unit.name)]
    if len(run.sweep.speeds_rpm) > 1:
        outputs.append(plot_speed_sweep(run.sweep, out_dir / "dynamics_speed.png",
                                        run.settings.follower.natural_frequency_hz,
                                        f"{name}: peak acceleration against speed", unit.name))
    return outputs


def impact_plots(run: ImpactRun, out_dir: Path, name: str) -> list[Path]:
    """Rebound and impact force against speed, and the lever's response after the impact."""
    return [plot_rebound(run.sweep, out_dir / "impact_rebound.png", run.model.allowed_amplitude_mm,
                         f"{name}: rebound and impact force against speed"),
            plot_impact_response([i for i in run.sweep.impacts if len(i.time)], run.model,
                                 out_dir / "impact_response.png")]
