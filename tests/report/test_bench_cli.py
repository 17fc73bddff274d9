"""`camcad bench`: the aggregated speed-against-error report (one small benchmark, quick)."""

import json


def test_bench_quick_writes_table_json_and_plot(cli, tmp_path):
    result = cli("bench", "--quick", "--only", "impact", "-o", tmp_path, "--json")
    assert result.code == 0, result.err
    payload = result.json()
    rows = payload["rows"]
    assert {row["benchmark"] for row in rows} == {"impact"}
    for row in rows:
        for key in ("kernel", "method", "setting", "time_s", "error", "error_unit"):
            assert key in row
        assert row["time_s"] > 0
    closed = next(r for r in rows if r["method"] == "closed-form Duhamel")
    assert closed["error"] < 1e-9  # the closed form against DOP853 at rtol 1e-13
    table = (tmp_path / "bench.md").read_text()
    assert "| impact | stop impact response | closed-form Duhamel |" in table
    assert json.loads((tmp_path / "bench.json").read_text()) == json.loads(json.dumps(rows))
    assert (tmp_path / "bench.png").read_bytes()[:4] == b"\x89PNG"


def test_bench_unknown_name_is_one_line(cli):
    result = cli("bench", "--only", "nonsense")
    assert result.code == 2 and "no benchmark named 'nonsense'" in result.err
