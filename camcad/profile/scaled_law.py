"""A law in follower units: the swing of an oscillating follower, breakpoints, and descriptions of a law.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camcad.errors import CamcadError
from camcad.law.law import Kinematics, MotionLaw, Phase, PiecewiseLinearLaw

# --------------------------------------------------------------------------------------------
# Laws in follower units
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class ScaledLaw:
    """``law`` with s, v, a, j multiplied by ``factor`` (e.g. mm of lift → rad of swing).

    Parameters
    ----------
    law : MotionLaw
        The law scaled (θ in rad).
    factor : float
        The scale, in the new unit per unit of the law (rad per mm for a swing; dimensionless for mm to mm).

    Examples
    --------
    >>> import numpy as np
    >>> import camcad
    >>> from camcad.profile import ScaledLaw
    >>> law = camcad.compose([("rise", 180), ("return", 180)], 20.0)
    >>> half = ScaledLaw(law, 0.5)
    >>> float(half.kinematics(np.radians([180.0])).s[0])          # the 20 mm rise halved, mm
    10.0
    """

    law: MotionLaw
    factor: float

    @property
    def cycle(self) -> float:
        return self.law.cycle

    @property
    def phases(self) -> tuple[Phase, ...]:
        return self.law.phases

    def kinematics(self, theta) -> Kinematics:
        kin = self.law.kinematics(theta)
        f = self.factor
        return Kinematics(kin.theta, kin.s * f, kin.v * f, kin.a * f, kin.j * f)

    def breakpoints(self) -> np.ndarray:
        return law_breakpoints(self.law)

    def describe(self) -> str:
        return describe_law(self.law)


def swing_law(law: MotionLaw, *, arm_mm: float | None = None, swing_deg: float | None = None,
              samples: int = 8193) -> ScaledLaw:
    """An oscillating follower's law ψ(θ) in rad from a lift law in mm.

    With ``swing_deg`` the law is scaled so that its stroke max(s) − min(s) equals the swing;
    otherwise s is the arc travelled by the roller centre, ψ = s / L (``arm_mm``).

    Parameters
    ----------
    law : MotionLaw
        The lift law, s in mm, θ in rad.
    arm_mm : float, optional
        L, the arm from the pivot to the roller centre, mm (ψ = s/L).
    swing_deg : float, optional
        The stroke to scale the law to, deg (taken before ``arm_mm``).
    samples : int
        Points sampled over the cycle to find the law's stroke (a count).

    Returns
    -------
    ScaledLaw
        ψ(θ) in rad (its v, a, j in rad/rad, rad/rad², rad/rad³).

    Raises
    ------
    CamcadError
        Neither a swing nor a positive arm, or a law without stroke.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> import camcad
    >>> from camcad.profile import swing_law
    >>> law = camcad.compose([("rise", 180), ("return", 180)], 20.0)
    >>> round(math.degrees(swing_law(law, swing_deg=24.0).kinematics(np.radians([180.0])).s[0]), 9)
    24.0
    >>> round(float(swing_law(law, arm_mm=100.0).kinematics(np.radians([180.0])).s[0]), 12)    # 20 mm / 100 mm
    0.2
    """
    if swing_deg is not None:
        theta = np.linspace(0.0, law.cycle, samples)
        stroke = float(np.ptp(law.kinematics(theta).s))
        if not stroke > 0.0:
            raise CamcadError("the law has no stroke to scale to a swing", "law",
                              "check the law: its displacement is constant")
        return ScaledLaw(law, math.radians(swing_deg) / stroke)
    if arm_mm is None or not arm_mm > 0.0:
        raise CamcadError("an oscillating follower needs its arm length to turn lift into swing",
                          "follower", "give --arm L, or --swing DEG")
    return ScaledLaw(law, 1.0 / arm_mm)


def law_breakpoints(law: MotionLaw) -> np.ndarray:
    """θ (rad) in [0, cycle] where the curvature of the cam may jump: phase ends, the inner pieces of a
    composed law, and the jumps of a drawn law's acceleration (its repeated knots).

    The other knots of a drawn law are kinks of a (jumps of the jerk only): s, v and a, and with them
    the pitch curve's curvature, are continuous there, so they need no node of their own. Taking
    every knot made a 1,000,000-vertex law cost 1,000,000 profile points and minutes of synthesis.
    """
    points = {0.0, float(law.cycle)}
    for phase in law.phases:
        points.update((float(phase.start), float(phase.end)))
    inner = getattr(law, "breakpoints", None)
    if inner is not None:
        points.update(float(x) for x in np.asarray(inner()))
    if isinstance(law, PiecewiseLinearLaw):
        points.update(float(x) for x in law.x[:-1][np.diff(law.x) == 0])
    return merge_close(np.array(sorted(p for p in points if 0.0 <= p <= law.cycle)), 0.0, float(law.cycle))


def merge_close(points: np.ndarray, first: float, last: float, gap: float = 1e-9) -> np.ndarray:
    """Sorted ``points`` with any closer than ``gap`` (rad) to the previous kept one dropped, ``first``
    and ``last`` kept exactly: phase ends summed in floating point land an ulp from the cycle end,
    and a node there would be a zero-length segment in the drawing."""
    kept = [first]
    for p in points:
        if p - kept[-1] > gap and last - p > gap:
            kept.append(float(p))
    kept.append(last)
    return np.array(kept)


def describe_law(law: MotionLaw) -> str:
    """One ASCII line describing the law."""
    describe = getattr(law, "describe", None)
    if describe is not None:
        return describe()
    if isinstance(law, PiecewiseLinearLaw):
        return f"drawn acceleration polyline, {len(law.x)} vertices, cycle {math.degrees(law.cycle):.6g} deg"
    return type(law).__name__


def describe_phases(law: MotionLaw) -> str:
    """E.g. "rise 0-120, dwell 120-180, return 180-300, dwell 300-360" (deg), or "not given"."""
    if not law.phases:
        return "not given"
    return ", ".join(f"{p.kind} {math.degrees(p.start):.6g}-{math.degrees(p.end):.6g}" for p in law.phases)


