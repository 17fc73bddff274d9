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
    samples: dict[str, list[tuple[float, float]]] = {name: [] for name in [*FLOORS, *(c[0] for c in COMMANDS)]}
    env_python = [sys.executable]
    with tempfile.TemporaryDirectory() as scratch:
        for repeat in range(repeats + warm):       # the first round warms the file cache and is dropped
            for name, args in FLOORS.items():
                timing = _run(env_python + args)
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
    for label, _, floor, limit in COMMANDS:
        wall, cpu = medians[label]
        ratio = cpu / medians[floor][1]
        rows.append(dict(kernel="process (whole command)", method=label, setting=f"floor: import {floor}",
                         time_s=wall, cpu_s=cpu, ratio=ratio, wall_ratio=wall / medians[floor][0],
                         ratio_limit=limit, passed=ratio <= limit,
                         error=ratio, error_unit=f"CPU time / floor CPU time (limit {limit:g})"))
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
