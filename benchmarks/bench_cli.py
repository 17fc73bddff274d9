"""camcad as a process: each command's whole run against the interpreter floors measured in the same run.

A user meets camcad as a process, and there start-up dominates: a command is only as fast as the
libraries it must import. So each command is timed as a whole process (wall and CPU time, median of
repeats) next to the "floor" commands that import just the libraries it cannot avoid, run interleaved
with it so that the machine's load falls on both alike; the figure of merit is the ratio to its floor.

| command | floor | ratio limit (issue 14) |
|---|---|---|
| camcad --help | python -c "import typer" | 1.5 |
| camcad profile --no-plots | python -c "import numpy, ezdxf" | 1.3 |
| camcad profile (summary plot) | python -c "import numpy, ezdxf" | 2.5 |
| camcad profile loom_group1.toml --no-plots | python -c "import numpy, ezdxf, scipy.optimize" | 2.0 |
| camcad profile loom_group1.toml (plots) | python -c "import numpy, ezdxf, scipy.optimize" | 4.0 |

Two more floors bound what any run with plots can reach: a process that imports numpy, ezdxf and
matplotlib's Figure with the Agg canvas (what drawing needs before anything is drawn), and one that also
saves an empty page of the summary's size at camcad's DPI. Their ratios to "import numpy, ezdxf" are
the part of a plot target that matplotlib takes before camcad draws a line. Beside them, in this process
after a warm-up (so no import is counted), the CPU time of drawing and saving the default's summary
page, a page with only its profile panel, and an empty page of the same size. And where `camcad profile
--no-plots` spends its CPU time, measured inside one such process: importing numpy and ezdxf, importing
typer, creating camcad's dataclasses (Python 3.11 compiles each one's methods from source at import), and
the rest (camcad's other imports and the work).

The ratios are of CPU time (user + system of the child process), which the load of other processes on a
shared machine disturbs far less than wall time; wall medians and wall ratios are reported beside them.

camcad's modules are byte-compiled first (``compileall``), as ``pip install`` does for an installed
package and as Python does on first import: an editable install run with ``PYTHONDONTWRITEBYTECODE=1``
(set on this machine) would otherwise compile ~40 modules from source in every process, 0.14 s each
run, which is not what a user's process costs.

Run: python benchmarks/bench_cli.py [--quick]   (quick: one round, no warm-up)
"""

from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LOOM = ROOT / "samples" / "scenes" / "loom_group1.toml"

FLOORS = {
    "typer": ["-c", "import typer"],
    "numpy, ezdxf": ["-c", "import numpy, ezdxf"],
    "numpy, ezdxf, scipy.optimize": ["-c", "import numpy, ezdxf, scipy.optimize"],
}
#: floors of a run with plots (label, python arguments); ratios to "numpy, ezdxf"
_MPL = ("import numpy, ezdxf; from matplotlib.figure import Figure; "
        "from matplotlib.backends.backend_agg import FigureCanvasAgg")
PLOT_FLOORS = {
    "numpy, ezdxf, matplotlib (Figure, Agg)": ["-c", _MPL],
    "... and save an empty 15 x 9 in page": ["-c", _MPL + "; f = Figure(figsize=(15, 9), dpi={dpi}); "
                                             "FigureCanvasAgg(f); f.savefig({png!r}, dpi={dpi}, "
                                             "pil_kwargs={{'compress_level': {level}}})"],
}
#: (label, camcad arguments, floor, ratio limit); "{out}" becomes a fresh output folder
COMMANDS = [
    ("camcad --help", ["--help"], "typer", 1.5),
    ("camcad profile --no-plots", ["profile", "--no-plots", "-o", "{out}"], "numpy, ezdxf", 1.3),
    ("camcad profile", ["profile", "-o", "{out}"], "numpy, ezdxf", 2.5),
    ("camcad profile loom_group1.toml --no-plots", ["profile", str(LOOM), "--no-plots", "-o", "{out}"],
     "numpy, ezdxf, scipy.optimize", 2.0),
    ("camcad profile loom_group1.toml", ["profile", str(LOOM), "-o", "{out}"], "numpy, ezdxf, scipy.optimize", 4.0),
]


def _camcad() -> list[str]:
    script = Path(sys.executable).parent / "camcad"
    return [str(script)] if script.exists() else [sys.executable, "-m", "camcad"]


def _run(argv: list[str]) -> tuple[float, float]:
    """(wall s, CPU s of the child) of one process; it must succeed (exit 0 or 1)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode not in (0, 1):
        raise RuntimeError(f"{' '.join(argv)} exited {done.returncode}: {done.stderr[-300:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def run(quick: bool = False) -> list[dict]:
    import compileall

    compileall.compile_dir(str(ROOT / "camcad"), quiet=1)
    # quick: one round and no warm-up round (a smoke test of the benchmark, not a measurement)
    repeats, warm = (1, 0) if quick else (7, 1)
    camcad = _camcad()
    from camcad.report.figure import DPI, PNG_COMPRESSION

    floors = {**FLOORS, **PLOT_FLOORS}
    samples: dict[str, list[tuple[float, float]]] = {name: [] for name in [*floors, *(c[0] for c in COMMANDS)]}
    env_python = [sys.executable]
    with tempfile.TemporaryDirectory() as scratch:
        png = str(Path(scratch) / "empty.png")
        for repeat in range(repeats + warm):       # the first round warms the file cache and is dropped
            for name, args in floors.items():
                timing = _run(env_python + [a.format(dpi=DPI, png=png, level=PNG_COMPRESSION) for a in args])
                if repeat >= warm:
                    samples[name].append(timing)
            for label, args, _, _ in COMMANDS:
                out = str(Path(scratch) / f"{len(samples[label])}-{abs(hash(label))}")
                timing = _run(camcad + [a.replace("{out}", out) for a in args])
                if repeat >= warm:
                    samples[label].append(timing)
    medians = {name: (statistics.median(w for w, _ in runs), statistics.median(c for _, c in runs))
               for name, runs in samples.items()}
    rows = []
    for name in FLOORS:
        wall, cpu = medians[name]
        rows.append(dict(kernel="process start-up (floor)", method=f'python -c "import {name}"', setting="-",
                         time_s=wall, cpu_s=cpu, error=None, error_unit="-"))
    base = medians["numpy, ezdxf"]
    for name in PLOT_FLOORS:
        wall, cpu = medians[name]
        rows.append(dict(kernel="process start-up (floor of a run with plots)", method=f"python: {name}",
                         setting="floor: import numpy, ezdxf", time_s=wall, cpu_s=cpu, ratio=cpu / base[1],
                         wall_ratio=wall / base[0], error=cpu / base[1], error_unit="CPU time / floor CPU time"))
    for label, _, floor, limit in COMMANDS:
        wall, cpu = medians[label]
        ratio = cpu / medians[floor][1]
        rows.append(dict(kernel="process (whole command)", method=label, setting=f"floor: import {floor}",
                         time_s=wall, cpu_s=cpu, ratio=ratio, wall_ratio=wall / medians[floor][0],
                         ratio_limit=limit, passed=ratio <= limit,
                         error=ratio, error_unit=f"CPU time / floor CPU time (limit {limit:g})"))
    return rows + breakdown(1 if quick else 7, base[1]) + page_costs(1 if quick else 5)


#: a child process that runs `camcad profile --no-plots` in itself and prints where its CPU time went beyond
#: "import numpy, ezdxf": typer's import, the dataclasses camcad creates (Python 3.11 compiles each one's
#: methods from source at import) and the rest (camcad's other imports and the work)
_BREAKDOWN = r"""
import contextlib, dataclasses, io, json, sys, time
t0 = time.process_time()
import numpy, ezdxf
t1 = time.process_time()
import typer
t2 = time.process_time()
made, spent, process_class = [0], [0.0], dataclasses._process_class
def timed(*args, **kwargs):
    c = time.process_time()
    try:
        return process_class(*args, **kwargs)
    finally:
        made[0] += 1
        spent[0] += time.process_time() - c
dataclasses._process_class = timed
sys.argv = ["camcad", "profile", "--no-plots", "-o", sys.argv[1]]
from camcad.cli import main
with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):
    main()
t3 = time.process_time()
print(json.dumps({"floor": t1 - t0, "typer": t2 - t1, "dataclasses": spent[0], "count": made[0],
                  "rest": t3 - t2 - spent[0]}))
"""


def breakdown(repeats: int, floor_cpu: float) -> list[dict]:
    """Where `camcad profile --no-plots` spends its CPU time beyond its floor (median of ``repeats`` runs);
    ratios to ``floor_cpu``, the CPU time of the process ``python -c "import numpy, ezdxf"``."""
    import json

    runs = []
    with tempfile.TemporaryDirectory() as scratch:
        for k in range(repeats):
            done = subprocess.run([sys.executable, "-c", _BREAKDOWN, str(Path(scratch) / str(k))], cwd=ROOT,
                                  capture_output=True, text=True, check=True)
            runs.append(json.loads(done.stdout.strip().splitlines()[-1]))
    median = {key: statistics.median(run[key] for run in runs) for key in runs[0]}
    parts = {"importing numpy, ezdxf": "floor", "importing typer": "typer",
             f"{median['count']:.0f} dataclasses created": "dataclasses",
             "camcad's other imports and the work": "rest"}
    return [dict(kernel="camcad profile --no-plots, inside (CPU)", method=label, setting="-", time_s=median[key],
                 cpu_s=median[key], ratio=median[key] / floor_cpu, error=median[key] / floor_cpu,
                 error_unit='CPU time / CPU time of python -c "import numpy, ezdxf"') for label, key in parts.items()]


def page_costs(repeats: int) -> list[dict]:
    """CPU time of drawing and saving the default's summary page, its profile panel alone and an empty
    page of the same size, in this process after one warm-up of each (median of ``repeats``)."""
    from camcad.report.figure import new_figure, save_figure
    from camcad.report.profile import draw_profile, plot_summary
    from camcad.scene.default import default_tables
    from camcad.scene.file import scene_from_dict
    from camcad.scene.pipeline import PipelineOptions, analyse_scene

    scene = scene_from_dict(default_tables(), Path("default"), from_file=False)
    run = next(iter(analyse_scene(scene, PipelineOptions(plots=())).runs.values()))
    result, report = run.profile, run.report

    def profile_panel():
        fig, ax = new_figure(5.0, 9.0, layout=None)   # fixed margins, as on the summary page
        draw_profile(ax, result, legend=6, title="cam profile")
        return fig

    pages = {"the default's summary page (15 x 9 in)": lambda: plot_summary(result, report),
             "its profile panel alone (5 x 9 in)": profile_panel,
             "an empty page (15 x 9 in)": lambda: new_figure(15.0, 9.0, rows=0, layout=None)[0]}
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for label, make in pages.items():
            cpu, wall = [], []
            for k in range(repeats + 1):
                c0, w0 = time.process_time(), time.perf_counter()
                save_figure(make(), Path(scratch) / "page.png")
                if k:                                       # the first draws the fonts' caches: dropped
                    cpu.append(time.process_time() - c0)
                    wall.append(time.perf_counter() - w0)
            rows.append(dict(kernel="plot page (drawn and saved, in process)", method=label, setting="-",
                             time_s=statistics.median(wall), cpu_s=statistics.median(cpu), error=None,
                             error_unit="-"))
    return rows


def main() -> None:
    rows = run("--quick" in sys.argv)
    print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}")
    print(f"{'command':46} {'wall':>9} {'CPU':>9} {'ratio':>7} {'wall ratio':>10} {'limit':>6}")
    for r in rows:
        ratio = f"{r['ratio']:.2f}" if "ratio" in r else ""
        wall_ratio = f"{r['wall_ratio']:.2f}" if "wall_ratio" in r else ""
        limit = f"{r['ratio_limit']:g}" if "ratio_limit" in r else ""
        print(f"{r['method']:46} {r['time_s']:8.3f}s {r['cpu_s']:8.3f}s {ratio:>7} {wall_ratio:>10} {limit:>6}")


if __name__ == "__main__":
    main()
