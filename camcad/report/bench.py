"""Gathering the benchmarks of benchmarks/ into one speed-against-error report (Markdown and a plot).

Every benchmarks/bench_<name>.py exposes ``run(quick) -> list[dict]`` with the keys kernel, method,
setting, time_s (median of repeats), error and error_unit (the error against a tight reference).
"""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path
from typing import TYPE_CHECKING, cast

from camcad.errors import CamcadError
from camcad.io.atomic import write_atomic

if TYPE_CHECKING:
    from importlib.abc import Loader
    from importlib.machinery import ModuleSpec


def benchmarks_dir() -> Path:
    """benchmarks/ of the source checkout camcad runs from (or of the current directory)."""
    for candidate in (Path(__file__).resolve().parents[1] / "benchmarks", Path.cwd() / "benchmarks"):
        if candidate.is_dir() and any(candidate.glob("bench_*.py")):
            return candidate
    raise CamcadError("no benchmarks/ folder found", "camcad bench",
                      "run it from a source checkout of camcad (the benchmarks are not installed with the package)")


def find_benchmarks() -> dict[str, Path]:
    return {path.stem.removeprefix("bench_"): path for path in sorted(benchmarks_dir().glob("bench_*.py"))}


def load_benchmark(name: str, path: Path):
    import sys

    # the benchmarks import their shared helpers (benchmarks/timing.py) as top-level modules
    folder = str(path.parent)
    if folder not in sys.path:
        sys.path.insert(0, folder)
    spec = cast("ModuleSpec", importlib.util.spec_from_file_location(f"camcad_bench_{name}", path))  # a .py file
    module = importlib.util.module_from_spec(spec)
    cast("Loader", spec.loader).exec_module(module)
    if not hasattr(module, "run"):
        raise CamcadError(f"benchmark {name} has no run(quick) function", str(path), "add one returning its rows")
    return module


def _format_time(seconds) -> str:
    if seconds is None or not isinstance(seconds, (int, float)) or not math.isfinite(seconds):
        return "-"
    if seconds < 1e-3:
        return f"{seconds * 1e6:.1f} µs"
    if seconds < 1:
        return f"{seconds * 1e3:.2f} ms"
    return f"{seconds:.2f} s"


def _format_error(value) -> str:
    if value is None:
        return "-"
    if isinstance(value, (int, float)):
        return "0" if value == 0 else f"{value:.2e}"
    return str(value)


def markdown_table(rows: list[dict], quick: bool) -> str:
    """One Markdown table: benchmark | kernel | method | setting | time | error | unit."""
    lines = [f"speed against error ({'quick' if quick else 'full'} run; time = median of repeats)", "",
             "| benchmark | kernel | method | setting | time | error | error unit |",
             "|---|---|---|---|---|---|---|"]
    for row in rows:
        cells = [row.get("benchmark", ""), row.get("kernel", ""), row.get("method", ""), str(row.get("setting", "")),
                 _format_time(row.get("time_s")), _format_error(row.get("error")), row.get("error_unit", "")]
        lines.append("| " + " | ".join(str(c).replace("|", "/") for c in cells) + " |")
    return "\n".join(lines) + "\n"


def plot_speed_error(rows: list[dict], path: Path) -> Path:
    """Time against error on log axes: one colour per kernel, one marker per method, each method's
    settings joined in order of time (a method's curve is its speed-against-error trade-off)."""
    from camcad.report.figure import pyplot

    plt = pyplot()
    # the process rows' "error" is a ratio of CPU times, not an error against a reference: not plotted
    rows = [r for r in rows if not str(r.get("error_unit", "")).startswith("CPU time")]
    curves = len({(r.get("kernel"), r.get("method")) for r in rows})
    fig, ax = plt.subplots(figsize=(12, max(7.0, 0.19 * curves + 1.0)), constrained_layout=True)
    kernels = list(dict.fromkeys(row.get("kernel", "") for row in rows))
    colours = plt.get_cmap("tab10")
    markers = "osD^vP*Xh<>"
    for k, kernel in enumerate(kernels):
        methods = list(dict.fromkeys(r.get("method", "") for r in rows if r.get("kernel") == kernel))
        for m, method in enumerate(methods):
            points = sorted((r["time_s"], r["error"]) for r in rows
                            if r.get("kernel") == kernel and r.get("method") == method
                            and isinstance(r.get("time_s"), (int, float)) and isinstance(r.get("error"), (int, float))
                            and r["time_s"] > 0 and r["error"] > 0 and math.isfinite(r["error"]))
            if not points:
                continue
            times, errors = zip(*points)
            ax.plot(times, errors, marker=markers[m % len(markers)], color=colours(k % 10), alpha=0.85,
                    label=f"{kernel}: {method}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time (s, median of repeats)")
    ax.set_ylabel("error against the reference (each kernel in its own unit, see bench.md)")
    ax.set_title("camcad: speed against error of every kernel (down and left is better)")
    ax.grid(True, which="both", alpha=0.3)
    if ax.lines:
        ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    out = write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    plt.close(fig)
    return out
