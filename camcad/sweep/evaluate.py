"""One design of a sweep: its scene run through the pipeline, reduced to one row of figures.

A design is the sweep's scene with the design's values written in (``space.apply_values``), run through
``camcad.scene.pipeline.analyse_scene`` with ``checks_only`` (no smallest-base-radius design and no least
phase angles of a mechanism: figures the checks do not use) and no plots or files. Only the models the scene
has run. Its row holds:

- ``design`` (the id) and the varied keys' values (a column per key, named by the key);
- ``status``: ``ok``, ``bad input`` (the scene refuses the design's values: the message is in ``error``) or
  ``internal error`` (a bug: the exception is in ``error``);
- ``feasible``: every check passed; ``governing``: the check with the least margin ratio — the one that fails
  worst, or for a feasible design the tightest; ``min_margin_ratio``: its margin ratio;
- every check's ``.value``, ``.limit``, ``.margin``, ``.margin_ratio`` and ``.passed`` (columns named
  ``<check>.value`` …; a model's own checks as ``<model> <check>``; in a group ``<mechanism>/<check>.value`` …;
  the unit of each column is in the Parquet schema's field metadata).

The checks are those of the report: the profile's (pressure angle per phase, undercut, convex radius,
closure), each model's own ``checks`` when it has them, else its verdict as a figure against its limit:
contact stress against [σ_H] (and separation), the stop's rebound against its allowed amplitude, the
filter's verdict; for a group, the cyclogram's feasibility and makespan (a figure without a limit).
"""

from __future__ import annotations

import math
import os
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from camcad.errors import CamcadError
from camcad.io.input_file import read_input
from camcad.io.output_folder import safe_name
from camcad.scene.file import scene_from_dict
from camcad.scene.pipeline import PipelineOptions, analyse_scene
from camcad.sweep.batch import evaluate_batch, groups
from camcad.sweep.space import apply_values, build_space
from camcad.sweep.threads import pin_numerical_threads
from camcad.verdict import Check
from camcad.version import __version__

STATUS_OK, STATUS_BAD, STATUS_BUG = "ok", "bad input", "internal error"
#: the figures of each check, as column suffixes
CHECK_PARTS = ("value", "limit", "margin", "margin_ratio", "passed")
#: the longest error text kept in a row
ERROR_CHARS = 300


# --------------------------------------------------------------------------------------------
# the task: what travels to a worker
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class SweepTask:
    """Everything a worker needs to compute designs, with no shared file system: the scene's tables, the
    bytes of the law files it reads, the --vary texts, the draws, and a digest naming it all.

    Parameters
    ----------
    tables : dict
        The scene's TOML tables (law files named by their key in ``files``).
    name : str
        How the scene is named in messages (its file name, or "built-in default").
    files : dict
        {name used in ``tables``: file content (bytes)} of every law file.
    vary, samples, seed
        As ``space.build_space`` takes them.
    digest : str
        SHA-256 of all the above (a worker prepares each task once).
    """

    tables: dict
    name: str
    files: dict
    vary: tuple[str, ...]
    samples: int | None
    seed: int
    digest: str


def make_task(tables: dict, name: str, base_dir: Path | None, vary: list[str], samples: int | None,
              seed: int) -> SweepTask:
    """A SweepTask from a scene's tables; the law files the tables name (relative to ``base_dir``) are read
    into the task, and each ``file`` key is replaced by a plain name the worker writes the bytes under."""
    import copy
    import hashlib
    import json

    tables = copy.deepcopy(tables)
    files: dict[str, bytes] = {}
    for number, law in enumerate(_law_tables(tables)):
        given = law.get("file")
        if not isinstance(given, str):
            continue
        path = Path(given) if base_dir is None else base_dir / given
        content = read_input(path, "the law file ([law] file, relative to the scene)")

        name_in_task = f"law{number}_{safe_name(Path(given).name)}"
        files[name_in_task] = content
        law["file"] = name_in_task
    text = json.dumps([tables, name, sorted(files), list(vary), samples, seed], sort_keys=True, default=str)
    digest = hashlib.sha256(text.encode())
    for key in sorted(files):
        digest.update(files[key])
    return SweepTask(tables, name, files, tuple(vary), samples, int(seed), digest.hexdigest())


def _law_tables(tables: dict) -> list[dict]:
    group = tables.get("mechanisms")
    sections = list(group.values()) if isinstance(group, dict) else [tables]
    return [s["law"] for s in sections if isinstance(s, dict) and isinstance(s.get("law"), dict)]


class Prepared:
    """A task made ready on one worker: the design space and a folder holding the law files."""

    def __init__(self, task: SweepTask) -> None:
        self.task = task
        self.folder = Path(tempfile.mkdtemp(prefix="camcad-sweep-")) if task.files else None
        if self.folder is not None:
            import atexit
            import shutil

            atexit.register(shutil.rmtree, self.folder, True)   # a forked pool worker never runs atexit
        for name, content in task.files.items():
            (self.folder / name).write_bytes(content)
        self.space = build_space(task.tables, list(task.vary), task.samples, task.seed)
        self.keys = {spec.key.path: spec.key for spec in self.space.specs}
        # messages name the scene as the user knows it; the law files are given by absolute paths
        self.scene_path = Path(task.name)

    def scene_tables(self, design: int) -> tuple[dict, dict]:
        """(the design's values, its scene tables)."""
        values = self.space.values(design)
        return values, apply_values(self.task.tables, self.keys, values)

    def clean(self, text: str) -> str:
        """A message with the worker's own folder replaced by the scene's name: the same text on any worker."""
        if self.folder is not None:
            text = text.replace(str(self.folder.resolve()), "<scene folder>")
            text = text.replace(str(self.folder), "<scene folder>")
        return text


_PREPARED: dict[str, Prepared] = {}


def prepared(task: SweepTask) -> Prepared:
    """The worker's Prepared for ``task`` (made once per process)."""
    found = _PREPARED.get(task.digest)
    if found is None:
        if len(_PREPARED) > 4:
            _PREPARED.clear()
        found = _PREPARED[task.digest] = Prepared(task)
    return found


# --------------------------------------------------------------------------------------------
# one design
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Figure:
    """One check of a design as the sweep records it: the figure, its limit, the margin towards failure (in the
    check's unit), the margin as a fraction of |limit|, and the verdict. From a report's check dictionary the
    figures are taken as the report gives them (``camcad profile`` prints the same numbers)."""

    name: str
    value: float | None
    limit: float | None
    unit: str
    margin: float | None
    margin_ratio: float | None
    passed: bool

    @classmethod
    def of(cls, check: Check) -> Figure:
        return cls(check.name, check.value, check.limit, check.unit, check.margin, check.margin_ratio,
                   bool(check.passed))


def design_checks(report: dict) -> list[Figure]:
    """Every check of a scene's report (``analyse_scene(...).report``) as ``Figure`` objects, named as the
    sweep's columns are (``<mechanism>/<check>`` in a group).

    Examples
    --------
    >>> report = {"checks": {"pressure angle, rise": {"value": 18.4, "limit": 30.0, "margin": 11.6,
    ...           "margin_ratio": 0.3867, "unit": "deg", "sense": "max", "passed": True}}, "passed": True}
    >>> [(f.name, f.margin, f.passed) for f in design_checks(report)]
    [('pressure angle, rise', 11.6, True)]
    """
    mechanisms = report.get("mechanisms")
    if mechanisms is None:
        found = _mechanism_checks(report, "")
    else:
        found = []
        for name, mech in mechanisms.items():
            found.extend(_mechanism_checks(mech, f"{name}/"))
    cyclogram = report.get("cyclogram")
    own = cyclogram.get("checks") if isinstance(cyclogram, dict) else None
    if isinstance(own, dict) and own:   # the cyclogram's own verdict, when its report has one
        found.extend(_from_dict(_prefixed("cyclogram", name, ""), entry) for name, entry in own.items())
    elif cyclogram is not None:
        feasible = bool(cyclogram.get("passed", cyclogram.get("feasible", False)))
        found.append(Figure.of(Check("cyclogram feasible", 1.0 if feasible else 0.0, None, "",
                                     passed_override=feasible)))
        if cyclogram.get("makespan_deg") is not None:
            found.append(Figure.of(Check("cyclogram makespan", float(cyclogram["makespan_deg"]), None, "deg")))
    return found


def _mechanism_checks(mech: dict, prefix: str) -> list[Figure]:
    found = [_from_dict(prefix + name, data) for name, data in (mech.get("checks") or {}).items()]
    for model in ("spectrum", "dynamics", "impact", "contact"):
        data = mech.get(model)
        if not isinstance(data, dict):
            continue
        own = data.get("checks")
        if isinstance(own, dict) and own:
            found.extend(_from_dict(_prefixed(model, name, prefix), entry) for name, entry in own.items())
            continue
        found.extend(Figure.of(c) for c in _model_checks(model, data, prefix))
    return found


def _prefixed(model: str, name: str, prefix: str) -> str:
    """A model's check named for its column: "<mechanism>/<model> <check>" (the model once)."""
    return f"{prefix}{name}" if name.startswith(model) else f"{prefix}{model} {name}"


def _from_dict(name: str, data: dict) -> Figure:
    """A check from its JSON form ({"value", "limit", "margin", "margin_ratio", "unit", "sense", "passed"}; a
    model may say "allowed" for "limit" and leave out the margin, which is then computed)."""
    limit = _number(data.get("limit", data.get("allowed")))
    sense = data.get("sense", "max")
    check = Check(name, _number(data.get("value")), limit, data.get("unit", ""), sense if sense in ("max", "min")
                  else "max")
    passed = data.get("passed")
    margin = _number(data["margin"]) if "margin" in data else check.margin
    ratio = _number(data["margin_ratio"]) if "margin_ratio" in data else check.margin_ratio
    return Figure(name, check.value, check.limit, check.unit, margin, ratio,
                  passed if isinstance(passed, bool) else bool(check.passed))


def _model_checks(model: str, data: dict, prefix: str) -> list[Check]:
    """The verdict of a model whose report has no ``checks`` yet, as figures against limits."""
    passed = bool(data.get("passed", True))
    if model == "contact":
        out = [Check(f"{prefix}contact stress", _number(data.get("sigma_max_MPa")), _number(data.get("allowable_MPa")),
                     "MPa", "max")]
        if data.get("separation") is not None:
            separated = bool(data["separation"])
            out.append(Check(f"{prefix}contact separation", 1.0 if separated else 0.0, None, "",
                             passed_override=not separated))
        return out
    if model == "impact":
        rebound = data.get("rebound_mm")
        worst = max(rebound) if isinstance(rebound, list) and rebound else None
        allowed = _number(data.get("allowed_amplitude_mm"))
        return [Check(f"{prefix}impact rebound", _number(worst), allowed, "mm", "max",
                      passed_override=None if allowed is not None else passed)]
    return [Check(f"{prefix}{model}", 1.0 if passed else 0.0, None, "", passed_override=passed)]


def _number(value: Any) -> float | None:
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def evaluate_design(prep: Prepared, design: int) -> dict:
    """The row of design ``design`` (module docstring): a dict of column → value."""
    row: dict[str, Any] = {"design": int(design)}
    if prep.space.samples > 1:
        row["sample"] = int(design) % prep.space.samples
    try:
        values, tables = prep.scene_tables(design)
        row.update(values)
        tables = _with_files(tables, prep)
        scene = scene_from_dict(tables, prep.scene_path, from_file=False)
        result = analyse_scene(scene, PipelineOptions(plots=(), checks_only=True))
    except CamcadError as err:
        return _failed(row, prep, STATUS_BAD, err.message())
    except Exception as err:  # noqa: BLE001 - a bug in one design must not stop a million others
        return _failed(row, prep, STATUS_BUG, f"{type(err).__name__}: {err}")
    return row_of(row, result.report, bool(result.passed))


def row_of(row: dict, report: dict, passed: bool) -> dict:
    """``row`` (the design's id and values) completed from its report: status, feasibility, the governing
    check, and every check's figures (module docstring)."""
    checks = design_checks(report)
    row.update(status=STATUS_OK, error="", feasible=passed and all(c.passed for c in checks))
    governing, ratio = _governing(checks)
    row["governing"] = governing
    row["min_margin_ratio"] = ratio
    for check in checks:
        for part in CHECK_PARTS:
            row[f"{check.name}.{part}"] = _part(check, part)
        row.setdefault("_units", {})[check.name] = check.unit
    return row


def _with_files(tables: dict, prep: Prepared) -> dict:
    if prep.folder is None:
        return tables
    for law in _law_tables(tables):
        if isinstance(law.get("file"), str):
            law["file"] = str(prep.folder / law["file"])
    return tables


def _failed(row: dict, prep: Prepared, status: str, message: str) -> dict:
    if "design" in row and len(row) <= 2:
        import contextlib

        with contextlib.suppress(Exception):  # the values themselves failed: the error says why
            row.update(prep.space.values(row["design"]))
    text = " ".join(prep.clean(message).split())
    row.update(status=status, error=text[:ERROR_CHARS], feasible=False, governing=status,
               min_margin_ratio=math.nan)
    return row


def _governing(checks: list[Figure]) -> tuple[str, float]:
    """The check with the least margin ratio (failed checks without a ratio first), and that ratio."""
    failed = [c for c in checks if not c.passed]
    pool = failed or [c for c in checks if c.margin_ratio is not None]
    if not pool:
        return "", math.nan
    ranked = sorted(pool, key=lambda c: (c.margin_ratio if c.margin_ratio is not None else -math.inf))
    best = ranked[0]
    return best.name, (best.margin_ratio if best.margin_ratio is not None else math.nan)


def _part(check: Figure, part: str):
    if part == "passed":
        return bool(check.passed)
    value = getattr(check, part)
    return math.nan if value is None else float(value)


# --------------------------------------------------------------------------------------------
# a chunk: the unit of work
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class ChunkResult:
    """The rows of designs ``start`` … ``stop - 1``, with the worker's CPU and wall time (s) and pid."""

    chunk: int
    start: int
    stop: int
    rows: list
    cpu_s: float
    wall_s: float
    worker: str


def evaluate_chunk(task: SweepTask, chunk: int, start: int, stop: int) -> ChunkResult:
    """Rows of designs ``start`` … ``stop - 1`` of ``task`` (what a worker process or a Dask worker runs).

    Examples
    --------
    >>> from camcad.scene.default import default_tables
    >>> task = make_task(default_tables(), "default", None, ["follower.base_radius=40,50"], None, 0)
    >>> result = evaluate_chunk(task, 0, 0, 2)
    >>> [(r["design"], r["follower.base_radius"], r["feasible"]) for r in result.rows]
    [(0, 40.0, True), (1, 50.0, True)]
    """
    import warnings

    cpu, wall = time.process_time(), time.perf_counter()
    pin_numerical_threads()     # one design per core: no BLAS threads spinning beside it
    prep = prepared(task)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # numerical warnings: each design's figures say what they are
        # designs that share a law (only the follower's dimensions differ) are computed together
        rows = [row for group in groups(prep, list(range(start, stop)))
                for row in evaluate_batch(prep, group, evaluate_design, _with_files, row_of)]
        rows.sort(key=lambda row: row["design"])
    return ChunkResult(chunk, start, stop, rows, time.process_time() - cpu, time.perf_counter() - wall,
                       f"{os.uname().nodename}:{os.getpid()}")


def worker_version() -> str:
    """camcad's version on a worker (the Dask engine checks the cluster runs the same camcad)."""
    return __version__
