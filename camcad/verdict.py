"""Checks an engineer can sign: every verdict is a figure, a limit and a margin, and says why.

A ``Check`` compares one figure with one limit. ``sense`` says which side is safe: ``"max"`` (the value
must not exceed the limit: pressure angle, stress, rebound) or ``"min"`` (it must not fall below it:
radius of curvature, safety factor, transmission angle). The margin is measured towards failure and is
positive while the check passes:

    sense "max":  margin = limit − value        sense "min":  margin = value − limit

and ``margin_ratio`` is the margin as a fraction of |limit| (the yardstick for "tightest first"). A check
without a limit (``limit=None``) is a figure reported for information; it passes.

Each check also names what it applies to (``applies``: the phase, the cam angles, the speeds, and which
phase angles were analysed — the law's own or the cyclogram's) and may carry a ``note`` (e.g. "held at its
limit by the cyclogram"). ``Warning`` is what a senior engineer would flag even where the scene sets no
limit; it carries the figure that triggered it.

JSON form (docs/INTERFACE.md): ``{"value", "limit", "margin", "passed", "why", ...}``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

#: significant digits of figures in reports (text and JSON): 169.99999999999997 → 170
REPORT_DIGITS = 10
#: a passing check whose margin is at most this fraction of its limit (of max(|limit|, |value|)) ends at its
#: limit: reported "at limit" (a warning), never a clean "ok" (a design held there by an optimiser, a root
#: found to round-off)
AT_LIMIT = 1e-6


def rounded(value: Any, digits: int = REPORT_DIGITS) -> Any:
    """``value`` rounded to ``digits`` significant digits (floats only; inf/nan and others unchanged).

    Examples
    --------
    >>> rounded(169.99999999999997), rounded(1.2345678901234e-7, 4), rounded(3)
    (170.0, 1.235e-07, 3)
    """
    if isinstance(value, bool) or not isinstance(value, float) or not math.isfinite(value) or value == 0.0:
        return value
    return float(f"{value:.{digits}g}")


@dataclass(frozen=True)
class Check:
    """One figure against one limit.

    Parameters
    ----------
    name : str
        What is checked, e.g. ``"pressure angle, rise"``.
    value : float or None
        The figure (in ``unit``); None when it could not be computed (then ``why`` says why).
    limit : float or None
        The limit (in ``unit``); None for a figure without a limit.
    unit : str
        Unit of value, limit and margin (``"deg"``, ``"mm"``, ``"MPa"``, ``""`` for a ratio).
    sense : {"max", "min"}
        ``"max"``: value <= limit passes; ``"min"``: value >= limit passes.
    applies : str
        Where it applies: phase, cam angle, speeds, and whose phase angles.
    note : str
        Anything the engineer should know about this check (e.g. held at the limit by the cyclogram).
    passed_override : bool or None
        A verdict that is not a plain comparison (e.g. a profile that does not close); None = compare.
    scale : float
        The size of the quantity, in ``unit``, against which "at limit" is judged when the limit is 0 (e.g. the
        largest normal force for a least normal force of 0 N); 0: max(|limit|, |value|) alone.
    """

    name: str
    value: float | None
    limit: float | None
    unit: str = ""
    sense: str = "max"
    applies: str = ""
    note: str = ""
    passed_override: bool | None = None
    scale: float = 0.0

    def __post_init__(self) -> None:
        if self.sense not in ("max", "min"):
            raise ValueError(f"sense must be 'max' or 'min', not {self.sense!r}")

    @property
    def margin(self) -> float | None:
        """Distance to failure in ``unit``: positive while passing."""
        if self.value is None or self.limit is None:
            return None
        return self.limit - self.value if self.sense == "max" else self.value - self.limit

    @property
    def margin_ratio(self) -> float | None:
        """The margin as a fraction of |limit| (None without a limit or with a zero limit)."""
        margin = self.margin
        if margin is None or self.limit is None or self.limit == 0:
            return None
        return margin / abs(self.limit)

    @property
    def passed(self) -> bool:
        if self.passed_override is not None:
            return self.passed_override
        if self.limit is None:
            return True
        if self.value is None or (not math.isfinite(self.value) and self.sense == "max" and self.value > 0):
            return False
        margin = self.margin
        return margin is not None and margin >= 0.0

    @property
    def at_limit(self) -> bool:
        """Passes, but ends at its limit: margin ≤ ``AT_LIMIT`` × max(|limit|, |value|, ``scale``) (a limit of 0
        with a value of 0 too). Such a check is reported "at limit" (a warning), never a clean pass."""
        if not self.passed or self.passed_override is not None or self.limit is None or self.value is None:
            return False
        margin = self.margin
        if margin is None or not math.isfinite(margin):
            return False
        return margin <= AT_LIMIT * max(abs(self.limit), abs(self.value), abs(self.scale))

    @property
    def status(self) -> str:
        """"ok", "at limit" (passes with no margin to speak of: a warning) or "fail"."""
        if not self.passed:
            return "fail"
        return "at limit" if self.at_limit else "ok"

    @property
    def why(self) -> str:
        """One line: the figure, the limit, the margin and what it applies to."""
        unit = f" {self.unit}" if self.unit else ""
        if self.value is None:
            text = f"{self.name}: not computed"
        elif self.limit is None:
            text = f"{self.name} {_fmt(self.value)}{unit} (no limit set)"
        else:
            relation = "<=" if self.sense == "max" else ">="
            ok = relation if self.passed else ("exceeds" if self.sense == "max" else "is below")
            text = (f"{self.name} {_fmt(self.value)}{unit} {ok} limit {_fmt(self.limit)}{unit}, "
                    + ("at its limit, " if self.at_limit else "") + f"margin {_fmt(self.margin)}{unit}")
            if self.margin_ratio is not None:
                text += f" ({100 * self.margin_ratio:.3g} %)"
        if self.applies:
            text += f"; {self.applies}"
        if self.note:
            text += f"; {self.note}"
        return text

    def to_dict(self) -> dict:
        """The JSON form: value, limit, margin, margin_ratio, unit, passed, status ("ok", "at limit", "fail"),
        why, applies, note."""
        out = {"value": _json_number(self.value), "limit": _json_number(self.limit),
               "margin": _json_number(self.margin), "margin_ratio": _json_number(self.margin_ratio),
               "unit": self.unit, "sense": self.sense, "passed": self.passed, "status": self.status,
               "why": self.why}
        if self.applies:
            out["applies"] = self.applies
        if self.note:
            out["note"] = self.note
        return out


@dataclass(frozen=True)
class Warning:
    """Something a senior engineer would flag although no limit is violated.

    Parameters
    ----------
    what : str
        One line with the figure that triggered it, e.g. "convex profile radius 1.43 mm is 0.14 of the
        roller radius 10 mm".
    figure : float or None
        That figure.
    rule : str
        The rule that fired, e.g. "convex radius < 0.5 x roller radius".
    """

    what: str
    figure: float | None = None
    rule: str = ""

    def to_dict(self) -> dict:
        return {"what": self.what, "figure": _json_number(self.figure), "rule": self.rule}


@dataclass(frozen=True)
class Verdict:
    """The checks and warnings of one analysis, tightest margin first."""

    checks: tuple[Check, ...] = ()
    warnings: tuple[Warning, ...] = field(default_factory=tuple)

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks)

    @property
    def at_limit(self) -> list[Check]:
        """The checks that pass but end at their limit (``Check.at_limit``): warnings to weigh."""
        return [c for c in self.checks if c.at_limit]

    def tightest(self) -> list[Check]:
        """Checks with a limit, the least relative margin first (failed ones are negative)."""
        limited = [c for c in self.checks if c.limit is not None and c.value is not None]
        return sorted(limited, key=lambda c: (c.margin_ratio if c.margin_ratio is not None else math.inf))

    def to_dict(self) -> dict:
        return {"passed": self.passed,
                "checks": {c.name: c.to_dict() for c in self.checks},
                "tightest": [c.name for c in self.tightest()],
                "at_limit": [c.name for c in self.at_limit],
                "warnings": [w.to_dict() for w in self.warnings]}


def note_line(note: str, indent: str = "  ") -> str:
    """One printed line of a reader's or a model's note: ``warning: …`` for a note that is a warning (its
    text starts with "warning: "), ``note: …`` otherwise.

    >>> note_line("warning: 2 dwells are not at zero"), note_line("3 pieces joined end to end")
    ('  warning: 2 dwells are not at zero', '  note: 3 pieces joined end to end')
    """
    return f"{indent}{note}" if note.startswith("warning: ") else f"{indent}note: {note}"


def _fmt(value: float | None) -> str:
    if value is None:
        return "-"
    if not math.isfinite(value):
        return "inf" if value > 0 else ("-inf" if value < 0 else "nan")
    return f"{value:.4g}"


def _json_number(value: float | None) -> float | None:
    """JSON has no inf or nan: they become None (the ``why`` text says what they were)."""
    if value is None or not math.isfinite(value):
        return None
    return rounded(float(value))
