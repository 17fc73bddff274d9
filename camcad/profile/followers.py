"""Followers: what touches the cam, where it sits, and the design limits that go with it.

Frames and signs (docs/INTERFACE.md): the cam centre is the origin of the fixed frame; the cam turns
counter-clockwise by default (``cw`` flips it). A translating follower moves along +y on
the line x = e (offset e, mm). An oscillating follower pivots at A = (C, 0) (C the pivot
distance, mm); its arm of length L carries the roller centre B = A + L·(−cos γ, sin γ), where
γ = γ0 + ψ is the angle between the line A→O and the arm, γ0 the arm angle on the base
circle and ψ the swing (rad): a larger γ puts the roller farther from the cam centre.

A second roller on the same follower gives the conjugate pair (cam and counter-cam): for a
translating follower it sits ``pair_distance`` mm below the first on the follower axis and
touches the counter-cam from the other side; for an oscillating follower it is on a second
arm of the same length turned by ``pair_angle_deg`` from the first, on the other side of the
line of centres. ``groove`` asks for the outer flank of a groove (face) cam as well.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import cast

from camcad.errors import CamcadError
from camcad.profile import defaults

FOLLOWER_KINDS = ("roller", "flat", "oscillating", "knife")


@dataclass(frozen=True)
class Follower:
    """A follower and its design limits (lengths in mm, angles in deg).

    Frames and signs: the cam centre is the origin and the cam turns counter-clockwise unless ``cw``.
    A translating follower moves along +y on the line x = e (``offset``); an oscillating follower
    pivots at (C, 0) and its arm of length L carries the roller (see ``camcad.profile.followers``).

    Parameters
    ----------
    kind : str
        "roller" (translating roller), "knife" (a roller with Rr = 0), "flat" (translating flat face
        perpendicular to its axis) or "oscillating" (oscillating roller).
    base_radius : float
        Rb, base-circle radius of the cam profile, mm.
    roller_radius : float
        Rr, mm; 0 for a knife edge; not used by "flat".
    offset : float
        e, translating followers: the follower's axis is the line x = e, mm.
    pivot : float, optional
        C, distance from the cam centre to the pivot of an oscillating follower, mm.
    arm : float, optional
        L, arm length of an oscillating follower (pivot to roller centre), mm.
    cw : bool
        The cam turns clockwise.
    pressure_angle_limit_rise_deg : float, optional
        Limit of |pressure angle| while the follower moves away from the cam centre (rise), deg;
        None: not checked. Dwells use the rise limit.
    pressure_angle_limit_return_deg : float, optional
        Limit of |pressure angle| while the follower moves toward the cam centre (return), deg;
        None: not checked.
    reversible : bool
        The cam runs both ways, so each moving phase is a working stroke in one direction: the rise
        limit then applies to returns too.
    groove : bool
        Also build the outer flank of a groove cam (roller followers).
    pair_distance : float, optional
        Translating conjugate pair: distance between the two roller centres, mm.
    pair_angle_deg : float, optional
        Oscillating conjugate pair: angle between the two arms, deg.
    rho_min : float, optional
        Smallest allowed radius of curvature of the convex parts of the profile, mm; None: only
        "no undercut" is checked.

    Examples
    --------
    The pitch curve of a roller follower starts on the circle of radius Rp = Rb + Rr:

    >>> import camcad
    >>> follower = camcad.Follower("roller", base_radius=40.0, roller_radius=10.0)
    >>> follower.prime_radius
    50.0
    >>> follower.describe()
    'translating roller, Rb 40 mm, Rr 10 mm, e 0 mm, CCW'
    >>> camcad.Follower("roller", base_radius=40.0, roller_radius=10.0, offset=60.0).validate()
    Traceback (most recent call last):
    ...
    camcad.errors.CamcadError: follower: offset |e| = 60 mm is not less than Rb + Rr = 50 mm; reduce the offset or enlarge the base circle
    """  # noqa: E501 - a doctest's expected output is one line

    kind: str
    base_radius: float
    roller_radius: float = 0.0
    offset: float = 0.0
    pivot: float | None = None
    arm: float | None = None
    cw: bool = False
    pressure_angle_limit_rise_deg: float | None = defaults.PRESSURE_ANGLE_LIMIT_RISE_DEG
    pressure_angle_limit_return_deg: float | None = defaults.PRESSURE_ANGLE_LIMIT_RETURN_DEG
    reversible: bool = False
    groove: bool = False
    pair_distance: float | None = None
    pair_angle_deg: float | None = None
    rho_min: float | None = None

    @property
    def sigma(self) -> float:
        """+1 for counter-clockwise rotation, −1 for clockwise."""
        return -1.0 if self.cw else 1.0

    @property
    def has_roller(self) -> bool:
        return self.kind in ("roller", "knife", "oscillating")

    @property
    def prime_radius(self) -> float:
        """Rp = Rb + Rr (mm): radius of the pitch curve's base circle (Rb for a flat face)."""
        return self.base_radius + (self.roller_radius if self.has_roller else 0.0)

    @property
    def has_pair(self) -> bool:
        return self.pair_distance is not None or self.pair_angle_deg is not None

    def with_base_radius(self, base_radius: float) -> Follower:
        return replace(self, base_radius=float(base_radius))

    def describe(self) -> str:
        """One ASCII line for the drawing and the report."""
        turn = "CW" if self.cw else "CCW"
        if self.kind == "flat":
            text = f"translating flat face, Rb {self.base_radius:.6g} mm, e {self.offset:.6g} mm"
        elif self.kind == "oscillating":
            text = (f"oscillating roller, Rb {self.base_radius:.6g} mm, Rr {self.roller_radius:.6g} mm, "
                    f"pivot C {self.pivot:.6g} mm, arm L {self.arm:.6g} mm")
        elif self.kind == "knife" or self.roller_radius == 0.0:
            text = f"translating knife edge, Rb {self.base_radius:.6g} mm, e {self.offset:.6g} mm"
        else:
            text = (f"translating roller, Rb {self.base_radius:.6g} mm, Rr {self.roller_radius:.6g} mm, "
                    f"e {self.offset:.6g} mm")
        return f"{text}, {turn}"

    def validate(self, where: str = "follower") -> Follower:
        """Raise CamcadError for a follower that cannot work; return self."""
        if self.kind not in FOLLOWER_KINDS:
            raise CamcadError(f"follower type {self.kind!r} is unknown", where,
                              f"use one of {', '.join(FOLLOWER_KINDS)}")
        for name in ("base_radius", "roller_radius", "offset"):
            if not math.isfinite(getattr(self, name)):
                raise CamcadError(f"{name} must be finite", where, "give a number in mm")
        if not self.base_radius > 0.0:
            raise CamcadError(f"base radius must be positive, got {self.base_radius:g} mm", where,
                              "give --rb / base_radius > 0")
        if self.roller_radius < 0.0:
            raise CamcadError(f"roller radius must be >= 0, got {self.roller_radius:g} mm", where,
                              "give --rr / roller_radius >= 0 (0 is a knife edge)")
        if self.kind == "knife" and self.roller_radius != 0.0:
            raise CamcadError("a knife-edge follower has no roller", where,
                              "drop the roller radius or use type roller")
        for name in ("pressure_angle_limit_rise_deg", "pressure_angle_limit_return_deg"):
            value = getattr(self, name)
            if value is not None and not 0.0 < value < 90.0:
                raise CamcadError(f"{name.replace('_deg', '')} is {value:g} deg", where,
                                  "give a limit between 0 and 90 deg")
        if self.rho_min is not None and not self.rho_min >= 0.0:
            raise CamcadError(f"curvature limit must be >= 0, got {self.rho_min:g} mm", where,
                              "give the smallest allowed radius of curvature in mm")
        if self.kind in ("roller", "knife", "flat"):
            if abs(self.offset) >= self.prime_radius:
                raise CamcadError(f"offset |e| = {abs(self.offset):g} mm is not less than Rb + Rr = "
                                  f"{self.prime_radius:g} mm", where,
                                  "reduce the offset or enlarge the base circle")
            if self.pair_angle_deg is not None:
                raise CamcadError("pair_angle is for an oscillating follower", where,
                                  "use pair_distance (mm) for a translating conjugate pair")
        if self.kind == "oscillating":
            if self.pivot is None or self.arm is None:
                raise CamcadError("an oscillating follower needs its pivot distance and arm length", where,
                                  "give --pivot C and --arm L (mm), or pivot = ... and arm = ...")
            if not (self.pivot > 0.0 and self.arm > 0.0):
                raise CamcadError("pivot distance and arm length must be positive", where,
                                  "give C > 0 and L > 0 in mm")
            rp = self.prime_radius
            if not abs(self.pivot - self.arm) < rp < self.pivot + self.arm:
                raise CamcadError(f"the roller cannot reach the base circle: Rb + Rr = {rp:g} mm must lie "
                                  f"between |C - L| = {abs(self.pivot - self.arm):g} and C + L = "
                                  f"{self.pivot + self.arm:g} mm", where,
                                  "change the pivot distance, the arm or the base radius")
            if self.pair_distance is not None:
                raise CamcadError("pair_distance is for a translating follower", where,
                                  "use pair_angle (deg) for an oscillating conjugate pair")
        if self.kind == "flat" and (self.groove or self.has_pair):
            raise CamcadError("groove and conjugate cams are built for roller followers", where,
                              "use a roller or oscillating follower")
        if self.groove and self.roller_radius == 0.0:
            raise CamcadError("a groove needs a roller (Rr > 0)", where, "give a roller radius")
        if self.pair_distance is not None and not self.pair_distance > 0.0:
            raise CamcadError("pair distance must be positive", where, "give the roller-centre distance in mm")
        if self.pair_angle_deg is not None and not 0.0 < self.pair_angle_deg < 180.0:
            raise CamcadError("pair angle must be between 0 and 180 deg", where,
                              "give the angle between the two arms in deg")
        return self

    def as_dict(self) -> dict:
        return {"type": self.kind, "base_radius_mm": self.base_radius,
                "roller_radius_mm": self.roller_radius if self.has_roller else None,
                "offset_mm": self.offset if self.kind != "oscillating" else None,
                "pivot_mm": self.pivot, "arm_mm": self.arm, "cw": self.cw,
                "pressure_angle_limit_rise_deg": self.pressure_angle_limit_rise_deg,
                "pressure_angle_limit_return_deg": self.pressure_angle_limit_return_deg,
                "reversible": self.reversible, "groove": self.groove,
                "pair_distance_mm": self.pair_distance, "pair_angle_deg": self.pair_angle_deg,
                "rho_min_mm": self.rho_min}


def arm_angle_on_base_circle(follower: Follower) -> float:
    """γ0 (rad): arm angle of the oscillating follower with the roller on the base circle.

    Law of cosines in the triangle cam centre O – pivot A – roller centre B:
        (Rb + Rr)² = C² + L² − 2 C L cos γ0.
    """
    c, arm, rp = cast(float, follower.pivot), cast(float, follower.arm), follower.prime_radius
    return math.acos((c**2 + arm**2 - rp**2) / (2.0 * c * arm))


