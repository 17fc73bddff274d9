"""Scene tables as TOML text (``scene_toml``): the scene files camcad writes (a sweep's best design, the
scene a command built from its options) are read back by ``camcad profile`` as they stand."""

from __future__ import annotations

import json
import math
import re
from typing import Any

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def scene_toml(tables: dict, header: str = "") -> str:
    """Scene tables as TOML text: top-level keys, then each table, arrays of tables as ``[[name]]``.

    Parameters
    ----------
    tables : dict
        The scene's tables (strings, numbers, booleans, lists, tables; ``inf`` and ``nan`` allowed).
    header : str
        Comment lines put first (each line gets a ``#``).

    Returns
    -------
    str

    Examples
    --------
    >>> import tomllib
    >>> tables = {"name": "x", "law": {"lift": 25.0, "phases": "0:90:rise"},
    ...           "cyclogram": {"operations": [{"from": 1, "bounds_deg": [0.0, float("inf")]}]}}
    >>> tomllib.loads(scene_toml(tables)) == tables
    True
    """
    lines = [f"# {line}".rstrip() for line in header.splitlines()]
    _table(tables, [], lines)
    return "\n".join(lines).strip() + "\n"


def _table(table: dict, path: list[str], lines: list[str]) -> None:
    scalars = {k: v for k, v in table.items() if not isinstance(v, dict) and not _array_of_tables(v)}
    if path and (scalars or not any(isinstance(v, dict) or _array_of_tables(v) for v in table.values())):
        lines += ["", f"[{'.'.join(_key(p) for p in path)}]"]
    for key, value in scalars.items():
        lines.append(f"{_key(key)} = {_value(value)}")
    for key, value in table.items():
        if isinstance(value, dict):
            _table(value, path + [key], lines)
        elif _array_of_tables(value):
            for item in value:
                lines += ["", f"[[{'.'.join(_key(p) for p in path + [key])}]]"]
                for k, v in item.items():
                    lines.append(f"{_key(k)} = {_value(v)}")


def _array_of_tables(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def _key(key: str) -> str:
    key = str(key)
    return key if _BARE.match(key) else json.dumps(key, ensure_ascii=False)


def _value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"cannot write {type(value).__name__} to TOML")
