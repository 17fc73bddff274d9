"""`camcad linkage analyse|adjust|tune` as library calls: the linkage after the follower, from a scene's
``[linkage]`` or from options, analysed, made adjustable for a regulation task, or tuned to given extreme
positions (Sunkuev 1984, ch. 3, 4 and 6).

``run_linkage_analyse``, ``run_linkage_adjust`` and ``run_linkage_tune`` take a request (``LinkageSource`` for
the linkage, plus the command's own fields) and return a ``camcad.linkage.runners.LinkageReport`` subclass:
``to_dict()`` is the JSON, ``exit_code`` the verdict, ``lines()`` the text; ``camcad.report.linkage_commands``
writes the files. Lengths mm, angles deg.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

import numpy as np

from camcad.errors import CamcadError
from camcad.linkage import adjust as adj_mod
from camcad.linkage.adjust import Adjustment, adjusted, characteristics, radius
from camcad.linkage.analysis import LinkageAnalysis, analyse
from camcad.linkage.expr import parse_expression
from camcad.linkage.runners import LinkageReport, in_radians, numbers
from camcad.linkage.tune import TuneResult, settings_table, solve_settings, tuned
from camcad.profile.animation import FRAME_STEP_DEG
from camcad.scene.animation import cam_mechanism_frames, linkage_motion
from camcad.scene.linkage import (
    CommandLinkage,
    adjustment_of,
    cam_profile,
    from_options,
    from_scene,
    setting_value,
    working_report,
)


@dataclass(frozen=True)
class LinkageSource:
    """The linkage after the follower a command works on: a scene's ``[linkage]``, or options.

    Parameters
    ----------
    scene : Path or None
        A scene (.toml) with a ``[linkage]``; then the options below describing the linkage stay None.
    mechanism : str or None
        The mechanism of a group scene.
    pivot : str or sequence of float
        Input pivot O (the follower's pivot) X, Y, mm.
    output_pivot : str or sequence of float
        Output pivot C, X, Y, mm.
    links : str or sequence of float
        Input link OA, coupler AB, output link CB, mm.
    input_angle : float or None
        The input link's angle at ψ = 0, deg.
    swing : float or None
        The follower's swing ψ_max, deg.
    sense : int
        +1: the input link turns counter-clockwise as ψ grows; −1 clockwise (camcad's oscillating follower).
    branch : int
        Assembly branch ±1.
    output_pivot_2 : str or sequence of float
        Six-bar: the second output pivot F, X, Y, mm.
    links_2 : str or sequence of float
        Six-bar: CD, DE, FE, mm.
    coupling_2 : float
        Six-bar: the angle from CB to CD, deg.
    branch_2 : int
        Six-bar: the second loop's branch ±1.
    coupler_point : str or sequence of float
        A coupler point U (along AB), V (to its left), mm.
    mu_min : float
        Transmission-angle limit, deg.

    Examples
    --------
    >>> src = LinkageSource(links="40,120,90", output_pivot="100,20", input_angle=80, swing=30, sense=-1)
    >>> round(resolve(src).psi_max, 12) == round(math.radians(30), 12)
    True
    """

    scene: Path | None = None
    mechanism: str | None = None
    pivot: Any = (0.0, 0.0)
    output_pivot: Any = None
    links: Any = None
    input_angle: float | None = None
    swing: float | None = None
    sense: int = 1
    branch: int = 1
    output_pivot_2: Any = None
    links_2: Any = None
    coupling_2: float = 0.0
    branch_2: int = 1
    coupler_point: Any = None
    mu_min: float = 30.0


def resolve(source: LinkageSource, coupler_point: bool = True) -> CommandLinkage:
    """The nominal linkage and the follower's swing of a ``LinkageSource``."""
    if source.scene is not None:
        given = [o for o, v in (("--output-pivot", source.output_pivot), ("--links", source.links),
                                ("--input-angle", source.input_angle), ("--swing", source.swing),
                                ("--links-2", source.links_2)) if v is not None]
        if given:
            raise CamcadError(f"{given[0]} describes the linkage, which the scene already does", given[0],
                              "give the scene or the linkage options, not both")
        scene = Path(source.scene)
        if scene.is_dir() or scene.suffix.lower() != ".toml":
            raise CamcadError("not a scene file", str(scene), "give a .toml scene with a [linkage]")
        return from_scene(scene, source.mechanism)
    if source.links is None or source.output_pivot is None or source.input_angle is None:
        missing = next(o for o, v in (("--links", source.links), ("--output-pivot", source.output_pivot),
                                      ("--input-angle", source.input_angle)) if v is None)
        raise CamcadError("missing", missing, "give a scene, or --links A,B,C --output-pivot X,Y --input-angle DEG "
                                              "--swing DEG")
    a, b, c = numbers(source.links, "--links", 3, "40,120,90")  # type: ignore[misc]
    point = numbers(source.coupler_point, "--coupler-point", 2, "30,10") if coupler_point else None
    values: dict[str, Any] = {
        "type": "sixbar" if source.links_2 is not None else "fourbar",
        "input_pivot": list(numbers(source.pivot, "--pivot", 2, "0,0") or (0.0, 0.0)),
        "output_pivot": list(numbers(source.output_pivot, "--output-pivot", 2, "100,20") or ()),
        "input_link": a, "coupler": b, "output_link": c, "input_angle": source.input_angle, "branch": source.branch,
        "coupler_point": None if point is None else list(point), "mu_min": source.mu_min}
    if source.links_2 is not None:
        d2, e2, f2 = numbers(source.links_2, "--links-2", 3, "50,110,70")  # type: ignore[misc]
        pivot_2 = numbers(source.output_pivot_2, "--output-pivot-2", 2, "180,-30")
        values.update({"output_pivot_2": None if pivot_2 is None else list(pivot_2), "input_link_2": d2,
                       "coupler_2": e2, "output_link_2": f2, "coupling_2": source.coupling_2,
                       "branch_2": source.branch_2})
    if source.sense not in (1, -1):
        raise CamcadError(f"--sense must be +1 or -1, got {source.sense}", "--sense", "write --sense 1 or --sense -1")
    return from_options(values, source.swing, source.sense, "command line")


def inputs_of(command: CommandLinkage) -> tuple[Path, ...]:
    """The files a command read (the scene and the files it names)."""
    return () if command.scene is None else tuple(Path(p) for p in command.scene.input_files())


@dataclass(frozen=True)
class ElementSpec:
    """An adjustable element given by options (``camcad.linkage.adjust.Adjustment``).

    Parameters
    ----------
    element : str or None
        pivot (a frame pivot on an arc or slot), joint (a joint on its lever) or link_angle; None: the scene's
        ``[linkage.adjust]``.
    joint : str
        The element's joint: C or F (pivot), A, B or E (joint).
    path : str
        arc or slot.
    centre : str or sequence of float
        The arc's centre X, Y, mm.
    direction : float
        The slot's direction, deg.

    Examples
    --------
    >>> ElementSpec("pivot", "C", centre="100,5").centre
    '100,5'
    """

    element: str | None = None
    joint: str = "C"
    path: str = "arc"
    centre: Any = None
    direction: float = 0.0


def element_of(command: CommandLinkage, spec: ElementSpec):
    """(Adjustment, the scene's AdjustSpec or None): the options' element, else the scene's
    [linkage.adjust]; (None, None) if neither."""
    if spec.element is None:
        context = command.context
        if context is not None and context.spec.adjust is not None:
            return adjustment_of(context.spec.adjust), context.spec.adjust
        return None, None
    if spec.element not in ("pivot", "joint", "link_angle"):
        raise CamcadError(f"unknown element {spec.element!r}", "--element", "use pivot, joint or link_angle")
    joints = {"pivot": ("C", "F"), "joint": ("A", "B", "E"), "link_angle": ("",)}[spec.element]
    if spec.element != "link_angle" and spec.joint.upper() not in joints:
        raise CamcadError(f"joint {spec.joint!r} cannot be a {spec.element}", "--joint", f"use {' or '.join(joints)}")
    xy = numbers(spec.centre, "--centre", 2, "100,5")
    if spec.element != "link_angle" and spec.path == "arc" and xy is None:
        raise CamcadError("an arc needs its centre", "--centre", "give --centre X,Y (mm)")
    return Adjustment(spec.element, spec.joint.upper() if spec.element != "link_angle" else "", spec.path,
                      None if xy is None else complex(*xy), math.radians(spec.direction)), None


# --------------------------------------------------------------------------------------------
# analyse
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class AnalyseRequest:
    """What ``camcad linkage analyse`` analyses.

    Parameters
    ----------
    source : LinkageSource
        The linkage (a scene or options).
    points : int
        Samples over the swing.
    cam : bool
        With a scene: draw the cam on the same sheet (and animate it with the linkage).
    animate : tuple of str
        Animation files to write ("html", "gif", "mp4"); () none. With a scene's cam: the cam, the follower
        and the linkage over one turn (``camcad.scene.animation.cam_mechanism_frames``); otherwise the linkage
        alone over the swing and back (``linkage_motion``).
    animate_step_deg : float
        Between frames: cam angle (deg) with a cam, the follower's swing (deg) without; must divide 360.

    Examples
    --------
    >>> AnalyseRequest(LinkageSource(links="40,120,90", output_pivot="100,20", input_angle=80, swing=30)).points
    721
    """

    source: LinkageSource = field(default_factory=LinkageSource)
    points: int = 721
    cam: bool = True
    animate: tuple[str, ...] = ()
    animate_step_deg: float = FRAME_STEP_DEG


@dataclass
class AnalyseReport(LinkageReport):
    """The analysis (``analysis``) of the linkage (``command``), with a scene the working member's motion and
    every setting of ``[linkage.adjust]``."""

    command_linkage: CommandLinkage | None = None
    analysis: LinkageAnalysis | None = None
    settings: list = field(default_factory=list)         # (label, Linkage) per setting
    settings_rows: list = field(default_factory=list)
    setting_unit: str = "deg"
    element: str = ""
    arc: Any = None
    profile: Any = None
    working: Any = None                                   # (theta, kinematics, unit) with a scene


def run_linkage_analyse(request: AnalyseRequest) -> AnalyseReport:
    """Analyse the linkage after the follower (``camcad linkage analyse``).

    Exact Π, Π′, Π″, Π‴, transmission angles, dead points, branch, coupler path; with a scene also the working
    member's motion, every setting and the cam.

    Parameters
    ----------
    request : AnalyseRequest
        The linkage (a scene or options; mm, deg) and the samples over the swing.

    Returns
    -------
    AnalyseReport
        ``to_dict()``: ``linkage`` (the analysis: stroke, Π′ range, μ min per loop in deg, dead points, limit
        positions, checks), with a scene ``working_member`` and ``settings``.

    References
    ----------
    F. Freudenstein, Trans. ASME 77 (1955) 853–861 (the loop equation); Sunkuev 1984, ch. 4 (the six-bar of
    two four-bars in series).

    Examples
    --------
    >>> src = LinkageSource(links="40,120,90", output_pivot="100,20", input_angle=80, swing=30, sense=-1)
    >>> r = run_linkage_analyse(AnalyseRequest(src, points=181))
    >>> r.exit_code, round(r.to_dict()["linkage"]["swing_deg"], 6)
    (0, 30.0)
    """
    if not 11 <= request.points <= 200001:
        raise CamcadError(f"--points {request.points} is out of range", "--points", "give 11 to 200001")
    command = resolve(request.source)
    result = analyse(command.linkage, command.psi_max, request.points)
    payload: dict[str, Any] = {"command": "linkage analyse", "name": command.name,
                               "linkage": result.report(command.mu_min)}
    report = AnalyseReport("analysis", payload, bool(payload["linkage"]["passed"]), [], f"linkage-{command.name}",
                           inputs_of(command), command, result)
    ctx = command.context
    if ctx is not None:
        payload["law_of"] = ctx.law_of
        payload["working_member"] = working_report(ctx, command.follower_law, command.output_law)
        theta = np.linspace(0.0, command.follower_law.cycle, 1441)
        report.working = (theta, ctx.working_law(command.follower_law).kinematics(theta), ctx.transfer.unit_out)
        if ctx.spec.adjust is not None:
            adj = adjustment_of(ctx.spec.adjust)
            for value in ctx.spec.adjust.settings:
                x = setting_value(ctx.spec.adjust, value)
                ch = characteristics(command.linkage, adj, x, command.psi_max)
                report.settings_rows.append({"setting": value, **{k: v for k, v in ch.as_dict(adj.unit).items()
                                                                  if not k.startswith("setting")}})
                report.settings.append((f"{value:g} {'mm' if adj.unit == 'mm' else 'deg'}",
                                        adjusted(command.linkage, adj, x)))
            payload["settings"] = {"element": adj.describe(), "rows": report.settings_rows}
            report.setting_unit = "deg" if adj.unit == "rad" else "mm"
            report.element = adj.describe()
            if adj.element != "link_angle" and adj.path == "arc":
                report.arc = (adj.centre, radius(command.linkage, adj),
                              [setting_value(ctx.spec.adjust, v) for v in ctx.spec.adjust.settings])
        if request.cam:
            report.profile = cam_profile(command)
    if request.animate:
        _animate(report, request, command, result)
    report.summary = _analyse_lines(payload, command.mu_min)
    if "skipped" in payload.get("animation", {}):
        report.summary.append(f"  animation      not written: {payload['animation']['skipped']}")
    return report


def _animate(report: AnalyseReport, request: AnalyseRequest, command: CommandLinkage,
             result: LinkageAnalysis) -> None:
    """The frames of ``--animate``: the cam, its follower and the linkage with a scene's cam, else the linkage
    alone over the swing; none (and why, in the JSON) where the linkage does not close over the swing."""
    report.animate = request.animate
    if not result.closes:
        report.payload["animation"] = {"skipped": "the linkage does not close over the whole swing: nothing to draw "
                                                  "where it breaks"}
        return
    if report.profile is not None:
        frames = cam_mechanism_frames(command.name, report.profile, command.context, command.follower_law,
                                      request.animate_step_deg)
        report.animation = frames
        report.payload["animation"] = {"moves": "the cam over one turn, the follower and the linkage after it",
                                       "frames": frames.count, "step_deg": 360.0 / frames.count}
        return
    motion = linkage_motion(command.linkage, command.psi_max, request.animate_step_deg, command.name,
                            input_label="follower's swing ψ", output_label="working member Π")
    report.animation = motion
    report.payload["animation"] = {"moves": "the linkage alone over the follower's swing and back",
                                   "frames": motion.count, "step_deg": round(float(abs(motion.input_deg[1])), 9)}


def _analyse_lines(payload: dict, mu_min: float) -> list[str]:
    rep = payload["linkage"]
    lines = [(f"camcad linkage analyse: {payload['name']}, {rep['type']}, swing {rep['swing_deg']:.6g} deg -> stroke "
              f"{rep['stroke_deg']:.6g} deg ({rep['output_direction']})"),
             (f"  Pi'            {rep['pi_prime_range'][0]:.6g} .. {rep['pi_prime_range'][1]:.6g} rad/rad; "
              f"|Pi''| <= {rep['pi_second_abs_max']:.4g}, |Pi'''| <= {rep['pi_third_abs_max']:.4g}"),
             f"  mu min         {', '.join(f'{m:.3f}' for m in rep['mu_min_deg'])} deg (limit {mu_min:g})",
             (f"  dead points    {rep['dead_points_swing_deg'] or 'none'}; limit positions "
              f"{rep['limit_positions_swing_deg'] or 'none'} (swing deg)"),
             (f"  branch         {'continuous' if rep['branch_continuous'] else 'NOT continuous'}; "
              f"{'monotone' if rep['monotone'] else 'NOT monotone'}")]
    if "working_member" in payload:
        w = payload["working_member"]
        line = f"  working member stroke {w['stroke']:.6g} {w['unit']}, |y''| <= {w['acceleration_analog_max']:.5g}"
        if "round_trip_max" in w:
            line += f"; law_of = output round trip {w['round_trip_max']:.3g} {w['round_trip_unit']}"
        lines.append(line)
    for row in payload.get("settings", {}).get("rows", []):
        lines.append(f"  setting {row['setting']:<8g} psi1 {row['psi1_deg']:+.5f}, psi2 {row['psi2_deg']:+.5f}, "
                     f"swing {row['swing_deg']:.5f}, mu min {row['mu_min_deg']:.2f} deg"
                     + ("" if row["branch_continuous"] else ", BRANCH BROKEN"))
    lines += [f"  check {name:<20} " + ("ok" if check["passed"] else "FAILED") for name, check in rep["checks"].items()]
    return lines


# --------------------------------------------------------------------------------------------
# adjust
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class AdjustRequest:
    """What ``camcad linkage adjust`` solves: a regulation task of Sunkuev 1984's Table 3 or Table 2.

    Parameters
    ----------
    source : LinkageSource
        The linkage (a scene or options).
    task : int or None
        The task: Table 3 1–6, Table 2 1–17.
    table : int
        3 (rocker input: the cam case) or 2 (crank input).
    swing_range : str or sequence of float
        Task 1: the swings A, B to cover, deg.
    keep : str
        Task 1: keep psi1 or psi2 constant.
    count : int
        Settings listed.
    x : str or sequence of float
        Tasks 2–6: the regulating variable's range U0, U1 (deg for task 2, where x = ψ₁).
    psi1, psi2, swing_function, psi2_of_psi1 : str or None
        Tasks 2–6: the requirements as expressions of x giving deg.
    element : ElementSpec
        Table 2: the element whose settings are checked.
    settings : str or sequence of float
        Table 2: the settings to check, deg (mm for a slot).
    synthesise : bool
        Table 2: find the element for the task instead of checking one (the pivot C on an arc, or with
        ``element`` joint B the rocker's pin on an arc), fitted over ``x`` (default 0:1).
    phi1, phi2 : str or None
        Table 2, f columns: φ₁, φ₂ (the crank's angles at the output's extremes; changes from the nominal, deg)
        as expressions of x; ``psi1``, ``psi2`` and ``swing_function`` likewise for Table 2.
    var_range : str or sequence of float
        Table 2, a var column: the change from the nominal to sweep, A, B deg.

    Examples
    --------
    >>> src = LinkageSource(links="40,120,90", output_pivot="100,20", input_angle=80, swing=30, sense=-1)
    >>> AdjustRequest(src, task=1, swing_range="18:30").table
    3
    """

    source: LinkageSource = field(default_factory=LinkageSource)
    task: int | None = None
    table: int = 3
    swing_range: Any = None
    keep: str = "psi1"
    count: int = 7
    x: Any = None
    psi1: str | None = None
    psi2: str | None = None
    swing_function: str | None = None
    psi2_of_psi1: str | None = None
    element: ElementSpec = field(default_factory=ElementSpec)
    settings: Any = None
    synthesise: bool = False
    phi1: str | None = None
    phi2: str | None = None
    var_range: Any = None


@dataclass
class AdjustReport(LinkageReport):
    """The adjustable mechanism of a task: the nominal linkage, every setting's linkage, the element's arc."""

    command_linkage: CommandLinkage | None = None
    rows: list = field(default_factory=list)
    settings: list = field(default_factory=list)
    arc: Any = None
    task: int = 1
    table: int = 3
    element: str = ""
    drawing_note: str = ""


def _functions(options: dict) -> dict:
    """Expressions of the regulating variable x (deg values) → callables rad → rad."""
    out = {}
    for key, (option, text) in options.items():
        if text is None:
            continue
        try:
            expr = parse_expression(text)
        except CamcadError as err:
            raise CamcadError(err.what, option, err.fix) from None
        out[key] = in_radians(expr, key == "psi2_of_psi1")
    return out


def run_linkage_adjust(request: AdjustRequest) -> AdjustReport:
    """An adjustable mechanism for a regulation task of Sunkuev 1984's Tables 2 and 3 (``camcad linkage adjust``).

    Parameters
    ----------
    request : AdjustRequest
        The linkage, the table and task, and the task's data (deg; functions of x in deg).

    Returns
    -------
    AdjustReport
        ``to_dict()``: the element, the arc (mm), every setting's ψ₁, ψ₂, swing and worst transmission angle
        (deg), the deviations from the task (deg), the requirements and their verdict.

    References
    ----------
    Sunkuev 1984, ch. 3 (Tables 2 and 3; the auxiliary mechanism formed in the extreme positions).

    Examples
    --------
    >>> src = LinkageSource(links="40,120,90", output_pivot="100,20", input_angle=80, swing=30, sense=-1)
    >>> r = run_linkage_adjust(AdjustRequest(src, task=1, swing_range="10:20", count=3))
    >>> r.exit_code, [round(row["swing_deg"], 9) for row in r.to_dict()["rows"]]
    (0, [10.0, 15.0, 20.0])
    """
    if request.table not in (2, 3):
        raise CamcadError(f"--table {request.table}: Sunkuev 1984's regulation tables are 2 and 3", "--table",
                          "use 2 or 3")
    if request.task is None:
        raise CamcadError("missing", "--task", "give the regulation task, e.g. --task 1")
    if not 2 <= request.count <= 201:
        raise CamcadError(f"--count {request.count} is out of range", "--count", "give 2 to 201")
    command = resolve(request.source, coupler_point=False)
    if request.table == 2:
        return _adjust_table2(request, command)
    lk, psi_max = command.linkage, command.psi_max
    task = request.task
    if task == 1:
        span = numbers(request.swing_range, "--swing-range", 2, "18:30")
        if span is None:
            raise CamcadError("missing", "--swing-range", "give the swings to cover, e.g. --swing-range 18:30 (deg)")
        lo, hi = span
        if not (lo > 0 and hi > lo):
            raise CamcadError(f"--swing-range {lo:g}:{hi:g} must be 0 < A < B (deg)", "--swing-range",
                              "e.g. --swing-range 18:30")
        result = adj_mod.solve_task1(lk, psi_max, (math.radians(lo), math.radians(hi)), request.count, request.keep)
    elif task in (2, 3, 4, 5, 6):
        span = numbers(request.x, "--x", 2, "0:10")
        if span is None:
            raise CamcadError("missing", "--x", "give the regulating variable's range, e.g. --x 0:10")
        u0, u1 = span
        if u1 == u0:
            raise CamcadError("--x has no width", "--x", "give U0:U1 with U1 != U0")
        needed = {2: {"psi2_of_psi1": ("--psi2-of-psi1", request.psi2_of_psi1)}, 3: {"psi1": ("--psi1", request.psi1)},
                  4: {"psi2": ("--psi2", request.psi2)},
                  5: {"psi1": ("--psi1", request.psi1), "psi2": ("--psi2", request.psi2)},
                  6: {"swing": ("--swing-function", request.swing_function)}}[task]
        for option, text in needed.values():
            if text is None:
                raise CamcadError("missing", option, f"task {task} needs {option} EXPR (deg, a function of x)")
        if task == 2:
            u0, u1 = math.radians(u0), math.radians(u1)
        result = adj_mod.fit_task(lk, psi_max, task, (u0, u1), _functions(needed), count=max(request.count, 11),
                                  mu_min=math.radians(command.mu_min))
    else:
        raise CamcadError(f"Table 3 has no task {task}", "--task", "tasks are 1 to 6")
    rows = [{"u": float(u), **r.as_dict(result.adjustment.unit)} for u, r in zip(result.u, result.rows)]
    if task == 1:
        for row in rows:
            row["u"] = row["swing_deg"]
    verdict = adj_mod.check_requirements(rows, task, 3, kept=request.keep if task == 1 else "psi1")
    checks_ok = all(r["branch_continuous"] and r["mu_min_deg"] >= command.mu_min for r in rows)
    adj = result.adjustment
    arc_centre = cast(complex, adj.centre)  # every task of Table 3 moves joint A on an arc
    payload: dict[str, Any] = {
        "command": "linkage adjust", "name": command.name, "table": 3, "task": task, "element": adj.describe(),
        "arc_centre_mm": [arc_centre.real, arc_centre.imag], "arc_radius_mm": result.radius, "rows": rows,
        "deviation_deg": {k: math.degrees(v) for k, v in result.deviation.items()}, "monotone": result.monotone,
        "requirements": verdict, "notes": list(result.notes),
        "passed": bool(verdict["passed"] and checks_ok and result.monotone)}
    if result.evidence:
        payload["evidence"] = result.evidence
    settings = [(f"x = {r['setting_deg']:.3f} deg", adjusted(lk, adj, math.radians(r["setting_deg"]))) for r in rows]
    arc = (adj.centre, result.radius, [math.radians(r["setting_deg"]) for r in rows])
    summary = [f"camcad linkage adjust: Table 3 task {task}, {adj.describe()}, radius {result.radius:.4f} mm"]
    summary += [f"  x {r['u']:<10.5g} lock {r['setting_deg']:9.4f} deg  psi1 {r['psi1_deg']:+.9f}  psi2 "
                f"{r['psi2_deg']:+.6f}  swing {r['swing_deg']:.6f}  mu {r['mu_min_deg']:.2f}" for r in rows]
    summary.append("  deviation      " + ", ".join(f"{k} {v:.3g} deg" for k, v in payload["deviation_deg"].items()))
    if result.evidence:
        ev = result.evidence
        summary.append(f"  evidence       {ev['starts']} starts, {ev['reaching_best']} reach the best within "
                       f"{ev['tolerance_deg']:g} deg; spread of the ends {ev['spread_deg']:.3g} deg")
    summary += [f"  requirement {k}: {v['need']} " + ("ok" if v["passed"] else "NOT met")
                for k, v in verdict.items() if isinstance(v, dict)]
    return AdjustReport("adjust", payload, bool(payload["passed"]), summary, f"adjust-{command.name}",
                        inputs_of(command), command, rows, settings, arc, task, 3, adj.describe(),
                        f"arc radius {result.radius:.4f} mm, lock angles {rows[0]['setting_deg']:.3f} .. "
                        f"{rows[-1]['setting_deg']:.3f} deg")


def _adjust_table2(request: AdjustRequest, command: CommandLinkage) -> AdjustReport:
    """Table 2 (crank input): an element's settings checked against the task, or (``synthesise``) found."""
    lk = command.linkage
    task = cast(int, request.task)
    if task not in adj_mod.TABLE2:
        raise CamcadError(f"Table 2 has no task {task}", "--task", "tasks are 1 to 17")
    extra: dict[str, Any] = {}
    values: Sequence[float] | None          # the settings, deg or mm
    if request.synthesise:
        span = numbers(request.x, "--x", 2, "0:1") or (0.0, 1.0)
        var = numbers(request.var_range, "--var-range", 2, "0:8")
        texts = {"phi1": ("--phi1", request.phi1), "psi1": ("--psi1", request.psi1), "phi2": ("--phi2", request.phi2),
                 "psi2": ("--psi2", request.psi2), "psi12": ("--swing-function", request.swing_function)}
        found = adj_mod.synthesise_table2(lk, task, span, _functions(texts), None if var is None else
                                          (math.radians(var[0]), math.radians(var[1])),
                                          joint=request.element.joint if request.element.element else "C",
                                          count=max(request.count, 5), mu_min=math.radians(command.mu_min))
        adj, values = found.adjustment, found.settings
        notes = list(found.notes)
        extra = {"u": [float(v) for v in found.u], "deviation_deg": found.deviation, "evidence": found.evidence}
    else:
        adj, spec = element_of(command, request.element)
        values = numbers(request.settings, "--settings", None, "10,20,30") or \
            (list(spec.settings) if spec is not None else None)
        if adj is None or not values:
            raise CamcadError("Table 2 checks an adjustable element's settings", "--element",
                              "give --element, --joint, --centre and --settings (or a scene with [linkage.adjust]), "
                              "or --synthesise")
        notes = []
    rows = []
    for v in values:
        x = math.radians(v) if adj.unit == "rad" else v
        ch = adj_mod.crank_characteristics(lk, adj, x)
        if not ch:
            raise CamcadError(f"at setting {v:g} the input link cannot turn fully (not a crank)", "--table 2",
                              "Table 2 is for a rotating input; the cam's rocker input is Table 3")
        rows.append({"setting": v, **ch})
    verdict = adj_mod.check_requirements(rows, task, 2)
    payload = {"command": "linkage adjust", "name": command.name, "table": 2, "task": task,
               "element": adj.describe(), "synthesised": bool(request.synthesise), "rows": rows,
               "requirements": verdict, "notes": notes, "passed": bool(verdict["passed"]), **extra}
    summary = [f"camcad linkage adjust: Table 2 task {task}, {adj.describe()}"
               + (" (synthesised)" if request.synthesise else "")]
    summary += [f"  setting {r['setting']:<10.6g} phi1 {r['phi1_deg']:.4f} psi1 {r['psi1_deg']:.4f} phi2 "
                f"{r['phi2_deg']:.4f} psi2 {r['psi2_deg']:.4f} deg" for r in rows]
    summary += [f"  requirement {k}: {v['need']} " + ("ok" if v["passed"] else "NOT met")
                for k, v in verdict.items() if isinstance(v, dict)]
    if extra:
        summary.append("  deviation      " + ", ".join(f"{k} {v:.3g} deg" for k, v in extra["deviation_deg"].items()))
        ev = extra["evidence"]
        summary.append(f"  evidence       {ev['starts']} starts, {ev['reaching_best']} reach the best within "
                       f"{ev['tolerance_deg']:g} deg")
    summary += [f"  note           {n}" for n in notes]
    settings = [(f"{r['setting']:.4g}", adjusted(lk, adj, math.radians(r["setting"]) if adj.unit == "rad"
                                                  else r["setting"])) for r in rows]
    arc = None
    if adj.element != "link_angle" and adj.path == "arc":
        arc = (adj.centre, radius(lk, adj), [math.radians(r["setting"]) for r in rows])
    return AdjustReport("adjust", payload, bool(verdict["passed"]), summary, f"adjust-{command.name}",
                        inputs_of(command), command, rows, settings, arc, task, 2, adj.describe(),
                        f"Table 2 task {task}: every setting, crank input")


# --------------------------------------------------------------------------------------------
# tune
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class TuneRequest:
    """What ``camcad linkage tune`` finds: the settings for given extreme positions (Sunkuev 1984, ch. 6).

    Parameters
    ----------
    source : LinkageSource
        The linkage (a scene or options).
    psi1, psi2 : float or None
        The requested extreme positions of the working member, deg.
    grid : str or None
        A settings table instead: ``"P1A:P1B:N,SWA:SWB:M"`` (ψ₁ values and swings, deg).
    range : str or sequence of float
        The interval of x₁ searched, deg (mm for a slot).
    points : int
        Samples of F(x₁).
    element : ElementSpec
        The element of x₁ (default: the scene's ``[linkage.adjust]``).

    Examples
    --------
    >>> TuneRequest(LinkageSource(scene=None), psi1=-2.0, psi2=12.0).points
    721
    """

    source: LinkageSource = field(default_factory=LinkageSource)
    psi1: float | None = None
    psi2: float | None = None
    grid: str | None = None
    range: Any = None
    points: int = 721
    element: ElementSpec = field(default_factory=ElementSpec)


@dataclass
class TuneReport(LinkageReport):
    """Every root of F(x₁) = 0, or the settings table."""

    command_linkage: CommandLinkage | None = None
    result: TuneResult | None = None
    rows: list = field(default_factory=list)
    settings: list = field(default_factory=list)
    unit: str = "deg"
    table_comment: str = ""


def grid_axes(text: str) -> tuple[list[float], list[float]]:
    """"P1A:P1B:N,SWA:SWB:M" → the ψ₁ values and the swing values (deg)."""
    parts = text.split(",")
    if len(parts) != 2:
        raise CamcadError(f"{text!r} is not two ranges", "--grid", "write --grid -2:2:3,10:20:3")
    axes = []
    for part in parts:
        bits = part.split(":")
        try:
            if len(bits) == 1:
                axes.append([float(bits[0])])
                continue
            start, stop, n = float(bits[0]), float(bits[1]), int(bits[2])
        except (ValueError, IndexError):
            raise CamcadError(f"{part!r} is not A:B:N", "--grid", "write --grid -2:2:3,10:20:3") from None
        if not 1 <= n <= 50:
            raise CamcadError(f"{n} values is out of range", "--grid", "give 1 to 50 values per axis")
        axes.append(list(np.linspace(start, stop, n)))
    return axes[0], axes[1]


def run_linkage_tune(request: TuneRequest) -> TuneReport:
    """Settings for given extreme positions (``camcad linkage tune``).

    Every root of Sunkuev 1984's F(x₁) = f₁(x₁) − f₂(x₁) = 0, or the settings table.

    Parameters
    ----------
    request : TuneRequest
        The linkage and its element, ψ₁ and ψ₂ (deg) or the table's grid (deg).

    Returns
    -------
    TuneReport
        ``to_dict()``: ``roots`` (x₁ in deg or mm, x₂ deg, the round trip's error in deg) or ``rows``.

    References
    ----------
    Sunkuev 1984, ch. 6 (equations (1) and (2): x₂ = f₁(x₁), x₂ = f₂(x₁), F(x₁) = 0).

    Examples
    --------
    >>> src = LinkageSource(links="40,120,90", output_pivot="100,20", input_angle=80, swing=30, sense=-1)
    >>> r = run_linkage_tune(TuneRequest(src, psi1=-2, psi2=12, element=ElementSpec("pivot", "C", centre="100,5")))
    >>> r.exit_code, len(r.to_dict()["roots"]) >= 1
    (0, True)
    """
    if not 11 <= request.points <= 100001:
        raise CamcadError(f"--points {request.points} is out of range", "--points", "give 11 to 100001")
    command = resolve(request.source, coupler_point=False)
    adj, _ = element_of(command, request.element)
    if adj is None:
        raise CamcadError("no adjustable element for x1", "--element",
                          "give --element pivot --joint C --centre X,Y (or a scene with [linkage.adjust])")
    if adj.element == "link_angle":
        raise CamcadError("x2 is the input link's clamp angle: x1 must be a pivot or joint", "--element",
                          "use --element pivot or joint")
    lk, psi_max = command.linkage, command.psi_max
    span = numbers(request.range, "--range", 2, "30:150")
    rng = None
    if span is not None:
        rng = (math.radians(span[0]), math.radians(span[1])) if adj.unit == "rad" else span
    unit = "deg" if adj.unit == "rad" else "mm"
    payload: dict[str, Any] = {"command": "linkage tune", "name": command.name, "element": adj.describe(),
                               "x1_unit": unit}
    if request.grid is not None:
        if request.psi1 is not None or request.psi2 is not None:
            raise CamcadError("--grid and --psi1/--psi2 both ask for settings", "--grid", "give one of them")
        first, second = grid_axes(request.grid)
        rows = settings_table(lk, adj, psi_max, np.radians(first), np.radians(second), rng, min(request.points, 361))
        payload.update({"rows": rows, "passed": all(r["x1"] is not None for r in rows)})
        summary = [f"camcad linkage tune: settings table, {adj.describe()}"]
        summary += [f"  psi1 {r['psi1_deg']:+8.3f} swing {r['swing_deg']:8.3f} deg -> " +
                    (f"root {r['root']}: x1 {r['x1']:.6f} {unit}, x2 {r['x2_deg']:.6f} deg (error {r['error_deg']:.2g})"
                     if r["x1"] is not None else "no setting") for r in rows]
        return TuneReport("tune", payload, bool(payload["passed"]), summary, f"tune-{command.name}",
                          inputs_of(command), command, None, rows, [], unit,
                          "settings table: every root x1 (lock angle or slot position) and x2 (clamp angle) per "
                          "psi1, swing")
    if request.psi1 is None or request.psi2 is None:
        raise CamcadError("missing", "--psi1" if request.psi1 is None else "--psi2",
                          "give --psi1 DEG --psi2 DEG (or --grid for a settings table)")
    result = solve_settings(lk, adj, psi_max, math.radians(request.psi1), math.radians(request.psi2), rng,
                            request.points)
    rows = [{"root": k, "x1": math.degrees(r.x1) if unit == "deg" else r.x1, "x2_deg": math.degrees(r.x2),
             "psi1_deg": math.degrees(r.psi1), "psi2_deg": math.degrees(r.psi2), "error_deg": math.degrees(r.error),
             "mu_min_deg": math.degrees(r.mu_min) if np.isfinite(r.mu_min) else None,
             "branch_continuous": r.branch_continuous} for k, r in enumerate(result.roots, start=1)]
    payload.update({"psi1_deg": request.psi1, "psi2_deg": request.psi2, "roots": rows, "passed": bool(rows)})
    settings = [(f"root {k + 1}", tuned(lk, adj, r.x1, r.x2)) for k, r in enumerate(result.roots)]
    summary = [(f"camcad linkage tune: psi1 {request.psi1:g} deg, psi2 {request.psi2:g} deg; x1 on {adj.describe()}, "
                "x2 the input link's clamp angle")]
    summary += [f"  root {r['root']}: x1 {r['x1']:.9f} {unit}, x2 {r['x2_deg']:.9f} deg; round trip error "
                f"{r['error_deg']:.2g} deg, mu min {r['mu_min_deg'] or float('nan'):.2f} deg" +
                ("" if r["branch_continuous"] else ", BRANCH BROKEN") for r in rows] or [
        "  no setting gives these extreme positions"]
    return TuneReport("tune", payload, bool(rows), summary, f"tune-{command.name}", inputs_of(command), command,
                      result, rows, settings, unit, "")
