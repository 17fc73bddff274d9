"""The scene's [dynamics] section (the elastic follower, stiffness tables, solver settings, limits) and
``camcad dynamics`` as one library function (``run_dynamics_report``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, cast

import numpy as np

from camcad.arrays import unique
from camcad.dynamics.beats import harmonic_beats
from camcad.dynamics.compare import compare_laws
from camcad.dynamics.model import (
    ElasticFollower,
    StiffnessTable,
    damping_ratio_from_psi,
)
from camcad.dynamics.runs import run_dynamics
from camcad.dynamics.steady import DEFAULT_SAMPLES, SOLVERS
from camcad.errors import CamcadError
from camcad.law.source import load_law
from camcad.scene.analysis import require_file
from camcad.scene.fields import Field, read_table
from camcad.scene.law import profile_follower

# --------------------------------------------------------------------------------------------
# The scene's [dynamics] section
# --------------------------------------------------------------------------------------------

DYNAMICS_FIELDS = [
    Field("natural_frequency_hz", "float", "Hz", positive=True,
          help="natural frequency of the follower system (or give mass_kg and stiffness_N_per_m)"),
    Field("mass_kg", "float", "kg", positive=True, help="reduced mass of the follower (kg·m² for rad)"),
    Field("stiffness_N_per_m", "float", "N/m", positive=True, help="reduced stiffness c2 of the driven chain"),
    Field("damping_ratio", "float", "", minimum=0.0, maximum=0.99, help="damping ratio ζ (or give psi)"),
    Field("psi", "float", "", minimum=0.0, maximum=12.0, help="dissipation coefficient ψ = 4πζ"),
    Field("stiffness_variation", "list", "[deg, factor]",
          help="c2(θ)/c2 as [[theta_deg, factor], ...], periodic polyline"),
    Field("output_unit", "str", "", default="mm", choices=("mm", "rad"),
          help="unit of the law's displacement: mm (translating) or rad (oscillating); --unit overrides it"),
    Field("start_pulse_ratio", "float", "", minimum=0.0,
          help="summary dynamic load at the start of motion, × the phase's peak rigid acceleration"),
    Field("flywheel_inertia_kg_m2", "float", "kg·m²", positive=True, help="J0 (multi-mass model)"),
    Field("cam_inertia_kg_m2", "float", "kg·m²", positive=True, help="J1 (multi-mass model)"),
    Field("shaft_stiffness_N_m_per_rad", "float", "N·m/rad", positive=True,
          help="c1 between flywheel and cam (multi-mass model; omit for a rigid shaft)"),
    Field("drive", "str", "", default="speed", choices=("speed", "motor"),
          help="the multi-mass model's drive: speed (the flywheel at the machine's speed) or motor (motor_torque)"),
    Field("motor_torque", "list", "[rpm, N·m]",
          help="the motor's static characteristic M0(n) as [[rpm, torque_Nm], ...] (drive = \"motor\")"),
    Field("harmonic_plot", "int", "", minimum=1, maximum=1024,
          help="draw this harmonic of s and a over the cycle and its beats with the free vibration"),
    Field("allowed_peak_accel_ratio", "float", "", positive=True),
    Field("allowed_dynamic_error_mm", "float", "mm", positive=True),
    Field("allowed_residual_mm", "float", "mm", positive=True),
    Field("method", "str", "", default="auto", choices=("auto", "frequency", "time")),
    Field("solver", "str", "", default="RK45", choices=SOLVERS),
    Field("rtol", "float", "", default=1e-8, positive=True, maximum=0.1),
    Field("samples", "int", "", default=DEFAULT_SAMPLES, minimum=64, maximum=2**22),
]


@dataclass(frozen=True)
class DynamicsSettings:
    """A parsed [dynamics] section: the follower, the checks' limits and the solver knobs."""

    follower: ElasticFollower
    output_unit: str = "mm"
    start_pulse_ratio: float | None = None
    flywheel_inertia: float | None = None
    cam_inertia: float | None = None
    shaft_stiffness: float | None = None
    allowed_peak_accel_ratio: float | None = None
    allowed_dynamic_error_mm: float | None = None
    allowed_residual_mm: float | None = None
    method: str = "auto"
    solver: str = "RK45"
    rtol: float = 1e-8
    samples: int = DEFAULT_SAMPLES
    where: str = "[dynamics]"   # the section in its file, for errors found when the model runs
    motor_torque: tuple[tuple[float, float], ...] | None = None   # (rpm, N·m): drive = "motor"
    harmonic_plot: int | None = None

    @property
    def has_multimass(self) -> bool:
        return self.flywheel_inertia is not None and self.cam_inertia is not None and self.follower.mass_kg is not None


def parse_dynamics(table: Any, where: str, cycle_deg: float = 360.0) -> DynamicsSettings:
    """Read a scene's [dynamics] table (units per key in DYNAMICS_FIELDS) into DynamicsSettings.

    The natural frequency comes from ``natural_frequency_hz`` or from ``mass_kg`` and
    ``stiffness_N_per_m`` (not both); the damping from ``damping_ratio`` or ``psi`` (one of them).
    """
    values = read_table(table, DYNAMICS_FIELDS, where)
    fn, mass, stiffness = values["natural_frequency_hz"], values["mass_kg"], values["stiffness_N_per_m"]
    if fn is not None and stiffness is not None:
        raise CamcadError("both natural_frequency_hz and stiffness_N_per_m given", where,
                          "give one: the frequency, or the mass and the stiffness")
    if fn is None:
        if stiffness is None or mass is None:
            raise CamcadError("missing value 'natural_frequency_hz' (Hz)", where,
                              "add natural_frequency_hz = ..., or mass_kg and stiffness_N_per_m")
        fn = math.sqrt(stiffness / mass) / (2.0 * math.pi)
    zeta, psi = values["damping_ratio"], values["psi"]
    if zeta is not None and psi is not None:
        raise CamcadError("both damping_ratio and psi given", where, "give one of them (psi = 4π·damping_ratio)")
    if zeta is None and psi is None:
        raise CamcadError("missing value 'damping_ratio'", where,
                          "add damping_ratio = 0.05 (or psi = ..., the dissipation coefficient)")
    zeta = damping_ratio_from_psi(psi) if zeta is None else zeta
    if zeta >= 1.0:
        raise CamcadError(f"psi {psi:g} gives a damping ratio {zeta:.3g} >= 1", where, "give psi < 4π")
    variation = None
    if values["stiffness_variation"] is not None:
        variation = _stiffness_table(values["stiffness_variation"], where, cycle_deg)
    follower = ElasticFollower(fn, zeta, mass, variation)
    shaft = values["shaft_stiffness_N_m_per_rad"]
    if (values["flywheel_inertia_kg_m2"] is None) != (values["cam_inertia_kg_m2"] is None) or \
            (shaft is not None and values["flywheel_inertia_kg_m2"] is None):
        raise CamcadError("the multi-mass model needs flywheel_inertia_kg_m2 and cam_inertia_kg_m2 together",
                          where, "give both (and shaft_stiffness_N_m_per_rad for an elastic shaft), or neither")
    if values["flywheel_inertia_kg_m2"] is not None and mass is None:
        raise CamcadError("the multi-mass model needs the driven mass", where, "add mass_kg = ...")
    motor = _motor(values["drive"], values["motor_torque"], where)
    if motor is not None and values["flywheel_inertia_kg_m2"] is None:
        raise CamcadError("a motor drive turns the flywheel of the multi-mass model", where,
                          "give flywheel_inertia_kg_m2 and cam_inertia_kg_m2 (and mass_kg)")
    return DynamicsSettings(follower, values["output_unit"], values["start_pulse_ratio"],
                            values["flywheel_inertia_kg_m2"], values["cam_inertia_kg_m2"], shaft,
                            values["allowed_peak_accel_ratio"], values["allowed_dynamic_error_mm"],
                            values["allowed_residual_mm"], values["method"], values["solver"], values["rtol"],
                            values["samples"], where, motor, values["harmonic_plot"])


def _motor(drive: str, table, where: str) -> tuple[tuple[float, float], ...] | None:
    """The motor characteristic of ``drive = "motor"``: (rpm, N·m) pairs, rpm increasing, torque finite."""
    fix = 'write motor_torque = [[0, 450.0], [400, 320.0], [430, 0.0]] (rpm, N m) with drive = "motor"'
    if drive == "speed":
        if table is not None:
            raise CamcadError("motor_torque is given but drive is \"speed\"", where, 'set drive = "motor"')
        return None
    if table is None:
        raise CamcadError("drive = \"motor\" needs the motor's characteristic", where, fix)
    try:
        pairs = np.asarray(table, dtype=float)
    except (TypeError, ValueError):
        raise CamcadError("motor_torque must be a list of [rpm, N m] pairs", where, fix) from None
    if pairs.ndim != 2 or pairs.shape[1] != 2 or len(pairs) < 2 or not np.isfinite(pairs).all():
        raise CamcadError("motor_torque must be a list of two or more [rpm, N m] pairs", where, fix)
    if np.any(np.diff(pairs[:, 0]) <= 0) or pairs[0, 0] < 0:
        raise CamcadError("motor_torque speeds must start at 0 or more and increase", where, fix)
    return tuple((float(a), float(b)) for a, b in pairs)


def _stiffness_table(raw: list, where: str, cycle_deg: float) -> StiffnessTable:
    fix = "write stiffness_variation = [[0, 1.0], [180, 1.2]] (deg, factor > 0)"
    try:
        pairs = np.asarray(raw, dtype=float)
    except (TypeError, ValueError):
        raise CamcadError("stiffness_variation must be a list of [deg, factor] pairs", where, fix) from None
    if pairs.ndim != 2 or pairs.shape[1] != 2 or len(pairs) < 1 or not np.isfinite(pairs).all():
        raise CamcadError("stiffness_variation must be a list of [deg, factor] pairs", where, fix)
    if np.any(pairs[:, 1] <= 0):
        raise CamcadError("stiffness_variation factors must be positive", where, fix)
    if np.any(pairs[:, 0] < 0) or np.any(pairs[:, 0] >= cycle_deg):
        raise CamcadError(f"stiffness_variation angles must lie in [0, {cycle_deg:g}) deg", where, fix)
    if len(unique(pairs[:, 0])) != len(pairs):
        raise CamcadError("stiffness_variation repeats an angle", where, fix)
    return StiffnessTable.from_degrees(pairs, cycle_deg)


# --------------------------------------------------------------------------------------------
# camcad dynamics
# --------------------------------------------------------------------------------------------

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


def dynamics_settings(request: DynamicsRequest, src) -> DynamicsSettings:
    """The scene's [dynamics] section with the command-line options on top (each option checked as the
    [dynamics] key it overrides: one line naming the option)."""
    from dataclasses import replace

    by_name = {f.name: f for f in DYNAMICS_FIELDS}
    given = {}
    for option, (attribute, name) in _DYNAMICS_OPTIONS.items():
        value = getattr(request, attribute)
        if value is not None:
            given[name] = read_table({name: value}, [by_name[name]], option)[name]
    if src.section("dynamics") is not None:
        settings = parse_dynamics(src.section("dynamics"), src.section_where("dynamics"), math.degrees(src.law.cycle))
    elif src.scene is not None and "natural_frequency_hz" not in given:
        raise CamcadError("the scene has no [dynamics] section", src.where,
                          "add [dynamics] with natural_frequency_hz and damping_ratio, or pass --fn and --zeta")
    else:
        if "natural_frequency_hz" not in given:
            raise CamcadError("no natural frequency given", "command line", "pass --fn HZ (and --zeta Z)")
        if "damping_ratio" not in given and "psi" not in given:
            raise CamcadError("no damping given", "command line",
                              "pass --zeta Z (or --psi, the dissipation coefficient)")
        settings = DynamicsSettings(ElasticFollower(given["natural_frequency_hz"], 0.0))
    if "damping_ratio" in given and "psi" in given:
        raise CamcadError("both --zeta and --psi given", "command line", "give one of them")
    follower = settings.follower
    if "damping_ratio" in given:
        damping = given["damping_ratio"]
    elif "psi" in given:
        damping = damping_ratio_from_psi(given["psi"])
        if damping >= 1.0:
            raise CamcadError(f"--psi {given['psi']:g} gives a damping ratio {damping:.3g} >= 1", "--psi",
                              "give psi < 4 pi")
    else:
        damping = follower.damping_ratio
    follower = ElasticFollower(given.get("natural_frequency_hz", follower.natural_frequency_hz), damping,
                               given.get("mass_kg", follower.mass_kg), follower.stiffness)
    overrides: dict[str, Any] = {"follower": follower}
    for name, attribute in (("method", "method"), ("solver", "solver"), ("rtol", "rtol"), ("samples", "samples"),
                            ("start_pulse_ratio", "start_pulse_ratio"),
                            ("allowed_peak_accel_ratio", "allowed_peak_accel_ratio"),
                            ("allowed_dynamic_error_mm", "allowed_dynamic_error_mm"),
                            ("allowed_residual_mm", "allowed_residual_mm")):
        if name in given:
            overrides[attribute] = given[name]
    if src.unit in ("mm", "rad"):
        overrides["output_unit"] = src.unit
    else:
        raise CamcadError(f"the dynamics works on a law in mm or rad, not {src.unit}", "--unit",
                          "give the law in rad of swing (--unit rad with a law in rad)")
    settings = replace(settings, **overrides)
    if settings.samples % 2:
        raise CamcadError(f"--samples {settings.samples} must be an even number >= 64", "--samples", "give e.g. 4096")
    if settings.method == "frequency" and not follower.constant_stiffness:
        raise CamcadError("the frequency-domain path needs a constant stiffness", src.where,
                          "use --method time (or auto) with a stiffness_variation")
    return settings


def lead_in_request(option: str | None, src) -> tuple[float, float] | None:
    """(angle deg, fraction) from --lead-in DEG[:FRACTION], else from the scene's [filter] lead-in, else None."""
    if option is not None:
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
    table = src.section("filter")
    if isinstance(table, dict) and "lead_in_deg" in table:
        from camcad.scene.filter import parse_filter

        settings = parse_filter(table, src.section_where("filter"))
        return cast(float, settings.lead_in_deg), settings.lead_in_fraction  # the table states lead_in_deg
    return None


def analysis_law(src, speeds) -> tuple[Any, list[str], Any]:
    """The law the pipeline's steps 5–7 analyse for a scene's mechanism: after its [filter] step (as
    ``camcad profile`` does); a law file's own law. Returns (law, notes, FilterStep or None)."""
    if src.scene is None or src.mechanism is None or not src.mechanism.has("filter"):
        return src.law, [], None
    from camcad.scene.filter import filter_step

    step = filter_step(src.scene, src.mechanism, src.law, speeds, src.unit)
    if step.report is None:
        return src.law, [f"[filter] not applied: {step.skipped}"], step
    return step.law, ["the scene's [filter] was applied first, as camcad profile does (its law is analysed)"], step


def run_dynamics_report(request: DynamicsRequest, source=None, progress=None):
    """``camcad dynamics``: the elastic follower over the speeds, as an AnalysisReport (key ``dynamics``)
    whose ``result`` is the camcad.dynamics.runs.DynamicsRun.

    Parameters
    ----------
    request : DynamicsRequest
    source : AnalysisSource or None
        The law already resolved (default: ``resolve_source(request.law)``).
    progress : callable or None
        ``progress(done, total)`` after each speed.

    Returns
    -------
    camcad.scene.analysis.AnalysisReport
    """
    from camcad.scene.analysis import AnalysisReport, resolve_source

    src = source if source is not None else resolve_source(request.law, command="dynamics")
    speeds = src.require_speeds("dynamics")
    settings = dynamics_settings(request, src)
    law, notes, step = analysis_law(src, speeds)
    lead = lead_in_request(request.lead_in, src) if step is None or step.report is None else None
    applies = src.angles.describe() if src.angles is not None else ""
    run = run_dynamics(law, settings, speeds, progress=progress, lead_in=lead, applies=applies)
    if request.compare is not None and "start_load" in run.report:
        run.report["compare"] = compared_with(law, run, request.compare, src, settings, speeds)
    harmonic = request.harmonic if request.harmonic is not None else settings.harmonic_plot
    if harmonic is not None:
        run = replace(run, beats=harmonic_beats(law, settings.follower, max(float(v) for v in speeds), harmonic))
        run.report["harmonic"] = beats_summary(run.beats, settings)
    summary = src.summary()
    summary["notes"] = list(src.notes) + notes
    return AnalysisReport("dynamics", run.report, run.verdict, summary, run)


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


def compared_with(law, run, path, src, settings, speeds) -> dict:
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

