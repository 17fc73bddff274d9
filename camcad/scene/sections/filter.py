"""The scene's ``[filter]`` section: the resonance band, the lead-in, and the limits the filtered law is
judged against, with their defaults (docs/analyses.md)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from camcad.balance.conditions import DEFAULT_TOL as BALANCE_TOLERANCE
from camcad.scene.fields import Field, parse_rpm, read_table

#: default limits of the filtered law (``camcad.scene.filtering``'s docstring)
DEFAULT_MAX_DEVIATION_FRACTION = 0.01       # of the lift
DEFAULT_DWELL_TOL_FRACTION = 1e-3           # of the lift
DEFAULT_MAX_PEAK_RATIO = 1.5
DEFAULT_CLOSURE_TOL = BALANCE_TOLERANCE     # of the lift
#: a harmonic whose amplitude is at most this fraction of the lift is zero: its initial phase is meaningless
ZERO_AMPLITUDE = 1e-12
#: harmonic counts at which the sampled max error is reported (and the least N, when --tol is given)
MAX_ERROR_AT = (1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024)

FILTER_FIELDS = [
    Field("fn_hz", "float", "Hz", positive=True,
          help="natural frequency of the follower system; omitted: taken from [dynamics]"),
    Field("rpm", "number_or_list", "rpm", positive=True,
          help="speed or [n1, n2] range (or \"n1:n2\"); omitted: taken from [machine]"),
    Field("band", "float", "fraction of fn", default=0.05, minimum=0.0, maximum=0.99,
          help="half-width of the resonance band, e.g. 0.05 for ±5 %"),
    Field("neighbours", "int", "harmonics", default=1, minimum=0, help="harmonics removed on each side"),
    Field("taper", "int", "harmonics", default=0, minimum=0, help="raised-cosine ramp beyond the removed ones"),
    Field("harmonics", "int", "", default=64, minimum=1, maximum=1 << 16, help="harmonics analysed"),
    Field("keep_dwells", "bool", "", default=True, help="compensate so the dwells stay within dwell_tol_mm"),
    Field("dwell_tol_mm", "float", "mm", positive=True, help="default 1e-3 of the lift"),
    Field("lead_in_deg", "float", "deg", positive=True, maximum=180.0, help="lead-in angle, e.g. 14"),
    Field("lead_in_fraction", "float", "of peak acceleration", default=0.1, positive=True, maximum=1.0),
    Field("start_window_deg", "float", "deg", default=7.0, positive=True, maximum=90.0),
    Field("step_deg", "float", "deg", default=0.1, positive=True, maximum=30.0,
          help="vertex step of the filtered polyline"),
    Field("exact_dwells", "bool", "", default=False,
          help="write the filtered law with a = 0 on the dwells (brings part of the band back)"),
    Field("max_deviation_mm", "float", "mm", positive=True,
          help="largest deviation of the written law from the original; default 1 % of the lift"),
    Field("max_peak_accel_ratio", "float", "", default=DEFAULT_MAX_PEAK_RATIO, positive=True,
          help="largest peak acceleration of the written law over the original's"),
    Field("closure_tol", "float", "of the lift", default=DEFAULT_CLOSURE_TOL, positive=True, maximum=0.1,
          help="closure of the written law (s and v gaps over the cycle)"),
    Field("enabled", "bool", "", default=True),
]


@dataclass(frozen=True)
class FilterSettings:
    """Resonance filtering and lead-in settings (Hz, rpm, mm, deg) and the limits of the result; None = not given."""

    fn_hz: float | None = None
    rpm: tuple[float, float] | None = None
    band: float = 0.05
    neighbours: int = 1
    taper: int = 0
    harmonics: int = 64
    keep_dwells: bool = True
    dwell_tol_mm: float | None = None
    lead_in_deg: float | None = None
    lead_in_fraction: float = 0.1
    start_window_deg: float = 7.0
    step_deg: float = 0.1
    exact_dwells: bool = False
    max_deviation_mm: float | None = None
    max_peak_accel_ratio: float = DEFAULT_MAX_PEAK_RATIO
    closure_tol: float = DEFAULT_CLOSURE_TOL
    enabled: bool = True


def parse_filter(table: Any, where: str = "[filter]") -> FilterSettings:
    """A scene's ``[filter]`` table → FilterSettings (unknown keys, types and ranges checked)."""
    if isinstance(table, dict) and isinstance(table.get("rpm"), str):
        table = {**table, "rpm": list(parse_rpm(table["rpm"], f"{where} rpm"))}
    values = read_table(table, FILTER_FIELDS, where)
    rpm = values.pop("rpm")
    if rpm is not None:
        rpm = parse_rpm(rpm, f"{where} rpm")
    return FilterSettings(rpm=rpm, **values)


