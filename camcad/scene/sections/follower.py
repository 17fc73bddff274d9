"""The scene's ``[follower]`` section (mm, deg) → a validated ``Follower``."""

from __future__ import annotations

import math

from camcad.errors import CamcadError
from camcad.law.motion_table import ProfileFollower
from camcad.profile import defaults
from camcad.profile.followers import FOLLOWER_KINDS, Follower
from camcad.scene.fields import Field, read_table

# --------------------------------------------------------------------------------------------
# Scene section [follower]
# --------------------------------------------------------------------------------------------

FOLLOWER_FIELDS: list[Field] = [
    Field("type", "str", choices=FOLLOWER_KINDS, default="roller",
          help="roller, knife, flat or oscillating"),
    Field("base_radius", "float", "mm", positive=True, help="base-circle radius of the profile"),
    Field("auto_base_radius", "bool", default=False,
          help="use the smallest base radius that meets the pressure-angle and curvature limits"),
    Field("roller_radius", "float", "mm", minimum=0.0, help="roller radius (0 = knife edge)"),
    Field("offset", "float", "mm", default=0.0, help="offset e of a translating follower's axis"),
    Field("pivot", "float", "mm", positive=True, help="pivot distance C of an oscillating follower"),
    Field("arm", "float", "mm", positive=True, help="arm length L of an oscillating follower"),
    Field("initial_angle", "float", "deg", minimum=0.0, maximum=180.0,
          help="arm angle γ0 on the base circle (oscillating; instead of base_radius)"),
    Field("pressure_angle_limit_rise", "float", "deg", minimum=0.0, maximum=90.0,
          default=defaults.PRESSURE_ANGLE_LIMIT_RISE_DEG),
    Field("pressure_angle_limit_return", "float", "deg", minimum=0.0, maximum=90.0,
          default=defaults.PRESSURE_ANGLE_LIMIT_RETURN_DEG),
    Field("reversible", "bool", default=False),
    Field("cw", "bool", default=False),
    Field("groove", "bool", default=False),
    Field("pair_distance", "float", "mm", positive=True),
    Field("pair_angle", "float", "deg", minimum=0.0, maximum=180.0),
    Field("rho_min", "float", "mm", minimum=0.0, help="smallest convex radius of curvature allowed"),
    Field("swing", "float", "deg", positive=True,
          help="total swing of an oscillating follower (scales the law)"),
]


def parse_follower(table, where: str) -> Follower:
    """The scene's ``[follower]`` table (mm, deg) → a validated ``Follower``.

    ``roller_radius`` is required for roller and oscillating followers, ``pivot`` and ``arm``
    for oscillating ones; an oscillating follower takes ``base_radius`` or ``initial_angle``
    (γ0, then Rb = √(C² + L² − 2CL cos γ0) − Rr). ``swing`` is read by ``swing_of``.
    """
    values = read_table(table, FOLLOWER_FIELDS, where)
    kind = values["type"]
    roller = values["roller_radius"]
    if kind == "knife":
        if roller not in (None, 0.0):
            raise CamcadError("a knife-edge follower has no roller", where, "drop roller_radius")
        roller = 0.0
    elif kind in ("roller", "oscillating") and roller is None:
        raise CamcadError(f"missing value 'roller_radius' (mm) for a {kind} follower", where,
                          "add roller_radius = ... (0 for a knife edge)")
    elif kind == "flat":
        if roller not in (None, 0.0):
            raise CamcadError("a flat-faced follower has no roller", where, "drop roller_radius")
        roller = 0.0
    if kind != "oscillating":
        for key in ("pivot", "arm", "initial_angle", "pair_angle", "swing"):
            if values[key] is not None:
                raise CamcadError(f"'{key}' is for an oscillating follower, this one is {kind!r}", where,
                                  f"drop {key} or set type = \"oscillating\"")
    base = values["base_radius"]
    if kind == "oscillating":
        if values["pivot"] is None or values["arm"] is None:
            raise CamcadError("an oscillating follower needs 'pivot' and 'arm' (mm)", where,
                              "add pivot = ... and arm = ...")
        if values["initial_angle"] is not None:
            if base is not None:
                raise CamcadError("give base_radius or initial_angle, not both", where,
                                  "drop one of them: each fixes the other")
            c, arm, gamma0 = values["pivot"], values["arm"], math.radians(values["initial_angle"])
            base = math.sqrt(c**2 + arm**2 - 2.0 * c * arm * math.cos(gamma0)) - roller
            if not base > 0.0:
                raise CamcadError(f"initial_angle {values['initial_angle']:g} deg gives base radius "
                                  f"{base:g} mm", where, "use a larger initial angle")
    if values["auto_base_radius"]:
        if base is not None:
            raise CamcadError("base_radius and auto_base_radius both choose the base radius", where,
                              "give only one of them")
        base = _placeholder_base(kind, values, roller)  # until follower_for_law sizes it for its law
    if base is None:
        raise CamcadError("missing value 'base_radius' (mm)", where,
                          "add base_radius = ... (or auto_base_radius = true)")
    follower = Follower(
        kind=kind, base_radius=base, roller_radius=roller, offset=values["offset"],
        pivot=values["pivot"], arm=values["arm"], cw=values["cw"],
        pressure_angle_limit_rise_deg=_limit(values["pressure_angle_limit_rise"]),
        pressure_angle_limit_return_deg=_limit(values["pressure_angle_limit_return"]),
        reversible=values["reversible"], groove=values["groove"],
        pair_distance=values["pair_distance"], pair_angle_deg=values["pair_angle"],
        rho_min=values["rho_min"])
    return follower.validate(where)


def _placeholder_base(kind: str, values: dict, roller: float) -> float:
    """A base radius (mm) the follower's own checks accept, held until ``follower_for_law`` sizes it:
    the prime circle clear of the offset (translating), or a roller centre the arm can reach midway
    between |C − L| and C + L (oscillating)."""
    if kind == "oscillating":
        c, arm = values["pivot"], values["arm"]
        low, high = max(abs(c - arm), roller), c + arm
        return max(0.5 * (low + high) - roller, 1e-9 * high) if high > low else 1.0
    return max(1.0, abs(values["offset"]) - roller + 1.0)


def swing_of(table, where: str) -> float | None:
    """The ``swing`` (deg) of a scene's [follower] table, or None."""
    return read_table(table, FOLLOWER_FIELDS, where)["swing"]


def _limit(value: float | None) -> float | None:
    """A limit of 0 or 90 deg means "not checked" in a scene file."""
    if value is None or value <= 0.0 or value >= 90.0:
        return None
    return value


def profile_follower(table, where: str) -> ProfileFollower | None:
    """The follower of a scene's [follower] table as a radius-vector table needs it (kind, roller, offset,
    pivot, arm, turn), or None without a table."""
    if not isinstance(table, dict):
        return None
    values = read_table(table, FOLLOWER_FIELDS, where)
    kind = "oscillating" if values["type"] == "oscillating" else "translating"
    if values["type"] == "flat":
        raise CamcadError("a radius-vector table needs a roller follower (a flat face touches the profile "
                          "elsewhere)", where, "give type = \"roller\", \"knife\" or \"oscillating\"")
    return ProfileFollower(kind, float(values["roller_radius"] or 0.0), float(values["offset"]), values["pivot"],
                           values["arm"], bool(values["cw"]))
