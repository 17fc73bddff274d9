"""Periodic steady state of the elastic follower: frequency domain (exact for constant stiffness),
time marching with shooting, transients, and sweeps over speed (see camcad.dynamics.model).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import cast

import numpy as np

from camcad.balance.conditions import DEFAULT_TOL as BALANCE_TOLERANCE
from camcad.dynamics.model import ElasticFollower, rpm_to_rad_s
from camcad.dynamics.spectrum import LawSpectrum, check_closure, law_spectrum
from camcad.errors import CamcadError
from camcad.law.law import MotionLaw

#: a law whose displacement or velocity does not return to its start within this fraction of the
#: lift (per rad for the velocity) has a break: its periodic response is meaningless. The same
#: tolerance as ``camcad check``, so every law that passes the check can be analysed.
CLOSURE_TOLERANCE = BALANCE_TOLERANCE
DEFAULT_SAMPLES = 16384
SOLVERS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
#: frequency path: a harmonic whose |D_k| = |ωn² − Ω_k² + 2iζωnΩ_k| is at most this fraction of ωn² is in
#: resonance. The exact response there is unbounded (ζ = 0) and the computed one is ruled by the round-off
#: of Ω_k (relative error ≈ 4e-16/|D_k/ωn²|, 4e-6 at this bound), so it is not computed from D_k.
RESONANCE_DETUNING = 1e-10
#: a resonant harmonic whose forcing, as a displacement amplitude 2|F_k|/Ω_k², is at most this fraction of the
#: lift is zero (round-off of the sampled spectrum is ~1e-16 of the lift): its term is dropped, which is the
#: ζ → 0 limit of the damped response (X_k = F_k/D_k = 0 for every ζ > 0 when F_k = 0)
ZERO_HARMONIC = 1e-12
#: time path: an eigenvalue λ of the monodromy matrix with |1 − λ| ≤ this × rtol is resonance. The shooting
#: solve divides by 1 − λ, and the marched monodromy carries an error of the order of rtol, so the response
#: would be ruled by integration error (measured: relative error ≈ 0.02–0.1 rtol/|1 − λ|, ≤ 1e-3 here).
RESONANCE_GAP_PER_RTOL = 100.0


class ResonanceError(CamcadError):
    """No bounded periodic steady state at one speed: exact resonance with a harmonic that is not zero.

    A CamcadError: ``camcad.steady_state`` raises it; ``sweep`` lists the speed in ``Sweep.unbounded``.

    Attributes
    ----------
    what : str
        What happened, in words.
    rpm : float
        The speed, rpm.
    harmonic : int, optional
        The order k in resonance (None on the time path, which cannot tell).
    amplitude : float, optional
        The displacement amplitude of that harmonic's forcing, law units (mm or rad; None on the time path).
    fix : str
        What to do about it.
    """

    def __init__(self, what: str, rpm: float, harmonic: int | None = None, amplitude: float | None = None,
                 fix: str = "give a damping ratio > 0 or another speed") -> None:
        super().__init__(what, "dynamics", fix)
        self.rpm = float(rpm)
        self.harmonic = harmonic
        self.amplitude = amplitude


# --------------------------------------------------------------------------------------------
# Responses
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Response:
    """Periodic response at one speed, sampled at ``theta`` (rad); ``camcad.steady_state`` returns it.

    Attributes
    ----------
    rpm : float
        The speed, rpm.
    theta : ndarray
        The cam angles sampled, rad.
    displacement_rigid : ndarray
        s, mm.
    dynamic_error : ndarray
        x = y − s, mm.
    accel_rigid, accel_elastic : ndarray
        s̈ and ÿ, mm/s².
    link_accel : ndarray
        ÿ − F/m, the force in the elastic link per unit mass, mm/s².
    method : str
        "frequency" or "time".
    notes : tuple of str
        What the solution assumed (e.g. the ζ → 0 limit at an exact resonance with a zero harmonic).
    """

    rpm: float
    theta: np.ndarray
    displacement_rigid: np.ndarray
    dynamic_error: np.ndarray
    accel_rigid: np.ndarray
    accel_elastic: np.ndarray
    link_accel: np.ndarray
    method: str = ""
    notes: tuple[str, ...] = ()

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

    Exact resonance (|D_k| ≤ ``RESONANCE_DETUNING`` ωn², in practice ζ = 0 and Ω_k = ωn): a harmonic whose
    forcing is zero (displacement amplitude ≤ ``ZERO_HARMONIC`` × lift) is dropped — the ζ → 0 limit, a
    bounded steady state, stated in ``Response.notes``; one that is not zero has no bounded steady state
    and raises ``ResonanceError`` naming the harmonic and its amplitude.

    Parameters
    ----------
    law_or_spectrum : MotionLaw or LawSpectrum
        The law (mm or rad) or its sampled spectrum (``law_spectrum``).
    follower : ElasticFollower
        Natural frequency (Hz) and damping ratio; constant stiffness.
    rpm : float
        Cam speed, rpm.
    samples : int
        Samples per cycle when a law is given.
    external : callable or None
        Load per unit mass, θ (rad) → law units/s².

    Returns
    -------
    Response
        Sampled over one cycle; law units, law units/s².

    Examples
    --------
    >>> from camcad.law.standard import compose
    >>> law = compose([("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)], 25.0, "cycloidal")
    >>> r = steady_state_frequency(law, ElasticFollower(6.0, 0.0), 60.0, samples=1024)   # harmonic 6 is zero
    >>> "zeta -> 0 limit" in r.notes[0]
    True
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
    forcing = big_omega**2 * spectrum.coefficients
    f_grid = _external_on_grid(external, spectrum.theta)
    if external is not None:
        forcing = forcing + np.fft.rfft(f_grid) / n
    # the Nyquist term (the last) is dropped below, so its denominator does not matter
    resonant = np.flatnonzero(np.abs(denominator[:-1]) <= RESONANCE_DETUNING * wn**2)
    notes = []
    for index in resonant:
        k = int(index)
        amplitude = 2.0 * abs(forcing[k]) / big_omega[k]**2
        if amplitude > ZERO_HARMONIC * spectrum.lift:
            raise ResonanceError(
                f"the follower (fn {follower.natural_frequency_hz:g} Hz, damping ratio {zeta:g}) is in resonance "
                f"with harmonic {k} of the law (amplitude {amplitude:.3g}, law units) at {rpm:g} rpm: "
                "no bounded periodic steady state", rpm, k, float(amplitude))
        denominator[k] = 1.0
        forcing[k] = 0.0
        notes.append(f"harmonic {k} is in exact resonance at {rpm:g} rpm but its amplitude is zero "
                     f"({amplitude:.2g}): the steady state is the zeta -> 0 limit, without that harmonic")
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
                    accel_elastic - f_grid, "frequency", tuple(notes))


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
        scalar = getattr(self.law, "acceleration_at", None)   # the standard and drawn laws' fast path
        a = scalar(theta) if scalar is not None else float(self.law.kinematics(np.array([theta])).a[0])
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
    for lo, hi in itertools.pairwise(cuts):
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

    Works with variable stiffness. Output at ``samples`` uniform points per cycle.

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, s in mm).
    follower : ElasticFollower
        The follower (Hz; its stiffness table, dimensionless).
    rpm : float
        The speed, rpm.
    samples : int
        Points per cycle (a count).
    method : str
        A solve_ivp method.
    rtol : float
        Relative tolerance (dimensionless).
    atol : float, optional
        Absolute tolerance, mm and mm/rad (default rtol × 1e-3 × lift: the dynamic error is a small
        fraction of the lift, so a looser atol would dominate).
    external : callable, optional
        θ (rad) → external load per unit mass, mm/s².

    Returns
    -------
    Response
        The periodic response (rad, mm, mm/s²).

    Examples
    --------
    The harmonic law at r = 0.4 (``camcad.steady_state``'s example): the elastic peak is 1/(1 − r²) times the
    rigid one.

    >>> import camcad
    >>> law = camcad.compose([("rise", 180), ("return", 180)], 20.0, "harmonic")       # s = 10 - 10 cos(theta), mm
    >>> from camcad.dynamics import steady_state_time
    >>> response = steady_state_time(law, camcad.ElasticFollower(10.0), 240.0, samples=256)
    >>> round(response.peak_accel_ratio, 6), round(1 / (1 - 0.4 ** 2), 6)
    (1.190476, 1.190476)
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
        raise ResonanceError(f"the follower is in resonance at {rpm:g} rpm (a free vibration repeats itself each "
                             f"cycle within {gap:.2g}): no unique periodic steady state", rpm,
                             fix="give a damping ratio > 0, another speed, or a tighter --rtol")
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
    """Start-up: march from θ_start with x = x0, ẋ = xdot0 to θ_end.

    Knobs as ``steady_state_time``; output at ``samples`` points from θ_start to θ_end.

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, s in mm).
    follower : ElasticFollower
        The follower (Hz).
    rpm : float
        The speed, rpm.
    theta_end : float
        Where to stop, rad of cam angle.
    theta_start : float
        Where to start, rad.
    x0 : float
        The dynamic error at the start, mm.
    xdot0 : float
        Its rate, mm/s.
    samples : int
        Points returned (a count).
    method : str
        A solve_ivp method.
    rtol : float
        Relative tolerance (dimensionless).
    atol : float, optional
        Absolute tolerance, mm.
    external : callable, optional
        θ (rad) → external load per unit mass, mm/s².

    Returns
    -------
    Transient
        theta (rad), the dynamic error x (mm) and its rate dx/dθ (mm/rad), the accelerations (mm/s²).

    Examples
    --------
    From rest on a dwell nothing moves:

    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> import math
    >>> from camcad.dynamics import transient_time
    >>> start = transient_time(law, camcad.ElasticFollower(10.0), 60.0, math.radians(360.0),
    ...                        theta_start=math.radians(270.0), samples=11)
    >>> float(abs(start.dynamic_error).max())
    0.0
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
    """The periodic steady-state response of an elastic follower at one speed.

    With the dynamic error x = y − s the model is ẍ + 2ζωn ẋ + ωn² φ(θ) x = −s̈ + F/m, s̈ = ω² a(θ),
    θ = ωt (``camcad.dynamics.model``). "frequency": each harmonic of s through the frequency response
    X_k = (Ω_k² S_k + F_k/m)/(ωn² − Ω_k² + 2iζωnΩ_k), Ω_k = kνω — exact for constant stiffness to the
    sampling error; "time": time marching (scipy's solve_ivp) and shooting for the periodic state, for
    a stiffness that varies with θ too.

    Parameters
    ----------
    law : MotionLaw
        The law: θ in rad, s in mm (or rad of swing), a in mm/rad²; it must close (balanced).
    follower : ElasticFollower
        Natural frequency (Hz), damping ratio, optional mass (kg) and stiffness variation.
    rpm : float
        Cam speed n, rpm (ω = 2πn/60 rad/s).
    method : str
        "frequency", "time" or "auto" (frequency when the stiffness is constant).
    samples : int
        Samples per cycle (a count): the accuracy knob of the frequency path and the output grid.
    solver : str
        The solve_ivp method of the time path ("RK45", "DOP853", "Radau", …).
    rtol : float
        Relative tolerance of the time path (dimensionless).
    external : callable, optional
        A periodic external load per unit mass, θ (rad) → mm/s² (law units/s²).

    Returns
    -------
    Response
        Over one cycle at ``theta`` (rad): ``displacement_rigid`` s (mm), ``dynamic_error`` x (mm),
        ``accel_rigid`` s̈ and ``accel_elastic`` ÿ (mm/s²), ``link_accel`` (mm/s²); ``peak_accel_ratio``
        max|ÿ|/max|s̈| (dimensionless) and ``dynamic_error_max`` (mm).

    Raises
    ------
    ResonanceError
        A CamcadError: the follower is in exact resonance with a non-zero harmonic (no bounded
        periodic steady state).

    References
    ----------
    R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 8–9.
    I. I. Vulfson, Dynamics of Cyclic Machines, Springer (2015), ch. 2–3.

    Examples
    --------
    The full-cycle harmonic law s = 10 − 10 cos θ (mm) is one harmonic, so the steady state is the
    single-degree-of-freedom frequency response: at a frequency ratio r = Ω/ωn = 4 Hz / 10 Hz = 0.4
    (240 rpm, fn 10 Hz, no damping) the elastic acceleration is 1/(1 − r²) times the rigid one and the
    dynamic error is 10 r²/(1 − r²) mm:

    >>> import camcad
    >>> law = camcad.compose([("rise", 180), ("return", 180)], 20.0, "harmonic")
    >>> response = camcad.steady_state(law, camcad.ElasticFollower(10.0), 240.0)
    >>> r = 0.4
    >>> round(response.peak_accel_ratio, 9), round(1.0 / (1.0 - r**2), 9)
    (1.19047619, 1.19047619)
    >>> round(response.dynamic_error_max, 9), round(10.0 * r**2 / (1.0 - r**2), 9)
    (1.904761905, 1.904761905)

    The time path (marching and shooting) agrees:

    >>> marched = camcad.steady_state(law, camcad.ElasticFollower(10.0), 240.0, method="time", samples=256)
    >>> round(marched.peak_accel_ratio, 6)
    1.190476
    """
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
    """Figures of the steady state over a list of speeds (rpm); ``sweep`` returns it.

    Attributes
    ----------
    speeds_rpm : ndarray
        The speeds, rpm.
    peak_accel_ratio : ndarray
        Elastic over rigid peak acceleration, one per speed (dimensionless).
    dynamic_error_max : ndarray
        The largest dynamic error, law units (mm or rad).
    peak_accel_rigid, peak_accel_elastic : ndarray
        The rigid and elastic peak accelerations, law units/s² (mm/s² or rad/s²).
    method : str
        "frequency" or "time".
    responses : dict
        {rpm: Response} for the speeds asked for.
    unbounded : dict
        {rpm: reason} of each speed without a bounded steady state (``ResonanceError``); its ratio, error and
        elastic peak are +inf.
    notes : dict
        {rpm: notes of its response} (e.g. the ζ → 0 limit at an exact resonance with a zero harmonic).
    """

    speeds_rpm: np.ndarray
    peak_accel_ratio: np.ndarray
    dynamic_error_max: np.ndarray
    peak_accel_rigid: np.ndarray
    peak_accel_elastic: np.ndarray
    method: str
    responses: dict = field(default_factory=dict)
    unbounded: dict = field(default_factory=dict)
    notes: dict = field(default_factory=dict)


def sweep(law: MotionLaw, follower: ElasticFollower, speeds_rpm, *, method: str = "auto",
          samples: int = DEFAULT_SAMPLES, solver: str = "RK45", rtol: float = 1e-8, external_at=None,
          keep=(), progress: Callable[[int, int], None] | None = None) -> Sweep:
    """Steady state at every speed.

    A speed without a bounded steady state (exact resonance with a harmonic that is not zero) does not stop the
    sweep: it is listed in ``Sweep.unbounded`` with +inf figures.

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, s in mm or rad).
    follower : ElasticFollower
        The follower (Hz, dimensionless damping).
    speeds_rpm : sequence of float
        The speeds, rpm.
    method : str
        "auto", "frequency" or "time" (as ``camcad.steady_state``).
    samples : int
        Points per cycle (a count).
    solver : str
        The solve_ivp method of the time path.
    rtol : float
        Relative tolerance of the time path (dimensionless).
    external_at : callable, optional
        rpm → the external load at that speed (θ in rad → mm/s²), or None.
    keep : sequence of float
        Speeds (rpm) whose full Response is kept.
    progress : callable, optional
        Called as progress(done, total) after each speed (counts).

    Returns
    -------
    Sweep
        One figure per speed: ratios (dimensionless), errors (law units), peaks (law units/s²).

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 180), ("return", 180)], 20.0, "harmonic")       # s = 10 - 10 cos(theta), mm
    >>> from camcad.dynamics import sweep
    >>> result = sweep(law, camcad.ElasticFollower(10.0), [240.0, 360.0])
    >>> [round(float(x), 6) for x in result.peak_accel_ratio], [round(1 / (1 - r * r), 6) for r in (0.4, 0.6)]
    ([1.190476, 1.5625], [1.190476, 1.5625])
    """
    speeds = np.atleast_1d(np.asarray(speeds_rpm, dtype=float))
    if method == "auto":
        method = "frequency" if follower.constant_stiffness else "time"
    spectrum = law_spectrum(law, samples) if method == "frequency" else None
    peak_analog = float(np.max(np.abs(spectrum.a))) if spectrum is not None else \
        float(np.max(np.abs(law.kinematics(law.cycle * np.arange(samples) / samples).a)))
    keep = {float(k) for k in keep}
    ratio, error, rigid, elastic = (np.empty(len(speeds)) for _ in range(4))
    responses: dict = {}
    unbounded: dict = {}
    notes: dict = {}
    if method == "frequency" and external_at is None:
        _broadcast_sweep(cast(LawSpectrum, spectrum), follower, speeds, keep, progress,
                         (ratio, error, rigid, elastic), responses, unbounded, notes)
        return Sweep(speeds, ratio, error, rigid, elastic, method, responses, unbounded, notes)
    for i, rpm in enumerate(speeds):
        external = external_at(rpm) if external_at else None
        try:
            if method == "frequency":
                response = steady_state_frequency(cast(LawSpectrum, spectrum), follower, rpm, external=external)
            else:
                response = steady_state(law, follower, rpm, method=method, samples=samples, solver=solver,
                                        rtol=rtol, external=external)
        except ResonanceError as err:
            unbounded[float(rpm)] = err
            ratio[i] = error[i] = elastic[i] = math.inf
            rigid[i] = peak_analog * rpm_to_rad_s(rpm)**2
        else:
            ratio[i] = response.peak_accel_ratio
            error[i] = response.dynamic_error_max
            rigid[i] = response.peak_accel_rigid
            elastic[i] = response.peak_accel_elastic
            if response.notes:
                notes[float(rpm)] = response.notes
            if float(rpm) in keep:
                responses[float(rpm)] = response
        if progress:
            progress(i + 1, len(speeds))
    return Sweep(speeds, ratio, error, rigid, elastic, method, responses, unbounded, notes)


#: speeds per block of the broadcast sweep (a block holds speeds × samples complex harmonics)
SWEEP_BLOCK = 16


def _broadcast_sweep(spectrum: LawSpectrum, follower: ElasticFollower, speeds: np.ndarray, keep: set, progress,
                     figures, responses: dict, unbounded: dict, notes: dict) -> None:
    """The frequency path over many speeds at once: the harmonics of every speed of a block in one array,
    two inverse FFTs along its rows (the same arithmetic, speed by speed, as ``steady_state_frequency``, which
    still takes any speed in exact resonance, where it decides whether a bounded state exists)."""
    ratio, error, rigid, elastic = figures
    n = spectrum.samples
    wn, zeta = follower.omega_n, follower.damping_ratio
    orders = spectrum.orders
    peak_a = float(np.max(np.abs(spectrum.a)))
    for first in range(0, len(speeds), SWEEP_BLOCK):
        block = speeds[first:first + SWEEP_BLOCK]
        omega = np.array([rpm_to_rad_s(float(rpm)) for rpm in block])
        big_omega = orders[None, :] * omega[:, None]
        denominator = wn**2 - big_omega**2 + 2j * zeta * wn * big_omega
        resonant = np.any(np.abs(denominator[:, :-1]) <= RESONANCE_DETUNING * wn**2, axis=1)
        x_k = big_omega**2 * spectrum.coefficients / np.where(np.abs(denominator) > 0, denominator, 1.0)
        x_k[:, -1] = 0.0
        y_k = spectrum.coefficients + x_k
        y_k[:, -1] = 0.0
        x = np.fft.irfft(x_k * n, n, axis=1)
        accel = np.fft.irfft(-big_omega**2 * y_k * n, n, axis=1)
        for row, rpm in enumerate(block):
            i = first + row
            if resonant[row]:       # the scalar path decides (zero harmonic dropped, or no bounded state)
                try:
                    response = steady_state_frequency(spectrum, follower, float(rpm))
                except ResonanceError as err:
                    unbounded[float(rpm)] = err
                    ratio[i] = error[i] = elastic[i] = math.inf
                    rigid[i] = peak_a * rpm_to_rad_s(float(rpm))**2
                else:
                    ratio[i], error[i] = response.peak_accel_ratio, response.dynamic_error_max
                    rigid[i], elastic[i] = response.peak_accel_rigid, response.peak_accel_elastic
                    if response.notes:
                        notes[float(rpm)] = response.notes
                    if float(rpm) in keep:
                        responses[float(rpm)] = response
            else:
                accel_rigid_peak = float(np.max(np.abs(omega[row]**2 * spectrum.a)))
                elastic[i] = float(np.max(np.abs(accel[row])))
                rigid[i] = accel_rigid_peak
                ratio[i] = elastic[i] / accel_rigid_peak
                error[i] = float(np.max(np.abs(x[row])))
                if float(rpm) in keep:
                    responses[float(rpm)] = Response(float(rpm), spectrum.theta, spectrum.s, x[row].copy(),
                                                     omega[row]**2 * spectrum.a, accel[row].copy(),
                                                     accel[row] - np.zeros_like(spectrum.theta), "frequency", ())
            if progress:
                progress(i + 1, len(speeds))
