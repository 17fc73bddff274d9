"""The resonance band: which harmonics of a law excite a follower of natural frequency fn over a speed range.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from camcad.errors import CamcadError

# =============================================================================================
# Resonance filtering
# =============================================================================================

@dataclass(frozen=True)
class ResonanceBand:
    """Harmonics that meet the natural frequency over a speed range.

    k is *resonant* when |k n/60 − fn| ≤ band·fn for some n ∈ [n1, n2] rpm, i.e.
        60 fn (1 − band)/n2 ≤ k ≤ 60 fn (1 + band)/n1     (both ends included, to 1e-9 relative).
    ``camcad.resonant_harmonics`` returns it; the example is there.

    Attributes
    ----------
    fn_hz : float
        The natural frequency, Hz.
    rpm : tuple of float
        (n1, n2), rpm.
    band : float
        The relative half-width of the band around fn (a fraction).
    neighbours : int
        Harmonics added on each side.
    taper : int
        Harmonics of raised-cosine ramp beyond those.
    k_low, k_high : float
        The band's ends in harmonic order (dimensionless).
    core : tuple of int
        The resonant harmonics.
    removed : tuple of int
        ``core`` with ``neighbours`` on each side.
    gains : dict
        {k: g} multiplying the harmonics: 0 for the removed ones, sin²(π d / (2(taper + 1))) over the
        next ``taper`` at distance d (dimensionless).
    """

    fn_hz: float
    rpm: tuple[float, float]
    band: float
    neighbours: int
    taper: int
    k_low: float
    k_high: float
    core: tuple[int, ...]
    removed: tuple[int, ...]
    gains: dict

    @property
    def highest(self) -> int:
        return max(self.gains) if self.gains else 0

    def frequency_band_hz(self) -> tuple[float, float]:
        return self.fn_hz * (1.0 - self.band), self.fn_hz * (1.0 + self.band)


#: the most harmonics a resonance band may cover (with its neighbours and taper)
MAX_HARMONICS = 100_000


def speed_range(rpm, where: str = "rpm") -> tuple[float, float]:
    """(n1, n2) in rpm from one speed or a sequence of speeds; CamcadError unless positive and finite.

    Parameters
    ----------
    rpm : float or sequence of float
        The speeds, rpm.
    where : str
        Named in errors.

    Returns
    -------
    tuple of float
        The slowest and the fastest, rpm.

    Raises
    ------
    CamcadError
        A speed that is not positive and finite.

    Examples
    --------
    >>> from camcad.fourier import speed_range
    >>> speed_range([420, 280, 330]), speed_range(300)
    ((280.0, 420.0), (300.0, 300.0))
    """
    values = [rpm] if isinstance(rpm, (int, float)) and not isinstance(rpm, bool) else list(rpm)
    if not values or any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0
                         for v in values):
        raise CamcadError(f"speeds must be positive numbers (rpm), got {rpm!r}", where,
                          "give one speed or a range n1:n2 in rpm")
    return float(min(values)), float(max(values))


def resonant_harmonics(fn_hz: float, rpm, band: float = 0.05, neighbours: int = 1, taper: int = 0,
                       where: str = "filter") -> ResonanceBand:
    """The harmonics of a law that meet a natural frequency fn over a speed range (the resonance band).

    Harmonic k is *resonant* when |k n/60 − fn| ≤ band·fn for some speed n ∈ [n1, n2] rpm, i.e.
    60 fn (1 − band)/n2 ≤ k ≤ 60 fn (1 + band)/n1 (both ends included, to 1e-9 relative). ``removed``
    adds ``neighbours`` harmonics on each side; ``gains`` multiply the harmonics: 0 for the removed ones
    and, with ``taper`` > 0, a raised-cosine ramp g = sin²(π d / (2(taper + 1))) over the next ``taper``
    harmonics at distance d from the removed set.

    Parameters
    ----------
    fn_hz : float
        Natural frequency of the follower system, Hz.
    rpm : float or sequence of float
        One speed or the speeds (n1 … n2) of the machine, rpm.
    band : float
        Half-width of the band as a fraction of fn (0.05: ±5 %), dimensionless.
    neighbours : int
        Harmonics removed on each side of the resonant ones (a count).
    taper : int
        Harmonics over which the gain ramps back to 1 (a count; 0: a hard cut).
    where : str
        What to name in an error message.

    Returns
    -------
    ResonanceBand
        ``k_low``, ``k_high`` (the band in harmonic numbers, dimensionless), ``core`` (the resonant k),
        ``removed``, ``gains`` ({k: gain}, dimensionless), ``fn_hz`` (Hz), ``rpm`` (n1, n2 in rpm).

    Raises
    ------
    CamcadError
        A speed or frequency that is not positive, a band outside [0, 1), negative counts.

    References
    ----------
    Resonance filtering of a motion law (removing the resonating harmonic and its neighbours): PhD
    abstract on the batten mechanism of the STB loom, Novosibirsk.

    Examples
    --------
    fn = 100 Hz, 300–400 rpm, ±5 %: by hand k ≥ 60·100·0.95/400 = 14.25 and k ≤ 60·100·1.05/300 = 21:

    >>> import camcad
    >>> band = camcad.resonant_harmonics(100.0, (300.0, 400.0), band=0.05, neighbours=1)
    >>> round(band.k_low, 9), round(band.k_high, 9), band.core
    (14.25, 21.0, (15, 16, 17, 18, 19, 20, 21))
    >>> band.removed
    (14, 15, 16, 17, 18, 19, 20, 21, 22)
    """
    low, high = speed_range(rpm, where)
    if not (np.isfinite(fn_hz) and fn_hz > 0):
        raise CamcadError(f"natural frequency {fn_hz!r} Hz must be positive", where, "give fn in Hz, e.g. --fn 160")
    if not (np.isfinite(band) and 0 <= band < 1):
        raise CamcadError(f"band {band!r} must be a fraction in [0, 1)", where,
                          "give the half-width as a fraction of fn, e.g. 0.05 for ±5 %")
    if neighbours < 0 or taper < 0:
        raise CamcadError("neighbours and taper must be >= 0", where, "give whole numbers >= 0")
    k_low = 60.0 * fn_hz * (1.0 - band) / high
    k_high = 60.0 * fn_hz * (1.0 + band) / low
    slack = 1e-9
    first = max(1, math.ceil(k_low * (1 - slack)))
    last = math.floor(k_high * (1 + slack))
    count = last - first + 1 + 2 * neighbours + 2 * taper   # counted before any list of them is made
    if count > MAX_HARMONICS:
        raise CamcadError(f"the band covers {count:.3g} harmonics (at most {MAX_HARMONICS})", where,
                          "narrow the band or the speed range, or lower fn")
    core = tuple(range(first, last + 1))
    removed: set[int] = set()
    for k in core:
        removed.update(j for j in range(k - neighbours, k + neighbours + 1) if j >= 1)
    gains = {k: 0.0 for k in removed}
    if taper and removed:
        for d in range(1, taper + 1):
            gain = math.sin(math.pi * d / (2 * (taper + 1))) ** 2
            for j in (min(removed) - d, max(removed) + d):
                if j >= 1 and j not in gains:
                    gains[j] = gain
    return ResonanceBand(float(fn_hz), (low, high), float(band), int(neighbours), int(taper), k_low, k_high,
                         core, tuple(sorted(removed)), dict(sorted(gains.items())))



