"""`camcad contact SCENE` (Hertz stress along the profile, against speed, phase-angle limits) and
`camcad cyclogram SCENE` (the group's network optimised by LP, with the limits as lower bounds)."""

from __future__ import annotations

from typing import Annotated, Any

import typer

from camcad.cli import app
from camcad.cli.common import (JsonOpt, MechanismOpt, NoPlotsOpt, OutOpt, RpmOpt, SceneArg, console, finish, output_dir,
                     print_json)

SamplesOpt = Annotated[int, typer.Option("--samples", help="Cam-angle samples per phase for the stress maximum.")]


@app.command()
def contact(scene_file: SceneArg, mechanism: MechanismOpt = None, rpm: RpmOpt = None, output: OutOpt = None,
            no_plots: NoPlotsOpt = False, samples: SamplesOpt = 2000, as_json: JsonOpt = False) -> None:
    """Hertz contact stress along the profile, safety factor against speed, separation and the least
    phase angle of each rise and return (exit 0 ok, 1 stress over [σ_H] or separation, 2 bad input)."""
    from camcad.errors import CamcadError

    if samples < 16:
        raise CamcadError(f"--samples {samples} is too few", "--samples", "give at least 16 per phase")
    from camcad.scene.mechanism import mechanism_contact
    from camcad.scene.file import read_scene, speeds_or_option

    scene = read_scene(scene_file)
    group = [scene.mechanism(mechanism)] if mechanism is not None else list(scene.mechanisms)
    speeds = speeds_or_option(scene, rpm)
    if speeds is None:
        raise CamcadError("no speed given", f"{scene_file} [machine]", "add [machine] rpm = ... or pass --rpm")
    outdir = output_dir(output, scene_file.stem)
    reports: dict[str, dict] = {}
    skipped: dict[str, str] = {}
    outputs: list[str] = []
    for mech in _progress(group, "contact stress", as_json):
        name = mech.name
        if not mech.has("contact"):
            skipped[name] = "no [contact] section"
            continue
        report, at_worst, sweep = mechanism_contact(scene, mech, speeds, samples)
        reports[name] = report
        if not no_plots:
            from camcad.report.cyclogram import plot_contact_stress, plot_safety_versus_speed

            outputs.append(str(plot_contact_stress(at_worst, outdir / f"contact_{name}.png", title=name)))
            if len(speeds) > 1:
                outputs.append(str(plot_safety_versus_speed(sweep, outdir / f"contact_speed_{name}.png",
                                                            title=f"{name}: contact safety factor")))
    if not reports:
        raise CamcadError("no mechanism has a [contact] section", str(scene_file),
                          "add [contact] (materials, loads, allowable stress) to a mechanism")
    worst_name = max(reports, key=lambda n: reports[n]["sigma_max_MPa"])
    summary = {k: reports[worst_name][k] for k in ("sigma_max_MPa", "at_deg", "safety_factor", "phase_limit_deg",
                                                    "rpm")}
    summary.update(passed=all(r["passed"] for r in reports.values()),
                   separation=any(r["separation"] for r in reports.values()), mechanism=worst_name,
                   mechanisms=reports)
    report_path = outdir / "contact.json"
    outputs.append(str(report_path))
    payload = {"scene": str(scene_file), "contact": summary, "skipped": skipped, "outputs": outputs}
    finish(payload, report_path, as_json, _print_contact, summary["passed"])


def _progress(items, what: str, quiet: bool):
    """Iterate ``items`` with a rich progress bar on stderr (none with --json)."""
    items = list(items)
    if quiet or len(items) < 2:
        yield from items
        return
    from rich.progress import Progress

    with Progress(console=console(stderr=True), transient=True) as progress:
        task = progress.add_task(what, total=len(items))
        for item in items:
            yield item
            progress.advance(task)


def _print_contact(payload: dict) -> None:
    from rich.table import Table

    out = console()
    table = Table(title=f"contact stress — {payload['scene']}")
    for column in ("mechanism", "σ_max MPa", "at deg", "rpm", "safety", "separation", "phase limits deg"):
        table.add_column(column)
    for name, r in payload["contact"]["mechanisms"].items():
        limits = ", ".join(f"{k} {v:.2f}" if v is not None else f"{k} —" for k, v in r["phase_limit_deg"].items())
        table.add_row(name, f"{r['sigma_max_MPa']:.1f}", f"{r['at_deg']:.2f}", f"{r['rpm']:g}",
                      f"{r['safety_factor']:.3f}", "yes" if r["separation"] else "no", limits)
    out.print(table)
    for name, reason in payload["skipped"].items():
        out.print(f"skipped {name}: {reason}")
    out.print("passed" if payload["contact"]["passed"] else "FAILED: stress over [σ_H] or separation")


# --------------------------------------------------------------------------------------------
# camcad cyclogram
# --------------------------------------------------------------------------------------------

@app.command()
def cyclogram(scene_file: SceneArg, rpm: RpmOpt = None, output: OutOpt = None, no_plots: NoPlotsOpt = False,
              samples: SamplesOpt = 2000, as_json: JsonOpt = False) -> None:
    """Optimise the group's cyclogram: least makespan by LP under the operations' bounds and their
    phase-angle limits (vibration, contact stress); exit 1 when the network is infeasible."""
    from camcad.cyclogram.lp import optimise
    from camcad.scene.cyclogram import parse_cyclogram
    from camcad.errors import CamcadError
    from camcad.io.jsonout import write_json

    from camcad.cyclogram.retime import format_phases
    from camcad.scene.mechanism import cyclogram_limits, retimed_phases
    from camcad.scene.file import read_scene, speeds_or_option

    scene = read_scene(scene_file)
    if scene.cyclogram is None:
        raise CamcadError("the scene has no [cyclogram] section", str(scene_file),
                          "add [cyclogram] with [[cyclogram.operations]] (from, to, bounds_deg)")
    mechanisms = [m.name for m in scene.mechanisms if m.prefix]
    network = parse_cyclogram(scene.cyclogram, f"{scene_file} [cyclogram]", mechanisms)
    speeds = speeds_or_option(scene, rpm)
    limits, skipped = cyclogram_limits(scene, network, speeds, samples)
    result = optimise(network, limits, strict=False, where=f"{scene_file} [cyclogram]")
    payload: dict[str, Any] = {"scene": str(scene_file), "cyclogram": result.report(),
                               "phase_limits": {label: [{"deg": l.angle_deg, "source": l.source,
                                                         "value": l.value, "limit": l.limit,
                                                         "binding": l.binding, "note": l.note}
                                                        for l in found]
                                                for label, found in limits.items()},
                               "skipped": skipped}
    outdir = output_dir(output, scene_file.stem)
    outputs: list[str] = []
    if result.feasible:
        payload["cyclogram"]["phases"] = {name: format_phases(phases)
                                          for name, phases in retimed_phases(scene, result).items()}
        if not no_plots:
            from camcad.report.cyclogram import plot_gantt, plot_network

            title = str(scene.cyclogram.get("name") or scene.name)
            outputs.append(str(plot_gantt(result, outdir / "cyclogram.png", title)))
            outputs.append(str(plot_network(result, outdir / "network.png", title)))
    report_path = outdir / "cyclogram.json"
    outputs.append(str(report_path))
    payload["outputs"] = outputs
    write_json(report_path, payload)
    if as_json:
        print_json(payload)
        if not result.feasible:
            import sys

            print(f"camcad: {result.explanation}", file=sys.stderr)
    else:
        _print_cyclogram(payload)
    raise typer.Exit(0 if result.feasible else 1)


def _print_cyclogram(payload: dict) -> None:
    from rich.table import Table

    out = console()
    report = payload["cyclogram"]
    if not report["feasible"]:
        out.print(f"{report['explanation']}")
        return
    table = Table(title=f"cyclogram — {payload['scene']}: makespan {report['makespan_deg']:.3f} deg")
    for column in ("operation", "from deg", "phase angle deg", "least deg", "bound from", "active"):
        table.add_column(column)
    times = report["event_times_deg"]
    for label, angle in report["phase_angles_deg"].items():
        tail = label.split("->")[0]
        least = report["lower_bounds_deg"][label]
        table.add_row(label, f"{times[tail]:.3f}", f"{angle:.3f}", f"{least['deg']:.3f}", least["source"],
                      "yes" if label in report["active_bounds"] else "")
    out.print(table)
    out.print(f"critical path: {' -> '.join(report['critical_path'])}")
    for name, text in report.get("phases", {}).items():
        out.print(f"{name}: phases = \"{text}\"")
    for what, why in payload["skipped"].items():
        out.print(f"skipped {what}: {why}")
