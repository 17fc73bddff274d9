"""Reading a law from a text table: two columns, cam angle θ (deg) and acceleration analog a.

Accepted: comma, semicolon, tab or whitespace separators; a decimal comma when the separator is a
semicolon or a tab; '#' comments; a header line of column names. Rows out of angle order are
sorted (stably, so the two rows of a jump keep their order) and the report says so.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from camcad.errors import CamcadError

TABLE_SUFFIXES = (".csv", ".txt", ".tsv", ".dat", ".tab")


@dataclass(frozen=True)
class Table:
    theta_deg: np.ndarray
    accel: np.ndarray
    delimiter: str          # as found: ",", ";", "\t" or " "
    decimal_comma: bool
    line_numbers: np.ndarray  # 1-based line of each row in the file
    notes: tuple[str, ...] = ()


def read_table(path: str | Path) -> Table:
    path = Path(path)
    where = str(path)
    if not path.exists():
        raise CamcadError("file not found", where, "check the path")
    raw = path.read_bytes()
    if b"\x00" in raw[:4096]:
        raise CamcadError("binary data, not a text table", where,
                          "give a .csv/.txt table of angle (deg) and acceleration, or a DXF drawing")
    text = raw.decode("utf-8-sig", errors="replace")
    rows: list[tuple[int, str]] = []
    for number, line in enumerate(text.splitlines(), start=1):
        content = line.split("#", 1)[0].strip()
        if content:
            rows.append((number, content))
    if not rows:
        raise CamcadError("the table is empty", where, "add rows 'angle_deg, acceleration'")
    delimiter = _delimiter([content for _, content in rows[:50]])
    decimal_comma = delimiter in (";", "\t") and any(re.search(r"\d,\d", c) for _, c in rows)
    theta, accel, lines = [], [], []
    for index, (number, content) in enumerate(rows):
        fields = _split(content, delimiter)
        if decimal_comma:
            fields = [f.replace(",", ".") for f in fields]
        values = [_number(f) for f in fields]
        if index == 0 and any(v is None for v in values[:2]):
            continue  # a header line of column names
        if len(fields) < 2:
            raise CamcadError(f"line {number} has {len(fields)} column, need 2 (angle_deg, acceleration)",
                              where, "write one angle and one acceleration per line")
        if values[0] is None or values[1] is None:
            bad = fields[0] if values[0] is None else fields[1]
            raise CamcadError(f"line {number}: {bad!r} is not a number", where, "fix or delete that line")
        if not (math.isfinite(values[0]) and math.isfinite(values[1])):
            raise CamcadError(f"line {number}: non-finite value ({fields[0]}, {fields[1]})", where,
                              "give finite numbers")
        theta.append(values[0])
        accel.append(values[1])
        lines.append(number)
    theta_arr = np.array(theta, dtype=float)
    accel_arr = np.array(accel, dtype=float)
    line_arr = np.array(lines, dtype=int)
    notes: list[str] = []
    if np.any(np.diff(theta_arr) < 0):
        order = np.argsort(theta_arr, kind="stable")
        theta_arr, accel_arr, line_arr = theta_arr[order], accel_arr[order], line_arr[order]
        notes.append("rows were not in angle order; sorted by angle (rows of equal angle keep their order)")
    return Table(theta_arr, accel_arr, delimiter, decimal_comma, line_arr, tuple(notes))


def _delimiter(samples: list[str]) -> str:
    for candidate in (";", "\t", ","):
        if all(candidate in s for s in samples[1:] or samples):
            return candidate
    return " "


def _split(content: str, delimiter: str) -> list[str]:
    if delimiter == " ":
        return content.split()
    return [f.strip() for f in content.split(delimiter) if f.strip() != ""]


def _number(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


def write_table(path: Path, theta_deg: np.ndarray, accel: np.ndarray, delimiter: str = ",",
                decimal_comma: bool = False, header: str = "theta_deg,accel") -> None:
    """Write a two-column law table in the same dialect it was read in (not atomic; see io.atomic)."""
    sep = delimiter if delimiter != " " else " "
    lines = [f"# {header.replace(',', sep)}"]
    for t, a in zip(theta_deg, accel):
        row = f"{t:.10g}{sep}{a:.12g}"
        if decimal_comma:
            row = row.replace(".", ",")
        lines.append(row)
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")
