"""The scene's ``[stops.published]`` table: figures a source published for the stop impact, and which of
them the scene was calibrated to (``camcad.dynamics.rebound.PublishedImpact``).

    [stops.published]
    source = "Podgorny et al. 2018"
    rebound_mm = [[177, 0.022], [280, 0.07], [320, 0.078], [370, 0.092], [420, 0.105]]   # [rpm, mm]
    rebound_measured_mm = [[177, 0.02]]
    force_N = [[280, 4.137], [420, 6.2]]                                                  # [rpm, N]
    f_free_hz = 297.0            # computed in the source
    f_stop_hz = 768.0
    f_free_measured_hz = 268.0
    f_stop_measured_hz = 700.0
    calibrated = ["rebound_mm@280", "force_N@280", "f_free_hz", "f_stop_hz"]

A figure named in ``calibrated`` was used to choose the scene's inputs: reported as "calibrated", it
cannot validate the model; every other figure is reported as "validates".
"""

from __future__ import annotations

from typing import Any

from camcad.dynamics.rebound import PublishedFigure, PublishedImpact
from camcad.errors import CamcadError, excerpt
from camcad.scene.fields import Field, read_table

PUBLISHED_FIELDS: list[Field] = [
    Field("source", "str", default="", help="(the work the figures are taken from)"),
    Field("rebound_mm", "list", "rpm, mm", default=[], help="([[rpm, mm], ...] computed first rebounds)"),
    Field("rebound_measured_mm", "list", "rpm, mm", default=[], help="([[rpm, mm], ...] measured first rebounds)"),
    Field("force_N", "list", "rpm, N", default=[], help="([[rpm, N], ...] computed impact forces)"),
    Field("f_free_hz", unit="Hz", positive=True, help="(computed natural frequency off the stop)"),
    Field("f_stop_hz", unit="Hz", positive=True, help="(computed natural frequency on the stop)"),
    Field("f_free_measured_hz", unit="Hz", positive=True, help="(measured natural frequency off the stop)"),
    Field("f_stop_measured_hz", unit="Hz", positive=True, help="(measured natural frequency on the stop)"),
    Field("calibrated", "list", default=[],
          help="(the figures the scene was fitted to: \"rebound_mm@280\", \"force_N@280\", \"f_free_hz\", ...)"),
]


def _pairs(raw: Any, key: str, where: str) -> list[tuple[float, float]]:
    pairs = []
    for item in raw:
        if (not isinstance(item, list) or len(item) != 2
                or any(isinstance(x, bool) or not isinstance(x, (int, float)) for x in item)
                or not item[0] > 0 or not item[1] > 0):
            raise CamcadError(f"'{key}' holds {excerpt(item)}, not [rpm, value] with both > 0", where,
                              f"write {key} = [[280, 0.07], [420, 0.105]]")
        pairs.append((float(item[0]), float(item[1])))
    return pairs


def parse_published(table: Any, where: str) -> PublishedImpact:
    """A ``[stops.published]`` table (module docstring) → PublishedImpact; a ``calibrated`` name that matches
    no figure is an error (one line naming it and the figures there are)."""
    values = read_table(table, PUBLISHED_FIELDS, where)
    figures: list[PublishedFigure] = []
    for key, quantity, kind in (("rebound_mm", "rebound_mm", "computed"),
                                ("rebound_measured_mm", "rebound_mm", "measured"),
                                ("force_N", "force_N", "computed")):
        figures += [PublishedFigure(quantity, value, rpm, kind) for rpm, value in _pairs(values[key], key, where)]
    for key, quantity, kind in (("f_free_hz", "f_free_hz", "computed"), ("f_stop_hz", "f_stop_hz", "computed"),
                                ("f_free_measured_hz", "f_free_hz", "measured"),
                                ("f_stop_measured_hz", "f_stop_hz", "measured")):
        if values[key] is not None:
            figures.append(PublishedFigure(quantity, values[key], None, kind))
    keys = [f.key for f in figures]
    calibrated = set()
    for name in values["calibrated"]:
        if not isinstance(name, str) or name not in keys:
            raise CamcadError(f"calibrated names {excerpt(name)}, not one of the figures", where,
                              f"name one of: {', '.join(keys)}")
        calibrated.add(name)
    figures = [PublishedFigure(f.quantity, f.value, f.rpm, f.kind, f.key in calibrated) for f in figures]
    return PublishedImpact(tuple(figures), values["source"])
