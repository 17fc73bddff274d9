"""A motion law designed from scratch: a sequence of segments, each with its interval, shape and end values.

A segment runs from the previous segment's end (the first from 0°, at 0 mm) to ``to_deg``, with one of
the shapes ``dwell``, ``constant_velocity`` or a law of the VDI 2143 catalogue (``camcad.law.vdi``), and
ends at ``to_mm``. Its other end values follow the shape's class:

- a shape *takes* from the previous segment the start values it has room for (poly5 takes v and a,
  poly7 v, a and j, the lobe laws v) and *sets* the others itself (a dwell rests, a constant velocity
  moves at (to_mm − s0)/β, a lobe law starts at zero acceleration);
- the end values it may *state* (``v_end`` for poly3/5/7 and the lobe laws, ``a_end`` for poly5/7,
  ``j_end`` for poly7) are a number (mm/deg, mm/deg², mm/deg³), ``"match"`` (the value the next segment
  sets at its start), or left out: then the next segment's own start value where it sets one, else rest.

The boundary values are solved segment by segment, so s, v and the values each shape takes are
continuous by construction (exactly, to round-off). A joint where a shape sets a value that differs from
the previous end is reported in the continuity class of that joint (C3: s, v, a, j continuous; C2: the
jerk jumps; C1: the acceleration jumps). A velocity that would jump, or a cycle that does not close, is
refused with one line naming the segment. The last segment must end at the cycle (360° unless stated) and
at the first segment's start (0 mm, and its start velocity).

Every segment is a phase of the law (``SegmentLaw.phases``): a rise where it ends higher than it
started, a return where lower, a dwell; each phase states its end position and velocity, so the balance
check and ``fix`` hold a drawing of the law to them. Changing a segment's angle (``retimed``) solves the
law again with the same stated values: a segment's least angle keeps its end values.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace
from itertools import pairwise
from typing import Any

import numpy as np

from camcad.errors import CamcadError
from camcad.law.law import Kinematics, Phase, wrap, wrap_angle
from camcad.law.pieces import Piece, evaluate_chain
from camcad.law.standard import shape_named
from camcad.law.vdi import ALIASES, CATALOGUE, Bounds, FixedLaw

#: the shapes a segment may have besides the catalogue's
OWN_SHAPES = ("dwell", "constant_velocity")
#: a joint value counts as continuous within this fraction of the law's largest value of that order
CONTINUITY_TOLERANCE = 1e-9
#: deg -> rad factor for an end value of order k (mm/deg^k -> mm/rad^k)
DEG = 180.0 / math.pi
ORDER_KEYS = {"v": ("v_end", 1), "a": ("a_end", 2), "j": ("j_end", 3)}
UNITS = {"v": "mm/deg", "a": "mm/deg^2", "j": "mm/deg^3"}


@dataclass(frozen=True)
class SegmentSpec:
    """One segment as the user states it: its end angle, shape, end position and end values.

    Parameters
    ----------
    to_deg : float
        The cam angle where the segment ends (deg); it starts where the previous one ends (the first at 0).
    shape : str
        "dwell", "constant_velocity", a catalogue law or alias (``camcad.law.vdi``), or a rest-to-rest shape of
        ``camcad.law.standard`` ("scca:b:c:d").
    to_mm : float, optional
        The position at the segment's end (mm); a dwell keeps its start.
    v_end, a_end, j_end : float or str, optional
        The velocity (mm/deg), acceleration (mm/deg²), jerk (mm/deg³) at the end, where the shape has room for
        it; "match": the value the next segment sets at its start; None: that value where the next segment
        sets one, else rest.
    param : float, optional
        The shape's parameter: the inflection point λ of a lobe law (a fraction of the segment, 0 < λ < 1).

    Examples
    --------
    >>> SegmentSpec(140, "poly5", 12.0, v_end="match").shape
    'poly5'
    """

    to_deg: float
    shape: str
    to_mm: float | None = None
    v_end: float | str | None = None
    a_end: float | str | None = None
    j_end: float | str | None = None
    param: float | None = None

    def stated(self, order: str):
        return getattr(self, ORDER_KEYS[order][0])


@dataclass(frozen=True)
class _Shape:
    """What the solver needs of a segment's shape: which start values it takes, which end values it states,
    and how to build it."""

    name: str
    law: Any             # LobeLaw | PolyLaw | FixedLaw; None for dwell and constant velocity
    takes: frozenset
    stated: frozenset
    reversal: str = ""

    def demand(self, width: float, s0: float, s1: float, v0: float, param, start_reversal: bool) -> dict:
        """The start values the shape sets itself."""
        if self.name == "dwell":
            return {"v": 0.0, "a": 0.0, "j": 0.0}
        if self.name == "constant_velocity":
            return {"v": (s1 - s0) / width, "a": 0.0, "j": 0.0}
        found = self.law.demand(width, s0, s1, v0, param, start_reversal)
        return {k: v for k, v in found.items() if k not in self.takes}

    def build(self, start: float, width: float, bounds: Bounds, param, start_reversal: bool) -> tuple:
        if self.name == "dwell":
            return (Piece(start, start + width, bounds.s0, 0.0),)
        if self.name == "constant_velocity":
            return (Piece(start, start + width, bounds.s0, (bounds.s1 - bounds.s0) / width),)
        return self.law.build(start, width, bounds, param, start_reversal)


@functools.cache
def _shape(name: str) -> _Shape:
    """The solver's view of a shape name; KeyError with the names when it is unknown."""
    if name in OWN_SHAPES:
        return _Shape(name, None, frozenset(), frozenset())
    key = ALIASES.get(name, name)
    if key in CATALOGUE:
        law = CATALOGUE[key]
        return _Shape(key, law, frozenset(law.takes), frozenset(law.stated), getattr(law, "reversal", ""))
    head = name.split(":")[0]
    if head in CATALOGUE or head in ALIASES:
        raise KeyError(f"write the parameter of {head} as lambda = ..., not {name!r}")
    try:
        standard = shape_named(name)
    except KeyError:
        names = ", ".join((*OWN_SHAPES, *sorted(CATALOGUE), *sorted(ALIASES), "scca:b:c:d"))
        raise KeyError(f"unknown segment shape {name!r}; shapes: {names}") from None
    return _Shape(name, FixedLaw(name, standard), frozenset(), frozenset())


def shape_names() -> tuple[str, ...]:
    """Every shape name a segment accepts (``scca:b:c:d`` stands for Norton's SCCA members)."""
    return (*OWN_SHAPES, *sorted(CATALOGUE), *sorted(ALIASES), "scca:b:c:d")


@dataclass(frozen=True)
class Joint:
    """The joint between two segments (or the cycle's end and start): where, and what jumps there.

    ``jumps``: {"s", "v", "a", "j"} right − left (mm, mm/rad, mm/rad², mm/rad³); ``continuous``: the
    orders that are continuous within ``CONTINUITY_TOLERANCE``; ``class_`` "C3", "C2" or "C1".
    """

    at_deg: float
    before: int
    after: int
    jumps: dict
    class_: str

    def describe(self) -> str:
        words = {"C3": "s, v, a, j continuous", "C2": "s, v, a continuous; the jerk jumps",
                 "C1": "s, v continuous; the acceleration jumps"}[self.class_]
        return f"{self.at_deg:.6g} deg (segment {self.before} -> {self.after}): {self.class_}, {words}"

    def to_dict(self) -> dict:
        return {"at_deg": self.at_deg, "segments": [self.before, self.after], "class": self.class_,
                "jumps": {"s_mm": self.jumps["s"], "v_mm_per_deg": self.jumps["v"] / DEG,
                          "a_mm_per_deg2": self.jumps["a"] / DEG**2, "j_mm_per_deg3": self.jumps["j"] / DEG**3}}


@dataclass(frozen=True)
class Segment:
    """A solved segment: its interval (rad), shape, parameter, boundary values and pieces."""

    number: int
    spec: SegmentSpec
    start: float
    end: float
    shape: str
    kind: str
    start_values: tuple[float, float, float, float]    # s, v, a, j (mm, mm/rad, mm/rad², mm/rad³)
    end_values: tuple[float, float, float, float]
    pieces: tuple
    start_reversal: bool = False
    start_deg: float = 0.0
    end_deg: float = 0.0
    target: tuple[float, float] = (0.0, 0.0)            # the stated end position (mm) and velocity (mm/rad)

    @property
    def width(self) -> float:
        return self.end - self.start

    def motion_class(self, scale_v: float, scale_a: float) -> str:
        """The VDI 2143 class of the transition, e.g. "R-G": R rest, G constant velocity, U reversal, B motion."""
        def state(values) -> str:
            moving = abs(values[1]) > scale_v
            accelerating = abs(values[2]) > scale_a
            return {(False, False): "R", (True, False): "G", (False, True): "U", (True, True): "B"}[
                (moving, accelerating)]

        return f"{state(self.start_values)}-{state(self.end_values)}"

    def label(self) -> str:
        return f"segment {self.number} ({self.shape} {self.start_deg:.6g}..{self.end_deg:.6g} deg)"


@dataclass(frozen=True)
class SegmentLaw:
    """A law made of solved segments (``solve_segments``): a ``MotionLaw`` with exact s, v, a, j everywhere.

    Every segment is a phase (rise, return or dwell) that states its end position and velocity. θ in rad;
    s mm (or rad of swing for an oscillating follower's law), v mm/rad, a mm/rad², j mm/rad³.
    """

    segments: tuple[Segment, ...]
    cycle: float
    specs: tuple[SegmentSpec, ...]
    joints: tuple[Joint, ...] = ()
    where: str = ""
    _pieces: tuple = field(default=(), repr=False, compare=False)

    @property
    def phases(self) -> tuple[Phase, ...]:
        return tuple(Phase(seg.kind, seg.start, seg.end, seg.target[0], seg.target[1] if seg.kind != "dwell" else 0.0)
                     for seg in self.segments)

    @property
    def lift(self) -> float:
        """The largest displacement minus the smallest (mm), over the segments' ends and extremes."""
        theta = np.linspace(0.0, self.cycle, 4097)
        s = self.kinematics(theta).s
        return float(np.ptp(np.concatenate((s, [seg.end_values[0] for seg in self.segments]))))

    @functools.cached_property
    def _chain(self) -> tuple[tuple, np.ndarray]:
        pieces = tuple(p for seg in self.segments for p in seg.pieces if p.end > p.start)
        return pieces, np.array([p.start for p in pieces])

    def kinematics(self, theta) -> Kinematics:
        theta = np.asarray(theta, dtype=float)
        t = wrap(theta, self.cycle)
        pieces, starts = self._chain
        values = [evaluate_chain(pieces, starts, t, order) for order in range(4)]
        return Kinematics(theta=theta, s=values[0], v=values[1], a=values[2], j=values[3])

    def _piece_at(self, theta: float):
        t = wrap_angle(float(theta), self.cycle)
        pieces, starts = self._chain
        k = min(max(int(np.searchsorted(starts, t, side="right")) - 1, 0), len(pieces) - 1)
        return pieces[k], np.array([t])

    def acceleration_at(self, theta: float) -> float:
        """a(θ) (mm/rad²) at one cam angle θ (rad), without ``kinematics``'s array work (ODE right-hand sides)."""
        piece, t = self._piece_at(theta)
        return float(piece.evaluate(t, 2)[0])

    def motion_at(self, theta: float) -> tuple[float, float]:
        """(s, v) (mm, mm/rad) at one cam angle θ (rad)."""
        piece, t = self._piece_at(theta)
        return float(piece.evaluate(t, 0)[0]), float(piece.evaluate(t, 1)[0])

    def breakpoints(self) -> np.ndarray:
        """θ (rad) where s, v, a or j may be non-smooth: the segments' ends and the joints of their pieces."""
        pieces, _ = self._chain
        points = {0.0, float(self.cycle)}
        for p in pieces:
            points.update((float(p.start), float(p.end)))
            points.update(float(x) for x in getattr(p, "inner_breakpoints", lambda: ())())
        return np.array(sorted(points))

    def describe(self) -> str:
        """One line, e.g. "dwell 0-60, poly5 60-140 to 12 mm, constant_velocity 140-200 to 30 mm" (deg, mm)."""
        parts = []
        for seg in self.segments:
            text = f"{seg.shape} {seg.start_deg:.6g}-{seg.end_deg:.6g}"
            if seg.kind != "dwell":
                text += f" to {seg.target[0]:.6g} mm"
            parts.append(text)
        return ", ".join(parts)

    def retimed(self, phases: tuple[Phase, ...], where: str = "") -> SegmentLaw:
        """The law solved again with new segment angles (one phase per segment, same kinds, covering the cycle):
        every segment keeps its stated end position and values; a constant velocity takes its new speed."""
        if len(phases) != len(self.segments):
            raise CamcadError(f"{len(phases)} phases for a law of {len(self.segments)} segments", where or self.where,
                              "give one phase per segment")
        specs = tuple(replace(spec, to_deg=math.degrees(p.end)) for spec, p in zip(self.specs, phases))
        return solve_segments(specs, math.degrees(self.cycle), where or self.where)

    def to_dict(self) -> dict:
        """The segments and joints in deg and mm (velocities per deg), for reports."""
        scale = self._scales()
        rows = []
        for seg in self.segments:
            # values within the continuity tolerance of 0 are 0 (the solve's round-off, not a value)
            s0, v0, a0, _ = (x if abs(x) > tol else 0.0 for x, tol in zip(seg.start_values, scale))
            s1, v1, a1, _ = (x if abs(x) > tol else 0.0 for x, tol in zip(seg.end_values, scale))
            kin = self.kinematics(np.linspace(seg.start, seg.end, 513))
            rows.append({"segment": seg.number, "shape": seg.shape, "kind": seg.kind,
                         "from_deg": seg.start_deg, "to_deg": seg.end_deg,
                         "lambda": seg.spec.param, "class": seg.motion_class(scale[1], scale[2]),
                         "s_start_mm": s0, "s_end_mm": s1, "v_start_mm_per_deg": v0 / DEG,
                         "v_end_mm_per_deg": v1 / DEG, "a_start_mm_per_deg2": a0 / DEG**2,
                         "a_end_mm_per_deg2": a1 / DEG**2,
                         "v_max_mm_per_deg": float(np.max(np.abs(kin.v))) / DEG,
                         "a_max_mm_per_deg2": float(np.max(np.abs(kin.a))) / DEG**2})
        return {"segments": rows, "joints": [j.to_dict() for j in self.joints]}

    def _scales(self) -> tuple[float, float, float, float]:
        return _scales(self.segments, self.cycle)


def _scales(segments, cycle: float) -> tuple[float, float, float, float]:
    """The smallest jump of s, v, a, j that counts (mm, mm/rad, mm/rad², mm/rad³): ``CONTINUITY_TOLERANCE`` of
    the law's largest value of that order (of the lift for s)."""
    grids = []
    for seg in segments:
        for piece in seg.pieces:
            if piece.end > piece.start:
                grids.append((piece, np.linspace(piece.start, piece.end, 65)))
    peaks = []
    for order in range(4):
        values = [np.max(np.abs(p.evaluate(g, order))) for p, g in grids]
        peaks.append(float(max(values)) if values else 0.0)
    lift = max(peaks[0], 1e-300)
    width = min(seg.width for seg in segments)
    floors = [lift, lift / width, lift / width**2, lift / width**3]
    low = [CONTINUITY_TOLERANCE * max(p, 1e-12 * f) for p, f in zip(peaks, floors)]
    return low[0], low[1], low[2], low[3]


# --------------------------------------------------------------------------------------------
# Solving the boundary values
# --------------------------------------------------------------------------------------------

def _refuse(what: str, where: str, fix: str) -> None:
    raise CamcadError(what, where, fix)


def _shape_of(spec: SegmentSpec, number: int, where: str) -> _Shape:
    try:
        shape = _shape(spec.shape)
    except KeyError as err:
        raise CamcadError(str(err.args[0]), f"{where} segment {number}", "pick one of the shapes listed") from None
    problem = shape.law.check_param(spec.param) if shape.law is not None else (
        None if spec.param is None else f"{spec.shape} has no parameter")
    if problem:
        raise CamcadError(problem, f"{where} segment {number}", "give 0 < lambda < 1, or leave it out")
    for order, (key, _) in ORDER_KEYS.items():
        if spec.stated(order) is not None and order not in shape.stated:
            allowed = ", ".join(ORDER_KEYS[o][0] for o in sorted(shape.stated)) or "no end value"
            raise CamcadError(f"{key} is not a free end value of {shape.name} (it states {allowed})",
                              f"{where} segment {number}", f"drop {key}, or use poly5 or poly7 for the transition")
        value = spec.stated(order)
        if isinstance(value, str) and value != "match":
            raise CamcadError(f"{key} = {value!r} is neither a number nor \"match\"", f"{where} segment {number}",
                              f'write {key} = "match" or a number in {UNITS[order]}')
        if isinstance(value, float) and not math.isfinite(value):
            raise CamcadError(f"{key} = {value} is not finite", f"{where} segment {number}", "give a finite number")
    return shape


def solve_segments(specs, cycle_deg: float = 360.0, where: str = "segments") -> SegmentLaw:
    """Solve a law given as segments: every boundary value, each segment's pieces, the joints' continuity.

    Parameters
    ----------
    specs : sequence of SegmentSpec
        The segments in order: each ends at ``to_deg`` (deg), the first starts at 0 deg and 0 mm. Shapes:
        "dwell", "constant_velocity", the VDI 2143 catalogue (``camcad.law.vdi``: inclined_sine,
        modified_sine, modified_trapezoid, constant_acceleration, harmonic_combination, poly3, poly5,
        poly7, harmonic, double_harmonic; cycloidal, poly345, poly4567 as aliases) or "scca:b:c:d".
        ``to_mm`` is the position at the segment's end (mm; a dwell keeps its start).
    cycle_deg : float
        The cycle the last segment ends at (deg).
    where : str
        What to name in an error message (the scene section or option).

    Returns
    -------
    SegmentLaw
        A ``MotionLaw`` (θ rad; s mm, v mm/rad, a mm/rad², j mm/rad³) with one phase per segment and the
        continuity class of every joint (``joints``).

    References
    ----------
    VDI 2143 Blatt 1, Bewegungsgesetze für Kurvengetriebe (VDI, 1980): the motion tasks and the laws.

    Raises
    ------
    CamcadError
        One line naming the segment: an unknown shape or key, angles that do not increase to the cycle,
        a missing end position, a velocity that would jump, a law that does not close.

    Examples
    --------
    The issue's example: a dwell, a poly5 from rest into a constant velocity, the constant velocity, a
    poly5 back to rest, a return and a dwell. The constant velocity is exactly (30 − 12)/60 mm/deg:

    >>> import math
    >>> law = solve_segments([SegmentSpec(60, "dwell"), SegmentSpec(140, "poly5", 12.0, v_end="match"),
    ...                       SegmentSpec(200, "constant_velocity", 30.0), SegmentSpec(240, "poly5", 36.0),
    ...                       SegmentSpec(330, "modified_sine", 0.0), SegmentSpec(360, "dwell")])
    >>> k = law.kinematics([math.radians(170.0)])
    >>> round(float(k.v[0]) * math.pi / 180.0, 12), round(float(k.a[0]), 12)
    (0.3, 0.0)
    >>> [j.class_ for j in law.joints]     # the jerk jumps where a motion starts or ends; the two dwells meet smoothly
    ['C2', 'C2', 'C2', 'C2', 'C2', 'C3']
    >>> [p.kind for p in law.phases]
    ['dwell', 'rise', 'rise', 'rise', 'return', 'dwell']
    """
    specs = tuple(specs)
    if not specs:
        raise CamcadError("the law has no segments", where, 'add segments, e.g. "0:60:dwell,60:180:poly5:20,..."')
    if not (math.isfinite(cycle_deg) and 0.0 < cycle_deg <= 360.0):
        raise CamcadError(f"cycle {cycle_deg:g} deg is not in (0, 360]", where, "give the working angle in degrees")
    shapes = [_shape_of(spec, k + 1, where) for k, spec in enumerate(specs)]
    ends = [float(spec.to_deg) for spec in specs]
    previous = 0.0
    for k, end in enumerate(ends):
        if not math.isfinite(end) or not end > previous:
            raise CamcadError(f"segment {k + 1} ends at {end:g} deg, not after its start {previous:g} deg",
                              f"{where} segment {k + 1}", "give each segment a to_deg larger than the previous one")
        previous = end
    tol_deg = 1e-9 * cycle_deg
    if abs(ends[-1] - cycle_deg) > tol_deg:
        raise CamcadError(f"the last segment ends at {ends[-1]:g} deg, not at the cycle's end {cycle_deg:g} deg",
                          f"{where} segment {len(specs)}", f"make the last to_deg {cycle_deg:g}")
    ends[-1] = cycle_deg
    starts = [0.0, *ends[:-1]]
    widths = [math.radians(e - s) for s, e in zip(starts, ends)]
    # the end positions
    positions = []
    level = 0.0
    for k, (spec, shape) in enumerate(zip(specs, shapes)):
        if shape.name == "dwell":
            if spec.to_mm is not None and abs(spec.to_mm - level) > 1e-9 * max(1.0, abs(level)):
                raise CamcadError(f"segment {k + 1} is a dwell at {level:g} mm but its to_mm is {spec.to_mm:g}",
                                  f"{where} segment {k + 1}", "drop to_mm of a dwell, or make the segment a motion")
            positions.append(level)
            continue
        if spec.to_mm is None:
            raise CamcadError(f"segment {k + 1} ({spec.shape}) does not say where it ends", f"{where} segment {k + 1}",
                              "add to_mm = the position at its end (mm)")
        if not math.isfinite(spec.to_mm) or abs(spec.to_mm) > 1e6:
            raise CamcadError(f"segment {k + 1} ends at to_mm = {spec.to_mm:g}", f"{where} segment {k + 1}",
                              "give a finite position in mm")
        level = float(spec.to_mm)
        positions.append(level)
    if abs(positions[-1]) > 1e-9 * max(1.0, max(abs(p) for p in positions)):
        raise CamcadError(f"the law ends at {positions[-1]:g} mm but the cycle starts at 0 mm, so the cam would not "
                          "close", f"{where} segment {len(specs)}", "make the last motion end at to_mm = 0")
    positions[-1] = 0.0
    s_start = [0.0, *positions[:-1]]

    def demand_of(k: int, v0: float, start_reversal: bool) -> dict:
        return shapes[k].demand(widths[k], s_start[k], positions[k], v0, specs[k].param, start_reversal)

    # the first segment starts at rest unless it sets its own start (a constant velocity)
    first = demand_of(0, 0.0, False)
    current = (0.0, first.get("v", 0.0), first.get("a", 0.0), first.get("j", 0.0))
    segments: list[Segment] = []
    for k, (spec, shape) in enumerate(zip(specs, shapes)):
        number = k + 1
        theta0 = math.radians(starts[k])
        width = widths[k]
        s0, v_in, a_in, j_in = current
        start_reversal = bool(shape.reversal) and k > 0 and abs(a_in) > 0.0 and abs(v_in) <= _small_v(widths, positions)
        own = demand_of(k, v_in, start_reversal)
        if k > 0 and "v" in own and abs(own["v"] - v_in) > _small_v(widths, positions):
            prev = segments[-1]
            _velocity_jump(prev, spec, shape, own["v"], v_in, number, where)
        v0 = v_in if "v" in shape.takes else own.get("v", 0.0)
        a0 = a_in if "a" in shape.takes else own.get("a", 0.0)
        j0 = j_in if "j" in shape.takes else own.get("j", 0.0)
        end_values = {}
        nxt = (k + 1) % len(specs)
        for order in ("v", "a", "j"):
            if order not in shape.stated:
                continue
            raw = spec.stated(order)
            key = ORDER_KEYS[order][0]
            if isinstance(raw, (int, float)) and not isinstance(raw, bool):
                end_values[order] = float(raw) * DEG ** ORDER_KEYS[order][1]
                continue
            v_next = end_values.get("v", 0.0)
            next_reversal = bool(shapes[nxt].reversal) and abs(v_next) <= _small_v(widths, positions) and (
                order != "v") and end_values.get("a", 0.0) != 0.0
            demanded = _next_demand(shapes, widths, s_start, positions, specs, nxt, v_next, next_reversal)
            if raw == "match":
                if order not in demanded:
                    raise CamcadError(f"{key} = \"match\" but segment {nxt + 1} ({specs[nxt].shape}) takes its start "
                                      f"{order} from this one", f"{where} segment {number}",
                                      f"give {key} a value in {UNITS[order]}")
                end_values[order] = demanded[order]
            else:
                end_values[order] = demanded.get(order, 0.0)
        bounds = Bounds(s0, positions[k], v0, end_values.get("v", 0.0), a0, end_values.get("a", 0.0), j0,
                        end_values.get("j", 0.0))
        try:
            pieces = shape.build(theta0, width, bounds, spec.param, start_reversal)
        except np.linalg.LinAlgError:
            raise CamcadError(f"segment {number} ({spec.shape}) cannot meet its end values",
                              f"{where} segment {number}", "change its end values or its angle") from None
        start_vals = pieces[0].start_values()
        end_vals = pieces[-1].end_values()
        if not all(math.isfinite(x) for x in (*start_vals, *end_vals)):
            raise CamcadError(f"segment {number} ({spec.shape}) has no finite solution", f"{where} segment {number}",
                              "change its end values or its angle")
        kind = _kind(shape.name, s0, positions[k], pieces)
        target_v = end_values.get("v", end_vals[1]) if shape.name != "dwell" else 0.0
        segments.append(Segment(number, spec, theta0, theta0 + width, shape.name, kind, start_vals, end_vals,
                                tuple(pieces), start_reversal, starts[k], ends[k], (positions[k], target_v)))
        current = end_vals
    # the cycle closes: the last end meets the first start
    last, head = segments[-1], segments[0]
    if abs(last.end_values[1] - head.start_values[1]) > _small_v(widths, positions):
        _velocity_jump(last, specs[0], shapes[0], head.start_values[1], last.end_values[1], 1, where, wrap_=True)
    joints = _joints(segments, math.radians(cycle_deg))
    return SegmentLaw(tuple(segments), math.radians(cycle_deg), specs, joints, where)


def _small_v(widths, positions) -> float:
    """A velocity below this (mm/rad) is rest: ``CONTINUITY_TOLERANCE`` of the largest position change per the
    smallest width."""
    span = max([abs(p) for p in positions] + [1e-300])
    return CONTINUITY_TOLERANCE * span / min(widths)


def _next_demand(shapes, widths, s_start, positions, specs, k: int, v0: float, reversal: bool) -> dict:
    return shapes[k].demand(widths[k], s_start[k], positions[k], v0, specs[k].param, reversal)


def _velocity_jump(prev: Segment, spec: SegmentSpec, shape: _Shape, wanted: float, arriving: float, number: int,
                   where: str, wrap_: bool = False) -> None:
    what = {"dwell": "rests", "constant_velocity": f"moves at {wanted / DEG:.6g} mm/deg"}.get(
        shape.name, f"starts at {wanted / DEG:.6g} mm/deg (its own start)")
    place = "the cycle's start" if wrap_ else f"its start ({math.degrees(prev.end):.6g} deg)"
    states_v = {n for n, law in CATALOGUE.items() if "v" in law.stated}
    fix = (f"give segment {prev.number} v_end = \"match\" (or {wanted / DEG:.6g})" if prev.shape in states_v else
           f"put a poly5 or inclined_sine between them, or give segment {number} a shape that takes the velocity")
    raise CamcadError(f"segment {number} ({spec.shape}) {what} but segment {prev.number} ({prev.shape}) arrives at "
                      f"{place} at {arriving / DEG:.6g} mm/deg: the velocity would jump", f"{where} segment {number}",
                      fix)


def _kind(shape: str, s0: float, s1: float, pieces) -> str:
    if shape == "dwell":
        return "dwell"
    span = max(abs(s0), abs(s1), 1e-300)
    if s1 - s0 > 1e-12 * span:
        return "rise"
    if s0 - s1 > 1e-12 * span:
        return "return"
    grid = [np.linspace(p.start, p.end, 65) for p in pieces]
    s = np.concatenate([p.evaluate(g, 0) for p, g in zip(pieces, grid)])
    if np.max(np.abs(s - s0)) <= 1e-12 * span:
        return "dwell"
    return "rise" if np.max(s) - s0 >= s0 - np.min(s) else "return"


def _joints(segments: list[Segment], cycle: float) -> tuple[Joint, ...]:
    scales = _scales(segments, cycle)
    joints = []
    for before, after in [*pairwise(segments), (segments[-1], segments[0])]:
        jumps = {name: after.start_values[i] - before.end_values[i] for i, name in enumerate("svaj")}
        continuous = [abs(jumps[name]) <= scales[i] for i, name in enumerate("svaj")]
        class_ = "C3" if all(continuous) else "C2" if all(continuous[:3]) else "C1"
        at = math.degrees(after.start) if after is not segments[0] else math.degrees(cycle)
        joints.append(Joint(at, before.number, after.number, jumps, class_))
    return tuple(joints)


# --------------------------------------------------------------------------------------------
# The command line's text form
# --------------------------------------------------------------------------------------------

def parse_segments(text: str, where: str = "--segments") -> tuple[SegmentSpec, ...]:
    """Segments from a text: comma-separated ``start:end:shape[:to_mm][:key=value…]`` items (deg, mm).

    Keys: ``v_end``, ``a_end``, ``j_end`` (a number in mm/deg, mm/deg², mm/deg³, or ``match``) and
    ``lambda`` (the inflection point of a lobe law). Each item starts where the previous ends, the first
    at 0.

    Parameters
    ----------
    text : str
        E.g. "0:60:dwell,60:140:poly5:12:v_end=match,140:200:constant_velocity:30,...".
    where : str
        The option or key the text came from (for messages).

    Returns
    -------
    tuple of SegmentSpec
        One per item (angles in deg, positions in mm).

    Raises
    ------
    CamcadError
        A malformed item, a gap or an overlap, an unknown key.

    Examples
    --------
    >>> specs = parse_segments("0:60:dwell,60:140:poly5:12:v_end=match,140:360:modified_sine:0:lambda=0.4")
    >>> specs[1].shape, specs[1].to_mm, specs[1].v_end, specs[2].param
    ('poly5', 12.0, 'match', 0.4)
    """
    items = [item.strip() for item in text.split(",") if item.strip()]
    if not items:
        raise CamcadError("no segments given", where,
                          'write e.g. "0:60:dwell,60:180:poly5:20,180:300:poly5:0,300:360:dwell"')
    specs = []
    previous = 0.0
    for number, item in enumerate(items, start=1):
        parts = [p.strip() for p in item.split(":")]
        if len(parts) < 3:
            raise CamcadError(f"segment {number} {item!r} is not start:end:shape[:to_mm]", where,
                              'write e.g. "60:140:poly5:12"')
        try:
            start, end = float(parts[0]), float(parts[1])
        except ValueError:
            raise CamcadError(f"segment {number} {item!r}: start and end must be numbers (deg)", where,
                              'write e.g. "60:140:poly5:12"') from None
        if abs(start - previous) > 1e-9 * max(1.0, abs(previous)):
            raise CamcadError(f"segment {number} starts at {start:g} deg, not where the previous ends ({previous:g})",
                              where, "make each segment start where the previous one ends, the first at 0")
        previous = end
        shape = parts[2]
        values: dict = {}
        rest = parts[3:]
        if rest and "=" not in rest[0]:
            values["to_mm"] = _number(rest[0], number, "to_mm", where)
            rest = rest[1:]
        for entry in rest:
            key, sep, raw = entry.partition("=")
            key = key.strip()
            if not sep or key not in ("v_end", "a_end", "j_end", "lambda"):
                raise CamcadError(f"segment {number}: {entry!r} is not v_end=, a_end=, j_end= or lambda=", where,
                                  'write e.g. "60:140:poly5:12:v_end=match"')
            if key == "lambda":
                values["param"] = _number(raw, number, key, where)
            else:
                values[key] = "match" if raw.strip() == "match" else _number(raw, number, key, where)
        specs.append(SegmentSpec(end, shape, **values))
    return tuple(specs)


def _number(raw: str, number: int, key: str, where: str) -> float:
    try:
        value = float(raw)
    except ValueError:
        raise CamcadError(f"segment {number}: {key} {raw!r} is not a number", where,
                          f"write {key} as a number") from None
    if not math.isfinite(value):
        raise CamcadError(f"segment {number}: {key} {raw!r} is not finite", where, "give a finite number")
    return value


def spec_tables(specs) -> list[dict]:
    """The segments as [[law.segments]] tables (what a scene holds): to_deg, shape and the keys that are set."""
    tables = []
    for spec in specs:
        table: dict = {"to_deg": spec.to_deg, "shape": spec.shape}
        for key in ("to_mm", "v_end", "a_end", "j_end"):
            if getattr(spec, key) is not None:
                table[key] = getattr(spec, key)
        if spec.param is not None:
            table["lambda"] = spec.param
        tables.append(table)
    return tables


def format_segments(specs) -> str:
    """The text form of segments (``parse_segments``'s inverse)."""
    out = []
    start = 0.0
    for spec in specs:
        parts = [f"{start:.10g}", f"{spec.to_deg:.10g}", spec.shape]
        if spec.to_mm is not None:
            parts.append(f"{spec.to_mm:.10g}")
        for key in ("v_end", "a_end", "j_end"):
            value = getattr(spec, key)
            if value is not None:
                parts.append(f"{key}={value if isinstance(value, str) else format(value, '.10g')}")
        if spec.param is not None:
            parts.append(f"lambda={spec.param:.10g}")
        out.append(":".join(parts))
        start = spec.to_deg
    return ",".join(out)
