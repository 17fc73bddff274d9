"""Least admissible phase angles: relations (contact stress, vibration) and root finding on them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from camcad.errors import CamcadError
from camcad.numerics import brent_root

if TYPE_CHECKING:
    from camcad.cyclogram.network import Network

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
                      xtol_deg: float = 1e-10, max_iter: int = 200, reason=None) -> PhaseLimit:
    """Least phase angle t in [lower, upper] (deg) with relation(t) ≤ limit, for a non-increasing
    relation (a stress or an amplitude that falls as the operation gets longer).

    Bracket check: if relation(lower) ≤ limit the lower end is returned (not binding); if
    relation(upper) > limit no phase angle in the interval is admissible and a CamcadError says so.
    Otherwise Brent's method (``camcad.numerics.brent_root``: no scipy import for this) finds the
    crossing relation(t) = limit to ``xtol_deg`` (absolute, deg),
    in a handful of evaluations — no scan. For a monotone relation the crossing is the least
    admissible t; for a non-monotone one it is *a* crossing inside the bracket.

    The relation may return +inf for an inadmissible t (e.g. the profile undercuts); NaN is an error.
    ``reason`` (t → text, "" where admissible) names what makes a t inadmissible, for the note.
    Units: t deg; relation and limit in the same unit (MPa, mm, ...).
    """
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
    root = brent_root(excess, lower_deg, upper_deg, xtol=xtol_deg, maxiter=max_iter)
    # Brent's method returns a point within xtol of the sign change, on either side; at a jump to an
    # inadmissible value (e.g. an undercut) step to the admissible side
    step = xtol_deg
    while excess(root) >= INADMISSIBLE and root < upper_deg:
        root = min(root + step, upper_deg)
        step *= 2.0
    value = float(relation(root))
    note = ""
    if value < limit - 1e-6 * abs(limit):
        why = (reason(root * (1.0 - 1e-7) - 1e-9) if reason is not None else "") or \
            "the relation is infinite there"
        note = (f"set at {root:.6g} deg, below which the phase is inadmissible: {why}; {source} there is "
                f"{value:.6g}, under its limit")
    return PhaseLimit(float(root), value, limit, True, source, count + 1, note)




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


