"""``camcad compare``'s outputs: the side-by-side table (text, compare.csv, compare.json) and the plots.

- ``plot_laws``: s, v, a of both laws over the cycle and s_B − s_A (the displacement deviation);
- ``plot_speed``: peak acceleration (rigid and elastic) and peak velocity against speed for both laws, with the
  published points of the scene's [compare] beside camcad's curves;
- ``plot_contact``: the contact-stress safety factor and σ_max against shaft speed for both laws (the batten
  study's Fig. 10), with published points;
- ``plot_harmonics``: the harmonic amplitudes of s of both laws;
- ``compare_command``: the whole command (read, compute with ``camcad.scene.commands.compare.run_compare``, write).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from camcad.io.atomic import write_text_atomic
from camcad.report.command import finish, open_folder
from camcad.report.figure import COLOURS, new_figure, save_figure
from camcad.report.text import fmt, table
from camcad.scene.commands.compare import CompareRequest, run_compare
from camcad.scene.file import read_scene

_A, _B = "#1f4e79", "#e07b00"


def _rate_labels(unit: str) -> tuple[str, str]:
    return {"mm": ("m/s", "m/s²"), "rad": ("rad/s", "rad/s²"), "deg": ("deg/s", "deg/s²")}[unit]


def plot_laws(report, *, samples: int = 4097):
    """s, v, a of A and B over the cycle (deg), and s_B − s_A."""
    comparison = report.comparison
    law_a, law_b = comparison.laws
    unit = comparison.unit
    fig, axes = new_figure(10, 9, rows=4, sharex=True)
    theta = np.linspace(0.0, law_a.cycle, samples)
    for law, colour, name in ((law_a, _A, report.names[0]), (law_b, _B, report.names[1])):
        kin = law.kinematics(theta)
        s0 = law.kinematics(np.zeros(1)).s[0]
        deg = np.degrees(theta)
        axes[0].plot(deg, kin.s - s0, color=colour, lw=1.2, label=f"{name}")
        axes[1].plot(deg, kin.v, color=colour, lw=1.2)
        axes[2].plot(deg, kin.a, color=colour, lw=1.2)
    grid, deviation = comparison.deviation
    axes[3].plot(np.degrees(grid), deviation, color="black", lw=1.0)
    for ax, label in zip(axes, (f"s ({unit})", f"v ({unit}/rad)", f"a ({unit}/rad²)", f"s_B - s_A ({unit})")):
        ax.set_ylabel(label)
        ax.grid(color="0.9")
        ax.axhline(0.0, color="0.5", lw=0.6)
    for phase in law_a.phases:
        if phase.kind != "dwell":
            for ax in axes:
                ax.axvspan(math.degrees(phase.start), math.degrees(phase.end), color=COLOURS[phase.kind],
                           alpha=0.35, lw=0, zorder=0)
    axes[0].legend(fontsize=8, loc="best")
    axes[3].set_xlabel("cam angle θ (deg); shaded: the phases of A")
    worst = float(np.max(np.abs(deviation)))
    fig.suptitle(f"{report.names[0]} (A) and {report.names[1]} (B): largest |s_B - s_A| {worst:.3g} {unit}",
                 fontsize=10)
    return fig


def _published_points(report, figure: str):
    """(rpm, value, which law, label) of the published figures of ``figure`` with a speed."""
    return [(item.rpm, item.published, item.law, item.name) for item in report.published
            if item.figure == figure and item.rpm and item.law in ("A", "B") and isinstance(item.published, float)]


def plot_speed(report):
    """Peak acceleration (rigid, elastic) and peak velocity against speed for both laws, published points."""
    comparison = report.comparison
    speeds = np.array(comparison.speeds)
    v_unit, a_unit = _rate_labels(comparison.unit)
    fig, (top, bottom) = new_figure(9, 7, rows=2, sharex=True)
    for which, colour, name in (("a", _A, report.names[0]), ("b", _B, report.names[1])):
        rigid = [getattr(comparison.find("peak_accel_rigid", rpm=r), which) for r in speeds]
        top.plot(speeds, rigid, "o-", color=colour, ms=3, label=f"{name}: rigid")
        elastic = [comparison.find("peak_accel_elastic", rpm=r) for r in speeds]
        if all(e is not None for e in elastic):
            top.plot(speeds, [getattr(e, which) for e in elastic], "s--", color=colour, ms=3,
                     label=f"{name}: elastic")
        velocity = [getattr(comparison.find("peak_velocity", rpm=r), which) for r in speeds]
        bottom.plot(speeds, velocity, "o-", color=colour, ms=3, label=name)
    for ax, figure in ((top, "peak_accel_rigid"), (bottom, "peak_velocity")):
        for rpm, value, law, label in _published_points(report, figure):
            ax.plot([rpm], [value], marker="*", ms=12, ls="none", color=_A if law == "A" else _B,
                    markeredgecolor="black", label=f"published: {label}")
        ax.grid(color="0.9")
        ax.legend(fontsize=8, loc="best")
    top.set_ylabel(f"peak acceleration, {a_unit}")
    bottom.set_ylabel(f"peak velocity, {v_unit}")
    bottom.set_xlabel("shaft speed n, rpm")
    top.set_title("Peak acceleration and velocity against speed (stars: published values)", fontsize=10)
    return fig


def plot_contact(report):
    """Safety factor [σ_H]/σ_max and σ_max against shaft speed for both laws (the batten study's Fig. 10)."""
    curves = report.curves
    fig, (top, bottom) = new_figure(9, 7, rows=2, sharex=True)
    for sweep, colour, name in ((curves[0], _A, report.names[0]), (curves[1], _B, report.names[1])):
        bottom.plot(sweep.rpm, sweep.safety_factor, "-", color=colour, lw=1.6, label=name)
        top.plot(sweep.rpm, sweep.sigma_max, "-", color=colour, lw=1.6, label=name)
    allowable = curves[0].allowable
    top.axhline(allowable, color=COLOURS["limit"], ls="--", label=f"[σ_H] = {allowable:g} MPa")
    bottom.axhline(1.0, color=COLOURS["limit"], ls="--", label="1")
    for ax, figure in ((top, "sigma_max"), (bottom, "safety_factor")):
        for rpm, value, law, label in _published_points(report, figure):
            ax.plot([rpm], [value], marker="*", ms=12, ls="none", color=_A if law == "A" else _B,
                    markeredgecolor="black", label=f"published: {label}")
        ax.grid(color="0.9")
        ax.legend(fontsize=8, loc="best")
    for rpm in report.comparison.speeds:
        for ax in (top, bottom):
            ax.axvline(rpm, color="0.8", lw=0.6, zorder=0)
    top.set_ylabel("σ_max along the profile, MPa")
    bottom.set_ylabel("safety factor [σ_H]/σ_max")
    bottom.set_xlabel("shaft speed n, rpm (grey: the compared speeds)")
    top.set_title("Contact stress and its safety factor against speed, both laws (cf. the batten study's Fig. 10)",
                  fontsize=10)
    return fig


def plot_harmonics(report):
    """Amplitudes A_k of s of both laws (log scale)."""
    comparison = report.comparison
    unit = comparison.unit
    rows = comparison.harmonics
    ks = np.array([r["k"] for r in rows])
    fig, ax = new_figure(10, 4.5)
    ax.bar(ks - 0.2, [max(r[f"A_{unit}"], 1e-300) for r in rows], width=0.4, color=_A, label=report.names[0])
    ax.bar(ks + 0.2, [max(r[f"B_{unit}"], 1e-300) for r in rows], width=0.4, color=_B, label=report.names[1])
    ax.set_yscale("log")
    peak = max(max(r[f"A_{unit}"], r[f"B_{unit}"]) for r in rows)
    ax.set_ylim(peak * 1e-9, peak * 2)
    ax.set_xlabel("harmonic k")
    ax.set_ylabel(f"amplitude of s, {unit}")
    ax.grid(color="0.9", axis="y")
    ax.legend(fontsize=8)
    ax.set_title("Harmonic amplitudes of the displacement", fontsize=10)
    return fig


def compare_figures(report) -> list[tuple[str, object]]:
    figures = [("compare_laws.png", plot_laws(report)), ("compare_speed.png", plot_speed(report)),
               ("compare_harmonics.png", plot_harmonics(report))]
    if report.curves[0] is not None and report.curves[1] is not None:
        figures.append(("compare_contact.png", plot_contact(report)))
    return figures


def _shown(report):
    """The figures the text shows: speed-dependent ones at the first and the fastest speed."""
    speeds = report.comparison.speeds
    keep = {speeds[0], max(speeds)}
    return [f for f in report.comparison.figures if f.rpm is None or f.rpm in keep or f.name.startswith("start")
            or f.name == "residual_vibration"]


def compare_csv(report) -> str:
    """Every figure as a CSV row: name, motion, rpm, unit, A, B, A/B, applies."""
    lines = ["name,motion,rpm,unit,A,B,A_over_B,applies"]
    for f in report.comparison.figures:
        cells = [f.name, f.motion or "", "" if f.rpm is None else f"{f.rpm:g}", f.unit,
                 "" if f.a is None else f"{f.a:.12g}", "" if f.b is None else f"{f.b:.12g}",
                 "" if f.ratio is None else f"{f.ratio:.12g}", '"' + f.applies.replace('"', "'") + '"']
        lines.append(",".join(cells))
    return "\n".join(lines) + "\n"


def compare_lines(run) -> list[str]:
    """The text output: the laws, the figures as A, B and A/B with what each applies to, the harmonics, the
    published figures with their status, the files written."""
    report = run.report
    comparison = report.comparison
    lines = [f"A: {report.names[0]} ({report.sources[0]['where']}); phases {report.sources[0]['phases']}",
             f"B: {report.names[1]} ({report.sources[1]['where']}); phases {report.sources[1]['phases']}"]
    if report.scene:
        lines.append(f"mechanism: {report.scene}; speeds {', '.join(f'{s:g}' for s in comparison.speeds)} rpm")
    rows = [[f.label, f.unit, fmt(f.a), fmt(f.b), fmt(f.ratio), f.applies] for f in _shown(report)]
    lines += ["", "figure side by side (A/B: law A over law B)"]
    lines += table(["figure", "unit", "A", "B", "A/B", "applies to"], rows)
    unit = comparison.unit
    listed = [r for r in comparison.harmonics if max(r[f"A_{unit}"], r[f"B_{unit}"]) > 0][:24]
    lines += ["", f"harmonic amplitudes of s ({unit})"]
    lines += table(["k", "A", "B", "A/B", "phase A deg", "phase B deg"],
                   [[r["k"], fmt(r[f"A_{unit}"]), fmt(r[f"B_{unit}"]), fmt(r["A/B"]), fmt(r["A_phase_deg"]),
                     fmt(r["B_phase_deg"])] for r in listed])
    if report.published:
        lines += ["", "published figures beside camcad's"]
        lines += table(["figure", "published", "camcad", "unit", "status", "why / which inputs"],
                       [[p.name, _value_text(p.published), fmt(p.camcad), p.unit, p.status, p.detail]
                        for p in report.published])
        for p in report.published:
            if p.applies:
                lines.append(f"  {p.name}: {p.applies}" + (f" (source: {p.source})" if p.source else ""))
    for note in list(report.notes) + list(comparison.notes):
        lines.append(f"  note: {note}")
    return lines + [f"written: {p}" for p in run.outputs]


def _value_text(value) -> str:
    if value is None:
        return "-"
    if isinstance(value, list):
        return f"{fmt(value[0])}-{fmt(value[1])}"
    return fmt(value)


@dataclass(frozen=True)
class CompareCommand:
    """``camcad compare``: the request (camcad.scene.commands.compare.CompareRequest) and what to write."""

    request: CompareRequest
    output: Path | None = None
    plots: bool = True


def compare_command(command: CompareCommand, progress=None):
    """Run ``camcad compare``: compute (``run_compare``), write compare.csv, the plots and compare.json into
    the output folder (never over an input). Returns a CommandRun."""
    request = command.request
    inputs = [p for p in (request.a, request.b) if p is not None]
    name = "compare"
    if request.scene is not None:
        scene_path = Path(request.scene)
        if scene_path.is_file():
            inputs += read_scene(scene_path).input_files()
            name = f"{scene_path.stem}_compare"
    with open_folder(command.output, name, inputs) as out:
        report = run_compare(request, progress)
        written = [write_text_atomic(out.path("compare.csv"), compare_csv(report))]
        if command.plots:
            written += [save_figure(fig, out.path(file)) for file, fig in compare_figures(report)]
        return finish(report, out, written, "compare.json", compare_lines)
