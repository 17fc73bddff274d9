"""Polydyne (dynamic compensation): the cam that makes the elastic follower do the wanted law at a design speed.

The single-DOF elastic follower of ``camcad.dynamics.model``, m ÿ + b (ẏ − ṡ) + c (y − s) = 0, follows the cam's
motion s(θ) with a dynamic error. Asking instead that the driven mass move exactly as the wanted law y(θ) and
solving for the cam gives, with θ = ω t, K = (ω/ωn)² and λ = 2ζω/ωn (rad of cam angle),

    s + λ s' = y + λ y' + K y''        (' = d/dθ),

so the cam's motion is s = y + u with u + λ u' = K y''. Without damping (ζ = 0) this is the classical polydyne
cam s = y + (m/c) ÿ = y + K y'' (Stoddart 1953; Norton, Cam Design and Manufacturing Handbook, 2nd ed., 2009,
ch. 10). With the chain's damping the first-order equation is solved exactly for its periodic solution:
between the law's breakpoints u(θ) = e^{−(θ−b)/λ} u(b⁺) + ∫₀^{(θ−b)/λ} e^{−x} K y''(θ − λx) dx (graded
Gauss–Legendre panels in x), at a breakpoint u is continuous, and periodicity fixes u(0). Its derivatives solve
the same equation with K y^(k+2) as forcing and a jump K[y^(k+1)]/λ wherever y^(k+1) jumps. (Norton writes the
damper to the ground, m ÿ + c_d ẏ + k y = k s, which gives s = y + (m/k) ÿ + (c_d/k) ẏ; camcad's chain damps the
relative motion, hence the equation above. Both are the same cam without damping.)

Limits. The cam's derivatives are s^(k) = y^(k) + K y^(k+2) (ζ = 0): its velocity is continuous only if the law's
jerk y''' is (class C³), its acceleration only if y'''' is (C⁴), its jerk only if y^(5) is (C⁵). A law of class
C² or less (cycloidal, 3-4-5 polynomial: their jerk jumps against the dwells) gives a cam whose velocity jumps —
refused. 4-5-6-7 (C³) gives a cam whose acceleration jumps, and with it the curvature of its profile; 5-6-7-8-9
(``poly56789``, C⁴) a continuous acceleration with a jerk that jumps. The compensation is exact at the design
speed only: at another speed n the cam's K y'' no longer matches, and the residual vibration comes back
(``residual_about``), growing with |n² − n_d²| — it is reported at every speed of the scene.

Sources: D. A. Stoddart, "Polydyne cam design", Machine Design 25 (1953); R. L. Norton, Cam Design and
Manufacturing Handbook, 2nd ed. (2009), ch. 10 (polydyne cams); the single-DOF model of camcad.dynamics.model.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from camcad.arrays import unique
from camcad.dynamics.model import ElasticFollower
from camcad.errors import CamcadError
from camcad.law.law import Kinematics, Phase

#: highest derivative the cam needs (its jerk): the law's derivatives up to order 5
ORDERS = 4
#: graded panels (in units of λ) of the kernel e^{−x}; beyond the last the kernel is below e^{-40} ≈ 4e-18
_X_EDGES = np.array([0.0, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 28.0, 40.0])
_GAUSS = np.polynomial.legendre.leggauss(12)
#: a jump of a law's derivative smaller than this fraction of the derivative's peak is round-off
JUMP_FRACTION = 1e-9


def law_class(law, breakpoints) -> tuple[int, list[tuple[int, float, float]]]:
    """The law's smoothness at its breakpoints: (r, jumps), r the largest order with y, y', …, y^(r) continuous
    (capped at 5), jumps [(order k, θ rad, [y^(k)] mm/rad^k)] of the derivatives up to order 5 that jump."""
    cycle = float(law.cycle)
    inner = 1e-12 * cycle
    grid = np.linspace(0.0, cycle, 4001)
    found: list[tuple[int, float, float]] = []
    for order in range(1, 6):
        peak = float(np.max(np.abs(_derivative(law, grid, order)))) or 1.0
        for b in breakpoints:
            left = b - inner if b > 0 else cycle - inner
            right = b + inner if b < cycle else inner
            jump = float(_derivative(law, np.array([right]), order)[0] - _derivative(law, np.array([left]), order)[0])
            if abs(jump) > JUMP_FRACTION * peak:
                found.append((order, float(b % cycle), jump))
    orders = [k for k, _, _ in found]
    return (min(orders) - 1 if orders else 5), found


def _derivative(law, theta, order: int) -> np.ndarray:
    try:
        return np.asarray(law.derivative(np.asarray(theta, dtype=float), order), dtype=float)
    except (AttributeError, ValueError):
        raise CamcadError(f"the law has no derivative of order {order} in closed form (a drawn law's jerk jumps at "
                          "every vertex; modified trapezoid, modified sine and SCCA are pieced)", "polydyne",
                          "give the law as a standard shape: poly56789 (class C4), poly4567 (C3), harmonic or "
                          "cycloidal") from None


def _breakpoints(law) -> np.ndarray:
    points = {0.0, float(law.cycle)}
    for phase in law.phases:
        points.update((float(phase.start), float(phase.end)))
    inner = getattr(law, "breakpoints", None)
    if inner is not None:
        points.update(float(x) for x in np.asarray(inner()))
    return unique(np.array(sorted(p for p in points if 0.0 <= p <= float(law.cycle))))


class _Lag:
    """The periodic solution u of u + λ u' = K y''(θ) and its derivatives (module docstring).

    Within each panel between the law's breakpoints u = u_p + C_i e^{−(θ − b_i)/λ}: the particular solution
    u_p = K Σ_j (−λ)^j y^(2+j) (a finite sum for a polynomial law, a geometric series of ratio λΩ for a sine
    of frequency Ω) and a decaying homogeneous term whose C_i make u continuous at every breakpoint and periodic
    over the cycle. Derivatives: u^(k) = u_p^(k) + C_i (−1/λ)^k e^{−(θ − b_i)/λ}. ``converged`` is False when
    the series does not settle to round-off within ``MAX_TERMS`` terms (λΩ near or above 1): the caller falls back
    to ``_LagByQuadrature``.
    """

    MAX_TERMS = 60

    def __init__(self, wanted, k: float, lam: float, edges: np.ndarray, cycle: float) -> None:
        self.wanted, self.k, self.lam, self.edges, self.cycle = wanted, k, lam, edges, cycle
        grid = np.linspace(0.0, cycle, 2001)
        first = float(np.max(np.abs(_derivative(wanted, grid, 2)))) or 1.0
        self.terms, self.converged = 1, False
        for j in range(1, self.MAX_TERMS):
            size = lam**j * float(np.max(np.abs(_derivative(wanted, grid, 2 + j))))
            if size <= 1e-17 * first:
                self.terms, self.converged = j, True
                break
        if not self.converged:
            return
        before = np.nextafter(edges[1:], -np.inf)          # the panel's own side of its end
        left = self.particular(before, 0)
        right = self.particular(edges[:-1], 0)
        decay = np.exp(-np.diff(edges) / lam)
        # C_{i+1} = u(b_{i+1}⁻) − u_p(b_{i+1}⁺) = left_i + C_i decay_i − right_{i+1}; periodic: C_m ≡ C_0
        count = len(decay)
        coefficient = np.zeros(count)
        value, gain = 0.0, 1.0
        for i in range(count):
            value = value * decay[i] + left[i] - right[(i + 1) % count]
            gain *= decay[i]
        c0 = value / (1.0 - gain)
        coefficient[0] = c0
        for i in range(count - 1):
            coefficient[i + 1] = coefficient[i] * decay[i] + left[i] - right[i + 1]
        self.coefficient = coefficient

    def particular(self, theta, order: int) -> np.ndarray:
        out = np.zeros_like(np.asarray(theta, dtype=float))
        for j in range(self.terms):
            out += (-self.lam) ** j * _derivative(self.wanted, theta, 2 + j + order)
        return self.k * out

    def __call__(self, theta, order: int) -> np.ndarray:
        theta = np.asarray(theta, dtype=float)
        wrapped = np.mod(theta, self.cycle)
        index = np.clip(np.searchsorted(self.edges, wrapped, side="right") - 1, 0, len(self.coefficient) - 1)
        since = wrapped - self.edges[index]
        return (self.particular(wrapped, order)
                + self.coefficient[index] * (-1.0 / self.lam) ** order * np.exp(-since / self.lam))


class _LagByQuadrature:
    """The same periodic solution, one derivative order at a time: w + λ w' = g(θ) with jumps J_i at the
    breakpoints; w(θ) = e^{−(θ−b)/λ} w(b⁺) + ∫₀^{(θ−b)/λ} e^{−x} g(θ − λx) dx by graded Gauss–Legendre panels.
    Slower than the series; used where the series does not converge (λ times the law's frequency near 1)."""

    def __init__(self, forcing, edges: np.ndarray, jumps: np.ndarray, lam: float, cycle: float) -> None:
        self.forcing, self.edges, self.lam, self.cycle = forcing, edges, lam, cycle
        decay = np.exp(-np.diff(edges) / lam)
        pieces = np.array([self._integral(np.array([b]), np.array([b - a]))[0]
                           for a, b in itertools.pairwise(edges)])
        # w(b_{i+1}⁻) = decay_i w(b_i⁺) + piece_i; w(b_{i+1}⁺) = w(b_{i+1}⁻) + J_{i+1}; w(b_0⁺) = w(b_m⁻) + J_0
        value = 0.0
        for i in range(len(decay)):
            value = decay[i] * value + pieces[i] + (jumps[i + 1] if i + 1 < len(decay) else 0.0)
        total_decay = float(np.prod(decay))
        first = (value + jumps[0]) / (1.0 - total_decay)
        starts = [first]
        value = first
        for i in range(len(decay) - 1):
            value = decay[i] * value + pieces[i] + jumps[i + 1]
            starts.append(value)
        self.starts = np.array(starts)            # w(b_i⁺), i = 0 .. m-1

    def _integral(self, theta: np.ndarray, span: np.ndarray) -> np.ndarray:
        """∫₀^{span/λ} e^{−x} g(θ − λx) dx for each θ (arrays), graded Gauss–Legendre panels."""
        u, w = _GAUSS
        top = span / self.lam
        out = np.zeros_like(theta)
        for lo, hi in itertools.pairwise(_X_EDGES):
            a = np.minimum(lo, top)
            b = np.minimum(hi, top)
            half = 0.5 * (b - a)
            if not np.any(half > 0):
                continue
            x = (0.5 * (a + b))[:, None] + half[:, None] * u[None, :]
            values = self.forcing(theta[:, None] - self.lam * x)
            out += np.sum(np.exp(-x) * values * w[None, :], axis=1) * half
        return out

    def __call__(self, theta) -> np.ndarray:
        theta = np.mod(np.asarray(theta, dtype=float), self.cycle)
        index = np.clip(np.searchsorted(self.edges, theta, side="right") - 1, 0, len(self.starts) - 1)
        since = theta - self.edges[index]
        return np.exp(-since / self.lam) * self.starts[index] + self._integral(theta, since)


@dataclass(frozen=True)
class PolydyneLaw:
    """The polydyne cam's motion law (a MotionLaw: ``cycle``, ``phases``, ``kinematics``), module docstring.

    Parameters
    ----------
    wanted : MotionLaw
        The law the driven mass must do, with ``derivative(theta, order)`` up to order 5 (a composed standard
        law); θ rad, s in its unit (mm, or rad of swing).
    follower : ElasticFollower
        Natural frequency (Hz) and damping ratio of the single-DOF follower.
    rpm : float
        The design speed, rpm.

    Examples
    --------
    Undamped, s = y + (ω/ωn)² y'': at 300 rpm and 50 Hz K = (5/50)² = 0.01:

    >>> import numpy as np, camcad
    >>> law = camcad.compose([("rise", 120), ("dwell", 60), ("return", 120), ("dwell", 60)], 10.0, "poly56789")
    >>> cam = PolydyneLaw(law, camcad.ElasticFollower(50.0), 300.0)
    >>> t = np.array([0.6])
    >>> bool(np.isclose(cam.kinematics(t).s, law.kinematics(t).s + 0.01 * law.kinematics(t).a, rtol=1e-14))
    True
    """

    wanted: object
    follower: ElasticFollower
    rpm: float

    @property
    def cycle(self) -> float:
        return float(self.wanted.cycle)          # type: ignore[attr-defined]

    @property
    def phases(self) -> tuple[Phase, ...]:
        return tuple(self.wanted.phases)         # type: ignore[attr-defined]

    @property
    def ratio(self) -> float:
        """K = (ω/ωn)² (rad² of cam angle: m/c times ω²)."""
        return (2.0 * math.pi * self.rpm / 60.0 / self.follower.omega_n) ** 2

    @property
    def lag(self) -> float:
        """λ = 2ζω/ωn, rad of cam angle (b/c times ω)."""
        return 2.0 * self.follower.damping_ratio * (2.0 * math.pi * self.rpm / 60.0) / self.follower.omega_n

    def breakpoints(self) -> np.ndarray:
        return _breakpoints(self.wanted)

    def _lag(self):
        """The solver of u + λ u' = K y'' (the series, else the quadrature per order), built once."""
        cached = getattr(self, "_lag_cache", None)
        if cached is not None:
            return cached
        edges = self.breakpoints()
        k, lam = self.ratio, self.lag
        series = _Lag(self.wanted, k, lam, edges, self.cycle)
        if series.converged:
            solver = series
        else:
            orders = []
            inner = 1e-12 * self.cycle
            for order in range(ORDERS):
                jumps = np.zeros(len(edges))
                if order >= 1:
                    for i, b in enumerate(edges[:-1]):
                        left = b - inner if b > 0 else self.cycle - inner
                        step = _derivative(self.wanted, np.array([b + inner, left]), order + 1)
                        jumps[i] = k * (step[0] - step[1]) / lam
                orders.append(_LagByQuadrature(lambda t, n=order: k * _derivative(self.wanted, t, n + 2), edges,
                                               jumps, lam, self.cycle))
            solver = lambda theta, order: orders[order](theta)  # noqa: E731
        object.__setattr__(self, "_lag_cache", solver)
        return solver

    def correction(self, theta, order: int = 0) -> np.ndarray:
        """u^(k)(θ) = s^(k) − y^(k) (the law's unit per rad^k) of order k = 0..3."""
        theta = np.asarray(theta, dtype=float)
        if self.follower.damping_ratio == 0.0:
            return self.ratio * _derivative(self.wanted, theta, order + 2)
        return self._lag()(theta, order)

    def kinematics(self, theta) -> Kinematics:
        theta = np.asarray(theta, dtype=float)
        y = self.wanted.kinematics(theta)        # type: ignore[attr-defined]
        return Kinematics(theta, y.s + self.correction(theta, 0), y.v + self.correction(theta, 1),
                          y.a + self.correction(theta, 2), y.j + self.correction(theta, 3))


def polydyne_law(wanted, follower: ElasticFollower, rpm: float) -> tuple[PolydyneLaw, list[str]]:
    """The polydyne cam for ``wanted`` at ``rpm`` and the notes on its smoothness (module docstring).

    Parameters
    ----------
    wanted : MotionLaw
        The law the driven mass must do (a composed standard law: its derivatives up to order 5 exist).
    follower : ElasticFollower
        fn (Hz) and ζ (dimensionless) of the single-DOF follower.
    rpm : float
        The design speed, rpm.

    Returns
    -------
    (PolydyneLaw, list of str)
        The cam's motion law (θ rad; s in the law's unit, mm or rad) and the notes on its class and jumps.

    Raises
    ------
    CamcadError
        A law without closed-form derivatives, or of class below C³ (the cam's velocity would jump).

    Examples
    --------
    >>> import camcad
    >>> law = camcad.compose([("rise", 120), ("dwell", 60), ("return", 120), ("dwell", 60)], 10.0, "poly4567")
    >>> cam, notes = polydyne_law(law, camcad.ElasticFollower(60.0, 0.05), 400.0)
    >>> "class C3" in notes[0]
    True
    """
    if not (math.isfinite(rpm) and rpm > 0.0):
        raise CamcadError(f"the polydyne design speed {rpm:g} rpm is not a speed", "polydyne",
                          "give the speed the cam is designed for, rpm")
    breakpoints = _breakpoints(wanted)
    smooth, jumps = law_class(wanted, breakpoints)
    cam = PolydyneLaw(wanted, follower, float(rpm))
    k = cam.ratio
    notes = [f"polydyne cam for {rpm:g} rpm: K = (w/wn)^2 = {k:.6g} rad^2, lag 2 zeta w/wn = {cam.lag:.6g} rad; "
             f"the law is of class C{smooth}"]
    first = {order: (b, size) for order, b, size in reversed(jumps)}
    if smooth < 3:
        order = smooth + 1
        b, size = first[order]
        raise CamcadError(f"the law's derivative of order {order} jumps by {size:.6g} at {math.degrees(b):.6g} deg "
                          f"(class C{smooth}): the polydyne cam's velocity would jump by K x that "
                          f"({k * size:.6g} per rad)" if order == 3 else
                          f"the law's derivative of order {order} jumps at {math.degrees(b):.6g} deg (class "
                          f"C{smooth}): the polydyne cam would have a corner", "polydyne",
                          "use a law of class C4 such as poly56789 (or poly4567, class C3, with an acceleration "
                          "step in the cam)")
    if smooth == 3:
        b, size = first[4]
        notes.append(f"the cam's acceleration jumps by {k * size:.6g} per rad^2 at {math.degrees(b):.6g} deg (the "
                     "law is C3, not C4): its profile's curvature jumps there; poly56789 (C4) avoids it")
    elif smooth == 4:
        b, size = first[5]
        notes.append(f"the cam's jerk jumps by {k * size:.6g} per rad^3 at {math.degrees(b):.6g} deg (the law is C4, "
                     "not C5): a finite step, as a 3-4-5 law's")
    return cam, notes


# --------------------------------------------------------------------------------------------
# Residual vibration about the wanted law
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class PhaseResidual:
    """The free vibration of the driven mass about the wanted law after one motion phase at one speed:
    ``amplitude`` (the law's unit), with the error ``error`` and its rate ``rate`` (per rad) at the phase's end."""

    phase: Phase
    rpm: float
    amplitude: float
    error: float
    rate: float


def residual_about(cam, wanted, follower: ElasticFollower, rpm: float, *, nodes: int = 16) -> list[PhaseResidual]:
    """The residual vibration of the elastic follower driven by ``cam`` about the ``wanted`` law after each
    rise and return, the follower starting the phase at rest on the cam's position.

    With θ = ω t, r = ωn/ω and the error e = y − y_w, m ÿ + b (ẏ − ṡ) + c (y − s) = 0 becomes
    e'' + 2ζr e' + r² e = g(θ), g = r² (s − y_w) + 2ζr (s' − y_w') − y_w''. With p = −ζr + i r_d (r_d = r√(1 − ζ²))
    the quantity q = e' + (ζr + i r_d) e obeys q' = p q + g, so at the phase's end T

        q(T) = q(θ0) e^{p(T−θ0)} + ∫ g(τ) e^{p(T−τ)} dτ,     A = |q(T)|/r_d = √(e² + ((e' + ζ r e)/r_d)²),

    the amplitude of the free vibration that follows (camcad.dynamics.model; docs/INTERFACE.md's residual vibration when
    ``cam`` is ``wanted``). The integral is Gauss–Legendre over panels split at the law's breakpoints and at most
    one radian of r_d τ wide (``nodes`` per panel). For the polydyne cam at its design speed g vanishes
    identically (r² K = 1, r² λ = 2ζr), so the residual is the quadrature's round-off.

    Parameters
    ----------
    cam, wanted : MotionLaw
        The cam's motion and the law the driven mass should do (the same unit: mm or rad).
    follower : ElasticFollower
        fn (Hz) and ζ (dimensionless).
    rpm : float
        The speed, rpm.
    nodes : int
        Gauss–Legendre nodes per panel (a count).

    Returns
    -------
    list of PhaseResidual
        One per rise and return: the amplitude (the law's unit), e and e' (per rad) at the phase's end.

    Examples
    --------
    The cycloidal rise's closed form (camcad.dynamics.residual.cycloidal_residual_amplitude) without damping:

    >>> import camcad
    >>> from camcad.dynamics.residual import cycloidal_residual_amplitude
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 10.0)
    >>> rise = residual_about(law, law, camcad.ElasticFollower(30.0), 300.0)[0]
    >>> round(rise.amplitude, 9) == round(cycloidal_residual_amplitude(10.0, 0.05, 30.0), 9)
    True
    """
    omega = 2.0 * math.pi * rpm / 60.0
    zeta = follower.damping_ratio
    r = follower.omega_n / omega
    rd = r * math.sqrt(1.0 - zeta * zeta)
    p = complex(-zeta * r, rd)
    u, w = np.polynomial.legendre.leggauss(nodes)
    compensated = isinstance(cam, PolydyneLaw) and cam.wanted is wanted
    edges_all = _breakpoints(wanted)

    def forcing(theta: np.ndarray) -> np.ndarray:
        y = wanted.kinematics(theta)
        if compensated:
            difference, rate = cam.correction(theta, 0), cam.correction(theta, 1)
        else:
            k = cam.kinematics(theta)
            difference, rate = k.s - y.s, k.v - y.v
        return r * r * difference + 2.0 * zeta * r * rate - y.a

    out = []
    for phase in wanted.phases:
        if phase.kind == "dwell":
            continue
        cuts = [phase.start, *[float(b) for b in edges_all if phase.start < b < phase.end], phase.end]
        pieces: list[tuple[float, float]] = []
        for lo, hi in itertools.pairwise(cuts):
            count = max(1, math.ceil((hi - lo) * max(rd, 1.0)))
            pieces.extend(zip(np.linspace(lo, hi, count + 1)[:-1], np.linspace(lo, hi, count + 1)[1:]))
        bounds = np.array(pieces)
        half = 0.5 * (bounds[:, 1] - bounds[:, 0])[:, None]
        tau = 0.5 * (bounds[:, 1] + bounds[:, 0])[:, None] + half * u[None, :]
        weight = (half * w[None, :]).ravel()
        tau = tau.ravel()
        end = phase.end
        integral = complex(np.sum(weight * forcing(tau) * np.exp(p * (end - tau))))
        start = cam.kinematics(np.array([phase.start]))
        y0 = wanted.kinematics(np.array([phase.start]))
        e0, e0_rate = float(start.s[0] - y0.s[0]), float(0.0 - y0.v[0])     # at rest on the cam
        q = (e0_rate + complex(zeta * r, rd) * e0) * np.exp(p * (end - phase.start)) + integral
        error = float(q.imag / rd)
        rate = float(q.real - zeta * r * error)
        out.append(PhaseResidual(phase, float(rpm), float(abs(q) / rd), error, rate))
    return out
