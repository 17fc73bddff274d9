"""``camcad cyclogram``: the Gantt chart and the network of an optimised cyclogram (Figures), files and text.

- ``plot_gantt``: one row per operation of a mechanism, every bar named (operation, mechanism, phase) with its
  phase angle; the part of a bar up to its least admissible angle is solid, the margin beyond it light, so a
  bar held at its limit has no light part; operations with an active bound (they set the makespan) are red.
- ``plot_network``: events at their optimal times, operations as arrows labelled with their phase angles
  (labels moved apart where they would overlap); the critical path red, an active upper bound dashed — the
  legend lists only the styles drawn.

Both take a ``CyclogramResult`` or the ``cyclogram`` object of a report (``cyclogram_view``), so the scene
pipeline can plot from its report.json content.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from camcad.report.command import finish, open_folder, write_figures
from camcad.report.figure import new_figure
from camcad.report.text import fmt, table, verdict_lines
from camcad.scene.commands.cyclogram import run_cyclogram
from camcad.scene.commands.source import require_scene
from camcad.scene.file import read_scene
from camcad.scene.sections.cyclogram import parse_cyclogram

if TYPE_CHECKING:
    from camcad.cyclogram.network import Network
    from camcad.scene.commands.cyclogram import CyclogramRequest

ACTIVE_COLOUR = "#c0392b"
SLACK_COLOUR = "#2e86c1"
MARGIN_ALPHA = 0.35


@dataclass(frozen=True)
class CyclogramView:
    """What the plots need of an optimised cyclogram (from a CyclogramResult or its report dict)."""

    network: Network
    makespan_deg: float
    event_times_deg: dict
    phase_angles_deg: dict
    critical_path: tuple
    active: frozenset                      # {(label, "min" | "max")}
    least_deg: dict = field(default_factory=dict)   # {label: (deg, source)}


def cyclogram_view(result, network=None) -> CyclogramView:
    """A CyclogramView of a CyclogramResult, or of a report's ``cyclogram`` dict with its ``network``."""
    if isinstance(result, dict):
        return CyclogramView(network, float(result["makespan_deg"]), dict(result["event_times_deg"]),
                             dict(result["phase_angles_deg"]), tuple(result["critical_path"]),
                             frozenset((a["operation"], a["kind"]) for a in result.get("active", [])),
                             {k: (v["deg"], v["source"]) for k, v in result.get("lower_bounds_deg", {}).items()})
    return CyclogramView(result.network, float(result.makespan_deg), dict(result.event_times_deg),
                         dict(result.phase_angles_deg), tuple(result.critical_path),
                         frozenset((c.label, c.kind) for c in result.active), dict(result.lower_bounds_deg))


def _bars(start: float, width: float, cycle: float) -> list[tuple[float, float]]:
    """(left, width) pieces of a bar on [0, cycle): a bar running past the cycle end wraps to 0."""
    left = start % cycle
    if left + width <= cycle + 1e-9:
        return [(left, width)]
    return [(left, cycle - left), (0.0, left + width - cycle)]


def plot_gantt(result, *, title: str = "", network=None):
    """Gantt-style cyclogram (module docstring): every operation of a mechanism on its own row, named.

    Parameters
    ----------
    result : CyclogramResult or dict
        The optimised cyclogram (or its report's ``cyclogram`` object with ``network``).

    Returns
    -------
    matplotlib.figure.Figure
    """
    view = result if isinstance(result, CyclogramView) else cyclogram_view(result, network)
    net = view.network
    cycle = max(360.0, net.cycle_deg)
    with_mechanism = [op for op in net.operations if op.mechanism]
    shown = with_mechanism or list(net.operations)
    shown.sort(key=lambda op: (view.event_times_deg[op.tail] % cycle, op.label))
    fig, ax = new_figure(12, 1.9 + 0.42 * len(shown))
    labels = []
    for row, op in enumerate(shown):
        start = view.event_times_deg[op.tail]
        width = view.phase_angles_deg[op.label]
        least, source = view.least_deg.get(op.label, (0.0, "bounds_deg"))
        active = (op.label, "min") in view.active or (op.label, "max") in view.active
        colour = ACTIVE_COLOUR if active else SLACK_COLOUR
        solid = min(least, width)
        for left, span in _bars(start, solid, cycle):
            ax.broken_barh([(left, span)], (row - 0.32, 0.64), facecolors=colour, edgecolors="black", linewidth=0.5)
        if width - solid > 1e-9:
            for left, span in _bars(start + solid, width - solid, cycle):
                ax.broken_barh([(left, span)], (row - 0.32, 0.64), facecolors=colour, alpha=MARGIN_ALPHA,
                               edgecolors="black", linewidth=0.5)
        end = (start + width) % cycle or cycle
        text = f"{width:.1f}°" + (f"  (least {least:.1f}°, {source})" if least > 0 else "")
        ax.text(min(end + 1.5, cycle - 1), row, text, ha="left" if end + 1.5 < cycle - 40 else "right",
                va="center", fontsize=7, color="0.15")
        what = f"{op.mechanism} {op.phase}" if op.mechanism and op.phase else (op.mechanism or "")
        name = op.name or op.label
        labels.append(f"{name} [{op.label}]" + (f" — {what}" if what else ""))
    placed: list[tuple[float, int]] = []
    degrees_per_char = 2.4 * cycle / 360.0
    for event, time in sorted(view.event_times_deg.items(), key=lambda item: item[1]):
        x = time % cycle
        ax.axvline(x, color="0.6", linestyle="--", linewidth=0.6, zorder=0)
        level = 0
        while any(abs(x - other) < degrees_per_char * (len(event) + 2) and lvl == level for other, lvl in placed):
            level += 1
        placed.append((x, level))
        ax.text(x, -0.55 - 0.3 * level, event, ha="center", va="bottom", fontsize=7, color="0.25")
    top = max((lvl for _, lvl in placed), default=0)
    ax.set_yticks(range(len(shown)), labels, fontsize=7.5)
    ax.set_ylim(len(shown) - 0.4, -0.85 - 0.3 * top)
    ax.set_xlim(0, cycle)
    ax.set_xticks(np.arange(0, cycle + 1, 30))
    ax.set_xlabel("cam shaft angle, deg (event numbers on top)")
    ax.set_axisbelow(True)
    ax.grid(axis="x", color="0.9")
    from matplotlib.patches import Patch

    handles = [Patch(color=ACTIVE_COLOUR, label="active bound: sets the makespan"),
               Patch(color=SLACK_COLOUR, label="slack"),
               Patch(facecolor="0.5", alpha=MARGIN_ALPHA, label="margin beyond the least admissible angle")]
    ax.legend(handles=handles, fontsize=7, loc="lower right", framealpha=0.9)
    slack = net.cycle_deg - view.makespan_deg
    ax.set_title(f"{title or 'Cyclogram'}: makespan {view.makespan_deg:.2f}° of {net.cycle_deg:g}° "
                 f"(slack {slack:.2f}°), start at {net.start_deg:g}°", fontsize=9)
    return fig


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


def _separate(boxes: list[list[float]], step: float, rounds: int = 200) -> list[list[float]]:
    """Move overlapping label boxes [x0, y0, x1, y1] (display units) apart vertically, the later one each time."""
    for _ in range(rounds):
        moved = False
        for i in range(len(boxes)):
            for j in range(i + 1, len(boxes)):
                a, b = boxes[i], boxes[j]
                if a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]:
                    shift = step if b[1] >= a[1] else -step
                    b[1] += shift
                    b[3] += shift
                    moved = True
        if not moved:
            break
    return boxes


def plot_network(result, *, title: str = "", network=None):
    """The network (module docstring): events at their optimal times (x, deg), operations as labelled arrows.

    Parameters
    ----------
    result : CyclogramResult or dict
        The optimised cyclogram (or its report's ``cyclogram`` object with ``network``).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.lines import Line2D

    view = result if isinstance(result, CyclogramView) else cyclogram_view(result, network)
    net = view.network
    times = view.event_times_deg
    span = max(view.makespan_deg or 1.0, 1.0)
    lanes = _lanes(times, 0.08 * span)
    top = max(lanes.values())
    fig, ax = new_figure(12, 3.2 + 1.0 * (top + 1), layout=None)
    fig.subplots_adjust(left=0.03, right=0.99, top=0.92, bottom=0.16)
    ax.set_xlim(min(times.values()) - 0.05 * span, max(times.values()) + 0.05 * span)
    ax.set_ylim(-0.9, top + 0.9)
    fig.canvas.draw()
    to_display = ax.transData
    from_display = ax.transData.inverted()
    styles = set()
    pending = []
    on_path_ops = {(a, b) for a, b in zip(view.critical_path, view.critical_path[1:])}
    for op in net.operations:
        start = np.array([times[op.tail], lanes[op.tail]])
        end = np.array([times[op.head], lanes[op.head]])
        active_min = (op.label, "min") in view.active
        active_max = (op.label, "max") in view.active
        critical = (op.tail, op.head) in on_path_ops or (op.head, op.tail) in on_path_ops or active_min or active_max
        style = ("critical" if critical else "slack", "dashed" if active_max else "solid")
        styles.add(style)
        bend = 0.25 if lanes[op.tail] == lanes[op.head] else 0.08
        ax.annotate("", xy=end, xytext=start,
                    arrowprops={"arrowstyle": "-|>", "color": ACTIVE_COLOUR if critical else SLACK_COLOUR,
                                    "linewidth": 2.0 if critical else 1.0, "linestyle": "--" if active_max else "-",
                                    "shrinkA": 10, "shrinkB": 10, "connectionstyle": f"arc3,rad={bend}"})
        p0, p2 = to_display.transform(start), to_display.transform(end)
        middle = (p0 + p2) / 2
        dx, dy = p2 - p0
        control = middle + bend * np.array([dy, -dx])
        at = (p0 + 2 * control + p2) / 4
        text = f"{view.phase_angles_deg[op.label]:.1f}°"
        width, height = 7.0 * len(text) + 6, 14.0
        pending.append([at[0] - width / 2, at[1] - height / 2, at[0] + width / 2, at[1] + height / 2, text, critical])
    boxes = _separate([p[:4] for p in pending], 15.0)
    for (x0, y0, x1, y1), (_, _, _, _, text, critical) in zip(boxes, pending):
        x, y = from_display.transform(((x0 + x1) / 2, (y0 + y1) / 2))
        ax.text(x, y, text, ha="center", va="center", fontsize=7, color=ACTIVE_COLOUR if critical else "black",
                bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "edgecolor": "none", "alpha": 0.9}, zorder=5)
    for event, time in times.items():
        critical = event in view.critical_path
        ax.plot(time, lanes[event], "o", markersize=17, markerfacecolor="white",
                markeredgecolor=ACTIVE_COLOUR if critical else "black", markeredgewidth=1.5, zorder=6)
        ax.text(time, lanes[event], event, ha="center", va="center", fontsize=7.5, zorder=7)
    ax.set_yticks([])
    ax.set_xlabel("event time p, deg (on the machine's cycle)")
    ax.grid(axis="x", color="0.9")
    handles = []
    if ("critical", "solid") in styles:
        handles.append(Line2D([], [], color=ACTIVE_COLOUR, lw=2.0, label="critical path (active bounds)"))
    if ("critical", "dashed") in styles or ("slack", "dashed") in styles:
        handles.append(Line2D([], [], color=ACTIVE_COLOUR, lw=2.0, ls="--", label="active upper bound"))
    if ("slack", "solid") in styles:
        handles.append(Line2D([], [], color=SLACK_COLOUR, lw=1.0, label="operation with slack"))
    ax.legend(handles=handles, fontsize=7.5, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=len(handles),
              frameon=False)
    ax.set_title(f"{title or 'Network'}: critical path {' → '.join(view.critical_path)}; phase angles on the arrows",
                 fontsize=9)
    return fig


def cyclogram_figures(report) -> list[tuple[str, object]]:
    """(file name, Figure) of a feasible cyclogram report: the Gantt chart and the network."""
    found = report.result
    if not found.result.feasible:
        return []
    title = report.source.get("title", "")
    return [("cyclogram.png", plot_gantt(found.result, title=title)),
            ("network.png", plot_network(found.result, title=title))]


def scene_cyclogram_figures(scene, cyclogram_report: dict) -> list[tuple[str, object]]:
    """The Gantt chart and the network of a scene pipeline's ``cyclogram`` object (report.json), for the
    scene's outputs (camcad.report.scene)."""
    if not cyclogram_report or not cyclogram_report.get("feasible"):
        return []

    network = parse_cyclogram(scene.cyclogram, f"{scene.path} [cyclogram]",
                              [m.name for m in scene.mechanisms if m.prefix])
    title = str(scene.cyclogram.get("name") or scene.name)
    view = cyclogram_view(cyclogram_report, network)
    return [("cyclogram.png", plot_gantt(view, title=title)), ("network.png", plot_network(view, title=title))]


def cyclogram_lines(run) -> list[str]:
    report = run.report
    body = report.body
    lines = [f"{report.source['name']} ({report.source['scene']}): cyclogram"]
    if not body["feasible"]:
        lines.append(body.get("explanation", "the cyclogram is infeasible"))
    else:
        lines.append(f"makespan {fmt(body['makespan_deg'], 6)} deg of {fmt(body['cycle_deg'])} deg; critical path "
                     f"{' -> '.join(body['critical_path'])}")
        rows = []
        times = body["event_times_deg"]
        for label, angle in body["phase_angles_deg"].items():
            least = body["lower_bounds_deg"][label]
            rows.append([label, fmt(times[label.split('->')[0]], 6), fmt(angle, 6), fmt(least["deg"], 6),
                         least["source"], "yes" if label in body["active_bounds"] else ""])
        lines += table(["operation", "from deg", "phase angle deg", "least deg", "bound from", "active"], rows)
        for name, text in body.get("phases", {}).items():
            lines.append(f'{name}: phases = "{text}"')
    for what, why in report.skipped.items():
        lines.append(f"  skipped {what}: {why}")
    lines += verdict_lines(report.verdict)
    return lines + [f"written: {p}" for p in run.outputs]


@dataclass(frozen=True)
class CyclogramCommand:
    """``camcad cyclogram``: the request (camcad.scene.commands.cyclogram.CyclogramRequest) and what to write."""

    request: CyclogramRequest
    output: Path | None = None
    plots: bool = True


def cyclogram_command(command: CyclogramCommand):
    """Run ``camcad cyclogram``: compute (camcad.scene.commands.cyclogram.run_cyclogram), write the Gantt chart, the
    network and cyclogram.json. Returns a CommandRun (exit code 1 when the network is infeasible)."""
    path = require_scene(command.request.scene, "cyclogram")
    scene = read_scene(path)
    with open_folder(command.output, path.stem, scene.input_files()) as out:
        report = run_cyclogram(command.request)
        written = write_figures(out, cyclogram_figures(report) if command.plots else [], "cyclogram.json")
        return finish(report, out, written, "cyclogram.json", cyclogram_lines)
