"""Resonance filtering: remove the band's harmonics from a law, keep its dwells and closure.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, cast

import numpy as np

from camcad.arrays import unique
from camcad.fourier.analysis import analyse
from camcad.fourier.resonance import ResonanceBand
from camcad.fourier.series import (
    CorrectedLaw,
    FourierLaw,
    Spectrum,
    evaluate_series,
    evaluate_series_orders,
    series_on_grid,
)
from camcad.law.law import MotionLaw, Phase, PiecewiseLinearLaw

#: the highest harmonic the dwell compensation may use: its least-squares fit is an SVD of (16 per period of
#: it) x (2 per harmonic) values, measured (3-4-5 law, dwell tolerance 1e-9 mm) at 2.7 s of CPU and 201 MB
#: for 262 harmonics, 11.5 s and 577 MB for 514, 58 s and 2.2 GB for 1,060; beyond this the removal is left
#: uncompensated and the report says so (its dwell check shows the deviation with its margin)
MAX_COMPENSATION_HARMONICS = 400


def motion_starts(phases: tuple[Phase, ...]) -> list[float]:
    """θ (rad) where a rise or return begins after a dwell.

    Parameters
    ----------
    phases : tuple of Phase
        The law's phases (rad).

    Returns
    -------
    list of float
        The starts, rad.

    Examples
    --------
    >>> import numpy as np
    >>> import camcad
    >>> law = camcad.compose([("dwell", 70), ("rise", 100), ("dwell", 110), ("return", 80)], 25.0)
    >>> from camcad.fourier import motion_starts
    >>> [round(float(np.degrees(t)), 9) for t in motion_starts(law.phases)]
    [70.0, 280.0]
    """
    starts = []
    for index, phase in enumerate(phases):
        if phase.kind != "dwell" and phases[index - 1].kind == "dwell":
            starts.append(phase.start)
    return starts


def dwell_grid(phases: tuple[Phase, ...], spacing: float) -> np.ndarray:
    """Points (rad) on every dwell, ends included, at most ``spacing`` apart.

    Parameters
    ----------
    phases : tuple of Phase
        The law's phases (rad).
    spacing : float
        The largest spacing, rad.

    Returns
    -------
    ndarray
        The points, rad.

    Examples
    --------
    >>> import numpy as np
    >>> import camcad
    >>> law = camcad.compose([("dwell", 70), ("rise", 100), ("dwell", 110), ("return", 80)], 25.0)
    >>> from camcad.fourier import dwell_grid
    >>> grid = dwell_grid(law.phases, np.radians(10.0))
    >>> round(float(np.degrees(grid.min())), 9), round(float(np.degrees(grid.max())), 9), len(grid)
    (0.0, 280.0, 20)
    """
    parts = [np.linspace(p.start, p.end, math.ceil(p.width / spacing) + 1)
             for p in phases if p.kind == "dwell"]
    return np.concatenate(parts) if parts else np.zeros(0)


def knots_of(law) -> np.ndarray:
    """Angles (rad) where the law's acceleration may jump or kink: knots, phase ends."""
    points = [p.start for p in law.phases] + [p.end for p in law.phases]
    if isinstance(law, PiecewiseLinearLaw):
        points += list(law.x)
    if isinstance(law, CorrectedLaw):
        points += list(knots_of(law.base))
    return unique(np.asarray(points, dtype=float)) if points else np.zeros(0)


def jumps_and_phase_ends(law) -> np.ndarray:
    """Angles (rad) where a drawn base law's acceleration jumps, and the ends of its phases."""
    points = [p.start for p in law.phases] + [p.end for p in law.phases]
    base = law
    while isinstance(base, CorrectedLaw):
        base = base.base
    if isinstance(base, PiecewiseLinearLaw):
        points += list(base.x[:-1][np.diff(base.x) == 0])
    return unique(np.asarray(points, dtype=float)) if points else np.zeros(0)


def evaluation_grid(law, samples: int) -> np.ndarray:
    """A uniform grid plus the knots approached from both sides, so jumps and extremes at knots are seen."""
    grid = np.arange(samples + 1) * (law.cycle / samples)
    knots = knots_of(law)
    knots = knots[(knots >= 0) & (knots <= law.cycle)]
    left = np.nextafter(knots, -np.inf)
    return unique(np.concatenate((grid, knots, left[left >= 0])))


def series_on_evaluation_grid(series: FourierLaw, grid: np.ndarray, samples: int,
                              orders: tuple[int, ...]) -> list[np.ndarray]:
    """Derivatives of ``series`` at the points of ``evaluation_grid(law, samples)``: the uniform points
    θ_j = j T/M by one inverse FFT per order (O(M log M) however many harmonics), the knots beside them
    by Horner's scheme (``evaluate_series_orders``). Units of s per rad^order."""
    step = series.cycle / samples
    index = np.rint(grid / step)
    uniform = (index * step == grid) & (index >= 0) & (index <= samples)
    if 2 * series.harmonics >= samples or not uniform.any():
        return evaluate_series_orders(series.mean, series.coefficients, series.cycle, grid, orders)
    j = index[uniform].astype(int) % samples                      # θ = T is θ = 0 of the periodic series
    others = evaluate_series_orders(series.mean, series.coefficients, series.cycle, grid[~uniform], orders)
    values = []
    for order, off_grid in zip(orders, others):
        out = np.empty(len(grid))
        out[uniform] = series_on_grid(series.mean, series.coefficients, samples, order, series.cycle)[j]
        out[~uniform] = off_grid
        values.append(out)
    return values


def start_accelerations(law, window: float, samples: int = 512) -> list[float]:
    """max |a| (mm/rad²) over [θs, θs + window] after each motion start θs.

    Parameters
    ----------
    law : MotionLaw
        The law (θ in rad, a in mm/rad²).
    window : float
        The window, rad.
    samples : int
        Points per window.

    Returns
    -------
    list of float
        One maximum per motion start, mm/rad².

    Examples
    --------
    The cycloid's a = (2πh/β²) sin(2πu) reaches its peak a quarter into the rise:

    >>> import math
    >>> import camcad
    >>> from camcad.fourier import start_accelerations
    >>> law = camcad.compose([("dwell", 90), ("rise", 90), ("dwell", 90), ("return", 90)], 20.0)
    >>> peak = 2 * math.pi * 20.0 / math.radians(90.0) ** 2
    >>> [round(a / peak, 9) for a in start_accelerations(law, math.radians(22.5))]
    [1.0, 1.0]
    """
    values = []
    for start in motion_starts(tuple(law.phases)):
        theta = start + np.linspace(0.0, window, samples + 1)
        values.append(float(np.max(np.abs(law.kinematics(theta).a))))
    return values


@dataclass(frozen=True)
class FilterResult:
    """A filtered law and the figures the batten study and docs/INTERFACE.md ask for (mm, mm/rad², rad).

    ``camcad.filter_law`` returns it; the example is there.

    Attributes
    ----------
    law : CorrectedLaw
        The filtered law (rad, mm).
    original : MotionLaw
        The law filtered.
    band : ResonanceBand
        The harmonics removed and their gains.
    spectrum : Spectrum
        The original's spectrum (mm).
    removal : FourierLaw
        What was taken out (mm).
    compensation : FourierLaw, optional
        What was added back to keep the dwells (mm), or None.
    max_deviation : float
        The largest |s_filtered − s_original|, mm.
    dwell_deviation : float, optional
        The largest deviation on the dwells, mm.
    removal_bound : float
        Σ (1 − g_k) A_k, mm: what the removal can move s at most.
    lift_original, lift_filtered : float
        The lifts, mm.
    peak_accel_original, peak_accel_filtered, peak_accel_removed_only : float
        The peak |a|, mm/rad² (the last without the compensation).
    start_accel_original, start_accel_filtered : float, optional
        The largest |a| over the window after each motion start, mm/rad².
    start_window : float
        That window, rad.
    dwell_tol : float
        The dwell tolerance, mm.
    dwells_kept : bool
        Whether the dwells stay within it.
    lambda_used : float, optional
        The compensation's regularisation (dimensionless), or None.
    notes : tuple of str
        What was done, in words.
    """

    law: CorrectedLaw
    original: Any
    band: ResonanceBand
    spectrum: Spectrum
    removal: FourierLaw
    compensation: FourierLaw | None
    max_deviation: float
    dwell_deviation: float | None
    removal_bound: float
    lift_original: float
    lift_filtered: float
    peak_accel_original: float
    peak_accel_filtered: float
    peak_accel_removed_only: float
    start_accel_original: float | None
    start_accel_filtered: float | None
    start_window: float
    dwell_tol: float
    dwells_kept: bool
    lambda_used: float | None
    notes: tuple[str, ...]

    @property
    def peak_accel_ratio(self) -> float:
        return self.peak_accel_filtered / self.peak_accel_original

    @property
    def start_accel_ratio(self) -> float | None:
        if self.start_accel_original is None or self.start_accel_original == 0:
            return None
        return cast(float, self.start_accel_filtered) / self.start_accel_original

    def report(self) -> dict:
        """docs/INTERFACE.md ``spectrum`` filter keys and the further figures."""
        band = self.band
        ratio = self.start_accel_ratio
        comp = None
        if self.compensation is not None:
            amplitudes = self.compensation.coefficients
            used = np.flatnonzero(np.abs(amplitudes) > 0) + 1
            comp = {"harmonics": [int(k) for k in used],
                    "max_amplitude_mm": float(2 * np.max(np.abs(amplitudes))) if len(amplitudes) else 0.0,
                    "mean_shift_mm": float(self.compensation.mean),
                    "regularisation": self.lambda_used,
                    "peak_accel_ratio_without": self.peak_accel_removed_only / self.peak_accel_original}
        return {
            "removed": list(band.removed),
            "attenuated": {str(k): g for k, g in band.gains.items() if g > 0},
            "resonant": list(band.core),
            "k_band": [band.k_low, band.k_high],
            "fn_hz": band.fn_hz, "rpm": list(band.rpm), "band": band.band, "neighbours": band.neighbours,
            "taper": band.taper,
            "max_deviation_mm": self.max_deviation,
            "dwell_deviation_mm": self.dwell_deviation,
            "removed_amplitude_sum_mm": self.removal_bound,
            "dwell_tol_mm": self.dwell_tol,
            "dwells_kept": self.dwells_kept,
            "lift_mm": self.lift_original,
            "lift_change_mm": self.lift_filtered - self.lift_original,
            "peak_accel_ratio": self.peak_accel_ratio,
            "peak_accel_mm_per_rad2": {"original": self.peak_accel_original, "filtered": self.peak_accel_filtered},
            "start_accel": {"window_deg": float(np.degrees(self.start_window)),
                            "original_mm_per_rad2": self.start_accel_original,
                            "filtered_mm_per_rad2": self.start_accel_filtered,
                            "ratio": ratio,
                            "change_percent": None if ratio is None else 100.0 * (ratio - 1.0)},
            "compensation": comp,
            "notes": list(self.notes),
        }


def filter_law(law: MotionLaw, band: ResonanceBand, *, harmonics: int = 64, keep_dwells: bool = True,
               dwell_tol: float | None = None, start_window_deg: float = 7.0,
               compensation_harmonics: int | None = None, samples: int | None = None,
               spectrum: Spectrum | None = None, unit: str = "mm") -> FilterResult:
    """Remove (or taper) the resonant harmonics of a law, keeping its dwells and lift within ``dwell_tol``.

    The filtered law is law − Σ_{k} (1 − g_k)·(term k) (``CorrectedLaw``): exact, every other harmonic
    kept. On the dwells it deviates by the removed terms, at most Σ (1 − g_k) A_k. When that exceeds
    ``dwell_tol`` (mm, default 1e-3 × lift) and ``keep_dwells`` is set, a compensation δ made only of
    harmonics outside the removed set (k ≤ ``compensation_harmonics``, default 2·max removed + 8, and a
    constant) is added: the least-squares fit of −(removed terms) on the dwells and at the extremes of s,
    regularised by λ·mean(δ² + δ''²/(k_b ω0)⁴) — the displacement and acceleration it costs (k_b the
    lowest touched harmonic). λ is the largest that meets the tolerance;
    if none does, the smallest deviation reached is reported with its cost. The resonant harmonics
    stay exactly zero either way.

    Parameters
    ----------
    law : MotionLaw
        The law over one cycle: θ in rad, s in mm (or rad of swing), a in mm/rad².
    band : ResonanceBand
        The harmonics to remove and their gains (``resonant_harmonics``).
    harmonics : int
        Harmonics analysed (a count; at least the highest one touched is used).
    keep_dwells : bool
        Compensate so that the dwells and the lift stay within ``dwell_tol``.
    dwell_tol : float, optional
        Largest deviation allowed on the dwells and at the extremes of s, mm; default 1e-3 × lift.
    start_window_deg : float
        Window after each motion start over which max |a| is the start-of-motion load, deg (the source
        saw it over about the first 7°).
    compensation_harmonics : int, optional
        Highest harmonic the compensation may use (a count); default 2·(highest removed) + 8; above
        ``MAX_COMPENSATION_HARMONICS`` the dwells are left uncompensated and ``notes`` says so.
    samples : int, optional
        Uniform grid for the maxima (a count); default ≥ 64 points per period of the highest harmonic,
        at least 2^14.
    spectrum : Spectrum, optional
        The law's spectrum when already computed (``analyse``); computed when None.
    unit : str
        The law's unit of s, written in the notes ("mm", or "rad" for a swing).

    Returns
    -------
    FilterResult
        ``law`` the filtered law (mm, mm/rad²), ``max_deviation`` and ``dwell_deviation`` (mm),
        ``removal_bound`` Σ(1 − g_k)A_k (mm), ``lift_original``/``lift_filtered`` (mm),
        ``peak_accel_original``/``peak_accel_filtered`` (mm/rad²) and their ratio (dimensionless),
        ``start_accel_original``/``start_accel_filtered`` (mm/rad²), ``notes``; ``report()`` gives the
        docs/INTERFACE.md ``spectrum`` filter keys.

    References
    ----------
    Resonance filtering (the resonating 17th harmonic and its neighbours removed cut the acceleration
    at the start of motion by about 61 %): PhD abstract on the batten mechanism of the STB loom,
    Novosibirsk (the batten study; ``docs/analyses.md``).

    Examples
    --------
    The removed harmonics of the filtered law are zero (an independent exact analysis of the result),
    and its dwells stay within the tolerance, 1e-3 of the 20 mm lift:

    >>> import camcad
    >>> law = camcad.compose([("rise", 90), ("dwell", 90), ("return", 90), ("dwell", 90)], 20.0)
    >>> band = camcad.resonant_harmonics(100.0, (300.0, 400.0))
    >>> filtered = camcad.filter_law(law, band, harmonics=32)
    >>> after = camcad.analyse(filtered.law, 32)
    >>> max(float(after.amplitudes[k - 1]) for k in band.removed) < 1e-12
    True
    >>> filtered.dwells_kept, filtered.dwell_tol, filtered.dwell_deviation <= filtered.dwell_tol
    (True, 0.02, True)
    """
    cycle = law.cycle
    omega = 2.0 * np.pi / cycle
    notes: list[str] = []
    wide = max(harmonics, band.highest)
    if spectrum is None or len(spectrum.coefficients) < wide:
        spectrum = analyse(law, wide)
    if not spectrum.converged:
        notes.append(f"FFT analysis did not reach its tolerance: coefficient error "
                     f"{spectrum.coefficient_error:.3g} {unit}")
    removal = np.zeros(band.highest, dtype=complex)
    for k, gain in band.gains.items():
        removal[k - 1] = -(1.0 - gain) * spectrum.coefficients[k - 1]
    removal_law = FourierLaw(cycle, 0.0, removal)
    bound = float(np.sum(2.0 * np.abs(removal)))
    phases = tuple(law.phases)
    if samples is None:
        top = max(band.highest, compensation_harmonics or 0, 2 * band.highest + 8)
        samples = max(1 << 14, 1 << math.ceil(math.log2(64 * (top + 1))))
    grid = evaluation_grid(law, samples)
    base = law.kinematics(grid)
    lift = float(np.ptp(base.s))
    tol = 1e-3 * lift if dwell_tol is None else float(dwell_tol)
    if dwell_tol is None:
        notes.append(f"dwell tolerance not given: 1e-3 of the lift, {tol:.4g} {unit}")
    dwells = dwell_grid(phases, cycle / samples)
    extremes = grid[[int(np.argmax(base.s)), int(np.argmin(base.s))]]
    keep_points = np.concatenate((dwells, extremes))

    # the written law starts from rest at s = 0 (docs/INTERFACE.md), so a filtered law still moving at θ = 0 is closed
    # with a change whose lowest harmonic m lies below the band: it moves s by up to about 2|v(0)|/(m ω0)
    # (measured: the sine of the closing change and the removed linear drift add)
    closing = _closing_order(band.removed)
    v_law0 = float(law.kinematics(np.zeros(1)).v[0])

    def deviation_on(points, correction: FourierLaw, with_drift: bool = True) -> float:
        # measured from θ = 0, where a law read back from a file starts at s = 0 (docs/INTERFACE.md): what the
        # written law's dwells and lift show against the original read the same way
        if len(points) == 0:
            return 0.0
        values = evaluate_series(correction.mean, correction.coefficients, cycle, np.append(points, 0.0))
        deviation = float(np.max(np.abs(values[:-1] - values[-1])))
        if with_drift:
            v0 = v_law0 + float(evaluate_series(correction.mean, correction.coefficients, cycle, np.zeros(1), 1)[0])
            deviation += 2.0 * abs(v0) / (closing * omega)
        return deviation

    plain_dwell = deviation_on(keep_points, removal_law)
    correction = removal_law
    compensation = None
    lam = None
    highest = (compensation_harmonics or (2 * max(band.gains) + 8)) if band.removed else 0
    if not band.removed:
        notes.append("no harmonic falls in the band: nothing removed")
    elif keep_dwells and plain_dwell > tol and highest > MAX_COMPENSATION_HARMONICS:
        notes.append(f"the dwells are not compensated: it would take harmonics up to {highest} (at most "
                     f"{MAX_COMPENSATION_HARMONICS}; the band lies at harmonics {min(band.gains)}-{max(band.gains)}); "
                     f"removal alone moves them by {plain_dwell:.4g} {unit}")
    elif keep_dwells and plain_dwell > tol:
        # fit on 16 points per period of the highest harmonic, check on the fine grid
        fit_points = np.concatenate((dwell_grid(phases, cycle / (16 * highest)), extremes))
        compensation, lam, reached = _compensate(removal_law, fit_points, keep_points, band, tol, omega, highest,
                                                 v_law0, closing)
        correction = FourierLaw(cycle, compensation.mean, _add_series(removal, compensation.coefficients))
        if not reached:
            notes.append("the dwells and the lift cannot be kept within the tolerance with the harmonics "
                         "outside the band; the smallest deviation reached is reported with its cost")
    filtered = CorrectedLaw(law, FourierLaw(cycle, correction.mean, correction.coefficients, phases))
    delta_s, delta_a = series_on_evaluation_grid(correction, grid, samples, (0, 2))
    a_filtered = base.a + delta_a
    a_removed = a_filtered if correction is removal_law else \
        base.a + series_on_evaluation_grid(removal_law, grid, samples, (2,))[0]
    peak = float(np.max(np.abs(base.a)))
    dwell_dev = deviation_on(dwells, correction, with_drift=False) if len(dwells) else None
    kept_dev = deviation_on(keep_points, correction)
    dwells_kept = kept_dev <= tol * (1 + 1e-9)
    if compensation is not None:
        notes.append(f"plain removal moved the dwells/lift by {plain_dwell:.4g} {unit} (> {tol:.4g} {unit}); "
                     f"the compensation brings it to {kept_dev:.4g} {unit} at peak-acceleration ratio "
                     f"{np.max(np.abs(a_filtered)) / peak:.4f} (removal alone: {np.max(np.abs(a_removed)) / peak:.4f})")
    window = float(np.radians(start_window_deg))
    starts_before = start_accelerations(law, window)
    starts_after = start_accelerations(filtered, window)
    return FilterResult(
        law=filtered, original=law, band=band, spectrum=spectrum, removal=removal_law, compensation=compensation,
        max_deviation=float(np.max(np.abs(delta_s - delta_s[0]))), dwell_deviation=dwell_dev, removal_bound=bound,
        lift_original=lift, lift_filtered=float(np.ptp(base.s + delta_s)),
        peak_accel_original=peak, peak_accel_filtered=float(np.max(np.abs(a_filtered))),
        peak_accel_removed_only=float(np.max(np.abs(a_removed))),
        start_accel_original=max(starts_before) if starts_before else None,
        start_accel_filtered=max(starts_after) if starts_after else None,
        start_window=window, dwell_tol=tol, dwells_kept=bool(dwells_kept), lambda_used=lam, notes=tuple(notes))


def _add_series(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    out = np.zeros(max(len(first), len(second)), dtype=complex)
    out[:len(first)] += first
    out[:len(second)] += second
    return out


def _closing_order(removed) -> int:
    """The lowest harmonic of the closing change a from-rest export makes (camcad.fourier.export): the one
    just below the removed band (the one just above it when the band starts at k = 1)."""
    if not removed:
        return 1
    low = min(removed)
    return low - 1 if low > 1 else max(removed) + 1


def _compensate(removal: FourierLaw, points: np.ndarray, check_points: np.ndarray, band: ResonanceBand,
                tol: float, omega: float, highest: int, v_law0: float = 0.0,
                closing: int = 1) -> tuple[FourierLaw, float, bool]:
    """δ = x0 + 2 Re Σ_{k∈C} x_k e^{ikω0θ}, C = {1..highest} \\ band, minimising
    mean_D (removal + δ)² + λ Σ_k 2|x_k|² (1 + (k/k_b)⁴), k_b the lowest touched harmonic: the mean
    square over the cycle of δ (the displacement change) plus δ''/(k_b ω0)² (the acceleration change,
    weighted to equal the displacement at the band). Two more rows, each weighted as the whole fit set,
    pin the deviation at θ = 0 (where a written law is read back from s = 0) and the filtered law's
    velocity there (``v_law0`` + removal' + δ' = 0, so the written law starts from rest without drift).

    Solved for every λ from one SVD of the prewhitened design matrix on the fit points D; the largest λ
    whose deviation on ``check_points`` (from θ = 0, plus the from-rest drift 2|v(0)|/(closing·ω0)) is
    ≤ tol is used (the least cost), else the one with the smallest deviation.
    """
    allowed = [k for k in range(1, highest + 1) if k not in band.gains]
    reference = float(min(band.gains))

    def design_of(theta: np.ndarray, order: int = 0) -> np.ndarray:
        columns = [np.ones(len(theta)) if order == 0 else np.zeros(len(theta))]
        for k in allowed:
            arg = k * omega * theta
            if order == 0:
                columns += [2.0 * np.cos(arg), -2.0 * np.sin(arg)]
            else:
                columns += [-2.0 * k * omega * np.sin(arg), -2.0 * k * omega * np.cos(arg)]
        return np.column_stack(columns)

    count = len(points)
    anchor = np.zeros(1)
    series = (removal.mean, removal.coefficients, removal.cycle)
    v_target = -(v_law0 + float(evaluate_series(*series, anchor, 1)[0]))
    scale_v = 2.0 / (closing * omega)      # a velocity residue at θ = 0 costs this drift per mm/rad
    weights = np.append(np.full(count, 1.0 / math.sqrt(count)), [1.0, scale_v])
    target = np.concatenate((-evaluate_series(*series, np.concatenate((points, anchor))), [v_target])) * weights
    design = np.vstack((design_of(points), design_of(anchor), design_of(anchor, 1))) * weights[:, None]
    anchor_target = -evaluate_series(*series, anchor)
    check_target = -evaluate_series(*series, check_points) - anchor_target
    check_design = design_of(check_points) - design_of(anchor)
    velocity_row = design_of(anchor, 1)[0]
    penalty = np.concatenate(([0.0], np.repeat([2.0 * (1.0 + (k / reference) ** 4) for k in allowed], 2)))
    # the constant costs nothing; a tiny weight keeps the prewhitening invertible
    penalty[0] = 1e-6 * penalty[1:].min()
    whiten = 1.0 / np.sqrt(penalty)
    u, sigma, vt = np.linalg.svd(design * whiten, full_matrices=False)
    projected = u.T @ target
    best = None
    chosen = None
    for lam in sigma[0] ** 2 * np.logspace(2, -16, 109):
        x = whiten * (vt.T @ (sigma / (sigma**2 + lam) * projected))
        deviation = float(np.max(np.abs(check_design @ x - check_target))) + \
            abs(float(velocity_row @ x) - v_target) * scale_v
        if best is None or deviation < best[0]:
            best = (deviation, x, lam)
        if deviation <= tol:
            chosen = (deviation, x, lam)
            break
    deviation, x, lam = cast(tuple[float, np.ndarray, float], chosen or best)  # 109 steps: best is set
    coefficients = np.zeros(highest, dtype=complex)
    for index, k in enumerate(allowed):
        coefficients[k - 1] = x[1 + 2 * index] + 1j * x[2 + 2 * index]
    return FourierLaw(removal.cycle, float(x[0]), coefficients), float(lam), chosen is not None
