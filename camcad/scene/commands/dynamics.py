"""``camcad dynamics`` as one library function (``run_dynamics_report``): the elastic follower over a speed
range, on the law ``camcad profile`` analyses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

from camcad.dynamics.beats import harmonic_beats
from camcad.dynamics.compare import compare_laws
from camcad.dynamics.model import ElasticFollower, damping_ratio_from_psi
from camcad.dynamics.runs import run_dynamics
from camcad.errors import CamcadError
from camcad.law.source import load_law
from camcad.scene.analysis_report import AnalysisReport
from camcad.scene.commands.source import AnalysisSource, require_file, resolve_source
from camcad.scene.fields import read_table
from camcad.scene.pipeline import DynamicsExtras
from camcad.scene.sections.dynamics import DYNAMICS_FIELDS, DynamicsSettings, check_settings
from camcad.scene.sections.follower import profile_follower


@dataclass(frozen=True)
class DynamicsRequest:
    """Everything ``camcad dynamics`` can be asked (None: the scene's [dynamics] value, else the default)."""

    law: Any
    fn: float | None = None
    zeta: float | None = None
    psi: float | None = None
    mass: float | None = None
    method: str | None = None
    solver: str | None = None
    rtol: float | None = None
    samples: int | None = None
    start_pulse: float | None = None
    compare: Any = None
    lead_in: str | None = None
    max_ratio: float | None = None
    max_error: float | None = None
    max_residual: float | None = None
    harmonic: int | None = None


#: command-line option → [dynamics] field (validated by the field's type and range)
_DYNAMICS_OPTIONS = {"--fn": ("fn", "natural_frequency_hz"), "--zeta": ("zeta", "damping_ratio"),
                     "--psi": ("psi", "psi"), "--mass": ("mass", "mass_kg"), "--method": ("method", "method"),
                     "--solver": ("solver", "solver"), "--rtol": ("rtol", "rtol"), "--samples": ("samples", "samples"),
                     "--start-pulse": ("start_pulse", "start_pulse_ratio"),
                     "--max-ratio": ("max_ratio", "allowed_peak_accel_ratio"),
                     "--max-error": ("max_error", "allowed_dynamic_error_mm"),
                     "--max-residual": ("max_residual", "allowed_residual_mm")}


def option_values(request: DynamicsRequest) -> dict:
    """{[dynamics] key: value} of the options given, each checked as the key it stands for (one line naming the
    option)."""
    by_name = {f.name: f for f in DYNAMICS_FIELDS}
    given = {}
    for option, (attribute, name) in _DYNAMICS_OPTIONS.items():
        value = getattr(request, attribute)
        if value is not None:
            given[name] = read_table({name: value}, [by_name[name]], option)[name]
    if "damping_ratio" in given and "psi" in given:
        raise CamcadError("both --zeta and --psi given", "command line", "give one of them")
    if "psi" in given and damping_ratio_from_psi(given["psi"]) >= 1.0:
        raise CamcadError(f"--psi {given['psi']:g} gives a damping ratio {damping_ratio_from_psi(given['psi']):.3g}"
                          " >= 1", "--psi", "give psi < 4 pi")
    return given


def file_settings(given: dict, unit: str) -> DynamicsSettings:
    """The elastic follower of a law file: from the options alone (``option_values``)."""
    if "natural_frequency_hz" not in given:
        raise CamcadError("no natural frequency given", "command line", "pass --fn HZ (and --zeta Z)")
    if "damping_ratio" not in given and "psi" not in given:
        raise CamcadError("no damping given", "command line", "pass --zeta Z (or --psi, the dissipation coefficient)")
    damping = given["damping_ratio"] if "damping_ratio" in given else damping_ratio_from_psi(given["psi"])
    follower = ElasticFollower(given["natural_frequency_hz"], damping, given.get("mass_kg"))
    if unit not in ("mm", "rad"):
        raise CamcadError(f"the dynamics works on a law in mm or rad, not {unit}", "--unit",
                          "give the law in rad of swing (--unit rad with a law in rad)")
    settings = DynamicsSettings(follower, unit)
    overrides = {attribute: given[name] for name, attribute in (
        ("method", "method"), ("solver", "solver"), ("rtol", "rtol"), ("samples", "samples"),
        ("start_pulse_ratio", "start_pulse_ratio"), ("allowed_peak_accel_ratio", "allowed_peak_accel_ratio"),
        ("allowed_dynamic_error_mm", "allowed_dynamic_error_mm"), ("allowed_residual_mm", "allowed_residual_mm"))
        if name in given}
    return check_settings(replace(settings, **overrides), "command line")


def scene_overrides(src: AnalysisSource, given: dict) -> AnalysisSource:
    """The scene with the options written into its [dynamics] (a damping or frequency given replaces the
    scene's other way of stating it); a scene without [dynamics] needs --fn and --zeta (or --psi)."""
    if src.section("dynamics") is None and ("natural_frequency_hz" not in given or
                                            not ({"damping_ratio", "psi"} & set(given))):
        raise CamcadError("the scene has no [dynamics] section", src.where,
                          "add [dynamics] with natural_frequency_hz and damping_ratio, or pass --fn and --zeta")
    drop = tuple(key for key, given_key in (("psi", "damping_ratio"), ("damping_ratio", "psi"),
                                           ("stiffness_N_per_m", "natural_frequency_hz")) if given_key in given)
    return src.with_overrides("dynamics", given, drop)


def lead_in_option(option: str | None) -> tuple[float, float] | None:
    """(angle deg, fraction) from --lead-in DEG[:FRACTION], or None."""
    if option is None:
        return None
    parts = option.split(":")
    try:
        if len(parts) not in (1, 2):
            raise ValueError
        angle = float(parts[0])
        fraction = float(parts[1]) if len(parts) == 2 else 0.1
    except ValueError:
        raise CamcadError(f"--lead-in {option!r} is not DEG or DEG:FRACTION", "--lead-in",
                          "write --lead-in 14 or --lead-in 14:0.1") from None
    if not (math.isfinite(angle) and 0 < angle <= 180 and math.isfinite(fraction) and 0 < fraction <= 1):
        raise CamcadError(f"--lead-in {option!r} needs 0 < DEG <= 180 and 0 < FRACTION <= 1", "--lead-in",
                          "write --lead-in 14:0.1")
    return angle, fraction


def run_dynamics_report(request: DynamicsRequest, source: AnalysisSource | None = None, progress=None):
    """``camcad dynamics``: the elastic follower over the speeds, as an AnalysisReport (key ``dynamics``)
    whose ``result`` is the camcad.dynamics.runs.DynamicsRun.

    A scene's mechanism is analysed as ``camcad profile`` analyses it (the pipeline's dynamics step on its
    machine: the [filter]ed law, the working member behind a [linkage], the cyclogram's phase angles, the law's
    unit), with the options written into its [dynamics]; a law file with the options alone.

    Parameters
    ----------
    request : DynamicsRequest
    source : AnalysisSource or None
        The law already resolved (default: ``resolve_source(request.law)``).
    progress : callable or None
        ``progress(done, total)`` after each speed.

    Returns
    -------
    camcad.scene.analysis_report.AnalysisReport
    """
    src = source if source is not None else resolve_source(request.law, command="dynamics")
    speeds = src.require_speeds("dynamics")
    given = option_values(request)
    lead = lead_in_option(request.lead_in)
    if src.scene is not None and src.mechanism is not None:
        src = scene_overrides(src, given)
        found = src.machine(("dynamics",), dynamics_extras=DynamicsExtras(lead, progress=progress)).dynamics
        if found is None:
            raise CamcadError("the dynamics did not run", src.where, "give the scene a [machine] rpm or pass --rpm")
        run = found
    else:
        settings = file_settings(given, src.unit)
        applies = src.angles.describe() if src.angles is not None else ""
        run = run_dynamics(src.law, settings, speeds, progress=progress, lead_in=lead, applies=applies)
    law, settings = src.law, run.settings
    if request.compare is not None and "start_load" in run.report:
        run.report["compare"] = compared_with(law, run, request.compare, src, settings, speeds)
    harmonic = request.harmonic if request.harmonic is not None else settings.harmonic_plot
    if harmonic is not None:
        run = replace(run, beats=harmonic_beats(law, settings.follower, max(float(v) for v in speeds), harmonic))
        run.report["harmonic"] = beats_summary(run.beats, settings)
    return AnalysisReport("dynamics", run.report, run.verdict, src.summary(), run)


def beats_summary(beats, settings) -> dict:
    """The figures of one harmonic and its beats with the free vibration (``camcad.dynamics.beats``)."""
    unit = settings.output_unit
    out = {"k": beats.k, "rpm": beats.rpm, f"amplitude_{unit}": beats.amplitude, "phase_deg": beats.phase_deg,
           "forced_hz": beats.forced_hz, "free_hz": beats.free_hz, "beat_period_s": beats.beat_period_s,
           "beat_period_deg": beats.beat_deg, f"steady_amplitude_{unit}": beats.steady_amplitude,
           "free_vibration_decay_s": beats.decay_s}
    if not settings.follower.constant_stiffness:
        out["note"] = "drawn with the nominal stiffness (the stiffness variation is left out of this plot)"
    return out


def compared_with(law, run, path, src: AnalysisSource, settings, speeds) -> dict:
    """``dynamics --compare LAW``: ``camcad compare``'s kernel on this law (A) and the one named (B), read as
    ``camcad compare`` reads it (its recorded phases, the scene's [follower] for a radius table), with the
    start-of-motion loads of B and this law's over B's (``reduction``) phase by phase."""
    follower = None
    if src.section("follower") is not None:
        follower = profile_follower(src.section("follower"), src.section_where("follower"))
    loaded = load_law(require_file(path, "law file"), cycle_deg=math.degrees(law.cycle), follower=follower)
    other = run_dynamics(loaded.law, settings, speeds)
    comparison = compare_laws(law, loaded.law, speeds, settings=settings, unit=settings.output_unit,
                              runs=(run, other))
    fastest = max(float(s) for s in speeds)
    pairs = [f for f in comparison.figures if f.name == "start_load"]
    return {"law": str(path), "rpm": fastest, "phases_read": [p.as_deg() for p in loaded.law.phases],
            "notes": [loaded.source, *loaded.notes],
            "phases": other.report.get("start_load", {}).get("phases", []),
            "reduction": [f.ratio for f in pairs], "side_by_side": comparison.to_dict()}
