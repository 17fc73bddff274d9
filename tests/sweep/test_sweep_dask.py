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


@pytest.mark.reference("property", "exit 2 with what to do when the cluster has no workers; resume completes")
def test_a_cluster_that_loses_every_worker_stops_the_sweep_with_what_to_do(tmp_path):
    # issue 34 F14: losing every Dask worker was an internal error (AttributeError); now one line, exit 2,
    # and --resume completes the sweep once workers are back
    import os
    import subprocess
    import sys
    import time

    from conftest import ROOT

    from camcad.sweep.store import read_results

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None, worker_dashboard_address=None) as lost:
        # 401 designs (about 20 s on two workers), so that the workers are gone long before the last chunk
        args = [sys.executable, "-m", "camcad", "sweep", "--vary", "follower.base_radius=30:70:0.1", "--chunk", "2",
                "--scheduler", lost.scheduler_address, "--connect-timeout", "3", "--no-plots", "--no-best",
                "-o", tmp_path / "out", "--json"]
        env = {**os.environ, "PYTHONPATH": str(ROOT)}
        run = subprocess.Popen([str(a) for a in args], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        results = tmp_path / "out" / "results"
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and len(list(results.glob("chunk-*.parquet"))) < 2:
            time.sleep(0.2)
        lost.scale(0)                                    # every worker leaves
        _out, err = run.communicate(timeout=180)
        lines = err.decode().strip().splitlines()
        assert run.returncode == 2, err
        assert len(lines) == 1 and "lost the workers" in lines[0] and "--resume" in lines[0], lines
        assert len(lines[0]) < 300
        lost.scale(2)
        with distributed.Client(lost.scheduler_address) as client:
            client.wait_for_workers(2, timeout=60)
        resumed = subprocess.run([str(a) for a in args[:-1]] + ["--resume", "--json"], env=env, capture_output=True,
                                 timeout=300)
        assert resumed.returncode == 0, resumed.stderr
    assert read_results(tmp_path / "out").column("design").to_pylist() == list(range(401))
