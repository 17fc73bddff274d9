"""Bad-input fuzzing: property tests of the reader and a short fixed-seed run of the mutation fuzzer."""

import ezdxf
import numpy as np
import pytest
from fuzz_dxf import classify, fuzz
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from camcad.errors import CamcadError
from camcad.law.source import load_law


@pytest.mark.reference("property", "30 mutated drawings: each a result or one clear line, no finding")
def test_short_mutation_fuzz_run_has_no_findings():
    # CI runs 30 fixed-seed cases; the long campaign over every command is tests/fuzz_cli.py
    outcomes = fuzz(cases=30, seed=3)
    findings = [o for o in outcomes if o.status == "FINDING"]
    assert not findings, findings
    assert {o.status for o in outcomes} == {"ok", "error"}   # both kinds of outcome are exercised


@pytest.mark.reference("property", "the fuzzer's classification of hand-made outcomes")
def test_classify_catches_what_it_must():
    assert classify(2, "", "Traceback (most recent call last):\n  ...\nValueError", False)[0] == "FINDING"
    assert classify(2, "", "camcad: error: internal error (ValueError: x); rerun", False)[0] == "FINDING"
    assert classify(None, "", "", False)[0] == "FINDING"
    assert classify(0, "{}", "", False, cpu=10.5)[0] == "FINDING"          # past the 10 s of CPU a case may use
    assert classify(0, "{}", "", False, cpu=9.5)[0] == "ok"
    assert classify(0, "{}", "", True)[0] == "FINDING"
    assert classify(0, "not json", "", False)[0] == "FINDING"
    assert classify(2, "", "camcad: error: x.dxf: no curve found; draw it", False)[0] == "error"


finite = st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False)


@pytest.mark.reference("property", "hypothesis: any polyline gives a sorted finite law or one clear line")
@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.lists(st.tuples(finite, finite), min_size=0, max_size=40), st.booleans())
def test_any_polyline_gives_a_law_or_a_clear_error(tmp_path, points, closed):
    doc = ezdxf.new()
    if len(points) >= 1:
        doc.modelspace().add_lwpolyline(points, close=closed)
    path = tmp_path / "p.dxf"
    doc.saveas(path)
    try:
        loaded = load_law(path)
    except CamcadError as err:
        assert "\n" not in err.message()
        return
    assert np.all(np.diff(loaded.law.x) >= 0)
    assert np.isfinite(loaded.law.a).all()


# --- fuzz findings, each kept as a test ---------------------------------------------------------

@pytest.mark.reference("regression", "fuzz seed 7 case 490: a coordinate of 1e308 overflowed the chain joiner "
                                     "(internal error)")
def test_finding_huge_coordinates_in_a_line_chain(tmp_path, cli):
    # seed 7, case 490: a coordinate of 1e308 overflowed the chain joiner's k-d tree (internal error)
    doc = ezdxf.new()
    doc.modelspace().add_line((0, 0), (90, 1))
    doc.modelspace().add_line((90, 1), (1e308, -1))
    doc.modelspace().add_line((1e308, -1), (360, 0))
    path = tmp_path / "huge.dxf"
    doc.saveas(path)
    result = cli("check", path)
    assert result.code == 2
    assert "internal error" not in result.err and len(result.err.strip().splitlines()) == 1


@pytest.mark.reference("regression", "fuzz seed 7 case 1275: numpy's overflow warning printed before the error line")
def test_finding_overflow_warning_does_not_reach_stderr(tmp_path, cli):
    # seed 7, case 1275: a vertex at 1e308 made numpy print an overflow warning before the error line
    x = np.linspace(0, 360, 20)
    pts = list(zip(x, np.sin(np.radians(2 * x))))
    pts[7] = (pts[7][0], 1e308)
    doc = ezdxf.new()
    doc.modelspace().add_lwpolyline(pts)
    path = tmp_path / "overflow.dxf"
    doc.saveas(path)
    result = cli("check", path)
    assert result.code == 2
    assert len(result.err.strip().splitlines()) == 1
    assert "out-of-range" in result.err


@pytest.mark.reference("regression", "fuzz seed 11 case 1737: an LWPOLYLINE with no vertices made the curve choice "
                                     "fail (internal error)")
def test_finding_polyline_without_vertices(tmp_path, cli):
    # seed 11, case 1737 (duplicated lines of fig2_rise_area_too_large.dxf): an LWPOLYLINE left with no
    # vertices made the curve choice reduce an empty array (internal error)
    doc = ezdxf.new()
    doc.modelspace().add_lwpolyline([])
    doc.modelspace().add_lwpolyline([(0, 0), (90, 1), (180, -1), (270, 1), (360, 0)])
    path = tmp_path / "empty_polyline.dxf"
    doc.saveas(path)
    result = cli("check", path)
    assert result.code in (0, 1), result.err   # the good curve is still found
    only_empty = tmp_path / "only_empty.dxf"  # ezdxf will not write an empty polyline: write it by hand
    only_empty.write_text("0\nSECTION\n2\nENTITIES\n0\nLWPOLYLINE\n5\n2F\n100\nAcDbEntity\n8\n0\n"
                          "100\nAcDbPolyline\n90\n0\n70\n0\n0\nENDSEC\n0\nEOF\n")
    result = cli("check", only_empty)
    assert result.code == 2 and "0 vertices" in result.err and len(result.err.strip().splitlines()) == 1
