"""Area balance of a drawn acceleration law: the check, and every way of correcting it.

The conditions (Dupliak & Kotsiyba 2018, Dupliak & Kotsiyba 2018, eqs. 1–3; θ in rad, the law starts from rest
at s = 0): the velocity is zero at the end of every rise and every return (the accelerating and
decelerating areas of each phase balance), and the displacement comes back to its start at the
end of the cycle (rise = −return, the profile closes). With v(0) = s(0) = 0,

    v(θc) = ∫₀^θc a dθ,        s(θc) = ∫₀^θc (θc − τ) a(τ) dτ,

both *linear* in the ordinates a_i of the drawn polyline. So every condition is a row of a small
matrix C (one row per condition, one column per vertex), computed exactly from the piecewise-linear
shape functions, and a correction δ that restores balance solves C δ = −C a.

Correction modes (docs/INTERFACE.md; the source's list (a)–(g)):
- ``min-change``: the δ of least ∫ δa(θ)² dθ — the smallest change of the drawn curve as a function —
  over all vertices that are off the axis, solved exactly with the polyline's mass matrix M
  (δ = −M⁻¹Cᵀ (C M⁻¹ Cᵀ)⁻¹ C a); vertices on the axis (dwells, phase boundaries) stay put.
- ``extrema``: only the local maximum and minimum points move, equal neighbours together (b).
- ``extrema-resample``: the curve is resampled with the step and each lobe is scaled as a whole so its
  extremum takes the new value, every point recomputed from it (c).
- ``keypoints``: every vertex off the axis moves, least sum of squared vertex changes (d).
- ``segment``: only the vertices in a chosen angle range move (e).
- ``phase``: the decelerating part of each phase and then the whole last return are stretched in
  angle with the ordinates kept (closed form: a stretch f scales an area by f and a displacement
  by f²); a neighbouring dwell takes up the change (f).
- ``phase-keypoints``: a phase stretch limited to ``max_stretch``, then key points for the rest (g).
- ``move``: the user's points are set where they put them and held; the mode rebalances the rest (a).
Every mode keeps the drawn rise (the displacement over each rise, a linear condition too) unless
``keep_lift=False``, and moves the two vertices of a jump together (docs/fix.md).
Each vertex mode can also run the source's own loop, ``method="iterate"``: resample with ``step_deg``,
integrate with the trapezoidal rule, raise or lower the points by trial steps until the areas agree
within the tolerance.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

# eager: a light module, and its function ``conditions`` shares the module's name (a lazy name would be
# replaced by the submodule once that is imported)
from camcad.balance.conditions import (
    DEFAULT_MAX_STRETCH,
    DEFAULT_STEP_DEG,
    DEFAULT_TOL,
    METHODS,
    MODES,
    Condition,
    conditions,
    functional_rows,
    lift_conditions,
    mass_matrix,
)
from camcad.lazy import lazy_exports

if TYPE_CHECKING:  # the names for type checkers and IDEs; at run time they load on first use
    from camcad.balance.checking import (
        BalanceReport,
        check,
        check_by_trapezoid,
        trapezoid_residuals,
    )
    from camcad.balance.correction import Correction, Move, correct, difference_norms
    from camcad.balance.modes import (
        extremum_groups,
        jump_nodes,
        least_change,
        lobe_groups,
        lobes,
    )

#: public name -> the module that defines it (imported on first use: importing this package stays cheap)
_EXPORTS: dict[str, str] = {
    "BalanceReport": "camcad.balance.checking",
    "check": "camcad.balance.checking",
    "check_by_trapezoid": "camcad.balance.checking",
    "correct": "camcad.balance.correction",
    "Correction": "camcad.balance.correction",
    "difference_norms": "camcad.balance.correction",
    "extremum_groups": "camcad.balance.modes",
    "jump_nodes": "camcad.balance.modes",
    "least_change": "camcad.balance.modes",
    "lobe_groups": "camcad.balance.modes",
    "lobes": "camcad.balance.modes",
    "Move": "camcad.balance.correction",
    "trapezoid_residuals": "camcad.balance.checking",
}


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())

__all__ = [
    "DEFAULT_MAX_STRETCH",
    "DEFAULT_STEP_DEG",
    "DEFAULT_TOL",
    "METHODS",
    "MODES",
    "BalanceReport",
    "Condition",
    "Correction",
    "Move",
    "check",
    "check_by_trapezoid",
    "conditions",
    "correct",
    "difference_norms",
    "extremum_groups",
    "functional_rows",
    "jump_nodes",
    "least_change",
    "lift_conditions",
    "lobe_groups",
    "lobes",
    "mass_matrix",
    "trapezoid_residuals",
]
