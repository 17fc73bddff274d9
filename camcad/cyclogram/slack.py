"""Where the slack of an optimal cyclogram goes: every operation off the critical path keeps a margin.

The least makespan M* fixes the critical operations at their least admissible phase angles; the other
operations can be longer than their least angles without lengthening the cycle. The earliest schedule
(``camcad.cyclogram.optimise``) gives that freedom to whatever arcs come last — often idle waits — and
leaves the working operations at their limits, where their checks (contact stress, pressure angle, rebound)
end with no margin. The rule here:

    with the makespan held at M*, maximise the smallest relative margin (t − [φ])/[φ] of the operations
    that can have one; then, with those that cannot do better held there, the next smallest; and so on
    (a lexicographic max–min, "leximin").

An operation with [φ] > 0 is *critical* when it cannot be longer than [φ] in any schedule of makespan M*:
its largest phase angle t_max = −D(head → tail) equals [φ], D being the heaviest walk of the constraint
graph with the makespan arc end → start of weight −M* (the all-pairs longest paths, Floyd–Warshall in the
max-plus algebra). Every other operation gets a positive margin: the schedules of makespan M* are a convex
set, so the average of schedules each giving one operation a margin gives all of them one, and the first
max–min round already finds a positive smallest margin.

Each round is the linear programme

    maximise z  subject to  p(y) − p(x) ≥ [φ](1 + z)  for the free operations,
                            the other difference constraints, and p(end) − p(start) ≤ M*,

solved exactly by its structure (no LP solver): for a fixed z the constraints are difference constraints,
feasible exactly when their graph has no positive cycle; a cycle C weighs A_C + z·B_C (B_C ≥ 0 the least
angles of the free operations on it), so the largest feasible z is the least ratio −A_C/B_C over the cycles
with B_C > 0. Newton's (Dinkelbach's) iteration finds it: from an upper bound z, take a positive cycle at z
(``find_conflict``), move z to where that cycle weighs zero, repeat until no cycle is positive; z falls
strictly at every step and no cycle returns, so it ends after finitely many cycles at the exact optimum.
The operations that cannot exceed [φ](1 + z*) are then held there and the next round frees the rest.
The final schedule is the earliest one under the raised bounds. Angles are in degrees throughout.

Reference: W. Dinkelbach, "On nonlinear fractional programming", Management Science 13 (1967) 492–498
(the iteration); R. M. Karp, "A characterization of the minimum cycle mean in a digraph", Discrete
Mathematics 23 (1978) 309–311 (ratio cycles); the max–min fairness rule as in D. Bertsekas, R. Gallager,
Data Networks, 2nd ed. (1992), §6.5.2.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field, replace

import numpy as np

from camcad.cyclogram.conflicts import find_conflict
from camcad.cyclogram.constraints import Constraint

#: a phase angle within this (deg, relative to max(1, angle)) of its raised bound cannot be longer
PIN_TOL_DEG = 1e-8
#: rounds of the max–min (each holds at least one operation; a safety bound on top of that)
MAX_ROUNDS = 10_000
#: Newton steps of one round (each step drops at least one cycle for good; a safety bound)
MAX_NEWTON = 10_000

SLACK_RULE = ("leximin: with the makespan held at its least value, maximise the smallest relative margin "
              "(t - least)/least of the operations off the critical path, then the next smallest, and so on")


def heaviest_walks(events: list[str], constraints: Iterable[Constraint]) -> np.ndarray:
    """D[i, j]: the heaviest walk from event i to event j over the constraint arcs tail → head of weight
    ``weight`` (deg; −inf where there is none; 0 on the diagonal). Floyd–Warshall in the max-plus algebra;
    the graph must hold no positive cycle (a feasible set of constraints)."""
    index = {e: k for k, e in enumerate(events)}
    n = len(events)
    dist = np.full((n, n), -np.inf)
    np.fill_diagonal(dist, 0.0)
    for c in constraints:
        i, j = index[c.tail], index[c.head]
        dist[i, j] = max(dist[i, j], c.weight)
    for k in range(n):
        dist = np.maximum(dist, dist[:, k:k + 1] + dist[k:k + 1, :])
    return dist


def largest_phase_angles(events: list[str], constraints: list[Constraint], labels: dict[str, tuple[str, str]]
                         ) -> dict[str, float]:
    """{label: the largest phase angle t = p(head) − p(tail) any schedule meeting ``constraints`` allows}
    (deg; inf when unbounded): t_max = −D(head → tail) (``heaviest_walks``)."""
    walks = heaviest_walks(events, constraints)
    index = {e: k for k, e in enumerate(events)}
    return {label: float(-walks[index[head], index[tail]]) for label, (tail, head) in labels.items()}


@dataclass(frozen=True)
class SlackPlan:
    """How the slack of a least makespan was spread (``spread_slack`` returns it; the example is there).

    Attributes
    ----------
    margins : dict
        {label: relative margin (t − [φ])/[φ], dimensionless} of every operation with [φ] > 0 (0 for the
        critical ones).
    critical : tuple of str
        The labels that cannot be longer than [φ] at this makespan.
    rounds : tuple
        (z, labels held at z) per max–min round, z dimensionless.
    raised : tuple of Constraint
        The constraints with the raised bounds (deg), from which the schedule is the earliest.
    newton_steps : int
        Cycles visited (a count).
    """

    margins: dict[str, float]
    critical: tuple[str, ...]
    rounds: tuple[tuple[float, tuple[str, ...]], ...]
    raised: tuple[Constraint, ...] = field(default_factory=tuple)
    newton_steps: int = 0

    @property
    def smallest_margin(self) -> float | None:
        """The smallest relative margin of the non-critical operations (None when there are none)."""
        values = [self.margins[label] for label in self.margins if label not in self.critical]
        return min(values) if values else None


def spread_slack(events: list[str], constraints: list[Constraint], labels: dict[str, tuple[str, str]],
                 start: str, end: str, makespan_deg: float, *, pin_tol_deg: float = PIN_TOL_DEG) -> SlackPlan:
    """Spread the slack of a least makespan by the max–min rule (module docstring).

    Parameters
    ----------
    events : list of str
        The events.
    constraints : list of Constraint
        Every difference constraint (deg) of the optimal cyclogram, ``kind`` "min" ones carrying the least
        admissible angles; the "cycle" constraint is replaced by p(end) − p(start) ≤ ``makespan_deg``.
    labels : dict
        {operation label: (tail, head)} of the operations.
    start, end : str
        The first and last events.
    makespan_deg : float
        The makespan to hold (deg), normally the least one.
    pin_tol_deg : float
        A phase angle within this (deg, relative to max(1, angle)) of its raised bound counts as held.

    Returns
    -------
    SlackPlan
        The operations' relative margins (dimensionless), the critical ones, the raised bounds (deg).

    Examples
    --------
    At the least makespan of 55 deg the path S-Y-E is critical; S-X-E (30 + 10 deg) has 15 deg to share, and
    max-min gives both of its operations the same relative margin z: 30(1 + z) + 10(1 + z) = 55, z = 3/8.

    >>> import camcad
    >>> network = camcad.make_network([camcad.Operation("S", "X", 30.0), camcad.Operation("S", "Y", 40.0),
    ...                                camcad.Operation("X", "E", 10.0), camcad.Operation("Y", "E", 15.0)])
    >>> from camcad.cyclogram import constraints_of, spread_slack
    >>> labels = {op.label: (op.tail, op.head) for op in network.operations}
    >>> plan = spread_slack(list(network.events), constraints_of(network), labels, "S", "E", 55.0)
    >>> sorted(plan.critical), {k: round(v, 9) for k, v in sorted(plan.margins.items())}
    (['S->Y', 'Y->E'], {'S->X': 0.375, 'S->Y': 0.0, 'X->E': 0.375, 'Y->E': 0.0})
    """
    base = [c for c in constraints if c.kind != "cycle"]
    base.append(Constraint("cycle", "makespan", float(makespan_deg), "least makespan", end, start))
    least = {c.label: c.bound for c in base if c.kind == "min"}
    reach = largest_phase_angles(events, base, labels)
    candidates = [label for label in labels if least.get(label, 0.0) > 0.0]
    critical = tuple(label for label in candidates
                     if reach[label] <= least[label] + pin_tol_deg * max(1.0, abs(least[label])))
    free = [label for label in candidates if label not in critical]
    held: dict[str, float] = {}
    rounds = []
    steps = 0
    for _ in range(MAX_ROUNDS):
        if not free:
            break
        z, cycle, used = _max_min_round(events, base, least, free, held, reach)
        steps += used
        raised = _raised(base, least, free, held, z)
        reach_now = largest_phase_angles(events, raised, {label: labels[label] for label in free})
        pinned = [label for label in free
                  if reach_now[label] <= least[label] * (1.0 + z) + pin_tol_deg * max(1.0, least[label] * (1.0 + z))]
        if not pinned:   # round-off hid the bottleneck: hold the free operations of the last tight cycle
            pinned = [label for label in free if any(c.kind == "min" and c.label == label for c in cycle)] or free
        rounds.append((z, tuple(pinned)))
        for label in pinned:
            held[label] = z
        free = [label for label in free if label not in held]
    raised = _raised(base, least, [], held, 0.0)
    margins = {label: held.get(label, 0.0) for label in candidates}
    return SlackPlan(margins, critical, tuple(rounds), tuple(raised), steps)


def _raised(base: list[Constraint], least: dict[str, float], free: list[str], held: dict[str, float],
            z: float) -> list[Constraint]:
    """The constraints with each free operation's least angle raised to [φ](1 + z), each held one to
    [φ](1 + z_held)."""
    out = []
    free_set = set(free)
    for c in base:
        if c.kind == "min" and c.label in free_set:
            out.append(replace(c, bound=least[c.label] * (1.0 + z), source=f"{c.source}, raised by the slack rule"))
        elif c.kind == "min" and c.label in held and held[c.label] > 0.0:
            out.append(replace(c, bound=least[c.label] * (1.0 + held[c.label]),
                               source=f"{c.source}, raised by the slack rule"))
        else:
            out.append(c)
    return out


def _max_min_round(events, base, least, free, held, reach) -> tuple[float, list[Constraint], int]:
    """The largest z with every free operation at least [φ](1 + z) (module docstring: Newton on cycles);
    the last cycle that bounded it and the number of cycles visited."""
    # an upper bound: no operation can have more than its own largest angle allows
    z = min(reach[label] / least[label] - 1.0 for label in free)
    if not math.isfinite(z):
        z = 1.0
        while not find_conflict(events, _raised(base, least, free, held, z)) and z < 1e12:
            z *= 2.0
    last: list[Constraint] = []
    free_set = set(free)
    for step in range(1, MAX_NEWTON + 1):
        cycle = find_conflict(events, _raised(base, least, free, held, z))
        if not cycle:
            return max(z, 0.0), last, step
        # the cycle's weight at z is A + B z; its free operations' least angles make up B
        slope = sum(least[c.label] for c in cycle if c.kind == "min" and c.label in free_set)
        weight = sum(c.weight for c in cycle)
        if slope <= 0.0:   # a positive cycle without a free operation: the base was infeasible (cannot be)
            raise RuntimeError("the constraints are infeasible at the least makespan")
        z = z - weight / slope
        last = cycle
    raise RuntimeError("the max-min slack did not settle")
