"""The scene pipeline: what `camcad profile SCENE.toml` runs, in SPEC.md's order, and only what the scene asks for.

For every mechanism: 1 read the law → 2 check (and fix, when [law] fix says so) its balance → 3 resonance
filtering and lead-in ([filter], with a natural frequency and speeds) → 4 profile synthesis ([follower]) →
5 elastic dynamics ([dynamics] and speeds) → 6 stop impact ([stops] and speeds) → 7 contact stress
([contact], [follower] and speeds) → 8 the least phase angles that 6 and 7 allow. Then 9, when the scene has
a [cyclogram]: the network is optimised with those limits, its phase angles go back into each mechanism's
law (shape and lift kept) and steps 3–7 run again on the retimed laws → 10 the outputs: per mechanism
profile.dxf, law.csv and plots, and one report.json. A step that does not run says why under ``skipped``;
no step fills in a physical quantity the scene did not give.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from camcad.errors import CamcadError
from camcad.scene.file import Mechanism, Scene, mechanism_law, read_scene
from camcad.scene.mechanism import LimitMemo

#: cam-angle samples per phase for the contact-stress maximum and its phase limits
CONTACT_SAMPLES = 2000


@dataclass(frozen=True)
class PipelineOptions:
    """How a scene run writes its outputs, and where.

    Parameters
    ----------
    output : Path or None
        The output folder; None: ``./camcad-out/<scene name>/``.
    tol_mm : float
        Chord tolerance of the written profile, mm: the largest distance between the written curve and the
        exact profile.
    arcs : bool
        Write the profile as lines and tangent arcs (bulges) instead of chords (no unit).
    spline : bool
        Also write a closed control-point SPLINE of the profile (no unit).
    r12 : bool
        Write DXF R12 instead of R2000 (no unit).
    plots : tuple of str
        Names of the plots to draw (``camcad.report.profile.PLOTS`` and the models' "dynamics", "impact",
        "contact"); ("all",) every one; () none (no unit).
    contact_samples : int
        Cam-angle samples per phase for the contact-stress maxima and their phase limits (dimensionless).
    checks_only : bool
        Only what the checks need (no unit): no smallest base radius, no least phase angles of a mechanism
        the cyclogram does not retime, no pitch curve sampled for writing — what ``camcad sweep`` runs.
    export : dict, optional
        The part's files and units given on the command line (``camcad.scene.export.ExportSettings`` field
        names → values; lengths mm, feed mm/min), put over each mechanism's [export] section.

    Examples
    --------
    >>> PipelineOptions(plots=()).tol_mm
    0.001
    """

    output: Path | None = None
    tol_mm: float = 0.001
    arcs: bool = False
    spline: bool = False
    r12: bool = False
    plots: tuple[str, ...] = ("summary",)   # names of the plots to draw ("all": every one; (): none)
    contact_samples: int = CONTACT_SAMPLES
    #: only what the checks need (``camcad sweep``): no smallest-base-radius design and no written pitch curve in
    #: the profile, no least phase angles (step 8) of a mechanism the cyclogram does not retime; the checks are
    #: unchanged
    checks_only: bool = False
    export: dict | None = None


@dataclass
class MechanismRun:
    """What the pipeline found for one mechanism (filled step by step)."""

    name: str
    law: Any = None
    report: dict = field(default_factory=dict)
    skipped: dict = field(default_factory=dict)
    ran: list = field(default_factory=list)
    profile: Any = None
    dynamics: Any = None
    impact: Any = None
    contact: Any = None
    memo: Any = None        # LimitMemo shared by the scene's runs: least phase angles solved once
    linkage: Any = None     # camcad.scene.linkage.LinkageContext: the [linkage] after the follower, or None


@dataclass(frozen=True)
class SceneResult:
    """What the pipeline found: the scene, every mechanism's run, the report (SPEC.md keys; no outputs yet)."""

    scene: Scene
    runs: dict
    report: dict
    group: bool

    @property
    def passed(self) -> bool:
        return bool(self.report["passed"])


Progress = Callable[[str], None]


def analyse_scene(path: str | Path | Scene, options: PipelineOptions = PipelineOptions(),
                  progress: Progress | None = None) -> SceneResult:
    """Run the scene pipeline's analyses (steps 1–9) and return what they found, writing nothing.

    For every mechanism: read the law, check (and fix) its balance, resonance filtering, profile
    synthesis, elastic dynamics, stop impact, contact stress and the least phase angles they allow; then
    the cyclogram, whose phase angles go back into the laws (module docstring; SPEC.md "The scene
    pipeline"). Only the steps the scene asks for run; ``report["skipped"]`` says why the others did
    not. ``run_scene`` also writes the outputs (step 10).

    Parameters
    ----------
    path : str, Path or Scene
        The scene file, or a ``Scene`` (``read_scene``, or built by a command from its options).
    options : PipelineOptions
        How the outputs would be written (chord tolerance ``tol_mm`` in mm, arcs, spline, R12, plots)
        and the contact-stress sampling (``contact_samples``, a count per phase).
    progress : callable, optional
        Called with a short text (no unit) as each step starts.

    Returns
    -------
    SceneResult
        ``report``: the SPEC.md keys (angles deg, lengths mm, speeds rpm, forces N, stresses MPa),
        with ``models_run`` and ``skipped``; ``runs``: each mechanism's law, profile and models;
        ``passed``: the verdict.

    Raises
    ------
    CamcadError
        Bad input anywhere in the scene: one line naming the file and section.

    Examples
    --------
    A scene with a cycloidal law and a roller follower runs the law and the profile only; its pressure
    angle is the one ``synthesize`` finds for the same law and follower:

    >>> import tempfile, pathlib
    >>> import camcad
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "cam.toml").write_text('''
    ... name = "cam"
    ... [law]
    ... standard = "cycloidal"
    ... phases = "0:90:rise,90:180:dwell,180:270:return,270:360:dwell"
    ... lift = 20.0
    ... [follower]
    ... type = "roller"
    ... base_radius = 40.0
    ... roller_radius = 10.0
    ... ''')
    >>> result = camcad.analyse_scene(folder / "cam.toml")
    >>> result.report["models_run"], result.passed
    (['law', 'profile'], True)
    >>> result.report["skipped"]["dynamics"]
    'no [dynamics] in scene'
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> alone = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0))
    >>> import math
    >>> round(result.report["pressure_angle_max_deg"], 9) == round(math.degrees(alone.pressure_angle.maximum.value), 9)
    True
    """
    scene = path if isinstance(path, Scene) else read_scene(path)
    say = progress or (lambda _text: None)
    if not scene.mechanisms:
        raise CamcadError("the scene has no mechanism to make a profile of", str(scene.path),
                          "add [law] and [follower], or [mechanisms.NAME] tables "
                          "(camcad cyclogram runs a bare network)")
    group = bool(scene.mechanisms[0].prefix)
    if scene.cyclogram is not None:  # a broken network is reported before any work is done
        from camcad.scene.cyclogram import parse_cyclogram

        parse_cyclogram(scene.cyclogram, f"{scene.path} [cyclogram]", [m.name for m in scene.mechanisms if m.prefix])
    runs = {}
    memo = LimitMemo()
    # a mechanism the cyclogram will retime needs only its phase limits before the cyclogram; its profile,
    # dynamics and contact are analysed once, with the phase angles it ends up with
    retimable = _network_mechanisms(scene)
    for mech in scene.mechanisms:
        runs[mech.name] = _analyse(scene, mech, mechanism_law(scene, mech), options, say, memo=memo,
                                   only_limits=mech.name in retimable)
    top_skipped: dict[str, str] = {}
    cyclogram_report = None
    if scene.cyclogram is not None:
        say("cyclogram")
        cyclogram_report, retimed = _cyclogram(scene, runs, options)
        from camcad.scene.mechanism import law_with_phases

        for name in retimable:
            mech = scene.mechanism(name)
            base = mechanism_law(scene, mech)
            if name in retimed:
                say(f"{name}: analysing with the cyclogram's phase angles")
                base = replace(base, law=law_with_phases(base.law, retimed[name], mech.where(scene.path, "law")))
            run = _analyse(scene, mech, base, options, say, limits=False, memo=memo,
                           phase_source=("the cyclogram's phase angles" if name in retimed
                                         else "the law's own phase angles (the cyclogram did not retime them)"))
            first = runs[name]
            if "phase_limits" in first.report:
                run.report["phase_limits"] = first.report["phase_limits"]
            elif "phase_limits" in first.skipped:
                run.skipped["phase_limits"] = first.skipped["phase_limits"]
            if name in retimed:
                run.report["retimed_by_cyclogram"] = _phases_text(retimed[name])
            runs[name] = run
    else:
        top_skipped["cyclogram"] = "no [cyclogram] in scene"
    report = _scene_report(scene, runs, group, cyclogram_report, top_skipped)
    return SceneResult(scene, runs, report, group)


# --------------------------------------------------------------------------------------------
# one mechanism: steps 2–8
# --------------------------------------------------------------------------------------------

def _network_mechanisms(scene: Scene) -> list[str]:
    """Names of the mechanisms that the scene's cyclogram has operations of (in scene order)."""
    if scene.cyclogram is None:
        return []
    named = {str(op.get("mechanism")) for op in scene.cyclogram.get("operations", []) if isinstance(op, dict)
             and op.get("mechanism") is not None}
    return [m.name for m in scene.mechanisms if m.name in named]


def _analyse(scene: Scene, mech: Mechanism, built, options: PipelineOptions, say: Progress,
             limits: bool = True, memo: LimitMemo | None = None, only_limits: bool = False,
             phase_source: str = "the law's own phase angles") -> MechanismRun:
    """Steps 2–8 for one mechanism. ``only_limits``: just what its phase limits need (no profile, no
    dynamics), for a mechanism the cyclogram will retime and analyse again."""
    run = MechanismRun(mech.name, law=built.law, memo=memo)
    # checks only: no least phase angles, but for a mechanism the cyclogram retimes (it reuses them: same figures)
    limits = limits and (only_limits or not options.checks_only)
    # ---- [linkage] (camcad.scene.linkage): with [law] law_of = "output" the law becomes the follower's law
    # designed for the working member; dynamics, impact and contact below get the working member through Pi
    from camcad.scene.linkage import prepare as prepare_linkage

    built, run.linkage = prepare_linkage(scene, mech, built)
    run.law = built.law
    # ----
    where = lambda section: mech.where(scene.path, section)  # noqa: E731
    speeds = list(scene.speeds_rpm) if scene.speeds_rpm else None
    run.report["law"] = {"notes": list(built.notes), "phases_deg": [p.as_deg() for p in built.law.phases]}
    run.ran.append("law")
    # 2 balance
    if built.balance is not None:
        run.report["law"]["balance"] = built.balance
        run.ran.append("balance")
        if built.correction is not None:
            run.report["law"]["fixed"] = {"mode": built.correction.mode,
                                          "rms_change": built.correction.rms_change,
                                          "max_change": built.correction.max_change,
                                          "after": built.correction.after.to_dict()}
    else:
        run.skipped["balance"] = "a standard law is balanced by construction"
    # 3 filter
    if mech.has("filter"):
        say(f"{mech.name}: resonance filtering")
        _filter(scene, mech, run, speeds)
    else:
        run.skipped["filter"] = "no [filter] in scene"
    # 4 profile
    if mech.has("follower") and only_limits:
        pass
    elif mech.has("follower"):
        say(f"{mech.name}: profile")
        run.profile = _profile(scene, mech, run.law, options)
        from camcad.profile.summary import profile_report

        run.report["profile"] = profile_report(run.profile, phase_source)
        run.ran.append("profile")
    else:
        run.skipped["profile"] = "no [follower] in scene"
    # 5 dynamics, 6 impact, 7 contact
    for section, step, _needs in (("dynamics", _dynamics, "elastic data"), ("stops", _impact, "stops"),
                                 ("contact", _contact, "materials and loads")):
        key = "impact" if section == "stops" else section
        if not mech.has(section):
            run.skipped[key] = f"no [{section}] in scene"
            continue
        if speeds is None:
            run.skipped[key] = "no [machine] rpm in scene"
            continue
        if section == "contact" and not mech.has("follower"):
            run.skipped[key] = "no [follower] in scene: the contact needs the profile"
            continue
        if section == "dynamics" and only_limits:
            continue
        say(f"{mech.name}: {key}")
        step(scene, mech, run, speeds, options, where(section), limits)
        run.ran.append(key)
    # ---- [linkage]: its analysis, and every setting of [linkage.adjust] through the models above
    if run.linkage is not None and not only_limits:
        from camcad.scene.linkage import linkage_step

        say(f"{mech.name}: linkage")
        linkage_step(scene, mech, run, speeds, options, {"dynamics": _dynamics, "impact": _impact,
                                                         "contact": _contact})
        run.ran.append("linkage")
    # ----
    # 8 phase limits
    if limits:
        found = {}
        if run.impact is not None and run.report["impact"].get("phase_limit_deg") is not None:
            stop_phase = "rise" if run.impact.model.stop == "upper" else "return"
            found[stop_phase] = {"vibration (impact rebound)": run.report["impact"]["phase_limit_deg"]}
        if run.contact is not None:
            for label, angle in run.report["contact"].get("phase_limit_deg", {}).items():
                found.setdefault(label, {})["contact stress"] = angle
        if mech.has("follower"):
            from camcad.scene.mechanism import PRESSURE_SAMPLES, pressure_angle_limits

            for label, angle in pressure_angle_limits(built.law, mech.sections["follower"],
                                                      mech.where(scene.path, "follower"), PRESSURE_SAMPLES,
                                                      memo=memo).items():
                found.setdefault(label, {})["pressure angle"] = angle
        if found:
            run.report["phase_limits"] = {label: {**sources, "least_deg": max(
                (v for v in sources.values() if v is not None), default=None)} for label, sources in found.items()}
        else:
            run.skipped["phase_limits"] = "no [follower], [stops] or [contact] in scene"
    return run


def _filter(scene: Scene, mech: Mechanism, run: MechanismRun, speeds) -> None:
    from camcad.scene.analysis import law_unit, pipeline_angles
    from camcad.scene.filter import filter_step

    unit, _ = law_unit(scene, mech, None, run.law)
    step = filter_step(scene, mech, run.law, speeds, unit, pipeline_angles(scene, mech, run.law).describe())
    if step.report is None:
        run.skipped["filter"] = step.skipped
        return
    run.law = step.law
    run.report["spectrum"] = step.report.analysis_dict()
    run.ran.append("filter")


def _profile(scene: Scene, mech: Mechanism, law, options: PipelineOptions):
    from dataclasses import replace as with_fields

    from camcad.profile.synth import ProfileSettings, synthesize
    from camcad.scene.follower import follower_for_law

    follower, law, _, notes = follower_for_law(mech.sections["follower"], mech.where(scene.path, "follower"), law)
    settings = ProfileSettings(tol_mm=options.tol_mm, arcs=options.arcs, spline=options.spline, r12=options.r12,
                               plots=bool(options.plots), name=mech.name, design=not options.checks_only,
                               checks_only=options.checks_only)
    result = synthesize(law, follower, settings.validate(), name=mech.name)
    return with_fields(result, notes=tuple(notes) + result.notes) if notes else result


def _dynamics(scene, mech, run, speeds, options, where, limits) -> None:
    from camcad.dynamics.runs import run_dynamics
    from camcad.scene.analysis import law_unit, pipeline_angles, rounded_tree
    from camcad.scene.dynamics import parse_dynamics

    settings = parse_dynamics(mech.sections["dynamics"], where, math.degrees(run.law.cycle))
    unit, _ = law_unit(scene, mech, None, run.law)
    if unit in ("mm", "rad"):
        settings = replace(settings, output_unit=unit)
    law = run.law if run.linkage is None else run.linkage.working_law(run.law)  # [linkage]: the working member
    lead = None
    if mech.has("filter"):
        from camcad.scene.filter import parse_filter

        filt = parse_filter(mech.sections["filter"], mech.where(scene.path, "filter"))
        if filt.lead_in_deg is not None and "filter" not in run.ran:
            lead = (filt.lead_in_deg, filt.lead_in_fraction)
    run.dynamics = run_dynamics(law, settings, speeds, lead_in=lead,
                                applies=pipeline_angles(scene, mech, run.law).describe())
    run.report["dynamics"] = rounded_tree(run.dynamics.to_dict())


def _impact(scene, mech, run, speeds, options, where, limits) -> None:
    from camcad.dynamics.runs import run_impact
    from camcad.scene.analysis import pipeline_angles, rounded_tree
    from camcad.scene.stops import parse_stops

    model = parse_stops(mech.sections["stops"], where)
    law = run.law if run.linkage is None else run.linkage.working_law(run.law)  # [linkage]: the working member
    run.impact = run_impact(law, model, speeds, applies=pipeline_angles(scene, mech, run.law).describe())
    run.report["impact"] = rounded_tree(run.impact.to_dict())


def _contact(scene, mech, run, speeds, options, where, limits) -> None:
    from camcad.scene.analysis import pipeline_angles, rounded_tree
    from camcad.scene.contact import contact_step, contact_verdict

    # the retimed pass (limits False) keeps the first pass's least angles in report["phase_limits"]
    extra = None if run.linkage is None else (lambda theta: run.linkage.load_on(run.law, theta))  # [linkage]
    found = contact_step(scene, mech, run.law, speeds, options.contact_samples, pipeline_angles(scene, mech, run.law),
                         None if limits else {}, memo=run.memo, extra_load=extra)
    run.contact = found
    run.report["contact"] = rounded_tree({**found.report, **contact_verdict([found], speeds).to_dict()})


# --------------------------------------------------------------------------------------------
# 9 cyclogram
# --------------------------------------------------------------------------------------------

def _cyclogram(scene: Scene, runs: dict, options: PipelineOptions):
    """Optimise the network with the operations' limits; return (report, {mechanism: new phases})."""
    from camcad.scene.analysis import rounded_tree
    from camcad.scene.cyclogram import cyclogram_verdict
    from camcad.scene.phase_angles import cyclogram_angles

    speeds = list(scene.speeds_rpm) if scene.speeds_rpm else None
    # the impact rebound limit of a mechanism with [stops] bounds the phase that approaches its stop
    impacts = {name: run.impact for name, run in runs.items() if run.impact is not None}
    memo = next(iter(runs.values())).memo if runs else None
    found = cyclogram_angles(scene, speeds, options.contact_samples, impacts=impacts, memo=memo)
    report = rounded_tree({**found.report(), **cyclogram_verdict(found).to_dict()})
    return report, found.phases


def _phases_text(phases) -> str:
    from camcad.cyclogram.retime import format_phases

    return format_phases(phases)


# --------------------------------------------------------------------------------------------
# 10 outputs and the report
# --------------------------------------------------------------------------------------------

def _mechanism_report(run: MechanismRun) -> dict:
    out: dict[str, Any] = {}
    if "profile" in run.report:
        out.update(run.report["profile"])
    for key, value in run.report.items():
        if key != "profile":
            out[key] = value
    out["models_run"] = list(run.ran)
    out["skipped"] = dict(run.skipped)
    checks = {}
    if "profile" in run.report:
        checks["profile"] = bool(run.report["profile"]["passed"])
    for key in ("spectrum", "dynamics", "impact", "contact", "linkage"):
        if key in run.report:
            checks[key] = bool(run.report[key].get("passed", True))
    out["checks_by_model"] = checks
    out["passed"] = all(checks.values())
    return out


def _scene_report(scene: Scene, runs: dict, group: bool, cyclogram_report, top_skipped) -> dict:
    mechanisms = {name: _mechanism_report(run) for name, run in runs.items()}
    passed = all(m["passed"] for m in mechanisms.values())
    if cyclogram_report is not None:
        passed = passed and cyclogram_report["passed"]
    if not group:
        (only,) = mechanisms.values()
        report = {"scene": str(scene.path), "name": scene.name, "description": scene.description, **only}
        report["skipped"] = {**only["skipped"], **top_skipped}
    else:
        report = {"scene": str(scene.path), "name": scene.name, "description": scene.description,
                  "mechanisms": mechanisms, "skipped": dict(top_skipped)}
    if cyclogram_report is not None:
        report["cyclogram"] = cyclogram_report
    report["speeds_rpm"] = list(scene.speeds_rpm) if scene.speeds_rpm else None
    report["passed"] = passed
    return report
