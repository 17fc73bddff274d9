"""Sorted sets of numbers (``unique``, ``union``) without the start-up cost of ``numpy.unique``.

``numpy.unique`` and ``numpy.union1d`` (numpy 2.x) look up ``numpy.ma`` on every call, and the first
lookup imports the masked-array package: 15–20 ms of a command whose whole run is a few hundred
milliseconds (measured with ``python -X importtime``). camcad only needs the sorted distinct values
of a 1-D float array, which a sort and a comparison of neighbours give. NaN sorts last and is kept
once, as ``numpy.unique`` does (``equal_nan=True``); ``tests/law/test_arrays.py`` compares the two.
"""

from __future__ import annotations

import numpy as np


def unique(values) -> np.ndarray:
    """The sorted distinct values of ``values`` (flattened), NaN kept once at the end.

    Parameters
    ----------
    values : array_like
        Numbers, any shape.

    Returns
    -------
    ndarray
        1-D, sorted, no repeats.

    Examples
    --------
    >>> unique([3.0, 1.0, 3.0, 2.0]).tolist()
    [1.0, 2.0, 3.0]
    """
    ordered = np.sort(np.asarray(values).ravel())
    if ordered.size == 0:
        return ordered
    keep = np.empty(ordered.size, dtype=bool)
    keep[0] = True
    np.not_equal(ordered[1:], ordered[:-1], out=keep[1:])
    if ordered.dtype.kind in "fc" and np.isnan(ordered[-1]):   # NaNs sort last: keep the first of them
        first_nan = int(np.flatnonzero(np.isnan(ordered))[0])
        keep[first_nan:] = False
        keep[first_nan] = True
    return ordered[keep]


def union(first, second) -> np.ndarray:
    """The sorted distinct values of both arrays (as ``numpy.union1d``).

    Examples
    --------
    >>> union([0.0, 0.5, 1.0], [0.25, 0.5]).tolist()
    [0.0, 0.25, 0.5, 1.0]
    """
    return unique(np.concatenate((np.ravel(first), np.ravel(second))))


def present(index, count: int) -> np.ndarray:
    """The distinct values of ``index`` (non-negative integers below ``count``), sorted: ``unique`` of an index
    array in one counting pass instead of a sort (a law's segment of each of a million angles).

    Examples
    --------
    >>> present(np.array([2, 0, 2, 2]), 4).tolist()
    [0, 2]
    """
    return np.flatnonzero(np.bincount(np.asarray(index).ravel(), minlength=count))
