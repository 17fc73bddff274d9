"""`camcad spectrum LAW|SCENE`: harmonic analysis of a motion law, resonance band, filtering, lead-in.

Thin: the options become a SpectrumRequest, ``camcad.report.spectrum.spectrum_command`` computes and writes,
and the run is printed (text or --json). Exit 0 when every check passed, 1 when one failed, 2 bad input.
"""

from __future__ import annotations

from typing import Annotated

import typer

from camcad.cli import app
from camcad.cli.analysis_options import PhaseAnglesOpt, UnitOpt, emit
from camcad.cli.common import (
    CycleOpt,
    HandleOpt,
    JsonOpt,
    LayerOpt,
    LiftOpt,
    MechanismOpt,
    NoPlotsOpt,
    OutOpt,
    PhasesOpt,
    ReturnStandardOpt,
    SourceArg,
    StandardOpt,
    XDegOpt,
)


@app.command()
def spectrum(
        source: SourceArg = None,
        harmonics: Annotated[int | None, typer.Option(
            "--harmonics", "-N", help="Harmonics analysed and listed (default 64).")] = None,
        tol: Annotated[float | None, typer.Option(
            "--tol", help="RMS tolerance (law unit): report the least N that meets it.")] = None,
        method: Annotated[str, typer.Option(
            "--method", help="auto (exact when the law allows it) | exact | fft.")] = "auto",
        coef_tol: Annotated[float, typer.Option(
            "--coef-tol", help="FFT path: amplitude tolerance (law unit) the sampling is refined to.")] = 1e-9,
        fn: Annotated[float | None, typer.Option("--fn", help="Natural frequency of the follower system (Hz).")] = None,
        rpm: Annotated[str | None, typer.Option("--rpm", help="Speed range N1:N2 (rpm) (or one speed N).")] = None,
        band: Annotated[float | None, typer.Option(
            "--band", help="Half-width of the resonance band, fraction of fn (default 0.05).")] = None,
        neighbours: Annotated[int | None, typer.Option(
            "--neighbours", help="Harmonics removed on each side of the resonant ones (default 1).")] = None,
        taper: Annotated[int | None, typer.Option(
            "--taper", help="Raised-cosine taper over this many further harmonics (default 0: remove).")] = None,
        do_filter: Annotated[bool, typer.Option(
            "--filter", help="Remove the resonant harmonics; write the filtered law (DXF, CSV) and judge it.")] = False,
        force: Annotated[bool, typer.Option(
            "--force", help="Filter an unbalanced law anyway (it is refused otherwise).")] = False,
        keep_dwells: Annotated[bool | None, typer.Option(
            "--keep-dwells/--no-keep-dwells",
            help="Compensate so dwells and lift stay within --dwell-tol (default on).")] = None,
        dwell_tol: Annotated[float | None, typer.Option(
            "--dwell-tol", help="Dwell deviation limit (law unit; default 1e-3 of the lift).")] = None,
        max_deviation: Annotated[float | None, typer.Option(
            "--max-deviation",
            help="Largest deviation of the written law from the original (law unit; default 1 % of the lift).")] = None,
        max_peak_ratio: Annotated[float | None, typer.Option(
            "--max-peak-ratio", help="Largest peak acceleration, written over original (default 1.5).")] = None,
        closure_tol: Annotated[float | None, typer.Option(
            "--closure-tol", help="Closure of the written law, fraction of the lift (default 1e-5).")] = None,
        lead_in: Annotated[float | None, typer.Option(
            "--lead-in", help="Lead-in segments of this angle before each motion (deg), e.g. 14.")] = None,
        lead_in_fraction: Annotated[float | None, typer.Option(
            "--lead-in-fraction", help="Lead-in acceleration, fraction of the peak (default 0.1).")] = None,
        start_window: Annotated[float | None, typer.Option(
            "--start-window",
            help="Window after each motion start for the start-of-motion acceleration (deg, default 7).")] = None,
        exact_dwells: Annotated[bool, typer.Option(
            "--exact-dwells",
            help="Write the filtered law with a = 0 on the dwells (brings part of the band back).")] = False,
        step: Annotated[float | None, typer.Option(
            "--step", help="Vertex step of the written polyline (deg, default 0.1).")] = None,
        r12: Annotated[bool, typer.Option("--r12", help="Write the filtered law as DXF R12.")] = False,
        unit: UnitOpt = None, phase_angles: PhaseAnglesOpt = "auto",
        standard: StandardOpt = None, return_standard: ReturnStandardOpt = None, phases: PhasesOpt = None,
        lift: LiftOpt = None, layer: LayerOpt = None, handle: HandleOpt = None, cycle: CycleOpt = 360.0,
        x_deg: XDegOpt = False, mechanism: MechanismOpt = None,
        output: OutOpt = None, no_plots: NoPlotsOpt = False,
        as_json: JsonOpt = False) -> None:
    """Harmonics of a law, the resonance band over a speed range, filtering.

    Amplitudes and initial phases of s and a, truncation error against N, the resonance band over a speed
    range; with --filter the resonant harmonics are removed, the filtered law is written and judged
    (deviation, dwells, peak acceleration, closure: exit 1 when a limit is exceeded). An unbalanced law is
    refused (exit 2) unless --force."""
    from camcad.report.spectrum import SpectrumCommand, spectrum_command
    from camcad.scene.commands.source import LawRequest
    from camcad.scene.commands.spectrum import SpectrumRequest

    law = LawRequest(source, standard, return_standard, phases, lift, layer, handle, cycle, x_deg, mechanism, unit,
                     phase_angles, rpm)
    request = SpectrumRequest(law, harmonics, tol, method, coef_tol, fn, band, neighbours, taper, do_filter,
                              keep_dwells, dwell_tol, lead_in, lead_in_fraction, start_window, exact_dwells, step,
                              max_deviation, max_peak_ratio, closure_tol, force)
    emit(spectrum_command(SpectrumCommand(request, output, not no_plots, r12)), as_json)
