"""The issue's must-show sweep, run for real: base radius 30…80 mm (0.5 mm) × rise angle 60…120° (1°) of the
default scene, 6161 designs.

1. ``camcad sweep`` on the local pool, killed with SIGKILL once half of its chunks are on disk, then
   ``--resume``: every design must be on disk exactly once and the chunks written before the kill untouched;
2. (``--dask``) the same sweep on a 2-worker ``dask.distributed.LocalCluster``: every chunk file must be
   byte-identical to the local pool's;
3. ``camcad profile --auto-rb`` for every rise angle of the grid: the sweep's boundary (least feasible grid
   base radius) must lie within one grid step above it;
4. the README's figures: docs/img/sweep_region.png (the feasible region with the auto-rb curve over it) and
   docs/img/sweep_pareto.png; the figures and checks in docs/sweep_must_show.json.

Run: python docs/make_sweep_figures.py [--workers 2] [--dask] [--out FOLDER]   (tens of minutes on 2 cores)
     python docs/make_sweep_figures.py --figures-only FOLDER/pool                (redraw the figures only)
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

VARY = ["--vary", "follower.base_radius=30:80:0.5", "--vary", "law.phases.rise=60:120:1"]
AXES = ["--plot", "law.phases.rise,follower.base_radius"]
CHUNK = 20          # designs per task, fixed so that the pool's and the cluster's chunk files can be compared
STEP_MM = 0.5


def camcad(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run([sys.executable, "-m", "camcad", *args], capture_output=True, text=True, env=env,
                          check=False)
    if check and done.returncode not in (0, 1):
        raise SystemExit(f"camcad {' '.join(args[:3])} ... failed ({done.returncode}): {done.stderr.strip()}")
    return done


def chunk_files(folder: Path) -> dict[str, tuple[int, int]]:
    return {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in sorted((folder / "results").glob("chunk-*.parquet"))}


def killed_then_resumed(folder: Path, workers: int) -> dict:
    """Start the sweep, SIGKILL it (and its pool) once half of its chunks are written, resume it."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    args = [sys.executable, "-m", "camcad", "sweep", *VARY, *AXES, "--chunk", str(CHUNK), "--workers", str(workers),
            "-o", str(folder), "--json"]
    total = -(-6161 // CHUNK)
    started = time.perf_counter()
    process = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env,
                               start_new_session=True)
    while process.poll() is None and len(chunk_files(folder)) < total // 2:
        time.sleep(0.2)
    if process.poll() is not None:
        raise SystemExit("the sweep ended before it could be killed halfway")
    os.killpg(process.pid, signal.SIGKILL)
    process.wait()
    killed_after = time.perf_counter() - started
    before = chunk_files(folder)
    leftovers = sorted(p.name for p in (folder / "results").glob(".chunk-*.tmp"))
    resumed = camcad("sweep", *VARY, *AXES, "--workers", str(workers), "-o", str(folder), "--resume", "--json")
    report = json.loads(resumed.stdout)
    after = chunk_files(folder)
    untouched = all(after.get(name) == identity for name, identity in before.items())
    from camcad.sweep.store import read_results

    ids = read_results(folder, columns=["design"]).column("design").to_pylist()
    return {"chunks": total, "chunks_on_disk_at_kill": len(before), "killed_after_s": killed_after,
            "partial_files_left_by_the_kill": leftovers, "chunks_resumed": report["throughput"]["chunks_computed"],
            "designs_resumed": report["throughput"]["designs_computed"],
            "chunks_written_before_the_kill_untouched": untouched,
            "every_design_exactly_once": ids == list(range(6161)), "report": report}


def on_local_cluster(folder: Path, pool_folder: Path) -> dict:
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster:
        done = camcad("sweep", *VARY, "--chunk", str(CHUNK), "--scheduler", cluster.scheduler_address,
                      "-o", str(folder), "--no-plots", "--no-best", "--json")
    report = json.loads(done.stdout)
    names = sorted(p.name for p in (folder / "results").glob("chunk-*.parquet"))
    same = names == sorted(p.name for p in (pool_folder / "results").glob("chunk-*.parquet")) and all(
        (folder / "results" / n).read_bytes() == (pool_folder / "results" / n).read_bytes() for n in names)
    return {"chunk_files": len(names), "byte_identical_to_the_local_pool": same,
            "throughput": report["throughput"]}


def auto_rb(rise: float, scratch: Path) -> float:
    """camcad profile --auto-rb on the default design with the rise over ``rise`` deg (the next dwell takes up
    the change, as the sweep's law.phases.rise does); its base radius (mm)."""
    from camcad.cli import main

    phases = f"0:{rise:g}:rise,{rise:g}:180:dwell,180:300:return,300:360:dwell"
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        try:
            main(["profile", "--auto-rb", "--phases", phases, "--no-plots", "--json", "-o", str(scratch / f"r{rise:g}")])
        except SystemExit:
            pass
    return float(json.loads(out.getvalue())["follower"]["base_radius_mm"])


def figures(folder: Path, solved: dict[float, float]) -> list[str]:
    """docs/img/sweep_region.png (the region, the auto-rb curve over it) and docs/img/sweep_pareto.png (the
    trade-off between the smallest cam and the shortest rise: min base radius, min rise angle)."""
    import numpy as np

    from camcad.report.figure import save_figure
    from camcad.report.sweep import axis_label, pareto_figure, region_figure
    from camcad.sweep import analysis
    from camcad.sweep.store import read_results

    cols = analysis.columns(read_results(folder))
    x, y = cols["law.phases.rise"], cols["follower.base_radius"]
    feasible = cols["feasible"] & (cols["status"] == "ok")
    labels = np.where(feasible, "feasible", cols["governing"]).astype(object)
    rises = np.array(sorted(solved))
    fig = region_figure(x, y, labels, axis_label("law.phases.rise", "deg"), axis_label("follower.base_radius", "mm"),
                        f"default scene (cycloidal rise of 25 mm, roller 10 mm, pressure-angle limit 30 deg): "
                        f"{int(feasible.sum())} of {len(x)} designs feasible",
                        reference=(rises, np.array([solved[r] for r in rises]),
                                   "least Rb: camcad profile --auto-rb"),
                        boundary=analysis.feasible_boundary(x, y, feasible), zoom=(74.6, 80.4, 39.8, 46.2))
    region = save_figure(fig, ROOT / "docs" / "img" / "sweep_region.png")
    objectives = [analysis.Objective("min", "follower.base_radius"), analysis.Objective("min", "law.phases.rise")]
    points = {"design": cols["design"], "feasible": feasible, "follower.base_radius": y, "law.phases.rise": x}
    rows = np.flatnonzero(feasible)
    values = np.column_stack([y[rows], x[rows]])
    front = rows[analysis.pareto_front(values, ["min", "min"])]
    best = analysis.best_index(points, objectives)
    fig = pareto_figure(points, front, best, objectives,
                        {"follower.base_radius": axis_label("follower.base_radius", "mm"),
                         "law.phases.rise": axis_label("law.phases.rise", "deg")},
                        f"smallest cam against shortest rise: {len(front)} Pareto-optimal of {len(rows)} feasible "
                        "designs", best_label="least base radius, then shortest rise")
    pareto = save_figure(fig, ROOT / "docs" / "img" / "sweep_pareto.png")
    return [str(region.relative_to(ROOT)), str(pareto.relative_to(ROOT))]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--dask", action="store_true", help="also run the sweep on a 2-worker LocalCluster")
    parser.add_argument("--out", type=Path, default=None, help="folder for the sweeps (default: a temporary one)")
    parser.add_argument("--figures-only", type=Path, default=None,
                        help="redraw the figures from the sweep in this folder and docs/sweep_must_show.json")
    options = parser.parse_args()
    if options.figures_only is not None:
        saved = json.loads((ROOT / "docs" / "sweep_must_show.json").read_text())
        solved = {r["rise_deg"]: r["auto_rb_mm"] for r in saved["boundary_vs_auto_rb"]["rows"]}
        print("written", ", ".join(figures(options.figures_only, solved)))
        return
    out = options.out or Path(tempfile.mkdtemp(prefix="camcad-must-show-"))
    out.mkdir(parents=True, exist_ok=True)
    found: dict = {"command": " ".join(["camcad sweep", *VARY, *AXES, "--chunk", str(CHUNK), "--workers",
                                        str(options.workers), "-o", "OUT"]),
                   "load_average_at_start": list(os.getloadavg())}
    pool = out / "pool"
    print(f"1. local pool ({options.workers} workers), killed halfway, resumed -> {pool}", flush=True)
    found["kill_and_resume"] = killed_then_resumed(pool, options.workers)
    report = found["kill_and_resume"].pop("report")
    found["sweep"] = {k: report[k] for k in ("designs", "chunks", "counts", "best", "pareto", "objectives")}
    found["sweep"]["resumed_run_throughput"] = report["throughput"]
    print("   ", {k: v for k, v in found["kill_and_resume"].items()}, flush=True)
    if options.dask:
        print("2. LocalCluster, 2 workers", flush=True)
        found["local_cluster"] = on_local_cluster(out / "dask", pool)
        print("   ", found["local_cluster"], flush=True)
    print("3. camcad profile --auto-rb per rise angle", flush=True)
    scratch = out / "auto-rb"
    boundary = {b["x"]: b for b in report["region"]["boundary"]}
    rows, worst = [], 0.0
    solved = {}
    for rise in sorted(boundary):
        rb = auto_rb(rise, scratch)
        solved[rise] = rb
        b = boundary[rise]
        least, below = b["least_feasible"], b["greatest_infeasible"]
        if below is None:        # the whole column is feasible: the least Rb must lie at or below the grid's 30 mm
            agrees = least == 30.0 and rb <= 30.0
        elif least is None:      # no feasible design in the column: the least Rb must lie above 80 mm
            agrees = rb > 80.0
        else:
            agrees = below < rb <= least and least - rb < STEP_MM
            worst = max(worst, least - rb)
        rows.append({"rise_deg": rise, "auto_rb_mm": rb, "least_feasible_mm": least, "greatest_infeasible_mm": below,
                     "monotone": b["monotone"], "agrees": agrees})
    found["boundary_vs_auto_rb"] = {
        "rise_angles": len(rows), "agree": sum(r["agrees"] for r in rows),
        "inside_the_grid": sum(r["greatest_infeasible_mm"] is not None and r["least_feasible_mm"] is not None
                               for r in rows),
        "largest_gap_least_feasible_minus_auto_rb_mm": worst, "rows": rows}
    print("   ", {k: v for k, v in found["boundary_vs_auto_rb"].items() if k != "rows"}, flush=True)
    found["figures"] = figures(pool, solved)
    found["load_average_at_end"] = list(os.getloadavg())
    target = ROOT / "docs" / "sweep_must_show.json"
    target.write_text(json.dumps(found, indent=2) + "\n")
    print(f"written {target.relative_to(ROOT)} and {', '.join(found['figures'])}")


if __name__ == "__main__":
    main()
