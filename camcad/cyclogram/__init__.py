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

from camcad.cyclogram.limits import LinearRelation, INADMISSIBLE, PhaseLimit, least_phase_angle, vibration_limits
from camcad.cyclogram.network import Operation, Network, make_network, find_cycle
from camcad.cyclogram.constraints import Constraint, effective_lower_bounds, constraints_of
from camcad.cyclogram.lp import CyclogramResult, optimise
from camcad.cyclogram.conflicts import find_conflict, longest_path_times
from camcad.cyclogram.retime import stretch_phase, retime_phases, format_phases, operation_timing


__all__ = [
    "Constraint",
    "CyclogramResult",
    "INADMISSIBLE",
    "LinearRelation",
    "Network",
    "Operation",
    "PhaseLimit",
    "constraints_of",
    "effective_lower_bounds",
    "find_conflict",
    "find_cycle",
    "format_phases",
    "least_phase_angle",
    "longest_path_times",
    "make_network",
    "operation_timing",
    "optimise",
    "retime_phases",
    "stretch_phase",
    "vibration_limits",
]
