"""One mechanism of a scene: the analyses that need its law, its profile and its other sections together.

- the cam's contact geometry along the profile (pressure angle, radius of curvature, concave parts
  negative) from camcad.profile, in the form camcad.contact takes;
- contact stress along the profile over the machine's speeds, with the least admissible phase angle
  of each rise and return (root finding on σ_max(t) = [σ_H], camcad.scene.stretch.least_angle);
- the phase-angle limits of a cyclogram's operations, and the optimal angles fed back into the laws.
A phase stretched to t keeps its shape and lift (camcad.law.retime); the next dwell takes up the change.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from camcad.arrays import unique
from camcad.contact import contact_stress, stress_versus_speed
from camcad.cyclogram.limits import vibration_limits
from camcad.cyclogram.retime import operation_timing, retime_phases, stretch_phase
from camcad.errors import CamcadError
from camcad.extrema import zoom_max
from camcad.law.segments import SegmentLaw
from camcad.numerics import bounded_minimum
from camcad.profile.geometry import CamGeometry
from camcad.scene.file import Mechanism, Scene
from camcad.scene.follower import follower_for_law
from camcad.scene.laws import law_with_phases, mechanism_law, phases_deg
from camcad.scene.sections.contact import parse_contact
from camcad.scene.sections.follower import parse_follower
from camcad.scene.stretch import PhaseStretch, least_angle

#: cam-angle samples per phase for the pressure-angle maximum of a stretched phase
PRESSURE_SAMPLES = 361
#: the phase limits aim this far inside each limit, so the design at the limit passes its own check
#: (a root found to round-off may otherwise sit a hair over it)
STRESS_MARGIN = 1e-9       # relative, of [σ_H]
PRESSURE_MARGIN_DEG = 1e-6


@dataclass(frozen=True)
class ContactGeometry:
    """What camcad.contact needs at cam angles ``theta`` (rad): the roller centre's (or flat face's)
    path s, v, a (mm, mm/rad, mm/rad²; arm × swing for an oscillating follower), the pressure angle
    (rad), the profile radius (mm, convex > 0), the other flank's radius seen from the roller (groove
    cams; else None) and the follower radius (mm, inf for a flat face)."""

    theta: Any
    s: Any
    v: Any
    a: Any
    pressure_angle: Any
    rho: Any
    rho_back: Any
    follower_radius: float
    kind: str

    def arrays(self) -> tuple[Any, Any, Any, Any, Any, Any, float, Any]:
        return (self.theta, self.s, self.v, self.a, self.pressure_angle, self.rho, self.follower_radius,
                self.rho_back)


def cam_of(law, follower_table: dict, where: str):
    """(CamGeometry, follower, scale) of a law on the [follower] of a scene; ``scale`` turns the follower's
    s, v, a into mm at the roller (the arm length for an oscillating follower, whose law becomes a swing)."""
    follower, law, scale, _ = follower_for_law(follower_table, where, law)
    return CamGeometry(law, follower), follower, scale


def contact_geometry(law, follower_table: dict, where: str, theta) -> ContactGeometry:
    """The cam's geometry at ``theta`` (rad) from camcad.profile: the follower from ``parse_follower``,
    the pitch curve, pressure angle and radii from ``CamGeometry`` (the lift law becomes a swing law
    for an oscillating follower, as ``camcad profile`` does)."""
    cam, follower, scale = cam_of(law, follower_table, where)
    if follower.kind == "knife":
        raise CamcadError("a knife edge has no Hertz contact (zero radius)", where,
                          "give the follower a roller (roller_radius > 0)")
    theta = np.asarray(theta, dtype=float)
    kin = cam.kinematics(theta)
    if follower.kind == "flat":
        rho = cam.profile(theta).rho
        radius, back = math.inf, None
    else:
        pitch = cam.pitch(theta)
        radius = float(follower.roller_radius)
        rho = pitch.rho - radius
        # a groove's outer wall X = P + Rr n has radius ρ_p + Rr seen from outside; the roller
        # touches it from inside, so it sees −(ρ_p + Rr) in the convex-positive convention
        back = -(pitch.rho + radius) if follower.groove else None
    return ContactGeometry(theta, kin.s * scale, kin.v * scale, kin.a * scale, cam.pressure_angle(theta),
                           rho, back, radius, follower.kind)


def pressure_angle_limit_of(follower, kind: str) -> float | None:
    """The pressure-angle limit (deg) of a phase kind; a reversible cam has the rise limit on both."""
    if kind == "rise" or follower.reversible:
        return follower.pressure_angle_limit_rise_deg
    return follower.pressure_angle_limit_return_deg


def phase_pressure_function(law, follower_table: dict, index: int, where: str, samples: int):
    """φ_max(t): the largest |pressure angle| (deg) over phase ``index`` of ``law`` stretched to t deg;
    +inf when the stretched cam undercuts (no pressure angle is meaningful there)."""
    phases = phases_deg(law)

    def phi_max(width_deg: float) -> float:
        stretched, (start, end) = stretched_phase(phases, index, width_deg)
        cam, _, _ = cam_of(law_with_phases(law, stretched, where), follower_table, where)
        theta = np.linspace(np.radians(start), np.radians(end), samples)
        values = np.abs(cam.pressure_angle(theta))   # |φ| is finite on the grid
        k = int(np.argmax(values))
        best = float(values[k])
        lo, hi = theta[max(k - 1, 0)], theta[min(k + 1, len(theta) - 1)]
        # the grid's best point refined by Brent's bounded search (a method apart from the fast route's
        # zooming grids)
        if hi > lo:
            _, value = bounded_minimum(lambda t: -float(np.abs(cam.pressure_angle(np.array([t])))[0]), lo, hi,
                                       xatol=1e-13)
            best = max(best, -value)
        return float(np.degrees(best))

    return phi_max


def pressure_stretch(law, follower_table: dict, index: int, where: str, samples: int) -> PhaseStretch:
    """Phase ``index`` ready to be stretched: its ``pressure_max_deg(widths)`` is the largest |pressure
    angle| (deg) over the phase stretched to each width (deg), all widths in one pass, and its
    ``pressure_inverse`` the closed-form least width where there is one (``camcad.scene.stretch``)."""
    cam, _, scale = cam_of(law, follower_table, where)
    return PhaseStretch.sample(cam, scale, phases_deg(law), index, samples)


def pressure_angle_limits(law, follower_table: dict, where: str, samples: int,
                          memo: LimitMemo | None = None) -> dict:
    """{phase label: least phase angle (deg) at which the phase's |pressure angle| meets the follower's
    limit}, by root finding on φ_max(t) (``camcad.scene.stretch.least_angle``); None where no limit is set."""
    follower = parse_follower(follower_table, where)
    phases = phases_deg(law)
    found: dict[str, Any] = {}
    for index, label in motion_labels(phases):
        start, end, kind = phases[index]
        limit = pressure_angle_limit_of(follower, kind)
        if limit is None:
            found[label] = None
            continue
        stretch = pressure_stretch(law, follower_table, index, where, samples)
        try:
            found[label] = _solve(memo, (id(law), index, "pressure angle"), stretch.pressure_max_deg,
                                  limit - PRESSURE_MARGIN_DEG, 0.1 * (end - start), stretch_room(phases, index),
                                  source="pressure angle", what=f"{label}",
                                  inverse=stretch.pressure_inverse).angle_deg
        except CamcadError:
            found[label] = None
    return found


#: the undercut limit aims this far inside (relative, of 1/(Rr + ρ_min)): the cam at its least angle keeps its
#: convex pitch radius above Rr by round-off at least
CURVATURE_MARGIN = 1e-9
#: the lower end of the undercut and cusp searches, a fraction of the phase: both relations grow without bound as
#: the phase shortens, so the crossing is always above it
CURVATURE_LOWER_FRACTION = 1e-3


@dataclass(frozen=True)
class GeometryRelation:
    """One geometric limit of a phase's angle: relation(widths) ≤ ``limit`` (non-increasing in the width), its
    closed-form inverse where there is one, and the least fraction of the phase the search starts at."""

    source: str
    relation: Any
    limit: float
    inverse: Any = None
    lower_fraction: float = CURVATURE_LOWER_FRACTION


def geometry_relations(law, follower_table: dict, index: int, where: str, samples: int) -> list[GeometryRelation]:
    """The follower's geometric limits on phase ``index``'s angle (``geometry_limits`` says which and why)."""
    follower = parse_follower(follower_table, where)
    phases = phases_deg(law)
    kind = phases[index][2]
    direct = isinstance(law, SegmentLaw)
    stretch = pressure_stretch(law, follower_table, index, where, samples)
    found = []
    if follower.kind == "flat":
        name = "cusp" if follower.rho_min is None else "curvature"
        rho_min = follower.rho_min or 0.0
        limit = -CURVATURE_MARGIN * follower.base_radius
        if direct:
            deficit = _direct_relation(law, follower_table, index, where, samples, "flat")
            found.append(GeometryRelation(name, lambda w, f=deficit: f(w) + rho_min, limit))
        else:
            least = stretch.flat_least_width(rho_min)[0] * (1.0 + CURVATURE_MARGIN)
            found.append(GeometryRelation(name, lambda w: stretch.flat_radius_deficit(w, rho_min), limit,
                                          inverse=lambda _limit: least if math.isfinite(least) else None))
        return found
    pressure_limit = pressure_angle_limit_of(follower, kind)
    if pressure_limit is not None:
        relation = (_direct_relation(law, follower_table, index, where, samples, "pressure") if direct
                    else stretch.pressure_max_deg)
        found.append(GeometryRelation("pressure angle", relation, pressure_limit - PRESSURE_MARGIN_DEG,
                                      None if direct else stretch.pressure_inverse, 0.1))
    if stretch.curvature_reach() > 0.0:
        relation = (_direct_relation(law, follower_table, index, where, samples, "curvature") if direct
                    else stretch.curvature_ratio)
        found.append(GeometryRelation("undercut" if follower.rho_min is None else "curvature", relation,
                                      1.0 - CURVATURE_MARGIN))
    return found


def geometry_limits(law, follower_table: dict, where: str, samples: int, memo: LimitMemo | None = None
                    ) -> tuple[dict, list[str]]:
    """The least angle of every rise and return that the follower's geometry allows, by source.

    - "pressure angle": the phase's largest |φ| reaches the follower's limit (root finding on φ_max(t));
      not for a flat face, whose pressure angle is zero by construction;
    - "undercut" (a roller or an oscillating roller; "curvature" with ``rho_min``): the pitch curve's largest
      convex curvature reaches 1/(Rr + ρ_min), where the profile loops (ρ_min = 0) or breaks its curvature limit;
    - "cusp" (a flat face; "curvature" with ``rho_min``): the profile radius ρ = Rb + s + a reaches ρ_min
      (0: a cusp), in closed form: t = β·max √(−a/(Rb + s − ρ_min)) over the decelerating samples.

    A phase stretched to t keeps its shape and lift (the next dwell takes up the change); a phase of a law
    designed from segments is solved again at t, keeping its end values (``camcad.law.retime``).

    Returns
    -------
    (dict, list of str)
        {label: {source: least angle (deg) or None}} and notes (why an angle is missing or what binds it).
    """
    follower = parse_follower(follower_table, where)
    phases = phases_deg(law)
    found: dict[str, dict] = {}
    notes: list[str] = []
    direct = isinstance(law, SegmentLaw)
    for index, label in motion_labels(phases):
        start, end, kind = phases[index]
        width = end - start
        upper = stretch_room(phases, index)
        sources: dict[str, Any] = {}
        if direct:
            if upper <= width:
                found[label] = {"pressure angle": None}
                notes.append(f"{label}: no neighbouring dwell takes up a change of its angle, so it has no least "
                             "angle of its own (shorten or lengthen the segments around it)")
                continue
            upper -= 1e-9 * upper   # the phase angles carry round-off: stay inside the room the dwell gives
        if follower.kind != "flat" and pressure_angle_limit_of(follower, kind) is None:
            sources["pressure angle"] = None
        for item in geometry_relations(law, follower_table, index, where, samples):
            try:
                sources[item.source] = _solve(memo, (id(law), index, item.source), item.relation, item.limit,
                                              item.lower_fraction * width, upper, source=item.source, what=label,
                                              inverse=item.inverse).angle_deg
            except CamcadError as err:
                sources[item.source] = None
                notes.append(f"{label}: {err.what}")
        if follower.kind == "flat":
            notes.append(f"{label}: a flat face has no pressure angle; its least angle is bound by the "
                         f"{'cusp condition Rb + s + a > 0' if follower.rho_min is None else 'curvature limit'}")
        found[label] = sources
    return found, notes


def _direct_relation(law, follower_table: dict, index: int, where: str, samples: int, quantity: str):
    """relation(widths) → values for phase ``index`` stretched by solving the law again at each width (the route
    for a law whose phases do not scale with their angle: a segment's end velocity is kept, not scaled):
    "pressure" the largest |φ| (deg), "curvature" (Rr + ρ_min)·κ_max, "flat" −min(Rb + s + a) (mm)."""
    phases = phases_deg(law)
    pressure = phase_pressure_function(law, follower_table, index, where, samples) if quantity == "pressure" else None

    def one(width_deg: float) -> float:
        if pressure is not None:
            return pressure(width_deg)
        try:
            stretched, (start, end) = stretched_phase(phases, index, width_deg)
        except CamcadError:
            return math.inf
        cam, follower, _ = cam_of(law_with_phases(law, stretched, where), follower_table, where)
        grid = np.linspace(np.radians(start), np.radians(end), samples)
        if quantity == "flat":
            def values(t):
                kin = cam.kinematics(np.ravel(t))
                return -(follower.base_radius + kin.s + kin.a).reshape(1, -1)
        else:
            reach = follower.roller_radius + (follower.rho_min or 0.0)

            def values(t):
                rho = cam.pitch(np.ravel(t)).rho
                with np.errstate(divide="ignore", invalid="ignore"):
                    kappa = np.where(np.isfinite(rho), 1.0 / rho, 0.0)
                ratio = reach * kappa
                if follower.groove:
                    ratio = np.maximum(ratio, -ratio)
                return np.nan_to_num(ratio, nan=1e300, posinf=1e300, neginf=-1e300).reshape(1, -1)
        return float(zoom_max(values, grid, 1)[0][0])

    return lambda widths: np.array([one(float(w)) for w in np.atleast_1d(widths)])


class LimitMemo:
    """Least phase angles already solved in one pipeline run, so the cyclogram's bounds reuse the
    mechanisms' own (the relation is non-increasing: a crossing inside the new bounds is the answer)."""

    def __init__(self) -> None:
        self._solved: dict[tuple, list] = {}

    def solve(self, key: tuple, relation, limit: float, lower: float, upper: float, **kwargs):
        """``least_angle(relation, limit, lower, upper, **kwargs)``, from an earlier answer when one applies."""
        source = kwargs.get("source", "limit")
        for found in self._solved.get(key, []):
            if found.limit != limit:
                continue
            if found.binding and lower < found.angle_deg <= upper:
                return replace(found, evaluations=0, source=source)
            if not found.binding and lower >= found.angle_deg:
                value = float(relation(np.array([lower]))[0])
                return replace(found, angle_deg=float(lower), value=value, evaluations=1, source=source)
        found = least_angle(relation, limit, lower, upper, **kwargs)
        self._solved.setdefault(key, []).append(found)
        return found


def _solve(memo: LimitMemo | None, key: tuple, relation, limit, lower, upper, **kwargs):
    if memo is None:
        return least_angle(relation, limit, lower, upper, **kwargs)
    return memo.solve(key, relation, limit, lower, upper, **kwargs)


def motion_labels(phases) -> list[tuple[int, str]]:
    """(index, label) of every rise and return: "rise", "return", then "rise_2", "return_2", ..."""
    counts: dict[str, int] = {}
    out = []
    for index, (_, _, kind) in enumerate(phases):
        if kind == "dwell":
            continue
        counts[kind] = counts.get(kind, 0) + 1
        out.append((index, kind if counts[kind] == 1 else f"{kind}_{counts[kind]}"))
    return out


def stretched_phase(phases, index: int, width_deg: float):
    """The phases with phase ``index`` made ``width_deg`` wide (camcad.cyclogram.stretch_phase), and that
    phase's (start_deg, end_deg) in the result (a neighbouring dwell may vanish and shift the indices)."""
    stretched = stretch_phase(phases, index, width_deg)
    kind = phases[index][2]
    start = phases[index][0]
    candidates = [(a, b) for a, b, k in stretched
                  if k == kind and abs((b - a) - width_deg) <= 1e-9 * max(1.0, width_deg)]
    bounds = min(candidates, key=lambda ab: abs(ab[0] - start))
    return stretched, bounds


def phase_grid(phases: list[tuple[float, float, str]], samples: int) -> np.ndarray:
    """θ (rad): ``samples`` points in every phase, ends included (a phase end is sampled once)."""
    pieces = [np.linspace(np.radians(start), np.radians(end), samples) for start, end, _ in phases]
    return unique(np.concatenate(pieces))


def stretch_room(phases: list[tuple[float, float, str]], index: int) -> float:
    """The widest the phase can become by taking a neighbouring dwell (deg)."""
    start, end, _ = phases[index]
    room = 0.0
    for neighbour in (index + 1, index - 1):
        if 0 <= neighbour < len(phases) and phases[neighbour][2] == "dwell":
            room = max(room, phases[neighbour][1] - phases[neighbour][0])
    return end - start + room


def phase_index(phases, kind: str, occurrence: int, where: str) -> int:
    seen = 0
    for index, (_, _, phase_kind) in enumerate(phases):
        if phase_kind == kind:
            seen += 1
            if seen == occurrence:
                return index
    raise CamcadError(f"the law has no {kind} number {occurrence}", where,
                      "check the operation's phase and occurrence")


def contact_params(scene: Scene, mech: Mechanism):
    if not mech.has("contact"):
        raise CamcadError(f"mechanism {mech.name!r} has no [contact] section", str(scene.path),
                          "add materials, loads and the allowable stress in [contact]")
    return parse_contact(mech.sections["contact"], mech.where(scene.path, "contact"))


def phase_stress_function(law, follower_table: dict, params, speeds: list[float], index: int, where: str,
                          samples: int):
    """σ_max(t): the largest σ_H over phase ``index`` of ``law`` stretched to t deg (the next dwell takes
    up the change), sampled at ``samples`` cam angles in the phase, over all ``speeds``; +inf when the
    stretched cam is not admissible (the roller does not fit, the follower jams, or a force-closed
    follower leaves the cam)."""
    phases = phases_deg(law)

    def sigma_max(width_deg: float) -> float:
        stretched, (start, end) = stretched_phase(phases, index, width_deg)
        stretched_law = law_with_phases(law, stretched, where)
        theta = np.linspace(np.radians(start), np.radians(end), samples)
        geometry = contact_geometry(stretched_law, follower_table, where, theta)
        worst = 0.0
        for rpm in speeds:
            try:
                result = contact_stress(*geometry.arrays()[:7], rpm, params, geometry.rho_back)
            except CamcadError:
                return float("inf")
            if result.separation:
                return float("inf")  # the spring no longer holds the follower on the cam: not admissible
            worst = max(worst, result.sigma_max)
        return worst

    return sigma_max


@dataclass(frozen=True)
class StressRelation:
    """σ_max(widths): the largest σ_H (MPa) over a phase stretched to each width (deg) and over the speeds,
    all widths in one pass, +inf where the stretched cam is not admissible; ``reason(width)`` says why a
    width is not admissible ("" where it is)."""

    stretch: PhaseStretch
    params: Any
    speeds: tuple

    def __call__(self, widths):
        return self.stretch.stress_max(widths, self.params, self.speeds)

    def reason(self, width_deg: float) -> str:
        return self.stretch.stress_inadmissible(width_deg, self.params, self.speeds)


@dataclass(frozen=True)
class DirectStressRelation:
    """σ_max(widths) of a law whose phases do not scale with their angle (a segment law): one stretched law
    solved per width; +inf where no neighbouring dwell takes up the width or the cam is not admissible."""

    one: Any

    def __call__(self, widths):
        def direct(width: float) -> float:
            try:
                return self.one(width)
            except CamcadError:       # no neighbouring dwell takes up that width
                return math.inf

        return np.array([direct(float(w)) for w in np.atleast_1d(widths)])

    def reason(self, width_deg: float) -> str:
        return ("no neighbouring dwell takes up that angle, or the stretched cam is not admissible"
                if not math.isfinite(float(self(width_deg)[0])) else "")


def stress_relation(law, follower_table: dict, params, speeds: list[float], index: int, where: str,
                    samples: int) -> StressRelation | DirectStressRelation:
    """σ_max(widths): the largest σ_H (MPa) over phase ``index`` stretched to each width (deg) and over
    ``speeds``, all widths in one pass; +inf where the stretched cam is not admissible (``reason`` says why)."""
    if isinstance(law, SegmentLaw):
        # a segment keeps its end values when its angle changes: the law is solved again at each width
        return DirectStressRelation(phase_stress_function(law, follower_table, params, speeds, index, where, samples))
    cam, _, scale = cam_of(law, follower_table, where)
    stretch = PhaseStretch.sample(cam, scale, phases_deg(law), index, samples)
    return StressRelation(stretch, params, tuple(speeds))


def mechanism_contact(scene: Scene, mech: Mechanism, speeds: list[float], samples: int, law=None,
                      with_limits: bool = True, memo: LimitMemo | None = None, extra_load=None):
    """Contact analysis of one mechanism: stress along the profile at every speed, the worst speed's
    figures (docs/INTERFACE.md ``contact`` keys), separation, and (``with_limits``) the contact-limited least phase
    angle of each rise and return. ``law`` defaults to the mechanism's [law]. ``extra_load(theta)``: a
    ``camcad.linkage.transfer.LinkageLoad`` (the working member behind a [linkage]) or None; with one, the
    phase limits are not computed (their stretched phases do not carry it). Returns (report, ContactResult at
    the worst speed, SpeedSweep)."""
    params = contact_params(scene, mech)
    law_where = mech.where(scene.path, "law")
    if law is None:
        law = mechanism_law(scene, mech).law
    phases = phases_deg(law)
    follower_table = mech.sections.get("follower", {})
    geometry = contact_geometry(law, follower_table, mech.where(scene.path, "follower"), phase_grid(phases, samples))
    if params.roller_radius is not None and params.roller_radius != geometry.follower_radius:
        raise CamcadError(f"roller_radius {params.roller_radius:g} mm differs from the follower's "
                          f"{geometry.follower_radius:g} mm", mech.where(scene.path, "contact"),
                          "give the roller radius in [follower] only")
    theta, s, v, a, phi, rho, radius, back = geometry.arrays()
    load = None if extra_load is None else extra_load(theta)
    sweep = stress_versus_speed(theta, s, v, a, phi, rho, radius, speeds, params, back, linkage_load=load)
    at_worst = contact_stress(theta, s, v, a, phi, rho, radius, float(sweep.rpm[sweep.worst]), params, back,
                              linkage_load=load)
    report = at_worst.report()
    report["separation"] = bool(np.any(sweep.separation))
    report["passed"] = bool(np.all(sweep.sigma_max <= params.allowable_stress)) and not report["separation"]
    report["versus_speed"] = sweep.report()
    report["follower"] = geometry.kind
    limits: dict[str, Any] = {}
    notes: list[str] = []
    if load is not None:
        with_limits = False
        notes.append("the working member's inertia and load through the [linkage] are in the contact force; the "
                     "contact-limited phase angles are not computed with them")
    for index, label in (motion_labels(phases) if with_limits else []):
        start, end, _ = phases[index]
        relation = stress_relation(law, follower_table, params, speeds, index, law_where, samples)
        try:
            found = _solve(memo, (id(law), index, "contact"), relation,
                           params.allowable_stress * (1 - STRESS_MARGIN), 0.1 * (end - start),
                           stretch_room(phases, index), source="contact stress", what=f"{mech.name} {label}",
                           reason=relation.reason)
            limits[label] = found.angle_deg
            if found.note:
                notes.append(f"{label}: {found.note}")
            if not found.binding:
                notes.append(f"{label}: [σ_H] is met down to {found.angle_deg:.6g} deg, a tenth of the phase")
        except CamcadError as err:
            limits[label] = None
            notes.append(err.message())
    report["phase_limit_deg"] = limits
    report["notes"] = notes
    return report, at_worst, sweep


def cyclogram_limits(scene: Scene, network, speeds: list[float] | None, samples: int,
                     memo: LimitMemo | None = None):
    """Phase limits of the network's operations: vibration (from the operation's relation) and contact
    stress (from the operation's mechanism, when it has [law], [follower] and [contact]).
    Returns (limits {label: [PhaseLimit]}, skipped {what: why})."""
    limits = vibration_limits(network)
    skipped: dict[str, str] = {}
    by_name = {m.name: m for m in scene.mechanisms}
    for op in network.operations:
        if op.mechanism is None or op.phase is None or op.phase == "dwell":
            continue
        mech = by_name[op.mechanism]
        if mech.has("follower"):
            limits.setdefault(op.label, []).extend(_pressure_limit(scene, mech, op, memo))
        if not mech.has("contact"):
            skipped[f"contact limit {op.label}"] = f"mechanism {op.mechanism} has no [contact]"
            continue
        if speeds is None:
            skipped[f"contact limit {op.label}"] = "no [machine] rpm"
            continue
        law_where = mech.where(scene.path, "law")
        law = mechanism_law(scene, mech).law
        phases = phases_deg(law)
        index = phase_index(phases, op.phase, op.occurrence, law_where)
        params = contact_params(scene, mech)
        relation = stress_relation(law, mech.sections.get("follower", {}), params, speeds, index, law_where,
                                   samples)
        upper = op.max_deg if math.isfinite(op.max_deg) else stretch_room(phases, index)
        lower = max(op.min_deg, 1e-3 * upper)
        limits.setdefault(op.label, []).append(_solve(
            memo, (id(law), index, "contact"), relation, params.allowable_stress * (1 - STRESS_MARGIN), lower,
            upper, source="contact", what=f"operation {op.label} ({op.mechanism} {op.phase})",
            reason=relation.reason))
    return limits, skipped


def _pressure_limit(scene: Scene, mech: Mechanism, op, memo: LimitMemo | None = None) -> list:
    """The least phase angles of an operation from its mechanism's geometry: the pressure-angle limit, the roller's
    undercut, the flat face's cusp (``geometry_relations``), within the operation's bounds."""
    follower_table = mech.sections["follower"]
    where = mech.where(scene.path, "follower")
    law = mechanism_law(scene, mech).law
    phases = phases_deg(law)
    index = phase_index(phases, op.phase, op.occurrence, mech.where(scene.path, "law"))
    upper = op.max_deg if math.isfinite(op.max_deg) else stretch_room(phases, index)
    lower = max(op.min_deg, 1e-3 * upper)
    return [_solve(memo, (id(law), index, item.source), item.relation, item.limit, lower, upper, source=item.source,
                   what=f"operation {op.label} ({op.mechanism} {op.phase})", inverse=item.inverse)
            for item in geometry_relations(law, follower_table, index, where, PRESSURE_SAMPLES)]


def retimed_phases(scene: Scene, result) -> dict[str, list[tuple[float, float, str]]]:
    """{mechanism: new (start_deg, end_deg, kind) phases} with the optimal angles of its operations fed back."""
    found = {}
    by_name = {m.name: m for m in scene.mechanisms}
    for name, timing in operation_timing(result).items():
        mech = by_name[name]
        law_where = mech.where(scene.path, "law")
        phases = phases_deg(mechanism_law(scene, mech).law)
        found[name] = retime_phases(phases, timing, where=law_where)
    return found
