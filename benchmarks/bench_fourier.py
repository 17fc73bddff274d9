"""Fourier analysis and resonance filtering: time against coefficient error, a law sampled at 2^16 points.

Law: dwell 65°, cycloidal rise 110°, dwell 115°, cycloidal return 70° (lift 25 mm). Reference: the
closed-form coefficients derived in tests/fourier/test_fourier.py (c_k(a) of each cycloidal motion is
(h/T)·4π² e^{−ikθ1}(1 − e^{−ikβ})/(β(4π² − k²β²)), c_k(s) = −c_k(a)/k²), written out again here, for
k = 1..32 (none of them makes kβ a whole turn for either motion). Error: max_k |A_k − A_k,ref| (mm).

Methods:
- exact, polyline of a: the law's a sampled at M uniform points as a drawn polyline, analysed exactly
  (jump formula, one FFT of the knot jumps); its error is the polyline's chord error, ~h².
- exact, polyline, scattered knots: the same with M random knots (the direct knot sums, O(M·N)).
- rfft of s samples: one real FFT of M uniform samples of s (aliasing only).
- fft adaptive: ``analyse(method="fft", tol)`` doubling the sampling until two agree within tol.
- exact, closed-form pieces: the composite law integrated piecewise (polynomial + exponentials).
- filter: remove the band (fn 160 Hz, 330…420 rpm, ±5 %, one neighbour) from the 2^16-point polyline
  law; error = the largest amplitude left in the band, measured by an FFT of 2^16 samples of the filtered
  law's s (not by the filter's own exact analysis, which is 0 by construction); with dwell compensation to
  1e-4 mm; and the export to a closed 0.1° polyline (error: the band left in an FFT of the written polyline).

Run: python benchmarks/bench_fourier.py [--quick]
"""

from __future__ import annotations

import argparse

import numpy as np
from timing import median_time

from camcad import fourier
from camcad.law.law import PiecewiseLinearLaw
from camcad.law.standard import compose

LIFT = 25.0
PHASES = [("dwell", 65.0), ("rise", 110.0), ("dwell", 115.0), ("return", 70.0)]
HARMONICS = 32
TWO_PI = 2.0 * np.pi
REFERENCES = {"mm vs closed form": "closed-form coefficients c_k of the cycloidal motions (written out here)",
              "mm left in band": "none needed: the removed harmonics must be 0; measured by FFT, not by the filter"}


def reference_amplitudes(harmonics: int = HARMONICS) -> np.ndarray:
    w = np.arange(1, harmonics + 1, dtype=float)

    def motion(start_deg, width_deg, h):
        theta1, beta = np.radians(start_deg), np.radians(width_deg)
        return h * 4 * np.pi**2 * np.exp(-1j * w * theta1) * (1 - np.exp(-1j * w * beta)) / (
            TWO_PI * beta * (4 * np.pi**2 - w**2 * beta**2))

    accel = motion(65.0, 110.0, LIFT) + motion(290.0, 70.0, -LIFT)
    return 2 * np.abs(accel / w**2)


class Opaque:
    """Hides the law's type so ``analyse`` has to sample it."""

    def __init__(self, law):
        self.law, self.cycle, self.phases = law, law.cycle, law.phases

    def kinematics(self, theta):
        return self.law.kinematics(theta)


def _median_time(function, repeats: int):
    return median_time(function, repeats, warm_up=True)


def run(quick: bool) -> list[dict]:
    repeats = 3 if quick else 7
    law = compose(PHASES, LIFT, "cycloidal")
    reference = reference_amplitudes()
    rows = []

    def row(method, setting, elapsed, error, unit="mm vs closed form"):
        rows.append({"kernel": "fourier", "method": method, "setting": setting, "time_s": elapsed,
                     "error": float(error), "error_unit": unit, "reference": REFERENCES.get(unit.split(",")[0], unit)})

    def amplitude_error(spectrum):
        return np.max(np.abs(spectrum.amplitudes[:HARMONICS] - reference))

    sizes = [1 << 10, 1 << 12, 1 << 14, 1 << 16]
    for count in sizes:
        theta = np.arange(count + 1) * (TWO_PI / count)
        polyline = PiecewiseLinearLaw(theta, law.kinematics(theta).a, TWO_PI, law.phases)
        elapsed, spectrum = _median_time(lambda polyline=polyline: fourier.analyse(polyline, HARMONICS), repeats)
        row("exact, polyline of a", f"M={count} uniform knots", elapsed, amplitude_error(spectrum))
        s = law.kinematics(theta[:-1]).s
        elapsed, spectrum = _median_time(lambda s=s: fourier.analyse_samples(s, TWO_PI, HARMONICS), repeats)
        row("rfft of s samples", f"M={count}", elapsed, amplitude_error(spectrum))
    scattered = 1 << 12 if quick else 1 << 16
    rng = np.random.default_rng(1)
    theta = np.sort(np.concatenate(([0.0, TWO_PI], rng.uniform(0.0, TWO_PI, scattered - 2))))
    polyline = PiecewiseLinearLaw(theta, law.kinematics(theta).a, TWO_PI, law.phases)
    elapsed, spectrum = _median_time(lambda: fourier.analyse(polyline, HARMONICS), max(1, repeats // 2))
    row("exact, polyline, scattered knots", f"M={scattered} random knots", elapsed, amplitude_error(spectrum))
    for tol in (1e-6, 1e-9, 1e-12):
        elapsed, spectrum = _median_time(lambda tol=tol: fourier.analyse(Opaque(law), HARMONICS, tol=tol), repeats)
        row("fft adaptive (sampling doubled)", f"tol={tol:g} -> M={spectrum.samples}", elapsed,
            amplitude_error(spectrum))
    elapsed, spectrum = _median_time(lambda: fourier.analyse(law, HARMONICS), repeats)
    row("exact, closed-form pieces", "composite law", elapsed, amplitude_error(spectrum))

    # truncation: the series cut after N harmonics against the law itself (RMS over the cycle, mm);
    # the time is that of evaluating the truncated series on 4096 points
    full = fourier.analyse(law, 256)
    grid = np.linspace(0.0, TWO_PI, 4096, endpoint=False)
    exact_s = law.kinematics(grid).s
    for n in (4, 16, 64, 256):
        kept = fourier.FourierLaw(TWO_PI, full.mean, full.coefficients[:n], law.phases)
        elapsed, s_n = _median_time(lambda kept=kept: kept.kinematics(grid).s, repeats)
        rows.append({"kernel": "fourier truncation", "method": "series cut after N harmonics", "setting": f"N={n}",
                         "time_s": elapsed, "error": float(np.sqrt(np.mean((s_n - exact_s) ** 2))),
                         "error_unit": "mm RMS vs the law's closed-form s",
                         "reference": "the composite law's own s(θ)"})

    # filtering the law sampled at 2^16 points
    count = 1 << 16
    theta = np.arange(count + 1) * (TWO_PI / count)
    polyline = PiecewiseLinearLaw(theta, law.kinematics(theta).a, TWO_PI, law.phases)
    band = fourier.resonant_harmonics(160.0, (330.0, 420.0), 0.05, 1)
    removed = np.array(band.removed) - 1

    # the band left in the filtered law, measured by another route than the filter's own construction (which
    # subtracts the removed terms, so its exact analysis gives 0 by design): an FFT of 2^16 samples of s of
    # the filtered law (aliasing ~ the coefficients beyond 2^15, negligible here), and for the written
    # polyline an FFT of its vertices' a interpolated on 2^18 points, A_k(s) = A_k(a)/k²
    def band_left(filtered_law):
        samples = 1 << 16
        s_samples = filtered_law.kinematics(np.arange(samples) * (TWO_PI / samples)).s
        return float(np.max(2 * np.abs(np.fft.rfft(s_samples)[removed + 1]) / samples))

    def band_left_polyline(polyline):
        samples = 1 << 18
        theta = np.arange(samples) * (TWO_PI / samples)
        a = np.interp(theta, polyline.x, polyline.a)
        k = removed + 1
        return float(np.max(2 * np.abs(np.fft.rfft(a)[k]) / samples / k**2))

    fft_unit = "mm left in band, by FFT of samples"
    elapsed, result = _median_time(lambda: fourier.filter_law(polyline, band, keep_dwells=False), repeats)
    row("filter: remove band", f"M={count}, k={band.removed[0]}..{band.removed[-1]}", elapsed,
        band_left(result.law), fft_unit)
    elapsed, kept = _median_time(lambda: fourier.filter_law(polyline, band, dwell_tol=1e-4), max(1, repeats // 2))
    row("filter: remove band, keep dwells", f"M={count}, dwell tol 1e-4 mm -> {kept.dwell_deviation:.2g} mm",
        elapsed, band_left(kept.law), fft_unit)
    elapsed, exported = _median_time(lambda: fourier.export_polyline(result.law, removed=band.removed),
                                     max(1, repeats // 2))
    row("export: closed 0.1 deg polyline", f"{len(exported.law.x)} vertices", elapsed,
        band_left_polyline(exported.law), "mm left in band, by FFT of the written polyline")
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats, smaller scattered-knot case")
    args = parser.parse_args()
    rows = run(args.quick)
    print(f"{'method':34} | {'setting':44} | {'time (median)':>13} | error (and its reference)")
    print("-" * 122)
    for r in rows:
        print(f"{r['method']:34} | {r['setting']:44} | {r['time_s'] * 1e3:10.2f} ms | "
              f"{r['error']:.3g} {r['error_unit']}")


if __name__ == "__main__":
    main()
