"""Plain-text rendering shared by the analysis commands: tables, the verdict (tightest margins first),
warnings and the header every command prints (source, unit, which phase angles were analysed).

Figures are shown to 4 significant digits; the JSON carries them to ``camcad.verdict.REPORT_DIGITS``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

from camcad.verdict import note_line


def fmt(value, digits: int = 4) -> str:
    """A figure for a table: ``digits`` significant digits, "-" for None, "inf" for an unbounded one.

    Examples
    --------
    >>> fmt(169.99999999999997), fmt(None), fmt(float("inf")), fmt(3), fmt(0.000123456)
    ('170', '-', 'inf', '3', '0.0001235')
    """
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, int):
        return str(value)
    value = float(value)
    if not math.isfinite(value):
        return "inf" if value > 0 else ("-inf" if value < 0 else "nan")
    return f"{value:.{digits}g}"


def table(headers: Sequence[str], rows: Iterable[Sequence], title: str = "") -> list[str]:
    """A plain-text table: columns right-aligned except the first, a rule under the headers."""
    rows = [[str(cell) for cell in row] for row in rows]
    widths = [max([len(h)] + [len(row[i]) for row in rows]) for i, h in enumerate(headers)]

    def line(cells):
        return "  ".join(cell.ljust(widths[i]) if i == 0 else cell.rjust(widths[i]) for i, cell in enumerate(cells))

    out = [title] if title else []
    out.append(line(headers))
    out.append("  ".join("-" * w for w in widths))
    out.extend(line(row) for row in rows)
    return out


def header_lines(report) -> list[str]:
    """The source, the unit of the law and the phase angles analysed, and the notes."""
    source = report.source
    lines = []
    where = source.get("where") or source.get("scene", "")
    name = source.get("name", "")
    unit = source.get("unit")
    head = f"{name} ({where})" if where and where != name else name
    if unit:
        head += f"; law in {unit}"
    lines.append(head)
    angles = source.get("phase_angles")
    if isinstance(angles, dict):
        whose = "the cyclogram's" if angles.get("source") == "cyclogram" else "the law's own"
        lines.append(f"phase angles analysed: {whose} ({angles.get('phases', '')})"
                     + (f"; {angles['note']}" if angles.get("note") else ""))
    elif isinstance(angles, str):
        lines.append(f"phase angles analysed: {angles}")
    for note in source.get("notes", []):
        lines.append(note_line(note))
    for what, why in report.skipped.items():
        lines.append(f"  skipped {what}: {why}")
    return lines


def verdict_lines(verdict, common: str = "", details: bool = True) -> list[str]:
    """Checks with a limit, the tightest margin first; then the figures without a limit; then warnings;
    then the one-line verdict. ``common``: a part of every check's ``applies`` already printed in the
    header (e.g. the phase angles), left out of the per-check lines; ``details`` False prints only the
    checks' notes (the JSON keeps what each applies to)."""
    lines = []

    def strip(text: str) -> str:
        if common:
            text = text.replace(f"; {common}", "").replace(common, "")
        return text.strip("; ")

    tight = verdict.tightest()
    if tight:
        rows = []
        for check in tight:
            ratio = check.margin_ratio
            rows.append([check.name, fmt(check.value), fmt(check.limit), fmt(check.margin),
                         "-" if ratio is None else f"{100 * ratio:.3g} %", check.unit or "-",
                         {"ok": "ok", "at limit": "AT LIMIT", "fail": "FAILED"}[check.status]])
        lines += table(["check (tightest margin first)", "value", "limit", "margin", "margin %", "unit", ""], rows)
        for check in tight:
            extra = "; ".join(part for part in ((strip(check.applies) if details else ""), check.note) if part)
            if extra:
                lines.append(f"  {check.name}: {extra}")
    others = [c for c in verdict.checks if c not in tight]
    for check in others:
        lines.append(("" if check.passed else "FAILED: ") + strip(check.why))
    for check in verdict.at_limit:
        lines.append(f"WARNING: {check.name} ends at its limit: no margin")
    for warning in verdict.warnings:
        lines.append(f"WARNING: {warning.what}")
    failed = [c.name for c in verdict.checks if not c.passed]
    held = len(verdict.at_limit)
    tail = f"; {held} at {'its' if held == 1 else 'their'} limit (no margin)" if held else ""
    lines.append("all checks passed" + tail if not failed else f"FAILED: {', '.join(failed)}")
    return lines


def output_lines(outputs) -> list[str]:
    return [f"written: {path}" for path in outputs]


def common_applies(report) -> str:
    """The part every check's ``applies`` ends with (the phase angles of a single-law report), printed once in
    the header; "" when the checks differ there."""
    tails = [c.applies.rsplit("; ", 1)[-1] for c in report.verdict.checks if c.applies]
    if len(tails) != len(report.verdict.checks) or not tails or any(t != tails[0] for t in tails):
        return ""
    return tails[0] if "phase angles" in tails[0] else ""
