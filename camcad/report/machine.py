"""``camcad machine``: the machine's cyclogram chart, every group's outputs, machine.json and the text.

- ``plot_machine``: one chart of the whole machine on the main shaft's angle: a band per group with a row
  per operation of its mechanisms, then the machine's own operations; each bar solid up to its least
  admissible angle and light beyond (its margin), critical operations red, the limiting operation purple
  with its length under the other objective drawn as an outline beside it; the shared events as dashed lines
  named on top.
- ``machine_command``: runs ``camcad.scene.machine.analyse_machine``, writes each group's pipeline outputs
  into a subfolder named after the group (profile.dxf, law.csv, report.json and plots per mechanism, the
  group's cyclogram chart), then ``machine_cyclogram.png`` and ``machine.json`` at the top.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from camcad.errors import CamcadError
from camcad.io.jsonout import write_json
from camcad.io.output_folder import OutputFolder, safe_name
from camcad.report.figure import new_figure, save_figure
from camcad.report.scene import write_scene
from camcad.report.text import fmt, table, verdict_lines
from camcad.scene.machine import MachineAnalysis, analyse_machine, read_machine
from camcad.scene.pipeline import PipelineOptions

CRITICAL_COLOUR = "#c0392b"
SLACK_COLOUR = "#2e86c1"
LIMITING_COLOUR = "#7d3c98"
MACHINE_COLOUR = "#7f8c8d"
MARGIN_ALPHA = 0.35
BAND_COLOURS = ("#f4f6f7", "#fdf2e9")


def _pieces(start: float, width: float, cycle: float) -> list[tuple[float, float]]:
    """(left, width) of a bar on [0, cycle): a bar past the cycle's end wraps to 0."""
    left = start % cycle
    if left + width <= cycle + 1e-9:
        return [(left, width)]
    return [(left, cycle - left), (0.0, left + width - cycle)]


def plot_machine(analysis: MachineAnalysis, *, title: str = ""):
    """The machine's cyclogram chart (module docstring).

    Parameters
    ----------
    analysis : MachineAnalysis
        A feasible machine (``camcad.scene.machine.analyse_machine``).
    title : str
        The chart's title (default: the machine's name).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    result = analysis.result
    found = result.result
    machine = analysis.machine
    cycle = float(machine.network.cycle_deg)
    times = found.event_times_deg
    rows: list[tuple[str, Any, str]] = []      # (band, op, label)
    for group in machine.groups:
        labels = machine.labels_of(group.name)
        ops = [machine.network.operation(labels[op.label]) for op in group.network.operations if op.mechanism]
        ops.sort(key=lambda op: (times[op.tail], op.label))
        for op in ops:
            own = next(o for o in group.network.operations if labels[o.label] == op.label)
            mech = (op.mechanism or "").split(":", 1)[-1]
            rows.append((group.name, op, f"{own.name or own.label} [{own.label}] — {mech} {op.phase or ''}".strip()))
    machine_ops = [machine.network.operation(label) for label, (owner, _) in machine.origin.items()
                   if not owner and (machine.network.operation(label).min_deg > 0 or label == machine.limiting)]
    for op in machine_ops:
        rows.append(("machine", op, f"{op.name or op.label} [{op.label}]"))
    fig, ax = new_figure(13, 2.3 + 0.36 * len(rows))
    critical = set(found.critical_operations) | {c.label for c in found.active if c.kind == "min"}
    bands: dict[str, list[int]] = {}
    for row, (band, op, _) in enumerate(rows):
        bands.setdefault(band, []).append(row)
        start = times[op.tail]
        width = found.phase_angles_deg[op.label]
        least = found.lower_bounds_deg[op.label][0]
        if op.label == machine.limiting:
            least = op.min_deg
            colour = LIMITING_COLOUR
        else:
            plain = SLACK_COLOUR if band != "machine" else MACHINE_COLOUR
            colour = CRITICAL_COLOUR if op.label in critical else plain
        solid = min(least, width)
        for left, span in _pieces(start, solid, cycle):
            ax.broken_barh([(left, span)], (row - 0.32, 0.64), facecolors=colour, edgecolors="black", linewidth=0.5)
        if width - solid > 1e-9:
            for left, span in _pieces(start + solid, width - solid, cycle):
                ax.broken_barh([(left, span)], (row - 0.32, 0.64), facecolors=colour, alpha=MARGIN_ALPHA,
                               edgecolors="black", linewidth=0.5)
        text = f"{width:.1f}°"
        if op.label == machine.limiting and analysis.other is not None and analysis.other.feasible:
            other = analysis.other
            o_start, o_width = other.result.event_times_deg[op.tail], float(other.limiting_deg or 0.0)
            for left, span in _pieces(o_start, o_width, cycle):
                ax.broken_barh([(left, span)], (row + 0.36, 0.14), facecolors="none", edgecolors=LIMITING_COLOUR,
                               linewidth=0.8, linestyle="--")
            text += f" (limiting op.; {o_width:.1f}° with the {other.objective.replace('_', ' ')} objective)"
        elif least > 0:
            text += f"  (least {least:.1f}°)"
        end = (start + width) % cycle or cycle
        right = end + 1.5 < cycle - 60
        ax.text(end + 1.5 if right else start % cycle - 1.5, row, text, ha="left" if right else "right",
                va="center", fontsize=7, color="0.15")
    for k, (band, members) in enumerate(bands.items()):
        ax.axhspan(min(members) - 0.5, max(members) + 0.5, color=BAND_COLOURS[k % 2], zorder=-2)
        ax.text(cycle + 2, (min(members) + max(members)) / 2, band, rotation=90, ha="left", va="center",
                fontsize=8, color="0.3", clip_on=False)
    # the machine's own and shared events, named on top
    shown: dict[float, list[str]] = {}
    for written, event in machine.event_of.items():
        if ":" not in event or written != event:
            name = event if ":" not in event else written
            if event in times:
                shown.setdefault(round(times[event] % cycle, 6), [])
                if name not in shown[round(times[event] % cycle, 6)]:
                    shown[round(times[event] % cycle, 6)].append(name)
    for x, names in sorted(shown.items()):
        ax.axvline(x, color="0.45", linestyle="--", linewidth=0.7, zorder=0)
        ax.text(x, -0.62, " = ".join(sorted(set(names), key=len)), ha="center", va="bottom", fontsize=7,
                color="0.2", rotation=0)
    ax.set_yticks(range(len(rows)), [label for _, _, label in rows], fontsize=7.5)
    ax.set_ylim(len(rows) - 0.4, -0.95)
    ax.set_xlim(0, cycle)
    ax.set_xticks(np.arange(0, cycle + 1, 30))
    ax.set_xlabel("main shaft angle, deg (machine and shared events on top)")
    ax.grid(axis="x", color="0.9")
    ax.set_axisbelow(True)
    handles: list[Any] = [Patch(color=CRITICAL_COLOUR, label="critical: at its least angle"),
               Patch(color=SLACK_COLOUR, label="off the critical path: keeps a margin"),
               Patch(facecolor="0.5", alpha=MARGIN_ALPHA, label="margin beyond the least admissible angle"),
               Patch(color=LIMITING_COLOUR, label="limiting operation")]
    if analysis.other is not None:
        handles.append(Line2D([], [], color=LIMITING_COLOUR, ls="--", lw=0.8,
                              label="limiting operation under the other objective"))
    fig.legend(handles=handles, fontsize=7, loc="outside lower center", ncol=len(handles), frameon=False)
    head = title or analysis.scene.settings.get("name") or analysis.scene.name
    text = (f"{head}: objective {result.objective.replace('_', ' ')}; makespan {found.makespan_deg:.2f}° of "
            f"{cycle:g}° (least cycle {result.least_cycle_deg:.2f}°)")
    if result.limiting_deg is not None:
        text += f"; limiting operation {result.limiting_deg:.2f}°"
    ax.set_title(text, fontsize=9)
    return fig


def plot_shaft(found, *, title: str = ""):
    """The elastic main shaft over its last simulated turn: the twist at each cam (deg, the cam lagging the
    drive > 0), and each follower's law distortion by the twist s(φ_k) − s(ωt) beside its whole dynamic error
    q/scale − s(ωt) (the law's unit), against the drive's angle.

    Parameters
    ----------
    found : camcad.dynamics.shaft.ShaftResult

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, (top, bottom) = new_figure(11, 7.5, rows=2, sharex=True)
    angle = np.degrees(found.drive) % 360.0
    order = np.argsort(angle, kind="stable")
    colours = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown")
    for k, cam in enumerate(found.shaft.cams):
        colour = colours[k % len(colours)]
        unit = "mm" if cam.position_scale == 1e-3 else "rad"
        twist = found.twist_deg(k)
        top.plot(angle[order], twist[order], color=colour, lw=1.0,
                 label=f"{cam.name}: max |twist| {np.max(np.abs(twist)):.3g} deg")
        distortion = found.twist_distortion(k)
        error = found.dynamic_error(k)
        bottom.plot(angle[order], distortion[order], color=colour, lw=1.2,
                    label=f"{cam.name}: law at the twisted cam angle, max {np.max(np.abs(distortion)):.3g} {unit}")
        bottom.plot(angle[order], error[order], color=colour, lw=0.8, ls="--",
                    label=f"{cam.name}: whole dynamic error (twist and chain), max {np.max(np.abs(error)):.3g} {unit}")
    top.set_ylabel("shaft twist at the cam, deg")
    units = sorted({"mm" if cam.position_scale == 1e-3 else "rad" for cam in found.shaft.cams})
    bottom.set_ylabel(f"deviation from the ideal law, {' or '.join(units)}")
    bottom.set_xlabel("drive (main shaft) angle, deg")
    bottom.set_xlim(0, 360)
    for ax in (top, bottom):
        ax.axhline(0.0, color="0.5", lw=0.6)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7.5, loc="upper left")
    frequencies = ", ".join(f"{f:.4g}" for f in found.shaft.torsional_frequencies_hz())
    top.set_title(title or (f"Cams on the elastic main shaft at {found.rpm:g} rpm (shaft modes {frequencies} Hz; "
                            "the last simulated turn)"), fontsize=10)
    return fig


# --------------------------------------------------------------------------------------------
# camcad machine
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class MachineRequest:
    """What ``camcad machine`` can be asked: the machine scene, the objective (None: the scene's), the output
    folder, plots or not, contact samples per phase."""

    scene: Path
    objective: str | None = None
    output: Path | None = None
    plots: bool = True
    samples: int = 2000


@dataclass
class MachineReport:
    """One run of ``camcad machine``: the analysis, the files written, the JSON (``to_dict``) and the exit code
    (0 every check passed, 1 one failed)."""

    analysis: MachineAnalysis
    outputs: list[Path] = field(default_factory=list)

    @property
    def exit_code(self) -> int:
        return 0 if self.analysis.passed else 1

    def to_dict(self) -> dict:
        return {**self.analysis.report, "outputs": [str(p) for p in self.outputs]}

    def lines(self) -> list[str]:
        return machine_lines(self)


def run_machine(request: MachineRequest) -> MachineReport:
    """``camcad machine``: analyse the machine (``camcad.scene.machine.analyse_machine``) and write its outputs
    (module docstring) into ``request.output`` (default ``./camcad-out/<machine name>/``).

    Parameters
    ----------
    request : MachineRequest

    Returns
    -------
    MachineReport
    """
    if isinstance(request.samples, bool) or not isinstance(request.samples, int) or not 16 <= request.samples <= 10**6:
        raise CamcadError(f"--samples {request.samples} is not in 16..1000000", "--samples",
                          "give the cam-angle samples per phase, e.g. 2000")
    scene = read_machine(request.scene)
    folder = request.output if request.output is not None else Path("camcad-out") / safe_name(scene.name)
    inputs = scene.input_files()
    with OutputFolder(folder, inputs):       # refused before any work when an output would replace an input
        pass
    plots: tuple[str, ...] = ("summary",) if request.plots else ()
    options = PipelineOptions(plots=plots, contact_samples=request.samples)
    analysis = analyse_machine(scene, options, objective=request.objective)
    outputs: list[Path] = []
    for name, run in analysis.groups.items():
        written = write_scene(run, replace(options, output=Path(folder) / safe_name(name)))
        outputs.extend(Path(p) for p in written.report.get("outputs", []))
    with OutputFolder(folder, inputs) as out:
        if request.plots and analysis.result.feasible:
            outputs.append(save_figure(plot_machine(analysis), out.path("machine_cyclogram.png")))
        if request.plots and analysis.shaft is not None:
            outputs.append(save_figure(plot_shaft(analysis.shaft), out.path("shaft.png")))
        json_path = out.path("machine.json")
        outputs.append(json_path)
        report = MachineReport(analysis, outputs)
        write_json(json_path, report.to_dict())
    return report


def machine_lines(report: MachineReport) -> list[str]:
    """The text of ``camcad machine``: the objective, the limiting operation under both objectives, each
    group's placement and phases, the machine's checks and each group's verdict."""
    analysis = report.analysis
    body = analysis.report["machine"]
    lines = [f"{analysis.scene.name} ({analysis.scene.path}): machine of {len(analysis.scene.groups)} groups"]
    lines += [f"  note: {note}" for note in analysis.report.get("notes", [])]
    if not body["feasible"]:
        lines.append(body.get("explanation", "the machine's cyclogram is infeasible"))
    else:
        lines.append(f"objective {body['objective']}: makespan {fmt(body['makespan_deg'], 6)} deg of "
                     f"{fmt(body['cycle_deg'])} deg (least cycle {fmt(body['least_cycle_deg'], 6)} deg)")
        limiting = body.get("limiting")
        if limiting:
            lines.append(f"limiting operation {limiting['operation']} ({limiting['name']}): "
                         f"{fmt(limiting['deg'], 6)} deg; with the least cycle {fmt(limiting['at_least_cycle_deg'], 6)}"
                         f" deg; longest the cycle allows {fmt(limiting['longest_deg'], 6)} deg")
        lines.append(f"critical path {' -> '.join(body['critical_path'])}")
        rows = [[name, group["start_event"], fmt(group["start_deg"], 6), fmt(group["makespan_deg"], 6),
                 ", ".join(group["critical_operations"]) or "-"] for name, group in body["groups"].items()]
        lines += table(["group", "first event", "at deg", "makespan deg", "critical operations"], rows)
        for name, group in analysis.report["groups"].items():
            phases = (group.get("cyclogram") or {}).get("phases", {})
            for mech, text in phases.items():
                lines.append(f'{name}: {mech}: phases = "{text}"')
            lines.append(f"{name}: " + ("all checks passed" if group["passed"] else "a check FAILED"))
    shaft = analysis.report.get("shaft")
    if shaft:
        lines.append(f"elastic main shaft at {fmt(shaft['rpm'])} rpm (modes "
                     f"{', '.join(fmt(f) for f in shaft['torsional_frequencies_hz'])} Hz), the last simulated turn:")
        rows = []
        for cam in shaft["cams"]:
            unit = "mm" if "law_distortion_max_mm" in cam else "rad"
            rows.append([cam["mechanism"], fmt(cam["twist_max_deg"]), fmt(cam[f"law_distortion_max_{unit}"]),
                         fmt(cam[f"dynamic_error_max_{unit}"]), fmt(cam["peak_accel_ratio"]), unit])
        lines += table(["cam", "twist max deg", "law distortion max", "dynamic error max", "accel ratio", "unit"],
                       rows)
    for what, why in (analysis.report.get("skipped") or {}).items():
        lines.append(f"  skipped {what}: {why}")
    lines += verdict_lines(analysis.verdict)
    return lines + [f"written: {p}" for p in report.outputs]
