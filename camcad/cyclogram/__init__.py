"""Cyclogram of a group of mechanisms: a network of events and operations, its least makespan by longest paths.

Model (Podgorny, Maksimchuk, Kirillov, Skeeba, Obrabotka Metallov 20(1) 2018 44–54, Podgorny et al. 2018,
after Hendrickson & Janson, Civil Engineering Systems 1 (1984) 195–203):
vertices are events x with times p(x) (deg of the cam shaft); arcs are operations (x, y) whose phase
angle is t(x, y) = p(y) − p(x). Minimise p(N) − p(1) subject to

    [φ(x, y)] ≤ t(x, y) ≤ φ_max(x, y)  for every operation,   p(N) − p(1) ≤ cycle,

where the least admissible phase angle [φ] is the larger of the designer's bound and the limits
from contact stress (σ_max(t) ≤ [σ_H]) and vibration (amplitude(t) ≤ [a]), each found by root
finding on a monotone relation (``least_phase_angle``).

Every constraint is a difference constraint p(head) ≥ p(tail) + weight: a lower bound is an arc
x → y of weight [φ], an upper bound an arc y → x of weight −φ_max, the cycle an arc N → 1 of
weight −cycle. The LP optimum is therefore a longest path from 1 to N in that graph (which is how
``optimise`` finds it: Bellman–Ford, no LP solver), and the
system is infeasible exactly when the graph has a cycle of positive weight; such a simple cycle is
an irreducible conflicting set (drop any one of its constraints and the rest can be met).

Angles are degrees throughout this module (the cyclogram is an interface quantity).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from camcad.lazy import lazy_exports

if TYPE_CHECKING:  # the names for type checkers and IDEs; at run time they load on first use
    from camcad.cyclogram.conflicts import find_conflict
    from camcad.cyclogram.constraints import Constraint, constraints_of, effective_lower_bounds
    from camcad.cyclogram.limits import INADMISSIBLE, LinearRelation, PhaseLimit, least_phase_angle, vibration_limits
    from camcad.cyclogram.lp import CyclogramResult, optimise
    from camcad.cyclogram.machine import Group, Machine, MachineResult, make_machine, optimise_machine
    from camcad.cyclogram.network import Network, Operation, find_cycle, make_network
    from camcad.cyclogram.retime import format_phases, operation_timing, retime_phases, stretch_phase
    from camcad.cyclogram.slack import SlackPlan, spread_slack

#: public name -> the module that defines it (imported on first use: importing this package stays cheap)
_EXPORTS: dict[str, str] = {
    "Constraint": "camcad.cyclogram.constraints",
    "CyclogramResult": "camcad.cyclogram.lp",
    "INADMISSIBLE": "camcad.cyclogram.limits",
    "LinearRelation": "camcad.cyclogram.limits",
    "Network": "camcad.cyclogram.network",
    "Operation": "camcad.cyclogram.network",
    "PhaseLimit": "camcad.cyclogram.limits",
    "constraints_of": "camcad.cyclogram.constraints",
    "effective_lower_bounds": "camcad.cyclogram.constraints",
    "find_conflict": "camcad.cyclogram.conflicts",
    "find_cycle": "camcad.cyclogram.network",
    "Group": "camcad.cyclogram.machine",
    "Machine": "camcad.cyclogram.machine",
    "MachineResult": "camcad.cyclogram.machine",
    "make_machine": "camcad.cyclogram.machine",
    "optimise_machine": "camcad.cyclogram.machine",
    "SlackPlan": "camcad.cyclogram.slack",
    "spread_slack": "camcad.cyclogram.slack",
    "format_phases": "camcad.cyclogram.retime",
    "least_phase_angle": "camcad.cyclogram.limits",
    "make_network": "camcad.cyclogram.network",
    "operation_timing": "camcad.cyclogram.retime",
    "optimise": "camcad.cyclogram.lp",
    "retime_phases": "camcad.cyclogram.retime",
    "stretch_phase": "camcad.cyclogram.retime",
    "vibration_limits": "camcad.cyclogram.limits",
}


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())


__all__ = [
    "INADMISSIBLE",
    "Constraint",
    "CyclogramResult",
    "Group",
    "LinearRelation",
    "Machine",
    "MachineResult",
    "Network",
    "Operation",
    "PhaseLimit",
    "SlackPlan",
    "constraints_of",
    "effective_lower_bounds",
    "find_conflict",
    "find_cycle",
    "format_phases",
    "least_phase_angle",
    "make_machine",
    "make_network",
    "operation_timing",
    "optimise",
    "optimise_machine",
    "retime_phases",
    "spread_slack",
    "stretch_phase",
    "vibration_limits",
]
