"""The scene's ``[compare]`` section: the laws ``camcad compare`` puts side by side (``a``, ``b`` and further
``[compare.laws]``), and in ``[[compare.published]]`` tables the published figures to put beside camcad's, each
marked "published", "reproduced", "depends on chosen inputs" or "not reproduced" (``camcad.scene.commands.compare``).
"""

from __future__ import annotations

from typing import Any

from camcad.dynamics.compare import START_WINDOW_DEG
from camcad.errors import CamcadError
from camcad.scene.fields import Field, read_table

#: speeds of the contact-stress sweep drawn against speed (the batten study's Fig. 10)
CONTACT_CURVE_POINTS = 41
#: cam-angle samples per phase of the contact stress
CONTACT_SAMPLES = 2000
#: a published figure is reproduced when camcad's is within this fraction of it (unless the entry says)
DEFAULT_TOLERANCE = 0.05
SELECTIONS = ("A", "B", "A/B", "B/A", "reduction")

COMPARE_FIELDS = [
    Field("a", "str", help="(law A: a DXF drawing or table, relative to the scene; absent: the scene's [law])"),
    Field("b", "str", help="(law B: a DXF drawing or table, relative to the scene)"),
    Field("name_a", "str", help="(a name for law A in the report)"),
    Field("name_b", "str", help="(a name for law B in the report)"),
    Field("laws", "table", help="(further laws by name, NAME = \"file\", for the published figures' pairs)"),
    Field("harmonics", "int", default=32, minimum=1, maximum=1024, help="(harmonics listed side by side)"),
    Field("start_window_deg", "float", "deg", default=START_WINDOW_DEG, positive=True, maximum=90.0,
          help="(the start-of-motion window)"),
    Field("published", "list", help="(published figures to put beside camcad's: [[compare.published]] tables)"),
]

COMPARE_PUBLISHED_FIELDS = [
    Field("name", "str", required=True, help="(the figure in words)"),
    Field("value", "number_or_list", help="(the published value, or [low, high] for a range)"),
    Field("unit", "str", default=""),
    Field("figure", "str", help="(camcad's figure: stroke, peak_velocity, peak_accel_rigid, peak_accel_elastic, "
                                "start_accel_rigid, start_accel_elastic, start_load, start_load_pulse, "
                                "start_deformation, displacement_deviation, sigma_max, safety_factor, ...)"),
    Field("law", "str", default="A", choices=SELECTIONS, help="(which value: A, B, A/B, B/A or reduction)"),
    Field("pair", "list", help="([law A, law B] by name: A, B, law (the scene's) or a [compare.laws] name)"),
    Field("rpm", "float", "rpm", positive=True),
    Field("motion", "str", help="(rise, return, rise_2, ...; absent: the first motion)"),
    Field("source", "str", help="(where the source gives it)"),
    Field("input", "bool", default=False, help="(the figure is an input taken from the source)"),
    Field("calibrated", "bool", default=False,
          help="(camcad's inputs were chosen to meet this figure: depends_on says which)"),
    Field("tolerance", "float", default=DEFAULT_TOLERANCE, positive=True, help="(relative)"),
    Field("depends_on", "str", help="(the chosen inputs camcad's figure depends on)"),
    Field("why_not", "str", help="(why camcad does not reproduce the figure)"),
]


def parse_compare(table: Any, where: str) -> dict:
    """A scene's [compare] table (COMPARE_FIELDS; each [[compare.published]] by COMPARE_PUBLISHED_FIELDS)."""
    values = read_table(table, COMPARE_FIELDS, where)
    published = []
    for index, entry in enumerate(values["published"] or []):
        item = read_table(entry, COMPARE_PUBLISHED_FIELDS, f"{where} published #{index + 1}")
        if isinstance(item["value"], list) and len(item["value"]) != 2:
            raise CamcadError(f"published #{index + 1}: value must be a number or [low, high]", where,
                              "write value = 3.45 or value = [1.5, 1.8]")
        if item["figure"] is None and item["why_not"] is None:
            raise CamcadError(f"published #{index + 1} ({item['name']}) names no camcad figure", where,
                              "give figure = ..., or why_not = \"...\" when camcad cannot reproduce it")
        published.append(item)
    values["published"] = published
    laws = values["laws"] or {}
    for name, path in laws.items():
        if not isinstance(path, str) or name in ("A", "B", "law"):
            raise CamcadError(f"[compare.laws] {name} must name a law file (and not be A, B or law)", where,
                              f'write {name} = "law.dxf"')
    values["laws"] = dict(laws)
    return values
