"""Plots of a law's spectrum and of resonance filtering (PNG, Agg backend).

- ``plot_spectrum``: bar plots of the harmonic amplitudes of s (mm) and of a (mm/rad²), log scale,
  with the resonance band k·n/60 = fn(1 ± band), n ∈ [n1, n2], shaded and the removed harmonics marked.
- ``plot_filtered``: original against filtered s and a over the cycle, and the displacement
  deviation with the dwells shaded and the tolerance drawn.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from camcad.io.atomic import write_atomic
from camcad.report.figure import pyplot

_REMOVED = "#c0392b"
_TAPERED = "#e67e22"
_KEPT = "#34495e"
_BAND = "#f5b7b1"


def _save(fig, path: str | Path) -> Path:
    plt = pyplot()
    try:
        return write_atomic(path, lambda tmp: fig.savefig(tmp, format="png", dpi=130))
    finally:
        plt.close(fig)


def _bar_colours(ks: np.ndarray, band) -> list[str]:
    gains = band.gains if band is not None else {}
    return [(_REMOVED if gains[k] == 0 else _TAPERED) if k in gains else _KEPT for k in ks]


def plot_spectrum(spectrum, path: str | Path, *, band=None, title: str = "", max_harmonics: int | None = None,
                  filtered=None) -> Path:
    """Amplitudes A_k of s and of a against k, the resonance band shaded (``band``: a ResonanceBand).

    ``filtered``: an optional second Spectrum (after filtering), drawn as outlined bars.
    """
    plt = pyplot()
    count = len(spectrum.coefficients) if max_harmonics is None else min(max_harmonics, len(spectrum.coefficients))
    ks = np.arange(1, count + 1)
    fig, axes = plt.subplots(2, 1, figsize=(10, 7), sharex=True)
    floor = {}
    for ax, values, other, label in (
            (axes[0], spectrum.amplitudes[:count], None if filtered is None else filtered.amplitudes[:count],
             "displacement amplitude $A_k$ (mm)"),
            (axes[1], spectrum.accel_amplitudes[:count],
             None if filtered is None else filtered.accel_amplitudes[:count],
             "acceleration amplitude (mm/rad$^2$)")):
        positive = values[values > 0]
        low = float(positive.max()) * 1e-12 if len(positive) else 1e-12
        floor[label] = low
        ax.bar(ks, np.maximum(values, low), color=_bar_colours(ks, band), width=0.8, label="original")
        if other is not None:
            ax.bar(ks, np.maximum(other, low), facecolor="none", edgecolor="#16a085", linewidth=1.0, width=0.8,
                   label="filtered")
        ax.set_yscale("log")
        ax.set_ylabel(label)
        ax.grid(True, which="major", axis="y", alpha=0.3)
        if band is not None and band.k_high >= 1:
            ax.axvspan(max(band.k_low, 0.5), band.k_high, color=_BAND, alpha=0.6, zorder=0)
    axes[-1].set_xlabel("harmonic k")
    axes[-1].set_xlim(0.3, count + 0.7)
    if band is not None:
        low_hz, high_hz = band.frequency_band_hz()
        axes[0].set_title(
            f"resonance band (shaded): k n/60 in [{low_hz:.4g}, {high_hz:.4g}] Hz for n in "
            f"[{band.rpm[0]:g}, {band.rpm[1]:g}] rpm -> k in [{band.k_low:.3f}, {band.k_high:.3f}]; "
            f"removed {_ranges(band.removed)}", fontsize=9)
        handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in (_KEPT, _REMOVED, _TAPERED, _BAND)]
        names = ["kept", "removed", "tapered", "resonance band"]
        if filtered is not None:
            handles.append(plt.Rectangle((0, 0), 1, 1, facecolor="none", edgecolor="#16a085"))
            names.append("filtered")
        axes[0].legend(handles, names, loc="upper right", fontsize=8)
    fig.suptitle(title or "harmonic amplitudes", fontsize=11)
    fig.tight_layout()
    return _save(fig, path)


def _ranges(values) -> str:
    values = sorted(values)
    if not values:
        return "none"
    parts = []
    start = prev = values[0]
    for v in values[1:] + [None]:
        if v is not None and v == prev + 1:
            prev = v
            continue
        parts.append(f"{start}" if start == prev else f"{start}-{prev}")
        if v is not None:
            start = prev = v
    return ", ".join(parts)


def plot_filtered(original, filtered, path: str | Path, *, title: str = "", dwell_tol: float | None = None,
                  samples: int = 4096, labels: tuple[str, str] = ("original", "filtered"), written=None) -> Path:
    """Original against filtered s and a over one cycle, and the deviation of s with the dwells shaded.

    ``written``: optionally the law as written to the DXF (from rest at s = 0), whose deviation from the
    original is drawn too.
    """
    plt = pyplot()
    theta = np.linspace(0.0, original.cycle, samples + 1)
    first = original.kinematics(theta)
    second = filtered.kinematics(theta)
    deg = np.degrees(theta)
    fig, axes = plt.subplots(3, 1, figsize=(10, 9), sharex=True)
    axes[0].plot(deg, first.s, color=_KEPT, lw=1.2, label=labels[0])
    axes[0].plot(deg, second.s, color="#16a085", lw=1.0, ls="--", label=labels[1])
    axes[0].set_ylabel("s (mm)")
    axes[0].legend(loc="upper right", fontsize=8)
    deviation = second.s - first.s
    axes[1].plot(deg, deviation * 1e3, color="#8e44ad", lw=1.0, label=f"{labels[1]} - {labels[0]}")
    if written is not None:
        third = written.kinematics(theta)
        axes[1].plot(deg, (third.s - first.s) * 1e3, color=_TAPERED, lw=0.9, ls="--",
                     label="as written (from rest at s = 0) - " + labels[0])
    axes[1].legend(loc="lower left", fontsize=8)
    axes[1].set_ylabel("s deviation (µm)")
    if dwell_tol is not None:
        for sign in (-1, 1):
            axes[1].axhline(sign * dwell_tol * 1e3, color=_REMOVED, lw=0.8, ls=":")
        axes[1].text(deg[-1], dwell_tol * 1e3, " dwell tolerance", color=_REMOVED, fontsize=8, va="bottom", ha="right")
    for ax in axes:
        for phase in original.phases:
            if phase.kind == "dwell":
                ax.axvspan(np.degrees(phase.start), np.degrees(phase.end), color="#ecf0f1", zorder=0)
    peak = int(np.argmax(np.abs(deviation)))
    axes[1].annotate(f"max {abs(deviation[peak]) * 1e3:.3g} µm at {deg[peak]:.1f}°", (deg[peak], deviation[peak] * 1e3),
                     fontsize=8, xytext=(5, 5), textcoords="offset points")
    axes[2].plot(deg, first.a, color=_KEPT, lw=1.2, label=labels[0])
    axes[2].plot(deg, second.a, color="#16a085", lw=1.0, ls="--", label=labels[1])
    axes[2].set_ylabel("a (mm/rad$^2$)")
    axes[2].set_xlabel("cam angle θ (deg)  (dwells shaded)")
    axes[2].legend(loc="upper right", fontsize=8)
    for ax in axes:
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlim(0, deg[-1])
    fig.suptitle(title or "original and filtered law", fontsize=11)
    fig.tight_layout()
    return _save(fig, path)


def plot_truncation(rms_errors: np.ndarray, path: str | Path, *, max_errors: dict | None = None,
                    tol: float | None = None, title: str = "") -> Path:
    """RMS (and sampled max) error of the truncated series against the number of harmonics N."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ns = np.arange(len(rms_errors))
    positive = rms_errors > 0
    ax.semilogy(ns[positive], rms_errors[positive], "o-", ms=3, color=_KEPT, label="RMS error (Parseval)")
    if max_errors:
        keys = sorted(max_errors)
        ax.semilogy(keys, [max_errors[k] for k in keys], "s--", ms=4, color=_TAPERED, label="max error (sampled)")
    if tol is not None:
        ax.axhline(tol, color=_REMOVED, ls=":", lw=1, label=f"tolerance {tol:g} mm")
    ax.set_xlabel("harmonics kept N")
    ax.set_ylabel("error of the truncated series (mm)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(title or "truncation error", fontsize=11)
    fig.tight_layout()
    return _save(fig, path)
