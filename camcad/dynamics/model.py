"""The elastic follower with one degree of freedom: units, stiffness (constant or variable), loads.

Elastic follower with one degree of freedom: the cam drives the follower's reduced mass through a spring.

Model (translating follower; for an oscillating one read mm as rad of swing and kg as kg·m²)::

    m ÿ + b (ẏ − ṡ) + c(θ) (y − s) = F(t)

s(θ) is the law's displacement (the rigid, kinematic motion), y the actual motion of the reduced
mass m, c the reduced stiffness of the driven chain (constant, or varying with the cam angle θ),
b the dissipation of that chain and F an external load on the mass. With the dynamic error
x = y − s, the natural frequency ωn = √(c0/m) and the damping ratio ζ = b/(2√(c0 m))::

    ẍ + 2ζωn ẋ + ωn² φ(θ) x = −s̈ + F/m,     s̈ = ω² a(θ),  θ = ω t,  φ(θ) = c(θ)/c0.

The actual acceleration of the follower is ÿ = s̈ + ẍ; the force in the elastic link per unit
mass is ÿ − F/m = −(ωn² φ x + 2ζωn ẋ). Sign convention: x > 0 when the follower is ahead of (above)
its kinematic position. Units: θ rad, t s, s and x mm, accelerations mm/s², ω and ωn rad/s.

The source's dissipation coefficient ψ (the fraction of the vibration energy lost per cycle) is
turned into a damping ratio at resonance: ψ = 2πbωn/c = 4πζ, so ζ = ψ/(4π).

Two solution paths, which must agree where both apply:

- **frequency domain** (``steady_state_frequency``): the periodic steady state, exact for constant
  stiffness. The displacement is sampled at N uniform points over the cycle and transformed
  (numpy rfft): s(θ) = Σ S_k e^{ikνθ}, ν = 2π/cycle. Each harmonic goes through the frequency
  response: with Ω_k = kνω and D_k = ωn² − Ω_k² + 2iζωnΩ_k,
  X_k = (Ω_k² S_k + F_k/m)/D_k and Ÿ_k = −Ω_k² (S_k + X_k). Accuracy knob: ``samples`` (N).
  Measured against the time path at tight tolerance (cycloidal cycle, fn = 40 Hz, ζ = 0.05, 280 rpm):
  dynamic error O(N^-4) (2e-11 mm at N = 4096) and elastic acceleration O(N^-2) (7.7e-8 of the peak
  at N = 4096, largest at the jerk jumps). Where the law's acceleration jumps (a drawn law) the
  damped elastic acceleration has a kink and its series converges only as O(N^-1) there
  (3.3e-4 of the peak at N = 4096, 8.2e-5 at 16384), the displacement as O(N^-3).
- **time marching** (``steady_state_time``, ``transient_time``): scipy's solve_ivp on the equation
  above written in θ (x'' + 2ζ(ωn/ω) x' + (ωn/ω)² φ x = −a + F/(mω²)); variable stiffness,
  start-up from rest, and the check of the other path. The periodic steady state is found exactly
  for this linear equation by shooting: the response over one cycle from x = x' = 0 plus the
  monodromy matrix Φ integrated alongside give the periodic initial state z0 = (I − Φ)⁻¹ z_p.
  Knobs: ``method`` (RK45, DOP853, Radau, LSODA, …), ``rtol``, ``atol``.

Residual vibration (docs/INTERFACE.md): the amplitude of the free vibration after a motion phase that
starts from rest. The response after the phase is x = e^{−ζωn u} (C cos ωd u + D sin ωd u),
u = t − T; the amplitude is the envelope at the end of the phase, A = √(C² + D²) =
√(x_T² + ((ẋ_T + ζωn x_T)/ωd)²). ``residual_vibration`` evaluates it by the Duhamel integral
A = |∫₀ᵀ g(τ) e^{−ζωn(T−τ)} e^{−iωdτ} dτ| / ωd, g = −s̈ (composite Gauss–Legendre quadrature,
knobs ``panels`` and ``nodes``), or by time marching (``method="time"``).

Sources: I. I. Vulfson, Dynamics of Cyclic Machines, Springer (2015), ch. 2–3 (the elastic
follower, ψ); R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 8–9 (the
single-DOF follower model, residual vibration); the batten study (the batten study: variable c2, ψ, the
summary dynamic load at the start of motion lasting about half the free period).
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from camcad.balance.conditions import DEFAULT_TOL as BALANCE_TOLERANCE

#: a law whose displacement or velocity does not return to its start within this fraction of the
#: lift (per rad for the velocity) has a break: its periodic response is meaningless. The same
#: tolerance as ``camcad check``, so every law that passes the check can be analysed.
CLOSURE_TOLERANCE = BALANCE_TOLERANCE
DEFAULT_SAMPLES = 16384
SOLVERS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
#: frequency path: a harmonic whose |D_k| = |ωn² − Ω_k² + 2iζωnΩ_k| is at most this fraction of ωn² is in
#: resonance. The exact response there is unbounded (ζ = 0) and the computed one is ruled by the round-off
#: of Ω_k (relative error ≈ 4e-16/|D_k/ωn²|, 4e-6 at this bound), so it is refused instead.
RESONANCE_DETUNING = 1e-10
#: time path: an eigenvalue λ of the monodromy matrix with |1 − λ| ≤ this × rtol is resonance. The shooting
#: solve divides by 1 − λ, and the marched monodromy carries an error of the order of rtol, so the response
#: would be ruled by integration error (measured: relative error ≈ 0.02–0.1 rtol/|1 − λ|, ≤ 1e-3 here).
RESONANCE_GAP_PER_RTOL = 100.0



def rpm_to_rad_s(rpm: float) -> float:
    """Angular speed ω = 2πn/60 (rad/s) of a shaft turning at n rpm.

    Parameters
    ----------
    rpm : float
        n, rpm.

    Returns
    -------
    float
        ω, rad/s.

    Examples
    --------
    >>> import math
    >>> from camcad.dynamics import rpm_to_rad_s
    >>> round(rpm_to_rad_s(60.0), 12) == round(2 * math.pi, 12)
    True
    """
    return 2.0 * math.pi * float(rpm) / 60.0


def damping_ratio_from_psi(psi: float) -> float:
    """Damping ratio ζ = ψ/(4π) equivalent to the dissipation coefficient ψ (dimensionless).

    ψ is the energy dissipated per cycle over the peak elastic energy; for viscous damping at
    resonance ψ = πbωnX² / (cX²/2) = 4πζ. Source: Vulfson (2015), §1.4.

    Parameters
    ----------
    psi : float
        ψ, dimensionless.

    Returns
    -------
    float
        ζ, dimensionless.

    Examples
    --------
    >>> import math
    >>> from camcad.dynamics import damping_ratio_from_psi
    >>> round(damping_ratio_from_psi(0.3), 12) == round(0.3 / (4 * math.pi), 12)
    True
    """
    return psi / (4.0 * math.pi)


@dataclass(frozen=True)
class OutputUnit:
    """The unit of the law's displacement and what follows from it for reports.

    si_scale: SI per law unit (mm → m: 1e-3; rad: 1); accel_key/accel_label: the SI acceleration
    (m/s² or rad/s²); fine_label: 1e-3 of the law unit (µm or mrad); force_key/force_label: N or N·m.
    """

    name: str
    si_scale: float
    accel_key: str
    accel_label: str
    fine_label: str
    force_key: str
    force_label: str


OUTPUT_UNITS = {
    "mm": OutputUnit("mm", 1e-3, "m_s2", "m/s²", "µm", "force_N", "N"),
    "rad": OutputUnit("rad", 1.0, "rad_s2", "rad/s²", "mrad", "moment_N_m", "N·m"),
}


def unit_key(key: str, unit: str) -> str:
    """A JSON key that carries a length, in the law's unit: ``_mm`` → ``_rad`` (``_mm2`` → ``_rad2``).

    Keys of a translating follower's law keep their docs/INTERFACE.md names (``dynamic_error_max_mm``); those of an
    oscillating follower's law (rad or deg of swing) say so (``dynamic_error_max_rad``).

    Examples
    --------
    >>> unit_key("dynamic_error_max_mm", "rad"), unit_key("variance_mm2", "deg"), unit_key("lift_mm", "mm")
    ('dynamic_error_max_rad', 'variance_deg2', 'lift_mm')
    """
    if unit == "mm":
        return key
    for suffix in ("_mm2", "_mm"):
        if key.endswith(suffix):
            return key[: -len(suffix)] + "_" + unit + suffix[3:]
    return key.replace("_mm_", f"_{unit}_")


# --------------------------------------------------------------------------------------------
# The elastic follower
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class StiffnessTable:
    """Relative stiffness φ(θ) = c(θ)/c0 of the driven chain, a periodic polyline in θ.

    Linear interpolation, periodic with ``cycle``; ``derivative`` is dφ/dθ (per rad).

    Parameters
    ----------
    theta : ndarray
        The knots, rad, increasing, within one cycle.
    factor : ndarray
        φ at the knots (dimensionless, > 0).
    cycle : float
        The period, rad.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from camcad.dynamics import StiffnessTable
    >>> table = StiffnessTable(np.array([0.0, math.pi]), np.array([1.0, 2.0]))
    >>> [round(float(v), 9) for v in table(np.array([math.pi / 2, 3 * math.pi / 2]))]   # half-way up, half-way back
    [1.5, 1.5]
    """

    theta: np.ndarray
    factor: np.ndarray
    cycle: float = 2.0 * math.pi
    if TYPE_CHECKING:  # set in __post_init__, not fields of the dataclass
        _xs: np.ndarray = field(init=False)
        _ys: np.ndarray = field(init=False)
        _slopes: np.ndarray = field(init=False)
        _xs_list: list[float] = field(init=False)

    def __post_init__(self) -> None:
        theta = np.asarray(self.theta, dtype=float)
        factor = np.asarray(self.factor, dtype=float)
        if theta.ndim != 1 or theta.shape != factor.shape or len(theta) < 1:
            raise ValueError("theta and factor must be 1-D arrays of equal length")
        if np.any(np.diff(theta) <= 0) or theta[0] < 0 or theta[-1] >= self.cycle + 1e-12:
            raise ValueError("theta must increase within one cycle")
        if np.any(factor <= 0):
            raise ValueError("stiffness factors must be positive")
        # one period of knots with the wrap-around closing segment, for np.interp
        xs = np.concatenate(([theta[-1] - self.cycle], theta, [theta[0] + self.cycle]))
        ys = np.concatenate(([factor[-1]], factor, [factor[0]]))
        object.__setattr__(self, "theta", theta)
        object.__setattr__(self, "factor", factor)
        object.__setattr__(self, "_xs", xs)
        object.__setattr__(self, "_ys", ys)
        object.__setattr__(self, "_slopes", np.diff(ys) / np.diff(xs))
        object.__setattr__(self, "_xs_list", xs.tolist())

    def __call__(self, theta) -> np.ndarray:
        t = np.mod(np.asarray(theta, dtype=float), self.cycle)
        return np.interp(t, self._xs, self._ys)

    def derivative(self, theta):
        """dc/dθ (1/rad) of the piecewise-linear factor: its slope on the knot interval θ lies in (the right
        one at a knot); a float for a float θ."""
        if isinstance(theta, float):     # one angle (an ODE right-hand side): no array overhead
            index = bisect.bisect_right(self._xs_list, theta % self.cycle) - 1
            return float(self._slopes[min(max(index, 0), len(self._slopes) - 1)])
        t = np.mod(np.asarray(theta, dtype=float), self.cycle)
        index = np.clip(np.searchsorted(self._xs, t, side="right") - 1, 0, len(self._slopes) - 1)
        return self._slopes[index]

    @classmethod
    def from_degrees(cls, pairs, cycle_deg: float = 360.0) -> StiffnessTable:
        pairs = np.asarray(pairs, dtype=float).reshape(-1, 2)
        order = np.argsort(pairs[:, 0])
        return cls(np.radians(pairs[order, 0]), pairs[order, 1], float(np.radians(cycle_deg)))


@dataclass(frozen=True)
class ElasticFollower:
    """The elastic follower: a reduced mass on a spring, driven by the cam through the law.

    m ÿ + b (ẏ − ṡ) + c(θ) (y − s) = F(t): s(θ) is the law (the rigid motion), y the actual motion of the
    reduced mass m, c the reduced stiffness of the driven chain (constant, or c0·φ(θ)), ωn = √(c0/m),
    ζ = b/(2√(c0 m)). The source's dissipation coefficient ψ (energy lost per cycle over the peak elastic
    energy) is ζ = ψ/(4π) (``camcad.dynamics.model.damping_ratio_from_psi``).

    Parameters
    ----------
    natural_frequency_hz : float
        fn = ωn/(2π) of the follower system at the nominal stiffness c0, Hz.
    damping_ratio : float
        ζ, dimensionless, 0 ≤ ζ < 1.
    mass_kg : float, optional
        The reduced mass m, kg (kg·m² for an oscillating follower); needed only for forces.
    stiffness : StiffnessTable, optional
        The relative stiffness φ(θ) = c(θ)/c0 (dimensionless, θ in rad) of a chain whose stiffness
        varies with the cam angle; None: constant stiffness.

    References
    ----------
    I. I. Vulfson, Dynamics of Cyclic Machines, Springer (2015), ch. 2–3 (the elastic follower, ψ).
    R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 8–9 (the single-DOF model).

    Examples
    --------
    ωn = 2π fn and ωd = ωn √(1 − ζ²): for 50 Hz and ζ = 0.1, 314.159 and 312.585 rad/s:

    >>> import camcad
    >>> follower = camcad.ElasticFollower(50.0, damping_ratio=0.1)
    >>> round(follower.omega_n, 3), round(follower.omega_d, 3)
    (314.159, 312.585)
    >>> round(camcad.ElasticFollower(50.0, mass_kg=2.0).stiffness_n_per_m)    # c0 = m ωn², N/m
    197392
    """

    natural_frequency_hz: float
    damping_ratio: float = 0.0
    mass_kg: float | None = None
    stiffness: StiffnessTable | None = None

    def __post_init__(self) -> None:
        if not (math.isfinite(self.natural_frequency_hz) and self.natural_frequency_hz > 0):
            raise ValueError("natural frequency must be positive")
        if not (math.isfinite(self.damping_ratio) and 0 <= self.damping_ratio < 1):
            raise ValueError("damping ratio must be in [0, 1)")

    @classmethod
    def from_mass_stiffness(cls, mass_kg: float, stiffness_n_per_m: float, damping_ratio: float = 0.0,
                            stiffness: StiffnessTable | None = None) -> ElasticFollower:
        """fn = √(c/m)/(2π) Hz from the reduced mass (kg) and stiffness (N/m)."""
        fn = math.sqrt(stiffness_n_per_m / mass_kg) / (2.0 * math.pi)
        return cls(fn, damping_ratio, mass_kg, stiffness)

    @property
    def omega_n(self) -> float:
        """Undamped natural angular frequency ωn = 2π fn (rad/s)."""
        return 2.0 * math.pi * self.natural_frequency_hz

    @property
    def omega_d(self) -> float:
        """Damped natural angular frequency ωd = ωn √(1 − ζ²) (rad/s)."""
        return self.omega_n * math.sqrt(1.0 - self.damping_ratio**2)

    @property
    def stiffness_n_per_m(self) -> float | None:
        """Nominal reduced stiffness c0 = m ωn² (N/m) when the mass is known."""
        return None if self.mass_kg is None else self.mass_kg * self.omega_n**2

    @property
    def constant_stiffness(self) -> bool:
        return self.stiffness is None

    def stiffness_factor(self, theta) -> np.ndarray:
        if self.stiffness is None:
            return np.ones_like(np.asarray(theta, dtype=float))
        return self.stiffness(theta)


# --------------------------------------------------------------------------------------------
# External loads on the mass (per unit mass, mm/s²), periodic in θ
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class HalfSinePulse:
    """External load per unit mass F/m = amplitude · sin(π (θ − start)/width) for start ≤ θ ≤ start + width.

    The batten study's "summary dynamic load" at the start of motion: a load that varies sinusoidally and lasts
    about half the free-vibration period (``start_pulse`` makes it).

    Parameters
    ----------
    start, width : float
        Where the pulse starts and how long it lasts, rad of cam angle.
    amplitude : float
        Its peak per unit mass, mm/s² (signed).
    cycle : float
        Its period, rad.

    Examples
    --------
    >>> import math
    >>> from camcad.dynamics import HalfSinePulse
    >>> pulse = HalfSinePulse(start=1.0, width=0.5, amplitude=-200.0)
    >>> [round(float(x), 9) for x in pulse([1.25, 2.0, 1.25 + 2 * math.pi])]   # the peak, after it, a cycle later
    [-200.0, 0.0, -200.0]
    """

    start: float
    width: float
    amplitude: float
    cycle: float = 2.0 * math.pi

    def __call__(self, theta) -> np.ndarray:
        u = np.mod(np.asarray(theta, dtype=float) - self.start, self.cycle)
        inside = u <= self.width
        return np.where(inside, self.amplitude * np.sin(np.pi * np.minimum(u, self.width) / self.width), 0.0)

    @property
    def breakpoints(self) -> tuple[float, ...]:
        return (self.start % self.cycle, (self.start + self.width) % self.cycle)


@dataclass(frozen=True)
class LoadSum:
    """Sum of external loads (each a callable θ → mm/s² with ``breakpoints``)."""

    loads: tuple[Any, ...]

    def __call__(self, theta) -> np.ndarray:
        theta = np.asarray(theta, dtype=float)
        return sum((load(theta) for load in self.loads), np.zeros_like(theta))

    @property
    def breakpoints(self) -> tuple[float, ...]:
        return tuple(b for load in self.loads for b in getattr(load, "breakpoints", ()))




