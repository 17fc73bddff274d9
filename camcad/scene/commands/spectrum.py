"""``camcad spectrum`` as one library function (``run_spectrum``): the harmonics of a law, the truncation
errors, the resonance band over the speed range, and the filtered law judged against its limits.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, cast

import numpy as np

from camcad import fourier
from camcad.balance.checking import check, check_recorded
from camcad.dynamics.model import unit_key
from camcad.errors import CamcadError
from camcad.fourier.series import Spectrum
from camcad.io.law_record import LawRecord
from camcad.law.law import PiecewiseLinearLaw
from camcad.scene.analysis_report import AnalysisReport
from camcad.scene.commands.source import AnalysisSource, resolve_source
from camcad.scene.fields import parse_rpm, read_table
from camcad.scene.filtering import (
    FilterOutcome,
    WrittenFigures,
    apply_filter,
    filter_body,
    judge_filter,
    written_record,
)
from camcad.scene.sections.dynamics import parse_dynamics
from camcad.scene.sections.filter import (
    DEFAULT_CLOSURE_TOL,
    FILTER_FIELDS,
    MAX_ERROR_AT,
    ZERO_AMPLITUDE,
    FilterSettings,
    parse_filter,
)
from camcad.verdict import Verdict


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


def run_spectrum(request: SpectrumRequest, source: AnalysisSource | None = None):
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
    camcad.scene.analysis_report.AnalysisReport
    """
    _check_spectrum_options(request)
    overrides = _option_overrides(request)
    src = source if source is not None else resolve_source(request.law, command="spectrum")
    if src.scene is not None:
        # the [law]'s law at the phase angles camcad profile analyses, before its [filter] (this command filters)
        run = src.machine(())
        src.law, src.unit = run.given_law, run.unit
        src.notes = list(run.report["law"]["notes"]) + (
            [f"the law's displacement is in {run.unit} ({run.unit_why})"] if run.unit != "mm" else [])
    law, unit, notes = src.law, src.unit, list(src.notes)
    scene_settings = None
    if src.section("filter") is not None:
        scene_settings = parse_filter(src.section("filter"), src.section_where("filter"))
    base = scene_settings if scene_settings is not None else FilterSettings()
    settings = replace(base, **overrides)
    natural = settings.fn_hz
    if natural is None and src.section("dynamics") is not None:
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
        body.update(filter_body(outcome, figures, unit))
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

