"""A mechanism of a scene in motion: the cam and its follower (``camcad.profile.animation``) and, with a
``[linkage]``, the linkage after the follower, frame by frame.

The linkage's joints come from ``camcad.linkage.analysis.Linkage.joints`` at the follower's swing ψ of each
frame (rad, from the roller on the base circle), in the cam's fixed frame (mm): the input link turns with
the follower's arm about its pivot, the coupler and the output link follow, and the working member's
position y = Π(ψ(θ)) (rad or mm) is given beside them. A linkage given as a table or a ratio has no
geometry to draw: only its working member's y is given.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from camcad.profile.animation import FRAME_STEP_DEG, CamFrames, cam_frames

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
    cam = cam_frames(run.profile, step_deg)
    unit = "rad" if cam.kind == "oscillating" else "mm"
    context = run.linkage
    if context is None:
        return MechanismFrames(run.name, cam, law_unit=unit)
    theta = np.radians(cam.theta_deg)
    working = context.working_law(run.law).kinematics(theta).s
    drawn = None
    if context.linkage is not None and cam.kind == "oscillating":
        drawn = linkage_frames(context.linkage, cam.s)
    return MechanismFrames(run.name, cam, drawn, working - working[0], context.transfer.unit_out, unit)
