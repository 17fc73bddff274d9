"""``camcad spectrum``'s outputs: the spectrum table, the filtered law (DXF, CSV), the plots and the text.

- ``plot_spectrum``: harmonic amplitudes of s and of a (log scale) with the resonance band shaded and the
  removed harmonics marked; harmonics of zero amplitude are not drawn (they are listed in a note).
- ``plot_filtered``: the original and the written law, the deviation with its limits (dwell tolerance,
  largest deviation) and the acceleration with the peak-ratio limit, each margin written where it applies.
- ``plot_truncation``: the RMS (and sampled max) error of the series cut after N harmonics.
- ``write_spectrum``: every file of a run into an OutputFolder; ``spectrum_command``: the whole command.

Units: the law's own (mm, or rad/deg of swing for an oscillating follower): amplitudes in that unit,
deviations in its thousandth (µm, mrad, mdeg), accelerations as analogs per rad² of cam angle.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from camcad.io.atomic import write_text_atomic
from camcad.report.command import finish, open_folder
from camcad.report.figure import COLOURS, new_figure, save_figure
from camcad.report.text import common_applies, fmt, header_lines, output_lines, table, verdict_lines
from camcad.scene.commands.source import resolve_source
from camcad.scene.commands.spectrum import run_spectrum
from camcad.verdict import note_line

if TYPE_CHECKING:
    from camcad.scene.commands.spectrum import SpectrumRequest

_REMOVED = "#c0392b"
_TAPERED = "#e67e22"
_KEPT = "#34495e"
_BAND = "#f5b7b1"
_FILTERED = "#16a085"
#: a harmonic below this fraction of the largest is zero: no bar is drawn for it
ZERO_BAR = 1e-12

#: (fine label, scale from the law unit) of each law unit
FINE = {"mm": ("µm", 1e3), "rad": ("mrad", 1e3), "deg": ("mdeg", 1e3)}


def accel_label(unit: str) -> str:
    return f"{unit}/rad²"


def _bar_colours(ks: np.ndarray, band) -> list[str]:
    gains = band.gains if band is not None else {}
    return [(_REMOVED if gains[k] == 0 else _TAPERED) if k in gains else _KEPT for k in ks]


def _ranges(values) -> str:
    values = sorted(values)
    if not values:
        return "none"
    parts = []
    start = prev = values[0]
    for v in values[1:] + [None]:
        if v is not None and v == prev + 1:
            prev = v
            continue
        parts.append(f"{start}" if start == prev else f"{start}-{prev}")
        if v is not None:
            start = prev = v
    return ", ".join(parts)


def _short_list(values, limit: int = 12) -> str:
    values = list(values)
    text = ", ".join(str(v) for v in values[:limit])
    return text + (f", … ({len(values)} in all)" if len(values) > limit else "")


def plot_spectrum(spectrum, *, band=None, title: str = "", max_harmonics: int | None = None, filtered=None,
                  unit: str = "mm"):
    """Amplitudes A_k of s (``unit``) and of a (``unit``/rad²) against k, the resonance band shaded.

    Parameters
    ----------
    spectrum : camcad.fourier.Spectrum
    band : camcad.fourier.ResonanceBand or None
    filtered : Spectrum or None
        The filtered law's spectrum, drawn as outlined bars.
    unit : str
        The law's unit (mm, rad, deg).

    Returns
    -------
    matplotlib.figure.Figure
    """
    count = len(spectrum.coefficients) if max_harmonics is None else min(max_harmonics, len(spectrum.coefficients))
    ks = np.arange(1, count + 1)
    fig, axes = new_figure(10, 7.5, rows=2, sharex=True)
    zero_lists = []
    for ax, values, other, label in (
            (axes[0], spectrum.amplitudes[:count], None if filtered is None else filtered.amplitudes[:count],
             f"displacement amplitude $A_k$ ({unit})"),
            (axes[1], spectrum.accel_amplitudes[:count],
             None if filtered is None else filtered.accel_amplitudes[:count],
             f"acceleration amplitude ({accel_label(unit)})")):
        top = float(np.max(values)) if len(values) else 0.0
        drawn = values > ZERO_BAR * top
        zero_lists.append(ks[~drawn])
        positive = values[drawn]
        floor = max(float(positive.min()) * 0.3, top * 1e-9) if len(positive) else 1e-12
        colours = np.array(_bar_colours(ks, band), dtype=object)
        # bars start at the axis floor, so a zero harmonic never shows as a stub
        ax.bar(ks[drawn], values[drawn] - floor, bottom=floor, color=list(colours[drawn]), width=0.8)
        if other is not None:
            shown = other > ZERO_BAR * top
            ax.bar(ks[shown], other[shown] - floor, bottom=floor, facecolor="none", edgecolor=_FILTERED,
                   linewidth=1.0, width=0.8)
        ax.set_yscale("log")
        ax.set_ylim(floor, top * 3 if top > 0 else 1.0)
        ax.set_ylabel(label)
        ax.grid(True, which="major", axis="y", alpha=0.3)
        if band is not None and band.k_high >= 1:
            ax.axvspan(max(band.k_low, 0.5), band.k_high, color=_BAND, alpha=0.6, zorder=0)
    axes[-1].set_xlabel("harmonic k (frequency k·n/60 Hz at n rpm)")
    axes[-1].set_xlim(0.3, count + 0.7)
    from matplotlib.patches import Patch

    handles = [Patch(color=_KEPT, label="kept")]
    if band is not None:
        if any(g == 0 for g in band.gains.values()):
            handles.append(Patch(color=_REMOVED, label="removed"))
        if any(g > 0 for g in band.gains.values()):
            handles.append(Patch(color=_TAPERED, label="tapered"))
        handles.append(Patch(color=_BAND, label="resonance band"))
        low_hz, high_hz = band.frequency_band_hz()
        axes[0].set_title(
            f"resonance band (shaded): k·n/60 in [{low_hz:.4g}, {high_hz:.4g}] Hz for n in "
            f"[{band.rpm[0]:g}, {band.rpm[1]:g}] rpm → k in [{band.k_low:.3f}, {band.k_high:.3f}]; "
            f"removed k = {_ranges(band.removed)}", fontsize=9)
    if filtered is not None:
        handles.append(Patch(facecolor="none", edgecolor=_FILTERED, label="filtered"))
    axes[0].legend(handles=handles, loc="upper right", fontsize=8)
    zeros = sorted(set(zero_lists[0]) & set(zero_lists[1]))
    if zeros:
        axes[-1].set_xlabel(f"harmonic k (frequency k·n/60 Hz at n rpm); zero amplitude, not drawn: "
                            f"k = {_short_list(zeros)}")
    fig.suptitle(title or "harmonic amplitudes", fontsize=11)
    return fig


def _checks_by_name(verdict) -> dict:
    return {check.name: check for check in verdict.checks} if verdict is not None else {}


def plot_filtered(original, written, *, title: str = "", verdict=None, unit: str = "mm", samples: int = 4096,
                  labels: tuple[str, str] = ("original", "written (filtered.dxf)")):
    """The original and the written law (both read from rest at s = 0), their deviation with its limits, and
    their accelerations with the peak-ratio limit.

    Parameters
    ----------
    original, written : MotionLaw
    verdict : camcad.verdict.Verdict or None
        ``judge_filter``'s checks: their limits and margins are drawn where they apply.
    unit : str
        The law's unit.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fine, scale = FINE.get(unit, (unit, 1.0))
    checks = _checks_by_name(verdict)
    theta = np.linspace(0.0, original.cycle, samples + 1)
    first, second = original.kinematics(theta), written.kinematics(theta)
    s_o = first.s - original.kinematics(np.zeros(1)).s[0]
    s_w = second.s - written.kinematics(np.zeros(1)).s[0]
    deg = np.degrees(theta)
    fig, axes = new_figure(10, 9.5, rows=3, sharex=True)
    for ax in axes:
        for phase in written.phases:
            if phase.kind == "dwell":
                ax.axvspan(np.degrees(phase.start), np.degrees(phase.end), color=COLOURS["dwell"], zorder=0)
    axes[0].plot(deg, s_o, color=_KEPT, lw=1.4, label=labels[0])
    axes[0].plot(deg, s_w, color=_FILTERED, lw=1.0, ls="--", label=labels[1])
    axes[0].set_ylabel(f"s ({unit}, from rest at s = 0)")
    axes[0].legend(loc="upper right", fontsize=8)
    deviation = (s_w - s_o) * scale
    axes[1].plot(deg, deviation, color="#8e44ad", lw=1.0, label=f"{labels[1]} − {labels[0]}")
    for name, style in (("dwell deviation", ":"), ("deviation from the original", "--")):
        check = checks.get(name)
        if check is None or check.limit is None:
            continue
        for sign in (-1, 1):
            axes[1].axhline(sign * check.limit * scale, color=COLOURS["limit"], lw=0.9, ls=style,
                            label=(f"{name} limit ±{check.limit * scale:.3g} {fine}: value {check.value * scale:.3g}, "
                                   f"margin {check.margin * scale:.3g} {fine}") if sign > 0 else None)
    peak = int(np.argmax(np.abs(deviation)))
    right = deg[peak] > 0.7 * deg[-1]
    axes[1].annotate(f"largest {abs(deviation[peak]):.3g} {fine} at {deg[peak]:.1f}°", (deg[peak], deviation[peak]),
                     fontsize=8, xytext=(-5 if right else 5, 5), textcoords="offset points",
                     ha="right" if right else "left")
    axes[1].set_ylabel(f"deviation of s ({fine})")
    axes[1].legend(loc="lower left", fontsize=7.5)
    axes[2].plot(deg, first.a, color=_KEPT, lw=1.4, label=labels[0])
    axes[2].plot(deg, second.a, color=_FILTERED, lw=1.0, ls="--", label=labels[1])
    ratio = checks.get("peak acceleration ratio")
    if ratio is not None and ratio.limit is not None:
        allowed = ratio.limit * float(np.max(np.abs(first.a)))
        for sign in (-1, 1):
            axes[2].axhline(sign * allowed, color=COLOURS["limit"], lw=0.9, ls="--",
                            label=(f"peak limit {ratio.limit:g} × original: ratio {ratio.value:.3g}, margin "
                                   f"{ratio.margin:.3g}") if sign > 0 else None)
    axes[2].set_ylabel(f"a ({accel_label(unit)})")
    axes[2].set_xlabel("cam angle θ (deg); dwells shaded")
    axes[2].legend(loc="upper right", fontsize=7.5)
    for ax in axes:
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlim(0, deg[-1])
    verdict_text = "" if verdict is None else ("  (all checks passed)" if verdict.passed else "  (a check FAILED)")
    fig.suptitle((title or "original and written law") + verdict_text, fontsize=11)
    return fig


def plot_truncation(rms_errors: np.ndarray, *, max_errors: dict | None = None, tol: float | None = None,
                    title: str = "", unit: str = "mm"):
    """RMS (Parseval) and sampled max error of the series cut after N harmonics, against N (``unit``)."""
    fig, ax = new_figure(8, 4.5)
    ns = np.arange(len(rms_errors))
    positive = rms_errors > 0
    ax.semilogy(ns[positive], rms_errors[positive], "o-", ms=3, color=_KEPT, label="RMS error (Parseval)")
    if max_errors:
        keys = sorted(max_errors)
        ax.semilogy(keys, [max_errors[k] for k in keys], "s--", ms=4, color=_TAPERED, label="max error (sampled)")
    if tol is not None:
        ax.axhline(tol, color=_REMOVED, ls=":", lw=1, label=f"tolerance {tol:g} {unit}")
    ax.set_xlabel("harmonics kept N")
    ax.set_ylabel(f"error of the truncated series ({unit})")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(title or "truncation error", fontsize=11)
    return fig


# --------------------------------------------------------------------------------------------
# Files and text
# --------------------------------------------------------------------------------------------

def write_spectrum(report, out, *, r12: bool = False, plots: bool = True, json_name: str | None = None) -> list[Path]:
    """Write a spectrum run's files into ``out`` (an OutputFolder): spectrum.csv; with a filter or lead-in
    filtered.dxf and filtered.csv (the written law); the plots. Every name (and ``json_name``, written later
    by the caller) is checked as one set before the first file is written. Returns the paths."""
    result = report.result
    data = ["spectrum.csv"] + (["filtered.dxf", "filtered.csv"] if result.outcome is not None else [])
    plot_names = ["spectrum.png", "truncation.png"] + (["filtered.png"] if result.outcome is not None else [])
    out.plan(data + (plot_names if plots else []) + ([json_name] if json_name else []))
    unit = result.unit
    outputs = []
    gains = (result.resonance.gains if result.resonance is not None and result.outcome is not None
             and result.outcome.filtered is not None else {})
    rows = [f"k,amplitude_{unit},phase_deg,accel_amplitude_{unit}_per_rad2,accel_phase_deg,gain"]
    for row in report.body["harmonics"]:
        phase = "" if row["phase_deg"] is None else f"{row['phase_deg']:.10g}"
        accel_phase = "" if row["accel_phase_deg"] is None else f"{row['accel_phase_deg']:.10g}"
        rows.append(f"{row['k']},{row['amplitude']:.12g},{phase},{row['accel_amplitude']:.12g},{accel_phase},"
                    f"{gains.get(row['k'], 1.0):g}")
    outputs.append(write_text_atomic(out.path("spectrum.csv"), "\n".join(rows) + "\n"))
    outcome = result.outcome
    if outcome is not None:
        from camcad.io.law_write import write_law_csv, write_law_dxf

        final = outcome.law
        title = (f"camcad spectrum {result.name}: " + ("filtered" if outcome.filtered is not None else "")
                 + (" + lead-in" if outcome.lead_in is not None else "") + f" law, a ({unit}/rad^2) vs deg")
        outputs.append(write_law_dxf(out.path("filtered.dxf"), np.degrees(final.x), final.a, layer="ACCEL",
                                     r12=r12, title=title, record=result.record))
        # a at the polyline's own ordinates: both values of a jump (kinematics gives the right-hand one twice)
        rows = replace(final.kinematics(final.x), a=np.asarray(final.a))
        outputs.append(write_law_csv(out.path("filtered.csv"), rows, record=result.record, unit=unit))
    if plots:
        name = result.name
        figures = [("spectrum.png", plot_spectrum(result.spectrum, band=result.resonance, filtered=result.after,
                                                  title=f"{name}: harmonic amplitudes", unit=unit)),
                   ("truncation.png", plot_truncation(result.rms, max_errors=result.max_errors, tol=result.tol,
                                                      title=f"{name}: error of the truncated series", unit=unit))]
        if outcome is not None:
            what = "filtered" if outcome.filtered is not None else "lead-in"
            figures.append(("filtered.png", plot_filtered(result.law, outcome.law, verdict=report.verdict, unit=unit,
                                                          title=f"{name}: original and {what} law as written")))
        for file_name, fig in figures:
            outputs.append(save_figure(fig, out.path(file_name)))
    return outputs


def spectrum_lines(run) -> list[str]:
    """The text output of ``camcad spectrum``: header, harmonics, truncation errors, resonance, the filter's
    figures, the verdict (tightest margins first) and the files written."""
    report = run.report
    data = report.body
    result = report.result
    unit = result.unit
    lines = header_lines(report)
    lines.append(f"{data['method']} analysis" + (f" ({data['samples']} samples)" if data["samples"] else "")
                 + f", mean {fmt(data['mean'], 6)} {unit}")
    removed = set(data.get("removed", []))
    resonant = set(result.resonance.core) if result.resonance is not None else set()
    rows = []
    listed = result.listed
    harmonics = data["harmonics"]
    extra = [r for r in harmonics[listed:] if r["k"] in resonant or r["k"] in removed]
    for row in harmonics[:listed] + extra:
        mark = "removed" if row["k"] in removed else ("resonant" if row["k"] in resonant else "")
        rows.append([row["k"], fmt(row["amplitude"], 6), fmt(row["phase_deg"], 6), fmt(row["accel_amplitude"], 6),
                     fmt(row["accel_phase_deg"], 6), mark])
    lines += table(["k", f"A_k ({unit})", "phi_k (deg)", f"accel A_k ({accel_label(unit)})", "accel phi_k (deg)", ""],
                   rows, title=f"harmonics of s = mean + sum A_k sin(k theta + phi_k) (first {listed}; "
                               "phi '-' where A_k is zero)")
    error_rows = []
    for n, value in data["max_error"].items():
        rms = data["rms_error"].get(n, data.get("rms_error_at_least_harmonics"))
        error_rows.append([n, f"{rms:.3e}", f"{value:.3e}"])
    lines += table(["N", f"RMS ({unit})", f"max ({unit})"], error_rows,
                   title="error of the series truncated after N harmonics")
    if "least_harmonics" in data:
        least = data["least_harmonics"]
        lines.append(f"least N with RMS error <= {result.tol:g} {unit}: {least if least is not None else 'not found'}")
    if "resonance" in data:
        r = data["resonance"]
        lines.append(f"resonance: fn {r['fn_hz']:g} Hz, {r['rpm'][0]:g}..{r['rpm'][1]:g} rpm, "
                     f"band +-{100 * r['band']:g} % -> k in [{r['k_band'][0]:.3f}, {r['k_band'][1]:.3f}]: "
                     f"resonant {r['resonant'] or 'none'}")
    if "removed" in data:
        lines.append(f"filtered: removed {_ranges(data['removed'])}")
    if "lead_in" in data:
        lead = data["lead_in"]
        lines.append(f"lead-in: {lead['angle_deg']:g} deg at {lead['fraction']:g} of the peak acceleration before "
                     f"{len(lead['segments'])} motion(s)")
    for note in data.get("notes", []) + data.get("filter", {}).get("notes", []):
        lines.append(note_line(note))
    if report.verdict.checks:
        lines += verdict_lines(report.verdict, common_applies(report))
    lines += output_lines(run.outputs)
    return lines


@dataclass(frozen=True)
class SpectrumCommand:
    """``camcad spectrum``: what to compute (camcad.scene.commands.spectrum.SpectrumRequest) and what to write."""

    request: SpectrumRequest
    output: Path | None = None
    plots: bool = True
    r12: bool = False


def spectrum_command(command: SpectrumCommand):
    """Run ``camcad spectrum``: resolve the law, compute (camcad.scene.commands.spectrum.run_spectrum), write the files
    and spectrum.json into the output folder (the inputs are never replaced). Returns a CommandRun."""
    src = resolve_source(command.request.law, command="spectrum")
    with open_folder(command.output, src.name, src.inputs) as out:
        report = run_spectrum(command.request, src)
        written = write_spectrum(report, out, r12=command.r12, plots=command.plots, json_name="spectrum.json")
        return finish(report, out, written, "spectrum.json", spectrum_lines)
