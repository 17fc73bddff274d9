"""camcad as a process: whole commands against the interpreter floor that imports what they cannot avoid.

A user meets camcad as a process, where start-up dominates: a command is only as fast as the libraries it
must import. Each command runs as a whole process next to the floor process ``python -c "import numpy,
ezdxf"`` (and ``import typer`` for ``--help``), interleaved round by round so that the machine's load falls
on both alike; the figure is the ratio of their CPU times (user + system of the child, which other
processes' load disturbs far less than wall time), with the wall ratio beside it. Each row also lists the
heavy libraries the command imported (scipy, matplotlib, rich, shapely), from a separate probe run.

The law the commands read is written here (a cycloidal dwell-rise-dwell-return acceleration as a DXF
LWPOLYLINE), so an installed camcad runs this without its source checkout. camcad's modules are
byte-compiled first where they are writable (as ``pip install`` does).
"""

from __future__ import annotations

import json
import math
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: (label, camcad arguments, floor, ratio limit or None); {law} and {out} are filled in
COMMANDS = [
    ("camcad --help", ["--help"], "typer", 1.5),
    ("camcad check LAW", ["check", "{law}"], "numpy, ezdxf", 1.5),
    ("camcad profile --no-plots", ["profile", "--no-plots", "-o", "{out}"], "numpy, ezdxf", 1.3),
    ("camcad fix LAW --no-plots", ["fix", "{law}", "-o", "{out}/fixed.dxf", "--no-plots"], "numpy, ezdxf", None),
    ("camcad spectrum LAW --no-plots", ["spectrum", "{law}", "--no-plots", "-o", "{out}"], "numpy, ezdxf", None),
]
FLOORS = {"typer": "import typer", "numpy, ezdxf": "import numpy, ezdxf"}
HEAVY = ("scipy", "matplotlib", "rich", "shapely")

_PROBE = """
import json, sys
from camcad.cli import main
try:
    main(sys.argv[1:])
except SystemExit:
    pass
print("\\nMODULES" + json.dumps(sorted({m.split('.')[0] for m in sys.modules})))
"""


def write_law(path: Path) -> Path:
    """A cycloidal dwell-rise-dwell-return acceleration (90° each, 2° steps) as an LWPOLYLINE."""
    import ezdxf

    doc = ezdxf.new("R2000")
    points = []
    for k in range(181):
        deg = 2.0 * k
        u = (deg % 90.0) / 90.0
        sign = {1: 1.0, 3: -1.0}.get(int(deg // 90.0) if deg < 360 else 3, 0.0)
        points.append((deg, sign * 10.0 * math.sin(2 * math.pi * u) if sign else 0.0))
    doc.modelspace().add_lwpolyline(points, dxfattribs={"layer": "ACCEL"})
    doc.saveas(path)
    return path


def camcad_command() -> list[str]:
    script = Path(sys.executable).parent / "camcad"
    return [str(script)] if script.exists() else [sys.executable, "-m", "camcad"]


def run_process(argv: list[str], cwd: Path) -> tuple[float, float]:
    """(wall s, CPU s of the child); it must succeed (exit 0 or 1)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=cwd)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode not in (0, 1):
        raise RuntimeError(f"{' '.join(argv)} exited {done.returncode}: {done.stderr[-300:]}")
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def imported(args: list[str], cwd: Path) -> list[str]:
    """The heavy top-level packages a command imports (a separate run of it in one interpreter)."""
    done = subprocess.run([sys.executable, "-c", _PROBE, *args], capture_output=True, text=True, cwd=cwd)
    found = done.stdout.rsplit("\nMODULES", 1)
    return [m for m in json.loads(found[1]) if m in HEAVY] if len(found) == 2 else ["(probe failed)"]


def _compile() -> None:
    import compileall

    try:
        compileall.compile_dir(str(Path(__file__).resolve().parents[1]), quiet=1)
    except OSError:
        pass   # an installed, read-only package: pip compiled it


def run(quick: bool = False) -> list[dict]:
    """One row per command: CPU and wall medians, the ratio to its floor, the limit, the heavy imports."""
    _compile()
    rounds, warm = (2, 1) if quick else (9, 1)
    camcad = camcad_command()
    samples: dict[str, list[tuple[float, float]]] = {name: [] for name in [*FLOORS, *(c[0] for c in COMMANDS)]}
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        law = write_law(folder / "law.dxf")
        heavy = {label: imported([a.replace("{law}", str(law)).replace("{out}", str(folder / "probe"))
                                  for a in args], folder) if limit or not quick else ["(not probed in a quick run)"]
                 for label, args, _, limit in COMMANDS}
        for r in range(rounds + warm):
            for name, code in FLOORS.items():
                timing = run_process([sys.executable, "-c", code], folder)
                if r >= warm:
                    samples[name].append(timing)
            for label, args, _, _ in COMMANDS:
                out = folder / f"out-{r}-{abs(hash(label))}"
                timing = run_process(camcad + [a.replace("{law}", str(law)).replace("{out}", str(out))
                                               for a in args], folder)
                if r >= warm:
                    samples[label].append(timing)
    medians = {name: (statistics.median(w for w, _ in runs), statistics.median(c for _, c in runs))
               for name, runs in samples.items()}
    rows = []
    for name in FLOORS:
        wall, cpu = medians[name]
        rows.append({"benchmark": "startup", "kernel": "process start-up (floor)",
                     "method": f'python -c "{FLOORS[name]}"', "setting": "-", "time_s": wall, "cpu_s": cpu,
                     "error": None, "error_unit": "-", "reference": "none", "reference_source": "a timing"})
    for label, _, floor, limit in COMMANDS:
        wall, cpu = medians[label]
        ratio = cpu / medians[floor][1]
        rows.append({"benchmark": "startup", "kernel": "process (whole command)", "method": label,
                     "setting": f"floor: {FLOORS[floor]}", "time_s": wall, "cpu_s": cpu, "ratio": ratio,
                     "wall_ratio": wall / medians[floor][0], "ratio_limit": limit,
                     "passed": None if limit is None else ratio <= limit, "imports": heavy[label],
                     "error": ratio,
                     "error_unit": "CPU time / floor CPU time" + (f" (limit {limit:g})" if limit else ""),
                     "reference": "none", "reference_source": "a timing: the floor process in the same run",
                     "rounds": rounds,
                     "load_average": list(os.getloadavg())})
    return rows


if __name__ == "__main__":
    for row in run("--quick" in sys.argv):
        extra = f" ratio {row['ratio']:.2f} (wall {row['wall_ratio']:.2f}) limit {row['ratio_limit']} " \
                f"imports {row['imports']}" if "ratio" in row else ""
        print(f"{row['method']:42s} cpu {row['cpu_s']:.3f}s wall {row['time_s']:.3f}s{extra}")
