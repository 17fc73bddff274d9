"""The cyclogram's network: events, operations (phase angles with bounds), cycle detection.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field

from camcad.errors import CamcadError, nearest_name

# --------------------------------------------------------------------------------------------
# The network
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Operation:
    """One operation (an arc) of the cyclogram's network, from event ``tail`` to event ``head``.

    Its phase angle t = p(head) − p(tail) (deg) is what the cyclogram optimises, within its bounds.

    Parameters
    ----------
    tail : str
        The event that starts it.
    head : str
        The event that ends it.
    min_deg : float
        The least admissible phase angle [φ], deg (≥ 0).
    max_deg : float
        The largest phase angle, deg (``math.inf``: unbounded).
    mechanism : str, optional
        The mechanism doing it (a row of the Gantt chart).
    name : str
        A label for reports (no unit).
    phase : str, optional
        Which phase of that mechanism's law it is ("rise", "return", "dwell"), for feeding the
        optimal angle back into the law.
    occurrence : int
        Which occurrence of that phase kind (1: the first; a count).
    amplitude : callable, optional
        A vibration relation amplitude(t): mm against the phase angle t in deg.
    amplitude_limit_mm : float, optional
        The limit of ``amplitude``, mm; it becomes a lower bound on t.

    References
    ----------
    Podgorny et al., Obrabotka Metallov 20(1) (2018) 44–54: the cyclogram as a network of
    events and operations with least admissible phase angles.

    Examples
    --------
    >>> import camcad
    >>> feed = camcad.Operation("start", "fed", min_deg=30.0, max_deg=90.0, mechanism="feeder")
    >>> feed.label, feed.min_deg, feed.max_deg
    ('start->fed', 30.0, 90.0)
    """

    tail: str
    head: str
    min_deg: float = 0.0
    max_deg: float = math.inf
    mechanism: str | None = None
    name: str = ""
    phase: str | None = None
    occurrence: int = 1
    amplitude: Callable[[float], float] | None = field(default=None, compare=False)
    amplitude_limit_mm: float | None = None

    @property
    def label(self) -> str:
        return f"{self.tail}->{self.head}"


@dataclass(frozen=True)
class Network:
    """A cyclogram's events and operations, its first and last event, the cycle and where it starts.

    Build it with ``camcad.make_network`` (which validates it).

    Parameters
    ----------
    events : tuple of str
        The events.
    operations : tuple of Operation
        The operations between them (bounds in deg).
    start, end : str
        The first and last events.
    cycle_deg : float
        The machine's cycle, deg.
    start_deg : float
        Where the first event sits on the machine's cycle, deg.

    Examples
    --------
    >>> import camcad
    >>> network = camcad.make_network([camcad.Operation("S", "X", 30.0), camcad.Operation("S", "Y", 40.0),
    ...                                camcad.Operation("X", "E", 10.0), camcad.Operation("Y", "E", 15.0)])
    >>> network.events, network.start, network.end, network.operation("S->Y").min_deg
    (('S', 'X', 'Y', 'E'), 'S', 'E', 40.0)
    """

    events: tuple[str, ...]
    operations: tuple[Operation, ...]
    start: str
    end: str
    cycle_deg: float = 360.0
    start_deg: float = 0.0

    def operation(self, label: str) -> Operation:
        for op in self.operations:
            if op.label == label:
                return op
        raise KeyError(label)


def make_network(operations: Iterable[Operation], events: Iterable[str] | None = None,
                 start: str | None = None, end: str | None = None, cycle_deg: float = 360.0,
                 start_deg: float = 0.0, where: str = "[cyclogram]") -> Network:
    """A validated cyclogram network: its events, its operations, the first and last event.

    Raises CamcadError for an operation naming an unknown event, an operation from an event to itself,
    two operations between the same events, bounds with min > max, a cycle of operations (named:
    "a -> b -> c -> a"), no unique first or last event, and an event on no path from the first to the
    last.

    Parameters
    ----------
    operations : iterable of Operation
        The operations (arcs), with their bounds in deg.
    events : iterable of str, optional
        The events in order; by default those the operations name, in order of appearance.
    start, end : str, optional
        The first and last events; found as the only event without a predecessor (successor) when None.
    cycle_deg : float
        The machine's cycle, deg.
    start_deg : float
        Where the first event sits on the machine's cycle, deg.
    where : str
        What to name in an error message (the scene section).

    Returns
    -------
    Network
        ``events``, ``operations``, ``start``, ``end``, ``cycle_deg`` and ``start_deg`` (deg).

    Raises
    ------
    CamcadError
        The network is not a usable cyclogram (see above).

    References
    ----------
    Podgorny et al., Obrabotka Metallov 20(1) (2018) 44–54.

    Examples
    --------
    >>> import camcad
    >>> network = camcad.make_network([camcad.Operation("a", "b", 30.0), camcad.Operation("b", "c", 45.0)])
    >>> network.events, network.start, network.end, network.cycle_deg
    (('a', 'b', 'c'), 'a', 'c', 360.0)
    >>> camcad.make_network([camcad.Operation("a", "b"), camcad.Operation("b", "a")])
    Traceback (most recent call last):
    ...
    camcad.errors.CamcadError: [cyclogram]: the operations form a cycle: a -> b -> a; an event cannot come before itself; remove or reverse one of these operations
    """  # noqa: E501 - a doctest's expected output is one line
    ops = tuple(operations)
    if not ops:
        raise CamcadError("the cyclogram has no operations", where, "add [[cyclogram.operations]] tables")
    order: list[str] = list(events) if events is not None else []
    if events is not None:
        if len(set(order)) != len(order):
            twice = sorted({e for e in order if order.count(e) > 1})
            raise CamcadError(f"event {twice[0]!r} is listed twice", where, "list each event once")
        for op in ops:
            for name in (op.tail, op.head):
                if name not in order:
                    raise CamcadError(f"operation {op.label} names event {name!r}, which is not in events",
                                      where, nearest_name(name, order).replace("valid keys", "events"))
    else:
        for op in ops:
            for name in (op.tail, op.head):
                if name not in order:
                    order.append(name)
    seen: dict[tuple[str, str], Operation] = {}
    for op in ops:
        if op.tail == op.head:
            raise CamcadError(f"operation {op.label} starts and ends at the same event", where,
                              "an operation joins two different events")
        if (op.tail, op.head) in seen:
            raise CamcadError(f"two operations join {op.tail} to {op.head}", where,
                              "merge them, or add an event between them")
        seen[(op.tail, op.head)] = op
        if not op.min_deg >= 0.0:
            raise CamcadError(f"operation {op.label}: lower bound {op.min_deg:g} deg is negative", where,
                              "give bounds_deg = [min, max] with 0 <= min")
        if op.max_deg < op.min_deg:
            raise CamcadError(f"operation {op.label}: bounds [{op.min_deg:g}, {op.max_deg:g}] deg have min > max",
                              where, "give bounds_deg = [min, max] with min <= max")
    cycle = find_cycle(order, [(op.tail, op.head) for op in ops])
    if cycle:
        raise CamcadError(f"the operations form a cycle: {' -> '.join(cycle)}", where,
                          "an event cannot come before itself; remove or reverse one of these operations")
    successors: dict[str, list[str]] = {e: [] for e in order}
    predecessors: dict[str, list[str]] = {e: [] for e in order}
    for op in ops:
        successors[op.tail].append(op.head)
        predecessors[op.head].append(op.tail)
    if start is None:
        sources = [e for e in order if not predecessors[e]]
        if len(sources) != 1:
            raise CamcadError(f"the network has {len(sources)} first events ({', '.join(sources)})", where,
                              "give start = \"...\" and join the others to it with operations")
        start = sources[0]
    if end is None:
        sinks = [e for e in order if not successors[e]]
        if len(sinks) != 1:
            raise CamcadError(f"the network has {len(sinks)} last events ({', '.join(sinks)})", where,
                              "give end = \"...\" and join the others to it with operations")
        end = sinks[0]
    for name, role in ((start, "start"), (end, "end")):
        if name not in order:
            raise CamcadError(f"{role} event {name!r} is not an event of the network", where,
                              nearest_name(name, order).replace("valid keys", "events"))
    after_start = reachable_from(start, successors)
    before_end = reachable_from(end, predecessors)
    for event in order:
        if event not in after_start:
            raise CamcadError(f"event {event!r} does not follow the first event {start!r}", where,
                              f"add an operation leading to {event!r} from {start!r} or an event after it")
        if event not in before_end:
            raise CamcadError(f"event {event!r} does not lead to the last event {end!r}", where,
                              f"add an operation from {event!r} towards {end!r}")
    if not (math.isfinite(cycle_deg) and cycle_deg > 0):
        raise CamcadError(f"cycle_deg {cycle_deg:g} must be a positive number", where, "give cycle_deg = 360")
    return Network(tuple(order), ops, start, end, float(cycle_deg), float(start_deg))


def reachable_from(origin: str, neighbours: Mapping[str, list[str]]) -> set[str]:
    """The nodes reachable from ``origin`` along ``neighbours`` (``origin`` included)."""
    seen = {origin}
    stack = [origin]
    while stack:
        for nxt in neighbours[stack.pop()]:
            if nxt not in seen:
                seen.add(nxt)
                stack.append(nxt)
    return seen


def find_cycle(nodes: Iterable[str], arcs: Iterable[tuple[str, str]]) -> list[str]:
    """A directed cycle of the graph as [a, b, ..., a], or [] when it is acyclic (iterative DFS).

    Parameters
    ----------
    nodes : iterable of str
        The nodes.
    arcs : iterable of (str, str)
        The arcs (tail, head).

    Returns
    -------
    list of str
        The nodes of one cycle, the first repeated at the end; [] for an acyclic graph (no unit).

    Examples
    --------
    >>> from camcad.cyclogram import find_cycle
    >>> find_cycle("abc", [("a", "b"), ("b", "c"), ("c", "a")]), find_cycle("abc", [("a", "b"), ("b", "c")])
    (['a', 'b', 'c', 'a'], [])
    """
    successors: dict[str, list[str]] = {n: [] for n in nodes}
    for tail, head in arcs:
        successors.setdefault(tail, []).append(head)
        successors.setdefault(head, [])
    state = {n: 0 for n in successors}   # 0 new, 1 on the stack, 2 done
    for root in successors:
        if state[root]:
            continue
        path = [root]
        iterators = [iter(successors[root])]
        state[root] = 1
        while iterators:
            nxt = next(iterators[-1], None)
            if nxt is None:
                state[path.pop()] = 2
                iterators.pop()
            elif state[nxt] == 1:
                return path[path.index(nxt):] + [nxt]
            elif state[nxt] == 0:
                state[nxt] = 1
                path.append(nxt)
                iterators.append(iter(successors[nxt]))
    return []




