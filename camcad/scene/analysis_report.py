"""What every analysis returns: the phase angles it ran with and its report object.

- ``PhaseAngles``: which phase angles an analysis ran with (the law's own, or the optimised cyclogram's).
- ``AnalysisReport``: the analysis object under its docs/INTERFACE.md key (figures, ``checks``, ``warnings``,
  ``passed``), the source it ran on, and the objects the plots need. ``to_dict`` is the JSON of the
  command; ``analysis_dict`` the object the pipeline puts in report.json — one definition of each key.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from camcad.verdict import Verdict, rounded


@dataclass(frozen=True)
class PhaseAngles:
    """Which phase angles an analysis ran with: ``source`` "law" (the law's own: given, detected or the
    scene's [law] phases) or "cyclogram" (the optimised cyclogram's, as ``camcad profile`` uses them),
    the phases (start_deg, end_deg, kind) and a note (e.g. held at a limit by the cyclogram)."""

    source: str
    phases_deg: tuple[tuple[float, float, str], ...]
    note: str = ""

    @property
    def text(self) -> str:
        """"0:90:dwell,90:180:rise,..." (deg)."""
        return ",".join(f"{float(a):.10g}:{float(b):.10g}:{k}" for a, b, k in self.phases_deg)

    def describe(self) -> str:
        """One line: whose phase angles, and the motions' angles."""
        motions = ", ".join(f"{k} {rounded(float(b) - float(a), 6):g} deg" for a, b, k in self.phases_deg
                            if k != "dwell")
        whose = "the cyclogram's phase angles" if self.source == "cyclogram" else "the law's own phase angles"
        return f"{whose} ({motions})" if motions else whose

    def to_dict(self) -> dict:
        out = {"source": self.source, "phases": self.text}
        if self.note:
            out["note"] = self.note
        return out

    @classmethod
    def of_law(cls, law, source: str = "law", note: str = "") -> PhaseAngles:
        return cls(source, tuple((math.degrees(p.start), math.degrees(p.end), p.kind) for p in law.phases), note)



def rounded_tree(value: Any, digits: int | None = None) -> Any:
    """Every float in a JSON-like tree rounded to its meaningful digits (``camcad.verdict.rounded``).

    Examples
    --------
    >>> rounded_tree({"a": [169.99999999999997, 1], "b": {"c": 0.30000000000000004}})
    {'a': [170.0, 1], 'b': {'c': 0.3}}
    """
    if isinstance(value, dict):
        return {k: rounded_tree(v, digits) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [rounded_tree(v, digits) for v in value]
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        return rounded_tree(value.tolist(), digits)
    if isinstance(value, float):
        return rounded(value) if digits is None else rounded(value, digits)
    return value


@dataclass
class AnalysisReport:
    """What an analysis command returns (module docstring).

    ``key``: the docs/INTERFACE.md key of the analysis object (spectrum, dynamics, impact, contact, cyclogram);
    ``body``: its figures; ``verdict``: its checks and warnings; ``source``: ``AnalysisSource.summary()``
    (or the scene for contact and cyclogram); ``result``: the analysis objects the plots need;
    ``skipped``: steps not run and why.
    """

    key: str
    body: dict
    verdict: Verdict
    source: dict = field(default_factory=dict)
    result: Any = None
    skipped: dict = field(default_factory=dict)

    @property
    def passed(self) -> bool:
        return self.verdict.passed

    @property
    def exit_code(self) -> int:
        """docs/INTERFACE.md: 0 when every check passed, 1 when one failed."""
        return 0 if self.passed else 1

    def analysis_dict(self) -> dict:
        """The analysis object: its figures, ``passed``, ``checks``, ``tightest`` and ``warnings`` (rounded)."""
        return rounded_tree({**self.body, **self.verdict.to_dict()})

    def to_dict(self) -> dict:
        """The command's JSON: the source, the phase angles analysed and the analysis object."""
        out = rounded_tree(dict(self.source))
        if self.skipped:
            out["skipped"] = dict(self.skipped)
        out[self.key] = self.analysis_dict()
        return out
