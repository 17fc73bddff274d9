"""The pipeline's filter step (step 3): resonance filtering and lead-in, and the filtered law judged.

- ``apply_filter``: resonance filtering and lead-in (camcad.fourier) → the closed polyline law to continue with.
- ``judge_filter``: the written law against the original, as both are read back (from rest at s = 0):
  largest deviation, dwell deviation, peak acceleration ratio, closure — each a figure, a limit and a margin.
- ``filter_step``: step 3 of the scene pipeline, on the ``[filter]`` settings (``camcad.scene.sections.filter``).

Default limits (docs/analyses.md; change them with the options or the [filter] keys):

========================  ====================================  ================================
check                     default limit                          option / [filter] key
========================  ====================================  ================================
deviation from original   1 % of the lift (filtering only)       --max-deviation / max_deviation_mm
dwell deviation           1e-3 of the lift                       --dwell-tol / dwell_tol_mm
peak acceleration ratio   1.5 (filtered / original)              --max-peak-ratio / max_peak_accel_ratio
closure (s and v)         1e-5 of the lift (``camcad check``)    --closure-tol / closure_tol
========================  ====================================  ================================

A lead-in moves the law on purpose, so without a given ``max_deviation_mm`` its deviation is reported
as a figure only. An unbalanced law is refused before filtering (``force`` filters it anyway).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from camcad.arrays import unique
from camcad.dynamics.model import unit_key
from camcad.errors import CamcadError
from camcad.fourier.analysis import analyse
from camcad.fourier.export import ExportedLaw, export_polyline
from camcad.fourier.filter import FilterResult, filter_law
from camcad.fourier.leadin import LeadInResult, add_lead_in
from camcad.fourier.resonance import resonant_harmonics
from camcad.io.law_record import LawRecord
from camcad.law.law import MotionLaw, PiecewiseLinearLaw
from camcad.scene.analysis_report import AnalysisReport
from camcad.scene.sections.dynamics import parse_dynamics
from camcad.scene.sections.filter import (
    DEFAULT_DWELL_TOL_FRACTION,
    DEFAULT_MAX_DEVIATION_FRACTION,
    FilterSettings,
    parse_filter,
)
from camcad.verdict import Check, Verdict, Warning

# =============================================================================================
# Filtering and lead-in
# =============================================================================================

@dataclass(frozen=True)
class FilterOutcome:
    """The filter step's result: the law to continue with (a closed polyline) and what was done to get it."""

    law: PiecewiseLinearLaw
    filtered: FilterResult | None
    lead_in: LeadInResult | None
    exported: ExportedLaw | None
    band_amplitudes: dict = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    @property
    def passed(self) -> bool:
        """The dwells were kept within their tolerance, the written law closes and a lead-in balanced
        (the filter's own figures; ``judge_filter`` is the verdict on the written law)."""
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
                 rpm=None, where: str = "[filter]", unit: str = "mm") -> FilterOutcome:
    """Resonance filtering (when a natural frequency and a speed range are known) and lead-in segments
    (when ``lead_in_deg`` is set), in that order; returns the closed polyline law to continue with.

    ``fn_hz``/``rpm`` fill in what ``settings`` leaves out (e.g. from the scene's [dynamics] and [machine]);
    ``unit`` is the law's (mm, or rad for a swing), used in the notes.
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
                              dwell_tol=settings.dwell_tol_mm, start_window_deg=settings.start_window_deg, unit=unit)
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


# =============================================================================================
# The verdict on the written law
# =============================================================================================

@dataclass(frozen=True)
class WrittenFigures:
    """The written law against the original, both read from rest at s = 0 (law units, per rad for v)."""

    deviation: float
    deviation_at_deg: float
    dwell_deviation: float | None
    peak_accel_original: float
    peak_accel_written: float
    lift: float
    closure_s: float
    closure_v: float

    @property
    def peak_accel_ratio(self) -> float:
        return self.peak_accel_written / self.peak_accel_original if self.peak_accel_original > 0 else math.inf


def _sided_grid(laws, samples: int, cycle: float) -> np.ndarray:
    """A uniform grid plus every knot and phase end of ``laws``, each approached from both sides."""
    points = [np.arange(samples + 1) * (cycle / samples)]
    for law in laws:
        points.append(np.array([p.start for p in law.phases] + [p.end for p in law.phases]))
        if isinstance(law, PiecewiseLinearLaw):
            points.append(np.asarray(law.x, dtype=float))
    knots = np.concatenate(points)
    knots = knots[(knots >= 0.0) & (knots <= cycle)]
    return unique(np.concatenate((knots, np.nextafter(knots, -np.inf).clip(0.0))))


def written_figures(original: MotionLaw, written: MotionLaw, samples: int = 1 << 15) -> WrittenFigures:
    """Compare the written law with the original as both are read back: from rest at s = 0 at θ = 0.

    Independent of how the written law was made: both laws are sampled on one grid (uniform, plus every
    knot and phase end from both sides), and the figures are maxima over it.
    """
    cycle = original.cycle
    grid = _sided_grid((original, written), samples, cycle)
    first, second = original.kinematics(grid), written.kinematics(grid)
    zero_o, zero_w = original.kinematics(np.zeros(1)), written.kinematics(np.zeros(1))
    s_o = first.s - zero_o.s[0]
    s_w = second.s - zero_w.s[0]
    deviation = s_w - s_o
    index = int(np.argmax(np.abs(deviation)))
    dwell = np.zeros(len(grid), dtype=bool)
    for phase in written.phases:
        if phase.kind == "dwell":
            dwell |= (grid >= phase.start) & (grid <= phase.end)
    ends = written.kinematics(np.array([0.0, cycle]))
    return WrittenFigures(
        deviation=float(abs(deviation[index])), deviation_at_deg=float(np.degrees(grid[index])),
        dwell_deviation=float(np.max(np.abs(deviation[dwell]))) if dwell.any() else None,
        peak_accel_original=float(np.max(np.abs(first.a))), peak_accel_written=float(np.max(np.abs(second.a))),
        lift=float(np.ptp(s_o)), closure_s=float(ends.s[1] - ends.s[0]), closure_v=float(ends.v[1] - ends.v[0]))


def judge_filter(original: MotionLaw, outcome: FilterOutcome, settings: FilterSettings, unit: str = "mm",
                 applies: str = "", written: str = "the written law") -> tuple[WrittenFigures, Verdict]:
    """The checks of a filtered (or lead-in) law: figures of ``written_figures`` against the limits of
    ``settings`` (module docstring's table); warnings for a raised start-of-motion acceleration and for a
    lead-in that did not balance."""
    figures = written_figures(original, outcome.law)
    lift = figures.lift
    tail = f"; {applies}" if applies else ""
    what = f"{written} against the original, both read from rest at s = 0"
    max_dev = settings.max_deviation_mm
    if max_dev is None and outcome.lead_in is None:
        max_dev = DEFAULT_MAX_DEVIATION_FRACTION * lift
    dwell_tol = settings.dwell_tol_mm if settings.dwell_tol_mm is not None else DEFAULT_DWELL_TOL_FRACTION * lift
    closure = settings.closure_tol * lift
    note_dev = ("" if settings.max_deviation_mm is not None or outcome.lead_in is None
                else "a lead-in moves the law on purpose: no default limit (give --max-deviation)")
    checks = [
        Check("deviation from the original", figures.deviation, max_dev, unit,
              applies=f"{what}, largest at {figures.deviation_at_deg:.4g} deg{tail}", note=note_dev),
        Check("dwell deviation", figures.dwell_deviation, dwell_tol, unit, applies=f"{what}, on the dwells{tail}"),
        Check("peak acceleration ratio", figures.peak_accel_ratio, settings.max_peak_accel_ratio, "",
              applies=f"max |a| of {written} over the original's{tail}"),
        Check("closure of s", abs(figures.closure_s), closure, unit, applies=f"s(360) - s(0) of {written}{tail}"),
        Check("closure of v", abs(figures.closure_v), closure, f"{unit}/rad",
              applies=f"v(360) - v(0) of {written}{tail}"),
    ]
    warnings = []
    if outcome.filtered is not None and outcome.filtered.start_accel_ratio is not None \
            and outcome.filtered.start_accel_ratio > 1.0:
        ratio = outcome.filtered.start_accel_ratio
        warnings.append(Warning(f"filtering raised the acceleration at the start of motion x{ratio:.3g} (first "
                                f"{np.degrees(outcome.filtered.start_window):.3g} deg of each motion)", ratio,
                                "start-of-motion acceleration ratio > 1"))
    if outcome.lead_in is not None and not outcome.lead_in.balanced:
        warnings.append(Warning("the lead-in law did not balance with its new phases", None,
                                "lead-in rebalanced within the balance tolerance"))
    return figures, Verdict(tuple(checks), tuple(warnings))


# =============================================================================================
# Step 3 of the pipeline
# =============================================================================================

def written_record(original: MotionLaw, outcome: FilterOutcome, settings: FilterSettings, unit: str = "mm",
                   writer: str = "camcad spectrum --filter", lift: float | None = None) -> LawRecord:
    """camcad's record of the written law (``camcad.io.law_record``): its phases, and the rule it was judged
    by here, so ``camcad check`` of the written file judges it the same way. A law that passes the balance
    conditions with its phases (a lead-in law, exact dwells) keeps the "balance" rule; a filtered law, whose
    dwells keep the filter's small residue, the "closure" rule with this run's dwell tolerance and each
    dwell's level (the original's s there, from rest at s = 0). ``lift``: the lift the limits were taken
    from (``WrittenFigures.lift``; default: the original's stroke on 4097 samples)."""
    final = outcome.law
    if lift is None:
        lift = float(np.ptp(original.kinematics(np.linspace(0.0, original.cycle, 4097)).s))
    balanced = (outcome.lead_in.balanced if outcome.lead_in is not None
                else outcome.exported is not None and outcome.exported.balanced_with_phases)
    extra = {"removed": list(outcome.filtered.band.removed)} if outcome.filtered is not None else {}
    if balanced:
        return LawRecord.for_law(final, writer, unit=unit, basis="balance", tol=settings.closure_tol, lift=lift,
                                 extra=extra)
    zero = float(original.kinematics(np.zeros(1)).s[0])
    levels = tuple(float(original.kinematics(np.array([(p.start + p.end) / 2.0])).s[0]) - zero
                   for p in final.phases if p.kind == "dwell")
    dwell_tol = settings.dwell_tol_mm if settings.dwell_tol_mm is not None else DEFAULT_DWELL_TOL_FRACTION * lift
    return LawRecord.for_law(final, writer, unit=unit, basis="closure", tol=settings.closure_tol, lift=lift,
                             dwell_tol=dwell_tol, dwell_levels=levels, extra=extra)


@dataclass(frozen=True)
class FilterStep:
    """The pipeline's filter step on one mechanism: the law to continue with, the report (None when the
    step did not run) and why it did not run."""

    law: Any
    report: Any = None
    skipped: str | None = None
    fn_hz: float | None = None


def filter_step(scene, mech, law, speeds, unit: str = "mm", applies: str = "") -> FilterStep:
    """Step 3 of docs/INTERFACE.md's pipeline on one mechanism: [filter] with fn from [filter] or [dynamics] and the
    speed range from [filter] or [machine]; judged as ``camcad spectrum --filter`` judges it."""
    if not mech.has("filter"):
        return FilterStep(law, skipped="no [filter] in scene")
    settings = parse_filter(mech.sections["filter"], mech.where(scene.path, "filter"))
    if not settings.enabled:
        return FilterStep(law, skipped="[filter] enabled = false")
    fn = settings.fn_hz
    if fn is None and mech.has("dynamics"):
        fn = parse_dynamics(mech.sections["dynamics"], mech.where(scene.path, "dynamics"),
                            math.degrees(law.cycle)).follower.natural_frequency_hz
    rpm = settings.rpm or ((min(speeds), max(speeds)) if speeds else None)
    if fn is None and settings.lead_in_deg is None:
        return FilterStep(law, skipped="no natural frequency ([filter] fn_hz or [dynamics]) and no lead-in")
    if fn is not None and rpm is None:
        return FilterStep(law, skipped="no speed range ([filter] rpm or [machine] rpm)")
    outcome = apply_filter(law, settings, fn_hz=fn, rpm=rpm, where=mech.where(scene.path, "filter"), unit=unit)
    figures, verdict = judge_filter(law, outcome, settings, unit, applies)
    body = {**filter_body(outcome, figures, unit), "natural_frequency_hz": fn}
    report = AnalysisReport("spectrum", body, verdict, result=outcome)
    return FilterStep(outcome.law, report, None, fn)


def filter_body(outcome: FilterOutcome, figures: WrittenFigures, unit: str) -> dict:
    """The filter's docs/INTERFACE.md keys (``removed``, ``max_deviation_mm``, ``dwell_deviation_mm``,
    ``peak_accel_ratio``) for the written law, and the filter's own figures under ``filter``."""
    body: dict[str, Any] = {}
    if outcome.filtered is not None:
        band = outcome.filtered.band
        body.update({"removed": list(band.removed), "resonant": list(band.core),
                     "attenuated": {str(k): g for k, g in band.gains.items() if g > 0}})
    body.update({unit_key("max_deviation_mm", unit): figures.deviation,
                 unit_key("dwell_deviation_mm", unit): figures.dwell_deviation,
                 "peak_accel_ratio": figures.peak_accel_ratio, unit_key("lift_mm", unit): figures.lift,
                 unit_key("closure_gap_mm", unit): figures.closure_s,
                 unit_key("velocity_gap_mm_per_rad", unit): figures.closure_v})
    own = outcome.report()
    if outcome.filtered is not None:
        body["start_accel"] = own.pop("start_accel")
        body["filter"] = {_rekey(k, unit): v for k, v in own.items()
                          if k not in ("removed", "resonant", "attenuated", "lead_in", "export",
                                       "final_band_amplitudes_mm", "pipeline_notes")}
        body["filter"]["notes"] = own.get("notes", [])
    for key in ("lead_in", "export"):
        if key in own:
            body[key] = {_rekey(k, unit): v for k, v in own[key].items()}
    if "final_band_amplitudes_mm" in own:
        body[unit_key("band_left_mm", unit)] = own["final_band_amplitudes_mm"]
    if own.get("pipeline_notes"):
        body["notes"] = own["pipeline_notes"]
    return body


def _rekey(key: str, unit: str) -> str:
    return unit_key(key, unit) if unit != "mm" else key


