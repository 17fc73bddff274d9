"""Conflicting constraints: positive cycles (Bellman-Ford) and longest paths of the constraint graph.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from camcad.cyclogram.constraints import Constraint


def find_conflict(events: Iterable[str], constraints: list[Constraint], tol_deg: float = 1e-9,
                  dense_limit: int = 120) -> list[Constraint]:
    """A positive cycle of the constraint graph with the fewest constraints ([] when there is none).

    Max-plus powers of the weight matrix: D_k[i, j] is the heaviest walk of exactly k arcs from
    i to j; the first k with D_k[v, v] > tol gives a positive closed walk of the least length,
    which is a simple cycle (a shorter positive cycle would have shown up earlier). O(n⁴) time,
    O(n³) memory, so above ``dense_limit`` events Bellman–Ford finds some positive simple cycle
    instead (still irreducible, perhaps not the shortest).

    Parameters
    ----------
    events : iterable of str
        The events (the graph's nodes).
    constraints : list of Constraint
        The difference constraints (deg).
    tol_deg : float
        A cycle heavier than this is positive, deg.
    dense_limit : int
        Above this many events, Bellman–Ford instead (a count).

    Returns
    -------
    list of Constraint
        The constraints of the cycle (deg), in order around it; [] when the constraints can all hold.

    Examples
    --------
    S->Y at least 40 deg cannot fit in a cycle of 50 deg with Y->E at least 15:

    >>> import camcad
    >>> network = camcad.make_network([camcad.Operation("S", "X", 30.0), camcad.Operation("S", "Y", 40.0),
    ...                                camcad.Operation("X", "E", 10.0), camcad.Operation("Y", "E", 15.0)])
    >>> from camcad.cyclogram import constraints_of, find_conflict
    >>> short = camcad.make_network(network.operations, cycle_deg=50.0)
    >>> sorted((c.kind, c.label) for c in find_conflict(short.events, constraints_of(short)))
    [('cycle', 'makespan'), ('min', 'S->Y'), ('min', 'Y->E')]
    """
    names = list(events)
    index = {e: k for k, e in enumerate(names)}
    n = len(names)
    weight = np.full((n, n), -np.inf)
    which = np.full((n, n), -1, dtype=int)
    for k, c in enumerate(constraints):
        i, j = index[c.tail], index[c.head]
        if c.weight > weight[i, j]:
            weight[i, j] = c.weight
            which[i, j] = k
    if n > dense_limit:
        cycle = _bellman_ford_cycle(weight, tol_deg)
    else:
        cycle = _shortest_positive_cycle(weight, tol_deg)
    return [constraints[which[i, j]] for i, j in cycle]


def _shortest_positive_cycle(weight: np.ndarray, tol: float) -> list[tuple[int, int]]:
    n = len(weight)
    walks = weight.copy()
    parents = [np.tile(np.arange(n)[:, None], (1, n))]  # parents[0][i, j]: vertex before j, 1 arc
    for length in range(1, n + 1):
        diagonal = np.diagonal(walks)
        if np.any(diagonal > tol):
            v = int(np.argmax(diagonal))
            arcs = []
            j = v
            for step in range(length - 1, -1, -1):
                i = int(parents[step][v, j])
                arcs.append((i, j))
                j = i
            return arcs[::-1]
        with np.errstate(invalid="ignore"):
            candidates = walks[:, :, None] + weight[None, :, :]   # [i, m, j]
        best = np.argmax(candidates, axis=1)
        walks = np.take_along_axis(candidates, best[:, None, :], axis=1)[:, 0, :]
        parents.append(best)
    return []


def _bellman_ford_cycle(weight: np.ndarray, tol: float) -> list[tuple[int, int]]:
    """Some positive simple cycle by Bellman–Ford (vectorised passes, every vertex a source).

    After each pass the predecessor graph is searched for a cycle (pointer doubling); a cycle
    there always has positive weight (each arc was set by a strict improvement), so the search
    usually stops long before the n-th pass (the "walk to root" idea of Cherkassky & Goldberg,
    Negative-cycle detection algorithms, Math. Programming 85 (1999))."""
    n = len(weight)
    tails, heads = np.nonzero(np.isfinite(weight))
    w = weight[tails, heads]
    dist = np.zeros(n)
    pred = np.full(n, -1)
    for _ in range(n + 1):
        candidate = dist[tails] + w
        improving = np.flatnonzero(candidate > dist[heads] + tol)
        if not len(improving):
            return []
        # the best improving arc into each head
        ranked = improving[np.argsort(-candidate[improving], kind="stable")]
        _, first = np.unique(heads[ranked], return_index=True)
        chosen = ranked[first]
        dist[heads[chosen]] = candidate[chosen]
        pred[heads[chosen]] = tails[chosen]
        cycle = _predecessor_cycle(pred)
        if cycle:
            return cycle
    return []


def _predecessor_cycle(pred: np.ndarray) -> list[tuple[int, int]]:
    """A cycle of the graph v → pred[v] as arcs (tail, head) in the forward direction, or []."""
    n = len(pred)
    jump = np.where(pred < 0, n, pred)
    jump = np.append(jump, n)           # index n: a sink that points to itself
    steps = 1
    while steps < n:                    # after >= n steps every walk that does not end is on a cycle
        jump = jump[jump]
        steps *= 2
    on_cycle = np.flatnonzero(jump[:n] < n)
    if not len(on_cycle):
        return []
    start = int(jump[on_cycle[0]])
    cycle = [start]
    v = int(pred[start])
    while v != start:
        cycle.append(v)
        v = int(pred[v])
    # cycle lists v, pred(v), pred(pred(v)), ...: the arcs run the other way
    return [(cycle[k + 1] if k + 1 < len(cycle) else cycle[0], cycle[k]) for k in range(len(cycle))][::-1]
