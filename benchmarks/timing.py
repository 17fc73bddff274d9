"""What every benchmark shares: the median time of repeated runs (standard library only, so the peer's
own environment can use it too)."""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from typing import Any


def median_time(function: Callable[[], Any], repeats: int, warm_up: bool = False) -> tuple[float, Any]:
    """(median wall time in s over ``repeats`` runs, the last result); ``warm_up`` runs it once untimed first
    (imports and caches are then not part of the kernel's time)."""
    if warm_up:
        function()
    times, value = [], None
    for _ in range(max(1, repeats)):
        start = time.perf_counter()
        value = function()
        times.append(time.perf_counter() - start)
    return statistics.median(times), value
