"""Sweep throughput: designs per second per core, measured as whole processes against a floor process.

A child process prepares a sweep of the built-in default scene and computes N designs the way a worker does
(``camcad.sweep.evaluate.evaluate_chunk``, in chunks); a floor process does the same imports and preparation
and computes one design. The CPU time of the whole child (user + system, ``resource.getrusage``) less the
floor's, over N − 1 designs, is the CPU time per design, imports excluded; its inverse is designs per second
per core. Both processes run in the same run, interleaved round by round.

Sweeps: the follower's dimensions (base radius × roller radius: the law is the same for every design) and one
that varies the law (the rise angle × the base radius). Then the local pool of 2 processes and a
``dask.distributed.LocalCluster`` of 2 worker processes (when dask is installed) on the same designs: the
wall time per design and the workers' CPU time per design, so Dask's overhead over the local pool is their
difference. Last, what 10⁷ designs would cost on paper at the measured rates (core-hours).

Each row's error is the largest difference between the figures of a sample of its designs and the same
designs run one at a time through the scene pipeline (``evaluate_design``): the batch and the one-at-a-time
route must agree (reference: camcad itself, the per-design pipeline).
"""

from __future__ import annotations

import json
import math
import os
import resource
import statistics
import subprocess
import sys

from camcad.scene.default import default_tables
from camcad.sweep.engine import DaskCluster, LocalPool
from camcad.sweep.evaluate import make_task

#: (name, --vary specs, designs in a full run, in a quick run, target designs/s/core)
SWEEPS = (
    ("follower dimensions (default scene)", ("follower.base_radius=30:79.5:0.5", "follower.roller_radius=5:14:1"),
     1000, 200, 1000.0),
    ("law varies (default scene)", ("law.phases.rise=60:117:3", "follower.base_radius=40:58:2"), 200, 60, 100.0),
)

_CHILD = r"""
import json, sys, time
settings = json.loads(sys.argv[1])
from camcad.scene.default import default_tables
from camcad.sweep.evaluate import evaluate_chunk, make_task
task = make_task(default_tables(), "built-in default", None, settings["vary"], None, 0)
count, chunk = settings["count"], settings["chunk"]
rows = []
for first in range(0, count, chunk):
    rows += evaluate_chunk(task, first // chunk, first, min(first + chunk, count)).rows
ok = sum(r["status"] == "ok" for r in rows)
print(json.dumps({"designs": len(rows), "ok": ok, "feasible": sum(bool(r["feasible"]) for r in rows)}))
"""

_CHECK = r"""
import json, math, sys
settings = json.loads(sys.argv[1])
from camcad.scene.default import default_tables
from camcad.sweep.evaluate import evaluate_chunk, evaluate_design, make_task, prepared
task = make_task(default_tables(), "built-in default", None, settings["vary"], None, 0)
ids = settings["ids"]
batch = {}
for i in ids:
    batch[i] = evaluate_chunk(task, 0, i, i + 1).rows[0]
together = evaluate_chunk(task, 0, 0, settings["count"]).rows
prep = prepared(task)
worst = 0.0
for i in ids:
    one = evaluate_design(prep, i)
    row = together[i]
    for key, value in one.items():
        if key.startswith("_"):
            continue
        other = row.get(key)
        if isinstance(value, float) and isinstance(other, float):
            if math.isnan(value) and math.isnan(other):
                continue
            worst = max(worst, abs(value - other) / max(abs(value), 1e-300))
        elif value != other:
            worst = math.inf
print(json.dumps({"worst": worst}))
"""


def _child_cpu(code: str, settings: dict) -> tuple[float, dict]:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run([sys.executable, "-c", code, json.dumps(settings)], capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise RuntimeError(f"the sweep child failed: {done.stderr[-400:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, json.loads(done.stdout.strip().splitlines()[-1])


def rate_rows(quick: bool) -> list[dict]:
    rounds = 1 if quick else 3
    rows = []
    for name, vary, full, small, target in SWEEPS:
        count = small if quick else full
        chunk = max(1, min(count, 250))
        runs, floors = [], []
        result: dict = {}
        for _ in range(rounds):
            cpu, result = _child_cpu(_CHILD, {"vary": list(vary), "count": count, "chunk": chunk})
            runs.append(cpu)
            floors.append(_child_cpu(_CHILD, {"vary": list(vary), "count": 1, "chunk": 1})[0])
        per_design = (statistics.median(runs) - statistics.median(floors)) / max(count - 1, 1)
        rate = 1.0 / per_design if per_design > 0 else math.inf
        _, check = _child_cpu(_CHECK, {"vary": list(vary), "count": min(count, 40), "ids": [0, 7, 19, 33]})
        rows.append({"benchmark": "sweeps", "kernel": f"sweep: {name}", "method": "one worker (evaluate_chunk)",
                     "setting": f"{count} designs ({' × '.join(vary)})", "time_s": per_design, "cpu_s": per_design,
                     "designs_per_s_per_core": rate, "target_designs_per_s_per_core": target,
                     "passed": rate >= target, "process_cpu_s": statistics.median(runs),
                     "floor_process_cpu_s": statistics.median(floors), "designs": result["designs"],
                     "ok": result["ok"], "feasible": result["feasible"],
                     "core_hours_for_1e7": 1e7 * per_design / 3600.0,
                     "error": check["worst"], "error_unit": "largest relative difference of a design's figures",
                     "reference": "camcad itself", "reference_source": "the same designs one at a time through the "
                                                                       "scene pipeline (evaluate_design)"})
    return rows


def engine_rows(quick: bool) -> list[dict]:
    """The follower sweep on a local pool of 2 processes and on a Dask LocalCluster of 2 worker processes."""
    name, vary, full, small, _ = SWEEPS[0]
    count = small if quick else full
    task = make_task(default_tables(), "built-in default", None, list(vary), None, 0)
    chunk = max(1, count // 16)
    chunks = [(k, first, min(first + chunk, count)) for k, first in enumerate(range(0, count, chunk))]
    rows = []

    def measure(engine, label: str, setting: str) -> None:
        import time

        wall = time.perf_counter()
        results = list(engine.run(task, chunks))
        wall = time.perf_counter() - wall
        worker_cpu = sum(r.cpu_s for r in results)
        designs = sum(len(r.rows) for r in results)
        rows.append({"benchmark": "sweeps", "kernel": f"sweep engine: {name}", "method": label, "setting": setting,
                     "time_s": wall / designs, "wall_s_per_design": wall / designs,
                     "worker_cpu_s_per_design": worker_cpu / designs, "designs": designs, "chunks": len(chunks),
                     "error": None, "error_unit": "-", "reference": "none", "reference_source": "a timing",
                     "load_average": list(os.getloadavg())})

    with LocalPool(2) as pool:
        list(pool.run(task, chunks[:2]))          # warm the workers (imports, the task prepared)
        measure(pool, "local pool", f"2 processes, {count} designs, {len(chunks)} chunks")
    if quick:
        rows.append({"benchmark": "sweeps", "kernel": f"sweep engine: {name}", "method": "dask LocalCluster",
                     "setting": "not run in a quick run (starting a cluster takes seconds)", "time_s": None,
                     "error": None, "error_unit": "-", "reference": "none", "reference_source": "a timing"})
        return rows
    try:
        import distributed
    except ImportError:
        rows.append({"benchmark": "sweeps", "kernel": f"sweep engine: {name}", "method": "dask LocalCluster",
                     "setting": "dask is not installed (pip install camcad[dask])", "time_s": None, "error": None,
                     "error_unit": "-", "reference": "none", "reference_source": "a timing"})
        return rows
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster, DaskCluster(cluster.scheduler_address) as dask:
        list(dask.run(task, chunks[:2]))
        measure(dask, "dask LocalCluster", f"2 worker processes, {count} designs, {len(chunks)} chunks")
    pool_row, dask_row = rows[-2], rows[-1]
    dask_row["overhead_s_per_chunk"] = (dask_row["wall_s_per_design"] - pool_row["wall_s_per_design"]) * count \
        / len(chunks)
    return rows


def run(quick: bool = False) -> list[dict]:
    return rate_rows(quick) + engine_rows(quick)


if __name__ == "__main__":
    for r in run("--quick" in sys.argv):
        print({k: v for k, v in r.items() if k not in ("benchmark",)})
