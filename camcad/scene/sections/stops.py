"""The scene's ``[stops]`` section: the lever, its stop and the impact limit (the stop-impact model of
Podgorny et al. 2018, docs/references.md)."""

from __future__ import annotations

import math
from typing import Any

from camcad.dynamics.impact import STOP_SIDES, LeverBeam, StopModel, lever_stiffness, reduced_mass
from camcad.errors import CamcadError
from camcad.scene.fields import Field, read_table
from camcad.scene.sections.published import parse_published

STOPS_FIELDS = [
    Field("youngs_modulus_MPa", "float", "MPa", positive=True, help="E of the lever"),
    Field("second_moment_mm4", "float", "mm^4", positive=True, help="J of the lever's section"),
    Field("arm_a_mm", "float", "mm", positive=True, help="lever arm a (between the supports)"),
    Field("arm_b_mm", "float", "mm", positive=True, help="lever arm b (overhang to the contact point)"),
    Field("stiffness_N_per_m", "float", "N/m", positive=True, help="reduced stiffness c (instead of E, J, a, b)"),
    Field("lever_inertia_kg_m2", "float", "kg·m²", positive=True, help="J_A, moment of inertia about the pivot"),
    Field("lever_length_mm", "float", "mm", positive=True, help="l, pivot to the contact point"),
    Field("mass_kg", "float", "kg", positive=True, help="reduced mass at the contact point (instead of J_A, l)"),
    Field("stop_arm_mm", "float", "mm", positive=True,
          help="pivot to where the stop touches the lever (beyond the drive): the lever on the stop is a beam on "
               "three supports (Fig. 6); needs E, J, a, b"),
    Field("stop_stiffness_N_per_m", "float", "N/m", positive=True,
          help="the stop's contact stiffness: in series at stop_arm_mm, or alone in parallel at the contact point "
               "(overrides the beam)"),
    Field("restitution", "float", "", required=True, minimum=0.0, maximum=1.0, help="k, 5/9 for steel"),
    Field("damping_ratio", "float", "", required=True, minimum=0.0, maximum=0.99),
    Field("preload_mm", "float", "mm", required=True, positive=True),
    Field("stop", "str", "", default="upper", choices=STOP_SIDES),
    Field("ratio", "float", "", default=1.0, positive=True,
          help="displacement of the contact point per unit of the law's displacement"),
    Field("allowed_amplitude_mm", "float", "mm", positive=True, help="rebound limit"),
    Field("published", "table",
          help="published figures to compare with ([stops.published]: camcad.scene.sections.published)"),
]


def parse_stops(table: Any, where: str) -> StopModel:
    """Read a scene's [stops] table (units per key in STOPS_FIELDS) into a StopModel.

    The lever's stiffness comes from youngs_modulus_MPa, second_moment_mm4, arm_a_mm, arm_b_mm
    (c = 3EJ/((a+b)b²)) or from stiffness_N_per_m; its mass from lever_inertia_kg_m2 and
    lever_length_mm (m = J_A/l²) or from mass_kg.
    """
    values = read_table(table, STOPS_FIELDS, where)
    lever = ("youngs_modulus_MPa", "second_moment_mm4", "arm_a_mm", "arm_b_mm")
    stiffness = _one_of(values, lever, ("stiffness_N_per_m",), where, "the lever's stiffness")
    if stiffness == "stiffness_N_per_m":
        c = values["stiffness_N_per_m"]
    else:
        c = lever_stiffness(*(values[key] for key in lever))
    inertia = ("lever_inertia_kg_m2", "lever_length_mm")
    mass_from = _one_of(values, inertia, ("mass_kg",), where, "the lever's reduced mass")
    mass = values["mass_kg"] if mass_from == "mass_kg" else reduced_mass(*(values[key] for key in inertia))
    added, beam = _on_stop(values, c, lever, stiffness, where)
    return StopModel(mass, c, added, values["restitution"], values["damping_ratio"],
                     values["preload_mm"], values["stop"], values["ratio"], values["allowed_amplitude_mm"], beam)


def _on_stop(values: dict, c: float, lever: tuple[str, ...], stiffness_from: str, where: str):
    """(stiffness the stop adds at the contact point, N/m; the LeverBeam or None): the lever on three supports
    when the scene gives stop_arm_mm, else the stop's contact stiffness in parallel (the override)."""
    arm, contact = values["stop_arm_mm"], values["stop_stiffness_N_per_m"]
    if arm is None:
        if contact is None:
            raise CamcadError("missing the stop: give stop_arm_mm (the lever on its stop as a beam) or "
                              "stop_stiffness_N_per_m (the stop's stiffness in parallel)", where,
                              "add stop_arm_mm = ... (pivot to where the stop touches the lever, mm)")
        return contact, None
    if stiffness_from != lever[0]:
        raise CamcadError("stop_arm_mm needs the lever as a beam (youngs_modulus_MPa, second_moment_mm4, arm_a_mm, "
                          "arm_b_mm), not stiffness_N_per_m", where, "give the lever's E, J, a and b")
    a, b = values["arm_a_mm"], values["arm_b_mm"]
    if not arm > a:
        raise CamcadError(f"stop_arm_mm {arm:g} mm is not beyond the drive (arm_a_mm {a:g} mm)", where,
                          "give the distance from the pivot to the stop's contact, greater than arm_a_mm")
    if arm > 10.0 * (a + b):
        raise CamcadError(f"stop_arm_mm {arm:g} mm is more than ten lever lengths", where, "check the unit: mm")
    beam = LeverBeam(values["youngs_modulus_MPa"], values["second_moment_mm4"], a, b, arm,
                     math.inf if contact is None else contact)
    on_stop = beam.stop_stiffness_n_per_m
    if not math.isfinite(on_stop):
        raise CamcadError(f"a rigid stop at the reduced mass (stop_arm_mm {arm:g} = arm_a_mm + arm_b_mm) holds it "
                          "still: no frequency on the stop", where,
                          "give the stop's contact stiffness stop_stiffness_N_per_m, or where else the stop touches")
    return on_stop - c, beam


def published_of(table: Any, where: str):
    """The [stops.published] figures of a [stops] table (camcad.scene.sections.published), or None."""
    if not isinstance(table, dict) or table.get("published") is None:
        return None
    return parse_published(table["published"], where[:-1] + ".published]" if where.endswith("]") else where)




def _one_of(values: dict, group: tuple[str, ...], alternative: tuple[str, ...], where: str, what: str) -> str:
    given = [key for key in group if values[key] is not None]
    other = [key for key in alternative if values[key] is not None]
    if given and other:
        raise CamcadError(f"{what} is given twice ({', '.join(given + other)})", where,
                          f"give either {', '.join(group)} or {', '.join(alternative)}")
    if other:
        return other[0]
    if len(given) != len(group):
        missing = [key for key in group if values[key] is None]
        raise CamcadError(f"missing value '{missing[0]}' for {what}", where,
                          f"give {', '.join(group)}, or {', '.join(alternative)}")
    return group[0]


