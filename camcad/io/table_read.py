"""Reading a law from a text table: two columns, cam angle θ (deg) and acceleration analog a.

Accepted: comma, semicolon, tab or whitespace separators; values in double quotes (as spreadsheets
write them); a decimal comma when the separator is a semicolon or a tab, or inside quoted values of
a comma-separated file; '#' comments; a header line of column names; UTF-8 (with or without a
byte-order mark) or UTF-16 text. Rows out of angle order are sorted (stably, so the two rows of a
jump keep their order) and the report says so. A comma-separated file whose rows have more fields
than its header (unquoted decimal commas: "90,1,5") is ambiguous and refused with a line saying how
to save it. Only regular files are read, at most ``input_file.MAX_INPUT_BYTES``.
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from camcad.errors import CamcadError
from camcad.io.input_file import decode_text, read_input

TABLE_SUFFIXES = (".csv", ".txt", ".tsv", ".dat", ".tab")
#: the most lines a law table may have (a drawn law has hundreds of rows, a law sampled every 0.001 deg 360,001;
#: checked before any line is parsed: 500,000 rows take about 4 s to read)
MAX_TABLE_LINES = 500_000


@dataclass(frozen=True)
class Table:
    theta_deg: np.ndarray
    accel: np.ndarray
    delimiter: str          # as found: ",", ";", "\t" or " "
    decimal_comma: bool
    line_numbers: np.ndarray  # 1-based line of each row in the file
    notes: tuple[str, ...] = ()


def read_table(path: str | Path) -> Table:
    """Read a two-column law table (see the module docstring for the dialects).

    Parameters
    ----------
    path : str or Path
        The table file.

    Returns
    -------
    Table
        θ (deg) and a per row, in angle order, with the dialect found and notes.

    Raises
    ------
    CamcadError
        Not a readable table: one line naming the file and, where it applies, the line.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "law.csv"
    >>> _ = f.write_text('"theta";"a"\\n"0";"0,5"\\n"90";"-1,25"\\n')
    >>> t = read_table(f)
    >>> t.theta_deg.tolist(), t.accel.tolist(), t.delimiter, t.decimal_comma
    ([0.0, 90.0], [0.5, -1.25], ';', True)
    """
    path = Path(path)
    where = str(path)
    raw = read_input(path, "a .csv/.txt table of angle (deg) and acceleration")
    text, encoding = decode_text(raw)
    if "\x00" in text[:4096]:
        raise CamcadError("binary data, not a text table", where,
                          "give a .csv/.txt table of angle (deg) and acceleration, or a DXF drawing")
    line_count = text.count("\n") + 1
    if line_count > MAX_TABLE_LINES:
        raise CamcadError(f"the table has {line_count:,} lines, more than camcad reads ({MAX_TABLE_LINES:,})", where,
                          "give the law with fewer rows (a drawn law needs hundreds)")
    rows: list[tuple[int, str]] = []
    for number, line in enumerate(text.splitlines(), start=1):
        content = line.split("#", 1)[0].strip()
        if content:
            rows.append((number, content))
    if not rows:
        raise CamcadError("the table is empty", where, "add rows 'angle_deg, acceleration'")
    delimiter = _delimiter([content for _, content in rows[:50]])
    split = [(number, _split(content, delimiter)) for number, content in rows]
    quoted = any('"' in content for _, content in rows)
    decimal_comma = any(re.search(r"\d,\d", f) for _, fields in split for f in fields[:2]) and \
        (delimiter in (";", "\t") or quoted)
    if delimiter == "," and not quoted:
        _refuse_ambiguous_commas(split, where)
    theta, accel, lines = [], [], []
    for index, (number, fields) in enumerate(split):
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
            raise CamcadError(f"line {number}: {_excerpt(bad)} is not a number", where, "fix or delete that line")
        if not (math.isfinite(values[0]) and math.isfinite(values[1])):
            raise CamcadError(f"line {number}: non-finite value ({_excerpt(fields[0])}, {_excerpt(fields[1])})", where,
                              "give finite numbers")
        theta.append(values[0])
        accel.append(values[1])
        lines.append(number)
    theta_arr = np.array(theta, dtype=float)
    accel_arr = np.array(accel, dtype=float)
    line_arr = np.array(lines, dtype=int)
    notes: list[str] = []
    if encoding not in ("utf-8", "latin-1"):
        notes.append(f"the table is {encoding.upper()} text" if encoding != "utf-8-sig"
                     else "the table starts with a UTF-8 byte-order mark (ignored)")
    if decimal_comma:
        notes.append("decimal commas read as decimal points")
    if np.any(np.diff(theta_arr) < 0):
        order = np.argsort(theta_arr, kind="stable")
        theta_arr, accel_arr, line_arr = theta_arr[order], accel_arr[order], line_arr[order]
        notes.append("rows were not in angle order; sorted by angle (rows of equal angle keep their order)")
    return Table(theta_arr, accel_arr, delimiter, decimal_comma, line_arr, tuple(notes))


def _refuse_ambiguous_commas(split: list[tuple[int, list[str]]], where: str) -> None:
    """Unquoted comma-separated rows with more fields than the header, or (without a header) with
    varying numbers of fields: decimal commas that cannot be told from separators ("90,1,5" is 90
    and 1.5, or 90.1 and 5)."""
    numeric = [(n, f) for n, f in split if all(_number(v) is not None for v in f)]
    if not numeric:
        return
    header = split[0][1] if len(numeric) < len(split) else None
    widths = {len(f) for _, f in numeric}
    width = len(header) if header else min(widths)
    if header is None and len(widths) == 1:
        return
    for number, fields in numeric:
        if len(fields) > width:
            raise CamcadError(f"line {number} has {len(fields)} comma-separated fields "
                              f"({_excerpt(','.join(fields))}): decimal commas and comma separators "
                              "cannot be told apart", where,
                              "save the table with ';' as separator, or with decimal points, or quote the values")


def _excerpt(text: str, limit: int = 24) -> str:
    """A short, quoted excerpt of a value for an error message."""
    text = " ".join(str(text).split())
    return repr(text if len(text) <= limit else text[: limit - 3] + "...")


def _delimiter(samples: list[str]) -> str:
    for candidate in (";", "\t", ","):
        if all(candidate in s for s in samples[1:] or samples):
            return candidate
    return " "


def _split(content: str, delimiter: str) -> list[str]:
    if delimiter == " ":
        return content.split()
    fields = next(csv.reader([content], delimiter=delimiter, quotechar='"', skipinitialspace=True), [])
    return [f.strip() for f in fields if f.strip() != ""]


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
