"""`camcad spectrum LAW|SCENE`: harmonic analysis of a motion law, resonance band, filtering, lead-in."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Optional

import typer

from camcad.cli import app
from camcad.cli.common import (CycleOpt, HandleOpt, JsonOpt, LayerOpt, LiftOpt, MechanismOpt, NoPlotsOpt, OutOpt,
                     PhasesOpt, ReturnStandardOpt, SourceArg, StandardOpt, XDegOpt, console, finish, output_dir)

#: harmonic counts at which the sampled max error is reported (and the least N, when --tol is given)
_MAX_ERROR_AT = (1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024)


@app.command()
def spectrum(
        source: SourceArg = None,
        harmonics: Annotated[Optional[int], typer.Option("--harmonics", "-N", help="Harmonics analysed and listed (default 64).")] = None,
        tol: Annotated[Optional[float], typer.Option("--tol", help="RMS tolerance (mm): report the least N that meets it.")] = None,
        method: Annotated[str, typer.Option("--method", help="auto (exact when the law allows it) | exact | fft.")] = "auto",
        coef_tol: Annotated[float, typer.Option("--coef-tol", help="FFT path: amplitude tolerance (mm) the sampling is refined to.")] = 1e-9,
        fn: Annotated[Optional[float], typer.Option("--fn", help="Natural frequency of the follower system (Hz).")] = None,
        rpm: Annotated[Optional[str], typer.Option("--rpm", help="Speed range N1:N2 (rpm) (or one speed N).")] = None,
        band: Annotated[Optional[float], typer.Option("--band", help="Half-width of the resonance band, fraction of fn (default 0.05).")] = None,
        neighbours: Annotated[Optional[int], typer.Option("--neighbours", help="Harmonics removed on each side of the resonant ones (default 1).")] = None,
        taper: Annotated[Optional[int], typer.Option("--taper", help="Raised-cosine taper over this many further harmonics (default 0: remove).")] = None,
        do_filter: Annotated[bool, typer.Option("--filter", help="Remove the resonant harmonics; write the filtered law (DXF, CSV).")] = False,
        keep_dwells: Annotated[Optional[bool], typer.Option("--keep-dwells/--no-keep-dwells", help="Compensate so dwells and lift stay within --dwell-tol (default on).")] = None,
        dwell_tol: Annotated[Optional[float], typer.Option("--dwell-tol", help="Dwell and lift tolerance (mm; default 1e-3 of the lift).")] = None,
        lead_in: Annotated[Optional[float], typer.Option("--lead-in", help="Lead-in segments of this angle before each motion (deg), e.g. 14.")] = None,
        lead_in_fraction: Annotated[Optional[float], typer.Option("--lead-in-fraction", help="Lead-in acceleration, fraction of the peak (default 0.1).")] = None,
        start_window: Annotated[Optional[float], typer.Option("--start-window", help="Window after each motion start for the start-of-motion acceleration (deg, default 7).")] = None,
        exact_dwells: Annotated[bool, typer.Option("--exact-dwells", help="Write the filtered law with a = 0 on the dwells (brings part of the band back).")] = False,
        step: Annotated[Optional[float], typer.Option("--step", help="Vertex step of the written polyline (deg, default 0.1).")] = None,
        r12: Annotated[bool, typer.Option("--r12", help="Write the filtered law as DXF R12.")] = False,
        standard: StandardOpt = None, return_standard: ReturnStandardOpt = None, phases: PhasesOpt = None,
        lift: LiftOpt = None, layer: LayerOpt = None, handle: HandleOpt = None, cycle: CycleOpt = 360.0,
        x_deg: XDegOpt = False, mechanism: MechanismOpt = None,
        output: OutOpt = None, no_plots: NoPlotsOpt = False,
        as_json: JsonOpt = False) -> None:
    """Harmonics of a law (amplitudes and initial phases of s and a), truncation error against N, the
    resonance band over a speed range; with --filter the resonant harmonics are removed and the filtered
    law is written (exit 1 when the dwells and lift cannot be kept within the tolerance)."""
    import numpy as np

    from camcad import fourier
    from camcad.errors import CamcadError
    from camcad.scene.fields import parse_rpm

    if method not in ("auto", "exact", "fft"):
        raise CamcadError(f"unknown method {method!r}", "--method", "use auto, exact or fft")
    if not (np.isfinite(coef_tol) and coef_tol > 0):
        raise CamcadError(f"--coef-tol {coef_tol!r} must be positive", "--coef-tol", "give e.g. 1e-9 (mm)")
    if tol is not None and not (np.isfinite(tol) and tol > 0):
        raise CamcadError(f"--tol {tol!r} must be positive", "--tol", "give the RMS tolerance in mm, e.g. 0.001")
    law, name, notes, scene_settings, scene_fn, scene_rpm = _load(source, standard, return_standard, phases, lift,
                                                                   layer, handle, cycle, x_deg, mechanism)
    settings = _merge(scene_settings, harmonics=harmonics, band=band, neighbours=neighbours, taper=taper,
                      keep_dwells=keep_dwells, dwell_tol_mm=dwell_tol, lead_in_deg=lead_in,
                      lead_in_fraction=lead_in_fraction, start_window_deg=start_window, step_deg=step)
    if settings.harmonics < 1 or settings.harmonics > 1 << 16:
        raise CamcadError(f"--harmonics {settings.harmonics} is not in 1..65536", "--harmonics", "give e.g. 64")
    natural = fn if fn is not None else (settings.fn_hz if settings.fn_hz is not None else scene_fn)
    speeds = parse_rpm(rpm, "--rpm") if rpm is not None else (settings.rpm or scene_rpm)
    resonance = None
    if natural is not None and speeds is not None:
        resonance = fourier.resonant_harmonics(natural, speeds, settings.band, settings.neighbours, settings.taper,
                                               "--fn/--rpm")
    elif natural is not None and do_filter:
        raise CamcadError("filtering needs the speed range", "--rpm", "pass --rpm N1:N2 (rpm)")
    wants_filter = do_filter or (scene_settings is not None and scene_settings.enabled and natural is not None)
    if wants_filter and resonance is None:
        raise CamcadError("filtering needs the natural frequency and the speed range", "--filter",
                          "pass --fn HZ and --rpm N1:N2")

    count = settings.harmonics if resonance is None else max(settings.harmonics, resonance.highest)
    result = fourier.analyse(law, count, tol=coef_tol, method=method)
    if not result.converged:
        notes.append(f"the FFT sampling stopped at {result.samples} points with amplitude error "
                     f"{result.coefficient_error:.3g} mm > --coef-tol {coef_tol:g}")
    rms = result.rms_errors()
    least = None
    if tol is not None:
        if result.method == "exact":
            least, grown = fourier.least_harmonics(law, tol, start=count)
        else:
            least, grown = result.least_harmonics(tol), result
        if least is None:
            notes.append(f"no N up to {len(grown.coefficients)} harmonics meets the RMS tolerance {tol:g} mm")
    shown = sorted(set([n for n in _MAX_ERROR_AT if n <= count] + ([least] if least is not None and least <= count
                                                                   else [])))
    max_err = dict(zip(shown, fourier.max_errors(law, result, shown))) if shown else {}
    if least is not None and least > count:
        max_err[least] = float(fourier.max_errors(law, grown, [least])[0])

    payload = {
        "harmonics": result.table()[:settings.harmonics] if resonance is None else result.table(),
        "mean": result.mean,
        "rms_error": {str(n): float(e) for n, e in enumerate(rms)},
        **({"rms_error_at_least_harmonics": float(grown.rms_error(least))}
           if tol is not None and least is not None else {}),
        "max_error": {str(n): float(e) for n, e in max_err.items()},
        "method": result.method, "samples": result.samples, "coefficient_error_mm": result.coefficient_error,
        "mean_square_mm2": result.mean_square, "cycle_deg": float(np.degrees(law.cycle)),
        "phase_convention": "s = mean + sum_k A_k sin(k*360*theta/cycle + phase_k)",
    }
    if tol is not None:
        payload["tol_mm"] = tol
        payload["least_harmonics"] = least
    if resonance is not None:
        payload["resonance"] = {"fn_hz": resonance.fn_hz, "rpm": list(resonance.rpm), "band": resonance.band,
                                "k_band": [resonance.k_low, resonance.k_high], "resonant": list(resonance.core),
                                "neighbours": resonance.neighbours, "to_remove": list(resonance.removed)}
    outcome = None
    if wants_filter or settings.lead_in_deg is not None:
        from dataclasses import replace

        filter_settings = replace(settings, fn_hz=natural if wants_filter else None, rpm=speeds,
                                  exact_dwells=exact_dwells or settings.exact_dwells)
        outcome = _apply(law, filter_settings, wants_filter)
        payload.update(outcome.report())

    out_dir = output_dir(output, name)
    outputs = _write_outputs(out_dir, law, result, resonance, outcome, payload, rms, max_err, tol, no_plots, r12, name)
    payload_out = {"source": name, "notes": notes, "spectrum": payload, "outputs": [str(p) for p in outputs]}
    report_path = out_dir / "spectrum.json"
    payload_out["outputs"].append(str(report_path))
    finish(payload_out, report_path, as_json, lambda p: _print(p, result, resonance, settings.harmonics),
           outcome is None or outcome.passed)


def _apply(law, settings, wants_filter: bool):
    from camcad.scene import filter as scene_filter

    return scene_filter.apply_filter(law, settings, where="--filter" if wants_filter else "--lead-in")


def _merge(settings, **overrides):
    from camcad.scene import filter as scene_filter

    base = settings if settings is not None else scene_filter.FilterSettings()
    given = {key: value for key, value in overrides.items() if value is not None}
    return scene_filter.FilterSettings(**{**base.__dict__, **given})


def _load(source, standard, return_standard, phases, lift, layer, handle, cycle, x_deg, mechanism):
    """(law, name, notes, [filter] settings or None, fn from [dynamics] or None, rpm range or None)."""
    from camcad.scene import filter as scene_filter
    from camcad.cli.common import resolve_source

    src = resolve_source(source, standard, return_standard, phases, lift, layer, handle, cycle, x_deg, mechanism)
    settings = None
    if src.section("filter") is not None:
        settings = scene_filter.parse_filter(src.section("filter"), src.section_where("filter"))
    fn = None
    if src.section("dynamics") is not None:
        from camcad.scene.dynamics import parse_dynamics

        fn = parse_dynamics(src.section("dynamics"), src.section_where("dynamics")).follower.natural_frequency_hz
    speeds = src.speeds(None)
    rpm_range = (min(speeds), max(speeds)) if speeds else None
    return src.law, src.name, src.notes, settings, fn, rpm_range


def _write_outputs(out_dir: Path, law, result, resonance, outcome, payload, rms, max_err, tol, no_plots, r12, name):
    import numpy as np

    from camcad.io.atomic import write_text_atomic

    outputs = []
    rows = ["k,amplitude_mm,phase_deg,accel_amplitude_mm_per_rad2,accel_phase_deg,gain"]
    gains = resonance.gains if (resonance is not None and outcome is not None and outcome.filtered is not None) else {}
    for row in result.table():
        rows.append(f"{row['k']},{row['amplitude']:.12g},{row['phase_deg']:.10g},{row['accel_amplitude']:.12g},"
                    f"{row['accel_phase_deg']:.10g},{gains.get(row['k'], 1.0):g}")
    outputs.append(write_text_atomic(out_dir / "spectrum.csv", "\n".join(rows) + "\n"))
    if outcome is not None:
        from camcad.io.law_write import write_law_csv, write_law_dxf

        final = outcome.law
        title = f"camcad spectrum {name}: " + ("filtered" if outcome.filtered is not None else "") + \
                (" + lead-in" if outcome.lead_in is not None else "") + " law, a (mm/rad^2) vs deg"
        outputs.append(write_law_dxf(out_dir / "filtered.dxf", np.degrees(final.x), final.a, layer="ACCEL",
                                     r12=r12, title=title))
        outputs.append(write_law_csv(out_dir / "filtered.csv", final.kinematics(final.x)))
    if not no_plots:
        from camcad.report.spectrum import plot_filtered, plot_spectrum, plot_truncation

        after = None
        if outcome is not None and outcome.filtered is not None:
            from camcad import fourier

            after = fourier.analyse(outcome.filtered.law, len(result.coefficients))
        outputs.append(plot_spectrum(result, out_dir / "spectrum.png", band=resonance, filtered=after,
                                     title=f"{name}: harmonic amplitudes"))
        outputs.append(plot_truncation(rms, out_dir / "truncation.png", max_errors=max_err, tol=tol,
                                       title=f"{name}: error of the truncated series"))
        if outcome is not None:
            if outcome.filtered is not None:
                outputs.append(plot_filtered(law, outcome.filtered.law, out_dir / "filtered.png",
                                             dwell_tol=outcome.filtered.dwell_tol, written=outcome.law,
                                             title=f"{name}: original and filtered law"))
            else:
                outputs.append(plot_filtered(law, outcome.law, out_dir / "filtered.png",
                                             labels=("original", "with lead-in"),
                                             title=f"{name}: original and lead-in law (as written)"))
    return outputs


def _print(payload_out: dict, result, resonance, listed: int) -> None:
    from rich.table import Table

    out = console()
    data = payload_out["spectrum"]
    out.print(f"{payload_out['source']}: {data['method']} analysis"
              + (f" ({data['samples']} samples)" if data["samples"] else "")
              + f", amplitude error <= {data['coefficient_error_mm']:.2g} mm; mean {data['mean']:.6g} mm")
    for note in payload_out["notes"]:
        out.print(f"  note: {note}")
    removed = set(data.get("removed", []))
    resonant = set(resonance.core) if resonance is not None else set()
    table = Table(title=f"harmonics of s = mean + sum A_k sin(k theta + phi_k)  (first {listed})")
    for column in ("k", "A_k (mm)", "phi_k (deg)", "accel A_k (mm/rad^2)", "accel phi_k (deg)", ""):
        table.add_column(column, justify="right")
    rows = data["harmonics"]
    extra = [r for r in rows[listed:] if r["k"] in resonant or r["k"] in removed]
    for row in rows[:listed] + extra:
        mark = "removed" if row["k"] in removed else ("resonant" if row["k"] in resonant else "")
        table.add_row(str(row["k"]), f"{row['amplitude']:.6g}", f"{row['phase_deg']:.3f}",
                      f"{row['accel_amplitude']:.6g}", f"{row['accel_phase_deg']:.3f}", mark)
    out.print(table)
    errors = Table(title="error of the series truncated after N harmonics")
    errors.add_column("N", justify="right")
    errors.add_column("RMS (mm)", justify="right")
    errors.add_column("max (mm)", justify="right")
    for n, value in data["max_error"].items():
        rms = data["rms_error"].get(n, data.get("rms_error_at_least_harmonics"))
        errors.add_row(n, f"{rms:.3e}", f"{value:.3e}")
    out.print(errors)
    if "tol_mm" in data:
        least = data["least_harmonics"]
        out.print(f"least N with RMS error <= {data['tol_mm']:g} mm: {least if least is not None else 'not found'}")
    if "resonance" in data:
        r = data["resonance"]
        out.print(f"resonance: fn {r['fn_hz']:g} Hz, {r['rpm'][0]:g}..{r['rpm'][1]:g} rpm, band +-{100 * r['band']:g} % "
                  f"-> k in [{r['k_band'][0]:.3f}, {r['k_band'][1]:.3f}]: resonant {r['resonant'] or 'none'}")
    if "removed" in data:
        start = data["start_accel"]
        ratio = start["ratio"]
        out.print(f"filtered: removed {data['removed']}; max deviation {data['max_deviation_mm']:.4g} mm, "
                  f"on the dwells {_fmt(data['dwell_deviation_mm'])} mm (tolerance {data['dwell_tol_mm']:.4g} mm, "
                  f"{'kept' if data['dwells_kept'] else 'NOT kept'}); lift change "
                  f"{data['lift_change_mm']:.3g} mm; peak acceleration x{data['peak_accel_ratio']:.4f}"
                  + (f"; start of motion x{ratio:.4f}" if ratio is not None else ""))
        for note in data["notes"]:
            out.print(f"  {note}")
    if "lead_in" in data:
        lead = data["lead_in"]
        out.print(f"lead-in: {lead['angle_deg']:g} deg at {lead['fraction']:g} of the peak acceleration before "
                  f"{len(lead['segments'])} motion(s); balanced: {lead['balanced']}; peak acceleration "
                  f"x{lead['peak_accel_ratio']:.4f}; lift change {lead['lift_change_mm']:.3g} mm")
    for note in data.get("pipeline_notes", []):
        out.print(f"  note: {note}")
    if "export" in data:
        ex = data["export"]
        out.print(f"written law: {ex['vertices']} vertices, closes: {ex['closed']}, deviation of s "
                  f"{ex['max_deviation_mm']:.3g} mm")
    for path in payload_out["outputs"]:
        out.print(f"written: {path}")


def _fmt(value) -> str:
    return "-" if value is None else f"{value:.4g}"
