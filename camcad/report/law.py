"""``camcad law``: a motion designed from scratch, written as a drawing, a table and plots.

The law comes from a scene's [law] (standard shapes or [[law.segments]]) or from the command line
(``--segments``, or ``--rise-law``/``--return-law`` with ``--phases`` and ``--lift``). It is written into the
output folder as

- ``law.dxf``: the acceleration analog as a polyline (layer ACCELERATION; x = cam angle in deg, y in mm/rad²),
  the axes (AXES), a mark and a label at every phase (PHASE_MARKS), the title (TEXT). The polyline is the
  closed form sampled until its chords are within ``tol`` of the peak acceleration, then balanced with the
  least change so that every phase ends where the law does (``camcad.balance.drawn``); the phases are kept in
  the drawing (``camcad.io.law_record``), so ``camcad check`` reads it back with them and ``camcad edit``
  opens it to go on by hand;
- ``law.csv``: θ (deg), s (mm), v (mm/rad), a (mm/rad²), j (mm/rad³) every ``step`` degrees and at every phase
  boundary, from the closed form;
- ``law.png``: s, v, a and j against the cam angle with the phases and the continuity class of every joint;
- ``law.json``: the report.
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass, field
from pathlib import Path
from typing import cast

import numpy as np

from camcad.balance.drawn import DrawnLaw, drawn_polyline
from camcad.errors import CamcadError
from camcad.io.law_write import write_law_csv, write_law_drawing
from camcad.law.law import Kinematics, MotionLaw
from camcad.law.segments import DEG, SegmentLaw, parse_segments, solve_segments
from camcad.law.standard import CompositeLaw
from camcad.law.vdi import catalogue_table
from camcad.report.command import CommandRun, finish, open_folder
from camcad.report.figure import COLOURS, new_figure, save_figure
from camcad.scene.default import default_tables
from camcad.scene.file import read_scene
from camcad.scene.laws import build_law, mechanism_law
from camcad.scene.sections.law import parse_law


@dataclass(frozen=True)
class LawRequest:
    """What ``camcad law`` is asked for.

    Parameters
    ----------
    scene : Path or None
        A scene whose [law] to draw (``mechanism`` picks one of a group).
    mechanism : str or None
        The mechanism of a group scene.
    segments : str or None
        ``--segments``: "start:end:shape[:to_mm][:key=value...]" items (deg, mm; ``camcad.law.segments``).
    rise_law, return_law : str or None
        Standard shapes of the rises and returns (with ``phases`` and ``lift``).
    phases : str or None
        "0:90:rise,..." (deg).
    lift : float or None
        The lift of every rise and return (mm).
    cycle : float or None
        The working angle (deg); 360 when not given.
    output : Path or None
        The output folder (default ./camcad-out/<name>/).
    plots : bool
        Write law.png (no unit).
    tol : float
        Chord tolerance of the drawn acceleration, a fraction of its peak (dimensionless).
    step_deg : float
        Step of the table (deg).
    r12 : bool
        Write DXF R12 instead of R2000 (no unit).
    """

    scene: Path | None = None
    mechanism: str | None = None
    segments: str | None = None
    rise_law: str | None = None
    return_law: str | None = None
    phases: str | None = None
    lift: float | None = None
    cycle: float | None = None
    output: Path | None = None
    plots: bool = True
    tol: float = 1e-5
    step_deg: float = 0.5
    r12: bool = False


@dataclass
class LawReport:
    """A designed law, its drawing and what was written; ``to_dict`` is the JSON, ``exit_code`` 0."""

    name: str
    law: MotionLaw
    source: str
    notes: list[str]
    drawn: DrawnLaw
    peaks: dict
    outputs: list = field(default_factory=list)

    @property
    def exit_code(self) -> int:
        return 0

    def to_dict(self) -> dict:
        law = self.law
        body: dict = {"name": self.name, "source": self.source, "cycle_deg": math.degrees(law.cycle),
                      "description": describe(law), "phases": [p.as_deg() for p in law.phases],
                      "peaks": self.peaks, "drawing": self.drawn.to_dict(), "notes": list(self.notes)}
        if isinstance(law, SegmentLaw):
            body.update(law.to_dict())
        elif isinstance(law, CompositeLaw):
            body["shapes"] = _shape_rows(law)
        return {"law": body}


def describe(law) -> str:
    text = getattr(law, "describe", None)
    return text() if text is not None else type(law).__name__


def _shape_rows(law: CompositeLaw) -> list[dict]:
    rows = []
    for seg in law.segments:
        row = {"kind": seg.kind, "from_deg": math.degrees(seg.start), "to_deg": math.degrees(seg.end)}
        if seg.shape is not None:
            peaks = getattr(seg.shape, "peaks", None)
            row["shape"] = seg.shape.name
            row["lift_mm"] = seg.lift
            if peaks is not None:
                row["coefficients"] = peaks().to_dict()
        rows.append(row)
    return rows


def peaks_of(law: MotionLaw) -> dict:
    """Largest |s|, |v|, |a|, |j| over the cycle (mm, mm/deg, mm/deg², mm/deg³) and where (deg)."""
    theta = np.linspace(0.0, law.cycle, 36001)
    inner = getattr(law, "breakpoints", None)
    if inner is not None:
        theta = np.union1d(theta, np.asarray(inner()))
    kin = law.kinematics(theta)
    out: dict = {}
    for name, values, unit in (("s", kin.s, 0), ("v", kin.v, 1), ("a", kin.a, 2), ("j", kin.j, 3)):
        k = int(np.argmax(np.abs(values)))
        out[f"{name}_max"] = float(np.abs(values[k])) / DEG**unit
        out[f"{name}_max_at_deg"] = float(np.degrees(theta[k]))
    out["units"] = "mm, mm/deg, mm/deg^2, mm/deg^3"
    return out


# --------------------------------------------------------------------------------------------
# Building the law
# --------------------------------------------------------------------------------------------

def design_law(request: LawRequest) -> tuple[str, MotionLaw, str, list[str], list[Path]]:
    """(name, law, source, notes, inputs) of a request: a scene's law, the command line's segments or standard law,
    or the built-in default law."""
    options = [name for name, value in (("--segments", request.segments), ("--rise-law", request.rise_law),
                                        ("--return-law", request.return_law), ("--phases", request.phases),
                                        ("--lift", request.lift)) if value is not None]
    cycle = 360.0 if request.cycle is None else float(request.cycle)
    if request.scene is not None:
        if options or request.cycle is not None:
            raise CamcadError(f"{', '.join(options or ['--cycle'])} describe a law; a scene holds its own",
                              str(request.scene), "change the scene's [law] instead, or drop the scene")
        scene = read_scene(request.scene)
        if not scene.mechanisms:
            raise CamcadError("the scene has no mechanism with a law", str(request.scene), "add a [law] section")
        if request.mechanism is None:
            if len(scene.mechanisms) > 1:
                names = ", ".join(m.name for m in scene.mechanisms)
                raise CamcadError(f"the scene holds {len(scene.mechanisms)} mechanisms ({names})", str(request.scene),
                                  "pick one with --mechanism")
            mech = scene.mechanisms[0]
        else:
            mech = scene.mechanism(request.mechanism)
        if mech.has("law") and "file" in mech.sections["law"]:
            raise CamcadError("the scene's law is a drawing already (file = ...)", mech.where(scene.path, "law"),
                              "camcad law designs a law from segments or standard shapes; open a drawing with "
                              "camcad edit")
        built = mechanism_law(scene, mech)
        name = mech.name if len(scene.mechanisms) > 1 or mech.prefix else scene.name
        return name, cast(MotionLaw, built.law), f"scene {request.scene}", list(built.notes), [Path(request.scene)]
    if request.segments is not None:
        if any(v is not None for v in (request.rise_law, request.return_law, request.phases, request.lift)):
            raise CamcadError("--segments give the whole law; --rise-law, --return-law, --phases and --lift describe "
                              "a standard one", "--segments", "give one or the other")
        law = solve_segments(parse_segments(request.segments), cycle, "--segments")
        return "law", law, "--segments", [f"segment law: {law.describe()}"], []
    table = dict(default_tables()["law"]) if not options else {}
    if options:
        table["standard"] = request.rise_law or "cycloidal"
        for key, value in (("return_standard", request.return_law), ("phases", request.phases),
                           ("lift", request.lift)):
            if value is not None:
                table[key] = value
    table["cycle"] = cycle
    spec = parse_law(table, "command line", Path.cwd())
    built = build_law(spec)
    notes = list(built.notes) + ([] if options else ["no law given: the built-in default law"])
    return "law", cast(MotionLaw, built.law), "standard shapes", notes, []


# --------------------------------------------------------------------------------------------
# The plot
# --------------------------------------------------------------------------------------------

def plot_law(law: MotionLaw, *, title: str = ""):
    """s, v, a and j of a law against the cam angle, its phases shaded and its joints marked with their class.

    Parameters
    ----------
    law : MotionLaw
        The law (θ rad; s mm, v mm/rad, a mm/rad², j mm/rad³): drawn in mm, mm/deg, mm/deg², mm/deg³.
    title : str
        The plot's title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    cycle_deg = math.degrees(law.cycle)
    theta = np.linspace(0.0, law.cycle, 4001)
    inner = getattr(law, "breakpoints", None)
    points = np.asarray(inner()) if inner is not None else np.array([])
    # both sides of every joint, so a jump is drawn vertical
    eps = 1e-9 * law.cycle
    theta = np.union1d(theta, np.clip(np.concatenate((points - eps, points + eps)), 0.0, law.cycle))
    kin: Kinematics = law.kinematics(theta)
    deg = np.degrees(theta)
    fig, axes = new_figure(10.0, 8.0, rows=4, sharex=True)
    rows = ((kin.s, 0, "s, mm"), (kin.v, 1, "v, mm/deg"), (kin.a, 2, "a, mm/deg²"), (kin.j, 3, "j, mm/deg³"))
    for ax, (values, power, label) in zip(axes, rows):
        for phase in law.phases:
            ax.axvspan(math.degrees(phase.start), math.degrees(phase.end), color=COLOURS.get(phase.kind, "white"),
                       zorder=0, linewidth=0)
        ax.plot(deg, values / DEG**power, color=COLOURS["law"], linewidth=1.2)
        ax.axhline(0.0, color="0.6", linewidth=0.6)
        ax.set_ylabel(label)
        ax.grid(color="0.9")
    joints = getattr(law, "joints", ())
    for joint in joints:
        for ax in axes:
            ax.axvline(joint.at_deg % cycle_deg if joint.at_deg < cycle_deg else cycle_deg, color="0.35",
                       linewidth=0.6, linestyle=":")
        at_end = joint.at_deg >= cycle_deg
        axes[0].annotate(joint.class_, (cycle_deg if at_end else joint.at_deg, 1.0), xycoords=("data", "axes fraction"),
                         xytext=(-2 if at_end else 2, -10), textcoords="offset points", fontsize=7,
                         ha="right" if at_end else "left")
    labels = getattr(law, "segments", ())
    if isinstance(law, SegmentLaw):
        for seg in labels:
            axes[3].annotate(seg.shape, ((seg.start_deg + seg.end_deg) / 2.0, 0.02), xycoords=("data", "axes fraction"),
                             ha="center", fontsize=7, rotation=90 if seg.end_deg - seg.start_deg < 40 else 0)
    axes[-1].set_xlabel("cam angle θ, deg (rises shaded green, returns red, dwells grey; joints dotted with their "
                        "continuity class)")
    axes[-1].set_xlim(0.0, cycle_deg)
    axes[0].set_title(textwrap.fill(title or describe(law), 120), fontsize=9)
    return fig


def law_lines(run: CommandRun) -> list[str]:
    """The text of ``camcad law``."""
    report: LawReport = run.report
    law = report.law
    lines = [f"{report.name}: {describe(law)}"]
    body = report.to_dict()["law"]
    for row in body.get("segments", []):
        lines.append(f"  {row['segment']:>2} {row['shape']:<22} {row['from_deg']:>7.6g}-{row['to_deg']:<7.6g} deg  "
                     f"{row['class']:<4} {row['s_start_mm']:.6g} -> {row['s_end_mm']:.6g} mm, "
                     f"v {row['v_start_mm_per_deg']:.4g} -> {row['v_end_mm_per_deg']:.4g} mm/deg")
    for row in body.get("shapes", []):
        coefficients = row.get("coefficients")
        extra = (f"  Cv {coefficients['cv']:.4f}, Ca {coefficients['ca']:.4f}, "
                 + (f"Cj {coefficients['cj']:.4f}" if coefficients["cj"] is not None else "Cj inf (a jumps)")
                 if coefficients else "")
        lines.append(f"  {row['kind']:<7} {row.get('shape', ''):<22} {row['from_deg']:>7.6g}-{row['to_deg']:<7.6g} deg"
                     + extra)
    if body.get("joints"):
        lines.append("  joints: " + ", ".join(f"{j['at_deg']:.6g} {j['class']}" for j in body["joints"]))
    p = report.peaks
    lines.append(f"  peaks: s {p['s_max']:.6g} mm, v {p['v_max']:.4g} mm/deg, a {p['a_max']:.4g} mm/deg^2, "
                 f"j {p['j_max']:.4g} mm/deg^3")
    d = report.drawn.to_dict()
    lines.append(f"  drawing: {d['vertices']} vertices, chord error {d['chord_error_mm_per_rad2']:.3g} mm/rad^2, "
                 f"balancing change {d['balancing_change_mm_per_rad2']:.3g} mm/rad^2 "
                 f"({100 * d['deviation_of_peak']:.3g} % of the peak); every phase ends at its position and velocity "
                 f"within {d['largest_residual']:.2g}")
    for note in report.notes:
        lines.append(f"  note: {note}")
    if run.outputs:
        lines.append(f"wrote {', '.join(Path(p).name for p in run.outputs)} into {Path(run.outputs[0]).parent}/")
    return lines


def catalogue_lines() -> list[str]:
    """The VDI 2143 catalogue as text: name, classes, parameter and the rest-to-rest coefficients."""
    lines = ["VDI 2143 catalogue (C_v, C_a, C_j of the member from rest to rest, or to a reversal):"]
    for row in catalogue_table():
        cj = f"{row['cj']:.4f}" if row["cj"] is not None else "inf (a jumps)"
        parameter = f", parameter {row['parameter']}" if row["parameter"] else ""
        lines.append(f"  {row['name']:<22} {row['member']}: Cv {row['cv']:.4f}, Ca {row['ca']:.4f}, Cj {cj}; "
                     f"{row['classes']}{parameter}")
    lines.append("  plus dwell and constant_velocity; aliases cycloidal = inclined_sine, poly345 = poly5, "
                 "poly4567 = poly7; scca:b:c:d (rest to rest)")
    return lines


# --------------------------------------------------------------------------------------------
# The command
# --------------------------------------------------------------------------------------------

def table_points(law: MotionLaw, step_deg: float) -> np.ndarray:
    """θ (rad): every ``step_deg`` from 0 to the cycle and every phase boundary."""
    if not (math.isfinite(step_deg) and step_deg > 0.0):
        raise CamcadError(f"step {step_deg:g} deg must be positive", "--step", "give e.g. --step 0.5")
    cycle_deg = math.degrees(law.cycle)
    if cycle_deg / step_deg > 1_000_000:
        raise CamcadError(f"step {step_deg:g} deg makes more than 1,000,000 rows", "--step", "give a coarser step")
    grid = np.radians(np.arange(0.0, cycle_deg + 0.5 * step_deg, step_deg))
    grid = grid[grid <= law.cycle]
    bounds = [p.start for p in law.phases] + [law.cycle]
    return np.union1d(grid, bounds)


def run_law(request: LawRequest) -> CommandRun:
    """Design the law, draw it and write law.dxf, law.csv, law.png and law.json (module docstring).

    Parameters
    ----------
    request : LawRequest
        The law's source and how to write it.

    Returns
    -------
    CommandRun
        The report (``payload``: {"law": ..., "outputs": [...]}), the files written and its text.

    Raises
    ------
    CamcadError
        Bad input: an impossible segment specification, a malformed option, a scene without a designed law.
    """
    if not (math.isfinite(request.tol) and 0.0 < request.tol < 1.0):
        raise CamcadError(f"chord tolerance {request.tol:g} is not a fraction of the peak acceleration in (0, 1)",
                          "--tol", "give e.g. 1e-5")
    name, law, source, notes, inputs = design_law(request)
    points = table_points(law, request.step_deg)
    drawn = drawn_polyline(law, tol=request.tol)
    with open_folder(request.output, name, inputs) as out:
        written = []
        rows = [(p.kind, math.degrees(p.start), math.degrees(p.end), p.s_end, math.radians(p.v_end))
                for p in drawn.law.phases]
        labels = _labels(law)
        written.append(write_law_drawing(out.path("law.dxf"), np.degrees(drawn.law.x), drawn.law.a,
                                         cycle_deg=math.degrees(law.cycle), phases=rows, labels=labels,
                                         title=f"{name}: acceleration analog a (mm/rad^2) against cam angle (deg)",
                                         r12=request.r12))
        written.append(write_law_csv(out.path("law.csv"), law.kinematics(points)))
        if request.plots:
            written.append(save_figure(plot_law(law, title=f"{name}: {describe(law)}"), out.path("law.png")))
        report = LawReport(name, law, source, notes, drawn, peaks_of(law))
        run = finish(report, out, written, "law.json", law_lines)
    return run


def _labels(law) -> list[str]:
    if isinstance(law, SegmentLaw):
        return [f"{seg.number} {seg.shape.replace('_', ' ')}" for seg in law.segments]
    if isinstance(law, CompositeLaw):
        return [f"{seg.kind} {seg.shape.name.replace('_', ' ')}" if seg.shape is not None else seg.kind
                for seg in law.segments]
    return [p.kind for p in law.phases]
