"""Turning an exact curve into points, tangent arcs or a spline within a chord tolerance.

The curve is known exactly at any θ (``CurveFn``: θ → ``CurveGeometry``), so the written
geometry can be placed where it is needed and then verified against the exact curve.

Polyline (``chord_nodes``): a chord of length c on an arc of radius ρ deviates from it by the
sagitta c²/(8ρ), so the tangent may turn by Δα = √(8 tol/|ρ|) per chord and the number of
chords per radian of θ is n(θ) = |X'| / √(8 |ρ| tol) (|X'| the speed along the curve). The nodes
equidistribute ∫ n dθ between breakpoints (where the curvature may jump); then every interval
is checked against exact interior points and the few that exceed the tolerance are bisected.

Arcs (``biarc_fit``): between two nodes with exact unit tangents t0, t1 a biarc (two circular
arcs meeting with a common tangent) matches both end points and tangents, so the chain is
tangent-continuous (G1). The equal-tangent-length biarc is used: with v = P1 − P0,
t = t0 + t1, the control points P0 + δ t0 and P1 − δ t1 must be 2δ apart, |v − δ t| = 2δ,
whose positive root, written without cancellation, is
    δ = |v|² / (v·t + √((v·t)² + 2(1 − t0·t1)|v|²)),
and the joint is the midpoint of P0 + δ t0 and P1 − δ t1. Its deviation from the curve is
O(h³) against O(h²) for chords, so far fewer segments are needed. Each arc is written as a
polyline bulge b = tan(α/4) (α the signed included angle). Source: K. M. Bolton, "Biarc
curves", Computer-Aided Design 7 (1975) 89–92; D. B. Parkinson and D. N. Moreton, "Optimal
biarc-curve fitting", Computer-Aided Design 23 (1991) 411–419.

Spline (``interpolating_spline``): a clamped cubic B-spline through the nodes in the curve's
own parameter θ, with the exact end derivatives, so a closed profile closes with a common
tangent. It is written with control points and knots (no fit points; see dxf-interop.md).

The accuracy knob of each routine is ``tol`` (mm); ``samples`` is the number of exact interior
points per interval used for the check.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from itertools import pairwise

import numpy as np

from camcad.arrays import unique
from camcad.errors import CamcadError
from camcad.profile.geometry import CurveGeometry, cross, dot, perp

CurveFn = Callable[[np.ndarray], CurveGeometry]

# Placement aims below the tolerance so that few intervals need bisection; the check
# itself accepts up to ``ACCEPT`` × tol to leave room for its own estimation error.
PLACEMENT_MARGIN = 0.8
ACCEPT = 0.97
#: the most points a written curve may have (a CAD program opens 1,000,000 vertices slowly; the check samples 7
#: points per interval, so 3,000,000 nodes ran out of memory for a 1e9 mm base radius: fuzz case 53324)
MAX_NODES = 1_000_000


def _pieces(lo: float, hi: float, breakpoints) -> np.ndarray:
    inner = np.asarray([b for b in np.asarray(breakpoints, dtype=float) if lo < b < hi])
    return unique(np.concatenate(([lo], inner, [hi])))


def _density(curve: CurveFn, theta: np.ndarray, tol: float) -> np.ndarray:
    """Chords per radian of θ for a sagitta of ``tol``: |X'| / √(8 |ρ| tol) (a cusp, ρ → 0, would ask for
    infinitely many chords; a chord of length tol is enough there)."""
    return density_of(curve(theta), tol)


def pilot_grid(lo: float, hi: float, breakpoints, pilot: int) -> list[np.ndarray]:
    """The pilot grid of each piece between breakpoints (at least 8 intervals per piece)."""
    edges = _pieces(lo, hi, breakpoints)
    widths = np.diff(edges)
    counts = np.maximum(8, np.ceil(pilot * widths / (hi - lo))).astype(int)
    return [np.linspace(a, b, k + 1) for a, b, k in zip(edges[:-1], edges[1:], counts)]


def chord_counts(pilot_theta: list[np.ndarray], density: np.ndarray) -> list[np.ndarray]:
    """The cumulative predicted chord count along each piece's pilot grid (``density`` on the concatenated
    pilot grid)."""
    cumulatives = []
    start = 0
    for grid in pilot_theta:
        dens = density[start:start + len(grid)]
        start += len(grid)
        cumulatives.append(np.concatenate(([0.0], np.cumsum(np.diff(grid) * (dens[:-1] + dens[1:]) / 2.0))))
    return cumulatives


def _total_nodes(cumulatives: list[np.ndarray]) -> float:
    return float(sum(max(1.0, np.ceil(c[-1])) if np.isfinite(c[-1]) else np.inf for c in cumulatives)) + 1.0


def nodes_from_density(pilot_theta: list[np.ndarray], density: np.ndarray, lo: float, hi: float,
                       tol: float) -> np.ndarray:
    """Nodes that equidistribute the predicted chord count (``density`` on the concatenated pilot grid);
    refused before any node is placed when the whole curve would need more than :data:`MAX_NODES`."""
    cumulatives = chord_counts(pilot_theta, density)
    total = _total_nodes(cumulatives)
    if total > MAX_NODES:
        shown = f"{total:,.0f}" if np.isfinite(total) else "infinitely many"
        raise CamcadError(f"the chord tolerance {tol:g} mm needs about {shown} points on one curve, more than "
                          f"camcad writes ({MAX_NODES:,})", "profile", "use a coarser --tol-mm")
    nodes = [np.array([lo])]
    for grid, cumulative in zip(pilot_theta, cumulatives):
        chords = max(1, int(np.ceil(cumulative[-1])))
        if cumulative[-1] > 0.0:
            targets = np.linspace(0.0, cumulative[-1], chords + 1)[1:]
            nodes.append(np.interp(targets, cumulative, grid))
        else:
            nodes.append(np.linspace(grid[0], grid[-1], chords + 1)[1:])
    out = np.concatenate(nodes)
    out[-1] = hi
    return unique(out)


def predicted_nodes(curve: CurveFn, lo: float, hi: float, tol: float, breakpoints=(), pilot: int = 2048) -> float:
    """How many points ``chord_nodes`` will place on [lo, hi] for the chord tolerance ``tol`` (mm): the chord
    count integrated on a pilot grid (module docstring), computed before any point is placed.

    Examples
    --------
    A circle of radius R = 100 mm, tolerance 0.01 mm: a chord of sagitta h = 0.8·tol (the placement margin)
    spans √(8·R·h) of arc, so the circle takes 2πR / √(8·R·h) = 248.4 chords, 249 of them, and 250 points:

    >>> import numpy as np
    >>> from camcad.profile.geometry import CurveGeometry
    >>> def circle(t):
    ...     t = np.asarray(t, dtype=float)
    ...     return CurveGeometry(t, np.column_stack((100 * np.cos(t), 100 * np.sin(t))),
    ...                          np.column_stack((-np.sin(t), np.cos(t))), np.full(t.shape, 100.0),
    ...                          np.full(t.shape, 100.0))
    >>> predicted_nodes(circle, 0.0, 2 * np.pi, 0.01)
    250.0
    """
    pilot_theta = pilot_grid(lo, hi, breakpoints, pilot)
    density = _density(curve, np.concatenate(pilot_theta), PLACEMENT_MARGIN * tol)
    return _total_nodes(chord_counts(pilot_theta, density))


def density_of(geo: CurveGeometry, tol: float) -> np.ndarray:
    rho = np.maximum(np.abs(geo.rho), tol / 8.0)
    with np.errstate(invalid="ignore"):
        density = geo.speed / np.sqrt(8.0 * rho * tol)
    return np.where(np.isfinite(density), density, 0.0)


def initial_nodes(curve: CurveFn, lo: float, hi: float, tol: float, breakpoints=(),
                  pilot: int = 2048) -> np.ndarray:
    """Nodes that equidistribute the predicted chord count, breakpoints included."""
    pilot_theta = pilot_grid(lo, hi, breakpoints, pilot)
    density = _density(curve, np.concatenate(pilot_theta), PLACEMENT_MARGIN * tol)
    return nodes_from_density(pilot_theta, density, lo, hi, tol)


def peak_of_samples(samples: np.ndarray) -> np.ndarray:
    """Largest value along axis 1 of samples taken at equal steps, refined by a parabola
    through the largest sample and its two neighbours (the ends are zero by construction)."""
    n, _m = samples.shape
    padded = np.concatenate((np.zeros((n, 1)), samples, np.zeros((n, 1))), axis=1)
    k = np.argmax(padded[:, 1:-1], axis=1) + 1
    rows = np.arange(n)
    y0, y1, y2 = padded[rows, k - 1], padded[rows, k], padded[rows, k + 1]
    curvature = y2 - 2.0 * y1 + y0
    with np.errstate(divide="ignore", invalid="ignore"):
        vertex = y1 - (y2 - y0) ** 2 / (8.0 * curvature)
    vertex = np.where(curvature < 0.0, vertex, y1)
    return np.maximum(y1, np.minimum(vertex, 2.0 * y1 + 1e-300))


def interior_theta(a: np.ndarray, b: np.ndarray, samples: int) -> np.ndarray:
    frac = np.arange(1, samples + 1) / (samples + 1)
    return a[:, None] + (b - a)[:, None] * frac[None, :]


def point_segment_distance(points: np.ndarray, start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """Distance from points (..., 2) to segments start→end (broadcast), mm."""
    seg = end - start
    length2 = dot(seg, seg)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(length2 > 0.0, dot(points - start, seg) / length2, 0.0)
    t = np.clip(t, 0.0, 1.0)
    foot = start + t[..., None] * seg
    return np.hypot(*(points - foot).transpose(-1, *range(points.ndim - 1)))


def chord_deviation(curve: CurveFn, nodes: np.ndarray, node_points: np.ndarray, samples: int = 7
                    ) -> np.ndarray:
    """Largest distance between the exact curve and each chord (one value per interval), mm."""
    a, b = nodes[:-1], nodes[1:]
    theta = interior_theta(a, b, samples)
    exact = curve(theta.ravel()).points.reshape(len(a), samples, 2)
    dist = point_segment_distance(exact, node_points[:-1, None, :], node_points[1:, None, :])
    return peak_of_samples(dist)


@dataclass(frozen=True)
class Polyline:
    """Chord approximation: ``theta`` nodes (rad), ``points`` (N, 2) exactly on the curve, and the
    largest chord deviation found by the check (mm)."""

    theta: np.ndarray
    points: np.ndarray
    max_deviation: float


def chord_nodes(curve: CurveFn, lo: float, hi: float, tol: float, breakpoints=(), samples: int = 7,
                max_rounds: int = 60) -> Polyline:
    """Nodes on [lo, hi] whose chords stay within ``tol`` (mm) of the exact curve."""
    if not tol > 0.0:
        raise CamcadError(f"chord tolerance must be positive, got {tol:g} mm", "--tol-mm", "give e.g. 0.001")
    nodes = initial_nodes(curve, lo, hi, tol, breakpoints)
    for _ in range(max_rounds):
        points = curve(nodes).points
        deviation = chord_deviation(curve, nodes, points, samples)
        bad = deviation > ACCEPT * tol
        if not bad.any():
            return Polyline(nodes, points, float(deviation.max(initial=0.0)))
        if len(nodes) + bad.sum() > MAX_NODES:
            break
        nodes = np.sort(np.concatenate((nodes, (nodes[:-1][bad] + nodes[1:][bad]) / 2.0)))
    raise CamcadError(f"could not meet the chord tolerance {tol:g} mm with {len(nodes)} points "
                      "(the profile has a cusp or a loop)", "profile", "use a coarser --tol-mm or fix the undercut")


def chord_nodes_joint(evaluate, names, lo: float, hi: float, tol: float, breakpoints=(), samples: int = 7,
                      max_rounds: int = 60, points=None) -> dict[str, Polyline]:
    """``chord_nodes`` of several curves of one θ (e.g. a cam's profile and pitch curve) at once: every
    stage evaluates all of them with one call ``evaluate(theta) -> {name: CurveGeometry}`` (``points(theta)
    -> {name: (N, 2) points}``, when given, for the stages that need the points alone); each curve gets
    exactly the nodes ``chord_nodes`` would give it."""
    if points is None:
        def points(theta: np.ndarray) -> dict[str, np.ndarray]:
            return {n: g.points for n, g in evaluate(theta).items()}

    if not tol > 0.0:
        raise CamcadError(f"chord tolerance must be positive, got {tol:g} mm", "--tol-mm", "give e.g. 0.001")
    names = list(names)
    pilot_theta = pilot_grid(lo, hi, breakpoints, 2048)
    pilot_geo = evaluate(np.concatenate(pilot_theta))
    nodes = {n: nodes_from_density(pilot_theta, density_of(pilot_geo[n], PLACEMENT_MARGIN * tol), lo, hi, tol)
             for n in names}
    done: dict[str, Polyline] = {}
    for _ in range(max_rounds):
        pending = [n for n in names if n not in done]
        if not pending:
            return done
        parts, spans, start = [], {}, 0
        for n in pending:
            inner = interior_theta(nodes[n][:-1], nodes[n][1:], samples).ravel()
            parts += [nodes[n], inner]
            spans[n] = (start, start + len(nodes[n]), start + len(nodes[n]) + len(inner))
            start = spans[n][2]
        geo = points(np.concatenate(parts))
        for n in pending:
            first, middle, last = spans[n]
            ends = geo[n][first:middle]
            exact = geo[n][middle:last].reshape(len(nodes[n]) - 1, samples, 2)
            deviation = peak_of_samples(point_segment_distance(exact, ends[:-1, None, :], ends[1:, None, :]))
            bad = deviation > ACCEPT * tol
            if not bad.any():
                done[n] = Polyline(nodes[n], ends, float(deviation.max(initial=0.0)))
                continue
            if len(nodes[n]) + bad.sum() > MAX_NODES:
                raise CamcadError(f"could not meet the chord tolerance {tol:g} mm with {len(nodes[n])} points "
                                  "(the profile has a cusp or a loop)", "profile",
                                  "use a coarser --tol-mm or fix the undercut")
            nodes[n] = np.sort(np.concatenate((nodes[n], (nodes[n][:-1][bad] + nodes[n][1:][bad]) / 2.0)))
    if len(done) == len(names):
        return done
    worst = next(n for n in names if n not in done)
    raise CamcadError(f"could not meet the chord tolerance {tol:g} mm with {len(nodes[worst])} points "
                      "(the profile has a cusp or a loop)", "profile", "use a coarser --tol-mm or fix the undercut")


# --------------------------------------------------------------------------------------------
# Biarcs
# --------------------------------------------------------------------------------------------

BULGE_STRAIGHT = 1e-9  # below this |bulge| an arc is treated as its chord (sagitta < 1e-9 × chord)


@dataclass(frozen=True)
class ArcPath:
    """Tangent arcs as polyline vertices and bulges (bulge[i] belongs to vertices[i] → [i+1]).

    theta: the nodes (rad) where the path touches the curve with its exact tangent; between
    two nodes lie two arcs meeting at a joint, so len(vertices) = 2·len(theta) − 1.
    """

    theta: np.ndarray
    vertices: np.ndarray
    bulges: np.ndarray
    max_deviation: float


def bulge_of(chord: np.ndarray, tangent: np.ndarray, at_start: bool) -> np.ndarray:
    """Bulge of the arc over ``chord`` with the unit ``tangent`` at its start (or end).

    The tangent makes the angle α/2 with the chord (α the signed included angle, > 0 for a
    counter-clockwise arc, where the start tangent lies clockwise of the chord), b = tan(α/4).
    """
    half = np.arctan2(cross(chord, tangent), dot(chord, tangent))  # chord → tangent
    return np.tan((-half if at_start else half) / 2.0)


def biarcs(p0: np.ndarray, t0: np.ndarray, p1: np.ndarray, t1: np.ndarray
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Equal-tangent-length biarcs P0→J→P1 (module docstring); returns joints and both bulges."""
    v = p1 - p0
    t = t0 + t1
    vt = dot(v, t)
    vv = dot(v, v)
    gap = 2.0 * (1.0 - dot(t0, t1))
    root = np.sqrt(np.maximum(vt**2 + gap * vv, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        delta = np.where(vt + root > 0.0, vv / (vt + root), 0.0)
    joint = (p0 + delta[:, None] * t0 + p1 - delta[:, None] * t1) / 2.0
    b1 = bulge_of(joint - p0, t0, at_start=True)
    b2 = bulge_of(p1 - joint, t1, at_start=False)
    return joint, b1, b2


def arc_centre(start: np.ndarray, end: np.ndarray, bulge: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centre and radius of the arc start→end with ``bulge`` (|bulge| > 0).

    The centre lies (c/2)(1 − b²)/(2b) from the chord's midpoint, to the left for b > 0."""
    chord = end - start
    length = np.hypot(chord[..., 0], chord[..., 1])
    unit = chord / length[..., None]
    offset = (length / 2.0) * (1.0 - bulge**2) / (2.0 * bulge)
    centre = (start + end) / 2.0 + offset[..., None] * perp(unit)
    radius = (length / 2.0) * (1.0 + bulge**2) / (2.0 * np.abs(bulge))
    return centre, radius


def point_arc_distance(points: np.ndarray, start: np.ndarray, end: np.ndarray, bulge: np.ndarray
                       ) -> np.ndarray:
    """Distance from points (n, m, 2) to the arcs start→end (n, 2) with bulges (n,), mm.

    Arcs here are less than a half circle (|b| < 1); a point whose direction from the centre
    lies outside the arc's sweep is measured to the nearer end point."""
    straight = np.abs(bulge) < BULGE_STRAIGHT
    safe = np.where(straight, 1.0, bulge)
    centre, radius = arc_centre(start, end, safe)
    s, e, c = start[:, None, :], end[:, None, :], centre[:, None, :]
    rel = points - c
    to_circle = np.abs(np.hypot(rel[..., 0], rel[..., 1]) - radius[:, None])
    turn = np.sign(safe)[:, None]
    inside = (turn * cross(s - c, rel) >= 0.0) & (turn * cross(rel, e - c) >= 0.0)
    ends = np.minimum(np.hypot(*(points - s).transpose(2, 0, 1)), np.hypot(*(points - e).transpose(2, 0, 1)))
    arc = np.where(inside, to_circle, ends)
    line = point_segment_distance(points, s, e)
    return np.where(straight[:, None], line, arc)


def biarc_deviation(curve: CurveFn, nodes: np.ndarray, points: np.ndarray, joints: np.ndarray,
                    b1: np.ndarray, b2: np.ndarray, samples: int = 9) -> np.ndarray:
    """Largest distance from the exact curve to each biarc (one value per interval), mm."""
    theta = interior_theta(nodes[:-1], nodes[1:], samples)
    exact = curve(theta.ravel()).points.reshape(len(nodes) - 1, samples, 2)
    first = point_arc_distance(exact, points[:-1], joints, b1)
    second = point_arc_distance(exact, joints, points[1:], b2)
    return peak_of_samples(np.minimum(first, second))


def _biarc_pass(curve: CurveFn, nodes: np.ndarray, samples: int):
    geo = curve(nodes)
    p, t = geo.points, geo.tangent
    joints, b1, b2 = biarcs(p[:-1], t[:-1], p[1:], t[1:])
    return p, joints, b1, b2, biarc_deviation(curve, nodes, p, joints, b1, b2, samples)


def _redistribute(nodes: np.ndarray, intervals_wanted: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """New nodes with ``intervals_wanted[i]`` intervals (fractional) in place of interval i,
    spread evenly in that count; every edge (breakpoint) stays a node."""
    cumulative = np.concatenate(([0.0], np.cumsum(intervals_wanted)))
    at_edges = np.interp(edges, nodes, cumulative)
    out = [edges[:1]]
    for c0, c1 in pairwise(at_edges):
        count = max(1, int(np.ceil(c1 - c0)))
        out.append(np.interp(np.linspace(c0, c1, count + 1)[1:], cumulative, nodes))
    merged = unique(np.concatenate(out))
    merged[-1] = nodes[-1]
    return merged


def biarc_fit(curve: CurveFn, lo: float, hi: float, tol: float, breakpoints=(), samples: int = 9,
              max_rounds: int = 60) -> ArcPath:
    """Tangent-continuous arcs on [lo, hi] within ``tol`` (mm) of the exact curve."""
    if not tol > 0.0:
        raise CamcadError(f"chord tolerance must be positive, got {tol:g} mm", "--tol-mm", "give e.g. 0.001")
    edges = _pieces(lo, hi, breakpoints)
    nodes = initial_nodes(curve, lo, hi, max(1000.0 * tol, 0.05), breakpoints, pilot=512)
    # biarc error grows like h³: re-place the nodes twice so that each interval's predicted
    # error is PLACEMENT_MARGIN × tol, then bisect the few intervals that still exceed it
    for _ in range(2):
        deviation = _biarc_pass(curve, nodes, samples)[-1]
        ratio = np.maximum(deviation, 1e-300) / (PLACEMENT_MARGIN * tol)
        nodes = _redistribute(nodes, np.cbrt(ratio), edges)
    for _ in range(max_rounds):
        p, joints, b1, b2, deviation = _biarc_pass(curve, nodes, samples)
        bad = deviation > ACCEPT * tol
        if not bad.any():
            vertices = np.empty((2 * len(nodes) - 1, 2))
            vertices[0::2] = p
            vertices[1::2] = joints
            bulges = np.zeros(len(vertices))
            bulges[0:-1:2] = b1
            bulges[1:-1:2] = b2
            return ArcPath(nodes, vertices, bulges, float(deviation.max(initial=0.0)))
        if len(nodes) + bad.sum() > MAX_NODES:
            break
        nodes = np.sort(np.concatenate((nodes, (nodes[:-1][bad] + nodes[1:][bad]) / 2.0)))
    raise CamcadError(f"could not fit tangent arcs within {tol:g} mm (the profile has a cusp or a loop)",
                      "profile", "use a coarser --tol-mm, drop --arcs or fix the undercut")


# --------------------------------------------------------------------------------------------
# Spline
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class SplineData:
    """A clamped B-spline: ``control_points`` (n, 2), ``knots`` (n + degree + 1), ``degree``."""

    control_points: np.ndarray
    knots: np.ndarray
    degree: int = 3


def interpolating_spline(curve: CurveFn, theta: np.ndarray) -> SplineData:
    """Clamped cubic B-spline through the curve at ``theta`` with the exact end derivatives."""
    from scipy.interpolate import make_interp_spline

    geo = curve(theta)
    start = geo.tangent[0] * geo.speed[0]
    end = geo.tangent[-1] * geo.speed[-1]
    spline = make_interp_spline(theta, geo.points, k=3, bc_type=([(1, start)], [(1, end)]))
    return SplineData(np.asarray(spline.c), np.asarray(spline.t), 3)
