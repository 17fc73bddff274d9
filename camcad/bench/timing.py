"""CPU time of several candidates measured in one run, interleaved (standard library only).

On a shared machine wall time measures the other processes as much as the work; the CPU time of this
process (``time.process_time``: user + system of all its threads) does not, to first order. Each
candidate is run once untimed (imports, caches), then ``rounds`` times in rotated order, each time in a
batch long enough to be above the clock's resolution; a candidate's figure is the median over the
rounds of its batch's CPU time per call. Ratios between candidates are ratios of these medians.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from typing import Any

#: a timed batch lasts at least this much CPU time (s), so that the clock's resolution does not matter
MIN_BATCH_S = 0.02


def batch_size(function: Callable[[], Any], min_batch_s: float = MIN_BATCH_S) -> int:
    """How many calls of ``function`` make a batch of at least ``min_batch_s`` of CPU time (1 for slow ones)."""
    calls = 1
    while True:
        start = time.process_time()
        for _ in range(calls):
            function()
        spent = time.process_time() - start
        if spent >= min_batch_s or calls >= 1 << 16:
            return calls
        calls = max(calls * 2, int(calls * min_batch_s / max(spent, 1e-6)) + 1)


def cpu_interleaved(candidates: dict[str, Callable[[], Any]], rounds: int = 5,
                    min_batch_s: float = MIN_BATCH_S) -> dict[str, float]:
    """Median CPU time per call (s) of each candidate, measured in ``rounds`` interleaved rounds.

    Parameters
    ----------
    candidates : dict of str to callable
        Name → a function of no arguments (its result is discarded).
    rounds : int
        Rounds; in round r the candidates run in their order rotated by r.
    min_batch_s : float
        Least CPU time of one batch of calls (s).

    Returns
    -------
    dict of str to float
        Name → CPU seconds per call (median over the rounds).

    Examples
    --------
    >>> times = cpu_interleaved({"sum": lambda: sum(range(1000)), "nothing": lambda: None}, rounds=3,
    ...                         min_batch_s=0.001)
    >>> times["sum"] > times["nothing"] >= 0.0
    True
    """
    names = list(candidates)
    sizes = {name: batch_size(candidates[name], min_batch_s) for name in names}   # also the warm-up
    samples: dict[str, list[float]] = {name: [] for name in names}
    for r in range(max(1, rounds)):
        order = names[r % len(names):] + names[:r % len(names)]
        for name in order:
            function, calls = candidates[name], sizes[name]
            start = time.process_time()
            for _ in range(calls):
                function()
            samples[name].append((time.process_time() - start) / calls)
    return {name: statistics.median(values) for name, values in samples.items()}


def cpu_once(function: Callable[[], Any]) -> tuple[float, Any]:
    """(CPU seconds, result) of one call."""
    start = time.process_time()
    result = function()
    return time.process_time() - start, result
