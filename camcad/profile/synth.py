"""Profile synthesis for one mechanism: curves, checks and figures (the library entry point).

``synthesize(law, follower, settings)`` builds the exact geometry (``geometry.CamGeometry``),
places the written points by the chord tolerance (``sampling``), finds the extrema of the
pressure angle and of the radii of curvature (grid search refined by zooming grids, ``camcad.extrema``),
and runs the checks: pressure angle against its limits per phase, undercut (a convex pitch
radius ≤ Rr, a flat-face radius ≤ 0, or a loop or cusp, which shapely sees as a profile
polygon that is not valid and simple), the curvature limit, and closure. ``report(result)``
gives the docs/INTERFACE.md keys; ``output.write_outputs`` writes the files.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import cast

import numpy as np

from camcad.arrays import union
from camcad.errors import CamcadError
from camcad.extrema import zoom_max, zoom_min
from camcad.law.law import Kinematics, MotionLaw
from camcad.profile import defaults
from camcad.profile.design import BaseRadiusDesign, min_base_radius
from camcad.profile.followers import Follower
from camcad.profile.geometry import (
    CamGeometry,
    CurveGeometry,
    PitchGeometry,
    flat_face_profile,
    parallel_curve,
    pitch_geometry,
    pitch_points,
    rotate,
)
from camcad.profile.sampling import (
    MAX_NODES,
    ArcPath,
    CurveFn,
    Polyline,
    SplineData,
    biarc_fit,
    chord_nodes_joint,
    interpolating_spline,
    predicted_nodes,
)


@dataclass(frozen=True)
class ProfileSettings:
    """How to synthesise a cam profile and what to write.

    Parameters
    ----------
    tol_mm : float
        Chord tolerance: the largest distance between the written and the exact curve, mm (at most 1).
    arcs : bool
        Write the profile as lines and tangent arcs (bulges) instead of chords.
    spline : bool
        Also write a closed control-point SPLINE of the profile (not with ``r12``).
    r12 : bool
        Write DXF R12 instead of R2000.
    plots : bool
        Write the summary plot (PNG) with the files.
    csv_step_deg : float
        Step of the law.csv table, deg (0 < step ≤ 10).
    analysis_step_deg : float
        Grid step of the extremum search before its refinement by zooming grids, deg.
    design : bool
        Also compute the smallest base radius meeting the limits (``min_base_radius``).
    name : str
        The design's name (output folder, drawing title).
    checks_only : bool
        Skip what only the written files need: the pitch curves' chord polylines (left empty; every check
        figure is the same; ``camcad sweep`` uses it).

    Examples
    --------
    >>> import camcad
    >>> settings = camcad.ProfileSettings(tol_mm=0.01, arcs=True, plots=False)
    >>> settings.validate().tol_mm
    0.01
    >>> camcad.ProfileSettings(r12=True, spline=True).validate()
    Traceback (most recent call last):
    ...
    camcad.errors.CamcadError: --r12 --spline: DXF R12 has no SPLINE entity; drop --spline, or drop --r12 to write R2000
    """

    tol_mm: float = defaults.CHORD_TOLERANCE_MM
    arcs: bool = False
    spline: bool = False
    r12: bool = False
    plots: bool = True
    csv_step_deg: float = defaults.CSV_STEP_DEG
    analysis_step_deg: float = 0.1
    design: bool = True
    name: str = "profile"
    checks_only: bool = False

    def validate(self) -> ProfileSettings:
        if not (math.isfinite(self.tol_mm) and self.tol_mm > 0.0):
            raise CamcadError(f"chord tolerance must be a positive number of mm, got {self.tol_mm!r}",
                              "--tol-mm", "give e.g. --tol-mm 0.001")
        if self.tol_mm > 1.0:
            raise CamcadError(f"chord tolerance {self.tol_mm:g} mm is coarser than 1 mm", "--tol-mm",
                              "give a tolerance of at most 1 mm")
        if self.r12 and self.spline:
            raise CamcadError("DXF R12 has no SPLINE entity", "--r12 --spline",
                              "drop --spline, or drop --r12 to write R2000")
        if not 0.0 < self.csv_step_deg <= 10.0:
            raise CamcadError(f"csv step {self.csv_step_deg:g} deg is out of range", "csv_step_deg",
                              "give a step between 0 and 10 deg")
        return self


@dataclass(frozen=True)
class Extremum:
    """A value and the cam angle where it occurs (θ in rad)."""

    value: float
    at: float

    def deg(self) -> dict:
        return {"value": self.value, "at_deg": math.degrees(self.at)}


@dataclass(frozen=True)
class CurveResult:
    """One written curve (profile, pitch curve, groove flank, counter-cam) and its checks.

    polyline: chord nodes within the tolerance (all lobes; the closing node is dropped when the
              curve closes). arcs / spline: the other representations, when asked for.
    rho_convex_min:  smallest radius of curvature of its convex parts (mm).
    rho_concave_min: smallest |radius| of its concave parts (mm), None if it has none.
    simple:   shapely finds the closed polygon valid and its ring simple (no loop, no cusp); None for a
              curve not written (``ProfileSettings.checks_only``: its polyline is empty).
    closure_gap: distance between the curve's end and its start (mm); closed: gap ≤ tol.
    """

    name: str
    polyline: Polyline
    arcs: ArcPath | None
    spline: SplineData | None
    rho_convex_min: Extremum | None
    rho_concave_min: Extremum | None
    simple: bool | None
    closure_gap: float
    closed: bool


@dataclass(frozen=True)
class LawTable:
    """The law and the checks on a uniform θ grid (law.csv, plots, contact stress).

    theta (rad); s, v, a, j in follower units (mm or rad of swing, per rad of cam angle);
    pressure_angle (rad); limit (rad, NaN where none applies); rho_pitch and rho_profile (mm,
    signed, + convex); the roller centre in the fixed frame ``centre`` (mm).
    """

    theta: np.ndarray
    s: np.ndarray
    v: np.ndarray
    a: np.ndarray
    j: np.ndarray
    pressure_angle: np.ndarray
    limit: np.ndarray
    rho_pitch: np.ndarray
    rho_profile: np.ndarray


@dataclass(frozen=True)
class PressureAngleCheck:
    """Pressure-angle figures (rad) and the verdict. ``worst_margin`` = min(limit − |φ|)."""

    maximum: Extremum
    minimum: Extremum
    rise_max: Extremum | None
    return_max: Extremum | None
    worst_margin: Extremum | None
    passed: bool


@dataclass(frozen=True)
class ProfileResult:
    """Everything ``synthesize`` found: the curves, the checks and the law table (mm and rad).

    Returned by ``synthesize``; ``camcad.report`` turns it into the docs/INTERFACE.md keys (deg and mm),
    ``write_outputs`` into files and the ``plot_*`` functions into figures.

    Attributes
    ----------
    name : str
        The design's name.
    law : MotionLaw
        The law the cam was made for (θ in rad; s in mm, or rad of swing for an oscillating follower).
    follower : Follower
        The follower (validated).
    settings : ProfileSettings
        The settings used.
    geometry : CamGeometry
        The exact geometry: pitch curve, profile, pressure angle as functions of θ (rad).
    profile : CurveResult
        The cam profile as written: chord polyline (mm) within ``settings.tol_mm``, optional arcs and
        spline, its smallest convex and concave radii of curvature (mm), closure gap (mm).
    pitch : CurveResult
        The pitch curve (path of the roller centre), mm.
    outer : CurveResult or None
        The outer flank of a groove cam (``follower.groove``), mm.
    counter : CurveResult or None
        The counter-cam profile of a conjugate pair, mm.
    counter_pitch : CurveResult or None
        The counter-cam's pitch curve, mm.
    table : LawTable
        The law and the checks on a uniform grid: θ (rad), s, v, a, j (follower units per rad of cam
        angle), pressure angle and its limit (rad), radii of curvature (mm).
    pressure_angle : PressureAngleCheck
        Extremes of the pressure angle (rad) with where they occur (θ in rad), the worst margin to the
        limits (rad) and the verdict.
    counter_pressure_angle : PressureAngleCheck or None
        The same for the counter-cam's roller.
    rho_pitch_min : Extremum or None
        Smallest convex radius of curvature of the pitch curve (mm) and its θ (rad).
    rho_pitch_concave_min : Extremum or None
        Smallest |radius| of the concave parts of the pitch curve (mm) and its θ (rad).
    undercut : bool
        The profile undercuts (loop or cusp); ``undercut_reasons`` says why.
    undercut_reasons : tuple of str
        Each reason, in words with its figures (mm, deg).
    curvature_passed : bool
        Every convex radius of curvature is at least ``follower.rho_min``.
    closure_kink : float
        Angle between the profile's tangents where the cycle closes, rad (0 for a balanced law).
    design : BaseRadiusDesign or None
        The smallest base radii (mm) meeting the limits, when ``settings.design``.
    face_extent : (float, float) or None
        Flat-faced follower: the extent of the contact point on the face, mm.
    notes : tuple of str
        What the synthesis noticed, in words.
    """

    name: str
    law: MotionLaw
    follower: Follower
    settings: ProfileSettings
    geometry: CamGeometry
    profile: CurveResult
    pitch: CurveResult
    outer: CurveResult | None
    counter: CurveResult | None
    counter_pitch: CurveResult | None
    table: LawTable
    pressure_angle: PressureAngleCheck
    counter_pressure_angle: PressureAngleCheck | None
    rho_pitch_min: Extremum | None
    rho_pitch_concave_min: Extremum | None
    undercut: bool
    undercut_reasons: tuple[str, ...]
    curvature_passed: bool
    closure_kink: float
    design: BaseRadiusDesign | None
    face_extent: tuple[float, float] | None
    notes: tuple[str, ...] = field(default=())

    @property
    def checks(self) -> dict[str, bool]:
        """Each design check and whether it passed."""
        out = {"pressure_angle": self.pressure_angle.passed, "undercut": not self.undercut,
               "curvature": self.curvature_passed, "closed": self.profile.closed}
        if self.counter_pressure_angle is not None:
            out["counter_pressure_angle"] = self.counter_pressure_angle.passed
        return out

    @property
    def passed(self) -> bool:
        return all(self.checks.values())


# --------------------------------------------------------------------------------------------
# extrema
# --------------------------------------------------------------------------------------------

def refine_min(fn, theta: np.ndarray, values: np.ndarray) -> Extremum | None:
    """Smallest finite value of ``fn`` (θ → array): best grid point, refined by zooming grids between its
    neighbours (``camcad.extrema.zoom_min``). ``values`` = fn(theta); non-finite entries are excluded."""
    if not np.isfinite(values).any():
        return None
    return Extremum(*zoom_min(fn, theta, first=values))


def refine_max(fn, theta: np.ndarray, values: np.ndarray) -> Extremum | None:
    found = refine_min(lambda t: -fn(t), theta, -values)
    return None if found is None else Extremum(-found.value, found.at)


def _convex(rho: np.ndarray) -> np.ndarray:
    return np.where(rho > 0.0, rho, np.inf)


def _concave(rho: np.ndarray) -> np.ndarray:
    return np.where(rho < 0.0, -rho, np.inf)


# --------------------------------------------------------------------------------------------
# curves
# --------------------------------------------------------------------------------------------

def _replicate(points: np.ndarray, lobes: int, cycle: float, sigma: float) -> np.ndarray:
    """Copies of one lobe's points turned by −σ·k·cycle for k = 0 … lobes − 1, joined."""
    parts = [points[:-1] if lobes > 1 else points]
    for k in range(1, lobes):
        turned = rotate(points, np.full(len(points), -sigma * k * cycle))
        parts.append(turned[:-1] if k < lobes - 1 else turned)
    return np.concatenate(parts)


def _check_pair_clearance(geometry: CamGeometry, analysis: np.ndarray, first=None) -> None:
    """Refuse a conjugate pair whose second roller covers the cam centre somewhere in the cycle.

    A roller of radius Rr whose centre comes within Rr of the cam's axis would have to pass
    through the shaft: no counter-cam exists (its offset curve is undefined there).
    """
    follower = geometry.follower
    if first is not None:
        centre = first.second.centre
    else:
        with np.errstate(invalid="ignore", divide="ignore"):  # the normal is undefined where it crosses
            centre = geometry.pitch(analysis, second=True).centre
    radius = np.hypot(centre[:, 0], centre[:, 1])
    clearance = radius - follower.roller_radius
    worst = int(np.nanargmin(np.where(np.isfinite(clearance), clearance, -np.inf)))
    if np.isfinite(clearance[worst]) and clearance[worst] > 1e-9 * max(1.0, follower.roller_radius):
        return
    key = "pair_distance" if follower.pair_distance is not None else "pair_angle"
    setting = (f"{follower.pair_distance:g} mm" if follower.pair_distance is not None
               else f"{follower.pair_angle_deg:g} deg")
    raise CamcadError(
        f"the second roller of the pair covers the cam centre at {math.degrees(analysis[worst]):.2f} deg "
        f"(its centre {radius[worst]:.3f} mm from the axis, roller radius {follower.roller_radius:g} mm)",
        f"follower {key} = {setting}",
        "choose a pair distance (or angle) that keeps the second roller clear of the cam shaft "
        "for the whole cycle")


def _is_simple(points: np.ndarray) -> bool:
    """The closed polygon is valid and its ring simple (no loop, no cusp overlap).

    Most cams are star-shaped about their axis: when every edge turns the polar angle about the origin
    forwards by less than π and the edges turn it by exactly one full turn, every ray from the axis
    meets the ring once, so the ring is simple and bounds a valid polygon (a sufficient condition,
    exact, in one vectorised pass). Anything else goes to shapely (20 ms to import)."""
    if len(points) < 4 or not np.all(np.isfinite(points)):
        return False
    if _star_shaped(points):
        return True
    import shapely

    ring = shapely.LinearRing(points)
    return bool(ring.is_simple and shapely.Polygon(ring).is_valid)


def _star_shaped(points: np.ndarray) -> bool:
    """True when the closed ring (its last point joined to its first) turns once about the origin, every
    edge forwards (or every edge backwards) by less than π, and passes clear of the origin."""
    if np.any(points[0] != points[-1]):
        points = np.concatenate((points, points[:1]))
    x, y = points[:, 0], points[:, 1]
    if np.any(np.hypot(x, y) == 0.0):
        return False
    cross = x[:-1] * y[1:] - y[:-1] * x[1:]
    dot = x[:-1] * x[1:] + y[:-1] * y[1:]
    turn = np.arctan2(cross, dot)                 # the signed angle each edge subtends at the origin
    if not (np.all(cross > 0.0) or np.all(cross < 0.0)):
        return False
    # one turn: 2π to round-off (each term is exact to an ulp of π, and there are len(turn) of them)
    return bool(abs(abs(math.fsum(turn)) - 2.0 * math.pi) < 1e-9)


def libreoffice_arcs_note(arcs: ArcPath) -> str:
    """What LibreOffice Draw shows of a profile written as tangent arcs: it draws a polyline's bulges as the
    chords between the arcs' ends (measured with LibreOffice Draw 7.4), up to the largest sagitta
    c·|b|/2 (c the chord, b the bulge) inside the arcs."""
    v = arcs.vertices
    ends = np.roll(v, -1, axis=0) if len(arcs.bulges) == len(v) else v[1:]
    chord = np.hypot(*(ends - v[: len(ends)]).T)
    sagitta = float(np.max(chord * np.abs(arcs.bulges[: len(ends)]) / 2.0, initial=0.0))
    return (f"LibreOffice Draw (7.4) draws the tangent arcs as their chords, up to {sagitta:.3g} mm off the profile; "
            "for LibreOffice write the profile without --arcs (chords within the tolerance) or use cam.step")


def _written_curves(geometry: CamGeometry, settings: ProfileSettings) -> list[tuple[str, CurveFn]]:
    """(name, curve) of every curve profile.dxf holds as points (as ``synthesize`` writes them)."""
    follower = geometry.follower
    curves: list[tuple[str, CurveFn]] = [("profile", geometry.profile)]
    if not settings.checks_only:
        curves.append(("pitch", geometry.pitch))
    if follower.groove:
        curves.append(("outer flank", geometry.outer_flank))
    if follower.has_pair:
        curves.append(("counter-cam", geometry.counter_profile))
        if not settings.checks_only:
            curves.append(("counter-cam pitch", lambda t: geometry.pitch(t, second=True)))
    return curves


def _check_point_budget(geometry: CamGeometry, settings: ProfileSettings) -> None:
    """Refuse, before any point is placed, a cam whose written curves would hold more than ``MAX_NODES`` points
    together (every curve of profile.dxf, every lobe, and the spline's control points when asked for): the
    count is predicted from the chord tolerance on a pilot grid (``sampling.predicted_nodes``)."""
    cycle = float(geometry.law.cycle)
    breaks = geometry.breakpoints()
    breaks = breaks[breaks <= cycle]
    per_curve = {}
    for name, curve in _written_curves(geometry, settings):
        with np.errstate(all="ignore"):
            count = geometry.lobes * predicted_nodes(curve, 0.0, cycle, settings.tol_mm, breaks)
        per_curve[name] = count * (2 if settings.spline and name in ("profile", "outer flank", "counter-cam") else 1)
    total = sum(per_curve.values())
    if not total <= MAX_NODES:
        parts = ", ".join(f"{name} {count:.3g}" for name, count in per_curve.items())
        raise CamcadError(f"the written curves would hold about {total:.3g} points ({parts}), more than camcad "
                          f"writes ({MAX_NODES:,})", "profile",
                          f"use a coarser --tol-mm (now {settings.tol_mm:g} mm) or a smaller cam (base radius "
                          f"{geometry.follower.base_radius:g} mm)")


# --------------------------------------------------------------------------------------------
# every curve of the mechanism at once
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Sample:
    """The law, the pitch curve(s) and every curve of the cam at the same θ (one kinematics evaluation)."""

    kin: Kinematics
    pitch: PitchGeometry
    second: PitchGeometry | None
    curves: dict[str, CurveGeometry]


def _sampler(geometry: CamGeometry):
    """θ → _Sample: the profile, the pitch curve, the outer flank of a groove, the counter-cam and its pitch
    curve, from one evaluation of the law (as ``CamGeometry.profile``, ``pitch``, ``outer_flank`` and
    ``counter_profile`` give them one at a time)."""
    follower = geometry.follower
    rr, sigma = follower.roller_radius, geometry.sigma

    def sample(theta) -> _Sample:
        theta = np.asarray(theta, dtype=float)
        kin = geometry.kinematics(theta)
        pitch = pitch_geometry(theta, geometry.track_of(kin), sigma)
        second = None
        curves: dict[str, CurveGeometry] = {"pitch": pitch}
        if follower.kind == "flat":
            curves["profile"] = flat_face_profile(theta, kin, follower.base_radius, sigma)
        else:
            curves["profile"] = parallel_curve(pitch, rr)
        if follower.groove:
            curves["outer flank"] = parallel_curve(pitch, -rr)
        if follower.has_pair:
            with np.errstate(invalid="ignore", divide="ignore"):  # undefined where the pair cannot exist
                second = pitch_geometry(theta, geometry.track_of(kin, second=True), sigma)
                curves["counter-cam"] = parallel_curve(second, rr)
            curves["counter-cam pitch"] = second
        return _Sample(kin, pitch, second, curves)

    def points(theta) -> dict[str, np.ndarray]:
        """The points alone of every curve at θ (as ``sample(theta).curves[name].points``)."""
        theta = np.asarray(theta, dtype=float)
        kin = geometry.kinematics(theta)
        centre, normal = pitch_points(theta, geometry.track_of(kin), sigma)
        found = {"pitch": centre}
        if follower.kind == "flat":
            found["profile"] = flat_face_profile(theta, kin, follower.base_radius, sigma).points
        else:
            found["profile"] = centre - rr * normal
        if follower.groove:
            found["outer flank"] = centre - (-rr) * normal
        if follower.has_pair:
            with np.errstate(invalid="ignore", divide="ignore"):
                other, other_normal = pitch_points(theta, geometry.track_of(kin, second=True), sigma)
                found["counter-cam"] = other - rr * other_normal
            found["counter-cam pitch"] = other
        return found

    sample.points = points  # type: ignore[attr-defined]
    return sample


def _objectives(geometry: CamGeometry, names: list[str]) -> list[tuple[str, bool, object]]:
    """(key, is a minimum, f(sample) → values) of every extremum the checks need: the smallest convex and
    concave radius of each curve, the pressure angle's extremes, its peaks on the rise and the return and the
    worst margin to its limits (per roller), the flat face's lowest signed radius. A minimum is found as
    the maximum of −f."""
    follower = geometry.follower
    found: list[tuple[str, bool, object]] = []
    for name in names:
        found.append((f"{name}:convex", True, lambda smp, n=name: -_convex(smp.curves[n].rho)))
        found.append((f"{name}:concave", True, lambda smp, n=name: -_concave(smp.curves[n].rho)))
    flat = follower.kind == "flat"
    for second in ((False, True) if follower.has_pair else (False,)):
        tag = "counter" if second else "main"

        def pitch_of(smp: _Sample, second=second) -> PitchGeometry:
            return cast(PitchGeometry, smp.second if second else smp.pitch)

        def phi(smp: _Sample, pitch_of=pitch_of) -> np.ndarray:
            return np.zeros_like(smp.kin.theta) if flat else pitch_of(smp).pressure_angle

        found.append((f"{tag}:max", False, phi))
        found.append((f"{tag}:min", True, lambda smp, phi=phi: -phi(smp)))
        if flat:
            continue

        def moving(smp: _Sample, kind: str, pitch_of=pitch_of) -> np.ndarray:
            p = pitch_of(smp)
            going = p.outward_speed > geometry.dwell_speed if kind == "rise" else \
                p.outward_speed < -geometry.dwell_speed
            return np.where(going, np.abs(p.pressure_angle), -np.inf)

        def margin(smp: _Sample, pitch_of=pitch_of) -> np.ndarray:
            p = pitch_of(smp)
            limit = geometry.pressure_angle_limit(p.outward_speed)
            return np.where(np.isnan(limit), np.inf, limit - np.abs(p.pressure_angle))

        found.append((f"{tag}:rise", False, lambda smp, moving=moving: moving(smp, "rise")))
        found.append((f"{tag}:return", False, lambda smp, moving=moving: moving(smp, "return")))
        found.append((f"{tag}:margin", True, lambda smp, margin=margin: -margin(smp)))
    if flat:
        found.append(("flat:lowest", True, lambda smp: -smp.curves["profile"].rho))
    return found


def _extrema(sample, analysis: np.ndarray, first: _Sample, objectives) -> dict[str, Extremum | None]:
    """Every objective's extremum over the analysis grid, refined by zooming grids (``camcad.extrema``), all
    objectives in one evaluation of the mechanism per level; None where an objective has no finite value.
    Each row follows exactly the steps ``refine_min`` / ``refine_max`` take for it alone."""
    values = np.array([np.broadcast_to(fn(first), analysis.shape) for _, _, fn in objectives], dtype=float)
    active = [r for r in range(len(objectives)) if np.isfinite(values[r]).any()]
    out: dict[str, Extremum | None] = {key: None for key, _, _ in objectives}
    if not active:
        return out
    functions = [objectives[r][2] for r in active]

    def evaluate(u: np.ndarray) -> np.ndarray:
        u = np.asarray(u, dtype=float)
        smp = sample(u.ravel())
        result = np.empty(u.shape)
        for row, fn in enumerate(functions):
            result[row] = np.broadcast_to(fn(smp), (u.size,)).reshape(u.shape)[row]
        return result

    peak, at = zoom_max(evaluate, analysis, len(active), first=values[active])
    for row, r in enumerate(active):
        key, minimum, _ = objectives[r]
        out[key] = Extremum(float(-peak[row]) if minimum else float(peak[row]), float(at[row]))
    return out


def _ends(sample, geometry: CamGeometry) -> _Sample:
    return sample(np.array([0.0, float(geometry.law.cycle)]))


def gap_and_kink(ends: CurveGeometry, geometry: CamGeometry) -> tuple[float, float]:
    """Gap (mm) between the end of one lobe and the start of the next, in the fixed frame, and the angle (rad)
    between their tangents; ``ends`` is the curve at θ = 0 and at the cycle's end."""
    cycle = float(geometry.law.cycle)
    back = geometry.sigma * cycle  # undo the cam's turn so both points are in the fixed frame
    end_point = rotate(ends.points[1:], np.array([back]))[0]
    end_tangent = rotate(ends.tangent[1:], np.array([back]))[0]
    gap = float(np.hypot(*(end_point - ends.points[0])))
    kink = float(abs(math.atan2(end_tangent[0] * ends.tangent[0][1] - end_tangent[1] * ends.tangent[0][0],
                                float(np.dot(end_tangent, ends.tangent[0])))))
    return gap, kink


def written_curve(name: str, one: Polyline, curve, geometry: CamGeometry, settings: ProfileSettings,
                   gap: float, extrema: dict, want_arcs: bool, want_spline: bool, notes: list[str]) -> CurveResult:
    """A written curve from its chord nodes on one lobe (``one``): all lobes, arcs and spline when asked."""
    cycle = float(geometry.law.cycle)
    lobes, sigma = geometry.lobes, geometry.sigma
    closed = gap <= settings.tol_mm
    theta_all = np.concatenate([one.theta[:-1] + k * cycle for k in range(lobes)] + [[2.0 * math.pi]])
    points_all = _replicate(one.points, lobes, cycle, sigma)
    if closed:
        theta_all, points_all = theta_all[:-1], points_all[:-1]
    polyline = Polyline(theta_all, points_all, one.max_deviation)
    arcs = None
    if want_arcs:
        breaks = geometry.breakpoints()
        breaks = breaks[breaks <= cycle]
        try:
            path = biarc_fit(curve, 0.0, cycle, settings.tol_mm, breaks, samples=17)
            vertices = _replicate(path.vertices, lobes, cycle, sigma)
            bulges = np.concatenate([path.bulges[:-1]] * lobes + [path.bulges[-1:]])
            arc_theta = np.concatenate([path.theta[:-1] + k * cycle for k in range(lobes)] + [[2.0 * math.pi]])
            if closed:
                vertices, bulges = vertices[:-1], bulges[:-1]
            arcs = ArcPath(arc_theta, vertices, bulges, path.max_deviation)
            if name == "profile":
                notes.append(libreoffice_arcs_note(arcs))
        except CamcadError as err:
            notes.append(f"{name}: no tangent arcs written ({err.what})")
    spline = None
    if want_spline:
        if closed:
            spline = interpolating_spline(curve, np.append(polyline.theta, 2.0 * math.pi))
            if name == "profile":
                notes.append("LibreOffice Draw (7.4) does not draw SPLINE entities: it shows the layer PROFILE's "
                             "chord polyline (within the chord tolerance), not PROFILE_SPLINE")
        else:
            notes.append(f"{name}: no spline written, the curve does not close")
    ring = points_all if closed else np.concatenate((points_all, points_all[:1]))
    return CurveResult(name, polyline, arcs, spline, extrema[f"{name}:convex"], extrema[f"{name}:concave"],
                       _is_simple(ring), gap, closed)


# --------------------------------------------------------------------------------------------
# pressure angle
# --------------------------------------------------------------------------------------------

def _pressure_from(extrema: dict, tag: str, follower: Follower) -> PressureAngleCheck:
    """The pressure-angle check of one roller (``tag`` "main" or "counter") from the refined extrema."""
    maximum = cast(Extremum, extrema[f"{tag}:max"])   # φ is finite on the whole grid: both extremes exist
    minimum = cast(Extremum, extrema[f"{tag}:min"])
    if follower.kind == "flat":
        return PressureAngleCheck(maximum, minimum, None, None, None, True)
    worst = extrema[f"{tag}:margin"]
    passed = worst is None or worst.value >= -1e-12
    return PressureAngleCheck(maximum, minimum, extrema[f"{tag}:rise"], extrema[f"{tag}:return"], worst, passed)


# --------------------------------------------------------------------------------------------
# synthesis
# --------------------------------------------------------------------------------------------

def analysis_grid(geometry: CamGeometry, step_deg: float) -> np.ndarray:
    """Uniform θ over the cam's turn (rad) with the law's breakpoints added."""
    count = math.ceil(360.0 / step_deg)
    return union(np.linspace(0.0, 2.0 * math.pi, count + 1), geometry.breakpoints())


def law_table(geometry: CamGeometry, step_deg: float, sample=None) -> LawTable:
    """The law and the checks on a uniform grid of ``step_deg`` (``sample``: the mechanism's ``_sampler``)."""
    count = int(round(360.0 / step_deg))  # noqa: RUF046 - round() of a numpy float is a float on numpy < 2
    theta = np.linspace(0.0, 2.0 * math.pi, count + 1)
    smp = (sample or _sampler(geometry))(theta)
    kin, pitch = smp.kin, smp.pitch
    if geometry.follower.kind == "flat":
        phi = np.zeros_like(theta)
        limit = np.full_like(theta, np.nan)
        rho_profile = smp.curves["profile"].rho
    else:
        phi = pitch.pressure_angle
        limit = geometry.pressure_angle_limit(pitch.outward_speed)
        rho_profile = pitch.rho - geometry.follower.roller_radius
    return LawTable(theta, kin.s, kin.v, kin.a, kin.j, phi, limit, pitch.rho, rho_profile)


def synthesize(law: MotionLaw, follower: Follower, settings: ProfileSettings | None = None,
               name: str | None = None) -> ProfileResult:
    """Synthesise the cam profile for a law and a follower, and check it.

    Builds the exact geometry, places the written points by the chord tolerance, finds the extrema of
    the pressure angle and of the radii of curvature (grid search refined by zooming grids)
    and runs the checks: pressure angle within its limits per phase; no undercut (convex pitch
    radius ≤ Rr, flat-face radius ≤ 0, or a profile polygon that shapely finds not valid and simple);
    convex profile radius ≥ ``follower.rho_min`` when given; the profile closes within ``tol_mm``.
    For a translating roller follower the pressure angle is φ = atan((v − e)/(d + s)),
    d = √(Rp² − e²), Rp = Rb + Rr (docs/INTERFACE.md).

    Parameters
    ----------
    law : MotionLaw
        The follower's motion: s in mm (translating follower) or in rad of swing (oscillating
        follower; see ``camcad.profile.followers.swing_law``) against θ in rad; e.g. ``compose`` or
        ``load_law(...).law``.
    follower : Follower
        The follower and its limits (mm, deg).
    settings : ProfileSettings, optional
        Chord tolerance (mm), representation, analysis step (deg); defaults when None.
    name : str, optional
        The design's name; ``settings.name`` when None.

    Returns
    -------
    ProfileResult
        Curves in mm, angles in rad, and the checks; ``camcad.profile_report(result)`` gives them in deg
        and mm with every margin.

    Raises
    ------
    CamcadError
        A follower that cannot work (``Follower.validate``) or settings out of range.

    References
    ----------
    R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 7–8 (pressure angle and
    radius of curvature of roller and flat followers).
    J. Angeles, C. S. López-Cajún, Optimization of Cam Mechanisms (1991), ch. 2.

    Examples
    --------
    A cycloidal dwell–rise–dwell–return cycle of 20 mm and a translating roller follower, Rb 40 mm,
    Rr 10 mm, no offset. The largest pressure angle, by hand from docs/INTERFACE.md's formula on a fine grid of
    the law, is the one ``synthesize`` found by its own search:

    >>> import numpy as np
    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> follower = camcad.Follower("roller", base_radius=40.0, roller_radius=10.0)
    >>> result = camcad.synthesize(law, follower, camcad.ProfileSettings(plots=False))
    >>> k = camcad.kinematics_deg(law, np.linspace(0.0, 90.0, 90001))
    >>> by_hand = np.degrees(np.arctan(k.v / (40.0 + 10.0 + k.s))).max()
    >>> round(float(by_hand), 6), round(float(np.degrees(result.pressure_angle.maximum.value)), 6)
    (23.233017, 23.233017)
    >>> result.passed, result.undercut, result.profile.closed
    (True, False, True)
    """
    settings = (settings or ProfileSettings()).validate()
    geometry = CamGeometry(law, follower)
    follower = geometry.follower
    notes: list[str] = []
    analysis = analysis_grid(geometry, settings.analysis_step_deg)
    _check_point_budget(geometry, settings)   # every written curve, all lobes, before any point is placed
    sample = _sampler(geometry)
    first = sample(analysis)
    if follower.has_pair:
        _check_pair_clearance(geometry, analysis, first)
    names = ["profile", "pitch"] + (["outer flank"] if follower.groove else []) + \
        (["counter-cam", "counter-cam pitch"] if follower.has_pair else [])
    written = [n for n in names if not (settings.checks_only and n in ("pitch", "counter-cam pitch"))]
    extrema = _extrema(sample, analysis, first, _objectives(geometry, names))
    cycle = float(geometry.law.cycle)
    breaks = geometry.breakpoints()
    chords = chord_nodes_joint(lambda t: sample(t).curves, written, 0.0, cycle, settings.tol_mm,
                               breaks[breaks <= cycle], points=sample.points)
    ends = _ends(sample, geometry)
    functions = {"profile": geometry.profile, "pitch": geometry.pitch, "outer flank": geometry.outer_flank,
                 "counter-cam": geometry.counter_profile,
                 "counter-cam pitch": lambda t: geometry.pitch(t, second=True)}
    results: dict[str, CurveResult] = {}
    for label in names:
        gap, _ = gap_and_kink(ends.curves[label], geometry)
        if label not in written:   # only its figures: the radii of curvature and the closure
            empty = Polyline(np.empty(0), np.empty((0, 2)), 0.0)
            results[label] = CurveResult(label, empty, None, None, extrema[f"{label}:convex"],
                                         extrema[f"{label}:concave"], None, gap, gap <= settings.tol_mm)
            continue
        drawn = label in ("profile", "outer flank", "counter-cam")
        results[label] = written_curve(label, chords[label], functions[label], geometry, settings, gap, extrema,
                                        drawn and settings.arcs, drawn and settings.spline, notes)
    face = None
    if follower.kind == "flat":
        v = first.kin.v * follower.sigma
        face = (float(v.min() - follower.offset), float(v.max() - follower.offset))
    _, kink = gap_and_kink(ends.curves["profile"], geometry)
    return assemble_result(name or settings.name, law, follower, settings, geometry, results, extrema, kink,
                           law_table(geometry, settings.csv_step_deg, sample), face, notes)


def assemble_result(name: str, law: MotionLaw, follower: Follower, settings: ProfileSettings, geometry: CamGeometry,
                    results: dict, extrema: dict, kink: float, table: LawTable, face, notes: list[str]
                    ) -> ProfileResult:
    """A ProfileResult from its curves (``results``: name → CurveResult), the refined extrema, the closure's kink
    (rad) and the law table: the pressure-angle checks, the undercut's reasons, the curvature limit, the notes and
    (with ``settings.design``) the smallest base radius. ``synthesize`` and its batch over followers
    (``camcad.profile.batch``) both end here."""
    rr = follower.roller_radius
    profile, pitch = results["profile"], results["pitch"]
    outer = results.get("outer flank")
    counter, counter_pitch = results.get("counter-cam"), results.get("counter-cam pitch")
    pressure = _pressure_from(extrema, "main", follower)
    counter_pressure = _pressure_from(extrema, "counter", follower) if follower.has_pair else None

    reasons: list[str] = []
    if follower.kind == "flat":
        # the signed radius Rb + s + a is smooth, so its own minimum is found even where it dips below
        # zero for less than a step of the analysis grid (the convex and concave minima cannot see that)
        lowest = extrema["flat:lowest"]
        if lowest is not None and lowest.value <= 0.0:
            reasons.append(f"flat-face radius Rb + s + a <= 0 at {math.degrees(lowest.at):.3f} deg")
    elif rr > 0.0 and pitch.rho_convex_min is not None and pitch.rho_convex_min.value <= rr:
        reasons.append(f"convex pitch radius {pitch.rho_convex_min.value:.6g} mm <= Rr {rr:g} mm "
                       f"at {math.degrees(pitch.rho_convex_min.at):.3f} deg")
    if not profile.simple:
        reasons.append("the profile polygon is not simple (loop or cusp)")
    if outer is not None:
        if pitch.rho_concave_min is not None and pitch.rho_concave_min.value <= rr:
            reasons.append(f"outer flank: concave pitch radius {pitch.rho_concave_min.value:.6g} mm <= Rr")
        if not outer.simple:
            reasons.append("outer flank polygon is not simple")
    if counter is not None and counter_pitch is not None:
        if rr > 0.0 and counter_pitch.rho_convex_min is not None and counter_pitch.rho_convex_min.value <= rr:
            reasons.append(f"counter-cam: convex pitch radius {counter_pitch.rho_convex_min.value:.6g} mm <= Rr")
        if not counter.simple:
            reasons.append("counter-cam polygon is not simple")

    curvature_passed = True
    if follower.rho_min is not None:
        for curve in (profile, outer, counter):
            if curve is not None and curve.rho_convex_min is not None and \
                    curve.rho_convex_min.value < follower.rho_min:
                curvature_passed = False
                notes.append(f"{curve.name}: convex radius {curve.rho_convex_min.value:.6g} mm < "
                             f"limit {follower.rho_min:g} mm")
        if outer is not None and pitch.rho_concave_min is not None and \
                pitch.rho_concave_min.value - rr < follower.rho_min:
            curvature_passed = False

    if not profile.closed:
        notes.append(f"the profile does not close (gap {profile.closure_gap:.6g} mm): the law's displacement "
                     "does not come back; balance it with camcad fix")
    design = None
    if settings.design:
        try:
            design = min_base_radius(law, follower)
        except CamcadError as err:
            notes.append(f"design: {err.what}")
    return ProfileResult(
        name=name, law=law, follower=follower, settings=settings, geometry=geometry,
        profile=profile, pitch=pitch, outer=outer, counter=counter, counter_pitch=counter_pitch,
        table=table, pressure_angle=pressure,
        counter_pressure_angle=counter_pressure, rho_pitch_min=pitch.rho_convex_min,
        rho_pitch_concave_min=pitch.rho_concave_min, undercut=bool(reasons),
        undercut_reasons=tuple(reasons), curvature_passed=curvature_passed, closure_kink=kink,
        design=design, face_extent=face, notes=tuple(notes))
