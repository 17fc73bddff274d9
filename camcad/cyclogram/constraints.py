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


