"""`camcad linkage`: the atlas of adjustable chains, function generators, guiding mechanisms, and the linkage after
the follower (Sunkuev 1984). Each command builds a request, runs it (``camcad.report.linkage_commands``) and prints;
the work is in ``camcad.linkage.runners`` and ``camcad.scene.linkage_commands``."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.analysis_options import emit
from camcad.cli.common import JsonOpt, NoPlotsOpt, OutOpt

linkage_app = typer.Typer(no_args_is_help=True, help="Linkages (Sunkuev 1984): atlas of adjustable chains, function "
                                                    "generators, guiding mechanisms, adjustable mechanisms.")
app.add_typer(linkage_app, name="linkage")


def _opt(name: str, text: str):
    return typer.Option(name, help=text)


MuOpt = Annotated[float, _opt("--mu-min", "Transmission-angle limit (deg).")]
RatioOpt = Annotated[float, _opt("--ratio-max", "Largest link-length ratio.")]
SeedOpt = Annotated[int, _opt("--seed", "The random-number seed of the random starts.")]
SceneOptArg = Annotated[Path | None, typer.Argument(help="A scene (.toml) with a [linkage]; or give the linkage by "
                                                         "options.", show_default=False)]
MechOpt = Annotated[str | None, _opt("--mechanism", "The mechanism of a group scene.")]
PivotOpt = Annotated[str, _opt("--pivot", "Input pivot O = the follower's pivot, X,Y (mm).")]
OutPivotOpt = Annotated[str | None, _opt("--output-pivot", "Output pivot C, X,Y (mm).")]
LinksOpt = Annotated[str | None, _opt("--links", "Input link OA, coupler AB, output link CB: A,B,C (mm).")]
InputAngleOpt = Annotated[float | None, _opt("--input-angle", "Input link's angle at psi = 0 (deg).")]
SwingOpt = Annotated[float | None, _opt("--swing", "The follower's swing psi_max (deg).")]
SenseOpt = Annotated[int, _opt("--sense", "+1: the input link turns CCW as psi grows; -1: CW (as camcad's "
                                          "oscillating follower).")]
BranchOpt = Annotated[int, _opt("--branch", "Assembly branch +1 or -1.")]
OutPivot2Opt = Annotated[str | None, _opt("--output-pivot-2", "Six-bar: second output pivot F, X,Y.")]
Links2Opt = Annotated[str | None, _opt("--links-2", "Six-bar: CD, DE, FE (mm).")]
Coupling2Opt = Annotated[float, _opt("--coupling-2", "Six-bar: angle from CB to CD (deg).")]
Branch2Opt = Annotated[int, _opt("--branch-2", "Six-bar: branch of the second loop.")]
CouplerOpt = Annotated[str | None, _opt("--coupler-point", "Coupler point U,V (mm along AB, left of AB).")]
ElementOpt = Annotated[str | None, _opt("--element", "The adjustable element: pivot, joint or link_angle "
                                                     "(default: the scene's [linkage.adjust]).")]
JointOpt = Annotated[str, _opt("--joint", "The element's joint (C, F, A, B, E).")]
PathOpt = Annotated[str, _opt("--path", "The element's path: arc or slot.")]
CentreOpt = Annotated[str | None, _opt("--centre", "Arc centre X,Y (mm).")]
DirectionOpt = Annotated[float, _opt("--direction", "Slot direction (deg).")]
AnimateOpt = Annotated[bool, typer.Option(
    "--animate", help="Also write animation.html: with a scene's cam, the cam, the follower and the linkage over a "
                      "turn; otherwise the linkage alone over its input range and back (one self-contained page).")]
AnimateFormatOpt = Annotated[str | None, typer.Option(
    "--animate-format", help="Animation files: a comma list of html (default), gif, mp4 (mp4 needs ffmpeg); "
                             "implies --animate.")]
AnimateStepOpt = Annotated[float | None, typer.Option(
    "--animate-step", help="Between frames: cam angle with a cam, input angle without (deg, default 1; it must "
                           "divide 360); implies --animate.")]
SOURCE = ("scene", "mechanism", "pivot", "output_pivot", "links", "input_angle", "swing", "sense", "branch",
          "output_pivot_2", "links_2", "coupling_2", "branch_2", "coupler_point", "mu_min")
ELEMENT = {"element": "element", "joint": "joint", "path": "path", "centre": "centre", "direction": "direction"}


def _source(values: dict):
    from camcad.scene.linkage_commands import LinkageSource

    return LinkageSource(**{k: values[k] for k in SOURCE if k in values})


def _element(values: dict):
    from camcad.scene.linkage_commands import ElementSpec

    return ElementSpec(**{field: values[key] for key, field in ELEMENT.items()})


def _go(request, output: Path | None, plots: bool, as_json: bool) -> None:
    from camcad.report.linkage_commands import linkage_command

    emit(linkage_command(request, output, plots), as_json)


@linkage_app.command()
def atlas(links: Annotated[int, _opt("--links", "Number of links n (frame counted); with --adjustable, n'.")],
          dof: Annotated[int, _opt("--dof", "Mobility W; with --adjustable, W' of the adjustable chain.")] = 1,
          adjustable: Annotated[int | None, _opt("--adjustable", "m locked pairs: adjustable chains "
                                                                 "(Sunkuev 1984, Table 1).")] = None,
          output: OutOpt = None, no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Enumerate planar chains with revolute pairs (or adjustable chains) up to isomorphism; draw the atlas and
    each chain's kinematic scheme."""
    from camcad.linkage.runners import AtlasRequest

    _go(AtlasRequest(links, dof, adjustable), output, not no_plots, as_json)


@linkage_app.command()
def fgen(function: Annotated[str | None, _opt("--function", 'y = f(x), e.g. "log10(x)".')] = None,
         table: Annotated[Path | None, _opt("--table", "Two-column table x, y (.csv/.txt).")] = None,
         x: Annotated[str | None, _opt("--x", "Interval X0:X1 of x (default with --table: its range).")] = None,
         input_range: Annotated[float | None, _opt("--input-range", "Turn of the input link (deg, signed).")] = None,
         output_range: Annotated[float | None, _opt("--output-range", "Turn of the output link (deg).")] = None,
         method: Annotated[str, _opt("--method", "q (Sunkuev 1984's), precision, lsq, minimax (under the limits), "
                                                 "remez (no limits: reference), or all.")] = "q",
         nodes: Annotated[int | None, _opt("--nodes", "q: S nodes (odd, default 5); lsq: N points.")] = None,
         spacing: Annotated[str, _opt("--spacing", "Nodes: chebyshev or uniform.")] = "chebyshev",
         mu_min: MuOpt = 30.0, ratio_max: RatioOpt = 10.0,
         frame: Annotated[float, _opt("--frame", "Frame length OC of the result (mm).")] = 100.0,
         phi0: Annotated[float | None, _opt("--phi0", "precision: input offset (deg); default scanned.")] = None,
         psi0: Annotated[float | None, _opt("--psi0", "precision: output offset (deg).")] = None,
         pick: Annotated[str, _opt("--pick", "q, the last step: centre of the Q rectangle, or search it.")] = "centre",
         seed: SeedOpt = 0,
         max_error: Annotated[float | None, _opt("--max-error", "Accuracy asked for (deg); default 1 % of the "
                                                                "output range.")] = None,
         chain: Annotated[str, _opt("--chain", "fourbar, or sixbar: two four-bars in series by the six-bar Q "
                                               "method (S >= 9 nodes).")] = "fourbar",
         output: OutOpt = None, no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Synthesise a four-bar (or, with --chain sixbar, a six-bar) function generator y = f(x); exit 1 when a check
    (accuracy, transmission angle, link ratio, branch) fails (--method all compares and exits 0)."""
    from camcad.linkage.runners import FgenRequest

    _go(FgenRequest(function, table, x, input_range, output_range, method, nodes, spacing, mu_min, ratio_max, frame,
                    phi0, psi0, pick, seed, max_error, chain), output, not no_plots, as_json)


@linkage_app.command()
def path(points: Annotated[list[Path] | None, _opt("--points", "A curve: table x_mm,y_mm (the points in order); "
                                                             "repeat for a family.")] = None,
         timed: Annotated[list[Path] | None, _opt("--timed", "A timed curve: table phi_deg,x_mm,y_mm.")] = None,
         distance: Annotated[list[Path] | None, _opt("--distance", "A distance to --fixed-point: table "
                                                                   "phi_deg,L_mm.")] = None,
         fixed_point: Annotated[str | None, _opt("--fixed-point", "The fixed point X,Y (mm) of --distance.")] = None,
         method: Annotated[str, _opt("--method", "q (Sunkuev 1984's), deviation, or all (both; the best is "
                                                 "reported).")] = "all",
         nodes: Annotated[int, _opt("--nodes", "q: interpolate on 2 or 3 nodes per subset.")] = 3,
         mu_min: MuOpt = 30.0, ratio_max: RatioOpt = 10.0,
         max_deviation: Annotated[float | None, _opt("--max-deviation", "Accuracy asked for (mm); default 0.1 % of "
                                                                        "the target's size.")] = None,
         seed: SeedOpt = 0, starts: Annotated[int, _opt("--starts", "A family's random starts (stage 1).")] = 20,
         output: OutOpt = None, no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Synthesise a guiding four-bar: its coupler point through a curve, a timed curve, or at given distances from
    a fixed point (Sunkuev 1984, ch. 2 and 5); three or more tables: one adjustable four-bar for the family; exit 1
    when a check (deviation, transmission angle, link ratio) fails."""
    from camcad.linkage.runners import PathRequest

    _go(PathRequest(points, timed, distance, fixed_point, None, None, method, nodes, mu_min, ratio_max, max_deviation,
                    seed, starts), output, not no_plots, as_json)


@linkage_app.command()
def variator(u_mean: Annotated[str | None, _opt("--u-mean", "Mean velocity analog U_cp regulated, A:B (rad per rad of "
                                                            "crank).")] = None,
             interval: Annotated[float, _opt("--interval", "The crank's working interval (deg).")] = 90.0,
             settings: Annotated[int, _opt("--settings", "Settings p (U_cp spread over A:B).")] = 3,
             crank: Annotated[float, _opt("--crank", "Crank length OA (mm).")] = 20.0,
             mu_min: MuOpt = 30.0, ratio_max: RatioOpt = 10.0,
             starts: Annotated[int, _opt("--starts", "Random starts of stage 2.")] = 24, seed: SeedOpt = 0,
             max_delta: Annotated[float | None, _opt("--max-delta", "Allowed non-uniformity [delta].")] = None,
             output: OutOpt = None, no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """The transforming six-bar of an impulse variator (Sunkuev 1984, Fig. 7): U constant over the working interval
    while its mean is regulated; the non-uniformity delta reported; exit 1 when a check fails."""
    from camcad.linkage.runners import VariatorRequest

    _go(VariatorRequest(u_mean, interval, settings, crank, mu_min, ratio_max, starts, seed, max_delta), output,
        not no_plots, as_json)


@linkage_app.command()
def analyse(scene: SceneOptArg = None, mechanism: MechOpt = None, pivot: PivotOpt = "0,0",
            output_pivot: OutPivotOpt = None, links: LinksOpt = None, input_angle: InputAngleOpt = None,
            swing: SwingOpt = None, sense: SenseOpt = 1, branch: BranchOpt = 1, output_pivot_2: OutPivot2Opt = None,
            links_2: Links2Opt = None, coupling_2: Coupling2Opt = 0.0, branch_2: Branch2Opt = 1,
            coupler_point: CouplerOpt = None, mu_min: MuOpt = 30.0,
            points: Annotated[int, _opt("--points", "Samples over the swing.")] = 721,
            cam: Annotated[bool, typer.Option("--cam/--no-cam", help="Scene: draw (and animate) the cam with the "
                                                                     "linkage.")] = True,
            animate: AnimateOpt = False, animate_format: AnimateFormatOpt = None, animate_step: AnimateStepOpt = None,
            output: OutOpt = None, no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Analyse the linkage after the follower: exact Pi, Pi', Pi'', Pi''', transmission angles, dead points,
    branch, coupler path; exit 1 when a check fails."""
    from camcad.cli.report_options import animate_options
    from camcad.scene.linkage_commands import AnalyseRequest

    source = _source(locals())
    formats, step = animate_options(animate, animate_format, animate_step)
    _go(AnalyseRequest(source, points, cam, formats, step), output, not no_plots, as_json)


@linkage_app.command()
def adjust(scene: SceneOptArg = None, mechanism: MechOpt = None,
           task: Annotated[int | None, _opt("--task", "Regulation task of Table 3 (1-6) or, with --table 2, of Table "
                                                      "2 (1-17).")] = None,
           table: Annotated[int, _opt("--table", "3: rocker input (the cam case); 2: crank input.")] = 3,
           swing_range: Annotated[str | None, _opt("--swing-range", "Task 1: swings A:B (deg) to cover.")] = None,
           keep: Annotated[str, _opt("--keep", "Task 1: keep psi1 or psi2 constant.")] = "psi1",
           count: Annotated[int, _opt("--count", "Settings listed.")] = 7,
           u_range: Annotated[str | None, _opt("--x", "Tasks 2-6: range U0:U1 of the regulating variable x.")] = None,
           psi1: Annotated[str | None, _opt("--psi1", "Tasks 3, 5: psi1 (deg) as a function of x.")] = None,
           psi2: Annotated[str | None, _opt("--psi2", "Tasks 4, 5: psi2 (deg) as a function of x.")] = None,
           swing_fn: Annotated[str | None, _opt("--swing-function", "Task 6: the swing (deg) of x.")] = None,
           psi2_of_psi1: Annotated[str | None, _opt("--psi2-of-psi1", "Task 2: psi2 (deg) of x = psi1 (deg).")] = None,
           pivot: PivotOpt = "0,0", output_pivot: OutPivotOpt = None, links: LinksOpt = None,
           input_angle: InputAngleOpt = None, swing: SwingOpt = None, sense: SenseOpt = 1, branch: BranchOpt = 1,
           output_pivot_2: OutPivot2Opt = None, links_2: Links2Opt = None, coupling_2: Coupling2Opt = 0.0,
           branch_2: Branch2Opt = 1, mu_min: MuOpt = 30.0, element: ElementOpt = None, joint: JointOpt = "C",
           path: PathOpt = "arc", centre: CentreOpt = None, direction: DirectionOpt = 0.0,
           settings: Annotated[str | None, _opt("--settings", "--table 2: settings to check (deg or mm).")] = None,
           synthesise: Annotated[bool, typer.Option("--synthesise", help="--table 2: find the element for the "
                                                                         "task.")] = False,
           phi1: Annotated[str | None, _opt("--phi1", "--table 2: phi1 change (deg) as a function of x.")] = None,
           phi2: Annotated[str | None, _opt("--phi2", "--table 2: phi2 change (deg) as a function of x.")] = None,
           var_range: Annotated[str | None, _opt("--var-range", "--table 2: a var column's change A:B (deg).")]
           = None,
           output: OutOpt = None, no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """An adjustable mechanism for a regulation task (Sunkuev 1984, Tables 2 and 3); exit 1 when it fails a check."""
    from camcad.scene.linkage_commands import AdjustRequest

    values = locals()
    _go(AdjustRequest(_source(values), task, table, swing_range, keep, count, u_range, psi1, psi2, swing_fn,
                      psi2_of_psi1, _element(values), settings, synthesise, phi1, phi2, var_range), output,
        not no_plots, as_json)


@linkage_app.command()
def family(member: Annotated[list[str] | None, _opt("--member", "A member psi(x) (deg) of the input angle x (deg); "
                                                               "repeat for each.")] = None,
           table: Annotated[Path | None, _opt("--table", "Members as a table: x (deg), one column per member.")]
           = None,
           phi: Annotated[str | None, _opt("--phi", "Input interval A:B (deg) of every member.")] = None,
           nodes: Annotated[int, _opt("--nodes", "S nodes per member (odd).")] = 5,
           crank: Annotated[float, _opt("--crank", "Crank length OA (mm).")] = 40.0,
           phi0: Annotated[float, _opt("--phi0", "The crank's angle at x = 0 (deg).")] = 0.0,
           spacing: Annotated[str, _opt("--spacing", "chebyshev or uniform nodes.")] = "chebyshev",
           ratio_max: RatioOpt = 10.0, mu_min: MuOpt = 30.0,
           output: OutOpt = None, no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """One adjustable four-bar for a family of position functions (Sunkuev 1984, ch. 4: Q, then the circle through the
    pivots); exit 1 when a member fails its checks."""
    from camcad.linkage.runners import FamilyRequest

    _go(FamilyRequest(tuple(member or ()), table, phi, nodes, crank, phi0, spacing, ratio_max, mu_min), output,
        not no_plots, as_json)


@linkage_app.command()
def tune(scene: SceneOptArg = None, mechanism: MechOpt = None,
         psi1: Annotated[float | None, _opt("--psi1", "Requested first extreme position (deg).")] = None,
         psi2: Annotated[float | None, _opt("--psi2", "Requested second extreme position (deg).")] = None,
         grid: Annotated[str | None, _opt("--grid", "Settings table: PSI1_A:PSI1_B:N,SWING_A:SWING_B:M (deg).")]
         = None,
         x1_range: Annotated[str | None, _opt("--range", "Interval A:B of x1 searched (deg, mm for a slot).")] = None,
         points: Annotated[int, _opt("--points", "Samples of F(x1).")] = 721,
         element: ElementOpt = None, joint: JointOpt = "C", path: PathOpt = "arc", centre: CentreOpt = None,
         direction: DirectionOpt = 0.0, pivot: PivotOpt = "0,0", output_pivot: OutPivotOpt = None,
         links: LinksOpt = None, input_angle: InputAngleOpt = None, swing: SwingOpt = None, sense: SenseOpt = 1,
         branch: BranchOpt = 1, output_pivot_2: OutPivot2Opt = None, links_2: Links2Opt = None,
         coupling_2: Coupling2Opt = 0.0, branch_2: Branch2Opt = 1, mu_min: MuOpt = 30.0,
         output: OutOpt = None, no_plots: NoPlotsOpt = False, as_json: JsonOpt = False) -> None:
    """Settings (x1 on the adjustable element, x2 the input link's clamp angle) for given extreme positions, every
    root of F(x1) = 0 (Sunkuev 1984, ch. 6); exit 1 when none is found."""
    from camcad.scene.linkage_commands import TuneRequest

    values = locals()
    _go(TuneRequest(_source(values), psi1, psi2, grid, x1_range, points, _element(values)), output, not no_plots,
        as_json)
