"""A law from a table of the motion: displacement, swing, or radius-vectors of a cam profile through its follower.

The batten study's method, made reproducible (PhD abstract on the batten mechanism of the STB loom,
Novosibirsk: the serial cam's radius-vectors smoothed by quintic splines, the second derivative, which
oscillated with the step, smoothed again by a cubic spline):

1. radius-vectors (``theta_deg,r_mm``) become the follower's motion through the follower given
   (``ProfileFollower``: translating roller with offset, oscillating roller; ``radius_to_motion``):
   the cam is turned by each cam angle and the roller is brought down onto it — the roller centre's
   height (or the arm's angle) is the largest one at which the roller touches a point of the profile.
   The profile between the table's points is the periodic cubic spline through them (interpolation:
   the table's noise goes on to step 2 unchanged);
2. the motion (s or ψ at the table's angles) gets the periodic quintic smoothing spline
   (``camcad.law.smoothing``), its smoothing chosen by generalised cross-validation or by the stated
   measurement error; the report gives the fit's residual (RMS, max) and the noise it implies;
3. the second derivative of the quintic, a = s'', is smoothed again by a periodic cubic smoothing
   spline (GCV, stated, or "none"); the report gives the oscillation removed (RMS, max, % of the peak);
4. the phases are found from the smoothed motion — a dwell is where both |v| ≤ 1 % of the peak velocity
   and |a| ≤ twice the ripple of a on the dwell's core (at least 0.5 % of the motion's peak), and each
   motion starts where its acceleration, extrapolated along the line through 20 % and 40 % of its peak,
   reaches zero; a motion without a dwell between rise and return is split at its extreme
   displacement — unless the phases are given;
5. the law is the acceleration as a polyline (step ≤ 0.25°), a = 0 on each dwell but within 3° (or 3
   table steps) of a motion — the boundaries found from a noisy table may be a little off — balanced
   with the least change (trapezoid-weighted) so the follower stands still at each dwell's level (the
   fit's mean there), v = 0 at the end of every rise and return and s closes: a law every camcad
   command takes as drawn. The change and the law's deviation from the fitted motion are reported.

Refused with one line: fewer than 8 rows, angles outside the cycle, two rows at one angle, a gap in the
angles (the table does not cover the cycle), a table that does not close (its motion drifts over the
cycle by more than 5 standard errors of the fit and more than 1e-4 of the stroke),
and a motion that is not at rest at 0° (camcad's laws start from rest: the fix names the angle to
shift the table by). Whether a table closes is judged by fitting it with the periodic spline plus a ramp
J·θ/T (unpenalised; a row at the cycle's end sits at the ramp's top): J is the drift over the cycle.
The 360° row may be there or not.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, cast

import numpy as np

from camcad.errors import CamcadError
from camcad.law.law import Phase, PiecewiseLinearLaw
from camcad.law.smoothing import SmoothingFit, fit_periodic

#: the fewest rows a motion table needs (a quintic spline and its closure test)
MIN_ROWS = 8
#: the largest step of the written acceleration polyline (deg)
MAX_STEP_DEG = 0.25
#: the motion is at rest at 0° when |v(0)| is at most this fraction of the peak velocity
REST_FRACTION = 0.02
#: a dwell: |v| at most this fraction of the peak velocity...
DWELL_V_FRACTION = 0.01
#: ... and |a| at most twice the ripple of a on the dwell's core, but at least this fraction of the peak
DWELL_A_FLOOR = 0.005
#: the motion's start: the line through these fractions of its peak acceleration, extrapolated to zero
ONSET_FRACTIONS = (0.2, 0.4)
#: a gap in the angles larger than this many median steps means the table does not cover the cycle
MAX_GAP_STEPS = 3.0
#: a = 0 on each dwell but within this angle (deg; or this many table steps) of a motion: the boundaries
#: found from a noisy table may be a little off, and the follower surely stands still inside
DWELL_MARGIN_DEG = 3.0
DWELL_MARGIN_STEPS = 3.0
#: the correction that balances the smoothed law: hat functions this far apart (deg), and the weight of its
#: size against the law's distance from the fitted motion (per rad, in (law unit)^2 per (law unit/rad^2)^2)
CORRECTION_STEP_DEG = 2.0
CORRECTION_PENALTY = 1e-6
#: a phase boundary found within this angle (deg; or two table steps) of 0° or of the cycle's end is taken there
SNAP_DEG = 1.0
#: a table does not close when its fitted drift over the cycle exceeds this many standard errors...
SEAM_SIGMAS = 5.0
#: ... and more than this fraction of the stroke (a local cubic across a motion is not exact)
SEAM_FLOOR = 1e-4


@dataclass(frozen=True)
class ProfileFollower:
    """The follower that turns a cam profile's radius-vectors into a motion (lengths mm).

    Frames as camcad's profile (``camcad.profile.followers``): the cam centre at the origin, the cam
    turning counter-clockwise (``cw``: clockwise); a translating roller on the line x = e moving along
    +y; an oscillating roller on an arm of length L about the pivot (C, 0), the roller centre at
    (C, 0) + L(−cos γ, sin γ), a larger γ farther from the cam. The table's θ is the polar angle of
    the profile point in the cam's own frame (the frame of camcad's profile.dxf).

    Parameters
    ----------
    kind : str
        "translating" (roller or knife edge, Rr = 0) or "oscillating".
    roller_radius : float
        Rr, mm (≥ 0; > 0 for an oscillating roller).
    offset : float
        e, mm (translating).
    pivot, arm : float or None
        C and L, mm (oscillating).
    cw : bool
        The cam turns clockwise.

    Examples
    --------
    >>> ProfileFollower("oscillating", 25.0, pivot=160.0, arm=120.0).describe()
    'oscillating roller Rr 25 mm, pivot C 160 mm, arm L 120 mm, CCW'
    """

    kind: str
    roller_radius: float
    offset: float = 0.0
    pivot: float | None = None
    arm: float | None = None
    cw: bool = False

    def describe(self) -> str:
        turn = "CW" if self.cw else "CCW"
        if self.kind == "oscillating":
            return (f"oscillating roller Rr {self.roller_radius:g} mm, pivot C {self.pivot:g} mm, "
                    f"arm L {self.arm:g} mm, {turn}")
        return f"translating roller Rr {self.roller_radius:g} mm, offset e {self.offset:g} mm, {turn}"

    def validate(self, where: str) -> ProfileFollower:
        if self.kind not in ("translating", "oscillating"):
            raise CamcadError(f"follower {self.kind!r} cannot follow a radius table", where,
                              "give a translating roller (with offset) or an oscillating roller")
        if not (math.isfinite(self.roller_radius) and self.roller_radius >= 0):
            raise CamcadError("the roller radius must be >= 0", where, "give the roller radius in mm")
        if self.kind == "oscillating" and not (self.pivot and self.arm and self.pivot > 0 and self.arm > 0
                                               and self.roller_radius > 0):
            raise CamcadError("an oscillating follower needs the pivot distance, arm and roller radius", where,
                              "give pivot C, arm L and roller_radius (mm)")
        return self


def follower_from_options(kind: str | None, roller_radius: float | None = None, offset: float = 0.0,
                          pivot: float | None = None, arm: float | None = None, cw: bool = False,
                          where: str = "--follower") -> ProfileFollower | None:
    """The ``ProfileFollower`` of the command-line options (``--follower roller|knife|oscillating --rr R
    --offset E --pivot C --arm L --cw``), None when ``kind`` is None.

    Examples
    --------
    >>> follower_from_options("roller", 10.0, offset=5.0).describe()
    'translating roller Rr 10 mm, offset e 5 mm, CCW'
    """
    if kind is None:
        return None
    if kind not in ("roller", "knife", "oscillating"):
        raise CamcadError(f"follower {kind!r} cannot follow a radius table", where,
                          "give --follower roller, knife or oscillating")
    if kind == "roller" and roller_radius is None:
        raise CamcadError("a roller follower needs its radius", "--rr", "give --rr R (mm)")
    radius = 0.0 if kind == "knife" else float(roller_radius or 0.0)
    return ProfileFollower("oscillating" if kind == "oscillating" else "translating", radius, float(offset or 0.0),
                           pivot, arm, cw).validate(where)


@dataclass(frozen=True)
class MotionTableLaw:
    """A law made from a motion table (module docstring): its acceleration polyline (``x`` rad, ``a`` in
    law units per rad²), phases, unit, the fits, and the figures the report gives (``report()``)."""

    x: np.ndarray
    a: np.ndarray
    cycle: float
    phases: tuple[Phase, ...]
    unit: str
    kind: str
    fit: SmoothingFit
    accel_fit: SmoothingFit | None
    figures: dict
    notes: tuple[str, ...] = ()
    motion: tuple[np.ndarray, np.ndarray] = field(default=(np.zeros(0), np.zeros(0)), repr=False)

    def report(self) -> dict:
        return dict(self.figures)


# --------------------------------------------------------------------------------------------
# Radius-vectors -> motion
# --------------------------------------------------------------------------------------------

def radius_to_motion(theta_deg: np.ndarray, r_mm: np.ndarray, follower: ProfileFollower, cycle_deg: float = 360.0,
                     *, where: str = "table", samples_per_deg: int = 50) -> tuple[np.ndarray, np.ndarray, dict]:
    """The follower's motion at the table's angles from a cam profile's radius-vectors (module docstring).

    Parameters
    ----------
    theta_deg : ndarray
        Polar angles of the profile points in the cam's frame (deg), over one turn.
    r_mm : ndarray
        Their radii, mm.
    follower : ProfileFollower
    cycle_deg : float
        Must be 360 deg (a profile is one turn).
    where : str
        For messages.
    samples_per_deg : int
        Profile points per degree the roller is fitted against (the error of the discrete contact is
        about (r·Δ)²/(8ρ) before the parabolic refinement, far below the table's noise).

    Returns
    -------
    (theta_deg, motion, figures)
        The cam angles (the table's angles), the displacement s (mm, from the lowest position) or the
        swing ψ (rad, from the smallest arm angle), and figures (base radius found, unit).

    Examples
    --------
    A circle of radius 50 about the cam centre gives no motion:

    >>> import numpy as np
    >>> theta = np.arange(0.0, 360.0, 1.0)
    >>> _, s, figures = radius_to_motion(theta, np.full(360, 50.0), ProfileFollower("translating", 10.0))
    >>> float(np.max(np.abs(s))) < 1e-9, round(figures["base_radius_mm"], 9)
    (True, 50.0)
    """
    from scipy.interpolate import CubicSpline  # start-up cost: loaded when a radius table is read

    follower = follower.validate(where)
    if abs(cycle_deg - 360.0) > 1e-9:
        raise CamcadError(f"a radius table is one turn of the cam, not a cycle of {cycle_deg:g} deg", where,
                          "leave --cycle out (360)")
    theta_deg = np.asarray(theta_deg, dtype=float)
    r_mm = np.asarray(r_mm, dtype=float)
    if np.any(r_mm <= 0):
        raise CamcadError(f"a radius-vector is {float(r_mm.min()):g} mm, not positive", where,
                          "give the profile's radii from the cam centre (mm)")
    closing = abs(theta_deg[-1] - theta_deg[0] - 360.0) <= 1e-6 * 360.0
    angles, radii = (theta_deg[:-1], r_mm[:-1]) if closing else (theta_deg, r_mm)
    if closing and abs(r_mm[-1] - r_mm[0]) > 1e-3 * float(np.ptp(r_mm) or 1.0) + 1e-9:
        raise CamcadError(f"the profile does not close: r({theta_deg[-1]:g}) = {r_mm[-1]:g} mm but "
                          f"r({theta_deg[0]:g}) = {r_mm[0]:g} mm", where, "give one turn of the profile")
    spline = CubicSpline(np.radians(np.append(angles, angles[0] + 360.0)), np.append(radii, radii[0]),
                         bc_type="periodic")
    count = int(360 * samples_per_deg)
    alpha = np.radians(angles[0]) + np.arange(count) * (2.0 * np.pi / count)
    radius = spline(alpha)
    points = np.column_stack((radius * np.cos(alpha), radius * np.sin(alpha)))
    sigma = -1.0 if follower.cw else 1.0
    phi = np.radians(theta_deg)
    values = np.empty(len(phi))
    for start in range(0, len(phi), 16):
        block = phi[start:start + 16]
        c, s = np.cos(sigma * block)[:, None], np.sin(sigma * block)[:, None]
        x = c * points[None, :, 0] - s * points[None, :, 1]
        y = s * points[None, :, 0] + c * points[None, :, 1]
        values[start:start + len(block)] = _contact(x, y, follower)
    if not np.all(np.isfinite(values)):
        bad = float(theta_deg[int(np.flatnonzero(~np.isfinite(values))[0])])
        raise CamcadError(f"at cam angle {bad:g} deg the follower does not reach the profile", where,
                          "check the follower (offset, pivot, arm) against the cam's size")
    lowest = float(np.min(values))
    figures: dict = {"follower": follower.describe(), "profile_points": count}
    if follower.kind == "translating":
        height = lowest
        figures["base_radius_mm"] = math.hypot(height, follower.offset) - follower.roller_radius
        figures["unit"] = "mm"
    else:
        c_, l_ = float(cast(float, follower.pivot)), float(cast(float, follower.arm))
        prime = math.sqrt(c_**2 + l_**2 - 2.0 * c_ * l_ * math.cos(lowest))
        figures["base_radius_mm"] = prime - follower.roller_radius
        figures["arm_angle_on_base_circle_deg"] = math.degrees(lowest)
        figures["unit"] = "rad"
    return theta_deg, values - lowest, figures


def _contact(x: np.ndarray, y: np.ndarray, follower: ProfileFollower) -> np.ndarray:
    """Roller centre height (translating) or arm angle γ (oscillating) for each row of rotated profile
    points (x, y): the largest at which the roller touches a point, refined by a parabola through the
    best point and its neighbours."""
    rr = follower.roller_radius
    if follower.kind == "translating":
        dx = x - follower.offset
        if rr == 0.0:  # knife edge: where the profile crosses the line x = e, above the centre
            return _knife(dx, y)
        inside = np.abs(dx) <= rr
        candidate = np.where(inside, y + np.sqrt(np.clip(rr * rr - dx * dx, 0.0, None)), -np.inf)
    else:
        c_, l_ = float(cast(float, follower.pivot)), float(cast(float, follower.arm))
        ux, uy = x - c_, y
        rho = np.hypot(ux, uy)
        beta = np.arctan2(uy, -ux)
        kappa = (l_ * l_ + rho * rho - rr * rr) / (2.0 * l_ * np.maximum(rho, 1e-300))
        inside = np.abs(kappa) <= 1.0
        candidate = np.where(inside, beta + np.arccos(np.clip(kappa, -1.0, 1.0)), -np.inf)
    best = np.argmax(candidate, axis=1)
    rows = np.arange(len(best))
    n = candidate.shape[1]
    left = candidate[rows, (best - 1) % n]
    mid = candidate[rows, best]
    right = candidate[rows, (best + 1) % n]
    denominator = left - 2.0 * mid + right
    ok = np.isfinite(left) & np.isfinite(right) & (denominator < 0)
    shift = np.where(ok, 0.5 * (left - right) / np.where(ok, denominator, 1.0), 0.0)
    refined = mid - 0.25 * (left - right) * shift
    return np.where(np.isfinite(mid), refined, np.nan)


def _knife(dx: np.ndarray, y: np.ndarray) -> np.ndarray:
    nxt = np.roll(dx, -1, axis=1)
    y_next = np.roll(y, -1, axis=1)
    crosses = (dx == 0) | (dx * nxt < 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(dx != nxt, dx / (dx - nxt), 0.0)
    height = np.where(crosses, y + t * (y_next - y), -np.inf)
    out = np.max(height, axis=1)
    return np.where(np.isfinite(out) & (out > 0), out, np.nan)


# --------------------------------------------------------------------------------------------
# Motion -> law
# --------------------------------------------------------------------------------------------

def motion_law(theta_deg: np.ndarray, values: np.ndarray, cycle_deg: float = 360.0, *, unit: str = "mm",
               kind: str = "displacement", sigma: float | None = None, accel_smoothing: str | float = "gcv",
               phases: tuple[Phase, ...] | None = None, where: str = "table") -> MotionTableLaw:
    """The law of a tabulated motion s(θ) (or ψ(θ)): the module docstring's steps 2–5.

    Parameters
    ----------
    theta_deg : ndarray
        Cam angles (deg), increasing, within [0, cycle]; unequal steps allowed; the row at the cycle's
        end (360°) may be there or not.
    values : ndarray
        The motion: mm, or deg or rad of swing (``unit``).
    cycle_deg : float
        The cycle (deg).
    unit : str
        The motion's unit, for messages and the report.
    kind : str
        What the table held ("displacement", "swing_deg", "swing_rad", "radius"), for the report.
    sigma : float, optional
        The stated measurement error of the motion (mm, or rad or deg of swing: its unit); None: GCV
        chooses the smoothing.
    accel_smoothing : str or float
        The cubic re-smoothing of a = s'': "gcv", "none", or the stated error of a (mm/rad², or the swing's
        unit per rad²).
    phases : tuple of Phase, optional
        The phases (rad); None: found from the motion (module docstring, step 4).
    where : str
        For messages.

    Returns
    -------
    MotionTableLaw
        The acceleration polyline (θ in rad, a in the motion's unit per rad²: mm/rad², or rad or deg of
        swing per rad²), its phases (rad) and the smoothing's figures.

    Examples
    --------
    A cycloidal dwell-rise-dwell-return of 20 mm sampled every 2°: the law's peak acceleration is the
    closed form 2πh/β² within 0.5 %.

    >>> import math
    >>> import numpy as np
    >>> theta = np.arange(0.0, 360.0, 2.0)
    >>> u = np.clip((theta - 90.0) / 90.0, 0, 1)
    >>> w = np.clip((theta - 270.0) / 90.0, 0, 1)
    >>> s = 20 * ((u - np.sin(2 * np.pi * u) / (2 * np.pi)) - (w - np.sin(2 * np.pi * w) / (2 * np.pi)))
    >>> law = motion_law(theta, s)
    >>> peak = 2 * math.pi * 20 / (math.pi / 2) ** 2
    >>> abs(float(np.max(law.a)) / peak - 1) < 5e-3
    True
    >>> [(p.kind, round(math.degrees(p.start))) for p in law.phases]
    [('dwell', 0), ('rise', 90), ('dwell', 180), ('return', 270)]
    """
    theta_deg = np.asarray(theta_deg, dtype=float)
    values = np.asarray(values, dtype=float)
    if isinstance(accel_smoothing, str) and accel_smoothing not in ("gcv", "none"):
        raise CamcadError(f"accel smoothing {accel_smoothing!r} is not gcv, none or an error", where,
                          "give gcv, none, or the stated error of a (its unit per rad^2)")
    notes: list[str] = []
    n_rows = len(theta_deg)
    if n_rows < MIN_ROWS:
        raise CamcadError(f"the table has {n_rows} rows; a motion table needs at least {MIN_ROWS}", where,
                          "give the motion over the whole cycle")
    if theta_deg[0] < -1e-9 * cycle_deg or theta_deg[-1] > cycle_deg * (1 + 1e-9):
        raise CamcadError(f"the angles run {theta_deg[0]:g}..{theta_deg[-1]:g} deg, outside the cycle 0..{cycle_deg:g}",
                          where, f"give angles from 0 to {cycle_deg:g} deg (or pass --cycle)")
    steps = np.diff(theta_deg)
    if np.any(steps <= 1e-9 * cycle_deg):
        index = int(np.flatnonzero(steps <= 1e-9 * cycle_deg)[0])
        raise CamcadError(f"two rows at {theta_deg[index]:g} deg: a motion has one value at each angle", where,
                          "delete or average the repeated row")
    closing = abs(theta_deg[-1] - cycle_deg) <= 1e-6 * cycle_deg and theta_deg[0] <= 1e-6 * cycle_deg
    data_theta, data_values = (theta_deg[:-1], values[:-1]) if closing else (theta_deg, values)
    median = float(np.median(np.diff(data_theta)))
    wrap_gap = cycle_deg - data_theta[-1] + data_theta[0]
    gaps = np.append(np.diff(data_theta), wrap_gap)
    worst = int(np.argmax(gaps))
    if gaps[worst] > MAX_GAP_STEPS * median:
        after = data_theta[(worst + 1) % len(data_theta)]
        raise CamcadError(f"the table has no rows between {data_theta[worst]:g} and {after:g} deg "
                          f"(a gap of {gaps[worst]:g} deg, its step is {median:g} deg)", where,
                          "give the motion over the whole cycle")
    cycle = math.radians(cycle_deg)
    stroke = float(np.ptp(values))
    if not stroke > 0:
        raise CamcadError("the motion is constant: there is no law", where, "check the column")
    # closure: the table fitted with a periodic spline plus a ramp J·θ/T (a row at the cycle's end is at the
    # ramp's top): J is how far the motion is from returning to its start
    ramp = np.where(theta_deg >= cycle_deg * (1 - 1e-9), 1.0, theta_deg / cycle_deg)
    test = fit_periodic(np.radians(theta_deg), values, cycle, degree=5, ramp=ramp, where=where)
    jump, jump_error = float(test.ramp or 0.0), float(test.ramp_error or 0.0)
    if abs(jump) > SEAM_SIGMAS * jump_error and abs(jump) > SEAM_FLOOR * stroke:
        raise CamcadError(f"the table does not close: its motion drifts by {jump:.4g} {unit} over the cycle "
                          f"(noise about {test.sigma:.2g} {unit})", where,
                          "give a table of one whole cycle whose motion returns to its start")
    fit = fit_periodic(np.radians(data_theta), data_values, cycle, degree=5, sigma=sigma, where=where)
    seam = {"jump": jump, "standard_error": jump_error}
    spline = fit.spline
    at = np.radians(data_theta)
    a_raw = spline(at, 2)
    accel_fit = None
    if accel_smoothing == "none":
        def accel(theta):
            return spline(theta, 2)
    else:
        stated = None if accel_smoothing == "gcv" else float(accel_smoothing)
        accel_fit = fit_periodic(at, a_raw, cycle, degree=3, sigma=stated, where=f"{where} (acceleration)")
        accel = accel_fit.spline
    step = min(MAX_STEP_DEG, median / 2.0)
    count = max(64, math.ceil(cycle_deg / step))
    grid = np.linspace(0.0, cycle, count + 1)
    a_smooth = accel(grid)
    v_fit = spline(grid, 1)
    peak_a = float(np.max(np.abs(a_smooth)))
    peak_v = float(np.max(np.abs(v_fit)))
    v0 = float(v_fit[0])
    if abs(v0) > REST_FRACTION * peak_v:
        shift = _rest_shift(grid, v_fit, peak_v)
        raise CamcadError(f"the motion is not at rest at 0 deg (v = {v0:.3g} {unit}/rad, "
                          f"{100 * abs(v0) / peak_v:.0f} % of its peak): camcad's laws start from rest", where,
                          f"start the table on a dwell: subtract {shift:.6g} deg from its angles (mod {cycle_deg:g})")
    if phases is None:
        phases, phase_notes = find_phases(grid, a_smooth, v_fit, spline(grid), cycle,
                                          math.radians(max(SNAP_DEG, 2.0 * median)))
        notes.extend(phase_notes)
    else:
        notes.append("phases as given")
    cores = dwell_cores(tuple(phases), cycle, math.radians(max(DWELL_MARGIN_DEG, DWELL_MARGIN_STEPS * median)))
    knots = np.unique(np.concatenate((grid, at, [p.start for p in phases], [p.end for p in phases],
                                      [c for core in cores for c in core])))
    a_knots = accel(knots)
    balanced, change = _balance(knots, a_knots, tuple(phases), cores, spline, cycle, at)
    s_fit = spline(at) - float(spline(np.zeros(1))[0])
    law_s = _integrate(knots, balanced, at)
    deviation = float(np.max(np.abs(law_s - s_fit)))
    oscillation = a_raw - (accel_fit.spline(at) if accel_fit is not None else a_raw)
    peak_raw = float(np.max(np.abs(a_raw)))
    figures: dict[str, Any] = {
        "kind": kind, "unit": unit, "rows": n_rows, "step_deg": median, "equal_steps": bool(np.ptp(np.diff(
            data_theta)) <= 1e-9 * cycle_deg), "row_at_cycle_end": bool(closing),
        "smoothing": {"degree": 5, "method": fit.method, "lambda": fit.lam, "dof": fit.dof,
                      "knots_every": fit.knots_every, f"residual_rms_{unit}": fit.residual_rms,
                      f"residual_max_{unit}": fit.residual_max, f"noise_{unit}": fit.sigma},
        "accel_smoothing": (None if accel_fit is None else {
            "degree": 3, "method": accel_fit.method, "lambda": accel_fit.lam, "dof": accel_fit.dof,
            f"oscillation_removed_rms_{unit}_per_rad2": float(np.sqrt(np.mean(oscillation**2))),
            f"oscillation_removed_max_{unit}_per_rad2": float(np.max(np.abs(oscillation))),
            "oscillation_removed_percent_of_peak": 100.0 * float(np.max(np.abs(oscillation))) / peak_raw}),
        "closure": {f"jump_{unit}": seam["jump"], f"standard_error_{unit}": seam["standard_error"]},
        f"balance_change_max_{unit}_per_rad2": change, "balance_change_percent_of_peak": 100.0 * change / peak_a,
        f"law_vs_fit_max_{unit}": deviation,
        "phases": ",".join(f"{math.degrees(p.start):.6g}:{math.degrees(p.end):.6g}:{p.kind}" for p in phases),
    }
    notes.insert(0, f"{kind} table of {n_rows} rows ({'equal' if figures['equal_steps'] else 'unequal'} steps, "
                    f"median {median:g} deg{', with' if closing else ', without'} the {cycle_deg:g} deg row): "
                    f"quintic smoothing spline ({_method_text(fit)}), residual RMS {fit.residual_rms:.3g} {unit}, "
                    f"max {fit.residual_max:.3g} {unit}")
    if accel_fit is not None:
        removed = cast(dict, figures["accel_smoothing"])
        notes.insert(1, f"second derivative smoothed again by a cubic spline ({_method_text(accel_fit)}): "
                        f"oscillation removed RMS {removed[f'oscillation_removed_rms_{unit}_per_rad2']:.3g}, "
                        f"max {float(np.max(np.abs(oscillation))):.3g} {unit}/rad^2 "
                        f"({removed['oscillation_removed_percent_of_peak']:.2g} % of the peak)")
    else:
        notes.insert(1, "second derivative not smoothed again (accel_smoothing none)")
    margin = max(DWELL_MARGIN_DEG, DWELL_MARGIN_STEPS * median)
    notes.append(f"balanced with a = 0 on the dwells (but within {margin:g} deg of a motion): least change "
                 f"{change:.3g} {unit}/rad^2 ({figures['balance_change_percent_of_peak']:.2g} % of the peak); "
                 f"the law's displacement is within {deviation:.3g} {unit} of the fitted motion")
    return MotionTableLaw(knots, balanced, cycle, tuple(phases), unit, kind, fit, accel_fit, figures, tuple(notes),
                          (at, s_fit))


def _method_text(fit: SmoothingFit) -> str:
    text = {"gcv": "smoothing by generalised cross-validation", "stated": "smoothing for the stated error",
            "interpolation": "interpolation"}[fit.method]
    extra = f", a knot every {fit.knots_every} rows" if fit.knots_every > 1 else ""
    return f"{text}, {fit.dof:.1f} degrees of freedom of {fit.n}{extra}"


def _rest_shift(grid: np.ndarray, v: np.ndarray, peak: float) -> float:
    """The angle (deg) of the middle of the longest stretch at rest, to shift the table by."""
    rest = np.abs(v) <= DWELL_V_FRACTION * peak
    if not rest.any():
        return 0.0
    runs = _runs(rest)
    start, end = max(runs, key=lambda r: r[1] - r[0])
    return float(np.degrees(grid[(start + end) // 2]))


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Index ranges [start, end] of the True runs of ``mask`` (not wrapping)."""
    edges = np.flatnonzero(np.diff(np.concatenate(([0], mask.astype(int), [0]))))
    return [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2])]


def find_phases(grid: np.ndarray, a: np.ndarray, v: np.ndarray, s: np.ndarray, cycle: float, snap: float = 0.0
                ) -> tuple[tuple[Phase, ...], list[str]]:
    """Dwells, rises and returns of a smoothed motion sampled on ``grid`` (0..cycle, rad; module docstring,
    step 4). The search runs in a frame that starts in the middle of the longest stretch at rest, so a
    dwell across 0° is one dwell; the phases are then cut at 0° again, and a boundary within ``snap``
    (rad) of 0° or of the cycle's end is taken there (the law starts from rest at 0°)."""
    peak_v = float(np.max(np.abs(v)))
    n = len(grid) - 1                      # grid[n] is grid[0] + cycle
    slow_all = np.abs(v[:n]) <= DWELL_V_FRACTION * peak_v
    notes: list[str] = []
    if not slow_all.any() or slow_all.all():
        notes.append("no dwell found in the motion (|v| <= 1 % of its peak nowhere, or everywhere)")
        return (Phase("rise", 0.0, cycle),) if slow_all.all() else _no_dwell(grid, s, cycle), notes
    runs = _runs(np.concatenate((slow_all, slow_all)))
    longest = max((r for r in runs if r[1] - r[0] < n), key=lambda r: r[1] - r[0])
    offset = ((longest[0] + longest[1]) // 2) % n
    order = (np.arange(n + 1) + offset) % n
    theta = grid[order] + np.where(np.arange(n + 1) + offset >= n, cycle, 0.0)
    theta[-1] = theta[0] + cycle
    ar, vr, sr = a[order], v[order], s[order]
    slow = np.abs(vr) <= DWELL_V_FRACTION * peak_v
    edges: list[tuple[int, int]] = []
    for lo, hi in _runs(slow):
        if hi <= lo:
            continue
        margin = max(1, (hi - lo) // 10)
        inner = np.abs(ar[lo + margin:hi - margin + 1]) if hi - lo > 2 * margin else np.abs(ar[lo:hi + 1])
        threshold = max(2.0 * float(np.max(inner)), DWELL_A_FLOOR * float(np.max(np.abs(a))))
        quiet = (np.abs(ar) <= threshold) & slow
        middle = (lo + hi) // 2 if lo > 0 else 0
        if hi == n:
            middle = n if lo > 0 else middle
        if not quiet[middle]:
            continue  # a constant-velocity stretch, not a dwell
        first = last = middle
        while first > lo and quiet[first - 1]:
            first -= 1
        while last < hi and quiet[last + 1]:
            last += 1
        edges.append((first, last))
    bounds: list[tuple[float, float]] = []
    for number, (first, last) in enumerate(edges):
        start = theta[first] if first == 0 else _onset(theta, ar, first, -1, edges[number - 1][1])
        end = theta[last] if last == n else _onset(theta, ar, last, +1, edges[number + 1][0])
        bounds.append((float(start), float(end)))
    rolled: list[Phase] = []
    position = float(theta[0])
    for start, end in bounds:
        if end <= max(start, position) + 1e-12:
            continue    # the motion passes through rest without stopping (the top of a rise-return)
        if start > position + 1e-12:
            rolled.extend(_motions(position, start, theta, sr))
        rolled.append(Phase("dwell", max(start, position), end))
        position = end
    base = float(theta[0])
    phases: list[Phase] = []
    for phase in rolled:  # back to 0..cycle: the phase over the cycle's end is cut in two
        lo, hi = phase.start - base + grid[offset], phase.end - base + grid[offset]
        if hi <= cycle + 1e-12:
            phases.append(Phase(phase.kind, lo, min(hi, cycle)))
        elif lo >= cycle - 1e-12:
            phases.append(Phase(phase.kind, lo - cycle, hi - cycle))
        else:
            phases.append(Phase(phase.kind, lo, cycle))
            phases.append(Phase(phase.kind, 0.0, hi - cycle))
    phases.sort(key=lambda p: p.start)
    snapped = []

    def snapped_at(angle: float) -> float:
        return 0.0 if angle <= snap else cycle if angle >= cycle - snap else angle

    for phase in phases:
        begin, finish = snapped_at(phase.start), snapped_at(phase.end)
        if finish - begin > 1e-12:
            snapped.append(Phase(phase.kind, begin, finish))
    merged: list[Phase] = []
    for phase in snapped:
        if phase.end - phase.start <= 1e-12:
            continue
        if merged and merged[-1].kind == phase.kind == "dwell" and abs(merged[-1].end - phase.start) <= 1e-12:
            merged[-1] = Phase("dwell", merged[-1].start, phase.end)
        else:
            merged.append(phase)
    text = ", ".join(f"{p.kind} {math.degrees(p.start):.4g}-{math.degrees(p.end):.4g}" for p in merged)
    notes.append(f"phases found from the smoothed motion: {text} deg (a dwell: |v| <= 1 % of the peak velocity "
                 "and |a| within twice its ripple; each motion starts where its acceleration, extrapolated from "
                 "20 % and 40 % of its peak, is zero); give --phases (or [law] phases) to state them")
    return tuple(merged), notes


def _no_dwell(grid: np.ndarray, s: np.ndarray, cycle: float) -> tuple[Phase, ...]:
    return tuple(_motions(0.0, cycle, grid, s))


def _crossing(theta: np.ndarray, values: np.ndarray, level: float) -> float | None:
    """The first angle along ``theta`` where ``values`` reaches ``level`` (linear between samples)."""
    above = np.flatnonzero(values >= level)
    if len(above) == 0:
        return None
    k = int(above[0])
    if k == 0:
        return float(theta[0])
    v0, v1 = values[k - 1], values[k]
    return float(theta[k - 1] + (level - v0) / (v1 - v0) * (theta[k] - theta[k - 1]))


def _onset(theta: np.ndarray, a: np.ndarray, index: int, direction: int, other: int) -> float:
    """Where the motion next to a dwell whose edge is ``theta[index]`` starts (direction +1: the motion
    follows the dwell; −1: it precedes it, and the angle is where it ends): its acceleration extrapolated to
    zero along the line through ``ONSET_FRACTIONS`` of the motion's peak (the motion runs to the next
    dwell's edge ``other``); the dwell's edge when that line does not help."""
    path = np.arange(index, other + direction, direction)
    if len(path) < 3:
        return float(theta[index])
    values = np.abs(a[path])
    peak = float(np.max(values))
    t_low = _crossing(theta[path], values, ONSET_FRACTIONS[0] * peak)
    t_high = _crossing(theta[path], values, ONSET_FRACTIONS[1] * peak)
    if t_low is None or t_high is None or (t_high - t_low) * direction <= 0:
        return float(theta[index])
    ratio = ONSET_FRACTIONS[0] / (ONSET_FRACTIONS[1] - ONSET_FRACTIONS[0])
    zero = t_low - ratio * (t_high - t_low)
    reach = 4.0 * abs(t_high - t_low)
    lo, hi = sorted((float(theta[index]) - direction * reach, t_low))
    return float(np.clip(zero, lo, hi))


def _motions(start: float, end: float, grid: np.ndarray, s: np.ndarray) -> list[Phase]:
    """A motion between two dwells: a rise or a return, or a rise and a return split at the extreme."""
    inside = (grid >= start) & (grid <= end)
    theta, values = grid[inside], s[inside]
    if len(values) < 3:
        last = min(int(np.searchsorted(grid, end)), len(s) - 1)
        first = min(int(np.searchsorted(grid, start)), len(s) - 1)
        return [Phase("rise" if s[last] >= s[first] else "return", start, end)]
    net = values[-1] - values[0]
    top, bottom = int(np.argmax(values)), int(np.argmin(values))
    span = float(np.ptp(values))
    up_then_down = 0 < top < len(values) - 1 and values[top] - max(values[0], values[-1]) > 0.1 * span
    down_then_up = 0 < bottom < len(values) - 1 and min(values[0], values[-1]) - values[bottom] > 0.1 * span
    if up_then_down:
        return [Phase("rise", start, float(theta[top])), Phase("return", float(theta[top]), end)]
    if down_then_up:
        return [Phase("return", start, float(theta[bottom])), Phase("rise", float(theta[bottom]), end)]
    return [Phase("rise" if net >= 0 else "return", start, end)]


def dwell_cores(phases: tuple[Phase, ...], cycle: float, margin: float) -> list[tuple[float, float]]:
    """The dwells shrunk by ``margin`` (rad) at each end that meets a motion (not at 0° or the cycle's end,
    which meet the next cycle's dwell or start from rest): where the follower surely stands still even when
    the phase boundaries found from a noisy table are a little off. A dwell too short to shrink has none."""
    cores = []
    for phase in phases:
        if phase.kind != "dwell":
            continue
        lo = phase.start + (margin if phase.start > 0.0 else 0.0)
        hi = phase.end - (margin if phase.end < cycle else 0.0)
        if hi - lo > margin / 4:
            cores.append((lo, hi))
    return cores


def _integrals(x: np.ndarray, columns: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(V, S): v and s at every knot of the polylines (x, columns[:, j]) from rest at s = 0 (exact: v piecewise
    quadratic, s piecewise cubic), one column per polyline."""
    lengths = np.diff(x)[:, None]
    dv = lengths * (columns[:-1] + columns[1:]) / 2.0
    velocity = np.vstack((np.zeros((1, columns.shape[1])), np.cumsum(dv, axis=0)))
    ds = velocity[:-1] * lengths + lengths**2 * (2.0 * columns[:-1] + columns[1:]) / 6.0
    return velocity, np.vstack((np.zeros((1, columns.shape[1])), np.cumsum(ds, axis=0)))


def _balance(x: np.ndarray, a: np.ndarray, phases: tuple[Phase, ...], cores: list[tuple[float, float]],
             s_fit, cycle: float, at: np.ndarray) -> tuple[np.ndarray, float]:
    """a = 0 on the dwells' cores; elsewhere the smoothed a plus a smooth correction (hat functions every
    ``CORRECTION_STEP_DEG``) chosen so that, from rest at s = 0, the law's s is as close as it can be to the
    fitted motion at the table's angles ``at`` (knots of ``x``), under the conditions: the follower stands
    still at each core's level (the fit's mean over the core), v = 0 at the end of every rise and return,
    and s closes. Returns the law's ordinates and the largest change of a outside the cores."""
    a = np.array(a, dtype=float)
    fixed = np.zeros(len(x), dtype=bool)
    for lo, hi in cores:
        on = (x >= lo - 1e-12) & (x <= hi + 1e-12)
        a[on] = 0.0
        fixed |= on
    levels = [float(np.mean(s_fit(np.linspace(lo, hi, 65)))) for lo, hi in cores]
    reference = levels[0] if cores and cores[0][0] == 0.0 else float(s_fit(np.zeros(1))[0])
    # the correction: hat functions on a coarse grid, nothing on the cores
    nodes = np.linspace(0.0, cycle, max(8, math.ceil(math.degrees(cycle) / CORRECTION_STEP_DEG)) + 1)
    basis = np.zeros((len(x), len(nodes)))
    for j in range(len(nodes)):
        hat = np.zeros(len(nodes))
        hat[j] = 1.0
        basis[:, j] = np.interp(x, nodes, hat)
    basis[fixed] = 0.0
    basis = basis[:, np.flatnonzero(np.any(basis != 0.0, axis=0))]
    if basis.shape[1] == 0:
        return a, 0.0
    # v and s of the law (column 0) and of each correction (the others) at every knot
    velocity, displacement = _integrals(x, np.column_stack((a, basis)))
    position = {float(value): i for i, value in enumerate(x)}
    rows, goals = [], []
    for (lo, _hi), level in zip(cores, levels):
        if lo > 0.0:
            rows += [velocity[position[lo]], displacement[position[lo]]]
            goals += [0.0, level - reference]
    for phase in phases:
        if phase.kind != "dwell":
            rows.append(velocity[position[phase.end]])
            goals.append(0.0)
    if not cores or cores[-1][1] < cycle:
        rows.append(displacement[-1])
        goals.append(0.0)
    g = np.array(rows)
    mass = np.zeros(len(x))
    lengths = np.diff(x)
    mass[:-1] += lengths / 2.0
    mass[1:] += lengths / 2.0
    rows_at = np.array([position[float(t)] for t in at])
    weights = np.sqrt(np.full(len(at), cycle / len(at)))
    response = displacement[rows_at, 1:] * weights[:, None]
    target = (s_fit(at) - reference - displacement[rows_at, 0]) * weights
    smooth = np.sqrt(CORRECTION_PENALTY * mass)[:, None] * basis
    normal = response.T @ response + smooth.T @ smooth
    c_matrix = g[:, 1:]
    d_vector = np.array(goals) - g[:, 0]
    size = basis.shape[1]
    kkt = np.block([[normal, c_matrix.T], [c_matrix, np.zeros((len(goals), len(goals)))]])
    solution = np.linalg.lstsq(kkt, np.concatenate((response.T @ target, d_vector)), rcond=None)[0]
    change = basis @ solution[:size]
    return a + change, float(np.max(np.abs(change)))


def _integrate(x: np.ndarray, a: np.ndarray, at: np.ndarray) -> np.ndarray:
    """s of the polyline (x, a) from rest at s = 0 at the angles ``at`` (exact, piecewise cubic)."""
    return PiecewiseLinearLaw(x, a, float(x[-1])).kinematics(at).s


__all__ = ["MotionTableLaw", "ProfileFollower", "find_phases", "follower_from_options", "motion_law",
           "radius_to_motion"]
