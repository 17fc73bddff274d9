"""Identical inputs and options give byte-identical outputs (issue 19 item 6): every kind of DXF, CSV and
JSON camcad writes, run twice with ezdxf's clock moved between (ezdxf would stamp the time and a random
GUID), nothing on stderr. With SOURCE_DATE_EPOCH set, camcad's own drawings carry that time."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from conftest import SAMPLES

from camcad.io.law_write import write_corrected_drawing, write_law_csv, write_law_dxf
from camcad.law.source import load_law


@pytest.fixture(autouse=True)
def moving_clock(monkeypatch):
    """ezdxf's clock jumps an hour at every reading: a time stamp anywhere in an output would show."""
    import datetime as real

    import ezdxf.document

    class Clock(real.datetime):
        calls = 0

        @classmethod
        def now(cls, tz=None):
            cls.calls += 1
            return real.datetime(2024, 5, 1, tzinfo=tz) + real.timedelta(hours=cls.calls)

    monkeypatch.setattr(ezdxf.document, "datetime", Clock)
    return Clock


def _twice(make, tmp_path: Path) -> list[dict[str, bytes]]:
    """Run ``make(folder)`` twice into the same folder; the bytes of every file each time."""
    results = []
    for _ in range(2):
        folder = tmp_path / "out"
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir()
        make(folder)
        results.append({p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*"))
                        if p.is_file()})
    return results


def _same(first: dict[str, bytes], second: dict[str, bytes], suffixes: set[str]) -> None:
    assert first.keys() == second.keys()
    assert suffixes <= {Path(name).suffix for name in first}
    for name, data in first.items():
        assert data == second[name], name


@pytest.mark.reference("property", "two runs under a moved clock: byte-identical outputs, nothing on stderr")
@pytest.mark.parametrize("options", [[], ["--r12"], ["--arcs"], ["--spline"]], ids=["r2000", "r12", "arcs", "spline"])
def test_profile_outputs_are_byte_identical(cli, tmp_path, options):
    law = SAMPLES / "dxf" / "balanced_drdr_cycloidal.dxf"

    def make(folder):
        result = cli("profile", law, "--rb", "40", "--rr", "8", "-o", folder, "--no-plots", *options)
        assert result.code in (0, 1), result.err
        assert result.err == ""

    first, second = _twice(make, tmp_path)
    _same(first, second, {".dxf", ".csv", ".json"})


@pytest.mark.reference("property", "two runs under a moved clock: byte-identical outputs")
def test_law_dxf_and_csv_are_byte_identical(tmp_path):
    theta = np.linspace(0, 360, 361)
    accel = np.sin(np.radians(2 * theta))

    def make(folder):
        from camcad.law.law import PiecewiseLinearLaw

        write_law_dxf(folder / "law.dxf", theta, accel)
        write_law_dxf(folder / "law12.dxf", theta, accel, r12=True)
        law = PiecewiseLinearLaw(np.radians(theta), accel, 2 * np.pi)
        write_law_csv(folder / "law.csv", law.kinematics(np.radians(theta)))

    first, second = _twice(make, tmp_path)
    _same(first, second, {".dxf", ".csv"})


@pytest.mark.reference("property", "two runs under a moved clock: byte-identical outputs, nothing on stderr")
@pytest.mark.parametrize("name", ["fig2_rise_area_too_large.dxf", "r12_polyline_harmonic.dxf", "spline_law.dxf",
                                  "line_chain_trapezoid.dxf"])
def test_fix_outputs_are_byte_identical(cli, tmp_path, name):
    source = tmp_path / name
    shutil.copy(SAMPLES / "dxf" / name, source)

    def make(folder):
        result = cli("fix", source, "-o", folder / "fixed.dxf", "--json")
        assert result.code == 0, result.err
        assert result.err == ""
        (folder / "fix.json").write_text(result.out)
        table = cli("fix", source, "-o", folder / "fixed.csv", "--json", "--no-plots")
        assert table.code == 0 and table.err == ""

    first, second = _twice(make, tmp_path)
    _same(first, second, {".dxf", ".csv", ".json", ".png"})


@pytest.mark.reference("property", "a CR LF drawing corrected twice: byte-identical, CR LF kept")
def test_corrected_crlf_drawing_is_byte_identical(tmp_path):
    # a drawing saved with CR LF line ends, as AutoCAD does: a law (a rise over 0..180, a return after) and its axis
    import io

    import ezdxf
    import numpy as np

    doc = ezdxf.new("R2000")
    x = np.linspace(0, 360, 73)
    a = 10 * np.sin(np.radians(2 * x)) * np.where(x <= 180, 1.0, -1.0)
    doc.modelspace().add_lwpolyline(list(zip(x, a)), dxfattribs={"layer": "LAW"})
    doc.modelspace().add_line((0, 0), (360, 0), dxfattribs={"layer": "AXES"})
    text = io.StringIO()
    doc.write(text)
    path = tmp_path / "crlf_input.dxf"
    path.write_bytes(text.getvalue().replace("\n", "\r\n").encode("ascii"))
    loaded = load_law(path)

    def make(folder):
        write_corrected_drawing(loaded, loaded.law.with_ordinates(loaded.law.a * 0.5), folder / "fixed.dxf")

    first, second = _twice(make, tmp_path)
    _same(first, second, {".dxf"})
    assert b"\r\n" in first["fixed.dxf"][:100]


@pytest.mark.reference("closed form", "the DXF Julian date of SOURCE_DATE_EPOCH: 1970-01-01 is day 2440588, "
                                      "2000-01-01 day 2451545")
def test_source_date_epoch_sets_the_stamps_of_camcads_own_drawings(tmp_path, monkeypatch):
    import ezdxf

    epoch = 1_700_000_000                      # 2023-11-14 22:13:20 UTC
    monkeypatch.setenv("SOURCE_DATE_EPOCH", str(epoch))
    path = write_law_dxf(tmp_path / "law.dxf", np.array([0.0, 180.0, 360.0]), np.array([0.0, 1.0, 0.0]))
    text = path.read_text()
    # DXF date: the Julian day number of the civil date plus the fraction of the day since midnight
    # (AutoCAD's "Julian date"); the Unix epoch's day, 1970-01-01, has the Julian day number 2440588
    julian = epoch / 86400.0 + 2440588.0
    value = float(text.split("$TDCREATE")[1].split("\n")[2])
    assert value == pytest.approx(julian, abs=1e-6)
    monkeypatch.delenv("SOURCE_DATE_EPOCH")
    plain = write_law_dxf(tmp_path / "law2.dxf", np.array([0.0, 180.0, 360.0]), np.array([0.0, 1.0, 0.0]))
    value = float(plain.read_text().split("$TDCREATE")[1].split("\n")[2])
    assert value == pytest.approx(2451545.0, abs=1e-6)  # 2000-01-01 00:00 UTC (Julian day number 2451545)
    assert ezdxf.readfile(plain).header["$VERSIONGUID"] is not None


@pytest.mark.reference("property", "ezdxf's own save under the moved clock differs: the checks above can fail")
def test_the_moving_clock_would_show_in_a_plain_ezdxf_save(tmp_path):
    # the check above has teeth: ezdxf's own save, twice, differs under the same clock
    import ezdxf

    doc = ezdxf.new("R2000")
    doc.saveas(tmp_path / "a.dxf")
    doc.saveas(tmp_path / "b.dxf")
    assert (tmp_path / "a.dxf").read_bytes() != (tmp_path / "b.dxf").read_bytes()
