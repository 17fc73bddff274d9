"""The scene's [filter] section, and the pipeline step that applies it (camcad.fourier).
"""

from __future__ import annotations


from dataclasses import dataclass, field
from typing import Any


from camcad.errors import CamcadError
from camcad.law.law import MotionLaw, PiecewiseLinearLaw
from camcad.scene.fields import Field, read_table
from camcad.fourier.analysis import analyse
from camcad.fourier.export import ExportedLaw, export_polyline
from camcad.fourier.filter import FilterResult, filter_law
from camcad.fourier.leadin import LeadInResult, add_lead_in
from camcad.fourier.resonance import resonant_harmonics
from camcad.scene.fields import parse_rpm


# =============================================================================================
# The scene's [filter] section, and the pipeline step
# =============================================================================================

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
    Field("enabled", "bool", "", default=True),
]


@dataclass(frozen=True)
class FilterSettings:
    """Resonance filtering and lead-in settings (Hz, rpm, mm, deg); None = not given."""

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


@dataclass(frozen=True)
class FilterOutcome:
    """The pipeline step: the law to continue with (a closed polyline) and what was done to get it."""

    law: PiecewiseLinearLaw
    filtered: FilterResult | None
    lead_in: LeadInResult | None
    exported: ExportedLaw | None
    band_amplitudes: dict = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    @property
    def passed(self) -> bool:
        """The dwells were kept within their tolerance, the written law closes and a lead-in balanced."""
        return not ((self.filtered is not None and not self.filtered.dwells_kept)
                    or (self.exported is not None and not self.exported.closed)
                    or (self.lead_in is not None and not self.lead_in.balanced))

    def report(self) -> dict:
        out: dict = {"pipeline_notes": list(self.notes)} if self.notes else {}
        if self.filtered is not None:
            out.update(self.filtered.report())
        if self.lead_in is not None:
            out["lead_in"] = self.lead_in.report()
        if self.exported is not None:
            out["export"] = self.exported.report()
        if self.band_amplitudes:
            out["final_band_amplitudes_mm"] = {str(k): v for k, v in self.band_amplitudes.items()}
        return out


def apply_filter(law: MotionLaw, settings: FilterSettings, *, fn_hz: float | None = None,
                 rpm=None, where: str = "[filter]") -> FilterOutcome:
    """Resonance filtering (when a natural frequency and a speed range are known) and lead-in segments
    (when ``lead_in_deg`` is set), in that order; returns the closed polyline law to continue with.

    ``fn_hz``/``rpm`` fill in what ``settings`` leaves out (e.g. from the scene's [dynamics] and [machine]).
    """
    fn = settings.fn_hz if settings.fn_hz is not None else fn_hz
    speeds = settings.rpm if settings.rpm is not None else rpm
    filtered = exported = lead = None
    current = law
    if fn is not None:
        if speeds is None:
            raise CamcadError("resonance filtering needs the speed range", where,
                              "add rpm = [n1, n2] to [filter] or [machine], or pass --rpm N1:N2")
        band = resonant_harmonics(fn, speeds, settings.band, settings.neighbours, settings.taper, where)
        filtered = filter_law(law, band, harmonics=settings.harmonics, keep_dwells=settings.keep_dwells,
                              dwell_tol=settings.dwell_tol_mm, start_window_deg=settings.start_window_deg)
        current = filtered.law
    elif settings.lead_in_deg is None:
        raise CamcadError("nothing to do: no natural frequency and no lead-in", where,
                          "give fn_hz (or a [dynamics] section) and rpm, or lead_in_deg")
    if settings.lead_in_deg is not None:
        lead = add_lead_in(current, settings.lead_in_deg, settings.lead_in_fraction,
                           step_deg=settings.step_deg, where=where)
        final = lead.law
    else:
        exported = export_polyline(current, step_deg=settings.step_deg,
                                   removed=filtered.band.removed if filtered else (),
                                   exact_dwells=settings.exact_dwells,
                                   drift_tol=filtered.dwell_tol / 4 if filtered else None, where=where)
        final = exported.law
    band_after = {}
    notes = []
    if filtered is not None and filtered.band.removed:
        # what the written law carries at the removed harmonics (the lead-in's plateaus and exact dwells
        # put some of it back), against what the original had there
        after = analyse(final, max(filtered.band.removed))
        band_after = {int(k): float(after.amplitudes[k - 1]) for k in filtered.band.removed}
        before = sum(2 * abs(filtered.spectrum.coefficients[k - 1]) for k in filtered.band.removed)
        now = sum(band_after.values())
        if lead is not None and before > 0:
            notes.append(f"the lead-in plateaus (jumps of a) have harmonics of their own: the written law carries "
                         f"{now:.3g} mm summed over the removed harmonics, {100 * now / before:.0f} % of the "
                         f"original's {before:.3g} mm")
    return FilterOutcome(final, filtered, lead, exported, band_after, tuple(notes))


