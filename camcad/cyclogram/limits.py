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

    Parameters
    ----------
    slope : float
        The relation's unit per deg (mm/deg for an amplitude).
    intercept : float
        The value at t = 0, in the relation's unit (mm).

    Examples
    --------
    >>> from camcad.cyclogram import LinearRelation
    >>> relation = LinearRelation(-0.003, 0.208)
    >>> round(relation(36.0), 12), round(relation.solve(0.1), 9)       # (0.208 - 0.1)/0.003 = 36 deg
    (0.1, 36.0)
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

    ``least_phase_angle`` returns it; the example is there.

    Attributes
    ----------
    angle_deg : float
        The least t, deg.
    value : float
        The relation there, in its unit (MPa, mm, ...).
    limit : float
        The allowed value, in the relation's unit (MPa, mm, ...).
    binding : bool
        False when the lower end of the search interval already meets the limit (angle_deg is that end).
    source : str
        The relation ("contact", "vibration", ...).
    evaluations : int
        The relation's evaluations (a count).
    note : str
        Says when the angle is set by a jump to inadmissible values (the relation is +inf below it, e.g.
        the profile undercuts) rather than by reaching the limit.
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
    """Least phase angle t in [lower, upper] (deg) with relation(t) ≤ limit, for a non-increasing relation.

    The relation is a stress or an amplitude that falls as the operation gets longer. Bracket check: if
    relation(lower) ≤ limit the lower end is returned (not binding); if relation(upper) > limit no phase angle
    in the interval is admissible and a CamcadError says so. Otherwise Brent's method
    (``camcad.numerics.brent_root``: no scipy import for this) finds the crossing relation(t) = limit to
    ``xtol_deg`` (absolute, deg), in a handful of evaluations — no scan. For a monotone relation the crossing is
    the least admissible t; for a non-monotone one it is *a* crossing inside the bracket.

    The relation may return +inf for an inadmissible t (e.g. the profile undercuts); NaN is an error.
    ``reason`` (t → text, "" where admissible) names what makes a t inadmissible, for the note.

    Parameters
    ----------
    relation : callable
        t (deg) → the stress or amplitude there (MPa, mm, ...).
    limit : float
        The allowed value, in the relation's unit.
    lower_deg, upper_deg : float
        The interval searched, deg.
    source : str
        Names the relation ("contact", "vibration", ...).
    what : str
        Names the operation in messages.
    xtol_deg : float
        The root's tolerance, deg.
    max_iter : int
        Brent's iterations at most (a count).
    reason : callable, optional
        t (deg) → why t is inadmissible ("" where it is admissible).

    Returns
    -------
    PhaseLimit
        The least angle (deg), the relation there and the limit (its unit), whether it binds.

    Raises
    ------
    CamcadError
        No phase angle in the interval meets the limit, or the relation is NaN.

    Examples
    --------
    The published vibration relation of the shuttle lift, a = −0.003 t + 0.208 mm, against 0.1 mm:

    >>> from camcad.cyclogram import least_phase_angle
    >>> limit = least_phase_angle(lambda t: -0.003 * t + 0.208, 0.1, 20.0, 70.0, source="vibration")
    >>> round(limit.angle_deg, 9), limit.binding                        # (0.208 - 0.1)/0.003 = 36 deg
    (36.0, True)
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
    """The least phase angle of every operation with a vibration relation, against its amplitude limit.

    For each: the least t in [min_deg, max_deg (or cycle_deg)] with amplitude(t) ≤ amplitude_limit_mm
    (``least_phase_angle``).

    Parameters
    ----------
    network : Network
        The cyclogram network; operations with ``amplitude`` and ``amplitude_limit_mm`` are limited.
    xtol_deg : float
        The root's tolerance, deg.

    Returns
    -------
    dict
        {label: [PhaseLimit]}, angles in deg.

    Examples
    --------
    >>> import camcad
    >>> from camcad.cyclogram import LinearRelation, vibration_limits
    >>> lift = camcad.Operation("3", "7", 25.0, 70.0, amplitude=LinearRelation(-0.003, 0.208), amplitude_limit_mm=0.1)
    >>> round(vibration_limits(camcad.make_network([lift]))["3->7"][0].angle_deg, 9)
    36.0
    """
    limits: dict[str, list[PhaseLimit]] = {}
    for op in network.operations:
        if op.amplitude is None or op.amplitude_limit_mm is None:
            continue
        upper = op.max_deg if math.isfinite(op.max_deg) else network.cycle_deg
        limits.setdefault(op.label, []).append(least_phase_angle(
            op.amplitude, op.amplitude_limit_mm, op.min_deg, upper, source="vibration",
            what=f"operation {op.label}", xtol_deg=xtol_deg))
    return limits


