"""`camcad sweep --scheduler`: the same sweep on a 2-worker ``dask.distributed.LocalCluster`` (processes, on
127.0.0.1 only) and on the local pool gives identical Parquet files, byte for byte."""

from __future__ import annotations

import pytest

pytest.importorskip("pyarrow")
distributed = pytest.importorskip("distributed")

VARY = ["--vary", "follower.base_radius=30:50:5", "--vary", "law.phases.rise=60,90,200",
        "--vary", "law.standard=cycloidal,poly345"]   # 30 designs; rise 200 deg is refused (bad input rows)


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None, worker_dashboard_address=None) as found:
        yield found


@pytest.mark.reference("second method", "the same sweep on the local process pool: byte-identical Parquet files")
def test_a_local_cluster_gives_the_local_pool_s_parquet(tmp_path, cli, cluster):
    from camcad.sweep.store import read_results

    dask_out, pool_out = tmp_path / "dask", tmp_path / "pool"
    on_dask = cli("sweep", *VARY, "--chunk", "4", "--scheduler", cluster.scheduler_address, "-o", dask_out,
                  "--no-plots", "--no-best", "--json")
    assert on_dask.code == 0, on_dask.err
    speed = on_dask.json()["throughput"]
    assert speed["engine"] == "dask" and speed["workers"] == 2 and speed["worker_processes"] == 2
    on_pool = cli("sweep", *VARY, "--chunk", "4", "--workers", "2", "-o", pool_out, "--no-plots", "--no-best",
                  "--json")
    assert on_pool.code == 0, on_pool.err
    dask_files = sorted((dask_out / "results").glob("*.parquet"))
    pool_files = sorted((pool_out / "results").glob("*.parquet"))
    assert [p.name for p in dask_files] == [p.name for p in pool_files] and len(dask_files) == 8
    for a, b in zip(dask_files, pool_files):
        assert a.read_bytes() == b.read_bytes(), a.name
    table = read_results(dask_out)
    assert table.equals(read_results(pool_out))
    assert table.column("design").to_pylist() == list(range(30))
    assert table.column("status").to_pylist().count("bad input") == 10
    assert on_dask.json()["counts"] == on_pool.json()["counts"]
