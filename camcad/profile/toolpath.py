"""From the exact profile to the part: flanks, cutter paths, contour programs and solid outlines (mm, rad).

Every flank a cutter machines is a parallel curve of a *base* curve known in closed form (``geometry``):
the pitch curve P(θ) with its outward unit normal n and signed radius of curvature ρ (+ convex), or for a
flat-faced follower the profile itself (its normal is the face's normal). A flank is X = P − sign·Rr·n,
where sign = +1 for the cam profile and the counter-cam (material toward the cam centre) and −1 for the
groove's outer flank (material away from it); the follower sits on the side sign·n.

The centre of a cutter of radius R that touches the flank from the follower's side is the exact offset
along the normal

    C(θ) = X + sign·R·n = P − sign·(Rr − R)·n,

a parallel curve of the same base at the distance d = sign·(Rr − R); its radius of curvature is ρ − d and
its speed |P'|·|1 − d/ρ| (``geometry.parallel_curve``). Where 1 − d/ρ ≤ 0 the offset runs backwards: a
cusp and a loop, the cutter gouging the flank (an outside contour's concave part of radius smaller than R,
an inside contour's convex part of radius smaller than R). That is refused with the cam angle of the worst
point. A path free of cusps can still cross itself (a neck narrower than the cutter): the sampled path is
tested for crossings (shapely) and a crossing is refused with its cam angle too.

A contour program (``contour_program``) follows each flank's cutter centre — or, with the machine's own
radius compensation (G41/G42), the flank itself — as lines and arcs of the biarc fit within the tolerance
(``sampling.biarc_fit``), from a start on the middle of the near dwell (where a lead-in mark matters
least), in the climb-milling sense (the material on the right of the travel: clockwise around an outside
contour, counter-clockwise around an inside one), entered and left on tangent arcs. A groove is first cut
along its pitch curve, then, when the cutter is narrower than the groove, each flank is finished from the
pitch curve.

A solid's outline (``outline_spline``) is a clamped cubic B-spline through exact points of a flank with
the exact tangents, one piece per smooth stretch of the law (knots of full multiplicity at the law's
breakpoints, where the curvature may jump), refined until it is within the tolerance of the exact curve.

Sources: the offset (parallel) curve and its cusps, R. T. Farouki and C. A. Neff, "Analytic properties of
plane offset curves", Computer Aided Geometric Design 7 (1990) 83–99; biarcs, K. M. Bolton, "Biarc curves",
Computer-Aided Design 7 (1975) 89–92; cutter compensation and lead-in arcs, ISO 6983-1:2009 (G40–G42) and
P. Smid, CNC Programming Handbook, 3rd ed. (2008), ch. 30 (cutter radius offset).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import cast

import numpy as np

from camcad.errors import CamcadError
from camcad.extrema import zoom_min
from camcad.profile.geometry import CamGeometry, CurveGeometry, PitchGeometry, parallel_curve, rotate
from camcad.profile.sampling import (
    BULGE_STRAIGHT,
    ArcPath,
    SplineData,
    arc_centre,
    biarc_fit,
    chord_nodes,
)
from camcad.profile.synth import ProfileResult

#: cam-angle step of the grid on which a cutter path is searched for cusps before the search zooms in, rad
SEARCH_STEP = math.radians(0.1)
#: an arc whose sagitta is at most this fraction of the tolerance is written as a straight line
STRAIGHT_SAGITTA = 0.02
#: an arc shorter than this (mm) is written as a straight line (controllers refuse tiny arcs)
SHORT_ARC_MM = 0.005
#: height above the stock (its top at Z 0) for rapid moves, mm
CLEARANCE_MM = 5.0


# --------------------------------------------------------------------------------------------
# flanks
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Flank:
    """One flank of the cam that a cutter machines, as a parallel curve of its base curve.

    Attributes
    ----------
    name : str
        "profile", "outer flank" (groove) or "counter-cam" (conjugate pair).
    key : str
        The column prefix in the tables: "" for the profile, "outer_", "counter_".
    part : str
        The part it belongs to: "cam" or "counter_cam".
    sign : float
        +1: the material lies toward the cam centre (an outside contour); −1: away from it (inside).
    roller_radius : float
        Rr, mm (0 for a flat face or a knife edge).
    base : callable
        θ (rad) → ``PitchGeometry`` of the base curve (pitch curve, or the flat face's profile), mm.
    """

    name: str
    key: str
    part: str
    sign: float
    roller_radius: float
    base: Callable[[np.ndarray], PitchGeometry]

    @property
    def side(self) -> str:
        return "outside" if self.sign > 0 else "inside"

    def contour(self, theta: np.ndarray) -> CurveGeometry:
        """The flank itself, X = P − sign·Rr·n (mm)."""
        return parallel_curve(self.base(np.asarray(theta, dtype=float)), self.sign * self.roller_radius)

    def distance(self, cutter_radius: float) -> float:
        """d of the cutter centre's parallel curve C = P − d·n, mm."""
        return self.sign * (self.roller_radius - cutter_radius)

    def cutter(self, cutter_radius: float) -> Callable[[np.ndarray], CurveGeometry]:
        """θ (rad) → the cutter centre's path C = X + sign·R·n (mm)."""
        d = self.distance(cutter_radius)
        return lambda theta: parallel_curve(self.base(np.asarray(theta, dtype=float)), d)

    def normal(self, theta: np.ndarray) -> np.ndarray:
        """Unit normal of the flank pointing out of the material, toward the follower and the cutter."""
        return self.sign * self.base(np.asarray(theta, dtype=float)).normal


def _flat_base(geometry: CamGeometry) -> Callable[[np.ndarray], PitchGeometry]:
    """The flat face's profile as a base curve: its normal is the face's normal R(−σθ)(0, 1)."""
    def base(theta: np.ndarray) -> PitchGeometry:
        profile = geometry.profile(theta)
        up = np.stack((np.zeros_like(theta), np.ones_like(theta)), axis=-1)
        normal = rotate(up, -geometry.sigma * theta)
        zero = np.zeros_like(theta)
        return PitchGeometry(theta=theta, points=profile.points, tangent=profile.tangent, speed=profile.speed,
                             rho=profile.rho, normal=normal, pressure_angle=zero, outward_speed=zero,
                             centre=profile.points)
    return base


def flanks(result: ProfileResult) -> list[Flank]:
    """The flanks of a synthesised cam: the profile, a groove's outer flank, a conjugate pair's counter-cam.

    Parameters
    ----------
    result : ProfileResult
        The synthesised cam (``synthesize``).

    Returns
    -------
    list of Flank
        In that order; each a parallel curve of its base curve (mm).

    Examples
    --------
    >>> import camcad
    >>> from camcad.profile.toolpath import flanks
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> follower = camcad.Follower("roller", base_radius=40.0, roller_radius=10.0, groove=True)
    >>> result = camcad.synthesize(law, follower, camcad.ProfileSettings(plots=False, design=False))
    >>> [(f.name, f.side) for f in flanks(result)]
    [('profile', 'outside'), ('outer flank', 'inside')]
    """
    geometry = result.geometry
    follower = result.follower
    if follower.kind == "flat":
        return [Flank("profile", "", "cam", 1.0, 0.0, _flat_base(geometry))]
    rr = follower.roller_radius
    out = [Flank("profile", "", "cam", 1.0, rr, lambda t: geometry.pitch(t))]
    if follower.groove:
        out.append(Flank("outer flank", "outer_", "cam", -1.0, rr, lambda t: geometry.pitch(t)))
    if follower.has_pair:
        out.append(Flank("counter-cam", "counter_", "counter_cam", 1.0, rr, lambda t: geometry.pitch(t, second=True)))
    return out


def part_ready(result: ProfileResult, what: str) -> None:
    """Refuse to make ``what`` (cutter path, program, solid) of a profile that undercuts or does not close."""
    if result.undercut:
        raise CamcadError(f"the profile undercuts ({'; '.join(result.undercut_reasons)})", f"--export {what}",
                          "enlarge the base circle or make the roller smaller before making the part")
    for curve in (result.profile, result.outer, result.counter):
        if curve is not None and not curve.closed:
            raise CamcadError(f"the {curve.name} does not close (gap {curve.closure_gap:.6g} mm)", f"--export {what}",
                              "balance the law (camcad fix) before making the part")


# --------------------------------------------------------------------------------------------
# cutter paths
# --------------------------------------------------------------------------------------------

def _grid(geometry: CamGeometry, lo: float = 0.0) -> np.ndarray:
    count = math.ceil(2.0 * math.pi / SEARCH_STEP)
    grid = np.linspace(lo, lo + 2.0 * math.pi, count + 1)
    breaks = _breaks(geometry, lo)
    return np.unique(np.concatenate((grid, breaks)))


def _breaks(geometry: CamGeometry, lo: float = 0.0) -> np.ndarray:
    """The law's breakpoints (rad) moved into [lo, lo + 2π]."""
    breaks = geometry.breakpoints()
    breaks = np.where(breaks < lo, breaks + 2.0 * math.pi, breaks)
    return np.unique(breaks[(breaks >= lo) & (breaks <= lo + 2.0 * math.pi)])


def check_cutter(result: ProfileResult, flank: Flank, cutter_radius: float) -> None:
    """Refuse a cutter that cannot follow ``flank``: its centre's path has a cusp (the cutter is larger than a
    concave radius of an outside contour or a convex radius of an inside one) somewhere in the turn.

    The offset's stretch 1 − d/ρ of the base curve (``Flank.distance``) is searched for its smallest value on
    a 0.1° grid with the law's breakpoints, refined by zooming grids; a value ≤ 0 is a cusp.

    Raises
    ------
    CamcadError
        With the cam angle (deg) of the worst point, the flank's radius there (mm) and the cutter's.
    """
    geometry = result.geometry
    d = flank.distance(cutter_radius)
    if d == 0.0:
        return

    def stretch(theta: np.ndarray) -> np.ndarray:
        rho = flank.base(theta).rho
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(np.isfinite(rho), 1.0 - d / rho, 1.0)

    grid = _grid(geometry)
    value, at = zoom_min(stretch, grid, first=stretch(grid))
    if value > 1e-9:
        return
    rho_flank = float(flank.contour(np.array([at])).rho[0])
    shape = "concave" if flank.sign > 0 else "convex"
    raise CamcadError(
        f"a cutter of radius {cutter_radius:g} mm cannot follow the {flank.name} ({flank.side} contour): its "
        f"path loops where the flank's {shape} radius is {abs(rho_flank):.4g} mm, at cam angle "
        f"{math.degrees(at) % 360.0:.2f} deg (undercut)",
        "--cutter-radius", f"use a cutter of radius below {abs(rho_flank):.4g} mm")


def check_crossing(result: ProfileResult, flank: Flank, cutter_radius: float, points: np.ndarray,
                   theta: np.ndarray) -> None:
    """Refuse a cutter path (closed, sampled at ``theta``) that crosses itself, naming the cam angle."""
    import shapely

    ring = shapely.LinearRing(points)
    if ring.is_simple:
        return
    segments = shapely.linestrings(np.stack((points, np.roll(points, -1, axis=0)), axis=1))
    tree = shapely.STRtree(segments)
    left, right = tree.query(segments, predicate="intersects")
    count = len(points)
    apart = np.minimum(np.abs(left - right), count - np.abs(left - right)) > 1
    first = int(np.min(left[apart])) if apart.any() else 0
    raise CamcadError(
        f"the path of a cutter of radius {cutter_radius:g} mm around the {flank.name} crosses itself at cam angle "
        f"{math.degrees(theta[first]) % 360.0:.2f} deg: the cutter does not fit between two parts of the flank",
        "--cutter-radius", "use a smaller cutter")


def check_groove(result: ProfileResult, cutter_radius: float) -> None:
    """A groove's cutter must fit the groove (R ≤ Rr)."""
    follower = result.follower
    if follower.groove and cutter_radius > follower.roller_radius:
        raise CamcadError(f"a cutter of radius {cutter_radius:g} mm is wider than the groove "
                          f"(roller radius {follower.roller_radius:g} mm)", "--cutter-radius",
                          f"use a cutter of radius at most {follower.roller_radius:g} mm")


@dataclass(frozen=True)
class CutterPath:
    """A cutter centre's path around one flank: cam angles (rad), centres (mm) and the unit normals from the
    flank toward the centre, at the points asked for."""

    flank: Flank
    cutter_radius: float
    theta: np.ndarray
    points: np.ndarray
    normals: np.ndarray


def cutter_paths(result: ProfileResult, cutter_radius: float, theta: np.ndarray) -> list[CutterPath]:
    """The cutter centre's path around every flank at the cam angles ``theta`` (rad), checked.

    Parameters
    ----------
    result : ProfileResult
        The synthesised cam; it must not undercut and must close (``part_ready``).
    cutter_radius : float
        R, mm (> 0).
    theta : ndarray
        Cam angles (rad) at which to give the path.

    Returns
    -------
    list of CutterPath
        One per flank (``flanks``): C = X + sign·R·n, exact (mm).

    Raises
    ------
    CamcadError
        A cutter wider than the groove, a cusp (undercut) or a crossing of a path, with its cam angle.

    Examples
    --------
    On a base-circle dwell the centre of a 5 mm cutter runs on the circle Rb + 5:

    >>> import numpy as np, camcad
    >>> from camcad.profile.toolpath import cutter_paths
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> result = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0),
    ...                            camcad.ProfileSettings(plots=False, design=False))
    >>> (path,) = cutter_paths(result, 5.0, np.radians([300.0]))
    >>> round(float(np.hypot(*path.points[0])), 12)
    45.0
    """
    if not (math.isfinite(cutter_radius) and cutter_radius > 0.0):
        raise CamcadError(f"the cutter radius must be a positive number of mm, got {cutter_radius!r}",
                          "--cutter-radius", "give e.g. --cutter-radius 5")
    part_ready(result, "cutter")
    check_groove(result, cutter_radius)
    theta = np.asarray(theta, dtype=float)
    out = []
    for flank in flanks(result):
        check_cutter(result, flank, cutter_radius)
        fn = flank.cutter(cutter_radius)
        nodes = chord_nodes(fn, 0.0, 2.0 * math.pi, max(result.settings.tol_mm, 1e-4), _breaks(result.geometry))
        check_crossing(result, flank, cutter_radius, nodes.points[:-1], nodes.theta[:-1])
        out.append(CutterPath(flank, cutter_radius, theta, fn(theta).points, flank.normal(theta)))
    return out


# --------------------------------------------------------------------------------------------
# contour programs: moves
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Move:
    """One move of a contour program (mm).

    kind : "rapid" (G0), "line" (G1) or "arc" (G2 clockwise / G3 counter-clockwise about ``centre``).
    end : (x, y), or None for a move along Z only.
    z : the Z of a move along Z (None: Z unchanged).
    comp : "left" (G41), "right" (G42) or "off" (G40) switched on this move; None: unchanged.
    note : a comment written before the move ("" for none).
    """

    kind: str
    end: tuple[float, float] | None = None
    z: float | None = None
    centre: tuple[float, float] | None = None
    ccw: bool = False
    comp: str | None = None
    note: str = ""


@dataclass(frozen=True)
class Pass:
    """One closed contour of a program: what it cuts and its moves from the start of the lead-in."""

    label: str
    flank: Flank | None
    start: tuple[float, float]
    moves: tuple[Move, ...]
    arcs: int
    lines: int
    max_deviation: float


@dataclass(frozen=True)
class ContourProgram:
    """A contour program for one part (cam or counter-cam): its passes at one depth (mm).

    comp : "camcad" (the moves are the cutter centre's) or "machine" (the moves are the flanks; the
    control offsets them by its own tool radius, G41/G42).
    """

    part: str
    comp: str
    cutter_radius: float
    depth: float
    clearance: float
    start_deg: float
    passes: tuple[Pass, ...]
    tol_mm: float


def start_angle(result: ProfileResult) -> float:
    """Cam angle (rad) where a contour starts: the middle of the dwell nearest the cam centre (the base
    circle, where a lead-in mark matters least), or 0 for a law without a dwell."""
    law = result.law
    dwells = [p for p in law.phases if p.kind == "dwell"]
    if not dwells:
        return 0.0
    middles = np.array([(p.start + p.end) / 2.0 for p in dwells])
    heights = law.kinematics(middles).s
    k = int(np.argmin(heights + 1e-9 * np.arange(len(heights))))   # the first of equal heights
    return float(middles[k])


def arc_moves(path: ArcPath, tol: float) -> list[Move]:
    """The lines and arcs of a biarc path (``sampling.biarc_fit``): an arc whose sagitta is at most
    ``STRAIGHT_SAGITTA`` × ``tol`` or whose chord is shorter than ``SHORT_ARC_MM`` becomes a line."""
    v, b = path.vertices, path.bulges
    moves: list[Move] = []
    for i in range(len(v) - 1):
        start, end, bulge = v[i], v[i + 1], float(b[i])
        chord = float(np.hypot(*(end - start)))
        if chord == 0.0:
            continue
        sagitta = chord * abs(bulge) / 2.0
        if abs(bulge) < BULGE_STRAIGHT or sagitta <= STRAIGHT_SAGITTA * tol or chord < SHORT_ARC_MM:
            moves.append(Move("line", (float(end[0]), float(end[1]))))
            continue
        centre, _ = arc_centre(start, end, np.asarray(bulge))
        moves.append(Move("arc", (float(end[0]), float(end[1])), centre=(float(centre[0]), float(centre[1])),
                          ccw=bulge > 0.0))
    return moves


def _reverse(start: tuple[float, float], moves: list[Move]) -> tuple[tuple[float, float], list[Move]]:
    """The same closed path run the other way."""
    points = [start] + [cast(tuple[float, float], m.end) for m in moves]
    out = []
    for k in range(len(moves) - 1, -1, -1):
        m = moves[k]
        out.append(Move(m.kind, points[k], centre=m.centre, ccw=not m.ccw))
    return points[-1], out


def _turns_left(a: np.ndarray, b: np.ndarray) -> bool:
    return bool(a[0] * b[1] - a[1] * b[0] > 0.0)


def _lead(point: np.ndarray, tangent: np.ndarray, away: np.ndarray, radius: float, entering: bool
          ) -> tuple[list[tuple[float, float]], Move]:
    """A straight line and a quarter arc of ``radius`` tangent to the contour at ``point`` (travel direction
    ``tangent``), on the side ``away`` from the material: returns the line's far end and the arc's near end
    (lead-in: line end → arc start → point), and the arc move (for a lead-out, from ``point``)."""
    centre = point + radius * away
    if entering:
        near = centre - radius * tangent                    # the arc's start
        far = near + radius * away                          # the line's start
        ccw = _turns_left(near - centre, point - centre)
        arc = Move("arc", (float(point[0]), float(point[1])), centre=(float(centre[0]), float(centre[1])), ccw=ccw)
        return [(float(far[0]), float(far[1])), (float(near[0]), float(near[1]))], arc
    near = centre + radius * tangent                        # the arc's end
    far = near + radius * away
    ccw = _turns_left(point - centre, near - centre)
    arc = Move("arc", (float(near[0]), float(near[1])), centre=(float(centre[0]), float(centre[1])), ccw=ccw)
    return [(float(near[0]), float(near[1])), (float(far[0]), float(far[1]))], arc


def _contour_pass(result: ProfileResult, label: str, flank: Flank | None, fn, away_fn, start: float, climb_ccw: bool,
                  lead_radius: float, tol: float, comp: str | None, depth: float, first: bool) -> Pass:
    """One closed contour with its lead-in and lead-out; ``fn`` θ → CurveGeometry of the programmed path,
    ``away_fn`` θ → unit normal pointing away from the material (toward the cutter)."""
    geometry = result.geometry
    path = biarc_fit(fn, start, start + 2.0 * math.pi, tol, _breaks(geometry, start), samples=17)
    moves = arc_moves(path, tol)
    p0 = path.vertices[0]
    t0 = fn(np.array([start])).tangent[0]
    begin = (float(p0[0]), float(p0[1]))
    # θ increasing runs clockwise around the cam for σ = +1 (``geometry``)
    runs_ccw = geometry.sigma < 0.0
    if runs_ccw != climb_ccw:
        begin, moves = _reverse(begin, moves)
        t0 = -t0
    # the closing vertex is the start itself: make it exactly so
    last = moves[-1]
    moves[-1] = Move(last.kind, begin, centre=last.centre, ccw=last.ccw)
    away = away_fn(np.array([start]))[0]
    p = np.array(begin)
    (line_start, arc_start), arc_in = _lead(p, t0, away, lead_radius, entering=True)
    (_arc_end, line_end), arc_out = _lead(p, t0, away, lead_radius, entering=False)
    body: list[Move] = []
    if first:
        body.append(Move("rapid", line_start, note=f"{label}: to the start of the lead-in"))
        body.append(Move("line", None, z=-depth, note="down to depth"))
    else:
        body.append(Move("line", line_start, note=f"{label}: to the start of the lead-in"))
    body.append(Move("line", arc_start, comp=comp, note="lead-in"))
    body.append(arc_in)
    body.append(Move(moves[0].kind, moves[0].end, centre=moves[0].centre, ccw=moves[0].ccw,
                     note=f"{label}: the contour"))
    body.extend(moves[1:])
    body.append(Move(arc_out.kind, arc_out.end, centre=arc_out.centre, ccw=arc_out.ccw, note="lead-out"))
    body.append(Move("line", line_end, comp="off" if comp else None))
    arcs = sum(m.kind == "arc" for m in moves)
    return Pass(label, flank, begin, tuple(body), arcs, len(moves) - arcs, path.max_deviation)


def contour_program(result: ProfileResult, part: str, cutter_radius: float, depth: float,
                    comp: str = "camcad", tol: float | None = None) -> ContourProgram:
    """The contour program of one part (mm): passes of lines and arcs, lead-ins and lead-outs.

    Parameters
    ----------
    result : ProfileResult
        The synthesised cam (not undercut, closed).
    part : str
        "cam" or "counter_cam" (a conjugate pair's second plate).
    cutter_radius : float
        R, mm.
    depth : float
        Depth of cut below the stock's top (Z 0), mm (> 0).
    comp : str
        "camcad": the program follows the cutter centre (the exact offset, ``Flank.cutter``);
        "machine": it follows the flank and switches on the control's compensation (G41, the cutter left of
        the travel), lead-in arcs of radius 2R.
    tol : float, optional
        Largest distance of the lines and arcs from the exact path, mm; ``result.settings.tol_mm`` by default.

    Returns
    -------
    ContourProgram
        Its passes (moves in mm): the outside contour, or for a groove the pitch-curve slot and then each
        flank's finishing pass (when R < Rr).

    Raises
    ------
    CamcadError
        A cutter that cannot follow a flank (``check_cutter``, ``check_crossing``), a groove narrower than
        the cutter, or machine compensation asked for a groove.

    Examples
    --------
    >>> import camcad
    >>> from camcad.profile.toolpath import contour_program
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> result = camcad.synthesize(law, camcad.Follower("roller", base_radius=40.0, roller_radius=10.0),
    ...                            camcad.ProfileSettings(plots=False, design=False, tol_mm=0.01))
    >>> program = contour_program(result, "cam", cutter_radius=5.0, depth=10.0)
    >>> [p.label for p in program.passes], program.start_deg
    (['profile, outside contour'], 315.0)
    >>> program.passes[0].moves[0].kind, program.passes[0].moves[1].z
    ('rapid', -10.0)
    """
    tol = result.settings.tol_mm if tol is None else tol
    if comp not in ("camcad", "machine"):
        raise CamcadError(f"cutter compensation {comp!r} is unknown", "--comp", "use camcad or machine")
    if not (math.isfinite(depth) and depth > 0.0):
        raise CamcadError(f"the depth of cut must be a positive number of mm, got {depth!r}", "--depth",
                          "give e.g. --depth 10")
    part_ready(result, "gcode")
    check_groove(result, cutter_radius)
    chosen = [f for f in flanks(result) if f.part == part]
    if not chosen:
        raise ValueError(f"no flank belongs to part {part!r}")
    start = start_angle(result)
    geometry = result.geometry
    passes: list[Pass] = []
    groove = result.follower.groove and part == "cam"
    if groove and comp == "machine":
        raise CamcadError("the control's cutter compensation cannot enter a groove on a lead-in arc", "--comp machine",
                          "use --comp camcad for a groove cam (the program then follows the cutter centre)")
    for flank in chosen:
        check_cutter(result, flank, cutter_radius)
    if groove:
        pitch = chosen[0]
        slot = pitch.cutter(pitch.roller_radius)   # d = 0: the pitch curve itself
        nodes = chord_nodes(slot, 0.0, 2.0 * math.pi, max(tol, 1e-4), _breaks(geometry))
        check_crossing(result, pitch, pitch.roller_radius, nodes.points[:-1], nodes.theta[:-1])
        passes.append(_slot_pass(result, slot, start, tol, depth))
        width = pitch.roller_radius - cutter_radius
        if width > 0.0:
            for flank in chosen:
                fn = flank.cutter(cutter_radius)
                nodes = chord_nodes(fn, 0.0, 2.0 * math.pi, max(tol, 1e-4), _breaks(geometry))
                check_crossing(result, flank, cutter_radius, nodes.points[:-1], nodes.theta[:-1])
                passes.append(_contour_pass(result, f"{flank.name}, finishing", flank, fn, flank.normal, start,
                                            climb_ccw=flank.sign < 0, lead_radius=width / 2.0, tol=tol, comp=None,
                                            depth=depth, first=False))
    else:
        for k, flank in enumerate(chosen):
            if comp == "camcad":
                fn = flank.cutter(cutter_radius)
                nodes = chord_nodes(fn, 0.0, 2.0 * math.pi, max(tol, 1e-4), _breaks(geometry))
                check_crossing(result, flank, cutter_radius, nodes.points[:-1], nodes.theta[:-1])
                lead, side = cutter_radius, None
            else:
                fn, lead, side = flank.contour, 2.0 * cutter_radius, "left"
            passes.append(_contour_pass(result, f"{flank.name}, {flank.side} contour", flank, fn, flank.normal, start,
                                        climb_ccw=flank.sign < 0, lead_radius=lead, tol=tol, comp=side, depth=depth,
                                        first=k == 0))
    return ContourProgram(part, comp, cutter_radius, depth, CLEARANCE_MM, math.degrees(start), tuple(passes), tol)


def _slot_pass(result: ProfileResult, fn, start: float, tol: float, depth: float) -> Pass:
    """The groove's first pass: the cutter centre on the pitch curve, plunged at the start (a centre-cutting
    cutter), climb sense as for the inner flank (clockwise around the cam)."""
    geometry = result.geometry
    path = biarc_fit(fn, start, start + 2.0 * math.pi, tol, _breaks(geometry, start), samples=17)
    moves = arc_moves(path, tol)
    begin = (float(path.vertices[0][0]), float(path.vertices[0][1]))
    if geometry.sigma < 0.0:
        begin, moves = _reverse(begin, moves)
    last = moves[-1]
    moves[-1] = Move(last.kind, begin, centre=last.centre, ccw=last.ccw)
    body = [Move("rapid", begin, note="groove: to the pitch curve"),
            Move("line", None, z=-depth, note="plunge to depth (a centre-cutting cutter)"),
            Move(moves[0].kind, moves[0].end, centre=moves[0].centre, ccw=moves[0].ccw,
                 note="groove: along the pitch curve")]
    body.extend(moves[1:])
    arcs = sum(m.kind == "arc" for m in moves)
    return Pass("groove, pitch curve", None, begin, tuple(body), arcs, len(moves) - arcs, path.max_deviation)


# --------------------------------------------------------------------------------------------
# solid outlines
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Outline:
    """A closed flank as a clamped cubic B-spline (mm) in the cam angle θ (rad), and where its pieces meet.

    ``spline``: control points, knots (θ) and degree 3; ``joints``: θ where the law's pieces meet (knots of
    full multiplicity) and the ends; ``max_deviation``: the largest distance found between the spline and the
    exact flank (mm)."""

    name: str
    spline: SplineData
    joints: np.ndarray
    max_deviation: float


def _piece_spline(fn, theta: np.ndarray):
    from scipy.interpolate import make_interp_spline

    geo = fn(theta)
    start = geo.tangent[0] * geo.speed[0]
    end = geo.tangent[-1] * geo.speed[-1]
    return make_interp_spline(theta, geo.points, k=3, bc_type=([(1, start)], [(1, end)]))


def outline_spline(result: ProfileResult, fn, name: str, tol: float, max_rounds: int = 30) -> Outline:
    """The closed curve ``fn`` (θ → CurveGeometry, over one turn) as a clamped cubic B-spline within ``tol``.

    Each smooth piece between the law's breakpoints is interpolated at exact points with its exact end
    derivatives (so the pieces join with a common tangent); the distance to the exact curve is checked at 8
    points per span and a span over ``tol`` is halved, until none is.

    Returns
    -------
    Outline
        The spline (mm, knots in rad), its joints (rad) and its largest deviation (mm).
    """
    geometry = result.geometry
    edges = np.unique(np.concatenate(([0.0], _breaks(geometry), [2.0 * math.pi])))
    # a cubic's error falls as h⁴: start from the nodes of a chord tolerance 100 times coarser and halve the
    # spans that miss
    nodes = chord_nodes(fn, 0.0, 2.0 * math.pi, min(100.0 * tol, 0.5), edges).theta
    for _ in range(max_rounds):
        pieces, worst, bad = [], 0.0, []
        for lo, hi in itertools.pairwise(edges):
            inside = nodes[(nodes > lo) & (nodes < hi)]
            theta = np.concatenate(([lo], inside, [hi]))
            if len(theta) < 4:
                theta = np.linspace(lo, hi, 4)
            spline = _piece_spline(fn, theta)
            frac = (np.arange(1, 9) / 9.0)[None, :]
            check = (theta[:-1, None] + np.diff(theta)[:, None] * frac).ravel()
            distance = np.hypot(*(spline(check) - fn(check).points).T).reshape(-1, 8).max(axis=1)
            worst = max(worst, float(distance.max()))
            over = distance > 0.5 * tol
            bad.extend(((theta[:-1] + theta[1:]) / 2.0)[over])
            pieces.append(spline)
        if not bad:
            break
        nodes = np.unique(np.concatenate((nodes, bad)))
    else:
        raise CamcadError(f"the {name} could not be fitted by a spline within {tol:g} mm", "--tol-mm",
                          "use a coarser --tol-mm")
    # pieces A (knots a⁴ … b⁴) and B (b⁴ … c⁴) join as a⁴ … b³ … c⁴, sharing the control point at b
    control = np.concatenate([pieces[0].c] + [p.c[1:] for p in pieces[1:]])
    if len(pieces) == 1:
        knots = pieces[0].t
    else:
        knots = np.concatenate([pieces[0].t[:-1]] + [p.t[4:-1] for p in pieces[1:-1]] + [pieces[-1].t[4:]])
    return Outline(name, SplineData(control, knots, 3), edges, worst)


# --------------------------------------------------------------------------------------------
# points tables
# --------------------------------------------------------------------------------------------

def table_angles(result: ProfileResult, step_deg: float | None) -> np.ndarray:
    """Cam angles (rad) of a points table over one turn: every ``step_deg`` from 0 (the end of the turn not
    repeated), or with ``step_deg`` None the profile's own chord nodes (within its chord tolerance) and those
    of every other flank, merged."""
    if step_deg is not None:
        count = round(360.0 / step_deg)
        if abs(count * step_deg - 360.0) > 1e-9 * 360.0:
            raise CamcadError(f"a step of {step_deg:g} deg does not divide the turn", "--step-deg",
                              "give a step that divides 360 (e.g. 1, 0.5, 0.25)")
        return np.radians(np.arange(count) * step_deg)
    nodes = [result.profile.polyline.theta]
    for curve in (result.outer, result.counter):
        if curve is not None:
            nodes.append(curve.polyline.theta)
    theta = np.unique(np.concatenate(nodes))
    return theta[theta < 2.0 * math.pi - 1e-12]


def polar(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Polar radius (mm) and polar angle (deg, [0, 360)) of points about the cam centre."""
    r = np.hypot(points[:, 0], points[:, 1])
    angle = np.degrees(np.arctan2(points[:, 1], points[:, 0])) % 360.0
    return r, np.where(angle >= 360.0, 0.0, angle)


def turn_sense(result: ProfileResult) -> str:
    return "clockwise" if result.follower.cw else "counter-clockwise"


__all__ = ["CLEARANCE_MM", "ContourProgram", "CutterPath", "Flank", "Move", "Outline", "Pass", "check_crossing",
           "check_cutter", "check_groove", "contour_program", "cutter_paths", "flanks", "outline_spline",
           "part_ready", "polar", "start_angle", "table_angles", "turn_sense"]
