"""Extrema of sampled functions, refined by zooming grids: many functions (rows) at once, no scalar loop.

The largest value of f over a grid is refined around the best sample: ``ZOOM_LEVELS`` finer grids of
``ZOOM_SAMPLES`` points, each spanning the neighbours of the previous best, then f at the vertex of the
parabola through the last best point and its two neighbours. Every level is one vectorised evaluation
of f over all rows, so refining an extremum costs ``ZOOM_LEVELS`` + 1 calls where a scalar search
(Brent's) costs ten to twenty. Each level spans twice the previous spacing in 16 steps, so the last
spacing is h/512 (h the first grid's step); for a smooth peak the parabola takes the abscissa well
within it and the value to round-off. Every value returned is one f
took (never the parabola's own, which overshoots across a jump); a peak at a kink or a jump is found to
within the last spacing. tests/law/test_extrema.py compares it with Brent's bounded search (``camcad.numerics``) and
with closed forms.
"""

from __future__ import annotations

import math

import numpy as np

#: refinement of a peak: zoom levels around the best sample, and samples per level
ZOOM_LEVELS = 3
ZOOM_SAMPLES = 17


def zoom_max(values, grid: np.ndarray, rows: int, first: np.ndarray | None = None
             ) -> tuple[np.ndarray, np.ndarray]:
    """The largest value of each row of ``values`` and where it is.

    Parameters
    ----------
    values : callable
        ``values(u)`` → array (rows, M): the functions at the abscissae ``u``, given as a 1-D grid shared
        by all rows or as a (rows, M) array. Non-finite values count as absent.
    grid : ndarray
        The first grid (1-D, increasing).
    rows : int
        Number of functions.
    first : ndarray, optional
        ``values(grid)`` when already computed.

    Returns
    -------
    (peak, at) : ndarrays of shape (rows,)
        The largest value (−inf where a row has no finite value) and its abscissa.

    Examples
    --------
    >>> import numpy as np
    >>> peak, at = zoom_max(lambda u: np.atleast_2d(np.sin(u)), np.linspace(0.0, 3.0, 7), 1)
    >>> round(float(peak[0]), 12), round(float(at[0]), 6)
    (1.0, 1.570796)
    """
    grid = np.asarray(grid, dtype=float)
    sampled = np.asarray(values(grid) if first is None else first, dtype=float).reshape(rows, -1)
    sampled = np.where(np.isfinite(sampled), sampled, -np.inf)
    best = np.argmax(sampled, axis=1)
    return zoom_from(values, grid, best, sampled[np.arange(rows), best])


def zoom_from(values, grid: np.ndarray, best: np.ndarray, peak: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``zoom_max`` from the best sample of each row already found: ``best`` its index in ``grid`` and ``peak``
    its value (−inf for a row without a finite value); the same refinement, row by row."""
    grid = np.asarray(grid, dtype=float)
    best = np.asarray(best)
    peak = np.asarray(peak, dtype=float)
    rows = len(best)
    every = np.arange(rows)
    at = grid[best]
    lo = grid[np.maximum(best - 1, 0)]
    hi = grid[np.minimum(best + 1, len(grid) - 1)]
    fractions = np.linspace(0.0, 1.0, ZOOM_SAMPLES)[None, :]
    for level in range(ZOOM_LEVELS):
        local = lo[:, None] + (hi - lo)[:, None] * fractions
        vals = np.asarray(values(local), dtype=float).reshape(rows, -1)
        vals = np.where(np.isfinite(vals), vals, -np.inf)
        k = np.argmax(vals, axis=1)
        better = vals[every, k] > peak
        peak = np.where(better, vals[every, k], peak)
        centre = local[every, k]
        at = np.where(better, centre, at)
        step = (hi - lo) / (ZOOM_SAMPLES - 1)
        if level == ZOOM_LEVELS - 1:
            inner = (k > 0) & (k < ZOOM_SAMPLES - 1)
            left = vals[every, np.maximum(k - 1, 0)]
            right = vals[every, np.minimum(k + 1, ZOOM_SAMPLES - 1)]
            middle = vals[every, k]
            with np.errstate(divide="ignore", invalid="ignore"):   # −inf neighbours: no parabola there
                curvature = left - 2.0 * middle + right
                offset = 0.5 * (left - right) / curvature
                vertex = middle - 0.25 * (left - right) * offset
            ok = inner & np.isfinite(vertex) & (curvature < 0.0) & (np.abs(offset) <= 1.0)
            if ok.any():
                # the function itself at the parabola's vertex, not the parabola's value: across a jump the
                # parabola overshoots every value the function takes
                guess = np.where(ok, centre + offset * step, centre)
                there = np.asarray(values(guess[:, None]), dtype=float).reshape(rows)
                better = ok & np.isfinite(there) & (there > peak)
                peak = np.where(better, there, peak)
                at = np.where(better, guess, at)
        lo = np.maximum(centre - step, lo)
        hi = np.minimum(centre + step, hi)
    return peak, at


def zoom_min(fn, grid: np.ndarray, first: np.ndarray | None = None) -> tuple[float, float]:
    """The smallest value of one function ``fn`` (1-D abscissae → array) over ``grid`` and where it is, refined
    as ``zoom_max`` refines a peak; (inf, nan) where ``fn`` has no finite value. ``first`` = fn(grid) when
    already computed.

    Examples
    --------
    >>> import numpy as np
    >>> value, at = zoom_min(np.cos, np.linspace(2.0, 4.0, 9))
    >>> round(value, 12), round(at, 6)
    (-1.0, 3.141593)
    """
    def negated(u: np.ndarray) -> np.ndarray:
        return -np.asarray(fn(np.ravel(u)), dtype=float).reshape(1, -1)

    peak, at = zoom_max(negated, grid, 1, None if first is None else -np.asarray(first, dtype=float))
    if not np.isfinite(peak[0]):
        return math.inf, math.nan
    return float(-peak[0]), float(at[0])
