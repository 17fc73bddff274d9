"""Where a scene's follower meets its law: the follower of a ``[follower]`` section on a law, the law in the
follower's units, and the base radius sized when ``auto_base_radius`` asks.
"""

from __future__ import annotations

from typing import cast

from camcad.errors import CamcadError
from camcad.profile.design import min_base_radius
from camcad.profile.scaled_law import swing_law
from camcad.scene.fields import read_table
from camcad.scene.sections.follower import FOLLOWER_FIELDS, parse_follower, swing_of


def follower_for_law(table, where: str, law):
    """The follower of a [follower] table on ``law`` (mm, or mm of the roller's arc for an oscillating
    follower): (follower, the law in follower units, scale to mm at the roller, notes).

    An oscillating follower's law becomes a swing (``swing_law``; ``swing`` deg, else arc / arm), and
    ``auto_base_radius`` sizes the base radius as the smallest that meets the limits (``min_base_radius``).
    This is the one place where a scene's follower meets its law: the profile, the contact and the phase
    limits all go through it.
    """
    follower = parse_follower(table, where)
    notes: list[str] = []
    scale = 1.0
    if follower.kind == "oscillating":
        arm = cast(float, follower.arm)  # parse_follower validated it
        law = swing_law(law, arm_mm=arm, swing_deg=swing_of(table, where))
        scale = arm      # ψ (rad) → arc of the roller centre (mm)
    if read_table(table, FOLLOWER_FIELDS, where)["auto_base_radius"]:
        design = min_base_radius(law, follower)
        if design.rb_min is None:
            raise CamcadError("no base radius meets the limits: " + "; ".join(design.notes), where,
                              "relax the pressure-angle or curvature limits, or change the follower")
        follower = follower.with_base_radius(design.rb_min)
        notes.append(f"base radius {design.rb_min:.9g} mm: the smallest that meets the limits "
                     f"(limited by {design.limited_by})")
    return follower, law, scale, notes
