"""Cam profile synthesis: followers, geometry and checks, base-radius design, outputs.

Library entry points (what the CLI and the scene pipeline call):

    follower = Follower("roller", base_radius=40.0, roller_radius=10.0)
    result = synthesize(law, follower, ProfileSettings(tol_mm=0.001))
    figures = report(result)                                        # docs/INTERFACE.md keys

Modules: ``followers`` (Follower), ``scaled_law`` (swing_law: the law in follower units), ``geometry``
(closed-form pitch curve, profile, pressure angle, radius of curvature), ``sampling`` (chord
tolerance, tangent arcs, spline), ``design`` (smallest base radius), ``synth`` (synthesize,
report), ``defaults`` (the built-in design). The scene's [follower] section is read by
``camcad.scene.follower``; the output files are written by ``camcad.report.profile_files``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from camcad.lazy import lazy_exports

if TYPE_CHECKING:  # the names for type checkers and IDEs; at run time they load on first use
    from camcad.profile.defaults import DEFAULT_NAME
    from camcad.profile.design import BaseRadiusDesign, min_base_radius
    from camcad.profile.followers import FOLLOWER_KINDS, Follower
    from camcad.profile.geometry import CamGeometry
    from camcad.profile.scaled_law import ScaledLaw, swing_law
    from camcad.profile.summary import profile_report
    from camcad.profile.synth import ProfileResult, ProfileSettings, synthesize

#: public name -> the module that defines it (imported on first use: importing this package stays cheap)
_EXPORTS: dict[str, str] = {
    "BaseRadiusDesign": "camcad.profile.design",
    "CamGeometry": "camcad.profile.geometry",
    "DEFAULT_NAME": "camcad.profile.defaults",
    "FOLLOWER_KINDS": "camcad.profile.followers",
    "Follower": "camcad.profile.followers",
    "ProfileResult": "camcad.profile.synth",
    "ProfileSettings": "camcad.profile.synth",
    "ScaledLaw": "camcad.profile.scaled_law",
    "min_base_radius": "camcad.profile.design",
    "profile_report": "camcad.profile.summary",
    "swing_law": "camcad.profile.scaled_law",
    "synthesize": "camcad.profile.synth",
}


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())


def default_design():
    """The built-in design ``camcad profile`` runs without a law: (name, law, follower).

    Returns
    -------
    tuple
        The design's name (str), its law (a MotionLaw: θ in rad, s in mm) and its Follower (mm).

    Examples
    --------
    >>> from camcad.profile import default_design
    >>> name, law, follower = default_design()
    >>> [p.kind for p in law.phases], follower.kind
    (['rise', 'dwell', 'return', 'dwell'], 'roller')
    """
    from camcad.law.standard import compose
    from camcad.profile import defaults
    from camcad.profile.followers import Follower

    law = compose(
        defaults.DEFAULT_PHASES_DEG,
        defaults.DEFAULT_LIFT_MM,
        defaults.DEFAULT_RISE_SHAPE,
        defaults.DEFAULT_RETURN_SHAPE,
    )
    follower = Follower(
        "roller", defaults.DEFAULT_BASE_RADIUS_MM, defaults.DEFAULT_ROLLER_RADIUS_MM, defaults.DEFAULT_OFFSET_MM
    )
    return defaults.DEFAULT_NAME, law, follower


__all__ = [
    "DEFAULT_NAME",
    "FOLLOWER_KINDS",
    "BaseRadiusDesign",
    "CamGeometry",
    "Follower",
    "ProfileResult",
    "ProfileSettings",
    "ScaledLaw",
    "default_design",
    "min_base_radius",
    "profile_report",
    "swing_law",
    "synthesize",
]
