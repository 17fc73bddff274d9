"""Running a sweep: check it, size its chunks, compute the chunks not yet on disk, and stream them to Parquet.

``prepare_sweep`` reads the scene, builds the design space (every key and SPEC checked before any work) and
runs design 0 in this process: a scene or a first design the pipeline refuses stops the sweep with one line,
and its time sizes the chunks (``TARGET_CHUNK_S`` of work each, at least ``CHUNKS_PER_WORKER`` chunks per
worker). ``compute_chunks`` then computes every chunk whose file is missing (all of them for a fresh folder, the
rest for ``--resume``), writing each one as it completes. Timings, never in the data, are returned as a
``RunStats``: wall time, the workers' CPU time, designs per second, and per core.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from camcad.errors import CamcadError
from camcad.scene.default import default_tables
from camcad.scene.file import read_scene
from camcad.sweep import store
from camcad.sweep.engine import Engine
from camcad.sweep.evaluate import (
    STATUS_BAD,
    STATUS_BUG,
    SweepTask,
    evaluate_design,
    make_task,
    prepared,
)

#: seconds of work per chunk the automatic chunk size aims at
TARGET_CHUNK_S = 0.5
#: the automatic chunk size leaves at least this many chunks per worker (the last ones balance the load)
CHUNKS_PER_WORKER = 4
#: the largest automatic chunk (designs)
MAX_CHUNK = 2000


@dataclass(frozen=True)
class SweepPlan:
    """A sweep ready to run: its task, design count, chunking and the first design's row and timing.

    Parameters
    ----------
    task : SweepTask
        What travels to the workers.
    designs : int
        Number of designs.
    chunk_designs : int
        Designs per chunk (the last chunk may hold fewer).
    keys : dict
        {key path: kind} of the varied keys (their columns).
    units : dict
        {key path: unit}.
    first_row : dict
        Design 0's row (computed while preparing).
    first_s : float
        Wall time of design 0 (s), measured after a warm-up.
    """

    task: SweepTask
    designs: int
    chunk_designs: int
    keys: dict
    units: dict
    first_row: dict
    first_s: float

    @property
    def chunks(self) -> int:
        return math.ceil(self.designs / self.chunk_designs)

    def bounds(self, chunk: int) -> tuple[int, int]:
        """(first design, one past the last design) of ``chunk``."""
        start = chunk * self.chunk_designs
        return start, min(start + self.chunk_designs, self.designs)

    def manifest(self) -> dict:
        """What ``sweep.json`` holds (``camcad.sweep.store.manifest``)."""
        return store.manifest(self.task, self.designs, self.chunk_designs, self.keys)


def load_scene_tables(scene_path: Path | None) -> tuple[dict, str, Path | None, list[Path]]:
    """(tables, name, folder of relative law files, input files) of a scene file, or of the built-in default."""
    if scene_path is None:
        return default_tables(), "built-in default", None, []
    scene = read_scene(scene_path)  # the structure is checked here, each section by the pipeline
    return scene.raw, scene_path.name, scene.base_dir, scene.input_files()


def prepare_sweep(tables: dict, name: str, base_dir: Path | None, vary: list[str], samples: int | None = None,
                  seed: int = 0) -> SweepPlan:
    """Check the sweep and size its chunks (module docstring); a one-line CamcadError for bad input.

    Parameters
    ----------
    tables : dict
        The scene's TOML tables.
    name : str
        The scene's name in messages (its file name).
    base_dir : Path or None
        Folder of the scene's relative law files.
    vary : list of str
        ``KEY=SPEC`` texts.
    samples, seed : int
        Draws per grid point of the distribution keys, and their seed.

    Returns
    -------
    SweepPlan
        Not yet chunked (``chunk_designs`` 0): ``sized`` chunks it for the engine's workers.
    """
    task = make_task(tables, name, base_dir, vary, samples, seed)
    prep = prepared(task)
    space = prep.space
    keys = {spec.key.path: spec.key.kind for spec in space.specs}
    units = {spec.key.path: spec.key.unit for spec in space.specs}
    evaluate_design(prep, 0)  # warm-up: the first call imports the pipeline's modules
    started = time.perf_counter()
    first = evaluate_design(prep, 0)
    first_s = time.perf_counter() - started
    if first["status"] == STATUS_BAD:
        raise CamcadError(f"design 0 ({_values_text(first, keys)}) is refused: {first['error']}", "camcad sweep",
                          "fix the scene or the --vary values")
    if first["status"] == STATUS_BUG:
        raise RuntimeError(f"design 0 hit an internal error: {first['error']}")
    return SweepPlan(task, space.size, 0, keys, units, first, first_s)


def sized(plan: SweepPlan, workers: int, chunk_designs: int | None = None) -> SweepPlan:
    """The plan with its chunk size: ``chunk_designs`` when given, else ``auto_chunk`` for ``workers``."""
    from dataclasses import replace

    if chunk_designs is None:
        chunk_designs = auto_chunk(plan.first_s, plan.designs, workers)
    elif chunk_designs < 1:
        raise CamcadError(f"--chunk must be at least 1, got {chunk_designs}", "--chunk", "give --chunk N, N >= 1")
    return replace(plan, chunk_designs=int(chunk_designs))


def auto_chunk(seconds_per_design: float, designs: int, workers: int) -> int:
    """Designs per chunk: ``TARGET_CHUNK_S`` of work, but at least ``CHUNKS_PER_WORKER`` chunks per worker.

    Examples
    --------
    >>> auto_chunk(0.05, 6161, 2), auto_chunk(2.0, 100, 2), auto_chunk(0.001, 10**7, 64)
    (10, 1, 500)
    """
    by_time = max(1, round(TARGET_CHUNK_S / max(seconds_per_design, 1e-6)))
    by_balance = max(1, designs // (CHUNKS_PER_WORKER * max(workers, 1)))
    return int(min(by_time, by_balance, MAX_CHUNK))


def _values_text(row: dict, keys: dict) -> str:
    return ", ".join(f"{k}={row.get(k)!r}" for k in keys)[:120]


@dataclass
class RunStats:
    """How a run went (timings: report.json only, never in the data)."""

    engine: dict
    chunks: int
    chunks_before: int            # complete on disk before this run (--resume)
    chunks_computed: int = 0
    designs_computed: int = 0
    wall_s: float = 0.0
    cpu_s: float = 0.0            # sum of the workers' CPU time over the chunks computed
    stopped: bool = False         # stopped before the end (--stop-after-chunks)
    load_before: tuple = ()
    load_after: tuple = ()
    hosts: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        workers = max(int(self.engine.get("workers", 1)), 1)
        rate = self.designs_computed / self.wall_s if self.wall_s > 0 else None
        return {**self.engine, "chunks": self.chunks, "chunks_on_disk_before": self.chunks_before,
                "chunks_computed": self.chunks_computed, "designs_computed": self.designs_computed,
                "wall_s": self.wall_s, "worker_cpu_s": self.cpu_s, "designs_per_s": rate,
                "designs_per_s_per_worker": None if rate is None else rate / workers,
                "designs_per_cpu_s": (self.designs_computed / self.cpu_s) if self.cpu_s > 0 else None,
                "cpu_s_per_design": (self.cpu_s / self.designs_computed) if self.designs_computed else None,
                "load_average_before": list(self.load_before), "load_average_after": list(self.load_after),
                "worker_processes": len(self.hosts), "stopped": self.stopped}


Progress = Callable[[int, int, int, float], None]


def compute_chunks(plan: SweepPlan, folder: Path, engine: Engine, resume: bool = False,
              progress: Progress | None = None, stop_after_chunks: int | None = None, out=None) -> RunStats:
    """Compute the plan's chunks that are not on disk in ``folder`` and write each as it completes.

    Parameters
    ----------
    plan : SweepPlan
        From ``prepare_sweep``.
    folder : Path
        The output folder (``sweep.json`` and ``results/`` go in it).
    engine : Engine
        Where the chunks run (``camcad.sweep.engine.make_engine``).
    resume : bool
        Complete the sweep already in ``folder`` (its manifest must describe the same sweep); without it a
        folder that already holds a sweep is refused.
    progress : callable, optional
        ``progress(designs done, designs in all, designs computed by this run, seconds)`` after each chunk.
    stop_after_chunks : int, optional
        Stop after this many chunks are written (as an interruption would; for tests and demonstrations).
    out : OutputFolder, optional
        The locked output folder that hands out the paths (``camcad.io.output_folder``).

    Returns
    -------
    RunStats
    """
    store.require_pyarrow()
    path = (lambda *parts: out.path(*parts)) if out is not None else (lambda *parts: folder.joinpath(*parts))
    results = path(store.RESULTS)
    wanted = plan.manifest()
    found = store.read_manifest(folder)
    if found is not None and not resume:
        raise CamcadError("the folder holds a sweep already", str(folder),
                          "add --resume to complete it, or write into another folder with -o")
    if found is not None:
        differs = store.same_sweep(found, wanted)
        if differs:
            raise CamcadError(f"the folder holds another sweep (its {differs} differ)", str(folder),
                              "resume with the same scene and options, or write into another folder with -o")
    elif results.is_dir() and any(results.glob("chunk-*.parquet")):
        raise CamcadError("the folder holds results without a manifest", str(folder),
                          "write into another folder with -o")
    store.write_manifest(path(store.MANIFEST), wanted)
    store.clean_partial(results)
    done = set()
    if resume:
        for chunk in range(plan.chunks):
            chunk_path = results / store.chunk_name(chunk)
            if chunk_path.exists() and store.chunk_is_complete(chunk_path, *plan.bounds(chunk)):
                done.add(chunk)
    todo = [(chunk, *plan.bounds(chunk)) for chunk in range(plan.chunks) if chunk not in done]
    stats = RunStats(engine.describe(), plan.chunks, len(done), load_before=_load())
    designs_done = sum(plan.bounds(c)[1] - plan.bounds(c)[0] for c in done)
    started = time.perf_counter()
    if progress:
        progress(designs_done, plan.designs, 0, 0.0)
    iterator = engine.run(plan.task, todo)
    try:
        for result in iterator:
            table = store.rows_to_table(result.rows, plan.keys, plan.units)
            store.write_chunk(path(store.RESULTS, store.chunk_name(result.chunk)), table)
            stats.chunks_computed += 1
            count = result.stop - result.start
            stats.designs_computed += count
            stats.cpu_s += result.cpu_s
            stats.hosts[result.worker] = stats.hosts.get(result.worker, 0) + count
            designs_done += count
            if progress:
                progress(designs_done, plan.designs, stats.designs_computed, time.perf_counter() - started)
            if stop_after_chunks is not None and stats.chunks_computed >= stop_after_chunks \
                    and stats.chunks_computed < len(todo):
                stats.stopped = True
                break
    finally:
        close = getattr(iterator, "close", None)
        if close is not None:
            close()
        stats.wall_s = time.perf_counter() - started
        stats.load_after = _load()
    return stats


def _load() -> tuple:
    try:
        return tuple(round(x, 2) for x in os.getloadavg())
    except OSError:
        return ()
