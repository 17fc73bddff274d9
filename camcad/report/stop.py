"""The stop impact beside its published figures: plots (Figures) and text lines.

- ``plot_published``: the first rebound against speed (camcad's model as a line over every speed shown, the
  published computed rebounds as filled markers, the measured ones open, the calibrated ones as stars) with
  the study's variants (one calibration each) as thin lines; the impact force against speed with the published
  forces; each panel says which figures are calibrated and which validate, and every error in the legend.
- ``plot_analogs``: the paper's Fig. 4 — displacement, velocity and acceleration analogs of the driven link
  with its elasticity (the elastic follower at the lever's free frequency) at the published speeds, beside the
  rigid law's, over the approach to the stop.
- ``published_lines``: the published figures beside camcad's with each error and role, the study's table and
  conclusion.
"""

from __future__ import annotations

import math

import numpy as np

from camcad.dynamics.impact import find_contact, impact_at
from camcad.dynamics.model import ElasticFollower, rpm_to_rad_s
from camcad.dynamics.steady import steady_state
from camcad.report.figure import COLOURS, new_figure
from camcad.report.text import fmt, table

VARIANT_STYLES = {"elastic approach": ("tab:orange", "--"), "Hertz duration": ("tab:green", "-."),
                  "restitution(v)": ("tab:purple", ":"), "half-sine pulse": ("tab:brown", (0, (3, 1, 1, 1))),
                  "cam-driven contact": ("tab:gray", (0, (5, 2)))}


def plot_published(run, *, title: str = ""):
    """Rebound and force against speed with the published points (module docstring).

    Parameters
    ----------
    run : camcad.dynamics.runs.ImpactRun
        An impact run with ``published`` figures (``run.study`` adds the variants).

    Returns
    -------
    matplotlib.figure.Figure
    """
    model, law = run.model, run.law
    fig, (left, right) = new_figure(13, 5.2, cols=2)
    speeds = [i.rpm for i in run.sweep.impacts] + [c.figure.rpm for c in run.comparisons if c.figure.rpm]
    low, high = 0.9 * min(speeds), 1.05 * max(speeds)
    grid = np.linspace(low, high, 60)
    contact = find_contact(law, model.stop, model.preload_mm, model.ratio)
    impacts = [impact_at(law, model, n, contact=contact) for n in grid]
    left.plot(grid, [i.rebound_mm for i in impacts], color="tab:red", lw=1.6, label="camcad (the paper's model)")
    right.plot(grid, [i.force_n for i in impacts], color="tab:blue", lw=1.6, label="camcad F = S/τ")
    if run.study is not None:
        for variant in run.study.variants[1:]:
            colour, style = VARIANT_STYLES.get(variant.name, ("0.5", "--"))
            left.plot(variant.speeds_rpm, variant.values_mm, color=colour, ls=style, lw=0.9,
                      label=f"{variant.name} (calibrated at {run.study.calibration_rpm:g} rpm)")
    for row in run.comparisons:
        figure = row.figure
        if figure.rpm is None:
            continue
        ax = left if figure.quantity == "rebound_mm" else right
        colour = "tab:red" if figure.quantity == "rebound_mm" else "tab:blue"
        marker = "*" if figure.calibrated else "o"
        face = "none" if figure.kind == "measured" else colour
        size = 11 if figure.calibrated else 6
        label = (f"{figure.kind} {figure.value:g} at {figure.rpm:g} rpm: "
                 + ("calibrated" if figure.calibrated else f"camcad {row.camcad:.4g} ({100 * row.relative:+.1f} %)"))
        edge = "black" if face != "none" else colour
        ax.plot([figure.rpm], [figure.value], marker=marker, ms=size, mfc=face, mec=edge, color=colour, ls="none",
                label=label, zorder=5)
    if model.allowed_amplitude_mm:
        left.axhline(model.allowed_amplitude_mm, color=COLOURS["limit"], ls="--", lw=0.8,
                     label=f"allowed {model.allowed_amplitude_mm:g} mm")
    source = run.published.source if run.published is not None else ""
    left.set_title("first rebound against speed\n" + _roles(run, "rebound_mm"), fontsize=9)
    left.set_xlabel("speed n, rpm")
    left.set_ylabel("first rebound amplitude, mm")
    left.set_ylim(bottom=0)
    right.set_title("impact force against speed\n" + _roles(run, "force_N"), fontsize=9)
    right.set_xlabel("speed n, rpm")
    right.set_ylabel("impact force F, N")
    right.set_ylim(bottom=0)
    for ax, where in ((left, "lower right"), (right, "upper left")):
        ax.set_xlim(low, high)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc=where)
    fig.suptitle((title or "Impact on the stop") + (f" — published: {source}" if source else "")
                 + "\nstars: the figures the scene was calibrated to; filled: computed in the source, open: measured",
                 fontsize=9.5)
    return fig


def _roles(run, quantity: str) -> str:
    """"calibrated at 280 rpm; validating 177 +101 %, 320 +2.6 %, …" for one quantity's computed figures."""
    rows = [r for r in run.comparisons if r.figure.quantity == quantity and r.figure.kind == "computed"]
    calibrated = [f"{r.figure.rpm:g}" for r in rows if r.figure.calibrated]
    checked = [f"{r.figure.rpm:g} rpm {100 * r.relative:+.1f} %" for r in rows if not r.figure.calibrated]
    parts = []
    if calibrated:
        parts.append(f"calibrated at {', '.join(calibrated)} rpm")
    if checked:
        parts.append("validating " + ", ".join(checked))
    return "; ".join(parts) or "no published figures"


def plot_analogs(law, natural_frequency_hz: float, damping_ratio: float, speeds_rpm, *, window=None,
                 title: str = "", unit: str = "mm", contact_deg: float | None = None):
    """The paper's Fig. 4: displacement, velocity and acceleration analogs with the link's elasticity.

    The elastic follower (natural frequency Hz, damping ratio) in steady state at each speed (rpm): its
    displacement y (law units), velocity analog dy/dθ = ẏ/ω and acceleration analog d²y/dθ² = ÿ/ω² (per rad,
    per rad²), beside the rigid law's s, ds/dθ, d²s/dθ² (black, dashed). ``window`` (deg, deg) limits the cam
    angles shown; ``contact_deg`` marks where the lever meets its stop (beyond it the lever is on the stop,
    which this free model does not hold).

    Returns
    -------
    matplotlib.figure.Figure
    """
    follower = ElasticFollower(natural_frequency_hz, damping_ratio)
    fig, axes = new_figure(9.5, 9.0, rows=3, sharex=True)
    first = True
    for rpm in speeds_rpm:
        response = steady_state(law, follower, float(rpm), samples=1 << 14)
        theta = response.theta
        omega = rpm_to_rad_s(float(rpm))
        y = response.displacement_elastic
        v = np.gradient(y, theta)
        a = response.accel_elastic / omega**2
        if first:
            kin = law.kinematics(theta)
            for ax, rigid in zip(axes, (kin.s, kin.v, kin.a)):
                ax.plot(np.degrees(theta), rigid, color="black", ls="--", lw=1.0, label="rigid law")
            first = False
        for ax, values in zip(axes, (y, v, a)):
            ax.plot(np.degrees(theta), values, lw=1.0, label=f"elastic, {rpm:g} rpm")
    labels = (f"displacement, {unit}", f"velocity analog, {unit}/rad", f"acceleration analog, {unit}/rad²")
    if contact_deg is not None:
        for k, ax in enumerate(axes):
            ax.axvline(contact_deg, color=COLOURS["limit"], lw=0.8, ls=":",
                       label=f"contact with the stop, {contact_deg:.2f} deg (free model beyond it)" if k == 0 else None)
    for ax, label in zip(axes, labels):
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    if window is not None:
        axes[-1].set_xlim(*window)
        for ax in axes:
            _autoscale_window(ax, window)
    axes[0].legend(fontsize=7.5, loc="best")
    axes[-1].set_xlabel("cam angle, deg")
    axes[0].set_title(title or f"Analogs with the link's elasticity ({natural_frequency_hz:.4g} Hz, "
                               f"ζ {damping_ratio:.3g}): the source's Fig. 4", fontsize=10)
    return fig


def _autoscale_window(ax, window) -> None:
    lo, hi = window
    values = []
    for line in ax.get_lines():
        x, y = (np.asarray(d, dtype=float) for d in line.get_data())
        inside = (x >= lo) & (x <= hi)
        values.extend(y[inside].tolist())
    if values:
        bottom, top = min(values), max(values)
        pad = 0.06 * (top - bottom or 1.0)
        ax.set_ylim(bottom - pad, top + pad)


def published_lines(run) -> list[str]:
    """The published figures beside camcad's (value, error, role), the study's variants and its conclusion."""
    if not run.comparisons:
        return []
    source = run.published.source if run.published is not None else ""
    lines = [f"published figures ({source}):" if source else "published figures:"]
    rows = []
    for row in run.comparisons:
        f = row.figure
        rows.append([f.quantity, "-" if f.rpm is None else fmt(f.rpm), f.kind, fmt(f.value), fmt(row.camcad),
                     fmt(row.error), f"{100 * row.relative:+.2f} %", row.role])
    lines += table(["figure", "rpm", "kind", "published", "camcad", "error", "error %", "role"], rows)
    study = run.study
    if study is not None:
        lines.append(f"the rebound's speed dependence, each variant calibrated once at {study.calibration_rpm:g} rpm "
                     "(error % at each published speed):")
        head = ["variant"] + [f"{s:g} rpm" for s in study.speeds_rpm]
        rows = [[v.name] + [f"{100 * e:+.1f}" for e in v.errors] for v in study.variants]
        lines += table(head, rows)
        lines.append(study.conclusion)
    return lines


def analogs_window(run) -> tuple[float, float]:
    """The cam angles (deg) around the approach to the stop: the approach phase and a little after."""
    phase = run.sweep.contact.phase
    start, end = math.degrees(phase.start), math.degrees(phase.end)
    width = end - start
    return start - 0.3 * width, end + 0.8 * width
