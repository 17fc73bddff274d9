"""The scene's [filter] section, the pipeline's filter step, and ``camcad spectrum`` as one library function.

- ``parse_filter``: the [filter] table → ``FilterSettings`` (resonance band, lead-in, and the limits the
  filtered law is judged against).
- ``apply_filter``: resonance filtering and lead-in (camcad.fourier) → the closed polyline law to continue with.
- ``judge_filter``: the written law against the original, as both are read back (from rest at s = 0):
  largest deviation, dwell deviation, peak acceleration ratio, closure — each a figure, a limit and a margin.
- ``filter_step``: step 3 of the scene pipeline (and of the commands that analyse a scene's law as
  ``camcad profile`` does).
- ``run_spectrum``: everything ``camcad spectrum`` computes, as an ``AnalysisReport``.

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
from dataclasses import dataclass, field, replace
from typing import Any, cast

import numpy as np

from camcad.arrays import unique
from camcad.balance.conditions import DEFAULT_TOL as BALANCE_TOLERANCE
from camcad.errors import CamcadError
from camcad.fourier.analysis import analyse
from camcad.fourier.export import ExportedLaw, export_polyline
from camcad.fourier.filter import FilterResult, filter_law
from camcad.fourier.leadin import LeadInResult, add_lead_in
from camcad.fourier.resonance import resonant_harmonics
from camcad.fourier.series import Spectrum
from camcad.io.law_record import LawRecord
from camcad.law.law import MotionLaw, PiecewiseLinearLaw
from camcad.scene.fields import Field, parse_rpm, read_table
from camcad.verdict import Check, Verdict, Warning

#: default limits of the filtered law (module docstring)
DEFAULT_MAX_DEVIATION_FRACTION = 0.01       # of the lift
DEFAULT_DWELL_TOL_FRACTION = 1e-3           # of the lift
DEFAULT_MAX_PEAK_RATIO = 1.5
DEFAULT_CLOSURE_TOL = BALANCE_TOLERANCE     # of the lift
#: a harmonic whose amplitude is at most this fraction of the lift is zero: its initial phase is meaningless
ZERO_AMPLITUDE = 1e-12
#: harmonic counts at which the sampled max error is reported (and the least N, when --tol is given)
MAX_ERROR_AT = (1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024)


# =============================================================================================
# The scene's [filter] section
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


# =============================================================================================
# Step 3 of the pipeline
# =============================================================================================

@dataclass(frozen=True)
class FilterStep:
    """The pipeline's filter step on one mechanism: the law to continue with, the report (None when the
    step did not run) and why it did not run."""

    law: Any
    report: Any = None
    skipped: str | None = None
    fn_hz: float | None = None


def filter_step(scene, mech, law, speeds, unit: str = "mm", applies: str = "") -> FilterStep:
    """Step 3 of SPEC.md's pipeline on one mechanism: [filter] with fn from [filter] or [dynamics] and the
    speed range from [filter] or [machine]; judged as ``camcad spectrum --filter`` judges it."""
    from camcad.scene.analysis import AnalysisReport

    if not mech.has("filter"):
        return FilterStep(law, skipped="no [filter] in scene")
    settings = parse_filter(mech.sections["filter"], mech.where(scene.path, "filter"))
    if not settings.enabled:
        return FilterStep(law, skipped="[filter] enabled = false")
    fn = settings.fn_hz
    if fn is None and mech.has("dynamics"):
        from camcad.scene.dynamics import parse_dynamics

        fn = parse_dynamics(mech.sections["dynamics"], mech.where(scene.path, "dynamics"),
                            math.degrees(law.cycle)).follower.natural_frequency_hz
    rpm = settings.rpm or ((min(speeds), max(speeds)) if speeds else None)
    if fn is None and settings.lead_in_deg is None:
        return FilterStep(law, skipped="no natural frequency ([filter] fn_hz or [dynamics]) and no lead-in")
    if fn is not None and rpm is None:
        return FilterStep(law, skipped="no speed range ([filter] rpm or [machine] rpm)")
    outcome = apply_filter(law, settings, fn_hz=fn, rpm=rpm, where=mech.where(scene.path, "filter"), unit=unit)
    figures, verdict = judge_filter(law, outcome, settings, unit, applies)
    body = {**_filter_body(outcome, figures, unit), "natural_frequency_hz": fn}
    report = AnalysisReport("spectrum", body, verdict, result=outcome)
    return FilterStep(outcome.law, report, None, fn)


def _filter_body(outcome: FilterOutcome, figures: WrittenFigures, unit: str) -> dict:
    """The filter's SPEC.md keys (``removed``, ``max_deviation_mm``, ``dwell_deviation_mm``,
    ``peak_accel_ratio``) for the written law, and the filter's own figures under ``filter``."""
    from camcad.dynamics.model import unit_key

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
    from camcad.dynamics.model import unit_key

    return unit_key(key, unit) if unit != "mm" else key


# =============================================================================================
# camcad spectrum
# =============================================================================================

@dataclass(frozen=True)
class SpectrumRequest:
    """Everything ``camcad spectrum`` can be asked (None: the scene's [filter] value, else the default)."""

    law: Any
    harmonics: int | None = None
    tol: float | None = None
    method: str = "auto"
    coef_tol: float = 1e-9
    fn: float | None = None
    band: float | None = None
    neighbours: int | None = None
    taper: int | None = None
    do_filter: bool = False
    keep_dwells: bool | None = None
    dwell_tol: float | None = None
    lead_in: float | None = None
    lead_in_fraction: float | None = None
    start_window: float | None = None
    exact_dwells: bool = False
    step: float | None = None
    max_deviation: float | None = None
    max_peak_ratio: float | None = None
    closure_tol: float | None = None
    force: bool = False


#: command-line option → [filter] field it overrides (validated by the field's type and range)
_OPTION_FIELDS = {"--harmonics": "harmonics", "--band": "band", "--neighbours": "neighbours", "--taper": "taper",
                  "--dwell-tol": "dwell_tol_mm", "--lead-in": "lead_in_deg", "--lead-in-fraction": "lead_in_fraction",
                  "--start-window": "start_window_deg", "--step": "step_deg", "--max-deviation": "max_deviation_mm",
                  "--max-peak-ratio": "max_peak_accel_ratio", "--closure-tol": "closure_tol", "--fn": "fn_hz"}


def _option_overrides(request: SpectrumRequest) -> dict:
    """{field: value} of the options given, each checked against its [filter] field (one line naming the option)."""
    given = {"--harmonics": request.harmonics, "--band": request.band, "--neighbours": request.neighbours,
             "--taper": request.taper, "--dwell-tol": request.dwell_tol, "--lead-in": request.lead_in,
             "--lead-in-fraction": request.lead_in_fraction, "--start-window": request.start_window,
             "--step": request.step, "--max-deviation": request.max_deviation,
             "--max-peak-ratio": request.max_peak_ratio, "--closure-tol": request.closure_tol, "--fn": request.fn}
    by_name = {f.name: f for f in FILTER_FIELDS}
    out = {}
    for option, value in given.items():
        if value is None:
            continue
        name = _OPTION_FIELDS[option]
        out[name] = read_table({name: value}, [by_name[name]], option)[name]
    if request.keep_dwells is not None:
        out["keep_dwells"] = request.keep_dwells
    return out


def _check_spectrum_options(request: SpectrumRequest) -> None:
    if request.method not in ("auto", "exact", "fft"):
        raise CamcadError(f"unknown method {request.method!r}", "--method", "use auto, exact or fft")
    if not (math.isfinite(request.coef_tol) and request.coef_tol > 0):
        raise CamcadError(f"--coef-tol {request.coef_tol:g} must be positive", "--coef-tol", "give e.g. 1e-9 (mm)")
    if request.tol is not None and not (math.isfinite(request.tol) and request.tol > 0):
        raise CamcadError(f"--tol {request.tol:g} must be positive", "--tol",
                          "give the RMS tolerance in the law's unit, e.g. 0.001")


def _is_balanced(law, lift: float, loaded=None) -> tuple[bool, str]:
    """(balanced, figures) — ``camcad check`` for a drawn law (by the rule camcad recorded in the file when
    its phases came from there: a filtered or synthesised law); closure of s and v for any other law."""
    if isinstance(law, PiecewiseLinearLaw):
        from camcad.balance.checking import check, check_recorded

        recorded = loaded is not None and loaded.record is not None and loaded.phases_from_record
        report = check_recorded(law, loaded.record) if recorded else check(law)
        if report.balanced:
            return True, ""
        closures = report.velocity_closure
        return False, (f"closure gap {report.displacement_closure:.4g}, v at the end of rise {closures['rise']:.3g}, "
                       f"of return {closures['return']:.3g}")
    ends = law.kinematics(np.array([0.0, law.cycle]))
    gap_s, gap_v = float(ends.s[1] - ends.s[0]), float(ends.v[1] - ends.v[0])
    ok = abs(gap_s) <= DEFAULT_CLOSURE_TOL * lift and abs(gap_v) <= DEFAULT_CLOSURE_TOL * lift
    return ok, "" if ok else f"s gap {gap_s:.4g}, v gap {gap_v:.4g} over the cycle"


@dataclass(frozen=True)
class SpectrumResult:
    """What the plots and files of ``camcad spectrum`` need (the report layer writes them)."""

    law: Any
    spectrum: Any
    resonance: Any
    outcome: FilterOutcome | None
    rms: np.ndarray
    max_errors: dict
    tol: float | None
    unit: str
    name: str
    listed: int
    after: Any = None
    figures: WrittenFigures | None = None
    record: LawRecord | None = None


def run_spectrum(request: SpectrumRequest, source=None):
    """``camcad spectrum``: harmonics of the law, truncation errors, the resonance band over the speed
    range, and with ``do_filter`` (or a scene's enabled [filter]) the filtered law judged against its
    limits (module docstring). Returns an AnalysisReport (key ``spectrum``) whose ``result`` is a
    SpectrumResult.

    Parameters
    ----------
    request : SpectrumRequest
    source : AnalysisSource or None
        The law already resolved (default: ``resolve_source(request.law)``).

    Returns
    -------
    camcad.scene.analysis.AnalysisReport
    """
    from camcad import fourier
    from camcad.dynamics.model import unit_key
    from camcad.scene.analysis import AnalysisReport, resolve_source

    _check_spectrum_options(request)
    overrides = _option_overrides(request)
    src = source if source is not None else resolve_source(request.law, command="spectrum")
    law, unit, notes = src.law, src.unit, list(src.notes)
    scene_settings = None
    if src.section("filter") is not None:
        scene_settings = parse_filter(src.section("filter"), src.section_where("filter"))
    base = scene_settings if scene_settings is not None else FilterSettings()
    settings = replace(base, **overrides)
    natural = settings.fn_hz
    if natural is None and src.section("dynamics") is not None:
        from camcad.scene.dynamics import parse_dynamics

        natural = parse_dynamics(src.section("dynamics"), src.section_where("dynamics")).follower.natural_frequency_hz
    speeds: tuple[float, float] | None
    if request.law.rpm is not None:
        speeds = parse_rpm(request.law.rpm, "--rpm")
    else:
        speeds = settings.rpm or ((min(src.speeds), max(src.speeds)) if src.speeds else None)
    resonance = None
    if natural is not None and speeds is not None:
        resonance = fourier.resonant_harmonics(natural, speeds, settings.band, settings.neighbours, settings.taper,
                                               "--fn/--rpm")
    elif natural is not None and request.do_filter:
        raise CamcadError("filtering needs the speed range", "--rpm", "pass --rpm N1:N2 (rpm)")
    wants_filter = request.do_filter or (scene_settings is not None and scene_settings.enabled and natural is not None)
    if wants_filter and resonance is None:
        raise CamcadError("filtering needs the natural frequency and the speed range", "--filter",
                          "pass --fn HZ and --rpm N1:N2")
    count = settings.harmonics if resonance is None else max(settings.harmonics, resonance.highest)
    result = fourier.analyse(law, count, tol=request.coef_tol, method=request.method)
    if not result.converged:
        notes.append(f"the FFT sampling stopped at {result.samples} points with amplitude error "
                     f"{result.coefficient_error:.3g} {unit} > --coef-tol {request.coef_tol:g}")
    rms = result.rms_errors()
    least = grown = None
    tol = request.tol
    if tol is not None:
        if result.method == "exact":
            least, grown = fourier.least_harmonics(law, tol, start=count)
        else:
            least, grown = result.least_harmonics(tol), result
        if least is None:
            notes.append(f"no N up to {len(grown.coefficients)} harmonics meets the RMS tolerance {tol:g} {unit}")
    shown = sorted(set([n for n in MAX_ERROR_AT if n <= count] + ([least] if least is not None and least <= count
                                                                  else [])))
    max_err = dict(zip(shown, fourier.max_errors(law, result, shown))) if shown else {}
    if least is not None and least > count:
        max_err[least] = float(fourier.max_errors(law, cast(Spectrum, grown), [least])[0])  # set with least
    lift = float(np.ptp(law.kinematics(np.linspace(0.0, law.cycle, 4097)).s))
    rows = result.table() if resonance is not None else result.table()[:settings.harmonics]
    for row in rows:
        if row["amplitude"] <= ZERO_AMPLITUDE * lift:
            row["phase_deg"] = None
        if row["accel_amplitude"] <= ZERO_AMPLITUDE * lift:
            row["accel_phase_deg"] = None
    body: dict[str, Any] = {
        "unit": unit, "harmonics": rows, "mean": result.mean,
        "rms_error": {str(n): float(e) for n, e in enumerate(rms)},
        "max_error": {str(n): float(e) for n, e in max_err.items()},
        "method": result.method, "samples": result.samples,
        unit_key("coefficient_error_mm", unit): result.coefficient_error,
        unit_key("variance_mm2", unit): result.mean_square,
        # the old name of the variance (it never was the mean square): kept one release, docs/analyses.md
        "mean_square_mm2": result.mean_square,
        "cycle_deg": float(np.degrees(law.cycle)),
        "phase_convention": "s = mean + sum_k A_k sin(k*360*theta/cycle + phase_k)",
    }
    if tol is not None:
        body[unit_key("tol_mm", unit)] = tol
        body["least_harmonics"] = least
        if least is not None:
            body["rms_error_at_least_harmonics"] = float(cast(Spectrum, grown).rms_error(least))
    if resonance is not None:
        body["resonance"] = {"fn_hz": resonance.fn_hz, "rpm": list(resonance.rpm), "band": resonance.band,
                             "k_band": [resonance.k_low, resonance.k_high], "resonant": list(resonance.core),
                             "neighbours": resonance.neighbours, "to_remove": list(resonance.removed)}
    outcome = figures = after = record = None
    verdict = Verdict()
    applies = src.angles.describe() if src.angles is not None else ""
    if wants_filter or settings.lead_in_deg is not None:
        balanced, why = _is_balanced(law, lift, src.loaded if src.law is law else None)
        if not balanced and not request.force:
            raise CamcadError(f"the law is not balanced ({why}): its filtered law would hide the break", src.where,
                              "fix it first with camcad fix, or pass --force")
        if not balanced:
            notes.append(f"the law is not balanced ({why}); filtered anyway (--force)")
        filter_settings = replace(settings, fn_hz=natural if wants_filter else None, rpm=speeds,
                                  exact_dwells=request.exact_dwells or settings.exact_dwells)
        outcome = apply_filter(law, filter_settings, where="--filter" if wants_filter else "--lead-in", unit=unit)
        figures, verdict = judge_filter(law, outcome, filter_settings, unit, applies,
                                        "the written law (filtered.dxf)")
        body.update(_filter_body(outcome, figures, unit))
        if outcome.filtered is not None:
            after = fourier.analyse(outcome.filtered.law, len(result.coefficients))
        record = written_record(law, outcome, filter_settings, unit,
                                "camcad spectrum --filter" if wants_filter else "camcad spectrum --lead-in",
                                figures.lift)
    spectrum_result = SpectrumResult(law, result, resonance, outcome, rms, max_err, tol, unit, src.name,
                                     settings.harmonics, after, figures, record)
    summary = src.summary()
    summary["notes"] = notes
    return AnalysisReport("spectrum", body, verdict, summary, spectrum_result)

