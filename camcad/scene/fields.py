"""Validated reading of parameter tables (scene TOML sections): units, types, unknown keys.

Every scene section is read through ``read_table`` so that a typo, a missing value or a
wrong type gets the same clear one-line error everywhere.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from camcad.errors import CamcadError, excerpt, nearest_name

_MISSING = object()


@dataclass(frozen=True)
class Field:
    """One key of a table: its type ("float", "int", "str", "bool", "list", "table"), unit and limits."""

    name: str
    kind: str = "float"
    unit: str = ""
    required: bool = False
    default: Any = None
    minimum: float | None = None       # inclusive
    maximum: float | None = None       # inclusive
    positive: bool = False             # strictly > 0
    choices: tuple[str, ...] = ()
    help: str = ""


def _describe(field: Field) -> str:
    unit = f" ({field.unit})" if field.unit else ""
    return f"'{field.name}'{unit}"


def read_table(table: Any, fields: list[Field], where: str) -> dict[str, Any]:
    """Check ``table`` against ``fields``; return {name: value} with defaults filled in.

    Raises CamcadError for a key not in ``fields`` (naming the nearest valid one), a missing
    required key, a value of the wrong type, a non-finite number, or a value out of range.
    ``where`` names the file and section, e.g. "scene.toml [follower]".
    """
    if not isinstance(table, dict):
        raise CamcadError(f"expected a table of keys, got {type(table).__name__}", where,
                          "write it as a [section] with key = value lines")
    by_name = {field.name: field for field in fields}
    for key in table:
        if key not in by_name:
            raise CamcadError(f"unknown key '{key}'", where, nearest_name(key, list(by_name)))
    values: dict[str, Any] = {}
    for field in fields:
        raw = table.get(field.name, _MISSING)
        if raw is _MISSING:
            if field.required:
                raise CamcadError(f"missing value {_describe(field)}", where,
                                  f"add {field.name} = ...{' ' + field.help if field.help else ''}")
            values[field.name] = field.default
            continue
        values[field.name] = _coerce(raw, field, where)
    return values


def _coerce(raw: Any, field: Field, where: str) -> Any:
    name = _describe(field)
    if field.kind == "float":
        if isinstance(raw, bool) or not isinstance(raw, (int, float)):
            raise CamcadError(f"{name} must be a number, got {excerpt(raw)}", where,
                              f"write {field.name} = 12.5 (a plain number in {field.unit or 'its unit'})")
        value = float(raw)
        if not math.isfinite(value):
            raise CamcadError(f"{name} must be finite, got {excerpt(raw)}", where, "give a finite number")
        _check_range(value, field, where)
        return value
    if field.kind == "int":
        if isinstance(raw, bool) or not isinstance(raw, int):
            raise CamcadError(f"{name} must be a whole number, got {excerpt(raw)}", where,
                              f"write {field.name} = 3")
        _check_range(raw, field, where)
        return raw
    if field.kind == "str":
        if not isinstance(raw, str):
            raise CamcadError(f"{name} must be text, got {excerpt(raw)}", where,
                              f'write {field.name} = "..." in quotes')
        if field.choices and raw not in field.choices:
            raise CamcadError(f"{name} is {excerpt(raw)}, not one of {', '.join(field.choices)}", where,
                              nearest_name(raw, list(field.choices)).replace("valid keys", "choices"))
        return raw
    if field.kind == "bool":
        if not isinstance(raw, bool):
            raise CamcadError(f"{name} must be true or false, got {excerpt(raw)}", where,
                              f"write {field.name} = true")
        return raw
    if field.kind == "list":
        if not isinstance(raw, list):
            raise CamcadError(f"{name} must be a list, got {excerpt(raw)}", where,
                              f"write {field.name} = [ ... ]")
        return raw
    if field.kind == "table":
        if not isinstance(raw, dict):
            raise CamcadError(f"{name} must be a table, got {excerpt(raw)}", where,
                              f"write it as [.{field.name}] or {field.name} = {{ ... }}")
        return raw
    if field.kind == "number_or_list":
        if isinstance(raw, list):
            return [_coerce(item, Field(field.name, "float", field.unit, minimum=field.minimum,
                                        maximum=field.maximum, positive=field.positive), where)
                    for item in raw]
        return _coerce(raw, Field(field.name, "float", field.unit, minimum=field.minimum,
                                  maximum=field.maximum, positive=field.positive), where)
    raise ValueError(f"unknown field kind {field.kind!r}")


#: no physical quantity of a cam mechanism is this large in its unit (mm, N, MPa, Hz, kg, ...): larger
#: values are typing mistakes, and they overflow the squares and cubes of the models
MAX_MAGNITUDE = 1e9
#: nor is a positive quantity this small (a lever of 1e-300 mm divides by zero)
MIN_POSITIVE = 1e-12


def _check_range(value: float, field: Field, where: str) -> None:
    name = _describe(field)
    if field.positive and not value > 0:
        raise CamcadError(f"{name} must be positive, got {value:g}", where, "give a value > 0")
    if abs(value) > MAX_MAGNITUDE and field.maximum is None:
        raise CamcadError(f"{name} is {value:g}, out of any mechanism's range", where,
                          f"give a value of at most {MAX_MAGNITUDE:g} in its unit")
    if field.positive and value < MIN_POSITIVE and field.minimum is None:
        raise CamcadError(f"{name} is {value:g}, too small to compute with", where,
                          f"give a value of at least {MIN_POSITIVE:g} in its unit")
    if field.minimum is not None and value < field.minimum:
        raise CamcadError(f"{name} must be at least {field.minimum:g}, got {value:g}", where,
                          f"give a value >= {field.minimum:g}")
    if field.maximum is not None and value > field.maximum:
        raise CamcadError(f"{name} must be at most {field.maximum:g}, got {value:g}", where,
                          f"give a value <= {field.maximum:g}")


#: speeds sampled over an [n1, n2] range given without a step
RANGE_SPEEDS = 15
#: the fastest cam shaft camcad takes (rpm)
MAX_RPM = 1e6
#: the slowest speed any analysis accepts (rpm): one turn in 11.6 hours; slower, ω² underflows the models' scales
MIN_RPM = 1e-3


def parse_speeds(value: Any, where: str = "--rpm") -> list[float]:
    """Machine speeds (rpm) from a number, "n", [n1, n2], "n1:n2" or "n1:n2:step".

    A range without a step gives RANGE_SPEEDS equally spaced speeds, ends included; with a
    step, n1, n1 + step, … and n2 itself. Speeds must be positive and finite.
    """
    fix = 'write rpm = 300, rpm = [280, 420] or rpm = "280:420:20"'
    if isinstance(value, bool) or value is None:
        raise CamcadError(f"rpm must be a speed, got {excerpt(value)}", where, fix)
    step = None
    if isinstance(value, (int, float)):
        ends = [float(value)]
    elif isinstance(value, (list, tuple)):
        if len(value) != 2 or any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in value):
            raise CamcadError(f"rpm {excerpt(value)} must be two numbers [n1, n2]", where, fix)
        ends = [float(v) for v in value]
    elif isinstance(value, str):
        parts = [p.strip() for p in value.split(":")]
        try:
            numbers = [float(p) for p in parts]
        except ValueError:
            raise CamcadError(f"rpm {excerpt(value)} is not N, N1:N2 or N1:N2:STEP", where, fix) from None
        if len(numbers) not in (1, 2, 3):
            raise CamcadError(f"rpm {excerpt(value)} is not N, N1:N2 or N1:N2:STEP", where, fix)
        ends, step = numbers[:2], (numbers[2] if len(numbers) == 3 else None)
    else:
        raise CamcadError(f"rpm must be a number, [n1, n2] or \"n1:n2:step\", got {excerpt(value)}", where, fix)
    if not all(math.isfinite(e) and e > 0 for e in ends):
        raise CamcadError(f"speeds must be positive, got {excerpt(value)}", where, fix)
    if max(ends) > MAX_RPM:
        raise CamcadError(f"a speed of {max(ends):g} rpm is out of any machine's range", where,
                          f"give speeds up to {MAX_RPM:g} rpm")
    if min(ends) < MIN_RPM:
        raise CamcadError(f"a speed of {min(ends):g} rpm is below any machine's range", where,
                          f"give speeds of at least {MIN_RPM:g} rpm")
    if len(ends) == 1:
        return ends
    low, high = sorted(ends)
    if step is not None:
        if not (math.isfinite(step) and step > 0):
            raise CamcadError(f"the speed step must be positive, got {step:g}", where, fix)
        count = math.floor((high - low) / step + 1e-9)
        if count > 100_000:
            raise CamcadError(f"{count} speeds is too many", where, "use a larger step")
        speeds = [low + step * i for i in range(count + 1)]
        if high - speeds[-1] > 1e-9 * high:
            speeds.append(high)
        return speeds
    if low == high:
        return [low]
    return [low + (high - low) * i / (RANGE_SPEEDS - 1) for i in range(RANGE_SPEEDS)]


def parse_rpm(value: Any, where: str = "--rpm") -> tuple[float, float]:
    """The speed range (n1, n2) in rpm of a speed or range given as ``parse_speeds`` accepts."""
    speeds = parse_speeds(value, where)
    return min(speeds), max(speeds)
