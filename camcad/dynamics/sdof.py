"""Elastic follower with one degree of freedom: the cam drives the follower's reduced mass through a spring.

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

Residual vibration (SPEC.md): the amplitude of the free vibration after a motion phase that
starts from rest. The response after the phase is x = e^{−ζωn u} (C cos ωd u + D sin ωd u),
u = t − T; the amplitude is the envelope at the end of the phase, A = √(C² + D²) =
√(x_T² + ((ẋ_T + ζωn x_T)/ωd)²). ``residual_vibration`` evaluates it by the Duhamel integral
A = |∫₀ᵀ g(τ) e^{−ζωn(T−τ)} e^{−iωdτ} dτ| / ωd, g = −s̈ (composite Gauss–Legendre quadrature,
knobs ``panels`` and ``nodes``), or by time marching (``method="time"``).

Sources: I. I. Vulfson, Dynamics of Cyclic Machines, Springer (2015), ch. 2–3 (the elastic
follower, ψ); R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 8–9 (the
single-DOF follower model, residual vibration); the batten study (seed 001: variable c2, ψ, the
summary dynamic load at the start of motion lasting about half the free period).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from camcad.balance import DEFAULT_TOL as BALANCE_TOLERANCE
from camcad.errors import CamcadError
from camcad.law.law import MotionLaw, Phase
from camcad.params import Field, read_table

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
    """Angular speed ω = 2πn/60 (rad/s) of a shaft turning at n rpm."""
    return 2.0 * math.pi * float(rpm) / 60.0


def damping_ratio_from_psi(psi: float) -> float:
    """Damping ratio ζ = ψ/(4π) equivalent to the dissipation coefficient ψ (dimensionless).

    ψ is the energy dissipated per cycle over the peak elastic energy; for viscous damping at
    resonance ψ = πbωnX² / (cX²/2) = 4πζ. Source: Vulfson (2015), §1.4.
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


# --------------------------------------------------------------------------------------------
# The elastic follower
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class StiffnessTable:
    """Relative stiffness φ(θ) = c(θ)/c0 of the driven chain, a periodic polyline in θ.

    ``theta`` (rad, increasing, within one cycle) and ``factor`` (dimensionless, > 0); linear
    interpolation, periodic with ``cycle`` (rad). ``derivative`` is dφ/dθ (per rad).
    """

    theta: np.ndarray
    factor: np.ndarray
    cycle: float = 2.0 * math.pi

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

    def __call__(self, theta) -> np.ndarray:
        t = np.mod(np.asarray(theta, dtype=float), self.cycle)
        return np.interp(t, self._xs, self._ys)

    def derivative(self, theta) -> np.ndarray:
        t = np.mod(np.asarray(theta, dtype=float), self.cycle)
        slopes = np.diff(self._ys) / np.diff(self._xs)
        index = np.clip(np.searchsorted(self._xs, t, side="right") - 1, 0, len(slopes) - 1)
        return slopes[index]

    @classmethod
    def from_degrees(cls, pairs, cycle_deg: float = 360.0) -> "StiffnessTable":
        pairs = np.asarray(pairs, dtype=float).reshape(-1, 2)
        order = np.argsort(pairs[:, 0])
        return cls(np.radians(pairs[order, 0]), pairs[order, 1], float(np.radians(cycle_deg)))


@dataclass(frozen=True)
class ElasticFollower:
    """Reduced mass on a spring: natural frequency (Hz), damping ratio, optional mass and stiffness variation.

    ``mass_kg`` (kg, or kg·m² for an oscillating follower) is needed only for forces.
    ``stiffness`` is φ(θ) = c(θ)/c0; None means constant stiffness.
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
                            stiffness: StiffnessTable | None = None) -> "ElasticFollower":
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

    ``start`` and ``width`` in rad of cam angle, ``amplitude`` in mm/s² (signed), periodic with
    ``cycle``. The source's "summary dynamic load" at the start of motion (seed 001): a load that
    varies sinusoidally and lasts about half the free-vibration period.
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


# --------------------------------------------------------------------------------------------
# The law's spectrum
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class LawSpectrum:
    """A law sampled at ``samples`` uniform points over its cycle, and the rfft of its displacement.

    theta (rad, [0, cycle) without the end), s (mm), a (mm/rad², exact at the samples);
    coefficients S_k (mm), k = 0 … N/2, with s(θ) = Σ_k S_k e^{ikνθ} over k = −N/2 … N/2,
    S_{−k} = conj(S_k), ν = 2π/cycle (harmonic orders per rad).
    """

    cycle: float
    theta: np.ndarray
    s: np.ndarray
    a: np.ndarray
    coefficients: np.ndarray
    lift: float
    phases: tuple[Phase, ...] = ()

    @property
    def samples(self) -> int:
        return len(self.theta)

    @property
    def orders(self) -> np.ndarray:
        """Angular frequency of each harmonic per rad of cam angle, kν (1/rad)."""
        return 2.0 * np.pi / self.cycle * np.arange(len(self.coefficients))


def check_closure(law: MotionLaw, where: str = "law", tolerance: float = CLOSURE_TOLERANCE) -> float:
    """Lift of the law (mm); CamcadError when s or v at the end of the cycle differ from the start.

    Tolerance: ``tolerance`` × lift (mm) for s, and × lift per rad for v.
    """
    theta = np.linspace(0.0, law.cycle, 4097)
    kin = law.kinematics(theta)
    lift = float(kin.s.max() - kin.s.min())
    if not lift > 0:
        raise CamcadError("the law does not move (zero lift)", where, "give a law with a rise")
    gap_s = float(kin.s[-1] - kin.s[0])
    gap_v = float(kin.v[-1] - kin.v[0])
    if abs(gap_s) > tolerance * lift or abs(gap_v) > tolerance * lift:
        raise CamcadError(f"the law does not close over the cycle (s gap {gap_s:.3g} mm, v gap {gap_v:.3g} mm/rad), "
                          "so its cam has a break and no periodic motion", where,
                          "balance it first with camcad fix")
    return lift


def law_spectrum(law: MotionLaw, samples: int = DEFAULT_SAMPLES, where: str = "law") -> LawSpectrum:
    """Sample the law at ``samples`` points per cycle and take the rfft of its displacement."""
    if samples < 8 or samples % 2:
        raise ValueError("samples must be an even number >= 8")
    lift = check_closure(law, where)
    theta = law.cycle * np.arange(samples) / samples
    kin = law.kinematics(theta)
    coefficients = np.fft.rfft(kin.s) / samples
    return LawSpectrum(law.cycle, theta, kin.s, kin.a, coefficients, lift, tuple(law.phases))


# --------------------------------------------------------------------------------------------
# Responses
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Response:
    """Periodic response at one speed, sampled at ``theta`` (rad).

    displacement_rigid s (mm); dynamic_error x = y − s (mm); accel_rigid s̈ and accel_elastic ÿ
    (mm/s²); link_accel = ÿ − F/m, the force in the elastic link per unit mass (mm/s²).
    """

    rpm: float
    theta: np.ndarray
    displacement_rigid: np.ndarray
    dynamic_error: np.ndarray
    accel_rigid: np.ndarray
    accel_elastic: np.ndarray
    link_accel: np.ndarray
    method: str = ""

    @property
    def displacement_elastic(self) -> np.ndarray:
        return self.displacement_rigid + self.dynamic_error

    @property
    def peak_accel_rigid(self) -> float:
        return float(np.max(np.abs(self.accel_rigid)))

    @property
    def peak_accel_elastic(self) -> float:
        return float(np.max(np.abs(self.accel_elastic)))

    @property
    def peak_accel_ratio(self) -> float:
        """max|ÿ| / max|s̈| over the cycle (elastic / rigid)."""
        return self.peak_accel_elastic / self.peak_accel_rigid

    @property
    def dynamic_error_max(self) -> float:
        """max|y − s| over the cycle (mm)."""
        return float(np.max(np.abs(self.dynamic_error)))


def _external_on_grid(external, theta: np.ndarray) -> np.ndarray:
    return np.zeros_like(theta) if external is None else np.asarray(external(theta), dtype=float)


def steady_state_frequency(law_or_spectrum: MotionLaw | LawSpectrum, follower: ElasticFollower, rpm: float, *,
                           samples: int = DEFAULT_SAMPLES, external=None) -> Response:
    """Periodic steady state at ``rpm`` by the frequency response of each harmonic (module docstring).

    Exact (to the sampling error, knob ``samples``) for constant stiffness; a follower with
    variable stiffness raises CamcadError (use ``steady_state_time``). ``external`` is a periodic
    load per unit mass (callable θ → mm/s²), sampled on the same grid.
    """
    if not follower.constant_stiffness:
        raise CamcadError("the frequency-domain path needs a constant stiffness", "dynamics",
                          "use the time path (--method time) for a stiffness that varies with the cam angle")
    spectrum = law_or_spectrum if isinstance(law_or_spectrum, LawSpectrum) else law_spectrum(law_or_spectrum, samples)
    n = spectrum.samples
    omega = rpm_to_rad_s(rpm)
    wn, zeta = follower.omega_n, follower.damping_ratio
    big_omega = spectrum.orders * omega
    denominator = wn**2 - big_omega**2 + 2j * zeta * wn * big_omega
    # the Nyquist term (the last) is dropped below, so its denominator does not matter
    resonant = np.flatnonzero(np.abs(denominator[:-1]) <= RESONANCE_DETUNING * wn**2)
    if len(resonant):
        k = int(resonant[0])
        raise CamcadError(f"the follower (fn {follower.natural_frequency_hz:g} Hz, damping ratio {zeta:g}) is in "
                          f"resonance with harmonic {k} of the law at {rpm:g} rpm: no periodic steady state",
                          "dynamics", "give a damping ratio > 0 or another speed")
    forcing = big_omega**2 * spectrum.coefficients
    f_grid = _external_on_grid(external, spectrum.theta)
    if external is not None:
        forcing = forcing + np.fft.rfft(f_grid) / n
    x_k = forcing / denominator
    # the Nyquist term k = N/2 is the aliased sum of all higher harmonics; multiplied by Ω² it would
    # add a sample-to-sample alternation to the acceleration, so it is left out
    x_k[-1] = 0.0
    x = np.fft.irfft(x_k * n, n)
    y_k = spectrum.coefficients + x_k
    y_k[-1] = 0.0
    accel_elastic = np.fft.irfft(-big_omega**2 * y_k * n, n)
    accel_rigid = omega**2 * spectrum.a
    return Response(float(rpm), spectrum.theta, spectrum.s, x, accel_rigid, accel_elastic,
                    accel_elastic - f_grid, "frequency")


def _breakpoints(law: MotionLaw, external, start: float, end: float) -> np.ndarray:
    """Phase boundaries and load edges inside (start, end): where the integrator is restarted."""
    cuts = {start, end}
    cycle = law.cycle
    marks = [p.start for p in law.phases] + [p.end for p in law.phases]
    marks += list(getattr(external, "breakpoints", ()))
    first = math.floor(start / cycle)
    for turn in range(first, math.ceil(end / cycle) + 1):
        for mark in marks:
            value = turn * cycle + mark
            if start < value < end:
                cuts.add(value)
    return np.array(sorted(cuts))


class _TimeModel:
    """Right-hand side of the equation in θ, with the state (x, x') and optionally the monodromy columns."""

    def __init__(self, law: MotionLaw, follower: ElasticFollower, rpm: float, external) -> None:
        self.law = law
        self.follower = follower
        self.omega = rpm_to_rad_s(rpm)
        ratio = follower.omega_n / self.omega
        self.k2 = ratio**2
        self.c1 = 2.0 * follower.damping_ratio * ratio
        self.external = external
        self.stiffness = follower.stiffness

    def forcing(self, theta: float) -> float:
        a = float(self.law.kinematics(np.array([theta])).a[0])
        if self.external is not None:
            a -= float(self.external(theta)) / self.omega**2
        return -a

    def spring(self, theta: float) -> float:
        return self.k2 if self.stiffness is None else self.k2 * float(self.stiffness(theta))

    def rhs(self, theta: float, z: np.ndarray) -> np.ndarray:
        k = self.spring(theta)
        return np.array([z[1], self.forcing(theta) - self.c1 * z[1] - k * z[0]])

    def rhs_with_monodromy(self, theta: float, z: np.ndarray) -> np.ndarray:
        k = self.spring(theta)
        c = self.c1
        return np.array([z[1], self.forcing(theta) - c * z[1] - k * z[0],
                         z[3], -c * z[3] - k * z[2],
                         z[5], -c * z[5] - k * z[4]])

    def elastic_accel(self, theta: np.ndarray, x: np.ndarray, xp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """ÿ and the link force per unit mass (mm/s²) from the state in θ."""
        w2 = self.omega**2
        phi = np.ones_like(theta) if self.stiffness is None else self.stiffness(theta)
        link = -w2 * (self.k2 * phi * x + self.c1 * xp)
        f = _external_on_grid(self.external, theta)
        return link + f, link


def _march(fun, z0: np.ndarray, theta_eval: np.ndarray, cuts: np.ndarray, method: str, rtol: float,
           atol: float) -> tuple[np.ndarray, np.ndarray]:
    """Integrate from cuts[0] to cuts[-1], restarting at each cut (a discontinuity of the forcing).

    Returns the states at ``theta_eval`` (inside [cuts[0], cuts[-1]]) and the state at cuts[-1].
    """
    from scipy.integrate import solve_ivp

    if method not in SOLVERS:
        raise CamcadError(f"unknown solver {method!r}", "--solver", f"choose one of {', '.join(SOLVERS)}")
    out = np.empty((len(z0), len(theta_eval)))
    z = np.array(z0, dtype=float)
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        mask = (theta_eval >= lo) & (theta_eval < hi)
        sol = solve_ivp(fun, (lo, hi), z, method=method, rtol=rtol, atol=atol,
                        t_eval=np.append(theta_eval[mask], hi))
        if not sol.success:
            raise CamcadError(f"the time integration failed: {sol.message}", "dynamics",
                              "loosen --rtol or choose another --solver")
        out[:, mask] = sol.y[:, :-1]
        z = sol.y[:, -1]
    out[:, theta_eval == cuts[-1]] = z[:, None]
    return out, z


def steady_state_time(law: MotionLaw, follower: ElasticFollower, rpm: float, *, samples: int = DEFAULT_SAMPLES,
                      method: str = "RK45", rtol: float = 1e-8, atol: float | None = None,
                      external=None) -> Response:
    """Periodic steady state at ``rpm`` by time marching and shooting (module docstring).

    Works with variable stiffness. Knobs: ``method`` (a solve_ivp method), ``rtol``, ``atol``
    (default rtol × 1e-3 × lift, in mm and mm/rad: the dynamic error is a small fraction of the lift,
    so a looser atol would dominate). Output at ``samples`` uniform points per cycle.
    """
    lift = check_closure(law)
    model = _TimeModel(law, follower, rpm, external)
    atol = rtol * 1e-3 * lift if atol is None else atol
    theta = law.cycle * np.arange(samples) / samples
    cuts = _breakpoints(law, external, 0.0, law.cycle)
    z0 = np.array([0.0, 0.0, 1.0, 0.0, 0.0, 1.0])
    states, z_end = _march(model.rhs_with_monodromy, z0, theta, cuts, method, rtol, atol)
    monodromy = np.array([[z_end[2], z_end[4]], [z_end[3], z_end[5]]])
    system = np.eye(2) - monodromy
    # a free vibration that repeats itself after one cycle (an eigenvalue of the monodromy at 1) makes
    # I − Φ singular; cond(I − Φ) does not see it, because I − Φ is then small as a whole
    gap = float(np.min(np.abs(1.0 - np.linalg.eigvals(monodromy))))
    if gap <= RESONANCE_GAP_PER_RTOL * rtol:
        raise CamcadError(f"the follower is in resonance at {rpm:g} rpm (a free vibration repeats itself each "
                          f"cycle within {gap:.2g}): no periodic steady state", "dynamics",
                          "give a damping ratio > 0, another speed, or a tighter --rtol")
    start = np.linalg.solve(system, z_end[:2])
    x = states[0] + states[2] * start[0] + states[4] * start[1]
    xp = states[1] + states[3] * start[0] + states[5] * start[1]
    accel_elastic, link = model.elastic_accel(theta, x, xp)
    kin = law.kinematics(theta)
    return Response(float(rpm), theta, kin.s, x, model.omega**2 * kin.a, accel_elastic, link,
                    f"time {method} rtol={rtol:g}")


@dataclass(frozen=True)
class Transient:
    """Response from given initial conditions: theta (rad), x (mm), x' = dx/dθ (mm/rad), ÿ (mm/s²)."""

    rpm: float
    theta: np.ndarray
    dynamic_error: np.ndarray
    dynamic_error_rate: np.ndarray
    accel_rigid: np.ndarray
    accel_elastic: np.ndarray


def transient_time(law: MotionLaw, follower: ElasticFollower, rpm: float, theta_end: float, *,
                   theta_start: float = 0.0, x0: float = 0.0, xdot0: float = 0.0, samples: int = 2001,
                   method: str = "RK45", rtol: float = 1e-8, atol: float | None = None,
                   external=None) -> Transient:
    """Start-up: march from θ_start (rad) with x = x0 (mm), ẋ = xdot0 (mm/s) to θ_end (rad).

    Knobs as ``steady_state_time``; output at ``samples`` points from θ_start to θ_end.
    """
    lift = check_closure(law)
    model = _TimeModel(law, follower, rpm, external)
    atol = rtol * 1e-3 * lift if atol is None else atol
    theta = np.linspace(theta_start, theta_end, samples)
    cuts = _breakpoints(law, external, theta_start, theta_end)
    states, _ = _march(model.rhs, np.array([x0, xdot0 / model.omega]), theta, cuts, method, rtol, atol)
    accel_elastic, _ = model.elastic_accel(theta, states[0], states[1])
    kin = law.kinematics(theta)
    return Transient(float(rpm), theta, states[0], states[1], model.omega**2 * kin.a, accel_elastic)


def steady_state(law: MotionLaw, follower: ElasticFollower, rpm: float, *, method: str = "auto",
                 samples: int = DEFAULT_SAMPLES, solver: str = "RK45", rtol: float = 1e-8,
                 external=None) -> Response:
    """The periodic steady state by ``method`` "frequency", "time" or "auto" (frequency when the stiffness is constant)."""
    if method == "auto":
        method = "frequency" if follower.constant_stiffness else "time"
    if method == "frequency":
        return steady_state_frequency(law, follower, rpm, samples=samples, external=external)
    if method == "time":
        return steady_state_time(law, follower, rpm, samples=samples, method=solver, rtol=rtol, external=external)
    raise CamcadError(f"unknown method {method!r}", "--method", "choose frequency, time or auto")


# --------------------------------------------------------------------------------------------
# Speed sweeps
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Sweep:
    """Figures of the steady state over a list of speeds (rpm).

    peak_accel_ratio (elastic / rigid), dynamic_error_max (mm), peak_accel_rigid and
    peak_accel_elastic (mm/s²), one per speed; ``responses`` keeps the full responses asked for.
    """

    speeds_rpm: np.ndarray
    peak_accel_ratio: np.ndarray
    dynamic_error_max: np.ndarray
    peak_accel_rigid: np.ndarray
    peak_accel_elastic: np.ndarray
    method: str
    responses: dict = field(default_factory=dict)


def sweep(law: MotionLaw, follower: ElasticFollower, speeds_rpm, *, method: str = "auto",
          samples: int = DEFAULT_SAMPLES, solver: str = "RK45", rtol: float = 1e-8, external_at=None,
          keep=(), progress: Callable[[int, int], None] | None = None) -> Sweep:
    """Steady state at every speed. ``external_at(rpm)`` gives the external load at that speed
    (or None); ``keep`` lists speeds whose full Response is kept; ``progress(done, total)`` is
    called after each speed."""
    speeds = np.atleast_1d(np.asarray(speeds_rpm, dtype=float))
    if method == "auto":
        method = "frequency" if follower.constant_stiffness else "time"
    spectrum = law_spectrum(law, samples) if method == "frequency" else None
    keep = {float(k) for k in keep}
    ratio, error, rigid, elastic = (np.empty(len(speeds)) for _ in range(4))
    responses = {}
    for i, rpm in enumerate(speeds):
        external = external_at(rpm) if external_at else None
        if method == "frequency":
            response = steady_state_frequency(spectrum, follower, rpm, external=external)
        else:
            response = steady_state(law, follower, rpm, method=method, samples=samples, solver=solver,
                                    rtol=rtol, external=external)
        ratio[i] = response.peak_accel_ratio
        error[i] = response.dynamic_error_max
        rigid[i] = response.peak_accel_rigid
        elastic[i] = response.peak_accel_elastic
        if float(rpm) in keep:
            responses[float(rpm)] = response
        if progress:
            progress(i + 1, len(speeds))
    return Sweep(speeds, ratio, error, rigid, elastic, method, responses)


# --------------------------------------------------------------------------------------------
# Residual vibration after each motion phase
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Residual:
    """Residual vibration after one motion phase started from rest: amplitude (mm) and the state at its end."""

    phase: Phase
    amplitude: float
    x_end: float
    xdot_end: float
    rpm: float


def motion_phases(law: MotionLaw) -> tuple[Phase, ...]:
    return tuple(p for p in law.phases if p.kind in ("rise", "return"))


def _panels(law: MotionLaw, start: float, end: float, panels: int) -> np.ndarray:
    edges = set(np.linspace(start, end, panels + 1).tolist())
    knots = getattr(law, "x", None)
    if knots is not None:
        knots = np.asarray(knots, dtype=float)
        edges.update(knots[(knots > start) & (knots < end)].tolist())
    return np.array(sorted(edges))


def residual_vibration(law: MotionLaw, follower: ElasticFollower, rpm: float, *, method: str = "duhamel",
                       panels: int = 32, nodes: int = 16, solver: str = "DOP853", rtol: float = 1e-11,
                       atol: float | None = None, phases: tuple[Phase, ...] | None = None) -> list[Residual]:
    """Residual vibration after each rise and return that starts from rest, at ``rpm``.

    method "duhamel": A = |∫₀ᵀ g(τ) e^{−ζωn(T−τ)} e^{−iωdτ} dτ| / ωd with g = −s̈ (mm/s²), by
    composite Gauss–Legendre quadrature (``panels`` equal panels, split further at the knots of a
    drawn law, ``nodes`` points each). method "time": solve_ivp (``solver``, ``rtol``, ``atol``) over the
    phase from x = ẋ = 0, then A = √(x² + ((ẋ + ζωn x)/ωd)²). Both use the nominal stiffness
    (the free vibration after the phase is that of the constant-stiffness follower).
    """
    omega = rpm_to_rad_s(rpm)
    wn, wd, zeta = follower.omega_n, follower.omega_d, follower.damping_ratio
    results = []
    for phase in (phases if phases is not None else motion_phases(law)):
        duration = phase.width / omega
        if method == "duhamel":
            u, w = np.polynomial.legendre.leggauss(nodes)
            edges = _panels(law, phase.start, phase.end, panels)
            half = np.diff(edges) / 2.0
            theta = ((edges[:-1] + edges[1:]) / 2.0)[:, None] + half[:, None] * u[None, :]
            weights = (half[:, None] * w[None, :]).ravel()
            theta = theta.ravel()
            tau = (theta - phase.start) / omega
            g = -omega**2 * law.kinematics(theta).a
            kernel = np.exp(-zeta * wn * (duration - tau) - 1j * wd * tau)
            integral = np.sum(weights * g * kernel) / omega     # dτ = dθ/ω
            # x(T + u) = e^{−ζωn u} Im(W e^{iωd u})/ωd with W = e^{iωdT}·integral
            w_end = np.exp(1j * wd * duration) * integral
            x_end = float(w_end.imag / wd)
            xdot_end = float((-zeta * wn * w_end.imag + wd * w_end.real) / wd)
            amplitude = float(abs(integral) / wd)
        elif method == "time":
            tr = transient_time(law, follower, rpm, phase.end, theta_start=phase.start, samples=2,
                                method=solver, rtol=rtol, atol=atol)
            x_end = float(tr.dynamic_error[-1])
            xdot_end = float(tr.dynamic_error_rate[-1] * omega)
            amplitude = math.hypot(x_end, (xdot_end + zeta * wn * x_end) / wd)
        else:
            raise CamcadError(f"unknown method {method!r}", "residual vibration", "choose duhamel or time")
        results.append(Residual(phase, amplitude, x_end, xdot_end, float(rpm)))
    return results


def cycloidal_residual_amplitude(lift: float, rise_time_s: float, natural_frequency_hz: float) -> float:
    """Closed-form residual vibration (mm) of an undamped follower after a cycloidal rise from rest.

    A = h |sin(πr)| / (π r |r² − 1|),  r = T fn (rise time over natural period); A = h/2 at r = 1.
    Vanishes when r is an integer ≥ 2. Derivation: with s̈ = (2πh/T²) sin(2πt/T) on [0, T],
    A = |∫₀ᵀ s̈ e^{iωnτ} dτ| / ωn and ∫₀ᵀ sin(Ωτ) e^{iωnτ} dτ = Ω (e^{iωnT} − 1)/(ωn² − Ω²), Ω = 2π/T.
    Source: derived here; the same result is tabulated by Norton (2009) §9 for the cycloidal rise.
    """
    r = rise_time_s * natural_frequency_hz
    if abs(r - 1.0) < 1e-9:
        return lift / 2.0
    return lift * abs(math.sin(math.pi * r)) / (math.pi * r * abs(r * r - 1.0))


# --------------------------------------------------------------------------------------------
# Load at the start of motion
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class StartLoad:
    """Peak force in the elastic link within one free period after a motion phase starts.

    peak_link_accel (law units/s², mm/s² or rad/s²; × mass = force), at_deg (cam angle of the
    peak), peak_rigid_accel (the law's own peak in the same window), force_n (N, or N·m for a rad
    output; None when the mass is unknown).
    """

    phase: Phase
    peak_link_accel: float
    at_deg: float
    peak_rigid_accel: float
    force_n: float | None


def start_pulse(law: MotionLaw, follower: ElasticFollower, rpm: float, phase: Phase, ratio: float) -> HalfSinePulse:
    """The summary dynamic load at the start of ``phase``: a half-sine lasting half the free period.

    Applied as an external load opposing the motion's initial acceleration, of amplitude
    ``ratio`` × the phase's peak rigid acceleration (mm/s²). Source: seed 001 (batten: a jump of
    acceleration at the start of motion, varying sinusoidally, lasting about half the free period).
    """
    omega = rpm_to_rad_s(rpm)
    theta = np.linspace(phase.start, phase.end, 513)
    a = law.kinematics(theta).a
    peak = float(np.max(np.abs(a))) * omega**2
    first = a[np.flatnonzero(np.abs(a) > 1e-9 * np.max(np.abs(a)))[0]] if np.any(a) else 1.0
    width = omega * 0.5 / follower.natural_frequency_hz
    return HalfSinePulse(phase.start, width, -math.copysign(ratio * peak, first), law.cycle)


def start_loads(response: Response, law: MotionLaw, follower: ElasticFollower, unit_scale: float = 1e-3
                ) -> list[StartLoad]:
    """Start-of-motion loads of every rise and return, read from a steady-state response.

    ``unit_scale`` turns the law's unit into SI (1e-3 for mm → m, 1 for rad), so the force is
    mass × peak × unit_scale in N (N·m for a rad output with the mass in kg·m²).
    """
    omega = rpm_to_rad_s(response.rpm)
    window = omega / follower.natural_frequency_hz   # one free period, in rad of cam angle
    out = []
    for phase in motion_phases(law):
        u = np.mod(response.theta - phase.start, law.cycle)
        mask = u <= window
        if not np.any(mask):
            continue
        link = np.abs(response.link_accel[mask])
        i = int(np.argmax(link))
        peak = float(link[i])
        at = float(np.degrees(response.theta[mask][i]))
        rigid = float(np.max(np.abs(response.accel_rigid[mask])))
        force = None if follower.mass_kg is None else follower.mass_kg * peak * unit_scale
        out.append(StartLoad(phase, peak, at, rigid, force))
    return out


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
          help="unit of the law's displacement: mm (translating) or rad (oscillating)"),
    Field("start_pulse_ratio", "float", "", minimum=0.0,
          help="summary dynamic load at the start of motion, × the phase's peak rigid acceleration"),
    Field("flywheel_inertia_kg_m2", "float", "kg·m²", positive=True, help="J0 (multi-mass model)"),
    Field("cam_inertia_kg_m2", "float", "kg·m²", positive=True, help="J1 (multi-mass model)"),
    Field("shaft_stiffness_N_m_per_rad", "float", "N·m/rad", positive=True,
          help="c1 between flywheel and cam (multi-mass model; omit for a rigid shaft)"),
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
    return DynamicsSettings(follower, values["output_unit"], values["start_pulse_ratio"],
                            values["flywheel_inertia_kg_m2"], values["cam_inertia_kg_m2"], shaft,
                            values["allowed_peak_accel_ratio"], values["allowed_dynamic_error_mm"],
                            values["allowed_residual_mm"], values["method"], values["solver"], values["rtol"],
                            values["samples"])


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
    if len(np.unique(pairs[:, 0])) != len(pairs):
        raise CamcadError("stiffness_variation repeats an angle", where, fix)
    return StiffnessTable.from_degrees(pairs, cycle_deg)
