"""Fourier analysis, synthesis, resonance filtering and lead-in segments (camcad.fourier).

Every figure is checked against something independent of the code under test: a closed form derived
here (derivation in the comment), numerical quadrature (scipy.integrate.quad, Gauss–Legendre), a second
method (FFT of samples against exact integration), or the balance check of another module.
"""

from __future__ import annotations

import json
import math
from itertools import pairwise
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

from camcad import balance, fourier
from camcad.errors import CamcadError
from camcad.law.law import Phase, PiecewiseLinearLaw
from camcad.law.standard import compose
from camcad.scene import filtering as scene_filtering
from camcad.scene.sections import filter as scene_filter

LIFT = 25.0
TWO_PI = 2.0 * np.pi
# dwell 70°, cycloidal rise 100°, dwell 110°, cycloidal return 80°: no k·β is a multiple of 360°
# for k < 9, so the closed form below has no removable singularity in the range tested first.
DRDR = [("dwell", 70.0), ("rise", 100.0), ("dwell", 110.0), ("return", 80.0)]


@pytest.fixture(scope="module")
def drdr():
    return compose(DRDR, LIFT, "cycloidal")


def cycloidal_drdr_coefficients(k: np.ndarray, lift: float = LIFT) -> tuple[np.ndarray, np.ndarray]:
    """Closed-form c_k of s and of a for the DRDR cycle with cycloidal rise and return (T = 2π, ω0 = 1).

    Derivation. On a cycloidal rise of lift h over β from θ1, a = (2πh/β²) sin(λ(θ − θ1)), λ = 2π/β, and
    a = 0 on the dwells. With w = k and t = θ − θ1,
        ∫_0^β sin(λt) e^{−iwt} dt = [e^{−iwt}(−iw sin λt − λ cos λt)/(λ² − w²)]_0^β = λ(1 − e^{−iwβ})/(λ² − w²)
    because λβ = 2π. So the rise gives
        c_k(a) = (1/T)(2πh/β²) e^{−iwθ1} λ(1 − e^{−iwβ})/(λ² − w²)
               = (h/T) 4π² e^{−iwθ1}(1 − e^{−iwβ}) / (β(4π² − w²β²)),
    and the return (a of the opposite sign) the same with −h. s and v are continuous and periodic, so two
    integrations by parts give c_k(s) = c_k(a)/(iw)² = −c_k(a)/w². Amplitude A_k = 2|c_k(s)|.
    """
    w = np.asarray(k, dtype=float)

    def motion(start_deg, width_deg, h):
        theta1, beta = np.radians(start_deg), np.radians(width_deg)
        return h * 4 * np.pi**2 * np.exp(-1j * w * theta1) * (1 - np.exp(-1j * w * beta)) / (
            TWO_PI * beta * (4 * np.pi**2 - w**2 * beta**2))

    accel = motion(70.0, 100.0, lift) + motion(280.0, 80.0, -lift)
    return -accel / w**2, accel


# ---------------------------------------------------------------------------------------------
# Analysis
# ---------------------------------------------------------------------------------------------

@pytest.mark.reference("closed form", "c_k of the cycloidal DRDR law derived in cycloidal_drdr_coefficients (two "
                                      "integrations by parts)")
def test_cycloidal_drdr_amplitudes_equal_closed_form(drdr):
    k = np.arange(1, 201)
    k = k[(k % 9 != 0)]  # k = 9m: k·80° = 2π·2m, the return's term is 0/0 in the closed form (its limit is 0)
    expected_s, expected_a = cycloidal_drdr_coefficients(k)
    spectrum = fourier.analyse(drdr, 200)
    assert spectrum.method == "exact"
    got = spectrum.coefficients[k - 1]
    # amplitudes A_k = 2|c_k| and the full complex coefficient (so the initial phases too)
    assert np.max(np.abs(spectrum.amplitudes[k - 1] - 2 * np.abs(expected_s))) <= 1e-9 * LIFT
    assert np.max(np.abs(2 * (got - expected_s))) <= 1e-9 * LIFT
    assert np.max(np.abs(spectrum.accel_coefficients[k - 1] - expected_a)) <= 1e-9 * LIFT
    # the measured agreement is round-off (about 4e-15 of the lift); the stated bound covers it
    assert spectrum.coefficient_error <= 1e-12 * LIFT
    # k = 9m: k·80° = 2m whole turns, so the return's numerator 1 − e^{−ikβ} is 0 while its denominator
    # 4π² − (kβ)² is not (kβ ≠ 2π): the return adds nothing. The rise (k·100° = 2.5m turns) remains for
    # odd m and vanishes too for even m.
    for k in (9, 27, 45):
        w, theta1, beta = float(k), np.radians(70.0), np.radians(100.0)
        rise = LIFT * 4 * np.pi**2 * np.exp(-1j * w * theta1) * (1 - np.exp(-1j * w * beta)) / (
            TWO_PI * beta * (4 * np.pi**2 - w**2 * beta**2))
        assert abs(spectrum.coefficients[k - 1] - (-rise / w**2)) <= 1e-9 * LIFT / 2
    for k in (18, 36):
        assert spectrum.amplitudes[k - 1] <= 1e-12 * LIFT


@pytest.mark.reference("second method", "the series summed here with numpy's sin from the reported amplitudes and "
                                        "phases; the mean h x 200/360 by hand")
def test_sine_form_and_phases_reproduce_the_law(drdr):
    # s(θ) = mean + Σ A_k sin(kθ + φ_k), evaluated here with numpy's sin from the reported amplitudes and
    # initial phases, must converge to the law; with 400 harmonics the truncation is ~3e-8 mm (A_k ~ k⁻⁴).
    spectrum = fourier.analyse(drdr, 400)
    theta = np.linspace(0, TWO_PI, 1001)
    k = spectrum.harmonics
    series = spectrum.mean + np.sin(np.outer(theta, k) + spectrum.phases) @ spectrum.amplitudes
    assert np.max(np.abs(series - drdr.kinematics(theta).s)) <= 1e-6
    # the mean is (1/T)∫s: rise and return each contribute h·β/2 (cycloid symmetric about its midpoint)
    # and the far dwell h·110°: (25·50° + 25·110° + 25·40°)/360° = 25·200/360
    assert spectrum.mean == pytest.approx(LIFT * 200.0 / 360.0, abs=1e-12 * LIFT)


@pytest.mark.reference("second method", "Parseval with (1/T) int (s - s_N)^2 by Gauss-Legendre on each phase, "
                                        "independent of the coefficients")
def test_truncation_rms_obeys_parseval(drdr):
    # Parseval: (1/T)∫(s − s_N)² dθ = Σ_{k>N} A_k²/2. The left side is integrated here by Gauss–Legendre
    # on each phase (s is analytic on each, s_N is a trigonometric polynomial of degree ≤ 200: 600 nodes
    # per phase of ≤ 110° integrate its square, e^{±i400θ}, to round-off), independently of the
    # coefficients. At N = 200 = K the reported RMS is the remainder alone (exact terms to 4K, then the
    # jump asymptotics), so that is checked too.
    spectrum = fourier.analyse(drdr, 200)
    nodes, weights = np.polynomial.legendre.leggauss(600)
    for n in (1, 3, 8, 21, 40, 100, 200):
        total = 0.0
        for phase in drdr.phases:
            half = phase.width / 2
            theta = phase.start + half * (nodes + 1)
            partial = spectrum.mean + np.sin(np.outer(theta, np.arange(1, n + 1)) + spectrum.phases[:n]) \
                @ spectrum.amplitudes[:n]
            total += half * np.sum(weights * (drdr.kinematics(theta).s - partial) ** 2)
        direct = math.sqrt(total / TWO_PI)
        assert abs(spectrum.rms_error(n) - direct) <= 1e-12 * LIFT, n
    # the whole: Σ_{k≤200} A_k²/2 + remainder estimate = (1/T)∫(s − mean)² (exact Gauss–Legendre of s²)
    parseval = np.sum(spectrum.amplitudes**2) / 2 + spectrum.tail_mean_square
    assert parseval == pytest.approx(spectrum.mean_square, rel=1e-12)


@pytest.mark.reference("second method", "E_m(z) = int_0^1 u^m e^(-izu) du by Gauss-Legendre quadrature")
def test_monomial_moments_against_quadrature():
    # E_m(z) = ∫_0^1 u^m e^{−izu} du on both sides of the switch at |z| = 8 (Gauss–Legendre / recurrence)
    z = np.array([0.0, 0.5, 7.9, 8.1, 30.0, 250.0])
    moments = fourier.monomial_moments(z, 7)
    for m in (0, 3, 7):
        for zi, got in zip(z, moments[m]):
            re = quad(lambda u, m=m, zi=zi: u**m * np.cos(zi * u), 0, 1, epsabs=1e-15, limit=400)[0]
            im = -quad(lambda u, m=m, zi=zi: u**m * np.sin(zi * u), 0, 1, epsabs=1e-15, limit=400)[0]
            assert abs(got - (re + 1j * im)) <= 1e-13, (m, zi)


def parabolic_drdr(unbalance: float = 0.0) -> PiecewiseLinearLaw:
    """Constant-acceleration rise (60–160°) and return (250–330°): a = ±A with jumps.

    Each half of a motion of width β at |a| = A moves A(β/2)²/2, so A = h/(β/2)² gives the lift h.
    The unequal widths keep the jump positions irregular, so no harmonic below 64 vanishes.
    """
    rise, back = np.radians(100.0), np.radians(80.0)
    up, down = LIFT / (rise / 2) ** 2, LIFT / (back / 2) ** 2
    deg = np.array([0, 60, 60, 110, 110, 160, 160, 250, 250, 290, 290, 330, 330, 360], dtype=float)
    a = np.array([0, 0, up, up, -up, -up, 0, 0, -down, -down, down, down * (1 + unbalance), 0, 0])
    phases = (Phase("dwell", 0, np.radians(60)), Phase("rise", np.radians(60), np.radians(160)),
              Phase("dwell", np.radians(160), np.radians(250)), Phase("return", np.radians(250), np.radians(330)),
              Phase("dwell", np.radians(330), TWO_PI))
    return PiecewiseLinearLaw(np.radians(deg), a, TWO_PI, phases)


@pytest.mark.reference("second method", "scipy quad of (1/T) int s cos k theta and sin k theta, piece by piece")
@pytest.mark.filterwarnings("ignore::scipy.integrate.IntegrationWarning")
@pytest.mark.parametrize("unbalance", [0.0, 0.2])
def test_drawn_law_coefficients_against_quadrature(unbalance):
    # The exact jump formula against adaptive quadrature of (1/T)∫ s cos kθ and sin kθ, piece by piece.
    # With unbalance the drawn law does not close (s(T) ≠ s(0)): the series is that of the periodic
    # extension, which the quadrature over [0, T) computes by definition.
    law = parabolic_drdr(unbalance)
    spectrum = fourier.analyse(law, 40)
    assert abs(law.kinematics(np.array([TWO_PI])).s[0]) > 0.1 or unbalance == 0.0
    breaks = np.unique(law.x)

    def integral(f):
        return sum(quad(f, lo, hi, epsabs=1e-14, epsrel=1e-13, limit=200)[0] for lo, hi in pairwise(breaks))

    def s(t):
        return law.kinematics(np.array([t])).s[0]

    def a(t):
        return law.kinematics(np.array([t])).a[0]

    for k in (1, 2, 7, 23, 40):
        expected = (integral(lambda t, k=k: s(t) * np.cos(k * t))
                    - 1j * integral(lambda t, k=k: s(t) * np.sin(k * t))) / TWO_PI
        assert abs(spectrum.coefficients[k - 1] - expected) <= 1e-11 * LIFT, k
        expected_a = (integral(lambda t, k=k: a(t) * np.cos(k * t))
                      - 1j * integral(lambda t, k=k: a(t) * np.sin(k * t))) / TWO_PI
        assert abs(spectrum.accel_coefficients[k - 1] - expected_a) <= 1e-10 * LIFT, k
    mean = integral(lambda t: law.kinematics(np.array([t])).s[0]) / TWO_PI
    assert spectrum.mean == pytest.approx(mean, abs=1e-11 * LIFT)


class Opaque:
    """A law the exact methods do not know, so ``analyse`` must sample it."""

    def __init__(self, law):
        self.law = law
        self.cycle = law.cycle
        self.phases = law.phases

    def kinematics(self, theta):
        return self.law.kinematics(theta)


@pytest.mark.reference("second method", "the exact analysis bounds the FFT path's stated error")
@pytest.mark.parametrize("tol", [1e-7, 1e-10])
def test_fft_path_reaches_its_tolerance(drdr, tol):
    exact = fourier.analyse(drdr, 64)
    sampled = fourier.analyse(Opaque(drdr), 64, tol=tol)
    assert sampled.method == "fft" and sampled.converged
    error = np.max(np.abs(sampled.amplitudes - exact.amplitudes))
    # the stopping rule (difference of two samplings) is the stated error, and it bounds the true one
    assert error <= sampled.coefficient_error <= tol
    assert sampled.mean == pytest.approx(exact.mean, abs=tol)


@pytest.mark.reference("second method", "the exact analysis of a law whose s jumps at the cycle end")
def test_fft_path_on_a_law_with_a_closure_jump():
    # the sample at θ = 0 is the mean of s(0) and s(T), where the series converges; the aliasing of a
    # 1/k spectrum then falls like 1/M², and the sampling is doubled until the tolerance is met
    law = parabolic_drdr(0.2)
    exact = fourier.analyse(law, 32)
    sampled = fourier.analyse(Opaque(law), 32, tol=1e-8)
    assert sampled.converged
    assert np.max(np.abs(sampled.amplitudes - exact.amplitudes)) <= 1e-8


@pytest.mark.reference("second method", "the direct sum sum_j D_j e^(-ik w0 x_j) against the FFT route")
@settings(max_examples=25, deadline=None)
@given(st.integers(min_value=16, max_value=300), st.integers(min_value=0, max_value=2**31 - 1))
def test_uniform_knot_fft_equals_direct_sum(count, seed):
    # knot_sums takes one FFT on uniformly spaced knots and a direct sum otherwise: two evaluations of
    # the same exact sum Σ_j Δ_j e^{−ikω0 x_j}, which must agree to round-off for every k (even k > M).
    rng = np.random.default_rng(seed)
    positions = np.arange(count) * (TWO_PI / count)
    deltas = rng.normal(size=(2, count))
    w = np.arange(1, 2 * count + 5).astype(float)
    fast = fourier.knot_sums(positions, deltas, w, TWO_PI)
    direct = deltas @ np.exp(-1j * np.outer(positions, w))
    assert np.max(np.abs(fast - direct)) <= 1e-11 * np.abs(deltas).sum()


@pytest.mark.reference("closed form", "chord-error bound |dc_k| <= h^2 max|a''|/(8 k^2) against the analytic law's "
                                      "exact coefficients")
def test_sampled_law_exact_and_fft_agree_with_reference(drdr):
    # a at 2^12 uniform points as a drawn polyline: its exact coefficients differ from the analytic law's
    # by the chord error of the polyline, |Δa| ≤ h²·max|a''|/8, so |Δc_k| ≤ h²·max|a''|/(8k²) per unit.
    count = 1 << 12
    theta = np.arange(count + 1) * (TWO_PI / count)
    polyline = PiecewiseLinearLaw(theta, drdr.kinematics(theta).a, TWO_PI, drdr.phases)
    reference = fourier.analyse(drdr, 64)
    exact = fourier.analyse(polyline, 64)
    h = TWO_PI / count
    a2_max = LIFT * (TWO_PI / np.radians(80.0)) ** 3 * TWO_PI / np.radians(80.0)  # |a''| of the faster motion
    bound = h**2 * a2_max / 8 / np.arange(1, 65) ** 2 * 2
    assert np.all(np.abs(exact.amplitudes - reference.amplitudes) <= bound)
    samples = fourier.analyse_samples(drdr.kinematics(theta[:-1]).s, TWO_PI, 64)
    # uniform samples of an analytic-per-phase law: aliasing Σ c_{k±jM}, |c_k| ~ k⁻⁴, far below 1e-10
    assert np.max(np.abs(samples.amplitudes - reference.amplitudes)) <= 1e-10


@pytest.mark.reference("closed form", "term by term: d/dtheta A sin(k theta + phi) = kA cos(k theta + phi), and so on")
def test_fourier_law_round_trip_and_derivatives():
    amplitudes = np.array([3.0, 0.5, 0.0, 0.125])
    phases = np.array([0.3, -2.0, 1.0, 3.0])
    law = fourier.FourierLaw.from_amplitudes(amplitudes, phases, 7.0, TWO_PI)
    theta = np.linspace(0, TWO_PI, 257)
    k = np.arange(1, 5)
    arg = np.outer(theta, k) + phases
    kin = law.kinematics(theta)
    # term by term: d/dθ A sin(kθ + φ) = kA cos(kθ + φ), d²: −k²A sin, d³: −k³A cos
    assert np.allclose(kin.s, 7.0 + np.sin(arg) @ amplitudes, atol=1e-13)
    assert np.allclose(kin.v, np.cos(arg) @ (k * amplitudes), atol=1e-13)
    assert np.allclose(kin.a, -np.sin(arg) @ (k**2 * amplitudes), atol=1e-13)
    assert np.allclose(kin.j, -np.cos(arg) @ (k**3 * amplitudes), atol=1e-12)
    spectrum = fourier.analyse(law, 6)
    assert np.allclose(spectrum.amplitudes[:4], amplitudes, atol=1e-14)
    keep = amplitudes > 0
    assert np.allclose(spectrum.phases[:4][keep], phases[keep], atol=1e-14)
    assert spectrum.rms_error(2) == pytest.approx(math.sqrt(0.125**2 / 2), rel=1e-14)


@pytest.mark.reference("property", "max >= RMS for every N; the sampled maximum agrees with a 4x finer sampling to "
                                   "1e-3")
def test_max_error_is_at_least_the_rms_error(drdr):
    spectrum = fourier.analyse(drdr, 64)
    ns = [1, 4, 16, 32]
    maxima = fourier.max_errors(drdr, spectrum, ns)
    assert np.all(maxima >= np.array([spectrum.rms_error(n) for n in ns]))
    # and the sampled maximum agrees with a 4× finer sampling to 1e-3 relative
    finer = fourier.max_errors(drdr, spectrum, ns, samples=1 << 17)
    assert np.allclose(maxima, finer, rtol=1e-3)


# ---------------------------------------------------------------------------------------------
# The database of patterns, and synthesis from it
# ---------------------------------------------------------------------------------------------

@pytest.mark.reference("closed form", "Fourier transforms of the cycloidal and harmonic f' derived in the test; 3-4-5 "
                                      "by quadrature")
def test_patterns_equal_their_closed_forms():
    database = fourier.pattern_database()
    z = np.array([0.3, 1.0, 5.0, 7.99, 8.01, 20.0, 100.0, 1000.0])
    # cycloidal: f' = 1 − cos 2πu; ∫_0^1 e^{−izu} = (1 − e^{−iz})/(iz), ∫_0^1 cos(2πu) e^{−izu} du =
    # ½[(e^{−iz} − 1)/(i(2π − z)) + (e^{−iz} − 1)/(−i(2π + z))] ⇒ Φ = (1 − e^{−iz})/i · 4π²/(z(4π² − z²))
    cycloidal = (1 - np.exp(-1j * z)) / 1j * 4 * np.pi**2 / (z * (4 * np.pi**2 - z**2))
    assert np.max(np.abs(database["cycloidal"].transform(z) - cycloidal)) <= 1e-13
    # harmonic: f' = (π/2) sin πu; ∫_0^1 sin(πu) e^{−izu} du = π(1 + e^{−iz})/(π² − z²)
    harmonic = (np.pi / 2) * np.pi * (1 + np.exp(-1j * z)) / (np.pi**2 - z**2)
    assert np.max(np.abs(database["harmonic"].transform(z) - harmonic)) <= 1e-13
    # 3-4-5: against quadrature of f' = 30u² − 60u³ + 30u⁴
    def fp(u):
        return 30 * u**2 - 60 * u**3 + 30 * u**4

    for zi in (0.7, 9.0, 40.0):
        expected = quad(lambda u, zi=zi: fp(u) * np.cos(zi * u), 0, 1, epsabs=1e-15)[0] - \
            1j * quad(lambda u, zi=zi: fp(u) * np.sin(zi * u), 0, 1, epsabs=1e-15)[0]
        assert abs(database["poly345"].transform(zi)[0] - expected) <= 1e-13
    # moments ∫f and ∫f²: 1/2 for every symmetric rise; ∫f² of the 3-4-5 is 181/462 (integrate the polynomial)
    assert database["poly345"].moments[0] == pytest.approx(0.5, abs=1e-15)
    assert database["poly345"].moments[1] == pytest.approx(181 / 462, abs=1e-15)


@pytest.mark.reference("second method", "patterns of v (the database) against direct integration of s")
def test_database_matches_direct_analysis(drdr):
    # two routes to one spectrum: patterns of v (database) against direct integration of s
    from_patterns = fourier.pattern_coefficients(DRDR, LIFT, "cycloidal", harmonics=100)
    direct = fourier.analyse(drdr, 100)
    assert np.max(np.abs(from_patterns.coefficients - direct.coefficients)) <= 1e-13 * LIFT
    assert from_patterns.mean == pytest.approx(direct.mean, abs=1e-13 * LIFT)
    assert from_patterns.mean_square == pytest.approx(direct.mean_square, rel=1e-13)


@pytest.mark.reference("second method", "the synthesised law against the closed-form law by the trapezoidal rule on "
                                        "2^15 points")
@pytest.mark.parametrize("kind, shape, tol", [("DRDR", "cycloidal", 1e-3), ("DRRD", "poly345", 1e-4),
                                              ("DRRD", "harmonic", 1e-3), ("DRDR", "poly4567", 1e-5)])
def test_database_synthesis_reaches_the_accuracy_with_the_predicted_n(kind, shape, tol):
    phases = fourier.tachogram(kind, 100.0, 80.0, far_dwell_deg=110.0, start_deg=70.0) if kind == "DRDR" else \
        fourier.tachogram(kind, 90.0, 90.0, start_deg=30.0)
    lift = 10.0
    result = fourier.synthesise_standard(phases, lift, tol * lift, shape=shape)
    n = result.harmonics
    # measured independently: the synthesised law against the closed-form law, trapezoidal rule on 2^15
    # points (exact for the trigonometric part; the law's harmonics beyond 2^14 are below 1e-18 mm)
    exact = compose(phases, lift, shape)
    theta = np.arange(1 << 15) * (TWO_PI / (1 << 15))
    s = exact.kinematics(theta).s

    def rms(law):
        return float(np.sqrt(np.mean((law.kinematics(theta).s - s) ** 2)))

    assert rms(result.law) <= tol * lift
    fewer = fourier.FourierLaw(TWO_PI, result.law.mean, result.law.coefficients[:n - 1])
    assert rms(fewer) > tol * lift           # N is the least that reaches it
    assert result.reached and result.rms_measured == pytest.approx(rms(result.law), rel=1e-9)
    assert result.rms_predicted == pytest.approx(rms(result.law), rel=1e-6)


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_tachogram_errors():
    with pytest.raises(CamcadError):
        fourier.tachogram("DRD", 90, 90)
    with pytest.raises(CamcadError):
        fourier.tachogram("DRRD", 200, 200)
    with pytest.raises(CamcadError):
        fourier.tachogram("DRDR", 90, 90)  # no far dwell


# ---------------------------------------------------------------------------------------------
# Resonance filtering
# ---------------------------------------------------------------------------------------------

@pytest.mark.reference("closed form", "k resonant iff 60 fn (1 - b)/n2 <= k <= 60 fn (1 + b)/n1: [15, 20] at 100 Hz, "
                                      "300-400 rpm")
def test_band_edges_are_included_exactly():
    # k resonant ⇔ 60 fn(1 − b)/n2 ≤ k ≤ 60 fn(1 + b)/n1: fn = 100 Hz, n = 300…400 rpm, b = 0 gives
    # exactly [15, 20]; moving fn by 1e-7 relative moves each edge across an integer.
    assert fourier.resonant_harmonics(100.0, (300, 400), 0.0, 0).core == tuple(range(15, 21))
    assert fourier.resonant_harmonics(100.0 * (1 - 1e-7), (300, 400), 0.0, 0).core == tuple(range(15, 20))
    assert fourier.resonant_harmonics(100.0 * (1 + 1e-7), (300, 400), 0.0, 0).core == tuple(range(16, 21))
    # b = 0.05: [14.25, 21.0] → 15…21, with one neighbour 14…22; a taper of 2 adds 13, 12 and 23, 24
    band = fourier.resonant_harmonics(100.0, (300, 400), 0.05, 1, taper=2)
    assert band.core == tuple(range(15, 22))
    assert band.removed == tuple(range(14, 23))
    assert band.gains[13] == pytest.approx(math.sin(math.pi / 6) ** 2) and band.gains[12] == pytest.approx(0.75)
    assert band.gains[23] == band.gains[13] and 11 not in band.gains and 25 not in band.gains
    # one speed: k n/60 = fn ± 5 % at 330 rpm → k ∈ [27.636, 30.545]
    assert fourier.resonant_harmonics(160.0, 330, 0.05, 0).core == (28, 29, 30)


def fft_amplitudes(s: np.ndarray, harmonics: int = 64) -> np.ndarray:
    """Amplitudes A_1 … A_harmonics of a displacement sampled at n uniform angles over one cycle (the end
    point left out): 2|c_k| from numpy's FFT, independent of camcad's analysis. Aliasing adds the harmonics
    n − k, n + k, …; a law whose acceleration is at least piecewise continuous has |A_k| ∝ k⁻³ or faster."""
    c = np.fft.rfft(s) / len(s)
    return 2.0 * np.abs(c[1:harmonics + 1])


def _sampled_s(law, n: int = 1 << 15) -> np.ndarray:
    return law.kinematics(TWO_PI * np.arange(n) / n).s


@pytest.mark.reference("second method", "numpy's FFT of the filtered law's sampled displacement (2^15 points), not "
                                        "camcad's analysis")
@pytest.mark.parametrize("base", ["composite", "drawn"])
def test_filtering_removes_exactly_the_band(drdr, base):
    # the filtered law's displacement, sampled and transformed by numpy's FFT (not camcad's analysis, which
    # reads a filtered law's coefficients back from the correction it was built with): each removed harmonic
    # keeps less than 1e-6 of its amplitude (a law that kept 0.1 % of the band fails by a factor 1000), the
    # others are unchanged
    law = drdr if base == "composite" else parabolic_drdr()
    band = fourier.resonant_harmonics(100.0, (300, 400), 0.0, 1)       # removes 14…21
    result = fourier.filter_law(law, band, keep_dwells=False)
    before = fft_amplitudes(_sampled_s(law))
    after = fft_amplitudes(_sampled_s(result.law))
    removed = np.array(band.removed) - 1
    kept = np.setdiff1d(np.arange(64), removed)
    assert band.removed == tuple(range(14, 22))
    assert np.max(after[removed]) <= 1e-12 * LIFT
    present = removed[before[removed] > 1e-9 * LIFT]       # the composite law's 18th is zero (18 x 100° = 5 x 360°)
    assert len(present) >= 7 and np.max(after[present] / before[present]) <= 1e-6
    assert np.max(np.abs(after[kept] - before[kept])) <= 1e-12 * LIFT
    # the edges: 14 and 21 gone, 13 and 22 untouched (and nonzero, so the test could fail)
    assert after[13] <= 1e-12 * LIFT and after[20] <= 1e-12 * LIFT
    assert after[12] == pytest.approx(before[12], rel=1e-9) and before[12] > 1e-6 * LIFT
    assert after[21] == pytest.approx(before[21], rel=1e-9) and before[21] > 1e-6 * LIFT


@pytest.mark.reference("second method", "numpy's FFT of filtered.csv's displacement against camcad's band_left_mm; "
                                        "the band's size in closed form")
def test_the_written_filtered_law_has_no_band_left(tmp_path, capsys):
    # the law camcad writes (spectrum --filter: filtered.csv, s every 0.1° to 12 digits), read back and transformed
    # by numpy's FFT: (1) what is left of each removed harmonic equals what camcad reports (band_left_mm, from its
    # exact analysis of the written polyline); (2) it is under 3e-4 of the original's band (closed form): closing
    # the polyline from rest (export_polyline: a constant and one low harmonic added to a) puts back about 1e-4 of
    # each removed harmonic; a filter that kept 0.1 % of the band would leave 1e-3
    out = tmp_path / "out"
    code, stdout, _ = _run(["spectrum", "--standard", "cycloidal", "--phases",
                            "0:70:dwell,70:170:rise,170:280:dwell,280:360:return", "--lift", "25", "--fn", "100",
                            "--rpm", "300:400", "--band", "0", "--filter", "--no-plots", "-o", str(out), "--json"],
                           capsys)
    assert code == 0
    reported = json.loads(stdout)["spectrum"]["band_left_mm"]
    table = np.loadtxt(out / "filtered.csv", delimiter=",", comments="#", skiprows=2)
    theta, s = table[:, 0], table[:, 1]
    assert len(theta) == 3601 and np.allclose(np.diff(theta), 0.1, atol=1e-9)
    left = fft_amplitudes(s[:-1])
    k = np.arange(14, 22)
    assert sorted(int(key) for key in reported) == list(k)
    assert left[k - 1] == pytest.approx([reported[str(h)] for h in k], rel=1e-3, abs=1e-12 * LIFT)
    original = 2 * np.abs(cycloidal_drdr_coefficients(k)[0])
    assert np.sum(original) > 5e-4 * LIFT            # 16 µm over the band: a figure the test can miss
    assert np.sum(left[k - 1]) <= 3e-4 * np.sum(original)


@pytest.mark.reference("second method", "the removed terms on the dwells summed here from the original's amplitudes "
                                        "and phases")
def test_filtered_law_closes_and_dwell_deviation_is_bounded(drdr):
    band = fourier.resonant_harmonics(100.0, (300, 400), 0.0, 1)
    result = fourier.filter_law(drdr, band, keep_dwells=False)
    ends = result.law.kinematics(np.array([0.0, TWO_PI]))
    assert abs(ends.s[1] - ends.s[0]) <= 1e-12 * LIFT and abs(ends.v[1] - ends.v[0]) <= 1e-12 * LIFT
    # the dwell deviation is the removed terms on the dwells, measured from θ = 0 (where a written law is
    # read back from s = 0), recomputed here from the original's amplitudes and phases on a dense grid, and
    # bounded by twice the sum of the removed amplitudes
    spectrum = fourier.analyse(drdr, 64)
    k = np.array(band.removed)
    dwells = np.concatenate([np.linspace(p.start, p.end, 20001) for p in drdr.phases if p.kind == "dwell"])
    removed_terms = np.sin(np.outer(dwells, k) + spectrum.phases[k - 1]) @ spectrum.amplitudes[k - 1]
    at_zero = np.sin(spectrum.phases[k - 1]) @ spectrum.amplitudes[k - 1]
    assert result.dwell_deviation == pytest.approx(np.max(np.abs(removed_terms - at_zero)), rel=1e-4)
    assert np.sum(spectrum.amplitudes[k - 1]) == pytest.approx(result.removal_bound)
    assert result.dwell_deviation <= 2 * result.removal_bound
    report = result.report()
    for key in ("removed", "max_deviation_mm", "dwell_deviation_mm", "peak_accel_ratio"):
        assert key in report
    assert report["removed"] == list(range(14, 22))


@pytest.mark.reference("second method", "max |a| sampled every 0.005 deg, and over the first 7 deg of each motion")
def test_peak_and_start_accelerations_reported(drdr):
    band = fourier.resonant_harmonics(100.0, (300, 400), 0.0, 1)
    result = fourier.filter_law(drdr, band, keep_dwells=False, start_window_deg=7.0)
    theta = np.linspace(0, TWO_PI, 72001)   # 0.005° apart; |a'| ≤ 4π²h/β³ bounds the sampling error
    a0 = drdr.kinematics(theta).a
    a1 = result.law.kinematics(theta).a
    assert result.peak_accel_ratio == pytest.approx(np.max(np.abs(a1)) / np.max(np.abs(a0)), rel=1e-5)
    # start of motion: max |a| over the first 7° of the rise (70°) and of the return (280°)
    windows = [np.radians(np.linspace(s, s + 7.0, 7001)) for s in (70.0, 280.0)]
    expected = max(np.max(np.abs(result.law.kinematics(w).a)) for w in windows)
    assert result.start_accel_filtered == pytest.approx(expected, rel=1e-6)


@pytest.mark.reference("second method", "the dwell deviation sampled here; the band by numpy's FFT of the displacement")
def test_keeping_the_dwells_by_compensation(drdr):
    band = fourier.resonant_harmonics(100.0, (300, 400), 0.0, 1)
    tol = 2e-4
    plain = fourier.filter_law(drdr, band, keep_dwells=False)
    assert plain.dwell_deviation > tol          # so the compensation has work to do
    kept = fourier.filter_law(drdr, band, dwell_tol=tol)
    assert kept.dwells_kept and kept.compensation is not None
    dwells = np.concatenate([np.linspace(p.start, p.end, 20001) for p in drdr.phases if p.kind == "dwell"])
    deviation = np.max(np.abs(kept.law.kinematics(dwells).s - drdr.kinematics(dwells).s))
    assert deviation <= tol * 1.001              # sampled on the filter's grid; the trig polynomial is smooth
    after = fft_amplitudes(_sampled_s(kept.law))           # numpy's FFT of the displacement, not camcad's analysis
    assert np.max(after[np.array(band.removed) - 1]) <= 1e-12 * LIFT
    assert abs(kept.lift_filtered - kept.lift_original) <= 2 * tol


@pytest.mark.reference("property", "removing harmonics 1-4 leaves no compensation that keeps the dwells to 1e-6 mm: "
                                   "said, with its cost")
def test_dwells_that_cannot_be_kept_are_reported(drdr):
    # removing k = 1…3 takes away most of the law; no compensation outside the band restores the dwells
    # to a nanometre, so the result says so and what it cost
    band = fourier.resonant_harmonics(5.0, (100, 150), 0.0, 1)     # k ∈ [2, 3] → removed 1…4
    result = fourier.filter_law(drdr, band, dwell_tol=1e-6)
    assert not result.dwells_kept
    assert any("cannot be kept" in note for note in result.notes)
    assert "peak_accel_ratio_without" in result.report()["compensation"]


@pytest.mark.reference("closed form", "chord error of the written polyline at the law's kinks: band amplitude <= 2 "
                                      "h^2/12 x kinks/(2 pi k^2)")
def test_written_law_rereads_and_closes(drdr, tmp_path):
    from camcad.io.law_write import write_law_dxf
    from camcad.law.source import load_law

    band = fourier.resonant_harmonics(100.0, (300, 400), 0.0, 1)
    result = fourier.filter_law(drdr, band, keep_dwells=False)
    exported = fourier.export_polyline(result.law, removed=band.removed)
    assert exported.closed
    # The band stays removed in the written polyline up to its chord error. A polyline through a(θ_i)
    # misses a by e ≈ a''·t(h − t)/2 in each cell (mean h²a''/12). Where a is smooth that has no band
    # content (the filtered a''_k = −k² a_k = 0 there), but at the law's kinks (a' jumps by ±h·4π²/β³ at
    # both ends of each cycloidal motion) the delta part of a'' is missing from e, so
    #     |e_k| ≤ (h²/12) Σ|Δa'|/T,   and in s:  ΔA_k ≤ 2 (h²/12) Σ|Δa'| / (T k²),
    # which falls as h².
    step = np.radians(0.1)
    kinks = 2 * LIFT * 4 * np.pi**2 * (1 / np.radians(100.0) ** 3 + 1 / np.radians(80.0) ** 3)
    for k, amplitude in exported.band_amplitudes.items():
        assert amplitude <= 1.2 * 2 * step**2 / 12 * kinks / (TWO_PI * k**2), k
    original = fourier.analyse(drdr, 21).amplitudes
    present = [k for k in band.removed if original[k - 1] > 1e-9]   # k = 18 is 0 in this law
    assert max(exported.band_amplitudes[k] / original[k - 1] for k in present) < 1e-3
    finer = fourier.export_polyline(result.law, step_deg=0.05, removed=band.removed)
    ratio = np.array([exported.band_amplitudes[k] / finer.band_amplitudes[k] for k in present])
    assert np.all((ratio > 3.5) & (ratio < 4.5))
    # the closing change touches only the constant and harmonic 1, so nothing else of the spectrum moves
    assert exported.max_change <= 0.05
    # starting from rest cancels v(0) of the filtered law with c·sin(mθ)-like terms: the s drift is about
    # |v(0)|/m, so asking for a quarter of it picks m = 4 and the written law follows the filtered one
    v0 = abs(result.law.kinematics(np.zeros(1)).v[0])
    assert exported.max_deviation == pytest.approx(v0, rel=0.05) and v0 > 1e-4
    closer = fourier.export_polyline(result.law, removed=band.removed, drift_tol=v0 / 4)
    assert closer.max_deviation <= 1.05 * v0 / 4 and closer.closed
    assert "harmonic 4" in closer.notes[0]
    path = write_law_dxf(tmp_path / "filtered.dxf", np.degrees(exported.law.x), exported.law.a)
    loaded = load_law(path)
    assert np.allclose(loaded.law.a, exported.law.a, rtol=1e-12, atol=1e-12 * LIFT)
    report = balance.check(loaded.law)
    assert report.balanced, report.to_dict()["conditions"]
    assert abs(report.displacement_closure) <= 1e-9 * LIFT


# ---------------------------------------------------------------------------------------------
# Lead-in segments
# ---------------------------------------------------------------------------------------------

@pytest.mark.reference("closed form", "plateau of 0.1 x peak over 14 deg: the follower leaves it with v = 0.1 peak x "
                                      "14 deg (rad)")
def test_lead_in_segments_are_placed_and_the_law_still_closes(drdr):
    result = fourier.add_lead_in(drdr, 14.0, 0.1)
    law = result.law
    peak = 2 * np.pi * LIFT / np.radians(80.0) ** 2     # cycloidal Ca = 2π on the faster motion (the return)
    # before balancing: a plateau of 0.1 × peak from 56° to 70° (rise) and of −0.1 × peak from 266° to
    # 280° (return); the follower leaves the plateau with v = 0.1·peak·14° (rad), exactly
    raw = result.unbalanced
    inside = np.radians(np.linspace(56.5, 69.5, 27))
    assert np.allclose(raw.kinematics(inside).a, 0.1 * result.peak_accel, rtol=1e-12)
    assert result.peak_accel == pytest.approx(peak, rel=1e-9)
    v_end = raw.kinematics(np.radians([70.0])).v[0]
    assert v_end == pytest.approx(0.1 * peak * np.radians(14.0), rel=1e-9)
    # after balancing and scaling back to the lift: plateau held (scaled), dwell untouched, closed
    assert np.allclose(law.kinematics(inside).a, result.segments[0][2], rtol=1e-12)
    assert result.segments[0][2] == pytest.approx(0.1 * peak * result.scale, rel=1e-12)
    assert np.all(law.kinematics(np.radians(np.linspace(0, 55.9, 50))).a == 0)
    check = balance.check(law)
    assert check.balanced and result.balanced
    assert np.ptp(law.kinematics(np.linspace(0, TWO_PI, 100001)).s) == pytest.approx(LIFT, rel=1e-6)
    phases = [(p.kind, round(np.degrees(p.start), 9)) for p in law.phases]
    assert ("rise", 56.0) in phases and ("return", 266.0) in phases


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_lead_in_longer_than_the_dwell_is_refused(drdr):
    with pytest.raises(CamcadError, match="not longer than the lead-in"):
        fourier.add_lead_in(drdr, 75.0, 0.1)
    with pytest.raises(CamcadError):
        fourier.add_lead_in(drdr, 14.0, 1.5)


@pytest.mark.reference("closed form", "the start jump becomes A_rise - 0.1 A_peak with the plateau at 0.1 of the peak")
def test_lead_in_on_a_law_with_a_start_jump():
    # the parabolic law jumps from 0 to A_rise at the start of the rise: the lead-in plateau is 0.1 of the
    # peak |a| (the return's A), so the jump at the old start becomes A_rise − 0.1·A_peak
    law = parabolic_drdr()
    result = fourier.add_lead_in(law, 14.0, 0.1, keep_lift=False)
    accel = LIFT / (np.radians(80.0) / 2) ** 2    # the return's, the larger: the peak
    rise_accel = LIFT / (np.radians(100.0) / 2) ** 2
    assert result.start_jump_original[0] == pytest.approx(rise_accel, rel=1e-12)
    assert result.start_jump_new[0] == pytest.approx(rise_accel - 0.1 * accel, rel=1e-12)
    assert result.segments[0][2] == pytest.approx(0.1 * accel, rel=1e-12)
    assert result.segments[1][2] == pytest.approx(-0.1 * accel, rel=1e-12)
    assert result.balanced


# ---------------------------------------------------------------------------------------------
# Scene section and command line
# ---------------------------------------------------------------------------------------------

@pytest.mark.reference("property", "the [filter] section parsed as written; unknown and bad keys refused with the "
                                   "reason")
def test_parse_filter_section():
    settings_ = scene_filter.parse_filter({"fn_hz": 160.0, "rpm": "330:420", "band": 0.1, "neighbours": 2,
                                      "lead_in_deg": 14.0}, "scene.toml [filter]")
    assert settings_.rpm == (330.0, 420.0) and settings_.neighbours == 2 and settings_.lead_in_fraction == 0.1
    assert scene_filter.parse_filter({"rpm": [300, 400]}).rpm == (300.0, 400.0)
    with pytest.raises(CamcadError, match="did you mean 'neighbours'"):
        scene_filter.parse_filter({"fn_hz": 160.0, "neighbors": 2}, "scene.toml [filter]")
    with pytest.raises(CamcadError, match="must be positive"):
        scene_filter.parse_filter({"fn_hz": -1.0})
    with pytest.raises(CamcadError):
        scene_filter.parse_filter({"rpm": "fast"})
    with pytest.raises(CamcadError):
        fourier.resonant_harmonics(160.0, (0, 330))
    # a range given high to low is the same range
    assert fourier.speed_range((420, 330)) == (330.0, 420.0)
    with pytest.raises(CamcadError):
        fourier.resonant_harmonics(160.0, (330, 420), band=1.5)


@pytest.mark.reference("property", "the pipeline's filter removes 14-21 and writes a closed law; nothing to do is "
                                   "refused")
def test_apply_filter_pipeline_step(drdr):
    settings_ = scene_filter.FilterSettings(fn_hz=100.0, rpm=(300.0, 400.0), band=0.0, keep_dwells=False)
    outcome = scene_filtering.apply_filter(drdr, settings_)
    assert outcome.exported is not None and outcome.exported.closed
    assert set(outcome.report()["removed"]) == set(range(14, 22))
    with pytest.raises(CamcadError, match="nothing to do"):
        scene_filtering.apply_filter(drdr, scene_filter.FilterSettings())


def _run(argv, capsys):
    from camcad.cli import app, register_all
    from camcad.cli.common import run_app

    register_all()
    code = run_app(app, argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


@pytest.mark.reference("closed form", "the JSON amplitudes against cycloidal_drdr_coefficients; the written DXF "
                                      "checks balanced")
def test_cli_spectrum_json_and_filter(tmp_path, capsys):
    out = tmp_path / "out"
    code, stdout, _ = _run(["spectrum", "--standard", "cycloidal", "--phases",
                            "0:70:dwell,70:170:rise,170:280:dwell,280:360:return", "--lift", "25",
                            "--fn", "100", "--rpm", "300:400", "--band", "0", "--filter", "--no-keep-dwells",
                            "--dwell-tol", "0.05", "-N", "32", "--tol", "1e-3", "--no-plots", "-o", str(out),
                            "--json"], capsys)
    assert code == 0
    payload = json.loads(stdout)
    spectrum = payload["spectrum"]
    expected, _ = cycloidal_drdr_coefficients(np.arange(1, 33))
    amplitudes = np.array([row["amplitude"] for row in spectrum["harmonics"][:32]])
    assert np.allclose(amplitudes[[k - 1 for k in range(1, 33) if k % 9]],
                       2 * np.abs(expected)[[k - 1 for k in range(1, 33) if k % 9]], atol=1e-9 * LIFT)
    assert spectrum["removed"] == list(range(14, 22)) and spectrum["least_harmonics"] == 21
    for key in ("mean", "rms_error", "max_deviation_mm", "dwell_deviation_mm", "peak_accel_ratio"):
        assert key in spectrum
    assert (out / "filtered.dxf").exists() and (out / "filtered.csv").exists()
    code, stdout, _ = _run(["check", str(out / "filtered.dxf"), "--json"], capsys)
    assert code == 0 and json.loads(stdout)["balanced"]


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_cli_bad_input_is_one_line(capsys, tmp_path):
    code, stdout, stderr = _run(["spectrum", "--standard", "cycloidal", "-o", str(tmp_path), "--json"], capsys)
    assert code == 2 and stdout == "" and stderr.count("\n") == 1 and stderr.startswith("camcad: error:")
    code, _, stderr = _run(["spectrum", "--standard", "cycloidal", "--lift", "25", "--phases",
                            "0:180:rise,180:360:return", "--filter", "-o", str(tmp_path)], capsys)
    assert code == 2 and "--fn" in stderr


@pytest.mark.reference("property", "a dwell tolerance that cannot be met: the check fails, exit 1")
def test_cli_exit_1_when_dwells_cannot_be_kept(capsys, tmp_path):
    code, stdout, _ = _run(["spectrum", "--standard", "cycloidal", "--lift", "25", "--phases",
                            "0:70:dwell,70:170:rise,170:280:dwell,280:360:return", "--fn", "5", "--rpm", "100:150",
                            "--band", "0", "--filter", "--dwell-tol", "1e-6", "--no-plots", "-o", str(tmp_path),
                            "--json"], capsys)
    spectrum = json.loads(stdout)["spectrum"]
    assert code == 1 and spectrum["filter"]["dwells_kept"] is False
    assert spectrum["checks"]["dwell deviation"]["passed"] is False and spectrum["passed"] is False


def _direct_sum(mean, coefficients, cycle, theta, order):
    """mean + 2 Re Σ c_k (ikω0)^order e^{ikω0θ}, term by term with numpy's exp (an independent reference)."""
    k = np.flatnonzero(coefficients) + 1
    w = k * (2.0 * np.pi / cycle)
    terms = (coefficients[k - 1] * (1j * w) ** order)[None, :] * np.exp(1j * np.outer(theta, w))
    return (mean if order == 0 else 0.0) + 2.0 * np.real(terms.sum(axis=1))


@pytest.mark.reference("second method", "the direct sum of the sparse terms, against Horner and the inverse FFT")
def test_sparse_high_harmonics_by_horner_and_on_the_grid_by_fft_match_a_direct_sum():
    # A filter's removal at a slow speed: 60 harmonics around k = 2300 in a vector of 2400 (the fuzz campaign's
    # case 21419, `spectrum --filter` at 3 rpm, evaluated 229 such terms at 524,296 points in 92 s). Horner's
    # scheme over the non-zero terms and the inverse FFT on the uniform grid must both equal the direct sum.
    rng = np.random.default_rng(21419)
    coefficients = np.zeros(2400, dtype=complex)
    band = np.arange(2270, 2330)
    coefficients[band - 1] = (rng.normal(size=60) + 1j * rng.normal(size=60)) * 1e-6
    coefficients[[0, 4, 9]] = [0.3 - 0.1j, 0.02j, -0.004]            # and a few low ones far below it
    cycle = 2.0 * np.pi
    law = compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    samples = 1 << 13
    grid = fourier.filter.evaluation_grid(law, samples)
    assert len(grid) > samples + 1                                   # the knots are there, off the grid
    series = fourier.FourierLaw(cycle, 0.7, coefficients)
    orders = (0, 1, 2, 3)
    on_grid = fourier.filter.series_on_evaluation_grid(series, grid, samples, orders)
    by_horner = fourier.series.evaluate_series_orders(0.7, coefficients, cycle, grid, orders)
    # every method rounds the phase kω0θ (up to 2330·2π ≈ 1.5e4 rad) to eps·1.5e4 ≈ 3e-12 relative per term:
    # with 63 terms the three agree to 1e-11 of the largest value, not to eps
    for order, fft_values, horner_values in zip(orders, on_grid, by_horner):
        reference = _direct_sum(0.7, coefficients, cycle, grid, order)
        scale = np.max(np.abs(reference))
        assert np.max(np.abs(fft_values - reference)) <= 1e-11 * scale, order
        assert np.max(np.abs(horner_values - reference)) <= 1e-11 * scale, order


@pytest.mark.reference("second method", "numpy's FFT of the displacement: the band removed without a compensation, "
                                        "the notes say why")
def test_a_compensation_past_its_bound_is_left_out_and_said():
    # 100 Hz at 25-25.5 rpm: the band at harmonics 223-253, a compensation up to harmonic 514 (measured 11.5 s
    # and 577 MB; at 3 rpm, 4,756 harmonics ran out of memory). Past MAX_COMPENSATION_HARMONICS the removal
    # stands alone, the notes say why, and the dwell check reports the deviation against the tolerance.
    law = compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    band = fourier.resonant_harmonics(100.0, (25.0, 25.5))
    assert 2 * max(band.gains) + 8 > fourier.filter.MAX_COMPENSATION_HARMONICS
    result = fourier.filter_law(law, band, harmonics=32, dwell_tol=1e-9)
    assert result.compensation is None
    assert any("not compensated" in note and "at most 400" in note for note in result.notes)
    # the removal alone: the band is gone from the filtered law's displacement (numpy's FFT of 2^15 samples)
    after = fft_amplitudes(_sampled_s(result.law), max(band.gains) + 2)
    assert max(float(after[k - 1]) for k in band.removed) < 1e-12
    # and the dwells are reported as not kept: the band's terms move them by about 1e-6 mm, far past 1e-9 mm
    assert result.dwell_deviation > 1e-7 and not result.dwells_kept


@pytest.mark.reference("property", "a swing in rad: the filter's notes say rad, never mm")
def test_the_filter_notes_speak_the_law_s_unit(capsys, tmp_path):
    # the batten's law is a swing in rad: its filter notes say rad, not mm (they said mm before this stop)
    scene = Path(__file__).resolve().parents[2] / "samples" / "scenes" / "batten.toml"
    code, stdout, _ = _run(["spectrum", str(scene), "-N", "20", "--filter", "--no-plots", "-o", str(tmp_path),
                            "--json"], capsys)
    notes = json.loads(stdout)["spectrum"]["filter"]["notes"]
    assert code in (0, 1) and any("dwell tolerance not given" in note for note in notes), notes
    assert all(" mm" not in note for note in notes) and any(note.endswith(" rad") for note in notes), notes
