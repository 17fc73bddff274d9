"""A mechanism of a scene in motion: the cam and its follower (``camcad.profile.animation``) and, with a
``[linkage]``, the linkage after the follower, frame by frame.

The linkage's joints come from ``camcad.linkage.analysis.Linkage.joints`` at the follower's swing ψ of each
frame (rad, from the roller on the base circle), in the cam's fixed frame (mm): the input link turns with
the follower's arm about its pivot, the coupler and the output link follow, and the working member's
position y = Π(ψ(θ)) (rad or mm) is given beside them. A linkage given as a table or a ratio has no
geometry to draw: only its working member's y is given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camcad.errors import CamcadError
from camcad.profile.animation import FRAME_STEP_DEG, CamFrames, cam_frames, frame_angles

#: the links of the linkage's drawing: (joint, joint, what), joints named as ``Linkage.joints`` names them
FOURBAR_LINKS = (("O", "A", "input link (on the follower's shaft)"), ("A", "B", "coupler"),
                 ("C", "B", "output link (working member)"))
SIXBAR_LINKS = (("O", "A", "input link (on the follower's shaft)"), ("A", "B", "coupler"),
                ("C", "B", "output link"), ("C", "D", "second input link (rigid with the output link)"),
                ("D", "E", "second coupler"), ("F", "E", "second output link (working member)"))


@dataclass(frozen=True)
class LinkageFrames:
    """The linkage after the follower at each frame (fixed frame of the cam, mm).

    Attributes
    ----------
    joints : dict of str to ndarray, shape (N, 2)
        Every joint at every frame: O (the follower's pivot), A, B, C (and D, E, F of a six-bar; P a coupler
        point), mm.
    links : tuple of (str, str, str)
        The links to draw: two joints and what the link is.
    fixed : tuple of str
        The joints fixed to the frame (pivots).
    transmission_deg : list of ndarray, shape (N,)
        The transmission angle of each loop at each frame, deg.
    """

    joints: dict
    links: tuple
    fixed: tuple
    transmission_deg: list


@dataclass(frozen=True)
class MechanismFrames:
    """One mechanism of a scene in motion (``mechanism_frames``).

    Attributes
    ----------
    name : str
        The mechanism's name.
    cam : CamFrames
        The cam and its follower at each frame (mm, deg).
    linkage : LinkageFrames or None
        The linkage after the follower at each frame (mm); None without a drawable [linkage].
    working : ndarray, shape (N,), or None
        The working member's position from its position at θ = 0, in ``working_unit`` (rad or mm); None
        without a [linkage].
    working_unit : str
        "rad" or "mm" ("" without a [linkage]).
    law_unit : str
        The follower law's unit: "mm", or "rad" of swing.
    """

    name: str
    cam: CamFrames
    linkage: LinkageFrames | None = None
    working: np.ndarray | None = None
    working_unit: str = ""
    law_unit: str = "mm"

    @property
    def count(self) -> int:
        """Number of frames."""
        return self.cam.count


def linkage_frames(linkage, psi: np.ndarray) -> LinkageFrames:
    """The joints of ``linkage`` (``camcad.linkage.analysis.Linkage``) at the swings ``psi`` (rad), mm.

    Examples
    --------
    A parallelogram four-bar turns its output link with its input link:

    >>> import math
    >>> from camcad.linkage.analysis import Linkage, Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 1.0, -1),), theta0=math.pi / 2)
    >>> frames = linkage_frames(lk, np.array([0.0, 0.5]))
    >>> [round(float(v), 12) for v in frames.joints["B"][0]], frames.fixed
    ([3.0, 1.0], ('O', 'C'))
    """
    psi = np.asarray(psi, dtype=float)
    raw = linkage.joints(psi)
    joints = {name: np.stack((np.real(z) * np.ones_like(psi), np.imag(z) * np.ones_like(psi)), axis=-1)
              for name, z in raw.items()}
    six = len(linkage.loops) > 1
    return LinkageFrames(joints=joints, links=SIXBAR_LINKS if six else FOURBAR_LINKS,
                         fixed=("O", "C", "F") if six else ("O", "C"),
                         transmission_deg=[np.degrees(mu) for mu in linkage.transmission(psi)])


def mechanism_frames(run, step_deg: float = FRAME_STEP_DEG) -> MechanismFrames:
    """The frames of one mechanism of a scene run (``camcad.scene.pipeline.MechanismRun`` with a profile).

    Parameters
    ----------
    run : MechanismRun
        A mechanism the pipeline analysed, with its profile (and its ``[linkage]``, when it has one).
    step_deg : float
        Cam angle between frames, deg (must divide 360).

    Returns
    -------
    MechanismFrames
        The cam and follower (mm, deg), the linkage's joints (mm) and the working member's position (rad or
        mm) at each frame.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> import camcad
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "cam.toml").write_text('''
    ... name = "cam"
    ... [law]
    ... standard = "cycloidal"
    ... phases = "0:90:rise,90:180:dwell,180:270:return,270:360:dwell"
    ... lift = 20.0
    ... [follower]
    ... type = "roller"
    ... base_radius = 40.0
    ... roller_radius = 10.0
    ... ''')
    >>> run = camcad.analyse_scene(folder / "cam.toml").runs["cam"]
    >>> frames = mechanism_frames(run, step_deg=2.0)
    >>> frames.count, frames.linkage is None, round(float(frames.cam.s[45]), 9)
    (180, True, 20.0)
    """
    return cam_mechanism_frames(run.name, run.profile, run.linkage, run.law, step_deg)


def cam_mechanism_frames(name: str, profile, context=None, law=None,
                         step_deg: float = FRAME_STEP_DEG) -> MechanismFrames:
    """The frames of a cam (``ProfileResult``) and, with ``context`` (``camcad.scene.linkage.LinkageContext``)
    and the follower's ``law``, the linkage after its follower (``mechanism_frames`` of a scene run, and
    ``camcad linkage analyse`` of a scene): mm, deg; the working member's position in rad or mm."""
    cam = cam_frames(profile, step_deg)
    unit = "rad" if cam.kind == "oscillating" else "mm"
    if context is None:
        return MechanismFrames(name, cam, law_unit=unit)
    theta = np.radians(cam.theta_deg)
    working = context.working_law(law).kinematics(theta).s
    drawn = None
    if context.linkage is not None and cam.kind == "oscillating":
        drawn = linkage_frames(context.linkage, cam.s)
    return MechanismFrames(name, cam, drawn, working - working[0], context.transfer.unit_out, unit)


@dataclass(frozen=True)
class LinkageMotion:
    """A linkage alone moving over its input range and back (``linkage_motion``): no cam drives it.

    Attributes
    ----------
    name : str
        The linkage's name.
    input_deg : ndarray, shape (N,)
        The input at each frame, deg from its position at the start of the range: up from 0 to the range's
        end, then back (the last frame one step before 0, so the motion loops).
    output_deg : ndarray, shape (N,)
        The output link's turn from its position at input 0, deg (the working member's Π of a linkage after a
        follower; the output link's turn of a function generator).
    linkage : LinkageFrames
        The joints at each frame (mm) and the loops' transmission angles (deg).
    input_label, output_label : str
        What the input and the output are (for the page's charts).
    target : ndarray, shape (M, 2), or None
        A curve the coupler point P is to trace (``camcad linkage path``), mm.
    target_output_deg : ndarray, shape (N,), or None
        The output the linkage is to give at each frame (a function generator's f), deg.
    """

    name: str
    input_deg: np.ndarray
    output_deg: np.ndarray
    linkage: LinkageFrames
    input_label: str = "input ψ"
    output_label: str = "output Π"
    target: np.ndarray | None = None
    target_output_deg: np.ndarray | None = None

    @property
    def count(self) -> int:
        """Number of frames."""
        return int(self.input_deg.size)


def sweep_angles(span_deg: float, step_deg: float = FRAME_STEP_DEG) -> np.ndarray:
    """The inputs of a there-and-back sweep of ``span_deg`` (deg, signed): ceil(|span|/step) equal steps out,
    the same back, 2·ceil(|span|/step) frames (the first 0, the turn-back at ``span_deg``).

    Examples
    --------
    >>> sweep_angles(30.0, 10.0).tolist()
    [0.0, 10.0, 20.0, 30.0, 20.0, 10.0]
    >>> len(sweep_angles(-25.0, 2.0))
    26
    """
    frame_angles(step_deg)                  # the same steps as a cam's frames: refused the same way
    span = float(span_deg)
    if not math.isfinite(span) or span == 0.0:
        raise CamcadError(f"an input range of {span_deg!r} deg has no motion to animate", "--animate",
                          "give the linkage a swing (--swing DEG), or leave --animate out")
    count = max(1, math.ceil(abs(span) / float(step_deg) - 1e-9))
    out = np.linspace(0.0, span, count + 1)
    return np.concatenate((out, out[-2:0:-1]))


def linkage_motion(linkage, span_rad: float, step_deg: float = FRAME_STEP_DEG, name: str = "linkage", *,
                   input_label: str = "input ψ", output_label: str = "output Π") -> LinkageMotion:
    """A linkage (``camcad.linkage.analysis.Linkage``) alone, moved over its input range [0, ``span_rad``] (rad)
    and back at ``step_deg`` (deg) between frames.

    Parameters
    ----------
    linkage : Linkage
        The linkage; its input ψ (rad) turns the input link by ``input_sense`` ψ from ``theta0``.
    span_rad : float
        The input range, rad (a follower's swing ψ_max; a function generator's input turn).
    step_deg : float
        Input angle between frames, deg (a step that divides 360, as a cam's).
    name, input_label, output_label : str
        The linkage's name and what its input and output are.

    Returns
    -------
    LinkageMotion
        The joints (mm), the input and the output's turn Π(ψ) (deg) at each frame.

    Examples
    --------
    A parallelogram four-bar turns its output link with its input link:

    >>> from camcad.linkage.analysis import Linkage, Loop
    >>> lk = Linkage((Loop((0.0, 0.0), (3.0, 0.0), 1.0, 3.0, 1.0, -1),), theta0=math.pi / 2)
    >>> motion = linkage_motion(lk, math.radians(30.0), 5.0)
    >>> motion.count, [round(float(v), 9) for v in motion.output_deg[:3]]
    (12, [0.0, 5.0, 10.0])
    """
    psi_deg = sweep_angles(math.degrees(span_rad), step_deg)
    psi = np.radians(psi_deg)
    drawn = linkage_frames(linkage, psi)
    closes = np.all([np.isfinite(xy).all() for xy in drawn.joints.values()])
    if not closes:
        raise CamcadError("the linkage does not close over its whole input range: there is nothing to draw where "
                          "it breaks", "--animate", "fix the linkage (see the analysis's checks), or leave "
                                                    "--animate out")
    output = np.degrees(linkage.position(psi, order=1)[0])
    return LinkageMotion(name, psi_deg, output, drawn, input_label, output_label)
