"""``camcad sweep`` as one library call: ``run_sweep(SweepRequest(...)) -> SweepReport``.

The request names the scene, the varied keys and the engine; ``run_sweep`` checks the sweep, computes the
designs whose chunks are not on disk (``camcad.sweep.run.compute_chunks``), writes what a designer looks at
(``camcad.report.sweep.sweep_outputs``), report.json and throughput.json, and returns the report: its
``to_dict()`` is the ``--json`` payload, ``lines()`` the text the command prints, ``exit_code`` the command's.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from camcad.errors import CamcadError
from camcad.io.jsonout import write_json
from camcad.io.output_folder import OutputFolder, safe_name
from camcad.report.sweep import sweep_outputs
from camcad.sweep import analysis, store
from camcad.sweep.engine import make_engine
from camcad.sweep.evaluate import prepared
from camcad.sweep.run import compute_chunks, load_scene_tables, prepare_sweep, sized

#: every file the sweep writes into its folder, and the folders it fills
OUTPUT_FILES = ("sweep.json", "report.json", "throughput.json", "best.toml", "region.png", "pareto.png", "pareto.csv")
OUTPUT_FOLDERS = ("results", "best")


@dataclass(frozen=True)
class SweepRequest:
    """What ``camcad sweep`` can be asked: the scene, the keys varied, what "best" means, the engine.

    Parameters
    ----------
    scene : Path or None
        The scene file (.toml); None: the built-in default design.
    vary : tuple of str
        ``KEY=SPEC`` texts: a scene key (``follower.base_radius``, ``law.phases.rise``, ...) over a range
        ``A:B:STEP``, a list ``a,b,c`` or a distribution ``normal(mu,sigma)`` / ``uniform(a,b)``, in the key's
        own unit (mm, deg, rpm, ...).
    samples : int or None
        Draws of the distribution keys per grid point (Monte-Carlo); no unit.
    seed : int
        Seed of the draws (the same seed, the same draws); no unit.
    objectives : tuple of str
        ``min:COLUMN`` / ``max:COLUMN`` in order of priority; empty: min of the first varied key, then
        max:min_margin_ratio.
    scheduler : str or None
        A Dask cluster: ``tcp://HOST:PORT`` of its scheduler, or its scheduler file; None: a local pool.
    workers : int or None
        Processes of the local pool (None: every core; 1 runs in this process); no unit.
    chunk : int or None
        Designs per task (None: about 0.5 s of work, at least 4 tasks per worker); no unit.
    output : Path or None
        Output folder (None: ./camcad-out/<scene>-sweep/).
    resume : bool
        Complete the sweep already in the output folder.
    plot : str or None
        ``KEY_X,KEY_Y``: the keys on the axes of the feasible-region plot (None: the first two numeric keys).
    connect_timeout : float
        Seconds to wait for the Dask scheduler and its first worker (s).
    run_best : bool
        Run the best design through ``camcad profile`` into ``best/``.
    plots : bool
        Draw region.png and pareto.png.
    stop_after_chunks : int or None
        Stop after computing this many chunks (a test of ``resume``); no unit.
    progress : callable or None
        Called as ``progress(done, total, computed, seconds)`` (designs, designs, designs, s) as chunks complete.

    Examples
    --------
    >>> SweepRequest(vary=("follower.base_radius=30:50:5",), workers=1).vary
    ('follower.base_radius=30:50:5',)
    """

    scene: Path | None = None
    vary: tuple[str, ...] = ()
    samples: int | None = None
    seed: int = 0
    objectives: tuple[str, ...] = ()
    scheduler: str | None = None
    workers: int | None = None
    chunk: int | None = None
    output: Path | None = None
    resume: bool = False
    plot: str | None = None
    connect_timeout: float = 10.0
    run_best: bool = True
    plots: bool = True
    stop_after_chunks: int | None = None
    progress: Callable[[int, int, int, float], None] | None = field(default=None, compare=False)


@dataclass
class SweepReport:
    """What ``run_sweep`` found: ``body`` (report.json and throughput.json merged: the --json payload) or,
    for a sweep stopped before its end, ``stopped`` (the one line that says how to complete it)."""

    body: dict
    stopped: str | None = None

    @property
    def exit_code(self) -> int:
        """130 stopped, 3 a design hit an internal error, 0 a feasible design found, 1 none."""
        if self.stopped is not None:
            return 130
        counts = self.body["counts"]
        return 3 if counts["internal_errors"] else (0 if counts["feasible"] else 1)

    def errors(self) -> list[str]:
        """The lines for stderr: how to complete a stopped sweep, or the designs that hit an internal error."""
        if self.stopped is not None:
            return [f"error: {self.stopped}"]
        counts = self.body["counts"]
        if not counts["internal_errors"]:
            return []
        errors = counts["errors"]["internal error"]
        first = errors[0]["error"] if errors else ""
        return [f"internal error in {counts['internal_errors']} designs (first: {first[:120]}) - please report it; "
                "their rows say which"]

    def to_dict(self) -> dict:
        """The --json payload (report.json's content with the run's throughput)."""
        return dict(self.body)

    def lines(self) -> list[str]:
        """The text ``camcad sweep`` prints."""
        return [] if self.stopped is not None else _lines(self.body)


def run_sweep(request: SweepRequest) -> SweepReport:
    """``camcad sweep``: every design of the --vary grid (and draws) through the scene's checks.

    The results are Parquet chunks, the feasible region, the Pareto front, the best design and report.json.
    The designs run on a local pool of processes or a Dask cluster (``scheduler``); each chunk is written as it
    completes, so ``resume`` completes an interrupted sweep. A Ctrl-C (KeyboardInterrupt) while the designs
    are computed keeps the chunks written and returns a report that says so (``exit_code`` 130).

    Parameters
    ----------
    request : SweepRequest
        The scene, the keys varied (in their own units: mm, deg, rpm, ...), the objectives, the engine.

    Returns
    -------
    SweepReport
        ``to_dict()``: scene, vary, samples, seed, designs, counts, objectives, pareto, best (the varied values
        in their units), outputs, results, manifest and the throughput (wall s, CPU s, designs/s);
        ``exit_code`` 0 when a feasible design was found, 1 when none, 3 when a design hit an internal
        error, 130 when stopped.

    Raises
    ------
    CamcadError
        Bad input: a key or SPEC that does not fit the scene, design 0 refused, an output that would replace
        an input, a missing extra (pyarrow, dask.distributed).

    Examples
    --------
    Five base radii of the built-in default design, in this process, no plots and no best design run:

    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp()) / "sweep"
    >>> report = run_sweep(SweepRequest(vary=("follower.base_radius=30:50:5",), workers=1, output=folder,
    ...                                 plots=False, run_best=False))
    >>> report.to_dict()["designs"], report.exit_code
    (5, 0)
    >>> (folder / "report.json").exists()
    True
    """
    store.require_pyarrow()
    tables, name, base_dir, inputs = load_scene_tables(request.scene)
    plan = prepare_sweep(tables, name, base_dir, list(request.vary), request.samples, request.seed)
    space = prepared(plan.task).space
    names = list(plan.first_row) + ["min_margin_ratio"]
    objectives = ([analysis.parse_objective(text, names) for text in request.objectives] if request.objectives
                  else analysis.default_objectives(plan.keys))
    plot_axes = None
    if request.plot is not None:
        parts = [p.strip() for p in request.plot.split(",")]
        if len(parts) != 2:
            raise CamcadError(f"{request.plot[:60]!r} is not KEY_X,KEY_Y", "--plot", "give two varied keys, e.g. "
                              "--plot law.phases.rise,follower.base_radius")
        plot_axes = analysis.region_axes(space, (parts[0], parts[1]))
    stem = Path(name).stem if request.scene is not None else "default"
    folder = request.output if request.output is not None else Path("camcad-out") / f"{safe_name(stem)}-sweep"
    with OutputFolder(folder, inputs) as out:
        out.plan(OUTPUT_FILES, folders=OUTPUT_FOLDERS)  # a clash with an input is refused before any work
        chunk = request.chunk
        if request.resume and chunk is None:
            found = store.read_manifest(out.folder)
            if found is not None:
                chunk = int(found["chunk_designs"])
        with make_engine(request.workers, request.scheduler, request.connect_timeout) as engine:
            plan = sized(plan, engine.workers, chunk)
            try:
                stats = compute_chunks(plan, out.folder, engine, resume=request.resume, progress=request.progress,
                                       stop_after_chunks=request.stop_after_chunks, out=out)
            except KeyboardInterrupt:
                return SweepReport({}, f"interrupted; the chunks written are kept: rerun with --resume to complete "
                                       f"the sweep in {out.folder}")
        if stats.stopped:
            return SweepReport({}, f"stopped after {stats.chunks_computed} chunks (--stop-after-chunks); rerun "
                                   f"with --resume to complete the sweep in {out.folder}")
        found = sweep_outputs(out.folder, plan, tables, base_dir, objectives, plot_axes, plots=request.plots,
                              run_best=request.run_best, out=out)
        report = {"scene": str(request.scene) if request.scene is not None else name, "vary": list(plan.task.vary),
                  "samples": plan.task.samples, "seed": plan.task.seed, "designs": plan.designs, **found,
                  "results": str(out.path(store.RESULTS)), "manifest": str(out.path(store.MANIFEST))}
        body = _write_reports(out, report, {"chunks": plan.chunks, "chunk_designs": plan.chunk_designs,
                                            "throughput": stats.as_dict()})
    return SweepReport(body)


def _write_reports(out: OutputFolder, report: dict, run: dict) -> dict:
    """report.json (what the sweep found: the same bytes for the same sweep) and throughput.json (how this run
    went: chunking, engine, timings); returns both merged, the --json payload."""
    run_path, report_path = out.path("throughput.json"), out.path("report.json")
    report["outputs"] = [*report["outputs"], str(run_path), str(report_path)]
    write_json(run_path, run)
    write_json(report_path, report)
    return {**report, **run}


def _lines(report: dict) -> list[str]:
    counts, speed = report["counts"], report["throughput"]
    lines = [f"camcad sweep: {counts['designs']} designs, {counts['feasible']} feasible, {counts['infeasible']} "
             f"infeasible, {counts['bad_input']} refused (bad input), {counts['internal_errors']} internal errors"]
    if counts.get("grid_points") is not None:
        lines.append(f"  grid points feasible in every draw: {counts['grid_points_feasible_in_every_draw']} of "
                     f"{counts['grid_points']}")
    for check, count in list(counts["failed_by"].items())[:6]:
        lines.append(f"  failed {check}: {count}")
    for kind in ("bad input", "internal error"):
        for item in counts["errors"].get(kind, [])[:2]:
            lines.append(f"  {kind} ({item['designs']} designs): {item['error'][:150]}")
    if speed["designs_computed"]:
        rate = speed["designs_per_s"] or 0.0
        per_cpu = speed["designs_per_cpu_s"] or 0.0
        lines.append(f"  computed {speed['designs_computed']} designs in {speed['wall_s']:.3g} s on "
                     f"{speed['workers']} {speed['engine']} workers: {rate:.3g} designs/s "
                     f"({rate / max(speed['workers'], 1):.3g} per worker); {per_cpu:.3g} designs per CPU-second")
    if speed["chunks_on_disk_before"]:
        lines.append(f"  resumed: {speed['chunks_on_disk_before']} of {speed['chunks']} chunks were on disk")
    best = report.get("best")
    if best:
        values = ", ".join(f"{k} = {v}" for k, v in best["values"].items())
        lines.append(f"  best ({', '.join(report['objectives'])}): design {best['design']}: {values}; governing "
                     f"{best['governing']}")
        if "profile" in best:
            lines.append(f"  best design through camcad profile: "
                         f"{'passed' if best['profile']['passed'] else 'FAILED'} -> {best['profile']['folder']}")
    else:
        lines.append("  no feasible design")
    count = report["pareto"]["designs"]
    lines.append(f"  Pareto front: {count} design{'' if count == 1 else 's'}")
    lines.append("written: " + ", ".join(report["outputs"]))
    return lines
