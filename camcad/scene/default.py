"""The built-in default design as a scene: what ``camcad profile`` runs with no argument.

A 25 mm lift, cycloidal rise over 120°, far dwell 60°, 3-4-5 polynomial return over 120°, near dwell
60°, on a translating roller follower with Rb = 50 mm, Rr = 10 mm and no offset, with the default
pressure-angle limits (camcad.profile.defaults). As TOML::

    name = "default"
    [law]
    standard = "cycloidal"
    return_standard = "poly345"
    phases = "0:120:rise,120:180:dwell,180:300:return,300:360:dwell"
    lift = 25.0
    [follower]
    type = "roller"
    base_radius = 50.0
    roller_radius = 10.0
"""

from __future__ import annotations

from camcad.profile import defaults


def default_phases() -> str:
    """The default phases as a ``--phases`` string (deg)."""
    parts, start = [], 0.0
    for kind, width in defaults.DEFAULT_PHASES_DEG:
        parts.append(f"{start:g}:{start + width:g}:{kind}")
        start += width
    return ",".join(parts)


def default_tables() -> dict:
    """The default design's scene as TOML tables ({name, law, follower})."""
    return {
        "name": defaults.DEFAULT_NAME,
        "law": {"standard": defaults.DEFAULT_RISE_SHAPE, "return_standard": defaults.DEFAULT_RETURN_SHAPE,
                "phases": default_phases(), "lift": defaults.DEFAULT_LIFT_MM},
        "follower": {"type": "roller", "base_radius": defaults.DEFAULT_BASE_RADIUS_MM,
                     "roller_radius": defaults.DEFAULT_ROLLER_RADIUS_MM, "offset": defaults.DEFAULT_OFFSET_MM,
                     "pressure_angle_limit_rise": defaults.PRESSURE_ANGLE_LIMIT_RISE_DEG,
                     "pressure_angle_limit_return": defaults.PRESSURE_ANGLE_LIMIT_RETURN_DEG},
    }
