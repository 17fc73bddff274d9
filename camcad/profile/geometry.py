"""Cam geometry in closed form: pitch curve, profile, pressure angle, radius of curvature.

Everything is a pure function of the cam angle θ (rad) and the law's s, v, a (no jerk is
needed, so drawn laws with piecewise-constant jerk are fine).

The roller centre (or the flat face's point on its axis) is a point q(θ) of the fixed frame
with derivatives q', q''. The cam turns by σθ (σ = +1 counter-clockwise, −1 clockwise), so
in the cam's own frame the point is P = R(−σθ) q and, with J the rotation by +90°
(J(x, y) = (−y, x)), dR(−σθ)/dθ = −σ R(−σθ) J:

    P'  = R(−σθ) T,    T  = q' − σ J q
    P'' = R(−σθ) T2,   T2 = q'' − 2σ J q' − q

The pitch curve winds once around the cam centre, clockwise for σ = +1, so its outward
normal is n = σ J T / |T| and its signed radius of curvature (positive where the curve is
convex, i.e. turns toward the cam centre) is

    ρ = −σ |T|³ / (T × T2).

For a translating roller, q = (e, d + s), q' = (0, v), q'' = (0, a), d = √(Rp² − e²):
T = (σ(d + s), v − σe) and, with σ = +1, ρ = ((d+s)² + (v−e)²)^{3/2} / ((d+s)² + (v−e)(2v−e) − a(d+s)),
which for e = 0 is the textbook ρ = ((Rp+s)² + v²)^{3/2} / ((Rp+s)² + 2v² − a(Rp+s)).

Pressure angle: the angle between the common normal n and the direction w in which the roller
centre moves when it moves away from the cam (its own path), signed so that it is positive on
the rise: φ = σ·atan2(w × n, w · n). For the translating roller it is
φ = atan((v − σe)/(d + s)), docs/INTERFACE.md's φ = atan((v − e)/(d + s)) for the default CCW cam;
for the oscillating roller (pivot A = (C, 0), B = A + L(−cos γ, sin γ), γ = γ0 + ψ) it is
φ = atan((L(1 + ψ') − C cos γ)/(C sin γ)) for σ = +1.

The roller profile is the parallel curve X = P − Rr n (the groove's outer flank P + Rr n);
its radius of curvature is ρ − Rr (ρ + Rr): a convex pitch radius ρ ≤ Rr is an undercut.
The flat face (perpendicular to its axis, at height p = Rb + s) touches the cam at the fixed
point (σ v, p), the envelope of its lines; its radius of curvature is ρ = p + p'' = Rb + s + a,
and its pressure angle is 0.

Sources: R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 7–8
(pressure angle and radius of curvature of roller and flat followers); J. Angeles and
C. S. López-Cajún, Optimization of Cam Mechanisms (1991), ch. 2 (the same results in the
vector form used here). The formulas were derived again for this module; the tests check
them against derivatives of generated points and circumradii of point triples.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import cast

import numpy as np

from camcad.arrays import unique
from camcad.errors import CamcadError
from camcad.law.law import Kinematics, MotionLaw
from camcad.profile.followers import Follower, arm_angle_on_base_circle
from camcad.profile.scaled_law import law_breakpoints, merge_close


def rotate(points: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rotate each row (x, y) of ``points`` by its ``angle`` (rad, counter-clockwise)."""
    return turn(points, np.cos(angle), np.sin(angle))


def turn(points: np.ndarray, c: np.ndarray, s: np.ndarray) -> np.ndarray:
    """``rotate`` with the angle's cosine ``c`` and sine ``s`` given (one pair of them serves several curves)."""
    x, y = points[..., 0], points[..., 1]
    shape = x.shape if np.shape(c) == x.shape else np.broadcast_shapes(x.shape, np.shape(c))
    out = np.empty(shape + (2,))
    out[..., 0] = c * x - s * y
    out[..., 1] = s * x + c * y
    return out


def perp(vectors: np.ndarray) -> np.ndarray:
    """J v: each (x, y) turned by +90° → (−y, x)."""
    out = np.empty_like(vectors, dtype=float)
    out[..., 0] = -vectors[..., 1]
    out[..., 1] = vectors[..., 0]
    return out


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """z-component of a × b for rows of 2-vectors."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


@dataclass(frozen=True)
class Track:
    """The roller centre (or the flat face's axis point) in the fixed frame, mm.

    q, dq, d2q: position and its first two θ-derivatives (mm, mm/rad, mm/rad²), shape (N, 2).
    outward:    unit vector along the point's own path, pointing away from the cam centre.
    """

    q: np.ndarray
    dq: np.ndarray
    d2q: np.ndarray
    outward: np.ndarray


def translating_track(kin: Kinematics, height: float, offset: float, shift: float = 0.0) -> Track:
    """q = (e, h + s − shift): a point on the axis x = e of a translating follower.

    ``height`` h is d = √(Rp² − e²) for a roller, Rb for a flat face; ``shift`` puts the
    second roller of a conjugate pair ``shift`` mm lower on the same axis.
    """
    n = kin.s.shape
    zeros = np.zeros(n)
    y = height + kin.s - shift
    q = np.stack((np.full(n, float(offset)), y), axis=-1)
    dq = np.stack((zeros, kin.v), axis=-1)
    d2q = np.stack((zeros, kin.a), axis=-1)
    up = np.where(height - shift >= 0.0, 1.0, -1.0) * np.ones(n)
    outward = np.stack((zeros, up), axis=-1)
    return Track(q, dq, d2q, outward)


def oscillating_track(kin: Kinematics, pivot: float, arm: float, gamma0: float,
                      turn: float = 0.0) -> Track:
    """B = A + L(−cos γ, sin γ), γ = γ0 + ψ − ``turn``, A = (C, 0); ψ = kin.s (rad).

    B' = L ψ' w and B'' = L(ψ'' w − ψ'² u) with u = (−cos γ, sin γ), w = (sin γ, cos γ).
    ``turn`` > 0 is the second arm of a conjugate pair, on the other side of the line of centres.
    """
    gamma = gamma0 + kin.s - turn
    u = np.stack((-np.cos(gamma), np.sin(gamma)), axis=-1)
    w = np.stack((np.sin(gamma), np.cos(gamma)), axis=-1)
    q = np.stack((pivot + arm * u[:, 0], arm * u[:, 1]), axis=-1)
    dq = arm * kin.v[:, None] * w
    d2q = arm * (kin.a[:, None] * w - (kin.v**2)[:, None] * u)
    # w · B = C sin γ: w points away from the cam centre when the arm is above the line of centres
    outward = np.where((np.sin(gamma) >= 0.0)[:, None], w, -w)
    return Track(q, dq, d2q, outward)


@dataclass(frozen=True)
class CurveGeometry:
    """A curve of the cam sampled at ``theta`` (rad), in the cam's frame (mm).

    points:  (N, 2) positions.
    tangent: (N, 2) unit tangents in the direction of increasing θ.
    speed:   |dX/dθ| (mm/rad).
    rho:     signed radius of curvature (mm): > 0 convex, < 0 concave, ±inf straight.
    """

    theta: np.ndarray
    points: np.ndarray
    tangent: np.ndarray
    speed: np.ndarray
    rho: np.ndarray


@dataclass(frozen=True)
class PitchGeometry(CurveGeometry):
    """The pitch curve plus what the contact needs.

    normal:          (N, 2) outward unit normal in the cam frame.
    pressure_angle:  φ (rad), signed (positive on the rise).
    outward_speed:   d/dθ of the roller centre along its path, away from the cam (mm/rad);
                     > 0 rise, < 0 return, 0 dwell.
    centre:          (N, 2) roller centre in the fixed frame.
    """

    normal: np.ndarray
    pressure_angle: np.ndarray
    outward_speed: np.ndarray
    centre: np.ndarray


def pitch_geometry(theta: np.ndarray, track: Track, sigma: float) -> PitchGeometry:
    """Pitch curve, outward normal, radius of curvature and pressure angle (module docstring)."""
    q, dq, d2q = track.q, track.dq, track.d2q
    t1 = dq - sigma * perp(q)
    t2 = d2q - 2.0 * sigma * perp(dq) - q
    speed = np.hypot(t1[:, 0], t1[:, 1])
    bend = cross(t1, t2)
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = np.where(bend != 0.0, -sigma * speed**3 / bend, np.inf)
    tangent_fixed = t1 / speed[:, None]
    normal_fixed = sigma * perp(tangent_fixed)
    w = track.outward
    phi = sigma * np.arctan2(cross(w, normal_fixed), dot(w, normal_fixed))
    angle = -sigma * theta
    c, s = np.cos(angle), np.sin(angle)
    return PitchGeometry(
        theta=theta, points=turn(q, c, s), tangent=turn(tangent_fixed, c, s), speed=speed,
        rho=rho, normal=turn(normal_fixed, c, s), pressure_angle=phi,
        outward_speed=dot(dq, w), centre=q)


def pitch_points(theta: np.ndarray, track: Track, sigma: float) -> tuple[np.ndarray, np.ndarray]:
    """(points, outward normals) of the pitch curve in the cam's frame: ``pitch_geometry``'s ``points`` and
    ``normal`` alone (what placing and checking chords needs)."""
    q, dq = track.q, track.dq
    t1 = dq - sigma * perp(q)
    normal_fixed = sigma * perp(t1 / np.hypot(t1[:, 0], t1[:, 1])[:, None])
    angle = -sigma * theta
    c, s = np.cos(angle), np.sin(angle)
    return turn(q, c, s), turn(normal_fixed, c, s)


def parallel_curve(pitch: PitchGeometry, distance: float) -> CurveGeometry:
    """The curve X = P − distance·n (the roller profile for distance = Rr > 0, the groove's
    outer flank for distance = −Rr); ρ_X = ρ − distance, |X'| = |T| |1 − distance/ρ|.

    Where 1 − distance/ρ < 0 the curve runs backwards (a cusp and a loop: undercut)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        stretch = np.where(np.isfinite(pitch.rho), 1.0 - distance / pitch.rho, 1.0)
    points = pitch.points - distance * pitch.normal
    direction = np.where(stretch >= 0.0, 1.0, -1.0)[:, None]
    return CurveGeometry(theta=pitch.theta, points=points, tangent=pitch.tangent * direction,
                         speed=pitch.speed * np.abs(stretch), rho=pitch.rho - distance)


def flat_face_profile(theta: np.ndarray, kin: Kinematics, base_radius: float, sigma: float
                      ) -> CurveGeometry:
    """Profile touched by a translating flat face: X = R(−σθ)(σv, Rb + s), ρ = Rb + s + a.

    dX/dθ = σ ρ R(−σθ)(1, 0), so the tangent turns at exactly 1 rad/rad and |X'| = |ρ|.
    """
    p = base_radius + kin.s
    rho = p + kin.a
    contact = np.stack((sigma * kin.v, p), axis=-1)
    angle = -sigma * theta
    unit = np.stack((np.full_like(rho, sigma), np.zeros_like(rho)), axis=-1)
    direction = np.where(rho >= 0.0, 1.0, -1.0)[:, None]
    return CurveGeometry(theta=theta, points=rotate(contact, angle),
                         tangent=rotate(unit * direction, angle), speed=np.abs(rho), rho=rho)


@dataclass(frozen=True)
class CamGeometry:
    """One cam mechanism: a law in follower units and a follower; every curve at any θ (rad).

    The law's s is in mm for translating followers and in rad (swing ψ) for the oscillating
    one (see ``swing_law``). A law whose cycle is 2π/k gives a cam with k lobes.

    Parameters
    ----------
    law : MotionLaw
        The follower's law: θ in rad, s in mm (rad of swing for an oscillating follower).
    follower : Follower
        The follower and its limits (mm, deg).

    Examples
    --------
    A translating roller without offset: the pressure angle is atan(v/(Rb + Rr + s)).

    >>> import math
    >>> import numpy as np
    >>> import camcad
    >>> from camcad.profile import CamGeometry
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> cam = CamGeometry(law, camcad.Follower("roller", 40.0, 10.0))
    >>> theta = np.radians([45.0])
    >>> kin = law.kinematics(theta)
    >>> expected = math.atan(kin.v[0] / (50.0 + kin.s[0]))
    >>> cam.lobes, bool(abs(cam.pressure_angle(theta)[0] - expected) < 1e-12)
    (1, True)
    """

    law: MotionLaw
    follower: Follower
    lobes: int = field(init=False)
    height: float = field(init=False)       # d = √(Rp² − e²) (roller) or Rb (flat), mm
    gamma0: float = field(init=False)       # oscillating: arm angle on the base circle, rad

    def __post_init__(self) -> None:
        follower = self.follower.validate()
        cycle = float(self.law.cycle)
        lobes = round(2.0 * math.pi / cycle)
        if lobes < 1 or abs(lobes * cycle - 2.0 * math.pi) > 1e-9:
            raise CamcadError(f"the law's cycle is {math.degrees(cycle):.6g} deg, which does not divide "
                              "one turn of the cam", "law",
                              "give a law over 360 deg (or 360/k deg for a cam with k lobes)")
        object.__setattr__(self, "lobes", int(lobes))
        if follower.kind == "flat":
            height = follower.base_radius
        elif follower.kind == "oscillating":
            height = follower.prime_radius
        else:
            height = math.sqrt(follower.prime_radius**2 - follower.offset**2)
        object.__setattr__(self, "height", height)
        object.__setattr__(self, "gamma0",
                           arm_angle_on_base_circle(follower) if follower.kind == "oscillating" else 0.0)

    @property
    def sigma(self) -> float:
        return self.follower.sigma

    @functools.cached_property
    def dwell_speed(self) -> float:
        """|outward speed| (mm/rad) below which the follower counts as dwelling: 1e-9 of its peak speed."""
        return 1e-9 * peak_speed(self.law) * (cast(float, self.follower.arm) if self.follower.kind == "oscillating"
                                              else 1.0)

    def breakpoints(self) -> np.ndarray:
        """θ (rad) in [0, 2π] where curvature may jump: the law's breakpoints on every lobe."""
        one = law_breakpoints(self.law)
        cycle = float(self.law.cycle)
        points = np.concatenate([one + k * cycle for k in range(self.lobes)])
        return merge_close(unique(np.clip(points, 0.0, 2.0 * math.pi)), 0.0, 2.0 * math.pi)

    def kinematics(self, theta: np.ndarray) -> Kinematics:
        return self.law.kinematics(np.asarray(theta, dtype=float))

    def track(self, theta: np.ndarray, second: bool = False) -> Track:
        return self.track_of(self.kinematics(theta), second)

    def track_of(self, kin: Kinematics, second: bool = False) -> Track:
        """The track of the law sampled as ``kin`` (one kinematics evaluation serves several curves)."""
        f = self.follower
        if f.kind == "oscillating":
            turn = math.radians(cast(float, f.pair_angle_deg)) if second else 0.0
            return oscillating_track(kin, cast(float, f.pivot), cast(float, f.arm), self.gamma0, turn)
        shift = cast(float, f.pair_distance) if second else 0.0
        return translating_track(kin, self.height, f.offset, shift)

    def pitch(self, theta: np.ndarray, second: bool = False) -> PitchGeometry:
        """Pitch curve of the main roller (or of the second roller of a conjugate pair)."""
        theta = np.asarray(theta, dtype=float)
        if second and not self.follower.has_pair:
            raise ValueError("this follower has no second roller")
        return pitch_geometry(theta, self.track(theta, second), self.sigma)

    def profile(self, theta: np.ndarray) -> CurveGeometry:
        """The cam profile the follower touches."""
        theta = np.asarray(theta, dtype=float)
        if self.follower.kind == "flat":
            return flat_face_profile(theta, self.kinematics(theta), self.follower.base_radius, self.sigma)
        return parallel_curve(self.pitch(theta), self.follower.roller_radius)

    def outer_flank(self, theta: np.ndarray) -> CurveGeometry:
        """The groove's outer flank, P + Rr n."""
        return parallel_curve(self.pitch(np.asarray(theta, dtype=float)), -self.follower.roller_radius)

    def counter_profile(self, theta: np.ndarray) -> CurveGeometry:
        """The counter-cam touched by the second roller of a conjugate pair."""
        return parallel_curve(self.pitch(np.asarray(theta, dtype=float), second=True),
                              self.follower.roller_radius)

    def pressure_angle(self, theta: np.ndarray, second: bool = False) -> np.ndarray:
        """φ (rad); identically 0 for the flat face."""
        theta = np.asarray(theta, dtype=float)
        if self.follower.kind == "flat":
            return np.zeros_like(theta)
        return self.pitch(theta, second).pressure_angle

    def pressure_angle_limit(self, outward_speed: np.ndarray) -> np.ndarray:
        """The limit of |φ| (rad) that applies at each point; NaN where none applies.

        Non-reversible: the rise limit while the roller moves away from the cam centre and in
        dwells, the return limit while it comes back. Reversible: each moving phase is a
        working stroke in one of the two directions, so the stricter limit applies everywhere.
        """
        f = self.follower
        rise = math.radians(f.pressure_angle_limit_rise_deg) if f.pressure_angle_limit_rise_deg else math.nan
        back = (math.radians(f.pressure_angle_limit_return_deg)
                if f.pressure_angle_limit_return_deg else math.nan)
        if f.reversible:
            strict = np.nanmin([rise, back]) if not (math.isnan(rise) and math.isnan(back)) else math.nan
            return np.full(np.shape(outward_speed), strict)
        return np.where(outward_speed < -self.dwell_speed, back, rise)


@functools.lru_cache(maxsize=64)
def _peak_speed_cached(law: MotionLaw) -> float:
    v = law.kinematics(np.linspace(0.0, float(law.cycle), 4097)).v
    return max(float(np.max(np.abs(v))), 1e-300)


def peak_speed(law: MotionLaw) -> float:
    """max |v| of ``law`` on 4097 samples of its cycle (mm/rad or rad/rad); cached for hashable laws."""
    try:
        return _peak_speed_cached(law)  # type: ignore[arg-type]  # an unhashable law raises TypeError
    except TypeError:  # a law holding arrays is not hashable: sample it each time
        return _peak_speed_cached.__wrapped__(law)
