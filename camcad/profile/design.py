"""Design helper: the smallest base radius that meets the pressure-angle and curvature limits.

Each limit gives a margin function of the base radius Rb,
    g_φ(Rb) = min over θ of (limit(θ) − |φ(θ; Rb)|)                    (rad)
    g_ρ(Rb) = min over θ of (1/(Rr + ρ_min) − κ(θ; Rb))                (1/mm)
with κ = 1/ρ the signed curvature of the pitch curve (positive convex): the profile's convex
radius ρ − Rr stays ≥ ρ_min exactly when κ ≤ 1/(Rr + ρ_min), and κ, unlike ρ, stays finite
through inflections, so g_ρ is continuous. For a groove the outer flank adds
κ ≥ −1/(Rr + ρ_min). For the flat face ρ = Rb + s + a ≥ ρ_min gives Rb in closed form.

The smallest Rb is the root of g = 0, found with Brent's method (camcad.numerics.brent_root) on a
bracket [geometric lower bound, an upper bound found by doubling]; the inner minimum over θ is
taken on a grid and refined by zooming grids around the worst grid point (``camcad.extrema``). For a
translating follower |φ| = atan(|v − σe|/(d + s)) falls as d = √(Rp² − e²) grows at every θ,
so g_φ is increasing and its root unique; the tests compare it with the per-θ closed form
d ≥ |v − σe|/tan(limit) − s. For the oscillating follower Rb is bounded (|C − L| < Rb + Rr <
C + L) and g_φ rises and falls again as the arm straightens: its peak is found by a bounded
Brent search and the root on the rising side. For g_ρ the root found is the one inside the
bracket. The result is rounded up by the solver's tolerance, so the design meets its limits.

The accuracy knobs are ``xtol`` (mm, on Rb; by default 1e-11 × the mechanism's size, stroke + Rr + |e|
or the pivot's reach, so that a cam drawn at 1e-6 or 1e6 scale gets the same relative accuracy) and
``grid`` (points per cycle before refinement). The other lengths of the search (its lower bound, first
bracket and give-up bound) are fractions and multiples of that size too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import cast

import numpy as np

from camcad.arrays import union
from camcad.extrema import zoom_min
from camcad.law.law import MotionLaw
from camcad.numerics import bounded_minimum, brent_root
from camcad.profile.followers import Follower
from camcad.profile.geometry import CamGeometry
from camcad.profile.scaled_law import law_breakpoints


@dataclass(frozen=True)
class BaseRadiusDesign:
    """Smallest base radii (mm); None where a limit is not given or cannot be met.

    What ``camcad.min_base_radius`` returns; the example is there.

    Attributes
    ----------
    rb_pressure_angle : float, optional
        The smallest Rb meeting the pressure-angle limits, mm.
    rb_curvature : float, optional
        The smallest Rb whose profile has no convex radius below ρ_min (below 0, i.e. no undercut, when no
        ρ_min is given), mm.
    rb_min : float, optional
        The larger of the two, mm; ``limited_by`` names which one.
    limited_by : str
        "pressure angle" or "curvature".
    notes : tuple of str
        Why a figure is missing, in words.
    """

    rb_pressure_angle: float | None
    rb_curvature: float | None
    rb_min: float | None
    limited_by: str
    notes: tuple[str, ...] = ()

    def as_dict(self) -> dict:
        return {"rb_min_mm": self.rb_min, "rb_pressure_angle_mm": self.rb_pressure_angle,
                "rb_curvature_mm": self.rb_curvature, "limited_by": self.limited_by,
                "notes": list(self.notes)}


def _worst(values_fn, theta: np.ndarray) -> float:
    """min over θ of values_fn(θ): grid minimum refined by zooming grids (``camcad.extrema.zoom_min``)."""
    return zoom_min(values_fn, theta)[0]


def pressure_angle_margin(law: MotionLaw, follower: Follower, theta: np.ndarray) -> float:
    """g_φ (rad) for ``follower`` as given (its Rb); +inf when no limit applies."""
    geometry = CamGeometry(law, follower)

    def margin(t: np.ndarray) -> np.ndarray:
        pitch = geometry.pitch(t)
        limit = geometry.pressure_angle_limit(pitch.outward_speed)
        return np.where(np.isnan(limit), np.inf, limit - np.abs(pitch.pressure_angle))

    return _worst(margin, theta)


def _translating_pressure_angle_rb(law: MotionLaw, follower: Follower, theta: np.ndarray) -> float:
    """The smallest Rb (mm) meeting the pressure-angle limits of a translating roller or knife, in closed form.

    tan|φ| = |v − σe|/(d + s) with d = √(Rp² − e²), so |φ| ≤ limit(θ) ⇔ d ≥ |v − σe|/tan(limit) − s at
    every θ; d_min is the largest right-hand side (grid maximum refined by zooming grids) and
    Rb = √(d_min² + e²) − Rr. The limit in force at each θ (rise, return, reversible) is the one the
    profile's own check applies (``CamGeometry.pressure_angle_limit``).
    """
    geometry = CamGeometry(law, follower)
    sigma, offset = follower.sigma, follower.offset

    def needed(t: np.ndarray) -> np.ndarray:   # d required at θ, −inf where no limit applies
        kin = law.kinematics(t)
        limit = geometry.pressure_angle_limit(kin.v)
        with np.errstate(divide="ignore", invalid="ignore"):
            d = np.abs(kin.v - sigma * offset) / np.tan(limit) - kin.s
        return np.where(np.isnan(limit), -np.inf, d)

    d_min = -_worst(lambda t: -needed(t), theta)
    if not math.isfinite(d_min):
        return 0.0
    return math.hypot(max(d_min, 0.0), offset) - follower.roller_radius


def curvature_margin(law: MotionLaw, follower: Follower, theta: np.ndarray) -> float:
    """g_ρ (1/mm) for a roller follower as given (its Rb); +inf when nothing limits it."""
    geometry = CamGeometry(law, follower)
    reach = follower.roller_radius + (follower.rho_min or 0.0)
    if reach <= 0.0:
        return math.inf  # a knife edge with no curvature limit: any convex radius will do

    def margin(t: np.ndarray) -> np.ndarray:
        rho = geometry.pitch(t).rho
        with np.errstate(divide="ignore"):
            kappa = np.where(np.isfinite(rho), 1.0 / rho, 0.0)
        worst = 1.0 / reach - kappa
        if follower.groove:
            worst = np.minimum(worst, kappa + 1.0 / reach)
        return worst

    return _worst(margin, theta)


class _GridCache:
    """A law whose kinematics on one fixed grid are computed once (the base-radius search evaluates the
    same θ grid for every trial Rb; only the geometry changes)."""

    def __init__(self, law: MotionLaw, grid: np.ndarray) -> None:
        self.law, self.grid = law, grid
        self.cycle, self.phases = law.cycle, law.phases
        self._kin = law.kinematics(grid)

    def kinematics(self, theta: np.ndarray):
        return self._kin if theta is self.grid else self.law.kinematics(theta)

    def breakpoints(self) -> np.ndarray:
        return law_breakpoints(self.law)


def _bounds(follower: Follower, law: MotionLaw) -> tuple[float, float, float]:
    """Geometric range of Rb (mm): the pitch circle must clear the offset, or the arm must reach; and
    the mechanism's size (mm) that scales the search."""
    theta = np.linspace(0.0, law.cycle, 1025)
    stroke = float(np.ptp(law.kinematics(theta).s))
    rr = follower.roller_radius
    if follower.kind == "oscillating":
        c, arm = cast(float, follower.pivot), cast(float, follower.arm)
        span = c + arm - abs(c - arm)
        lo = max(abs(c - arm) - rr, 0.0) + 1e-7 * span
        hi = c + arm - rr - 1e-7 * span
        return lo, hi, span
    size = (stroke + rr + abs(follower.offset)) or 1.0   # 1 mm only for a knife edge on a law without stroke
    lo = max(abs(follower.offset) - rr, 0.0) + 1e-7 * size
    return lo, math.inf, size


def _solve(margin_of_rb, lo: float, hi: float, xtol: float, what: str, size: float
           ) -> tuple[float | None, str | None]:
    """Smallest Rb in (lo, hi) with margin ≥ 0: lo itself if it passes, else the bracketed root.

    An open range (hi = inf) is bracketed by doubling from ``size`` (mm) up to 1e7 × size."""
    if margin_of_rb(lo) >= 0.0:
        return lo, f"{what}: met by any base radius above the geometric minimum {lo:.6g} mm"
    if math.isinf(hi):
        hi = max(2.0 * lo, size)
        while margin_of_rb(hi) < 0.0:
            hi *= 2.0
            if hi > 1e7 * size:
                return None, f"{what}: no base radius up to {1e7 * size:.3g} mm meets the limit"
    elif margin_of_rb(hi) < 0.0:
        # oscillating follower: the margin rises, peaks and falls again as the arm straightens;
        # find the peak by a bounded Brent search, then the root on its rising side
        best_x, best_fun = bounded_minimum(lambda rb: -margin_of_rb(rb), lo, hi, xatol=1e-6 * (hi - lo))
        if -best_fun < 0.0:
            return None, (f"{what}: no base radius between {lo:.6g} and {hi:.6g} mm meets the limit "
                          f"with this pivot and arm (best {best_x:.6g} mm)")
        hi = float(best_x)
    root = brent_root(margin_of_rb, lo, hi, xtol=xtol, rtol=4.0 * np.finfo(float).eps)
    rounded = min(root + 2.0 * xtol, hi)  # round up: the result must meet the limit
    return rounded, None


def min_base_radius(law: MotionLaw, follower: Follower, *, xtol: float | None = None, grid: int = 2048
                    ) -> BaseRadiusDesign:
    """The smallest base radius (mm) meeting the follower's pressure-angle limits and curvature limit.

    The follower's own base radius is ignored. Translating roller or knife: the pressure-angle bound is
    in closed form per θ, d ≥ |v − σe|/tan(limit) − s with d = √(Rp² − e²); oscillating follower and
    the curvature limit: the root of the margin function by Brent's method. Flat face:
    ρ = Rb + s + a ≥ ρ_min gives Rb ≥ ρ_min − min(s + a). The result is rounded up by the solver's
    tolerance, so a cam of that base radius meets its limits (module docstring).

    Parameters
    ----------
    law : MotionLaw
        The law in follower units: s in mm (or rad of swing for the oscillating follower), θ in rad.
    follower : Follower
        The follower: its kind, Rr, offset (mm), pivot and arm (mm), limits (deg) and ``rho_min`` (mm).
    xtol : float, optional
        Tolerance on Rb, mm; by default 1e-11 × the mechanism's size (stroke + Rr + |e|, or the pivot's
        reach), so a cam drawn at 1e-6 or 1e6 scale gets the same relative accuracy.
    grid : int
        Points per cycle of the inner search over θ before its refinement (a count, no unit).

    Returns
    -------
    BaseRadiusDesign
        ``rb_pressure_angle``, ``rb_curvature`` and ``rb_min`` (the larger) in mm, None where a limit is
        not given or cannot be met; ``limited_by`` names the limit that sets ``rb_min``.

    References
    ----------
    R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 7 (sizing the cam by its
    pressure angle and radius of curvature).
    R. P. Brent, Algorithms for Minimization without Derivatives (1973), ch. 4–5.

    Examples
    --------
    A flat-faced follower on the full-cycle harmonic law s = h(1 − cos θ)/2: s + a = h/2 at every θ,
    so with h = 20 mm and ρ_min = 25 mm the bound is Rb = 25 − 10 = 15 mm:

    >>> import numpy as np
    >>> import camcad
    >>> harmonic = camcad.compose([("rise", 180), ("return", 180)], 20.0, "harmonic")
    >>> design = camcad.min_base_radius(harmonic, camcad.Follower("flat", base_radius=1.0, rho_min=25.0))
    >>> round(design.rb_min, 9), design.limited_by
    (15.0, 'curvature')

    A translating roller (Rr 10 mm, limits 30° rise and 45° return): the per-θ bound evaluated by hand on
    a fine grid of the law gives the same radius:

    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> design = camcad.min_base_radius(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0))
    >>> k = camcad.kinematics_deg(law, np.linspace(0.0, 360.0, 360001))
    >>> limit = np.radians(np.where(k.v >= 0.0, 30.0, 45.0))
    >>> by_hand = float((np.abs(k.v) / np.tan(limit) - k.s).max()) - 10.0
    >>> round(by_hand, 6), round(design.rb_pressure_angle, 6)
    (25.018891, 25.018891)
    """
    one_lobe = union(np.linspace(0.0, law.cycle, grid + 1), law_breakpoints(law))
    notes: list[str] = []
    rb_rho: float | None

    if follower.kind == "flat":
        # ρ = Rb + s + a ≥ ρ_min  ⇔  Rb ≥ ρ_min − min(s + a)
        def s_plus_a(t: np.ndarray) -> np.ndarray:
            kin = law.kinematics(t)
            return kin.s + kin.a

        rb_rho = max((follower.rho_min or 0.0) - _worst(s_plus_a, one_lobe), 0.0)
        notes.append("flat face: pressure angle is 0 by construction")
        return BaseRadiusDesign(None, rb_rho, rb_rho, "curvature", tuple(notes))

    lo, hi, size = _bounds(follower, law)
    xtol = 1e-11 * size if xtol is None else xtol
    limits_given = (follower.pressure_angle_limit_rise_deg is not None
                    or follower.pressure_angle_limit_return_deg is not None)
    rb_pa: float | None = None
    if limits_given and follower.kind in ("roller", "knife"):
        # rounded up by the tolerance, as the root finder's result is: the design must meet its limits
        rb_pa = max(_translating_pressure_angle_rb(law, follower, one_lobe) + 2.0 * xtol, lo)
    elif limits_given:
        cached = _GridCache(law, one_lobe)
        rb_pa, note = _solve(lambda rb: pressure_angle_margin(cached, follower.with_base_radius(rb), one_lobe),
                             lo, hi, xtol, "pressure angle", size)
        if note:
            notes.append(note)
    else:
        notes.append("pressure angle: no limit given")
    cached = _GridCache(law, one_lobe)
    rb_rho, note = _solve(lambda rb: curvature_margin(cached, follower.with_base_radius(rb), one_lobe),
                          lo, hi, xtol, "curvature", size)
    if note:
        notes.append(note)
    found = [(rb, name) for rb, name in ((rb_pa, "pressure angle"), (rb_rho, "curvature")) if rb is not None]
    if not found or (limits_given and rb_pa is None) or rb_rho is None:
        return BaseRadiusDesign(rb_pa, rb_rho, None, "not reachable", tuple(notes))
    rb_min, limited_by = max(found)
    return BaseRadiusDesign(rb_pa, rb_rho, rb_min, limited_by, tuple(notes))
