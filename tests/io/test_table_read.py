"""Reading law tables: every dialect gives the rows the test wrote, and what cannot be read says why."""

from __future__ import annotations

import numpy as np
import pytest

from camcad.errors import CamcadError
from camcad.io.table_read import read_table, write_table

ROWS = [(0.0, 0.0), (45.0, 1.25), (90.0, -0.5), (135.0, 0.0), (180.0, -1.75), (360.0, 0.0)]


def _text(sep: str, decimal: str = ".", quote: str = "", header: str | None = "theta{sep}a") -> str:
    lines = [header.format(sep=sep)] if header else []
    for t, a in ROWS:
        cells = [f"{t:g}".replace(".", decimal), f"{a:g}".replace(".", decimal)]
        lines.append(sep.join(f"{quote}{c}{quote}" for c in cells))
    return "\n".join(lines) + "\n"


@pytest.mark.reference("property", "every table dialect gives back the rows written")
@pytest.mark.parametrize("name,text,encoding", [
    ("comma", _text(","), "utf-8"),
    ("semicolon_decimal_comma", _text(";", ","), "utf-8"),
    ("tab_decimal_comma", _text("\t", ","), "utf-8"),
    ("whitespace", _text(" ", header=None), "utf-8"),
    ("quoted_comma_decimal_comma", _text(",", ",", '"'), "utf-8"),
    ("quoted_semicolon", _text(";", ",", '"'), "utf-8"),
    ("bom", _text(","), "utf-8-sig"),
    ("utf16", _text(";", ","), "utf-16"),
    ("comments", "# exported\n" + _text(",") + "# end\n", "utf-8"),
    ("crlf", _text(",").replace("\n", "\r\n"), "utf-8"),
])
def test_every_dialect_gives_the_rows_written(tmp_path, name, text, encoding):
    path = tmp_path / f"{name}.csv"
    path.write_bytes(text.encode(encoding))
    table = read_table(path)
    assert table.theta_deg.tolist() == [t for t, _ in ROWS]
    assert table.accel.tolist() == [a for _, a in ROWS]


@pytest.mark.reference("property", "rows sorted by angle, the rows of a jump kept in file order")
def test_rows_out_of_order_are_sorted_keeping_jumps(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text("90,1\n0,0\n90,-1\n45,1\n")
    table = read_table(path)
    assert table.theta_deg.tolist() == [0, 45, 90, 90] and table.accel.tolist() == [0, 1, 1, -1]
    assert table.line_numbers.tolist() == [2, 4, 1, 3]
    assert any("sorted" in n for n in table.notes)


@pytest.mark.reference("property", "a header names the law's column; without one the first two columns")
def test_a_header_names_the_law_column_and_no_header_keeps_the_first_two(tmp_path):
    path = tmp_path / "law.csv"
    path.write_text("theta_deg,s_mm,a\n0,0,0\n90,1.5,2\n")
    assert read_table(path).accel.tolist() == [0.0, 2.0] and read_table(path).kind == "acceleration"
    headerless = tmp_path / "three.csv"
    headerless.write_text("0,0,0\n90,1.5,2\n")
    assert read_table(headerless).accel.tolist() == [0.0, 1.5]


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
@pytest.mark.parametrize("text,expected", [
    ("theta,a\n0,0\n90,1,5\n", "line 3 has 3 comma-separated fields"),
    ("0,0\n90,1,5\n180,0\n", "decimal commas and comma separators cannot be told apart"),
    ("theta,a\n0,zero\n", "line 2: 'zero' is not a number"),
    ("theta,a\n0,inf\n", "non-finite"),
    ("# nothing\n", "the table is empty"),
    ("0\n", "line 1 has 1 column"),
])
def test_what_cannot_be_read_says_why_in_one_line(tmp_path, text, expected):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(CamcadError) as caught:
        read_table(path)
    message = caught.value.message()
    assert expected in message and "\n" not in message and len(message) < 300


@pytest.mark.reference("property", "bad input: refused in one line naming the part at fault (docs/INTERFACE.md)")
def test_binary_data_is_not_a_table(tmp_path):
    path = tmp_path / "bin.csv"
    path.write_bytes(bytes(range(256)) * 8)
    with pytest.raises(CamcadError, match="binary data, not a text table"):
        read_table(path)


@pytest.mark.reference("property", "a table written by numpy in each dialect reads back to 1e-12")
@pytest.mark.parametrize("delimiter,decimal_comma", [(",", False), (";", True), ("\t", True)])
def test_written_tables_read_back(tmp_path, delimiter, decimal_comma):
    theta = np.array([0.0, 12.5, 90.0, 360.0])
    accel = np.array([0.0, -1.0 / 3.0, 2.5e-7, 0.0])
    path = tmp_path / "w.csv"
    write_table(path, theta, accel, delimiter, decimal_comma)
    table = read_table(path)
    assert np.array_equal(table.theta_deg, theta)
    assert np.allclose(table.accel, accel, rtol=1e-12, atol=0)
    assert table.delimiter == delimiter and table.decimal_comma == decimal_comma
