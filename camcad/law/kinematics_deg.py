"""A law's kinematics at cam angles given in degrees: the public API's unit at the boundary."""

from __future__ import annotations

import numpy as np

from camcad.law.law import Kinematics, MotionLaw


def kinematics_deg(law: MotionLaw, theta_deg) -> Kinematics:
    """s, v, a, j of ``law`` at the cam angles ``theta_deg`` (degrees).

    Parameters
    ----------
    law : MotionLaw
        Any law (standard, composed, drawn).
    theta_deg : array_like
        Cam angles, deg.

    Returns
    -------
    Kinematics
        ``theta`` (rad), s (mm, or rad of swing), and the analogs v = ds/dθ (mm/rad), a = d²s/dθ² (mm/rad²),
        j = d³s/dθ³ (mm/rad³) per radian of cam angle (docs/INTERFACE.md); time derivatives at n rpm are v·ω, a·ω²,
        j·ω³ with ω = 2πn/60.

    Examples
    --------
    >>> from camcad.law.standard import compose
    >>> law = compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0, "cycloidal")
    >>> float(kinematics_deg(law, [45.0]).s[0])      # half the rise at half the rise angle
    10.0
    """
    return law.kinematics(np.radians(np.asarray(theta_deg, dtype=float)))
