"""``camcad contact``: the contact-stress plots (Figures), files and text.

- ``plot_contact_stress``: σ_H and the normal force along the profile at the worst speed, [σ_H] and the
  margin at the maximum, the least normal force of a force-closed follower, the phases shaded, and which
  phase angles were analysed.
- ``plot_safety_versus_speed``: σ_max and the safety factor [σ_H]/σ_max against speed (as the batten study
  plots it), each in its own panel with its limit.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from camcad.io.output_folder import distinct_names
from camcad.report.command import finish, open_folder, write_figures
from camcad.report.figure import COLOURS, new_figure
from camcad.report.text import fmt, table, verdict_lines
from camcad.scene.commands.contact import run_contact
from camcad.scene.commands.source import require_scene
from camcad.scene.file import read_scene

if TYPE_CHECKING:
    from camcad.scene.commands.contact import ContactRequest

_STRESS = "#2e86c1"


def _shade(ax, phases_deg) -> None:
    colours = {"rise": "#e8f0fb", "return": "#fbeee8"}
    for start, end, kind in phases_deg:
        if kind in colours:
            ax.axvspan(start, end, color=colours[kind], zorder=0)


def plot_contact_stress(item, *, title: str = "", check=None, force_check=None):
    """σ_H and the normal force against the cam angle at the worst speed of one mechanism.

    Parameters
    ----------
    item : camcad.scene.contact.MechanismContact
    check, force_check : camcad.verdict.Check or None
        The stress check and the normal-force check: their limits and margins are drawn.

    Returns
    -------
    matplotlib.figure.Figure
    """
    result = item.at_worst
    theta_deg = np.degrees(result.theta)
    fig, (ax_s, ax_f) = new_figure(9.5, 6.5, rows=2, sharex=True)
    for ax in (ax_s, ax_f):
        _shade(ax, item.angles.phases_deg)
    ax_s.plot(theta_deg, result.sigma, color=_STRESS, label="σ_H")
    margin = result.allowable - result.sigma_max
    ax_s.axhline(result.allowable, color=COLOURS["limit"], linestyle="--",
                 label=f"[σ_H] = {result.allowable:g} MPa: margin {margin:.4g} MPa "
                       f"({100 * margin / result.allowable:.3g} %)")
    ax_s.plot(np.degrees(result.at), result.sigma_max, "o", color=COLOURS["limit"])
    ax_s.annotate(f"σ_max {result.sigma_max:.4g} MPa at {np.degrees(result.at):.1f}°",
                  (np.degrees(result.at), result.sigma_max), textcoords="offset points", xytext=(6, -14), fontsize=8)
    ax_s.set_ylabel("contact stress σ_H, MPa")
    ax_s.set_ylim(0, max(result.allowable, result.sigma_max) * 1.12)
    ax_s.legend(fontsize=8, loc="lower right")
    ax_f.plot(theta_deg, result.normal_force, color="black", lw=1.0, label=f"normal force at {result.rpm:g} rpm")
    ax_f.axhline(0.0, color="0.5", linewidth=0.8)
    if force_check is not None:
        ax_f.plot(np.degrees(result.min_force_at), result.min_force, "v", color=COLOURS["limit"],
                  label=f"least {force_check.value:.4g} N (all speeds) ≥ 0: margin {force_check.margin:.4g} N")
    if result.separation:
        ax_f.fill_between(theta_deg, result.normal_force, 0.0, where=result.normal_force <= 0,
                          color=COLOURS["fail"], alpha=0.3, label="follower leaves the cam")
    ax_f.legend(fontsize=8, loc="upper right")
    ax_f.set_ylabel("normal force, N")
    ax_f.set_xlabel("cam angle θ, deg (rises shaded blue, returns red)")
    ax_f.set_xlim(0, 360)
    for ax in (ax_s, ax_f):
        ax.grid(color="0.9")
    whose = item.angles.describe()
    ax_s.set_title(f"{title or item.name} at {result.rpm:g} rpm: safety factor {result.safety_factor:.3f}\n"
                   f"{whose}", fontsize=9)
    return fig


def plot_safety_versus_speed(sweep, *, title: str = ""):
    """σ_max with [σ_H] (top) and the safety factor [σ_H]/σ_max with 1 (bottom) against the shaft speed; the
    separation speed of a force-closed follower is marked when it falls in the range."""
    fig, (top, bottom) = new_figure(8.5, 6, rows=2, sharex=True)
    top.plot(sweep.rpm, sweep.sigma_max, "s-", color=_STRESS, ms=3, label="σ_max along the profile")
    top.axhline(sweep.allowable, color=COLOURS["limit"], ls="--", label=f"[σ_H] = {sweep.allowable:g} MPa")
    top.set_ylabel("σ_max, MPa")
    top.set_ylim(0, max(sweep.allowable, float(np.max(sweep.sigma_max))) * 1.12)
    bottom.plot(sweep.rpm, sweep.safety_factor, "o-", color="black", ms=3, label="safety factor [σ_H]/σ_max")
    worst = int(np.argmin(sweep.safety_factor))
    bottom.axhline(1.0, color=COLOURS["limit"], ls="--",
                   label=f"1: least {sweep.safety_factor[worst]:.3f} at {sweep.rpm[worst]:g} rpm, margin "
                         f"{sweep.safety_factor[worst] - 1:.3g}")
    bottom.set_ylabel("safety factor")
    bottom.set_xlabel("shaft speed n, rpm")
    if np.isfinite(sweep.separation_rpm) and sweep.separation_rpm <= sweep.rpm.max():
        for ax in (top, bottom):
            ax.axvline(sweep.separation_rpm, color="black", linestyle=":",
                       label=f"separation from {sweep.separation_rpm:.0f} rpm" if ax is bottom else None)
    for ax in (top, bottom):
        ax.grid(color="0.9")
        ax.legend(fontsize=8, loc="best")
    top.set_title(title or "Contact stress and safety factor against speed", fontsize=10)
    return fig


def contact_figures(report) -> list[tuple[tuple[str, ...], object]]:
    """((file name parts), Figure) of a contact report: per mechanism the stress along the profile and, with
    several speeds, the safety factor against speed."""
    checks = {c.name: c for c in report.verdict.checks}
    figures: list[tuple[tuple[str, ...], object]] = []
    for item in report.result:
        stress = checks.get(f"{item.name}: contact stress")
        force = checks.get(f"{item.name}: normal force (spring holds the follower)")
        figures.append(((f"contact_{item.name}.png",), plot_contact_stress(item, check=stress, force_check=force)))
        if len(item.sweep.rpm) > 1:
            figures.append(((f"contact_speed_{item.name}.png",),
                            plot_safety_versus_speed(item.sweep, title=f"{item.name}: contact stress against speed")))
    return figures


def contact_lines(run) -> list[str]:
    report = run.report
    source = report.source
    lines = [f"{source['name']} ({source['scene']}): contact stress",
             f"phase angles analysed: {source['phase_angles']}"]
    rows = []
    for item in report.result:
        r = report.body["mechanisms"][item.name]
        limits = ", ".join(f"{k} {fmt(v)}" for k, v in r["phase_limit_deg"].items()) or "-"
        motions = ", ".join(f"{k} {fmt(b - a)}" for a, b, k in item.angles.phases_deg if k != "dwell")
        rows.append([item.name, fmt(r["sigma_max_MPa"]), fmt(r["at_deg"]), fmt(r["rpm"]), fmt(r["safety_factor"]),
                     "yes" if r["separation"] else "no", f"{motions} ({item.angles.source})", limits])
    lines += table(["mechanism", "σ_max MPa", "at deg", "rpm", "safety", "separation", "phase angles deg",
                    "least for [σ_H] deg"], rows)
    for name, r in report.body["mechanisms"].items():
        for note in r.get("notes", []):
            lines.append(f"  {name}: {note}")
        if r["phase_angles"].get("note"):
            lines.append(f"  {name}: {r['phase_angles']['note']}")
    for name, reason in report.skipped.items():
        lines.append(f"  skipped {name}: {reason}")
    lines += verdict_lines(report.verdict, details=False)
    return lines + [f"written: {p}" for p in run.outputs]


@dataclass(frozen=True)
class ContactCommand:
    """``camcad contact``: the request (camcad.scene.commands.contact.ContactRequest) and what to write."""

    request: ContactRequest
    output: Path | None = None
    plots: bool = True


def contact_command(command: ContactCommand):
    """Run ``camcad contact``: compute (camcad.scene.commands.contact.run_contact), write the plots and
    contact.json into the output folder (the scene and its law files are never replaced). Returns a CommandRun."""
    path = require_scene(command.request.scene, "contact")
    scene = read_scene(path)
    with open_folder(command.output, path.stem, scene.input_files()) as out:
        report = run_contact(command.request)
        distinct_names([item.name for item in report.result], "mechanisms", str(path))   # one plot each
        written = write_figures(out, contact_figures(report) if command.plots else [], "contact.json")
        return finish(report, out, written, "contact.json", contact_lines)
