"""Plots of the area balance: a, v and s over the cycle, phases shaded, areas filled, closures marked."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from camcad.arrays import unique
from camcad.io.atomic import write_atomic
from camcad.report.figure import new_figure

PHASE_COLOURS = {"rise": "#e8f1fb", "return": "#fdeee6", "dwell": "#f2f2f2"}


def _dense(law, samples: int = 4000) -> np.ndarray:
    theta = np.linspace(0.0, law.cycle, samples)
    return unique(np.concatenate((theta, law.x)))


def plot_balance(law, report, path: str | Path, *, corrected=None, after=None, title: str = "") -> Path:
    """Three stacked panels (a, v, s against θ in deg); with ``corrected`` (and its check ``after``), the
    corrected law on top."""
    fig, axes = new_figure(10, 8.5, rows=3, sharex=True)
    theta = _dense(law)
    kin = law.kinematics(theta)
    deg = np.degrees(theta)
    for ax in axes:
        for phase in law.phases:
            ax.axvspan(np.degrees(phase.start), np.degrees(phase.end), color=PHASE_COLOURS[phase.kind], zorder=0)
        ax.axhline(0.0, color="0.4", lw=0.8)
        ax.grid(True, alpha=0.3)
    ax_a, ax_v, ax_s = axes
    ax_a.fill_between(deg, kin.a, 0, where=kin.a >= 0, color="#2a9d8f", alpha=0.35, label="area above the axis")
    ax_a.fill_between(deg, kin.a, 0, where=kin.a < 0, color="#e76f51", alpha=0.35, label="area below the axis")
    ax_a.plot(deg, kin.a, color="k", lw=1.2, label="drawn law")
    ax_v.plot(deg, kin.v, color="k", lw=1.2)
    ax_s.plot(deg, kin.s, color="k", lw=1.2)
    if corrected is not None:
        theta_c = _dense(corrected)
        kin_c = corrected.kinematics(theta_c)
        deg_c = np.degrees(theta_c)
        ax_a.plot(deg_c, kin_c.a, color="#1d4ed8", lw=1.4, ls="--", label="corrected")
        ax_v.plot(deg_c, kin_c.v, color="#1d4ed8", lw=1.4, ls="--")
        ax_s.plot(deg_c, kin_c.s, color="#1d4ed8", lw=1.4, ls="--")
    for row in report.phases:
        mid = (row["start_deg"] + row["end_deg"]) / 2
        ax_a.annotate(row["kind"], (mid, 1.0), xycoords=("data", "axes fraction"), ha="center", va="top",
                      fontsize=9, color="0.3")
        if row["kind"] != "dwell":
            text = f"+{row['area_positive']:.4g}\n{row['area_negative']:.4g}"
            ax_a.annotate(text, (mid, 0.04), xycoords=("data", "axes fraction"), ha="center", fontsize=8)
            ax_v.plot([row["end_deg"]], [row["v_end"]], "o", color="#e76f51" if abs(row["v_end"]) > report.tolerance_abs
                      else "#2a9d8f")
    ax_s.plot([np.degrees(law.cycle)], [report.displacement_closure], "s",
              color="#2a9d8f" if report.balanced else "#e76f51", clip_on=False, zorder=5,
              label=f"closure gap {report.displacement_closure:.3g} mm")
    ax_a.set_ylabel("a (mm/rad²)")
    ax_v.set_ylabel("v (mm/rad)")
    ax_s.set_ylabel("s (mm)")
    ax_s.set_xlabel("cam angle θ (deg)")
    handles = [h for ax in (ax_a, ax_s) for h in ax.get_legend_handles_labels()[0]]
    fig.legend(handles=handles, loc="outside lower center", ncols=len(handles), fontsize=8, frameon=False)
    verdict = "balanced" if report.balanced else f"NOT balanced (closure gap {report.displacement_closure:.3g} mm)"
    if after is not None:
        verdict = (f"drawn: {verdict}; corrected: " + ("balanced" if after.balanced else "NOT balanced")
                   + f" (gap {after.displacement_closure:.2g} mm)")
    else:
        verdict += f", tolerance {report.tolerance_abs:.3g} mm"
    fig.suptitle(f"{title}\n{verdict}" if title else verdict)
    ax_s.set_xlim(0, np.degrees(law.cycle))
    return write_atomic(Path(path), lambda tmp: fig.savefig(tmp, dpi=120, format="png"))
