"""Cyclogram plots (Gantt chart and network) and the contact-stress plots of the same issue.

The contact plots live here with the cyclogram because both serve the phase-angle limits;
they move to a plots/contact.py of their own if contact grows more plots.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from camcad.io.atomic import write_atomic
from camcad.report.figure import pyplot

ACTIVE_COLOUR = "#c0392b"
SLACK_COLOUR = "#2e86c1"
FREE_COLOUR = "#95a5a6"


def _save(fig, path: str | Path) -> Path:
    plt = pyplot()
    out = write_atomic(path, lambda tmp: fig.savefig(tmp, format="png", dpi=130, bbox_inches="tight"))
    plt.close(fig)
    return out


def _bars(start: float, width: float, cycle: float) -> list[tuple[float, float]]:
    """(left, width) pieces of a bar on [0, cycle): a bar running past the cycle end wraps to 0."""
    left = start % cycle
    if left + width <= cycle + 1e-9:
        return [(left, width)]
    return [(left, cycle - left), (0.0, left + width - cycle)]


def plot_gantt(result, path: str | Path, title: str = "") -> Path:
    """Gantt-style cyclogram: one row per mechanism, a bar per operation over 0…cycle deg.

    Operations with an active bound (they set the makespan) are red, the others blue. Operations
    without a mechanism (waits, pure precedence) appear in the network plot only, unless no
    operation names a mechanism (then every operation gets its own row). Dashed lines mark the
    event times, labelled along the top.
    """
    plt = pyplot()
    network = result.network
    cycle = 360.0 if network.cycle_deg <= 360.0 else network.cycle_deg
    with_mechanism = [op for op in network.operations if op.mechanism]
    shown = with_mechanism or list(network.operations)
    rows: list[str] = []
    for op in shown:
        row = op.mechanism or op.label
        if row not in rows:
            rows.append(row)
    active = set(result.active_bounds)
    fig, ax = plt.subplots(figsize=(11, 1.6 + 0.75 * len(rows)))
    degrees_per_char = 2.6 * cycle / 360.0   # 7-pt text on an 11-inch figure
    for op in shown:
        row = rows.index(op.mechanism or op.label)
        start = result.event_times_deg[op.tail]
        width = result.phase_angles_deg[op.label]
        colour = ACTIVE_COLOUR if op.label in active else SLACK_COLOUR
        pieces = _bars(start, width, cycle)
        ax.broken_barh(pieces, (row - 0.32, 0.64), facecolors=colour, edgecolors="black", linewidth=0.6,
                       alpha=0.9)
        left, span = max(pieces, key=lambda piece: piece[1])
        name = op.name or op.label
        if span >= degrees_per_char * (len(name) + 1):
            text = f"{name}\n{width:.1f}°"
        elif span >= degrees_per_char * 5:
            text = f"{width:.1f}°"
        else:
            text = ""
        ax.text(left + span / 2, row, text, ha="center", va="center", fontsize=7, color="white", clip_on=True)
    placed: list[tuple[float, int]] = []
    for event, time in sorted(result.event_times_deg.items(), key=lambda item: item[1]):
        x = time % cycle
        ax.axvline(x, color="0.6", linestyle="--", linewidth=0.6, zorder=0)
        level = 0
        while any(abs(x - other) < degrees_per_char * 2.5 and lvl == level for other, lvl in placed):
            level += 1
        placed.append((x, level))
        ax.text(x, -0.45 - 0.22 * level, event, ha="center", va="bottom", fontsize=7, color="0.3")
    top = max((lvl for _, lvl in placed), default=0)
    ax.set_yticks(range(len(rows)), rows)
    ax.set_ylim(len(rows) - 0.4, -0.75 - 0.22 * top)
    ax.set_xlim(0, cycle)
    ax.set_xticks(np.arange(0, cycle + 1, 30))
    ax.set_xlabel("cam shaft angle, deg")
    ax.grid(axis="x", color="0.9")
    heading = title or "Cyclogram"
    ax.set_title(f"{heading}: makespan {result.makespan_deg:.2f}° of {network.cycle_deg:g}°  "
                 f"(red: operations with an active bound; numbers on top: events)", fontsize=9)
    return _save(fig, path)


def _lanes(times: dict[str, float], spacing: float) -> dict[str, int]:
    """A lane per event so that events closer in time than ``spacing`` do not overlap."""
    lanes: dict[str, int] = {}
    last_in_lane: dict[int, float] = {}
    for event, time in sorted(times.items(), key=lambda item: item[1]):
        lane = 0
        while lane in last_in_lane and time - last_in_lane[lane] < spacing:
            lane += 1
        lanes[event] = lane
        last_in_lane[lane] = time
    return lanes


def plot_network(result, path: str | Path, title: str = "") -> Path:
    """The network: events at their optimal times (x, deg), operations as arrows labelled with
    their phase angles; the critical path's arcs red, an active upper bound dashed."""
    plt = pyplot()
    network = result.network
    times = result.event_times_deg
    span = max(result.makespan_deg or 1.0, 1.0)
    lanes = _lanes(times, 0.1 * span)
    top = max(lanes.values())
    active = {(c.label, c.kind) for c in result.active}
    fig, ax = plt.subplots(figsize=(11, 2.6 + 0.9 * (top + 1)))
    ax.set_xlim(min(times.values()) - 0.05 * span, max(times.values()) + 0.05 * span)
    ax.set_ylim(-0.8, top + 0.8)
    to_display = ax.transData
    from_display = ax.transData.inverted()
    for op in network.operations:
        start = np.array([times[op.tail], lanes[op.tail]])
        end = np.array([times[op.head], lanes[op.head]])
        on_path = (op.label, "min") in active or (op.label, "max") in active
        bend = 0.25 if lanes[op.tail] == lanes[op.head] else 0.08
        ax.annotate("", xy=end, xytext=start,
                    arrowprops=dict(arrowstyle="-|>", color=ACTIVE_COLOUR if on_path else SLACK_COLOUR,
                                    linewidth=2.0 if on_path else 1.0,
                                    linestyle="--" if (op.label, "max") in active else "-",
                                    shrinkA=9, shrinkB=9, connectionstyle=f"arc3,rad={bend}"))
        # label at the middle of matplotlib's arc3 curve (a quadratic Bézier in display space)
        p0, p2 = to_display.transform(start), to_display.transform(end)
        middle = (p0 + p2) / 2
        dx, dy = p2 - p0
        control = middle + bend * np.array([dy, -dx])
        label_at = from_display.transform((p0 + 2 * control + p2) / 4)
        # angles only: the operations' names are on the Gantt chart, and long ones would collide here
        label = f"{result.phase_angles_deg[op.label]:.1f}°"
        ax.text(*label_at, label, ha="center", va="center", fontsize=6.5,
                color=ACTIVE_COLOUR if on_path else "black",
                bbox=dict(boxstyle="round,pad=0.15", facecolor="white", edgecolor="none", alpha=0.85))
    for event, time in times.items():
        critical = event in result.critical_path
        ax.plot(time, lanes[event], "o", markersize=15, markerfacecolor="white",
                markeredgecolor=ACTIVE_COLOUR if critical else "black", markeredgewidth=1.5, zorder=3)
        ax.text(time, lanes[event], event, ha="center", va="center", fontsize=7, zorder=4)
    ax.set_yticks([])
    ax.set_xlabel("event time p, deg")
    ax.grid(axis="x", color="0.9")
    path_text = " → ".join(result.critical_path)
    ax.set_title(f"{title or 'Network'}: critical path {path_text} (red; dashed: an active upper bound)",
                 fontsize=9)
    return _save(fig, path)


def plot_contact_stress(result, path: str | Path, title: str = "") -> Path:
    """σ_H and the normal force against cam angle at one speed, with [σ_H] and the maximum marked."""
    plt = pyplot()
    theta_deg = np.degrees(result.theta)
    fig, (ax_s, ax_f) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    ax_s.plot(theta_deg, result.sigma, color=SLACK_COLOUR, label="σ_H")
    ax_s.axhline(result.allowable, color=ACTIVE_COLOUR, linestyle="--", label=f"[σ_H] = {result.allowable:g} MPa")
    ax_s.plot(np.degrees(result.at), result.sigma_max, "o", color=ACTIVE_COLOUR)
    ax_s.annotate(f"{result.sigma_max:.0f} MPa at {np.degrees(result.at):.1f}°",
                  (np.degrees(result.at), result.sigma_max), textcoords="offset points", xytext=(6, 6),
                  fontsize=8)
    ax_s.set_ylabel("contact stress σ_H, MPa")
    ax_s.legend(fontsize=8, loc="upper right")
    ax_f.plot(theta_deg, result.normal_force, color="black")
    ax_f.axhline(0.0, color="0.5", linewidth=0.8)
    if result.separation:
        ax_f.fill_between(theta_deg, result.normal_force, 0.0, where=result.normal_force <= 0,
                          color=ACTIVE_COLOUR, alpha=0.3, label="follower leaves the cam")
        ax_f.legend(fontsize=8)
    ax_f.set_ylabel("normal force, N")
    ax_f.set_xlabel("cam angle θ, deg")
    ax_f.set_xlim(theta_deg[0], theta_deg[-1])
    for ax in (ax_s, ax_f):
        ax.grid(color="0.9")
    ax_s.set_title(f"{title or 'Contact stress'} at {result.rpm:g} rpm: safety factor "
                   f"{result.safety_factor:.2f}", fontsize=9)
    return _save(fig, path)


def plot_safety_versus_speed(sweep, path: str | Path, title: str = "") -> Path:
    """Safety factor [σ_H]/σ_max and σ_max against shaft speed (as the source plots it)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(sweep.rpm, sweep.safety_factor, "o-", color=SLACK_COLOUR, label="safety factor")
    ax.axhline(1.0, color=ACTIVE_COLOUR, linestyle="--", label="[σ_H] reached")
    if np.isfinite(sweep.separation_rpm) and sweep.separation_rpm <= sweep.rpm.max():
        ax.axvline(sweep.separation_rpm, color="black", linestyle=":",
                   label=f"separation from {sweep.separation_rpm:.0f} rpm")
    ax.set_xlabel("shaft speed n, rpm")
    ax.set_ylabel("safety factor [σ_H]/σ_max")
    second = ax.twinx()
    second.plot(sweep.rpm, sweep.sigma_max, "s--", color="0.4", markersize=4, label="σ_max")
    second.set_ylabel("σ_max, MPa")
    lines = ax.get_legend_handles_labels()
    extra = second.get_legend_handles_labels()
    ax.legend(lines[0] + extra[0], lines[1] + extra[1], fontsize=8, loc="upper center",
              bbox_to_anchor=(0.5, -0.16), ncol=4, frameon=False)
    ax.grid(color="0.9")
    ax.set_title(title or "Contact safety factor against speed", fontsize=9)
    return _save(fig, path)
