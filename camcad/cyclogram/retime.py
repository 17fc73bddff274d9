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
    """The phases with phase ``index`` made ``width_deg`` wide, keeping its start.

    The next dwell (else the previous one) takes up the difference so the cycle still adds up.

    Parameters
    ----------
    phases_deg : list of (float, float, str)
        (start_deg, end_deg, kind) covering [0, cycle_deg], deg.
    index : int
        The phase to stretch (0-based).
    width_deg : float
        Its new width, deg.
    cycle_deg : float
        The cycle, deg.

    Returns
    -------
    list of (float, float, str)
        The new phases, deg.

    Raises
    ------
    CamcadError
        No neighbouring dwell is wide enough.

    Examples
    --------
    >>> from camcad.cyclogram import format_phases, stretch_phase
    >>> phases = [(0.0, 90.0, "rise"), (90.0, 180.0, "dwell"), (180.0, 270.0, "return"), (270.0, 360.0, "dwell")]
    >>> format_phases(stretch_phase(phases, 0, 120.0))
    '0:120:rise,120:180:dwell,180:270:return,270:360:dwell'
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

    Parameters
    ----------
    phases_deg : list of (float, float, str)
        The law's phases: start and end in deg, and kind.
    assignments : dict
        {(kind, occurrence): (start_deg, width_deg)}, deg.
    cycle_deg : float
        The cycle, deg.
    where : str
        Named in errors.

    Returns
    -------
    list of (float, float, str)
        (start_deg, end_deg, kind) covering [0, cycle_deg], deg; ``format_phases`` writes them as text.

    Raises
    ------
    CamcadError
        Motions that overlap, an occurrence the law does not have, a motion across the cycle's end.

    Examples
    --------
    >>> from camcad.cyclogram import format_phases, retime_phases
    >>> phases = [(0.0, 30.0, "dwell"), (30.0, 90.0, "rise"), (90.0, 200.0, "dwell"), (200.0, 260.0, "return"),
    ...           (260.0, 360.0, "dwell")]
    >>> format_phases(retime_phases(phases, {("rise", 1): (40.0, 50.0)}))
    '0:40:dwell,40:90:rise,90:200:dwell,200:260:return,260:360:dwell'
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
    """The scene's ``phases`` text ("0:90:dwell,90:180:rise,...") from (start, end, kind) in deg.

    Parameters
    ----------
    phases_deg : list of (float, float, str)
        The phases: start and end in deg, and kind.

    Returns
    -------
    str
        The text, angles in deg.

    Examples
    --------
    >>> from camcad.cyclogram import format_phases
    >>> format_phases([(0.0, 90.0, "rise"), (90.0, 180.0, "dwell"), (180.0, 270.0, "return"), (270.0, 360.0, "dwell")])
    '0:90:rise,90:180:dwell,180:270:return,270:360:dwell'
    """
    return ",".join(f"{start:.10g}:{end:.10g}:{kind}" for start, end, kind in phases_deg)


def operation_timing(result: CyclogramResult) -> dict[str, dict[tuple[str, int], tuple[float, float]]]:
    """What ``retime_phases`` needs for each mechanism, from an optimal cyclogram.

    Each operation that names a mechanism and a phase gives that phase's new start and width, wrapped into
    [0, cycle).

    Parameters
    ----------
    result : CyclogramResult
        A feasible cyclogram.

    Returns
    -------
    dict
        {mechanism: {(phase kind, occurrence): (start_deg, width_deg)}}, deg.

    Raises
    ------
    CamcadError
        An infeasible cyclogram.

    Examples
    --------
    >>> import camcad
    >>> from camcad.cyclogram import operation_timing
    >>> network = camcad.make_network([camcad.Operation("0", "1", 20.0),
    ...                                camcad.Operation("1", "2", 35.0, mechanism="lift", phase="rise")])
    >>> operation_timing(camcad.optimise(network))
    {'lift': {('rise', 1): (20.0, 35.0)}}
    """
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




