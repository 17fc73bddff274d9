"""Residual vibration after a motion phase that starts from rest (Duhamel integral; closed form for cycloidal).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camcad.balance.conditions import DEFAULT_TOL as BALANCE_TOLERANCE
from camcad.dynamics.model import ElasticFollower, rpm_to_rad_s
from camcad.dynamics.steady import transient_time
from camcad.errors import CamcadError
from camcad.law.law import MotionLaw, Phase

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



# --------------------------------------------------------------------------------------------
# Residual vibration after each motion phase
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Residual:
    """Residual vibration after one motion phase started from rest: amplitude (mm) and the state at its end.

    ``camcad.residual_vibration`` returns one per motion; the example is there.

    Attributes
    ----------
    phase : Phase
        The motion (rad).
    amplitude : float
        The free vibration's amplitude after it, mm (rad for a swing).
    x_end : float
        The dynamic error at the phase's end, mm.
    xdot_end : float
        Its rate there, mm/s.
    rpm : float
        The speed, rpm.
    """

    phase: Phase
    amplitude: float
    x_end: float
    xdot_end: float
    rpm: float


def motion_phases(law: MotionLaw) -> tuple[Phase, ...]:
    """The law's motions from rest to rest: its rises and returns, a phase that blends into the next one in
    motion (it states an end velocity, as the segments of a poly5 into a constant velocity do) joined to it."""
    found: list[Phase] = []
    blending = False
    for p in law.phases:
        if p.kind not in ("rise", "return"):
            blending = False
            continue
        if blending and found:
            last = found[-1]
            found[-1] = Phase(last.kind, last.start, p.end, p.s_end, p.v_end)
        else:
            found.append(p)
        blending = p.v_end != 0.0
    return tuple(found)


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
    """The residual vibration after each rise and return that starts from rest, at one speed.

    The amplitude of the free vibration after a motion phase of duration T started from rest:
    A = √(x_T² + ((ẋ_T + ζωn x_T)/ωd)²). method "duhamel": A = |∫₀ᵀ g(τ) e^{−ζωn(T−τ)} e^{−iωdτ} dτ| / ωd
    with g = −s̈ (mm/s²), by composite Gauss–Legendre quadrature (``panels`` equal panels, split further
    at the knots of a drawn law, ``nodes`` points each). method "time": solve_ivp over the phase from
    x = ẋ = 0. Both use the nominal stiffness.

    Parameters
    ----------
    law : MotionLaw
        The law: θ in rad, s in mm (or rad of swing), a in mm/rad².
    follower : ElasticFollower
        Natural frequency (Hz) and damping ratio.
    rpm : float
        Cam speed, rpm.
    method : str
        "duhamel" (quadrature of the Duhamel integral) or "time" (time marching).
    panels : int
        Equal quadrature panels per phase (a count).
    nodes : int
        Gauss–Legendre nodes per panel (a count).
    solver : str
        The solve_ivp method of the time path.
    rtol : float
        Relative tolerance of the time path (dimensionless).
    atol : float, optional
        Absolute tolerance of the time path, mm (and mm/rad for x′); default from ``rtol`` and the lift.
    phases : tuple of Phase, optional
        The phases to analyse (rad); default every rise and return of the law.

    Returns
    -------
    list of Residual
        One per phase: ``phase`` (rad), ``amplitude`` A (mm, or rad of swing), ``x_end`` (mm) and
        ``xdot_end`` (mm/s) at the end of the phase, ``rpm``.

    References
    ----------
    R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 9 (residual vibration;
    the cycloidal rise's closed form).
    A. A. Yablonsky, S. S. Noreiko, Course of the Theory of Vibrations (2007) (the Duhamel integral).

    Examples
    --------
    After a cycloidal rise of h = 20 mm lasting T, an undamped follower of natural frequency fn keeps
    vibrating with A = h |sin πr| / (π r |r² − 1|), r = T fn. A 90° rise at 60 rpm lasts 0.25 s; with
    fn = 10 Hz, r = 2.5:

    >>> import math
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> rise, back = camcad.residual_vibration(law, camcad.ElasticFollower(10.0), 60.0)
    >>> r = 0.25 * 10.0
    >>> round(rise.amplitude, 9), round(20.0 * abs(math.sin(math.pi * r)) / (math.pi * r * abs(r * r - 1.0)), 9)
    (0.485043636, 0.485043636)
    >>> rise.phase.kind, back.phase.kind
    ('rise', 'return')
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

    Parameters
    ----------
    lift : float
        h, mm.
    rise_time_s : float
        T, the rise's duration, s.
    natural_frequency_hz : float
        fn, Hz.

    Returns
    -------
    float
        The amplitude A, mm.

    Examples
    --------
    >>> from camcad.dynamics import cycloidal_residual_amplitude
    >>> round(cycloidal_residual_amplitude(20.0, 0.25, 10.0), 9), cycloidal_residual_amplitude(20.0, 0.1, 10.0)
    (0.485043636, 10.0)
    """
    r = rise_time_s * natural_frequency_hz
    if abs(r - 1.0) < 1e-9:
        return lift / 2.0
    return lift * abs(math.sin(math.pi * r)) / (math.pi * r * abs(r * r - 1.0))




