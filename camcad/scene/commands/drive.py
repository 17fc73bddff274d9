"""``camcad drive`` as one library function (``run_drive``): the camshaft
torque and power of every mechanism and of the group on the one shaft, the flywheel for a speed fluctuation,
the motor through its gearbox — each check a figure, a limit and a margin.

The mechanisms are the machine ``camcad profile SCENE`` builds (``camcad.scene.pipeline.analyse_scene``): the
law after its balance, filter and linkage steps and at the cyclogram's phase angles, the profile's geometry,
the [linkage]'s working member reduced to the follower. Each mechanism with a ``[follower]`` and a
``[contact]`` (the follower's mass, spring and preload) drives the shaft with the torque of
``camcad.dynamics.torque`` (its ``[contact]`` load and guide friction, its ``[load]`` process force, pair
friction and gravity when stated); the shaft's torque is their sum at each cam angle. Where a mechanism has
the elastic model (``[dynamics]`` with ``mass_kg``) its elastic torque is also given: its driven mass's force
m ÿ (the elastic acceleration of ``camcad.dynamics.steady``) in place of m s̈.

The ``[drive]`` keys: ``camcad.scene.sections.drive``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

from camcad.arrays import unique
from camcad.dynamics.flywheel import energy_fluctuation, motor_torque
from camcad.dynamics.model import OUTPUT_UNITS
from camcad.dynamics.steady import steady_state
from camcad.dynamics.torque import CamDrive, cycle_figures
from camcad.errors import CamcadError
from camcad.profile.scaled_law import ScaledLaw
from camcad.scene.analysis_report import AnalysisReport
from camcad.scene.commands.source import require_scene
from camcad.scene.fields import parse_speeds
from camcad.scene.file import read_scene
from camcad.scene.laws import law_unit
from camcad.scene.pipeline import PipelineOptions, analyse_scene
from camcad.scene.sections.contact import parse_contact
from camcad.scene.sections.drive import DriveSpec, parse_drive
from camcad.scene.sections.dynamics import parse_dynamics
from camcad.scene.sections.load import gravity_load, parse_load
from camcad.verdict import Check, Verdict, Warning

#: samples per turn of the grid the elastic torque is summed on (the responses are interpolated onto it)
ELASTIC_SAMPLES = 8192
#: a force-closed follower whose least force is within this fraction of its largest is at the point of leaving
#: the cam (the contact check's business: a warning here)
SEPARATION_TOL = 1e-9
#: a speed fluctuation above this (10 %) makes the energy method's constant-speed torque doubtful: warned
DELTA_WARN = 0.1


# --------------------------------------------------------------------------------------------
# The request and the result
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class DriveRequest:
    """What ``camcad drive`` can be asked: the scene, the speeds and the speed fluctuation allowed.

    Parameters
    ----------
    scene : Path
        The scene file (.toml).
    rpm : str or None
        The speeds as ``--rpm`` takes them ("300", "280:420", "280:420:20"), rpm; None: the scene's [machine] rpm.
    delta : float or None
        The coefficient of speed fluctuation allowed, (n_max − n_min)/n_mean (dimensionless); None: the scene's
        [drive] delta.

    Examples
    --------
    >>> DriveRequest("loom.toml", rpm="420", delta=1 / 30).rpm
    '420'
    """
    scene: Path
    rpm: str | None = None
    delta: float | None = None


@dataclass
class MechanismDrive:
    """One mechanism on the shaft: its CamDrive, the law it runs, its elastic data, its cam inertia."""
    name: str
    drive: Any                    # camcad.dynamics.torque.CamDrive
    law: Any
    cam_inertia: float = 0.0
    elastic: Any = None           # (dynamics law, settings, si scale) or None
    notes: list = field(default_factory=list)


@dataclass
class DriveResult:
    """What ``run_drive`` found, for the plots and files: the mechanisms, the speeds (rpm), the governing
    speed, the shaft's torque function per speed, the figures, the energy per speed, the elastic curves."""
    mechanisms: list
    speeds: list
    governing_rpm: float
    figures: dict                 # rpm -> CycleFigures of the shaft
    energy: dict                  # rpm -> EnergyFluctuation
    elastic: dict                 # rpm -> (theta rad, shaft elastic torque N m) or {}
    spec: DriveSpec
    inertia_present: float

    def shaft_torque(self, theta, rpm: float):
        """The shaft's torque (N·m) at ``theta`` (rad) and ``rpm``."""
        return sum((m.drive.components(theta, rpm).total for m in self.mechanisms),
                   np.zeros_like(np.asarray(theta, dtype=float)))

    def components(self, theta, rpm: float) -> dict:
        """{mechanism: TorqueComponents} at ``theta`` (rad) and ``rpm``."""
        return {m.name: m.drive.components(theta, rpm) for m in self.mechanisms}

    def breakpoints(self) -> np.ndarray:
        return unique(np.concatenate([m.drive.breakpoints() for m in self.mechanisms]))


# --------------------------------------------------------------------------------------------
# Building the mechanisms from the pipeline's machine
# --------------------------------------------------------------------------------------------

class _Loads:
    """The sum of a mechanism's loads along the path (N, θ rad → array) with their breakpoints."""
    def __init__(self, parts: list) -> None:
        self.parts = parts

    def __call__(self, theta) -> np.ndarray:
        theta = np.asarray(theta, dtype=float)
        return sum((np.asarray(p(theta), dtype=float) * np.ones_like(theta) for p in self.parts),
                   np.zeros_like(theta))

    def breakpoints(self) -> np.ndarray:
        found = [np.asarray(p.breakpoints(), dtype=float) for p in self.parts if hasattr(p, "breakpoints")]
        return unique(np.concatenate(found)) if found else np.zeros(0)


class _ContactLoad:
    """[contact] load over its range (N), as camcad contact applies it."""
    def __init__(self, params) -> None:
        self.params = params

    def __call__(self, theta) -> np.ndarray:
        return self.params.load_over(theta)

    def breakpoints(self) -> np.ndarray:
        if self.params.load_range_deg is None:
            return np.zeros(0)
        return np.mod(np.radians(np.array(self.params.load_range_deg)), 2.0 * math.pi)


class _LinkageForce:
    """The working member behind a [linkage], reduced to the roller's path: (θ rad, rpm) → N."""
    def __init__(self, context, law) -> None:
        self.context, self.law = context, law

    def __call__(self, theta, rpm: float) -> np.ndarray:
        load = self.context.load_on(self.law, np.asarray(theta, dtype=float))
        return np.zeros_like(np.asarray(theta, dtype=float)) if load is None else load.at(rpm)

    def breakpoints(self) -> np.ndarray:
        span = self.context.spec.values.get("output_load_range_deg")
        return np.zeros(0) if span is None else np.mod(np.radians(np.array(span)), 2.0 * math.pi)


def mechanism_drive(scene, mech, run) -> MechanismDrive:
    """The CamDrive of one mechanism from the pipeline's run (its profile's geometry, its law and linkage)
    and its [contact] and [load] sections."""
    params = parse_contact(mech.sections["contact"], mech.where(scene.path, "contact"))
    cam = run.profile.geometry
    follower = cam.follower
    scale = float(follower.arm) if follower.kind == "oscillating" else 1.0
    notes: list[str] = []
    parts: list = [_ContactLoad(params)] if params.load != 0.0 else []
    pair, cam_inertia = 0.0, 0.0
    if mech.has("load"):
        spec = parse_load(mech.sections["load"], mech.where(scene.path, "load"), scene.base_dir)
        process = spec.on_law(run.law)
        if process is not None:
            parts.append(process)
        notes.extend(spec.notes)
        pair, cam_inertia = spec.pair_friction, spec.cam_inertia
        if spec.gravity_up_deg is not None:
            weight = gravity_load(params.mass, spec.gravity_up_deg, cam)
            parts.append(weight)
            notes.append(f"the follower's weight ({params.mass:g} kg) is counted, up at {spec.gravity_up_deg:g} "
                         "deg in the cam's drawing")
    linkage = _LinkageForce(run.linkage, run.law) if run.linkage is not None else None
    if run.linkage is not None and run.linkage.load_on(run.law, np.zeros(1)) is None:
        linkage = None
    drive = CamDrive(cam, scale, params.mass, params.spring_rate, params.preload, params.friction, pair,
                     params.closure, _Loads(parts) if parts else None, linkage)
    assumed = [a for a in params.assumed if not (a.startswith("load =") and mech.has("load"))]
    if assumed:
        notes.append("[contact]: " + "; ".join(assumed))
    return MechanismDrive(mech.name, drive, run.law, cam_inertia, _elastic_of(scene, mech, run), notes)


def _elastic_of(scene, mech, run):
    """(law, DynamicsSettings, SI per law unit) of the elastic model, or None without [dynamics] mass_kg.

    The driven coordinate: behind a [linkage] the working member's law (as the pipeline's dynamics step); for an
    oscillating follower its swing in rad (the profile's own swing law; J = mass_kg in kg·m²), or the roller's
    arc in mm when [dynamics] output_unit says "mm"; for a translating follower its lift in mm.
    """
    if not mech.has("dynamics"):
        return None

    table = mech.sections["dynamics"]
    settings = parse_dynamics(table, mech.where(scene.path, "dynamics"), math.degrees(run.law.cycle))
    if settings.follower.mass_kg is None:
        return None
    follower = run.profile.follower
    if run.linkage is not None:
        unit, _ = law_unit(scene, mech, None, run.law)
        law, unit = run.linkage.working_law(run.law), (unit if unit in ("mm", "rad") else settings.output_unit)
    elif follower.kind == "oscillating":
        swing = run.profile.geometry.law
        explicit = isinstance(table, dict) and table.get("output_unit") == "mm"
        law, unit = (ScaledLaw(swing, float(follower.arm)), "mm") if explicit else (swing, "rad")
    else:
        law, unit = run.law, "mm"
    settings = replace(settings, output_unit=unit)
    return law, settings, OUTPUT_UNITS[unit].si_scale


def elastic_increment(item: MechanismDrive, rpm: float):
    """(θ rad, ΔT N·m) on the response's grid: the elastic torque minus the rigid one of one mechanism,
    m (ÿ − s̈) y' in SI (the driven mass's force with its elastic acceleration, through its law's velocity)."""
    law, settings, si = item.elastic
    response = steady_state(law, settings.follower, rpm, method=settings.method, samples=settings.samples,
                            solver=settings.solver, rtol=settings.rtol)
    velocity = law.kinematics(response.theta).v
    increment = settings.follower.mass_kg * (response.accel_elastic - response.accel_rigid) * si * velocity * si
    return response.theta, increment, float(law.cycle)


# --------------------------------------------------------------------------------------------
# camcad drive
# --------------------------------------------------------------------------------------------

def run_drive(request: DriveRequest):
    """``camcad drive``: camshaft torque and power, flywheel and motor of a scene, as an AnalysisReport.

    The mechanisms of the scene drive one shaft; the report (key ``drive``) gives the flywheel for a speed
    fluctuation and the motor through its gearbox too. The figures (docs/INTERFACE.md): ``torque_peak_Nm`` (max |T|),
    ``torque_rms_Nm``, ``torque_mean_Nm``, ``power_peak_W``, ``power_mean_W`` of the shaft at the speed of the
    largest peak (``rpm``), the same at every speed (``speeds``) and per mechanism (``mechanisms``), the energy
    swing and the flywheel (``flywheel``), the motor (``motor``), the elastic torque where a mechanism has the
    elastic model (``elastic``).

    Parameters
    ----------
    request : DriveRequest
        The scene (a path), the speeds (the --rpm text, rpm) and δ (dimensionless; None: the scene's).

    Returns
    -------
    camcad.scene.analysis_report.AnalysisReport
        ``body``: the figures (torques N·m, power W, energy J, inertia kg·m², angles deg, speeds rpm),
        ``verdict``: the checks; ``result`` is the DriveResult the plots and torque.csv are made from.

    Raises
    ------
    CamcadError
        No speed, no mechanism with a [follower] and a [contact], or bad input anywhere in the scene.

    Examples
    --------
    A frictionless follower with a spring (m 2 kg, k 5 N/mm, F0 100 N) on a cycloidal cam: no process load, so
    the shaft gets back all it gives (mean torque 0):

    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "cam.toml").write_text('''
    ... [machine]
    ... rpm = 300
    ... [law]
    ... standard = "cycloidal"
    ... phases = "0:90:rise,90:180:dwell,180:270:return,270:360:dwell"
    ... lift = 20.0
    ... [follower]
    ... type = "roller"
    ... base_radius = 40.0
    ... roller_radius = 10.0
    ... [contact]
    ... cam_modulus = 2.1e5
    ... cam_poisson = 0.3
    ... follower_modulus = 2.1e5
    ... follower_poisson = 0.3
    ... width = 10.0
    ... mass = 2.0
    ... spring_rate = 5.0
    ... preload = 100.0
    ... allowable_stress = 1500.0
    ... ''')
    >>> report = run_drive(DriveRequest(folder / "cam.toml"))
    >>> abs(report.body["torque_mean_Nm"]) < 1e-9, round(report.body["torque_peak_Nm"], 3)
    (True, 4.376)
    """
    path = require_scene(Path(request.scene), "drive")
    scene = read_scene(path)
    spec = parse_drive(scene.raw.get("drive"), f"{path} [drive]")
    if request.delta is not None:
        if not 0.0 < request.delta < 1.0:
            raise CamcadError(f"--delta {request.delta:g} is not a speed fluctuation in (0, 1)", "--delta",
                              "give e.g. --delta 0.0333 (1/30)")
        spec = replace(spec, delta=float(request.delta))
    speeds = parse_speeds(request.rpm, "--rpm") if request.rpm is not None else (
        list(scene.speeds_rpm) if scene.speeds_rpm else None)
    if speeds is None:
        raise CamcadError("no speed given", f"{path} [machine]", "add [machine] rpm = ... or pass --rpm")
    pipeline = analyse_scene(scene, PipelineOptions(plots=(), checks_only=True))
    mechanisms, skipped = [], {}
    for mech in scene.mechanisms:
        run = pipeline.runs[mech.name]
        if not mech.has("contact"):
            skipped[mech.name] = "no [contact]: the follower's mass, spring and preload are given there"
        elif run.profile is None:
            skipped[mech.name] = "no [follower]: the torque needs the cam's geometry"
        else:
            mechanisms.append(mechanism_drive(scene, mech, run))
    if not mechanisms:
        raise CamcadError("no mechanism has a [follower] and a [contact]", str(path),
                          "add [contact] with the follower's mass, spring_rate and preload (docs/drive.md)")
    result = DriveResult(mechanisms, [float(s) for s in speeds], float(speeds[0]), {}, {}, {}, spec,
                         _inertia_present(spec, mechanisms))
    bps = result.breakpoints()
    per_mechanism: dict[str, list] = {m.name: [] for m in mechanisms}
    least_force: dict[str, tuple[float, float, float]] = {}
    grid = unique(np.concatenate((np.linspace(0.0, 2.0 * math.pi, 2881), bps)))
    for rpm in result.speeds:
        shaft = partial(_shaft_at, result, rpm)
        result.figures[rpm] = cycle_figures(shaft, bps, rpm)
        result.energy[rpm] = energy_fluctuation(shaft, bps, rpm, result.figures[rpm].mean)
        for item in mechanisms:
            figures = cycle_figures(partial(_total_at, item.drive, rpm), item.drive.breakpoints(), rpm)
            per_mechanism[item.name].append(figures.to_dict())
            if item.drive.closure == "force":
                force = item.drive.components(grid, rpm).axial_force
                k = int(np.argmin(force))
                if item.name not in least_force or force[k] < least_force[item.name][0]:
                    least_force[item.name] = (float(force[k]), float(grid[k]), rpm)
    result.governing_rpm = max(result.speeds, key=lambda n: result.figures[n].peak)
    _elastic(result)
    body = _body(result, per_mechanism)
    verdict = _verdict(result, body, least_force)
    source = {"scene": str(path), "name": scene.name,
              "phase_angles": ("the cyclogram's (as camcad profile uses them)" if scene.cyclogram is not None
                               else "the laws' own"),
              "scene_checks_passed": bool(pipeline.passed)}
    return AnalysisReport("drive", body, verdict, source, result, skipped)


def _shaft_at(result: DriveResult, rpm: float, theta) -> np.ndarray:
    return result.shaft_torque(theta, rpm)


def _total_at(drive, rpm: float, theta) -> np.ndarray:
    return drive.components(theta, rpm).total


def _motor_at(result: DriveResult, rpm: float, ratio: float, efficiency: float, theta) -> np.ndarray:

    return motor_torque(result.shaft_torque(theta, rpm), ratio, efficiency)


def _inertia_present(spec: DriveSpec, mechanisms) -> float:
    """Everything turning with the camshaft, reduced to it (kg·m²): the cams, the shaft's parts, the flywheel
    and the motor's rotor through the gearbox (i² J_m)."""
    return (sum(m.cam_inertia for m in mechanisms) + spec.shaft_inertia + (spec.flywheel_inertia or 0.0)
            + spec.gear_ratio**2 * spec.motor_inertia)


def _elastic(result: DriveResult) -> None:
    """The shaft's elastic torque at every speed on a uniform grid (the rigid torque plus each elastic
    mechanism's increment, interpolated periodically from its response's grid)."""
    elastic = [m for m in result.mechanisms if m.elastic is not None]
    if not elastic:
        return
    theta = 2.0 * math.pi * np.arange(ELASTIC_SAMPLES) / ELASTIC_SAMPLES
    for rpm in result.speeds:
        total = result.shaft_torque(theta, rpm)
        for item in elastic:
            grid, increment, cycle = elastic_increment(item, rpm)
            total = total + np.interp(np.mod(theta, cycle), grid, increment, period=cycle)
        result.elastic[rpm] = (theta, total)


def _figures_on_grid(theta, torque, rpm: float) -> dict:
    """Peak, max, min, RMS and mean of a torque sampled uniformly over one turn (N·m, W)."""
    omega = 2.0 * math.pi * rpm / 60.0
    k, top, low = int(np.argmax(np.abs(torque))), int(np.argmax(torque)), int(np.argmin(torque))
    mean, rms = float(np.mean(torque)), float(np.sqrt(np.mean(torque**2)))
    return {"rpm": rpm, "torque_peak_Nm": float(abs(torque[k])), "torque_peak_at_deg": math.degrees(theta[k]),
            "torque_max_Nm": float(torque[top]), "torque_min_Nm": float(torque[low]), "torque_rms_Nm": rms,
            "torque_mean_Nm": mean, "power_peak_W": float(abs(torque[k])) * omega, "power_mean_W": mean * omega}


def _body(result: DriveResult, per_mechanism: dict) -> dict:

    spec = result.spec
    governing = result.figures[result.governing_rpm].to_dict()
    body: dict[str, Any] = dict(governing)
    body["speeds_rpm"] = list(result.speeds)
    body["speeds"] = [{**result.figures[n].to_dict(), "energy_swing_J": result.energy[n].delta_energy}
                      for n in result.speeds]
    body["mechanisms"] = {m.name: {"per_speed": per_mechanism[m.name],
                                   "closure": m.drive.closure, "cam_inertia_kg_m2": m.cam_inertia,
                                   "elastic_model": m.elastic is not None, "notes": list(m.notes)}
                          for m in result.mechanisms}
    # the flywheel: the energy method at every speed; the worst speed rules the inertia
    swing = {n: result.energy[n] for n in result.speeds}
    flywheel: dict[str, Any] = {"energy_swing_J": {str(n): e.delta_energy for n, e in swing.items()},
                                "inertia_present_kg_m2": result.inertia_present,
                                "inertia_parts_kg_m2": {
                                    "cams": sum(m.cam_inertia for m in result.mechanisms),
                                    "shaft": spec.shaft_inertia, "flywheel": spec.flywheel_inertia or 0.0,
                                    "motor_through_gearbox": spec.gear_ratio**2 * spec.motor_inertia}}
    deltas = {n: e.delta_with(result.inertia_present) for n, e in swing.items()}
    worst_delta = max(result.speeds, key=lambda n: deltas[n])
    flywheel["speed_fluctuation"] = None if not math.isfinite(deltas[worst_delta]) else deltas[worst_delta]
    flywheel["speed_fluctuation_rpm"] = worst_delta
    if spec.delta is not None:
        need = {n: e.inertia_for(spec.delta) for n, e in swing.items()}
        worst = max(result.speeds, key=lambda n: need[n])
        without = result.inertia_present - (spec.flywheel_inertia or 0.0)
        flywheel.update(delta=spec.delta, inertia_required_kg_m2=need[worst], inertia_required_rpm=worst,
                        flywheel_required_kg_m2=max(0.0, need[worst] - without),
                        inertia_required_per_speed_kg_m2={str(n): v for n, v in need.items()})
    body["flywheel"] = flywheel
    body["energy_swing_J"] = swing[result.governing_rpm].delta_energy
    # the motor through the gearbox
    i, eta = spec.gear_ratio, spec.gear_efficiency
    motor: dict[str, Any] = {"regime": spec.motor, "gear_ratio": i, "gear_efficiency": eta,
                             "speed_rpm": max(result.speeds) * i}
    bps = result.breakpoints()
    per_speed = []
    for n in result.speeds:
        shaft = cycle_figures(partial(_motor_at, result, n, i, eta), bps, n)
        mean_motor = float(motor_torque(np.array([result.figures[n].mean]), i, eta)[0])
        per_speed.append({"rpm": n, "motor_rpm": n * i, "torque_peak_Nm": shaft.peak, "torque_rms_Nm": shaft.rms,
                          "torque_mean_Nm": mean_motor})
    motor["per_speed"] = per_speed
    if spec.motor == "servo":
        rms_at = max(per_speed, key=lambda r: r["torque_rms_Nm"])
        peak_at = max(per_speed, key=lambda r: r["torque_peak_Nm"])
        motor.update(torque_rms_Nm=rms_at["torque_rms_Nm"], torque_rms_rpm=rms_at["rpm"],
                     torque_peak_Nm=peak_at["torque_peak_Nm"], torque_peak_rpm=peak_at["rpm"])
    else:
        mean_at = max(per_speed, key=lambda r: abs(r["torque_mean_Nm"]))
        motor.update(torque_rms_Nm=abs(mean_at["torque_mean_Nm"]), torque_rms_rpm=mean_at["rpm"],
                     torque_peak_Nm=abs(mean_at["torque_mean_Nm"]), torque_peak_rpm=mean_at["rpm"])
    if spec.run_up_s is not None:
        fastest = max(result.speeds)
        omega_motor = 2.0 * math.pi * fastest * i / 60.0
        inertia_at_motor = (result.inertia_present - i**2 * spec.motor_inertia) / (i**2 * eta) + spec.motor_inertia
        load = float(motor_torque(np.array([result.figures[fastest].maximum]), i, eta)[0])
        motor["run_up"] = {"time_s": spec.run_up_s, "inertia_at_motor_kg_m2": inertia_at_motor,
                           "accelerating_torque_Nm": inertia_at_motor * omega_motor / spec.run_up_s,
                           "load_torque_Nm": max(load, 0.0),
                           "torque_Nm": inertia_at_motor * omega_motor / spec.run_up_s + max(load, 0.0)}
    body["motor"] = motor
    if result.elastic:
        rows = [_figures_on_grid(theta, torque, n) for n, (theta, torque) in result.elastic.items()]
        worst = max(rows, key=lambda r: r["torque_peak_Nm"])
        body["elastic"] = {**worst, "per_speed": rows,
                           "mechanisms": [m.name for m in result.mechanisms if m.elastic is not None],
                           "note": "the driven mass's force m y'' of the elastic model in place of m s''; the "
                                   "other mechanisms rigid; friction and spring at the rigid positions"}
    return body


def _force_scale(result: DriveResult, name: str) -> list[float]:
    """The largest |force| along one mechanism's path at the extreme speeds (N), the yardstick of round-off."""
    item = next(m for m in result.mechanisms if m.name == name)
    theta = np.linspace(0.0, 2.0 * math.pi, 721)
    return [float(np.max(np.abs(item.drive.components(theta, n).axial_force)))
            for n in (min(result.speeds), max(result.speeds))]


def _span(speeds) -> str:
    return f"{min(speeds):g} rpm" if min(speeds) == max(speeds) else f"{min(speeds):g}-{max(speeds):g} rpm"


def _verdict(result: DriveResult, body: dict, least_force: dict) -> Verdict:
    spec = result.spec
    checks: list[Check] = []
    warnings: list[Warning] = []
    span = _span(result.speeds)
    for name, (force, at, rpm) in least_force.items():
        # the contact's check (camcad contact, profile) rules separation; here it is the torque's premise
        body["mechanisms"][name]["least_force_N"] = {"value": force, "at_deg": math.degrees(at), "rpm": rpm}
        scale = max(abs(f) for f in _force_scale(result, name))
        if force <= SEPARATION_TOL * scale:
            warnings.append(Warning(
                f"{name}: the force holding the follower on the cam falls to {force:.3g} N at "
                f"{math.degrees(at):.4g} deg, {rpm:g} rpm: the torque there assumes contact (camcad contact "
                "checks the separation)", force, "least force along the path <= 1e-9 of its largest"))
    motor = body["motor"]
    regime = ("speed held by the drive: the motor gives the cam's torque as it comes" if spec.motor == "servo"
              else "mains motor on a flywheel: it gives the mean torque")
    if spec.motor_rated_torque is not None:
        what = "RMS" if spec.motor == "servo" else "mean"
        checks.append(Check(f"motor torque, {what} against rated", motor["torque_rms_Nm"], spec.motor_rated_torque,
                            "N m", applies=f"at {motor['torque_rms_rpm']:g} rpm (worst of {span}), gear ratio "
                                           f"{spec.gear_ratio:g}, efficiency {spec.gear_efficiency:g}; {regime}"))
    if spec.motor_peak_torque is not None:
        if spec.motor == "servo":
            checks.append(Check("motor torque, peak against peak", motor["torque_peak_Nm"], spec.motor_peak_torque,
                                "N m", applies=f"at {motor['torque_peak_rpm']:g} rpm (worst of {span}); {regime}"))
        if "run_up" in motor:
            checks.append(Check("motor torque, run-up against peak", motor["run_up"]["torque_Nm"],
                                spec.motor_peak_torque, "N m",
                                applies=f"from rest to {max(result.speeds):g} rpm in {spec.run_up_s:g} s, with the "
                                        "largest load torque at that speed"))
    if spec.motor_max_speed is not None:
        checks.append(Check("motor speed", motor["speed_rpm"], spec.motor_max_speed, "rpm",
                            applies=f"{max(result.speeds):g} rpm x gear ratio {spec.gear_ratio:g}"))
    flywheel = body["flywheel"]
    if spec.delta is not None and spec.motor == "induction":
        value = flywheel["speed_fluctuation"]
        checks.append(Check("speed fluctuation (energy method)", math.inf if value is None else value, spec.delta, "",
                            applies=f"at {flywheel['speed_fluctuation_rpm']:g} rpm (worst of {span}), inertia "
                                    f"{result.inertia_present:.4g} kg m^2 on the camshaft",
                            note=(f"needs {flywheel['inertia_required_kg_m2']:.4g} kg m^2: a flywheel of "
                                  f"{flywheel['flywheel_required_kg_m2']:.4g} kg m^2")))
    value = flywheel["speed_fluctuation"]
    if value is not None and value > DELTA_WARN and spec.motor == "induction":
        warnings.append(Warning(f"speed fluctuation {value:.3g} exceeds {DELTA_WARN:g}: the torque at constant speed "
                                "(the energy method's premise) is doubtful", value, f"delta > {DELTA_WARN:g}"))
    for check in checks:
        if check.passed and check.margin == 0.0:
            warnings.append(Warning(f"{check.name} is at its limit ({check.value:.6g} {check.unit}): no margin",
                                    check.value, "margin 0"))
    for name, item in body["mechanisms"].items():
        if any(r["torque_peak_Nm"] == 0.0 for r in item["per_speed"]):
            warnings.append(Warning(f"{name}: no torque at all (no mass, spring or load)", 0.0, "torque 0"))
    return Verdict(tuple(checks), tuple(warnings))
