"""Fourier analysis and synthesis of motion laws, and resonance filtering (docs/references.md, the batten study).

Conventions
-----------
A law is periodic with period T = ``cycle`` (rad); ω0 = 2π/T is the fundamental (per radian of cam
angle). The displacement series is written in the source's form, with amplitudes and *initial phases*:

    s(θ) = mean + Σ_{k≥1} A_k sin(k ω0 θ + φ_k),        A_k ≥ 0 (mm), φ_k ∈ (−π, π].

Internally the complex coefficients c_k = (1/T) ∫_0^T s(θ) e^{−i k ω0 θ} dθ are kept, so that
s = c_0 + 2 Re Σ c_k e^{i k ω0 θ}, A_k = 2|c_k| and φ_k = arg c_k + π/2. The acceleration analog
a = d²s/dθ² (mm/rad²) is analysed the same way with its own coefficients. At a cam speed n (rpm) the
k-th harmonic has the frequency k·n/60 Hz.

Exact coefficients
------------------
* A piecewise-linear acceleration (a drawn law) has a piecewise-cubic s. Integrating by parts on each
  piece and summing, every term cancels except the jumps Δf^{(m)} = f^{(m)}(x⁺) − f^{(m)}(x⁻) of the
  derivatives at the knots x_j (the jump at θ = 0 is s(0⁺) − s(T⁻), the cycle closure):

      ∫_0^T f(θ) e^{−iwθ} dθ = Σ_j e^{−iw x_j} Σ_{m=0}^{3} Δ_j f^{(m)} / (iw)^{m+1},   w = k ω0.

  Exact for every k; on uniformly spaced knots the knot sums are one FFT.
* A composite standard law (``standard.compose``) is, on each phase, a polynomial plus complex
  exponentials in t = θ − θ0. ∫_0^L t^m e^{−iwt} dt = L^{m+1} E_m(wL) with E_m(z) = ∫_0^1 u^m e^{−izu} du
  (Gauss–Legendre, exact to round-off, for |z| < 8; the recurrence E_m = (m E_{m−1} − e^{−iz})/(iz),
  stable for |z| ≥ 8, otherwise), and ∫_0^L e^{iλt} e^{−iwt} dt = L e^{iδ} sin δ/δ, δ = (λ − w)L/2.
* Any other law: FFT of a uniform sampling, doubled until two successive samplings agree on the first
  N amplitudes within the tolerance (the trapezoidal rule; the sample at θ = 0 is the mean of s(0) and
  s(T), the value the Fourier series converges to at a closure jump).

Truncation error (Parseval): (1/T)∫(s − s_N)² dθ = Σ_{k>N} A_k²/2. The sum over the computed
harmonics is exact; beyond them the remainder is estimated from the jump asymptotics
|c_k|² ≈ (1/T²) Σ_m Σ_j |Δ_j f^{(m)}|² / (kω0)^{2m+2} (averaged over k), summed with the Hurwitz zeta.

Sources: PhD abstract on the batten mechanism of the STB loom, Novosibirsk (the batten study; docs/references.md:
harmonic patterns, RMS error against the number of harmonics, resonance filtering of the 17th harmonic
and its neighbours, lead-in segments of 14° at 0.1 of the peak acceleration); A. Zygmund,
Trigonometric Series (1959), ch. II (integration by parts, Parseval); W. H. Press et al., Numerical
Recipes, 3rd ed. (2007), §13.9 (Fourier integrals of piecewise polynomials).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from camcad.lazy import lazy_exports

if TYPE_CHECKING:  # the names for type checkers and IDEs; at run time they load on first use
    from camcad.fourier.analysis import HEADROOM, analyse, analyse_samples, exact_available, least_harmonics, max_errors
    from camcad.fourier.exact import (
        EPS,
        Piece,
        composite_pieces,
        knot_sums,
        monomial_moments,
        shape_terms,
        tail_mean_square,
        uniform_grid_size,
    )
    from camcad.fourier.export import ExportedLaw, acceleration_polyline, export_polyline
    from camcad.fourier.filter import FilterResult, dwell_grid, filter_law, motion_starts, start_accelerations
    from camcad.fourier.leadin import LeadInResult, add_lead_in
    from camcad.fourier.patterns import (
        TACHOGRAMS,
        MotionPattern,
        Synthesis,
        motion_pattern,
        pattern_coefficients,
        pattern_database,
        synthesise_standard,
        tachogram,
    )
    from camcad.fourier.resonance import ResonanceBand, resonant_harmonics, speed_range
    from camcad.fourier.series import (
        CorrectedLaw,
        FourierLaw,
        Spectrum,
        amplitudes_of,
        coefficients_from,
        evaluate_series,
        evaluate_series_orders,
        initial_phases_of,
        series_on_grid,
    )

#: public name -> the module that defines it (imported on first use: importing this package stays cheap)
_EXPORTS: dict[str, str] = {
    "CorrectedLaw": "camcad.fourier.series",
    "EPS": "camcad.fourier.exact",
    "ExportedLaw": "camcad.fourier.export",
    "FilterResult": "camcad.fourier.filter",
    "FourierLaw": "camcad.fourier.series",
    "HEADROOM": "camcad.fourier.analysis",
    "LeadInResult": "camcad.fourier.leadin",
    "MotionPattern": "camcad.fourier.patterns",
    "Piece": "camcad.fourier.exact",
    "ResonanceBand": "camcad.fourier.resonance",
    "Spectrum": "camcad.fourier.series",
    "Synthesis": "camcad.fourier.patterns",
    "TACHOGRAMS": "camcad.fourier.patterns",
    "acceleration_polyline": "camcad.fourier.export",
    "add_lead_in": "camcad.fourier.leadin",
    "amplitudes_of": "camcad.fourier.series",
    "analyse": "camcad.fourier.analysis",
    "analyse_samples": "camcad.fourier.analysis",
    "coefficients_from": "camcad.fourier.series",
    "composite_pieces": "camcad.fourier.exact",
    "dwell_grid": "camcad.fourier.filter",
    "evaluate_series": "camcad.fourier.series",
    "evaluate_series_orders": "camcad.fourier.series",
    "exact_available": "camcad.fourier.analysis",
    "export_polyline": "camcad.fourier.export",
    "filter_law": "camcad.fourier.filter",
    "initial_phases_of": "camcad.fourier.series",
    "knot_sums": "camcad.fourier.exact",
    "least_harmonics": "camcad.fourier.analysis",
    "max_errors": "camcad.fourier.analysis",
    "monomial_moments": "camcad.fourier.exact",
    "motion_pattern": "camcad.fourier.patterns",
    "motion_starts": "camcad.fourier.filter",
    "pattern_coefficients": "camcad.fourier.patterns",
    "pattern_database": "camcad.fourier.patterns",
    "resonant_harmonics": "camcad.fourier.resonance",
    "series_on_grid": "camcad.fourier.series",
    "shape_terms": "camcad.fourier.exact",
    "speed_range": "camcad.fourier.resonance",
    "start_accelerations": "camcad.fourier.filter",
    "synthesise_standard": "camcad.fourier.patterns",
    "tachogram": "camcad.fourier.patterns",
    "tail_mean_square": "camcad.fourier.exact",
    "uniform_grid_size": "camcad.fourier.exact",
}


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())


__all__ = [
    "EPS",
    "HEADROOM",
    "TACHOGRAMS",
    "CorrectedLaw",
    "ExportedLaw",
    "FilterResult",
    "FourierLaw",
    "LeadInResult",
    "MotionPattern",
    "Piece",
    "ResonanceBand",
    "Spectrum",
    "Synthesis",
    "acceleration_polyline",
    "add_lead_in",
    "amplitudes_of",
    "analyse",
    "analyse_samples",
    "coefficients_from",
    "composite_pieces",
    "dwell_grid",
    "evaluate_series",
    "evaluate_series_orders",
    "exact_available",
    "export_polyline",
    "filter_law",
    "initial_phases_of",
    "knot_sums",
    "least_harmonics",
    "max_errors",
    "monomial_moments",
    "motion_pattern",
    "motion_starts",
    "pattern_coefficients",
    "pattern_database",
    "resonant_harmonics",
    "series_on_grid",
    "shape_terms",
    "speed_range",
    "start_accelerations",
    "synthesise_standard",
    "tachogram",
    "tail_mean_square",
    "uniform_grid_size",
]
