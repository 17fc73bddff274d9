"""The machine's cyclogram: several groups' networks joined into one, and its two objectives.

Podgorny et al. (2018, Fig. 1) draw the loom's cyclogram as one network in which each group of mechanisms
is a subgraph and one arc, the *limiting operation* 10.1–10.2, is what the machine's speed is made for:
"the length of arc 10.1–10.2 can be increased by shortening the operations in the groups", each group being
a network optimisation of its own. Here the machine is one network:

- every group's events, named ``GROUP:EVENT`` ("group1:8"), with the group's operations, bounds and phase
  limits (contact stress, pressure angle, vibration, impact rebound: ``camcad.scene.phase_angles``);
- the machine's own events (plain names, "10.1") and operations joining them to the groups' events;
- *shared events*: several names that are one event of the machine ("group1:8" is "10.1": the weft is in
  the shuttle when the insertion starts) — merged into one vertex;
- a group's own ``cycle_deg`` when it is shorter than the machine's: p(group end) − p(group start) ≤ it;
- the machine cycle: p(end) − p(start) ≤ ``cycle_deg`` (360 for one turn of the main shaft).

Objectives, both solved exactly by the network's structure (difference constraints):

- ``least_cycle``: minimise p(end) − p(start) — the longest path from the first event
  (``camcad.cyclogram.optimise``);
- ``limiting``: maximise the limiting operation t(L) = p(head) − p(tail) within the cycle — the largest
  value of a difference under difference constraints is minus the heaviest walk head → tail of the
  constraint graph (the machine cycle is its arc end → start of weight −cycle_deg;
  ``camcad.cyclogram.slack.largest_phase_angles``). Every group is then as short as its limits allow where
  it stands in series with L. With t(L) held at that length, the schedule is the least makespan's.

In both, the slack left over goes by the max–min rule of ``camcad.cyclogram.slack`` (``schedule``).
Each group's phase angles are then read off the machine's schedule (``group_result``), so every group's
profiles are regenerated at the machine's phase angles. Angles are degrees throughout.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

from camcad.cyclogram.constraints import Constraint, constraints_of
from camcad.cyclogram.limits import PhaseLimit
from camcad.cyclogram.lp import CyclogramResult, optimise
from camcad.cyclogram.network import Network, Operation, make_network
from camcad.cyclogram.slack import largest_phase_angles
from camcad.errors import CamcadError, nearest_name

#: between a group's name and one of its events: "group1:8"
SEP = ":"
OBJECTIVES = ("least_cycle", "limiting")
#: the source of the limiting operation's lower bound once it is held at its longest
LIMITING_SOURCE = "limiting operation at its longest"


@dataclass(frozen=True)
class Group:
    """One group of a machine: its network and its operations' phase limits.

    Parameters
    ----------
    name : str
        The group's name (no ":"); its events are "NAME:EVENT" in the machine.
    network : Network
        Its network (``make_network``), bounds in deg.
    limits : mapping of str to sequence of PhaseLimit
        {operation label: [PhaseLimit]}, least phase angles in deg (contact stress, pressure angle, ...).

    References
    ----------
    Podgorny et al., Obrabotka Metallov 20(1) (2018) 44–54, Figs. 1–2: a group is a subgraph of the machine.

    Examples
    --------
    >>> import camcad
    >>> group = camcad.Group("lift", camcad.make_network([camcad.Operation("1", "2", 36.0)]))
    >>> group.name, group.network.events
    ('lift', ('1', '2'))
    """

    name: str
    network: Network
    limits: Mapping[str, Sequence[PhaseLimit]] = field(default_factory=dict)


@dataclass(frozen=True)
class Machine:
    """A machine of groups joined into one network (``camcad.make_machine``, where the example is).

    Parameters
    ----------
    groups : tuple of Group
        The groups, as given.
    network : Network
        Every event and operation, a group's events as "GROUP:EVENT", merged where shared.
    limits : dict
        The groups' phase limits under the machine's labels ({label: [PhaseLimit]}).
    extra : tuple of Constraint
        The groups' own cycles (deg).
    event_of : dict
        {name as written: machine event}.
    origin : dict
        {machine label: (group or "", label there)}.
    limiting : str, optional
        The limiting operation's machine label (or None).

    Examples
    --------
    >>> import camcad
    >>> a = camcad.Group("a", camcad.make_network([camcad.Operation("1", "2", 40.0)]))
    >>> b = camcad.Group("b", camcad.make_network([camcad.Operation("1", "2", 60.0)]))
    >>> machine = camcad.make_machine([a, b], [camcad.Operation("0", "a:1"), camcad.Operation("a:2", "b:1", 10.0),
    ...                                        camcad.Operation("b:2", "360")])
    >>> machine.event_of["a:1"], [g.name for g in machine.groups]
    ('a:1', ['a', 'b'])
    """

    groups: tuple[Group, ...]
    network: Network
    limits: dict[str, list[PhaseLimit]]
    extra: tuple[Constraint, ...]
    event_of: dict[str, str]
    origin: dict[str, tuple[str, str]]
    limiting: str | None = None

    def group(self, name: str) -> Group:
        for group in self.groups:
            if group.name == name:
                return group
        raise KeyError(name)

    def labels_of(self, group: str) -> dict[str, str]:
        """{label in the group: label in the machine} of a group's operations."""
        return {own: label for label, (owner, own) in self.origin.items() if owner == group}


def make_machine(groups: Iterable[Group], operations: Iterable[Operation], shared: Iterable[Sequence[str]] = (),
                 *, cycle_deg: float = 360.0, start_deg: float = 0.0, limiting: str | None = None,
                 start: str | None = None, end: str | None = None, names: Mapping[int, str] | None = None,
                 where: str = "[machine]") -> Machine:
    """Join groups into one machine network (module docstring).

    Parameters
    ----------
    groups : iterable of Group
        The groups (their networks and phase limits, deg).
    operations : iterable of Operation
        The machine's own operations, between machine events (plain names) and groups' events
        ("GROUP:EVENT"), bounds in deg.
    shared : iterable of sequences of str
        Each a set of event names that are one event of the machine.
    cycle_deg : float
        The machine's cycle, deg (360: one turn of the main shaft).
    start_deg : float
        Where the machine's first event sits on the main shaft, deg.
    limiting : str, optional
        The limiting operation: the label "x->y" (names as written) or the name of one of ``operations``.
    start, end : str, optional
        The machine's first and last events (names as written); found when there is only one.
    names : mapping of int to str, optional
        A name for the merged event of ``shared[k]`` (default: its machine event, else its names joined
        by "=").
    where : str
        What to name in an error message.

    Returns
    -------
    Machine
        ``network`` (bounds in deg, cycle and start in deg), ``limits`` (least angles in deg), ``event_of``,
        ``origin``, ``limiting`` (no unit: names and labels).

    Raises
    ------
    CamcadError
        An unknown group or event, a shared set with two machine events or one event twice, and whatever
        ``make_network`` refuses in the joined network (a cycle, two operations between the same events,
        an event off every path from the first to the last).

    References
    ----------
    Podgorny, Maksimchuk, Kirillov, Skeeba, "Features of machine cyclogram optimization with the account of
    interaction of mechanism links with stops", Obrabotka Metallov 20(1) (2018) 44–54, Fig. 1.

    Examples
    --------
    Two groups in series around a limiting operation: the machine starts at "0", group a runs, the limiting
    operation L runs from a's end to b's start, group b runs and the machine ends at "360":

    >>> import camcad
    >>> a = camcad.Group("a", camcad.make_network([camcad.Operation("1", "2", 40.0)]))
    >>> b = camcad.Group("b", camcad.make_network([camcad.Operation("1", "2", 60.0)]))
    >>> machine = camcad.make_machine([a, b], [camcad.Operation("0", "a:1"), camcad.Operation("b:2", "360"),
    ...                                        camcad.Operation("a:2", "b:1", 90.0, name="L")], limiting="L")
    >>> machine.limiting, machine.network.start, machine.network.end
    ('a:2->b:1', '0', '360')
    """
    groups = tuple(groups)
    seen_names: set[str] = set()
    for group in groups:
        if SEP in group.name or not group.name:
            raise CamcadError(f"group name {group.name!r} must be non-empty and without {SEP!r}", where,
                              "rename the group")
        if group.name in seen_names:
            raise CamcadError(f"group {group.name!r} is given twice", where, "give each group once")
        seen_names.add(group.name)
    by_group = {g.name: g for g in groups}
    ops = tuple(operations)
    written: list[str] = []        # every name as written, machine events in order of appearance
    for group in groups:
        written.extend(f"{group.name}{SEP}{e}" for e in group.network.events)
    for op in ops:
        for name in (op.tail, op.head):
            _check_ref(name, by_group, where)
            if name not in written:
                written.append(name)
    # shared events: union of names into one machine event
    event_of = {name: name for name in written}
    shared = [list(s) for s in shared]
    for k, members in enumerate(shared):
        if len(members) < 2:
            raise CamcadError(f"shared[{k + 1}] names {len(members)} event", where,
                              "list two or more events that are one event of the machine")
        if len(set(members)) != len(members):
            raise CamcadError(f"shared[{k + 1}] names an event twice", where, "list each event once")
        for name in members:
            _check_ref(name, by_group, where)
            if name not in event_of:
                written.append(name)
                event_of[name] = name
        plain = [name for name in members if SEP not in name]
        if len(plain) > 1:
            raise CamcadError(f"shared[{k + 1}] joins two machine events ({plain[0]}, {plain[1]})", where,
                              "a shared set may hold one machine event; name the others once")
        taken = [name for name in members if event_of[name] != name]
        if taken:
            raise CamcadError(f"event {taken[0]!r} is in two shared sets", where, "merge those sets into one")
        merged: str = (names or {}).get(k) or (plain[0] if plain else "=".join(members))
        for name in members:
            event_of[name] = merged
    flat_events: list[str] = []
    for name in written:
        if event_of[name] not in flat_events:
            flat_events.append(event_of[name])
    # the joined operations
    flat_ops: list[Operation] = []
    origin: dict[str, tuple[str, str]] = {}
    limits: dict[str, list[PhaseLimit]] = {}
    extra: list[Constraint] = []
    for group in groups:
        def ref(event: str, g: str = group.name) -> str:
            return event_of[f"{g}{SEP}{event}"]
        for op in group.network.operations:
            mechanism = f"{group.name}{SEP}{op.mechanism}" if op.mechanism else None
            flat = replace(op, tail=ref(op.tail), head=ref(op.head), mechanism=mechanism)
            flat_ops.append(flat)
            origin[flat.label] = (group.name, op.label)
            if op.label in group.limits:
                limits[flat.label] = list(group.limits[op.label])
        if group.network.cycle_deg < cycle_deg:
            extra.append(Constraint("max", f"{group.name} cycle", float(group.network.cycle_deg),
                                    f"{group.name} cycle_deg", ref(group.network.end), ref(group.network.start)))
    limiting_label = None
    for op in ops:
        flat = replace(op, tail=event_of[op.tail], head=event_of[op.head])
        flat_ops.append(flat)
        origin[flat.label] = ("", op.label)
        if limiting is not None and limiting in (op.label, op.name):
            if limiting_label is not None:
                raise CamcadError(f"two operations match the limiting operation {limiting!r}", where,
                                  "name it by its label \"x->y\"")
            limiting_label = flat.label
    if limiting is not None and limiting_label is None:
        choices = [op.label for op in ops] + [op.name for op in ops if op.name]
        raise CamcadError(f"the limiting operation {limiting!r} is not one of the machine's operations", where,
                          nearest_name(limiting, choices).replace("valid keys", "operations"))
    for given, role in ((start, "start"), (end, "end")):
        if given is not None and given not in event_of:
            raise CamcadError(f"{role} event {given!r} is not an event of the machine", where,
                              nearest_name(given, list(event_of)).replace("valid keys", "events"))
    network = make_network(flat_ops, flat_events, None if start is None else event_of[start],
                           None if end is None else event_of[end], cycle_deg, start_deg, where)
    return Machine(groups, network, limits, tuple(extra), event_of, origin, limiting_label)


def _check_ref(name: str, groups: Mapping[str, Group], where: str) -> None:
    if not isinstance(name, str) or not name:
        raise CamcadError(f"event {name!r} is not a name", where, "write events as \"GROUP:EVENT\" or a plain name")
    if SEP not in name:
        return
    group, event = name.split(SEP, 1)
    if group not in groups:
        raise CamcadError(f"event {name!r} names unknown group {group!r}", where,
                          nearest_name(group, list(groups)).replace("valid keys", "groups"))
    if event not in groups[group].network.events:
        raise CamcadError(f"group {group!r} has no event {event!r}", where,
                          nearest_name(event, list(groups[group].network.events)).replace("valid keys", "events"))


@dataclass(frozen=True)
class MachineResult:
    """The machine's optimal cyclogram under one objective (``camcad.optimise_machine`` returns it).

    Attributes
    ----------
    machine : Machine
        The machine solved.
    objective : str
        "least_cycle" or "limiting".
    result : CyclogramResult
        The joined network's cyclogram (event times on the main shaft, deg).
    least_cycle_deg : float, optional
        The least makespan of the machine whatever the objective, deg.
    limiting_deg : float, optional
        t(L) in ``result``, deg.
    limiting_at_least_cycle_deg : float, optional
        t(L) in the least-cycle schedule, deg.
    limiting_longest_deg : float, optional
        The longest t(L) the cycle allows, deg.
    groups : dict
        {group: CyclogramResult of its own network with the machine's event times}.
    """

    machine: Machine
    objective: str
    result: CyclogramResult
    least_cycle_deg: float | None = None
    limiting_deg: float | None = None
    limiting_at_least_cycle_deg: float | None = None
    limiting_longest_deg: float | None = None
    groups: dict[str, CyclogramResult] = field(default_factory=dict)

    @property
    def feasible(self) -> bool:
        return self.result.feasible

    def report(self) -> dict[str, Any]:
        """The machine's ``cyclogram`` keys (docs/INTERFACE.md: makespan_deg, event_times_deg, phase_angles_deg,
        critical_path, active_bounds, feasible), the objective and the limiting operation, and per group its
        start, makespan and phases."""
        out = self.result.report()
        out["objective"] = self.objective
        out["least_cycle_deg"] = self.least_cycle_deg
        if self.machine.limiting is not None:
            label = self.machine.limiting
            own = next(op for op in self.machine.network.operations if op.label == label)
            out["limiting"] = {"operation": label, "name": own.name, "deg": self.limiting_deg,
                               "at_least_cycle_deg": self.limiting_at_least_cycle_deg,
                               "longest_deg": self.limiting_longest_deg, "least_deg": own.min_deg}
        out["shared_events"] = {name: event for name, event in self.machine.event_of.items() if name != event}
        out["groups"] = {}
        for name, found in self.groups.items():
            group = self.machine.group(name)
            out["groups"][name] = {"start_event": group.network.start, "end_event": group.network.end,
                                   "start_deg": found.event_times_deg[group.network.start],
                                   "makespan_deg": found.makespan_deg,
                                   "critical_operations": list(found.critical_operations)}
        return out


def optimise_machine(machine: Machine, objective: str = "least_cycle", *, schedule: str = "leximin",
                     where: str = "[machine]") -> MachineResult:
    """The machine's cyclogram under ``objective`` (module docstring), with every group's phase angles.

    Parameters
    ----------
    machine : Machine
        The joined network (``make_machine``), deg.
    objective : {"least_cycle", "limiting"}
        Minimise the machine's makespan p(end) − p(start); or maximise the limiting operation within the
        cycle (``machine.limiting`` must be set).
    schedule : {"leximin", "earliest"}
        Where the slack left over goes (``camcad.cyclogram.optimise``).
    where : str
        What to name in an error message.

    Returns
    -------
    MachineResult
        ``result`` (event times and phase angles in deg), ``least_cycle_deg``, ``limiting_deg``,
        ``limiting_at_least_cycle_deg``, ``limiting_longest_deg`` (deg), ``groups`` (each group's
        CyclogramResult, deg). Infeasible: ``result.feasible`` False with the conflicting constraints
        (``result.conflict``).

    Raises
    ------
    CamcadError
        An unknown objective, or "limiting" without a limiting operation.

    References
    ----------
    Podgorny et al., Obrabotka Metallov 20(1) (2018) 44–54, Fig. 1: the limiting operation 10.1–10.2 is
    lengthened by shortening the operations of the groups.

    Examples
    --------
    The series machine of ``make_machine``: a takes 40°, b 60°, L at least 90°. The least cycle is
    40 + 90 + 60 = 190°; within 360° L can be 360 − 40 − 60 = 260°:

    >>> import camcad
    >>> a = camcad.Group("a", camcad.make_network([camcad.Operation("1", "2", 40.0)]))
    >>> b = camcad.Group("b", camcad.make_network([camcad.Operation("1", "2", 60.0)]))
    >>> machine = camcad.make_machine([a, b], [camcad.Operation("0", "a:1"), camcad.Operation("b:2", "360"),
    ...                                        camcad.Operation("a:2", "b:1", 90.0, name="L")], limiting="L")
    >>> least = camcad.optimise_machine(machine, "least_cycle")
    >>> longest = camcad.optimise_machine(machine, "limiting")
    >>> least.least_cycle_deg, least.limiting_deg, longest.limiting_deg, longest.result.makespan_deg
    (190.0, 90.0, 260.0, 360.0)
    """
    if objective not in OBJECTIVES:
        raise CamcadError(f"unknown objective {objective!r}", where, f"choose one of {', '.join(OBJECTIVES)}")
    if objective == "limiting" and machine.limiting is None:
        raise CamcadError("the objective 'limiting' needs a limiting operation", where,
                          "name it with limiting = \"x->y\" (or choose objective = \"least_cycle\")")
    network = machine.network
    least = optimise(network, machine.limits, strict=False, where=where, schedule=schedule, extra=machine.extra)
    if not least.feasible:
        return MachineResult(machine, objective, least)
    label = machine.limiting
    at_least = longest = None
    if label is not None:
        at_least = least.phase_angles_deg[label]
        constraints = constraints_of(network, machine.limits) + list(machine.extra)
        op = next(o for o in network.operations if o.label == label)
        longest = largest_phase_angles(list(network.events), constraints, {label: (op.tail, op.head)})[label]
        longest = min(longest, op.max_deg)
    chosen = least
    if objective == "limiting" and label is not None and longest is not None and math.isfinite(longest):
        # held at its longest value (a cycle that closes to round-off is not a conflict: ``optimise``)
        held = longest
        limits = {k: list(v) for k, v in machine.limits.items()}
        limits.setdefault(label, []).append(PhaseLimit(held, held, held, True, LIMITING_SOURCE))
        chosen = optimise(network, limits, strict=False, where=where, schedule=schedule, extra=machine.extra)
    found = MachineResult(machine, objective, chosen, least.makespan_deg,
                          None if label is None else chosen.phase_angles_deg[label], at_least, longest)
    return replace(found, groups={g.name: group_result(machine, chosen, g.name) for g in machine.groups})


def group_result(machine: Machine, result: CyclogramResult, name: str) -> CyclogramResult:
    """One group's CyclogramResult read off the machine's schedule: its own events and operations with the
    machine's event times (deg on the main shaft), its bounds, its active constraints and margins; what the
    group's mechanisms are retimed with (``camcad.cyclogram.operation_timing``)."""
    group = machine.group(name)
    own = group.network
    times = {e: result.event_times_deg[machine.event_of[f"{name}{SEP}{e}"]] for e in own.events}
    labels = machine.labels_of(name)
    back = {flat: label for label, flat in labels.items()}
    angles = {op.label: times[op.head] - times[op.tail] for op in own.operations}
    lower = {label: result.lower_bounds_deg[flat] for label, flat in labels.items()}
    by_label = {op.label: op for op in own.operations}
    active = tuple(replace(c, label=back[c.label], tail=by_label[back[c.label]].tail if c.kind == "min"
                           else by_label[back[c.label]].head,
                           head=by_label[back[c.label]].head if c.kind == "min" else by_label[back[c.label]].tail)
                   for c in result.active if c.label in back)
    inverse: dict[str, str] = {}
    for written, event in machine.event_of.items():
        if written.startswith(f"{name}{SEP}"):
            inverse.setdefault(event, written.split(SEP, 1)[1])
    path = tuple(inverse[e] for e in result.critical_path if e in inverse)
    makespan = times[own.end] - times[own.start]
    network = replace(own, cycle_deg=machine.network.cycle_deg, start_deg=times[own.start])
    return CyclogramResult(network, True, makespan, times, angles, path, active, lower,
                           cycle_slack_deg=own.cycle_deg - makespan,
                           solver_message=f"read off the machine's schedule ({result.solver_message})",
                           schedule=result.schedule,
                           margins={back[k]: v for k, v in result.margins.items() if k in back},
                           critical_operations=tuple(back[k] for k in result.critical_operations if k in back))
