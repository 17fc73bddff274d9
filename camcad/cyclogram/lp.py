"""The cyclogram optimisation: the least makespan over difference constraints, by longest paths.

Every constraint of a cyclogram is a difference constraint p(head) − p(tail) ≥ weight (lower bounds,
upper bounds as backward arcs, the cycle). The least makespan and the earliest schedule are then the
longest-path distances from the first event (Bellman–Ford), and the bounds are infeasible exactly when
the constraint graph has a positive cycle. This is the linear programme of the source (minimise
p(N) − p(1)) solved exactly by its combinatorial structure, without scipy.optimize (0.6 s of CPU to
import, which a scene run otherwise does not need); tests/cyclogram/test_cyclogram.py checks it against scipy's
LP (HiGHS) and against a dynamic programme over a topological order.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from camcad.cyclogram.conflicts import find_conflict
from camcad.cyclogram.constraints import Constraint, constraints_of, effective_lower_bounds
from camcad.cyclogram.limits import PhaseLimit
from camcad.cyclogram.network import Network, reachable_from
from camcad.cyclogram.slack import SLACK_RULE, spread_slack
from camcad.errors import CamcadError

#: how the slack of the least makespan is placed: "earliest" (every event as early as it can be) or
#: "leximin" (the operations off the critical path keep the largest smallest relative margin:
#: ``camcad.cyclogram.slack``)
SCHEDULES = ("earliest", "leximin")

# --------------------------------------------------------------------------------------------
# Constraints and the LP
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class CyclogramResult:
    """The optimal cyclogram, or why there is none.

    Times in deg on the machine's cycle (the first event at ``network.start_deg``). ``camcad.optimise`` returns
    it; the example is there and at ``effective_lower_bounds``.

    Attributes
    ----------
    network : Network
        The network solved.
    feasible : bool
        Whether every constraint can hold.
    makespan_deg : float, optional
        The least makespan, deg (None when infeasible).
    event_times_deg : dict
        {event: time, deg}: the earliest schedule with the least makespan (unique), or the leximin one.
    phase_angles_deg : dict
        {label: t(x, y) = p(y) − p(x), deg}.
    critical_path : tuple of str
        Events along one longest (zero-slack) path from first to last event, which may step back along an
        upper bound.
    active : tuple of Constraint
        The bounds on some longest path (tightening one lengthens the makespan).
    lower_bounds_deg : dict
        {label: (least admissible angle deg, its source)}.
    conflict : tuple of Constraint
        When infeasible: a smallest set of constraints that cannot hold together (a positive cycle).
    explanation : str
        The conflict in words.
    cycle_slack_deg : float, optional
        The cycle minus the makespan, deg.
    solver_message : str
        What the solver said.
    schedule : str
        "earliest" or "leximin".
    margins : dict
        {label: relative margin (t − [φ])/[φ], dimensionless} under the leximin schedule.
    critical_operations : tuple of str
        The operations held at their least angle.
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
    schedule: str = "earliest"
    margins: dict[str, float] = field(default_factory=dict)
    critical_operations: tuple[str, ...] = ()

    @property
    def active_bounds(self) -> list[str]:
        """Labels "x->y" of operations with an active bound (docs/INTERFACE.md ``active_bounds``)."""
        labels = []
        for c in self.active:
            if c.label not in labels:
                labels.append(c.label)
        return labels

    def report(self) -> dict:
        """The docs/INTERFACE.md ``cyclogram`` keys and more."""
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
            "schedule": self.schedule,
        }
        if self.schedule == "leximin" and self.feasible:
            out["slack_rule"] = SLACK_RULE
            out["critical_operations"] = list(self.critical_operations)
            out["phase_margins"] = {label: {"relative": r, "deg": self.phase_angles_deg[label]
                                            - self.lower_bounds_deg[label][0]} for label, r in self.margins.items()}
            others = [r for label, r in self.margins.items() if label not in self.critical_operations]
            out["smallest_margin"] = min(others) if others else None
        if not self.feasible:
            out["conflict"] = [c.describe() for c in self.conflict]
            out["explanation"] = self.explanation
        return out

    def raise_if_infeasible(self, where: str = "[cyclogram]") -> CyclogramResult:
        if not self.feasible:
            raise CamcadError(self.explanation, where, _conflict_fix(self.conflict))
        return self


def _conflict_fix(conflict: tuple[Constraint, ...]) -> str:
    if not conflict:
        return "check the bounds of the operations"
    excess = sum(c.weight for c in conflict)
    return f"relax one of these constraints by at least {excess:.6g} deg"


def optimise(network: Network, limits: Mapping[str, Iterable[PhaseLimit]] | None = None, *,
             strict: bool = True, tight_tol_deg: float = 1e-6,
             where: str = "[cyclogram]", schedule: str = "earliest",
             extra: Iterable[Constraint] = ()) -> CyclogramResult:
    """The cyclogram of least makespan p(end) − p(start) under the difference constraints.

    The linear programme — minimise p(end) with p(start) = start_deg under p(head) − p(tail) ≥ min,
    ≤ max, then the earliest schedule with that makespan (the least element of the feasible set,
    unique) — is solved exactly by its structure: the earliest times are the longest-path distances
    from the first event over the constraint arcs (Bellman–Ford), and there is no schedule exactly when
    the arcs hold a positive cycle. A constraint is tight when its slack ≤ ``tight_tol_deg``; the active
    bounds are the tight ones on a start→end path of tight constraints (a longest path).

    Parameters
    ----------
    network : Network
        The network (``make_network``), bounds in deg.
    limits : mapping of str to iterable of PhaseLimit, optional
        Phase limits ({"x->y": [PhaseLimit, ...]}, angles in deg) added to the operations' lower
        bounds (from contact stress, vibration, impact).
    strict : bool
        Raise CamcadError when infeasible; otherwise return a result with ``feasible`` False.
    tight_tol_deg : float
        Slack below which a constraint counts as tight, deg.
    where : str
        What to name in an error message.
    schedule : {"earliest", "leximin"}
        Where the slack goes once the makespan is least: every event as early as it can be, or the
        operations off the critical path with the largest smallest relative margin (t − [φ])/[φ], then the
        next smallest (``camcad.cyclogram.slack``); the makespan is the same.
    extra : iterable of Constraint
        Further difference constraints (deg), e.g. a group's own cycle inside a machine.

    Returns
    -------
    CyclogramResult
        ``makespan_deg``, ``event_times_deg`` ({event: deg}), ``phase_angles_deg`` ({"x->y": deg}),
        ``critical_path``, ``active_bounds``, ``feasible``; when infeasible, ``conflict`` (a smallest
        set of constraints that cannot hold together) and ``explanation``; ``report()`` gives the
        docs/INTERFACE.md ``cyclogram`` keys.

    Raises
    ------
    CamcadError
        Infeasible with ``strict``: names a smallest conflicting set and by how much it overruns.

    References
    ----------
    Podgorny et al., Obrabotka Metallov 20(1) (2018) 44–54: minimise p(N) − p(1) subject to
    p(x) ≤ p(y) − t(x, y), t(x, y) ≥ [φ(x, y)].
    T. H. Cormen et al., Introduction to Algorithms, 3rd ed. (2009), §24.4 (difference constraints and
    shortest paths; longest paths are the same with the signs turned).

    Examples
    --------
    a→b takes 30–90°, b→c 45–60°, and a→c at least 100°: by hand the makespan is max(30 + 45, 100) =
    100°, set by a→c alone, and the earliest b is 100 − 60 = 40°:

    >>> import camcad
    >>> network = camcad.make_network([camcad.Operation("a", "b", 30.0, 90.0), camcad.Operation("b", "c", 45.0, 60.0),
    ...                                camcad.Operation("a", "c", 100.0)])
    >>> result = camcad.optimise(network)
    >>> result.makespan_deg, result.event_times_deg, result.active_bounds
    (100.0, {'a': 0.0, 'b': 40.0, 'c': 100.0}, ['a->c'])

    Bounds that cannot hold together:

    >>> tight = camcad.make_network([camcad.Operation("a", "b", 30.0, 40.0), camcad.Operation("b", "c", 45.0, 50.0),
    ...                              camcad.Operation("a", "c", 0.0, 60.0)])
    >>> camcad.optimise(tight, strict=False).explanation
    'the cyclogram is infeasible: t(a->b) >= 30 deg (bounds_deg); t(b->c) >= 45 deg (bounds_deg); t(a->c) <= 60 deg (bounds_deg) cannot all hold (together they overrun by 15 deg)'
    """  # noqa: E501 - a doctest's expected output is one line
    if schedule not in SCHEDULES:
        raise CamcadError(f"unknown schedule {schedule!r}", where, f"choose one of {', '.join(SCHEDULES)}")
    constraints = constraints_of(network, limits) + list(extra)
    lower = effective_lower_bounds(network, limits)
    times, settled = _longest_paths(network, constraints)
    # a cycle that keeps lengthening the paths is a contradiction when it overruns by more than
    # find_conflict's tolerance (1e-9 deg); below that the schedule holds to round-off
    conflict = [] if settled else find_conflict(network.events, constraints)
    if conflict:
        # read the cycle from the first event when it passes there
        lead = next((k for k, c in enumerate(conflict) if c.tail == network.start), 0)
        conflict = conflict[lead:] + conflict[:lead]
        explanation = _explain(conflict, "a positive cycle of the constraints")
        result = CyclogramResult(network, False, lower_bounds_deg=lower, conflict=tuple(conflict),
                                 explanation=explanation, solver_message="infeasible (a positive cycle)")
        if strict:
            result.raise_if_infeasible(where)
        return result
    makespan = times[network.end] - network.start_deg
    margins: dict[str, float] = {}
    critical_operations: tuple[str, ...] = ()
    if schedule == "leximin":
        labels = {op.label: (op.tail, op.head) for op in network.operations}
        plan = spread_slack(list(network.events), constraints, labels, network.start, network.end, makespan)
        spread, settled = _longest_paths(network, list(plan.raised))
        if settled and abs(spread[network.end] - times[network.end]) <= 1e-9 * max(1.0, abs(makespan)):
            times = spread
            margins, critical_operations = plan.margins, plan.critical
        else:   # cannot happen for a feasible plan; the earliest schedule stays
            schedule = "earliest"
    phase_angles = {op.label: times[op.head] - times[op.tail] for op in network.operations}
    active, path = critical_of(network, constraints, times, tight_tol_deg)
    cycle_slack = network.cycle_deg - makespan
    return CyclogramResult(network, True, makespan, times, phase_angles, tuple(path), tuple(active),
                           lower, cycle_slack_deg=cycle_slack, solver_message="optimal (longest paths)",
                           schedule=schedule, margins=margins, critical_operations=critical_operations)


def longest_paths(network: Network, constraints: list[Constraint]) -> tuple[dict[str, float], bool]:
    """The earliest event times (deg) under ``constraints`` — the longest-path distances from the first event,
    held at ``network.start_deg`` — and whether they settled (False: a positive cycle, no schedule)."""
    return _longest_paths(network, constraints)


def critical_of(network: Network, constraints: list[Constraint], times: Mapping[str, float],
                tight_tol_deg: float = 1e-6) -> tuple[list[Constraint], list[str]]:
    """The active constraints (tight to ``tight_tol_deg`` deg, on a first-to-last path of tight constraints)
    of the schedule ``times`` (deg), and one such path of events."""
    slack = [times[c.head] - times[c.tail] - c.weight for c in constraints]
    tight = [c for c, gap in zip(constraints, slack) if gap <= tight_tol_deg and c.kind != "cycle"]
    return _critical(network, tight)


def _longest_paths(network: Network, constraints: list[Constraint], tol: float = 1e-12
                   ) -> tuple[dict[str, float], bool]:
    """Longest-path distances from the first event (held at ``start_deg``) over the constraint arcs
    tail → head of length weight (Bellman–Ford: at most one pass per event), and whether they settled;
    they do not when a positive cycle keeps lengthening them. An arc is relaxed only when it lengthens
    a distance by more than ``tol`` relative, so a cycle that closes to round-off (an upper bound equal
    to a sum of lower bounds) is not taken for a positive one."""
    rank = _topological_rank(network)
    # the operations' arcs in topological order settle in one pass; the backward arcs (upper bounds,
    # the cycle) after them, each may need one more
    constraints = sorted(constraints, key=lambda c: (c.kind != "min", rank[c.tail]))
    times = {e: -math.inf for e in network.events}
    times[network.start] = network.start_deg
    for _ in range(len(network.events) + 1):
        changed = False
        for c in constraints:
            reach = times[c.tail] + c.weight
            if reach > times[c.head] + tol * max(1.0, abs(reach)):
                if c.head == network.start:    # the first event is held: a cycle through it is positive
                    return times, False
                times[c.head] = reach
                changed = True
        if not changed:
            return times, True
    return times, False


def _topological_rank(network: Network) -> dict[str, int]:
    """Each event's place in a topological order of the operations (Kahn; the network is acyclic)."""
    successors: dict[str, list[str]] = {e: [] for e in network.events}
    waiting = dict.fromkeys(network.events, 0)
    for op in network.operations:
        successors[op.tail].append(op.head)
        waiting[op.head] += 1
    ready = [e for e in network.events if waiting[e] == 0]
    rank: dict[str, int] = {}
    for event in ready:              # the list grows as events become ready
        rank[event] = len(rank)
        for nxt in successors[event]:
            waiting[nxt] -= 1
            if waiting[nxt] == 0:
                ready.append(nxt)
    return rank


def _critical(network: Network, tight: list[Constraint]) -> tuple[list[Constraint], list[str]]:
    """Tight constraints on a start→end path of tight constraints, and one such path of events."""
    forward: dict[str, list[Constraint]] = {e: [] for e in network.events}
    backward: dict[str, list[Constraint]] = {e: [] for e in network.events}
    for c in tight:
        forward[c.tail].append(c)
        backward[c.head].append(c)
    from_start = reachable_from(network.start, {e: [c.head for c in forward[e]] for e in network.events})
    to_end = reachable_from(network.end, {e: [c.tail for c in backward[e]] for e in network.events})
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
    while (step := previous.get(path[-1])) is not None:
        path.append(step.tail)
    return active, path[::-1]


def _explain(conflict: list[Constraint], solver_message: str) -> str:
    if not conflict:
        return f"the cyclogram is infeasible ({solver_message})"
    excess = sum(c.weight for c in conflict)
    return ("the cyclogram is infeasible: " + "; ".join(c.describe() for c in conflict)
            + f" cannot all hold (together they overrun by {excess:.6g} deg)")




