"""The scene pipeline: what `camcad profile SCENE.toml` runs, in docs/INTERFACE.md's order: what the scene asks for.

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

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from camcad.cyclogram.retime import format_phases
from camcad.errors import CamcadError
from camcad.law.segments import SegmentLaw
from camcad.profile.summary import profile_report
from camcad.profile.synth import ProfileSettings, synthesize
from camcad.scene.file import Mechanism, Scene, read_scene
from camcad.scene.follower import follower_for_law
from camcad.scene.laws import law_unit, law_with_phases, mechanism_law, pipeline_angles
from camcad.scene.mechanism import PRESSURE_SAMPLES, LimitMemo, geometry_limits
from camcad.scene.sections.cyclogram import parse_cyclogram

if TYPE_CHECKING:
    from camcad.scene.phase_angles import CyclogramAngles

#: the models a run may be restricted to (``PipelineOptions.models``), in the pipeline's order
MODELS = ("filter", "profile", "dynamics", "impact", "contact", "linkage")

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
    models : tuple of str or None
        The model steps of the analysis pass (names in ``MODELS``; no unit); None: every one the scene has.
        The steps that decide the phase angles (the limits before a cyclogram) run as for ``camcad profile``.
    mechanisms : tuple of str or None
        The mechanisms to analyse (None: all); the others take part only in the cyclogram's limits.
    use_cyclogram : bool
        False: the laws' own phase angles even in a scene with a [cyclogram] (no unit).
    dynamics_extras : DynamicsExtras or None
        What ``camcad dynamics`` adds to the dynamics step (a lead-in in deg, a second law, a progress callback).
    impact_progress : callable or None
        ``camcad impact``'s ``progress(done, total)`` callback (counts).
    impact_study : bool
        With ``[stops.published]``, also study the rebound's speed dependence against the published figures.
    servo : camcad.profile.servo.ServoExport or None
        Write each mechanism's servo (electronic cam) table (``--export servo``); None: not.
    polydyne_rpm : float or None
        Design every mechanism with [dynamics] as a polydyne cam for this speed, rpm (``--polydyne``); None: the
        scene's ``[dynamics] polydyne_rpm``.
    export : dict, optional
        The part's files and units given on the command line (``camcad.scene.sections.export.ExportSettings`` field
        names → values; lengths mm, feed mm/min), put over each mechanism's [export] section.
    animate : tuple of str
        Write each mechanism's animation (``camcad.report.animation``) in these formats: "html"
        (animation.html), "gif", "mp4"; () none.
    animate_step_deg : float
        Cam angle between the animation's frames, deg (must divide 360).
    report : tuple of str
        Write the design's report: "html" (report.html), "pdf" (also report.pdf, printed by headless
        Chromium); () none.
    command : str
        The command that ran, for the report's "how to reproduce it" (no unit); "" when called from Python.

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
    #: the model steps of the analysis pass (names in ``MODELS``); None: every one the scene has. The steps that
    #: decide the phase angles (the limits before a cyclogram) run as for ``camcad profile``, so a stand-alone
    #: command analyses the same machine
    models: tuple[str, ...] | None = None
    #: the mechanisms to analyse (None: all); the others take part only in the cyclogram's limits
    mechanisms: tuple[str, ...] | None = None
    #: False: the laws' own phase angles even in a scene with a [cyclogram] (``--phase-angles law``)
    use_cyclogram: bool = True
    #: what ``camcad dynamics`` adds to the dynamics step: a lead-in to compare, a second law, a progress callback
    dynamics_extras: DynamicsExtras | None = None
    #: ``camcad impact``'s progress callback ``progress(done, total)``
    impact_progress: Callable[[int, int], None] | None = None
    #: ``camcad impact``: with [stops.published], also study the rebound's speed dependence against them
    impact_study: bool = False
    #: ``--export servo``: the servo table settings (camcad.profile.servo.ServoExport) or None
    servo: Any = None
    #: ``--polydyne RPM``: the design speed of a polydyne cam (overrides [dynamics] polydyne_rpm), rpm
    polydyne_rpm: float | None = None
    #: the part's files and units given on the command line (``ExportSettings`` field names → values), or None
    export: dict | None = None
    #: ``--animate``: animation formats ("html", "gif", "mp4"); () none
    animate: tuple[str, ...] = ()
    #: ``--animate-step``: cam angle between frames, deg
    animate_step_deg: float = 1.0
    #: ``--report``: "html" (report.html) and "pdf" (report.pdf); () none
    report: tuple[str, ...] = ()
    #: the command that ran (the report says how to reproduce it); "" from Python
    command: str = ""

    def runs(self, model: str) -> bool:
        """Whether the analysis pass runs ``model`` (one of ``MODELS``)."""
        return self.models is None or model in self.models


@dataclass(frozen=True)
class DynamicsExtras:
    """What ``camcad dynamics`` asks of the dynamics step beyond the scene: a lead-in (deg, fraction of the
    peak acceleration) to compare, a second law (and its name) whose start-of-motion load is compared, and a
    ``progress(done, total)`` callback."""

    lead_in: tuple[float, float] | None = None
    compare: Any = None
    compare_name: str = ""
    progress: Callable[[int, int], None] | None = None


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
    unit: str = "mm"        # unit of the [law]'s displacement (mm, rad or deg)
    unit_why: str = ""      # how the unit was decided (camcad.scene.laws.law_unit)
    given_law: Any = None   # the [law]'s law at the phase angles analysed, before the filter and the linkage
    output_law: Any = None  # the same after the filter: with law_of = "output", the working member's law
    #: the contact-limited least phase angles when they come from the cyclogram ({} none), None: found by the step
    contact_least: dict | None = None


@dataclass(frozen=True)
class SceneResult:
    """What the pipeline found: the scene, every mechanism's run, the report (docs/INTERFACE.md keys; no outputs
    yet)."""

    scene: Scene
    runs: dict
    report: dict
    group: bool
    cyclogram: CyclogramAngles | None = None    # the optimised cyclogram (step 9), when it ran

    @property
    def passed(self) -> bool:
        return bool(self.report["passed"])


Progress = Callable[[str], None]


def analyse_scene(path: str | Path | Scene, options: PipelineOptions = PipelineOptions(),
                  progress: Progress | None = None, *, angles=None) -> SceneResult:
    """Run the scene pipeline's analyses (steps 1–9) and return what they found, writing nothing.

    For every mechanism: read the law, check (and fix) its balance, resonance filtering, profile
    synthesis, elastic dynamics, stop impact, contact stress and the least phase angles they allow; then
    the cyclogram, whose phase angles go back into the laws (module docstring; docs/INTERFACE.md "The scene
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
    angles : camcad.scene.phase_angles.CyclogramAngles, optional
        The group's phase angles already decided elsewhere (a machine of groups, ``camcad.scene.machine``):
        step 9 uses them instead of optimising the scene's [cyclogram] on its own.

    Returns
    -------
    SceneResult
        ``report``: the docs/INTERFACE.md keys (angles deg, lengths mm, speeds rpm, forces N, stresses MPa),
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
        parse_cyclogram(scene.cyclogram, f"{scene.path} [cyclogram]", [m.name for m in scene.mechanisms if m.prefix])
    runs: dict[str, MechanismRun] = {}
    memo = LimitMemo()
    wanted = set(options.mechanisms) if options.mechanisms is not None else None
    for name in wanted or ():
        scene.mechanism(name)  # an unknown name: one line listing the scene's mechanisms
    use_cyclogram = scene.cyclogram is not None and options.use_cyclogram
    # a mechanism the cyclogram will retime needs only its phase limits before the cyclogram; its profile,
    # dynamics and contact are analysed once, with the phase angles it ends up with
    retimable = _network_mechanisms(scene) if use_cyclogram else []
    for mech in scene.mechanisms:
        if mech.name in retimable:
            runs[mech.name] = _analyse(scene, mech, mechanism_law(scene, mech), options, say, memo, stage="limits")
        elif wanted is None or mech.name in wanted:
            runs[mech.name] = _analyse(scene, mech, mechanism_law(scene, mech), options, say, memo, stage="single")
    top_skipped: dict[str, str] = {}
    cyclogram_report = found = None
    if use_cyclogram:
        say("cyclogram")
        cyclogram_report, found = _models().cyclogram_step(scene, runs, options, angles)
        retimed = found.phases
        for name in retimable:
            if wanted is not None and name not in wanted:
                del runs[name]
                continue
            mech = scene.mechanism(name)
            base = mechanism_law(scene, mech)
            if name in retimed:
                say(f"{name}: analysing with the cyclogram's phase angles")
                base = replace(base, law=law_with_phases(base.law, retimed[name], mech.where(scene.path, "law")))
            run = _analyse(scene, mech, base, options, say, memo, stage="final",
                           phase_source=("the cyclogram's phase angles" if name in retimed
                                         else "the law's own phase angles (the cyclogram did not retime them)"),
                           contact_least=found.contact_least(name))
            first = runs[name]
            if "phase_limits" in first.report:
                run.report["phase_limits"] = first.report["phase_limits"]
            elif "phase_limits" in first.skipped:
                run.skipped["phase_limits"] = first.skipped["phase_limits"]
            if name in retimed:
                run.report["retimed_by_cyclogram"] = format_phases(retimed[name])
            runs[name] = run
    elif scene.cyclogram is not None:
        top_skipped["cyclogram"] = "the laws' own phase angles were asked for (--phase-angles law)"
    else:
        top_skipped["cyclogram"] = "no [cyclogram] in scene"
    report = _scene_report(scene, runs, group, cyclogram_report, top_skipped)
    return SceneResult(scene, runs, report, group, found)


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


def _analyse(scene: Scene, mech: Mechanism, built, options: PipelineOptions, say: Progress, memo: LimitMemo,
             stage: str, phase_source: str = "the law's own phase angles",
             contact_least: dict | None = None) -> MechanismRun:
    """Steps 2–8 for one mechanism. ``stage``: "single" (a mechanism the cyclogram does not retime: every step
    the options ask for, its least phase angles included unless ``checks_only``), "limits" (a mechanism the
    cyclogram will retime: only what its phase limits need) or "final" (its analysis at the cyclogram's
    phase angles, whose contact-limited least angles are ``contact_least``)."""
    run = MechanismRun(mech.name, law=built.law, memo=memo)
    only_limits = stage == "limits"
    # least phase angles (step 8): before a cyclogram, and for a whole profile run (not for sweeps' checks, not
    # for a stand-alone command, which reports its model only)
    limits = only_limits or (stage == "single" and not options.checks_only and options.models is None)
    run.contact_least = None if only_limits or (stage == "single" and not options.checks_only) else \
        dict(contact_least or {})
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
        run.skipped["balance"] = ("a law designed from segments meets its end values by construction"
                                  if isinstance(built.law, SegmentLaw) else
                                  "a standard law is balanced by construction")
    # 3 filter: on the law as the [law] gives it (the working member's with law_of = "output"), before the linkage
    # turns it into the follower's
    run.unit, run.unit_why = law_unit(scene, mech, None, built.law)
    run.given_law = built.law
    if mech.has("filter"):
        say(f"{mech.name}: resonance filtering")
        step = _models().filter_step(scene, mech, built.law, speeds, run.unit,
                           pipeline_angles(scene, mech, built.law).describe())
        if step.report is None:
            run.skipped["filter"] = step.skipped
        else:
            built = replace(built, law=step.law)
            run.report["spectrum"] = step.report.analysis_dict()
            run.ran.append("filter")
    else:
        run.skipped["filter"] = "no [filter] in scene"
    run.output_law = built.law
    # ---- [linkage] (camcad.scene.linkage): with [law] law_of = "output" the law becomes the follower's law
    # designed for the working member; dynamics, impact and contact below get the working member through Pi
    if mech.has("linkage") or (mech.sections.get("law") or {}).get("law_of") == "output":
        built, run.linkage = _models().prepare(scene, mech, built)
    run.law = built.law
    # ---- polydyne (camcad.scene.polydyne): the cam for the elastic follower at a design speed
    dynamics_table = mech.sections.get("dynamics")
    design = options.polydyne_rpm if options.polydyne_rpm is not None else (
        dynamics_table.get("polydyne_rpm") if isinstance(dynamics_table, dict) else None)
    if design is not None:
        say(f"{mech.name}: polydyne cam for {design:g} rpm")
        _models().polydyne_step(scene, mech, run, speeds, design)
    # ----
    # ----
    # 4 profile
    if mech.has("follower") and (only_limits or not options.runs("profile")):
        pass
    elif mech.has("follower"):
        say(f"{mech.name}: profile")
        run.profile = _profile(scene, mech, run.law, options)
        run.report["profile"] = profile_report(run.profile, phase_source)
        run.ran.append("profile")
    else:
        run.skipped["profile"] = "no [follower] in scene"
    # 5 dynamics, 6 impact, 7 contact
    for section, step_name in (("dynamics", "dynamics_step"), ("stops", "impact_step"), ("contact", "contact_step_of")):
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
        if (section == "dynamics" and only_limits) or (not only_limits and not options.runs(key)):
            continue
        say(f"{mech.name}: {key}")
        getattr(_models(), step_name)(scene, mech, run, speeds, options, where(section), run.contact_least is None)
        run.ran.append(key)
    # ---- [linkage]: its analysis, and every setting of [linkage.adjust] through the models above
    if run.linkage is not None and not only_limits and options.runs("linkage"):
        say(f"{mech.name}: linkage")
        models = _models()
        models.linkage_step(scene, mech, run, speeds, options, {"dynamics": models.dynamics_step,
                                                                "impact": models.impact_step,
                                                                "contact": models.contact_step_of})
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
            geometry, geometry_notes = geometry_limits(built.law, mech.sections["follower"],
                                                       mech.where(scene.path, "follower"), PRESSURE_SAMPLES, memo=memo)
            for label, sources in geometry.items():
                found.setdefault(label, {}).update(sources)
            if geometry_notes:
                run.report["phase_limit_notes"] = geometry_notes
        if found:
            run.report["phase_limits"] = {label: {**sources, "least_deg": max(
                (v for v in sources.values() if v is not None), default=None)} for label, sources in found.items()}
        else:
            run.skipped["phase_limits"] = "no [follower], [stops] or [contact] in scene"
    return run


def _models():
    """``camcad.scene.models``, imported when a scene has a model (a start-up case of tests/project/test_layering.py:
    ``camcad profile`` of a plain cam imports no model, tests/project/test_startup.py)."""
    from camcad.scene import models

    return models


def _profile(scene: Scene, mech: Mechanism, law, options: PipelineOptions):
    follower, law, _, notes = follower_for_law(mech.sections["follower"], mech.where(scene.path, "follower"), law)
    settings = ProfileSettings(tol_mm=options.tol_mm, arcs=options.arcs, spline=options.spline, r12=options.r12,
                               plots=bool(options.plots), name=mech.name, design=not options.checks_only,
                               checks_only=options.checks_only)
    result = synthesize(law, follower, settings.validate(), name=mech.name)
    return replace(result, notes=tuple(notes) + result.notes) if notes else result


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
    if not group and len(mechanisms) == 1:
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
