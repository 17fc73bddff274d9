"""A sweep's results on disk: one Parquet file per chunk, written atomically, and the manifest that resumes it.

Layout of the output folder::

    sweep.json                     the manifest: what the sweep is (scene digest, keys, draws, chunking)
    results/chunk-00000000.parquet the rows of chunk 0 (designs 0 … C − 1), sorted by design id
    results/chunk-00000001.parquet …

A chunk file appears by an atomic rename once all its rows are computed (``camcad.io.atomic``), so a file
that is there is complete; ``--resume`` skips the chunks whose file is there and holds exactly the chunk's
design ids, and computes the others. The data columns hold no time stamps and no worker names, so a design's
row is the same whichever worker computed it (timings go to report.json). ``read_results`` gives every
chunk as one table, sorted by design id (pyarrow's dataset reader works on ``results/`` as well).

pyarrow is an optional dependency (``pip install 'camcad[sweep]'``); ``require_pyarrow`` says so in one line.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable
from pathlib import Path

from camcad.errors import CamcadError
from camcad.io.atomic import write_atomic
from camcad.io.input_file import check_json_nesting, read_input
from camcad.io.jsonout import write_json

#: manifest format version
MANIFEST_VERSION = 1
RESULTS = "results"
MANIFEST = "sweep.json"
#: the columns every row has, in this order, before the keys' and the checks' columns
LEAD_COLUMNS = ("design", "sample")
TAIL_COLUMNS = ("status", "error", "feasible", "governing", "min_margin_ratio")
INSTALL_FIX = "install the sweep extra: pip install 'camcad[sweep]'"


def require_pyarrow():
    """The ``pyarrow`` module, or a one-line CamcadError saying how to install it."""
    try:
        import pyarrow
        import pyarrow.parquet
    except ImportError:
        raise CamcadError("camcad sweep writes Parquet with pyarrow, which is not installed", "camcad sweep",
                          INSTALL_FIX) from None
    return pyarrow


def chunk_name(chunk: int) -> str:
    """File name of chunk ``chunk``: ``chunk-00000042.parquet`` (names sort in chunk order)."""
    return f"chunk-{int(chunk):08d}.parquet"


def chunk_number(path: Path) -> int | None:
    name = Path(path).name
    if not (name.startswith("chunk-") and name.endswith(".parquet")):
        return None
    digits = name[len("chunk-"):-len(".parquet")]
    return int(digits) if digits.isdigit() else None


def rows_to_table(rows: list[dict], key_kinds: dict[str, str], key_units: dict[str, str] | None = None):
    """The rows of one chunk as a pyarrow Table: ``design`` (and ``sample``), the keys (typed as ``key_kinds``
    says: float, int, str, bool), the status columns, then every check's figures in the order the checks first
    appear. Units go in each field's metadata (``unit``)."""
    pa = require_pyarrow()
    rows = sorted(rows, key=lambda r: r["design"])
    units: dict[str, str] = {}
    check_columns: list[str] = []
    seen = set()
    for row in rows:
        for name, unit in row.get("_units", {}).items():
            units.setdefault(name, unit)
        for column in row:
            if column in seen or column == "_units" or column in LEAD_COLUMNS or column in TAIL_COLUMNS \
                    or column in key_kinds:
                continue
            seen.add(column)
            check_columns.append(column)
    arrays, fields = [], []

    def add(name: str, kind: str, unit: str | None = None) -> None:
        values = [row.get(name) for row in rows]
        if kind == "float":  # a figure not computed (NaN) is stored as null
            values = [None if v is None or math.isnan(v) else float(v) for v in values]
        typ = {"float": pa.float64(), "int": pa.int64(), "str": pa.string(), "bool": pa.bool_()}[kind]
        metadata = {"unit": unit} if unit else None
        fields.append(pa.field(name, typ, metadata=metadata))
        arrays.append(pa.array(values, type=typ))

    add("design", "int")
    if any("sample" in row for row in rows):
        add("sample", "int")
    for key, kind in key_kinds.items():
        add(key, kind, (key_units or {}).get(key))
    add("status", "str")
    add("error", "str")
    add("feasible", "bool")
    add("governing", "str")
    add("min_margin_ratio", "float")
    for column in check_columns:
        check, part = column.rsplit(".", 1)
        unit = units.get(check, "") if part in ("value", "limit", "margin") else None
        add(column, "bool" if part == "passed" else "float", unit)
    return pa.Table.from_arrays(arrays, schema=pa.schema(fields))


def write_chunk(path: Path, table) -> Path:
    """Write one chunk's table to ``path`` atomically (temporary file beside it, fsync, rename)."""
    import pyarrow.parquet as pq

    return write_atomic(path, lambda tmp: pq.write_table(table, tmp, compression="zstd"))


def chunk_is_complete(path: Path, start: int, stop: int) -> bool:
    """The chunk file at ``path`` holds exactly the design ids ``start`` … ``stop - 1``."""
    import pyarrow.parquet as pq

    try:
        ids = pq.read_table(path, columns=["design"]).column("design").to_pylist()
    except Exception:  # noqa: BLE001 - unreadable: computed again
        return False
    return ids == list(range(start, stop))


def read_results(folder: str | Path, columns: list[str] | None = None):
    """Every chunk of the sweep in ``folder`` as one pyarrow Table, sorted by design id (columns missing in
    some chunks are null there).

    Parameters
    ----------
    folder : str or Path
        The sweep's output folder (the one holding ``results/``), or ``results/`` itself.
    columns : list of str, optional
        Only these columns.

    Returns
    -------
    pyarrow.Table
    """
    pa = require_pyarrow()
    import pyarrow.parquet as pq

    folder = Path(folder)
    results = folder if folder.name == RESULTS else folder / RESULTS
    files = sorted(p for p in results.glob("chunk-*.parquet") if chunk_number(p) is not None)
    if not files:
        raise CamcadError("no results", str(results), "run the sweep first")
    tables = []
    for path in files:
        table = pq.read_table(path)
        if columns is not None:
            table = table.select([c for c in columns if c in table.column_names])
        tables.append(table)
    table = pa.concat_tables(tables, promote_options="default")
    return table.sort_by("design")


def clean_partial(results: Path) -> int:
    """Remove temporary files a killed run left in ``results/`` (their chunks are computed again)."""
    removed = 0
    if results.is_dir():
        for path in results.glob(".chunk-*.tmp"):
            path.unlink(missing_ok=True)
            removed += 1
    return removed


# --------------------------------------------------------------------------------------------
# the manifest
# --------------------------------------------------------------------------------------------

def manifest(task, designs: int, chunk_designs: int, keys: Iterable[str]) -> dict:
    """What the sweep is: enough to know a folder's chunks belong to it (``--resume``)."""
    return {"camcad_sweep": MANIFEST_VERSION, "digest": task.digest, "scene": task.name,
            "vary": list(task.vary), "samples": task.samples, "seed": task.seed, "designs": int(designs),
            "chunk_designs": int(chunk_designs), "chunks": math.ceil(designs / chunk_designs),
            "keys": list(keys)}


def read_manifest(folder: Path) -> dict | None:
    path = folder / MANIFEST
    if not path.exists():
        return None
    try:
        text = read_input(path, "the sweep's manifest (sweep.json)", 1 << 20).decode("utf-8")
        check_json_nesting(text, str(path))
        found = json.loads(text)
    except (CamcadError, OSError, ValueError):
        raise CamcadError("the sweep's manifest is unreadable", str(path),
                          "remove the folder's sweep.json and results/, or write into another folder with -o") from None
    if not isinstance(found, dict) or found.get("camcad_sweep") != MANIFEST_VERSION:
        raise CamcadError("not a camcad sweep manifest (or from another version)", str(path),
                          "write into another folder with -o")
    return found


def same_sweep(found: dict, wanted: dict) -> str | None:
    """None when ``found`` (a folder's manifest) is the sweep ``wanted``; else what differs, in words."""
    for key, words in (("digest", "the scene, its law files, --vary, --samples or --seed"),
                       ("chunk_designs", "--chunk")):
        if found.get(key) != wanted.get(key):
            return words
    return None


def write_manifest(path: Path, data: dict) -> Path:
    return write_json(path, data)
