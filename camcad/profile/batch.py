"""Many followers on one law at once: ``synthesize``'s checks for a batch of translating roller followers.

A sweep over a follower's dimensions (base radius, roller radius, offset, limits) runs the same law for every
design. Here the law is evaluated once per set of cam angles and every follower's pitch curve, profile,
pressure angle and radius of curvature are arrays over (followers × angles); the extrema of every follower are
refined together by the same zooming grids (``camcad.extrema.zoom_max``, one evaluation per level for all of
them), the profiles' chords are placed and checked together, and each follower ends in the same
``assemble_result`` as ``synthesize``. Every figure is the one ``synthesize`` gives the follower alone: the same
arithmetic in the same order on the same angles (tests/profile/test_profile_batch.py compares them exactly).

Supported: translating roller (or knife-edge) followers without groove or conjugate pair, turning the same way,
with checks only (``ProfileSettings.checks_only``: the pitch curve's chords are not placed). ``supports`` says
whether a batch qualifies; anything else goes through ``synthesize`` one follower at a time.
"""

from __future__ import annotations

import math
from typing import cast

import numpy as np

from camcad.extrema import zoom_from
from camcad.law.law import MotionLaw
from camcad.profile.followers import Follower
from camcad.profile.geometry import CamGeometry, CurveGeometry, turn
from camcad.profile.sampling import (
    ACCEPT,
    MAX_NODES,
    PLACEMENT_MARGIN,
    Polyline,
    density_of,
    interior_theta,
    nodes_from_density,
    peak_of_samples,
    pilot_grid,
    point_segment_distance,
)
from camcad.profile.synth import (
    CurveResult,
    Extremum,
    LawTable,
    ProfileResult,
    ProfileSettings,
    analysis_grid,
    assemble_result,
    gap_and_kink,
    written_curve,
)

#: the objectives of one follower, in this order (``synth._objectives`` for a translating roller)
OBJECTIVES = ("profile:convex", "profile:concave", "pitch:convex", "pitch:concave", "main:max", "main:min",
              "main:rise", "main:return", "main:margin")
MINIMA = {"profile:convex", "profile:concave", "pitch:convex", "pitch:concave", "main:min", "main:margin"}


def supports(followers: list[Follower], settings: ProfileSettings) -> bool:
    """True when ``synthesize_many`` takes these followers (module docstring)."""
    if not followers or not settings.checks_only or settings.arcs or settings.spline or settings.design:
        return False
    first = followers[0]
    return all(f.kind in ("roller", "knife") and not f.groove and not f.has_pair and f.cw == first.cw
               and f.reversible == first.reversible for f in followers)


class _Batch:
    """Per-follower parameters as columns (followers, 1) and the pitch geometry of any angles."""

    def __init__(self, geometries: list[CamGeometry]) -> None:
        self.geometries = geometries
        self.law = geometries[0].law
        followers = [g.follower for g in geometries]
        self.sigma = followers[0].sigma
        self.offset = np.array([f.offset for f in followers])[:, None]
        self.height = np.array([g.height for g in geometries])[:, None]
        self.roller = np.array([f.roller_radius for f in followers])[:, None]
        self.dwell_speed = geometries[0].dwell_speed
        limits = [g.pressure_angle_limit(np.array([1.0, -1.0])) for g in geometries]   # (rise side, return side)
        self.limit_out = np.array([lim[0] for lim in limits])[:, None]
        self.limit_back = np.array([lim[1] for lim in limits])[:, None]

    def pitch(self, theta: np.ndarray, rows: np.ndarray | None = None, points_only: bool = False,
              curvature_only: bool = False) -> dict:
        """The pitch geometry of ``pitch_geometry`` for a translating track: the same operations in the same
        order. θ is 1-D (the same angles for every follower: the law is evaluated once and broadcast) or of
        shape (rows, m) with ``rows`` the follower of each row (all followers when None). ``points_only``:
        the points and normals alone (``pitch_points``); ``curvature_only``: and the speed and radius of
        curvature, without the pressure angle."""
        theta = np.asarray(theta, dtype=float)
        pick = slice(None) if rows is None else rows
        e, height, rr = self.offset[pick], self.height[pick], self.roller[pick]
        shape = (len(e), len(theta)) if theta.ndim == 1 else theta.shape
        motion = getattr(self.law, "motion", None)
        if points_only and motion is not None:     # positions and normals need s and v only
            s, v = motion(theta.ravel())
            a = j = None
        else:
            kin = self.law.kinematics(theta.ravel())
            s, v, a, j = kin.s, kin.v, kin.a, kin.j
        if theta.ndim != 1:
            s, v = s.reshape(shape), v.reshape(shape)
            if a is not None and j is not None:
                a, j = a.reshape(shape), j.reshape(shape)
        sigma = self.sigma
        qx = np.broadcast_to(e, shape)
        qy = np.broadcast_to(height + s - 0.0, shape)
        # t1 = dq − σ J q, t2 = d2q − 2σ J dq − q with q = (e, d + s), dq = (0, v), d2q = (0, a)
        t1x = 0.0 - sigma * -qy
        t1y = np.broadcast_to(v - sigma * qx, shape)
        speed = np.hypot(t1x, t1y)
        tx, ty = t1x / speed, t1y / speed
        nx, ny = sigma * -ty, sigma * tx
        found = {"theta": np.broadcast_to(theta, shape), "qx": qx, "qy": qy, "tx": tx, "ty": ty, "nx": nx,
                 "ny": ny, "speed": speed, "roller": rr, "pick": pick}
        if points_only:
            return found
        assert a is not None and j is not None   # left None only when ``points_only``
        t2x = 0.0 - 2.0 * sigma * -v - qx
        t2y = a - 2.0 * sigma * np.zeros(np.shape(a)) - qy
        bend = t1x * t2y - t1y * t2x
        with np.errstate(divide="ignore", invalid="ignore"):
            rho = np.where(bend != 0.0, -sigma * speed**3 / bend, np.inf)
        if curvature_only:
            found.update(rho=rho)
            return found
        up = np.where(height - 0.0 >= 0.0, 1.0, -1.0) * np.ones(shape)
        wx = np.zeros(shape)
        phi = sigma * np.arctan2(wx * ny - up * nx, wx * nx + up * ny)
        outward = 0.0 * wx + v * up
        found.update(s=np.broadcast_to(s, shape), v=np.broadcast_to(v, shape), a=np.broadcast_to(a, shape),
                     j=np.broadcast_to(j, shape), rho=rho, phi=phi, outward=outward)
        return found

    def limit(self, outward: np.ndarray, pick) -> np.ndarray:
        if self.geometries[0].follower.reversible:
            return np.broadcast_to(self.limit_out[pick], outward.shape)
        return np.where(outward < -self.dwell_speed, self.limit_back[pick], self.limit_out[pick])

    def objectives(self, p: dict, stacked: bool = True):
        """Every objective (``OBJECTIVES``, as maxima: a minimum negated) at the sampled angles, shape
        (objectives, *θ shape) (a list of them when not ``stacked``)."""
        rho, phi, outward = p["rho"], p["phi"], p["outward"]
        profile_rho = rho - p["roller"]
        convex = lambda r: np.where(r > 0.0, r, np.inf)        # noqa: E731 - synth._convex
        concave = lambda r: np.where(r < 0.0, -r, np.inf)      # noqa: E731 - synth._concave
        rise = np.where(outward > self.dwell_speed, np.abs(phi), -np.inf)
        back = np.where(outward < -self.dwell_speed, np.abs(phi), -np.inf)
        limit = self.limit(outward, p["pick"])
        margin = np.where(np.isnan(limit), np.inf, limit - np.abs(phi))
        found = [-convex(profile_rho), -concave(profile_rho), -convex(rho), -concave(rho), phi, -phi, rise, back,
                 -margin]
        return np.stack(found) if stacked else found

    def profile_points(self, p: dict) -> np.ndarray:
        """Profile points in the cam's frame, shape (*θ shape, 2): P − Rr n (``parallel_curve``), each
        component turned as ``geometry.turn`` turns it."""
        c, s = np.cos(-self.sigma * p["theta"]), np.sin(-self.sigma * p["theta"])
        rr = p["roller"]
        out = np.empty(np.shape(p["qx"]) + (2,))
        out[..., 0] = (c * p["qx"] - s * p["qy"]) - rr * (c * p["nx"] - s * p["ny"])
        out[..., 1] = (s * p["qx"] + c * p["qy"]) - rr * (s * p["nx"] + c * p["ny"])
        return out


def synthesize_many(law: MotionLaw, followers: list[Follower], settings: ProfileSettings,
                    name: str | None = None) -> list[ProfileResult | None]:
    """``synthesize(law, f, settings)`` for every follower f, as one batch (module docstring).

    Parameters
    ----------
    law : MotionLaw
        The law all followers share (θ in rad, s in mm).
    followers : list of Follower
        Translating roller or knife-edge followers (``supports``).
    settings : ProfileSettings
        With ``checks_only`` (no arcs, spline or base-radius design).
    name : str, optional
        The designs' name.

    Returns
    -------
    list of ProfileResult or None
        One per follower, as ``synthesize`` gives it (curves in mm, angles in rad); None for a follower whose
        profile no chords within the tolerance follow (a cusp or a loop: ``synthesize`` refuses it and says why).

    Raises
    ------
    ValueError
        Followers or settings the batch does not take (``supports``).

    References
    ----------
    R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 7–8 (as ``synthesize``).

    Examples
    --------
    Three base radii (mm) of the default cam: the peak pressure angle on the rise falls as the cam grows, and
    each is the one ``synthesize`` finds for that follower alone:

    >>> from dataclasses import replace
    >>> import camcad
    >>> from camcad.profile import default_design
    >>> _, law, follower = default_design()
    >>> settings = camcad.ProfileSettings(plots=False, design=False, checks_only=True)
    >>> followers = [replace(follower, base_radius=rb) for rb in (40.0, 50.0, 60.0)]
    >>> results = camcad.synthesize_many(law, followers, settings)
    >>> [round(math.degrees(r.pressure_angle.rise_max.value), 4) for r in results] == [
    ...     round(math.degrees(camcad.synthesize(law, f, settings).pressure_angle.rise_max.value), 4)
    ...     for f in followers]
    True
    >>> results[0].pressure_angle.rise_max.value > results[2].pressure_angle.rise_max.value
    True
    """
    settings = settings.validate()
    if not supports(followers, settings):
        raise ValueError("synthesize_many takes translating roller followers with checks only; use synthesize")
    # blocks of followers: the arrays of a block (followers × angles) stay in the processor's cache
    return [result for first in range(0, len(followers), BLOCK)
            for result in _block(law, followers[first:first + BLOCK], settings, name)]


#: followers computed together (a block's arrays of followers × 3,600 angles stay in cache)
BLOCK = 256


def _block(law: MotionLaw, followers: list[Follower], settings: ProfileSettings, name: str | None
           ) -> list[ProfileResult | None]:
    geometries = [CamGeometry(law, f) for f in followers]
    batch = _Batch(geometries)
    count = len(geometries)
    analysis = analysis_grid(geometries[0], settings.analysis_step_deg)
    first = batch.pitch(analysis)
    # each objective's best sample on the analysis grid (``zoom_max``'s first step), objective by objective
    best, highest = [], []
    for sampled in batch.objectives(first, stacked=False):
        sampled = np.where(np.isfinite(sampled), sampled, -np.inf)
        index = np.argmax(sampled, axis=1)
        best.append(index)
        highest.append(sampled[np.arange(count), index])
    best_all, peak_all = np.concatenate(best), np.concatenate(highest)
    active = np.flatnonzero(np.isfinite(peak_all))      # a row without a finite value has no extremum
    objective_of = active // count
    follower_of = active % count

    def evaluate(u: np.ndarray) -> np.ndarray:
        u = np.asarray(u, dtype=float)
        theta = u.reshape(len(active), -1)
        p = batch.pitch(theta, follower_of)
        every = batch.objectives(p)                        # (objectives, rows, m)
        return every[objective_of, np.arange(len(active))].reshape(u.shape)

    peak, at = zoom_from(evaluate, analysis, best_all[active], peak_all[active])
    extrema: list[dict[str, Extremum | None]] = [{key: None for key in OBJECTIVES} for _ in range(count)]
    for row, (k, i) in enumerate(zip(objective_of.tolist(), follower_of.tolist())):
        key = OBJECTIVES[k]
        extrema[i][key] = Extremum(float(-peak[row]) if key in MINIMA else float(peak[row]), float(at[row]))
    cycle = float(law.cycle)
    breaks = geometries[0].breakpoints()
    polylines = _chords(batch, 0.0, cycle, settings.tol_mm, breaks[breaks <= cycle])
    ends = _ends(batch, cycle)
    table = _tables(batch, settings.csv_step_deg)
    results: list[ProfileResult | None] = []
    for i, geometry in enumerate(geometries):
        one = polylines[i]
        if one is None:
            results.append(None)
            continue
        notes: list[str] = []
        end = ends[i]
        gap, kink = gap_and_kink(end["profile"], geometry)
        pitch_gap, _ = gap_and_kink(end["pitch"], geometry)
        empty = Polyline(np.empty(0), np.empty((0, 2)), 0.0)
        curves = {"profile": written_curve("profile", one, geometry.profile, geometry, settings, gap,
                                           extrema[i], False, False, notes),
                  "pitch": CurveResult("pitch", empty, None, None, extrema[i]["pitch:convex"],
                                       extrema[i]["pitch:concave"], None, pitch_gap, pitch_gap <= settings.tol_mm)}
        results.append(assemble_result(name or settings.name, law, geometry.follower, settings, geometry, curves,
                                       extrema[i], kink, table[i], None, notes))
    return results


def _profile_geometry(batch: _Batch, p: dict, points: bool = True):
    """(points or None, speed, rho) of the profile (``parallel_curve``) from the pitch geometry ``p``."""
    rho = p["rho"]
    rr = p["roller"]
    with np.errstate(divide="ignore", invalid="ignore"):
        stretch = np.where(np.isfinite(rho), 1.0 - rr / rho, 1.0)
    return batch.profile_points(p) if points else None, p["speed"] * np.abs(stretch), rho - rr


def _chords(batch: _Batch, lo: float, hi: float, tol: float, breakpoints: np.ndarray, samples: int = 7,
            max_rounds: int = 60) -> list[Polyline | None]:
    """``chord_nodes`` of every follower's profile (``chord_nodes_joint``'s steps, the followers together);
    None for a follower whose chords do not meet the tolerance (where ``chord_nodes_joint`` raises)."""
    count = len(batch.geometries)
    pilot = pilot_grid(lo, hi, breakpoints, 2048)
    grid = np.concatenate(pilot)
    p = batch.pitch(grid, curvature_only=True)
    _, speed, rho = _profile_geometry(batch, p, points=False)
    nodes = []
    for i in range(count):
        geo = CurveGeometry(grid, np.empty((0, 2)), np.empty((0, 2)), speed[i], rho[i])
        nodes.append(nodes_from_density(pilot, _density(geo, PLACEMENT_MARGIN * tol), lo, hi, tol))
    # (nodes_from_density raises CamcadError, as chord_nodes_joint does, when the tolerance needs too many points)
    done: dict[int, Polyline | None] = {}
    for _ in range(max_rounds):
        pending = [i for i in range(count) if i not in done]
        if not pending:
            break
        parts, owner, spans, start = [], [], [], 0
        for i in pending:                                  # each follower's nodes, then its interior points
            inner = interior_theta(nodes[i][:-1], nodes[i][1:], samples).ravel()
            parts += [nodes[i], inner]
            size = len(nodes[i]) + len(inner)
            owner.append(np.full(size, i))
            spans.append(start)
            start += size
        theta = np.concatenate(parts)[:, None]
        points = batch.profile_points(batch.pitch(theta, np.concatenate(owner), points_only=True))[:, 0]
        for row, i in enumerate(pending):
            n = len(nodes[i])
            ends = points[spans[row]:spans[row] + n]
            exact = points[spans[row] + n:spans[row] + n + samples * (n - 1)].reshape(n - 1, samples, 2)
            deviation = peak_of_samples(point_segment_distance(exact, ends[:-1, None, :], ends[1:, None, :]))
            bad = deviation > ACCEPT * tol
            if not bad.any():
                done[i] = Polyline(nodes[i], ends, float(deviation.max(initial=0.0)))
            elif n + bad.sum() > MAX_NODES:
                done[i] = None
            else:
                nodes[i] = np.sort(np.concatenate((nodes[i], (nodes[i][:-1][bad] + nodes[i][1:][bad]) / 2.0)))
    return [done.get(i) for i in range(count)]


def _density(geo: CurveGeometry, tol: float) -> np.ndarray:
    return density_of(geo, tol)


def _ends(batch: _Batch, cycle: float) -> list[dict[str, CurveGeometry]]:
    """Every follower's profile and pitch curve at θ = 0 and at the cycle's end (points and tangents)."""
    count = len(batch.geometries)
    theta = np.broadcast_to(np.array([0.0, cycle]), (count, 2))
    p = batch.pitch(np.array([0.0, cycle]))
    c, s = np.cos(-batch.sigma * p["theta"]), np.sin(-batch.sigma * p["theta"])
    tangent = turn(np.stack((p["tx"], p["ty"]), axis=-1), c, s)
    points, speed, rho = _profile_geometry(batch, p)
    pitch_points = turn(np.stack((p["qx"], p["qy"]), axis=-1), c, s)
    with np.errstate(divide="ignore", invalid="ignore"):
        stretch = np.where(np.isfinite(p["rho"]), 1.0 - p["roller"] / p["rho"], 1.0)
    direction = np.where(stretch >= 0.0, 1.0, -1.0)[..., None]
    found = []
    for i in range(count):
        found.append({"profile": CurveGeometry(theta[i], points[i], tangent[i] * direction[i], speed[i], rho[i]),
                      "pitch": CurveGeometry(theta[i], pitch_points[i], tangent[i], p["speed"][i], p["rho"][i])})
    return found


def _tables(batch: _Batch, step_deg: float) -> list[LawTable]:
    """``law_table`` of every follower."""
    count = len(batch.geometries)
    steps = int(round(360.0 / step_deg))  # noqa: RUF046 - round() of a numpy float is a float on numpy < 2
    theta = np.linspace(0.0, 2.0 * math.pi, steps + 1)
    p = batch.pitch(theta)
    limit = batch.limit(p["outward"], slice(None))
    return [LawTable(theta, p["s"][i], p["v"][i], p["a"][i], p["j"][i], p["phi"][i], np.array(limit[i]), p["rho"][i],
                     p["rho"][i] - cast(float, batch.roller[i, 0])) for i in range(count)]
