"""Cam profile synthesis: followers, geometry and checks, base-radius design, outputs.

Library entry points (what the CLI and the scene pipeline call):

    follower = parse_follower(table, "scene.toml [follower]")      # or Follower(...)
    result = synthesize(law, follower, ProfileSettings(tol_mm=0.001))
    paths = write_outputs(result, outdir)                           # profile.dxf, law.csv, plots, report.json
    figures = report(result)                                        # SPEC.md keys

Modules: ``followers`` (Follower, FOLLOWER_FIELDS, parse_follower, swing_law), ``geometry``
(closed-form pitch curve, profile, pressure angle, radius of curvature), ``sampling`` (chord
tolerance, tangent arcs, spline), ``design`` (smallest base radius), ``synth`` (synthesize,
report), ``output`` (files), ``defaults`` (the built-in design).
"""

from camcad.profile.defaults import DEFAULT_NAME
from camcad.profile.design import BaseRadiusDesign, min_base_radius
from camcad.profile.followers import (FOLLOWER_FIELDS, FOLLOWER_KINDS, Follower, ScaledLaw, parse_follower, swing_law,
                        swing_of)
from camcad.profile.geometry import CamGeometry
from camcad.profile.output import build_drawing, write_outputs
from camcad.profile.synth import ProfileResult, ProfileSettings, report, synthesize


def default_design():
    """The built-in design of ``defaults``: (name, law, follower)."""
    from camcad.law.standard import compose
    from camcad.profile import defaults

    law = compose(defaults.DEFAULT_PHASES_DEG, defaults.DEFAULT_LIFT_MM, defaults.DEFAULT_RISE_SHAPE,
                  defaults.DEFAULT_RETURN_SHAPE)
    follower = Follower("roller", defaults.DEFAULT_BASE_RADIUS_MM, defaults.DEFAULT_ROLLER_RADIUS_MM,
                        defaults.DEFAULT_OFFSET_MM)
    return defaults.DEFAULT_NAME, law, follower


__all__ = ["BaseRadiusDesign", "CamGeometry", "DEFAULT_NAME", "FOLLOWER_FIELDS", "FOLLOWER_KINDS", "Follower",
           "ProfileResult", "ProfileSettings", "ScaledLaw", "build_drawing", "default_design", "min_base_radius",
           "parse_follower", "report", "swing_law", "swing_of", "synthesize", "write_outputs"]
