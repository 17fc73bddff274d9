"""Phase angles of the optimised cyclogram fed back into each mechanism's phases.
"""

from __future__ import annotations

from collections.abc import Mapping
from itertools import pairwise
from typing import TYPE_CHECKING, Any

from camcad.errors import CamcadError

if TYPE_CHECKING:    # the LP (scipy.optimize) is not imported by a profile that only stretches phases
    from camcad.cyclogram.lp import CyclogramResult

# --------------------------------------------------------------------------------------------
# Feeding the optimal angles back into a mechanism's phases
# --------------------------------------------------------------------------------------------

def stretch_phase(phases_deg: list[tuple[float, float, str]], index: int, width_deg: float,
                  cycle_deg: float = 360.0) -> list[tuple[float, float, str]]:
    """The phases with phase ``index`` (0-based) made ``width_deg`` wide, keeping its start; the
    next dwell (else the previous one) takes up the difference so the cycle still adds up.

    Phases are (start_deg, end_deg, kind) covering [0, cycle_deg]. Raises CamcadError when no
    neighbouring dwell is wide enough.
    """
    phases: list[list[Any]] = [list(p) for p in phases_deg]
    change = width_deg - (phases[index][1] - phases[index][0])
    for neighbour in (index + 1, index - 1):
        if 0 <= neighbour < len(phases) and phases[neighbour][2] == "dwell":
            if phases[neighbour][1] - phases[neighbour][0] - change < 0.0:
                continue
            if neighbour > index:
                phases[index][1] += change
                phases[neighbour][0] += change
            else:
                phases[index][0] -= change
                phases[neighbour][1] -= change
            return [tuple(p) for p in phases if p[1] > p[0]]
    raise CamcadError(f"phase {index + 1} ({phases[index][2]}) cannot be made {width_deg:g} deg wide: "
                      "no neighbouring dwell is wide enough", "phases",
                      "give the law a longer dwell next to that phase")


def retime_phases(phases_deg: list[tuple[float, float, str]],
                  assignments: Mapping[tuple[str, int], tuple[float, float]],
                  cycle_deg: float = 360.0, where: str = "phases") -> list[tuple[float, float, str]]:
    """New phases of a mechanism's law after the cyclogram moved some of its motions.

    ``assignments`` maps (kind, occurrence) — e.g. ("rise", 1), the first rise — to its new
    (start_deg, width_deg). Rises and returns not assigned keep their place; dwells become the gaps
    between the motions, and a motion that crosses 0/cycle is rejected (shift ``start_deg``).
    Returns (start_deg, end_deg, kind) covering [0, cycle_deg]; ``format_phases`` writes them as text.
    """
    occurrences: dict[str, int] = {}
    motions = []
    used = set()
    for start, end, kind in phases_deg:
        if kind == "dwell":
            continue
        occurrences[kind] = occurrences.get(kind, 0) + 1
        key = (kind, occurrences[kind])
        if key in assignments:
            used.add(key)
            new_start, width = assignments[key]
            motions.append((float(new_start), float(new_start) + float(width), kind))
        else:
            motions.append((float(start), float(end), kind))
    missing = [k for k in assignments if k not in used]
    if missing:
        kind, occurrence = missing[0]
        raise CamcadError(f"the law has no {kind} number {occurrence}", where,
                          "check the operation's phase and occurrence against the law's phases")
    tol = 1e-9 * cycle_deg
    for start, end, kind in motions:
        if start < -tol or end > cycle_deg + tol:
            raise CamcadError(f"the {kind} would run over {start:.6g}..{end:.6g} deg, across the cycle's "
                              f"start", where, "shift the cyclogram's start_deg so every motion lies in 0..360")
    motions.sort()
    for (s0, e0, k0), (s1, e1, k1) in pairwise(motions):
        if s1 < e0 - tol:
            raise CamcadError(f"the {k0} {s0:.6g}..{e0:.6g} deg and the {k1} {s1:.6g}..{e1:.6g} deg overlap",
                              where, "give the mechanism's operations consecutive events in the cyclogram")
    order = [k for _, _, k in sorted((s, e, k) for s, e, k in phases_deg if k != "dwell")]
    if [k for _, _, k in motions] != order:
        raise CamcadError("the new timing changes the order of the law's rises and returns", where,
                          "keep the operations in the law's order")
    result: list[tuple[float, float, str]] = []
    cursor = 0.0
    for start, end, kind in motions:
        start, end = max(start, 0.0), min(end, cycle_deg)
        if start - cursor > tol:
            result.append((cursor, start, "dwell"))
        result.append((start if start - cursor > tol else cursor, end, kind))
        cursor = end
    if cycle_deg - cursor > tol:
        result.append((cursor, cycle_deg, "dwell"))
    else:
        result[-1] = (result[-1][0], cycle_deg, result[-1][2])
    return result


def format_phases(phases_deg: list[tuple[float, float, str]]) -> str:
    """"0:90:dwell,90:180:rise,..." (the scene's ``phases`` text) from (start, end, kind) in deg."""
    return ",".join(f"{start:.10g}:{end:.10g}:{kind}" for start, end, kind in phases_deg)


def operation_timing(result: CyclogramResult) -> dict[str, dict[tuple[str, int], tuple[float, float]]]:
    """{mechanism: {(phase kind, occurrence): (start_deg, width_deg)}} from an optimal cyclogram,
    wrapped into [0, cycle): what ``retime_phases`` needs for each mechanism."""
    if not result.feasible:
        raise CamcadError("the cyclogram is infeasible; there are no phase angles to feed back",
                          "[cyclogram]", "resolve the conflict first")
    timing: dict[str, dict[tuple[str, int], tuple[float, float]]] = {}
    for op in result.network.operations:
        if op.mechanism is None or op.phase is None:
            continue
        start = result.event_times_deg[op.tail] % result.network.cycle_deg
        timing.setdefault(op.mechanism, {})[(op.phase, op.occurrence)] = (
            start, result.phase_angles_deg[op.label])
    return timing




