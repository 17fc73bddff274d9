"""The scene's ``[dynamics]`` section: the elastic follower, stiffness tables, solver settings, limits."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from camcad.arrays import unique
from camcad.dynamics.model import (
    ElasticFollower,
    StiffnessTable,
    damping_ratio_from_psi,
)
from camcad.dynamics.steady import DEFAULT_SAMPLES, SOLVERS
from camcad.errors import CamcadError
from camcad.scene.fields import Field, read_table

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
    Field("polydyne_rpm", "float", "rpm", positive=True,
          help="design the cam for this speed so the elastic follower does the law (polydyne; camcad.scene.polydyne)"),
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
    return check_settings(DynamicsSettings(
        follower, values["output_unit"], values["start_pulse_ratio"], values["flywheel_inertia_kg_m2"],
        values["cam_inertia_kg_m2"], shaft, values["allowed_peak_accel_ratio"], values["allowed_dynamic_error_mm"],
        values["allowed_residual_mm"], values["method"], values["solver"], values["rtol"], values["samples"], where,
        motor, values["harmonic_plot"]), where)


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


def check_settings(settings: DynamicsSettings, where: str) -> DynamicsSettings:
    """The settings, refused (one line naming ``where``) where they ask for what the model cannot do: an odd
    number of samples, or the frequency-domain path with a varying stiffness."""
    if settings.samples % 2:
        raise CamcadError(f"samples {settings.samples} must be an even number >= 64", where, "give e.g. 4096")
    if settings.method == "frequency" and not settings.follower.constant_stiffness:
        raise CamcadError("the frequency-domain path needs a constant stiffness", where,
                          "use method time (or auto) with a stiffness_variation")
    return settings


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


