"""``camcad synth``: a law of a given tachogram synthesised from the harmonic database, as a command.

The options become a ``SynthRequest``; ``run_synth`` takes the phases (a tachogram with its angles, or
``--phases``), the shapes of the rises and returns (standard ones, or a drawn law's own: ``--shape-from``),
the lift, and the RMS error wanted (or the number of harmonics), synthesises the law from the database
(``camcad.fourier.synth``), writes it as an acceleration polyline that closes (``export_polyline``, as
``spectrum --filter`` writes its law) and judges the written law against the closed-form composite law on the
same basis ``camcad spectrum`` judges a filtered one (``written_figures``): RMS error (measured), dwell
deviation, closure of s and v. The written law carries camcad's record (its phases and this rule).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from camcad.errors import CamcadError
from camcad.fourier.export import export_polyline
from camcad.fourier.synth import (
    DATABASE_Z,
    drawn_shapes,
    full_database,
    named_shape,
    synthesise_tachogram,
    tachogram_phases,
)
from camcad.io.law_record import LawRecord
from camcad.law.phases import parse_phases
from camcad.law.source import load_law
from camcad.scene.analysis_report import rounded_tree
from camcad.scene.commands.source import LAW_UNITS, looks_like_scene, require_file
from camcad.scene.file import read_scene
from camcad.scene.filtering import written_figures
from camcad.scene.laws import law_unit, mechanism_law
from camcad.scene.sections.filter import DEFAULT_CLOSURE_TOL, DEFAULT_DWELL_TOL_FRACTION
from camcad.verdict import Check, Verdict

#: the RMS error wanted when neither --tol nor --harmonics is given, a fraction of the lift
DEFAULT_TOL_FRACTION = 1e-3
#: harmonic counts at which the RMS error is tabulated
RMS_AT = (1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 256, 512)


@dataclass(frozen=True)
class SynthRequest:
    """What ``camcad synth`` can be asked (angles deg; lift and tolerances in the law's unit)."""

    lift: float | None = None
    tachogram: str | None = None
    phases: str | None = None
    rise_deg: float | None = None
    return_deg: float | None = None
    start_deg: float = 0.0
    far_dwell_deg: float = 0.0
    cycle: float = 360.0
    unit: str = "mm"
    shape: str = "cycloidal"
    return_shape: str | None = None
    shape_from: Path | None = None
    tol: float | None = None
    harmonics: int | None = None
    dwell_tol: float | None = None
    step_deg: float = 0.1



@dataclass
class SynthReport:
    """What ``camcad synth`` found: the figures (``body``), the verdict on the written law, the synthesis, the
    written law and its record, and the database the patterns came from."""

    body: dict
    verdict: Verdict
    synthesis: Any
    written: Any
    record: LawRecord
    database: dict
    unit: str
    notes: list = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return self.verdict.passed

    @property
    def exit_code(self) -> int:
        return 0 if self.passed else 1

    def to_dict(self) -> dict:
        return {"synth": rounded_tree({**self.body, **self.verdict.to_dict(), "notes": list(self.notes)})}


def synth_phases(request: SynthRequest) -> list[tuple[str, float]]:
    """(kind, width deg) of the request: ``--phases``, or the tachogram and its angles."""
    if request.phases is not None and request.tachogram is not None:
        raise CamcadError("both --phases and --tachogram given", "command line", "give one of them")
    if request.phases is not None:
        phases = parse_phases(request.phases, request.cycle)
        return [(p.kind, math.degrees(p.end - p.start)) for p in phases]
    if request.tachogram is None:
        raise CamcadError("no phases given", "command line",
                          "give --tachogram DRTD --rise DEG --return DEG [--start DEG], or --phases")
    if request.rise_deg is None or request.return_deg is None:
        raise CamcadError("the tachogram needs the rise and return angles", "--tachogram",
                          "give --rise DEG and --return DEG")
    return tachogram_phases(request.tachogram, request.rise_deg, request.return_deg, start_deg=request.start_deg,
                            far_dwell_deg=request.far_dwell_deg, cycle_deg=request.cycle)


def run_synth(request: SynthRequest) -> SynthReport:
    """``camcad synth`` (module docstring).

    Parameters
    ----------
    request : SynthRequest

    Returns
    -------
    SynthReport
        ``to_dict()`` is ``{"synth": {...}}``; ``exit_code`` 1 when the written law misses a limit.
    """
    if request.unit not in LAW_UNITS:
        raise CamcadError(f"unknown unit {request.unit!r}", "--unit", f"use one of {', '.join(LAW_UNITS)}")
    if not (math.isfinite(request.step_deg) and 0 < request.step_deg <= 5):
        raise CamcadError(f"--step {request.step_deg:g} deg is not in (0, 5]", "--step", "give e.g. 0.1")
    notes: list[str] = []
    drawn: dict = {}
    if request.shape_from is not None:
        source, unit = _drawn_law(Path(request.shape_from), request.cycle)
        drawn = drawn_shapes(source, Path(request.shape_from).stem)
        notes.append(f"drawn shapes from {request.shape_from}: " + ", ".join(sorted(drawn)))
        if request.phases is None and request.tachogram is None:
            # the drawn law's own tachogram: its phases and its stroke
            text = ",".join(f"{math.degrees(p.start):.10g}:{math.degrees(p.end):.10g}:{p.kind}" for p in source.phases)
            stroke = float(np.ptp(source.kinematics(np.linspace(0.0, source.cycle, 8193)).s))
            request = replace(request, phases=text, lift=request.lift if request.lift is not None else stroke,
                              unit=unit if unit is not None else request.unit)
            notes.append(f"the tachogram of {Path(request.shape_from or '').name}: {text} (deg), lift "
                         f"{request.lift:.6g} "
                         f"{request.unit}")
    if request.lift is None or not (math.isfinite(request.lift) and request.lift > 0):
        raise CamcadError("the lift (or swing) must be given and positive", "--lift",
                          "give --lift H (mm, or rad/deg of swing with --unit)")
    lift = float(request.lift)
    phases_deg = synth_phases(request)
    rise_name = _resolve(request.shape, "rise", drawn)
    back_name = _resolve(request.return_shape or request.shape, "return", drawn)
    rise_shape, back_shape = named_shape(rise_name, drawn), named_shape(back_name, drawn)
    database = full_database(drawn)
    if rise_name not in database:
        database[rise_name] = full_database({rise_name: rise_shape})[rise_name]
    if back_name not in database:
        database[back_name] = full_database({back_name: back_shape})[back_name]
    tol = request.tol
    if tol is None and request.harmonics is None:
        tol = DEFAULT_TOL_FRACTION * lift
        notes.append(f"RMS error wanted not given: {DEFAULT_TOL_FRACTION:g} of the lift, {tol:.4g} {request.unit}")
    found = synthesise_tachogram(phases_deg, lift, database[rise_name], database[back_name], rise_shape=rise_shape,
                       return_shape=back_shape, tol=tol, harmonics=request.harmonics, cycle_deg=request.cycle,
                       names=(rise_name, back_name))
    dwell_tol = request.dwell_tol if request.dwell_tol is not None else DEFAULT_DWELL_TOL_FRACTION * lift
    exported = export_polyline(found.law, step_deg=request.step_deg, drift_tol=dwell_tol / 4, where="synth")
    written = exported.law
    figures = written_figures(found.exact, written)
    closure = DEFAULT_CLOSURE_TOL * figures.lift
    unit = request.unit
    checks = []
    if tol is not None:
        checks.append(Check("RMS error against the closed-form law", found.rms_measured, tol, unit,
                            applies=f"the series of {found.harmonics} harmonics, over the cycle on {found.samples} "
                                    "points"))
    if figures.dwell_deviation is not None:
        checks.append(Check("dwell deviation", figures.dwell_deviation, dwell_tol, unit,
                            applies="the written law (synth.dxf) against the closed-form law, both from rest at "
                                    "s = 0, on the dwells"))
    checks += [
        Check("closure of s", abs(figures.closure_s), closure, unit, applies="s(360) - s(0) of the written law"),
        Check("closure of v", abs(figures.closure_v), closure, f"{unit}/rad", applies="v(360) - v(0) of the "
                                                                                     "written law"),
    ]
    verdict = Verdict(tuple(checks))
    zero = float(found.exact.kinematics(np.zeros(1)).s[0])
    levels = tuple(float(found.exact.kinematics(np.array([(p.start + p.end) / 2.0])).s[0]) - zero
                   for p in written.phases if p.kind == "dwell")
    basis = "balance" if exported.balanced_with_phases else "closure"
    record = LawRecord.for_law(written, "camcad synth", unit=unit, basis=basis, tol=DEFAULT_CLOSURE_TOL,
                               lift=figures.lift, dwell_tol=dwell_tol if basis == "closure" else None,
                               dwell_levels=levels if basis == "closure" else (),
                               extra={"harmonics": found.harmonics, "shapes": [rise_name, back_name]})
    spectrum = found.spectrum
    rms = spectrum.rms_errors()
    shown = [n for n in RMS_AT if n <= len(spectrum.coefficients)]
    body: dict[str, Any] = {
        "unit": unit, "lift": lift, "cycle_deg": request.cycle,
        "phases": ",".join(f"{a:.10g}:{b:.10g}:{k}" for a, b, k in _bounds(phases_deg)),
        "tachogram": request.tachogram, "shapes": {"rise": rise_name, "return": back_name},
        "harmonics": found.harmonics, f"rms_error_predicted_{unit}": found.rms_predicted,
        f"rms_error_measured_{unit}": found.rms_measured, f"max_error_{unit}": found.max_error,
        f"tol_{unit}": tol, "rms_error": {str(n): float(rms[n]) for n in shown},
        "series": [{"k": int(k), f"amplitude_{unit}": float(a), "phase_deg": float(np.degrees(p))}
                   for k, a, p in zip(spectrum.harmonics[:found.harmonics], spectrum.amplitudes[:found.harmonics],
                                      spectrum.phases[:found.harmonics])],
        "mean": spectrum.mean, f"dwell_deviation_{unit}": figures.dwell_deviation,
        f"peak_accel_{unit}_per_rad2": figures.peak_accel_written,
        f"peak_accel_closed_form_{unit}_per_rad2": figures.peak_accel_original,
        "export": exported.report(), "patterns": {name: _kind(p) for name, p in database.items()},
    }
    if request.harmonics is None and found.rms_predicted > (tol or 0) * 1.000001:
        notes.append(f"no series of up to {len(spectrum.coefficients)} harmonics meets the RMS error {tol:g}")
    return SynthReport(body, verdict, found, written, record, database, unit, notes)


def _drawn_law(path: Path, cycle: float):
    """(law, unit or None) of --shape-from: a law file (DXF or table, its recorded phases), or a scene's law
    (through its [follower] for a radius table) in the scene's unit."""
    path = require_file(path, "law or scene file")
    if looks_like_scene(path):
        scene = read_scene(path)
        if len(scene.mechanisms) != 1:
            raise CamcadError("--shape-from takes a scene of one mechanism", str(path), "give the law file itself")
        mech = scene.mechanisms[0]
        law = mechanism_law(scene, mech).law
        return law, law_unit(scene, mech, None, law)[0]
    loaded = load_law(path, cycle_deg=cycle)
    return loaded.law, loaded.unit


def _resolve(name: str, kind: str, drawn: dict) -> str:
    """A shape's name; "drawn" is the drawn law's own rise (or return) of --shape-from."""
    if name != "drawn":
        return name
    if not drawn:
        raise CamcadError("--shape drawn needs the drawn law", "--shape", "give --shape-from LAW (DXF or table)")
    return next((n for n in drawn if n.endswith(f"_{kind}")), next(iter(drawn)))


def _bounds(phases_deg) -> list[tuple[float, float, str]]:
    out, start = [], 0.0
    for kind, width in phases_deg:
        out.append((start, start + width, kind))
        start += width
    return out


def _kind(pattern) -> str:
    return "exact" if type(pattern).__name__ == "MotionPattern" else "quadrature"


def database_rows(database: dict, z=DATABASE_Z) -> list[dict]:
    """The database as rows: shape, z, |Φ(z)|, arg Φ(z) (deg)."""
    rows = []
    for name, pattern in sorted(database.items()):
        for item in pattern.table(z):
            rows.append({"shape": name, **item})
    return rows


__all__ = ["SynthReport", "SynthRequest", "database_rows", "run_synth", "synth_phases"]
