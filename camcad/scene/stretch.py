"""A motion phase stretched to many widths at once: the fast route to least phase angles.

When a cyclogram lengthens or shortens a phase from width β to t, the phase keeps its shape and lift
(``camcad.law.retime``): in the normalised angle u = (θ − θ0)/β the displacement is unchanged, the
velocity analog scales by β/t and the acceleration analog by (β/t)² (v = h f'(u)/t, a = h f''(u)/t²).
The pressure angle, the pitch curve's radius of curvature and the contact force at a point depend
only on the follower, s, v, a (and, for a load that acts over a range of cam angles, on θ) — not on
where the rest of the cycle is. So the phase is sampled once, on u, and every trial width is a
rescaling of the same samples: a whole set of widths is evaluated in one vectorised pass, with no
law rebuilt and no profile synthesised per trial (``PhaseStretch``).

The direct route — retime the law, build the cam, sample the stretched phase — is kept in
``camcad.scene.mechanism`` (``phase_pressure_function``, ``phase_stress_function``); the tests check
that both give the same relations.

Which neighbour takes up the change follows ``camcad.cyclogram.retime.stretch_phase``: the next dwell
if it is wide enough (the phase keeps its start), else the previous one (it keeps its end).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, cast

import numpy as np

from camcad.arrays import union
from camcad.contact import axial_force, effective_radius, fits, hertz_peak_pressure
from camcad.cyclogram.limits import INADMISSIBLE, PhaseLimit
from camcad.errors import CamcadError
from camcad.extrema import zoom_max
from camcad.law.law import Kinematics
from camcad.numerics import brent_root
from camcad.profile.geometry import CamGeometry, oscillating_track, pitch_geometry, translating_track
from camcad.profile.scaled_law import law_breakpoints

if TYPE_CHECKING:
    from camcad.contact import ContactParams

#: widths evaluated in one pass to bracket the least phase angle before Brent's method narrows it
BRACKET_WIDTHS = 16
#: a finite stand-in for an unbounded curvature ratio (a cusp of the pitch curve) in the sampled maxima
UNBOUNDED = 1e300


@dataclass(frozen=True)
class PhaseStretch:
    """Phase ``index`` of ``cam``'s law, sampled on u ∈ [0, 1] and rescaled to any widths (deg).

    Parameters
    ----------
    cam : CamGeometry
        The cam (law in follower units: mm, or rad of swing).
    scale : float
        Follower units → mm at the roller (the arm for an oscillating follower, else 1).
    phases_deg : list of (start_deg, end_deg, kind)
        The law's phases.
    index : int
        The phase to stretch.
    u : ndarray
        Normalised samples in [0, 1] (the law's breakpoints inside the phase included).
    """

    cam: CamGeometry
    scale: float
    phases_deg: tuple
    index: int
    u: np.ndarray

    @classmethod
    def sample(cls, cam: CamGeometry, scale: float, phases_deg, index: int, samples: int) -> PhaseStretch:
        """Uniform samples on the phase (``samples`` points, ends included) plus its inner breakpoints."""
        start, end, _ = phases_deg[index]
        width = math.radians(end - start)
        u = np.linspace(0.0, 1.0, samples)
        inner = (law_breakpoints(cam.law) - math.radians(start)) / width
        u = union(u, inner[(inner > 0.0) & (inner < 1.0)])
        return cls(cam, float(scale), tuple(tuple(p) for p in phases_deg), index, u)

    @property
    def width_deg(self) -> float:
        start, end, _ = self.phases_deg[self.index]
        return end - start

    @property
    def kind(self) -> str:
        return self.phases_deg[self.index][2]

    def start_deg(self, widths_deg: np.ndarray) -> np.ndarray:
        """Start of the stretched phase (deg) for each width: it keeps its start when the next dwell
        can take up the change, else its end (the previous dwell takes it), as ``stretch_phase`` does."""
        start, end, _ = self.phases_deg[self.index]
        change = np.asarray(widths_deg, dtype=float) - (end - start)
        after = self.index + 1
        before = self.index - 1
        room_after = (self.phases_deg[after][1] - self.phases_deg[after][0]
                      if after < len(self.phases_deg) and self.phases_deg[after][2] == "dwell" else -np.inf)
        keeps_start = room_after - change >= 0.0
        return np.where(keeps_start, start, end - np.asarray(widths_deg, dtype=float)) if before >= 0 else \
            np.full_like(change, start)

    def kinematics(self, widths_deg: np.ndarray, u: np.ndarray | None = None) -> Kinematics:
        """s, v, a, j (follower units) of the phase stretched to each width: arrays of shape (K, N)."""
        widths = np.atleast_1d(np.asarray(widths_deg, dtype=float))
        u = self.u if u is None else u
        start, _, _ = self.phases_deg[self.index]
        base = self.cam.kinematics(math.radians(start) + u * math.radians(self.width_deg))
        ratio = (self.width_deg / widths)[:, None]
        shape = (len(widths), u.shape[-1]) if u.ndim == 1 else u.shape
        theta = np.radians(self.start_deg(widths))[:, None] + u * np.radians(widths)[:, None]
        return Kinematics(theta=np.broadcast_to(theta, shape),
                          s=np.broadcast_to(base.s, shape), v=base.v * ratio, a=base.a * ratio**2,
                          j=base.j * ratio**3)

    def pitch(self, kin: Kinematics):
        """The pitch-curve geometry (pressure angle, radius of curvature, outward speed) of flattened samples."""
        flat = Kinematics(theta=np.zeros(kin.s.size), s=np.ravel(kin.s), v=np.ravel(kin.v), a=np.ravel(kin.a),
                          j=np.ravel(kin.j))
        f = self.cam.follower
        if f.kind == "oscillating":
            track = oscillating_track(flat, cast(float, f.pivot), cast(float, f.arm), self.cam.gamma0)
        else:
            track = translating_track(flat, self.cam.height, f.offset)
        return pitch_geometry(flat.theta, track, self.cam.sigma)

    # -- the pressure angle -------------------------------------------------------------------
    def pressure_max_deg(self, widths_deg: np.ndarray) -> np.ndarray:
        """The largest |pressure angle| (deg) over the phase, for each width: the best sample refined by
        zooming grids around it (``camcad.extrema.zoom_max``)."""
        widths = np.atleast_1d(np.asarray(widths_deg, dtype=float))
        if self.cam.follower.kind == "flat":
            return np.zeros(len(widths))

        def values(u_rows: np.ndarray) -> np.ndarray:
            kin = self.kinematics(widths, u_rows)
            return np.abs(self.pitch(kin).pressure_angle).reshape(u_rows.shape if u_rows.ndim == 2
                                                                  else (len(widths), -1))

        return np.degrees(zoom_max(values, self.u, len(widths))[0])

    def pressure_inverse(self, limit_deg: float) -> float | None:
        """The width (deg) at which the largest |pressure angle| reaches ``limit_deg``, in closed form where
        one exists, else None.

        A translating roller (or knife-edge) follower without offset has tan φ = v/(Rp + s): stretched to
        t the phase keeps s and scales v by β/t, so the worst sample is the same at every width and
        tan φ_max(t) = (β/t)·tan φ_max(β), hence t = β·tan φ_max(β)/tan(limit) — exact, and exactly the
        inverse of ``pressure_max_deg`` (the same samples and refinement at β).
        """
        f = self.cam.follower
        if f.kind in ("flat", "oscillating") or f.offset != 0.0 or not 0.0 < limit_deg < 90.0:
            return None
        own = float(self.pressure_max_deg(np.array([self.width_deg]))[0])
        return self.width_deg * math.tan(math.radians(own)) / math.tan(math.radians(limit_deg))

    # -- undercut and curvature --------------------------------------------------------------
    def curvature_reach(self) -> float:
        """Rr + ρ_min (mm): a convex pitch radius below it undercuts the roller (or breaks the curvature limit);
        0 for a knife edge without a curvature limit (nothing to keep)."""
        f = self.cam.follower
        return float(f.roller_radius + (f.rho_min or 0.0))

    def curvature_ratio(self, widths_deg: np.ndarray) -> np.ndarray:
        """(Rr + ρ_min)·κ_max over the phase stretched to each width (dimensionless), κ = 1/ρ the pitch curve's
        signed curvature (convex positive; a groove's outer flank adds −κ): above 1 the profile undercuts the
        roller (its convex radius ρ − Rr falls below ρ_min, or below 0: a loop). κ stays finite through the
        inflections where ρ is infinite, so the ratio is continuous in the width. The best sample refined by
        zooming grids (``camcad.extrema.zoom_max``)."""
        widths = np.atleast_1d(np.asarray(widths_deg, dtype=float))
        reach = self.curvature_reach()
        groove = self.cam.follower.groove

        def values(u_rows: np.ndarray) -> np.ndarray:
            kin = self.kinematics(widths, u_rows)
            rho = self.pitch(kin).rho
            with np.errstate(divide="ignore", invalid="ignore"):
                kappa = np.where(np.isfinite(rho), 1.0 / rho, 0.0)
            # a pitch cusp (ρ = 0) is an undercut: a large finite ratio (zoom_max leaves non-finite values out)
            ratio = np.nan_to_num(reach * kappa, nan=UNBOUNDED, posinf=UNBOUNDED, neginf=-UNBOUNDED)
            if groove:
                ratio = np.maximum(ratio, -ratio)
            return ratio.reshape(u_rows.shape if u_rows.ndim == 2 else (len(widths), -1))

        return zoom_max(values, self.u, len(widths))[0]

    def flat_radius_deficit(self, widths_deg: np.ndarray, rho_min: float = 0.0) -> np.ndarray:
        """ρ_min − min(Rb + s + a) (mm) over the phase stretched to each width: a flat face's profile radius
        falls below ρ_min (0: a cusp) where it is positive. Stretched to t the phase keeps s and scales a by
        (β/t)². The worst sample refined by zooming grids."""
        widths = np.atleast_1d(np.asarray(widths_deg, dtype=float))
        rb = self.cam.follower.base_radius

        def values(u_rows: np.ndarray) -> np.ndarray:
            kin = self.kinematics(widths, u_rows)
            return (rho_min - (rb + kin.s + kin.a)).reshape(u_rows.shape if u_rows.ndim == 2 else (len(widths), -1))

        return zoom_max(values, self.u, len(widths))[0]

    def flat_least_width(self, rho_min: float = 0.0) -> tuple[float, float]:
        """The least width (deg) at which a flat face keeps its profile radius ρ = Rb + s + a at or above
        ``rho_min`` (0: the cusp condition), in closed form, and the u (0..1 of the phase) that sets it.

        Stretched to t the phase keeps s and scales a by (β/t)², so ρ(u; t) = Rb + s(u) + a(u)(β/t)² ≥ ρ_min
        at every u with a(u) < 0 exactly when t ≥ β·√(−a(u)/(Rb + s(u) − ρ_min)); the least width is the largest
        of these (the samples' best refined by zooming grids). (0, nan) when no sample decelerates; inf when
        Rb + s − ρ_min ≤ 0 where a < 0 (no width helps: the base circle is too small)."""
        f = self.cam.follower
        start, _, _ = self.phases_deg[self.index]
        beta = self.width_deg

        def needed(u: np.ndarray) -> np.ndarray:
            kin = self.cam.kinematics(math.radians(start) + np.ravel(u) * math.radians(beta))
            room = f.base_radius + kin.s - rho_min
            with np.errstate(divide="ignore", invalid="ignore"):
                ratio = np.where(kin.a < 0.0, np.where(room > 0.0, -kin.a / room, UNBOUNDED), 0.0)
            return (beta * np.sqrt(ratio)).reshape(1, -1)

        peak, at = zoom_max(needed, self.u, 1)
        width = float(peak[0])
        return (math.inf if width >= beta * math.sqrt(UNBOUNDED) * 0.5 else width), float(at[0])

    # -- contact stress -----------------------------------------------------------------------
    def stress_max(self, widths_deg: np.ndarray, params: ContactParams, speeds_rpm) -> np.ndarray:
        """σ_max (MPa) over the phase and the speeds, for each width; +inf where the stretched cam is not
        admissible (the roller does not fit a concave flank, the follower jams, or a force-closed follower
        leaves the cam: ``stress_inadmissible`` says which). The sampled maximum, as
        ``camcad.contact.contact_stress`` reports it."""
        worst, jams, no_fit, separation = self._stress(widths_deg, params, speeds_rpm)
        return np.where(jams | no_fit | separation, np.inf, worst)

    def stress_inadmissible(self, width_deg: float, params: ContactParams, speeds_rpm) -> str:
        """Why the phase stretched to ``width_deg`` (deg) is not admissible for contact ("" when it is): the
        force-closed follower leaves the cam, the follower jams, or the roller does not fit a concave flank."""
        _, jams, no_fit, separation = self._stress(np.array([float(width_deg)]), params, speeds_rpm)
        reasons = []
        if separation[0]:
            reasons.append("the force-closed follower leaves the cam (the spring no longer holds it)")
        if jams[0]:
            reasons.append("the follower jams (friction locks it against its guide)")
        if no_fit[0]:
            reasons.append("the roller does not fit a concave flank")
        return "; ".join(reasons)

    def _stress(self, widths_deg: np.ndarray, params: ContactParams, speeds_rpm):
        """(σ_max sampled, jams, roller does not fit, separation), each one value per width."""
        widths = np.atleast_1d(np.asarray(widths_deg, dtype=float))
        kin = self.kinematics(widths)
        pitch = self.pitch(kin)
        f = self.cam.follower
        shape = kin.v.shape
        s, v, a = kin.s * self.scale, kin.v * self.scale, kin.a * self.scale
        phi = pitch.pressure_angle.reshape(shape) if f.kind != "flat" else np.zeros(shape)
        if f.kind == "flat":
            rho = (self.cam.follower.base_radius + kin.s + kin.a)
            radius = math.inf
            back = None
        else:
            radius = float(f.roller_radius)
            rho = pitch.rho.reshape(shape) - radius
            back = -(pitch.rho.reshape(shape) + radius) if f.groove else None
        theta = kin.theta
        load = params.load_over(theta)
        # The axial force m·a·ω²/1000 + k·s + F0 + Q is affine in ω², so at every θ its size (and its sign)
        # is extreme at the slowest or the fastest speed; F_n = F/(cos φ ∓ μ|sin φ|) keeps that, and σ_H
        # grows with |F_n|. The largest σ_H over a speed range, and whether F_n ≤ 0 anywhere in it, are
        # therefore decided by the two end speeds alone (exactly, not approximately).
        given = np.asarray(list(speeds_rpm), dtype=float)
        speeds = np.array([given.min(), given.max()])[:, None, None]   # (2, K, N)
        force = axial_force(s[None], a[None], speeds, params.mass, params.spring_rate, params.preload, load[None])
        mu = params.friction
        denominator = np.cos(phi) - mu * np.abs(np.sin(phi)) * np.sign(v) * np.sign(force)
        jams = np.any(denominator <= 0.0, axis=(0, 2))
        with np.errstate(divide="ignore", invalid="ignore"):
            force_n = force / denominator
        rho_used = np.broadcast_to(rho, force_n.shape)
        if params.closure == "form" and back is not None:
            rho_used = np.where(force_n < 0.0, back[None], rho_used)
        no_fit = ~np.all(fits(rho_used, radius), axis=(0, 2))
        pressing = np.abs(force_n) if params.closure == "form" else np.maximum(force_n, 0.0)
        separation = (np.any(force_n <= 0.0, axis=(0, 2)) if params.closure == "force"
                      else np.zeros(len(widths), dtype=bool))
        with np.errstate(divide="ignore", invalid="ignore"):
            sigma = hertz_peak_pressure(pressing, params.width, effective_radius(rho_used, radius), params.e_star)
        worst = np.nanmax(np.where(np.isfinite(sigma) | np.isinf(sigma), sigma, np.nan), axis=(0, 2))
        return worst, jams, no_fit, separation


def least_angle(relation, limit: float, lower_deg: float, upper_deg: float, *, source: str = "limit",
                what: str = "", xtol_deg: float = 1e-10, inverse=None, reason=None) -> PhaseLimit:
    """The least phase angle t in [lower, upper] (deg) with relation(t) <= limit, for a relation that is
    non-increasing in t and evaluates many widths at once (``relation(widths) -> values``).

    The same answer as ``camcad.cyclogram.limits.least_phase_angle`` (which takes a scalar relation): the
    lower end when it already meets the limit (not binding), a CamcadError when even the upper end does
    not; otherwise the crossing to ``xtol_deg``. One pass over ``BRACKET_WIDTHS`` widths brackets the
    crossing, then Brent's method on single widths narrows it. +inf marks an inadmissible width (e.g. an
    undercut); when the crossing is such a jump rather than the limit, the note says so. ``inverse``
    (limit → width, or None) gives the crossing in closed form where the relation has one
    (``PhaseStretch.pressure_inverse``); the ends are checked as for any relation. ``reason`` (width →
    text, "" where admissible) names what makes a width inadmissible, for the note.
    """
    count = 0

    def many(widths) -> np.ndarray:
        nonlocal count
        widths = np.atleast_1d(np.asarray(widths, dtype=float))
        count += len(widths)
        values = np.asarray(relation(widths), dtype=float)
        if np.any(np.isnan(values)) or np.any(values == -np.inf):
            bad = float(widths[np.flatnonzero(np.isnan(values) | (values == -np.inf))[0]])
            raise CamcadError(f"the {source} relation is not a number at {bad:g} deg", what or source,
                              "check the data of that operation")
        return values

    label = f"{what}: " if what else ""
    ends = many([lower_deg, upper_deg])
    if ends[0] <= limit:
        return PhaseLimit(lower_deg, float(ends[0]), limit, False, source, count)
    if ends[1] > limit:
        reached = "an inadmissible value" if not math.isfinite(ends[1]) else f"{ends[1]:.6g}"
        raise CamcadError(f"{label}even the longest phase angle {upper_deg:g} deg gives {source} {reached} "
                          f"> the limit {limit:g}", what or source,
                          "raise the operation's upper bound, or change the law, materials or loads")
    exact = inverse(limit) if inverse is not None else None
    if exact is not None and lower_deg < exact <= upper_deg:
        at_exact = float(many([exact])[0])
        if math.isfinite(at_exact):
            return PhaseLimit(float(exact), at_exact, limit, True, source, count)
    grid = np.linspace(lower_deg, upper_deg, BRACKET_WIDTHS + 2)[1:-1]
    values = many(grid)
    below = np.flatnonzero(values <= limit)
    hi = float(grid[below[0]]) if len(below) else upper_deg
    lo_candidates = grid[grid < hi]
    lo = float(lo_candidates[-1]) if len(lo_candidates) else lower_deg

    def excess(t: float) -> float:
        value = float(many([t])[0])
        return INADMISSIBLE * (1.0 + abs(limit)) if value == math.inf else value - limit

    root = brent_root(excess, lo, hi, xtol=xtol_deg, rtol=4 * 2.220446049250313e-16)
    step = xtol_deg
    while excess(root) >= INADMISSIBLE and root < upper_deg:   # at a jump to inadmissible: step inside
        root = min(root + step, upper_deg)
        step *= 2.0
    value = float(many([root])[0])
    note = ""
    if value < limit - 1e-6 * abs(limit):
        note = inadmissible_note(root, source, value, reason)
    return PhaseLimit(float(root), value, limit, True, source, count, note)


def inadmissible_note(root_deg: float, source: str, value: float, reason=None) -> str:
    """The note of a least phase angle set by a jump to inadmissible widths rather than by its limit: what
    makes the widths just below ``root_deg`` inadmissible (``reason(width)``; a generic phrase without it)."""
    why = ""
    if reason is not None:
        below = root_deg * (1.0 - 1e-7) - 1e-9
        why = reason(below) or ""
    why = why or "the stretched cam is not admissible"
    return (f"set at {root_deg:.6g} deg, below which the phase is inadmissible: {why}; {source} there is "
            f"{value:.6g}, under its limit")
