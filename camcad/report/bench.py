"""`camcad bench`: speed against error of camcad's kernels, from the package itself (``camcad.bench``).

``run_bench(request) -> BenchReport`` runs the packaged benchmarks — ``kernels`` (each kernel against its
numpy floor and a fair peer, CPU time in one run, errors against independent references), ``sweeps``
(designs per second per core) and ``startup`` (whole commands against their import floors) — and, when
camcad runs from a source checkout, the benchmarks of its ``benchmarks/`` folder named with ``--only``
(``--only all`` runs every one). It writes bench.md, bench.json and bench.png. Every row names the
reference its error is measured against (``reference``: the kind — closed form, second method, published,
property, camcad itself, or none for a timing — and, where known, ``reference_source``).

A source benchmark is a file benchmarks/bench_<name>.py with ``run(quick) -> list[dict]`` (keys kernel,
method, setting, time_s, error, error_unit, and reference where it has one).
"""

from __future__ import annotations

import contextlib
import importlib.util
import io
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, cast

from camcad.bench import kernels, startup, sweeps
from camcad.errors import CamcadError
from camcad.io.atomic import write_atomic, write_text_atomic
from camcad.io.jsonout import write_json
from camcad.report.figure import pyplot

if TYPE_CHECKING:
    from importlib.abc import Loader
    from importlib.machinery import ModuleSpec

#: the benchmarks inside the package: name → run(quick) (installed with camcad)
PACKAGED: dict[str, Callable[[bool], list[dict]]] = {"kernels": kernels.run, "sweeps": sweeps.run,
                                                     "startup": startup.run}

#: the reference of each source benchmark's rows that do not name their own: (kind, source); keyed by
#: benchmark, then by a phrase of the row's error unit (first match; "" matches every row)
SOURCE_REFERENCES: dict[str, list[tuple[str, tuple[str, str]]]] = {
    "balance": [("", ("second method", "Simpson's rule per drawn segment, math.fsum"))],
    "cli": [("", ("none", "a timing: the floor process in the same run"))],
    "cyclogram": [("cycle", ("property", "the conflict is checked to be a closed cycle of positive excess")),
                  ("", ("second method", "the exact longest path of the generated network"))],
    "dynamics": [("", ("closed form", "periodic solution by matrix exponentials per phase"))],
    "edit": [("", ("none", "a timing"))],
    "fourier": [("band", ("property", "the removed harmonics must be 0 (measured by an FFT of samples)")),
                ("RMS", ("camcad itself", "the composite law's own s(θ)")),
                ("", ("closed form", "c_k of the cycloidal motions in closed form"))],
    "hard": [("phase edges", ("closed form", "the phase edges of the generated law")),
             ("rise vs", ("closed form", "the generated law's rise")),
             ("closure", ("second method", "Simpson's rule per drawn segment")),
             ("re-read", ("property", "the written file read back")),
             ("pressure angle", ("camcad itself", "camcad's geometry of the same law")),
             ("refused", ("property", "an expected refusal")),
             ("", ("none", "a timing"))],
    "impact": [("", ("closed form", "the impact response by matrix exponentials"))],
    "linkage": [("published", ("published", "the atlas counts of the source work")),
                ("Table 1", ("published", "the source work's Table 1")),
                ("", ("camcad itself", "the synthesised linkage evaluated by camcad's own analysis"))],
    "peer": [("", ("closed form", "polar closed form of the roller cam (Norton 2009)"))],
    "profile": [("", ("closed form", "polar closed form of the default cam (camcad.bench.references.RollerCam)"))],
    "sweep": [("difference", ("camcad itself", "the full pipeline's check figures")),
              ("", ("none", "a timing"))],
}


@dataclass(frozen=True)
class BenchRequest:
    """What ``run_bench`` runs (``camcad bench``'s options).

    Parameters
    ----------
    quick : bool
        Fewer settings and repeats (the packaged benchmarks in under a minute).
    only : tuple of str, optional
        Benchmark names: ``kernels``, ``sweeps``, ``startup`` (installed with camcad), a source checkout's
        ``benchmarks/`` names, or "all"; None: the packaged ones.
    output : Path, optional
        Folder for bench.md, bench.json and bench.png (default ./camcad-out/bench/).
    plots : bool
        Draw bench.png.

    Examples
    --------
    >>> import camcad
    >>> request = camcad.BenchRequest(quick=True, only=("kernels",))
    >>> request.quick, request.only, request.plots
    (True, ('kernels',), True)
    """

    quick: bool = False
    only: tuple[str, ...] | None = None
    output: Path | None = None
    plots: bool = True


@dataclass(frozen=True)
class BenchReport:
    """The rows of every benchmark run (each with its ``reference``), the files written, the benchmarks
    left out and why (``skipped``: name → reason), and the targets: every kernel within 2× its floor."""

    quick: bool
    rows: list[dict]
    outputs: list[Path] = field(default_factory=list)
    skipped: dict[str, str] = field(default_factory=dict)

    @property
    def exit_code(self) -> int:
        return 0

    def targets(self) -> dict:
        """Each target with its figure: kernels ≤ 2× their floor, process ratios within their limits."""
        found = {}
        kernel_rows = [r for r in self.rows if r.get("benchmark") == "kernels"]
        if kernel_rows:
            worst = max(kernel_rows, key=lambda r: r["floor_ratio"] or math.inf)
            found["kernels within 2x their floor"] = {"worst": worst["floor_ratio"],
                                                      "kernel": f"{worst['kernel']}, {worst['setting']}",
                                                      "passed": kernels.floor_ratio_ok(kernel_rows)}
        for r in self.rows:
            if r.get("ratio_limit"):
                found[f"{r['method']} <= {r['ratio_limit']:g}x its floor"] = {"ratio": r["ratio"],
                                                                              "passed": r["passed"]}
            if r.get("target_designs_per_s_per_core"):
                found[f"{r['kernel']} >= {r['target_designs_per_s_per_core']:g} designs/s/core"] = {
                    "rate": r["designs_per_s_per_core"], "passed": r["passed"]}
        return found

    def to_dict(self) -> dict:
        return {"quick": self.quick, "rows": self.rows, "targets": self.targets(), "skipped": self.skipped,
                "outputs": [str(p) for p in self.outputs]}

    def markdown(self) -> str:
        return markdown_report(self.rows, self.quick, self.targets(), self.skipped)


def benchmarks_dir() -> Path | None:
    """benchmarks/ of the source checkout camcad runs from (or of the current directory), if there is one."""
    for candidate in (Path(__file__).resolve().parents[2] / "benchmarks", Path.cwd() / "benchmarks"):
        if candidate.is_dir() and any(candidate.glob("bench_*.py")):
            return candidate
    return None


def find_benchmarks() -> dict[str, Path]:
    """The source checkout's benchmarks: name → file (empty for an installed camcad)."""
    folder = benchmarks_dir()
    return {} if folder is None else {p.stem.removeprefix("bench_"): p for p in sorted(folder.glob("bench_*.py"))}


def load_benchmark(name: str, path: Path):
    import sys

    # the source benchmarks import their shared helpers (benchmarks/timing.py) as top-level modules
    folder = str(path.parent)
    if folder not in sys.path:
        sys.path.insert(0, folder)
    spec = cast("ModuleSpec", importlib.util.spec_from_file_location(f"camcad_bench_{name}", path))  # a .py file
    module = importlib.util.module_from_spec(spec)
    cast("Loader", spec.loader).exec_module(module)
    if not hasattr(module, "run"):
        raise CamcadError(f"benchmark {name} has no run(quick) function", str(path), "add one returning its rows")
    return module


#: the kinds of reference a row's error may be measured against ("none": the row is a timing)
REFERENCE_KINDS = ("closed form", "second method", "published", "property", "camcad itself", "none")


def with_reference(name: str, row: dict) -> dict:
    """The row with its ``reference`` (one of ``REFERENCE_KINDS``) and ``reference_source``: its own when it
    names a kind, else the kind its benchmark's rows are measured against (``SOURCE_REFERENCES``), its own
    text (if any) kept as the source."""
    own = row.get("reference")
    if own in REFERENCE_KINDS:
        return {"reference_source": "", **row}
    if row.get("error") is None:
        return {**row, "reference": "none", "reference_source": own or "a timing"}
    unit = str(row.get("error_unit", ""))
    for phrase, (kind, source) in SOURCE_REFERENCES.get(name, []):
        if phrase in unit:
            return {**row, "reference": kind, "reference_source": own or source}
    return {**row, "reference": "unnamed", "reference_source": own or "the benchmark names none"}


def run_bench(request: BenchRequest, status: Callable[[str], None] | None = None) -> BenchReport:
    """Run the benchmarks of ``request`` and write bench.md, bench.json (and bench.png).

    Parameters
    ----------
    request : BenchRequest
        Which benchmarks, how thoroughly, where to write.
    status : callable, optional
        Told the name of each benchmark as it starts.

    Returns
    -------
    BenchReport
        Every row (times in s of CPU or wall as each row says, errors in the row's unit, its reference).

    Raises
    ------
    CamcadError
        An unknown benchmark name, or a source benchmark asked for without a source checkout.

    Examples
    --------
    A name that is no benchmark is refused before anything runs:

    >>> import camcad
    >>> camcad.run_bench(camcad.BenchRequest(only=("nonsense",)))
    Traceback (most recent call last):
    ...
    camcad.errors.CamcadError: --only: no benchmark named 'nonsense'; choose from kernels, sweeps, startup, ...
    """
    source = find_benchmarks()
    if request.only is None:
        wanted = list(PACKAGED)
    elif "all" in request.only:
        wanted = list(PACKAGED) + [n for n in source if n not in PACKAGED]
    else:
        wanted = list(request.only)
    skipped: dict[str, str] = {}
    for name in wanted:
        if name not in PACKAGED and name not in source:
            known = list(PACKAGED) + list(source)
            fix = f"choose from {', '.join(known)}" + ("" if source else " (the other benchmarks are in a source "
                                                                         "checkout's benchmarks/, not installed)")
            raise CamcadError(f"no benchmark named {name!r}", "--only", fix)
    if request.only is None and not source:
        skipped["benchmarks/"] = "not installed with the package: the source checkout's benchmarks/ folder"
    rows: list[dict] = []
    for name in wanted:
        if status is not None:
            status(f"camcad bench: {name}{' (quick)' if request.quick else ''}")
        with contextlib.redirect_stdout(io.StringIO()):   # the benchmarks' own printing is for their scripts
            found = PACKAGED[name](request.quick) if name in PACKAGED else \
                load_benchmark(name, source[name]).run(request.quick)
        rows += [with_reference(name, {"benchmark": name, **r}) for r in found]
    out_dir = request.output if request.output is not None else Path("camcad-out") / "bench"
    report = BenchReport(request.quick, rows, [], skipped)
    outputs = [write_text_atomic(out_dir / "bench.md", report.markdown()), write_json(out_dir / "bench.json",
                                                                                      report_payload(report))]
    if request.plots:
        outputs.append(plot_speed_error(rows, out_dir / "bench.png"))
    return BenchReport(request.quick, rows, outputs, skipped)


def report_payload(report: BenchReport) -> dict:
    return {key: value for key, value in report.to_dict().items() if key != "outputs"}


# =============================================================================================
# Tables
# =============================================================================================


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


def _ratio(value) -> str:
    return "-" if value is None or not math.isfinite(value) else f"{value:.2f}"


def _cells(cells) -> str:
    return "| " + " | ".join(str(c).replace("|", "/") for c in cells) + " |"


def kernel_table(rows: list[dict]) -> list[str]:
    """The kernels against their floors and peers (CPU time per call, one run)."""
    lines = ["| kernel | setting | camcad | floor | camcad / floor | fair peer | peer | peer / camcad | "
             "camcad error | floor error | peer error | error unit | reference |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        peer = r["peer"] if r.get("status", "ok") == "ok" else f"{r['peer']} ({r['status']})"
        lines.append(_cells([r["kernel"], r["setting"], _format_time(r["camcad_s"]), _format_time(r["floor_s"]),
                             _ratio(r["floor_ratio"]), peer, _format_time(r["peer_s"]), _ratio(r["peer_ratio"]),
                             _format_error(r["camcad_error"]), _format_error(r["floor_error"]),
                             _format_error(r["peer_error"]), r["error_unit"],
                             f"{r['reference']}: {r['reference_source']}"]))
    return lines


def other_table(rows: list[dict]) -> list[str]:
    lines = ["| benchmark | kernel | method | setting | time | error | error unit | reference |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        reference = r.get("reference", "")
        if r.get("reference_source"):
            reference = f"{reference}: {r['reference_source']}"
        lines.append(_cells([r.get("benchmark", ""), r.get("kernel", ""), r.get("method", ""), r.get("setting", ""),
                             _format_time(r.get("cpu_s", r.get("time_s"))), _format_error(r.get("error")),
                             r.get("error_unit", ""), reference]))
    return lines


def markdown_report(rows: list[dict], quick: bool, targets: dict, skipped: dict) -> str:
    """bench.md: the kernel table, then every other row, the targets and what was left out."""
    kernel_rows = [r for r in rows if r.get("benchmark") == "kernels"]
    others = [r for r in rows if r.get("benchmark") != "kernels"]
    lines = [f"# camcad bench ({'quick' if quick else 'full'} run)", ""]
    if kernel_rows:
        lines += ["## Kernels against their numpy floor and a fair peer",
                  "",
                  "CPU time per call (median of interleaved rounds, this process); camcad / floor ≤ 2 is the "
                  "target at equal error; peer / camcad > 1: camcad is faster. Errors against the reference named.",
                  "", *kernel_table(kernel_rows), ""]
    if others:
        lines += ["## Other measurements", "", "time: CPU time where the row has one, else wall time.", "",
                  *other_table(others), ""]
    if targets:
        lines += ["## Targets", ""]
        for name, figures in targets.items():
            shown = ", ".join(f"{k} {v:.3g}" if isinstance(v, float) else f"{k} {v}" for k, v in figures.items())
            lines.append(f"- {name}: {shown}")
        lines.append("")
    for name, reason in skipped.items():
        lines.append(f"- left out: {name}: {reason}")
    return "\n".join(lines).rstrip() + "\n"


def markdown_table(rows: list[dict], quick: bool) -> str:
    """All rows as one table (kept for the source benchmarks' own scripts)."""
    return markdown_report(rows, quick, {}, {})


# =============================================================================================
# Plot
# =============================================================================================


def plot_speed_error(rows: list[dict], path: Path) -> Path:
    """Time against error on log axes: the kernels' camcad, floor and peer points joined per kernel, and every
    other row with an error (one colour per kernel, one marker per method)."""
    plt = pyplot()
    points: list[tuple[str, str, float, float]] = []
    for r in rows:
        if r.get("benchmark") == "kernels":
            for who in ("camcad", "floor", "peer"):
                t, e = r.get(f"{who}_s"), r.get(f"{who}_error")
                if isinstance(t, (int, float)) and isinstance(e, (int, float)) and t > 0 and e > 0:
                    setting = r["setting"].split(";")[0] if ";" in r["setting"] else r["setting"].split(",")[0]
                    points.append((f"{r['kernel']} ({setting})", who, t, e))
        elif not str(r.get("error_unit", "")).startswith("CPU time"):
            t, e = r.get("time_s"), r.get("error")
            if isinstance(t, (int, float)) and isinstance(e, (int, float)) and t > 0 and e > 0 and math.isfinite(e):
                points.append((str(r.get("kernel", "")), str(r.get("method", "")), t, e))
    curves = len({(k, m) for k, m, _, _ in points})
    fig, ax = plt.subplots(figsize=(12, max(7.0, 0.19 * curves + 1.0)), constrained_layout=True)
    kernel_names = list(dict.fromkeys(k for k, _, _, _ in points))
    colours = plt.get_cmap("tab10")
    markers = "osD^vP*Xh<>"
    for k, kernel in enumerate(kernel_names):
        methods = list(dict.fromkeys(m for kk, m, _, _ in points if kk == kernel))
        for m, method in enumerate(methods):
            pts = sorted((t, e) for kk, mm, t, e in points if kk == kernel and mm == method)
            times, errors = zip(*pts)
            ax.plot(times, errors, marker=markers[m % len(markers)], color=colours(k % 10), alpha=0.85,
                    label=f"{kernel}: {method}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time (s; CPU time for the kernels)")
    ax.set_ylabel("error against the reference (each kernel in its own unit, see bench.md)")
    ax.set_title("camcad: speed against error of every kernel (down and left is better)")
    ax.grid(True, which="both", alpha=0.3)
    if ax.lines:
        ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    out = write_atomic(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    plt.close(fig)
    return out
