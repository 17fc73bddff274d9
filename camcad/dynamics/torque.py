"""Camshaft torque and power of a cam mechanism, by the power balance of the follower.

The cam drives the follower's path coordinate s (the roller centre's path, mm: the translating follower's
lift, or L·ψ for an oscillating follower of arm L; the flat face's lift). The force the follower needs along
that path (N, positive pressing it onto the cam) is

    F = m a ω²/1000 + k s + F0 + Q(θ) + F_link(θ, ω),

m the mass reduced to the path (kg), a = d²s/dθ² (mm/rad²), k the spring rate (N/mm), F0 the preload (N),
Q the process and external loads (N, resisting the follower's motion away from the cam), F_link the working
member behind a linkage reduced to the path (``camcad.linkage.transfer.LinkageLoad``: A ω² + B). The
normal force at the contact, with friction μ_g in the follower's guide, is F_n = F/(cos φ − μ_g |sin φ|
sgn(v F)) (``camcad.contact.normal_force``: the same force ``camcad contact`` computes). Since the cam
turns at ω and the follower's path point moves at ṡ = v ω, the power the shaft gives the follower is
F_n cos φ · ṡ (the component of the contact force along the path does all the follower's work), so

    T_cam = F_n cos φ · v / 1000                                  (N·m; v = ds/dθ in mm/rad)

— with μ_g = 0 exactly T = F v/1000, the classical T = (m ω² s'' + k s + F0) s' of a rigid follower. Friction
in the higher pair (coefficient μ_c: sliding for a flat face or a knife edge; for a roller, the roller's
bearing and rolling resistance referred to its rim, μ_c = μ_pin r_pin/Rr + f_roll/Rr) dissipates
μ_c |F_n| |v_t| where v_t is the speed of the cam's surface relative to the follower's body at the contact
(the roller's rim speed, or the flat face's sliding speed): its torque is μ_c |F_n| w / 1000 with
w = |v_t|/ω (mm/rad), computed from the contact point in the fixed frame (``contact_slip``). It is taken at
the normal force without it (first order in μ_c: the tangential force's own share of the guide reaction,
of order μ_c μ_g and μ_c tan φ, is neglected).

Sign: T > 0 the shaft drives the mechanism; T < 0 the mechanism gives energy back to the shaft (a spring
pushing the follower down the return, the follower's inertia decelerating). Power P = T ω (W).

For a form-closed cam (a groove or a conjugate pair) F may change sign: a negative force is carried by the
outer flank of the groove or by the second roller, whose pressure angle and slip are used there. For a
force-closed follower F ≤ 0 means the follower leaves the cam; the torque there is not physical and the
callers report it (``TorqueComponents.axial_force``).

Sources: R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 10 (camshaft torque
T = F v/ω from the power balance, the flywheel); the same in Norton, Design of Machinery (camshaft torque
and its dynamic force analysis).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from camcad.arrays import unique
from camcad.contact import angular_speed, normal_force
from camcad.extrema import zoom_max
from camcad.profile.geometry import CamGeometry, perp, rotate

#: Gauss–Legendre nodes per panel and the widest panel (rad) of the cycle integrals
GAUSS_NODES = 12
PANEL_RAD = math.radians(2.0)
#: the uniform grid (rad) the peaks are first sampled on, before ``zoom_max`` refines them
PEAK_STEP_RAD = math.radians(0.25)
#: a mean torque within this fraction of the peak is the round-off of its quadrature (measured: 1e-17 of the
#: peak for the loom group, whose loads do no net work): reported as 0
ROUND_OFF = 1e-12


# --------------------------------------------------------------------------------------------
# Contact slip
# --------------------------------------------------------------------------------------------

def contact_slip(cam: CamGeometry, theta, second: bool = False, outer: bool = False) -> np.ndarray:
    """w = |v_t|/ω (mm/rad): the speed of the cam's surface relative to the follower's body at the contact
    point, per unit cam speed — a roller's rim speed, a flat face's or a knife edge's sliding speed.

    In the fixed frame the contact point P (roller centre q minus Rr n, n the outward normal of the pitch
    curve; q + Rr n on a groove's outer flank; the flat face's point (σv, Rb + s)) moves with the cam at
    σ ω J P (J: the turn by +90°); the follower's body point there moves at ω (0, v) (translating) or
    ω α' J (P − A) (oscillating: the arm's angle α turns at α' = −ψ' about the pivot A). The relative velocity
    is along the tangent t = J n.

    Parameters
    ----------
    cam : CamGeometry
        The cam and its follower (θ rad; s mm, or rad of swing).
    theta : array_like
        Cam angles θ, rad.
    second : bool
        The second roller of a conjugate pair.
    outer : bool
        The outer flank of a groove (the roller touches it from inside).

    Returns
    -------
    ndarray
        w, mm/rad (≥ 0).

    Examples
    --------
    On the base circle a translating roller's rim runs at the cam's surface speed ω Rb:

    >>> import numpy as np, camcad
    >>> law = camcad.compose([("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)], 10.0)
    >>> cam = CamGeometry(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0))
    >>> round(float(contact_slip(cam, np.array([0.5]))[0]), 9)
    40.0
    """
    theta = np.asarray(theta, dtype=float)
    follower = cam.follower
    sigma = cam.sigma
    kin = cam.kinematics(theta)
    if follower.kind == "flat":
        point = np.stack((sigma * kin.v, follower.base_radius + kin.s), axis=-1)
        normal = np.stack((np.zeros_like(theta), np.ones_like(theta)), axis=-1)
    else:
        pitch = cam.pitch(theta, second)
        normal = rotate(pitch.normal, sigma * theta)          # back to the fixed frame
        radius = follower.roller_radius
        point = pitch.centre + (radius if outer else -radius) * normal
    cam_speed = sigma * perp(point)
    if follower.kind == "oscillating":
        pivot = np.array([float(follower.pivot), 0.0])        # type: ignore[arg-type]  # validated
        body = (-kin.v)[:, None] * perp(point - pivot)
    else:
        body = np.stack((np.zeros_like(theta), kin.v), axis=-1)
    tangent = perp(normal)
    relative = cam_speed - body
    return np.abs(tangent[:, 0] * relative[:, 0] + tangent[:, 1] * relative[:, 1])


# --------------------------------------------------------------------------------------------
# One mechanism
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class TorqueComponents:
    """The camshaft torque of one mechanism at one speed, arrays over ``theta`` (rad).

    Torques in N·m, each the share of one force (its power over ω): ``inertia`` (m a ω²), ``spring``
    (k s + F0), ``load`` (process, external and gravity loads), ``linkage`` (the working member behind a
    linkage), ``friction`` (the guide's and the higher pair's losses); ``total`` their sum. ``axial_force``
    F (N) along the path and ``normal_force`` F_n (N) at the contact.
    """

    theta: np.ndarray
    rpm: float
    inertia: np.ndarray
    spring: np.ndarray
    load: np.ndarray
    linkage: np.ndarray
    friction: np.ndarray
    total: np.ndarray
    axial_force: np.ndarray
    normal_force: np.ndarray

    @property
    def power(self) -> np.ndarray:
        """P = T ω, W."""
        return self.total * float(angular_speed(self.rpm))


@dataclass(frozen=True)
class CamDrive:
    """What the camshaft drives at one cam: the cam, the follower's forces, its friction.

    Parameters
    ----------
    cam : CamGeometry
        The cam and its follower (θ rad; s mm, or rad of swing for an oscillating follower).
    scale : float
        mm of the path per unit of the law's s: 1 for a translating follower, the arm L (mm) for an
        oscillating one (its roller centre's arc L ψ).
    mass : float
        Mass reduced to the path, kg.
    spring_rate : float
        Spring rate along the path, N/mm.
    preload : float
        Spring force at s = 0, N.
    guide_friction : float
        Friction coefficient μ_g in the follower's guide (dimensionless).
    pair_friction : float
        Friction coefficient μ_c in the higher pair (dimensionless; a roller's referred to its rim).
    closure : str
        "force" (a spring holds the follower) or "form" (a groove or a conjugate pair carries both signs).
    load : callable, optional
        Q(θ): process and external loads along the path, N (θ rad → array), resisting the motion away
        from the cam.
    linkage : callable, optional
        (θ rad, rpm) → N: the working member behind a linkage, reduced to the path.

    Examples
    --------
    A frictionless rigid follower: T = (m a ω²/1000 + k s + F0) v/1000 (N·m):

    >>> import numpy as np, camcad
    >>> law = camcad.compose([("rise", 180), ("return", 180)], 20.0, "cycloidal")
    >>> cam = CamGeometry(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0))
    >>> drive = CamDrive(cam, 1.0, mass=2.0, spring_rate=5.0, preload=100.0)
    >>> theta = np.array([0.7])
    >>> k = law.kinematics(theta)
    >>> omega = 2 * np.pi * 300 / 60
    >>> by_hand = (2.0 * k.a * omega**2 / 1000 + 5.0 * k.s + 100.0) * k.v / 1000
    >>> bool(np.isclose(drive.components(theta, 300.0).total, by_hand, rtol=1e-12))
    True
    """

    cam: CamGeometry
    scale: float
    mass: float
    spring_rate: float = 0.0
    preload: float = 0.0
    guide_friction: float = 0.0
    pair_friction: float = 0.0
    closure: str = "force"
    load: Callable | None = None
    linkage: Callable | None = None

    def breakpoints(self) -> np.ndarray:
        """θ (rad) in [0, 2π] where the torque may be non-smooth: the law's and the loads' breakpoints."""
        points = [self.cam.breakpoints()]
        for source in (self.load, self.linkage):
            extra = getattr(source, "breakpoints", None)
            if extra is not None:
                points.append(np.asarray(extra(), dtype=float))
        return unique(np.clip(np.concatenate(points), 0.0, 2.0 * math.pi))

    def components(self, theta, rpm: float) -> TorqueComponents:
        """The torque and its shares at cam angles ``theta`` (rad) and ``rpm`` (module docstring)."""
        theta = np.asarray(theta, dtype=float)
        omega = float(angular_speed(rpm))
        kin = self.cam.kinematics(theta)
        s, v, a = kin.s * self.scale, kin.v * self.scale, kin.a * self.scale
        zero = np.zeros_like(theta)
        f_inertia = self.mass * a * omega**2 / 1000.0
        f_spring = self.spring_rate * s + self.preload
        f_load = zero if self.load is None else np.asarray(self.load(theta), dtype=float) * np.ones_like(theta)
        f_link = zero if self.linkage is None else np.asarray(self.linkage(theta, rpm), dtype=float)
        force = f_inertia + f_spring + f_load + f_link
        phi = self.cam.pressure_angle(theta)
        second = self.cam.follower.has_pair and self.closure == "form"
        if second:     # a negative force is carried by the second roller, at its own pressure angle
            phi = np.where(force < 0.0, self.cam.pressure_angle(theta, second=True), phi)
        fn = normal_force(force, phi, v, self.guide_friction)
        driving = fn * np.cos(phi) * v / 1000.0
        pair = zero
        if self.pair_friction > 0.0:
            slip = contact_slip(self.cam, theta)
            if force.min(initial=0.0) < 0.0 and self.closure == "form":
                other = (contact_slip(self.cam, theta, second=True) if second
                         else contact_slip(self.cam, theta, outer=True))
                slip = np.where(force < 0.0, other, slip)
            pair = self.pair_friction * np.abs(fn) * slip / 1000.0
        per = v / 1000.0
        inertia, spring, load, link = f_inertia * per, f_spring * per, f_load * per, f_link * per
        total = driving + pair
        friction = total - (inertia + spring + load + link)
        return TorqueComponents(theta, float(rpm), inertia, spring, load, link, friction, total, force, fn)


# --------------------------------------------------------------------------------------------
# Figures over the cycle
# --------------------------------------------------------------------------------------------

def cycle_nodes(breakpoints, cycle: float = 2.0 * math.pi, nodes: int = GAUSS_NODES,
                panel: float = PANEL_RAD) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights (rad) over [0, cycle], panels split at ``breakpoints`` (rad) and at
    most ``panel`` wide: ∫ f dθ ≈ Σ w f(x), exact to round-off for a function smooth between breakpoints.

    Examples
    --------
    >>> x, w = cycle_nodes([0.0, 1.0])
    >>> round(float(np.sum(w * np.sin(x) ** 2)), 12), round(math.pi, 12)
    (3.14159265359, 3.14159265359)
    """
    edges = unique(np.concatenate((np.clip(np.asarray(breakpoints, dtype=float), 0.0, cycle), [0.0, cycle])))
    pieces = []
    for lo, hi in itertools.pairwise(edges):
        if hi - lo <= 1e-15:
            continue
        count = max(1, math.ceil((hi - lo) / panel))
        pieces.append(np.linspace(lo, hi, count + 1))
    bounds = np.concatenate([np.column_stack((p[:-1], p[1:])) for p in pieces])
    u, weight = np.polynomial.legendre.leggauss(nodes)
    half = 0.5 * (bounds[:, 1] - bounds[:, 0])[:, None]
    mid = 0.5 * (bounds[:, 1] + bounds[:, 0])[:, None]
    return (mid + half * u[None, :]).ravel(), (half * weight[None, :]).ravel()


@dataclass(frozen=True)
class CycleFigures:
    """Peak, extremes, mean and RMS of a periodic torque (N·m) over one turn, with where (rad) and the
    power figures (W) at the speed ``rpm``."""

    rpm: float
    peak: float          # max |T|
    peak_at: float
    maximum: float
    maximum_at: float
    minimum: float
    minimum_at: float
    mean: float
    rms: float

    @property
    def omega(self) -> float:
        return float(angular_speed(self.rpm))

    def to_dict(self) -> dict:
        """The figures in docs/INTERFACE.md's units (N·m, W, deg, rpm)."""
        w = self.omega
        return {"rpm": self.rpm, "torque_peak_Nm": self.peak, "torque_peak_at_deg": math.degrees(self.peak_at),
                "torque_max_Nm": self.maximum, "torque_max_at_deg": math.degrees(self.maximum_at),
                "torque_min_Nm": self.minimum, "torque_min_at_deg": math.degrees(self.minimum_at),
                "torque_rms_Nm": self.rms, "torque_mean_Nm": self.mean,
                "power_peak_W": self.peak * w, "power_max_W": self.maximum * w, "power_min_W": self.minimum * w,
                "power_mean_W": self.mean * w}


def cycle_figures(torque: Callable[[np.ndarray], np.ndarray], breakpoints, rpm: float) -> CycleFigures:
    """Peak |T|, max, min (refined by ``camcad.extrema.zoom_max`` from a 0.25° grid and the breakpoints),
    mean (1/2π)∫T dθ and RMS √((1/2π)∫T² dθ) (Gauss–Legendre between the breakpoints) of a torque over
    one turn.

    Parameters
    ----------
    torque : callable
        θ (rad, 1-D array) → T (N·m).
    breakpoints : array_like
        θ (rad) where T may be non-smooth.
    rpm : float
        The speed, rpm (for the power figures).

    Returns
    -------
    CycleFigures

    Examples
    --------
    T = 2 + 3 sin θ: mean 2, RMS √(4 + 9/2), peak 5 at 90°:

    >>> f = cycle_figures(lambda t: 2.0 + 3.0 * np.sin(t), [], 60.0)
    >>> round(f.mean, 12), round(f.rms, 12), round(f.peak, 9), round(math.degrees(f.peak_at), 4)
    (2.0, 2.915475947423, 5.0, 90.0)
    """
    edges = unique(np.concatenate((np.asarray(breakpoints, dtype=float), [0.0, 2.0 * math.pi])))
    grid = unique(np.concatenate((np.arange(0.0, 2.0 * math.pi, PEAK_STEP_RAD), edges)))

    sign = np.array([1.0, -1.0, 0.0])[:, None]

    def three(u):
        """Rows T, −T and |T| at the abscissae ``u`` (1-D: shared; (3, M): one row each)."""
        u = np.asarray(u, dtype=float)
        values = np.asarray(torque(u.ravel()), dtype=float).reshape(u.shape)
        values = np.broadcast_to(values, (3, values.shape[-1]))
        return np.where(sign == 0.0, np.abs(values), sign * values)

    top, at = zoom_max(three, grid, 3)
    x, w = cycle_nodes(edges)
    values = np.asarray(torque(x), dtype=float)
    mean = float(np.sum(w * values)) / (2.0 * math.pi)
    rms = math.sqrt(float(np.sum(w * values**2)) / (2.0 * math.pi))
    if abs(mean) <= ROUND_OFF * float(top[2]):   # a conservative system's mean is 0: its sum's round-off
        mean = 0.0
    return CycleFigures(float(rpm), float(top[2]), float(at[2]) % (2.0 * math.pi), float(top[0]),
                        float(at[0]) % (2.0 * math.pi), float(-top[1]), float(at[1]) % (2.0 * math.pi), mean, rms)
