"""Throughput of `camcad sweep`: designs per second per core for the default scene and the loom group, the
speed-up from 1 to 2 local workers, and what a sweep saves by running only what the checks need.

Rows:
- one design through the scene pipeline, in full (what `camcad profile` analyses: the checks, the smallest
  base radius, the least phase angles) and checks only (what a sweep runs); the error is the largest
  difference between the two routes' check figures (value, limit, margin), which must be 0;
- a sweep of N designs of the default scene (base radius × rise angle) in this process (1 worker) and on a
  local pool of 2 processes: time per design (wall), designs per second, and per CPU-second of the workers;
- the same for the loom group (4 mechanisms, contact stress, cyclogram) varying the shuttle lift's base
  radius.

The machine may be shared: each row carries the load average when it ran, and the CPU time per design (the
workers' own CPU time, which sharing the cores does not inflate much) is the figure to scale from.

Run: python benchmarks/bench_sweep.py [--quick | --speedup]   (--quick: the default scene only, seconds; in full:
     minutes; --speedup: the default scene's sweeps on 1 and 2 workers only, about a minute)
"""

from __future__ import annotations

import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from timing import median_time

from camcad.scene.default import default_tables
from camcad.scene.file import read_scene, scene_from_dict
from camcad.scene.pipeline import PipelineOptions, analyse_scene

ROOT = Path(__file__).resolve().parents[1]
LOOM = ROOT / "samples" / "scenes" / "loom_group1.toml"


def _figures(report: dict) -> dict:
    from camcad.sweep.evaluate import design_checks

    return {f.name: (f.value, f.limit, f.margin) for f in design_checks(report)}


def _largest_difference(a: dict, b: dict) -> float:
    if set(a) != set(b):
        return float("inf")
    worst = 0.0
    for name, figures in a.items():
        for x, y in zip(figures, b[name]):
            if (x is None) != (y is None):
                return float("inf")
            if x is not None:
                worst = max(worst, abs(x - y))
    return worst


def design_rows(repeats: int, loom_repeats: int) -> list[dict]:
    rows = []
    cases = [("default scene", lambda: scene_from_dict(default_tables(), Path("default"), from_file=False), repeats),
             ("loom group (4 mechanisms)", lambda: read_scene(LOOM), loom_repeats)][:2 if loom_repeats else 1]
    for kernel, make, count in cases:
        found = {}
        for method, checks_only in (("full pipeline (camcad profile)", False), ("checks only (sweep)", True)):
            options = PipelineOptions(plots=(), checks_only=checks_only)
            analyse_scene(make(), options)   # warm-up: imports
            cpu = time.process_time()
            t, result = median_time(lambda make=make, options=options: analyse_scene(make(), options), count,
                                    warm_up=False)
            found[checks_only] = _figures(result.report)
            rows.append({"kernel": f"one design: {kernel}", "method": method, "setting": "-", "time_s": t,
                         "cpu_s": (time.process_time() - cpu) / count, "error": None,
                         "error_unit": "max |difference| of check figures vs full", "load_average": _load()})
        rows[-1]["error"] = _largest_difference(found[False], found[True])
        rows[-2]["error"] = 0.0
    return rows


def sweep_rows(designs_default: int, designs_loom: int, rounds: int) -> list[dict]:
    """Sweeps on 1 and 2 workers, interleaved ``rounds`` times (1, 2, 1, 2, ...) so that both see the same
    load on a shared machine; each row has the medians over the rounds. ``cores_obtained`` is the workers'
    CPU time over the wall time: how much of the machine the sweep actually got."""
    import statistics

    from camcad.sweep.engine import make_engine
    from camcad.sweep.run import compute_chunks, prepare_sweep, sized

    rows = []
    radii = max(1, designs_default // 10)
    default_vary = [f"follower.base_radius=30:{30 + 2 * (radii - 1)}:2", "law.phases.rise=60:114:6"]
    loom_vary = [f"mechanisms.shuttle_lift.follower.base_radius=40:{40 + 2 * max(designs_loom - 1, 0)}:2"]
    loom_tables = read_scene(LOOM).raw
    cases = [("default scene", default_tables(), "built-in default", None, default_vary),
             ("loom group (4 mechanisms)", loom_tables, LOOM.name, LOOM.parent, loom_vary)][:2 if designs_loom else 1]
    for kernel, tables, name, base, vary in cases:
        plan = prepare_sweep(tables, name, base, vary)
        runs: dict[int, list[dict]] = {1: [], 2: []}
        for _ in range(rounds):
            for workers in (1, 2):
                with tempfile.TemporaryDirectory() as folder, make_engine(workers) as engine:
                    sized_plan = sized(plan, workers, max(1, plan.designs // (4 * workers)))
                    runs[workers].append(compute_chunks(sized_plan, Path(folder), engine).as_dict())
        rates = {}
        for workers in (1, 2):
            found = runs[workers]
            rate = statistics.median(r["designs_per_s"] for r in found)
            rates[workers] = rate
            cpu = statistics.median(r["cpu_s_per_design"] for r in found)
            cores = statistics.median(r["worker_cpu_s"] / r["wall_s"] for r in found)
            rows.append({"kernel": f"sweep: {kernel}", "method": "in-process" if workers == 1 else "local pool",
                         "setting": f"{workers} worker{'s' if workers > 1 else ''}, {plan.designs} designs",
                         "time_s": 1.0 / rate, "error": None, "error_unit": "-", "designs_per_s": rate,
                         "designs_per_s_per_worker": rate / workers, "cpu_s_per_design": cpu,
                         "cores_obtained": cores, "rounds": rounds, "workers": workers,
                         "load_average": found[0]["load_average_before"]})
        rows[-1]["speedup_vs_1_worker"] = rates[2] / rates[1]
    return rows


def _load() -> list:
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except OSError:
        return []


def run(quick: bool = False) -> list[dict]:
    if quick:   # the default scene only (the loom group's rows take minutes)
        return design_rows(3, 0) + sweep_rows(20, 0, 1)
    return design_rows(15, 3) + sweep_rows(200, 8, 3)


def main() -> None:
    quick = "--quick" in sys.argv
    # --speedup: only the default scene's 1- and 2-worker sweeps (200 designs, interleaved twice)
    rows = sweep_rows(200, 0, 2) if "--speedup" in sys.argv else run(quick)
    print(f"cores: {len(os.sched_getaffinity(0)) if hasattr(os, 'sched_getaffinity') else os.cpu_count()}, "
          f"load average now {_load()}")
    print(f"{'kernel':36s} {'method':32s} {'setting':26s} {'time/design':>12s} {'CPU/design':>11s}  notes")
    for row in rows:
        cpu = row.get("cpu_s", row.get("cpu_s_per_design"))
        notes = []
        if row.get("designs_per_s"):
            notes.append(f"{row['designs_per_s']:.3g} designs/s ({row['designs_per_s_per_worker']:.3g} per worker)")
        if row.get("cores_obtained"):
            notes.append(f"got {row['cores_obtained']:.2f} cores")
        if row.get("speedup_vs_1_worker"):
            notes.append(f"speed-up 1->2 workers {row['speedup_vs_1_worker']:.2f}")
        if row.get("error") is not None:
            notes.append(f"check figures vs full: {row['error']:.3g}")
        notes.append(f"load {row.get('load_average')}")
        print(f"{row['kernel']:36s} {row['method']:32s} {row['setting']:26s} {row['time_s'] * 1e3:10.1f}ms "
              f"{(cpu or 0) * 1e3:9.1f}ms  {'; '.join(notes)}")
    for row in rows:
        if row["method"] == "in-process" and row.get("cpu_s_per_design"):
            per_design = row["cpu_s_per_design"]
            core_hours = 1e7 * per_design / 3600
            print(f"10^7 designs of the {row['kernel'].split(': ')[1]} at {per_design * 1e3:.1f} ms of CPU each: "
                  f"{core_hours:,.0f} core-hours, i.e. about {core_hours:,.0f} cores for one hour "
                  f"({core_hours / 32:,.0f} 32-core machines) before scheduling overhead")


if __name__ == "__main__":
    main()
