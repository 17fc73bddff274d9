"""The scene's ``[contact]`` section: materials, loads and the allowable stress (Hertz contact, camcad.contact)."""

from __future__ import annotations

from typing import Any

from camcad.contact import ContactParams
from camcad.errors import CamcadError
from camcad.scene.fields import Field, read_table

CLOSURES = ("force", "form")

CONTACT_FIELDS: list[Field] = [
    Field("cam_modulus", unit="MPa", required=True, positive=True,
          help="(Young's modulus of the cam, e.g. 2.1e5 for steel)"),
    Field("cam_poisson", required=True, minimum=0.0, maximum=0.5,
          help="(Poisson's ratio of the cam, e.g. 0.3)"),
    Field("follower_modulus", unit="MPa", required=True, positive=True,
          help="(Young's modulus of the roller or flat face)"),
    Field("follower_poisson", required=True, minimum=0.0, maximum=0.5,
          help="(Poisson's ratio of the roller or flat face)"),
    Field("width", unit="mm", required=True, positive=True,
          help="(contact width L: the narrower of cam and roller)"),
    Field("mass", unit="kg", required=True, minimum=0.0,
          help="(follower mass reduced to the contact point)"),
    Field("allowable_stress", unit="MPa", required=True, positive=True,
          help="(allowable contact stress [sigma_H])"),
    Field("closure", "str", default="force", choices=CLOSURES,
          help="force: a spring keeps the follower on the cam; form: a groove or conjugate cam"),
    Field("spring_rate", unit="N/mm", minimum=0.0, help="(spring rate, needed for closure = force)"),
    Field("preload", unit="N", help="(spring force at the lowest follower position)"),
    Field("load", unit="N", help="(external or technological load on the follower, N)"),
    Field("load_range_deg", "list", unit="deg",
          help="([start, end] cam angles where the load acts; all the cycle if not given)"),
    Field("friction", minimum=0.0, help="(friction coefficient in the follower guide)"),
    Field("roller_radius", unit="mm", positive=True,
          help="(only when the [follower] section does not give it)"),
]





def parse_contact(table: Any, where: str) -> ContactParams:
    """A scene's ``[contact]`` section → ContactParams (unknown keys, missing values, wrong types
    and units give a one-line CamcadError naming ``where``)."""
    values = read_table(table, CONTACT_FIELDS, where)
    assumed: list[str] = []
    if values["closure"] == "force":
        for name, unit in (("spring_rate", "N/mm"), ("preload", "N")):
            if values[name] is None:
                raise CamcadError(f"missing value '{name}' ({unit}) for a force-closed follower", where,
                                  f"add {name} = ... or set closure = \"form\" for a groove cam")
        if values["spring_rate"] == 0.0 and values["preload"] <= 0.0:
            raise CamcadError("a force-closed follower needs a spring: spring_rate and preload are 0",
                              where, "give the spring's rate and preload, or closure = \"form\"")
    for name, unit in (("spring_rate", "N/mm"), ("preload", "N"), ("load", "N"), ("friction", "")):
        if values[name] is None:
            values[name] = 0.0
            if name in ("load", "friction") or values["closure"] == "force":
                assumed.append(f"{name} = 0{(' ' + unit) if unit else ''} (not given)")
    load_range = values["load_range_deg"]
    if load_range is not None:
        if (len(load_range) != 2 or any(isinstance(x, bool) or not isinstance(x, (int, float))
                                         for x in load_range)):
            raise CamcadError(f"'load_range_deg' must be [start, end] in deg, got {load_range!r}",
                              where, "write load_range_deg = [90.0, 180.0]")
        load_range = (float(load_range[0]), float(load_range[1]))
    return ContactParams(
        cam_modulus=values["cam_modulus"], cam_poisson=values["cam_poisson"],
        follower_modulus=values["follower_modulus"], follower_poisson=values["follower_poisson"],
        width=values["width"], mass=values["mass"], allowable_stress=values["allowable_stress"],
        closure=values["closure"], spring_rate=values["spring_rate"], preload=values["preload"],
        load=values["load"], load_range_deg=load_range, friction=values["friction"],
        roller_radius=values["roller_radius"], assumed=tuple(assumed))


