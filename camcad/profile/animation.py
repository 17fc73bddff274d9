"""The cam mechanism in motion: where every part is, frame by frame, as pure functions of the cam angle.

``cam_frames(result, step_deg)`` samples one turn of the cam at a fixed step and gives, in the fixed frame
(cam centre at the origin, mm, angles in deg counter-clockwise), the cam's turn, the follower's position
and the contact, for every follower type: the translating roller, knife edge and flat face, the
oscillating roller, the second roller of a conjugate pair and the groove's outer flank. The report layer
draws them (``camcad.report.animation``); nothing here draws.

Frames and signs (``camcad.profile.geometry``): the cam turns by σθ (σ = +1 counter-clockwise, −1 for a
``cw`` cam), so a point X of the cam's own frame is at R(σθ) X. The roller centre is the track point q(θ)
of the follower (``Track``); the contact is q − Rr·n, n the outward normal of the pitch curve turned into
the fixed frame; the flat face touches at (σ v, Rb + s).

The roller rolls on the cam without slipping. Relative to the cam it turns by −σ S(θ)/Rr, S(θ) = ∫₀^θ |P'| dθ
the arc length its centre has run along the pitch curve in the cam's frame (a disc rolling on a curve turns
by the arc length of its centre's path over its radius: the coin-rotation rule), so its absolute turn is

    φ_roller(θ) = σ (θ − S(θ)/Rr).

On a dwell (S = Rp θ) this is −σ θ Rb/Rr: the roller turns against the cam at the ratio of the radii, as a
gear pair would.

Sources: R. L. Norton, Cam Design and Manufacturing Handbook, 2nd ed. (2009), ch. 7 (the follower's
positions); the rolling rule is the kinematics of a disc rolling on a curve (e.g. J. L. Meriam, Engineering
Mechanics: Dynamics, rolling without slip).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import cast

import numpy as np

from camcad.errors import CamcadError
from camcad.profile.geometry import CamGeometry, rotate

#: the default step between frames, deg of cam angle (360 frames a turn)
FRAME_STEP_DEG = 1.0
#: sub-steps per frame of the arc-length integral of the roller's rolling (trapezoidal rule)
ROLLING_SUBSTEPS = 16


@dataclass(frozen=True)
class CamFrames:
    """One turn of a cam mechanism, frame by frame (fixed frame: cam centre at the origin; mm and deg).

    Attributes
    ----------
    kind : str
        The follower: "roller", "knife", "flat" or "oscillating".
    theta_deg : ndarray, shape (N,)
        Cam angle of each frame, deg (0, step, …, 360 − step).
    cam_turn_deg : ndarray, shape (N,)
        How far the cam has turned, σθ (deg, counter-clockwise positive).
    s, v, a : ndarray, shape (N,)
        The follower's law at each frame: mm (or rad of swing for an oscillating follower), per rad and
        per rad² of cam angle.
    pressure_angle_deg : ndarray, shape (N,)
        φ (deg); 0 for a flat face.
    pressure_angle_limit_deg : ndarray, shape (N,)
        The limit of |φ| that applies at each frame (deg); NaN where none applies.
    centre : ndarray, shape (N, 2)
        The roller centre (knife: its tip; flat face: the face's point on its axis), mm.
    contact : ndarray, shape (N, 2)
        Where the follower touches the cam, mm.
    normal : ndarray, shape (N, 2)
        The common normal at the contact, pointing away from the cam, fixed frame (unit vectors:
        dimensionless).
    roller_turn_deg : ndarray, shape (N,)
        The roller's absolute turn from frame 0 (deg, counter-clockwise positive); zeros without a roller.
    second_centre, second_contact : ndarray, shape (N, 2), or None
        The second roller of a conjugate pair and its contact with the counter-cam, mm.
    second_roller_turn_deg : ndarray, shape (N,) or None
        The second roller's turn (deg).
    pivot : (float, float) or None
        The oscillating follower's pivot (C, 0), mm.
    profile, pitch, outer, counter : ndarray, shape (M, 2), or None
        The cam's curves in its own frame (at θ = 0), mm: profile, pitch curve, the groove's outer flank and
        the counter-cam.
    base_radius, roller_radius : float
        Rb and Rr, mm (Rr = 0 for a knife or a flat face).
    offset : float
        e, the translating follower's axis x = e, mm.
    face : (float, float) or None
        The flat face's extent along x, relative to its axis, mm.
    """

    kind: str
    theta_deg: np.ndarray
    cam_turn_deg: np.ndarray
    s: np.ndarray
    v: np.ndarray
    a: np.ndarray
    pressure_angle_deg: np.ndarray
    pressure_angle_limit_deg: np.ndarray
    centre: np.ndarray
    contact: np.ndarray
    normal: np.ndarray
    roller_turn_deg: np.ndarray
    second_centre: np.ndarray | None
    second_contact: np.ndarray | None
    second_roller_turn_deg: np.ndarray | None
    pivot: tuple[float, float] | None
    profile: np.ndarray
    pitch: np.ndarray | None
    outer: np.ndarray | None
    counter: np.ndarray | None
    base_radius: float
    roller_radius: float
    offset: float
    face: tuple[float, float] | None

    @property
    def count(self) -> int:
        """Number of frames."""
        return int(self.theta_deg.size)

    def cam_points(self, curve: np.ndarray, frame: int) -> np.ndarray:
        """Points of a curve of the cam's own frame (e.g. ``profile``) where they are at ``frame``, mm."""
        angle = math.radians(float(self.cam_turn_deg[frame]))
        return rotate(np.asarray(curve, dtype=float), np.full(len(curve), angle))


def frame_angles(step_deg: float = FRAME_STEP_DEG) -> np.ndarray:
    """Cam angles of the frames of one turn, deg: 0, step, …, 360 − step (``step_deg`` must divide 360).

    Examples
    --------
    >>> frame_angles(90.0).tolist()
    [0.0, 90.0, 180.0, 270.0]
    >>> len(frame_angles())
    360
    """
    step = float(step_deg)
    if not math.isfinite(step) or step <= 0.0 or step > 90.0:
        raise CamcadError(f"frame step {step_deg!r} deg is out of range", "--animate-step",
                          "give a step between 0.05 and 90 deg that divides 360, e.g. 1 or 2")
    count = round(360.0 / step)
    if abs(count * step - 360.0) > 1e-9 * 360.0 or count > 7200:
        raise CamcadError(f"a frame step of {step:g} deg does not divide 360 deg into at most 7200 frames",
                          "--animate-step", "give a step that divides 360, e.g. 0.5, 1, 2 or 5")
    return np.arange(count) * (360.0 / count)


def rolling_arc(geometry: CamGeometry, theta: np.ndarray, second: bool = False,
                substeps: int = ROLLING_SUBSTEPS) -> np.ndarray:
    """S(θ) = ∫₀^θ |P'(t)| dt (mm) at the increasing cam angles ``theta`` (rad, the first 0): the arc length the
    roller centre has run along the pitch curve in the cam's frame (trapezoidal rule, ``substeps`` per
    interval; exact where the centre runs on a circle, as on a dwell)."""
    theta = np.asarray(theta, dtype=float)
    if theta.size == 0 or theta[0] != 0.0 or np.any(np.diff(theta) <= 0.0):
        raise ValueError("theta must increase from 0")
    fraction = np.arange(substeps) / substeps
    fine = np.append((theta[:-1, None] + np.diff(theta)[:, None] * fraction).ravel(), theta[-1])
    speed = geometry.pitch(fine, second).speed
    arc = np.concatenate(([0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(fine))))
    return arc[::substeps]


def cam_frames(result, step_deg: float = FRAME_STEP_DEG) -> CamFrames:
    """Every part of a synthesised cam mechanism at each frame of one turn (module docstring).

    Parameters
    ----------
    result : ProfileResult
        The synthesised cam (``camcad.synthesize``).
    step_deg : float
        Cam angle between frames, deg; must divide 360 (default 1: 360 frames).

    Returns
    -------
    CamFrames
        Positions in the fixed frame (mm), the cam's and the rollers' turns (deg), the law (mm or rad of
        swing) and the pressure angle (deg) at each frame.

    Examples
    --------
    A translating roller on a cycloidal rise: its centre is at height d + s on the axis, and the contact
    is one roller radius from it.

    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> follower = camcad.Follower("roller", base_radius=40.0, roller_radius=10.0)
    >>> frames = cam_frames(camcad.synthesize(law, follower, camcad.ProfileSettings(plots=False, design=False)))
    >>> frames.count, round(float(frames.centre[90, 1]), 9), round(float(frames.s[90]), 9)
    (360, 70.0, 20.0)
    >>> import numpy as np
    >>> round(float(np.hypot(*(frames.centre[45] - frames.contact[45]))), 9)
    10.0
    """
    geometry: CamGeometry = result.geometry
    follower = geometry.follower
    sigma = geometry.sigma
    theta_deg = frame_angles(step_deg)
    theta = np.radians(theta_deg)
    kin = geometry.kinematics(theta)
    pitch = geometry.pitch(theta)
    turn = sigma * theta
    rr = follower.roller_radius if follower.has_roller else 0.0
    centre = pitch.centre
    if follower.kind == "flat":
        contact = np.stack((sigma * kin.v, follower.base_radius + kin.s), axis=-1)
        normal = np.tile([0.0, 1.0], (theta.size, 1))
        phi = np.zeros_like(theta)
        limit = np.full_like(theta, np.nan)
    else:
        normal = rotate(pitch.normal, turn)
        contact = centre - rr * normal
        phi = pitch.pressure_angle
        limit = geometry.pressure_angle_limit(pitch.outward_speed)
    rolling = np.zeros_like(theta)
    if rr > 0.0:
        rolling = np.degrees(sigma * (theta - rolling_arc(geometry, theta) / rr))
    second_centre = second_contact = second_turn = None
    if follower.has_pair:
        other = geometry.pitch(theta, second=True)
        second_centre = other.centre
        second_contact = second_centre - rr * rotate(other.normal, turn)
        if rr > 0.0:
            second_turn = np.degrees(sigma * (theta - rolling_arc(geometry, theta, second=True) / rr))
        else:
            second_turn = np.zeros_like(theta)
    pivot = (float(cast(float, follower.pivot)), 0.0) if follower.kind == "oscillating" else None

    def points(curve):
        return None if curve is None else np.asarray(curve.polyline.points, dtype=float)

    return CamFrames(
        kind="knife" if follower.kind == "roller" and rr == 0.0 else follower.kind,
        theta_deg=theta_deg, cam_turn_deg=np.degrees(turn), s=kin.s, v=kin.v, a=kin.a,
        pressure_angle_deg=np.degrees(phi), pressure_angle_limit_deg=np.degrees(limit), centre=centre,
        contact=contact, normal=normal,
        roller_turn_deg=rolling, second_centre=second_centre, second_contact=second_contact,
        second_roller_turn_deg=second_turn, pivot=pivot,
        profile=cast(np.ndarray, points(result.profile)),
        pitch=points(result.pitch) if follower.kind != "flat" else None, outer=points(result.outer),
        counter=points(result.counter), base_radius=float(follower.base_radius), roller_radius=float(rr),
        offset=float(follower.offset), face=tuple(result.face_extent) if result.face_extent is not None else None)
