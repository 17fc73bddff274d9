"""Reading a law from a text table: cam angle θ (deg) and one column of the motion, its kind named by the header.

Kinds (docs/INTERFACE.md "Tables name their kind in the header"; the first column is the cam angle θ in deg):

=====================================  ==========================================================
header                                 the second column is
=====================================  ==========================================================
``theta_deg,a…`` (a, accel, a_mm…)     the acceleration analog a (mm/rad²), as before
no header                              the acceleration analog a (mm/rad²), as before
``theta_deg,s_mm``                     the follower's displacement s (mm)
``theta_deg,psi_deg`` / ``psi_rad``    the swing ψ of an oscillating follower (deg or rad)
``theta_deg,r_mm``                     radius-vectors of the cam profile (mm; θ is the polar angle)
=====================================  ==========================================================

A header whose law column camcad does not know is refused (one line naming the columns camcad reads),
never read as an acceleration. A table with several columns is read by the one that gives the law most
directly: an acceleration column when there is one (camcad's own ``law.csv`` and ``filtered.csv`` hold
s, v, a and j: their ``a_mm_per_rad2`` is the law exactly), else its one motion column; the other
columns are named in a note. A comment line ``# camcad-law: {...}`` is the record camcad writes with
its laws (``camcad.io.law_record``): the table's phase angles and the rule it was judged by.

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
from camcad.io.law_record import LawRecord, record_of_comment, table_line

TABLE_SUFFIXES = (".csv", ".txt", ".tsv", ".dat", ".tab")
#: the kinds of law column, and the unit of each
TABLE_KINDS = {"acceleration": "mm/rad^2", "displacement": "mm", "swing_deg": "deg", "swing_rad": "rad",
               "radius": "mm"}
#: the headers camcad reads, for messages
KNOWN_HEADERS = "theta_deg with a (acceleration), s_mm, psi_deg, psi_rad or r_mm"

_ANGLE = re.compile(r"^(theta|θ|phi|φ|fi|angle|cam|alpha|α|deg|x$|x_)")
_ACCEL = re.compile(r"^(a|a_.*|acc.*|y|y_.*)$")
_DISPLACEMENT = re.compile(r"^(s|s_mm|s_mm_.*|displacement(_mm)?|lift(_mm)?|stroke(_mm)?)$")
_SWING_DEG = re.compile(r"^(psi|ψ|swing)_(deg|degrees?)$")
_SWING_RAD = re.compile(r"^(psi|ψ|swing)_rad(ians?)?$")
_SWING_BARE = re.compile(r"^(psi|ψ|swing)$")
_RADIUS = re.compile(r"^(r|r_mm|radius(_mm)?|rho(_mm)?|radius_vector(_mm)?)$")
#: further columns that camcad's own law tables hold beside their law column
_DERIVED = re.compile(r"^(v|v_.*|j|j_.*|s|s_.*|vel.*|jerk.*)$")
#: the most lines a law table may have (a drawn law has hundreds of rows, a law sampled every 0.001 deg 360,001;
#: checked before any line is parsed: 500,000 rows take about 4 s to read)
MAX_TABLE_LINES = 500_000


@dataclass(frozen=True)
class Table:
    """A table as read: θ (deg) and the values of its law column, of the ``kind`` the header names.

    ``values`` are accelerations (mm/rad²), displacements (mm), swings (deg or rad) or radius-vectors
    (mm) per ``kind`` (``TABLE_KINDS``); ``accel`` is the same array under its old name. ``record`` is
    the ``LawRecord`` of a table camcad wrote (its phases and the rule it was judged by), else None.
    """

    theta_deg: np.ndarray
    values: np.ndarray
    delimiter: str          # as found: ",", ";", "\t" or " "
    decimal_comma: bool
    line_numbers: np.ndarray  # 1-based line of each row in the file
    notes: tuple[str, ...] = ()
    kind: str = "acceleration"
    header: tuple[str, ...] = ()
    column: int = 1
    record: LawRecord | None = None

    @property
    def accel(self) -> np.ndarray:
        """The law column's values (the acceleration for an acceleration table)."""
        return self.values

    @property
    def unit(self) -> str:
        return TABLE_KINDS[self.kind]


def read_table(path: str | Path) -> Table:
    """Read a two-column law table (see the module docstring for the dialects).

    Parameters
    ----------
    path : str or Path
        The table file.

    Returns
    -------
    Table
        θ (deg) and the law column per row, in angle order, with its kind, the dialect found, notes
        and the record camcad wrote with it (if any).

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
    line_count = text.count("\n") + (0 if text.endswith("\n") else 1)   # a last newline ends a line
    if line_count > MAX_TABLE_LINES:
        raise CamcadError(f"the table has {line_count:,} lines, more than camcad reads ({MAX_TABLE_LINES:,})", where,
                          "give the law with fewer rows (a drawn law needs hundreds)")
    fast = read_plain_table(text, where)
    if fast is not None:
        theta_arr, accel_arr, line_arr, found_delimiter, found_header, found_kind, found_column, found_notes, \
            found_record = fast
        return _table(theta_arr, accel_arr, line_arr, found_delimiter, False, found_header, found_kind, found_column,
                      found_notes, found_record, encoding)
    rows: list[tuple[int, str]] = []
    record = None
    for number, line in enumerate(text.splitlines(), start=1):
        content, _, comment = line.partition("#")
        content = content.strip()
        if comment and not content:
            try:
                found = record_of_comment(comment)
            except ValueError as err:
                raise CamcadError(f"line {number}: camcad's record of the law cannot be read ({err})", where,
                                  "delete that comment line, or write the table again with camcad") from None
            record = found or record
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
    kind, column = "acceleration", 1
    header: tuple[str, ...] = ()
    header_notes: list[str] = []
    for index, (number, fields) in enumerate(split):
        if index == 0 and any(_number(f.replace(",", ".") if decimal_comma else f) is None for f in fields[:2]):
            header = tuple(fields)
            kind, column, header_notes = header_kind(header, where, number)
            continue  # a header line of column names
        if decimal_comma:
            fields = [f.replace(",", ".") for f in fields]
        values = [_number(f) for f in fields]
        if len(fields) < 2:
            raise CamcadError(f"line {number} has {len(fields)} column, need 2 (angle_deg, acceleration)",
                              where, "write one angle and one acceleration per line")
        if len(fields) <= column:
            raise CamcadError(f"line {number} has {len(fields)} columns, the header names {column + 1}", where,
                              "give every row a value in each column of the header")
        first, value = values[0], values[column]
        if first is None or value is None:
            bad = fields[0] if first is None else fields[column]
            raise CamcadError(f"line {number}: {_excerpt(bad)} is not a number", where, "fix or delete that line")
        if not (math.isfinite(first) and math.isfinite(value)):
            raise CamcadError(f"line {number}: non-finite value ({_excerpt(fields[0])}, {_excerpt(fields[column])})",
                              where, "give finite numbers")
        theta.append(first)
        accel.append(value)
        lines.append(number)
    if not theta:
        raise CamcadError("the table has a header but no rows", where, "add rows 'angle_deg, value'")
    return _table(np.array(theta, dtype=float), np.array(accel, dtype=float), np.array(lines, dtype=int), delimiter,
                  decimal_comma, header, kind, column, header_notes, record, encoding)


def _table(theta_arr: np.ndarray, accel_arr: np.ndarray, line_arr: np.ndarray, delimiter: str, decimal_comma: bool,
           header: tuple[str, ...], kind: str, column: int, header_notes: list[str], record: LawRecord | None,
           encoding: str) -> Table:
    """The Table of rows as read: notes on the encoding and the decimal commas, rows sorted by angle."""
    notes: list[str] = list(header_notes)
    if encoding not in ("utf-8", "latin-1"):
        notes.append(f"the table is {encoding.upper()} text" if encoding != "utf-8-sig"
                     else "the table starts with a UTF-8 byte-order mark (ignored)")
    if decimal_comma:
        notes.append("decimal commas read as decimal points")
    if np.any(np.diff(theta_arr) < 0):
        order = np.argsort(theta_arr, kind="stable")
        theta_arr, accel_arr, line_arr = theta_arr[order], accel_arr[order], line_arr[order]
        notes.append("rows were not in angle order; sorted by angle (rows of equal angle keep their order)")
    return Table(theta_arr, accel_arr, delimiter, decimal_comma, line_arr, tuple(notes), kind, header, column,
                 record)


#: the first lines a plain table may spend on comments and blank lines before its first row
_PLAIN_HEAD_LINES = 200


def read_plain_table(text: str, where: str):
    """The fast path of ``read_table``: a plain table (no quotes, no comment or blank line after its first row,
    decimal points, the same number of numeric fields in every row, finite values) parsed by
    ``numpy.loadtxt``. None for anything else, which the careful reader then reads (and explains)."""
    import io

    if '"' in text:
        return None
    record, number, pos = None, 0, 0
    while True:                                   # leading comment and blank lines, then the first row
        end = text.find("\n", pos)
        line = text[pos:] if end < 0 else text[pos:end]
        number += 1
        content, _, comment = line.partition("#")
        if content.strip():
            break
        if comment:
            try:
                record = record_of_comment(comment) or record
            except ValueError:
                return None                       # the careful reader says what is wrong with it
        if end < 0 or number > _PLAIN_HEAD_LINES:
            return None
        pos = end + 1
    if "#" in text[pos:]:
        return None
    samples = text[pos:pos + 16384].split("\n")[:50]
    samples = [s.strip() for s in (samples[:-1] if len(samples) > 1 else samples) if s.strip()]
    delimiter = _delimiter(samples)
    if delimiter in (";", "\t") and "," in text[pos:]:
        return None                               # decimal commas
    first = _split(samples[0], delimiter)
    header: tuple[str, ...] = ()
    kind, column = "acceleration", 1
    notes: list[str] = []
    first_row = number
    if any(_number(f) is None for f in first[:2]):
        header = tuple(first)
        kind, column, notes = header_kind(header, where, number)
        end = text.find("\n", pos)
        if end < 0:
            return None
        pos, first_row = end + 1, number + 1
    body = text[pos:]
    expected = body.count("\n") + (0 if body.endswith("\n") or not body else 1)
    if expected == 0:
        return None
    try:
        values = np.loadtxt(io.StringIO(body), delimiter=None if delimiter == " " else delimiter, ndmin=2,
                            dtype=float, comments=None)
    except ValueError:
        return None
    columns = values.shape[1]
    if len(values) != expected or columns < 2 or column >= columns or (header and len(header) != columns):
        return None                               # blank lines, ragged or ambiguous rows: read carefully
    theta, law = values[:, 0], values[:, column]
    if not (np.all(np.isfinite(theta)) and np.all(np.isfinite(law))):
        return None
    lines = np.arange(first_row, first_row + len(values))
    return theta.copy(), law.copy(), lines, delimiter, header, kind, column, notes, record


def _name(text: str) -> str:
    """A column name reduced for matching: lower case, no quotes, units in brackets joined with '_'
    ("Theta (deg)" -> "theta_deg", "a [mm/rad²]" -> "a_mm/rad²")."""
    name = text.strip().strip('"').strip("'").lower()
    name = re.sub(r"[\s\(\)\[\]{}]+", "_", name)
    return re.sub(r"_+", "_", name).strip("_")


def header_kind(header: tuple[str, ...], where: str = "table", line: int = 1) -> tuple[str, int, list[str]]:
    """(kind, index of the law column, notes) of a table's header (module docstring's table).

    Raises CamcadError (one line, exit 2) for a header whose law column camcad does not know.

    Examples
    --------
    >>> header_kind(("theta_deg", "s_mm"))[:2]
    ('displacement', 1)
    >>> header_kind(("theta_deg", "s_mm", "v_mm_per_rad", "a_mm_per_rad2", "j_mm_per_rad3"))[:2]
    ('acceleration', 3)
    >>> header_kind(("theta_deg", "torque_Nm"))
    Traceback (most recent call last):
    ...
    camcad.errors.CamcadError: table: line 1: the header names the columns 'theta_deg', 'torque_Nm'; camcad reads a law from theta_deg with a (acceleration), s_mm, psi_deg, psi_rad or r_mm; name the columns so (or remove the header line: an unnamed second column is the acceleration)
    """  # noqa: E501 - a doctest's expected output is one line
    names = [_name(h) for h in header]
    listed = ", ".join(_excerpt(h) for h in header[:6]) + (", ..." if len(header) > 6 else "")
    fix = "name the columns so (or remove the header line: an unnamed second column is the acceleration)"
    refuse = CamcadError(f"line {line}: the header names the columns {listed}; camcad reads a law from "
                         f"{KNOWN_HEADERS}", where, fix)
    if len(names) < 2 or not _ANGLE.match(names[0]):
        raise refuse
    kinds = []
    for index, name in enumerate(names[1:], start=1):
        if _ACCEL.match(name):
            kinds.append(("acceleration", index))
        elif _DISPLACEMENT.match(name):
            kinds.append(("displacement", index))
        elif _SWING_DEG.match(name):
            kinds.append(("swing_deg", index))
        elif _SWING_RAD.match(name):
            kinds.append(("swing_rad", index))
        elif _RADIUS.match(name):
            kinds.append(("radius", index))
        elif _SWING_BARE.match(name):
            raise CamcadError(f"line {line}: the column {_excerpt(header[index])} does not say its unit", where,
                              "name it psi_deg or psi_rad")
    if not kinds:
        raise refuse
    chosen = next((k for k in kinds if k[0] == "acceleration"), None)
    if chosen is None:
        motion = {k for k, _ in kinds}
        if len(motion) > 1:
            raise CamcadError(f"line {line}: the header names {len(motion)} kinds of law ({listed})", where,
                              "keep one law column: s_mm, psi_deg, psi_rad or r_mm")
        chosen = kinds[0]
    kind, column = chosen
    notes = []
    others = [header[i] for i in range(1, len(header)) if i != column]
    if others:
        notes.append(f"the law is read from the column {header[column]!r} ({kind}); "
                     f"the column{'s' if len(others) > 1 else ''} {', '.join(repr(o) for o in others)} "
                     "ignored")
    return kind, column, notes


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
                decimal_comma: bool = False, header: str = "theta_deg,accel", record: LawRecord | None = None) -> None:
    """Write a two-column law table in the same dialect it was read in (not atomic; see io.atomic); with
    ``record``, its comment line first (``camcad.io.law_record``)."""
    sep = delimiter if delimiter != " " else " "
    lines = [table_line(record)] if record is not None else []
    lines.append(f"# {header.replace(',', sep)}")
    for t, a in zip(theta_deg, accel):
        row = f"{t:.10g}{sep}{a:.12g}"
        if decimal_comma:
            row = row.replace(".", ",")
        lines.append(row)
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")
