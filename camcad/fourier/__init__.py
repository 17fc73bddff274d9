"""Fourier analysis and synthesis of motion laws, and resonance filtering (background.md §2, seed 001).

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

Sources: PhD abstract on the batten mechanism of the STB loom, Novosibirsk (seed 001; background.md §2:
harmonic patterns, RMS error against the number of harmonics, resonance filtering of the 17th harmonic
and its neighbours, lead-in segments of 14° at 0.1 of the peak acceleration); A. Zygmund,
Trigonometric Series (1959), ch. II (integration by parts, Parseval); W. H. Press et al., Numerical
Recipes, 3rd ed. (2007), §13.9 (Fourier integrals of piecewise polynomials).
"""

from __future__ import annotations

from camcad.fourier.series import (
    amplitudes_of,
    initial_phases_of,
    coefficients_from,
    evaluate_series,
    evaluate_series_orders,
    series_on_grid,
    FourierLaw,
    CorrectedLaw,
    Spectrum,
)
from camcad.fourier.exact import (
    EPS,
    monomial_moments,
    Piece,
    shape_terms,
    composite_pieces,
    uniform_grid_size,
    knot_sums,
    tail_mean_square,
)
from camcad.fourier.analysis import exact_available, analyse, analyse_samples, max_errors, HEADROOM, least_harmonics
from camcad.fourier.patterns import (
    MotionPattern,
    motion_pattern,
    pattern_database,
    TACHOGRAMS,
    tachogram,
    Synthesis,
    pattern_coefficients,
    synthesise_standard,
)
from camcad.fourier.resonance import ResonanceBand, resonant_harmonics, speed_range
from camcad.fourier.filter import motion_starts, dwell_grid, start_accelerations, FilterResult, filter_law
from camcad.fourier.export import acceleration_polyline, ExportedLaw, export_polyline
from camcad.fourier.leadin import LeadInResult, add_lead_in


__all__ = [
    "CorrectedLaw",
    "EPS",
    "ExportedLaw",
    "FilterResult",
    "FourierLaw",
    "HEADROOM",
    "LeadInResult",
    "MotionPattern",
    "Piece",
    "ResonanceBand",
    "Spectrum",
    "Synthesis",
    "TACHOGRAMS",
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
    "speed_range",
    "pattern_coefficients",
    "pattern_database",
    "resonant_harmonics",
    "series_on_grid",
    "shape_terms",
    "start_accelerations",
    "synthesise_standard",
    "tachogram",
    "tail_mean_square",
    "uniform_grid_size",
]
