"""Cyclogram of a group of mechanisms: a network of events and operations, optimised by LP.

Model (Podgorny, Maksimchuk, Kirillov, Skeeba, Obrabotka Metallov 20(1) 2018 44–54, seed 000,
after Hendrickson & Janson, Civil Engineering Systems 1 (1984) 195–203):
vertices are events x with times p(x) (deg of the cam shaft); arcs are operations (x, y) whose phase
angle is t(x, y) = p(y) − p(x). Minimise p(N) − p(1) subject to

    [φ(x, y)] ≤ t(x, y) ≤ φ_max(x, y)  for every operation,   p(N) − p(1) ≤ cycle,

where the least admissible phase angle [φ] is the larger of the designer's bound and the limits
from contact stress (σ_max(t) ≤ [σ_H]) and vibration (amplitude(t) ≤ [a]), each found by root
finding on a monotone relation (``least_phase_angle``).

Every constraint is a difference constraint p(head) ≥ p(tail) + weight: a lower bound is an arc
x → y of weight [φ], an upper bound an arc y → x of weight −φ_max, the cycle an arc N → 1 of
weight −cycle. The LP optimum is therefore a longest path from 1 to N in that graph, and the
system is infeasible exactly when the graph has a cycle of positive weight; such a simple cycle is
an irreducible conflicting set (drop any one of its constraints and the rest can be met).

Angles are degrees throughout this module (the cyclogram is an interface quantity).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from camcad.errors import CamcadError
from camcad.params import Field, nearest_name, read_table

# --------------------------------------------------------------------------------------------
# Phase-angle limits: the least t with relation(t) <= limit, by root finding
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class LinearRelation:
    """value(t) = slope · t + intercept, t in deg (e.g. the source's rebound amplitude, mm).

    Podgorny et al. (2018) linearise the first rebound amplitude of the shuttle lift against the
    phase angle of operation (3, 7): a = −0.003 t + 0.208 (a mm, t deg).
    """

    slope: float
    intercept: float

    def __call__(self, t_deg: float) -> float:
        return self.slope * t_deg + self.intercept

    def solve(self, value: float) -> float:
        """The t (deg) where the relation equals ``value`` (closed form)."""
        return (value - self.intercept) / self.slope


#: stand-in for an infinite relation value (an inadmissible phase angle) inside the root finder
INADMISSIBLE = 1e30


@dataclass(frozen=True)
class PhaseLimit:
    """The least admissible phase angle of one operation from one relation.

    ``angle_deg``: least t; ``value`` the relation there; ``limit`` the allowed value; ``binding``
    False when the lower end of the search interval already meets the limit (then angle_deg is
    that end); ``source`` ("contact", "vibration", ...) names the relation; ``evaluations`` counts
    its evaluations. ``note`` says when the angle is set by a jump to inadmissible values (the
    relation is +inf below it, e.g. the profile undercuts) rather than by reaching the limit.
    """

    angle_deg: float
    value: float
    limit: float
    binding: bool
    source: str
    evaluations: int = 0
    note: str = ""


def least_phase_angle(relation: Callable[[float], float], limit: float, lower_deg: float,
                      upper_deg: float, *, source: str = "limit", what: str = "",
                      xtol_deg: float = 1e-10, max_iter: int = 200) -> PhaseLimit:
    """Least phase angle t in [lower, upper] (deg) with relation(t) ≤ limit, for a non-increasing
    relation (a stress or an amplitude that falls as the operation gets longer).

    Bracket check: if relation(lower) ≤ limit the lower end is returned (not binding); if
    relation(upper) > limit no phase angle in the interval is admissible and a CamcadError says so.
    Otherwise scipy's brentq finds the crossing relation(t) = limit to ``xtol_deg`` (absolute, deg),
    in a handful of evaluations — no scan. For a monotone relation the crossing is the least
    admissible t; for a non-monotone one it is *a* crossing inside the bracket.

    The relation may return +inf for an inadmissible t (e.g. the profile undercuts); NaN is an error.
    Units: t deg; relation and limit in the same unit (MPa, mm, ...).
    """
    from scipy.optimize import brentq

    count = 0

    def excess(t: float) -> float:
        nonlocal count
        count += 1
        value = float(relation(t))
        if math.isnan(value) or value == -math.inf:
            raise CamcadError(f"the {source} relation is not a number at {t:g} deg", what or source,
                              "check the data of that operation")
        if value == math.inf:
            # inadmissible outright (e.g. the profile undercuts): a large finite excess keeps
            # Brent's method bracketing; it falls back to bisection near such a step
            return INADMISSIBLE * (1.0 + abs(limit))
        return value - limit

    label = f"{what}: " if what else ""
    at_lower = excess(lower_deg)
    if at_lower <= 0.0:
        return PhaseLimit(lower_deg, at_lower + limit, limit, False, source, count)
    at_upper = excess(upper_deg) if upper_deg > lower_deg else at_lower
    if at_upper > 0.0:
        reached = "an inadmissible value" if at_upper >= INADMISSIBLE else f"{at_upper + limit:.6g}"
        raise CamcadError(
            f"{label}even the longest phase angle {upper_deg:g} deg gives {source} {reached} "
            f"> the limit {limit:g}", what or source,
            "raise the operation's upper bound, or change the law, materials or loads")
    root = brentq(excess, lower_deg, upper_deg, xtol=xtol_deg, maxiter=max_iter)
    # brentq returns a point within xtol of the sign change, on either side; at a jump to an
    # inadmissible value (e.g. an undercut) step to the admissible side
    step = xtol_deg
    while excess(root) >= INADMISSIBLE and root < upper_deg:
        root = min(root + step, upper_deg)
        step *= 2.0
    value = float(relation(root))
    note = ""
    if value < limit - 1e-6 * abs(limit):
        note = (f"set by an inadmissible range below {root:.6g} deg (e.g. an undercut), where {source} "
                f"is {value:.6g}, under the limit")
    return PhaseLimit(float(root), value, limit, True, source, count + 1, note)


# --------------------------------------------------------------------------------------------
# The network
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Operation:
    """One operation (arc) of the cyclogram, from event ``tail`` to event ``head``.

    ``min_deg``/``max_deg``: the designer's bounds on its phase angle (deg; max may be inf).
    ``mechanism``: the mechanism doing it (a Gantt row), ``phase``/``occurrence``: which phase of
    that mechanism's law it is (e.g. the first "rise"), for feeding the optimal angle back.
    ``amplitude``/``amplitude_limit_mm``: a vibration relation amplitude(t) (mm, t deg) and its limit.
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
    """Events, operations, the first and last event, the cycle (deg) and where the first event sits
    on the machine's cycle (``start_deg``). Build it with ``make_network`` (validates it)."""

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
    """A validated Network. Raises CamcadError for: an operation naming an unknown event, an
    operation from an event to itself, two operations between the same events, bounds with
    min > max, a cycle of operations (named: "a -> b -> c -> a"), no unique first/last event,
    and an event on no path from the first to the last."""
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
    successors = {e: [] for e in order}
    predecessors = {e: [] for e in order}
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
    after_start = _reachable(start, successors)
    before_end = _reachable(end, predecessors)
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


def _reachable(origin: str, neighbours: Mapping[str, list[str]]) -> set[str]:
    seen = {origin}
    stack = [origin]
    while stack:
        for nxt in neighbours[stack.pop()]:
            if nxt not in seen:
                seen.add(nxt)
                stack.append(nxt)
    return seen


def find_cycle(nodes: Iterable[str], arcs: Iterable[tuple[str, str]]) -> list[str]:
    """A directed cycle of the graph as [a, b, ..., a], or [] when it is acyclic (iterative DFS)."""
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


# --------------------------------------------------------------------------------------------
# Constraints and the LP
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Constraint:
    """One difference constraint p(head) ≥ p(tail) + weight (deg).

    kind "min": t(label) ≥ bound; "max": t(label) ≤ bound; "cycle": makespan ≤ bound.
    ``source`` says where the bound comes from ("bounds_deg", "contact", "vibration", "cycle_deg").
    """

    kind: str
    label: str
    bound: float
    source: str
    tail: str
    head: str

    @property
    def weight(self) -> float:
        return self.bound if self.kind == "min" else -self.bound

    def describe(self) -> str:
        if self.kind == "min":
            return f"t({self.label}) >= {self.bound:.6g} deg ({self.source})"
        if self.kind == "max":
            return f"t({self.label}) <= {self.bound:.6g} deg ({self.source})"
        return f"makespan p({self.tail}) - p({self.head}) <= {self.bound:.6g} deg ({self.source})"


def effective_lower_bounds(network: Network, limits: Mapping[str, Iterable[PhaseLimit]] | None = None
                           ) -> dict[str, tuple[float, str]]:
    """{label: (least admissible phase angle deg, its source)}: the largest of the operation's own
    lower bound and its phase limits (a tie keeps the designer's bound as the source)."""
    limits = limits or {}
    unknown = [label for label in limits if label not in {op.label for op in network.operations}]
    if unknown:
        raise CamcadError(f"phase limit for unknown operation {unknown[0]!r}", "cyclogram",
                          nearest_name(unknown[0], [op.label for op in network.operations])
                          .replace("valid keys", "operations"))
    result = {}
    for op in network.operations:
        bound, source = float(op.min_deg), "bounds_deg"
        for limit in limits.get(op.label, ()):
            if limit.angle_deg > bound:
                bound, source = limit.angle_deg, limit.source
        result[op.label] = (bound, source)
    return result


def constraints_of(network: Network, limits: Mapping[str, Iterable[PhaseLimit]] | None = None
                   ) -> list[Constraint]:
    """Every difference constraint of the network: lower and upper bounds, and the cycle."""
    lower = effective_lower_bounds(network, limits)
    constraints = []
    for op in network.operations:
        bound, source = lower[op.label]
        constraints.append(Constraint("min", op.label, float(bound), source, op.tail, op.head))
        if math.isfinite(op.max_deg):
            constraints.append(Constraint("max", op.label, float(op.max_deg), "bounds_deg", op.head, op.tail))
    constraints.append(Constraint("cycle", "makespan", float(network.cycle_deg), "cycle_deg",
                                  network.end, network.start))
    return constraints


@dataclass(frozen=True)
class CyclogramResult:
    """The optimal cyclogram, or why there is none.

    Times in deg on the machine's cycle (the first event at ``network.start_deg``). ``event_times_deg``
    is the earliest schedule with the least makespan (unique); ``phase_angles_deg`` t(x, y) = p(y) − p(x);
    ``critical_path`` events along one longest (zero-slack) path from first to last event, which
    may step back along an upper bound; ``active`` the bounds on some longest path (tightening
    one lengthens the makespan). When infeasible: ``conflict`` a smallest set of constraints that
    cannot hold together (a positive cycle) and ``explanation`` in words.
    """

    network: Network
    feasible: bool
    makespan_deg: float | None = None
    event_times_deg: dict[str, float] = field(default_factory=dict)
    phase_angles_deg: dict[str, float] = field(default_factory=dict)
    critical_path: tuple[str, ...] = ()
    active: tuple[Constraint, ...] = ()
    lower_bounds_deg: dict[str, tuple[float, str]] = field(default_factory=dict)
    conflict: tuple[Constraint, ...] = ()
    explanation: str = ""
    cycle_slack_deg: float | None = None
    solver_message: str = ""

    @property
    def active_bounds(self) -> list[str]:
        """Labels "x->y" of operations with an active bound (SPEC.md ``active_bounds``)."""
        labels = []
        for c in self.active:
            if c.label not in labels:
                labels.append(c.label)
        return labels

    def report(self) -> dict:
        """The SPEC.md ``cyclogram`` keys and more."""
        out: dict[str, Any] = {
            "passed": self.feasible,
            "feasible": self.feasible,
            "makespan_deg": self.makespan_deg,
            "event_times_deg": dict(self.event_times_deg),
            "phase_angles_deg": dict(self.phase_angles_deg),
            "critical_path": list(self.critical_path),
            "active_bounds": self.active_bounds,
            "active": [{"operation": c.label, "kind": c.kind, "bound_deg": c.bound, "source": c.source}
                       for c in self.active],
            "lower_bounds_deg": {k: {"deg": v, "source": s} for k, (v, s) in self.lower_bounds_deg.items()},
            "cycle_deg": self.network.cycle_deg,
            "cycle_slack_deg": self.cycle_slack_deg,
        }
        if not self.feasible:
            out["conflict"] = [c.describe() for c in self.conflict]
            out["explanation"] = self.explanation
        return out

    def raise_if_infeasible(self, where: str = "[cyclogram]") -> "CyclogramResult":
        if not self.feasible:
            raise CamcadError(self.explanation, where, _conflict_fix(self.conflict))
        return self


def _conflict_fix(conflict: tuple[Constraint, ...]) -> str:
    if not conflict:
        return "check the bounds of the operations"
    excess = sum(c.weight for c in conflict)
    return f"relax one of these constraints by at least {excess:.6g} deg"


def optimise(network: Network, limits: Mapping[str, Iterable[PhaseLimit]] | None = None, *,
             strict: bool = True, tight_tol_deg: float = 1e-6, lp_tol: float = 1e-10,
             where: str = "[cyclogram]") -> CyclogramResult:
    """Least makespan p(end) − p(start) by linear programming (scipy linprog, HiGHS).

    Stage 1 minimises p(end) with p(start) = start_deg under all difference constraints; stage 2
    minimises Σ p with the makespan held, which picks the earliest schedule (the least element of
    the feasible set, unique) so that the event times do not depend on the solver's path.
    A constraint is tight when its slack ≤ ``tight_tol_deg``; the active bounds are the tight ones
    on a start→end path of tight constraints (a longest path). ``lp_tol`` is HiGHS's primal and
    dual feasibility tolerance (its accuracy knob; deg): the times are exact to about that times
    the number of operations on a path (HiGHS's own default, 1e-7, would round away bounds that small).

    ``limits`` adds phase limits ({label: [PhaseLimit, ...]}) to the operations' lower bounds.
    Infeasible: ``strict`` raises CamcadError naming a smallest conflicting set; otherwise the
    result has ``feasible`` False, ``conflict`` and ``explanation``.
    """
    from scipy.optimize import linprog
    from scipy.sparse import csr_matrix

    constraints = constraints_of(network, limits)
    lower = effective_lower_bounds(network, limits)
    index = {event: k for k, event in enumerate(network.events)}
    n = len(network.events)
    m = len(constraints)
    # p(tail) − p(head) ≤ −weight
    rows = np.repeat(np.arange(m), 2)
    cols = np.array([[index[c.tail], index[c.head]] for c in constraints]).ravel()
    data = np.tile([1.0, -1.0], m)
    a_ub = csr_matrix((data, (rows, cols)), shape=(m, n))
    b_ub = np.array([-c.weight for c in constraints])
    bounds = [(None, None)] * n
    bounds[index[network.start]] = (network.start_deg, network.start_deg)
    objective = np.zeros(n)
    objective[index[network.end]] = 1.0
    options = {"primal_feasibility_tolerance": lp_tol, "dual_feasibility_tolerance": lp_tol}
    first = linprog(objective, A_ub=a_ub, b_ub=b_ub, bounds=bounds, method="highs", options=options)
    if first.status == 2:
        conflict = find_conflict(network.events, constraints)
        # read the cycle from the first event when it passes there
        lead = next((k for k, c in enumerate(conflict) if c.tail == network.start), 0)
        conflict = conflict[lead:] + conflict[:lead]
        explanation = _explain(conflict, first.message)
        result = CyclogramResult(network, False, lower_bounds_deg=lower, conflict=tuple(conflict),
                                 explanation=explanation, solver_message=first.message)
        if strict:
            result.raise_if_infeasible(where)
        return result
    if first.status != 0:
        raise CamcadError(f"the LP solver failed: {first.message}", where,
                          "check the bounds for extreme values; report it if they are sensible")
    makespan = float(first.x[index[network.end]]) - network.start_deg
    # stage 2: hold the makespan (with the solver's tolerance) and take the earliest times
    hold = network.start_deg + makespan + 10.0 * lp_tol * max(1.0, abs(makespan))
    bounds[index[network.end]] = (None, hold)
    second = linprog(np.ones(n), A_ub=a_ub, b_ub=b_ub, bounds=bounds, method="highs", options=options)
    if second.status != 0:
        raise CamcadError(f"the LP solver failed on the earliest schedule: {second.message}", where,
                          "report it with the scene")
    times = {event: float(second.x[index[event]]) for event in network.events}
    phase_angles = {op.label: times[op.head] - times[op.tail] for op in network.operations}
    slack = [times[c.head] - times[c.tail] - c.weight for c in constraints]
    tight = [c for c, gap in zip(constraints, slack) if gap <= tight_tol_deg and c.kind != "cycle"]
    active, path = _critical(network, tight)
    cycle_slack = network.cycle_deg - makespan
    return CyclogramResult(network, True, makespan, times, phase_angles, tuple(path), tuple(active),
                           lower, cycle_slack_deg=cycle_slack, solver_message=second.message)


def _critical(network: Network, tight: list[Constraint]) -> tuple[list[Constraint], list[str]]:
    """Tight constraints on a start→end path of tight constraints, and one such path of events."""
    forward: dict[str, list[Constraint]] = {e: [] for e in network.events}
    backward: dict[str, list[Constraint]] = {e: [] for e in network.events}
    for c in tight:
        forward[c.tail].append(c)
        backward[c.head].append(c)
    from_start = _reachable(network.start, {e: [c.head for c in forward[e]] for e in network.events})
    to_end = _reachable(network.end, {e: [c.tail for c in backward[e]] for e in network.events})
    active = [c for c in tight if c.tail in from_start and c.head in to_end]
    active_set = set(active)
    # one path: breadth-first over active constraints, in operation order
    previous: dict[str, Constraint | None] = {network.start: None}
    queue = [network.start]
    for event in queue:
        for c in forward[event]:
            if c in active_set and c.head not in previous:
                previous[c.head] = c
                queue.append(c.head)
    path = [network.end]
    while previous.get(path[-1]) is not None:
        path.append(previous[path[-1]].tail)
    return active, path[::-1]


def _explain(conflict: list[Constraint], solver_message: str) -> str:
    if not conflict:
        return f"the cyclogram is infeasible ({solver_message})"
    excess = sum(c.weight for c in conflict)
    return ("the cyclogram is infeasible: " + "; ".join(c.describe() for c in conflict)
            + f" cannot all hold (together they overrun by {excess:.6g} deg)")


def find_conflict(events: Iterable[str], constraints: list[Constraint], tol_deg: float = 1e-9,
                  dense_limit: int = 120) -> list[Constraint]:
    """A positive cycle of the constraint graph with the fewest constraints ([] when there is none).

    Max-plus powers of the weight matrix: D_k[i, j] is the heaviest walk of exactly k arcs from
    i to j; the first k with D_k[v, v] > tol gives a positive closed walk of the least length,
    which is a simple cycle (a shorter positive cycle would have shown up earlier). O(n⁴) time,
    O(n³) memory, so above ``dense_limit`` events Bellman–Ford finds some positive simple cycle
    instead (still irreducible, perhaps not the shortest).
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


def longest_path_times(network: Network, limits: Mapping[str, Iterable[PhaseLimit]] | None = None
                       ) -> dict[str, float]:
    """Earliest event times (deg) by Bellman–Ford longest paths from the first event, ignoring the
    cycle constraint: the second method the LP is checked against. Raises CamcadError on a positive
    cycle (infeasible bounds)."""
    constraints = [c for c in constraints_of(network, limits) if c.kind != "cycle"]
    times = {e: -math.inf for e in network.events}
    times[network.start] = network.start_deg
    for _ in range(len(network.events)):
        changed = False
        for c in constraints:
            if times[c.tail] + c.weight > times[c.head] + 1e-12:
                times[c.head] = times[c.tail] + c.weight
                changed = True
        if not changed:
            return times
    raise CamcadError("the bounds contradict each other (a positive cycle)", "cyclogram",
                      "see the conflict reported by optimise()")


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
    phases = [list(p) for p in phases_deg]
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
            return [tuple(p) for p in phases if p[1] > p[0]]  # type: ignore[misc]
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
    for (s0, e0, k0), (s1, e1, k1) in zip(motions[:-1], motions[1:]):
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


# --------------------------------------------------------------------------------------------
# The scene's [cyclogram] section
# --------------------------------------------------------------------------------------------

CYCLOGRAM_FIELDS: list[Field] = [
    Field("operations", "list", required=True,
          help="([[cyclogram.operations]] tables with from, to, bounds_deg)"),
    Field("events", "list", help="(event names in order; optional)"),
    Field("start", "str", help="(first event; default: the only event without predecessors)"),
    Field("end", "str", help="(last event; default: the only event without successors)"),
    Field("cycle_deg", unit="deg", default=360.0, positive=True,
          help="(the group must fit in this angle of the cycle)"),
    Field("start_deg", unit="deg", default=0.0, minimum=0.0, maximum=360.0,
          help="(where the first event sits on the machine's cycle)"),
    Field("name", "str", default="", help="(name of the group)"),
]

OPERATION_FIELDS: list[Field] = [
    Field("from", "str", required=True, help="(the event the operation starts at)"),
    Field("to", "str", required=True, help="(the event it ends at)"),
    Field("bounds_deg", "list", unit="deg", required=True,
          help="([min, max] phase angle in deg; max may be inf)"),
    Field("name", "str", default=""),
    Field("mechanism", "str", help="(the mechanism doing the operation)"),
    Field("phase", "str", choices=("rise", "return", "dwell"),
          help="(which phase of the mechanism's law the operation is)"),
    Field("occurrence", "int", default=1, minimum=1, help="(1 for the first such phase, 2, ...)"),
    Field("amplitude_limit_mm", unit="mm", positive=True,
          help="(allowed vibration amplitude of the working member)"),
    Field("amplitude_slope_mm_per_deg", unit="mm/deg",
          help="(amplitude = slope * t + intercept, e.g. -0.003)"),
    Field("amplitude_intercept_mm", unit="mm", help="(e.g. 0.208)"),
]


def _event_name(value: Any, key: str, where: str) -> str:
    if isinstance(value, bool) or not isinstance(value, (str, int)):
        raise CamcadError(f"'{key}' must be an event name or number, got {value!r}", where,
                          f'write {key} = "3" or {key} = 3')
    return str(value)


def parse_cyclogram(table: Any, where: str, mechanisms: Iterable[str] | None = None) -> Network:
    """A scene's ``[cyclogram]`` section → validated Network.

    Keys: ``operations`` (array of tables: ``from``, ``to``, ``bounds_deg = [min, max]`` deg,
    optional ``name``, ``mechanism``, ``phase``, ``occurrence``, and a vibration limit
    ``amplitude_limit_mm`` with the linear relation ``amplitude_slope_mm_per_deg``,
    ``amplitude_intercept_mm``), optional ``events``, ``start``, ``end``, ``cycle_deg`` (360),
    ``start_deg`` (0), ``name``. Event names may be numbers. ``mechanisms``: the scene's mechanism
    names, to check the operations' ``mechanism``. Errors are one-line CamcadErrors naming ``where``.
    """
    if isinstance(table, dict):
        table = dict(table)
        for key in ("start", "end"):
            if key in table:
                table[key] = _event_name(table[key], key, where)
        if isinstance(table.get("events"), list):
            table["events"] = [_event_name(e, "events", where) for e in table["events"]]
    values = read_table(table, CYCLOGRAM_FIELDS, where)
    known = list(mechanisms) if mechanisms is not None else None
    operations = []
    for k, raw in enumerate(values["operations"], start=1):
        here = f"{where} operations[{k}]"
        if isinstance(raw, dict):
            raw = dict(raw)
            for key in ("from", "to"):
                if key in raw:
                    raw[key] = _event_name(raw[key], key, here)
        op = read_table(raw, OPERATION_FIELDS, here)
        here = f"{where} operation {op['from']}->{op['to']}"
        bounds = op["bounds_deg"]
        if (len(bounds) != 2 or any(isinstance(b, bool) or not isinstance(b, (int, float)) for b in bounds)
                or math.isnan(bounds[0]) or math.isnan(bounds[1])):
            raise CamcadError(f"'bounds_deg' must be [min, max] in deg, got {bounds!r}", here,
                              "write bounds_deg = [20.0, 60.0] (max may be inf)")
        low, high = float(bounds[0]), float(bounds[1])
        if not math.isfinite(low) or low < 0:
            raise CamcadError(f"lower bound {low:g} deg must be a finite number >= 0", here,
                              "write bounds_deg = [min, max] with 0 <= min")
        if high < low:
            raise CamcadError(f"bounds_deg [{low:g}, {high:g}] has min > max", here, "swap or correct them")
        if known is not None and op["mechanism"] is not None and op["mechanism"] not in known:
            fix = (nearest_name(op["mechanism"], known).replace("valid keys", "mechanisms") if known
                   else f"add [mechanisms.{op['mechanism']}] to the scene, or drop 'mechanism'")
            raise CamcadError(f"unknown mechanism {op['mechanism']!r}", here, fix)
        if op["phase"] is not None and op["mechanism"] is None:
            raise CamcadError("'phase' needs a 'mechanism'", here, "name the mechanism whose law it is")
        relation = None
        vib = (op["amplitude_limit_mm"], op["amplitude_slope_mm_per_deg"], op["amplitude_intercept_mm"])
        if any(v is not None for v in vib):
            if any(v is None for v in vib):
                raise CamcadError("a vibration limit needs amplitude_limit_mm, amplitude_slope_mm_per_deg "
                                  "and amplitude_intercept_mm", here, "give all three, or none")
            if not vib[1] < 0:
                raise CamcadError(f"amplitude_slope_mm_per_deg {vib[1]:g} must be negative (the amplitude "
                                  "falls as the operation gets longer)", here, "give a negative slope")
            relation = LinearRelation(vib[1], vib[2])
        operations.append(Operation(op["from"], op["to"], low, high, op["mechanism"], op["name"],
                                    op["phase"], op["occurrence"], relation, op["amplitude_limit_mm"]))
    return make_network(operations, values["events"], values["start"], values["end"],
                        values["cycle_deg"], values["start_deg"], where)


def vibration_limits(network: Network, xtol_deg: float = 1e-10) -> dict[str, list[PhaseLimit]]:
    """{label: [PhaseLimit]} for every operation with a vibration relation: the least t in
    [min_deg, max_deg (or cycle_deg)] with amplitude(t) ≤ amplitude_limit_mm (``least_phase_angle``)."""
    limits: dict[str, list[PhaseLimit]] = {}
    for op in network.operations:
        if op.amplitude is None or op.amplitude_limit_mm is None:
            continue
        upper = op.max_deg if math.isfinite(op.max_deg) else network.cycle_deg
        limits.setdefault(op.label, []).append(least_phase_angle(
            op.amplitude, op.amplitude_limit_mm, op.min_deg, upper, source="vibration",
            what=f"operation {op.label}", xtol_deg=xtol_deg))
    return limits
