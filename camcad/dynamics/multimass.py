"""The batten study's multi-mass model: flywheel, elastic main shaft, cam, position function, elastic driven chain.

The batten study (PhD abstract, Novosibirsk, batten of the STB loom) names the elements — J0 moment of
inertia of the pulley/flywheel, J1 of the cam, J2 of the driven mass, c1 reduced stiffness of the
main shaft between cam and flywheel, c2 the variable reduced stiffness of the driven system, ψ the
dissipation coefficient, M0 the driving torque, Π(φ) the position (transfer) function — but its
equations are images that did not survive. They are derived here with Lagrange's equations.

Generalised coordinates: φ0 flywheel angle, φ1 cam angle (rad), q the driven coordinate (m for a
translating output, rad for an oscillating one). The cam imposes Π(φ1) on the input end of the
driven chain; the chain's spring c2(φ1) and damper b2 connect that end to the driven mass.

    T = ½ J0 φ̇0² + ½ J1 φ̇1² + ½ J2 q̇²
    V = ½ c1 (φ0 − φ1)² + ½ c2(φ1) (Π(φ1) − q)²
    R = ½ b1 (φ̇0 − φ̇1)² + ½ b2 (Π'(φ1) φ̇1 − q̇)²        (Rayleigh dissipation function)
    d/dt ∂T/∂q̇_i + ∂R/∂q̇_i + ∂V/∂q_i = Q_i,   Q = (M0, 0, M2)

give, with the twist torque M_s = c1 (φ0 − φ1) + b1 (φ̇0 − φ̇1) and the chain force
F2 = c2 (Π − q) + b2 (Π' φ̇1 − q̇):

    J0 φ̈0 = M0 − M_s
    J1 φ̈1 = M_s − Π'(φ1) F2 − ½ c2'(φ1) (Π − q)²
    J2 q̈  = F2 + M2(t)

Π' = dΠ/dφ and c2' = dc2/dφ1; the last term of the cam equation comes from the stiffness varying
with the cam angle. M2 is an external load on the driven mass (the source's summary dynamic load at
the start of motion). Dissipation: b2 = 2 ζ2 √(c2 J2), b1 = 2 ζ1 √(c1 J0 J1/(J0 + J1)) with ζ = ψ/(4π).

Limits (the source: "the shaft is much stiffer than the driven chain, so q1 and its derivatives can
be taken zero"):
- rigid shaft, c1 = ∞: φ0 ≡ φ1 and (J0 + J1) φ̈1 = M0 − Π' F2 − ½ c2' (Π − q)²;
- speed drive: the flywheel turns at a prescribed constant speed, φ0 = ω t (M0 is whatever it takes);
- rigid shaft with a speed drive: φ1 = ω t and J2 q̈ + b2 (q̇ − Π' ω) + c2 (q − Π) = M2 — exactly the
  single-DOF follower of ``sdof`` with y = q/scale, s = Π/scale, ωn² = c2/J2, ζ = b2/(2√(c2 J2)).

Drives: ``SpeedDrive(rpm)``, ``MotorDrive(torque, no_load_rpm, slope)`` with the linear static
characteristic M0 = torque + slope (ω_idle − φ̇0) (N·m; slope N·m·s/rad), or ``MotorCurve`` with a motor's
tabulated characteristic M0(n) (a scene's [dynamics] motor_torque).

Units: SI throughout (kg·m², N·m/rad, N/m or N·m/rad, s); the law's displacement (mm or rad) is
turned into Π by ``position_scale`` (1e-3 for mm → m, 1 for rad).
Source: the batten study; Lagrange's equations with dissipation as in Vulfson, Dynamics of Cyclic
Machines (2015), ch. 1–3.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from camcad.dynamics.model import SOLVERS, ElasticFollower, StiffnessTable, rpm_to_rad_s
from camcad.errors import CamcadError
from camcad.law.law import MotionLaw


@dataclass(frozen=True)
class MultiMassModel:
    """Parameters of the multi-mass model (module docstring), SI units.

    Parameters
    ----------
    flywheel_inertia, cam_inertia : float
        J0 and J1, kg·m².
    shaft_stiffness : float
        c1, N·m/rad (math.inf for a rigid shaft).
    driven_inertia : float
        J2, kg (or kg·m² for a rad output).
    driven_stiffness : float
        c2, the chain's nominal stiffness, N/m (or N·m/rad).
    damping_ratio : float
        ζ2 of the chain (dimensionless).
    shaft_damping_ratio : float
        ζ1 of the shaft (dimensionless).
    stiffness : StiffnessTable, optional
        φ(φ1) = c2(φ1)/c2 (dimensionless), None for a constant c2.
    position_scale : float
        Output units per unit of the law's displacement (1e-3 for mm → m; dimensionless ratio).

    Examples
    --------
    A rigid shaft and a speed drive reduce it to the single-degree-of-freedom follower (``simulate``'s
    example); its chain's natural frequency is √(c2/J2)/(2π):

    >>> import math
    >>> from camcad.dynamics import MultiMassModel
    >>> model = MultiMassModel(2.5, 0.3, math.inf, 1.2, 1.2 * (2 * math.pi * 40.0) ** 2)
    >>> round(math.sqrt(model.driven_stiffness / model.driven_inertia) / (2 * math.pi), 9)
    40.0
    """

    flywheel_inertia: float
    cam_inertia: float
    shaft_stiffness: float
    driven_inertia: float
    driven_stiffness: float
    damping_ratio: float = 0.0
    shaft_damping_ratio: float = 0.0
    stiffness: StiffnessTable | None = None
    position_scale: float = 1e-3

    @classmethod
    def from_follower(cls, follower: ElasticFollower, flywheel_inertia: float, cam_inertia: float,
                      shaft_stiffness: float = math.inf, shaft_damping_ratio: float | None = None,
                      position_scale: float = 1e-3) -> MultiMassModel:
        """The chain of a single-DOF follower (its mass, fn, ζ and stiffness variation) on a shaft."""
        if follower.mass_kg is None:
            raise CamcadError("the multi-mass model needs the driven mass", "dynamics", "give mass_kg")
        zeta = follower.damping_ratio
        return cls(flywheel_inertia, cam_inertia, shaft_stiffness, follower.mass_kg,
                   follower.mass_kg * follower.omega_n**2, zeta,
                   zeta if shaft_damping_ratio is None else shaft_damping_ratio, follower.stiffness, position_scale)

    @property
    def rigid_shaft(self) -> bool:
        return math.isinf(self.shaft_stiffness)

    @property
    def chain_damping(self) -> float:
        """b2 = 2 ζ2 √(c2 J2) (N·s/m or N·m·s/rad)."""
        return 2.0 * self.damping_ratio * math.sqrt(self.driven_stiffness * self.driven_inertia)

    def shaft_damping(self, speed_drive: bool) -> float:
        """b1 = 2 ζ1 √(c1 J_red) (N·m·s/rad); J_red = J1 under a speed drive, J0J1/(J0+J1) otherwise."""
        if self.rigid_shaft:
            return 0.0
        reduced = self.cam_inertia if speed_drive else \
            self.flywheel_inertia * self.cam_inertia / (self.flywheel_inertia + self.cam_inertia)
        return 2.0 * self.shaft_damping_ratio * math.sqrt(self.shaft_stiffness * reduced)


@dataclass(frozen=True)
class SpeedDrive:
    """The flywheel turns at a constant ``rpm`` whatever the load (an ideal speed source).

    Parameters
    ----------
    rpm : float
        The speed, rpm.

    Examples
    --------
    >>> from camcad.dynamics import SpeedDrive
    >>> SpeedDrive(300.0).nominal_rpm
    300.0
    """

    rpm: float

    @property
    def nominal_rpm(self) -> float:
        return self.rpm


@dataclass(frozen=True)
class MotorDrive:
    """Driving torque on the flywheel M0 = torque + slope (ω_idle − φ̇0), N·m (a linear static characteristic).

    Parameters
    ----------
    no_load_rpm : float
        The no-load speed, rpm (ω_idle = 2π no_load_rpm/60).
    slope : float
        The characteristic's slope, N·m·s/rad (≥ 0).
    torque : float
        The torque at the no-load speed, N·m.

    Examples
    --------
    A motor idling at 300 rpm, 2 N·m·s/rad: 10 rpm below idle it gives 2 × 2π·10/60 N·m.

    >>> import math
    >>> from camcad.dynamics import MotorDrive, rpm_to_rad_s
    >>> motor = MotorDrive(300.0, slope=2.0)
    >>> round(motor(rpm_to_rad_s(290.0)), 9), round(2.0 * 2 * math.pi * 10 / 60, 9)
    (2.094395102, 2.094395102)
    """

    no_load_rpm: float
    slope: float = 0.0
    torque: float = 0.0

    @property
    def nominal_rpm(self) -> float:
        return self.no_load_rpm

    def __call__(self, speed: float) -> float:
        return self.torque + self.slope * (rpm_to_rad_s(self.no_load_rpm) - speed)


@dataclass(frozen=True)
class MotorCurve:
    """Driving torque on the flywheel from a motor's static characteristic: M0(n) tabulated against speed
    (``points``: (rpm, N·m) pairs, rpm increasing), linear between the points and continued along the end
    segments beyond them (an induction motor above its synchronous speed brakes). The model starts at
    ``nominal_rpm``: where the torque falls to zero (the no-load speed) when the table crosses zero, else its
    fastest speed.

    Examples
    --------
    >>> motor = MotorCurve(((0.0, 400.0), (400.0, 300.0), (430.0, 0.0)))
    >>> motor.nominal_rpm, round(motor(rpm_to_rad_s(415.0)), 9)
    (430.0, 150.0)
    """

    points: tuple[tuple[float, float], ...]

    def __post_init__(self) -> None:
        rpm = [p[0] for p in self.points]
        if len(self.points) < 2 or any(b <= a for a, b in itertools.pairwise(rpm)):
            raise ValueError("a motor characteristic needs two or more (rpm, N m) points, rpm increasing")

    @property
    def nominal_rpm(self) -> float:
        rpm = np.array([p[0] for p in self.points])
        torque = np.array([p[1] for p in self.points])
        crossing = np.flatnonzero((torque[:-1] > 0) & (torque[1:] <= 0))
        if len(crossing):
            i = int(crossing[0])
            return float(rpm[i] + torque[i] * (rpm[i + 1] - rpm[i]) / (torque[i] - torque[i + 1]))
        return float(rpm[-1])

    def __call__(self, speed: float) -> float:
        rpm = speed * 60.0 / (2.0 * math.pi)
        points = self.points
        if rpm <= points[0][0] or rpm >= points[-1][0]:
            (r0, t0), (r1, t1) = (points[0], points[1]) if rpm <= points[0][0] else (points[-2], points[-1])
            return float(t0 + (t1 - t0) * (rpm - r0) / (r1 - r0))
        return float(np.interp(rpm, [p[0] for p in points], [p[1] for p in points]))


@dataclass(frozen=True)
class MultiMassResult:
    """Time histories of the multi-mass model at the ``time`` samples (s); ``simulate`` returns them.

    Attributes
    ----------
    time : ndarray
        The instants, s.
    phi0, phi1 : ndarray
        The flywheel's and the cam's angles, rad.
    q : ndarray
        The driven mass's position, output units (m or rad).
    dphi0, dphi1, dq : ndarray
        Their rates, rad/s and output units per s.
    ddq : ndarray
        The driven acceleration q̈, output units per s².
    dynamic_error : ndarray
        (q − Π(φ1))/scale in the law's unit (mm or rad).
    accel_elastic : ndarray
        q̈/scale, law units/s².
    accel_rigid : ndarray
        d²Π/dt²/scale at the actual cam motion, law units/s².
    """

    time: np.ndarray
    phi0: np.ndarray
    phi1: np.ndarray
    q: np.ndarray
    dphi0: np.ndarray
    dphi1: np.ndarray
    dq: np.ndarray
    ddq: np.ndarray
    dynamic_error: np.ndarray
    accel_elastic: np.ndarray
    accel_rigid: np.ndarray

    @property
    def cam_speed_rpm(self) -> np.ndarray:
        return self.dphi1 * 60.0 / (2.0 * math.pi)

    def energy(self, model: MultiMassModel, law: MotionLaw) -> np.ndarray:
        """T + V (J) along the solution (module docstring), for the conservation check of the undamped free model."""
        pi = law.kinematics(self.phi1).s * model.position_scale
        c2 = model.driven_stiffness * (1.0 if model.stiffness is None else model.stiffness(self.phi1))
        kinetic = 0.5 * (model.flywheel_inertia * self.dphi0**2 + model.cam_inertia * self.dphi1**2
                         + model.driven_inertia * self.dq**2)
        twist = 0.0 if model.rigid_shaft else 0.5 * model.shaft_stiffness * (self.phi0 - self.phi1)**2
        return kinetic + twist + 0.5 * c2 * (pi - self.q)**2


class _Equations:
    """Accelerations of the model for one combination of shaft (rigid/elastic) and drive (speed/torque)."""

    def __init__(self, model: MultiMassModel, law: MotionLaw, drive, load: Callable[[float], float] | None):
        self.m = model
        self.law = law
        self.scale = model.position_scale
        self.speed_drive = isinstance(drive, SpeedDrive)
        self.omega = rpm_to_rad_s(drive.nominal_rpm)
        self.drive = drive
        self.load = load
        self.b1 = model.shaft_damping(self.speed_drive)
        self.b2 = model.chain_damping
        self.motion_at = getattr(law, "motion_at", None)

    def chain(self, phi1: float, dphi1: float, q: float, dq: float) -> tuple[float, float]:
        """Chain force F2 (N or N·m) and the chain's torque on the cam Π' F2 + ½ c2' (Π − q)² (N·m)."""
        if self.motion_at is not None:      # a standard law: s and v without array overhead
            s, v = self.motion_at(phi1)
        else:
            kin = self.law.kinematics(np.array([phi1]))
            s, v = kin.s[0], kin.v[0]
        pi, dpi = s * self.scale, v * self.scale
        stiffness = self.m.stiffness
        c2 = self.m.driven_stiffness * (1.0 if stiffness is None else float(stiffness(phi1)))
        dc2 = 0.0 if stiffness is None else self.m.driven_stiffness * float(stiffness.derivative(phi1))
        stretch = pi - q
        force = c2 * stretch + self.b2 * (dpi * dphi1 - dq)
        return force, dpi * force + 0.5 * dc2 * stretch**2

    def external(self, t: float) -> float:
        return 0.0 if self.load is None else float(self.load(t))

    def state_names(self) -> tuple[str, ...]:
        if self.m.rigid_shaft and self.speed_drive:
            return ("q", "dq")
        if self.m.rigid_shaft or self.speed_drive:
            return ("phi1", "q", "dphi1", "dq")
        return ("phi0", "phi1", "q", "dphi0", "dphi1", "dq")

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        m = self.m
        if m.rigid_shaft and self.speed_drive:
            q, dq = y
            force, _ = self.chain(self.omega * t, self.omega, q, dq)
            return np.array([dq, (force + self.external(t)) / m.driven_inertia])
        if m.rigid_shaft:
            phi1, q, dphi1, dq = y
            force, torque = self.chain(phi1, dphi1, q, dq)
            ddphi1 = (self.drive(dphi1) - torque) / (m.flywheel_inertia + m.cam_inertia)
            return np.array([dphi1, dq, ddphi1, (force + self.external(t)) / m.driven_inertia])
        if self.speed_drive:
            phi1, q, dphi1, dq = y
            phi0, dphi0 = self.omega * t, self.omega
        else:
            phi0, phi1, q, dphi0, dphi1, dq = y
        shaft = m.shaft_stiffness * (phi0 - phi1) + self.b1 * (dphi0 - dphi1)
        force, torque = self.chain(phi1, dphi1, q, dq)
        ddphi1 = (shaft - torque) / m.cam_inertia
        ddq = (force + self.external(t)) / m.driven_inertia
        if self.speed_drive:
            return np.array([dphi1, dq, ddphi1, ddq])
        ddphi0 = (self.drive(dphi0) - shaft) / m.flywheel_inertia
        return np.array([dphi0, dphi1, dq, ddphi0, ddphi1, ddq])

    def initial(self, q0: float, dq0: float) -> np.ndarray:
        w = self.omega
        values = {"phi0": 0.0, "phi1": 0.0, "q": q0, "dphi0": w, "dphi1": w, "dq": dq0}
        return np.array([values[name] for name in self.state_names()])

    def unpack(self, t: np.ndarray, y: np.ndarray) -> dict[str, np.ndarray]:
        named = dict(zip(self.state_names(), y))
        w = self.omega
        if "phi1" not in named:
            named["phi1"], named["dphi1"] = w * t, np.full_like(t, w)
        if "phi0" not in named:
            if self.speed_drive:
                named["phi0"], named["dphi0"] = w * t, np.full_like(t, w)
            else:
                named["phi0"], named["dphi0"] = named["phi1"], named["dphi1"]
        return named


#: explicit solve_ivp methods: their step is bounded by stability, |λ h| ≲ EXPLICIT_STABILITY (RK45's
#: boundary on the imaginary axis is about 3.3, RK23's 1.7, DOP853's about 4; the bound of RK45 is used)
EXPLICIT_SOLVERS = ("RK45", "RK23", "DOP853")
EXPLICIT_STABILITY = 3.3
#: the least step count an explicit solver may need before the model is refused as too stiff for it
#: (the batten sample needs ~550 by this estimate)
MAX_EXPLICIT_STEPS = 20_000
#: evaluations of the equations a solver may make, a backstop of about 10 s of CPU: explicit solvers
#: evaluate ~30,000 times a second here, the implicit ones (Radau, BDF, LSODA: Newton iterations and
#: finite-difference Jacobians around each evaluation) ~3,000; the batten sample makes ~14,000 with DOP853
MAX_EVALUATIONS = 100_000
MAX_IMPLICIT_EVALUATIONS = 30_000


def highest_frequency(model: MultiMassModel, slope_max: float, speed_drive: bool) -> float:
    """An upper bound (rad/s) of the model's highest natural frequency: ω²max ≤ trace of M⁻¹K.

    K couples the cam's rotation and the driven mass through the chain (stiffness c2, lever Π' at most
    ``slope_max`` output units per rad); the shaft adds c1 between flywheel and cam. The trace of M⁻¹K
    is the sum of the diagonal terms, each a stiffness over its inertia, and bounds the largest
    eigenvalue of the (symmetric, positive) undamped problem.
    """
    c2 = model.driven_stiffness * (1.0 if model.stiffness is None else float(np.max(model.stiffness.factor)))
    trace = c2 / model.driven_inertia
    if model.rigid_shaft:
        if not speed_drive:
            trace += c2 * slope_max**2 / (model.flywheel_inertia + model.cam_inertia)
    else:
        trace += (model.shaft_stiffness + c2 * slope_max**2) / model.cam_inertia
        if not speed_drive:
            trace += model.shaft_stiffness / model.flywheel_inertia
    return math.sqrt(trace)


class _OverBudget(Exception):
    pass


class _Budgeted:
    """The equations' right-hand side, refusing to be evaluated more than ``budget`` times."""

    def __init__(self, rhs, budget: int):
        self.rhs, self.left = rhs, budget

    def __call__(self, t, y):
        self.left -= 1
        if self.left < 0:
            raise _OverBudget
        return self.rhs(t, y)


def simulate(model: MultiMassModel, law: MotionLaw, drive: SpeedDrive | MotorDrive | MotorCurve,
             duration_s: float, *,
             samples: int = 2001, q0: float | None = None, dq0: float | None = None,
             load: Callable[[float], float] | None = None, method: str = "RK45", rtol: float = 1e-9,
             atol: float | None = None, where: str = "[dynamics]") -> MultiMassResult:
    """March the multi-mass model from t = 0 to ``duration_s`` with solve_ivp; histories at ``samples`` instants.

    Start: φ0 = φ1 = 0 turning at the drive's nominal speed, the driven mass on its kinematic
    position and velocity (q = Π(0), q̇ = Π'(0) ω) unless ``q0``/``dq0`` say otherwise.

    Parameters
    ----------
    model : MultiMassModel
        The model (SI units).
    law : MotionLaw
        The law Π(φ1) (θ in rad, s in mm or rad).
    drive : SpeedDrive, MotorDrive or MotorCurve
        What turns the flywheel (rpm, N·m).
    duration_s : float
        How long, s.
    samples : int
        Instants returned (a count).
    q0, dq0 : float, optional
        The driven mass's start, output units and output units per s.
    load : callable, optional
        t (s) → the external load M2 on the driven mass, N (or N·m).
    method : str
        A solve_ivp method.
    rtol : float
        Relative tolerance (dimensionless).
    atol : float, optional
        Absolute tolerance, output units: m or rad (default rtol × 1e-3 × lift).
    where : str
        Named in errors.

    Returns
    -------
    MultiMassResult
        Histories at ``samples`` instants over ``duration_s`` (s, rad, output units).

    Examples
    --------
    A rigid shaft held at speed: the driven mass follows the law with the dynamic error of a single-degree-of-
    freedom follower, small far below its 40 Hz:

    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> import math
    >>> from camcad.dynamics import MultiMassModel, SpeedDrive, simulate
    >>> model = MultiMassModel(2.5, 0.3, math.inf, 1.2, 1.2 * (2 * math.pi * 40.0) ** 2, damping_ratio=0.1)
    >>> result = simulate(model, law, SpeedDrive(60.0), 1.0, samples=201)
    >>> round(float(result.time[-1]), 9), bool(abs(result.dynamic_error).max() < 0.5)     # s; mm
    (1.0, True)
    """
    from scipy.integrate import solve_ivp

    if method not in SOLVERS:
        raise CamcadError(f"unknown solver {method!r}", "--solver", f"choose one of {', '.join(SOLVERS)}")
    eq = _Equations(model, law, drive, load)
    kin0 = law.kinematics(np.array([0.0]))
    q_start = kin0.s[0] * model.position_scale if q0 is None else q0
    dq_start = kin0.v[0] * model.position_scale * eq.omega if dq0 is None else dq0
    grid = law.kinematics(np.linspace(0.0, law.cycle, 1025))
    lift = float(np.ptp(grid.s)) * model.position_scale
    atol = rtol * 1e-3 * (lift or 1.0) if atol is None else atol
    omega_max = highest_frequency(model, float(np.max(np.abs(grid.v))) * model.position_scale,
                                  isinstance(drive, SpeedDrive))
    if method in EXPLICIT_SOLVERS:
        steps = duration_s * omega_max / EXPLICIT_STABILITY
        if steps > MAX_EXPLICIT_STEPS:
            raise CamcadError(
                f"the multi-mass model is too stiff for {method}: fastest mode up to "
                f"{omega_max / (2.0 * math.pi):.3g} Hz (J1 {model.cam_inertia:g} kg·m², c1 {model.shaft_stiffness:g} "
                f"N·m/rad) needs >= {steps:,.0f} steps (budget {MAX_EXPLICIT_STEPS:,})", where,
                "check cam_inertia_kg_m2 and shaft_stiffness_N_m_per_rad, or set solver = \"Radau\"")
    budget = MAX_EVALUATIONS if method in EXPLICIT_SOLVERS else MAX_IMPLICIT_EVALUATIONS
    counted = _Budgeted(eq.rhs, budget)
    time = np.linspace(0.0, duration_s, samples)
    try:
        sol = solve_ivp(counted, (0.0, duration_s), eq.initial(q_start, dq_start), method=method, rtol=rtol,
                        atol=atol, t_eval=time)
    except _OverBudget:
        raise CamcadError(f"the multi-mass integration ({method}, rtol {rtol:g}) needed more than "
                          f"{budget:,} evaluations over {duration_s:.3g} s (fastest mode up to "
                          f"{omega_max / (2.0 * math.pi):.3g} Hz)", where,
                          "loosen rtol, or check cam_inertia_kg_m2 and shaft_stiffness_N_m_per_rad") from None
    if not sol.success:
        raise CamcadError(f"the multi-mass integration failed: {sol.message}", "dynamics",
                          "loosen the tolerance or choose another solver")
    named = eq.unpack(time, sol.y)
    names = eq.state_names()
    rates = np.array([eq.rhs(t, y) for t, y in zip(time, sol.y.T)]).T
    ddq = rates[names.index("dq")]
    ddphi1 = rates[names.index("dphi1")] if "dphi1" in names else np.zeros_like(time)
    kin = law.kinematics(named["phi1"])
    scale = model.position_scale
    accel_rigid = kin.a * named["dphi1"]**2 + kin.v * ddphi1
    return MultiMassResult(time, named["phi0"], named["phi1"], named["q"], named["dphi0"], named["dphi1"],
                           named["dq"], ddq, named["q"] / scale - kin.s, ddq / scale, accel_rigid)
