"""`camcad bench`: the speed-against-error report, from the package and from a source checkout's benchmarks/."""

import json

import pytest

from camcad.report import bench as report_bench


def test_a_source_benchmark_writes_table_json_and_plot_with_a_reference_on_every_row(cli, tmp_path):
    result = cli("bench", "--quick", "--only", "impact", "-o", tmp_path, "--json")
    assert result.code == 0, result.err
    payload = result.json()
    rows = payload["rows"]
    assert {row["benchmark"] for row in rows} == {"impact"}
    for row in rows:
        for key in ("kernel", "method", "setting", "time_s", "error", "error_unit", "reference"):
            assert key in row
        assert row["reference"] in report_bench.REFERENCE_KINDS
        assert row["time_s"] > 0
    closed = next(r for r in rows if r["method"] == "closed-form Duhamel")
    assert closed["error"] < 1e-9  # the closed form against DOP853 at rtol 1e-13
    table = (tmp_path / "bench.md").read_text()
    assert "| impact | stop impact response | closed-form Duhamel |" in table
    assert json.loads((tmp_path / "bench.json").read_text())["rows"] == json.loads(json.dumps(rows))
    assert (tmp_path / "bench.png").read_bytes()[:4] == b"\x89PNG"


def test_bench_unknown_name_is_one_line(cli):
    result = cli("bench", "--only", "nonsense")
    assert result.code == 2 and "no benchmark named 'nonsense'" in result.err


def _fake_kernels(quick):
    from camcad.bench.kernels import row

    return [row("a kernel", "a setting", {"camcad": 2e-3, "floor": 1e-3, "peer": 4e-3},
                {"camcad": 1e-9, "floor": 2e-9, "peer": 1e-6}, "mm", "closed form", "a formula", peer="a peer",
                floor_figures=0.0, status="ok")]


def test_an_installed_camcad_runs_its_own_benchmarks_and_names_what_it_leaves_out(monkeypatch, tmp_path, cli):
    # an installed package has no benchmarks/ beside it: the packaged benchmarks run, a source one is refused in
    # one line that says where it lives
    monkeypatch.setattr(report_bench, "benchmarks_dir", lambda: None)
    monkeypatch.setattr(report_bench, "PACKAGED", {"kernels": _fake_kernels})
    report = report_bench.run_bench(report_bench.BenchRequest(True, None, tmp_path, False))
    assert [r["kernel"] for r in report.rows] == ["a kernel"]
    assert "benchmarks/" in report.skipped
    text = (tmp_path / "bench.md").read_text()
    assert "| a kernel | a setting | 2.00 ms | 1.00 ms | 2.00 | a peer | 4.00 ms | 2.00 |" in text
    assert report.targets()["kernels within 2x their floor"]["passed"] is True
    result = cli("bench", "--only", "balance")
    assert result.code == 2 and "not installed" in result.err


@pytest.mark.parametrize("name", sorted(report_bench.SOURCE_REFERENCES))
def test_every_source_benchmark_row_gets_a_reference_kind(name):
    for unit in ("mm vs closed form", "closure / lift", "deg (max |error|)", "chains vs published", "-", ""):
        found = report_bench.with_reference(name, {"error": 1.0, "error_unit": unit})
        assert found["reference"] in report_bench.REFERENCE_KINDS, (name, unit, found)
    assert report_bench.with_reference(name, {"error": None})["reference"] == "none"
