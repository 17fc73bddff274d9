"""Difference constraints of the cyclogram: p(head) >= p(tail) + weight, from bounds, limits and the cycle."""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from camcad.cyclogram.limits import PhaseLimit
from camcad.cyclogram.network import Network
from camcad.errors import CamcadError, nearest_name


@dataclass(frozen=True)
class Constraint:
    """One difference constraint p(head) ≥ p(tail) + weight (deg).

    kind "min": t(label) ≥ bound; "max": t(label) ≤ bound; "cycle": makespan ≤ bound.
    ``source`` says where the bound comes from ("bounds_deg", "contact", "vibration", "cycle_deg").
    ``constraints_of`` makes them from a network; its example shows them.

    Attributes
    ----------
    kind : str
        "min", "max" or "cycle".
    label : str
        The operation's label ("tail->head"), or "makespan".
    bound : float
        The bound, deg.
    source : str
        Where the bound comes from.
    tail, head : str
        The events it joins.
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
    """{label: (least admissible phase angle deg, its source)} of every operation of a network.

    The largest of the operation's own lower bound and its phase limits (a tie keeps the designer's bound
    as the source).

    Parameters
    ----------
    network : Network
        The cyclogram network (bounds in deg).
    limits : dict, optional
        {label: [PhaseLimit]}: least admissible angles the mechanisms' models give (deg).

    Returns
    -------
    dict
        {label: (angle in deg, source)}.

    Examples
    --------
    A vibration limit of 42 deg on S->Y lifts its bound from 40 deg, and the least makespan from 55 to
    42 + 15 = 57 deg:

    >>> import camcad
    >>> network = camcad.make_network([camcad.Operation("S", "X", 30.0), camcad.Operation("S", "Y", 40.0),
    ...                                camcad.Operation("X", "E", 10.0), camcad.Operation("Y", "E", 15.0)])
    >>> from camcad.cyclogram import PhaseLimit, effective_lower_bounds
    >>> limits = {"S->Y": [PhaseLimit(42.0, 0.1, 0.1, True, "vibration")]}
    >>> effective_lower_bounds(network, limits)["S->Y"]
    (42.0, 'vibration')
    >>> camcad.optimise(network).makespan_deg, camcad.optimise(network, limits).makespan_deg
    (55.0, 57.0)
    """
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
    """Every difference constraint of the network: lower and upper bounds, and the cycle.

    Parameters
    ----------
    network : Network
        The cyclogram network (bounds in deg).
    limits : dict, optional
        {label: [PhaseLimit]}: least admissible angles the mechanisms' models give (deg).

    Returns
    -------
    list of Constraint
        One "min" per operation (its effective lower bound, deg), one "max" per finite upper bound, and the
        "cycle" constraint on the makespan (deg).

    Examples
    --------
    >>> import camcad
    >>> network = camcad.make_network([camcad.Operation("S", "X", 30.0), camcad.Operation("S", "Y", 40.0),
    ...                                camcad.Operation("X", "E", 10.0), camcad.Operation("Y", "E", 15.0)])
    >>> from camcad.cyclogram import constraints_of
    >>> [(c.kind, c.label, c.bound) for c in constraints_of(network)][-2:]
    [('min', 'Y->E', 15.0), ('cycle', 'makespan', 360.0)]
    """
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


