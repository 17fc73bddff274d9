"""``camcad synth``'s outputs: the law (synth.dxf, synth.csv — with camcad's record), the series (harmonics.csv),
the database (patterns.csv), the plots and the text.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from camcad.io.atomic import write_text_atomic
from camcad.io.law_write import write_law_csv, write_law_dxf
from camcad.report.command import finish, open_folder
from camcad.report.figure import COLOURS, new_figure, save_figure
from camcad.report.text import fmt, table, verdict_lines
from camcad.scene.commands.synth import SynthRequest, database_rows, run_synth


def plot_synth(report):
    """The written law's a and s against the closed-form law, and their difference."""
    found = report.synthesis
    law, exact = report.written, found.exact
    unit = report.unit
    theta = np.linspace(0.0, law.cycle, 4097)
    mine, theirs = law.kinematics(theta), exact.kinematics(theta)
    deg = np.degrees(theta)
    fig, axes = new_figure(10, 8, rows=3, sharex=True)
    axes[0].plot(deg, theirs.a, color=COLOURS["original"], lw=2.0, label="closed form")
    axes[0].plot(deg, mine.a, color=COLOURS["law"], lw=1.0, label=f"{found.harmonics} harmonics (synth.dxf)")
    axes[1].plot(deg, theirs.s - theirs.s[0], color=COLOURS["original"], lw=2.0)
    axes[1].plot(deg, mine.s, color=COLOURS["law"], lw=1.0)
    axes[2].plot(deg, mine.s - (theirs.s - theirs.s[0]), color="black", lw=1.0)
    for ax, label in zip(axes, (f"a ({unit}/rad²)", f"s ({unit})", f"written - closed form ({unit})")):
        ax.set_ylabel(label)
        ax.grid(color="0.9")
        for phase in law.phases:
            if phase.kind != "dwell":
                ax.axvspan(np.degrees(phase.start), np.degrees(phase.end), color=COLOURS[phase.kind], alpha=0.35,
                           lw=0, zorder=0)
    axes[0].legend(fontsize=8)
    axes[2].set_xlabel("cam angle θ (deg)")
    fig.suptitle(f"synthesised from the database: {found.shapes[0]} / {found.shapes[1]}, {found.harmonics} "
                 f"harmonics, RMS error {found.rms_measured:.3g} {unit}", fontsize=10)
    return fig


def plot_rms(report):
    """RMS error of the series against the number of harmonics (Parseval), with the tolerance."""
    found = report.synthesis
    rms = found.spectrum.rms_errors()
    fig, ax = new_figure(8, 4.5)
    n = np.arange(len(rms))
    ax.semilogy(n[1:], rms[1:], color=COLOURS["law"], lw=1.2, label="RMS error after N harmonics")
    if found.tol is not None:
        ax.axhline(found.tol, color=COLOURS["limit"], ls="--", label=f"wanted {found.tol:.3g} {report.unit}")
    ax.axvline(found.harmonics, color="0.5", ls=":", label=f"N = {found.harmonics}")
    ax.set_xlabel("harmonics N")
    ax.set_ylabel(f"RMS error ({report.unit})")
    ax.grid(color="0.9")
    ax.legend(fontsize=8)
    ax.set_title("RMS error of the series against the number of harmonics", fontsize=10)
    return fig


def _csv(rows: list[dict]) -> str:
    if not rows:
        return ""
    names = list(rows[0])
    return "\n".join([",".join(names)] + [",".join(f"{r[k]:.12g}" if isinstance(r[k], float) else str(r[k])
                                                   for k in names) for r in rows]) + "\n"


def write_synth(report, out, *, plots: bool = True, r12: bool = False) -> list[Path]:
    """synth.dxf and synth.csv (the written law with its record), harmonics.csv, patterns.csv and the plots."""
    law = report.written
    unit = report.unit
    outputs = [write_law_dxf(out.path("synth.dxf"), np.degrees(law.x), law.a, r12=r12, record=report.record,
                             title=f"camcad synth: {report.synthesis.shapes[0]}/{report.synthesis.shapes[1]}, "
                                   f"{report.synthesis.harmonics} harmonics, a ({unit}/rad^2) vs deg")]
    rows = replace(law.kinematics(law.x), a=np.asarray(law.a))
    outputs.append(write_law_csv(out.path("synth.csv"), rows, record=report.record, unit=unit))
    outputs.append(write_text_atomic(out.path("harmonics.csv"), _csv(report.body["series"])))
    outputs.append(write_text_atomic(out.path("patterns.csv"), _csv(database_rows(report.database))))
    if plots:
        outputs.append(save_figure(plot_synth(report), out.path("synth.png")))
        outputs.append(save_figure(plot_rms(report), out.path("synth_rms.png")))
    return outputs


def synth_lines(run) -> list[str]:
    report = run.report
    body = report.body
    unit = report.unit
    lines = [f"synthesised law: {body['phases']} (deg), lift {fmt(body['lift'])} {unit}; rises "
             f"{body['shapes']['rise']}, returns {body['shapes']['return']}",
             f"{body['harmonics']} harmonics: RMS error {fmt(body[f'rms_error_measured_{unit}'])} {unit} "
             f"(Parseval {fmt(body[f'rms_error_predicted_{unit}'])}), largest {fmt(body[f'max_error_{unit}'])} {unit}",
             "", "RMS error against the number of harmonics"]
    lines += table(["N", f"RMS ({unit})"], [[n, fmt(v)] for n, v in body["rms_error"].items()])
    lines += ["", "the series s = mean + sum A_k sin(k theta + phase_k)"]
    lines += table(["k", f"A_k ({unit})", "phase_k (deg)"],
                   [[r["k"], fmt(r[f"amplitude_{unit}"]), fmt(r["phase_deg"])] for r in body["series"][:32]])
    patterns = ", ".join(f"{k} ({v})" for k, v in body["patterns"].items())
    lines.append(f"database patterns: {patterns}")
    for note in report.notes:
        lines.append(f"  note: {note}")
    lines += verdict_lines(report.verdict, details=False)
    return lines + [f"written: {p}" for p in run.outputs]


@dataclass(frozen=True)
class SynthCommand:
    request: SynthRequest
    output: Path | None = None
    plots: bool = True
    r12: bool = False


def synth_command(command: SynthCommand):
    """Run ``camcad synth``: compute (``run_synth``), write the law, the series, the database and the plots and
    synth.json into the output folder. Returns a CommandRun."""
    request = command.request
    inputs = [Path(request.shape_from)] if request.shape_from is not None else []
    with open_folder(command.output, "synth", inputs) as out:
        report = run_synth(request)
        written = write_synth(report, out, plots=command.plots, r12=command.r12)
        return finish(report, out, written, "synth.json", synth_lines)
